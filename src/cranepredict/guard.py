"""The collision guard: will the crane hit anything in the predicted future, and when must it stop?

:func:`guard` predicts the future under the current command (the C core), then the C core's
``crane_guard`` measures every part of the crane's shape (the crane file's ``[shape]``) against
every obstacle of a :class:`~cranepredict.world.World` along it: the minimum clearance per part,
the first contact (found between samples too), the latest time to begin stopping and the signal
GO / WARN / STOP. See docs/guard.md.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import api
from ._checks import number as _number
from .crane import Crane
from .shape import Shape
from .types import Hold, Inputs, Pressure, PressureSeries, State, Trajectory, Valve, ValveSeries
from .world import World

__all__ = ["guard", "Verdict", "Contact", "StopAnalysis", "stop_inputs", "stop_state", "part_solids",
           "obstacle_clearances", "stop_settled", "DEFAULT_REACTION", "DEFAULT_CYCLE", "SIGNALS"]

#: Delay from the stop decision to the stop taking effect, s (operator or controller + valve).
DEFAULT_REACTION = 0.2
#: Control cycle, s: STOP when stopping cannot wait one more cycle.
DEFAULT_CYCLE = 0.01
DEFAULT_TIME_TOLERANCE = 1e-4        # s: the first contact is located this closely
DEFAULT_CLEARANCE_TOLERANCE = 1e-3   # m: per-part minima may be this much too large
#: Default spacing of the samples the guard judges, s: every round(GUARD_SPACING / dt)-th step of
#: the prediction (which still integrates at dt). Between them the motion bound finds any contact.
GUARD_SPACING = 0.01
#: How long each piece of a stop is predicted, s: the PATU 655 at full lever comes to rest within
#: about 0.1 s of its valve reaching neutral (then oscillates by millimetres on the oil); a stop
#: still moving at the end of a piece is followed by another, up to STOP_FOLLOW_MAX.
DEFAULT_STOP_HORIZON = 0.5
#: The longest a stop is followed, s: a stop that has not come to rest by then (a slewing load on
#: its relief valves) is not a stop the guard can vouch for: that stop time counts as unsafe.
STOP_FOLLOW_MAX = 10.0
#: At rest: every point of the crane's path slower than this over the final STOP_REST_WINDOW s of the
#: stop (the tip is the fastest point of a turning boom, and carries the slew and the telescope).
STOP_REST_SPEED = 0.005   # m/s
STOP_REST_WINDOW = 0.1    # s
SIGNALS = ("GO", "WARN", "STOP")
JOINTS = ("lift", "tilt", "slew", "extension")


def _c() -> Any:
    """(ffi, lib) of the compiled core, imported on first use (the twin works without it)."""
    from ._cranepredict import ffi, lib

    return ffi, lib


def _kind(name: str) -> int:
    return int(getattr(_c()[1], "CRANE_SOLID_" + name.upper()))


def _kind_name(code: int) -> str:
    return next(k for k in ("plane", "box", "capsule", "sphere", "cylinder") if _kind(k) == code)


def _field_name(code: int) -> str:
    """The world file's / shape's name of a CRANE_GUARD_FIELD_* code (half extents are given as size)."""
    for name in ("kind", "a", "b", "radius", "axes", "half", "drop"):
        if int(getattr(_c()[1], "CRANE_GUARD_FIELD_" + name.upper())) == code:
            return "size" if name == "half" else name
    return "?"


_FRAMES = {"boom_plane": "BASE", "lift_boom": "LIFT", "link_pin": "LINK_PIN",
           "outer_boom": "OUTER", "extension_boom": "EXTENSION"}


def _frame(body: str) -> int:
    return int(getattr(_c()[1], "CRANE_FRAME_" + _FRAMES[body]))


# -- what "stop" means -----------------------------------------------------------------------------

def _stop_drive(drive: Any) -> Any:
    """The stop of one drive: the operator's lever to neutral. A valve-driven actuator (Valve,
    ValveSeries) stops by its valve to neutral (lever 0) and decelerates through the spool's lag,
    the oil's stiffness and its relief valves. A pressure-driven one (Pressure, PressureSeries: the
    pressures were given, the valve that made them was not) stops the same way: its valve to
    neutral, from the chamber pressures it had (the guard starts the spool fully open in the
    direction of motion: the longest the valve can take to close). A held actuator stays held."""
    if isinstance(drive, (Valve, ValveSeries, Pressure, PressureSeries)):
        return Valve(0.0)
    if isinstance(drive, Hold):
        return Hold()
    raise TypeError(f"no stop is defined for a {type(drive).__name__} drive")


def stop_inputs(inputs: Inputs) -> Inputs:
    """The inputs that stop the crane: every drive (lift, tilt, slew, extension) to its stop,
    the valve to neutral (the one place that says so); held drives stay held."""
    if not isinstance(inputs, Inputs):
        raise TypeError(f"inputs must be a cranepredict.Inputs, got {type(inputs).__name__}")
    return Inputs(**{name: _stop_drive(getattr(inputs, name)) for name in JOINTS})


def _unmodelled_stop(crane: Crane, inputs: Inputs) -> Optional[str]:
    """Why the stop of these inputs cannot be predicted (a moving drive whose actuator has no
    valve in the crane file), or None."""
    actuators = {"lift": crane.lift_cylinder, "tilt": crane.tilt_cylinder,
                 "slew": crane.slew_drive, "extension": crane.extension_cylinder}
    for name in JOINTS:
        if isinstance(getattr(inputs, name), Hold):
            continue
        act = actuators[name]
        if act is None or getattr(act, "hydraulics", None) is None:
            return (f"the {name} is pressure-driven and its actuator has no hydraulics table in "
                    f"the crane file: its stop (the valve to neutral) cannot be predicted")
    return None


# -- results ---------------------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class Contact:
    """The first time the clearance of a part to an obstacle is at or below the margin.

    t (s): the clearance is above the margin on [0, t); on_part, on_obstacle: the closest points
    at t (world, m); theta: joint angles at t (rad); slew (rad), extension (m) at t; gradient:
    d clearance / d q per joint, q = lift angle, tilt angle, slew (m/rad), extension (m/m);
    approach: its rate from each joint's motion at t (m/s, < 0 = that joint closes the gap);
    closing: the joints (levers) that close it, to cut while the others stay allowed.
    """

    t: float
    part: str
    obstacle: str
    clearance: float
    on_part: np.ndarray
    on_obstacle: np.ndarray
    theta: np.ndarray
    slew: float
    extension: float
    gradient: Dict[str, float]
    approach: Dict[str, float]
    closing: Tuple[str, ...]
    at_start: bool


@dataclass(frozen=True)
class StopAnalysis:
    """When stopping must begin: ``latest`` (s) is the last time at which the stop command, taking
    effect ``reaction`` s later, keeps the clearance above the margin (< 0: already too late).
    ``model`` says what the stop is; ``note`` what that assumes."""

    latest: float
    reaction: float
    model: str
    note: str


@dataclass(frozen=True, eq=False)
class Verdict:
    """The guard's answer for one predicted future (see :func:`guard`)."""

    signal: str
    reason: str
    clearance: Dict[str, float]
    contact: Optional[Contact]
    stop: Optional[StopAnalysis]
    margin: float
    horizon: float
    world: World
    trajectory: Trajectory = field(repr=False)
    evaluations: int = 0

    def to_dict(self) -> dict:
        """Plain types, for JSON."""
        c = self.contact
        out: dict = {"signal": self.signal, "reason": self.reason, "world": self.world.name,
                     "margin_m": self.margin, "horizon_s": self.horizon,
                     # None: no obstacle to measure against (JSON has no infinity)
                     "min_clearance_m": {k: (c if math.isfinite(c) else None)
                                         for k, c in self.clearance.items()},
                     "evaluations": self.evaluations,
                     "contact": None, "stop": None}
        if c is not None:
            out["contact"] = {"t_s": c.t, "part": c.part, "obstacle": c.obstacle,
                              "clearance_m": c.clearance, "at_start": c.at_start,
                              "on_part_m": c.on_part.tolist(), "on_obstacle_m": c.on_obstacle.tolist(),
                              "theta_rad": c.theta.tolist(), "slew_rad": c.slew,
                              "extension_m": c.extension, "gradient": dict(c.gradient),
                              "approach_m_per_s": dict(c.approach), "closing": list(c.closing)}
        if self.stop is not None:
            out["stop"] = {"latest_s": self.stop.latest if math.isfinite(self.stop.latest) else None,
                           "reaction_s": self.stop.reaction,
                           "model": self.stop.model, "note": self.stop.note}
        return out


