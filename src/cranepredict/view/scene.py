"""What the display draws for a frame, as plain arrays (no viewer library needed).

Every solid becomes instances of three unit meshes, so one frame is a handful of array updates
whatever the number of parts, ghosts and obstacles: a unit ``cylinder`` (radius 1, height 1 along
its Z, centred), a unit ``sphere`` (radius 1) and a unit ``box`` (edges 1), each instance placed by
a position, an orientation (quaternion w, x, y, z) and per-axis scales. A capsule is a cylinder
and a sphere at each end.

Colours: each part by its predicted clearance (the minimum over the horizon, from the verdict):
red at or within the margin, amber within ``NEAR_BAND`` beyond it, green farther; the banner by the
signal (GO green, WARN amber, STOP red, FAULT grey).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

from ..guard import part_solids
from ..world import World
from .frame import Frame

__all__ = ["Instances", "Banner", "Scene", "frame_scene", "obstacle_instances", "pose_instances",
           "part_colour", "ghost_indices", "banner", "sample_at", "NEAR_BAND", "GHOSTS",
           "CLEARANCE_COLOURS", "SIGNAL_COLOURS", "OBSTACLE_COLOUR", "GROUND_COLOUR",
           "CONTACT_OBSTACLE_COLOUR", "GHOST_OPACITY", "SHAPES"]

RGB = Tuple[int, int, int]

#: m beyond the margin within which a part is drawn amber ("near").
NEAR_BAND = 1.0
CLEARANCE_COLOURS: Dict[str, RGB] = {"within margin": (215, 35, 30), "near": (245, 165, 20),
                                     "clear": (45, 160, 75), "no obstacle": (150, 150, 160)}
SIGNAL_COLOURS: Dict[str, str] = {"GO": "#1e8a3a", "WARN": "#e39a00", "STOP": "#cc1010",
                                  "FAULT": "#5a5a66"}
OBSTACLE_COLOUR: RGB = (140, 95, 60)
CONTACT_OBSTACLE_COLOUR: RGB = (190, 40, 160)
GROUND_COLOUR: RGB = (185, 185, 175)
#: Ghosts (the crane at future times): how many, and their opacities, nearest first.
GHOSTS = 4
GHOST_OPACITY = (0.42, 0.34, 0.27, 0.21)
#: Obstacles thinner than this are drawn at this radius (m) so that they can be seen (a power
#: line's conductor is 15 mm); the guard measures them at their true size.
VISIBLE_RADIUS_MIN = 0.04
#: Side of the square drawn for a ground plane, m.
PLANE_SIZE = 30.0
PLANE_THICKNESS = 0.02
SHAPES = ("cylinder", "sphere", "box")


@dataclass(frozen=True, eq=False)
class Instances:
    """Instances of one unit mesh: positions (n, 3) m, wxyzs (n, 4), scales (n, 3) m,
    colours (n, 3) 0-255, opacities (n,) in (0, 1]."""

    positions: np.ndarray
    wxyzs: np.ndarray
    scales: np.ndarray
    colours: np.ndarray
    opacities: np.ndarray

    def __len__(self) -> int:
        return len(self.positions)


class _Builder:
    def __init__(self) -> None:
        self.rows: Dict[str, List[tuple]] = {k: [] for k in SHAPES}

    def add(self, shape: str, position, wxyz, scale, colour: RGB, opacity: float) -> None:
        self.rows[shape].append((position, wxyz, scale, colour, opacity))

    def capsule(self, a, b, radius: float, colour: RGB, opacity: float, caps: bool = True) -> None:
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        d = b - a
        length = float(np.linalg.norm(d))
        if length > 1e-9:
            self.add("cylinder", 0.5 * (a + b), _quat_z_to(d / length), (radius, radius, length),
                     colour, opacity)
        if caps or length <= 1e-9:
            for end in ((a, b) if length > 1e-9 else (a,)):
                self.add("sphere", end, (1.0, 0.0, 0.0, 0.0), (radius,) * 3, colour, opacity)

    def solid(self, s: dict, colour: RGB, opacity: float, min_radius: float = 0.0) -> None:
        kind = s["kind"]
        r = max(float(s.get("radius", 0.0)), min_radius)
        if kind == "capsule":
            self.capsule(s["a"], s["b"], r, colour, opacity)
        elif kind == "cylinder":
            self.capsule(s["a"], s["b"], r, colour, opacity, caps=False)
        elif kind == "sphere":
            self.add("sphere", s["a"], (1.0, 0.0, 0.0, 0.0), (r,) * 3, colour, opacity)
        elif kind == "box":
            axes = np.asarray(s["axes"], dtype=float).reshape(3, 3)
            self.add("box", s["a"], _quat_of(axes.T), tuple(2.0 * np.asarray(s["half"], dtype=float)),
                     colour, opacity)
        elif kind == "plane":
            n = np.asarray(s["b"], dtype=float)
            n = n / np.linalg.norm(n)
            centre = np.asarray(s["a"], dtype=float) - 0.5 * PLANE_THICKNESS * n
            self.add("box", centre, _quat_z_to(n), (PLANE_SIZE, PLANE_SIZE, PLANE_THICKNESS),
                     colour, opacity)
        else:  # pragma: no cover - the kinds are fixed by the world file and the shape
            raise ValueError(f"no drawing for a solid of kind {kind!r}")

    def build(self) -> Dict[str, Instances]:
        out = {}
        for shape, rows in self.rows.items():
            if not rows:
                out[shape] = Instances(np.zeros((0, 3)), np.zeros((0, 4)), np.zeros((0, 3)),
                                       np.zeros((0, 3), dtype=np.uint8), np.zeros(0))
                continue
            p, q, s, c, o = zip(*rows)
            out[shape] = Instances(np.array(p, dtype=float), np.array(q, dtype=float),
                                   np.array(s, dtype=float), np.array(c, dtype=np.uint8),
                                   np.array(o, dtype=float))
        return out


def _quat_z_to(u: np.ndarray) -> Tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) turning +Z onto the unit vector u (the shortest turn)."""
    ux, uy, uz = (float(v) for v in u)
    if uz < -1.0 + 1e-12:
        return (0.0, 1.0, 0.0, 0.0)
    w = 1.0 + uz
    n = math.sqrt(w * w + uy * uy + ux * ux)
    return (w / n, -uy / n, ux / n, 0.0)


