"""What makes a file an SRDF, for the loader of one file and for a folder's search.

An SRDF (MoveIt's semantic description) has a ``<robot>`` root, as a URDF has, and is
told by its content, which beats its name: outside the SRDF elements (`SRDF_ELEMENTS`,
MoveIt's and Pinocchio's), no ``<link>``, no ``<joint>`` (a group's ``<joint name>`` is
the SRDF's; a ``<joint>`` in a ``<ros2_control>`` block, even in a macro, is a URDF's)
and no xacro element that could make one (a macro call, an include: only definitions,
conditions and arguments); and at least one SRDF element, or a name that says SRDF
(``.srdf``, ``.srdf.xacro``, in any case): the name decides only a ``<robot>`` that
holds neither a robot's elements nor an SRDF's. A ``.srdf`` file that holds a link is a
robot, read as a URDF. Names are taken as written (``xacro:include``, ``link``), as
xacro and the URDF readers take them, whatever namespace a prefix is bound to.

The search reads the bytes (`srdf.bytes_scan`), the loader the parsed tree (`srdf_tree`); both
by this one rule. Where the search cannot be sure (a xacro call, whose output only xacro
knows; an entity; a file past the size cap), the file is inspected, and its reader,
which parses it whole (and expands a xacro file), tells: an SRDF is never a robot of its
own, and is refused in one line saying how it is read (``--srdf``; `SRDF_CODE`), which
a search's caller takes for a note.
"""

from __future__ import annotations

from lxml import etree

from cspace._formats.shared.roots import SRDF_CODE, SRDF_ELEMENTS, URDF_ELEMENTS, XACRO_QUIET
from cspace._formats.shared.xmlio import line_of
from cspace.errors import NotARobotError

_QUIET = frozenset(f"xacro:{name}" for name in XACRO_QUIET)


def _written(element: etree._Element) -> str:
    """An element's name as written: ``xacro:macro``, ``link`` (a default namespace aside)."""
    tag = element.tag if isinstance(element.tag, str) else ""
    local = etree.QName(tag).localname if tag.startswith("{") else tag
    return f"{element.prefix}:{local}" if element.prefix else local


def srdf_tree(root: etree._Element, *, named: bool = False) -> bool:
    """Whether a parsed ``<robot>`` is an SRDF by its content (see the module).

    ``named``: the file's name says SRDF, which decides a root that holds neither a
    robot's elements nor an SRDF's. An iterative walk that stops at the first URDF
    element; SRDF elements are not entered.
    """
    if _written(root) != "robot":
        return False
    found = False
    stack = list(root.iterchildren(tag=etree.Element))
    while stack:
        element = stack.pop()
        name = _written(element)
        if name.startswith("xacro:"):
            if name not in _QUIET:
                return False  # a call or an include: it may make links
        elif name in SRDF_ELEMENTS:
            found = True
            continue
        elif name in URDF_ELEMENTS:
            return False
        stack.extend(element.iterchildren(tag=etree.Element))
    return found or named


def refuse_srdf(
    path: str, root: etree._Element, *, named: bool, written: etree._Element | None = None
) -> None:
    """Refuse an SRDF named as a robot, in one line that says how it is read.

    Args:
        path: The file, as named.
        root: Its parsed root, or the root of what xacro made of it.
        named: The file's name says SRDF (`named_srdf`).
        written: The file's own root when ``root`` is xacro's output, else None.

    Raises:
        NotARobotError: ``root`` is an SRDF by its content (`srdf_tree`; code
            `SRDF_CODE`).
    """
    if not srdf_tree(root, named=named):
        return
    name = root.get("name")
    of = f" of robot '{name}'" if name else ""
    if written is None and not path.lower().endswith(".xacro"):
        file = "FILE" if path == "-" else path  # standard input: --srdf reads a file
        how = f"read it with its URDF: cspace inspect ROBOT.urdf --srdf {file} (or --srdf auto)"
    else:  # xacro makes it: --srdf reads the SRDF xacro writes
        how = "expand it with xacro, then read it with its URDF: --srdf FILE"
    raise NotARobotError(
        path,
        f"an SRDF (MoveIt's semantic description{of}), not a robot: {how}",
        code=SRDF_CODE,
        line=line_of(root if written is None else written),
        element="robot",
    )
