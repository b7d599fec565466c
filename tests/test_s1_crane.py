"""The default crane is the one its cited source simulates ([S1], PatuCrane_Exudyn RigidSystem.py):
[S1]'s friction law with its factor 4 on the lift cylinder, and [S1]'s lumped outer boom."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import pytest

import cranepredict as cp
from cranepredict import _core, reference_common, twin
from cranepredict.types import Pressure

# tanh(4) and tanh(8) from a table (not from the code under test).
TANH4 = 0.999329299739067
TANH8 = 0.9999997749296758

# [S1]'s cylinder friction: F_C, F_S, sigma, v_S, and k (4 on the lift cylinder, 1 on the tilt).
FC, FS, SIGMA, VS = 210.0, 300.0, 330.0, 0.005

def _boom_torques(crane, extension, theta, omega, alpha):
    """The booms' torques of the core's inverse dynamics with the slew and the extension at rest."""
    q = (theta[0], theta[1], 0.0, extension)
    return _core.inverse_dynamics(crane, q, (omega[0], omega[1], 0.0, 0.0),
                                  (alpha[0], alpha[1], 0.0, 0.0))[:2]



def _hand_values(k: float) -> list[tuple[float, float]]:
    """(v, F) of [S1]'s law k [F_C tanh(4x) + (F_S - F_C) x / (x^2/4 + 3/4)^2] sign(v)
    + sigma tanh(4) v, x = |v| / v_S, worked out by hand at points where the fraction is simple."""
    return [
        (0.0, 0.0),
        # x = 1: x / (1/4 + 3/4)^2 = 1, the Stribeck peak: k (F_C tanh 4 + F_S - F_C) + sigma tanh4 v_S
        (VS, k * (FC * TANH4 + (FS - FC)) + SIGMA * TANH4 * VS),
        # x = 2, moving in: 2 / (7/4)^2 = 32/49; the law is odd
        (-2 * VS, -(k * (FC * TANH8 + (FS - FC) * 32 / 49) + SIGMA * TANH4 * 2 * VS)),
        # x = 100 (0.5 m/s): 100 / (2500.75)^2; tanh(400) = 1
        (0.5, k * (FC + (FS - FC) * 100 / 2500.75**2) + SIGMA * TANH4 * 0.5),
    ]


def test_crane_file_has_s1_friction_with_lift_factor_4(crane):
    for cyl, k in ((crane.lift_cylinder, 4.0), (crane.tilt_cylinder, 1.0)):
        f = cyl.friction
        assert (f.coulomb, f.static, f.viscous, f.stribeck_velocity, f.factor) == (FC, FS, SIGMA, VS, k)
    assert not any("tanh_velocity" in e for e in crane.estimates)


@pytest.mark.parametrize("joint,k", [(0, 4.0), (1, 1.0)])
def test_friction_matches_s1_law_by_hand(crane, joint, k):
    """C core, twin and the Exudyn reference's force law against the hand values (at zero
    pressures the cylinder force is minus the friction)."""
    model = twin.TwinModel(crane, 0.0)
    cyl = (crane.lift_cylinder, crane.tilt_cylinder)[joint]
    law = reference_common.cylinder_law(cyl, reference_common.pressure_fn(Pressure(0.0, 0.0)), 0.0)
    for v, friction in _hand_values(k):
        assert -_core.cylinder_force(crane, joint, 0.0, 0.0, v) == pytest.approx(friction, rel=1e-12, abs=1e-12)
        assert model.friction_force(joint, v) == pytest.approx(friction, rel=1e-12, abs=1e-12)
        # the connector's tension = -(cylinder force) = friction at zero pressures
        assert law(None, 0.0, 0, 1.0, v, 0.0, 0.0, 0.0) == pytest.approx(friction, rel=1e-12, abs=1e-12)


def test_friction_peak_and_slope_at_rest_are_s1s(crane):
    """Independent of the formula's spelling: the Stribeck term peaks at v = v_S (x / (x^2/4+3/4)^2
    has its maximum 1 at x = 1), and the slope at v = 0 is k (4 F_C + 16/9 (F_S - F_C)) / v_S + sigma tanh 4."""
    m = twin.TwinModel(crane, 0.0)
    k = 4.0
    h = 1e-7
    slope = (_core.cylinder_force(crane, 0, 0.0, 0.0, -h) - _core.cylinder_force(crane, 0, 0.0, 0.0, h)) / (2 * h)
    assert slope == pytest.approx(k * (4 * FC + 16 / 9 * (FS - FC)) / VS + SIGMA * TANH4, rel=1e-6)

    def stribeck(v: float) -> float:  # the friction minus its Coulomb and viscous parts
        return m.friction_force(0, v) - k * FC * math.tanh(4 * v / VS) - SIGMA * TANH4 * v

    assert stribeck(VS) == pytest.approx(k * (FS - FC), rel=1e-12)
    assert stribeck(0.98 * VS) < stribeck(VS) > stribeck(1.02 * VS)


def test_friction_is_finite_and_odd_far_out(crane):
    m = twin.TwinModel(crane, 0.0)
    for v in (1e3, 1e4, 1e5):  # beyond the C core's Stribeck cut-off (v_S 1e6) too
        f = -_core.cylinder_force(crane, 0, 0.0, 0.0, v)
        assert f == pytest.approx(4 * FC + SIGMA * TANH4 * v, rel=1e-12)
        assert m.friction_force(0, v) == pytest.approx(f, rel=1e-12)
        assert _core.cylinder_force(crane, 0, 0.0, 0.0, -v) == f


# [S1]'s "TiltBoom+ExtensionBoom" body (RigidSystem.py): mass 141.942729 + 15.928340 kg, centre of
# mass (0.659935, 0.251085) in the outer boom frame, Izz 67.053707 about it.
S1_OUTER_MASS = 141.942729 + 15.928340
S1_OUTER_COM = (0.659935, 0.251085)
S1_OUTER_IZZ = 67.053707


def test_outer_plus_extension_boom_at_zero_extension_is_s1s_body(crane):
    """The crane file's outer and extension booms, combined by hand (parallel-axis theorem) at zero
    extension and without load, and as the C core and the twin lump them, are [S1]'s one body."""
    c = crane.with_load(0.0)
    ob, eb, g = c.outer_boom, c.extension_boom, c.geometry
    assert g.extension_min == 0.0
    x_e = (g.extension_mount[0] + eb.com[0], g.extension_mount[1] + eb.com[1])
    m = ob.mass + eb.mass
    com = tuple((ob.mass * ob.com[i] + eb.mass * x_e[i]) / m for i in range(2))

    def d2(a, b):
        return (a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2

    izz = ob.izz + ob.mass * d2(ob.com, com) + eb.izz + eb.mass * d2(x_e, com)
    assert m == pytest.approx(S1_OUTER_MASS, abs=1e-3)
    assert com == pytest.approx(S1_OUTER_COM, abs=2e-6)
    assert izz == pytest.approx(S1_OUTER_IZZ, abs=1e-3)

    # The C core's lumping and the twin's bodies 2 and 3, seen through their dynamics: a crane
    # whose outer boom is [S1]'s combined body (and whose extension boom weighs next to nothing)
    # has the same joint torques.
    s1 = dataclasses.replace(c, outer_boom=cp.Body(mass=S1_OUTER_MASS, com=S1_OUTER_COM, izz=S1_OUTER_IZZ),
                             extension_boom=cp.Body(mass=1e-9, com=eb.com, izz=1e-9))
    rng = np.random.default_rng(8)
    lo = [_core.joint_angle(c, j, s)[0] for j, s in ((0, 0.1), (1, 0.7))]
    hi = [_core.joint_angle(c, j, s)[0] for j, s in ((0, 0.5), (1, 0.1))]
    for _ in range(5):
        theta = rng.uniform(lo, hi)
        omega, alpha = rng.uniform(-1, 1, 2), rng.uniform(-2, 2, 2)
        ours = _boom_torques(c, 0.0, theta, omega, alpha)
        theirs = _boom_torques(s1, 0.0, theta, omega, alpha)
        assert ours == pytest.approx(theirs, rel=2e-5)
        ours = twin.TwinModel(c, 0.0).inverse_dynamics(theta, omega, alpha)
        theirs = twin.TwinModel(s1, 0.0).inverse_dynamics(theta, omega, alpha)
        assert ours == pytest.approx(theirs, rel=2e-5)
    assert {"outer_boom.com", "outer_boom.izz"} <= set(crane.estimates)
