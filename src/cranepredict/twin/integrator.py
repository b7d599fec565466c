"""The twin's integrator (docs/model.md, "Integration and samples", "End stops", "Release",
"Four joints", "Hydraulics"; the C core's integrator.c): fixed-step RK4 with substeps on the
joints and the valve-driven actuators' chambers and spools, with the end-stop impacts and the
releases located inside a step.

In layers, each knowing only the one below: rk4_step is the scheme, one step of x' = f(t, x);
_Prediction.step cuts a step into pieces at the impacts and releases located inside it;
_Prediction.advance takes a piece in equal substeps (the stiffness bound); integrate runs the
steps, cut at the sampled drives' knots, and hands every sample to a callback (predict.py
records them)."""

from __future__ import annotations

import math
from bisect import bisect_right
from typing import Any, Callable, List, Optional, Sequence, Tuple

from ._internal import (EXTENSION, HYD, JOINTS, LIFT, SLEW, SPOOL, TILT, Quad, State, State8,
                        _inverse2, _inverse_column, _PressureDrive)
from .dynamics import _Configuration
from .hydraulics import _ValveDrive, substep_count
from .model import TwinModel

#: Bisections used to locate an end-stop impact inside a step (spec: 60).
EVENT_BISECTIONS = 60
#: Bisections used to locate a release from a stop inside a step (spec: 40).
RELEASE_BISECTIONS = 40
#: Most pieces (impacts and releases) one step is cut into; the last takes the rest (spec: 8).
MAX_PIECES = 8


def rk4_step(f: Callable[[float, State], State], t: float, x: State, h: float,
             project: Optional[Callable[[State, float], State]] = None) -> State:
    """One classical RK4 step of size h of x' = f(t, x) (docs/model.md, "Integration and samples").

    project(y, dt), if given, maps every stage's state and the result, dt their time from t: the
    relief and anti-cavitation valves' implicit update ("Integration (stiffness and substeps)")."""
    def stage(k: State, dt: float) -> State:      # x + dt k
        y = tuple(a + dt * b for a, b in zip(x, k))
        return y if project is None else project(y, dt)

    half = 0.5 * h
    k1 = f(t, x)
    k2 = f(t + half, stage(k1, half))
    k3 = f(t + half, stage(k2, half))
    k4 = f(t + h, stage(k3, h))
    sixth = h / 6.0
    y = tuple(a + sixth * (b1 + 2.0 * b2 + 2.0 * b3 + b4) for a, b1, b2, b3, b4 in zip(x, k1, k2, k3, k4))
    return y if project is None else project(y, h)


