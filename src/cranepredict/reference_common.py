"""What the two Exudyn reference models share (install extra ``[reference]``): the planar one
(:mod:`cranepredict.reference`, 2D bodies, lift and tilt) and the spatial one
(:mod:`cranepredict.reference_spatial`, 3D bodies, four joints).

Each law is written here once, from docs/model.md, and both references use it:

* the boom-plane kinematics of an assembly pose (the triangle and the four-bar closed in closed
  form: :func:`pose`), the initial condition from which the engine then keeps the loops closed;
* the drives: a pressure drive's pressures (:func:`pressure_fn`), a valve drive's lever
  (:func:`lever_fn`);
* the actuator's force ``p_a A_a - p_b A_b - F_friction(v)`` with [S1]'s friction law, as an Exudyn
  spring-damper user function (:func:`cylinder_law`);
* the valve-and-oil hydraulics of docs/model.md "Hydraulics": a circuit's parameters
  (:func:`circuit`), the valve's flows with its orifice root, the relief and anti-cavitation
  valves, the chambers' compliance and their continuity equations (:func:`oil_rates`), and the
  Exudyn element that integrates them with the mechanics (:func:`add_oil`);
* the end stops, event-driven: the perfectly plastic impact (:func:`plastic_impact`), the contact
  changes at an event (:func:`start_on_stops`, :func:`apply_events`), the event locator
  (:func:`watch`), the solver's settings (:func:`solve`), the loop over the smooth pieces
  (:func:`run_pieces`) and their joining into one series (:func:`join_pieces`).

An actuator here is "cylinder-like": its stroke and stroke rate, its ``area_a``, ``area_b``,
``stroke_min``, ``stroke_max``, ``friction`` and ``hydraulics`` (the spatial reference gives the
slew drive and the telescope such an equivalent cylinder).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, List, Sequence, Tuple

import numpy as np

from .crane import Crane
from .types import Pressure, PressureSeries, Valve, ValveSeries

#: An impact is located when the step ends no more than this past the stroke limit, m (the stroke
#: is then put on the limit).
STOP_TOLERANCE = 1e-8
#: A release is located when the step ends with the stop pulling no more than this, N.
RELEASE_TOLERANCE = 1.0
#: Smallest step Exudyn is asked for while it locates an event, s.
EVENT_MIN_STEP = 1e-7
#: More end-stop events than this in one run means the stops chatter (an error).
MAX_PIECES = 64
#: Pressures enter Exudyn in MPa, so that Newton's residual mixes quantities of similar size
#: (positions in m, angles in rad).
P_UNIT = 1e6
#: Pa beyond its setting at which a relief or anti-cavitation valve passes the nominal flow
#: (docs/model.md, "Relief, cavitation floor, leakage").
LIMIT_OVERRIDE = 5e3
#: The vacuum floor: below the cavitation pressure by more than FLOOR_MARGIN (Pa), a make-up flow
#: FLOOR_GAIN times the anti-cavitation valve's gradient more (docs/model.md, "Relief, cavitation
#: floor, leakage").
FLOOR_MARGIN = 8e3
FLOOR_GAIN = 100.0


def available() -> bool:
    """True if the Exudyn engine can be imported."""
    try:
        import exudyn  # noqa: F401
    except ImportError:
        return False
    return True


# -- boom-plane kinematics of an assembly pose ---------------------------------------------------

def rot(a: float) -> np.ndarray:
    """The 2x2 rotation by a (rad)."""
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
class Pose:
    """Absolute frame origins and angles of the four moving bodies, in the boom plane."""

    th_lift: float        # lift boom frame angle
    th_outer: float       # outer boom frame angle (absolute)
    ph_link1: float       # side link 1 frame angle (absolute)
    ph_link2: float       # side link 2 frame angle (absolute)
    o_link2: np.ndarray   # side link 2 frame origin = Q


def pose(crane: Crane, lift_stroke: float, tilt_stroke: float) -> Pose:
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
    R = rot(th_lift)
    return Pose(th_lift=th_lift, th_outer=th_lift + th_rel, ph_link1=th_lift + ph1_rel,
                ph_link2=th_lift + ph2_rel, o_link2=O1 + R @ Q)


# -- drives and the cylinder force law -----------------------------------------------------------

def is_valve(drive) -> bool:
    """True for a valve drive (the actuator carries its oil)."""
    return isinstance(drive, (Valve, ValveSeries))


def pressure_fn(drive):
    """(mbs, t) -> (p_a, p_b) of a pressure drive (absolute time t)."""
    if isinstance(drive, Pressure):
        pa, pb = drive.p_a, drive.p_b
        return lambda mbs, t: (pa, pb)
    if isinstance(drive, PressureSeries):
        ts, pas, pbs = (np.asarray(a, dtype=float) for a in (drive.t, drive.p_a, drive.p_b))
        return lambda mbs, t: (float(np.interp(t, ts, pas)), float(np.interp(t, ts, pbs)))
    raise TypeError(f"not a pressure drive: {drive!r}")


def drive_pressures(drive, t: np.ndarray) -> np.ndarray:
    """(N, 2) pressures of a pressure drive at times t, zeros for any other drive."""
    if not isinstance(drive, (Pressure, PressureSeries)):
        return np.zeros((t.size, 2))
    fn = pressure_fn(drive)
    return np.array([fn(None, x) for x in t]).reshape(-1, 2)


def lever_fn(drive):
    """t -> lever command in [-1, 1] of a valve drive (absolute time)."""
    if isinstance(drive, Valve):
        u = drive.u
        return lambda t: u
    ts, us = np.asarray(drive.t, dtype=float), np.asarray(drive.u, dtype=float)
    return lambda t: float(np.interp(t, ts, us))


def cylinder_law(cyl, pressures, t_offset: float):
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

@dataclass(frozen=True)
class Circuit:
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


def circuit(cyl) -> Circuit:
    """The circuit of a cylinder (or an actuator's equivalent cylinder) with a hydraulics table."""
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
    return Circuit(area_a=cyl.area_a, area_b=cyl.area_b, stroke_min=cyl.stroke_min,
                   stroke_max=cyl.stroke_max, compensated=compensated, p_supply=h.supply_pressure,
                   p_tank=h.tank_pressure, p_relief=h.relief_pressure,
                   p_cavitation=h.cavitation_pressure, k_in=k_in, k_out=k_out,
                   dead_band=h.dead_band, tau=h.spool_time_constant, d_laminar=dl,
                   g_limit=g_limit, leakage=h.leakage, v_hose_a=h.hose_volume_a,
                   v_hose_b=h.hose_volume_b, b_oil=h.oil_bulk_modulus, b_hose=h.hose_bulk_modulus,
                   b_cyl=h.cylinder_bulk_modulus)


def compliance(c: Circuit, volume: float, v_hose: float) -> float:
    """V / Be of a chamber, m^3/Pa: the oil, the cylinder wall and the hose in series."""
    return volume / c.b_oil + (volume - v_hose) / c.b_cyl + v_hose / c.b_hose


def root(c: Circuit, dp: float) -> float:
    """sign(dp) sqrt(|dp|), replaced inside the laminar region by the odd cubic with the same
    value and slope at its edge."""
    if abs(dp) >= c.d_laminar:
        return math.copysign(math.sqrt(abs(dp)), dp)
    x = dp / c.d_laminar
    return math.sqrt(c.d_laminar) * x * (5.0 - x * x) / 4.0


def _smoothstep(x: float) -> float:
    """0 below 0, 1 above 1, x (3 - x^2)/2 between: how much of the compensated flow gets in."""
    return 0.0 if x <= 0.0 else 1.0 if x >= 1.0 else x * (3.0 - x * x) / 2.0


def valve_flows(c: Circuit, y: float, pa: float, pb: float) -> Tuple[float, float]:
    """(flow into chamber a, flow out of chamber b), m^3/s, at spool position y."""
    if not c.compensated:
        if y >= 0.0:
            return y * c.k_in * root(c, c.p_supply - pa), y * c.k_in * root(c, pb - c.p_tank)
        return y * c.k_in * root(c, pa - c.p_tank), y * c.k_in * root(c, c.p_supply - pb)
    if abs(y) <= c.dead_band:
        return 0.0, 0.0
    r = (abs(y) - c.dead_band) / (1.0 - c.dead_band)
    if y > 0.0:
        return (r * c.k_in * _smoothstep((c.p_supply - pa) / c.d_laminar),
                r * c.k_out * root(c, pb - c.p_tank))
    return (-r * c.k_out * root(c, pa - c.p_tank),
            -r * c.k_in * _smoothstep((c.p_supply - pb) / c.d_laminar))


def limit_flow(c: Circuit, p: float) -> float:
    """Flow into a chamber through its anti-cavitation (below p_cavitation, with the vacuum
    floor's below its knee) and relief (above p_relief) valves, m^3/s."""
    if p < c.p_cavitation:
        knee = c.p_cavitation - FLOOR_MARGIN
        return c.g_limit * (c.p_cavitation - p) + (FLOOR_GAIN * c.g_limit * (knee - p)
                                                    if p < knee else 0.0)
    if p > c.p_relief:
        return -c.g_limit * (p - c.p_relief)
    return 0.0


def oil_rates(c: Circuit, y: float, stroke: float, rate: float, pa: float, pb: float):
    """dp_a/dt and dp_b/dt, Pa/s: the continuity equations of the two chambers."""
    qa, qb = valve_flows(c, y, pa, pb)
    q_leak = c.leakage * (pa - pb)
    va = c.v_hose_a + c.area_a * (stroke - c.stroke_min)
    vb = c.v_hose_b + c.area_b * (c.stroke_max - stroke)
    return ((qa - c.area_a * rate - q_leak + limit_flow(c, pa)) / compliance(c, va, c.v_hose_a),
            (c.area_b * rate - qb + q_leak + limit_flow(c, pb)) / compliance(c, vb, c.v_hose_b))


def add_oil(mbs, c: Circuit, lever, oil0, t0: float, measure) -> int:
    """The oil of a valve-driven actuator (chamber pressures p_a, p_b and, with a spool lag, the
    spool position y), integrated by Exudyn together with the mechanics; returns its node.

    The continuity equations dp/dt = f(p, y, stroke, stroke rate) and the spool's lag are first
    order. Exudyn integrates ODE1 coordinates at first order only (measured: a theta-method with
    theta = 2/3, docs/validation.md), so each of these quantities is the *velocity* of an ODE2
    coordinate (its time integral) with unit mass whose force (an ObjectGenericODE2 user function)
    is its rate: generalized-alpha then integrates it at second order. ``measure(mbs)`` gives the
    actuator's (stroke, stroke rate) from its force element; ``lever(t)`` the command at absolute
    time t; ``oil0`` = (p_a, p_b, y) at t0. The node's velocities are p_a, p_b in MPa
    (:data:`P_UNIT`) and y."""
    from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2
    n = 3 if c.tau > 0 else 2
    x0 = [oil0[0] / P_UNIT, oil0[1] / P_UNIT] + ([oil0[2]] if n == 3 else [])
    node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0] * n, initialCoordinates=[0.0] * n,
                                       initialCoordinates_t=x0, numberOfODE2Coordinates=n))

    def rates(mbs_, t, itemNumber, x, x_t):
        stroke, rate = measure(mbs_)
        u = lever(t + t0)
        y = x_t[2] if n == 3 else u
        dpa, dpb = oil_rates(c, y, stroke, rate, x_t[0] * P_UNIT, x_t[1] * P_UNIT)
        out = [dpa / P_UNIT, dpb / P_UNIT]
        if n == 3:
            out.append((u - y) / c.tau)
        return np.array(out)

    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[node], massMatrix=np.eye(n), forceUserFunction=rates))
    return node


