"""The package as a newcomer meets it: the twin imports without the compiled
core, the trajectory's arrays are named once, the tools do not import the tests, types ship."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

import cranepredict as cp
from cranepredict import twin

ROOT = Path(__file__).resolve().parents[1]
STATE = cp.State(lift_stroke=0.1, tilt_stroke=0.3)
INPUTS = cp.Inputs(lift=cp.Pressure(100e5, 0), tilt=cp.Hold())


# -- the twin without the compiled extension ------------------------------

BLOCKED = """
import sys
class Blocker:
    def find_spec(self, name, path=None, target=None):
        if name == "cranepredict._cranepredict":
            raise ImportError("the compiled extension is blocked for this test")
sys.meta_path.insert(0, Blocker())
from cranepredict import twin
from cranepredict.types import Hold, Inputs, Pressure, State
State(lift_stroke=0.1, tilt_stroke=0.3); Inputs(lift=Pressure(1e7), tilt=Hold())
assert "cranepredict._cranepredict" not in sys.modules
print("ok")
"""


def test_twin_and_types_import_without_the_compiled_extension():
    r = subprocess.run([sys.executable, "-c", BLOCKED], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and r.stdout.strip() == "ok", r.stderr


def test_the_trajectory_arrays_are_named_once(crane):
    import dataclasses

    from cranepredict.types import ARRAYS

    tr = cp.predict(crane, STATE, INPUTS, 0.01)
    py = twin.simulate(crane, STATE, INPUTS, 0.01, 2e-3)
    assert tuple(py) == ARRAYS  # the twin's keys
    for cls in (cp.Trajectory, cp.TrajectoryBatch):
        arrays = [f.name for f in dataclasses.fields(cls) if "ndarray" in str(f.type)]
        assert set(ARRAYS) <= set(arrays), cls
    assert all(isinstance(getattr(tr, name), np.ndarray) for name in ARRAYS)


DT_STUDY = """
import runpy, sys
sys.argv = ["dt_study.py", "--help"]
try:
    runpy.run_path(sys.argv_path, run_name="__main__")
except SystemExit:
    pass
assert "conftest" not in sys.modules, "the tool imported the tests"
assert not any(p.rstrip("/").endswith("tests") for p in sys.path), sys.path
print("ok")
"""


def test_dt_study_does_not_import_the_tests():
    code = DT_STUDY.replace("sys.argv_path", repr(str(ROOT / "tools" / "dt_study.py")))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                       cwd=ROOT / "tools")
    assert r.returncode == 0 and r.stdout.strip().endswith("ok"), r.stderr


def test_the_package_ships_its_type_marker():
    from importlib import resources

    assert resources.files("cranepredict").joinpath("py.typed").is_file()
    text = (ROOT / "pyproject.toml").read_text()
    assert '"cranepredict" = ["py.typed"]' in text
