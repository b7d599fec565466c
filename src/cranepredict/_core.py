"""Thin layer over the C core: structs from dataclasses, status codes to exceptions.

Everything here is a translation; the model lives in csrc/. Input validation with the names of the
user's fields happens in api.py before the core is called; the core checks everything again and
:func:`ensure` turns any status it returns into an exception that says what was wrong.
"""

from __future__ import annotations

import dataclasses
import math
import os
import struct
import threading
from typing import TYPE_CHECKING, Any, Mapping, Sequence, Tuple

import numpy as np

from ._cranepredict import ffi, lib

from .types import Pressure, State

if TYPE_CHECKING:  # pragma: no cover
    from .crane import Crane
    from .types import Inputs

PRESSURE_MAX = float(lib.CRANE_PRESSURE_MAX)
N_POINTS = int(lib.CRANE_N_POINTS)

# What each status means in terms of the crane file / the call's arguments.
_CONTEXT = {
    lib.CRANE_E_GEOMETRY: "the lift triangle must keep the rod eye counterclockwise of the cylinder "
                          "base (0 < gamma < pi) over the whole lift stroke: check geometry.lift_pivot, "
                          "geometry.lift_cylinder_base, geometry.lift_cylinder_rod and "
                          "lift_cylinder.length_retracted/stroke_min/stroke_max",
    lib.CRANE_E_FOURBAR: "the tilt four-bar must close, with one sign of ds/dtheta, at every tilt "
                         "stroke in [tilt_cylinder.stroke_min, tilt_cylinder.stroke_max]: check "
                         "geometry.tilt_cylinder_base, link1_pivot, tilt_pivot, link_pin, link2_end, "
                         "link2_attach and tilt_cylinder.length_retracted",
}


class CoreError(ValueError):
    """The C core rejected an input; ``status`` is its crane_status code."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


def ensure(status: int, what: str) -> None:
    """Raises CoreError for any status but CRANE_OK, with the core's message and our context."""
    if status == lib.CRANE_OK:
        return
    message = ffi.string(lib.crane_status_message(status)).decode()
    extra = _CONTEXT.get(status)
    raise CoreError(status, f"{what}: {message}" + (f" ({extra})" if extra else ""))


# -- structs ----------------------------------------------------------------------------------

def _vec(dst: Any, v: Sequence[float]) -> None:
    dst.x, dst.y = v


def _body(dst: Any, body: Any) -> None:
    dst.mass, dst.izz = body.mass, body.izz
    _vec(dst.com, body.com)
    # a body known only by izz is slender along its x axis (docs/model.md, "Four joints")
    dst.ixx = 0.0 if body.ixx is None else body.ixx
    dst.iyy = body.izz if body.iyy is None else body.iyy
    dst.ixy = 0.0 if body.ixy is None else body.ixy


def _friction(dst: Any, f: Any) -> None:
    dst.coulomb, dst.static_, dst.viscous = f.coulomb, f.static, f.viscous
    dst.stribeck_velocity, dst.factor = f.stribeck_velocity, f.factor


def _hydraulics(hd: Any, h: Any) -> None:
    if h is None:
        hd.valve = lib.CRANE_VALVE_NONE
        return
    hd.valve = lib.CRANE_VALVE_COMPENSATED if h.valve == "compensated" else lib.CRANE_VALVE_ORIFICE
    for name in _HYDRAULIC_FIELDS:
        setattr(hd, name, getattr(h, name))


def _cylinder(dst: Any, cyl: Any) -> None:
    dst.bore, dst.rod, dst.length_retracted = cyl.bore, cyl.rod, cyl.length_retracted
    dst.stroke_min, dst.stroke_max = cyl.stroke_min, cyl.stroke_max
    _friction(dst.friction, cyl.friction)
    _hydraulics(dst.hydraulics, cyl.hydraulics)


