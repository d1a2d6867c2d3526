"""Joint kinds, and the one table from Pinocchio's joint models to kinds and spaces.

Each joint contributes a space to the product (see ``shared/reference/cspace-math.md``
section 1): a limited revolute joint an interval (homeomorphic to R), an unlimited one
the circle S^1, a prismatic or helical joint R, a planar joint SE(2) = R^2 × S^1, a
spherical joint SO(3) = RP^3 (a 3-ball, homeomorphic to R^3, when its rotation is
limited), a floating joint SE(3) = R^3 × RP^3; fixed and mimic joints a point.
"""

from __future__ import annotations

from typing import NamedTuple

from cspace.joint_kind import JointKind
from cspace.manifold import CIRCLE, LINE, POINT, SO3, NormalForm


class JointModelRule(NamedTuple):
    """How one Pinocchio joint model is classified.

    Attributes:
        kind: The kind when the joint's rotation is limited (or when limits do not matter).
        limited: The joint's space when the file limits its rotation.
        unlimited: The joint's space when it does not.
        unlimited_kind: The kind when unlimited, if it differs (revolute -> continuous).
        euler: True when Pinocchio keeps the joint in Euler-angle coordinates (singular).
    """

    kind: JointKind
    limited: NormalForm
    unlimited: NormalForm
    unlimited_kind: JointKind | None = None
    euler: bool = False

    def classify(self, limited: bool) -> tuple[JointKind, NormalForm]:
        """The kind and space of a joint of this model, limited or not."""
        if limited:
            return self.kind, self.limited
        return self.unlimited_kind or self.kind, self.unlimited


def _same(kind: JointKind, space: NormalForm) -> JointModelRule:
    return JointModelRule(kind, space, space)


_REVOLUTE = JointModelRule(JointKind.REVOLUTE, LINE, CIRCLE, JointKind.CONTINUOUS)
_SPHERICAL = JointModelRule(JointKind.SPHERICAL, NormalForm(r=3), SO3)

JOINT_MODELS: dict[str, JointModelRule] = {
    **{f"JointModelR{a}": _REVOLUTE for a in "XYZ"},
    "JointModelRevoluteUnaligned": _REVOLUTE,
    **{f"JointModelRUB{a}": _same(JointKind.CONTINUOUS, CIRCLE) for a in "XYZ"},
    "JointModelRevoluteUnboundedUnaligned": _same(JointKind.CONTINUOUS, CIRCLE),
    **{f"JointModelP{a}": _same(JointKind.PRISMATIC, LINE) for a in "XYZ"},
    "JointModelPrismaticUnaligned": _same(JointKind.PRISMATIC, LINE),
    **{f"JointModelH{a}": _same(JointKind.HELICAL, LINE) for a in "XYZ"},
    "JointModelHelicalUnaligned": _same(JointKind.HELICAL, LINE),
    # URDF's planar <limit> is not a rotation limit: always SE(2).
    "JointModelPlanar": _same(JointKind.PLANAR, NormalForm(r=2, t=1)),
    "JointModelSpherical": _SPHERICAL,
    "JointModelSphericalZYX": JointModelRule(JointKind.SPHERICAL, NormalForm(r=3), SO3, euler=True),
    "JointModelFreeFlyer": _same(JointKind.FLOATING, NormalForm(r=3, rp3=1)),
    "JointModelTranslation": _same(JointKind.TRANSLATION, NormalForm(r=3)),
    "JointModelUniversal": JointModelRule(JointKind.UNIVERSAL, NormalForm(r=2), NormalForm(t=2)),
    "JointModelMimic": _same(JointKind.MIMIC, POINT),
}
"""Pinocchio ``shortname()`` -> classification rule. The only place joint models are named."""

FIXED_RULE = _same(JointKind.FIXED, POINT)
"""Fixed joints are frames in Pinocchio, not joints; they contribute a point."""
