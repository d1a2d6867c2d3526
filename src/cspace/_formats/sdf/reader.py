"""The SDF (SDFormat) reader: an ``<sdf>`` document's model to a `Reading`.

The Pinocchio wheels on PyPI are built without SDFormat, so `cspace` reads the file
itself and assembles the Pinocchio model joint by joint through Pinocchio's model API
(`build_model`): the joint models and the q/v layout are still Pinocchio's. Each joint
is placed where the file's poses put it, as libsdformat resolves them for Drake
(`sdf._poses`: ``relative_to``, frames, nested models, placement frames, each
version's rules), its axes turned into its own frame; a joint whose pose the file does
not resolve is left unplaced, and `cspace.pinocchio_model` refuses the model.

SDF conventions kept here: ``<axis><xyz>`` defaults to (0, 0, 1); a limit bound that
is missing, or whose magnitude is 1e16 or more (SDF's default), means "no limit", so a
``revolute`` joint without finite limits turns freely (S^1), like ``continuous``; with
one bound given it is an interval up to SDF's default for the other (R); a
``universal`` (or ``revolute2``) joint has two rotation axes, ``<axis>`` and ``<axis2>``;
``screw`` is helical (R), ``<screw_thread_pitch>`` m per turn (right-handed) or the
older ``<thread_pitch>`` rad per m (left-handed), 1 m per turn by default, as
libsdformat reads them; the parent link ``world`` is the world.
"""

from __future__ import annotations

import math
from typing import NoReturn

from lxml import etree

from cspace._findings import Diagnostic, finding
from cspace._formats.sdf._collision import read_link
from cspace._formats.sdf._loops import ball_constraints, ball_cut, limits_left, loop_cut
from cspace._formats.sdf._poses import PoseGraph
from cspace._formats.sdf._scene import WORLD, SdfJoint, SdfLink, child_text, read_scene
from cspace._formats.shared.collisions import CollisionCounter
from cspace._formats.shared.description import JointSpec, JointToAdd, LinkSpec
from cspace._formats.shared.loops import spanning_tree
from cspace._formats.shared.pose import IDENTITY
from cspace._formats.shared.reading import Reading, ReadRequest, joint_list
from cspace._formats.shared.robot_size import check_count, check_cuts
from cspace._formats.shared.structure import build_checked, build_description, read_each
from cspace._formats.shared.xmlio import check_joint_type, fail_at, line_of
from cspace._formats.urdf.numbers import parse_number
from cspace._joint_kind import JointKind
from cspace.errors import InvalidElementError, RobotFileError

SDF_JOINT_TYPES = (
    "revolute",
    "continuous",
    "prismatic",
    "ball",
    "universal",
    "revolute2",
    "screw",
    "fixed",
    "gearbox",
)
"""The joint types SDFormat defines."""

_MODELS = {
    "revolute": "revolute",
    "continuous": "continuous",
    "prismatic": "prismatic",
    "ball": "spherical",
    "universal": "universal",
    "revolute2": "universal",
    "screw": "helical",
}
"""SDF joint type -> the joint model `cspace` asks Pinocchio for."""

_LIMITABLE = ("revolute", "prismatic", "screw", "universal", "revolute2")

SDF_KINDS = {
    "revolute": JointKind.REVOLUTE,
    "continuous": JointKind.CONTINUOUS,
    "prismatic": JointKind.PRISMATIC,
    "ball": JointKind.SPHERICAL,
    "universal": JointKind.UNIVERSAL,
    "revolute2": JointKind.UNIVERSAL,
    "screw": JointKind.HELICAL,
    "fixed": JointKind.FIXED,
}
"""Each SDF joint type cspace reads, in cspace's words."""

NO_LIMIT = 1e16
"""SDF's default limit magnitude: a bound this large is no bound."""


