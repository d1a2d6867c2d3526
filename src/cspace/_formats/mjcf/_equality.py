"""MJCF ``<equality>`` constraints: linear joint couplings as mimic joints, findings for all.

A joint equality ``<joint joint1 joint2 polycoef="a0 a1 0 0 0">`` that is active at the
start makes ``joint1`` a function of ``joint2``: ``joint1 = a1 * joint2 + offset`` with
``offset = a0 + qpos0(joint1) - a1 * qpos0(joint2)`` (MuJoCo's polynomial is in the
displacements from ``qpos0``). That is the relation of a URDF ``<mimic>`` (and what
MuJoCo's URDF import writes for one): ``joint1`` is a mimic joint, a point in the
C-space, and keeps its entry in MuJoCo's qpos (`linear_couplings`). A chain of ties is
composed into one relation to its first leader; a second tie on one joint, a circle of
ties and every other coupling stay findings.

The other constraints do not change the joint space, so they leave the normal form as
it is; but they close a kinematic loop or couple joints, so the configurations the robot
can actually take are a subset of that space (LaValle, section 4.4: closed chains).
Each constraint MuJoCo compiled becomes an info finding:

- ``<joint joint1 joint2>``: a mimic joint as above - ``equality-mimic``; otherwise
  ``joint1`` follows a polynomial of ``joint2`` (without ``joint2``, it is held at a
  fixed value) - ``equality-joint``;
- ``<weld>`` and ``<connect>``: two bodies (or the bodies of two sites; the world when
  one is missing) are held together; the joints on the tree path between them form the
  closed chain - ``equality-weld``, ``equality-connect``;
- ``<tendon>`` couples the lengths of tendons - ``equality-tendon``;

MuJoCo itself refuses a constraint that names a joint, body or site the model does not
have; `cspace` refuses more than `MAX_CONSTRAINTS` constraints.
"""

import math
from collections.abc import Iterator, Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.mjcf._prescan import MAX_CONSTRAINTS
from cspace._formats.shared.description import CutSpec
from cspace._formats.shared.pose import Pose
from cspace._record import NamedTuple
from cspace.errors import InvalidElementError

_CONNECT, _WELD, _JOINT, _TENDON = 0, 1, 2, 3
"""MuJoCo's ``mjtEq`` values."""

_SCALAR = (2, 3)
"""MuJoCo's ``mjtJoint`` values of the one-number joints: slide, hinge."""


class Coupling(NamedTuple):
    """A joint that follows another: ``value = multiplier * leader + offset``.

    Attributes:
        leader: The leader's MuJoCo joint id (a joint that follows none).
        multiplier: ``polycoef[1]`` (composed along a chain), dimensionless.
        offset: In the follower's units (rad or m), ``qpos0`` folded in.
        equality: The constraint's index in MuJoCo's ``eq_*`` arrays.
        through: The joints between follower and leader, for a chain of ties.
    """

    leader: int
    multiplier: float
    offset: float
    equality: int
    through: tuple[int, ...] = ()


class Couplings(NamedTuple):
    """What `linear_couplings` found.

    Attributes:
        mimics: The couplings, by follower's MuJoCo joint id.
        refused: Why a joint equality is no mimic joint, by constraint index (only
            for those that would have been one but for this reason).
        disabled: True when ``<option><flag equality="disable"/>`` switches every
            equality constraint off.
    """

    mimics: dict[int, Coupling]
    refused: dict[int, str]
    disabled: bool


