"""What a prediction takes (State, drives, Inputs) and what it gives back (Trajectory).

SI units: strokes in m, stroke rates in m/s, angles in rad, pressures in Pa (gauge), times in s.
Four-column arrays are [lift, tilt, slew, extension] (the joints' order, JOINTS); two-column arrays
are [lift, tilt].
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np

__all__ = ["State", "Pressure", "PressureSeries", "Hold", "Valve", "ValveSeries", "Drive", "Inputs",
           "Trajectory", "TrajectoryBatch", "POINT_NAMES", "PRESSURE_MAX", "STROKE_RATE_MAX", "ARRAYS",
           "CHAMBER_PRESSURE_MIN", "JOINTS", "SLEW_RATE_MAX"]

from ._checks import PRESSURE_MAX
from ._checks import number as _number

#: Pa (gauge): the lowest chamber pressure a state may hold (-1 bar: vacuum).
CHAMBER_PRESSURE_MIN = -1e5

#: Names of the points in ``Trajectory.points`` (the C core's and the twin's order).
POINT_NAMES = ("pillar_base", "lift_pivot", "lift_cylinder_base", "lift_cylinder_rod",
               "tilt_cylinder_base", "link1_pivot", "link_pin", "link2_attach", "tilt_pivot",
               "extension_mount", "tip")


#: The joints, in the order of every four-column array (C: CRANE_LIFT .. CRANE_EXTENSION).
JOINTS = ("lift", "tilt", "slew", "extension")

#: The arrays of a Trajectory (and a TrajectoryBatch), in their order; the twin returns these keys.
ARRAYS = ("t", "strokes", "theta", "omega", "slew", "extension", "slew_rate", "extension_rate",
          "tip", "stop", "p_a", "p_b", "flow_a", "flow_b", "spool")

#: m/s: the largest initial stroke rate accepted (either sign), of the boom cylinders and the
#: telescope. Hydraulic cylinders move below about 1 m/s; far above this the end-stop events of the
#: C core and the twin stop agreeing (they differ by metres at 1e10 m/s) and at about 1e100 m/s
#: the state overflows.
STROKE_RATE_MAX = 10.0

#: rad/s: the largest initial slew rate accepted (either sign); a loader crane slews below about
#: 0.5 rad/s. The same stroke-rate bound at the rack of a 1 m pinion.
SLEW_RATE_MAX = 10.0


def _pressure(value: object, name: str) -> float:
    p = _number(value, name)
    if not 0.0 <= p <= PRESSURE_MAX:
        raise ValueError(f"{name} must be in [0, {PRESSURE_MAX:g}] Pa, got {p!r}")
    return p


#: Pa (1 bar): boom-cylinder pressures that all lie in (0, this) where holding the booms takes
#: tens of bar are warned about: most likely written in bar, not Pa.
PLAUSIBLE_PRESSURE_MIN = 1e5


def looks_like_bar(peak: float) -> bool:
    """Whether pressures whose largest is ``peak`` (Pa) look written in bar: above 0 but below
    PLAUSIBLE_PRESSURE_MIN (175 for 175 bar)."""
    return 0.0 < peak < PLAUSIBLE_PRESSURE_MIN


def bar_for_pa(owner: str, peaks: Dict[str, float]) -> Optional[str]:
    """The warning text when the largest of ``peaks`` (Pa) looks written in bar
    (:func:`looks_like_bar`), naming the fields; else None."""
    if not looks_like_bar(max(peaks.values())):
        return None
    fields = ", ".join(f"{owner}.{k} = {v:g} Pa" for k, v in peaks.items() if v > 0.0)
    return (f"{fields}: below 1 bar, where the boom cylinders need tens of bar; pressures are in "
            "Pa (175 bar = 175e5 Pa)")


def _warn_if_bar(owner: str, peaks: Dict[str, float]) -> None:
    """warnings.warn(bar_for_pa(...)) if it applies; stacklevel points at the caller's constructor."""
    text = bar_for_pa(owner, peaks)
    if text is not None:
        warnings.warn(text, UserWarning, stacklevel=4)


