"""A robot made ready for ``cspace collisions``: its shapes, pairs and the file's matrix.

`prepare` reads the robot file as ``inspect`` does (its report gives the C-space the
samples are drawn from and the poses it stores), finds and reads the meshes of its
collision shapes (`read_shape_meshes`; MJCF's geoms as MuJoCo compiles them), leaves
out the links whose shapes cannot all be had (a `collision-skipped` finding each), and
reads what the robot's files say of each link pair: an SRDF's ``<disable_collisions>``,
``<enable_collisions>`` and ``<disable_default_collisions>`` as MoveIt's allowed
collision matrix applies them, MuJoCo's contact filters, or PhysX's collision filters
of an OpenUSD stage.
"""

import math
import os
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.meshes._bounds import Mesh
from cspace._formats.shared.description import JointSpec, LinkSpec
from cspace._model._collision_pairs import (
    MAX_DOFS,
    MAX_SHAPE_PAIRS,
    LinkPair,
    SelfCollision,
    adjacent_pairs,
    link_pair,
)
from cspace._model._collision_shapes import (
    MeshKey,
    Shapes,
    TooManyShapes,
    build_shapes,
    check_shape_count,
    mesh_key,
)
from cspace._model.options import LoadOptions
from cspace._record import NamedTuple
from cspace._reports.collisions import FileRule
from cspace._reports.report import Report
from cspace.errors import RobotFileError, RobotStructureError, XacroError
from cspace.space._collisions.tally import Sampler

MAX_CHECKED_TRIANGLES = 2_000_000
"""Most triangles of meshes a robot's collision shapes are built of (coal's BVH costs about
575 bytes a triangle: 1.2 GB). example-robot-data's romeo, the largest, has 105,000."""

MAX_FINDINGS = 200
"""Most findings of one kind about one file's elements (unknown links, skipped links)."""


class Prepared(NamedTuple):
    """A robot ready to be sampled.

    Attributes:
        report: Its ``inspect`` report.
        file: The robot file on disk.
        shapes: Its collision shapes.
        pairs: Every pair of links with shapes, sorted.
        engine: The checker of the pairs sampled (`engine.pairs`): every pair but the
            adjacent ones the file's matrix does not check (as MoveIt's setup assistant,
            which samples no adjacent pair: they cost most, their meshes overlapping).
        adjacent: The adjacent pairs.
        default: The pairs in collision at MoveIt's default configuration.
        rules: What the file's matrix says of each pair, or None (no file says).
        matrix: ``srdf``, ``mjcf``, ``usd`` (PhysX's collision filters) or ``none``.
        srdf: The SRDF read, or None.
        sampler: The robot's seeded samples (within MoveIt's bounds, `moveit_limits`).
        findings: What was found while getting ready (skipped links, unknown links).
    """

    report: Report
    file: str
    shapes: Shapes
    pairs: tuple[LinkPair, ...]
    engine: SelfCollision
    adjacent: frozenset[LinkPair]
    default: frozenset[LinkPair]
    rules: "dict[LinkPair, FileRule] | None"
    matrix: str
    srdf: str | None
    sampler: Sampler
    findings: tuple[Diagnostic, ...]

    def checked(self, pair: LinkPair) -> bool:
        """Whether the file's matrix checks ``pair`` (no file: every pair but adjacent)."""
        return _checked(self.rules, self.adjacent, pair)


def _checked(
    rules: "dict[LinkPair, FileRule] | None", adjacent: frozenset[LinkPair], pair: LinkPair
) -> bool:
    """Whether ``rules`` check ``pair`` (None: every pair but adjacent ones)."""
    if rules is None:
        return pair not in adjacent
    rule = rules.get(pair)
    return True if rule is None else rule.checked


