"""The URDF document Pinocchio's parser is given: the robot as the reader read it.

:func:`document_for_pinocchio` serialises the ``<link>`` and ``<joint>`` elements the
reader read, with the numbers urdfdom would refuse rewritten (the reader's fixes), and
without the ``<mimic>`` elements the report ignores.
"""

from __future__ import annotations

from collections.abc import Sequence

from lxml import etree

Fix = tuple[etree._Element, str, str]
"""An attribute to rewrite for urdfdom: the element, the attribute, the new value."""

KEPT = ("link", "joint")
"""The elements Pinocchio's model is built from; urdfdom need not parse the others."""


def document_for_pinocchio(
    root: etree._Element, fixes: Sequence[Fix], without_mimic: frozenset[str] = frozenset()
) -> str:
    """The robot's links and joints as read, with every number urdfdom would refuse rewritten.

    The elements are serialised by lxml, so Pinocchio's XML parser sees exactly what
    this reader saw (encoding, character references and attribute white space
    resolved once). Only ``<link>`` and ``<joint>`` elements are kept (Pinocchio's
    model reads nothing else; ``<gazebo>``, ``<transmission>`` and the like need
    not be parsed twice), and of the root's attributes only ``name`` (urdfdom would
    read a ``version``). The joints named in ``without_mimic`` lose their ``<mimic>``
    (one this report ignores).

    The tree is serialised in one call with what is left out taken out of it, and
    put back afterwards, with the fixes undone: ``root`` is as it was on return.
    """
    saved = [(element, key, element.get(key)) for element, key, _ in fixes]
    attributes = list(root.attrib.items())
    root_name = root.get("name") or ""
    hidden: list[tuple[etree._Element, int, etree._Element]] = []  # parent, index, element
    try:
        for element, key, value in fixes:
            element.set(key, value)
        for index, child in reversed(list(enumerate(root))):
            if isinstance(child.tag, str) and child.tag not in KEPT:
                hidden.append((root, index, child))
                root.remove(child)
            elif child.tag == "joint" and child.get("name") in without_mimic:
                for mimic in reversed(child.findall("mimic")):
                    hidden.append((child, child.index(mimic), mimic))
                    child.remove(mimic)
        root.attrib.clear()
        root.set("name", root_name)
        return etree.tostring(root, encoding="unicode", with_tail=False)
    finally:
        root.attrib.clear()
        for attribute, text in attributes:
            root.set(attribute, text)
        for parent, index, element in reversed(hidden):
            parent.insert(index, element)
        for element, key, old in reversed(saved):
            element.set(key, old or "")
