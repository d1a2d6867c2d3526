"""The report of a robot's configuration space, and its JSON form (schema_version 1).

A `Report` is immutable; `Report.to_dict` gives exactly the JSON document
that ``cspace inspect --format json`` writes and that ``cspace schema`` describes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

from cspace._factor_kinds import Coordinates
from cspace._findings import Diagnostic, Severity
from cspace._joint_kind import JointKind
from cspace._manifold import NormalForm
from cspace._safetext import json_text

SCHEMA_VERSION = 1


def index_range(start: int | None, count: int) -> str:
    """A slice of q or v as text: ``-`` (none), ``7`` (one entry) or ``7..10``."""
    if start is None or count == 0:
        return "-"
    return str(start) if count == 1 else f"{start}..{start + count - 1}"


class Limits(NamedTuple):
    """Position limits as the file gives them (rad for rotations, m for translations).

    Attributes:
        lower: One lower bound per limited coordinate.
        upper: One upper bound per limited coordinate.
        unit: ``"rad"`` or ``"m"``.
    """

    lower: tuple[float, ...]
    upper: tuple[float, ...]
    unit: str

    def to_dict(self) -> dict[str, Any]:
        """JSON form; a non-finite number (not valid JSON) becomes null."""
        return {
            "lower": _finite_or_none(self.lower),
            "upper": _finite_or_none(self.upper),
            "unit": self.unit,
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> Limits:
        """The limits of a JSON form (a null bound, a non-finite one, is NaN)."""
        return cls(_floats(document["lower"]), _floats(document["upper"]), str(document["unit"]))


class MimicRelation(NamedTuple):
    """``joint value = multiplier * leader value + offset``."""

    joint: str
    multiplier: float
    offset: float

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        multiplier, offset = _finite_or_none((self.multiplier, self.offset))
        return {"joint": self.joint, "multiplier": multiplier, "offset": offset}

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> MimicRelation:
        """The relation of a JSON form (a null number, a non-finite one, is NaN)."""
        multiplier, offset = _floats([document["multiplier"], document["offset"]])
        return cls(str(document["joint"]), multiplier, offset)


class JointReport(NamedTuple):
    """One joint of the robot, fixed and mimic joints included.

    Attributes:
        name: Joint name.
        kind: Its kind.
        parent_link: Parent link, or None for a root joint added above the root link.
        child_link: Child link.
        space: The joint's own space.
        limits: Position limits, or None when the joint has none.
        q_index: First index in Pinocchio's q, or None when the joint has no coordinates.
        nq: Number of q entries.
        v_index: First index in Pinocchio's v, or None.
        nv: Number of v entries.
        mimic: The mimic relation, or None.
        pinocchio_model: Pinocchio's joint model (``shortname()``), or None for fixed joints.
        line: Line of the joint in the file, or None.
        qposadr: For an MJCF file, the joint's first index in MuJoCo's ``qpos``
            (``jnt_qposadr``, quaternions w first); None for other formats, fixed joints
            and a root joint `cspace` added.
        dofadr: For an MJCF file, the joint's first index in MuJoCo's ``qvel``
            (``jnt_dofadr``); None as for ``qposadr``.
        mujoco_type: For an MJCF file, MuJoCo's joint type (``hinge``, ``slide``,
            ``ball``, ``free``; a mimic joint's too); None as for ``qposadr``.
    """

    name: str
    kind: JointKind
    parent_link: str | None
    child_link: str
    space: NormalForm
    limits: Limits | None = None
    q_index: int | None = None
    nq: int = 0
    v_index: int | None = None
    nv: int = 0
    mimic: MimicRelation | None = None
    pinocchio_model: str | None = None
    line: int | None = None
    qposadr: int | None = None
    dofadr: int | None = None
    mujoco_type: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this joint."""
        return {
            "name": self.name,
            "kind": self.kind.value,
            "parent_link": self.parent_link,
            "child_link": self.child_link,
            "manifold": self.space.notation,
            "dimension": self.space.dimension,
            "limits": None if self.limits is None else self.limits.to_dict(),
            "q_index": self.q_index,
            "nq": self.nq,
            "v_index": self.v_index,
            "nv": self.nv,
            "mimic": None if self.mimic is None else self.mimic.to_dict(),
            "pinocchio_model": self.pinocchio_model,
            "line": self.line,
            "qposadr": self.qposadr,
            "dofadr": self.dofadr,
            "mujoco_type": self.mujoco_type,
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> JointReport:
        """The joint of a JSON form.

        ``qposadr``, ``dofadr`` and ``mujoco_type`` may be absent (older reports).
        """
        limits, mimic = document["limits"], document["mimic"]
        return cls(
            name=str(document["name"]),
            kind=JointKind(document["kind"]),
            parent_link=document["parent_link"],
            child_link=str(document["child_link"]),
            space=_space(str(document["manifold"])),
            limits=None if limits is None else Limits.from_dict(limits),
            q_index=document["q_index"],
            nq=int(document["nq"]),
            v_index=document["v_index"],
            nv=int(document["nv"]),
            mimic=None if mimic is None else MimicRelation.from_dict(mimic),
            pinocchio_model=document["pinocchio_model"],
            line=document["line"],
            qposadr=document.get("qposadr"),
            dofadr=document.get("dofadr"),
            mujoco_type=document.get("mujoco_type"),
        )


class Source(NamedTuple):
    """Where the report came from.

    Attributes:
        path: The path as given.
        format: ``urdf``, ``mjcf``, ``sdf`` or ``xacro``.
        sha256: Hex SHA-256 of the file's bytes.
    """

    path: str
    format: str
    sha256: str


class Report(NamedTuple):
    """Everything `cspace` knows about one robot's configuration space.

    Attributes:
        tool_version: Version of `cspace` that made the report.
        source: The robot file.
        robot: The robot's name.
        root_joint: None, ``"floating"`` or ``"planar"``.
        manifold: The whole space in normal form.
        nq: Pinocchio's configuration vector length.
        nv: Pinocchio's tangent vector length.
        joints: Every joint in tree order.
        diagnostics: Findings, in joint order.
        coordinates: The canonical coordinates (none for a report made without them).
    """

    tool_version: str
    source: Source
    robot: str
    root_joint: str | None
    manifold: NormalForm
    nq: int
    nv: int
    joints: tuple[JointReport, ...]
    diagnostics: tuple[Diagnostic, ...]
    coordinates: Coordinates = Coordinates()

    @property
    def dimension(self) -> int:
        """Dimension of the configuration space."""
        return self.manifold.dimension

    def has(self, severity: Severity) -> bool:
        """True when at least one finding has this severity."""
        return any(d.severity is severity for d in self.diagnostics)

    def ignoring(self, codes: set[str] | frozenset[str]) -> Report:
        """The same report without the findings whose code is in ``codes``."""
        kept = tuple(d for d in self.diagnostics if d.code not in codes)
        return self._replace(diagnostics=kept)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document (schema_version 1), keys in a fixed order."""
        return {
            "schema_version": SCHEMA_VERSION,
            "tool": {"name": "cspace", "version": self.tool_version},
            "source": {
                "path": self.source.path,
                "format": self.source.format,
                "sha256": self.source.sha256,
            },
            "robot": self.robot,
            "root_joint": self.root_joint,
            "dimension": self.dimension,
            "nq": self.nq,
            "nv": self.nv,
            "manifold": {
                "notation": self.manifold.notation,
                "ascii": self.manifold.ascii,
                "factors": self.manifold.counts(),
                "fundamental_group": self.manifold.fundamental_group,
                "simply_connected": self.manifold.simply_connected,
            },
            "joints": self._joint_dicts(),
            "coordinates": self.coordinates.to_dict(),
            "diagnostics": [d.to_dict() for d in self.diagnostics],
        }

    def _joint_dicts(self) -> list[dict[str, Any]]:
        """Each joint's JSON object, with its ``slots`` in every convention it knows."""
        from cspace._slots import joint_slots

        out: list[dict[str, Any]] = []
        column = tangent = 0
        for joint in self.joints:
            document = joint.to_dict()
            slots = joint_slots(joint, column, tangent)
            if slots is not None:
                document["slots"] = slots
                column += len(slots["canonical"]["names"]) if "canonical" in slots else 0
                tangent += len(slots["tangent"]["names"]) if "tangent" in slots else 0
            out.append(document)
        return out

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> Report:
        """The report of a JSON document, as `to_dict` writes it.

        The document must have the report's shape: one `to_dict` made, or a saved
        report that `read_report_document` checked. A
        non-finite limit, written as null, comes back as NaN.
        """
        factors = document["manifold"]["factors"]
        return cls(
            tool_version=str(document["tool"]["version"]),
            source=Source(**{k: str(document["source"][k]) for k in Source._fields}),
            robot=str(document["robot"]),
            root_joint=document["root_joint"],
            manifold=NormalForm(int(factors["R"]), int(factors["T"]), int(factors["RP3"])),
            nq=int(document["nq"]),
            nv=int(document["nv"]),
            joints=tuple(JointReport.from_dict(j) for j in document["joints"]),
            diagnostics=tuple(
                Diagnostic(
                    Severity(d["severity"]),
                    str(d["code"]),
                    d["joint"],
                    str(d["message"]),
                    d.get("line"),
                )
                for d in document["diagnostics"]
            ),
            coordinates=Coordinates.from_dict(document["coordinates"]),
        )

    def to_json(self, *, indent: int | None = 2) -> str:
        r"""The JSON document as text: deterministic, UTF-8, no trailing newline.

        Every character ``str.isprintable()`` rejects (controls, bidi controls,
        zero-width characters) is a ``\uXXXX`` escape: the same JSON value, safe bytes.
        """
        return json_text(self.to_dict(), indent=indent)


def _finite_or_none(values: tuple[float, ...]) -> list[float | None]:
    return [v if math.isfinite(v) else None for v in values]


def _floats(values: Sequence[float | None]) -> tuple[float, ...]:
    return tuple(math.nan if v is None else float(v) for v in values)


def _space(notation: str) -> NormalForm:
    from cspace.notation import parse_notation  # only when a report is read back

    return parse_notation(notation)
