"""Detailed reference model of the crane on the Exudyn multibody engine (install extra ``[reference]``).

The fast model (docs/model.md) is checked against this one, as the paper checks its C model against
a Simscape Multibody model. Both carry the same bodies (the side links included); this one is
formulated independently of the fast model's two-coordinate equations:

* the bodies are **four free rigid bodies** (lift boom, outer boom, side links 1 and 2, crane file
  ``side_link1``/``side_link2``) in absolute coordinates, and the four-bar is **closed by the
  engine's joint constraints** (five revolute joints, index-3 DAE solved by Exudyn's implicit
  generalized-alpha integrator), not by closed-form kinematics;
* the cylinders are **force elements** between their pins (``ObjectConnectorSpringDamper`` with a
  force user function): ``F = p_a A_a - p_b A_b - F_friction(v)`` along the pin-to-pin line, with
  the same friction law and the same pressure inputs as the fast model;
* a **valve-driven** cylinder (``Valve``/``ValveSeries``) carries its oil: the chamber pressures
  (and the spool, with a spool lag) are integrated by Exudyn with the mechanics, from the chamber
  equations of docs/model.md "Hydraulics" written again here (:func:`_oil_rates`), fed by the
  stroke and stroke rate of the cylinder's force element. Exudyn integrates ODE1 coordinates at
  first order only (a theta-method, theta = 2/3, measured), so each of these first-order
  quantities is the velocity of an ODE2 coordinate (``ObjectGenericODE2``, unit mass, force = its
  rate), which generalized-alpha integrates at second order. ``oil_element="exudyn"`` uses
  Exudyn's own ``ObjectConnectorHydraulicActuatorSimple`` instead (published orifice law only),
  as a cross-check. At an end stop the pressures keep evolving with the stroke locked; they carry
  across every event unchanged;
* the **end stops** are rigid unilateral contacts with a perfectly plastic impact, handled
  event-driven: while a cylinder is off its stops its stroke is free; when it reaches a limit
  (Exudyn's step is shortened until the step ends within ``STOP_TOLERANCE`` of the limit) the
  piece of motion ends, the impact takes away the cylinder's stroke rate (the impulse acts along
  that cylinder only; a free other cylinder keeps the momentum the impulse does not take), and the
  next piece holds the stroke at the limit with a distance constraint (``ObjectConnectorDistance``)
  while the cylinder's force element keeps acting. The stop is released when its constraint force
  would have to pull (located to ``RELEASE_TOLERANCE``): the stop can only push. This is the
  physics of the fast model's stops (docs/model.md "End stops") without penalty parameters: no
  penetration, no rebound, and each piece is a smooth DAE, so the integrator converges at its order.
* a **held** cylinder (``Hold``: rigid, no oil) is a fixed pin-to-pin distance constraint
  (``ObjectConnectorDistance``).

Modelled planar (2D) in the boom plane, like the fast model: the slew angle and the extension are
kinematic inputs held constant during a prediction (no slew dynamics), so the motion is planar and a
3D model would add only constraints that keep it so. World output is the boom-plane result rotated
by the slew angle. The outer boom, the extension boom at its current extension and the load (a
point mass at the tip) form one rigid body (they are rigidly joined during a prediction). Cylinder
masses are not in the crane file and are neglected here too (massless force elements).

Use :func:`predict_reference` for a :class:`~cranepredict.types.Trajectory`, or :func:`simulate` for
the trajectory plus diagnostics (constraint residuals, wall time).

Layout: :func:`_build` assembles one smooth piece as an Exudyn system, :func:`_watch_events` and
:func:`_solve` integrate it to its first end-stop event, :func:`_event_loop` strings the pieces
together across impacts and releases, :func:`_join` and :func:`_output` turn them into the
trajectory.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Dict, Optional, Tuple

import numpy as np

from .crane import Crane
from .types import (POINT_NAMES, Hold, Inputs, Pressure, PressureSeries, State, Trajectory, Valve,
                    ValveSeries)

__all__ = ["predict_reference", "simulate", "ReferenceRun", "DEFAULT_REFERENCE_DT",
           "STOP_TOLERANCE", "available"]

#: Default step of the reference integrator, s (convergence: docs/validation.md).
DEFAULT_REFERENCE_DT = 2.5e-4
#: An impact is located when the step ends no more than this past the stroke limit, m (the stroke
#: is then put on the limit).
STOP_TOLERANCE = 1e-8
#: A release is located when the step ends with the stop pulling no more than this, N.
RELEASE_TOLERANCE = 1.0
#: Smallest step Exudyn is asked for while it locates an event, s.
EVENT_MIN_STEP = 1e-7
#: More end-stop events than this in one run means the stops chatter (an error).
MAX_PIECES = 64


def available() -> bool:
    """True if the Exudyn engine can be imported."""
    try:
        import exudyn  # noqa: F401
    except ImportError:
        return False
    return True


# -- small planar helpers (used only for the initial pose and the output) --------------------------

def _rot(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


def _circle(c0: np.ndarray, r0: float, c1: np.ndarray, r1: float, sign: float) -> np.ndarray:
    d = c1 - c0
    D = float(np.hypot(*d))
    u = d / D
    a = (r0 * r0 - r1 * r1 + D * D) / (2 * D)
    h2 = r0 * r0 - a * a
    if h2 <= 0:
        raise ValueError("the four-bar cannot close at this stroke")
    return c0 + a * u + sign * math.sqrt(h2) * np.array([-u[1], u[0]])


def _angle(v: np.ndarray) -> float:
    return math.atan2(v[1], v[0])


@dataclass(frozen=True)
class _Pose:
    """Absolute frame origins and angles of the four moving bodies, in the boom plane."""

    th_lift: float        # lift boom frame angle
    th_outer: float       # outer boom frame angle (absolute)
    ph_link1: float       # side link 1 frame angle (absolute)
    ph_link2: float       # side link 2 frame angle (absolute)
    o_link2: np.ndarray   # side link 2 frame origin = Q


def _pose(crane: Crane, lift_stroke: float, tilt_stroke: float) -> _Pose:
    """Assembly pose for given strokes: the initial condition of the DAE (the engine then keeps
    the loop closed). Lift: the triangle O1-B1-E1; tilt: pins Q and A of the four-bar."""
    g = crane.geometry
    O1, B1, E1 = (np.array(v) for v in (g.lift_pivot, g.lift_cylinder_base, g.lift_cylinder_rod))
    L = crane.lift_cylinder.length_retracted + lift_stroke
    # E1 in the boom plane is at distance |E1| from O1 and L from B1; pick the solution with
    # 0 < angle(B1-O1 -> E1w-O1) < pi (the boom above the cylinder base line)
    Ew = _circle(O1, float(np.hypot(*E1)), B1, L, +1.0)
    th_lift = _angle(Ew - O1) - _angle(E1)
    # four-bar in the lift boom frame
    B2, P1, O2 = (np.array(v) for v in (g.tilt_cylinder_base, g.link1_pivot, g.tilt_pivot))
    lp, l2e, la = (np.array(v) for v in (g.link_pin, g.link2_end, g.link2_attach))
    Lt = crane.tilt_cylinder.length_retracted + tilt_stroke
    Q = _circle(P1, float(np.hypot(*lp)), B2, Lt, -1.0)
    A = _circle(O2, float(np.hypot(*la)), Q, float(np.hypot(*l2e)), -1.0)
    th_rel = _angle(A - O2) - _angle(la)
    ph1_rel = _angle(Q - P1) - _angle(lp)
    ph2_rel = _angle(A - Q) - _angle(l2e)
    R = _rot(th_lift)
    return _Pose(th_lift=th_lift, th_outer=th_lift + th_rel, ph_link1=th_lift + ph1_rel,
                 ph_link2=th_lift + ph2_rel, o_link2=O1 + R @ Q)


def _lumped_outer(crane: Crane, extension: float) -> Tuple[float, np.ndarray, float]:
    """Outer boom + extension boom (at ``extension``) + load point mass as one rigid body:
    mass, centre of mass (outer boom frame), Izz about that centre."""
    g = crane.geometry
    ob, eb = crane.outer_boom, crane.extension_boom
    mount = np.array(g.extension_mount)
    parts = [(ob.mass, np.array(ob.com), ob.izz),
             (eb.mass, mount + np.array([extension, 0.0]) + np.array(eb.com), eb.izz),
             (crane.load_mass, mount + np.array([extension + g.tip_distance, 0.0]), 0.0)]
    m = sum(p[0] for p in parts)
    c = sum(p[0] * p[1] for p in parts) / m
    izz = sum(p[2] + p[0] * float((p[1] - c) @ (p[1] - c)) for p in parts)
    return m, c, izz


# -- pressure inputs and the cylinder force law --------------------------------------------------

def _pressure_fn(drive):
    """(mbs, t) -> (p_a, p_b) of a pressure drive (absolute time t)."""
    if isinstance(drive, Pressure):
        pa, pb = drive.p_a, drive.p_b
        return lambda mbs, t: (pa, pb)
    if isinstance(drive, PressureSeries):
        ts, pas, pbs = (np.asarray(a, dtype=float) for a in (drive.t, drive.p_a, drive.p_b))
        return lambda mbs, t: (float(np.interp(t, ts, pas)), float(np.interp(t, ts, pbs)))
    raise TypeError(f"not a pressure drive: {drive!r}")


def _cylinder_law(cyl, pressures, t_offset: float):
    """Exudyn spring-damper user function: returns the connector's tension (positive pulls the pins
    together) = -(cylinder force). ``pressures(mbs, t)`` gives (p_a, p_b) at absolute time t (``t``
    is the segment's time)."""
    Aa, Ab = cyl.area_a, cyl.area_b
    fr = cyl.friction
    k, Fc, dFs, sig, vS = fr.factor, fr.coulomb, fr.static - fr.coulomb, fr.viscous, fr.stribeck_velocity

    def law(mbs, t, itemNumber, stroke, rate, stiffness, damping, force):
        pa, pb = (0.0, 0.0) if pressures is None else pressures(mbs, t + t_offset)
        x = abs(rate) / vS  # [S1]'s friction law (docs/model.md, "Cylinders")
        q = x * x / 4 + 0.75
        ffric = math.copysign(k * (Fc * math.tanh(4 * x) + dFs * x / (q * q)), rate) + sig * math.tanh(4) * rate
        return -(pa * Aa - pb * Ab - ffric)

    return law


# -- valve-and-oil hydraulics (docs/model.md "Hydraulics"), written from the spec ---------------

#: Pressures enter Exudyn in MPa, so that Newton's residual mixes quantities of similar size
#: (positions in m, angles in rad).
_P_UNIT = 1e6


@dataclass(frozen=True)
class _Circuit:
    """One cylinder's circuit, from its crane-file ``hydraulics`` table, in the terms the chamber
    equations use (SI)."""

    area_a: float
    area_b: float
    stroke_min: float
    stroke_max: float
    compensated: bool     # valve = "compensated" (else "orifice")
    p_supply: float
    p_tank: float
    p_relief: float
    p_cavitation: float
    k_in: float           # orifice: the valve's coefficient; compensated: the meter-in flow, m^3/s
    k_out: float          # orifice: = k_in; compensated: the meter-out orifice's coefficient
    dead_band: float
    tau: float            # spool time constant, s (0: the spool follows the lever)
    d_laminar: float
    g_limit: float        # gradient of the relief and anti-cavitation valves, m^3/(s Pa)
    leakage: float
    v_hose_a: float
    v_hose_b: float
    b_oil: float
    b_hose: float
    b_cyl: float


#: Pa beyond its setting at which a relief or anti-cavitation valve passes the nominal flow
#: (docs/model.md, "Relief, cavitation floor, leakage").
LIMIT_OVERRIDE = 5e3


def _circuit(cyl) -> _Circuit:
    h = cyl.hydraulics
    dl = h.laminar_pressure_drop
    compensated = h.valve == "compensated"
    if compensated:
        k_in = h.nominal_flow
        k_out = h.meter_out_flow / math.sqrt(h.meter_out_pressure_drop)
    else:
        k_in = k_out = h.nominal_flow / math.sqrt(h.nominal_pressure_drop)
    # the relief and anti-cavitation valves pass the nominal flow at LIMIT_OVERRIDE beyond their
    # settings
    g_limit = h.nominal_flow / LIMIT_OVERRIDE
    return _Circuit(area_a=cyl.area_a, area_b=cyl.area_b, stroke_min=cyl.stroke_min,
                    stroke_max=cyl.stroke_max, compensated=compensated, p_supply=h.supply_pressure,
                    p_tank=h.tank_pressure, p_relief=h.relief_pressure,
                    p_cavitation=h.cavitation_pressure, k_in=k_in, k_out=k_out,
                    dead_band=h.dead_band, tau=h.spool_time_constant, d_laminar=dl,
                    g_limit=g_limit, leakage=h.leakage, v_hose_a=h.hose_volume_a,
                    v_hose_b=h.hose_volume_b, b_oil=h.oil_bulk_modulus, b_hose=h.hose_bulk_modulus,
                    b_cyl=h.cylinder_bulk_modulus)


def _compliance(c: _Circuit, volume: float, v_hose: float) -> float:
    """V / Be of a chamber, m^3/Pa: the oil, the cylinder wall and the hose in series."""
    return volume / c.b_oil + (volume - v_hose) / c.b_cyl + v_hose / c.b_hose


def _root(c: _Circuit, dp: float) -> float:
    """sign(dp) sqrt(|dp|), replaced inside the laminar region by the odd cubic with the same
    value and slope at its edge."""
    if abs(dp) >= c.d_laminar:
        return math.copysign(math.sqrt(abs(dp)), dp)
    x = dp / c.d_laminar
    return math.sqrt(c.d_laminar) * x * (5.0 - x * x) / 4.0


def _smoothstep(x: float) -> float:
    """0 below 0, 1 above 1, x (3 - x^2)/2 between: how much of the compensated flow gets in."""
    return 0.0 if x <= 0.0 else 1.0 if x >= 1.0 else x * (3.0 - x * x) / 2.0


def _valve_flows(c: _Circuit, y: float, pa: float, pb: float) -> Tuple[float, float]:
    """(flow into chamber a, flow out of chamber b), m^3/s, at spool position y."""
    if not c.compensated:
        if y >= 0.0:
            return y * c.k_in * _root(c, c.p_supply - pa), y * c.k_in * _root(c, pb - c.p_tank)
        return y * c.k_in * _root(c, pa - c.p_tank), y * c.k_in * _root(c, c.p_supply - pb)
    if abs(y) <= c.dead_band:
        return 0.0, 0.0
    r = (abs(y) - c.dead_band) / (1.0 - c.dead_band)
    if y > 0.0:
        return (r * c.k_in * _smoothstep((c.p_supply - pa) / c.d_laminar),
                r * c.k_out * _root(c, pb - c.p_tank))
    return (-r * c.k_out * _root(c, pa - c.p_tank),
            -r * c.k_in * _smoothstep((c.p_supply - pb) / c.d_laminar))


def _limit_flow(c: _Circuit, p: float) -> float:
    """Flow into a chamber through its anti-cavitation (below p_cavitation) and relief (above
    p_relief) valves, m^3/s."""
    if p < c.p_cavitation:
        return c.g_limit * (c.p_cavitation - p)
    if p > c.p_relief:
        return -c.g_limit * (p - c.p_relief)
    return 0.0


def _oil_rates(c: _Circuit, y: float, stroke: float, rate: float, pa: float, pb: float):
    """dp_a/dt and dp_b/dt, Pa/s: the continuity equations of the two chambers."""
    qa, qb = _valve_flows(c, y, pa, pb)
    q_leak = c.leakage * (pa - pb)
    va = c.v_hose_a + c.area_a * (stroke - c.stroke_min)
    vb = c.v_hose_b + c.area_b * (c.stroke_max - stroke)
    return ((qa - c.area_a * rate - q_leak + _limit_flow(c, pa)) / _compliance(c, va, c.v_hose_a),
            (c.area_b * rate - qb + q_leak + _limit_flow(c, pb)) / _compliance(c, vb, c.v_hose_b))


def _lever_fn(drive):
    """t -> lever command in [-1, 1] of a valve drive (absolute time)."""
    if isinstance(drive, Valve):
        u = drive.u
        return lambda t: u
    ts, us = np.asarray(drive.t, dtype=float), np.asarray(drive.u, dtype=float)
    return lambda t: float(np.interp(t, ts, us))


def _is_valve(drive) -> bool:
    return isinstance(drive, (Valve, ValveSeries))


# -- bodies and assembly poses -------------------------------------------------------------------

_ORDER = ("lift", "outer", "link1", "link2")


def _bodies(crane: Crane, extension: float) -> Dict[str, Tuple[float, np.ndarray, float]]:
    """(mass, centre of mass in the body's frame, Izz about it) of the four moving bodies."""
    m2, c2, i2 = _lumped_outer(crane, extension)
    return {"lift": (crane.lift_boom.mass, np.array(crane.lift_boom.com), crane.lift_boom.izz),
            "outer": (m2, c2, i2),
            "link1": (crane.side_link1.mass, np.array(crane.side_link1.com), crane.side_link1.izz),
            "link2": (crane.side_link2.mass, np.array(crane.side_link2.com), crane.side_link2.izz)}


def _node_coords(crane: Crane, bodies, lift_stroke: float, tilt_stroke: float) -> Dict[str, np.ndarray]:
    """Node coordinates (x, y of the centre of mass, frame angle) of each body at given strokes."""
    g = crane.geometry
    p = _pose(crane, lift_stroke, tilt_stroke)
    O1 = np.array(g.lift_pivot)
    R = _rot(p.th_lift)
    frames = {"lift": (O1, p.th_lift),
              "outer": (O1 + R @ np.array(g.tilt_pivot), p.th_outer),
              "link1": (O1 + R @ np.array(g.link1_pivot), p.ph_link1),
              "link2": (p.o_link2, p.ph_link2)}
    return {k: np.array([*(o + _rot(a) @ bodies[k][1]), a]) for k, (o, a) in frames.items()}


def _stroke_jacobians(crane: Crane, bodies, s: Tuple[float, float]) -> Dict[str, np.ndarray]:
    """d(node coordinates)/d(lift stroke, tilt stroke) per body, (3, 2), by central differences."""
    h = 1e-6
    cols = {k: np.zeros((3, 2)) for k in _ORDER}
    for j in range(2):
        dp, dm = list(s), list(s)
        dp[j] += h
        dm[j] -= h
        qp, qm = _node_coords(crane, bodies, *dp), _node_coords(crane, bodies, *dm)
        for k in _ORDER:
            cols[k][:, j] = (qp[k] - qm[k]) / (2 * h)
    return cols


def _stroke_mass_matrix(crane: Crane, bodies, s: Tuple[float, float]) -> np.ndarray:
    """The 2x2 mass matrix of the crane in stroke coordinates (side links included)."""
    J = _stroke_jacobians(crane, bodies, s)
    return sum(J[k].T @ np.diag([bodies[k][0], bodies[k][0], bodies[k][2]]) @ J[k] for k in _ORDER)


def _plastic_impact(crane: Crane, bodies, s, rates, j: int, others_free: bool) -> list:
    """Stroke rates after a perfectly plastic impact of cylinder j on its stop: the stop's impulse
    acts along cylinder j only (a generalised force on stroke j) and ends its stroke rate; a free
    other cylinder keeps the momentum the impulse does not take (M dv = P e_j, dv_j = -v_j)."""
    out = list(rates)
    if others_free:
        Minv = np.linalg.inv(_stroke_mass_matrix(crane, bodies, tuple(s)))
        o = 1 - j
        out[o] = rates[o] - rates[j] * Minv[o, j] / Minv[j, j]
    out[j] = 0.0
    return out


# -- the model: one smooth piece of motion as an Exudyn system -----------------------------------

@dataclass
class ReferenceRun:
    """A reference simulation: the trajectory and diagnostics."""

    trajectory: Trajectory
    wall: float                   #: wall time of build + solve, s
    residual_max: float           #: largest joint-constraint violation over the run, m
    held_length_error: float      #: largest drift of a held cylinder's pin-to-pin length, m
    dt: float
    events: list                  #: (t, "impact" | "release", cylinder 0/1, side -1/+1) in order


def _joints(g):
    """Revolute joints: (body a, point in a's frame, body b, point in b's frame)."""
    return [("ground", g.lift_pivot, "lift", (0.0, 0.0)),
            ("lift", g.tilt_pivot, "outer", (0.0, 0.0)),
            ("lift", g.link1_pivot, "link1", (0.0, 0.0)),
            ("link1", g.link_pin, "link2", (0.0, 0.0)),
            ("link2", g.link2_end, "outer", g.link2_attach)]


def _cyl(crane: Crane, j: int):
    return crane.lift_cylinder if j == 0 else crane.tilt_cylinder


def _cylinders(crane: Crane, inputs: Inputs):
    """(cylinder, drive, base pin, rod pin) of the lift and the tilt cylinder."""
    g = crane.geometry
    return [(crane.lift_cylinder, inputs.lift, ("ground", g.lift_cylinder_base), ("lift", g.lift_cylinder_rod)),
            (crane.tilt_cylinder, inputs.tilt, ("lift", g.tilt_cylinder_base), ("link1", g.link_pin))]


@dataclass
class _Model:
    """One piece's Exudyn system, assembled and ready to solve."""

    mbs: object
    q0: Dict[str, np.ndarray]     #: node reference coordinates (the sensors give displacements)
    sensors: Dict[str, Tuple[int, int]]   #: (coordinates, velocities) sensor per body
    watched: dict                 #: cylinder -> ("impact", force element, cylinder) | ("release", stop, side)
    oil_sensors: Dict[int, tuple]  #: valve-driven cylinder -> (sensor of its oil, unit of p in Pa)


def _build(crane: Crane, bodies, inputs: Inputs, modes, s, rates, held, oil, t0: float,
           oil_element: str = "ode2") -> _Model:
    """The Exudyn system of one piece, started at (strokes s, stroke rates) at time t0: the four
    bodies under gravity, the five revolute joints, and per cylinder a held length ("held"), a free
    force element (mode 0, watched for an impact) or a force element plus a distance constraint on
    its stop (mode -1/+1, watched for a release)."""
    import exudyn as exu
    from exudyn.itemInterface import (MarkerBodyMass, MarkerBodyPosition, LoadMassProportional,
                                      NodeRigidBody2D, ObjectConnectorDistance,
                                      ObjectConnectorSpringDamper, ObjectGround,
                                      ObjectJointRevolute2D, ObjectRigidBody2D, SensorNode)
    g = crane.geometry
    q0 = _node_coords(crane, bodies, *s)
    v0 = {k: np.zeros(3) for k in _ORDER}
    if any(rates):
        J = _stroke_jacobians(crane, bodies, tuple(s))
        v0 = {k: J[k] @ np.array(rates, dtype=float) for k in _ORDER}

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    nodes, objs = {}, {}
    for name in _ORDER:
        m, com, izz = bodies[name]
        nodes[name] = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=list(q0[name]),
                                                  initialVelocities=list(v0[name])))
        objs[name] = mbs.AddObject(ObjectRigidBody2D(physicsMass=m, physicsInertia=izz,
                                                     nodeNumber=nodes[name]))
        mk = mbs.AddMarker(MarkerBodyMass(bodyNumber=objs[name]))
        mbs.AddLoad(LoadMassProportional(markerNumber=mk, loadVector=[0.0, -crane.gravity, 0.0]))

    def marker(name: str, point_in_frame) -> int:
        if name == "ground":
            return mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground,
                                                    localPosition=[*point_in_frame, 0.0]))
        local = np.array(point_in_frame, dtype=float) - bodies[name][1]
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[name], localPosition=[*local, 0.0]))

    for a, pa, b, pb in _joints(g):
        mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[marker(a, pa), marker(b, pb)]))

    watched = {}
    oil_nodes: Dict[int, tuple] = {}     # cylinder -> (node, output variable, unit in Pa)
    pre_steps: list = []
    for j, (cyl, drive, base, rod) in enumerate(_cylinders(crane, inputs)):
        mks = [marker(*base), marker(*rod)]
        if modes[j] == "held":
            mbs.AddObject(ObjectConnectorDistance(markerNumbers=mks, distance=cyl.length_retracted + held[j]))
            continue
        if _is_valve(drive) and oil_element == "exudyn":
            pressures, spring = _add_actuator(mbs, crane, j, drive, oil[j], t0, oil_nodes, mks,
                                              pre_steps)
        elif _is_valve(drive):
            pressures, spring = _add_oil(mbs, crane, j, drive, oil[j], t0, oil_nodes)
        else:
            pressures, spring = _pressure_fn(drive), [None]
        spring[0] = mbs.AddObject(ObjectConnectorSpringDamper(
            markerNumbers=mks, referenceLength=cyl.length_retracted,
            springForceUserFunction=_cylinder_law(cyl, pressures, t0)))   # pressures None: friction only
        spring = spring[0]
        if modes[j] == 0:
            watched[j] = ("impact", spring, cyl)
        else:
            lim = cyl.stroke_max if modes[j] > 0 else cyl.stroke_min
            stop = mbs.AddObject(ObjectConnectorDistance(markerNumbers=mks,
                                                         distance=cyl.length_retracted + lim))
            watched[j] = ("release", stop, modes[j])

    sensors = {name: (mbs.AddSensor(SensorNode(nodeNumber=nodes[name], storeInternal=True,
                                               writeToFile=False,
                                               outputVariableType=exu.OutputVariableType.Coordinates)),
                      mbs.AddSensor(SensorNode(nodeNumber=nodes[name], storeInternal=True,
                                               writeToFile=False,
                                               outputVariableType=exu.OutputVariableType.Coordinates_t)))
               for name in _ORDER}
    oil_sensors = {j: (mbs.AddSensor(SensorNode(nodeNumber=n, storeInternal=True, writeToFile=False,
                                                outputVariableType=var)), unit)
                   for j, (n, var, unit) in oil_nodes.items()}
    if pre_steps:
        mbs.SetPreStepUserFunction(lambda mbs_, t: all([f(mbs_, t) for f in pre_steps]))
    return _Model(mbs=mbs, q0=q0, sensors=sensors, watched=watched, oil_sensors=oil_sensors)


