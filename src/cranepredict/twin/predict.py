"""The twin's entry points (the C core's predict.c): the drives of a prediction, the bound on its
work, the samples it returns, and the crane's points and transmissions for the API."""

from __future__ import annotations

import math
from typing import Any, List, Tuple

import numpy as np

from ..types import POINT_NAMES
from ._internal import (EXTENSION, HYD, JOINT_NAMES, JOINTS, LIFT, SLEW, SPOOL, TILT, Quad,
                        State, _PressureDrive)
from .cylinder import equivalent_cylinder
from .hydraulics import _ValveDrive, substep_count
from . import rosw
from .integrator import _Prediction, integrate
from .model import TwinModel

def _drive(drive: Any, cylinder: Any = None) -> Any:
    """None for a held cylinder, else its pressure or valve drive."""
    if getattr(drive, "held", False):
        return None
    if hasattr(drive, "u"):
        return _ValveDrive(drive, cylinder)
    return _PressureDrive(drive)


def _optional_drive(crane: Any, inputs: Any, joint: int) -> Any:
    """The slew or extension drive: left out (older Inputs) or Hold means held."""
    name = "slew" if joint == SLEW else "extension"
    drive = getattr(inputs, name, None)
    if drive is None or getattr(drive, "held", False):
        return None
    actuator = "slew_drive" if joint == SLEW else "extension_cylinder"
    if getattr(crane, actuator, None) is None:
        raise ValueError(f"Inputs.{name}: the crane has no {actuator} to drive")
    cyl = equivalent_cylinder(crane, joint)
    if hasattr(drive, "u") and cyl.hydraulics is None:
        raise ValueError(f"Inputs.{name}: a valve drive needs {actuator}.hydraulics in the crane file")
    return _drive(drive, cyl)


def _initial_state(pred: _Prediction, state: Any) -> Tuple[State, Quad, Quad]:
    """(x, strokes, stroke rates) at t = 0 from a State, before the t = 0 stop rule; the slew and
    the extension in their own terms (the coordinate is the "stroke")."""
    model = pred.model
    slew0 = float(state.slew)
    ext0 = float(state.extension)
    strokes0 = (float(state.lift_stroke), float(state.tilt_stroke), slew0, ext0)
    rates0 = (float(state.lift_stroke_rate), float(state.tilt_stroke_rate),
              float(getattr(state, "slew_rate", 0.0)), float(getattr(state, "extension_rate", 0.0)))
    q0 = [0.0, 0.0, slew0, ext0]
    qd0 = [0.0, 0.0, 0.0, 0.0]
    for j in (LIFT, TILT):
        q0[j], ratio = model.joint_angle(j, strokes0[j])
        qd0[j] = 0.0 if pred.held[j] else rates0[j] / ratio
    for j in (SLEW, EXTENSION):
        qd0[j] = 0.0 if pred.held[j] else rates0[j]
    x: State = tuple(q0) + tuple(qd0)
    if pred.hydraulic:
        hyd = [0.0] * 12
        for j, name in enumerate(JOINT_NAMES):
            if pred.valve[j]:
                hyd[2 * j] = float(getattr(state, f"{name}_p_a"))
                hyd[2 * j + 1] = float(getattr(state, f"{name}_p_b"))
                hyd[SPOOL - HYD + j] = float(getattr(state, f"{name}_spool", 0.0))
        x = x + tuple(hyd)
    return x, strokes0, rates0


def _check_work(pred: _Prediction, horizon: float, dt: float, n: int) -> None:
    """Bad input: the work counts against MAX_STEPS as in the C core: with valves every step takes
    up to the worst-case substeps (docs/model.md "Hydraulics": at the stroke ends, where the
    chambers are smallest; the last step up to 1.25 dt), and every knot of a sampled drive inside
    the horizon cuts a step once more ("Integration and samples"), which costs at most one
    substep more: a step's pieces sum to its length, ceil(a) + ceil(b) <= ceil(a + b) + 1."""
    from .._checks import MAX_STEPS

    knots = sum(1 for drive in pred.drives for tk in (getattr(drive, "times", None) or ())
                if 0.0 < tk < horizon)
    worst = 1
    if pred.hydraulic:
        lam = max(drive.stiffness(s) for drive, valve in zip(pred.drives, pred.valve) if valve
                  for s in (drive.stroke_min, drive.stroke_max))
        worst = substep_count(lam, 1.25 * dt)
    if n * worst + knots > MAX_STEPS:
        raise ValueError(f"horizon / dt asks for more than {MAX_STEPS} steps with the cuts at the "
                         f"drives' samples and the valve-driven cylinders' substeps ({n} steps x "
                         f"up to {worst} substeps + {knots} cuts): raise dt, shorten the "
                         "horizon or send fewer samples")


