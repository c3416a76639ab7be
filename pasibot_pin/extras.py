"""The optional dependencies (pip extras) and the one-line error when one is missing.

``pip install pasibot-pin`` runs every command but ``sweep`` and ``optimize``; those need the
``[sweep]`` extra (pyarrow tables, SciPy's Latin hypercube, Optuna, Dask), and MuJoCo comes
with ``[mujoco]``. A command checks its extra before any work, so a missing one leaves no file.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Iterable

from pasibot_pin.errors import MissingExtraError, ParameterError

EXTRAS: dict[str, tuple[str, ...]] = {
    "sweep": ("pyarrow", "scipy", "optuna", "distributed", "tqdm"),
    "mujoco": ("mujoco",),
}
"""Each extra -> the modules it brings (pyproject's ``[project.optional-dependencies]``)."""


def missing(modules: Iterable[str]) -> list[str]:
    """The modules of ``modules`` that cannot be imported here (looked up, not imported)."""
    return [m for m in modules if importlib.util.find_spec(m) is None]


def require(extra: str, modules: Iterable[str], what: str) -> None:
    """Raise :class:`~pasibot_pin.errors.MissingExtraError` if any of ``modules`` is not installed.

    Args:
        extra: the pip extra that brings them (a key of :data:`EXTRAS`).
        modules: the importable names needed.
        what: who needs them, for the message (``pasibot sweep``).

    """
    if extra not in EXTRAS:
        raise ParameterError(f"unknown extra {extra!r}; known: {', '.join(EXTRAS)}")
    absent = missing(modules)
    if absent:
        raise MissingExtraError(
            f"{what} needs the [{extra}] extra ({', '.join(absent)} not installed): pip install 'pasibot-pin[{extra}]'"
        )