def _add_oil(mbs, crane: Crane, j: int, drive, oil0, t0: float, oil_nodes: Dict[int, tuple]):
    """The oil of valve-driven cylinder j (chamber pressures p_a, p_b and, with a spool lag, the
    spool position y), integrated by Exudyn together with the mechanics.

    The continuity equations dp/dt = f(p, y, stroke, stroke rate) and the spool's lag are first
    order. Exudyn integrates ODE1 coordinates at first order only (measured: a theta-method with
    theta = 2/3, docs/validation.md), so each of these quantities is the *velocity* of an ODE2
    coordinate (its time integral) with unit mass whose force (an ObjectGenericODE2 user function)
    is its rate: generalized-alpha then integrates it at second order. The stroke and the stroke
    rate come from the cylinder's force element. ``oil0`` = (p_a, p_b, y) at t0. Returns the
    pressure function for the force element and a one-item list to receive the force element."""
    import exudyn as exu
    from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2
    cyl = _cyl(crane, j)
    c = _circuit(cyl)
    lever = _lever_fn(drive)
    n = 3 if c.tau > 0 else 2
    x0 = [oil0[0] / _P_UNIT, oil0[1] / _P_UNIT] + ([oil0[2]] if n == 3 else [])
    spring = [None]
    node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0] * n, initialCoordinates=[0.0] * n,
                                       initialCoordinates_t=x0, numberOfODE2Coordinates=n))
    oil_nodes[j] = (node, exu.OutputVariableType.Coordinates_t, _P_UNIT)
    L0 = cyl.length_retracted

    def rates(mbs_, t, itemNumber, q, q_t):
        d = mbs_.GetObjectOutput(spring[0], exu.OutputVariableType.Displacement)
        v = mbs_.GetObjectOutput(spring[0], exu.OutputVariableType.Velocity)
        L = math.hypot(d[0], d[1])
        u = lever(t + t0)
        y = q_t[2] if n == 3 else u
        dpa, dpb = _oil_rates(c, y, L - L0, (d[0] * v[0] + d[1] * v[1]) / L,
                              q_t[0] * _P_UNIT, q_t[1] * _P_UNIT)
        out = [dpa / _P_UNIT, dpb / _P_UNIT]
        if n == 3:
            out.append((u - y) / c.tau)
        return np.array(out)

    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[node], massMatrix=np.eye(n), forceUserFunction=rates))

    def pressures(mbs_, t):
        x = mbs_.GetNodeOutput(node, exu.OutputVariableType.Coordinates_t)
        return x[0] * _P_UNIT, x[1] * _P_UNIT

    return pressures, spring


