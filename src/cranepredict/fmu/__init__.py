"""The crane twin as an FMI 3.0 or 2.0 co-simulation FMU (docs/fmu.md).

:func:`export_fmu` writes an FMU whose ``doStep`` advances the C core (``crane_step``: its own RK4,
end stops and valves), compiled at export with this machine's C compiler from the core's sources,
the FMU's interface (``crane_fmu.c``, ``fmi3_crane.c`` / ``fmi2_crane.c``) and a configuration
written here (the crane's parameters, the variables), against the FMI headers of the installed
FMPy package (``pip install cranepredict[fmu]``). The FMU carries the binary for this platform,
``sources/`` with a build description (to compile it elsewhere), and the crane file in
``resources/``.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union
from xml.sax.saxutils import escape

from ..crane import Crane

__all__ = ["export_fmu", "variables", "Variable", "MODEL_IDENTIFIER", "DRIVES"]

MODEL_IDENTIFIER = "crane"
DRIVES = ("valve", "pressure")
_JOINTS = ("lift", "tilt", "slew", "extension")
_HERE = Path(__file__).resolve().parent
_FMU_SOURCES = ("crane_fmu.h", "crane_fmu.c")
_UNITS = ("m", "m/s", "rad", "rad/s", "Pa", "kg", "s")
# SI base-unit exponents of each unit (FMI's BaseUnit)
_BASE = {"m": {"m": 1}, "m/s": {"m": 1, "s": -1}, "rad": {"rad": 1}, "rad/s": {"rad": 1, "s": -1},
         "Pa": {"kg": 1, "m": -1, "s": -2}, "kg": {"kg": 1}, "s": {"s": 1}}


@dataclass(frozen=True)
class Variable:
    """One scalar variable of the FMU: its name (the Python API's), the quantity of crane_fmu.h
    it stands for, FMI type, causality, variability, unit ("" = dimensionless) and start value."""

    name: str
    quantity: str
    type: str            # "Float64", "Int32", "Boolean"
    causality: str       # "input", "output", "parameter", "independent"
    variability: str     # "continuous", "discrete", "fixed", "tunable"
    unit: str
    description: str
    start: Optional[float] = None
    min: Optional[float] = None
    max: Optional[float] = None


def _levered(crane: Crane, levers: Optional[Sequence[str]]) -> Tuple[str, ...]:
    """The joints given a lever: those asked for (default: every actuator with a valve circuit)."""
    has = {"lift": crane.lift_cylinder.hydraulics is not None,
           "tilt": crane.tilt_cylinder.hydraulics is not None,
           "slew": crane.slew_drive is not None and crane.slew_drive.hydraulics is not None,
           "extension": crane.extension_cylinder is not None
           and crane.extension_cylinder.hydraulics is not None}
    if levers is None:
        chosen = tuple(j for j in _JOINTS if has[j])
    else:
        if isinstance(levers, str) or not all(isinstance(j, str) for j in levers):
            raise TypeError(f"levers must be a sequence of joint names, got {levers!r}")
        for j in levers:
            if j not in _JOINTS:
                raise ValueError(f"levers: {j!r} is not a joint (one of {', '.join(_JOINTS)})")
            if not has[j]:
                raise ValueError(f"levers: crane {crane.name!r} has no valve circuit on the {j} "
                                 "(its crane file gives it no hydraulics)")
        chosen = tuple(j for j in _JOINTS if j in levers)
    if not chosen:
        raise ValueError(f"crane {crane.name!r}: no actuator has a valve circuit to put a lever "
                         "on; export with drive='pressure'")
    return chosen


def variables(crane: Crane, *, drive: str = "valve", levers: Optional[Sequence[str]] = None,
              start: Optional[Mapping[str, float]] = None, step: float = 5e-3,
              guard: bool = False, guard_horizon: float = 2.0) -> List[Variable]:
    """The FMU's variables, in value-reference order (the value reference is the index)."""
    if drive not in DRIVES:
        raise ValueError(f"drive must be one of {', '.join(DRIVES)}, got {drive!r}")
    g = crane.geometry
    pose = {"lift_stroke": (crane.lift_cylinder.stroke_min + crane.lift_cylinder.stroke_max) / 2,
            "tilt_stroke": (crane.tilt_cylinder.stroke_min + crane.tilt_cylinder.stroke_max) / 2,
            "slew": 0.0, "extension": g.extension_min}
    for k, v in (start or {}).items():
        if k not in pose:
            raise ValueError(f"start: {k!r} is not one of {', '.join(pose)}")
        pose[k] = float(v)
    V = Variable
    out = [V("time", "Q_TIME", "Float64", "independent", "continuous", "s", "simulation time")]
    if drive == "valve":
        for j in _levered(crane, levers):
            out.append(V(f"{j}_lever", f"Q_{j.upper()}_LEVER", "Float64", "input", "continuous", "",
                         f"the {j} valve's lever: -1 (fully open, retracting) .. 1 (fully open, "
                         "extending); 0 closed", 0.0, -1.0, 1.0))
    else:
        if levers is not None:
            raise ValueError("levers are for drive='valve'")
        for j in ("lift", "tilt"):
            for side in ("a", "b"):
                out.append(V(f"{j}_p_{side}_in", f"Q_{j.upper()}_P_{side.upper()}_IN", "Float64",
                             "input", "continuous", "Pa",
                             f"the {j} cylinder's {'bore' if side == 'a' else 'rod'}-side pressure "
                             "(pressure drive)", 0.0, 0.0))
    out.append(V("load_mass", "Q_LOAD_MASS", "Float64", "parameter", "tunable", "kg",
                 "the load at the tip", float(crane.load_mass), 0.0))
    for name, unit, what in (("lift_stroke", "m", "the lift cylinder's initial stroke"),
                             ("tilt_stroke", "m", "the tilt cylinder's initial stroke"),
                             ("slew", "rad", "the initial slew angle"),
                             ("extension", "m", "the initial extension")):
        out.append(V(f"{name}_start", f"Q_{name.upper()}_START", "Float64", "parameter", "fixed",
                     unit, what + " (the crane starts at rest there)", pose[name]))
    out.append(V("step", "Q_STEP", "Float64", "parameter", "fixed", "s",
                 "the core's RK4 step (a communication step shorter than it is one step)",
                 float(step), 0.0))
    if drive == "pressure":
        for j in ("lift", "tilt"):
            out.append(V(f"{j}_hold", f"Q_{j.upper()}_HOLD", "Boolean", "parameter", "fixed", "",
                         f"the {j} cylinder is held (its valve closed; pressure inputs ignored)",
                         0.0))
    if guard:
        out.append(V("guard_horizon", "Q_GUARD_HORIZON", "Float64", "parameter", "fixed", "s",
                     "how far ahead the guard predicts (the inputs held)", float(guard_horizon),
                     0.0))
    for ax in "xyz":
        out.append(V(f"tip_{ax}", f"Q_TIP_{ax.upper()}", "Float64", "output", "continuous", "m",
                     f"the tip's world {ax}"))
    for j in ("lift", "tilt"):
        out.append(V(f"{j}_stroke", f"Q_{j.upper()}_STROKE", "Float64", "output", "continuous", "m",
                     f"the {j} cylinder's stroke"))
        out.append(V(f"{j}_stroke_rate", f"Q_{j.upper()}_STROKE_RATE", "Float64", "output",
                     "continuous", "m/s", f"the {j} cylinder's stroke rate"))
    for j, what in (("lift", "the lift angle"), ("tilt", "the tilt angle"),):
        rel = " (relative to the lift boom)" if j == "tilt" else ""
        out.append(V(f"{j}_angle", f"Q_{j.upper()}_ANGLE", "Float64", "output", "continuous", "rad",
                     what + rel))
        out.append(V(f"{j}_angle_rate", f"Q_{j.upper()}_ANGLE_RATE", "Float64", "output",
                     "continuous", "rad/s", f"the rate of {what}{rel}"))
    out += [V("slew", "Q_SLEW", "Float64", "output", "continuous", "rad", "the slew angle"),
            V("slew_rate", "Q_SLEW_RATE", "Float64", "output", "continuous", "rad/s",
              "the slew rate"),
            V("extension", "Q_EXTENSION", "Float64", "output", "continuous", "m", "the extension"),
            V("extension_rate", "Q_EXTENSION_RATE", "Float64", "output", "continuous", "m/s",
              "the extension rate")]
    for j in _JOINTS:
        for side in ("a", "b"):
            out.append(V(f"{j}_p_{side}", f"Q_{j.upper()}_P_{side.upper()}", "Float64", "output",
                         "continuous", "Pa",
                         f"the {j} actuator's chamber {side} pressure (valve: computed; pressure "
                         "drive: the given one; held: 0)"))
    for j in _JOINTS:
        out.append(V(f"{j}_stop", f"Q_{j.upper()}_STOP", "Int32", "output", "discrete", "",
                     f"the {j} actuator's end stop: -1 at the start of its range, +1 at its end, "
                     "0 otherwise"))
    if guard:
        out += [V("guard_signal", "Q_GUARD_SIGNAL", "Int32", "output", "discrete", "",
                  "the collision guard's verdict on the future under the inputs: 0 GO, 1 WARN, "
                  "2 STOP"),
                V("time_to_contact", "Q_TIME_TO_CONTACT", "Float64", "output", "continuous", "s",
                  "the first predicted contact, from now (guard_horizon if none)"),
                V("min_clearance", "Q_MIN_CLEARANCE", "Float64", "output", "continuous", "m",
                  "the least clearance between the crane's parts and the obstacles over the "
                  "guard horizon"),
                V("stop_latest", "Q_STOP_LATEST", "Float64", "output", "continuous", "s",
                  "the latest time, from now, to begin a stop that keeps the margin (< 0: too "
                  "late; guard_horizon if no contact)")]
    return out


# ---- the configuration (C) ----

def _c_value(value: Any, ctype: Any) -> str:
    """A C99 initializer of a cffi value: structs by designated fields, arrays by items, reals as
    hexadecimal literals (exact)."""
    from .._core import ffi

    if ctype.kind == "struct":
        return "{" + ", ".join(f".{name} = {_c_value(getattr(value, name), f.type)}"
                               for name, f in ctype.fields) + "}"
    if ctype.kind == "array":
        return "{" + ", ".join(_c_value(value[i], ctype.item) for i in range(ctype.length)) + "}"
    if ctype.kind == "pointer":
        return "0"
    if isinstance(value, float):
        return value.hex()
    if ctype.kind == "enum":
        return str(int(ffi.cast("int", value)))
    return str(int(value))


def _guard_c(crane: Crane, world: Any) -> str:
    """The guard's parts, obstacles and settings (cranepredict.guard's translation and defaults);
    without a world, none (the guard is off)."""
    import importlib

    from .._core import ffi
    g = importlib.import_module("cranepredict.guard")   # the module (the package's guard is the function)

    if world is None:
        return ("const crane_part cfmu_parts[1] = {0};\nconst size_t cfmu_n_parts = 0;\n"
                "const crane_solid cfmu_obstacles[1] = {0};\nconst size_t cfmu_n_obstacles = 0;\n"
                "const crane_guard_config cfmu_guard_config = {0};\n")
    shape = g._shape(crane, None)
    parts, solids = g._parts(crane, shape), g._solids(world)
    n_parts, n_obs = len(shape.parts), len(world.obstacles)
    g._check_layout(parts, n_parts, solids, world, shape)
    cfg = ffi.new("crane_guard_config *", {
        "margin": world.margin, "reaction": g.DEFAULT_REACTION, "cycle": g.DEFAULT_CYCLE,
        "time_tolerance": g.DEFAULT_TIME_TOLERANCE,
        "clearance_tolerance": g.DEFAULT_CLEARANCE_TOLERANCE})
    part_t, solid_t = ffi.typeof("crane_part"), ffi.typeof("crane_solid")
    return (f"const crane_part cfmu_parts[] = {{\n    "
            + ",\n    ".join(_c_value(parts[i], part_t) for i in range(n_parts))
            + f"}};\nconst size_t cfmu_n_parts = {n_parts};\n"
            f"const crane_solid cfmu_obstacles[] = {{\n    "
            + ",\n    ".join(_c_value(solids[i], solid_t) for i in range(n_obs))
            + f"}};\nconst size_t cfmu_n_obstacles = {n_obs};\n"
            f"const crane_guard_config cfmu_guard_config = "
            f"{_c_value(cfg[0], ffi.typeof('crane_guard_config'))};\n")


def _config_c(crane: Crane, drive: str, variables_: List[Variable], levered: Sequence[str],
              token: str, world: Any = None) -> str:
    from .._core import ffi, params

    prm = params(crane)
    kinds = {"output": "CFMU_OUTPUT", "independent": "CFMU_OUTPUT", "input": "CFMU_INPUT"}
    rows, starts = [], []
    for v in variables_:
        kind = kinds.get(v.causality) or ("CFMU_TUNABLE" if v.variability == "tunable"
                                          else "CFMU_FIXED")
        rows.append(f"    {{{v.quantity}, CFMU_{v.type.upper()}, {kind}}},   /* {v.name} */")
        if v.start is not None:
            starts.append(f"    value[{v.quantity}] = {float(v.start).hex()};   /* {v.name} */")
    return f"""/* Written by cranepredict.fmu at export: the crane {crane.name!r} and the FMU's variables
 * (docs/fmu.md). */
#include "crane_fmu.h"

const char cfmu_token[] = "{token}";
const int cfmu_drive = {"CRANE_DRIVE_VALVE" if drive == "valve" else "CRANE_DRIVE_PRESSURE"};
const int cfmu_levered[4] = {{{", ".join("1" if j in levered else "0" for j in _JOINTS)}}};

/* by value reference */
const cfmu_variable cfmu_variables[] = {{
{chr(10).join(rows)}
}};
const size_t cfmu_n_variables = sizeof cfmu_variables / sizeof cfmu_variables[0];

/* the collision guard (with a world) */
{_guard_c(crane, world)}

void cfmu_defaults(crane_params *params, double value[Q_COUNT])
{{
    static const crane_params crane = {_c_value(prm[0], ffi.typeof("crane_params"))};
    *params = crane;
{chr(10).join(starts)}
}}
"""


# ---- the model description ----

def _attr(**kw: Any) -> str:
    return "".join(f' {k}="{escape(str(v), {chr(34): "&quot;"})}"' for k, v in kw.items()
                   if v is not None)


def _num(x: Optional[float]) -> Optional[str]:
    return None if x is None else repr(float(x))


def _units_xml() -> str:
    units = []
    for u in _UNITS:
        units.append(f'    <Unit name="{u}"><BaseUnit{_attr(**_BASE[u])}/></Unit>')
    return "  <UnitDefinitions>\n" + "\n".join(units) + "\n  </UnitDefinitions>\n"


def _initial(v: Variable) -> Optional[str]:
    if v.causality == "parameter":
        return "exact"
    if v.causality == "output":
        return "calculated"
    return None


def _model_description_3(crane: Crane, vs: List[Variable], token: str, step: float,
                         sources: Sequence[str]) -> str:
    rows = []
    for vr, v in enumerate(vs):
        start = None
        if v.start is not None:
            start = ("true" if v.start else "false") if v.type == "Boolean" else _num(v.start)
        rows.append(f"    <{v.type}" + _attr(
            name=v.name, valueReference=vr, causality=v.causality, variability=v.variability,
            initial=_initial(v), unit=v.unit or None, description=v.description,
            min=_num(v.min) if v.type == "Float64" else None,
            max=_num(v.max) if v.type == "Float64" else None, start=start) + "/>")
    outputs = [vr for vr, v in enumerate(vs) if v.causality == "output"]
    structure = "".join(f'    <Output valueReference="{vr}"/>\n' for vr in outputs) + \
        "".join(f'    <InitialUnknown valueReference="{vr}"/>\n' for vr in outputs)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription{_attr(fmiVersion="3.0", modelName=f"cranepredict {crane.name}",
                           instantiationToken=token, description=_DESCRIPTION,
                           generationTool="cranepredict", variableNamingConvention="flat")}>
  <CoSimulation{_attr(modelIdentifier=MODEL_IDENTIFIER, canHandleVariableCommunicationStepSize="true",
                      canGetAndSetFMUState="true", canSerializeFMUState="true",
                      canReturnEarlyAfterIntermediateUpdate="false", hasEventMode="false",
                      providesIntermediateUpdate="false")}/>
{_units_xml()}  <DefaultExperiment{_attr(startTime="0", stopTime="2", stepSize=_num(max(step, 0.01)))}/>
  <ModelVariables>
{chr(10).join(rows)}
  </ModelVariables>
  <ModelStructure>
{structure}  </ModelStructure>
</fmiModelDescription>
"""


def _model_description_2(crane: Crane, vs: List[Variable], token: str, step: float,
                         sources: Sequence[str]) -> str:
    types = {"Float64": "Real", "Int32": "Integer", "Boolean": "Boolean"}
    rows = []
    for vr, v in enumerate(vs):
        causality = "local" if v.causality == "independent" else v.causality
        attrs: Dict[str, Any] = {}
        if v.start is not None:
            attrs["start"] = ("true" if v.start else "false") if v.type == "Boolean" else _num(v.start)
        if v.type == "Float64":
            attrs.update(unit=v.unit or None, min=_num(v.min), max=_num(v.max))
        rows.append(f"    <ScalarVariable" + _attr(
            name=v.name, valueReference=vr, causality=v.causality, variability=v.variability,
            initial=_initial(v), description=v.description) +
            f"><{types[v.type]}{_attr(**attrs)}/></ScalarVariable>")
        del causality
    index = {vr: vr + 1 for vr in range(len(vs))}   # ScalarVariable order, 1-based
    outputs = [index[vr] for vr, v in enumerate(vs) if v.causality == "output"]
    files = "".join(f'      <File name="{f}"/>\n' for f in sources if f.endswith(".c"))
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription{_attr(fmiVersion="2.0", modelName=f"cranepredict {crane.name}", guid=token,
                           description=_DESCRIPTION, generationTool="cranepredict",
                           variableNamingConvention="flat")}>
  <CoSimulation{_attr(modelIdentifier=MODEL_IDENTIFIER, canHandleVariableCommunicationStepSize="true",
                      canGetAndSetFMUstate="true", canSerializeFMUstate="true",
                      canNotUseMemoryManagementFunctions="true")}>
    <SourceFiles>
{files}    </SourceFiles>
  </CoSimulation>
{_units_xml()}  <DefaultExperiment{_attr(startTime="0", stopTime="2", stepSize=_num(max(step, 0.01)))}/>
  <ModelVariables>
{chr(10).join(rows)}
  </ModelVariables>
  <ModelStructure>
    <Outputs>
{"".join(f'      <Unknown index="{i}"/>{chr(10)}' for i in outputs)}    </Outputs>
    <InitialUnknowns>
{"".join(f'      <Unknown index="{i}"/>{chr(10)}' for i in outputs)}    </InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"""


_DESCRIPTION = ("A hydraulic loader crane (cranepredict's C core): doStep advances the core's own "
                "RK4 with end stops and valves")


def _build_description(sources: Sequence[str]) -> str:
    files = "".join(f'      <SourceFile name="{f}"/>\n' for f in sources if f.endswith(".c"))
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiBuildDescription fmiVersion="3.0">
  <BuildConfiguration modelIdentifier="{MODEL_IDENTIFIER}">
    <SourceFileSet language="C99">
{files}    </SourceFileSet>
    <Library name="m"/>
  </BuildConfiguration>
</fmiBuildDescription>
"""


# ---- building ----

def _core_dir() -> Path:
    """The C core's sources: shipped in the package (a wheel) or the checkout's csrc/."""
    shipped = _HERE / "core"
    if (shipped / "crane.h").is_file():
        return shipped
    checkout = _HERE.parents[2] / "csrc"
    if (checkout / "crane.h").is_file():
        return checkout
    raise RuntimeError("the C core's sources are not installed with cranepredict (looked in "
                       f"{shipped} and {checkout})")


def _fmi_headers() -> Path:
    try:
        import fmpy
    except ImportError:
        raise ImportError("exporting an FMU needs the FMI headers of FMPy: "
                          "pip install 'cranepredict[fmu]'") from None
    path = Path(fmpy.__file__).parent / "c-code"
    if not (path / "fmi3Functions.h").is_file():
        raise RuntimeError(f"the installed FMPy has no FMI headers in {path}")
    return path


def _platform(fmi: int) -> str:
    import fmpy
    return fmpy.platform_tuple if fmi == 3 else fmpy.platform


def compiler(cc: Optional[str] = None) -> str:
    """The C compiler to build with: cc, else $CC, else cc/gcc/clang on PATH."""
    for c in ([cc] if cc else []) + ([os.environ["CC"]] if os.environ.get("CC") else []) + \
            ["cc", "gcc", "clang"]:
        path = shutil.which(c.split()[0])
        if path:
            return path
    raise RuntimeError("exporting an FMU compiles its binary with this machine's C compiler: "
                       "none found (cc, gcc or clang on PATH, or set CC)")


def export_fmu(crane: Crane, path: Union[str, os.PathLike], *, fmi: int = 3, drive: str = "valve",
               levers: Optional[Sequence[str]] = None,
               start: Optional[Mapping[str, float]] = None, step: float = 5e-3,
               crane_file: Optional[Union[str, os.PathLike]] = None,
               world: Any = None, guard_horizon: float = 2.0,
               cc: Optional[str] = None) -> Path:
    """Writes a co-simulation FMU of the crane to ``path`` (FMI ``fmi`` = 3 or 2).

    ``drive="valve"``: inputs are the levers (``lift_lever``, ... in [-1, 1]) of ``levers``
    (default: every actuator with a valve circuit; the others are held); the crane starts at rest
    on closed valves, the chambers holding it (computed at the end of the initialization, for the
    initial pose and ``load_mass`` set then). ``drive="pressure"``: inputs are the lift and tilt
    cylinders' chamber pressures (``lift_p_a_in``, ...), the paper's experiment; the slew and the
    extension are held, and Boolean parameters ``lift_hold``/``tilt_hold`` hold a cylinder.
    ``start``: default initial pose (``lift_stroke``, ``tilt_stroke``, ``slew``, ``extension``;
    default the middle of each stroke, slew 0, the shortest extension), parameters of the FMU.
    ``step``: the default of the FMU's ``step`` parameter, the core's RK4 step (s).
    ``crane_file``: the crane file the crane was read from, copied to ``resources/crane.toml``
    (default: the packaged file for the PATU 655; else a note that the parameters are compiled in).
    ``world``: a :class:`cranepredict.World`; the FMU then also outputs the collision guard's
    verdict on the future under the current inputs over ``guard_horizon`` s (``guard_signal``,
    ``time_to_contact``, ``min_clearance``, ``stop_latest``: the C core's ``crane_guard``, whose
    stop freezes the crane after the reaction time; the world's margin, the guard's default
    reaction and cycle).
    Needs a C compiler (``cc``, else $CC, cc, gcc or clang) and FMPy's FMI headers. Returns the
    path written."""
    if not isinstance(crane, Crane):
        raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
    if isinstance(fmi, bool) or fmi not in (2, 3):
        raise ValueError(f"fmi must be 3 or 2, got {fmi!r}")
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not 0 < step < float("inf"):
        raise ValueError(f"step must be > 0 and finite (s), got {step!r}")
    if world is not None:
        from ..world import World
        if not isinstance(world, World):
            raise TypeError(f"world must be a cranepredict.World, got {type(world).__name__}")
        if not world.obstacles:
            raise ValueError(f"world {world.name!r} has no obstacles: nothing to guard against")
    if isinstance(guard_horizon, bool) or not isinstance(guard_horizon, (int, float)) or \
            not 0 < guard_horizon < float("inf"):
        raise ValueError(f"guard_horizon must be > 0 and finite (s), got {guard_horizon!r}")
    vs = variables(crane, drive=drive, levers=levers, start=start, step=step,
                   guard=world is not None, guard_horizon=guard_horizon)
    levered = [v.name[:-len("_lever")] for v in vs if v.name.endswith("_lever")]
    headers = _fmi_headers()
    cc_path = compiler(cc)
    from .._core import check_crane
    check_crane(crane)
    core = _core_dir()
    core_files = sorted(p.name for p in core.iterdir() if p.suffix in (".c", ".h"))
    api = f"fmi{fmi}_crane.c"
    digest = hashlib.sha256(repr((crane, vs, fmi, world)).encode()).hexdigest()
    token = "{" + str(uuid.UUID(digest[:32])) + "}"
    config = _config_c(crane, drive, vs, levered, token, world)
    sources = core_files + list(_FMU_SOURCES) + ["crane_fmu_config.c", api]
    path = Path(path)
    with tempfile.TemporaryDirectory(prefix="cranepredict-fmu-") as tmp:
        root = Path(tmp)
        src = root / "sources"
        src.mkdir()
        for f in core_files:
            shutil.copy2(core / f, src / f)
        for f in list(_FMU_SOURCES) + [api]:
            shutil.copy2(_HERE / f, src / f)
        (src / "crane_fmu_config.c").write_text(config, encoding="utf-8")
        if fmi == 3:
            (src / "buildDescription.xml").write_text(_build_description(sources), encoding="utf-8")
            md = _model_description_3(crane, vs, token, step, sources)
        else:
            md = _model_description_2(crane, vs, token, step, sources)
        (root / "modelDescription.xml").write_text(md, encoding="utf-8")
        res = root / "resources"
        res.mkdir()
        (res / "crane.toml").write_text(_crane_text(crane, crane_file), encoding="utf-8")
        binary = root / "binaries" / _platform(fmi) / f"{MODEL_IDENTIFIER}.so"
        binary.parent.mkdir(parents=True)
        cmd = [cc_path, "-shared", "-fPIC", "-O2", "-std=c99", "-fvisibility=hidden",
               f"-I{headers}", f"-I{src}", "-o", str(binary)] + \
              [str(src / f) for f in sources if f.endswith(".c")] + ["-lm"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"compiling the FMU failed ({' '.join(cmd[:3])} ...):\n"
                               f"{r.stdout}{r.stderr}")
        tmp_fmu = root / "out.fmu"
        with zipfile.ZipFile(tmp_fmu, "w", zipfile.ZIP_DEFLATED) as z:
            for p in sorted(root.rglob("*")):
                if p.is_file() and p != tmp_fmu:
                    z.write(p, p.relative_to(root).as_posix())
        path.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(tmp_fmu, path)
    return path


def _crane_text(crane: Crane, crane_file: Optional[Union[str, os.PathLike]]) -> str:
    """The crane file the FMU was made from."""
    if crane_file is not None:
        return Path(crane_file).read_text(encoding="utf-8")
    if crane == Crane.patu655():
        return (Path(__file__).resolve().parents[1] / "cranes" / "patu655.toml").read_text(
            encoding="utf-8")
    return (f"# crane {crane.name!r}: its parameters are compiled into the FMU "
            "(sources/crane_fmu_config.c)\n")
