"""A closed-loop episode in one process: the simulated crane, the live twin, and the verdict fed
back to the crane one control period later (the bus's and the computation's delay)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional, Tuple

from ..crane import Crane
from ..types import State
from ..world import World
from .loop import LiveTwin, LiveVerdict
from .measurement import Sensors, default_sensors
from .sim import LeverScript, Plant, SensorModel, SimCrane, perturbed_crane

__all__ = ["Episode", "run_episode", "demo_setup"]


@dataclass
class Episode:
    """What happened: the verdicts in order, whether the true crane touched an obstacle (and
    where), its smallest clearance (m), when the first STOP or FAULT came and the counts of each
    signal."""

    verdicts: List[LiveVerdict] = field(default_factory=list)
    collided: bool = False
    contact: Optional[str] = None
    first_stop: Optional[float] = None
    first_fault: Optional[float] = None
    counts: Dict[str, int] = field(default_factory=dict)
    vacuum_clips: int = 0
    min_clearance: float = float("inf")


def run_episode(crane: Crane, world: World, start: State, script: LeverScript, seconds: float, *,
                obey: bool = True, plant_crane: Optional[Crane] = None,
                sensors: Optional[Sensors] = None, seed: int = 0, horizon: float = 2.0,
                delay_cycles: int = 1, twin: Optional[LiveTwin] = None,
                inject: Optional[Callable[[int, SimCrane], None]] = None,
                on_verdict: Optional[Callable[[LiveVerdict], None]] = None,
                stop_at_collision: bool = True) -> Episode:
    """Runs ``seconds`` of the loop at 100 Hz: the plant (``plant_crane``, default
    :func:`perturbed_crane` of ``crane``) follows ``script`` through valves that obey the
    verdict of ``delay_cycles`` periods ago (or ignore it, ``obey=False``); the twin (default
    :class:`LiveTwin` of ``crane``) judges each measurement. ``inject(k, sim)`` may alter the
    simulated crane before cycle k (fault injection)."""
    sensors = sensors or default_sensors()
    plant = Plant(plant_crane or perturbed_crane(crane), start, world=world)
    sim = SimCrane(plant, script, SensorModel(sensors, seed=seed), obey=obey)
    twin = twin or LiveTwin(crane, world, sensors=sensors, horizon=horizon)
    ep = Episode()
    pending: List[LiveVerdict] = []
    n = int(round(seconds / sim.period))
    for k in range(n):
        if inject is not None:
            inject(k, sim)
        v = twin.cycle(sim.measurement())
        ep.verdicts.append(v)
        if on_verdict is not None:
            on_verdict(v)
        if v.signal == "STOP" and ep.first_stop is None:
            ep.first_stop = v.t
        if v.signal == "FAULT" and ep.first_fault is None:
            ep.first_fault = v.t
        pending.append(v)
        decided = pending.pop(0) if len(pending) > delay_cycles else None
        sim.step(allowed=decided is not None and not decided.stops)
        if plant.collided and not ep.collided:
            ep.collided, ep.contact = True, plant.contact
            if stop_at_collision:
                break
    ep.counts = dict(twin.counts)
    ep.vacuum_clips = plant.vacuum_clips
    ep.min_clearance = plant.min_clearance
    return ep


def demo_setup(crane: Crane) -> Tuple[State, LeverScript, str]:
    """The demo: the crane at rest with its boom up, the operator extending the telescope
    towards the wall of the example world ``wall`` (0.5 s idle, then the extension lever at
    0.8 and held)."""
    from ..api import state_at_rest

    start = state_at_rest(perturbed_crane(crane), 0.25, 0.2, extension=0.0)
    script = LeverScript(((0.0, (0.0, 0.0, 0.0, 0.0)), (0.5, (0.0, 0.0, 0.0, 0.8))))
    return start, script, "wall"
