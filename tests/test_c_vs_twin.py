"""The C core and the pure-Python twin, written independently from docs/model.md, agree."""

from __future__ import annotations

import numpy as np
import pytest

import cranepredict as cp
from conftest import random_case

TOL = 1e-9  # m, tip; the target


def _compare(c, initial, inputs, horizon, dt=None):
    a = cp.predict(c, initial, inputs, horizon, dt=dt, backend="c")
    b = cp.predict(c, initial, inputs, horizon, dt=dt, backend="python")
    assert a.t.shape == b.t.shape
    np.testing.assert_array_equal(a.stop, b.stop)
    np.testing.assert_allclose(a.t, b.t, rtol=0, atol=1e-12)
    return (float(np.max(np.abs(a.tip - b.tip))), float(np.max(np.abs(a.strokes - b.strokes))),
            float(np.max(np.abs(a.omega - b.omega))))


@pytest.mark.slow
def test_fifty_random_scenarios_agree():
    crane = cp.Crane.patu655()
    rng = np.random.default_rng(2026)
    worst = 0.0
    kinds = set()
    for _ in range(50):
        c, initial, inputs = random_case(rng, crane)
        kinds.add((type(inputs.lift).__name__, type(inputs.tilt).__name__))
        tip, strokes, omega = _compare(c, initial, inputs, 2.0)
        worst = max(worst, tip)
        assert tip < TOL and strokes < TOL
    assert len(kinds) >= 6  # holds, constant pressures and series, in many combinations
    print(f"C vs twin: max tip difference over 50 random scenarios = {worst:.2e} m")


@pytest.mark.parametrize("name", cp.scenarios.names())
def test_every_named_scenario_agrees(name):
    sc = cp.scenarios.get(name)
    tip, strokes, _ = _compare(sc.crane, sc.initial, sc.inputs, sc.horizon)
    assert tip < TOL and strokes < TOL


def test_odd_horizon_and_initial_velocity_agree(crane):
    # horizon not a multiple of dt (a shorter last step), initial stroke rates, a stop at t = 0
    initial = cp.State(lift_stroke=0.535, tilt_stroke=0.1, tilt_stroke_rate=0.05, slew=1.0, extension=0.7)
    inputs = cp.Inputs(lift=cp.Pressure(120e5, 0), tilt=cp.Pressure(0, 30e5))
    tip, strokes, _ = _compare(crane, initial, inputs, 0.7777, dt=2e-3)
    assert tip < TOL


def _random_valve_case(rng, crane, horizon=2.0):
    """A valve-driven case: levers constant or sampled (also slammed), the other cylinder often
    pressure-driven or held, strokes over the whole range (stops included), loads 0-500 kg."""
    while True:
        c = crane.with_load(float(rng.uniform(0, 500)))
        lc, tc = c.lift_cylinder, c.tilt_cylinder
        strokes = [float(rng.choice([rng.uniform(cyl.stroke_min, cyl.stroke_max), cyl.stroke_min,
                                     cyl.stroke_max], p=[0.8, 0.1, 0.1])) for cyl in (lc, tc)]
        extension = float(rng.uniform(0, 1))
        try:
            rest = cp.state_at_rest(c, *strokes, extension=extension,
                                    lift_rod_pressure=float(rng.uniform(1e5, 40e5)),
                                    tilt_rod_pressure=float(rng.uniform(1e5, 40e5)))
        except ValueError:   # that rod pressure cannot hold this pose: the tank pressure can
            try:
                rest = cp.state_at_rest(c, *strokes, extension=extension)
            except ValueError:   # not even below the relief setting: another load and pose
                continue
        break
    drives = []
    for _ in range(2):
        kind = rng.integers(0, 5)
        if kind <= 1:
            drives.append(cp.Valve(float(rng.uniform(-1, 1))))
        elif kind == 2:
            n = int(rng.integers(2, 7))
            t = np.unique(np.concatenate([[0.0], np.sort(rng.uniform(0, horizon, n - 2)), [horizon]]))
            drives.append(cp.ValveSeries(t=t, u=rng.choice([-1.0, 0.0, 1.0, rng.uniform(-1, 1)], t.size)))
        elif kind == 3:
            drives.append(cp.Pressure(rng.uniform(0, 150e5), rng.uniform(0, 50e5)))
        else:
            drives.append(cp.Hold())
    if not any(isinstance(d, (cp.Valve, cp.ValveSeries)) for d in drives):
        drives[0] = cp.Valve(float(rng.uniform(-1, 1)))
    spools = {}
    for name, d in zip(("lift", "tilt"), drives):
        if isinstance(d, (cp.Valve, cp.ValveSeries)):
            spools[f"{name}_spool"] = float(rng.uniform(-1, 1))
    import dataclasses
    return c, dataclasses.replace(rest, **spools), cp.Inputs(lift=drives[0], tilt=drives[1])


