"""Crane definitions: one TOML file per crane, loaded into frozen dataclasses.

The crane file is the single source of every parameter (SI units). Loading checks the types and
shapes here; every rule of the crane (each field's range, the lift triangle, the tilt four-bar over
the whole stroke) is the C core's ``crane_params_check``, the one validator, which reports the field
at fault: the error names it by its dotted name in the crane file, with its allowed range.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Mapping, Optional, Tuple, Union

from ._checks import number as _number
from ._checks import tomllib
from .shape import Shape

Vec2 = Tuple[float, float]

__all__ = ["Body", "Friction", "Hydraulics", "Cylinder", "SlewDrive", "ExtensionCylinder", "Geometry",
           "Crane", "FOUR_JOINT_FIELDS", "VALVES"]

#: The valve types of a cylinder's hydraulics (docs/model.md, "Hydraulics").
VALVES = ("orifice", "compensated")

#: Crane file fields of the four-joint model (docs/model.md, "Four joints"): top-level tables, and
#: the fields of every body. The C core checks their rules (crane_params_check) with the rest.
FOUR_JOINT_FIELDS = ("pillar", "slew_drive", "extension_cylinder")
FOUR_JOINT_BODY_FIELDS = ("ixx", "iyy", "ixy")


def _disc_area(diameter: float) -> float:
    """Area of a circle of the given diameter, m^2 (a piston, a rod)."""
    return math.pi * diameter**2 / 4.0


class _PistonAreas:
    """The two piston areas of a double-acting cylinder; the subclass has ``bore`` and ``rod`` (m)."""

    bore: float
    rod: float

    @property
    def area_a(self) -> float:
        """Bore-side piston area, m^2."""
        return _disc_area(self.bore)

    @property
    def area_b(self) -> float:
        """Rod-side annulus area, m^2."""
        return _disc_area(self.bore) - _disc_area(self.rod)


@dataclass(frozen=True)
class Body:
    """A rigid body: mass (kg), centre of mass in its own frame (m), Izz about the centre (kg m^2).

    ``ixx``, ``iyy``, ``ixy`` (kg m^2, optional) are the in-plane entries of its inertia tensor about
    the centre in its own frame, as [S1] gives them (``ixy = -integral(x y dm)``); the four-joint
    model's slew inertia needs them (docs/model.md, "Four joints"; left out: 0, izz, 0)."""

    mass: float
    com: Vec2
    izz: float
    ixx: Optional[float] = None
    iyy: Optional[float] = None
    ixy: Optional[float] = None


@dataclass(frozen=True)
class Friction:
    """Smooth Stribeck friction of a cylinder, [S1]'s law (N, N s/m, m/s); see docs/model.md.
    ``factor`` (k, dimensionless) multiplies the Coulomb and static levels, not the viscous one."""

    coulomb: float
    static: float
    viscous: float
    stribeck_velocity: float
    factor: float


@dataclass(frozen=True)
class Hydraulics:
    """A cylinder's valve and oil (docs/model.md, "Hydraulics"): Pa, m^3, m^3/s, s, m^3/(s Pa).

    ``valve`` is "orifice" (critical centre, [S1]/[S2]: Q = y K g(dp) per edge with
    K = nominal_flow/sqrt(nominal_pressure_drop)) or "compensated" (load-sensing PVG32 of [S3]:
    meter-in flow source y nominal_flow beyond the dead band, meter-out orifice of
    meter_out_flow at meter_out_pressure_drop). ``spool_time_constant`` 0 means no spool lag,
    ``leakage`` 0 none.
    """

    valve: str
    supply_pressure: float
    tank_pressure: float
    relief_pressure: float
    nominal_flow: float
    nominal_pressure_drop: float
    laminar_pressure_drop: float
    cavitation_pressure: float
    hose_volume_a: float
    hose_volume_b: float
    oil_bulk_modulus: float
    hose_bulk_modulus: float
    cylinder_bulk_modulus: float
    dead_band: float = 0.0
    meter_out_flow: float = 0.0
    meter_out_pressure_drop: float = 0.0
    spool_time_constant: float = 0.0
    leakage: float = 0.0


@dataclass(frozen=True)
class Cylinder(_PistonAreas):
    """A double-acting hydraulic cylinder: diameters, pin-to-pin length at stroke 0, stroke range (m)."""

    bore: float
    rod: float
    length_retracted: float
    stroke_min: float
    stroke_max: float
    friction: Friction
    hydraulics: Optional[Hydraulics] = None   #: None: the cylinder cannot be valve-driven


