"""The quasi-static limit omega -> 0 of a welded walk: the hip pitch where the robot stands still.

At each crank angle (cranks held, the swing foot at the spring's rest angle) the hip-holding
torque tau(pitch) (:meth:`StaticProblem.torque`) is driven to zero by the
secant method (:func:`static_equilibrium`), with its stability d^2V/dpitch^2. A whole sweep of
springs and angles at once: :func:`pasibot_pin.studies.methods.static_batch.static_equilibria`. Used by the
spring study (:mod:`pasibot_pin.studies.spring_study`) and the floor's quasi-static answer
(:mod:`pasibot_pin.studies.floor_static`).

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from pasibot_pin.constraints import ConstraintSystem, coordinate
from pasibot_pin.dynamics.simulator import BipedSimulator, SimulationSettings
from pasibot_pin.dynamics.spring_energy import AnkleSpring
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.coordinates import HIP_PITCH, other
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot


# --------------------------------------------------------------------------- statics (the omega -> 0 limit)
@dataclass
class StaticEquilibrium:
    """Hip pitch at static equilibrium along the crank cycle (cranks still, swing foot at rest angle).

    Attributes:
        theta: right crank angles (n,) [rad].
        hip_pitch: equilibrium hip pitch (n,) [rad]; NaN where there is none within the search range.
        stiffness: d(holding torque)/d(pitch) at the equilibrium, i.e. d^2V/dpitch^2 (n,)
            [N.m/rad]: positive when the equilibrium is stable, negative when the robot falls away.
        found: True where an equilibrium was found.

    """

    __repr__ = short_repr

    theta: np.ndarray
    hip_pitch: np.ndarray
    stiffness: np.ndarray
    found: np.ndarray

    @property
    def max_excursion(self) -> float:
        """Largest |equilibrium hip pitch| [rad] (inf when some crank angle has no stable equilibrium)."""
        if not np.all(self.found) or np.any(self.stiffness <= 0):
            return math.inf
        return float(np.max(np.abs(self.hip_pitch)))


class StaticProblem:
    """The hip-holding torque as a function of the hip pitch, at one crank angle.

    Cranks locked at ``theta``, swing ankle at the rest angle, stance foot welded flat.
    ``cache`` (a dict) lets several springs share the work that does not depend on the
    stiffness: the assembly at each crank angle, and per (crank angle, rest angle) the
    constraint system and the projections onto it (the same start and pitch give the same q;
    only the torque, from the spring forces, differs).
    """

    projections: dict
    """Closed configurations already found, by hip pitch (shared through ``cache`` by the problems of one angle)."""

    def __init__(self, robot: PasibotRobot, spring: AnkleSpring | None, theta: float, cache: dict | None = None):
        spring = spring if spring is not None else AnkleSpring(0.0, math.pi / 2)
        settings = SimulationSettings(omega=0.0, spring=spring, hip="level", swing_ankle="rest", theta0=theta)
        self.robot = robot
        self.sim = BipedSimulator(robot, settings)
        key = round(float(theta), 12)
        shared_key = ("system", key, float(spring.rest_angle))
        if cache is not None and shared_key in cache:
            self.q_level, self.cset, self.targets, self.projections = cache[shared_key]
            self.row = self.cset.nrows - 1
            return
        if cache is not None and key in cache:
            q_level, stance, weld = cache[key]
        else:
            q_level, _, stance = self.sim.initial_state()
            weld = self.sim.ground_weld(stance, q_level)
            if cache is not None:
                cache[key] = (q_level, stance, weld)
        self.q_level = q_level.copy()
        swing = other(stance)
        self.q_level[self.sim.ankles[swing]] = math.pi / 2 - spring.rest_angle
        # one system per crank angle: the swing ankle's rest angle and the hip pitch are targets of their
        # rows (offset 0, so a target t gives the residual q_i - t, the same bits as an offset t)
        system_key = ("rows", key)
        if cache is not None and system_key in cache:
            self.cset = cache[system_key]
        else:
            coords = [c.at(0.0) if c.name == f"{swing}_j13_ankle" else c for c in self.sim.coordinate_rows(stance)]
            coords = [c for c in coords if c.name != "hip_pitch"]
            cmodels = list(robot.loop_constraints) + [weld]
            rows = [*coords, coordinate("hip_pitch", HIP_PITCH)]  # the hip-pitch row is last
            self.cset = ConstraintSystem(robot.model, robot.data, cmodels, rows, robot.geometry.L)
            if cache is not None:
                cache[system_key] = self.cset
        self.targets = self.cset.targets(0.0)
        self.targets[self.cset.labels.index(f"{swing}_j13_ankle") - self.cset.n_constraint_rows] = (
            math.pi / 2 - spring.rest_angle
        )
        self.row = self.cset.nrows - 1
        self.projections = {}
        if cache is not None:
            cache[shared_key] = (self.q_level, self.cset, self.targets, self.projections)

    def torque(self, pitch: float, q_guess=None) -> tuple[float, np.ndarray]:
        """The hip-holding torque [N.m] at hip pitch ``pitch`` [rad], and the static q it solved.

        ``q_guess``: the Newton start (default: the level pose at this crank angle).

        At rest the system is square (nv rows: loops, weld, cranks, swing ankle, hip), so J a = 0
        gives a = 0 and M a + h = tau + J^T lambda reduces to J^T lambda = g(q) - tau_spring(q): the
        hip row's multiplier is x . (g - tau_spring) with J x = e_hip. x . g and x on the ankles
        depend on q only and are kept with the projection (shared by every stiffness).
        """
        q = self.q_level if q_guess is None else np.array(q_guess, dtype=float)
        key = (float(pitch), q.tobytes())
        entry = self.projections.get(key)
        if entry is None:
            targets = self.targets.copy()
            targets[-1] = pitch
            q, rows, _ = self.cset.project_rows(q, 0.0, targets=targets, metric="mass", max_iter=20)
            entry = self.projections[key] = (q.copy(), *self._hip_row(q, rows.jac))
        q, x_gravity, x_ankles = entry
        # tau_spring on an ankle coordinate is -T = K_e (beta - beta0) (damping: no rate at rest)
        spring = self.sim.settings.spring
        if spring is None:
            raise ParameterError("a static problem needs an ankle spring")
        hold = x_gravity
        for i, x_i in x_ankles:
            hold -= x_i * spring.stiffness * ((math.pi / 2 - q[i]) - spring.rest_angle)
        return float(hold), q.copy()

    def _hip_row(self, q: np.ndarray, jac: np.ndarray) -> tuple[float, tuple[tuple[int, float], ...]]:
        """The hip row's multiplier map: x . g(q) and x on each ankle coordinate, for J x = e_hip."""
        model, data = self.robot.model, self.robot.data
        unit = np.zeros(self.cset.nrows)
        unit[self.row] = 1.0
        x = np.linalg.solve(jac, unit)
        gravity = pin.computeGeneralizedGravity(model, data, q)
        return float(x.dot(gravity)), tuple((i, float(x[i])) for i in self.sim.ankles.values())


