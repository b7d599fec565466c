"""Accepted hydraulic parameters at the corners of their ranges: each prediction is either right
(against a run with a 20x finer step) or refused with a ValueError; never finite garbage (a spool
beyond [-1, 1], pressures of 1e12 bar) returned as a result."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import cranepredict as cp
from cranepredict.types import PRESSURE_MAX


def _hydraulics(crane, **kw):
    out = crane
    for name in ("lift_cylinder", "tilt_cylinder"):
        cyl = getattr(out, name)
        out = dataclasses.replace(out, **{name: dataclasses.replace(
            cyl, hydraulics=dataclasses.replace(cyl.hydraulics, **kw))})
    return out


def _scaled_hoses(crane, factor):
    h = crane.lift_cylinder.hydraulics
    out = _hydraulics(crane, hose_volume_a=h.hose_volume_a * factor,
                      hose_volume_b=h.hose_volume_b * factor)
    return out


SC = cp.scenarios.get("lever-open")
CLOSED = cp.Inputs(lift=cp.Valve(0.0), tilt=cp.Valve(0.0))
SLAM = cp.Inputs(lift=cp.ValveSeries(t=[0, 0.1, 0.12, 0.3, 0.32, 1.0], u=[0, 0, 1, 1, -1, -1]),
                 tilt=cp.ValveSeries(t=[0, 0.2, 0.22, 1.0], u=[0, 0, -1, -1]))

CORNERS = {
    "tau at 3e-4 s": (lambda c: _hydraulics(c, spool_time_constant=3e-4), SC.inputs),
    "tau at 1e-6 s": (lambda c: _hydraulics(c, spool_time_constant=1e-6), SC.inputs),
    "tau 0, lever slammed": (lambda c: _hydraulics(c, spool_time_constant=0.0), SLAM),
    "leakage at its maximum, valves closed": (lambda c: _hydraulics(c, leakage=1e-6), CLOSED),
    "leakage 1e-8, valves closed": (lambda c: _hydraulics(c, leakage=1e-8), CLOSED),
    "leakage 1e-9, lever open": (lambda c: _hydraulics(c, leakage=1e-9), SC.inputs),
    "hoses 1/100": (lambda c: _scaled_hoses(c, 0.01), SLAM),
    "oil 100x stiffer": (lambda c: _hydraulics(c, oil_bulk_modulus=c.lift_cylinder.hydraulics
                                               .oil_bulk_modulus * 100), SLAM),
    "relief at the supply": (lambda c: _hydraulics(c, relief_pressure=c.lift_cylinder.hydraulics
                                                   .supply_pressure), SLAM),
}


@pytest.mark.parametrize("corner", list(CORNERS))
def test_corner_is_right_or_refused(corner):
    make, inputs = CORNERS[corner]
    crane = make(SC.crane)
    state = cp.state_at_rest(crane, SC.initial.lift_stroke, SC.initial.tilt_stroke)
    horizon = 1.0
    try:
        traj = cp.predict(crane, state, inputs, horizon)
    except ValueError as e:
        assert "diverged" in str(e) or "MAX_STEPS" in str(e), str(e)
        return
    assert np.all(np.abs(traj.spool) <= 1.0)
    assert np.all(np.abs(traj.p_a) <= PRESSURE_MAX) and np.all(np.abs(traj.p_b) <= PRESSURE_MAX)
    try:
        fine = cp.predict(crane, state, inputs, horizon, dt=cp.DEFAULT_DT / 20, method="rk4")
    except ValueError as e:
        # RK4's substeps for this corner are over MAX_STEPS: the converged run is the default
        # method at a tolerance 10 times tighter (it converges to RK4's solution:
        # tests/test_rosw.py)
        assert "MAX_STEPS" in str(e), str(e)
        fine = cp.predict(crane, state, inputs, horizon, dt=cp.DEFAULT_DT / 20,
                          tolerance=cp.Tolerance(tip=5e-6, pressure=1e3))
    np.testing.assert_allclose(traj.tip, fine.tip[::20], rtol=0, atol=1e-3)
    np.testing.assert_allclose(traj.p_a, fine.p_a[::20], rtol=0, atol=0.5e5)


def test_state_at_rest_refuses_a_load_above_the_relief():
    """2,000 kg needs 413 bar in the lift cylinder, above its 150 bar relief: refused, naming the
    load, the pressure and the relief (the pose could not be held: the tip fell 2.5 m in 1 s)."""
    crane = cp.Crane.patu655().with_load(2000.0)
    with pytest.raises(ValueError, match=r"load_mass = 2000 kg needs lift p_a = \d+\.\d bar, above "
                                         r"lift_cylinder\.hydraulics\.relief_pressure = \d+ bar"):
        cp.state_at_rest(crane, 0.116, 0.20)