# -- translation to the C structs (cached: cranes, shapes and worlds are immutable) -------------

def _anchor(dst: Any, point: Any, crane: Crane) -> None:
    g = crane.geometry
    # each named point: the body whose frame it is given in (docs/model.md "Frames") and where
    named = {"pillar_base": ("boom_plane", (0.0, 0.0)),
             "lift_pivot": ("boom_plane", g.lift_pivot),
             "lift_cylinder_base": ("boom_plane", g.lift_cylinder_base),
             "lift_cylinder_rod": ("lift_boom", g.lift_cylinder_rod),
             "tilt_cylinder_base": ("lift_boom", g.tilt_cylinder_base),
             "link1_pivot": ("lift_boom", g.link1_pivot),
             "link_pin": ("link_pin", (0.0, 0.0)),
             "link2_attach": ("outer_boom", g.link2_attach),
             "tilt_pivot": ("lift_boom", g.tilt_pivot),
             "extension_mount": ("outer_boom", g.extension_mount),
             "tip": ("extension_boom", (g.tip_distance, 0.0))}
    if isinstance(point, str):
        body, at = named[point]
    else:
        body, at = point[0], (point[1], point[2])
    dst.frame = _frame(body)
    dst.at.x, dst.at.y = at


def _parts(crane: Crane, shape: Shape) -> Any:
    ffi, _ = _c()
    arr = ffi.new("crane_part[]", len(shape.parts))
    for dst, p in zip(arr, shape.parts):
        dst.kind = _kind(p.kind)
        _anchor(dst.a, p.a, crane)
        if p.b is not None:
            _anchor(dst.b, p.b, crane)
        dst.radius, dst.drop = p.radius, p.drop
        dst.half = [0.5 * v for v in p.size]
    return arr


