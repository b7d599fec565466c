"""The collision guard's verdict (cp.guard, csrc/guard.c): hand-built cases with answers derived on
paper, first contact and latest stop time against brute force (dense sampling with the pure-Python
twin's kinematics and coal's distances), nothing missed between samples, signals, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

import importlib

import cranepredict as cp
from cranepredict import twin
from cranepredict._cranepredict import ffi, lib
from cranepredict.types import POINT_NAMES

coal = pytest.importorskip("coal")
G = importlib.import_module("cranepredict.guard")   # the module (cp.guard is the function)


@pytest.fixture(scope="module")
def crane() -> cp.Crane:
    return cp.Crane.patu655()


def _world(margin: float, *obstacles: dict) -> cp.World:
    return cp.World.from_dict({"name": "test", "margin": margin, "obstacle": list(obstacles)})


HELD = cp.Inputs(lift=cp.Hold(), tilt=cp.Hold())
REST = cp.State(lift_stroke=0.2, tilt_stroke=0.3)


# -- independent posing and distances ------------------------------------------------------------

def _frames(crane: cp.Crane, theta: np.ndarray, extension: float):
    """Origins and angles of the body frames in the boom plane (docs/model.md "Frames")."""
    g = crane.geometry

    def rot(a, v):
        return np.array([math.cos(a) * v[0] - math.sin(a) * v[1], math.sin(a) * v[0] + math.cos(a) * v[1]])

    o1 = np.array(g.lift_pivot)
    o2 = o1 + rot(theta[0], g.tilt_pivot)
    a2 = theta[0] + theta[1]
    oe = o2 + rot(a2, np.array(g.extension_mount) + [extension, 0.0])
    return {"boom_plane": (np.zeros(2), 0.0), "lift_boom": (o1, theta[0]),
            "outer_boom": (o2, a2), "extension_boom": (oe, a2)}, rot


def independent_solids(crane: cp.Crane, state: cp.State, theta: np.ndarray) -> dict:
    """The parts at a pose from the twin's points (pure Python) and the frames of docs/model.md."""
    pts = twin.points(crane, state.extension, state.slew, np.asarray(theta).reshape(1, 2))[0]
    named = {n: pts[i] for i, n in enumerate(POINT_NAMES)}
    frames, rot = _frames(crane, theta, state.extension)
    c, s = math.cos(state.slew), math.sin(state.slew)

    def world(p):
        if isinstance(p, str):
            return named[p]
        origin, ang = frames[p[0]]
        x, y = origin + rot(ang, (p[1], p[2]))
        return np.array([x * c, x * s, y])

    out = {}
    for part in crane.shape.parts:
        a = world(part.a)
        if part.kind == "capsule":
            out[part.name] = {"kind": "capsule", "a": a, "b": world(part.b), "r": part.radius}
        elif part.kind == "sphere":
            out[part.name] = {"kind": "sphere", "a": a - [0, 0, part.drop], "r": part.radius}
        else:
            R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
            out[part.name] = {"kind": "box", "a": a - [0, 0, part.drop], "R": R,
                              "half": np.array(part.size) / 2}
    return out


def _obstacle_dict(o: cp.Obstacle) -> dict:
    s = o.solid()
    d = {"kind": s["kind"], "a": np.array(s["a"], dtype=float)}
    if s["kind"] == "plane":
        d["n"] = np.array(s["b"])
    elif s["kind"] == "box":
        d["R"] = np.array(s["axes"]).reshape(3, 3).T
        d["half"] = np.array(s["half"])
    else:
        d["r"] = s["radius"]
        if "b" in s:
            d["b"] = np.array(s["b"], dtype=float)
    return d


def coal_clearances(crane, state, theta, world) -> np.ndarray:
    """parts x obstacles clearances (coal; overlap counts as 0)."""
    from test_guard_geometry import theirs

    parts = independent_solids(crane, state, theta)
    obs = [_obstacle_dict(o) for o in world.obstacles]
    return np.array([[max(0.0, theirs(p, o)) for o in obs] for p in parts.values()])


