"""A robot file's own account of its joints and links, independent of the format.

Every format reader (`cspace._formats.table`) produces a `RobotDescription`; it keeps what
Pinocchio drops or rewrites: fixed joints, the limits as written, the mimic relation,
and the line each element stands on, so that errors and diagnostics can point at it.
"""

import re
from typing import TYPE_CHECKING

from cspace._findings import Diagnostic
from cspace._formats.shared.pose import IDENTITY, Pose
from cspace._joint_kind import JointKind
from cspace._record import NamedTuple

if TYPE_CHECKING:  # a URDF without <ros2_control> does not import its records
    from cspace._ros2_control import ControlHardware


class MimicSpec(NamedTuple):
    """``joint = multiplier * leader + offset`` as written in the file.

    Attributes:
        joint: Name of the leader joint.
        multiplier: Dimensionless factor.
        offset: In the joint's units (rad or m).
    """

    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


class JointSpec(NamedTuple):
    """One joint as the file declares it.

    Attributes:
        name: The joint's name.
        type: The format's own word for the joint type (e.g. URDF ``revolute``, MJCF
            ``hinge``), for messages only.
        parent: Parent link name.
        child: Child link name.
        kind: What the joint is, in cspace's words: the reader translates its format's
            type into it, and nothing past the readers looks at ``type``.
        axis: Joint axis (x, y, z) as written (not normalised), or None when absent.
        lower: Lower position limits as written, one per limited coordinate (rad or m).
        upper: Upper position limits as written, same length as ``lower``.
        limits_defaulted: True when the limit element omits both bounds, so that the
            format's defaults (URDF: 0 and 0) were used.
        bounds_missing: The bounds (``"lower"``, ``"upper"``) the limit element omits and
            the format's default stands for.
        mimic: The mimic relation, or None.
        line: 1-based line of the joint's element, or None.
        limit_line: Line of its ``<limit>`` element, or None.
        axis_line: Line of its ``<axis>`` element, or None.
        origin: The joint frame in the parent link's frame when every joint is at zero,
            or None when the reader does not place it (then the model built from the
            reading has no kinematics, and `cspace.pinocchio_model` refuses it). The
            joint's axis (``JointToAdd.axis``) is expressed in this frame. A floating
            joint's origin is the identity: its value is the child's pose in the parent.
        child_in_joint: The child link's frame in the joint frame (URDF: the same
            frame, the identity; SDF: the inverse of the joint's pose in its child;
            OpenUSD: the inverse of the joint's frame in body1).
        rates: The ``<limit>``'s maximum effort and velocity as written (URDF:
            ``(("effort", e), ("velocity", v))``; a negative one is a finding), or ().
        soft: The ``<safety_controller>``'s ``soft_lower_limit`` and
            ``soft_upper_limit`` (URDF, 0 where not given, as urdfdom reads them), or None:
            MoveIt bounds the joint to them within its limits; Pinocchio ignores them.
    """

    name: str
    type: str
    parent: str
    child: str
    kind: JointKind
    axis: tuple[float, float, float] | None = None
    lower: tuple[float, ...] = ()
    upper: tuple[float, ...] = ()
    limits_defaulted: bool = False
    bounds_missing: tuple[str, ...] = ()
    mimic: MimicSpec | None = None
    line: int | None = None
    limit_line: int | None = None
    axis_line: int | None = None
    origin: Pose | None = None
    child_in_joint: Pose = IDENTITY
    rates: tuple[tuple[str, float], ...] = ()
    soft: tuple[float, float] | None = None

    @property
    def limited(self) -> bool:
        """True when the file gives position limits for every coordinate it limits."""
        return bool(self.lower) and len(self.lower) == len(self.upper)


class PoseSpec(NamedTuple):
    """A pose the file stores, as written (an MJCF keyframe's qpos).

    Attributes:
        name: Its name (``key<N>`` for an unnamed keyframe).
        source: ``keyframe``.
        line: Its line, or None.
        values: Each joint's values in canonical order (a quaternion w first), not yet
            wrapped or normalised: ``(joint, values)`` pairs.
    """

    name: str
    source: str
    line: int | None
    values: tuple[tuple[str, tuple[float, ...]], ...]


