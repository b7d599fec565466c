"""The collision guard on a moving slew and telescope: futures in which only slewing, or
only the telescope, brings the crane into contact, judged by the C core's crane_guard and checked
against brute force (every sample of a dense prediction of the pure-Python twin, posed
independently, coal's distances); and the guarantee of docs/guard.md "Nothing is missed" against
a dense resampling of the interpolated motion itself, with all four joints moving."""

from __future__ import annotations

import importlib
import math
import types

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import twin

coal = pytest.importorskip("coal")
G = importlib.import_module("cranepredict.guard")   # the module (cp.guard is the function)
from test_guard import _world, coal_clearances  # noqa: E402

REST = cp.State(lift_stroke=0.3, tilt_stroke=0.2)
VALUES = {"margin": 0.0, "reaction": 0.2, "cycle": 0.01, "time_tolerance": 1e-4,
          "clearance_tolerance": 1e-3}


@pytest.fixture(scope="module")
def crane() -> cp.Crane:
    return cp.Crane.patu655()


def _future(crane, lift=None, slew=None, extension=None, horizon=2.0, dt=0.001, state=REST):
    """A four-joint future of the twin (its own integrator, not the C core's), as a namespace of
    per-sample arrays."""
    inputs = types.SimpleNamespace(lift=lift or cp.Hold(), tilt=cp.Hold(), slew=slew,
                                   extension=extension)
    out, _ = twin._run(crane, state, inputs, horizon, dt)
    return types.SimpleNamespace(**out)


def _every(f, k):
    return types.SimpleNamespace(**{name: getattr(f, name)[::k] for name in G.SAMPLE_FIELDS})


def _guard(crane, world, f, every):
    """crane_guard on every `every`-th sample of the future f."""
    res, clearance = G._judge(crane, world, G._samples(_every(f, every)), crane.shape,
                              dict(VALUES, margin=world.margin))
    return res, clearance


def _clearance_at(crane, world, theta, slew, extension):
    pose = types.SimpleNamespace(slew=float(slew), extension=float(extension))
    return coal_clearances(crane, pose, theta, world)


def _brute_first(crane, world, f):
    """The first sample of f whose clearance (coal, independent posing) is at or below the margin."""
    for k in range(len(f.t)):
        if _clearance_at(crane, world, f.theta[k], f.slew[k], f.extension[k]).min() <= world.margin:
            return k
    return None


WALL_BESIDE = {"name": "wall", "kind": "box", "centre": [4.0, 2.6, 1.5], "size": [8.0, 0.3, 6.0]}


@pytest.mark.slow
def test_slewing_alone_meets_a_wall_beside_the_crane(crane):
    """Boom held, the slew driven (60 bar): the tip swings toward a wall beside the crane (parallel
    to X, 2.45 m to the side). Held, the slew finds nothing; slewing, the guard (every 10th sample
    of 1 ms) finds the contact no later than brute force on every sample, and at most one sample
    (+ the time tolerance) earlier; the contact names the slew as the closing lever."""
    world = _world(0.2, WALL_BESIDE)
    still = _future(crane, horizon=2.0)
    res, _ = _guard(crane, world, still, 10)
    assert not res.contact
    f = _future(crane, slew=cp.Pressure(p_a=60e5, p_b=0.0))
    assert f.slew[-1] > 0.9 and np.ptp(f.theta, axis=0).max() == 0.0   # only the slew moves
    k = _brute_first(crane, world, f)
    res, _ = _guard(crane, world, f, 10)
    assert k is not None and res.contact and not res.at_start
    t_bf = f.t[k]
    assert res.t <= t_bf + 1e-12 and t_bf - res.t <= 0.001 + 1e-4
    assert res.slew == pytest.approx(np.interp(res.t, f.t, f.slew), abs=1e-6)
    assert res.approach[2] < 0 and res.approach[0] == 0 and res.approach[3] == 0


def test_telescope_alone_meets_a_wall_ahead(crane):
    """Boom and slew held, the telescope driven (2 bar): the load moves out along the outer boom
    toward a wall ahead. Held, nothing; telescoping, the first contact as by brute force."""
    world = _world(0.2, {"name": "wall", "kind": "box", "centre": [5.7, 0.0, 1.5],
                         "size": [0.3, 8.0, 6.0]})
    res, _ = _guard(crane, world, _future(crane, horizon=1.0), 10)
    assert not res.contact
    f = _future(crane, extension=cp.Pressure(p_a=2e5, p_b=0.0), horizon=1.0)
    assert np.ptp(f.theta, axis=0).max() == 0.0 and np.ptp(f.slew) == 0.0
    k = _brute_first(crane, world, f)
    res, _ = _guard(crane, world, f, 10)
    assert k is not None and res.contact and not res.at_start
    t_bf = f.t[k]
    assert 0.2 < t_bf < 0.95                               # before the telescope's end stop
    assert res.t <= t_bf + 1e-12 and t_bf - res.t <= 0.001 + 1e-4
    assert res.approach[3] < 0 and res.approach[2] == 0 and res.approach[0] == 0


