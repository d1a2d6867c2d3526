"""The poses a robot file stores (MJCF keyframes, SRDF group states), as configurations."""

import math
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._factor_kinds import Coordinates
from cspace._record import NamedTuple

MAX_POSE_NUMBERS = 250_000
"""Most numbers of stored poses' configurations a report lists: poses past it are listed
without their configuration. A quarter of the million JSON values a saved report may
hold (`savedreport.MAX_REPORT_VALUES`), so that the largest report cspace writes (5,000
joints, 10,000 findings, 50,000 group members listed) is read back."""


class StoredPose(NamedTuple):
    """One pose a robot file stores.

    Attributes:
        name: Its name in the file (``key<N>`` for an unnamed MJCF keyframe).
        source: ``keyframe`` (MJCF ``<key>``) or ``group_state`` (SRDF).
        line: Its line in the file that stores it, or None.
        group: The SRDF group it is a state of, or None.
        configuration: Its canonical configuration (the report's ``coordinates``
            order; quaternions normalised, angles of S^1 in [-pi, pi)), or None when it
            is no point of the space (a value not finite or of the wrong count). Values
            outside limits are kept as written: the findings name them.
    """

    name: str
    source: str
    line: int | None
    group: str | None
    configuration: tuple[float, ...] | None

    @property
    def label(self) -> str:
        """How ``cspace convert ROBOT#LABEL`` names it: ``name``, or ``group/name``."""
        return self.name if self.group is None else f"{self.group}/{self.name}"

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this pose."""
        return {
            "name": self.name,
            "source": self.source,
            "group": self.group,
            "line": self.line,
            "configuration": None if self.configuration is None else list(self.configuration),
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "StoredPose":
        """The pose of a JSON object."""
        values = document["configuration"]
        configuration = None if values is None else tuple(float(v) for v in values)
        if configuration is not None and not all(math.isfinite(v) for v in configuration):
            configuration = None
        group, line = document["group"], document["line"]
        return cls(
            name=str(document["name"]),
            source=str(document["source"]),
            line=None if line is None else int(line),
            group=None if group is None else str(group),
            configuration=configuration,
        )


def assemble(
    coordinates: Coordinates, values: Mapping[str, Sequence[float]]
) -> tuple[float, ...] | None:
    """A canonical configuration from each joint's values, the others at neutral.

    Args:
        coordinates: The robot's canonical coordinates.
        values: Joint name -> its values in canonical order (a quaternion w first), not
            yet wrapped or normalised; joints without coordinates are skipped.

    Returns:
        The configuration: angles of S^1 wrapped into [-pi, pi), quaternions normalised
        onto w >= 0; None when a value is not finite, a joint's count is not its
        coordinates' count, or a quaternion is zero.
    """
    entries = coordinates.entries
    x = [c.neutral for c in entries]
    starts: dict[str, int] = {}
    sizes: dict[str, int] = {}
    for index, entry in enumerate(entries):
        starts.setdefault(entry.joint, index)
        sizes[entry.joint] = sizes.get(entry.joint, 0) + 1
    for joint, given in values.items():
        if joint not in starts:
            continue
        if len(given) != sizes[joint] or not all(math.isfinite(v) for v in given):
            return None
        x[starts[joint] : starts[joint] + sizes[joint]] = [float(v) for v in given]
    index = 0
    while index < len(entries):
        entry = entries[index]
        if entry.factor == "S^1":
            wrapped = math.remainder(x[index], 2.0 * math.pi)
            x[index] = -math.pi if wrapped >= math.pi else wrapped
        elif entry.factor == "RP^3":
            w, a, b, c = x[index : index + 4]
            norm = math.sqrt(w * w + a * a + b * b + c * c)
            if norm == 0.0 or not math.isfinite(norm):
                return None
            sign = -1.0 if w < 0.0 else 1.0
            x[index : index + 4] = [sign * v / norm for v in (w, a, b, c)]
            index += 3
        index += 1
    return tuple(x)


class SrdfSummary(NamedTuple):
    """What the SRDF read with the robot says (the report's ``srdf`` section).

    Attributes:
        path: The SRDF file, as given (or as found beside the URDF).
        sha256: Its hash.
        virtual_joint: Its virtual joint's name and type (``name:type``), or None.
        passive: The passive joints (cspace's names).
        groups: ``(group, its joints with coordinates, why MoveIt would not load it
            or None)``, in file order.
    """

    path: str
    sha256: str
    virtual_joint: str | None
    passive: tuple[str, ...]
    groups: tuple[tuple[str, tuple[str, ...], str | None], ...]

    def to_dict(self) -> dict[str, Any]:
        """The JSON object."""
        return {
            "path": self.path,
            "sha256": self.sha256,
            "virtual_joint": self.virtual_joint,
            "passive": list(self.passive),
            "groups": [
                {"name": name, "joints": list(joints), "broken": broken}
                for name, joints, broken in self.groups
            ],
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "SrdfSummary":
        """The section of a JSON report."""
        virtual = document["virtual_joint"]
        return cls(
            path=str(document["path"]),
            sha256=str(document["sha256"]),
            virtual_joint=None if virtual is None else str(virtual),
            passive=tuple(str(j) for j in document["passive"]),
            groups=tuple(
                (
                    str(g["name"]),
                    tuple(str(j) for j in g["joints"]),
                    None if g["broken"] is None else str(g["broken"]),
                )
                for g in document["groups"]
            ),
        )


class GroupView(NamedTuple):
    """The SRDF group whose own C-space a report describes (the report's ``group``).

    Attributes:
        name: The group.
        joints: Its joints with coordinates in the group's space, in tree order (passive
            joints are held; a mimic joint moves with its leader, without coordinates).
        held: The robot's other moving joints, held still, each with the canonical
            values it is held at (none for a mimic joint, which follows its leader).
        held_at: The pose they are held at: a stored pose's label, or ``neutral``.
    """

    name: str
    joints: tuple[str, ...]
    held: tuple[tuple[str, tuple[float, ...]], ...]
    held_at: str

    def to_dict(self) -> dict[str, Any]:
        """The JSON object."""
        return {
            "name": self.name,
            "joints": list(self.joints),
            "held": [{"joint": joint, "values": list(values)} for joint, values in self.held],
            "held_at": self.held_at,
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "GroupView":
        """The section of a JSON report."""
        return cls(
            name=str(document["name"]),
            joints=tuple(str(j) for j in document["joints"]),
            held=tuple(
                (str(h["joint"]), tuple(float(v) for v in h["values"])) for h in document["held"]
            ),
            held_at=str(document["held_at"]),
        )


def pick(poses: Sequence[StoredPose], wanted: str) -> StoredPose:
    """The stored pose called ``wanted`` (its label ``group/name``, or its name alone).

    Raises:
        LookupError: No such pose, several of that name, or one that is no configuration
            (its message is one line, for the caller's error).
    """
    from cspace._safetext import printable

    found = [p for p in poses if p.label == wanted] or [p for p in poses if p.name == wanted]
    if not found:
        labels = ", ".join(printable(p.label) for p in poses[:20]) or "none"
        raise LookupError(f"no stored pose '{printable(wanted)}' (poses: {labels})")
    if len(found) > 1:
        several = ", ".join(printable(p.label) for p in found)
        raise LookupError(f"pose '{printable(wanted)}' is several ({several}): name one")
    if found[0].configuration is None:
        raise LookupError(
            f"pose '{printable(found[0].label)}' has no configuration in the report (a value "
            "not finite or of the wrong count, or past what cspace lists: `cspace inspect` "
            "says which)"
        )
    return found[0]
