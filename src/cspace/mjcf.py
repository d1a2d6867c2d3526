"""The MJCF (MuJoCo XML) reader: a ``<mujoco>`` document to a checked :class:`RobotDescription`.

It reads what the configuration space depends on and what Pinocchio's MJCF parser
drops or rewrites:

- joint types: ``free`` (also ``<freejoint/>``), ``ball``, ``hinge`` (the default),
  ``slide``; a body without a joint is welded to its parent (a fixed joint named
  ``BODY_fixed``, the name Pinocchio gives its frame);
- ``<default>`` classes (``class`` on a joint, ``childclass`` on a body or frame);
- ``<compiler angle>`` (``degree`` is MuJoCo's default: hinge and ball ranges are
  converted to rad) and ``autolimits`` (``true`` by default: a joint with a ``range``
  and ``limited="auto"`` is limited);
- a ball joint's ``range="0 MAX"`` (a cone of rotations: the joint is a 3-ball, R^3,
  not RP^3), which Pinocchio ignores.

Several joints in one body are one ``JointModelComposite`` in Pinocchio; they are kept
here as the separate joints the file declares, in file order, each from the parent body
to the body, and :func:`flatten_composites` splits Pinocchio's composite to match.
Unnamed joints get Pinocchio's names, ``BODYJoint_K`` (K-th joint of the body).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

from lxml import etree

from .adapter import ROOT_JOINT_NAME, PinJoint, PinModel
from .description import JointSpec, LinkSpec, RobotDescription
from .errors import InvalidElementError, ModelBuildError, UnknownJointTypeError
from .structure import build_description, unique_by_name
from .xmlio import line_of

MJCF_JOINT_TYPES = ("free", "ball", "slide", "hinge")
"""The joint types MuJoCo defines."""

WORLD = "world"
"""The root link: MuJoCo's world body."""

UNSUPPORTED_ELEMENTS = ("replicate", "attach", "composite", "flexcomp")
"""Elements that make bodies or joints `cspace` does not expand; refused rather than
ignored (``<include>`` is spliced in before reading, see :mod:`cspace.mjcf_include`)."""

MAX_DOF = 200
"""Most degrees of freedom (hinge and slide 1, ball 3, free 6) in an MJCF model.
Pinocchio's MJCF parser needs memory that grows about with the cube of the model's
degrees of freedom (200: 340 MiB; 250: 600 MiB; 400: 2.1 GiB; 600: 6.9 GiB), so larger
models are refused before it runs."""

DOF = {"free": 6, "ball": 3, "slide": 1, "hinge": 1}
"""Degrees of freedom of each MuJoCo joint type."""

COMPILER_KEYWORDS = {"angle": ("degree", "radian"), "autolimits": ("true", "false")}
"""The ``<compiler>`` attributes the C-space depends on, and the keywords MuJoCo takes."""


@dataclass(frozen=True)
class BodyJoints:
    """The moving joints of one body, in file order (several: a Pinocchio composite)."""

    body: str
    joints: tuple[str, ...]
    line: int | None


@dataclass(frozen=True)
class MjcfRobot:
    """What the MJCF reader found.

    Attributes:
        description: The checked description (joints depth-first, bodies in file order).
        bodies: Every body that has moving joints, in Pinocchio's order.
    """

    description: RobotDescription
    bodies: tuple[BodyJoints, ...]


def body_name(element: etree._Element) -> str:
    """A ``<body>``'s name, or ``(unnamed body at line N)``; ``world`` for ``<worldbody>``."""
    if element.tag == "worldbody":
        return WORLD
    return element.get("name") or f"(unnamed body at line {line_of(element)})"


def _fail(path: str, code: str, problem: str, element: etree._Element, name: str | None) -> None:
    raise InvalidElementError(path, problem, code=code, line=line_of(element), element=name)


class _Defaults:
    """``<default>`` classes: class name -> joint attributes (inherited ones merged in)."""

    def __init__(self, path: str, root: etree._Element) -> None:
        self.path = path
        self.joint: dict[str, dict[str, str]] = {}
        for top in root.iterchildren("default"):  # top-level sections all add to "main"
            self._read(top, self.joint.pop("main", {}), "main")

    def _read(self, element: etree._Element, inherited: dict[str, str], name: str) -> None:
        if name in self.joint:  # MuJoCo refuses it; reading on would mix two classes
            _fail(
                self.path,
                "duplicate-class",
                f"default class '{name}' is defined twice (MuJoCo refuses repeated class names)",
                element,
                name,
            )
        attributes = dict(inherited)
        for joint in element.iterchildren("joint"):
            attributes.update({str(k): str(v) for k, v in joint.attrib.items()})
        self.joint[name] = attributes
        for child in element.iterchildren("default"):
            self._read(child, attributes, child.get("class", ""))

    def resolve(self, path: str, joint: etree._Element, childclass: str) -> dict[str, str]:
        """The joint's attributes: its own over its class's (``main`` when none).

        Raises:
            InvalidElementError: The class does not exist.
        """
        name = joint.get("class") or childclass
        if name not in self.joint and name != "main":
            _fail(path, "unknown-class", f"default class '{name}' does not exist", joint, None)
        attributes = dict(self.joint.get(name, {}))
        attributes.update({str(k): str(v) for k, v in joint.attrib.items()})
        return attributes