@dataclass(frozen=True)
class SlewDrive:
    """The slew actuator: two cylinders of one bore on a rack turning a pinion of pitch radius
    ``pinion_radius`` (m) on the pillar; the slew range ``slew_min`` .. ``slew_max`` (rad) is the
    rack's travel; friction at the rack's speed (docs/model.md, "Four joints")."""

    bore: float
    pinion_radius: float
    slew_min: float
    slew_max: float
    friction: Friction
    hydraulics: Optional[Hydraulics] = None   #: chamber a turns towards +slew; None: no valve drive

    @property
    def area(self) -> float:
        """One cylinder's piston area, m^2 (both chambers of the equivalent cylinder)."""
        return _disc_area(self.bore)

    @property
    def area_a(self) -> float:
        """Chamber a's area of the equivalent cylinder, m^2 (turns towards +slew): one bore."""
        return self.area

    @property
    def area_b(self) -> float:
        """Chamber b's area, m^2: the other cylinder's bore, the same."""
        return self.area

    @property
    def displacement(self) -> float:
        """Oil volume per radian of slew, m^3/rad (area times pinion radius)."""
        return self.area * self.pinion_radius


@dataclass(frozen=True)
class ExtensionCylinder(_PistonAreas):
    """The telescope's cylinder inside the outer boom: its stroke is the extension minus
    ``geometry.extension_min`` (m), bore side extending (docs/model.md, "Four joints")."""

    bore: float
    rod: float
    friction: Friction
    hydraulics: Optional[Hydraulics] = None   #: None: the extension cannot be valve-driven


@dataclass(frozen=True)
class Geometry:
    """Pivot and pin positions (m), each in the frame named in docs/model.md."""

    lift_pivot: Vec2
    lift_cylinder_base: Vec2
    lift_cylinder_rod: Vec2
    tilt_cylinder_base: Vec2
    link1_pivot: Vec2
    tilt_pivot: Vec2
    link_pin: Vec2
    link2_end: Vec2
    link2_attach: Vec2
    extension_mount: Vec2
    tip_distance: float
    extension_min: float
    extension_max: float


@dataclass(frozen=True)
class Crane:
    """Every parameter of one crane. Build it with :meth:`patu655` or :meth:`from_toml`."""

    name: str
    gravity: float
    load_mass: float
    geometry: Geometry
    lift_boom: Body
    outer_boom: Body
    extension_boom: Body
    side_link1: Body
    side_link2: Body
    lift_cylinder: Cylinder
    tilt_cylinder: Cylinder
    estimates: Tuple[str, ...] = field(default=())
    #: The pillar turns with the slew only: its inertia about the slew axis (docs/model.md, "Four
    #: joints"); optional (left out: none).
    pillar: Optional[Body] = None
    #: The four-joint model's actuators (docs/model.md, "Four joints"); optional (left out: the
    #: joint can only be held).
    slew_drive: Optional[SlewDrive] = None
    extension_cylinder: Optional[ExtensionCylinder] = None
    #: The parts for the collision guard (the crane file's ``[shape]``; docs/guard.md), if given.
    shape: Optional[Shape] = None

    def __post_init__(self) -> None:
        _check_crane(self)

    # -- construction -------------------------------------------------------------------------
    @classmethod
    def patu655(cls) -> "Crane":
        """The default crane: the PATU 655 of the public sources (see the crane file's comments)."""
        text = resources.files("cranepredict").joinpath("cranes/patu655.toml").read_text("utf-8")
        return cls.from_toml_string(text)

    @classmethod
    def from_toml(cls, path: Union[str, Path]) -> "Crane":
        """Loads a crane file. Raises ValueError/TypeError naming the field at fault."""
        try:
            text = Path(path).read_text("utf-8")
        except UnicodeDecodeError as exc:
            bad = exc.object[exc.start:exc.start + 1]
            raise ValueError(f"crane file {str(path)!r} is not UTF-8 text (TOML must be): at byte "
                             f"offset {exc.start}, {bad!r}") from None
        return cls.from_toml_string(text)

    @classmethod
    def from_toml_string(cls, text: str) -> "Crane":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"crane file is not valid TOML: {exc}") from None
        return cls.from_dict(data)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> "Crane":
        """Builds a crane from nested mappings shaped like the crane file."""
        return _build(cls, data, "")

    # -- output -------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        return _to_plain(self)

    def to_toml(self) -> str:
        """The crane file text for this crane (loads back to an equal Crane)."""
        return _dump_toml(self.to_dict())

    # -- variants -----------------------------------------------------------------------------
    def with_load(self, mass: float) -> "Crane":
        """The same crane with another load mass (kg, >= 0) at the tip."""
        return dataclasses.replace(self, load_mass=_number(mass, "load_mass"))


# -- loading ----------------------------------------------------------------------------------

def _vec2(value: Any, name: str) -> Vec2:
    # A table ({x = 1.0, y = 0.0}) has a length of 2 too, but no value[0].
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__") or len(value) != 2:
        table = " (a table)" if isinstance(value, Mapping) else ""
        raise TypeError(f"{name} must be a pair [x, y] of numbers, as in `{name.rsplit('.', 1)[-1]} "
                        f"= [0.5, 0.1]`, got {value!r}{table}")
    return (_number(value[0], f"{name}[0]"), _number(value[1], f"{name}[1]"))


