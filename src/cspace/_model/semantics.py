"""An SRDF read with a URDF: found, its virtual joint taken, its groups and states applied.

- `find_srdf`: the SRDF of a URDF's robot (``--srdf auto``), where ROS and MoveIt
  packages lay it out (beside the URDF, ``srdf/``, ``config/``, a sibling
  ``*_moveit_config`` package: `cspace._model._srdf_find`), only inside the folders
  cspace may read for the robot, links followed only inside them; `search` says where
  it looked, and `not_found` makes that a note of the report.
- `root_of`: the root joint the SRDF's virtual joint stands for (in place of
  ``--root-joint``).
- `with_srdf`: the report with the SRDF's groups, passive joints, checked states and
  poses.
- `group_report`: the report of one group's own C-space, the other joints held.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from cspace._findings import Diagnostic, finding
from cspace._formats.srdf.reader import Srdf
from cspace._joint_kind import JointKind
from cspace._joint_table import canonical_coordinates
from cspace._manifold import NormalForm
from cspace._model._root_advice import without_advice
from cspace._model._srdf_find import Search
from cspace._model._srdf_groups import resolve
from cspace._model._srdf_states import state_findings
from cspace._model.adapter import ROOT_JOINT_NAME
from cspace._reports.poses import GroupView, SrdfSummary, pick
from cspace._reports.report import Report
from cspace.errors import InvalidElementError


def find_srdf(
    file: str | os.PathLike[str] | None,
    robot: str | None = None,
    folders: Sequence[str] | None = None,
    *,
    name: str | None = None,
    parts: frozenset[str] = frozenset(),
) -> str | None:
    """The SRDF of the robot in the URDF ``file``, where its project lays it out, or None.

    See `cspace._model._srdf_find` for where it looks and which it takes: ``NAME.srdf``
    beside the URDF, in ``../srdf``, ``srdf/``, ``config/``, ``../config`` or a sibling
    ``*_moveit_config`` package, or an SRDF there that names the same robot (``name``),
    or one whose name begins the URDF's and that names only the robot's links and joints
    (``parts``). Only inside ``folders`` (real folders; default: `srdf_folders`), in no
    version-control folder, links followed only inside them: a candidate that leads
    outside is not looked at beyond the way there (`cspace._reach`), neither opened nor
    named. ``robot``: an ``erd:`` robot's name, whose SRDF example-robot-data names
    after the robot (``ur5.srdf`` for ``ur5_robot.urdf``). Without ``name`` and
    ``parts``, a URDF's are read from ``file`` itself (a xacro file's are not: only
    xacro knows them).
    """
    if file is None:
        return None
    if name is None and not parts:
        name, parts = _names_in(os.fspath(file))
    return search(os.fspath(file), robot, folders, name, parts).path


def _names_in(file: str) -> tuple[str | None, frozenset[str]]:
    """A URDF's ``<robot name>`` and the names of its links and joints, as written."""
    from cspace._formats.shared.xmlio import parse_xml, read_source

    if file.lower().endswith(".xacro"):
        return None, frozenset()
    root = parse_xml(read_source(file))
    if root.tag != "robot":
        return None, frozenset()
    named = root.iterchildren("link", "joint")
    return root.get("name"), frozenset(str(e.get("name")) for e in named if e.get("name"))


def search(
    file: str,
    robot: str | None = None,
    folders: Sequence[str] | None = None,
    name: str | None = None,
    parts: frozenset[str] = frozenset(),
) -> Search:
    """`find_srdf`, with where it looked and why it found none (`Search`)."""
    from cspace._model._srdf_find import search_srdf, srdf_folders

    allowed = srdf_folders(file) if folders is None else tuple(folders)
    return search_srdf(file, robot, allowed, name, parts)


def not_found(search: Search, file: str, name: str | None) -> Diagnostic:
    """The ``srdf-not-found`` note of a search that found none: where it looked."""
    from cspace._formats.shared.roots import file_stem

    robot = f"robot '{name}'" if name else "the robot"
    looked = ", ".join(search.looked) or "nowhere inside the robot's project"
    why = f" ({search.problem})" if search.problem else ""
    return finding(
        "srdf-not-found",
        None,
        f"--srdf auto found no SRDF of {robot} ({file_stem(file)}.srdf, or one naming the "
        f"robot){why}; looked in {looked}",
    )


