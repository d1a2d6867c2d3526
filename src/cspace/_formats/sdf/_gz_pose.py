"""Poses as libsdformat resolves them: gz-math's ``Pose3d``, quaternions as written.

libsdformat keeps a ``<pose>``'s quaternion as the file writes it (``quat_xyzw``; an rpy
one is unit) and resolves SDFormat's pose graph with gz-math's arithmetic (gz-math 9 in
libsdformat 16, as Drake 1.51 builds them):

- ``Pose3::operator*`` (`then`) moves a position by ``q v q⁻¹``, ``Quaternion::Inverse``
  being ``q̄ / |q|²``: a rotation by q normalised, whatever q's norm; the rotations'
  product is not normalised (norms multiply);
- ``Pose3::Inverse`` (`invert`) is ``(q⁻¹ * -p, q⁻¹)`` with ``Quaternion * Vector3``
  (`turn`), ``v + 2w (u × v) + 2 u × (u × v)``, which is a rotation only for a unit
  quaternion: for ``q = k q̂`` it is ``R̂ v + (k² - 1)(R̂ v - v)``. A frame resolved
  relative to one whose quaternion (from the scope's root) is off unit is thus put off
  where rigid transforms put it, by about twice the norm's error times its distance;
- ``JointAxis::ResolveXyz`` turns an axis with ``Quaternion * Vector3`` too.

Drake makes each pose it resolves a rigid transform (``RotationMatrix(Quaternion)``
divides by the norm) and normalises joint axes; `rigid` is that step.
"""

from __future__ import annotations

import math

from cspace._formats.shared.pose import (
    IDENTITY,
    Pose,
    QuaternionWxyz,
    Vector,
    product,
    rotate,
    unit,
)

QUATERNION_NORMS = (0.5, 2.0)
"""The norms a quaternion, as written or multiplied along a chain of poses, may have.

gz-math divides by the squared norm: within these, its arithmetic reproduced here agrees
with Drake's to rounding; outside, cspace takes the pose for a mistake.
"""


def norm(q: QuaternionWxyz) -> float:
    """The quaternion's norm."""
    return math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])


def turn(q: QuaternionWxyz, v: Vector) -> Vector:
    """gz-math's ``Quaternion * Vector3``: ``v`` rotated by ``q`` when ``q`` is unit."""
    w, x, y, z = q
    uv = (y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0])
    uuv = (y * uv[2] - z * uv[1], z * uv[0] - x * uv[2], x * uv[1] - y * uv[0])
    return (
        v[0] + 2.0 * (w * uv[0] + uuv[0]),
        v[1] + 2.0 * (w * uv[1] + uuv[1]),
        v[2] + 2.0 * (w * uv[2] + uuv[2]),
    )


def then(a: Pose, b: Pose) -> Pose:
    """gz-math's ``a * b``: ``b``, given in ``a``'s frame, where ``a`` is; norms multiply."""
    if b == IDENTITY:
        return a
    if a == IDENTITY:
        return b
    moved = rotate(unit(a.rotation_wxyz), b.position)
    position = (a.position[0] + moved[0], a.position[1] + moved[1], a.position[2] + moved[2])
    return Pose(position, product(a.rotation_wxyz, b.rotation_wxyz))


def invert(a: Pose) -> Pose:
    """gz-math's ``Pose3::Inverse`` (``a``'s quaternion is not zero)."""
    if a == IDENTITY:
        return a
    w, x, y, z = a.rotation_wxyz
    squared = w * w + x * x + y * y + z * z
    inverse = (w / squared, -x / squared, -y / squared, -z / squared)
    back = turn(inverse, (-a.position[0], -a.position[1], -a.position[2]))
    return Pose(back, inverse)


def chained(a: Pose, b: Pose) -> Pose | None:
    """`then`, or None when the product's norm leaves `QUATERNION_NORMS`."""
    pose = then(a, b)
    return pose if usable(pose.rotation_wxyz) else None


def usable(q: QuaternionWxyz) -> bool:
    """Whether a quaternion's norm is within `QUATERNION_NORMS` (so finite, not zero)."""
    return QUATERNION_NORMS[0] <= norm(q) <= QUATERNION_NORMS[1]


def rigid(a: Pose) -> Pose:
    """The rigid transform Drake makes of a resolved pose: its rotation normalised."""
    return Pose(a.position, unit(a.rotation_wxyz))
