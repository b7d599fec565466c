"""The four-joint API: State, Inputs and Trajectory carry the slew and the extension,
bad input is named, lift-and-tilt code keeps its meaning, the trajectory's 3D points follow each
sample's slew and extension, the slew drive's and the telescope's valves obey their hand
calculations, and the named spatial scenarios do what they say."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core

HORIZON = 0.4
DT = 2e-3
H = cp.Hold()


def _rest(crane, **kw):
    return cp.state_at_rest(crane, 0.20, 0.05, **kw)


def _spatial(crane):
    """A short valve-driven future moving all four joints (the twin)."""
    initial = _rest(crane, slew=0.3, extension=0.5)
    inputs = cp.Inputs(lift=cp.Valve(0.5), tilt=cp.Valve(-0.3), slew=cp.Valve(0.8),
                       extension=cp.ValveSeries(t=[0.0, 0.2, 0.4], u=[1.0, 1.0, -1.0]))
    return initial, inputs


# -- the contract's shapes ----------------------------------------------------------------------

def test_trajectory_carries_the_four_joints_per_sample(crane):
    initial, inputs = _spatial(crane)
    tr = cp.predict(crane, initial, inputs, HORIZON, dt=DT, backend="python")
    n = int(round(HORIZON / DT)) + 1
    assert tr.t.shape == (n,)
    for name in ("strokes", "theta", "omega"):
        assert getattr(tr, name).shape == (n, 2), name
    for name in ("slew", "extension", "slew_rate", "extension_rate"):
        assert getattr(tr, name).shape == (n,), name
    for name in ("stop", "p_a", "p_b", "flow_a", "flow_b", "spool"):
        assert getattr(tr, name).shape == (n, 4), name
    assert tr.tip.shape == (n, 3)
    # every joint moved, and the rates are those of the coordinates (central differences)
    assert np.ptp(tr.slew) > 0.005 and np.ptp(tr.extension) > 0.01 and np.ptp(tr.theta[:, 0]) > 1e-3
    for q, qd in ((tr.slew, tr.slew_rate), (tr.extension, tr.extension_rate)):
        fd = (q[2:] - q[:-2]) / (2 * DT)
        assert np.max(np.abs(fd - qd[1:-1])) < 0.02 * np.max(np.abs(qd)) + 1e-6
    # the slew's and the extension's valve columns are filled, their stops not reached
    assert tr.spool[-1, 2] == pytest.approx(0.8, abs=1e-3) and tr.flow_a[-1, 2] > 0.0
    assert tr.spool[-1, 3] < 0.0 and not tr.stop.any()
    with pytest.raises(ValueError):
        tr.slew[0] = 1.0   # read-only like every array


def test_batch_carries_the_four_joints(crane):
    initials = [cp.State(0.1, 0.3, slew=s, extension=e) for s, e in ((0.0, 0.0), (1.0, 0.7), (-2.0, 1.0))]
    inputs = [cp.Inputs(lift=cp.Pressure(p, 0.0), tilt=H) for p in (60e5, 90e5, 120e5)]
    batch = cp.predict_many(crane, initials, inputs, HORIZON, dt=DT)
    n = int(round(HORIZON / DT)) + 1
    assert batch.slew.shape == (3, n) and batch.extension_rate.shape == (3, n)
    assert batch.stop.shape == (3, n, 4) and batch.p_a.shape == (3, n, 4)
    for k, x in enumerate(initials):
        assert np.all(batch.slew[k] == x.slew) and np.all(batch.extension[k] == x.extension)
        one = batch[k]
        np.testing.assert_allclose(one.points()["tip"], one.tip, rtol=0, atol=1e-12)


@pytest.mark.parametrize("threads", [1, 2])
def test_batch_of_moving_slews_and_extensions_is_predict_future_by_future(threads):
    """predict_many over the spatial scenarios (valves and pressures on the slew and the
    telescope, end stops) gives exactly predict()'s numbers for each future."""
    names = [n for n in cp.scenarios.names() if cp.scenarios.get(n).spatial]
    scs = [cp.scenarios.get(n) for n in names]
    crane = scs[0].crane
    same = [sc for sc in scs if sc.crane == crane and sc.horizon == scs[0].horizon]
    assert len(same) >= 4, names
    batch = cp.predict_many(crane, [sc.initial for sc in same] * 2, [sc.inputs for sc in same] * 2,
                            same[0].horizon, threads=threads)
    for k, sc in enumerate(same * 2):
        one = cp.predict(crane, sc.initial, sc.inputs, sc.horizon)
        assert np.ptp(one.slew) > 0 or np.ptp(one.extension) > 0, sc.name
        for name in cp.types.ARRAYS:
            assert np.array_equal(getattr(batch[k], name), getattr(one, name)), (sc.name, name)


