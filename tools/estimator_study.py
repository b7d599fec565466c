"""The estimator against a known truth: a simulated crane whose load is 30 % off the crane file's,
strokes with 0.2 mm and pressures with 2 bar of noise at 100 Hz. Prints, per estimated state, the
RMS and worst error of the estimate and (for measured fields) of the raw sensor.

    python tools/estimator_study.py [--seconds 6] [--seed 1] [--friction 1.0] [--supply 1.0]
                                    [--jacobian-columns 4]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import cranepredict as cp
from cranepredict.live.estimator import EKF, ESTIMATED, JACOBIAN_COLUMNS
from cranepredict.live.sim import LeverScript, Plant, SensorModel, SimCrane, perturbed_crane

#: The lever script: lift up, tilt out, slew and extend, then reverse, then let go.
SCRIPT = LeverScript(((0.0, (0.0, 0.0, 0.0, 0.0)), (0.3, (0.6, 0.0, 0.0, 0.0)),
                      (1.2, (0.6, 0.5, 0.3, 0.0)), (2.4, (-0.4, 0.5, 0.0, 0.6)),
                      (3.6, (-0.5, -0.4, -0.3, -0.6)), (4.8, (0.0, 0.0, 0.0, 0.0))))


def run(seconds: float = 6.0, seed: int = 1, load: float = 1.3, friction: float = 1.0,
        supply: float = 1.0, sensors=None, jacobian_columns: int = JACOBIAN_COLUMNS):
    crane = cp.Crane.patu655()
    truth_crane = perturbed_crane(crane, load=load, friction=friction, supply=supply)
    start = cp.state_at_rest(truth_crane, 0.25, 0.35, slew=0.0, extension=0.3)
    sensors = sensors or cp.live.default_sensors()
    sim = SimCrane(Plant(truth_crane, start), SCRIPT, SensorModel(sensors, seed=seed))
    ekf = EKF(crane, sensors, jacobian_columns=jacobian_columns)
    rows, walls = [], []
    for _ in range(int(round(seconds / sim.period)) + 1):
        m = sim.measurement()
        t0 = time.perf_counter()
        est = ekf.update(m)
        walls.append(time.perf_counter() - t0)
        truth = sim.plant.state
        rows.append((m, est, truth))
        sim.step(allowed=True)
    return rows, np.array(walls[1:]), ekf


def table(rows, settle: float = 0.5):
    out = {}
    for name in ESTIMATED:
        err, raw = [], []
        for m, est, truth in rows:
            if m.t < settle:
                continue
            err.append(getattr(est, name) - getattr(truth, name))
            if getattr(m, name) is not None:
                raw.append(getattr(m, name) - getattr(truth, name))
        err = np.array(err)
        raw = np.array(raw) if raw else None
        out[name] = (float(np.sqrt(np.mean(err**2))), float(np.abs(err).max()),
                     None if raw is None else float(np.sqrt(np.mean(raw**2))),
                     None if raw is None else float(np.abs(raw).max()))
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=6.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--load", type=float, default=1.3)
    ap.add_argument("--friction", type=float, default=1.0)
    ap.add_argument("--supply", type=float, default=1.0)
    ap.add_argument("--jacobian-columns", type=int, default=JACOBIAN_COLUMNS)
    a = ap.parse_args()
    rows, walls, ekf = run(a.seconds, a.seed, a.load, a.friction, a.supply,
                           jacobian_columns=a.jacobian_columns)
    scale = {"m": (1e3, "mm"), "rad": (1e3, "mrad"), "m/s": (1e3, "mm/s"), "rad/s": (1e3, "mrad/s"),
             "Pa": (1e-5, "bar")}
    print(f"plant: load x{a.load}, friction x{a.friction}, supply x{a.supply}; {a.seconds:g} s at 100 Hz, "
          f"seed {a.seed}; {a.jacobian_columns} Jacobian columns an update; errors after 0.5 s")
    print(f"{'state':18s} {'RMS':>9s} {'worst':>9s} {'raw RMS':>9s} {'raw worst':>9s}  unit")
    for name, (rms, worst, rrms, rworst) in table(rows).items():
        unit = "Pa" if "_p_" in name else ("rad/s" if name == "slew_rate" else
                                           "m/s" if name.endswith("rate") else "rad" if name == "slew" else "m")
        k, u = scale[unit]
        f = lambda v: "-" if v is None else f"{v * k:9.3f}"
        print(f"{name:18s} {f(rms)} {f(worst)} {f(rrms)} {f(rworst)}  {u}")
    print(f"update: median {np.median(walls) * 1e3:.2f} ms, p99 {np.percentile(walls, 99) * 1e3:.2f} ms; "
          f"projections into the state domain: {ekf.projections}")


if __name__ == "__main__":
    main()
