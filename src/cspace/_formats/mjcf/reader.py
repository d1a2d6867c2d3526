"""The MJCF reader: MuJoCo's own compiler is the front end.

An MJCF model is what MuJoCo compiles from it: includes, ``<default>`` classes,
``<frame>``, ``childclass``, ``<replicate>``, ``<attach>``, angle units and
``autolimits`` are MuJoCo's to resolve, not ours. So `cspace`:

1. reads every file the model needs, bounded and once (`mjcf_prescan`);
2. has MuJoCo parse and compile it in a confined child process with hard limits: the
   documents the pre-scan read, as lxml serialises them (MuJoCo's XML parser would read
   some bytes otherwise), its error lines mapped back to the file's
   (`mjcf_worker`, `mjcf_compile`), with geometry files
   replaced (they need not exist);
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

import base64
import math
import os
import re
import threading
from collections.abc import Sequence
from dataclasses import replace
from typing import Any, NamedTuple

from lxml import etree

from cspace._confine.kept import KeptChild
from cspace._confine.sandbox import ChildLimits, ChildRefused
from cspace._findings import Diagnostic, finding
from cspace._formats.mjcf._keys import key_findings, key_poses
from cspace._formats.mjcf._models import mujoco_document, original_line
from cspace._formats.mjcf._prescan import PreScan, prescan
from cspace._formats.mjcf._units import radian_slips
from cspace._formats.shared.description import JointSpec, LinkSpec, MimicSpec, RobotDescription
from cspace._formats.shared.kinematic_tree import KinematicTree, TreeBody, TreeJoint
from cspace._formats.shared.reading import Reading, ReadRequest
from cspace._formats.shared.robot_size import check_sizes
from cspace._formats.shared.structure import build_description
from cspace._formats.shared.xmlio import MAX_FILE_BYTES, ReadBudget, SourceFile
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

MJCF_LIMITS = ChildLimits(
    cpu_seconds=5, wall_seconds=6.0, memory_bytes=512 * 2**20, output_bytes=MAX_FILE_BYTES
)
"""The bounds of MuJoCo's compile. The child maps 187 MiB once MuJoCo is imported; every
model of dm_control and Gymnasium compiles within 250 MiB; 512 MiB keeps the child's
resident memory under the 600 MiB a robot file may cost. A 1,000-deep chain (the
deepest the pre-scan allows) compiles in 1.2 s of CPU, 1.5-2.5 s on a busy 2-core machine."""

# MUJOCO_GL=disable: MuJoCo skips loading an OpenGL library (40 ms) it would not use.
COMPILER = KeptChild(
    "cspace._formats.mjcf._worker", MJCF_LIMITS, "MuJoCo", env={"MUJOCO_GL": "disable"}
)
"""This process's MuJoCo child: it compiles one model a request, confined (`mjcf_worker`)."""


CACHE_SIZE = 16
"""Compiled models kept in memory, by the digest of everything MuJoCo was given: the same
bytes compile to the same model, so ``inspect`` then ``pinocchio_model`` (or ``load``) of
one file compiles it once."""

_compiled: dict[str, bytes] = {}
_compiled_lock = threading.Lock()


class MainDocument(NamedTuple):
    """The main file, as read and as MuJoCo was given it (for the lines of its messages).

    Attributes:
        root: Its parsed root element.
        data: Its bytes.
        text: The document MuJoCo was given
            (`mujoco_document`).
    """

    root: etree._Element
    data: bytes
    text: str


class Compiling:
    """A model for MuJoCo to compile in its child process (started); `finish` compiles it."""

    def __init__(
        self,
        path: str,
        scan: PreScan,
        request: dict[str, Any] | None,
        key: str,
        answer: bytes = b"",
        main: MainDocument | None = None,
    ) -> None:
        self.path = path
        self.scan = scan
        self.main = main
        self.request = request
        self.key = key
        self.answer = answer

    def finish(self) -> Reading:
        """The robot MuJoCo compiled.

        Raises:
            MujocoError: MuJoCo refused the model (its own reason, with the line where
                it gives one), or the compile hit a limit.
            RobotStructureError: More joints, links or depth than `cspace` reads.
        """
        answer = self.answer
        if self.request is not None:
            try:
                answer = COMPILER.ask(self.request)
            except ChildRefused as exc:
                raise _refused(self.path, str(exc), self.scan, self.main) from None
            with _compiled_lock:
                while len(_compiled) >= CACHE_SIZE:
                    _compiled.pop(next(iter(_compiled)))
                _compiled[self.key] = answer
        import json

        try:
            facts = json.loads(answer)
            return read_facts(self.path, facts, self.scan)
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
                self.path, "MuJoCo's compiler gave an answer cspace cannot read"
            ) from None


