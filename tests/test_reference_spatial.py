"""The twin's four-joint motion against the spatial Exudyn reference (issue 11's scenarios): 3D rigid
bodies with full tensors, engine joints (slew revolute, prismatic extension, the four-bar closed by
constraints), force elements for the actuators; generalized-alpha at 0.25 ms. Targets as for the
planar scenarios: tip max <= 20 mm, RMS <= 10 mm at the twin's default step (2 ms).

The reference has no end stops, so the scenarios stay inside every range (the reference raises if
one is left); the telescope into its end stop is checked by hand in tests/test_four_joints.py.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import reference_spatial as rs
from test_four_joints import _run4

pytestmark = pytest.mark.skipif(not rs.available(), reason="the spatial reference needs Exudyn ([reference] extra)")

H = cp.Hold()
TIP_MAX = 20e-3
TIP_RMS = 10e-3


def _holding_lift(crane, lift, tilt, extension):
    return cp.holding_pressure(crane, cp.State(lift_stroke=lift, tilt_stroke=tilt, extension=extension),
                               joint="lift")


def _scenarios():
    crane = cp.Crane.patu655()
    heavy = crane.with_load(500.0)
    lift_p = _holding_lift(crane, 0.25, 0.4, 0.5) * 1.08
    reverse = cp.PressureSeries(t=[0.0, 0.8, 0.9, 2.0], p_a=[80e5, 80e5, 0.0, 0.0], p_b=[0.0, 0.0, 80e5, 80e5])
    return {
        # name: (crane, (lift, tilt, slew, extension), drives)
        "slewing-while-lifting": (crane, (0.25, 0.4, 0.0, 0.5),
                                  {"lift": cp.Pressure(lift_p, 0.0), "tilt": H, "extension": H,
                                   "slew": cp.Pressure(60e5, 0.0)}),
        "extending-while-slewing": (crane, (0.30, 0.10, 0.0, 0.1),
                                    {"lift": H, "tilt": H, "extension": cp.Pressure(2.1e5, 0.0),
                                     "slew": cp.Pressure(40e5, 0.0)}),
        "stopping-a-slew-load-out": (heavy, (0.30, 0.05, 0.0, 1.0),
                                     {"lift": H, "tilt": H, "extension": H, "slew": reverse}),
        "slewing-folded": (crane, (0.05, 0.75, 0.0, 0.0),
                           {"lift": H, "tilt": H, "extension": H, "slew": cp.Pressure(20e5, 0.0)}),
        "slewing-stretched": (crane, (0.30, 0.05, 0.0, 1.0),
                              {"lift": H, "tilt": H, "extension": H, "slew": cp.Pressure(20e5, 0.0)}),
    }


def _compare(crane, start, drives, horizon=2.0, twin_crane=None):
    lift, tilt, slew, extension = start
    arrays, events = _run4(twin_crane or crane, horizon, 2e-3, lift=lift, tilt=tilt, slew=slew,
                           extension=extension, drives=drives)
    assert not events, "the spatial reference has no end stops: the scenario must stay inside"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        run = rs.simulate(crane, lift, tilt, slew, extension, drives, horizon)
    assert run.t.shape == arrays["t"].shape and np.allclose(run.t, arrays["t"], atol=1e-9)
    err = np.linalg.norm(run.tip - arrays["tip"], axis=1)
    return arrays, run, float(err.max()), float(np.sqrt(np.mean(err ** 2)))


@pytest.mark.parametrize("name", list(_scenarios()))
def test_twin_agrees_with_the_spatial_reference(name):
    crane, start, drives = _scenarios()[name]
    arrays, run, tip_max, tip_rms = _compare(crane, start, drives)
    print(f"{name}: tip max {tip_max * 1e3:.4f} mm, RMS {tip_rms * 1e3:.4f} mm, "
          f"slew {arrays['slew'][-1]:.4f} rad, reference {run.wall_time:.1f} s")
    assert np.ptp(arrays["slew"]) > 0.1                       # the crane slews
    assert np.max(np.linalg.norm(arrays["tip"] - arrays["tip"][0], axis=1)) > 0.5
    assert tip_max <= TIP_MAX and tip_rms <= TIP_RMS
    assert np.max(np.abs(run.extension - arrays["extension"])) < 1e-3


def test_spatial_reference_tells_a_wrong_slew_inertia():
    """The comparison has teeth: a twin whose pillar weighs 200 kg more (J_z + 200 x^2 with the
    centre moved out to 1 m) misses the folded crane's tip by several times the target."""
    import dataclasses

    crane, start, drives = _scenarios()["slewing-folded"]
    wrong = dataclasses.replace(crane, pillar=dataclasses.replace(crane.pillar, mass=crane.pillar.mass + 200.0,
                                                                  com=(1.0, crane.pillar.com[1])))
    _, _, tip_max, _ = _compare(crane, start, drives, twin_crane=wrong)
    assert tip_max > 5 * TIP_MAX                             # 187 mm


