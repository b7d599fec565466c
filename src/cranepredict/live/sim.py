"""A simulated crane to test the live twin against: the plant is not the twin's own model.

The plant is the C core with a perturbed crane file (:func:`perturbed_crane`: load mass, friction
and supply pressure off by realistic amounts), stepped cycle by cycle by chained short predictions
(``Trajectory.final_state``). :class:`SensorModel` turns its state into what transducers report
(noise, the bus's resolution, each sensor's rate); :class:`LeverScript` is the operator;
:class:`SimCrane` is the crane's ECU: it follows the script and obeys the verdict (valves to
neutral unless a fresh GO or WARN).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .. import api
from ..crane import Crane
from ..guard import guard
from .._checks import PRESSURE_MAX
from ..types import CHAMBER_PRESSURE_MIN, JOINTS, State
from ..world import World
from .measurement import PRESSURES, Measurement, Sensors, default_sensors, levers

__all__ = ["perturbed_crane", "Plant", "SensorModel", "LeverScript", "SimCrane", "RESOLUTION"]

#: The resolution a transducer's value reaches the twin at (the DBC's: 0.1 mm, 0.125 mrad, 0.1 bar).
RESOLUTION = {"lift_stroke": 1e-4, "tilt_stroke": 1e-4, "extension": 1e-4, "slew": 1.25e-4,
              **{p: 1e4 for p in PRESSURES}}


def _hydraulics(actuator: Any, supply: float) -> Any:
    if actuator is None or actuator.hydraulics is None:
        return actuator
    h = actuator.hydraulics
    return dataclasses.replace(actuator, hydraulics=dataclasses.replace(
        h, supply_pressure=h.supply_pressure * supply))


def _friction(actuator: Any, factor: float) -> Any:
    if actuator is None:
        return actuator
    f = actuator.friction
    return dataclasses.replace(actuator, friction=dataclasses.replace(
        f, coulomb=f.coulomb * factor, static=f.static * factor, viscous=f.viscous * factor))


def perturbed_crane(crane: Crane, *, load: float = 1.3, friction: float = 1.2,
                    supply: float = 0.97) -> Crane:
    """The crane with its load mass times ``load``, every friction level times ``friction`` and
    every supply pressure times ``supply`` (a different crane of the same build, as a real one
    differs from its crane file: the load on the hook is guessed, seals wear, the pump's
    setting drifts)."""
    c = crane.with_load(crane.load_mass * load)
    for name in ("lift_cylinder", "tilt_cylinder", "slew_drive", "extension_cylinder"):
        act = getattr(c, name)
        c = dataclasses.replace(c, **{name: _hydraulics(_friction(act, friction), supply)})
    return c


@dataclass
class Plant:
    """The true crane: its state, advanced one control period at a time under the valves'
    commands. With a ``world``, each step also says whether the crane touched an obstacle
    (clearance <= 0 anywhere along the step, found by the guard with a zero margin) and keeps
    the smallest clearance of any part at the guard's samples (``min_clearance``, m)."""

    crane: Crane
    state: State
    world: Optional[World] = None
    t: float = 0.0
    dt: Optional[float] = None
    collided: bool = False
    contact: Optional[str] = None
    vacuum_clips: int = 0
    min_clearance: float = math.inf

    def step(self, valve: Sequence[float], period: float) -> State:
        inputs = levers(*valve)
        if self.world is not None:
            v = guard(self.crane, self.world, self.state, inputs, period, dt=self.dt, margin=0.0)
            traj = v.trajectory
            self.min_clearance = min(self.min_clearance, min(v.clearance.values(), default=math.inf))
            if v.contact is not None and not self.collided:
                self.collided = True
                self.contact = (f"{v.contact.part} touched {v.contact.obstacle} at "
                                f"t = {self.t + v.contact.t:.2f} s")
        else:
            traj = api.predict(self.crane, self.state, inputs, period, dt=self.dt)
        try:
            self.state = traj.final_state
        except ValueError:
            # the model's cavitation valve lets a chamber dip below vacuum for a step (-1.3 bar
            # at full lever on the telescope); the State cannot hold that: the plant's chambers
            # are taken at vacuum there, and the event counted
            self.vacuum_clips += 1
            self.state = dataclasses.replace(
                traj, p_a=np.maximum(traj.p_a, CHAMBER_PRESSURE_MIN),
                p_b=np.maximum(traj.p_b, CHAMBER_PRESSURE_MIN)).final_state
        self.t += period
        return self.state


