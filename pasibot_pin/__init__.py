"""pasibot_pin: the PASIBOT closed-loop biped in Pinocchio.

>>> import pasibot_pin as pp
>>> robot = pp.load()            # ankle-spring biped, L = 0.05 m
>>> robot.q0                     # satisfies every loop
"""

import os as _os
import sys as _sys

if _sys.argv and (_sys.argv[0] == "-m" or _os.path.basename(_sys.argv[0]) == "pasibot"):
    # Our commands (``pasibot``, ``python -m pasibot_pin[.module]``): one OpenBLAS thread per process unless the
    # caller chose otherwise. Every matrix here is small; the BLAS threads only spin, on CPU the pool's other
    # worker needs (``pasibot analyze``: 6 % of its CPU). Set here, before numpy is first imported: this package
    # is imported before ``pasibot_pin.__main__`` runs, and the pool's forked workers keep it.
    _os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def _interrupted_at_start(signum, frame):  # noqa: ARG001 (a signal handler's signature)
    """Ctrl-C while ``pasibot`` still imports: no work started, no file or child yet; exit 130 quietly."""
    _os.write(2, b"pasibot: interrupted\n")
    _os._exit(130)


_orig = getattr(_sys, "orig_argv", [])
if _os.path.basename(_sys.argv[0] if _sys.argv else "") == "pasibot" or (
    "-m" in _orig and _orig[_orig.index("-m") + 1 :][:1] == ["pasibot_pin"]
):
    # The command line, until pasibot_pin.__main__.main installs its own handlers: a Ctrl-C during the imports
    # (a second or so) would otherwise print a KeyboardInterrupt traceback.
    import signal as _signal

    _signal.signal(_signal.SIGINT, _interrupted_at_start)

from pasibot_pin.model.description import Loop, loop_table, render_urdf  # noqa: E402
from pasibot_pin.model.params import (  # noqa: E402
    VARIANTS,
    Geometry,
    MassModel,
    human_description_mass_model,
    percentage_mass_model,
)
from pasibot_pin.model.paths import PACKAGE_DIRS, URDF_PATH, XACRO_PATH, urdf_path  # noqa: E402
from pasibot_pin.model.robot import PasibotRobot, load  # noqa: E402

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