def _solids(world: World) -> Any:
    ffi, _ = _c()
    arr = ffi.new("crane_solid[]", max(1, len(world.obstacles)))
    for dst, o in zip(arr, world.obstacles):
        s = o.solid()
        dst.kind = _kind(s["kind"])
        dst.a = list(s["a"])
        if "b" in s:
            dst.b = list(s["b"])
        dst.radius = s.get("radius", 0.0)
        if "axes" in s:
            dst.axes = list(s["axes"])
            dst.half = list(s["half"])
    return arr


_CACHE: dict = {}
_CACHE_MAX = 64


def _cached(kind: str, key: Tuple[Any, ...], build: Any) -> Any:
    """Per-object cache keyed by identity, holding the objects so their ids stay theirs."""
    k = (kind,) + tuple(id(x) for x in key)
    entry = _CACHE.get(k)
    if entry is None or any(a is not b for a, b in zip(entry[0], key)):
        if len(_CACHE) >= _CACHE_MAX:
            _CACHE.clear()
        entry = (key, build())
        _CACHE[k] = entry
    return entry[1]


def _check_layout(parts: Any, n_parts: int, solids: Any, world: World, shape: Shape) -> None:
    from ._core import ensure

    ffi, lib = _c()
    which, fld = ffi.new("size_t *"), ffi.new("int *")
    status = lib.crane_guard_check(parts, n_parts, solids, len(world.obstacles), which, fld)
    if status == lib.CRANE_E_PART:
        raise ValueError(f"shape.{shape.parts[which[0]].name}.{_field_name(fld[0])} is not valid")
    if status == lib.CRANE_E_SOLID:
        o = world.obstacles[which[0]]
        raise ValueError(f"obstacle {o.name!r} (obstacle[{which[0]}]).{_field_name(fld[0])} "
                         f"is not valid")
    ensure(status, "guard")


def part_solids(crane: Crane, state: State, theta: Optional[np.ndarray] = None,
                shape: Optional[Shape] = None, *, slew: Optional[float] = None,
                extension: Optional[float] = None) -> Dict[str, dict]:
    """The parts as world solids at one pose (default: the state's joint angles, slew and
    extension), for drawing and checks: name -> {"kind", "a", "b", "radius", "axes", "half"}
    (numpy arrays, m)."""
    shape = _shape(crane, shape)
    slew = state.slew if slew is None else _number(slew, "slew")
    extension = state.extension if extension is None else _number(extension, "extension")
    if theta is None:
        from . import _core

        theta = np.array([_core.joint_angle(crane, 0, state.lift_stroke, state.extension)[0],
                          _core.joint_angle(crane, 1, state.tilt_stroke, state.extension)[0]])
    from . import _core

    ffi, lib = _c()
    model = _core.model(crane, state.extension)
    parts = _cached("parts", (crane, shape), lambda: _parts(crane, shape))
    out = ffi.new("crane_solid[]", len(shape.parts))
    _core.ensure(lib.crane_part_solids(model, parts, len(shape.parts), slew, extension,
                                       [float(theta[0]), float(theta[1])], out), "part_solids")
    return {p.name: {"kind": _kind_name(s.kind), "a": np.array(list(s.a)), "b": np.array(list(s.b)),
                     "radius": float(s.radius), "axes": np.array(list(s.axes)).reshape(3, 3),
                     "half": np.array(list(s.half))}
            for p, s in zip(shape.parts, out)}


def _shape(crane: Crane, shape: Optional[Shape]) -> Shape:
    if not isinstance(crane, Crane):
        raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
    shape = crane.shape if shape is None else shape
    if shape is None:
        raise ValueError(f"crane {crane.name!r} has no [shape] table (the guard needs the parts' "
                         f"sizes; see docs/guard.md)")
    if not isinstance(shape, Shape):
        raise TypeError(f"shape must be a cranepredict.Shape, got {type(shape).__name__}")
    return shape


# -- the verdict -----------------------------------------------------------------------------------

