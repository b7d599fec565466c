"""Speed of uncertainty sweeps (docs/sweep.md): futures per second of predict_many with a crane
per future (``vary``), of a whole study in-process and on a two-worker Dask LocalCluster, and the
overhead per chunk.

    pytest benchmarks/test_bench_sweep.py --benchmark-only -s     the figures of docs/sweep.md
    pytest benchmarks --benchmark-disable                         each once, as a test (CI)

A study's future is more than a prediction: the command's 2 s, the guard's measure per obstacle,
the twin's decision's stop and the sample's own latest stop time (the guard's bisection: several
stop predictions). Timings on a shared machine are noisy: the figures are printed and recorded in
extra_info, not asserted.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import uncertainty

from conftest import benchmarks_enabled

STUDY = cp.studies.get("power-line-load")
SC = cp.scenarios.get("paper-fig4")
F = 400


def _rate(benchmark, futures: int, seconds: float, **info) -> float:
    rate = futures / seconds
    benchmark.extra_info.update(futures=futures, seconds=round(seconds, 4),
                                futures_per_s=round(rate, 1), **info)
    return rate


@pytest.mark.parametrize("how", ["vary", "shared", "crane-per-future"])
def test_predict_many_per_future_cranes(benchmark, request, how):
    """400 futures of paper-fig4 (2 s, default dt), each with its own load (``vary``), against one
    crane for all and against a Crane built per future (with_load) and predicted one by one."""
    loads = np.linspace(160.0, 240.0, F)
    initials, inputs = [SC.initial] * F, [SC.inputs] * F
    if how == "vary":
        def fn():
            return cp.predict_many(SC.crane, initials, inputs, 2.0, vary={"load_mass": loads})
    elif how == "shared":
        def fn():
            return cp.predict_many(SC.crane, initials, inputs, 2.0)
    else:
        def fn():
            return [cp.predict(SC.crane.with_load(float(m)), SC.initial, SC.inputs, 2.0)
                    for m in loads]
    rounds = 15 if benchmarks_enabled(request.config) else 1
    benchmark.pedantic(fn, rounds=rounds, iterations=1, warmup_rounds=0)
    seconds = benchmark.stats.stats.median if benchmarks_enabled(request.config) else None
    if seconds:
        print(f"\npredict_many {how}: {_rate(benchmark, F, seconds):,.0f} futures/s")


def _study(samples: int, chunk: int) -> uncertainty.Study:
    return dataclasses.replace(STUDY, samples=samples, chunk=chunk)


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as c, distributed.Client(c) as client:
        yield client


def _sweep(study, scheduler):
    return cp.sweep(study, scheduler=scheduler)


@pytest.mark.parametrize("where", ["in-process", "local-cluster"])
def test_study_futures_per_second(benchmark, request, where):
    """The example study: futures per second over its chunks (100 futures each), in this process
    (predict_many on 2 threads) and on a LocalCluster of 2 worker processes."""
    scheduler = "in-process" if where == "in-process" else request.getfixturevalue("cluster")
    samples = 800 if benchmarks_enabled(request.config) else 8
    study = _study(samples, min(100, samples))
    result = benchmark.pedantic(_sweep, args=(study, scheduler), rounds=1, iterations=1)
    rate = _rate(benchmark, samples, result.chunk_seconds, where=result.where)
    print(f"\nsweep {where}: {samples} futures in {result.chunk_seconds:.2f} s of chunks "
          f"({result.seconds:.2f} s with the twin's decisions and the summary): "
          f"{rate:,.0f} futures/s, {rate / 2:,.0f} per core")


@pytest.mark.parametrize("where", ["in-process", "local-cluster"])
def test_overhead_per_chunk(benchmark, request, where):
    """The same 60 futures in 60 chunks of 1 and in one chunk of 60: the difference per extra chunk
    is the cost of a chunk (its task, its draws, its predict_many calls and writing it back)."""
    scheduler = "in-process" if where == "in-process" else request.getfixturevalue("cluster")
    n = 60 if benchmarks_enabled(request.config) else 4

    def both():
        one = cp.sweep(_study(n, n), scheduler=scheduler).chunk_seconds
        many = cp.sweep(_study(n, 1), scheduler=scheduler).chunk_seconds
        return one, many

    one, many = benchmark.pedantic(both, rounds=1, iterations=1)
    overhead = (many - one) / (n - 1)
    benchmark.extra_info.update(one_chunk_s=round(one, 4), chunks_of_one_s=round(many, 4),
                                overhead_per_chunk_ms=round(overhead * 1e3, 2))
    print(f"\nchunk overhead {where}: {n} futures in 1 chunk {one:.2f} s, in {n} chunks "
          f"{many:.2f} s: {overhead * 1e3:.1f} ms per chunk")
