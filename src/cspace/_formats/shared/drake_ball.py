"""Drake's ``<drake:ball_constraint>``, in URDF and SDF: a point of one body held on another's.

Drake's parsers (``AddBallConstraint``) read, in URDF, as children of ``<robot>``::

    <drake:ball_constraint>
      <drake:ball_constraint_body_A name="A"/>
      <drake:ball_constraint_body_B name="B"/>
      <drake:ball_constraint_p_AP value="x y z"/>
      <drake:ball_constraint_p_BQ value="x y z"/>
    </drake:ball_constraint>

and in SDF, as children of a ``<model>``, the same four elements with their values as
text (``<drake:ball_constraint_body_A>A</drake:ball_constraint_body_A>``). The point P,
at ``p_AP`` in body A's frame (m), and the point Q, at ``p_BQ`` in body B's, coincide:
a ball joint that closes a loop (`CutSpec` with ``free="rotation"``). Each element is
matched by its ``drake`` prefix, as Drake matches it (see `urdf._drake.is_drake_joint`).
Drake's constraints have no name: cspace names each ``ball_constraint<K>``, K counting
from 0 in file order.
"""

from __future__ import annotations

from collections.abc import Callable

from lxml import etree

from cspace._formats.shared.description import CutSpec
from cspace._formats.shared.pose import Pose
from cspace._formats.shared.xmlio import fail_at, line_of
from cspace._formats.urdf._drake import is_drake
from cspace._formats.urdf.numbers import parse_number
from cspace.errors import RobotStructureError

KIND = "drake:ball_constraint"
"""The cut's kind, as the file names it."""


def ball_constraint(
    path: str,
    element: etree._Element,
    index: int,
    value: Callable[[etree._Element], str | None],
    link: Callable[[str], str | None],
) -> CutSpec:
    """One ``<drake:ball_constraint>`` as a cut.

    Args:
        path: The file, for messages.
        element: The ``<drake:ball_constraint>``.
        index: Its place among the file's ball constraints (its name's number).
        value: A part's value as the format writes it (URDF: its ``name`` or ``value``
            attribute; SDF: its text), None when absent.
        link: The link a body name written in the element names (scoped, for SDF), or
            None when no link has that name.

    Raises:
        InvalidElementError: A part missing or given twice, or a point that is not three
            numbers (NaN and infinities are numbers: the closure analysis says they
            cannot close a loop).
        RobotStructureError: A body that is no link (``missing-link``).
    """
    name = f"ball_constraint{index}"
    owner = f"<drake:ball_constraint> '{name}'"
    parts: dict[str, str] = {}
    for part in ("body_A", "body_B", "p_AP", "p_BQ"):
        found = [c for c in element if is_drake(c, f"ball_constraint_{part}")]
        if len(found) != 1:
            problem = "has no" if not found else f"has {len(found)}"
            fail_at(
                path,
                "missing-element",
                f"{owner} {problem} <drake:ball_constraint_{part}>",
                element,
                name,
            )
        text = value(found[0])
        if text is None or not text.strip():
            what = "name" if part.startswith("body") else "value"
            fail_at(
                path,
                "missing-attribute",
                f"{owner}: <drake:ball_constraint_{part}> gives no {what}",
                found[0],
                name,
            )
        parts[part] = text.strip()
    links = []
    for part in ("body_A", "body_B"):
        found_link = link(parts[part])
        if found_link is None:
            raise RobotStructureError(
                path,
                f"{owner} names {part} '{parts[part][:80]}', which is no link",
                code="missing-link",
                line=line_of(element),
                element=name,
            )
        links.append(found_link)
    points = []
    for part in ("p_AP", "p_BQ"):
        words = parts[part].split()
        numbers = [parse_number(word) for word in words]
        if len(numbers) != 3 or any(n is None for n in numbers):
            fail_at(
                path,
                "bad-number",
                f"{owner}: <drake:ball_constraint_{part}> '{parts[part][:80]}' is not "
                "three numbers",
                element,
                name,
            )
        x, y, z = (float(n) for n in numbers if n is not None)
        points.append(Pose((x, y, z)))
    return CutSpec(
        kind=KIND,
        name=name,
        link_a=links[0],
        frame_a=points[0],
        link_b=links[1],
        frame_b=points[1],
        free="rotation",
        line=line_of(element),
    )
