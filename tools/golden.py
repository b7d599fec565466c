#!/usr/bin/env python3
"""Golden vectors for the C tests (in the style of CMSIS-DSP's reference patterns): the named
scenarios and the pure-Python twin's trajectories of them, written as C data.

The twin is the executable specification (docs/model.md), written independently of the C core.
The C-only builds (double, float, the cross builds under qemu, the sanitizers) have no Python, so
they check themselves against these files. Two generated files, both committed:

    csrc/example/crane_scenarios.h   every named scenario's setup (load, initial state, drives,
                                     horizon) as C99 initializers: the one source of the paper
                                     scenario in the example, the benchmark, the tests and the fuzzer
    csrc/tests/golden.h              the twin's trajectory of each scenario at dt = 1 ms, one
                                     sample every 50 ms and the last one (all four joints: strokes,
                                     angles and rates of lift and tilt, slew and extension and their
                                     rates, tip, the four actuators' pressures and stop flags), and
                                     the first stop samples

    python3 tools/golden.py            # write both files
    python3 tools/golden.py --check    # exit 1 if a committed file is stale (numbers to 1e-10)

Needs the package installed (the twin, the scenarios); tests/test_golden.py runs --check.
"""
from __future__ import annotations

import argparse
import difflib
import math
import re
import sys
from pathlib import Path
from typing import List

import numpy as np

import cranepredict as cp
from cranepredict.types import Hold, Pressure, PressureSeries, Valve, ValveSeries

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS_H = ROOT / "csrc" / "example" / "crane_scenarios.h"
GOLDEN_H = ROOT / "csrc" / "tests" / "golden.h"
DT = 1e-3
EVERY = 50
CRANE = "PATU 655"  # the crane of crane_patu655.h; every scenario must use it

_HEAD = """/* SPDX-License-Identifier: MIT */
/*
 * {what}
 *
 * GENERATED from the TOML files in src/cranepredict/scenarios by tools/golden.py -- do not edit.
 * Regenerate:  python3 tools/golden.py   (tests/test_golden.py checks it is current)
{more} */
"""


def _ident(name: str) -> str:
    return re.sub(r"[^A-Z0-9]", "_", name.upper())


def _lit(x: float) -> str:
    """A C double literal that round-trips exactly (repr is the shortest such string)."""
    s = repr(float(x))
    if "e" not in s and "." not in s and "n" not in s:
        s += ".0"
    return s


def _r(x: float) -> str:
    return f"CRANE_R({_lit(x)})"


JOINTS = ("lift", "tilt", "slew", "extension")   # the C core's four-entry arrays, in its order


def _chambers(s) -> str:
    """The state's chamber pressures and spools of all four actuators [lift, tilt, slew,
    extension] (valve-driven ones, issues 9 and 11), if any is given."""
    p_a = [getattr(s, f"{j}_p_a") for j in JOINTS]
    p_b = [getattr(s, f"{j}_p_b") for j in JOINTS]
    spool = [getattr(s, f"{j}_spool") for j in JOINTS]
    if all(v is None for v in p_a + p_b) and not any(spool):
        return ""

    def four(vals):
        return "{" + ", ".join(_r(0.0 if v is None else v) for v in vals) + "}"

    return (f", \\\n    .p_a = {four(p_a)}, \\\n    .p_b = {four(p_b)}, \\\n"
            f"    .spool = {four(spool)}")


def _drive(d) -> str | None:
    """The crane_drive initializer, or None for a drive type this generator does not write yet."""
    if isinstance(d, Hold):
        return "{.mode = CRANE_DRIVE_HOLD}"
    if isinstance(d, Pressure):
        return f"{{.mode = CRANE_DRIVE_PRESSURE, .p_a = {_r(d.p_a)}, .p_b = {_r(d.p_b)}}}"
    if isinstance(d, PressureSeries):
        return (f"{{.mode = CRANE_DRIVE_PRESSURE, .t = {_arr(d.t)}, .p_a_samples = {_arr(d.p_a)}, "
                f".p_b_samples = {_arr(d.p_b)}, .n_samples = {len(d.t)}}}")
    if isinstance(d, Valve):
        return f"{{.mode = CRANE_DRIVE_VALVE, .u = {_r(d.u)}}}"
    if isinstance(d, ValveSeries):
        return (f"{{.mode = CRANE_DRIVE_VALVE, .t = {_arr(d.t)}, .u_samples = {_arr(d.u)}, "
                f".n_samples = {len(d.t)}}}")
    return None


