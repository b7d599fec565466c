"""The C core's four-joint model (docs/model.md, "Four joints"): its inverse dynamics against the
independent Lagrange oracle (tests/lagrange4.py) and the twin, its predictions against the twin's
four-joint path (twin._run) with end stops on all four joints, energy along its trajectories, and
its checks of the slew and extension drives.

The core is called through the binding's struct conversion (so that the tests reach states and
drives the API would refuse), with plain namespaces or the API's State and Inputs.
"""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core, twin
from cranepredict._cranepredict import ffi, lib
from lagrange4 import Lagrange4

ZERO = cp.Pressure(0.0, 0.0)
HOLD = cp.Hold()


def _namespaces(lift=0.25, tilt=0.4, slew=0.0, extension=0.5, rates=(0, 0, 0, 0), drives=None):
    d = drives or {}
    state = SimpleNamespace(lift_stroke=lift, tilt_stroke=tilt, slew=slew, extension=extension,
                            lift_stroke_rate=rates[0], tilt_stroke_rate=rates[1],
                            slew_rate=rates[2], extension_rate=rates[3])
    inputs = SimpleNamespace(lift=d.get("lift", ZERO), tilt=d.get("tilt", ZERO),
                             slew=d.get("slew", ZERO), extension=d.get("extension", ZERO))
    return state, inputs


def core_run(crane, state, inputs, horizon, dt, method="auto"):
    """(status, samples) of crane_predict for a namespace state and inputs (with the method)."""
    prm = _core.params(crane)
    s = ffi.new("crane_state *")
    _core._state(s, state)
    inp = ffi.new("crane_inputs *")
    keep: list = []
    _core._inputs(inp, inputs, keep)
    _core.solver(inp, method, None)
    n = _core.sample_count(horizon, dt)
    out = np.empty(n, dtype=_core.SAMPLE_DTYPE)
    written = ffi.new("size_t *")
    st = lib.crane_predict(prm, s, inp, horizon, dt,
                                 ffi.cast("crane_sample *", ffi.from_buffer(out)), n, written,
                           _core.work())
    return st, out[: written[0]]


def _id4(crane, q, qd, qdd):
    tau = ffi.new("crane_real[4]")
    st = lib.crane_inverse_dynamics(_core.model(crane, crane.geometry.extension_min), list(q),
                                     list(qd), list(qdd), tau)
    assert st == lib.CRANE_OK, st
    return np.array(list(tau))


def _random_states(n, seed, crane):
    rng = np.random.default_rng(seed)
    g = crane.geometry
    for _ in range(n):
        q = np.array([rng.uniform(-0.2, 1.4), rng.uniform(-3.0, -0.1), rng.uniform(-3, 3),
                      rng.uniform(g.extension_min, g.extension_max)])
        yield q, rng.uniform(-2, 2, 4), rng.uniform(-5, 5, 4), rng.uniform(0, 500)


# -- inverse dynamics --------------------------------------------------------------------------

def test_core_inverse_dynamics_equals_lagrange_and_the_twin(crane):
    """crane_inverse_dynamics against the oracle (to 1e-9 of the largest force; the extension
    force on its own scale) and against the twin's inverse_dynamics4 (to 1e-12), 60 random
    states, loads and extensions."""
    worst_oracle = worst_twin = worst_e = 0.0
    for q, qd, qdd, load in _random_states(60, 17, crane):
        c = crane.with_load(load)
        tau = _id4(c, q, qd, qdd)
        ref = Lagrange4(c).torques(q, qd, qdd)
        tw = np.array(twin.TwinModel(c, 0.0).inverse_dynamics4(tuple(q), tuple(qd), tuple(qdd)))
        worst_oracle = max(worst_oracle, float(np.max(np.abs(tau - ref)) / np.max(np.abs(ref))))
        worst_twin = max(worst_twin, float(np.max(np.abs(tau - tw)) / np.max(np.abs(tw))))
        worst_e = max(worst_e, abs(tau[3] - ref[3]) / max(abs(ref[3]), 1.0))
    assert worst_oracle < 1e-9, worst_oracle
    assert worst_e < 1e-9, worst_e
    assert worst_twin < 1e-12, worst_twin


