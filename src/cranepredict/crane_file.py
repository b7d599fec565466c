"""The crane-file reference, generated: every table and field of a crane file with its unit, the
range the validator enforces, its default, its meaning, and the PATU 655's value with the source
its crane file gives for it.

Each column comes from the one place that defines it, so the reference cannot go stale: the
fields and defaults from the dataclasses of :mod:`cranepredict.crane`, the ranges from the C
core's validator (``crane_field_rule``, the text of the rule ``crane_params_check`` applies), the
values and sources from ``cranes/patu655.toml`` and its comments; only the unit and the meaning of
each field are written here (:data:`FIELDS`; tests/test_crane_file_reference.py requires one
entry per field). ``python -m cranepredict.crane_file`` prints the reference (Markdown).
"""

from __future__ import annotations

import dataclasses
import re
from importlib import resources
from typing import Any, Dict, List, Optional, Tuple

from . import crane as _crane
from ._checks import tomllib
from .shape import LENGTH_MAX, PART_KINDS, BODY_FRAMES

__all__ = ["FIELDS", "TABLES", "markdown", "leaves"]

_POINT = "a point (x, y) of the mechanism, m, in the {frame} frame"

#: (dataclass name, field) -> (unit, meaning). The frames are docs/model.md's ("Frames").
FIELDS: Dict[Tuple[str, str], Tuple[str, str]] = {
    ("Crane", "name"): ("text", "the crane's name, printed by the CLI"),
    ("Crane", "gravity"): ("m/s^2", "gravitational acceleration, along -y of the boom plane"),
    ("Crane", "load_mass"): ("kg", "the load, a point mass at the tip (`Crane.with_load` changes it)"),
    ("Crane", "estimates"): ("list of names",
                             "the dotted names of the values no source gives (a table's name: all of it)"),
    ("Geometry", "lift_pivot"): ("m", "O1, the lift boom's pivot on the pillar, boom-plane frame"),
    ("Geometry", "lift_cylinder_base"): ("m", "the lift cylinder's pin on the pillar, boom-plane frame"),
    ("Geometry", "lift_cylinder_rod"): ("m", "the lift cylinder's rod pin, lift-boom frame"),
    ("Geometry", "tilt_cylinder_base"): ("m", "the tilt cylinder's pin, lift-boom frame"),
    ("Geometry", "link1_pivot"): ("m", "side link 1's pivot on the lift boom, lift-boom frame"),
    ("Geometry", "tilt_pivot"): ("m", "O2, the outer boom's pivot, lift-boom frame"),
    ("Geometry", "link_pin"): ("m", "the pin of side links 1 and 2 and the tilt cylinder's rod, "
                                    "side-link-1 frame"),
    ("Geometry", "link2_end"): ("m", "side link 2's end on the outer boom, side-link-2 frame"),
    ("Geometry", "link2_attach"): ("m", "the same point in the outer-boom frame"),
    ("Geometry", "extension_mount"): ("m", "where the extension boom's frame starts at extension 0, "
                                           "outer-boom frame"),
    ("Geometry", "tip_distance"): ("m", "the load point along the extension boom's x axis"),
    ("Geometry", "extension_min"): ("m", "the telescope's shortest extension"),
    ("Geometry", "extension_max"): ("m", "the telescope's longest extension"),
    ("Body", "mass"): ("kg", "the body's mass"),
    ("Body", "com"): ("m", "its centre of mass, in its own frame"),
    ("Body", "izz"): ("kg m^2", "its moment of inertia about the centre of mass, normal to the boom plane"),
    ("Body", "ixx"): ("kg m^2", "in-plane inertia tensor entry about the centre (the four-joint model's "
                                "slew inertia); left out: 0"),
    ("Body", "iyy"): ("kg m^2", "in-plane inertia tensor entry about the centre; left out: izz"),
    ("Body", "ixy"): ("kg m^2", "in-plane product of inertia, -integral(x y dm); left out: 0"),
    ("Cylinder", "bore"): ("m", "the piston's diameter"),
    ("Cylinder", "rod"): ("m", "the rod's diameter"),
    ("Cylinder", "length_retracted"): ("m", "pin-to-pin length at stroke 0"),
    ("Cylinder", "stroke_min"): ("m", "the stroke at the lower end stop (fully retracted)"),
    ("Cylinder", "stroke_max"): ("m", "the stroke at the upper end stop (fully extended)"),
    ("Cylinder", "friction"): ("table", "its seal friction"),
    ("Cylinder", "hydraulics"): ("table", "its valve and oil; left out: it cannot be valve-driven"),
    ("Friction", "coulomb"): ("N", "Coulomb friction force F_C (times factor)"),
    ("Friction", "static"): ("N", "static (breakaway) friction force F_S (times factor)"),
    ("Friction", "viscous"): ("N s/m", "viscous coefficient"),
    ("Friction", "stribeck_velocity"): ("m/s", "Stribeck velocity v_S: where the static level decays"),
    ("Friction", "factor"): ("1", "k, multiplies the Coulomb and static levels, not the viscous one"),
    ("Hydraulics", "valve"): ("name", "`orifice` (critical-centre spool) or `compensated` "
                                      "(pressure-compensated, load-sensing)"),
    ("Hydraulics", "supply_pressure"): ("Pa", "the pump's pressure at the valve (gauge)"),
    ("Hydraulics", "tank_pressure"): ("Pa", "the return line's pressure (gauge)"),
    ("Hydraulics", "relief_pressure"): ("Pa", "the port relief valves' opening pressure"),
    ("Hydraulics", "nominal_flow"): ("m^3/s", "the flow at full opening and the nominal pressure drop"),
    ("Hydraulics", "nominal_pressure_drop"): ("Pa", "the pressure drop at which nominal_flow is rated"),
    ("Hydraulics", "dead_band"): ("1", "the lever's dead band, a fraction of full travel"),
    ("Hydraulics", "meter_out_flow"): ("m^3/s", "the compensated valve's meter-out flow at "
                                                "meter_out_pressure_drop"),
    ("Hydraulics", "meter_out_pressure_drop"): ("Pa", "the pressure drop at which meter_out_flow is rated"),
    ("Hydraulics", "spool_time_constant"): ("s", "the spool's first-order lag behind the lever; 0: none"),
    ("Hydraulics", "laminar_pressure_drop"): ("Pa", "below this pressure drop an edge's flow is laminar "
                                                    "(linear in the drop)"),
    ("Hydraulics", "cavitation_pressure"): ("Pa", "the lowest chamber pressure (gauge): the oil cavitates"),
    ("Hydraulics", "hose_volume_a"): ("m^3", "oil volume of the hose to chamber a (bore side)"),
    ("Hydraulics", "hose_volume_b"): ("m^3", "oil volume of the hose to chamber b (rod side)"),
    ("Hydraulics", "oil_bulk_modulus"): ("Pa", "the oil's bulk modulus"),
    ("Hydraulics", "hose_bulk_modulus"): ("Pa", "the hoses' effective bulk modulus"),
    ("Hydraulics", "cylinder_bulk_modulus"): ("Pa", "the cylinder tube's effective bulk modulus"),
    ("Hydraulics", "leakage"): ("m^3/(s Pa)", "internal leakage from chamber a to b per pascal; 0: none"),
    ("SlewDrive", "bore"): ("m", "each of the rack's two cylinders' bore"),
    ("SlewDrive", "pinion_radius"): ("m", "the pinion's pitch radius (rack travel per radian)"),
    ("SlewDrive", "slew_min"): ("rad", "the slew at one end of the rack's travel"),
    ("SlewDrive", "slew_max"): ("rad", "the slew at the other end"),
    ("SlewDrive", "friction"): ("table", "the rack's friction, at the rack's speed"),
    ("SlewDrive", "hydraulics"): ("table", "its valve and oil (chamber a turns towards +slew); "
                                           "left out: the slew cannot be valve-driven"),
    ("ExtensionCylinder", "bore"): ("m", "the telescope cylinder's piston diameter"),
    ("ExtensionCylinder", "rod"): ("m", "its rod's diameter (stroke = extension - extension_min)"),
    ("ExtensionCylinder", "friction"): ("table", "its seal friction"),
    ("ExtensionCylinder", "hydraulics"): ("table", "its valve and oil; left out: the extension "
                                                   "cannot be valve-driven"),
}