def _actuators(prm: Any, crane: "Crane") -> None:
    """The slew drive and the extension cylinder (docs/model.md, "Four joints"), if the crane has
    them; `present` = 0 tells the core that the joint can only be held."""
    sd, ec = crane.slew_drive, crane.extension_cylinder
    prm.slew_drive.present = int(sd is not None)
    if sd is not None:
        d = prm.slew_drive
        d.bore, d.pinion_radius, d.slew_min, d.slew_max = sd.bore, sd.pinion_radius, sd.slew_min, sd.slew_max
        _friction(d.friction, sd.friction)
        _hydraulics(d.hydraulics, getattr(sd, "hydraulics", None))
    prm.extension_cylinder.present = int(ec is not None)
    if ec is not None:
        c = prm.extension_cylinder
        c.bore, c.rod = ec.bore, ec.rod
        _friction(c.friction, ec.friction)
        _hydraulics(c.hydraulics, getattr(ec, "hydraulics", None))


# crane_hydraulics fields besides valve: the same names as the crane file's
_HYDRAULIC_FIELDS = ("supply_pressure", "tank_pressure", "relief_pressure", "nominal_flow",
                     "nominal_pressure_drop", "dead_band", "meter_out_flow",
                     "meter_out_pressure_drop", "spool_time_constant", "laminar_pressure_drop",
                     "cavitation_pressure", "hose_volume_a", "hose_volume_b", "oil_bulk_modulus",
                     "hose_bulk_modulus", "cylinder_bulk_modulus", "leakage")


def _too_large(obj: Any, prefix: str = "") -> str:
    """The dotted name of the first int in a crane (dataclasses, pairs) too large for a double."""
    for f in dataclasses.fields(obj):
        value, name = getattr(obj, f.name), prefix + f.name
        if dataclasses.is_dataclass(value):
            found = _too_large(value, name + ".")
            if found:
                return found
        for i, v in enumerate(value if isinstance(value, tuple) else (value,)):
            if isinstance(v, int):
                try:
                    float(v)
                except OverflowError:
                    return f"{name}[{i}]" if isinstance(value, tuple) else name
    return ""


def _new_params(crane: "Crane") -> Any:
    """A new crane_params struct holding the crane's parameters."""
    try:
        return _fill_params(crane)
    except OverflowError:  # a crane built directly (the file loader converts its numbers)
        name = _too_large(crane) or "a number of the crane"
        raise ValueError(f"{name} must be a finite number, got an int too large for a float") from None


def _fill_params(crane: "Crane") -> Any:
    prm = ffi.new("crane_params *")
    g = crane.geometry
    prm.gravity = crane.gravity
    for name in ("lift_pivot", "lift_cylinder_base", "lift_cylinder_rod", "tilt_cylinder_base",
                 "link1_pivot", "tilt_pivot", "link_pin", "link2_end", "link2_attach",
                 "extension_mount"):
        _vec(getattr(prm, name), getattr(g, name))
    prm.tip_distance, prm.extension_min, prm.extension_max = g.tip_distance, g.extension_min, g.extension_max
    _body(prm.lift_boom, crane.lift_boom)
    _body(prm.outer_boom, crane.outer_boom)
    _body(prm.extension_boom, crane.extension_boom)
    _body(prm.side_link1, crane.side_link1)
    _body(prm.side_link2, crane.side_link2)
    prm.load_mass = crane.load_mass
    _cylinder(prm.cylinder[lib.CRANE_LIFT], crane.lift_cylinder)
    _cylinder(prm.cylinder[lib.CRANE_TILT], crane.tilt_cylinder)
    if crane.pillar is not None:   # else all zero: no pillar inertia
        _body(prm.pillar, crane.pillar)
    _actuators(prm, crane)
    return prm


# The one cache of derived structs: a Crane is immutable, so its crane_params and its crane_models
# (one per extension) are built once per Crane object. It is keyed by identity (the entry holds the
# crane, so its id is not reused while cached) and the models by the extension's exact bits, never
# by equality: -0.0 == 0.0, yet the sign of a zero in a point changes the branch of atan2 and so
# the angles (tests/test_bounds.py); an equality key would hand one crane another's struct. Identity
# is also cheaper: hashing a Crane (nested frozen dataclasses) costs microseconds per call.
_CACHE: dict = {}
_CACHE_MAX = 64


def _entry(crane: "Crane") -> Tuple[Any, Any, dict]:
    """(crane, crane_params *, {extension bits: crane_model *}) of a crane."""
    entry = _CACHE.get(id(crane))
    if entry is None or entry[0] is not crane:
        if len(_CACHE) >= _CACHE_MAX:
            _CACHE.clear()
        entry = (crane, _new_params(crane), {})
        _CACHE[id(crane)] = entry
    return entry