class _Reader:
    def __init__(self, path: str) -> None:
        self.path = path

    def fail(self, code: str, problem: str, element: etree._Element) -> NoReturn:
        fail_at(self.path, code, problem, element)

    def text(self, element: etree._Element, tag: str, owner: str) -> str:
        value = child_text(element, tag)
        if not value:
            self.fail("missing-element", f"{owner} has no <{tag}>", element)
        return value

    def numbers(self, element: etree._Element, tag: str, count: int, owner: str) -> list[float]:
        child = element.find(tag)
        if child is None:
            return []
        text = child.text or ""
        try:
            values = [float(x) for x in text.split()]
        except ValueError:
            values = []
        if len(values) != count:
            self.fail("bad-number", f"{owner}: <{tag}>{text}</{tag}> is not {count} numbers", child)
        return values

    def axis(
        self, joint: etree._Element, tag: str, owner: str
    ) -> tuple[tuple[float, float, float], tuple[float, float]]:
        """The axis (unit as written) and its limits (lower, upper; +-inf when absent)."""
        element = joint.find(tag)
        if element is None:
            return (0.0, 0.0, 1.0), (-math.inf, math.inf)
        xyz = self.numbers(element, "xyz", 3, f"{owner} <{tag}>") or [0.0, 0.0, 1.0]
        limit = element.find("limit")
        bounds = [-math.inf, math.inf]
        if limit is not None:
            for k, key in enumerate(("lower", "upper")):
                found = self.numbers(limit, key, 1, f"{owner} <{tag}><limit>")
                if found and abs(found[0]) < NO_LIMIT:
                    bounds[k] = found[0]
        return (xyz[0], xyz[1], xyz[2]), (bounds[0], bounds[1])

    def joint(self, joint: SdfJoint) -> tuple[JointSpec, JointToAdd | None]:
        element, name = joint.element, joint.name
        owner = f"joint '{name}'"
        joint_type = element.get("type", "").strip()
        check_joint_type(self.path, name, joint_type, SDF_JOINT_TYPES, element)
        if joint_type == "gearbox":
            self.fail(
                "unsupported-joint-type",
                f"{owner} is a gearbox, which cspace does not model",
                element,
            )
        self.text(element, "parent", owner)
        self.text(element, "child", owner)
        if joint.static and joint_type != "fixed":
            self.fail(
                "moving-joint-in-static-model",
                f"{owner} is a {joint_type} joint in a static model: SDFormat makes a "
                "static model immovable, and Drake refuses any joint in it but a fixed one",
                element,
            )
        if joint.of_world and joint_type != "fixed":
            self.fail(
                "moving-world-joint",
                f"{owner} is a {joint_type} joint of the <world> itself: Drake reads only "
                "fixed ones there; put a moving joint in a model",
                element,
            )
        parent, child = joint.parent, joint.child
        axis, (low, high) = self.axis(element, "axis", owner)
        axis2, (low2, high2) = self.axis(element, "axis2", owner)
        lower: tuple[float, ...] = ()
        upper: tuple[float, ...] = ()
        two_axes = joint_type in ("universal", "revolute2")
        finite = [math.isfinite(x) for x in ((low, high, low2, high2) if two_axes else (low, high))]
        if two_axes and any(finite) and not all(finite):
            self.fail(
                "unsupported-limits",
                f"{owner} limits only some of its two axes; cspace reports a universal "
                "joint with both axes limited (R^2) or neither (T^2)",
                element,
            )
        if joint_type in _LIMITABLE and two_axes and all(finite):
            lower, upper = (low, low2), (high, high2)
        elif joint_type in _LIMITABLE and any(finite):
            # One bound given: the other is SDF's default, -1e16 or 1e16 (an interval).
            lower = (low if math.isfinite(low) else -NO_LIMIT,)
            upper = (high if math.isfinite(high) else NO_LIMIT,)
        spec = JointSpec(
            name=name,
            type=joint_type,
            parent=parent,
            child=child,
            kind=SDF_KINDS[joint_type],
            axis=None if joint_type in ("ball", "fixed") else axis,
            lower=lower,
            upper=upper,
            line=line_of(element),
            limit_line=line_of(element.find("axis/limit")),
            axis_line=line_of(element.find("axis")),
        )
        if joint_type == "fixed":
            return spec, None
        self.numbers(element, "thread_pitch", 1, owner)  # a malformed one is a bad-number
        model = _MODELS[joint_type]
        if model == "revolute" and not lower:
            model = "continuous"
        pitch = _pitch(element)
        add = JointToAdd(
            name, None, model, _unit(axis), _unit(axis2), DEFAULT_PITCH if pitch is None else pitch
        )
        return spec, add


DEFAULT_PITCH = 1 / (2 * math.pi)
"""SDFormat's screw pitch when a joint gives none: 1 m per turn, in m per rad."""


