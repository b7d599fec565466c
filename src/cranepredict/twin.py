"""Pure-Python twin of the fast crane model (docs/model.md).

The twin exists to validate the C core: it is written from the same specification but shares no
code with it, so an error in one shows up as a disagreement with the other.  It follows
docs/model.md step by step (kinematics, iterative Newton-Euler with the side links' share by
virtual work, smooth Stribeck friction, RK4 with impacts and releases located inside a step) and is
deliberately plain: Python floats and ``math`` in the hot path,
because for 2x2 algebra they are faster than numpy; numpy only builds the output arrays.

Index 0 is the lift joint/cylinder, index 1 the tilt joint/cylinder.  Angles are in the boom plane
(x outward, y up); world coordinates are X, Y horizontal and Z up.
"""

from __future__ import annotations

import math
from bisect import bisect_right
from typing import Any, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from .types import POINT_NAMES

__all__ = ["POINT_NAMES", "TwinModel", "simulate", "points", "LIFT", "TILT", "SLEW", "EXTENSION"]

LIFT = 0
TILT = 1
SLEW = 2
EXTENSION = 3

#: Bisections used to locate an end-stop impact inside a step (spec: 60).
EVENT_BISECTIONS = 60
#: Bisections used to locate a release from a stop inside a step (spec: 40).
RELEASE_BISECTIONS = 40
#: Most pieces (impacts and releases) one step is cut into; the last takes the rest (spec: 8).
MAX_PIECES = 8
#: Where a valve-driven state's hydraulic entries start: the chamber pressures (p_a, p_b) of the
#: four joints [lift, tilt, slew, extension] follow (theta0, theta1, psi, e) and their rates, then
#: the four spools (SPOOL + j).
HYD = 8
SPOOL = HYD + 8

Vec = Tuple[float, float]
Pair = Tuple[float, float]
Quad = Tuple[float, float, float, float]
Tensor = Tuple[float, float, float]     # in-plane inertia tensor entries (ixx, iyy, ixy)
Matrix2 = Tuple[Pair, Pair]
Matrix4 = Tuple[Tuple[float, float, float, float], ...]

_HALF_PI = 0.5 * math.pi
_TWO_PI = 2.0 * math.pi


# --------------------------------------------------------------------------------------------
# Plane-vector helpers (spec "Helpers")
# --------------------------------------------------------------------------------------------

def _vec(p: Sequence[float]) -> Vec:
    """A geometry point as a plain float pair (the crane may hold numpy scalars or lists)."""
    return (float(p[0]), float(p[1]))


def _tensor(body: Any) -> Tensor:
    """A crane body's in-plane inertia tensor entries (ixx, iyy, ixy); left out: (0, izz, 0)."""
    ixx = getattr(body, "ixx", None)
    iyy = getattr(body, "iyy", None)
    ixy = getattr(body, "ixy", None)
    return (0.0 if ixx is None else float(ixx), float(body.izz) if iyy is None else float(iyy),
            0.0 if ixy is None else float(ixy))


def _sub(a: Vec, b: Vec) -> Vec:
    return (a[0] - b[0], a[1] - b[1])


def _dot(a: Vec, b: Vec) -> float:
    return a[0] * b[0] + a[1] * b[1]


def _perp(v: Vec) -> Vec:
    """Rotate by +90 deg: the velocity direction of a point at v on a body turning about the origin."""
    return (-v[1], v[0])


def _cross(a: Vec, b: Vec) -> float:
    """z component of a x b: the moment about the origin of a force b applied at a."""
    return a[0] * b[1] - a[1] * b[0]


def _rotate(angle: float, v: Vec) -> Vec:
    """R(angle) v, R = [[cos, -sin], [sin, cos]]."""
    c = math.cos(angle)
    s = math.sin(angle)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _norm(v: Vec) -> float:
    return math.sqrt(v[0] * v[0] + v[1] * v[1])


def _circle(c0: Vec, r0: float, c1: Vec, r1: float, sign: float) -> Vec:
    """Intersection of the circle about c0 (radius r0) and about c1 (radius r1).

    sign = -1 picks the point to the right of the directed line c0 -> c1, +1 the one to the left.
    A mechanism that cannot close raises ValueError instead of silently producing NaN.
    """
    dx = c1[0] - c0[0]
    dy = c1[1] - c0[1]
    d = math.sqrt(dx * dx + dy * dy)
    if not d > 0.0:
        raise ValueError("four-bar does not close: coincident circle centres")
    ux = dx / d
    uy = dy / d
    a = (r0 * r0 - r1 * r1 + d * d) / (2.0 * d)
    h2 = r0 * r0 - a * a
    if not h2 > 0.0:
        raise ValueError(
            f"four-bar does not close (circles about ({c0[0]:.6g}, {c0[1]:.6g}) r={r0:.6g} and "
            f"({c1[0]:.6g}, {c1[1]:.6g}) r={r1:.6g} do not intersect)")
    h = sign * math.sqrt(h2)
    # p = c0 + a u + sign sqrt(h2) perp(u), perp(u) = (-uy, ux)
    return (c0[0] + a * ux - h * uy, c0[1] + a * uy + h * ux)


def _solve(a: List[List[float]], b: List[float]) -> List[float]:
    """x with a x = b, Gaussian elimination with partial pivoting (n <= 4)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            if f != 0.0:
                for k in range(c, n + 1):
                    m[r][k] -= f * m[c][k]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x


def _wrap_tilt(theta: float) -> float:
    """Wrap into (-3pi/2, pi/2]: the PATU tilt runs from ~0 to ~-190 deg, so this keeps it continuous."""
    while theta > _HALF_PI:
        theta -= _TWO_PI
    while theta <= -3.0 * _HALF_PI:
        theta += _TWO_PI
    return theta


# --------------------------------------------------------------------------------------------
# 4x4 homogeneous transforms (spec "Frames": T_w0, T01, T12, T2e)
# --------------------------------------------------------------------------------------------

def _planar_transform(angle: float, origin: Vec) -> Matrix4:
    """[R(angle), origin] as a 4x4 transform about z (a body frame inside the boom plane)."""
    c = math.cos(angle)
    s = math.sin(angle)
    return ((c, -s, 0.0, origin[0]),
            (s, c, 0.0, origin[1]),
            (0.0, 0.0, 1.0, 0.0),
            (0.0, 0.0, 0.0, 1.0))


def _world_transform(slew: float) -> Matrix4:
    """T_w0 = Rot_Z(slew) Rot_X(+90 deg): the boom plane (x, y) goes to (x cos, x sin, y), Z up."""
    c = math.cos(slew)
    s = math.sin(slew)
    # Rot_X(90) = [[1,0,0],[0,0,-1],[0,1,0]]; Rot_Z(psi) Rot_X(90) = [[c,0,s],[s,0,-c],[0,1,0]]
    return ((c, 0.0, s, 0.0),
            (s, 0.0, -c, 0.0),
            (0.0, 1.0, 0.0, 0.0),
            (0.0, 0.0, 0.0, 1.0))


def _compose(a: Matrix4, b: Matrix4) -> Matrix4:
    """a b for 4x4 transforms (written out: this runs three times per output sample)."""
    b0, b1, b2, b3 = b
    return tuple(
        (r[0] * b0[0] + r[1] * b1[0] + r[2] * b2[0] + r[3] * b3[0],
         r[0] * b0[1] + r[1] * b1[1] + r[2] * b2[1] + r[3] * b3[1],
         r[0] * b0[2] + r[1] * b1[2] + r[2] * b2[2] + r[3] * b3[2],
         r[0] * b0[3] + r[1] * b1[3] + r[2] * b2[3] + r[3] * b3[3])
        for r in a)  # type: ignore[return-value]


def _apply(m: Matrix4, p: Vec) -> Tuple[float, float, float]:
    """m (p.x, p.y, 0, 1): a planar point of m's frame in the frame m maps into."""
    x, y = p
    return (m[0][0] * x + m[0][1] * y + m[0][3],
            m[1][0] * x + m[1][1] * y + m[1][3],
            m[2][0] * x + m[2][1] * y + m[2][3])


# --------------------------------------------------------------------------------------------
# Poses shared by the kinematics and the dynamics of one configuration
# --------------------------------------------------------------------------------------------

class _LinkPose(NamedTuple):
    """The four-bar at one tilt angle, in the lift boom frame (origin O1): everything about the
    side links and the tilt cylinder that depends on theta1 alone (spec "Side links").

    Kept apart from theta0 so that a held or stopped tilt reuses it for a whole prediction."""

    theta: float     #: the tilt angle this pose is for
    ratio: float     #: ds/dtheta1, the tilt cylinder's transmission
    arm_a: Vec       #: A - O2 (A turns about O2 with the outer boom)
    arm_q: Vec       #: Q - P1 (Q turns about P1 with side link 1)
    link: Vec        #: A - Q (side link 2, rigid)
    den1: float      #: perp(Q - P1).(A - Q)
    den2: float      #: perp(A - Q).(Q - P1)
    k1: float        #: dphi1 per unit tilt rate
    k2: float        #: dphi2 per unit tilt rate
    d1: Vec          #: side link 1's centre of mass, P1 + R(phi1) cL1
    e1: Vec          #: R(phi1) cL1
    j1: Vec          #: side link 1's centre-of-mass velocity per unit tilt rate, v1/u
    d2: Vec          #: side link 2's centre of mass, Q + R(phi2) cL2
    e2: Vec          #: R(phi2) cL2
    j2: Vec          #: side link 2's centre-of-mass velocity per unit tilt rate, v2/u
    phi1: float      #: side link 1's turn relative to the lift boom
    phi2: float      #: side link 2's turn relative to the lift boom
    stroke: float    #: the tilt stroke at this angle


class _Configuration(NamedTuple):
    """One joint configuration theta, with every vector the Newton-Euler pass needs already in
    the boom plane. The forward dynamics calls ID three times (bias, two mass-matrix columns)
    at the same theta, so the trigonometry and the four-bar are done once, here.

    Rotating the side links' lift-frame vectors by R(theta0) before the arithmetic instead of
    after (spec: D = R d, V = R v, Acc = R acc) is the same thing: rotation is linear and keeps
    dot products, cross products and perp."""

    ratio: Pair      #: (ds/dtheta0, ds/dtheta1)
    tilt_stroke: float  #: the tilt stroke (from the four-bar pose)
    r12: Vec         #: R(theta0) O2
    cc1: Vec         #: R(theta0) c1
    cc2: Vec         #: R(theta0 + theta1) c_ob (the outer boom alone)
    cc3: Vec         #: R(theta0 + theta1) (mount + (e, 0) + c3): body 3 (extension boom + load)
    u: Vec           #: R(theta0 + theta1) (1, 0): the extension's direction
    th0: float       #: theta0: the lift boom's angle in the boom plane
    th12: float      #: theta0 + theta1: the outer boom's and body 3's
    arm_a: Vec       #: R(theta0) (A - O2)
    arm_q: Vec       #: R(theta0) (Q - P1)
    link: Vec        #: R(theta0) (A - Q)
    den1: float
    den2: float
    k1: float
    k2: float
    d1: Vec          #: R(theta0) d1, from O1
    e1: Vec
    j1: Vec
    d2: Vec          #: R(theta0) d2, from O1
    e2: Vec
    j2: Vec
    phi1: float      #: theta0 + phi1: side link 1's angle in the boom plane
    phi2: float      #: theta0 + phi2
    lumped: Tuple[float, float]  #: (m, izz) of body 2 lumped with body 3 at this extension
    cc2l: Vec        #: R(theta0 + theta1) c of that lumped body


def _vertical_inertia(t: Tensor, phi: float) -> Tuple[float, float]:
    """(J_v, J_v'): a body's inertia about a vertical axis through its centre when turned by phi
    in the boom plane, and its derivative by phi (spec "Four joints")."""
    s2 = math.sin(2.0 * phi)
    c2 = math.cos(2.0 * phi)
    ixx, iyy, ixy = t
    # ixx sin^2 + 2 ixy sin cos + iyy cos^2, with the double angles
    return (0.5 * (ixx + iyy) + 0.5 * (iyy - ixx) * c2 + ixy * s2,
            (ixx - iyy) * s2 + 2.0 * ixy * c2)


