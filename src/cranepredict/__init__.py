"""cranepredict: faster-than-real-time prediction of a hydraulic mobile crane's booms and load.

Data flow: crane file (TOML) -> :class:`Crane` -> :func:`predict` (C core, or the pure-Python twin
with ``backend="python"``) -> :class:`Trajectory` (numpy arrays) -> checks and plots.
"""

from .api import BACKENDS, DEFAULT_DT, predict, predict_many, state_at_rest
from .crane import Body, Crane, Cylinder, Friction, Geometry, Hydraulics
from .types import (POINT_NAMES, Hold, Inputs, Pressure, PressureSeries, State, Trajectory,
                    TrajectoryBatch, Valve, ValveSeries)
from . import scenarios

__all__ = ["predict", "predict_many", "TrajectoryBatch", "DEFAULT_DT", "BACKENDS", "Crane", "Body", "Cylinder", "Friction", "Geometry", "Hydraulics", "Valve", "ValveSeries", "state_at_rest",
           "State", "Pressure", "PressureSeries", "Hold", "Inputs", "Trajectory", "POINT_NAMES",
           "scenarios"]
__version__ = "0.1.0"
