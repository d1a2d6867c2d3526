"""The report of ``cspace collisions``: which link pairs of a robot collide, and how often.

A `CollisionReport` holds every pair of links that have collision shapes, each in
MoveIt's setup assistant's class (`PAIR_KINDS`) with the share of samples in which it
collides and a 95% confidence interval, what the robot's own files say of it (an SRDF's
``<disable_collisions>``, MuJoCo's contact filters, PhysX's collision filters), the share
of the C-space free of self-collision, joint ranges in which the robot always collides
with itself, the stored poses in collision, and the findings. ``to_dict`` is its JSON
document (``kind`` ``"collisions"``, `COLLISIONS_SCHEMA_VERSION`).
"""

from typing import Any

from cspace._findings import Diagnostic, Severity
from cspace._record import NamedTuple
from cspace._reports.report import Source

COLLISIONS_SCHEMA_VERSION = 1
"""The version of the collisions document's layout."""

PAIR_KINDS = ("adjacent", "default", "always", "never", "sometimes")
"""MoveIt's classes, in the order a pair takes the first that fits: joined by a joint
(looking through links without geometry), in collision at the default configuration, in
collision in 95% of the samples or more (MoveIt's ``min_collision_fraction``), at none, and
the rest (`sometimes`: the pairs to check)."""

MUJOCO_PARENT = "parent and child"
"""The reason of MuJoCo's parent-child filter (`FileRule.reason`): a filter by design, so a
pair it skips that collides is no finding."""

ALWAYS_SHARE = 0.95
"""The share of samples in collision from which a pair is *always* in collision: MoveIt's
setup assistant's ``min_collision_fraction`` (it disables such pairs as ``Always``)."""

MOVEIT_REASONS = {
    "adjacent": "Adjacent",
    "default": "Default",
    "always": "Always",
    "never": "Never",
}
"""The ``reason`` MoveIt's setup assistant writes for each class it disables."""


class Share(NamedTuple):
    """``hits`` of ``samples`` samples, with its 95% confidence interval.

    Attributes:
        hits: Samples counted.
        samples: Samples drawn.
        low: The interval's lower end (Wilson score; 0 when ``hits`` is 0, exact
            Clopper-Pearson when ``hits`` is ``samples``).
        high: Its upper end (Wilson score; exact Clopper-Pearson when ``hits`` is 0, 1
            when ``hits`` is ``samples``).
    """

    hits: int
    samples: int
    low: float
    high: float

    @property
    def share(self) -> float:
        """``hits / samples`` (0 when no sample was drawn)."""
        return self.hits / self.samples if self.samples else 0.0

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this share."""
        return {
            "hits": self.hits,
            "samples": self.samples,
            "share": self.share,
            "low": self.low,
            "high": self.high,
        }


class Witness(NamedTuple):
    """A sample in which a pair collides: proof that it can.

    Attributes:
        sample: The sample's index in the seeded sequence (``cspace collisions --seed``).
        configuration: Its canonical configuration, by coordinate name, one number each
            (a quaternion's four are coordinates of their own, ``joint.qw`` to ``joint.qz``,
            as `ConfigurationSpace.names` names them).
    """

    sample: int
    configuration: tuple[tuple[str, tuple[float, ...]], ...]

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this witness."""
        return {
            "sample": self.sample,
            "configuration": {
                name: values[0] if len(values) == 1 else list(values)
                for name, values in self.configuration
            },
        }


