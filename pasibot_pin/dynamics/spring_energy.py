"""The welded walker's physics outside the integrator: the ankle spring, energies and foot poses.

:class:`AnkleSpring` (a linear torsion spring and damper at each ankle) and its forces, the
robot's total energy, a foot's pose and a sole's height above the ground: what the simulator
(:mod:`pasibot_pin.dynamics.simulator`), the lockstep walks and the spring study share.

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import symmetric_mass_matrix
from pasibot_pin.errors import ParameterError

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot


def check_finite(name: str, value: float, minimum: float | None = None) -> float:
    """``value`` as a float if it is finite (and >= ``minimum`` when given), else ParameterError naming ``name``."""
    value = float(value)
    if not math.isfinite(value) or (minimum is not None and value < minimum):
        bound = "" if minimum is None else f" >= {minimum:g}"
        raise ParameterError(f"parameter {name!r} must be a finite number{bound}, got {value!r}")
    return value


# --------------------------------------------------------------------------- the spring
@dataclass(frozen=True)
class AnkleSpring:
    """Linear torsion spring (and damper) at each ankle.

    Attributes:
        stiffness: K_e [N.m/rad].
        rest_angle: beta0, the angle from the forward foot to the shank at zero torque [rad].
        damping: c [N.m.s/rad].

    """

    stiffness: float
    rest_angle: float
    damping: float = 0.0

    def __post_init__(self) -> None:
        check_finite("stiffness", self.stiffness, 0.0)
        check_finite("rest_angle", self.rest_angle)
        check_finite("damping", self.damping, 0.0)

    def torque(self, beta: float, beta_dot: float) -> float:
        """T = -K_e (beta - beta0) - c beta_dot [N.m], the generalised force on beta."""
        return -self.stiffness * (beta - self.rest_angle) - self.damping * beta_dot

    def energy(self, beta: float) -> float:
        """Stored energy 0.5 K_e (beta - beta0)^2 [J]."""
        return 0.5 * self.stiffness * (beta - self.rest_angle) ** 2

    def scaled(self, factor: float) -> AnkleSpring:
        """The same spring with the stiffness times ``factor`` (damping and rest angle kept)."""
        return replace(self, stiffness=self.stiffness * check_finite("factor", factor, 0.0))


def foot_inertia_about_ankle(robot: PasibotRobot, side: str = "right") -> float:
    """Rotational inertia of a foot about its ankle axis [kg.m^2]."""
    joint = robot.model.getJointId(f"{side}_j13_ankle")
    inertia = robot.model.inertias[joint]
    c = inertia.lever
    return float(inertia.inertia[1, 1] + inertia.mass * (c[0] ** 2 + c[2] ** 2))


def critical_foot_damping(robot: PasibotRobot, stiffness: float) -> float:
    """The ankle damping that critically damps the unloaded foot on its spring [N.m.s/rad]."""
    return 2.0 * math.sqrt(check_finite("stiffness", stiffness, 0.0) * foot_inertia_about_ankle(robot))


# --------------------------------------------------------------------------- constraints
def mass_matrix(robot: PasibotRobot, q: np.ndarray) -> np.ndarray:
    """Joint-space mass matrix M(q) (symmetric) [kg, kg.m, kg.m^2]."""
    return symmetric_mass_matrix(robot.model, robot.data, q)


# --------------------------------------------------------------------------- forces and energy
def ankle_indices(robot: PasibotRobot) -> dict[str, int]:
    """Velocity index of each ankle joint, by side."""
    return {side: robot.idx_v(f"{side}_j13_ankle") for side in ("right", "left")}


def ankle_beta(robot: PasibotRobot, q: np.ndarray) -> dict[str, float]:
    """Beta = pi/2 - q_ankle of each ankle [rad]: the angle from the forward foot to the shank."""
    return {side: math.pi / 2 - q[i] for side, i in ankle_indices(robot).items()}


def spring_forces(
    robot: PasibotRobot, spring: AnkleSpring | None, q: np.ndarray, v: np.ndarray, ankles: dict[str, int] | None = None
) -> np.ndarray:
    """Generalised force of the ankle springs (nv,) [N.m]: -T on each ankle coordinate.

    ``ankles``: :func:`ankle_indices` of ``robot`` if already known.
    """
    tau = np.zeros(robot.model.nv)
    if spring is None:
        return tau
    for i in (ankles or ankle_indices(robot)).values():
        tau[i] = -spring.torque(math.pi / 2 - q[i], -v[i])
    return tau


def total_energy(
    robot: PasibotRobot, q: np.ndarray, v: np.ndarray, spring: AnkleSpring | None = None
) -> dict[str, float]:
    """Kinetic, gravity-potential (z = 0 reference) and spring energies [J], and their sum."""
    kinetic = float(pin.computeKineticEnergy(robot.model, robot.data, q, v))
    potential = float(pin.computePotentialEnergy(robot.model, robot.data, q))
    elastic = 0.0 if spring is None else sum(spring.energy(b) for b in ankle_beta(robot, q).values())
    return {"kinetic": kinetic, "potential": potential, "spring": elastic, "total": kinetic + potential + elastic}


def foot_pose(robot: PasibotRobot, q: np.ndarray, side: str) -> tuple[float, float, float]:
    """World x, z [m] of ``side``'s ankle frame and its sole pitch [rad]."""
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    fid = robot.frame_id(f"{side}_foot")
    pose = pin.updateFramePlacement(model, data, fid)
    return float(pose.translation[0]), float(pose.translation[2]), math.atan2(pose.rotation[2, 0], pose.rotation[0, 0])


def sole_height(robot: PasibotRobot, q: np.ndarray, side: str, frames: tuple[int, int] | None = None) -> float:
    """Lowest z of ``side``'s toe and heel [m] (negative: below the ground).

    ``frames``: the toe and heel frame indices of ``side`` if already known.
    """
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    ids = frames or (robot.frame_id(f"{side}_toe"), robot.frame_id(f"{side}_heel"))
    return float(min(pin.updateFramePlacement(model, data, f).translation[2] for f in ids))