def _pitch(joint: etree._Element) -> float | None:
    """A screw joint's pitch in m per rad, as libsdformat reads it for Drake.

    ``<screw_thread_pitch>`` is m per turn, right-handed; the older ``<thread_pitch>``
    rad per m, left-handed. None when the one given is not a finite number.
    """
    if joint.find("screw_thread_pitch") is not None:
        per_turn = parse_number(child_text(joint, "screw_thread_pitch"))
    elif joint.find("thread_pitch") is not None:
        per_m = parse_number(child_text(joint, "thread_pitch"))
        per_turn = -2 * math.pi / per_m if per_m else None
    else:
        per_turn = 1.0
    if per_turn is None or not math.isfinite(per_turn):
        return None
    return per_turn / (2 * math.pi)


def _unit(axis: tuple[float, float, float]) -> tuple[float, float, float]:
    norm = math.hypot(*axis)  # scaled: no overflow or underflow
    if not math.isfinite(norm) or norm == 0.0:
        return (0.0, 0.0, 1.0)  # the axis-invalid finding reports it
    return (axis[0] / norm, axis[1] / norm, axis[2] / norm)


def read_sdf(path: str, root: etree._Element) -> Reading:
    """Read an SDF document's models, as SDFormat and Drake read them.

    A link that no joint holds floats, unless its model is static: SDFormat simulates it
    free, and Drake gives it a floating joint. cspace adds that joint (named after the
    link, as Drake names it) with a ``sdf-link-floats`` finding; its value is the link's
    pose in the world. A static model's links are welded to the world where their poses
    put them (a fixed joint ``world_to_<link>``, unless the only one is at the world's
    origin). A world of several models is one robot of them all, each model's names
    prefixed with its own (``arm::shoulder``).

    Every joint is placed as the file's poses place it (`JointSpec.origin`,
    `JointSpec.child_in_joint`, its axes in its own frame), or left unplaced when they
    do not resolve (`sdf._poses`); the C-space is the same either way.

    Args:
        path: The file, for messages.
        root: The parsed ``<sdf>`` element.

    Returns:
        The checked description and the joints to assemble, parents first, each placed
        in the one above it, with every link's frame (a `JointList`).

    Raises:
        NotARobotError: The document holds no model.
        InvalidElementError: A missing element, a malformed number, an unsupported part.
        UnknownJointTypeError: A joint type SDFormat does not define.
        RobotStructureError: The links and joints do not form one tree.
    """
    reader = _Reader(path)
    scene = read_scene(path, root)
    balls = ball_constraints(scene)
    check_count(path, "SDF joints", len(scene.joints), line_of(scene.element))
    check_cuts(path, len(balls), line_of(scene.element))
    problems: list[RobotFileError] = []  # every element's, reported together
    pairs = read_each(scene.joints, reader.joint, problems)
    everything = [spec for spec, _ in pairs]
    tree, loops = spanning_tree(everything, [link.name for link in scene.links], WORLD)
    check_cuts(path, len(loops) + len(balls), line_of(scene.element))
    kept = {id(spec) for spec in tree}
    pairs = [pair for pair in pairs if id(pair[0]) in kept]
    specs = [spec for spec, _ in pairs]
    held = {spec.child for spec in specs}
    free = [link for link in scene.links if link.name not in held]
    used = {spec.name for spec in specs}
    added: list[tuple[JointSpec, JointToAdd | None]] = []
    floating = [link for link in free if not link.static]
    welded = [link for link in free if link.static]
    graph = PoseGraph(scene, root)
    counter = CollisionCounter(path)
    links = [read_link(link, graph, counter) for link in scene.links]
    needs_world = (
        bool(floating)
        or len(free) > 1
        or any(WORLD in (s.parent, s.child) for s in everything)
        or any(graph.link(link) != IDENTITY for link in welded)  # Drake welds it where it is
    )
    for link in floating + (welded if needs_world else []):
        name = _unused(link.name if not link.static else f"world_to_{link.name}", used)
        kind = JointKind.FIXED if link.static else JointKind.FLOATING
        line = line_of(link.element)
        spec = JointSpec(
            name,
            "floating" if kind is JointKind.FLOATING else "fixed",
            WORLD,
            link.name,
            kind,
            line=line,
            origin=graph.link(link) if link.static else IDENTITY,  # floating: q is its pose
        )
        added.append((spec, None if link.static else JointToAdd(name, None, "floating")))
    if needs_world and all(link.name != WORLD for link in scene.links):
        links.insert(0, LinkSpec(WORLD, line_of(scene.element)))
    by_name = {joint.name: joint for joint in scene.joints}
    pairs = added + [_placed(graph, by_name[spec.name], spec, add) for spec, add in pairs]
    names = {link.name for link in scene.links}
    cuts = read_each(
        loops, lambda loop: loop_cut(path, graph, by_name[loop[0].name], *loop), problems
    )
    cuts += read_each(
        enumerate(balls), lambda ball: ball_cut(path, *ball[1], ball[0], names), problems
    )
    if cuts:
        _check_placed(path, [spec for spec, _ in pairs])
    description = build_checked(
        problems,
        lambda: build_description(
            path,
            name=scene.name,
            format="sdf",
            links=links,
            joints=[spec for spec, _ in pairs],
        ),
    )
    if cuts:
        limited = [limits_left(spec) for spec, _ in loops if spec.limited]
        description = description.replace(
            cuts=tuple(cuts), findings=(*description.findings, *limited)
        )
    if floating:
        description = description.replace(
            findings=(*description.findings, _floats(floating, added))
        )
    from cspace._formats.sdf._initial import initial_pose

    pose, said = initial_pose(specs, {j.name: j.element for j in scene.joints})
    if said:
        description = description.replace(findings=(*description.findings, *said))
    to_add = {spec.name: add for spec, add in pairs if add is not None}
    poses = () if pose is None else (pose,)
    return Reading(description, joint_list(description, to_add), poses=poses)


