"""From a robot file to a `Report`.

The file is read and checked by our own reader (which keeps fixed joints, limits as
written and line numbers), the model is built by Pinocchio (which decides the joint
models and the layout of q and v), and the two are joined by joint name.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from cspace._findings import Diagnostic, Severity, finding
from cspace._formats.shared.description import JointSpec, PoseSpec, RobotDescription
from cspace._formats.shared.xmlio import SourceFile
from cspace._joint_kind import JointKind
from cspace._joint_report import kept_limits
from cspace._joint_table import (
    EULER_MODELS,
    KIND_OF_MODEL,
    JointFactors,
    canonical_coordinates,
    factors_of,
    kind_of,
)
from cspace._manifold import NormalForm
from cspace._model.adapter import ROOT_JOINT_NAME, PinJoint, PinModel
from cspace._model.diagnostics import joint_findings, robot_findings
from cspace._reports.poses import StoredPose, assemble
from cspace._reports.report import JointReport, Limits, MimicRelation, Report, Source
from cspace._version import __version__
from cspace.errors import ModelBuildError, RobotStructureError, UnsupportedJointModelError


def _finite_mimic(spec: JointSpec) -> bool:
    mimic = spec.mimic
    return mimic is None or (math.isfinite(mimic.multiplier) and math.isfinite(mimic.offset))


def _whole_ball(kind: JointKind, limits: Limits | None) -> bool:
    """A ball's range is its largest rotation angle: from pi on, it excludes nothing."""
    return (
        kind is JointKind.SPHERICAL
        and limits is not None
        and len(limits.upper) == 1
        and limits.upper[0] >= math.pi
    )


def _mimic(spec: JointSpec, pj: PinJoint) -> MimicRelation | None:
    if pj.mimic is not None and _finite_mimic(spec):
        return MimicRelation(pj.mimic.leader, pj.mimic.scaling, pj.mimic.offset)
    # Pinocchio was given finite stand-ins, or kept the joint free (see mimic_fallback):
    # the report keeps what the file says.
    if spec.mimic is not None:
        return MimicRelation(spec.mimic.joint, spec.mimic.multiplier, spec.mimic.offset)
    return None


def _classify(path: str, spec: JointSpec, pj: PinJoint) -> tuple[JointReport, JointFactors]:
    """The joint's report, and its factors (none when it has no coordinates of its own)."""
    limits = kept_limits(spec.kind, spec.lower, spec.upper)
    kind = kind_of(pj.model, limits)
    if kind is None:
        raise UnsupportedJointModelError(
            path, joint=spec.name, joint_model=pj.model, known_models=list(KIND_OF_MODEL)
        )
    mimic = _mimic(spec, pj)
    if mimic is not None:
        kind = JointKind.MIMIC
    has_coordinates = pj.nq > 0 and pj.mimic is None
    found = factors_of(kind, pj.nq, pj.nv, limits)
    if found.unsupported is not None and not found.factors:
        raise UnsupportedJointModelError(
            path, joint=spec.name, joint_model=pj.model, known_models=list(KIND_OF_MODEL)
        )
    joint = JointReport(
        name=spec.name,
        kind=kind,
        parent_link=spec.parent,
        child_link=spec.child,
        space=found.space,
        limits=limits,
        q_index=pj.idx_q if has_coordinates else None,
        nq=pj.nq if has_coordinates else 0,
        v_index=pj.idx_v if has_coordinates else None,
        nv=pj.nv if has_coordinates else 0,
        mimic=mimic,
        pinocchio_model=pj.model,
        line=spec.line,
        origin=pj.origin if kind is JointKind.FLOATING else None,
    )
    return joint, found if has_coordinates else JointFactors()


def _fixed(spec: JointSpec) -> tuple[JointReport, JointFactors]:
    """A fixed joint: a point, no coordinates, no Pinocchio joint (it is a frame there)."""
    found = factors_of(JointKind.FIXED, 0, 0, None)
    kind, space = JointKind.FIXED, found.space
    return JointReport(spec.name, kind, spec.parent, spec.child, space, line=spec.line), found


