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
#: The integrated state: State8, with valves followed by the chamber pressures and the spools
#: (HYD, SPOOL).
State = Tuple[float, ...]


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


def _rot(c: float, s: float, v: Vec) -> Vec:
    """R v, R = [[c, -s], [s, c]]: a rotation by the angle of cosine c and sine s."""
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _rotate(angle: float, v: Vec) -> Vec:
    """R(angle) v."""
    return _rot(math.cos(angle), math.sin(angle), v)


def _norm(v: Vec) -> float:
    return math.sqrt(v[0] * v[0] + v[1] * v[1])



def _lu(a: Sequence[Sequence[float]]) -> Tuple[List[List[float]], List[int]]:
    """The LU factors of a square matrix, Gaussian elimination with partial pivoting in Python's
    floats (the same bits on every machine, which a BLAS does not promise): (rows, order), the
    rows holding U on and above the diagonal and the multipliers below it, order the rows of a
    they came from. A zero pivot (a singular matrix) raises ZeroDivisionError."""
    n = len(a)
    m = [[float(v) for v in row] for row in a]
    order = list(range(n))
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        order[c], order[p] = order[p], order[c]
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            m[r][c] = f
            if f != 0.0:
                row, pivot = m[r], m[c]
                for k in range(c + 1, n):
                    row[k] -= f * pivot[k]
    return m, order


def _lu_solve(factors: Tuple[List[List[float]], List[int]], b: Sequence[float]) -> List[float]:
    """x with a x = b, from a's factors (_lu)."""
    m, order = factors
    n = len(order)
    y = [float(b[i]) for i in order]
    for c in range(n):
        yc = y[c]
        for r in range(c + 1, n):
            f = m[r][c]
            if f != 0.0:
                y[r] -= f * yc
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        row = m[r]
        x[r] = (y[r] - sum(row[k] * x[k] for k in range(r + 1, n))) / row[r]
    return x


def _solve(a: Sequence[Sequence[float]], b: Sequence[float]) -> List[float]:
    """x with a x = b (Gaussian elimination with partial pivoting)."""
    return _lu_solve(_lu(a), b)


def _inverse_column(a: List[List[float]], i: int) -> List[float]:
    """Column i of a^-1: x with a x = e_i."""
    return _solve(a, [1.0 if k == i else 0.0 for k in range(len(a))])


def _inverse2(m: Matrix2) -> Matrix2:
    """The inverse of a 2x2 matrix, in closed form."""
    (m00, m01), (m10, m11) = m
    det = m00 * m11 - m01 * m10
    return ((m11 / det, -m01 / det), (-m10 / det, m00 / det))


# --------------------------------------------------------------------------------------------
# Drives
# --------------------------------------------------------------------------------------------

def _signal(drive: Any, *names: str) -> Tuple[Optional[List[float]], List[Any]]:
    """(times, values of each field in names) of a drive: times None and the values floats for a
    constant drive, lists for a sampled one (``drive.t``)."""
    times = getattr(drive, "t", None)
    if times is None:
        return None, [float(getattr(drive, name)) for name in names]
    return [float(x) for x in times], [[float(x) for x in getattr(drive, name)] for name in names]


def _segment(times: List[float], t: float) -> Tuple[int, float]:
    """(k, s): t lies at the fraction s of the way from times[k] to times[k + 1] (the first or
    last segment for a t outside the samples: no clamping, the validation keeps t inside)."""
    k = bisect_right(times, t) - 1
    k = min(max(k, 0), len(times) - 2)
    return k, (t - times[k]) / (times[k + 1] - times[k])


def _lerp(values: List[float], k: int, s: float) -> float:
    """values linearly interpolated at the fraction s of segment k."""
    return values[k] + s * (values[k + 1] - values[k])


class _PressureDrive:
    """Chamber pressures of one cylinder: constant, or samples interpolated linearly."""

    def __init__(self, drive: Any) -> None:
        self.times, (self.p_a, self.p_b) = _signal(drive, "p_a", "p_b")

    def pressures(self, t: float) -> Pair:
        if self.times is None:
            return self.p_a, self.p_b
        k, s = _segment(self.times, t)
        return _lerp(self.p_a, k, s), _lerp(self.p_b, k, s)
