"""One leg's kinematics: foot paths, straight-line metrics, K sweep, Jacobians (seed §4, §5).

Everything here works on the one-leg model (``load(variant, legs=1)``), whose world frame is
the leg frame of DESIGN §4: origin at the crank pivot 0, x toward the rocker pivot 3 (forward),
z up. Points are reported as (x, z) [m]; angles [rad]; the crank rate ``omega`` [rad/s].

- :func:`leg_cycle` samples a crank turn on the closure manifold: ankle, toe and heel paths,
  foot pitch and, with ``omega``, the ankle's velocity and acceleration.
- :func:`straight_line_metrics` gives the stance stroke, the ankle band, the straightness
  deviation, the swing lift, the crank-angle span near the ground and the foot pitch.
- :func:`k_sweep` repeats the cycle for several frame ratios K (seed Fig 4.2.4).
- :func:`open_chain_jacobian` is the seed's 6x4 geometric Jacobian of the open chain
  theta1, theta2, theta4, theta6 (tree joints ``j0_crank``, ``j1``, ``j4``, ``j6``) from
  joint 0 to the ankle; :func:`constrained_jacobian` is the ankle velocity per unit crank
  rate on the closure manifold; :func:`ankle_motion` gives the ankle velocity and acceleration
  from the Jacobians and the drift terms.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import frame_jacobian, planar_pitch
from pasibot_pin.model import closure
from pasibot_pin.reprs import short_repr

STANCE: tuple[float, float] = (math.pi / 2, 3 * math.pi / 2)
"""Crank-angle window of the stance phase [rad] (DESIGN §4: 90 deg to 270 deg)."""

OPEN_CHAIN: tuple[str, ...] = ("j0_crank", "j1", "j4", "j6")
"""Tree joints of the seed's open chain theta1, theta2, theta4, theta6 (joint 0 to the ankle)."""

LOCAL_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def _check_one_leg(robot) -> None:
    if getattr(robot, "legs", None) != 1:
        raise ValueError("parameter 'robot' must be a one-leg robot (load(variant, legs=1)), the leg frame")


def _check_omega(omega: float | None) -> None:
    if omega is not None and (not math.isfinite(omega) or omega <= 0.0):
        raise ValueError(f"parameter 'omega' must be a positive finite crank rate [rad/s], got {omega!r}")


def crank_grid(step: float = math.radians(1.0), start: float = 0.0, turns: float = 1.0) -> np.ndarray:
    """Crank angles from ``start`` over ``turns`` turns every ``step``, both ends included [rad].

    Raises:
        ValueError: when ``step`` does not divide the range into whole samples.

    """
    if not math.isfinite(step) or step <= 0.0:
        raise ValueError(f"parameter 'step' must be a positive crank increment [rad], got {step!r}")
    if not math.isfinite(turns) or turns <= 0.0:
        raise ValueError(f"parameter 'turns' must be positive, got {turns!r}")
    count = 2 * math.pi * turns / step
    n = round(count)
    if n < 2 or abs(count - n) > 1e-9 * max(count, 1.0):
        raise ValueError(
            f"parameter 'step' = {math.degrees(step):.6g} deg must divide {360 * turns:g} deg into at least 2 samples"
        )
    return start + step * np.arange(n + 1)


# --------------------------------------------------------------------------- the cycle
@dataclass
class LegCycle:
    """One leg sampled over crank angles, in the leg frame.

    Attributes:
        robot: the one-leg robot.
        theta: crank angles (N,) [rad].
        q: closed configurations (N, nq).
        ankle: ankle (joint 13) positions (N, 2), x and z [m].
        toe: toe positions (N, 2) [m].
        heel: heel positions (N, 2) [m].
        foot_pitch: sole direction (heel -> toe), counter-clockwise from +x (N,) [rad].
        omega: crank rate [rad/s] or ``None``.
        v: joint velocities (N, nv) [rad/s, m/s] (with ``omega``).
        a: joint accelerations (N, nv) at constant ``omega`` (with ``omega``).
        ankle_velocity: ankle velocity (N, 2) [m/s] (with ``omega``).
        ankle_acceleration: ankle acceleration (N, 2) [m/s^2] (with ``omega``).

    """

    __repr__ = short_repr

    robot: object
    theta: np.ndarray
    q: np.ndarray
    ankle: np.ndarray
    toe: np.ndarray
    heel: np.ndarray
    foot_pitch: np.ndarray
    omega: float | None = None
    v: np.ndarray | None = None
    a: np.ndarray | None = None
    ankle_velocity: np.ndarray | None = None
    ankle_acceleration: np.ndarray | None = None

    def in_stance(self) -> np.ndarray:
        """Boolean mask (N,) of the samples in the stance window 90..270 deg (mod 360)."""
        return stance_mask(self.theta)


