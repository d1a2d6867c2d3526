"""The MJCF reader: MuJoCo's own compiler is the front end.

An MJCF model is what MuJoCo compiles from it: includes, ``<default>`` classes,
``<frame>``, ``childclass``, ``<replicate>``, ``<attach>``, angle units and
``autolimits`` are MuJoCo's to resolve, not ours. So `cspace`:

1. reads every file the model needs, bounded and once (`_prescan`);
2. has MuJoCo parse and compile it in a confined child process with hard limits: the
   documents the pre-scan read, as lxml serialises them (MuJoCo's XML parser would read
   some bytes otherwise), its error lines mapped back to the file's
   (`_compiler`, in this process; `_worker`, `_compile`, in the child), with geometry
   files replaced (they need not exist);
3. reads the compiled model's facts here into a `RobotDescription` and a
   `KinematicTree`, from which
   `build_tree_model` builds the Pinocchio model.

The joints are MuJoCo's, in MuJoCo's order (``jnt_type``: ``free``, ``ball``, ``slide``,
``hinge``), with MuJoCo's limits (``jnt_limited``, ``jnt_range``; a ball's range is a
cone of rotations, ``0 MAX``) and MuJoCo's ``qposadr``/``dofadr``. A body without a joint
is welded to its parent: a fixed joint named ``BODY_fixed``.

MuJoCo names nothing it is not given a name for, so `cspace` names what the file leaves
unnamed, and says so in a ``name-made-up`` finding: a body is ``body<ID>`` (its MuJoCo
body id), a joint ``<BODY>Joint_<K>`` (the K-th joint of its body, from 0: the name
Pinocchio's MJCF parser gives). A made-up name that a named element already has gets
``_2``, ``_3``, ... appended.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.mjcf._actuators import actuator_findings, read_actuators
from cspace._formats.mjcf._compiler import start_compile
from cspace._formats.mjcf._keys import key_findings, key_poses
from cspace._formats.mjcf._prescan import PreScan
from cspace._formats.mjcf._units import radian_slips
from cspace._formats.shared.description import JointSpec, LinkSpec, MimicSpec, RobotDescription
from cspace._formats.shared.kinematic_tree import KinematicTree, TreeBody, TreeJoint
from cspace._formats.shared.reading import Reading, ReadRequest
from cspace._formats.shared.robot_size import check_sizes
from cspace._formats.shared.structure import build_description
from cspace._joint_kind import JointKind
from cspace.errors import MujocoError

MJCF_JOINT_TYPES = ("free", "ball", "slide", "hinge")
"""MuJoCo's joint types, by ``mjtJoint`` value (``mjJNT_FREE`` is 0)."""

WORLD = "world"
"""The root link: MuJoCo's world body."""

_MODELS = {"free": "floating", "ball": "spherical", "slide": "prismatic", "hinge": "revolute"}

MJCF_KINDS = {
    "free": JointKind.FLOATING,
    "ball": JointKind.SPHERICAL,
    "slide": JointKind.PRISMATIC,
    "hinge": JointKind.REVOLUTE,
}
"""Each MuJoCo joint type in cspace's words (an unlimited hinge becomes continuous in the
analysis, from its limits)."""


def read(request: ReadRequest) -> Reading:
    """Read the MJCF file ``request`` names (the format's reader).

    MuJoCo compiles in a child process; ``request.meanwhile`` runs in this one while it
    does (the loader imports Pinocchio then).

    Raises:
        MujocoError: MuJoCo refused the model (its own reason, with the line where it
            gives one), the compile hit a limit, or its answer cannot be read.
        RobotStructureError: More joints, links or depth than `cspace` reads.
    """
    compiling = start_compile(
        request.path,
        request.source,
        request.root,
        request.on_disk,
        budget=request.budget,
        allow_dirs=request.allow_dirs,
    )
    request.meanwhile()
    answer = compiling.finish()
    import json

    try:
        facts = json.loads(answer)
        reading = read_facts(request.path, facts, compiling.scan)
        return _with_geometry(reading, facts, request, compiling.scan)
    except (
        ValueError,
        TypeError,
        KeyError,
        IndexError,
        AttributeError,
        RecursionError,
        ArithmeticError,
    ):
        raise MujocoError(
            request.path, "MuJoCo's compiler gave an answer cspace cannot read"
        ) from None


