"""A world file: the obstacles around the crane and the clearance margin (TOML, SI units).

Coordinates are in the crane's base frame (docs/model.md "Frames": origin at the pillar base,
X, Y horizontal, Z up). Obstacle kinds: a ground ``plane`` (the solid is below it), oriented
``box`` (turned by ``yaw`` about Z), vertical ``cylinder``, ``capsule`` (a power line), ``sphere``.
Every obstacle has a unique ``name``; a bad field is reported with the obstacle's name and the
field. Example worlds ship with the package (:func:`names`, :func:`get`). See docs/guard.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Dict, List, Mapping, Tuple, Union

import numpy as np

from ._checks import number as _number
from ._checks import tomllib

__all__ = ["Obstacle", "World", "OBSTACLE_KINDS", "names", "get"]

Vec3 = Tuple[float, float, float]

#: kind -> (required fields, optional fields with defaults)
OBSTACLE_KINDS: Dict[str, Tuple[Tuple[str, ...], Dict[str, Any]]] = {
    "plane": (("point", "normal"), {}),
    "box": (("centre", "size"), {"yaw": 0.0}),
    "cylinder": (("base", "height", "radius"), {}),
    "capsule": (("a", "b", "radius"), {}),
    "sphere": (("centre", "radius"), {}),
}
_VECTORS = {"point", "normal", "centre", "size", "base", "a", "b"}


#: The largest coordinate or size accepted, m (the C core's CRANE_GUARD_LENGTH_MAX).
LENGTH_MAX = 1e6


def _length(value: Any, where: str) -> float:
    x = _number(value, where)
    if not abs(x) <= LENGTH_MAX:
        raise ValueError(f"{where} must be within +-{LENGTH_MAX:g} m, got {x:g}")
    return x


def _vec3(value: Any, where: str) -> Vec3:
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
        raise TypeError(f"{where} must be [x, y, z] in m, got {value!r}")
    return tuple(_length(x, f"{where}[{i}]") for i, x in enumerate(value))  # type: ignore[return-value]


@dataclass(frozen=True)
class Obstacle:
    """One obstacle: ``kind`` and its fields (SI units, base frame).

    plane: ``point``, ``normal`` (any length > 0, pointing out of the solid, i.e. up for the ground);
    box: ``centre``, ``size`` (full lengths along its axes, > 0), ``yaw`` (rad about Z, default 0);
    cylinder: ``base`` (centre of its bottom), ``height`` (> 0), ``radius`` (> 0), vertical;
    capsule: ``a``, ``b`` (axis ends), ``radius`` (>= 0); sphere: ``centre``, ``radius`` (> 0).
    """

    name: str
    kind: str
    fields: Tuple[Tuple[str, Any], ...]

    def __getitem__(self, key: str) -> Any:
        return dict(self.fields)[key]

    @classmethod
    def make(cls, name: str, kind: str, where: str = "", **values: Any) -> "Obstacle":
        """Checks and builds an obstacle; errors name it as ``where`` (default: its name)."""
        where = where or f"obstacle {name!r}"
        if not isinstance(kind, str) or kind not in OBSTACLE_KINDS:
            raise ValueError(f"{where}.kind must be one of {tuple(OBSTACLE_KINDS)}, got {kind!r}")
        required, optional = OBSTACLE_KINDS[kind]
        unknown = sorted(set(values) - set(required) - set(optional))
        if unknown:
            raise ValueError(f"{where}: unknown field(s) {', '.join(unknown)} for a {kind}; "
                             f"allowed: {', '.join(required + tuple(optional))}")
        missing = [f for f in required if f not in values]
        if missing:
            raise ValueError(f"{where}.{missing[0]} is missing (a {kind} needs {', '.join(required)})")
        out: Dict[str, Any] = dict(optional)
        for key, value in values.items():
            if key in _VECTORS:
                out[key] = _vec3(value, f"{where}.{key}")
            elif key == "yaw":
                out[key] = _number(value, f"{where}.{key}")
            else:
                out[key] = _length(value, f"{where}.{key}")
        if kind == "plane" and not np.linalg.norm(out["normal"]) > 0:
            raise ValueError(f"{where}.normal must not be zero")
        if kind == "box" and not min(out["size"]) > 0:
            raise ValueError(f"{where}.size must be > 0 m in every direction, got {list(out['size'])}")
        if kind in ("cylinder", "sphere") and not out["radius"] > 0:
            raise ValueError(f"{where}.radius must be > 0 m, got {out['radius']}")
        if kind == "capsule" and not out["radius"] >= 0:
            raise ValueError(f"{where}.radius must be >= 0 m, got {out['radius']}")
        if kind == "cylinder" and not out["height"] > 0:
            raise ValueError(f"{where}.height must be > 0 m, got {out['height']}")
        return cls(name=name, kind=kind, fields=tuple(sorted(out.items())))

    def solid(self) -> dict:
        """The obstacle as the C core's crane_solid fields (kind name, a, b, radius, axes, half)."""
        f = dict(self.fields)
        if self.kind == "plane":
            n = np.asarray(f["normal"], dtype=float)
            return {"kind": "plane", "a": f["point"], "b": tuple(n / np.linalg.norm(n))}
        if self.kind == "box":
            c, s = math.cos(f["yaw"]), math.sin(f["yaw"])
            return {"kind": "box", "a": f["centre"], "axes": (c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0),
                    "half": tuple(0.5 * v for v in f["size"])}
        if self.kind == "cylinder":
            x, y, z = f["base"]
            return {"kind": "cylinder", "a": (x, y, z), "b": (x, y, z + f["height"]),
                    "radius": f["radius"]}
        if self.kind == "capsule":
            return {"kind": "capsule", "a": f["a"], "b": f["b"], "radius": f["radius"]}
        return {"kind": "sphere", "a": f["centre"], "radius": f["radius"]}

    def to_plain(self) -> dict:
        return {"name": self.name, "kind": self.kind,
                **{k: list(v) if isinstance(v, tuple) else v for k, v in self.fields}}


