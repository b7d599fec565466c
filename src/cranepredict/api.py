"""The prediction entry points: :func:`predict` (one future, C core or twin) and
:func:`predict_many` (many futures of one crane, C core)."""

from __future__ import annotations

import os
import warnings
from functools import partial
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple

import numpy as np

from ._checks import MAX_SAMPLES, MAX_STEPS, kept_samples, step_count
from ._checks import number as _number
from . import solver
from .crane import Crane
from .solver import Tolerance
from .statics import holding_forces, pressures_in_bar, supply_short
from .types import (ARRAYS, POINT_NAMES, Hold, Inputs, Pressure, PressureSeries, State, Trajectory,
                    TrajectoryBatch, Valve, ValveSeries)

__all__ = ["predict", "predict_many", "state_at_rest", "DEFAULT_DT", "BACKENDS", "MAX_STEPS",
           "MAX_SAMPLES", "VARY_FIELDS"]

# The C core (the compiled extension) is imported on the first call that needs it, so that the
# package, its types and the twin import without it (tests/test_package.py).
_CORE: Any = None


_CORES: list = []


def cores() -> int:
    """os.cpu_count() (at least 1), asked once: the call reads the system's files (about 6 us),
    and a guard's verdict, a control loop's call, asks four times."""
    if not _CORES:
        _CORES.append(os.cpu_count() or 1)
    return int(_CORES[0])


def _core_module() -> Any:
    global _CORE
    if _CORE is None:
        from . import _core

        _CORE = _core
    return _CORE


#: Default RK4 step and sample interval, s. Chosen by measured accuracy (tools/dt_study.py, checked
#: by tests/test_default_step.py): over the named scenarios and 30 random ones the tip stays within
#: 0.36 mm of a converged run (the accuracy target is 1 mm; 10 ms misses it; docs/dt-study.md). Steps are cut
#: at the samples of sampled drives, and valve-driven cylinders add their own substeps.
DEFAULT_DT = 5e-3

BACKENDS = ("c", "python")

# Trajectory array (types.ARRAYS) -> field of the core's crane_sample, where the names differ.
_SAMPLE_FIELD = {"strokes": "stroke"}

#: Batches smaller than this run in one thread (a thread costs more than it saves).
MIN_FUTURES_PER_THREAD = 8


def _sample_arrays(samples: np.ndarray) -> dict:
    """The Trajectory arrays as field views of the core's samples (shape (N,) or (F, N); no copy)."""
    return {k: samples[_SAMPLE_FIELD.get(k, k)] for k in ARRAYS}


def _check(crane: Crane, initial: State, inputs: Inputs, horizon: float, dt: float,
           backend: str, sample_every: int = 1) -> int:
    """predict()'s checks, naming the field and the allowed range; returns the number of steps."""
    n_steps = _check_call(crane, horizon, dt, sample_every, backend)[2]
    _check_future(crane, initial, inputs, horizon)
    return n_steps


def _check_call(crane: Crane, horizon: Any, dt: Any, sample_every: Any,
                backend: Any) -> Tuple[float, float, int]:
    """The checks of predict()'s call arguments besides the future itself (the place for a new
    keyword's check): (horizon, dt, number of steps), the first two as floats."""
    horizon, dt, n_steps = _check_shared(crane, horizon, dt, backend)
    _check_sample_every(sample_every)
    if n_steps >= MAX_SAMPLES and kept_samples(n_steps, int(sample_every)) > MAX_SAMPLES:
        raise ValueError(f"horizon / dt must give at most {MAX_SAMPLES:,} samples per call "
                         f"(cranepredict.MAX_SAMPLES), got horizon {horizon:g} s / dt {dt:g} s = "
                         f"{kept_samples(n_steps, int(sample_every)):,} samples: shorten the "
                         "horizon, take a larger dt, or raise sample_every")
    return horizon, dt, n_steps


