"""Detailed reference model of the crane on the Exudyn multibody engine (install extra ``[reference]``).

The fast model (docs/model.md) is checked against this one, as the paper checks its C model against
a Simscape Multibody model. What this model keeps that the fast one does not:

* the two **side links** of the tilt four-bar are rigid bodies with their own masses and inertias
  (crane file ``side_link1``/``side_link2``);
* the four-bar is **closed by the engine's joint constraints** (five revolute joints, index-3 DAE
  solved by Exudyn's implicit generalized-alpha integrator), not by closed-form kinematics;
* the cylinders are **force elements** between their pins (``ObjectConnectorSpringDamper`` with a
  force user function): ``F = p_a A_a - p_b A_b - F_friction(v)`` along the pin-to-pin line, with
  the same friction law and the same pressure inputs as the fast model;
* the **end stops** are compliant contacts on the cylinder stroke: when the stroke passes a limit,
  a unilateral penalty spring-damper acts along the cylinder (stiffness ``STOP_STIFFNESS``, damping
  ``STOP_DAMPING``: overcritical for the booms' effective mass, so the impact is practically
  plastic; the contact can only push, never pull, so the boom leaves the stop when the net force
  pulls it off). This is the physical picture of a piston hitting its cylinder head, without the
  rigid-plastic idealisation of the fast model.
* a **held** cylinder (closed valve) is a fixed pin-to-pin distance constraint
  (``ObjectConnectorDistance``).

Modelled planar (2D) in the boom plane, like the fast model: the slew angle and the extension are
kinematic inputs held constant during a prediction (no slew dynamics), so the motion is planar and a
3D model would add only constraints that keep it so. World output is the boom-plane result rotated
by the slew angle. The outer boom, the extension boom at its current extension and the load (a
point mass at the tip) form one rigid body (they are rigidly joined during a prediction). Cylinder
masses are not in the crane file and are neglected here too (massless force elements).

Use :func:`predict_reference` for a :class:`~cranepredict.types.Trajectory`, or :func:`simulate` for
the trajectory plus diagnostics (constraint residuals, wall time).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Dict, Optional, Tuple

import numpy as np

from .crane import Crane
from .types import POINT_NAMES, Hold, Inputs, Pressure, PressureSeries, State, Trajectory

__all__ = ["predict_reference", "simulate", "ReferenceRun", "DEFAULT_REFERENCE_DT",
           "STOP_STIFFNESS", "STOP_DAMPING", "available"]

#: Default step of the reference integrator, s (convergence: docs/validation.md).
DEFAULT_REFERENCE_DT = 2.5e-4
#: End-stop contact stiffness along the cylinder, N/m (steel-on-steel stop, far stiffer than the
#: booms: 137 kN of cylinder force presses it in by 0.014 mm).
STOP_STIFFNESS = 1e10
#: End-stop contact damping, N s/m (overcritical for an effective mass up to ~1e5 kg at the
#: cylinder: the impact is practically plastic, as in the fast model).
STOP_DAMPING = 2e9
#: The contact damping grows linearly over the first STOP_ONSET of penetration (m), so that the
#: contact force is continuous (a Hunt-Crossley-like regularisation; Newton needs it).
STOP_ONSET = 1e-6
#: Samples count as "at the stop" when the stroke is within this distance of the limit, m.
STOP_TOLERANCE = 1e-5


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
    if isinstance(drive, Pressure):
        pa, pb = drive.p_a, drive.p_b
        return lambda t: (pa, pb)
    if isinstance(drive, PressureSeries):
        ts, pas, pbs = (np.asarray(a, dtype=float) for a in (drive.t, drive.p_a, drive.p_b))
        return lambda t: (float(np.interp(t, ts, pas)), float(np.interp(t, ts, pbs)))
    raise TypeError(f"not a pressure drive: {drive!r}")


def _cylinder_law(cyl, drive, stop_k: float, stop_d: float):
    """Exudyn spring-damper user function: returns the connector's tension (positive pulls the pins
    together) = -(cylinder force) + end-stop contact forces."""
    pfun = _pressure_fn(drive)
    Aa, Ab = cyl.area_a, cyl.area_b
    fr = cyl.friction
    Fc, dFs, sig, vS, vT = fr.coulomb, fr.static - fr.coulomb, fr.viscous, fr.stribeck_velocity, fr.tanh_velocity
    smin, smax = cyl.stroke_min, cyl.stroke_max

    def law(mbs, t, itemNumber, stroke, rate, stiffness, damping, force):
        pa, pb = pfun(t)
        ffric = (Fc + dFs * math.exp(-(rate / vS) ** 2)) * math.tanh(rate / vT) + sig * rate
        tension = -(pa * Aa - pb * Ab - ffric)
        if stroke > smax:        # piston on the cylinder head: pushes the pins together
            pen = stroke - smax
            tension += max(0.0, stop_k * pen + stop_d * min(1.0, pen / STOP_ONSET) * rate)
        elif stroke < smin:      # piston on the cylinder bottom: pushes the pins apart
            pen = smin - stroke
            tension -= max(0.0, stop_k * pen - stop_d * min(1.0, pen / STOP_ONSET) * rate)
        return tension

    return law


# -- the model -----------------------------------------------------------------------------------

@dataclass
class ReferenceRun:
    """A reference simulation: the trajectory and diagnostics."""

    trajectory: Trajectory
    wall: float                   #: wall time of build + solve, s
    residual_max: float           #: largest joint-constraint violation over the run, m
    held_length_error: float      #: largest drift of a held cylinder's pin-to-pin length, m
    dt: float


def simulate(crane: Crane, initial: State, inputs: Inputs, horizon: float, *,
             dt: float = DEFAULT_REFERENCE_DT, stop_stiffness: float = STOP_STIFFNESS,
             stop_damping: float = STOP_DAMPING, spectral_radius: float = 0.5) -> ReferenceRun:
    """Runs the Exudyn reference model; see the module text for what it contains."""
    from . import api

    api._check(crane, initial, inputs, horizon, dt, "c")  # the same input checks as predict()
    import exudyn as exu
    from exudyn.itemInterface import (MarkerBodyMass, MarkerBodyPosition, LoadMassProportional,
                                      NodeRigidBody2D, ObjectConnectorDistance,
                                      ObjectConnectorSpringDamper, ObjectGround,
                                      ObjectJointRevolute2D, ObjectRigidBody2D, SensorNode)

    wall0 = time.perf_counter()
    g = crane.geometry
    e = initial.extension
    pose = _pose(crane, initial.lift_stroke, initial.tilt_stroke)
    O1 = np.array(g.lift_pivot)
    m2, c2, i2 = _lumped_outer(crane, e)

    # frames: (origin, angle) of each body, and the body's (mass, com in its frame, izz)
    def frames(p: _Pose) -> Dict[str, Tuple[np.ndarray, float]]:
        R = _rot(p.th_lift)
        return {"lift": (O1, p.th_lift),
                "outer": (O1 + R @ np.array(g.tilt_pivot), p.th_outer),
                "link1": (O1 + R @ np.array(g.link1_pivot), p.ph_link1),
                "link2": (p.o_link2, p.ph_link2)}

    bodies = {"lift": (crane.lift_boom.mass, np.array(crane.lift_boom.com), crane.lift_boom.izz),
              "outer": (m2, c2, i2),
              "link1": (crane.side_link1.mass, np.array(crane.side_link1.com), crane.side_link1.izz),
              "link2": (crane.side_link2.mass, np.array(crane.side_link2.com), crane.side_link2.izz)}
    order = ("lift", "outer", "link1", "link2")

    def node_coords(p: _Pose) -> Dict[str, np.ndarray]:
        out = {}
        for name, (o, a) in frames(p).items():
            out[name] = np.array([*(o + _rot(a) @ bodies[name][1]), a])
        return out

    q0 = node_coords(pose)
    # initial velocities from the stroke rates (difference of assembly poses)
    v0 = {k: np.zeros(3) for k in order}
    if initial.lift_stroke_rate or initial.tilt_stroke_rate:
        hs = 1e-7
        rl, rt = initial.lift_stroke_rate, initial.tilt_stroke_rate
        qp = node_coords(_pose(crane, initial.lift_stroke + hs * rl, initial.tilt_stroke + hs * rt))
        qm = node_coords(_pose(crane, initial.lift_stroke - hs * rl, initial.tilt_stroke - hs * rt))
        v0 = {k: (qp[k] - qm[k]) / (2 * hs) for k in order}

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    nodes, objs = {}, {}
    for name in order:
        m, com, izz = bodies[name]
        nodes[name] = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=list(q0[name]),
                                                  initialVelocities=list(v0[name])))
        objs[name] = mbs.AddObject(ObjectRigidBody2D(physicsMass=m, physicsInertia=izz,
                                                     nodeNumber=nodes[name]))
        mk = mbs.AddMarker(MarkerBodyMass(bodyNumber=objs[name]))
        mbs.AddLoad(LoadMassProportional(markerNumber=mk, loadVector=[0.0, -crane.gravity, 0.0]))

    def marker(name: str, point_in_frame) -> int:
        """Position marker at a point given in the body's frame (origin at its pivot)."""
        if name == "ground":
            return mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground,
                                                    localPosition=[*point_in_frame, 0.0]))
        local = np.array(point_in_frame, dtype=float) - bodies[name][1]
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[name], localPosition=[*local, 0.0]))

    # joints: (body a, point in a's frame, body b, point in b's frame)
    joints = [("ground", g.lift_pivot, "lift", (0.0, 0.0)),
              ("lift", g.tilt_pivot, "outer", (0.0, 0.0)),
              ("lift", g.link1_pivot, "link1", (0.0, 0.0)),
              ("link1", g.link_pin, "link2", (0.0, 0.0)),
              ("link2", g.link2_end, "outer", g.link2_attach)]
    for a, pa, b, pb in joints:
        mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[marker(a, pa), marker(b, pb)]))

    cylinders = [("lift", crane.lift_cylinder, inputs.lift, ("ground", g.lift_cylinder_base),
                  ("lift", g.lift_cylinder_rod), initial.lift_stroke),
                 ("tilt", crane.tilt_cylinder, inputs.tilt, ("lift", g.tilt_cylinder_base),
                  ("link1", g.link_pin), initial.tilt_stroke)]
    for _, cyl, drive, base, rod, s0 in cylinders:
        mks = [marker(*base), marker(*rod)]
        if isinstance(drive, Hold):
            mbs.AddObject(ObjectConnectorDistance(markerNumbers=mks,
                                                  distance=cyl.length_retracted + s0))
        else:
            mbs.AddObject(ObjectConnectorSpringDamper(
                markerNumbers=mks, referenceLength=cyl.length_retracted,
                springForceUserFunction=_cylinder_law(cyl, drive, stop_stiffness, stop_damping)))

    sensors = {name: (mbs.AddSensor(SensorNode(nodeNumber=nodes[name], storeInternal=True,
                                               writeToFile=False,
                                               outputVariableType=exu.OutputVariableType.Coordinates)),
                      mbs.AddSensor(SensorNode(nodeNumber=nodes[name], storeInternal=True,
                                               writeToFile=False,
                                               outputVariableType=exu.OutputVariableType.Coordinates_t)))
               for name in order}
    mbs.Assemble()

    n_steps = int(math.ceil(horizon / dt - 1e-9))
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = n_steps
    ss.timeIntegration.endTime = float(horizon)
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    ss.timeIntegration.newton.useModifiedNewton = False
    ss.timeIntegration.newton.relativeTolerance = 1e-8
    ss.timeIntegration.newton.absoluteTolerance = 1e-10
    ss.timeIntegration.newton.maxIterations = 25
    ss.solutionSettings.writeSolutionToFile = False
    ss.solutionSettings.sensorsWritePeriod = 0.0      # every step
    ss.displayStatistics = False
    ss.displayComputationTime = False
    ok = exu.SolveDynamic(mbs, ss, updateInitialValues=False)
    if not ok:
        raise RuntimeError("Exudyn's solver did not converge on the reference model")
    data = {name: (mbs.GetSensorStoredData(sensors[name][0]), mbs.GetSensorStoredData(sensors[name][1]))
            for name in order}
    wall = time.perf_counter() - wall0

    t = data["lift"][0][:, 0].copy()
    q = {k: data[k][0][:, 1:4] + q0[k] for k in order}   # sensors give displacements
    qd = {k: data[k][1][:, 1:4] for k in order}

    def world_point(name: str, point_in_frame) -> np.ndarray:
        """(N, 2) boom-plane positions of a point fixed in a body's frame."""
        if name == "ground":
            return np.broadcast_to(np.array(point_in_frame, dtype=float), (t.size, 2)).copy()
        local = np.array(point_in_frame, dtype=float) - bodies[name][1]
        ph = q[name][:, 2]
        c, s = np.cos(ph), np.sin(ph)
        return q[name][:, :2] + np.stack([c * local[0] - s * local[1], s * local[0] + c * local[1]], 1)

    # diagnostics: joint residuals and held-cylinder length drift, from the stored coordinates
    res = max(float(np.max(np.hypot(*(world_point(a, pa) - world_point(b, pb)).T)))
              for a, pa, b, pb in joints)
    strokes = np.empty((t.size, 2))
    held_err = 0.0
    for j, (_, cyl, drive, base, rod, s0) in enumerate(cylinders):
        L = np.hypot(*(world_point(*rod) - world_point(*base)).T)
        strokes[:, j] = L - cyl.length_retracted
        if isinstance(drive, Hold):
            held_err = max(held_err, float(np.max(np.abs(strokes[:, j] - s0))))
    th_lift = q["lift"][:, 2]
    th_tilt = q["outer"][:, 2] - th_lift
    th_tilt = np.where(th_tilt > math.pi / 2, th_tilt - 2 * math.pi, th_tilt)
    th_tilt = np.where(th_tilt <= -1.5 * math.pi, th_tilt + 2 * math.pi, th_tilt)
    theta = np.stack([th_lift, th_tilt], 1)
    omega = np.stack([qd["lift"][:, 2], qd["outer"][:, 2] - qd["lift"][:, 2]], 1)
    stop = np.zeros((t.size, 2), dtype=np.int32)
    for j, (_, cyl, drive, *_rest) in enumerate(cylinders):
        if not isinstance(drive, Hold):
            stop[strokes[:, j] >= cyl.stroke_max - STOP_TOLERANCE, j] = 1
            stop[strokes[:, j] <= cyl.stroke_min + STOP_TOLERANCE, j] = -1

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
    arrays = dict(t=t, strokes=strokes, theta=theta, omega=omega, tip=tip, stop=stop)
    for a in list(arrays.values()) + [xyz]:
        a.setflags(write=False)

    def points(th: np.ndarray) -> np.ndarray:
        if th.shape != theta.shape or not np.array_equal(th, theta):
            raise ValueError("the reference trajectory draws only its own poses")
        return xyz

    traj = Trajectory(slew=initial.slew, extension=e, backend="exudyn", _points=points, **arrays)
    return ReferenceRun(trajectory=traj, wall=wall, residual_max=res, held_length_error=held_err, dt=dt)