@dataclass(frozen=True)
class State:
    """The crane at the start of a prediction: its four joints and their rates.

    Strokes (m) set the boom angles; slew (rad, about the vertical axis) and extension (m) are the
    other two joints. The crane starts at rest unless rates are given: stroke rates (m/s), the slew
    rate (rad/s) and the extension rate (m/s). A held joint (:class:`Hold`) must start at rest.

    A valve-driven actuator (:class:`Valve`, :class:`ValveSeries`) also needs its chamber
    pressures (Pa gauge, p_a bore side, p_b rod side; for the slew drive, chamber a turns towards
    +slew; measured, or from :func:`cranepredict.state_at_rest`) and, with a spool lag, its spool
    position in [-1, 1] (default 0: closed). Other drives ignore them.
    """

    lift_stroke: float
    tilt_stroke: float
    slew: float = 0.0
    extension: float = 0.0
    lift_stroke_rate: float = 0.0
    tilt_stroke_rate: float = 0.0
    lift_p_a: Optional[float] = None
    lift_p_b: Optional[float] = None
    tilt_p_a: Optional[float] = None
    tilt_p_b: Optional[float] = None
    lift_spool: float = 0.0
    tilt_spool: float = 0.0
    slew_rate: float = 0.0
    extension_rate: float = 0.0
    slew_p_a: Optional[float] = None
    slew_p_b: Optional[float] = None
    extension_p_a: Optional[float] = None
    extension_p_b: Optional[float] = None
    slew_spool: float = 0.0
    extension_spool: float = 0.0

    def __post_init__(self) -> None:
        for name in ("lift_stroke", "tilt_stroke", "slew", "extension",
                     "lift_stroke_rate", "tilt_stroke_rate", "slew_rate", "extension_rate",
                     "lift_spool", "tilt_spool", "slew_spool", "extension_spool"):
            object.__setattr__(self, name, _number(getattr(self, name), f"State.{name}"))
        for name, limit, unit, const in (
                ("lift_stroke_rate", STROKE_RATE_MAX, "m/s", "STROKE_RATE_MAX"),
                ("tilt_stroke_rate", STROKE_RATE_MAX, "m/s", "STROKE_RATE_MAX"),
                ("extension_rate", STROKE_RATE_MAX, "m/s", "STROKE_RATE_MAX"),
                ("slew_rate", SLEW_RATE_MAX, "rad/s", "SLEW_RATE_MAX")):
            v = getattr(self, name)
            if not -limit <= v <= limit:
                raise ValueError(f"State.{name} must be in [-{limit:g}, {limit:g}] "
                                 f"{unit} (cranepredict.{const}), got {v!r}")

        for name in ("lift_p_a", "lift_p_b", "tilt_p_a", "tilt_p_b", "slew_p_a", "slew_p_b",
                     "extension_p_a", "extension_p_b"):
            v = getattr(self, name)
            if v is None:
                continue
            p = _number(v, f"State.{name}")
            if not CHAMBER_PRESSURE_MIN <= p <= PRESSURE_MAX:
                raise ValueError(f"State.{name} must be in [{CHAMBER_PRESSURE_MIN:g}, "
                                 f"{PRESSURE_MAX:g}] Pa, got {p!r}")
            object.__setattr__(self, name, p)
        # the boom cylinders carry the booms' weight: tens of bar at any pose off the stops (the
        # slew drive and the telescope may hold with less)
        given = {name: getattr(self, name) for name in ("lift_p_a", "lift_p_b", "tilt_p_a", "tilt_p_b")
                 if getattr(self, name) is not None}
        if given:
            _warn_if_bar("State", {k: abs(v) for k, v in given.items()})
        for name in ("lift_spool", "tilt_spool", "slew_spool", "extension_spool"):
            if not -1.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"State.{name} must be in [-1, 1], got {getattr(self, name)}")

    def pressures(self, joint: str) -> Tuple[Optional[float], Optional[float]]:
        """(p_a, p_b) of the "lift", "tilt", "slew" or "extension" actuator (None where not given)."""
        if joint not in JOINTS:
            raise ValueError(f"joint must be one of {JOINTS}, got {joint!r}")
        return getattr(self, f"{joint}_p_a"), getattr(self, f"{joint}_p_b")


