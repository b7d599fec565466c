"""cranepredict: faster-than-real-time prediction of a hydraulic mobile crane's booms and load.

Data flow: crane file (TOML) -> :class:`Crane` -> :func:`predict` (C core, or the pure-Python twin
with ``backend="python"``) -> :class:`Trajectory` (numpy arrays) -> checks and plots.
"""

from ._checks import MAX_SAMPLES, MAX_STEPS
from .api import BACKENDS, DEFAULT_DT, predict, predict_many, state_at_rest
from .crane import Body, Crane, Cylinder, Friction, Geometry, Hydraulics
from .solver import METHODS, Tolerance, default_tolerance
from .statics import holding_pressure
from .types import (POINT_NAMES, STROKE_RATE_MAX, Hold, Inputs, Pressure, PressureSeries, State,
                    Trajectory, TrajectoryBatch, Valve, ValveSeries)
from . import scenarios
from .guard import Contact, StopAnalysis, Verdict, guard, stop_inputs
from .shape import Part, Shape
from .world import Obstacle, World
from . import worlds
from .uncertainty import Study, SweepResult, sweep
from . import studies
from .live import EKF, Estimator, LiveTwin, LiveVerdict, Measurement, Sensor, Sensors

__all__ = ["predict", "predict_many", "TrajectoryBatch", "DEFAULT_DT", "BACKENDS", "MAX_STEPS",
           "MAX_SAMPLES", "STROKE_RATE_MAX", "Crane", "Body", "Cylinder", "Friction", "Geometry",
           "Hydraulics", "Valve", "ValveSeries", "state_at_rest",
           "State", "Pressure", "PressureSeries", "Hold", "Inputs", "Trajectory", "POINT_NAMES",
           "scenarios", "holding_pressure", "guard", "Verdict", "Contact", "StopAnalysis",
           "stop_inputs", "Shape", "Part", "World", "Obstacle", "worlds", "sweep", "Study", "SweepResult",
           "studies",
           "Measurement", "Sensor", "Sensors", "LiveTwin", "LiveVerdict", "Estimator", "EKF",
           "METHODS", "Tolerance", "default_tolerance"]
__version__ = "0.1.0"