def stance_mask(theta: np.ndarray) -> np.ndarray:
    """True where the crank angle lies in the stance window [90, 270] deg (mod 360)."""
    wrapped = np.mod(np.asarray(theta, dtype=float), 2 * math.pi)
    tol = 1e-12
    return (wrapped >= STANCE[0] - tol) & (wrapped <= STANCE[1] + tol)


def _xz(data: pin.Data, fid: int) -> np.ndarray:
    return data.oMf[fid].translation[[0, 2]].copy()


def leg_cycle(
    robot,
    thetas: Sequence[float] | np.ndarray | None = None,
    omega: float | None = None,
) -> LegCycle:
    """Sample the leg over crank angles on the closure manifold (warm-started Newton).

    Args:
        robot: a one-leg robot (``load(variant, legs=1)``); the ``spring`` foot is held level.
        thetas: crank angles [rad], ordered (default: one turn every 1 deg, 0 to 360 deg).
        omega: crank rate [rad/s]; when given, joint and ankle velocities and accelerations
            are computed at constant rate.

    Returns:
        The :class:`LegCycle`.

    Raises:
        ValueError: not a one-leg robot, bad ``omega`` or angles, or a loop that cannot close.

    """
    _check_one_leg(robot)
    _check_omega(omega)
    thetas = crank_grid() if thetas is None else np.asarray(thetas, dtype=float).reshape(-1)
    if thetas.size == 0 or not np.all(np.isfinite(thetas)):
        raise ValueError("parameter 'thetas' must be a non-empty sequence of finite crank angles [rad]")
    qs = sweep(robot, thetas)
    model, data = robot.model, robot.data
    ids = {name: robot.frame_id(f"right_{name}") for name in ("foot", "toe", "heel")}
    n = len(thetas)
    ankle, toe, heel, pitch = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros((n, 2)), np.zeros(n)
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(model, data, q)
        ankle[k], toe[k], heel[k] = _xz(data, ids["foot"]), _xz(data, ids["toe"]), _xz(data, ids["heel"])
        pitch[k] = planar_pitch(data.oMf[ids["foot"]].rotation)
    cycle = LegCycle(robot, thetas, qs, ankle, toe, heel, pitch, omega)
    if omega is not None:  # exact v and a of the closed form (its jets), then the ankle's by Pinocchio
        _, cycle.v, cycle.a, _ = closure.analytic_motion(robot, thetas, float(omega))
        cycle.ankle_velocity, cycle.ankle_acceleration = np.zeros((n, 2)), np.zeros((n, 2))
        for k, q in enumerate(qs):
            pin.forwardKinematics(model, data, q, cycle.v[k], cycle.a[k])
            cycle.ankle_velocity[k] = pin.getFrameVelocity(model, data, ids["foot"], LOCAL_WORLD_ALIGNED).linear[[0, 2]]
            accel = pin.getFrameClassicalAcceleration(model, data, ids["foot"], LOCAL_WORLD_ALIGNED)
            cycle.ankle_acceleration[k] = accel.linear[[0, 2]]
    return cycle


def leg_prescriptions(robot) -> list[closure.Prescribed]:
    """What fixes a one-leg pose besides the loops: the crank, and for ``spring`` the foot pitch.

    The ``spring`` foot hangs on a free ankle; here it is held level (pitch 0), as the
    biped holds both its stance and its swing foot.
    """
    out = [closure.joint_coordinate(robot, j) for j in robot.actuated_joints]
    if robot.spec.free_ankle:
        out.append(closure.frame_pitch(robot, "right_foot"))
    return out


def _leg_targets(robot, prescribed, theta: float) -> list[float]:
    return [float(theta) if p.name in robot.actuated_joints else 0.0 for p in prescribed]