@dataclass(frozen=True)
class Pressure:
    """Constant chamber pressures (Pa): p_a on the bore side, p_b on the rod side."""

    p_a: float
    p_b: float = 0.0
    held = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "p_a", _pressure(self.p_a, "Pressure.p_a"))
        object.__setattr__(self, "p_b", _pressure(self.p_b, "Pressure.p_b"))

    @property
    def t(self) -> None:
        return None


def _signal(value: Any, name: str) -> np.ndarray:
    """A read-only float copy of a sampled signal: 1-D, at least 2 samples, finite; a huge int,
    a non-number or a bad shape names the field."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise TypeError(f"{name} must be a sequence of numbers, got {type(value).__name__}")
    if not (isinstance(value, np.ndarray) and value.dtype.kind in "iuf"):
        for i, v in enumerate(value):
            if isinstance(v, (bool, np.bool_)) or \
                    not isinstance(v, (int, float, np.floating, np.integer)):
                raise TypeError(f"{name}[{i}] must be a number, got {type(v).__name__}")
    try:
        a = np.array(value, dtype=float, copy=True)
    except OverflowError:
        raise ValueError(f"{name} must be finite: it holds an int too large for a float") from None
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a sequence of numbers") from None
    if a.ndim != 1 or a.size < 2:
        raise ValueError(f"{name} must be 1-D with at least 2 samples, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite")
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class PressureSeries:
    """Chamber pressures sampled at times t (s, strictly increasing, covering [0, horizon]),
    interpolated linearly. The arrays are copied; the caller's are never modified."""

    t: np.ndarray
    p_a: np.ndarray
    p_b: np.ndarray
    held = False

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("t", "p_a", "p_b"):
            arrays[name] = _signal(getattr(self, name), f"PressureSeries.{name}")
        if not (arrays["t"].size == arrays["p_a"].size == arrays["p_b"].size):
            raise ValueError("PressureSeries.t, p_a and p_b must have the same length, got "
                             f"{arrays['t'].size}, {arrays['p_a'].size}, {arrays['p_b'].size}")
        if np.any(np.diff(arrays["t"]) <= 0):
            raise ValueError("PressureSeries.t must be strictly increasing")
        for name in ("p_a", "p_b"):
            a = arrays[name]
            if a.min() < 0.0 or a.max() > PRESSURE_MAX:
                raise ValueError(f"PressureSeries.{name} must be in [0, {PRESSURE_MAX:g}] Pa, "
                                 f"got [{float(a.min())!r}, {float(a.max())!r}]")
        for name, a in arrays.items():
            object.__setattr__(self, name, a)
        # the arrays are read-only: their peaks, asked on every call's checks, once
        object.__setattr__(self, "_peaks", (float(arrays["p_a"].max()), float(arrays["p_b"].max())))

    @property
    def peak_pressures(self) -> Tuple[float, float]:
        """(largest p_a, largest p_b), Pa."""
        return self._peaks

    @classmethod
    def ramp(cls, t0: float, t1: float, start: Tuple[float, float], end: Tuple[float, float],
             horizon: float) -> "PressureSeries":
        """(p_a, p_b) held at ``start`` until t0, linear to ``end`` at t1, then held to horizon."""
        t0, t1, horizon = (_number(v, n) for v, n in ((t0, "t0"), (t1, "t1"), (horizon, "horizon")))
        if not 0.0 <= t0 < t1 <= horizon:
            raise ValueError(f"ramp times must satisfy 0 <= t0 < t1 <= horizon, got {t0}, {t1}, {horizon}")
        ts = [0.0, t0, t1, horizon] if t0 > 0 else [0.0, t1, horizon]
        if ts[-1] == ts[-2]:
            ts = ts[:-1]
        pts = [start if t <= t0 else end for t in ts]
        return cls(t=ts, p_a=[p[0] for p in pts], p_b=[p[1] for p in pts])

    def covers(self, horizon: float) -> bool:
        return bool(self.t[0] <= 0.0 and self.t[-1] >= horizon)


