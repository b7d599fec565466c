"""The PATU 655's frames on the bus: the DBC shipped with the package (``patu655.dbc``), encoding and
decoding with J1939's not-available and error codes, rolling counters and timeouts.

Needs the ``live`` extra (cantools; python-can for the transport). The DBC is the one source of
every frame's identifier, signal layout and resolution; this module reads it and adds what a DBC
cannot say: which signal is "not available" or "sensor error", the counters' rules, the timeouts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from importlib import resources
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from ..types import JOINTS, Inputs
from .measurement import Measurement, levers

__all__ = ["database", "Codec", "SensorFrames", "MeasurementAssembler", "VerdictFrame",
           "VerdictMonitor", "SENSOR_FRAMES", "LEVER_FRAME", "VERDICT_FRAME", "ERROR", "FAULTS",
           "SIGNAL_CODES", "CYCLE"]

#: The sensor frames and the State fields each carries (position first, then p_a, p_b).
SENSOR_FRAMES: Dict[str, Tuple[str, str, str]] = {
    "LiftCylinder": ("lift_stroke", "lift_p_a", "lift_p_b"),
    "TiltCylinder": ("tilt_stroke", "tilt_p_a", "tilt_p_b"),
    "SlewDrive": ("slew", "slew_p_a", "slew_p_b"),
    "ExtensionCylinder": ("extension", "extension_p_a", "extension_p_b"),
}
LEVER_FRAME = "Levers"
VERDICT_FRAME = "Verdict"
#: The counter signal of each frame.
COUNTERS = {"LiftCylinder": "lift_counter", "TiltCylinder": "tilt_counter",
            "SlewDrive": "slew_counter", "ExtensionCylinder": "extension_counter",
            "Levers": "levers_counter", "Verdict": "verdict_counter"}
#: The verdict's signal codes (the DBC's value table).
SIGNAL_CODES = {"GO": 0, "WARN": 1, "STOP": 2, "FAULT": 3}
#: The verdict's fault codes (the DBC's value table), by the live twin's fault kinds.
FAULTS = {"none": 0, "stale": 1, "out of range": 2, "sensor error": 3, "innovation": 4,
          "levers stale": 5, "internal": 6, "settling": 7}
#: s: the frames' nominal cycle (the DBC's GenMsgCycleTime).
CYCLE = 0.01


class _Error:
    """A signal that carries J1939's "error" code: the sensor reported a fault."""

    def __repr__(self) -> str:
        return "ERROR"


#: The decoded value of a signal that flags a sensor error.
ERROR = _Error()

_DB: Any = None


def database() -> Any:
    """The shipped DBC as a cantools database (loaded once)."""
    global _DB
    if _DB is None:
        try:
            import cantools
        except ImportError as e:  # pragma: no cover - the live extra is installed in CI
            raise ImportError("the live bus needs the 'live' extra: pip install 'cranepredict[live]'") from e
        text = resources.files("cranepredict.live").joinpath("patu655.dbc").read_text()
        _DB = cantools.database.load_string(text, database_format="dbc")
    return _DB


def _limits(length: int) -> Tuple[int, int, int]:
    """J1939: (largest valid raw value, first error code, first not-available code)."""
    if length == 4:
        return 0xD, 0xE, 0xF
    if length == 8:
        return 0xFA, 0xFE, 0xFF
    if length == 16:
        return 0xFAFF, 0xFE00, 0xFF00
    raise ValueError(f"no J1939 range for a {length}-bit signal")