def predict_reference(crane: Crane, initial: State, inputs: Inputs, horizon: float, *,
                      dt: Optional[float] = None) -> Trajectory:
    """The reference model's :class:`Trajectory` (same arguments as :func:`cranepredict.predict`)."""
    return simulate(crane, initial, inputs, horizon,
                    dt=DEFAULT_REFERENCE_DT if dt is None else dt).trajectory


# -- comparison with the fast model --------------------------------------------------------------

def compare(scenario, *, dt_ref: float = DEFAULT_REFERENCE_DT, dt_fast: Optional[float] = None,
            repeat_fast: int = 21) -> dict:
    """Runs a scenario on the fast model (C) and on the reference; the tip error (m) is measured at
    the fast model's samples (the reference tip linearly interpolated onto them). "Before/after
    the stop" splits at the first sample where either model is at an end stop (None: no stop)."""
    from . import api

    sc = scenario
    fast = api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_fast)
    walls = []
    for _ in range(repeat_fast):
        t0 = time.perf_counter()
        api.predict(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_fast)
        walls.append(time.perf_counter() - t0)
    wall_fast = float(np.median(walls))
    run = simulate(sc.crane, sc.initial, sc.inputs, sc.horizon, dt=dt_ref)
    ref = run.trajectory
    tip_ref = np.stack([np.interp(fast.t, ref.t, ref.tip[:, i]) for i in range(3)], 1)
    err = np.linalg.norm(tip_ref - fast.tip, axis=1)
    stops = [x for x in (fast.t[np.flatnonzero(fast.stop.any(1))[:1]].tolist()
                         + ref.t[np.flatnonzero(ref.stop.any(1))[:1]].tolist())]
    t_stop = min(stops) if stops else None
    before = err if t_stop is None else err[fast.t < t_stop]
    after = None if t_stop is None else err[fast.t >= t_stop]

    def mx(a):
        return None if a is None or a.size == 0 else float(a.max())

    return {"name": sc.name, "tags": list(sc.tags), "horizon": sc.horizon,
            "max_error_mm": float(err.max()) * 1e3, "rms_error_mm": float(np.sqrt(np.mean(err**2))) * 1e3,
            "max_error_before_stop_mm": None if mx(before) is None else mx(before) * 1e3,
            "max_error_after_stop_mm": None if mx(after) is None else mx(after) * 1e3,
            "first_stop_time_s": t_stop,
            "stop_time_fast_s": stops[0] if fast.stop.any() else None,
            "wall_fast_s": wall_fast, "wall_reference_s": run.wall,
            "speed_ratio": run.wall / wall_fast,
            "constraint_residual_m": run.residual_max,
            "_fast": fast, "_ref": ref, "_err": err}
