"""Bounded work and C entry points that answered OK to bad input.

The limits are the C core's (crane.h: CRANE_MAX_STEPS, CRANE_MAX_SAMPLES, CRANE_MAX_BATCH_STEPS),
checked before anything runs; csrc/tests/test_bounds.c checks the same in the C-only, float and
cross builds.
"""

from __future__ import annotations

import time

import pytest

import cranepredict as cp
from cranepredict import _core
from cranepredict._cranepredict import ffi, lib

def _boom_torques(crane, extension, theta, omega, alpha):
    """The booms' torques of the core's inverse dynamics with the slew and the extension at rest."""
    q = (theta[0], theta[1], 0.0, extension)
    return _core.inverse_dynamics(crane, q, (omega[0], omega[1], 0.0, 0.0),
                                  (alpha[0], alpha[1], 0.0, 0.0))[:2]



def _mid_angles(crane):
    """The middle of each joint's angle range (from the stroke limits, through the public API)."""
    mid = []
    for joint, cyl in ((lib.CRANE_LIFT, crane.lift_cylinder), (lib.CRANE_TILT, crane.tilt_cylinder)):
        a = _core.joint_angle(crane, joint, cyl.stroke_min)[0]
        b = _core.joint_angle(crane, joint, cyl.stroke_max)[0]
        mid.append((a + b) / 2)
    return tuple(mid)


def _tilt_lower_limit(crane):
    return min(_core.joint_angle(crane, lib.CRANE_TILT, s)[0]
               for s in (crane.tilt_cylinder.stroke_min, crane.tilt_cylinder.stroke_max))


def _args():
    return cp.State(lift_stroke=0.1, tilt_stroke=0.2), cp.Inputs(lift=cp.Hold(), tilt=cp.Hold())


def test_limits_are_core_constants():
    assert lib.CRANE_MAX_STEPS == 2**20
    assert lib.CRANE_MAX_SAMPLES == 2**23 and lib.CRANE_MAX_BATCH_STEPS == 2**23
    n = ffi.new("size_t *")
    assert lib.crane_sample_count(lib.CRANE_MAX_STEPS * 1e-3, 1e-3, n) == lib.CRANE_OK
    assert n[0] == lib.CRANE_MAX_STEPS + 1


@pytest.mark.parametrize("horizon, dt", [(1e9, 1e-3), (1.0, 1e-12), (1e5, 1e-3)])
def test_too_many_steps_is_refused_before_anything_runs(crane, horizon, dt):
    # Finding 3: horizon = 1e9 or dt = 1e-12 died in numpy ("Unable to allocate 40 TiB"),
    # horizon = 1e5 allocated 4.4 GB.
    state, inputs = _args()
    n = ffi.new("size_t *")
    assert lib.crane_sample_count(horizon, dt, n) == lib.CRANE_E_STEPS
    with pytest.raises(ValueError, match="MAX_STEPS"):
        cp.predict(crane, state, inputs, horizon, dt=dt)


def test_huge_sample_every_with_a_huge_horizon_is_refused_at_once(crane):
    # Finding 3: predict_many(..., horizon=1e9, sample_every=10**12) ran for hours.
    state, inputs = _args()
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match="MAX_STEPS"):
        cp.predict_many(crane, [state], [inputs], 1e9, dt=1e-3, sample_every=10**12)
    assert time.perf_counter() - t0 < 1.0


def test_one_calls_samples_and_work_are_bounded(crane):
    state, inputs = _args()
    st = ffi.new("crane_state[]", 40)
    inp = ffi.new("crane_inputs[]", 40)
    for k in range(40):
        _core._state(st[k], state)
        _core._inputs(inp[k], inputs, [])
    out = ffi.new("crane_sample[]", 2)
    failed = ffi.new("size_t *")
    p = _core.params(crane)
    # 9 futures x 1,000,001 samples > 2^23; 9 futures x 1,000,000 steps (11 samples each) > 2^23
    assert lib.crane_predict_many(p, 1, 9, st, inp, 1000.0, 1e-3, 1, out, 2, failed,
                                  _core.work()) == \
        lib.CRANE_E_SAMPLE_COUNT
    assert lib.crane_predict_many(p, 1, 9, st, inp, 1000.0, 1e-3, 100000, out, 2, failed,
                                  _core.work()) == \
        lib.CRANE_E_BATCH
    assert failed[0] == 9


def test_cylinder_force_at_stroke_rate_1e307_is_an_error(crane):
    # Finding 5: returned -inf with CRANE_OK.
    with pytest.raises(_core.CoreError) as info:
        _core.cylinder_force(crane, lib.CRANE_LIFT, 0.0, 0.0, 1e307)
    assert info.value.status == lib.CRANE_E_OVERFLOW


def test_inverse_dynamics_at_omega_1e160_is_an_error(crane):
    # Finding 5: returned +-inf with CRANE_OK.
    with pytest.raises(_core.CoreError) as info:
        _boom_torques(crane, 0.0, _mid_angles(crane), (0.0, 1e160), (0.0, 0.0))
    assert info.value.status == lib.CRANE_E_OVERFLOW


def test_inverse_dynamics_where_the_four_bar_is_open_is_an_error(crane):
    # Finding 5: crane_joint_stroke rejected this tilt angle, inverse dynamics answered OK.
    theta = (_mid_angles(crane)[0], _tilt_lower_limit(crane) - 0.3)
    with pytest.raises(_core.CoreError, match="outside the range"):
        _core.joint_stroke(crane, lib.CRANE_TILT, theta[1])
    with pytest.raises(_core.CoreError) as info:
        _boom_torques(crane, 0.0, theta, (0.0, 0.0), (0.0, 0.0))
    assert info.value.status == lib.CRANE_E_ANGLE


def test_points_with_n_near_size_max_over_2_is_an_error(crane):
    # Finding 5: 2 n wrapped and the pose loop read past the caller's array.
    m = _core.model(crane, 0.0)
    theta = ffi.new("crane_real[2]", list(_mid_angles(crane)))
    xyz = ffi.new("crane_real[]", 3 * lib.CRANE_N_POINTS)
    n = 2 ** (8 * ffi.sizeof("size_t") - 1)  # SIZE_MAX / 2 + 1
    assert lib.crane_points(m, 0.0, n, theta, xyz) == lib.CRANE_E_OVERFLOW
    assert lib.crane_points(m, 0.0, 1, theta, xyz) == lib.CRANE_OK