# -- the guarantee against the interpolated motion itself ---------------------------------------

def _hermite(f, k, u):
    """The cubic Hermite interpolant of sample k -> k + 1 of f at fractions u, per coordinate
    (theta0, theta1, slew, extension), in the standard basis (written apart from guard.c's)."""
    h = f.t[k + 1] - f.t[k]
    h00, h10 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u
    h01, h11 = -2 * u**3 + 3 * u**2, u**3 - u**2
    out = []
    for x, v in ((f.theta[:, 0], f.omega[:, 0]), (f.theta[:, 1], f.omega[:, 1]),
                 (f.slew, f.slew_rate), (f.extension, f.extension_rate)):
        out.append(h00 * x[k] + h10 * h * v[k] + h01 * x[k + 1] + h11 * h * v[k + 1])
    return np.array(out).T


def _dense_first(crane, world, coarse, per_step):
    """The first time of the interpolated motion, resampled per_step times per step, at which a
    clearance is at or below the margin (None if never), and the smallest clearance."""
    u = np.arange(per_step) / per_step
    least = math.inf
    for k in range(len(coarse.t) - 1):
        for ui, q in zip(u, _hermite(coarse, k, u)):
            c = _clearance_at(crane, world, q[:2], q[2], q[3]).min()
            least = min(least, c)
            if c <= world.margin:
                return coarse.t[k] + ui * (coarse.t[k + 1] - coarse.t[k]), least
    return None, least


@pytest.mark.slow
def test_nothing_is_missed_with_all_four_joints_moving(crane):
    """Lifting, slewing and telescoping at once; the guard judges samples 50 ms apart. Random
    obstacles (boxes, spheres, wires) near the path of the load and the extension boom. Against
    the same interpolated motion resampled 100 times per step with coal: the first contact is
    never later than the first dense contact and at most one dense step (0.5 ms) + a few time
    tolerances earlier; without a contact, the motion stays clear of the margin everywhere."""
    f = _future(crane, lift=cp.Pressure(p_a=120e5, p_b=0.0), slew=cp.Pressure(p_a=40e5, p_b=0.0),
                extension=cp.Pressure(p_a=0.0, p_b=5e5), horizon=1.0, dt=0.005,
                state=cp.State(lift_stroke=0.3, tilt_stroke=0.2, extension=0.3))
    assert f.slew[-1] > 0.3 and np.ptp(f.extension) > 0.05 and np.ptp(f.theta[:, 0]) > 0.5
    coarse = _every(f, 10)
    rng = np.random.default_rng(11)
    tip = f.tip
    found = 0
    for trial in range(8):
        obstacles = []
        for i, kind in enumerate(("box", "sphere", "capsule")):
            p = tip[rng.integers(len(f.t))] + rng.normal(0, 1.0, 3) - [0, 0, 0.6]
            o = {"name": f"o{i}", "kind": kind}
            if kind == "box":
                o.update(centre=p.tolist(), size=rng.uniform(0.2, 0.8, 3).tolist(),
                         yaw=float(rng.uniform(0, 3)))
            elif kind == "sphere":
                o.update(centre=p.tolist(), radius=float(rng.uniform(0.1, 0.4)))
            else:
                d = rng.normal(0, 1, 3)
                d /= np.linalg.norm(d)
                o.update(a=(p - 2 * d).tolist(), b=(p + 2 * d).tolist(), radius=0.0)
            obstacles.append(o)
        world = _world(0.15, *obstacles)
        res, _ = _guard(crane, world, coarse, 1)
        t_dense, least = _dense_first(crane, world, coarse, 100)
        if t_dense is None:
            assert not res.contact, f"trial {trial}: a contact the dense motion does not have"
            assert least > world.margin
        else:
            found += 1
            print(f"trial {trial}: contact at {res.t:.5f} s, dense {t_dense:.5f} s, sample step {res.t / 0.05:.3f}")
            assert res.contact, f"trial {trial}: missed a contact at {t_dense:.4f} s"
            assert res.t <= t_dense + 1e-12 and t_dense - res.t <= 0.0005 + 5e-4
    assert 0 < found < 8
