"""Uncertainty sweeps: how often does the twin's guard, run with the crane file's nominal
parameters, miss a contact that the real crane makes (docs/sweep.md)?

A :class:`Study` (a TOML file) names the crane, the world, the cases (initial states and operator
commands), the uncertain parameters and their distributions, the number of samples and the seed.
Each sample is a "real" crane: the sampled parameters (the load, friction, pressures: predicted
with :func:`~cranepredict.predict_many`'s ``vary``, no Crane per sample) starting from the measured
state plus the sampled sensor offsets. It is judged under the decision the twin took for its case
with the nominal parameters (the guard's verdict: GO runs the command; WARN stops at the latest
stop time; STOP stops now): did the real crane still come within the world's margin of an
obstacle (a contact the nominal verdict missed)? :func:`sweep` runs the samples in chunks of
``predict_many`` and the guard's measure, on Dask (a LocalCluster, or a cluster's scheduler) or in
this process, writes each chunk as it comes (NPZ), skips the chunks already written when run
again, and summarises per obstacle.

The table is the same whatever runs it: chunk i draws its samples from its own seed, spawned from
the study's (``numpy.random.SeedSequence(seed, spawn_key=(i,))``), and every chunk is computed the
same way on any worker.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import api
from ._checks import number as _number
from ._checks import tomllib
from .crane import Crane
from .guard import (DEFAULT_CYCLE, DEFAULT_REACTION, DEFAULT_STOP_HORIZON, GUARD_SPACING,
                    SAMPLE_FIELDS, SIGNALS, STOP_FOLLOW_MAX, guard, obstacle_clearances,
                    stop_inputs, stop_settled, stop_state)
from .types import Inputs, State
from .world import World

__all__ = ["Study", "Case", "Uncertain", "Summary", "ObstacleSummary", "SweepResult", "sweep", "has_dask",
           "load_study", "STATE_OFFSETS", "DISTRIBUTIONS", "NORMAL_CLIP", "MAX_SAMPLES"]

#: The state fields a study may offset (a sensor's error: the real crane starts elsewhere than the
#: twin believes), as ``"state.<field>"``: m, m, rad, m.
STATE_OFFSETS = ("lift_stroke", "tilt_stroke", "slew", "extension")
DISTRIBUTIONS = ("uniform", "normal")
#: A normal distribution's draws are clipped to mean +- NORMAL_CLIP standard deviations, so that
#: the values a study can draw are bounded and checked before it runs.
NORMAL_CLIP = 4.0
#: The most samples a study may ask for.
MAX_SAMPLES = 10 ** 9
MAX_CHUNK = 100_000

_FIELDS = ("name", "description", "crane", "load_mass", "world", "horizon", "samples", "seed",
           "chunk", "target", "guard", "case", "uncertain")
_GUARD_FIELDS = ("margin", "reaction", "cycle", "dt")


# -- the study ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Uncertain:
    """One uncertain parameter: ``name`` is a crane-file field of
    :data:`cranepredict.api.VARY_FIELDS` (e.g. ``"load_mass"``) or ``"state.<field>"`` (an offset
    added to the measured initial state, STATE_OFFSETS). ``distribution`` "uniform" draws from
    [a, b], "normal" from mean a, standard deviation b (clipped to NORMAL_CLIP deviations). For a
    crane field the draw is the value, or with ``relative`` the fraction added to the nominal value
    (value = nominal (1 + draw)); for a state field it is the offset."""

    name: str
    distribution: str
    a: float
    b: float
    relative: bool = False

    def __post_init__(self) -> None:
        where = f"uncertain.{self.name}"
        if self.name.startswith("state."):
            if self.name[6:] not in STATE_OFFSETS:
                raise ValueError(f"{where}: a state offset must be one of "
                                 f"{', '.join('state.' + f for f in STATE_OFFSETS)}")
            if self.relative:
                raise ValueError(f"{where}.relative: a state offset is absolute (m or rad)")
        elif self.name not in api.VARY_FIELDS:
            raise ValueError(f"uncertain: {self.name!r} is neither a crane field a sweep can vary "
                             f"(load_mass, gravity, <actuator>.friction.<field>, "
                             f"<actuator>.hydraulics.<number>: cranepredict.api.VARY_FIELDS) nor "
                             f"state.<{'|'.join(STATE_OFFSETS)}>")
        if self.distribution not in DISTRIBUTIONS:
            raise ValueError(f"{where}: the distribution must be one of {DISTRIBUTIONS}, got "
                             f"{self.distribution!r}")
        a = _number(self.a, f"{where}.{self.distribution}[0]")
        b = _number(self.b, f"{where}.{self.distribution}[1]")
        if not (math.isfinite(a) and math.isfinite(b)):
            raise ValueError(f"{where}.{self.distribution} must be finite, got [{a}, {b}]")
        if self.distribution == "uniform" and not a <= b:
            raise ValueError(f"{where}.uniform = [low, high] must have low <= high, got [{a}, {b}]")
        if self.distribution == "normal" and not b >= 0:
            raise ValueError(f"{where}.normal = [mean, sd] must have sd >= 0, got [{a}, {b}]")
        if self.relative and not self.bounds()[0] > -1:
            raise ValueError(f"{where}: a relative draw must stay above -1 (the value's sign would "
                             f"flip), got a lowest draw of {self.bounds()[0]:g}")
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "b", b)

    @property
    def is_state(self) -> bool:
        return self.name.startswith("state.")

    def bounds(self) -> Tuple[float, float]:
        """The lowest and highest draw."""
        if self.distribution == "uniform":
            return self.a, self.b
        return self.a - NORMAL_CLIP * self.b, self.a + NORMAL_CLIP * self.b

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        if self.distribution == "uniform":
            return rng.uniform(self.a, self.b, n)
        lo, hi = self.bounds()
        return np.clip(rng.normal(self.a, self.b, n), lo, hi)

    def value(self, nominal: float, draw: np.ndarray) -> np.ndarray:
        """The crane field's value for these draws (relative: nominal (1 + draw))."""
        return nominal * (1.0 + draw) if self.relative else np.asarray(draw, dtype=float)


