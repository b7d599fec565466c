"""predict_many: the batch equals predict() future by future (exactly), and bad input is rejected
with the index of the bad future."""

from __future__ import annotations

import numpy as np
import pytest

import cranepredict as cp

from conftest import random_drive

HORIZON = 0.4
DT = 2e-3


def _futures(crane: cp.Crane, n: int, seed: int = 4, horizon: float = HORIZON):
    rng = np.random.default_rng(seed)
    lift, tilt, g = crane.lift_cylinder, crane.tilt_cylinder, crane.geometry
    initials, inputs = [], []
    for k in range(n):
        li, ti = random_drive(rng, horizon), random_drive(rng, horizon)
        # Some futures start on a stroke limit (end stops at t = 0), some at an extension.
        ls = lift.stroke_min if k % 7 == 3 else float(rng.uniform(lift.stroke_min, lift.stroke_max))
        ts = tilt.stroke_max if k % 5 == 2 else float(rng.uniform(tilt.stroke_min, tilt.stroke_max))
        ext = float(rng.uniform(g.extension_min, g.extension_max)) if k % 3 == 0 else 0.0
        initials.append(cp.State(lift_stroke=ls, tilt_stroke=ts, slew=float(rng.uniform(-3, 3)),
                                 extension=ext))
        inputs.append(cp.Inputs(lift=li, tilt=ti))
    return initials, inputs


FIELDS = cp.types.ARRAYS


@pytest.mark.parametrize("threads", [1, 2])   # at most the cores (CI: 2)
def test_equals_predict(crane, threads):
    initials, inputs = _futures(crane, 24)
    batch = cp.predict_many(crane, initials, inputs, HORIZON, dt=DT, threads=threads)
    assert len(batch) == 24
    n = int(np.ceil(HORIZON / DT - 1e-9)) + 1
    assert batch.tip.shape == (24, n, 3) and batch.theta.shape == (24, n, 2) and batch.t.shape == (n,)
    for k in range(24):
        one = cp.predict(crane, initials[k], inputs[k], HORIZON, dt=DT)
        for name in FIELDS:
            assert np.array_equal(getattr(batch[k], name), getattr(one, name)), (k, name)
        for name in ("slew", "extension", "slew_rate", "extension_rate"):
            assert np.array_equal(getattr(batch[k], name), getattr(one, name)), (k, name)


@pytest.mark.parametrize("every", [1, 3, 7, 200, 1000])
def test_sample_every_keeps_every_mth_step_and_the_last(crane, every):
    horizon, dt = 0.411, 2e-3         # 206 steps, the last one short
    initials, inputs = _futures(crane, 5, seed=9, horizon=horizon)
    batch = cp.predict_many(crane, initials, inputs, horizon, dt=dt, sample_every=every)
    n_steps = int(np.ceil(horizon / dt - 1e-9))
    keep = list(range(0, n_steps + 1, every))
    if keep[-1] != n_steps:
        keep.append(n_steps)
    assert batch.sample_every == every
    for k in range(5):
        one = cp.predict(crane, initials[k], inputs[k], horizon, dt=dt)
        for name in FIELDS:
            assert np.array_equal(getattr(batch[k], name), getattr(one, name)[keep]), (k, name)


def test_empty_and_single(crane):
    initials, inputs = _futures(crane, 1)
    assert len(cp.predict_many(crane, [], [], HORIZON, dt=DT)) == 0
    one = cp.predict_many(crane, initials, inputs, HORIZON, dt=DT)
    assert np.array_equal(one.tip[0], cp.predict(crane, initials[0], inputs[0], HORIZON, dt=DT).tip)


def test_points_and_read_only(crane):
    initials, inputs = _futures(crane, 3)
    batch = cp.predict_many(crane, initials, inputs, HORIZON, dt=DT)
    pts = batch[2].points()
    assert np.allclose(pts["tip"], batch.tip[2], atol=1e-12)
    with pytest.raises(ValueError):
        batch.tip[0, 0, 0] = 1.0
    with pytest.raises(IndexError):
        batch[3]