class _Samples:
    """The n + 1 samples of a prediction (types.ARRAYS), filled in by record()."""

    def __init__(self, pred: _Prediction, n: int, strokes0: Quad) -> None:
        self.pred = pred
        self.strokes0 = strokes0
        self.t = np.empty(n + 1)
        self.strokes = np.empty((n + 1, 2))
        self.theta = np.empty((n + 1, 2))
        self.omega = np.empty((n + 1, 2))
        self.tip = np.empty((n + 1, 3))
        self.stop = np.zeros((n + 1, 4), dtype=np.int64)
        self.coords = np.empty((n + 1, 2))            # (slew, extension)
        self.rates = np.empty((n + 1, 2))             # (slew rate, extension rate)
        self.p_a = np.zeros((n + 1, 4))
        self.p_b = np.zeros((n + 1, 4))
        self.flow_a = np.zeros((n + 1, 4))
        self.flow_b = np.zeros((n + 1, 4))
        self.spool = np.zeros((n + 1, 4))

    def record(self, i: int, t: float, x: State) -> None:
        """Sample i: the state x at time t, with the joint status of the prediction."""
        pred, model = self.pred, self.pred.model
        self.t[i] = t
        for j in (LIFT, TILT):
            if pred.held[j]:
                self.strokes[i, j] = self.strokes0[j]
            elif pred.stop[j] != 0:
                self.strokes[i, j] = model.stroke_at_stop[j][pred.stop[j]]
            else:
                # the stroke -> angle -> stroke round trip can land a few 1e-16 m outside
                self.strokes[i, j] = min(max(model.joint_stroke(j, x[j]), model.stroke_min[j]),
                                         model.stroke_max[j])
            self.stop[i, j] = pred.flag(j)
        for k, j in enumerate((SLEW, EXTENSION)):
            if pred.held[j]:
                self.coords[i, k] = self.strokes0[j]
            elif pred.stop[j] != 0:
                self.coords[i, k] = model.limit(j, pred.stop[j])
            else:
                self.coords[i, k] = x[j]
            self.rates[i, k] = x[4 + j]
            self.stop[i, j] = pred.flag(j)
        self.theta[i] = (x[0], x[1])
        self.omega[i] = (x[4], x[5])
        self.tip[i] = model.tip((x[0], x[1]), self.coords[i, 0], self.coords[i, 1])
        for j in JOINTS:
            drive = pred.drives[j]
            if drive is None:
                continue
            if pred.valve[j]:
                y = x[SPOOL + j] if drive.tau > 0.0 else drive.lever(t)
                self.p_a[i, j], self.p_b[i, j] = x[HYD + 2 * j], x[HYD + 1 + 2 * j]
                self.flow_a[i, j], self.flow_b[i, j] = drive.flows(y, x[HYD + 2 * j],
                                                                   x[HYD + 1 + 2 * j])
                self.spool[i, j] = y
            else:
                self.p_a[i, j], self.p_b[i, j] = drive.pressures(t)

    def arrays(self) -> dict:
        """The samples by the names of types.ARRAYS, in its order."""
        return {"t": self.t, "strokes": self.strokes, "theta": self.theta, "omega": self.omega,
                "slew": self.coords[:, 0].copy(), "extension": self.coords[:, 1].copy(),
                "slew_rate": self.rates[:, 0].copy(), "extension_rate": self.rates[:, 1].copy(),
                "tip": self.tip, "stop": self.stop, "p_a": self.p_a, "p_b": self.p_b,
                "flow_a": self.flow_a, "flow_b": self.flow_b, "spool": self.spool}


