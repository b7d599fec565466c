"""The valve inputs, the hydraulic state and the crane file's hydraulics tables."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import cranepredict as cp


def test_crane_file_has_both_circuits_and_round_trips(crane):
    for cyl in (crane.lift_cylinder, crane.tilt_cylinder):
        h = cyl.hydraulics
        assert h is not None and h.valve == "orifice"
        assert h.supply_pressure == 80e5 and h.tank_pressure == 1e5           # [S1]
        assert h.oil_bulk_modulus == 1.65e9 and h.hose_bulk_modulus == 0.7e9  # [S1]
    assert crane.lift_cylinder.hydraulics.nominal_flow == pytest.approx(24e-3 / 60)
    assert crane.tilt_cylinder.hydraulics.nominal_flow == pytest.approx(54e-3 / 60)
    assert cp.Crane.from_toml_string(crane.to_toml()) == crane


def test_s3_compensated_valve_is_expressible(crane):
    s3 = cp.Hydraulics(valve="compensated", supply_pressure=92e5, tank_pressure=1e5,
                       relief_pressure=200e5, nominal_flow=40e-3 / 60, nominal_pressure_drop=7e5,
                       laminar_pressure_drop=2e5, cavitation_pressure=-0.9e5,
                       hose_volume_a=1.9e-4, hose_volume_b=1.9e-4, oil_bulk_modulus=0.9e9,
                       hose_bulk_modulus=0.5e9, cylinder_bulk_modulus=1.3e11, dead_band=0.114,
                       meter_out_flow=40e-3 / 60, meter_out_pressure_drop=7e5,
                       spool_time_constant=0.03)
    c = dataclasses.replace(crane, lift_cylinder=dataclasses.replace(crane.lift_cylinder,
                                                                      hydraulics=s3))
    assert cp.Crane.from_toml_string(c.to_toml()).lift_cylinder.hydraulics == s3


@pytest.mark.parametrize("field, value, words", [
    ("laminar_pressure_drop", 0.0, "must be > 0, got 0.0"),
    ("supply_pressure", 0.5e5, "must be > lift_cylinder.hydraulics.tank_pressure (100000.0) and <= 1e8"),
    ("relief_pressure", 50e5, "must be >= lift_cylinder.hydraulics.supply_pressure (8000000.0)"),
    ("dead_band", 0.1, "must be 0 for an orifice valve"),
    ("hose_volume_b", -1e-4, "must be > 0"),
    ("cavitation_pressure", 2e5, "must be >= -1e5 and <= lift_cylinder.hydraulics.tank_pressure"),
])
def test_bad_hydraulics_name_the_field(crane, field, value, words):
    """The C core's validator checks the circuit like every other field and names it."""
    d = crane.to_dict()
    d["lift_cylinder"]["hydraulics"][field] = value
    with pytest.raises(ValueError) as e:
        cp.Crane.from_dict(d)
    assert str(e.value).startswith(f"lift_cylinder.hydraulics.{field} {words}"), str(e.value)


def test_bad_valve_name(crane):
    d = crane.to_dict()
    d["tilt_cylinder"]["hydraulics"]["valve"] = "spool"
    with pytest.raises(ValueError, match=r"tilt_cylinder\.hydraulics\.valve must be one of"):
        cp.Crane.from_dict(d)


def test_lever_and_series_checks():
    with pytest.raises(ValueError, match=r"Valve.u must be in \[-1, 1\]"):
        cp.Valve(1.5)
    with pytest.raises(ValueError, match=r"ValveSeries.u must be in \[-1, 1\]"):
        cp.ValveSeries(t=[0, 1], u=[0, -1.01])
    with pytest.raises(ValueError, match="strictly increasing"):
        cp.ValveSeries(t=[0, 0], u=[0, 1])
    t = np.array([0.0, 1.0])
    series = cp.ValveSeries(t=t, u=[0.0, 1.0])
    t[1] = 5.0
    assert series.t[1] == 1.0   # copied


def test_prediction_checks(crane):
    rest = cp.state_at_rest(crane, 0.2, 0.3)
    with pytest.raises(ValueError, match="ValveSeries.t must cover"):
        cp.predict(crane, rest, cp.Inputs(lift=cp.ValveSeries([0, 1], [0, 1]), tilt=cp.Hold()),
                   2.0, backend="python")
    with pytest.raises(ValueError, match="State.tilt_p_a is required"):
        cp.predict(crane, cp.State(0.2, 0.3), cp.Inputs(lift=cp.Hold(), tilt=cp.Valve(0.5)), 1.0,
                   backend="python")
    bare = dataclasses.replace(crane, tilt_cylinder=dataclasses.replace(crane.tilt_cylinder,
                                                                         hydraulics=None))
    with pytest.raises(ValueError, match="tilt_cylinder.hydraulics"):
        cp.predict(bare, rest, cp.Inputs(lift=cp.Hold(), tilt=cp.Valve(0.5)), 1.0, backend="python")
    with pytest.raises(ValueError, match=r"State.lift_p_a must be in \[-100000"):
        cp.State(0.2, 0.3, lift_p_a=-2e5, lift_p_b=0.0)
    with pytest.raises(ValueError, match=r"State.tilt_spool must be in \[-1, 1\]"):
        cp.State(0.2, 0.3, tilt_spool=2.0)


