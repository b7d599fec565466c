"""The live twin in the loop against the simulated crane (a perturbed plant, not the twin's own
model): the estimator against the known truth, the fail-safe under injected faults, and the
interlock closing the loop (obeyed: no collision; ignored: collision)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict.live import default_sensors, levers
from cranepredict.live.bus import MeasurementAssembler, SensorFrames
from cranepredict.live.episode import demo_setup, run_episode
from cranepredict.live.estimator import EKF, chi2_quantile
from cranepredict.live.sim import LeverScript, Plant, SensorModel, SimCrane, perturbed_crane

SCRIPT = LeverScript(((0.0, (0.0, 0.0, 0.0, 0.0)), (0.3, (0.6, 0.0, 0.0, 0.0)),
                      (1.2, (0.6, 0.5, 0.3, 0.0)), (2.4, (-0.4, 0.5, 0.0, 0.6))))


@pytest.fixture(scope="module")
def world():
    return cp.worlds.get("wall")


def _sim(crane, seed=3, sensors=None, load=1.3, friction=1.0, supply=1.0):
    truth = perturbed_crane(crane, load=load, friction=friction, supply=supply)
    start = cp.state_at_rest(truth, 0.25, 0.35, extension=0.3)
    return SimCrane(Plant(truth, start), SCRIPT, SensorModel(sensors or default_sensors(), seed=seed))


def test_chi2_quantile_matches_known_values():
    # tabulated: chi2(0.99, 10) = 23.209, chi2(0.999, 100) = 149.449
    assert chi2_quantile(0.99, 10) == pytest.approx(23.209, rel=0.01)
    assert chi2_quantile(0.999, 100) == pytest.approx(149.449, rel=0.005)


def test_the_estimator_recovers_the_unmeasured_rates_and_filters_the_pressures(crane):
    """Load 30 % off the crane file's, strokes 0.2 mm and pressures 2 bar of noise at 100 Hz:
    the stroke rates (not measured) within 5 mm/s RMS, the pressures within 1.5 bar RMS and
    better than the raw sensor."""
    sim = _sim(crane)
    ekf = EKF(crane, default_sensors())
    err = {n: [] for n in ("lift_stroke_rate", "tilt_stroke_rate", "lift_p_a", "lift_p_b",
                           "tilt_p_a", "tilt_p_b")}
    raw = {n: [] for n in err if "_p_" in n}
    for k in range(360):
        m = sim.measurement()
        est = ekf.update(m)
        if m.t >= 0.5:
            for n in err:
                err[n].append(getattr(est, n) - getattr(sim.plant.state, n))
            for n in raw:
                raw[n].append(getattr(m, n) - getattr(sim.plant.state, n))
        sim.step(allowed=True)
    rms = {n: math.sqrt(np.mean(np.square(v))) for n, v in err.items()}
    moving = max(abs(s.lift_stroke_rate) for _, s, _, _ in sim.history)
    assert moving > 0.03                         # the crane moved: the rates had to be found
    for n in ("lift_stroke_rate", "tilt_stroke_rate"):
        assert rms[n] <= 5e-3, (n, rms[n])
    for n in raw:
        raw_rms = math.sqrt(np.mean(np.square(raw[n])))
        assert rms[n] <= 1.5e5 and rms[n] < raw_rms, (n, rms[n], raw_rms)
    # the covariance stays symmetric positive definite
    P = ekf.covariance
    assert np.array_equal(P, P.T)
    np.linalg.cholesky(ekf.scaled_covariance())              # raises unless positive definite


def test_the_estimator_refuses_what_it_cannot_work_with(crane):
    with pytest.raises(ValueError, match="must measure every joint's position.*'extension'"):
        EKF(crane, default_sensors().without("extension"))
    ekf = EKF(crane)
    m = cp.Measurement(t=0.0, inputs=levers(), lift_stroke=0.2, tilt_stroke=0.3, slew=0.0)
    with pytest.raises(ValueError, match=r"first measurement must hold every joint's position, missing \['extension'\]"):
        ekf.update(m)
    ekf.update(cp.Measurement(t=0.0, inputs=levers(), lift_stroke=0.2, tilt_stroke=0.3, slew=0.0,
                              extension=0.1))
    with pytest.raises(ValueError, match="Measurement.t must increase"):
        ekf.update(cp.Measurement(t=0.0, inputs=levers(), lift_stroke=0.2))


def _first(verdicts, signal, after=-1.0):
    return next((v.t for v in verdicts if v.signal == signal and v.t > after), None)


def _run(crane, world, inject, seconds=1.2, sensors=None):
    sensors = sensors or default_sensors()
    start = cp.state_at_rest(perturbed_crane(crane), 0.25, 0.35, extension=0.3)
    return run_episode(crane, world, start, SCRIPT, seconds, sensors=sensors, inject=inject,
                       horizon=1.0)


def test_a_sensor_that_stops_reporting_faults_within_its_max_age(crane, world):
    def drop(k, sim):
        if k == 60:
            sim.sensor_model.sensors = sim.sensor_model.sensors.without("tilt_p_b")
    ep = _run(crane, world, drop)
    v = ep.verdicts
    assert v[59].signal in ("GO", "WARN")
    t_fault = _first(v, "FAULT", after=0.6)
    max_age = default_sensors()["tilt_p_b"].max_age
    assert t_fault is not None and t_fault - 0.59 <= max_age + 0.01 + 1e-9
    assert all(x.signal == "FAULT" for x in v if x.t >= t_fault)   # never a GO while stale
    assert "tilt_p_b" in next(x for x in v if x.t == t_fault).reason


@pytest.mark.parametrize("field, value, kind", [("lift_p_a", 400e5, "out of range"),
                                               ("tilt_stroke", 0.95, "out of range")])
def test_an_out_of_range_sensor_faults_at_once(crane, world, field, value, kind):
    def bad(k, sim):
        if k == 50:
            sim.sensor_model.stuck[field] = value
    ep = _run(crane, world, bad, seconds=0.6)
    v = ep.verdicts
    assert v[49].signal != "FAULT" and v[50].signal == "FAULT" and v[50].fault == kind
    assert field in v[50].reason


def test_a_stuck_sensor_fails_the_innovation_test(crane, world):
    def stuck(k, sim):
        if k == 40:          # the lift stroke freezes while the lift boom moves
            sim.sensor_model.stuck["lift_stroke"] = round(sim.plant.state.lift_stroke, 4)
    ep = _run(crane, world, stuck, seconds=1.5)
    faults = [x for x in ep.verdicts if x.signal == "FAULT" and x.t > 0.4]
    assert faults and faults[0].fault == "innovation"
    assert faults[0].t - 0.4 <= 1.0          # a slowly moving stroke: about 0.9 s
    clean = _run(crane, world, None, seconds=1.5)           # the same run without the fault
    assert not any(x.signal == "FAULT" for x in clean.verdicts if x.t > 0.1)


def _bus_episode(crane, world, fault, cycles=80):
    """The loop through the DBC frames: the crane's frames encoded and decoded each cycle."""
    sim = _sim(crane)
    twin = cp.LiveTwin(crane, world, horizon=1.0)
    frames, asm, out = SensorFrames(), MeasurementAssembler(), []
    for k in range(cycles):
        values, request, scale = sim.measure()
        msgs = frames.messages(values, request, scale, timestamp=sim.plant.t,
                               frozen=fault(k)[0])
        for msg in msgs:
            if msg.arbitration_id not in fault(k)[1]:
                got = asm.feed(msg)
        m, faults = got if got is not None else (None, ["levers: not available"])
        v = twin.cycle(m, faults) if m is not None else twin.fault(sim.plant.t, "levers stale", faults[0])
        out.append(v)
        sim.step(allowed=not v.stops)
    return out