def _arr(a) -> str:
    return "(const crane_real[]){" + ", ".join(_r(v) for v in a) + "}"


def _drives(sc) -> list:
    """The scenario's four drives [lift, tilt, slew, extension] (a drive left out is a Hold)."""
    return [getattr(sc.inputs, j) for j in JOINTS]


def _valves(sc) -> bool:
    return any(isinstance(d, (Valve, ValveSeries)) for d in _drives(sc))


def written() -> List:
    """The scenarios both files carry: those whose four drives _drive can write (the spatial ones,
    which move the slew or the extension, included: the C core moves all four joints)."""
    return [sc for sc in cp.scenarios.all_scenarios()
            if all(_drive(d) is not None for d in _drives(sc))]


def _left_out() -> str:
    names = sorted(set(cp.scenarios.names()) - {sc.name for sc in written()})
    return (" * Left out (drive types this generator does not write yet): " + ", ".join(names) + "\n"
            if names else "")


def scenarios_header() -> str:
    out = [_HEAD.format(
        what="The named scenarios of cranepredict (src/cranepredict/scenarios) for the C core.",
        more=_left_out() + """ *
 * For scenario X (the file's name in capitals, '-' -> '_'):
 *   CRANE_SCENARIO_X_LOAD_MASS   the load, kg: set crane_params.load_mass of CRANE_PATU655_INIT
 *   CRANE_SCENARIO_X_STATE       a crane_state initializer
 *   CRANE_SCENARIO_X_INPUTS      a crane_inputs initializer: the four drives [lift, tilt, slew,
 *                                extension] (sampled drives as compound literals)
 *   CRANE_SCENARIO_X_HORIZON     s
 * CRANE_SCENARIO_LIST(ENTRY) calls ENTRY("name", X) for every scenario X, in the order of the
 * names (csrc/bench/bench_core.c picks one by name through it).
 * Every scenario uses the PATU 655 (crane_patu655.h).
""")]
    out.append("#ifndef CRANE_SCENARIOS_H\n#define CRANE_SCENARIOS_H\n\n#include \"crane.h\"\n\n"
               "#ifndef CRANE_R\n#define CRANE_R(x) ((crane_real)(x))\n#endif\n")
    for sc in written():
        if sc.crane.name != CRANE:
            raise SystemExit(f"scenario {sc.name}: crane {sc.crane.name!r}, the C tests have {CRANE!r} only")
        x, s = _ident(sc.name), sc.initial
        out.append(f"\n/* {sc.name}: {sc.description.replace('*/', '* /')} */")
        out.append(f"#define CRANE_SCENARIO_{x}_LOAD_MASS {_r(sc.crane.load_mass)}")
        out.append(f"#define CRANE_SCENARIO_{x}_STATE {{ \\\n"
                   f"    .stroke = {{{_r(s.lift_stroke)}, {_r(s.tilt_stroke)}}}, \\\n"
                   f"    .stroke_rate = {{{_r(s.lift_stroke_rate)}, {_r(s.tilt_stroke_rate)}}}, \\\n"
                   f"    .slew = {_r(s.slew)}, .extension = {_r(s.extension)}, \\\n"
                   f"    .slew_rate = {_r(s.slew_rate)}, .extension_rate = {_r(s.extension_rate)}"
                   + _chambers(s) + "}")
        out.append(f"#define CRANE_SCENARIO_{x}_INPUTS {{.drive = {{ \\\n    "
                   + ", \\\n    ".join(_drive(d) for d in _drives(sc)) + "}}")
        out.append(f"#define CRANE_SCENARIO_{x}_HORIZON {_r(sc.horizon)}")
    out.extend(_estimator_lines())
    out.append("\n/* Every scenario above: ENTRY(\"name\", X) */\n#define CRANE_SCENARIO_LIST(ENTRY) \\\n"
               + " \\\n".join(f"    ENTRY(\"{sc.name}\", {_ident(sc.name)})" for sc in written()))
    out.append("\n#endif\n")
    return "\n".join(out)