# -- lift-and-tilt code keeps its meaning -------------------------------------------------------------

@pytest.mark.parametrize("backend", ["c", "python"])
def test_left_out_slew_and_extension_drives_are_holds(crane, backend):
    initial = cp.State(0.15, 0.35, slew=0.7, extension=0.4)
    old = cp.Inputs(lift=cp.Pressure(120e5, 0.0), tilt=cp.Pressure(0.0, 40e5))
    new = cp.Inputs(lift=old.lift, tilt=old.tilt, slew=H, extension=H)
    a = cp.predict(crane, initial, old, 1.0, backend=backend)
    b = cp.predict(crane, initial, new, 1.0, backend=backend)
    for name in cp.types.ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.all(a.slew == 0.7) and np.all(a.extension == 0.4)
    assert np.all(a.slew_rate == 0.0) and np.all(a.extension_rate == 0.0)
    assert not a.stop[:, 2:].any() and not a.p_a[:, 2:].any() and not a.spool[:, 2:].any()


def test_held_four_joint_twin_is_the_c_core(crane):
    """The twin's public path is the four-joint one; with the slew and the extension held it is
    the planar model the C core runs (the C core written independently, to 1e-9 m)."""
    sc = cp.scenarios.get("slewed-extended")
    a = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="c")
    b = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="python")
    assert np.max(np.abs(a.tip - b.tip)) < 1e-9
    assert np.array_equal(a.stop, b.stop)


# -- the 3D tip and points at each sample's slew and extension ------------------------------------------

def test_tip_and_points_follow_each_samples_slew_and_extension(crane):
    """The twin's trajectory against the C core's kinematics (crane_points, an independent
    implementation) evaluated at each sample's theta, slew and extension."""
    initial, inputs = _spatial(crane)
    tr = cp.predict(crane, initial, inputs, HORIZON, dt=DT, backend="python")
    pts = tr.points()
    np.testing.assert_allclose(pts["tip"], tr.tip, rtol=0, atol=1e-12)
    worst = 0.0
    for k in range(0, len(tr.t), 10):
        ref = _core.points(crane, float(tr.extension[k]), float(tr.slew[k]), tr.theta[k:k + 1])[0]
        mine = np.array([pts[name][k] for name in cp.POINT_NAMES])
        worst = max(worst, float(np.max(np.abs(mine - ref))))
        # and by hand: the tip lies in the vertical plane at the slew angle
        x, y, _ = tr.tip[k]
        assert abs(-x * math.sin(tr.slew[k]) + y * math.cos(tr.slew[k])) < 1e-12
    assert worst < 1e-12


def test_points_of_a_c_trajectory_at_the_held_pose(crane):
    initial = cp.State(0.1, 0.3, slew=-1.2, extension=0.9)
    tr = cp.predict(crane, initial, cp.Inputs(lift=cp.Pressure(90e5, 0.0), tilt=H), HORIZON, dt=DT)
    pts = tr.points()
    ref = _core.points(crane, 0.9, -1.2, tr.theta)
    np.testing.assert_array_equal(pts["tip"], ref[:, cp.POINT_NAMES.index("tip")])
    np.testing.assert_allclose(pts["tip"], tr.tip, rtol=0, atol=1e-12)


# -- bad input, named -------------------------------------------------------------------------------

