"""Spatial reference model of the four-joint crane (slew, lift, tilt, extension) on the Exudyn
engine (install extra ``[reference]``); docs/model.md, section "Four joints"; docs/validation.md.

A second, independent formulation of the fast model's four-joint dynamics, for checking the twin
and the C core. What it does differently:

* every body is a **3D rigid body** with its full inertia tensor (the crane file's ``ixx``,
  ``iyy``, ``ixy``, ``izz``; Euler-parameter nodes, redundant coordinates): the pillar, the lift
  boom, the outer boom, the extension boom with the load (a rigid union, lumped exactly), and the two
  side links of the four-bar;
* the joints are the **engine's constraints**: the slew a revolute joint about the world Z axis,
  lift and tilt revolute joints about the boom plane's normal, the extension a prismatic joint along
  the outer boom, the four-bar closed by its revolute joints and an in-plane pin at the outer boom
  (as [S1] closes it in 3D); an index-3 DAE solved by Exudyn's implicit generalized-alpha;
* the actuators are **force elements**: the lift, tilt and extension cylinders spring-damper
  connectors between their pins with the force ``p_a A_a - p_b A_b - F_fric(v)`` along the pin
  line; the slew drive a torsional connector about the slew axis with
  ``r_p (A (p_a - p_b) - F_fric(r_p omega_s))``; a held actuator is a rigid constraint (distance,
  or a fixed slew joint);
* the drives are those of the fast model: pressure (constant or samples), hold, and the **valve
  with the oil** on any of the four actuators: the chamber pressures (and the spool) are
  integrated by Exudyn with the mechanics from the chamber equations of docs/model.md
  "Hydraulics" as :mod:`cranepredict.reference_common` writes them (``oil_rates``: one formula for
  both references), fed by the stroke and the stroke rate measured on the actuator's force element
  (pin distance, or the slew connector's rotation: rack travel ``r_p (psi - slew_min)``);
* the **end stops** of all four actuators (lift and tilt stroke, the slew range, the extension
  range) are rigid unilateral contacts with a perfectly plastic impact, event-driven as in
  :mod:`cranepredict.reference` (the impact, the event locator and the loop over the pieces are
  :mod:`cranepredict.reference_common`'s): the motion is integrated
  in smooth pieces; a piece ends when an actuator reaches a limit (located to ``STOP_TOLERANCE``)
  or a stop would have to pull (``RELEASE_TOLERANCE``); the impact's impulse acts along that
  actuator only (``dv = -v_j M^-1 e_j / (M^-1)_jj`` over the free actuators, M the 4x4 mass
  matrix in actuator coordinates from the bodies' Jacobians, by differences of the 3D poses), and
  the next piece holds the actuator on its limit by a rigid constraint while its force element
  keeps acting. No penalty parameters, no rebound; the pressures carry across every event.

Coordinates of the state: q = (lift stroke, tilt stroke, slew, extension), m, m, rad, m.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from . import reference_common as common
from .crane import Crane
from .reference_common import available
from .types import Hold, Pressure, PressureSeries, Valve, ValveSeries

__all__ = ["SpatialRun", "simulate", "DEFAULT_SPATIAL_DT", "JOINTS", "available"]

#: Default step of the spatial reference integrator, s (convergence: docs/validation.md).
DEFAULT_SPATIAL_DT = 2.5e-4
#: The four actuators, in the order of every four-column array.
JOINTS = ("lift", "tilt", "slew", "extension")
LIFT, TILT, SLEW, EXTENSION = range(4)
_BODIES = ("pillar", "lift", "outer", "ext", "link1", "link2")
#: the extension cylinder's force element runs from this far behind the extension boom's origin at
#: the lower end of its range (the pin line is the boom's axis, so only its rate matters), m
_EXT_BEHIND = 1.0

# the boom plane (x out, y up, z normal) into the world at slew 0: (x, y, z) -> (x, -z, y)
_PLANE = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _world(psi: float) -> np.ndarray:
    return _rz(psi) @ _PLANE


def _tensor(body) -> np.ndarray:
    xx = 0.0 if body.ixx is None else body.ixx
    yy = body.izz if body.iyy is None else body.iyy
    xy = 0.0 if body.ixy is None else body.ixy
    return np.array([[xx, xy, 0.0], [xy, yy, 0.0], [0.0, 0.0, body.izz]])


def _shifted(m: float, d) -> np.ndarray:
    """Parallel-axis term of a point mass m at d (boom-plane vector) from the centre."""
    d3 = np.array([d[0], d[1], 0.0])
    return m * (d3 @ d3 * np.eye(3) - np.outer(d3, d3))


# -- the actuators in common terms ----------------------------------------------------------------

@dataclass(frozen=True)
class _Actuator:
    """One joint's actuator: the range of its coordinate q, and the equivalent cylinder the
    hydraulics and the force law see (``cyl``: area_a, area_b, stroke_min, stroke_max, friction,
    hydraulics), whose stroke is ``scale (q - origin)``."""

    lo: float
    hi: float
    scale: float
    origin: float
    cyl: Any


def _actuators(crane: Crane) -> List[Optional[_Actuator]]:
    g = crane.geometry
    lc, tc = crane.lift_cylinder, crane.tilt_cylinder
    out: List[Optional[_Actuator]] = [_Actuator(lc.stroke_min, lc.stroke_max, 1.0, 0.0, lc),
                                      _Actuator(tc.stroke_min, tc.stroke_max, 1.0, 0.0, tc)]
    sd = crane.slew_drive
    out.append(None if sd is None else _Actuator(
        sd.slew_min, sd.slew_max, sd.pinion_radius, sd.slew_min,
        SimpleNamespace(area_a=sd.area, area_b=sd.area, stroke_min=0.0,
                        stroke_max=sd.pinion_radius * (sd.slew_max - sd.slew_min),
                        friction=sd.friction, hydraulics=getattr(sd, "hydraulics", None))))
    ec = crane.extension_cylinder
    out.append(None if ec is None else _Actuator(
        g.extension_min, g.extension_max, 1.0, g.extension_min,
        SimpleNamespace(area_a=ec.area_a, area_b=ec.area_b, stroke_min=0.0,
                        stroke_max=g.extension_max - g.extension_min,
                        friction=ec.friction, hydraulics=getattr(ec, "hydraulics", None))))
    return out


# -- bodies and their poses as functions of q -------------------------------------------------------

def _masses(crane: Crane) -> Dict[str, Tuple[float, np.ndarray, np.ndarray]]:
    """(mass, centre of mass in the body's frame, inertia tensor about it) per body; the extension
    boom and the load are one rigid union (parallel axes, full tensor)."""
    g = crane.geometry
    eb = crane.extension_boom
    tip_local = np.array([g.tip_distance, 0.0])
    m3 = eb.mass + crane.load_mass
    c3 = (eb.mass * np.array(eb.com) + crane.load_mass * tip_local) / m3
    j3 = _tensor(eb) + _shifted(eb.mass, np.array(eb.com) - c3) + _shifted(crane.load_mass, tip_local - c3)
    body = {"pillar": crane.pillar, "lift": crane.lift_boom, "outer": crane.outer_boom,
            "link1": crane.side_link1, "link2": crane.side_link2}
    out = {k: (b.mass, np.array(b.com, float), _tensor(b)) for k, b in body.items()}
    out["ext"] = (m3, c3, j3)
    return out


def _frames(crane: Crane, q) -> Dict[str, Tuple[float, np.ndarray]]:
    """(in-plane angle, origin) of every body frame in the boom plane at q (closed-form triangle
    and four-bar: the initial condition of a piece; the engine then keeps the loops closed)."""
    g = crane.geometry
    p = common.pose(crane, q[LIFT], q[TILT])
    o1, o2, p1 = (np.array(v, float) for v in (g.lift_pivot, g.tilt_pivot, g.link1_pivot))
    outer = o1 + common.rot(p.th_lift) @ o2
    return {"pillar": (0.0, np.zeros(2)),
            "lift": (p.th_lift, o1),
            "outer": (p.th_outer, outer),
            "ext": (p.th_outer, outer + common.rot(p.th_outer) @ (np.array(g.extension_mount) + [q[EXTENSION], 0.0])),
            "link1": (p.ph_link1, o1 + common.rot(p.th_lift) @ p1),
            "link2": (p.ph_link2, p.o_link2)}


def _poses(crane: Crane, masses, q) -> Dict[str, Tuple[np.ndarray, np.ndarray]]:
    """World (rotation matrix, centre of mass) of every body at q."""
    w = _world(q[SLEW])
    out = {}
    for name, (phi, origin) in _frames(crane, q).items():
        com = origin + common.rot(phi) @ masses[name][1]
        out[name] = (w @ _rz(phi), w @ np.array([com[0], com[1], 0.0]))
    return out


def _jacobians(crane: Crane, masses, q) -> Dict[str, Tuple[np.ndarray, np.ndarray]]:
    """d(centre velocity)/dqdot and d(angular velocity, world)/dqdot per body, (3, 4) each, by
    central differences of the poses."""
    h = 1e-6
    lin = {k: np.zeros((3, 4)) for k in _BODIES}
    ang = {k: np.zeros((3, 4)) for k in _BODIES}
    base = _poses(crane, masses, q)
    for j in range(4):
        qp, qm = list(q), list(q)
        qp[j] += h
        qm[j] -= h
        pp, pm = _poses(crane, masses, qp), _poses(crane, masses, qm)
        for k in _BODIES:
            lin[k][:, j] = (pp[k][1] - pm[k][1]) / (2 * h)
            om = (pp[k][0] - pm[k][0]) / (2 * h) @ base[k][0].T     # skew(angular velocity)
            ang[k][:, j] = [om[2, 1], om[0, 2], om[1, 0]]
    return {k: (lin[k], ang[k]) for k in _BODIES}


def _mass_matrix(crane: Crane, masses, q) -> np.ndarray:
    """The 4x4 mass matrix in actuator coordinates q (all bodies, full tensors)."""
    jac = _jacobians(crane, masses, q)
    rot = _poses(crane, masses, q)
    m = np.zeros((4, 4))
    for k in _BODIES:
        jv, jw = jac[k]
        r = rot[k][0]
        m += masses[k][0] * jv.T @ jv + jw.T @ (r @ masses[k][2] @ r.T) @ jw
    return m


# -- drives ----------------------------------------------------------------------------------------

def _drives(inputs) -> List[Any]:
    """[lift, tilt, slew, extension] drives; a drive left out is held."""
    return [getattr(inputs, name, None) or Hold() for name in JOINTS]


def _check(crane: Crane, acts, q, qd, drives, oil, horizon: float, dt: float) -> None:
    if not (math.isfinite(horizon) and horizon > 0):
        raise ValueError(f"horizon must be > 0 s, got {horizon!r}")
    if not (math.isfinite(dt) and 0 < dt <= horizon):
        raise ValueError(f"dt must be in (0, horizon] s, got {dt!r}")
    for j, name in enumerate(JOINTS):
        d = drives[j]
        if not isinstance(d, (Pressure, PressureSeries, Hold, Valve, ValveSeries)):
            raise TypeError(f"inputs.{name} must be Pressure, PressureSeries, Hold, Valve or "
                            f"ValveSeries, got {type(d).__name__}")
        act = acts[j]
        if act is None and not isinstance(d, Hold):
            raise ValueError(f"inputs.{name}: the crane has no {name} actuator; only Hold() is allowed")
        if act is not None and not act.lo <= q[j] <= act.hi:
            raise ValueError(f"state: {name} {q[j]!r} outside its range [{act.lo}, {act.hi}]")
        if isinstance(d, Hold) and qd[j] != 0.0:
            raise ValueError(f"state: the held {name} must have rate 0, got {qd[j]!r}")
        if common.is_valve(d):
            if act.cyl.hydraulics is None:
                raise ValueError(f"inputs.{name}: a valve drive needs the crane file's "
                                 f"{name} hydraulics table")
            if oil[j][0] is None or oil[j][1] is None:
                raise ValueError(f"state: the valve-driven {name} needs {name}_p_a and {name}_p_b")


# -- one smooth piece as an Exudyn system ----------------------------------------------------------

@dataclass
class _Piece:
    t: np.ndarray
    q: np.ndarray        #: (N, 4)
    qd: np.ndarray       #: (N, 4)
    tip: np.ndarray      #: (N, 3)
    modes: list
    oil: Dict[int, np.ndarray]   #: valve-driven actuator -> (N, 3) p_a, p_b (Pa), spool


def _piece(crane: Crane, masses, acts, drives, modes, q, qd, held, oil, t0: float, t_end: float,
           dt: float, spectral_radius: float) -> Tuple[_Piece, list]:
    """Builds and integrates one smooth piece from (q, qd) at t0 until t_end or its first event.
    modes per actuator: "held", 0 (free, watched for an impact), -1/+1 (on that stop, watched for
    a release)."""
    import exudyn as exu
    from exudyn.itemInterface import (MarkerBodyPosition, MarkerBodyRigid, NodeGenericData,
                                      ObjectConnectorDistance, ObjectConnectorSpringDamper,
                                      ObjectConnectorTorsionalSpringDamper, ObjectGround,
                                      ObjectJointGeneric, ObjectJointPrismaticX,
                                      ObjectJointRevoluteZ, SensorBody, SensorNode)
    from exudyn.utilities import RigidBodyInertia

    g = crane.geometry
    poses = _poses(crane, masses, q)
    jac = _jacobians(crane, masses, q)
    qd_arr = np.array(qd, float)

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    bodies = {}
    for name in _BODIES:
        m, _, tensor = masses[name]
        rot, pos = poses[name]
        bodies[name] = mbs.CreateRigidBody(
            inertia=RigidBodyInertia(mass=m, inertiaTensor=tensor),
            referencePosition=list(pos), referenceRotationMatrix=rot,
            initialVelocity=list(jac[name][0] @ qd_arr), initialAngularVelocity=list(jac[name][1] @ qd_arr),
            gravity=[0.0, 0.0, -crane.gravity])

    def local(name, p):
        """A point given in a body's frame (boom-plane coordinates), relative to its centre."""
        com = masses[name][1]
        return [float(p[0] - com[0]), float(p[1] - com[1]), 0.0]

    def rigid(name, p):
        return mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies[name], localPosition=local(name, p)))

    def point(name, p):
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodies[name], localPosition=local(name, p)))

    # --- joints (the slew's below, with its drive) ------------------------------------------------
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("pillar", g.lift_pivot), rigid("lift", (0.0, 0.0))]))
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("lift", g.tilt_pivot), rigid("outer", (0.0, 0.0))]))
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("lift", g.link1_pivot), rigid("link1", (0.0, 0.0))]))
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("link1", g.link_pin), rigid("link2", (0.0, 0.0))]))
    # the four-bar's closure: in-plane position only (the loop is planar; [S1] closes it so too)
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[rigid("link2", g.link2_end), rigid("outer", g.link2_attach)],
                                     constrainedAxes=[1, 1, 0, 0, 0, 0]))
    mount = np.array(g.extension_mount, float)
    mbs.AddObject(ObjectJointPrismaticX(markerNumbers=[rigid("outer", mount + [q[EXTENSION], 0.0]),
                                                       rigid("ext", (0.0, 0.0))]))

    # --- actuators: force elements, stops, holds, oil --------------------------------------------
    force_el: Dict[int, int] = {}            # actuator -> its force element
    measure: Dict[int, Any] = {}             # actuator -> mbs -> (q_j, qd_j) from its force element
    gaps: Dict[int, tuple] = {}              # actuator -> (kind, gap(), gap at start) for common.watch
    oil_nodes: Dict[int, int] = {}

    def pressures_of(j):
        """(mbs, t) -> (p_a, p_b) at absolute time t: the oil state or the pressure drive."""
        if common.is_valve(drives[j]):
            return common.oil_pressures(oil_nodes[j])
        return common.pressure_fn(drives[j])

    # the slew: revolute (free) or fixed (held, on a stop) about the world Z axis through the base
    to_y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])   # joint z on the pillar's y
    slew_g = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0]))
    slew_p = rigid("pillar", (0.0, 0.0))
    base_rot = _rz(q[SLEW])
    if modes[SLEW] == 0:
        mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[slew_g, slew_p], rotationMarker0=base_rot,
                                           rotationMarker1=to_y))
    else:
        slew_fix = mbs.AddObject(ObjectJointGeneric(markerNumbers=[slew_g, slew_p], constrainedAxes=[1] * 6,
                                                    rotationMarker0=base_rot, rotationMarker1=to_y))

    linear = {LIFT: ([point("pillar", g.lift_cylinder_base), point("lift", g.lift_cylinder_rod)],
                     crane.lift_cylinder.length_retracted),
              TILT: ([point("lift", g.tilt_cylinder_base), point("link1", g.link_pin)],
                     crane.tilt_cylinder.length_retracted),
              EXTENSION: ([point("outer", mount + [g.extension_min - _EXT_BEHIND, 0.0]), point("ext", (0.0, 0.0))],
                          _EXT_BEHIND - g.extension_min)}
    # the pin distance of a linear actuator is its coordinate plus this: q_j = distance - length0

    for j in range(4):
        act = acts[j]
        if j == SLEW:
            if modes[j] == "held":
                continue
            r_p = act.scale
            psi0 = q[SLEW]
            data = mbs.AddNode(NodeGenericData(initialCoordinates=[0.0], numberOfDataCoordinates=1))
            holder = {}

            def slew_torque(mbs_, t, item, rotation, angular_velocity, stiffness, damping, offset,
                            r_p=r_p, holder=holder):
                # the connector's torque acts against its rotation: -(r_p F) = r_p law(...)
                return r_p * holder["law"](mbs_, t, item, 0.0, r_p * angular_velocity, 0.0, 0.0, 0.0)

            el = mbs.AddObject(ObjectConnectorTorsionalSpringDamper(
                markerNumbers=[slew_g, slew_p], nodeNumber=data, rotationMarker0=base_rot,
                rotationMarker1=to_y, springTorqueUserFunction=slew_torque))
            force_el[j] = el

            def slew_measure(mbs_, el=el, psi0=psi0):
                # the connector's rotation about its axis, continuous (its data node counts the turns)
                w = mbs_.GetObjectOutput(el, exu.OutputVariableType.AngularVelocityLocal)
                return psi0 + float(mbs_.GetObjectOutput(el, exu.OutputVariableType.Rotation)), float(w)
            measure[j] = slew_measure
        else:
            mks, length0 = linear[j]
            if modes[j] == "held":
                mbs.AddObject(ObjectConnectorDistance(markerNumbers=mks, distance=length0 + held[j]))
                continue
            holder = {}

            def spring_force(mbs_, t, item, dlength, rate, stiffness, damping, force, holder=holder):
                return holder["law"](mbs_, t, item, dlength, rate, stiffness, damping, force)

            el = mbs.AddObject(ObjectConnectorSpringDamper(markerNumbers=mks, referenceLength=length0,
                                                           springForceUserFunction=spring_force))
            force_el[j] = el

            def lin_measure(mbs_, el=el, length0=length0):
                d = np.asarray(mbs_.GetObjectOutput(el, exu.OutputVariableType.Displacement))
                v = np.asarray(mbs_.GetObjectOutput(el, exu.OutputVariableType.Velocity))
                dist = float(np.linalg.norm(d))
                return dist - length0, float(d @ v) / dist
            measure[j] = lin_measure

        if common.is_valve(drives[j]):
            def stroke_of(mbs_, j=j, act=act):
                qj, qdj = measure[j](mbs_)
                return act.scale * (qj - act.origin), act.scale * qdj
            oil_nodes[j] = common.add_oil(mbs, common.circuit(act.cyl), common.lever_fn(drives[j]), oil[j],
                                          t0, stroke_of)
        holder["law"] = common.cylinder_law(act.cyl, pressures_of(j), t0)

        if modes[j] == 0:
            def impact_gap(j=j, act=act):
                return common.stop_gap(measure[j](mbs)[0], act.lo, act.hi)
            gaps[j] = ("impact", impact_gap, common.stop_gap(q[j], act.lo, act.hi)[0])
        elif j == SLEW:
            # the fixed joint's torque on the pillar about Z (its z axis): a stop at slew_max
            # pushes towards -psi (torque <= 0); it would have to pull when the sign turns
            def slew_pull(side=modes[j], fix=slew_fix):
                torque = float(mbs.GetObjectOutput(fix, exu.OutputVariableType.TorqueLocal)[2])
                return (torque if side > 0 else -torque), side
            gaps[j] = ("release", slew_pull, None)
        else:
            lim = act.hi if modes[j] > 0 else act.lo
            stop = mbs.AddObject(ObjectConnectorDistance(markerNumbers=mks, distance=length0 + lim))

            def pull(side=modes[j], stop=stop):
                return common.stop_pull(float(mbs.GetObjectOutput(stop, exu.OutputVariableType.Force)), side)
            gaps[j] = ("release", pull, None)

    # --- sensors: the coordinates from the pins, the slew from the pillar, the tip -----------------
    def body_sensor(name, p, var):
        return mbs.AddSensor(SensorBody(bodyNumber=bodies[name], localPosition=local(name, p), storeInternal=True,
                                        writeToFile=False, outputVariableType=var))

    P, V = exu.OutputVariableType.Position, exu.OutputVariableType.Velocity
    pins = {LIFT: (("pillar", g.lift_cylinder_base), ("lift", g.lift_cylinder_rod)),
            TILT: (("lift", g.tilt_cylinder_base), ("link1", g.link_pin)),
            EXTENSION: (("outer", mount + [g.extension_min - _EXT_BEHIND, 0.0]), ("ext", (0.0, 0.0)))}
    pin_sensors = {j: [(body_sensor(*a, P), body_sensor(*a, V)) for a in ab] for j, ab in pins.items()}
    rot_sensor = body_sensor("pillar", (0.0, 0.0), exu.OutputVariableType.RotationMatrix)
    w_sensor = body_sensor("pillar", (0.0, 0.0), exu.OutputVariableType.AngularVelocity)
    tip_sensor = body_sensor("ext", (g.tip_distance, 0.0), P)
    oil_sensors = {j: mbs.AddSensor(SensorNode(
        nodeNumber=node, storeInternal=True, writeToFile=False,
        outputVariableType=exu.OutputVariableType.Coordinates_t)) for j, node in oil_nodes.items()}

    st = common.watch(mbs, gaps)
    common.solve(mbs, t_end - t0, dt, spectral_radius)

    def data(s):
        return mbs.GetSensorStoredData(s)

    t = data(tip_sensor)[:, 0] + t0
    qs = np.empty((t.size, 4))
    qds = np.empty((t.size, 4))
    for j, ((pa, va), (pb, vb)) in pin_sensors.items():
        d = data(pb)[:, 1:] - data(pa)[:, 1:]
        v = data(vb)[:, 1:] - data(va)[:, 1:]
        dist = np.linalg.norm(d, axis=1)
        qs[:, j] = dist - linear[j][1]
        qds[:, j] = np.einsum("ij,ij->i", d, v) / dist
    rot = data(rot_sensor)[:, 1:].reshape(-1, 3, 3)
    ang = np.arctan2(rot[:, 1, 0], rot[:, 0, 0])
    qs[:, SLEW] = q[SLEW] + np.unwrap(ang - ang[0])
    qds[:, SLEW] = data(w_sensor)[:, 3]
    for j in range(4):     # a held or stopped actuator is exactly where its constraint keeps it
        if modes[j] != 0:
            qs[:, j] = held[j] if modes[j] == "held" else (acts[j].hi if modes[j] > 0 else acts[j].lo)
            qds[:, j] = 0.0
    oil_out = {}
    for j, s in oil_sensors.items():
        oil_out[j] = common.oil_samples(data(s)[:, 1:], common.P_UNIT, common.lever_fn(drives[j]), t)
    return _Piece(t=t, q=qs, qd=qds, tip=data(tip_sensor)[:, 1:], modes=list(modes), oil=oil_out), st["events"]


