"""The display's frames and scenes, without a browser: what is drawn where, in which colour, and
what the banner says (checked against the guard's verdict and the parts' solids)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict.guard import part_solids
from cranepredict.view import Frame
from cranepredict.view import scene as sc


def _frame(scenario: str, world: str, **kw) -> Frame:
    s = cp.scenarios.get(scenario)
    return Frame.predict(s.crane, cp.worlds.get(world), s.initial, s.inputs, s.horizon, **kw)


def _rotate(q, v):
    """v turned by the unit quaternion q = (w, x, y, z): v + 2 w (u x v) + 2 u x (u x v)."""
    w, u = q[0], np.asarray(q[1:])
    return v + 2 * w * np.cross(u, v) + 2 * np.cross(u, np.cross(u, v))


def test_capsule_instances_reproduce_the_parts_ends_and_radii():
    f = _frame("paper-fig4", "wall")
    s = sc.frame_scene(f)
    solids = part_solids(f.crane, f.state, f.theta[0],
                                                  slew=float(f.slew[0]),
                                                  extension=float(f.extension[0]))
    cyl = s.now["cylinder"]
    capsules = [x for x in solids.values() if x["kind"] == "capsule"]
    assert len(cyl) == len(capsules)
    for k, part in enumerate(capsules):
        q, p, r = cyl.wxyzs[k], cyl.positions[k], cyl.scales[k]
        assert abs(np.linalg.norm(q) - 1) < 1e-12
        # the unit cylinder's end centres (0, 0, +-1/2), scaled and turned, are the capsule's ends
        ends = [p + _rotate(q, np.array([0.0, 0.0, h * r[2]])) for h in (-0.5, 0.5)]
        np.testing.assert_allclose(ends[0], part["a"], atol=1e-9)
        np.testing.assert_allclose(ends[1], part["b"], atol=1e-9)
        assert r[0] == r[1] == pytest.approx(part["radius"])
    # two end spheres per capsule plus the load's sphere
    assert len(s.now["sphere"]) == 2 * len(capsules) + 1
    load = solids["load"]
    assert any(np.allclose(p, load["a"]) and np.allclose(r, load["radius"])
               for p, r in zip(s.now["sphere"].positions, s.now["sphere"].scales))


def test_box_obstacle_instance_has_the_worlds_corners():
    world = cp.worlds.get("building-edge")
    inst = sc.obstacle_instances(world)["box"]
    o = next(o for o in world.obstacles if o.name == "building")
    centre, size, yaw = np.array(o["centre"]), np.array(o["size"]), o["yaw"]
    # the corners by the world file's own words: size along the box's axes, turned by yaw about Z
    c, s = math.cos(yaw), math.sin(yaw)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    want = sorted(tuple(np.round(centre + R @ (0.5 * size * np.array(sg)), 9))
                  for sg in np.ndindex(2, 2, 2) for sg in [np.array(sg) * 2 - 1])
    k = int(np.argmin(np.linalg.norm(inst.positions - centre, axis=1)))
    got = sorted(tuple(np.round(inst.positions[k] +
                                _rotate(inst.wxyzs[k], inst.scales[k] * (np.array(sg) - 0.5)), 9))
                 for sg in np.ndindex(2, 2, 2))
    np.testing.assert_allclose(got, want, atol=1e-9)
    # the ground plane: a thin square whose top face is the plane
    ground = [o for o in world.obstacles if o.kind == "plane"][0]
    tops = inst.positions[:, 2] + 0.5 * inst.scales[:, 2]
    assert np.any(np.isclose(tops, ground["point"][2]) & np.isclose(inst.scales[:, 0], sc.PLANE_SIZE))


def test_thin_power_lines_are_drawn_at_a_visible_radius():
    inst = sc.obstacle_instances(cp.worlds.get("power-line"))
    assert inst["cylinder"].scales[:, 0].min() == sc.VISIBLE_RADIUS_MIN
    assert len(inst["cylinder"]) == 5          # three conductors and two poles


def test_part_colours_follow_the_clearance_bands():
    m = 0.3
    assert sc.part_colour(0.3, m) == sc.CLEARANCE_COLOURS["within margin"]
    assert sc.part_colour(-0.1, m) == sc.CLEARANCE_COLOURS["within margin"]
    assert sc.part_colour(0.31, m) == sc.CLEARANCE_COLOURS["near"]
    assert sc.part_colour(1.3, m) == sc.CLEARANCE_COLOURS["near"]
    assert sc.part_colour(1.31, m) == sc.CLEARANCE_COLOURS["clear"]
    assert sc.part_colour(math.inf, m) == sc.CLEARANCE_COLOURS["no obstacle"]
    f = _frame("paper-fig4", "building-edge")
    s = sc.frame_scene(f)
    assert s.part_colours["load"] == sc.CLEARANCE_COLOURS["within margin"]
    for name, c in f.verdict.clearance.items():
        assert s.part_colours[name] == sc.part_colour(c, f.verdict.margin)


def test_ghosts_are_four_future_poses_evenly_through_the_horizon():
    f = _frame("paper-fig4", "wall")
    s = sc.frame_scene(f)
    np.testing.assert_allclose(s.ghost_times, [0.5, 1.0, 1.5, 2.0], atol=0.006)
    n_parts = len(f.crane.shape.parts)
    n_capsules = sum(p.kind == "capsule" for p in f.crane.shape.parts)
    assert len(s.ghosts["cylinder"]) == 4 * n_capsules
    assert len(s.ghosts["sphere"]) == 4 * (2 * n_capsules + n_parts - n_capsules)
    assert np.all(s.ghosts["cylinder"].opacities < 1) and np.all(s.now["cylinder"].opacities == 1)
    # the last ghost's load hangs at the last sample's tip
    load = part_solids(f.crane, f.state, f.theta[-1], slew=float(f.slew[-1]),
                                                extension=float(f.extension[-1]))["load"]["a"]
    assert np.min(np.linalg.norm(s.ghosts["sphere"].positions - load, axis=1)) < 1e-12
    assert sc.ghost_indices(np.array([0.0])) == ()
    assert sc.ghost_indices(np.array([0.0, 1.0]), 4) == (1,)


def test_banner_says_the_verdicts_contact_and_stop_time():
    warn = _frame("paper-fig4", "power-line")
    b = sc.banner(warn)
    v = warn.verdict
    assert (b.signal, b.part, b.obstacle) == ("WARN", v.contact.part, v.contact.obstacle)
    assert b.time_to_contact == v.contact.t and b.stop_by == v.stop.latest
    assert b.colour == sc.SIGNAL_COLOURS["WARN"]
    assert f"contact in {v.contact.t:.2f} s" in b.headline
    assert f"within {v.stop.latest:.2f} s" in b.headline
    stop = sc.banner(_frame("paper-fig4", "building-edge"))
    assert stop.signal == "STOP" and stop.time_to_contact == 0.0 and "now" in stop.headline
    go = sc.banner(_frame("paper-fig4", "cab"))
    assert go.signal == "GO" and go.time_to_contact is None and go.part is None


def test_fault_frame_has_no_verdict_and_the_crane_as_last_known():
    s = cp.scenarios.get("paper-fig4")
    f = Frame.faulted(s.crane, s.initial, cp.worlds.get("wall"), "CAN timeout")
    assert f.signal == "FAULT" and f.verdict is None and len(f.t) == 1
    b = sc.banner(f)
    assert b.signal == "FAULT" and b.detail == "CAN timeout"
    traj = cp.predict(s.crane, s.initial, s.inputs, 0.01)
    np.testing.assert_allclose(f.tip[0], traj.tip[0], atol=1e-9)
    scene = sc.frame_scene(f)
    assert len(scene.ghosts["cylinder"]) == 0 and scene.contact is None
    assert set(scene.part_colours.values()) == {sc.CLEARANCE_COLOURS["no obstacle"]}


def test_frame_refuses_bad_input_naming_the_field():
    s = cp.scenarios.get("paper-fig4")
    world = cp.worlds.get("wall")
    good = _frame("paper-fig4", "wall")
    kw = dict(crane=s.crane, state=s.initial, world=world, t=good.t, theta=good.theta,
              slew=good.slew, extension=good.extension, tip=good.tip, verdict=good.verdict)
    with pytest.raises(ValueError, match="theta must have shape"):
        Frame(**{**kw, "theta": good.theta[:-1]})
    with pytest.raises(ValueError, match="t must be"):
        Frame(**{**kw, "t": good.t[::-1]})
    with pytest.raises(ValueError, match="tip must be finite"):
        tip = np.array(good.tip)
        tip[3, 1] = np.nan
        Frame(**{**kw, "tip": tip})
    with pytest.raises(ValueError, match="either a verdict or a fault"):
        Frame(**{**kw, "verdict": None})
    with pytest.raises(TypeError, match="world must be"):
        Frame(**{**kw, "world": "wall"})
    with pytest.raises(ValueError, match="fault must say"):
        Frame.faulted(s.crane, s.initial, world, "")
    # the arrays the caller passed are not modified and the frame's are read-only
    theta = np.array(good.theta)
    f = Frame(**{**kw, "theta": theta})
    theta[0, 0] = 99.0
    assert f.theta[0, 0] != 99.0 and not f.theta.flags.writeable


def test_viewer_refuses_bad_settings_before_starting():
    from cranepredict.view import Viewer

    with pytest.raises(ValueError, match="port must be in 0..65535"):
        Viewer(port=70000)
    with pytest.raises(ValueError, match="ghosts must be in 0..12"):
        Viewer(port=0, ghosts=-1)


def test_cli_view_reports_bad_world_and_missing_viser(capsys, monkeypatch):
    import sys

    from cranepredict import cli

    import importlib.util

    assert cli.main(["view", "--world", "no-such-world", "--port", "0"]) == 2
    err = capsys.readouterr().err
    if importlib.util.find_spec("viser") is not None:   # without it, that is said first
        assert "--world: no such file, and not an example world" in err
    monkeypatch.setitem(sys.modules, "viser", None)
    assert cli.main(["view", "--port", "0"]) == 2
    assert capsys.readouterr().err == ("cranepredict: error: the display needs viser: "
                                       "pip install 'cranepredict[view]'\n")