@dataclass
class SensorModel:
    """Transducers: each configured sensor samples the true state at its own rate, adds Gaussian
    noise of its std, saturates at its range (pressures: vacuum to PRESSURE_MAX) and is rounded to
    the bus's resolution; a stuck sensor repeats a value."""

    sensors: Sensors = field(default_factory=default_sensors)
    seed: int = 0
    stuck: Dict[str, float] = field(default_factory=dict)
    rng: np.random.Generator = field(init=False)
    next_sample: Dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.rng = np.random.default_rng(self.seed)

    def sample(self, state: State, t: float) -> Dict[str, Optional[float]]:
        out: Dict[str, Optional[float]] = {}
        for s in self.sensors.sensors:
            due = self.next_sample.get(s.field, -math.inf)
            if t + 1e-9 < due:
                out[s.field] = None
                continue
            self.next_sample[s.field] = max(due + 1.0 / s.rate, t) if math.isfinite(due) else t + 1.0 / s.rate
            if s.field in self.stuck:
                out[s.field] = self.stuck[s.field]
                continue
            v = getattr(state, s.field) + s.std * float(self.rng.standard_normal())
            if s.field in PRESSURES:   # a transducer saturates at its range (vacuum at the bottom)
                v = min(max(v, CHAMBER_PRESSURE_MIN), PRESSURE_MAX)
            q = RESOLUTION.get(s.field)
            out[s.field] = round(v / q) * q if q else v
        return out


@dataclass(frozen=True)
class LeverScript:
    """The operator: lever positions (lift, tilt, slew, extension) held from each time on.
    ``steps`` = ((t0, (u...)), (t1, (u...)), ...), t0 = 0, increasing."""

    steps: Tuple[Tuple[float, Tuple[float, float, float, float]], ...]

    def at(self, t: float) -> Tuple[float, float, float, float]:
        u = self.steps[0][1]
        for t0, v in self.steps:
            if t + 1e-12 >= t0:
                u = v
        return u


@dataclass
class SimCrane:
    """The crane's ECU: each control period it reads the operator's levers (the script), lets the
    valves follow them only on a fresh GO or WARN when it ``obeys`` (else valves to neutral),
    advances the plant and reports the sensors. ``delay`` (s) is the bus's: the measurement of
    time t reaches the twin at t + delay (a whole number of periods)."""

    plant: Plant
    script: LeverScript
    sensor_model: SensorModel = field(default_factory=SensorModel)
    period: float = 0.01
    obey: bool = True
    valve_scale: float = 1.0
    applied: Tuple[float, ...] = (0.0, 0.0, 0.0, 0.0)
    history: List[Tuple[float, State, Tuple[float, ...], float]] = field(default_factory=list)

    def measure(self) -> Tuple[Dict[str, Optional[float]], Tuple[float, ...], float]:
        """The sensors now, the operator's levers, the scale applied to them."""
        return (self.sensor_model.sample(self.plant.state, self.plant.t),
                self.script.at(self.plant.t), self.valve_scale)

    def measurement(self) -> Measurement:
        values, request, scale = self.measure()
        return Measurement(t=self.plant.t, inputs=levers(*(u * scale for u in request)),
                           request=levers(*request), **{k: v for k, v in values.items()})

    def step(self, allowed: bool) -> State:
        """Advances one period; ``allowed``: the latest verdict lets the valves follow the levers."""
        request = self.script.at(self.plant.t)
        self.valve_scale = 1.0 if (allowed or not self.obey) else 0.0
        valve = tuple(u * self.valve_scale for u in request)
        self.history.append((self.plant.t, self.plant.state, valve, self.valve_scale))
        self.applied = valve
        return self.plant.step(valve, self.period)
