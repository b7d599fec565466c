"""The twin's error-controlled methods (docs/model.md, "Integration: the default method
(ROS34PW2)" and "the explicit pair (DOPRI5(4))"; the C core's integrator.c): the ROS34PW2
Rosenbrock-W method or the explicit pair DOPRI5(4) with error control, dense output at the sample
times, the end stops, the releases and the relief and anti-cavitation valves' openings located in
the step.

An independent implementation of the specification: the W-method's matrix is assembled here as
the dense matrix of the state (the C core eliminates the chambers and solves the mass matrix
instead), factored once a step by Gaussian elimination in Python's floats: the same bits on every
machine, which numpy's LAPACK does not promise (its last bits follow the BLAS kernels of the CPU,
and the C tests' golden vectors are the twin's numbers)."""

from __future__ import annotations

import math
from bisect import bisect_right
from typing import Callable, List, Optional, Sequence, Tuple

import numpy as np

from ._internal import (EXTENSION, HYD, JOINTS, LIFT, SLEW, SPOOL, TILT, State, _inverse_column,
                        _lu, _lu_solve)
from .cylinder import friction_rate
from .hydraulics import LIMIT_OVERRIDE, _ValveDrive
from .integrator import RELEASE_BISECTIONS, _next_knot, _physical, _Prediction

#: ROS34PW2 (Rang and Angermann 2005) in Hairer and Wanner's transformed form (spec).
GAMMA = 0.43586652150845900
ALPHA = (0.0, 0.87173304301691801, 0.73157995778885238, 1.0)
A = ((), (2.0,), (1.4192173174557647, -0.25923221167296971),
     (4.1847604823191607, -0.28519201735549591, 2.2942803602790417))
C = ((), (-4.5885607205580835,), (-4.1847604823191607, 0.28519201735549591),
     (-6.3681792001283578, -6.7956209444668362, 2.8700986043310561))
M = (4.1847604823191601, -0.28519201735549587, 2.2942803602790414, 1.0)
E = (0.27774994764796811, -1.403239895175999, 1.7726301276675507, 0.5)

#: The step control of the spec: first, largest and smallest step (s), shrink and growth limits,
#: safety factor, the early-event fraction, a spool's tolerance, a chamber event's least fraction.
FIRST_STEP = 1e-3
MAX_STEP = 0.1
MIN_STEP = 1e-7
SHRINK = 0.2
GROW = 5.0
SAFETY = 0.9
EVENT_FRACTION = 0.125
SPOOL_TOLERANCE = 1e-3
#: a chamber whose own slope over a ROS34PW2 step, -h dp'/dp, exceeds this is sampled linearly
STIFF_SAMPLE = 10.0

#: DOPRI5(4) (Dormand and Prince; Hairer, Norsett and Wanner I, II.5): nodes, stage rows (the
#: seventh row is the solution's weights b), the error's weights d = b - b^ (spec).
DP_C = (0.0, 0.2, 0.3, 0.8, 8 / 9, 1.0, 1.0)
DP_A = ((), (0.2,), (3 / 40, 9 / 40), (44 / 45, -56 / 15, 32 / 9),
        (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729),
        (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656),
        (35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84))
DP_D = (35 / 384 - 5179 / 57600, 0.0, 500 / 1113 - 7571 / 16695, 125 / 192 - 393 / 640,
        -2187 / 6784 + 92097 / 339200, 11 / 84 - 187 / 2100, -1 / 40)
#: Its dense output of order 4 (Hairer, Norsett and Wanner I, II.6, CONTD5; spec).
DP_DENSE = (-12715105075 / 11282082432, 0.0, 87487479700 / 32700410799,
            -10690763975 / 1880347072, 701980252875 / 199316789632, -1453857185 / 822651844,
            69997945 / 29380423)


def on_grid(h: float) -> float:
    """A proposed step rounded down onto the grid m 2^e, m in {16, ..., 31} / 32, by exact
    operations (spec): error ratios a few ulps apart propose the same step."""
    m, e = math.frexp(h)
    return math.ldexp(math.floor(m * 32.0) / 32.0, e)


