"""Where Drake's MJCF parser builds a mechanism other than MuJoCo's from the same file.

Drake's parser (``pydrake.multibody.parsing.Parser``, ``detail_mujoco_parser.cc``) makes
a body with several joints a chain of massless bodies, one joint each: every joint but
the last joins the previous body of the chain (the parent first) to a new one placed
where that previous body is, the joint's ``pos`` and ``axis`` read in that body's frame;
the last joint alone carries the body's own ``pos`` and ``quat``. So where MuJoCo places
the body at ``X_PB J1 J2 ... Jn`` (each joint in the body's frame, in order), Drake
places it at ``J1 J2 ... J(n-1) X_PB Jn``: the first joints turn (or slide) the body about
axes in the parent's frame, before its placement. The two agree for every value of the
joints exactly when each joint but the last commutes with the placement ``X_PB``:

- a hinge (a turn about the line through ``pos`` along ``axis``) when the placement maps
  that line onto itself, direction kept: ``R axis = axis`` and ``R^T (pos - t) - pos``
  along ``axis`` (``X_PB = (R, t)``);
- a slide (a move along ``axis``) when ``R axis = axis``;
- a ball (every turn about ``pos``) only when the placement is the identity.

A single joint, its ``pos``, its ``ref`` and ``<compiler angle>`` are read alike by both
(Drake folds ``ref`` into the joint's frame and starts the joint there, as MuJoCo's
qpos0 does), and a free joint stands alone in its body (MuJoCo refuses more than 6
degrees of freedom in one body). Everything here is computed from MuJoCo's compiled
model (`KinematicTree`): the body's placement and each joint's anchor and unit axis, in
the body's frame, are the numbers Drake reads from the file.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.kinematic_tree import KinematicTree, QuaternionWxyz, TreeJoint, Vector

TOLERANCE = 1e-10
"""How far (m, or a unit vector's components) a joint may be from commuting with its
body's placement and still count as commuting: rounding in a compiled model is about
1e-16, and a defect of 1e-10 moves a body by less than 1e-9 at a joint value of pi."""

SHOWN = 6
"""Bodies a finding names; the rest are counted."""


def _rotate(q: QuaternionWxyz, v: Vector) -> Vector:
    """``v`` turned by the unit quaternion ``q`` (w, x, y, z)."""
    w, x, y, z = q
    # v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    cx, cy, cz = y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]
    return (
        v[0] + 2.0 * (w * cx + y * cz - z * cy),
        v[1] + 2.0 * (w * cy + z * cx - x * cz),
        v[2] + 2.0 * (w * cz + x * cy - y * cx),
    )


def _norm(v: Vector) -> float:
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def _minus(a: Vector, b: Vector) -> Vector:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _unit(q: QuaternionWxyz) -> QuaternionWxyz:
    n = math.sqrt(sum(c * c for c in q)) or 1.0
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def commutes(joint: TreeJoint, position: Vector, quaternion: QuaternionWxyz) -> bool:
    """Whether ``joint``'s motion commutes with the placement (``position``, ``quaternion``).

    See the module docstring: the condition for each kind of joint.
    """
    q = _unit(quaternion)
    inverse = (q[0], -q[1], -q[2], -q[3])
    if joint.model == "spherical":
        turned = max(_norm(_minus(_rotate(q, e), e)) for e in ((1, 0, 0), (0, 1, 0), (0, 0, 1)))
        return turned <= TOLERANCE and _norm(position) <= TOLERANCE
    axis = joint.axis
    if _norm(_minus(_rotate(q, axis), axis)) > TOLERANCE:
        return False
    if joint.model != "revolute":  # a slide moves along its turned axis: kept
        return True
    moved = _minus(_rotate(inverse, _minus(joint.anchor, position)), joint.anchor)
    across = (
        moved[1] * axis[2] - moved[2] * axis[1],
        moved[2] * axis[0] - moved[0] * axis[2],
        moved[0] * axis[1] - moved[1] * axis[0],
    )
    return _norm(across) <= TOLERANCE


def drake_differs(
    tree: KinematicTree, lines: dict[tuple[str, str], int], framed: Sequence[int] = ()
) -> list[Diagnostic]:
    """The ``drake-mjcf-differs`` findings of a compiled model (none when Drake agrees).

    Args:
        tree: The model's bodies and joints, as MuJoCo compiled them.
        lines: ``("body", name)`` -> line in the main file, where known.
        framed: The bodies a ``<frame>``, ``<replicate>`` or ``<attach>`` places, by
            MuJoCo id: Drake's parser ignores these elements, and so leaves out the
            bodies and everything below them (a model of more than 2,000 bodies has
            none listed, `mjcf._compile.FRAMED_BODIES`).

    Returns:
        One finding naming the bodies Drake leaves out, when there are any; one naming
        each body it places otherwise (and the joints it applies before the body's
        placement), when there are any.
    """
    left_out: list[int] = []
    out = set(framed)
    for index, body in enumerate(tree.bodies):  # each body after its parent
        if index in out or (body.parent >= 0 and body.parent in out):
            out.add(index)
            left_out.append(index)
    by_body: dict[int, list[TreeJoint]] = {}
    for joint in tree.joints:
        by_body.setdefault(joint.body, []).append(joint)
    moved: list[tuple[str, list[str]]] = []
    for index, joints in by_body.items():
        if len(joints) < 2 or index in out:
            continue
        body = tree.bodies[index]
        before = [
            j.name for j in joints[:-1] if not commutes(j, body.position, body.quaternion_wxyz)
        ]
        if before:
            moved.append((body.name, before))
    found = []
    if left_out:
        names = [tree.bodies[i].name for i in left_out]
        moving = [j.name for j in tree.joints if j.body in out]
        found.append(
            finding(
                "drake-mjcf-differs",
                moving[0] if moving else None,
                f"Drake's MJCF parser leaves out {len(names):,} body(ies) that MuJoCo "
                f"makes: {_listed(names)}, placed by a <frame>, <replicate> or <attach> "
                f"(which Drake ignores, with all they hold){_joints(moving)}",
                lines.get(("body", names[0])),
            )
        )
    if moved:
        first_body, first_joints = moved[0]
        example = ", ".join(f"'{j}'" for j in first_joints)
        found.append(
            finding(
                "drake-mjcf-differs",
                first_joints[0],
                f"Drake's MJCF parser places {len(moved):,} body(ies) otherwise than "
                f"MuJoCo: {_listed([name for name, _ in moved])}. Of a body with several "
                f"joints it applies all but the last ({example} of '{first_body}') in the "
                "parent's frame, before the body's pos and quat, where MuJoCo applies them "
                "in the body's frame, after: Drake's q of a configuration (--to drake) "
                "puts these bodies, and those below them, elsewhere than MuJoCo's qpos does",
                lines.get(("body", first_body)),
            )
        )
    return found


def _listed(names: Sequence[str]) -> str:
    """The first `SHOWN` names, quoted, and how many more."""
    shown = ", ".join(f"'{name}'" for name in names[:SHOWN])
    return shown + (f" and {len(names) - SHOWN:,} more" if len(names) > SHOWN else "")


def _joints(names: Sequence[str]) -> str:
    """The joints Drake loses with the bodies, as a clause (none: empty)."""
    if not names:
        return ""
    return (
        f", and their joints ({_listed(names)}): Drake's q has fewer positions than the "
        "--to drake vectors cspace writes"
    )