def brute_first_contact(crane, state, inputs, world, horizon, dt):
    """Every sample of a prediction at dt (the model's own motion, no interpolation): the first
    whose coal clearance is at or below the margin, the prediction, and (t, min clearance) so far."""
    traj = cp.predict(crane, state, inputs, horizon, dt=dt)
    prefix = []
    for t, th in zip(traj.t, traj.theta):
        m = coal_clearances(crane, state, th, world).min()
        prefix.append((t, m))
        if m <= world.margin:
            return t, traj, prefix
    return None, traj, prefix


# -- hand-built cases, answers derived on paper ------------------------------------------------------

def test_pillar_over_the_ground_and_beside_a_wall(crane):
    """The pillar is the capsule pillar_base (0,0,0) - lift_pivot (-0.09, 1.4261) (boom plane),
    radius 0.20. Ground 1.2 m below the base: its lowest point is the base, 1.2 - 0.2 = 1.0 m up.
    A wall face at X = 1.0 (box centre 1.5, 1 m thick): the pillar's nearest point is the base
    (its axis leans back, to x = -0.09), 1.0 - 0.2 = 0.8 m away. Nothing moves (both held)."""
    world = _world(0.1, {"name": "ground", "kind": "plane", "point": [0, 0, -1.2], "normal": [0, 0, 5]},
                   {"name": "wall", "kind": "box", "centre": [1.5, 0, 0.5], "size": [1.0, 20, 1.0]})
    shape = cp.Shape(parts=(crane.shape.parts[0],))
    v = cp.guard(crane, world, REST, HELD, 1.0, shape=shape)
    assert v.signal == "GO" and v.contact is None
    assert v.clearance["pillar"] == pytest.approx(0.8, abs=1e-12)
    world2 = _world(0.1, world.obstacles[0].to_plain())
    assert cp.guard(crane, world2, REST, HELD, 1.0, shape=shape).clearance["pillar"] == \
        pytest.approx(1.0, abs=1e-12)


def test_box_over_the_lift_boom_clears_by_a_known_margin(crane):
    """A cube (half 0.25) hung straight above the lift boom's mid-point, its lower face h = 0.6 m
    above the boom's axis along the boom's normal: the boom (radius 0.13) clears it by
    h - 0.13 = 0.47 m if the cube is turned with the boom. Here the cube is axis-aligned and the
    boom tilted by theta0, so its nearest corner is lower: the lower face's corner toward the
    boom's rising side. Paper: distance from the axis line to the corner point, minus 0.13."""
    state = cp.State(lift_stroke=0.3, tilt_stroke=0.3, slew=0.0)
    pts = twin.points(crane, 0.0, 0.0, np.array([[cp._core.joint_angle(crane, 0, 0.3)[0],
                                                  cp._core.joint_angle(crane, 1, 0.3)[0]]]))[0]
    o1, o2 = pts[POINT_NAMES.index("lift_pivot")], pts[POINT_NAMES.index("tilt_pivot")]
    mid = (o1 + o2) / 2
    u = (o2 - o1) / np.linalg.norm(o2 - o1)
    centre = mid + np.array([0.0, 0.0, 1.0]) * 1.2
    world = _world(0.05, {"name": "cube", "kind": "box", "centre": centre.tolist(), "size": [0.5, 0.5, 0.5]})
    shape = cp.Shape(parts=(crane.shape.parts[1],))
    v = cp.guard(crane, world, state, HELD, 0.5, shape=shape)
    # corners of the lower face; the axis line's distance to each, nearest wins (all project inside
    # the boom's length, so the capsule's end caps play no part)
    corners = [centre + [sx * 0.25, sy * 0.25, -0.25] for sx in (-1, 1) for sy in (-1, 1)]
    dist = min(np.linalg.norm(np.cross(c - o1, u)) for c in corners)
    for c in corners:
        assert 0 < (c - o1) @ u < np.linalg.norm(o2 - o1)
    # the face's nearest point could also be an edge or the face interior: the axis lies in the
    # plane y = 0 and rises with slope u_z/u_x, so the nearest point of the face is a corner or an
    # edge point at y = 0; check the edge points too
    for sx in (-1, 1):
        c = centre + [sx * 0.25, 0.0, -0.25]
        dist = min(dist, np.linalg.norm(np.cross(c - o1, u)))
    assert v.clearance["lift_boom"] == pytest.approx(dist - 0.13, abs=1e-9)