def guard(crane: Crane, world: World, state: State, inputs: Inputs, horizon: float, *,
          dt: Optional[float] = None, reaction: float = DEFAULT_REACTION,
          cycle: float = DEFAULT_CYCLE, margin: Optional[float] = None,
          time_tolerance: float = DEFAULT_TIME_TOLERANCE,
          clearance_tolerance: float = DEFAULT_CLEARANCE_TOLERANCE,
          sample_every: Optional[int] = None, stop_horizon: float = DEFAULT_STOP_HORIZON,
          shape: Optional[Shape] = None, stop_hint: Optional[float] = None) -> Verdict:
    """Predicts the future under ``inputs`` and judges it against the world's obstacles.

    Returns a :class:`Verdict`: the minimum clearance of each part over the samples (m; at most
    ``clearance_tolerance`` above the exact minimum), the first contact (clearance <= margin; found
    between samples too, to ``time_tolerance``), the stop analysis and the signal: GO (no contact
    within the horizon), WARN (contact predicted, stopping can wait beyond the next control
    ``cycle``), STOP (stopping must begin now, or the clearance is already within the margin).
    The stop is :func:`stop_inputs`: every moving drive's valve to neutral, taking effect
    ``reaction`` s after the decision, followed through the oil and the inertia until the crane is
    at rest (pieces of ``stop_horizon`` s, at most STOP_FOLLOW_MAX s); the latest stop time is the
    last judged sample from which that stop keeps the margin (docs/guard.md, "The guarantee").
    A stop the model cannot predict (a pressure drive without hydraulics, a stop that does not come
    to rest, a state the core cannot continue from) counts as unsafe. ``margin`` defaults to the
    world's. The parts move with each sample's joint angles, slew and extension. The prediction
    integrates at ``dt``; the guard judges every ``sample_every``-th step (default: about every
    GUARD_SPACING = 10 ms), the per-part minima are over those samples, and contacts are found
    between them too (docs/guard.md, "Nothing is missed"). ``Verdict.trajectory`` holds those samples.
    ``stop_hint`` (s from the prediction's start, finite), a latest stop time expected from
    a previous verdict (a control loop's last cycle, moved by the time since), is where the search
    for the latest stop time begins, outwards in doubling steps, then by splitting the bracket:
    the same answer as without it (stopping later is taken never to be safer, as the search
    assumes) from 2 stop predictions instead of about 10 when the hint is right.
    """
    shape = _shape(crane, shape)
    if not isinstance(world, World):
        raise TypeError(f"world must be a cranepredict.World, got {type(world).__name__}")
    if not isinstance(state, State):
        raise TypeError(f"state must be a cranepredict.State, got {type(state).__name__}")
    if not isinstance(inputs, Inputs):
        raise TypeError(f"inputs must be a cranepredict.Inputs, got {type(inputs).__name__}")
    margin = world.margin if margin is None else margin
    checks = (("margin", margin, 0.0, True), ("reaction", reaction, 0.0, True),
              ("cycle", cycle, 0.0, False), ("time_tolerance", time_tolerance, 0.0, False),
              ("clearance_tolerance", clearance_tolerance, 0.0, True),
              ("stop_horizon", stop_horizon, 0.0, False))
    values = {}
    for name, value, low, closed in checks:
        v = _number(value, name)
        if not (math.isfinite(v) and (v >= low if closed else v > low)):
            raise ValueError(f"{name} must be {'>=' if closed else '>'} {low:g} and finite, got {v:g}")
        values[name] = v
    if stop_hint is not None:
        stop_hint = _number(stop_hint, "stop_hint")   # finite, or a ValueError naming it
    if values["stop_horizon"] > STOP_FOLLOW_MAX:
        raise ValueError(f"stop_horizon must be in (0, {STOP_FOLLOW_MAX:g}] s "
                         f"(cranepredict.guard.STOP_FOLLOW_MAX), got {values['stop_horizon']:g}")
    dt = api.DEFAULT_DT if dt is None else dt
    if sample_every is None:
        step = _number(dt, "dt")
        sample_every = max(1, int(round(GUARD_SPACING / step))) if step > 0 else 1
    # checks crane, state, inputs, horizon, dt and sample_every, naming the field
    traj = api.predict_many(crane, [state], [inputs], horizon, dt=dt, sample_every=sample_every)[0]
    stop = stop_inputs(inputs)
    res, clearance = _judge(crane, world, _samples(traj), shape, values)
    verdict = _verdict(res, clearance, shape, world, values, float(horizon), traj)
    if verdict.contact is None or _freezes(stop):
        return verdict
    if verdict.contact.at_start:   # too late for any stop: say which stop that is
        return _with_stop(verdict, -math.inf, values, None)
    why = _unmodelled_stop(crane, inputs)
    if why is not None:
        return _with_stop(verdict, -math.inf, values, why)
    latest, why = _latest_stop(crane, world, traj, inputs, stop, shape, values, dt, sample_every,
                               verdict.contact.t, stop_hint)
    return _with_stop(verdict, latest, values, why)


