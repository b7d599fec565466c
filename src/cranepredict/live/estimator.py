"""State estimation: the crane's full state (every joint's position and rate, every chamber's
pressure) from what it measures.

:class:`Estimator` is the interface the live twin uses: ``update(measurement) -> State`` and
``covariance``. :class:`EKF` is an extended Kalman filter over the model: its model step is the C
core's prediction over the period between two measurements; its Jacobian is by finite differences
(every perturbed state predicted in one ``predict_many`` call). The filter runs in the C core
(``crane_estimator_update``, ``backend="c"``, the product: its cost is per control cycle on the
controller) or in numpy (``backend="python"``, the same algorithm written independently, which
validates it). The measurement model is linear
(the sensors measure state fields). The estimate is kept in the valid state domain (projected
after each update) and the covariance symmetric positive definite (Joseph form, symmetrised,
eigenvalues floored). A normalised-innovation-squared (NIS) test over a window of cycles flags
an estimator that no longer explains the sensors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from .. import api
from .._checks import PRESSURE_MAX
from ..crane import Crane
from ..types import (CHAMBER_PRESSURE_MIN, JOINTS, SLEW_RATE_MAX, STROKE_RATE_MAX, Hold, Inputs,
                     State, Valve)
from .measurement import POSITIONS, PRESSURES, RATES, SPOOLS, Measurement, Sensors, default_sensors

__all__ = ["Estimator", "EKF", "ESTIMATED", "InnovationFault", "chi2_quantile"]

#: The estimated State fields, in the order of the state vector and the covariance's rows.
ESTIMATED = POSITIONS + RATES + PRESSURES

#: The Jacobian's columns an update renews by default (in turn; each column then at most 30 ms
#: old at 100 Hz): 5 futures an update instead of 17, with the estimates of the accuracy study
#: within 1 % of the whole Jacobian's (docs/live.md).
JACOBIAN_COLUMNS = 4

#: The finite-difference step of each estimated field (its SI unit).
_STEP = {**{p: 1e-5 for p in POSITIONS}, **{r: 1e-4 for r in RATES}, **{p: 1e3 for p in PRESSURES}}


class InnovationFault(Exception):
    """The estimator's innovation test failed: the model no longer explains the sensors."""


@lru_cache(maxsize=1024)
def chi2_quantile(p: float, k: int) -> float:
    """The p-quantile of the chi-square distribution with k degrees of freedom (Wilson-Hilferty,
    within 1 % for k >= 3 at p <= 0.9999). Cached: the innovation test asks the same few every
    cycle, and the bisection costs more than the rest of a C filter's update."""
    # the standard normal quantile by bisection on erf
    lo, hi = -10.0, 10.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if 0.5 * (1.0 + math.erf(mid / math.sqrt(2.0))) < p:
            lo = mid
        else:
            hi = mid
    z = 0.5 * (lo + hi)
    a = 2.0 / (9.0 * k)
    return k * (1.0 - a + z * math.sqrt(a)) ** 3


class Estimator:
    """The interface of a state estimator: ``update(measurement) -> State`` (the estimate at the
    measurement's time) and ``covariance`` (of :data:`ESTIMATED`, SI units); ``reset()`` forgets
    everything (the next measurement initialises)."""

    covariance: np.ndarray

    def update(self, measurement: Measurement) -> State:  # pragma: no cover - interface
        raise NotImplementedError

    def reset(self) -> None:  # pragma: no cover - interface
        raise NotImplementedError