def test_core_inverse_dynamics_sees_the_slew_terms(crane):
    """The test above can fail: without the pillar's inertia, or with the slew rate's centrifugal
    load dropped (omega_s = 0 in the core, not in the oracle), the core is far off the oracle."""
    q, qd, qdd = (0.3, -1.0, 0.5, 0.6), (0.5, -0.7, 0.8, 0.3), (1.0, 2.0, -1.5, 0.7)
    ref = Lagrange4(crane).torques(q, qd, qdd)
    no_pillar = dataclasses.replace(crane, pillar=None)
    assert abs(_id4(no_pillar, q, qd, qdd)[2] - ref[2]) > 1e-6 * abs(ref[2])
    still = _id4(crane, q, (0.5, -0.7, 0.0, 0.3), qdd)
    assert np.max(np.abs(still[[0, 1, 3]] - ref[[0, 1, 3]])) > 1e-3


def test_core_slew_equation_for_a_held_boom(crane):
    """Hand check: with every rate 0 and only a slew acceleration, tau = (0 + gravity, J_z
    alpha_s, ...) where J_z is summed body by body by the oracle's mass matrix."""
    q = np.array([0.4, -1.2, 0.0, 0.7])
    tau = _id4(crane, q, (0, 0, 0, 0), (0, 0, 2.5, 0))
    grav = _id4(crane, q, (0, 0, 0, 0), (0, 0, 0, 0))
    j_z = Lagrange4(crane).mass_matrix(q)[2, 2]
    assert abs(tau[2] - 2.5 * j_z) < 1e-9 * 2.5 * j_z
    assert np.max(np.abs((tau - grav)[[0, 1, 3]])) < 1e-9 * abs(tau[2])
    assert grav[2] == 0.0


def test_core_inverse_dynamics_checks_its_arguments(crane):
    m = _core.model(crane, 0.0)
    tau = ffi.new("crane_real[4]")
    z = [0.0, 0.0, 0.0, 0.0]
    assert lib.crane_inverse_dynamics(m, [0.3, -1.0, 0.0, 2.0], z, z, tau) == lib.CRANE_E_EXTENSION
    assert lib.crane_inverse_dynamics(m, [9.0, -1.0, 0.0, 0.5], z, z, tau) == lib.CRANE_E_ANGLE
    assert lib.crane_inverse_dynamics(m, [0.3, -1.0, float("nan"), 0.5], z, z, tau) == \
        lib.CRANE_E_NONFINITE
    assert lib.crane_inverse_dynamics(ffi.NULL, z, z, z, tau) == lib.CRANE_E_NULL


# -- predictions against the twin ---------------------------------------------------------------

def _compare(crane, state, inputs, horizon, dt):
    """Worst differences C - twin: tip (m), slew (rad), extension (m), strokes (m), and the
    twin's impacts; the stop flags must agree."""
    st, out = core_run(crane, state, inputs, horizon, dt)
    assert st == lib.CRANE_OK, st
    tw, events = twin._run(crane, state, inputs, horizon, dt)
    assert len(out) == len(tw["t"])
    np.testing.assert_array_equal(out["t"], tw["t"])
    np.testing.assert_array_equal(out["stop"], tw["stop"])   # [lift, tilt, slew, extension]
    return (float(np.max(np.abs(out["tip"] - tw["tip"]))),
            float(np.max(np.abs(out["slew"] - tw["slew"]))),
            float(np.max(np.abs(out["extension"] - tw["extension"]))),
            float(np.max(np.abs(out["stroke"] - tw["strokes"]))),
            events)


@pytest.mark.parametrize("seed", range(8))
def test_core_four_joints_match_the_twin(crane, seed):
    """Random four-joint futures (every joint driven by random constant pressures or held, random
    strokes, rates, loads, 2 s at 2 ms, end stops included): the C core's tip within 1e-9 m of the
    twin's, slew and extension likewise, identical stop flags."""
    rng = np.random.default_rng(1000 + seed)
    c = crane.with_load(float(rng.uniform(0, 500)))
    sd = c.slew_drive

    def drive(scale):
        if rng.uniform() < 0.2:
            return HOLD
        return cp.Pressure(float(rng.uniform(0, scale)), float(rng.uniform(0, scale)))

    drives = {"lift": drive(160e5), "tilt": drive(120e5), "slew": drive(60e5),
              "extension": drive(40e5)}
    if drives["slew"] is HOLD and drives["extension"] is HOLD:
        drives["extension"] = cp.Pressure(30e5, 5e5)

    def rate(name, scale):
        return 0.0 if drives[name] is HOLD else float(rng.uniform(-scale, scale))

    state, inputs = _namespaces(
        lift=float(rng.uniform(0.02, 0.5)), tilt=float(rng.uniform(0.05, 0.7)),
        slew=float(rng.uniform(sd.slew_min, sd.slew_max)),
        extension=float(rng.uniform(0.0, 1.0)),
        rates=(rate("lift", 0.05), rate("tilt", 0.05), rate("slew", 0.5), rate("extension", 0.1)),
        drives=drives)
    tip, slew, ext, stroke, events = _compare(c, state, inputs, 2.0, 2e-3)
    assert tip < 1e-9 and slew < 1e-9 and ext < 1e-9 and stroke < 1e-9, (tip, slew, ext, stroke, events)


