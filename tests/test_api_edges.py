"""What a new user meets first: drives left out are held, thinned samples from predict, units
that look wrong warned about, a load the supply cannot lift flagged, the guard's exit status,
and a Crane that is cheap to build."""

from __future__ import annotations

import dataclasses
import json
import typing
import warnings

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import cli


# -- every drive left out is held -----------------------------------------------------------------

def test_inputs_without_tilt_holds_the_tilt(crane):
    initial = cp.State(lift_stroke=0.116, tilt_stroke=0.20)
    lift = cp.Pressure(p_a=175e5, p_b=0.0)
    short = cp.Inputs(lift=lift)
    assert short == cp.Inputs(lift=lift, tilt=cp.Hold(), slew=cp.Hold(), extension=cp.Hold())
    tr = cp.predict(crane, initial, short, 0.5)
    assert np.all(tr.strokes[:, 1] == 0.20)            # the tilt stroke never moved
    assert tr.strokes[-1, 0] > 0.116 + 0.01            # while the lift cylinder did


def test_inputs_with_nothing_given_holds_the_whole_crane(crane):
    initial = cp.State(lift_stroke=0.116, tilt_stroke=0.20, slew=0.3, extension=0.2)
    tr = cp.predict(crane, initial, cp.Inputs(), 0.2)
    assert np.all(tr.strokes == [0.116, 0.20]) and np.all(tr.slew == 0.3)
    assert np.all(tr.extension == 0.2)
    assert np.all(tr.tip == tr.tip[0])


# -- predict(sample_every=...) ----------------------------------------------------------------------

@pytest.mark.parametrize("backend", ["c", "python"])
def test_predict_sample_every_keeps_t0_every_mth_step_and_the_last(backend):
    sc = cp.scenarios.get("lever-open")
    horizon, m = 0.5, 7                                  # 100 steps: 0, 7, ..., 98, then 100
    full = cp.predict(sc.crane, sc.initial, sc.inputs, horizon, backend=backend)
    thin = cp.predict(sc.crane, sc.initial, sc.inputs, horizon, backend=backend, sample_every=m)
    rows = list(range(0, 101, m)) + [100]
    assert len(full.t) == 101 and len(thin.t) == len(rows)
    for name in cp.types.ARRAYS:
        np.testing.assert_array_equal(getattr(thin, name), getattr(full, name)[rows], err_msg=name)
    # the same numbers as predict_many's thinned batch
    batch = cp.predict_many(sc.crane, [sc.initial], [sc.inputs], horizon, sample_every=m)
    np.testing.assert_allclose(thin.tip, batch.tip[0], rtol=0, atol=1e-9)


@pytest.mark.parametrize("bad", [0, -1, 2.0, True, "3", cp.MAX_STEPS + 1])
def test_predict_sample_every_bad_is_named(crane, bad):
    with pytest.raises(ValueError, match="sample_every must be an int in"):
        cp.predict(crane, cp.State(0.1, 0.2), cp.Inputs(), 0.1, sample_every=bad)


# -- the README's guard block reads a GO verdict ----------------------------------------------------

def test_readme_guard_block_runs_on_every_example_world():
    from test_readme import readme_blocks, run_blocks

    blocks = readme_blocks()
    guard = [b for b in blocks if "cp.guard(" in b]
    assert len(guard) == 1
    ns = run_blocks(blocks[:blocks.index(guard[0])])
    signals = set()
    for name in cp.worlds.names():
        code = guard[0].replace('cp.worlds.get("power-line")', f'cp.worlds.get("{name}")')
        assert code != guard[0] or name == "power-line"
        run = dict(ns)
        exec(compile(code, "README.md (guard block)", "exec"), run)
        signals.add(run["v"].signal)
    assert "GO" in signals and signals - {"GO"}      # both branches of the block ran


# -- implausible magnitudes -------------------------------------------------------------------------

