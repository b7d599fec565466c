"""Valve-driven actuators in the twin (docs/model.md, "Hydraulics"; the C core's hydraulics.c):
the valve's flows, the chamber equations, the relief and anti-cavitation valves and the stiffness
bound that sets the substeps."""

from __future__ import annotations

import math
from typing import Any, Tuple

from ._internal import Pair, _lerp, _segment, _signal
from .cylinder import piston_areas


#: The relief and anti-cavitation valves pass the valve's nominal flow this far beyond their
#: settings, Pa (docs/model.md, "Relief, cavitation floor, leakage").
LIMIT_OVERRIDE = 5e3
#: The vacuum floor: a chamber more than FLOOR_MARGIN (Pa) below its cavitation pressure is held
#: by a make-up flow FLOOR_GAIN times the limit valve's gradient (docs/model.md, "Relief,
#: cavitation floor, leakage").
FLOOR_MARGIN = 8e3
FLOOR_GAIN = 100.0

#: Substeps keep lambda h/n below this (RK4 is stable on the negative real axis up to 2.785).
SUBSTEP_STABILITY = 2.5


def substep_count(lam: float, h: float) -> int:
    """n = max(1, ceil(h lambda / SUBSTEP_STABILITY)): how many equal substeps a step of size h
    takes at the stiffness bound lambda, 1/s (docs/model.md, "Integration (stiffness and
    substeps)")."""
    return max(1, int(math.ceil(h * lam / SUBSTEP_STABILITY)))


def _signed_root(dp: float, laminar: float) -> float:
    """The orifice law g(dp) of docs/model.md: sign(dp) sqrt|dp|, replaced for |dp| < laminar by
    the odd cubic that meets it with the same value and slope (so the flow stays Lipschitz)."""
    if dp >= laminar:
        return math.sqrt(dp)
    if dp <= -laminar:
        return -math.sqrt(-dp)
    x = dp / laminar
    return math.sqrt(laminar) * x * (5.0 - x * x) * 0.25


def _signed_root_slope(dp: float, laminar: float) -> float:
    """d g(dp) / d dp of _signed_root."""
    if dp >= laminar:
        return 0.5 / math.sqrt(dp)
    if dp <= -laminar:
        return 0.5 / math.sqrt(-dp)
    x = dp / laminar
    return math.sqrt(laminar) * (5.0 - 3.0 * x * x) * 0.25 / laminar


def _saturation_slope(x: float) -> float:
    """d phi / dx of _saturation."""
    return 0.0 if x <= 0.0 or x >= 1.0 else (1.0 - x * x) * 1.5