def _check_sample_every(sample_every: Any) -> None:
    if type(sample_every) is int and 1 <= sample_every <= MAX_STEPS:
        return
    if isinstance(sample_every, bool) or not isinstance(sample_every, (int, np.integer)) \
            or not 1 <= sample_every <= MAX_STEPS:
        raise ValueError(f"sample_every must be an int in [1, {MAX_STEPS:,}] (cranepredict.MAX_STEPS), "
                         f"got {sample_every!r}")


def _kept_rows(n_steps: int, sample_every: int) -> np.ndarray:
    """Rows of a full prediction (n_steps + 1 samples) that sample_every keeps: t = 0, after every
    sample_every-th step and after the last step (the C core's crane_sample_count_every)."""
    rows = np.arange(0, n_steps + 1, sample_every)
    return rows if rows[-1] == n_steps else np.append(rows, n_steps)


def _check_shared(crane: Crane, horizon: Any, dt: Any, backend: Any) -> Tuple[float, float, int]:
    """The checks of the arguments a batch of futures shares: (horizon, dt, number of steps),
    the first two as floats."""
    if not isinstance(crane, Crane):
        raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
    h = _number(horizon, "horizon")
    if not h > 0:
        raise ValueError(f"horizon must be > 0 s, got {horizon}")
    d = _number(dt, "dt")
    if not d > 0:
        raise ValueError(f"dt must be > 0 s, got {dt}")
    if d > h:
        raise ValueError(f"dt must be in (0, horizon] = (0, {horizon}] s, got {dt}")
    return h, d, step_count(h, d)


_VALVES = (Valve, ValveSeries)


def _check_future(crane: Crane, initial: State, inputs: Inputs, horizon: float) -> None:
    """The checks of one future: its initial state and inputs against the crane and horizon."""
    if not isinstance(initial, State):
        raise TypeError(f"initial must be a cranepredict.State, got {type(initial).__name__}")
    if not isinstance(inputs, Inputs):
        raise TypeError(f"inputs must be a cranepredict.Inputs, got {type(inputs).__name__}")
    _check_boom("lift", crane.lift_cylinder, initial.lift_stroke, initial.lift_stroke_rate,
                inputs.lift, initial, horizon)
    _check_boom("tilt", crane.tilt_cylinder, initial.tilt_stroke, initial.tilt_stroke_rate,
                inputs.tilt, initial, horizon)
    g = crane.geometry
    if not g.extension_min <= initial.extension <= g.extension_max:
        raise ValueError(f"State.extension must be in [{g.extension_min}, {g.extension_max}] m "
                         f"(geometry.extension_min/max), got {initial.extension}")
    sd = crane.slew_drive
    if sd is not None and not sd.slew_min <= initial.slew <= sd.slew_max:
        raise ValueError(f"State.slew must be in [{sd.slew_min}, {sd.slew_max}] rad "
                         f"(slew_drive.slew_min/max), got {initial.slew}")
    slew, extension = inputs.slew, inputs.extension
    if not (slew.held and initial.slew_rate == 0.0):   # else nothing to check
        _check_joint("slew", "slew_drive", sd, "slew_rate", initial.slew_rate, "rad/s", slew,
                     initial, horizon)
    if not (extension.held and initial.extension_rate == 0.0):
        _check_joint("extension", "extension_cylinder", crane.extension_cylinder,
                     "extension_rate", initial.extension_rate, "m/s", extension, initial, horizon)


def _check_boom(joint: str, cyl: Any, stroke: float, rate: float, drive: Any, initial: State,
                horizon: float) -> None:
    """A boom cylinder's initial stroke and rate, and its drive."""
    if not cyl.stroke_min <= stroke <= cyl.stroke_max:
        raise ValueError(f"State.{joint}_stroke must be in [{cyl.stroke_min}, {cyl.stroke_max}] m "
                         f"({joint}_cylinder.stroke_min/max), got {stroke}")
    if drive.held:
        if rate != 0.0:
            raise ValueError(f"State.{joint}_stroke_rate must be 0 for a held {joint} cylinder, "
                             f"got {rate}")
    elif type(drive) is not Pressure:
        _check_drive(joint, cyl.hydraulics, f"{joint}_cylinder", drive, initial, horizon)