class _Prediction:
    """One prediction: the model, the drives and the joint status (held / stopped side) of the
    four joints (spec "Four joints": the end-stop rules of "End stops" over four joints)."""

    def __init__(self, model: TwinModel, drives: Sequence[Optional[_PressureDrive]]) -> None:
        self.model = model
        self.drives = tuple(drives)
        self.held = tuple(d is None for d in drives)
        #: the valve-driven joints; with any, the state is 10 long: (theta0, theta1, omega0,
        #: omega1, p_a0, p_b0, p_a1, p_b1, y0, y1), entries of other joints unused (kept at 0)
        self.valve = tuple(isinstance(d, _ValveDrive) for d in drives)
        self.hydraulic = any(self.valve)
        #: G_lim/C(V) of both chambers of each valve-driven joint at the start of the current
        #: substep (substeps): the rates of the relief and anti-cavitation valves' implicit update
        self.limit_coef: List[Tuple[float, float]] = [(0.0, 0.0)] * 4
        #: stop[j]: 0 not stopped, -1 at the lower angle limit, +1 at the upper (angle terms;
        #: the reported flag is converted to actuator terms by TwinModel.stop_flag)
        self.stop = [0, 0, 0, 0]
        #: the last release verdict, ((t, x, stop), released): a step that ends on a stop asks
        #: at its end and the next step asks again at its start, mostly at the same t
        self._last_release: Optional[Tuple[Tuple[Any, ...], Tuple[int, ...]]] = None
        #: (time, joint, angle side) of every impact, for diagnostics
        self.events: List[Tuple[float, int, int]] = []

    def locked(self) -> Tuple[bool, ...]:
        return tuple(self.held[j] or self.stop[j] != 0 for j in JOINTS)

    def flag(self, j: int) -> int:
        """Joint j's stop flag as reported, in actuator terms (TwinModel.stop_flag; 0: not
        stopped)."""
        return self.model.stop_flag[j][self.stop[j]] if self.stop[j] != 0 else 0

    def _conf(self, x: Sequence[float]) -> _Configuration:
        return self.model._configuration((x[0], x[1]), x[3])

    def acceleration(self, t: float, x: Sequence[float], locked: Tuple[bool, ...],
                     conf: Optional[_Configuration] = None) -> Quad:
        """qdd at time t: actuator forces of the unlocked joints into forward dynamics (conf: x's
        configuration, if already at hand)."""
        if all(locked):
            return 0.0, 0.0, 0.0, 0.0
        if conf is None:
            conf = self._conf(x)
        qd = x[4:8]
        tau = self.torques(t, conf, qd, locked, x)
        if locked[SLEW] and locked[EXTENSION]:
            # both at rest (held, or stopped with the rate zeroed): the planar 2x2 solve
            a = self.model._forward_dynamics(conf, qd[:2], tau[:2], locked[:2])
            return a[0], a[1], 0.0, 0.0
        return self.model._forward4(conf, qd, tau, locked)

    def ratio(self, conf: _Configuration, j: int) -> float:
        """ds/dq of joint j's actuator."""
        if j == SLEW:
            return self.model.slew_ratio
        if j == EXTENSION:
            return 1.0
        return conf.ratio[j]

    def torques(self, t: float, conf: _Configuration, qd: Sequence[float],
                locked: Sequence[bool], x: Sequence[float]) -> Quad:
        """Actuator forces at time t of the joints that are not locked (0 for the others); a
        valve-driven cylinder's pressures are the state's."""
        tau = [0.0, 0.0, 0.0, 0.0]
        for j in JOINTS:
            if not locked[j]:
                if self.valve[j]:
                    p_a, p_b = x[HYD + 2 * j], x[HYD + 1 + 2 * j]
                else:
                    p_a, p_b = self.drives[j].pressures(t)  # type: ignore[union-attr]
                tau[j] = self.model._joint_torque(j, self.ratio(conf, j), qd[j], p_a, p_b)
        return tau[0], tau[1], tau[2], tau[3]

    def stroke(self, j: int, theta: float, conf: Optional[_Configuration] = None) -> float:
        """Joint j's stroke: its limit on a stop, else from the angle (the slew: the rack's
        travel r_p (psi - slew_min); the extension: e - extension_min)."""
        if j in (SLEW, EXTENSION):
            q = theta if self.stop[j] == 0 else self.model.limit(j, self.stop[j])
            return self.ratio(None, j) * (q - self.model.angle_limits[j][0])  # type: ignore[arg-type]
        if self.stop[j] != 0:
            return self.model.stroke_at_stop[j][self.stop[j]]
        if j == LIFT:
            return self.model.lift_stroke(theta)
        return conf.tilt_stroke if conf is not None else self.model.tilt_stroke(theta)

    def derivative(self, t: float, x: State, locked: Tuple[bool, ...]) -> State:
        """d/dt of the state with the joints `locked` held still: qd, qdd and, with valves, the
        chamber pressures and the spools."""
        if not self.hydraulic:
            return x[4:8] + self.acceleration(t, x, locked)
        conf = self._conf(x)
        d = list(x[4:8]) + list(self.acceleration(t, x, locked, conf)) + [0.0] * 12
        for j in JOINTS:
            if not self.valve[j]:
                continue
            v = 0.0 if locked[j] else self.ratio(conf, j) * x[4 + j]
            d[HYD + 2 * j], d[HYD + 1 + 2 * j], d[SPOOL + j] = self.drives[j].rates(  # type: ignore
                t, self.stroke(j, x[j], conf), v, x[HYD + 2 * j], x[HYD + 1 + 2 * j], x[SPOOL + j])
        return tuple(d)

    def rk4(self, t: float, x: State, h: float, locked: Tuple[bool, ...]) -> State:
        """One step of the scheme (rk4_step) of size h with the joints `locked` held still."""
        return rk4_step(lambda s, y: self.derivative(s, y, locked), t, x, h,
                        self.limit_valves if self.hydraulic else None)

    def limit_valves(self, x: Tuple[float, ...], dt: float) -> Tuple[float, ...]:
        """x with the implicit part of every valve-driven chamber's relief and anti-cavitation
        valves over dt applied (docs/model.md, "Integration (stiffness and substeps)")."""
        y = list(x)
        for j in JOINTS:
            if self.valve[j]:
                y[HYD + 2 * j], y[HYD + 1 + 2 * j] = self.drives[j].limit_valves(  # type: ignore
                    self.limit_coef[j], dt, x[HYD + 2 * j], x[HYD + 1 + 2 * j])
        return tuple(y)

    def substeps(self, x: Sequence[float], h: float) -> int:
        """n = max(1, ceil(h Lambda / 2.5)): Lambda from the chamber volumes at the step's start
        (hydraulics) and the extension's friction (spec "Four joints"), the larger."""
        lam = 0.0
        for j in JOINTS:
            if self.valve[j]:
                stroke = self.stroke(j, x[j])
                self.limit_coef[j] = self.drives[j].limit_coefficients(stroke)  # type: ignore
                lam = max(lam, self.drives[j].stiffness(stroke))  # type: ignore
        if not self.held[EXTENSION]:
            lam = max(lam, self.extension_friction_rate(x))
        return substep_count(lam, h)

    def plastic_impact(self, x: State8, joint: int, side: int) -> State8:
        """Put the joint on its limit and stop it; the impulse acts on this joint only: over the
        free joints F, qd_F <- qd_F - Minv e_i (qd_i / Minv_ii) (Minv the inverse of M over F)."""
        q = list(x[:4])
        w = list(x[4:8])
        q[joint] = self.model.limit(joint, side)
        free = [j for j in JOINTS if j == joint or (not self.held[j] and self.stop[j] == 0)]
        if len(free) > 1:
            col = self._inverse_mass_column(q, free, joint)
            scale = w[joint] / col[free.index(joint)]
            for k, j in enumerate(free):
                w[j] -= col[k] * scale
        w[joint] = 0.0
        self.stop[joint] = side
        return tuple(q) + tuple(w) + tuple(x[8:])

    def _inverse_mass_column(self, q: Sequence[float], free: List[int], joint: int) -> List[float]:
        """Column `joint` of M^-1 over the joints `free` at q, at q's extension (a stopped extension
        need not be the model's); for the two booms alone the planar model's closed-form M^-1
        (the C core's arithmetic)."""
        conf = self.model._configuration((q[0], q[1]), q[3])
        if all(j in (LIFT, TILT) for j in free):
            minv = _inverse2(self.model._mass_matrix(conf))
            return [minv[j][joint] for j in free]
        return _inverse_column(self.model._mass_matrix4(conf, free), free.index(joint))

    def stop_at_start(self, x: State8, strokes: Sequence[float], rates: Sequence[float]) -> State8:
        """t = 0 rule: a free joint at a stroke limit whose stroke rate does not point into the
        range starts STOPPED there (with a plastic impact if it was moving)."""
        model = self.model
        for j in JOINTS:
            if self.held[j]:
                continue
            if j in (LIFT, TILT):
                lo, hi = model.stroke_min[j], model.stroke_max[j]
            else:
                lo, hi = model.angle_limits[j]
            if strokes[j] <= lo and rates[j] <= 0.0:
                at_min = True
            elif strokes[j] >= hi and rates[j] >= 0.0:
                at_min = False
            else:
                continue
            # the angle side of that stroke limit (from the sign of ds/dtheta)
            flag = -1 if at_min else +1
            side = -1 if model.stop_flag[j][-1] == flag else +1
            x = self.plastic_impact(x, j, side)
            self.events.append((0.0, j, side))
        return x

    def extension_friction_rate(self, x: State8) -> float:
        """lambda_e = G_f (M^-1)_ee, 1/s, over the joints that are not held: how fast the
        extension's friction acts near rest (spec "Four joints"; the light extension boom makes it
        the stiffest term of the mechanics). Coupled to free booms, (M^-1)_ee is up to ~4 / m3."""
        free = [j for j in JOINTS if not self.held[j]]
        mass = self.model._mass_matrix4(self._conf(x), free)
        i = free.index(EXTENSION)
        col = _inverse_column(mass, i)
        # (M^-1)_ee taken at most 4 / m_ext: the bound on the work of a call (spec)
        return self.model.friction_slope(EXTENSION) * min(col[i], 4.0 / self.model.extension_boom[0])

    def release(self, t: float, x: State8) -> None:
        """Let go of the STOPPED joints that the release rule frees at (t, x)."""
        for j in self.released(t, x):
            self.stop[j] = 0

    def released(self, t: float, x: State8) -> Tuple[int, ...]:
        """The STOPPED joints that leave their stops at (t, x) (docs/model.md, "Release").

        The unilateral stops form a small complementarity problem. The candidate release sets
        are the subsets of STOPPED joints in the order of their bitmask (lift 1, tilt 2, slew 4,
        extension 8; for two joints: none, lift, tilt, both); the first is taken in which every
        released joint accelerates into its range and every joint left on its stop is pressed
        onto it (its reaction M qdd - (tau - h) points into the range). Changes nothing, so
        that the release search inside a step can ask it at trial times."""
        if not any(self.stop):
            return ()
        key = (t, x, tuple(self.stop))
        last = self._last_release
        if last is not None and last[0] == key:
            return last[1]
        released = self._release_rule(t, x)
        self._last_release = (key, released)
        return released

    def _release_rule(self, t: float, x: State8) -> Tuple[int, ...]:
        """The complementarity rule itself, for released()."""
        m = self.model
        conf = self._conf(x)
        qd = x[4:8]
        planar = self.held[SLEW] and self.held[EXTENSION]   # the planar model's arithmetic
        if planar:
            h = m._inverse_dynamics(conf, qd[:2], (0.0, 0.0), m.gravity) + (0.0, 0.0)
        else:
            h = m._id4(conf, qd, (0.0, 0.0, 0.0, 0.0), m.gravity)
        tau = self.torques(t, conf, qd, self.held, x)
        net = tuple(tau[j] - h[j] for j in JOINTS)
        mass: Optional[List[List[float]]] = None   # only a candidate that moves a joint needs M
        stopped = [self.stop[j] != 0 for j in JOINTS]
        for mask in range(16):
            released = tuple(j for j in JOINTS if mask & (1 << j))
            if any(not stopped[j] for j in released):
                continue
            locked = tuple(self.held[j] or (stopped[j] and j not in released) for j in JOINTS)
            if planar:
                alpha = m._forward_dynamics(conf, qd[:2], tau[:2], locked[:2]) + (0.0, 0.0)
            else:
                alpha = m._forward4(conf, qd, tau, locked)
            consistent = True
            for j in JOINTS:
                if not stopped[j]:
                    continue
                inward = float(-self.stop[j])  # the lower stop (-1) is left with alpha > 0
                if j in released:
                    consistent = consistent and inward * alpha[j] > 0.0
                else:
                    if not any(alpha):
                        reaction = -net[j]
                    else:
                        if mass is None:
                            mass = ([list(row) for row in m._mass_matrix(conf)] if planar
                                    else m._mass_matrix4(conf, JOINTS))
                        reaction = sum(mass[j][k] * alpha[k] for k in range(len(mass))) - net[j]
                    consistent = consistent and inward * reaction >= 0.0
            if consistent:
                return released
        return ()

    @staticmethod
    def crossing_time(th0: float, w0: float, th1: float, w1: float, h: float,
                      limit: float, below: bool) -> float:
        """Time in (0, h] at which the cubic Hermite interpolant of theta on the step reaches
        the limit: 60 bisections, lo inside, hi outside, returns hi."""
        lo = 0.0
        hi = h
        for _ in range(EVENT_BISECTIONS):
            mid = 0.5 * (lo + hi)
            s = mid / h
            s2 = s * s
            s3 = s2 * s
            theta = ((2.0 * s3 - 3.0 * s2 + 1.0) * th0 + (s3 - 2.0 * s2 + s) * h * w0
                     + (-2.0 * s3 + 3.0 * s2) * th1 + (s3 - s2) * h * w1)
            outside = theta < limit if below else theta > limit
            if outside:
                hi = mid
            else:
                lo = mid
        return hi

    def advance(self, t: float, x: State, t_end: float) -> State:
        """x from t to t_end, one piece of a step ("Hydraulics" and "Four joints", the extension's
        friction): n equal substeps, each a full step of the scheme with its releases and impacts,
        the last ending at t_end."""
        h = t_end - t
        n_sub = self.substeps(x, h) if self.hydraulic or not self.held[EXTENSION] else 1
        if n_sub == 1:
            self.release(t, x)
            return self.step(t, x, h)
        sub = h / n_sub
        for i in range(n_sub):
            t_sub = t + i * sub
            self.release(t_sub, x)
            x = self.step(t_sub, x, t_end - t_sub if i == n_sub - 1 else sub)
        return x

    def step(self, t: float, x: State8, h: float) -> State8:
        """One step of size h, cut into pieces at the impacts and releases located inside it
        (at most MAX_PIECES; the last takes the rest of the step whatever happens in it)."""
        t_cur = t
        remaining = h
        for piece in range(1, MAX_PIECES + 1):
            locked = self.locked()
            x1 = self.rk4(t_cur, x, remaining, locked)
            if piece == MAX_PIECES:
                return self.impacts(t_cur + remaining, x1, touching=False)
            tau = self.impact_time(x, x1, remaining, locked)
            if tau is not None:
                x = self.impacts(t_cur + tau, self.rk4(t_cur, x, tau, locked), touching=True)
            elif any(self.stop) and self.released(t_cur + remaining, x1):
                tau, x = self.release_time(t_cur, x, remaining, x1, locked)
                self.release(t_cur + tau, x)
            else:
                return x1
            t_cur = t_cur + tau
            remaining = remaining - tau
            if not remaining > 0.0:
                return x
        raise AssertionError("unreachable: the last piece returns")

    def impact_time(self, x: State8, x1: State8, h: float, locked: Tuple[bool, ...]
                    ) -> Optional[float]:
        """Size of the piece up to the first impact in the RK4 step x -> x1 of size h, or None
        if no free joint ends strictly outside its limits."""
        tau = math.inf
        for j in JOINTS:
            if locked[j]:
                continue
            lower, upper = self.model.angle_limits[j]
            if x1[j] < lower:
                tau = min(tau, self.crossing_time(x[j], x[4 + j], x1[j], x1[4 + j], h, lower, True))
            elif x1[j] > upper:
                tau = min(tau, self.crossing_time(x[j], x[4 + j], x1[j], x1[4 + j], h, upper, False))
        return None if tau == math.inf else tau

    def impacts(self, t: float, x: State8, touching: bool) -> State8:
        """In joint order, every free joint beyond a limit (or at it, if touching) is put on it
        with a plastic impact. After a located impact the joint is at the limit to within the
        bisection, so it counts as touching; the last piece of a step takes only those beyond."""
        for j in JOINTS:
            if self.held[j] or self.stop[j] != 0:
                continue
            lower, upper = self.model.angle_limits[j]
            if x[j] < lower or (touching and x[j] == lower):
                side = -1
            elif x[j] > upper or (touching and x[j] == upper):
                side = +1
            else:
                continue
            x = self.plastic_impact(x, j, side)
            self.events.append((t, j, side))
        return x

    def release_time(self, t: float, x: State8, h: float, x1: State8,
                     locked: Tuple[bool, ...]) -> Tuple[float, State8]:
        """The piece size (and the state it ends in) at which a stopped joint is released,
        given that the release rule frees something at the end of the RK4 step x -> x1 of size
        h: RELEASE_BISECTIONS bisections keeping lo (releases nothing) and hi (releases).

        Without this a joint would leave its stop only at the start of the next step: a delay
        of up to dt, and a tip error of first order in dt."""
        lo = 0.0
        hi = h
        x_hi = x1
        for _ in range(RELEASE_BISECTIONS):
            mid = 0.5 * (lo + hi)
            x_mid = self.rk4(t, x, mid, locked)
            if self.released(t + mid, x_mid):
                hi = mid
                x_hi = x_mid
            else:
                lo = mid
        return hi, x_hi


