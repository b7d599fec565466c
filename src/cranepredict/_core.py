"""Thin layer over the C core: structs from dataclasses, status codes to exceptions.

Everything here is a translation; the model lives in csrc/. Input validation with the names of the
user's fields happens in api.py before the core is called; the core checks everything again and
:func:`ensure` turns any status it returns into an exception that says what was wrong.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING, Any, Sequence, Tuple

import numpy as np

from ._cranepredict import ffi, lib

if TYPE_CHECKING:  # pragma: no cover
    from .crane import Crane
    from .types import Inputs, State

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


def _cylinder(dst: Any, cyl: Any) -> None:
    dst.bore, dst.rod, dst.length_retracted = cyl.bore, cyl.rod, cyl.length_retracted
    dst.stroke_min, dst.stroke_max = cyl.stroke_min, cyl.stroke_max
    f = cyl.friction
    dst.friction.coulomb, dst.friction.static_, dst.friction.viscous = f.coulomb, f.static, f.viscous
    dst.friction.stribeck_velocity, dst.friction.tanh_velocity = f.stribeck_velocity, f.tanh_velocity


@functools.lru_cache(maxsize=64)
def params(crane: "Crane") -> Any:
    """The crane_params struct of a crane (cached: a Crane is immutable)."""
    p = ffi.new("crane_params *")
    g = crane.geometry
    p.gravity = crane.gravity
    for name in ("lift_pivot", "lift_cylinder_base", "lift_cylinder_rod", "tilt_cylinder_base",
                 "link1_pivot", "tilt_pivot", "link_pin", "link2_end", "link2_attach",
                 "extension_mount"):
        _vec(getattr(p, name), getattr(g, name))
    p.tip_distance, p.extension_min, p.extension_max = g.tip_distance, g.extension_min, g.extension_max
    _body(p.lift_boom, crane.lift_boom)
    _body(p.outer_boom, crane.outer_boom)
    _body(p.extension_boom, crane.extension_boom)
    p.load_mass = crane.load_mass
    _cylinder(p.cylinder[lib.CRANE_LIFT], crane.lift_cylinder)
    _cylinder(p.cylinder[lib.CRANE_TILT], crane.tilt_cylinder)
    return p


@functools.lru_cache(maxsize=64)
def model(crane: "Crane", extension: float) -> Any:
    """A crane_model (derived constants) for kinematics and dynamics queries."""
    m = ffi.new("crane_model *")
    ensure(lib.crane_model_init(m, params(crane), extension), "crane")
    return m


def check_crane(crane: "Crane") -> None:
    """The kinematic checks of a crane file (lift triangle, four-bar closing), by the C core."""
    m = ffi.new("crane_model *")
    ensure(lib.crane_model_init(m, params(crane), crane.geometry.extension_min), f"crane {crane.name!r}")


def _sample_dtype() -> np.dtype:
    real = np.float64
    fields = [("t", real, ()), ("stroke", real, (2,)), ("theta", real, (2,)), ("omega", real, (2,)),
              ("tip", real, (3,)), ("stop", np.intc, (2,))]
    return np.dtype({
        "names": [f[0] for f in fields],
        "formats": [(f[1], f[2]) if f[2] else f[1] for f in fields],
        "offsets": [ffi.offsetof("crane_sample", f[0]) for f in fields],
        "itemsize": ffi.sizeof("crane_sample"),
    })


SAMPLE_DTYPE = _sample_dtype()


def _drive(dst: Any, drive: Any, keep: list) -> None:
    if drive.held:
        dst.mode = lib.CRANE_DRIVE_HOLD
        return
    dst.mode = lib.CRANE_DRIVE_PRESSURE
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


def predict(crane: "Crane", state: "State", inputs: "Inputs", horizon: float,
            dt: float) -> np.ndarray:
    """Runs crane_predict; returns the samples as a structured array (SAMPLE_DTYPE)."""
    s = ffi.new("crane_state *")
    s.stroke = (state.lift_stroke, state.tilt_stroke)
    s.stroke_rate = (state.lift_stroke_rate, state.tilt_stroke_rate)
    s.slew, s.extension = state.slew, state.extension
    inp = ffi.new("crane_inputs *")
    keep: list = []
    _drive(inp.drive[lib.CRANE_LIFT], inputs.lift, keep)
    _drive(inp.drive[lib.CRANE_TILT], inputs.tilt, keep)
    n = sample_count(horizon, dt)
    out = np.empty(n, dtype=SAMPLE_DTYPE)
    written = ffi.new("size_t *")
    ensure(lib.crane_predict(params(crane), s, inp, horizon, dt,
                             ffi.cast("crane_sample *", ffi.from_buffer(out)), n, written),
           "predict")
    return out[: written[0]]


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


def inverse_dynamics(crane: "Crane", extension: float, theta: Sequence[float],
                     omega: Sequence[float], alpha: Sequence[float]) -> Tuple[float, float]:
    tau = ffi.new("crane_real[2]")
    ensure(lib.crane_inverse_dynamics(model(crane, extension), list(theta), list(omega),
                                      list(alpha), tau), "inverse_dynamics")
    return float(tau[0]), float(tau[1])


def cylinder_force(crane: "Crane", joint: int, p_a: float, p_b: float, stroke_rate: float) -> float:
    f = ffi.new("crane_real *")
    ensure(lib.crane_cylinder_force(model(crane, crane.geometry.extension_min), joint, p_a, p_b,
                                    stroke_rate, f), "cylinder_force")
    return float(f[0])