#: Dotted table name -> what the table is, and whether it may be left out.
TABLES: Dict[str, str] = {
    "": "The top level of the file.",
    "geometry": "Pivots and pins of the mechanism; each pair [x, y] in the frame named (docs/model.md, "
                "\"Frames\").",
    "pillar": "The slewing pillar; optional (left out: no slew inertia of its own).",
    "lift_boom": "The lift (inner) boom.",
    "outer_boom": "The outer (tilt) boom, without the extension boom.",
    "extension_boom": "The extension (telescope) boom.",
    "side_link1": "Side link 1 of the tilt four-bar (frame origin at its pivot on the lift boom).",
    "side_link2": "Side link 2 of the tilt four-bar (frame origin at its pin with side link 1).",
    "lift_cylinder": "The lift cylinder.",
    "tilt_cylinder": "The tilt cylinder.",
    "slew_drive": "The slew actuator: two cylinders on one rack turning a pinion; optional (left out: "
                  "the slew can only be held).",
    "extension_cylinder": "The telescope's cylinder inside the outer boom; optional (left out: the "
                          "extension can only be held).",
}

_FRICTION = "Smooth Stribeck friction, [S1]'s law (docs/model.md, \"Cylinders\")."
_HYDRAULICS = ("The valve and the oil of a valve-driven actuator (docs/model.md, \"Hydraulics\"); "
               "optional (left out: Valve and ValveSeries drives are refused).")


