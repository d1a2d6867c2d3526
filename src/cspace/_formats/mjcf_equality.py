"""MJCF ``<equality>`` constraints: findings naming the joints they tie.

An equality constraint does not change the joint space, so it leaves the normal form as
it is; but it closes a kinematic loop or couples joints, so the configurations the robot
can actually take are a subset of that space (LaValle, section 4.4: closed chains).
Each constraint MuJoCo compiled becomes an info finding:

- ``<joint joint1 joint2>``: ``joint1`` follows a polynomial of ``joint2`` (without
  ``joint2``, it is held at a fixed value) - ``equality-joint``;
- ``<weld>`` and ``<connect>``: two bodies (or the bodies of two sites; the world when
  one is missing) are held together; the joints on the tree path between them form the
  closed chain - ``equality-weld``, ``equality-connect``;
- ``<tendon>`` couples the lengths of tendons - ``equality-tendon``;

MuJoCo itself refuses a constraint that names a joint, body or site the model does not
have; `cspace` refuses more than `MAX_CONSTRAINTS` constraints.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.mjcf_prescan import MAX_CONSTRAINTS
from cspace.errors import InvalidElementError

_CONNECT, _WELD, _JOINT, _TENDON = 0, 1, 2, 3
"""MuJoCo's ``mjtEq`` values."""


def equality_findings(
    path: str, facts: dict[str, Any], body_names: Sequence[str], joint_names: Sequence[str]
) -> Iterator[Diagnostic]:
    """One finding per equality constraint of a compiled model, in MuJoCo's order.

    Args:
        path: The file, for messages.
        facts: The compiled model's facts (`facts`).
        body_names: Every body's name, by MuJoCo body id.
        joint_names: Every joint's name, by MuJoCo joint id.

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
    for kind, (first, second), _, active, _ in facts["equalities"]:
        inactive = "" if active else ' (inactive at the start: active="false")'
        if kind == _JOINT:
            if second < 0:
                what = f"holds joint '{joint_names[first]}' at a fixed value"
            else:
                what = (
                    f"ties joint '{joint_names[first]}' to joint '{joint_names[second]}' "
                    "(a polynomial of it)"
                )
            yield finding(
                "equality-joint",
                joint_names[first],
                f"<equality><joint> {what}{inactive}: the reachable set is a subset of "
                "the joint space",
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
                f"closed chain ({joints}); the reachable set is a subset of the joint space",
            )
        elif kind == _TENDON:
            names = [tendons[t] for t in (first, second) if t >= 0]
            yield finding(
                "equality-tendon",
                None,
                f"<equality><tendon> couples tendon(s) {', '.join(names)}{inactive}: the "
                "joints they span form a closed chain; the reachable set is a subset of "
                "the joint space",
            )


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