@dataclass(frozen=True)
class Hold:
    """The cylinder's valve is closed: its stroke stays at the initial value (the paper's tilt)."""

    held = True


def _percent_hint(worst: float) -> str:
    """A hint for a lever given in percent (|u| up to 100) instead of a fraction of full opening."""
    return " (in percent? the lever is a fraction: give u / 100)" if 1.0 < worst <= 100.0 else ""


def _lever(value: object, name: str) -> float:
    u = _number(value, name)
    if not -1.0 <= u <= 1.0:
        raise ValueError(f"{name} must be in [-1, 1] (the lever; > 0 extends), got {u!r}"
                         + _percent_hint(abs(u)))
    return u


@dataclass(frozen=True)
class Valve:
    """The operator's lever held at u in [-1, 1] (u > 0 extends the cylinder, 0 closes the valve).

    The cylinder needs a ``hydraulics`` table in the crane file; the chamber pressures follow from
    the oil flows and the motion (docs/model.md, "Hydraulics")."""

    u: float
    held = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "u", _lever(self.u, "Valve.u"))

    @property
    def t(self) -> None:
        return None


@dataclass(frozen=True)
class ValveSeries:
    """A sampled lever signal: u (in [-1, 1]) at times t (s, strictly increasing, covering
    [0, horizon]), interpolated linearly. The arrays are copied; the caller's are never modified."""

    t: np.ndarray
    u: np.ndarray
    held = False

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("t", "u"):
            arrays[name] = _signal(getattr(self, name), f"ValveSeries.{name}")
        if arrays["t"].size != arrays["u"].size:
            raise ValueError("ValveSeries.t and u must have the same length, got "
                             f"{arrays['t'].size} and {arrays['u'].size}")
        if np.any(np.diff(arrays["t"]) <= 0):
            raise ValueError("ValveSeries.t must be strictly increasing")
        u = arrays["u"]
        if u.min() < -1.0 or u.max() > 1.0:
            raise ValueError(f"ValveSeries.u must be in [-1, 1] (the lever), "
                             f"got [{float(u.min())!r}, {float(u.max())!r}]"
                             + _percent_hint(float(abs(u).max())))
        for name, a in arrays.items():
            object.__setattr__(self, name, a)

    def covers(self, horizon: float) -> bool:
        return bool(self.t[0] <= 0.0 and self.t[-1] >= horizon)


Drive = Union[Pressure, PressureSeries, Hold, Valve, ValveSeries]


