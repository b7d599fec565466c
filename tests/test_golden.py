"""The golden vectors of the C tests (tools/golden.py) are the twin's current trajectories of the
named scenarios, and the scenario header is the scenario files."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("golden", ROOT / "tools" / "golden.py")
golden = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(golden)


@pytest.mark.slow
def test_generated_golden_files_are_up_to_date():
    r = subprocess.run([sys.executable, str(ROOT / "tools" / "golden.py"), "--check"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr


def test_staleness_check_can_fail():
    """The check compares numbers to 1e-10 and the text exactly: a changed digit or word is stale,
    round-off of the twin's arithmetic is not."""
    text = golden.SCENARIOS_H.read_text()
    assert golden.same(text, text)
    assert not golden.same(text, text.replace("CRANE_R(17500000.0)", "CRANE_R(17600000.0)", 1))
    assert not golden.same(text, text.replace("CRANE_DRIVE_HOLD", "CRANE_DRIVE_PRESSURE", 1))
    assert golden.same("x = 0.1;", "x = 0.10000000000000002;")
    assert golden.same("p = 82669.6104211959;", "p = 82669.61042133273;")   # 1.4e-7 Pa of round-off
    assert not golden.same("x = 4.61499752;", "x = 4.61499753;")             # 1e-8 m: stale


def test_a_scenario_with_a_drive_the_generator_cannot_write_is_listed_not_dropped(monkeypatch):
    import dataclasses

    import cranepredict as cp

    class Valve:  # a drive type the generator does not know
        held = False

    sc = cp.scenarios.get("load-0")
    odd = dataclasses.replace(sc, name="valve-x", inputs=object.__new__(cp.Inputs))
    object.__setattr__(odd.inputs, "lift", Valve())
    object.__setattr__(odd.inputs, "tilt", cp.Hold())
    object.__setattr__(odd.inputs, "slew", cp.Hold())
    object.__setattr__(odd.inputs, "extension", cp.Hold())
    monkeypatch.setattr(golden.cp.scenarios, "all_scenarios", lambda: [sc, odd])
    monkeypatch.setattr(golden.cp.scenarios, "names", lambda: ["load-0", "valve-x"])
    assert [s.name for s in golden.written()] == ["load-0"]
    text = golden.scenarios_header()
    assert "Left out (drive types this generator does not write yet): valve-x" in text
    assert "CRANE_SCENARIO_LOAD_0_STATE" in text and "VALVE_X" not in text


def test_the_spatial_scenarios_are_in_both_files_with_their_four_drives():
    """The C tests check the four joints: every spatial scenario is written, with its slew and
    extension drives (valves and valve series included) and golden samples of all four joints."""
    import cranepredict as cp

    spatial = [sc for sc in cp.scenarios.all_scenarios() if sc.spatial]
    assert len(spatial) >= 7
    assert {sc.name for sc in golden.written()} == set(cp.scenarios.names())
    scen, gold = golden.SCENARIOS_H.read_text(), golden.GOLDEN_H.read_text()
    for sc in spatial:
        x = golden._ident(sc.name)
        inputs = scen[scen.index(f"#define CRANE_SCENARIO_{x}_INPUTS"):]
        inputs = inputs[:inputs.index("#define", 1)]
        assert inputs.count(".mode = ") == 4, sc.name
        assert f"golden_{x.lower()}[]" in gold and f'{{"{sc.name}", ' in gold
    sl = scen[scen.index("#define CRANE_SCENARIO_SLEW_STOP_LOAD_OUT_INPUTS"):]
    assert ".u_samples = (const crane_real[]){CRANE_R(1.0), CRANE_R(1.0), CRANE_R(0.0)" in sl.split("\n")[3]
    # a golden sample carries slew, extension, their rates and four-column pressures and flags
    assert "double t, stroke[2], theta[2], omega[2], slew, extension, slew_rate, extension_rate;" in gold
    assert "p_a[4], p_b[4];" in gold and "int stop[4];" in gold and "long first_stop[4];" in gold


def test_staleness_check_sees_a_four_joint_number():
    text = golden.GOLDEN_H.read_text()
    row = text[text.index("golden_valve_all_four[] = {"):].split("\n")[2]   # the sample at 0.05 s
    slew = row.split("}, ")[3].split(", ")[0]                                 # after omega: the slew
    assert 0.3 < float(slew) < 0.31
    assert not golden.same(text, text.replace(row, row.replace(slew, repr(float(slew) + 1e-8), 1)))
