"""The hydraulics verified independently of the implementation (docs/model.md
"Hydraulics"): a power balance over a run, hand-derived steady states, the oil-spring frequency,
and the dangerous corners of the numerics."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core
from lagrange import Lagrange

BACKENDS = ("c", "python")


def _simpson(y: np.ndarray, h: float) -> float:
    assert y.size % 2 == 1
    return float(h / 3.0 * (y[0] + y[-1] + 4.0 * y[1:-1:2].sum() + 2.0 * y[2:-1:2].sum()))


def _friction(f: cp.Friction, v: np.ndarray) -> np.ndarray:
    """docs/model.md, "Cylinders" ([S1]'s law; written here again: the test shares no code with
    the model)."""
    v = np.asarray(v, dtype=float)
    x = np.abs(v) / f.stribeck_velocity
    return (f.factor * (f.coulomb * np.tanh(4 * x) + (f.static - f.coulomb) * x / (x * x / 4 + 0.75) ** 2)
            * np.sign(v) + f.viscous * np.tanh(4.0) * v)


def _compliance(h: cp.Hydraulics, v: np.ndarray, v_hose: float) -> np.ndarray:
    return v / h.oil_bulk_modulus + (v - v_hose) / h.cylinder_bulk_modulus + v_hose / h.hose_bulk_modulus


# The default method at its default tolerance leaves 3.4e-5 of the pump work (its error control:
# 5e-5 m and 1e4 Pa per step); the balance to 1e-6 asks for a tight one: 1.8e-8 at this tolerance.
TIGHT = cp.Tolerance(tip=1e-8, pressure=1.0)


@pytest.mark.slow
@pytest.mark.parametrize("backend, method", [("c", "rk4"), ("c", "rosw"), ("python", "rk4")])
def test_power_balance(crane, backend, method):
    """pump work = change of mechanical energy + friction work + throttling losses + change of the
    oil's stored compression energy (C(V) p^2/2, less the work of the compliance change
    (p^2/2) C'(V) dV/dt of a lumped chamber), to 1e-6 of the pump work. RK4 steps dt; the default
    method (ROS34PW2) samples its dense output every dt at the tolerance TIGHT."""
    dt, horizon = 1e-4, 0.6
    rest = cp.state_at_rest(crane, 0.15, 0.35, lift_rod_pressure=20e5, tilt_rod_pressure=30e5)
    inputs = cp.Inputs(lift=cp.ValveSeries(t=[0.0, 0.2, 1.0], u=[0.0, 0.8, 0.5]),
                       tilt=cp.ValveSeries(t=[0.0, 0.3, 1.0], u=[0.0, -0.6, -0.6]))
    tr = cp.predict(crane, rest, inputs, horizon, dt=dt, backend=backend, method=method,
                    tolerance=TIGHT if method == "rosw" else None)
    assert not tr.stop.any()
    pump = np.zeros(tr.t.size)
    loss = np.zeros(tr.t.size)
    compliance_work = np.zeros(tr.t.size)
    e_oil = np.zeros(tr.t.size)
    for j, cyl in enumerate((crane.lift_cylinder, crane.tilt_cylinder)):
        h = cyl.hydraulics
        p_a, p_b, q_a, q_b, y = tr.p_a[:, j], tr.p_b[:, j], tr.flow_a[:, j], tr.flow_b[:, j], tr.spool[:, j]
        # the relief and anti-cavitation valves stay shut in this run (their flows are not here)
        assert h.cavitation_pressure < min(p_a.min(), p_b.min())
        assert max(p_a.max(), p_b.max()) < h.relief_pressure
        ext = y >= 0
        q_s = np.where(ext, q_a, -q_b)          # from the supply
        q_t = np.where(ext, q_b, -q_a)          # to the tank
        pump += h.supply_pressure * q_s - h.tank_pressure * q_t
        loss += np.where(ext, q_a * (h.supply_pressure - p_a) + q_b * (p_b - h.tank_pressure),
                         -q_b * (h.supply_pressure - p_b) - q_a * (p_a - h.tank_pressure))
        ds = np.array([_core.joint_angle(crane, j, s)[1] for s in tr.strokes[:, j]])
        v = ds * tr.omega[:, j]
        loss += _friction(cyl.friction, v) * v
        vol_a = h.hose_volume_a + cyl.area_a * (tr.strokes[:, j] - cyl.stroke_min)
        vol_b = h.hose_volume_b + cyl.area_b * (cyl.stroke_max - tr.strokes[:, j])
        e_oil += (_compliance(h, vol_a, h.hose_volume_a) * p_a ** 2
                  + _compliance(h, vol_b, h.hose_volume_b) * p_b ** 2) / 2
        dc = 1 / h.oil_bulk_modulus + 1 / h.cylinder_bulk_modulus
        compliance_work += dc / 2 * (p_a ** 2 * cyl.area_a * v - p_b ** 2 * cyl.area_b * v)
    lag = Lagrange(crane, 0.0)
    e_mech = np.array([lag.energy(q, w) for q, w in zip(tr.theta, tr.omega)])
    w_pump = _simpson(pump, dt)
    rhs = (e_mech[-1] - e_mech[0]) + _simpson(loss, dt) + (e_oil[-1] - e_oil[0]) \
        - _simpson(compliance_work, dt)
    assert w_pump > 1e3          # J: the run does real work
    residual = abs(w_pump - rhs) / w_pump
    print(f"power balance ({backend}, {method}): pump work {w_pump:.3f} J, relative residual {residual:.2e}")
    assert residual < 1e-6


def _with_hydraulics(crane: cp.Crane, joint: str, **changes) -> cp.Crane:
    cyl = getattr(crane, f"{joint}_cylinder")
    return dataclasses.replace(crane, **{f"{joint}_cylinder": dataclasses.replace(
        cyl, hydraulics=dataclasses.replace(cyl.hydraulics, **changes))})


S3_LIFT = dict(valve="compensated", supply_pressure=160e5, nominal_flow=40e-3 / 60, dead_band=0.114,
               meter_out_flow=40e-3 / 60, meter_out_pressure_drop=7e5, oil_bulk_modulus=0.9e9,
               hose_bulk_modulus=0.5e9, cylinder_bulk_modulus=1.3e11, relief_pressure=200e5)


@pytest.mark.slow
@pytest.mark.parametrize("backend", BACKENDS)
def test_compensated_valve_at_constant_lever_gives_q_over_a(crane, backend):
    """Meter-in flow source: the stroke rate settles at r nominal_flow / A_a whatever the load."""
    c = _with_hydraulics(crane, "lift", **S3_LIFT)
    u = 0.6
    h = c.lift_cylinder.hydraulics
    expected = (u - h.dead_band) / (1 - h.dead_band) * h.nominal_flow / c.lift_cylinder.area_a
    for load in (0.0, 500.0):
        cl = c.with_load(load)
        rest = cp.state_at_rest(cl, 0.10, 0.35)
        tr = cp.predict(cl, rest, cp.Inputs(lift=cp.Valve(u), tilt=cp.Hold()), 3.0, dt=2e-3,
                        backend=backend)
        late = tr.t > 0.5
        assert np.all(tr.p_a[late, 0] < h.supply_pressure - h.laminar_pressure_drop)
        assert not tr.stop.any()
        # the flow source leaves the oil spring lightly damped (the meter-out orifice damps it):
        # the stroke oscillates about a line of slope Q/A; fit the line over 2.5 s
        rate = np.polyfit(tr.t[late], tr.strokes[late, 0], 1)[0]
        print(f"compensated, load {load} kg: {rate:.6f} m/s, Q/A = {expected:.6f} m/s")
        assert abs(rate / expected - 1) < 2e-3


@pytest.mark.parametrize("backend", BACKENDS)
def test_orifice_valve_pressure_split(crane, backend):
    """Orifice valve at constant lever and constant load (no gravity: the load is friction): the
    stroke rate v and the pressures solve A_a v = u K sqrt(p_S - p_a), A_b v = u K sqrt(p_b - p_T),
    p_a A_a - p_b A_b = F_fric(v), solved here by bisection."""
    c = dataclasses.replace(crane, gravity=0.0)
    cyl = c.lift_cylinder
    h = cyl.hydraulics
    u = 0.5
    k = u * h.nominal_flow / math.sqrt(h.nominal_pressure_drop)

    def split(v):
        p_a = h.supply_pressure - (cyl.area_a * v / k) ** 2
        p_b = h.tank_pressure + (cyl.area_b * v / k) ** 2
        return p_a, p_b, p_a * cyl.area_a - p_b * cyl.area_b - float(_friction(cyl.friction, np.array(v)))

    lo, hi = 1e-6, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if split(mid)[2] > 0 else (lo, mid)
    v = lo
    rest = cp.State(0.05, 0.35, lift_p_a=1e5, lift_p_b=1e5)
    # converged (a tenth of the default tolerances): the hand split is the model's; the method's
    # error at its default (0.1 bar, 600 Pa here) is tests/test_rosw.py's
    tr = cp.predict(c, rest, cp.Inputs(lift=cp.Valve(u), tilt=cp.Hold()), 1.0, dt=1e-3, backend=backend,
                    tolerance=cp.Tolerance(tip=5e-6, pressure=1e3))
    rate = np.gradient(tr.strokes[:, 0], tr.t)
    late = tr.t > 0.6
    assert not tr.stop[late].any()
    # the stroke rate from the three equations (the booms' inertia, ignored by hand, is felt at
    # 1e-3: the transmission ds/dtheta changes as the boom turns)
    assert np.max(np.abs(rate[late] / v - 1)) < 2e-3
    # the pressure split at the simulated stroke rate: the two orifice equations (the oil's
    # compression, C dp/dt, ignored by hand, is felt at 1e-4 of p_S - p_a)
    split_a = h.supply_pressure - (cyl.area_a * rate[late] / k) ** 2
    split_b = h.tank_pressure + (cyl.area_b * rate[late] / k) ** 2
    print(f"orifice split: v {rate[late][-1]:.6f} m/s (hand {v:.6f}), p_a {tr.p_a[-1, 0] / 1e5:.4f} bar "
          f"(hand {split_a[-1] / 1e5:.4f}), p_b {tr.p_b[-1, 0] / 1e5:.4f} bar (hand {split_b[-1] / 1e5:.4f})")
    assert np.max(np.abs(tr.p_a[late, 0] - split_a)) < 0.02e5     # measured 1,670 Pa
    assert np.max(np.abs(tr.p_b[late, 0] - split_b)) < 0.02e5     # measured 950 Pa


@pytest.mark.slow
@pytest.mark.parametrize("backend", BACKENDS)
def test_closed_valve_static_pressures_and_oil_spring_frequency(crane, backend):
    """A closed valve holding a load: 100 kg added to a crane at rest on its oil. The lift
    settles (about a mean) where the trapped oil's pressures p_a0 + A_a x/C_a, p_b0 - A_b x/C_b
    carry the new load, and oscillates at sqrt(k/m): k = (A_a^2/C_a + A_b^2/C_b) (ds/dtheta)^2,
    m = M00 (tilt held), from the bulk moduli, the volumes and Lagrange's mass matrix."""
    from conftest import frictionless

    c0 = frictionless(crane)
    rest = cp.state_at_rest(c0, 0.20, 0.35, lift_rod_pressure=30e5)   # no cavitation on the rod side
    c1 = c0.with_load(c0.load_mass + 100.0)
    tr = cp.predict(c1, rest, cp.Inputs(lift=cp.Valve(0.0), tilt=cp.Hold()), 3.0, dt=5e-4,
                    backend=backend)
    cyl, h = c1.lift_cylinder, c1.lift_cylinder.hydraulics
    s0 = rest.lift_stroke
    v_a = h.hose_volume_a + cyl.area_a * (s0 - cyl.stroke_min)
    v_b = h.hose_volume_b + cyl.area_b * (cyl.stroke_max - s0)
    c_a = float(_compliance(h, np.array(v_a), h.hose_volume_a))
    c_b = float(_compliance(h, np.array(v_b), h.hose_volume_b))
    k_s = cyl.area_a ** 2 / c_a + cyl.area_b ** 2 / c_b
    th, ds = _core.joint_angle(c1, 0, s0)
    lag = Lagrange(c1, 0.0)
    # the new load's force at the cylinder, from the potential's gradient (complex step)
    qc = np.array([th, _core.joint_angle(c1, 1, rest.tilt_stroke)[0]], dtype=complex)
    qc[0] += 1e-30j
    f_new = float(np.imag(lag.potential(qc)) / 1e-30) / ds
    f_old = rest.lift_p_a * cyl.area_a - rest.lift_p_b * cyl.area_b
    x = (f_new - f_old) / k_s                     # m the stroke gives way
    assert x > 1e-5
    # mean over whole periods: between the first and the last upward crossing of the mean
    s = tr.strokes[:, 0]
    mid = 0.5 * (s.max() + s.min())
    up = np.flatnonzero((s[:-1] < mid) & (s[1:] >= mid))
    assert up.size >= 8      # periods (4.5 Hz on the PATU)
    # crossing times by linear interpolation
    tc = tr.t[up] + (mid - s[up]) / (s[up + 1] - s[up]) * (tr.t[1] - tr.t[0])
    period = (tc[-1] - tc[0]) / (up.size - 1)
    m = lag.mass_matrix(qc.real)[0, 0]
    f_hand = math.sqrt(k_s * ds ** 2 / m) / (2 * math.pi)
    print(f"oil spring: {1 / period:.3f} Hz simulated, {f_hand:.3f} Hz by hand; "
          f"static give {x * 1e6:.2f} um simulated {(s0 - mid) * 1e6:.2f} um")
    assert abs(1 / period / f_hand - 1) < 0.01
    assert abs((s0 - mid) / x - 1) < 0.01
    sel = slice(up[0], up[-1])
    p_a_hand = rest.lift_p_a + cyl.area_a * x / c_a
    p_b_hand = rest.lift_p_b - cyl.area_b * x / c_b
    assert abs(np.mean(tr.p_a[sel, 0]) - p_a_hand) < 0.01 * abs(p_a_hand - rest.lift_p_a)
    assert abs(np.mean(tr.p_b[sel, 0]) - p_b_hand) < 0.01 * abs(p_b_hand - rest.lift_p_b) + 1.0


