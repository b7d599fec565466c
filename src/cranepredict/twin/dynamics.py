"""Dynamics of the twin (docs/model.md, "Dynamics", "Side links", "Four joints"; the C core's
dynamics.c): iterative Newton-Euler inverse dynamics, the mass matrix and forward dynamics, in the
planar shape (the slew and the extension at rest, the extension boom and the load lumped with the
outer boom) and the four-joint shape."""

from __future__ import annotations

import math
from typing import Any, List, NamedTuple, Optional, Sequence, Tuple

from ._internal import (EXTENSION, LIFT, SLEW, TILT, Matrix2, Pair, Quad, Tensor, Vec, _cross,
                        _dot, _inverse2, _rot, _solve, _sub, _tensor, _vec)


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


#: A rigid body in the plane: mass, centre of mass (in the frame it is given in), izz and the
#: in-plane inertia tensor entries (ixx, iyy, ixy) about the centre.
Body = Tuple[float, Vec, float, Tensor]


def _body(body: Any) -> Body:
    """A crane body (lift boom, side link, ...) as a Body in its own frame."""
    return float(body.mass), _vec(body.com), float(body.izz), _tensor(body)


def _point_mass(mass: float, at: Vec) -> Body:
    """A point mass (the load) as a Body."""
    return mass, at, 0.0, (0.0, 0.0, 0.0)


def _moved(body: Body, origin: Vec) -> Body:
    """body in a frame in which its own frame's origin is at origin (the frames parallel)."""
    m, c, izz, t = body
    return m, (origin[0] + c[0], origin[1] + c[1]), izz, t


def _lump(bodies: Sequence[Body]) -> Body:
    """Rigidly joined bodies as one body: the masses summed, the centre of mass, and izz and the
    tensor about that centre by parallel axes; every sum in the order the bodies are given."""
    m, (cx, cy), izz, (ixx, iyy, ixy) = bodies[0]
    sx, sy = m * cx, m * cy
    for mk, ck, _, _ in bodies[1:]:
        m += mk
        sx += mk * ck[0]
        sy += mk * ck[1]
    centre = (sx / m, sy / m)
    for k, (mk, ck, izz_k, (ixx_k, iyy_k, ixy_k)) in enumerate(bodies):
        if k > 0:
            izz += izz_k
            ixx += ixx_k
            iyy += iyy_k
            ixy += ixy_k
        d = _sub(ck, centre)
        izz += mk * _dot(d, d)
        ixx += mk * d[1] * d[1]
        iyy += mk * d[0] * d[0]
        ixy -= mk * d[0] * d[1]
    return m, centre, izz, (ixx, iyy, ixy)


class Dynamics:
    """TwinModel's dynamics (the constants are derived in TwinModel.__init__)."""

    def _configuration(self, theta: Sequence[float], extension: Optional[float] = None
                       ) -> _Configuration:
        """Everything ID needs about the configuration (theta, e), in the boom plane; the
        extension defaults to the model's."""
        th0, th1 = theta[0], theta[1]
        e = self.extension if extension is None else extension
        c0, s0 = math.cos(th0), math.sin(th0)          # R(theta0)
        th12 = th0 + th1
        c12, s12 = math.cos(th12), math.sin(th12)      # R(theta0 + theta1)
        pose = self._link_pose(th1)
        mount = self.extension_mount
        lumped = self._lumped_outer_body(e)
        return _Configuration(
            (self._lift_transmission(th0), pose.ratio), pose.stroke,
            _rot(c0, s0, self.tilt_pivot), _rot(c0, s0, self.c1), _rot(c12, s12, self.c2),
            _rot(c12, s12, (mount[0] + e + self.c3[0], mount[1] + self.c3[1])),
            (c12, s12), th0, th12,
            _rot(c0, s0, pose.arm_a), _rot(c0, s0, pose.arm_q), _rot(c0, s0, pose.link),
            pose.den1, pose.den2, pose.k1, pose.k2,
            _rot(c0, s0, pose.d1), _rot(c0, s0, pose.e1), _rot(c0, s0, pose.j1),
            _rot(c0, s0, pose.d2), _rot(c0, s0, pose.e2), _rot(c0, s0, pose.j2),
            th0 + pose.phi1, th0 + pose.phi2, (lumped[0], lumped[2]), _rot(c12, s12, lumped[1]))

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
        mount = self.extension_mount
        at = (mount[0] + e, mount[1])           # the extension boom frame's origin
        m2, c2, i2, _ = _lump((self.outer_boom, _moved(self.extension_boom, at),
                               _moved(self.load, at)))
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
        return _inverse2(self.mass_matrix(theta))

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

    def forward_dynamics4(self, q: Sequence[float], qd: Sequence[float], tau: Sequence[float],
                          locked: Sequence[bool]) -> Quad:
        """Joint accelerations of the four joints; a locked joint has qdd = 0."""
        return self._forward4(self._configuration((q[0], q[1]), q[3]), qd, tau, locked)
