"""An independent formulation of the crane's dynamics, for the tests only.

Lagrange's equations  tau = M(q) qdd + (dM/dt) qd - 1/2 d(qd' M qd)/dq + dV/dq  built from the
kinetic and potential energy of each body separately: the lift boom, the outer boom, the extension
boom, the load (point mass) and the two side links of the four-bar. The fast model lumps the outer
boom, extension boom and load into one body and carries the side links through velocity ratios
and virtual work; here every body is a function p(q) of the joint angles and nothing else:

* positions p(q) are computed from the geometry (the side links from the four-bar closure), with
  arithmetic that also works for complex q;
* Jacobians dp/dq by the complex step (exact to machine precision, no subtraction);
* dM/dq by a five-point central difference (about 1e-9 relative), dV/dq by the complex step.

It shares no code with the C core or the twin; it reads the crane's parameters only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, List, Tuple

import numpy as np

H = 1e-30      # complex step
H_FD = 1e-3    # five-point stencil for dM/dq


def _rot(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def _dir_rot(v):
    """The rotation taking the x axis to the direction of v (complex-safe, no atan2)."""
    n = np.sqrt(v[0] ** 2 + v[1] ** 2)
    return np.array([[v[0], -v[1]], [v[1], v[0]]]) / n


def _circle(c0, r0, c1, r1, sign):
    d = c1 - c0
    dist = np.sqrt(d[0] ** 2 + d[1] ** 2)
    a = (r0 ** 2 - r1 ** 2 + dist ** 2) / (2 * dist)
    u = d / dist
    return c0 + a * u + sign * np.sqrt(r0 ** 2 - a ** 2) * np.array([-u[1], u[0]])


@dataclass
class _Body:
    mass: float
    izz: float
    position: Callable      # q -> centre of mass in the boom plane
    spin: Callable          # real q -> d(body angle)/dq, shape (2,)


class Lagrange:
    def __init__(self, crane, extension: float = 0.0, side_links: bool = True) -> None:
        g = crane.geometry
        self.gravity = crane.gravity
        o1 = np.array(g.lift_pivot, float)
        o2 = np.array(g.tilt_pivot, float)
        p1 = np.array(g.link1_pivot, float)
        pin = np.array(g.link_pin, float)
        end2 = np.array(g.link2_end, float)
        attach = np.array(g.link2_attach, float)
        l1, l2 = np.hypot(*pin), np.hypot(*end2)
        ext_origin = np.array(g.extension_mount, float) + np.array([extension, 0.0])

        def lift_point(r):
            return lambda q: o1 + _rot(q[0]) @ r

        def outer_point(r):
            return lambda q: o1 + _rot(q[0]) @ (o2 + _rot(q[1]) @ r)

        def pins(q):   # Q and A in the lift boom frame
            a = o2 + _rot(q[1]) @ attach
            return _circle(p1, l1, a, l2, +1.0), a

        def link1_com(q):
            qq, _ = pins(q)
            local = p1 + _dir_rot(qq - p1) @ np.linalg.solve(_dir_rot(pin).real, np.asarray(crane.side_link1.com, float))
            return o1 + _rot(q[0]) @ local

        def link2_com(q):
            qq, a = pins(q)
            local = qq + _dir_rot(a - qq) @ np.linalg.solve(_dir_rot(end2).real, np.asarray(crane.side_link2.com, float))
            return o1 + _rot(q[0]) @ local

        def link_spin(which):
            def spin(q):
                # d(angle of the link's line)/dq2 = cross(v, dv/dq2) / |v|^2, dv by the complex step
                qc = np.array(q, dtype=complex)
                qc[1] += 1j * H
                qq, a = pins(qc)
                v = (qq - p1) if which == 1 else (a - qq)
                dv, v = np.imag(v) / H, np.real(v)
                return np.array([1.0, (v[0] * dv[1] - v[1] * dv[0]) / (v @ v)])
            return spin

        fixed1 = lambda q: np.array([1.0, 0.0])  # noqa: E731
        fixed2 = lambda q: np.array([1.0, 1.0])  # noqa: E731
        self.bodies: List[_Body] = [
            _Body(crane.lift_boom.mass, crane.lift_boom.izz, lift_point(np.array(crane.lift_boom.com, float)), fixed1),
            _Body(crane.outer_boom.mass, crane.outer_boom.izz, outer_point(np.array(crane.outer_boom.com, float)), fixed2),
            _Body(crane.extension_boom.mass, crane.extension_boom.izz,
                  outer_point(ext_origin + np.array(crane.extension_boom.com, float)), fixed2),
            _Body(crane.load_mass, 0.0, outer_point(ext_origin + np.array([g.tip_distance, 0.0])), fixed2),
        ]
        if side_links:
            self.bodies += [
                _Body(crane.side_link1.mass, crane.side_link1.izz, link1_com, link_spin(1)),
                _Body(crane.side_link2.mass, crane.side_link2.izz, link2_com, link_spin(2)),
            ]
        self._tip = outer_point(ext_origin + np.array([g.tip_distance, 0.0]))

    def _jacobian(self, b: _Body, q) -> np.ndarray:
        cols = []
        for k in range(2):
            qc = np.array(q, dtype=complex)
            qc[k] += 1j * H
            cols.append(np.imag(b.position(qc)) / H)
        return np.stack(cols, axis=1)

    def mass_matrix(self, q) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        m = np.zeros((2, 2))
        for b in self.bodies:
            j = self._jacobian(b, q)
            w = b.spin(q)
            m += b.mass * (j.T @ j) + b.izz * np.outer(w, w)
        return m

    def potential(self, q):
        return sum(b.mass * self.gravity * b.position(q)[1] for b in self.bodies)

    def energy(self, q, qd) -> float:
        qd = np.asarray(qd, dtype=float)
        return float(0.5 * qd @ self.mass_matrix(q) @ qd + np.real(self.potential(np.asarray(q, float))))

    def _dm(self, q, k) -> np.ndarray:
        e = np.zeros(2)
        e[k] = H_FD
        f = self.mass_matrix
        return (-f(q + 2 * e) + 8 * f(q + e) - 8 * f(q - e) + f(q - 2 * e)) / (12 * H_FD)

    def torques(self, q, qd, qdd) -> Tuple[float, float]:
        """tau = M qdd + dM/dt qd - 1/2 d(qd' M qd)/dq + dV/dq."""
        q, qd, qdd = (np.asarray(v, dtype=float) for v in (q, qd, qdd))
        m = self.mass_matrix(q)
        dm = [self._dm(q, k) for k in range(2)]
        mdot = dm[0] * qd[0] + dm[1] * qd[1]
        dT = np.array([0.5 * qd @ dm[k] @ qd for k in range(2)])
        dV = []
        for k in range(2):
            qc = np.array(q, dtype=complex)
            qc[k] += 1j * H
            dV.append(np.imag(self.potential(qc)) / H)
        tau = m @ qdd + mdot @ qd - dT + np.array(dV)
        return float(tau[0]), float(tau[1])

    def tip(self, q) -> np.ndarray:
        return np.real(self._tip(np.asarray(q, dtype=float)))