def _with_geometry(
    reading: Reading, facts: dict[str, Any], request: ReadRequest, scan: PreScan
) -> Reading:
    """``reading`` with the model's collision geometry (`Reading.geometry`), when read.

    Geometry the child could not read leaves ``geometry`` None: only the collision
    analysis needs it.
    """
    tree = reading.recipe  # the bodies in MuJoCo's order, named as cspace names them
    if facts.get("collision") is None or not isinstance(tree, KinematicTree):
        return reading
    from cspace._formats.mjcf._geometry import read_geometry

    try:
        geometry = read_geometry(
            facts["collision"],
            [body.name for body in tree.bodies],
            [int(body[1]) for body in facts["bodies"]],
            request.source,
            request.on_disk,
            request.allow_dirs,
            scan,
        )
    except (ValueError, TypeError, KeyError, IndexError, AttributeError):
        return reading
    return reading._replace(geometry=geometry)


def _vector(values: Any) -> tuple[float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]))


def _quaternion(values: Any) -> tuple[float, float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]), float(values[3]))


def _made_up(names: Sequence[str]) -> Diagnostic:
    shown = ", ".join(names[:20]) + (f", ... ({len(names):,} in all)" if len(names) > 20 else "")
    return finding(
        "name-made-up",
        names[0],
        f"the file leaves {len(names):,} joint(s) or body(ies) unnamed, which MuJoCo allows; "
        f"cspace calls them {shown} (body<ID>, <BODY>Joint_<K>)",
    )


class _Names:
    """Names for what the file leaves unnamed, unique against every given name."""

    def __init__(self, given: Sequence[str | None]) -> None:
        self.used = {name for name in given if name}
        self.made_up: list[str] = []

    def name(self, given: str | None, wanted: str, *, report: bool = True) -> str:
        if given:
            return given
        name, k = wanted, 1
        while name in self.used:
            k += 1
            name = f"{wanted}_{k}"
        self.used.add(name)
        if report:
            self.made_up.append(name)
        return name