def _actuator_circuit(cyl) -> _Circuit:
    c = _circuit(cyl)
    if c.compensated or c.tau > 0 or c.leakage > 0 or cyl.stroke_min != 0.0:
        raise ValueError("oil_element='exudyn' needs hydraulics.valve = 'orifice', "
                         "spool_time_constant = 0 and leakage = 0, on a cylinder with stroke_min = 0")
    return c


def _add_actuator(mbs, crane: Crane, j: int, drive, oil0, t0: float, oil_nodes: Dict[int, tuple], mks,
                  pre_steps: list):
    """The cross-check of :func:`_add_oil`: Exudyn's own ObjectConnectorHydraulicActuatorSimple
    (its pressures an ODE1 node, integrated at first order) between the cylinder's pins, for the
    orifice valve without spool lag, laminar region, relief, anti-cavitation valve or leakage
    (which it does not have): the valve edges are its two valve openings, set from the lever
    before every step. The friction stays in the force element this returns (pressures None)."""
    import exudyn as exu
    from exudyn.itemInterface import NodeGenericODE1, ObjectConnectorHydraulicActuatorSimple
    cyl = _cyl(crane, j)
    c = _actuator_circuit(cyl)
    node = mbs.AddNode(NodeGenericODE1(referenceCoordinates=[0.0, 0.0],
                                       initialCoordinates=[oil0[0], oil0[1]],
                                       numberOfODE1Coordinates=2))
    oil_nodes[j] = (node, exu.OutputVariableType.Coordinates, 1.0)
    act = mbs.AddObject(ObjectConnectorHydraulicActuatorSimple(
        markerNumbers=list(mks), nodeNumbers=[node], offsetLength=cyl.length_retracted,
        strokeLength=cyl.stroke_max, chamberCrossSection0=c.area_a, chamberCrossSection1=c.area_b,
        hoseVolume0=c.v_hose_a, hoseVolume1=c.v_hose_b, valveOpening0=0.0, valveOpening1=0.0,
        actuatorDamping=0.0, oilBulkModulus=c.b_oil, cylinderBulkModulus=c.b_cyl,
        hoseBulkModulus=c.b_hose, nominalFlow=c.k_in, systemPressure=c.p_supply,
        tankPressure=c.p_tank, useChamberVolumeChange=True))
    lever = _lever_fn(drive)

    def pre_step(mbs_, t):
        # its edge a opens to the supply for u > 0 (to the tank for u < 0), its edge b the other way
        u = lever(t + t0)
        mbs_.SetObjectParameter(act, "valveOpening0", u)
        mbs_.SetObjectParameter(act, "valveOpening1", -u)
        return True

    pre_steps.append(pre_step)
    return None, [None]