def test_dropped_and_frozen_frames_fault_within_the_max_age(crane, world):
    codec = MeasurementAssembler().codec
    lift = codec.frame_id("LiftCylinder")
    ok = _bus_episode(crane, world, lambda k: ((), ()))
    assert [v.signal for v in ok[15:]].count("FAULT") == 0
    dropped = _bus_episode(crane, world, lambda k: ((), (lift,) if k >= 40 else ()))
    frozen = _bus_episode(crane, world, lambda k: (("LiftCylinder",) if k >= 40 else (), ()))
    for run in (dropped, frozen):
        assert run[39].signal != "FAULT"
        first = next(k for k, v in enumerate(run) if k >= 40 and v.signal == "FAULT")
        assert (first - 39) * 0.01 <= default_sensors()["lift_stroke"].max_age + 0.01 + 1e-9
        assert all(v.signal == "FAULT" for v in run[first:])
    levers_lost = _bus_episode(crane, world, lambda k: ((), (codec.frame_id("Levers"),) if k == 50 else ()))
    assert levers_lost[50].signal == "FAULT" and levers_lost[50].fault == "levers stale"


def test_the_interlock_obeyed_prevents_the_collision_that_ignoring_it_lets_happen(crane):
    start, script, name = demo_setup(crane)
    world = cp.worlds.get(name)
    ignored = run_episode(crane, world, start, script, 6.0, obey=False)
    assert ignored.collided and "wall" in ignored.contact
    obeyed = run_episode(crane, world, start, script, 6.0, obey=True)
    assert not obeyed.collided and obeyed.first_stop is not None
    assert obeyed.counts["STOP"] > 0


