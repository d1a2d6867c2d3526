"""Mimic joints of a USD stage: Newton's ``NewtonMimicAPI`` and PhysX's ``PhysxMimicJointAPI``.

``NewtonMimicAPI`` (what ``urdf-usd-converter`` writes for a URDF ``<mimic>``) says
``follower = coef0 + coef1 * leader``, ``coef0`` in the follower's units (degrees for a
revolute joint, stage units for a prismatic one). ``PhysxMimicJointAPI:<axis>`` says
``follower + gearing * leader + offset = 0``, so ``follower = -gearing * leader -
offset`` (the offset in radians or stage units, as Newton reads it). Where a joint has
both, Newton's wins (as in Newton's importer); ``newton:mimicEnabled = false`` turns it
off. Both joints must be revolute or both prismatic, each one joint of the tree: else
the joint is read without the relation and a ``mimic-ignored`` warning says why.
"""

from __future__ import annotations

import math
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, JointToAdd, MimicSpec
from cspace._joint_kind import JointKind

_ANGLES = (JointKind.REVOLUTE, JointKind.CONTINUOUS)
_ONE = (*_ANGLES, JointKind.PRISMATIC)


def with_mimics(
    pairs: list[tuple[JointSpec, JointToAdd | None]],
    joints: list[dict[str, Any]],
    names: dict[str, str],
    meters: float,
) -> tuple[list[tuple[JointSpec, JointToAdd | None]], list[Diagnostic]]:
    """The tree's joints with their mimic relations, and what was ignored.

    Args:
        pairs: The tree's joints (cspace's, in order) and what Pinocchio is asked for.
        joints: The stage's joints as the worker read them (``mimic`` where one is set).
        names: Each joint's name, by prim path.
        meters: The stage's ``metersPerUnit``.
    """
    specs = {spec.name: spec for spec, _ in pairs}
    found: list[Diagnostic] = []
    relations: dict[str, MimicSpec] = {}
    for joint in joints:
        said = joint.get("mimic")
        name = names[joint["path"]]
        if not said:
            continue
        if name not in specs:  # left out of the tree, or a D6 joint split per axis
            if any(n.startswith(f"{name}.") for n in specs):
                found.append(_ignored(name, said, "it is a generic joint of several axes"))
            continue
        follower = specs[name]
        leaders = [names[p] for p in said["leader"] if p in names]
        leader = specs.get(leaders[0]) if leaders else None
        why = _why_not(follower, leader, said)
        if why is not None or leader is None:
            found.append(_ignored(name, said, str(why)))
            continue
        offset = float(said["offset"])
        if said["api"] == "NewtonMimicAPI" and follower.kind in _ANGLES:
            offset = math.radians(offset)
        elif follower.kind is JointKind.PRISMATIC:
            offset *= meters
        relations[name] = MimicSpec(leader.name, float(said["multiplier"]), offset)
    out = [(spec._replace(mimic=relations.get(spec.name)), add) for spec, add in pairs]
    return out, found


def _ignored(name: str, said: dict[str, Any], why: str) -> Diagnostic:
    return finding(
        "mimic-ignored", name, f"joint '{name}' has {said['api']}, but {why}: it is read without it"
    )


def _why_not(follower: JointSpec, leader: JointSpec | None, said: dict[str, Any]) -> str | None:
    """Why a joint cannot follow its leader, or None when it can."""
    if follower.type == "locked":
        return "it is locked (its lower limit is above its upper)"
    if leader is None:
        targets = ", ".join(f"'{p}'" for p in said["leader"]) or "none"
        return f"its leader ({targets}) is no joint of the tree"
    if leader.name == follower.name:
        return "it names itself as its leader"
    if follower.kind not in _ONE or leader.kind not in _ONE:
        return "only a revolute or prismatic joint can follow one"
    if (follower.kind is JointKind.PRISMATIC) != (leader.kind is JointKind.PRISMATIC):
        return f"its leader '{leader.name}' is of another kind (an angle and a length)"
    if not all(math.isfinite(float(said[k])) for k in ("offset", "multiplier")):
        return "its coefficients are not finite numbers"
    return None