def read_facts(path: str, facts: dict[str, Any], scan: PreScan) -> Reading:
    """The description and the kinematic tree of a compiled model.

    Args:
        path: The file, for messages.
        facts: What `facts` read of the compiled model.
        scan: The pre-scan (for line numbers of named elements in the main file).

    Raises:
        RobotStructureError: More joints, links or depth than `cspace` reads, or a name
            too long.
    """
    bodies, joints = facts["bodies"], facts["joints"]
    names = _Names([b[0] for b in bodies] + [j[0] for j in joints])
    body_names = [WORLD] + [names.name(b[0], f"body{i}") for i, b in enumerate(bodies) if i > 0]
    lines = scan.lines
    by_body: dict[int, list[JointSpec]] = {}
    tree_joints: list[TreeJoint] = []
    addresses: dict[str, tuple[int, int, str]] = {}
    for given, kind, body, qposadr, dofadr, limited, (low, high), anchor, axis, ref in joints:
        joint_type = MJCF_JOINT_TYPES[int(kind)]
        own = by_body.setdefault(int(body), [])
        name = names.name(given, f"{body_names[body]}Joint_{len(own)}")
        lower: tuple[float, ...] = ()
        upper: tuple[float, ...] = ()
        if limited and joint_type in ("hinge", "slide"):
            lower, upper = (float(low),), (float(high),)
        elif limited and joint_type == "ball":  # a cone of rotations: "0 MAX"
            lower, upper = (0.0,), (float(high),)
        line = lines.get(("freejoint" if joint_type == "free" else "joint", name)) or lines.get(
            ("joint", name)
        )
        own.append(
            JointSpec(
                name=name,
                type=joint_type,
                parent=body_names[bodies[body][1]],
                child=body_names[body],
                kind=MJCF_KINDS[joint_type],
                axis=_vector(axis) if joint_type in ("hinge", "slide") else None,
                lower=lower,
                upper=upper,
                line=line,
            )
        )
        one_dof = joint_type in ("hinge", "slide") and bool(limited)
        tree_joints.append(
            TreeJoint(
                name=name,
                body=int(body),
                model=_MODELS[joint_type],
                anchor=_vector(anchor),
                axis=_vector(axis),
                reference=float(ref) if joint_type in ("hinge", "slide") else 0.0,
                lower=float(low) if one_dof else -math.inf,
                upper=float(high) if one_dof else math.inf,
            )
        )
        addresses[name] = (int(qposadr), int(dofadr), joint_type)
    links = [LinkSpec(WORLD, None)]
    groups = []
    for index in range(1, len(bodies)):
        name = body_names[index]
        line = lines.get(("body", name))
        links.append(LinkSpec(name, line))
        parent = body_names[bodies[index][1]]
        groups.append(JointSpec(name, "body", parent, name, JointKind.FIXED, line=line))
    checked = build_description(
        path, name=str(facts["name"]), format="mjcf", links=links, joints=groups
    )
    body_index = {name: i for i, name in enumerate(body_names)}
    ordered: list[JointSpec] = []
    for group in checked.joints:
        moving = by_body.get(body_index[group.child])
        if moving:
            ordered.extend(moving)
            continue
        fixed = names.name(None, f"{group.child}_fixed", report=False)  # welded to its parent
        ordered.append(
            JointSpec(fixed, "fixed", group.parent, group.child, JointKind.FIXED, line=group.line)
        )
    check_sizes(path, "mjcf", checked.links, ordered)  # a body may hold several joints
    from cspace._formats.mjcf._equality import (
        closure_cuts,
        equality_findings,
        left_out_of_closure,
        linear_couplings,
    )

    joint_names = [j.name for j in tree_joints]
    couplings = linear_couplings(facts)
    if couplings.mimics:  # each follower a mimic joint, as a URDF <mimic> is
        mimics = {
            joint_names[k]: MimicSpec(joint_names[c.leader], c.multiplier, c.offset)
            for k, c in couplings.mimics.items()
        }
        ordered = [j._replace(mimic=mimics.get(j.name)) for j in ordered]
    findings: list[Diagnostic] = list(checked.findings)
    if names.made_up:
        findings.append(_made_up(names.made_up))
    # an attached model reads its ranges in its own <compiler angle>, which is not said
    degree = bool(facts.get("degree", True)) and not scan.attaches
    findings.extend(radian_slips(ordered, degree))
    findings.extend(equality_findings(path, facts, body_names, joint_names, couplings))
    ties = {k: (c.leader, c.multiplier, c.offset) for k, c in couplings.mimics.items()}
    findings.extend(key_findings(facts, joint_names, MJCF_JOINT_TYPES, lines, ties))
    from cspace._formats.mjcf._key_more import more_key_findings

    tied = {c.equality for c in couplings.mimics.values()}
    findings.extend(more_key_findings(facts, joint_names, lines, ties, tied))
    if scan.beyond is not None:
        findings.append(
            finding(
                "read-beyond-folder",
                None,
                f"the model reads '{scan.beyond}' (and maybe more) from outside its own folder, "
                f"within the folders cspace may read: {', '.join(scan.allowed)}",
            )
        )
    cuts = closure_cuts(facts, body_names, lines)
    partial = left_out_of_closure(facts, couplings) if cuts else None
    if partial is not None:
        findings.append(partial)
    description = RobotDescription(
        name=checked.name,
        format="mjcf",
        root_link=WORLD,
        links=checked.links,
        joints=tuple(ordered),
        findings=tuple(findings),
        cuts=cuts,
        actuated=tuple(
            dict.fromkeys(
                joint_names[a[3]] for a in facts.get("actuators", ()) if len(a) > 3 and a[3] >= 0
            )
        ),
    )
    tree = KinematicTree(
        name=checked.name,
        bodies=tuple(
            TreeBody(body_names[i], int(b[1]) if i else -1, _vector(b[2]), _quaternion(b[3]))
            for i, b in enumerate(bodies)
        ),
        joints=tuple(tree_joints),
    )
    from cspace._formats.mjcf._drake import drake_differs

    differs = drake_differs(tree, lines, facts.get("framed") or ())  # Drake's MJCF reading
    if differs:
        description = description.replace(findings=(*description.findings, *differs))
    from cspace._formats.shared.robot_size import check_name

    for given, *_ in facts.get("keys", []):  # a pose's name goes in the report
        if given:
            check_name(path, str(given), lines.get(("key", str(given))), "a keyframe name")
    poses = key_poses(facts, joint_names, MJCF_JOINT_TYPES, lines)
    actuators = read_actuators(facts, joint_names, body_names, lines)
    for actuator in actuators:  # names the report holds, as a joint's; at the actuator's line
        line = lines.get(("actuator", actuator.name or ""))
        if actuator.name:
            check_name(path, actuator.name, line, "an actuator's name")
        if actuator.target:
            what = f"the name of the {actuator.transmission} an actuator drives"
            check_name(path, actuator.target, line, what)
    if actuators:
        joint_lines = {j.name: j.line for j in ordered}
        said = actuator_findings(facts, actuators, joint_names, joint_lines)
        description = description.replace(findings=(*description.findings, *said))
    return Reading(description, tree, addresses, poses, actuators=actuators)
