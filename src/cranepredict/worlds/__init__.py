"""Example world files for the collision guard (TOML data files next to this module).

``names()`` lists them, ``get(name)`` loads one as a :class:`cranepredict.World`.
"""

from ..world import get, names

__all__ = ["names", "get"]