class _Reader:
    def __init__(self, path: str, root: etree._Element) -> None:
        self.path = path
        compiler: dict[str, str] = {}
        for element in root.iterchildren("compiler"):
            for key, keywords in COMPILER_KEYWORDS.items():
                value = element.get(key)
                if value is not None and value not in keywords:
                    _fail(
                        path,
                        "bad-value",
                        f'<compiler {key}="{value}"> is not a keyword MuJoCo knows '
                        f"({' or '.join(keywords)})",
                        element,
                        None,
                    )
            compiler.update({str(k): str(v) for k, v in element.attrib.items()})
        self.degrees = compiler.get("angle", "degree") == "degree"
        self.autolimits = compiler.get("autolimits", "true") == "true"
        self.defaults = _Defaults(path, root)
        self.links: list[LinkSpec] = [LinkSpec(WORLD, line_of(root))]
        self.groups: list[JointSpec] = []
        self.joints: dict[str, list[JointSpec]] = {}
        self.moving: list[BodyJoints] = []
        self.dof = 0

    def numbers(self, text: str, count: int, element: etree._Element, what: str) -> list[float]:
        try:
            values = [float(x) for x in text.split()]
        except ValueError:
            values = []
        if len(values) != count:
            _fail(
                self.path, "bad-number", f'{what}: "{text}" is not {count} numbers', element, None
            )
        return values

    def bodies(self, parent: etree._Element, parent_body: str, childclass: str) -> None:
        for element in parent.iterchildren():
            if not isinstance(element.tag, str):
                continue
            if element.tag in UNSUPPORTED_ELEMENTS:
                _fail(
                    self.path,
                    "unsupported-element",
                    f"<{element.tag}> is not supported: cspace does not expand the bodies it makes",
                    element,
                    None,
                )
            if element.tag in ("body", "frame"):
                inner = element.get("childclass", childclass)
                if element.tag == "frame":
                    self.bodies(element, parent_body, inner)
                else:
                    self.body(element, parent_body, inner)

    def body(self, element: etree._Element, parent_body: str, childclass: str) -> None:
        line = line_of(element)
        declared = [e for e in element.iterchildren("joint", "freejoint")]
        name = element.get("name")
        if not name:
            if declared:
                _fail(
                    self.path,
                    "missing-attribute",
                    f"<body> at line {line} has joints but no name; Pinocchio's MJCF "
                    "parser drops unnamed bodies with their joints (name the body)",
                    element,
                    None,
                )
            name = body_name(element)
        self.links.append(LinkSpec(name, line))
        self.groups.append(
            JointSpec(name=name, type="body", parent=parent_body, child=name, line=line)
        )
        joints = [self.joint(e, k, name, parent_body, childclass) for k, e in enumerate(declared)]
        if not joints:
            joints = [JointSpec(f"{name}_fixed", "fixed", parent_body, name, line=line)]
        else:
            self.moving.append(BodyJoints(name, tuple(j.name for j in joints), line))
        self.joints[name] = joints
        self.bodies(element, name, childclass)

    def joint(
        self, element: etree._Element, k: int, body: str, parent_body: str, childclass: str
    ) -> JointSpec:
        attributes = self.defaults.resolve(self.path, element, childclass)
        name = attributes.get("name") or f"{body}Joint_{k}"
        owner = f"joint '{name}'"
        joint_type = "free" if element.tag == "freejoint" else attributes.get("type", "hinge")
        if joint_type not in MJCF_JOINT_TYPES:
            raise UnknownJointTypeError(
                self.path,
                joint=name,
                joint_type=joint_type,
                valid_types=MJCF_JOINT_TYPES,
                line=line_of(element),
            )
        self.dof += DOF[joint_type]
        if self.dof > MAX_DOF:
            _fail(
                self.path,
                "too-many-dofs",
                f"the model has more than {MAX_DOF} degrees of freedom, more than cspace "
                "builds from MJCF (Pinocchio's MJCF parser needs memory growing with their cube)",
                element,
                name,
            )
        axis = None
        if joint_type in ("hinge", "slide"):
            values = self.numbers(attributes.get("axis", "0 0 1"), 3, element, f"{owner} axis")
            axis = (values[0], values[1], values[2])
        lower: tuple[float, ...] = ()
        upper: tuple[float, ...] = ()
        if joint_type != "free" and self.limited(attributes, element, owner):
            low, high = self.numbers(attributes["range"], 2, element, f"{owner} range")
            if joint_type != "slide" and self.degrees:
                low, high = math.radians(low), math.radians(high)
            # A ball's range is a cone: "0 MAX", MAX the largest rotation angle.
            lower, upper = ((0.0,), (high,)) if joint_type == "ball" else ((low,), (high,))
        return JointSpec(
            name=name,
            type=joint_type,
            parent=parent_body,
            child=body,
            axis=axis,
            lower=lower,
            upper=upper,
            has_limit_element="range" in attributes,
            line=line_of(element),
        )

    def limited(self, attributes: dict[str, str], element: etree._Element, owner: str) -> bool:
        limited = attributes.get("limited", "auto")
        if limited not in ("true", "false", "auto"):
            _fail(
                self.path,
                "bad-value",
                f'{owner}: limited="{limited}" is not true, false or auto',
                element,
                None,
            )
        has_range = "range" in attributes
        if limited == "true" and not has_range:
            _fail(
                self.path,
                "missing-limit",
                f'{owner} is limited="true" but has no range',
                element,
                None,
            )
        if limited == "auto" and has_range and not self.autolimits:
            _fail(
                self.path,
                "missing-attribute",
                f'{owner} has a range but limited="auto" under <compiler autolimits="false">, '
                'which MuJoCo refuses (say limited="true" or "false")',
                element,
                None,
            )
        return has_range and limited != "false"

    def expanded(self, ordered: tuple[JointSpec, ...]) -> Iterator[JointSpec]:
        for group in ordered:
            yield from self.joints[group.child]