def attempt_cap(horizon: float, drives: Sequence[object] = ()) -> int:
    """The most step attempts over a horizon (spec): 64 + ceil(4096 horizon), plus one for each
    sample time of a sampled drive inside (0, horizon)."""
    knots = sum(1 for d in drives for tk in (getattr(d, "times", None) or ())
                if 0.0 < tk < horizon)
    return 64 + int(math.ceil(horizon * 4096.0)) + knots


class _Rosw:
    """One prediction with ROS34PW2: the prediction's model, drives and joint status (pred), the
    limit valves' modes and the tolerances."""

    def __init__(self, pred: _Prediction, tip: float, pressure: float, dopri: bool = False
                 ) -> None:
        self.pred = pred
        #: DOPRI5(4) instead of ROS34PW2 (a future without valve drives)
        self.dopri = dopri
        #: the explicit pair's stages k1..k6 of the step last taken (its dense output)
        self.stages: List[Sequence[float]] = []
        model = pred.model
        #: open[j][side]: that chamber's limit valve is open over the current step
        self.open = [[False, False] for _ in JOINTS]
        #: floor[j][side]: that chamber's vacuum floor is in the matrix over the current step
        self.floor = [[False, False] for _ in JOINTS]
        reach = math.hypot(*model.tilt_pivot) + math.hypot(
            model.extension_mount[0] + model.extension_limits[1] + model.tip_distance,
            model.extension_mount[1])
        n = len(self._dims())
        self.tol = [0.0] * n
        for j in JOINTS:
            q_tol = tip if j == EXTENSION else tip / reach
            self.tol[j] = self.tol[4 + j] = q_tol
        if pred.hydraulic:
            for j in JOINTS:
                self.tol[HYD + 2 * j] = self.tol[HYD + 2 * j + 1] = pressure
                self.tol[SPOOL + j] = SPOOL_TOLERANCE

    def _dims(self) -> range:
        return range(SPOOL + 4 if self.pred.hydraulic else 8)

    # -- the rates and the matrix ---------------------------------------------------------------

    def rates(self, t: float, x: State) -> List[float]:
        """f(t, x) under the joint status and the limit valves' modes of the step."""
        pred = self.pred
        locked = pred.locked()
        f = list(pred.derivative(t, x, locked))
        if pred.hydraulic:
            for j in JOINTS:
                if pred.valve[j] and any(self.open[j]):
                    stroke = pred.stroke(j, x[j])
                    drive = pred.drives[j]
                    for side in (0, 1):
                        if self.open[j][side]:
                            i = HYD + 2 * j + side
                            f[i] += drive.limit_rate(stroke, side, x[i], self.floor[j][side])  # type: ignore[union-attr]
        return f

    def modes(self, x: State, f: Sequence[float]) -> bool:
        """The limit valves' modes at a step's start (spec: beyond the nearer setting, or at it,
        with the free rate, f without the valve's own flow, pointing beyond; or beyond it by
        more than the valve's override); True if any changed."""
        pred = self.pred
        changed = False
        for j in JOINTS:
            if not pred.valve[j]:
                continue
            drive = pred.drives[j]
            for side in (0, 1):
                i = HYD + 2 * j + side
                beyond, setting = drive.limit_side(x[i])  # type: ignore[union-attr]
                near = abs(x[i] - setting) <= LIMIT_OVERRIDE
                rate = f[i]
                if self.open[j][side] and beyond != 0 and near:   # the open valve's flow out
                    rate -= drive.limit_rate(pred.stroke(j, x[j]), side, x[i])  # type: ignore[union-attr]
                pointing = rate < 0.0 if setting == drive.p_c else rate > 0.0  # type: ignore[union-attr]
                is_open = (beyond != 0 or x[i] == setting) and (pointing or not near)
                changed = changed or is_open != self.open[j][side]
                self.open[j][side] = is_open
        return changed

    def floors(self, x: State, f: Sequence[float]) -> bool:
        """The vacuum floors held in over a step (spec: an open limit valve's chamber below the
        floor's knee, or at it with its rate f pointing below); True if any changed."""
        pred = self.pred
        changed = False
        for j in JOINTS:
            for side in (0, 1):
                i = HYD + 2 * j + side
                knee = pred.drives[j].floor_knee if pred.valve[j] else 0.0  # type: ignore[union-attr]
                held = bool(pred.valve[j] and self.open[j][side] and
                            (x[i] < knee or (x[i] == knee and f[i] < 0.0)))
                changed = changed or held != self.floor[j][side]
                self.floor[j][side] = held
        return changed

    def matrix(self, t: float, x: State) -> np.ndarray:
        """The W-method's matrix J at (t, x) (spec): the stiff couplings only."""
        pred, model = self.pred, self.pred.model
        n = len(self._dims())
        J = np.zeros((n, n))
        locked = pred.locked()
        free = [j for j in JOINTS if not locked[j]]
        minv: List[List[float]] = []
        if free:
            conf = pred._conf(x)
            if pred.held[SLEW] and pred.held[EXTENSION]:
                full = model._mass_matrix(conf)
                mass = [[full[r][k] for k in free] for r in free]
            else:
                mass = model._mass_matrix4(conf, free)
            columns = [_inverse_column(mass, k) for k in range(len(free))]
            minv = [[column[r] for column in columns] for r in range(len(free))]
        conf = pred._conf(x)
        for k, j in enumerate(free):
            ds = pred.ratio(conf, j)
            J[j, 4 + j] = 1.0
            slope = friction_rate(model.friction[j], ds * x[4 + j])
            damping = ds * ds * slope if slope > 0.0 else 0.0
            for r, i in enumerate(free):
                J[4 + i, 4 + j] = -minv[r][k] * damping
            if pred.valve[j]:
                drive = pred.drives[j]
                for r, i in enumerate(free):
                    J[4 + i, HYD + 2 * j] = minv[r][k] * drive.area_a * ds  # type: ignore[union-attr]
                    J[4 + i, HYD + 2 * j + 1] = -minv[r][k] * drive.area_b * ds  # type: ignore[union-attr]
                c_a, c_b = drive.compliances(pred.stroke(j, x[j], conf))  # type: ignore[union-attr]
                J[HYD + 2 * j, 4 + j] = -drive.area_a * ds / c_a  # type: ignore[union-attr]
                J[HYD + 2 * j + 1, 4 + j] = drive.area_b * ds / c_b  # type: ignore[union-attr]
        for j in JOINTS:
            if not pred.valve[j]:
                continue
            drive = pred.drives[j]
            stroke = pred.stroke(j, x[j], conf if free else None)
            c_a, c_b = drive.compliances(stroke)  # type: ignore[union-attr]
            y = x[SPOOL + j] if drive.tau > 0.0 else drive.lever(t)  # type: ignore[union-attr]
            a, b = HYD + 2 * j, HYD + 2 * j + 1
            # the valve's branch once: its slopes in the pressures and its gain in the spool
            o, w_a, w_b, gain, s_a, s_b = drive.branch(y, x[a], x[b], slopes=True)  # type: ignore[union-attr]
            d_a, d_b = o * s_a, o * s_b
            leak = drive.leakage  # type: ignore[union-attr]
            g_a = drive.limit_slope(self.floor[j][0]) if self.open[j][0] else 0.0  # type: ignore[union-attr]
            g_b = drive.limit_slope(self.floor[j][1]) if self.open[j][1] else 0.0  # type: ignore[union-attr]
            J[a, a] = (d_a - leak - g_a) / c_a
            J[a, b] = leak / c_a
            J[b, a] = leak / c_b
            J[b, b] = (-d_b - leak - g_b) / c_b
            if drive.tau > 0.0:  # type: ignore[union-attr]
                J[SPOOL + j, SPOOL + j] = -1.0 / drive.tau  # type: ignore[union-attr]
                # the valve's gain (spec)
                J[a, SPOOL + j] = gain * w_a / c_a
                J[b, SPOOL + j] = -(gain * w_b) / c_b
        return J

    # -- a step -------------------------------------------------------------------------------

    def dp_step(self, t: float, x: State, f0: Sequence[float], h: float
                ) -> Tuple[State, float, List[float]]:
        """One DOPRI5(4) step of size h from (t, x), f0 = f(t, x); returns (x1, the error's
        largest ratio to its tolerance, f(t + h, x1))."""
        n = len(x)
        ks: List[Sequence[float]] = [f0]
        fy: List[float] = []
        for s in range(1, 7):
            row = DP_A[s]
            xs = []
            for i in range(n):
                v = 0.0
                for m in range(s):
                    v += row[m] * ks[m][i]
                xs.append(x[i] + h * v)
            fy = self.rates(t + DP_C[s] * h, tuple(xs))
            ks.append(fy)
        b = DP_A[6]
        x1 = []
        err = 0.0
        for i in range(n):
            v = 0.0
            e = 0.0
            for m in range(6):
                v += b[m] * ks[m][i]
                e += DP_D[m] * ks[m][i]
            e += DP_D[6] * fy[i]
            x1.append(x[i] + h * v)
            r = abs(h * e) / self.tol[i]
            if not r <= err and err == err:   # a NaN, once met, stays
                err = r
        self.stages = ks[:6]   # the step last taken's k1..k6, for the dense output
        return tuple(x1), err, fy

    def adaptive_step(self, t: float, x: State, f0: Sequence[float], W: np.ndarray, h: float
                      ) -> Tuple[State, float]:
        """The step of the method in use (DOPRI5(4) or ROS34PW2): (x1, its error ratio). A stage
        whose arithmetic fails (a stage far beyond an end stop, where the four-bar degenerates:
        a division by zero here, an inf or a NaN in the C core) fails the step: a NaN ratio,
        rejected as the core rejects it."""
        try:
            if self.dopri:
                x1, err, _ = self.dp_step(t, x, f0, h)
                return x1, err
            return self.step(t, x, f0, W, h)
        except (ArithmeticError, ValueError):
            return tuple(x), math.nan

    def root(self, err: float) -> float:
        """err^(1/(p + 1)) with the estimate's order p: the step factor's divisor."""
        return err ** 0.2 if self.dopri else err ** (1.0 / 3.0)

    def step(self, t: float, x: State, f0: Sequence[float], W: np.ndarray, h: float
             ) -> Tuple[State, float]:
        """One ROS34PW2 step of size h from (t, x), f0 = f(t, x), W = I - gamma h J factor
        (solved afresh); returns (x1, the error's largest ratio to its tolerance)."""
        gh = GAMMA * h
        xa = np.asarray(x, dtype=float)
        factors = _lu((np.eye(len(xa)) - gh * W).tolist())
        us: List[np.ndarray] = []
        for s in range(4):
            if s == 0:
                f = np.asarray(f0, dtype=float)
            else:
                xs = xa + sum(A[s][k] * us[k] for k in range(s))
                f = np.asarray(self.rates(t + ALPHA[s] * h, tuple(xs.tolist())))
            rhs = gh * f
            if s:
                rhs = rhs + GAMMA * sum(C[s][k] * us[k] for k in range(s))
            us.append(np.array(_lu_solve(factors, rhs.tolist())))
        x1 = xa + sum(M[s] * us[s] for s in range(4))
        e = sum(E[s] * us[s] for s in range(4))
        with np.errstate(invalid="ignore", divide="ignore"):
            ratios = np.abs(e) / np.asarray(self.tol)
        err = float(np.max(ratios)) if not np.isnan(ratios).any() else math.nan
        return tuple(x1.tolist()), err