class FileRule(NamedTuple):
    """What a file the robot comes with says of one link pair.

    Attributes:
        checked: Whether the tool checks the pair (not disabled in the SRDF, let through
            by MuJoCo's or PhysX's filters).
        reason: Why, as the file says (an SRDF ``reason``, a filter's rule).
        line: The line of the element that says so, or None.
        file: The file of ``line`` when it is not the robot file (the SRDF), or None.
    """

    checked: bool
    reason: str | None
    line: int | None = None
    file: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this rule."""
        return {"checked": self.checked, "reason": self.reason, "line": self.line} | (
            {} if self.file is None else {"file": self.file}
        )


class PairReport(NamedTuple):
    """One pair of links with collision shapes.

    Attributes:
        link1: The first link (names sorted, as MoveIt writes them).
        link2: The second.
        kind: Its class, one of `PAIR_KINDS`.
        collisions: The samples in which the pair collides, with its confidence interval;
            None when the pair was not sampled: an adjacent pair that no file checks
            (MoveIt's setup assistant samples no adjacent pair either).
        witness: The first sample in which it collides, or None.
        rule: What the robot's SRDF, MuJoCo's or PhysX's filters say of it, or None when
            no file says (a URDF without an SRDF).
    """

    link1: str
    link2: str
    kind: str
    collisions: Share | None
    witness: Witness | None = None
    rule: FileRule | None = None

    @property
    def checked(self) -> bool:
        """Whether a planner checks the pair: as its file says, else unless adjacent."""
        return self.rule.checked if self.rule is not None else self.kind != "adjacent"

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this pair."""
        return {
            "link1": self.link1,
            "link2": self.link2,
            "kind": self.kind,
            "collisions": None if self.collisions is None else self.collisions.to_dict(),
            "witness": None if self.witness is None else self.witness.to_dict(),
            "rule": None if self.rule is None else self.rule.to_dict(),
        }


def disabled_but_reachable(pair: PairReport) -> bool:
    """Whether the SRDF disables ``pair`` where the samples show it may collide.

    The pair collides in some samples and is neither adjacent nor always in collision
    (the setup assistant's own ``Adjacent`` and ``Always``); or it is in collision at
    the default configuration, and in samples, but the SRDF disables it for another
    reason than ``Default`` (a ``Never`` the default configuration itself disproves).
    The `collision-disabled-but-reachable` finding, and the pages' pairs against their
    file, are these.
    """
    rule, share = pair.rule, pair.collisions
    if rule is None or rule.checked or share is None or share.hits == 0:
        return False
    return pair.kind == "sometimes" or (pair.kind == "default" and rule.reason != "Default")


class CollidingRange(NamedTuple):
    """A range of one coordinate in which every sample is in self-collision.

    Counted with the pairs cspace would check (`PairReport.kind` ``sometimes``): a range
    where the robot always hits itself whatever the other joints do.

    Attributes:
        coordinate: The coordinate (a joint's name for a one-coordinate joint).
        low: The range's lower end (rad or m).
        high: Its upper end; below ``low`` for a range of a circle across -pi.
        samples: Samples whose coordinate lies in the range, all in collision.
        free_high: The exact 95% upper bound of the free share in the range.
    """

    coordinate: str
    low: float
    high: float
    samples: int
    free_high: float

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this range."""
        return {
            "coordinate": self.coordinate,
            "low": self.low,
            "high": self.high,
            "samples": self.samples,
            "free_high": self.free_high,
        }


class PoseCollision(NamedTuple):
    """A pose the robot's files store, and its link pairs in collision.

    Attributes:
        name: Its name (``group/name`` for an SRDF group state of a name two groups have).
        source: ``keyframe``, ``group_state``, ``initial_value``... as the report lists it.
        line: Its line, or None.
        pairs: The link pairs in collision at it, sorted (of the pairs sampled: an adjacent
            pair only when the file checks it).
        checked: Those of ``pairs`` a planner checks (`PairReport.checked`).
    """

    name: str
    source: str
    line: int | None
    pairs: tuple[tuple[str, str], ...]
    checked: tuple[tuple[str, str], ...]

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this pose."""
        return {
            "name": self.name,
            "source": self.source,
            "line": self.line,
            "pairs": [list(p) for p in self.pairs],
            "checked": [list(p) for p in self.checked],
        }


class CollisionReport(NamedTuple):
    """What ``cspace collisions`` found of one robot.

    Attributes:
        source: The robot file.
        robot: The robot's name.
        tool_version: cspace's version.
        seed: The samples' seed.
        matrix: Which file says which pairs are checked: ``srdf`` (MoveIt's
            ``<disable_collisions>``), ``mjcf`` (MuJoCo's contact filters), ``usd``
            (PhysX's collision filters of an OpenUSD stage), or ``none`` (every pair but
            adjacent ones).
        srdf: The SRDF read, or None.
        links: The links with collision shapes, in the file's order.
        pairs: Every pair of them (names sorted), sorted.
        free: The samples in which no pair the matrix checks collides.
        free_suggested: The samples in which no ``sometimes`` pair collides (the matrix
            `--write-srdf` writes).
        ranges: Coordinate ranges in which every sample collides (``free_suggested``'s
            pairs).
        poses: The stored poses in collision.
        diagnostics: The findings.
    """

    source: Source
    robot: str
    tool_version: str
    seed: int
    matrix: str
    srdf: str | None
    links: tuple[str, ...]
    pairs: tuple[PairReport, ...]
    free: Share
    free_suggested: Share
    ranges: tuple[CollidingRange, ...] = ()
    poses: tuple[PoseCollision, ...] = ()
    diagnostics: tuple[Diagnostic, ...] = ()

    @property
    def samples(self) -> int:
        """How many samples were drawn."""
        return self.free.samples

    def has(self, severity: Severity) -> bool:
        """True when at least one finding has this severity."""
        return any(d.severity is severity for d in self.diagnostics)

    def ignoring(self, codes: set[str] | frozenset[str]) -> "CollisionReport":
        """The same report without the findings whose code is in ``codes``."""
        return self._replace(diagnostics=tuple(d for d in self.diagnostics if d.code not in codes))

    def to_dict(self) -> dict[str, Any]:
        """The JSON document, keys in a fixed order."""
        return {
            "schema_version": COLLISIONS_SCHEMA_VERSION,
            "kind": "collisions",
            "tool": {"name": "cspace", "version": self.tool_version},
            "source": {
                "path": self.source.path,
                "format": self.source.format,
                "sha256": self.source.sha256,
            },
            "robot": self.robot,
            "samples": self.samples,
            "seed": self.seed,
            "matrix": self.matrix,
            "srdf": self.srdf,
            "links": list(self.links),
            "pairs": [p.to_dict() for p in self.pairs],
            "free": self.free.to_dict(),
            "free_suggested": self.free_suggested.to_dict(),
            "ranges": [r.to_dict() for r in self.ranges],
            "poses": [p.to_dict() for p in self.poses],
            "diagnostics": [d.to_dict() for d in self.diagnostics],
        }