# -- event location inside a piece ---------------------------------------------------------------

def _watch_events(model: _Model, crane: Crane, s) -> dict:
    """Installs the user functions that end the piece at its first event: a free cylinder reaching
    a stop (located to STOP_TOLERANCE of stroke) or a stopped one whose stop would have to pull
    (located to RELEASE_TOLERANCE); see :func:`_watch`."""
    import exudyn as exu
    mbs, watched = model.mbs, model.watched

    def gap_fn(j: int):
        kind, obj, extra = watched[j]
        if kind == "impact":
            def gap():
                stroke = float(mbs.GetObjectOutput(obj, exu.OutputVariableType.Distance)) - extra.length_retracted
                up, lo = stroke - extra.stroke_max, extra.stroke_min - stroke
                return (up, +1) if up >= lo else (lo, -1)
            return gap

        # the distance constraint's force is its tension: an upper stop (piston on the head) holds
        # the pins together (tension >= 0), a lower stop pushes them apart (tension <= 0)
        def pull():
            tension = float(mbs.GetObjectOutput(obj, exu.OutputVariableType.Force))
            return (-tension if extra > 0 else tension), extra
        return pull

    gaps = {}
    for j in watched:
        cyl = _cyl(crane, j)
        g0 = max(s[j] - cyl.stroke_max, cyl.stroke_min - s[j]) if watched[j][0] == "impact" else None
        gaps[j] = (watched[j][0], gap_fn(j), g0)
    return _watch(mbs, gaps)