def _corners(crane):
    """(name, crane, initial, inputs): the stiff corners of docs/model.md "Hydraulics"."""
    lc, tc = crane.lift_cylinder, crane.tilt_cylinder
    comp = _with_hydraulics(crane, "lift", **S3_LIFT)
    slam = cp.ValveSeries(t=[0.0, 0.05, 0.051, 0.25, 0.251, 0.4, 0.401, 0.5],
                          u=[0.0, 0.0, 1.0, 1.0, -1.0, -1.0, 0.0, 0.0])
    top = cp.state_at_rest(crane, lc.stroke_max, tc.stroke_min)
    bottom = cp.state_at_rest(crane, lc.stroke_min, tc.stroke_max)
    h = lc.hydraulics
    return [
        ("lift and tilt driven onto their upper stops", crane, top,
         cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(-1.0))),
        ("lift and tilt driven onto their lower stops", crane, bottom,
         cp.Inputs(lift=cp.Valve(-1.0), tilt=cp.Valve(1.0))),
        ("dp = 0 across the open edges", crane,
         dataclasses.replace(cp.state_at_rest(crane, 0.3, 0.4), lift_p_a=h.supply_pressure,
                             lift_p_b=h.tank_pressure, lift_spool=1.0),
         cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(0.0))),
        ("lever slammed open and shut at the bottom", crane, bottom,
         cp.Inputs(lift=slam, tilt=cp.Valve(0.0))),
        ("lever slammed, no spool lag", _with_hydraulics(crane, "lift", spool_time_constant=0.0),
         cp.state_at_rest(crane, 0.01, 0.4), cp.Inputs(lift=slam, tilt=cp.Hold())),
        ("compensated valve onto the upper stop", comp, cp.state_at_rest(comp, lc.stroke_max - 1e-3, 0.4),
         cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Hold())),
    ]


