"""How close a walk came to each rule's limit (:class:`Margin`), as the walking verdict reports it.

Units: as each rule's (``Margin.unit``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

NEAR: float = 0.1
"""A rule whose value came within this share of its limit is near its boundary [-]."""


@dataclass(frozen=True)
class Margin:
    """How close a walk came to one rule's limit.

    Attributes:
        rule: the rule's name (``hip_pitch``, ``slide``, ``advance_low``, ``advance_high``, ``flight``,
            ``landing``, ``swing``, ``foot_roll``, ``hip_roll``, ``steps``).
        value: the value the walk reached (its worst) [unit].
        limit: the rule's limit [unit].
        unit: the unit of both.
        sense: ``max`` (the value must stay at most the limit) or ``min`` (at least it).
        decided: this rule decided the outcome.
        scale: what "near" is measured against (NaN: the limit itself; the advance band: its tolerance).

    """

    rule: str
    value: float
    limit: float
    unit: str
    sense: str
    decided: bool = False
    scale: float = math.nan

    @property
    def margin(self) -> float:
        """How far inside the limit the value stayed (negative: past it) [unit]."""
        return self.limit - self.value if self.sense == "max" else self.value - self.limit

    @property
    def near(self) -> bool:
        """The value came within :data:`NEAR` of the limit, either side."""
        if self.unit == "steps":  # a count: reaching the steps asked is the pass, not a close call
            return False
        scale = abs(self.limit) if math.isnan(self.scale) else self.scale
        return math.isfinite(self.margin) and abs(self.margin) <= NEAR * max(scale, 1e-12)

    def text(self) -> str:
        """``rule value <= limit unit`` (``>=`` for a least value; ``>`` or ``<`` once past the limit).

        ``rule not reached (limit ...)`` when the walk ended before the rule could be measured.
        """
        flag = " (decided)" if self.decided else " (near)" if self.near else ""
        if math.isnan(self.value):
            return f"{self.rule} not reached (limit {self.limit:.3g} {self.unit}){flag}"
        within = self.margin >= 0
        mark = ("<=" if within else ">") if self.sense == "max" else (">=" if within else "<")
        return f"{self.rule} {self.value:.3g} {mark} {self.limit:.3g} {self.unit}{flag}"