# -- against brute force -----------------------------------------------------------------------------

CASES = [("power-line", "paper-fig4"), ("building-edge", "end-stop-lift-lower")]


@pytest.mark.parametrize("world_name, scenario", CASES)
def test_first_contact_matches_dense_brute_force(crane, world_name, scenario):
    """The guard judges every 8th sample of a prediction at 1.25 ms (its samples 10 ms apart);
    brute force checks every sample with coal. The guard's first contact is never later than the
    first sample at or below the margin and at most one sample (+ the time tolerance) earlier; the
    reported points realise the reported clearance."""
    sc = cp.scenarios.get(scenario)
    world = cp.worlds.get(world_name)
    dt, every = 0.00125, 8
    t_bf, _, _ = brute_first_contact(sc.crane, sc.initial, sc.inputs, world, 1.0, dt)
    v = cp.guard(sc.crane, world, sc.initial, sc.inputs, 1.0, dt=dt, sample_every=every)
    assert t_bf is not None and v.contact is not None
    assert v.contact.t <= t_bf + 1e-12
    assert t_bf - v.contact.t <= dt + 1e-4
    assert np.linalg.norm(v.contact.on_part - v.contact.on_obstacle) == pytest.approx(v.contact.clearance, abs=1e-9)
    assert v.contact.clearance <= world.margin + 0.01


def test_random_worlds_first_contact_and_minimum_clearance(crane):
    """Random boxes, spheres and wires near a scenario's path; the guard judges every 4th sample of
    a 2.5 ms prediction, brute force every sample. Contact never late and at most a sample early;
    without contact, every part's minimum is within the clearance tolerance above the brute-force
    minimum over the guard's samples."""
    sc = cp.scenarios.get("both-driven")
    rng = np.random.default_rng(3)
    dt, every = 0.0025, 4
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, 1.0, dt=dt)
    contacts = 0
    for trial in range(6):
        obstacles = []
        for i in range(3):
            p = traj.tip[rng.integers(len(traj.t))] + rng.normal(0, 0.8, 3)
            kind = ("box", "sphere", "capsule")[i]
            o = {"name": f"o{i}", "kind": kind}
            if kind == "box":
                o.update(centre=p.tolist(), size=rng.uniform(0.2, 1.0, 3).tolist(), yaw=float(rng.uniform(0, 3)))
            elif kind == "sphere":
                o.update(centre=p.tolist(), radius=float(rng.uniform(0.1, 0.5)))
            else:
                o.update(a=(p - [0, 2, 0]).tolist(), b=(p + [0, 2, 0]).tolist(), radius=0.02)
            obstacles.append(o)
        world = _world(0.2, *obstacles)
        v = cp.guard(sc.crane, world, sc.initial, sc.inputs, 1.0, dt=dt, sample_every=every)
        t_bf, tr, _ = brute_first_contact(sc.crane, sc.initial, sc.inputs, world, 1.0, dt)
        if t_bf is None:
            assert v.contact is None
            mins = np.min([coal_clearances(sc.crane, sc.initial, th, world).min(axis=1)
                           for th in tr.theta[::every]], axis=0)
            got = np.array(list(v.clearance.values()))
            assert np.all(got >= mins - 1e-9) and np.all(got <= mins + 1e-3 + 1e-9)
        else:
            contacts += 1
            assert v.contact is not None
            assert v.contact.t <= t_bf + 1e-12 and t_bf - v.contact.t <= dt + 1e-4
    assert 0 < contacts < 6


