"""An independent formulation of the four-joint crane's dynamics (slew, lift, tilt, extension), for
the tests only: the oracle of docs/model.md, section "Four joints".

Every body is a rigid body in space: its centre of mass p(q) (world, Z up) and its rotation
R(q) (world from body) are functions of q = (theta0, theta1, psi, e) built from the geometry with
arithmetic that also works for complex q, and its inertia tensor J about the centre is the full
3x3 one of the crane file (in-plane entries ixx, iyy, ixy and izz). The kinetic energy is
``T = 1/2 qd' M(q) qd`` with

    M = sum_b  m_b Jv_b' Jv_b + Jw_b' (R_b J_b R_b') Jw_b,

Jv = dp/dq by the complex step, Jw the world angular velocity per joint rate from
``[w]x = (dR/dq_k) R'`` (dR/dq_k by the complex step), V = g sum m_b p_b.Z, and Lagrange's
equations  tau = M qdd + Mdot qd - 1/2 d(qd' M qd)/dq + dV/dq  with dM/dq by a five-point central
difference. Nothing here assumes what the fast model's derivation shows (the block structure of M,
the centrifugal and Coriolis terms): the tests check those claims against this.

Bodies: the pillar (turns with psi), the lift boom, the outer boom, the extension boom, the load (a
point mass at the tip) and the two side links of the four-bar. It shares no code with the C core,
the twin or tests/lagrange.py; it reads the crane's parameters only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, List

import numpy as np

H = 1e-30      # complex step
H_FD = 1e-3    # five-point stencil for dM/dq

LIFT, TILT, SLEW, EXTENSION = 0, 1, 2, 3

# the boom plane (x out, y up, z normal) into the world at psi = 0: (x, y, z) -> (x, -z, y)
_PLANE_TO_WORLD = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def _rot3(a):
    """Rotation by a about the boom plane's normal (z), as a 3x3 (complex-safe)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0 * c], [s, c, 0 * c], [0 * c, 0 * c, 1 + 0 * c]])


def _dir_rot3(v):
    """The rotation about z taking the x axis to the direction of the plane vector v (no atan2)."""
    n = np.sqrt(v[0] ** 2 + v[1] ** 2)
    c, s = v[0] / n, v[1] / n
    return np.array([[c, -s, 0 * c], [s, c, 0 * c], [0 * c, 0 * c, 1 + 0 * c]])


def _world(psi):
    """Boom plane -> world: Rot_Z(psi) Rot_X(+90 deg)."""
    c, s = np.cos(psi), np.sin(psi)
    rz = np.array([[c, -s, 0 * c], [s, c, 0 * c], [0 * c, 0 * c, 1 + 0 * c]])
    return rz @ _PLANE_TO_WORLD


def _p3(v):
    return np.array([v[0], v[1], 0.0 * v[0]])


def _circle(c0, r0, c1, r1, sign):
    d = c1 - c0
    dist = np.sqrt(d[0] ** 2 + d[1] ** 2)
    a = (r0 ** 2 - r1 ** 2 + dist ** 2) / (2 * dist)
    u = d / dist
    h = np.sqrt(r0 ** 2 - a ** 2)
    return c0 + a * u + sign * h * np.array([-u[1], u[0], 0.0 * u[0]])


def tensor(body, *, izz=None) -> np.ndarray:
    """A crane body's 3x3 inertia tensor about its centre in its own frame (the crane file's
    in-plane entries; left out: ixx = 0, iyy = izz, ixy = 0)."""
    zz = body.izz if izz is None else izz
    xx = 0.0 if body.ixx is None else body.ixx
    yy = zz if body.iyy is None else body.iyy
    xy = 0.0 if body.ixy is None else body.ixy
    return np.array([[xx, xy, 0.0], [xy, yy, 0.0], [0.0, 0.0, zz]])


@dataclass
class _Body:
    name: str
    mass: float
    inertia: np.ndarray            # 3x3 about the centre, body frame
    position: Callable             # q -> world centre of mass
    rotation: Callable             # q -> world-from-body rotation