def _build(cls: type, data: Mapping[str, Any], prefix: str) -> Any:
    where = prefix.rstrip(".") or "crane file"
    if not isinstance(data, Mapping):
        raise TypeError(f"{where} must be a table, got {type(data).__name__}")
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(set(data) - names)
    if unknown:
        raise ValueError(f"{where}: unknown field(s) {', '.join(prefix + u for u in unknown)}; "
                         f"allowed: {', '.join(sorted(names))}")
    hints = _hints(cls)
    kwargs = {}
    for f in dataclasses.fields(cls):
        name = prefix + f.name
        if f.name not in data:
            if f.default is not dataclasses.MISSING:
                continue
            raise ValueError(f"{name} is missing from the crane file")
        value, hint = data[f.name], hints[f.name]
        if hint == Optional[Shape]:
            kwargs[f.name] = None if value is None else Shape.from_dict(value)
            continue
        if hint == Optional[Body]:
            hint = Body
        hint = _unwrap_optional(hint)
        if dataclasses.is_dataclass(hint):
            kwargs[f.name] = _build(hint, value, name + ".")
        elif hint is Vec2:
            kwargs[f.name] = _vec2(value, name)
        elif hint is str:
            if not isinstance(value, str):
                raise TypeError(f"{name} must be a string")
            kwargs[f.name] = value
        elif hint == Tuple[str, ...]:
            if isinstance(value, str) or not all(isinstance(v, str) for v in value):
                raise TypeError(f"{name} must be a list of strings")
            kwargs[f.name] = tuple(value)
        else:
            kwargs[f.name] = _number(value, name)
    return cls(**kwargs)


def _unwrap_optional(hint: Any) -> Any:
    """Optional[X] -> X (a field the crane file may leave out); anything else unchanged."""
    import typing

    args = typing.get_args(hint)
    if typing.get_origin(hint) is Union and len(args) == 2 and type(None) in args:
        return args[0] if args[1] is type(None) else args[1]
    return hint


_HINTS: dict = {}


def _hints(cls: type) -> dict:
    """The resolved type hints of a crane dataclass (cached: typing.get_type_hints costs about
    1 ms per class and a Crane is checked on every construction, with_load included)."""
    import typing

    hints = _HINTS.get(cls)
    if hints is None:
        hints = _HINTS[cls] = typing.get_type_hints(cls, globalns=globals())
    return hints


# The kinds of field _check_shapes tells apart.
_SHAPE, _TABLE, _VEC2, _STR, _STRS, _NUMBER = range(6)
_PLANS: dict = {}


def _plan(cls: type) -> list:
    """(name, kind, optional, table class) per field of a crane dataclass, from its type hints,
    built once per class so that checking a crane compares no typing objects."""
    plan = _PLANS.get(cls)
    if plan is not None:
        return plan
    plan = []
    hints = _hints(cls)
    for f in dataclasses.fields(cls):
        hint = hints[f.name]
        inner = _unwrap_optional(hint)
        optional = inner is not hint
        if inner is Shape:
            kind = _SHAPE
        elif dataclasses.is_dataclass(inner):
            kind = _TABLE
        elif inner is Vec2:
            kind = _VEC2
        elif inner is str:
            kind = _STR
        elif inner == Tuple[str, ...]:
            kind = _STRS
        else:
            kind = _NUMBER
        plan.append((f.name, kind, optional, inner))
    _PLANS[cls] = plan
    return plan


def _check_shapes(obj: Any, cls: type, prefix: str) -> None:
    """Types and shapes of a (possibly directly constructed) dataclass, naming the field."""
    for fname, kind, optional, inner in _plan(cls):
        name, value = prefix + fname, getattr(obj, fname)
        if optional and value is None:
            continue
        if kind == _SHAPE:   # checked by Shape itself (the collision guard's parts)
            if not isinstance(value, Shape):
                raise TypeError(f"{name} must be a cranepredict.Shape, got {type(value).__name__}")
        elif kind == _TABLE:
            if not isinstance(value, inner):
                raise TypeError(f"{name} must be a {inner.__name__}, got {type(value).__name__}")
            _check_shapes(value, inner, name + ".")
        elif kind == _VEC2:
            if not isinstance(value, tuple) or len(value) != 2:
                raise TypeError(f"{name} must be a pair (x, y) of numbers, got {value!r}")
            for i, x in enumerate(value):
                if isinstance(x, bool) or not isinstance(x, (int, float)):
                    raise TypeError(f"{name}[{i}] must be a number, got {type(x).__name__}")
        elif kind == _STR:
            if not isinstance(value, str):
                raise TypeError(f"{name} must be a string, got {type(value).__name__}")
        elif kind == _STRS:
            if not isinstance(value, tuple) or not all(isinstance(v, str) for v in value):
                raise TypeError(f"{name} must be a tuple of strings")
        elif isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"{name} must be a number, got {type(value).__name__}")


