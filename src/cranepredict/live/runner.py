"""The live twin and the simulated crane on a python-can bus, and the replay of a recorded log.

:func:`run_twin` serves the twin: frames in, a Verdict frame out per Levers frame (and a FAULT
verdict when the levers stop coming). :func:`run_sim` plays the crane's ECU. :func:`replay` runs
the twin over a python-can log (.blf, .asc, .log); :func:`record` writes one of the simulated
crane alone. :func:`demo` puts the two on one virtual bus.
"""

from __future__ import annotations

import math
import threading
import time
import uuid
from typing import Any, Callable, Dict, List, Optional

from ..crane import Crane
from ..world import World
from .bus import VERDICT_FRAME, Codec, MeasurementAssembler, SensorFrames, VerdictFrame, VerdictMonitor
from .loop import LiveTwin, LiveVerdict
from .sim import SimCrane

__all__ = ["run_twin", "run_sim", "replay", "record", "verdict_message", "demo"]


def verdict_message(frame: VerdictFrame, v: LiveVerdict, crane: Crane, world: World,
                    timestamp: float) -> Any:
    """The Verdict frame of a live verdict."""
    parts = [p.name for p in crane.shape.parts] if crane.shape is not None else []
    obstacles = [o.name for o in world.obstacles]
    latest = v.latest_stop
    return frame.message(
        v.signal, timestamp, time_to_contact=v.time_to_contact,
        latest_stop=None if latest is None else (latest if math.isfinite(latest) else -1.0),
        speed_limit=v.speed_limit, fault=v.fault or "none",
        part=parts.index(v.part) if v.part in parts else None,
        obstacle=obstacles.index(v.obstacle) if v.obstacle in obstacles else None)


def run_twin(bus: Any, twin: LiveTwin, *, stop: Optional[threading.Event] = None,
             on_verdict: Optional[Callable[[LiveVerdict], None]] = None,
             clock: Callable[[], float] = time.time, max_cycles: Optional[int] = None) -> int:
    """Serves the twin on ``bus`` until ``stop`` is set (or ``max_cycles`` verdicts): each Levers
    frame closes a measurement, the verdict goes out at once. Without a Levers frame for the
    sensors' ``levers_max_age``, a FAULT verdict goes out each such period. Returns the number
    of measurements judged (``max_cycles`` counts these)."""
    asm, out = MeasurementAssembler(), VerdictFrame()
    sent, last = 0, clock()
    age = twin.sensors.levers_max_age
    while not (stop is not None and stop.is_set()) and (max_cycles is None or sent < max_cycles):
        msg = bus.recv(timeout=age / 2)
        now = clock()
        got = asm.feed(msg) if msg is not None else None
        if got is None:
            if now - last > age:
                v = twin.no_levers(now, f"no lever frame for {now - last:.3f} s")
                bus.send(verdict_message(out, v, twin.crane, twin.world, now))
                last = now
                if on_verdict:
                    on_verdict(v)
            continue
        m, faults = got
        last = now
        v = twin.cycle(m, faults) if m is not None else twin.fault(
            float(msg.timestamp), "levers stale", "; ".join(faults))
        bus.send(verdict_message(out, v, twin.crane, twin.world, float(msg.timestamp)))
        sent += 1
        if on_verdict:
            on_verdict(v)
    return sent