@dataclass(frozen=True)
class Case:
    """A start and a command: the twin's measured state and the operator's inputs."""

    name: str
    initial: State
    inputs: Inputs


@dataclass(frozen=True, eq=False)
class Study:
    """An uncertainty study (docs/sweep.md): every sample draws a case and the uncertain parameters.

    ``margin``, ``reaction``, ``cycle`` and ``dt`` are the twin's guard settings (margin: the
    world's unless given; a larger one is what a study may recommend); a real crane's contact is
    always judged against the world's margin, the site's rule. ``target`` is the miss rate the
    summary sizes a margin for. ``chunk`` samples run together (one task on a cluster)."""

    name: str
    crane: Crane
    world: World
    horizon: float
    cases: Tuple[Case, ...]
    uncertain: Tuple[Uncertain, ...]
    samples: int
    seed: int
    chunk: int = 100
    target: float = 0.01
    margin: Optional[float] = None
    reaction: float = DEFAULT_REACTION
    cycle: float = DEFAULT_CYCLE
    dt: float = api.DEFAULT_DT
    description: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.crane, Crane):
            raise TypeError(f"crane must be a cranepredict.Crane, got {type(self.crane).__name__}")
        if not isinstance(self.world, World):
            raise TypeError(f"world must be a cranepredict.World, got {type(self.world).__name__}")
        if not self.world.obstacles:
            raise ValueError(f"world {self.world.name!r} has no obstacles: a study measures the "
                             "crane against them")
        for name, low, high in (("samples", 1, MAX_SAMPLES), ("seed", 0, 2 ** 63 - 1),
                                ("chunk", 1, MAX_CHUNK)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
                    or not low <= value <= high:
                raise ValueError(f"{name} must be an int in [{low:,}, {high:,}], got {value!r}")
            object.__setattr__(self, name, int(value))
        checks = (("horizon", 0.0, False, math.inf), ("target", 0.0, False, 1.0),
                  ("reaction", 0.0, True, math.inf), ("cycle", 0.0, False, math.inf),
                  ("dt", 0.0, False, math.inf))
        for name, low, closed, high in checks:
            v = _number(getattr(self, name), name)
            if not (math.isfinite(v) and (v >= low if closed else v > low) and v < high):
                raise ValueError(f"{name} must be in {'[' if closed else '('}{low:g}, {high:g}), "
                                 f"got {v:g}")
            object.__setattr__(self, name, v)
        if self.dt > self.horizon:
            raise ValueError(f"guard.dt must be in (0, horizon] = (0, {self.horizon:g}] s, got "
                             f"{self.dt:g}")
        if self.margin is not None:
            m = _number(self.margin, "guard.margin")
            if not (math.isfinite(m) and m >= 0):
                raise ValueError(f"guard.margin must be >= 0 m and finite, got {m:g}")
            object.__setattr__(self, "margin", m)
        cases = tuple(self.cases)
        if not cases or not all(isinstance(c, Case) for c in cases):
            raise ValueError("case: a study needs at least one case (a [[case]] table: initial and "
                             "inputs, or a scenario)")
        object.__setattr__(self, "cases", cases)
        unc = tuple(sorted(self.uncertain, key=lambda u: u.name))
        names = [u.name for u in unc]
        if len(set(names)) != len(names):
            raise ValueError(f"uncertain: a parameter is named twice: {names}")
        object.__setattr__(self, "uncertain", unc)
        if self.crane.shape is None:
            raise ValueError(f"crane {self.crane.name!r} has no [shape] table: the guard needs "
                             "the parts' sizes (docs/guard.md)")
        _check_ends(self)

    @property
    def guard_margin(self) -> float:
        return self.world.margin if self.margin is None else float(self.margin)

    @property
    def parameters(self) -> Tuple[str, ...]:
        return tuple(u.name for u in self.uncertain)

    @property
    def n_chunks(self) -> int:
        return -(-self.samples // self.chunk)

    def with_run(self, samples: Optional[int] = None, seed: Optional[int] = None) -> "Study":
        """The study with another number of samples or seed (the CLI's --samples, --seed)."""
        changes = {k: v for k, v in (("samples", samples), ("seed", seed)) if v is not None}
        return dataclasses.replace(self, **changes) if changes else self

    def nominal(self, u: Uncertain) -> float:
        """The crane file's value of an uncertain crane field (0 for a state offset)."""
        if u.is_state:
            return 0.0
        node: Any = self.crane
        for part in u.name.split("."):
            node = getattr(node, part)
        return float(node)

    def fingerprint(self) -> str:
        """A digest of everything that decides the table (not the number of samples): a folder
        of chunks belongs to the study with this fingerprint."""
        with np.printoptions(threshold=sys.maxsize, floatmode="unique"):
            text = repr((self.crane.to_dict(), self.world.name, self.world.margin,
                         [o.to_plain() for o in self.world.obstacles], self.horizon,
                         [(c.name, repr(c.initial), repr(c.inputs)) for c in self.cases],
                         self.uncertain, self.seed, self.chunk, self.guard_margin, self.reaction,
                         self.cycle, self.dt))
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    @classmethod
    def from_toml(cls, path: Union[str, Path]) -> "Study":
        """A study file (TOML); a crane or world file it names is found next to it. Errors name
        the file and the field."""
        path = Path(path)
        try:
            text = path.read_text("utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise ValueError(f"study file {str(path)!r}: {getattr(exc, 'strerror', None) or exc}") \
                from None
        try:
            return cls.from_toml_string(text, base=path.parent, default_name=path.stem)
        except (ValueError, TypeError) as exc:
            raise _same_kind(exc)(f"{path}: {exc}") from None

    @classmethod
    def from_toml_string(cls, text: str, base: Union[str, Path] = ".",
                         default_name: str = "study") -> "Study":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"study file is not valid TOML: {exc}") from None
        return cls.from_dict(data, base=base, default_name=default_name)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], base: Union[str, Path] = ".",
                  default_name: str = "study") -> "Study":
        from . import scenarios

        unknown = sorted(set(data) - set(_FIELDS))
        if unknown:
            raise ValueError(f"study: unknown field(s) {', '.join(unknown)}; allowed: "
                             f"{', '.join(_FIELDS)}")
        for name in ("horizon", "samples", "seed", "world"):
            if name not in data:
                raise ValueError(f"study: {name} is missing")
        crane = _crane(data.get("crane", "patu655"), Path(base))
        if "load_mass" in data:
            crane = crane.with_load(data["load_mass"])
        world = _world(data["world"], Path(base))
        settings = data.get("guard", {})
        if not isinstance(settings, Mapping):
            raise TypeError("study: guard must be a table")
        bad = sorted(set(settings) - set(_GUARD_FIELDS))
        if bad:
            raise ValueError(f"study: unknown field(s) guard.{', guard.'.join(bad)}; allowed: "
                             f"{', '.join('guard.' + f for f in _GUARD_FIELDS)}")
        raw_cases = data.get("case", [])
        if not isinstance(raw_cases, list) or not raw_cases:
            raise ValueError("study: case must be one or more [[case]] tables (initial and inputs, "
                             "or scenario = \"name\")")
        cases = []
        for i, table in enumerate(raw_cases):
            where = f"case[{i}]"
            if not isinstance(table, Mapping):
                raise TypeError(f"study: {where} must be a table")
            extra = sorted(set(table) - {"name", "scenario", "initial", "inputs"})
            if extra:
                raise ValueError(f"study: unknown field(s) {where}.{', '.join(extra)}; allowed: "
                                 "name, scenario, or initial and inputs")
            name = str(table.get("name", table.get("scenario", f"case {i}")))
            if "scenario" in table:
                if "initial" in table or "inputs" in table:
                    raise ValueError(f"study: {where} takes either scenario or initial and inputs")
                sc = scenarios.get(table["scenario"])
                cases.append(Case(name, sc.initial, sc.inputs))
                continue
            if "initial" not in table or "inputs" not in table:
                raise ValueError(f"study: {where} needs initial and inputs tables (or scenario)")
            initial, inputs = scenarios.start_and_command(crane, table["initial"], table["inputs"],
                                                          f"{where}")
            cases.append(Case(name, initial, inputs))
        raw_unc = data.get("uncertain", {})
        if not isinstance(raw_unc, Mapping):
            raise TypeError("study: uncertain must be a table of parameters")
        uncertain = [_uncertain(name, spec) for name, spec in raw_unc.items()]
        return cls(name=str(data.get("name", default_name)), crane=crane, world=world,
                   horizon=data["horizon"], cases=tuple(cases), uncertain=tuple(uncertain),
                   samples=data["samples"], seed=data["seed"], chunk=data.get("chunk", 100),
                   target=data.get("target", 0.01), margin=settings.get("margin"),
                   reaction=settings.get("reaction", DEFAULT_REACTION),
                   cycle=settings.get("cycle", DEFAULT_CYCLE),
                   dt=settings.get("dt", api.DEFAULT_DT),
                   description=str(data.get("description", "")))


