"""Command line: ``cranepredict demo`` runs the paper's scenario and reports speed."""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from typing import List, Optional

import numpy as np


_ACTUATORS = ("lift cylinder", "tilt cylinder", "slew drive", "extension cylinder")


def _demo(args: argparse.Namespace) -> int:
    from . import api, scenarios
    from .types import JOINTS

    if args.repeat is not None and args.repeat < 1:
        raise ValueError(f"--repeat must be >= 1 (timed repetitions), got {args.repeat}")
    sc = scenarios.get(args.scenario)
    if args.plot:
        _check_plot_dir(args.plot)
    dt = args.dt if args.dt is not None else api.DEFAULT_DT
    backend = args.backend or "c"
    traj = api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt, backend=backend)
    repeat = args.repeat if args.repeat is not None else (201 if backend == "c" else 3)
    walls = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt, backend=backend)
        walls.append(time.perf_counter() - t0)
    wall = statistics.median(walls)
    deg = np.degrees
    print(f"scenario   {sc.name}: {sc.description}")
    print(f"crane      {sc.crane.name}, load {sc.crane.load_mass:g} kg, horizon {sc.horizon:g} s, "
          f"dt {dt:g} s ({len(traj.t)} samples)")
    print(f"backend    {'C core' if backend == 'c' else 'twin (pure Python)'}")
    for k, word in ((0, "start"), (-1, "end  ")):
        x, y, z = traj.tip[k]
        print(f"tip {word}  x {x:7.3f} m  y {y:7.3f} m  z {z:7.3f} m   "
              f"(lift {deg(traj.theta[k, 0]):6.1f} deg, tilt {deg(traj.theta[k, 1]):6.1f} deg, "
              f"slew {deg(traj.slew[k]):6.1f} deg, extension {traj.extension[k]:5.3f} m)")
    for j, name in enumerate(_ACTUATORS):
        for side, word in ((+1, "upper"), (-1, "lower")):
            t_stop = traj.first_stop_time(j, side)
            if t_stop is not None:
                print(f"end stop   {name} reached its {word} stop at t = {t_stop:.3f} s")
    if not traj.stop.any():
        print("end stop   none reached")
    for j, joint in enumerate(JOINTS):
        if hasattr(getattr(sc.inputs, joint), "u"):   # valve-driven: the pressures are results
            print(f"pressures  {joint}: p_a {traj.p_a[0, j] / 1e5:6.1f} -> {traj.p_a[-1, j] / 1e5:6.1f} bar, "
                  f"p_b {traj.p_b[0, j] / 1e5:6.1f} -> {traj.p_b[-1, j] / 1e5:6.1f} bar "
                  f"(max {max(traj.p_a[:, j].max(), traj.p_b[:, j].max()) / 1e5:.1f} bar)")
    print(f"speed      {wall * 1e6:.0f} us per prediction (median of {repeat}): "
          f"{sc.horizon / wall:,.0f}x faster than real time (the paper: 17x)")
    if args.plot:
        print(f"plot       {_demo_plot(sc, traj, args.plot)}")
    return 0


def _demo_plot(sc, traj, out_dir: str) -> str:
    """Side and top views of the motion (plot.py)."""
    from . import plot

    return plot.demo_plot(sc, traj, out_dir)


def _scenarios(args: argparse.Namespace) -> int:
    from . import scenarios

    for name in scenarios.names():
        print(f"{name:24s} {scenarios.get(name).description}")
    return 0


def _validate(args: argparse.Namespace) -> int:
    """Every chosen scenario on the fast model (the C core at its default step) and on the
    reference: the planar one (reference.py) where the slew and the extension are held, the
    spatial one (reference_spatial.py) where either moves (validation.py compares them). Exit
    status 1 if a scenario misses an accuracy target (tip max, tip RMS, chamber-pressure RMS)."""
    import json

    from . import reference, scenarios, validation

    # Everything that can fail fast is checked before the slow validation starts.
    if not reference.available():
        raise ValueError("validate needs Exudyn: pip install 'cranepredict[reference]'")
    chosen = [scenarios.get(n) for n in (args.scenario or scenarios.names())]
    if args.plot:
        _check_plot_dir(args.plot)
    dt_ref = reference.DEFAULT_REFERENCE_DT if args.dt_ref is None else args.dt_ref
    if not 0.0 < dt_ref <= min(sc.horizon for sc in chosen):
        raise ValueError(f"--dt-ref must be in (0, horizon] s, got {dt_ref:g}")
    rows = validation.compare_all(chosen, dt_ref=dt_ref, backend="c")
    if args.plot:
        _plots(rows, args.plot)
    public = [{k: v for k, v in r.items() if not k.startswith("_")} for r in rows]
    missed = [r["name"] for r in public if not r["within_targets"]]
    if args.json:
        print(json.dumps(public, indent=2))
    else:
        print("\n".join(validation.table(public, dt_ref)))
    return 1 if missed else 0


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
    """A tip-path and error plot per scenario (plot.py)."""
    from . import plot

    plot.validate_plots(rows, out_dir)


