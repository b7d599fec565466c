"""The state estimator in the C core (crane_estimator_init / crane_estimator_update).

Checked three ways: against a Kalman update derived by hand (a held crane, where the model is the
identity on the positions and the filter is scalar per field), against the numpy implementation of
the same filter written independently (``EKF(backend="python")``) over a simulated episode, and
for its answers to bad input (a status code, the estimator untouched).
"""

from __future__ import annotations

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core
from cranepredict._cranepredict import ffi, lib
from cranepredict.live.estimator import EKF, ESTIMATED
from cranepredict.live.sim import LeverScript, Plant, SensorModel, SimCrane, perturbed_crane

N = lib.CRANE_EST_N
POS = slice(0, 4)


def _config(crane, noise=None):
    ekf = EKF(crane)
    c = ffi.new("crane_estimator_config *")
    c.lo, c.hi = list(ekf.lo), list(ekf.hi)
    c.noise = list(ekf._q if noise is None else noise)
    c.fd_step, c.scale = list(ekf._h), list(ekf._scale)
    c.dt = cp.DEFAULT_DT
    return c


def _x0(crane):
    rest = cp.state_at_rest(crane, 0.15, 0.30, slew=0.2, extension=0.4)
    return np.array([getattr(rest, n) or 0.0 for n in ESTIMATED])


def _held():
    inputs = ffi.new("crane_inputs *")   # a zero drive is a hold
    return inputs


def _model(crane):
    return _core._cached(crane, crane.geometry.extension_min)[1]


