"""Which link pairs of a USD robot PhysX never collides: its collision filters, read.

`collision_filters` asks the stage's OpenUSD child (`usd.child`) for what UsdPhysics's
own parser (PhysX's) says, then names the link pairs, as the reader names links, that no
collision of PhysX's is ever reported for:

- an enabled joint whose ``physics:collisionEnabled`` is false (UsdPhysics's default:
  "determines if the jointed subtrees should collide or not", false unless authored)
  filters its two bodies (PhysX's joint without ``eCOLLISION_ENABLED``);
- a joint of an articulation (not ``physics:excludeFromArticulation``) filters its two
  bodies whatever it says: PhysX never collides an articulation's parent and child
  links ("parent/child collisions are disabled internally", ``PxArticulationFlag``);
- an articulation whose prim says ``physxArticulation:enabledSelfCollisions = false``
  (PhysxSchema's ``PhysxArticulationAPI``, read as authored) filters every pair of its
  links (Isaac Lab's ``enabled_self_collisions=False``);
- ``physics:filteredPairs`` (``PhysicsFilteredPairsAPI``) of a body, a collider or an
  articulation filters it against each target (a body, collider or articulation);
- ``PhysicsCollisionGroup``: two colliders whose groups are filtered do not collide. A
  group filters another it lists in ``physics:filteredGroups`` (itself too), or, with
  ``physics:invertFilteredGroups``, every group it does not list; either side's rule
  filters the pair; groups with the same ``physics:mergeGroup`` are one (UsdPhysics
  merges them); the members are the colliders of its ``colliders`` collection, as
  UsdPhysics computes them. A collider of several groups is filtered against another
  when one of its groups is (PhysX gives a shape one group).

A link pair is filtered when every pair of their colliders is (a joint's, an
articulation's, a body's filter takes them all). Only links with colliders
(`LinkSpec.collisions` read) are named. The first rule in the order above gives the
reason.
"""

import os
from collections.abc import Iterable, Sequence
from itertools import combinations
from typing import Any

from cspace._record import NamedTuple

MAX_FILTERED_PAIRS = 1_000_000
"""Most link pairs named (a robot of 1,400 links has as many pairs)."""

MAX_CHECKS = 4_000_000
"""Most collider pairs looked at for the pairs and groups that filter single colliders."""

Pair = tuple[str, str]


class CollisionFilters(NamedTuple):
    """A USD robot's link pairs PhysX does not collide.

    Attributes:
        pairs: Each filtered link pair, its names sorted, and why in a line (the rule
            and the prim that says it).
        problems: What was not read, in a line each (a target that is no part of the
            robot, a bound passed); empty when every filter was read.
    """

    pairs: dict[Pair, str]
    problems: tuple[str, ...]


def collision_filters(path: str, allow_dirs: Sequence[str] = ()) -> CollisionFilters:
    """The link pairs the USD stage at ``path`` filters (see the module docstring).

    Args:
        path: The stage on disk (as `cspace.inspect` reads it).
        allow_dirs: Folders beside its own it may compose files from (``--allow-dir``).

    Raises:
        RobotFileError: ``usd-refused``: the OpenUSD child could not read the stage.
    """
    import json

    from cspace._confine.sandbox import ChildRefused
    from cspace._formats.usd.child import ask
    from cspace.errors import RobotFileError

    allowed = [os.path.dirname(os.path.abspath(path)), *map(str, allow_dirs)]
    try:
        answer = ask({"path": os.path.abspath(path), "filters": True},
                     [os.path.abspath(a) for a in allowed])  # fmt: skip
    except ChildRefused as exc:
        raise RobotFileError(path, str(exc), code="usd-refused") from None
    return filters_of(json.loads(answer))