def test_core_extension_and_slew_end_stops_match_the_twin(crane):
    """The telescope into its end stop (and held there), the slew into its stop and back out
    under a reversed pressure sample, lift and tilt stopped at a limit meanwhile."""
    sd = crane.slew_drive
    state, inputs = _namespaces(extension=0.2, drives={
        "lift": HOLD, "tilt": HOLD, "slew": HOLD, "extension": cp.Pressure(50e5, 0.0)})
    tip, slew, ext, _, events = _compare(crane, state, inputs, 2.0, 2e-3)
    assert [e[1] for e in events] == [3] and tip < 1e-9 and ext < 1e-12
    reverse = cp.PressureSeries(t=[0.0, 0.6, 0.7, 1.5], p_a=[40e5, 40e5, 0.0, 0.0],
                                p_b=[0.0, 0.0, 40e5, 40e5])
    state, inputs = _namespaces(lift=0.0, tilt=0.75, slew=sd.slew_max - 0.2, extension=0.0, drives={
        "lift": cp.Pressure(0.0, 50e5), "tilt": HOLD, "slew": reverse, "extension": cp.Pressure(0.0, 10e5)})
    tip, slew, ext, _, events = _compare(crane, state, inputs, 1.5, 2e-3)
    assert {e[1] for e in events} >= {0, 2}, events
    assert tip < 1e-9 and slew < 1e-9 and ext < 1e-9, (tip, slew, ext)


def test_core_four_joints_keep_the_twins_valve_driven_booms(crane):
    """Lift and tilt valve-driven (oil model) while the slew and the extension move under
    pressure: the four-joint path's hydraulic state against the twin's."""
    st0 = cp.state_at_rest(crane, 0.25, 0.4, extension=0.5)
    state = SimpleNamespace(**{k: getattr(st0, k) for k in (
        "lift_stroke", "tilt_stroke", "lift_stroke_rate", "tilt_stroke_rate", "lift_p_a",
        "lift_p_b", "tilt_p_a", "tilt_p_b", "lift_spool", "tilt_spool")},
        slew=0.0, extension=0.5, slew_rate=0.0, extension_rate=0.0)
    inputs = SimpleNamespace(lift=cp.Valve(0.6), tilt=cp.Valve(-0.3), slew=cp.Pressure(40e5, 0.0),
                             extension=cp.Pressure(25e5, 0.0))
    tip, slew, ext, _, _ = _compare(crane, state, inputs, 1.0, 2e-3)
    assert tip < 1e-9 and slew < 1e-9 and ext < 1e-9, (tip, slew, ext)
    st, out = core_run(crane, state, inputs, 1.0, 2e-3)
    tw, _ = twin._run(crane, state, inputs, 1.0, 2e-3)
    assert float(np.max(np.abs(out["p_a"] - tw["p_a"]))) < 1e-3


def test_core_four_joints_conserve_energy_without_friction_and_gravity(crane):
    """All four joints move from initial rates (0 Pa, no friction, no gravity): the oracle's
    kinetic energy along the C core's trajectory is conserved (RK4 at 1 ms: the twin's 4e-15)."""
    from test_four_joints import _frictionless4

    c = _frictionless4(crane, gravity=0.0)
    state, inputs = _namespaces(rates=(0.05, -0.08, 0.4, 0.05))
    st, out = core_run(c, state, inputs, 1.0, 1e-3, "rk4")
    assert st == lib.CRANE_OK and not out["stop"].any()
    q = np.column_stack([out["theta"], out["slew"], out["extension"]])
    qd = np.column_stack([out["omega"], out["slew_rate"], out["extension_rate"]])
    assert np.ptp(q[:, 2]) > 0.2 and np.ptp(q[:, 3]) > 0.03
    lag = Lagrange4(c)
    e = np.array([lag.kinetic(a, b) for a, b in zip(q[::20], qd[::20])])
    assert e[0] > 10.0
    assert float(np.max(np.abs(e - e[0])) / e[0]) < 1e-9