#: The state estimator's example (the board's estimator run, csrc/board): the live twin's filter
#: (cp.EKF) for this scenario's crane, measuring what the scenario's crane moves on: the boom
#: cylinders' strokes and chamber pressures, the slew angle and the extension (the slew's and the
#: telescope's chambers, held, are not measured).
ESTIMATOR_SCENARIO = "lever-open"
ESTIMATOR_SENSORS = ("lift_stroke", "tilt_stroke", "slew", "extension",
                     "lift_p_a", "lift_p_b", "tilt_p_a", "tilt_p_b")


def _estimator_lines() -> List[str]:
    """The estimator example as C initializers: cp.EKF's configuration, each field's sensor
    variance, and the filter after its first measurement (the scenario's initial state)."""
    from cranepredict.live.estimator import ESTIMATED
    from cranepredict.live.measurement import default_sensors

    sc = cp.scenarios.get(ESTIMATOR_SCENARIO)
    sensors = default_sensors(fields=ESTIMATOR_SENSORS)
    ekf = cp.EKF(sc.crane, sensors, backend="python")
    ekf.update(cp.Measurement(t=0.0, inputs=sc.inputs,
                              **{f: getattr(sc.initial, f) for f in ESTIMATOR_SENSORS}))
    variance = [sensors[f].std ** 2 if f in ESTIMATOR_SENSORS else 0.0 for f in ESTIMATED]

    def arr(values) -> str:
        return "{" + ", ".join(_r(float(v)) for v in values) + "}"

    x = "CRANE_EXAMPLE_ESTIMATOR"
    dt = cp.DEFAULT_DT if ekf.dt is None else ekf.dt
    return [
        f"\n/* The state estimator (cp.EKF, docs/live.md) for {ESTIMATOR_SCENARIO}'s crane, measuring",
        " * " + ", ".join(ESTIMATOR_SENSORS) + ":",
        f" *   {x}_CONFIG       a crane_estimator_config initializer",
        f" *   {x}_VARIANCE     each estimated field's sensor variance (SI units^2; 0: not measured)",
        f" *   {x}_X0, {x}_COVARIANCE0_DIAGONAL, {x}_SPOOL0",
        " *                    the filter after its first measurement, the scenario's initial state",
        " *                    (crane_estimator_init's; the covariance is diagonal) */",
        f"#define {x}_CONFIG {{ \\\n    .lo = {arr(ekf.lo)}, \\\n    .hi = {arr(ekf.hi)}, \\\n"
        f"    .noise = {arr(ekf._q)}, \\\n    .fd_step = {arr(ekf._h)}, \\\n"
        f"    .scale = {arr(ekf._scale)}, \\\n    .dt = {_r(dt)}, "
        f".jacobian_columns = {ekf.jacobian_columns}}}",
        f"#define {x}_VARIANCE {arr(variance)}",
        f"#define {x}_X0 {arr(ekf.x)}",
        f"#define {x}_COVARIANCE0_DIAGONAL {arr(np.diag(ekf.covariance))}",
        f"#define {x}_SPOOL0 {arr(ekf.spools)}",
    ]


def _first_stops(stop: np.ndarray) -> List[int]:
    """Per joint [lift, tilt, slew, extension]: the first sample with a stop flag, -1 if none."""
    firsts = []
    for j in range(len(JOINTS)):
        idx = np.flatnonzero(stop[:, j] != 0)
        firsts.append(int(idx[0]) if idx.size else -1)
    return firsts


