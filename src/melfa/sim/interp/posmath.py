"""Position arithmetic of a running program (melfa-basic-iv.md §7), in radians.

``P1*P2`` composes transforms in P1's tool frame, ``P1/P2`` undoes it, ``P1+P2`` and
``P1-P2`` work element by element in world coordinates. Rotations use the project's
A/B/C convention R = Rz(C)·Ry(B)·Rx(A) (rv6s.md §5, same as `melfa.kin`). Pure Python
on 3×3 tuples: a statement like ``MOV P1*P2`` must cost microseconds, not a numpy call.
"""

from __future__ import annotations

import math
from dataclasses import replace

from melfa.sim.interp.values import Joints, Position

Mat = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
Vec = tuple[float, float, float]


def rotation(a: float, b: float, c: float) -> Mat:
    """R = Rz(c)·Ry(b)·Rx(a), angles in radians."""
    ca, sa = math.cos(a), math.sin(a)
    cb, sb = math.cos(b), math.sin(b)
    cc, sc = math.cos(c), math.sin(c)
    return (
        (cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa),
        (sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa),
        (-sb, cb * sa, cb * ca),
    )


def angles(r: Mat) -> Vec:
    """A, B, C (radians) of a rotation matrix; at B = ±90° A is taken as 0."""
    sb = -r[2][0]
    cb = math.hypot(r[0][0], r[1][0])
    b = math.atan2(sb, cb)
    if cb > 1e-9:
        return (math.atan2(r[2][1], r[2][2]), b, math.atan2(r[1][0], r[0][0]))
    return (0.0, b, math.atan2(-r[0][1], r[1][1]))


def matmul(p: Mat, q: Mat) -> Mat:
    return tuple(  # type: ignore[return-value]
        tuple(p[i][0] * q[0][j] + p[i][1] * q[1][j] + p[i][2] * q[2][j] for j in range(3))
        for i in range(3)
    )


def transpose(r: Mat) -> Mat:
    return ((r[0][0], r[1][0], r[2][0]), (r[0][1], r[1][1], r[2][1]), (r[0][2], r[1][2], r[2][2]))


def apply(r: Mat, v: Vec) -> Vec:
    return (
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    )


def _from(r: Mat, t: Vec, like: Position, l1: float, l2: float) -> Position:
    a, b, c = angles(r)
    return replace(like, x=t[0], y=t[1], z=t[2], a=a, b=b, c=c, l1=l1, l2=l2)


def wrap(angle: float) -> float:
    """Angle into (-π, π], as the controller displays orientation."""
    w = math.remainder(angle, 2 * math.pi)
    return math.pi if w == -math.pi else w


def multiply(p1: Position, p2: Position) -> Position:
    """``P1 * P2``: P2 expressed in P1's tool frame; flags from P1 [S2f]."""
    r1 = rotation(p1.a, p1.b, p1.c)
    r2 = rotation(p2.a, p2.b, p2.c)
    d = apply(r1, (p2.x, p2.y, p2.z))
    t = (p1.x + d[0], p1.y + d[1], p1.z + d[2])
    return _from(matmul(r1, r2), t, p1, p1.l1 + p2.l1, p1.l2 + p2.l2)


def inverse(p: Position) -> Position:
    """``INV(P)``: the inverse transform, so that ``P * INV(P)`` is the identity."""
    rt = transpose(rotation(p.a, p.b, p.c))
    t = apply(rt, (p.x, p.y, p.z))
    return _from(rt, (-t[0], -t[1], -t[2]), p, -p.l1, -p.l2)


def divide(p1: Position, p2: Position) -> Position:
    """``P1 / P2`` = P1 · P2⁻¹, so ``(P1 * P2) / P2 == P1``."""
    return multiply(p1, inverse(p2))


def add(p1: Position, p2: Position) -> Position:
    """``P1 + P2``: element by element in world coordinates, flags from P1 [S2f "(3)"]."""
    return replace(
        p1,
        x=p1.x + p2.x, y=p1.y + p2.y, z=p1.z + p2.z,
        a=wrap(p1.a + p2.a), b=wrap(p1.b + p2.b), c=wrap(p1.c + p2.c),
        l1=p1.l1 + p2.l1, l2=p1.l2 + p2.l2,
    )  # fmt: skip


def subtract(p1: Position, p2: Position) -> Position:
    return replace(
        p1,
        x=p1.x - p2.x, y=p1.y - p2.y, z=p1.z - p2.z,
        a=wrap(p1.a - p2.a), b=wrap(p1.b - p2.b), c=wrap(p1.c - p2.c),
        l1=p1.l1 - p2.l1, l2=p1.l2 - p2.l2,
    )  # fmt: skip


def scale(p: Position, k: float) -> Position:
    """``P * M`` (and ``P / M`` with 1/M): every coordinate scaled [S2 p.163]."""
    return replace(
        p, x=p.x * k, y=p.y * k, z=p.z * k, a=p.a * k, b=p.b * k, c=p.c * k,
        l1=p.l1 * k, l2=p.l2 * k,
    )  # fmt: skip


