"""Short ``repr`` of the result records: one line with shapes and key figures, no array dumps.

A study's result holds arrays of thousands of samples, robots and Pinocchio objects; the
dataclass ``repr`` prints them all (and object addresses). :func:`short_repr`, set as a result
class's ``__repr__``, prints each field as: numbers (4 significant digits), short strings, array
shapes with their range, the length of lists and dicts (and their keys), the robot's variant,
nested records by their own short ``repr`` when it is short, else by their class name.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping

import numpy as np

FIELD_CHARS = 80
"""Longest text of one field; longer ones are cut to their class name."""


def _number(value: float) -> str:
    return f"{value:.4g}" if math.isfinite(value) else str(value)


def _scalar(value) -> str | None:
    """The text of a number, bool, None or short string; ``None`` for anything else."""
    if value is None or isinstance(value, (bool, np.bool_)):
        return repr(bool(value)) if value is not None else "None"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return _number(float(value))
    if isinstance(value, str):
        return repr(value) if len(value) <= 40 else repr(value[:37] + "...")
    return None


def _array(value: np.ndarray) -> str:
    shape = "x".join(str(n) for n in value.shape) or "scalar"
    if value.size == 0:
        return f"array({shape})"
    if value.size <= 4 and value.dtype.kind in "fiub":
        return "[" + ", ".join(_scalar(v) for v in value.ravel()) + "]"
    if value.dtype.kind in "fiu" and np.all(np.isfinite(value)):
        return f"array({shape}, {_number(float(np.min(value)))}..{_number(float(np.max(value)))})"
    return f"array({shape}, {value.dtype})"


def short(value) -> str:
    """One field's short text (see the module's notes)."""
    text = _scalar(value)
    if text is not None:
        return text
    if isinstance(value, np.ndarray):
        return _array(value)
    if hasattr(value, "variant") and hasattr(value, "legs") and hasattr(value, "model"):
        return f"<robot {value.variant}, {value.legs} leg(s)>"
    if isinstance(value, Mapping):
        keys = [str(k) for k in value]
        texts = [_scalar(v) for v in value.values()]
        if len(keys) <= 4 and all(t is not None for t in texts):
            text = "{" + ", ".join(f"{k}: {t}" for k, t in zip(keys, texts)) + "}"
        else:
            text = f"dict[{len(keys)}: {', '.join(keys[:4])}{', ...' if len(keys) > 4 else ''}]"
        return text if len(text) <= FIELD_CHARS else f"dict[{len(keys)}]"
    if isinstance(value, (list, tuple)):
        texts = [_scalar(v) for v in value]
        if len(value) <= 4 and all(t is not None for t in texts):
            left, right = ("[", "]") if isinstance(value, list) else ("(", ")")
            text = left + ", ".join(texts) + right
            if len(text) <= FIELD_CHARS:
                return text
        kind = type(value[0]).__name__ if len(value) else ""
        return f"{type(value).__name__}[{len(value)}{' ' + kind if kind else ''}]"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        text = repr(value)
        return text if len(text) <= FIELD_CHARS and "\n" not in text else f"{type(value).__name__}(...)"
    return f"<{type(value).__name__}>"


def short_repr(self) -> str:
    """``ClassName(field=short, ...)`` of a dataclass instance: use as ``__repr__ = short_repr``."""
    fields = ", ".join(f"{f.name}={short(getattr(self, f.name))}" for f in dataclasses.fields(self) if f.repr)
    return f"{type(self).__name__}({fields})"