def other_robot(srdf: Srdf, robot: str) -> Diagnostic:
    """The ``srdf-other-robot`` warning: the SRDF names a robot other than ``robot``.

    MoveIt and Pinocchio read such an SRDF without a word; its virtual joint, passive
    joints and groups were written for the robot it names, and shape this report.
    """
    return finding(
        "srdf-other-robot",
        None,
        f"the SRDF names robot '{srdf.robot}', and the URDF robot '{robot}': check that it "
        "is this robot's (its virtual joint and groups shape this report)",
        None,
        srdf.path,
    )


def root_of(
    srdf: Srdf, root_link: str, given: str | None, default: str | None
) -> tuple[str | None, str | None]:
    """The root joint to add, and the virtual joint's name (None when it has none).

    Args:
        srdf: The SRDF.
        root_link: The URDF's root link.
        given: ``--root-joint`` as the user gave it, or None.
        default: The root joint cspace would add otherwise (``erd:`` robots), or None.

    Raises:
        InvalidElementError: Two virtual joints hold the root link, or the one that does
            contradicts ``given`` (code ``srdf-virtual-joint``).
    """
    held = [v for v in srdf.virtual_joints if v.child_link == root_link]
    if not held:
        return given or default, None
    if len(held) > 1:
        raise InvalidElementError(
            srdf.path,
            f"virtual joints '{held[0].name}' and '{held[1].name}' both hold root link "
            f"'{root_link}'",
            line=held[1].line,
            element=held[1].name,
            code="srdf-virtual-joint",
        )
    virtual = held[0]
    root = None if virtual.type == "fixed" else virtual.type
    if given is not None and given != root:
        raise InvalidElementError(
            srdf.path,
            f"virtual joint '{virtual.name}' is {virtual.type}, and --root-joint asks for "
            f"{given}: give one of them",
            line=virtual.line,
            element=virtual.name,
            code="srdf-virtual-joint",
        )
    return root, virtual.name


def with_srdf(report: Report, srdf: Srdf, virtual: str | None) -> Report:
    """The report with what the SRDF says: groups, passive joints, states as poses."""
    resolved = resolve(srdf, report.joints, virtual if report.root_joint is not None else None)
    found, poses = state_findings(resolved, report.joints, report.coordinates)
    notes = [
        finding("srdf-ignored", None, problem, line, srdf.path) for line, problem in srdf.notes
    ]
    notes += [
        finding(
            "srdf-ignored",
            None,
            f"virtual joint '{v.name}' holds link '{v.child_link}', not the root link "
            "(MoveIt reads only the root's)",
            v.line,
            srdf.path,
        )
        for v in srdf.virtual_joints
        if v.name != virtual
    ]
    if virtual is not None and report.root_joint is not None:
        notes.append(
            finding(
                "srdf-virtual-joint",
                ROOT_JOINT_NAME,
                f"the {report.root_joint} virtual joint '{virtual}' of the SRDF is the root "
                f"joint '{ROOT_JOINT_NAME}'",
                next((v.line for v in srdf.virtual_joints if v.name == virtual), None),
                srdf.path,
            )
        )
    passive = tuple(j.name for j in report.joints if j.name in resolved.passive)
    notes.extend(
        finding(
            "joint-passive",
            name,
            f"joint '{name}' is passive in the SRDF: planners do not move it (it is held in "
            "every group's C-space)",
        )
        for name in passive
    )
    if srdf.robot and report.robot and srdf.robot != report.robot:
        notes.append(other_robot(srdf, report.robot))
    kind = next((v.type for v in srdf.virtual_joints if v.name == virtual), None)
    summary = SrdfSummary(
        path=srdf.path,
        sha256=srdf.sha256,
        virtual_joint=None if virtual is None else f"{virtual}:{kind}",
        passive=passive,
        groups=tuple(
            (g.name, resolved.groups[g.name], resolved.broken.get(g.name)) for g in srdf.groups
        ),
    )
    # the virtual joint is the root's joint, whatever its type: no advice to add one
    kept = report.diagnostics if virtual is None else without_advice(report.diagnostics)
    return report._replace(
        diagnostics=(*kept, *resolved.findings, *notes, *found),
        poses=(*report.poses, *poses),
        srdf=summary,
    )


MAX_LISTED_MEMBERS = 50_000
"""Most group members the report's ``srdf.groups`` lists in all (1,000 groups of 5,000
joints would be 5 million names): groups past it are listed without their joints."""


def listed(report: Report) -> Report:
    """The report with its SRDF's groups listed up to `MAX_LISTED_MEMBERS` joints."""
    if report.srdf is None:
        return report
    room, kept, bare = MAX_LISTED_MEMBERS, [], 0
    for name, joints, broken in report.srdf.groups:
        room -= len(joints)
        bare += room < 0
        kept.append((name, joints if room >= 0 else (), broken))
    if not bare:
        return report
    note = finding(
        "srdf-ignored",
        None,
        f"{bare:,} groups listed without their joints: cspace lists {MAX_LISTED_MEMBERS:,} "
        "group members at most (--group reads them all)",
        None,
        report.srdf.path,
    )
    return report._replace(
        srdf=report.srdf._replace(groups=tuple(kept)), diagnostics=(*report.diagnostics, note)
    )