class Codec:
    """Signals <-> frame bytes by the DBC, with None = not available and ERROR = sensor error."""

    def __init__(self) -> None:
        self.db = database()
        self._by_name = {m.name: m for m in self.db.messages}
        self._by_id = {m.frame_id: m for m in self.db.messages}

    def frame_id(self, frame: str) -> int:
        return self._by_name[frame].frame_id

    def name(self, frame_id: int) -> Optional[str]:
        m = self._by_id.get(frame_id)
        return None if m is None else m.name

    def encode(self, frame: str, values: Mapping[str, Any]) -> bytes:
        """The frame's 8 bytes: each signal's value (SI units) rounded to the DBC's resolution;
        None or a missing signal -> not available, ERROR -> the error code. A value outside the
        signal's valid range raises ValueError naming it."""
        msg = self._by_name[frame]
        raw = {}
        for s in msg.signals:
            valid, err, na = _limits(s.length)
            v = values.get(s.name)
            if v is None:
                raw[s.name] = (1 << s.length) - 1       # J1939 sends "not available" as all ones
            elif v is ERROR:
                raw[s.name] = err
            else:
                r = round((float(v) - s.offset) / s.scale) if math.isfinite(float(v)) else -1
                if not 0 <= r <= valid:
                    raise ValueError(f"{frame}.{s.name} = {v!r} is outside the signal's range "
                                     f"[{s.offset:g}, {s.offset + valid * s.scale:g}]")
                raw[s.name] = r
        data = bytearray(msg.encode(raw, scaling=False, strict=False, padding=True))
        return bytes(data)

    def decode(self, frame_id: int, data: bytes) -> Optional[Tuple[str, Dict[str, Any]]]:
        """(frame name, signal -> value in SI units, None if not available, ERROR if flagged),
        or None for a frame this DBC does not define."""
        msg = self._by_id.get(frame_id)
        if msg is None or len(data) != msg.length:
            return None
        raw = msg.decode(bytes(data), decode_choices=False, scaling=False)
        out: Dict[str, Any] = {}
        for s in msg.signals:
            valid, err, na = _limits(s.length)
            r = int(raw[s.name])
            out[s.name] = s.offset + r * s.scale if r <= valid else (ERROR if err <= r < na else None)
        return msg.name, out

    def message(self, frame: str, values: Mapping[str, Any], timestamp: float) -> Any:
        """A python-can Message of the frame (extended identifier)."""
        import can

        return can.Message(arbitration_id=self.frame_id(frame), is_extended_id=True,
                           data=self.encode(frame, values), timestamp=timestamp)


@dataclass
class SensorFrames:
    """The crane ECU's side: one cycle's sensor values and levers -> its frames, each with its
    rolling counter (0..13, J1939's 4-bit valid range, then 0 again)."""

    codec: Codec = field(default_factory=Codec)
    counters: Dict[str, int] = field(default_factory=dict)

    def next_counter(self, frame: str) -> int:
        c = self.counters.get(frame, -1)
        c = (c + 1) % 14
        self.counters[frame] = c
        return c

    def messages(self, values: Mapping[str, Any], lever: Sequence[float], valve_scale: float,
                 timestamp: float, *, frames: Optional[Sequence[str]] = None,
                 frozen: Sequence[str] = ()) -> List[Any]:
        """The sensor frames (``frames``, default all four) and the Levers frame last; a frame in
        ``frozen`` repeats its previous counter (a fault, for tests)."""
        out = []
        for frame in list(SENSOR_FRAMES if frames is None else frames) + [LEVER_FRAME]:
            if frame in frozen and frame in self.counters:
                counter = self.counters[frame]
            else:
                counter = self.next_counter(frame)
            if frame == LEVER_FRAME:
                sig = {f"{j}_lever": u for j, u in zip(JOINTS, lever)}
                sig["valve_scale"] = valve_scale
            else:
                sig = {f: values.get(f) for f in SENSOR_FRAMES[frame]}
            sig[COUNTERS[frame]] = counter
            out.append(self.codec.message(frame, sig, timestamp))
        return out


def _counter_step(previous: Optional[int], counter: int) -> int:
    """Frames since the previous counter (1 = in order, 0 = frozen, k > 1 = k - 1 lost)."""
    if previous is None:
        return 1
    return (counter - previous) % 14