# -- the event loop ---------------------------------------------------------------------------------

def _limits(acts):
    """(lower, upper) limit of each actuator's coordinate (None: the crane has no such actuator,
    which is then held)."""
    return [None if a is None else (a.lo, a.hi) for a in acts]


@dataclass(frozen=True)
class SpatialRun:
    """The spatial reference's samples (every integrator step, events included): t (N,) s;
    tip (N, 3) m, world; strokes (N, 2) m and stroke_rates (N, 2) m/s [lift, tilt]; slew (N,) rad,
    extension (N,) m and their rates; stop (N, 4) [lift, tilt, slew, extension] in actuator terms
    (-1 at the range's start, +1 at its end, 0 otherwise and when held); p_a, p_b (N, 4) Pa (the
    oil of a valve-driven actuator, the given pressures of a pressure-driven one, 0 when held),
    spool (N, 4); events: (t, "impact" | "release", joint name, side) in order; wall: s."""

    t: np.ndarray
    tip: np.ndarray
    strokes: np.ndarray
    stroke_rates: np.ndarray
    slew: np.ndarray
    extension: np.ndarray
    slew_rate: np.ndarray
    extension_rate: np.ndarray
    stop: np.ndarray
    p_a: np.ndarray
    p_b: np.ndarray
    spool: np.ndarray
    events: tuple
    wall: float
    dt: float