class CutSpec(NamedTuple):
    """A constraint that closes a kinematic loop: two frames, on two links, held together.

    The tree (`RobotDescription.joints`) is the mechanism with its loops cut open; each
    cut is one closing constraint. Its two frames coincide when the loop is closed, up to
    the motion ``free`` leaves: ``"rotation"`` (a ball joint, MJCF ``connect``: the
    origins coincide, 3 equations), ``"none"`` (a weld, a fixed joint: 6), ``"revolute"``
    (the origins coincide and the frames differ by a rotation about ``axis``: 5) or
    ``"prismatic"`` (the same orientation, the origins apart along ``axis``: 5).

    Attributes:
        kind: The constraint as the file names it (``connect``, ``weld``, ``ball``,
            ``revolute``, ``drake:ball_constraint``...), for messages and the report.
        name: Its name (the file's, or one made from its kind and index).
        link_a: The first link.
        frame_a: The constraint's frame in ``link_a``'s frame (m, unit quaternion).
        link_b: The second link.
        frame_b: The constraint's frame in ``link_b``'s frame.
        free: What the constraint leaves free: ``rotation``, ``none``, ``revolute``,
            ``prismatic``.
        axis: The free axis of a ``revolute`` or ``prismatic`` cut, a unit vector in
            ``frame_a``.
        line: 1-based line of its element, or None.
    """

    kind: str
    name: str
    link_a: str
    frame_a: Pose
    link_b: str
    frame_b: Pose
    free: str = "none"
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    line: int | None = None

    @property
    def rows(self) -> int:
        """How many scalar equations the constraint makes."""
        return CUT_ROWS[self.free]


CUT_ROWS = {"rotation": 3, "none": 6, "revolute": 5, "prismatic": 5}
"""Equations per cut, by what it leaves free (in 3-D)."""


COLLISION_KINDS = ("box", "sphere", "cylinder", "capsule", "mesh")
"""The collision shapes the readers keep."""


class CollisionSpec(NamedTuple):
    """One collision shape of a link, as the file writes it.

    Attributes:
        kind: ``box``, ``sphere``, ``cylinder``, ``capsule`` or ``mesh``.
        sizes: In m: a box's (x, y, z) edge lengths, a sphere's (radius,), a cylinder's
            or capsule's (radius, length) (the capsule's length between its caps'
            centres); () for a mesh.
        origin: The shape's frame in the link's frame.
        mesh: A mesh's file name as written (URDF ``filename``, SDF ``<uri>``), or None.
        scale: A mesh's scale on (x, y, z), (1, 1, 1) unless the file gives one.
        line: 1-based line of its ``<collision>`` element, or None.
    """

    kind: str
    sizes: tuple[float, ...] = ()
    origin: Pose = IDENTITY
    mesh: str | None = None
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    line: int | None = None


class LinkSpec(NamedTuple):
    """One link (body) as the file declares it.

    Attributes:
        name: The link's name.
        line: 1-based line of the link's element, or None.
        collisions: Its collision shapes, in file order (those of a URDF or an SDF file).
        unread: The collision elements the reader could not read, as ``(line,
            problem)``. A URDF link with one has no ``collisions``, as Pinocchio's URDF
            parser gives it none (printing an error and going on).
    """

    name: str
    line: int | None = None
    collisions: tuple[CollisionSpec, ...] = ()
    unread: tuple[tuple[int | None, str], ...] = ()