def _physical(x: Sequence[float]) -> bool:
    """Finite, and (with valves) every chamber pressure within +-PRESSURE_MAX and every spool in
    [-1, 1]: an integration gone unstable shows there first (docs/model.md, "Bad input")."""
    from .._checks import PRESSURE_MAX

    if not all(math.isfinite(v) for v in x):
        return False
    if len(x) > HYD:
        return all(-PRESSURE_MAX <= v <= PRESSURE_MAX for v in x[HYD:SPOOL]) and \
            all(-1.0 <= v <= 1.0 for v in x[SPOOL:])
    return True


def _next_knot(drives: Sequence[Any], t: float, t_end: float, dt: float) -> float:
    """The earliest sample time of a sampled drive inside (t, t_end), more than dt/1000 from
    both ends (docs/model.md, "Integration and samples"); t_end if there is none."""
    lo, hi = t + 1e-3 * dt, t_end - 1e-3 * dt
    knot = t_end
    for drive in drives:
        times = getattr(drive, "times", None)
        if not times:
            continue
        i = bisect_right(times, lo)
        if i < len(times) and times[i] < hi:
            knot = min(knot, times[i])
    return knot


def integrate(pred: _Prediction, x: State, horizon: float, dt: float, n: int,
              record: Callable[[int, float, State], None]) -> State:
    """x over n steps of dt, the last ending at horizon, with record(k, t, x) after step k - 1
    (docs/model.md "Integration and samples": a step is cut at the sampled drives' knots inside
    it, each piece a step of its own, advanced by _Prediction.advance)."""
    for k in range(n):
        last = k == n - 1
        t_end = horizon if last else (k + 1) * dt
        t = k * dt
        while True:
            t_q = _next_knot(pred.drives, t, t_end, dt)
            x = pred.advance(t, x, t_q)
            t = t_q
            if t >= t_end:
                break
        if not _physical(x):
            raise ValueError(f"the prediction diverged at t = {t:g} s (the state is no longer finite, "
                             "or a spool or chamber pressure left its range): check the crane's "
                             "parameters for absurd values")
        record(k + 1, t_end, x)
    return x