def linear_couplings(facts: dict[str, Any]) -> Couplings:
    """The joint equalities that make a joint a mimic joint.

    In MuJoCo's order, a constraint is taken when the model's equality constraints are
    enabled, and it is a joint equality active at the start, with two scalar joints and
    a linear polynomial (``polycoef`` beyond the second number all 0) of finite numbers.
    A chain of ties is composed (a joint that follows a follower follows that one's
    leader), whichever order the constraints come in; a second tie on one joint, or a
    tie that closes a circle, stays a finding.
    """
    joints = facts["joints"]
    disabled = bool(facts.get("equality_disabled", False))
    mimics: dict[int, Coupling] = {}
    refused: dict[int, str] = {}
    for index, (kind, (first, second), _, active, _, poly) in enumerate(facts["equalities"]):
        if disabled or kind != _JOINT or not active or second < 0 or first == second:
            continue
        if int(joints[first][1]) not in _SCALAR or int(joints[second][1]) not in _SCALAR:
            continue
        if any(c != 0.0 for c in poly[2:]):
            continue
        if first in mimics:
            refused[index] = "a second tie on a joint that already follows another"
            continue
        a0, a1 = poly[0], poly[1]
        offset = a0 + float(joints[first][9]) - a1 * float(joints[second][9])
        above = mimics.get(second)
        if above is not None:  # second follows a leader: so does first, through second
            coupling = Coupling(
                above.leader,
                a1 * above.multiplier,
                a1 * above.offset + offset,
                index,
                (second, *above.through),
            )
        else:
            coupling = Coupling(second, a1, offset, index)
        if coupling.leader == first:
            refused[index] = "the ties go round in a circle"
            continue
        below = {
            f: Coupling(
                coupling.leader,
                c.multiplier * coupling.multiplier,
                c.multiplier * coupling.offset + c.offset,
                c.equality,
                (*c.through, first, *coupling.through),
            )
            for f, c in mimics.items()
            if c.leader == first
        }
        numbers = [coupling.multiplier, coupling.offset]
        numbers += [n for c in below.values() for n in (c.multiplier, c.offset)]
        if not all(math.isfinite(n) for n in numbers):
            refused[index] = "its numbers, with qpos0 folded in, are not all finite"
            continue
        mimics[first] = coupling
        mimics.update(below)
    return Couplings(mimics, refused, disabled)


def equality_findings(
    path: str,
    facts: dict[str, Any],
    body_names: Sequence[str],
    joint_names: Sequence[str],
    couplings: Couplings,
) -> Iterator[Diagnostic]:
    """One finding per equality constraint of a compiled model, in MuJoCo's order.

    Args:
        path: The file, for messages.
        facts: The compiled model's facts (`facts`).
        body_names: Every body's name, by MuJoCo body id.
        joint_names: Every joint's name, by MuJoCo joint id.
        couplings: The joint equalities read as mimic joints (`linear_couplings`).

    Raises:
        InvalidElementError: More than `MAX_CONSTRAINTS` constraints (code
            ``too-many-constraints``).
    """
    count = len(facts["equalities"])
    if count > MAX_CONSTRAINTS:
        raise InvalidElementError(
            path,
            f"the model has {count:,} equality constraints, more than the "
            f"{MAX_CONSTRAINTS:,} cspace reads",
            code="too-many-constraints",
        )
    parent = [int(b[1]) for b in facts["bodies"]]
    moving: dict[int, list[str]] = {}
    for joint, name in zip(facts["joints"], joint_names, strict=True):
        moving.setdefault(int(joint[2]), []).append(name)
    tendons = [t or f"tendon{i}" for i, t in enumerate(facts["tendons"])]
    by_equality = {c.equality: (f, c) for f, c in couplings.mimics.items()}
    qposadr = [int(joint[3]) for joint in facts["joints"]]
    for index, (kind, (first, second), _, active, _, poly) in enumerate(facts["equalities"]):
        inactive = "" if active else ' (inactive at the start: active="false")'
        subset = "the reachable set is a subset of the joint space"
        if couplings.disabled:  # MuJoCo applies none of them
            inactive = ' (switched off: <option><flag equality="disable"/>)'
            subset = "it constrains nothing while it is off"
        if index in by_equality:
            follower, c = by_equality[index]
            through = "".join(f" through '{joint_names[j]}'" for j in c.through)
            yield finding(
                "equality-mimic",
                joint_names[follower],
                f"<equality><joint> makes joint '{joint_names[follower]}' follow joint "
                f"'{joint_names[c.leader]}'{through} ({joint_names[follower]} = "
                f"{c.multiplier:g} * {joint_names[c.leader]} + {c.offset:g}), as a URDF "
                "<mimic> does: a point of the C-space, its entry kept in MuJoCo's qpos "
                f"(qpos[{qposadr[follower]}])",
            )
        elif kind == _JOINT:
            why = couplings.refused.get(index)
            yield finding(
                "equality-joint",
                joint_names[first],
                f"<equality><joint> {_tie(joint_names, first, second, poly, why)}"
                f"{inactive}: {subset}",
            )
        elif kind in (_CONNECT, _WELD):
            tag = "connect" if kind == _CONNECT else "weld"
            loop = _loop(parent, moving, first, max(second, 0))
            joints = ", ".join(loop) if loop else "none (the bodies are welded already)"
            yield finding(
                f"equality-{tag}",
                loop[0] if loop else None,
                f"<equality><{tag}> ties body '{body_names[first]}' to body "
                f"'{body_names[max(second, 0)]}'{inactive}: the joints between them form a "
                f"closed chain ({joints}); {subset}",
            )
        elif kind == _TENDON:
            names = [tendons[t] for t in (first, second) if t >= 0]
            yield finding(
                "equality-tendon",
                None,
                f"<equality><tendon> couples tendon(s) {', '.join(names)}{inactive}: the "
                f"joints they span form a closed chain; {subset}",
            )