def prepare(path: str | os.PathLike[str], options: LoadOptions) -> Prepared:
    """Read the robot at ``path`` and make it ready to be sampled (see the module).

    Raises:
        RobotFileError: The robot file or its SRDF cannot be read.
        UnsupportedConfigurationError: A robot with closed loops (its samples would not
            close them).
    """
    from cspace._model.loader import built_and_report
    from cspace.space import ConfigurationSpace

    built, report, file = built_and_report(path, options)
    if report.closure is not None:
        raise RobotFileError(
            report.source.path,
            "cspace collisions samples trees: this robot has closed loops, which its samples "
            "would not close",
            code="collisions-loops",
        )
    model = built.model.pinocchio
    if model.nv > MAX_DOFS:  # before anything else is read: its Pinocchio data is nv^3
        raise RobotStructureError(
            report.source.path,
            f"the robot has {model.nv:,} degrees of freedom; cspace collisions samples robots "
            f"of at most {MAX_DOFS:,} (Pinocchio's data for its kinematics holds 32 nv^3 "
            "bytes: 11 GB at 700)",
            code="too-many-dofs",
        )
    description = built.reading.description
    findings: list[Diagnostic] = []
    only: dict[LinkPair, set[tuple[int, int]]] | None = None
    rules: dict[LinkPair, FileRule] | None = None
    matrix = "none"
    if built.format == "mjcf":
        mjcf = _mjcf(built, report.source.path)
        shapes, only = mjcf.shapes, {p: set(chosen) for p, chosen in mjcf.partial.items()}
        rules = {
            pair: FileRule(f.checked, f.reason, f.line, f.file) for pair, f in mjcf.filters.items()
        }
        matrix = "mjcf"
        findings += [
            finding("collision-skipped", None, f"body '{body}': {why}", line)
            for body, line, why in mjcf.problems[:MAX_FINDINGS]
        ]
        unread = {body for body, _, _ in mjcf.problems}
    else:
        try:  # before any mesh is read
            check_shape_count(sum(len(link.collisions) for link in description.links))
        except TooManyShapes as exc:
            raise RobotFileError(report.source.path, str(exc), code="too-many-elements") from None
        shapes, skipped, unread = _described_shapes(built, file, options, model)
        findings += skipped
    if built.format == "usd":
        from cspace._formats.usd.filters import collision_filters

        filtered = collision_filters(file, [os.fspath(d) for d in options.allow_dirs])
        rules = {pair: FileRule(False, why) for pair, why in filtered.pairs.items()}
        matrix = "usd"
        findings += [
            finding("collision-unknown-link", None, f"PhysX's collision filters: {problem}")
            for problem in filtered.problems[:MAX_FINDINGS]
        ]
    edges = [(j.parent, j.child) for j in description.joints]
    # a link left out still has geometry: adjacency does not look through it, as MoveIt's
    # (which reads its meshes) would not
    solid = [*shapes.with_geometry, *sorted(unread - set(shapes.with_geometry))]
    adjacent = frozenset(adjacent_pairs(solid, edges))
    links = shapes.with_geometry
    if len(links) * (len(links) - 1) // 2 > MAX_SHAPE_PAIRS:  # before the pairs are made
        raise _too_many(report.source.path, f"{len(links):,} links with collision shapes")
    pairs = sorted({link_pair(a, b) for i, a in enumerate(links) for b in links[i + 1 :]})
    if matrix == "usd" and rules is not None:  # PhysX collides every pair it does not filter
        rules = {pair: rules.get(pair, FileRule(True, None)) for pair in pairs}
    srdf_path = None
    if built.srdf is not None:
        from cspace.space._collisions.srdf import srdf_rules

        srdf_path = built.srdf.path
        rules, unknown = srdf_rules(built.srdf, pairs, [link.name for link in description.links])
        matrix = "srdf"
        findings += unknown
    elif built.srdf_note is not None:  # --srdf auto found none: where it looked
        findings.append(built.srdf_note)
    sampled = [p for p in pairs if p not in adjacent or _checked(rules, adjacent, p)]
    try:
        engine = SelfCollision(model, shapes, sampled, only)
    except ValueError as exc:
        raise _too_many(report.source.path, str(exc)) from None
    from cspace._model._collision_pairs import default_configuration

    space = ConfigurationSpace.from_report(report)
    moveit = moveit_limits(description.joints, space)
    at_default = engine.colliding(default_configuration(model, moveit))
    default = frozenset(engine.pairs[k] for k in at_default)
    wide = [  # no range a double holds (not finite, or limits of +-1e308), no MoveIt bounds
        c
        for c in space.coordinates
        if c.factor == "R^1" and not math.isfinite(c.upper - c.lower) and c.name not in moveit
    ]
    held = {c.name: (c.neutral, c.neutral) for c in wide if c.unit != "rad"}
    findings += _held(report, space, held)
    held |= {c.name: _one_turn(c.lower, c.upper) for c in wide if c.unit == "rad"}
    sampler = Sampler(space, held | moveit)
    return Prepared(
        report, file, shapes, tuple(pairs), engine, adjacent, default, rules, matrix,
        srdf_path, sampler, tuple(findings),
    )  # fmt: skip


