"""An independent formulation of the crane's dynamics, for the tests only.

Lagrange's equations  tau = M(q) qdd + (dM/dt) qd - 1/2 d(qd' M qd)/dq + dV/dq  built from the
kinetic and potential energy of each body separately: the lift boom, the outer boom, the extension
boom and the load (point mass) - the fast model lumps the last three into one body, so this checks
the lumping too. Jacobians are geometric (a point of body b moves with perp(p - pivot) per joint
rate); derivatives of M and V with respect to q are taken by the complex step, which is exact to
machine precision (no subtraction), so the comparison can be made at 1e-9 relative.
It shares no code with the C core or the twin; it reads the crane's parameters only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Tuple

import numpy as np

H = 1e-30  # complex step


def _rot(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def _perp(v):
    return np.array([-v[1], v[0]])


@dataclass
class _PointMass:
    frame: int           # 1: lift boom frame (origin O1), 2: outer boom frame (origin O2)
    r: np.ndarray        # centre of mass in that frame
    mass: float
    izz: float


class Lagrange:
    def __init__(self, crane, extension: float = 0.0) -> None:
        g = crane.geometry
        self.gravity = crane.gravity
        self.o1 = np.array(g.lift_pivot, dtype=float)
        self.o2_local = np.array(g.tilt_pivot, dtype=float)
        mount = np.array(g.extension_mount, dtype=float)
        ext_origin = mount + np.array([extension, 0.0])
        self.bodies: List[_PointMass] = [
            _PointMass(1, np.array(crane.lift_boom.com, float), crane.lift_boom.mass, crane.lift_boom.izz),
            _PointMass(2, np.array(crane.outer_boom.com, float), crane.outer_boom.mass, crane.outer_boom.izz),
            _PointMass(2, ext_origin + np.array(crane.extension_boom.com, float),
                       crane.extension_boom.mass, crane.extension_boom.izz),
            _PointMass(2, ext_origin + np.array([g.tip_distance, 0.0]), crane.load_mass, 0.0),
        ]

    # positions in the boom plane, valid for complex q (complex step)
    def _position(self, b: _PointMass, q):
        r1 = _rot(q[0])
        if b.frame == 1:
            return self.o1 + r1 @ b.r
        return self.o1 + r1 @ (self.o2_local + _rot(q[1]) @ b.r)

    def _jacobian(self, b: _PointMass, q):
        p = self._position(b, q)
        jq1 = _perp(p - self.o1)
        if b.frame == 1:
            return np.stack([jq1, np.zeros(2, dtype=jq1.dtype)], axis=1), np.array([1.0, 0.0])
        o2 = self.o1 + _rot(q[0]) @ self.o2_local
        return np.stack([jq1, _perp(p - o2)], axis=1), np.array([1.0, 1.0])

    def mass_matrix(self, q):
        q = np.asarray(q)
        m = np.zeros((2, 2), dtype=q.dtype)
        for b in self.bodies:
            j, jw = self._jacobian(b, q)
            m = m + b.mass * (j.T @ j) + b.izz * np.outer(jw, jw)
        return m

    def potential(self, q):
        return sum(b.mass * self.gravity * self._position(b, q)[1] for b in self.bodies)

    def kinetic(self, q, qd):
        qd = np.asarray(qd, dtype=float)
        return 0.5 * qd @ self.mass_matrix(np.asarray(q, dtype=float)) @ qd

    def energy(self, q, qd) -> float:
        return float(self.kinetic(q, qd) + self.potential(np.asarray(q, dtype=float)))

    def _dq(self, f, q, k):
        qc = np.array(q, dtype=complex)
        qc[k] += 1j * H
        return np.imag(f(qc)) / H

    def torques(self, q, qd, qdd) -> Tuple[float, float]:
        """tau = M qdd + dM/dt qd - 1/2 d(qd' M qd)/dq + dV/dq."""
        q, qd, qdd = (np.asarray(v, dtype=float) for v in (q, qd, qdd))
        m = self.mass_matrix(q)
        dm = [self._dq(self.mass_matrix, q, k) for k in range(2)]
        mdot = dm[0] * qd[0] + dm[1] * qd[1]
        dT = np.array([0.5 * qd @ dm[k] @ qd for k in range(2)])
        dV = np.array([self._dq(self.potential, q, k) for k in range(2)])
        tau = m @ qdd + mdot @ qd - dT + dV
        return float(tau[0]), float(tau[1])

    def tip(self, q) -> np.ndarray:
        return np.real(self._position(self.bodies[3], np.asarray(q, dtype=float)))
