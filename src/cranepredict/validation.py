"""The fast model against the Exudyn references (install extra ``[reference]``; docs/validation.md):
the comparison ``cranepredict validate`` and the tests run.

:func:`compare` runs one scenario on the fast model and on the reference that fits it (the planar
:mod:`cranepredict.reference` while the slew and the extension are held, the spatial
:mod:`cranepredict.reference_spatial` when either moves) and measures the tip and chamber-pressure
errors against the targets; :func:`compare_all` does so for each scenario in turn and
:func:`table` prints the rows as ``cranepredict validate`` shows them.
"""

from __future__ import annotations

import time
from typing import List, Optional

import numpy as np

from . import reference, reference_spatial
from .reference import DEFAULT_REFERENCE_DT
from .reference_common import is_valve
from .types import Hold

__all__ = ["compare", "compare_all", "table", "tip_errors", "TARGET_MAX_MM", "TARGET_RMS_MM",
           "TARGET_SPEED_RATIO", "TARGET_PRESSURE_RMS_BAR"]

#: The fast model's targets against the reference (docs/validation.md), used by ``cranepredict
#: validate`` and the tests: per scenario a tip error of at most 20 mm (max) and 10 mm (RMS), and
#: the fast model at least 100 times faster.
TARGET_MAX_MM = 20.0
TARGET_RMS_MM = 10.0
TARGET_SPEED_RATIO = 100.0
#: and for valve-driven cylinders a chamber-pressure RMS error of at most 2 bar (the validation targets).
TARGET_PRESSURE_RMS_BAR = 2.0


def tip_errors(t: np.ndarray, tip: np.ndarray, ref) -> np.ndarray:
    """(N,) distance, m, between the tip ``tip`` (N, 3) at times ``t`` and the reference's tip
    (``ref.t``, ``ref.tip``) linearly interpolated onto them."""
    tip_ref = np.stack([np.interp(t, ref.t, ref.tip[:, i]) for i in range(3)], 1)
    return np.linalg.norm(tip_ref - tip, axis=1)


def compare(scenario, *, dt_ref: float = DEFAULT_REFERENCE_DT, dt_fast: Optional[float] = None,
            repeat_fast: int = 21, backend: str = "c") -> dict:
    """Runs a scenario on the fast model (``backend``) and on the reference; the tip error (m) is
    measured at the fast model's samples (the reference tip linearly interpolated onto them).
    "Before/after the stop" splits at the first sample where either model is at an end stop (None:
    no stop). For valve-driven cylinders the chamber pressures are compared the same way:
    ``pressure_rms_bar`` is the largest RMS over their chambers (None: no valve drive). A scenario
    that drives the slew or the extension runs on the spatial reference
    (:mod:`cranepredict.reference_spatial`; its constraint residual is not reported: None);
    ``reference`` says which ("planar" or "spatial"). ``within_targets``: the tip max, tip RMS and
    (valve drives) pressure RMS within TARGET_MAX_MM, TARGET_RMS_MM, TARGET_PRESSURE_RMS_BAR."""
    from . import api

    sc = scenario
    fast = api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_fast, backend=backend)
    walls = []
    for _ in range(repeat_fast):
        t0 = time.perf_counter()
        api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_fast, backend=backend)
        walls.append(time.perf_counter() - t0)
    wall_fast = float(np.median(walls))
    joints = ("lift", "tilt", "slew", "extension")
    drives = [getattr(sc.inputs, n, None) or Hold() for n in joints]
    if any(not isinstance(d, Hold) for d in drives[2:]):
        # the slew or the extension moves: the spatial reference (3D bodies, four actuators)
        run = reference_spatial.simulate(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_ref)
        ref, residual, kind = run, None, "spatial"
    else:
        run = reference.simulate(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_ref)
        ref, residual, kind = run.trajectory, run.residual_max, "planar"
    err = tip_errors(fast.t, fast.tip, ref)
    stops = [x for x in (fast.t[np.flatnonzero(fast.stop.any(1))[:1]].tolist()
                         + ref.t[np.flatnonzero(ref.stop.any(1))[:1]].tolist())]
    t_stop = min(stops) if stops else None
    before = err if t_stop is None else err[fast.t < t_stop]
    after = None if t_stop is None else err[fast.t >= t_stop]

    def mx(a):
        return None if a is None or a.size == 0 else float(a.max())

    p_rms = {}
    for j in (j for j, d in enumerate(drives) if is_valve(d)):
        for ch in ("p_a", "p_b"):
            dp = np.interp(fast.t, ref.t, getattr(ref, ch)[:, j]) - getattr(fast, ch)[:, j]
            p_rms[f"{joints[j]}.{ch}"] = float(np.sqrt(np.mean(dp ** 2))) / 1e5

    max_mm, rms_mm = float(err.max()) * 1e3, float(np.sqrt(np.mean(err**2))) * 1e3
    p_worst = max(p_rms.values()) if p_rms else None
    within = (max_mm <= TARGET_MAX_MM and rms_mm <= TARGET_RMS_MM
              and (p_worst is None or p_worst <= TARGET_PRESSURE_RMS_BAR))
    return {"name": sc.name, "tags": list(sc.tags), "horizon": sc.horizon, "reference": kind,
            "max_error_mm": max_mm, "rms_error_mm": rms_mm,
            "max_error_before_stop_mm": None if mx(before) is None else mx(before) * 1e3,
            "max_error_after_stop_mm": None if mx(after) is None else mx(after) * 1e3,
            "first_stop_time_s": t_stop,
            "stop_time_fast_s": stops[0] if fast.stop.any() else None,
            "wall_fast_s": wall_fast, "wall_reference_s": run.wall,
            "speed_ratio": run.wall / wall_fast,
            "constraint_residual_m": residual,
            "pressure_rms_bar": p_worst,
            "pressure_rms_by_chamber_bar": p_rms, "backend": backend,
            "dt_fast_s": api.DEFAULT_DT if dt_fast is None else float(dt_fast), "dt_reference_s": dt_ref,
            "within_targets": within,
            "_fast": fast, "_ref": ref, "_err": err}


