"""MJCF ``<equality>`` constraints: findings naming the joints they tie.

An equality constraint does not change the joint space, so it leaves the normal form as
it is; but it closes a kinematic loop or couples joints, so the configurations the robot
can actually take are a subset of that space (LaValle, section 4.4: closed chains).
Each constraint becomes an info finding:

- ``<joint joint1 joint2>``: ``joint1`` follows a polynomial of ``joint2`` (without
  ``joint2``, it is held at a fixed value) - ``equality-joint``;
- ``<weld>`` and ``<connect>``: two bodies (or the bodies of two sites; the world when
  one is missing) are held together; the joints on the tree path between them form the
  closed chain - ``equality-weld``, ``equality-connect``;
- ``<tendon>`` couples the lengths of tendons - ``equality-tendon``.

A constraint naming a joint, body or site the model does not have is refused, as MuJoCo
refuses it, and so are more than :data:`MAX_CONSTRAINTS` constraints.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

from lxml import etree

from .description import JointSpec
from .diagnostics import finding
from .errors import InvalidElementError
from .mjcf import WORLD, body_name
from .report import Diagnostic
from .xmlio import line_of

MAX_CONSTRAINTS = 1000
"""Most ``<equality>`` constraints read. Real models have a few dozen; each weld or
connect walks the tree between two bodies, and 60,000 of them on a 250-deep chain took
5 s."""


def equality_findings(
    path: str, root: etree._Element, joints: Sequence[JointSpec]
) -> Iterator[Diagnostic]:
    """One finding per ``<equality>`` constraint of the (spliced) ``<mujoco>`` document.

    Args:
        path: The file, for messages.
        root: The ``<mujoco>`` element, includes spliced in.
        joints: The model's joints (fixed ones included), each from parent to child body.

    Raises:
        InvalidElementError: A constraint names a joint, body or site that does not exist
            (code ``unknown-name``), or there are too many (``too-many-constraints``).
    """
    tree = _Tree(path, root, joints)
    constraints = [
        element
        for section in root.iterchildren("equality")
        for element in section.iterchildren(tag=etree.Element)
    ]
    if len(constraints) > MAX_CONSTRAINTS:
        raise InvalidElementError(
            path,
            f"the model has {len(constraints):,} equality constraints, more than the "
            f"{MAX_CONSTRAINTS:,} cspace reads",
            line=line_of(constraints[MAX_CONSTRAINTS]),
            code="too-many-constraints",
        )
    for element in constraints:
        tag = str(element.tag)
        inactive = ' (inactive at the start: active="false")' if _off(element) else ""
        if tag == "joint":
            yield tree.joint_tie(element, inactive)
        elif tag in ("weld", "connect"):
            yield tree.body_tie(element, tag, inactive)
        elif tag == "tendon":
            names = [str(element.get(a)) for a in ("tendon1", "tendon2") if element.get(a)]
            yield finding(
                "equality-tendon",
                None,
                f"<equality><tendon> couples tendon(s) {', '.join(names)}{inactive}: the "
                "joints they span form a closed chain; the reachable set is a subset of "
                "the joint space",
            )


def _off(element: etree._Element) -> bool:
    return element.get("active", "true") == "false"


class _Tree:
    """The model's bodies, their parents, their joints and the sites on them."""

    def __init__(self, path: str, root: etree._Element, joints: Sequence[JointSpec]) -> None:
        self.path = path
        self.joint_names = {j.name for j in joints if j.type != "fixed"}
        self.parent: dict[str, str] = {}
        self.moving: dict[str, list[str]] = {}
        for joint in joints:
            self.parent[joint.child] = joint.parent
            if joint.type != "fixed":
                self.moving.setdefault(joint.child, []).append(joint.name)
        self.site_body: dict[str, str] = {}
        for site in root.iter("site"):
            owner = site.getparent()
            while owner is not None and owner.tag not in ("body", "worldbody"):
                owner = owner.getparent()  # a site may sit in a <frame>
            if site.get("name") and owner is not None:
                self.site_body[str(site.get("name"))] = body_name(owner)

    def _unknown(self, element: etree._Element, what: str, name: str) -> InvalidElementError:
        return InvalidElementError(
            self.path,
            f"<equality><{element.tag}> names {what} '{name}', which does not exist",
            line=line_of(element),
            element=name,
            code="unknown-name",
        )

    def joint_tie(self, element: etree._Element, inactive: str) -> Diagnostic:
        first, second = element.get("joint1", ""), element.get("joint2")
        for name in (first, second):
            if name is not None and name not in self.joint_names:
                raise self._unknown(element, "joint", name)
        if second is None:
            what = f"holds joint '{first}' at a fixed value"
        else:
            what = f"ties joint '{first}' to joint '{second}' (a polynomial of it)"
        return finding(
            "equality-joint",
            first,
            f"<equality><joint> {what}{inactive}: the reachable set is a subset of the joint space",
        )

    def _body(self, element: etree._Element, k: int) -> str:
        site = element.get(f"site{k}")
        if site is not None:
            if site not in self.site_body:
                raise self._unknown(element, "site", site)
            return self.site_body[site]
        body = element.get(f"body{k}") or WORLD
        if body != WORLD and body not in self.parent:
            raise self._unknown(element, "body", body)
        return body

    def _ancestors(self, body: str) -> list[str]:
        chain = [body]
        while chain[-1] in self.parent:
            chain.append(self.parent[chain[-1]])
        return chain

    def body_tie(self, element: etree._Element, tag: str, inactive: str) -> Diagnostic:
        first, second = self._body(element, 1), self._body(element, 2)
        up, down = self._ancestors(first), self._ancestors(second)
        below = set(down)
        common = next(body for body in up if body in below)
        path = up[: up.index(common)] + down[: down.index(common)]
        loop = [joint for body in path for joint in self.moving.get(body, [])]
        joints = ", ".join(loop) if loop else "none (the bodies are welded already)"
        return finding(
            f"equality-{tag}",
            loop[0] if loop else None,
            f"<equality><{tag}> ties body '{first}' to body '{second}'{inactive}: the joints "
            f"between them form a closed chain ({joints}); the reachable set is a subset of "
            "the joint space",
        )
