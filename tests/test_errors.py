"""Every error names the input at fault (issue 8, finding 6): huge ints, tables where pairs are
expected, wrong types in directly built dataclasses, files that are not UTF-8, batches that are not
sequences, absurd stroke rates."""

from __future__ import annotations

import pytest

import cranepredict as cp

STATE = dict(lift_stroke=0.1, tilt_stroke=0.3)
INPUTS = cp.Inputs(lift=cp.Pressure(100e5, 0), tilt=cp.Hold())


@pytest.mark.parametrize("rate", [1e300, -1e300, 1e10, 10.5])
@pytest.mark.parametrize("name", ["lift_stroke_rate", "tilt_stroke_rate"])
def test_a_stroke_rate_of_1e300_blames_the_stroke_rate(name, rate):
    with pytest.raises(ValueError, match=rf"State.{name} must be in \[-10, 10\] m/s "
                                         r"\(cranepredict.STROKE_RATE_MAX\)"):
        cp.State(**STATE, **{name: rate})


def test_stroke_rates_up_to_the_limit_are_accepted(crane):
    state = cp.State(**STATE, lift_stroke_rate=cp.STROKE_RATE_MAX)
    c = cp.predict(crane, state, INPUTS, 0.05)
    py = cp.predict(crane, state, INPUTS, 0.05, backend="python")
    assert abs(c.tip - py.tip).max() < 1e-9
