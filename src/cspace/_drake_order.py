"""Drake's joint order and the names of its positions and velocities, from a report.

No NumPy: the report's JSON slots (``drake_q``, ``drake_v``) are made from these, and
the maps of `_drake` build on them. Drake's parser numbers a robot's joints depth first
from the world, a body's children in the order their joints are declared in the file;
a joint's entries are named after it (a free body after the body):

======================  ============================  ============================
joint                   q                             v
======================  ============================  ============================
revolute, continuous    ``j_q``                       ``j_w``
prismatic               ``j_x``                       ``j_v``
ball (roll, pitch, yaw) ``j_qx, j_qy, j_qz``          ``j_wx, j_wy, j_wz``
universal               ``j_qx, j_qy``                ``j_wx, j_wy``
planar                  ``j_x, j_y, j_qz``            ``j_vx, j_vy, j_wz``
floating (free body)    ``b_qw .. b_qz, b_x .. b_z``  ``b_wx .. b_wz, b_vx .. b_vz``
======================  ============================  ============================
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from cspace._joint_kind import JointKind
from cspace._joint_table import locked
from cspace.errors import JointMatchError

if TYPE_CHECKING:
    from cspace._joint_report import JointReport

_ONE = {
    JointKind.REVOLUTE: ("q", "w"),
    JointKind.CONTINUOUS: ("q", "w"),
    JointKind.HELICAL: ("q", "w"),  # Drake's screw joint: the angle
    JointKind.PRISMATIC: ("x", "v"),
}
"""The suffixes of a one-coordinate joint's position and velocity."""

_SEVERAL = {
    JointKind.SPHERICAL: (("qx", "qy", "qz"), ("wx", "wy", "wz")),
    JointKind.UNIVERSAL: (("qx", "qy"), ("wx", "wy")),
    JointKind.PLANAR: (("x", "y", "qz"), ("vx", "vy", "wz")),
}
"""The suffixes of the positions and velocities of a joint of several coordinates."""

_FREE = (("qw", "qx", "qy", "qz", "x", "y", "z"), ("wx", "wy", "wz", "vx", "vy", "vz"))
"""A free body's: its quaternion and position; its angular and linear velocities."""


Key = tuple[float, ...]
"""Where a joint is declared, compared as Drake's parser makes joints and bodies."""


def _declared(joints: tuple[JointReport, ...], fmt: str) -> list[Key]:
    """Each joint's place in the order Drake's parser makes them (its line last).

    MJCF: the report's order. SDF: Drake's parser makes a model's nested models (in
    order) before its own links and joints, so a joint scoped ``outer::inner::j`` comes
    before ``outer::k`` whatever their lines: the key is the first line of each model on
    the joint's path (a floating joint cspace gives a free link is named after it), then
    infinity (a model after the models it holds), then the line. Else: the line.
    """
    if fmt == "mjcf":
        return [(float(index),) for index in range(len(joints))]
    lines = [float(j.line) if j.line is not None else math.inf for j in joints]
    if fmt != "sdf":
        return [(line,) for line in lines]
    paths = [tuple(j.name.split("::")[:-1]) for j in joints]
    first: dict[tuple[str, ...], float] = {}
    for path, line in zip(paths, lines, strict=True):
        for k in range(1, len(path) + 1):
            first[path[:k]] = min(first.get(path[:k], math.inf), line)
    return [
        (*(first[path[:k]] for k in range(1, len(path) + 1)), math.inf, line)
        for path, line in zip(paths, lines, strict=True)
    ]