def _cached(crane: "Crane", extension: float) -> Tuple[Any, Any]:
    """(crane_params *, crane_model *) of a crane at an extension."""
    _, prm, models = _entry(crane)
    # By exact bits: only the zeros are two floats that compare equal (NaN never gets here).
    key: Any = extension if extension != 0.0 else ("-0" if math.copysign(1.0, extension) < 0 else "+0")
    m = models.get(key)
    if m is None:
        m = _keep_params(ffi.new("crane_model *"), prm)
        ensure(lib.crane_model_init(m, prm, extension), "crane")
        if len(models) < _CACHE_MAX:
            models[key] = m
    return prm, m


def _keep_params(m: Any, prm: Any) -> Any:
    """The model, holding its params alive: a crane_model points into its crane_params (crane.h),
    so a model handed out must outlive a cache clear that drops the params' other reference."""
    return ffi.gc(m, lambda _model, _params=prm: None)


def params(crane: "Crane") -> Any:
    """The crane_params struct of a crane (cached; no check of the crane)."""
    return _entry(crane)[1]


def model(crane: "Crane", extension: float) -> Any:
    """A crane_model (derived constants) for kinematics and dynamics queries (cached)."""
    return _cached(crane, extension)[1]


def check_crane(crane: "Crane") -> None:
    """The kinematic checks of a crane file (lift triangle, four-bar closing), by the C core."""
    m = ffi.new("crane_model *")
    ensure(lib.crane_model_init(m, _new_params(crane), crane.geometry.extension_min),
           f"crane {crane.name!r}")


def _sample_dtype() -> np.dtype:
    real = np.float64
    fields = [("t", real, ()), ("stroke", real, (2,)), ("theta", real, (2,)), ("omega", real, (2,)),
              ("slew", real, ()), ("extension", real, ()), ("slew_rate", real, ()),
              ("extension_rate", real, ()),
              ("tip", real, (3,)), ("stop", np.intc, (4,)), ("p_a", real, (4,)), ("p_b", real, (4,)),
              ("flow_a", real, (4,)), ("flow_b", real, (4,)), ("spool", real, (4,))]
    return np.dtype({
        "names": [f[0] for f in fields],
        "formats": [(f[1], f[2]) if f[2] else f[1] for f in fields],
        "offsets": [ffi.offsetof("crane_sample", f[0]) for f in fields],
        "itemsize": ffi.sizeof("crane_sample"),
    })


SAMPLE_DTYPE = _sample_dtype()


_OK = lib.CRANE_OK
_HOLD, _PRESSURE, _VALVE = lib.CRANE_DRIVE_HOLD, lib.CRANE_DRIVE_PRESSURE, lib.CRANE_DRIVE_VALVE


def _drive(dst: Any, drive: Any, keep: list) -> None:
    if drive.held:
        dst.mode = _HOLD
        return
    if type(drive) is Pressure:   # the common case first
        dst.mode = _PRESSURE
        dst.p_a, dst.p_b = drive.p_a, drive.p_b
        dst.n_samples = 0
        return
    if hasattr(drive, "u"):
        dst.mode = _VALVE
        if drive.t is None:
            dst.u = drive.u
            dst.n_samples = 0
            return
        arrays = [ffi.from_buffer("crane_real[]", np.ascontiguousarray(a, dtype=np.float64))
                  for a in (drive.t, drive.u)]
        keep.extend(arrays)
        dst.t, dst.u_samples = arrays
        dst.n_samples = len(drive.t)
        return
    dst.mode = _PRESSURE
    if drive.t is None:
        dst.p_a, dst.p_b = drive.p_a, drive.p_b
        dst.n_samples = 0
        return
    arrays = [ffi.from_buffer("crane_real[]", np.ascontiguousarray(a, dtype=np.float64))
              for a in (drive.t, drive.p_a, drive.p_b)]
    keep.extend(arrays)
    dst.t, dst.p_a_samples, dst.p_b_samples = arrays
    dst.n_samples = len(drive.t)


