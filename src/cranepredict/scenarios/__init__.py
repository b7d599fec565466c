"""Named scenarios, kept as data: one TOML file per scenario in this folder.

A scenario file names a crane (a file in ``cranepredict/cranes`` without ``.toml``), optionally
overrides its load, and gives the initial state, the drive of each cylinder and the horizon
(here shaped like paper-fig4.toml; the file itself is the authority):

    name = "paper-fig4"
    description = "..."
    crane = "patu655"
    load_mass = 200.0          # kg, optional
    horizon = 2.0              # s
    [initial]                  # State fields (m, rad, m/s)
    lift_stroke = 0.116
    tilt_stroke = 0.20
    [inputs.lift]              # constant pressures (Pa) ...
    p_a = 175e5
    p_b = 0.0
    [inputs.tilt]              # ... or hold = true, or sampled: t = [...], p_a = [...], p_b = [...]
    hold = true

A valve-driven cylinder takes the lever, ``u = 0.5`` or sampled ``t = [...], u = [...]``; its
chamber pressures go into ``[initial]`` (``lift_p_a = ...``), or ``at_rest = true`` there starts
from :func:`cranepredict.state_at_rest` at the given strokes (slew, extension and
``lift_rod_pressure``/``tilt_rod_pressure``/``extension_rod_pressure`` allowed too).

``[inputs.slew]`` and ``[inputs.extension]`` drive the slew and the telescope the same ways
(optional: left out, the joint is held). A scenario that moves either is *spatial*
(``Scenario.spatial``; tag it "spatial").
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from typing import Any, Dict, List, Mapping, Tuple

import numpy as np

from .._checks import number, tomllib
from ..crane import Crane
from ..types import Drive, Hold, Inputs, Pressure, PressureSeries, State, Valve, ValveSeries

__all__ = ["Scenario", "get", "names", "all_scenarios", "from_dict", "start_and_command",
           "random_case", "random_drive"]


@dataclass(frozen=True)
class Scenario:
    name: str
    description: str
    crane: Crane
    initial: State
    inputs: Inputs
    horizon: float
    tags: Tuple[str, ...] = ()

    @property
    def spatial(self) -> bool:
        """Whether the slew or the extension moves (a drive other than Hold on either)."""
        return not (isinstance(self.inputs.slew, Hold) and isinstance(self.inputs.extension, Hold))


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


def _initial(crane: Crane, d: Any, where: str) -> State:
    """[initial]: State fields, or at_rest = true and the arguments of state_at_rest."""
    if isinstance(d, Mapping) and d.get("at_rest", False) is True:
        from ..api import state_at_rest

        args = {k: v for k, v in d.items() if k != "at_rest"}
        try:
            return state_at_rest(crane, **args)
        except TypeError as exc:  # an unknown or missing argument
            raise TypeError(f"{where} (at_rest): {exc}") from None
    return _state(d, where)


def _state(d: Any, where: str) -> State:
    if not isinstance(d, Mapping):
        raise TypeError(f"{where} must be a table of State fields, got {type(d).__name__}")
    unknown = sorted(set(d) - set(State.__dataclass_fields__))
    if unknown:
        raise ValueError(f"{where}: unknown field(s) {unknown}; allowed: "
                         f"{sorted(State.__dataclass_fields__)}")
    try:
        return State(**d)
    except TypeError as exc:  # a required stroke missing
        raise TypeError(f"{where}: {exc}") from None


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
    missing = sorted({"name", "horizon", "initial"} - set(data))
    if missing:
        raise ValueError(f"{where}: missing field(s) {missing}")
    crane = _crane(data.get("crane", "patu655"), where)
    if "load_mass" in data:
        crane = crane.with_load(data["load_mass"])
    initial, inputs = start_and_command(crane, data["initial"], data.get("inputs", {}), where)
    return Scenario(
        name=data["name"],
        description=data.get("description", ""),
        crane=crane,
        initial=initial,
        inputs=inputs,
        horizon=number(data["horizon"], f"{where}.horizon"),
        tags=tuple(data.get("tags", ())),
    )


def start_and_command(crane: Crane, initial: Any, inputs: Any, where: str) -> Tuple[State, Inputs]:
    """A scenario file's ``[initial]`` and ``[inputs]`` tables (the format above) as a State and
    Inputs of the crane; errors name ``where``'s field."""
    if not isinstance(inputs, Mapping):
        raise TypeError(f"{where}.inputs must be a table of drives, got {type(inputs).__name__}")
    if not {"lift", "tilt"} <= set(inputs) <= {"lift", "tilt", "slew", "extension"}:
        raise ValueError(f"{where}.inputs must have the tables lift and tilt, and optionally slew "
                         f"and extension; got {sorted(inputs)}")
    for name, d in inputs.items():
        if not isinstance(d, Mapping):
            raise TypeError(f"{where}.inputs.{name} must be a table, got {type(d).__name__}")
    drives = {name: _drive(d, f"{where}.inputs.{name}") for name, d in inputs.items()}
    return _initial(crane, initial, f"{where}.initial"), Inputs(**drives)


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


# -- random scenarios (the tests' C-vs-twin comparisons, tools/dt_study.py) -------------------------

def random_drive(rng: np.random.Generator, horizon: float) -> Drive:
    """A random drive: held, constant pressures, or 2-7 pressure samples over [0, horizon]
    (pressures in [0, 200] bar)."""
    kind = rng.integers(0, 3)
    if kind == 0:
        return Hold()
    if kind == 1:
        return Pressure(p_a=rng.uniform(0, 200e5), p_b=rng.uniform(0, 200e5))
    n = int(rng.integers(2, 8))
    t = np.concatenate([[0.0], np.sort(rng.uniform(0, horizon, n - 2)), [horizon]])
    t = np.unique(t)
    return PressureSeries(t=t, p_a=rng.uniform(0, 200e5, t.size), p_b=rng.uniform(0, 200e5, t.size))


def random_case(rng: np.random.Generator, crane: Crane,
                horizon: float = 2.0) -> Tuple[Crane, State, Inputs]:
    """(crane, initial, inputs): loads 0-500 kg, strokes across their ranges, slew, extension."""
    c = crane.with_load(float(rng.uniform(0, 500)))
    lc, tc, g = c.lift_cylinder, c.tilt_cylinder, c.geometry
    initial = State(lift_stroke=float(rng.uniform(lc.stroke_min, lc.stroke_max)),
                    tilt_stroke=float(rng.uniform(tc.stroke_min, tc.stroke_max)),
                    slew=float(rng.uniform(-np.pi, np.pi)),
                    extension=float(rng.uniform(g.extension_min, g.extension_max)))
    inputs = Inputs(lift=random_drive(rng, horizon), tilt=random_drive(rng, horizon))
    return c, initial, inputs