def simulate(crane: Crane, initial, inputs, horizon: float, *, dt: float = DEFAULT_SPATIAL_DT,
             spectral_radius: float = 0.5) -> SpatialRun:
    """Integrates the four-joint crane over [0, horizon] from ``initial`` (a State: strokes,
    slew, extension, their rates ``lift_stroke_rate``, ``tilt_stroke_rate``, ``slew_rate``,
    ``extension_rate``, and for every valve-driven actuator ``<joint>_p_a``, ``<joint>_p_b``,
    ``<joint>_spool``) with ``inputs`` (drives ``lift``, ``tilt``, ``slew``, ``extension``;
    Pressure, PressureSeries, Hold, Valve, ValveSeries; a drive left out is held)."""
    horizon, dt = float(horizon), float(dt)
    acts = _actuators(crane)
    drives = _drives(inputs)
    q = [float(initial.lift_stroke), float(initial.tilt_stroke), float(initial.slew), float(initial.extension)]
    qd = [float(getattr(initial, f"{n}_rate", 0.0) if n in ("slew", "extension")
                else getattr(initial, f"{n}_stroke_rate", 0.0)) for n in JOINTS]
    oil0 = {j: (getattr(initial, f"{n}_p_a", None), getattr(initial, f"{n}_p_b", None),
                float(getattr(initial, f"{n}_spool", 0.0)))
            for j, n in enumerate(JOINTS) if common.is_valve(drives[j])}
    _check(crane, acts, q, qd, drives, oil0, horizon, dt)

    wall0 = time.perf_counter()
    masses = _masses(crane)
    held = list(q)
    modes: list = ["held" if isinstance(d, Hold) else 0 for d in drives]
    events: list = []
    limits = _limits(acts)

    def mass_matrix(q_):
        return _mass_matrix(crane, masses, q_)

    common.start_on_stops(limits, mass_matrix, modes, q, qd, events, JOINTS.__getitem__)
    x = SimpleNamespace(q=q, qd=qd, oil=dict(oil0))

    def integrate(t0):
        return _piece(crane, masses, acts, drives, modes, x.q, x.qd, held, x.oil, t0, horizon, dt,
                      spectral_radius)

    def after_events(piece, evs, t0):
        x.oil = {j: tuple(o[-1]) for j, o in piece.oil.items()}
        x.q, x.qd = list(piece.q[-1]), list(piece.qd[-1])
        common.apply_events(limits, mass_matrix, evs, t0, modes, x.q, x.qd, events, JOINTS.__getitem__)

    pieces = common.run_pieces(integrate, after_events, horizon)
    wall = time.perf_counter() - wall0

    # one series: each piece's first sample replaces the previous piece's last (the same instant,
    # after the event)
    def cat(get):
        return common.join_pieces(pieces, get)

    t = cat(lambda p: p.t)
    keep = common.increasing(t)
    qs, qds, tip = (cat(lambda p, a=a: getattr(p, a))[keep] for a in ("q", "qd", "tip"))
    stop = common.stop_rows(pieces)[keep]
    t = t[keep]
    p_a, p_b, spool = np.zeros((t.size, 4)), np.zeros((t.size, 4)), np.zeros((t.size, 4))
    for j, d in enumerate(drives):
        if common.is_valve(d):
            o = cat(lambda p, j=j: p.oil[j])[keep]
            p_a[:, j], p_b[:, j], spool[:, j] = o[:, 0], o[:, 1], o[:, 2]
        else:
            p_a[:, j], p_b[:, j] = common.drive_pressures(d, t).T
    out = dict(t=t, tip=tip, strokes=qs[:, :2], stroke_rates=qds[:, :2], slew=qs[:, SLEW],
               extension=qs[:, EXTENSION], slew_rate=qds[:, SLEW], extension_rate=qds[:, EXTENSION],
               stop=stop, p_a=p_a, p_b=p_b, spool=spool)
    for a in out.values():
        a.setflags(write=False)
    return SpatialRun(events=tuple(events), wall=wall, dt=dt, **out)
