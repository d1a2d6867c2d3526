"""The URDF reader: a parsed XML tree to a checked `RobotDescription`.

It reads what the configuration space depends on (links, joints, their types, axes,
limits and mimic relations) and checks every joint element Pinocchio's URDF parser
(urdfdom) would refuse, so that a broken file gets one precise message with its line
instead of the parser's. It never opens meshes or ``package://`` paths.

Defaults follow the URDF specification: a missing ``<axis>`` is (1, 0, 0); a missing
``lower`` or ``upper`` in ``<limit>`` is 0; a missing mimic multiplier is 1 and offset 0.

Numbers are C-locale decimals (``-1.5``, ``.5``, ``2e-3``; surrounding spaces allowed),
plus ``nan`` and ``inf``, which are read as such and reported as findings (urdfdom
refuses them, and ``1e400``, outright). Pinocchio is given the document as this reader
read it, with every number it would refuse written in a form it accepts (NaN as 0, an
infinity as the largest double, a non-finite axis as (0, 0, 0)): the report's own
values and findings always come from the file, never from that copy.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import NoReturn

from lxml import etree

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, LinkSpec, MimicSpec, RobotDescription
from cspace._formats.shared.reading import Reading, ReadRequest, UrdfText
from cspace._formats.shared.robot_size import MAX_JOINTS, check_count
from cspace._formats.shared.structure import build_checked, build_description, read_each
from cspace._formats.shared.xmlio import check_joint_type, fail_at, leniencies, line_of, xml_version
from cspace._formats.urdf._drake import DRAKE_JOINTS, drake_differs, drake_joint, is_drake_joint
from cspace._formats.urdf._recipe import document_for_pinocchio
from cspace._formats.urdf._world import WORLD, with_world
from cspace._formats.urdf.numbers import (
    URDFDOM_NUMBER,
    URDFDOM_VECTOR,
    for_urdfdom,
    parse_number,
    urdfdom_accepts,
)
from cspace._joint_kind import JointKind
from cspace.errors import InvalidElementError, RobotFileError

URDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
"""The joint types the URDF specification defines."""

LIMIT_REQUIRED = ("revolute", "prismatic")
"""URDF types whose ``<limit>`` element is required."""

MIMIC_TYPES = ("revolute", "continuous", "prismatic")
"""URDF types a ``<mimic>`` applies to (one coordinate each); Pinocchio ignores it on others."""

URDF_KINDS = {
    "revolute": JointKind.REVOLUTE,
    "continuous": JointKind.CONTINUOUS,
    "prismatic": JointKind.PRISMATIC,
    "fixed": JointKind.FIXED,
    "floating": JointKind.FLOATING,
    "planar": JointKind.PLANAR,
}
"""Each URDF joint type in cspace's words."""

NO_AXIS = ("fixed", "floating")
"""URDF types whose ``<axis>`` is ignored (urdfdom does not read it)."""


# Optional numeric attributes of the joint's other elements, which urdfdom parses (and
# refuses when malformed) although the C-space does not depend on them.
_OTHER_NUMBERS = {
    "dynamics": ("damping", "friction"),
    "safety_controller": ("soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"),
    "calibration": ("rising", "falling"),
}
_MAGNITUDES = ("effort", "velocity", "friction")
"""Attributes that are magnitudes: Pinocchio refuses negative ones."""
_REQUIRED = {
    "limit": ("effort", "velocity"),
    "safety_controller": ("k_velocity",),
}


