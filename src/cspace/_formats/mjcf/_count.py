"""What an MJCF model expands to, counted before MuJoCo builds anything.

MuJoCo's own parse and compile bound nothing: ``<replicate>`` multiplies, ``<attach>``
copies a model, ``<include>`` splices a file in where it stands, and MuJoCo parses
every ``<model>`` asset whether it is attached or not. So the pre-scan counts, for the
main document and for every model asset: the bodies, joints, elements and equality
constraints after all of that (a replicated element ``count`` times over), the depth of
the body tree, and how deep elements nest once included files are spliced in.

The walk is iterative (an explicit stack of child iterators), never recursive: however
deep a file nests its bodies, frames or includes, nothing here grows Python's stack.
"""

import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

from lxml import etree

from cspace._formats.mjcf._models import ModelAsset, fail_in, name_key, where_text
from cspace._formats.shared.robot_size import MAX_JOINTS
from cspace._formats.shared.xmlio import MAX_TAGS, line_of
from cspace._record import NamedTuple
from cspace.errors import (
    FileUnreadableError,
    InvalidElementError,
    RobotFileError,
    RobotStructureError,
)

MAX_BODIES = MAX_JOINTS + 1
"""Most bodies after ``<replicate>`` and ``<attach>`` (the world not counted)."""

MAX_BODY_DEPTH = 1000
"""Most MJCF bodies on one path from the world, attached models and includes counted
(a ``<frame>`` is no body). MuJoCo's compile time grows about with the cube of the
depth: a 1,000-deep chain takes it 1.2 s of CPU (2-core machine, MuJoCo 4.0), within
its 5 s; MuJoCo itself refuses 1,024 ("depth limit exceeded in signature
computation")."""

MAX_NESTING = 2048
"""Most elements nested on one path of a document, the files it includes spliced in
where they stand (each ``<model>`` file is a document of its own). One file nests at
most 256 deep (libxml2), but includes, 16 deep, would reach 4,336. 2,048 leaves room for
a frame around every body of a `MAX_BODY_DEPTH` chain; MuJoCo parses and compiles
4,000 nested frames in 0.1 s."""

MAX_ELEMENTS = MAX_TAGS
"""Most elements after ``<replicate>`` and ``<attach>``, each copy counted, and every
model asset's own elements once more (MuJoCo parses each, attached or not)."""

MAX_CONSTRAINTS = 1000
"""Most ``<equality>`` constraints. Real models have a few dozen; MuJoCo's compile of
60,000 took more than 1 GiB, and each weld or connect is a walk through the tree."""


@dataclass
class Totals:
    """What one document expands to (or has expanded to so far)."""

    bodies: int = 0
    joints: int = 0
    elements: int = 0
    depth: int = 0
    nesting: int = 0
    constraints: int = 0


class _Level(NamedTuple):
    """The children of one element, being walked, and what they stand under."""

    children: Iterator[etree._Element]
    multiplier: int  # the product of the <replicate> counts above
    depth: int  # bodies above
    nesting: int  # elements above, the document's root included
    file: str | None  # the file they stand in (None: the main file)
    constraints: bool  # the children of an <equality>: each is a constraint


_WHOLE = re.compile(r"[+-]?[0-9]+")