def _check_joint(joint: str, actuator: str, act: Any, rate_name: str, rate: float, unit: str,
                 drive: Any, initial: State, horizon: float) -> None:
    """The slew's or the extension's drive: held from rest, or by an actuator the crane has."""
    if drive.held:
        if rate != 0.0:
            raise ValueError(f"State.{rate_name} must be 0 for a held {joint}, got {rate} {unit}")
        return
    if act is None:
        raise ValueError(f"Inputs.{joint}: the crane has no {actuator} (crane file), so its "
                         f"{joint} can only be held (Hold())")
    _check_drive(joint, act.hydraulics, actuator, drive, initial, horizon)


def _check_drive(joint: str, hydraulics: Any, actuator: str, drive: Any, initial: State,
                 horizon: float) -> None:
    """A joint's drive against the horizon, its actuator's circuit and the initial chambers."""
    if isinstance(drive, PressureSeries) and not drive.covers(horizon):
        raise ValueError(f"Inputs.{joint}: PressureSeries.t must cover [0, horizon] = [0, {horizon}] s, "
                         f"got [{drive.t[0]}, {drive.t[-1]}]")
    if isinstance(drive, _VALVES):
        if hydraulics is None:
            raise ValueError(f"Inputs.{joint}: a valve drive needs {actuator}.hydraulics "
                             "in the crane file")
        if isinstance(drive, ValveSeries) and not drive.covers(horizon):
            raise ValueError(f"Inputs.{joint}: ValveSeries.t must cover [0, horizon] = "
                             f"[0, {horizon}] s, got [{drive.t[0]}, {drive.t[-1]}]")
        for side in ("p_a", "p_b"):
            if getattr(initial, f"{joint}_{side}") is None:
                raise ValueError(f"State.{joint}_{side} is required for a valve-driven {joint} "
                                 f"({actuator}): pass the measured chamber pressures or start from "
                                 "cranepredict.state_at_rest(...)")


def predict(crane: Crane, initial: State, inputs: Inputs, horizon: float, *,
            dt: Optional[float] = None, sample_every: int = 1, backend: str = "c",
            method: str = "auto", tolerance: Optional[Tolerance] = None) -> Trajectory:
    """Predicts the crane's motion over ``horizon`` seconds from rest (or the given stroke rates).

    ``backend="c"`` runs the C core (the product); ``backend="python"`` runs the pure-Python twin,
    an independent implementation of the same model used to validate the core. All four joints
    move (lift, tilt, slew, extension; docs/model.md "Four joints"); a drive left out of
    ``inputs`` is held at the value in ``initial``. ``sample_every = m`` keeps only t = 0, every
    m-th step and the last step, as in :func:`predict_many` (the integration still takes every
    step). A call takes at most MAX_STEPS steps and returns at most MAX_SAMPLES samples (both
    checked before anything runs).

    ``method="auto"`` (the default) integrates with error control to ``tolerance`` (a
    :class:`Tolerance`; None: the default, within 0.25 mm of tip and 0.35 bar of a converged run on
    every named scenario) and samples every ``dt``: ``dt`` is where the samples are, not the step.
    It runs ROS34PW2 (``"rosw"``) where a drive is a valve or the telescope moves (stiff) and the
    explicit pair DOPRI5(4) (``"dopri5"``, not with a valve drive) elsewhere; either may be asked
    for by name. ``method="rk4"`` is fixed-step RK4 with step ``dt`` (docs/model.md,
    "Integration"). Raises ValueError/TypeError naming the field and its allowed range on bad
    input; the arguments are never modified.

    A valve-driven boom cylinder levered against a load that needs more than its supply pressure
    to hold is listed in ``Trajectory.supply_short`` and warned about (``warnings.warn``): levered
    against the load, the boom sinks.
    """
    method, tolerance = solver.check(method, tolerance)
    seconds, step, n_steps = _check_call(crane, horizon, DEFAULT_DT if dt is None else dt,
                                         sample_every, backend)
    _check_future(crane, initial, inputs, horizon)
    solver.check_inputs(method, inputs)
    short = _warn(crane, initial, inputs)
    run = _predict_c if backend == "c" else _predict_twin
    return run(crane, initial, inputs, seconds, step, n_steps, int(sample_every), method,
               tolerance, short)