def _reversal_fraction(pred: _Prediction, x: State, x1: State) -> float:
    """The largest fraction (<= 1) of the step from x to x1 that keeps every free joint whose
    rate changes sign within its actuator's Stribeck velocity of speed change (ds/dq at x; spec,
    "the explicit pair")."""
    frac = 1.0
    conf = None
    locked = pred.locked()
    for j in JOINTS:
        w0, w1 = x[4 + j], x1[4 + j]
        if locked[j] or not ((w0 < 0.0 < w1) or (w1 < 0.0 < w0)):
            continue
        if conf is None:
            conf = pred._conf(x)
        dv = abs(pred.ratio(conf, j) * (w1 - w0))
        vs = pred.model.friction[j][3]
        if dv > vs and vs / dv < frac:
            frac = vs / dv
    return frac


def _chord_error(drive: _ValveDrive, a: float, b: float) -> float:
    """The spool error a step over [a, b] can leave by seeing the lever at its stages only (spec,
    the drives' rule): the lever's samples inside depart by delta from its chord over the step
    (delta linear between them, 0 at a and b), which a spool of lag tau follows by at most
    min(max |delta|, integral |delta| dt / tau) (tau = 0: the spool is the lever)."""
    times, u = drive.times, drive.u
    assert times is not None
    k = bisect_right(times, a)
    u_a = drive.lever(a)
    slope = (drive.lever(b) - u_a) / (b - a)
    t0, d0, peak, area = a, 0.0, 0.0, 0.0
    while True:
        t1 = times[k] if k < len(times) and times[k] < b else b
        d1 = u[k] - (u_a + slope * (t1 - a)) if t1 < b else 0.0
        m0, m1 = abs(d0), abs(d1)
        if m0 + m1 > 0:   # a trapezoid, or two triangles where delta changes sign
            area += (t1 - t0) * ((m0 + m1) / 2 if d0 * d1 >= 0
                                 else (d0 * d0 + d1 * d1) / (2 * (m0 + m1)))
        if m1 > peak:
            peak = m1
        if not t1 < b:
            break
        t0, d0 = t1, d1
        k += 1
    tau = drive.tau
    return area / tau if tau > 0 and area < tau * peak else peak