class Counter:
    """Counts documents; an attached model's totals are counted once, before it is attached.

    Args:
        path: The main file, for messages.
        parsed: Each ``<include>`` element read -> the included root and its file name.
    """

    def __init__(
        self, path: str, parsed: Mapping[etree._Element, tuple[etree._Element, str]]
    ) -> None:
        self.path = path
        self.parsed = parsed
        self.totals: dict[ModelAsset, Totals] = {}

    def count(
        self,
        root: etree._Element,
        file: str | None,
        assets: Mapping[str, ModelAsset],
        into: Totals | None = None,
    ) -> Totals:
        """What the document ``root`` (of ``file``) expands to.

        Args:
            root: The document's root element.
            file: Its file (None: the main file).
            assets: Its model assets by name key: what its ``<attach>`` may name.
            into: Totals to add to (a new one when None).

        Raises:
            RobotFileError: Past a limit, or an ``<attach>`` the pre-scan cannot count.
        """
        into = into if into is not None else Totals()
        levels = [_Level(root.iterchildren(tag=etree.Element), 1, 0, 1, file, False)]
        while levels:
            level = levels[-1]
            child = next(level.children, None)
            if child is None:
                levels.pop()
                continue
            included = self.parsed.get(child)
            if included is not None:  # its file's children stand where it stands
                other, name = included
                children = other.iterchildren(tag=etree.Element)
                levels.append(level._replace(children=children, file=name))
                continue
            levels.append(self._add(child, level, into, assets))
            self.check(into, child, level.file)
        self.check(into, root, file)
        return into

    def _add(
        self,
        element: etree._Element,
        level: _Level,
        into: Totals,
        assets: Mapping[str, ModelAsset],
    ) -> _Level:
        """Count ``element`` itself; the level its children stand at."""
        tag = element.tag
        multiplier, depth, nesting = level.multiplier, level.depth, level.nesting + 1
        into.elements += multiplier
        into.nesting = max(into.nesting, nesting)
        if level.constraints:
            into.constraints += multiplier
        if tag == "replicate":
            multiplier *= self._whole(element, level.file)
        elif tag == "body":
            into.bodies += multiplier
            depth += 1
            into.depth = max(into.depth, depth)
        elif tag in ("joint", "freejoint") and depth > 0:
            into.joints += multiplier
        elif tag == "flexcomp":  # a body (with up to 3 slides) per point
            inline = len(str(element.get("point", "")).split()) // 3
            points = max(self._whole(element, level.file, 3), inline)
            into.bodies += multiplier * points
            into.joints += multiplier * points * 3
            into.elements += multiplier * points
        elif tag == "attach":
            part = self._attached(element, level.file, assets)
            into.bodies += multiplier * part.bodies
            into.joints += multiplier * part.joints
            into.elements += multiplier * part.elements
            into.constraints += multiplier * part.constraints
            into.depth = max(into.depth, depth + part.depth)
        children = element.iterchildren(tag=etree.Element)
        return _Level(children, multiplier, depth, nesting, level.file, tag == "equality")

    def _attached(
        self, element: etree._Element, file: str | None, assets: Mapping[str, ModelAsset]
    ) -> Totals:
        """The totals of the model an ``<attach>`` attaches, as MuJoCo resolves its name.

        Raises:
            InvalidElementError: An ``<attach>`` of a body or frame of the same document
                (no ``model``), or of a name no model asset of the document has
                (``unsupported-element``).
        """
        if "model" not in element.attrib:
            raise fail_in(
                self.path,
                file,
                "unsupported-element",
                "<attach> without a model attaches a copy of a body or frame of this same "
                "model; cspace attaches only a <model> asset read from its file",
                element,
            )
        name = str(element.get("model"))
        model = assets.get(name_key(name))
        part = None if model is None else self.totals.get(model)
        if part is None:  # a body of this file, or a model not read
            raise fail_in(
                self.path,
                file,
                "unsupported-element",
                f'<attach model="{name}">: cspace attaches only a <model> asset read from its '
                "file, and no asset of this document is named so",
                element,
            )
        return part

    def _whole(self, element: etree._Element, file: str | None, numbers: int = 1) -> int:
        """The product of the (first ``numbers``) whole numbers of ``count``, at least 1.

        Raises:
            InvalidElementError: A word that is not a whole number as MuJoCo reads one
                (an optional sign, then digits): cspace could not bound what it makes.
        """
        product = 1
        for word in str(element.get("count", "1")).split()[:numbers]:
            if not _WHOLE.fullmatch(word):
                raise fail_in(
                    self.path,
                    file,
                    "bad-number",
                    f'<{element.tag} count="{element.get("count")}">: "{word}" is not a whole '
                    "number",
                    element,
                )
            digits = word.lstrip("+-").lstrip("0")
            # past 12 digits, more than any limit (and int() of 4,301 digits raises)
            product *= 10**12 if len(digits) > 12 else max(1, int(word))
        return product

    def check(self, totals: Totals, element: etree._Element, file: str | None) -> None:
        """Refuse totals past a limit, at ``element`` (of ``file``) where they got there.

        Raises:
            RobotStructureError: Too many bodies or joints (``too-many-joints``), bodies
                or elements nested too deep (``too-deep``).
            FileUnreadableError: Too many elements (``too-much-input``).
            InvalidElementError: Too many equality constraints (``too-many-constraints``).
        """
        if (
            totals.bodies <= MAX_BODIES
            and totals.joints <= MAX_JOINTS
            and totals.depth <= MAX_BODY_DEPTH
            and totals.nesting <= MAX_NESTING
            and totals.elements <= MAX_ELEMENTS
            and totals.constraints <= MAX_CONSTRAINTS
        ):
            return  # the common case, at every element: no message made
        over: tuple[tuple[bool, str, type[RobotFileError], str], ...] = (
            (
                totals.bodies > MAX_BODIES,
                f"more than {MAX_BODIES:,} bodies",
                RobotStructureError,
                "too-many-joints",
            ),
            (
                totals.joints > MAX_JOINTS,
                f"more than {MAX_JOINTS:,} joints",
                RobotStructureError,
                "too-many-joints",
            ),
            (
                totals.depth > MAX_BODY_DEPTH,
                f"bodies nested more than {MAX_BODY_DEPTH:,} deep",
                RobotStructureError,
                "too-deep",
            ),
            (
                totals.nesting > MAX_NESTING,
                f"elements nested more than {MAX_NESTING:,} deep",
                RobotStructureError,
                "too-deep",
            ),
            (
                totals.elements > MAX_ELEMENTS,
                f"more than {MAX_ELEMENTS:,} elements",
                FileUnreadableError,
                "too-much-input",
            ),
            (
                totals.constraints > MAX_CONSTRAINTS,
                f"more than {MAX_CONSTRAINTS:,} equality constraints",
                InvalidElementError,
                "too-many-constraints",
            ),
        )
        for hit, what, error, code in over:
            if hit:
                problem = (
                    f"the model expands (<replicate>, <attach>, <include>) to {what}, "
                    "more than cspace gives MuJoCo's compiler"
                )
                if file is not None:
                    problem += f" (in {where_text(file, element)})"
                raise error(
                    self.path,
                    problem,
                    line=line_of(element) if file is None else None,
                    element=str(element.tag),
                    code=code,
                )
