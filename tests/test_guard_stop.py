"""The guard's guarantee over every drive: stopping at the reported latest time keeps the margin,
stopping one judged sample later does not. Checked by independent predictions of the stop (every
valve to neutral when the stop takes effect, followed for seconds) and coal's distances on every
sample, over random poses and valve commands that move the slew and the telescope too."""

from __future__ import annotations

import importlib
import math
import types

import numpy as np
import pytest

import cranepredict as cp

coal = pytest.importorskip("coal")
G = importlib.import_module("cranepredict.guard")   # the module (cp.guard is the function)
from test_guard import _world, coal_clearances  # noqa: E402

REACTION = 0.2
FOLLOW = 4.0        # s of stop predicted by the check (the guard follows until at rest)


@pytest.fixture(scope="module")
def crane() -> cp.Crane:
    return cp.Crane.patu655()


def _all_neutral(inputs: cp.Inputs) -> cp.Inputs:
    """Every lever to neutral, written here (not by stop_inputs): a held drive stays held."""
    return cp.Inputs(**{j: cp.Hold() if isinstance(getattr(inputs, j), cp.Hold) else cp.Valve(0.0)
                        for j in ("lift", "tilt", "slew", "extension")})


def _pose(traj, k):
    return types.SimpleNamespace(slew=float(traj.slew[k]), extension=float(traj.extension[k]))


def _min_clearance(crane, traj, world, upto=None):
    n = len(traj.t) if upto is None else upto
    return min(coal_clearances(crane, _pose(traj, k), traj.theta[k], world).min() for k in range(n))


def _stays_clear(crane, sc_state, inputs, world, t_s, horizon):
    """Run the command, decide to stop at t_s: the valves go to neutral at the first sample at or
    after t_s + REACTION; the whole motion (command, then the stop for FOLLOW s) keeps every
    clearance above the margin?"""
    dt = cp.DEFAULT_DT
    traj = cp.predict(crane, sc_state, inputs, horizon)
    m = int(math.ceil((t_s + REACTION) / dt - 1e-9))
    before = _min_clearance(crane, traj, world, upto=m + 1)
    after = cp.predict(crane, traj.state(m), _all_neutral(inputs), FOLLOW)
    return min(before, _min_clearance(crane, after, world)) > world.margin


def _random_case(crane, rng):
    lc, tc, ec = crane.lift_cylinder, crane.tilt_cylinder, crane.geometry
    sd = crane.slew_drive
    state = cp.state_at_rest(crane, rng.uniform(lc.stroke_min + 0.02, lc.stroke_max - 0.02),
                             rng.uniform(tc.stroke_min + 0.02, tc.stroke_max - 0.02),
                             slew=rng.uniform(sd.slew_min + 0.8, sd.slew_max - 0.8),
                             extension=rng.uniform(ec.extension_min, ec.extension_max - 0.3))
    def lever(lo):
        return float(rng.choice([-1, 1]) * rng.uniform(lo, 1.0))
    inputs = cp.Inputs(lift=cp.Valve(lever(0.0)), tilt=cp.Valve(lever(0.0)),
                       slew=cp.Valve(lever(0.4)) if rng.random() < 0.8 else cp.Valve(0.0),
                       extension=cp.Valve(lever(0.4)) if rng.random() < 0.6 else cp.Hold())
    return state, inputs