def compare_all(scenarios, *, dt_ref: float = DEFAULT_REFERENCE_DT, backend: str = "c") -> List[dict]:
    """:func:`compare` on each scenario in turn (the fast model at its default step)."""
    return [compare(sc, dt_ref=dt_ref, backend=backend) for sc in scenarios]


def table(rows: List[dict], dt_ref: float) -> List[str]:
    """The lines ``cranepredict validate`` prints: a row per scenario (the reference used, the tip
    errors, the pressure RMS, the wall times, whether it met the targets), the targets, and the
    scenarios that missed them."""
    def f(v, fmt):
        return "-" if v is None else format(v, fmt)

    out = [f"fast model: C core, dt {rows[0]['dt_fast_s']:g} s; reference: Exudyn, dt {dt_ref:g} s "
           "(planar: slew and extension held; spatial: either moves)",
           f"{'scenario':22s} {'ref':>7s} {'max mm':>8s} {'rms mm':>8s} {'pre-stop':>9s} {'post-stop':>9s} "
           f"{'stop s':>6s} {'p rms bar':>9s} {'fast ms':>8s} {'ref s':>6s} {'ratio':>6s} {'targets':>7s}"]
    for r in rows:
        out.append(f"{r['name']:22s} {r['reference']:>7s} {r['max_error_mm']:8.3f} {r['rms_error_mm']:8.3f} "
                   f"{f(r['max_error_before_stop_mm'], '9.3f'):>9s} {f(r['max_error_after_stop_mm'], '9.3f'):>9s} "
                   f"{f(r['first_stop_time_s'], '6.3f'):>6s} {f(r['pressure_rms_bar'], '9.4f'):>9s} "
                   f"{r['wall_fast_s'] * 1e3:8.3f} "
                   f"{r['wall_reference_s']:6.2f} {r['speed_ratio']:6.0f} "
                   f"{'met' if r['within_targets'] else 'MISSED':>7s}")
    out.append(f"targets per scenario: max <= {TARGET_MAX_MM:g} mm, RMS <= "
               f"{TARGET_RMS_MM:g} mm, chamber pressures RMS <= "
               f"{TARGET_PRESSURE_RMS_BAR:g} bar (valve drives); speed ratio >= "
               f"{TARGET_SPEED_RATIO:g} (see docs/validation.md)")
    missed = [r["name"] for r in rows if not r["within_targets"]]
    if missed:
        out.append(f"missed the targets: {', '.join(missed)}")
    return out