def test_pressure_driven_stop_is_the_valve_to_neutral(crane):
    """The paper's pressure-driven lift towards the power line: its stop is the lift valve to
    neutral from the chamber pressures it had, the spool starting fully open in the direction of
    motion (docs/guard.md). Stopping so at `latest` keeps the margin (coal on every sample of an
    independent prediction of the stop, followed for 3 s) and one judged sample later does not."""
    import dataclasses

    sc = cp.scenarios.get("paper-fig4")
    world = cp.worlds.get("power-line")
    dt, every, reaction = 0.0025, 4, 0.2
    v = cp.guard(sc.crane, world, sc.initial, sc.inputs, 1.2, dt=dt, sample_every=every,
                 reaction=reaction)
    assert v.signal == "WARN" and v.stop.model == "valves to neutral"
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, 1.2, dt=dt)
    stop = cp.Inputs(lift=cp.Valve(0.0), tilt=cp.Hold())

    def stays_clear(t_s):
        m = int(np.ceil((t_s + reaction) / dt - 1e-9))
        start = traj.state(m)
        start = dataclasses.replace(start, lift_spool=float(np.sign(start.lift_stroke_rate)))
        after = cp.predict(sc.crane, start, stop, 3.0, dt=dt)
        return min(min(coal_clearances(sc.crane, sc.initial, th, world).min() for th in traj.theta[:m + 1]),
                   min(coal_clearances(sc.crane, sc.initial, th, world).min() for th in after.theta)) \
            > world.margin

    # a frozen crane (the Hold stop) would allow stopping until first contact - reaction
    assert v.stop.latest < v.contact.t - reaction - 2 * every * dt
    assert stays_clear(v.stop.latest)
    assert not stays_clear(v.stop.latest + every * dt)


def test_nothing_is_missed_between_samples(crane):
    """A thin wire across the path of the extension boom's end, where the boom passes only between
    two of the guard's samples (every 50th of a 1 ms prediction: 50 ms apart): every guard sample
    is clear of it by more than 0.1 m, yet the guard finds the contact inside that step, as the
    motion bound demands."""
    from test_guard_geometry import theirs

    sc = cp.scenarios.get("paper-fig4")
    dt, every = 0.001, 50
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, 1.0, dt=dt)
    coarse = np.arange(0, len(traj.t), every)
    k = int(np.argmax(np.linalg.norm(np.diff(traj.tip[coarse], axis=0), axis=1)))   # fastest step
    mid = coarse[k] + every // 2
    shape = cp.Shape(parts=(crane.shape.parts[3],))   # the extension boom
    end = independent_solids(crane, sc.initial, traj.theta[mid])["extension_boom"]["b"]
    world = _world(0.02, {"name": "wire", "kind": "capsule", "a": (end - [0, 5, 0]).tolist(),
                          "b": (end + [0, 5, 0]).tolist(), "radius": 0.0})
    wire = _obstacle_dict(world.obstacles[0])
    clear = [theirs(independent_solids(crane, sc.initial, traj.theta[i])["extension_boom"], wire)
             for i in coarse]
    assert min(clear) > 0.1, "the wire must be clear at every guard sample for this test to mean anything"
    v = cp.guard(crane, world, sc.initial, sc.inputs, 1.0, dt=dt, sample_every=every, shape=shape)
    assert v.contact is not None and traj.t[coarse[k]] < v.contact.t < traj.t[coarse[k + 1]]
    assert abs(v.contact.t - traj.t[mid]) < 0.01   # the boom's end reaches the wire at mid-step


# -- signals and the lever --------------------------------------------------------------------------