def _watch(mbs, gaps: dict) -> dict:
    """Ends the piece at its first event. ``gaps``: per watched actuator (kind "impact" or
    "release", gap(), its value at the piece's start or None), where gap() gives (how far the event
    is past, side): for a free actuator the penetration of the nearer stop, for a stopped one the
    pull its stop would have to exert. A step that ends past an event is redone shorter (regula
    falsi) until it ends within the tolerance (STOP_TOLERANCE, RELEASE_TOLERANCE); then the
    post-step function stops the solver. Returns the dict whose "events" lists what ended the piece
    as (kind, actuator, side)."""
    tol = {"impact": STOP_TOLERANCE, "release": RELEASE_TOLERANCE}
    st = {"t_last": 0.0, "gap_last": {j: g0 for j, (_, _, g0) in gaps.items()}, "events": []}

    def post_newton(mbs_, t):
        h = t - st["t_last"]
        st["events"] = []
        rec = -1.0
        for j, (kind, gap, _) in gaps.items():
            gj, side = gap()
            if gj <= 0:
                continue
            if gj <= tol[kind] or h <= 2 * EVENT_MIN_STEP:
                st["events"].append((kind, j, side))
                continue
            g_prev = st["gap_last"][j]
            if g_prev is None or g_prev >= 0:
                hr = EVENT_MIN_STEP
            else:   # regula falsi between the step's start (gap < 0) and its end (gap > 0)
                frac = -g_prev / (gj - g_prev)
                hr = max(EVENT_MIN_STEP, h * (frac + 1e-3 * (1 - frac)))
            rec = hr if rec < 0 else min(rec, hr)
        if rec > 0:
            st["events"] = []
            return [1.0, rec]   # error > iterationTolerance: the step is redone with size rec
        return [0.0, -1.0]

    def post_step(mbs_, t):
        st["t_last"] = t
        for j, (_, gap, _) in gaps.items():
            st["gap_last"][j] = gap()[0]
        return not st["events"]

    mbs.SetPostNewtonUserFunction(post_newton)
    mbs.SetPostStepUserFunction(post_step)
    return st


