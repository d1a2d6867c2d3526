"""Rigid transforms for the readers, without Pinocchio: a position and a unit quaternion.

A `Pose` is the frame of one thing expressed in the frame of another: ``position`` is
its origin (m), ``rotation_wxyz`` its orientation as a unit quaternion ``(w, x, y, z)``.
``compose(a, b)`` is ``a * b``: ``b`` given in ``a``'s frame, expressed where ``a`` is.
"""

import math

from cspace._record import NamedTuple

Vector = tuple[float, float, float]
QuaternionWxyz = tuple[float, float, float, float]


class Pose(NamedTuple):
    """A frame in another frame.

    Attributes:
        position: The origin (x, y, z), m.
        rotation_wxyz: The orientation, a unit quaternion (w, x, y, z).
    """

    position: Vector = (0.0, 0.0, 0.0)
    rotation_wxyz: QuaternionWxyz = (1.0, 0.0, 0.0, 0.0)


IDENTITY = Pose()
"""The frame itself."""


def product(a: QuaternionWxyz, b: QuaternionWxyz) -> QuaternionWxyz:
    """The Hamilton product ``a b`` (of any norms)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def rotate(q: QuaternionWxyz, v: Vector) -> Vector:
    """``v`` rotated by the unit quaternion ``q``."""
    _, x, y, z = product(product(q, (0.0, *v)), (q[0], -q[1], -q[2], -q[3]))
    return (x, y, z)


def unit(q: QuaternionWxyz) -> QuaternionWxyz:
    """``q`` scaled to norm 1 (the identity when it is zero)."""
    norm = math.sqrt(sum(c * c for c in q))
    if norm == 0.0 or not math.isfinite(norm):
        return (1.0, 0.0, 0.0, 0.0)
    w, x, y, z = (c / norm for c in q)
    return (w, x, y, z)


def compose(a: Pose, b: Pose) -> Pose:
    """``a * b``: the frame ``b`` (given in ``a``'s frame) expressed where ``a`` is."""
    moved = rotate(a.rotation_wxyz, b.position)
    position = (
        a.position[0] + moved[0],
        a.position[1] + moved[1],
        a.position[2] + moved[2],
    )
    return Pose(position, unit(product(a.rotation_wxyz, b.rotation_wxyz)))


def inverse(a: Pose) -> Pose:
    """The frame ``a`` was given in, expressed in ``a``'s frame."""
    w, x, y, z = a.rotation_wxyz
    conjugate = (w, -x, -y, -z)
    back = rotate(conjugate, a.position)
    return Pose((-back[0], -back[1], -back[2]), conjugate)


def from_rpy(roll: float, pitch: float, yaw: float) -> QuaternionWxyz:
    """The rotation ``Rz(yaw) * Ry(pitch) * Rx(roll)`` (URDF's and SDF's fixed-axis rpy)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    )