def filters_of(facts: dict[str, Any]) -> CollisionFilters:
    """The filtered link pairs of a stage's facts (with ``filters``, `usd._worker`)."""
    from cspace._formats.usd._collision import usable
    from cspace._formats.usd.reader import prim_names

    bodies = list(facts["bodies"])
    names = prim_names(bodies, facts.get("display_names", {}))
    said = facts.get("filters") or {}
    meters = float(facts.get("meters_per_unit") or 1.0)
    rules = _Rules(names, [f for f in facts.get("colliders", ()) if usable(f, meters)])
    problems = ["more filtered-pair targets or group members than cspace reads"] * bool(
        said.get("cut")
    )
    shown = facts.get("display_names", {})
    joints = said.get("joints", ())
    bodies_of = _articulated(bodies, joints, said.get("articulations", ()))
    linked = {b for parts in bodies_of.values() for part in parts for b in part}
    for joint, body0, body1, enabled, excluded in joints:
        name = shown.get(joint) or str(joint).rsplit("/", 1)[-1]
        if not enabled:
            why = f"joint '{name}' has physics:collisionEnabled false (the default)"
        elif not excluded and body0 in linked:  # then body1 is in its part too
            why = f"joint '{name}' joins them in an articulation (PhysX never collides them)"
        else:
            continue
        rules.bodies([body0], [body1], why)
    for prim, selfish in said.get("articulations", ()):
        if not selfish:
            why = f"articulation '{prim}' has physxArticulation:enabledSelfCollisions false"
            for part in bodies_of.get(str(prim), ()):
                rules.bodies(part, part, why)
    everything = {p: [b for part in parts for b in part] for p, parts in bodies_of.items()}
    rules.colliders(said.get("pairs", ()), everything, problems)
    rules.groups(said.get("groups", ()), said.get("members", ()))
    return CollisionFilters(rules.found, tuple(problems + rules.problems))


def _articulated(
    bodies: list[str], joints: Iterable[Any], articulations: Iterable[Any]
) -> dict[str, list[list[str]]]:
    """Each articulation's links: the bodies joined by its joints, part by part.

    An articulation (its prim has ``PhysicsArticulationRootAPI``) is made of the bodies
    at or below its prim and those joined to them by enabled joints not excluded from
    articulations; each set of bodies so joined is one part (PhysX's articulation).
    """
    parent = {b: b for b in bodies}

    def find(body: str) -> str:
        while parent[body] != body:
            parent[body] = parent[parent[body]]
            body = parent[body]
        return body

    for _, body0, body1, _, excluded in joints:
        if not excluded and body0 in parent and body1 in parent:
            parent[find(body0)] = find(body1)
    parts: dict[str, list[str]] = {}
    for body in bodies:
        parts.setdefault(find(body), []).append(body)
    found: dict[str, list[list[str]]] = {}
    for prim, _ in articulations:
        top = str(prim).rstrip("/") + "/"
        roots = dict.fromkeys(find(b) for b in bodies if b == prim or b.startswith(top))
        found[str(prim)] = [parts[r] for r in roots]
    return found


