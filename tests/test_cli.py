"""The command line, run as a user would."""

from __future__ import annotations

import re
import subprocess
import sys


def _run(*args):
    return subprocess.run([sys.executable, "-m", "cranepredict.cli", *args], capture_output=True,
                          text=True, timeout=120)


def test_help():
    r = _run("--help")
    assert r.returncode == 0 and "demo" in r.stdout


def test_demo_reports_start_end_stop_and_speed():
    r = _run("demo", "--repeat", "5")
    assert r.returncode == 0, r.stderr
    assert "paper-fig4" in r.stdout
    assert re.search(r"tip start .* m", r.stdout) and re.search(r"tip end .* m", r.stdout)
    assert re.search(r"lift cylinder reached its upper stop at t = [01]\.\d+ s", r.stdout)
    assert re.search(r"[\d,]+x faster than real time", r.stdout)


def test_unknown_scenario_is_a_clear_error():
    r = _run("demo", "--scenario", "nope")
    assert r.returncode == 2 and "no scenario named 'nope'" in r.stderr
