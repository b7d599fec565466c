"""The one entry point: :func:`predict`."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from . import _core
from .crane import Crane
from .types import Hold, Inputs, PressureSeries, State, Trajectory

__all__ = ["predict", "DEFAULT_DT", "BACKENDS"]

#: Default RK4 step, s. Chosen by measured accuracy: see README ("Accuracy of the default step").
DEFAULT_DT = 1e-3

BACKENDS = ("c", "python")


def _check(crane: Crane, initial: State, inputs: Inputs, horizon: float, dt: float,
           backend: str) -> None:
    """Checks that need more than one argument, naming the field and the allowed range."""
    if not isinstance(crane, Crane):
        raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
    if not isinstance(initial, State):
        raise TypeError(f"initial must be a cranepredict.State, got {type(initial).__name__}")
    if not isinstance(inputs, Inputs):
        raise TypeError(f"inputs must be a cranepredict.Inputs, got {type(inputs).__name__}")
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
    for name, value in (("horizon", horizon), ("dt", dt)):
        if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
            raise TypeError(f"{name} must be a number, got {type(value).__name__}")
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and > 0 s, got {value}")
    if dt > horizon:
        raise ValueError(f"dt must be in (0, horizon] = (0, {horizon}] s, got {dt}")
    for joint, cyl, stroke, rate, drive in (
            ("lift", crane.lift_cylinder, initial.lift_stroke, initial.lift_stroke_rate, inputs.lift),
            ("tilt", crane.tilt_cylinder, initial.tilt_stroke, initial.tilt_stroke_rate, inputs.tilt)):
        if not cyl.stroke_min <= stroke <= cyl.stroke_max:
            raise ValueError(f"State.{joint}_stroke must be in [{cyl.stroke_min}, {cyl.stroke_max}] m "
                             f"({joint}_cylinder.stroke_min/max), got {stroke}")
        if isinstance(drive, Hold) and rate != 0.0:
            raise ValueError(f"State.{joint}_stroke_rate must be 0 for a held {joint} cylinder, got {rate}")
        if isinstance(drive, PressureSeries) and not drive.covers(horizon):
            raise ValueError(f"Inputs.{joint}: PressureSeries.t must cover [0, horizon] = [0, {horizon}] s, "
                             f"got [{drive.t[0]}, {drive.t[-1]}]")
    g = crane.geometry
    if not g.extension_min <= initial.extension <= g.extension_max:
        raise ValueError(f"State.extension must be in [{g.extension_min}, {g.extension_max}] m "
                         f"(geometry.extension_min/max), got {initial.extension}")


def predict(crane: Crane, initial: State, inputs: Inputs, horizon: float, *,
            dt: Optional[float] = None, backend: str = "c") -> Trajectory:
    """Predicts the crane's motion over ``horizon`` seconds from rest (or the given stroke rates).

    ``backend="c"`` runs the C core (the product); ``backend="python"`` runs the pure-Python twin,
    an independent implementation of the same model used to validate the core. Slew angle and
    extension stay as given in ``initial`` during the prediction. Raises ValueError/TypeError
    naming the field and its allowed range on bad input; the arguments are never modified.
    """
    dt = DEFAULT_DT if dt is None else dt
    _check(crane, initial, inputs, horizon, dt, backend)
    if backend == "c":
        s = _core.predict(crane, initial, inputs, float(horizon), float(dt))
        arrays = {k: np.ascontiguousarray(s[f]) for k, f in
                  (("t", "t"), ("strokes", "stroke"), ("theta", "theta"), ("omega", "omega"),
                   ("tip", "tip"), ("stop", "stop"))}

        def points(theta: np.ndarray) -> np.ndarray:
            return _core.points(crane, initial.extension, initial.slew, theta)
    else:
        from . import twin

        arrays = twin.simulate(crane, initial, inputs, float(horizon), float(dt))

        def points(theta: np.ndarray) -> np.ndarray:
            return twin.points(crane, initial.extension, initial.slew, theta)
    for a in arrays.values():
        a.setflags(write=False)
    return Trajectory(t=arrays["t"], strokes=arrays["strokes"], theta=arrays["theta"],
                      omega=arrays["omega"], tip=arrays["tip"], stop=arrays["stop"],
                      slew=initial.slew, extension=initial.extension, backend=backend,
                      _points=points)