_PRESSURES = (Pressure, PressureSeries)


def _warn(crane: Crane, initial: State, inputs: Inputs) -> Tuple[str, ...]:
    """predict()'s warnings (pressures that look like bar; boom cylinders whose supply cannot
    hold the load: returned, for Trajectory.supply_short), pointed at predict()'s caller."""
    lift, tilt = inputs.lift, inputs.tilt
    if isinstance(lift, _PRESSURES) or isinstance(tilt, _PRESSURES):
        for text in pressures_in_bar(crane, initial, inputs):
            warnings.warn(text, UserWarning, stacklevel=3)
    if not (isinstance(lift, _VALVES) or isinstance(tilt, _VALVES)):
        return ()
    short = supply_short(crane, initial, inputs)
    for joint, needed, supply in short:
        warnings.warn(f"Inputs.{joint}: holding the load at this pose takes {needed / 1e5:.1f} bar, "
                      f"more than the supply's {supply / 1e5:.1f} bar ({joint}_cylinder.hydraulics."
                      f"supply_pressure): levered against the load, the {joint} boom sinks",
                      UserWarning, stacklevel=3)
    return tuple(joint for joint, _, _ in short)


class _SampleFields:
    """name -> a Trajectory array (types.ARRAYS), as a read-only field view of the C core's
    samples, made on the first read of any (Trajectory._of_fields)."""

    __slots__ = ("_buffer", "_n", "_samples")

    def __init__(self, buffer: Optional[np.ndarray] = None, n: int = 0,
                 samples: Optional[np.ndarray] = None) -> None:
        self._buffer, self._n, self._samples = buffer, n, samples

    def __call__(self, name: str) -> np.ndarray:
        samples = self._samples
        if samples is None:
            samples = self._samples = _core_module().samples(self._buffer, self._n)
        return samples[_SAMPLE_FIELD.get(name, name)]


def _predict_c(crane: Crane, initial: State, inputs: Inputs, horizon: float, dt: float,
               n_steps: int, every: int, method: str, tolerance: Tolerance,
               short: Tuple[str, ...]) -> Trajectory:
    _core = _core_module()
    if every == 1:
        fields = _SampleFields(*_core.predict_buffer(crane, initial, inputs, horizon, dt,
                                                     n_steps + 1, method, tolerance))
    else:   # the C core thins the samples itself (no full-length buffer)
        batch = _core.predict_many(crane, [initial], [inputs], horizon, dt, every, 1, None,
                                   method, tolerance)
        batch.setflags(write=False)
        fields = _SampleFields(samples=batch[0])
    return Trajectory._of_fields(fields, "c", partial(_c_points, crane), _c_transmission(crane),
                                 short)


def _predict_twin(crane: Crane, initial: State, inputs: Inputs, horizon: float, dt: float,
                  n_steps: int, every: int, method: str, tolerance: Tolerance,
                  short: Tuple[str, ...]) -> Trajectory:
    from . import twin

    try:
        arrays = twin.simulate(crane, initial, inputs, horizon, dt, method=method,
                               tolerance=tolerance)
    except (OverflowError, ZeroDivisionError) as exc:
        raise ValueError(f"the twin's arithmetic failed ({exc}): a parameter of crane "
                         f"{crane.name!r} is beyond what a double can carry through the model "
                         "(check the crane file for absurd magnitudes)") from None
    if every > 1:
        rows = _kept_rows(n_steps, every)
        arrays = {k: np.ascontiguousarray(a[rows]) for k, a in arrays.items()}
    for a in arrays.values():
        a.setflags(write=False)

    def points(theta: np.ndarray, slew: np.ndarray, extension: np.ndarray) -> np.ndarray:
        return twin.points(crane, extension, slew, theta)

    def transmission(joint: int, stroke: float, extension: float) -> float:
        return twin.stroke_transmission(crane, joint, stroke, extension)

    return Trajectory(**arrays, backend="python", _points=points, _transmission=transmission,
                      supply_short=short)


