"""``cranepredict view``: the display of a named scenario's predicted future in a world, or of a
recorded CAN log run through the live twin (``--replay LOG``, a timeline over its cycles)."""

from __future__ import annotations

import argparse
import os
import sys
import time
from typing import List, Optional

from .. import scenarios
from .. import world as world_mod
from .frame import Frame
from .server import Viewer, require_viser

DEFAULT_SCENARIO = "paper-fig4"
#: s: the live twin's prediction horizon in a replay unless --horizon says otherwise.
REPLAY_HORIZON = 2.0


def replay_recording(args: argparse.Namespace) -> List[Frame]:
    """The frames of --replay LOG: the live twin (--crane, --world, --horizon, --reaction,
    --cycle) over the log, one frame per cycle."""
    from ..crane import Crane

    if args.scenario is not None:
        raise ValueError("--scenario and --replay are two sources: give one")
    if not os.path.exists(args.replay):
        raise ValueError(f"--replay: no such file: {args.replay!r}")
    if not args.replay.lower().endswith((".blf", ".asc", ".log")):
        raise ValueError(f"--replay: a python-can log (.blf, .asc or .log), got {args.replay!r}")
    try:
        import can  # noqa: F401
        import cantools  # noqa: F401
    except ImportError:
        raise ValueError("--replay needs the live twin's bus: pip install 'cranepredict[live]'") \
            from None
    from ..live.loop import LiveTwin
    from .sources import replay_frames

    crane = Crane.patu655() if args.crane is None else Crane.from_toml(args.crane)
    world = load_world(args.world)
    twin = LiveTwin(crane, world, horizon=REPLAY_HORIZON if args.horizon is None else args.horizon,
                    reaction=args.reaction, cycle_time=args.cycle)
    frames = replay_frames(args.replay, twin)
    if not frames:
        raise ValueError(f"--replay: {args.replay!r} has no cycle with a state estimate "
                         f"(no complete sensor frames and levers)")
    return frames


def load_world(name_or_path: str) -> world_mod.World:
    """A world file (TOML) or an example world's name; ValueError naming both choices."""
    if os.path.exists(name_or_path):
        return world_mod.World.from_toml(name_or_path)
    if name_or_path in world_mod.names():
        return world_mod.get(name_or_path)
    raise ValueError(f"--world: no such file, and not an example world "
                     f"({', '.join(world_mod.names())}): {name_or_path!r}")


def scenario_frame(args: argparse.Namespace) -> Frame:
    """The frame of --scenario in --world (the guard's verdict on its horizon)."""
    sc = scenarios.get(args.scenario or DEFAULT_SCENARIO)
    world = load_world(args.world)
    horizon = sc.horizon if args.horizon is None else args.horizon
    return Frame.predict(sc.crane, world, sc.initial, sc.inputs, horizon, reaction=args.reaction,
                         cycle=args.cycle)


def run(args: argparse.Namespace) -> int:
    """Checks everything, serves the page, prints its address and waits (Ctrl-C stops)."""
    require_viser()
    # bad input fails here, before the server starts
    if args.crane is not None and args.replay is None:
        raise ValueError("--crane is the live twin's crane in a --replay (a scenario has its own)")
    if args.replay is not None:
        print(f"replaying {args.replay} through the live twin ...", flush=True)
        frames = replay_recording(args)
    else:
        frames = [scenario_frame(args)]
    viewer = Viewer(host=args.host, port=args.port, ghosts=args.ghosts)
    try:
        print(f"display    {viewer.url}  (Ctrl-C stops)")
        if args.replay is not None:
            viewer.play(frames)
            counts = {s: sum(f.signal == s for f in frames) for s in ("GO", "WARN", "STOP", "FAULT")}
            print(f"replay     {os.path.basename(args.replay)} in {frames[0].world.name}: "
                  f"{len(frames)} cycles, t = {frames[0].clock:.2f}-{frames[-1].clock:.2f} s ("
                  + ", ".join(f"{k} {n}" for k, n in counts.items()) + "); the slider "
                  "'recording, frame' picks the cycle")
        else:
            frame = frames[0]
            viewer.show(frame)
            b = frame.verdict
            print(f"scenario   {args.scenario or DEFAULT_SCENARIO} in {frame.world.name}: "
                  f"{frame.signal}" + (f" - {b.reason}" if b is not None else ""))
        sys.stdout.flush()
        serve(args.serve_for)
        return 0
    finally:
        viewer.close()


def serve(seconds: Optional[float]) -> None:
    """Keeps the page up for ``seconds`` (None: until Ctrl-C)."""
    if seconds is not None:
        time.sleep(seconds)
        return
    while True:
        time.sleep(3600)