def configuration_at(robot, theta: float, q_guess: np.ndarray | None = None) -> np.ndarray:
    """Closed configuration of a one-leg robot at crank angle ``theta`` [rad].

    Warm-started from ``q_guess`` (default: the analytic assembly).
    """
    _check_one_leg(robot)
    if not math.isfinite(theta):
        raise ValueError(f"parameter 'theta' must be finite, got {theta!r}")
    q_guess = closure.assemble(robot, float(theta)) if q_guess is None else q_guess
    prescribed = leg_prescriptions(robot)
    return closure.solve_configuration(robot, q_guess, prescribed, _leg_targets(robot, prescribed, theta))


def sweep(robot, thetas: Sequence[float] | np.ndarray) -> np.ndarray:
    """Closed configurations of a one-leg robot at crank angles (N, nq).

    The closed form (:func:`~pasibot_pin.model.closure.analytic_configurations`, the assembly
    branch of the seed) for every sample at once, then one batched Newton
    (:meth:`~pasibot_pin.constraints.ConstraintSystem.project_many`) that only iterates where the
    closed form is not closed to the tolerance. The ``spring`` foot is held level
    (:func:`leg_prescriptions`).
    """
    _check_one_leg(robot)
    thetas = np.asarray(thetas, dtype=float).reshape(-1)
    if thetas.size == 0 or not np.all(np.isfinite(thetas)):
        raise ValueError("parameter 'thetas' must be a non-empty sequence of finite crank angles [rad]")
    prescribed = leg_prescriptions(robot)
    guess, _ = closure.analytic_configurations(robot, thetas)
    targets = np.array([_leg_targets(robot, prescribed, float(theta)) for theta in thetas])
    try:
        q, _ = closure.system(robot, None, prescribed).project_many(guess, targets)
    except ValueError:  # name the crank angle where the loop cannot close, as Newton per sample does
        q = guess
        for k, theta in enumerate(thetas):
            q[k] = configuration_at(robot, float(theta), guess[k])
    return q


def frame_xz(robot, q: np.ndarray, frame: str = "right_foot") -> np.ndarray:
    """World (x, z) of a frame at ``q`` [m] (the leg frame for a one-leg robot)."""
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return _xz(robot.data, robot.frame_id(frame))


# --------------------------------------------------------------------------- metrics
@dataclass(frozen=True)
class StraightLineMetrics:
    """Straight-line quality of the ankle path (DESIGN §4 reference values in brackets).

    Attributes:
        L: crank length [m].
        ground_z: ankle height at touch-down (theta = 90 deg), the ground line [m] (-28 L).
        lowest_z: lowest ankle height over the turn [m] (-28 L for K = 2).
        stroke: ankle x travel over stance, x(90 deg) - x(270 deg) [m] (8 L).
        ankle_band: peak-to-peak ankle height over stance [m] (0.0195 L).
        deviation: largest distance of the stance ankle from the chord 90 -> 270 deg [m].
        deviation_theta: crank angles of the stance peaks [rad] (128.7 and 231.3 deg).
        lift: largest ankle height above the ground line [m] (1.798 L).
        lift_theta: crank angle of the largest lift [rad] (0).
        tolerance: height tolerance used for the ground span [m].
        ground_span: crank-angle span of the contiguous interval, around the path's lowest
            point, where the ankle is within ``tolerance`` of its lowest height [rad].
        ground_interval: its first and last crank angle [rad] (the first may be negative).
        stance_pitch_max: largest |foot pitch| over stance [rad] (parallel: < 0.12 deg).
        stance_pitch_range: lowest and highest foot pitch over stance [rad].
        pitch_at_zero: foot pitch at theta = 0 [rad] (parallel: about -12.4 deg).

    """

    __repr__ = short_repr

    L: float
    ground_z: float
    lowest_z: float
    stroke: float
    ankle_band: float
    deviation: float
    deviation_theta: tuple[float, float]
    lift: float
    lift_theta: float
    tolerance: float
    ground_span: float
    ground_interval: tuple[float, float]
    stance_pitch_max: float
    stance_pitch_range: tuple[float, float]
    pitch_at_zero: float

    def in_L(self) -> dict[str, float]:
        """The length metrics in units of L and the angles in degrees (for printouts)."""
        return {
            "stroke/L": self.stroke / self.L,
            "ankle_band/L": self.ankle_band / self.L,
            "deviation/L": self.deviation / self.L,
            "lift/L": self.lift / self.L,
            "lift_theta_deg": math.degrees(self.lift_theta),
            "tolerance/L": self.tolerance / self.L,
            "ground_span_deg": math.degrees(self.ground_span),
            "stance_pitch_max_deg": math.degrees(self.stance_pitch_max),
            "pitch_at_zero_deg": math.degrees(self.pitch_at_zero),
        }