def test_mismatched_lengths(crane):
    initials, inputs = _futures(crane, 4)
    with pytest.raises(ValueError, match="same length.*4 and 3"):
        cp.predict_many(crane, initials, inputs[:3], HORIZON, dt=DT)


@pytest.mark.parametrize("k", [0, 5, 11])
def test_bad_future_names_its_index(crane, k):
    initials, inputs = _futures(crane, 12)
    lift = crane.lift_cylinder
    bad = list(initials)
    bad[k] = cp.State(lift_stroke=lift.stroke_max + 0.01, tilt_stroke=0.3)
    with pytest.raises(ValueError, match=rf"future {k} .*lift_stroke"):
        cp.predict_many(crane, bad, inputs, HORIZON, dt=DT)
    bad_inputs = list(inputs)
    bad_inputs[k] = cp.Inputs(lift=cp.PressureSeries(t=[0.0, HORIZON / 2], p_a=[1e5, 1e5],
                                                     p_b=[0.0, 0.0]), tilt=cp.Hold())
    with pytest.raises(ValueError, match=rf"future {k} .*cover"):
        cp.predict_many(crane, initials, bad_inputs, HORIZON, dt=DT)
    wrong_type = list(inputs)
    wrong_type[k] = "not inputs"
    with pytest.raises(TypeError, match=rf"future {k} "):
        cp.predict_many(crane, initials, wrong_type, HORIZON, dt=DT)


def test_bad_shared_arguments(crane):
    initials, inputs = _futures(crane, 2)
    with pytest.raises(ValueError, match="dt"):
        cp.predict_many(crane, initials, inputs, HORIZON, dt=-1.0)
    with pytest.raises(ValueError, match="sample_every"):
        cp.predict_many(crane, initials, inputs, HORIZON, dt=DT, sample_every=0)
    with pytest.raises(ValueError, match="threads"):
        cp.predict_many(crane, initials, inputs, HORIZON, dt=DT, threads=0)
    with pytest.raises(TypeError, match="Crane"):
        cp.predict_many("patu", initials, inputs, HORIZON, dt=DT)


def test_inputs_not_modified(crane):
    initials, inputs = _futures(crane, 4)
    before = (list(initials), list(inputs))
    cp.predict_many(crane, initials, inputs, HORIZON, dt=DT)
    assert (initials, inputs) == before


# -- a crane per future (vary) ---------------------------------------------------------------------

def _replaced(crane: cp.Crane, dotted: str, value: float) -> cp.Crane:
    """The crane with one nested field replaced, built the ordinary way (a Crane, checked)."""
    import dataclasses

    head, _, rest = dotted.partition(".")
    if not rest:
        return dataclasses.replace(crane, **{head: value})
    return dataclasses.replace(crane, **{head: _replaced(getattr(crane, head), rest, value)})


@pytest.mark.parametrize("threads", [1, 2])
def test_vary_equals_predict_with_each_crane(crane, threads):
    """Each future of a varied batch is predict() with a Crane built with its values, exactly: the
    load (pressure drives) and the lift valve's supply and friction (valve drives)."""
    rng = np.random.default_rng(11)
    n = 20
    valve = cp.scenarios.get("valve-lift-step")
    initials = [valve.initial] * n
    inputs = [valve.inputs] * n
    vary = {"load_mass": rng.uniform(100, 300, n),
            "lift_cylinder.hydraulics.supply_pressure":
                valve.crane.lift_cylinder.hydraulics.supply_pressure * rng.uniform(0.9, 1.1, n),
            "lift_cylinder.friction.factor": rng.uniform(2, 6, n)}
    before = {k: v.copy() for k, v in vary.items()}
    batch = cp.predict_many(valve.crane, initials, inputs, HORIZON, dt=DT, threads=threads, vary=vary)
    for k in (0, 7, 19):
        c = valve.crane
        for name, values in vary.items():
            c = _replaced(c, name, float(values[k]))
        one = cp.predict(c, initials[k], inputs[k], HORIZON, dt=DT)
        for field in FIELDS:
            assert np.array_equal(getattr(batch[k], field), getattr(one, field)), (k, field)
    assert all(np.array_equal(before[k], vary[k]) for k in vary)   # the caller's arrays untouched
    # and the values matter: a heavier load under the same lever ends lower
    heavy, light = int(np.argmax(vary["load_mass"])), int(np.argmin(vary["load_mass"]))
    assert batch[heavy].tip[-1, 2] != batch[light].tip[-1, 2]


