"""A URDF's ``<ros2_control>`` elements, read as ros2_control's parser reads them, and checked.

ros2_control (``hardware_interface/src/component_parser.cpp``) reads the ``<ros2_control>``
children of ``<robot>`` and no other (one inside a ``<link>`` is not read); in each, its
``<hardware>`` (``<plugin>``), ``<joint>``, ``<sensor>``, ``<gpio>``, ``<transmission>``
and ``<properties>`` children, refusing any other. A joint's interfaces keep their
``<param>`` values as text (the last of a name wins); a position command interface's
``min`` and ``max`` narrow the URDF's limits (the larger lower bound, the smaller upper
one: a wider bound is ignored), and bound a continuous joint, which URDF leaves free;
``<limits enable="false"/>`` on the joint, or on its position command interface, leaves
it no position limits at all, not even the URDF's.
ros2_control refuses to start on a joint the URDF lacks, a fixed joint, a ``mimic``
attribute neither true nor false, and a mimic joint (unless its ``mimic="false"``) with
command interfaces or without its leader in the same component.

The checks here are cspace's findings on them; the position ``initial_value`` of each
component's joints is one stored pose, named after the component.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from lxml import etree

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, PoseSpec
from cspace._formats.shared.robot_size import MAX_JOINTS, check_count, check_name
from cspace._formats.shared.xmlio import line_of
from cspace._joint_kind import JointKind
from cspace._ros2_control import (
    MAX_NUMBER_TEXT,
    ControlHardware,
    ControlInterface,
    ControlJoint,
    control_number,
    position_bounds,
)

MAX_INTERFACES = 4 * MAX_JOINTS
"""Most command and state interfaces in all of a file's ``<ros2_control>`` elements."""

SLACK = 1e-4
"""How far past a bound an initial value may be (rad or m), as for keyframes."""

SOURCE = "ros2_control"
"""The ``source`` of the poses the initial values make."""

_CHILDREN = frozenset({"hardware", "joint", "sensor", "gpio", "transmission", "properties"})
_LIMITED = (JointKind.REVOLUTE, JointKind.PRISMATIC)
_ONE_COORDINATE = (JointKind.REVOLUTE, JointKind.PRISMATIC, JointKind.CONTINUOUS)


def read_ros2_control(
    path: str, root: etree._Element
) -> tuple[tuple[ControlHardware, ...], list[Diagnostic]]:
    """The ``<ros2_control>`` children of ``root``, and what is malformed in them.

    Raises:
        RobotStructureError: More elements than cspace reads (``too-many-joints``), or a
            name too long (``name-too-long``).
    """
    elements = list(root.iterchildren("ros2_control"))
    if not elements:
        return (), []
    line = line_of(root)
    check_count(path, "<ros2_control> elements", len(elements), line)
    joints = [j for e in elements for j in e.iterchildren("joint")]
    check_count(path, "<ros2_control> joints", len(joints), line)
    interfaces = sum(
        1 for j in joints for _ in j.iterchildren("command_interface", "state_interface")
    )
    check_count(path, "<ros2_control> interfaces", interfaces, line, MAX_INTERFACES)
    found: list[Diagnostic] = []
    return tuple(_hardware(path, e, found) for e in elements), found


def _invalid(element: etree._Element, problem: str, joint: str | None = None) -> Diagnostic:
    return finding("ros2-control-invalid", joint, problem, line_of(element))


def _name(path: str, element: etree._Element, what: str, found: list[Diagnostic]) -> str:
    name = (element.get("name") or "").strip()
    check_name(path, name, line_of(element), f"the name of a {what}")
    if not name:
        found.append(_invalid(element, f"a <{what}> without a 'name': ros2_control refuses it"))
    return name