def start_compile(
    path: str,
    source: SourceFile,
    root: etree._Element,
    file: str | None,
    *,
    budget: ReadBudget,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
) -> Compiling:
    """Read what the model needs and start MuJoCo compiling it.

    Args:
        path: The file, for messages.
        source: The main file's bytes.
        root: Its parsed ``<mujoco>`` element.
        file: The main file on disk, or None (standard input).
        budget: The run's budget, already charged with the main file.
        allow_dirs: Folders, besides the file's own, that includes may come from.

    Raises:
        RobotFileError: An include or model cannot be read, or the model expands past
            the limits (see `prescan`).
    """
    scan = prescan(path, root, file, budget=budget, allow_dirs=allow_dirs, data=source.data)
    main = mujoco_document(root)  # what the pre-scan read, not the bytes: see _mjcf_models
    request = {
        "main": main,
        "includes": {k: base64.b64encode(v).decode("ascii") for k, v in scan.includes.items()},
        "placeholders": sorted(scan.placeholders),
    }
    import hashlib

    digest = hashlib.sha256(main.encode("utf-8"))  # what MuJoCo is given
    for name, data in sorted(scan.includes.items()):
        digest.update(b"\0%d:%s\0" % (len(name), name.encode("utf-8", "surrogateescape")))
        digest.update(hashlib.sha256(data).digest())
    digest.update("\0".join(sorted(scan.placeholders)).encode("utf-8", "surrogateescape"))
    key = digest.hexdigest()
    with _compiled_lock:
        cached = _compiled.get(key)
    if cached is not None:
        return Compiling(path, scan, None, key, cached)
    COMPILER.start()  # MuJoCo loads in the child while this process works on
    return Compiling(path, scan, request, key, main=MainDocument(root, source.data, main))


_LINE = re.compile(r",? ?\bline\s*[=:]?\s*(\d+)")
_LINE_0 = re.compile(r",? ?\bline\s*[=:]?\s*0+\b")
_ELEMENT = re.compile(r"Element name '([^']+)'")
_AT = re.compile(r"Element (name )?'([^']*)'(?:, id -?\d+)?, line (\d+)")


def read(request: ReadRequest) -> Reading:
    """Read the MJCF file ``request`` names (the format's reader).

    MuJoCo compiles in a child process; ``request.meanwhile`` runs in this one while it
    does (the loader imports Pinocchio then).
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
    return compiling.finish()


def _refused(path: str, text: str, scan: PreScan, main: MainDocument | None) -> MujocoError:
    """MuJoCo's message as one line, with the file and line where it or the pre-scan knows.

    MuJoCo names an element (by tag or name) and its line in the document it was given;
    of a nested message (a model file MuJoCo could not parse), the last is the main
    document's, and only the last is read. That line is mapped back to the file's, when
    the main document has such an element there. An element of an included file is at
    line 0; then its name, when it has one, finds its file and line. A file given to
    MuJoCo under another name (two files of one base name) is called by its own.
    """
    for given, name in scan.given.items():
        text = text.replace(given, name)
    lines = [" ".join(part.split()) for part in text.splitlines()]
    message = "; ".join(part for part in lines if part)
    line = None
    # (where the line number stands, by name or by tag, the name or tag, the line)
    spots: list[tuple[int, int, bool, str | None, str]] = [
        (m.start(3), m.end(3), bool(m.group(1)), m.group(2), m.group(3))
        for m in _AT.finditer(message)
    ]
    if not spots and (bare := _LINE.search(message)) is not None:
        spots = [(bare.start(1), bare.end(1), False, None, bare.group(1))]
    # MuJoCo's own location is the last: an earlier one may be text of the file's (a
    # class name quoted in the message), and mapping each took a parse of the document
    for start, end, by_name, named_as, said in spots[-1:]:
        at = None if main is None else original_line(*main, int(said), by_name, named_as)
        if at is not None:
            line = at
            message = f"{message[:start]}{at}{message[end:]}"
    message = _LINE_0.sub("", message)  # "line 0": no line
    named = _ELEMENT.search(message)
    if line is None and named and named.group(1) in scan.where:
        file, at = scan.where[named.group(1)]
        if file is None:
            line = at
        else:
            message += f" (in {file}, line {at})"
    return MujocoError(path, f"MuJoCo refuses the model: {message}", line=line)


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
    from cspace._formats.mjcf._equality import equality_findings, linear_couplings

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
    description = RobotDescription(
        name=checked.name,
        format="mjcf",
        root_link=WORLD,
        links=checked.links,
        joints=tuple(ordered),
        findings=tuple(findings),
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
        description = replace(description, findings=(*description.findings, *differs))
    from cspace._formats.shared.robot_size import check_name

    for given, *_ in facts.get("keys", []):  # a pose's name goes in the report
        if given:
            check_name(path, str(given), lines.get(("key", str(given))), "a keyframe name")
    poses = key_poses(facts, joint_names, MJCF_JOINT_TYPES, lines)
    return Reading(description, tree, addresses, poses)
