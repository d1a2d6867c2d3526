"""The URDF reader: a parsed XML tree to a checked :class:`RobotDescription`.

It reads only what the configuration space depends on (links, joints, their types,
axes, limits and mimic relations) and never opens meshes or ``package://`` paths.
Defaults follow the URDF specification: a missing ``<axis>`` is (1, 0, 0); a missing
``lower`` or ``upper`` in ``<limit>`` is 0; a missing mimic multiplier is 1 and offset 0.
"""

from __future__ import annotations

from lxml import etree

from .description import JointSpec, LinkSpec, MimicSpec, RobotDescription
from .errors import InvalidElementError, UnknownJointTypeError
from .structure import build_description
from .xmlio import line_of

URDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
"""The joint types the URDF specification defines."""

LIMIT_REQUIRED = ("revolute", "prismatic")
"""URDF types whose ``<limit>`` element is required."""


class _Reader:
    def __init__(self, path: str) -> None:
        self.path = path

    def fail(self, code: str, problem: str, element: etree._Element, name: str | None) -> None:
        raise InvalidElementError(
            self.path, problem, code=code, line=line_of(element), element=name
        )

    def attribute(self, element: etree._Element, key: str, owner: str) -> str:
        value = element.get(key)
        if value is None or not value.strip():
            self.fail(
                "missing-attribute",
                f"{owner}: <{element.tag}> has no '{key}' attribute",
                element,
                None,
            )
        return str(value).strip()

    def number(self, element: etree._Element, key: str, default: float, owner: str) -> float:
        text = element.get(key)
        if text is None or not text.strip():
            return default
        try:
            return float(text)
        except ValueError:
            self.fail(
                "bad-number",
                f'{owner}: <{element.tag} {key}="{text}"> is not a number',
                element,
                None,
            )
        raise AssertionError("unreachable")  # pragma: no cover

    def vector(self, element: etree._Element, key: str, owner: str) -> tuple[float, float, float]:
        text = element.get(key, "")
        parts = text.split()
        try:
            values = [float(p) for p in parts]
        except ValueError:
            values = []
        if len(values) != 3:
            self.fail(
                "bad-number",
                f'{owner}: <{element.tag} {key}="{text}"> is not three numbers',
                element,
                None,
            )
        return (values[0], values[1], values[2])

    def link_name(self, joint: etree._Element, tag: str, owner: str) -> str:
        element = joint.find(tag)
        if element is None:
            self.fail("missing-element", f"{owner} has no <{tag}> element", joint, None)
        return self.attribute(element, "link", owner)  # type: ignore[arg-type]

    def joint(self, element: etree._Element) -> JointSpec:
        name = self.attribute(element, "name", f"<joint> at line {line_of(element)}")
        owner = f"joint '{name}'"
        joint_type = self.attribute(element, "type", owner)
        if joint_type not in URDF_JOINT_TYPES:
            raise UnknownJointTypeError(
                self.path,
                joint=name,
                joint_type=joint_type,
                valid_types=URDF_JOINT_TYPES,
                line=line_of(element),
            )
        parent = self.link_name(element, "parent", owner)
        child = self.link_name(element, "child", owner)
        axis_element = element.find("axis")
        axis = None if axis_element is None else self.vector(axis_element, "xyz", owner)
        limit = element.find("limit")
        if limit is None and joint_type in LIMIT_REQUIRED:
            self.fail(
                "missing-limit",
                f"{owner} is {joint_type} but has no <limit> element (URDF requires one)",
                element,
                name,
            )
        lower: tuple[float, ...] = ()
        upper: tuple[float, ...] = ()
        if limit is not None and (
            joint_type in LIMIT_REQUIRED
            or (joint_type == "continuous" and (limit.get("lower") or limit.get("upper")))
        ):
            lower = (self.number(limit, "lower", 0.0, owner),)
            upper = (self.number(limit, "upper", 0.0, owner),)
        mimic_element = element.find("mimic")
        mimic = None
        if mimic_element is not None:
            mimic = MimicSpec(
                joint=self.attribute(mimic_element, "joint", owner),
                multiplier=self.number(mimic_element, "multiplier", 1.0, owner),
                offset=self.number(mimic_element, "offset", 0.0, owner),
            )
        return JointSpec(
            name=name,
            type=joint_type,
            parent=parent,
            child=child,
            axis=axis,
            lower=lower,
            upper=upper,
            has_limit_element=limit is not None,
            mimic=mimic,
            limits_defaulted=bool(lower)
            and limit is not None
            and limit.get("lower") is None
            and limit.get("upper") is None,
            line=line_of(element),
        )


def read_urdf(path: str, root: etree._Element) -> RobotDescription:
    """Read a URDF document's ``<robot>`` element.

    Args:
        path: The file, for messages.
        root: The parsed ``<robot>`` element.

    Returns:
        The checked description.

    Raises:
        InvalidElementError: An element lacks what URDF requires, or a number is malformed.
        UnknownJointTypeError: A joint type URDF does not define.
        RobotStructureError: The links and joints do not form one tree.

    Joints come depth-first from the root link, siblings by name: Pinocchio's order.
    """
    reader = _Reader(path)
    links = [
        LinkSpec(reader.attribute(e, "name", f"<link> at line {line_of(e)}"), line_of(e))
        for e in root.iterchildren("link")
    ]
    joints = [reader.joint(e) for e in root.iterchildren("joint")]
    # Pinocchio's URDF parser (through urdfdom) visits sibling joints by name.
    return build_description(
        path,
        name=root.get("name", ""),
        format="urdf",
        links=links,
        joints=joints,
        siblings_by_name=True,
    )
