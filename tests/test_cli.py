"""The command line, run as a user would."""

from __future__ import annotations

import re
import subprocess
import sys
import types

import pytest

import cranepredict as cp


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


# -- bad arguments: exit status 2, one line, before any slow work ----------

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
    from cranepredict import reference, validation

    def forbidden(*args, **kwargs):
        raise AssertionError("the slow validation ran before the arguments were checked")

    monkeypatch.setattr(reference, "available", lambda: True)
    monkeypatch.setattr(validation, "compare", forbidden)


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


# -- validate: every scenario, the spatial ones on the spatial reference, the C core as fast model --

def _fake_row(sc, max_mm, p_rms):
    return {"name": sc.name, "tags": list(sc.tags), "horizon": sc.horizon,
            "reference": "spatial" if sc.spatial else "planar", "max_error_mm": max_mm,
            "rms_error_mm": max_mm / 2, "max_error_before_stop_mm": max_mm, "max_error_after_stop_mm": None,
            "first_stop_time_s": None, "stop_time_fast_s": None, "wall_fast_s": 1e-3,
            "wall_reference_s": 1.0, "speed_ratio": 1000.0, "constraint_residual_m": None,
            "pressure_rms_bar": p_rms, "pressure_rms_by_chamber_bar": {}, "backend": "c",
            "dt_fast_s": 2e-3, "dt_reference_s": 2.5e-4,
            "within_targets": max_mm <= 20.0 and max_mm / 2 <= 10.0 and (p_rms is None or p_rms <= 2.0)}


def test_validate_runs_the_spatial_scenarios_on_the_c_core(capsys, monkeypatch):
    """No scenario is dropped: the spatial ones are compared too, each with backend "c" at the
    default step; a missed target (here the tip max of one, the pressure RMS of another) is
    named, and the exit status is 1."""
    from cranepredict import cli, reference, validation

    calls = []

    def fake(sc, **kw):
        calls.append((sc.name, kw))
        return _fake_row(sc, 25.0 if sc.name == "slew-folded" else 0.1,
                         3.0 if sc.name == "valve-all-four" else (0.01 if "valve" in sc.tags else None))

    monkeypatch.setattr(reference, "available", lambda: True)
    monkeypatch.setattr(validation, "compare", fake)
    status = cli.main(["validate", "--scenario", "slew-folded", "--scenario", "load-0",
                       "--scenario", "valve-all-four"])
    out = capsys.readouterr().out
    assert [c[0] for c in calls] == ["slew-folded", "load-0", "valve-all-four"]
    assert all(kw.get("backend", "c") == "c" and kw.get("dt_fast") is None for _, kw in calls)
    assert status == 1
    rows = {line.split()[0]: line.split() for line in out.splitlines() if line.split()[:1] in
            (["slew-folded"], ["load-0"], ["valve-all-four"])}
    assert rows["slew-folded"][1] == "spatial" and rows["slew-folded"][-1] == "MISSED"
    assert rows["load-0"][1] == "planar" and rows["load-0"][-1] == "met"
    assert rows["valve-all-four"][-1] == "MISSED" and "3.0000" in rows["valve-all-four"]
    assert "missed the targets: slew-folded, valve-all-four" in out
    calls.clear()
    assert cli.main(["validate"]) == 1
    import cranepredict as cp
    assert [c[0] for c in calls] == cp.scenarios.names()


def test_validate_a_spatial_scenario_for_real():
    pytest.importorskip("exudyn")
    import json

    r = _run("validate", "--scenario", "slew-stretched", "--json")
    assert r.returncode == 0, r.stderr
    (row,) = json.loads(r.stdout)
    assert row["name"] == "slew-stretched" and row["reference"] == "spatial" and row["backend"] == "c"
    assert row["dt_fast_s"] == cp.DEFAULT_DT and row["within_targets"]
    assert row["max_error_mm"] <= 20.0 and row["rms_error_mm"] <= 10.0