def _placed(
    graph: PoseGraph, joint: SdfJoint, spec: JointSpec, add: JointToAdd | None
) -> tuple[JointSpec, JointToAdd | None]:
    """The joint where the file puts it, its axes in its own frame; unplaced if unresolved."""
    tags = ("axis", "axis2") if spec.kind is JointKind.UNIVERSAL else ("axis",)
    written = () if add is None or spec.axis is None else (add.axis, add.axis2)
    placed = graph.joint(joint, tuple(zip(tags, written, strict=False)))
    if placed is None or (spec.kind is JointKind.HELICAL and _pitch(joint.element) is None):
        return spec, add
    spec = spec._replace(origin=placed.origin, child_in_joint=placed.child_in_joint)
    if add is not None and placed.axes:
        turned = [_unit(axis) for axis in placed.axes]
        add = add._replace(axis=turned[0], axis2=turned[1] if len(turned) > 1 else add.axis2)
    return spec, add


def _check_placed(path: str, specs: list[JointSpec]) -> None:
    """Refuse a mechanism with loops whose tree has a joint the poses do not place.

    Raises:
        InvalidElementError: ``loop-not-placed``, at the first such joint: without its
            frames the loops cannot be closed, and the closure would be wrong.
    """
    for spec in specs:
        if spec.origin is None:
            raise InvalidElementError(
                path,
                f"joint '{spec.name}' is on a mechanism with kinematic loops, and its pose "
                "does not resolve as SDFormat defines (a relative_to or expressed_in naming "
                "no frame, a malformed <pose>, an unknown version): cspace cannot say where "
                "the loops close",
                code="loop-not-placed",
                line=spec.line,
                element=spec.name,
            )


def _unused(name: str, used: set[str]) -> str:
    """``name``, or ``_name``, ``__name`` ...: the first no joint has (as Drake does)."""
    while name in used:
        name = f"_{name}"
    used.add(name)
    return name


def _floats(links: list[SdfLink], added: list[tuple[JointSpec, JointToAdd | None]]) -> Diagnostic:
    names = [spec.name for spec, add in added if add is not None]
    shown = ", ".join(f"'{n}'" for n in names[:10]) + (
        f" and {len(names) - 10:,} more" if len(names) > 10 else ""
    )
    return finding(
        "sdf-link-floats",
        names[0],
        f"{len(links):,} link(s) of a model that is not static have no joint to the world: "
        f"SDFormat lets them float (Drake adds a floating joint), and so does cspace "
        f"({shown}); to bolt one down, mark its model <static>true</static> or add a "
        "fixed joint from 'world'",
        line_of(links[0].element),
    )


def read(request: ReadRequest) -> Reading:
    """Read the SDF file ``request`` names (the format's reader; see `read_sdf`)."""
    return read_sdf(request.path, request.root)
