"""Spatial reference model of the four-joint crane (slew, lift, tilt, extension) on the Exudyn
engine (install extra ``[reference]``); docs/model.md, section "Four joints".

A second, independent formulation of the fast model's four-joint dynamics, for checking the twin
(and later the C core). What it does differently:

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
  or a fixed slew joint).

Limits: the crane starts at rest, and **no end stop** is modelled: a run that leaves an actuator's
range raises ValueError (the five issue-11 scenarios here stay inside them; the telescope into its
end stop is not covered).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Dict, Optional

import numpy as np

from .crane import Crane
from .types import Hold, Pressure, PressureSeries

__all__ = ["SpatialRun", "simulate", "DEFAULT_SPATIAL_DT", "available"]

#: Default step of the spatial reference integrator, s.
DEFAULT_SPATIAL_DT = 2.5e-4

# the boom plane (x out, y up, z normal) into the world at slew 0: (x, y, z) -> (x, -z, y)
_PLANE = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def available() -> bool:
    """True if the Exudyn engine can be imported."""
    try:
        import exudyn  # noqa: F401
    except ImportError:
        return False
    return True


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _world(psi: float) -> np.ndarray:
    return _rz(psi) @ _PLANE


def _circle(c0, r0, c1, r1, sign):
    d = c1 - c0
    dist = float(np.hypot(*d))
    a = (r0 ** 2 - r1 ** 2 + dist ** 2) / (2 * dist)
    u = d / dist
    return c0 + a * u + sign * math.sqrt(r0 ** 2 - a ** 2) * np.array([-u[1], u[0]])


def _angle(v) -> float:
    return math.atan2(v[1], v[0])


def _tensor(body) -> np.ndarray:
    xx = 0.0 if body.ixx is None else body.ixx
    yy = body.izz if body.iyy is None else body.iyy
    xy = 0.0 if body.ixy is None else body.ixy
    return np.array([[xx, xy, 0.0], [xy, yy, 0.0], [0.0, 0.0, body.izz]])


def _friction(fr, v: float) -> float:
    """[S1]'s friction law (docs/model.md, "Cylinders"), opposing v."""
    x = abs(v) / fr.stribeck_velocity
    q = x * x / 4 + 0.75
    levels = fr.factor * (fr.coulomb * math.tanh(4 * x) + (fr.static - fr.coulomb) * x / (q * q))
    return math.copysign(levels, v) + fr.viscous * math.tanh(4) * v


def _pressures(drive):
    if isinstance(drive, Pressure):
        pa, pb = drive.p_a, drive.p_b
        return lambda t: (pa, pb)
    if isinstance(drive, PressureSeries):
        ts, pas, pbs = (np.asarray(a, dtype=float) for a in (drive.t, drive.p_a, drive.p_b))
        return lambda t: (float(np.interp(t, ts, pas)), float(np.interp(t, ts, pbs)))
    raise TypeError(f"not a pressure drive: {drive!r}")


@dataclass(frozen=True)
class SpatialRun:
    """The reference's samples: t (N,), tip (N, 3) world, slew (N,), extension (N,); wall
    time, s."""

    t: np.ndarray
    tip: np.ndarray
    slew: np.ndarray
    extension: np.ndarray
    wall_time: float


def _pose(crane: Crane, lift_stroke: float, tilt_stroke: float) -> Dict[str, Any]:
    """Boom-plane angles of the lift boom, the outer boom and the side links (from the strokes,
    closed-form triangle and four-bar) and the pins Q, A in the lift boom frame."""
    g = crane.geometry
    o1, b1, e1 = (np.array(v, float) for v in (g.lift_pivot, g.lift_cylinder_base, g.lift_cylinder_rod))
    db, dr = np.hypot(*(b1 - o1)), np.hypot(*e1)
    length = crane.lift_cylinder.length_retracted + lift_stroke
    gamma = math.acos((db * db + dr * dr - length * length) / (2 * db * dr))
    th0 = gamma - _angle(e1) + _angle(b1 - o1)
    b2, p1, o2 = (np.array(v, float) for v in (g.tilt_cylinder_base, g.link1_pivot, g.tilt_pivot))
    pin, end2, attach = (np.array(v, float) for v in (g.link_pin, g.link2_end, g.link2_attach))
    lt = crane.tilt_cylinder.length_retracted + tilt_stroke
    q = _circle(p1, np.hypot(*pin), b2, lt, -1.0)
    a = _circle(o2, np.hypot(*attach), q, np.hypot(*end2), -1.0)
    th1 = _angle(a - o2) - _angle(attach)
    phi1 = _angle(q - p1) - _angle(pin)
    phi2 = _angle(a - q) - _angle(end2)
    return {"th0": th0, "th1": th1, "phi1": phi1, "phi2": phi2, "q": q, "a": a}


