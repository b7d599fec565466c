"""Inputs a hostile caller tried: each is refused as the project promises (ValueError/TypeError
naming the field and the range, before slow work; a C status code; the CLI exits 2 with one line)."""

from __future__ import annotations

import subprocess
import sys
import time

import numpy as np
import pytest

import cranepredict as cp
from cranepredict._cranepredict import ffi, lib


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "cranepredict.cli", *args], capture_output=True,
                          text=True, timeout=300)


def _one_line_exit_2(r, *fragments):
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    for f in fragments:
        assert f in lines[0], lines[0]


# -- the C guard's NULL check -----------------------------------------------------------------------

def test_c_guard_with_parts_no_obstacles_and_no_work_is_refused():
    """3 parts, 0 obstacles, work = NULL, capacity 21: CRANE_E_NULL (it stored through NULL)."""
    crane = cp.Crane.patu655()
    from cranepredict import _core

    G = __import__("importlib").import_module("cranepredict.guard")
    parts = G._parts(crane, cp.Shape(parts=crane.shape.parts[:3]))
    samples = np.zeros(2, dtype=_core.SAMPLE_DTYPE)
    samples["t"] = [0.0, 0.01]
    cfg = ffi.new("crane_guard_config *", {"margin": 0.1, "reaction": 0.2, "cycle": 0.01,
                                           "time_tolerance": 1e-4, "clearance_tolerance": 1e-3})
    res = ffi.new("crane_guard_result *")
    clearance = ffi.new("crane_real[3]")
    status = lib.crane_guard(_core.model(crane, crane.geometry.extension_min), parts, 3, ffi.NULL, 0,
                             ffi.cast("crane_sample *", ffi.from_buffer(samples)), 2, cfg,
                             clearance, ffi.NULL, 21, res)
    assert status == lib.CRANE_E_NULL


def test_c_sample_every_message_names_the_range():
    msg = ffi.string(lib.crane_status_message(lib.CRANE_E_SAMPLE_EVERY)).decode()
    assert "[1, CRANE_MAX_STEPS]" in msg


# -- files and the CLI ----------------------------------------------------------------------------

def test_guard_world_that_is_a_directory(tmp_path):
    _one_line_exit_2(_cli("guard", "--world", str(tmp_path)), "is a directory")
    with pytest.raises(ValueError, match="is a directory"):
        cp.World.from_toml(tmp_path)


