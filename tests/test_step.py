"""crane_step: one control period, state in, state out; chained periods continue one prediction."""

import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core
from cranepredict._core import ffi, lib

PERIOD = 0.01


def _c_state(state):
    s = ffi.new("crane_state *")
    _core._state(s, state)
    return s


def _c_inputs(inputs, method="auto"):
    inp, keep = ffi.new("crane_inputs *"), []
    _core._inputs(inp, inputs, keep)
    _core.solver(inp, method, None)
    return inp, keep


def _chain(sc, n, dt, period=PERIOD, method="auto"):
    """n chained crane_step calls from the scenario's initial state: the samples at the periods'
    ends and the last state (C structs all the way: no Python conversion in between)."""
    s = _c_state(sc.initial)
    inp, _keep = _c_inputs(sc.inputs, method)
    out = ffi.new("crane_sample[2]")
    ends = np.empty(n, dtype=_core.SAMPLE_DTYPE)
    view = ffi.cast("crane_sample *", ffi.from_buffer(ends))
    for k in range(n):
        m = _core.model(sc.crane, s.extension)   # the telescope's model at its extension
        assert lib.crane_step(m, s, inp, period, dt, s, out, _core.work()) == lib.CRANE_OK, k
        view[k] = out[1]
    return ends, s


# the paper's pressure drive into the lift's upper stop, the tilt driven onto its stop, the lift
# lever (valve) from rest, the lever into the upper stop (valve), the telescope and the slew moving
@pytest.mark.parametrize("name", ["paper-fig4", "end-stop-tilt", "lever-open", "valve-end-stop",
                                  "extend-while-slewing"])
