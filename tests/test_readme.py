"""The README's Python blocks run as printed, in order (each block sees the names of the ones
before it, as a reader typing them in would)."""

from __future__ import annotations

import re
from pathlib import Path

import cranepredict as cp

README = Path(__file__).parents[1] / "README.md"


def readme_blocks() -> list:
    """The ```python blocks of README.md, in order."""
    return re.findall(r"```python\n(.*?)```", README.read_text("utf-8"), flags=re.S)


def run_blocks(blocks: list) -> dict:
    ns: dict = {}
    for i, code in enumerate(blocks):
        exec(compile(code, f"README.md (python block {i + 1})", "exec"), ns)
    return ns


def test_readme_python_blocks_run():
    blocks = readme_blocks()
    assert len(blocks) >= 3
    ns = run_blocks(blocks)
    assert isinstance(ns["traj"], cp.Trajectory)
