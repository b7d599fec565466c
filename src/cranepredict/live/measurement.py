"""What the crane's sensors report in one control cycle (:class:`Measurement`) and what sensors a
crane has (:class:`Sensor`, :class:`Sensors`).

A Measurement uses the :class:`~cranepredict.State`'s field names for what is measured and None for
what is not (this cycle, or ever); it is checked like a State (finite numbers in the same ranges,
the error naming the field). SI units: m, rad, Pa (gauge), s.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Dict, Iterable, Optional, Tuple

from .._checks import PRESSURE_MAX
from .._checks import number as _number
from ..types import (CHAMBER_PRESSURE_MIN, JOINTS, SLEW_RATE_MAX, STROKE_RATE_MAX, Hold, Inputs,
                     State, Valve)

__all__ = ["Measurement", "Sensor", "Sensors", "MEASURABLE", "POSITIONS", "PRESSURES",
           "levers", "default_sensors"]

#: The State's position fields, one per joint (JOINTS order).
POSITIONS = ("lift_stroke", "tilt_stroke", "slew", "extension")
#: The State's rate fields, one per joint (JOINTS order).
RATES = ("lift_stroke_rate", "tilt_stroke_rate", "slew_rate", "extension_rate")
#: The State's chamber pressure fields (JOINTS order, p_a before p_b).
PRESSURES = tuple(f"{j}_{s}" for j in JOINTS for s in ("p_a", "p_b"))
#: The State's spool fields (JOINTS order).
SPOOLS = tuple(f"{j}_spool" for j in JOINTS)
#: Every field a sensor may measure: the State's fields.
MEASURABLE = tuple(f.name for f in dataclasses.fields(State))


def _range(name: str) -> Tuple[float, float, str]:
    """The allowed range of a State field (as State checks it) and its unit."""
    if name in PRESSURES:
        return CHAMBER_PRESSURE_MIN, PRESSURE_MAX, "Pa"
    if name in SPOOLS:
        return -1.0, 1.0, ""
    if name == "slew_rate":
        return -SLEW_RATE_MAX, SLEW_RATE_MAX, "rad/s"
    if name in RATES:
        return -STROKE_RATE_MAX, STROKE_RATE_MAX, "m/s"
    return -math.inf, math.inf, "rad" if name == "slew" else "m"


@dataclass(frozen=True, kw_only=True)
class Measurement:
    """The sensors' values at time ``t`` (s) and the lever commands.

    Each State field (``lift_stroke``, ``tilt_stroke``, ``slew``, ``extension``, ``lift_p_a``, ...)
    holds the measured value, or None where the crane does not measure it or no new sample arrived
    this cycle. ``inputs`` are the valves' commands at ``t`` (after any interlock; the
    estimator holds them until the next measurement), as
    :class:`~cranepredict.Valve` drives; ``request`` the operator's levers before the interlock
    (None: the same as ``inputs``): the live twin predicts the future under ``request``.
    """

    t: float
    inputs: Inputs
    request: Optional[Inputs] = None
    lift_stroke: Optional[float] = None
    tilt_stroke: Optional[float] = None
    slew: Optional[float] = None
    extension: Optional[float] = None
    lift_stroke_rate: Optional[float] = None
    tilt_stroke_rate: Optional[float] = None
    lift_p_a: Optional[float] = None
    lift_p_b: Optional[float] = None
    tilt_p_a: Optional[float] = None
    tilt_p_b: Optional[float] = None
    lift_spool: Optional[float] = None
    tilt_spool: Optional[float] = None
    slew_rate: Optional[float] = None
    extension_rate: Optional[float] = None
    slew_p_a: Optional[float] = None
    slew_p_b: Optional[float] = None
    extension_p_a: Optional[float] = None
    extension_p_b: Optional[float] = None
    slew_spool: Optional[float] = None
    extension_spool: Optional[float] = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "t", _number(self.t, "Measurement.t"))
        for name in ("inputs", "request"):
            value = getattr(self, name)
            if value is None and name == "request":
                continue
            if not isinstance(value, Inputs):
                raise TypeError(f"Measurement.{name} must be a cranepredict.Inputs, "
                                f"got {type(value).__name__}")
        for name in MEASURABLE:
            value = getattr(self, name)
            if value is None:
                continue
            x = _number(value, f"Measurement.{name}")
            low, high, unit = _range(name)
            if not low <= x <= high:
                raise ValueError(f"Measurement.{name} must be in [{low:g}, {high:g}] {unit}, got {x:g}")
            object.__setattr__(self, name, x)

    def values(self) -> Dict[str, float]:
        """The measured fields (name -> value), without the Nones."""
        return {n: getattr(self, n) for n in MEASURABLE if getattr(self, n) is not None}

    @property
    def predicted_inputs(self) -> Inputs:
        """The inputs the future is predicted under: ``request``, or ``inputs`` without one."""
        return self.inputs if self.request is None else self.request


def levers(lift: float = 0.0, tilt: float = 0.0, slew: float = 0.0,
           extension: float = 0.0) -> Inputs:
    """Inputs of four levers (each in [-1, 1]), every joint valve-driven."""
    return Inputs(lift=Valve(lift), tilt=Valve(tilt), slew=Valve(slew), extension=Valve(extension))


def lever_values(inputs: Inputs) -> Tuple[float, float, float, float]:
    """The four lever positions of Inputs of Valve (or Hold = 0) drives, JOINTS order."""
    out = []
    for j in JOINTS:
        d = getattr(inputs, j)
        if isinstance(d, Valve):
            out.append(d.u)
        elif isinstance(d, Hold):
            out.append(0.0)
        else:
            raise TypeError(f"Inputs.{j} must be a Valve (a lever) or Hold on a live crane, "
                            f"got {type(d).__name__}")
    return tuple(out)  # type: ignore[return-value]


@dataclass(frozen=True)
class Sensor:
    """One transducer: the State field it measures, its noise (standard deviation, the field's
    SI unit), its sample rate (Hz) and the largest age (s) its newest sample may have before the
    live twin treats the data as stale (default: three sample periods)."""

    field: str
    std: float
    rate: float = 100.0
    max_age: Optional[float] = None

    def __post_init__(self) -> None:
        if self.field not in MEASURABLE:
            raise ValueError(f"Sensor.field must be one of the State's fields {MEASURABLE}, "
                             f"got {self.field!r}")
        std = _number(self.std, f"Sensor({self.field}).std")
        rate = _number(self.rate, f"Sensor({self.field}).rate")
        if not std > 0:
            raise ValueError(f"Sensor({self.field}).std must be > 0, got {std:g}")
        if not 0 < rate <= 10_000:
            raise ValueError(f"Sensor({self.field}).rate must be in (0, 10000] Hz, got {rate:g}")
        age = 3.0 / rate if self.max_age is None else _number(self.max_age, f"Sensor({self.field}).max_age")
        if not age >= 1.0 / rate:
            raise ValueError(f"Sensor({self.field}).max_age must be >= one sample period "
                             f"{1.0 / rate:g} s, got {age:g}")
        object.__setattr__(self, "std", std)
        object.__setattr__(self, "rate", rate)
        object.__setattr__(self, "max_age", age)


@dataclass(frozen=True)
class Sensors:
    """The sensors a crane has, one per measured field; a field without a sensor is not measured
    (a missing sensor). ``levers_max_age`` (s): the largest age of the lever commands."""

    sensors: Tuple[Sensor, ...]
    levers_max_age: float = 0.05

    def __post_init__(self) -> None:
        items = tuple(self.sensors)
        for s in items:
            if not isinstance(s, Sensor):
                raise TypeError(f"Sensors.sensors must hold Sensor objects, got {type(s).__name__}")
        names = [s.field for s in items]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"Sensors.sensors: one sensor per field, got several for {dup}")
        age = _number(self.levers_max_age, "Sensors.levers_max_age")
        if not age > 0:
            raise ValueError(f"Sensors.levers_max_age must be > 0 s, got {age:g}")
        object.__setattr__(self, "sensors", items)
        object.__setattr__(self, "levers_max_age", age)

    @property
    def fields(self) -> Tuple[str, ...]:
        return tuple(s.field for s in self.sensors)

    def __getitem__(self, name: str) -> Sensor:
        for s in self.sensors:
            if s.field == name:
                return s
        raise KeyError(f"no sensor measures {name!r} (measured: {self.fields})")

    def __contains__(self, name: object) -> bool:
        return name in self.fields

    def without(self, *names: str) -> "Sensors":
        """These sensors less the named ones (a missing sensor)."""
        for n in names:
            self[n]
        return dataclasses.replace(self, sensors=tuple(s for s in self.sensors if s.field not in names))

    def with_noise(self, **std: float) -> "Sensors":
        """These sensors with the named fields' noise replaced (std in the field's unit)."""
        for n in std:
            self[n]
        return dataclasses.replace(self, sensors=tuple(
            dataclasses.replace(s, std=std[s.field]) if s.field in std else s for s in self.sensors))


def default_sensors(stroke_std: float = 2e-4, pressure_std: float = 2e5, rate: float = 100.0,
                    slew_std: float = 5e-4, extension_std: float = 5e-4,
                    fields: Optional[Iterable[str]] = None) -> Sensors:
    """A loader crane's usual transducers: the boom cylinders' strokes (magnetostrictive position
    sensors, 0.2 mm), all eight chamber pressures (2 bar), the slew angle (absolute encoder,
    0.5 mrad) and the extension (draw-wire sensor, 0.5 mm), every one at ``rate`` Hz. ``fields``
    picks a subset."""
    std = {"lift_stroke": stroke_std, "tilt_stroke": stroke_std, "slew": slew_std,
           "extension": extension_std, **{p: pressure_std for p in PRESSURES}}
    chosen = tuple(std) if fields is None else tuple(fields)
    return Sensors(tuple(Sensor(f, std[f], rate) for f in chosen))