def _link_torques(mass: float, izz: float, k: float, d: Vec, e: Vec, j: Vec, base_v: Vec,
                  base_acc: Vec, dphi: float, ddphi: float, w1: float, a1: float,
                  g: float, cen_x: float = 0.0, n_g: float = 0.0) -> Pair:
    """One side link's share of (tau0, tau1), by virtual work.

    The link's frame origin moves relative to the lift boom with base_v, base_acc (zero for
    link 1 on P1, the pin Q's motion for link 2) and the link turns by dphi, ddphi relative to
    the lift boom; d is its centre of mass from O1, e from its frame origin, j its velocity per
    unit tilt rate, k its turn rate per unit tilt rate (boom-plane axes). The lift boom frame
    turns with w1, a1, so the absolute centre-of-mass acceleration picks up the Coriolis term
    2 w1 perp(V) besides a1 perp(D) - w1^2 D. Gravity is the base acceleration (0, g); the
    slew adds the centripetal acceleration cen_x (along x) and the moment n_g (spec "Four joints").
    """
    # motion relative to the lift boom: v = base_v + dphi perp(e), acc likewise
    vx = base_v[0] - dphi * e[1]
    vy = base_v[1] + dphi * e[0]
    rel_x = base_acc[0] - ddphi * e[1] - dphi * dphi * e[0]
    rel_y = base_acc[1] + ddphi * e[0] - dphi * dphi * e[1]
    # acc_cL = acc_O1 + Acc + 2 w1 perp(V) + a1 perp(D) - w1^2 D
    fx = mass * (rel_x - 2.0 * w1 * vy - a1 * d[1] - w1 * w1 * d[0] + cen_x)
    fy = mass * (g + rel_y + 2.0 * w1 * vx + a1 * d[0] - w1 * w1 * d[1])
    n = izz * (a1 + ddphi) + n_g
    # tau0 += cross(D, F) + N, tau1 += F . j + N k
    return d[0] * fy - d[1] * fx + n, fx * j[0] + fy * j[1] + n * k


# --------------------------------------------------------------------------------------------
# The model
# --------------------------------------------------------------------------------------------