def closure_cuts(
    facts: dict[str, Any], body_names: Sequence[str], lines: dict[tuple[str, str], int]
) -> tuple[CutSpec, ...]:
    """The active ``connect`` and ``weld`` constraints as the cuts of a mechanism's loops.

    The frames are where MuJoCo holds the two bodies together (`_compile._closure`): a
    connect holds two points (the rotation free), a weld two frames. None when the
    model's equality constraints are switched off; an inactive one is no cut.
    """
    if facts.get("equality_disabled"):
        return ()
    equalities = facts["equalities"]
    cuts = []
    for index, frame_a, frame_b, *rest in facts.get("closures", ()):
        kind, (first, second), _, active, name, _ = equalities[index]
        if not active:
            continue
        tag = "connect" if kind == _CONNECT else "weld"
        turns = kind == _WELD and (not rest or float(rest[0]) != 0.0)  # torquescale 0: none
        label = str(name) if name else f"{tag}{index}"
        cuts.append(
            CutSpec(
                kind=tag,
                name=label,
                link_a=body_names[first],
                frame_a=_pose(frame_a),
                link_b=body_names[max(second, 0)],
                frame_b=_pose(frame_b),
                free="none" if turns else "rotation",
                line=lines.get((tag, label)) if name else None,
            )
        )
    return tuple(cuts)


def left_out_of_closure(facts: dict[str, Any], couplings: Couplings) -> Diagnostic | None:
    """A warning when the model's loops come with constraints the closure does not hold.

    An active joint equality that is no mimic joint (a polynomial tie, a joint held) and
    an active tendon equality constrain the mechanism too; the closure's mobility counts
    only its connects and welds, so it may be higher than the mechanism's.
    """
    if facts.get("equality_disabled"):
        return None
    tied = {c.equality for c in couplings.mimics.values()}
    others = [
        index
        for index, (kind, _, _, active, _, _) in enumerate(facts["equalities"])
        if active and ((kind == _JOINT and index not in tied) or kind == _TENDON)
    ]
    if not others:
        return None
    return finding(
        "closure-partial",
        None,
        f"{len(others)} joint or tendon equalit"
        f"{'y constrains' if len(others) == 1 else 'ies constrain'} the mechanism beside "
        "its connects and welds; the closure does not hold them, so its mobility may be "
        "higher than the mechanism's",
    )


def _pose(frame: Sequence[Sequence[float]]) -> Pose:
    x, y, z = (float(v) for v in frame[0])
    w, i, j, k = (float(v) for v in frame[1])
    return Pose((x, y, z), (w, i, j, k))


def _tie(
    names: Sequence[str], first: int, second: int, poly: Sequence[float], why: str | None
) -> str:
    """What a joint equality that is no mimic joint does, and why it is none."""
    if second < 0:
        return f"holds joint '{names[first]}' at a fixed value"
    tie = f"ties joint '{names[first]}' to joint '{names[second]}'"
    if not all(math.isfinite(c) for c in poly):
        return f"{tie} (by a polynomial with a number that is not finite)"
    if any(c != 0.0 for c in poly[2:]):
        return f"{tie} (a polynomial of it of degree above 1, which no mimic joint is)"
    if why is not None:
        return f"{tie} (linearly, but no mimic joint: {why})"
    return f"{tie} (a polynomial of it)"


def _loop(
    parent: Sequence[int], moving: dict[int, list[str]], first: int, second: int
) -> list[str]:
    """The moving joints on the tree path between two bodies, from ``first`` up then down."""
    up = _ancestors(parent, first)
    down = _ancestors(parent, second)
    below = set(down)
    common = next(body for body in up if body in below)
    path = up[: up.index(common)] + down[: down.index(common)]
    return [joint for body in path for joint in moving.get(body, [])]


def _ancestors(parent: Sequence[int], body: int) -> list[int]:
    chain = [body]
    while chain[-1] > 0:
        chain.append(parent[chain[-1]])
    return chain