@pytest.mark.parametrize("dt", [0.01, 0.005, 0.001])
def test_chained_periods_equal_one_prediction(name, dt):
    """With RK4, 200 chained 10-ms steps = one 2-s prediction: same step grid, so they differ only
    by the rounding of the stroke -> angle conversion at each period's start (docs/model.md)."""
    sc = cp.scenarios.get(name)
    whole = _core.predict(sc.crane, sc.initial, sc.inputs, 2.0, dt, "rk4")
    every = round(PERIOD / dt)
    ref = whole[every::every]
    ends, _ = _chain(sc, 200, dt, method="rk4")
    np.testing.assert_allclose(ends["t"], PERIOD)
    np.testing.assert_allclose(ends["tip"], ref["tip"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(ends["stroke"], ref["stroke"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(ends["slew"], ref["slew"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(ends["extension"], ref["extension"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(ends["p_a"], ref["p_a"], rtol=1e-9, atol=1e-3)
    np.testing.assert_allclose(ends["p_b"], ref["p_b"], rtol=1e-9, atol=1e-3)
    np.testing.assert_array_equal(ends["stop"], ref["stop"])
    if name in ("paper-fig4", "end-stop-tilt", "valve-end-stop"):
        assert ends["stop"].any(), "the scenario must reach a stop"


@pytest.mark.filterwarnings("ignore:Inputs.lift. holding the load")
@pytest.mark.parametrize("name", ["paper-fig4", "end-stop-tilt", "lever-open", "valve-end-stop",
                                  "extend-while-slewing"])
def test_chained_periods_with_the_error_controlled_method(name):
    """With the default method each period is integrated to the tolerance from its own start (the
    steps depend on where the periods begin), so 200 chained 10-ms periods agree with the one 2-s
    prediction to the method's accuracy, not to rounding: both within 1 mm of tip and 0.5 bar of
    the converged RK4 run (dt 2e-5 s), and on the same stops."""
    sc = cp.scenarios.get(name)
    ref = _core.predict(sc.crane, sc.initial, sc.inputs, 2.0, 2e-5, "rk4")[500::500]
    whole = _core.predict(sc.crane, sc.initial, sc.inputs, 2.0, PERIOD)[1:]
    ends, _ = _chain(sc, 200, PERIOD)
    for got in (ends, whole):
        assert np.abs(got["tip"] - ref["tip"]).max() <= 1e-3
        assert np.abs(got["p_a"] - ref["p_a"]).max() <= 0.5e5
        assert np.abs(got["p_b"] - ref["p_b"]).max() <= 0.5e5
    assert np.abs(ends["tip"] - whole["tip"]).max() > 1e-12   # not rounding: other steps
    assert (ends["stop"] != whole["stop"]).sum() <= 2   # a stop reached one period apart at most


def test_step_not_dividing_the_period():
    """dt = 4 ms in 10-ms periods (steps of 4, 4, 2 ms): another step grid than one prediction's
    at 4 ms, so the two differ by more than rounding, each within the 4-ms truncation error of a
    fine reference (the paper's pressure drive into the lift's stop: valves substep finer)."""
    sc = cp.scenarios.get("paper-fig4")
    fine = _core.predict(sc.crane, sc.initial, sc.inputs, 2.0, 1e-4, "rk4")[200::200]
    ends, _ = _chain(sc, 200, 0.004, method="rk4")
    whole = _core.predict(sc.crane, sc.initial, sc.inputs, 2.0, 0.004, "rk4")[5::5]   # every 20 ms
    err_chain = np.abs(ends["tip"][1::2] - fine["tip"]).max()
    err_whole = np.abs(whole["tip"] - fine["tip"]).max()
    assert err_whole < 1e-5, err_whole
    assert err_chain < 1.5 * err_whole, (err_chain, err_whole)
    assert np.abs(ends["tip"][1::2] - whole["tip"]).max() > 1e-9   # not rounding: another grid


@pytest.mark.filterwarnings("ignore:Inputs.lift. holding the load")
@pytest.mark.parametrize("name", ["lever-open", "paper-fig4", "extend-while-slewing",
                                  "valve-all-four"])
def test_next_state_is_trajectory_state(name):
    """The state out is Trajectory.state's at the period's end (one rule, in C and Python)."""
    sc = cp.scenarios.get(name)
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, 0.3, dt=0.01)
    want = traj.final_state
    s = _c_state(sc.initial)
    inp, _keep = _c_inputs(sc.inputs)
    nxt, out = ffi.new("crane_state *"), ffi.new("crane_sample[2]")
    assert lib.crane_step(_core.model(sc.crane, s.extension), s, inp, 0.3, 0.01, nxt,
                          out, _core.work()) == lib.CRANE_OK
    assert (nxt.stroke[0], nxt.stroke[1]) == (want.lift_stroke, want.tilt_stroke)
    assert (nxt.stroke_rate[0], nxt.stroke_rate[1]) == (want.lift_stroke_rate,
                                                        want.tilt_stroke_rate)
    assert (nxt.slew, nxt.extension, nxt.slew_rate, nxt.extension_rate) == \
        (want.slew, want.extension, want.slew_rate, want.extension_rate)
    for j, joint in enumerate(("lift", "tilt", "slew", "extension")):
        assert nxt.p_a[j] == (getattr(want, f"{joint}_p_a") or 0.0)
        assert nxt.p_b[j] == (getattr(want, f"{joint}_p_b") or 0.0)
        assert nxt.spool[j] == getattr(want, f"{joint}_spool")
    assert out[0].t == 0.0 and out[1].t == 0.3
    assert tuple(out[1].tip) == tuple(traj.tip[-1])
    assert tuple(out[0].tip) == tuple(traj.tip[0])


def test_stroke_rate_is_a_finite_difference():
    """The stroke rate of the state out agrees with the strokes' motion (independent of ds/dtheta)."""
    sc = cp.scenarios.get("lever-open")
    ends, s = _chain(sc, 51, 0.001, method="rk4")
    h = 2e-5
    fine = _core.predict(sc.crane, sc.initial, sc.inputs, 0.51 + h, 1e-5, "rk4")
    k = int(round(0.51 / 1e-5))
    fd = (fine["stroke"][k + 2] - fine["stroke"][k]) / (2e-5)
    assert s.stroke_rate[0] == pytest.approx(fd[0], rel=1e-4)
    assert s.stroke_rate[1] == pytest.approx(fd[1], rel=1e-3, abs=1e-7)


def _bad_call(**change):
    sc = cp.scenarios.get("lever-open")
    s = _c_state(sc.initial)
    inp, keep = _c_inputs(sc.inputs)
    args = dict(model=_core.model(sc.crane, s.extension), state=s, inputs=inp, period=PERIOD,
                dt=0.005, next=ffi.new("crane_state *"), out=ffi.new("crane_sample[2]"),
                work=_core.work())
    args.update(change)
    before = bytes(ffi.buffer(args["next"])) if args["next"] != ffi.NULL else None
    st = lib.crane_step(args["model"], args["state"], args["inputs"], args["period"], args["dt"],
                        args["next"], args["out"], args["work"])
    if before is not None and st != lib.CRANE_OK:
        assert bytes(ffi.buffer(args["next"])) == before, "nothing is written on an error"
    return st


def test_bad_input_gets_a_status():
    assert _bad_call() == lib.CRANE_OK
    for field in ("model", "state", "inputs", "next", "out", "work"):
        assert _bad_call(**{field: ffi.NULL}) == lib.CRANE_E_NULL, field
    assert _bad_call(period=0.0) == lib.CRANE_E_HORIZON
    assert _bad_call(period=-0.01) == lib.CRANE_E_HORIZON
    assert _bad_call(period=math.nan) == lib.CRANE_E_NONFINITE
    assert _bad_call(period=math.inf) == lib.CRANE_E_NONFINITE
    assert _bad_call(dt=0.0) == lib.CRANE_E_DT
    assert _bad_call(dt=0.02) == lib.CRANE_E_DT
    assert _bad_call(dt=math.nan) == lib.CRANE_E_NONFINITE
    assert _bad_call(period=1e9, dt=1e-6) == lib.CRANE_E_STEPS


def test_bad_state_and_inputs_get_a_status():
    sc = cp.scenarios.get("lever-open")
    s = _c_state(sc.initial)
    s.stroke[0] = math.nan
    assert _bad_call(state=s) == lib.CRANE_E_NONFINITE
    s = _c_state(sc.initial)
    s.stroke[0] = 10.0
    assert _bad_call(state=s) == lib.CRANE_E_STROKE
    s = _c_state(sc.initial)
    s.p_a[0] = -1e9
    assert _bad_call(state=s) == lib.CRANE_E_VALVE
    s = _c_state(sc.initial)
    s.extension = 0.5   # not the model's extension
    assert _bad_call(state=s) == lib.CRANE_E_EXTENSION
    inp, _keep = _c_inputs(sc.inputs)
    inp.drive[0].u = 2.0
    assert _bad_call(inputs=inp) == lib.CRANE_E_VALVE
    inp.drive[0].mode = 7
    assert _bad_call(inputs=inp) == lib.CRANE_E_DRIVE
