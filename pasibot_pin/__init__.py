"""pasibot_pin: the PASIBOT closed-loop biped in Pinocchio.

>>> import pasibot_pin as pp
>>> robot = pp.load()            # ankle-spring biped, L = 0.05 m
>>> robot.q0                     # satisfies every loop
"""

from pasibot_pin.model.description import Loop, loop_table, render_urdf
from pasibot_pin.model.params import VARIANTS, Geometry, MassModel, human_description_mass_model, percentage_mass_model
from pasibot_pin.model.paths import PACKAGE_DIRS, URDF_PATH, XACRO_PATH, urdf_path
from pasibot_pin.model.robot import PasibotRobot, load

__version__ = "0.1.0"

__all__ = [
    "PACKAGE_DIRS",
    "URDF_PATH",
    "VARIANTS",
    "XACRO_PATH",
    "Geometry",
    "Loop",
    "MassModel",
    "PasibotRobot",
    "human_description_mass_model",
    "load",
    "loop_table",
    "percentage_mass_model",
    "render_urdf",
    "urdf_path",
]
