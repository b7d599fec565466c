"""The command line, run as a user would."""

from __future__ import annotations

import re
import subprocess
import sys
import types

import pytest


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


def test_demo_runs_a_spatial_scenario_and_draws_the_slew(tmp_path):
    pytest.importorskip("matplotlib")
    r = _run("demo", "--scenario", "telescope-end-stop", "--repeat", "1", "--plot", str(tmp_path))
    assert r.returncode == 0, r.stderr
    assert re.search(r"tip end .* extension 1\.000 m\)", r.stdout)
    assert re.search(r"extension cylinder reached its upper stop at t = [12]\.\d+ s", r.stdout)
    assert "pressures  extension:" in r.stdout
    r = _run("demo", "--scenario", "slew-folded", "--repeat", "1", "--plot", str(tmp_path))
    assert r.returncode == 0, r.stderr
    assert re.search(r"tip end .* slew +8[0-9]\.\d deg", r.stdout)   # 1.43 rad: it slewed
    assert (tmp_path / "demo-slew-folded.png").stat().st_size > 10_000


def test_unknown_scenario_is_a_clear_error():
    r = _run("demo", "--scenario", "nope")
    assert r.returncode == 2 and "no scenario named 'nope'" in r.stderr


# -- bad arguments: exit status 2, one line, before any slow work (issue 8, finding 6) ----------

def _main(capsys, *args):
    from cranepredict import cli

    status = cli.main(list(args))
    err = capsys.readouterr().err
    return status, err


def test_demo_repeat_0_is_one_line_with_status_2(capsys):
    status, err = _main(capsys, "demo", "--repeat", "0")
    assert status == 2
    assert err == "cranepredict: error: --repeat must be >= 1 (timed repetitions), got 0\n"


@pytest.fixture
def no_slow_validation(monkeypatch):
    """The reference reported available, its comparison forbidden: the checks must come first."""
    from cranepredict import reference

    def forbidden(*args, **kwargs):
        raise AssertionError("the slow validation ran before the arguments were checked")

    monkeypatch.setattr(reference, "available", lambda: True)
    monkeypatch.setattr(reference, "compare", forbidden)


def test_validate_unknown_scenario_fails_before_the_validation(capsys, no_slow_validation):
    status, err = _main(capsys, "validate", "--scenario", "load-0", "--scenario", "nosuch")
    assert status == 2 and err.count("\n") == 1
    assert err.startswith("cranepredict: error: no scenario named 'nosuch'; known: ")


def test_validate_plot_without_matplotlib_fails_before_the_validation(capsys, no_slow_validation,
                                                                      monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    status, err = _main(capsys, "validate", "--scenario", "load-0", "--plot", str(tmp_path))
    assert status == 2
    assert err == "cranepredict: error: --plot needs matplotlib: pip install 'cranepredict[plot]'\n"


def test_validate_plot_into_an_unwritable_dir_fails_before_the_validation(capsys, no_slow_validation,
                                                                          monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", types.ModuleType("matplotlib"))  # (not needed)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    status, err = _main(capsys, "validate", "--scenario", "load-0", "--plot", str(blocker / "plots"))
    assert status == 2 and err.count("\n") == 1
    assert err.startswith(f"cranepredict: error: --plot {blocker / 'plots'}: cannot write there (")


def test_validate_without_exudyn_is_one_line(capsys, monkeypatch):
    from cranepredict import reference

    monkeypatch.setattr(reference, "available", lambda: False)
    status, err = _main(capsys, "validate")
    assert status == 2
    assert err == "cranepredict: error: validate needs Exudyn: pip install 'cranepredict[reference]'\n"


@pytest.mark.parametrize("dt_ref", ["0", "-1e-4", "nan", "5"])
def test_validate_bad_dt_ref_fails_before_the_validation(capsys, no_slow_validation, dt_ref):
    status, err = _main(capsys, "validate", "--scenario", "load-0", f"--dt-ref={dt_ref}")
    assert status == 2 and err.startswith("cranepredict: error: --dt-ref must be in (0, horizon] s")


def test_ctrl_c_is_one_line_with_status_130(capsys, monkeypatch):
    from cranepredict import api

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(api, "predict", interrupted)
    status, err = _main(capsys, "demo", "--repeat", "1")
    assert status == 130 and err == "cranepredict: interrupted\n"
