"""The live twin: the crane's sensors in, a verdict out, every control cycle (docs/live.md).

:class:`Measurement` (one cycle's sensor values and levers), :class:`Sensors` (what the crane
measures, how noisy, how often). The bus (:mod:`cranepredict.live.bus`) needs the ``live`` extra
(python-can, cantools); nothing here imports it until used.
"""

from .measurement import (MEASURABLE, Measurement, Sensor, Sensors, default_sensors, lever_values,
                          levers)

from .estimator import EKF, Estimator, InnovationFault
from .loop import LiveTwin, LiveVerdict

__all__ = ["LiveTwin", "LiveVerdict", "Estimator", "EKF", "InnovationFault", "Measurement", "Sensor", "Sensors", "default_sensors", "levers", "lever_values",
           "MEASURABLE"]