class TwinModel:
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
        self.tilt_l1 = _norm(_vec(geo.link_pin))
        self.tilt_l2 = _norm(_vec(geo.link2_end))
        self.tilt_ra = _norm(self.link2_attach)
        self.tilt_alpha_a = math.atan2(self.link2_attach[1], self.link2_attach[0])
        link_pin = _vec(geo.link_pin)                               # Q in side link 1's frame
        link2_end = _vec(geo.link2_end)                             # A in side link 2's frame
        self.link1_angle0 = math.atan2(link_pin[1], link_pin[0])    # phi1 = angle(Q - P1) - this
        self.link2_angle0 = math.atan2(link2_end[1], link2_end[0])  # phi2 = angle(A - Q) - this

        # --- outer end of the booms ------------------------------------------------------
        self.extension_mount = _vec(geo.extension_mount)            # outer boom frame
        self.tip_distance = float(geo.tip_distance)

        # --- cylinders -------------------------------------------------------------------
        cylinders = (crane.lift_cylinder, crane.tilt_cylinder)
        self.length_retracted: Pair = tuple(float(c.length_retracted) for c in cylinders)  # type: ignore
        self.stroke_min: Pair = tuple(float(c.stroke_min) for c in cylinders)  # type: ignore
        self.stroke_max: Pair = tuple(float(c.stroke_max) for c in cylinders)  # type: ignore
        self.area_bore: Pair = tuple(math.pi * float(c.bore) ** 2 / 4.0 for c in cylinders)  # type: ignore
        self.area_rod: Pair = tuple(
            math.pi * (float(c.bore) ** 2 - float(c.rod) ** 2) / 4.0 for c in cylinders)  # type: ignore
        frictions = [c.friction for c in cylinders]

        # --- slew drive and extension cylinder (spec "Four joints"): equivalent cylinders --
        slew_drive = getattr(crane, "slew_drive", None)
        ext_cyl = getattr(crane, "extension_cylinder", None)
        self.has_actuator = (True, True, slew_drive is not None, ext_cyl is not None)
        e_min, e_max = float(geo.extension_min), float(geo.extension_max)
        if slew_drive is not None:
            area = math.pi * float(slew_drive.bore) ** 2 / 4.0
            #: ds/dpsi of the rack (constant)
            self.slew_ratio = float(slew_drive.pinion_radius)
            slew_limits = (float(slew_drive.slew_min), float(slew_drive.slew_max))
            slew_areas = (area, area)
            frictions.append(slew_drive.friction)
        else:
            self.slew_ratio = 1.0
            slew_limits = (-math.inf, math.inf)
            slew_areas = (0.0, 0.0)
            frictions.append(None)
        if ext_cyl is not None:
            ext_areas = (math.pi * float(ext_cyl.bore) ** 2 / 4.0,
                         math.pi * (float(ext_cyl.bore) ** 2 - float(ext_cyl.rod) ** 2) / 4.0)
            frictions.append(ext_cyl.friction)
        else:
            ext_areas = (0.0, 0.0)
            frictions.append(None)
        self.area_bore = self.area_bore + (slew_areas[0], ext_areas[0])  # type: ignore
        self.area_rod = self.area_rod + (slew_areas[1], ext_areas[1])  # type: ignore
        self.friction = tuple(
            (0.0, 0.0, 0.0, 1.0, 0.0) if f is None else
            (float(f.coulomb), float(f.static), float(f.viscous), float(f.stribeck_velocity),
             float(f.factor))
            for f in frictions)
        self.slew_limits: Pair = slew_limits
        self.extension_limits: Pair = (e_min, e_max)

        # --- bodies (spec "Four joints": body 2 the outer boom alone, body 3 extension + load)
        self.m1 = float(crane.lift_boom.mass)
        self.c1 = _vec(crane.lift_boom.com)
        self.i1 = float(crane.lift_boom.izz)
        self.t1 = _tensor(crane.lift_boom)
        self.m2 = float(crane.outer_boom.mass)
        self.c2 = _vec(crane.outer_boom.com)
        self.i2 = float(crane.outer_boom.izz)
        self.t2 = _tensor(crane.outer_boom)
        self.m3, self.c3, self.i3, self.t3 = self._extension_body(crane)
        # side link 1's frame has its origin at P1, side link 2's at the pin Q
        self.link1_mass = float(crane.side_link1.mass)
        self.link1_com = _vec(crane.side_link1.com)
        self.link1_izz = float(crane.side_link1.izz)
        self.link1_tensor = _tensor(crane.side_link1)
        self.link2_mass = float(crane.side_link2.mass)
        self.link2_com = _vec(crane.side_link2.com)
        self.link2_izz = float(crane.side_link2.izz)
        self.link2_tensor = _tensor(crane.side_link2)
        pillar = crane.pillar
        #: the pillar's constant share of the slew inertia, m x^2 + iyy
        self.pillar_inertia = 0.0 if pillar is None else (
            float(pillar.mass) * float(pillar.com[0]) ** 2 + _tensor(pillar)[1])
        self._pose: Optional[_LinkPose] = None                      # the last four-bar pose
        self._lumped: dict = {}                                     # extension -> lumped body 2
        self._m_ext = float(crane.extension_boom.mass)
        self._c_ext = _vec(crane.extension_boom.com)
        self._i_ext = float(crane.extension_boom.izz)
        self._m_load = float(crane.load_mass)

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

    def _fourbar_branch(self) -> float:
        """Exact validity of the four-bar over the tilt stroke (spec "Tilt kinematics"), decided in
        closed form; returns the assembly sign for angle -> stroke, raises ValueError if invalid.

        Let phi be the direction of Q - P1 (Q = P1 + l1 (cos phi, sin phi)). As the stroke grows,
        the cylinder length L = |Q - B2| grows and phi turns clockwise from the direction of
        B2 - P1 through the angle psi = acos((l1^2 + d^2 - L^2) / (2 l1 d)), so the stroke range is
        an arc [phi1, phi0] of phi. On it |Q - O2|^2 = |P1 - O2|^2 + l1^2 + 2 l1 (P1 - O2).n(phi)
        (n the unit vector): a sinusoid in phi, extreme where n(phi) is +-(P1 - O2)/|P1 - O2|.
        The links align (A on the line P1 Q, dtheta/ds = 0) where |P1 - O2 + (l1 +- l2) n(phi)| = ra,
        again a sinusoid in phi with closed-form roots; between them cross(Q - P1, A - Q) has one sign.
        """
        l1, l2, ra = self.tilt_l1, self.tilt_l2, self.tilt_ra
        p1, b2, o2 = self.link1_pivot, self.tilt_cylinder_base, self.tilt_pivot
        d = _norm(_sub(b2, p1))
        if not (l1 > 0.0 and l2 > 0.0 and ra > 0.0 and d > 0.0):
            raise ValueError("four-bar does not close: a link of zero length")
        lengths = [self.length_retracted[TILT] + s for s in (self.stroke_min[TILT], self.stroke_max[TILT])]
        if not (lengths[0] > abs(l1 - d) and lengths[1] < l1 + d):
            raise ValueError("four-bar does not close: the tilt cylinder cannot reach side link 1 "
                             "at a stroke limit")
        base_dir = math.atan2(b2[1] - p1[1], b2[0] - p1[0])
        phis = [base_dir - math.acos((l1 * l1 + d * d - L * L) / (2.0 * l1 * d)) for L in lengths]
        hi_phi, lo_phi = phis                                    # phi decreases as L grows
        off = _sub(p1, o2)
        c = _norm(off)
        off_dir = math.atan2(off[1], off[0])

        def inside(phi: float) -> bool:
            """phi (any turn) strictly inside the arc (lo_phi, hi_phi), which is shorter than pi."""
            return 0.0 < (phi - lo_phi) % _TWO_PI < hi_phi - lo_phi

        def reach(phi: float) -> float:
            return math.hypot(off[0] + l1 * math.cos(phi), off[1] + l1 * math.sin(phi))

        reaches = [reach(lo_phi), reach(hi_phi)]
        if c > 0.0 and inside(off_dir):
            reaches.append(c + l1)
        if c > 0.0 and inside(off_dir + math.pi):
            reaches.append(abs(c - l1))
        if not (min(reaches) > abs(ra - l2) and max(reaches) < ra + l2):
            raise ValueError("four-bar does not close: side link 2 cannot reach the outer boom "
                             "somewhere over the tilt stroke")
        # where the side links may align: c^2 + k^2 + 2 k c cos(phi - off_dir) = ra^2
        roots = []
        for k in (l1 + l2, l1 - l2):
            if k == 0.0 or c == 0.0:
                continue
            r = (ra * ra - c * c - k * k) / (2.0 * k * c)
            if -1.0 <= r <= 1.0:
                for phi in (off_dir + math.acos(r), off_dir - math.acos(r)):
                    if inside(phi):
                        roots.append(lo_phi + (phi - lo_phi) % _TWO_PI)
        marks = sorted([lo_phi, hi_phi] + roots)
        probes = marks + [(a + b) / 2.0 for a, b in zip(marks, marks[1:])]
        signs = set()
        for phi in probes:
            q = (p1[0] + l1 * math.cos(phi), p1[1] + l1 * math.sin(phi))
            a = _circle(o2, ra, q, l2, -1.0)
            cross = _cross(_sub(q, p1), _sub(a, q))
            signs.add(0 if cross == 0.0 else (1 if cross > 0.0 else -1))
        if len(signs) != 1 or 0 in signs:
            raise ValueError("four-bar passes a dead centre over the tilt stroke (the side links "
                             "align: theta1 stops being monotonic in the stroke)")
        branch = -1.0 if signs == {1} else 1.0
        ends = [self.tilt_angle(s) for s in (self.stroke_min[TILT], self.stroke_max[TILT])]
        lo, hi = -3.0 * _HALF_PI, _HALF_PI
        if not (all(lo < th < hi and ds != 0.0 for th, ds in ends)
                and (ends[1][0] - ends[0][0]) * ends[0][1] > 0.0):
            raise ValueError("the tilt angle leaves (-3pi/2, pi/2) over the tilt stroke")
        return branch

    def _extension_body(self, crane: Any) -> Tuple[float, Vec, float, Tensor]:
        """Body 3 = extension boom + load at the tip, lumped once per crane in the extension
        boom frame (they slide together): mass, centre, izz and in-plane tensor (parallel axes)."""
        m_ext = float(crane.extension_boom.mass)
        c_ext = _vec(crane.extension_boom.com)
        m_load = float(crane.load_mass)
        tip = (self.tip_distance, 0.0)
        m3 = m_ext + m_load
        c3 = ((m_ext * c_ext[0] + m_load * tip[0]) / m3, (m_ext * c_ext[1] + m_load * tip[1]) / m3)
        t_ext = _tensor(crane.extension_boom)
        i3 = float(crane.extension_boom.izz)
        ixx, iyy, ixy = t_ext
        for m, p in ((m_ext, c_ext), (m_load, tip)):
            d = _sub(p, c3)
            i3 += m * _dot(d, d)
            ixx += m * d[1] * d[1]
            iyy += m * d[0] * d[0]
            ixy -= m * d[0] * d[1]
        return m3, c3, i3, (ixx, iyy, ixy)

    # ---------------------------------------------------------------------------------
    # Lift kinematics (triangle)
    # ---------------------------------------------------------------------------------

    def _lift_gamma(self, theta: float) -> float:
        """Angle at O1 from (B1 - O1) to R(theta0) E1."""
        return theta + self.lift_eps - self.lift_beta

    def _lift_length(self, gamma: float) -> float:
        """Cylinder pin-to-pin length for the triangle angle gamma (law of cosines)."""
        db, dr = self.lift_db, self.lift_dr
        return math.sqrt(db * db + dr * dr - 2.0 * db * dr * math.cos(gamma))

    def _lift_ratio(self, gamma: float, length: float) -> float:
        """ds/dtheta0 = db dr sin(gamma) / L."""
        return self.lift_db * self.lift_dr * math.sin(gamma) / length

    def lift_angle(self, stroke: float) -> Pair:
        """Lift angle theta0 and ds/dtheta0 for a lift stroke."""
        db, dr = self.lift_db, self.lift_dr
        length = self.length_retracted[LIFT] + stroke
        cos_gamma = (db * db + dr * dr - length * length) / (2.0 * db * dr)
        if not -1.0 <= cos_gamma <= 1.0:
            raise ValueError(f"lift triangle does not close at stroke {stroke!r}")
        gamma = math.acos(cos_gamma)
        theta = gamma - self.lift_eps + self.lift_beta
        return theta, self._lift_ratio(gamma, length)

    def lift_stroke(self, theta: float) -> float:
        """Lift stroke for a lift angle."""
        return self._lift_length(self._lift_gamma(theta)) - self.length_retracted[LIFT]

    def _lift_transmission(self, theta: float) -> float:
        gamma = self._lift_gamma(theta)
        return self._lift_ratio(gamma, self._lift_length(gamma))

    # ---------------------------------------------------------------------------------
    # Tilt kinematics (four-bar of side links)
    # ---------------------------------------------------------------------------------

    def _tilt_pins(self, theta: float) -> Tuple[Vec, Vec]:
        """(A, Q) in the lift boom frame for a tilt angle: A turns with the outer boom about O2,
        Q closes the side links about P1."""
        a = _rotate(theta, self.link2_attach)
        a = (self.tilt_pivot[0] + a[0], self.tilt_pivot[1] + a[1])
        q = _circle(self.link1_pivot, self.tilt_l1, a, self.tilt_l2, self.tilt_branch)
        return a, q

    def _tilt_ratio(self, q: Vec, a: Vec, length: float) -> float:
        """ds/dtheta1 by virtual velocities: A turns about O2, Q about P1, link QA is rigid."""
        q_arm = _perp(_sub(q, self.link1_pivot))            # perp(Q - P1)
        link = _sub(q, a)                                   # Q - A
        rod = _sub(q, self.tilt_cylinder_base)              # Q - B2
        a_arm = _perp(_sub(a, self.tilt_pivot))             # perp(A - O2)
        return (_dot(rod, q_arm) / length) * _dot(link, a_arm) / _dot(link, q_arm)

    def tilt_angle(self, stroke: float) -> Pair:
        """Tilt angle theta1 (relative to the lift boom) and ds/dtheta1 for a tilt stroke."""
        length = self.length_retracted[TILT] + stroke
        q = _circle(self.link1_pivot, self.tilt_l1, self.tilt_cylinder_base, length, -1.0)
        a = _circle(self.tilt_pivot, self.tilt_ra, q, self.tilt_l2, -1.0)
        theta = _wrap_tilt(
            math.atan2(a[1] - self.tilt_pivot[1], a[0] - self.tilt_pivot[0]) - self.tilt_alpha_a)
        return theta, self._tilt_ratio(q, a, length)

    def tilt_stroke(self, theta: float) -> float:
        """Tilt stroke for a tilt angle."""
        _, q = self._tilt_pins(theta)
        return _norm(_sub(q, self.tilt_cylinder_base)) - self.length_retracted[TILT]

    def _tilt_transmission(self, theta: float) -> float:
        return self._link_pose(theta).ratio

    def _link_pose(self, theta: float) -> _LinkPose:
        """The four-bar at tilt angle theta1 (spec "Side links": pose, velocity ratios).

        The last pose is kept: the tilt transmission and the dynamics of one RK4 stage ask for
        the same angle, and a held or stopped tilt asks for one angle the whole prediction."""
        pose = self._pose
        if pose is not None and pose.theta == theta:
            return pose
        a, q = self._tilt_pins(theta)
        arm_a = _sub(a, self.tilt_pivot)
        arm_q = _sub(q, self.link1_pivot)
        link = _sub(a, q)
        # closure A - Q = R(phi2) link2_end differentiated: dA - dQ is perpendicular to A - Q
        den1 = _dot(_perp(arm_q), link)
        den2 = _dot(_perp(link), arm_q)
        k1 = _dot(_perp(arm_a), link) / den1
        k2 = _dot(_perp(arm_a), arm_q) / den2
        phi1 = math.atan2(arm_q[1], arm_q[0]) - self.link1_angle0
        phi2 = math.atan2(link[1], link[0]) - self.link2_angle0
        e1 = _rotate(phi1, self.link1_com)
        e2 = _rotate(phi2, self.link2_com)
        d1 = (self.link1_pivot[0] + e1[0], self.link1_pivot[1] + e1[1])
        d2 = (q[0] + e2[0], q[1] + e2[1])
        # v1 = dphi1 perp(e1), v2 = dQ + dphi2 perp(e2), dQ = dphi1 perp(Q - P1); per unit u
        j1 = (-k1 * e1[1], k1 * e1[0])
        j2 = (-k1 * arm_q[1] - k2 * e2[1], k1 * arm_q[0] + k2 * e2[0])
        length = _norm(_sub(q, self.tilt_cylinder_base))
        ratio = self._tilt_ratio(q, a, length)
        pose = _LinkPose(theta, ratio, arm_a, arm_q, link, den1, den2, k1, k2,
                         d1, e1, j1, d2, e2, j2, phi1, phi2, length - self.length_retracted[TILT])
        self._pose = pose
        return pose

    # ---------------------------------------------------------------------------------
    # Joint dispatch
    # ---------------------------------------------------------------------------------

    def joint_angle(self, joint: int, stroke: float) -> Pair:
        """(theta, ds/dtheta) of joint 0 (lift) or 1 (tilt) for a stroke."""
        return self.lift_angle(stroke) if joint == LIFT else self.tilt_angle(stroke)

    def joint_stroke(self, joint: int, theta: float) -> float:
        """Stroke of joint 0 (lift) or 1 (tilt) for an angle."""
        return self.lift_stroke(theta) if joint == LIFT else self.tilt_stroke(theta)

    def transmission(self, joint: int, theta: float) -> float:
        """ds/dtheta of a joint at an angle (what turns cylinder force into joint torque)."""
        return self._lift_transmission(theta) if joint == LIFT else self._tilt_transmission(theta)

    # ---------------------------------------------------------------------------------
    # Dynamics
    # ---------------------------------------------------------------------------------

    def _configuration(self, theta: Sequence[float], extension: Optional[float] = None
                       ) -> _Configuration:
        """Everything ID needs about the configuration (theta, e), in the boom plane; the
        extension defaults to the model's."""
        th0, th1 = theta[0], theta[1]
        e = self.extension if extension is None else extension
        c = math.cos(th0)
        s = math.sin(th0)

        def rot(v: Vec) -> Vec:   # R(theta0) v
            return (c * v[0] - s * v[1], s * v[0] + c * v[1])

        pose = self._link_pose(th1)
        th12 = th0 + th1
        mount = self.extension_mount
        lumped = self._lumped_outer_body(e)
        return _Configuration(
            (self._lift_transmission(th0), pose.ratio), pose.stroke,
            rot(self.tilt_pivot), rot(self.c1), _rotate(th12, self.c2),
            _rotate(th12, (mount[0] + e + self.c3[0], mount[1] + self.c3[1])),
            (math.cos(th12), math.sin(th12)), th0, th12,
            rot(pose.arm_a), rot(pose.arm_q), rot(pose.link), pose.den1, pose.den2,
            pose.k1, pose.k2,
            rot(pose.d1), rot(pose.e1), rot(pose.j1), rot(pose.d2), rot(pose.e2), rot(pose.j2),
            th0 + pose.phi1, th0 + pose.phi2, (lumped[0], lumped[2]), _rotate(th12, lumped[1]))

    def inverse_dynamics(self, theta: Sequence[float], omega: Sequence[float],
                         alpha: Sequence[float], gravity: Optional[float] = None) -> Pair:
        """Joint torques (tau0, tau1) by the iterative planar Newton-Euler of the spec, with the
        side links' share by virtual work.

        Gravity enters as a base acceleration (0, +g); ``gravity`` defaults to the crane's and
        is 0 when building the mass matrix.
        """
        g = self.gravity if gravity is None else gravity
        return self._inverse_dynamics(self._configuration(theta), omega, alpha, g)

    def _lumped_outer_body(self, e: float) -> Tuple[float, Vec, float]:
        """Body 2 = outer boom + extension boom at extension e + load at the tip, in the outer boom
        frame (spec "Bodies and the lumped outer boom"): the planar model's body 2, for motion
        with the extension at rest; summed in the spec's order (the C core's)."""
        cached = self._lumped.get(e)
        if cached is not None:
            return cached
        m_ob, c_ob, m_ext, c_ext, m_load = self.m2, self.c2, self._m_ext, self._c_ext, self._m_load
        mount = self.extension_mount
        x_ext = (mount[0] + e + c_ext[0], mount[1] + c_ext[1])
        x_tip = (mount[0] + e + self.tip_distance, mount[1])
        m2 = m_ob + m_ext + m_load
        c2 = ((m_ob * c_ob[0] + m_ext * x_ext[0] + m_load * x_tip[0]) / m2,
              (m_ob * c_ob[1] + m_ext * x_ext[1] + m_load * x_tip[1]) / m2)

        def offset2(p: Vec) -> float:
            d = _sub(p, c2)
            return _dot(d, d)

        i2 = (self.i2 + m_ob * offset2(c_ob) + self._i_ext + m_ext * offset2(x_ext)
              + m_load * offset2(x_tip))
        lumped = (m2, c2, i2)
        self._lumped[e] = lumped
        return lumped

    def _inverse_dynamics(self, conf: _Configuration, omega: Sequence[float],
                          alpha: Sequence[float], g: float) -> Pair:
        """ID of the planar model (spec "Dynamics"): the slew and the extension at rest, the
        outer boom lumped with the extension boom and the load, then the two side links. (The
        same physics as _id4 with their rates zero; kept in the planar model's arithmetic, which
        the C core shares, so that rounding does not move a located event between them.)"""
        w1 = omega[0]
        w2 = omega[0] + omega[1]
        a1 = alpha[0]
        a2 = alpha[0] + alpha[1]
        r12, cc1, cc2 = conf.r12, conf.cc1, conf.cc2l
        m1 = self.m1
        m2, i2 = conf.lumped

        # forward recursion: accelerations (acc = acc_parent + a perp(r) - w^2 r)
        acc_c1 = (-a1 * cc1[1] - w1 * w1 * cc1[0], g + a1 * cc1[0] - w1 * w1 * cc1[1])
        acc_o2 = (-a1 * r12[1] - w1 * w1 * r12[0], g + a1 * r12[0] - w1 * w1 * r12[1])
        acc_c2 = (acc_o2[0] - a2 * cc2[1] - w2 * w2 * cc2[0],
                  acc_o2[1] + a2 * cc2[0] - w2 * w2 * cc2[1])

        # backward recursion: forces and moments about each joint
        f2 = (m2 * acc_c2[0], m2 * acc_c2[1])
        n2 = i2 * a2 + _cross(cc2, f2)
        f1c = (m1 * acc_c1[0], m1 * acc_c1[1])
        n1 = self.i1 * a1 + _cross(cc1, f1c) + _cross(r12, f2) + n2

        links = self._side_link_torques(conf, w1, a1, omega[1], alpha[1], g)
        return n1 + links[0], n2 + links[1]

    def inverse_dynamics4(self, q: Sequence[float], qd: Sequence[float], qdd: Sequence[float],
                          gravity: Optional[float] = None) -> Quad:
        """Generalized forces (tau0, tau1, tau_s, tau_e) of the four joints, q = (theta0,
        theta1, psi, e) (spec "Four joints"): N m for the revolute joints, N for the extension."""
        g = self.gravity if gravity is None else gravity
        return self._id4(self._configuration((q[0], q[1]), q[3]), qd, qdd, g)

    def _id4(self, conf: _Configuration, qd: Sequence[float], qdd: Sequence[float],
             g: float) -> Quad:
        """ID at a prepared configuration: the three in-plane bodies with the slew's centripetal
        and gyroscopic terms, the side links, then the slew's J_z alpha_s + Jdot_z omega_s."""
        w1 = qd[0]
        w2 = qd[0] + qd[1]
        ws = qd[2]
        ve = qd[3]
        a1 = qdd[0]
        a2 = qdd[0] + qdd[1]
        ae = qdd[3]
        r12, cc1, cc2, cc3, u = conf.r12, conf.cc1, conf.cc2, conf.cc3, conf.u
        m1, m2, m3 = self.m1, self.m2, self.m3
        s2 = ws * ws
        x0 = self.lift_pivot[0]               # O1's distance from the slew axis
        x2 = x0 + r12[0]                      # O2's
        if s2 != 0.0:
            n_g1 = -0.5 * s2 * _vertical_inertia(self.t1, conf.th0)[1]
            n_g23 = _vertical_inertia(self.t2, conf.th12)[1] + _vertical_inertia(self.t3, conf.th12)[1]
            n_g23 *= -0.5 * s2
        else:
            n_g1 = n_g23 = 0.0

        # forward recursion: accelerations (acc = acc_parent + a perp(r) - w^2 r + cen)
        acc_c1 = (-a1 * cc1[1] - w1 * w1 * cc1[0] - s2 * (x0 + cc1[0]),
                  g + a1 * cc1[0] - w1 * w1 * cc1[1])
        acc_o2 = (-a1 * r12[1] - w1 * w1 * r12[0], g + a1 * r12[0] - w1 * w1 * r12[1])
        acc_c2 = (acc_o2[0] - a2 * cc2[1] - w2 * w2 * cc2[0] - s2 * (x2 + cc2[0]),
                  acc_o2[1] + a2 * cc2[0] - w2 * w2 * cc2[1])
        cor = 2.0 * w2 * ve                   # Coriolis of the sliding body 3: cor perp(u)
        acc_c3 = (acc_o2[0] - a2 * cc3[1] - w2 * w2 * cc3[0] - cor * u[1] + ae * u[0]
                  - s2 * (x2 + cc3[0]),
                  acc_o2[1] + a2 * cc3[0] - w2 * w2 * cc3[1] + cor * u[0] + ae * u[1])

        # backward recursion: forces and moments about each joint
        f3 = (m3 * acc_c3[0], m3 * acc_c3[1])
        tau_e = _dot(f3, u)
        f2c = (m2 * acc_c2[0], m2 * acc_c2[1])
        n2 = (self.i2 + self.i3) * a2 + n_g23 + _cross(cc2, f2c) + _cross(cc3, f3)
        f2 = (f2c[0] + f3[0], f2c[1] + f3[1])
        f1c = (m1 * acc_c1[0], m1 * acc_c1[1])
        n1 = self.i1 * a1 + n_g1 + _cross(cc1, f1c) + _cross(r12, f2) + n2

        links = self._side_link_torques(conf, w1, a1, qd[1], qdd[1], g, s2)
        tau_s = 0.0
        if ws != 0.0 or qdd[2] != 0.0:
            j_z, j_dot = self._slew_inertia(conf, qd)
            tau_s = j_z * qdd[2] + j_dot * ws
        return n1 + links[0], n2 + links[1], tau_s, tau_e

    def slew_inertia(self, q: Sequence[float], qd: Sequence[float]) -> Pair:
        """(J_z, dJ_z/dt): the crane's inertia about the slew axis at q and its rate of change
        with the rates qd (spec "Four joints")."""
        return self._slew_inertia(self._configuration((q[0], q[1]), q[3]), qd)

    def _slew_inertia(self, conf: _Configuration, qd: Sequence[float]) -> Pair:
        w1 = qd[0]
        w2 = qd[0] + qd[1]
        r12, cc1, cc2, cc3 = conf.r12, conf.cc1, conf.cc2, conf.cc3
        x0 = self.lift_pivot[0]
        x2 = x0 + r12[0]
        j_z = self.pillar_inertia
        j_dot = 0.0
        # (mass, x from the axis, xdot, tensor, phi, phidot) of every moving body
        k1 = conf.k1 * qd[1]
        k2 = conf.k2 * qd[1]
        bodies = (
            (self.m1, x0 + cc1[0], -w1 * cc1[1], self.t1, conf.th0, w1),
            (self.m2, x2 + cc2[0], -w1 * r12[1] - w2 * cc2[1], self.t2, conf.th12, w2),
            (self.m3, x2 + cc3[0], -w1 * r12[1] - w2 * cc3[1] + qd[3] * conf.u[0], self.t3,
             conf.th12, w2),
            (self.link1_mass, x0 + conf.d1[0], qd[1] * conf.j1[0] - w1 * conf.d1[1],
             self.link1_tensor, conf.phi1, w1 + k1),
            (self.link2_mass, x0 + conf.d2[0], qd[1] * conf.j2[0] - w1 * conf.d2[1],
             self.link2_tensor, conf.phi2, w1 + k2),
        )
        for m, x, xdot, t, phi, phidot in bodies:
            j_v, j_v_prime = _vertical_inertia(t, phi)
            j_z += m * x * x + j_v
            j_dot += 2.0 * m * x * xdot + j_v_prime * phidot
        return j_z, j_dot

    def _side_link_torques(self, conf: _Configuration, w1: float, a1: float,
                           u: float, a: float, g: float, s2: float = 0.0) -> Pair:
        """The side links' share of (tau0, tau1) (spec "Side links"): the four-bar's
        acceleration analysis gives each link's motion relative to the lift boom, which the
        lift boom's own motion then carries."""
        arm_a, arm_q, link = conf.arm_a, conf.arm_q, conf.link
        dphi1 = conf.k1 * u
        dphi2 = conf.k2 * u
        # rhs = ddA + dphi1^2 (Q - P1) + dphi2^2 (A - Q), ddA = a perp(A - O2) - u^2 (A - O2)
        sq1 = dphi1 * dphi1
        sq2 = dphi2 * dphi2
        rhs = (-a * arm_a[1] - u * u * arm_a[0] + sq1 * arm_q[0] + sq2 * link[0],
               a * arm_a[0] - u * u * arm_a[1] + sq1 * arm_q[1] + sq2 * link[1])
        ddphi1 = _dot(rhs, link) / conf.den1
        ddphi2 = _dot(rhs, arm_q) / conf.den2
        # side link 2 rides on the pin Q, which turns about P1 with side link 1
        dq = (-dphi1 * arm_q[1], dphi1 * arm_q[0])
        ddq = (-ddphi1 * arm_q[1] - sq1 * arm_q[0], ddphi1 * arm_q[0] - sq1 * arm_q[1])
        cen1 = cen2 = n_g1 = n_g2 = 0.0
        if s2 != 0.0:   # the slew's centripetal acceleration and gyroscopic moment
            x0 = self.lift_pivot[0]
            cen1 = -s2 * (x0 + conf.d1[0])
            cen2 = -s2 * (x0 + conf.d2[0])
            n_g1 = -0.5 * s2 * _vertical_inertia(self.link1_tensor, conf.phi1)[1]
            n_g2 = -0.5 * s2 * _vertical_inertia(self.link2_tensor, conf.phi2)[1]
        tau1_0, tau1_1 = _link_torques(self.link1_mass, self.link1_izz, conf.k1, conf.d1, conf.e1,
                                       conf.j1, (0.0, 0.0), (0.0, 0.0), dphi1, ddphi1, w1, a1, g,
                                       cen1, n_g1)
        tau2_0, tau2_1 = _link_torques(self.link2_mass, self.link2_izz, conf.k2, conf.d2, conf.e2,
                                       conf.j2, dq, ddq, dphi2, ddphi2, w1, a1, g, cen2, n_g2)
        return tau1_0 + tau2_0, tau1_1 + tau2_1

    def mass_matrix(self, theta: Sequence[float]) -> Matrix2:
        """M with column j = ID(theta, 0, e_j, g=0)."""
        return self._mass_matrix(self._configuration(theta))

    def _mass_matrix(self, conf: _Configuration) -> Matrix2:
        col0 = self._inverse_dynamics(conf, (0.0, 0.0), (1.0, 0.0), 0.0)
        col1 = self._inverse_dynamics(conf, (0.0, 0.0), (0.0, 1.0), 0.0)
        return ((col0[0], col1[0]), (col0[1], col1[1]))

    def bias(self, theta: Sequence[float], omega: Sequence[float]) -> Pair:
        """h = ID(theta, omega, 0, g): Coriolis, centrifugal and gravity torques."""
        return self._inverse_dynamics(self._configuration(theta), omega, (0.0, 0.0), self.gravity)

    def forward_dynamics(self, theta: Sequence[float], omega: Sequence[float],
                         tau: Sequence[float], locked: Sequence[bool]) -> Pair:
        """Joint accelerations from M alpha = tau - h; a locked joint has alpha = 0 and the
        other obeys M_ii alpha_i = tau_i - h_i (only column i of M is needed then)."""
        return self._forward_dynamics(self._configuration(theta), omega, tau, locked)

    def _forward_dynamics(self, conf: _Configuration, omega: Sequence[float],
                          tau: Sequence[float], locked: Sequence[bool]) -> Pair:
        lock0, lock1 = bool(locked[0]), bool(locked[1])
        if lock0 and lock1:
            return 0.0, 0.0
        h = self._inverse_dynamics(conf, omega, (0.0, 0.0), self.gravity)
        if lock0:
            m11 = self._inverse_dynamics(conf, (0.0, 0.0), (0.0, 1.0), 0.0)[1]
            return 0.0, (tau[1] - h[1]) / m11
        if lock1:
            m00 = self._inverse_dynamics(conf, (0.0, 0.0), (1.0, 0.0), 0.0)[0]
            return (tau[0] - h[0]) / m00, 0.0
        (m00, m01), (m10, m11) = self._mass_matrix(conf)
        r0 = tau[0] - h[0]
        r1 = tau[1] - h[1]
        det = m00 * m11 - m01 * m10
        return (m11 * r0 - m01 * r1) / det, (m00 * r1 - m10 * r0) / det

    def inverse_mass_matrix(self, theta: Sequence[float]) -> Matrix2:
        """M^-1, used by the plastic impact."""
        (m00, m01), (m10, m11) = self.mass_matrix(theta)
        det = m00 * m11 - m01 * m10
        return ((m11 / det, -m01 / det), (-m10 / det, m00 / det))

    # ---------------------------------------------------------------------------------
    # Four joints: mass matrix and forward dynamics (spec "Four joints")
    # ---------------------------------------------------------------------------------

    def _mass_matrix4(self, conf: _Configuration, joints: Sequence[int]) -> List[List[float]]:
        """The rows and columns `joints` of M (columns ID(q, 0, e_j, 0)); block diagonal, so the
        slew's entry is J_z alone."""
        cols = []
        for j in joints:
            unit = [0.0, 0.0, 0.0, 0.0]
            unit[j] = 1.0
            col = self._id4(conf, (0.0, 0.0, 0.0, 0.0), unit, 0.0)
            cols.append([col[i] for i in joints])
        return [[cols[c][r] for c in range(len(joints))] for r in range(len(joints))]

    def _forward4(self, conf: _Configuration, qd: Sequence[float], tau: Sequence[float],
                  locked: Sequence[bool]) -> Quad:
        """qdd from M qdd = tau - h over the joints that are not locked (the others 0)."""
        free = [j for j in (LIFT, TILT, SLEW, EXTENSION) if not locked[j]]
        if not free:
            return 0.0, 0.0, 0.0, 0.0
        h = self._id4(conf, qd, (0.0, 0.0, 0.0, 0.0), self.gravity)
        mass = self._mass_matrix4(conf, free)
        sol = _solve(mass, [tau[j] - h[j] for j in free])
        out = [0.0, 0.0, 0.0, 0.0]
        for j, a in zip(free, sol):
            out[j] = a
        return out[0], out[1], out[2], out[3]

    def friction_slope(self, joint: int) -> float:
        """G_f, N s/m: the slope of the actuator's friction force at rest, k (4 F_C + 16/9 (F_S -
        F_C)) / v_S + sigma tanh(4) (the law's steepest point)."""
        f_c, f_s, sigma, v_s, k = self.friction[joint]
        return k * (4.0 * f_c + 16.0 / 9.0 * (f_s - f_c)) / v_s + sigma * math.tanh(4.0)

    def forward_dynamics4(self, q: Sequence[float], qd: Sequence[float], tau: Sequence[float],
                          locked: Sequence[bool]) -> Quad:
        """Joint accelerations of the four joints; a locked joint has qdd = 0."""
        return self._forward4(self._configuration((q[0], q[1]), q[3]), qd, tau, locked)

    # ---------------------------------------------------------------------------------
    # Cylinders
    # ---------------------------------------------------------------------------------

    def friction_force(self, joint: int, stroke_rate: float) -> float:
        """[S1]'s smooth Stribeck friction opposing the stroke rate: with x = |v| / v_S,
        k [F_C tanh(4x) + (F_S - F_C) x / (x^2/4 + 3/4)^2] sign(v) + sigma tanh(4) v."""
        f_c, f_s, sigma, v_s, k = self.friction[joint]
        if stroke_rate == 0.0:
            return 0.0
        x = abs(stroke_rate) / v_s
        q = x * x / 4.0 + 0.75
        levels = k * (f_c * math.tanh(4.0 * x) + (f_s - f_c) * x / (q * q))
        return math.copysign(levels, stroke_rate) + sigma * math.tanh(4.0) * stroke_rate

    def cylinder_force(self, joint: int, p_a: float, p_b: float, stroke_rate: float) -> float:
        """Piston force (N, positive extends): pressures on both areas minus friction."""
        return p_a * self.area_bore[joint] - p_b * self.area_rod[joint] \
            - self.friction_force(joint, stroke_rate)

    def joint_torque(self, joint: int, theta: float, omega: float, p_a: float, p_b: float) -> float:
        """tau_i = F_i ds/dtheta_i, with the stroke rate v_i = ds/dtheta_i omega_i."""
        return self._joint_torque(joint, self.transmission(joint, theta), omega, p_a, p_b)

    def _joint_torque(self, joint: int, ratio: float, omega: float, p_a: float, p_b: float) -> float:
        """joint_torque with the transmission ds/dtheta_i already known."""
        return self.cylinder_force(joint, p_a, p_b, ratio * omega) * ratio

    # ---------------------------------------------------------------------------------
    # Points
    # ---------------------------------------------------------------------------------

    def _frames(self, theta: Sequence[float], slew: float, extension: Optional[float] = None
                ) -> Tuple[Matrix4, Matrix4, Matrix4, Matrix4]:
        """World transforms of the boom plane, lift boom, outer boom and extension boom frames."""
        e = self.extension if extension is None else extension
        t_w0 = _world_transform(slew)
        t_w1 = _compose(t_w0, _planar_transform(theta[0], self.lift_pivot))
        t_w2 = _compose(t_w1, _planar_transform(theta[1], self.tilt_pivot))
        mount = self.extension_mount
        t_we = _compose(t_w2, _planar_transform(0.0, (mount[0] + e, mount[1])))
        return t_w0, t_w1, t_w2, t_we

    def points(self, theta: Sequence[float], slew: float, extension: Optional[float] = None
               ) -> List[Tuple[float, float, float]]:
        """The 11 POINT_NAMES points in world coordinates (m), for drawing the crane."""
        t_w0, t_w1, t_w2, t_we = self._frames(theta, slew, extension)
        _, q = self._tilt_pins(theta[1])
        return [
            _apply(t_w0, (0.0, 0.0)),
            _apply(t_w0, self.lift_pivot),
            _apply(t_w0, self.lift_cylinder_base),
            _apply(t_w1, self.lift_cylinder_rod),
            _apply(t_w1, self.tilt_cylinder_base),
            _apply(t_w1, self.link1_pivot),
            _apply(t_w1, q),
            _apply(t_w2, self.link2_attach),
            _apply(t_w1, self.tilt_pivot),
            _apply(t_w2, self.extension_mount),
            _apply(t_we, (self.tip_distance, 0.0)),
        ]

    def tip(self, theta: Sequence[float], slew: float, extension: Optional[float] = None
            ) -> Tuple[float, float, float]:
        """World position of the load point, T_w0 T01 T12 T2e (tip_distance, 0, 0, 1)."""
        return _apply(self._frames(theta, slew, extension)[3], (self.tip_distance, 0.0))


