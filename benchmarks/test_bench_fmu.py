"""Speed of the exported FMU's doStep at 10-ms communication steps (docs/fmu.md, "Speed"): 2 s of
lever-open (lift and tilt levers; the core's 5-ms step: two RK4 steps with the valves' substeps
per doStep) and of all four levers (the four-joint model), and with a world (each step also
predicts the 2-s future and judges it with crane_guard), through FMPy's FMI 3 calls (ctypes: what
a Python importer pays), and crane_step alone through cffi for comparison.

    pytest benchmarks/test_bench_fmu.py --benchmark-only -s     the figures of docs/fmu.md
    pytest benchmarks --benchmark-disable                       each once, as a test (CI)

Printed, not asserted: timings on a shared machine are noisy.
"""

from __future__ import annotations

import shutil

import pytest

import cranepredict as cp

fmpy = pytest.importorskip("fmpy", reason="the [fmu] extra (FMPy) is not installed")
if not any(shutil.which(c) for c in ("cc", "gcc", "clang")):
    pytest.skip("exporting an FMU compiles it: no C compiler on PATH", allow_module_level=True)

from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi3 import FMU3Slave  # noqa: E402

from cranepredict import _core  # noqa: E402
from cranepredict._core import ffi, lib  # noqa: E402
from cranepredict.fmu import export_fmu  # noqa: E402

POSE = {"lift_stroke": 0.116, "tilt_stroke": 0.20}
STEPS = 200   # 2 s of 10-ms communication steps


BEAM = cp.World.from_toml_string("""
name = "beam"
margin = 0.30
[[obstacle]]
name = "beam"
kind = "box"
centre = [4.6, 0.0, 2.2]
size = [2.0, 10.0, 0.3]
yaw = 0.0
""")
LABEL = {"lift-tilt": "lift and tilt levers", "four-levers": "all four levers",
         "guard": "lift and tilt levers, guard against a beam"}


@pytest.fixture(scope="module", params=["lift-tilt", "four-levers", "guard"])
def unit(request, tmp_path_factory):
    levers = None if request.param == "four-levers" else ["lift", "tilt"]
    path = export_fmu(cp.Crane.patu655(), tmp_path_factory.mktemp("fmu") / "c.fmu", levers=levers,
                      start=POSE, world=BEAM if request.param == "guard" else None)
    md = read_model_description(path)
    d = extract(path)
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=d, modelIdentifier="crane")
    fmu.instantiate()
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu.enterInitializationMode()
    fmu.setFloat64([vr["lift_lever"]], [1.0])
    if "slew_lever" in vr:
        fmu.setFloat64([vr["slew_lever"]], [0.5])
    fmu.exitInitializationMode()
    yield request.param, fmu
    fmu.terminate()
    fmu.freeInstance()
    shutil.rmtree(d, ignore_errors=True)


def test_do_step_10ms(benchmark, unit):
    name, fmu = unit
    state = fmu.getFMUState()

    def run():
        fmu.setFMUState(state)   # every round from the same start: the same 2 s of motion
        t = 0.0
        for _ in range(STEPS):
            fmu.doStep(t, 0.01)
            t += 0.01

    benchmark(run)
    fmu.freeFMUState(state)
    if benchmark.stats is not None:
        us = benchmark.stats.stats.median / STEPS * 1e6
        benchmark.extra_info["doStep_us"] = us
        print(f"\nFMU doStep (10 ms, {LABEL[name]}, FMI 3 through FMPy): {us:.1f} us per step, "
              f"{0.01 / (us * 1e-6):,.0f}x faster than real time")


def test_crane_step_10ms(benchmark):
    """crane_step alone (cffi), lever-open's inputs: the FMU's work without the FMI calls."""
    sc = cp.scenarios.get("lever-open")
    s0 = ffi.new("crane_state *")
    _core._state(s0, sc.initial)
    inp, keep = ffi.new("crane_inputs *"), []
    _core._inputs(inp, sc.inputs, keep)
    m = _core.model(sc.crane, s0.extension)
    s, out, work = ffi.new("crane_state *"), ffi.new("crane_sample[2]"), _core.work()

    def run():
        s[0] = s0[0]
        for _ in range(STEPS):
            lib.crane_step(m, s, inp, 0.01, 0.005, s, out, work)

    benchmark(run)
    if benchmark.stats is not None:
        us = benchmark.stats.stats.median / STEPS * 1e6
        benchmark.extra_info["crane_step_us"] = us
        print(f"\ncrane_step (10 ms, lever-open, cffi): {us:.1f} us per step")
