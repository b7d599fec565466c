"""Crane definitions: one TOML file per crane, loaded into frozen dataclasses.

The crane file is the single source of every parameter (SI units). Loading checks each field and
names the one at fault; the checks that need the kinematics (the lift triangle, the tilt four-bar
closing over the whole stroke) are done by the C core's ``crane_model_init`` so the formulas live
once per implementation.
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

Vec2 = Tuple[float, float]

__all__ = ["Body", "Friction", "Hydraulics", "Cylinder", "Geometry", "Crane", "VALVES"]

#: The valve types of a cylinder's hydraulics (docs/model.md, "Hydraulics").
VALVES = ("orifice", "compensated")


@dataclass(frozen=True)
class Body:
    """A rigid body: mass (kg), centre of mass in its own frame (m), Izz about the centre (kg m^2)."""

    mass: float
    com: Vec2
    izz: float


@dataclass(frozen=True)
class Friction:
    """Smooth Stribeck friction of a cylinder (N, N s/m, m/s); see docs/model.md."""

    coulomb: float
    static: float
    viscous: float
    stribeck_velocity: float
    tanh_velocity: float


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
class Cylinder:
    """A double-acting hydraulic cylinder: diameters, pin-to-pin length at stroke 0, stroke range (m)."""

    bore: float
    rod: float
    length_retracted: float
    stroke_min: float
    stroke_max: float
    friction: Friction
    hydraulics: Optional[Hydraulics] = None   #: None: the cylinder cannot be valve-driven

    @property
    def area_a(self) -> float:
        """Bore-side piston area, m^2."""
        return math.pi * self.bore**2 / 4.0

    @property
    def area_b(self) -> float:
        """Rod-side annulus area, m^2."""
        return math.pi * (self.bore**2 - self.rod**2) / 4.0


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
    pillar: Body
    lift_boom: Body
    outer_boom: Body
    extension_boom: Body
    side_link1: Body
    side_link2: Body
    lift_cylinder: Cylinder
    tilt_cylinder: Cylinder
    estimates: Tuple[str, ...] = field(default=())

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
        return cls.from_toml_string(Path(path).read_text("utf-8"))

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
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise TypeError(f"{name} must be a pair [x, y] of numbers, got {value!r}")
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
        if hint == Optional[Hydraulics]:
            hint = Hydraulics
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


def _hints(cls: type) -> dict:
    import typing

    return typing.get_type_hints(cls, globalns=globals())


def _check_crane(c: Crane) -> None:
    """Field checks with the field's name and allowed range; kinematic checks by the C core."""
    def positive(x: float, name: str) -> None:
        if not (math.isfinite(x) and x > 0.0):
            raise ValueError(f"{name} must be > 0, got {x}")

    def nonneg(x: float, name: str) -> None:
        if not (math.isfinite(x) and x >= 0.0):
            raise ValueError(f"{name} must be >= 0, got {x}")

    nonneg(c.gravity, "gravity")
    nonneg(c.load_mass, "load_mass")
    for body_name in ("pillar", "lift_boom", "outer_boom", "extension_boom", "side_link1", "side_link2"):
        body = getattr(c, body_name)
        positive(body.mass, f"{body_name}.mass")
        positive(body.izz, f"{body_name}.izz")
        for i, v in enumerate(body.com):
            if not math.isfinite(v):
                raise ValueError(f"{body_name}.com[{i}] must be finite, got {v}")
    g = c.geometry
    positive(g.tip_distance, "geometry.tip_distance")
    if not g.extension_min <= g.extension_max:
        raise ValueError(f"geometry.extension_min ({g.extension_min}) must be <= "
                         f"geometry.extension_max ({g.extension_max})")
    for cyl_name in ("lift_cylinder", "tilt_cylinder"):
        cyl = getattr(c, cyl_name)
        positive(cyl.rod, f"{cyl_name}.rod")
        if not cyl.bore > cyl.rod:
            raise ValueError(f"{cyl_name}.bore ({cyl.bore} m) must be > {cyl_name}.rod ({cyl.rod} m)")
        positive(cyl.length_retracted, f"{cyl_name}.length_retracted")
        nonneg(cyl.stroke_min, f"{cyl_name}.stroke_min")
        if not cyl.stroke_min < cyl.stroke_max:
            raise ValueError(f"{cyl_name}.stroke_min ({cyl.stroke_min} m) must be < "
                             f"{cyl_name}.stroke_max ({cyl.stroke_max} m)")
        fr = cyl.friction
        nonneg(fr.coulomb, f"{cyl_name}.friction.coulomb")
        nonneg(fr.viscous, f"{cyl_name}.friction.viscous")
        if not fr.static >= fr.coulomb:
            raise ValueError(f"{cyl_name}.friction.static ({fr.static} N) must be >= "
                             f"{cyl_name}.friction.coulomb ({fr.coulomb} N)")
        positive(fr.stribeck_velocity, f"{cyl_name}.friction.stribeck_velocity")
        positive(fr.tanh_velocity, f"{cyl_name}.friction.tanh_velocity")
        if cyl.hydraulics is not None:
            _check_hydraulics(cyl.hydraulics, f"{cyl_name}.hydraulics")
    from . import _core  # the kinematic checks: the lift triangle and the four-bar closing

    _core.check_crane(c)


#: Pa: the range of a chamber pressure (the state's and the circuit's); -1 bar gauge is vacuum.
CHAMBER_PRESSURE_MIN = -1e5


def _check_hydraulics(h: Hydraulics, where: str) -> None:
    """The ranges of docs/model.md "Hydraulics" (crane file), naming the field."""
    from ._core import PRESSURE_MAX

    if h.valve not in VALVES:
        raise ValueError(f"{where}.valve must be one of {VALVES}, got {h.valve!r}")

    def rng(name: str, lo: float, hi: float, lo_open: bool = False) -> None:
        x = getattr(h, name)
        if not (math.isfinite(x) and (x > lo if lo_open else x >= lo) and x <= hi):
            raise ValueError(f"{where}.{name} must be in {'(' if lo_open else '['}{lo:g}, {hi:g}], "
                             f"got {x}")

    rng("tank_pressure", 0.0, PRESSURE_MAX)
    rng("supply_pressure", h.tank_pressure, PRESSURE_MAX, lo_open=True)
    rng("relief_pressure", h.supply_pressure, PRESSURE_MAX)
    rng("cavitation_pressure", CHAMBER_PRESSURE_MIN, h.tank_pressure)
    for name in ("nominal_flow", "nominal_pressure_drop", "laminar_pressure_drop", "hose_volume_a",
                 "hose_volume_b", "oil_bulk_modulus", "hose_bulk_modulus", "cylinder_bulk_modulus"):
        rng(name, 0.0, math.inf, lo_open=True)
    rng("dead_band", 0.0, 0.99)
    rng("spool_time_constant", 0.0, 10.0)
    rng("leakage", 0.0, 1e-6)
    if h.valve == "compensated":
        rng("meter_out_flow", 0.0, math.inf, lo_open=True)
        rng("meter_out_pressure_drop", 0.0, math.inf, lo_open=True)
    else:
        rng("meter_out_flow", 0.0, math.inf)
        rng("meter_out_pressure_drop", 0.0, math.inf)
        if h.dead_band != 0.0:
            raise ValueError(f"{where}.dead_band must be 0 for an orifice valve (critical centre), "
                             f"got {h.dead_band}")


# -- writing ----------------------------------------------------------------------------------

def _to_plain(obj: Any) -> Any:
    if dataclasses.is_dataclass(obj):
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
