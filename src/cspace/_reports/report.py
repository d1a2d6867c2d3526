"""The report of a robot's configuration space, and its JSON form (schema_version 1).

A `Report` is immutable; `Report.to_dict` gives exactly the JSON document
that ``cspace inspect --format json`` writes and that ``cspace schema`` describes.
"""

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from cspace._factor_kinds import Coordinates
from cspace._findings import Diagnostic, Severity
from cspace._joint_report import JointReport, Limits, MimicRelation
from cspace._manifold import NormalForm
from cspace._record import NamedTuple
from cspace._reports.poses import GroupView, SrdfSummary, StoredPose
from cspace._safetext import json_text

if TYPE_CHECKING:
    from cspace._actuators import Actuator
    from cspace._reports.closure import Closure
    from cspace._reports.limits import LimitsSummary
    from cspace._ros2_control import ControlHardware

__all__ = [
    "SCHEMA_VERSION",
    "JointReport",
    "Limits",
    "MimicRelation",
    "Report",
    "Source",
    "index_range",
]

SCHEMA_VERSION = 1


def index_range(start: int | None, count: int) -> str:
    """A slice of q or v as text: ``-`` (none), ``7`` (one entry) or ``7..10``."""
    if start is None or count == 0:
        return "-"
    return str(start) if count == 1 else f"{start}..{start + count - 1}"


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
        poses: The poses the robot file (or its SRDF) stores, as configurations.
        srdf: What the SRDF read with the robot says, or None.
        group: The SRDF group whose C-space this is (the other joints held), or None.
        closure: The mechanism's closed chains (its loops, mobility, configurations found
            on it), or None for a tree.
        ros2_control: The URDF's ``<ros2_control>`` hardware components (none when it
            has none).
        actuators: MJCF: each actuator, in ctrl order (none for other formats).
        limits_file: MoveIt's joint_limits.yaml read with the robot: every joint's
            limits and where each came from, or None.
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
    poses: tuple[StoredPose, ...] = ()
    srdf: SrdfSummary | None = None
    group: GroupView | None = None
    closure: "Closure | None" = None
    ros2_control: "tuple[ControlHardware, ...]" = ()
    actuators: "tuple[Actuator, ...]" = ()
    limits_file: "LimitsSummary | None" = None

    @property
    def dimension(self) -> int:
        """Dimension of the configuration space."""
        return self.manifold.dimension

    def has(self, severity: Severity) -> bool:
        """True when at least one finding has this severity."""
        return any(d.severity is severity for d in self.diagnostics)

    def ignoring(self, codes: set[str] | frozenset[str]) -> "Report":
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
            "poses": [p.to_dict() for p in self.poses],
        } | self._semantics_dict()

    def _semantics_dict(self) -> dict[str, Any]:
        """The ``srdf`` and ``group`` sections, when there are some."""
        out: dict[str, Any] = {}
        if self.srdf is not None:
            out["srdf"] = self.srdf.to_dict()
        if self.group is not None:
            out["group"] = self.group.to_dict()
        if self.closure is not None:
            out["closure"] = self.closure.to_dict(self.source.path)
        if self.ros2_control:
            out["ros2_control"] = [h.to_dict() for h in self.ros2_control]
        if self.actuators:
            out["actuators"] = [a.to_dict() for a in self.actuators]
        if self.limits_file is not None:
            out["limits_file"] = self.limits_file.to_dict()
        return out

    def _joint_dicts(self) -> list[dict[str, Any]]:
        """Each joint's JSON object, with its ``slots`` in every convention it knows."""
        from cspace._drake_order import drake_slots
        from cspace._slots import joint_slots

        out: list[dict[str, Any]] = []
        column = tangent = 0
        drake = drake_slots(self.joints, self.source.format)
        for joint in self.joints:
            document = joint.to_dict()
            slots = joint_slots(joint, column, tangent)
            if joint.name in drake:
                slots = (slots or {}) | drake[joint.name]
            if slots is not None:
                document["slots"] = slots
                column += len(slots["canonical"]["names"]) if "canonical" in slots else 0
                tangent += len(slots["tangent"]["names"]) if "tangent" in slots else 0
            out.append(document)
        return out

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Report":
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
                    None if d.get("file") is None else str(d["file"]),
                )
                for d in document["diagnostics"]
            ),
            coordinates=Coordinates.from_dict(document["coordinates"]),
            poses=tuple(StoredPose.from_dict(p) for p in document.get("poses", ())),
            srdf=None if document.get("srdf") is None else SrdfSummary.from_dict(document["srdf"]),
            group=None if document.get("group") is None else GroupView.from_dict(document["group"]),
            closure=_closure_of(document.get("closure")),
            ros2_control=_control_of(document.get("ros2_control")),
            actuators=_actuators_of(document.get("actuators")),
            limits_file=_limits_of(document.get("limits_file")),
        )

    def to_json(self, *, indent: int | None = 2) -> str:
        r"""The JSON document as text: deterministic, UTF-8, no trailing newline.

        Every character ``str.isprintable()`` rejects (controls, bidi controls,
        zero-width characters) is a ``\uXXXX`` escape: the same JSON value, safe bytes.
        """
        return json_text(self.to_dict(), indent=indent)


def _limits_of(document: Mapping[str, Any] | None) -> "LimitsSummary | None":
    """The joint limits of a report's ``limits_file`` object, or None."""
    if document is None:
        return None
    from cspace._reports.limits import LimitsSummary

    return LimitsSummary.from_dict(document)


def _actuators_of(documents: Sequence[Mapping[str, Any]] | None) -> "tuple[Actuator, ...]":
    """The actuators of a report's ``actuators`` (their module read only when it has some)."""
    if not documents:
        return ()
    from cspace._actuators import Actuator

    return tuple(Actuator.from_dict(a) for a in documents)


def _control_of(document: Any) -> "tuple[ControlHardware, ...]":
    """The components of a report's ``ros2_control`` (its module read only for some)."""
    if not document:
        return ()
    from cspace._ros2_control import ControlHardware

    return tuple(ControlHardware.from_dict(h) for h in document)


def _closure_of(document: Mapping[str, Any] | None) -> "Closure | None":
    """The closure of a report's ``closure`` object (its module read only when there is one)."""
    if document is None:
        return None
    from cspace._reports.closure import Closure

    return Closure.from_dict(document)