def _uncertain(name: str, spec: Any) -> Uncertain:
    where = f"uncertain.{name}"
    if not isinstance(spec, Mapping):
        raise TypeError(f"{where} must be a table, e.g. {{ uniform = [-0.2, 0.2], relative = true }}")
    kinds = [k for k in DISTRIBUTIONS if k in spec]
    extra = sorted(set(spec) - set(DISTRIBUTIONS) - {"relative"})
    if extra or len(kinds) != 1:
        raise ValueError(f"{where} must have one of uniform = [low, high] or normal = [mean, sd], "
                         f"and optionally relative = true; got {sorted(spec)}")
    pair = spec[kinds[0]]
    if not isinstance(pair, list) or len(pair) != 2:
        raise ValueError(f"{where}.{kinds[0]} must be a list of two numbers, got {pair!r}")
    relative = spec.get("relative", False)
    if not isinstance(relative, bool):
        raise TypeError(f"{where}.relative must be true or false, got {relative!r}")
    return Uncertain(name, kinds[0], pair[0], pair[1], relative)


def _crane(ref: Any, base: Path) -> Crane:
    if not isinstance(ref, str):
        raise TypeError(f"study: crane must be a crane name or a crane file, got {ref!r}")
    path = base / ref
    if ref.endswith(".toml") and path.is_file():
        return Crane.from_toml(path)
    from importlib import resources

    packaged = resources.files("cranepredict").joinpath(f"cranes/{ref}.toml")
    if packaged.is_file():
        return Crane.from_toml_string(packaged.read_text("utf-8"))
    raise ValueError(f"study: crane {ref!r} is neither a crane file next to the study nor a crane "
                     "of the package (patu655)")


def _world(ref: Any, base: Path) -> World:
    from . import world as world_mod

    if not isinstance(ref, str):
        raise TypeError(f"study: world must be a world name or a world file, got {ref!r}")
    path = base / ref
    if ref.endswith(".toml") and path.is_file():
        return World.from_toml(path)
    if ref in world_mod.names():
        return world_mod.get(ref)
    raise ValueError(f"study: world {ref!r} is neither a world file next to the study nor an "
                     f"example world ({', '.join(world_mod.names())})")


def _check_ends(study: Study) -> None:
    """Every combination of the distributions' ends, on every case, passes the checks of
    predict_many (one step): a study never stops half way on a value it drew."""
    crane_unc = [u for u in study.uncertain if not u.is_state]
    state_unc = [u for u in study.uncertain if u.is_state]
    corners = list(itertools.product(*[u.bounds() for u in crane_unc])) \
        if len(crane_unc) <= 10 else [tuple(u.bounds()[i] for u in crane_unc) for i in (0, 1)]
    offsets = list(itertools.product(*[u.bounds() for u in state_unc])) \
        if len(state_unc) <= 4 else [tuple(u.bounds()[i] for u in state_unc) for i in (0, 1)]
    rows = [(case, c, o) for case in study.cases for c in corners for o in offsets]
    vary = {u.name: np.array([u.value(study.nominal(u), np.float64(c[j])) for _, c, _ in rows])
            for j, u in enumerate(crane_unc)}
    initials = [_offset(case.initial, state_unc, o) for case, _, o in rows]
    try:
        api.predict_many(study.crane, initials, [case.inputs for case, _, _ in rows], study.dt,
                         dt=study.dt, vary=vary or None, threads=1)
    except (ValueError, TypeError) as exc:
        k = _future_index(str(exc))
        where = ""
        if k is not None:
            case, c, o = rows[k]
            ends = [f"{u.name} = {v:g}" for u, v in zip(crane_unc, [float(vary[u.name][k])
                                                                    for u in crane_unc])]
            ends += [f"{u.name} offset {v:g}" for u, v in zip(state_unc, o)]
            where = f" (case {case.name!r}{', ' if ends else ''}{', '.join(ends)})"
        raise _same_kind(exc)(f"uncertain: the distributions' ends give an invalid "
                              f"future{where}: {exc}") from None