def test_a_held_crane_is_the_hand_derived_scalar_kalman_update(crane):
    """Every joint held: the positions and pressures stay, the rates are 0 (F is the identity on
    the positions and pressures, 0 on the rates). A diagonal covariance stays diagonal and each
    measured field is a scalar Kalman filter: P- = P + q T, g = P- / (P- + r),
    x+ = x + g (z - x), P+ = P- r / (P- + r)."""
    x0 = _x0(crane)
    p0 = np.array([1e-6] * 4 + [1e-4] * 4 + [1e10] * 8)
    q = np.array([1e-8] * 4 + [4e-3] * 4 + [2.5e11] * 8)
    est = ffi.new("crane_estimator *")
    assert lib.crane_estimator_init(est, _config(crane, q), list(x0), list(np.diag(p0).ravel()),
                                    [0.0] * 4) == lib.CRANE_OK
    z = x0 + np.array([2e-4, -1e-4, 1e-3, 5e-4] + [0.0] * 4 + [3e5, -2e5] + [0.0] * 6)
    r = np.array([4e-8] * 4 + [0.0] * 4 + [4e10, 4e10] + [0.0] * 6)   # lift's pressures measured
    period = 0.01
    assert lib.crane_estimator_update(est, _model(crane), _held(), period, list(z),
                                      list(r)) == lib.CRANE_OK
    p_minus = p0 + q * period
    p_minus[4:8] = q[4:8] * period            # the rates' rows of F are 0: only the noise is left
    measured = r > 0
    gain = np.where(measured, p_minus / (p_minus + np.where(measured, r, 1.0)), 0.0)
    x_expected = x0 + gain * (z - x0)
    x_expected[4:8] = 0.0                     # held: the model's rates are 0
    p_expected = np.where(measured, p_minus * r / (p_minus + np.where(measured, r, 1.0)), p_minus)
    x = np.array(list(est.x))
    P = np.array(list(est.covariance)).reshape(N, N)
    np.testing.assert_allclose(x[POS], x_expected[POS], rtol=0, atol=1e-12)
    np.testing.assert_allclose(x[8:], x_expected[8:], rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(np.diag(P), p_expected, rtol=1e-9)
    assert np.max(np.abs(P - np.diag(np.diag(P)))) <= 1e-9 * np.max(np.diag(P))
    # the normalised innovation squared is sum (z - x-)^2 / (P- + r) over the measured fields
    nis = np.sum(np.where(measured, (z - x0) ** 2 / (p_minus + np.where(measured, r, 1.0)), 0.0))
    assert est.n_measured == 6 and est.nis == pytest.approx(nis, rel=1e-9)


def test_the_covariance_is_kept_positive_definite(crane):
    """A covariance with a negative eigenvalue (rounding gone wrong) comes back symmetric with its
    eigenvalues, in the fields' scales, floored at 1e-12: numpy's eigen-decomposition, floored,
    gives the same matrix."""
    ekf = EKF(crane)
    scale = np.array(ekf._scale)
    rng = np.random.default_rng(3)
    a = rng.normal(size=(N, N))
    w, v = np.linalg.eigh(a + a.T)            # some eigenvalues negative
    assert w.min() < 0
    ps = (v * w) @ v.T
    est = ffi.new("crane_estimator *")
    cov = ps * np.outer(scale, scale)
    assert lib.crane_estimator_init(est, _config(crane), list(_x0(crane)), list(cov.ravel()),
                                    [0.0] * 4) == lib.CRANE_OK
    P = np.array(list(est.covariance)).reshape(N, N) / np.outer(scale, scale)
    expected = (v * np.maximum(w, 1e-12)) @ v.T
    np.testing.assert_allclose(P, expected, atol=1e-10)
    assert np.array_equal(P, P.T)
    assert np.linalg.eigvalsh(P).min() > 0.5e-12


@pytest.mark.parametrize("columns", [4, 16, 3])
def test_c_equals_the_independent_numpy_filter_over_an_episode(columns):
    """A simulated crane whose load is 30 % off, driven through all four levers, 2 s at 100 Hz:
    the C filter and the numpy one (the same algorithm, its algebra in another order) give the
    same estimate, renewing the Jacobian's columns in the same turn (4 and 3 a cycle) or all. The finite-difference Jacobian amplifies the algebra's rounding (1e-16
    relative) by the ratio of a field's scale to its step (1e5 Pa / 1e3 Pa for the pressures), so
    the pressures agree to about 1e-8 of their size: 1 Pa is asked, 1e-5 bar."""
    crane = cp.Crane.patu655()
    truth = perturbed_crane(crane, load=1.3)
    start = cp.state_at_rest(truth, 0.25, 0.35, slew=0.0, extension=0.3)
    script = LeverScript(((0.0, (0.0, 0.0, 0.0, 0.0)), (0.3, (0.6, 0.0, 0.0, 0.0)),
                          (1.0, (0.6, 0.5, 0.3, 0.4)), (1.6, (-0.4, -0.5, -0.3, -0.4))))
    sensors = cp.live.default_sensors()
    sim = SimCrane(Plant(truth, start), script, SensorModel(sensors, seed=5))
    measurements = []
    for _ in range(201):
        measurements.append(sim.measurement())
        sim.step(allowed=True)
    runs = {}
    for backend in ("c", "python"):
        ekf = EKF(crane, sensors, backend=backend, jacobian_columns=columns)
        xs = []
        for m in measurements:
            ekf.update(m)
            xs.append(ekf.x.copy())
        runs[backend] = (np.array(xs), ekf)
    xc, xp = runs["c"][0], runs["python"][0]
    assert np.max(np.abs(xc[:, 0:4] - xp[:, 0:4])) < 1e-9            # m, rad
    assert np.max(np.abs(xc[:, 4:8] - xp[:, 4:8])) < 1e-7            # m/s, rad/s
    assert np.max(np.abs(xc[:, 8:] - xp[:, 8:])) < 1.0               # Pa
    c, p = runs["c"][1], runs["python"][1]
    assert c.nis[-1][1] == p.nis[-1][1] and c.nis[-1][0] == pytest.approx(p.nis[-1][0], rel=1e-6)
    assert c.projections == p.projections
    scale = np.outer(c._scale, c._scale)
    assert np.max(np.abs(c.covariance - p.covariance) / scale) < 1e-6
    # the rates moved: the episode exercised the filter, not a crane at rest
    assert np.ptp(xc[:, 4]) > 0.02 and np.ptp(xc[:, 6]) > 0.05


def test_each_update_renews_its_share_of_the_jacobians_columns_in_turn(monkeypatch):
    """The numpy filter's futures per update: the nominal one and 16 columns on the first update,
    then the nominal one and 4 columns; the columns go round (the C filter's turn is the same:
    the test above); a whole-Jacobian filter differs from it only by the columns' age."""
    from cranepredict import api
    crane = cp.Crane.patu655()
    start = cp.state_at_rest(crane, 0.25, 0.35, slew=0.0, extension=0.3)
    sensors = cp.live.default_sensors()
    sim = SimCrane(Plant(crane, start), LeverScript(((0.0, (0.5, 0.3, 0.0, 0.0)),)),
                   SensorModel(sensors, seed=2))
    sizes = []
    real = api.predict_many

    def counting(crane_, initials, *args, **kwargs):
        sizes.append(len(initials))
        return real(crane_, initials, *args, **kwargs)

    monkeypatch.setattr(api, "predict_many", counting)
    ekf = EKF(crane, sensors, backend="python")
    assert ekf.jacobian_columns == 4
    turns = []
    for _ in range(7):
        ekf.update(sim.measurement())
        turns.append(ekf._next_column)
        sim.step(allowed=True)
    assert sizes == [17] + [5] * 5      # the first measurement initialises, predicting nothing
    assert turns == [0, 0, 4, 8, 12, 0, 4]
    ekf.reset()
    ekf.update(sim.measurement())
    sim.step(allowed=True)
    ekf.update(sim.measurement())
    assert sizes[-1] == 17              # after a (re)start: every column again


@pytest.mark.parametrize("value, error", [(0, ValueError), (17, ValueError), (-1, ValueError),
                                          (True, TypeError), (4.0, TypeError), ("4", TypeError)])
def test_jacobian_columns_is_checked(value, error):
    with pytest.raises(error, match="jacobian_columns"):
        EKF(cp.Crane.patu655(), jacobian_columns=value)


def test_init_refuses_jacobian_columns_outside_0_to_16(crane):
    for bad in (-1, N + 1):
        c = _config(crane)
        c.jacobian_columns = bad
        est = ffi.new("crane_estimator *")
        assert lib.crane_estimator_init(est, c, list(_x0(crane)), [0.0] * (N * N),
                                        [0.0] * 4) == lib.CRANE_E_ESTIMATOR


def _bytes(est):
    return bytes(ffi.buffer(est))


@pytest.mark.parametrize("field, value, status", [
    ("dt", float("nan"), "CRANE_E_ESTIMATOR"), ("dt", 0.0, "CRANE_E_ESTIMATOR"),
    ("fd_step", 0.0, "CRANE_E_ESTIMATOR"), ("scale", -1.0, "CRANE_E_ESTIMATOR"),
    ("noise", -1.0, "CRANE_E_ESTIMATOR"), ("hi", -1e9, "CRANE_E_ESTIMATOR"),
])
def test_init_refuses_a_bad_config(crane, field, value, status):
    c = _config(crane)
    if field == "dt":
        c.dt = value
    else:
        getattr(c, field)[3] = value
    est = ffi.new("crane_estimator *")
    before = _bytes(est)
    assert lib.crane_estimator_init(est, c, list(_x0(crane)), [0.0] * (N * N),
                                    [0.0] * 4) == getattr(lib, status)
    assert _bytes(est) == before


def test_init_refuses_a_start_outside_the_domain_and_a_bad_spool(crane):
    est = ffi.new("crane_estimator *")
    x0 = _x0(crane)
    cov = list(np.eye(N).ravel())
    bad = x0.copy()
    bad[0] = crane.lift_cylinder.stroke_max + 1e-3
    assert lib.crane_estimator_init(est, _config(crane), list(bad), cov, [0.0] * 4) == \
        lib.CRANE_E_ESTIMATOR
    assert lib.crane_estimator_init(est, _config(crane), list(x0), cov, [0, 1.5, 0, 0]) == \
        lib.CRANE_E_VALVE
    nan_cov = list(np.eye(N).ravel())
    nan_cov[5] = float("nan")
    assert lib.crane_estimator_init(est, _config(crane), list(x0), nan_cov, [0.0] * 4) == \
        lib.CRANE_E_NONFINITE
    assert lib.crane_estimator_init(ffi.NULL, _config(crane), list(x0), cov, [0.0] * 4) == \
        lib.CRANE_E_NULL


@pytest.mark.parametrize("period, z_bad, var_bad, status", [
    (0.0, None, None, "CRANE_E_HORIZON"), (-0.01, None, None, "CRANE_E_HORIZON"),
    (float("nan"), None, None, "CRANE_E_NONFINITE"),
    (0.01, float("nan"), None, "CRANE_E_NONFINITE"), (0.01, None, -1.0, "CRANE_E_ESTIMATOR"),
    (0.01, None, float("inf"), "CRANE_E_ESTIMATOR"),
])
def test_update_refuses_bad_arguments_and_leaves_the_estimator(crane, period, z_bad, var_bad,
                                                               status):
    est = ffi.new("crane_estimator *")
    x0 = _x0(crane)
    assert lib.crane_estimator_init(est, _config(crane), list(x0), list(np.eye(N).ravel() * 1e-6),
                                    [0.0] * 4) == lib.CRANE_OK
    z, var = list(x0), [0.0] * N
    var[0] = 4e-8
    if z_bad is not None:
        z[0] = z_bad
    if var_bad is not None:
        var[1] = var_bad
    before = _bytes(est)
    assert lib.crane_estimator_update(est, _model(crane), _held(), period, z, var) == \
        getattr(lib, status)
    assert _bytes(est) == before
    assert lib.crane_estimator_update(est, ffi.NULL, _held(), 0.01, z, var) == lib.CRANE_E_NULL
    assert "estimator" in ffi.string(lib.crane_status_message(getattr(lib, status))).decode() or \
        status != "CRANE_E_ESTIMATOR"