class _Reader:
    """Reads one URDF document, keeping the findings and the fixes for Pinocchio's copy."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.findings: list[Diagnostic] = []
        self.fixes: list[tuple[etree._Element, str, str]] = []
        self.joint_name: str | None = None
        self.children: dict[str, etree._Element] = {}

    def fail(self, code: str, problem: str, element: etree._Element, name: str | None) -> NoReturn:
        """Raise an `InvalidElementError` about ``name`` (default: the current joint)."""
        fail_at(self.path, code, problem, element, name or self.joint_name)

    def attribute(self, element: etree._Element, key: str, owner: str | None) -> str:
        """A required, non-empty attribute; ``owner`` None: the element is its own owner."""
        value = element.get(key)
        if value is not None and (stripped := value.strip()):
            return stripped  # the usual case, before any message is built
        where = "" if owner is None else f"{owner}: "
        tag = etree.QName(element).localname  # as written: drake:joint, not {uri}joint
        tag = f"{element.prefix}:{tag}" if element.prefix else tag
        if value is None:
            self.fail(
                "missing-attribute",
                f"{where}<{tag}> has no '{key}' attribute",
                element,
                None,
            )
        if not str(value).strip():
            self.fail(
                "missing-attribute",
                f'{where}<{tag} {key}="{value}"> is empty',
                element,
                None,
            )
        return str(value).strip()

    def number(
        self,
        element: etree._Element,
        key: str,
        default: float | None,
        owner: str,
        *,
        checked_later: bool = True,
    ) -> float:
        """The number in attribute ``key``; ``default`` when absent (None: required).

        Args:
            element: The element holding the attribute.
            key: The attribute.
            default: The value when the attribute is absent; None when it is required.
            owner: Who the element belongs to, for messages (``joint 'NAME'``).
            checked_later: The value goes into the description, whose findings judge
                non-finite values; otherwise a ``number-invalid`` finding is made here.
        """
        text = element.get(key)
        if text is None:
            if default is None:
                self.fail(
                    "missing-attribute",
                    f"{owner}: <{element.tag}> has no '{key}' attribute (URDF requires it)",
                    element,
                    None,
                )
            return float(default)
        if URDFDOM_NUMBER.fullmatch(text):  # fast path: the plain decimals of most files
            plain = float(text)
            if math.isfinite(plain) and (plain >= 0 or key not in _MAGNITUDES):
                return plain
        value = parse_number(text)
        if value is None:
            what = "is empty, not a number" if not text.strip() else "is not a number"
            self.fail(
                "bad-number", f'{owner}: <{element.tag} {key}="{text}"> {what}', element, None
            )
            raise AssertionError("unreachable")  # pragma: no cover
        if key in _MAGNITUDES and value < 0:
            # Pinocchio refuses a negative effort, velocity or friction (its range
            # [-x, x] would be empty); the C-space does not depend on them.
            self.fixes.append((element, key, for_urdfdom(-value)))
            self.invalid(f'<{element.tag} {key}="{text.strip()}"> is negative', owner)
        elif not urdfdom_accepts(text, value):
            self.fixes.append((element, key, for_urdfdom(value)))
        if not math.isfinite(value) and not checked_later:
            self.invalid(f'<{element.tag} {key}="{text.strip()}"> is not a finite number', owner)
        return value

    def vector(
        self, element: etree._Element, key: str, owner: str, *, checked_later: bool
    ) -> tuple[float, float, float] | None:
        """Three numbers in attribute ``key``, or None when the attribute is absent."""
        text = element.get(key)
        if text is None:
            return None
        if URDFDOM_VECTOR.fullmatch(text):  # fast path: three plain decimals
            x, y, z = map(float, text.split())
            if math.isfinite(x) and math.isfinite(y) and math.isfinite(z):
                return (x, y, z)
        values = [parse_number(part) for part in text.split()]
        if len(values) != 3 or None in values:
            self.fail(
                "bad-number",
                f'{owner}: <{element.tag} {key}="{text}"> is not three numbers',
                element,
                None,
            )
        x, y, z = (float(v) for v in values)  # type: ignore[arg-type]
        finite = math.isfinite(x) and math.isfinite(y) and math.isfinite(z)
        if not (finite and URDFDOM_VECTOR.fullmatch(text)):
            # urdfdom splits on spaces only and refuses NaN, infinities and overflow.
            fixed = " ".join(repr(v) for v in (x, y, z)) if finite else "0 0 0"
            self.fixes.append((element, key, fixed))
        if not checked_later and not finite:
            self.invalid(f'<{element.tag} {key}="{text.strip()}"> is not finite', owner)
        return (x, y, z)

    def invalid(self, what: str, owner: str) -> None:
        """A ``number-invalid`` finding: ``owner: what``, and why it still analyses."""
        self.findings.append(
            finding(
                "number-invalid",
                self.joint_name,
                f"{owner}: {what}; the C-space does not depend on it, but URDF and "
                "Pinocchio refuse it",
            )
        )

    def child(self, tag: str) -> etree._Element | None:
        """The current joint's first child element ``tag`` (urdfdom reads only the first)."""
        return self.children.get(tag)

    def link_name(self, joint: etree._Element, tag: str, owner: str) -> str:
        element = self.child(tag)
        if element is None:
            self.fail("missing-element", f"{owner} has no <{tag}> element", joint, None)
        return self.attribute(element, "link", owner)

    def others(self, element: etree._Element, owner: str) -> None:
        """Check what urdfdom parses but the C-space ignores: origin, dynamics, ..."""
        origin = self.child("origin")
        if origin is not None:
            for key in ("xyz", "rpy"):
                self.vector(origin, key, owner, checked_later=False)
            if origin.get("quat_xyzw") is not None:  # URDF 1.1, as urdfdom reads it
                if origin.get("rpy") is not None:
                    self.fail(
                        "conflicting-attributes",
                        f"{owner}: <origin> gives both 'rpy' and 'quat_xyzw'; urdfdom refuses "
                        "an origin with both (give one or the other)",
                        origin,
                        None,
                    )
                quaternion = [parse_number(p) for p in origin.get("quat_xyzw", "").split()]
                if len(quaternion) != 4 or None in quaternion:
                    self.fail(
                        "bad-number",
                        f'{owner}: <origin quat_xyzw="{origin.get("quat_xyzw")}"> is not four '
                        "numbers",
                        origin,
                        None,
                    )
        for tag, keys in _OTHER_NUMBERS.items():
            child = self.child(tag)
            if child is None:
                continue
            required = _REQUIRED.get(tag, ())
            for key in keys:
                self.number(
                    child, key, None if key in required else 0.0, owner, checked_later=False
                )
        dynamics = self.child("dynamics")
        if (
            dynamics is not None
            and dynamics.get("damping") is None
            and dynamics.get("friction") is None
        ):
            self.fail(
                "missing-attribute",
                f"{owner}: <dynamics> has neither 'damping' nor 'friction' (URDF needs one)",
                dynamics,
                None,
            )

    def axis(self, element: etree._Element, owner: str) -> tuple[float, float, float] | None:
        axis_element = self.child("axis")
        if axis_element is None:
            return None
        if axis_element.get("xyz") is None:
            self.fail(
                "missing-attribute",
                f"{owner}: <axis> has no 'xyz' attribute (URDF requires it; "
                "leave out <axis> for the default (1, 0, 0))",
                axis_element,
                None,
            )
        return self.vector(axis_element, "xyz", owner, checked_later=True)

    def limits(
        self, limit: etree._Element, joint_type: str, owner: str
    ) -> tuple[tuple[float, ...], tuple[float, ...]]:
        for key in _REQUIRED["limit"]:
            self.number(limit, key, None, owner, checked_later=False)
        kept = joint_type in LIMIT_REQUIRED or (
            joint_type == "continuous" and bool(limit.get("lower") or limit.get("upper"))
        )
        # Limits the description does not keep (a fixed joint's, say) are judged here.
        lower = self.number(limit, "lower", 0.0, owner, checked_later=kept)
        upper = self.number(limit, "upper", 0.0, owner, checked_later=kept)
        return ((lower,), (upper,)) if kept else ((), ())

    def joint(self, element: etree._Element) -> JointSpec:
        self.joint_name = None
        self.children = {}
        for sub in element.iterchildren(tag=etree.Element):  # no comments or PIs
            self.children.setdefault(str(sub.tag), sub)
        name = self.attribute(element, "name", None)
        owner = f"joint '{name}'"
        self.joint_name = name
        joint_type = self.attribute(element, "type", owner)
        check_joint_type(self.path, name, joint_type, URDF_JOINT_TYPES, element)
        parent = self.link_name(element, "parent", owner)
        child = self.link_name(element, "child", owner)
        self.others(element, owner)
        axis = None if joint_type in NO_AXIS else self.axis(element, owner)
        limit = self.child("limit")
        if limit is None and joint_type in LIMIT_REQUIRED:
            self.fail(
                "missing-limit",
                f"{owner} is {joint_type} but has no <limit> element (URDF requires one)",
                element,
                name,
            )
        lower, upper = ((), ()) if limit is None else self.limits(limit, joint_type, owner)
        mimic_element = self.child("mimic")
        mimic = None
        if mimic_element is not None:
            follows = joint_type in MIMIC_TYPES
            mimic = MimicSpec(
                joint=self.attribute(mimic_element, "joint", owner),
                multiplier=self.number(
                    mimic_element, "multiplier", 1.0, owner, checked_later=follows
                ),
                offset=self.number(mimic_element, "offset", 0.0, owner, checked_later=follows),
            )
            if not follows and joint_type != "fixed":  # a fixed joint is a point anyway
                self.findings.append(
                    finding(
                        "mimic-ignored",
                        name,
                        f"{joint_type} joint '{name}' has a <mimic> element, which only a "
                        "revolute, continuous or prismatic joint can follow; Pinocchio ignores "
                        f"it, and so does this report ('{name}' is reported as {joint_type})",
                    )
                )
            if not follows:
                mimic = None
        return JointSpec(
            name=name,
            type=joint_type,
            parent=parent,
            child=child,
            kind=URDF_KINDS[joint_type],
            axis=axis,
            lower=lower,
            upper=upper,
            mimic=mimic,
            limits_defaulted=bool(lower)
            and limit is not None
            and limit.get("lower") is None
            and limit.get("upper") is None,
            bounds_missing=_missing(limit, ("lower", "upper")) if lower else (),
            line=line_of(element),
            limit_line=line_of(limit),
            axis_line=line_of(self.child("axis")),
        )


