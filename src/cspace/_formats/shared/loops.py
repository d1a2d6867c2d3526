"""A mechanism's joints split into a spanning tree and the joints that close its loops.

A file that writes a closed chain as joints (SDF: a link with two parent joints, or
joints that go round in a circle) describes a graph, not a tree. cspace keeps the first
parent joint of each link, in file order, unless it would close a cycle; every joint left
out is a cut (`CutSpec`): the loop is cut open there, and the cut's constraint closes it.

A joint naming a link that does not exist, joining a link to itself or naming the world
as its child, is left in the tree, so that the structure check
(`structure.build_description`) refuses it with its own code and line.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec


class _Forest:
    """Links grouped into the trees the joints kept so far make (union-find).

    Each group is one tree, and knows its root: the one link without a parent.
    """

    def __init__(self) -> None:
        self.up: dict[str, str] = {}
        self.size: dict[str, int] = {}
        self.root: dict[str, str] = {}  # a group's representative -> the tree's root link

    def find(self, link: str) -> str:
        if link not in self.up:
            self.up[link], self.size[link], self.root[link] = link, 1, link
            return link
        while self.up[link] != link:
            self.up[link] = self.up[self.up[link]]  # path halving: near-constant time
            link = self.up[link]
        return link

    def tree_root(self, link: str) -> str:
        return self.root[self.find(link)]

    def hang(self, parent: str, child: str) -> None:
        """``child``'s tree (``child`` its root) hung below ``parent``."""
        a, b = self.find(parent), self.find(child)
        root = self.root[a]
        if self.size[a] < self.size[b]:
            a, b = b, a
        self.up[b] = a
        self.size[a] += self.size[b]
        self.root[a] = root


def spanning_tree(
    joints: Sequence[JointSpec], links: Iterable[str], world: str | None = None
) -> tuple[list[JointSpec], list[tuple[JointSpec, JointSpec | None]]]:
    """The joints that make a tree, and those that close loops, each in file order.

    Joints are taken in the order of their lines (those without one last, in the order
    given). A joint is a cut when its child already has a parent joint, or when its
    parent hangs below its child (it would close a cycle).

    Args:
        joints: Every joint the file declares.
        links: The names of every link.
        world: The world's name, a parent link that is never a child: a joint naming
            it as its child stays in the tree, for the structure check to refuse.

    Returns:
        The tree's joints, in the order given, and each cut joint with the joint that
        holds its child in the tree (None when the cut closes a cycle of single parents).
    """
    known = set(links) | ({world} if world is not None else set())
    order = sorted(range(len(joints)), key=lambda k: (joints[k].line is None, joints[k].line or 0))
    forest = _Forest()
    holder: dict[str, JointSpec] = {}
    cut: dict[int, JointSpec | None] = {}
    for k in order:
        joint = joints[k]
        parent, child = joint.parent, joint.child
        if parent not in known or child not in known or parent == child or child == world:
            continue  # the structure check refuses it
        if child in holder:
            cut[k] = holder[child]
        elif forest.tree_root(parent) == child:
            cut[k] = None
        else:
            holder[child] = joint
            forest.hang(parent, child)
    tree = [joint for k, joint in enumerate(joints) if k not in cut]
    in_order = [k for k in order if k in cut]
    return tree, [(joints[k], cut[k]) for k in in_order]


def limits_ignored(
    name: str, bounds: Iterable[tuple[float, float]], line: int | None = None
) -> Diagnostic:
    """The warning for a loop-closing joint's limits (its (lower, upper) ``bounds``).

    The mechanism does not hold them: a cut keeps the loop closed at any angle.
    """
    shown = ", ".join(f"[{low:g}, {high:g}]" for low, high in bounds)
    return finding(
        "closure-limits-ignored",
        name,
        f"joint '{name}' closes a loop; its limits {shown} are not part of the "
        "mechanism cspace reports (a cut holds the loop closed at any angle): mobility and "
        "configurations may include what the limits forbid",
        line,
    )
