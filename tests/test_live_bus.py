"""The shipped DBC and its codec: J1939 identifiers, resolutions, not-available and error codes,
rolling counters, lost and frozen frames, the verdict's timeout on the crane's side."""

from __future__ import annotations

import math

import can
import pytest

from cranepredict.live import bus
from cranepredict.live.bus import (ERROR, Codec, MeasurementAssembler, SensorFrames, VerdictFrame,
                                   VerdictMonitor)

VALUES = {"lift_stroke": 0.23456, "lift_p_a": 61.234e5, "lift_p_b": 1.0e5,
          "tilt_stroke": 0.4, "tilt_p_a": 1e5, "tilt_p_b": 28.9e5,
          "slew": -3.3, "slew_p_a": 1e5, "slew_p_b": 1e5,
          "extension": 0.2, "extension_p_a": 1e5, "extension_p_b": 6.6e5}


def test_the_frames_are_j1939_proprietary_b_with_extended_ids_at_250_kbit():
    db = bus.database()
    assert db.dbc.attributes["Baudrate"].value == 250_000
    for m in db.messages:
        assert m.is_extended_frame and m.length == 8 and m.cycle_time == 10
        pdu_format = (m.frame_id >> 16) & 0xFF
        assert pdu_format == 0xFF, m.name                     # proprietary B: PF 255
        assert (m.frame_id >> 24) & 0x3 == 0                  # data page 0, EDP 0
    assert {m.name for m in db.messages} == set(bus.SENSOR_FRAMES) | {"Levers", "Verdict"}


def test_resolutions_fit_the_transducers():
    db = bus.database()
    sig = {s.name: s for m in db.messages for s in m.signals}
    assert sig["lift_stroke"].scale == pytest.approx(1e-4)    # 0.1 mm
    assert sig["lift_p_a"].scale == pytest.approx(1e4)        # 0.1 bar
    assert sig["slew"].scale <= 2 * math.pi / 2**14           # finer than a 14-bit encoder
    assert sig["lift_lever"].scale == pytest.approx(0.01)     # 1 % of the lever


def test_a_cycle_round_trips_within_half_a_resolution_step():
    frames = SensorFrames()
    asm = MeasurementAssembler()
    msgs = frames.messages(VALUES, (0.5, -0.25, 0.0, 1.0), 1.0, timestamp=12.5)
    assert [asm.feed(m) for m in msgs[:-1]] == [None] * 4
    m, faults = asm.feed(msgs[-1])
    assert faults == [] and m.t == 12.5
    for name, v in VALUES.items():
        step = 1e4 if "_p_" in name else (1.25e-4 if name == "slew" else 1e-4)
        assert abs(getattr(m, name) - v) <= step / 2 + 1e-12, name
    assert m.inputs.lift.u == 0.5 and m.request.tilt.u == pytest.approx(-0.25)
    assert m.inputs.extension.u == pytest.approx(1.0)


def test_valve_scale_zero_is_valves_to_neutral_while_the_request_stays():
    asm = MeasurementAssembler()
    for msg in SensorFrames().messages(VALUES, (0.8, 0, 0, 0), 0.0, timestamp=0.0):
        out = asm.feed(msg)
    m, _ = out
    assert m.inputs.lift.u == 0.0 and m.request.lift.u == pytest.approx(0.8)


def test_not_available_and_error_codes():
    c = Codec()
    data = c.encode("LiftCylinder", {"lift_stroke": None, "lift_p_a": ERROR, "lift_p_b": 2e5,
                                      "lift_counter": 3})
    assert data[0:2] == b"\xff\xff" and data[2:4] == b"\x00\xfe"
    name, sig = c.decode(c.frame_id("LiftCylinder"), data)
    assert name == "LiftCylinder" and sig["lift_stroke"] is None and sig["lift_p_a"] is ERROR
    assert sig["lift_p_b"] == pytest.approx(2e5)
    with pytest.raises(ValueError, match=r"LiftCylinder.lift_stroke = 7.0 is outside the signal.s range \[-0.1, 6.3255\]"):
        c.encode("LiftCylinder", {"lift_stroke": 7.0})
    assert c.decode(0x123, bytes(8)) is None