def _field_names() -> dict:
    """crane_field code -> the crane file's dotted name (crane.h: the enumerator is the dotted name
    in capitals with '.' -> '_')."""
    from ._cranepredict import lib

    def leaves(cls: type, prefix: str) -> list:
        out = []
        for f in dataclasses.fields(cls):
            hint = _hints(cls)[f.name]
            if f.name in ("name", "estimates", "shape"):
                continue
            hint = _unwrap_optional(hint)   # optional tables: pillar, hydraulics, actuators
            if dataclasses.is_dataclass(hint):
                out += leaves(hint, prefix + f.name + ".")
            else:
                out.append(prefix + f.name)
        return out

    names = {}
    for dotted in leaves(Crane, ""):
        code = getattr(lib, "CRANE_FIELD_" + dotted.upper().replace(".", "_"), None)
        if code is not None:
            names[int(code)] = dotted
    return names


_FIELD_NAMES: dict = {}


def field_name(code: int) -> str:
    """The crane file's dotted name of a crane_field code (KeyError for an unknown code)."""
    if not _FIELD_NAMES:
        _FIELD_NAMES.update(_field_names())
    return _FIELD_NAMES[code]


def _value(c: Crane, dotted: str) -> Any:
    node: Any = c
    for part in dotted.split("."):
        node = getattr(node, part)
    return node


def _check_crane(c: Crane) -> None:
    """Types and shapes here; every rule by the C core, which names the field at fault."""
    _check_shapes(c, Crane, "")
    from . import _core
    from ._cranepredict import ffi, lib

    for cyl_name in ("lift_cylinder", "tilt_cylinder", "slew_drive", "extension_cylinder"):
        actuator = getattr(c, cyl_name)
        hyd = actuator.hydraulics if actuator is not None else None
        if hyd is not None and hyd.valve not in VALVES:   # a name: the C core gets its enum
            raise ValueError(f"{cyl_name}.hydraulics.valve must be one of {VALVES}, got {hyd.valve!r}")
    field = ffi.new("crane_field *")
    status = lib.crane_params_check(_core.params(c), field)
    if status == lib.CRANE_OK:
        return
    raise _core.CoreError(status, rule_error(status, int(field[0]), lambda n: _value(c, n), c.name))


def rule_error(status: int, code: int, value_of: Any, crane_name: str) -> str:
    """The message of a crane rule the C core's crane_params_check found broken: the field's dotted
    name, its rule and value (``value_of(dotted name)``), a sibling field a rule names with its
    value."""
    from . import _core
    from ._cranepredict import ffi, lib

    what = ffi.string(lib.crane_status_message(status)).decode()
    name = field_name(code)
    value = value_of(name)
    if status in (lib.CRANE_E_GEOMETRY, lib.CRANE_E_FOURBAR):
        context = _core._CONTEXT.get(status)
        return (f"crane {crane_name!r}: {what}; it fails at {name} = {value}"
                + (f" ({context})" if context else ""))
    if status == lib.CRANE_E_NONFINITE:
        return f"{name} must be finite, got {value}"
    rule = ffi.string(lib.crane_field_rule(code)).decode()
    # a rule that names a sibling field ("> rod") gets its dotted name and value
    prefix = name.rpartition(".")[0]
    words = []
    for word in rule.split(" "):
        sibling = f"{prefix}.{word}" if prefix else word
        if word.isidentifier() and sibling != name and sibling in _FIELD_NAMES.values():
            word = f"{sibling} ({value_of(sibling)})"
        words.append(word)
    return f"{name} must be {' '.join(words)}, got {value} ({what})"


# -- writing ----------------------------------------------------------------------------------

def _to_plain(obj: Any) -> Any:
    if hasattr(obj, "to_plain"):
        return obj.to_plain()
    if dataclasses.is_dataclass(obj):
        # None = an optional table left out (the pillar, the shape)
        return {f.name: _to_plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                if getattr(obj, f.name) is not None}
    if isinstance(obj, tuple):
        return [_to_plain(v) for v in obj]
    return obj


def _toml_value(v: Any) -> str:
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(float(v))


def _dump_toml(d: Mapping[str, Any], prefix: str = "") -> str:
    lines = [f"{k} = {_toml_value(v)}" for k, v in d.items() if not isinstance(v, dict)]
    out = "\n".join(lines) + ("\n" if lines else "")
    for k, v in d.items():
        if isinstance(v, dict):
            out += f"\n[{prefix}{k}]\n" + _dump_toml(v, f"{prefix}{k}.")
    return out
