"""Where a stage's bodies and joint frames are, as UsdPhysics's parser reads them.

Run in `usd._worker`'s confined child; it answers plain numbers. A pose is a list
``[x, y, z, qw, qx, qy, qz]`` in stage units (the parent converts with
``metersPerUnit``), or None when it cannot be computed (a value that is not finite, a
transform that is singular).

- A body's frame is its composed world transform without its scale (``GfTransform``'s
  translation and rotation), as UsdPhysics gives PhysX a rigid body's pose (`rigid`).
- A joint's frame on one side is ``localPos`` and ``localRot`` (normalised; a zero
  quaternion is the identity, as ``GfQuatf.Normalize`` makes it) in that side's body,
  read as UsdPhysics's ``_GetLocalPose`` reads them: the position is scaled by the
  body's world scale (physics has no scale); a target below a body (a collision prim)
  has its anchor carried into the body's frame; a target that is no body (the
  converter's root Xform) has its anchor carried into the world; no target leaves the
  pose in world coordinates. All in double precision (UsdPhysics computes in float).
- cspace's body for a side is the nearest simulated rigid body at or above the target
  (`usd._worker._body_of`); where UsdPhysics's body differs (a disabled rigid body, a
  static collider), the anchor is carried from it into cspace's body or the world.
"""

from __future__ import annotations

import math
from typing import Any

Pose = list[float]

FLAT = 1e-9
"""A transform scaled by less than this along an axis is singular (``GfTransform`` gives
a zero scale as 1e-10): nothing in it has a place."""


def _finite(values: Any) -> bool:
    return all(math.isfinite(float(v)) for v in values)


def _singular(matrix: Any) -> bool:
    """Whether a transform is not finite or flattens space (a zero scale)."""
    from pxr import Gf  # type: ignore[import-untyped]

    if not _finite(c for row in matrix for c in row):
        return True
    if matrix.ExtractRotationMatrix().GetDeterminant() == 0.0:
        return True
    return min(abs(float(s)) for s in Gf.Transform(matrix).GetScale()) < FLAT


def rigid(matrix: Any) -> Pose | None:
    """The rotation and translation of a transform without its scale, or None."""
    from pxr import Gf

    if _singular(matrix):
        return None
    transform = Gf.Transform(matrix)
    rotation = transform.GetRotation().GetQuat().GetNormalized()
    pose = [*transform.GetTranslation(), rotation.GetReal(), *rotation.GetImaginary()]
    return [float(v) for v in pose] if _finite(pose) else None


def _as_matrix(pose: Pose) -> Any:
    from pxr import Gf

    matrix = Gf.Matrix4d(1.0)
    matrix.SetTranslate(Gf.Vec3d(*pose[:3]))
    matrix.SetRotateOnly(Gf.Quatd(pose[3], Gf.Vec3d(*pose[4:])))
    return matrix


def _usd_body(prim: Any) -> Any:
    """The body UsdPhysics's parser takes for a target: its rigid body, else collider."""
    from pxr import UsdPhysics

    collider = None
    while prim and not prim.IsPseudoRoot():
        if prim.HasAPI(UsdPhysics.RigidBodyAPI):
            return prim
        if collider is None and prim.HasAPI(UsdPhysics.CollisionAPI):
            collider = prim
        prim = prim.GetParent()
    return collider


def _scale(matrix: Any) -> Any:
    from pxr import Gf

    return Gf.Transform(matrix).GetScale()


