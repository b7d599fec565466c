"""Sphinx configuration of the user's guide: `pip install '.[docs]'`, then
`sphinx-build -W -b html docs docs/_build/html` (CI builds it with warnings as errors)."""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

import cranepredict
from cranepredict import cli, crane_file

HERE = Path(__file__).parent

project = "cranepredict"
author = "the cranepredict developers"
release = cranepredict.__version__
extensions = ["myst_parser", "sphinx.ext.autodoc"]
source_suffix = {".md": "markdown"}
exclude_patterns = ["_build"]
myst_heading_anchors = 3
autodoc_member_order = "bysource"
autodoc_typehints = "description"
html_title = f"cranepredict {release}"
try:
    import furo  # noqa: F401

    html_theme = "furo"
except ImportError:  # the default theme still builds
    html_theme = "alabaster"


def _cli_help() -> str:
    """Every command's --help, as the CLI prints it (argparse is the one source)."""
    out = ["# Command line", "",
           "`cranepredict COMMAND --help` prints these; generated from the argument parser.", ""]
    os.environ["COLUMNS"] = "100"   # the same text on every terminal

    def help_of(argv: list) -> str:
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf), contextlib.suppress(SystemExit):
            cli.main(argv + ["--help"])
        return buf.getvalue().rstrip()

    top = help_of([])
    commands = re.findall(r"^    ([a-z][a-z-]*)\s", top, flags=re.M)   # the COMMAND list
    for argv in [[]] + [[c] for c in commands]:
        title = "cranepredict" + (" " + argv[0] if argv else "")
        out += [f"## `{title}`", "", "```text", help_of(argv), "```", ""]
    return "\n".join(out)


def _generate() -> None:
    gen = HERE / "_generated"
    gen.mkdir(exist_ok=True)
    for name, text in (("crane-file.md", crane_file.markdown()), ("cli.md", _cli_help())):
        path = gen / name
        if not path.exists() or path.read_text("utf-8") != text:
            path.write_text(text, "utf-8")


_generate()