def golden_header() -> str:
    out = [_HEAD.format(
        what="Golden vectors: the pure-Python twin's trajectories of the named scenarios.",
        more=f""" *
 * dt = {DT:g} s; golden sample k is the prediction's sample min(k * {EVERY}, n - 1), n = n_samples.
 * Four-entry arrays are [lift, tilt, slew, extension] (crane.h), two-entry ones [lift, tilt].
 * first_stop[j]: the first sample (of all n) with a stop flag on joint j, -1 if none.
 * valves: 1 if an actuator is valve-driven (a build with CRANE_HYDRAULICS=0 refuses the scenario).
 * spatial: 1 if the slew or the extension is driven (not held).
 * p_a, p_b: the chamber pressures (valve) or the given pressures (pressure drive; 0 when held).
 * Values are the twin's doubles; the C test compares with a tolerance per precision.
""")]
    out.append("#ifndef CRANE_GOLDEN_H\n#define CRANE_GOLDEN_H\n\n#include <stddef.h>\n"
               "#include \"crane.h\"\n#include \"crane_scenarios.h\"\n")
    out.append(f"#define GOLDEN_DT {_lit(DT)}\n#define GOLDEN_EVERY {EVERY}\n")
    out.append("typedef struct {\n    double t, stroke[2], theta[2], omega[2], slew, extension, slew_rate,"
               " extension_rate;\n    double tip[3], p_a[4], p_b[4];\n"
               "    int stop[4];\n} golden_sample;\n")
    out.append("typedef struct {\n    const char *name;\n    int valves, spatial;\n    crane_real load_mass;\n"
               "    crane_state state;\n    crane_inputs inputs;\n    crane_real horizon;\n    size_t n_samples;\n"
               "    long first_stop[4];\n    size_t n_golden;\n    const golden_sample *golden;\n"
               "} golden_scenario;\n")
    table = []
    for sc in written():
        tr = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=DT, backend="python")
        n = len(tr.t)
        keep = sorted(set(range(0, n, EVERY)) | {n - 1})
        x, ident = _ident(sc.name), _ident(sc.name).lower()
        rows = []
        for k in keep:
            groups = ([tr.t[k]], tr.strokes[k], tr.theta[k], tr.omega[k],
                      [tr.slew[k]], [tr.extension[k]], [tr.slew_rate[k]], [tr.extension_rate[k]],
                      tr.tip[k], tr.p_a[k], tr.p_b[k])
            if not all(math.isfinite(v) for g in groups for v in g):
                raise SystemExit(f"scenario {sc.name}: non-finite twin sample {k}")
            cells = [_lit(g[0]) if len(g) == 1 else "{" + ", ".join(_lit(v) for v in g) + "}"
                     for g in groups]
            cells.append("{" + ", ".join(str(int(v)) for v in tr.stop[k]) + "}")
            rows.append("    {" + ", ".join(cells) + "},")
        out.append(f"static const golden_sample golden_{ident}[] = {{\n" + "\n".join(rows) + "\n};\n")
        firsts = ", ".join(str(f) for f in _first_stops(np.asarray(tr.stop)))
        table.append(f"    {{\"{sc.name}\", {int(_valves(sc))}, {int(sc.spatial)}, CRANE_SCENARIO_{x}_LOAD_MASS, "
                     f"CRANE_SCENARIO_{x}_STATE,\n"
                     f"     CRANE_SCENARIO_{x}_INPUTS, CRANE_SCENARIO_{x}_HORIZON, {n}, {{{firsts}}},\n"
                     f"     {len(keep)}, golden_{ident}}},")
    out.append("static const golden_scenario golden_scenarios[] = {\n" + "\n".join(table) + "\n};\n")
    out.append(f"enum {{ GOLDEN_N_SCENARIOS = {len(table)} }};\n\n#endif\n")
    return "\n".join(out)


_NUMBER = re.compile(r"-?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def same(old: str, new: str, rel: float = 1e-10, abs_: float = 1e-10) -> bool:
    """Equal text except numbers, which agree to rel/abs: the twin's last bits differ across
    platforms' libm and with the order of its arithmetic (a 1e7 Pa chamber pressure moves by 4e-7
    Pa), far below the C tests' tolerances (1e-9 m, 1e-3 Pa in double)."""
    if _NUMBER.sub("#", old) != _NUMBER.sub("#", new):
        return False
    a = [float(v) for v in _NUMBER.findall(old)]
    b = [float(v) for v in _NUMBER.findall(new)]
    return len(a) == len(b) and all(math.isclose(u, v, rel_tol=rel, abs_tol=abs_) for u, v in zip(a, b))


def main(argv: List[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 if a committed file is stale")
    a = ap.parse_args(argv)
    status = 0
    for path, text in ((SCENARIOS_H, scenarios_header()), (GOLDEN_H, golden_header())):
        rel = path.relative_to(ROOT)
        if a.check:
            old = path.read_text() if path.exists() else ""
            if same(old, text):
                print(f"up to date: {rel}")
            else:
                sys.stdout.writelines(list(difflib.unified_diff(
                    old.splitlines(True), text.splitlines(True), f"{rel} (committed)",
                    f"{rel} (from the twin)"))[:60])
                print(f"STALE: {rel}; run: python3 tools/golden.py", file=sys.stderr)
                status = 1
        else:
            path.write_text(text)
            print(f"wrote {rel}")
    return status


if __name__ == "__main__":
    sys.exit(main())