def test_signals_and_the_closing_lever(crane):
    sc = cp.scenarios.get("end-stop-lift-lower")
    world = cp.worlds.get("building-edge")
    warn = cp.guard(sc.crane, world, sc.initial, sc.inputs, 2.0, reaction=0.05)
    assert warn.signal == "WARN" and warn.stop.latest > G.DEFAULT_CYCLE
    assert warn.contact.closing == ("lift",) and warn.contact.approach["lift"] < 0
    # a longer reaction leaves no time: STOP
    late = cp.guard(sc.crane, world, sc.initial, sc.inputs, 2.0, reaction=0.2)
    assert late.signal == "STOP" and late.stop.latest < 0
    # cutting the closing lever (lift held, the others allowed) removes the contact
    cut = cp.Inputs(lift=cp.Hold(), tilt=sc.inputs.tilt)
    assert cp.guard(sc.crane, world, sc.initial, cut, 2.0).signal == "GO"
    # GO
    go = cp.guard(sc.crane, cp.worlds.get("wall"), sc.initial, HELD, 2.0)
    assert go.signal == "GO" and go.contact is None and go.stop is None
    # already within the margin at t = 0: STOP with that reason
    tip = cp.predict(sc.crane, sc.initial, HELD, 0.01).tip[0]
    ball = _world(0.3, {"name": "ball", "kind": "sphere", "centre": tip.tolist(), "radius": 0.2})
    now = cp.guard(sc.crane, ball, sc.initial, sc.inputs, 1.0)
    assert now.signal == "STOP" and now.contact.at_start and now.contact.t == 0.0
    assert "already at t = 0" in now.reason and "in contact" in now.reason
    d = now.to_dict()
    assert d["signal"] == "STOP" and d["contact"]["obstacle"] == "ball"


def test_part_solids_match_the_independent_pose(crane):
    """The C core's posed parts (crane_part_solids) against the twin's points and docs/model.md's
    frames, at random poses, slews and extensions."""
    rng = np.random.default_rng(5)
    for _ in range(20):
        st = cp.State(lift_stroke=rng.uniform(0, 0.535), tilt_stroke=rng.uniform(0, 0.78),
                      slew=rng.uniform(-3, 3), extension=rng.uniform(0, 1))
        th = np.array([cp._core.joint_angle(crane, 0, st.lift_stroke, st.extension)[0],
                       cp._core.joint_angle(crane, 1, st.tilt_stroke, st.extension)[0]])
        ours = G.part_solids(crane, st, th)
        ref = independent_solids(crane, st, th)
        for name, r in ref.items():
            assert ours[name]["a"] == pytest.approx(r["a"], abs=1e-12)
            if r["kind"] == "capsule":
                assert ours[name]["b"] == pytest.approx(r["b"], abs=1e-12)


