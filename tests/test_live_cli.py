"""The live twin's commands: the demo on a virtual bus (and its log replayed), the twin and the
simulated crane as two processes on a udp_multicast bus."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import pytest

from cranepredict.cli import main


def test_the_demo_stops_the_crane_before_the_wall_and_its_log_replays(tmp_path, capsys):
    log = str(tmp_path / "demo.asc")
    assert main(["live", "--demo", "--seconds", "6", "--log", log]) == 0
    out = capsys.readouterr().out
    assert "with the interlock:    no contact" in out
    assert "without the interlock: the load touched wall" in out
    assert "the interlock prevented that contact" in out
    assert " STOP " in out and os.path.getsize(log) > 0
    import importlib.util

    plot = importlib.util.find_spec("matplotlib") is not None   # the [plot] extra
    assert main(["replay", log, "--world", "wall", "--json"]
                + (["--plot", str(tmp_path)] if plot else [])) == 0
    timeline = json.loads(capsys.readouterr().out)
    assert len(timeline) == 600                                 # one verdict per Levers frame
    signals = [v["signal"] for v in timeline]
    assert signals[0] == "FAULT" and "GO" in signals and "STOP" in signals
    first_stop = next(v for v in timeline if v["signal"] == "STOP")
    assert first_stop["obstacle"] == "wall" and first_stop["time_to_contact_s"] <= 0.5
    assert os.path.exists(tmp_path / "replay-demo.png") or not plot


def test_replay_and_live_refuse_bad_arguments(tmp_path, capsys):
    assert main(["replay", str(tmp_path / "none.asc"), "--world", "wall"]) == 2
    assert "LOG: no such file" in capsys.readouterr().err
    assert main(["live", "--world", "wall"]) == 2
    assert "live needs --interface and --channel (or --demo)" in capsys.readouterr().err
    assert main(["live", "--demo", "--world", "moon"]) == 2
    assert "not an example world" in capsys.readouterr().err


def test_twin_and_simulated_crane_in_two_processes_on_udp_multicast(tmp_path):
    group = "239.74.163.%d" % (10 + os.getpid() % 200)
    cmd = [sys.executable, "-m", "cranepredict.cli"]
    twin = subprocess.Popen(cmd + ["live", "--interface", "udp_multicast", "--channel", group,
                                   "--cycles", "40", "--json"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        time.sleep(2.0)
        sim = subprocess.run(cmd + ["sim-crane", "--interface", "udp_multicast", "--channel", group,
                                    "--seconds", "0.4", "--lockstep"],
                             capture_output=True, text=True, timeout=120)
        assert sim.returncode == 0, sim.stderr
        out, err = twin.communicate(timeout=60)
    finally:
        twin.kill()
    assert twin.returncode == 0, err
    verdicts = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    judged = [v for v in verdicts if v["fault"] != "levers stale"]
    assert len(judged) == 40
    assert [v["signal"] for v in judged[:10]] == ["FAULT"] * 10   # the estimator settling
    assert all(v["signal"] == "GO" for v in judged[10:]), [v for v in judged if v["signal"] != "GO"][10:]
    assert "last verdict GO" in sim.stdout