def test_latest_stop_is_kept_with_the_slew_and_the_telescope_moving(crane):
    """A valve-driven slew towards a pole: the stop analysis follows the slew through its oil and
    inertia (it keeps turning after its valve closes), so stopping at `latest` keeps the margin."""
    state = cp.state_at_rest(crane, 0.116, 0.20, slew=0.0, extension=0.3)
    inputs = cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(0.0), slew=cp.Valve(0.8),
                       extension=cp.Valve(0.0))
    stop = cp.stop_inputs(inputs)
    assert all(getattr(stop, j) == cp.Valve(0.0) for j in ("lift", "tilt", "slew", "extension"))
    traj = cp.predict(crane, state, inputs, 3.0)
    p = traj.tip[int(round(2.5 / cp.DEFAULT_DT))]
    world = _world(0.3, {"name": "pole", "kind": "cylinder", "base": [p[0], p[1], -1.0],
                         "height": 9.0, "radius": 0.1})
    v = cp.guard(crane, world, state, inputs, 3.0, reaction=REACTION)
    assert v.signal == "WARN", v.reason
    assert _stays_clear(crane, state, inputs, world, v.stop.latest, 3.0)
    assert not _stays_clear(crane, state, inputs, world, v.stop.latest + G.GUARD_SPACING, 3.0)


def test_a_stop_hint_finds_the_same_latest_stop_with_fewer_stop_predictions(crane, monkeypatch):
    """guard(stop_hint=...) searches outwards from the hint: the same latest stop time as the
    bisection alone from any hint (early, right, late, past the contact), and with the right one
    (a control loop's last cycle) far fewer stop predictions."""
    state = cp.state_at_rest(crane, 0.116, 0.20, slew=0.0, extension=0.3)
    inputs = cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(0.0), slew=cp.Valve(0.8),
                       extension=cp.Valve(0.0))
    traj = cp.predict(crane, state, inputs, 3.0)
    p = traj.tip[int(round(2.5 / cp.DEFAULT_DT))]
    world = _world(0.3, {"name": "pole", "kind": "cylinder", "base": [p[0], p[1], -1.0],
                         "height": 9.0, "radius": 0.1})
    calls = []
    follow = G._stops_are_safe
    monkeypatch.setattr(G, "_stops_are_safe", lambda c, w, starts, *a: calls.extend(starts)
                        or follow(c, w, starts, *a))
    v = cp.guard(crane, world, state, inputs, 3.0, reaction=REACTION)
    plain = len(calls)
    assert v.signal == "WARN" and v.stop.latest > 0.5, v.reason
    for hint in (0.0, 0.013, v.stop.latest - 0.31, v.stop.latest - G.GUARD_SPACING, v.stop.latest,
                 v.stop.latest + G.GUARD_SPACING, v.stop.latest + 0.27, v.contact.t, 10.0, -5.0):
        del calls[:]
        h = cp.guard(crane, world, state, inputs, 3.0, reaction=REACTION, stop_hint=hint)
        assert h.stop.latest == v.stop.latest and h.signal == v.signal, hint
        if hint == v.stop.latest:
            assert len(calls) <= 2 < plain, (len(calls), plain)
    with pytest.raises(ValueError, match="stop_hint"):
        cp.guard(crane, world, state, inputs, 3.0, stop_hint=math.nan)
    with pytest.raises(TypeError, match="stop_hint"):
        cp.guard(crane, world, state, inputs, 3.0, stop_hint="soon")


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(12))
def test_latest_stop_over_random_four_drive_commands(crane, seed):
    rng = np.random.default_rng(1000 + seed)
    for _ in range(20):   # the first case whose ball is met
        state, inputs = _random_case(crane, rng)
        traj = cp.predict(crane, state, inputs, 2.0)
        p = traj.tip[int(round(1.4 / cp.DEFAULT_DT))]
        if np.linalg.norm(traj.tip[0] - p) < 0.8:
            continue                      # the tip hardly moves: no case
        world = _world(0.3, {"name": "ball", "kind": "sphere", "centre": p.tolist(), "radius": 0.3})
        v = cp.guard(crane, world, state, inputs, 2.0, reaction=REACTION)
        if v.signal != "WARN":
            continue
        break
    else:
        pytest.skip("no case with a WARN in 20 draws")
    assert _stays_clear(crane, state, inputs, world, v.stop.latest, 2.0), v.reason
    if v.stop.note == G.STOP_NOTE:   # tight: a later stop was judged to touch (not refused)
        assert not _stays_clear(crane, state, inputs, world, v.stop.latest + G.GUARD_SPACING,
                                2.0), v.reason


