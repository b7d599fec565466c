"""The user's guide: its code blocks run as printed, the generated crane-file reference covers
every field, and figures the guide derives from the code match the code."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

import cranepredict as cp
from cranepredict import crane_file

DOCS = Path(__file__).parents[1] / "docs"


def _blocks(name: str) -> list:
    return re.findall(r"```python\n(.*?)```", (DOCS / name).read_text("utf-8"), flags=re.S)


@pytest.mark.parametrize("page", ["getting-started.md", "tutorial.md", "howto.md", "sweep.md"])
def test_guide_python_blocks_run_in_order(page, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    blocks = _blocks(page)
    assert blocks
    ns: dict = {}
    for i, code in enumerate(blocks):
        exec(compile(code, f"docs/{page} (python block {i + 1})", "exec"), ns)


def test_tutorial_guard_sees_the_container():
    """The tutorial's site is not a trivial one: the lever log brings the load near the container."""
    ns: dict = {}
    import os
    import tempfile

    cwd = os.getcwd()
    with tempfile.TemporaryDirectory() as d:
        os.chdir(d)
        try:
            for code in _blocks("tutorial.md"):
                exec(code, ns)
        finally:
            os.chdir(cwd)
    assert ns["v"].clearance["load"] < 1.0


def test_crane_file_reference_covers_every_field():
    fields = crane_file.leaves()
    documented = set(crane_file.FIELDS)
    missing = {(owner, f.name) for _, owner, table, f in fields
               if table is None and (owner, f.name) not in documented}
    assert not missing, f"fields without a unit and meaning in crane_file.FIELDS: {sorted(missing)}"
    extra = documented - {(owner, f.name) for _, owner, _, f in fields}
    assert not extra, f"crane_file.FIELDS documents fields the crane file does not have: {extra}"
    text = crane_file.markdown()
    for dotted, _, table, f in fields:
        heading = f"## [{dotted}]" if table else None
        if heading:
            assert heading in text, dotted
    # every rule comes from the C validator: one row per leaf with the validator's text
    assert text.count("| `stroke_max` | m | > stroke_min |") == 2
    assert "| `supply_pressure` | Pa | > tank_pressure and <= 1e8 |" in text
    for part in cp.Crane.patu655().shape.parts:
        assert f"| {part.name} | {part.kind} |" in text


def test_a_new_field_without_documentation_fails_the_reference(monkeypatch):
    monkeypatch.delitem(crane_file.FIELDS, ("Hydraulics", "leakage"))
    with pytest.raises(KeyError):
        crane_file.markdown()


def test_the_sample_size_in_the_model_spec_is_the_core_s():
    from cranepredict._cranepredict import ffi

    text = (DOCS / "model.md").read_text("utf-8")
    sizes = re.findall(r"(\d+) bytes each", text)
    assert sizes == [str(ffi.sizeof("crane_sample"))]


def test_no_history_in_the_users_docs():
    pattern = re.compile(r"\bissue [0-9]+|\bstop [0-9]+\b|newest run|last stop", re.I)
    root = DOCS.parent
    for path in [root / "README.md", *DOCS.glob("*.md")]:
        if path.name == "guard.md":      # its stop analysis section is being rewritten apart
            continue
        hits = [line for line in path.read_text("utf-8").splitlines() if pattern.search(line)]
        assert not hits, f"{path.name}: {hits[:3]}"