def _domain(crane: Crane) -> Tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of every estimated field."""
    lo, hi = [], []
    g, sd = crane.geometry, crane.slew_drive
    for name in ESTIMATED:
        if name == "lift_stroke":
            b = (crane.lift_cylinder.stroke_min, crane.lift_cylinder.stroke_max)
        elif name == "tilt_stroke":
            b = (crane.tilt_cylinder.stroke_min, crane.tilt_cylinder.stroke_max)
        elif name == "slew":
            b = (sd.slew_min, sd.slew_max) if sd is not None else (-math.pi, math.pi)
        elif name == "extension":
            b = (g.extension_min, g.extension_max)
        elif name == "slew_rate":
            b = (-SLEW_RATE_MAX, SLEW_RATE_MAX)
        elif name in RATES:
            b = (-STROKE_RATE_MAX, STROKE_RATE_MAX)
        else:
            b = (CHAMBER_PRESSURE_MIN, PRESSURE_MAX)
        lo.append(b[0])
        hi.append(b[1])
    return np.array(lo), np.array(hi)


@dataclass
class _Noise:
    """Process noise densities (per second) of the model's error, by kind of field."""

    position: float = 1e-8         # m^2/s (rad^2/s)
    rate: float = 4e-3             # (m/s)^2/s: unmodelled forces (the load, friction)
    extension_rate: float = 4e-2   # (m/s)^2/s: the telescope's, larger (its friction and valve
                                   # are estimates in the crane file)
    pressure: float = 5e11         # Pa^2/s: unmodelled flows and loads (7 bar over 1 s)