def joints_add(j1: Joints, j2: Joints, sign: float = 1.0) -> Joints:
    n = max(len(j1.values), len(j2.values))
    a = list(j1.values) + [0.0] * (n - len(j1.values))
    b = list(j2.values) + [0.0] * (n - len(j2.values))
    return Joints(tuple(x + sign * y for x, y in zip(a, b, strict=True)))


def joints_scale(j: Joints, k: float) -> Joints:
    return Joints(tuple(x * k for x in j.values))


def distance(p1: Position, p2: Position) -> float:
    """``DIST(P1, P2)``: straight-line distance of the XYZ parts, mm."""
    return math.sqrt((p1.x - p2.x) ** 2 + (p1.y - p2.y) ** 2 + (p1.z - p2.z) ** 2)


def tool_offset(p: Position, dz: float) -> Position:
    """The close-distance target of ``MOV P, d``: `d` mm along P's tool Z [S1 MOV]."""
    return multiply(p, Position(0.0, 0.0, dz, 0.0, 0.0, 0.0, 0.0, 0.0, p.fl1, p.fl2))


def _axis_angle(r: Mat) -> tuple[Vec, float]:
    cos_t = max(-1.0, min(1.0, (r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0))
    theta = math.acos(cos_t)
    if theta < 1e-12:
        return (1.0, 0.0, 0.0), 0.0
    if math.pi - theta < 1e-6:
        # 180°: axis from the diagonal
        x = math.sqrt(max(0.0, (r[0][0] + 1) / 2))
        y = math.sqrt(max(0.0, (r[1][1] + 1) / 2))
        z = math.sqrt(max(0.0, (r[2][2] + 1) / 2))
        if x > 1e-6:
            y = math.copysign(y, r[0][1])
            z = math.copysign(z, r[0][2])
        elif y > 1e-6:
            z = math.copysign(z, r[1][2])
        return (x, y, z), theta
    s = 2 * math.sin(theta)
    return ((r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s), theta


def _axis_rotation(axis: Vec, theta: float) -> Mat:
    x, y, z = axis
    c, s = math.cos(theta), math.sin(theta)
    k = 1 - c
    return (
        (c + x * x * k, x * y * k - z * s, x * z * k + y * s),
        (y * x * k + z * s, c + y * y * k, y * z * k - x * s),
        (z * x * k - y * s, z * y * k + x * s, c + z * z * k),
    )


def interpolate(p1: Position, p2: Position, s: float) -> Position:
    """Pose a fraction `s` of the way from P1 to P2: linear XYZ, equivalent-rotation ABC."""
    r1 = rotation(p1.a, p1.b, p1.c)
    rel = matmul(transpose(r1), rotation(p2.a, p2.b, p2.c))
    axis, theta = _axis_angle(rel)
    r = matmul(r1, _axis_rotation(axis, theta * s))
    t = (p1.x + (p2.x - p1.x) * s, p1.y + (p2.y - p1.y) * s, p1.z + (p2.z - p1.z) * s)
    return _from(r, t, p1, p1.l1 + (p2.l1 - p1.l1) * s, p1.l2 + (p2.l2 - p1.l2) * s)


def frame(p1: Position, p2: Position, p3: Position) -> Position:
    """``FRAM(P1, P2, P3)``: origin P1, X toward P2, XY plane through P3."""
    ex = (p2.x - p1.x, p2.y - p1.y, p2.z - p1.z)
    v = (p3.x - p1.x, p3.y - p1.y, p3.z - p1.z)
    nx = math.sqrt(sum(c * c for c in ex))
    if nx < 1e-9:
        raise ValueError("P1 and P2 coincide")
    ex = (ex[0] / nx, ex[1] / nx, ex[2] / nx)
    ez = (ex[1] * v[2] - ex[2] * v[1], ex[2] * v[0] - ex[0] * v[2], ex[0] * v[1] - ex[1] * v[0])
    nz = math.sqrt(sum(c * c for c in ez))
    if nz < 1e-9:
        raise ValueError("the three points are on one line")
    ez = (ez[0] / nz, ez[1] / nz, ez[2] / nz)
    ey = (
        ez[1] * ex[2] - ez[2] * ex[1],
        ez[2] * ex[0] - ez[0] * ex[2],
        ez[0] * ex[1] - ez[1] * ex[0],
    )
    r: Mat = ((ex[0], ey[0], ez[0]), (ex[1], ey[1], ez[1]), (ex[2], ey[2], ez[2]))
    return _from(r, (p1.x, p1.y, p1.z), p1, p1.l1, p1.l2)


def in_zone(p: Position, p1: Position, p2: Position) -> bool:
    """``ZONE(P, P1, P2)``: is P inside the box spanned by P1 and P2 (XYZ and ABC)?"""
    for k in ("x", "y", "z", "a", "b", "c"):
        lo, hi = sorted((getattr(p1, k), getattr(p2, k)))
        if not lo - 1e-9 <= getattr(p, k) <= hi + 1e-9:
            return False
    return True
