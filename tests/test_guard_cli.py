"""`cranepredict guard`, run as a user would."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest


def _run(*args):
    return subprocess.run([sys.executable, "-m", "cranepredict.cli", "guard", *args],
                          capture_output=True, text=True, timeout=300)


def test_guard_prints_the_verdict_per_part():
    r = _run("--world", "power-line", "--scenario", "paper-fig4")
    assert r.returncode == 0, r.stderr
    assert "signal     WARN: contact of extension_boom and conductor 3" in r.stdout
    for part in ("pillar", "lift_boom", "outer_boom", "extension_boom", "load"):
        assert f"\n  {part} " in r.stdout
    assert "closing: lift" in r.stdout and "valve to neutral" in r.stdout


def test_guard_json_from_a_world_file(tmp_path):
    world = Path(__file__).parents[1] / "src" / "cranepredict" / "worlds" / "wall.toml"
    r = _run("--world", str(world), "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["signal"] == "GO" and d["contact"] is None and d["world"] == "wall"
    assert set(d["min_clearance_m"]) >= {"pillar", "load"}


def test_guard_plot(tmp_path):
    pytest.importorskip("matplotlib")
    r = _run("--world", "building-edge", "--scenario", "end-stop-lift-lower", "--plot", str(tmp_path))
    assert r.returncode == 0, r.stderr
    png = tmp_path / "guard-end-stop-lift-lower-building-edge.png"
    assert png.stat().st_size > 10_000


def test_guard_bad_world_is_one_line_exit_2(tmp_path):
    bad = tmp_path / "w.toml"
    bad.write_text("margin = 0.2\n[[obstacle]]\nname = 'mast'\nkind = 'cone'\n")
    r = _run("--world", str(bad))
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip().count("\n") == 0 and "obstacle 'mast' (obstacle[0]).kind" in r.stderr
    r = _run("--world", "nowhere")
    assert r.returncode == 2 and "not an example world" in r.stderr
