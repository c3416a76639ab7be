"""Is PASIBOT's gait stable? Its step-to-step (Poincaré) map, shot to a fixed point, and its multipliers.

The walk is forced: the cranks turn at omega and each step takes pi / omega. Its gait is
therefore a fixed point of a *stroboscopic* map: the state at the section (the right crank at
mid-stance, theta = pi) mapped to the state half a crank turn later, with the legs mirrored
(right <-> left), since then the left leg stands where the right one stood.

The state on the section is what the cranks do not prescribe, less the hip's forward position
(the floor is the same everywhere, so the map does not depend on it): the hip's height and pitch
and, with ankle springs, both ankle angles; then the rates of the hip's x, z and pitch and of the
ankles. A state is made whole by Newton on the loops with the cranks at the section's angle
(:meth:`GaitMap.configuration`); one map evaluation is a floor run of pi / omega from it.

:func:`gait_stability` walks the design a few steps (the warm-up), takes the state at the last
section as the guess, shoots the fixed point (:func:`~pasibot_pin.studies.methods.poincare.find_fixed_point`),
and gives the Floquet multipliers (eigenvalues of the linearised map; the gait is stable when all
have modulus < 1) and a basin estimate: the largest hip-pitch rate kick at the section from which
the walk returns (:func:`~pasibot_pin.studies.methods.poincare.basin_estimate`).

Units: SI, angles [rad], rates [rad/s, m/s].
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from pasibot_pin.constraints import coordinate
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.spring_energy import ankle_indices
from pasibot_pin.errors import DivergedError, NoFixedPointError, ParameterError
from pasibot_pin.model.coordinates import HIP_PITCH, HIP_X, HIP_Z
from pasibot_pin.model.design import design_robot
from pasibot_pin.studies.methods.map_fit import FittedFixedPoint, fit_fixed_point
from pasibot_pin.studies.methods.poincare import BasinEstimate, FixedPoint, basin_estimate, find_fixed_point
from pasibot_pin.studies.walking import WalkSettings, walk_design

SECTION_THETA = math.pi
"""The right crank's angle on the section: mid-stance of the right leg [rad]."""