def _solve(model: _Model, span: float, dt: float, spectral_radius: float) -> None:
    """Generalized-alpha with (modified) Newton over ``span`` at step ``dt`` (shortened only to locate
    an event), every step stored by the sensors."""
    import exudyn as exu
    mbs = model.mbs
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(math.ceil(span / dt - 1e-9))
    ss.timeIntegration.endTime = float(span)
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.adaptiveStep = True
    ss.timeIntegration.minimumStepSize = EVENT_MIN_STEP / 10
    ss.timeIntegration.discontinuous.useRecommendedStepSize = True
    ss.timeIntegration.discontinuous.iterationTolerance = 0.5
    ss.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    # modified Newton (the Jacobian kept while it converges) to the same tolerances: 3-4x faster
    # with the oil's user functions; the converged steps differ by < 1e-3 mm and 1e-3 bar
    ss.timeIntegration.newton.useModifiedNewton = True
    ss.timeIntegration.newton.relativeTolerance = 1e-8
    ss.timeIntegration.newton.absoluteTolerance = 1e-10
    ss.timeIntegration.newton.maxIterations = 25
    if hasattr(ss, "solution"):                # Exudyn >= 1.13 names
        ss.solution.file.write = False
        ss.solution.sensors.writePeriod = 0.0      # every step
    else:
        ss.solutionSettings.writeSolutionToFile = False
        ss.solutionSettings.sensorsWritePeriod = 0.0
    ss.displayStatistics = False
    ss.displayComputationTime = False
    # Exudyn prints its notes (e.g. on the user functions' allocations) to stdout, which would mix
    # into `cranepredict validate --json`; a failure is raised below, so the console is muted
    exu.SetWriteToConsole(False)
    try:
        ok = exu.SolveDynamic(mbs, ss, updateInitialValues=False)
    finally:
        exu.SetWriteToConsole(True)
    if not ok:
        raise RuntimeError("Exudyn's solver did not converge on the reference model")


@dataclass
class _Piece:
    """The samples of one smooth piece: time, node coordinates and velocities per body, and the
    cylinders' modes during it."""

    t: np.ndarray
    q: Dict[str, np.ndarray]
    qd: Dict[str, np.ndarray]
    modes: list
    oil: Dict[int, np.ndarray]    #: valve-driven cylinder -> (N, 3) p_a, p_b (Pa), spool y


def _oil_samples(x: np.ndarray, unit: float) -> np.ndarray:
    """(N, 3) p_a, p_b (Pa), y from the oil node's sensor (p in ``unit`` Pa, then y if it has one)."""
    out = np.zeros((x.shape[0], 3))
    out[:, :2] = x[:, :2] * unit
    if x.shape[1] > 2:
        out[:, 2] = x[:, 2]
    return out


def _segment(crane: Crane, bodies, inputs: Inputs, modes, s, rates, held, oil, t0: float,
             t_end: float, dt: float, spectral_radius: float,
             oil_element: str = "ode2") -> Tuple[_Piece, list]:
    """Integrates one smooth piece of the motion from (strokes s, stroke rates) at t0 until t_end or
    the first event (see :func:`_build` and :func:`_watch_events`). Returns the piece and the
    events that ended it (empty: it reached t_end)."""
    model = _build(crane, bodies, inputs, modes, s, rates, held, oil, t0, oil_element)
    st = _watch_events(model, crane, s)
    _solve(model, t_end - t0, dt, spectral_radius)
    data = {k: (model.mbs.GetSensorStoredData(model.sensors[k][0]),
                model.mbs.GetSensorStoredData(model.sensors[k][1])) for k in _ORDER}
    t = data["lift"][0][:, 0] + t0
    q = {k: data[k][0][:, 1:4] + model.q0[k] for k in _ORDER}   # sensors give displacements
    qd = {k: data[k][1][:, 1:4] for k in _ORDER}
    p = {j: _oil_samples(model.mbs.GetSensorStoredData(sn)[:, 1:], unit)
         for j, (sn, unit) in model.oil_sensors.items()}
    return _Piece(t=t, q=q, qd=qd, modes=list(modes), oil=p), st["events"]


# -- the event loop: pieces between end-stop events ----------------------------------------------

def _start_on_stops(crane: Crane, bodies, modes, s, rates, events: list):
    """At t = 0 a free cylinder on a limit whose rate does not point into the range is on its stop
    (a plastic impact at t = 0). Updates modes, s and rates in place; appends the events."""
    for j in range(2):
        if modes[j] == 0:
            cyl = _cyl(crane, j)
            for side, lim in ((+1, cyl.stroke_max), (-1, cyl.stroke_min)):
                if abs(s[j] - lim) <= STOP_TOLERANCE and side * rates[j] >= 0:
                    free_other = modes[1 - j] == 0
                    rates[:] = _plastic_impact(crane, bodies, s, rates, j, free_other)
                    s[j], modes[j] = lim, side
                    events.append((0.0, "impact", j, side))
                    break


def _apply_events(crane: Crane, bodies, evs, t0: float, modes, s, rates, events: list):
    """The contact changes at an event: an impact puts the stroke on the limit and takes its rate
    (plastic), a release frees the cylinder. Updates modes, s and rates in place."""
    for kind, j, side in evs:
        events.append((t0, kind, j, side))
        if kind == "impact":
            cyl = _cyl(crane, j)
            s[j] = cyl.stroke_max if side > 0 else cyl.stroke_min
            rates[:] = _plastic_impact(crane, bodies, s, rates, j, modes[1 - j] == 0)
            modes[j] = side
        else:
            modes[j] = 0
    for j in range(2):   # a stopped cylinder's stroke rate is zero (within the constraint)
        if modes[j] != 0:
            rates[j] = 0.0


