"""Statics of the crane at a pose: the pressure that holds a boom still.

Built on the C core's inverse dynamics (docs/model.md): at rest (omega = alpha = 0) the joint
torques are the gravity torques, and a cylinder holds its boom when its force p_a A_a - p_b A_b
times ds/dtheta equals its joint's torque. Friction vanishes at rest in the model, so the holding
pressure is one value: a little more raises the boom, a little less lets it sink.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional, Tuple

import numpy as np

from ._checks import number as _number
from .crane import Crane
from .types import (PRESSURE_MAX, Pressure, PressureSeries, State, Valve, ValveSeries, bar_for_pa,
                    looks_like_bar)

if TYPE_CHECKING:
    from .types import Inputs

__all__ = ["holding_pressure", "holding_forces", "supply_short", "pressures_in_bar"]

_JOINTS = ("lift", "tilt")


def holding_pressure(crane: Crane, state: State, joint: str = "lift", *,
                     p_b: Optional[float] = None, p_a: Optional[float] = None) -> float:
    """The chamber pressure (Pa) with which ``joint``'s cylinder holds the crane still at the pose
    of ``state`` (its strokes and extension; slew does not matter), the other cylinder held.

    Give the rod-side pressure ``p_b`` (default 0) to get the bore-side p_a, or give ``p_a``
    instead to get p_b (for a cylinder that the load pulls out, such as the PATU's tilt cylinder,
    only a rod-side pressure holds). Raises ValueError naming the field if the state is not at
    rest or outside the crane's ranges, or if no pressure in [0, PRESSURE_MAX] holds the boom.
    """
    if not isinstance(crane, Crane):
        raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
    if not isinstance(state, State):
        raise TypeError(f"state must be a cranepredict.State, got {type(state).__name__}")
    if joint not in _JOINTS:
        raise ValueError(f"joint must be one of {_JOINTS}, got {joint!r}")
    if p_a is not None and p_b is not None:
        raise ValueError("give p_a or p_b (the pressure on the other side is the result), not both")
    given_name, given = ("p_a", p_a) if p_a is not None else ("p_b", 0.0 if p_b is None else p_b)
    given = _number(given, given_name)
    if not 0.0 <= given <= PRESSURE_MAX:
        raise ValueError(f"{given_name} must be in [0, {PRESSURE_MAX:g}] Pa, got {given:g}")

    g = crane.geometry
    if not g.extension_min <= state.extension <= g.extension_max:
        raise ValueError(f"state.extension must be in [{g.extension_min}, {g.extension_max}] m, "
                         f"got {state.extension}")
    cylinders = (crane.lift_cylinder, crane.tilt_cylinder)
    for name, cyl in zip(_JOINTS, cylinders):
        stroke, rate = getattr(state, f"{name}_stroke"), getattr(state, f"{name}_stroke_rate")
        if rate != 0.0:
            raise ValueError(f"state.{name}_stroke_rate must be 0 (a boom at rest), got {rate}")
        if not cyl.stroke_min <= stroke <= cyl.stroke_max:
            raise ValueError(f"state.{name}_stroke must be in [{cyl.stroke_min}, {cyl.stroke_max}] m, "
                             f"got {stroke}")

    j = _JOINTS.index(joint)
    force = holding_forces(crane, state.lift_stroke, state.tilt_stroke, state.extension)[j]
    cyl = cylinders[j]
    if given_name == "p_b":
        result_name, result = "p_a", (force + given * cyl.area_b) / cyl.area_a
    else:
        result_name, result = "p_b", (given * cyl.area_a - force) / cyl.area_b
    if not 0.0 <= result <= PRESSURE_MAX:
        raise ValueError(f"no {result_name} in [0, {PRESSURE_MAX:g}] Pa holds the {joint} cylinder at "
                         f"this pose with {given_name} = {given:g} Pa: it would take {result:g} Pa"
                         f" (give {result_name} instead to get {given_name})")
    return result


def holding_forces(crane: Crane, lift_stroke: float, tilt_stroke: float,
                   extension: float) -> Tuple[float, float]:
    """The cylinder forces (N, positive extends) that hold the crane still at these strokes: each
    joint's gravity torque at rest (the core's inverse dynamics) over its ds/dtheta. The strokes
    and the extension must be in range (the callers check them and name the field)."""
    from . import _core  # the compiled core; imported here so the twin imports without it

    theta, ratio = [], []
    for j, stroke in enumerate((lift_stroke, tilt_stroke)):
        th, ds = _core.joint_angle(crane, j, stroke, extension)
        theta.append(th)
        ratio.append(ds)
    tau = _core.inverse_dynamics(crane, (theta[0], theta[1], 0.0, extension), (0.0,) * 4, (0.0,) * 4)
    return tau[0] / ratio[0], tau[1] / ratio[1]


def supply_short(crane: Crane, state: State, inputs: "Inputs") -> Tuple[Tuple[str, float, float], ...]:
    """The valve-driven boom cylinders levered against their load (at any time of the drive) whose
    load at the pose of ``state`` needs more pressure to hold than their supply gives: (joint,
    holding pressure in Pa, supply pressure in Pa) each.

    The load-carrying chamber is the bore side when the load pushes the cylinder in (the PATU's
    lift) and the rod side when it pulls it out (its tilt); the other chamber is at the tank
    pressure, as when the lever drives against the load. Above the supply pressure the lever
    cannot move the boom against its load: levered up, it sinks. The pose must be in range (the
    callers check it)."""
    driven = [j for j, name in enumerate(_JOINTS)
              if isinstance(getattr(inputs, name), (Valve, ValveSeries))]
    if not driven:
        return ()
    forces = holding_forces(crane, state.lift_stroke, state.tilt_stroke, state.extension)
    short = []
    for j in driven:
        cyl = (crane.lift_cylinder, crane.tilt_cylinder)[j]
        hyd = cyl.hydraulics
        force, tank = forces[j], hyd.tank_pressure
        lever = np.asarray(getattr(inputs, _JOINTS[j]).u, dtype=float)
        if not np.any(lever * (1.0 if force >= 0.0 else -1.0) > 0.0):
            continue   # never levered against the load: a closed valve holds up to the relief
        if force >= 0.0:
            needed = (force + tank * cyl.area_b) / cyl.area_a
        else:
            needed = (tank * cyl.area_a - force) / cyl.area_b
        if needed > hyd.supply_pressure:
            short.append((_JOINTS[j], needed, hyd.supply_pressure))
    return tuple(short)


def pressures_in_bar(crane: Crane, state: State, inputs: "Inputs") -> Tuple[str, ...]:
    """Warning texts for the pressure-driven boom cylinders whose given pressures all lie below
    1 bar while holding the booms at the pose of ``state`` takes more than 10 bar: pressures
    written in bar where Pa are meant (``Pressure(175, 0)``)."""
    texts = []
    forces = None
    for j, name, drive in ((0, "lift", inputs.lift), (1, "tilt", inputs.tilt)):
        if type(drive) is Pressure:
            p_a, p_b = drive.p_a, drive.p_b
        elif isinstance(drive, PressureSeries):
            p_a, p_b = drive.peak_pressures
        else:
            continue
        if not looks_like_bar(max(p_a, p_b)):
            continue
        text = bar_for_pa(f"Inputs.{name}: {type(drive).__name__}", {"p_a": p_a, "p_b": p_b})
        if text is None:
            continue
        if forces is None:
            forces = holding_forces(crane, state.lift_stroke, state.tilt_stroke, state.extension)
        cyl = (crane.lift_cylinder, crane.tilt_cylinder)[j]
        needed = abs(forces[j]) / (cyl.area_a if forces[j] >= 0.0 else cyl.area_b)
        if needed > 10e5:
            texts.append(text.replace("where the boom cylinders need tens of bar",
                                      f"where holding the {name} boom at this pose takes "
                                      f"{needed / 1e5:.0f} bar"))
    return tuple(texts) if texts else ()