class Lagrange4:
    """The four-joint crane: q = (theta0, theta1, psi, e), torques/forces in joint order."""

    def __init__(self, crane, side_links: bool = True, pillar: bool = True) -> None:
        g = crane.geometry
        self.gravity = crane.gravity
        o1 = _p3(np.array(g.lift_pivot, float))
        o2 = _p3(np.array(g.tilt_pivot, float))
        p1 = _p3(np.array(g.link1_pivot, float))
        pin = _p3(np.array(g.link_pin, float))
        end2 = _p3(np.array(g.link2_end, float))
        attach = _p3(np.array(g.link2_attach, float))
        mount = _p3(np.array(g.extension_mount, float))
        l1, l2 = np.hypot(pin[0], pin[1]), np.hypot(end2[0], end2[1])

        def lift_frame(q):      # (rotation, origin) of the lift boom frame in the boom plane
            return _rot3(q[0]), o1

        def outer_frame(q):
            r1, t1 = lift_frame(q)
            return r1 @ _rot3(q[1]), t1 + r1 @ o2

        def extension_frame(q):
            r2, t2 = outer_frame(q)
            return r2, t2 + r2 @ (mount + np.array([q[3], 0.0 * q[3], 0.0 * q[3]]))

        def pins(q):            # Q and A in the lift boom frame (four-bar closure)
            a = o2 + _rot3(q[1]) @ attach
            return _circle(p1, l1, a, l2, +1.0), a

        def link1_frame(q):
            qq, _ = pins(q)
            r1, t1 = lift_frame(q)
            return r1 @ _dir_rot3(qq - p1) @ np.linalg.inv(_dir_rot3(pin).real), t1 + r1 @ p1

        def link2_frame(q):
            qq, a = pins(q)
            r1, t1 = lift_frame(q)
            return r1 @ _dir_rot3(a - qq) @ np.linalg.inv(_dir_rot3(end2).real), t1 + r1 @ qq

        def pillar_frame(q):
            return _rot3(0.0 * q[0]), _p3(np.zeros(2))

        def body(name, mass, inertia, frame, local):
            local = _p3(np.asarray(local, float))

            def position(q):
                r, t = frame(q)
                return _world(q[2]) @ (t + r @ local)

            def rotation(q):
                r, _ = frame(q)
                return _world(q[2]) @ r
            return _Body(name, mass, inertia, position, rotation)

        self.bodies: List[_Body] = []
        if pillar and crane.pillar is not None:
            self.bodies.append(body("pillar", crane.pillar.mass, tensor(crane.pillar), pillar_frame,
                                    crane.pillar.com))
        self.bodies += [
            body("lift_boom", crane.lift_boom.mass, tensor(crane.lift_boom), lift_frame, crane.lift_boom.com),
            body("outer_boom", crane.outer_boom.mass, tensor(crane.outer_boom), outer_frame,
                 crane.outer_boom.com),
            body("extension_boom", crane.extension_boom.mass, tensor(crane.extension_boom),
                 extension_frame, crane.extension_boom.com),
            body("load", crane.load_mass, np.zeros((3, 3)), extension_frame, (g.tip_distance, 0.0)),
        ]
        if side_links:
            self.bodies += [
                body("side_link1", crane.side_link1.mass, tensor(crane.side_link1), link1_frame,
                     crane.side_link1.com),
                body("side_link2", crane.side_link2.mass, tensor(crane.side_link2), link2_frame,
                     crane.side_link2.com),
            ]
        tip = body("tip", 0.0, np.zeros((3, 3)), extension_frame, (g.tip_distance, 0.0))
        self._tip = tip.position

    # -- kinematics ---------------------------------------------------------------------------
    @staticmethod
    def _steps(f, q):
        """d f / d q_k for k = 0..3 by the complex step, and f(q)."""
        q = np.asarray(q, dtype=float)
        out = []
        for k in range(4):
            qc = q.astype(complex)
            qc[k] += 1j * H
            out.append(np.imag(f(qc)) / H)
        return out, np.real(f(q.astype(complex)))

    def jacobians(self, b: _Body, q):
        """(Jv 3x4, Jw 3x4, R 3x3) of a body at q."""
        dp, _ = self._steps(b.position, q)
        dr, r = self._steps(b.rotation, q)
        jw = []
        for d in dr:
            w = d @ r.T                       # skew-symmetric: [w]x
            jw.append(np.array([w[2, 1], w[0, 2], w[1, 0]]))
        return np.stack(dp, axis=1), np.stack(jw, axis=1), r

    def mass_matrix(self, q) -> np.ndarray:
        m = np.zeros((4, 4))
        for b in self.bodies:
            jv, jw, r = self.jacobians(b, q)
            m += b.mass * (jv.T @ jv) + jw.T @ (r @ b.inertia @ r.T) @ jw
        return m

    def potential(self, q):
        return sum(b.mass * self.gravity * b.position(q)[2] for b in self.bodies)

    def energy(self, q, qd) -> float:
        qd = np.asarray(qd, dtype=float)
        q = np.asarray(q, dtype=float)
        return float(0.5 * qd @ self.mass_matrix(q) @ qd + np.real(self.potential(q.astype(complex))))

    def kinetic(self, q, qd) -> float:
        qd = np.asarray(qd, dtype=float)
        return float(0.5 * qd @ self.mass_matrix(q) @ qd)

    def _dm(self, q, k) -> np.ndarray:
        e = np.zeros(4)
        e[k] = H_FD
        f = self.mass_matrix
        return (-f(q + 2 * e) + 8 * f(q + e) - 8 * f(q - e) + f(q - 2 * e)) / (12 * H_FD)

    def torques(self, q, qd, qdd, gravity: bool = True) -> np.ndarray:
        """tau = M qdd + dM/dt qd - 1/2 d(qd' M qd)/dq + dV/dq, joint order (lift, tilt, slew,
        extension): N m for the revolute joints, N for the extension."""
        q, qd, qdd = (np.asarray(v, dtype=float) for v in (q, qd, qdd))
        m = self.mass_matrix(q)
        dm = [self._dm(q, k) for k in range(4)]
        mdot = sum(dm[k] * qd[k] for k in range(4))
        dT = np.array([0.5 * qd @ dm[k] @ qd for k in range(4)])
        dV = np.zeros(4)
        if gravity:
            dv, _ = self._steps(self.potential, q)
            dV = np.array([float(x) for x in dv])
        return m @ qdd + mdot @ qd - dT + dV

    def tip(self, q) -> np.ndarray:
        return np.real(self._tip(np.asarray(q, dtype=float).astype(complex)))

    def body_position(self, name: str, q) -> np.ndarray:
        b = next(b for b in self.bodies if b.name == name)
        return np.real(b.position(np.asarray(q, dtype=float).astype(complex)))
