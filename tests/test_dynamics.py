"""Newton-Euler (C core and twin) against Lagrange's equations; energy conservation; the cylinder."""

from __future__ import annotations

import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core, twin
from conftest import frictionless
from lagrange import Lagrange

def _boom_torques(crane, extension, theta, omega, alpha):
    """The booms' torques of the core's inverse dynamics with the slew and the extension at rest."""
    q = (theta[0], theta[1], 0.0, extension)
    return _core.inverse_dynamics(crane, q, (omega[0], omega[1], 0.0, 0.0),
                                  (alpha[0], alpha[1], 0.0, 0.0))[:2]



def _random_states(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield (rng.uniform(-0.4, 1.6), rng.uniform(-3.3, 0.0), rng.uniform(0, 500), rng.uniform(0, 1),
               rng.uniform(-2, 2, 2), rng.uniform(-5, 5, 2))


def _rel(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


@pytest.mark.parametrize("backend", ["c", "twin"])
def test_newton_euler_equals_lagrange_at_random_states(crane, backend):
    worst = 0.0
    for th1, th2, load, ext, omega, alpha in _random_states(200, seed=7):
        c = crane.with_load(load)
        ref = Lagrange(c, ext).torques((th1, th2), omega, alpha)
        if backend == "c":
            tau = _boom_torques(c, ext, (th1, th2), omega, alpha)
        else:
            tau = twin.TwinModel(c, ext).inverse_dynamics((th1, th2), tuple(omega), tuple(alpha))
        worst = max(worst, _rel(tau, ref))
    assert worst < 1e-9, worst


def test_lagrange_reference_can_tell_a_wrong_model(crane):
    """The comparison above has teeth: a 1 % heavier load is seen at far more than 1e-9."""
    th, om, al = (0.3, -1.0), (0.5, -0.7), (1.0, 2.0)
    tau = _boom_torques(crane, 0.0, th, om, al)
    ref = Lagrange(crane.with_load(crane.load_mass * 1.01), 0.0).torques(th, om, al)
    assert _rel(tau, ref) > 1e-4


def _energy_drift(c, initial, dt, horizon):
    traj = cp.predict(c, initial, cp.Inputs(lift=cp.Pressure(0, 0), tilt=cp.Pressure(0, 0)), horizon, dt=dt,
                      method="rk4")
    assert not traj.stop.any(), "the energy test must not touch an end stop"
    lag = Lagrange(c, initial.extension)
    e = np.array([lag.energy(q, w) for q, w in zip(traj.theta, traj.omega)])
    return float(np.max(np.abs(e - e[0]))), float(np.max(np.abs(e)))


def test_energy_is_conserved_without_gravity_and_friction(crane):
    """Coriolis/centrifugal coupling only: both joints swing from initial stroke rates."""
    c = frictionless(crane, gravity=0.0)
    initial = cp.State(lift_stroke=0.25, tilt_stroke=0.4, lift_stroke_rate=0.05, tilt_stroke_rate=-0.08)
    drift, scale = _energy_drift(c, initial, 1e-3, 2.0)
    assert scale > 10.0  # the test is about a moving crane
    assert drift / scale < 1e-9


def test_energy_drift_shrinks_as_dt_to_the_fourth(crane):
    """Falling under gravity with zero pressures and no friction, until just before a stop."""
    c = frictionless(crane)
    initial = cp.State(lift_stroke=0.40, tilt_stroke=0.30, lift_stroke_rate=0.02)
    drifts = []
    for dt in (8e-3, 4e-3, 2e-3):
        drift, scale = _energy_drift(c, initial, dt, 0.4)
        drifts.append(drift)
    orders = [math.log2(drifts[i] / drifts[i + 1]) for i in range(2)]
    assert all(3.5 < o < 4.6 for o in orders), (drifts, orders)


def test_paper_cylinder_force_at_rest(crane):
    # 175 bar on a 100 mm bore, 0 on the rod side: 137,445 N (the paper's figure), no friction at rest.
    f = _core.cylinder_force(crane, 0, 175e5, 0.0, 0.0)
    assert abs(f - 137_445.0) < 1.0
    assert twin.TwinModel(crane, 0.0).cylinder_force(0, 175e5, 0.0, 0.0) == pytest.approx(f, abs=1e-9)


def test_friction_is_zero_at_rest_and_opposes_motion(crane):
    fr = crane.lift_cylinder.friction
    assert _core.cylinder_force(crane, 1, 0.0, 0.0, 0.0) == 0.0
    m = twin.TwinModel(crane, 0.0)
    for v in (1e-4, 1e-3, 5e-3, 0.05, 0.3):
        f_c = _core.cylinder_force(crane, 1, 0.0, 0.0, v)
        assert f_c < 0 and _core.cylinder_force(crane, 1, 0.0, 0.0, -v) == pytest.approx(-f_c, rel=1e-15)
        assert m.cylinder_force(1, 0.0, 0.0, v) == pytest.approx(f_c, rel=1e-12)
    # Well above the Stribeck velocity (x = 40): k F_C plus sigma tanh(4) v; the Stribeck tail
    # 4 k (F_S - F_C) / x^3 left there is 1e-4 of it.
    v = 0.2
    assert -_core.cylinder_force(crane, 0, 0.0, 0.0, v) == pytest.approx(
        fr.factor * fr.coulomb + fr.viscous * math.tanh(4.0) * v, rel=1.5e-4)
    # Near the Stribeck velocity the friction exceeds the Coulomb level (static peak).
    assert -_core.cylinder_force(crane, 0, 0.0, 0.0, 0.004) > fr.factor * fr.coulomb
