"""The Python API: bad input is rejected by name and range, nothing passed in is modified,
C status codes become clear exceptions."""

from __future__ import annotations

import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core
from cranepredict._cranepredict import ffi, lib

GOOD_STATE = dict(lift_stroke=0.1, tilt_stroke=0.3)


def _ok_inputs():
    return cp.Inputs(lift=cp.Pressure(100e5, 0), tilt=cp.Hold())


def test_predict_returns_arrays_of_the_documented_shapes(crane):
    tr = cp.predict(crane, cp.State(**GOOD_STATE), _ok_inputs(), 0.5, dt=0.01)
    n = 51
    assert tr.t.shape == (n,) and tr.strokes.shape == (n, 2) and tr.theta.shape == (n, 2)
    assert tr.omega.shape == (n, 2) and tr.tip.shape == (n, 3) and tr.stop.shape == (n, 4)
    for name in ("slew", "extension", "slew_rate", "extension_rate"):
        assert getattr(tr, name).shape == (n,), name
    for name in ("p_a", "p_b", "flow_a", "flow_b", "spool"):
        assert getattr(tr, name).shape == (n, 4), name
    assert tr.t[0] == 0.0 and tr.t[-1] == pytest.approx(0.5)
    pts = tr.points()
    assert set(pts) == set(cp.POINT_NAMES) and pts["tip"].shape == (n, 3)
    np.testing.assert_allclose(pts["tip"], tr.tip, atol=1e-12)
    with pytest.raises(ValueError):
        tr.tip[0, 0] = 1.0  # read-only


def test_a_c_trajectory_makes_its_arrays_on_first_read_and_keeps_them_read_only(crane):
    """The arrays of a C-core Trajectory are made when read (none before), each once, equal to
    those of the eager path (predict_many's batch, built by the constructor), and can neither be
    written, made writable, nor replaced."""
    import dataclasses

    state, inputs = cp.State(**GOOD_STATE), _ok_inputs()
    tr = cp.predict(crane, state, inputs, 0.5, dt=0.01)
    assert not set(cp.types.ARRAYS) & set(vars(tr)), "an array was made before it was read"
    tip = tr.tip
    assert tr.tip is tip and set(cp.types.ARRAYS) & set(vars(tr)) == {"tip"}
    eager = cp.predict_many(crane, [state], [inputs], 0.5, dt=0.01)[0]
    for name in cp.types.ARRAYS:
        np.testing.assert_array_equal(getattr(tr, name), getattr(eager, name), err_msg=name)
        a = getattr(tr, name)
        assert not a.flags.writeable, name
        with pytest.raises(ValueError):
            a.setflags(write=True)
    with pytest.raises(dataclasses.FrozenInstanceError):
        tr.tip = tip
    with pytest.raises(AttributeError, match="no attribute 'tipp'"):
        tr.tipp
    assert dataclasses.replace(tr, backend="c").tip.tolist() == tip.tolist()


@pytest.mark.parametrize("kwargs, exc, words", [
    (dict(horizon=0.0), ValueError, "horizon must be > 0 s"),
    (dict(horizon=math.inf), ValueError, "horizon must be finite"),
    (dict(dt=-1e-3), ValueError, "dt must be > 0 s"),
    (dict(dt=3.0), ValueError, r"dt must be in \(0, horizon\]"),
    (dict(dt="1ms"), TypeError, "dt must be a number"),
    (dict(backend="fortran"), ValueError, "backend must be one of"),
    (dict(initial=cp.State(lift_stroke=0.6, tilt_stroke=0.3)), ValueError,
     r"State.lift_stroke must be in \[0.0, 0.535\] m"),
    (dict(initial=cp.State(lift_stroke=0.1, tilt_stroke=-0.01)), ValueError,
     r"State.tilt_stroke must be in \[0.0, 0.78\] m"),
    (dict(initial=cp.State(lift_stroke=0.1, tilt_stroke=0.3, extension=1.5)), ValueError,
     r"State.extension must be in \[0.0, 1.0\] m"),
    (dict(initial=cp.State(lift_stroke=0.1, tilt_stroke=0.3, tilt_stroke_rate=0.1)), ValueError,
     "State.tilt_stroke_rate must be 0 for a held tilt cylinder"),
    (dict(inputs=cp.Inputs(lift=cp.PressureSeries(t=[0, 0.5], p_a=[1e6, 2e6], p_b=[0, 0]), tilt=cp.Hold())),
     ValueError, r"PressureSeries.t must cover \[0, horizon\]"),
    (dict(crane="PATU"), TypeError, "crane must be a cranepredict.Crane"),
    (dict(initial=(0.1, 0.3)), TypeError, "initial must be a cranepredict.State"),
    (dict(inputs={"lift": 1}), TypeError, "inputs must be a cranepredict.Inputs"),
])
def test_bad_predict_arguments_are_named(crane, kwargs, exc, words):
    args = dict(crane=crane, initial=cp.State(**GOOD_STATE), inputs=_ok_inputs(), horizon=1.0)
    args.update({k: v for k, v in kwargs.items() if k in args})
    extra = {k: v for k, v in kwargs.items() if k not in args}
    with pytest.raises(exc, match=words):
        cp.predict(args["crane"], args["initial"], args["inputs"], args["horizon"], **extra)