def test_state_at_rest_balances_gravity(crane):
    s = cp.state_at_rest(crane, 0.116, 0.32, extension=0.4)
    for j, (joint, cyl) in enumerate((("lift", crane.lift_cylinder), ("tilt", crane.tilt_cylinder))):
        p_a, p_b = s.pressures(joint)
        th, ds = cp._core.joint_angle(crane, j, (s.lift_stroke, s.tilt_stroke)[j], 0.4)
        assert min(p_a, p_b) == cyl.hydraulics.tank_pressure
    # the valves closed: the crane stays where it is (to rounding, friction holds the rest)
    tr = cp.predict(crane, s, cp.Inputs(lift=cp.Valve(0.0), tilt=cp.Valve(0.0)), 1.0,
                    backend="python")
    assert np.max(np.abs(tr.strokes - tr.strokes[0])) < 1e-9
    assert np.max(np.abs(tr.p_a - tr.p_a[0])) < 1.0
    s2 = cp.state_at_rest(crane, 0.116, 0.32, lift_rod_pressure=31e5)
    assert s2.lift_p_b == 31e5 and s2.lift_p_a > s.lift_p_a


def test_lever_open_extends_and_trajectory_carries_the_circuit(crane):
    s = cp.state_at_rest(crane, 0.116, 0.32)
    tr = cp.predict(crane, s, cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(0.0)), 1.0,
                    backend="python")
    for name in ("p_a", "p_b", "flow_a", "flow_b", "spool"):
        assert getattr(tr, name).shape == (tr.t.size, 4)   # [lift, tilt, slew, extension]
    assert tr.strokes[-1, 0] > tr.strokes[0, 0] + 0.01
    assert tr.flow_a[-1, 0] > 0 and tr.flow_b[-1, 0] > 0
    assert tr.spool[-1, 0] == pytest.approx(1.0, abs=1e-9)   # 30 ms lag, 1 s later
    assert tr.spool[0, 0] == 0.0
    # pressure drive: the trajectory reports the given pressures
    tp = cp.predict(crane, cp.State(0.116, 0.32), cp.Inputs(lift=cp.Pressure(175e5, 0), tilt=cp.Hold()),
                    0.1)
    assert np.all(tp.p_a[:, 0] == 175e5) and np.all(tp.p_a[:, 1] == 0)


def test_the_core_refuses_bad_valve_drives_itself(crane):
    """The C core checks a valve drive again (the Python layer checks it first): a lever outside
    [-1, 1], a drive on a cylinder without a circuit, a chamber pressure out of range or NaN."""
    from cranepredict import _core
    from cranepredict._cranepredict import ffi, lib

    def run(mutate):
        prm = ffi.new("crane_params *")
        prm[0] = _core.params(crane)[0]
        st = ffi.new("crane_state *")
        st.stroke = (0.2, 0.3)
        st.p_a = (50e5, 1e5)
        st.p_b = (1e5, 20e5)
        inp = ffi.new("crane_inputs *")
        for d in (inp.drive[lib.CRANE_LIFT], inp.drive[lib.CRANE_TILT]):
            d.mode = lib.CRANE_DRIVE_VALVE
            d.u = 0.5
        mutate(prm, st, inp)
        out = ffi.new("crane_sample[]", 11)
        n = ffi.new("size_t *")
        return lib.crane_predict(prm, st, inp, 0.01, 1e-3, out, 11, n, _core.work())

    def nothing(prm, st, inp):
        pass

    def lever(prm, st, inp):
        inp.drive[1].u = 1.5

    def no_circuit(prm, st, inp):
        prm.cylinder[0].hydraulics.valve = lib.CRANE_VALVE_NONE

    def pressure(prm, st, inp):
        st.p_b = (1e5, -2e5)

    def nan(prm, st, inp):
        st.spool = (float("nan"), 0.0)

    def circuit(prm, st, inp):
        prm.cylinder[1].hydraulics.laminar_pressure_drop = 0.0

    assert run(nothing) == lib.CRANE_OK
    assert run(lever) == lib.CRANE_E_VALVE
    assert run(no_circuit) == lib.CRANE_E_VALVE
    assert run(pressure) == lib.CRANE_E_VALVE
    assert run(nan) == lib.CRANE_E_NONFINITE
    assert run(circuit) == lib.CRANE_E_HYDRAULICS


def test_the_substeps_count_against_the_step_limit(crane):
    """A laminar region of 1e-6 Pa makes the chamber equations so stiff that a 2-s prediction
    would need billions of substeps: refused before it runs, by both implementations."""
    tiny = dataclasses.replace(crane, lift_cylinder=dataclasses.replace(
        crane.lift_cylinder, hydraulics=dataclasses.replace(crane.lift_cylinder.hydraulics,
                                                            laminar_pressure_drop=1e-6)))
    rest = cp.state_at_rest(tiny, 0.2, 0.3)
    inputs = cp.Inputs(lift=cp.Valve(0.5), tilt=cp.Hold())
    for backend in ("c", "python"):
        with pytest.raises(ValueError, match="more than .*steps"):
            cp.predict(tiny, rest, inputs, 2.0, backend=backend, method="rk4")
    # a short one still runs
    tr = cp.predict(tiny, rest, inputs, 1e-3, dt=1e-3, method="rk4")
    assert tr.t.size == 2
