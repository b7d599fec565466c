"""A Measurement holds what the crane's sensors report, under the State's names, checked like a
State; a Sensors configuration says what is measured, how noisy and how often."""

from __future__ import annotations

import dataclasses

import pytest

import cranepredict as cp
from cranepredict.live import MEASURABLE, Sensor, Sensors, default_sensors, levers


def test_measurement_uses_the_state_field_names_and_none_for_the_unmeasured():
    state_fields = {f.name for f in dataclasses.fields(cp.State)}
    assert set(MEASURABLE) == state_fields
    m = cp.Measurement(t=0.5, lift_stroke=0.2, tilt_p_a=50e5, inputs=levers(lift=0.3))
    assert m.lift_stroke == 0.2 and m.tilt_stroke is None and m.extension is None
    assert m.values() == {"lift_stroke": 0.2, "tilt_p_a": 50e5}
    assert m.predicted_inputs is m.inputs
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.lift_stroke = 0.3  # type: ignore[misc]


def test_the_request_is_what_the_future_is_predicted_under():
    m = cp.Measurement(t=0.0, inputs=levers(), request=levers(lift=1.0))
    assert m.predicted_inputs.lift.u == 1.0 and m.inputs.lift.u == 0.0


@pytest.mark.parametrize("kwargs, exc, words", [
    (dict(t=float("nan")), ValueError, "Measurement.t must be finite"),
    (dict(t="0"), TypeError, "Measurement.t must be a number"),
    (dict(lift_stroke=float("inf")), ValueError, "Measurement.lift_stroke must be finite"),
    (dict(lift_p_a=2e8), ValueError, "Measurement.lift_p_a must be in [-100000, 1e+08] Pa"),
    (dict(tilt_p_b=-2e5), ValueError, "Measurement.tilt_p_b must be in"),
    (dict(slew_rate=11.0), ValueError, "Measurement.slew_rate must be in [-10, 10] rad/s"),
    (dict(lift_spool=1.5), ValueError, "Measurement.lift_spool must be in [-1, 1]"),
    (dict(extension=True), TypeError, "Measurement.extension must be a number"),
    (dict(inputs=None), TypeError, "Measurement.inputs must be a cranepredict.Inputs"),
    (dict(request=(0, 0)), TypeError, "Measurement.request must be a cranepredict.Inputs"),
])
def test_bad_measurements_name_the_field(kwargs, exc, words):
    args = dict(t=0.0, inputs=levers(), **{k: v for k, v in kwargs.items() if k not in ("t", "inputs")})
    args.update({k: v for k, v in kwargs.items() if k in ("t", "inputs")})
    with pytest.raises(exc) as e:
        cp.Measurement(**args)
    assert words in str(e.value)


def test_the_default_sensors_and_a_missing_one():
    s = default_sensors()
    assert s.fields[:4] == ("lift_stroke", "tilt_stroke", "slew", "extension")
    assert len(s.fields) == 12 and s["lift_p_a"].std == 2e5 and s["lift_stroke"].std == 2e-4
    assert s["lift_stroke"].max_age == pytest.approx(0.03)          # three periods at 100 Hz
    fewer = s.without("extension_p_a", "extension_p_b")
    assert "extension_p_a" not in fewer and "extension_p_a" in s   # the original is unchanged
    assert fewer.with_noise(lift_stroke=1e-3)["lift_stroke"].std == 1e-3
    with pytest.raises(KeyError, match="no sensor measures 'lift_stroke_rate'"):
        s.without("lift_stroke_rate")


@pytest.mark.parametrize("kwargs, words", [
    (dict(field="lift_angle", std=1.0), "Sensor.field must be one of the State's fields"),
    (dict(field="lift_stroke", std=0.0), "Sensor(lift_stroke).std must be > 0"),
    (dict(field="lift_stroke", std=1e-4, rate=0.0), "Sensor(lift_stroke).rate must be in (0, 10000] Hz"),
    (dict(field="lift_stroke", std=1e-4, rate=100.0, max_age=0.001),
     "Sensor(lift_stroke).max_age must be >= one sample period 0.01 s"),
])
def test_bad_sensors_name_the_field(kwargs, words):
    with pytest.raises(ValueError) as e:
        Sensor(**kwargs)
    assert words in str(e.value)


def test_one_sensor_per_field():
    with pytest.raises(ValueError, match="one sensor per field"):
        Sensors((Sensor("lift_stroke", 1e-4), Sensor("lift_stroke", 2e-4)))