def read_mjcf(path: str, root: etree._Element) -> MjcfRobot:
    """Read an MJCF document's ``<mujoco>`` element.

    Args:
        path: The file, for messages.
        root: The parsed ``<mujoco>`` element.

    Returns:
        The checked description and the bodies that have moving joints.

    Raises:
        InvalidElementError: A malformed number, range or name, or an unsupported element.
        UnknownJointTypeError: A joint type MuJoCo does not define.
        RobotStructureError: Duplicate body or joint names.
    """
    reader = _Reader(path, root)
    for worldbody in root.iterchildren("worldbody"):
        reader.bodies(worldbody, WORLD, worldbody.get("childclass", "main"))
    checked = build_description(
        path,
        name=root.get("model", ""),
        format="mjcf",
        links=reader.links,
        joints=reader.groups,
    )
    joints = tuple(reader.expanded(checked.joints))
    unique_by_name(path, joints, "joint")  # a body's joints, now separate, share no name
    from .mjcf_equality import equality_findings

    description = RobotDescription(
        name=checked.name,
        format="mjcf",
        root_link=checked.root_link,
        links=checked.links,
        joints=joints,
        findings=(*checked.findings, *equality_findings(path, root, joints)),
    )
    return MjcfRobot(description, tuple(reader.moving))


def flatten_composites(path: str, robot: MjcfRobot, model: PinModel) -> PinModel:
    """Pinocchio's model with each composite joint split into the joints the file declares.

    Pinocchio makes one joint per body that has joints (a composite when it has
    several), in body order; each part keeps its own model and q/v slice and takes the
    name of the file's joint.

    Raises:
        ModelBuildError: Pinocchio's model left out a body's joints.
    """
    queue = list(model.joints)
    flat: list[PinJoint] = []
    if queue and queue[0].name == ROOT_JOINT_NAME:
        flat.append(queue.pop(0))
    for body in robot.bodies:
        pj = queue.pop(0) if queue else None
        if pj is not None and len(body.joints) == 1 and not pj.parts and pj.name == body.joints[0]:
            flat.append(pj)
        elif pj is not None and len(body.joints) > 1 and len(pj.parts) == len(body.joints):
            flat.extend(p._replace(name=n) for p, n in zip(pj.parts, body.joints, strict=True))
        else:
            raise ModelBuildError(
                path,
                f"Pinocchio's MJCF parser left out joint '{body.joints[0]}' of body "
                f"'{body.body}' (line {body.line}); it reads only the first body under "
                "<worldbody>, so cspace cannot give this robot's q/v layout",
                model.parser_messages,
            )
    return model._replace(joints=tuple(flat))