def moveit_limits(joints: Iterable[JointSpec], space: Any) -> dict[str, tuple[float, float]]:
    """The bounds MoveIt's robot model gives the joints a ``<safety_controller>`` narrows.

    MoveIt's ``RobotModel`` bounds a URDF revolute or prismatic joint with a
    ``<safety_controller>`` to its soft limits within its limits (``jointBoundsFromURDF``;
    a soft limit not written is 0, as urdfdom reads it), and its setup assistant takes
    its default state and its random states within those bounds: so are the samples
    here. A joint whose soft limits leave no range within its limits keeps its limits.

    Args:
        joints: The description's joints.
        space: The robot's `ConfigurationSpace` (a joint of one coordinate is named by it).

    Returns:
        (lower, upper) by coordinate name, for the coordinates whose bounds MoveIt narrows.
    """
    from cspace._model._limits_file import moveit_bounds

    lines = {c.name: c for c in space.coordinates if c.factor == "R^1"}
    out: dict[str, tuple[float, float]] = {}
    for joint in joints:
        line = lines.get(joint.name)
        if joint.soft is None or line is None:
            continue
        narrowed = moveit_bounds(joint)
        if not narrowed.limited or len(narrowed.lower) != 1:
            continue
        low, high = narrowed.lower[0], narrowed.upper[0]
        if line.lower <= low <= high <= line.upper and (low, high) != (line.lower, line.upper):
            out[line.name] = (low, high)
    return out


def _one_turn(lower: float, upper: float) -> tuple[float, float]:
    """One turn within an angle's limits too far apart to sample: [-pi, pi] where it fits.

    Angles a turn apart place a link alike, so the turn samples every placement.
    """
    start = max(lower, -math.pi)
    if start + 2 * math.pi > upper:
        start = upper - 2 * math.pi
    return start, start + 2 * math.pi


def _held(report: Report, space: Any, held: dict[str, tuple[float, float]]) -> list[Diagnostic]:
    """A `collision-held` warning for each joint held but a floating or planar root's.

    A root's position does not change which links collide; an inner joint's does (a
    prismatic joint without limits; a floating or planar joint below another joint,
    whose position is held and whose rotation is sampled).
    """
    from cspace._joint_kind import JointKind

    children = {j.child_link for j in report.joints}
    turning = {j.name for j in report.joints if j.kind in (JointKind.FLOATING, JointKind.PLANAR)}
    roots = {j.name for j in report.joints if j.name in turning and j.parent_link not in children}
    joints = list(dict.fromkeys(c.joint for c in space.coordinates if c.name in held))
    return [
        finding(
            "collision-held",
            joint,
            f"joint '{joint}' has no finite range (limits not finite, or further apart "
            "than a double holds): cspace holds "
            + (
                "its position at its neutral value (its rotation is sampled), so the pairs "
                "its translation brings together are not sampled"
                if joint in turning
                else "it at its neutral value, so the pairs its motion brings together are "
                "not sampled"
            ),
        )
        for joint in [j for j in joints if j not in roots][:MAX_FINDINGS]
    ]