def _hardware(path: str, element: etree._Element, found: list[Diagnostic]) -> ControlHardware:
    name = _name(path, element, "ros2_control", found)
    kind = (element.get("type") or "").strip()
    check_name(path, kind, line_of(element), "a <ros2_control> type")
    if not kind:
        found.append(
            _invalid(element, f"<ros2_control> '{name}' has no 'type': ros2_control refuses it")
        )
    plugin: str | None = None
    counts = {"sensor": 0, "gpio": 0}
    joints: list[ControlJoint] = []
    for child in element.iterchildren(tag=etree.Element):
        tag = child.tag if isinstance(child.tag, str) else ""
        if tag not in _CHILDREN:
            found.append(
                _invalid(
                    child,
                    f"<ros2_control> '{name}' has a <{tag[:40]}> child, which ros2_control refuses",
                )
            )
        elif tag == "hardware":
            item = child.find("plugin")
            if item is None:
                found.append(_invalid(child, f"<hardware> of '{name}' has no <plugin>"))
            else:
                plugin = (item.text or "").strip()
                check_name(path, plugin, line_of(item), "a hardware plugin")
        elif tag == "joint":
            joints.append(_joint(path, child, found))
        elif tag in counts:
            counts[tag] += 1
    return ControlHardware(
        name, kind, plugin, line_of(element), tuple(joints), counts["sensor"], counts["gpio"]
    )


def _enabled(element: etree._Element, found: list[Diagnostic], joint: str) -> bool:
    """Whether the element's ``<limits enable=>`` leaves its limits on (the default)."""
    limits = element.find("limits")
    if limits is None:
        return True
    said = (limits.get("enable") or "").strip().lower()
    if said not in ("true", "false"):
        found.append(
            _invalid(
                limits, '<limits> without enable="true" or "false": ros2_control refuses it', joint
            )
        )
    return said != "false"


def _joint(path: str, element: etree._Element, found: list[Diagnostic]) -> ControlJoint:
    name = _name(path, element, "joint", found)
    command: list[ControlInterface] = []
    state: list[ControlInterface] = []
    for child in element.iterchildren("command_interface", "state_interface"):
        interface = _interface(path, child, found, name)
        (command if child.tag == "command_interface" else state).append(interface)
    mimic = element.get("mimic")
    if mimic is not None:
        mimic = mimic[:MAX_NUMBER_TEXT]
    return ControlJoint(
        name, line_of(element), mimic, tuple(command), tuple(state), _enabled(element, found, name)
    )


def _interface(
    path: str, element: etree._Element, found: list[Diagnostic], joint: str
) -> ControlInterface:
    name = _name(path, element, str(element.tag), found)
    params: dict[str, str] = {}
    for param in element.iterchildren("param"):
        key = param.get("name")
        if key is None:
            found.append(
                _invalid(param, "a <param> without a 'name': ros2_control refuses it", joint)
            )
        elif key.strip() in ("min", "max", "initial_value"):
            text = _kept(param.text or "")
            if text:  # an empty one is none, to ros2_control
                params[key.strip()] = text
            else:
                params.pop(key.strip(), None)
    return ControlInterface(
        name,
        line_of(element),
        params.get("min"),
        params.get("max"),
        params.get("initial_value"),
        _enabled(element, found, joint),
    )


def _kept(text: str) -> str:
    """A number's text as the report keeps it: as written, or cut so that it reads as none."""
    text = text.strip(" \t\n\r")
    return text if len(text) <= MAX_NUMBER_TEXT else text[: MAX_NUMBER_TEXT - 4] + " ..."


def check_ros2_control(
    hardware: Sequence[ControlHardware], joints: Sequence[JointSpec]
) -> tuple[list[Diagnostic], list[PoseSpec]]:
    """The findings on the components' joints against the URDF's, and their initial poses."""
    by_name = {joint.name: joint for joint in joints}
    found: list[Diagnostic] = []
    poses: list[PoseSpec] = []
    exported: dict[tuple[str, str, str], str] = {}
    for component in hardware:
        values: list[tuple[str, tuple[float, ...]]] = []
        names = {joint.name for joint in component.joints}
        for joint in component.joints:
            spec = by_name.get(joint.name)
            if spec is None:
                if joint.name:
                    found.append(_unknown(component, joint))
                continue
            found.extend(_exported_twice(component, joint, exported))
            found.extend(_joint_findings(component, joint, spec, names))
            value = _initial(joint, spec, found)
            if value is not None:
                values.append((spec.name, (value,)))
        if values:
            poses.append(PoseSpec(component.name, SOURCE, component.line, tuple(values)))
    return found, poses


