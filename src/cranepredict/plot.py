"""The static figures of the command line (the ``[plot]`` extra: matplotlib), written as PNG files.

``demo_plot``: side and top views of a scenario's motion; ``guard_plot``: the guard's verdict in
side and top views with the obstacles near the crane; ``validate_plots``: the fast model's tip
path against the reference's and the error; ``sweep_plot``: an uncertainty study's summary. Each view is framed on what it shows (at least
``MIN_SPAN`` across, so that a view without motion is not magnified to rounding noise) and each
obstacle is drawn only in the views where it is near the crane's path.
"""

from __future__ import annotations

import os
import textwrap
from typing import Any, Dict, Iterable, List, Sequence, Tuple

import numpy as np

__all__ = ["demo_plot", "guard_plot", "demo_figure", "guard_figure", "validate_plots", "sweep_plot",
           "sweep_figure", "fit",
           "near_in_depth", "tip_view",
           "MIN_SPAN", "NEAR"]

#: The smallest extent a view shows, m.
MIN_SPAN = 1.0
#: An obstacle is drawn in a view when it comes within this distance (m) of the crane's path
#: along the view's depth (Y for the side view, Z for the top view).
NEAR = 2.0
_OBSTACLE_COLOURS = ("saddlebrown", "olive", "teal", "slateblue", "darkgoldenrod", "rosybrown",
                     "darkcyan", "sienna", "dimgray", "purple")


def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def fit(ax: Any, x: Iterable[float], y: Iterable[float], pad: float = 0.5,
        min_span: float = MIN_SPAN) -> Tuple[Tuple[float, float], Tuple[float, float]]:
    """Frames ax on the points (x, y) with ``pad`` m around them and at least ``min_span`` m
    across each axis (equal scales). Returns the limits."""
    lims = _limits(x, y, pad, min_span)
    ax.set_xlim(*lims[0])
    ax.set_ylim(*lims[1])
    ax.set_aspect("equal", adjustable="box")
    return lims[0], lims[1]


def _limits(x: Iterable[float], y: Iterable[float], pad: float,
            min_span: float) -> List[Tuple[float, float]]:
    lims = []
    for v in (np.asarray(list(x), dtype=float), np.asarray(list(y), dtype=float)):
        lo, hi = float(np.min(v)) - pad, float(np.max(v)) + pad
        if hi - lo < min_span:
            mid = 0.5 * (lo + hi)
            lo, hi = mid - 0.5 * min_span, mid + 0.5 * min_span
        lims.append((lo, hi))
    return lims


def _wrap(text: str, width: int = 110) -> str:
    return "\n".join(textwrap.wrap(text, width))


# -- demo ------------------------------------------------------------------------------------------

_CHAIN = ("pillar_base", "lift_pivot", "tilt_pivot", "extension_mount", "tip")