def _golden_max(func: Callable[[float], float], a: float, b: float, tol: float = 1e-10) -> tuple[float, float]:
    """Maximum of a unimodal function on [a, b] by golden-section search: (argmax, max)."""
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = func(c), func(d)
    while b - a > tol:
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - ratio * (b - a)
            fc = func(c)
        else:
            a, c, fc = c, d, fd
            d = a + ratio * (b - a)
            fd = func(d)
    x = (a + b) / 2
    return x, func(x)


def _bisect(func: Callable[[float], float], a: float, b: float, tol: float = 1e-12) -> float:
    """Root of ``func`` on [a, b] (a sign change) by bisection."""
    fa = func(a)
    for _ in range(200):
        m = (a + b) / 2
        fm = func(m)
        if (fm > 0) == (fa > 0):
            a, fa = m, fm
        else:
            b = m
        if b - a < tol:
            break
    return (a + b) / 2


class _AnkleProbe:
    """Ankle position and foot pitch at any crank angle, warm-started from the nearest sample."""

    def __init__(self, robot, cycle: LegCycle):
        self.robot, self.cycle = robot, cycle
        self.wrapped = np.mod(cycle.theta, 2 * math.pi)

    def q(self, theta: float) -> np.ndarray:
        diff = np.abs(np.angle(np.exp(1j * (self.wrapped - theta))))
        k = int(np.argmin(diff))
        guess = self.cycle.q[k].copy()
        guess[self.robot.idx_q("right_j0_crank")] = self.cycle.theta[k] + _wrap(theta - self.cycle.theta[k])
        return configuration_at(self.robot, self.cycle.theta[k] + _wrap(theta - self.cycle.theta[k]), guess)

    def z(self, theta: float) -> float:
        return float(frame_xz(self.robot, self.q(theta))[1])

    def pitch(self, theta: float) -> float:
        pin.framesForwardKinematics(self.robot.model, self.robot.data, self.q(theta))
        return planar_pitch(self.robot.data.oMf[self.robot.frame_id("right_foot")].rotation)


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def straight_line_metrics(
    robot, tolerance: float | None = None, step: float = math.radians(1.0)
) -> StraightLineMetrics:
    """Stroke, band, deviation, lift, ground span and foot pitch of a one-leg robot.

    Extremes and ground crossings are refined beyond the sampling (golden section and
    bisection on the closure manifold), so the numbers do not depend on ``step``.

    Args:
        robot: a one-leg robot.
        tolerance: height above the path's lowest point counted as "on the ground" for the
            span [m] (default 0.02 L, just above the stance band 0.0195 L; a tolerance below
            the band gives only the piece of stance around the lowest sample).
        step: sampling step of the crank turn before refinement [rad].

    Returns:
        The :class:`StraightLineMetrics`.

    """
    _check_one_leg(robot)
    L = robot.geometry.L
    tolerance = 0.02 * L if tolerance is None else float(tolerance)
    if not math.isfinite(tolerance) or tolerance <= 0.0:
        raise ValueError(f"parameter 'tolerance' must be a positive height [m], got {tolerance!r}")
    cycle = leg_cycle(robot, crank_grid(step))
    probe = _AnkleProbe(robot, cycle)
    q90, q270 = probe.q(STANCE[0]), probe.q(STANCE[1])
    p90, p270 = frame_xz(robot, q90), frame_xz(robot, q270)
    ground = float(p90[1])
    stroke = float(p90[0] - p270[0])
    chord = (p270 - p90) / np.linalg.norm(p270 - p90)
    normal = np.array([-chord[1], chord[0]])

    def distance(theta: float) -> float:
        return float(abs(np.dot(frame_xz(robot, probe.q(theta)) - p90, normal)))

    stance = cycle.in_stance()
    rel = np.abs((cycle.ankle - p90) @ normal)
    peaks = []
    for lo, hi in ((STANCE[0], math.pi), (math.pi, STANCE[1])):
        inside = stance & (np.mod(cycle.theta, 2 * math.pi) >= lo) & (np.mod(cycle.theta, 2 * math.pi) <= hi)
        k = int(np.argmax(np.where(inside, rel, -1.0)))
        th = float(np.mod(cycle.theta[k], 2 * math.pi))
        peaks.append(_golden_max(distance, max(lo, th - step), min(hi, th + step)))
    deviation = max(p[1] for p in peaks)
    # Band: highest and lowest stance heights (the ends are sampled exactly).
    z_stance = cycle.ankle[stance, 1]
    th_stance = np.mod(cycle.theta[stance], 2 * math.pi)
    k_hi, k_lo = int(np.argmax(z_stance)), int(np.argmin(z_stance))

    def window(k: int) -> tuple[float, float]:
        return max(STANCE[0], th_stance[k] - step), min(STANCE[1], th_stance[k] + step)

    z_hi = _golden_max(probe.z, *window(k_hi))[1]
    z_lo = -_golden_max(lambda t: -probe.z(t), *window(k_lo))[1]
    z_lo = min(z_lo, ground, float(p270[1]))
    band = z_hi - z_lo
    # Lift: the highest point of the swing.
    k = int(np.argmax(cycle.ankle[:, 1]))
    th = float(cycle.theta[k])
    lift_theta, z_top = _golden_max(probe.z, th - step, th + step)
    lift = z_top - ground
    # Ground span: the contiguous crank interval, around the lowest point of the path, where
    # the ankle is within ``tolerance`` of that lowest height.
    wrapped = np.mod(cycle.theta, 2 * math.pi)
    order = np.unique(np.round(wrapped, 12), return_index=True)[1]
    w, zw = wrapped[order], cycle.ankle[order, 1]
    k_low = int(np.argmin(zw))
    lowest = min(float(zw[k_low]), ground)
    low = zw - lowest < tolerance
    n = len(w)
    if low.all():
        start, end = 0.0, 2 * math.pi
    else:
        i = k_low
        while low[(i - 1) % n]:
            i -= 1
        j = k_low
        while low[(j + 1) % n]:
            j += 1

        def above(theta: float) -> float:
            return probe.z(theta) - lowest - tolerance

        a0, a1 = float(w[(i - 1) % n]), float(w[i % n])
        b0, b1 = float(w[j % n]), float(w[(j + 1) % n])
        start = _bisect(above, a0, a1 if a1 > a0 else a1 + 2 * math.pi)
        end = _bisect(above, b0, b1 if b1 > b0 else b1 + 2 * math.pi)
        start = start - 2 * math.pi if i < 0 else start
        end = end + 2 * math.pi if end < start else end
    pitch_stance = cycle.foot_pitch[stance]
    extremes = []
    for sign in (1.0, -1.0):  # refine the highest and the lowest stance pitch
        k = int(np.argmax(sign * pitch_stance))
        lo, hi = max(STANCE[0], th_stance[k] - step), min(STANCE[1], th_stance[k] + step)
        extremes.append(sign * _golden_max(lambda t, sg=sign: sg * probe.pitch(t), lo, hi)[1])
    pitch_hi = max(extremes[0], float(pitch_stance.max()))
    pitch_lo = min(extremes[1], float(pitch_stance.min()))
    p0 = probe.q(0.0)
    pin.framesForwardKinematics(robot.model, robot.data, p0)
    pitch0 = planar_pitch(robot.data.oMf[robot.frame_id("right_foot")].rotation)
    return StraightLineMetrics(
        L=L,
        ground_z=ground,
        lowest_z=lowest,
        stroke=stroke,
        ankle_band=float(band),
        deviation=float(deviation),
        deviation_theta=(peaks[0][0], peaks[1][0]),
        lift=float(lift),
        lift_theta=float(_wrap(lift_theta)),
        tolerance=tolerance,
        ground_span=float(end - start),
        ground_interval=(float(start), float(end)),
        stance_pitch_max=float(max(abs(pitch_hi), abs(pitch_lo))),
        stance_pitch_range=(float(pitch_lo), float(pitch_hi)),
        pitch_at_zero=float(pitch0),
    )


