#!/usr/bin/env python3
"""Generate a C header with a crane's parameters from its crane file (TOML).

The crane file is the one source of the parameters; the C example and embedded users compile the
generated header instead of parsing TOML on the target. The generated header is committed, so the
C build needs no Python; CI runs this script with --check to prove it is up to date.

The crane file is validated first by the one validator of a crane, the C core's
crane_params_check (through the cranepredict package: Crane.from_toml), so a header is generated
only for a crane that the core accepts, and an error names the crane file's field.

    python3 tools/crane2header.py                       # PATU 655 -> csrc/example/crane_patu655.h
    python3 tools/crane2header.py --check               # exit 1 if the committed header is stale
    python3 tools/crane2header.py CRANE.toml -o OUT.h --name my_crane

Needs Python >= 3.11 (tomllib) and the cranepredict package (pip install .).
"""
import argparse
import difflib
import math
import os
import re
import sys
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_TOML = os.path.join(ROOT, "src", "cranepredict", "cranes", "patu655.toml")
DEFAULT_OUT = os.path.join(ROOT, "csrc", "example", "crane_patu655.h")

# crane_params field <- dotted key in the crane file
VEC2 = [
    ("lift_pivot", "geometry.lift_pivot"),
    ("lift_cylinder_base", "geometry.lift_cylinder_base"),
    ("lift_cylinder_rod", "geometry.lift_cylinder_rod"),
    ("tilt_cylinder_base", "geometry.tilt_cylinder_base"),
    ("link1_pivot", "geometry.link1_pivot"),
    ("tilt_pivot", "geometry.tilt_pivot"),
    ("link_pin", "geometry.link_pin"),
    ("link2_end", "geometry.link2_end"),
    ("link2_attach", "geometry.link2_attach"),
    ("extension_mount", "geometry.extension_mount"),
]
SCALARS = [
    ("tip_distance", "geometry.tip_distance"),
    ("extension_min", "geometry.extension_min"),
    ("extension_max", "geometry.extension_max"),
]
BODIES = [("lift_boom", "lift_boom"), ("outer_boom", "outer_boom"),
          ("extension_boom", "extension_boom")]
# the side links of the tilt four-bar (docs/model.md, "Side links"); massless links (mass and izz
# 0 = neglected, the paper's model) are given as such in the crane file
SIDE_LINKS = [("side_link1", "side_link1"), ("side_link2", "side_link2")]
CYLINDERS = [("CRANE_LIFT", "lift_cylinder"), ("CRANE_TILT", "tilt_cylinder")]
CYL_FIELDS = ["bore", "rod", "length_retracted", "stroke_min", "stroke_max"]
FRICTION = [("coulomb", "coulomb"), ("static_", "static"), ("viscous", "viscous"),
            ("stribeck_velocity", "stribeck_velocity"), ("factor", "factor")]
# a cylinder's [hydraulics] table (docs/model.md, "Hydraulics"); valve is a string -> enum
HYDRAULICS = ["supply_pressure", "tank_pressure", "relief_pressure", "nominal_flow",
              "nominal_pressure_drop", "dead_band", "meter_out_flow", "meter_out_pressure_drop",
              "spool_time_constant", "laminar_pressure_drop", "cavitation_pressure",
              "hose_volume_a", "hose_volume_b", "oil_bulk_modulus", "hose_bulk_modulus",
              "cylinder_bulk_modulus", "leakage"]
# optional fields of the hydraulics table and their default (crane.py's Hydraulics)
HYDRAULICS_DEFAULTS = {"dead_band": 0.0, "meter_out_flow": 0.0, "meter_out_pressure_drop": 0.0,
                       "spool_time_constant": 0.0, "leakage": 0.0}