def _mjcf(built: Any, path: str) -> Any:
    """The MJCF robot's geoms and MuJoCo's filters (`mjcf_collision`), or its refusal.

    Raises:
        RobotFileError: More geoms than cspace reads of one model, or more collision
            geoms than it checks (``too-many-elements``).
        MujocoError: MuJoCo's compiler gave no geometry cspace can read.
    """
    from cspace._formats.mjcf._geom_facts import MAX_GEOMS
    from cspace._model._collision_mjcf import mjcf_collision
    from cspace.errors import MujocoError

    try:
        return mjcf_collision(built)
    except TooManyShapes as exc:  # (a ValueError)
        raise RobotFileError(path, str(exc), code="too-many-elements") from None
    except ValueError as exc:  # one line of the file's, not a bug
        if getattr(built.reading.geometry, "total", 0) > MAX_GEOMS:
            raise RobotFileError(path, str(exc), code="too-many-elements") from None
        raise MujocoError(path, str(exc)) from None


def _too_many(path: str, what: str) -> RobotFileError:
    """The refusal of a robot with more pairs of shapes than cspace checks."""
    return RobotFileError(
        path,
        f"{what}: more than the {MAX_SHAPE_PAIRS:,} pairs of collision shapes cspace checks",
        code="too-many-elements",
    )


def _described_shapes(
    built: Any, file: str, options: LoadOptions, model: Any
) -> tuple[Shapes, list[Diagnostic], set[str]]:
    """The shapes of a URDF's, xacro's, SDF's or OpenUSD's links, and the links left out.

    Returns:
        The shapes, a `collision-skipped` finding for each link left out, and their names.
    """
    from cspace._model._collision_meshes import read_shape_meshes

    links = built.reading.description.links
    packages = _packages(file, options)
    found = read_shape_meshes(links, file, packages, allow_dirs=options.allow_dirs)
    why: dict[str, tuple[int | None, str]] = {}
    for problem in found.problems:
        why.setdefault(problem.link, (problem.line, f"mesh '{problem.mesh}': {problem.problem}"))
    for link in links:
        for line, problem in link.unread:
            why.setdefault(link.name, (line, problem))
    _budget_triangles(links, found.meshes, why)
    kept = [link for link in links if link.name not in why]
    skipped = [
        finding(
            "collision-skipped",
            None,
            f"link '{name}': {problem}; its pairs are not checked",
            line,
        )
        for name, (line, problem) in list(why.items())[:MAX_FINDINGS]
    ]
    return build_shapes(model, kept, found.meshes), skipped, set(why)


def _budget_triangles(
    links: Sequence[LinkSpec],
    meshes: "Mapping[MeshKey, Mesh]",
    why: dict[str, tuple[int | None, str]],
) -> None:
    """Leave out (in ``why``) the links whose meshes pass `MAX_CHECKED_TRIANGLES`.

    Each mesh (built once, whatever the shapes naming it) is counted at its first shape,
    in the file's order; a link whose mesh passes the robot's budget is left out.
    """
    counted: set[MeshKey] = set()
    total = 0
    for link in links:
        for shape in link.collisions:
            key = mesh_key(shape)
            if shape.kind != "mesh" or key not in meshes or key in counted:
                continue
            counted.add(key)
            total += len(meshes[key].triangles)
            if total > MAX_CHECKED_TRIANGLES:
                why.setdefault(
                    link.name,
                    (
                        shape.line,
                        f"mesh '{shape.mesh}': its triangles pass the {MAX_CHECKED_TRIANGLES:,} "
                        "cspace checks for one robot (about 575 bytes each once built)",
                    ),
                )


def _packages(file: str, options: LoadOptions) -> dict[str, str]:
    """The ROS packages meshes may name: the robot file's own and ``--package-path``'s."""
    from cspace._formats.xacro.expand import ros_packages

    paths = () if options.xacro is None else options.xacro.package_paths
    try:
        return ros_packages(file, os.path.abspath(file), paths)[0]
    except XacroError:  # a package.xml naming no package: meshes name files, or lead nowhere
        return {}
