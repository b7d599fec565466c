"""``cranepredict view``: the display of a named scenario's predicted future in a world."""

from __future__ import annotations

import argparse
import os
import sys
import time

from .. import scenarios
from .. import world as world_mod
from .frame import Frame
from .server import Viewer, require_viser


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
    sc = scenarios.get(args.scenario)
    world = load_world(args.world)
    horizon = sc.horizon if args.horizon is None else args.horizon
    return Frame.predict(sc.crane, world, sc.initial, sc.inputs, horizon, reaction=args.reaction,
                         cycle=args.cycle)


def run(args: argparse.Namespace) -> int:
    """Checks everything, serves the page, prints its address and waits (Ctrl-C stops)."""
    require_viser()
    frame = scenario_frame(args)            # bad input fails here, before the server starts
    viewer = Viewer(host=args.host, port=args.port, ghosts=args.ghosts)
    try:
        viewer.show(frame)
        b = frame.verdict
        print(f"display    {viewer.url}  (Ctrl-C stops)")
        print(f"scenario   {args.scenario} in {frame.world.name}: {frame.signal}"
              + (f" - {b.reason}" if b is not None else ""))
        sys.stdout.flush()
        if args.serve_for is not None:
            time.sleep(args.serve_for)
            return 0
        while True:
            time.sleep(3600)
    finally:
        viewer.close()
