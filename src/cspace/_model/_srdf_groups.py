"""An SRDF's groups resolved against the robot, by MoveIt's rules.

srdfdom (which reads the SRDF) and ``moveit_core``'s ``RobotModel`` (which builds the
groups) decide, and cspace follows them:

- a ``<joint>`` member is that joint (the virtual joint by its name); a ``<link>``
  member the joint above that link (the virtual joint above the root link);
- a ``<chain base_link tip_link>`` is the joints from the tip up to the base; when the
  base is not above the tip, the joints from the tip up to the first link the two share
  *and the joint above that link*, and those from the base up to it (MoveIt's
  ``addJointModelGroup``);
- a ``<group>`` member adds every joint of that group;
- a member naming a joint or link the robot lacks is dropped, the group kept (srdfdom
  logs it); a group that includes a group the SRDF lacks, or itself, or that is empty,
  is not loaded (srdfdom's "unsatisfied subgroups", MoveIt's "unmet subgroup
  dependencies"): it is `Resolved.broken`, and ``--group`` refuses it.

Each of these is an ``srdf-ignored`` warning naming the SRDF file and line (at most
`MAX_NOTES`). Resolution is linear in the file: groups are resolved once each (an
explicit stack, no recursion), ancestors found once per link.
"""

from collections.abc import Iterable, Mapping, Sequence

from cspace._findings import Diagnostic, finding
from cspace._formats.srdf.reader import Chain, Group, Srdf
from cspace._joint_kind import JointKind
from cspace._joint_report import JointReport
from cspace._record import NamedTuple
from cspace.errors._base import did_you_mean

MAX_NOTES = 100
"""Most ``srdf-ignored`` findings listed (the last says how many more there are)."""


class Resolved(NamedTuple):
    """An SRDF's groups resolved against the robot.

    Attributes:
        srdf: The file as read.
        groups: Each group's joints with coordinates (or mimic joints), in tree order.
        broken: Groups MoveIt would not load -> why, as one line.
        passive: The passive joints (under cspace's names).
        names: SRDF joint name -> cspace's (the root's virtual joint -> ``root_joint``;
            other virtual joints -> ``""``, no joint of the robot).
        findings: The ``srdf-ignored`` findings.
    """

    srdf: Srdf
    groups: Mapping[str, tuple[str, ...]]
    broken: Mapping[str, str]
    passive: frozenset[str]
    names: Mapping[str, str]
    findings: tuple[Diagnostic, ...]


class _Notes:
    """The ``srdf-ignored`` findings, at most `MAX_NOTES` and one that counts the rest."""

    def __init__(self, srdf: Srdf) -> None:
        self.srdf, self.found, self.more = srdf, list[Diagnostic](), 0

    def add(self, line: int | None, problem: str, joint: str | None = None) -> None:
        if len(self.found) < MAX_NOTES:
            self.found.append(finding("srdf-ignored", joint, problem, line, self.srdf.path))
        else:
            self.more += 1

    def all(self) -> tuple[Diagnostic, ...]:
        if not self.more:
            return tuple(self.found)
        last = finding(
            "srdf-ignored", None, f"{self.more:,} more SRDF elements ignored", None, self.srdf.path
        )
        return (*self.found, last)


class _Tree:
    """The robot's links and the joint above each (the root joint above the root link)."""

    def __init__(self, joints: Sequence[JointReport]) -> None:
        self.above = {j.child_link: j for j in joints}
        self.links = set(self.above) | {str(j.parent_link) for j in joints if j.parent_link}

    def chain(self, chain: Chain) -> list[str]:
        """MoveIt's joints of ``chain`` (see the module docstring): O(depth)."""
        from_tip: list[str] = []
        link: str | None = chain.tip
        while link is not None and link != chain.base:
            joint = self.above.get(link)
            if joint is None:  # the root link, with no joint above it
                break
            from_tip.append(joint.name)
            link = joint.parent_link
        if link == chain.base:
            return from_tip
        position = {name: k for k, name in enumerate(from_tip)}
        from_base: list[str] = []
        link = chain.base
        while link is not None:
            joint = self.above.get(link)
            if joint is None:  # both reach the root link: it is the one they share
                return from_tip + from_base
            if joint.name in position:  # the joint above the shared link, and below
                return from_tip[: position[joint.name] + 1] + from_base
            from_base.append(joint.name)
            link = joint.parent_link
        return from_tip + from_base  # both reach the root joint's parent, the world