@dataclass(frozen=True)
class StabilitySettings:
    """How to shoot the gait.

    Attributes:
        warmup_steps: steps walked before the guess is taken [-].
        tol: the fixed point's tolerance, max |F(x) - x| [state units].
        max_iter: most Newton iterations [-].
        fd_step: finite-difference step, relative to each component's scale [-].
        relax_steps: plain steps x <- F(x) tried before Newton, each kept if it lowers the residual [-].
        basin_kicks: hip-pitch rate kicks tried for the basin [rad/s], increasing.
        basin_steps: steps a kicked walk has to return in [-].
        basin_tol: "returned" when the state is this close to the fixed point [state units].
        fit_steps: where Newton finds no fixed point (a step map that is not smooth: see
            :mod:`~pasibot_pin.studies.methods.map_fit`), the steps simulated for the fitted map; 0: no fit [-].
        fit_kick: the hip-pitch rate kick the fitted steps start with, to excite the gait's slow modes [rad/s].
        stall_ratio: Newton gives up (and the fit takes over) when an iteration after its first leaves
            the residual above this fraction of its value before: a step map that is not smooth stalls
            at the size of its jumps, and each more iteration costs a Jacobian and a line search [-].

    """

    warmup_steps: int = 4
    tol: float = 1e-6
    max_iter: int = 4
    fd_step: float = 1e-3
    relax_steps: int = 2
    basin_kicks: tuple[float, ...] = (0.1, 0.5, 2.0, 5.0)
    basin_steps: int = 4
    basin_tol: float = 1e-3
    fit_steps: int = 30
    fit_kick: float = 0.05
    stall_ratio: float = 0.5

    def __post_init__(self) -> None:
        for name in ("warmup_steps", "max_iter", "basin_steps"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 1000:
                raise ParameterError(f"parameter {name!r} must be an integer in [1, 1000], got {value!r}")
        relax = self.relax_steps
        if isinstance(relax, bool) or not isinstance(relax, int) or not 0 <= relax <= 100:
            raise ParameterError(f"parameter 'relax_steps' must be an integer in [0, 100], got {relax!r}")
        fit = self.fit_steps
        if isinstance(fit, bool) or not isinstance(fit, int) or not (fit == 0 or 24 <= fit <= 1000):
            raise ParameterError(f"parameter 'fit_steps' must be 0 or an integer in [24, 1000], got {fit!r}")
        if not (isinstance(self.fit_kick, (int, float)) and math.isfinite(self.fit_kick) and 0 <= self.fit_kick <= 1):
            raise ParameterError(f"parameter 'fit_kick' must be a number in [0, 1] rad/s, got {self.fit_kick!r}")
        if not (isinstance(self.stall_ratio, float) and 0 < self.stall_ratio < 1):
            raise ParameterError(f"parameter 'stall_ratio' must be a number in (0, 1), got {self.stall_ratio!r}")
        for name in ("tol", "fd_step", "basin_tol"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and 0 < value < 1):
                raise ParameterError(f"parameter {name!r} must be a number in (0, 1), got {value!r}")


class GaitMap:
    """The stroboscopic step-to-step map of a design's forced walk (see the module docstring).

    Args:
        robot: the design's two-legged robot.
        floor: the walk's :class:`~pasibot_pin.dynamics.floor.FloorSettings`.
        guess: a configuration near the section (Newton's start when a state is made whole).

    """

    def __init__(self, robot, floor, guess: np.ndarray | None = None) -> None:
        self.robot = robot
        self.guess = None if guess is None else np.array(guess, dtype=float)  # Newton's start for every state
        self.period = math.pi / floor.omega
        self.sim = FloorSimulator(robot, replace(floor, theta0=SECTION_THETA, crank_ramp=0.0))
        ankles = ankle_indices(robot) if robot.spec.free_ankle else {}
        self.ankles = [ankles[side] for side in ("right", "left")] if ankles else []
        self.q_index = [HIP_Z, HIP_PITCH, *self.ankles]
        self.v_index = [HIP_X, HIP_Z, HIP_PITCH, *self.ankles]
        base = self.sim.bilateral
        pinned = [coordinate(f"q{i}", i, 0.0) for i in (HIP_X, *self.q_index)]
        self.pinned = base.with_scalars([*base.scalars, *pinned])
        self.n_motors = len(base.scalars)
        self.evaluations = 0

    @property
    def size(self) -> int:
        """Dimension of the state on the section [-]."""
        return len(self.q_index) + len(self.v_index)

    def state(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The section's state of (q, v): hip z, pitch, ankles; the rates of hip x, z, pitch, ankles."""
        return np.concatenate((q[self.q_index], v[self.v_index]))

    def mirrored(self, x: np.ndarray) -> np.ndarray:
        """The state with the legs exchanged (the ankles' angles and rates swapped)."""
        x = np.array(x, dtype=float)
        if self.ankles:
            nq = len(self.q_index)
            for k in (2, nq + 3):  # the ankles follow the hip's entries
                x[k], x[k + 1] = x[k + 1], x[k]
        return x

    def configuration(self, x: np.ndarray, guess: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(q, v) of section state ``x``: the loops closed with the cranks at the section's angle, hip x = 0."""
        nq = len(self.q_index)
        crank_targets = self.sim.targets(0.0)
        q = self.sim.initial_state()[0] if guess is None else np.array(guess, dtype=float)
        q[HIP_X] = 0.0
        for k, target in zip(self.sim.motor_index, crank_targets):  # a long walk's cranks have turned many times
            q[k] = target + math.remainder(q[k] - target, 2.0 * math.pi)
        targets = np.concatenate((crank_targets, [0.0], x[:nq]))
        q = self.pinned.project(q, 0.0, targets=targets)
        rates = np.concatenate(([self.sim.settings.omega] * self.n_motors, x[nq:]))
        v = self.pinned.velocity(q, 0.0, rates=rates)
        return q, v

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """F(x): the state half a crank turn later, mirrored.

        Raises:
            DivergedError: the walk fell (|hip pitch| past the verdict's limit) or broke.

        """
        self.evaluations += 1
        q, v = self.configuration(np.asarray(x, dtype=float), self.guess)
        result = self.sim.run(self.period, q, v)
        if result.stopped:
            raise DivergedError(f"the step failed: {result.stop_reason}")
        if float(np.max(np.abs(result.hip_pitch))) > math.radians(10.0):
            raise DivergedError("the step failed: |hip pitch| passed 10 deg")
        return self.mirrored(self.state(result.q[-1], result.v[-1]))


@dataclass
class GaitStability:
    """The gait's fixed point, multipliers and basin.

    Attributes:
        fixed_point: the :class:`~pasibot_pin.studies.methods.poincare.FixedPoint` (its ``multipliers``,
            sorted by modulus, and ``stable``).
        basin: the hip-pitch rate kick bracket (:class:`~pasibot_pin.studies.methods.poincare.BasinEstimate`)
            [rad/s], or ``None`` if not estimated.
        labels: the names of the state's components.
        evaluations: map evaluations (each a floor run of pi / omega) [-].
        cpu_s: CPU time of the shooting, the basin and any warm-up walk [s].
        newton_note: why Newton found no fixed point, when the fixed point is a fitted one
            (:class:`~pasibot_pin.studies.methods.map_fit.FittedFixedPoint`); "" otherwise.

    """

    fixed_point: FixedPoint
    basin: BasinEstimate | None
    labels: list[str]
    evaluations: int
    cpu_s: float = math.nan
    newton_note: str = ""

    @property
    def fitted(self) -> bool:
        """True when the multipliers are those of a map fitted to simulated steps, not Newton's."""
        return isinstance(self.fixed_point, FittedFixedPoint)

    @property
    def multipliers(self) -> np.ndarray:
        """The Floquet multipliers, largest modulus first."""
        return self.fixed_point.multipliers

    @property
    def stable(self) -> bool:
        """True when every multiplier has modulus < 1."""
        return bool(self.fixed_point.stable)

    def summary(self) -> str:
        """Two lines: the multipliers and the verdict, then the basin."""
        mods = ", ".join(f"{abs(z):.3f}" for z in self.multipliers[:4])
        verdict = f"gait {'stable' if self.stable else 'unstable'}: |multipliers| {mods}"
        point = self.fixed_point
        if isinstance(point, FittedFixedPoint):
            low, high = point.spread
            return (
                f"{verdict} (dominant {point.dominant:.4g}, {low:.3f} to {high:.3f} over either half of the steps;"
                f" fitted to {point.evaluations} simulated steps, the step map not being smooth enough for Newton:"
                f" each step lands {_jitter(point, self.labels)} off the averaged map, the floor's time step"
                f" splitting the foot's landings; {self.evaluations} steps simulated in {self.cpu_s:.1f} s of CPU)"
                "\nbasin: not estimated (a kicked walk returns only to within the steps' jitter)"
            )
        text = (
            f"{verdict} (dominant {point.dominant:.4g}; Newton shooting with forward differences of the"
            f" step map, {self.evaluations} steps simulated in {self.cpu_s:.1f} s of CPU)"
        )
        if self.basin is not None and math.isinf(self.basin.failing):
            text += f"\nbasin: the walk returns from every hip-pitch rate kick tried, up to {self.basin.returning:.3g}"
            text += " rad/s"
        elif self.basin is not None:
            text += (
                f"\nbasin: the walk returns from a hip-pitch rate kick of {self.basin.returning:.3g} rad/s"
                f" and not from {self.basin.failing:.3g} rad/s"
            )
        return text

    def __repr__(self) -> str:
        return f"GaitStability({self.summary()!r})"


def _jitter(point: FittedFixedPoint, labels: list[str]) -> str:
    """The fit's RMS residual in the hip's forward speed [m/s] and pitch rate [rad/s], in words."""
    assert point.jitter is not None
    speed, rate = (point.jitter[labels.index(name)] for name in ("hip_vx_m_s", "hip_pitch_rate_rad_s"))
    return f"{speed:.2g} m/s (hip forward speed) and {rate:.2g} rad/s (pitch rate) RMS"


def section_state(gait_map: GaitMap, walk) -> tuple[np.ndarray, np.ndarray]:
    """The state at the last section of ``walk`` (right crank at mid-stance), and its q (a Newton guess).

    Raises:
        NoFixedPointError: the walk did not reach a section after its ramp (it failed first).

    """
    result, omega = walk.result, walk.omega
    theta = walk.settings.theta0 + omega * (result.t - 0.5 * walk.settings.crank_ramp)
    turns = (theta - SECTION_THETA) / (2 * math.pi)
    after_ramp = result.t > walk.settings.crank_ramp
    crossing = np.flatnonzero(after_ramp[1:] & (np.floor(turns[1:]) > np.floor(turns[:-1]))) + 1
    if not len(crossing):
        raise NoFixedPointError("no gait to shoot: the walk reached no section (right crank at mid-stance)")
    k = int(crossing[-1])
    return gait_map.state(result.q[k], result.v[k]), result.q[k]


def gait_stability(design, walk=None, settings: StabilitySettings | None = None, robot=None) -> GaitStability:
    """Shoot the design's gait and linearise it (see the module docstring).

    Args:
        design: the :class:`~pasibot_pin.model.design.Design`.
        walk: its :class:`~pasibot_pin.studies.walking.DesignWalk` (walked here if ``None``).
        settings: :class:`StabilitySettings`.
        robot: its robot, if built.

    Raises:
        NoFixedPointError: no periodic gait near the walk (it falls, or Newton does not converge).

    """
    start = time.process_time()
    settings = StabilitySettings() if settings is None else settings
    robot = design_robot(design, 2, visuals=False) if robot is None else robot
    if walk is None or walk.verdict.steps < settings.warmup_steps:
        walk = walk_design(design, WalkSettings(steps=settings.warmup_steps), robot)
    gait_map = GaitMap(robot, walk.settings)
    x0, gait_map.guess = section_state(gait_map, walk)
    point, newton_note = _shoot(gait_map, x0, settings)
    basin = None
    if settings.basin_kicks and not newton_note:
        pitch_rate = len(gait_map.q_index) + 2
        basin = basin_estimate(
            gait_map,
            point.x,
            pitch_rate,
            perturbations=settings.basin_kicks,
            steps=settings.basin_steps,
            tol=settings.basin_tol,
            bisections=2,
        )
    labels = ["hip_z_m", "hip_pitch_rad", *[f"{s}_ankle_rad" for s in ("right", "left")][: len(gait_map.ankles)]]
    labels += ["hip_vx_m_s", "hip_vz_m_s", "hip_pitch_rate_rad_s"]
    labels += [f"{s}_ankle_rate_rad_s" for s in ("right", "left")][: len(gait_map.ankles)]
    return GaitStability(point, basin, labels, gait_map.evaluations, time.process_time() - start, newton_note)


def _shoot(gait_map: GaitMap, x0: np.ndarray, settings: StabilitySettings) -> tuple[FixedPoint, str]:
    """(the gait's fixed point, "" or why Newton found none): Newton, else the map fitted to simulated steps.

    Raises:
        NoFixedPointError: neither finds one (the walk falls, or no fit is asked for).

    """
    scale = np.maximum(np.abs(x0), [0.01] * len(gait_map.q_index) + [0.1] * len(gait_map.v_index))
    try:
        point = find_fixed_point(
            gait_map,
            x0,
            tol=settings.tol,
            max_iter=settings.max_iter,
            fd_step=settings.fd_step,
            scale=scale,
            scheme="forward",
            relax_steps=settings.relax_steps,
            stall_ratio=settings.stall_ratio,
        )
        return point, ""
    except NoFixedPointError as err:
        if not settings.fit_steps:
            raise
        newton = str(err)
    kick = np.zeros(gait_map.size)
    kick[len(gait_map.q_index) + 2] = settings.fit_kick  # the hip's pitch rate
    try:
        return fit_fixed_point(gait_map, x0, settings.fit_steps, kick), newton
    except NoFixedPointError as err:
        raise NoFixedPointError(f"{newton}; nor a map fitted to {settings.fit_steps} simulated steps: {err}") from err