def sample_count(horizon: float, dt: float) -> int:
    n = ffi.new("size_t *")
    ensure(lib.crane_sample_count(horizon, dt, n), "horizon/dt")
    return int(n[0])


# crane_state is 20 crane_reals (doubles in this build), in this order: packed in one call.
_STATE_LAYOUT = (("stroke", 0), ("stroke_rate", 16), ("slew", 32), ("extension", 40),
                 ("slew_rate", 48), ("extension_rate", 56), ("p_a", 64), ("p_b", 96), ("spool", 128))
if ffi.sizeof("crane_real") != 8 or ffi.sizeof("crane_state") != 160 or any(
        ffi.offsetof("crane_state", name) != offset for name, offset in _STATE_LAYOUT):
    raise ImportError("crane_state's layout differs from _core._STATE_LAYOUT (csrc/crane.h changed): "
                      "update _state_bytes")
_STATE_PACK = struct.Struct("=20d").pack


def _state_bytes(s: State) -> bytes:
    """The crane_state of a State, as its bytes. Chamber pressures: only a valve-driven actuator
    reads them (api.py demands them there); one not given is 0."""
    return _STATE_PACK(s.lift_stroke, s.tilt_stroke, s.lift_stroke_rate, s.tilt_stroke_rate,
                       s.slew, s.extension, s.slew_rate, s.extension_rate,
                       s.lift_p_a or 0.0, s.tilt_p_a or 0.0, s.slew_p_a or 0.0,
                       s.extension_p_a or 0.0,
                       s.lift_p_b or 0.0, s.tilt_p_b or 0.0, s.slew_p_b or 0.0,
                       s.extension_p_b or 0.0,
                       s.lift_spool, s.tilt_spool, s.slew_spool, s.extension_spool)


# What _state takes as 0 from an object that is not a State and lacks it.
_STATE_OPTIONAL = frozenset(["slew_rate", "extension_rate"] + [
    f"{joint}_{name}" for joint in ("lift", "tilt", "slew", "extension")
    for name in ("p_a", "p_b", "spool")])


class _StateLike:
    """A State's attributes of any object (tests, tools): those in _STATE_OPTIONAL default to 0."""

    def __init__(self, obj: Any) -> None:
        self._obj = obj

    def __getattr__(self, name: str) -> Any:
        return getattr(self._obj, name, 0.0) if name in _STATE_OPTIONAL else getattr(self._obj, name)


def _state(dst: Any, state: Any) -> None:
    """Fills a crane_state (a pointer to one, or an element of a crane_state[]) from a State or an
    object with its attribute names (_StateLike)."""
    ptr = dst if ffi.typeof(dst).kind == "pointer" else ffi.addressof(dst)
    ffi.memmove(ptr, _state_bytes(state if isinstance(state, State) else _StateLike(state)), 160)


_JOINT_INDEX = (lib.CRANE_LIFT, lib.CRANE_TILT, lib.CRANE_SLEW, lib.CRANE_EXTENSION)


def _inputs(dst: Any, inputs: "Inputs", keep: list) -> None:
    """Fills a zeroed crane_inputs (as ffi.new makes it), whose zero drives are holds: a held
    drive is left as it is. ``keep`` receives what must outlive the call (sampled drives'
    buffers)."""
    drives = dst.drive
    for j, drive in zip(_JOINT_INDEX, (inputs.lift, inputs.tilt, inputs.slew, inputs.extension)):
        if not drive.held:
            _drive(drives[j], drive, keep)


def solver(dst: Any, method: str, tolerance: Any) -> None:
    """crane_inputs.solver from a checked method and Tolerance (solver.check); a tolerance of
    None (or None fields) leaves the core's default (0)."""
    s = dst.solver
    s.method = {"auto": lib.CRANE_METHOD_DEFAULT, "rosw": lib.CRANE_METHOD_ROSW,
                "dopri5": lib.CRANE_METHOD_DOPRI5, "rk4": lib.CRANE_METHOD_RK4}[method]
    if tolerance is not None:
        s.tip_tolerance = tolerance.tip or 0.0
        s.pressure_tolerance = tolerance.pressure or 0.0


SAMPLE_SIZE = ffi.sizeof("crane_sample")


