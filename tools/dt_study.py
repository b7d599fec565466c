#!/usr/bin/env python3
"""Error of the fast model (C core) against a converged RK4 run, over RK4's step or the default
method's tolerance.

--method rk4 (the default):

Runs every named scenario (the spatial ones, which move the slew and the extension, included) and
random cases, 2 s each, and prints the largest tip distance from a run at dt = 2e-5 s, per case and
summarized: over all cases, and over the four-joint ones alone (the spatial scenarios, and the
random four-joint cases). This is how cranepredict.DEFAULT_DT was chosen (README, "Accuracy of
the default step").

  * N random planar cases (cranepredict.scenarios.random_case: loads 0-500 kg, strokes across their
    ranges, holds, constant and sampled pressures on lift and tilt, a random slew and extension,
    both held);
  * M random four-joint cases (random_case4 below; random_case drives lift and tilt only): loads
    0-500 kg, a random pose from rest on closed valves (cranepredict.state_at_rest), all four
    actuators valve-driven, each lever closed, constant or sampled in [-1, 1], the slew or the
    telescope moving.

    python tools/dt_study.py [--random 30] [--random4 10] [--seed 5]

--method default: the default method (error-controlled: ROS34PW2 for a stiff future, DOPRI5(4)
for the others) at several tip tolerances (the pressure tolerance scaled alike: the default's
ratio, 1e4 Pa per 5e-5 m), on every named scenario over its own horizon: the worst tip distance
and the worst chamber pressure difference from RK4 at dt = 2e-5 s (both on the 5-ms sample grid),
and the wall time per call (the best of 3) against RK4 at the default step, 5 ms; then the worst
tip distance over the N random planar cases (random_case, pressure drives). (The number of step
attempts is not reported by the API; the time is what it costs.)

    python tools/dt_study.py --method default [--random 60] [--seed 1]

--method harsh: the default method at its default tolerance over N futures of harsh levers
(harsh_case: taps of 3 ms to 0.3 s, slams between -1, 0 and +1, strokes on or 1 mm off their
stops, half of them four-joint): the worst tip, the worst chamber pressures of the booms and of
the slew and the telescope, each future over 1 mm or 0.5 bar, each more than 0.1 bar below a
chamber's cavitation pressure (with the converged run's figure) and each with a sample that is
not a valid State.

    python tools/dt_study.py --method harsh --random 320 --seed 1
"""
import argparse
import sys
import time
import warnings

import numpy as np

import cranepredict as cp
from cranepredict.scenarios import random_case

REF_DT = 2e-5
DTS = (1e-2, 5e-3, 4e-3, 2e-3, 1e-3, 5e-4)
HORIZON = 2.0
JOINTS = ("lift", "tilt", "slew", "extension")


TIP_TOLERANCES = (1e-4, 5e-5, 1e-5, 1e-6, 1e-7)     # m; 5e-5 is the default


def tip_error(crane, initial, inputs, dt, ref):
    tr = cp.predict(crane, initial, inputs, HORIZON, dt=dt, method="rk4")
    k = np.rint(tr.t / REF_DT).astype(int)
    return float(np.max(np.linalg.norm(tr.tip - ref.tip[k], axis=1)))


def _lever(rng):
    """A valve drive: closed, a constant lever or 2-6 lever samples over the horizon, in [-1, 1]."""
    kind = rng.integers(0, 3)
    if kind == 0:
        return cp.Valve(0.0)
    if kind == 1:
        return cp.Valve(float(rng.uniform(-1, 1)))
    n = int(rng.integers(2, 7))
    t = np.unique(np.concatenate([[0.0], np.sort(rng.uniform(0, HORIZON, n - 2)), [HORIZON]]))
    return cp.ValveSeries(t=t, u=rng.uniform(-1, 1, t.size))


def random_case4(rng, crane):
    """(crane, initial, inputs): a random four-joint, valve-driven case (see the module's text)."""
    sd, g = crane.slew_drive, crane.geometry
    while True:
        c = crane.with_load(float(rng.uniform(0, 500)))
        lc, tc = c.lift_cylinder, c.tilt_cylinder
        try:
            initial = cp.state_at_rest(
                c, float(rng.uniform(lc.stroke_min, lc.stroke_max)),
                float(rng.uniform(tc.stroke_min, tc.stroke_max)),
                slew=float(rng.uniform(sd.slew_min, sd.slew_max)),
                extension=float(rng.uniform(g.extension_min, g.extension_max)))
        except ValueError:      # the balance needs a pressure out of range at this pose
            continue
        drives = {j: _lever(rng) for j in JOINTS}
        if any(not (isinstance(drives[j], cp.Valve) and drives[j].u == 0.0) for j in ("slew", "extension")):
            return c, initial, cp.Inputs(**drives)


