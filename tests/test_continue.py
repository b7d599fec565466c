"""Continuing a prediction: Trajectory.state(i) is the State the prediction continues from."""

import numpy as np
import pytest

import cranepredict as cp
from cranepredict.types import JOINTS

CONSTANT = (cp.Pressure, cp.Valve, cp.Hold)


def _constant_drives(sc):
    return all(isinstance(getattr(sc.inputs, j), CONSTANT) for j in JOINTS)


@pytest.mark.parametrize("name", ["lever-open", "valve-both-levers", "both-driven",
                                  "slew-while-lifting", "extend-while-slewing", "end-stop-tilt",
                                  "telescope-end-stop"])
@pytest.mark.parametrize("backend", ["c", "python"])
def test_second_half_continues_the_first(name, backend):
    """Predict 2 s with RK4; predict again from the state at 1 s: the second half is the same
    motion, to rounding (the same step grid)."""
    sc = cp.scenarios.get(name)
    assert _constant_drives(sc)
    horizon = 1.0 if backend == "python" else sc.horizon
    whole = cp.predict(sc.crane, sc.initial, sc.inputs, horizon, backend=backend, method="rk4")
    n = (len(whole.t) - 1) // 2
    rest = cp.predict(sc.crane, whole.state(n), sc.inputs, float(whole.t[-1] - whole.t[n]),
                      backend=backend, method="rk4")
    assert rest.t.shape == whole.t[n:].shape
    np.testing.assert_allclose(rest.tip, whole.tip[n:], rtol=0, atol=1e-9)
    np.testing.assert_allclose(rest.p_a, whole.p_a[n:], rtol=0, atol=1e-3)
    np.testing.assert_allclose(rest.p_b, whole.p_b[n:], rtol=0, atol=1e-3)
    np.testing.assert_array_equal(rest.stop, whole.stop[n:])


@pytest.mark.parametrize("name", ["lever-open", "valve-both-levers", "both-driven",
                                  "slew-while-lifting", "extend-while-slewing", "end-stop-tilt",
                                  "telescope-end-stop"])
def test_second_half_continues_the_first_to_the_methods_accuracy(name):
    """With the default (error-controlled) method the second half's steps start afresh at 1 s, so
    it continues the first to the method's accuracy: both within 1 mm of tip and 0.5 bar of the
    converged RK4 run (dt 2e-5 s)."""
    sc = cp.scenarios.get(name)
    whole = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon)
    ref = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, method="rk4", dt=2e-5,
                     sample_every=250)
    n = (len(whole.t) - 1) // 2
    rest = cp.predict(sc.crane, whole.state(n), sc.inputs, float(whole.t[-1] - whole.t[n]))
    assert rest.t.shape == whole.t[n:].shape
    assert np.abs(rest.tip - ref.tip[n:]).max() <= 1e-3
    assert np.abs(rest.p_a - ref.p_a[n:]).max() <= 0.5e5
    assert np.abs(rest.p_b - ref.p_b[n:]).max() <= 0.5e5


def test_chained_control_periods_equal_one_call():
    """200 chained 10-ms predictions give the 2-s prediction (fixed step: to rounding)."""
    sc = cp.scenarios.get("lever-open")
    whole = cp.predict(sc.crane, sc.initial, sc.inputs, 2.0, dt=0.005, method="rk4")
    state, tips = sc.initial, []
    for _ in range(200):
        part = cp.predict(sc.crane, state, sc.inputs, 0.01, dt=0.005, method="rk4")
        tips.append(part.tip[-1])
        state = part.final_state
    np.testing.assert_allclose(np.array(tips), whole.tip[2::2], rtol=0, atol=1e-9)


def test_state_fields_match_the_sample():
    sc = cp.scenarios.get("extend-while-slewing")
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, 0.5)
    st = traj.state(40)
    assert (st.lift_stroke, st.tilt_stroke) == tuple(traj.strokes[40])
    assert st.slew == traj.slew[40] and st.extension == traj.extension[40]
    assert st.slew_rate == traj.slew_rate[40] and st.extension_rate == traj.extension_rate[40]
    for j, name in enumerate(JOINTS):
        assert st.pressures(name) == (traj.p_a[40, j], traj.p_b[40, j])
        assert getattr(st, f"{name}_spool") == traj.spool[40, j]
    # the stroke rate is omega times ds/dtheta at the sample's pose (a finite difference of the
    # strokes, independent of the core's kinematics, agrees)
    dt = traj.t[41] - traj.t[39]
    fd = (traj.strokes[41] - traj.strokes[39]) / dt
    assert st.lift_stroke_rate == pytest.approx(fd[0], rel=2e-3, abs=2e-6)
    assert st.tilt_stroke_rate == pytest.approx(fd[1], rel=2e-3, abs=2e-6)


def test_c_and_twin_states_agree():
    sc = cp.scenarios.get("slew-while-lifting")
    a = cp.predict(sc.crane, sc.initial, sc.inputs, 0.5).final_state
    b = cp.predict(sc.crane, sc.initial, sc.inputs, 0.5, backend="python").final_state
    for f in ("lift_stroke", "tilt_stroke", "lift_stroke_rate", "tilt_stroke_rate", "slew",
              "slew_rate", "extension", "extension_rate"):
        assert getattr(a, f) == pytest.approx(getattr(b, f), abs=1e-9), f
    for f in ("lift_p_a", "lift_p_b", "tilt_p_a", "tilt_p_b", "slew_p_a", "slew_p_b"):
        assert getattr(a, f) == pytest.approx(getattr(b, f), abs=1e-3), f


def test_state_index_errors():
    sc = cp.scenarios.get("paper-fig4")
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, 0.1)
    with pytest.raises(IndexError, match=r"\[-21, 20\], got 21"):
        traj.state(21)
    with pytest.raises(TypeError, match="i must be an int"):
        traj.state(1.0)
    assert traj.state(-1) == traj.final_state