# -- guard: the collision guard's verdict on a scenario (docs/guard.md) ----------------------------

#: The exit status of ``cranepredict guard`` per verdict, so that a script can branch on it; 2
#: stays a usage or input error and 130 an interrupt, as for every command.
GUARD_EXIT = {"GO": 0, "WARN": 3, "STOP": 4}


def _guard(args: argparse.Namespace) -> int:
    import importlib
    import json
    import os

    from . import scenarios, world as world_mod

    g = importlib.import_module("cranepredict.guard")
    if args.plot:
        _check_plot_dir(args.plot)   # before the prediction, not after
    if os.path.exists(args.world):
        world = world_mod.World.from_toml(args.world)
    elif args.world in world_mod.names():
        world = world_mod.get(args.world)
    else:
        raise ValueError(f"--world: no such file, and not an example world ({', '.join(world_mod.names())}): "
                         f"{args.world!r}")
    sc = scenarios.get(args.scenario)
    horizon = sc.horizon if args.horizon is None else args.horizon
    v = g.guard(sc.crane, world, sc.initial, sc.inputs, horizon, reaction=args.reaction,
                cycle=args.cycle)
    if args.plot:
        path = _guard_plot(v, sc, args.plot, g)
    if args.json:
        d = v.to_dict()
        d["scenario"] = sc.name
        print(json.dumps(d, indent=2))
        return GUARD_EXIT[v.signal]
    print(f"world      {world.name}: {world.description} (margin {v.margin:g} m, "
          f"{len(world.obstacles)} obstacles)")
    print(f"scenario   {sc.name}: {sc.description} (horizon {horizon:g} s)")
    print(f"signal     {v.signal}: {v.reason}")
    print("min clearance over the horizon, per part:")
    for name, c in v.clearance.items():
        mark = "  <= margin" if c <= v.margin else ""
        print(f"  {name:16s} {c:8.3f} m{mark}")
    c = v.contact
    if c is not None:
        fmt = ", ".join
        print(f"contact    t = {c.t:.4f} s: {c.part} - {c.obstacle}, clearance {c.clearance:.4f} m, "
              f"at ({fmt(f'{x:.3f}' for x in c.on_part)}) - ({fmt(f'{x:.3f}' for x in c.on_obstacle)}) m")
        print("levers     " + ", ".join(f"{j} {c.approach[j]:+.3f} m/s" for j in c.approach) +
              f" (d clearance/dt from each joint; closing: {fmt(c.closing) or 'none'})")
        print(f"stop       begin by t = {v.stop.latest:.4f} s (reaction {v.stop.reaction:g} s); "
              f"{v.stop.note}")
    if args.plot:
        print(f"plot       {path}")
    return GUARD_EXIT[v.signal]


def _guard_plot(v, sc, out_dir: str, g) -> str:
    """Side and top views of the verdict (plot.py)."""
    from . import plot

    return plot.guard_plot(v, sc, out_dir, g)


# -- sweep: an uncertainty study (docs/sweep.md) ---------------------------------------------------

def _sweep(args: argparse.Namespace) -> int:
    import json
    import os

    from . import uncertainty

    if args.plot:
        _check_plot_dir(os.path.dirname(os.path.abspath(args.plot)))
    study = uncertainty.load_study(args.spec).with_run(args.samples, args.seed)
    out = args.out if args.out is not None else f"sweep-{study.name}"
    scheduler = "in-process" if args.in_process else args.scheduler
    if scheduler is None and not uncertainty.has_dask():
        print("cranepredict: Dask is not installed (the [sweep] extra): running in this process",
              file=sys.stderr)
        scheduler = "in-process"
    result = uncertainty.sweep(study, out=out, scheduler=scheduler, workers=args.workers,
                               progress=not args.json and sys.stderr.isatty())
    if args.plot:
        result.plot(args.plot)
    if args.json:
        d = result.summary.to_dict()
        d.update(study=study.name, out=str(result.out), seconds=result.seconds,
                 computed_chunks=result.computed_chunks, where=result.where)
        print(json.dumps(d, indent=2))
        return 0
    reused = study.n_chunks - result.computed_chunks
    print(f"study      {study.name}" + (f": {study.description}" if study.description else ""))
    print(f"samples    {study.samples:,} (seed {study.seed}, {study.n_chunks} chunks of "
          f"{study.chunk}); uncertain: {', '.join(study.parameters) or 'none'}")
    print(result.summary.text())
    computed = result.computed_futures
    rate = f", {computed / result.chunk_seconds:,.0f} futures/s" if computed else ""
    print(f"ran        {result.computed_chunks} chunks {result.where}: {result.chunk_seconds:.1f} s "
          f"of chunks{rate}, {result.seconds:.1f} s in all"
          + (f"; {reused} chunks were already in {out}" if reused else ""))
    print(f"table      {out}/chunk-*.npz, summary {out}/summary.json")
    if args.plot:
        print(f"plot       {args.plot}")
    return 0


