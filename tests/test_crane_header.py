"""The C header generated from the crane file (for embedded builds) is up to date with it."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TOOL = ROOT / "tools" / "crane2header.py"


@pytest.mark.skipif(sys.version_info < (3, 11), reason="tools/crane2header.py needs tomllib (3.11+)")
def test_generated_crane_header_matches_the_crane_file():
    r = subprocess.run([sys.executable, str(TOOL), "--check"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