def _harsh_lever(rng):
    """A lever as an operator at its worst: fully open, closed or anywhere, held; 1-3 taps
    (3 ms to 0.3 s, ramps of 1 ms) to -1, +1 or anywhere from neutral; or 2-7 samples slamming
    between -1, 0 and +1."""
    kind = rng.integers(0, 3)
    if kind == 0:
        return cp.Valve(float(rng.choice([-1.0, 0.0, 1.0, rng.uniform(-1, 1)])))
    if kind == 1:
        t, u = [0.0], [0.0]
        for start in np.sort(rng.uniform(0.05, HORIZON - 0.1, int(rng.integers(1, 4)))):
            width = float(rng.choice([0.003, 0.01, 0.03, 0.1, 0.3]))
            level = float(rng.choice([-1.0, 1.0, rng.uniform(-1, 1)]))
            knots = ((start, 0.0), (start + 1e-3, level), (start + 1e-3 + width, level),
                     (start + 2e-3 + width, 0.0))
            if start > t[-1] and knots[-1][0] < HORIZON:
                for tk, uk in knots:
                    t.append(tk)
                    u.append(uk)
        return cp.ValveSeries(t=np.array(t + [HORIZON]), u=np.array(u + [0.0]))
    n = int(rng.integers(2, 8))
    t = np.unique(np.concatenate([[0.0], np.sort(rng.uniform(0, HORIZON, n - 2)), [HORIZON]]))
    return cp.ValveSeries(t=t, u=rng.choice([-1.0, 0.0, 1.0], t.size))


def harsh_case(rng, crane):
    """(crane, initial, inputs): harsh levers on lift and tilt (_harsh_lever); half the cases
    four-joint (random_case4's pose, slew and telescope levers), half planar from rest with the
    strokes anywhere, on their stops or 1 mm off them."""
    if rng.uniform() < 0.5:
        c, initial, inputs = random_case4(rng, crane)
        return c, initial, cp.Inputs(lift=_harsh_lever(rng), tilt=_harsh_lever(rng),
                                     slew=inputs.slew, extension=inputs.extension)
    while True:
        c = crane.with_load(float(rng.uniform(0, 500)))
        strokes = [float(rng.choice([rng.uniform(cyl.stroke_min, cyl.stroke_max), cyl.stroke_min,
                                     cyl.stroke_max, cyl.stroke_min + 1e-3, cyl.stroke_max - 1e-3]))
                   for cyl in (c.lift_cylinder, c.tilt_cylinder)]
        try:
            initial = cp.state_at_rest(c, *strokes)
        except ValueError:      # the balance needs a pressure out of range at this pose
            continue
        return c, initial, cp.Inputs(lift=_harsh_lever(rng), tilt=_harsh_lever(rng))


def _best_time(f, repeat=3):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
    return best, out


