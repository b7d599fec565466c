"""Bounded work and memory (MAX_STEPS, MAX_SAMPLES, checked before anything runs), a batch that
Ctrl-C stops, and a cache that cannot change a result."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _checks, _core, twin
from cranepredict._cranepredict import lib

STATE = cp.State(lift_stroke=0.1, tilt_stroke=0.3)
INPUTS = cp.Inputs(lift=cp.Pressure(100e5, 0), tilt=cp.Hold())


@pytest.fixture
def nothing_runs(monkeypatch):
    """Fails the test if a prediction is run or its output allocated."""
    def forbidden(*args, **kwargs):
        raise AssertionError("a prediction ran although its arguments are over a limit")

    for target, name in ((_core, "predict"), (_core, "predict_many"), (twin, "simulate")):
        monkeypatch.setattr(target, name, forbidden)


def test_limits_are_the_c_cores():
    assert _checks.PRESSURE_MAX == lib.CRANE_PRESSURE_MAX
    assert cp.MAX_STEPS == lib.CRANE_MAX_STEPS
    assert cp.MAX_SAMPLES == lib.CRANE_MAX_SAMPLES


def test_step_count_is_the_c_cores():
    rng = np.random.default_rng(3)
    for _ in range(200):
        dt = float(10 ** rng.uniform(-5, -1))
        horizon = dt * float(rng.choice([1, 7, 1000, 12345.5, rng.uniform(1, 1e5)]))
        assert _checks.step_count(horizon, dt) + 1 == _core.sample_count(horizon, dt), (horizon, dt)


# The findings: predict_many(..., horizon=1e9, sample_every=10**12) ran for hours;
# horizon=1e9 or dt=1e-12 died in numpy ("Unable to allocate 40 TiB"); horizon=1e5 allocated 4.4 GB.
@pytest.mark.parametrize("backend", cp.BACKENDS)
@pytest.mark.parametrize("horizon, dt, words", [
    (1e9, 2e-3, r"horizon / dt must be at most 1,048,576 steps \(cranepredict.MAX_STEPS\), got "
                r"horizon 1e\+09 s / dt 0.002 s"),
    (1.0, 1e-12, r"at most 1,048,576 steps .* dt 1e-12 s"),
    (1e300, 1e-300, r"at most 1,048,576 steps .* = inf steps"),  # horizon / dt overflows
    (1e5, 2e-3, r"at most 1,048,576 steps .* = 50,000,000 steps"),
    (2097.154, 2e-3, r"at most 1,048,576 steps .* = 1,048,577 steps"),
    # (one prediction's MAX_STEPS + 1 samples are below MAX_SAMPLES: the steps limit comes first)
    (1e4, 2e-3, r"at most 1,048,576 steps .* = 5,000,000 steps"),
])
def test_predict_refuses_work_over_the_limits(crane, nothing_runs, backend, horizon, dt, words):
    with pytest.raises(ValueError, match=words):
        cp.predict(crane, STATE, INPUTS, horizon, dt=dt, backend=backend)


@pytest.mark.parametrize("kwargs, n, words", [
    (dict(horizon=1e9, dt=2e-3, sample_every=10**12), 1, r"at most 1,048,576 steps .* horizon 1e\+09 s"),
    (dict(horizon=1e9, dt=2e-3, sample_every=1000), 1, r"at most 1,048,576 steps .* horizon 1e\+09 s"),
    (dict(horizon=2.0, dt=1e-12), 1, r"at most 1,048,576 steps .* dt 1e-12 s"),
    (dict(horizon=2.0, sample_every=10**30), 1, r"sample_every must be an int in \[1, 1,048,576\] "
                                                r"\(cranepredict.MAX_STEPS\), got 1000000000000000000000000000000"),
    (dict(horizon=2.0, dt=2e-3), 8400, r"at most 8,388,608 samples \(cranepredict.MAX_SAMPLES\), got 8,400 "
                              r"futures x 1,001 samples .* sample_every 1"),
])
def test_predict_many_refuses_work_over_the_limits(crane, nothing_runs, kwargs, n, words):
    horizon = kwargs.pop("horizon")
    with pytest.raises(ValueError, match=words):
        cp.predict_many(crane, [STATE] * n, [INPUTS] * n, horizon, **kwargs)


def test_the_limits_themselves_are_accepted(crane, nothing_runs):
    # The largest step count, thinned to two samples.
    horizon = cp.MAX_STEPS * 1e-3
    assert _checks.step_count(horizon, 1e-3) == cp.MAX_STEPS
    assert _checks.kept_samples(cp.MAX_STEPS, cp.MAX_STEPS) == 2
    with pytest.raises(ValueError, match="at most 1,048,576 steps"):
        _checks.step_count(horizon * (1 + 1e-12), 1e-3)
    # A batch of exactly MAX_SAMPLES samples passes the checks (and reaches the stubbed run); one
    # future more does not. dt = 2^-10 s so that horizon / dt is exact.
    dt = 2.0 ** -10
    horizon = 8191 * dt  # 8191 steps, 8192 samples: 1024 futures make 2^23
    assert cp.MAX_SAMPLES == 1024 * 8192
    with pytest.raises(AssertionError, match="a prediction ran"):
        cp.predict_many(crane, [STATE] * 1024, [INPUTS] * 1024, horizon, dt=dt)
    with pytest.raises(ValueError, match="got 1,025 futures x 8,192 samples"):
        cp.predict_many(crane, [STATE] * 1025, [INPUTS] * 1025, horizon, dt=dt)


def test_predict_many_stops_between_chunks_on_ctrl_c(crane, monkeypatch):
    """A long batch runs in chunks of CHUNK_STEPS steps; Ctrl-C stops it after the chunk it arrived
    in, not after the whole batch. Python runs a SIGINT's handler in the main thread at its first
    bytecode after the C call returns: the KeyboardInterrupt is raised right where the chunk
    returns. (Raised here rather than sent by _thread.interrupt_main: that one is delivered at the
    main thread's next eval check, which may fall in a finaliser the garbage collector runs, where
    Python reports the exception as unraisable and drops it.)"""
    calls = []
    real = _core._run_chunk

    def chunk_then_ctrl_c(*args):
        calls.append(args[2])
        real(*args)
        raise KeyboardInterrupt

    monkeypatch.setattr(_core, "CHUNK_STEPS", 500)  # 250-step futures: 2 futures per chunk
    monkeypatch.setattr(_core, "_run_chunk", chunk_then_ctrl_c)
    with pytest.raises(KeyboardInterrupt):
        cp.predict_many(crane, [STATE] * 40, [INPUTS] * 40, 0.5, dt=2e-3, threads=1)
    assert calls == [2], calls


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="needs os.fork")
def test_a_threaded_batch_runs_in_a_forked_child(crane):
    """The batches' worker threads are kept between calls; a child forked after a threaded batch
    (multiprocessing's default on Linux) has none of them, and must make its own rather than queue
    its slices for threads that do not exist there (it hung until its alarm)."""
    import os
    import signal
    whole = cp.predict_many(crane, [STATE] * 4, [INPUTS] * 4, 0.5, threads=2)
    pid = os.fork()
    if pid == 0:   # the child: exit 0 if its threaded batch ran and equals the parent's
        code = 1
        try:
            signal.alarm(30)
            again = cp.predict_many(crane, [STATE] * 4, [INPUTS] * 4, 0.5, threads=2)
            code = 0 if np.array_equal(again.tip, whole.tip) else 2
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0


def test_chunked_batch_equals_one_call(crane, monkeypatch):
    from cranepredict import api

    initials = [cp.State(lift_stroke=0.05 + 0.01 * k, tilt_stroke=0.3) for k in range(30)]
    inputs = [cp.Inputs(lift=cp.Pressure(60e5 + 1e5 * k, 0), tilt=cp.Hold()) for k in range(30)]
    whole = cp.predict_many(crane, initials, inputs, 0.5, threads=1)
    monkeypatch.setattr(_core, "CHUNK_STEPS", 700)  # 2 futures of 250 steps per chunk
    for threads in (1, 2, 3):   # 3 through the core layer: the API allows at most the cores
        chunked = api._sample_arrays(_core.predict_many(crane, initials, inputs, 0.5,
                                                        cp.DEFAULT_DT, 1, threads))
        for name in cp.types.ARRAYS:
            got = chunked[name][0] if name == "t" else chunked[name]
            assert np.array_equal(got, getattr(whole, name)), (threads, name)


def test_chunked_batch_names_the_failed_future(crane, monkeypatch):
    """An error of the C core in a later chunk still names the right future (the Python checks
    are bypassed here to reach the C core's own)."""
    from cranepredict import api

    initials = [STATE] * 9 + [cp.State(lift_stroke=0.1, tilt_stroke=0.3, extension=5.0)]
    monkeypatch.setattr(api, "_check_future", lambda *a: None)
    monkeypatch.setattr(_core, "CHUNK_STEPS", 1000)
    with pytest.raises(_core.CoreError, match=r"predict_many \(future 9\)"):
        cp.predict_many(crane, initials, [INPUTS] * 10, 0.5, threads=2)


# -- the cache ------------------------------------------------------------

def _crane_with_rod_y(crane, y):
    d = copy.deepcopy(crane.to_dict())
    d["geometry"]["lift_cylinder_rod"] = [-0.3025, y]  # the rod eye on the -x axis: atan2 = +-pi
    return cp.Crane.from_dict(d)


def test_a_crane_with_minus_zero_is_not_served_another_cranes_struct(crane):
    """-0.0 == 0.0, so an equality-keyed cache gave the second crane the first one's struct: the
    lift angle then came out 2 pi from the twin's."""
    plus = _crane_with_rod_y(crane, 0.0)
    minus = _crane_with_rod_y(crane, -0.0)
    assert plus == minus  # equal as dataclasses, yet not the same numbers
    state = cp.State(lift_stroke=0.3, tilt_stroke=0.3)
    c_plus = cp.predict(plus, state, INPUTS, 0.1)
    c_minus = cp.predict(minus, state, INPUTS, 0.1)
    for c, tr in ((plus, c_plus), (minus, c_minus)):
        py = cp.predict(c, state, INPUTS, 0.1, backend="python")
        np.testing.assert_allclose(tr.theta, py.theta, atol=1e-12)
        assert math.copysign(1.0, _core.params(c).lift_cylinder_rod.y) == math.copysign(1.0, c.geometry.lift_cylinder_rod[1])
    assert abs(c_plus.theta[0, 0] - c_minus.theta[0, 0]) == pytest.approx(2 * math.pi)


def test_models_are_keyed_by_the_extensions_bits(crane):
    _, m_plus = _core._cached(crane, 0.0)
    _, m_minus = _core._cached(crane, -0.0)
    assert m_plus is not m_minus
    assert _core._cached(crane, 0.0)[1] is m_plus


def test_one_cache_holds_each_struct_once(crane):
    prm, m = _core._cached(crane, 0.25)
    assert _core.params(crane) is prm and _core.model(crane, 0.25) is m
    assert not hasattr(_core.params, "cache_info") and not hasattr(_core.model, "cache_info")


def test_params_of_a_crane_is_built_without_deriving_a_model(crane, monkeypatch):
    """The crane's validator reads params() of a crane that may not pass crane_model_init."""
    other = cp.Crane.from_dict(crane.to_dict())
    _core._CACHE.pop(id(other), None)
    monkeypatch.setattr(_core, "ensure", lambda *a: (_ for _ in ()).throw(AssertionError("checked")))
    assert _core.params(other).lift_boom.mass == crane.lift_boom.mass


def test_ctrl_c_while_waiting_for_the_other_threads_stops_them(crane, monkeypatch):
    """This thread's slice done, it waits for the other thread's: Ctrl-C there stops that one at
    its next chunk, and predict_many raises only once it has stopped (it writes into the output
    through raw pointers). A Thread.join() interrupted by Ctrl-C returned at once and left it
    running, chunk after chunk."""
    import signal
    import threading
    import time

    main = threading.main_thread()
    worker_chunks = []
    running = []
    real = _core._run_chunk

    def chunk(*args):
        if threading.current_thread() is main:
            return real(*args)
        running.append(1)
        worker_chunks.append(args[2])
        if len(worker_chunks) == 1:
            time.sleep(0.2)  # let this thread finish its slice and wait
            signal.pthread_kill(main.ident, signal.SIGINT)  # a real signal: it wakes a blocked wait
        time.sleep(0.05)
        status = real(*args)
        running.pop()
        return status

    monkeypatch.setattr(_core, "CHUNK_STEPS", 500)  # 2 futures of 250 steps per chunk
    monkeypatch.setattr(_core, "_run_chunk", chunk)
    with pytest.raises(KeyboardInterrupt):
        cp.predict_many(crane, [STATE] * 80, [INPUTS] * 80, 0.5, threads=2)
        for _ in range(10 ** 6):
            pass
    assert not running, "predict_many raised while the other thread was inside a chunk"
    chunks = len(worker_chunks)
    time.sleep(0.3)  # a worker left running would go on: 6 chunks in this time
    assert len(worker_chunks) == chunks and 1 <= chunks <= 3, worker_chunks  # of its 20


def test_a_valid_valve_batch_is_never_refused_for_its_substeps(crane):
    """1,200 lever-open futures in one thread: the core counts each future's valve substeps at
    their bound against CRANE_MAX_BATCH_STEPS; a chunk over it is split, never refused."""
    sc = cp.scenarios.get("lever-open")
    batch = cp.predict_many(sc.crane, [sc.initial] * 1200, [sc.inputs] * 1200, 2.0,
                            sample_every=400, threads=1)
    one = cp.predict(sc.crane, sc.initial, sc.inputs, 2.0)
    assert np.array_equal(batch.tip[1199, -1], one.tip[-1])


def test_threads_beyond_the_cores_are_refused(crane):
    import os

    with pytest.raises(ValueError, match=r"threads must be an int in \[1, \d+\] \(os.cpu_count"):
        cp.predict_many(crane, [STATE], [INPUTS], 0.5, threads=(os.cpu_count() or 1) + 1)