def _no_valves(crane):
    return dataclasses.replace(
        crane, slew_drive=dataclasses.replace(crane.slew_drive, hydraulics=None),
        extension_cylinder=dataclasses.replace(crane.extension_cylinder, hydraulics=None))


def _bad_cases(crane):
    sd = crane.slew_drive
    good = cp.State(0.1, 0.3, slew=0.5, extension=0.5)
    push = cp.Pressure(30e5, 0.0)
    rest = _rest(crane, slew=0.5, extension=0.5)
    return [
        ("slew out of range", crane, cp.State(0.1, 0.3, slew=sd.slew_max + 0.01), cp.Inputs(H, H),
         ValueError, rf"State.slew must be in \[{sd.slew_min}, {sd.slew_max}\] rad \(slew_drive.slew_min/max\)"),
        ("held slew moving", crane, cp.State(0.1, 0.3, slew_rate=0.1), cp.Inputs(H, H),
         ValueError, "State.slew_rate must be 0 for a held slew"),
        ("held extension moving", crane, cp.State(0.1, 0.3, extension_rate=0.1), cp.Inputs(H, H),
         ValueError, "State.extension_rate must be 0 for a held extension"),
        ("no slew drive", dataclasses.replace(crane, slew_drive=None), good, cp.Inputs(H, H, slew=push),
         ValueError, "Inputs.slew: the crane has no slew_drive"),
        ("no extension cylinder", dataclasses.replace(crane, extension_cylinder=None), good,
         cp.Inputs(H, H, extension=push), ValueError, "Inputs.extension: the crane has no extension_cylinder"),
        ("slew valve without hydraulics", _no_valves(crane), rest, cp.Inputs(H, H, slew=cp.Valve(0.5)),
         ValueError, r"Inputs.slew: a valve drive needs slew_drive.hydraulics"),
        ("extension valve without hydraulics", _no_valves(crane), rest,
         cp.Inputs(H, H, extension=cp.Valve(0.5)), ValueError,
         r"Inputs.extension: a valve drive needs extension_cylinder.hydraulics"),
        ("slew valve without chambers", crane, good, cp.Inputs(H, H, slew=cp.Valve(0.5)),
         ValueError, "State.slew_p_a is required for a valve-driven slew"),
        ("extension series too short", crane, rest,
         cp.Inputs(H, H, extension=cp.ValveSeries(t=[0.0, 0.1], u=[0.0, 1.0])),
         ValueError, r"Inputs.extension: ValveSeries.t must cover \[0, horizon\]"),
        ("slew pressures too short", crane, good,
         cp.Inputs(H, H, slew=cp.PressureSeries(t=[0.0, 0.1], p_a=[0, 1e6], p_b=[0, 0])),
         ValueError, r"Inputs.slew: PressureSeries.t must cover \[0, horizon\]"),
    ]


@pytest.mark.parametrize("backend", ["c", "python"])
def test_bad_four_joint_input_is_named(crane, backend):
    for what, c, initial, inputs, exc, words in _bad_cases(crane):
        with pytest.raises(exc, match=words):
            cp.predict(c, initial, inputs, HORIZON, dt=DT, backend=backend)
        assert what   # the case's name, for the traceback


@pytest.mark.parametrize("make, exc, words", [
    (lambda: cp.State(0.1, 0.3, slew_rate=11.0), ValueError,
     r"State.slew_rate must be in \[-10, 10\] rad/s \(cranepredict.SLEW_RATE_MAX\)"),
    (lambda: cp.State(0.1, 0.3, extension_rate=-10.5), ValueError,
     r"State.extension_rate must be in \[-10, 10\] m/s"),
    (lambda: cp.State(0.1, 0.3, slew_rate="fast"), TypeError, "State.slew_rate must be a number"),
    (lambda: cp.State(0.1, 0.3, extension_p_b=2e8), ValueError, r"State.extension_p_b must be in \[-100000, 1e\+08\] Pa"),
    (lambda: cp.State(0.1, 0.3, slew_spool=1.5), ValueError, r"State.slew_spool must be in \[-1, 1\]"),
    (lambda: cp.State(0.1, 0.3, slew_p_a=math.nan), ValueError, "State.slew_p_a must be finite"),
    (lambda: cp.Inputs(lift=H, tilt=H, slew=0.5), TypeError, "Inputs.slew must be Pressure"),
    (lambda: cp.Inputs(lift=H, tilt=H, extension="out"), TypeError, "Inputs.extension must be Pressure"),
    (lambda: cp.State(0.1, 0.3).pressures("boom"), ValueError, "joint must be one of"),
])
def test_bad_four_joint_types_are_rejected_at_construction(make, exc, words):
    with pytest.raises(exc, match=words):
        make()