def drake_order(joints: tuple[JointReport, ...], fmt: str) -> list[JointReport]:
    """The joints in Drake's order (see the module docstring).

    Depth first from the world, a link's children in the order their joints are
    declared (an MJCF file's: the report's, MuJoCo's own order; an SDF file's: its
    models' nested models before their own links and joints, see `_declared`; else the
    joint's line), several joints between two links together. At the world, trees
    joined to it by a joint come first, then the bodies Drake floats: trees of several
    bodies (those whose root has the most child links first), then single bodies.

    Raises:
        JointMatchError: The declaration order of siblings that move (a joint with
            positions into them or below) is unknown (a xacro file's report keeps no
            lines; two joints on one line), a floating joint below the root (Drake
            floats its child in the world), or a joint whose child is the link
            ``world`` (Drake's world, which it turns the joint around to hold).
    """
    for joint in joints:
        if joint.child_link == "world" and fmt != "mjcf":
            raise JointMatchError(
                f"joint '{joint.name}' has link 'world' as its child: Drake reads 'world' "
                f"as the world and turns the joint around (link '{joint.parent_link}' "
                "hangs from the world), which cspace does not map"
            )
    below: dict[str | None, dict[str, list[tuple[Key, int, JointReport]]]] = {}
    child_links = set()
    for index, (joint, declared) in enumerate(zip(joints, _declared(joints, fmt), strict=True)):
        below.setdefault(joint.parent_link, {}).setdefault(joint.child_link, []).append(
            (declared, index, joint)
        )
        child_links.add(joint.child_link)
    roots = [link for link in below if link not in child_links]
    moving: set[str | None] = set()  # links with a moving joint into them or below
    parent_of = {joint.child_link: joint.parent_link for joint in reversed(joints)}
    for joint in joints:
        link: str | None = joint.child_link
        while joint.kind is not JointKind.FIXED and link is not None and link not in moving:
            moving.add(link)
            link = parent_of.get(link)

    def groups(link: str | None, root: bool) -> list[list[tuple[Key, int, JointReport]]]:
        """The link's children, one group of joints each, last first (a stack)."""
        found = sorted(sorted(g) for g in below.get(link, {}).values())
        firsts = [g[0][0] for g in found if g[0][2].child_link in moving]  # welds: no q
        unknown = any(key[-1] == math.inf for key in firsts)  # the line, last
        if len(firsts) > 1 and (unknown or len(set(firsts)) < len(firsts)):
            raise JointMatchError(
                f"link '{link}' has several child joints and the report does not say in "
                "which order the file declares them (a xacro file's report keeps no "
                "lines; two joints on one line), which is Drake's order: expand it to a "
                "URDF with one joint per line first (xacro FILE > robot.urdf)"
            )
        for group in found:
            if group[0][2].kind is JointKind.FLOATING and not root:
                raise JointMatchError(
                    f"joint '{group[0][2].name}' is floating below link '{link}': Drake "
                    "floats its child in the world frame, which cspace does not map"
                )
        if root:  # jointed trees, then floated trees of several bodies, then single ones

            def rank(group: list[tuple[Key, int, JointReport]]) -> tuple[int, int]:
                if group[0][2].kind is not JointKind.FLOATING:
                    return (0, 0)
                children = len(below.get(group[0][2].child_link, {}))
                return (1, -children) if children else (2, 0)  # most child links first

            found.sort(key=rank)  # stable: declaration order within each
        return found[::-1]

    out: list[JointReport] = []
    entered: set[str | None] = set()  # links whose children are stacked: each once
    for root in sorted(roots, key=lambda link: min(min(g) for g in below[link].values())[:2]):
        entered.add(root)
        stack = groups(root, True)
        while stack:  # iterative: trees may be thousands of joints deep
            group = stack.pop()
            out += [joint for _, _, joint in group]
            child = group[0][2].child_link
            if child not in entered:
                entered.add(child)
                stack += groups(child, False)
    return out


def follower_kind(joint: JointReport, kind: JointKind | None) -> JointKind:
    """What a mimic or locked joint is in Drake: a prismatic or a revolute joint.

    Its own kind when it has one (a locked joint); a mimic joint's from MuJoCo's type or
    its limits' unit (m: it slides).
    """
    if kind in _ONE and kind is not None:
        return kind
    slides = joint.mujoco_type == "slide" or (joint.limits is not None and joint.limits.unit == "m")
    return JointKind.PRISMATIC if slides else JointKind.REVOLUTE


def taken_names(joints: tuple[JointReport, ...], fmt: str) -> frozenset[tuple[str, str]]:
    """(model scope, name) of every joint Drake makes from the file.

    All but the floating ones: Drake floats a body with a joint of its own, named after
    the body.
    """
    return frozenset(
        _scoped(joint.name, fmt) for joint in joints if joint.kind is not JointKind.FLOATING
    )