def oil_pressures(node: int):
    """(mbs, t) -> (p_a, p_b), Pa, of the oil node of :func:`add_oil`."""
    import exudyn as exu

    def pressures(mbs_, t):
        x = mbs_.GetNodeOutput(node, exu.OutputVariableType.Coordinates_t)
        return x[0] * P_UNIT, x[1] * P_UNIT

    return pressures


def oil_samples(x: np.ndarray, unit: float, lever, t: np.ndarray) -> np.ndarray:
    """(N, 3) p_a, p_b (Pa), y from an oil node's sensor samples ``x`` at times ``t`` (p in
    ``unit`` Pa, then y if the node has one; without, the spool follows the lever)."""
    out = np.zeros((x.shape[0], 3))
    out[:, :2] = x[:, :2] * unit
    out[:, 2] = x[:, 2] if x.shape[1] > 2 else [lever(tt) for tt in t]
    return out


# -- end stops: impacts, events, pieces ----------------------------------------------------------

def plastic_impact(mass_matrix: Callable, q: Sequence[float], qd: Sequence[float], j: int,
                   modes: Sequence) -> List[float]:
    """Rates after a perfectly plastic impact of actuator j on its stop: the stop's impulse acts
    along actuator j only (a generalised force on coordinate j) and ends its rate; the other free
    actuators (mode 0) keep the momentum the impulse does not take (M dv = P e_j over the free
    ones, dv_j = -v_j). ``mass_matrix(q)``: the mass matrix in actuator coordinates."""
    free = [k for k in range(len(qd)) if modes[k] == 0 or k == j]
    out = list(qd)
    if len(free) > 1:
        minv = np.linalg.inv(mass_matrix(q)[np.ix_(free, free)])
        i = free.index(j)
        for a, k in enumerate(free):
            out[k] = qd[k] - qd[j] * minv[a, i] / minv[i, i]
    out[j] = 0.0
    return out


