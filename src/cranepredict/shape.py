"""The crane's shape for the collision guard: the ``[shape]`` table of the crane file.

Each part is a capsule (a segment between two points of the crane plus a radius), or, for the
load, a sphere or a box hanging below a point. A point is one of the crane's named points
(:data:`cranepredict.POINT_NAMES`, e.g. ``"tilt_pivot"``) or ``[body, x, y]``: coordinates in a
body's frame of docs/model.md (``"boom_plane"``, ``"lift_boom"``, ``"outer_boom"``,
``"extension_boom"``). SI units (m). See docs/guard.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Optional, Tuple, Union

from ._checks import number as _number

__all__ = ["Part", "Shape", "PART_KINDS", "BODY_FRAMES"]

PART_KINDS = ("capsule", "sphere", "box")
#: The largest coordinate or size accepted, m (the C core's CRANE_GUARD_LENGTH_MAX).
LENGTH_MAX = 1e6
#: Frames a point can be given in, by the body's name (docs/model.md "Frames").
BODY_FRAMES = ("boom_plane", "lift_boom", "outer_boom", "extension_boom")

Point = Union[str, Tuple[str, float, float]]


def _point(value: Any, where: str) -> Point:
    from .types import POINT_NAMES

    if isinstance(value, str):
        if value not in POINT_NAMES:
            raise ValueError(f"{where} must be one of the crane's points {POINT_NAMES} or "
                             f"[body, x, y], got {value!r}")
        return value
    if isinstance(value, (list, tuple)) and len(value) == 3 and isinstance(value[0], str):
        if value[0] not in BODY_FRAMES:
            raise ValueError(f"{where}[0] must be one of {BODY_FRAMES}, got {value[0]!r}")
        x, y = _number(value[1], f"{where}[1]"), _number(value[2], f"{where}[2]")
        if not (abs(x) <= LENGTH_MAX and abs(y) <= LENGTH_MAX):
            raise ValueError(f"{where} coordinates must be within +-{LENGTH_MAX:g} m, got {x:g}, {y:g}")
        return (value[0], x, y)
    raise TypeError(f"{where} must be a point name or [body, x, y], got {value!r}")


@dataclass(frozen=True)
class Part:
    """One part of the crane's shape.

    capsule: the segment ``a``-``b`` grown by ``radius`` (>= 0); sphere: ``radius`` (> 0), centre
    ``drop`` m below ``a``; box: ``size`` (full lengths, > 0: outward in the boom plane, lateral,
    up), centre ``drop`` m below ``a``, turning with the slew. Lengths in m.
    """

    name: str
    kind: str
    a: Point
    b: Optional[Point] = None
    radius: float = 0.0
    drop: float = 0.0
    size: Tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        where = f"shape.{self.name}"
        if not isinstance(self.kind, str) or self.kind not in PART_KINDS:
            raise ValueError(f"{where}.kind must be one of {PART_KINDS}, got {self.kind!r}")
        object.__setattr__(self, "a", _point(self.a, f"{where}.a"))
        r = _number(self.radius, f"{where}.radius")
        d = _number(self.drop, f"{where}.drop")
        if self.kind == "capsule":
            if self.b is None:
                raise ValueError(f"{where}.b is missing (a capsule needs two points)")
            object.__setattr__(self, "b", _point(self.b, f"{where}.b"))
            if not 0 <= r <= LENGTH_MAX:
                raise ValueError(f"{where}.radius must be in [0, {LENGTH_MAX:g}] m, got {r}")
        elif self.b is not None:
            raise ValueError(f"{where}.b is only for capsules (a {self.kind} hangs below a)")
        if self.kind == "sphere" and not 0 < r <= LENGTH_MAX:
            raise ValueError(f"{where}.radius must be in (0, {LENGTH_MAX:g}] m, got {r}")
        if not abs(d) <= LENGTH_MAX:
            raise ValueError(f"{where}.drop must be within +-{LENGTH_MAX:g} m, got {d}")
        size = self.size
        if self.kind == "box":
            if isinstance(size, (str, bytes)) or not hasattr(size, "__len__") or len(size) != 3:
                raise TypeError(f"{where}.size must be [x, y, z] in m, got {size!r}")
            size = tuple(_number(v, f"{where}.size[{i}]") for i, v in enumerate(size))
            if not all(0 < v <= 2 * LENGTH_MAX for v in size):
                raise ValueError(f"{where}.size must be in (0, {2 * LENGTH_MAX:g}] m in every "
                                 f"direction, got {list(size)}")
        object.__setattr__(self, "radius", r)
        object.__setattr__(self, "drop", d)
        object.__setattr__(self, "size", tuple(float(v) for v in size))

    def to_plain(self) -> dict:
        out: dict = {"kind": self.kind, "a": _plain_point(self.a)}
        if self.kind == "capsule":
            out["b"] = _plain_point(self.b)
        if self.kind in ("capsule", "sphere"):
            out["radius"] = self.radius
        if self.kind in ("sphere", "box"):
            out["drop"] = self.drop
        if self.kind == "box":
            out["size"] = list(self.size)
        return out


#: The fields each kind of part takes in a crane file's [shape] table.
_KIND_FIELDS = {"capsule": {"kind", "a", "b", "radius"}, "sphere": {"kind", "a", "radius", "drop"},
                "box": {"kind", "a", "size", "drop"}}


def _plain_point(p: Optional[Point]) -> Any:
    return p if isinstance(p, str) else list(p)  # type: ignore[arg-type]


@dataclass(frozen=True)
class Shape:
    """The parts of a crane for the collision guard, in the crane file's order.
    ``estimates``: the parts whose sizes are estimates (for the PATU 655: all of them)."""

    parts: Tuple[Part, ...]
    estimates: Tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        if not self.parts:
            raise ValueError("shape must have at least one part")
        names = [p.name for p in self.parts]
        if len(set(names)) != len(names):
            raise ValueError(f"shape: part names must be unique, got {names}")

    @property
    def names(self) -> Tuple[str, ...]:
        return tuple(p.name for p in self.parts)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> "Shape":
        if not isinstance(data, Mapping):
            raise TypeError(f"shape must be a table, got {type(data).__name__}")
        est = data.get("estimates", [])
        if isinstance(est, str) or not all(isinstance(e, str) for e in est):
            raise TypeError("shape.estimates must be a list of part names")
        parts = []
        allowed = {"kind", "a", "b", "radius", "drop", "size"}
        for name, table in data.items():
            if name == "estimates":
                continue
            if not isinstance(table, Mapping):
                raise TypeError(f"shape.{name} must be a table, got {type(table).__name__}")
            unknown = sorted(set(table) - allowed)
            if unknown:
                raise ValueError(f"shape.{name}: unknown field(s) {', '.join(unknown)}; allowed: "
                                 f"{', '.join(sorted(allowed))}")
            if "kind" not in table or "a" not in table:
                raise ValueError(f"shape.{name}: kind and a are required")
            kind = table["kind"]
            if isinstance(kind, str) and kind in _KIND_FIELDS:
                extra = sorted(set(table) - _KIND_FIELDS[kind])
                if extra:
                    raise ValueError(f"shape.{name}: {', '.join(extra)} is not a field of a {kind} "
                                     f"(a {kind} takes {', '.join(sorted(_KIND_FIELDS[kind]))})")
            parts.append(Part(name=name, **dict(table)))
        return cls(parts=tuple(parts), estimates=tuple(est))

    def to_plain(self) -> dict:
        out: dict = {"estimates": list(self.estimates)}
        for p in self.parts:
            out[p.name] = p.to_plain()
        return out