def test_vary_bad_input_names_field_and_range(crane):
    initials, inputs = _futures(crane, 3)
    cases = [({"geometry.tip_distance": [1, 2, 3]}, ValueError, "not a field predict_many can vary"),
             ({"load_mass": [1, 2]}, ValueError, r"one value per future \(3\)"),
             ({"load_mass": [1, float("nan"), 2]}, ValueError, r"future 1 .*load_mass must be finite"),
             ({"load_mass": [1, -5, 2]}, ValueError, r"future 1 \(vary\): load_mass must be >= 0, got -5"),
             ({"lift_cylinder.friction.static": [1e9, 1e9, 1.0]}, ValueError,
              r"future 2 \(vary\): lift_cylinder.friction.static must be >= "
              r"lift_cylinder.friction.coulomb"),
             (["load_mass"], TypeError, "vary must be a mapping")]
    for vary, kind, text in cases:
        with pytest.raises(kind, match=text):
            cp.predict_many(crane, initials, inputs, HORIZON, dt=DT, vary=vary)
    no_slew = _replaced(crane, "slew_drive", None)
    with pytest.raises(ValueError, match="has no slew_drive.friction table"):
        cp.predict_many(no_slew, initials, inputs, HORIZON, dt=DT,
                        vary={"slew_drive.friction.factor": [1, 1, 1]})


@pytest.mark.parametrize("every", [3, 5])
def test_knots_on_the_sample_grid_read_the_same_with_any_sample_every(crane, every):
    """A sampled drive whose knots lie on the sample grid: a sample time on a knot reads the
    segment that starts there, whichever segment the samples before it left the drive's cursor in
    (the error-controlled method's dense output reads the drive at the kept samples only, so
    sample_every moves the cursor differently): the kept samples equal predict()'s, bit for bit.
    (Found by the fuzzer: the segment that ends at the knot gave a + 1 (b - a), not b.)"""
    t = np.array([-0.1, -0.05, 0.0, 0.05, 0.1, 0.15, 0.2])
    p_a = np.array([0.0, 1e6, 2e6, 3e6, 4e6 + 0.1, 0.3, 1e6])
    p_b = np.array([0.0, 5e5, 1e6, 0.0, 5e5 + 0.1, 0.3, 0.0])
    assert p_a[4] + 1.0 * (p_a[5] - p_a[4]) != p_a[5]   # the two segments differ at t = 0.15
    inputs = cp.Inputs(lift=cp.PressureSeries(t=t, p_a=p_a, p_b=p_b), tilt=cp.Hold())
    initial = cp.State(lift_stroke=0.116, tilt_stroke=0.2)
    one = cp.predict(crane, initial, inputs, 0.2, dt=1e-3)
    batch = cp.predict_many(crane, [initial] * 2, [inputs] * 2, 0.2, dt=1e-3, sample_every=every)
    keep = list(range(0, len(one.t), every))
    if keep[-1] != len(one.t) - 1:
        keep.append(len(one.t) - 1)
    assert one.p_a[150, 0] == 0.3
    for k in range(2):
        for name in FIELDS:
            assert np.array_equal(getattr(batch[k], name), getattr(one, name)[keep]), (k, name)