def start_on_stops(limits, mass_matrix: Callable, modes: list, q: list, qd: list, events: list,
                   label=lambda j: j) -> None:
    """At t = 0 a free actuator on a limit whose rate does not point into its range is on its stop
    (a plastic impact at t = 0). ``limits[j]`` = (lower, upper) limit of actuator j. Updates
    modes, q and qd in place; appends the events (0, "impact", label(j), side)."""
    for j in range(len(q)):
        if modes[j] != 0:
            continue
        lo, hi = limits[j]
        for side, lim in ((+1, hi), (-1, lo)):
            if abs(q[j] - lim) <= STOP_TOLERANCE and side * qd[j] >= 0:
                qd[:] = plastic_impact(mass_matrix, q, qd, j, modes)
                q[j], modes[j] = lim, side
                events.append((0.0, "impact", label(j), side))
                break


def apply_events(limits, mass_matrix: Callable, evs, t0: float, modes: list, q: list, qd: list,
                 events: list, label=lambda j: j) -> None:
    """The contact changes at an event: an impact puts the actuator on its limit and takes its rate
    (plastic), a release frees it. Updates modes, q and qd in place; appends the events
    (t0, kind, label(j), side)."""
    for kind, j, side in evs:
        events.append((t0, kind, label(j), side))
        if kind == "impact":
            q[j] = limits[j][1] if side > 0 else limits[j][0]
            qd[:] = plastic_impact(mass_matrix, q, qd, j, modes)
            modes[j] = side
        else:
            modes[j] = 0
    for j in range(len(q)):   # a stopped actuator's rate is zero (within the constraint)
        if modes[j] != 0:
            qd[j] = 0.0