def _exported_twice(
    component: ControlHardware, joint: ControlJoint, exported: dict[tuple[str, str, str], str]
) -> list[Diagnostic]:
    """A joint's interface that a component before it (or an entry before it) exports too.

    ros2_control's resource manager keeps one interface of a name (``JOINT/INTERFACE``)
    among state interfaces, and one among command interfaces: it throws on a second
    (``Tried to insert ... with already existing key``) as it imports the component
    that gives it, whose bounds then do not apply.
    """
    found = []
    for kind, items in (("command", joint.command), ("state", joint.state)):
        for item in items:
            key = (joint.name, kind, item.name)
            first = exported.get(key)
            if first is None:
                exported[key] = component.name
                continue
            message = (
                f"<ros2_control> '{component.name}' gives joint '{joint.name}' a {item.name} "
                f"{kind} interface that '{first}' gives too: ros2_control refuses the second"
            )
            found.append(finding("ros2-control-invalid", joint.name, message, item.line))
    return found


def _unknown(component: ControlHardware, joint: ControlJoint) -> Diagnostic:
    return finding(
        "ros2-control-unknown-joint",
        joint.name,
        f"<ros2_control> '{component.name}' names joint '{joint.name}', which the URDF does "
        "not have: ros2_control refuses to start",
        joint.line,
    )


def _joint_findings(
    component: ControlHardware, joint: ControlJoint, spec: JointSpec, names: set[str]
) -> list[Diagnostic]:
    """What ros2_control refuses or applies of a joint of ``component`` (``names``: its joints)."""
    said = f"<ros2_control> '{component.name}'"
    if spec.kind is JointKind.FIXED:
        message = f"{said} names fixed joint '{spec.name}': ros2_control refuses to start"
        return [finding("ros2-control-fixed-joint", spec.name, message, joint.line)]
    found: list[Diagnostic] = []
    mimic = (joint.mimic or "").strip().lower()
    if joint.mimic is not None and mimic not in ("true", "false"):
        message = (
            f"{said} gives joint '{spec.name}' mimic=\"{joint.mimic}\", neither true nor "
            "false: ros2_control refuses to start"
        )
        found.append(finding("ros2-control-invalid", spec.name, message, joint.line))
    leader = None if spec.mimic is None else spec.mimic.joint
    unset = joint.mimic is None or mimic == "true"
    if leader is not None and unset and not joint.command and leader not in names:
        message = (
            f"{said} names mimic joint '{spec.name}' without mimic=\"false\" and not its "
            f"leader '{leader}': ros2_control refuses to start"
        )
        found.append(finding("ros2-control-invalid", spec.name, message, joint.line))
    if spec.mimic is None and mimic == "true":
        message = (
            f"{said} marks joint '{spec.name}' mimic, which the URDF does not: "
            "ros2_control refuses to start"
        )
        found.append(finding("ros2-control-invalid", spec.name, message, joint.line))
    if spec.mimic is not None and joint.command:
        refused = (
            "ros2_control refuses to start"
            if mimic != "false"
            else ('mimic="false" lets ros2_control command it apart from its leader')
        )
        message = (
            f"{said} gives mimic joint '{spec.name}' (of '{spec.mimic.joint}') command "
            f"interfaces: {refused}"
        )
        found.append(finding("ros2-control-mimic-commanded", spec.name, message, joint.line))
    for interface in (*joint.command, *joint.state):
        for param in ("min", "max", "initial_value"):
            text = getattr(interface, param)
            if text is not None and control_number(text) is None:
                found.append(
                    finding(
                        "ros2-control-number-invalid",
                        spec.name,
                        f"{said}: {interface.name} interface of joint '{spec.name}' has {param} "
                        f"'{text}', which ros2_control does not read as a finite number",
                        interface.line,
                    )
                )
    if spec.mimic is None or mimic == "false":  # commanded apart: its bounds apply
        found.extend(_bounds(said, joint, spec))
    return found


