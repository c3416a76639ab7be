"""The robot on a floor: unilateral feet with Coulomb friction, time-stepped (Moreau, Anitescu).

One step algorithm with its seams, each in one module:

- :mod:`~pasibot_pin.dynamics.floor.ground`: the plane a foot stands on (flat, a slope): a point's
  gap, normal and tangents, and the friction.
- :mod:`~pasibot_pin.dynamics.floor.settings`: :class:`FloorSettings` (crank speed and ramp, springs,
  friction, time step, motors, slope) and the cranks' schedule.
- :mod:`~pasibot_pin.dynamics.floor.qp`: the contact QP of one step (the exact active set, a
  reduced solve on the free motions, proxsuite).
- :mod:`~pasibot_pin.dynamics.floor.engine`: :class:`FloorSimulator`, the planar biped (hip x, z,
  pitch): its step, start and run. The *shape track*
  (:mod:`~pasibot_pin.dynamics.floor.shape_track`, in 3-D coordinates
  :mod:`~pasibot_pin.dynamics.floor.shape_track3d`) is the legs' shape known ahead; the *tracked step*
  (:mod:`~pasibot_pin.dynamics.floor.tracked_step`) is the step that follows it, on the hip's freedoms in
  Python floats. "Track" means nothing else in the package (the viewer draws :class:`ForceArrows`).
- :mod:`~pasibot_pin.dynamics.floor.run`: what a run records (:class:`FloorResult`, the contact
  modes, the judge's samples).
- :mod:`~pasibot_pin.dynamics.floor.engine3d`: :class:`Floor3D`, the same step with a free hip in
  3-D (roll, yaw, sideways) and the soles' footprint.

The walk is judged by :mod:`pasibot_pin.dynamics.verdict`. This module names the package's public
classes; the rest is imported from the module that defines it.
"""

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.dynamics.floor.result3d import Floor3DResult
from pasibot_pin.dynamics.floor.run import FloorResult, StartState
from pasibot_pin.dynamics.floor.settings import FloorSettings

__all__ = ["Floor3D", "Floor3DResult", "FloorResult", "FloorSettings", "FloorSimulator", "Ground", "StartState"]
