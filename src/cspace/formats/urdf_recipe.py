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


def document_for_pinocchio(
    root: etree._Element, fixes: Sequence[Fix], without_mimic: frozenset[str] = frozenset()
) -> str:
    """The robot's links and joints as read, with every number urdfdom would refuse rewritten.

    The elements are serialised by lxml, so Pinocchio's XML parser sees exactly what
    this reader saw (encoding, character references and attribute white space
    resolved once). Only ``<link>`` and ``<joint>`` elements are kept (Pinocchio's
    model reads nothing else; ``<gazebo>``, ``<transmission>`` and the like need
    not be parsed twice). The fixes are undone afterwards. The joints named in
    ``without_mimic`` lose their ``<mimic>`` (one this report ignores).
    """
    saved = [(element, key, element.get(key)) for element, key, _ in fixes]
    for element, key, value in fixes:
        element.set(key, value)
    try:
        parts = [f'<robot name="{escape_attribute(root.get("name") or "")}">']
        parts.extend(
            etree.tostring(
                without_mimic_element(child, without_mimic), encoding="unicode", with_tail=False
            )
            for child in root.iterchildren("link", "joint")
        )
        parts.append("</robot>")
        return "\n".join(parts)
    finally:
        for element, key, old in reversed(saved):
            element.set(key, old or "")


def escape_attribute(text: str) -> str:
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


def without_mimic_element(element: etree._Element, names: frozenset[str]) -> etree._Element:
    """``element``, or a copy without its ``<mimic>`` when it is a joint named in ``names``."""
    if element.tag != "joint" or element.get("name") not in names:
        return element
    copy = etree.fromstring(etree.tostring(element))
    for mimic in copy.findall("mimic"):
        copy.remove(mimic)
    return copy
