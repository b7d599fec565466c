"""Actuator forces of the twin (docs/model.md, "Cylinders", "Four joints"; the C core's
cylinder.c): chamber pressures on the piston areas minus [S1]'s smooth Stribeck friction, and the
slew drive and the extension cylinder as equivalent cylinders."""

from __future__ import annotations

import math
from typing import Any, NamedTuple, Tuple

from ._internal import SLEW


#: A friction law's parameters: (F_C, F_S, sigma, v_S, k), N, N, N s/m, m/s, 1.
Friction = Tuple[float, float, float, float, float]
#: The friction of an actuator that is not there: none (v_S 1 keeps the law finite).
NO_FRICTION: Friction = (0.0, 0.0, 0.0, 1.0, 0.0)


def friction_parameters(friction: Any) -> Friction:
    """An actuator's friction table as the law's parameters; None: NO_FRICTION."""
    if friction is None:
        return NO_FRICTION
    return (float(friction.coulomb), float(friction.static), float(friction.viscous),
            float(friction.stribeck_velocity), float(friction.factor))


def piston_areas(bore: float, rod: float) -> Tuple[float, float]:
    """(A_a, A_b), m^2: the bore side's area and the rod side's annulus (rod 0: A_b = A_a)."""
    return (math.pi * float(bore) ** 2 / 4.0,
            math.pi * (float(bore) ** 2 - float(rod) ** 2) / 4.0)


def friction(f: Friction, v: float) -> float:
    """[S1]'s smooth Stribeck friction opposing the stroke rate v: with x = |v| / v_S,
    k [F_C tanh(4x) + (F_S - F_C) x / (x^2/4 + 3/4)^2] sign(v) + sigma tanh(4) v."""
    f_c, f_s, sigma, v_s, k = f
    if v == 0.0:
        return 0.0
    x = abs(v) / v_s
    q = x * x / 4.0 + 0.75
    levels = k * (f_c * math.tanh(4.0 * x) + (f_s - f_c) * x / (q * q))
    return math.copysign(levels, v) + sigma * math.tanh(4.0) * v


def friction_rate(f: Friction, v: float) -> float:
    """dF/dv of friction(f, v) at the stroke rate v (the error-controlled method's matrix,
    docs/model.md "Integration"): with x = |v| / v_S and q = x^2/4 + 3/4,
    k [4 F_C (1 - tanh^2(4x)) + (F_S - F_C) (q - x^2) / q^3] / v_S + sigma tanh(4)."""
    f_c, f_s, sigma, v_s, k = f
    x = abs(v) / v_s
    q = x * x / 4.0 + 0.75
    th = math.tanh(4.0 * x)
    return k * (4.0 * f_c * (1.0 - th * th) + (f_s - f_c) * (q - x * x) / (q * q * q)) / v_s \
        + sigma * math.tanh(4.0)


def friction_slope(f: Friction) -> float:
    """G_f, N s/m: the steepest slope of friction(f, v), at rest: k (4 F_C + 16/9 (F_S - F_C)) /
    v_S + sigma tanh(4)."""
    f_c, f_s, sigma, v_s, k = f
    return k * (4.0 * f_c + 16.0 / 9.0 * (f_s - f_c)) / v_s + sigma * math.tanh(4.0)


class Cylinders:
    """TwinModel's actuator forces (the areas and friction parameters are derived in
    TwinModel.__init__)."""

    def friction_slope(self, joint: int) -> float:
        """G_f, N s/m, of the joint's actuator (friction_slope)."""
        return friction_slope(self.friction[joint])

    def friction_force(self, joint: int, stroke_rate: float) -> float:
        """The joint's actuator friction at a stroke rate (friction)."""
        return friction(self.friction[joint], stroke_rate)

    def cylinder_force(self, joint: int, p_a: float, p_b: float, stroke_rate: float) -> float:
        """Piston force (N, positive extends): pressures on both areas minus friction."""
        return p_a * self.area_bore[joint] - p_b * self.area_rod[joint] \
            - friction(self.friction[joint], stroke_rate)

    def joint_torque(self, joint: int, theta: float, omega: float, p_a: float, p_b: float) -> float:
        """tau_i = F_i ds/dtheta_i, with the stroke rate v_i = ds/dtheta_i omega_i."""
        return self._joint_torque(joint, self.transmission(joint, theta), omega, p_a, p_b)

    def _joint_torque(self, joint: int, ratio: float, omega: float, p_a: float, p_b: float) -> float:
        """joint_torque with the transmission ds/dtheta_i already known."""
        return self.cylinder_force(joint, p_a, p_b, ratio * omega) * ratio


class _EquivalentCylinder(NamedTuple):
    """What a valve needs of the slew drive or the extension cylinder (spec "Four joints",
    "Actuators"): the areas through bore and rod (rod 0: A_b = A_a), the stroke range, the circuit."""

    bore: float
    rod: float
    stroke_min: float
    stroke_max: float
    hydraulics: Any


def equivalent_cylinder(crane: Any, joint: int) -> _EquivalentCylinder:
    """The slew drive (the rack: A_a = A_b, stroke r_p (psi - slew_min)) or the extension cylinder
    (stroke e - extension_min) as a cylinder, for its valve."""
    if joint == SLEW:
        sd = crane.slew_drive
        travel = float(sd.pinion_radius) * (float(sd.slew_max) - float(sd.slew_min))
        return _EquivalentCylinder(float(sd.bore), 0.0, 0.0, travel, sd.hydraulics)
    ec, g = crane.extension_cylinder, crane.geometry
    return _EquivalentCylinder(float(ec.bore), float(ec.rod), 0.0,
                               float(g.extension_max) - float(g.extension_min), ec.hydraulics)