# --------------------------------------------------------------------------------------------
# Drives
# --------------------------------------------------------------------------------------------

class _PressureDrive:
    """Chamber pressures of one cylinder: constant, or samples interpolated linearly."""

    def __init__(self, drive: Any) -> None:
        times = getattr(drive, "t", None)
        if times is None:
            self.times: Optional[List[float]] = None
            self.p_a: Any = float(drive.p_a)
            self.p_b: Any = float(drive.p_b)
        else:
            self.times = [float(x) for x in times]
            self.p_a = [float(x) for x in drive.p_a]
            self.p_b = [float(x) for x in drive.p_b]

    def pressures(self, t: float) -> Pair:
        if self.times is None:
            return self.p_a, self.p_b
        ts = self.times
        k = bisect_right(ts, t) - 1
        k = min(max(k, 0), len(ts) - 2)
        s = (t - ts[k]) / (ts[k + 1] - ts[k])
        return (self.p_a[k] + s * (self.p_a[k + 1] - self.p_a[k]),
                self.p_b[k] + s * (self.p_b[k + 1] - self.p_b[k]))


def _signed_root(dp: float, laminar: float) -> float:
    """The orifice law g(dp) of docs/model.md: sign(dp) sqrt|dp|, replaced for |dp| < laminar by
    the odd cubic that meets it with the same value and slope (so the flow stays Lipschitz)."""
    if dp >= laminar:
        return math.sqrt(dp)
    if dp <= -laminar:
        return -math.sqrt(-dp)
    x = dp / laminar
    return math.sqrt(laminar) * x * (5.0 - x * x) * 0.25