def _bounds(said: str, joint: ControlJoint, spec: JointSpec) -> list[Diagnostic]:
    """The position command interface's bounds against the URDF's limits."""
    item = joint.interface("command", "position")
    off = (not joint.limits_enabled and joint.command) or (item and not item.limits_enabled)
    if off and spec.kind in _LIMITED and spec.limited:
        message = (
            f"{said} turns off the limits of joint '{spec.name}' (<limits enable=\"false\"/>): "
            "ros2_control holds it to no position limits, not even the URDF's "
            f"[{spec.lower[0]:.8g}, {spec.upper[0]:.8g}] {_unit(spec)}"
        )
        line = item.line if item is not None else joint.line
        return [finding("ros2-control-bounds-exceed", spec.name, message, line)]
    bounds = position_bounds(joint)
    if bounds is None:
        return []
    low_text, high_text, line = bounds
    low, high = control_number(low_text), control_number(high_text)
    if (low_text is not None and low is None) or (high_text is not None and high is None):
        return []  # ros2_control skips the interface's limits (said above)
    unit = _unit(spec)
    given = f"[{_show(low)}, {_show(high)}] {unit}"
    if spec.kind is JointKind.CONTINUOUS:
        message = (
            f"{said} bounds continuous joint '{spec.name}' to {given}: its controllers "
            "stop it there, while the URDF (and its C-space, S^1) lets it turn freely"
        )
        return [finding("ros2-control-continuous-bounded", spec.name, message, line)]
    if spec.kind not in _LIMITED or not spec.limited:
        return []
    lower, upper = spec.lower[0], spec.upper[0]
    urdf = f"[{lower:.8g}, {upper:.8g}] {unit}"
    wider = (low is not None and low < lower) or (high is not None and high > upper)
    if wider:
        message = (
            f"{said} gives joint '{spec.name}' position bounds {given}, beyond the URDF's "
            f"limits {urdf}: ros2_control applies [{_show(_tighter(low, lower, max))}, "
            f"{_show(_tighter(high, upper, min))}] {unit}, the tighter of each"
        )
        return [finding("ros2-control-bounds-exceed", spec.name, message, line)]
    if (low is not None and low != lower) or (high is not None and high != upper):
        message = (
            f"{said} gives joint '{spec.name}' position bounds {given}, narrower than the "
            f"URDF's limits {urdf}: its controllers stop it before a planner reading the "
            "URDF expects"
        )
        return [finding("ros2-control-bounds-differ", spec.name, message, line)]
    return []


def _tighter(given: float | None, urdf: float, pick: Callable[[float, float], float]) -> float:
    return urdf if given is None else pick(given, urdf)


def _unit(spec: JointSpec) -> str:
    return "m" if spec.kind is JointKind.PRISMATIC else "rad"


def _show(value: float | None) -> str:
    return "URDF's" if value is None else f"{value:.8g}"


def _initial(joint: ControlJoint, spec: JointSpec, found: list[Diagnostic]) -> float | None:
    """The position initial value the joint gives (state interface first), checked."""
    item = joint.interface("state", "position") or joint.interface("command", "position")
    if item is None or item.initial_value is None or spec.kind not in _ONE_COORDINATE:
        return None
    if spec.mimic is not None:  # its leader's value moves it
        return None
    value = control_number(item.initial_value)  # finite, or None
    if value is None:
        return None  # said as ros2-control-number-invalid
    if spec.limited and spec.kind in _LIMITED:
        low, high = spec.lower[0], spec.upper[0]
        if not low - SLACK <= value <= high + SLACK:
            found.append(
                finding(
                    "pose-out-of-limits",
                    spec.name,
                    f"ros2_control initial_value of joint '{spec.name}' is {value:.8g}, "
                    f"outside [{low:.8g}, {high:.8g}] {_unit(spec)}",
                    item.line,
                )
            )
    return value