# --------------------------------------------------------------------------- K sweep
@dataclass
class KSweep:
    """Leg cycles for several frame ratios K (seed Fig 4.2.4).

    Attributes:
        variant: the leg variant.
        K: the ratios (n,).
        cycles: one :class:`LegCycle` per K.
        metrics: one :class:`StraightLineMetrics` per K.

    """

    __repr__ = short_repr

    variant: str
    K: np.ndarray
    cycles: list[LegCycle] = field(default_factory=list)
    metrics: list[StraightLineMetrics] = field(default_factory=list)


def k_sweep(
    K_values: Sequence[float] = (1.8, 2.0, 2.2),
    variant: str = "rigid",
    step: float = math.radians(2.0),
    **load_kwargs,
) -> KSweep:
    """Leg cycles and metrics of a one-leg robot for several K = L0 / L.

    Args:
        K_values: frame ratios to compare.
        variant: leg variant.
        step: crank sampling step [rad].
        **load_kwargs: passed to :func:`pasibot_pin.load` (``L=...``).

    Raises:
        ValueError: an empty list, a non-positive K, or a K at which a loop cannot close
            (named by the foundation's assembly).

    """
    from pasibot_pin.model.robot import load

    ks = np.asarray(list(K_values), dtype=float)
    if ks.size == 0 or not np.all(np.isfinite(ks)) or np.any(ks <= 0):
        raise ValueError(f"parameter 'K_values' must be positive finite ratios, got {list(K_values)!r}")
    out = KSweep(variant, ks)
    for k in ks:
        robot = load(variant, 1, K=float(k), **load_kwargs)
        out.cycles.append(leg_cycle(robot, crank_grid(step)))
        out.metrics.append(straight_line_metrics(robot, step=step))
    return out


