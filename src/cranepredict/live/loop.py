"""The live twin's loop: one :class:`Measurement` in, one :class:`LiveVerdict` out per control cycle.

:meth:`LiveTwin.cycle` checks the data (fail-safe first), estimates the state, predicts the future
under the operator's levers and judges it with the collision guard (:func:`cranepredict.guard`).
Anything that makes the estimate untrustworthy gives FAULT (treated as STOP) instead of a
prediction: a configured sensor without a sample for longer than its ``max_age``, a value outside
what the crane can be at, a sensor error flag or lost lever commands reported by the bus, an
estimator whose innovation test fails. After a FAULT the estimator starts again from the next
complete measurement: no GO comes from data older than the sensors' max age.
The verdict is advisory (docs/live.md).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Dict, Optional, Sequence

from ..crane import Crane
from ..guard import DEFAULT_REACTION, Verdict, guard
from ..types import JOINTS, State, Trajectory
from ..world import World
from .estimator import EKF, Estimator, InnovationFault
from .measurement import POSITIONS, PRESSURES, Measurement, Sensors, default_sensors

__all__ = ["LiveTwin", "LiveVerdict", "LIVE_SIGNALS", "FAULT_KINDS", "SLOWDOWN_WINDOW"]

LIVE_SIGNALS = ("GO", "WARN", "STOP", "FAULT")
#: What a FAULT can be (the DBC's fault codes, by name).
FAULT_KINDS = ("stale", "out of range", "sensor error", "innovation", "levers stale", "internal",
               "settling")
#: s: on WARN the suggested lever scale falls linearly from 1 to 0 as the latest stop time falls
#: from this to 0.
SLOWDOWN_WINDOW = 1.0


@dataclass(frozen=True, eq=False)
class LiveVerdict:
    """One cycle's answer. ``signal`` GO / WARN / STOP from the guard, or FAULT (treat as STOP)
    with ``fault`` (one of FAULT_KINDS) and ``reason``. ``state`` is the estimate (None on a
    FAULT before one exists); ``guard`` the collision guard's :class:`~cranepredict.Verdict`
    (None on FAULT), with the predicted trajectory. ``time_to_contact`` and ``latest_stop`` (s,
    from ``t``), ``part`` and ``obstacle`` of the first contact, or None; ``speed_limit`` in
    [0, 1]: the suggested scale of the levers."""

    t: float
    signal: str
    reason: str
    fault: Optional[str] = None
    state: Optional[State] = None
    guard: Optional[Verdict] = None
    speed_limit: float = 0.0
    wall: float = 0.0

    @property
    def time_to_contact(self) -> Optional[float]:
        c = None if self.guard is None else self.guard.contact
        return None if c is None else c.t

    @property
    def latest_stop(self) -> Optional[float]:
        s = None if self.guard is None else self.guard.stop
        return None if s is None else s.latest

    @property
    def part(self) -> Optional[str]:
        c = None if self.guard is None else self.guard.contact
        return None if c is None else c.part

    @property
    def obstacle(self) -> Optional[str]:
        c = None if self.guard is None else self.guard.contact
        return None if c is None else c.obstacle

    @property
    def trajectory(self) -> Optional[Trajectory]:
        return None if self.guard is None else self.guard.trajectory

    @property
    def stops(self) -> bool:
        """True if the crane must not follow the levers (STOP or FAULT)."""
        return self.signal in ("STOP", "FAULT")

    def to_dict(self) -> dict:
        latest = self.latest_stop
        return {"t_s": self.t, "signal": self.signal, "reason": self.reason, "fault": self.fault,
                "time_to_contact_s": self.time_to_contact,
                "latest_stop_s": latest if latest is None or math.isfinite(latest) else None,
                "part": self.part, "obstacle": self.obstacle, "speed_limit": self.speed_limit}


class LiveTwin:
    """The crane's twin in the loop: ``cycle(measurement) -> LiveVerdict`` every control period.

    ``estimator`` (default: an :class:`~cranepredict.live.estimator.EKF` over ``crane`` with
    ``sensors``); ``horizon`` (s) of the prediction; ``reaction`` (s) from the stop decision to the
    stop; ``cycle_time`` (s) the control period (the guard's "cannot wait one more cycle");
    ``range_tolerance`` (in sensor standard deviations) beyond a joint's range before a position
    is out of range; pressures are out of range below vacuum or above ``pressure_limit`` times the
    highest relief or supply pressure of the crane file. After the estimator (re)starts, the
    first ``settle`` cycles give FAULT ("settling"): its first estimate knows no rates.
    """

    def __init__(self, crane: Crane, world: World, *, estimator: Optional[Estimator] = None,
                 sensors: Optional[Sensors] = None, horizon: float = 2.0,
                 reaction: float = DEFAULT_REACTION, cycle_time: float = 0.01,
                 dt: Optional[float] = None, range_tolerance: float = 6.0,
                 pressure_limit: float = 1.25, settle: int = 10) -> None:
        if not isinstance(crane, Crane):
            raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
        if not isinstance(world, World):
            raise TypeError(f"world must be a cranepredict.World, got {type(world).__name__}")
        for name, v in (("horizon", horizon), ("reaction", reaction), ("cycle_time", cycle_time),
                        ("range_tolerance", range_tolerance), ("pressure_limit", pressure_limit)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0 \
                    or (v == 0 and name != "reaction"):
                raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
        self.crane, self.world = crane, world
        self.sensors = sensors if sensors is not None else (
            getattr(estimator, "sensors", None) or default_sensors())
        self.estimator = estimator if estimator is not None else EKF(crane, self.sensors, dt=dt)
        self.horizon, self.reaction, self.cycle_time, self.dt = horizon, reaction, cycle_time, dt
        self._limits = self._ranges(range_tolerance, pressure_limit)
        self.last_seen: Dict[str, float] = {}
        self.last_t: Optional[float] = None
        self.faulted = True          # until the estimator has a complete first measurement
        self.settle = int(settle)
        self.settling = 0
        self.counts: Dict[str, int] = {s: 0 for s in LIVE_SIGNALS}
        # the last verdict's latest stop as a time of the crane (s), where the next cycle's guard
        # begins its search (guard's stop_hint); None: no stop analysis, or no stop was safe
        self._stop_at: Optional[float] = None

    def _ranges(self, tol: float, limit: float) -> Dict[str, tuple]:
        c, g, sd = self.crane, self.crane.geometry, self.crane.slew_drive
        def std(f: str) -> float:
            return self.sensors[f].std if f in self.sensors else 0.0
        r = {"lift_stroke": (c.lift_cylinder.stroke_min, c.lift_cylinder.stroke_max),
             "tilt_stroke": (c.tilt_cylinder.stroke_min, c.tilt_cylinder.stroke_max),
             "slew": (sd.slew_min, sd.slew_max) if sd is not None else (-math.pi, math.pi),
             "extension": (g.extension_min, g.extension_max)}
        out = {f: (lo - tol * std(f), hi + tol * std(f)) for f, (lo, hi) in r.items()}
        highest = max(max(h.supply_pressure, h.relief_pressure) for h in
                      (getattr(a, "hydraulics", None) for a in (c.lift_cylinder, c.tilt_cylinder,
                                                                c.slew_drive, c.extension_cylinder))
                      if h is not None)
        for p in PRESSURES:
            out[p] = (-1e5 - tol * std(p), limit * highest)
        return out

    def fault(self, t: float, kind: str, reason: str, state: Optional[State] = None,
              wall: float = 0.0) -> LiveVerdict:
        """A FAULT verdict (and the estimator starts again)."""
        self.faulted = True
        self.estimator.reset()
        self.counts["FAULT"] += 1
        return LiveVerdict(t=t, signal="FAULT", reason=reason, fault=kind, state=state, wall=wall)

    def no_levers(self, t: float, reason: str) -> LiveVerdict:
        """A FAULT ("levers stale") while no lever frame arrives, between cycles. The estimator
        is kept: when measurements resume, their own times decide whether the data is stale."""
        self.counts["FAULT"] += 1
        return LiveVerdict(t=t, signal="FAULT", reason=reason, fault="levers stale")

    def cycle(self, measurement: Measurement, faults: Sequence[str] = ()) -> LiveVerdict:
        """One control cycle. ``faults``: what the bus found wrong since the last cycle (a sensor
        error flag, lost or frozen lever frames; MeasurementAssembler's list)."""
        t0 = time.perf_counter()
        if not isinstance(measurement, Measurement):
            raise TypeError(f"measurement must be a cranepredict.Measurement, "
                            f"got {type(measurement).__name__}")
        t = measurement.t
        if self.last_t is not None and not t > self.last_t:
            return self.fault(t, "internal", f"measurement time {t} s is not after {self.last_t} s")
        self.last_t = t
        values = measurement.values()
        for f, v in values.items():
            lo, hi = self._limits.get(f, (-math.inf, math.inf))
            if not lo <= v <= hi:
                return self.fault(t, "out of range", f"{f} = {v:g} outside [{lo:g}, {hi:g}]")
        for f in values:
            self.last_seen[f] = t
        for text in faults:
            kind = "sensor error" if text.startswith("sensor error") else (
                "levers stale" if text.startswith("levers") else
                "out of range" if text.startswith("out of range") else "stale")
            return self.fault(t, kind, text)
        stale = [s.field for s in self.sensors.sensors
                 if t - self.last_seen.get(s.field, -math.inf) > s.max_age + 1e-9]
        if stale:
            self.faulted = True
            self.estimator.reset()
            self.counts["FAULT"] += 1
            ages = ", ".join(f"{f} ({'never' if f not in self.last_seen else f'{t - self.last_seen[f]:.3f} s'})"
                             for f in stale[:4])
            return LiveVerdict(t=t, signal="FAULT", reason=f"stale or missing sensor data: {ages}",
                               fault="stale")
        try:
            if self.faulted:
                self.estimator.reset()
                if any(p not in values for p in POSITIONS):   # wait for a complete measurement
                    return self.fault(t, "stale", "waiting for every joint's position to start")
            if self.faulted:
                self.settling = self.settle
            state = self.estimator.update(measurement)
        except InnovationFault as e:
            return self.fault(t, "innovation", str(e))
        except (ValueError, TypeError, ArithmeticError) as e:
            return self.fault(t, "internal", f"estimator: {e}")
        self.faulted = False
        if self.settling > 0:
            self.settling -= 1
            self.counts["FAULT"] += 1
            return LiveVerdict(t=t, signal="FAULT", reason="estimator settling after a (re)start",
                               fault="settling", state=state, wall=time.perf_counter() - t0)
        try:
            hint = None if self._stop_at is None else self._stop_at - t
            self._stop_at = None
            v = guard(self.crane, self.world, state, measurement.predicted_inputs, self.horizon,
                      dt=self.dt, reaction=self.reaction, cycle=self.cycle_time, stop_hint=hint)
        except (ValueError, TypeError) as e:
            return self.fault(t, "internal", f"guard: {e}", state=state)
        if v.stop is not None and math.isfinite(v.stop.latest):
            self._stop_at = t + v.stop.latest
        speed = 1.0
        if v.signal == "STOP":
            speed = 0.0
        elif v.signal == "WARN" and v.stop is not None:
            speed = min(1.0, max(0.0, v.stop.latest / SLOWDOWN_WINDOW))
        self.counts[v.signal] += 1
        return LiveVerdict(t=t, signal=v.signal, reason=v.reason, state=state, guard=v,
                           speed_limit=speed, wall=time.perf_counter() - t0)