@dataclass(frozen=True, eq=False)
class World:
    """Named obstacles and the clearance margin (m, >= 0) the guard keeps from all of them."""

    name: str
    margin: float
    obstacles: Tuple[Obstacle, ...]
    description: str = ""

    def __post_init__(self) -> None:
        m = _number(self.margin, "world margin")
        if not (math.isfinite(m) and m >= 0):
            raise ValueError(f"world margin must be >= 0 m, got {m}")
        object.__setattr__(self, "margin", m)
        seen: set = set()
        dup = sorted({o.name for o in self.obstacles if o.name in seen or seen.add(o.name)})
        if dup:
            raise ValueError(f"world obstacle names must be unique, repeated: {', '.join(dup)}")

    @property
    def names(self) -> Tuple[str, ...]:
        return tuple(o.name for o in self.obstacles)

    @classmethod
    def from_toml(cls, path: Union[str, Path]) -> "World":
        """A world file (TOML, UTF-8); errors name the file."""
        path = Path(path)
        if path.is_dir():
            raise ValueError(f"world file {str(path)!r} is a directory, not a TOML file")
        try:
            text = path.read_text("utf-8")
        except UnicodeDecodeError as exc:
            raise ValueError(f"world file {str(path)!r} is not UTF-8 text (byte 0x{exc.object[exc.start]:02x} "
                             f"at position {exc.start}): save it as UTF-8") from None
        except OSError as exc:
            raise ValueError(f"world file {str(path)!r}: {exc.strerror or exc}") from None
        try:
            return cls.from_toml_string(text, default_name=path.stem)
        except (ValueError, TypeError) as exc:
            raise type(exc)(f"{path}: {exc}") from None

    @classmethod
    def from_toml_string(cls, text: str, default_name: str = "world") -> "World":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"world file is not valid TOML: {exc}") from None
        return cls.from_dict(data, default_name)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], default_name: str = "world") -> "World":
        allowed = {"name", "description", "margin", "obstacle"}
        unknown = sorted(set(data) - allowed)
        if unknown:
            raise ValueError(f"world file: unknown field(s) {', '.join(unknown)}; allowed: "
                             f"{', '.join(sorted(allowed))} ([[obstacle]] tables)")
        if "margin" not in data:
            raise ValueError("world file: margin (the clearance to keep, m) is missing")
        raw = data.get("obstacle", [])
        if not isinstance(raw, list):
            raise TypeError("world file: obstacle must be an array of tables ([[obstacle]])")
        obstacles: List[Obstacle] = []
        for i, table in enumerate(raw):
            if not isinstance(table, Mapping):
                raise TypeError(f"world file: obstacle[{i}] must be a table")
            name = table.get("name")
            if not isinstance(name, str) or not name:
                raise ValueError(f"world file: obstacle[{i}].name is missing (every obstacle is named)")
            where = f"obstacle {name!r} (obstacle[{i}])"
            if "kind" not in table:
                raise ValueError(f"{where}.kind is missing; one of {tuple(OBSTACLE_KINDS)}")
            values = {k: v for k, v in table.items() if k not in ("name", "kind")}
            obstacles.append(Obstacle.make(name, table["kind"], where, **values))
        desc = data.get("description", "")
        if not isinstance(desc, str):
            raise TypeError("world file: description must be a string")
        return cls(name=str(data.get("name", default_name)), margin=data["margin"],
                   obstacles=tuple(obstacles), description=desc)


def names() -> List[str]:
    """The example worlds shipped with the package."""
    return sorted(p.name[:-5] for p in resources.files(__package__ + ".worlds").iterdir()
                  if p.name.endswith(".toml"))


def get(name: str) -> World:
    """An example world by name (see :func:`names`)."""
    if name not in names():
        raise ValueError(f"unknown world {name!r}; known: {', '.join(names())}")
    text = resources.files(__package__ + ".worlds").joinpath(f"{name}.toml").read_text("utf-8")
    return World.from_toml_string(text, default_name=name)