def _sample_times(n_steps: int, horizon: float, dt: float, sample_every: int) -> np.ndarray:
    """The times of the kept samples (docs/model.md: t_k = k dt, the last one at the horizon), for
    a batch of no futures, whose arrays still have the batch's sample axis."""
    k = np.arange(0, n_steps + 1, sample_every, dtype=float)
    if k[-1] != n_steps:
        k = np.append(k, n_steps)
    t = k * dt
    t[-1] = horizon
    return t


def _c_transmission(crane: Crane) -> Any:
    """(joint, stroke, extension) -> ds/dtheta of a boom cylinder, by the C core."""
    return partial(_c_stroke_transmission, crane)


def _c_stroke_transmission(crane: Crane, joint: int, stroke: float, extension: float) -> float:
    return _core_module().joint_angle(crane, joint, stroke, extension)[1]


def _c_points(crane: Crane, theta: np.ndarray, slew: np.ndarray, extension: np.ndarray) -> np.ndarray:
    """The world positions of the crane's points at the poses of the samples, by the C core."""
    points = _core_module().points
    return _poses(lambda e, s, th: points(crane, e, s, th), theta, slew, extension)


def _poses(points: Any, theta: np.ndarray, slew: np.ndarray, extension: np.ndarray) -> np.ndarray:
    """points(extension, slew, theta rows) over runs of samples with the same slew and extension
    (one run when both are held)."""
    theta = np.asarray(theta, dtype=float).reshape(-1, 2)
    slew = np.broadcast_to(np.asarray(slew, dtype=float), theta.shape[:1])
    extension = np.broadcast_to(np.asarray(extension, dtype=float), theta.shape[:1])
    if theta.shape[0] == 0:
        return np.empty((0, len(POINT_NAMES), 3))
    change = np.flatnonzero((slew[1:] != slew[:-1]) | (extension[1:] != extension[:-1])) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change, [theta.shape[0]]))
    return np.concatenate([points(float(extension[a]), float(slew[a]), theta[a:b])
                           for a, b in zip(starts, ends)])