def _extension_near_holding(crane, start, k):
    """k times the pressure that holds the extension boom and the load against gravity along the
    outer boom (bore side if the boom points up, rod side if down)."""
    from cranepredict import twin

    model = twin.TwinModel(crane, 0.0)
    slope = math.sin(model.lift_angle(start[0])[0] + model.tilt_angle(start[1])[0])
    force = (crane.extension_boom.mass + crane.load_mass) * crane.gravity * slope
    ec = crane.extension_cylinder
    return cp.Pressure(k * force / ec.area_a, 0.0) if force > 0 else cp.Pressure(0.0, -k * force / ec.area_b)


def _random_cases(n, seed):
    """All four joints driven: lift and tilt at 95-105 % of their holding pressures, the slew at
    random pressures, the extension at 70-130 % of its holding pressure; loads 150-400 kg (lighter
    ones make the extension's friction stiff: many substeps, a slow test); kept only if no end
    stop is reached."""
    crane = cp.Crane.patu655()
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        c = crane.with_load(float(rng.uniform(150, 400)))
        start = (float(rng.uniform(0.1, 0.45)), float(rng.uniform(0.1, 0.6)), float(rng.uniform(-1, 1)),
                 float(rng.uniform(0.35, 0.65)))
        state = cp.State(lift_stroke=start[0], tilt_stroke=start[1], extension=start[3])
        k_lift, k_tilt = rng.uniform(0.95, 1.05, 2)
        try:
            tilt = cp.Pressure(cp.holding_pressure(c, state, joint="tilt", p_b=0.0) * k_tilt, 0.0)
        except ValueError:   # the load pulls the tilt cylinder out at this pose: hold on the rod side
            tilt = cp.Pressure(0.0, cp.holding_pressure(c, state, joint="tilt", p_a=0.0) * k_tilt)
        drives = {"lift": cp.Pressure(cp.holding_pressure(c, state, joint="lift") * k_lift, 0.0), "tilt": tilt,
                  "slew": cp.Pressure(*rng.uniform(0, 40e5, 2)), "extension": _extension_near_holding(c, start, float(rng.uniform(0.7, 1.3)))}
        if not _run4(c, 2.0, 2e-3, lift=start[0], tilt=start[1], slew=start[2], extension=start[3],
                     drives=drives)[1]:
            out.append((c, start, drives))
    return out


def test_twin_agrees_with_the_spatial_reference_in_random_cases():
    worst = (0.0, 0.0)
    for c, start, drives in _random_cases(5, 21):
        arrays, run, tip_max, tip_rms = _compare(c, start, drives)
        print(f"load {c.load_mass:.0f} kg: tip moves {np.ptp(arrays['tip'], axis=0).max():.2f} m, "
              f"max {tip_max * 1e3:.3f} mm, RMS {tip_rms * 1e3:.3f} mm")
        worst = (max(worst[0], tip_max), max(worst[1], tip_rms))
    assert worst[0] <= TIP_MAX and worst[1] <= TIP_RMS, worst