def simulate(crane: Crane, lift_stroke: float, tilt_stroke: float, slew: float, extension: float,
             drives: Dict[str, Any], horizon: float, *, dt: float = DEFAULT_SPATIAL_DT,
             sample_dt: float = 2e-3, spectral_radius: float = 0.9) -> SpatialRun:
    """Integrates the crane from rest with the drives {"lift", "tilt", "slew", "extension"}
    (Pressure, PressureSeries or Hold; left out = Hold) over [0, horizon]."""
    import exudyn as exu
    from exudyn.itemInterface import (MarkerBodyPosition, MarkerBodyRigid, ObjectConnectorDistance,
                                      ObjectConnectorSpringDamper, ObjectConnectorTorsionalSpringDamper,
                                      ObjectGround, ObjectJointGeneric, ObjectJointPrismaticX,
                                      ObjectJointRevoluteZ, SensorBody)
    from exudyn.utilities import RigidBodyInertia

    drives = {k: drives.get(k, Hold()) for k in ("lift", "tilt", "slew", "extension")}
    g = crane.geometry
    pose = _pose(crane, lift_stroke, tilt_stroke)
    th0, th1 = pose["th0"], pose["th1"]
    o1, o2 = np.array(g.lift_pivot, float), np.array(g.tilt_pivot, float)
    p1 = np.array(g.link1_pivot, float)
    mount = np.array(g.extension_mount, float)
    tip_local = np.array([g.tip_distance, 0.0])

    def rot2(a):
        c, s = math.cos(a), math.sin(a)
        return np.array([[c, -s], [s, c]])

    # body 3: extension boom + load, a rigid union lumped exactly (parallel axes, full tensor)
    eb = crane.extension_boom
    m3 = eb.mass + crane.load_mass
    c3 = (eb.mass * np.array(eb.com) + crane.load_mass * tip_local) / m3

    def shifted(m, d):
        d3 = np.array([d[0], d[1], 0.0])
        return m * (d3 @ d3 * np.eye(3) - np.outer(d3, d3))

    j3 = _tensor(eb) + shifted(eb.mass, np.array(eb.com) - c3) + shifted(crane.load_mass, tip_local - c3)

    # frames in the boom plane: (angle, origin) of each body frame
    frames = {
        "pillar": (0.0, np.zeros(2)),
        "lift": (th0, o1),
        "outer": (th0 + th1, o1 + rot2(th0) @ o2),
        "ext": (th0 + th1, o1 + rot2(th0) @ (o2 + rot2(th1) @ (mount + np.array([extension, 0.0])))),
        "link1": (th0 + pose["phi1"], o1 + rot2(th0) @ p1),
        "link2": (th0 + pose["phi2"], o1 + rot2(th0) @ pose["q"]),
    }
    masses = {
        "pillar": (crane.pillar.mass, np.array(crane.pillar.com), _tensor(crane.pillar)),
        "lift": (crane.lift_boom.mass, np.array(crane.lift_boom.com), _tensor(crane.lift_boom)),
        "outer": (crane.outer_boom.mass, np.array(crane.outer_boom.com), _tensor(crane.outer_boom)),
        "ext": (m3, c3, j3),
        "link1": (crane.side_link1.mass, np.array(crane.side_link1.com), _tensor(crane.side_link1)),
        "link2": (crane.side_link2.mass, np.array(crane.side_link2.com), _tensor(crane.side_link2)),
    }
    w0 = _world(slew)

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    bodies = {}
    for name, (phi, origin) in frames.items():
        m, com, tensor = masses[name]
        rot = w0 @ _rz(phi)
        pos = w0 @ np.array([*(origin + rot2(phi) @ com), 0.0])
        bodies[name] = mbs.CreateRigidBody(
            inertia=RigidBodyInertia(mass=m, inertiaTensor=tensor),
            referencePosition=list(pos), referenceRotationMatrix=rot,
            gravity=[0.0, 0.0, -crane.gravity])

    def local(name, p):
        """A point given in a body's frame (boom-plane coordinates), relative to its centre."""
        com = masses[name][1]
        return [float(p[0] - com[0]), float(p[1] - com[1]), 0.0]

    def rigid(name, p):
        return mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies[name], localPosition=local(name, p)))

    def point(name, p):
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodies[name], localPosition=local(name, p)))

    # --- joints ------------------------------------------------------------------------------
    # the slew axis: world Z = the pillar's local y; the joint frame's z put on it
    to_y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
    slew_g = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0]))
    slew_p = rigid("pillar", (0.0, 0.0))
    base_rot = _rz(slew) @ np.eye(3)         # ground joint frame turned with the initial slew
    if isinstance(drives["slew"], Hold):
        mbs.AddObject(ObjectJointGeneric(markerNumbers=[slew_g, slew_p], constrainedAxes=[1] * 6,
                                         rotationMarker0=base_rot, rotationMarker1=to_y))
    else:
        mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[slew_g, slew_p], rotationMarker0=base_rot,
                                           rotationMarker1=to_y))
        sd = crane.slew_drive
        area, r_p = math.pi * sd.bore ** 2 / 4, sd.pinion_radius
        pfun = _pressures(drives["slew"])

        def slew_law(mbs_, t, item, rotation, angular_velocity, stiffness, damping, offset):
            pa, pb = pfun(t)
            torque = r_p * (area * (pa - pb) - _friction(sd.friction, r_p * angular_velocity))
            return -torque                   # the connector's torque acts against its rotation

        mbs.AddObject(ObjectConnectorTorsionalSpringDamper(
            markerNumbers=[slew_g, slew_p], rotationMarker0=base_rot, rotationMarker1=to_y,
            springTorqueUserFunction=slew_law))
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("pillar", o1), rigid("lift", (0.0, 0.0))]))
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("lift", o2), rigid("outer", (0.0, 0.0))]))
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("lift", p1), rigid("link1", (0.0, 0.0))]))
    mbs.AddObject(ObjectJointRevoluteZ(markerNumbers=[rigid("link1", g.link_pin), rigid("link2", (0.0, 0.0))]))
    # the four-bar's closure: in-plane position only (the loop is planar; [S1] closes it so too)
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[rigid("link2", g.link2_end), rigid("outer", g.link2_attach)],
                                     constrainedAxes=[1, 1, 0, 0, 0, 0]))
    ext_outer = rigid("outer", mount + np.array([extension, 0.0]))
    ext_body = rigid("ext", (0.0, 0.0))
    mbs.AddObject(ObjectJointPrismaticX(markerNumbers=[ext_outer, ext_body]))

    # --- actuators -----------------------------------------------------------------------------
    def spring(markers, cyl_areas, friction, drive, length0, held_length):
        if isinstance(drive, Hold):
            mbs.AddObject(ObjectConnectorDistance(markerNumbers=markers, distance=held_length))
            return None
        aa, ab = cyl_areas
        pfun = _pressures(drive)

        def law(mbs_, t, item, dlength, rate, stiffness, damping, force):
            pa, pb = pfun(t)
            return -(pa * aa - pb * ab - _friction(friction, rate))
        return mbs.AddObject(ObjectConnectorSpringDamper(markerNumbers=markers, referenceLength=length0,
                                                         springForceUserFunction=law))

    lc, tc, ec = crane.lift_cylinder, crane.tilt_cylinder, crane.extension_cylinder
    spring([point("pillar", g.lift_cylinder_base), point("lift", g.lift_cylinder_rod)],
           (lc.area_a, lc.area_b), lc.friction, drives["lift"], lc.length_retracted,
           lc.length_retracted + lift_stroke)
    spring([point("lift", g.tilt_cylinder_base), point("link1", g.link_pin)],
           (tc.area_a, tc.area_b), tc.friction, drives["tilt"], tc.length_retracted,
           tc.length_retracted + tilt_stroke)
    # the extension cylinder along the boom axis: from 1 m behind the extension's origin at the
    # lower end of its range to the extension boom's origin, length 1 + (e - extension_min)
    behind = mount + np.array([g.extension_min - 1.0, 0.0])
    ext_markers = [point("outer", behind), point("ext", (0.0, 0.0))]
    spring(ext_markers, (ec.area_a, ec.area_b) if ec else (0.0, 0.0), ec.friction if ec else None,
           drives["extension"], 0.0, 1.0 + extension - g.extension_min)

    tip = mbs.AddSensor(SensorBody(bodyNumber=bodies["ext"], localPosition=local("ext", tip_local),
                                   storeInternal=True, outputVariableType=exu.OutputVariableType.Position))
    ext_pos = mbs.AddSensor(SensorBody(bodyNumber=bodies["ext"], localPosition=local("ext", (0.0, 0.0)),
                                       storeInternal=True, outputVariableType=exu.OutputVariableType.Position))
    # where the extension boom's origin started, on the outer boom
    ext_start = mbs.AddSensor(SensorBody(bodyNumber=bodies["outer"],
                                         localPosition=local("outer", mount + np.array([extension, 0.0])),
                                         storeInternal=True,
                                         outputVariableType=exu.OutputVariableType.Position))
    pillar_rot = mbs.AddSensor(SensorBody(bodyNumber=bodies["pillar"], localPosition=[0.0, 0.0, 0.0],
                                          storeInternal=True,
                                          outputVariableType=exu.OutputVariableType.RotationMatrix))
    mbs.Assemble()

    ss = exu.SimulationSettings()
    ss.timeIntegration.endTime = float(horizon)
    ss.timeIntegration.numberOfSteps = int(round(horizon / dt))
    ss.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.newton.relativeTolerance = 1e-10
    ss.timeIntegration.newton.absoluteTolerance = 1e-8
    ss.solutionSettings.sensorsWritePeriod = sample_dt
    ss.solutionSettings.writeSolutionToFile = False
    ss.displayComputationTime = False
    ss.displayStatistics = False
    start = time.perf_counter()
    mbs.SolveDynamic(ss)
    wall = time.perf_counter() - start

    tip_data = mbs.GetSensorStoredData(tip)
    t = tip_data[:, 0]
    rot = mbs.GetSensorStoredData(pillar_rot)[:, 1:].reshape(-1, 3, 3)
    slew_t = np.arctan2(rot[:, 1, 0], rot[:, 0, 0])
    slew_t = slew + np.unwrap(slew_t - slew_t[0]) + (slew_t[0] - slew)
    # the extension: the extension boom's origin from the mount, along the outer boom
    p_e = mbs.GetSensorStoredData(ext_pos)[:, 1:]
    along = tip_data[:, 1:] - p_e
    along /= np.linalg.norm(along, axis=1)[:, None]
    ext_t = extension + np.einsum("ij,ij->i", p_e - mbs.GetSensorStoredData(ext_start)[:, 1:], along)
    sd = crane.slew_drive
    tol = 1e-9
    if ext_t.min() < g.extension_min - tol or ext_t.max() > g.extension_max + tol:
        raise ValueError(f"the spatial reference has no end stops: the extension left "
                         f"[{g.extension_min}, {g.extension_max}] m (reached [{ext_t.min():.4f}, {ext_t.max():.4f}])")
    if sd is not None and (slew_t.min() < sd.slew_min - tol or slew_t.max() > sd.slew_max + tol):
        raise ValueError("the spatial reference has no end stops: the slew left its range")
    return SpatialRun(t=t, tip=tip_data[:, 1:], slew=slew_t, extension=ext_t, wall_time=wall)