def state_at_rest(crane: Crane, lift_stroke: float, tilt_stroke: float, *, slew: float = 0.0,
                  extension: float = 0.0, lift_rod_pressure: Optional[float] = None,
                  tilt_rod_pressure: Optional[float] = None,
                  extension_rod_pressure: Optional[float] = None) -> State:
    """The crane at rest at the given pose, holding itself on closed valves (docs/model.md,
    "Static state at rest"): each actuator that has ``hydraulics`` gets the chamber pressures whose
    force balances gravity (friction taken as 0), the spool closed. The boom cylinders carry the
    booms' gravity torques; the extension cylinder the gravity component along the outer boom of
    the extension boom and the load; the slew drive no load (the slew axis is vertical: both
    chambers at the tank pressure).

    The chamber that does not carry the load is at the tank pressure (the rod side when the
    cylinder pushes, the bore side when it pulls), unless ``<joint>_rod_pressure`` (Pa) is given:
    then the rod side has that pressure and the bore side balances the load. Raises ValueError
    naming the field if the pose is out of range or the balance needs a pressure outside
    [CHAMBER_PRESSURE_MIN, PRESSURE_MAX].
    """
    from .types import CHAMBER_PRESSURE_MIN, PRESSURE_MAX

    if not isinstance(crane, Crane):
        raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
    base = State(lift_stroke=lift_stroke, tilt_stroke=tilt_stroke, slew=slew, extension=extension)
    _check_future(crane, base, Inputs(lift=Hold(), tilt=Hold()), 1.0)
    forces = holding_forces(crane, base.lift_stroke, base.tilt_stroke, base.extension)
    fields = {}
    actuators = [("lift", crane.lift_cylinder, lift_rod_pressure, forces[0]),
                 ("tilt", crane.tilt_cylinder, tilt_rod_pressure, forces[1])]
    if crane.slew_drive is not None and crane.slew_drive.hydraulics is not None:
        actuators.append(("slew", crane.slew_drive, None, 0.0))
    ec = crane.extension_cylinder
    if ec is not None and ec.hydraulics is not None:
        actuators.append(("extension", ec, extension_rod_pressure, _extension_holding_force(crane, base)))
    for joint, cyl, rod, force in actuators:
        hyd = cyl.hydraulics
        if rod is not None:
            p_b = _number(rod, f"{joint}_rod_pressure")
            p_a = (force + p_b * cyl.area_b) / cyl.area_a
        elif force >= 0.0:
            p_b = hyd.tank_pressure
            p_a = (force + p_b * cyl.area_b) / cyl.area_a
        else:
            p_a = hyd.tank_pressure
            p_b = (p_a * cyl.area_a - force) / cyl.area_b
        for side, p in (("p_a", p_a), ("p_b", p_b)):
            if not CHAMBER_PRESSURE_MIN <= p <= PRESSURE_MAX:
                raise ValueError(f"state_at_rest: holding the crane needs {joint} {side} = {p:g} Pa, "
                                 f"outside [{CHAMBER_PRESSURE_MIN:g}, {PRESSURE_MAX:g}] Pa "
                                 f"(check {joint}_rod_pressure)")
            if p > hyd.relief_pressure:
                name = "slew_drive" if joint == "slew" else \
                    "extension_cylinder" if joint == "extension" else f"{joint}_cylinder"
                raise ValueError(
                    f"state_at_rest: holding the crane at this pose with load_mass = "
                    f"{crane.load_mass:g} kg needs {joint} {side} = {p / 1e5:.1f} bar, above "
                    f"{name}.hydraulics.relief_pressure = {hyd.relief_pressure / 1e5:g} bar: the "
                    f"relief valve would open and the {joint} would sink; lighten the load or "
                    f"choose another pose")
        fields[f"{joint}_p_a"] = p_a
        fields[f"{joint}_p_b"] = p_b
    return State(lift_stroke=base.lift_stroke, tilt_stroke=base.tilt_stroke, slew=base.slew,
                 extension=base.extension, **fields)


def _extension_holding_force(crane: Crane, state: State) -> float:
    """The extension cylinder's force (N, positive extends) that holds the telescope still: the
    extension's generalized gravity force at rest (ds/de = 1), from the core's four-joint inverse
    dynamics (docs/model.md, "Four joints")."""
    _core = _core_module()
    q = (_core.joint_angle(crane, 0, state.lift_stroke, state.extension)[0],
         _core.joint_angle(crane, 1, state.tilt_stroke, state.extension)[0],
         state.slew, state.extension)
    return _core.inverse_dynamics(crane, q, (0.0,) * 4, (0.0,) * 4)[3]


def _sequence(value: Any, name: str, kind: type) -> list:
    """A list of ``value``'s items; TypeError naming the argument if it is not a sequence."""
    if isinstance(value, (str, bytes, kind)) or not hasattr(value, "__iter__"):
        raise TypeError(f"{name} must be a sequence of cranepredict.{kind.__name__}, "
                        f"got {type(value).__name__}")
    return list(value)