VALVES = {"orifice": "CRANE_VALVE_ORIFICE", "compensated": "CRANE_VALVE_COMPENSATED"}
# keys of the crane file that the C model does not take from here (the shape is the collision
# guard's, given to crane_guard by the caller)
UNUSED = {"name", "estimates", "shape"}
# the four-joint actuators (docs/model.md, "Four joints"): optional tables; present = 0 without
SLEW_DRIVE_FIELDS = ["bore", "pinion_radius", "slew_min", "slew_max"]
EXTENSION_CYLINDER_FIELDS = ["bore", "rod"]


def lookup(data, dotted, used):
    node = data
    for part in dotted.split("."):
        if not isinstance(node, dict) or part not in node:
            raise SystemExit(f"crane file: missing {dotted}")
        node = node[part]
    used.add(dotted)
    return node


def num(x, what):
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
        raise SystemExit(f"crane file: {what} must be a finite number, got {x!r}")
    return float(x)


def lit(x):
    """A C double literal that round-trips exactly (repr is the shortest such string)."""
    s = repr(float(x))
    if "e" not in s and "." not in s:
        s += ".0"
    return f"CRANE_R({s})"


def leaves(data, prefix=""):
    for k, v in data.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            yield from leaves(v, key + ".")
        else:
            yield key


def validate(toml_path):
    """The crane file through the cranepredict loader: types by Python, every rule by the C core."""
    try:
        from cranepredict.crane import Crane
    except ImportError as exc:
        raise SystemExit(f"crane2header: needs the cranepredict package to validate the crane file "
                         f"with the C core (pip install .): {exc}")
    try:
        Crane.from_toml(toml_path)
    except (ValueError, TypeError) as exc:
        raise SystemExit(f"crane file {toml_path}: {exc}")