def _same_kind(exc: Exception) -> type:
    """ValueError or TypeError, as ``exc`` is (its own class may take other arguments)."""
    return ValueError if isinstance(exc, ValueError) else TypeError


def _future_index(text: str) -> Optional[int]:
    import re

    m = re.match(r"(?:predict_many \()?future (\d+)", text)
    return int(m.group(1)) if m else None


def _offset(state: State, unc: Sequence[Uncertain], draws: Sequence[float]) -> State:
    if not unc:
        return state
    return dataclasses.replace(state, **{u.name[6:]: getattr(state, u.name[6:]) + float(d)
                                         for u, d in zip(unc, draws)})


def load_study(spec: Union[str, Path, Study]) -> Study:
    """A study: a Study as it is, a study file, or the name of an example study of the package
    (:func:`cranepredict.studies.names`)."""
    from . import studies

    if isinstance(spec, Study):
        return spec
    if not isinstance(spec, (str, Path)):
        raise TypeError(f"study must be a Study, a study file or an example's name, got "
                        f"{type(spec).__name__}")
    if Path(spec).is_file():
        return Study.from_toml(spec)
    if str(spec) in studies.names():
        return studies.get(str(spec))
    raise ValueError(f"study {str(spec)!r}: no such file, and not an example study "
                     f"({', '.join(studies.names())})")


# -- the twin's decision per case ---------------------------------------------------------------------

@dataclass(frozen=True)
class Nominal:
    """What the twin with the nominal parameters said for each case: the signal (index into
    SIGNALS), when its decision stops the crane (s: WARN its latest stop time, STOP at once, 0;
    nan: GO, never), the obstacle of its first contact (-1: none), and that decision's clearance
    per obstacle (m) for the nominal crane."""

    signal: np.ndarray
    stop_time: np.ndarray
    obstacle: np.ndarray
    policy_clearance: np.ndarray
    reasons: Tuple[str, ...]


def _decisions(study: Study, margin: float) -> Tuple[List[Any], np.ndarray]:
    """The twin's verdict per case with the guard margin ``margin`` and the time its decision
    stops the crane (nan: GO)."""
    verdicts, stop_time = [], []
    for case in study.cases:
        v = guard(study.crane, study.world, case.initial, case.inputs, study.horizon, dt=study.dt,
                  reaction=study.reaction, cycle=study.cycle, margin=margin)
        verdicts.append(v)
        stop_time.append(math.nan if v.signal == "GO" else
                         0.0 if v.signal == "STOP" else float(v.stop.latest))
    return verdicts, np.array(stop_time)


def _nominal(study: Study) -> Nominal:
    verdicts, stop_time = _decisions(study, study.guard_margin)
    names = study.world.names
    n = len(study.cases)
    draws = np.zeros((n, len(study.uncertain)))
    for j, u in enumerate(study.uncertain):   # the nominal value: draw 0, or nominal absolute
        if not u.is_state and not u.relative:
            draws[:, j] = study.nominal(u)
    rows = _evaluate(study, np.arange(n), draws, stop_time, threads=1, latest=False)
    return Nominal(signal=np.array([SIGNALS.index(v.signal) for v in verdicts], dtype=np.int8),
                   stop_time=stop_time,
                   obstacle=np.array([names.index(v.contact.obstacle) if v.contact is not None
                                      else -1 for v in verdicts], dtype=np.int32),
                   policy_clearance=rows["policy_clearance"],
                   reasons=tuple(v.reason for v in verdicts))


# -- one chunk ----------------------------------------------------------------------------------------

def _sample_every(study: Study) -> int:
    return max(1, int(round(GUARD_SPACING / study.dt)))


def _fields(traj: Any) -> Dict[str, np.ndarray]:
    t = traj.t
    return {name: np.broadcast_to(getattr(traj, name), t.shape if name in
                                  ("slew", "extension", "slew_rate", "extension_rate")
                                  else getattr(traj, name).shape) for name in SAMPLE_FIELDS}


