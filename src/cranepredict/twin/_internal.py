"""What every part of the twin shares (the C core's crane_internal.h): the joint indices, the
layout of the integrated state, plane-vector helpers, a small linear solve and the sampled
drives' interpolation."""

from __future__ import annotations

import math
from bisect import bisect_right
from typing import Any, List, Optional, Sequence, Tuple

LIFT = 0
TILT = 1
SLEW = 2
EXTENSION = 3

JOINTS = (LIFT, TILT, SLEW, EXTENSION)
#: The joints' names in State's fields (lift_p_a, slew_p_a, ...).
JOINT_NAMES = ("lift", "tilt", "slew", "extension")

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
State8 = Tuple[float, ...]   # (theta0, theta1, psi, e, omega0, omega1, omega_s, v_e)


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