def _missing(element: etree._Element | None, keys: tuple[str, ...]) -> tuple[str, ...]:
    """The attributes among ``keys`` that ``element`` does not give."""
    return () if element is None else tuple(k for k in keys if k not in element.attrib)


def _leaderless(description: RobotDescription) -> tuple[list[JointSpec], list[Diagnostic]]:
    """Joints without the mimic relations whose leader has no single value to follow."""
    joints, findings = [], []
    for joint in description.joints:
        leader = description.joint(joint.mimic.joint) if joint.mimic else None
        if leader is not None and leader.type not in MIMIC_TYPES:
            findings.append(
                finding(
                    "mimic-ignored",
                    joint.name,
                    f"joint '{joint.name}' mimics '{leader.name}', a {leader.type} joint, which "
                    "has no single value to follow; the <mimic> is ignored and "
                    f"'{joint.name}' is reported as the {joint.type} joint it is",
                )
            )
            joint = joint._replace(mimic=None)
        joints.append(joint)
    return joints, findings


def read_urdf(path: str, root: etree._Element, text: str) -> Reading:
    """Read a URDF document's ``<robot>`` element.

    Args:
        path: The file, for messages.
        root: The parsed ``<robot>`` element.
        text: The document ``root`` was parsed from.

    Returns:
        The checked description, with the reader's own findings, and the document to
        give Pinocchio's URDF parser (``text``, or a copy with what that parser would
        refuse but the report can still describe rewritten).

    Raises:
        InvalidElementError: An element lacks what URDF requires, or a number is malformed.
        UnknownJointTypeError: A joint type URDF does not define.
        RobotStructureError: The links and joints do not form one tree.

    Joints come depth-first from the root link, siblings by name: Pinocchio's order.
    """
    reader = _Reader(path)
    check_count(
        path, "links", sum(1 for _ in root.iterchildren("link")), line_of(root), MAX_JOINTS + 1
    )

    def is_joint(element: etree._Element) -> bool:
        return element.tag == "joint" or is_drake_joint(element)

    count = sum(1 for e in root.iterchildren(tag=etree.Element) if is_joint(e))
    check_count(path, "joints", count, line_of(root), MAX_JOINTS)  # Drake's counted too
    elements = [e for e in root.iterchildren(tag=etree.Element) if is_joint(e)]
    problems: list[RobotFileError] = []  # every element's, reported together
    links = read_each(
        root.iterchildren("link"),
        lambda e: LinkSpec(reader.attribute(e, "name", None), line_of(e)),
        problems,
    )
    drake = [e for e in elements if e.tag != "joint"]
    joints = read_each(  # in the file's order: a name defined twice is first where it is
        elements,
        lambda e: reader.joint(e) if e.tag == "joint" else drake_joint(reader, e),
        problems,
    )
    links, world = with_world(links, joints)  # Drake's world, named but not declared
    if world is not None:
        reader.findings.append(world)
    name = root.get("name")
    if links and (name is None or not name.strip()):
        raise InvalidElementError(
            path,
            "<robot> has no 'name' attribute (URDF requires one; Pinocchio refuses the file)",
            code="missing-attribute",
            line=line_of(root),
            element="robot",
        )
    # Pinocchio's URDF parser (through urdfdom) visits sibling joints by name.
    description = build_checked(
        problems,
        lambda: build_description(
            path,
            name=name or "",
            format="urdf",
            links=links,
            joints=joints,
            siblings_by_name=True,
            line=line_of(root),
        ),
    )
    joints, ignored = _leaderless(description)
    dropped = frozenset(f.joint for f in ignored if f.joint is not None)
    version = xml_version(text[:200].encode("utf-8", "replace"))
    if version not in (None, "1.0", "1.1"):
        reader.findings.insert(
            0,
            finding(
                "xml-version",
                None,
                f'the file declares <?xml version="{version}"?>, which XML does not define; '
                "read as 1.0, as urdfdom and Pinocchio read it",
            ),
        )
    for leniency in leniencies(text.encode("utf-8", "surrogateescape")):
        reader.findings.insert(0, finding("xml-lenient", None, leniency))
    differs = drake_differs(joints)
    findings = (*reader.findings, *ignored, *differs)
    described = replace(description, joints=tuple(joints), findings=findings)
    stand_ins = [(e, DRAKE_JOINTS[e.get("type", "").strip()][1]) for e in drake]
    added = (WORLD,) if world is not None else ()
    document = document_for_pinocchio(root, reader.fixes, dropped, stand_ins, added)
    return Reading(described, UrdfText(document or text))


def read(request: ReadRequest) -> Reading:
    """Read the URDF file ``request`` names (the format's reader; see `read_urdf`)."""
    return read_urdf(request.path, request.root, request.source.text)
