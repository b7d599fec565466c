"""How a future is integrated (docs/model.md, "Integration"): the method and its tolerances.

``method="auto"`` (the default) integrates with error control: it takes the steps the accuracy
needs and samples the future every ``dt`` by dense output, so ``dt`` is where the samples are, not
how the core steps. It picks the ROS34PW2 Rosenbrock-W method (``"rosw"``, stiffly stable) for a
stiff future (a valve drive's chambers, a moving telescope's friction) and Dormand and Prince's
explicit pair DOPRI5(4) (``"dopri5"``, fewer and longer steps) for the others. Either can be asked
for by name (``"dopri5"`` only without valve drives). ``method="rk4"`` is fixed-step RK4 with step
``dt`` (a fixed cost per call: what the embedded worst case is stated for).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Optional, Tuple

from ._checks import number

__all__ = ["METHODS", "Tolerance", "default_tolerance", "TIP_TOLERANCE_RANGE",
           "PRESSURE_TOLERANCE_RANGE"]

METHODS = ("auto", "rosw", "dopri5", "rk4")
#: The tolerances a user may ask for (crane_solver in csrc/crane.h; CRANE_E_METHOD outside).
TIP_TOLERANCE_RANGE = (1e-9, 1.0)
PRESSURE_TOLERANCE_RANGE = (1.0, 1e7)


@dataclass(frozen=True)
class Tolerance:
    """The error control's tolerances per step of the default method: ``tip`` in m of tip position
    (an angle's share is ``tip`` over the crane's reach), ``pressure`` in Pa of chamber pressure.
    None: the core's default (:func:`default_tolerance`)."""

    tip: Optional[float] = None
    pressure: Optional[float] = None

    def __post_init__(self) -> None:
        for name, unit, (lo, hi) in (("tip", "m", TIP_TOLERANCE_RANGE),
                                     ("pressure", "Pa", PRESSURE_TOLERANCE_RANGE)):
            value = getattr(self, name)
            if value is not None and not lo <= number(value, f"Tolerance.{name}") <= hi:
                raise ValueError(f"Tolerance.{name} must be in [{lo:g}, {hi:g}] {unit}, got {value}")


@lru_cache(maxsize=None)
def default_tolerance() -> Tolerance:
    """The default tolerances, as the C core defines them (crane_solver_default; asked once: a
    Tolerance is immutable)."""
    from ._cranepredict import ffi, lib

    s = ffi.new("crane_solver *")
    lib.crane_solver_default(s)
    return Tolerance(tip=float(s.tip_tolerance), pressure=float(s.pressure_tolerance))


def check(method: str, tolerance: Optional[Tolerance]) -> Tuple[str, Tolerance]:
    """The method and tolerance checked, the tolerance's defaults filled in."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if tolerance is not None and not isinstance(tolerance, Tolerance):
        raise TypeError(f"tolerance must be a cranepredict.Tolerance, got {type(tolerance).__name__}")
    default = default_tolerance()
    if tolerance is None:
        return method, default
    return method, Tolerance(tip=default.tip if tolerance.tip is None else float(tolerance.tip),
                             pressure=default.pressure if tolerance.pressure is None
                             else float(tolerance.pressure))


def check_inputs(method: str, inputs: object) -> None:
    """The explicit pair refuses a future with a valve drive (its chambers are stiff)."""
    if method != "dopri5":
        return
    from .types import Valve, ValveSeries

    for name in ("lift", "tilt", "slew", "extension"):
        if isinstance(getattr(inputs, name, None), (Valve, ValveSeries)):
            raise ValueError(f"method 'dopri5' is for futures without valve drives (inputs.{name} "
                             "is a valve): use method='auto' (the default) or 'rosw'")