#: The crane-file fields :func:`predict_many` can vary per future (``vary``): the load, gravity,
#: and every number of each actuator's friction and hydraulics (``lift_cylinder``,
#: ``tilt_cylinder``, ``slew_drive``, ``extension_cylinder``; e.g.
#: ``"lift_cylinder.hydraulics.supply_pressure"``). The geometry and the bodies stay the crane's.
VARY_FIELDS = ("load_mass", "gravity") + tuple(
    f"{actuator}.{table}.{name}"
    for actuator in ("lift_cylinder", "tilt_cylinder", "slew_drive", "extension_cylinder")
    for table, names in (("friction", ("coulomb", "static", "viscous", "stribeck_velocity",
                                       "factor")),
                         ("hydraulics", ("supply_pressure", "tank_pressure", "relief_pressure",
                                         "nominal_flow", "nominal_pressure_drop", "dead_band",
                                         "meter_out_flow", "meter_out_pressure_drop",
                                         "spool_time_constant", "laminar_pressure_drop",
                                         "cavitation_pressure", "hose_volume_a", "hose_volume_b",
                                         "oil_bulk_modulus", "hose_bulk_modulus",
                                         "cylinder_bulk_modulus", "leakage")))
    for name in names)


def _check_vary(crane: Crane, vary: Any, f: int) -> Dict[str, np.ndarray]:
    """predict_many's ``vary``: names from VARY_FIELDS whose table the crane has, each with f
    finite numbers; returns name -> float64 array (copies: the caller's arrays are not kept)."""
    if not isinstance(vary, Mapping):
        raise TypeError(f"vary must be a mapping of crane-file field names to per-future values, "
                        f"got {type(vary).__name__}")
    out = {}
    for name, values in vary.items():
        if name not in VARY_FIELDS:
            raise ValueError(f"vary: {name!r} is not a field predict_many can vary per future; "
                             f"allowed: load_mass, gravity, <actuator>.friction.<field>, "
                             f"<actuator>.hydraulics.<number> (cranepredict.api.VARY_FIELDS)")
        node: Any = crane
        for part in name.split(".")[:-1]:
            node = getattr(node, part)
            if node is None:
                table = name.rpartition(".")[0]
                raise ValueError(f"vary: {name!r}: crane {crane.name!r} has no {table} table")
        try:
            a = np.array(values, dtype=np.float64)
        except (TypeError, ValueError):
            raise TypeError(f"vary[{name!r}] must be a sequence of {f} numbers") from None
        if a.shape != (f,):
            raise ValueError(f"vary[{name!r}] must have one value per future ({f}), got shape "
                             f"{a.shape}")
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError(f"future {bad[0]} (vary[{name!r}][{bad[0]}]): {name} must be finite, "
                             f"got {a[bad[0]]}")
        out[name] = a
    return out


def _cranes_per_future(crane: Crane, vary: Dict[str, np.ndarray], f: int) -> Any:
    """The crane_params of every future, each checked by the C core's crane_params_check (the one
    validator of a crane); an error names the future, the field, its rule and value."""
    from .crane import rule_error

    _core = _core_module()
    arr = _core.params_per_future(crane, vary, f)
    for k in range(f):
        status, code = _core.check_params(arr, k)
        if status:
            def value_of(name: str, k: int = k) -> Any:
                return vary[name][k] if name in vary else _value(crane, name)
            raise _core.CoreError(status, f"future {k} (vary): "
                                  f"{rule_error(status, code, value_of, crane.name)}")
    return arr


def _value(crane: Crane, dotted: str) -> Any:
    node: Any = crane
    for part in dotted.split("."):
        node = getattr(node, part)
    return node