def _view(args: argparse.Namespace) -> int:
    from .view import app

    return app.run(args)


def _fmu(args: argparse.Namespace) -> int:
    from .crane import Crane
    from .fmu import export_fmu

    crane = Crane.patu655() if args.crane in (None, "patu655") else Crane.from_toml(args.crane)
    start = {}
    for item in args.start or []:
        name, sep, value = item.partition("=")
        if not sep:
            raise ValueError(f"--start takes NAME=VALUE (e.g. lift_stroke=0.116), got {item!r}")
        try:
            start[name] = float(value)
        except ValueError:
            raise ValueError(f"--start {name}: {value!r} is not a number") from None
    levers = None if args.levers is None else [j for j in args.levers.split(",") if j]
    world = None
    if args.world is not None:
        from . import world as world_mod
        if os.path.exists(args.world):
            world = world_mod.World.from_toml(args.world)
        elif args.world in world_mod.names():
            world = world_mod.get(args.world)
        else:
            raise ValueError(f"--world: no such file, and not an example world "
                             f"({', '.join(world_mod.names())}): {args.world!r}")
    try:
        path = export_fmu(crane, args.output, fmi=args.fmi, drive=args.drive, levers=levers,
                          start=start, step=args.step,
                          crane_file=None if args.crane in (None, "patu655") else args.crane,
                          world=world, guard_horizon=args.guard_horizon)
    except (RuntimeError, ImportError) as exc:
        print(f"cranepredict: error: {exc}", file=sys.stderr)
        return 2
    print(f"wrote {path} (FMI {args.fmi}.0 co-simulation, crane {crane.name}, "
          f"{args.drive} drive)")
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="cranepredict",
        description="Faster-than-real-time prediction of a hydraulic crane's booms and load.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = sub.add_parser("demo", help="run the paper's scenario (or another) and report speed")
    demo.add_argument("--scenario", default="paper-fig4", help="scenario name (default: paper-fig4)")
    demo.add_argument("--dt", type=float, default=None,
                      help="sample interval, s (the default method steps as its accuracy needs; "
                           "default: the package default)")
    demo.add_argument("--repeat", type=int, default=None,
                      help="timed repetitions (default: 201 on the C core, 3 on the twin)")
    demo.add_argument("--backend", choices=("c", "python"), default=None,
                      help="c (the C core) or python (the twin); default: c")
    demo.add_argument("--plot", metavar="DIR", default=None,
                      help="write side and top views of the motion (needs the [plot] extra)")
    demo.set_defaults(func=_demo)
    val = sub.add_parser("validate", help="run the scenario suite on the fast model (C core, default "
                                          "step) and the Exudyn reference (planar, or spatial where the "
                                          "slew or the extension moves) and compare the tip and the "
                                          "chamber pressures (needs the [reference] extra)")
    val.add_argument("--json", action="store_true", help="print the results as JSON")
    val.add_argument("--plot", metavar="DIR", default=None,
                     help="write a tip-path and error plot per scenario (needs the [plot] extra)")
    val.add_argument("--scenario", action="append", default=None,
                     help="run only this scenario (repeatable; default: all)")
    val.add_argument("--dt-ref", type=float, default=None,
                     help="reference step, s (default: cranepredict.reference.DEFAULT_REFERENCE_DT, 2.5e-4)")
    val.set_defaults(func=_validate)
    grd = sub.add_parser("guard", help="the collision guard's verdict (GO/WARN/STOP) on a scenario's "
                                       "future against a world's obstacles",
                         epilog="exit status: 0 GO, 3 WARN, 4 STOP, 2 bad input")
    grd.add_argument("--world", required=True,
                     help="world file (TOML), or an example world's name (wall, cab, power-line, building-edge)")
    grd.add_argument("--scenario", default="paper-fig4", help="scenario name (default: paper-fig4)")
    grd.add_argument("--horizon", type=float, default=None, help="s (default: the scenario's)")
    grd.add_argument("--reaction", type=float, default=0.2,
                     help="delay from the stop decision to the stop, s (default: 0.2)")
    grd.add_argument("--cycle", type=float, default=0.01, help="control cycle, s (default: 0.01)")
    grd.add_argument("--json", action="store_true", help="print the verdict as JSON")
    grd.add_argument("--plot", metavar="DIR", default=None,
                     help="write side and top views (needs the [plot] extra)")
    grd.set_defaults(func=_guard)
    vw = sub.add_parser("view", help="the operator's display in a browser: the crane now, where it "
                                     "will be and the guard's verdict (needs the [view] extra)")
    vw.add_argument("--scenario", default=None, help="scenario name (default: paper-fig4)")
    vw.add_argument("--replay", metavar="LOG", default=None,
                    help="a recorded CAN log (.blf, .asc, .log) through the live twin, with a "
                         "timeline over its cycles (needs the [live] extra)")
    vw.add_argument("--crane", default=None,
                    help="--replay: the twin's crane file (TOML; default: the PATU 655)")
    vw.add_argument("--world", default="wall",
                    help="world file (TOML), or an example world's name (default: wall)")
    vw.add_argument("--horizon", type=float, default=None,
                    help="s (default: the scenario's; 2 in a replay)")
    vw.add_argument("--reaction", type=float, default=0.2,
                    help="delay from the stop decision to the stop, s (default: 0.2)")
    vw.add_argument("--cycle", type=float, default=0.01, help="control cycle, s (default: 0.01)")
    vw.add_argument("--ghosts", type=int, default=4, help="future poses drawn (default: 4)")
    vw.add_argument("--host", default="127.0.0.1",
                    help="address to listen on (default: 127.0.0.1, this machine only; 0.0.0.0: "
                         "every network of this machine)")
    vw.add_argument("--port", type=int, default=8080, help="port (default: 8080; 0: any free one)")
    vw.add_argument("--serve-for", type=float, default=None, metavar="S",
                    help="stop after S seconds (default: serve until Ctrl-C)")
    vw.set_defaults(func=_view)
    fmu = sub.add_parser("fmu", help="export the crane as an FMI co-simulation FMU (compiled with "
                                     "this machine's C compiler; needs the [fmu] extra)")
    fmu.add_argument("--crane", default="patu655",
                     help="crane file (TOML), or patu655 (default)")
    fmu.add_argument("--fmi", type=int, choices=(3, 2), default=3, help="FMI version (default: 3)")
    fmu.add_argument("--drive", choices=("valve", "pressure"), default="valve",
                     help="inputs: the valves' levers (default) or the lift and tilt cylinders' "
                          "chamber pressures (the paper's experiment)")
    fmu.add_argument("--levers", default=None, metavar="JOINTS",
                     help="comma-separated joints given a lever, e.g. lift,tilt (default: every "
                          "actuator with a valve circuit; the others are held)")
    fmu.add_argument("--start", action="append", default=None, metavar="NAME=VALUE",
                     help="default initial pose: lift_stroke, tilt_stroke (m), slew (rad), "
                          "extension (m) (repeatable; the FMU's *_start parameters)")
    fmu.add_argument("--step", type=float, default=5e-3,
                     help="default of the FMU's step parameter, the core's RK4 step, s (default: 0.005)")
    fmu.add_argument("--world", default=None,
                     help="world file (TOML) or an example world's name: the FMU also outputs the "
                          "collision guard's verdict (guard_signal, time_to_contact, "
                          "min_clearance, stop_latest)")
    fmu.add_argument("--guard-horizon", type=float, default=2.0,
                     help="with --world: how far ahead the guard predicts, s (default: 2)")
    fmu.add_argument("-o", "--output", required=True, help="the .fmu file to write")
    fmu.set_defaults(func=_fmu)
    from .live.cli import add_parsers as _live_parsers

    _live_parsers(sub)
    sw = sub.add_parser("sweep", help="an uncertainty study: how often the guard's verdict for the "
                                      "nominal crane misses a contact the real crane makes, over "
                                      "sampled loads, friction, pressures and sensor offsets "
                                      "(Dask: the [sweep] extra)")
    sw.add_argument("spec", metavar="SPEC",
                    help="study file (TOML), or an example study's name (power-line-load)")
    sw.add_argument("--samples", type=int, default=None, help="samples (default: the file's)")
    sw.add_argument("--seed", type=int, default=None, help="seed (default: the file's)")
    sw.add_argument("--out", metavar="DIR", default=None,
                    help="folder of the chunks and the summary (default: sweep-NAME); run again "
                         "with the same folder to resume")
    where = sw.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDR", default=None,
                       help="a Dask scheduler's address, e.g. tcp://host:8786 (default: a "
                            "LocalCluster on this machine)")
    where.add_argument("--in-process", action="store_true", help="run in this process, no Dask")
    sw.add_argument("--workers", type=int, default=None,
                    help="the LocalCluster's worker processes (default: the cores)")
    sw.add_argument("--plot", metavar="PNG", default=None,
                    help="write the summary's figure (needs the [plot] extra)")
    sw.add_argument("--json", action="store_true", help="print the summary as JSON")
    sw.set_defaults(func=_sweep)
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