def test_a_sensor_error_flag_reaches_the_measurement_as_a_fault():
    asm = MeasurementAssembler()
    vals = dict(VALUES, tilt_p_a=ERROR)
    for msg in SensorFrames().messages(vals, (0, 0, 0, 0), 1.0, timestamp=0.0):
        out = asm.feed(msg)
    m, faults = out
    assert m.tilt_p_a is None and faults == ["sensor error: tilt_p_a"]


def test_counters_roll_and_lost_and_frozen_frames_are_detected():
    frames, asm = SensorFrames(), MeasurementAssembler()
    seen = []
    for k in range(30):
        msgs = frames.messages(VALUES, (0, 0, 0, 0), 1.0, timestamp=0.01 * k)
        seen.append(asm.codec.decode(msgs[0].arbitration_id, msgs[0].data)[1]["lift_counter"])
        if k in (10, 11, 12):
            msgs = msgs[1:]          # three LiftCylinder frames lost
        for msg in msgs:
            out = asm.feed(msg)
        if k == 9 or k == 12:
            assert out[0].lift_stroke is not None if k == 9 else out[0].lift_stroke is None
    assert seen[:16] == list(range(14)) + [0, 1]               # 0..13, then 0 again
    assert asm.lost == {"LiftCylinder": 3}
    # a frozen counter: the frame's values are not taken as fresh
    msgs = frames.messages(VALUES, (0, 0, 0, 0), 1.0, timestamp=1.0, frozen=("TiltCylinder",))
    for msg in msgs:
        out = asm.feed(msg)
    assert out[0].tilt_stroke is None and out[0].lift_stroke is not None
    assert asm.frozen == {"TiltCylinder": 1}
    msgs = frames.messages(VALUES, (0, 0, 0, 0), 1.0, timestamp=1.01, frozen=("Levers",))
    for msg in msgs:
        out = asm.feed(msg)
    assert out == (None, ["levers: frozen counter"])


def test_the_crane_obeys_only_a_fresh_go_or_warn():
    vf, mon = VerdictFrame(), VerdictMonitor(max_age=0.05)
    assert not mon.allowed(0.0)                                  # no verdict yet
    mon.feed(vf.message("GO", 0.0, speed_limit=1.0))
    assert mon.allowed(0.04) and not mon.allowed(0.06)          # stale after 50 ms
    mon.feed(vf.message("WARN", 0.05, time_to_contact=1.2, latest_stop=0.7, speed_limit=0.5))
    assert mon.allowed(0.06) and mon.last["time_to_contact"] == pytest.approx(1.2)
    for signal in ("STOP", "FAULT"):
        mon.feed(vf.message(signal, 0.07, fault="stale" if signal == "FAULT" else "none"))
        assert not mon.allowed(0.07) and mon.signal(0.07) == signal
    mon.feed(vf.message("GO", 0.08))
    vf.counter -= 1                                              # the next repeats the counter
    assert mon.feed(vf.message("GO", 0.12)) is None              # frozen: not fresh, ignored
    assert mon.last_time == pytest.approx(0.08) and not mon.allowed(0.135)
    mon.feed(vf.message("GO", 0.13))
    assert mon.allowed(0.135)


def test_frames_cross_a_python_can_virtual_bus():
    with can.Bus(interface="virtual", channel="test-round-trip", preserve_timestamps=True) as tx, \
            can.Bus(interface="virtual", channel="test-round-trip") as rx:
        for msg in SensorFrames().messages(VALUES, (0.1, 0, 0, 0), 1.0, timestamp=3.0):
            tx.send(msg)
        asm, out = MeasurementAssembler(), None
        for _ in range(5):
            msg = rx.recv(timeout=1.0)
            assert msg is not None and msg.is_extended_id
            out = asm.feed(msg) or out
        m, faults = out
        assert m.t == 3.0 and m.lift_stroke == pytest.approx(0.2346) and faults == []