def demo_plot(sc: Any, traj: Any, out_dir: str) -> str:
    """Side view (outward from the slew axis in the boom plane vs height) and top view (X, Y) of
    the crane at five samples and the tip's path; returns the file written."""
    plt = _plt()
    fig = demo_figure(sc, traj)
    path = os.path.join(out_dir, f"demo-{sc.name}.png")
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def demo_figure(sc: Any, traj: Any) -> Any:
    """The figure of :func:`demo_plot` (a matplotlib Figure; close it after use)."""
    plt = _plt()
    pts = traj.points()
    n = len(traj.t)
    slew = np.broadcast_to(traj.slew, traj.t.shape)
    fig, (side, top) = plt.subplots(1, 2, figsize=(12, 5.5))

    def radial(xyz: np.ndarray, psi: np.ndarray) -> np.ndarray:
        """Signed distance from the slew axis in the boom plane (its outward direction)."""
        return xyz[..., 0] * np.cos(psi) + xyz[..., 1] * np.sin(psi)

    chain = np.stack([pts[name] for name in _CHAIN], axis=1)          # (N, 5, 3)
    for i, k in enumerate(sorted({0, n // 4, n // 2, 3 * n // 4, n - 1})):
        xyz = chain[k]
        shade = str(0.75 - 0.75 * i / 4)
        label = f"t = {traj.t[k]:.2f} s"
        side.plot(radial(xyz, slew[k]), xyz[:, 2], "o-", color=shade, lw=2, ms=3, label=label)
        top.plot(xyz[:, 0], xyz[:, 1], "o-", color=shade, lw=2, ms=3, label=label)
    side.plot(radial(traj.tip, slew), traj.tip[:, 2], "r-", lw=1, label="tip path")
    top.plot(traj.tip[:, 0], traj.tip[:, 1], "r-", lw=1, label="tip path")
    if np.ptp(slew) > 0:
        r_arc = 0.5 * float(np.max(np.hypot(traj.tip[:, 0], traj.tip[:, 1])))
        arc = np.linspace(float(slew.min()), float(slew.max()), 50)
        top.plot(r_arc * np.cos(arc), r_arc * np.sin(arc), "b:", lw=1,
                 label=f"slew {np.degrees(slew[0]):.0f} -> {np.degrees(slew[-1]):.0f} deg")
    # frame every point of the crane at every sample (a folded boom reaches beyond its tip)
    rad = radial(chain, slew[:, None])
    fit(side, rad.ravel(), chain[..., 2].ravel())
    fit(top, chain[..., 0].ravel(), chain[..., 1].ravel())
    side.set(xlabel="outward from the slew axis (boom plane), m", ylabel="Z (up), m",
             title="side view (in the boom plane)")
    top.set(xlabel="X, m", ylabel="Y, m", title="top view")
    for ax in (side, top):
        ax.grid(alpha=0.3)
    fig.legend(*top.get_legend_handles_labels(), loc="lower center", ncol=4, fontsize=8,
               frameon=False)
    fig.suptitle(f"{sc.name} ({traj.backend})")
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return fig


# -- guard -----------------------------------------------------------------------------------------

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


def _extent(s: dict, axis: int) -> Tuple[float, float]:
    """The obstacle solid's extent along a world axis (0 X, 1 Y, 2 Z), m."""
    kind = s["kind"]
    if kind == "plane":
        n = np.asarray(s["b"], dtype=float)
        if abs(n[axis]) > 0.999:                 # the plane is across this axis: below it is solid
            a = float(s["a"][axis])
            return (-np.inf, a) if n[axis] > 0 else (a, np.inf)
        return (-np.inf, np.inf)
    if kind == "box":
        R = np.array(s["axes"], dtype=float).reshape(3, 3)
        half = float(np.sum(np.abs(R[:, axis]) * np.asarray(s["half"], dtype=float)))
        c = float(s["a"][axis])
        return (c - half, c + half)
    a = float(s["a"][axis])
    b = float(s["b"][axis]) if kind != "sphere" else a
    r = float(s["radius"])
    return (min(a, b) - r, max(a, b) + r)


def near_in_depth(s: dict, axis: int, lo: float, hi: float, near: float = NEAR) -> bool:
    """Whether an obstacle solid comes within ``near`` m of [lo, hi] along a world axis."""
    a, b = _extent(s, axis)
    return b >= lo - near and a <= hi + near


def guard_plot(v: Any, sc: Any, out_dir: str, g: Any) -> str:
    """The guard's verdict: side (X, Z) and top (X, Y) views of the crane now, at the first
    contact and at the latest stop point, each part's predicted path, and the obstacles near the
    crane's path in each view; returns the file written."""
    plt = _plt()
    os.makedirs(out_dir, exist_ok=True)
    fig = guard_figure(v, sc, g)
    path_out = os.path.join(out_dir, f"guard-{sc.name}-{v.world.name}.png")
    fig.savefig(path_out, dpi=90)
    plt.close(fig)
    return path_out


def guard_figure(v: Any, sc: Any, g: Any) -> Any:
    """The figure of :func:`guard_plot` (a matplotlib Figure; close it after use)."""
    plt = _plt()
    traj, state, crane = v.trajectory, sc.initial, sc.crane
    views = (("side view", 2, "X, m", "Z (up), m", 1), ("top view", 1, "X, m", "Y, m", 2))
    fig, axes = plt.subplots(1, 2, figsize=(13, 6.5))
    stop_t = v.stop.latest if v.stop is not None else None
    slews, extensions = (np.broadcast_to(a, traj.t.shape) for a in (traj.slew, traj.extension))

    def at(t):
        """(theta, slew, extension) of the judged motion at t (linear between samples)."""
        th = np.array([np.interp(t, traj.t, traj.theta[:, j]) for j in range(2)])
        return th, float(np.interp(t, traj.t, slews)), float(np.interp(t, traj.t, extensions))

    poses = [(at(0.0), "0.6", "crane at t = 0")]
    if v.contact is not None:
        c = v.contact
        poses.append(((c.theta, c.slew, c.extension), "tab:red", f"at first contact, t = {c.t:.3f} s"))
    if stop_t is not None and np.isfinite(stop_t) and stop_t >= 0:
        poses.append((at(stop_t), "tab:orange", f"latest stop point, t = {stop_t:.3f} s"))
    if v.contact is None:
        poses.append((at(float(traj.t[-1])), "tab:blue", f"crane at t = {traj.t[-1]:.2f} s"))
    every = max(1, len(traj.t) // 80)
    path = [g.part_solids(crane, state, th, slew=ps, extension=e)
            for th, ps, e in zip(traj.theta[::every], slews[::every], extensions[::every])]
    # the crane's swept box (parts' ends grown by their radii): what "near" is measured from
    ends = np.array([x for p in path for sd in p.values() for x in (sd["a"], sd["b"])])
    grow = max(sd["radius"] for p in path for sd in p.values())
    lo_all, hi_all = ends.min(axis=0) - grow, ends.max(axis=0) + grow
    colour = {o.name: _OBSTACLE_COLOURS[i % len(_OBSTACLE_COLOURS)]
              for i, o in enumerate(v.world.obstacles)}
    left_out: Dict[str, List[str]] = {}
    for ax, (title, j, xl, yl, depth) in zip(axes, views):

        def xy(p):
            return p[0], p[j]

        frame_x, frame_y = _limits([lo_all[0] - 1.5, hi_all[0] + 1.5],
                                   [lo_all[j] - 1.5, hi_all[j] + 1.5], 0.0, MIN_SPAN)
        for o in v.world.obstacles:
            s = o.solid()
            col = colour[o.name]
            ex, ey = _extent(s, 0), _extent(s, j)
            in_frame = (ex[1] >= frame_x[0] and ex[0] <= frame_x[1] and
                        ey[1] >= frame_y[0] and ey[0] <= frame_y[1])
            if not (in_frame and near_in_depth(s, depth, lo_all[depth], hi_all[depth])):
                left_out.setdefault(title, []).append(o.name)
                continue
            if s["kind"] == "plane":
                n = np.asarray(s["b"])
                if abs(n[j]) > 0.99:            # seen edge-on: a line with the solid below
                    ax.axhline(s["a"][j], color=col, lw=2, label=o.name)
                continue
            if s["kind"] == "box":
                R = np.array(s["axes"]).reshape(3, 3)
                corners = np.array([np.asarray(s["a"]) + R.T @ (np.array([a, b, c]) * s["half"])
                                    for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)])
                ring = _hull(np.column_stack([corners[:, 0], corners[:, j]]))
                ax.fill(ring[:, 0], ring[:, 1], color=col, alpha=0.35, label=o.name)
                ax.plot(ring[:, 0], ring[:, 1], color=col, lw=1)
            elif s["kind"] == "sphere":
                ax.add_patch(plt.Circle(xy(s["a"]), s["radius"], color=col, alpha=0.5, label=o.name))
            else:
                a, b = np.asarray(s["a"]), np.asarray(s["b"])
                if np.hypot(b[0] - a[0], b[j] - a[j]) < 1e-9:   # seen end-on: a circle
                    ax.add_patch(plt.Circle(xy(a), max(s["radius"], 0.05), color=col, alpha=0.8,
                                            label=o.name))
                    ax.add_patch(plt.Circle(xy(a), s["radius"] + v.margin, fill=False, ls=":",
                                            color=col))
                else:
                    ax.plot([a[0], b[0]], [a[j], b[j]], color=col, label=o.name,
                            lw=max(1.5, 2 * s["radius"] * 20), solid_capstyle="butt")
        # the predicted path of each part's far end (the load: its centre)
        for name in v.clearance:
            end = np.array([(p[name]["b"] if p[name]["kind"] == "capsule" else p[name]["a"])
                            for p in path])
            ax.plot(end[:, 0], end[:, j], lw=0.7, alpha=0.5, color="0.4")
        for (th, ps, e), pose_colour, label in poses:
            solids = g.part_solids(crane, state, th, slew=ps, extension=e)
            first = True
            for s in solids.values():
                a = s["a"]
                if s["kind"] == "capsule":
                    b = s["b"]
                    ax.plot([a[0], b[0]], [a[j], b[j]], color=pose_colour, lw=3,
                            solid_capstyle="round", label=label if first else None)
                else:
                    ax.add_patch(plt.Circle(xy(a), s["radius"] or 0.2, fill=False,
                                            color=pose_colour, lw=2, label=label if first else None))
                first = False
        if v.contact is not None:
            c = v.contact
            ax.plot([c.on_part[0], c.on_obstacle[0]], [c.on_part[j], c.on_obstacle[j]], "k-", lw=1)
            ax.plot(*xy(c.on_part), "kx", ms=10, mew=2, label="first contact (closest points)")
        # frame the crane's reach, not the whole world (a power line may run 60 m)
        fit(ax, frame_x, frame_y, pad=0.0)
        ax.set(xlabel=xl, ylabel=yl, title=title)
        ax.grid(True, alpha=0.4)
        if left_out.get(title):
            ax.text(0.01, 0.01, _wrap("not drawn (outside this view, or more than "
                                      f"{NEAR:g} m along {'YZ'[depth - 1]} from the crane's path): "
                                      + ", ".join(left_out[title]), 70),
                    transform=ax.transAxes, fontsize=7, va="bottom", color="0.3")
    # one legend for both views, below them: no name is written over the drawing
    handles: Dict[str, Any] = {}
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles.keys()), loc="lower center",
               ncol=min(5, len(handles)), fontsize=8, frameon=False)
    fig.suptitle(_wrap(f"{sc.name} in {v.world.name}: {v.signal} - {v.reason}"), fontsize=9)
    rows = (len(handles) + 4) // 5
    fig.tight_layout(rect=(0, 0.035 * rows + 0.02, 1, 1))
    return fig


# -- validate --------------------------------------------------------------------------------------

def tip_view(tip: np.ndarray, slew: Any = 0.0) -> str:
    """Which view shows a tip path: "boom plane" (outward from the slew axis vs height) unless the
    path moves less in that plane than across it (a slew), then "top" (X, Y)."""
    tip = np.asarray(tip, dtype=float)
    psi = np.broadcast_to(np.asarray(slew, dtype=float), tip.shape[:1])
    radial = tip[:, 0] * np.cos(psi) + tip[:, 1] * np.sin(psi)
    in_plane = max(np.ptp(radial), np.ptp(tip[:, 2]))
    across = max(np.ptp(tip[:, 0]), np.ptp(tip[:, 1]))
    return "top" if in_plane < 0.2 * across else "boom plane"


def validate_plots(rows: Sequence[dict], out_dir: str) -> List[str]:
    """Per scenario: the tip paths of the fast model and the reference in the view that shows the
    motion (:func:`tip_view`), and the tip error over time; returns the files written."""
    plt = _plt()
    os.makedirs(out_dir, exist_ok=True)
    written = []
    for r in rows:
        fast, ref, err = r["_fast"], r["_ref"], r["_err"]
        fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
        view = tip_view(fast.tip, fast.slew)
        xs, ys = [], []
        for traj, style, label in ((fast, "-", "fast model (C)"), (ref, "--", "reference (Exudyn)")):
            if view == "top":
                x, y = traj.tip[:, 0], traj.tip[:, 1]
            else:
                psi = np.broadcast_to(np.asarray(traj.slew, dtype=float), traj.t.shape)
                x = traj.tip[:, 0] * np.cos(psi) + traj.tip[:, 1] * np.sin(psi)
                y = traj.tip[:, 2]
            ax.plot(x, y, style, label=label)
            xs.append(x)
            ys.append(y)
        ax.plot(xs[0][0], ys[0][0], "ko", label="start")
        fit(ax, np.concatenate(xs), np.concatenate(ys), pad=0.1, min_span=0.5)
        if view == "top":
            ax.set(xlabel="X, m", ylabel="Y, m", title=f"{r['name']}: tip path (top view)")
        else:
            ax.set(xlabel="outward from the slew axis (boom plane), m", ylabel="height, m",
                   title=f"{r['name']}: tip path (boom plane)")
        ax.grid(True)
        fig.legend(*ax.get_legend_handles_labels(), loc="lower left", ncol=3, fontsize=8,
                   frameon=False)
        ax2.plot(fast.t, err * 1e3)
        if r["first_stop_time_s"] is not None:
            ax2.axvline(r["first_stop_time_s"], color="r", ls=":", label="first end stop")
            ax2.legend()
        ax2.set_xlabel("t, s")
        ax2.set_ylabel("tip error |fast - reference|, mm")
        ax2.grid(True)
        ax2.set_title(f"max {r['max_error_mm']:.3f} mm, RMS {r['rms_error_mm']:.3f} mm")
        fig.tight_layout(rect=(0, 0.06, 1, 1))
        path = os.path.join(out_dir, f"{r['name']}.png")
        fig.savefig(path, dpi=90)
        plt.close(fig)
        written.append(path)
    return written


# -- an uncertainty study (docs/sweep.md) --------------------------------------------------------

def sweep_plot(result: Any, path: Any) -> Any:
    """Writes :func:`sweep_figure` as a PNG file; returns its path."""
    import pathlib

    path = pathlib.Path(path)
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    fig = sweep_figure(result)
    fig.savefig(path, dpi=110)
    _plt().close(fig)
    return path


def _closest_obstacles(result: Any, n: int = 3) -> List[int]:
    """The obstacles the real cranes came closest to (by the 1 % clearance under the decision)."""
    q = [o.clearance_quantiles[0] for o in result.summary.obstacles]
    return [int(i) for i in np.argsort(q)[:n]]


def sweep_figure(result: Any) -> Any:
    """Three panels: each sample's smallest clearance under the twin's decision against the first
    uncertain parameter (missed contacts marked); the distribution of that clearance for the
    closest obstacles; and the miss rate of the twin's decisions with a larger guard margin, with
    the study's target."""
    plt = _plt()
    study, summary, table = result.study, result.summary, result.table
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    margin = summary.world_margin
    closest = _closest_obstacles(result)
    names = [o.name for o in summary.obstacles]
    clear = table["policy_clearance"]
    missed = table["missed"].any(axis=1)
    ax = axes[0]
    if study.parameters:
        name = study.parameters[0]
        x = result.values(name)
        y = clear.min(axis=1)
        ax.scatter(x[~missed], y[~missed], s=6, color="tab:green", label="kept the margin")
        ax.scatter(x[missed], y[missed], s=6, color="tab:red", label="missed: within the margin")
        ax.set_xlabel(f"{name} (sampled)")
    ax.axhline(margin, color="k", lw=1, ls="--", label=f"world margin {margin:g} m")
    ax.set_ylabel("smallest clearance under the twin's decision, m")
    ax.set_title("each real crane", fontsize=10)
    ax.legend(fontsize=8, loc="best")
    ax = axes[1]
    for i, colour in zip(closest, _OBSTACLE_COLOURS):
        ax.hist(clear[:, i], bins=40, histtype="step", color=colour, label=names[i])
    ax.axvline(margin, color="k", lw=1, ls="--", label="world margin")
    ax.set_xlabel("clearance under the twin's decision, m")
    ax.set_ylabel("samples")
    ax.set_title("clearance per obstacle", fontsize=10)
    ax.legend(fontsize=8)
    ax = axes[2]
    curve = np.array(summary.margin_curve)
    ax.plot(curve[:, 0], curve[:, 1] * 100.0, "o-", ms=3, color="tab:blue", drawstyle="steps-post",
            label="missed")
    ax.axhline(summary.target * 100.0, color="tab:red", lw=1, ls=":",
               label=f"target {summary.target * 100:g} %")
    if np.isfinite(summary.margin_for_target):
        ax.axvline(summary.margin_for_target, color="tab:red", lw=1,
                   label=f"margin {summary.margin_for_target:.2f} m")
    ax.set_xlabel("guard margin, m")
    ax.set_ylabel("contacts missed, % of samples")
    ax.set_title("a larger guard margin", fontsize=10)
    ax.legend(fontsize=8)
    fig.suptitle(_wrap(f"{study.name}: {summary.samples:,} samples; {summary.miss_rate * 100:.1f} % "
                       f"missed at the guard margin {summary.guard_margin:g} m, "
                       f"{summary.needless_stop_rate * 100:.1f} % needless stops"), fontsize=11)
    fig.tight_layout()
    return fig