# --------------------------------------------------------------------------- Jacobians
def open_chain_columns(robot, side: str = "right") -> list[int]:
    """Velocity indices of the open chain theta1, theta2, theta4, theta6 of one leg."""
    return [robot.idx_v(f"{side}_{j}") for j in OPEN_CHAIN]


def ankle_on_chain(robot, side: str = "right") -> str:
    """Name of a frame at the ankle (joint 13) carried by the shank L5, the chain's end.

    ``rigid``: the foot (rigid to L5); ``spring``: the foot (at joint 13; its own ankle
    joint is outside the chain); ``parallel``: the shank's side of the cut joint 13.
    """
    return f"{side}_{robot.spec.ankle_frame}"


def open_chain_jacobian(robot, q: np.ndarray, side: str = "right", frame: str | None = None) -> np.ndarray:
    """The seed's 6x4 geometric Jacobian from joint 0 to the ankle (seed §5).

    Columns: the rates of ``j0_crank``, ``j1``, ``j4``, ``j6`` (seed theta1, theta2, theta4,
    theta6), the tree joints between the hip and the ankle. Rows: linear velocity (x, y, z)
    [m/s per rad/s] and angular velocity (x, y, z) [rad/s per rad/s] of the ankle, in the
    hip frame's axes (the leg frame; for one leg, the world). Column i is the seed's
    ``[z_i x (p_e - p_i); z_i]`` with the joint axis z_i = -y, i.e.
    ``(-(z_e - z_i), 0, x_e - x_i, 0, -1, 0)``.

    Args:
        robot: a loaded robot (one or two legs).
        q: configuration (need not close the loops: this is the open chain).
        side: ``right`` or ``left``.
        frame: end frame (default :func:`ankle_on_chain`); it must ride on the shank L5.

    Returns:
        Array (6, 4).

    Raises:
        ValueError: a wrong-size ``q`` or a frame not carried by the chain.

    """
    model, data = robot.model, robot.data
    q = np.asarray(q, dtype=float)
    if q.shape != (model.nq,):
        raise ValueError(f"parameter 'q' must have size nq = {model.nq}")
    frame = ankle_on_chain(robot, side) if frame is None else frame
    fid = robot.frame_id(frame)
    shank = model.getJointId(f"{side}_j6")
    parent = model.frames[fid].parentJoint
    if parent != shank and shank not in model.supports[parent]:
        raise ValueError(f"frame {frame!r} is not carried by the open chain j0_crank-j1-j4-j6 of the {side} leg")
    jac = frame_jacobian(model, data, q, fid)
    cols = jac[:, open_chain_columns(robot, side)]
    if robot.floating:  # express in the hip frame's axes
        pin.framesForwardKinematics(model, data, q)
        rot = data.oMf[robot.frame_id("hip")].rotation.T
        cols = np.vstack((rot @ cols[:3], rot @ cols[3:]))
    return cols


