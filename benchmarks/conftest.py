"""Shared pieces of the speed benchmarks: the scenarios, the converged reference runs, the
largest step within 1 mm, and recording the faster-than-real-time ratio in extra_info.

Run: pytest benchmarks --benchmark-only            (the ratio table, docs/benchmarks.md)
     pytest benchmarks --benchmark-disable         (each benchmark once, as a test: CI)
"""

from __future__ import annotations

import dataclasses
import functools
import time
from dataclasses import dataclass
from typing import Callable, Dict, Tuple

import numpy as np
import pytest

import cranepredict as cp

#: The converged run's step, s (checked below against half of it: they agree to < 1e-9 m).
DT_REF = 5e-5
#: Tip error allowed at the "largest dt", m.
TOL = 1e-3
#: Candidate steps for "the largest dt within 1 mm", s: divisors of the 2-s horizon and multiples
#: of DT_REF (so that every sample lands on a reference sample), capped at 50 ms (>= 40 samples
#: over 2 s: the error is measured at the samples, so a cap keeps the output usable).
DT_GRID = (1e-3, 2e-3, 2.5e-3, 4e-3, 5e-3, 8e-3, 1e-2, 1.25e-2, 2e-2, 2.5e-2, 4e-2, 5e-2)


@dataclass(frozen=True)
class Case:
    name: str
    crane: cp.Crane
    initial: cp.State
    inputs: cp.Inputs
    horizon: float

    def args(self):
        return self.crane, self.initial, self.inputs, self.horizon


def both_cylinders() -> Case:
    """Both cylinders driven, no end stop within 2 s (lift 75 bar on the bore side, tilt 30 bar on
    the rod side, from a low pose): both strokes move by about 0.25-0.3 m."""
    crane = cp.scenarios.get("paper-fig4").crane
    return Case("both-cylinders", crane, cp.State(lift_stroke=0.15, tilt_stroke=0.20),
                cp.Inputs(lift=cp.Pressure(p_a=75e5, p_b=0.0), tilt=cp.Pressure(p_a=0.0, p_b=30e5)),
                2.0)


def open_chain() -> Case:
    """both-cylinders with (practically) massless side links: our model is then exactly an open
    2-link chain, the model MuJoCo runs (its chain has no closed four-bar)."""
    c = both_cylinders()
    tiny = {"mass": 1e-9, "izz": 1e-9}
    crane = dataclasses.replace(c.crane, side_link1=dataclasses.replace(c.crane.side_link1, **tiny),
                                side_link2=dataclasses.replace(c.crane.side_link2, **tiny))
    return Case("open-chain", crane, c.initial, c.inputs, c.horizon)


def paper_fig4() -> Case:
    sc = cp.scenarios.get("paper-fig4")
    return Case("paper-fig4", sc.crane, sc.initial, sc.inputs, sc.horizon)


def lever_open() -> Case:
    """The operator's version of the paper's experiment: the lift lever fully open from
    rest (the crane holding itself on closed valves), the tilt valve closed, 2 s."""
    crane = cp.scenarios.get("paper-fig4").crane
    initial = cp.state_at_rest(crane, 0.116, 0.20)
    return Case("lever-open", crane, initial, cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(0.0)), 2.0)


def named(name: str) -> Callable[[], Case]:
    """A named scenario (src/cranepredict/scenarios) as a Case: its crane, start, drives, horizon."""
    def make() -> Case:
        sc = cp.scenarios.get(name)
        return Case(name, sc.crane, sc.initial, sc.inputs, sc.horizon)
    return make


CASES: Dict[str, Callable[[], Case]] = {"paper-fig4": paper_fig4, "both-cylinders": both_cylinders,
                                        "open-chain": open_chain, "lever-open": lever_open}
#: Four joints: all four actuators valve-driven from rest (valve-all-four; slew-while-
#: lifting: the slew and lift levers open, tilt and telescope valves closed) and the slew
#: pressure-driven with the booms and telescope held (slew-folded). 2 s each.
FOUR_JOINT_VALVE = ("valve-all-four", "slew-while-lifting")
FOUR_JOINT_PRESSURE = ("slew-folded",)
CASES.update({n: named(n) for n in FOUR_JOINT_VALVE + FOUR_JOINT_PRESSURE})


def _pressure_driven(name: str) -> bool:
    sc = cp.scenarios.get(name)
    drives = [getattr(sc.inputs, j, None) for j in ("lift", "tilt", "slew", "extension")]
    return not any(isinstance(d, (cp.Valve, cp.ValveSeries)) for d in drives)


#: Every named scenario without a valve drive (the target ">= 20,000x at the default settings").
NAMED_PRESSURE = tuple(n for n in cp.scenarios.names() if _pressure_driven(n))
CASES.update({n: named(n) for n in NAMED_PRESSURE if n not in CASES})


@functools.lru_cache(maxsize=None)
def case(name: str) -> Case:
    return CASES[name]()


@functools.lru_cache(maxsize=None)
def reference(name: str) -> cp.Trajectory:
    """The converged run (C core, RK4 at DT_REF)."""
    return cp.predict(*case(name).args(), dt=DT_REF, method="rk4")


def tip_error(name: str, t: np.ndarray, tip: np.ndarray) -> float:
    """Largest distance (m) between a run's tip and the converged run's at the run's samples."""
    ref = reference(name)
    idx = np.rint(np.asarray(t) / DT_REF).astype(int)
    if not np.allclose(ref.t[idx], t, atol=1e-12):
        raise ValueError("sample times are not on the reference grid")
    return float(np.max(np.linalg.norm(np.asarray(tip) - ref.tip[idx], axis=1)))


@functools.lru_cache(maxsize=None)
def largest_dt(name: str) -> Tuple[float, Dict[float, float]]:
    """The largest RK4 step of DT_GRID whose C run keeps the tip within TOL of the converged run
    (measured: every candidate is run), and the error of every candidate."""
    errors = {}
    for dt in DT_GRID:
        tr = cp.predict(*case(name).args(), dt=dt, method="rk4")
        errors[dt] = tip_error(name, tr.t, tr.tip)
    ok = [dt for dt, e in errors.items() if e <= TOL]
    return max(ok), errors


def benchmarks_enabled(config: pytest.Config) -> bool:
    return not (config.getoption("benchmark_disable", False) or
                config.getoption("benchmark_skip", False))


@pytest.fixture
def ratio(benchmark, request):
    """run(fn, simulated_s, **info): benchmarks fn and records in extra_info the
    faster-than-real-time ratio (simulated seconds / median wall seconds, and / min) and info."""
    enabled = benchmarks_enabled(request.config)

    def run(fn, simulated: float, **info):
        t0 = time.perf_counter()
        result = benchmark(fn)
        once = time.perf_counter() - t0
        stats = getattr(benchmark, "stats", None)
        if enabled and stats is not None:
            median, best = stats.stats.median, stats.stats.min
        else:       # --benchmark-disable: fn ran once
            median = best = once
        benchmark.extra_info.update(info)
        benchmark.extra_info["simulated_s"] = simulated
        benchmark.extra_info["ratio"] = round(simulated / median, 1)
        benchmark.extra_info["ratio_best"] = round(simulated / best, 1)
        return result

    return run
