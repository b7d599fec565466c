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

    if args.repeat < 1:
        raise ValueError(f"--repeat must be >= 1 (timed repetitions), got {args.repeat}")
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


def _validate(args: argparse.Namespace) -> int:
    import json

    from . import reference, scenarios

    # Everything that can fail fast is checked before the slow validation starts.
    if not reference.available():
        raise ValueError("validate needs Exudyn: pip install 'cranepredict[reference]'")
    chosen = [scenarios.get(n) for n in (args.scenario or scenarios.names())]
    if args.plot:
        _check_plot_dir(args.plot)
    dt_ref = reference.DEFAULT_REFERENCE_DT if args.dt_ref is None else args.dt_ref
    if not 0.0 < dt_ref <= min(sc.horizon for sc in chosen):
        raise ValueError(f"--dt-ref must be in (0, horizon] s, got {dt_ref:g}")
    rows = [reference.compare(sc, dt_ref=dt_ref) for sc in chosen]
    if args.plot:
        _plots(rows, args.plot)
    public = [{k: v for k, v in r.items() if not k.startswith("_")} for r in rows]
    if args.json:
        print(json.dumps(public, indent=2))
        return 0

    def f(v, fmt):
        return "-" if v is None else format(v, fmt)

    print(f"{'scenario':22s} {'max mm':>8s} {'rms mm':>8s} {'pre-stop':>9s} {'post-stop':>9s} "
          f"{'stop s':>6s} {'fast ms':>8s} {'ref s':>6s} {'ratio':>6s}")
    for r in public:
        print(f"{r['name']:22s} {r['max_error_mm']:8.3f} {r['rms_error_mm']:8.3f} "
              f"{f(r['max_error_before_stop_mm'], '9.3f'):>9s} {f(r['max_error_after_stop_mm'], '9.3f'):>9s} "
              f"{f(r['first_stop_time_s'], '6.3f'):>6s} {r['wall_fast_s'] * 1e3:8.3f} "
              f"{r['wall_reference_s']:6.2f} {r['speed_ratio']:6.0f}")
    print(f"targets per scenario: max <= {reference.TARGET_MAX_MM:g} mm, RMS <= "
          f"{reference.TARGET_RMS_MM:g} mm, ratio >= {reference.TARGET_SPEED_RATIO:g} "
          "(see docs/validation.md)")
    return 0


def _check_plot_dir(out_dir: str) -> None:
    """ValueError unless matplotlib is installed and out_dir is a folder we can write into."""
    import os
    import tempfile

    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise ValueError("--plot needs matplotlib: pip install 'cranepredict[plot]'") from None
    try:
        os.makedirs(out_dir, exist_ok=True)
        with tempfile.TemporaryFile(dir=out_dir):
            pass
    except OSError as exc:
        raise ValueError(f"--plot {out_dir}: cannot write there ({exc.strerror or exc})") from None


def _plots(rows, out_dir: str) -> None:
    import os

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(out_dir, exist_ok=True)
    for r in rows:
        fast, ref, err = r["_fast"], r["_ref"], r["_err"]
        fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
        for traj, style, label in ((fast, "-", "fast model (C)"), (ref, "--", "reference (Exudyn)")):
            radial = np.hypot(traj.tip[:, 0], traj.tip[:, 1])
            ax.plot(radial, traj.tip[:, 2], style, label=label)
        ax.plot(*[np.hypot(fast.tip[0, 0], fast.tip[0, 1]), fast.tip[0, 2]], "ko", label="start")
        ax.set_xlabel("horizontal reach in the boom plane, m")
        ax.set_ylabel("height, m")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True)
        ax.legend()
        ax.set_title(f"{r['name']}: tip path")
        ax2.plot(fast.t, err * 1e3)
        if r["first_stop_time_s"] is not None:
            ax2.axvline(r["first_stop_time_s"], color="r", ls=":", label="first end stop")
            ax2.legend()
        ax2.set_xlabel("t, s")
        ax2.set_ylabel("tip error |fast - reference|, mm")
        ax2.grid(True)
        ax2.set_title(f"max {r['max_error_mm']:.3f} mm, RMS {r['rms_error_mm']:.3f} mm")
        fig.tight_layout()
        fig.savefig(os.path.join(out_dir, f"{r['name']}.png"), dpi=90)
        plt.close(fig)


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
    val = sub.add_parser("validate", help="run the scenario suite on the fast model and the Exudyn "
                                          "reference and compare the tip (needs the [reference] extra)")
    val.add_argument("--json", action="store_true", help="print the results as JSON")
    val.add_argument("--plot", metavar="DIR", default=None,
                     help="write a tip-path and error plot per scenario (needs the [plot] extra)")
    val.add_argument("--scenario", action="append", default=None,
                     help="run only this scenario (repeatable; default: all)")
    val.add_argument("--dt-ref", type=float, default=None,
                     help="reference step, s (default: cranepredict.reference.DEFAULT_REFERENCE_DT, 2.5e-4)")
    val.set_defaults(func=_validate)
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
    except KeyboardInterrupt:
        print("cranepredict: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