def _step_end(drives: Sequence[object], t: float, t_end: float, dt: float) -> float:
    """Where a ROS34PW2 step from t to t_end ends (spec, the drives' rule): at a sampled pressure
    drive's first sample inside (more than dt/1000 from both ends); for a sampled lever, at t_end
    if _chord_error keeps the spool's tolerance, else at the farthest sample inside where it does
    (found by bisection over the samples; the lever is linear up to the first)."""
    lo_t = t + 1e-3 * dt
    end = t_end
    for drive in drives:
        times = getattr(drive, "times", None)
        if not times:
            continue
        if isinstance(drive, _ValveDrive):
            if _chord_error(drive, t, end) <= SPOOL_TOLERANCE:
                continue
            lo = bisect_right(times, lo_t)
            hi = bisect_right(times, end - 1e-3 * dt)
            if lo >= hi or times[lo] >= end - 1e-3 * dt:
                continue
            hi -= 1
            while lo < hi:
                mid = lo + (hi - lo + 1) // 2
                if _chord_error(drive, t, times[mid]) <= SPOOL_TOLERANCE:
                    lo = mid
                else:
                    hi = mid - 1
            end = times[lo]
            continue
        k = bisect_right(times, lo_t)
        if k < len(times) and times[k] < end - 1e-3 * dt:
            end = times[k]
    return end