def _quat_of(R: np.ndarray) -> Tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) of a rotation matrix (columns: the turned axes)."""
    m = np.asarray(R, dtype=float)
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = (0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s)
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = ((m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s)
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = ((m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = ((m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s)
    n = math.sqrt(sum(v * v for v in q))
    return tuple(v / n for v in q)  # type: ignore[return-value]


# -- colours and texts ------------------------------------------------------------------------------

def part_colour(clearance: float, margin: float) -> RGB:
    """A part's colour from its predicted clearance (m) and the margin (m)."""
    if not math.isfinite(clearance):
        return CLEARANCE_COLOURS["no obstacle"]
    if clearance <= margin:
        return CLEARANCE_COLOURS["within margin"]
    if clearance <= margin + NEAR_BAND:
        return CLEARANCE_COLOURS["near"]
    return CLEARANCE_COLOURS["clear"]


def ghost_indices(t: np.ndarray, n: int = GHOSTS) -> Tuple[int, ...]:
    """The samples drawn as ghosts: the ones nearest to n even steps through the horizon
    (k / n of it, k = 1..n), distinct, never the first (that is the crane now)."""
    t = np.asarray(t, dtype=float)
    if len(t) < 2 or n < 1:
        return ()
    out: List[int] = []
    for k in range(1, n + 1):
        i = int(np.argmin(np.abs(t - t[-1] * k / n)))
        if i > 0 and i not in out:
            out.append(i)
    return tuple(out)


def sample_at(frame: Frame, t: float) -> int:
    """The sample nearest to t (s from now), t clamped to [0, horizon]."""
    return int(np.argmin(np.abs(frame.t - min(max(float(t), 0.0), frame.horizon))))


@dataclass(frozen=True)
class Banner:
    """The verdict in words: signal, colour (#rrggbb), the headline, the detail and the fields a
    person reads (time to contact s, part, obstacle, latest time to begin stopping s; None where
    there is none)."""

    signal: str
    colour: str
    headline: str
    detail: str
    time_to_contact: Optional[float]
    part: Optional[str]
    obstacle: Optional[str]
    stop_by: Optional[float]


def banner(frame: Frame) -> Banner:
    """What the banner says for a frame."""
    sig, v = frame.signal, frame.verdict
    colour = SIGNAL_COLOURS[sig]
    if v is None:
        return Banner(sig, colour, "no prediction", frame.fault, None, None, None, None)
    c = v.contact
    if c is None:
        return Banner(sig, colour, f"no contact within {v.horizon:g} s", v.reason,
                      None, None, None, None)
    pair = f"{c.part} - {c.obstacle}"
    latest = v.stop.latest if v.stop is not None else None
    if c.at_start:
        state = "in contact" if c.clearance <= 0 else f"{c.clearance:.2f} m apart"
        headline = f"{pair} {state} now (margin {v.margin:g} m)"
        return Banner(sig, colour, headline, v.reason, 0.0, c.part, c.obstacle, latest)
    if latest is None:
        when = "-"
    elif not math.isfinite(latest):
        when = "too late: no stop keeps the margin"
    elif sig == "STOP":
        when = "begin stopping now"
    else:
        when = f"begin stopping within {latest:.2f} s"
    headline = f"contact in {c.t:.2f} s, {pair}; {when}"
    return Banner(sig, colour, headline, v.reason, c.t, c.part, c.obstacle, latest)


