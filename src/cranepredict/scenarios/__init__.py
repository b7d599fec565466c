"""Named scenarios, kept as data: one TOML file per scenario in this folder.

A scenario file names a crane (a file in ``cranepredict/cranes`` without ``.toml``), optionally
overrides its load, and gives the initial state, the drive of each cylinder and the horizon:

    name = "paper-fig4"
    description = "..."
    crane = "patu655"
    load_mass = 200.0          # kg, optional
    horizon = 2.0              # s
    [initial]                  # State fields (m, rad, m/s)
    lift_stroke = 0.116
    tilt_stroke = 0.32
    [inputs.lift]              # constant pressures (Pa) ...
    p_a = 175e5
    p_b = 0.0
    [inputs.tilt]              # ... or hold = true, or sampled: t = [...], p_a = [...], p_b = [...]
    hold = true

A valve-driven cylinder takes the lever, ``u = 0.5`` or sampled ``t = [...], u = [...]``; its
chamber pressures go into ``[initial]`` (``lift_p_a = ...``), or ``at_rest = true`` there starts
from :func:`cranepredict.state_at_rest` at the given strokes (slew, extension and
``lift_rod_pressure``/``tilt_rod_pressure`` allowed too).
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from typing import Any, Dict, List, Mapping, Tuple

from .._checks import tomllib
from ..crane import Crane
from ..types import Drive, Hold, Inputs, Pressure, PressureSeries, State, Valve, ValveSeries

__all__ = ["Scenario", "get", "names", "all_scenarios", "from_dict"]


@dataclass(frozen=True)
class Scenario:
    name: str
    description: str
    crane: Crane
    initial: State
    inputs: Inputs
    horizon: float
    tags: Tuple[str, ...] = ()


def _drive(d: Mapping[str, Any], where: str) -> Drive:
    keys = set(d)
    if keys == {"hold"}:
        if d["hold"] is not True:
            raise ValueError(f"{where}.hold must be true (omit it to drive the cylinder)")
        return Hold()
    if keys == {"p_a", "p_b"}:
        return Pressure(p_a=d["p_a"], p_b=d["p_b"])
    if keys == {"t", "p_a", "p_b"}:
        return PressureSeries(t=d["t"], p_a=d["p_a"], p_b=d["p_b"])
    if keys == {"u"}:
        return Valve(u=d["u"])
    if keys == {"t", "u"}:
        return ValveSeries(t=d["t"], u=d["u"])
    raise ValueError(f"{where} must have either hold = true, or p_a and p_b, or t, p_a and p_b, "
                     f"or u, or t and u; got keys {sorted(keys)}")


def _initial(crane: Crane, d: Mapping[str, Any]) -> State:
    d = dict(d)
    if d.pop("at_rest", False) is True:
        from ..api import state_at_rest

        return state_at_rest(crane, **d)
    return State(**d)


def _crane(name: str, where: str) -> Crane:
    path = resources.files("cranepredict").joinpath(f"cranes/{name}.toml")
    if not path.is_file():
        raise ValueError(f"{where}: no crane file named {name!r} in cranepredict/cranes")
    return Crane.from_toml_string(path.read_text("utf-8"))


def from_dict(data: Mapping[str, Any], where: str = "scenario") -> Scenario:
    allowed = {"name", "description", "crane", "load_mass", "horizon", "initial", "inputs", "tags"}
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise ValueError(f"{where}: unknown field(s) {unknown}; allowed: {sorted(allowed)}")
    crane = _crane(data.get("crane", "patu655"), where)
    if "load_mass" in data:
        crane = crane.with_load(data["load_mass"])
    inputs = data.get("inputs", {})
    if set(inputs) != {"lift", "tilt"}:
        raise ValueError(f"{where}.inputs must have exactly the tables lift and tilt")
    return Scenario(
        name=data["name"],
        description=data.get("description", ""),
        crane=crane,
        initial=_initial(crane, data["initial"]),
        inputs=Inputs(lift=_drive(inputs["lift"], f"{where}.inputs.lift"),
                      tilt=_drive(inputs["tilt"], f"{where}.inputs.tilt")),
        horizon=float(data["horizon"]),
        tags=tuple(data.get("tags", ())),
    )


def _load_all() -> Dict[str, Scenario]:
    out: Dict[str, Scenario] = {}
    for entry in sorted(resources.files(__name__).iterdir(), key=lambda p: p.name):
        if entry.name.endswith(".toml"):
            sc = from_dict(tomllib.loads(entry.read_text("utf-8")), entry.name)
            if sc.name in out:
                raise ValueError(f"{entry.name}: scenario name {sc.name!r} is used twice")
            out[sc.name] = sc
    return out


_CACHE: Dict[str, Scenario] = {}


def _all() -> Dict[str, Scenario]:
    if not _CACHE:
        _CACHE.update(_load_all())
    return _CACHE


def names() -> List[str]:
    """The names of all scenarios, sorted."""
    return sorted(_all())


def get(name: str) -> Scenario:
    """The scenario of that name; ValueError listing the names if there is none."""
    try:
        return _all()[name]
    except KeyError:
        raise ValueError(f"no scenario named {name!r}; known: {', '.join(names())}") from None


def all_scenarios() -> List[Scenario]:
    return [_all()[n] for n in names()]
