"""Example uncertainty studies (TOML files next to this module; docs/sweep.md).

``names()`` lists them, ``get(name)`` loads one as a :class:`cranepredict.uncertainty.Study`.
"""

from __future__ import annotations

from importlib import resources
from typing import TYPE_CHECKING, List

if TYPE_CHECKING:  # pragma: no cover
    from ..uncertainty import Study

__all__ = ["names", "get", "text"]


def names() -> List[str]:
    """The example studies shipped with the package."""
    return sorted(p.name[:-5] for p in resources.files(__name__).iterdir()
                  if p.name.endswith(".toml"))


def text(name: str) -> str:
    """The study file of an example, as text (to copy and edit)."""
    if name not in names():
        raise ValueError(f"unknown study {name!r}; known: {', '.join(names())}")
    return resources.files(__name__).joinpath(f"{name}.toml").read_text("utf-8")


def get(name: str) -> "Study":
    """An example study by name."""
    from ..uncertainty import Study

    return Study.from_toml_string(text(name), default_name=name)