_THREAD = threading.local()   # .work: this thread's crane_work


def work() -> Any:
    """This thread's crane_work, the predictions' working storage (crane.h): made at its first
    prediction and kept, as a call needs no initialised storage and two calls of one thread never
    overlap."""
    w = getattr(_THREAD, "work", None)
    if w is None:
        w = _THREAD.work = ffi.new("crane_work *")
    return w


def predict_buffer(crane: "Crane", state: "State", inputs: "Inputs", horizon: float, dt: float,
                   n: int, method: str = "auto", tolerance: Any = None) -> Tuple[np.ndarray, int]:
    """Runs crane_predict_model with the crane's cached model (the samples of crane_predict,
    without re-deriving the crane on every call) into a new buffer of ``n`` samples (the count
    crane_sample_count gives); returns the buffer, read-only (bytes: ``samples`` views them as
    SAMPLE_DTYPE), and the number of samples written."""
    m = _cached(crane, state.extension)[1]
    s = ffi.new("crane_state *")
    ffi.memmove(s, _state_bytes(state), 160)
    inp = ffi.new("crane_inputs *")
    keep: list = []
    _inputs(inp, inputs, keep)
    solver(inp, method, tolerance)
    out = np.empty(n * SAMPLE_SIZE, dtype=np.uint8)
    written = ffi.new("size_t *")
    status = lib.crane_predict_model(m, s, inp, horizon, dt, ffi.from_buffer("crane_sample[]", out),
                                     n, written, work())
    if status != _OK:
        ensure(status, "predict")
    out.setflags(write=False)
    return out, int(written[0])


def samples(buffer: np.ndarray, n: int) -> np.ndarray:
    """The first n samples of a predict_buffer buffer as a structured array (SAMPLE_DTYPE; a view,
    read-only like the buffer)."""
    return np.ndarray((n,), SAMPLE_DTYPE, buffer)


def predict(crane: "Crane", state: "State", inputs: "Inputs", horizon: float,
            dt: float, method: str = "auto", tolerance: Any = None) -> np.ndarray:
    """predict_buffer with the sample count of horizon and dt; returns the samples as a read-only
    structured array (SAMPLE_DTYPE)."""
    return samples(*predict_buffer(crane, state, inputs, horizon, dt, sample_count(horizon, dt),
                                   method, tolerance))


def sample_count_every(horizon: float, dt: float, sample_every: int) -> int:
    n = ffi.new("size_t *")
    ensure(lib.crane_sample_count_every(horizon, dt, sample_every, n), "horizon/dt/sample_every")
    return int(n[0])


#: Work per C call of predict_many, in steps (futures x steps each): 0.04 s on a desktop core,
#: about 0.4 s with valve substeps. Python sees Ctrl-C only between C calls, so a batch stops
#: within about that. A chunk the core refuses because its substeps take it over
#: CRANE_MAX_BATCH_STEPS (counted at their bound, before anything runs) is split in two.
CHUNK_STEPS = 250_000


# -- a crane per future (predict_many's vary) ------------------------------------------------------

_ACTUATORS = {"lift_cylinder": ("cylinder", 0), "tilt_cylinder": ("cylinder", 1),
              "slew_drive": ("slew_drive",), "extension_cylinder": ("extension_cylinder",)}
_FRICTION_FIELDS = ("coulomb", "static", "viscous", "stribeck_velocity", "factor")


def _vary_paths() -> dict:
    """Crane-file dotted name -> its path in crane_params, for every field predict_many may vary
    per future: the load, gravity, and each actuator's friction and hydraulic numbers (neither
    changes the geometry the Python checks and the guard read from the crane)."""
    paths: dict = {"load_mass": ("load_mass",), "gravity": ("gravity",)}
    for actuator, path in _ACTUATORS.items():
        for name in _FRICTION_FIELDS:
            paths[f"{actuator}.friction.{name}"] = path + ("friction", "static_" if name == "static" else name)
        for name in _HYDRAULIC_FIELDS:
            paths[f"{actuator}.hydraulics.{name}"] = path + ("hydraulics", name)
    return paths


VARY_PATHS = _vary_paths()