def _saturation(x: float) -> float:
    """phi(x) of the compensated valve's meter-in edge: 0 below 0, 1 above 1, C1 in between."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x * (3.0 - x * x) * 0.5


class _ValveDrive:
    """A valve-driven cylinder: the lever signal and the circuit of docs/model.md "Hydraulics"."""

    def __init__(self, drive: Any, cylinder: Any) -> None:
        hyd = cylinder.hydraulics
        times = getattr(drive, "t", None)
        if times is None:
            self.times: Optional[List[float]] = None
            self.u: Any = float(drive.u)
        else:
            self.times = [float(x) for x in times]
            self.u = [float(x) for x in drive.u]
        self.compensated = hyd.valve == "compensated"
        self.p_s = float(hyd.supply_pressure)
        self.p_t = float(hyd.tank_pressure)
        self.p_r = float(hyd.relief_pressure)
        self.p_c = float(hyd.cavitation_pressure)
        self.laminar = float(hyd.laminar_pressure_drop)
        self.q_n = float(hyd.nominal_flow)
        self.k = self.q_n / math.sqrt(float(hyd.nominal_pressure_drop))
        self.dead_band = float(hyd.dead_band)
        if self.compensated:
            self.k_m = float(hyd.meter_out_flow) / math.sqrt(float(hyd.meter_out_pressure_drop))
            self.gradient = max(1.25 * self.k_m / math.sqrt(self.laminar),
                                1.5 * self.q_n / self.laminar)
        else:
            self.k_m = 0.0
            self.gradient = 1.25 * self.k / math.sqrt(self.laminar)
        # the relief and anti-cavitation valves: the nominal flow at LIMIT_OVERRIDE beyond their
        # settings
        self.limit_gradient = self.q_n / LIMIT_OVERRIDE
        self.tau = float(hyd.spool_time_constant)
        self.leakage = float(hyd.leakage)
        self.v_hose = (float(hyd.hose_volume_a), float(hyd.hose_volume_b))
        self.b_oil = float(hyd.oil_bulk_modulus)
        self.b_hose = float(hyd.hose_bulk_modulus)
        self.b_cyl = float(hyd.cylinder_bulk_modulus)
        self.area_a = math.pi * float(cylinder.bore) ** 2 / 4.0
        self.area_b = math.pi * (float(cylinder.bore) ** 2 - float(cylinder.rod) ** 2) / 4.0
        self.stroke_min = float(cylinder.stroke_min)
        self.stroke_max = float(cylinder.stroke_max)

    def lever(self, t: float) -> float:
        if self.times is None:
            return self.u
        ts = self.times
        k = bisect_right(ts, t) - 1
        k = min(max(k, 0), len(ts) - 2)
        s = (t - ts[k]) / (ts[k + 1] - ts[k])
        return self.u[k] + s * (self.u[k + 1] - self.u[k])

    def volumes(self, stroke: float) -> Pair:
        return (self.v_hose[0] + self.area_a * (stroke - self.stroke_min),
                self.v_hose[1] + self.area_b * (self.stroke_max - stroke))

    def compliance(self, volume: float, side: int) -> float:
        """C(V) = V / Be: the oil, the cylinder wall and the hose in series."""
        v_hose = self.v_hose[side]
        return volume / self.b_oil + (volume - v_hose) / self.b_cyl + v_hose / self.b_hose

    def flows(self, y: float, p_a: float, p_b: float) -> Pair:
        """(Q_a into the bore side, Q_b out of the rod side) through the valve at spool y."""
        lam = self.laminar
        if not self.compensated:
            k = y * self.k
            if y >= 0.0:
                return k * _signed_root(self.p_s - p_a, lam), k * _signed_root(p_b - self.p_t, lam)
            return k * _signed_root(p_a - self.p_t, lam), k * _signed_root(self.p_s - p_b, lam)
        u0 = self.dead_band
        if y > u0:
            r = (y - u0) / (1.0 - u0)
            return (r * self.q_n * _saturation((self.p_s - p_a) / lam),
                    r * self.k_m * _signed_root(p_b - self.p_t, lam))
        if y < -u0:
            r = (-y - u0) / (1.0 - u0)
            return (-r * self.k_m * _signed_root(p_a - self.p_t, lam),
                    -r * self.q_n * _saturation((self.p_s - p_b) / lam))
        return 0.0, 0.0

    def limit_coefficients(self, stroke: float) -> Tuple[float, float]:
        """G_lim / C(V) of both chambers at a stroke: the rates of limit_valves."""
        v_a, v_b = self.volumes(stroke)
        return (self.limit_gradient / self.compliance(v_a, 0),
                self.limit_gradient / self.compliance(v_b, 1))

    def limit_valves(self, coef: Tuple[float, float], dt: float, p_a: float,
                     p_b: float) -> Tuple[float, float]:
        """The relief and anti-cavitation valves over dt (docs/model.md, "Relief, cavitation
        floor, leakage"): implicit Euler of dp/dt = Q_lim(p)/C(V) for each chamber alone, with
        the rates coef = G_lim/C(V) at the substep's start."""
        out = []
        for p, c in zip((p_a, p_b), coef):
            ref = self.p_c if p < self.p_c else self.p_r if p > self.p_r else p
            out.append(ref + (p - ref) / (1.0 + dt * c))
        return out[0], out[1]

    def rates(self, t: float, stroke: float, v: float, p_a: float, p_b: float,
              y: float) -> Tuple[float, float, float]:
        """(dp_a/dt, dp_b/dt, dy/dt) of the chamber equations."""
        if self.tau > 0.0:
            dy = (self.lever(t) - y) / self.tau
        else:
            y = self.lever(t)
            dy = 0.0
        q_a, q_b = self.flows(y, p_a, p_b)
        v_a, v_b = self.volumes(stroke)
        q_l = self.leakage * (p_a - p_b)
        # the relief and anti-cavitation valves are not here: limit_valves, implicitly
        dp_a = (q_a - self.area_a * v - q_l) / self.compliance(v_a, 0)
        dp_b = (self.area_b * v - q_b + q_l) / self.compliance(v_b, 1)
        return dp_a, dp_b, dy

    def stiffness(self, stroke: float) -> float:
        """lambda of docs/model.md: the bound of the pressure and spool rates at this stroke (each
        chamber's self-feedback, the leakage counted twice for the pair it couples, 1/tau)."""
        v_a, v_b = self.volumes(stroke)
        g = 2.0 * self.gradient + 2.0 * self.leakage
        lam = max(g / self.compliance(v_a, 0), g / self.compliance(v_b, 1))
        return max(lam, 1.0 / self.tau) if self.tau > 0 else lam


#: The relief and anti-cavitation valves pass the valve's nominal flow this far beyond their
#: settings, Pa (docs/model.md, "Relief, cavitation floor, leakage").
LIMIT_OVERRIDE = 5e3

#: Substeps keep lambda h/n below this (RK4 is stable on the negative real axis up to 2.785).
SUBSTEP_STABILITY = 2.5


def _drive(drive: Any, cylinder: Any = None) -> Any:
    """None for a held cylinder, else its pressure or valve drive."""
    if getattr(drive, "held", False):
        return None
    if hasattr(drive, "u"):
        return _ValveDrive(drive, cylinder)
    return _PressureDrive(drive)


# --------------------------------------------------------------------------------------------
# Integration with end stops
# --------------------------------------------------------------------------------------------

State8 = Tuple[float, ...]   # (theta0, theta1, psi, e, omega0, omega1, omega_s, v_e)

JOINTS = (LIFT, TILT, SLEW, EXTENSION)
#: The joints' names in State's fields (lift_p_a, slew_p_a, ...).
JOINT_NAMES = ("lift", "tilt", "slew", "extension")


class _Prediction:
    """One prediction: the model, the drives and the joint status (held / stopped side) of the
    four joints (spec "Four joints": the end-stop rules of "End stops" over four joints)."""

    def __init__(self, model: TwinModel, drives: Sequence[Optional[_PressureDrive]]) -> None:
        self.model = model
        self.drives = tuple(drives)
        self.held = tuple(d is None for d in drives)
        #: the valve-driven joints; with any, the state is 10 long: (theta0, theta1, omega0,
        #: omega1, p_a0, p_b0, p_a1, p_b1, y0, y1), entries of other joints unused (kept at 0)
        self.valve = tuple(isinstance(d, _ValveDrive) for d in drives)
        self.hydraulic = any(self.valve)
        #: G_lim/C(V) of both chambers of each valve-driven joint at the start of the current
        #: substep (substeps): the rates of the relief and anti-cavitation valves' implicit update
        self.limit_coef: List[Tuple[float, float]] = [(0.0, 0.0)] * 4
        #: stop[j]: 0 not stopped, -1 at the lower angle limit, +1 at the upper (angle terms;
        #: the reported flag is converted to actuator terms by TwinModel.stop_flag)
        self.stop = [0, 0, 0, 0]
        #: the last release verdict, ((t, x, stop), released): a step that ends on a stop asks
        #: at its end and the next step asks again at its start, mostly at the same t
        self._last_release: Optional[Tuple[Tuple[Any, ...], Tuple[int, ...]]] = None
        #: (time, joint, angle side) of every impact, for diagnostics
        self.events: List[Tuple[float, int, int]] = []

    def locked(self) -> Tuple[bool, ...]:
        return tuple(self.held[j] or self.stop[j] != 0 for j in JOINTS)

    def _conf(self, x: Sequence[float]) -> _Configuration:
        return self.model._configuration((x[0], x[1]), x[3])

    def acceleration(self, t: float, x: Sequence[float], locked: Tuple[bool, ...]) -> Quad:
        """qdd at time t: actuator forces of the unlocked joints into forward dynamics."""
        if all(locked):
            return 0.0, 0.0, 0.0, 0.0
        conf = self._conf(x)
        qd = x[4:8]
        tau = self.torques(t, conf, qd, locked, x)
        if locked[SLEW] and locked[EXTENSION]:
            # both at rest (held, or stopped with the rate zeroed): the planar 2x2 solve
            a = self.model._forward_dynamics(conf, qd[:2], tau[:2], locked[:2])
            return a[0], a[1], 0.0, 0.0
        return self.model._forward4(conf, qd, tau, locked)

    def ratio(self, conf: _Configuration, j: int) -> float:
        """ds/dq of joint j's actuator."""
        if j == SLEW:
            return self.model.slew_ratio
        if j == EXTENSION:
            return 1.0
        return conf.ratio[j]

    def torques(self, t: float, conf: _Configuration, qd: Sequence[float],
                locked: Sequence[bool], x: Sequence[float]) -> Quad:
        """Actuator forces at time t of the joints that are not locked (0 for the others); a
        valve-driven cylinder's pressures are the state's."""
        tau = [0.0, 0.0, 0.0, 0.0]
        for j in JOINTS:
            if not locked[j]:
                if self.valve[j]:
                    p_a, p_b = x[HYD + 2 * j], x[HYD + 1 + 2 * j]
                else:
                    p_a, p_b = self.drives[j].pressures(t)  # type: ignore[union-attr]
                tau[j] = self.model._joint_torque(j, self.ratio(conf, j), qd[j], p_a, p_b)
        return tau[0], tau[1], tau[2], tau[3]

    def stroke(self, j: int, theta: float, conf: Optional[_Configuration] = None) -> float:
        """Joint j's stroke: its limit on a stop, else from the angle (the slew: the rack's
        travel r_p (psi - slew_min); the extension: e - extension_min)."""
        if j in (SLEW, EXTENSION):
            lower, upper = self.model.angle_limits[j]
            q = theta if self.stop[j] == 0 else (lower if self.stop[j] < 0 else upper)
            return self.ratio(None, j) * (q - lower)  # type: ignore[arg-type]
        if self.stop[j] != 0:
            return self.model.stroke_at_stop[j][self.stop[j]]
        if j == LIFT:
            return self.model.lift_stroke(theta)
        return conf.tilt_stroke if conf is not None else self.model.tilt_stroke(theta)

    def derivative(self, t: float, x: Sequence[float], locked: Tuple[bool, ...]) -> Tuple[float, ...]:
        """d/dt of the hydraulic state: qd, qdd, the chamber pressures, the spools."""
        conf = self._conf(x)
        qdd = self.acceleration(t, x, locked)
        d = list(x[4:8]) + list(qdd) + [0.0] * 12
        for j in JOINTS:
            if not self.valve[j]:
                continue
            v = 0.0 if locked[j] else self.ratio(conf, j) * x[4 + j]
            d[HYD + 2 * j], d[HYD + 1 + 2 * j], d[SPOOL + j] = self.drives[j].rates(  # type: ignore
                t, self.stroke(j, x[j], conf), v, x[HYD + 2 * j], x[HYD + 1 + 2 * j], x[SPOOL + j])
        return tuple(d)

    def rk4_hydraulic(self, t: float, x: Sequence[float], h: float,
                      locked: Tuple[bool, ...]) -> Tuple[float, ...]:
        """Classical RK4 on the whole hydraulic state (docs/model.md, "Hydraulics")."""
        half = 0.5 * h
        k1 = self.derivative(t, x, locked)
        x2 = self.limit_valves(tuple(a + half * b for a, b in zip(x, k1)), half)
        k2 = self.derivative(t + half, x2, locked)
        x3 = self.limit_valves(tuple(a + half * b for a, b in zip(x, k2)), half)
        k3 = self.derivative(t + half, x3, locked)
        x4 = self.limit_valves(tuple(a + h * b for a, b in zip(x, k3)), h)
        k4 = self.derivative(t + h, x4, locked)
        sixth = h / 6.0
        return self.limit_valves(tuple(a + sixth * (b1 + 2.0 * b2 + 2.0 * b3 + b4)
                                       for a, b1, b2, b3, b4 in zip(x, k1, k2, k3, k4)), h)

    def limit_valves(self, x: Tuple[float, ...], dt: float) -> Tuple[float, ...]:
        """x with the implicit part of every valve-driven chamber's relief and anti-cavitation
        valves over dt applied (docs/model.md, "Integration (stiffness and substeps)")."""
        y = list(x)
        for j in JOINTS:
            if self.valve[j]:
                y[HYD + 2 * j], y[HYD + 1 + 2 * j] = self.drives[j].limit_valves(  # type: ignore
                    self.limit_coef[j], dt, x[HYD + 2 * j], x[HYD + 1 + 2 * j])
        return tuple(y)

    def substeps(self, x: Sequence[float], h: float) -> int:
        """n = max(1, ceil(h Lambda / 2.5)): Lambda from the chamber volumes at the step's start
        (hydraulics) and the extension's friction (spec "Four joints"), the larger."""
        lam = 0.0
        for j in JOINTS:
            if self.valve[j]:
                stroke = self.stroke(j, x[j])
                self.limit_coef[j] = self.drives[j].limit_coefficients(stroke)  # type: ignore
                lam = max(lam, self.drives[j].stiffness(stroke))  # type: ignore
        if not self.held[EXTENSION]:
            lam = max(lam, self.extension_friction_rate(x))
        return max(1, int(math.ceil(h * lam / SUBSTEP_STABILITY)))

    def rk4(self, t: float, x: Sequence[float], h: float, locked: Tuple[bool, ...]) -> Tuple[float, ...]:
        """One classical RK4 step of size h on (q, qd) (and the pressures, if any)."""
        if self.hydraulic:
            return self.rk4_hydraulic(t, x, h, locked)
        half = 0.5 * h
        k1 = self.acceleration(t, x, locked)
        x2 = tuple(x[j] + half * x[4 + j] for j in JOINTS) + tuple(x[4 + j] + half * k1[j] for j in JOINTS)
        k2 = self.acceleration(t + half, x2, locked)
        x3 = tuple(x[j] + half * x2[4 + j] for j in JOINTS) + tuple(x[4 + j] + half * k2[j] for j in JOINTS)
        k3 = self.acceleration(t + half, x3, locked)
        x4 = tuple(x[j] + h * x3[4 + j] for j in JOINTS) + tuple(x[4 + j] + h * k3[j] for j in JOINTS)
        k4 = self.acceleration(t + h, x4, locked)
        sixth = h / 6.0
        return (tuple(x[j] + sixth * (x[4 + j] + 2.0 * x2[4 + j] + 2.0 * x3[4 + j] + x4[4 + j])
                      for j in JOINTS)
                + tuple(x[4 + j] + sixth * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]) for j in JOINTS))

    def plastic_impact(self, x: State8, joint: int, side: int) -> State8:
        """Put the joint on its limit and stop it; the impulse acts on this joint only: over the
        free joints F, qd_F <- qd_F - Minv e_i (qd_i / Minv_ii) (Minv the inverse of M over F)."""
        q = list(x[:4])
        w = list(x[4:8])
        lower, upper = self.model.angle_limits[joint]
        q[joint] = lower if side < 0 else upper
        free = [j for j in JOINTS if j == joint or (not self.held[j] and self.stop[j] == 0)]
        if all(j in (LIFT, TILT) for j in free):
            # the planar model's impact (its closed-form M^-1, the C core's arithmetic)
            other = 1 - joint
            if other in free:
                # at the current extension (a stopped extension need not be the model's)
                (m00, m01), (m10, m11) = self.model._mass_matrix(
                    self.model._configuration((q[0], q[1]), q[3]))
                det = m00 * m11 - m01 * m10
                minv = ((m11 / det, -m01 / det), (-m10 / det, m00 / det))
                scale = w[joint] / minv[joint][joint]
                w[0] -= minv[0][joint] * scale
                w[1] -= minv[1][joint] * scale
            w[joint] = 0.0
            self.stop[joint] = side
            return tuple(q) + tuple(w) + tuple(x[8:])
        conf = self.model._configuration((q[0], q[1]), q[3])
        mass = self.model._mass_matrix4(conf, free)
        i = free.index(joint)
        unit = [1.0 if k == i else 0.0 for k in range(len(free))]
        col = _solve(mass, unit)                  # Minv e_i
        scale = w[joint] / col[i]
        for k, j in enumerate(free):
            w[j] -= col[k] * scale
        w[joint] = 0.0
        self.stop[joint] = side
        return tuple(q) + tuple(w) + tuple(x[8:])

    def stop_at_start(self, x: State8, strokes: Sequence[float], rates: Sequence[float]) -> State8:
        """t = 0 rule: a free joint at a stroke limit whose stroke rate does not point into the
        range starts STOPPED there (with a plastic impact if it was moving)."""
        model = self.model
        for j in JOINTS:
            if self.held[j]:
                continue
            if j in (LIFT, TILT):
                lo, hi = model.stroke_min[j], model.stroke_max[j]
            else:
                lo, hi = model.angle_limits[j]
            if strokes[j] <= lo and rates[j] <= 0.0:
                at_min = True
            elif strokes[j] >= hi and rates[j] >= 0.0:
                at_min = False
            else:
                continue
            # the angle side of that stroke limit (from the sign of ds/dtheta)
            flag = -1 if at_min else +1
            side = -1 if model.stop_flag[j][-1] == flag else +1
            x = self.plastic_impact(x, j, side)
            self.events.append((0.0, j, side))
        return x

    def extension_friction_rate(self, x: State8) -> float:
        """lambda_e = G_f (M^-1)_ee, 1/s, over the joints that are not held: how fast the
        extension's friction acts near rest (spec "Four joints"; the light extension boom makes it
        the stiffest term of the mechanics). Coupled to free booms, (M^-1)_ee is up to ~4 / m3."""
        free = [j for j in JOINTS if not self.held[j]]
        mass = self.model._mass_matrix4(self._conf(x), free)
        i = free.index(EXTENSION)
        col = _solve(mass, [1.0 if k == i else 0.0 for k in range(len(free))])
        # (M^-1)_ee taken at most 4 / m_ext: the bound on the work of a call (spec)
        return self.model.friction_slope(EXTENSION) * min(col[i], 4.0 / self.model._m_ext)

    def release(self, t: float, x: State8) -> None:
        """Let go of the STOPPED joints that the release rule frees at (t, x)."""
        for j in self.released(t, x):
            self.stop[j] = 0

    def released(self, t: float, x: State8) -> Tuple[int, ...]:
        """The STOPPED joints that leave their stops at (t, x) (docs/model.md, "Release").

        The unilateral stops form a small complementarity problem. The candidate release sets
        are the subsets of STOPPED joints in the order of their bitmask (lift 1, tilt 2, slew 4,
        extension 8; for two joints: none, lift, tilt, both); the first is taken in which every
        released joint accelerates into its range and every joint left on its stop is pressed
        onto it (its reaction M qdd - (tau - h) points into the range). Changes nothing, so
        that the release search inside a step can ask it at trial times."""
        if not any(self.stop):
            return ()
        key = (t, x, tuple(self.stop))
        last = self._last_release
        if last is not None and last[0] == key:
            return last[1]
        released = self._release_rule(t, x)
        self._last_release = (key, released)
        return released

    def _release_rule(self, t: float, x: State8) -> Tuple[int, ...]:
        """The complementarity rule itself, for released()."""
        m = self.model
        conf = self._conf(x)
        qd = x[4:8]
        planar = self.held[SLEW] and self.held[EXTENSION]   # the planar model's arithmetic
        if planar:
            h = m._inverse_dynamics(conf, qd[:2], (0.0, 0.0), m.gravity) + (0.0, 0.0)
        else:
            h = m._id4(conf, qd, (0.0, 0.0, 0.0, 0.0), m.gravity)
        tau = self.torques(t, conf, qd, self.held, x)
        net = tuple(tau[j] - h[j] for j in JOINTS)
        mass: Optional[List[List[float]]] = None   # only a candidate that moves a joint needs M
        stopped = [self.stop[j] != 0 for j in JOINTS]
        for mask in range(16):
            released = tuple(j for j in JOINTS if mask & (1 << j))
            if any(not stopped[j] for j in released):
                continue
            locked = tuple(self.held[j] or (stopped[j] and j not in released) for j in JOINTS)
            if planar:
                alpha = m._forward_dynamics(conf, qd[:2], tau[:2], locked[:2]) + (0.0, 0.0)
            else:
                alpha = m._forward4(conf, qd, tau, locked)
            consistent = True
            for j in JOINTS:
                if not stopped[j]:
                    continue
                inward = float(-self.stop[j])  # the lower stop (-1) is left with alpha > 0
                if j in released:
                    consistent = consistent and inward * alpha[j] > 0.0
                else:
                    if not any(alpha):
                        reaction = -net[j]
                    else:
                        if mass is None:
                            mass = ([list(row) for row in m._mass_matrix(conf)] if planar
                                    else m._mass_matrix4(conf, JOINTS))
                        reaction = sum(mass[j][k] * alpha[k] for k in range(len(mass))) - net[j]
                    consistent = consistent and inward * reaction >= 0.0
            if consistent:
                return released
        return ()

    @staticmethod
    def crossing_time(th0: float, w0: float, th1: float, w1: float, h: float,
                      limit: float, below: bool) -> float:
        """Time in (0, h] at which the cubic Hermite interpolant of theta on the step reaches
        the limit: 60 bisections, lo inside, hi outside, returns hi."""
        lo = 0.0
        hi = h
        for _ in range(EVENT_BISECTIONS):
            mid = 0.5 * (lo + hi)
            s = mid / h
            s2 = s * s
            s3 = s2 * s
            theta = ((2.0 * s3 - 3.0 * s2 + 1.0) * th0 + (s3 - 2.0 * s2 + s) * h * w0
                     + (-2.0 * s3 + 3.0 * s2) * th1 + (s3 - s2) * h * w1)
            outside = theta < limit if below else theta > limit
            if outside:
                hi = mid
            else:
                lo = mid
        return hi

    def step(self, t: float, x: State8, h: float) -> State8:
        """One step of size h, cut into pieces at the impacts and releases located inside it
        (at most MAX_PIECES; the last takes the rest of the step whatever happens in it)."""
        t_cur = t
        remaining = h
        for piece in range(1, MAX_PIECES + 1):
            locked = self.locked()
            x1 = self.rk4(t_cur, x, remaining, locked)
            if piece == MAX_PIECES:
                return self.impacts(t_cur + remaining, x1, touching=False)
            tau = self.impact_time(x, x1, remaining, locked)
            if tau is not None:
                x = self.impacts(t_cur + tau, self.rk4(t_cur, x, tau, locked), touching=True)
            elif any(self.stop) and self.released(t_cur + remaining, x1):
                tau, x = self.release_time(t_cur, x, remaining, x1, locked)
                self.release(t_cur + tau, x)
            else:
                return x1
            t_cur = t_cur + tau
            remaining = remaining - tau
            if not remaining > 0.0:
                return x
        raise AssertionError("unreachable: the last piece returns")

    def impact_time(self, x: State8, x1: State8, h: float, locked: Tuple[bool, ...]
                    ) -> Optional[float]:
        """Size of the piece up to the first impact in the RK4 step x -> x1 of size h, or None
        if no free joint ends strictly outside its limits."""
        tau = math.inf
        for j in JOINTS:
            if locked[j]:
                continue
            lower, upper = self.model.angle_limits[j]
            if x1[j] < lower:
                tau = min(tau, self.crossing_time(x[j], x[4 + j], x1[j], x1[4 + j], h, lower, True))
            elif x1[j] > upper:
                tau = min(tau, self.crossing_time(x[j], x[4 + j], x1[j], x1[4 + j], h, upper, False))
        return None if tau == math.inf else tau

    def impacts(self, t: float, x: State8, touching: bool) -> State8:
        """In joint order, every free joint beyond a limit (or at it, if touching) is put on it
        with a plastic impact. After a located impact the joint is at the limit to within the
        bisection, so it counts as touching; the last piece of a step takes only those beyond."""
        for j in JOINTS:
            if self.held[j] or self.stop[j] != 0:
                continue
            lower, upper = self.model.angle_limits[j]
            if x[j] < lower or (touching and x[j] == lower):
                side = -1
            elif x[j] > upper or (touching and x[j] == upper):
                side = +1
            else:
                continue
            x = self.plastic_impact(x, j, side)
            self.events.append((t, j, side))
        return x

    def release_time(self, t: float, x: State8, h: float, x1: State8,
                     locked: Tuple[bool, ...]) -> Tuple[float, State8]:
        """The piece size (and the state it ends in) at which a stopped joint is released,
        given that the release rule frees something at the end of the RK4 step x -> x1 of size
        h: RELEASE_BISECTIONS bisections keeping lo (releases nothing) and hi (releases).

        Without this a joint would leave its stop only at the start of the next step: a delay
        of up to dt, and a tip error of first order in dt."""
        lo = 0.0
        hi = h
        x_hi = x1
        for _ in range(RELEASE_BISECTIONS):
            mid = 0.5 * (lo + hi)
            x_mid = self.rk4(t, x, mid, locked)
            if self.released(t + mid, x_mid):
                hi = mid
                x_hi = x_mid
            else:
                lo = mid
        return hi, x_hi


