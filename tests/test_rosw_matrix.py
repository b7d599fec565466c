"""ROS34PW2's matrix J (docs/model.md, "The matrix J") against the model it linearises: the
chambers' rows of J are the derivatives of the chambers' rates in their own pressures, the joint
rates and the spool, exactly (J leaves out only the slopes through the configuration). Checked
against central finite differences of the twin's rates at random states, on both valves and on
every branch of their flow laws (supply or tank side, laminar or turbulent, the compensated valve's
dead band and saturation). The C core's J is the twin's: their results agree to rounding
(test_c_vs_twin), and a W-method's result depends on its J."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import cranepredict as cp
from cranepredict.twin._internal import HYD, SPOOL
from cranepredict.twin.predict import TwinModel, _drive, _initial_state, _Prediction
from cranepredict.twin.rosw import _Rosw


def _crane(valve: str) -> cp.Crane:
    crane = cp.Crane.patu655()
    if valve == "orifice":
        return crane
    comp = dict(valve="compensated", dead_band=0.114,
                meter_out_flow=crane.lift_cylinder.hydraulics.nominal_flow,
                meter_out_pressure_drop=7e5)
    for j in ("lift", "tilt"):
        cyl = getattr(crane, f"{j}_cylinder")
        crane = dataclasses.replace(crane, **{f"{j}_cylinder": dataclasses.replace(
            cyl, hydraulics=dataclasses.replace(cyl.hydraulics, **comp))})
    return crane


def _prediction(crane: cp.Crane, state: cp.State, inputs: cp.Inputs) -> tuple:
    model = TwinModel(crane, state.extension)
    drives = (_drive(inputs.lift, crane.lift_cylinder), _drive(inputs.tilt, crane.tilt_cylinder),
              None, None)
    pred = _Prediction(model, drives)
    x = _initial_state(pred, state)[0]
    return pred, x


def _random_case(rng: np.random.Generator, crane: cp.Crane) -> tuple:
    """A free pose (both strokes off their stops), random rates, pressures across supply and tank
    (some within the laminar drop of either: the cubic branch), spools across [-1, 1] with the
    dead band hit now and then, and a spool lag (the spool is then a state)."""
    h = crane.lift_cylinder.hydraulics
    p_s, p_t = h.supply_pressure, h.tank_pressure
    near = rng.uniform(-0.6, 0.6, 4) * h.laminar_pressure_drop

    def pressure(k: int) -> float:
        kind = rng.integers(0, 3)
        base = (p_s, p_t, rng.uniform(p_t, p_s))[kind]
        return float(min(max(base + near[k] if kind < 2 else base, 2e5), 3.0e7))

    lag = dict(spool_time_constant=0.03)
    for j in ("lift", "tilt"):
        cyl = getattr(crane, f"{j}_cylinder")
        crane = dataclasses.replace(crane, **{f"{j}_cylinder": dataclasses.replace(
            cyl, hydraulics=dataclasses.replace(cyl.hydraulics, **lag))})
    spools = rng.choice([-1.0, 1.0], 2) * rng.uniform(0.0, 1.0, 2)
    strokes = [float(rng.uniform(c.stroke_min + 0.05, c.stroke_max - 0.05))
               for c in (crane.lift_cylinder, crane.tilt_cylinder)]
    state = cp.State(lift_stroke=strokes[0], tilt_stroke=strokes[1],
                     lift_stroke_rate=float(rng.uniform(-0.05, 0.05)),
                     tilt_stroke_rate=float(rng.uniform(-0.05, 0.05)),
                     lift_p_a=pressure(0), lift_p_b=pressure(1), tilt_p_a=pressure(2),
                     tilt_p_b=pressure(3), lift_spool=float(spools[0]), tilt_spool=float(spools[1]))
    inputs = cp.Inputs(lift=cp.Valve(float(rng.uniform(-1, 1))), tilt=cp.Valve(float(rng.uniform(-1, 1))))
    return crane, state, inputs


@pytest.mark.parametrize("valve", ["orifice", "compensated"])
def test_the_chambers_rows_of_J_are_the_rates_derivatives(valve):
    rng = np.random.default_rng(17 if valve == "orifice" else 18)
    worst = 0.0
    for _ in range(40):
        crane, state, inputs = _random_case(rng, _crane(valve))
        pred, x = _prediction(crane, state, inputs)
        ros = _Rosw(pred, 5e-5, 1e4)
        f0 = ros.rates(0.0, x)
        if ros.modes(x, f0):        # a relief or anti-cavitation valve open: its mode too
            f0 = ros.rates(0.0, x)
        J = ros.matrix(0.0, x)
        for j in (0, 1):
            rows = (HYD + 2 * j, HYD + 2 * j + 1)
            columns = {"p_a": HYD + 2 * j, "p_b": HYD + 2 * j + 1, "omega": 4 + j,
                       "spool": SPOOL + j}
            for name, c in columns.items():
                step = {"p_a": 1.0, "p_b": 1.0, "omega": 1e-7, "spool": 1e-7}[name]
                lo, hi = list(x), list(x)
                lo[c] -= step
                hi[c] += step
                fd = (np.asarray(ros.rates(0.0, tuple(hi))) -
                      np.asarray(ros.rates(0.0, tuple(lo)))) / (2 * step)
                for r in rows:
                    scale = max(abs(fd[r]), abs(J[r, c]), 1e-3 * max(abs(J[r, r]), 1.0))
                    err = abs(J[r, c] - fd[r]) / scale
                    worst = max(worst, err)
                    assert err < 1e-4, (f"{valve}: J[{r}, {name}] = {J[r, c]:.6g}, finite "
                                        f"difference {fd[r]:.6g} (state {state}, inputs {inputs})")
    print(f"{valve}: J's chamber rows vs finite differences, worst relative {worst:.1e}")
