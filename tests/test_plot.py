"""The static figures: each view holds the whole crane, no text is written over other text, an
obstacle far from the crane's path is left out of the view, a pure slew's tip path is shown
where it moves."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import cranepredict as cp

pytest.importorskip("matplotlib")
guard_mod = __import__("importlib").import_module("cranepredict.guard")
from cranepredict import plot  # noqa: E402


def _texts(fig):
    """Window boxes of every visible, non-empty text in the figure (titles, labels, ticks,
    legend entries, notes), drawn."""
    from matplotlib.text import Text

    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    hidden = set()      # the labels of ticks outside an axis' view (matplotlib does not draw them)
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks():
                if not lo - 1e-9 <= tick.get_loc() <= hi + 1e-9:
                    hidden.update({id(tick.label1), id(tick.label2)})
    out = []
    for t in fig.findobj(Text):
        if id(t) in hidden:
            continue
        if t.get_visible() and t.get_text().strip() and t.get_alpha() != 0:
            out.append((t.get_text(), t.get_window_extent(r)))
    return out


def _overlaps(fig):
    boxes = _texts(fig)
    return [(a, b) for (a, ba), (b, bb) in itertools.combinations(boxes, 2)
            if ba.overlaps(bb) and ba.width > 0 and bb.width > 0]


def _close(fig):
    import matplotlib.pyplot as plt

    plt.close(fig)


@pytest.mark.parametrize("name", ["slew-folded", "paper-fig4", "slew-stretched"])
def test_demo_views_hold_every_point_of_the_crane(name):
    sc = cp.scenarios.get(name)
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="python"
                      if sc.spatial else "c")
    fig = plot.demo_figure(sc, traj)
    try:
        side, top = fig.axes[:2]
        pts = np.stack(list(traj.points().values()), axis=1)      # (N, points, 3)
        psi = np.broadcast_to(traj.slew, traj.t.shape)[:, None]
        radial = pts[..., 0] * np.cos(psi) + pts[..., 1] * np.sin(psi)
        for ax, x, y in ((side, radial, pts[..., 2]), (top, pts[..., 0], pts[..., 1])):
            (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
            assert x0 < x.min() and x.max() < x1 and y0 < y.min() and y.max() < y1, ax.get_title()
            assert x1 - x0 >= plot.MIN_SPAN and y1 - y0 >= plot.MIN_SPAN
        assert _overlaps(fig) == []
    finally:
        _close(fig)


def test_far_obstacles_are_left_out_of_the_view_they_would_cross():
    sc = cp.scenarios.get("paper-fig4")
    world = cp.worlds.get("power-line")
    v = cp.guard(sc.crane, world, sc.initial, sc.inputs, sc.horizon)
    fig = plot.guard_figure(v, sc, guard_mod)
    try:
        labels = set(fig.legends[0].get_texts()[i].get_text()
                     for i in range(len(fig.legends[0].get_texts())))
        # the poles stand 12 m to either side of the boom plane: in neither view near the crane
        assert "pole west" not in labels and "pole east" not in labels
        assert {"conductor 1", "conductor 2", "conductor 3"} <= labels
        notes = [t.get_text() for ax in fig.axes[:2] for t in ax.texts]
        assert any("pole west" in n and "pole east" in n for n in notes)
        assert _overlaps(fig) == []
    finally:
        _close(fig)
    s = {o.name: o.solid() for o in world.obstacles}
    assert not plot.near_in_depth(s["pole west"], 1, -0.5, 0.5)
    assert plot.near_in_depth(s["conductor 1"], 1, -0.5, 0.5)
    assert plot.near_in_depth(s["pole west"], 2, 0.0, 5.0)      # in height it is near


@pytest.mark.parametrize("world", ["building-edge", "wall", "cab"])
def test_guard_figure_text_does_not_overprint(world):
    sc = cp.scenarios.get("end-stop-lift-lower")
    v = cp.guard(sc.crane, cp.worlds.get(world), sc.initial, sc.inputs, sc.horizon)
    fig = plot.guard_figure(v, sc, guard_mod)
    try:
        assert _overlaps(fig) == []
    finally:
        _close(fig)


def test_tip_view_follows_the_motion():
    sc = cp.scenarios.get("slew-stretched")
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="python")
    assert plot.tip_view(traj.tip, traj.slew) == "top"
    sc = cp.scenarios.get("paper-fig4")
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon)
    assert plot.tip_view(traj.tip, traj.slew) == "boom plane"


def test_fit_keeps_a_minimum_span_around_a_still_point():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    try:
        (x0, x1), (y0, y1) = plot.fit(ax, [2.0, 2.0 + 1e-12], [1.0, 1.0], pad=0.0)
        assert x1 - x0 == pytest.approx(plot.MIN_SPAN) and y1 - y0 == pytest.approx(plot.MIN_SPAN)
        assert x0 < 2.0 < x1 and y0 < 1.0 < y1
    finally:
        plt.close(fig)


def test_validate_plot_of_a_slew_shows_the_top_view(tmp_path):
    """validate's tip-path panel, given rows as validation.compare makes them (the reference's
    own tip path stood in by the fast model's: what is tested is the panel, not the model)."""
    import matplotlib.image

    sc = cp.scenarios.get("slew-stretched")
    fast = cp.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, backend="python")
    row = {"name": sc.name, "_fast": fast, "_ref": fast, "_err": np.zeros(len(fast.t)),
           "first_stop_time_s": None, "max_error_mm": 0.0, "rms_error_mm": 0.0}
    (path,) = plot.validate_plots([row], str(tmp_path))
    assert matplotlib.image.imread(path).shape[0] > 100
    import matplotlib.pyplot as plt

    # the same panel, kept open to read its axes
    fig_before = set(plt.get_fignums())
    orig_close = plt.close
    kept = []
    plt.close = lambda fig=None: kept.append(fig)
    try:
        plot.validate_plots([row], str(tmp_path))
    finally:
        plt.close = orig_close
    fig = kept[0]
    try:
        ax = fig.axes[0]
        assert "top view" in ax.get_title()
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        assert y1 - y0 >= 0.5 and y0 < fast.tip[:, 1].min() and fast.tip[:, 1].max() < y1
        assert x0 < fast.tip[:, 0].min() and fast.tip[:, 0].max() < x1
        assert set(plt.get_fignums()) - fig_before
    finally:
        orig_close(fig)