@dataclass
class MeasurementAssembler:
    """The twin's side: frames in, one :class:`Measurement` per Levers frame out.

    Only the values that arrived since the last measurement are in it (others None), so the live
    twin sees each sample once and can age every sensor. A frame whose rolling counter did not
    advance (frozen) is discarded: its values are not fresh. Lost frames (a counter jump) and sensor
    error flags are counted and reported in ``faults`` of the next measurement."""

    codec: Codec = field(default_factory=Codec)
    pending: Dict[str, Any] = field(default_factory=dict)
    last_counter: Dict[str, int] = field(default_factory=dict)
    lost: Dict[str, int] = field(default_factory=dict)
    frozen: Dict[str, int] = field(default_factory=dict)
    faults: List[str] = field(default_factory=list)
    frames: int = 0

    def feed(self, msg: Any) -> Optional[Tuple[Optional[Measurement], List[str]]]:
        """One received frame; returns (measurement, faults) on a Levers frame, else None.
        The measurement is None if the frames cannot make one (faults say why)."""
        if not getattr(msg, "is_extended_id", True):
            return None
        dec = self.codec.decode(msg.arbitration_id, msg.data)
        if dec is None:
            return None
        name, sig = dec
        if name == VERDICT_FRAME:
            return None
        self.frames += 1
        step = _counter_step(self.last_counter.get(name), sig[COUNTERS[name]])
        counter = sig[COUNTERS[name]]
        if counter is None or counter is ERROR:
            self.faults.append(f"{name}: no rolling counter")
            return self._done(name, msg) if name == LEVER_FRAME else None
        self.last_counter[name] = int(counter)
        if step == 0:
            self.frozen[name] = self.frozen.get(name, 0) + 1
            return self._done(name, msg, fresh=False) if name == LEVER_FRAME else None
        if step > 1:
            self.lost[name] = self.lost.get(name, 0) + step - 1
        if name == LEVER_FRAME:
            return self._done(name, msg, sig)
        for f in SENSOR_FRAMES[name]:
            v = sig[f]
            if v is ERROR:
                self.faults.append(f"sensor error: {f}")
            elif v is not None:
                self.pending[f] = v
        return None

    def _done(self, name: str, msg: Any, sig: Optional[Dict[str, Any]] = None,
              fresh: bool = True) -> Tuple[Optional[Measurement], List[str]]:
        faults, self.faults = self.faults, []
        values, self.pending = self.pending, {}
        if sig is None or not fresh:
            faults.append("levers: frozen counter" if not fresh else "levers: not available")
            return None, faults
        u = [sig[f"{j}_lever"] for j in JOINTS]
        scale = sig["valve_scale"]
        if any(x is None or x is ERROR for x in u) or scale is None or scale is ERROR:
            faults.append("levers: not available or in error")
            return None, faults
        if any(not -1.0 <= x <= 1.0 for x in u):
            faults.append(f"out of range: levers {u} outside [-1, 1]")
            return None, faults
        try:
            m = Measurement(t=float(msg.timestamp), inputs=levers(*(x * scale for x in u)),
                            request=levers(*u), **values)
        except (TypeError, ValueError) as e:
            faults.append(f"out of range: {e}")
            return None, faults
        return m, faults


@dataclass
class VerdictFrame:
    """The twin's side: a verdict -> the Verdict frame, with its rolling counter."""

    codec: Codec = field(default_factory=Codec)
    counter: int = -1

    def message(self, signal: str, timestamp: float, *, time_to_contact: Optional[float] = None,
                latest_stop: Optional[float] = None, speed_limit: float = 0.0,
                fault: str = "none", part: Optional[int] = None,
                obstacle: Optional[int] = None) -> Any:
        self.counter = (self.counter + 1) % 14
        ttc = None if time_to_contact is None else min(max(time_to_contact, 0.0), 64.255)
        latest = None if latest_stop is None else min(max(latest_stop, -1.0), 63.255)
        return self.codec.message(VERDICT_FRAME, {
            "signal": SIGNAL_CODES[signal], "verdict_counter": self.counter,
            "time_to_contact": ttc, "latest_stop": latest,
            "speed_limit": min(max(speed_limit, 0.0), 1.0), "fault": FAULTS[fault],
            "part": part if part is not None and part <= 13 else None,
            "obstacle": obstacle if obstacle is not None and obstacle <= 13 else None}, timestamp)


@dataclass
class VerdictMonitor:
    """The crane ECU's side: Verdict frames in; ``allowed(t)`` says whether the valves may follow
    the levers: only on a fresh GO or WARN (counter advancing, newer than ``max_age`` s).
    Anything else (STOP, FAULT, no verdict, a frozen counter, a stale one) puts the valves to
    neutral."""

    max_age: float = 0.05
    codec: Codec = field(default_factory=Codec)
    last: Optional[Dict[str, Any]] = None
    last_time: float = -math.inf
    last_counter: Optional[int] = None

    def feed(self, msg: Any, t: Optional[float] = None) -> Optional[Dict[str, Any]]:
        """One received frame (a Verdict or not); ``t``: its receipt time on the ECU's clock
        (default: the frame's timestamp). Returns the verdict's signals if fresh."""
        dec = self.codec.decode(msg.arbitration_id, msg.data)
        if dec is None or dec[0] != VERDICT_FRAME:
            return None
        sig = dec[1]
        counter = sig["verdict_counter"]
        if counter is None or counter is ERROR or _counter_step(self.last_counter, int(counter)) == 0:
            return None    # frozen or missing counter: not a fresh verdict
        self.last_counter = int(counter)
        self.last, self.last_time = sig, float(msg.timestamp if t is None else t)
        return sig

    def signal(self, t: float) -> str:
        if self.last is None or t - self.last_time > self.max_age:
            return "FAULT"
        code = self.last["signal"]
        names = {v: k for k, v in SIGNAL_CODES.items()}
        return names.get(int(code), "FAULT") if isinstance(code, (int, float)) else "FAULT"

    def allowed(self, t: float) -> bool:
        return self.signal(t) in ("GO", "WARN")