# -- bad input ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("text, words", [
    ("margin = [", "not valid TOML"),
    ("obstacle = []", "margin .* is missing"),
    ("margin = 0.1\n[[obstacle]]\nname = 'w'\nkind = 'pyramid'", r"obstacle 'w' \(obstacle\[0\]\)\.kind must be one of"),
    ("margin = 0.1\n[[obstacle]]\nkind = 'box'", r"obstacle\[0\]\.name is missing"),
    ("margin = 0.1\n[[obstacle]]\nname = 'w'\nkind = 'box'\ncentre = [0, 0, 0]",
     r"obstacle 'w' \(obstacle\[0\]\)\.size is missing"),
    ("margin = 0.1\n[[obstacle]]\nname = 'w'\nkind = 'box'\ncentre = [0, 0, 0]\nsize = [1, 0, 1]",
     r"obstacle 'w' \(obstacle\[0\]\)\.size must be > 0"),
    ("margin = 0.1\n[[obstacle]]\nname = 'w'\nkind = 'box'\ncentre = [0, nan, 0]\nsize = [1, 1, 1]",
     r"obstacle 'w' \(obstacle\[0\]\)\.centre\[1\] must be finite"),
    ("margin = 0.1\n[[obstacle]]\nname = 'p'\nkind = 'cylinder'\nbase = [0, 0, 0]\nheight = 0\nradius = 0.1",
     r"obstacle 'p' \(obstacle\[0\]\)\.height must be > 0"),
    ("margin = 0.1\n[[obstacle]]\nname = 's'\nkind = 'sphere'\ncentre = [0, 0, 0]\nradius = -1",
     r"obstacle 's' \(obstacle\[0\]\)\.radius must be > 0"),
    ("margin = 0.1\n[[obstacle]]\nname = 'g'\nkind = 'plane'\npoint = [0, 0, 0]\nnormal = [0, 0, 0]",
     r"obstacle 'g' \(obstacle\[0\]\)\.normal must not be zero"),
    ("margin = 0.1\n[[obstacle]]\nname = 'g'\nkind = 'plane'\npoint = [0, 0]\nnormal = [0, 0, 1]",
     r"obstacle 'g' \(obstacle\[0\]\)\.point must be \[x, y, z\]"),
    ("margin = 0.1\n[[obstacle]]\nname = 's'\nkind = 'sphere'\ncentre = [0, 0, 0]\nradius = 1\ncolour = 'red'",
     r"obstacle 's' \(obstacle\[0\]\): unknown field\(s\) colour"),
    ("margin = -0.1", "margin must be >= 0"),
    ("margin = 0.1\n[[obstacle]]\nname = 'a'\nkind = 'sphere'\ncentre = [0, 0, 0]\nradius = 1\n"
     "[[obstacle]]\nname = 'a'\nkind = 'sphere'\ncentre = [1, 0, 0]\nradius = 1", "unique, repeated: a"),
    ("margin = 0.1\nwalls = 3", r"unknown field\(s\) walls"),
])
def test_malformed_world_files_name_the_obstacle_and_field(text, words):
    with pytest.raises((ValueError, TypeError), match=words):
        cp.World.from_toml_string(text)


def test_bad_shapes_and_settings_are_named(crane):
    d = crane.to_dict()
    d["shape"]["load"]["radius"] = 0.0
    with pytest.raises(ValueError, match=r"shape\.load\.radius must be in \(0, 1e\+06\] m"):
        cp.Crane.from_dict(d)
    d = crane.to_dict()
    d["shape"]["outer_boom"]["a"] = ["jib", 0.0, 0.0]
    with pytest.raises(ValueError, match=r"shape\.outer_boom\.a\[0\] must be one of"):
        cp.Crane.from_dict(d)
    d = crane.to_dict()
    d["shape"]["lift_boom"]["b"] = "nose"
    with pytest.raises(ValueError, match=r"shape\.lift_boom\.b must be one of the crane's points"):
        cp.Crane.from_dict(d)
    d = crane.to_dict()
    d["shape"]["pillar"]["radius"] = math.inf
    with pytest.raises(ValueError, match=r"shape\.pillar\.radius must be finite"):
        cp.Crane.from_dict(d)
    world = cp.worlds.get("wall")
    for kw, words in (({"reaction": -0.1}, "reaction must be >= 0"), ({"cycle": 0.0}, "cycle must be > 0"),
                      ({"margin": math.nan}, "margin must be finite"), ({"margin": -1.0}, "margin must be >= 0"),
                      ({"time_tolerance": 0.0}, "time_tolerance must be > 0")):
        with pytest.raises(ValueError, match=words):
            cp.guard(crane, world, REST, HELD, 1.0, **kw)
    import dataclasses

    with pytest.raises(ValueError, match="has no \\[shape\\]"):
        cp.guard(dataclasses.replace(crane, shape=None), world, REST, HELD, 1.0)
    with pytest.raises(TypeError, match="world must be a cranepredict.World"):
        cp.guard(crane, "wall.toml", REST, HELD, 1.0)