def _evaluate(study: Study, cases: np.ndarray, draws: np.ndarray, stop_time: np.ndarray,
              threads: Optional[int], latest: bool = True) -> Dict[str, np.ndarray]:
    """The real cranes of these rows (case index, draws of study.uncertain): under their command,
    per obstacle the first contact and the smallest clearance; under the decision that stops them
    at stop_time (nan: not at all) the same; and (``latest``) each one's own latest stop time."""
    n, names = len(cases), study.world.names
    crane_unc = [(j, u) for j, u in enumerate(study.uncertain) if not u.is_state]
    state_unc = [(j, u) for j, u in enumerate(study.uncertain) if u.is_state]
    vary = {u.name: u.value(study.nominal(u), draws[:, j]) for j, u in crane_unc}
    initials = [_offset(study.cases[c].initial, [u for _, u in state_unc],
                        [draws[k, j] for j, _ in state_unc]) for k, c in enumerate(cases)]
    inputs = [study.cases[c].inputs for c in cases]
    every = _sample_every(study)
    batch = api.predict_many(study.crane, initials, inputs, study.horizon, dt=study.dt,
                             sample_every=every, threads=threads, vary=vary or None)
    margin = study.world.margin
    t_contact = np.full((n, len(names)), math.inf)
    clearance = np.empty((n, len(names)))
    policy_t = np.full((n, len(names)), math.inf)
    policy_clearance = np.empty((n, len(names)))
    settled = np.ones(n, dtype=bool)
    commands = [batch[k] for k in range(n)]
    for k in range(n):
        t_contact[k], clearance[k] = obstacle_clearances(study.crane, study.world,
                                                         _fields(commands[k]), margin=margin)
    # the decision's stop: the valves to neutral from the first judged sample at or after
    # stop_time + reaction (as the guard's latest stop time means), followed until settled
    t = batch.t
    effect = {k: int(np.searchsorted(t, stop_time[k] + study.reaction - 1e-12)) for k in range(n)
              if math.isfinite(stop_time[k])}
    stops = {k: m for k, m in effect.items() if m < len(t)}
    pieces = _follow_stops(study, stops, commands, inputs, vary, every, threads)
    first = t_contact.min(axis=1)
    hint = {}   # row -> (the decision's stop sample, whether that stop kept the margin)
    for k, m in effect.items():
        i = int(np.searchsorted(t, stop_time[k] - 1e-12))
        piece = pieces.get(k)
        hint[k] = (i, m < len(t) and t[m] < first[k] and piece is not None and piece[1]
                   and not piece[2])
    for k in range(n):
        if k not in pieces:
            policy_t[k], policy_clearance[k] = t_contact[k], clearance[k]
            settled[k] = k not in stops   # a stop that could not be predicted: not settled
            continue
        piece, settled[k], _ = pieces[k]
        m = stops[k]
        head, tail = _fields(commands[k]), _fields(piece)
        joined = {f: np.concatenate([head[f][:m + 1], tail[f][1:] + (t[m] if f == "t" else 0.0)])
                  for f in SAMPLE_FIELDS}
        policy_t[k], policy_clearance[k] = obstacle_clearances(study.crane, study.world, joined,
                                                               margin=margin)
    out = {"t_contact": t_contact, "clearance": clearance, "policy_t": policy_t,
           "policy_clearance": policy_clearance, "stop_settled": settled}
    if latest:
        out["latest"] = _latest_stops(study, commands, inputs, vary, every, first, threads, hint)
    return out


def _follow_stops(study: Study, stops: Dict[int, int], commands: List[Any], inputs: List[Inputs],
                  vary: Dict[str, np.ndarray], every: int,
                  threads: Optional[int]) -> Dict[int, Tuple[Any, bool, bool]]:
    """Row -> (the stop's prediction from sample m = stops[row] of its command, settled, contact
    within the world's margin): pieces of DEFAULT_STOP_HORIZON s, twice as long for those neither
    settled nor in contact, at most STOP_FOLLOW_MAX s (the guard's rule: guard.stop_settled). A
    start the core refuses has no entry (the guard counts that stop as unsafe)."""
    out: Dict[int, Tuple[Any, bool, bool]] = {}
    starts = {}
    for k in sorted(stops):
        try:
            starts[k] = stop_state(commands[k], stops[k], inputs[k])
        except ValueError:
            pass
    rows = sorted(starts)
    horizon = DEFAULT_STOP_HORIZON
    while rows:
        sub = {name: values[rows] for name, values in vary.items()}
        pb = api.predict_many(study.crane, [starts[k] for k in rows],
                              [stop_inputs(inputs[k]) for k in rows], horizon, dt=study.dt,
                              sample_every=every, threads=threads, vary=sub or None)
        pending = []
        for j, k in enumerate(rows):
            piece = pb[j]
            first, _ = obstacle_clearances(study.crane, study.world, _fields(piece),
                                           margin=study.world.margin, per_obstacle=False)
            contact = bool(np.isfinite(first[0]))
            done = stop_settled(piece, DEFAULT_STOP_HORIZON)
            out[k] = (piece, done, contact)
            if not (done or contact) and horizon < STOP_FOLLOW_MAX - 1e-9:
                pending.append(k)
        rows, horizon = pending, min(2 * horizon, STOP_FOLLOW_MAX)
    return out


def _latest_stops(study: Study, commands: List[Any], inputs: List[Inputs],
                  vary: Dict[str, np.ndarray], every: int, first: np.ndarray,
                  threads: Optional[int], hint: Dict[int, Tuple[int, bool]]) -> np.ndarray:
    """Each real crane's own latest stop time (s; the guard's, judged against the world's margin:
    the last judged sample from which the valves to neutral, taking effect ``reaction`` later, keep
    the margin; -inf: not even stopping now does; nan: no contact to stop for). The boundary the
    guard's bisection finds (a later stop is never safer), searched in step over the rows so that
    each round is one batch: from ``hint`` (row -> a sample whose stop is known safe or not: the
    twin's decision) outwards in doubling steps, then by bisection; without one, by bisection."""
    n = len(commands)
    latest = np.full(n, math.nan)
    rows = [k for k in range(n) if math.isfinite(first[k])]
    if not rows:
        return latest
    t = commands[0].t

    def safe(at: Dict[int, int]) -> Dict[int, bool]:
        stops, ok = {}, {}
        for row, k in at.items():
            m = int(np.searchsorted(t, t[k] + study.reaction - 1e-12))
            if m >= len(t) or t[m] >= first[row]:
                ok[row] = False
            else:
                stops[row] = m
        pieces = _follow_stops(study, stops, commands, inputs, vary, every, threads)
        for row in stops:
            piece = pieces.get(row)
            ok[row] = piece is not None and piece[1] and not piece[2]
        return ok

    # per row: [lo: safe (-1: none known), hi: unsafe (or past the contact), step, direction]
    state = {}
    for k in rows:
        top = int(np.searchsorted(t, first[k] - study.reaction, side="right"))
        if k in hint and hint[k][0] < top:
            i, ok = hint[k]
            state[k] = [i, top, 1, 1] if ok else [-1, i, 1, -1]
        else:
            state[k] = [-1, top, 1, 0]
    while True:
        probe = {}
        for k, (lo, hi, step, way) in state.items():
            if hi - lo <= 1:
                continue
            p = lo + step if way > 0 else hi - step if way < 0 else -1
            if not lo < p < hi:
                state[k][3] = way = 0
                p = (lo + hi) // 2 if lo >= 0 else 0   # the guard tries stopping now first
            probe[k] = p
        if not probe:
            break
        for k, ok in safe(probe).items():
            st, p = state[k], probe[k]
            if ok:
                st[0] = p
                st[2], st[3] = (st[2] * 2, 1) if st[3] > 0 else (st[2], 0)
            else:
                st[1] = p
                st[2], st[3] = (st[2] * 2, -1) if st[3] < 0 else (st[2], 0)
    for k, (lo, _, _, _) in state.items():
        latest[k] = t[lo] if lo >= 0 else -math.inf
    return latest