def predict_many(crane: Crane, initials: Sequence[State], inputs_list: Sequence[Inputs],
                 horizon: float, *, dt: Optional[float] = None, sample_every: int = 1,
                 threads: Optional[int] = None,
                 vary: Optional[Mapping[str, Sequence[float]]] = None,
                 method: str = "auto", tolerance: Optional[Tolerance] = None) -> TrajectoryBatch:
    """Predicts many futures of one crane in one C call: future k from ``initials[k]`` under
    ``inputs_list[k]``, all over the same ``horizon`` with the same ``dt``.

    Returns a :class:`TrajectoryBatch` (arrays of shape (F, N, ...)); ``batch[k]`` equals
    ``predict(crane, initials[k], inputs_list[k], horizon, dt=dt)`` exactly at the kept samples.
    ``sample_every = m`` (1 <= m <= MAX_STEPS) keeps only t = 0, every m-th step and the last step
    (the integration still takes every step of size dt; only the output is thinned), which saves
    the memory and time of writing F x N samples when a coarser output is enough. Each future
    takes at most MAX_STEPS steps and the batch returns at most MAX_SAMPLES samples (F x N), both
    checked before anything runs; a long batch can be stopped with Ctrl-C. ``threads`` (default:
    2 on a machine with 2 or more cores, for batches of at least 2 x MIN_FUTURES_PER_THREAD
    futures) splits the batch into contiguous slices run in parallel; the C core itself stays
    single-threaded. Validation is predict()'s, per future; an error names the future's index.

    ``vary`` gives some of the crane's parameters per future without building a Crane per future:
    crane-file dotted names from VARY_FIELDS (the load, gravity, each actuator's friction and
    hydraulic numbers) mapped to one value per future, e.g. ``vary={"load_mass": masses}``; future
    k then runs the crane with those fields replaced by their k-th values, exactly as
    ``predict(crane_k, ...)`` with that crane would. Each future's crane is checked by the crane
    file's rules (an error names the future, the field and its range).
    """
    dt = DEFAULT_DT if dt is None else dt
    method, tolerance = solver.check(method, tolerance)
    n_steps = _check_shared(crane, horizon, dt, "c")[2]
    _check_sample_every(sample_every)
    initials = _sequence(initials, "initials", State)
    inputs_list = _sequence(inputs_list, "inputs_list", Inputs)
    if len(initials) != len(inputs_list):
        raise ValueError(f"initials and inputs_list must have the same length, got "
                         f"{len(initials)} and {len(inputs_list)}")
    if method == "dopri5":
        for k, one in enumerate(inputs_list):
            try:
                solver.check_inputs(method, one)
            except ValueError as e:
                raise ValueError(f"future {k} (inputs_list[{k}]): {e}") from None
    f = len(initials)
    per_future = kept_samples(n_steps, int(sample_every))
    if f * per_future > MAX_SAMPLES:
        raise ValueError(f"a batch must return at most {MAX_SAMPLES:,} samples (cranepredict.MAX_SAMPLES), "
                         f"got {f:,} futures x {per_future:,} samples (horizon {horizon:g} s, dt {dt:g} s, "
                         f"sample_every {sample_every}): raise sample_every, shorten the horizon, "
                         "take a larger dt or split the batch")
    for k, (initial, inputs) in enumerate(zip(initials, inputs_list)):
        try:
            _check_future(crane, initial, inputs, horizon)
        except (TypeError, ValueError) as e:
            raise type(e)(f"future {k} (initials[{k}], inputs_list[{k}]): {e}") from None
    per_future = None
    if vary is not None:
        per_future = _cranes_per_future(crane, _check_vary(crane, vary, f), f)
    if threads is None:
        threads = min(2, cores()) if f >= 2 * MIN_FUTURES_PER_THREAD else 1
    n_cores = cores()
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or \
            not 1 <= threads <= n_cores:
        raise ValueError(f"threads must be an int in [1, {n_cores}] (os.cpu_count(): more threads "
                         f"than cores only add memory and delay Ctrl-C), got {threads!r}")
    _core = _core_module()
    arrays = _sample_arrays(_core.predict_many(crane, initials, inputs_list, float(horizon),
                                               float(dt), int(sample_every), min(int(threads), max(f, 1)),
                                               per_future, method, tolerance))
    arrays["t"] = arrays["t"][0] if f else _sample_times(n_steps, float(horizon), float(dt),
                                                          int(sample_every))
    for a in arrays.values():
        a.setflags(write=False)
    return TrajectoryBatch(**arrays, backend="c", sample_every=int(sample_every),
                           _points=partial(_c_points, crane), _transmission=_c_transmission(crane))