class EKF(Estimator):
    """An extended Kalman filter over the C core's model (see the module's notes).

    ``sensors`` say what is measured and how noisy (default: :func:`default_sensors`);
    ``window`` cycles of normalised innovation squared are tested against their chi-square
    ``p``-quantile (all sensors together) and ``p_field``-quantile (each sensor alone): above
    either, :meth:`update` raises :class:`InnovationFault`. Each update renews
    ``jacobian_columns`` of the model Jacobian's 16 columns, in turn (16: all of them, every
    update; the first update after a (re)start renews all): one model future per column.
    """

    def __init__(self, crane: Crane, sensors: Optional[Sensors] = None, *, dt: Optional[float] = None,
                 window: int = 25, p: float = 1 - 1e-7, p_field: float = 1 - 1e-12, noise: Optional[_Noise] = None,
                 jacobian_columns: int = JACOBIAN_COLUMNS, backend: str = "c") -> None:
        if backend not in ("c", "python"):
            raise ValueError(f"backend must be 'c' or 'python', got {backend!r}")
        if isinstance(jacobian_columns, bool) or not isinstance(jacobian_columns, (int, np.integer)):
            raise TypeError(f"jacobian_columns must be an int, got {type(jacobian_columns).__name__}")
        if not 1 <= jacobian_columns <= len(ESTIMATED):
            raise ValueError(f"jacobian_columns must be in [1, {len(ESTIMATED)}], got {jacobian_columns}")
        self.jacobian_columns = int(jacobian_columns)
        self.backend = backend
        if not isinstance(crane, Crane):
            raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
        self.crane = crane
        self.sensors = default_sensors() if sensors is None else sensors
        if not isinstance(self.sensors, Sensors):
            raise TypeError(f"sensors must be a cranepredict.Sensors, got {type(self.sensors).__name__}")
        missing = [p for p in POSITIONS if p not in self.sensors]
        if missing:
            raise ValueError(f"sensors must measure every joint's position (the estimator cannot "
                             f"observe a joint without it): missing {missing}")
        self.dt = dt
        self.window = int(window)
        self.p = float(p)
        self.p_field = float(p_field)
        self.noise = noise or _Noise()
        self.lo, self.hi = _domain(crane)
        self._index = {n: i for i, n in enumerate(ESTIMATED)}
        self._q = np.array([self.noise.position] * 4 + [self.noise.rate] * 3
                           + [self.noise.extension_rate] + [self.noise.pressure] * 8)
        self._h = np.array([_STEP[n] for n in ESTIMATED])
        self._scale = np.array([1e-3] * 4 + [1e-3] * 4 + [1e5] * 8)
        self.projections = 0
        self.reset()

    def reset(self) -> None:
        self._c: Any = None
        self._jacobian: Optional[np.ndarray] = None   # the numpy filter's, column by column
        self._next_column = 0
        self.x: Optional[np.ndarray] = None
        self.covariance = np.zeros((len(ESTIMATED), len(ESTIMATED)))
        self.spools = np.zeros(4)
        self.t: Optional[float] = None
        self.inputs: Optional[Inputs] = None
        self.nis: List[Tuple[float, int]] = []
        self.field_nis: Dict[str, List[float]] = {}
        self.state: Optional[State] = None

    # -- state <-> vector ----------------------------------------------------------------------

    def _state(self, x: np.ndarray, inputs: Inputs, spools: np.ndarray) -> State:
        f = {n: float(v) for n, v in zip(ESTIMATED, x)}
        for j, name in enumerate(JOINTS):
            if isinstance(getattr(inputs, name), Hold):
                f[RATES[j]] = 0.0
            f[SPOOLS[j]] = float(spools[j])
        return State(**f)

    @staticmethod
    def _vector(s: State) -> np.ndarray:
        return np.array([0.0 if getattr(s, n) is None else getattr(s, n) for n in ESTIMATED])

    # -- the filter ----------------------------------------------------------------------------

    def _initialise(self, m: Measurement) -> State:
        values = m.values()
        missing = [p for p in POSITIONS if p not in values]
        if missing:
            raise ValueError(f"the first measurement must hold every joint's position, missing {missing}")
        # a position read a little beyond its end (noise at an end stop) starts at the end
        pose = {p: min(max(values[p], self.lo[i]), self.hi[i]) for i, p in enumerate(POSITIONS)}
        if any(pose[p] != values[p] for p in POSITIONS):
            self.projections += 1
        rest = api.state_at_rest(self.crane, pose["lift_stroke"], pose["tilt_stroke"],
                                 slew=pose["slew"], extension=pose["extension"])
        x = self._vector(rest)
        var = []
        for n in ESTIMATED:
            if n in values and n in self.sensors and n not in POSITIONS:
                x[self._index[n]] = values[n]
                var.append(self.sensors[n].std ** 2)
            elif n in POSITIONS:
                x[self._index[n]] = pose[n]
                var.append(self.sensors[n].std ** 2)
            elif n in RATES:
                var.append(0.05 ** 2)
            else:
                var.append((20e5) ** 2)
        self.x = np.clip(x, self.lo, self.hi)
        self.covariance = np.diag(var)
        self.spools = np.array([getattr(m, s) if getattr(m, s) is not None else
                                (getattr(m.inputs, j).u if isinstance(getattr(m.inputs, j), Valve) else 0.0)
                                for j, s in zip(JOINTS, SPOOLS)])
        self.t = m.t
        self.inputs = m.inputs
        if self.backend == "c":
            self._c_init()
        self.state = self._state(self.x, m.inputs, self.spools)
        return self.state

    # -- the C core's filter -------------------------------------------------------------------

    def _c_init(self) -> None:
        """The C estimator (crane_estimator) at the current estimate, covariance and spools."""
        from .. import _core

        ffi, lib = _core.ffi, _core.lib
        config = ffi.new("crane_estimator_config *")
        config.lo, config.hi = list(self.lo), list(self.hi)
        config.noise, config.fd_step, config.scale = list(self._q), list(self._h), list(self._scale)
        config.dt = api.DEFAULT_DT if self.dt is None else float(self.dt)
        config.jacobian_columns = self.jacobian_columns
        est = ffi.new("crane_estimator *")
        _core.ensure(lib.crane_estimator_init(est, config, list(self.x),
                                              list(self.covariance.ravel()), list(self.spools)),
                     "estimator")
        self._c = est
        self.x = np.array(list(est.x))
        self.covariance = np.array(list(est.covariance)).reshape(len(ESTIMATED), len(ESTIMATED))

    def _c_update(self, measurement: Measurement, period: float) -> Tuple[List[str], np.ndarray]:
        """One cycle in the C core; returns the measured fields and their innovations' NIS."""
        from .. import _core

        ffi, lib = _core.ffi, _core.lib
        values = measurement.values()
        z, var = np.zeros(len(ESTIMATED)), np.zeros(len(ESTIMATED))
        names = [n for n in ESTIMATED if n in values and n in self.sensors]
        for n in names:
            z[self._index[n]] = values[n]
            var[self._index[n]] = self.sensors[n].std ** 2
        inputs = ffi.new("crane_inputs *")
        keep: list = []
        _core._inputs(inputs, self.inputs, keep)
        est = self._c
        est.spool = list(self.spools)
        _, model = _core._cached(self.crane, self.crane.geometry.extension_min)
        status = lib.crane_estimator_update(est, model, inputs, float(period), list(z), list(var))
        if status != lib.CRANE_OK:
            self._c = None   # the filter must start again (crane.h)
            _core.ensure(status, "estimator")
        self.x = np.array(list(est.x))
        self.covariance = np.array(list(est.covariance)).reshape(len(ESTIMATED), len(ESTIMATED))
        self.spools = np.array(list(est.spool))
        self.projections += int(est.projected)
        field_nis = np.array(list(est.field_nis))[[self._index[n] for n in names]]
        if names:
            self.nis.append((float(est.nis), len(names)))
            self.nis = self.nis[-self.window:]
        return names, field_nis

    def _propagate(self, inputs: Inputs, period: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x', F, spools') over ``period`` under ``inputs``: the nominal future and one per
        renewed column of the Jacobian (all of them until each has been computed once, then
        ``jacobian_columns`` in turn), in one predict_many call."""
        x = self.x
        n = len(x)
        steps = np.where(x + self._h <= self.hi, self._h, -self._h)
        held = [isinstance(getattr(inputs, j), Hold) for j in JOINTS]
        if self._jacobian is None or self.jacobian_columns >= n:
            cols = list(range(n))
        else:
            cols = [(self._next_column + r) % n for r in range(self.jacobian_columns)]
        initials = [self._state(x, inputs, self.spools)]
        for i in cols:
            xi = x.copy()
            xi[i] += steps[i]
            initials.append(self._state(xi, inputs, self.spools))
        dt = min(api.DEFAULT_DT if self.dt is None else self.dt, period)
        # fixed RK4 steps, as the C filter's (an adaptive step's choice would put its tolerance's
        # noise into the finite differences)
        batch = api.predict_many(self.crane, initials, [inputs] * len(initials), period, dt=dt,
                                 sample_every=max(1, int(math.ceil(period / dt))), method="rk4")
        y = self._finals(batch)
        if self._jacobian is None:
            self._jacobian = np.zeros((n, n))
        for r, i in enumerate(cols):
            self._jacobian[:, i] = (y[1 + r] - y[0]) / steps[i]
        if len(cols) < n:
            self._next_column = (self._next_column + len(cols)) % n
        F = self._jacobian.copy()
        for j in range(4):
            if held[j]:   # a held joint: its pressures are not the model's, keep them
                for side in (2 * j, 2 * j + 1):
                    k = 8 + side
                    y[0, k] = x[k]
                    F[k, :] = 0.0
                    F[k, k] = 1.0
        return y[0], F, np.array(batch.spool[0, -1, :], dtype=float)

    def _finals(self, batch: Any) -> np.ndarray:
        """The estimated fields at each future's last sample (rows). Read from the arrays, not
        as States: a perturbed future may dip below a State's range (a chamber under vacuum for
        a step); the update projects the estimate back into the domain."""
        from .. import _core

        f = len(batch)
        y = np.empty((f, len(ESTIMATED)))
        y[:, 0:2] = batch.strokes[:, -1, :]
        y[:, 2] = batch.slew[:, -1]
        y[:, 3] = batch.extension[:, -1]
        for j in range(2):
            ds = [_core.joint_angle(self.crane, j, float(batch.strokes[k, -1, j]),
                                    float(batch.extension[k, -1]))[1] for k in range(f)]
            y[:, 4 + j] = batch.omega[:, -1, j] * np.array(ds)
        y[:, 6] = batch.slew_rate[:, -1]
        y[:, 7] = batch.extension_rate[:, -1]
        y[:, 8::2] = batch.p_a[:, -1, :]
        y[:, 9::2] = batch.p_b[:, -1, :]
        return y

    def _innovation_test(self) -> None:
        """Over the last ``window`` cycles: the normalised innovation squared of all the sensors
        together against its chi-square ``p``-quantile, and each sensor's own (a stuck or drifting
        sensor) against its chi-square ``p_field``-quantile (stricter: there are many sensors)."""
        if len(self.nis) < self.window:
            return
        total = sum(v for v, _ in self.nis)
        dof = sum(k for _, k in self.nis)
        bound = chi2_quantile(self.p, dof)
        if total > bound:
            raise InnovationFault(f"normalised innovation {total:.0f} over the last "
                                  f"{len(self.nis)} cycles exceeds its chi-square (1 - {1 - self.p:.0e}) "
                                  f"bound {bound:.0f} ({dof} degrees of freedom)")
        for n, vals in self.field_nis.items():
            if len(vals) < self.window:
                continue
            total, bound = sum(vals), chi2_quantile(self.p_field, len(vals))
            if total > bound:
                raise InnovationFault(f"{n}: normalised innovation {total:.0f} over the last "
                                      f"{len(vals)} samples exceeds its chi-square "
                                      f"(1 - {1 - self.p_field:.0e}) bound {bound:.0f} (a stuck or "
                                      f"drifting sensor?)")

    def _positive(self, P: np.ndarray) -> np.ndarray:
        """P symmetric and positive definite: symmetrised, and its eigenvalues floored in units
        where every field's scale is 1 (P spans 1e-9 m^2 to 1e10 Pa^2: unscaled, rounding alone
        makes small eigenvalues negative)."""
        s = self._scale
        Ps = 0.5 * (P + P.T) / np.outer(s, s)
        w, v = np.linalg.eigh(Ps)
        if w.min() < 1e-12:
            Ps = (v * np.maximum(w, 1e-12)) @ v.T
            Ps = 0.5 * (Ps + Ps.T)
        return Ps * np.outer(s, s)

    def scaled_covariance(self) -> np.ndarray:
        """The covariance in units of each field's scale (mm, mm/s, bar): well conditioned."""
        return self.covariance / np.outer(self._scale, self._scale)

    def update(self, measurement: Measurement) -> State:
        if not isinstance(measurement, Measurement):
            raise TypeError(f"measurement must be a cranepredict.Measurement, got {type(measurement).__name__}")
        if self.x is None:
            return self._initialise(measurement)
        period = measurement.t - self.t
        if not period > 0:
            raise ValueError(f"Measurement.t must increase: {measurement.t} after {self.t}")
        if self.backend == "c":
            if self._c is None:
                self._c_init()
            names, field_nis = self._c_update(measurement, period)
            for n, v in zip(names, field_nis):
                self.field_nis.setdefault(n, []).append(float(v))
                del self.field_nis[n][:-self.window]
            self._finish(measurement)
            return self.state
        # the valves' commands of the previous measurement, held over the period (zero-order hold)
        x, F, spools = self._propagate(self.inputs, period)
        P = F @ self.covariance @ F.T + np.diag(self._q * period)
        values = measurement.values()
        rows = [self._index[n] for n in ESTIMATED if n in values and n in self.sensors]
        if rows:
            names = [ESTIMATED[i] for i in rows]
            z = np.array([values[n] for n in names])
            r = np.array([self.sensors[n].std ** 2 for n in names])
            innov = z - x[rows]
            S = P[np.ix_(rows, rows)] + np.diag(r)
            S = 0.5 * (S + S.T)
            PHt = P[:, rows]
            K = np.linalg.solve(S, PHt.T).T
            x = x + K @ innov
            # Joseph form: (I - K H) P (I - K H)^T + K R K^T stays symmetric positive definite
            IKH = np.eye(len(x))
            IKH[:, rows] -= K
            P = IKH @ P @ IKH.T + (K * r) @ K.T
            self.nis.append((float(innov @ np.linalg.solve(S, innov)), len(rows)))
            self.nis = self.nis[-self.window:]
            for n, v in zip(names, innov ** 2 / np.diag(S)):
                self.field_nis.setdefault(n, []).append(float(v))
                del self.field_nis[n][:-self.window]
        P = self._positive(P)
        inside = np.clip(x, self.lo, self.hi)
        if np.any(inside != x):
            self.projections += 1
        self.x, self.covariance, self.spools = inside, P, spools
        self._finish(measurement)
        return self.state

    def _finish(self, measurement: Measurement) -> None:
        """The measured spools over the model's, the State, the innovation test."""
        self.t = measurement.t
        self.inputs = measurement.inputs
        for j, s in enumerate(SPOOLS):
            if getattr(measurement, s) is not None and s in self.sensors:
                self.spools[j] = getattr(measurement, s)
        self.state = self._state(self.x, measurement.inputs, self.spools)
        self._innovation_test()
