"""Command line: ``cranepredict demo`` runs the paper's scenario and reports speed."""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from typing import List, Optional

import numpy as np


def _demo(args: argparse.Namespace) -> int:
    from . import api, scenarios

    sc = scenarios.get(args.scenario)
    dt = args.dt if args.dt is not None else api.DEFAULT_DT
    traj = api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt)
    walls = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt)
        walls.append(time.perf_counter() - t0)
    wall = statistics.median(walls)
    deg = np.degrees
    print(f"scenario   {sc.name}: {sc.description}")
    print(f"crane      {sc.crane.name}, load {sc.crane.load_mass:g} kg, horizon {sc.horizon:g} s, "
          f"dt {dt:g} s ({len(traj.t)} samples)")
    x, y, z = traj.tip[0]
    print(f"tip start  x {x:7.3f} m  y {y:7.3f} m  z {z:7.3f} m   "
          f"(lift {deg(traj.theta[0, 0]):6.1f} deg, tilt {deg(traj.theta[0, 1]):6.1f} deg)")
    x, y, z = traj.tip[-1]
    print(f"tip end    x {x:7.3f} m  y {y:7.3f} m  z {z:7.3f} m   "
          f"(lift {deg(traj.theta[-1, 0]):6.1f} deg, tilt {deg(traj.theta[-1, 1]):6.1f} deg)")
    for j, name in enumerate(("lift", "tilt")):
        for side, word in ((+1, "upper"), (-1, "lower")):
            t_stop = traj.first_stop_time(j, side)
            if t_stop is not None:
                print(f"end stop   {name} cylinder reached its {word} stop at t = {t_stop:.3f} s")
    if not traj.stop.any():
        print("end stop   none reached")
    print(f"speed      {wall * 1e6:.0f} us per prediction (median of {args.repeat}): "
          f"{sc.horizon / wall:,.0f}x faster than real time (the paper: 17x)")
    return 0


def _scenarios(args: argparse.Namespace) -> int:
    from . import scenarios

    for name in scenarios.names():
        print(f"{name:24s} {scenarios.get(name).description}")
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="cranepredict",
        description="Faster-than-real-time prediction of a hydraulic crane's booms and load.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = sub.add_parser("demo", help="run the paper's scenario (or another) and report speed")
    demo.add_argument("--scenario", default="paper-fig4", help="scenario name (default: paper-fig4)")
    demo.add_argument("--dt", type=float, default=None, help="RK4 step, s (default: the package default)")
    demo.add_argument("--repeat", type=int, default=201, help="timed repetitions (default: 201)")
    demo.set_defaults(func=_demo)
    lst = sub.add_parser("scenarios", help="list the named scenarios")
    lst.set_defaults(func=_scenarios)
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    try:
        return args.func(args)
    except (ValueError, TypeError) as exc:
        print(f"cranepredict: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
