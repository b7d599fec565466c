"""Closed-loop episodes: the live twin against the simulated crane, randomised, with the
interlock obeyed and ignored. Prints the table of docs/live.md ("Closed loop").

    python tools/closed_loop_study.py [--episodes 100] [--seed 0] [--near-miss BAND] [--json FILE]

An episode: an example world, a start pose clear of every obstacle's margin at rest, and a lever
combination whose future (on the twin's crane file) comes within the margin between 1.5 and 4 s;
the plant's load, friction and supply pressure drawn off the crane file (x0.7-1.3, x0.8-1.25,
x0.95-1.03). Each runs until 2 s after that, once obeying the verdict and once ignoring it.
With ``--near-miss BAND`` (m) the levers' future instead passes the obstacles outside the margin,
its closest approach within BAND of it, over NEAR_MISS_LOOK s; each run lasts NEAR_MISS_RUN s
(the last STOP the twin can give then looks 2 s ahead: inside the look). A needless STOP: the
obeyed run STOPs, while the ignored run never comes within the world's margin of an obstacle;
also counted: the STOPs of episodes whose ignored run came within the margin without touching.
Ctrl-C prints the table of the episodes done so far (``--json`` is written after every episode).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import cranepredict as cp
from cranepredict.live.episode import run_episode
from cranepredict.live.sim import LeverScript, perturbed_crane

WORLDS = ("wall", "building-edge", "cab", "power-line")
NEAR_MISS_LOOK = 7.5   # s: the twin's future of a near-miss episode stays outside the margin so long
NEAR_MISS_RUN = 5.3    # s: a near-miss episode's runs (the levers move at 0.3 s)


def draw(rng: np.random.Generator, crane: cp.Crane, near_miss: float = 0.0):
    """(world, start state of the plant, script, plant crane, the runs' length in s)."""
    while True:
        world = cp.worlds.get(WORLDS[rng.integers(len(WORLDS))])
        plant = perturbed_crane(crane, load=rng.uniform(0.7, 1.3), friction=rng.uniform(0.8, 1.25),
                                supply=rng.uniform(0.95, 1.03))
        lc, tc, g = crane.lift_cylinder, crane.tilt_cylinder, crane.geometry
        try:
            start = cp.state_at_rest(plant, rng.uniform(0.1, 0.45) * lc.stroke_max / 0.535,
                                     rng.uniform(0.05, 0.7), slew=rng.uniform(-np.pi, np.pi),
                                     extension=rng.uniform(g.extension_min, 0.6))
        except ValueError:
            continue
        u = tuple(float(x) for x in np.round(rng.uniform(-0.8, 0.8, 4) * (rng.random(4) < 0.6), 2))
        if not any(u):
            continue
        inputs = cp.live.levers(*u)
        try:
            v = cp.guard(crane, world, start, inputs, NEAR_MISS_LOOK if near_miss else 5.0)
            rest = cp.guard(crane, world, start, cp.live.levers(), 0.5)
        except ValueError:
            continue
        if rest.contact is not None:
            continue
        script = LeverScript(((0.0, (0.0,) * 4), (0.3, u)))
        if near_miss:
            # the closest approach outside the margin by at most the band
            closest = min(v.clearance.values())
            if v.contact is None and world.margin < closest <= world.margin + near_miss:
                return world, start, script, plant, NEAR_MISS_RUN
        # clear of the margin at rest; the levers bring the crane within it 1.5-4 s ahead
        elif v.contact is not None and 1.5 <= v.contact.t <= 4.0:
            return world, start, script, plant, v.contact.t + 0.3 + 2.0


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--episodes", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--near-miss", type=float, default=0.0, metavar="BAND",
                    help="near-miss episodes: the closest approach within BAND m outside the margin")
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    crane = cp.Crane.patu655()
    rows = []
    t0, cpu0 = time.time(), time.process_time()
    try:
        _run(a, rng, crane, rows)
    except KeyboardInterrupt:       # Ctrl-C: the table of the episodes done so far
        print(f"\ninterrupted after {len(rows)} episodes")
    _summary(rows, time.time() - t0, time.process_time() - cpu0)


def _run(a: argparse.Namespace, rng: np.random.Generator, crane: cp.Crane, rows: list) -> None:
    for k in range(a.episodes):
        world, start, script, plant, seconds = draw(rng, crane, a.near_miss)
        ign = run_episode(crane, world, start, script, seconds, obey=False, plant_crane=plant, seed=k)
        obe = run_episode(crane, world, start, script, seconds, obey=True, plant_crane=plant, seed=k)
        t_hit = None
        if ign.collided:
            t_hit = float(ign.contact.rsplit("t = ", 1)[1].split(" s")[0])
        needless = obe.first_stop is not None and ign.min_clearance > world.margin
        # the stricter count: a STOP although the ignored run never touched (it may have come
        # within the margin, which the guard is there to keep)
        untouched = obe.first_stop is not None and not ign.collided
        faults = {}
        for v in obe.verdicts:
            if v.signal == "FAULT" and v.fault != "settling":
                faults[v.fault] = faults.get(v.fault, 0) + 1
        rows.append({"episode": k, "world": world.name, "margin": world.margin, "levers": script.steps[1][1],
                     "ignored_collided": ign.collided, "ignored_contact": ign.contact,
                     "ignored_min_clearance": ign.min_clearance,
                     "obeyed_min_clearance": obe.min_clearance, "obeyed_collided": obe.collided, "obeyed_contact": obe.contact,
                     "first_stop": obe.first_stop, "needless_stop": needless,
                     "stop_without_touch": untouched, "faults": faults,
                     "stop_cycles": obe.counts.get("STOP", 0)})
        print(f"{k:3d} {world.name:13s} levers {script.steps[1][1]} ignored: "
              f"{ign.contact or 'no contact'} (min {ign.min_clearance:.2f} m); obeyed: {obe.contact or 'no contact'} (min {obe.min_clearance:.2f} m); first STOP "
              f"{obe.first_stop}; faults {faults}", flush=True)
        if a.json:                  # after every episode: an interrupted run keeps what it did
            with open(a.json, "w") as f:
                json.dump(rows, f, indent=1)


def _summary(rows: list, wall: float, cpu: float) -> None:
    n = len(rows)
    if not n:
        return
    print(f"\n{n} episodes ({wall:.0f} s wall, {cpu:.0f} s CPU)")
    print(f"collisions, interlock ignored: {sum(r['ignored_collided'] for r in rows)}")
    print(f"collisions, interlock obeyed:  {sum(r['obeyed_collided'] for r in rows)}")
    print(f"prevented:                     {sum(r['ignored_collided'] and not r['obeyed_collided'] for r in rows)}")
    print(f"needless STOPs:                {sum(r['needless_stop'] for r in rows)} "
          f"(the ignored run never within the margin)")
    print(f"STOPs, ignored run untouched:  {sum(r['stop_without_touch'] for r in rows)} "
          f"(it came within the margin without touching)")
    print(f"obeyed runs within the margin: {sum(r['obeyed_min_clearance'] <= r['margin'] for r in rows)} "
          f"(smallest clearance {min(r['obeyed_min_clearance'] for r in rows):.3f} m)")
    print(f"episodes with a FAULT (not settling): {sum(bool(r['faults']) for r in rows)}; by kind: "
          f"{ {k: sum(r['faults'].get(k, 0) for r in rows) for k in sorted({k for r in rows for k in r['faults']})} }")


if __name__ == "__main__":
    main()