@pytest.mark.parametrize("make, exc, words", [
    (lambda: cp.State(lift_stroke=math.nan, tilt_stroke=0.3), ValueError, "State.lift_stroke must be finite"),
    (lambda: cp.State(lift_stroke="a", tilt_stroke=0.3), TypeError, "State.lift_stroke must be a number"),
    (lambda: cp.Pressure(p_a=-1.0), ValueError, r"Pressure.p_a must be in \[0, 1e\+08\] Pa"),
    (lambda: cp.Pressure(p_a=1e6, p_b=2e8), ValueError, "Pressure.p_b must be in"),
    (lambda: cp.PressureSeries(t=[0, 0], p_a=[0, 0], p_b=[0, 0]), ValueError, "strictly increasing"),
    (lambda: cp.PressureSeries(t=[0, 1], p_a=[0, 0, 0], p_b=[0, 0]), ValueError, "same length"),
    (lambda: cp.PressureSeries(t=[0, 1], p_a=[0, math.nan], p_b=[0, 0]), ValueError, "p_a must be finite"),
    (lambda: cp.Inputs(lift=cp.Hold(), tilt=5.0), TypeError, "Inputs.tilt must be Pressure"),
])
def test_bad_types_are_rejected_at_construction(make, exc, words):
    with pytest.raises(exc, match=words):
        make()


def test_nothing_passed_in_is_modified(crane):
    t = np.array([0.0, 0.5, 1.0])
    pa = np.array([100e5, 150e5, 120e5])
    pb = np.zeros(3)
    series = cp.PressureSeries(t=t, p_a=pa, p_b=pb)
    pa[0] = 1.0  # the series copied its arrays
    assert series.p_a[0] == 100e5
    before = crane.to_dict()
    cp.predict(crane, cp.State(**GOOD_STATE), cp.Inputs(lift=series, tilt=cp.Hold()), 1.0)
    assert crane.to_dict() == before and series.p_a[0] == 100e5


# --- the C core's own checks, reached by calling it directly (bypassing the Python checks) ----

def _raw_predict(crane, **over):
    s = ffi.new("crane_state *")
    s.stroke = over.get("stroke", (0.1, 0.3))
    s.extension = over.get("extension", 0.0)
    inp = ffi.new("crane_inputs *")
    inp.drive[0].mode = over.get("mode", lib.CRANE_DRIVE_PRESSURE)
    inp.drive[0].p_a = over.get("p_a", 1e7)
    inp.drive[1].mode = lib.CRANE_DRIVE_HOLD
    cap = over.get("capacity", 1001)
    out = ffi.new("crane_sample[]", cap + 1)
    out[cap].t = 12345.0  # a sentinel just past the capacity
    n = ffi.new("size_t *")
    st = lib.crane_predict(_core.params(crane), s, inp, over.get("horizon", 1.0), over.get("dt", 1e-3),
                           out, cap, n, _core.work())
    assert out[cap].t == 12345.0  # never written past the capacity
    return st


@pytest.mark.parametrize("over, status", [
    (dict(dt=0.0), "CRANE_E_DT"),
    (dict(dt=math.nan), "CRANE_E_NONFINITE"),
    (dict(horizon=-1.0), "CRANE_E_HORIZON"),
    (dict(stroke=(0.9, 0.3)), "CRANE_E_STROKE"),
    (dict(extension=5.0), "CRANE_E_EXTENSION"),
    (dict(p_a=-5.0), "CRANE_E_PRESSURE"),
    (dict(mode=7), "CRANE_E_DRIVE"),
    (dict(capacity=10), "CRANE_E_CAPACITY"),
])
def test_c_status_codes(crane, over, status):
    st = _raw_predict(crane, **over)
    assert st == getattr(lib, status)
    with pytest.raises(_core.CoreError) as info:
        _core.ensure(st, "predict")
    assert info.value.status == st and len(str(info.value)) > 20


def test_c_core_rejects_null_pointers(crane):
    n = ffi.new("size_t *")
    assert lib.crane_predict(ffi.NULL, ffi.NULL, ffi.NULL, 1.0, 1e-3, ffi.NULL, 0, n,
                             ffi.NULL) == lib.CRANE_E_NULL
    m = ffi.new("crane_model *")
    assert lib.crane_model_init(m, ffi.NULL, 0.0) == lib.CRANE_E_NULL


def test_every_status_has_a_message():
    # crane_status_message's switch has a default (MISRA 16.4), so the compiler no longer flags a
    # status without a case: each must have its own message, none the fallback of a non-status
    unknown = ffi.string(lib.crane_status_message(12345)).decode()
    names = [name for name in dir(lib) if name.startswith("CRANE_E_") or name == "CRANE_OK"]
    messages = {}
    for name in names:
        msg = ffi.string(lib.crane_status_message(getattr(lib, name))).decode()
        assert len(msg) >= 2 and (name == "CRANE_OK" or len(msg) > 10), name
        assert msg != unknown, name
        messages[msg] = name
    assert len(messages) == len(names) > 30


def test_absurd_gravity_raises_instead_of_returning_nan(crane):
    # gravity is validated >= 0 only; 1e135 overflows the state, which the core reports as
    # CRANE_E_DIVERGED (docs/model.md, "End stops") instead of returning NaN
    import dataclasses

    absurd = dataclasses.replace(crane, gravity=1e135)
    with pytest.raises(ValueError, match="diverged") as info:
        cp.predict(absurd, cp.State(**GOOD_STATE), _ok_inputs(), 0.2, dt=1e-3)
    assert getattr(info.value, "status", lib.CRANE_E_DIVERGED) == lib.CRANE_E_DIVERGED
    with pytest.raises(ValueError, match="diverged"):
        cp.predict_many(absurd, [cp.State(**GOOD_STATE)], [_ok_inputs()], 0.2, dt=1e-3)