# -- the scene of a frame ---------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class Scene:
    """What is drawn for one frame: the crane now (solid), the ghosts (translucent, at
    ``ghost_times`` s from now), the tip's path (N, 3), the closest points of the first contact
    (on the part, on the obstacle; None without contact), the part colours and the banner."""

    now: Dict[str, Instances]
    ghosts: Dict[str, Instances]
    ghost_times: Tuple[float, ...]
    tip_path: np.ndarray
    contact: Optional[Tuple[np.ndarray, np.ndarray]]
    part_colours: Dict[str, RGB]
    banner: Banner


def _part_colours(frame: Frame) -> Dict[str, RGB]:
    names = frame.crane.shape.names if frame.crane.shape is not None else ()
    if frame.verdict is None:
        return {n: CLEARANCE_COLOURS["no obstacle"] for n in names}
    v = frame.verdict
    return {n: part_colour(v.clearance.get(n, math.inf), v.margin) for n in names}


def _solids_at(frame: Frame, k: int) -> Dict[str, dict]:
    return part_solids(frame.crane, frame.state, frame.theta[k], slew=float(frame.slew[k]),
                       extension=float(frame.extension[k]))


def pose_instances(frame: Frame, samples: Sequence[int], opacities: Sequence[float],
                   colours: Optional[Dict[str, RGB]] = None) -> Dict[str, Instances]:
    """The crane's parts at the given samples as instances (one opacity per sample)."""
    colours = _part_colours(frame) if colours is None else colours
    b = _Builder()
    for k, opacity in zip(samples, opacities):
        for name, s in _solids_at(frame, k).items():
            b.solid(s, colours[name], opacity)
    return b.build()


def frame_scene(frame: Frame, ghosts: int = GHOSTS) -> Scene:
    """Everything drawn for a frame (the obstacles are drawn once per world:
    :func:`obstacle_instances`)."""
    if frame.crane.shape is None:
        raise ValueError(f"crane {frame.crane.name!r} has no [shape] table: the display draws "
                         f"its parts from it (see docs/guard.md)")
    colours = _part_colours(frame)
    idx = ghost_indices(frame.t, ghosts)
    now = pose_instances(frame, [0], [1.0], colours)
    ghost = pose_instances(frame, idx, GHOST_OPACITY[:len(idx)] if len(idx) <= len(GHOST_OPACITY)
                           else np.linspace(0.42, 0.15, len(idx)), colours)
    c = frame.verdict.contact if frame.verdict is not None else None
    contact = None if c is None else (np.array(c.on_part), np.array(c.on_obstacle))
    return Scene(now=now, ghosts=ghost, ghost_times=tuple(float(frame.t[i]) for i in idx),
                 tip_path=np.array(frame.tip), contact=contact, part_colours=colours,
                 banner=banner(frame))


def obstacle_instances(world: World, highlight: Iterable[str] = ()) -> Dict[str, Instances]:
    """The world's obstacles as instances (the ones named in ``highlight`` in the contact
    colour, the ground planes in the ground colour)."""
    hl = set(highlight)
    b = _Builder()
    for o in world.obstacles:
        s = o.solid()
        if s["kind"] == "plane":
            b.solid(s, GROUND_COLOUR, 0.55)
        else:
            b.solid(s, CONTACT_OBSTACLE_COLOUR if o.name in hl else OBSTACLE_COLOUR, 1.0,
                    min_radius=VISIBLE_RADIUS_MIN)
    return b.build()


def unit_meshes(segments: int = 24) -> Dict[str, Tuple[np.ndarray, np.ndarray]]:
    """(vertices, faces) of the unit cylinder (radius 1, height 1 along Z, centred), the unit
    sphere (radius 1) and the unit box (edges 1), outward faces counter-clockwise."""
    a = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    ring = np.column_stack([np.cos(a), np.sin(a)])
    # cylinder: two rings and the two end caps' centres
    v = np.vstack([np.column_stack([ring, np.full(segments, -0.5)]),
                   np.column_stack([ring, np.full(segments, 0.5)]), [[0, 0, -0.5], [0, 0, 0.5]]])
    f = []
    for i in range(segments):
        j = (i + 1) % segments
        f += [(i, j, segments + j), (i, segments + j, segments + i),
              (2 * segments, j, i), (2 * segments + 1, segments + i, segments + j)]
    cyl = (v, np.array(f))
    # sphere: latitude-longitude
    lat = np.linspace(0.0, np.pi, segments // 2 + 1)
    sv = [(math.sin(p) * math.cos(q), math.sin(p) * math.sin(q), math.cos(p)) for p in lat for q in a]
    sf = []
    for r in range(len(lat) - 1):
        for i in range(segments):
            j = (i + 1) % segments
            p0, p1 = r * segments + i, r * segments + j
            q0, q1 = (r + 1) * segments + i, (r + 1) * segments + j
            sf += [(p0, q0, q1), (p0, q1, p1)]
    sph = (np.array(sv), np.array(sf))
    bv = np.array([(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    bf = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                   (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])
    return {"cylinder": cyl, "sphere": sph, "box": (bv, bf)}
