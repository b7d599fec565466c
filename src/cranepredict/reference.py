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
  equations of docs/model.md "Hydraulics" (:func:`cranepredict.reference_common.oil_rates`, one
  formula for both references), fed by the stroke and stroke rate of the cylinder's force
  element. Exudyn integrates ODE1 coordinates at first order only (a theta-method, theta = 2/3,
  measured), so each of these first-order quantities is the velocity of an ODE2 coordinate
  (``ObjectGenericODE2``, unit mass, force = its rate), which generalized-alpha integrates at
  second order. ``oil_element="exudyn"`` uses Exudyn's own
  ``ObjectConnectorHydraulicActuatorSimple`` instead (published orifice law only), as a
  cross-check. At an end stop the pressures keep evolving with the stroke locked; they carry
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
:func:`_segment` integrate it to its first end-stop event, :func:`_event_loop` strings the pieces
together across impacts and releases, :func:`_join` and :func:`_output` turn them into the
trajectory. The laws this model shares with the spatial reference (drives, friction, valves and
oil, the impact, event location, the solver's settings) are :mod:`cranepredict.reference_common`'s.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Dict, Optional, Tuple

import numpy as np

from . import reference_common as common
from .crane import Crane
from .reference_common import STOP_TOLERANCE, available
from .types import POINT_NAMES, Hold, Inputs, State, Trajectory

__all__ = ["predict_reference", "simulate", "ReferenceRun", "DEFAULT_REFERENCE_DT",
           "STOP_TOLERANCE", "available"]

#: Default step of the reference integrator, s (convergence: docs/validation.md).
DEFAULT_REFERENCE_DT = 2.5e-4


# -- the outer boom's lumped body ----------------------------------------------------------------

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
    p = common.pose(crane, lift_stroke, tilt_stroke)
    O1 = np.array(g.lift_pivot)
    R = common.rot(p.th_lift)
    frames = {"lift": (O1, p.th_lift),
              "outer": (O1 + R @ np.array(g.tilt_pivot), p.th_outer),
              "link1": (O1 + R @ np.array(g.link1_pivot), p.ph_link1),
              "link2": (p.o_link2, p.ph_link2)}
    return {k: np.array([*(o + common.rot(a) @ bodies[k][1]), a]) for k, (o, a) in frames.items()}


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
        if common.is_valve(drive) and oil_element == "exudyn":
            pressures, spring = _add_actuator(mbs, crane, j, drive, oil[j], t0, oil_nodes, mks,
                                              pre_steps)
        elif common.is_valve(drive):
            pressures, spring = _add_oil(mbs, crane, j, drive, oil[j], t0, oil_nodes)
        else:
            pressures, spring = common.pressure_fn(drive), [None]
        spring[0] = mbs.AddObject(ObjectConnectorSpringDamper(
            markerNumbers=mks, referenceLength=cyl.length_retracted,
            springForceUserFunction=common.cylinder_law(cyl, pressures, t0)))   # pressures None: friction only
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
    """The oil of valve-driven cylinder j (:func:`cranepredict.reference_common.add_oil`), its
    stroke and stroke rate measured on the cylinder's force element. ``oil0`` = (p_a, p_b, y) at
    t0. Returns the pressure function for the force element and a one-item list to receive the
    force element."""
    import exudyn as exu
    cyl = _cyl(crane, j)
    spring = [None]
    L0 = cyl.length_retracted

    def measure(mbs_):
        d = mbs_.GetObjectOutput(spring[0], exu.OutputVariableType.Displacement)
        v = mbs_.GetObjectOutput(spring[0], exu.OutputVariableType.Velocity)
        L = math.hypot(d[0], d[1])
        return L - L0, (d[0] * v[0] + d[1] * v[1]) / L

    node = common.add_oil(mbs, common.circuit(cyl), common.lever_fn(drive), oil0, t0, measure)
    oil_nodes[j] = (node, exu.OutputVariableType.Coordinates_t, common.P_UNIT)
    return common.oil_pressures(node), spring


def _actuator_circuit(cyl) -> common.Circuit:
    c = common.circuit(cyl)
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
    lever = common.lever_fn(drive)

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
    (located to RELEASE_TOLERANCE); see :func:`cranepredict.reference_common.watch`."""
    import exudyn as exu
    mbs, watched = model.mbs, model.watched

    def gap_fn(j: int):
        kind, obj, extra = watched[j]
        if kind == "impact":
            def gap():
                stroke = float(mbs.GetObjectOutput(obj, exu.OutputVariableType.Distance)) - extra.length_retracted
                return common.stop_gap(stroke, extra.stroke_min, extra.stroke_max)
            return gap

        def pull():
            return common.stop_pull(float(mbs.GetObjectOutput(obj, exu.OutputVariableType.Force)), extra)
        return pull

    gaps = {}
    for j in watched:
        cyl = _cyl(crane, j)
        g0 = common.stop_gap(s[j], cyl.stroke_min, cyl.stroke_max)[0] if watched[j][0] == "impact" else None
        gaps[j] = (watched[j][0], gap_fn(j), g0)
    return common.watch(mbs, gaps)


@dataclass
class _Piece:
    """The samples of one smooth piece: time, node coordinates and velocities per body, and the
    cylinders' modes during it."""

    t: np.ndarray
    q: Dict[str, np.ndarray]
    qd: Dict[str, np.ndarray]
    modes: list
    oil: Dict[int, np.ndarray]    #: valve-driven cylinder -> (N, 3) p_a, p_b (Pa), spool y


def _segment(crane: Crane, bodies, inputs: Inputs, modes, s, rates, held, oil, t0: float,
             t_end: float, dt: float, spectral_radius: float,
             oil_element: str = "ode2") -> Tuple[_Piece, list]:
    """Integrates one smooth piece of the motion from (strokes s, stroke rates) at t0 until t_end or
    the first event (see :func:`_build` and :func:`_watch_events`). Returns the piece and the
    events that ended it (empty: it reached t_end)."""
    model = _build(crane, bodies, inputs, modes, s, rates, held, oil, t0, oil_element)
    st = _watch_events(model, crane, s)
    common.solve(model.mbs, t_end - t0, dt, spectral_radius)
    data = {k: (model.mbs.GetSensorStoredData(model.sensors[k][0]),
                model.mbs.GetSensorStoredData(model.sensors[k][1])) for k in _ORDER}
    t = data["lift"][0][:, 0] + t0
    q = {k: data[k][0][:, 1:4] + model.q0[k] for k in _ORDER}   # sensors give displacements
    qd = {k: data[k][1][:, 1:4] for k in _ORDER}
    drives = (inputs.lift, inputs.tilt)
    p = {j: common.oil_samples(model.mbs.GetSensorStoredData(sn)[:, 1:], unit, common.lever_fn(drives[j]), t)
         for j, (sn, unit) in model.oil_sensors.items()}
    return _Piece(t=t, q=q, qd=qd, modes=list(modes), oil=p), st["events"]


# -- the event loop: pieces between end-stop events ----------------------------------------------

def _limits(crane: Crane):
    """(stroke_min, stroke_max) of the lift and the tilt cylinder."""
    return [(c.stroke_min, c.stroke_max) for c in (crane.lift_cylinder, crane.tilt_cylinder)]


def _event_loop(crane: Crane, bodies, initial: State, inputs: Inputs, oil, horizon: float,
                dt: float, spectral_radius: float, oil_element: str = "ode2") -> Tuple[list, list]:
    """Integrates the motion in smooth pieces between end-stop events, from the initial state and
    ``oil`` (valve-driven cylinder -> initial (p_a, p_b, spool)). Returns the pieces and the events
    (t, kind, cylinder, side). The pressures carry across an event unchanged."""
    def mass_matrix(s):
        return _stroke_mass_matrix(crane, bodies, tuple(s))

    limits = _limits(crane)
    x = SimpleNamespace(s=[initial.lift_stroke, initial.tilt_stroke],
                        rates=[initial.lift_stroke_rate, initial.tilt_stroke_rate], oil=oil)
    held = list(x.s)
    modes = ["held" if isinstance(c[1], Hold) else 0 for c in _cylinders(crane, inputs)]
    events: list = []
    common.start_on_stops(limits, mass_matrix, modes, x.s, x.rates, events)

    def integrate(t0):
        return _segment(crane, bodies, inputs, modes, x.s, x.rates, held, x.oil, t0, horizon, dt,
                        spectral_radius, oil_element)

    def after_events(piece, evs, t0):
        x.oil = {j: tuple(p[-1]) for j, p in piece.oil.items()}
        x.s, x.rates = _strokes_and_rates(crane, bodies, {k: piece.q[k][-1] for k in _ORDER},
                                          {k: piece.qd[k][-1] for k in _ORDER})
        common.apply_events(limits, mass_matrix, evs, t0, modes, x.s, x.rates, events)

    return common.run_pieces(integrate, after_events, horizon), events


def _join(pieces: list):
    """One time series from the pieces (:func:`cranepredict.reference_common.join_pieces`); pieces
    of length zero (an event at their start) leave no sample. Returns t, q, qd, the (N, 2) stop
    flags and the pressures per valve-driven cylinder."""
    def cat(get):
        return common.join_pieces(pieces, get)

    t = cat(lambda p: p.t)
    q = {k: cat(lambda p, k=k: p.q[k]) for k in _ORDER}
    qd = {k: cat(lambda p, k=k: p.qd[k]) for k in _ORDER}
    mode_rows = common.stop_rows(pieces)
    oil = {j: cat(lambda p, j=j: p.oil[j]) for j in pieces[0].oil}
    keep = common.increasing(t)
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
        if common.is_valve(drive):
            c = common.circuit(cyl)
            pa, pb, y = oil[j][:, 0], oil[j][:, 1], oil[j][:, 2]
            flows = np.array([common.valve_flows(c, *v) for v in zip(y, pa, pb)]).reshape(-1, 2)
            out["p_a"][:, j], out["p_b"][:, j], out["spool"][:, j] = pa, pb, y
            out["flow_a"][:, j], out["flow_b"][:, j] = flows[:, 0], flows[:, 1]
        else:
            out["p_a"][:, j], out["p_b"][:, j] = common.drive_pressures(drive, t).T
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
            if common.is_valve(drive):
                _actuator_circuit(_cyl(crane, j))

    wall0 = time.perf_counter()
    bodies = _bodies(crane, initial.extension)
    oil0 = {j: (*initial.pressures(joint), getattr(initial, f"{joint}_spool"))
            for j, joint in enumerate(("lift", "tilt"))
            if common.is_valve((inputs.lift, inputs.tilt)[j])}
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
        r = common.rot(q[name][2]) @ local
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