def _table_doc(dotted: str) -> str:
    if dotted.endswith(".friction"):
        return _FRICTION
    if dotted.endswith(".hydraulics"):
        return _HYDRAULICS
    return TABLES[dotted]


def leaves(cls: type = _crane.Crane, prefix: str = "") -> List[Tuple[str, str, Optional[type], Any]]:
    """(dotted name, dataclass name, table class or None, field) for every field of a crane file,
    tables before their fields, in the dataclasses' order. The guard's ``shape`` table is left to
    :func:`_shape_section`."""
    out = []
    hints = _crane._hints(cls)
    for f in dataclasses.fields(cls):
        if f.name == "shape":
            continue
        inner = _crane._unwrap_optional(hints[f.name])
        table = inner if dataclasses.is_dataclass(inner) else None
        out.append((prefix + f.name, cls.__name__, table, f))
        if table is not None:
            out += leaves(table, prefix + f.name + ".")
    return out


def _patu_comments(text: str) -> Tuple[Dict[str, str], Dict[str, str]]:
    """The crane file's comments: dotted field -> its line's comment, dotted table -> its header's."""
    fields: Dict[str, str] = {}
    tables: Dict[str, str] = {}
    table = ""
    for line in text.splitlines():
        m = re.match(r"\s*\[([A-Za-z0-9_.]+)\]\s*(?:#\s*(.*))?$", line)
        if m:
            table = m.group(1)
            tables[table] = (m.group(2) or "").strip()
            continue
        m = re.match(r"\s*([A-Za-z0-9_]+)\s*=\s*[^#]*?(?:#\s*(.*))?$", line)
        if m and m.group(2):
            fields[(table + "." if table else "") + m.group(1)] = m.group(2).strip()
    return fields, tables


def _without_unit(text: str, unit: str) -> str:
    """A comment without the unit it starts with ("Pa [S1]" -> "[S1]"): the unit has its column."""
    if unit and text.startswith(unit):
        rest = text[len(unit):]
        if not rest or rest[0] in " :,;":
            return rest.lstrip(" :,;")
    return text


def _source(dotted: str, unit: str, estimates: Tuple[str, ...], comments: Dict[str, str],
            headers: Dict[str, str]) -> str:
    """Where the PATU 655's value comes from: the crane file's comment on the line, else on its
    table's header (or a parent table's); "estimate" when it is listed in ``estimates``."""
    parts = dotted.split(".")
    estimate = any(".".join(parts[:i]) in estimates for i in range(1, len(parts) + 1))
    text = comments.get(dotted, "")
    if not text:
        for i in range(len(parts) - 1, 0, -1):
            text = headers.get(".".join(parts[:i]), "")
            if text:
                break
    text = _without_unit(text, unit)
    if estimate and "estimate" not in text.lower():
        text = "estimate" + (f" ({text})" if text else "")
    return text or "-"


def _cell(text: Any) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _value(node: Any, dotted: str) -> Any:
    for part in dotted.split("."):
        if node is None:
            return None
        node = getattr(node, part)
    return node


def _fmt(v: Any) -> str:
    if v is None:
        return "-"
    if isinstance(v, tuple):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, float):
        return f"{v:g}"
    return str(v)


def _rules() -> Dict[str, str]:
    """dotted field -> the C validator's rule for it (crane_field_rule)."""
    from ._cranepredict import ffi, lib

    _crane.field_name(1)   # fills the code -> name table
    return {name: ffi.string(lib.crane_field_rule(code)).decode()
            for code, name in _crane._FIELD_NAMES.items()}


def _default(f: Any) -> str:
    if f.default is not dataclasses.MISSING:
        return "left out" if f.default is None else _fmt(f.default) if f.default != () else "[]"
    if f.default_factory is not dataclasses.MISSING:   # type: ignore[misc]
        return "[]"
    return "required"


