"""Command line: ``cranepredict demo`` runs the paper's scenario and reports speed."""

from __future__ import annotations

import argparse
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
    """Side view (radial distance from the slew axis vs height) and top view (X, Y: the slew) of
    the crane at a few samples and the tip's path."""
    import os

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pts = traj.points()
    chain = ("pillar_base", "lift_pivot", "tilt_pivot", "extension_mount", "tip")
    fig, (side, top) = plt.subplots(1, 2, figsize=(12, 5.5))
    n = len(traj.t)

    def radial(xyz: np.ndarray, psi: np.ndarray) -> np.ndarray:
        """Signed distance from the slew axis in the boom plane (its outward direction)."""
        return xyz[..., 0] * np.cos(psi) + xyz[..., 1] * np.sin(psi)

    for i, k in enumerate(sorted({0, n // 4, n // 2, 3 * n // 4, n - 1})):
        xyz = np.array([pts[name][k] for name in chain])
        shade = str(0.75 - 0.75 * i / 4)
        label = f"t = {traj.t[k]:.2f} s"
        side.plot(radial(xyz, traj.slew[k]), xyz[:, 2], "o-", color=shade, lw=2, ms=3, label=label)
        top.plot(xyz[:, 0], xyz[:, 1], "o-", color=shade, lw=2, ms=3, label=label)
    side.plot(radial(traj.tip, traj.slew), traj.tip[:, 2], "r-", lw=1, label="tip path")
    top.plot(traj.tip[:, 0], traj.tip[:, 1], "r-", lw=1, label="tip path")
    reach = float(np.max(np.hypot(traj.tip[:, 0], traj.tip[:, 1]))) * 1.1 + 0.5
    arc = np.linspace(float(traj.slew.min()), float(traj.slew.max()), 50)
    top.plot(0.5 * reach * np.cos(arc), 0.5 * reach * np.sin(arc), "b:", lw=1,
             label=f"slew {np.degrees(traj.slew[0]):.0f} -> {np.degrees(traj.slew[-1]):.0f} deg")
    side.set(xlabel="outward from the slew axis (boom plane), m", ylabel="Z (up), m", title="side view")
    top.set(xlabel="X, m", ylabel="Y, m", title="top view", xlim=(-reach, reach), ylim=(-reach, reach))
    for ax in (side, top):
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    top.legend(fontsize=8, loc="lower left")
    fig.suptitle(f"{sc.name} ({traj.backend})")
    fig.tight_layout()
    path = os.path.join(out_dir, f"demo-{sc.name}.png")
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def _scenarios(args: argparse.Namespace) -> int:
    from . import scenarios

    for name in scenarios.names():
        print(f"{name:24s} {scenarios.get(name).description}")
    return 0


def _validate(args: argparse.Namespace) -> int:
    """Every chosen scenario on the fast model (the C core at its default step) and on the
    reference: the planar one (reference.py) where the slew and the extension are held, the
    spatial one (reference_spatial.py) where either moves. Exit status 1 if a scenario misses an
    accuracy target (tip max, tip RMS, chamber-pressure RMS)."""
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
    rows = [reference.compare(sc, dt_ref=dt_ref, backend="c") for sc in chosen]
    if args.plot:
        _plots(rows, args.plot)
    public = [{k: v for k, v in r.items() if not k.startswith("_")} for r in rows]
    missed = [r["name"] for r in public if not r["within_targets"]]
    if args.json:
        print(json.dumps(public, indent=2))
        return 1 if missed else 0

    def f(v, fmt):
        return "-" if v is None else format(v, fmt)

    print(f"fast model: C core, dt {public[0]['dt_fast_s']:g} s; reference: Exudyn, dt {dt_ref:g} s "
          "(planar: slew and extension held; spatial: either moves)")
    print(f"{'scenario':22s} {'ref':>7s} {'max mm':>8s} {'rms mm':>8s} {'pre-stop':>9s} {'post-stop':>9s} "
          f"{'stop s':>6s} {'p rms bar':>9s} {'fast ms':>8s} {'ref s':>6s} {'ratio':>6s} {'targets':>7s}")
    for r in public:
        print(f"{r['name']:22s} {r['reference']:>7s} {r['max_error_mm']:8.3f} {r['rms_error_mm']:8.3f} "
              f"{f(r['max_error_before_stop_mm'], '9.3f'):>9s} {f(r['max_error_after_stop_mm'], '9.3f'):>9s} "
              f"{f(r['first_stop_time_s'], '6.3f'):>6s} {f(r['pressure_rms_bar'], '9.4f'):>9s} "
              f"{r['wall_fast_s'] * 1e3:8.3f} "
              f"{r['wall_reference_s']:6.2f} {r['speed_ratio']:6.0f} {'met' if r['within_targets'] else 'MISSED':>7s}")
    print(f"targets per scenario: max <= {reference.TARGET_MAX_MM:g} mm, RMS <= "
          f"{reference.TARGET_RMS_MM:g} mm, chamber pressures RMS <= "
          f"{reference.TARGET_PRESSURE_RMS_BAR:g} bar (valve drives); speed ratio >= "
          f"{reference.TARGET_SPEED_RATIO:g} (see docs/validation.md)")
    if missed:
        print(f"missed the targets: {', '.join(missed)}")
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


# -- guard: the collision guard's verdict on a scenario (docs/guard.md) ----------------------------

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
        return 0
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
    return 0


def _hull(p: np.ndarray) -> np.ndarray:
    """Convex hull of 2-D points (monotone chain), closed."""
    pts = sorted(map(tuple, p))
    if len(pts) < 3:
        return np.array(pts + pts[:1])

    def half(seq):
        out: list = []
        for q in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (q[1] - out[-2][1]) -
                                     (out[-1][1] - out[-2][1]) * (q[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(q)
        return out

    lower, upper = half(pts), half(pts[::-1])
    ring = lower[:-1] + upper[:-1]
    return np.array(ring + ring[:1])


def _guard_plot(v, sc, out_dir: str, g) -> str:
    import os

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(out_dir, exist_ok=True)
    traj, state, crane = v.trajectory, sc.initial, sc.crane
    views = (("side view", (0, 2), "X, m", "Z (up), m"), ("top view", (1,), "X, m", "Y, m"))
    fig, axes = plt.subplots(1, 2, figsize=(13, 6))
    stop_t = v.stop.latest if v.stop is not None else None
    # per sample (a Trajectory of a frozen slew and extension holds one value of each)
    slews, extensions = (np.broadcast_to(a, traj.t.shape) for a in (traj.slew, traj.extension))

    def at(t):
        """(theta, slew, extension) of the judged motion at t (linear between samples)."""
        th = np.array([np.interp(t, traj.t, traj.theta[:, j]) for j in range(2)])
        return th, float(np.interp(t, traj.t, slews)), float(np.interp(t, traj.t, extensions))

    poses = [(at(0.0), "0.6", "crane at t = 0")]
    if v.contact is not None:
        c = v.contact
        poses.append(((c.theta, c.slew, c.extension), "tab:red", f"at first contact, t = {c.t:.3f} s"))
    if stop_t is not None and stop_t >= 0:
        poses.append((at(stop_t), "tab:orange", f"last stop point, t = {stop_t:.3f} s"))
    every = max(1, len(traj.t) // 80)
    path = [g.part_solids(crane, state, th, slew=ps, extension=e)
            for th, ps, e in zip(traj.theta[::every], slews[::every], extensions[::every])]
    for ax, (title, idx, xl, yl) in zip(axes, views):
        j = idx[-1] if title == "side view" else 1

        def xy(p):
            return p[0], p[j]

        for o in v.world.obstacles:
            s = o.solid()
            if s["kind"] == "plane":
                n = np.asarray(s["b"])
                if title == "side view" and abs(n[2]) > 0.99:
                    ax.axhline(s["a"][2], color="saddlebrown", lw=2, label=o.name)
                continue
            if s["kind"] == "box":
                R = np.array(s["axes"]).reshape(3, 3)
                corners = np.array([np.asarray(s["a"]) + R.T @ (np.array([a, b, c]) * s["half"])
                                    for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)])
                ring = _hull(np.column_stack([corners[:, 0], corners[:, j]]))
                ax.fill(ring[:, 0], ring[:, 1], color="tab:brown", alpha=0.35)
                ax.plot(ring[:, 0], ring[:, 1], color="tab:brown", lw=1)
                ax.annotate(o.name, xy(np.asarray(s["a"])), fontsize=8, ha="center")
            elif s["kind"] == "sphere":
                ax.add_patch(plt.Circle(xy(s["a"]), s["radius"], color="tab:brown", alpha=0.4))
                ax.annotate(o.name, xy(s["a"]), fontsize=8)
            else:
                a, b = np.asarray(s["a"]), np.asarray(s["b"])
                if np.hypot(b[0] - a[0], b[j] - a[j]) < 1e-9:   # seen end-on: a circle
                    ax.add_patch(plt.Circle(xy(a), max(s["radius"], 0.05), color="tab:brown", alpha=0.6))
                    ax.add_patch(plt.Circle(xy(a), s["radius"] + v.margin, fill=False, ls=":",
                                            color="tab:brown"))
                else:
                    ax.plot([a[0], b[0]], [a[j], b[j]], color="tab:brown",
                            lw=max(1.5, 2 * s["radius"] * 20))
                ax.annotate(o.name, xy((a + b) / 2), fontsize=8)
        # the predicted path of each part's far end (the load: its centre)
        for name in v.clearance:
            end = np.array([(p[name]["b"] if p[name]["kind"] == "capsule" else p[name]["a"]) for p in path])
            ax.plot(end[:, 0], end[:, j], lw=0.8, alpha=0.7)
        for (th, ps, e), colour, label in poses:
            solids = g.part_solids(crane, state, th, slew=ps, extension=e)
            first = True
            for s in solids.values():
                a = s["a"]
                if s["kind"] == "capsule":
                    b = s["b"]
                    ax.plot([a[0], b[0]], [a[j], b[j]], color=colour, lw=3, solid_capstyle="round",
                            label=label if first else None)
                else:
                    ax.add_patch(plt.Circle(xy(a), s["radius"] or 0.2, fill=False, color=colour, lw=2))
                first = False
        if v.contact is not None:
            c = v.contact
            ax.plot([c.on_part[0], c.on_obstacle[0]], [c.on_part[j], c.on_obstacle[j]], "k-", lw=1)
            ax.plot(*xy(c.on_part), "kx", ms=10, mew=2, label="first contact (closest points)")
        # frame the crane's reach, not the whole world (a power line may run 60 m)
        reach = np.array([x for p in path for sd in p.values() for x in (sd["a"], sd["b"])])
        lo, hi = reach.min(axis=0) - 2.0, reach.max(axis=0) + 2.0
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[j], hi[j])
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_aspect("equal", adjustable="box")
        ax.grid(True, alpha=0.4)
        ax.set_title(title)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle(f"{sc.name} in {v.world.name}: {v.signal} - {v.reason}", fontsize=9)
    fig.tight_layout()
    path_out = os.path.join(out_dir, f"guard-{sc.name}-{v.world.name}.png")
    fig.savefig(path_out, dpi=90)
    plt.close(fig)
    return path_out


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="cranepredict",
        description="Faster-than-real-time prediction of a hydraulic crane's booms and load.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = sub.add_parser("demo", help="run the paper's scenario (or another) and report speed")
    demo.add_argument("--scenario", default="paper-fig4", help="scenario name (default: paper-fig4)")
    demo.add_argument("--dt", type=float, default=None, help="RK4 step, s (default: the package default)")
    demo.add_argument("--repeat", type=int, default=None,
                      help="timed repetitions (default: 201 on the C core, 3 on the twin)")
    demo.add_argument("--backend", choices=("c", "python"), default=None,
                      help="c (the C core) or python (the twin); default: c, the twin for a scenario "
                           "that moves the slew or the extension while the C core cannot")
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
                                       "future against a world's obstacles")
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
    from .live.cli import add_parsers as _live_parsers

    _live_parsers(sub)
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
