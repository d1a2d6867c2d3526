"""What makes a file an SRDF, for the loader of one file and for a folder's search.

An SRDF (MoveIt's semantic description) has a ``<robot>`` root, as a URDF has: it is
told by its name (``.srdf``, ``.srdf.xacro``, in any case) or by its content: at least
one of MoveIt's and Pinocchio's SRDF elements (`SRDF_ELEMENTS`), no ``<link>`` or
``<joint>`` outside them (a group's ``<joint name>`` is the SRDF's; a ``<joint>`` in a
``<ros2_control>`` block, even in a macro, is a URDF's), and no xacro element that could
make one (a macro call, an include: only definitions, conditions and arguments). The
search reads the bytes (`_xml_srdf`), the loader the parsed tree (`srdf_tree`); both by
this one rule. An SRDF is never a robot of its own: a search leaves it out, and the
loader refuses it in one line saying how it is read (``--srdf``).
"""

from __future__ import annotations

from lxml import etree

from cspace._formats._roots import (
    SRDF_ELEMENTS,
    URDF_ELEMENTS,
    XACRO_NAMESPACE,
    XACRO_QUIET,
    named_srdf,
)
from cspace._formats.xmlio import line_of
from cspace.errors import NotARobotError


def srdf_tree(root: etree._Element) -> bool:
    """Whether a parsed ``<robot>`` is an SRDF by its content (see the module).

    An iterative walk that stops at the first URDF element; SRDF elements are not
    entered.
    """
    if root.tag != "robot":
        return False
    found = False
    stack = list(root.iterchildren(tag=etree.Element))
    while stack:
        element = stack.pop()
        tag = element.tag if isinstance(element.tag, str) else ""
        local = etree.QName(tag).localname if tag.startswith("{") else tag
        xacro = element.prefix == "xacro" or tag.startswith(f"{{{XACRO_NAMESPACE}}}")
        if xacro and local not in XACRO_QUIET:
            return False  # a call or an include: it may make links
        if not xacro and local in SRDF_ELEMENTS:
            found = True
            continue
        if not xacro and local in URDF_ELEMENTS:
            return False
        stack.extend(element.iterchildren(tag=etree.Element))
    return found


def refuse_srdf(path: str, root: etree._Element, *, by_name: bool = True) -> None:
    """Refuse an SRDF named as a robot, in one line that says how it is read.

    ``by_name``: ``path`` is the file's name, which may say SRDF (not xacro's output).

    Raises:
        NotARobotError: ``path`` is named ``.srdf`` or ``.srdf.xacro`` (with
            ``by_name``), or ``root`` is an SRDF by its content (code ``srdf-not-robot``).
    """
    if root.tag != "robot" or not ((by_name and named_srdf(path)) or srdf_tree(root)):
        return
    name = root.get("name")
    of = f" of robot '{name}'" if name else ""
    if by_name and not path.lower().endswith(".xacro"):
        file = "FILE" if path == "-" else path  # standard input: --srdf reads a file
        how = f"read it with its URDF: cspace inspect ROBOT.urdf --srdf {file} (or --srdf auto)"
    else:  # xacro makes it: --srdf reads the SRDF xacro writes
        how = "expand it with xacro, then read it with its URDF: --srdf FILE"
    raise NotARobotError(
        path,
        f"an SRDF (MoveIt's semantic description{of}), not a robot: {how}",
        code="srdf-not-robot",
        line=line_of(root),
        element="robot",
    )