@dataclass(frozen=True)
class Inputs:
    """How each joint's actuator is driven during the prediction: the lift and tilt cylinders,
    the slew drive and the extension cylinder. A drive left out is held (:class:`Hold`): its
    joint keeps the value of the initial state, as a closed valve without give would."""

    lift: Drive = field(default_factory=lambda: Hold())
    tilt: Drive = field(default_factory=lambda: Hold())
    slew: Drive = field(default_factory=lambda: Hold())
    extension: Drive = field(default_factory=lambda: Hold())

    def __post_init__(self) -> None:
        for name in JOINTS:
            d = getattr(self, name)
            if not isinstance(d, (Pressure, PressureSeries, Hold, Valve, ValveSeries)):
                raise TypeError(f"Inputs.{name} must be Pressure, PressureSeries, Hold, Valve or "
                                f"ValveSeries, got {type(d).__name__}")


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A predicted motion, one row per sample (t = 0 first).

    t (N,) s; strokes (N, 2) m [lift, tilt]; theta (N, 2) rad (lift angle, tilt angle relative to
    the lift boom); omega (N, 2) rad/s; slew (N,) rad and slew_rate (N,) rad/s; extension (N,) m
    and extension_rate (N,) m/s; tip (N, 3) m in the world frame (X, Y horizontal, Z up) at each
    sample's pose. Four columns [lift, tilt, slew, extension]: stop (N, 4): -1 at the actuator's
    stroke_min (cylinder fully retracted; slew_min; extension_min), +1 at stroke_max (fully
    extended; slew_max; extension_max), 0 otherwise; p_a, p_b (N, 4) Pa: the chamber pressures of
    a valve-driven actuator, the given pressures of a pressure-driven one, 0 for a held one;
    flow_a, flow_b (N, 4) m^3/s: the valve's flow into chamber a and out of chamber b (0 unless
    valve-driven); spool (N, 4): the spool position (0 unless valve-driven).
    ``points()`` gives the world positions of every pivot and pin, to draw the crane;
    ``state(i)`` (and ``final_state``) the :class:`State` at sample i, to continue from.
    ``supply_short``: the valve-driven boom cylinders ("lift", "tilt") levered against their load
    whose load at the initial pose needs more than their supply pressure to hold: levered
    against it, the boom sinks (:func:`cranepredict.holding_pressure`); empty otherwise.
    Every array is read-only; those of a C-core prediction are views of the core's samples,
    each made on its first read.
    """

    t: np.ndarray
    strokes: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    slew: np.ndarray
    extension: np.ndarray
    slew_rate: np.ndarray
    extension_rate: np.ndarray
    tip: np.ndarray
    stop: np.ndarray
    backend: str
    _points: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] = field(repr=False)
    p_a: Optional[np.ndarray] = None
    p_b: Optional[np.ndarray] = None
    flow_a: Optional[np.ndarray] = None
    flow_b: Optional[np.ndarray] = None
    spool: Optional[np.ndarray] = None
    supply_short: Tuple[str, ...] = ()
    #: (joint, stroke, extension) -> ds/dtheta of a boom cylinder, by the backend that predicted
    _transmission: Optional[Callable[[int, float, float], float]] = field(default=None, repr=False)

    @classmethod
    def _of_fields(cls, fields: Callable[[str], np.ndarray], backend: str,
                   points: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray],
                   transmission: Optional[Callable[[int, float, float], float]],
                   supply_short: Tuple[str, ...] = ()) -> "Trajectory":
        """A Trajectory whose arrays (ARRAYS) are made on their first read, by ``fields(name)``
        (read-only views of the backend's samples), then kept: an array never read costs
        nothing. Reads as one built by the constructor with every array given."""
        self = object.__new__(cls)
        d = self.__dict__   # frozen: the fields are set here, once, as the constructor would
        d["backend"], d["_points"], d["_transmission"] = backend, points, transmission
        d["supply_short"], d["_fields"] = supply_short, fields
        return self

    def __getattr__(self, name: str) -> Any:
        # Called only for an attribute not yet in the instance: an array of a Trajectory made
        # by _of_fields, on its first read.
        fields = self.__dict__.get("_fields")
        if fields is None or name not in _ARRAY_SET:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        a = self.__dict__[name] = fields(name)
        return a

    def state(self, i: int) -> State:
        """The :class:`State` at sample ``i`` (negative counts from the end): the one the
        prediction would continue from. Strokes, stroke rates (omega times ds/dtheta at the
        sample's pose), slew, extension and their rates, every actuator's chamber pressures and
        spool. Predicting on from it under the same drives continues this trajectory (to the
        rounding of the angle <-> stroke conversion; docs/model.md). Raises ValueError naming the
        field if the sample is not a valid State (a chamber below vacuum, CHAMBER_PRESSURE_MIN)."""
        n = len(self.t)
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)):
            raise TypeError(f"Trajectory.state(i): i must be an int, got {type(i).__name__}")
        if not -n <= i < n:
            raise IndexError(f"Trajectory.state(i): i must be in [-{n}, {n - 1}], got {i}")
        if self._transmission is None:
            raise ValueError("Trajectory.state(i) needs a trajectory from cranepredict.predict "
                             "or predict_many")
        k = int(i) % n
        ext = float(np.broadcast_to(self.extension, self.t.shape)[k])
        fields: Dict[str, Any] = {
            "lift_stroke": float(self.strokes[k, 0]), "tilt_stroke": float(self.strokes[k, 1]),
            "slew": float(np.broadcast_to(self.slew, self.t.shape)[k]), "extension": ext,
            "slew_rate": float(np.broadcast_to(self.slew_rate, self.t.shape)[k]),
            "extension_rate": float(np.broadcast_to(self.extension_rate, self.t.shape)[k])}
        for j, name in enumerate(JOINTS[:2]):
            w = float(self.omega[k, j])
            fields[f"{name}_stroke_rate"] = 0.0 if w == 0.0 else \
                w * self._transmission(j, float(self.strokes[k, j]), ext)
        for j, name in enumerate(JOINTS):
            for side in ("p_a", "p_b", "spool"):
                a = getattr(self, side)
                if a is not None:
                    fields[f"{name}_{side}"] = float(a[k, j])
        try:
            return State(**fields)
        except ValueError as e:
            raise ValueError(f"Trajectory.state({i}) at t = {float(self.t[k]):g} s: {e}") from None

    @property
    def final_state(self) -> State:
        """The :class:`State` at the last sample (``state(-1)``)."""
        return self.state(-1)

    def points(self) -> Dict[str, np.ndarray]:
        """World positions (N, 3) of each point in POINT_NAMES at each sample's theta, slew and
        extension, computed on demand."""
        xyz = self._points(self.theta, self.slew, self.extension)
        return {name: xyz[:, i, :] for i, name in enumerate(POINT_NAMES)}

    def first_stop_time(self, joint: int, side: int = +1) -> Optional[float]:
        """Time (s) of the first sample with the joint (0 lift, 1 tilt, 2 slew, 3 extension) at
        that stop (+1 stroke_max, -1 stroke_min), or None."""
        hits = np.flatnonzero(self.stop[:, joint] == side)
        return float(self.t[hits[0]]) if hits.size else None


# The arrays with a default (None) would be found on the class before Trajectory.__getattr__
# made them: the class keeps none (the constructor's defaults are its own).
for _name in ARRAYS:
    if _name in Trajectory.__dict__:
        delattr(Trajectory, _name)
del _name
_ARRAY_SET = frozenset(ARRAYS)


@dataclass(frozen=True, eq=False)
class TrajectoryBatch:
    """Many predicted futures of one crane (``predict_many``), stacked: future k is row k.

    t (N,) s, shared by all futures; strokes, theta, omega (F, N, 2); slew, extension, slew_rate,
    extension_rate (F, N); tip (F, N, 3); stop, p_a, p_b, flow_a, flow_b, spool (F, N, 4).
    Units and conventions as in :class:`Trajectory`. ``batch[k]`` is future k as a Trajectory
    (views, no copy); ``len(batch)`` is F. With ``sample_every = m`` the samples are t = 0, every
    m-th step and the last step.
    """

    t: np.ndarray
    strokes: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    slew: np.ndarray
    extension: np.ndarray
    slew_rate: np.ndarray
    extension_rate: np.ndarray
    tip: np.ndarray
    stop: np.ndarray
    backend: str
    sample_every: int
    _points: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] = field(repr=False)
    p_a: Optional[np.ndarray] = None      #: (F, N, 4) Pa, as Trajectory.p_a
    p_b: Optional[np.ndarray] = None
    flow_a: Optional[np.ndarray] = None
    flow_b: Optional[np.ndarray] = None
    spool: Optional[np.ndarray] = None
    _transmission: Optional[Callable[[int, float, float], float]] = field(default=None, repr=False)

    def __len__(self) -> int:
        return int(self.tip.shape[0])

    def __getitem__(self, k: int) -> Trajectory:
        n = len(self)
        if not isinstance(k, (int, np.integer)) or isinstance(k, bool):
            raise TypeError(f"a TrajectoryBatch is indexed by an int, got {type(k).__name__}")
        if not -n <= k < n:
            raise IndexError(f"future index {k} out of range for {n} futures")
        k = int(k) % n
        arrays = {name: getattr(self, name) if name == "t" or getattr(self, name) is None
                  else getattr(self, name)[k] for name in ARRAYS}
        return Trajectory(**arrays, backend=self.backend, _points=self._points,
                          _transmission=self._transmission)