def test_core_planar_path_unchanged_with_slew_and_extension_held(crane):
    """Slew and extension held: the samples are the planar model's (the same as a call that
    leaves them out), the slew and the extension constant in the samples."""
    state, inputs = _namespaces(slew=0.7, extension=0.3, drives={
        "lift": cp.Pressure(80e5, 0.0), "tilt": cp.Pressure(0.0, 30e5), "slew": HOLD,
        "extension": HOLD})
    st, out = core_run(crane, state, inputs, 1.0, 2e-3)
    planar = cp.predict(crane, cp.State(lift_stroke=0.25, tilt_stroke=0.4, slew=0.7, extension=0.3),
                        cp.Inputs(lift=cp.Pressure(80e5, 0.0), tilt=cp.Pressure(0.0, 30e5)), 1.0,
                        dt=2e-3)
    assert st == lib.CRANE_OK
    np.testing.assert_array_equal(out["tip"], planar.tip)
    assert (out["slew"] == 0.7).all() and (out["extension"] == 0.3).all()
    assert (out["slew_rate"] == 0).all() and (out["extension_rate"] == 0).all()


# -- bad input --------------------------------------------------------------------------------

def test_core_refuses_bad_slew_and_extension_drives(crane):
    sd = crane.slew_drive
    drives = {"lift": HOLD, "tilt": HOLD, "slew": cp.Pressure(10e5, 0.0), "extension": HOLD}

    def status(c=crane, **kw):
        args = dict(drives=drives)
        args.update(kw)
        return core_run(c, *_namespaces(**args), 0.1, 0.01)[0]

    assert status() == lib.CRANE_OK
    assert status(slew=sd.slew_max + 0.01) == lib.CRANE_E_ANGLE
    assert status(c=dataclasses.replace(crane, slew_drive=None)) == lib.CRANE_E_ACTUATOR
    assert status(c=dataclasses.replace(crane, extension_cylinder=None), drives={
        **drives, "extension": cp.Pressure(1e5, 0.0)}) == lib.CRANE_E_ACTUATOR
    assert status(rates=(0, 0, 0, 0.1)) == lib.CRANE_E_STROKE_RATE   # a held extension moving
    assert status(drives={**drives, "slew": SimpleNamespace(held=False, p_a=-1.0, p_b=0.0, t=None)}) \
        == lib.CRANE_E_PRESSURE
    assert status(drives={**drives, "slew": SimpleNamespace(held=False, p_a=0.0, p_b=0.0, t=None)}) \
        == lib.CRANE_OK
    assert status(extension=1.5) == lib.CRANE_E_EXTENSION
    assert status(rates=(0, 0, float("inf"), 0)) == lib.CRANE_E_NONFINITE