def _c_call(crane, world, work_capacity, solids=None):
    g = G
    samples = G._samples(cp.predict(crane, REST, HELD, 0.1))
    parts = g._parts(crane, crane.shape)
    solids = g._solids(world) if solids is None else solids
    n_parts = len(crane.shape.parts)
    clearance = np.full(n_parts, 77.0)
    work = np.zeros(max(work_capacity, 1))
    cfg = ffi.new("crane_guard_config *", {"margin": 0.1, "reaction": 0.2, "cycle": 0.01,
                                           "time_tolerance": 1e-4, "clearance_tolerance": 0.0})
    res = ffi.new("crane_guard_result *")
    res.signal, res.t = 9, 55.0
    status = lib.crane_guard(cp._core.model(crane, 0.0), parts, n_parts, solids, len(world.obstacles),
                             ffi.cast("crane_sample *", ffi.from_buffer(samples)), len(samples), cfg,
                             ffi.cast("crane_real *", ffi.from_buffer(clearance)),
                             ffi.cast("crane_real *", ffi.from_buffer(work)), work_capacity, res)
    return status, clearance, res


def test_c_guard_buffer_too_small_and_bad_obstacle_write_nothing(crane):
    world = cp.worlds.get("cab")
    need = len(crane.shape.parts) * (len(world.obstacles) + lib.CRANE_GUARD_PART_WORK)
    status, clearance, res = _c_call(crane, world, need - 1)
    assert status == lib.CRANE_E_CAPACITY
    assert np.all(clearance == 77.0) and res.signal == 9 and res.t == 55.0
    status, clearance, res = _c_call(crane, world, need)
    assert status == lib.CRANE_OK and np.all(clearance < 77.0)
    g = G
    solids = g._solids(world)
    solids[1].half = [1.0, -1.0, 1.0]
    status, clearance, res = _c_call(crane, world, need, solids)
    assert status == lib.CRANE_E_SOLID and np.all(clearance == 77.0) and res.signal == 9
    which, field = ffi.new("size_t *"), ffi.new("int *")
    assert lib.crane_guard_check(g._parts(crane, crane.shape), len(crane.shape.parts), solids, 3,
                                 which, field) == lib.CRANE_E_SOLID
    assert which[0] == 1 and field[0] == lib.CRANE_GUARD_FIELD_HALF
    # the Python layer names the obstacle and field for what reaches the core
    with pytest.raises(ValueError, match=r"obstacle 'cab' \(obstacle\[1\]\)\.size is not valid"):
        g._check_layout(g._parts(crane, crane.shape), len(crane.shape.parts), solids, world, crane.shape)


def test_lengths_beyond_a_site_are_named(crane):
    """Coordinates and sizes are limited to +-1e6 m (the C core's CRANE_GUARD_LENGTH_MAX), so that
    squared lengths cannot overflow: a world file beyond that names the obstacle and field, and
    the core rejects such a solid itself."""
    with pytest.raises(ValueError, match=r"obstacle 'far' \(obstacle\[0\]\)\.centre\[0\] must be within"):
        cp.World.from_toml_string("margin = 0.1\n[[obstacle]]\nname = 'far'\nkind = 'sphere'\n"
                                  "centre = [1e7, 0, 0]\nradius = 1")
    from test_guard_geometry import _solid

    field = ffi.new("int *")
    far = _solid({"kind": "sphere", "a": np.array([2e6, 0.0, 0.0]), "r": 1.0})
    assert lib.crane_solid_check(far, field) == lib.CRANE_E_SOLID and field[0] == lib.CRANE_GUARD_FIELD_A


def test_an_empty_world_is_go_and_its_json_is_valid(crane):
    import json

    v = cp.guard(crane, _world(0.1), REST, HELD, 0.5)
    assert v.signal == "GO" and all(math.isinf(c) for c in v.clearance.values())
    d = json.loads(json.dumps(v.to_dict(), allow_nan=False))
    assert d["min_clearance_m"]["load"] is None


# -- valve-driven cylinders stop by their valves to neutral ----------------------------------------

