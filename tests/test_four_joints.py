"""The four-joint crane (docs/model.md, "Four joints"): its derivation checked against the
independent Lagrange oracle (tests/lagrange4.py) and by hand, and its crane-file parameters.

The fast model is not implemented yet; these tests check the specification itself: the block
structure of the mass matrix, the slew equation for a rigidly held boom (J_z from the bodies), its
Coriolis term, the centrifugal load of the slew rate on the booms and the extension's equation,
each formula written out here from the docs' text and compared with the oracle.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import cranepredict as cp
from lagrange import Lagrange
from lagrange4 import EXTENSION, LIFT, SLEW, TILT, Lagrange4, tensor

H = 1e-30


def _rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def _random_states(n, seed, crane):
    rng = np.random.default_rng(seed)
    g = crane.geometry
    for _ in range(n):
        q = np.array([rng.uniform(-0.4, 1.6), rng.uniform(-3.3, 0.0), rng.uniform(-3, 3),
                      rng.uniform(g.extension_min, g.extension_max)])
        yield q, rng.uniform(-2, 2, 4), rng.uniform(-5, 5, 4), rng.uniform(0, 500)


# -- the hand formulas of docs/model.md "Four joints" (boom plane, no side links) ----------------

def _rot(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def _bodies(crane, q):
    """(mass, boom-plane centre r_b, in-plane angle phi_b, tensor) of the pillar, lift boom, outer
    boom and body 3 (extension boom + load lumped in the extension frame), complex-safe in q."""
    g = crane.geometry
    o1, o2 = np.array(g.lift_pivot), np.array(g.tilt_pivot)
    mount = np.array(g.extension_mount)
    ext, load = crane.extension_boom, crane.load_mass
    tip = np.array([g.tip_distance, 0.0])
    m3 = ext.mass + load
    c3 = (ext.mass * np.array(ext.com) + load * tip) / m3

    def parallel(d):
        return np.array([[d[1] ** 2, -d[0] * d[1], 0], [-d[0] * d[1], d[0] ** 2, 0], [0, 0, d @ d]])

    j3 = tensor(ext) + ext.mass * parallel(np.array(ext.com) - c3) + load * parallel(tip - c3)
    r12 = _rot(q[0]) @ o2
    out = [(crane.pillar.mass, np.array(crane.pillar.com) + 0 * q[0], 0 * q[0], tensor(crane.pillar)),
           (crane.lift_boom.mass, o1 + _rot(q[0]) @ np.array(crane.lift_boom.com), q[0],
            tensor(crane.lift_boom)),
           (crane.outer_boom.mass, o1 + r12 + _rot(q[0] + q[1]) @ np.array(crane.outer_boom.com),
            q[0] + q[1], tensor(crane.outer_boom)),
           (m3, o1 + r12 + _rot(q[0] + q[1]) @ (mount + np.array([q[3], 0 * q[3]]) + c3), q[0] + q[1], j3)]
    return out


def _j_v(j, phi):
    s, c = np.sin(phi), np.cos(phi)
    return j[0, 0] * s * s + 2 * j[0, 1] * s * c + j[1, 1] * c * c


def _j_z(crane, q):
    """J_z = sum_b m_b x_b^2 + J_v,b(phi_b), the pillar included (docs: its J_P)."""
    return sum(m * r[0] ** 2 + _j_v(j, phi) for m, r, phi, j in _bodies(crane, q))


def _d_dq(f, q, k):
    qc = np.array(q, dtype=complex)
    qc[k] += 1j * H
    return float(np.imag(f(qc)) / H)


@pytest.fixture(scope="module")
def crane():
    return cp.Crane.patu655()


# -- the oracle against the planar one ---------------------------------------------------------

@pytest.mark.slow
def test_oracle_without_slew_and_extension_motion_is_the_planar_oracle(crane):
    """tests/lagrange.py (planar, 2 joints) and the spatial oracle agree on the lift and tilt
    torques when the slew and the extension do not move (any slew angle, any extension)."""
    worst = 0.0
    for q, qd, qdd, load in _random_states(40, 1, crane):
        c = crane.with_load(load)
        qd[SLEW] = qd[EXTENSION] = qdd[SLEW] = qdd[EXTENSION] = 0.0
        tau = Lagrange4(c).torques(q, qd, qdd)
        ref = Lagrange(c, q[EXTENSION]).torques(q[:2], qd[:2], qdd[:2])
        worst = max(worst, _rel(tau[:2], ref))
    assert worst < 1e-9, worst


def test_mass_matrix_is_block_diagonal(crane):
    """No inertial coupling between the slew and the in-plane joints (docs: M = diag(M_p, J_z)):
    the slew row's off-diagonal entries vanish to rounding against the matrix's size."""
    for q, _, _, load in _random_states(20, 2, crane):
        m = Lagrange4(crane.with_load(load)).mass_matrix(q)
        off = [m[SLEW, k] for k in (LIFT, TILT, EXTENSION)]
        assert np.max(np.abs(off)) < 1e-12 * np.max(np.abs(m)), (q, off)


# -- the slew equation by hand --------------------------------------------------------------------

def test_slew_of_a_rigidly_held_boom_is_torque_equals_j_z_alpha(crane):
    """Booms held (no rates), slew accelerated: tau_s = J_z alpha with J_z summed body by body
    (m x^2 + the body's inertia about the vertical, from its tensor), the in-plane joints loaded
    by gravity alone."""
    for q, _, qdd, load in _random_states(30, 3, crane):
        c = crane.with_load(load)
        lag = Lagrange4(c, side_links=False)
        alpha = qdd[SLEW]
        tau = lag.torques(q, np.zeros(4), np.array([0.0, 0.0, alpha, 0.0]))
        assert tau[SLEW] == pytest.approx(_j_z(c, q) * alpha, rel=1e-10)
        at_rest = lag.torques(q, np.zeros(4), np.zeros(4))
        assert _rel(tau[[LIFT, TILT, EXTENSION]], at_rest[[LIFT, TILT, EXTENSION]]) < 1e-12


def test_slew_inertia_follows_the_pose(crane):
    """The PATU 655's J_z from the bodies, folded vs stretched (patu655.md: ~8x with the pose)."""
    lag = Lagrange4(crane)
    folded = np.array([-0.3, -3.0, 0.0, 0.0])       # lift boom low, outer boom folded under it
    stretched = np.array([0.25, -0.25, 0.0, 1.0])   # both booms near horizontal, extension out
    j_f = lag.mass_matrix(folded)[SLEW, SLEW]
    j_s = lag.mass_matrix(stretched)[SLEW, SLEW]
    # folded: the booms within ~2 m of the axis; stretched: the 200 kg load alone at x_tip
    x_tip = lag.tip(stretched)[0]
    assert 200 < j_f < 1500
    assert crane.load_mass * x_tip ** 2 < j_s < 14000
    assert j_s / j_f > 7                            # 8.9e3 vs 1.1e3 kg m^2


def test_slew_coriolis_term(crane):
    """tau_s = J_z alpha_s + Jdot_z omega_s with Jdot_z = sum 2 m x xdot + J_v'(phi) phidot
    (docs), the rates of the centres by the complex step of the hand positions."""
    worst = 0.0
    for q, qd, qdd, load in _random_states(30, 4, crane):
        c = crane.with_load(load)
        tau = Lagrange4(c, side_links=False).torques(q, qd, qdd)
        jdot = 0.0
        for b in range(4):
            def x_of(qq, b=b):
                return _bodies(c, qq)[b][1][0]
            m, r, phi, j = _bodies(c, q)[b]
            xdot = sum(_d_dq(x_of, q, k) * qd[k] for k in range(4))
            phidot = sum(_d_dq(lambda qq, b=b: _bodies(c, qq)[b][2], q, k) * qd[k] for k in range(4))
            jv_prime = (j[0, 0] - j[1, 1]) * math.sin(2 * phi) + 2 * j[0, 1] * math.cos(2 * phi)
            jdot += 2 * m * r[0] * xdot + jv_prime * phidot
        expect = _j_z(c, q) * qdd[SLEW] + jdot * qd[SLEW]
        worst = max(worst, abs(tau[SLEW] - expect) / max(abs(expect), 1.0))
    assert worst < 1e-9, worst


def test_centrifugal_load_of_the_slew_rate_on_the_booms(crane):
    """The slew rate adds -1/2 omega_s^2 dJ_z/dq_k to each in-plane joint's equation (docs), and
    nothing else: the difference with and without the slew rate, by the oracle."""
    worst = 0.0
    for q, qd, qdd, load in _random_states(30, 5, crane):
        c = crane.with_load(load)
        lag = Lagrange4(c, side_links=False)
        still = qd.copy()
        still[SLEW] = 0.0
        diff = lag.torques(q, qd, qdd) - lag.torques(q, still, qdd)
        expect = [-0.5 * qd[SLEW] ** 2 * _d_dq(lambda qq: _j_z(c, qq), q, k) for k in (LIFT, TILT, EXTENSION)]
        scale = max(np.max(np.abs(lag.torques(q, qd, qdd))), 1.0)
        worst = max(worst, float(np.max(np.abs(diff[[LIFT, TILT, EXTENSION]] - expect))) / scale)
    assert worst < 1e-9, worst


def test_extension_equation_by_newton_along_the_boom(crane):
    """Booms not turning in the plane, the slew turning: body 3 (extension boom + load) obeys
    Newton's law along the boom, tau_e = m3 (a_e + g u.y - omega_s^2 x3 u.x)."""
    for q, qd, qdd, load in _random_states(30, 6, crane):
        c = crane.with_load(load)
        rates = np.array([0.0, 0.0, qd[SLEW], qd[EXTENSION]])
        acc = np.array([0.0, 0.0, qdd[SLEW], qdd[EXTENSION]])
        tau = Lagrange4(c).torques(q, rates, acc)
        m3, r3 = _bodies(c, q)[3][0], _bodies(c, q)[3][1]
        u = (math.cos(q[0] + q[1]), math.sin(q[0] + q[1]))
        expect = m3 * (qdd[EXTENSION] + c.gravity * u[1] - qd[SLEW] ** 2 * r3[0] * u[0])
        assert tau[EXTENSION] == pytest.approx(expect, rel=1e-9, abs=1e-9 * m3 * c.gravity)


def test_hand_checks_have_teeth(crane):
    """The comparisons above can fail: J_z without the bodies' own inertia about the vertical,
    or with the sign of ixy flipped, is off by far more than the tolerances."""
    q = np.array([0.6, -1.2, 0.0, 0.5])
    j = Lagrange4(crane, side_links=False).mass_matrix(q)[SLEW, SLEW]
    point_masses = sum(m * r[0] ** 2 for m, r, _, _ in _bodies(crane, q))
    assert abs(point_masses - j) / j > 1e-3
    flipped = dataclasses.replace(crane, lift_boom=dataclasses.replace(crane.lift_boom, ixy=-crane.lift_boom.ixy))
    assert abs(_j_z(flipped, q) - j) / j > 1e-5


# -- the crane file ------------------------------------------------------------------------------

def test_crane_file_has_the_four_joint_parameters(crane):
    """[S1]'s pillar tensor (iyy about the slew axis), and every number no source gives listed
    under `estimates`."""
    assert crane.pillar.iyy == 0.612552
    assert crane.pillar.mass * crane.pillar.com[0] ** 2 + crane.pillar.iyy == pytest.approx(0.6408, abs=1e-4)
    assert crane.slew_drive.slew_min < 0.0 < crane.slew_drive.slew_max
    for name in ("slew_drive.bore", "slew_drive.pinion_radius", "slew_drive.slew_min", "slew_drive.slew_max",
                 "slew_drive.friction", "extension_cylinder.bore", "extension_cylinder.rod",
                 "extension_cylinder.friction", "outer_boom.ixx", "outer_boom.iyy", "outer_boom.ixy",
                 "extension_boom.ixx", "extension_boom.iyy", "extension_boom.ixy"):
        assert name in crane.estimates, name
    # the outer boom's tensor is derived from [S1]'s combined body like its izz: outer + extension
    # boom at zero extension have [S1]'s (copied) tensor about the combined centre
    ob, eb = crane.outer_boom, crane.extension_boom
    m = ob.mass + eb.mass
    ce = np.array(crane.geometry.extension_mount) + np.array(eb.com)
    com = (ob.mass * np.array(ob.com) + eb.mass * ce) / m
    d_o, d_e = np.array(ob.com) - com, ce - com
    xx = ob.ixx + ob.mass * d_o[1] ** 2 + eb.ixx + eb.mass * d_e[1] ** 2
    yy = ob.iyy + ob.mass * d_o[0] ** 2 + eb.iyy + eb.mass * d_e[0] ** 2
    xy = ob.ixy - ob.mass * d_o[0] * d_o[1] + eb.ixy - eb.mass * d_e[0] * d_e[1]
    assert (xx, yy, xy) == pytest.approx((1.055433, 66.577004, 1.442440), abs=2e-3)


def test_crane_file_four_joint_tables_are_type_checked(crane):
    d = crane.to_dict()
    d["slew_drive"]["bore"] = "wide"
    with pytest.raises(TypeError, match="slew_drive.bore"):
        cp.Crane.from_dict(d)
    d = crane.to_dict()
    d["extension_cylinder"]["stroke"] = 1.0
    with pytest.raises(ValueError, match="extension_cylinder.stroke"):
        cp.Crane.from_dict(d)
    d = crane.to_dict()
    del d["slew_drive"], d["extension_cylinder"], d["lift_boom"]["ixx"]
    plain = cp.Crane.from_dict(d)
    assert plain.slew_drive is None and plain.lift_boom.ixx is None
    assert cp.Crane.from_toml_string(crane.to_toml()) == crane


# -- the twin (stage 2) ------------------------------------------------------------------------

def test_twin_four_joint_inverse_dynamics_equals_lagrange(crane):
    """The twin's four-joint Newton-Euler (docs: ID with the slew's centripetal and gyroscopic
    terms, the sliding body 3, J_z alpha_s + Jdot_z omega_s) against the spatial oracle, every
    component to 1e-9 of the largest, random states, loads and extensions."""
    from cranepredict import twin

    worst = 0.0
    for q, qd, qdd, load in _random_states(60, 11, crane):
        c = crane.with_load(load)
        ref = Lagrange4(c).torques(q, qd, qdd)
        tau = twin.TwinModel(c, 0.0).inverse_dynamics4(tuple(q), tuple(qd), tuple(qdd))
        worst = max(worst, _rel(tau, ref))
        # the extension force on its own scale (it is small next to the torques)
        assert tau[EXTENSION] == pytest.approx(ref[EXTENSION], rel=1e-8, abs=1e-9 * abs(ref).max())
    assert worst < 1e-9, worst


def test_twin_four_joint_lagrange_comparison_has_teeth(crane):
    """A 1 % error in the pillar's or the extension boom's inertia is seen far above 1e-9."""
    from cranepredict import twin

    q, qd, qdd = (0.3, -1.0, 0.5, 0.6), (0.5, -0.7, 0.8, 0.3), (1.0, 2.0, -1.5, 0.7)
    ref = Lagrange4(crane).torques(q, qd, qdd)
    wrong = dataclasses.replace(crane, extension_boom=dataclasses.replace(
        crane.extension_boom, ixx=crane.extension_boom.ixx + 0.01 * crane.extension_boom.iyy))
    assert _rel(twin.TwinModel(wrong, 0.0).inverse_dynamics4(q, qd, qdd), ref) > 1e-7


def _frictionless4(crane, gravity=None):
    from conftest import frictionless

    c = frictionless(crane, gravity)
    zero = cp.Friction(coulomb=0.0, static=0.0, viscous=0.0, stribeck_velocity=0.005, factor=1.0)
    return dataclasses.replace(
        c, slew_drive=dataclasses.replace(c.slew_drive, friction=zero),
        extension_cylinder=dataclasses.replace(c.extension_cylinder, friction=zero))


def _run4(crane, horizon, dt, *, lift=0.25, tilt=0.4, slew=0.0, extension=0.5, rates=(0, 0, 0, 0),
          drives=None, method="auto"):
    """The twin's four-joint prediction (the API does not carry the slew and extension drives
    yet): state and inputs as plain namespaces."""
    from types import SimpleNamespace

    from cranepredict import twin

    zero = cp.Pressure(0.0, 0.0)
    d = drives or {}
    state = SimpleNamespace(lift_stroke=lift, tilt_stroke=tilt, slew=slew, extension=extension,
                            lift_stroke_rate=rates[0], tilt_stroke_rate=rates[1],
                            slew_rate=rates[2], extension_rate=rates[3])
    inputs = SimpleNamespace(lift=d.get("lift", zero), tilt=d.get("tilt", zero),
                             slew=d.get("slew", zero), extension=d.get("extension", zero))
    return twin._run(crane, state, inputs, horizon, dt, method)


def _q_qd(crane, arrays):
    q = np.column_stack([arrays["theta"], arrays["slew"], arrays["extension"]])
    qd = np.column_stack([arrays["omega"], arrays["slew_rate"], arrays["extension_rate"]])
    return q, qd


def test_twin_four_joints_conserve_energy_without_friction_and_gravity(crane):
    """All four joints move from initial rates (pressures 0, no friction, no gravity): the
    kinetic energy, evaluated by the Lagrange oracle along the twin's trajectory, is conserved."""
    c = _frictionless4(crane, gravity=0.0)
    arrays, events = _run4(c, 1.0, 1e-3, rates=(0.05, -0.08, 0.4, 0.05), method="rk4")
    assert not events, "the energy test must not touch an end stop"
    q, qd = _q_qd(c, arrays)
    assert np.ptp(q[:, 2]) > 0.2 and np.ptp(q[:, 3]) > 0.03   # the slew and the extension move
    lag = Lagrange4(c)
    e = np.array([lag.kinetic(a, b) for a, b in zip(q[::20], qd[::20])])
    assert e[0] > 10.0
    drift = float(np.max(np.abs(e - e[0])) / e[0])
    assert drift < 1e-9, drift


def test_twin_four_joints_conserve_energy_with_gravity(crane):
    """With gravity, T + V (the oracle's) is conserved to the integrator's error."""
    c = _frictionless4(crane)
    arrays, events = _run4(c, 0.5, 1e-3, lift=0.40, tilt=0.30, rates=(0.02, 0.0, 0.5, 0.0),
                           method="rk4")
    assert not events
    q, qd = _q_qd(c, arrays)
    lag = Lagrange4(c)
    e = np.array([lag.energy(a, b) for a, b in zip(q[::25], qd[::25])])
    scale = max(np.max(np.abs(e)), 1.0)
    assert np.max(np.abs(e - e[0])) / scale < 1e-8


def test_slew_drive_starts_the_held_boom_with_j_z(crane):
    """Booms and extension held, the slew drive at 100 bar on chamber a: the slew accelerates
    from rest with alpha = r_p A dp / J_z (J_z from the oracle, no friction at rest)."""
    h = cp.Hold()
    arrays, _ = _run4(crane, 0.01, 1e-3, drives={"lift": h, "tilt": h, "extension": h,
                                                  "slew": cp.Pressure(100e5, 0.0)})
    sd = crane.slew_drive
    torque = sd.pinion_radius * sd.area * 100e5
    q0 = np.array([*arrays["theta"][0], arrays["slew"][0], arrays["extension"][0]])
    j_z = Lagrange4(crane).mass_matrix(q0)[SLEW, SLEW]
    # the rate after 1 ms, against alpha t (friction is ~ 1e-3 of the torque above v_S)
    assert arrays["slew_rate"][1] == pytest.approx(torque / j_z * 1e-3, rel=2e-2)
    assert np.all(arrays["theta"] == arrays["theta"][0])


def test_extension_runs_into_its_end_stop_and_stays(crane):
    """The telescope pushed out at 50 bar reaches extension_max, stops there (plastic), and the
    stop flag says so; the tip moves outward by the extension."""
    h = cp.Hold()
    arrays, events = _run4(crane, 2.0, 2e-3, extension=0.2,
                           drives={"lift": h, "tilt": h, "slew": h, "extension": cp.Pressure(50e5, 0.0)})
    e_max = crane.geometry.extension_max
    assert events and events[0][1] == EXTENSION and events[0][2] == +1
    assert arrays["extension"][-1] == e_max and arrays["stop"][-1, EXTENSION] == +1
    assert arrays["extension_rate"][-1] == 0.0
    u = arrays["tip"][-1] - arrays["tip"][0]
    assert np.linalg.norm(u) == pytest.approx(e_max - 0.2, rel=1e-12)


def test_slewing_moves_the_tip_around_the_axis(crane):
    """A held boom slewing: the tip keeps its height and its distance from the slew axis."""
    h = cp.Hold()
    arrays, _ = _run4(crane, 1.0, 2e-3, drives={"lift": h, "tilt": h, "extension": h,
                                                 "slew": cp.Pressure(80e5, 0.0)})
    tip = arrays["tip"]
    r = np.hypot(tip[:, 0], tip[:, 1])
    assert np.ptp(arrays["slew"]) > 0.1
    assert np.ptp(r) < 1e-12 * r[0] and np.ptp(tip[:, 2]) < 1e-12
    assert np.allclose(np.arctan2(tip[:, 1], tip[:, 0]), arrays["slew"], atol=1e-12)


def test_twin_four_joint_energy_drift_shrinks_as_dt_to_the_fourth(crane):
    """Slewing and extending while falling under gravity (no friction): the drift of T + V is
    RK4's, of fourth order in dt."""
    c = _frictionless4(crane)
    lag = Lagrange4(c)
    drifts = []
    for dt in (4e-3, 2e-3):
        arrays, events = _run4(c, 0.5, dt, lift=0.40, tilt=0.30, rates=(0.02, 0.0, 0.5, 0.0),
                               method="rk4")
        assert not events
        q, qd = _q_qd(c, arrays)
        step = int(round(0.02 / dt))
        e = np.array([lag.energy(a, b) for a, b in zip(q[::step], qd[::step])])
        drifts.append(float(np.max(np.abs(e - e[0]))))
    order = math.log2(drifts[0] / drifts[1])
    assert 3.5 < order < 4.6, (drifts, order)


def test_slew_runs_into_its_end_stop_and_leaves_it_when_reversed(crane):
    """The folded crane slewed at 60 bar from near slew_max hits the stop (plastic: the slew rate
    goes to 0, the booms' rates are untouched, M being block diagonal), stays while pushed, and
    leaves it when the pressure turns round."""
    sd = crane.slew_drive
    h = cp.Hold()
    push_then_pull = cp.PressureSeries(t=[0.0, 0.6, 0.61, 1.5], p_a=[60e5, 60e5, 0.0, 0.0],
                                       p_b=[0.0, 0.0, 60e5, 60e5])
    arrays, events = _run4(crane, 1.5, 2e-3, lift=0.05, tilt=0.75, slew=sd.slew_max - 0.2, extension=0.0,
                           drives={"lift": h, "tilt": h, "extension": h, "slew": push_then_pull})
    assert events and events[0][1] == SLEW and events[0][2] == +1
    t = arrays["t"]
    on_stop = arrays["stop"][:, SLEW] == +1
    assert on_stop.any() and np.all(arrays["slew"][on_stop] == sd.slew_max)
    assert np.all(arrays["slew_rate"][on_stop] == 0.0)
    # released after the pressure turned round, and moving back
    assert not on_stop[-1] and t[on_stop][-1] > 0.6 and arrays["slew_rate"][-1] < 0.0
    assert np.all(arrays["slew"] <= sd.slew_max)


def test_a_slew_impact_leaves_the_boom_rates_alone(crane):
    """Block diagonal M: the plastic impact on the slew stop changes only the slew rate, so the
    lift and tilt rates (free, moving) are continuous across it."""
    from cranepredict import twin

    zero = cp.Pressure(0.0, 0.0)
    model = twin.TwinModel(crane, 0.0)
    pred = twin._Prediction(model, (twin._PressureDrive(zero),) * 4)
    th0 = model.lift_angle(0.25)[0]
    th1 = model.tilt_angle(0.4)[0]
    x = (th0, th1, crane.slew_drive.slew_max, 0.5, 0.3, -0.2, 0.7, 0.1)
    y = pred.plastic_impact(x, SLEW, +1)
    assert y[4 + SLEW] == 0.0 and y[:4] == x[:4]
    assert y[4 + LIFT] == pytest.approx(x[4 + LIFT], abs=1e-15)
    assert y[4 + TILT] == pytest.approx(x[4 + TILT], abs=1e-15)
    assert y[4 + EXTENSION] == pytest.approx(x[4 + EXTENSION], abs=1e-15)
    # an extension impact, in contrast, changes the boom rates through the coupling of M_p
    pred2 = twin._Prediction(model, (twin._PressureDrive(zero),) * 4)
    x2 = x[:3] + (crane.geometry.extension_max,) + x[4:]
    z = pred2.plastic_impact(x2, EXTENSION, +1)
    assert z[4 + EXTENSION] == 0.0 and z[4 + SLEW] == x2[4 + SLEW]
    assert abs(z[4 + LIFT] - x2[4 + LIFT]) > 1e-3


@pytest.mark.slow
def test_extension_friction_substeps_keep_the_default_step_accurate(crane, monkeypatch):
    """The light extension boom (16 kg + load) on a cylinder's friction is stiff near rest:
    lambda = G_f (M^-1)_ee reaches 1e4 /s, beyond RK4's reach at 2 ms. With the substeps the
    2-ms run stays within 0.01 mm of a 0.25-ms one here (7e-6 m); without them it is 0.8 mm off
    (13 mm in a random case with the booms moving too)."""
    from cranepredict import twin

    c = crane.with_load(60.0)
    drives = {"lift": cp.Hold(), "tilt": cp.Hold(), "slew": cp.Pressure(30e5, 0.0),
              "extension": cp.PressureSeries(t=[0.0, 1.0, 1.01, 2.0], p_a=[1.2e5, 1.2e5, 0.0, 0.0],
                                             p_b=[0.0, 0.0, 1.2e5, 1.2e5])}
    start = dict(lift=0.30, tilt=0.10, slew=0.0, extension=0.3)

    def gap():
        coarse, e1 = _run4(c, 2.0, 2e-3, drives=drives, method="rk4", **start)
        fine, e2 = _run4(c, 2.0, 2.5e-4, drives=drives, method="rk4", **start)
        assert not e1 and not e2
        return float(np.max(np.linalg.norm(fine["tip"][::8] - coarse["tip"], axis=1)))

    with_substeps = gap()
    monkeypatch.setattr(twin._Prediction, "extension_friction_rate", lambda self, x: 0.0)
    without = gap()
    assert with_substeps < 1e-4, with_substeps
    assert without > 10 * with_substeps, (without, with_substeps)