class _EquivalentCylinder(NamedTuple):
    """What a valve needs of the slew drive or the extension cylinder (spec "Four joints",
    "Actuators"): the areas through bore and rod (rod 0: A_b = A_a), the stroke range, the circuit."""

    bore: float
    rod: float
    stroke_min: float
    stroke_max: float
    hydraulics: Any


def equivalent_cylinder(crane: Any, joint: int) -> _EquivalentCylinder:
    """The slew drive (the rack: A_a = A_b, stroke r_p (psi - slew_min)) or the extension cylinder
    (stroke e - extension_min) as a cylinder, for its valve."""
    if joint == SLEW:
        sd = crane.slew_drive
        travel = float(sd.pinion_radius) * (float(sd.slew_max) - float(sd.slew_min))
        return _EquivalentCylinder(float(sd.bore), 0.0, 0.0, travel, sd.hydraulics)
    ec, g = crane.extension_cylinder, crane.geometry
    return _EquivalentCylinder(float(ec.bore), float(ec.rod), 0.0,
                               float(g.extension_max) - float(g.extension_min), ec.hydraulics)


def _optional_drive(crane: Any, inputs: Any, joint: int) -> Any:
    """The slew or extension drive: left out (older Inputs) or Hold means held."""
    name = "slew" if joint == SLEW else "extension"
    drive = getattr(inputs, name, None)
    if drive is None or getattr(drive, "held", False):
        return None
    actuator = "slew_drive" if joint == SLEW else "extension_cylinder"
    if getattr(crane, actuator, None) is None:
        raise ValueError(f"Inputs.{name}: the crane has no {actuator} to drive")
    if hasattr(drive, "u"):
        cyl = equivalent_cylinder(crane, joint)
        if cyl.hydraulics is None:
            raise ValueError(f"Inputs.{name}: a valve drive needs {actuator}.hydraulics in the crane file")
        return _ValveDrive(drive, cyl)
    return _PressureDrive(drive)


