"""The one reader contract: what every format reader gives the model layer.

A reader turns a file's bytes into a `Reading`: the format-free description
(joints in cspace's words, limits as written, lines, the reader's own findings) and a
recipe saying how Pinocchio should build the model. The recipe is one of three, by what
the format needs:

- `UrdfText`: a URDF document for Pinocchio's own URDF parser (URDF and
  expanded xacro);
- `JointList`: moving joints and link frames to assemble through Pinocchio's model
  API (SDF and OpenUSD, whose parsers this Pinocchio lacks);
- `KinematicTree`: bodies and joints with their
  frames, from MuJoCo's compiled model (MJCF).

`build` takes any reading; nothing else in the model layer
asks which format a robot came from.
"""

import os
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from cspace._formats.shared.description import JointToAdd, PoseSpec, RobotDescription
from cspace._formats.shared.kinematic_tree import KinematicTree
from cspace._formats.shared.pose import IDENTITY, Pose, compose
from cspace._record import NamedTuple

if TYPE_CHECKING:
    from cspace._actuators import Actuator
    from cspace._formats.shared.xmlio import ReadBudget, SourceFile
    from cspace._formats.table import Format


class UrdfText(NamedTuple):
    """A URDF document for Pinocchio's URDF parser.

    Attributes:
        text: The document: the file as read, with what Pinocchio's parser would refuse
            but the report can still describe rewritten.
    """

    text: str


class LinkFrame(NamedTuple):
    """Where a link is, in the frame of the moving joint that carries it.

    Attributes:
        name: The link's name.
        joint: The moving joint that carries it, or None for the world's.
        pose: The link's frame in that joint's frame.
        via: The fixed joint it hangs from, or None (the link of a moving joint, or
            the root).
    """

    name: str
    joint: str | None
    pose: Pose
    via: str | None = None


class JointList(NamedTuple):
    """Moving joints to assemble through Pinocchio's model API, each after its parent.

    Attributes:
        joints: The joints, each placed in the frame of the moving joint above it.
        links: Every link, placed in its carrying joint's frame.
        unplaced: Why the joints cannot be placed (a joint the reader left without an
            origin), or None: then the model is for the configuration space only, and
            `cspace.pinocchio_model` refuses it.
    """

    joints: tuple[JointToAdd, ...]
    links: tuple[LinkFrame, ...] = ()
    unplaced: str | None = None


Recipe = UrdfText | JointList | KinematicTree
"""How Pinocchio builds a reading's model."""


class Reading(NamedTuple):
    """What a format reader found.

    Attributes:
        description: The checked description, joints in the order Pinocchio's model
            will have them.
        recipe: How to build the Pinocchio model.
        addresses: For MJCF, each moving joint's MuJoCo ``(qposadr, dofadr, type)`` by name;
            None for other formats.
        poses: The poses the file stores (MJCF keyframes that write qpos).
        path: The name messages give the robot when it is not the file's (xacro's
            output: ``"robot.xacro (expanded by xacro)"``), or None.
        actuators: MJCF: each actuator, in ctrl order (none for other formats).
        geometry: MJCF: the collision geometry and contact filters MuJoCo compiled
            (`cspace._formats.mjcf._geometry.MjcfGeometry`); None for other formats.
    """

    description: RobotDescription
    recipe: Recipe
    addresses: Mapping[str, tuple[int, int, str]] | None = None
    poses: tuple[PoseSpec, ...] = ()
    path: str | None = None
    actuators: "tuple[Actuator, ...]" = ()
    geometry: Any = None


def _nothing() -> None:
    """Nothing to do while a reader's child works."""


class ReadRequest(NamedTuple):
    """What a format reader is given: the file, read once, and what it may read besides.

    Attributes:
        path: The file as the user named it, for messages (``-`` for standard input).
        source: The file's bytes, read once (`shared.xmlio.read_source`).
        root: Its parsed root element (an XML format), or None (a format told by bytes).
        on_disk: The file on disk, or None (standard input).
        budget: The run's budget, charged with the file: every other file the reader
            reads (includes, xacro's output) is charged to it.
        allow_dirs: Folders, besides the file's own, that the files it reads may come from.
        options: Options of the format's own (xacro's `XacroOptions`), or None.
        named_srdf: The file's name says SRDF (`roots.named_srdf`): a reader that makes
            a new document (xacro) refuses an SRDF in it as the loader refuses one.
        meanwhile: Called by a reader whose work runs in a child process once the child
            has it (MuJoCo's compiler), so that the parent does its own work meanwhile.
    """

    path: str
    source: "SourceFile"
    root: Any
    on_disk: str | None
    budget: "ReadBudget"
    allow_dirs: Sequence[str | os.PathLike[str]] = ()
    options: Any = None
    named_srdf: bool = False
    meanwhile: Callable[[], None] = _nothing


def read(row: "Format", request: ReadRequest) -> Reading:
    """Read ``request``'s file with the reader of format ``row`` (imported now)."""
    import importlib

    result: Reading = importlib.import_module(row.reader).read(request)
    return result


def joint_list(description: RobotDescription, to_add: Mapping[str, JointToAdd]) -> JointList:
    """The moving joints to assemble, in tree order, each under the moving joint above it.

    Fixed joints are frames, not joints: a joint below one hangs from the moving joint
    above that, placed through it.

    Args:
        description: The checked description (joints depth-first from the root link).
        to_add: Each moving joint's model, by name (fixed joints have none).
    """
    carried: dict[str, tuple[str | None, Pose]] = {description.root_link: (None, IDENTITY)}
    links = [LinkFrame(description.root_link, None, IDENTITY)]
    ordered: list[JointToAdd] = []
    unplaced = None
    for spec in description.joints:
        above, parent_pose = carried[spec.parent]
        if spec.origin is None and unplaced is None:
            at = "" if spec.line is None else f" (line {spec.line})"
            unplaced = f"joint '{spec.name}'{at} has no placement"
        joint_pose = compose(parent_pose, spec.origin or IDENTITY)
        add = to_add.get(spec.name)
        if add is None:
            carried[spec.child] = (above, compose(joint_pose, spec.child_in_joint))
            links.append(LinkFrame(spec.child, above, carried[spec.child][1], spec.name))
        else:
            ordered.append(add._replace(parent=above, placement=joint_pose))
            carried[spec.child] = (spec.name, spec.child_in_joint)
            links.append(LinkFrame(spec.child, spec.name, spec.child_in_joint))
    return JointList(tuple(ordered), tuple(links), unplaced)