def _in_usd_body(stage: Any, cache: Any, target: str, local: Pose) -> tuple[Any, Pose | None]:
    """The anchor in UsdPhysics's body of ``target`` (None: in the world), and that body.

    UsdPhysics's ``_GetLocalPose``: a target that is its body has the position scaled by
    the body's world scale; any other target has the anchor carried through the world
    into the body (or left in the world) with the scale removed, then scaled alike.
    """
    from pxr import Gf

    rel = stage.GetPrimAtPath(target)
    body = _usd_body(rel) if rel else None
    world_rel = cache.GetLocalToWorldTransform(rel) if rel else Gf.Matrix4d(1.0)
    position = Gf.Vec3d(*local[:3])
    if _singular(world_rel):
        return body, None
    if not rel or rel != body:
        body_matrix = cache.GetLocalToWorldTransform(body) if body else Gf.Matrix4d(1.0)
        if _singular(body_matrix):
            return body, None
        anchor = (_as_matrix(local) * world_rel * body_matrix.GetInverse()).RemoveScaleShear()
        rotation = anchor.ExtractRotationQuat().GetNormalized()
        position = anchor.ExtractTranslation()
        scale = _scale(body_matrix)
    else:
        rotation = Gf.Quatd(local[3], Gf.Vec3d(*local[4:]))
        scale = _scale(world_rel)
    pose = [*Gf.CompMult(position, Gf.Vec3d(scale)), rotation.GetReal(), *rotation.GetImaginary()]
    return body, [float(v) for v in pose] if _finite(pose) else None


def _compose(a: Pose, b: Pose) -> Pose:
    from pxr import Gf

    qa = Gf.Quatd(a[3], Gf.Vec3d(*a[4:]))
    qb = Gf.Quatd(b[3], Gf.Vec3d(*b[4:]))
    moved = qa.Transform(Gf.Vec3d(*b[:3]))
    q = (qa * qb).GetNormalized()
    return [a[0] + moved[0], a[1] + moved[1], a[2] + moved[2], q.GetReal(), *q.GetImaginary()]


def _inverse(a: Pose) -> Pose:
    from pxr import Gf

    q = Gf.Quatd(a[3], Gf.Vec3d(*a[4:])).GetInverse()
    back = q.Transform(Gf.Vec3d(*a[:3]))
    return [-back[0], -back[1], -back[2], q.GetReal(), *q.GetImaginary()]


def _local(prim: Any, side: int) -> Pose | None:
    """``localPos`` and ``localRot`` as written (rotation normalised), or None.

    None where a value is not finite or not of its schema's type (a file may author
    another type: OpenUSD then gives what it holds).
    """
    from pxr import Gf

    def value(name: str, default: Any) -> Any:
        attribute = prim.GetAttribute(name)
        got = attribute.Get() if attribute else None
        return default if got is None else got

    try:
        position = value(f"physics:localPos{side}", Gf.Vec3f(0.0))
        rotation = value(f"physics:localRot{side}", Gf.Quatf(1.0))
        raw = [float(c) for c in (*position, rotation.GetReal(), *rotation.GetImaginary())]
    except (AttributeError, TypeError, ValueError):
        return None
    if len(raw) != 7 or not _finite(raw):
        return None
    big = max(abs(c) for c in raw[3:])  # scaled first: no square overflows
    length = math.sqrt(sum((c / big) ** 2 for c in raw[3:])) * big if big > 0.0 else 0.0
    unit = [c / length for c in raw[3:]] if length >= 1e-10 else [1.0, 0.0, 0.0, 0.0]
    return [*raw[:3], *unit]


def joint_frame(
    stage: Any, cache: Any, prim: Any, side: int, target: str | None, body: str | None
) -> Pose | None:
    """A joint's frame on one side (0 or 1) in cspace's body ``body`` (None: the world).

    Args:
        stage: The composed stage.
        cache: A ``UsdGeom.XformCache`` at the default time.
        prim: The joint's prim.
        side: 0 for ``localPos0``/``localRot0``, 1 for the other pair.
        target: The side's first relationship target, or None.
        body: The simulated rigid body cspace takes for it, or None for the world.
    """
    local = _local(prim, side)
    if local is None:
        return None
    if target is None:
        return local if body is None else None
    usd_body, pose = _in_usd_body(stage, cache, target, local)
    if pose is None or (usd_body and str(usd_body.GetPath()) == body):
        return pose
    if usd_body:  # a disabled body or a collider: carried into the world first
        frame = rigid(cache.GetLocalToWorldTransform(usd_body))
        if frame is None:
            return None
        pose = _compose(frame, pose)
    if body is None:
        return pose
    own = rigid(cache.GetLocalToWorldTransform(stage.GetPrimAtPath(body)))
    return None if own is None else _compose(_inverse(own), pose)
