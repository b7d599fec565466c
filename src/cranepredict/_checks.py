"""Input checks shared by the Python layer: one place that says what a number is, and the limits
of a call (pure Python: the twin and the types import it without the compiled C core)."""

from __future__ import annotations

import math
import sys

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = ["number", "tomllib", "PRESSURE_MAX", "MAX_STEPS", "MAX_SAMPLES", "step_count",
           "kept_samples"]

#: Pa (1000 bar): the largest pressure accepted; the C core's CRANE_PRESSURE_MAX.
PRESSURE_MAX = 1e8

#: The most RK4 steps one prediction may take (horizon / dt, rounded up): the C core's
#: CRANE_MAX_STEPS (2^20; crane.h says why), written here so that the twin imports without the
#: core (tests/test_bounds.py checks the two agree). The C core runs them in about 0.2 s on a
#: 2020s desktop core (0.15 us per step); the twin, about 100x slower, can be stopped with Ctrl-C.
#: Above it, a call is refused before anything is allocated or run.
MAX_STEPS = 1_048_576

#: The most output samples one call may return (predict: steps + 1; predict_many: futures x kept
#: samples per future): the C core's CRANE_MAX_SAMPLES (2^23). A sample takes
#: sizeof(crane_sample) = 288 bytes in the C core's double output (tests/test_bounds.py checks
#: it), so this bounds a call's output at about 2.4 GB.
MAX_SAMPLES = 8_388_608


def number(value: object, name: str) -> float:
    """``value`` as a finite float; TypeError for a non-number (bools included), ValueError for
    NaN, infinity or an int too large for a float, each naming the field."""
    if type(value) is float and math.isfinite(value):   # the common case, first
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise TypeError(f"{name} must be a number, got {type(value).__name__}")
    try:
        x = float(value)
    except OverflowError:
        raise ValueError(f"{name} must be a finite number, got an int of {int(value).bit_length()} "
                         "bits (too large for a float)") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x}")
    return x


def step_count(horizon: float, dt: float) -> int:
    """The number of RK4 steps of a prediction, ``ceil(horizon/dt - 1e-9)`` (at least 1), as the C
    core counts them (docs/model.md, "Integration and samples"); ValueError naming horizon, dt and
    MAX_STEPS when it is above the limit. horizon and dt are finite, > 0, dt <= horizon."""
    q = horizon / dt - 1e-9
    if not q <= MAX_STEPS:  # also catches horizon/dt overflowing to inf
        steps = f"{math.ceil(q):,}" if q < 1e18 else f"{q:.3g}"
        raise ValueError(f"horizon / dt must be at most {MAX_STEPS:,} steps (cranepredict.MAX_STEPS), "
                         f"got horizon {horizon:g} s / dt {dt:g} s = {steps} steps: shorten the "
                         "horizon or take a larger dt")
    return max(1, math.ceil(q))


def kept_samples(n_steps: int, sample_every: int) -> int:
    """Samples kept of a prediction of n_steps steps: t = 0, after every sample_every-th step and
    after the last step (the C core's crane_sample_count_every)."""
    return n_steps // sample_every + (n_steps % sample_every != 0) + 1