def stop_gap(x: float, lo: float, hi: float) -> Tuple[float, int]:
    """A free actuator at coordinate x: (how far it is past its nearer limit, that side)."""
    up, below = x - hi, lo - x
    return (up, +1) if up >= below else (below, -1)


def stop_pull(tension: float, side: int) -> Tuple[float, int]:
    """An actuator held on its stop by a distance constraint of this tension: (how hard the stop
    pulls, side). An upper stop (piston on the head) holds the pins together (tension >= 0), a lower
    stop pushes them apart (tension <= 0): the stop can only push."""
    return (-tension if side > 0 else tension), side


def watch(mbs, gaps: dict) -> dict:
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


def solve(mbs, span: float, dt: float, spectral_radius: float) -> None:
    """Generalized-alpha with (modified) Newton over ``span`` at step ``dt`` (shortened only to locate
    an event), every step stored by the sensors."""
    import exudyn as exu
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


def run_pieces(integrate: Callable, after_events: Callable, horizon: float) -> list:
    """The motion in smooth pieces between end-stop events: ``integrate(t0)`` integrates one piece
    from the current state at t0 until the horizon or its first event and returns (the piece, its
    events; none: it reached the horizon); ``after_events(piece, events, t0)`` sets the state the
    next piece starts from (the contact changes at the event). Returns the pieces."""
    pieces = []
    t0 = 0.0
    for _ in range(MAX_PIECES):
        piece, evs = integrate(t0)
        pieces.append(piece)
        t0 = float(piece.t[-1])
        if not evs or horizon - t0 <= 1e-12:
            return pieces
        after_events(piece, evs, t0)
    raise RuntimeError(f"more than {MAX_PIECES} end-stop events: the stops chatter")


def join_pieces(pieces: list, get: Callable) -> np.ndarray:
    """One series of ``get(piece)`` over the pieces: each piece's first sample replaces the previous
    piece's last (the same instant, after the event)."""
    last = len(pieces) - 1
    return np.concatenate([get(p) if i == last else get(p)[:-1] for i, p in enumerate(pieces)])


def stop_rows(pieces: list) -> np.ndarray:
    """(N, n) stop flags of the joined series: per sample the pieces' modes, held as 0."""
    return join_pieces(pieces, lambda p: np.tile([[m if m != "held" else 0 for m in p.modes]],
                                                 (p.t.size, 1))).astype(np.int32)


def increasing(t: np.ndarray) -> np.ndarray:
    """The samples to keep of a joined series: a piece of length zero (an event at its start)
    leaves none."""
    return np.concatenate([np.diff(t) > 0, [True]])


__all__ = ["available", "STOP_TOLERANCE", "RELEASE_TOLERANCE", "EVENT_MIN_STEP", "MAX_PIECES",
           "P_UNIT", "LIMIT_OVERRIDE", "rot", "Pose", "pose", "is_valve", "pressure_fn",
           "drive_pressures", "lever_fn", "cylinder_law", "Circuit", "circuit", "compliance", "root",
           "valve_flows", "limit_flow", "oil_rates", "add_oil", "oil_pressures", "oil_samples",
           "plastic_impact", "start_on_stops", "apply_events", "stop_gap", "stop_pull", "watch",
           "solve", "run_pieces", "join_pieces", "stop_rows", "increasing"]