class _Rules:
    """The filtered link pairs found so far, each with its first reason."""

    def __init__(self, names: dict[str, str], colliders: list[dict[str, Any]]) -> None:
        self.names = names
        self.link_of = {str(c["path"]): names[str(c["body"])] for c in colliders
                        if str(c["body"]) in names}  # fmt: skip
        self.by_link: dict[str, list[str]] = {}
        for collider, link in self.link_of.items():
            self.by_link.setdefault(link, []).append(collider)
        self.found: dict[Pair, str] = {}
        self.problems: list[str] = []
        self.checks = MAX_CHECKS

    def add(self, a: str, b: str, why: str) -> None:
        if a == b or a not in self.by_link or b not in self.by_link:
            return
        pair = (a, b) if a < b else (b, a)
        if pair in self.found:
            return
        if len(self.found) >= MAX_FILTERED_PAIRS:
            if not self.problems or "more filtered link pairs" not in self.problems[-1]:
                self.problems.append(f"more filtered link pairs than the {MAX_FILTERED_PAIRS:,} "
                                     "cspace names")  # fmt: skip
            return
        self.found[pair] = why

    def bodies(self, first: Iterable[str], second: Iterable[str], why: str) -> None:
        """Filter every link of ``first`` against every link of ``second`` (body paths)."""
        left = sorted({self.names[b] for b in first if b in self.names} & set(self.by_link))
        right = sorted({self.names[b] for b in second if b in self.names} & set(self.by_link))
        if left == right:
            for a, b in combinations(left, 2):
                self.add(a, b, why)
            return
        for a in left:
            for b in right:
                self.add(a, b, why)

    def colliders(
        self, pairs: Iterable[Any], bodies_of: dict[str, list[str]], problems: list[str]
    ) -> None:
        """``physics:filteredPairs``: a link pair when all its collider pairs are named."""
        named: set[tuple[str, str]] = set()
        touched: dict[Pair, str] = {}
        for source, targets in pairs:
            mine = self._resolve(str(source), bodies_of)
            for target in targets:
                theirs = self._resolve(str(target), bodies_of)
                if not mine or not theirs:
                    problems.append(f"physics:filteredPairs of '{source}' names '{target}', "
                                    "no body, collider or articulation of the robot")  # fmt: skip
                    continue
                if not self._spend(len(mine) * len(theirs)):
                    return
                for c in mine:
                    for d in theirs:
                        named.add((c, d) if c < d else (d, c))
                        a, b = sorted((self.link_of[c], self.link_of[d]))
                        touched.setdefault((a, b), f"physics:filteredPairs of '{source}'")
        for (a, b), why in touched.items():
            if (
                a != b
                and self._spend(len(self.by_link[a]) * len(self.by_link[b]))
                and all(
                    ((c, d) if c < d else (d, c)) in named
                    for c in self.by_link[a]
                    for d in self.by_link[b]
                )
            ):
                self.add(a, b, why)

    def _resolve(self, path: str, bodies_of: dict[str, list[str]]) -> list[str]:
        if path in self.link_of:
            return [path]
        if path in self.names:
            return list(self.by_link.get(self.names[path], ()))
        links = {self.names[b] for b in bodies_of.get(path, ()) if b in self.names}
        return [c for link in sorted(links) for c in self.by_link.get(link, ())]

    def _spend(self, checks: int) -> bool:
        self.checks -= checks
        if self.checks < 0 and "more collider pairs" not in " ".join(self.problems):
            self.problems.append(f"more collider pairs to look at than the {MAX_CHECKS:,} "
                                 "cspace does: some filtered pairs may be missing")  # fmt: skip
        return self.checks >= 0

    def groups(self, groups: Iterable[Any], members: Iterable[Any]) -> None:
        """Collision groups: a link pair when every pair of their colliders' groups is."""
        one: dict[str, str] = {}
        listed: dict[str, set[str]] = {}
        invert: dict[str, bool] = {}
        for path, filtered, inverted, merged in groups:
            for other in merged:
                one[str(other)] = str(path)
            listed[str(path)], invert[str(path)] = {str(f) for f in filtered}, bool(inverted)
        lists = {g: {one.get(f, f) for f in fs} for g, fs in listed.items()}

        def says(g: str, h: str) -> bool:
            return g in lists and ((h in lists[g]) != invert[g])

        of = {str(c): frozenset(one.get(str(g), str(g)) for g in gs) for c, gs in members}
        kinds: dict[frozenset[frozenset[str]], list[str]] = {}
        for link, colliders in self.by_link.items():
            sets = frozenset(of.get(c, frozenset()) for c in colliders)
            if all(sets):  # a collider of no group collides with all
                kinds.setdefault(sets, []).append(link)

        ordered = {g: tuple(sorted(g)) for sets in kinds for g in sets}

        def apart(x: frozenset[frozenset[str]], y: frozenset[frozenset[str]]) -> str | None:
            why = None
            for s in x:
                for t in y:
                    hit = next(((g, h) for g in ordered[s] for h in ordered[t]
                                if says(g, h) or says(h, g)), None)  # fmt: skip
                    if hit is None:
                        return None
                    why = why or hit
            return None if why is None else f"collision groups '{why[0]}' and '{why[1]}'"

        classes = sorted(kinds.items(), key=lambda item: sorted(item[1]))
        sizes = [sum(len(g) for g in x) for x, _ in classes]
        for i, (x, first) in enumerate(classes):
            for j, (y, second) in enumerate(classes[i:], i):
                # the groups looked at (both ways), at most: bounded as filteredPairs' are
                if not self._spend(max(1, sizes[i] * sizes[j])):
                    return
                why = apart(x, y)
                if why is None:
                    continue
                left, right = sorted(first), sorted(second)
                pairs = combinations(left, 2) if i == j else ((a, b) for a in left for b in right)
                for a, b in pairs:
                    self.add(a, b, why)