def test_nothing_passed_in_is_modified(crane):
    initial, inputs = _spatial(crane)
    before = (dataclasses.astuple(initial), inputs.extension.t.copy(), inputs.extension.u.copy())
    cp.predict(crane, initial, inputs, HORIZON, dt=DT, backend="python")
    assert dataclasses.astuple(initial) == before[0]
    assert np.array_equal(inputs.extension.t, before[1]) and np.array_equal(inputs.extension.u, before[2])


# -- state at rest and the valves of the new actuators, by hand ---------------------------------------

def test_state_at_rest_holds_the_telescope_against_gravity_along_the_boom(crane):
    """The extension cylinder carries (m_ext + m_load) g sin(theta0 + theta1): the gravity
    component along the outer boom (hand statics; the slew carries nothing)."""
    for lift, tilt in ((0.2, 0.05), (0.35, 0.6), (0.05, 0.3)):
        s = cp.state_at_rest(crane, lift, tilt, slew=1.0, extension=0.6)
        th = [_core.joint_angle(crane, j, x, 0.6)[0] for j, x in enumerate((lift, tilt))]
        force = (crane.extension_boom.mass + crane.load_mass) * crane.gravity * math.sin(sum(th))
        ec = crane.extension_cylinder
        assert s.extension_p_a * ec.area_a - s.extension_p_b * ec.area_b == pytest.approx(force, rel=1e-9)
        tank = ec.hydraulics.tank_pressure
        assert (s.extension_p_b if force >= 0 else s.extension_p_a) == tank
        assert s.slew_p_a == s.slew_p_b == crane.slew_drive.hydraulics.tank_pressure
    s = cp.state_at_rest(crane, 0.2, 0.05, extension=0.6, extension_rod_pressure=20e5)
    assert s.extension_p_b == 20e5


def test_closed_valves_hold_the_whole_crane_still(crane):
    initial = _rest(crane, slew=0.4, extension=0.6)
    closed = cp.Valve(0.0)
    tr = cp.predict(crane, initial, cp.Inputs(closed, closed, slew=closed, extension=closed), 1.0,
                    backend="python")
    assert np.max(np.abs(tr.tip - tr.tip[0])) < 1e-6
    assert np.max(np.abs(tr.p_a - tr.p_a[0])) < 1.0 and np.max(np.abs(tr.p_b - tr.p_b[0])) < 1.0


def test_slew_valve_steady_rate_by_hand(crane):
    """Slew lever fully open, booms held: in steady state the same flow passes both edges
    (A_a = A_b), so p_S - p_a = p_b - p_T and p_a - p_b carries the friction: omega =
    K sqrt((p_S - p_T - dp_f) / 2) / (A r_p), and the valve's flow is the rack's displacement."""
    sd = crane.slew_drive
    hyd = sd.hydraulics
    initial = cp.state_at_rest(crane, 0.1, 0.5, slew=-1.0, extension=0.0)
    tr = cp.predict(crane, initial, cp.Inputs(H, H, slew=cp.Valve(1.0), extension=H), 2.0,
                    backend="python")
    omega = tr.slew_rate[-1]
    assert abs(tr.slew_rate[-1] - tr.slew_rate[-50]) < 1e-3 * omega   # steady
    dp_f = tr.p_a[-1, 2] - tr.p_b[-1, 2]
    k = hyd.nominal_flow / math.sqrt(hyd.nominal_pressure_drop)
    q = k * math.sqrt((hyd.supply_pressure - hyd.tank_pressure - dp_f) / 2.0)
    assert omega == pytest.approx(q / (sd.area * sd.pinion_radius), rel=1e-3)
    assert tr.flow_a[-1, 2] == pytest.approx(sd.displacement * omega, rel=1e-3)
    assert tr.flow_b[-1, 2] == pytest.approx(sd.displacement * omega, rel=1e-3)
    # the friction at that rack speed, from the crane file's law, is what the pressures carry
    f = sd.friction
    x = sd.pinion_radius * omega / f.stribeck_velocity
    law = f.factor * (f.coulomb * math.tanh(4 * x) + (f.static - f.coulomb) * x / (x * x / 4 + 0.75) ** 2) \
        + f.viscous * math.tanh(4.0) * sd.pinion_radius * omega
    assert dp_f * sd.area == pytest.approx(law, rel=1e-2)


