#!/usr/bin/env python3
"""Generate csrc/board/board_scenarios.h, the board's scenarios, from the scenario files.

The scenario files (src/cranepredict/scenarios/*.toml, read by cranepredict.scenarios) are the one
source of the initial states and inputs; the board and its host twin compile this header, so
neither copies a number by hand. The header is committed (the board build needs no Python);
csrc/ci-embedded.sh runs this script with --check.

    python3 csrc/board/scenarios2header.py            # write the header
    python3 csrc/board/scenarios2header.py --check    # exit 1 if the committed header is stale

Needs the cranepredict package (pip install .). Each scenario must run on the crane of
csrc/example/crane_patu655.h up to its load, which the board sets per scenario.
"""
import argparse
import difflib
import os
import sys

import cranepredict as cp
from cranepredict.crane import Crane
from cranepredict.scenarios import get as get_scenario
from cranepredict.types import Hold, Pressure, PressureSeries

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
OUT = os.path.join(HERE, "board_scenarios.h")
CRANE_FILE = os.path.join(ROOT, "src", "cranepredict", "cranes", "patu655.toml")

# (name on the board, scenario file, step in s: None = the Python API's default)
BOARD = [
    ("paper-dt2ms", "paper-fig4", None),
    ("paper-dt1ms", "paper-fig4", 1e-3),
]


def r(x):
    """A number as CRANE_R(exact double)."""
    return f"CRANE_R({float(x)!r})"


def ident(name):
    return "board_" + name.replace("-", "_")


def drive(d, where, arrays):
    """The C initializer of one crane_drive; sampled inputs add their arrays to `arrays`."""
    if isinstance(d, Hold):
        return "{.mode = CRANE_DRIVE_HOLD}"
    if isinstance(d, Pressure):
        return f"{{.mode = CRANE_DRIVE_PRESSURE, .p_a = {r(d.p_a)}, .p_b = {r(d.p_b)}}}"
    if isinstance(d, PressureSeries):
        names = {}
        for field in ("t", "p_a", "p_b"):
            names[field] = f"{where}_{field}"
            values = ", ".join(r(v) for v in getattr(d, field))
            arrays.append(f"static const crane_real {names[field]}[] = {{{values}}};")
        return (f"{{.mode = CRANE_DRIVE_PRESSURE, .t = {names['t']}, "
                f".p_a_samples = {names['p_a']}, .p_b_samples = {names['p_b']}, "
                f".n_samples = {len(d.t)}}}")
    raise SystemExit(f"scenarios2header: {where}: drive {type(d).__name__} is not supported yet")


def generate():
    base = Crane.from_toml(CRANE_FILE)
    arrays, entries = [], []
    for name, scenario, dt in BOARD:
        sc = get_scenario(scenario)
        if sc.crane != base.with_load(sc.crane.load_mass):
            raise SystemExit(f"scenarios2header: {scenario} does not run on the crane of "
                             f"{os.path.relpath(CRANE_FILE, ROOT)} (up to its load)")
        s = sc.initial
        step = cp.DEFAULT_DT if dt is None else dt
        lift = drive(sc.inputs.lift, ident(name) + "_lift", arrays)
        tilt = drive(sc.inputs.tilt, ident(name) + "_tilt", arrays)
        entries.append(
            f"    {{.name = \"{name}\", .horizon = {r(sc.horizon)}, .dt = {r(step)}, "
            f".load_mass = {r(sc.crane.load_mass)}, \\\n"
            f"     .state0 = {{.stroke = {{{r(s.lift_stroke)}, {r(s.tilt_stroke)}}}, "
            f".stroke_rate = {{{r(s.lift_stroke_rate)}, {r(s.tilt_stroke_rate)}}}, \\\n"
            f"                .slew = {r(s.slew)}, .extension = {r(s.extension)}}}, \\\n"
            f"     .inputs = {{.drive = {{{lift}, \\\n"
            f"                          {tilt}}}}}}}, \\")
    src = [f" *   {n}: {f}.toml at dt = " +
           (f"{d!r} s" if d else f"{cp.DEFAULT_DT!r} s (cranepredict.DEFAULT_DT)")
           for n, f, d in BOARD]
    lines = [
        "/* SPDX-License-Identifier: MIT */",
        "/*",
        " * The board's scenarios (csrc/board): GENERATED from the scenario files in",
        " * src/cranepredict/scenarios by csrc/board/scenarios2header.py -- do not edit. Regenerate:",
        " *   python3 csrc/board/scenarios2header.py   (csrc/ci-embedded.sh checks it with --check)",
        " *",
    ] + src + [
        " */",
        "#ifndef BOARD_SCENARIOS_GENERATED_H",
        "#define BOARD_SCENARIOS_GENERATED_H",
        "",
        '#include "crane.h"',
        "",
        "#ifndef CRANE_R",
        "#define CRANE_R(x) ((crane_real)(x))",
        "#endif",
        "",
    ] + arrays + ([""] if arrays else []) + [
        "/* board_scenario initializers, in the order the board runs them. */",
        "#define BOARD_SCENARIOS_INIT { \\",
    ] + entries + [
        "}",
        "",
        "#endif",
    ]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="fail if the committed header is stale")
    a = ap.parse_args(argv)
    text = generate()
    if a.check:
        old = open(OUT).read() if os.path.exists(OUT) else ""
        if old != text:
            sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), text.splitlines(True),
                                                       OUT, "generated"))
            print(f"scenarios2header: {os.path.relpath(OUT, ROOT)} is stale: run "
                  "python3 csrc/board/scenarios2header.py")
            return 1
        print(f"scenarios2header: {os.path.relpath(OUT, ROOT)} is current")
        return 0
    with open(OUT, "w") as f:
        f.write(text)
    print(f"scenarios2header: wrote {os.path.relpath(OUT, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
