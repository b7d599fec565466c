"""A crane_model points into its crane_params (crane.h): a model handed out by the binding's cache
must keep its params alive after the cache drops them (it clears itself after 64 cranes). Before
the fix the model read freed memory: the lift angle at stroke 0.2 m came out 2.15 rad, not 0.27."""

import gc

import pytest

import cranepredict as cp

_core = pytest.importorskip("cranepredict._core")


def test_a_model_outlives_a_cache_clear():
    from cranepredict._cranepredict import ffi, lib

    crane = cp.Crane.patu655()
    model = _core.model(crane, 0.0)
    want, _ = _core.joint_angle(crane, 0, 0.2, 0.0)
    _core._CACHE.clear()
    gc.collect()
    # reuse the freed memory with garbage of the params' size
    junk = [ffi.new("crane_params *") for _ in range(2000)]
    for j in junk:
        ffi.memmove(j, b"\x7f" * ffi.sizeof("crane_params"), ffi.sizeof("crane_params"))
    theta, ds = ffi.new("double *"), ffi.new("double *")
    assert lib.crane_joint_angle(model, 0, 0.2, theta, ds) == lib.CRANE_OK
    assert theta[0] == want