def test_stop_inputs_map_each_lever_to_its_stop():
    v = cp.stop_inputs(cp.Inputs(lift=cp.Valve(0.7), tilt=cp.Pressure(p_a=1e6),
                                 slew=cp.Valve(0.8), extension=cp.ValveSeries(t=[0, 2], u=[0, 1])))
    assert v == cp.Inputs(lift=cp.Valve(0.0), tilt=cp.Valve(0.0), slew=cp.Valve(0.0),
                          extension=cp.Valve(0.0))
    s = cp.stop_inputs(cp.Inputs(lift=cp.ValveSeries(t=[0, 2], u=[0.2, -0.5]), tilt=cp.Hold()))
    assert s.lift == cp.Valve(0.0) and isinstance(s.tilt, cp.Hold)
    assert isinstance(s.slew, cp.Hold) and isinstance(s.extension, cp.Hold)


def test_a_pressure_drive_without_hydraulics_gets_no_latest_stop(crane):
    """A pressure-driven cylinder whose crane file has no valve: its stop cannot be predicted, so
    a predicted contact is a STOP that says why (never a latest time from a frozen crane)."""
    import dataclasses

    sc = cp.scenarios.get("paper-fig4")
    bare = dataclasses.replace(sc.crane, lift_cylinder=dataclasses.replace(
        sc.crane.lift_cylinder, hydraulics=None))
    v = cp.guard(bare, cp.worlds.get("power-line"), sc.initial, sc.inputs, 1.2)
    assert v.contact is not None and not v.contact.at_start
    assert v.signal == "STOP" and v.stop.latest == -math.inf
    assert "no hydraulics table" in v.reason and "lift" in v.reason


def _lever_open_ball():
    sc = cp.scenarios.get("lever-open")
    tr = cp.predict(sc.crane, sc.initial, sc.inputs, 2.0)
    p = tr.tip[int(round(1.2 / cp.DEFAULT_DT))]
    world = _world(0.2, {"name": "ball", "kind": "sphere", "centre": (p + [0, 0, 0.9]).tolist(),
                         "radius": 0.3})
    return sc, world


def test_valve_stop_analysis_against_the_stops_themselves(crane):
    """The lift lever fully open (valve-driven) toward a ball: the stop is every valve to neutral.
    Its latest stop time is earlier than the freeze bound (contact - reaction: a valve stop takes
    time); and, checked with coal on every sample of independent predictions, stopping at that
    time keeps the margin while stopping one judged sample later does not."""
    sc, world = _lever_open_ball()
    dt, reaction = cp.DEFAULT_DT, 0.2
    v = cp.guard(sc.crane, world, sc.initial, sc.inputs, 2.0, reaction=reaction)
    assert v.signal == "WARN" and v.stop.model == "valves to neutral"
    assert 0 < v.stop.latest <= v.contact.t - reaction
    traj = cp.predict(sc.crane, sc.initial, sc.inputs, 2.0, dt=dt)
    spacing = G.GUARD_SPACING
    stop = cp.stop_inputs(sc.inputs)

    def stays_clear(t_s):
        m = int(np.ceil((t_s + reaction) / dt - 1e-9))      # the stop takes effect at this sample
        before = min(coal_clearances(sc.crane, sc.initial, th, world).min() for th in traj.theta[:m + 1])
        _, ds0 = cp._core.joint_angle(sc.crane, 0, traj.strokes[m, 0])
        start = cp.State(lift_stroke=traj.strokes[m, 0], tilt_stroke=traj.strokes[m, 1],
                         lift_stroke_rate=traj.omega[m, 0] * ds0,
                         lift_p_a=traj.p_a[m, 0], lift_p_b=traj.p_b[m, 0], lift_spool=traj.spool[m, 0],
                         tilt_p_a=traj.p_a[m, 1], tilt_p_b=traj.p_b[m, 1], tilt_spool=traj.spool[m, 1],
                         tilt_stroke_rate=traj.omega[m, 1] * cp._core.joint_angle(sc.crane, 1, traj.strokes[m, 1])[1])
        after = cp.predict(sc.crane, start, stop, G.DEFAULT_STOP_HORIZON, dt=dt)
        during = min(coal_clearances(sc.crane, sc.initial, th, world).min() for th in after.theta)
        return min(before, during) > world.margin

    assert stays_clear(v.stop.latest)
    assert not stays_clear(v.stop.latest + spacing)
