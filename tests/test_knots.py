"""Steps are cut at the knots of sampled drives (docs/model.md, "Integration and samples").

A linearly interpolated drive has a kink at each sample; RK4 stepping across a kink is only first
order there, so a series whose knots fall between the steps would make the error fall as dt^2
instead of dt^4. Cutting the step at the knot restores the fourth order: measured here as the
observed order of the tip error against a converged run, on knots placed off every step grid.
"""
import numpy as np
import pytest

import cranepredict as cp

HORIZON = 1.2
# knots at times no step grid of the test hits (dt = 20, 10, 5 ms and the reference's 0.05 ms)
KNOTS = np.array([0.0, 0.21337, 0.52711, 0.80093, HORIZON])


def _case(kind):
    crane = cp.Crane.patu655().with_load(200.0)
    initial = cp.State(lift_stroke=0.15, tilt_stroke=0.30)
    if kind == "pressure":
        # the lift bore-side pressure ramps up and back down: four kinks, the lift always moving
        lift = cp.PressureSeries(t=KNOTS, p_a=[70e5, 70e5, 120e5, 80e5, 80e5], p_b=np.zeros(5))
        return crane, initial, cp.Inputs(lift=lift, tilt=cp.Hold())
    initial = cp.state_at_rest(crane, 0.15, 0.30)
    lift = cp.ValveSeries(t=KNOTS, u=[0.2, 0.2, 0.9, 0.5, 0.5])
    return crane, initial, cp.Inputs(lift=lift, tilt=cp.Valve(0.0))


def _errors(kind, backend, dts):
    crane, initial, inputs = _case(kind)
    ref = cp.predict(crane, initial, inputs, HORIZON, dt=5e-5, backend="c", method="rk4")
    errs = []
    for dt in dts:
        tr = cp.predict(crane, initial, inputs, HORIZON, dt=dt, backend=backend, method="rk4")
        k = np.rint(tr.t / 5e-5).astype(int)
        errs.append(float(np.max(np.linalg.norm(tr.tip - ref.tip[k], axis=1))))
    return np.array(errs)


def test_pressure_series_knots_keep_rk4_fourth_order():
    errs = _errors("pressure", "c", (0.02, 0.01, 0.005))
    order = np.log2(errs[:-1] / errs[1:])
    print("tip error [m] at dt = 20, 10, 5 ms:", errs, "observed order:", order)
    # without the cut the kinks hold the order near 2 (a kink costs O(dt^2) per step it falls in)
    assert np.all(order > 3.3), order


def test_twin_cuts_at_the_same_knots_as_the_c_core():
    for kind in ("pressure", "valve"):
        crane, initial, inputs = _case(kind)
        c = cp.predict(crane, initial, inputs, HORIZON, dt=0.02, backend="c", method="rk4")
        py = cp.predict(crane, initial, inputs, HORIZON, dt=0.02, backend="python", method="rk4")
        assert np.max(np.abs(c.tip - py.tip)) < 1e-9
        assert np.max(np.abs(c.p_a - py.p_a)) < 1e-3


def _series(knots_inside):
    """A constant lift pressure sampled so that knots_inside samples lie inside (0, 2) s."""
    n = knots_inside + 2
    lift = cp.PressureSeries(t=np.linspace(0.0, 2.0, n), p_a=np.full(n, 70e5), p_b=np.zeros(n))
    return cp.Inputs(lift=lift, tilt=cp.Hold())


@pytest.mark.parametrize("backend", cp.BACKENDS)
def test_every_knot_counts_against_the_step_limit(backend):
    """1,000 steps of 2 ms plus the knots inside the horizon must stay within MAX_STEPS (each knot
    may cut a step once more): one knot too many is refused before anything runs, by both
    implementations; exactly at the limit the C core runs it."""
    crane = cp.Crane.patu655()
    initial = cp.State(lift_stroke=0.15, tilt_stroke=0.30)
    room = cp.MAX_STEPS - 1000
    with pytest.raises(ValueError, match="1,048,576|1048576"):
        cp.predict(crane, initial, _series(room + 1), 2.0, dt=2e-3, backend=backend, method="rk4")
    if backend == "c":
        tr = cp.predict(crane, initial, _series(room), 2.0, dt=2e-3, method="rk4")
        assert tr.t[-1] == 2.0 and tr.t.size == 1001


def test_a_60s_lever_log_at_1khz_runs_as_the_steps_on_its_knots():
    """A recorded lever at 1 kHz over 60 s (60,000 knots): the default step is cut at every knot
    and each cut costs one substep more, not a step's worth, so the call stays within MAX_STEPS and
    runs. Cut at the knots, it integrates the same pieces as a 1-ms step that lands on every knot
    (kept every 5th sample): the two agree to rounding."""
    crane = cp.Crane.patu655().with_load(200.0)
    initial = cp.state_at_rest(crane, lift_stroke=0.116, tilt_stroke=0.20)
    t = np.arange(60_001) * 1e-3
    lever = cp.ValveSeries(t=t, u=0.8 * np.sin(0.5 * t))
    inputs = cp.Inputs(lift=lever, tilt=cp.Valve(0.0))
    cut = cp.predict(crane, initial, inputs, 60.0, method="rk4")    # the default step
    on_knots = cp.predict(crane, initial, inputs, 60.0, dt=1e-3, method="rk4",
                          sample_every=round(cp.DEFAULT_DT / 1e-3))
    assert cut.t.size == on_knots.t.size == round(60.0 / cp.DEFAULT_DT) + 1
    np.testing.assert_array_equal(cut.t, on_knots.t)
    assert np.max(np.abs(cut.tip - on_knots.tip)) < 1e-9
    assert np.max(np.abs(cut.p_a - on_knots.p_a)) < 1e-2              # Pa
    # the lever swings the boom through its range onto the lower stop and back
    assert cut.stop[:, 0].min() == -1 and np.ptp(cut.strokes[:, 0]) > 0.15