def markdown() -> str:
    """The crane-file reference as Markdown (MyST), one table per crane-file table."""
    text = resources.files("cranepredict").joinpath("cranes/patu655.toml").read_text("utf-8")
    patu = _crane.Crane.from_toml_string(text)
    comments, headers = _patu_comments(text)
    rules = _rules()
    rows: Dict[str, List[str]] = {}
    order: List[str] = []
    for dotted, owner, table, f in leaves():
        parent = dotted.rpartition(".")[0]
        if parent not in rows:
            rows[parent] = []
            order.append(parent)
        if table is not None:
            rows.setdefault(dotted, [])
            if dotted not in order:
                order.append(dotted)
            continue
        unit, meaning = FIELDS[(owner, f.name)]
        rule = rules.get(dotted, "a list of dotted field names" if f.name == "estimates" else
                         "text" if f.name == "name" else "-")
        value = _value(patu, dotted)
        rows[parent].append("| " + " | ".join(_cell(c) for c in (
            f"`{f.name}`", unit, rule, _default(f), meaning, _fmt(value),
            _source(dotted, unit, patu.estimates, comments, headers) if f.name not in ("name", "estimates")
            else "-")) + " |")
    out = ["# Crane file reference", "",
           "Every table and field of a crane file (TOML, SI units), generated from the package "
           "itself (`python -m cranepredict.crane_file`): the fields and defaults from the "
           "dataclasses of `cranepredict.crane`, the ranges from the C core's validator (the rule "
           "`crane_params_check` applies to each field, as its error message states it), the PATU "
           "655's values and their sources from `cranes/patu655.toml` and its comments. Source "
           "keys: [S1] Khadim et al. 2023 (PatuCrane_Exudyn), [S2] Khadim et al. 2022, [S3] the "
           "PVG32 valve model, [P] the seed paper; \"estimate\": no source gives the value.", "",
           "Beyond the per-field ranges, the validator checks the mechanism as a whole: the lift "
           "triangle and the tilt four-bar must close over the whole stroke range, and the error "
           "names the field where they fail. Write a crane file by copying "
           "`src/cranepredict/cranes/patu655.toml` and load it with "
           "`cranepredict.Crane.from_toml(path)`.", ""]
    for dotted in order:
        heading = f"[{dotted}]" if dotted else "Top level"
        out += [f"## {heading}", "", _table_doc(dotted), ""]
        if rows[dotted]:
            out += ["| field | unit | range (validator) | default | meaning | PATU 655 | source |",
                    "|---|---|---|---|---|---|---|", *rows[dotted], ""]
    out += _shape_section(patu)
    return "\n".join(out) + "\n"


#: Fields of a [shape.<part>] table: (unit, rule, default, meaning); shape.py checks them.
SHAPE_FIELDS = {
    "kind": ("name", " or ".join(PART_KINDS), "required",
             "capsule: a segment grown by a radius; sphere or box: hanging below a point (the load)"),
    "a": ("point", "a point name or [body, x, y], body one of " + ", ".join(BODY_FRAMES), "required",
          "the capsule's first end; the point a sphere or box hangs below"),
    "b": ("point", "as a; capsules only", "required for a capsule", "the capsule's second end"),
    "radius": ("m", f"capsule: [0, {LENGTH_MAX:g}]; sphere: (0, {LENGTH_MAX:g}]", "0",
               "the capsule's or sphere's radius"),
    "drop": ("m", f"within +-{LENGTH_MAX:g}", "0", "how far below a the sphere's or box's centre hangs"),
    "size": ("m", f"box only: each in (0, {2 * LENGTH_MAX:g}]", "-",
             "the box's full lengths: outward in the boom plane, lateral, up"),
}


def _shape_section(patu: Any) -> List[str]:
    out = ["## [shape]", "",
           "The crane's parts for the collision guard (docs/guard.md): one table `[shape.NAME]` per "
           "part, and `estimates`, the parts whose sizes no source gives. Optional (left out: the "
           "guard has nothing to measure). A point name is one of "
           + ", ".join(f"`{n}`" for n in _point_names()) + ".", "",
           "| field | unit | range (validator) | default | meaning |", "|---|---|---|---|---|"]
    for name, (unit, rule, default, meaning) in SHAPE_FIELDS.items():
        out.append("| " + " | ".join(_cell(c) for c in (f"`{name}`", unit, rule, default, meaning)) + " |")
    out += ["", "The PATU 655's parts (all estimates, sized from the pins and a 100 mm bore's tube):", "",
            "| part | kind | a | b | radius, m | drop, m |", "|---|---|---|---|---|---|"]
    for p in patu.shape.parts:
        out.append("| " + " | ".join(_cell(c) for c in (
            p.name, p.kind, _fmt(p.a), _fmt(p.b), _fmt(p.radius), _fmt(p.drop))) + " |")
    return out + [""]


def _point_names() -> Tuple[str, ...]:
    from .types import POINT_NAMES

    return POINT_NAMES


if __name__ == "__main__":   # pragma: no cover
    print(markdown(), end="")
