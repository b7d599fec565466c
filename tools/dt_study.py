#!/usr/bin/env python3
"""Tip error of the fast model (C core) against a converged run, for several RK4 steps.

Runs every named scenario and N random ones (loads 0-500 kg, strokes across their ranges, holds,
constant and sampled pressures, slew, extension; cranepredict.scenarios.random_case), 2 s each, and
prints the largest tip distance from a run at dt = 2e-5 s, per scenario and summarized. This is
how cranepredict.DEFAULT_DT was chosen (README, "Accuracy of the default step").

    python tools/dt_study.py [--random 20] [--seed 5]
"""
import argparse
import sys

import numpy as np

import cranepredict as cp
from cranepredict.scenarios import random_case

REF_DT = 2e-5
DTS = (1e-2, 5e-3, 4e-3, 2e-3, 1e-3, 5e-4)


def tip_error(crane, initial, inputs, dt, ref):
    tr = cp.predict(crane, initial, inputs, 2.0, dt=dt)
    k = np.rint(tr.t / REF_DT).astype(int)
    return float(np.max(np.linalg.norm(tr.tip - ref.tip[k], axis=1)))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--random", type=int, default=20)
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    cases = [(n, s.crane, s.initial, s.inputs) for n, s in
             ((n, cp.scenarios.get(n)) for n in cp.scenarios.names())
             if not s.spatial]   # the C core does not move the slew and the extension yet
    rng = np.random.default_rng(args.seed)
    for i in range(args.random):
        cases.append((f"random{i}",) + tuple(random_case(rng, cp.Crane.patu655())))
    print(f"{'tip error [mm] / dt [ms]':26s}" + "".join(f"{d * 1e3:9g}" for d in DTS))
    errors = []
    for name, crane, initial, inputs in cases:
        ref = cp.predict(crane, initial, inputs, 2.0, dt=REF_DT)
        row = [tip_error(crane, initial, inputs, d, ref) for d in DTS]
        errors.append(row)
        print(f"{name:26s}" + "".join(f"{e * 1e3:9.4f}" for e in row))
    e = np.array(errors) * 1e3
    for label, f in (("median", np.median), ("95th percentile", lambda a, axis: np.percentile(a, 95, axis=axis)),
                     ("worst", np.max)):
        print(f"{label:26s}" + "".join(f"{v:9.4f}" for v in f(e, axis=0)))
    print(f"({len(cases)} scenarios of 2 s; default dt = {cp.DEFAULT_DT * 1e3:g} ms)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
