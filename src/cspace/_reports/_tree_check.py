"""The kinematic tree of a saved report, checked as a robot file's tree is.

A report's joints are its tree in tree order: depth-first from the root link, parents
first. A saved report is untrusted, and the renderers and the diff walk its tree, so
before anything uses it the tree must be one that ``cspace inspect`` can write:

- joint names are unique (every format refuses ``duplicate-joint``);
- the first joint's parent link is the root: a link, or null for a root joint cspace
  added; no other joint has a null parent;
- every other joint hangs from a link an earlier joint reached (no second root, no loop,
  no joint before its parent's);
- every link has one parent link: a link is the child of one joint, except in MJCF, where
  a body's joints (several on one body) come one after another, each from the body's
  parent. Their number is bounded by the joints' (5,001 in a report): ``cspace
  inspect`` reads an MJCF body of up to 5,000 joints.

One pass over the joints, with dictionaries: linear in their number. A broken rule raises
`cspace.errors.ReportFileError` (``bad-report``) with the JSON Pointer of the joint's
field, e.g. ``link 'b' has two parents (joints 'j1' and 'j2') at /joints/7/child_link``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NoReturn

from cspace._formats.table import by_name
from cspace.errors import ReportFileError

_QUOTED_CHARS = 40
"""Longest name quoted whole in a message; a longer one is cut (it may be 256 long)."""


def quoted(name: str | None) -> str:
    """A name in quotes for a message: ``'b'``, cut after 40 characters."""
    if name is None:
        return "null"
    if len(name) <= _QUOTED_CHARS:
        return f"'{name}'"
    return f"'{name[:_QUOTED_CHARS]}...' ({len(name):,} characters)"


def _fail(path: str, problem: str, where: str) -> NoReturn:
    raise ReportFileError(path, f"not a valid cspace report: {problem}", pointer=where)


def check_tree(path: str, document: Mapping[str, Any]) -> None:
    """Refuse a report whose joints are not a tree ``cspace inspect`` could write.

    Args:
        path: The file, for messages.
        document: The report, valid under the report's JSON Schema.

    Raises:
        ReportFileError: A joint name twice, a second root, a loop, a link with two
            parents, or a joint before its parent's (code ``bad-report``).
    """
    joints: Sequence[Mapping[str, Any]] = document["joints"]
    several_per_body = by_name(document["source"]["format"]).stores == "mujoco"
    first_named: dict[str, int] = {}
    for index, joint in enumerate(joints):
        earlier = first_named.setdefault(joint["name"], index)
        if earlier != index:
            _fail(
                path,
                f"joint {quoted(joint['name'])} appears twice (joints {earlier} and {index})",
                f"/joints/{index}/name",
            )
    if not joints:
        return
    root = joints[0]["parent_link"]
    reached: dict[str | None, int] = {root: -1}  # link -> the joint that reached it
    for index, joint in enumerate(joints):
        parent, child = joint["parent_link"], joint["child_link"]
        if parent is None and index:
            _fail(
                path,
                f"joint {quoted(joint['name'])} has no parent link: only the first joint "
                "(a root joint cspace added) may have none",
                f"/joints/{index}/parent_link",
            )
        if parent not in reached:
            _unreached(path, joints, index, root)
        if child in reached:
            previous = joints[index - 1] if index else None
            if (
                several_per_body
                and previous is not None
                and (previous["parent_link"], previous["child_link"]) == (parent, child)
            ):
                continue  # one MJCF body's several joints
            _second_parent(path, joints, index, reached[child], root, several_per_body)
        reached[child] = index


def _second_parent(
    path: str,
    joints: Sequence[Mapping[str, Any]],
    index: int,
    first: int,
    root: str | None,
    several_per_body: bool,
) -> NoReturn:
    """Joint ``index`` leads to a link already reached (by joint ``first``, or the root)."""
    joint = joints[index]
    name, child, parent = quoted(joint["name"]), joint["child_link"], joint["parent_link"]
    where = f"/joints/{index}/child_link"
    if child == parent:
        _fail(path, f"joint {name} connects link {quoted(child)} to itself", where)
    if first < 0:
        _fail(
            path,
            f"link {quoted(root)} is the root and the child of joint {name}: the joints "
            "close a loop",
            where,
        )
    other = quoted(joints[first]["name"])
    problem = f"link {quoted(child)} has two parents (joints {other} and {name})"
    if joints[first]["parent_link"] == parent:
        problem += (
            ": an MJCF body's joints come one after another"
            if several_per_body
            else ": only MJCF puts several joints on one link"
        )
    _fail(path, problem, where)


def _unreached(
    path: str, joints: Sequence[Mapping[str, Any]], index: int, root: str | None
) -> NoReturn:
    """Joint ``index`` hangs from a link no earlier joint reached: say why.

    Walks up from that link through the joints that lead to it (once: this raises).
    """
    joint = joints[index]
    name, parent = quoted(joint["name"]), joint["parent_link"]
    where = f"/joints/{index}/parent_link"
    leading: dict[str, Mapping[str, Any]] = {}  # link -> the first joint leading to it
    for other in joints:
        leading.setdefault(other["child_link"], other)
    seen: set[str] = set()
    top: str | None = parent
    while top is not None and top in leading and top not in seen and top != root:
        seen.add(top)
        top = leading[top]["parent_link"]
    if top is not None and top in seen:
        problem = "on a loop of joints that no root reaches"
    elif top == root:
        problem = "which a later joint leads to: the joints are in tree order, parents first"
    else:
        second = "a second root" if top == parent else f"under a second root, {quoted(top)}"
        problem = f"{second} (the root is {quoted(root)}): a robot's links make one tree"
    _fail(path, f"joint {name} hangs from link {quoted(parent)}, {problem}", where)