def _event_loop(crane: Crane, bodies, initial: State, inputs: Inputs, oil, horizon: float,
                dt: float, spectral_radius: float, oil_element: str = "ode2") -> Tuple[list, list]:
    """Integrates the motion in smooth pieces between end-stop events, from the initial state and
    ``oil`` (valve-driven cylinder -> initial (p_a, p_b, spool)). Returns the pieces and the events
    (t, kind, cylinder, side). The pressures carry across an event unchanged."""
    s = [initial.lift_stroke, initial.tilt_stroke]
    rates = [initial.lift_stroke_rate, initial.tilt_stroke_rate]
    held = list(s)
    modes = ["held" if isinstance(c[1], Hold) else 0 for c in _cylinders(crane, inputs)]
    events: list = []
    _start_on_stops(crane, bodies, modes, s, rates, events)
    pieces = []
    t0 = 0.0
    for _ in range(MAX_PIECES):
        piece, evs = _segment(crane, bodies, inputs, modes, s, rates, held, oil, t0, horizon, dt,
                              spectral_radius, oil_element)
        pieces.append(piece)
        t0 = float(piece.t[-1])
        if not evs or horizon - t0 <= 1e-12:
            return pieces, events
        oil = {j: tuple(p[-1]) for j, p in piece.oil.items()}
        s, rates = _strokes_and_rates(crane, bodies, {k: piece.q[k][-1] for k in _ORDER},
                                      {k: piece.qd[k][-1] for k in _ORDER})
        _apply_events(crane, bodies, evs, t0, modes, s, rates, events)
    raise RuntimeError(f"more than {MAX_PIECES} end-stop events: the stops chatter")


def _join(pieces: list):
    """One time series from the pieces: each piece's first sample replaces the previous piece's
    last (the same instant, after the event); pieces of length zero (an event at their start)
    leave no sample. Returns t, q, qd, the (N, 2) stop flags and the pressures per valve-driven
    cylinder."""
    last = len(pieces) - 1

    def cat(get):
        return np.concatenate([get(p) if i == last else get(p)[:-1] for i, p in enumerate(pieces)])

    t = cat(lambda p: p.t)
    q = {k: cat(lambda p, k=k: p.q[k]) for k in _ORDER}
    qd = {k: cat(lambda p, k=k: p.qd[k]) for k in _ORDER}
    mode_rows = np.concatenate([np.tile([[m if m != "held" else 0 for m in p.modes]],
                                        (p.t.size if i == last else p.t.size - 1, 1))
                                for i, p in enumerate(pieces)]).astype(np.int32)
    oil = {j: cat(lambda p, j=j: p.oil[j]) for j in pieces[0].oil}
    keep = np.concatenate([np.diff(t) > 0, [True]])
    return (t[keep], {k: v[keep] for k, v in q.items()}, {k: v[keep] for k, v in qd.items()},
            mode_rows[keep], {j: v[keep] for j, v in oil.items()})


# -- output: trajectory and diagnostics from the bodies' coordinates -----------------------------

def _hydraulic_samples(crane: Crane, inputs: Inputs, t: np.ndarray, oil) -> Dict[str, np.ndarray]:
    """p_a, p_b, flow_a, flow_b, spool (N, 4) [lift, tilt, slew, extension] as the Trajectory
    gives them: a valve-driven cylinder's oil (flows from the valve law at the sampled pressures and
    spool), a pressure-driven one's given pressures, zeros for a held one (the slew and the
    extension are held in this planar model: their columns are zero)."""
    out = {k: np.zeros((t.size, 4)) for k in ("p_a", "p_b", "flow_a", "flow_b", "spool")}
    for j, (cyl, drive, *_pins) in enumerate(_cylinders(crane, inputs)):
        if _is_valve(drive):
            c = _circuit(cyl)
            pa, pb = oil[j][:, 0], oil[j][:, 1]
            y = oil[j][:, 2] if c.tau > 0 else np.array([_lever_fn(drive)(x) for x in t])
            flows = np.array([_valve_flows(c, *v) for v in zip(y, pa, pb)]).reshape(-1, 2)
            out["p_a"][:, j], out["p_b"][:, j], out["spool"][:, j] = pa, pb, y
            out["flow_a"][:, j], out["flow_b"][:, j] = flows[:, 0], flows[:, 1]
        elif not isinstance(drive, Hold):
            fn = _pressure_fn(drive)
            out["p_a"][:, j], out["p_b"][:, j] = np.array([fn(None, x) for x in t]).reshape(-1, 2).T
    return out


def _output(crane: Crane, bodies, initial: State, inputs: Inputs, t, q, qd, stop, oil):
    """The Trajectory (world points rotated by the slew) and the diagnostics: the largest joint
    residual and the largest drift of a held cylinder's length."""
    g = crane.geometry
    e = initial.extension
    held = (initial.lift_stroke, initial.tilt_stroke)

    def world_point(name: str, point_in_frame) -> np.ndarray:
        """(N, 2) boom-plane positions of a point fixed in a body's frame."""
        if name == "ground":
            return np.broadcast_to(np.array(point_in_frame, dtype=float), (t.size, 2)).copy()
        local = np.array(point_in_frame, dtype=float) - bodies[name][1]
        ph = q[name][:, 2]
        c, sn = np.cos(ph), np.sin(ph)
        return q[name][:, :2] + np.stack([c * local[0] - sn * local[1], sn * local[0] + c * local[1]], 1)

    res = max(float(np.max(np.hypot(*(world_point(a, pa) - world_point(b, pb)).T)))
              for a, pa, b, pb in _joints(g))
    strokes = np.empty((t.size, 2))
    held_err = 0.0
    for j, (cyl, drive, base, rod) in enumerate(_cylinders(crane, inputs)):
        L = np.hypot(*(world_point(*rod) - world_point(*base)).T)
        strokes[:, j] = L - cyl.length_retracted
        if isinstance(drive, Hold):
            held_err = max(held_err, float(np.max(np.abs(strokes[:, j] - held[j]))))
    th_lift = q["lift"][:, 2]
    th_tilt = q["outer"][:, 2] - th_lift
    th_tilt = np.where(th_tilt > math.pi / 2, th_tilt - 2 * math.pi, th_tilt)
    th_tilt = np.where(th_tilt <= -1.5 * math.pi, th_tilt + 2 * math.pi, th_tilt)
    theta = np.stack([th_lift, th_tilt], 1)
    omega = np.stack([qd["lift"][:, 2], qd["outer"][:, 2] - qd["lift"][:, 2]], 1)

    mount = np.array(g.extension_mount)
    plane = {"pillar_base": np.zeros((t.size, 2)),
             "lift_pivot": world_point("ground", g.lift_pivot),
             "lift_cylinder_base": world_point("ground", g.lift_cylinder_base),
             "lift_cylinder_rod": world_point("lift", g.lift_cylinder_rod),
             "tilt_cylinder_base": world_point("lift", g.tilt_cylinder_base),
             "link1_pivot": world_point("lift", g.link1_pivot),
             "link_pin": world_point("link1", g.link_pin),
             "link2_attach": world_point("outer", g.link2_attach),
             "tilt_pivot": world_point("outer", (0.0, 0.0)),
             "extension_mount": world_point("outer", mount + np.array([e, 0.0])),
             "tip": world_point("outer", mount + np.array([e + g.tip_distance, 0.0]))}
    cps, sps = math.cos(initial.slew), math.sin(initial.slew)

    def to_world(p: np.ndarray) -> np.ndarray:
        return np.stack([p[:, 0] * cps, p[:, 0] * sps, p[:, 1]], 1)

    xyz = np.stack([to_world(plane[n]) for n in POINT_NAMES], 1)
    tip = xyz[:, POINT_NAMES.index("tip"), :].copy()
    # the slew and the extension are held: constant per sample, their rates zero, never on a stop
    stop4 = np.zeros((t.size, 4), dtype=np.int32)
    stop4[:, :2] = stop
    arrays = dict(t=t, strokes=strokes, theta=theta, omega=omega,
                  slew=np.full(t.size, float(initial.slew)), extension=np.full(t.size, float(e)),
                  slew_rate=np.zeros(t.size), extension_rate=np.zeros(t.size), tip=tip, stop=stop4,
                  **_hydraulic_samples(crane, inputs, t, oil))
    for a in list(arrays.values()) + [xyz]:
        a.setflags(write=False)

    def points(th: np.ndarray, slew: np.ndarray, extension: np.ndarray) -> np.ndarray:
        if any(x.shape != y.shape or not np.array_equal(x, y)
               for x, y in ((th, theta), (slew, arrays["slew"]), (extension, arrays["extension"]))):
            raise ValueError("the reference trajectory draws only its own poses")
        return xyz

    traj = Trajectory(backend="exudyn", _points=points, **arrays)
    return traj, res, held_err


