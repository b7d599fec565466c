"""One validator of a crane: the C core's crane_params_check.

Python checks only types and shapes; every rule is the core's, which reports the field at fault,
and the error names it by the crane file's dotted name. The header generator uses the same check.
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cranepredict as cp
from cranepredict import _core
from cranepredict._cranepredict import ffi, lib
from cranepredict.crane import Crane, field_name

ROOT = Path(__file__).resolve().parents[1]
TOOL = ROOT / "tools" / "crane2header.py"


def _replace(crane: Crane, dotted: str, value) -> Crane:
    """The crane with one field replaced, built directly (not through the crane file's loader)."""
    head, _, rest = dotted.partition(".")
    if not rest:
        return dataclasses.replace(crane, **{head: value})
    return dataclasses.replace(crane, **{head: _replace(getattr(crane, head), rest, value)})


def _numeric_leaves(obj, prefix=""):
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if f.name in ("name", "estimates", "shape") or v is None:   # shape: the guard's
            continue
        if dataclasses.is_dataclass(v):
            yield from _numeric_leaves(v, prefix + f.name + ".")
        else:
            yield prefix + f.name, v


def _core_check(crane: Crane):
    field = ffi.new("crane_field *")
    return lib.crane_params_check(_core.params(crane), field), int(field[0])


def test_every_crane_field_code_is_a_field_of_the_crane_file(crane):
    enum = {v: k for k, v in ffi.typeof("crane_field").elements.items()}
    codes = [code for name, code in enum.items() if name not in ("CRANE_FIELD_NONE", "CRANE_FIELD_COUNT")]
    # every optional table given: the slew drive and the extension cylinder with a circuit too
    hyd = crane.lift_cylinder.hydraulics
    full = dataclasses.replace(
        crane, slew_drive=dataclasses.replace(crane.slew_drive, hydraulics=hyd),
        extension_cylinder=dataclasses.replace(crane.extension_cylinder, hydraulics=hyd))
    leaves = [name for name, _ in _numeric_leaves(full)]
    assert sorted(field_name(c) for c in codes) == sorted(leaves)


def test_each_field_made_nonfinite_is_named_by_the_core(crane):
    # Built directly, so that no Python check runs first: the names come from the core's codes.
    for name, value in _numeric_leaves(crane):
        if isinstance(value, str):   # hydraulics.valve: a name (crane.py checks it), an enum in C
            continue
        bad = (math.nan, value[1]) if isinstance(value, tuple) else math.inf
        with pytest.raises(ValueError, match=rf"^{name.replace('.', '[.]')} must be finite"):
            _replace(crane, name, bad)


@pytest.mark.parametrize("name, value, rule", [
    ("gravity", -1.0, ">= 0"),
    ("load_mass", -1.0, ">= 0"),
    ("geometry.tip_distance", 0.0, "> 0"),
    ("geometry.extension_max", -1.0, ">= geometry.extension_min (0.0)"),
    ("extension_boom.izz", 0.0, "> 0"),
    ("side_link2.mass", -1.0, ">= 0 (0 = neglected)"),
    ("side_link1.izz", -1e-9, ">= 0 (0 = neglected)"),
    ("tilt_cylinder.length_retracted", 0.0, "> 0"),
    ("lift_cylinder.friction.coulomb", -1.0, ">= 0"),
    ("lift_cylinder.friction.factor", -1.0, ">= 0"),
    ("tilt_cylinder.friction.stribeck_velocity", 0.0, "> 0"),
])
def test_a_broken_rule_names_the_field_and_its_range(crane, name, value, rule):
    with pytest.raises(ValueError) as info:
        _replace(crane, name, value)
    assert str(info.value).startswith(f"{name} must be {rule}, got {value}")


def test_massless_side_links_load_as_in_the_paper(crane):
    # Finding 1: Python rejected side links of mass 0 that C accepts (the paper's crane has none).
    massless = cp.Body(mass=0.0, com=(0.0, 0.0), izz=0.0)
    paper = dataclasses.replace(crane, side_link1=massless, side_link2=massless)
    assert Crane.from_toml_string(paper.to_toml()) == paper
    state = cp.State(lift_stroke=0.1, tilt_stroke=0.2)
    inputs = cp.Inputs(lift=cp.Hold(), tilt=cp.Hold())
    c = cp.predict(paper, state, inputs, 0.05, dt=0.01)
    twin = cp.predict(paper, state, inputs, 0.05, dt=0.01, backend="python")
    assert np.max(np.abs(c.tip - twin.tip)) < 1e-9


def test_negative_stroke_min_one_rule_in_c_and_python(crane):
    # Finding 1: C accepted stroke_min = -0.01 (length_retracted + stroke_min > 0), Python did not.
    # The one rule: stroke 0 is the retracted cylinder, so stroke_min >= 0, in the core.
    cyl = dataclasses.replace(crane.lift_cylinder, stroke_min=-0.01)
    p = _core.params(crane)
    bad = ffi.new("crane_params *", p[0])
    bad.cylinder[lib.CRANE_LIFT].stroke_min = -0.01
    field = ffi.new("crane_field *")
    assert lib.crane_params_check(bad, field) == lib.CRANE_E_CYLINDER
    assert field[0] == lib.CRANE_FIELD_LIFT_CYLINDER_STROKE_MIN
    m = ffi.new("crane_model *")
    assert lib.crane_model_init(m, bad, 0.0) == lib.CRANE_E_CYLINDER
    with pytest.raises(ValueError, match=r"^lift_cylinder\.stroke_min must be >= 0, got -0\.01"):
        dataclasses.replace(crane, lift_cylinder=cyl)


def test_pillar_is_optional(crane):
    # Finding 1: the crane file required a pillar body that no model uses (the slew is constant).
    d = crane.to_dict()
    del d["pillar"]
    no_pillar = Crane.from_dict(d)
    assert no_pillar.pillar is None
    assert "\n[pillar]" not in no_pillar.to_toml()   # the body's table (a shape part may be named so)
    assert Crane.from_toml_string(no_pillar.to_toml()) == no_pillar
    assert crane.pillar is not None and _core_check(no_pillar) == (lib.CRANE_OK, 0)


def test_c_reports_the_field_and_no_field_when_ok(crane):
    assert _core_check(crane) == (lib.CRANE_OK, lib.CRANE_FIELD_NONE)
    field = ffi.new("crane_field *", lib.CRANE_FIELD_GRAVITY)
    assert lib.crane_params_check(ffi.NULL, field) == lib.CRANE_E_NULL
    assert field[0] == lib.CRANE_FIELD_NONE
    assert lib.crane_params_check(_core.params(crane), ffi.NULL) == lib.CRANE_OK
    assert ffi.string(lib.crane_field_rule(lib.CRANE_FIELD_TILT_CYLINDER_BORE)) == b"> rod"
    assert ffi.string(lib.crane_field_rule(lib.CRANE_FIELD_COUNT)) == b""


@pytest.mark.skipif(sys.version_info < (3, 11), reason="tools/crane2header.py needs tomllib (3.11+)")
def test_crane2header_uses_the_core_validator(crane, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(crane.to_toml().replace("[side_link1]\nmass = ", "[side_link1]\nmass = -"))
    r = subprocess.run([sys.executable, str(TOOL), str(bad), "-o", str(tmp_path / "bad.h")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode != 0 and "side_link1.mass must be >= 0" in r.stdout + r.stderr
    massless = cp.Body(mass=0.0, com=(0.0, 0.0), izz=0.0)
    good = tmp_path / "paper.toml"
    good.write_text(dataclasses.replace(crane, side_link1=massless, side_link2=massless).to_toml())
    r = subprocess.run([sys.executable, str(TOOL), str(good), "-o", str(tmp_path / "paper.h")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    assert ".side_link1.mass = CRANE_R(0.0)" in (tmp_path / "paper.h").read_text()


def test_crane_model_is_opaque_to_the_binding(crane):
    # The binding depended on crane_model's layout; now it knows only its size
    # (from the compiled header), and the fields are the core's (documented in crane.h).
    m = _core.model(crane, 0.0)
    assert ffi.sizeof("crane_model") > 0  # known from the compiled header
    with pytest.raises(AttributeError):
        m.theta_min
    assert lib.crane_joint_angle(m, lib.CRANE_LIFT, 0.1, ffi.new("crane_real *"),
                                 ffi.new("crane_real *")) == lib.CRANE_OK
