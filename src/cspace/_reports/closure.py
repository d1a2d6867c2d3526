"""What a report says of a mechanism's closed kinematic chains: the ``closure`` object.

A robot whose file closes loops (MJCF ``connect``/``weld``, an SDF joint whose child
already has a parent, an OpenUSD joint left out of the articulation, Drake's
``drake:ball_constraint``) has two spaces: the tree's (the report's manifold, the
ambient space) and the mechanism's, the subset of it where every loop closes (LaValle,
*Planning Algorithms*, section 4.4). This record says what is known of the second:
its constraints, Grübler-Kutzbach's count, and the mobility found from the rank of
the constraint Jacobian at configurations found on it.
"""

from collections.abc import Mapping
from typing import Any

from cspace._record import NamedTuple


class Cut(NamedTuple):
    """One closing constraint, as the file writes it.

    Attributes:
        kind: As the file names it (``connect``, ``weld``, ``ball``, ``revolute``...).
        name: Its name.
        links: The two links it holds together.
        rows: How many scalar equations it makes (3 to 6).
        line: Its line in the robot file, or None.
        free: What it leaves free: ``rotation`` (3 rows), ``none`` (6), ``revolute`` or
            ``prismatic`` (5, about or along ``axis``).
        frames: Where it holds the links: the frame on the first link, in its frame
            (position, m, then unit quaternion w x y z with w >= 0), then the frame on the
            second, in its frame: 14 numbers.
        axis: The free axis (unit, in the first frame) of a revolute or prismatic cut.
    """

    kind: str
    name: str
    links: tuple[str, str]
    rows: int
    line: int | None = None
    free: str = "none"
    frames: tuple[float, ...] = ()
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)

    def to_dict(self, file: str) -> dict[str, Any]:
        """Its JSON object; ``file`` is the report's robot file."""
        a, b = self.frames[:7], self.frames[7:]
        return {
            "kind": self.kind,
            "name": self.name,
            "links": list(self.links),
            "rows": self.rows,
            "file": file,
            "line": self.line,
            "free": self.free,
            "frame_a": {"position": list(a[:3]), "rotation_wxyz": list(a[3:])},
            "frame_b": {"position": list(b[:3]), "rotation_wxyz": list(b[3:])},
            "axis": list(self.axis),
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Cut":
        """The cut of a JSON object `to_dict` wrote."""
        first, second = (str(link) for link in document["links"])
        line = document.get("line")
        frames = tuple(
            float(x)
            for side in ("frame_a", "frame_b")
            for part in ("position", "rotation_wxyz")
            for x in document[side][part]
        )
        x, y, z = (float(v) for v in document["axis"])
        return cls(
            str(document["kind"]),
            str(document["name"]),
            (first, second),
            int(document["rows"]),
            None if line is None else int(line),
            str(document["free"]),
            frames,
            (x, y, z),
        )


class Singularity(NamedTuple):
    """A configuration on the mechanism where the constraints' rank drops.

    Attributes:
        rank: The constraint Jacobian's rank there (below the highest seen).
        configuration: The configuration (the report's canonical coordinates).
    """

    rank: int
    configuration: tuple[float, ...]


class Closure(NamedTuple):
    """The closed chains of a mechanism, as cspace found them.

    Attributes:
        loops: Independent loops: the cuts, a pair of links held together twice (two
            connects make a hinge) counted once.
        cuts: The closing constraints, in file order (those the analysis left out, each
            with a ``closure-invalid`` finding, are not among them).
        constraint_rows: Scalar equations in all, the sum of the cuts' rows.
        grubler: The tree's dimension minus ``constraint_rows`` (Grübler-Kutzbach's
            count; wrong when the equations are dependent).
        mobility: The tree's dimension minus the highest rank of the constraint
            Jacobian seen on the mechanism (its dimension at regular points), or None
            when no configuration closed every loop or none was sought.
        samples: Configurations found on the mechanism (each closes every loop).
        attempts: Configurations projected to find them.
        rank: The lowest and highest rank of the constraint Jacobian at the samples, or
            None without samples.
        max_residual: The largest absolute residual (m, rad) of the samples kept, to
            three significant digits (at most `ASSEMBLED_TOLERANCE`), or None without
            samples.
        assembled: False when no configuration tried closes every loop.
        singularities: Samples where the rank is below the highest (at most
            `MAX_SINGULARITIES`).
        actuated: The joints taken as the ones commanded (the file's actuated joints),
            in file order.
        chart: Whether the actuated joints (with the joints on no loop) are coordinates
            of the mechanism (at a sample: the passive joints' Jacobian block of full
            column rank, its rank the constraints'): True when they are at some samples
            (a ``closure-chart-singular`` finding counts the others), False at none;
            None when no joint is named actuated or without samples.
    """

    loops: int
    cuts: tuple[Cut, ...]
    constraint_rows: int
    grubler: int
    mobility: int | None
    samples: int
    attempts: int
    rank: tuple[int, int] | None
    max_residual: float | None
    assembled: bool | None
    singularities: tuple[Singularity, ...] = ()
    actuated: tuple[str, ...] = ()
    chart: bool | None = None

    def to_dict(self, file: str) -> dict[str, Any]:
        """The JSON object (``closure`` of the report); ``file`` is the robot file."""
        return {
            "loops": self.loops,
            "cuts": [cut.to_dict(file) for cut in self.cuts],
            "constraint_rows": self.constraint_rows,
            "grubler": self.grubler,
            "mobility": self.mobility,
            "samples": self.samples,
            "attempts": self.attempts,
            "rank": None
            if self.rank is None
            else {"lowest": self.rank[0], "highest": self.rank[1]},
            "max_residual": self.max_residual,
            "assembled": self.assembled,
            "singularities": [
                {"rank": s.rank, "configuration": list(s.configuration)} for s in self.singularities
            ],
            "actuated": list(self.actuated),
            "chart": self.chart,
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Closure":
        """The record of a JSON object `to_dict` wrote (a checked saved report's)."""
        rank = document.get("rank")
        residual = document.get("max_residual")
        mobility = document.get("mobility")
        chart = document.get("chart")
        return cls(
            loops=int(document["loops"]),
            cuts=tuple(Cut.from_dict(c) for c in document["cuts"]),
            constraint_rows=int(document["constraint_rows"]),
            grubler=int(document["grubler"]),
            mobility=None if mobility is None else int(mobility),
            samples=int(document["samples"]),
            attempts=int(document["attempts"]),
            rank=None if rank is None else (int(rank["lowest"]), int(rank["highest"])),
            max_residual=None if residual is None else float(residual),
            assembled=None if document.get("assembled") is None else bool(document["assembled"]),
            singularities=tuple(
                Singularity(int(s["rank"]), tuple(float(x) for x in s["configuration"]))
                for s in document.get("singularities", ())
            ),
            actuated=tuple(str(j) for j in document.get("actuated", ())),
            chart=None if chart is None else bool(chart),
        )

    @property
    def summary(self) -> str:
        """One line: ``closed chains: 4 loops, mobility 10 (Grübler 10)``.

        ``not assembled`` when no configuration tried closes every loop, ``mobility not
        sought`` when none was tried (``assembled`` None: too large, or no model).
        """
        loops = f"{self.loops} loop{'' if self.loops == 1 else 's'}"
        if self.assembled is False:
            return f"closed chains: {loops}, not assembled (Grübler {self.grubler})"
        if self.assembled is None:
            return f"closed chains: {loops}, Grübler {self.grubler}, mobility not sought"
        if self.mobility is None:
            return f"closed chains: {loops}, Grübler {self.grubler}, mobility not found"
        return f"closed chains: {loops}, mobility {self.mobility} (Grübler {self.grubler})"


ASSEMBLED_TOLERANCE = 1e-6
"""Largest residual (m, rad) of a configuration the analysis takes as on the mechanism:
files write their numbers to six digits or so, and a loop's frames or axes rounded so
leave it open by that much wherever it moves (example-robot-data's Cassie: 9e-9 m)."""

MAX_SINGULARITIES = 8
"""Most singular configurations a report lists."""