def _chunk_rows(study: Study, index: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(sample numbers, case indices, draws) of chunk ``index``, from its own seed."""
    lo = index * study.chunk
    n = min(study.chunk, study.samples - lo)
    rng = np.random.default_rng(np.random.SeedSequence(study.seed, spawn_key=(index,)))
    cases = rng.integers(0, len(study.cases), n)
    draws = np.column_stack([u.draw(rng, n) for u in study.uncertain]) if study.uncertain \
        else np.zeros((n, 0))
    return np.arange(lo, lo + n, dtype=np.int64), cases.astype(np.int32), draws


def run_chunk(study: Study, nominal: Nominal, index: int,
              threads: Optional[int] = 1) -> Dict[str, np.ndarray]:
    """The table rows of chunk ``index`` (what a Dask task computes)."""
    samples, cases, draws = _chunk_rows(study, index)
    rows = _evaluate(study, cases, draws, nominal.stop_time[cases], threads)
    contact = np.isfinite(rows["t_contact"]).any(axis=1)
    latest = rows["latest"]
    signal = np.where(~contact, 0, np.where(latest < study.cycle, 2, 1)).astype(np.int8)
    return {"sample": samples, "case": cases, "draws": draws,
            "signal": signal, "latest": latest,
            "t_contact": rows["t_contact"], "clearance": rows["clearance"],
            "policy_clearance": rows["policy_clearance"],
            "missed": np.isfinite(rows["policy_t"]),
            "needless_stop": (nominal.signal[cases] != 0) & ~contact,
            "nominal_signal": nominal.signal[cases],
            "stop_settled": rows["stop_settled"]}


# -- results --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ObstacleSummary:
    """One obstacle over the samples: the fraction of real cranes that come within the world's
    margin of it under the command (contact_rate) and under the twin's decision (miss_rate: the
    contacts the nominal verdict missed); of needless stops the twin made for it (it predicted
    its first contact with this obstacle; the real crane under the command touched nothing); and
    the clearance under the decision at the 1 %, 5 % and 50 % quantiles (m)."""

    name: str
    contact_rate: float
    miss_rate: float
    needless_stop_rate: float
    clearance_quantiles: Tuple[float, float, float]


@dataclass(frozen=True)
class Summary:
    """The study's answer: per obstacle (ObstacleSummary) and over all obstacles, with the guard
    margin that keeps the miss rate at or below ``target`` (m; inf: none up to MARGIN_SEARCH m
    more does) and the miss rate against the guard margin (``margin_curve``: (margin, rate))."""

    samples: int
    target: float
    guard_margin: float
    world_margin: float
    miss_rate: float
    needless_stop_rate: float
    margin_for_target: float
    margin_curve: Tuple[Tuple[float, float], ...]
    obstacles: Tuple[ObstacleSummary, ...]
    nominal: Tuple[Tuple[str, str, str], ...]   # (case, signal, reason)

    def to_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["margin_for_target"] = self.margin_for_target if math.isfinite(self.margin_for_target) \
            else None
        return json.loads(json.dumps(d, default=float))

    def text(self) -> str:
        pct = 100.0
        lines = [f"the twin (nominal parameters, guard margin {self.guard_margin:g} m) per case:"]
        for case, signal, reason in self.nominal:
            lines.append(f"  {case}: {signal}: {reason}")
        lines.append(f"{self.samples:,} real cranes (sampled parameters) under the twin's decision, "
                     f"judged against the world's margin {self.world_margin:g} m:")
        lines.append(f"  {'obstacle':16s} {'contact':>8s} {'missed':>8s} {'needless':>9s}   "
                     f"clearance 1% / 5% / 50% (m)")
        for o in self.obstacles:
            q = " / ".join(f"{v:.3f}" for v in o.clearance_quantiles)
            lines.append(f"  {o.name:16s} {o.contact_rate * pct:7.2f}% {o.miss_rate * pct:7.2f}% "
                         f"{o.needless_stop_rate * pct:8.2f}%   {q}")
        margin = (f"a guard margin of {self.margin_for_target:.2f} m" if
                  math.isfinite(self.margin_for_target) else
                  f"no guard margin up to {self.guard_margin + MARGIN_SEARCH:g} m")
        lines.append(f"all obstacles: {self.miss_rate * pct:.2f} % missed, "
                     f"{self.needless_stop_rate * pct:.2f} % needless stops; {margin} keeps the "
                     f"misses at or below {self.target * pct:g} %")
        return "\n".join(lines)


#: How far above the study's guard margin the summary looks for one that meets the target, m, and
#: how closely it locates it.
MARGIN_SEARCH = 5.0
MARGIN_RESOLUTION = 0.01


def _miss_rate(study: Study, table: Mapping[str, np.ndarray], margin: float,
               cache: Dict[float, float]) -> float:
    """The fraction of samples whose contact the twin's decision with this guard margin misses:
    the real crane touches (under the command) and the decision is GO, or stops it later than its
    own latest stop time (a later stop is never safer: the guard's rule)."""
    if margin not in cache:
        _, stop_time = _decisions(study, margin)
        t = stop_time[table["case"]]
        contact = np.isfinite(table["t_contact"]).any(axis=1)
        with np.errstate(invalid="ignore"):
            late = np.isnan(t) | (t > table["latest"])
        cache[margin] = float((contact & late).mean())
    return cache[margin]


def _margin_search(study: Study, table: Mapping[str, np.ndarray]
                   ) -> Tuple[float, Tuple[Tuple[float, float], ...]]:
    """The smallest guard margin (to MARGIN_RESOLUTION) whose decisions miss at most the target
    fraction of contacts, and the miss rate on a grid of margins up to it (for the figure)."""
    cache: Dict[float, float] = {}
    lo = study.guard_margin

    def rate(m: float) -> float:
        return _miss_rate(study, table, round(m, 6), cache)

    found = math.inf
    if rate(lo) <= study.target:
        found = lo
    else:
        step, hi = 0.25, None
        m = lo
        while m < lo + MARGIN_SEARCH - 1e-9:
            m = min(m + step, lo + MARGIN_SEARCH)
            if rate(m) <= study.target:
                hi = m
                break
            step *= 2
        if hi is not None:
            a = max(lo, hi - step)
            while hi - a > MARGIN_RESOLUTION:
                mid = 0.5 * (a + hi)
                if rate(mid) <= study.target:
                    hi = mid
                else:
                    a = mid
            found = math.ceil(hi / MARGIN_RESOLUTION - 1e-9) * MARGIN_RESOLUTION
    top = found if math.isfinite(found) else lo + MARGIN_SEARCH
    grid = np.linspace(lo, max(top * 1.25 - 0.25 * lo, lo + 0.2), 12)
    for m in grid:
        rate(float(m))
    curve = tuple(sorted((m, r) for m, r in cache.items()))
    return found, curve


def summarize(study: Study, nominal: Nominal, table: Mapping[str, np.ndarray]) -> Summary:
    """The summary of a table (:attr:`SweepResult.table`)."""
    names = study.world.names
    case = table["case"]
    missed, clear = table["missed"], table["policy_clearance"]
    per = []
    for i, name in enumerate(names):
        per.append(ObstacleSummary(
            name=name, contact_rate=float(np.isfinite(table["t_contact"][:, i]).mean()),
            miss_rate=float(missed[:, i].mean()),
            needless_stop_rate=float((table["needless_stop"] & (nominal.obstacle[case] == i)).mean()),
            clearance_quantiles=tuple(float(q) for q in np.quantile(clear[:, i], (0.01, 0.05, 0.5)))))
    found, curve = _margin_search(study, table)
    return Summary(samples=len(case), target=study.target, guard_margin=study.guard_margin,
                   world_margin=study.world.margin, miss_rate=float(missed.any(axis=1).mean()),
                   needless_stop_rate=float(table["needless_stop"].mean()),
                   margin_for_target=found, margin_curve=curve, obstacles=tuple(per),
                   nominal=tuple((c.name, SIGNALS[int(s)], r) for c, s, r in
                                 zip(study.cases, nominal.signal, nominal.reasons)))


@dataclass(frozen=True, eq=False)
class SweepResult:
    """A finished study: the table (one row per sample, in sample order; per-obstacle columns in
    the world's order), its summary and where it was written.

    Table columns: ``sample``; ``case`` (index into study.cases); ``draws`` (samples x parameters,
    study.parameters' order: the draw, i.e. the value, the relative change or the offset);
    ``signal`` (the real crane's own verdict, index into SIGNALS) and ``latest`` (its latest stop
    time, s; -inf: too late at t = 0; nan: no contact); ``t_contact`` (s, first time within the
    world's margin under the command; inf: none) and ``clearance`` (m, smallest) per obstacle;
    ``policy_clearance`` (m, smallest under the twin's decision) and ``missed`` (within the margin
    under it) per obstacle; ``needless_stop``; ``nominal_signal`` (the twin's verdict);
    ``stop_settled`` (the decision's stop came to rest within STOP_FOLLOW_MAX s).

    ``seconds``: the whole run; ``chunk_seconds``: from the first chunk's start to the last one's
    end, for the ``computed_chunks`` with ``computed_futures`` (the others were read from ``out``):
    computed_futures / chunk_seconds is the study's rate."""

    study: Study
    nominal: Nominal
    table: Dict[str, np.ndarray] = field(repr=False)
    summary: Summary
    out: Optional[Path]
    seconds: float
    computed_chunks: int
    where: str
    chunk_seconds: float = 0.0
    computed_futures: int = 0

    def values(self, name: str) -> np.ndarray:
        """The sampled values of an uncertain parameter (crane fields: the value; state: the
        offset)."""
        j = self.study.parameters.index(name)
        u = self.study.uncertain[j]
        return u.value(self.study.nominal(u), self.table["draws"][:, j])

    def plot(self, path: Union[str, Path]) -> Path:
        """The summary's figure (needs matplotlib, the [plot] extra): plot.sweep_figure."""
        from . import plot

        return plot.sweep_plot(self, Path(path))


# -- running --------------------------------------------------------------------------------------------

COLUMNS = ("sample", "case", "draws", "signal", "latest", "t_contact", "clearance",
           "policy_clearance", "missed", "needless_stop", "nominal_signal", "stop_settled")


class _Store:
    """A folder of chunk files (chunk-00000.npz ...) and the study's manifest (study.json)."""

    def __init__(self, out: Path, study: Study) -> None:
        self.out = out
        out.mkdir(parents=True, exist_ok=True)
        manifest = {"name": study.name, "fingerprint": study.fingerprint(),
                    "samples": study.samples, "seed": study.seed, "chunk": study.chunk,
                    "parameters": list(study.parameters), "obstacles": list(study.world.names),
                    "cases": [c.name for c in study.cases], "columns": list(COLUMNS)}
        path = out / "study.json"
        if path.exists():
            old = json.loads(path.read_text("utf-8"))
            for key in ("name", "samples", "seed", "chunk", "fingerprint"):
                if old.get(key) != manifest[key]:
                    raise ValueError(f"--out {str(out)!r} holds the chunks of another study "
                                     f"({key} {old.get(key)!r}, not {manifest[key]!r}): choose "
                                     f"another folder or remove it")
        else:
            path.write_text(json.dumps(manifest, indent=1), "utf-8")

    def path(self, index: int) -> Path:
        return self.out / f"chunk-{index:05d}.npz"

    def load(self, index: int) -> Optional[Dict[str, np.ndarray]]:
        p = self.path(index)
        if not p.exists():
            return None
        with np.load(p) as f:
            return {k: f[k] for k in COLUMNS}

    def write(self, index: int, rows: Mapping[str, np.ndarray]) -> None:
        """Atomically: a chunk file is complete or absent (an interrupted write leaves a .tmp)."""
        tmp = self.out / f".chunk-{index:05d}.npz.tmp"
        with open(tmp, "wb") as f:
            np.savez(f, **rows)
        os.replace(tmp, self.path(index))


class _Progress:
    """A one-line progress bar on stderr."""

    def __init__(self, total: int, futures: int, enabled: bool) -> None:
        self.total, self.futures, self.enabled = total, futures, enabled
        self.done = 0
        self.start = time.perf_counter()

    def update(self, chunks: int, futures: int) -> None:
        self.done += chunks
        if not self.enabled:
            return
        width = 30
        filled = int(width * self.done / max(self.total, 1))
        rate = futures / max(time.perf_counter() - self.start, 1e-9)
        sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} "
                         f"chunks, {rate:,.0f} futures/s ")
        sys.stderr.flush()

    def close(self) -> None:
        if self.enabled:
            sys.stderr.write("\n")


