"""The URDF reader: a parsed XML tree to a checked `RobotDescription`.

It reads what the configuration space depends on (links, joints, their types, axes,
limits and mimic relations) and checks every joint element Pinocchio's URDF parser
(urdfdom) would refuse, so that a broken file gets one precise message with its line
instead of the parser's (each joint's elements are `_elements`'s to read). Each link's
``<collision>`` shapes are kept as urdfdom reads them (`_collision`, imported only when
the file has one), for the self-collision check. It never opens meshes or
``package://`` paths.

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

from collections.abc import Callable
from typing import TYPE_CHECKING

from lxml import etree

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import (
    CutSpec,
    JointSpec,
    LinkSpec,
    PoseSpec,
    RobotDescription,
)
from cspace._formats.shared.reading import Reading, ReadRequest, UrdfText
from cspace._formats.shared.robot_size import MAX_JOINTS, check_count, check_cuts
from cspace._formats.shared.structure import build_checked, build_description, read_each
from cspace._formats.shared.xmlio import leniencies, line_of, xml_version
from cspace._formats.urdf._drake import (
    DRAKE_JOINTS,
    drake_differs,
    drake_joint,
    is_drake,
    is_drake_joint,
)
from cspace._formats.urdf._elements import MIMIC_TYPES, ElementReader
from cspace._formats.urdf._recipe import document_for_pinocchio
from cspace._formats.urdf._world import WORLD, with_world
from cspace._joint_kind import JointKind
from cspace.errors import InvalidElementError, RobotFileError, RobotFileErrors

if TYPE_CHECKING:
    from cspace._ros2_control import ControlHardware


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
    reader = ElementReader(path)
    check_count(
        path, "links", sum(1 for _ in root.iterchildren("link")), line_of(root), MAX_JOINTS + 1
    )

    def is_joint(element: etree._Element) -> bool:
        return element.tag == "joint" or is_drake_joint(element)

    count = sum(1 for e in root.iterchildren(tag=etree.Element) if is_joint(e))
    check_count(path, "joints", count, line_of(root), MAX_JOINTS)  # Drake's counted too
    balls = [e for e in root.iterchildren(tag=etree.Element) if is_drake(e, "ball_constraint")]
    check_cuts(path, len(balls), line_of(root))
    elements = [e for e in root.iterchildren(tag=etree.Element) if is_joint(e)]
    problems: list[RobotFileError] = []  # every element's, reported together
    links = read_each(root.iterchildren("link"), _link_reader(path, root, reader), problems)
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
    cuts = _ball_constraints(path, balls, {link.name for link in description.links}, problems)
    if problems:
        raise RobotFileErrors.of(problems)
    differs = drake_differs(joints)
    hardware, malformed, controlled, poses = _ros2_control(path, root, joints)
    findings = (*reader.findings, *ignored, *differs, *malformed, *controlled)
    described = description.replace(
        joints=tuple(joints),
        findings=findings,
        cuts=tuple(cuts),
        actuated=_actuated(root, joints),
        ros2_control=hardware,
    )
    stand_ins = [(e, DRAKE_JOINTS[e.get("type", "").strip()][1]) for e in drake]
    added = (WORLD,) if world is not None else ()
    document = document_for_pinocchio(root, reader.fixes, dropped, stand_ins, added)
    return Reading(described, UrdfText(document or text), poses=tuple(poses))


def _link_reader(
    path: str, root: etree._Element, reader: ElementReader
) -> Callable[[etree._Element], LinkSpec]:
    """How each ``<link>`` is read: with its collision shapes, when the file has some.

    Their module is imported only then.
    """
    if root.find("link/collision") is None:
        return lambda e: LinkSpec(reader.attribute(e, "name", None), line_of(e))
    from cspace._formats.shared.collisions import CollisionCounter
    from cspace._formats.urdf._collision import read_link

    counter = CollisionCounter(path)
    return lambda e: read_link(e, reader.attribute(e, "name", None), counter)


def _ball_constraints(
    path: str, balls: list[etree._Element], names: set[str], problems: list[RobotFileError]
) -> list[CutSpec]:
    """The cuts of Drake's ball constraints (none read unless the file has some)."""
    if not balls:
        return []
    from cspace._formats.shared.drake_ball import ball_constraint

    return read_each(
        enumerate(balls),
        lambda ball: ball_constraint(
            path, ball[1], ball[0], _ball_value, lambda n: n if n in names else None
        ),
        problems,
    )


def _actuated(root: etree._Element, joints: list[JointSpec]) -> tuple[str, ...]:
    """The moving joints a ``<transmission>`` drives (its ``<joint name>``), in file order."""
    moving = {joint.name for joint in joints if joint.kind is not JointKind.FIXED}
    named = (
        str(joint.get("name"))
        for transmission in root.iterchildren("transmission")
        for joint in transmission.iterchildren("joint")
    )
    return tuple(dict.fromkeys(name for name in named if name in moving))


def _ros2_control(
    path: str, root: etree._Element, joints: list[JointSpec]
) -> tuple[tuple[ControlHardware, ...], list[Diagnostic], list[Diagnostic], list[PoseSpec]]:
    """The ``<ros2_control>`` elements, what is malformed in them, their findings and poses.

    Their module is read only when the file has some.
    """
    if root.find("ros2_control") is None:
        return (), [], [], []
    from cspace._formats.urdf._ros2_control import check_ros2_control, read_ros2_control

    hardware, malformed = read_ros2_control(path, root)
    controlled, poses = check_ros2_control(hardware, joints)
    return hardware, malformed, controlled, poses


def _ball_value(part: etree._Element) -> str | None:
    """A ``<drake:ball_constraint_*>`` part's value in URDF: its ``name`` or ``value``."""
    local = etree.QName(part).localname
    return part.get("name" if local.endswith(("_A", "_B")) else "value")


def read(request: ReadRequest) -> Reading:
    """Read the URDF file ``request`` names (the format's reader; see `read_urdf`)."""
    return read_urdf(request.path, request.root, request.source.text)