def _freezes(stop: Inputs) -> bool:
    """True if every drive is held: nothing moves, so a contact can only be one at t = 0."""
    return all(isinstance(getattr(stop, name), Hold) for name in JOINTS)


#: What crane_guard reads of a sample: the joint angles, slew, extension and their rates.
SAMPLE_FIELDS = ("t", "theta", "omega", "slew", "extension", "slew_rate", "extension_rate")


def _samples(traj: Trajectory) -> np.ndarray:
    """The C samples crane_guard reads, from a prediction."""
    from . import _core

    samples = np.zeros(len(traj.t), dtype=_core.SAMPLE_DTYPE)
    for name in SAMPLE_FIELDS:
        samples[name] = getattr(traj, name)
    return samples


def _judge(crane: Crane, world: World, samples: np.ndarray, shape: Shape,
           values: Dict[str, float]) -> Tuple[Any, np.ndarray]:
    """crane_guard on C samples (_samples): the C result and the per-part clearances."""
    from . import _core

    ffi, lib = _c()
    # the guard reads the crane's geometry and limits from the model, not its extension
    model = _core.model(crane, crane.geometry.extension_min)
    parts = _cached("parts", (crane, shape), lambda: _parts(crane, shape))
    solids = _cached("solids", (world,), lambda: _solids(world))
    n_parts, n_obs = len(shape.parts), len(world.obstacles)
    _check_layout(parts, n_parts, solids, world, shape)

    clearance = np.empty(n_parts)
    work = np.empty(n_parts * (n_obs + lib.CRANE_GUARD_PART_WORK))
    cfg = ffi.new("crane_guard_config *", {
        "margin": values["margin"], "reaction": values["reaction"], "cycle": values["cycle"],
        "time_tolerance": values["time_tolerance"],
        "clearance_tolerance": values["clearance_tolerance"]})
    res = ffi.new("crane_guard_result *")
    status = lib.crane_guard(model, parts, n_parts, solids, n_obs,
                             ffi.cast("crane_sample *", ffi.from_buffer(samples)), len(samples),
                             cfg, ffi.cast("crane_real *", ffi.from_buffer(clearance)),
                             ffi.cast("crane_real *", ffi.from_buffer(work)), work.size, res)
    _core.ensure(status, "guard")
    return res, clearance


def obstacle_clearances(crane: Crane, world: World, samples: Mapping[str, np.ndarray], *,
                        margin: Optional[float] = None, shape: Optional[Shape] = None,
                        time_tolerance: float = DEFAULT_TIME_TOLERANCE,
                        clearance_tolerance: float = DEFAULT_CLEARANCE_TOLERANCE,
                        per_obstacle: bool = True) -> Tuple[np.ndarray, np.ndarray]:
    """The guard's measure of a motion against each obstacle on its own: per obstacle of the world,
    the first time any part comes within ``margin`` of it (s, found between samples too; inf:
    never) and the smallest clearance of any part to it over the samples (m, at most
    ``clearance_tolerance`` too large). ``samples`` maps SAMPLE_FIELDS (t, theta, omega, slew,
    extension and their rates) to arrays of one motion (a Trajectory's, or pieces joined).
    ``per_obstacle=False``: the same over all obstacles at once (arrays of one entry; one C call)."""
    from . import _core

    shape = _shape(crane, shape)
    ffi, lib = _c()
    margin = world.margin if margin is None else margin
    values = {"margin": margin, "reaction": DEFAULT_REACTION, "cycle": DEFAULT_CYCLE,
              "time_tolerance": time_tolerance, "clearance_tolerance": clearance_tolerance}
    t = np.asarray(samples["t"])
    c_samples = np.zeros(len(t), dtype=_core.SAMPLE_DTYPE)
    for name in SAMPLE_FIELDS:
        c_samples[name] = samples[name]
    model = _core.model(crane, crane.geometry.extension_min)
    parts = _cached("parts", (crane, shape), lambda: _parts(crane, shape))
    solids = _cached("solids", (world,), lambda: _solids(world))
    n_parts, n_obs = len(shape.parts), len(world.obstacles)
    _check_layout(parts, n_parts, solids, world, shape)
    cfg = ffi.new("crane_guard_config *", values)
    res = ffi.new("crane_guard_result *")
    per_part = np.empty(n_parts)
    groups = [(i, 1) for i in range(n_obs)] if per_obstacle else [(0, n_obs)]
    work = np.empty(n_parts * (groups[0][1] + lib.CRANE_GUARD_PART_WORK))
    pointers = (ffi.cast("crane_sample *", ffi.from_buffer(c_samples)),
                ffi.cast("crane_real *", ffi.from_buffer(per_part)),
                ffi.cast("crane_real *", ffi.from_buffer(work)))
    first, clearance = np.full(len(groups), math.inf), np.empty(len(groups))
    for i, (start, count) in enumerate(groups):
        _core.ensure(lib.crane_guard(model, parts, n_parts, solids + start, count, pointers[0],
                                     len(t), cfg, pointers[1], pointers[2], work.size, res),
                     "guard")
        if res.contact:
            first[i] = res.t
        clearance[i] = per_part.min() if n_parts else math.inf
    return first, clearance