def _next_knot(drives: Sequence[Any], t: float, t_end: float, dt: float) -> float:
    """The earliest sample time of a sampled drive inside (t, t_end), more than dt/1000 from
    both ends (docs/model.md, "Integration and samples"); t_end if there is none."""
    lo, hi = t + 1e-3 * dt, t_end - 1e-3 * dt
    knot = t_end
    for drive in drives:
        times = getattr(drive, "times", None)
        if not times:
            continue
        i = bisect_right(times, lo)
        if i < len(times) and times[i] < hi:
            knot = min(knot, times[i])
    return knot


def _run(crane: Any, state: Any, inputs: Any, horizon: float, dt: float
         ) -> Tuple[dict, List[Tuple[float, int, int]]]:
    """simulate() plus the list of impacts (time, joint, angle side), for diagnostics and tests."""
    horizon = float(horizon)
    dt = float(dt)
    model = TwinModel(crane, state.extension)
    drives = (_drive(inputs.lift, crane.lift_cylinder), _drive(inputs.tilt, crane.tilt_cylinder),
              _optional_drive(crane, inputs, SLEW), _optional_drive(crane, inputs, EXTENSION))
    pred = _Prediction(model, drives)

    slew0 = float(state.slew)
    ext0 = float(state.extension)
    # the slew and the extension in their own terms (the coordinate is the "stroke")
    strokes0 = (float(state.lift_stroke), float(state.tilt_stroke), slew0, ext0)
    rates0 = (float(state.lift_stroke_rate), float(state.tilt_stroke_rate),
              float(getattr(state, "slew_rate", 0.0)), float(getattr(state, "extension_rate", 0.0)))
    q0 = [0.0, 0.0, slew0, ext0]
    qd0 = [0.0, 0.0, 0.0, 0.0]
    for j in (LIFT, TILT):
        q0[j], ratio = model.joint_angle(j, strokes0[j])
        qd0[j] = 0.0 if pred.held[j] else rates0[j] / ratio
    for j in (SLEW, EXTENSION):
        qd0[j] = 0.0 if pred.held[j] else rates0[j]
    x: State8 = tuple(q0) + tuple(qd0)
    if pred.hydraulic:
        hyd = [0.0] * 12
        for j, name in enumerate(JOINT_NAMES):
            if pred.valve[j]:
                hyd[2 * j] = float(getattr(state, f"{name}_p_a"))
                hyd[2 * j + 1] = float(getattr(state, f"{name}_p_b"))
                hyd[SPOOL - HYD + j] = float(getattr(state, f"{name}_spool", 0.0))
        x = x + tuple(hyd)
    x = pred.stop_at_start(x, strokes0, rates0)

    n = int(math.ceil(horizon / dt - 1e-9))
    # bad input: the work counts against MAX_STEPS as in the C core: with valves every step takes
    # up to the worst-case substeps (docs/model.md "Hydraulics": at the stroke ends, where the
    # chambers are smallest; the last step up to 1.25 dt), and every knot of a sampled drive
    # inside the horizon cuts a step once more ("Integration and samples"), which costs at most one
    # substep more: a step's pieces sum to its length, ceil(a) + ceil(b) <= ceil(a + b) + 1
    from ._checks import MAX_STEPS

    knots = sum(1 for drive in pred.drives for tk in (getattr(drive, "times", None) or ())
                if 0.0 < tk < horizon)
    worst = 1
    if pred.hydraulic:
        lam = max(drive.stiffness(s) for drive, valve in zip(pred.drives, pred.valve) if valve
                  for s in (drive.stroke_min, drive.stroke_max))
        worst = max(1, int(math.ceil(1.25 * dt * lam / SUBSTEP_STABILITY)))
    if n * worst + knots > MAX_STEPS:
        raise ValueError(f"horizon / dt asks for more than {MAX_STEPS} steps with the cuts at the "
                         f"drives' samples and the valve-driven cylinders' substeps ({n} steps x "
                         f"up to {worst} substeps + {knots} cuts): raise dt, shorten the "
                         "horizon or send fewer samples")
    t_out = np.empty(n + 1)
    strokes = np.empty((n + 1, 2))
    theta = np.empty((n + 1, 2))
    omega = np.empty((n + 1, 2))
    tip = np.empty((n + 1, 3))
    stop = np.zeros((n + 1, 4), dtype=np.int64)
    coords = np.empty((n + 1, 2))            # (slew, extension)
    rates = np.empty((n + 1, 2))             # (slew rate, extension rate)
    p_a = np.zeros((n + 1, 4))
    p_b = np.zeros((n + 1, 4))
    flow_a = np.zeros((n + 1, 4))
    flow_b = np.zeros((n + 1, 4))
    spool = np.zeros((n + 1, 4))

    def record(i: int, t: float, x: State8) -> None:
        t_out[i] = t
        for j in (LIFT, TILT):
            if pred.held[j]:
                strokes[i, j] = strokes0[j]
            elif pred.stop[j] != 0:
                strokes[i, j] = model.stroke_at_stop[j][pred.stop[j]]
            else:
                # the stroke -> angle -> stroke round trip can land a few 1e-16 m outside
                cyl = cylinders[j]
                strokes[i, j] = min(max(model.joint_stroke(j, x[j]), cyl.stroke_min), cyl.stroke_max)
            stop[i, j] = model.stop_flag[j][pred.stop[j]] if pred.stop[j] != 0 else 0
        for k, j in enumerate((SLEW, EXTENSION)):
            lower, upper = model.angle_limits[j]
            if pred.held[j]:
                coords[i, k] = strokes0[j]
            elif pred.stop[j] != 0:
                coords[i, k] = lower if pred.stop[j] < 0 else upper
            else:
                coords[i, k] = x[j]
            rates[i, k] = x[4 + j]
            stop[i, j] = model.stop_flag[j][pred.stop[j]] if pred.stop[j] != 0 else 0
        theta[i] = (x[0], x[1])
        omega[i] = (x[4], x[5])
        tip[i] = model.tip((x[0], x[1]), coords[i, 0], coords[i, 1])
        for j in JOINTS:
            drive = pred.drives[j]
            if drive is None:
                continue
            if pred.valve[j]:
                y = x[SPOOL + j] if drive.tau > 0.0 else drive.lever(t)
                p_a[i, j], p_b[i, j] = x[HYD + 2 * j], x[HYD + 1 + 2 * j]
                flow_a[i, j], flow_b[i, j] = drive.flows(y, x[HYD + 2 * j], x[HYD + 1 + 2 * j])
                spool[i, j] = y
            else:
                p_a[i, j], p_b[i, j] = drive.pressures(t)

    cylinders = (crane.lift_cylinder, crane.tilt_cylinder)
    record(0, 0.0, x)
    for k in range(n):
        last = k == n - 1
        t_end = horizon if last else (k + 1) * dt
        t = k * dt
        # docs/model.md "Integration and samples": the step is cut at the sampled drives' knots
        # inside it, each piece a step of its own; "Hydraulics" and "Four joints" (the extension's
        # friction): a piece is n equal substeps, each a full step of the scheme, the last ending
        # at the piece's end time
        while True:
            t_q = _next_knot(pred.drives, t, t_end, dt)
            h = t_q - t
            n_sub = pred.substeps(x, h) if pred.hydraulic or not pred.held[EXTENSION] else 1
            if n_sub == 1:
                pred.release(t, x)
                x = pred.step(t, x, h)
            else:
                sub = h / n_sub
                for i in range(n_sub):
                    t_sub = t + i * sub
                    pred.release(t_sub, x)
                    x = pred.step(t_sub, x, t_q - t_sub if i == n_sub - 1 else sub)
            t = t_q
            if t >= t_end:
                break
        if not _physical(x):
            raise ValueError(f"the prediction diverged at t = {t:g} s (the state is no longer finite, "
                             "or a spool or chamber pressure left its range): check the crane's "
                             "parameters for absurd values")
        record(k + 1, horizon if last else (k + 1) * dt, x)

    out = {"t": t_out, "strokes": strokes, "theta": theta, "omega": omega,
           "slew": coords[:, 0].copy(), "extension": coords[:, 1].copy(),
           "slew_rate": rates[:, 0].copy(), "extension_rate": rates[:, 1].copy(), "tip": tip,
           "stop": stop, "p_a": p_a, "p_b": p_b, "flow_a": flow_a, "flow_b": flow_b, "spool": spool}
    return out, pred.events


