"""The twin's model of one crane (the C core's model.c): every constant of a prediction derived
once from the crane, with the kinematics, dynamics and actuator forces of kinematics.py,
dynamics.py and cylinder.py."""

from __future__ import annotations

import math
from typing import Any, Optional, Tuple

from ._internal import EXTENSION, LIFT, SLEW, TILT, Pair, _norm, _sub, _tensor, _vec
from .cylinder import Cylinders, equivalent_cylinder, friction_parameters, piston_areas
from .dynamics import Dynamics, _body, _lump, _point_mass
from .kinematics import Kinematics, _LinkPose


class TwinModel(Kinematics, Dynamics, Cylinders):
    """The fast model of one crane at one extension: kinematics, dynamics and cylinder forces.

    Everything that is constant during a prediction (triangle and four-bar constants, piston
    areas, the lumped outer boom body, the angle limits) is computed once here.
    """

    def __init__(self, crane: Any, extension: float) -> None:
        geo = crane.geometry
        self.gravity = float(crane.gravity)
        self.extension = float(extension)

        # --- lift triangle ---------------------------------------------------------------
        self.lift_pivot = _vec(geo.lift_pivot)                      # O1, boom plane
        self.lift_cylinder_base = _vec(geo.lift_cylinder_base)      # B1, boom plane
        self.lift_cylinder_rod = _vec(geo.lift_cylinder_rod)        # E1, lift boom frame
        base_arm = _sub(self.lift_cylinder_base, self.lift_pivot)
        self.lift_db = _norm(base_arm)
        self.lift_dr = _norm(self.lift_cylinder_rod)
        self.lift_beta = math.atan2(base_arm[1], base_arm[0])
        self.lift_eps = math.atan2(self.lift_cylinder_rod[1], self.lift_cylinder_rod[0])

        # --- tilt four-bar ---------------------------------------------------------------
        self.tilt_cylinder_base = _vec(geo.tilt_cylinder_base)      # B2, lift boom frame
        self.link1_pivot = _vec(geo.link1_pivot)                    # P1, lift boom frame
        self.tilt_pivot = _vec(geo.tilt_pivot)                      # O2, lift boom frame
        self.link2_attach = _vec(geo.link2_attach)                  # A, outer boom frame
        link_pin = _vec(geo.link_pin)                               # Q in side link 1's frame
        link2_end = _vec(geo.link2_end)                             # A in side link 2's frame
        self.tilt_l1 = _norm(link_pin)
        self.tilt_l2 = _norm(link2_end)
        self.tilt_ra = _norm(self.link2_attach)
        self.tilt_alpha_a = math.atan2(self.link2_attach[1], self.link2_attach[0])
        self.link1_angle0 = math.atan2(link_pin[1], link_pin[0])    # phi1 = angle(Q - P1) - this
        self.link2_angle0 = math.atan2(link2_end[1], link2_end[0])  # phi2 = angle(A - Q) - this

        # --- outer end of the booms ------------------------------------------------------
        self.extension_mount = _vec(geo.extension_mount)            # outer boom frame
        self.tip_distance = float(geo.tip_distance)

        # --- actuators: the boom cylinders, then the slew drive and the extension cylinder as
        # equivalent cylinders (spec "Four joints")
        cylinders = (crane.lift_cylinder, crane.tilt_cylinder)
        self.length_retracted: Pair = tuple(float(c.length_retracted) for c in cylinders)  # type: ignore
        self.stroke_min: Pair = tuple(float(c.stroke_min) for c in cylinders)  # type: ignore
        self.stroke_max: Pair = tuple(float(c.stroke_max) for c in cylinders)  # type: ignore
        slew_drive = getattr(crane, "slew_drive", None)
        ext_cyl = getattr(crane, "extension_cylinder", None)
        self.has_actuator = (True, True, slew_drive is not None, ext_cyl is not None)
        areas = [piston_areas(c.bore, c.rod) for c in cylinders]
        frictions = [c.friction for c in cylinders]
        for joint, actuator in ((SLEW, slew_drive), (EXTENSION, ext_cyl)):
            if actuator is None:
                areas.append((0.0, 0.0))
                frictions.append(None)
            else:
                cyl = equivalent_cylinder(crane, joint)
                areas.append(piston_areas(cyl.bore, cyl.rod))
                frictions.append(actuator.friction)
        self.area_bore: Tuple[float, ...] = tuple(a for a, _ in areas)
        self.area_rod: Tuple[float, ...] = tuple(b for _, b in areas)
        self.friction = tuple(friction_parameters(f) for f in frictions)
        #: ds/dpsi of the rack (constant)
        self.slew_ratio = 1.0 if slew_drive is None else float(slew_drive.pinion_radius)
        self.slew_limits: Pair = (-math.inf, math.inf) if slew_drive is None else (
            float(slew_drive.slew_min), float(slew_drive.slew_max))
        self.extension_limits: Pair = (float(geo.extension_min), float(geo.extension_max))

        # --- bodies (spec "Four joints": body 2 the outer boom alone, body 3 extension + load)
        self.m1, self.c1, self.i1, self.t1 = _body(crane.lift_boom)
        self.outer_boom = _body(crane.outer_boom)
        self.m2, self.c2, self.i2, self.t2 = self.outer_boom
        self.extension_boom = _body(crane.extension_boom)
        #: the load, a point mass at the tip, in the extension boom frame
        self.load = _point_mass(float(crane.load_mass), (self.tip_distance, 0.0))
        # body 3: lumped once per crane in the extension boom frame (they slide together)
        self.m3, self.c3, self.i3, self.t3 = _lump((self.extension_boom, self.load))
        # side link 1's frame has its origin at P1, side link 2's at the pin Q
        (self.link1_mass, self.link1_com, self.link1_izz,
         self.link1_tensor) = _body(crane.side_link1)
        (self.link2_mass, self.link2_com, self.link2_izz,
         self.link2_tensor) = _body(crane.side_link2)
        pillar = crane.pillar
        #: the pillar's constant share of the slew inertia, m x^2 + iyy
        self.pillar_inertia = 0.0 if pillar is None else (
            float(pillar.mass) * float(pillar.com[0]) ** 2 + _tensor(pillar)[1])
        self._pose: Optional[_LinkPose] = None                      # the last four-bar pose
        self._lumped: dict = {}                                     # extension -> lumped body 2

        # --- tilt four-bar validity and assembly (spec "Tilt kinematics") ------------------
        #: the side of P1 -> A on which angle -> stroke puts Q (+1 left, -1 right)
        self.tilt_branch = self._fourbar_branch()

        # --- angle limits (spec "End stops") ----------------------------------------------
        # The stroke limit at the lower angle limit follows the sign of ds/dtheta, which the
        # four-bar check keeps constant over the stroke (lift: > 0 by the triangle's convention).
        #: stroke_at_stop[joint][side]: the stroke reported at a lower (-1) / upper (+1) stop
        #: stop_flag[joint][side]: the reported flag, in cylinder terms (-1 at stroke_min,
        #: +1 at stroke_max), for a joint stopped at its lower (-1) / upper (+1) angle limit
        limits, at_stop, flags = [], [], []
        for joint in (LIFT, TILT):
            theta_a, ds = self.joint_angle(joint, self.stroke_min[joint])
            theta_b = self.joint_angle(joint, self.stroke_max[joint])[0]
            if ds > 0.0:
                limits.append((theta_a, theta_b))
                at_stop.append({-1: self.stroke_min[joint], +1: self.stroke_max[joint]})
                flags.append({-1: -1, +1: +1})
            else:
                limits.append((theta_b, theta_a))
                at_stop.append({-1: self.stroke_max[joint], +1: self.stroke_min[joint]})
                flags.append({-1: +1, +1: -1})
        #: angle_limits[joint] = (lower, upper), for the slew and the extension their range
        self.angle_limits: Tuple[Pair, ...] = (limits[0], limits[1], self.slew_limits,
                                               self.extension_limits)
        self.stroke_at_stop = (at_stop[0], at_stop[1])
        # the slew and the extension: -1 at the range's start, +1 at its end
        self.stop_flag = (flags[0], flags[1], {-1: -1, +1: +1}, {-1: -1, +1: +1})

    def limit(self, joint: int, side: int) -> float:
        """The joint's lower (side -1) or upper (+1) angle limit; the slew's and the extension's
        range ends."""
        lower, upper = self.angle_limits[joint]
        return lower if side < 0 else upper