def stop_settled(piece: Trajectory, stop_horizon: float = DEFAULT_STOP_HORIZON) -> bool:
    """Whether a predicted stop (from its start over ``piece.t[-1]`` s) needs no longer look: the
    crane is at rest at its end, or (once followed for at least twice ``stop_horizon``) its second
    half stays within the joint ranges of its first: an oscillation on the closed valves' oil,
    which no energy feeds."""
    if _at_rest(piece):
        return True
    horizon = float(piece.t[-1] - piece.t[0])
    half = int(np.searchsorted(piece.t, piece.t[0] + 0.5 * horizon))
    if half < 2 or horizon < 2 * stop_horizon - 1e-12:
        return False
    q = np.column_stack([piece.theta, np.broadcast_to(piece.slew, piece.t.shape),
                         np.broadcast_to(piece.extension, piece.t.shape)])
    first, second = _joint_ranges(q[:half]), _joint_ranges(q[half:])
    return bool(np.all(second[:, 0] >= first[:, 0]) and np.all(second[:, 1] <= first[:, 1]))


def stop_state(traj: Trajectory, k: int, inputs: Inputs) -> State:
    """The state from which the stop starts at sample k of a prediction under ``inputs``: the
    sample's state (Trajectory.state), with the spool of each pressure-driven actuator fully open
    in the direction of its motion (its valve then takes the longest to close; at rest, closed)."""
    import dataclasses

    st = traj.state(k)
    rates = {"lift": st.lift_stroke_rate, "tilt": st.tilt_stroke_rate, "slew": st.slew_rate,
             "extension": st.extension_rate}
    spools = {f"{name}_spool": float(np.sign(rates[name])) for name in JOINTS
              if isinstance(getattr(inputs, name), (Pressure, PressureSeries))}
    return dataclasses.replace(st, **spools) if spools else st


def _at_rest(traj: Trajectory) -> bool:
    """Every point of the crane slower than STOP_REST_SPEED over the final STOP_REST_WINDOW s:
    the tip's speed bounds the booms' (it is their farthest point from every joint's axis) and
    carries the slew and the telescope."""
    t, tip = traj.t, traj.tip
    last = t >= t[-1] - STOP_REST_WINDOW - 1e-12
    k = max(1, int(np.argmax(last)))
    speed = np.linalg.norm(np.diff(tip[k - 1:], axis=0), axis=1) / np.diff(t[k - 1:])
    return bool(speed.max() < STOP_REST_SPEED)


def _joint_ranges(q: np.ndarray) -> np.ndarray:
    """Per joint: (min, max) over rows of q (lift angle, tilt angle, slew, extension), (4, 2)."""
    return np.column_stack([q.min(axis=0), q.max(axis=0)])


def _stops_are_safe(crane: Crane, world: World, starts: Sequence[State], stop: Inputs,
                    shape: Shape, values: Dict[str, float], dt: float,
                    sample_every: int) -> List[Tuple[bool, str]]:
    """For each start: predicts the stop over stop_horizon, then on from where it ended until it
    has been followed twice as long and so on (at most STOP_FOLLOW_MAX), judging each piece, until
    the crane is at rest or only repeats itself (the second half stays within the joint ranges of
    the first: an oscillation on the closed valves' oil, which no energy feeds); (safe, why not).
    A piece continues from the last one's final state (Trajectory.final_state) rather than
    predicting the stop again from its start. The pending stops of a round are one batch, on two
    threads where there are two cores (each future as its own prediction would be)."""
    out: List[Tuple[bool, str]] = [(False, "")] * len(starts)
    pending = list(range(len(starts)))
    froms = list(starts)
    sofar: Dict[int, Dict[str, np.ndarray]] = {}
    followed, length = 0.0, values["stop_horizon"]
    threads = min(2, api.cores(), max(len(starts), 1))
    while pending:
        batch = api.predict_many(crane, [froms[i] for i in pending], [stop] * len(pending),
                                 length, dt=dt, sample_every=sample_every,
                                 threads=min(threads, len(pending)))
        later = []
        for row, i in enumerate(pending):
            piece = batch[row]
            res, _ = _judge(crane, world, _samples(piece), shape, values)
            whole = None if res.contact else _followed(sofar.get(i), piece, followed)
            if whole is None:
                out[i] = (False, "")
            elif stop_settled(whole, values["stop_horizon"]):
                out[i] = (True, "")
            elif followed + length >= STOP_FOLLOW_MAX - 1e-9:
                out[i] = (False, f"a stop was still moving to new poses {STOP_FOLLOW_MAX:g} s "
                                 "after it took effect: that stop time counts as unsafe")
            else:
                try:
                    froms[i] = piece.final_state
                except ValueError as e:   # State refuses where the piece ended: unsafe
                    out[i] = (False, f"a stop could not be followed on ({e}): that stop time "
                                     "counts as unsafe")
                    continue
                sofar[i] = whole.__dict__
                later.append(i)
        followed += length
        pending, length = later, min(2 * followed, STOP_FOLLOW_MAX) - followed
    return out