def _run(crane: Any, state: Any, inputs: Any, horizon: float, dt: float,
         method: str = "auto", tolerance: Any = None
         ) -> Tuple[dict, List[Tuple[float, int, int]]]:
    """simulate() plus the list of impacts (time, joint, angle side), for diagnostics and tests."""
    horizon = float(horizon)
    dt = float(dt)
    model = TwinModel(crane, state.extension)
    drives = (_drive(inputs.lift, crane.lift_cylinder), _drive(inputs.tilt, crane.tilt_cylinder),
              _optional_drive(crane, inputs, SLEW), _optional_drive(crane, inputs, EXTENSION))
    pred = _Prediction(model, drives)
    x, strokes0, rates0 = _initial_state(pred, state)
    x = pred.stop_at_start(x, strokes0, rates0)
    n = int(math.ceil(horizon / dt - 1e-9))
    if method == "auto":   # the default's pick (spec): ROS34PW2 where the future is stiff (oil,
        # a moving telescope's friction), DOPRI5(4) elsewhere
        method = "rosw" if pred.hydraulic or not pred.held[EXTENSION] else "dopri5"
    if method != "rk4":
        _check_attempts(horizon, drives)
    else:
        _check_work(pred, horizon, dt, n)
    samples = _Samples(pred, n, strokes0)
    samples.record(0, 0.0, x)
    if method != "rk4":
        if tolerance is None or tolerance.tip is None or tolerance.pressure is None:
            from ..solver import check
            tolerance = check(method, tolerance)[1]
        rosw.integrate(pred, x, horizon, dt, n, tolerance.tip, tolerance.pressure, samples.record,
                       dopri=method == "dopri5")
    else:
        integrate(pred, x, horizon, dt, n, samples.record)
    return samples.arrays(), pred.events


def _check_attempts(horizon: float, drives: Any = ()) -> None:
    """Bad input: the error-controlled methods' attempt cap counts against MAX_STEPS (spec)."""
    from .._checks import MAX_STEPS

    if rosw.attempt_cap(horizon, drives) > MAX_STEPS:
        raise ValueError(f"horizon must allow at most {MAX_STEPS} step attempts of the default "
                         "method (64 + 4096 per second + the sampled drives' knots), got "
                         f"{horizon:g} s")


def simulate(crane: Any, state: Any, inputs: Any, horizon: float, dt: float,
             method: str = "auto", tolerance: Any = None) -> dict:
    """Predict the crane's four joints over [0, horizon] with end stops, per docs/model.md
    ("Four joints"; a left-out slew or extension drive is held): with RK4 steps dt, or with
    error control to the tolerance (a cranepredict.Tolerance with its numbers), sampled every dt
    ("Integration: the default method"): method="rosw" ROS34PW2, "dopri5" DOPRI5(4) (futures
    without valve drives), "auto" the first for a stiff future (a valve drive, a moving
    telescope), the second for the others.

    Returns numpy arrays (types.ARRAYS), N = n + 1 samples: ``t`` (N,), ``strokes``, ``theta``,
    ``omega`` (N, 2) [lift, tilt]; ``slew``, ``extension``, ``slew_rate``, ``extension_rate``
    (N,); ``tip`` (N, 3, world); ``stop`` (N, 4) [lift, tilt, slew, extension] in actuator terms
    (-1 stopped at stroke_min / the range's start, +1 at stroke_max / its end, 0 otherwise; for
    the tilt, stroke_max is the lower angle limit); ``p_a``, ``p_b``, ``flow_a``, ``flow_b``,
    ``spool`` (N, 4). Inputs are assumed validated by the API layer.
    """
    return _run(crane, state, inputs, horizon, dt, method, tolerance)[0]


def stroke_transmission(crane: Any, joint: int, stroke: float, extension: float) -> float:
    """ds/dtheta of a boom cylinder (0 lift, 1 tilt) at a stroke and extension: the factor that
    turns a sample's joint rate back into the stroke rate a State holds."""
    return TwinModel(crane, extension).joint_angle(joint, stroke)[1]


def points(crane: Any, extension: Any, slew: Any, theta_array: Any) -> np.ndarray:
    """World coordinates (N, 11, 3) of the POINT_NAMES points for each row (theta0, theta1), at
    the extension (m) and slew (rad) of that row (each a scalar or one value per row)."""
    thetas = np.asarray(theta_array, dtype=float).reshape(-1, 2)
    n = thetas.shape[0]
    exts = np.broadcast_to(np.asarray(extension, dtype=float), (n,)).tolist()
    slews = np.broadcast_to(np.asarray(slew, dtype=float), (n,)).tolist()
    model = TwinModel(crane, exts[0] if n else 0.0)
    out = np.empty((n, len(POINT_NAMES), 3))
    for i, (th0, th1) in enumerate(thetas.tolist()):
        out[i] = model.points((th0, th1), slews[i], exts[i])
    return out
