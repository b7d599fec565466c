"""Input checks shared by the Python layer: one place that says what a number is."""

from __future__ import annotations

import math
import sys

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = ["number", "tomllib"]


def number(value: object, name: str) -> float:
    """``value`` as a finite float; TypeError for a non-number (bools included), ValueError for
    NaN or infinity, each naming the field."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise TypeError(f"{name} must be a number, got {type(value).__name__}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x}")
    return x