@dataclass(frozen=True)
class AnkleMotion:
    """Motion of a one-leg robot's ankle at one crank angle, constant crank rate.

    Attributes:
        theta: crank angle [rad].
        omega: crank rate [rad/s].
        q: configuration.
        v: joint velocities on the closure manifold (nv,).
        a: joint accelerations on the closure manifold (nv,).
        jacobian: constrained Jacobian, ankle (x, z) velocity per unit crank rate (2,) [m/rad].
        velocity: ankle (x, z) velocity [m/s].
        acceleration: ankle (x, z) acceleration [m/s^2] (= J a + drift).
        drift: ankle (x, z) acceleration at zero joint acceleration [m/s^2] (Jdot v).
        chain_rates: rates of the open chain j0_crank, j1, j4, j6 [rad/s].

    """

    __repr__ = short_repr

    theta: float
    omega: float
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    jacobian: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    drift: np.ndarray
    chain_rates: np.ndarray


def _crank_rates(robot, omega: float) -> np.ndarray:
    """Rates of :func:`leg_prescriptions`: the crank at omega, the rest 0."""
    return np.array([omega if p.name in robot.actuated_joints else 0.0 for p in leg_prescriptions(robot)])


def constrained_jacobian(robot, q: np.ndarray, frame: str = "right_foot") -> np.ndarray:
    """Velocity of a frame's origin per unit crank rate on the closure manifold (x, z) [m/rad].

    Solves [J_c; J_s] v = [0; e_crank] for the joint rates of a unit crank rate, then maps
    them by the frame Jacobian. For one leg this is d(x, z)/d theta of the frame.
    """
    _check_one_leg(robot)
    prescribed = leg_prescriptions(robot)
    v = closure.solve_velocity(robot, q, prescribed, _crank_rates(robot, 1.0))
    jac = frame_jacobian(robot.model, robot.data, q, robot.frame_id(frame))
    return (jac @ v)[[0, 2]]


def ankle_motion(robot, q: np.ndarray, omega: float = 0.1, frame: str = "right_foot") -> AnkleMotion:
    """Ankle velocity and acceleration at ``q`` for a crank turning at constant ``omega``.

    v solves [J_c; J_s] v = [0; omega]; a solves [J_c; J_s] a = [-Jdot_c v; 0]. The ankle
    velocity is J v and its acceleration J a + Jdot v, the drift Jdot v being the frame's
    classical acceleration at a = 0 (Pinocchio).

    Args:
        robot: a one-leg robot.
        q: a closed configuration.
        omega: crank rate [rad/s].
        frame: the tracked frame (default the ankle, ``right_foot``).

    """
    _check_one_leg(robot)
    _check_omega(omega)
    model, data = robot.model, robot.data
    prescribed = leg_prescriptions(robot)
    rates = _crank_rates(robot, omega)
    v = closure.solve_velocity(robot, q, prescribed, rates)
    a = closure.solve_acceleration(robot, q, v, prescribed, np.zeros(len(prescribed)))
    fid = robot.frame_id(frame)
    jac = frame_jacobian(model, data, q, fid)
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    drift = pin.getFrameClassicalAcceleration(model, data, fid, LOCAL_WORLD_ALIGNED).linear[[0, 2]]
    velocity = (jac @ v)[[0, 2]]
    acceleration = (jac @ a)[[0, 2]] + drift
    return AnkleMotion(
        theta=float(q[robot.idx_q("right_j0_crank")]),
        omega=float(omega),
        q=np.array(q),
        v=v,
        a=a,
        jacobian=velocity / omega,
        velocity=velocity,
        acceleration=acceleration,
        drift=drift,
        chain_rates=v[open_chain_columns(robot)],
    )