def _dask_client(scheduler: Any, workers: Optional[int]) -> Tuple[Any, List[Any], str]:
    """(client, things to close afterwards, description) for a scheduler: a Client as it is, an
    address, or None for a LocalCluster of ``workers`` processes (default: the cores)."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise ValueError("running a study on Dask needs the [sweep] extra: pip install "
                         "'cranepredict[sweep]' (or run it in this process: --in-process)") from None
    if isinstance(scheduler, Client):
        return scheduler, [], f"on the Dask scheduler {scheduler.scheduler.address}"
    if isinstance(scheduler, str):
        client = Client(scheduler)
        return client, [client], f"on the Dask scheduler {scheduler}"
    if scheduler is not None:
        raise TypeError(f"scheduler must be None, 'in-process', an address or a "
                        f"distributed.Client, got {type(scheduler).__name__}")
    n = workers or os.cpu_count() or 1
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    client = Client(cluster)
    return client, [client, cluster], f"on a Dask LocalCluster of {n} worker processes"


def has_dask() -> bool:
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        return False
    return True


def sweep(study: Union[Study, str, Path], *, samples: Optional[int] = None,
          seed: Optional[int] = None, out: Union[str, Path, None] = None,
          scheduler: Any = None, workers: Optional[int] = None,
          progress: bool = False) -> SweepResult:
    """Runs an uncertainty study (docs/sweep.md) and returns its table and summary.

    ``study``: a :class:`Study`, a study file or an example's name (``cranepredict.studies``);
    ``samples`` and ``seed`` override the file's. ``out``: a folder the chunks are written to as
    they finish (NPZ) with the study's manifest; run again with the same folder, the chunks already
    there are read instead of computed (an interrupted study resumes), and a folder of another study
    is refused. ``scheduler``: None runs on a new Dask LocalCluster of ``workers`` processes
    (default: the cores) if Dask is installed (the [sweep] extra), else in this process;
    ``"in-process"`` runs here; an address (``"tcp://host:8786"``) or a ``distributed.Client`` (of
    any cluster: dask-jobqueue, Kubernetes) runs there. The table does not depend on where it ran.
    ``progress`` draws a bar on stderr.
    """
    study = load_study(study).with_run(samples, seed)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or not 1 <= workers <= 4096):
        raise ValueError(f"workers must be an int in [1, 4096], got {workers!r}")
    store = _Store(Path(out), study) if out is not None else None
    start = time.perf_counter()
    nominal = _nominal(study)
    results: Dict[int, Dict[str, np.ndarray]] = {}
    for i in range(study.n_chunks):
        rows = store.load(i) if store is not None else None
        if rows is not None:
            results[i] = rows
    pending = [i for i in range(study.n_chunks) if i not in results]
    bar = _Progress(study.n_chunks, study.samples, progress)
    bar.update(len(results), 0)
    computed, futures = 0, 0

    def keep(i: int, rows: Dict[str, np.ndarray]) -> None:
        nonlocal computed, futures
        if store is not None:
            store.write(i, rows)
        results[i] = rows
        computed += 1
        futures += len(rows["sample"])
        bar.update(1, sum(len(r["sample"]) for r in results.values()))

    local = scheduler == "in-process" or (scheduler is None and not has_dask())
    chunk_start = time.perf_counter()
    try:
        if local:
            where = "in this process"
            for i in pending:
                keep(i, run_chunk(study, nominal, i, threads=None))
        else:
            where, chunk_start = _run_dask(study, nominal, pending, scheduler, workers, keep)
    finally:
        bar.close()
    chunk_seconds = time.perf_counter() - chunk_start
    table = {k: np.concatenate([results[i][k] for i in range(study.n_chunks)]) for k in COLUMNS}
    summary = summarize(study, nominal, table)
    if store is not None:
        (store.out / "summary.json").write_text(json.dumps(summary.to_dict(), indent=1), "utf-8")
    return SweepResult(study=study, nominal=nominal, table=table, summary=summary,
                       out=store.out if store is not None else None,
                       seconds=time.perf_counter() - start, computed_chunks=computed, where=where,
                       chunk_seconds=chunk_seconds, computed_futures=futures)


def _run_dask(study: Study, nominal: Nominal, pending: List[int], scheduler: Any,
              workers: Optional[int], keep: Any) -> Tuple[str, float]:
    """Runs the pending chunks on Dask; (where, when the first was submitted)."""
    from dask.distributed import as_completed

    client, to_close, where = _dask_client(scheduler, workers)
    futures: List[Any] = []
    start = time.perf_counter()
    try:
        if pending:
            [s, n] = client.scatter([study, nominal], broadcast=True)
            futures = [client.submit(run_chunk, s, n, i, 1, key=f"cranepredict-sweep-{i}-"
                                     f"{study.fingerprint()}-{study.samples}", pure=False)
                       for i in pending]
            index = {f.key: i for f, i in zip(futures, pending)}
            for fut in as_completed(futures):
                keep(index[fut.key], fut.result())
    finally:
        unfinished = [f for f in futures if not f.done()]
        if unfinished:
            client.cancel(unfinished)
        del futures
        for thing in to_close:
            thing.close()
    return where, start
