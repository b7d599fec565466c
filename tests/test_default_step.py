"""RK4's default step (method="rk4"; the default method is checked in tests/test_rosw.py) is the product (README, "Accuracy of the default step"): predict() without a
dt keeps the tip within 1 mm of a converged run, over every named scenario and random cases.

This is what chose cp.DEFAULT_DT (tools/dt_study.py has the full table): at 10 ms one random case
of this set misses (1.35 mm), at 5 ms the worst is 0.36 mm.
"""
import numpy as np
import pytest

import cranepredict as cp
from cranepredict.scenarios import random_case

TOL = 1e-3          # m, the worst tip error allowed at the default settings
DT_CONVERGED = 1e-4


def _worst(crane, initial, inputs, horizon):
    tr = cp.predict(crane, initial, inputs, horizon, method="rk4")
    ref = cp.predict(crane, initial, inputs, horizon, dt=DT_CONVERGED, method="rk4")
    k = np.rint(tr.t / DT_CONVERGED).astype(int)
    assert np.allclose(ref.t[k], tr.t, atol=1e-12)
    return float(np.max(np.linalg.norm(tr.tip - ref.tip[k], axis=1)))


@pytest.mark.parametrize("name", cp.scenarios.names())
def test_every_named_scenario_within_1_mm_at_the_default_step(name):
    s = cp.scenarios.get(name)
    assert _worst(s.crane, s.initial, s.inputs, s.horizon) <= TOL


def test_random_cases_within_1_mm_at_the_default_step():
    rng = np.random.default_rng(5)      # tools/dt_study.py's seed: the same 30 cases
    errors = [_worst(*random_case(rng, cp.Crane.patu655()), 2.0) for _ in range(30)]
    print(f"default dt {cp.DEFAULT_DT * 1e3:g} ms: worst {max(errors) * 1e3:.3f} mm, median "
          f"{np.median(errors) * 1e3:.4f} mm over {len(errors)} random cases")
    assert max(errors) <= TOL