@pytest.mark.slow
# RK4's arithmetic is the same in both implementations; the error-controlled method solves its
# linear systems two ways (the chambers eliminated in closed form in C, a dense LU with partial
# pivoting in the twin), and with a relief or anti-cavitation valve open (G_lim/C ~ 1e8 /s in the
# matrix) their rounding differs by up to 2e-10 of the pressure. Their steps are the same (the
# proposals on a grid, docs/model.md "Integration"): measured 1.6e-6 Pa and a spool 1e-9 apart
# (before the grid, the step sizes drifted apart: 1.6e-3 Pa).
@pytest.mark.parametrize("method, spool_tol, p_tol", [("rk4", 1e-12, 1e-3), ("rosw", 1e-9, 1e-3)])
def test_twenty_random_valve_driven_cases_agree(method, spool_tol, p_tol):
    """Tip to 1e-9 m and chamber pressures to 1e-3 Pa (the issue's targets; measured 7e-15 m
    and 3e-7 Pa. With the earlier tanh friction law, smoothing over 1 mm/s, a release from a stop
    located by bisection put 5e-3 Pa between them in one case.)"""
    crane = cp.Crane.patu655()
    rng = np.random.default_rng(909)
    worst_tip = worst_p = 0.0
    stops = 0
    for _ in range(20):
        c, initial, inputs = _random_valve_case(rng, crane)
        a = cp.predict(c, initial, inputs, 2.0, backend="c", method=method)
        b = cp.predict(c, initial, inputs, 2.0, backend="python", method=method)
        np.testing.assert_array_equal(a.stop, b.stop)
        stops += int(a.stop.any())
        worst_tip = max(worst_tip, float(np.max(np.abs(a.tip - b.tip))))
        worst_p = max(worst_p, float(max(np.max(np.abs(a.p_a - b.p_a)), np.max(np.abs(a.p_b - b.p_b)))))
        np.testing.assert_allclose(a.flow_a, b.flow_a, rtol=0, atol=1e-12)
        np.testing.assert_allclose(a.spool, b.spool, rtol=0, atol=spool_tol)
    print(f"C vs twin, 20 valve-driven cases: tip {worst_tip:.2e} m, pressures {worst_p:.2e} Pa, "
          f"{stops} with end stops")
    assert worst_tip < TOL and worst_p < p_tol
    assert stops >= 4


def _drives_rule_cases():
    """Futures whose ROS34PW2 steps the drives' rule cuts (docs/model.md, "Integration"): a lever
    tap between two stages, a noisy 1-kHz lever log (the farthest sample that keeps the rule is
    found by bisection) and a pressure pulse in a future that a valve makes stiff."""
    sc = cp.scenarios.get("lever-open")
    rng = np.random.default_rng(5)
    t_log = np.arange(501) * 1e-3
    noisy = np.clip(0.6 * np.sin(6.0 * t_log) + rng.normal(0.0, 0.02, t_log.size), -1.0, 1.0)
    p_a = sc.initial.tilt_p_a
    return sc, [
        cp.Inputs(lift=cp.ValveSeries(t=[0, 0.3, 0.301, 0.31, 0.311, 0.5], u=[0, 0, 1, 1, 0, 0]),
                  tilt=cp.Valve(0.0)),
        cp.Inputs(lift=cp.ValveSeries(t=t_log, u=noisy), tilt=cp.Valve(-0.3)),
        cp.Inputs(lift=cp.Valve(0.2), tilt=cp.PressureSeries(
            t=[0, 0.2, 0.201, 0.21, 0.211, 0.5], p_a=[p_a, p_a, p_a + 40e5, p_a + 40e5, p_a, p_a],
            p_b=[sc.initial.tilt_p_b] * 6)),
    ]


@pytest.mark.parametrize("case", range(3))
def test_steps_cut_by_the_drives_rule_agree(case):
    sc, cases = _drives_rule_cases()
    inputs = cases[case]
    a = cp.predict(sc.crane, sc.initial, inputs, 0.5, backend="c")
    b = cp.predict(sc.crane, sc.initial, inputs, 0.5, backend="python")
    assert float(np.max(np.abs(a.tip - b.tip))) < TOL
    assert float(max(np.max(np.abs(a.p_a - b.p_a)), np.max(np.abs(a.p_b - b.p_b)))) < 1e-3


@pytest.mark.slow
def test_random_cases_with_the_compensated_valve_agree():
    """The compensated valve (its dead band, meter-in saturation and meter-out orifice, with a
    spool lag: the valve's gain in ROS34PW2's matrix takes its branches) on both booms: C and twin
    agree as with the orifice valve."""
    import dataclasses
    crane = cp.Crane.patu655()
    comp = dict(valve="compensated", dead_band=0.114, meter_out_flow=crane.lift_cylinder.hydraulics.nominal_flow,
                meter_out_pressure_drop=7e5)
    for j in ("lift", "tilt"):
        cyl = getattr(crane, f"{j}_cylinder")
        crane = dataclasses.replace(crane, **{f"{j}_cylinder": dataclasses.replace(
            cyl, hydraulics=dataclasses.replace(cyl.hydraulics, **comp))})
    rng = np.random.default_rng(911)
    worst_tip = worst_p = 0.0
    for _ in range(10):
        c, initial, inputs = _random_valve_case(rng, crane)
        a = cp.predict(c, initial, inputs, 2.0, backend="c")
        b = cp.predict(c, initial, inputs, 2.0, backend="python")
        np.testing.assert_array_equal(a.stop, b.stop)
        worst_tip = max(worst_tip, float(np.max(np.abs(a.tip - b.tip))))
        worst_p = max(worst_p, float(max(np.max(np.abs(a.p_a - b.p_a)), np.max(np.abs(a.p_b - b.p_b)))))
        np.testing.assert_allclose(a.spool, b.spool, rtol=0, atol=1e-9)
    print(f"C vs twin, 10 compensated-valve cases: tip {worst_tip:.2e} m, pressures {worst_p:.2e} Pa")
    assert worst_tip < TOL and worst_p < 1e-3