def _scoped(name: str, fmt: str) -> tuple[str, str]:
    """(model scope, name within it).

    An SDF file's ``outer::inner::j`` is (``outer::inner``, ``j``); other formats have
    one model.
    """
    if fmt != "sdf":
        return "", name
    scope, _, base = name.rpartition("::")
    return scope, base


def drake_names(
    joint: JointReport,
    kind: JointKind,
    fmt: str = "",
    taken: frozenset[tuple[str, str]] = frozenset(),
) -> tuple[list[str], list[str]]:
    """Drake's names of a joint's positions and velocities, stored as ``kind``.

    An SDF file's joints and links are named in Drake without their models' scope
    (``outer::inner::j`` is ``j`` of model instance ``outer::inner``; the names are those
    of ``GetPositionNames(add_model_instance_prefix=False)``). A floating body's joint is
    named after the body, with ``_`` before it while a joint of its model (``taken``,
    see `taken_names`) has that name, as Drake names it.

    Raises:
        JointMatchError: A kind Drake stores in coordinates cspace does not map.
    """
    name = _scoped(joint.name, fmt)[1]
    if kind in _ONE:
        q, v = _ONE[kind]
        return [f"{name}_{q}"], [f"{name}_{v}"]
    if kind is JointKind.FLOATING:
        scope, body = _scoped(joint.child_link, fmt)
        while (scope, body) in taken:
            body = f"_{body}"
        return [f"{body}_{s}" for s in _FREE[0]], [f"{body}_{s}" for s in _FREE[1]]
    if kind in _SEVERAL:
        qs, vs = _SEVERAL[kind]
        return [f"{name}_{s}" for s in qs], [f"{name}_{s}" for s in vs]
    raise JointMatchError(
        f"joint '{joint.name}' is {kind.value}: Drake stores it in coordinates cspace does not map"
    )


def drake_slots(joints: tuple[JointReport, ...], fmt: str) -> dict[str, dict[str, Any]]:
    """Each joint's ``drake_q`` and ``drake_v`` slots (index and names), by joint name.

    Empty when Drake's order or storage of the robot is not known (see `drake_order`,
    `drake_names`): the report then says nothing about Drake.

    Args:
        joints: A report's joints.
        fmt: Their file's format (``urdf``, ``mjcf``, ``sdf``, ``xacro``).
    """
    try:
        ordered = drake_order(joints, fmt)
        taken = taken_names(joints, fmt)
        slots: dict[str, dict[str, Any]] = {}
        nq = nv = 0
        for joint in ordered:
            moving = joint.kind is not JointKind.FIXED
            if joint.mimic is not None or (moving and locked(joint.limits)):
                kind = follower_kind(joint, joint.kind)  # Drake keeps its entry
            elif not moving or joint.q_index is None:
                continue
            else:
                kind = joint.kind
            q, v = drake_names(joint, kind, fmt, taken)
            slots[joint.name] = {
                "drake_q": {"index": nq, "names": q},
                "drake_v": {"index": nv, "names": v},
            }
            nq, nv = nq + len(q), nv + len(v)
    except JointMatchError:
        return {}
    return slots


def welded_roots(joints: tuple[JointReport, ...], fmt: str) -> tuple[str, ...]:
    """The root links Drake's parser would float where cspace keeps them fixed.

    Drake's URDF and SDF parsers make a link that no joint holds a free body (6 more
    degrees of freedom) unless it is the world; cspace, as Pinocchio, keeps a root link
    fixed unless it is given a root joint. Drake's vectors here are those of a plant with
    these links welded to the world. None for MJCF (MuJoCo's and Drake's MJCF parsers
    weld a body without joints), nor a root whose child is the link ``world`` (Drake's
    world holds it).
    """
    if fmt == "mjcf":
        return ()
    children = {joint.child_link for joint in joints}
    roots = dict.fromkeys(j.parent_link for j in joints if j.parent_link not in children)
    held = {j.parent_link for j in joints if j.child_link == "world"}  # the world's parent
    return tuple(r for r in roots if r is not None and r != "world" and r not in held)