def params_per_future(crane: "Crane", vary: Mapping[str, np.ndarray], n: int) -> Any:
    """A crane_params[n]: the crane's parameters with vary's fields (dotted name -> n values) set
    per future. Unchecked (crane_params_check does that, per future)."""
    base = params(crane)
    size = ffi.sizeof("crane_params")
    arr = ffi.new("crane_params[]", max(n, 1))
    raw = np.frombuffer(ffi.buffer(arr), dtype=np.uint8).reshape(-1, size)
    raw[:] = np.frombuffer(ffi.buffer(base), dtype=np.uint8)
    for name, values in vary.items():
        offset = ffi.offsetof("crane_params", *VARY_PATHS[name])
        column = np.ndarray((n,), dtype=np.float64, buffer=ffi.buffer(arr), offset=offset,
                            strides=(size,))
        column[:] = values
    return arr


def check_params(arr: Any, k: int) -> Tuple[int, int]:
    """crane_params_check of arr[k]: (status, crane_field code)."""
    field = ffi.new("crane_field *")
    status = lib.crane_params_check(arr + k, field)
    return int(status), int(field[0])


_WORKERS: list = []          # [ThreadPoolExecutor], made at the first threaded batch
_WORKERS_LOCK = threading.Lock()


def _forget_workers() -> None:
    """In a forked child: the parent's worker threads do not exist there, and an executor that
    believes it has idle ones would queue the slices for nobody. The child makes its own."""
    global _WORKERS_LOCK
    _WORKERS.clear()
    _WORKERS_LOCK = threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_workers)


def _workers() -> Any:
    """The worker threads of threaded batches, started once and kept: starting a thread per slice
    cost about 0.2 ms a batch, a tenth of a guard's verdict that predicts its stops in batches.
    Slices beyond its size wait for a free worker (each is independent of the others)."""
    from concurrent.futures import ThreadPoolExecutor
    with _WORKERS_LOCK:
        if not _WORKERS:
            _WORKERS.append(ThreadPoolExecutor(max_workers=64, thread_name_prefix="cranepredict"))
        return _WORKERS[0]


def _run_chunk(*args: Any) -> int:
    """One crane_predict_many call (a seam for the tests, which interrupt between chunks)."""
    return lib.crane_predict_many(*args)