def default_study(n_random: int, seed: int) -> int:
    """The default method's errors and cost over its tolerance, per named scenario, then over
    random planar cases."""
    warnings.simplefilter("ignore", UserWarning)     # the supply-short warnings of some scenarios
    default = cp.default_tolerance()
    per_tip = default.pressure / default.tip
    every = round(cp.DEFAULT_DT / REF_DT)
    print(f"{'tip mm / bar; tol [m]':22s}" + "".join(f"{t:>16g}" for t in TIP_TOLERANCES)
          + f"{'t def/rk4 ms':>16s}")
    worst = np.zeros((len(TIP_TOLERANCES), 2))
    times = np.zeros(len(TIP_TOLERANCES))
    time_rk4 = 0.0
    names = cp.scenarios.names()
    for n in names:
        s = cp.scenarios.get(n)
        args = (s.crane, s.initial, s.inputs, s.horizon)
        ref = cp.predict(*args, dt=REF_DT, method="rk4", sample_every=every)
        t_rk4, _ = _best_time(lambda: cp.predict(*args, method="rk4"))
        time_rk4 += t_rk4
        cells = []
        for i, tip in enumerate(TIP_TOLERANCES):
            tol = cp.Tolerance(tip=tip, pressure=tip * per_tip)
            t, tr = _best_time(lambda: cp.predict(*args, tolerance=tol))
            assert np.allclose(tr.t, ref.t, rtol=0, atol=1e-12)
            e_tip = float(np.max(np.linalg.norm(tr.tip - ref.tip, axis=1)))
            e_p = float(max(np.max(np.abs(tr.p_a - ref.p_a)), np.max(np.abs(tr.p_b - ref.p_b))))
            worst[i] = np.maximum(worst[i], (e_tip, e_p))
            times[i] += t
            if tip == default.tip:
                t_default = t
            cells.append(f"{e_tip * 1e3:8.4f}/{e_p / 1e5:7.4f}")
        print(f"{n:22s}" + "".join(f"{c:>16s}" for c in cells)
              + f"{t_default * 1e3:8.2f}/{t_rk4 * 1e3:.2f}", flush=True)
    horizon = sum(cp.scenarios.get(n).horizon for n in names)
    print(f"{'worst tip, mm':22s}" + "".join(f"{w * 1e3:16.4f}" for w in worst[:, 0]))
    print(f"{'worst pressure, bar':22s}" + "".join(f"{w / 1e5:16.4f}" for w in worst[:, 1]))
    print(f"{'time, all, ms':22s}" + "".join(f"{t * 1e3:16.1f}" for t in times)
          + f"   (RK4 at {cp.DEFAULT_DT * 1e3:g} ms: {time_rk4 * 1e3:.1f})")
    print(f"{'x real time':22s}" + "".join(f"{horizon / t:16.0f}" for t in times)
          + f"   (RK4: {horizon / time_rk4:.0f})")
    print(f"({len(names)} named scenarios, {horizon:g} s of futures; pressure tolerance "
          f"{per_tip:g} Pa per m of tip tolerance; default tip tolerance {default.tip:g} m; "
          f"converged run: RK4 at dt = {REF_DT * 1e3:g} ms)")
    rng = np.random.default_rng(seed)
    worst_random = np.zeros(len(TIP_TOLERANCES))
    for _ in range(n_random):
        crane, initial, inputs = random_case(rng, cp.Crane.patu655())
        ref = cp.predict(crane, initial, inputs, HORIZON, dt=REF_DT, method="rk4",
                         sample_every=every)
        for i, tip in enumerate(TIP_TOLERANCES):
            tol = cp.Tolerance(tip=tip, pressure=tip * per_tip)
            tr = cp.predict(crane, initial, inputs, HORIZON, tolerance=tol)
            worst_random[i] = max(worst_random[i],
                                  float(np.max(np.linalg.norm(tr.tip - ref.tip, axis=1))))
    print(f"{'random, worst tip mm':22s}" + "".join(f"{w * 1e3:16.4f}" for w in worst_random)
          + f"   ({n_random} random planar cases, seed {seed})")
    return 0


FLOOR_SLACK = 0.1e5   # Pa below a chamber's cavitation pressure (tests/test_chamber_floor.py)


