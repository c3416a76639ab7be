"""Is the 3-D gait stable? The step-to-step map with the hip free to roll and yaw, and its multipliers.

The 3-D walk is forced as the planar one is (:mod:`pasibot_pin.studies.gait_stability`): its gait is
a fixed point of the stroboscopic map from the right crank at mid-stance to half a crank turn
later, legs mirrored. On the 3-D floor the mirror also flips the sideways quantities: the hip's
lateral velocity, roll, roll rate and yaw rate change sign when the left leg takes the right's place.

The floor is the same everywhere and in every heading, so the map does not depend on the hip's x,
y or yaw: the state is read in the hip's heading frame (yaw removed), and it is the hip's height,
roll and pitch, then its linear velocity (forward, left, up) and angular velocity (about those
axes) [9]. The legs follow from the cranks and the loops (:meth:`GaitMap.configuration` closes
them); a springless variant only (an ankle spring adds two states the 3-D map does not carry).

:func:`gait_stability_3d` starts from the planar gait's fixed point (the symmetric walker's 3-D
gait is the planar one with every sideways quantity zero), shoots the 3-D fixed point, and gives
the 9 multipliers. Roll and yaw are not pinned by flat feet as pitch is: their multipliers are the
ones a planar analysis cannot give.

Units: SI, angles [rad], rates [rad/s, m/s].
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.dynamics.verdict import FAILURES
from pasibot_pin.errors import DivergedError, ParameterError
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.spatial import Footprint, planar_to_spatial, planar_velocity_to_spatial
from pasibot_pin.studies.gait_stability import GaitMap, StabilitySettings, gait_stability
from pasibot_pin.studies.methods.poincare import FixedPoint, find_fixed_point
from pasibot_pin.studies.walking import WalkSettings, floor_settings

LABELS_3D: tuple[str, ...] = (
    "hip_z_m", "hip_roll_rad", "hip_pitch_rad", "hip_v_forward_m_s", "hip_v_left_m_s", "hip_v_up_m_s",
    "roll_rate_rad_s", "pitch_axis_rate_rad_s", "yaw_rate_rad_s",
)  # fmt: skip
"""The 3-D section state's components, in the hip's heading frame."""

MIRRORED: tuple[int, ...] = (1, 4, 6, 8)
"""Components that change sign when the legs exchange: roll, lateral velocity, roll rate, yaw rate."""


class GaitMap3D:
    """The stroboscopic step map of a design's forced 3-D walk (see the module docstring).

    Args:
        robot: the design's two-legged robot (no free ankle).
        floor: the walk's :class:`~pasibot_pin.dynamics.floor.settings.FloorSettings`.
        footprint: the soles' lateral shape.
        guess: a planar configuration near the section (Newton's start when the loops are closed).

    """

    def __init__(self, robot, floor, footprint: Footprint, guess: np.ndarray | None = None) -> None:
        if robot.spec.free_ankle:
            raise ParameterError("parameter 'variant': the 3-D gait's stability is for a variant without ankle springs")
        self.planar = GaitMap(robot, floor, guess)
        self.engine = Floor3D(self.planar.sim, footprint, Ground(0.0, floor.mu))
        self.period = self.planar.period
        self.evaluations = 0

    size = len(LABELS_3D)

    def lift(self, x2: np.ndarray) -> np.ndarray:
        """The 3-D state of a planar section state (z, pitch, vx, vz, pitch rate): every sideways one 0."""
        z, pitch, vx, vz, pitch_rate = x2
        return np.array([z, 0.0, pitch, vx, 0.0, vz, 0.0, -pitch_rate, 0.0])

    def start_from(self, x2: np.ndarray) -> np.ndarray:
        """The lifted planar state ``x2`` (:meth:`lift`); its closed loops become every later Newton start."""
        start_q = self.planar.sim.initial_state()[0]  # the geometric start, its cranks at the section's angle
        self.planar.guess = self.planar.configuration(np.asarray(x2, dtype=float), start_q)[0]
        return self.lift(x2)

    def configuration(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, u) of state ``x``: the loops closed at the section's crank angle, the hip at x = y = 0, yaw 0."""
        z, roll, pitch, vx, vy, vz, wx, wy, wz = (float(a) for a in x)
        q2, v2 = self.planar.configuration(np.array([z, pitch, vx, vz, -wy]), self.planar.guess)
        q = planar_to_spatial(q2)
        q[3:7] = pin.Quaternion(pin.utils.rpyToMatrix(roll, -pitch, 0.0)).coeffs()
        u = planar_velocity_to_spatial(v2)
        u[:6] = (vx, vy, vz, wx, wy, wz)
        return q, u

    def state(self, q: np.ndarray, u: np.ndarray) -> np.ndarray:
        """The section state of (q, u) in the hip's heading frame (yaw, x and y removed)."""
        rotation = pin.Quaternion(q[3:7]).normalized().toRotationMatrix()
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        heading = pin.utils.rpyToMatrix(0.0, 0.0, yaw)
        roll, p, _ = pin.rpy.matrixToRpy(heading.T @ rotation)
        v, w = heading.T @ u[:3], heading.T @ u[3:6]
        return np.array([q[2], roll, -p, *v, *w])

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """F(x): the state half a crank turn later, mirrored.

        Raises:
            DivergedError: the walk failed within the step (fell, tipped, slipped, broke).

        """
        self.evaluations += 1
        q, u = self.configuration(np.asarray(x, dtype=float))
        result = self.engine.run(self.period, q, u, stop_on_verdict=False)
        failed = result.verdict.outcome in FAILURES and result.verdict.outcome != "undecided"
        if failed or result.u_end is None:
            raise DivergedError(f"the 3-D step failed: {result.verdict.summary()}")
        out = self.state(result.q[-1], result.u_end)
        out[list(MIRRORED)] *= -1.0
        return out


@dataclass
class GaitStability3D:
    """The 3-D gait's fixed point and multipliers.

    Attributes:
        fixed_point: the :class:`~pasibot_pin.studies.methods.poincare.FixedPoint` (9 states).
        planar_multipliers: the planar gait's multipliers, for comparison.
        evaluations: 3-D step-map evaluations [-].
        cpu_s: CPU time, the planar shooting included [s].
        planar_x: the planar gait's fixed point (z, pitch, vx, vz, pitch rate), its start.

    """

    fixed_point: FixedPoint
    planar_multipliers: np.ndarray
    evaluations: int
    cpu_s: float
    planar_x: np.ndarray

    labels = LABELS_3D

    @property
    def multipliers(self) -> np.ndarray:
        """The 3-D gait's multipliers, largest modulus first."""
        return self.fixed_point.multipliers

    @property
    def stable(self) -> bool:
        """True when every multiplier has modulus < 1."""
        return bool(self.fixed_point.stable)

    def summary(self) -> str:
        """One line: the verdict and the largest moduli."""
        mods = ", ".join(f"{abs(z):.3g}" for z in self.multipliers[:4])
        return (
            f"3-D gait {'stable' if self.stable else 'unstable'}: |multipliers| {mods} (9 states: height, roll, "
            f"pitch and the hip's six rates; Newton shooting with forward differences, {self.evaluations} 3-D "
            f"steps simulated in {self.cpu_s:.1f} s of CPU)"
        )


def gait_stability_3d(design, settings: StabilitySettings | None = None, robot=None) -> GaitStability3D:
    """Shoot the design's 3-D gait from its planar one and linearise it (see the module docstring).

    Raises:
        ParameterError: a variant with ankle springs.
        NoFixedPointError: no periodic gait (the planar one, or the 3-D one near it).

    """
    start = time.process_time()
    settings = StabilitySettings(basin_kicks=()) if settings is None else settings
    robot = design_robot(design, 2, visuals=False) if robot is None else robot
    planar = gait_stability(design, None, settings, robot)
    floor = floor_settings(design, WalkSettings(steps=settings.warmup_steps), robot)
    gait_map = GaitMap3D(robot, floor, design.footprint())
    x0 = gait_map.start_from(planar.fixed_point.x)
    scale = np.array([max(abs(x0[0]), 0.01), 0.01, 0.01, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1])
    point = find_fixed_point(gait_map, x0, tol=settings.tol, max_iter=settings.max_iter, fd_step=settings.fd_step,
                             scale=scale, scheme="forward", relax_steps=settings.relax_steps)  # fmt: skip
    cpu = time.process_time() - start
    return GaitStability3D(point, planar.multipliers, gait_map.evaluations, cpu, planar.fixed_point.x)
