"""The rimless wheel on a slope: a check of the floor's contact step and of the shooting on a closed form.

A hub of mass ``m`` (and a small rotational inertia ``I``) carries ``spokes`` massless spokes of
length ``l``, ``2 alpha = 2 pi / spokes`` apart, rolling down a slope ``gamma`` (McGeer 1990;
Coleman, Chatterjee and Ruina 1997). Each spoke tip is a unilateral point with Coulomb friction on
the :class:`~pasibot_pin.dynamics.floor.ground.Ground`, stepped by the floor's scheme (Moreau, Anitescu):
the velocity after a step of length ``h`` solves

    min_v  1/2 (v - v-)^T M (v - v-) - h (tau - b)^T v   s.t.   (J_n +- mu J_t) v >= -gap / h

with M and b from Pinocchio (the hub's planar x, z and pitch: the floor's planar root joint), the
QP by the floor's exact warm-started solver (``ContactQP.solve_free``). No impact law is
written: a tip that reaches the slope stops there, a plastic impact found by the step.

The step-to-step map takes the hub's rate at mid-stance (the stance spoke normal to the slope,
interpolated between steps) to the next stride's; :func:`check` finds its fixed point and slope
(see there why by bisection and a secant). With the mass at the hub (``I -> 0``) the closed form
is (angular momentum about the new tip)

    omega+ = cot(2 alpha) sqrt(4 (g / l) sin(alpha) sin(gamma)),   dP/domega+ = cos^2(2 alpha),

for 8 spokes, l = 1 m and gamma = 0.08 rad: 1.09546 rad/s and 0.5 (``tests/test_rimless_wheel.py``).

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.dynamics.floor.qp import ContactQP
from pasibot_pin.errors import NoFixedPointError, ParameterError, SimulationError
from pasibot_pin.model.description import planar_root_joint


@dataclass(frozen=True)
class RimlessWheel:
    """A rimless wheel on a slope (see the module docstring).

    Attributes:
        spokes: number of spokes [-].
        length: spoke length l [m].
        slope: the slope gamma, downhill along +x [rad].
        mass: hub mass [kg].
        inertia: the hub's rotational inertia over m l^2 [-] (0 is the closed form's; a little keeps M regular).
        mu: tip-slope friction [-] (high: the stance tip sticks).
        dt: time step [s].

    """

    spokes: int = 8
    length: float = 1.0
    slope: float = 0.08
    mass: float = 1.0
    inertia: float = 1e-6
    mu: float = 2.0
    dt: float = 2e-5

    def __post_init__(self) -> None:
        if not (isinstance(self.spokes, int) and 3 <= self.spokes <= 64):
            raise ParameterError(f"parameter 'spokes' must be an integer in [3, 64], got {self.spokes!r}")
        for name in ("length", "mass", "dt"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ParameterError(f"parameter {name!r} must be a positive number, got {value!r}")
        if not (0.0 < self.slope < 0.5):
            raise ParameterError(f"parameter 'slope' must be in (0, 0.5) rad, got {self.slope!r}")

    @property
    def alpha(self) -> float:
        """Half the angle between spokes [rad]."""
        return math.pi / self.spokes

    def closed_form(self, gravity: float = 9.81) -> tuple[float, float]:
        """The fixed point's post-impact rate [rad/s] and the map's slope there [-], with the mass at the hub."""
        a, g = self.alpha, gravity
        rate = math.sqrt(4.0 * g / self.length * math.sin(a) * math.sin(self.slope)) / math.tan(2.0 * a)
        return rate, math.cos(2.0 * a) ** 2


class WheelStepper:
    """The wheel's model and its floor step, and the step-to-step map (see the module docstring)."""

    def __init__(self, wheel: RimlessWheel) -> None:
        self.wheel = wheel
        model = pin.Model()
        joint = model.addJoint(0, planar_root_joint(), pin.SE3.Identity(), "hub")
        rotational = wheel.inertia * wheel.mass * wheel.length**2
        model.appendBodyToJoint(
            joint, pin.Inertia(wheel.mass, np.zeros(3), np.diag([rotational] * 3)), pin.SE3.Identity()
        )
        model.gravity.linear[:] = [0.0, 0.0, -9.81]
        self.tips = []
        for k in range(wheel.spokes):
            angle = 2.0 * wheel.alpha * k
            tip = wheel.length * np.array([math.sin(angle), 0.0, -math.cos(angle)])
            frame = pin.Frame(f"tip{k}", joint, 0, pin.SE3(np.eye(3), tip), pin.FrameType.OP_FRAME)
            self.tips.append(model.addFrame(frame, False))
        self.model, self.data = model, model.createData()
        self.ground = Ground(-wheel.slope, wheel.mu)  # rises along +x by -gamma: downhill along +x
        self.qp = ContactQP(model)

    def contact(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each tip's gap (k,) [m] and its normal and tangential Jacobian rows (k, 3)."""
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        points = np.array([data.oMf[i].translation for i in self.tips])
        jac = np.array([pin.getFrameJacobian(model, data, i, pin.LOCAL_WORLD_ALIGNED)[:3] for i in self.tips])
        return (
            self.ground.gap(points),
            jac.transpose(0, 2, 1) @ self.ground.normal,
            jac.transpose(0, 2, 1) @ self.ground.tangents[0],
        )

    def step(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[float]]:
        """One floor step: (q+, v+, each tip's normal impulse [N.s]).

        Every tip's two cone rows enter the QP (a tip far from the slope holds its rows loosely);
        the floor's warm-started exact solve (:meth:`~pasibot_pin.dynamics.floor.qp.ContactQP.solve_free`).
        """
        h, mu = self.wheel.dt, self.wheel.mu
        mass = pin.crba(self.model, self.data, q)
        bias = pin.nonLinearEffects(self.model, self.data, q, v)
        gap, normal, along = self.contact(q)
        cone = np.vstack((normal + mu * along, normal - mu * along))
        lower = np.concatenate((-gap / h, -gap / h))
        g = -(mass @ v - h * bias)
        x, z, _ = self.qp.solve_free(mass.tolist(), g.tolist(), cone.tolist(), lower.tolist(), [0.0] * len(g))
        k = len(self.tips)
        return q + h * np.array(x), np.array(x), [z[i] + z[i + k] for i in range(k)]

    def phase(self, pitch: float) -> float:
        """The stance spoke's angle from the slope's normal, in (-alpha, alpha] [rad]: +alpha as it lands, 0 mid-stance.

        The pitch turns about -y; spoke 0 is normal to the slope at pitch = -gamma.
        """
        a = self.wheel.alpha
        return a - (a - (pitch + self.wheel.slope)) % (2.0 * a)

    def mid_stance(self, rate: float) -> tuple[np.ndarray, np.ndarray]:
        """The state at mid-stance: spoke 0 normal to the slope, its tip at the origin.

        The hub rolls downhill about the tip at ``rate`` [rad/s] (a pitch rate of -rate).
        """
        q = np.array([0.0, 0.0, -self.wheel.slope])
        pin.framesForwardKinematics(self.model, self.data, q)
        r = -self.data.oMf[self.tips[0]].translation[[0, 2]]  # tip -> hub (x, z)
        q[:2] = r
        pitch_rate = -rate  # about -y: the hub's velocity is pitch_rate (0, -1, 0) x r
        return q, np.array([-pitch_rate * r[1], pitch_rate * r[0], pitch_rate])

    def stride(self, rate: float) -> tuple[float, float]:
        """One stride from mid-stance at ``rate``: (the next mid-stance rate, the rate after the landing) [rad/s].

        The next mid-stance is interpolated between the two steps around it. The landing is
        resolved over two steps (the step that brings the tip to the slope, then the one that
        stops it); its rate is the second one's, taken back one step along the slope of the next
        (a first-order correction for the step's length).
        """
        q, v = self.mid_stance(rate)
        self.qp.active = None
        before, previous = self.phase(q[2]), rate
        landing: int | None = None
        rates: list[float] = []
        for k in range(int(20.0 / self.wheel.dt)):
            q, v, impulses = self.step(q, v)
            now = self.phase(q[2])
            if landing is None and any(z > 0.0 for j, z in enumerate(impulses) if j != 0):
                landing = k
            if landing is not None and len(rates) < 3:
                rates.append(-float(v[2]))
            if landing is not None and len(rates) == 3 and before > 0.0 >= now:
                share = before / (before - now)
                return previous + share * (-float(v[2]) - previous), 2.0 * rates[1] - rates[2]
            before, previous = now, -float(v[2])
        raise SimulationError("rimless wheel: no stride within 20 s (it stopped or rolled back)")

    def step_map(self, rate: float) -> float:
        """The mid-stance rate of the next stride [rad/s] from this stride's ``rate`` (the step-to-step map)."""
        return self.stride(rate)[0]


@dataclass(frozen=True)
class WheelCheck:
    """The rimless wheel's periodic roll found on the floor's step, beside the closed form.

    Attributes:
        mid_stance_rate: the fixed point of the mid-stance map [rad/s].
        landing_rate: the rate just after a landing on that roll [rad/s] (closed form: ``closed_rate``).
        slope: the map's slope at the fixed point, a secant over +-``spread`` [-] (closed form: ``closed_slope``).
        closed_rate: cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(gamma)) [rad/s].
        closed_slope: cos^2(2 alpha) [-].
        spread: the secant's half width [rad/s].
        strides: strides simulated.

    """

    mid_stance_rate: float
    landing_rate: float
    slope: float
    closed_rate: float
    closed_slope: float
    spread: float
    strides: int


def check(
    wheel: RimlessWheel | None = None, bracket: tuple[float, float] = (0.4, 0.8), spread: float = 0.05
) -> WheelCheck:
    """The wheel's periodic roll on the floor's step, against the closed form (see the module docstring).

    The map is not smooth below the step's scale: a landing is resolved over two steps, and where in
    a step the tip meets the slope moves the rate after it by O(h) (8e-4 rad/s at h = 1e-4 s). So the
    fixed point is bracketed rather than Newton-shot with finite differences: F(x) - x keeps a sign
    change inside the bracket, each new point is the bracket's secant (regula falsi, Illinois: an end
    that stays twice has its value halved, so both ends close in), and the search stops when the bracket
    is 1e-4 rad/s wide or |F(x) - x| is 1e-4 rad/s or less. F is nearly affine, so this takes about
    half a bisection's strides; the landing rate is that last stride's. The slope is a secant over
    +-``spread``, wide against that jitter.

    Args:
        wheel: the wheel (default :class:`RimlessWheel`).
        bracket: mid-stance rates [rad/s] on both sides of the fixed point.
        spread: the secant's half width [rad/s].

    Raises:
        NoFixedPointError: F(x) - x has the same sign at both ends of ``bracket``.

    """
    stepper = WheelStepper(RimlessWheel() if wheel is None else wheel)
    strides = 0
    landings: dict[float, float] = {}

    def gap(x: float) -> float:
        nonlocal strides
        strides += 1
        after, landings[x] = stepper.stride(x)
        return after - x

    low, high = bracket
    f_low, f_high = gap(low), gap(high)
    if f_low * f_high > 0.0:
        raise NoFixedPointError(
            f"rimless wheel: no fixed point in {bracket} rad/s (F(x) - x: {f_low:+.3g}, {f_high:+.3g})"
        )
    kept = 0  # which end stayed last (-1 low, +1 high): Illinois halves an end that stays twice
    x, f_x = (low, f_low) if abs(f_low) < abs(f_high) else (high, f_high)
    while high - low > 1e-4 and abs(f_x) > 1e-4:
        x = (low * f_high - high * f_low) / (f_high - f_low)
        f_x = gap(x)
        if (f_x > 0.0) == (f_low > 0.0):
            low, f_low = x, f_x
            f_high, kept = (0.5 * f_high if kept == 1 else f_high), 1
        else:
            high, f_high = x, f_x
            f_low, kept = (0.5 * f_low if kept == -1 else f_low), -1
    slope = (stepper.step_map(x + spread) - stepper.step_map(x - spread)) / (2.0 * spread)
    closed_rate, closed_slope = stepper.wheel.closed_form()
    return WheelCheck(float(x), landings[x], float(slope), closed_rate, closed_slope, spread, strides + 2)
