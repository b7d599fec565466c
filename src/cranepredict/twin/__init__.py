"""Pure-Python twin of the fast crane model (docs/model.md).

The twin exists to validate the C core: it is written from the same specification but shares no
code with it, so an error in one shows up as a disagreement with the other.  It follows
docs/model.md step by step (kinematics, iterative Newton-Euler with the side links' share by
virtual work, smooth Stribeck friction, RK4 with impacts and releases located inside a step) and is
deliberately plain: Python floats and ``math`` in the hot path,
because for 2x2 algebra they are faster than numpy; numpy only builds the output arrays.

Index 0 is the lift joint/cylinder, index 1 the tilt joint/cylinder.  Angles are in the boom plane
(x outward, y up); world coordinates are X, Y horizontal and Z up.

The modules follow the C core's files (csrc/):

- ``kinematics``: the lift triangle, the tilt four-bar and its side links, the crane's points;
- ``dynamics``: Newton-Euler inverse dynamics, mass matrix and forward dynamics;
- ``cylinder``: piston areas, the friction law, actuator forces, the equivalent cylinders;
- ``hydraulics``: the valve's flows, the chamber equations, relief and anti-cavitation, substeps;
- ``model``: TwinModel, every constant of a prediction derived once from the crane;
- ``integrator``: the RK4 step, substeps, end-stop impacts and releases;
- ``predict``: the drives and the work bound of a prediction, its samples (``simulate``);
- ``_internal``: joint indices, the state's layout, plane vectors, the drives' interpolation.

A constant is read where it is defined: to change one in a test, patch that module
(``twin.hydraulics.SUBSTEP_STABILITY``), not this package.
"""

from __future__ import annotations

from ..types import POINT_NAMES
from ._internal import EXTENSION, JOINTS, LIFT, SLEW, TILT, _PressureDrive
from .integrator import _Prediction
from .kinematics import _circle
from .model import TwinModel
from .predict import _run, points, simulate, stroke_transmission

__all__ = ["POINT_NAMES", "TwinModel", "simulate", "points", "stroke_transmission", "LIFT", "TILT",
           "SLEW", "EXTENSION", "JOINTS",
           # for the tests: one prediction with its impacts, its parts, the four-bar's circles
           "_run", "_Prediction", "_PressureDrive", "_circle"]
