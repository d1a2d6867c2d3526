"""A URDF document's elements, read and checked as urdfdom reads them.

`ElementReader` reads a ``<joint>`` (its type, ``<parent>`` and ``<child>``, ``<axis>``,
``<limit>``, ``<mimic>``) into a `JointSpec`, and checks what urdfdom parses although
the configuration space does not depend on it (``<origin>``, ``<dynamics>``,
``<safety_controller>``, ``<calibration>``), so that a broken file gets one precise
message with its line instead of the parser's. A number urdfdom would refuse but the
report can still describe is kept as a fix for the document Pinocchio's parser is given.
"""

from __future__ import annotations

import math
from typing import NoReturn

from lxml import etree

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, MimicSpec
from cspace._formats.shared.xmlio import check_joint_type, fail_at, line_of
from cspace._formats.urdf.numbers import (
    URDFDOM_NUMBER,
    URDFDOM_VECTOR,
    for_urdfdom,
    parse_number,
    urdfdom_accepts,
)
from cspace._joint_kind import JointKind

URDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
"""The joint types the URDF specification defines."""

LIMIT_REQUIRED = ("revolute", "prismatic")
"""URDF types whose ``<limit>`` element is required."""

MIMIC_TYPES = ("revolute", "continuous", "prismatic")
"""URDF types a ``<mimic>`` applies to (one coordinate each); Pinocchio ignores it on others."""

URDF_KINDS = {
    "revolute": JointKind.REVOLUTE,
    "continuous": JointKind.CONTINUOUS,
    "prismatic": JointKind.PRISMATIC,
    "fixed": JointKind.FIXED,
    "floating": JointKind.FLOATING,
    "planar": JointKind.PLANAR,
}
"""Each URDF joint type in cspace's words."""

NO_AXIS = ("fixed", "floating")
"""URDF types whose ``<axis>`` is ignored (urdfdom does not read it)."""


# Optional numeric attributes of the joint's other elements, which urdfdom parses (and
# refuses when malformed) although the C-space does not depend on them.
_OTHER_NUMBERS = {
    "dynamics": ("damping", "friction"),
    "safety_controller": ("soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"),
    "calibration": ("rising", "falling"),
}
_MAGNITUDES = ("effort", "velocity", "friction")
"""Attributes that are magnitudes: Pinocchio refuses negative ones."""
_REQUIRED = {
    "limit": ("effort", "velocity"),
    "safety_controller": ("k_velocity",),
}