@pytest.mark.slow
@pytest.mark.parametrize("backend", BACKENDS)
def test_dangerous_corners_are_stable_and_accurate_at_the_default_step(crane, backend):
    """At the default step every corner stays within 1 mm (tip) and 1 bar of a run at dt/20, and
    the pressures stay between the cavitation floor and the relief setting, give or take those
    valves' override (laminar, nominal_flow/G = 6.7 bar at the nominal flow on the PATU)."""
    for name, c, initial, inputs in _corners(crane):
        fine = cp.predict(c, initial, inputs, 0.5, dt=cp.DEFAULT_DT / 20, backend=backend,
                          method="rk4")
        tr = cp.predict(c, initial, inputs, 0.5, backend=backend)
        tip = float(np.max(np.linalg.norm(tr.tip - fine.tip[::20], axis=1)))
        dp = float(max(np.max(np.abs(tr.p_a - fine.p_a[::20])), np.max(np.abs(tr.p_b - fine.p_b[::20]))))
        print(f"{name}: tip {tip * 1e3:.4f} mm, pressure {dp / 1e5:.4f} bar")
        assert tip < 1e-3 and dp < 1e5, name
        for j, cyl in enumerate((c.lift_cylinder, c.tilt_cylinder)):
            h = cyl.hydraulics
            for p in (tr.p_a[:, j], tr.p_b[:, j]):
                assert p.min() > h.cavitation_pressure - 10e5 and p.max() < h.relief_pressure + 10e5, name


def test_the_corners_need_the_substeps(crane, monkeypatch):
    """The corner test has teeth: with one substep per step (plain RK4 at 2 ms) the stiffest
    corner, the compensated valve at the stop, is unstable."""
    from cranepredict import twin

    name, c, initial, inputs = _corners(crane)[-1]
    fine = cp.predict(c, initial, inputs, 0.5, dt=cp.DEFAULT_DT / 20, backend="python",
                      method="rk4")
    monkeypatch.setattr(twin.hydraulics, "SUBSTEP_STABILITY", 1e12)
    try:
        tr = cp.predict(c, initial, inputs, 0.5, backend="python", method="rk4")
    except ValueError as e:            # diverged: the state stopped being finite
        assert "diverged" in str(e)
        return
    assert np.max(np.abs(tr.p_b - fine.p_b[::20])) > 1e5
