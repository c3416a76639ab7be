"""The package's errors: one small hierarchy, so code decides by an error's type, never by its text.

Every error is a :class:`PasibotError`, itself a ``ValueError`` (code written against
``ValueError`` keeps working). Two families:

* bad input, found before any work starts: :class:`ParameterError` (a parameter or flag out of
  its range, named in the message), :class:`DesignError` (a design whose linkage cannot be built
  or assembled), :class:`MissingExtraError` (an optional dependency is not installed);
* a computation that breaks on valid input, :class:`SimulationError` and its kinds:
  :class:`ClosureError` (a loop cannot close), :class:`SingularPoseError` (the constraint
  Jacobian lost rank), :class:`ContactSolveError` (the contact problem has no solution the
  solver finds), :class:`DivergedError` (the state left every physical bound),
  :class:`NoRestError` (a robot that cannot stand still where it was asked to start) and
  :class:`NoFixedPointError` (a search for a periodic gait, a fixed point of a step map, failed).

The command line prints any :class:`PasibotError` as one line and exits with code 2; a
simulation turns a :class:`SimulationError` into a named outcome (``diverged``) with the time it
broke.
"""

from __future__ import annotations

__all__ = [
    "AssemblyError",
    "ClosureError",
    "ContactSolveError",
    "DesignError",
    "DivergedError",
    "MissingExtraError",
    "NoFixedPointError",
    "NoRestError",
    "ParameterError",
    "PasibotError",
    "SimulationError",
    "SingularPoseError",
]


class PasibotError(ValueError):
    """Base of every error the package raises on purpose."""


class ParameterError(PasibotError):
    """A parameter (argument, flag or design-file entry) is missing, of the wrong type or out of range."""


class DesignError(PasibotError):
    """A design that cannot be built: its linkage does not assemble, or its parts contradict each other."""


class AssemblyError(DesignError):
    """A linkage that cannot assemble at some crank angle.

    ``fields``: the design fields (K, r1 .. r13, in L) a user can change to make the failing loop close.
    """

    def __init__(self, message: str, fields: tuple[str, ...] = ()):
        super().__init__(message)
        self.fields = fields


class InterferenceError(ParameterError):
    """A design whose parts meet before any motion: soles that intersect, or a leg in the other's way."""


class MissingExtraError(PasibotError):
    """A command or function needs an optional dependency (a pip extra) that is not installed."""


class SimulationError(PasibotError):
    """A computation on valid input broke numerically (the base of the kinds below)."""


class ClosureError(SimulationError):
    """Newton could not close a loop: the linkage cannot assemble at that configuration or time."""


class SingularPoseError(SimulationError):
    """A linear solve met a rank-deficient matrix: the constraint Jacobian (or the mass matrix) lost rank."""


class ContactSolveError(SimulationError):
    """The contact problem (a QP) found no solution."""


class DivergedError(SimulationError):
    """The state became non-finite or faster than any physical motion."""


class NoRestError(SimulationError):
    """The robot finds no state of rest where it was asked to start (it falls or keeps sliding)."""


class NoFixedPointError(SimulationError):
    """Newton found no fixed point of a step map (no periodic gait) within its iteration and evaluation budget."""