class ElementReader:
    """Reads one URDF document's elements, keeping findings and fixes for Pinocchio's copy."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.findings: list[Diagnostic] = []
        self.fixes: list[tuple[etree._Element, str, str]] = []
        self.joint_name: str | None = None
        self.children: dict[str, etree._Element] = {}
        self.rates: tuple[tuple[str, float], ...] = ()  # the last <limit>'s effort, velocity
        self.soft: tuple[float, float] | None = None  # its <safety_controller>'s

    def fail(self, code: str, problem: str, element: etree._Element, name: str | None) -> NoReturn:
        """Raise an `InvalidElementError` about ``name`` (default: the current joint)."""
        fail_at(self.path, code, problem, element, name or self.joint_name)

    def attribute(self, element: etree._Element, key: str, owner: str | None) -> str:
        """A required, non-empty attribute; ``owner`` None: the element is its own owner."""
        value = element.get(key)
        if value is not None and (stripped := value.strip()):
            return stripped  # the usual case, before any message is built
        where = "" if owner is None else f"{owner}: "
        tag = etree.QName(element).localname  # as written: drake:joint, not {uri}joint
        tag = f"{element.prefix}:{tag}" if element.prefix else tag
        if value is None:
            self.fail(
                "missing-attribute",
                f"{where}<{tag}> has no '{key}' attribute",
                element,
                None,
            )
        if not str(value).strip():
            self.fail(
                "missing-attribute",
                f'{where}<{tag} {key}="{value}"> is empty',
                element,
                None,
            )
        return str(value).strip()

    def number(
        self,
        element: etree._Element,
        key: str,
        default: float | None,
        owner: str,
        *,
        checked_later: bool = True,
    ) -> float:
        """The number in attribute ``key``; ``default`` when absent (None: required).

        Args:
            element: The element holding the attribute.
            key: The attribute.
            default: The value when the attribute is absent; None when it is required.
            owner: Who the element belongs to, for messages (``joint 'NAME'``).
            checked_later: The value goes into the description, whose findings judge
                non-finite values; otherwise a ``number-invalid`` finding is made here.
        """
        text = element.get(key)
        if text is None:
            if default is None:
                self.fail(
                    "missing-attribute",
                    f"{owner}: <{element.tag}> has no '{key}' attribute (URDF requires it)",
                    element,
                    None,
                )
            return float(default)
        if URDFDOM_NUMBER.fullmatch(text):  # fast path: the plain decimals of most files
            plain = float(text)
            if math.isfinite(plain) and (plain >= 0 or key not in _MAGNITUDES):
                return plain
        value = parse_number(text)
        if value is None:
            what = "is empty, not a number" if not text.strip() else "is not a number"
            self.fail(
                "bad-number", f'{owner}: <{element.tag} {key}="{text}"> {what}', element, None
            )
            raise AssertionError("unreachable")  # pragma: no cover
        if key in _MAGNITUDES and value < 0:
            # Pinocchio refuses a negative effort, velocity or friction (its range
            # [-x, x] would be empty); the C-space does not depend on them.
            self.fixes.append((element, key, for_urdfdom(-value)))
            self.invalid(f'<{element.tag} {key}="{text.strip()}"> is negative', owner)
        elif not urdfdom_accepts(text, value):
            self.fixes.append((element, key, for_urdfdom(value)))
        if not math.isfinite(value) and not checked_later:
            self.invalid(f'<{element.tag} {key}="{text.strip()}"> is not a finite number', owner)
        return value

    def vector(
        self, element: etree._Element, key: str, owner: str, *, checked_later: bool
    ) -> tuple[float, float, float] | None:
        """Three numbers in attribute ``key``, or None when the attribute is absent."""
        text = element.get(key)
        if text is None:
            return None
        if URDFDOM_VECTOR.fullmatch(text):  # fast path: three plain decimals
            x, y, z = map(float, text.split())
            if math.isfinite(x) and math.isfinite(y) and math.isfinite(z):
                return (x, y, z)
        values = [parse_number(part) for part in text.split()]
        if len(values) != 3 or None in values:
            self.fail(
                "bad-number",
                f'{owner}: <{element.tag} {key}="{text}"> is not three numbers',
                element,
                None,
            )
        x, y, z = (float(v) for v in values)  # type: ignore[arg-type]
        finite = math.isfinite(x) and math.isfinite(y) and math.isfinite(z)
        if not (finite and URDFDOM_VECTOR.fullmatch(text)):
            # urdfdom splits on spaces only and refuses NaN, infinities and overflow.
            fixed = " ".join(repr(v) for v in (x, y, z)) if finite else "0 0 0"
            self.fixes.append((element, key, fixed))
        if not checked_later and not finite:
            self.invalid(f'<{element.tag} {key}="{text.strip()}"> is not finite', owner)
        return (x, y, z)

    def invalid(self, what: str, owner: str) -> None:
        """A ``number-invalid`` finding: ``owner: what``, and why it still analyses."""
        self.findings.append(
            finding(
                "number-invalid",
                self.joint_name,
                f"{owner}: {what}; the C-space does not depend on it, but URDF and "
                "Pinocchio refuse it",
            )
        )

    def child(self, tag: str) -> etree._Element | None:
        """The current joint's first child element ``tag`` (urdfdom reads only the first)."""
        return self.children.get(tag)

    def link_name(self, joint: etree._Element, tag: str, owner: str) -> str:
        """The link a ``<parent>`` or ``<child>`` names."""
        element = self.child(tag)
        if element is None:
            self.fail("missing-element", f"{owner} has no <{tag}> element", joint, None)
        return self.attribute(element, "link", owner)

    def others(self, element: etree._Element, owner: str) -> None:
        """Check what urdfdom parses but the C-space ignores: origin, dynamics, ..."""
        origin = self.child("origin")
        if origin is not None:
            for key in ("xyz", "rpy"):
                self.vector(origin, key, owner, checked_later=False)
            if origin.get("quat_xyzw") is not None:  # URDF 1.1, as urdfdom reads it
                if origin.get("rpy") is not None:
                    self.fail(
                        "conflicting-attributes",
                        f"{owner}: <origin> gives both 'rpy' and 'quat_xyzw'; urdfdom refuses "
                        "an origin with both (give one or the other)",
                        origin,
                        None,
                    )
                quaternion = [parse_number(p) for p in origin.get("quat_xyzw", "").split()]
                if len(quaternion) != 4 or None in quaternion:
                    self.fail(
                        "bad-number",
                        f'{owner}: <origin quat_xyzw="{origin.get("quat_xyzw")}"> is not four '
                        "numbers",
                        origin,
                        None,
                    )
        for tag, keys in _OTHER_NUMBERS.items():
            child = self.child(tag)
            if child is None:
                continue
            required = _REQUIRED.get(tag, ())
            values = {
                key: self.number(
                    child, key, None if key in required else 0.0, owner, checked_later=False
                )
                for key in keys
            }
            if tag == "safety_controller":
                soft = (values["soft_lower_limit"], values["soft_upper_limit"])
                self.soft = soft if all(math.isfinite(v) for v in soft) else None
        dynamics = self.child("dynamics")
        if (
            dynamics is not None
            and dynamics.get("damping") is None
            and dynamics.get("friction") is None
        ):
            self.fail(
                "missing-attribute",
                f"{owner}: <dynamics> has neither 'damping' nor 'friction' (URDF needs one)",
                dynamics,
                None,
            )

    def axis(self, element: etree._Element, owner: str) -> tuple[float, float, float] | None:
        """The ``<axis>`` as written, or None."""
        axis_element = self.child("axis")
        if axis_element is None:
            return None
        if axis_element.get("xyz") is None:
            self.fail(
                "missing-attribute",
                f"{owner}: <axis> has no 'xyz' attribute (URDF requires it; "
                "leave out <axis> for the default (1, 0, 0))",
                axis_element,
                None,
            )
        return self.vector(axis_element, "xyz", owner, checked_later=True)

    def limits(
        self, limit: etree._Element, joint_type: str, owner: str
    ) -> tuple[tuple[float, ...], tuple[float, ...]]:
        self.rates = tuple(
            (key, self.number(limit, key, None, owner, checked_later=False))
            for key in _REQUIRED["limit"]
        )
        kept = joint_type in LIMIT_REQUIRED or (
            joint_type == "continuous" and bool(limit.get("lower") or limit.get("upper"))
        )
        # Limits the description does not keep (a fixed joint's, say) are judged here.
        lower = self.number(limit, "lower", 0.0, owner, checked_later=kept)
        upper = self.number(limit, "upper", 0.0, owner, checked_later=kept)
        return ((lower,), (upper,)) if kept else ((), ())

    def begin(self, element: etree._Element) -> tuple[str, str, str]:
        """Start on a joint element (URDF's or Drake's): its name, owner and type.

        Its children are kept by tag, the first of each (urdfdom reads only the first).
        """
        self.joint_name = None
        self.soft = None
        self.children = {}
        for sub in element.iterchildren(tag=etree.Element):  # no comments or PIs
            self.children.setdefault(str(sub.tag), sub)
        name = self.attribute(element, "name", None)
        owner = f"joint '{name}'"
        self.joint_name = name
        return name, owner, self.attribute(element, "type", owner)

    def joint(self, element: etree._Element) -> JointSpec:
        name, owner, joint_type = self.begin(element)
        check_joint_type(self.path, name, joint_type, URDF_JOINT_TYPES, element)
        parent = self.link_name(element, "parent", owner)
        child = self.link_name(element, "child", owner)
        self.others(element, owner)
        axis = None if joint_type in NO_AXIS else self.axis(element, owner)
        limit = self.child("limit")
        if limit is None and joint_type in LIMIT_REQUIRED:
            self.fail(
                "missing-limit",
                f"{owner} is {joint_type} but has no <limit> element (URDF requires one)",
                element,
                name,
            )
        self.rates = ()
        lower, upper = ((), ()) if limit is None else self.limits(limit, joint_type, owner)
        mimic_element = self.child("mimic")
        mimic = None
        if mimic_element is not None:
            follows = joint_type in MIMIC_TYPES
            mimic = MimicSpec(
                joint=self.attribute(mimic_element, "joint", owner),
                multiplier=self.number(
                    mimic_element, "multiplier", 1.0, owner, checked_later=follows
                ),
                offset=self.number(mimic_element, "offset", 0.0, owner, checked_later=follows),
            )
            if not follows and joint_type != "fixed":  # a fixed joint is a point anyway
                self.findings.append(
                    finding(
                        "mimic-ignored",
                        name,
                        f"{joint_type} joint '{name}' has a <mimic> element, which only a "
                        "revolute, continuous or prismatic joint can follow; Pinocchio ignores "
                        f"it, and so does this report ('{name}' is reported as {joint_type})",
                    )
                )
            if not follows:
                mimic = None
        return JointSpec(
            name=name,
            type=joint_type,
            parent=parent,
            child=child,
            kind=URDF_KINDS[joint_type],
            axis=axis,
            lower=lower,
            upper=upper,
            mimic=mimic,
            limits_defaulted=bool(lower)
            and limit is not None
            and limit.get("lower") is None
            and limit.get("upper") is None,
            bounds_missing=_missing(limit, ("lower", "upper")) if lower else (),
            line=line_of(element),
            limit_line=line_of(limit),
            axis_line=line_of(self.child("axis")),
            rates=self.rates,
            soft=self.soft,
        )


def _missing(element: etree._Element | None, keys: tuple[str, ...]) -> tuple[str, ...]:
    """The attributes among ``keys`` that ``element`` does not give."""
    return () if element is None else tuple(k for k in keys if k not in element.attrib)