def _physical(x: Sequence[float]) -> bool:
    """Finite, and (with valves) every chamber pressure within +-PRESSURE_MAX and every spool in
    [-1, 1]: an integration gone unstable shows there first (docs/model.md, "Bad input")."""
    from ._checks import PRESSURE_MAX

    if not all(math.isfinite(v) for v in x):
        return False
    if len(x) > HYD:
        return all(-PRESSURE_MAX <= v <= PRESSURE_MAX for v in x[HYD:SPOOL]) and \
            all(-1.0 <= v <= 1.0 for v in x[SPOOL:])
    return True


def simulate(crane: Any, state: Any, inputs: Any, horizon: float, dt: float) -> dict:
    """Predict the crane's four joints over [0, horizon] with RK4 steps dt and end stops, per
    docs/model.md ("Four joints"; a left-out slew or extension drive is held).

    Returns numpy arrays (types.ARRAYS), N = n + 1 samples: ``t`` (N,), ``strokes``, ``theta``,
    ``omega`` (N, 2) [lift, tilt]; ``slew``, ``extension``, ``slew_rate``, ``extension_rate``
    (N,); ``tip`` (N, 3, world); ``stop`` (N, 4) [lift, tilt, slew, extension] in actuator terms
    (-1 stopped at stroke_min / the range's start, +1 at stroke_max / its end, 0 otherwise; for
    the tilt, stroke_max is the lower angle limit); ``p_a``, ``p_b``, ``flow_a``, ``flow_b``,
    ``spool`` (N, 4). Inputs are assumed validated by the API layer.
    """
    return _run(crane, state, inputs, horizon, dt)[0]


def stroke_transmission(crane: Any, joint: int, stroke: float, extension: float) -> float:
    """ds/dtheta of a boom cylinder (0 lift, 1 tilt) at a stroke and extension: the factor that
    turns a sample's joint rate back into the stroke rate a State holds."""
    return TwinModel(crane, extension).joint_angle(joint, stroke)[1]


def points(crane: Any, extension: Any, slew: Any, theta_array: Any) -> np.ndarray:
    """World coordinates (N, 11, 3) of the POINT_NAMES points for each row (theta0, theta1), at
    the extension (m) and slew (rad) of that row (each a scalar or one value per row)."""
    thetas = np.asarray(theta_array, dtype=float).reshape(-1, 2)
    n = thetas.shape[0]
    exts = np.broadcast_to(np.asarray(extension, dtype=float), (n,)).tolist()
    slews = np.broadcast_to(np.asarray(slew, dtype=float), (n,)).tolist()
    model = TwinModel(crane, exts[0] if n else 0.0)
    out = np.empty((n, len(POINT_NAMES), 3))
    for i, (th0, th1) in enumerate(thetas.tolist()):
        out[i] = model.points((th0, th1), slews[i], exts[i])
    return out
