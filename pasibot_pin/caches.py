"""Values computed once per object (a Pinocchio model, a frozen geometry): the one cache helper.

Several layers keep what they derive from a model (its planar kinematics, constraint systems,
assembly plans, Newton-Euler layouts ...) so that a sweep derives it once. Every such cache is a
:class:`PerObjectCache`: keyed by the owner's identity plus a key of its own, bounded to
:data:`CACHE_SIZE` entries (the oldest goes first), and each entry holds its owner, so the owner's
``id`` cannot be reused by another object while the entry lives (a dead model's id given to a new
model would otherwise return the dead model's values).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

from pasibot_pin.errors import ParameterError

__all__ = ["CACHE_SIZE", "PerObjectCache"]

V = TypeVar("V")

CACHE_SIZE: int = 64
"""Entries kept by every per-object cache (the oldest is dropped first): a sweep's models, stances
and row sets fit many times over."""


class PerObjectCache(Generic[V]):
    """A bounded map (owner, key) -> value; the entry keeps its owner alive (no id reuse).

    Args:
        size: how many entries are kept (the oldest is dropped first).

    """

    def __init__(self, size: int = CACHE_SIZE) -> None:
        if size < 1:
            raise ParameterError(f"parameter 'size' must be >= 1, got {size!r}")
        self.size = size
        self._entries: dict[tuple[int, Hashable], tuple[object, V]] = {}

    def get(
        self,
        owner: object,
        build: Callable[[], V],
        key: Hashable = None,
        fresh: Callable[[V], bool] | None = None,
    ) -> V:
        """The value of ``owner`` and ``key``, made by ``build()`` the first time (or when stale).

        Args:
            owner: the object the value is derived from (compared by identity).
            build: makes the value (called only on a miss).
            key: what else the value depends on (hashable; ``None`` when only the owner).
            fresh: a check that a cached value still holds (e.g. the model was not changed in
                place since); a value failing it is built again.

        """
        full = (id(owner), key)
        entry = self._entries.get(full)
        if entry is not None and entry[0] is owner and (fresh is None or fresh(entry[1])):
            return entry[1]
        value = build()
        if full not in self._entries and len(self._entries) >= self.size:
            self._entries.pop(next(iter(self._entries)))
        self._entries[full] = (owner, value)
        return value

    def clear(self) -> None:
        """Drop every entry."""
        self._entries.clear()

    def __len__(self) -> int:
        return len(self._entries)
