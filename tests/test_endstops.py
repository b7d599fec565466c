"""End stops: never exceeded, no energy gained at an impact, released when the force pulls back."""

from __future__ import annotations

import numpy as np
import pytest

import cranepredict as cp
from conftest import frictionless, random_case
from lagrange import Lagrange


@pytest.mark.parametrize("backend", ["c", "python"])
def test_strokes_never_leave_their_range(crane, backend):
    rng = np.random.default_rng(11)
    n_stops = 0
    for _ in range(12 if backend == "python" else 60):
        c, initial, inputs = random_case(rng, crane)
        tr = cp.predict(c, initial, inputs, 2.0, backend=backend)
        for j, cyl in enumerate((c.lift_cylinder, c.tilt_cylinder)):
            assert tr.strokes[:, j].min() >= cyl.stroke_min
            assert tr.strokes[:, j].max() <= cyl.stroke_max
            at_hi = tr.stop[:, j] == 1
            assert np.all(tr.strokes[at_hi, j] == cyl.stroke_max)
            assert np.all(tr.omega[tr.stop[:, j] != 0, j] == 0.0)
        n_stops += int(tr.stop.any())
    assert n_stops > 0  # the random cases do reach stops


def test_paper_scenario_reaches_the_upper_stop_and_stays(crane):
    sc = cp.scenarios.get("paper-fig4")
    tr = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon)
    t_hit = tr.first_stop_time(0, +1)
    assert t_hit is not None and t_hit < 2.0
    after = tr.t >= t_hit
    assert np.all(tr.stop[after, 0] == 1)
    assert np.all(tr.strokes[after, 0] == sc.crane.lift_cylinder.stroke_max)
    assert np.all(tr.strokes[:, 1] == tr.strokes[0, 1])  # tilt held


def test_impact_gains_no_energy(crane):
    """Frictionless fall under gravity onto the lower lift stop: energy never rises, drops at impact.
    RK4 at 1 ms, whose energy error is far below the bound: the error-controlled methods hold a
    step's error to the tip tolerance, and between their samples the energy moves by that much
    (the explicit pair: 0.017 J of 8,307 J, over the 8e-3 J bound here)."""
    c = frictionless(crane)
    initial = cp.State(lift_stroke=0.2, tilt_stroke=0.3)
    for tilt in (cp.Hold(), cp.Pressure(0, 0)):
        tr = cp.predict(c, initial, cp.Inputs(lift=cp.Pressure(0, 0), tilt=tilt), 1.5, dt=1e-3,
                        method="rk4")
        hit = tr.first_stop_time(0, -1)
        assert hit is not None
        lag = Lagrange(c, 0.0)
        e = np.array([lag.energy(q, w) for q, w in zip(tr.theta, tr.omega)])
        assert np.all(np.diff(e) < 1e-6 * abs(e[0]) + 1e-6)
        k = int(np.flatnonzero(tr.t >= hit)[0])
        assert e[k] < e[k - 1] - 1.0  # the impact took energy out


def test_release_from_the_lower_stop_when_pressure_pushes(crane):
    initial = cp.State(lift_stroke=0.0, tilt_stroke=0.3)
    tr = cp.predict(crane, initial, cp.Inputs(lift=cp.Pressure(150e5, 0), tilt=cp.Hold()), 1.0)
    assert tr.stop[0, 0] == -1
    assert tr.strokes[-1, 0] > 0.05 and tr.stop[-1, 0] == 0


def test_release_from_the_upper_stop_when_gravity_pulls(crane):
    initial = cp.State(lift_stroke=0.535, tilt_stroke=0.3)
    tr = cp.predict(crane, initial, cp.Inputs(lift=cp.Pressure(0, 0), tilt=cp.Hold()), 1.0)
    assert tr.stop[0, 0] == 1
    assert tr.strokes[-1, 0] < 0.5


def test_stays_at_the_stop_while_pushed_into_it(crane):
    initial = cp.State(lift_stroke=0.535, tilt_stroke=0.3)
    tr = cp.predict(crane, initial, cp.Inputs(lift=cp.Pressure(175e5, 0), tilt=cp.Hold()), 1.0)
    assert np.all(tr.stop[:, 0] == 1) and np.all(tr.strokes[:, 0] == 0.535)


def test_tilt_reaches_both_of_its_stops(crane):
    down = cp.predict(crane, cp.State(lift_stroke=0.3, tilt_stroke=0.5),
                      cp.Inputs(lift=cp.Hold(), tilt=cp.Pressure(150e5, 0)), 2.0)
    assert down.first_stop_time(1, +1) is not None
    up = cp.predict(crane, cp.State(lift_stroke=0.3, tilt_stroke=0.2),
                    cp.Inputs(lift=cp.Hold(), tilt=cp.Pressure(0, 150e5)), 2.0)
    assert up.first_stop_time(1, -1) is not None


def test_both_joints_pressed_into_their_stops_stay_there_without_chatter(crane):
    """Lift pushed up to full stroke, tilt pulled in to stroke_min: once both are on their stops
    they stay, with one impact each (a release rule that frees a joint only because the other is
    locked makes it hit its stop again every step)."""
    from cranepredict import twin

    initial = cp.State(lift_stroke=0.3, tilt_stroke=0.2)
    inputs = cp.Inputs(lift=cp.Pressure(175e5, 0), tilt=cp.Pressure(0, 150e5))
    arrays, events = twin._run(crane, initial, inputs, 2.0, 1e-3)
    assert arrays["stop"][-1].tolist() == [1, -1, 0, 0]
    assert len(events) <= 4, events
    c = cp.predict(crane, initial, inputs, 2.0, dt=1e-3)
    assert c.stop[-1].tolist() == [1, -1, 0, 0]
    k = int(np.flatnonzero((c.stop[:, :2] != 0).all(axis=1))[0])
    assert np.all(c.stop[k:] == c.stop[-1]) and np.all(c.omega[k:] == 0.0)
    np.testing.assert_allclose(c.tip, arrays["tip"], rtol=0, atol=1e-9)
