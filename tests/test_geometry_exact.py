"""Exact geometry validity over the whole stroke range, the same in the C core and the twin, and
the twin's stop side from the sign of ds/dtheta."""

from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core, twin
from cranepredict._cranepredict import ffi, lib
from conftest import random_case

TOL = 1e-9  # m, tip: the C-vs-twin target of tests/test_c_vs_twin.py

TILT_POINTS = ("tilt_cylinder_base", "link1_pivot", "tilt_pivot", "link_pin", "link2_end",
               "link2_attach")


def _namespace(obj):
    """A crane as plain attributes, so that geometries the loader rejects reach both checks."""
    if dataclasses.is_dataclass(obj):
        return SimpleNamespace(**{f.name: _namespace(getattr(obj, f.name))
                                  for f in dataclasses.fields(obj)})
    return obj


def _verdicts(crane, geometry: dict):
    """(C status, C field, twin accepts) for the crane with some geometry points replaced."""
    ns = _namespace(crane)
    for k, v in geometry.items():
        setattr(ns.geometry, k, tuple(float(x) for x in v))
    field = ffi.new("crane_field *")
    params = getattr(_core.params, "__wrapped__", _core.params)  # uncached: ns is not hashable
    status = lib.crane_params_check(params(ns), field)
    try:
        twin.TwinModel(ns, 0.0)
        twin_ok = True
    except ValueError:
        twin_ok = False
    return status, int(field[0]), twin_ok


def _with_geometry(crane, **points):
    return dataclasses.replace(crane, geometry=dataclasses.replace(crane.geometry, **points))


def _compare(c, initial, inputs, horizon, dt=None):
    a = cp.predict(c, initial, inputs, horizon, dt=dt, backend="c")
    b = cp.predict(c, initial, inputs, horizon, dt=dt, backend="python")
    np.testing.assert_array_equal(a.stop, b.stop)
    return float(np.max(np.abs(a.tip - b.tip))), float(np.max(np.abs(a.strokes - b.strokes))), a


def _window_geometry(crane):
    """Finding 2's first crane: side link 2 just too short to reach the outer boom in a window of
    tilt strokes narrower than the 101-stroke sampling, half-way between samples 50 and 51.

    |Q - O2| is least (|c - l1|, c = |P1 - O2|) where Q - P1 points from P1 away from O2; O2 is
    placed so that this happens half-way between the two sampled strokes, and side link 2 is
    made ra + |c - l1| + 1e-7 long, so A cannot close (|ra - l2| > |Q - O2|) only near there."""
    g, cyl = crane.geometry, crane.tilt_cylinder
    p1, b2 = np.array(g.link1_pivot), np.array(g.tilt_cylinder_base)
    l1, ra = math.hypot(*g.link_pin), math.hypot(*g.link2_attach)
    d = float(np.linalg.norm(b2 - p1))
    u = (b2 - p1) / d

    def psi(s):  # angle at P1 from B2 - P1 clockwise to Q - P1
        length = cyl.length_retracted + s
        return math.acos((l1 * l1 + d * d - length * length) / (2 * l1 * d))

    strokes = np.linspace(cyl.stroke_min, cyl.stroke_max, 101)
    psi_mid = (psi(strokes[50]) + psi(strokes[51])) / 2
    c = math.hypot(*np.subtract(g.link1_pivot, g.tilt_pivot))
    away = math.atan2(u[1], u[0]) - psi_mid + math.pi
    o2 = p1 - c * np.array([math.cos(away), math.sin(away)])
    l2 = ra + abs(c - l1) + 1e-7
    end = np.array(g.link2_end) / math.hypot(*g.link2_end) * l2
    return {"tilt_pivot": tuple(o2), "link2_end": tuple(end)}, strokes, l2


def test_four_bar_open_in_a_window_between_sampled_strokes_is_rejected(crane):
    geometry, strokes, l2 = _window_geometry(crane)
    g = crane.geometry
    # The window lies between samples: all 101 strokes of the old check close.
    for s in strokes:
        q = twin._circle(g.link1_pivot, math.hypot(*g.link_pin), g.tilt_cylinder_base,
                         crane.tilt_cylinder.length_retracted + s, -1.0)
        twin._circle(geometry["tilt_pivot"], math.hypot(*g.link2_attach), q, l2, -1.0)
    status, field, twin_ok = _verdicts(crane, geometry)
    assert (status, field, twin_ok) == (lib.CRANE_E_FOURBAR, lib.CRANE_FIELD_GEOMETRY_LINK2_END, False)
    with pytest.raises(ValueError, match=r"four-bar.*geometry\.link2_end"):
        _with_geometry(crane, **geometry)