@pytest.mark.parametrize("world", cp.worlds.names())
def test_a_verdict_for_every_named_scenario(world):
    """The guard never fails on a future the predictor produced: every named scenario in every
    example world gets a verdict (chambers that cavitate included)."""
    for name in cp.scenarios.names():
        sc = cp.scenarios.get(name)
        v = cp.guard(sc.crane, cp.worlds.get(world), sc.initial, sc.inputs, sc.horizon)
        assert v.signal in G.SIGNALS, (world, name)
        if v.contact is not None and not v.contact.at_start:
            assert v.stop.model == G.STOP_MODEL and (v.signal == "STOP") == (v.stop.latest < 0.01)


def _follow_values(world, horizon=G.DEFAULT_STOP_HORIZON):
    return {"margin": world.margin, "reaction": REACTION, "cycle": G.DEFAULT_CYCLE,
            "time_tolerance": G.DEFAULT_TIME_TOLERANCE,
            "clearance_tolerance": G.DEFAULT_CLEARANCE_TOLERANCE, "stop_horizon": horizon}


def test_a_stop_followed_on_in_pieces_is_judged_over_all_of_them(crane, monkeypatch):
    """A stop that takes more than one piece: each piece continues from the last one's final
    state (the pieces' lengths 0.5, 0.5, 1, ... s); a "stop" that keeps both levers open reaches an
    obstacle only after the first piece and is unsafe; the valves to neutral from full speed ring
    on the oil past the first piece and settle, safe in a clear world; a piece whose end is not a
    valid State is unsafe, saying why."""
    start = cp.state_at_rest(crane, 0.05, 0.20)
    moving = cp.Inputs(lift=cp.Valve(1.0), tilt=cp.Valve(1.0))
    one_shot = cp.predict(crane, start, moving, 1.5)
    p = one_shot.tip[-1]
    hit = _world(0.1, {"name": "ball", "kind": "sphere", "centre": p.tolist(), "radius": 0.05})
    assert min(np.linalg.norm(one_shot.tip[:int(round(0.6 / cp.DEFAULT_DT))] - p, axis=1)) > 0.4
    lengths, froms = [], []
    follow = G.api.predict_many

    def recording(c, states, inputs, horizon, **kw):
        lengths.append(round(horizon, 9))
        froms.append(states[0])
        return follow(c, states, inputs, horizon, **kw)

    monkeypatch.setattr(G.api, "predict_many", recording)
    args = (crane.shape, _follow_values(hit), cp.DEFAULT_DT, 2)
    assert G._stops_are_safe(crane, hit, [start], moving, *args) == [(False, "")]
    assert lengths == [0.5, 0.5, 1.0] and froms[0] == start
    half = one_shot.state(int(round(0.5 / cp.DEFAULT_DT)))
    assert abs(froms[1].lift_stroke - half.lift_stroke) < 1e-5
    assert abs(froms[2].tilt_stroke - one_shot.state(int(round(1.0 / cp.DEFAULT_DT))).tilt_stroke) < 1e-5

    far = _world(0.1, {"name": "far", "kind": "sphere", "centre": [40.0, 0.0, 0.0], "radius": 0.1})
    neutral = _all_neutral(moving)
    del lengths[:]
    assert G._stops_are_safe(crane, far, [half], neutral, crane.shape, _follow_values(far),
                             cp.DEFAULT_DT, 2) == [(True, "")]
    assert len(lengths) >= 2 and lengths[:2] == [0.5, 0.5]
    del lengths[:]
    monkeypatch.setattr(cp.Trajectory, "final_state", property(
        lambda self: (_ for _ in ()).throw(ValueError("lift_p_a below vacuum"))))
    safe, why = G._stops_are_safe(crane, far, [half], neutral, crane.shape, _follow_values(far),
                                  cp.DEFAULT_DT, 2)[0]
    assert not safe and "could not be followed on" in why and "lift_p_a" in why
    assert lengths == [0.5]