def generate(toml_path, name):
    validate(toml_path)
    with open(toml_path, "rb") as f:
        data = tomllib.load(f)
    used = set()
    L = []

    def vec(field, key):
        v = lookup(data, key, used)
        if not isinstance(v, list) or len(v) != 2:
            raise SystemExit(f"crane file: {key} must be [x, y]")
        L.append(f"    .{field} = {{.x = {lit(num(v[0], key))}, .y = {lit(num(v[1], key))}}}, \\")

    def sca(field, key):
        L.append(f"    .{field} = {lit(num(lookup(data, key, used), key))}, \\")

    def body(field, key):
        """mass, com, izz and the in-plane tensor; left out: ixx 0, iyy izz, ixy 0 (crane.h)."""
        sca(f"{field}.mass", f"{key}.mass")
        vec(f"{field}.com", f"{key}.com")
        sca(f"{field}.izz", f"{key}.izz")
        table = data.get(key, {})
        for fld in ("ixx", "iyy", "ixy"):
            if fld in table:
                sca(f"{field}.{fld}", f"{key}.{fld}")
            else:
                default = num(table["izz"], f"{key}.izz") if fld == "iyy" else 0.0
                L.append(f"    .{field}.{fld} = {lit(default)}, \\")

    def friction(field, key):
        for fld, tkey in FRICTION:
            sca(f"{field}.friction.{fld}", f"{key}.friction.{tkey}")

    def hydraulics(field, key):
        hyd = data.get(key, {}).get("hydraulics")
        if hyd is None:
            L.append(f"    .{field}.hydraulics = {{.valve = CRANE_VALVE_NONE}}, \\")
            return
        valve = lookup(data, f"{key}.hydraulics.valve", used)
        if valve not in VALVES:
            raise SystemExit(f"crane file: {key}.hydraulics.valve must be one of {sorted(VALVES)}")
        L.append(f"    .{field}.hydraulics.valve = {VALVES[valve]}, \\")
        for fld in HYDRAULICS:
            if fld not in hyd and fld in HYDRAULICS_DEFAULTS:
                L.append(f"    .{field}.hydraulics.{fld} = {lit(HYDRAULICS_DEFAULTS[fld])}, \\")
            else:
                sca(f"{field}.hydraulics.{fld}", f"{key}.hydraulics.{fld}")

    sca("gravity", "gravity")
    for field, key in VEC2:
        vec(field, key)
    for field, key in SCALARS:
        sca(field, key)
    for field, key in BODIES:
        body(field, key)
    sca("load_mass", "load_mass")
    for field, key in SIDE_LINKS:
        body(field, key)
    for idx, key in CYLINDERS:
        for fld in CYL_FIELDS:
            sca(f"cylinder[{idx}].{fld}", f"{key}.{fld}")
        friction(f"cylinder[{idx}]", key)
        hydraulics(f"cylinder[{idx}]", key)
    if "pillar" in data:   # optional: all 0 without (no pillar inertia)
        body("pillar", "pillar")
    for key, fields in (("slew_drive", SLEW_DRIVE_FIELDS),
                        ("extension_cylinder", EXTENSION_CYLINDER_FIELDS)):
        if key not in data:   # optional: present = 0, the joint can only be held
            L.append(f"    .{key}.present = 0, \\")
            continue
        L.append(f"    .{key}.present = 1, \\")
        for fld in fields:
            sca(f"{key}.{fld}", f"{key}.{fld}")
        friction(key, key)
        hydraulics(key, key)

    unknown = [k for k in leaves(data) if k not in used and k.split(".")[0] not in UNUSED]
    if unknown:
        raise SystemExit("crane file: keys this generator does not map (extend tools/"
                         "crane2header.py): " + ", ".join(unknown))

    crane_name = data.get("name", name)
    guard = re.sub(r"[^A-Z0-9]", "_", f"CRANE_{name.upper()}_H")
    macro = re.sub(r"[^A-Z0-9]", "_", f"CRANE_{name.upper()}_INIT")
    rel = os.path.relpath(os.path.abspath(toml_path), ROOT).replace(os.sep, "/")
    head = f"""/* SPDX-License-Identifier: MIT */
/*
 * {crane_name}: crane parameters for the cranepredict C core.
 *
 * GENERATED from {rel} by tools/crane2header.py -- do not edit.
 * Regenerate:  python3 tools/crane2header.py   (CI checks it is current with --check)
 *
 * Use:  static const crane_params crane = {macro};
 * (C99 designated initializers, so the struct can live in flash). Every field of crane_params is
 * set, the side links, the pillar and the four-joint actuators included. Literals are
 * the crane file's numbers as exact doubles, rounded by CRANE_R.
 */
#ifndef {guard}
#define {guard}

#include "crane.h"

#ifndef CRANE_R
#define CRANE_R(x) ((crane_real)(x))
#endif

#define {macro} {{ \\
"""
    tail = """}

#endif
"""
    return head + "\n".join(L) + "\n" + tail


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("toml", nargs="?", default=DEFAULT_TOML)
    ap.add_argument("-o", "--output", default=None)
    ap.add_argument("--name", default=None, help="C identifier: the macro is CRANE_<NAME>_INIT")
    ap.add_argument("--check", action="store_true",
                    help="compare with the existing output instead of writing; exit 1 if stale")
    a = ap.parse_args(argv)
    name = a.name or os.path.splitext(os.path.basename(a.toml))[0]
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise SystemExit(f"--name {name!r} is not a C identifier")
    out = a.output or (DEFAULT_OUT if a.toml == DEFAULT_TOML
                       else os.path.join(ROOT, "csrc", "example", f"crane_{name}.h"))
    text = generate(a.toml, name)
    if a.check:
        try:
            with open(out) as f:
                old = f.read()
        except FileNotFoundError:
            old = ""
        if old != text:
            sys.stdout.writelines(difflib.unified_diff(
                old.splitlines(True), text.splitlines(True), out + " (committed)",
                out + " (from the crane file)"))
            print(f"STALE: {out} differs from {a.toml}; run: python3 tools/crane2header.py",
                  file=sys.stderr)
            return 1
        print(f"up to date: {os.path.relpath(out, ROOT)}")
        return 0
    with open(out, "w") as f:
        f.write(text)
    print(f"wrote {os.path.relpath(out, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