def group_report(report: Report, name: str, hold: str | None) -> Report:
    """The report of SRDF group ``name``'s own C-space, the robot's other joints held.

    The group's joints keep their coordinates (passive joints excepted); a mimic joint
    moves with its leader. Every other joint is reported fixed, held at the stored pose
    ``hold`` (a label of `Report.poses`) or at neutral: the C-space does not depend on
    where, the kinematics do. q and v indices are those of Pinocchio's reduced model
    (``buildReducedModel`` keeps the order).

    Raises:
        InvalidElementError: No SRDF, an unknown or broken group, or an unknown pose
            (code ``srdf-unknown-group``).
    """
    srdf = report.srdf
    path = report.source.path if srdf is None else srdf.path
    groups = {} if srdf is None else {g[0]: g for g in srdf.groups}
    if name not in groups:
        searched = next((d.message for d in report.diagnostics if d.code == "srdf-not-found"), "")
        known = ", ".join(groups) or f"none: no SRDF was read ({searched or '--srdf FILE'})"
        raise InvalidElementError(
            path, f"no group '{name}' (groups: {known})", element=name, code="srdf-unknown-group"
        )
    _, members, broken = groups[name]
    if broken is not None:
        raise InvalidElementError(
            path,
            f"group '{name}' cannot be used: {broken}",
            element=name,
            code="srdf-unknown-group",
        )
    held_at = None
    if hold is not None:
        try:
            held_at = pick(report.poses, hold)
        except LookupError as exc:
            raise InvalidElementError(
                path, f"--hold: {exc}", element=hold, code="srdf-unknown-group"
            ) from None
    passive = set(() if srdf is None else srdf.passive)
    keep = set(members) - passive
    joints, held = [], []
    q = v = 0
    for joint in report.joints:
        leader = joint.mimic.joint if joint.mimic is not None else None
        moving = joint.name in keep or (joint.kind is JointKind.MIMIC and leader in keep)
        if joint.nq == 0 and joint.kind is not JointKind.MIMIC:
            joints.append(joint)
        elif moving:
            joints.append(
                joint._replace(q_index=q if joint.nq else None, v_index=v if joint.nv else None)
            )
            q, v = q + joint.nq, v + joint.nv
        else:
            held.append(joint.name)
            joints.append(
                joint._replace(
                    kind=JointKind.FIXED,
                    space=NormalForm(),
                    limits=None,
                    q_index=None,
                    nq=0,
                    v_index=None,
                    nv=0,
                    mimic=None,
                    pinocchio_model=None,
                    qposadr=None,
                    dofadr=None,
                    mujoco_type=None,
                    at_world_origin=None,
                )
            )
    coordinates = canonical_coordinates(tuple(joints))
    kept = {c.joint for c in coordinates.entries}
    index = [i for i, c in enumerate(report.coordinates.entries) if c.joint in kept]
    poses = tuple(
        p._replace(
            configuration=None
            if p.configuration is None
            else tuple(p.configuration[i] for i in index)
        )
        for p in report.poses
        if p.group == name
    )
    kept_joints = tuple(j.name for j in joints if j.name in kept)
    neutral = [c.neutral for c in report.coordinates.entries]
    at = list(neutral if held_at is None else held_at.configuration or neutral)
    held_values = tuple(
        (joint, tuple(at[i] for i, c in enumerate(report.coordinates.entries) if c.joint == joint))
        for joint in held
    )
    diagnostics = report.diagnostics
    if report.closure is not None:  # its numbers are the whole robot's, its samples too
        diagnostics = (*diagnostics, _closure_of_whole(report.closure.loops))
    return report._replace(
        manifold=NormalForm.product([j.space for j in joints]),
        nq=q,
        nv=v,
        joints=tuple(joints),
        coordinates=coordinates,
        poses=poses,
        diagnostics=diagnostics,
        closure=None,
        group=GroupView(
            name, kept_joints, held_values, "neutral" if held_at is None else held_at.label
        ),
    )


def _closure_of_whole(loops: int) -> Diagnostic:
    return finding(
        "closure-whole-robot",
        None,
        f"the robot closes {loops} loop(s); a group's C-space holds the other joints, so "
        "its closed chains are reported for the whole robot: inspect it without --group",
    )