# Finding 2's second crane: a tilt four-bar with ds/dtheta1 > 0 (found by a seeded random search
# over perturbed PATU 655 four-bars; the PATU's is < 0). Its tilt stroke is cut at 0.55 m: beyond,
# it nears a dead centre (ds/dtheta1 = 10 m/rad at 0.78 m) where the default dt overshoots.
MIRRORED = {"tilt_cylinder_base": (1.2782, -0.2264), "link1_pivot": (2.7874, -0.045),
            "tilt_pivot": (2.495, -0.3608), "link_pin": (-0.3975, 0.403),
            "link2_end": (-0.7265, 0.2757), "link2_attach": (0.2163, -0.1219)}


def test_mirrored_four_bar_with_positive_ds_dtheta(crane):
    c = _with_geometry(crane, **MIRRORED)
    c = dataclasses.replace(c, tilt_cylinder=dataclasses.replace(c.tilt_cylinder, stroke_max=0.55))
    model = twin.TwinModel(c, 0.0)
    for s in np.linspace(c.tilt_cylinder.stroke_min, c.tilt_cylinder.stroke_max, 9):
        theta, ds = _core.joint_angle(c, 1, s)
        assert ds > 0
        # angle -> stroke inverts stroke -> angle (it took the PATU's assembly: 0.3 -> 0.991 m)
        assert abs(_core.joint_stroke(c, 1, theta) - s) < 1e-12
        assert abs(model.tilt_stroke(theta) - s) < 1e-12
    # Driven into both tilt stops: the stop flags are the C core's (the twin hard-coded the
    # PATU's side), and the tips agree.
    flags = set()
    for p_a, p_b in ((150e5, 0.0), (0.0, 150e5)):
        for tilt0 in (0.0, 0.3, 0.55):
            initial = cp.State(lift_stroke=0.3, tilt_stroke=tilt0)
            inputs = cp.Inputs(lift=cp.Pressure(80e5, 10e5), tilt=cp.Pressure(p_a, p_b))
            tip, strokes, traj = _compare(c, initial, inputs, 1.5)
            assert tip < TOL and strokes < TOL
            flags.add(int(traj.stop[-1, 1]))
    assert flags == {-1, 1}


@pytest.mark.parametrize("family", ["patu655", "mirrored"])
def test_random_cranes_c_and_twin_agree_on_validity_and_motion(crane, family):
    # Random four-bars around the PATU 655's (ds/dtheta1 < 0) and around MIRRORED's (> 0): the
    # C core and the twin accept the same ones, and predict the same motion on the first few.
    rng = np.random.default_rng(8 if family == "patu655" else 9)
    if family == "mirrored":
        crane = dataclasses.replace(crane, tilt_cylinder=dataclasses.replace(
            crane.tilt_cylinder, stroke_max=0.55))
    centre = crane.geometry if family == "patu655" else SimpleNamespace(**MIRRORED)
    spread = 0.12 if family == "patu655" else 0.04
    accepted, signs, rejected = 0, set(), 0
    for _ in range(300):
        geometry = {k: tuple(np.add(getattr(centre, k), rng.normal(0.0, spread, 2)))
                    for k in TILT_POINTS}
        status, _, twin_ok = _verdicts(crane, geometry)
        assert (status == lib.CRANE_OK) == twin_ok, geometry
        if status != lib.CRANE_OK:
            rejected += 1
            continue
        accepted += 1
        c = _with_geometry(crane, **geometry)
        signs.add(float(np.sign(_core.joint_angle(c, 1, c.tilt_cylinder.stroke_min)[1])))
        if accepted <= 6:
            c, initial, inputs = random_case(rng, c, 1.0)
            tip, strokes, _ = _compare(c, initial, inputs, 1.0)
            assert tip < TOL and strokes < TOL
    assert accepted >= 6 and rejected >= 6, (accepted, rejected)
    assert signs == ({-1.0} if family == "patu655" else {1.0})