def test_guard_plot_into_an_unwritable_place_before_the_prediction(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    _one_line_exit_2(_cli("guard", "--world", "cab", "--plot", str(blocker / "sub")), "--plot",
                     "cannot write there")


def test_world_file_not_utf8_names_the_file(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes('name = "Baustelle Mühle"\nmargin = 0.2\n'.encode("latin-1"))
    with pytest.raises(ValueError, match=r"latin1\.toml.*not UTF-8.*0xfc"):
        cp.World.from_toml(path)
    _one_line_exit_2(_cli("guard", "--world", str(path)), "latin1.toml", "not UTF-8")


def test_world_file_errors_name_the_file(tmp_path):
    path = tmp_path / "w.toml"
    path.write_text("margin = 0.2\n[[obstacle]]\nname = 'b'\nkind = 'sphere'\ncentre = [0, 0, 1]\n"
                    "radius = -1\n")
    with pytest.raises(ValueError, match=r"w\.toml: obstacle 'b' \(obstacle\[0\]\)\.radius"):
        cp.World.from_toml(path)


def test_a_world_of_1e5_obstacles_loads_in_linear_time():
    obstacles = [{"name": f"s{i}", "kind": "sphere", "centre": [10.0 + i, 0.0, 1.0], "radius": 0.1}
                 for i in range(100_000)]
    t0 = time.perf_counter()
    w = cp.World.from_dict({"margin": 0.1, "obstacle": obstacles})
    assert len(w.obstacles) == 100_000
    assert time.perf_counter() - t0 < 30   # quadratic: minutes; linear: about a second
    with pytest.raises(ValueError, match="repeated: s7"):
        cp.World.from_dict({"margin": 0.1, "obstacle": obstacles + [obstacles[7]]})


def test_obstacle_kind_that_is_a_list():
    with pytest.raises(ValueError, match=r"\.kind must be one of .*got \['sphere'\]"):
        cp.World.from_dict({"margin": 0.1, "obstacle": [{"name": "b", "kind": ["sphere"],
                                                         "centre": [0, 0, 1], "radius": 1}]})


def test_shape_box_given_a_radius_is_refused():
    crane = cp.Crane.patu655()
    shape = crane.shape.to_plain()
    shape["load"] = {"kind": "box", "a": "tip", "size": [0.5, 0.5, 0.5], "drop": 0.3, "radius": 0.2}
    with pytest.raises(ValueError, match=r"shape\.load: radius is not a field of a box"):
        cp.Shape.from_dict(shape)


# -- messages and silent acceptance -----------------------------------------------------------------

@pytest.mark.parametrize("make, text", [
    (lambda: cp.Valve(1.0000001), "got 1.0000001"),
    (lambda: cp.ValveSeries(t=[0, 2], u=[0, 1.0000001]), "got [0.0, 1.0000001]"),
    (lambda: cp.State(lift_stroke=0.1, tilt_stroke=0.2, lift_p_a=1.0000001e8), "got 100000010.0"),
])
def test_messages_keep_the_value_that_broke_the_range(make, text):
    with pytest.raises(ValueError) as e:
        make()
    assert text in str(e.value)


@pytest.mark.parametrize("make, field", [
    (lambda: cp.PressureSeries(t=[0, 2], p_a=[True, False], p_b=[0, 0]), "PressureSeries.p_a[0]"),
    (lambda: cp.ValveSeries(t=["0", "2"], u=[0, 0]), "ValveSeries.t[0]"),
    (lambda: cp.ValveSeries(t=[0, 2], u=[None, 0]), "ValveSeries.u[0]"),
    (lambda: cp.ValveSeries(t="02", u=[0, 0]), "ValveSeries.t"),
])
def test_series_refuse_bools_strings_and_none(make, field):
    with pytest.raises(TypeError) as e:
        make()
    assert str(e.value).startswith(f"{field} must be"), str(e.value)


def test_guard_names_its_own_arguments():
    sc = cp.scenarios.get("paper-fig4")
    w = cp.worlds.get("cab")
    with pytest.raises(TypeError, match=r"^state must be a cranepredict.State, got str"):
        cp.guard(sc.crane, w, "x", sc.inputs, 1.0)
    with pytest.raises(TypeError, match=r"^inputs must be a cranepredict.Inputs"):
        cp.guard(sc.crane, w, sc.initial, None, 1.0)
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"^stop_horizon must be in \(0, 10\] s"):
        cp.guard(sc.crane, w, sc.initial, sc.inputs, 1.0, stop_horizon=1e4)
    assert time.perf_counter() - t0 < 0.5   # before the prediction


def test_empty_batch_keeps_its_sample_times():
    sc = cp.scenarios.get("paper-fig4")
    empty = cp.predict_many(sc.crane, [], [], 2.0, sample_every=7)
    one = cp.predict_many(sc.crane, [sc.initial], [sc.inputs], 2.0, sample_every=7)
    assert empty.strokes.shape == (0,) + one.strokes.shape[1:]
    assert np.array_equal(empty.t, one.t)


def test_twin_on_a_crane_with_an_absurd_bore_is_a_value_error():
    import dataclasses

    sc = cp.scenarios.get("paper-fig4")
    crane = dataclasses.replace(sc.crane, lift_cylinder=dataclasses.replace(
        sc.crane.lift_cylinder, bore=1e200))
    for backend in ("c", "python"):
        with pytest.raises(ValueError):
            cp.predict(crane, sc.initial, sc.inputs, 0.1, backend=backend)