def test_core_checks_the_valves_of_the_slew_and_the_extension(crane):
    """A valve on the slew drive or the extension cylinder: accepted with a circuit, refused
    (CRANE_E_VALVE) without one, with a lever or spool beyond [-1, 1] or a chamber pressure out of
    range; a non-finite chamber pressure is CRANE_E_NONFINITE; nothing is written then."""
    base = {"lift": HOLD, "tilt": HOLD, "slew": HOLD, "extension": HOLD}

    def status(joint, drive, c=crane, **state):
        st, inputs = _namespaces(drives={**base, joint: drive})
        for k, v in state.items():
            setattr(st, k, v)
        return core_run(c, st, inputs, 0.1, 0.01)

    for joint, actuator in (("slew", "slew_drive"), ("extension", "extension_cylinder")):
        st, out = status(joint, cp.Valve(0.5), **{f"{joint}_p_a": 1e5, f"{joint}_p_b": 1e5})
        assert st == lib.CRANE_OK and len(out) == 11
        assert np.ptp(out[joint]) > 0   # the valve moves it
        no_circuit = dataclasses.replace(
            crane, **{actuator: dataclasses.replace(getattr(crane, actuator), hydraulics=None)})
        assert status(joint, cp.Valve(0.5), c=no_circuit)[0] == lib.CRANE_E_VALVE
        assert status(joint, SimpleNamespace(held=False, u=1.5, t=None))[0] == lib.CRANE_E_VALVE
        assert status(joint, cp.Valve(0.5), **{f"{joint}_spool": 1.5})[0] == lib.CRANE_E_VALVE
        assert status(joint, cp.Valve(0.5), **{f"{joint}_p_a": 2e9})[0] == lib.CRANE_E_VALVE
        assert status(joint, cp.Valve(0.5), **{f"{joint}_p_b": float("nan")})[0] \
            == lib.CRANE_E_NONFINITE
        assert status(joint, SimpleNamespace(held=False, u=[0.0, 1.0], t=[0.0, 0.05]))[0] \
            == lib.CRANE_E_SAMPLES   # the lever's samples do not cover the horizon
        st, out = status(joint, cp.Valve(0.5), **{f"{joint}_p_a": -1e9})
        assert st == lib.CRANE_E_VALVE and len(out) == 0


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(6))
def test_core_valve_driven_four_joints_match_the_twin(crane, seed):
    """Random valve-driven futures of all four joints (constant and sampled levers, the crane at
    rest or moving, loads 0-500 kg, 2 s at the default 2 ms; the slew and the telescope run into
    their stops in some): the C core's tip within 1e-9 m and chamber pressures within 1e-3 Pa of
    the twin's, identical stop flags."""
    rng = np.random.default_rng(2000 + seed)
    c = crane.with_load(float(rng.uniform(0, 500)))
    sd, g = c.slew_drive, c.geometry

    def lever():
        if rng.uniform() < 0.5:
            return cp.Valve(float(rng.uniform(-1, 1)))
        return cp.ValveSeries(t=[0.0, float(rng.uniform(0.2, 1.8)), 2.0],
                              u=[float(x) for x in rng.uniform(-1, 1, 3)])

    rest = cp.state_at_rest(c, float(rng.uniform(0.03, 0.5)), float(rng.uniform(0.05, 0.7)),
                            slew=float(rng.uniform(sd.slew_min + 0.1, sd.slew_max - 0.1)),
                            extension=float(rng.uniform(g.extension_min, g.extension_max)))
    state = dataclasses.replace(rest, slew_rate=float(rng.uniform(-0.3, 0.3)),
                                extension_rate=float(rng.uniform(-0.05, 0.05)))
    inputs = cp.Inputs(lift=lever(), tilt=lever(), slew=lever(), extension=lever())
    tip, slew, ext, stroke, events = _compare(c, state, inputs, 2.0, cp.DEFAULT_DT)
    assert tip < 1e-9 and slew < 1e-9 and ext < 1e-9 and stroke < 1e-9, (tip, slew, ext, stroke)
    st, out = core_run(c, state, inputs, 2.0, cp.DEFAULT_DT)
    tw, _ = twin._run(c, state, inputs, 2.0, cp.DEFAULT_DT)
    for side in ("p_a", "p_b"):
        assert float(np.max(np.abs(out[side] - tw[side]))) < 1e-3, side
    assert np.ptp(out["p_a"][:, 2]) > 1e4 or np.ptp(out["p_b"][:, 2]) > 1e4  # the slew's oil works



def test_core_counts_the_extension_substeps_against_max_steps(crane):
    """A moving extension may cut every step into friction substeps (docs/model.md, "Four
    joints"): their bound counts against MAX_STEPS, as the valves' do (60 s at 2 ms: 30,000 steps
    of up to ~50 substeps each is over 2^20; the same with the extension held is not)."""
    state, inputs = _namespaces(drives={"lift": HOLD, "tilt": HOLD, "slew": HOLD,
                                        "extension": cp.Pressure(10e5, 0.0)})
    assert core_run(crane, state, inputs, 60.0, 2e-3, "rk4")[0] == lib.CRANE_E_STEPS
    state, inputs = _namespaces(drives={"lift": HOLD, "tilt": HOLD, "slew": cp.Pressure(10e5, 0.0),
                                        "extension": HOLD})
    assert core_run(crane, state, inputs, 60.0, 2e-3, "rk4")[0] == lib.CRANE_OK