def _saturation(x: float) -> float:
    """phi(x) of the compensated valve's meter-in edge: 0 below 0, 1 above 1, C1 in between."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x * (3.0 - x * x) * 0.5


class _ValveDrive:
    """A valve-driven cylinder: the lever signal and the circuit of docs/model.md "Hydraulics"."""

    def __init__(self, drive: Any, cylinder: Any) -> None:
        hyd = cylinder.hydraulics
        self.times, (self.u,) = _signal(drive, "u")
        self.compensated = hyd.valve == "compensated"
        self.p_s = float(hyd.supply_pressure)
        self.p_t = float(hyd.tank_pressure)
        self.p_r = float(hyd.relief_pressure)
        self.p_c = float(hyd.cavitation_pressure)
        self.laminar = float(hyd.laminar_pressure_drop)
        self.q_n = float(hyd.nominal_flow)
        self.k = self.q_n / math.sqrt(float(hyd.nominal_pressure_drop))
        self.dead_band = float(hyd.dead_band)
        if self.compensated:
            self.k_m = float(hyd.meter_out_flow) / math.sqrt(float(hyd.meter_out_pressure_drop))
            self.gradient = max(1.25 * self.k_m / math.sqrt(self.laminar),
                                1.5 * self.q_n / self.laminar)
        else:
            self.k_m = 0.0
            self.gradient = 1.25 * self.k / math.sqrt(self.laminar)
        # the relief and anti-cavitation valves: the nominal flow at LIMIT_OVERRIDE beyond their
        # settings
        self.limit_gradient = self.q_n / LIMIT_OVERRIDE
        self.tau = float(hyd.spool_time_constant)
        self.leakage = float(hyd.leakage)
        self.v_hose = (float(hyd.hose_volume_a), float(hyd.hose_volume_b))
        self.b_oil = float(hyd.oil_bulk_modulus)
        self.b_hose = float(hyd.hose_bulk_modulus)
        self.b_cyl = float(hyd.cylinder_bulk_modulus)
        self.area_a, self.area_b = piston_areas(cylinder.bore, cylinder.rod)
        self.stroke_min = float(cylinder.stroke_min)
        self.stroke_max = float(cylinder.stroke_max)

    def lever(self, t: float) -> float:
        if self.times is None:
            return self.u
        return _lerp(self.u, *_segment(self.times, t))

    def volumes(self, stroke: float) -> Pair:
        return (self.v_hose[0] + self.area_a * (stroke - self.stroke_min),
                self.v_hose[1] + self.area_b * (self.stroke_max - stroke))

    def compliance(self, volume: float, side: int) -> float:
        """C(V) = V / Be: the oil, the cylinder wall and the hose in series."""
        v_hose = self.v_hose[side]
        return volume / self.b_oil + (volume - v_hose) / self.b_cyl + v_hose / self.b_hose

    def branch(self, y: float, p_a: float, p_b: float, slopes: bool = False
               ) -> Tuple[float, float, float, float, float, float]:
        """The valve at spool y on the branch y takes, each flow an opening o(y) times a flow per
        unit opening (Q_a = o w_a, Q_b = o w_b): (o, w_a, w_b, do/dy, dw_a/dp_a, dw_b/dp_b), the
        last two only with ``slopes`` (else 0; w_a does not depend on p_b, nor w_b on p_a). The
        orifice valve's o is K y, the compensated valve's (y -+ u0) / (1 - u0) beyond its dead
        band (inside: all 0). One function for the flows, their gains and their slopes, so that
        the three keep one branch."""
        lam = self.laminar
        s_a = s_b = 0.0
        if not self.compensated:
            o = y * self.k
            if y >= 0.0:
                dp_a, dp_b = self.p_s - p_a, p_b - self.p_t
                if slopes:   # dp_a falls with p_a on the supply side, dp_b rises with p_b
                    s_a, s_b = -_signed_root_slope(dp_a, lam), _signed_root_slope(dp_b, lam)
            else:
                dp_a, dp_b = p_a - self.p_t, self.p_s - p_b
                if slopes:
                    s_a, s_b = _signed_root_slope(dp_a, lam), -_signed_root_slope(dp_b, lam)
            return o, _signed_root(dp_a, lam), _signed_root(dp_b, lam), self.k, s_a, s_b
        u0 = self.dead_band
        if y > u0:
            x = (self.p_s - p_a) / lam
            if slopes:
                s_a = -self.q_n * _saturation_slope(x) / lam
                s_b = self.k_m * _signed_root_slope(p_b - self.p_t, lam)
            return ((y - u0) / (1.0 - u0), self.q_n * _saturation(x),
                    self.k_m * _signed_root(p_b - self.p_t, lam), 1.0 / (1.0 - u0), s_a, s_b)
        if y < -u0:
            x = (self.p_s - p_b) / lam
            if slopes:
                s_a = self.k_m * _signed_root_slope(p_a - self.p_t, lam)
                s_b = -self.q_n * _saturation_slope(x) / lam
            return ((y + u0) / (1.0 - u0), self.k_m * _signed_root(p_a - self.p_t, lam),
                    self.q_n * _saturation(x), 1.0 / (1.0 - u0), s_a, s_b)
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0

    def flows(self, y: float, p_a: float, p_b: float) -> Pair:
        """(Q_a into the bore side, Q_b out of the rod side) through the valve at spool y."""
        o, w_a, w_b = self.branch(y, p_a, p_b)[:3]
        return o * w_a, o * w_b

    def compliances(self, stroke: float) -> Pair:
        """(C_a, C_b) at a stroke."""
        v_a, v_b = self.volumes(stroke)
        return self.compliance(v_a, 0), self.compliance(v_b, 1)

    def limit_side(self, p: float) -> Tuple[int, float]:
        """(side, setting): the nearer limit valve's setting (the anti-cavitation valve's up to
        halfway to the relief's) and whether p is beyond it (-1 below p_cav, +1 above p_R, else
        0) (docs/model.md, "Integration": the limit valves as modes)."""
        if p <= self.p_c + (self.p_r - self.p_c) / 2.0:
            return (-1 if p < self.p_c else 0), self.p_c
        return (1 if p > self.p_r else 0), self.p_r

    def limit_outflow(self, p: float, floor: bool = False) -> float:
        """G_lim (p - setting): the flow out of a chamber through its open limit valve, and with
        its vacuum floor held in (ROS34PW2's mode over the step) FLOOR_GAIN G_lim (p - knee)
        more."""
        g = self.limit_gradient
        q = g * (p - self.limit_side(p)[1])
        if floor:
            q += FLOOR_GAIN * g * (p - (self.p_c - FLOOR_MARGIN))
        return q

    @property
    def floor_knee(self) -> float:
        """The vacuum floor's knee, Pa: the cavitation pressure less FLOOR_MARGIN."""
        return self.p_c - FLOOR_MARGIN

    def limit_slope(self, floor: bool) -> float:
        """An open limit valve's slope in ROS34PW2's matrix: G_lim, (1 + FLOOR_GAIN) G_lim with
        the chamber's vacuum floor held in over the step."""
        g = self.limit_gradient
        return (1.0 + FLOOR_GAIN) * g if floor else g

    def limit_rate(self, stroke: float, side: int, p: float, floor: bool = False) -> float:
        """-limit_outflow(p, floor) / C(V): an open limit valve's flow as the chamber's rate."""
        volume = self.volumes(stroke)[side]
        return -self.limit_outflow(p, floor) / self.compliance(volume, side)

    def limit_coefficients(self, stroke: float) -> Tuple[float, float]:
        """G_lim / C(V) of both chambers at a stroke: the rates of limit_valves."""
        v_a, v_b = self.volumes(stroke)
        return (self.limit_gradient / self.compliance(v_a, 0),
                self.limit_gradient / self.compliance(v_b, 1))

    def limit_valves(self, coef: Tuple[float, float], dt: float, p_a: float,
                     p_b: float) -> Tuple[float, float]:
        """The relief and anti-cavitation valves over dt (docs/model.md, "Relief, cavitation
        floor, leakage"): implicit Euler of dp/dt = Q_lim(p)/C(V) for each chamber alone, with
        the rates coef = G_lim/C(V) at the substep's start, the vacuum floor's included."""
        out = []
        knee = self.p_c - FLOOR_MARGIN
        for p, c in zip((p_a, p_b), coef):
            ref = self.p_c if p < self.p_c else self.p_r if p > self.p_r else p
            q = ref + (p - ref) / (1.0 + dt * c)
            if q < knee:        # the vacuum floor's flow as well (piecewise linear: one solution)
                a = dt * c
                q = (p + a * self.p_c + FLOOR_GAIN * a * knee) / (1.0 + a + FLOOR_GAIN * a)
            out.append(q)
        return out[0], out[1]

    def rates(self, t: float, stroke: float, v: float, p_a: float, p_b: float,
              y: float) -> Tuple[float, float, float]:
        """(dp_a/dt, dp_b/dt, dy/dt) of the chamber equations."""
        if self.tau > 0.0:
            dy = (self.lever(t) - y) / self.tau
        else:
            y = self.lever(t)
            dy = 0.0
        q_a, q_b = self.flows(y, p_a, p_b)
        v_a, v_b = self.volumes(stroke)
        q_l = self.leakage * (p_a - p_b)
        # the relief and anti-cavitation valves are not here: limit_valves, implicitly
        dp_a = (q_a - self.area_a * v - q_l) / self.compliance(v_a, 0)
        dp_b = (self.area_b * v - q_b + q_l) / self.compliance(v_b, 1)
        return dp_a, dp_b, dy

    def stiffness(self, stroke: float) -> float:
        """lambda of docs/model.md: the bound of the pressure and spool rates at this stroke (each
        chamber's self-feedback, the leakage counted twice for the pair it couples, 1/tau)."""
        v_a, v_b = self.volumes(stroke)
        g = 2.0 * self.gradient + 2.0 * self.leakage
        lam = max(g / self.compliance(v_a, 0), g / self.compliance(v_b, 1))
        return max(lam, 1.0 / self.tau) if self.tau > 0 else lam