def harsh_study(n: int, seed: int) -> int:
    """The default method at its default tolerance over n harsh lever futures (harsh_case): the
    worst tip, the worst chamber pressure of the booms and of the slew and telescope, and the
    futures over 1 mm or 0.5 bar."""
    warnings.simplefilter("ignore", UserWarning)
    every = round(cp.DEFAULT_DT / REF_DT)
    rng = np.random.default_rng(seed)
    worst = {"tip": (0.0, -1), "booms": (0.0, -1), "slew, telescope": (0.0, -1)}
    over, under, invalid, lowest = 0, 0, 0, float("inf")
    for k in range(n):
        crane, initial, inputs = harsh_case(rng, cp.Crane.patu655())
        ref = cp.predict(crane, initial, inputs, HORIZON, dt=REF_DT, method="rk4",
                         sample_every=every)
        tr = cp.predict(crane, initial, inputs, HORIZON)
        try:
            for i in range(tr.t.size):
                tr.state(i)      # ValueError if a sample is not a valid State
        except ValueError as e:
            invalid += 1
            print(f"case {k}: {e}", flush=True)
        for j, (joint, actuator) in enumerate(zip(("lift", "tilt", "slew", "extension"), (
                crane.lift_cylinder, crane.tilt_cylinder, crane.slew_drive,
                crane.extension_cylinder))):
            if isinstance(getattr(inputs, joint), (cp.Valve, cp.ValveSeries)):  # its chambers
                low = float(min(tr.p_a[:, j].min(), tr.p_b[:, j].min()))
                below = low - actuator.hydraulics.cavitation_pressure
                low_ref = float(min(ref.p_a[:, j].min(), ref.p_b[:, j].min()))
                if below < -FLOOR_SLACK:
                    under += 1
                    print(f"case {k}: the {joint}'s chamber {-below / 1e5:.3f} bar below its "
                          f"cavitation pressure (the converged run: "
                          f"{(actuator.hydraulics.cavitation_pressure - low_ref) / 1e5:.3f} bar)",
                          flush=True)
                lowest = min(lowest, below)
        dp = np.maximum(np.abs(tr.p_a - ref.p_a), np.abs(tr.p_b - ref.p_b)).max(axis=0)
        errors = {"tip": float(np.max(np.linalg.norm(tr.tip - ref.tip, axis=1))),
                  "booms": float(dp[:2].max()), "slew, telescope": float(dp[2:].max())}
        for key, e in errors.items():
            if e > worst[key][0]:
                worst[key] = (e, k)
        if errors["tip"] > 1e-3 or max(errors["booms"], errors["slew, telescope"]) > 0.5e5:
            over += 1
            print(f"case {k}: tip {errors['tip'] * 1e3:.3f} mm, booms {errors['booms'] / 1e5:.2f} "
                  f"bar, slew and telescope {errors['slew, telescope'] / 1e5:.2f} bar", flush=True)
    print(f"{n} harsh lever futures (seed {seed}): worst tip {worst['tip'][0] * 1e3:.3f} mm "
          f"(case {worst['tip'][1]}), booms' pressures {worst['booms'][0] / 1e5:.2f} bar (case "
          f"{worst['booms'][1]}), slew's and telescope's {worst['slew, telescope'][0] / 1e5:.2f} "
          f"bar (case {worst['slew, telescope'][1]}); {over} over 1 mm or 0.5 bar; lowest chamber "
          f"{lowest / 1e5:+.3f} bar from its cavitation pressure, {under} futures more than "
          f"{FLOOR_SLACK / 1e5:g} bar below it; {invalid} with a sample that is not a valid State")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--method", choices=("rk4", "default", "harsh"), default="rk4",
                    help="rk4: sweep RK4's step; default: sweep the default method's "
                         "tolerance (named scenarios, then random planar cases); harsh: the "
                         "default method over --random harsh lever futures")
    ap.add_argument("--random", type=int, default=30, help="random planar cases (random_case)")
    ap.add_argument("--random4", type=int, default=10, help="random four-joint valve-driven cases")
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    if args.method == "default":
        return default_study(args.random, args.seed)
    if args.method == "harsh":
        return harsh_study(args.random, args.seed)
    cases = []   # (name, four-joint?, crane, initial, inputs)
    for n in cp.scenarios.names():
        s = cp.scenarios.get(n)
        cases.append((n, s.spatial, s.crane, s.initial, s.inputs))
    rng = np.random.default_rng(args.seed)
    for i in range(args.random):
        cases.append((f"random{i}", False) + tuple(random_case(rng, cp.Crane.patu655())))
    rng4 = np.random.default_rng(args.seed + 1000)
    for i in range(args.random4):
        cases.append((f"random4-{i}", True) + tuple(random_case4(rng4, cp.Crane.patu655())))
    print(f"{'tip error [mm] / dt [ms]':26s}" + "".join(f"{d * 1e3:9g}" for d in DTS))
    errors = []
    for name, _, crane, initial, inputs in cases:
        ref = cp.predict(crane, initial, inputs, HORIZON, dt=REF_DT, method="rk4")
        row = [tip_error(crane, initial, inputs, d, ref) for d in DTS]
        errors.append(row)
        print(f"{name:26s}" + "".join(f"{e * 1e3:9.4f}" for e in row), flush=True)
    e = np.array(errors) * 1e3
    four = np.array([c[1] for c in cases])
    named4 = np.array([c[1] and not c[0].startswith("random4-") for c in cases])
    groups = ((f"all {len(cases)} cases", np.ones(len(cases), bool)),
              (f"planar ({int((~four).sum())})", ~four),
              (f"four-joint ({int(four.sum())})", four),
              (f"spatial scenarios ({int(named4.sum())})", named4),
              (f"random four-joint ({int((four & ~named4).sum())})", four & ~named4))
    for title, sel in groups:
        if not sel.any():
            continue
        print(f"-- {title}")
        for label, f in (("median", np.median),
                         ("95th percentile", lambda a, axis: np.percentile(a, 95, axis=axis)),
                         ("worst", np.max)):
            print(f"{label:26s}" + "".join(f"{v:9.4f}" for v in f(e[sel], axis=0)))
    print(f"({len(cases)} cases of {HORIZON:g} s; default dt = {cp.DEFAULT_DT * 1e3:g} ms; "
          f"converged run at dt = {REF_DT * 1e3:g} ms)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