def test_telescope_valve_extends_at_the_orifice_rate(crane):
    """Telescope lever fully open on a horizontal-ish boom: the bore side's flow is A_a v_e and
    the rod side's A_b v_e (steady, incompressible to the chambers' slow change)."""
    ec = crane.extension_cylinder
    initial = _rest(crane, extension=0.1)
    tr = cp.predict(crane, initial, cp.Inputs(cp.Valve(0.0), cp.Valve(0.0), extension=cp.Valve(1.0)),
                    1.5, backend="python")
    v = tr.extension_rate[-1]
    assert v > 0.05
    assert tr.flow_a[-1, 3] == pytest.approx(ec.area_a * v, rel=2e-3)
    assert tr.flow_b[-1, 3] == pytest.approx(ec.area_b * v, rel=2e-3)


# -- the named spatial scenarios ------------------------------------------------------------------------

SPATIAL_SCENARIOS = ("slew-while-lifting", "extend-while-slewing", "slew-stop-load-out", "slew-folded",
                   "slew-stretched", "telescope-end-stop")


def test_spatial_scenarios_are_tagged_and_move_what_they_say():
    names = cp.scenarios.names()
    assert set(SPATIAL_SCENARIOS) <= set(names)
    for sc in cp.scenarios.all_scenarios():
        assert sc.spatial == ("spatial" in sc.tags), sc.name
    for name in SPATIAL_SCENARIOS:
        assert cp.scenarios.get(name).spatial


def test_slewing_folded_turns_farther_than_stretched():
    """The same slew torque on the folded and the stretched crane: the slew inertia follows the
    pose, so the folded one turns several times as far."""
    far = {}
    for name in ("slew-folded", "slew-stretched"):
        sc = cp.scenarios.get(name)
        tr = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="python")
        assert np.all(tr.theta == tr.theta[0]) and np.all(tr.extension == tr.extension[0])
        far[name] = tr.slew[-1] - tr.slew[0]
    assert far["slew-stretched"] > 0.1 and far["slew-folded"] > 5 * far["slew-stretched"]


@pytest.mark.slow
def test_telescope_scenario_reaches_its_end_stop():
    sc = cp.scenarios.get("telescope-end-stop")
    tr = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="python")
    t_stop = tr.first_stop_time(3, +1)
    assert t_stop is not None and 0.5 < t_stop < sc.horizon
    on = tr.stop[:, 3] == 1
    assert np.all(tr.extension[on] == sc.crane.geometry.extension_max)
    assert np.all(tr.extension_rate[on] == 0.0)


@pytest.mark.slow
def test_slew_stop_scenario_brakes_the_slew():
    sc = cp.scenarios.get("slew-stop-load-out")
    tr = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="python")
    peak = int(np.argmax(tr.slew_rate))
    # the lever closes over 1.0-1.2 s (30 ms spool lag): the slew is fastest while it closes
    assert 1.0 < tr.t[peak] < 1.25
    assert abs(tr.slew_rate[-1]) < 0.5 * tr.slew_rate[peak]
    # braking the load on closed ports: the outlet chamber goes up towards the relief
    relief = sc.crane.slew_drive.hydraulics.relief_pressure
    assert tr.p_b[:, 2].max() > 0.5 * relief