def analyse(
    source: SourceFile,
    format: str,
    description: RobotDescription,
    model: PinModel,
    root_joint: str | None,
    addresses: Mapping[str, tuple[int, int, str]] | None = None,
    poses: Sequence[PoseSpec] = (),
    *,
    placed: bool = True,
) -> Report:
    """Join the file's description and Pinocchio's model into a report.

    Args:
        source: The file's bytes and name.
        format: The format reported in ``source.format``.
        description: The file's own account of its joints.
        model: Pinocchio's model.
        root_joint: The root joint added, or None.
        addresses: For MJCF, each joint's MuJoCo ``(qposadr, dofadr, type)`` by name.
        poses: The poses the file stores, listed in the report as configurations.
        placed: Whether the model's joints are where the file puts them (False: a
            reader left a joint unplaced, and the model is for the C-space only). Only
            then does the root joint's record say whether it is at the world's origin.

    Raises:
        RobotStructureError: A root joint is asked for and the file already has a joint
            of its name (``root_joint``).
        ModelBuildError: Pinocchio's model lacks a joint the file declares.
        UnsupportedJointModelError: Pinocchio made a joint model `cspace` does not know.
    """
    path = source.path
    by_name = {pj.name: pj for pj in model.joints}
    joints: list[JointReport] = []
    factors: list[JointFactors] = []  # each joint's, for its coordinates
    diagnostics: list[Diagnostic] = []
    if root_joint is not None:
        taken = description.joint(ROOT_JOINT_NAME)
        if taken is not None:  # Pinocchio would hold two joints of that name
            raise RobotStructureError(
                path,
                f"the file has a joint named '{ROOT_JOINT_NAME}', the name cspace gives the "
                f"{root_joint} root joint it adds; rename that joint to add one",
                code="duplicate-joint",
                line=taken.line,
                element=ROOT_JOINT_NAME,
            )
        kind = JointKind.FLOATING if root_joint == "floating" else JointKind.PLANAR
        spec = JointSpec(
            name=ROOT_JOINT_NAME,
            type=root_joint,
            parent="",
            child=description.root_link,
            kind=kind,
        )
        joint, found = _classify(path, spec, by_name[ROOT_JOINT_NAME])
        joints.append(joint._replace(parent_link=None))
        factors.append(found)
        diagnostics.append(
            finding(
                "root-joint-added",
                ROOT_JOINT_NAME,
                f"added a {root_joint} root joint '{ROOT_JOINT_NAME}' above link "
                f"'{description.root_link}'",
            )
        )
    found_by_joint: dict[str | None, list[Diagnostic]] = {}
    for said in description.findings:  # once: per joint it was quadratic
        found_by_joint.setdefault(said.joint, []).append(said)
    for spec in description.joints:
        if spec.kind is JointKind.FIXED:
            joint, found = _fixed(spec)
            joints.append(joint)
            factors.append(found)
        else:
            pj = by_name.get(spec.name)
            if pj is None:
                raise ModelBuildError(
                    path, f"Pinocchio's model has no joint '{spec.name}'", model.parser_messages
                )
            joint, found = _classify(path, spec, pj)
            factors.append(found)
            if addresses is not None and spec.name in addresses:
                qposadr, dofadr, mujoco_type = addresses[spec.name]
                joint = joint._replace(qposadr=qposadr, dofadr=dofadr, mujoco_type=mujoco_type)
            joints.append(joint)
            if _whole_ball(joint.kind, joint.limits):
                diagnostics.append(
                    finding(
                        "ball-range-whole",
                        spec.name,
                        f"ball joint '{spec.name}' allows rotations up to {spec.upper[0]:g} rad; "
                        "no rotation is larger than pi, so the range limits nothing: RP^3",
                    )
                )
            if pj.model in EULER_MODELS:
                diagnostics.append(
                    finding(
                        "euler-coordinates",
                        spec.name,
                        f"joint '{spec.name}' is kept in Euler-angle coordinates, which are "
                        "singular at some orientations",
                    )
                )
        leader = description.joint(spec.mimic.joint) if spec.mimic else None
        diagnostics.extend(joint_findings(spec, leader))
        diagnostics.extend(found_by_joint.get(spec.name, ()))
    diagnostics.extend(robot_findings(description, root_joint, model.pinocchio))
    named = {spec.name for spec in description.joints}
    diagnostics.extend(d for d in description.findings if d.joint not in named)
    if model.mimic_fallback is not None:
        diagnostics.append(
            finding(
                "mimic-kept-free",
                None,
                "Pinocchio cannot keep the mimic joints dependent here "
                f"({model.mimic_fallback}); its q and v keep the mimic joints' own entries, "
                "to be set from their leaders, and the dimension does not count them",
            )
        )
    diagnostics.extend(
        finding("parser-message", None, f"Pinocchio's parser said: {message}")
        for message in model.parser_messages
    )
    coordinates = canonical_coordinates(tuple(joints), factors)
    if placed and model.pinocchio is not None:
        joints = _with_root_placement(joints, model.pinocchio, diagnostics)
    return Report(
        tool_version=__version__,
        source=Source(path=path, format=format, sha256=source.sha256),
        robot=description.name or model.name,
        root_joint=root_joint,
        manifold=NormalForm.product([j.space for j in joints]),
        nq=model.nq,
        nv=model.nv,
        joints=tuple(joints),
        diagnostics=_at_most(diagnostics, MAX_FINDINGS),
        coordinates=coordinates,
        poses=tuple(
            StoredPose(p.name, p.source, p.line, None, assemble(coordinates, dict(p.values)))
            for p in poses
        ),
        ros2_control=description.ros2_control,
    )


def _with_root_placement(
    joints: list[JointReport], model: object, diagnostics: list[Diagnostic]
) -> list[JointReport]:
    """The joints, the root joint's record saying whether it is at the world's origin.

    A root joint Drake's URDF parser moves otherwise than Pinocchio (``drake-urdf-differs``:
    a planar joint whose ``<axis>`` is not +z moves in the plane normal to it, as URDF
    specifies) is not: Pinocchio's model, which ignores the axis, would say it is.
    """
    from cspace._model._root_place import at_world_origin

    answers = at_world_origin(joints, model)
    differs = {d.joint for d in diagnostics if d.code == "drake-urdf-differs"}
    answers = {name: placed and name not in differs for name, placed in answers.items()}
    return [j._replace(at_world_origin=answers[j.name]) if j.name in answers else j for j in joints]


MAX_FINDINGS = 10_000
"""Most findings in one report (the report schema takes as many, no more). A file of 5,000 joints
with a dozen bad numbers each made 80,000: a report too large to read or diff."""

_RANK = {Severity.ERROR: 0, Severity.WARNING: 1, Severity.INFO: 2}


def _at_most(diagnostics: list[Diagnostic], limit: int) -> tuple[Diagnostic, ...]:
    """The findings, or the ``limit - 1`` most severe (in order) and one that says so."""
    if len(diagnostics) <= limit:
        return tuple(diagnostics)
    kept = sorted(diagnostics, key=lambda d: _RANK[d.severity])[: limit - 1]
    left = len(diagnostics) - len(kept)
    note = finding(
        "findings-truncated", None, f"{left:,} more findings, none more severe, are not listed"
    )
    return (*kept, note)