def test_each_cycle_starts_the_stop_search_at_the_last_verdict_with_the_same_verdicts(
        crane, monkeypatch):
    """The loop hands the guard its last latest stop time (moved by the time since) as the
    search's start: over the demo's WARN and STOP cycles every verdict, signal and latest stop
    time, is the one the guard finds without it."""
    from cranepredict.live import loop

    start, script, name = demo_setup(crane)
    world = cp.worlds.get(name)
    runs, plain = {}, loop.guard
    for hinted in (True, False):
        seen = []

        def guard(*a, **k):
            seen.append(k.get("stop_hint"))
            if not hinted:
                k["stop_hint"] = None
            return plain(*a, **k)

        monkeypatch.setattr(loop, "guard", guard)
        sim = SimCrane(Plant(perturbed_crane(crane), start), script, SensorModel(seed=1))
        twin, asm, verdicts = cp.LiveTwin(crane, world), MeasurementAssembler(), []
        frames = SensorFrames()
        for _ in range(300):
            values, request, scale = sim.measure()
            m, faults = None, []
            for msg in frames.messages(values, request, scale, timestamp=sim.plant.t):
                m, faults = asm.feed(msg) or (m, faults)
            v = twin.cycle(m, faults)
            verdicts.append((v.signal, v.latest_stop))
            sim.step(allowed=not v.stops)
        runs[hinted] = verdicts, seen
    assert runs[True][0] == runs[False][0]
    signals = [s for s, _ in runs[True][0]]
    assert "WARN" in signals and "STOP" in signals
    assert sum(h is not None for h in runs[True][1]) > 20     # the hint was used


def test_a_first_position_read_just_beyond_its_end_starts_at_the_end(crane):
    """Noise at an end stop: the telescope retracted reads -0.7 mm; the estimate starts at 0."""
    ekf = EKF(crane)
    s = ekf.update(cp.Measurement(t=0.0, inputs=levers(), lift_stroke=0.2, tilt_stroke=0.3,
                                  slew=0.0, extension=-7e-4))
    assert s.extension == crane.geometry.extension_min and ekf.projections == 1
    s = ekf.update(cp.Measurement(t=0.01, inputs=levers(), lift_stroke=0.2, tilt_stroke=0.3,
                                  slew=0.0, extension=-7e-4))
    assert s.extension >= crane.geometry.extension_min


def test_a_pause_of_the_levers_faults_without_restarting_the_estimator(crane, world):
    sim = _sim(crane)
    twin = cp.LiveTwin(crane, world, horizon=1.0)
    for _ in range(15):
        v = twin.cycle(sim.measurement())
        sim.step(allowed=not v.stops)
    assert v.signal == "GO"
    pause = twin.no_levers(sim.plant.t, "no lever frame for 0.06 s")
    assert pause.signal == "FAULT" and pause.fault == "levers stale"
    assert twin.cycle(sim.measurement()).signal == "GO"          # fresh data: judged at once
    # levers again 40 ms later, but no sensor sample since: stale
    late = twin.cycle(cp.Measurement(t=sim.plant.t + 0.04, inputs=levers()))
    assert late.signal == "FAULT" and late.fault == "stale"