class RobotDescription:
    """A whole robot file, checked for structure, joints in tree order.

    An immutable value, equal to another of the same fields; `replace` makes a changed
    copy.

    Attributes:
        name: The robot's name (empty when the file gives none).
        format: The format's name in `cspace._formats.table.FORMATS` (``"urdf"``, ...).
        root_link: The one link without a parent.
        links: Every link, in file order.
        joints: Every joint (fixed ones included), depth-first from the root link,
            siblings in the order Pinocchio visits them (by name, for URDF).
        findings: What the format reader itself found (e.g. a non-finite number in an
            element the C-space does not depend on), in file order.
        cuts: The constraints that close kinematic loops (none for a tree), in file
            order; ``joints`` is the tree they cut open.
        actuated: The joints the file drives (MJCF actuators' joints, URDF
            transmissions' joints), in file order.
        ros2_control: A URDF's ``<ros2_control>`` hardware components, in file order.
    """

    # Written out rather than a frozen dataclass: defining one costs every start-up a
    # millisecond, and nothing on a URDF's path needs `dataclasses` otherwise.
    __slots__ = (
        "_by_name",
        "actuated",
        "cuts",
        "findings",
        "format",
        "joints",
        "links",
        "name",
        "root_link",
        "ros2_control",
    )
    name: str
    format: str
    root_link: str
    links: tuple[LinkSpec, ...]
    joints: tuple[JointSpec, ...]
    findings: tuple[Diagnostic, ...]
    cuts: tuple[CutSpec, ...]
    actuated: tuple[str, ...]
    ros2_control: "tuple[ControlHardware, ...]"
    _by_name: dict[str, JointSpec]

    def __init__(
        self,
        name: str,
        format: str,
        root_link: str,
        links: tuple[LinkSpec, ...],
        joints: tuple[JointSpec, ...],
        findings: tuple[Diagnostic, ...] = (),
        cuts: tuple[CutSpec, ...] = (),
        actuated: tuple[str, ...] = (),
        ros2_control: "tuple[ControlHardware, ...]" = (),
    ) -> None:
        by_name = {j.name: j for j in joints}
        fields = (name, format, root_link, links, joints, findings, cuts, actuated, ros2_control)
        for slot, value in zip(self._FIELDS, (*fields, by_name), strict=True):
            object.__setattr__(self, slot, value)

    _FIELDS = (
        "name",
        "format",
        "root_link",
        "links",
        "joints",
        "findings",
        "cuts",
        "actuated",
        "ros2_control",
        "_by_name",
    )

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"cannot assign to {name!r}: a description is immutable")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"cannot delete {name!r}: a description is immutable")

    def _key(self) -> tuple[object, ...]:
        fields = (self.name, self.format, self.root_link, self.links, self.joints)
        return (*fields, self.findings, self.cuts, self.actuated, self.ros2_control)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        return (
            f"RobotDescription(name={self.name!r}, format={self.format!r}, "
            f"root_link={self.root_link!r}, links={self.links!r}, joints={self.joints!r}, "
            f"findings={self.findings!r}, cuts={self.cuts!r}, actuated={self.actuated!r}, "
            f"ros2_control={self.ros2_control!r})"
        )

    def replace(
        self,
        *,
        name: str | None = None,
        format: str | None = None,
        root_link: str | None = None,
        links: tuple[LinkSpec, ...] | None = None,
        joints: tuple[JointSpec, ...] | None = None,
        findings: tuple[Diagnostic, ...] | None = None,
        cuts: tuple[CutSpec, ...] | None = None,
        actuated: tuple[str, ...] | None = None,
        ros2_control: "tuple[ControlHardware, ...] | None" = None,
    ) -> "RobotDescription":
        """A copy with the fields given changed (the index of joints made anew)."""
        return RobotDescription(
            self.name if name is None else name,
            self.format if format is None else format,
            self.root_link if root_link is None else root_link,
            self.links if links is None else links,
            self.joints if joints is None else joints,
            self.findings if findings is None else findings,
            self.cuts if cuts is None else cuts,
            self.actuated if actuated is None else actuated,
            self.ros2_control if ros2_control is None else ros2_control,
        )

    def joint(self, name: str) -> JointSpec | None:
        """The joint called ``name``, or None."""
        return self._by_name.get(name)

    def locate(self, message: str) -> tuple[int | None, str | None]:
        """The line and name of the joint or link a parser's message names, if any.

        Recognises the forms Pinocchio's parsers use: ``joint [NAME]``, ``Link [NAME]``,
        ``link 'NAME'`` (any case).

        Returns:
            (line, name), or (None, None) when the message names no known element.
        """
        links = {link.name: link.line for link in self.links}
        for match in re.finditer(_NAMED, message, re.IGNORECASE):
            kind, name = match.group(1).lower(), match.group(2) or match.group(3)
            if kind == "joint" and name in self._by_name:
                return self._by_name[name].line, name
            if kind == "link" and name in links:
                return links[name], name
        return None, None


_NAMED = r"\b(joint|link)\s*(?:\[([^\]]*)\]|'([^']*)')"
"""Compiled on first use (through `re`'s cache): only a parser's error needs it."""


class JointToAdd(NamedTuple):
    """One joint of a model that `cspace` assembles through Pinocchio's model API.

    Attributes:
        name: Joint name.
        parent: The nearest moving ancestor joint's name, or None for the root.
        model: ``revolute``, ``continuous``, ``prismatic``, ``helical``, ``spherical``,
            ``universal`` or ``floating``.
        axis: Unit axis (x, y, z), in the joint frame (`JointSpec.origin`).
        axis2: Second axis of a universal joint, in the joint frame.
        pitch: Helical pitch (m per rad).
        placement: The joint frame in the frame of the moving joint above it (the
            world's for the root) when every joint is at zero; `joint_list` sets it.
    """

    name: str
    parent: str | None
    model: str
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    axis2: tuple[float, float, float] = (0.0, 1.0, 0.0)
    pitch: float = 0.0
    placement: Pose = IDENTITY