def integrate(pred: _Prediction, x: State, horizon: float, dt: float, n: int, tip: float,
              pressure: float, record: Callable[[int, float, State], None],
              dopri: bool = False) -> State:
    """x over [0, horizon] with ROS34PW2, or with dopri DOPRI5(4) (spec), recording the sample at
    k dt for k = 1..n - 1 by dense output and the final state at the horizon as sample n."""
    ros = _Rosw(pred, tip, pressure, dopri)
    model = pred.model
    cap = attempt_cap(horizon, pred.drives)
    pred.release(0.0, x)

    def start(t: float, x: State, f: Optional[List[float]]) -> Tuple[List[float], np.ndarray]:
        if f is None:
            f = ros.rates(t, x)
        if ros.modes(x, f):
            f = ros.rates(t, x)
        if ros.floors(x, f):
            f = ros.rates(t, x)
        return f, (np.zeros((0, 0)) if dopri else ros.matrix(t, x))

    f0, J = start(0.0, x, None)
    t = 0.0
    h = min(dt, FIRST_STEP)
    grow = GROW
    attempts = 0
    k = 1
    while t < horizon:
        hs = min(h, MAX_STEP)
        last = False
        if hs >= horizon - t:
            hs = horizon - t
            last = True
        # the pair's steps end at a sampled drive's knot, ROS34PW2's by the drives' rule (spec)
        t_end = horizon if last else t + hs
        knot = (_next_knot(pred.drives, t, t_end, hs) if dopri
                else _step_end(pred.drives, t, t_end, hs))
        if knot < t_end:
            hs = knot - t
            last = False
        attempts += 1
        if attempts > cap:
            raise ArithmeticError("the error control could not meet the tolerance within the "
                                  "attempt cap")
        x1, err = ros.adaptive_step(t, x, f0, J, hs)
        if not err <= 1.0:
            if hs <= MIN_STEP:
                if err != err:
                    raise ValueError(f"the prediction diverged at t = {t:g} s (a stage is not "
                                     "finite even at the smallest step): check the crane's "
                                     "parameters for absurd values")
                raise ArithmeticError("the error control could not meet the tolerance at the "
                                      "smallest step")
            grow = 1.0
            fac = SAFETY / ros.root(err) if err == err else SHRINK
            h = max(on_grid(hs * max(fac, SHRINK)), MIN_STEP)
            continue
        if dopri and hs > MIN_STEP:
            frac = _reversal_fraction(pred, x, x1)
            if frac < 1.0:   # a friction reversal jumped across: again, shorter (spec)
                grow = 1.0
                h = max(on_grid(hs * max(frac, SHRINK)), MIN_STEP)
                continue
        fac = SAFETY / ros.root(err) if err > 0.0 else GROW
        h = on_grid(hs * min(fac, grow))
        grow = GROW
        # events: the first end stop, then an earlier chamber crossing
        tau = hs
        joint, upper = -1, False
        for j in JOINTS:
            if pred.locked()[j]:
                continue
            lo_q, hi_q = model.angle_limits[j]
            if x1[j] > hi_q:
                up = True
            elif x1[j] < lo_q:
                up = False
            else:
                continue
            tj = pred.crossing_time(x[j], x[4 + j], x1[j], x1[4 + j], hs, hi_q if up else lo_q,
                                    not up)
            if joint < 0 or tj < tau:
                joint, tau, upper = j, tj, up
        chamber, at = -1, 0.0
        if pred.hydraulic:
            for j in JOINTS:
                if not pred.valve[j]:
                    continue
                for side in (0, 1):
                    i = HYD + 2 * j + side
                    beyond, setting = pred.drives[j].limit_side(x1[i])  # type: ignore[union-attr]
                    if x1[i] == x[i]:
                        continue
                    if ros.open[j][side] != (beyond != 0):
                        tk = hs * ((x[i] - setting) / (x[i] - x1[i]))
                        if tk > 0.0 and tk < tau:
                            tau, chamber, at = tk, i, setting
                    knee = pred.drives[j].floor_knee  # type: ignore[union-attr]
                    if ros.open[j][side] and ros.floor[j][side] != (x1[i] < knee):
                        tk = hs * ((x[i] - knee) / (x[i] - x1[i]))
                        if tk > 0.0 and tk < tau:
                            tau, chamber, at = tk, i, knee
        if chamber >= 0:
            joint = -1
        changed = False
        if (joint >= 0 or chamber >= 0) and tau < hs * EVENT_FRACTION and \
                hs > FIRST_STEP * EVENT_FRACTION:
            h = hs * EVENT_FRACTION
            grow = 1.0
            continue
        if joint >= 0 or chamber >= 0:
            hs = tau
            last = False
            x1, _ = ros.adaptive_step(t, x, f0, J, hs)
            if any(pred.stop) and pred.released(t + hs, x1):
                joint = chamber = -1   # a release before the event comes first (spec)
            if chamber >= 0:     # onto the setting or the knee crossed
                x1 = x1[:chamber] + (at,) + x1[chamber + 1:]
                changed = True
        if joint < 0 and chamber < 0 and any(pred.stop) and pred.released(t + hs, x1):
            lo, hi = 0.0, hs
            for _ in range(RELEASE_BISECTIONS):
                mid = 0.5 * (lo + hi)
                x_mid, _ = ros.adaptive_step(t, x, f0, J, mid)
                if pred.released(t + mid, x_mid):
                    hi = mid
                else:
                    lo = mid
            if hi < hs:
                last = False
            hs = hi
            x1, _ = ros.adaptive_step(t, x, f0, J, hs)
            changed = True
        if pred.hydraulic:
            x1 = x1[:SPOOL] + tuple(min(max(y, -1.0), 1.0) if pred.valve[j] else y
                                    for j, y in zip(JOINTS, x1[SPOOL:]))
        f1 = ros.rates(t + hs, x1)
        if not _physical(x1) or not all(math.isfinite(v) for v in f1):
            raise ValueError(f"the prediction diverged at t = {t:g} s (the state is no longer "
                             "finite, or a spool or chamber pressure left its range): check the "
                             "crane's parameters for absurd values")
        if dopri and k < n and k * dt < t + hs:   # the pair's dense output's coefficients
            dense = []
            for i, (a, b, fb) in enumerate(zip(x, x1, f1)):
                dx = b - a
                bb = hs * ros.stages[0][i] - dx
                d = 0.0
                for m in range(6):
                    d += DP_DENSE[m] * ros.stages[m][i]
                d += DP_DENSE[6] * fb
                dense.append((bb, dx - hs * fb - bb, hs * d))
        while k < n and k * dt < t + hs:
            s = (k * dt - t) / hs
            if dopri:   # the pair's own dense output, order 4 (spec)
                xs = [a + s * ((b - a) + (1.0 - s) * (c0 + s * (c1 + (1.0 - s) * c2)))
                      for a, b, (c0, c1, c2) in zip(x, x1, dense)]
            else:
                xs = [(1.0 - s) * a + s * b + s * (s - 1.0) * ((1.0 - 2.0 * s) * (b - a)
                                                                + (s - 1.0) * hs * fa + s * hs * fb)
                      for a, b, fa, fb in zip(x, x1, f0, f1)]
            # a held or stopped joint stays exactly where it is, a free one between its stops
            # (spec)
            for j, lk in enumerate(pred.locked()):
                if lk:
                    xs[j], xs[4 + j] = x[j], x[4 + j]
                else:
                    lo_q, hi_q = model.angle_limits[j]
                    xs[j] = min(max(xs[j], lo_q), hi_q)
                if pred.hydraulic and pred.valve[j]:   # the cubic can pass a clamped end
                    xs[SPOOL + j] = min(max(xs[SPOOL + j], -1.0), 1.0)
                    for side in (0, 1):   # a chamber relaxing within the step: linear (spec)
                        i = HYD + 2 * j + side
                        if ros.open[j][side] or J[i, i] < -STIFF_SAMPLE / hs:
                            xs[i] = (1.0 - s) * x[i] + s * x1[i]
            record(k, k * dt, tuple(xs))
            k += 1
        t = horizon if last else t + hs
        if joint >= 0:
            x1 = pred.plastic_impact(x1, joint, +1 if upper else -1)
            pred.events.append((t, joint, +1 if upper else -1))
            changed = True
        for j in JOINTS:
            if pred.locked()[j]:
                continue
            lo_q, hi_q = model.angle_limits[j]
            if x1[j] < lo_q or (x1[j] == lo_q and x1[4 + j] <= 0.0):
                x1 = pred.plastic_impact(x1, j, -1)
                pred.events.append((t, j, -1))
                changed = True
            elif x1[j] > hi_q or (x1[j] == hi_q and x1[4 + j] >= 0.0):
                x1 = pred.plastic_impact(x1, j, +1)
                pred.events.append((t, j, +1))
                changed = True
        if changed:
            pred.release(t, x1)
            h = min(h, FIRST_STEP)
        x = x1
        if not last:
            f0, J = start(t, x, None if changed else f1)
    record(n, horizon, x)
    return x