def test_a_pressure_in_bar_is_warned_about_naming_the_field(crane):
    initial = cp.State(lift_stroke=0.116, tilt_stroke=0.20)
    with pytest.warns(UserWarning, match=r"Inputs\.lift: Pressure\.p_a = 175 Pa: below 1 bar, where "
                                         r"holding the lift boom at this pose takes \d+ bar") as rec:
        cp.predict(crane, initial, cp.Inputs(lift=cp.Pressure(175, 0)), 0.1)
    assert rec[0].filename == __file__                   # points at the caller's line
    lever = cp.PressureSeries(t=[0, 2], p_a=[0, 0], p_b=[20, 50])
    with pytest.warns(UserWarning, match=r"Inputs\.tilt: PressureSeries\.p_b = 50 Pa"):
        cp.predict(crane, initial, cp.Inputs(lift=cp.Hold(), tilt=lever), 0.1)


def test_small_pressures_where_small_ones_hold_are_not_warned_about(crane):
    """The telescope near horizontal holds on a fraction of a bar; a boom drive of 0 Pa is 'no
    pressure', not a unit slip."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cp.Pressure(175, 0)                              # no crane, no pose: nothing to compare
        initial = cp.State(lift_stroke=0.116, tilt_stroke=0.20, extension=0.5)
        cp.predict(crane, initial, cp.Inputs(extension=cp.Pressure(0.5e5, 0)), 0.1)
        cp.predict(crane, initial, cp.Inputs(lift=cp.Pressure(0, 0)), 0.1)


def test_measured_chamber_pressures_in_bar_are_warned_about():
    with pytest.warns(UserWarning, match=r"State\.lift_p_a = 53\.5 Pa.*State\.tilt_p_b = 77\.1 Pa") as rec:
        cp.State(lift_stroke=0.116, tilt_stroke=0.20, lift_p_a=53.5, lift_p_b=31.0,
                 tilt_p_a=48.1, tilt_p_b=77.1)
    assert rec[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cp.State(0.116, 0.20, lift_p_a=53.5e5, lift_p_b=1e5, tilt_p_a=1e5, tilt_p_b=77.1e5)
        cp.State(0.116, 0.20, lift_p_a=0.0, lift_p_b=0.0)          # no pressure at all: plausible
        cp.state_at_rest(cp.Crane.patu655(), 0.116, 0.20)


def test_plausible_pressures_are_not_warned_about():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        initial = cp.State(lift_stroke=0.116, tilt_stroke=0.20)
        for lift in (cp.Pressure(175e5, 0), cp.Pressure(2e5, 0.5e5),
                     cp.PressureSeries(t=[0, 2], p_a=[40e5, 90e5], p_b=[0, 0])):
            cp.predict(cp.Crane.patu655(), initial, cp.Inputs(lift=lift), 0.1)


def test_a_lever_in_percent_is_refused_with_the_hint():
    with pytest.raises(ValueError, match=r"ValveSeries\.u must be in \[-1, 1\].*percent.*u / 100"):
        cp.ValveSeries(t=[0.0, 0.5, 2.0], u=[0.0, 80.0, 80.0])
    with pytest.raises(ValueError, match=r"Valve\.u must be in \[-1, 1\].*percent"):
        cp.Valve(60)
    with pytest.raises(ValueError) as e:                # far outside: no percent hint
        cp.Valve(1e4)
    assert "percent" not in str(e.value)


# -- a load the supply cannot lift ------------------------------------------------------------------

def _lever_up(load):
    c = cp.Crane.patu655().with_load(load)
    initial = cp.state_at_rest(c, lift_stroke=0.116, tilt_stroke=0.20)
    return c, initial, cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(0.0))


def test_a_lift_the_supply_cannot_hold_is_flagged_and_sinks():
    c, initial, inputs = _lever_up(350.0)
    supply = c.lift_cylinder.hydraulics.supply_pressure
    tank = c.lift_cylinder.hydraulics.tank_pressure
    assert cp.holding_pressure(c, initial, "lift", p_b=tank) > supply   # the premise, from statics
    with pytest.warns(UserWarning, match=r"Inputs\.lift: .*hydraulics\.supply_pressure.*sinks"):
        tr = cp.predict(c, initial, inputs, 2.0)
    assert tr.supply_short == ("lift",)
    assert tr.tip[-1, 2] < tr.tip[0, 2] - 0.1           # lever fully up, yet the load goes down


def test_a_lift_the_supply_can_hold_is_not_flagged_and_rises():
    c, initial, inputs = _lever_up(200.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tr = cp.predict(c, initial, inputs, 2.0)
    assert tr.supply_short == ()
    assert tr.tip[-1, 2] > tr.tip[0, 2] + 0.1


def test_a_load_lowered_or_held_on_a_closed_valve_is_not_flagged():
    c, initial, _ = _lever_up(350.0)
    for lift in (cp.Valve(0.0), cp.Valve(-0.5), cp.ValveSeries(t=[0, 2], u=[0, -1])):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            tr = cp.predict(c, initial, cp.Inputs(lift=lift, tilt=cp.Valve(0.0)), 0.5)
        assert tr.supply_short == ()
    lever = cp.ValveSeries(t=[0, 1, 2], u=[0, 0, 0.3])       # up only later: flagged
    with pytest.warns(UserWarning, match=r"Inputs\.lift"):
        tr = cp.predict(c, initial, cp.Inputs(lift=lever, tilt=cp.Valve(0.0)), 2.0)
    assert tr.supply_short == ("lift",)


def test_pressure_drives_have_no_supply_to_fall_short_of(crane):
    heavy = crane.with_load(350.0)
    tr = cp.predict(heavy, cp.State(0.116, 0.20), cp.Inputs(lift=cp.Pressure(60e5)), 0.1)
    assert tr.supply_short == ()


# -- cranepredict guard: the exit status is the verdict ---------------------------------------------

@pytest.mark.parametrize("world, scenario, signal", [("wall", "paper-fig4", "GO"),
                                                     ("power-line", "paper-fig4", "WARN"),
                                                     ("building-edge", "paper-fig4", "STOP")])
@pytest.mark.parametrize("json_out", [False, True])
def test_guard_exit_status_by_verdict(capsys, world, scenario, signal, json_out):
    argv = ["guard", "--world", world, "--scenario", scenario] + (["--json"] if json_out else [])
    status = cli.main(argv)
    out = capsys.readouterr().out
    if json_out:
        assert json.loads(out)["signal"] == signal
    else:
        assert f"signal     {signal}:" in out
    assert status == {"GO": 0, "WARN": 3, "STOP": 4}[signal]
    assert status == cli.GUARD_EXIT[signal]


def test_guard_exit_status_is_in_its_help(capsys):
    with pytest.raises(SystemExit):
        cli.main(["guard", "--help"])
    assert "exit status: 0 GO, 3 WARN, 4 STOP, 2 bad input" in capsys.readouterr().out


# -- building a Crane --------------------------------------------------------------------------------

def test_crane_construction_resolves_no_type_hints(crane, monkeypatch):
    """A Crane is checked on every construction (with_load, dataclasses.replace): the checks must
    not resolve type hints each time (typing.get_type_hints cost about 20 ms a crane). The time
    itself is a benchmark (benchmarks/test_bench_speed.py)."""
    calls = []
    real = typing.get_type_hints
    monkeypatch.setattr(typing, "get_type_hints", lambda *a, **k: calls.append(a) or real(*a, **k))
    c = crane.with_load(123.0)
    c = dataclasses.replace(c, gravity=9.0)
    assert c.load_mass == 123.0 and calls == []
    with pytest.raises(TypeError, match="lift_cylinder.bore must be a number"):
        dataclasses.replace(crane, lift_cylinder=dataclasses.replace(crane.lift_cylinder, bore="x"))