def simulate(crane: Crane, initial: State, inputs: Inputs, horizon: float, *,
             dt: float = DEFAULT_REFERENCE_DT, spectral_radius: float = 0.5,
             oil_element: str = "ode2") -> ReferenceRun:
    """Runs the Exudyn reference model; see the module text for what it contains.

    The motion is integrated in smooth pieces between end-stop events (event-driven): while no
    stop is touched, or a stopped cylinder is held on it by a distance constraint, Exudyn's
    generalized-alpha integrates a smooth DAE; at an event the piece ends (Exudyn shortens the step
    so that it ends at the event), the contact changes, and a new piece starts from that state.

    ``oil_element``: "ode2" (the chamber equations of docs/model.md, second order) or "exudyn"
    (Exudyn's ObjectConnectorHydraulicActuatorSimple, for cross-checks: orifice valve without
    spool lag or leakage; its laminar region, relief and anti-cavitation valves are absent)."""
    from . import api

    api._check(crane, initial, inputs, horizon, dt, "c")  # the same input checks as predict()
    for name in ("slew", "extension"):
        if not isinstance(getattr(inputs, name, None) or Hold(), Hold):
            raise ValueError(f"Inputs.{name}: the planar reference holds the slew and the extension; "
                             "a future that moves them runs on cranepredict.reference_spatial")
    if oil_element not in ("ode2", "exudyn"):
        raise ValueError(f"oil_element must be 'ode2' or 'exudyn', got {oil_element!r}")
    if oil_element == "exudyn":
        for j, drive in enumerate((inputs.lift, inputs.tilt)):
            if _is_valve(drive):
                _actuator_circuit(_cyl(crane, j))

    wall0 = time.perf_counter()
    bodies = _bodies(crane, initial.extension)
    oil0 = {j: (*initial.pressures(joint), getattr(initial, f"{joint}_spool"))
            for j, joint in enumerate(("lift", "tilt"))
            if _is_valve((inputs.lift, inputs.tilt)[j])}
    pieces, events = _event_loop(crane, bodies, initial, inputs, oil0, horizon, dt, spectral_radius,
                                 oil_element)
    t, q, qd, stop, oil = _join(pieces)
    wall = time.perf_counter() - wall0
    traj, res, held_err = _output(crane, bodies, initial, inputs, t, q, qd, stop, oil)
    return ReferenceRun(trajectory=traj, wall=wall, residual_max=res, held_length_error=held_err,
                        dt=dt, events=events)


def _strokes_and_rates(crane: Crane, bodies, q: Dict[str, np.ndarray], qd: Dict[str, np.ndarray]):
    """Strokes and stroke rates from the bodies' node coordinates and velocities."""
    def point(name, p):
        if name == "ground":
            return np.array(p, dtype=float), np.zeros(2)
        local = np.array(p, dtype=float) - bodies[name][1]
        r = _rot(q[name][2]) @ local
        w = qd[name][2]
        return q[name][:2] + r, qd[name][:2] + w * np.array([-r[1], r[0]])

    g = crane.geometry
    s, rates = [], []
    for cyl, base, rod in ((crane.lift_cylinder, ("ground", g.lift_cylinder_base), ("lift", g.lift_cylinder_rod)),
                           (crane.tilt_cylinder, ("lift", g.tilt_cylinder_base), ("link1", g.link_pin))):
        (pb, vb), (pr, vr) = point(*base), point(*rod)
        d = pr - pb
        L = float(np.hypot(*d))
        s.append(L - cyl.length_retracted)
        rates.append(float(d @ (vr - vb)) / L)
    return s, rates


def predict_reference(crane: Crane, initial: State, inputs: Inputs, horizon: float, *,
                      dt: Optional[float] = None) -> Trajectory:
    """The reference model's :class:`Trajectory` (same arguments as :func:`cranepredict.predict`)."""
    return simulate(crane, initial, inputs, horizon,
                    dt=DEFAULT_REFERENCE_DT if dt is None else dt).trajectory


# -- comparison with the fast model --------------------------------------------------------------

#: The fast model's targets against this reference (docs/validation.md), used by ``cranepredict
#: validate`` and the tests: per scenario a tip error of at most 20 mm (max) and 10 mm (RMS), and
#: the fast model at least 100 times faster.
TARGET_MAX_MM = 20.0
TARGET_RMS_MM = 10.0
TARGET_SPEED_RATIO = 100.0
#: and for valve-driven cylinders a chamber-pressure RMS error of at most 2 bar (the validation targets).
TARGET_PRESSURE_RMS_BAR = 2.0

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
        from . import reference_spatial

        run = reference_spatial.simulate(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_ref)
        ref, residual, kind = run, None, "spatial"
    else:
        run = simulate(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_ref)
        ref, residual, kind = run.trajectory, run.residual_max, "planar"
    tip_ref = np.stack([np.interp(fast.t, ref.t, ref.tip[:, i]) for i in range(3)], 1)
    err = np.linalg.norm(tip_ref - fast.tip, axis=1)
    stops = [x for x in (fast.t[np.flatnonzero(fast.stop.any(1))[:1]].tolist()
                         + ref.t[np.flatnonzero(ref.stop.any(1))[:1]].tolist())]
    t_stop = min(stops) if stops else None
    before = err if t_stop is None else err[fast.t < t_stop]
    after = None if t_stop is None else err[fast.t >= t_stop]

    def mx(a):
        return None if a is None or a.size == 0 else float(a.max())

    p_rms = {}
    for j in (j for j, d in enumerate(drives) if _is_valve(d)):
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