def resolve(srdf: Srdf, joints: Sequence[JointReport], virtual: str | None) -> Resolved:
    """Every group of ``srdf`` as the robot's joints (see the module docstring).

    Args:
        srdf: The SRDF as read.
        joints: The robot's joints (the report's), in tree order.
        virtual: The SRDF's name of the virtual joint that became cspace's root joint
            (``root_joint``), or None.
    """
    names = {j.name: j.name for j in joints}
    root = next((j.name for j in joints if j.parent_link is None), None)
    for held in srdf.virtual_joints:  # a fixed or other virtual joint: no joint, no warning
        names.setdefault(held.name, "")
    if virtual is not None and root is not None:
        names[virtual] = root
    tree = _Tree(joints)
    moving = {j.name for j in joints if j.nq > 0 or j.kind is JointKind.MIMIC}
    order = {j.name: i for i, j in enumerate(joints)}
    by_group = {g.name: g for g in srdf.groups}
    notes = _Notes(srdf)
    own: dict[str, set[str]] = {}  # each group's joints, without its subgroups'
    broken: dict[str, str] = {}
    for group in srdf.groups:
        own[group.name] = _own(group.name, group, names, tree, notes)
        if not own[group.name] and not group.subgroups:  # srdfdom: "Group is empty"
            broken[group.name] = "it names nothing the robot has"
            notes.add(group.line, f"group '{group.name}' is empty (MoveIt does not load it)")
    resolved: dict[str, frozenset[str]] = {}
    for group in srdf.groups:
        if group.name not in resolved:
            _resolve_one(group.name, by_group, own, resolved, broken, notes)
    groups = {
        g.name: tuple(sorted(resolved.get(g.name, frozenset()) & moving, key=order.__getitem__))
        for g in srdf.groups
    }
    passive = set()
    for named in srdf.passive:
        if named.name in names:
            if names[named.name]:
                passive.add(names[named.name])
        else:
            notes.add(named.line, f"passive joint '{named.name}' is not in the robot")
    return Resolved(srdf, groups, broken, frozenset(passive), names, notes.all())


def _own(name: str, group: Group, names: Mapping[str, str], tree: _Tree, notes: _Notes) -> set[str]:
    """The joints a group names itself (joints, links, chains), unknown names dropped."""
    got: set[str] = set()

    def lacks(line: int | None, what: str, missing: str, known: Iterable[str]) -> None:
        notes.add(
            line,
            f"group '{name}' names {what} '{missing}', which the robot does not have"
            + did_you_mean(missing, known)
            + " (MoveIt drops it from the group)",
        )

    for member in group.joints:
        if member.name in names:
            if names[member.name]:
                got.add(names[member.name])
        else:
            lacks(member.line, "joint", member.name, names)
    for member in group.links:
        if member.name not in tree.links:
            lacks(member.line, "link", member.name, tree.links)
        elif member.name in tree.above:
            got.add(tree.above[member.name].name)
    for chain in group.chains:
        unknown = [x for x in (chain.base, chain.tip) if x not in tree.links]
        for link in unknown:
            lacks(chain.line, "link", link, tree.links)
        if not unknown:
            got.update(tree.chain(chain))
    return got


def _resolve_one(
    start: str,
    by_group: Mapping[str, Group],
    own: Mapping[str, set[str]],
    resolved: dict[str, frozenset[str]],
    broken: dict[str, str],
    notes: _Notes,
) -> None:
    """Resolve group ``start`` and the groups it includes, depth first, without recursion."""
    stack: list[tuple[str, int]] = [(start, 0)]
    on_stack = {start}
    while stack:
        name, next_sub = stack[-1]
        group = by_group[name]
        if next_sub < len(group.subgroups):
            stack[-1] = (name, next_sub + 1)
            sub = group.subgroups[next_sub]
            if sub.name in resolved:
                continue
            if sub.name not in by_group:
                problem = f"group '{name}' includes group '{sub.name}', which the SRDF lacks"
                broken.setdefault(name, problem)
                notes.add(sub.line, problem + did_you_mean(sub.name, by_group)
                          + " (MoveIt does not load it)")  # fmt: skip
                continue
            if sub.name in on_stack:
                names = [n for n, _ in stack]
                cycle = " -> ".join([*names[names.index(sub.name) :], sub.name])
                problem = f"group '{sub.name}' contains itself ({cycle})"
                for member, _ in stack:
                    broken.setdefault(member, problem)
                notes.add(sub.line, problem + " (MoveIt does not load it)")
                continue
            stack.append((sub.name, 0))
            on_stack.add(sub.name)
            continue
        got = set(own[name])
        for sub in group.subgroups:
            got |= resolved.get(sub.name, frozenset())
            if sub.name in broken and name not in broken:
                broken[name] = f"it includes group '{sub.name}': {broken[sub.name]}"
                notes.add(group.line, f"group '{name}' is not loaded by MoveIt: {broken[name]}")
        resolved[name] = frozenset(got)
        stack.pop()
        on_stack.discard(name)
