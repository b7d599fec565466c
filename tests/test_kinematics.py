"""Kinematics of both implementations: round trips, transmission ratios, hand-computed poses."""

from __future__ import annotations

import math

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core, twin

LIFT, TILT = 0, 1


def c_angle(crane, joint, s):
    return _core.joint_angle(crane, joint, s)


def c_stroke(crane, joint, th):
    return _core.joint_stroke(crane, joint, th)


def py_angle(crane, joint, s):
    return twin.TwinModel(crane, 0.0).joint_angle(joint, s)


def py_stroke(crane, joint, th):
    return twin.TwinModel(crane, 0.0).joint_stroke(joint, th)


BACKENDS = [pytest.param((c_angle, c_stroke), id="c"), pytest.param((py_angle, py_stroke), id="twin")]


def _cyl(crane, joint):
    return crane.lift_cylinder if joint == LIFT else crane.tilt_cylinder


@pytest.mark.parametrize("fns", BACKENDS)
@pytest.mark.parametrize("joint", [LIFT, TILT])
def test_stroke_angle_stroke_round_trip_over_full_stroke(crane, fns, joint):
    angle, stroke = fns
    cyl = _cyl(crane, joint)
    for s in np.linspace(cyl.stroke_min, cyl.stroke_max, 201):
        th, _ = angle(crane, joint, s)
        assert abs(stroke(crane, joint, th) - s) < 1e-12


@pytest.mark.parametrize("fns", BACKENDS)
@pytest.mark.parametrize("joint", [LIFT, TILT])
def test_transmission_ratio_matches_finite_differences(crane, fns, joint):
    angle, stroke = fns
    cyl = _cyl(crane, joint)
    for s in np.linspace(cyl.stroke_min + 0.01, cyl.stroke_max - 0.01, 41):
        th, ds_dth = angle(crane, joint, s)
        h = 1e-6
        fd = (stroke(crane, joint, th + h) - stroke(crane, joint, th - h)) / (2 * h)
        assert ds_dth == pytest.approx(fd, rel=1e-7, abs=1e-9)


def test_angle_ranges_and_signs(crane):
    # Lift: extending raises the boom, from about -24 deg to about +92 deg.
    lo, d_lo = c_angle(crane, LIFT, 0.0)
    hi, d_hi = c_angle(crane, LIFT, 0.535)
    assert -26 < math.degrees(lo) < -22 and 90 < math.degrees(hi) < 94
    assert d_lo > 0 and d_hi > 0
    # Tilt: extending folds the outer boom down, from about 0 deg to about -190 deg.
    lo, d0 = c_angle(crane, TILT, 0.0)
    hi, d1 = c_angle(crane, TILT, 0.78)
    assert -2 < math.degrees(lo) < 2 and -195 < math.degrees(hi) < -185
    assert d0 < 0 and d1 < 0


# World positions of the tip, computed by hand from the crane file's numbers:
# O1 = (-0.090, 1.4261), O2 = (2.881081, 0.021593) in the lift boom frame,
# tip = extension_mount + (extension + tip_distance, 0) = (-0.415 + e + 2.45, 0.287) in the outer boom frame.
HAND_POSES = [
    # (theta_lift, theta_tilt, slew, extension) -> world tip (X, Y, Z); the tilt angle must be
    # reachable by the tilt cylinder (about -190.8 to -0.2 deg).
    # lift boom horizontal, outer boom hanging straight down: outer frame (x, y) -> (y, -x)
    ((0.0, -math.pi / 2, 0.0, 0.0), (-0.090 + 2.881081 + 0.287, 0.0, 1.4261 + 0.021593 - 2.035)),
    ((0.0, -math.pi / 2, 0.0, 1.0), (-0.090 + 2.881081 + 0.287, 0.0, 1.4261 + 0.021593 - 3.035)),
    # lift boom vertical: lift frame (x, y) -> (-y, x); outer boom horizontal (relative -90 deg)
    ((math.pi / 2, -math.pi / 2, 0.0, 0.0), (-0.090 - 0.021593 + 2.035, 0.0, 1.4261 + 2.881081 + 0.287)),
    # lift boom vertical, outer boom folded to point straight down (relative -180 deg)
    ((math.pi / 2, -math.pi, 0.0, 0.0), (-0.090 - 0.021593 + 0.287, 0.0, 1.4261 + 2.881081 - 2.035)),
    # as the first, slewed by +90 deg: the tip swings from +X to +Y
    ((0.0, -math.pi / 2, math.pi / 2, 0.0), (0.0, -0.090 + 2.881081 + 0.287, 1.4261 + 0.021593 - 2.035)),
]


@pytest.mark.parametrize("pose, expected", HAND_POSES)
def test_forward_kinematics_against_hand_computed_poses(crane, pose, expected):
    th1, th2, slew, ext = pose
    theta = np.array([[th1, th2]])
    c_tip = _core.points(crane, ext, slew, theta)[0, cp.POINT_NAMES.index("tip")]
    py_tip = twin.points(crane, ext, slew, theta)[0, cp.POINT_NAMES.index("tip")]
    np.testing.assert_allclose(c_tip, expected, atol=1e-12)
    np.testing.assert_allclose(py_tip, expected, atol=1e-12)


def test_points_close_the_mechanism(crane):
    """Pins shared by two bodies are where both bodies put them (cylinder lengths, side links)."""
    rng = np.random.default_rng(1)
    g = crane.geometry
    for _ in range(20):
        s = (rng.uniform(0, 0.535), rng.uniform(0, 0.78))
        theta = np.array([[c_angle(crane, LIFT, s[0])[0], c_angle(crane, TILT, s[1])[0]]])
        p = dict(zip(cp.POINT_NAMES, _core.points(crane, 0.3, rng.uniform(-3, 3), theta)[0]))
        dist = lambda a, b: float(np.linalg.norm(p[a] - p[b]))  # noqa: E731
        assert dist("lift_cylinder_base", "lift_cylinder_rod") == pytest.approx(0.820 + s[0], abs=1e-12)
        assert dist("tilt_cylinder_base", "link_pin") == pytest.approx(1.050 + s[1], abs=1e-12)
        assert dist("link1_pivot", "link_pin") == pytest.approx(math.hypot(*g.link_pin), abs=1e-12)
        assert dist("link_pin", "link2_attach") == pytest.approx(math.hypot(*g.link2_end), abs=1e-12)
        assert dist("tilt_pivot", "link2_attach") == pytest.approx(math.hypot(*g.link2_attach), abs=1e-12)
