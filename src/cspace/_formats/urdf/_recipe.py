"""The URDF document Pinocchio's parser is given: the robot as the reader read it.

`document_for_pinocchio` serialises the ``<link>`` and ``<joint>`` elements the
reader read, with the numbers urdfdom would refuse rewritten (the reader's fixes), and
without the ``<mimic>`` elements the report ignores.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence

from lxml import etree

Fix = tuple[etree._Element, str, str]
"""An attribute to rewrite for urdfdom: the element, the attribute, the new value."""

KEPT = ("link", "joint")
"""The elements Pinocchio's model is built from; urdfdom need not parse the others."""


def document_for_pinocchio(
    root: etree._Element,
    fixes: Sequence[Fix],
    without_mimic: frozenset[str] = frozenset(),
    stand_ins: Sequence[tuple[etree._Element, str]] = (),
    added_links: Sequence[str] = (),
) -> str:
    """The robot's links and joints as read, with every number urdfdom would refuse rewritten.

    The elements are serialised by lxml, so Pinocchio's XML parser sees exactly what
    this reader saw (encoding, character references and attribute white space
    resolved once). Only ``<link>`` and ``<joint>`` elements are kept (Pinocchio's
    model reads nothing else; ``<gazebo>``, ``<transmission>`` and the like need
    not be parsed twice), and of the root's attributes only ``name`` (urdfdom would
    read a ``version``). The joints named in ``without_mimic`` lose their ``<mimic>``
    (one this report ignores). Each ``<drake:joint>`` of ``stand_ins`` is given as a
    ``<joint>`` of the type paired with it, with its name, parent, child and origin.
    Each of ``added_links`` is declared first, as an empty ``<link>`` (a ``world`` the
    file names but does not declare, see `urdf._world`).

    The root's content is serialised in one call, with what is left out taken out of
    the tree and put back afterwards in linear time (every child appended again, in
    order), and the fixes undone: ``root`` is as it was on return.
    """
    saved = [(element, key, element.get(key)) for element, key, _ in fixes]
    emptied: list[tuple[etree._Element, list[etree._Element]]] = []  # parent, its children
    try:
        for element, key, value in fixes:
            element.set(key, value)
        _keep_only(root, lambda child: child.tag in KEPT, emptied)
        for joint in root.iterchildren("joint"):
            if joint.get("name") in without_mimic:
                _keep_only(joint, lambda child: child.tag != "mimic", emptied)
        text = etree.tostring(root, encoding="unicode", with_tail=False)
        added = "".join(_stand_in(element, kind) for element, kind in stand_ins)
    finally:
        for parent, children in reversed(emptied):
            for child in children:  # appending a child moves it: the old order, linearly
                parent.append(child)
        for element, key, old in reversed(saved):
            element.set(key, old or "")
    name = _escape_attribute(root.get("name") or "")
    # The root's own start tag (its attributes and namespace declarations) is replaced;
    # lxml escapes ">" in attribute values, so the first ">" ends it.
    content = "" if text.endswith("/>") else text[text.index(">") + 1 : text.rindex("</")]
    declared = "".join(f'<link name="{_escape_attribute(link)}"/>' for link in added_links)
    return f'<robot name="{name}">{declared}{content}{added}</robot>'


def _stand_in(element: etree._Element, joint_type: str) -> str:
    """A ``<joint>`` of ``joint_type`` with the name, parent, child and origin of ``element``."""
    joint = etree.Element("joint", name=element.get("name", ""), type=joint_type)
    for sub in element.iterchildren("parent", "child", "origin"):
        joint.append(copy.deepcopy(sub))
    return etree.tostring(joint, encoding="unicode", with_tail=False)


def _keep_only(
    parent: etree._Element,
    keep: Callable[[etree._Element], bool],
    emptied: list[tuple[etree._Element, list[etree._Element]]],
) -> None:
    """Take out of ``parent`` the children ``keep`` refuses (and every non-element node).

    ``parent`` and its children as they were are added to ``emptied``, to be put back.
    """
    children = list(parent)
    if all(isinstance(child.tag, str) and keep(child) for child in children):
        return
    emptied.append((parent, children))
    for child in children:
        if not (isinstance(child.tag, str) and keep(child)):
            parent.remove(child)


def _escape_attribute(text: str) -> str:
    """``text`` as the value of a double-quoted XML attribute (white space kept exactly)."""
    for raw, escaped in _ATTRIBUTE_ESCAPES:
        text = text.replace(raw, escaped)
    return text


_ATTRIBUTE_ESCAPES = (
    ("&", "&amp;"),
    ("<", "&lt;"),
    ('"', "&quot;"),
    ("\t", "&#9;"),
    ("\n", "&#10;"),
    ("\r", "&#13;"),
)