def static_equilibrium(
    robot: PasibotRobot,
    spring: AnkleSpring | None,
    thetas: ArrayLike,
    search: float = math.radians(30.0),
    cache: dict | None = None,
) -> StaticEquilibrium:
    """Equilibrium hip pitch at each crank angle (the quasi-static limit omega -> 0).

    For each crank angle, the hip-holding torque tau(pitch) of :meth:`StaticProblem.torque` is
    driven to zero by the secant method from pitch = 0, within +-``search`` [rad]. ``cache``
    (a dict, filled on first use) shares the assembly of each crank angle between calls.
    """
    thetas = np.asarray(thetas, dtype=float)
    pitch = np.full(len(thetas), np.nan)
    stiff = np.full(len(thetas), np.nan)
    found = np.zeros(len(thetas), dtype=bool)
    for k, theta in enumerate(thetas):
        try:
            problem = StaticProblem(robot, spring, float(theta), cache)
            p0, p1 = 0.0, 1e-3
            f0, q = problem.torque(p0)
            f1, q = problem.torque(p1, q)
            for _ in range(30):
                if f1 == f0:
                    break
                p2 = p1 - f1 * (p1 - p0) / (f1 - f0)
                if abs(p2) > search:
                    break
                p0, f0 = p1, f1
                p1 = p2
                f1, q = problem.torque(p1, q)
                if abs(p1 - p0) < 1e-12:
                    break
            if abs(f1) < 1e-8 and abs(p1) <= search:
                eps = 1e-5
                fp = problem.torque(p1 + eps, q)[0]
                fm = problem.torque(p1 - eps, q)[0]
                pitch[k], stiff[k], found[k] = p1, (fp - fm) / (2 * eps), True
        except ValueError:
            continue
    return StaticEquilibrium(thetas, pitch, stiff, found)
