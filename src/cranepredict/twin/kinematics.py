"""Kinematics of the twin (docs/model.md, "Lift kinematics", "Tilt kinematics", "Frames"; the C
core's kinematics.c): the lift triangle, the tilt four-bar with its side links, the four-bar's
validity, and the world positions of the crane's points."""

from __future__ import annotations

import math
from typing import List, NamedTuple, Optional, Sequence, Tuple

from ._internal import (LIFT, TILT, Matrix4, Pair, Vec, _cross, _dot, _norm, _perp, _rotate,
                        _sub)

_HALF_PI = 0.5 * math.pi
_TWO_PI = 2.0 * math.pi


def _circle(c0: Vec, r0: float, c1: Vec, r1: float, sign: float, clamp: bool = False) -> Vec:
    """Intersection of the circle about c0 (radius r0) and about c1 (radius r1).

    sign = -1 picks the point to the right of the directed line c0 -> c1, +1 the one to the left.
    A mechanism that cannot close raises ValueError instead of silently producing NaN; with clamp
    (an integration stage beyond the tilt's range, spec "circle") h2 is clamped to 0 instead.
    """
    dx = c1[0] - c0[0]
    dy = c1[1] - c0[1]
    d = math.sqrt(dx * dx + dy * dy)
    if not d > 0.0:
        if clamp:
            return c0
        raise ValueError("four-bar does not close: coincident circle centres")
    ux = dx / d
    uy = dy / d
    a = (r0 * r0 - r1 * r1 + d * d) / (2.0 * d)
    h2 = r0 * r0 - a * a
    if clamp and not h2 > 0.0:
        h2 = 0.0
    elif not h2 > 0.0:
        raise ValueError(
            f"four-bar does not close (circles about ({c0[0]:.6g}, {c0[1]:.6g}) r={r0:.6g} and "
            f"({c1[0]:.6g}, {c1[1]:.6g}) r={r1:.6g} do not intersect)")
    h = sign * math.sqrt(h2)
    # p = c0 + a u + sign sqrt(h2) perp(u), perp(u) = (-uy, ux)
    return (c0[0] + a * ux - h * uy, c0[1] + a * uy + h * ux)


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


class Kinematics:
    """TwinModel's kinematics (the constants are derived in TwinModel.__init__)."""

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
        q = _circle(self.link1_pivot, self.tilt_l1, a, self.tilt_l2, self.tilt_branch, clamp=True)
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
        return self._link_pose(theta).stroke

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
