"""The project's licence (MIT) is stated once in each place a user or a tool looks for it."""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

from cranepredict._checks import tomllib

ROOT = Path(__file__).resolve().parents[1]


def test_licence_file_is_mit():
    text = (ROOT / "LICENSE").read_text("utf-8")
    assert text.startswith("MIT License\n")
    assert "Permission is hereby granted, free of charge" in text


def test_pyproject_and_installed_metadata_say_mit():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))["project"]
    assert project["license"] == "MIT"
    # The metadata of the installed package (PEP 639 field), i.e. what the build made of it.
    assert metadata.metadata("cranepredict")["License-Expression"] == "MIT"


def test_every_c_file_starts_with_an_spdx_line():
    files = sorted(p for p in (ROOT / "csrc").rglob("*") if p.suffix in (".c", ".h"))
    assert len(files) >= 10
    missing = [str(p.relative_to(ROOT)) for p in files
               if p.read_text("utf-8").splitlines()[0] != "/* SPDX-License-Identifier: MIT */"]
    assert not missing, f"C files without the SPDX line: {missing}"
