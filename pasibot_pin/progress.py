"""Progress bars on long work (sweeps, optimisations, the walking map), in one place.

:func:`progress_bar` gives tqdm's bar when tqdm is installed (the ``[sweep]`` extra), else a
plain one that prints ``done/total UNIT`` on stderr every tenth of the work.
"""

from __future__ import annotations

import sys


class PlainProgress:
    """The progress bar without tqdm: one ``done/total UNIT`` line on stderr per tenth of the work."""

    def __init__(self, total: int, done: int, enabled: bool, unit: str = "design"):
        self.total, self.done, self.enabled, self.unit = total, done, enabled, unit
        self.shown = -1

    def update(self, n: int = 1) -> None:
        """``n`` more items done."""
        self.done += n
        tenth = 10 * self.done // max(self.total, 1)
        if self.enabled and tenth != self.shown:
            self.shown = tenth
            print(f"{self.done}/{self.total} {self.unit}s", file=sys.stderr, flush=True)

    def close(self) -> None:
        """Nothing to release."""


def progress_bar(total: int, done: int, enabled: bool, unit: str = "design"):
    """A progress bar over ``total`` items, ``done`` already: tqdm's if installed, else :class:`PlainProgress`."""
    try:
        from tqdm.auto import tqdm  # deferred: optional extra (tqdm)
    except ImportError:
        return PlainProgress(total, done, enabled, unit)
    return tqdm(total=total, initial=done, unit=unit, disable=not enabled, smoothing=0.1, dynamic_ncols=True)