def run_sim(bus: Any, sim: SimCrane, seconds: float, *, lockstep: bool = True,
            verdict_timeout: float = 2.0, stop: Optional[threading.Event] = None) -> VerdictMonitor:
    """Plays the crane's ECU for ``seconds`` of simulated time: each period it sends the sensor and
    Levers frames, takes the verdicts received, and advances the plant with the valves following
    the levers only on a fresh GO or WARN. ``lockstep``: waits (up to ``verdict_timeout`` s of
    wall time) for the verdict of this period's frames, so the run does not depend on the
    machine's speed; otherwise runs by the wall clock."""
    frames, monitor = SensorFrames(), VerdictMonitor(max_age=0.05)
    n = int(round(seconds / sim.period))
    start = time.time()
    for _ in range(n):
        if stop is not None and stop.is_set():
            break
        values, request, scale = sim.measure()
        t = sim.plant.t if lockstep else time.time() - start
        for msg in frames.messages(values, request, scale, timestamp=t):
            bus.send(msg)
        deadline = time.time() + (verdict_timeout if lockstep else sim.period)
        while True:
            msg = bus.recv(timeout=max(0.0, deadline - time.time()))
            if msg is None:
                break
            if monitor.feed(msg, t if lockstep else time.time() - start) is not None and lockstep:
                break
            if time.time() >= deadline:
                break
        now = t if lockstep else time.time() - start
        sim.step(allowed=monitor.allowed(now))
        if not lockstep:
            time.sleep(max(0.0, start + sim.plant.t - time.time()))
    return monitor


def replay(path: str, twin: LiveTwin) -> List[LiveVerdict]:
    """The twin over a recorded log (python-can's formats: .blf, .asc, .log): the verdict of
    every Levers frame, in order."""
    import can

    asm, out = MeasurementAssembler(), []
    codec = Codec()
    verdict_id = codec.frame_id(VERDICT_FRAME)
    with can.LogReader(path) as reader:
        for msg in reader:
            if msg.arbitration_id == verdict_id:
                continue
            got = asm.feed(msg)
            if got is None:
                continue
            m, faults = got
            out.append(twin.cycle(m, faults) if m is not None else
                       twin.fault(float(msg.timestamp), "levers stale", "; ".join(faults)))
    return out


def record(sim: SimCrane, seconds: float, path: str) -> int:
    """Writes the simulated crane's frames (sensors and levers, no verdict) for ``seconds`` of
    simulated time to a python-can log (.blf, .asc, .log), the valves following the levers
    (the crane's true states are in ``sim.history``); returns the number of cycles. A log to try
    ``cranepredict replay`` and ``cranepredict view --replay`` on without a bus."""
    import can

    if not isinstance(seconds, (int, float)) or isinstance(seconds, bool) \
            or not 0 < seconds <= 3600:
        raise ValueError(f"seconds must be in (0, 3600], got {seconds!r}")
    frames = SensorFrames()
    n = int(round(seconds / sim.period))
    logger = can.Logger(path)
    try:
        for _ in range(n):
            values, request, scale = sim.measure()
            for msg in frames.messages(values, request, scale, timestamp=sim.plant.t):
                logger.on_message_received(msg)
            sim.step(allowed=True)
    finally:
        logger.stop()
    return n


def demo(crane: Crane, world: World, sim: SimCrane, twin: LiveTwin, seconds: float, *,
         on_verdict: Optional[Callable[[LiveVerdict], None]] = None,
         log: Optional[str] = None) -> Dict[str, Any]:
    """The simulated crane and the twin, each on its own connection to one python-can virtual
    bus (lockstep), for ``seconds``; ``log``: record the bus to this file (.blf, .asc, .log)."""
    import can

    channel = f"cranepredict-demo-{uuid.uuid4().hex[:8]}"
    stop = threading.Event()
    with can.Bus(interface="virtual", channel=channel, preserve_timestamps=True) as crane_bus, \
            can.Bus(interface="virtual", channel=channel, preserve_timestamps=True) as twin_bus:
        logger = None
        if log is not None:
            logger = can.Logger(log)
            listener_bus = can.Bus(interface="virtual", channel=channel, preserve_timestamps=True)
            notifier = can.Notifier(listener_bus, [logger])
        worker = threading.Thread(target=run_twin, args=(twin_bus, twin),
                                  kwargs=dict(stop=stop, on_verdict=on_verdict,
                                              clock=lambda: sim.plant.t), daemon=True)
        worker.start()
        try:
            monitor = run_sim(crane_bus, sim, seconds)
        finally:
            stop.set()
            worker.join(timeout=5.0)
            if logger is not None:
                time.sleep(0.05)
                notifier.stop()
                logger.stop()
                listener_bus.shutdown()
    return {"monitor": monitor}