def _followed(before: Optional[Dict[str, np.ndarray]], piece: Trajectory,
              start: float) -> SimpleNamespace:
    """A stop followed so far: the arrays stop_settled reads (t, tip, theta, slew, extension) of
    the pieces before (None for the first) and of this one, which starts at ``start`` s (its first
    sample is the last one before)."""
    n = len(piece.t)
    now = {"t": piece.t + start, "tip": piece.tip, "theta": piece.theta,
           "slew": np.broadcast_to(piece.slew, (n,)),
           "extension": np.broadcast_to(piece.extension, (n,))}
    if before is None:
        return SimpleNamespace(**now)
    return SimpleNamespace(**{k: np.concatenate([before[k], now[k][1:]]) for k in now})


def _latest_stop(crane: Crane, world: World, traj: Trajectory, inputs: Inputs, stop: Inputs,
                 shape: Shape, values: Dict[str, float], dt: float, sample_every: int,
                 t_contact: float, hint: Optional[float] = None) -> Tuple[float, Optional[str]]:
    """The latest judged sample time t_s at which stopping (taking effect at the first sample at or
    after t_s + reaction) keeps the clearance above the margin, by a search over the samples that
    takes stopping later never to be safer: the boundary between the safe samples and the unsafe
    ones. Each candidate predicts the stop from the state there (stop_state) until the crane is at
    rest and judges it; the command's own path is clear before its first contact. -inf if not even
    stopping at t = 0 is safe. A candidate whose stop cannot be predicted counts as unsafe; the
    second value says why, if that decided anything.
    The search probes two samples at a time (one batch of stops, on two cores): from t = 0, it
    splits the bracket in three each round; from a hint (a time), it probes the last sample at or
    before it and the next, then steps outwards (1, 2, 4, ... samples) until it has a safe sample
    below an unsafe one, and splits that bracket. Either way the boundary, when safety falls once
    with the stop time (the bisection's own assumption)."""
    reaction = values["reaction"]
    t = traj.t
    notes: list = []
    known: Dict[int, bool] = {}

    def safe(*ks: int) -> List[bool]:
        """Each candidate sample's verdict, the new ones predicted in one batch."""
        starts, rows = [], []
        for k in dict.fromkeys(ks):
            if k in known:
                continue
            m = int(np.searchsorted(t, t[k] + reaction - 1e-12))
            if m >= len(t) or t[m] >= t_contact:
                known[k] = False
                continue
            try:
                starts.append(stop_state(traj, m, inputs))
                rows.append((k, m))
            except ValueError as e:   # State refuses the state there: no verdict from it
                known[k] = False
                notes.append(f"the stop from t = {t[m]:.3f} s could not be predicted ({e})")
        if starts:
            try:
                verdicts = _stops_are_safe(crane, world, starts, stop, shape, values, dt,
                                           sample_every)
            except ValueError:        # the core refuses one of them: each on its own
                verdicts = []
                for start, (_, m) in zip(starts, rows):
                    try:
                        verdicts += _stops_are_safe(crane, world, [start], stop, shape, values,
                                                    dt, sample_every)
                    except ValueError as e:
                        verdicts.append((False, f"the stop from t = {t[m]:.3f} s could not be "
                                                f"predicted ({e})"))
            for (k, _), (ok, why) in zip(rows, verdicts):
                known[k] = ok
                if why:
                    notes.append(why)
        return [known[k] for k in ks]

    def answer(lo: int) -> Tuple[float, Optional[str]]:
        return (float(t[lo]) if lo >= 0 else -math.inf), (notes[-1] if notes else None)

    lo, hi = -1, int(np.searchsorted(t, t_contact - reaction, side="right"))  # safe(lo), not hi
    if hi <= 0:
        return answer(-1)
    k = 0 if hint is None else min(max(int(np.searchsorted(t, hint, side="right")) - 1, 0), hi - 1)
    if k > 0 and safe(k, min(k + 1, hi - 1))[0]:     # up from a safe hint: 1, 2, 4, ... later
        lo, step = k, 1
        while lo + step < hi and safe(lo + step)[0]:
            lo, step = lo + step, 2 * step
        hi = min(lo + step, hi)
    elif k > 0:                        # down from an unsafe hint, to a safe sample or to 0
        hi, step = k, 1
        while hi - step > 0 and not safe(hi - step)[0]:
            hi, step = hi - step, 2 * step
        lo = max(hi - step, 0)
        if lo == 0 and not safe(0)[0]:
            return answer(-1)
    elif not safe(0)[0]:
        return answer(-1)
    else:
        lo = 0
    while hi - lo > 1:                 # the bracket in three: two probes, one batch
        a = lo + max((hi - lo) // 3, 1)
        b = max(lo + 2 * (hi - lo) // 3, a + 1)
        probes = [a] if b >= hi else [a, b]
        for p, ok in zip(probes, safe(*probes)):
            if not ok:
                hi = p
                break
            lo = p
    return answer(lo)


STOP_MODEL = "valves to neutral"
STOP_NOTE = ("stop = every moving drive's valve to neutral (lift, tilt, slew, telescope; a "
             "pressure-driven one from its pressures, its spool fully open): the crane decelerates "
             "through the spool's lag, the oil's stiffness and the relief valves, followed until at "
             "rest; the latest time is that of the judged samples, found by a search that takes "
             "a later stop never to be safer")


def _with_stop(v: "Verdict", latest: float, values: Dict[str, float],
               why: Optional[str]) -> "Verdict":
    """The verdict with the stop analysis of valves to neutral (the signal follows from it)."""
    import dataclasses

    note = STOP_NOTE if why is None else f"{STOP_NOTE}; {why}"
    stop = StopAnalysis(latest=latest, reaction=values["reaction"], model=STOP_MODEL, note=note)
    signal = "STOP" if latest < values["cycle"] else "WARN"
    c = v.contact
    assert c is not None
    pair = f"{c.part} and {c.obstacle}"
    if c.at_start:
        return dataclasses.replace(v, stop=stop)
    if signal == "STOP":
        when = "no stop keeps the margin" if latest == -math.inf else f"by t = {latest:.3f} s: now"
        if why is not None and latest == -math.inf:
            when = f"now ({why})"
        reason = (f"contact of {pair} predicted at t = {c.t:.3f} s; with a {values['reaction']:g} s "
                  f"reaction and the valves to neutral stopping must begin {when}")
    else:
        reason = (f"contact of {pair} predicted at t = {c.t:.3f} s; with the valves to neutral "
                  f"stopping can wait until t = {latest:.3f} s")
    if c.closing:
        reason += f" (closing: {', '.join(c.closing)})"
    return dataclasses.replace(v, signal=signal, reason=reason, stop=stop)


def _verdict(res: Any, clearance: np.ndarray, shape: Shape, world: World, v: Dict[str, float],
             horizon: float, traj: Trajectory) -> Verdict:
    per_part = {p.name: float(c) for p, c in zip(shape.parts, clearance)}
    margin, reaction = v["margin"], v["reaction"]
    signal = SIGNALS[res.signal]
    contact = stop = None
    if res.contact:
        approach = {j: float(res.approach[i]) for i, j in enumerate(JOINTS)}
        contact = Contact(
            t=float(res.t), part=shape.parts[res.part].name,
            obstacle=world.obstacles[res.obstacle].name, clearance=float(res.clearance),
            on_part=np.array(list(res.on_part)), on_obstacle=np.array(list(res.on_obstacle)),
            theta=np.array(list(res.theta)), slew=float(res.slew), extension=float(res.extension),
            gradient={j: float(res.gradient[i]) for i, j in enumerate(JOINTS)},
            approach=approach, closing=tuple(j for j in JOINTS if approach[j] < 0),
            at_start=bool(res.at_start))
        stop = StopAnalysis(
            latest=float(res.stop_latest), reaction=reaction, model="hold",
            note="every drive is held: the crane does not move, so a contact is one at t = 0 "
                 "and no stop can remove it")
        pair = f"{contact.part} and {contact.obstacle}"
        if contact.at_start:
            state = "in contact" if contact.clearance <= 0 else \
                f"{contact.clearance:.3f} m apart, within the {margin:g} m margin"
            reason = f"already at t = 0: {pair} are {state}"
        elif signal == "STOP":
            reason = (f"contact of {pair} predicted at t = {contact.t:.3f} s; with a {reaction:g} s "
                      f"reaction stopping must begin by t = {stop.latest:.3f} s: now")
        else:
            reason = (f"contact of {pair} predicted at t = {contact.t:.3f} s; stopping can wait "
                      f"until t = {stop.latest:.3f} s")
        if contact.closing:
            reason += f" (closing: {', '.join(contact.closing)})"
    else:
        name = min(per_part, key=per_part.get) if per_part else "-"
        reason = (f"no contact within the {horizon:g} s horizon; smallest clearance "
                  f"{per_part.get(name, math.inf):.3f} m ({name})")
    return Verdict(signal=signal, reason=reason, clearance=per_part, contact=contact, stop=stop,
                   margin=margin, horizon=horizon, world=world, trajectory=traj,
                   evaluations=int(res.evaluations))