def predict_many(crane: "Crane", states: Sequence["State"], inputs: Sequence["Inputs"],
                 horizon: float, dt: float, sample_every: int, threads: int,
                 per_future: Any = None, method: str = "auto", tolerance: Any = None) -> np.ndarray:
    """Runs crane_predict_many; returns the samples as a (F, N) structured array (SAMPLE_DTYPE).
    ``per_future``: a crane_params[F] (params_per_future), one crane per future; None: the crane's.

    The batch is cut into chunks of about CHUNK_STEPS steps, one crane_predict_many call each, so
    that Ctrl-C stops it between chunks. With threads > 1 the batch is first cut into that many
    contiguous slices, each run chunk by chunk in its own thread: cffi releases the GIL during the
    call, so the slices run on separate cores. The first error stops every slice at its next chunk.
    """
    prm, _ = _cached(crane, states[0].extension if len(states) else 0.0)
    f = len(states)
    st = ffi.new("crane_state[]", max(f, 1))
    inp = ffi.new("crane_inputs[]", max(f, 1))
    keep: list = []
    for k in range(f):
        _state(st[k], states[k])
        _inputs(inp[k], inputs[k], keep)
        solver(inp[k], method, tolerance)
    n = sample_count_every(horizon, dt, sample_every)
    out = np.empty((f, n), dtype=SAMPLE_DTYPE)
    if f == 0:
        return out
    base = ffi.cast("crane_sample *", ffi.from_buffer(out))
    per_call = max(1, CHUNK_STEPS // (sample_count(horizon, dt) - 1))
    threads = max(1, min(int(threads), f))
    bounds = [f * i // threads for i in range(threads + 1)]
    errors: list = []  # (status, index of the failed future, or f for a shared argument)
    stop = threading.Event()
    done = [threading.Event() for _ in range(threads)]

    def run(i: int) -> None:
        try:
            failed = ffi.new("size_t *")
            lo, size = bounds[i], per_call
            while lo < bounds[i + 1]:
                if stop.is_set():
                    return
                hi = min(bounds[i + 1], lo + size)
                if per_future is None:
                    cranes, n_cranes = prm, 1
                else:
                    cranes, n_cranes = per_future + lo, hi - lo
                status = _run_chunk(cranes, n_cranes, hi - lo, st + lo, inp + lo, horizon, dt,
                                    sample_every, base + lo * n, n, failed, work())
                if status == lib.CRANE_E_BATCH and hi - lo > 1:
                    size = max(1, (hi - lo) // 2)   # refused before it ran: nothing written
                    continue
                if status != lib.CRANE_OK:
                    k = int(failed[0])
                    errors.append((status, lo + k if k < hi - lo else f))
                    stop.set()
                    return
                lo = hi
        finally:
            done[i].set()

    # The workers write into `out` through raw pointers: this call must not return or raise before
    # they have finished. Their own events are waited for, not Thread.join(): a join interrupted by
    # Ctrl-C marks a running thread as stopped (bpo-45274's clean-up) and then returns at once.
    started = []
    jobs = []
    try:
        pool = _workers() if threads > 1 else None
        for i in range(1, threads):
            jobs.append(pool.submit(run, i))
            started.append(i)
        run(0)
        for i in started:
            done[i].wait()
    except BaseException:  # Ctrl-C here (running or waiting): the others stop at their next chunk
        stop.set()
        for i in started:
            while not done[i].is_set():
                try:
                    done[i].wait()
                except KeyboardInterrupt:  # a second Ctrl-C: the first is raised once they stop
                    pass
        raise
    for job in jobs:
        job.result()    # an exception raised in a worker is raised here
    for status, k in sorted(errors, key=lambda e: e[1]):
        _ensure_many(status, k, f)
    return out


def _ensure_many(status: int, failed: int, n_futures: int) -> None:
    ensure(status, f"predict_many (future {failed})" if failed < n_futures else "predict_many")


def points(crane: "Crane", extension: float, slew: float, theta: np.ndarray) -> np.ndarray:
    """World positions (N, CRANE_N_POINTS, 3) of the crane's points at the poses theta (N, 2)."""
    th = np.ascontiguousarray(theta, dtype=np.float64).reshape(-1, 2)
    xyz = np.empty((th.shape[0], N_POINTS, 3))
    ensure(lib.crane_points(model(crane, extension), slew, th.shape[0],
                            ffi.cast("crane_real *", ffi.from_buffer(th)),
                            ffi.cast("crane_real *", ffi.from_buffer(xyz))), "points")
    return xyz


# -- single queries (tests, tools) ----------------------------------------------------------------

def joint_angle(crane: "Crane", joint: int, stroke: float, extension: float = 0.0) -> Tuple[float, float]:
    th, ds = ffi.new("crane_real *"), ffi.new("crane_real *")
    ensure(lib.crane_joint_angle(model(crane, extension), joint, stroke, th, ds), "joint_angle")
    return float(th[0]), float(ds[0])


def joint_stroke(crane: "Crane", joint: int, theta: float, extension: float = 0.0) -> float:
    s = ffi.new("crane_real *")
    ensure(lib.crane_joint_stroke(model(crane, extension), joint, theta, s), "joint_stroke")
    return float(s[0])


def inverse_dynamics(crane: "Crane", q: Sequence[float], qd: Sequence[float],
                     qdd: Sequence[float]) -> Tuple[float, float, float, float]:
    """The generalized forces [lift, tilt, slew, extension] (N m, N m, N m, N) at q = (theta0,
    theta1, slew, extension), rates qd and accelerations qdd, gravity included."""
    tau = ffi.new("crane_real[4]")
    ensure(lib.crane_inverse_dynamics(model(crane, q[3]), list(q), list(qd), list(qdd), tau),
           "inverse_dynamics")
    return float(tau[0]), float(tau[1]), float(tau[2]), float(tau[3])


def cylinder_force(crane: "Crane", joint: int, p_a: float, p_b: float, stroke_rate: float) -> float:
    f = ffi.new("crane_real *")
    ensure(lib.crane_cylinder_force(model(crane, crane.geometry.extension_min), joint, p_a, p_b,
                                    stroke_rate, f), "cylinder_force")
    return float(f[0])
