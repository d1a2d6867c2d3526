"""ros2_control's ``<ros2_control>`` elements of a URDF, as records every layer reads.

A URDF (or the URDF xacro makes) may hold, as children of ``<robot>``, one
``<ros2_control name= type=>`` element a hardware component: its ``<hardware><plugin>``,
and each ``<joint name=>`` it drives with its ``<command_interface name=>`` and
``<state_interface name=>``, whose ``<param name="min">``, ``max`` and ``initial_value``
are numbers written as text. ros2_control's own parser (``component_parser.cpp``) keeps
them as text and reads them later with its ``stod`` (`control_number`); so do these
records, and the report carries the text as written.
"""

import math
import re
from collections.abc import Mapping
from typing import Any

from cspace._record import NamedTuple

MAX_NUMBER_TEXT = 64
"""Longest text of a number kept as written (a longer one is no number: ros2_control's
``stod`` of it is too large or too precise to mean anything), in characters."""

_DECIMAL = re.compile(r"-?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)


def control_number(text: str | None) -> float | None:
    """A number as ros2_control's ``stod`` reads it, or None when it reads none.

    ``stod`` is ``std::from_chars`` on the text stripped of white space, after one leading
    ``+``: a C-locale decimal, the whole text, finite and within range (``nan``, ``inf``,
    ``1e400`` and ``1e-400`` are refused).
    """
    if text is None:
        return None
    stripped = text.strip(" \t\n\r\f\v")
    if stripped.startswith("+"):
        stripped = stripped[1:]
    if len(stripped) > MAX_NUMBER_TEXT or not _DECIMAL.fullmatch(stripped):
        return None
    value = float(stripped)
    mantissa = stripped.lower().partition("e")[0]
    if value == 0.0 and mantissa.strip("-.0"):
        return None  # below the least double: from_chars says out of range, not 0
    return value if math.isfinite(value) else None


class ControlInterface(NamedTuple):
    """One command or state interface of a joint.

    Attributes:
        name: Its name (``position``, ``velocity``, ``effort``, ...).
        line: Its line, or None.
        min: Its ``<param name="min">`` as written, or None.
        max: Its ``<param name="max">`` as written, or None.
        initial_value: Its ``<param name="initial_value">`` as written, or None.
        limits_enabled: False when its ``<limits enable="false"/>`` turns its bounds off.
    """

    name: str
    line: int | None = None
    min: str | None = None
    max: str | None = None
    initial_value: str | None = None
    limits_enabled: bool = True

    def to_dict(self) -> dict[str, Any]:
        """The JSON object."""
        return {
            "name": self.name,
            "line": self.line,
            "min": self.min,
            "max": self.max,
            "initial_value": self.initial_value,
            "limits_enabled": self.limits_enabled,
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "ControlInterface":
        """The interface of a JSON object."""
        return cls(
            name=str(document["name"]),
            line=_line(document["line"]),
            min=_text(document["min"]),
            max=_text(document["max"]),
            initial_value=_text(document["initial_value"]),
            limits_enabled=bool(document["limits_enabled"]),
        )


class ControlJoint(NamedTuple):
    """One ``<joint>`` of a hardware component.

    Attributes:
        name: The joint it names.
        line: Its line, or None.
        mimic: Its ``mimic`` attribute as written, or None.
        command: Its command interfaces, in file order.
        state: Its state interfaces, in file order.
        limits_enabled: False when its own ``<limits enable="false"/>`` turns every
            bound off.
    """

    name: str
    line: int | None = None
    mimic: str | None = None
    command: tuple[ControlInterface, ...] = ()
    state: tuple[ControlInterface, ...] = ()
    limits_enabled: bool = True

    def interface(self, kind: str, name: str) -> ControlInterface | None:
        """The first ``kind`` (``command`` or ``state``) interface called ``name``, or None."""
        return next((i for i in getattr(self, kind) if i.name == name), None)

    def to_dict(self) -> dict[str, Any]:
        """The JSON object."""
        return {
            "name": self.name,
            "line": self.line,
            "mimic": self.mimic,
            "limits_enabled": self.limits_enabled,
            "command_interfaces": [i.to_dict() for i in self.command],
            "state_interfaces": [i.to_dict() for i in self.state],
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "ControlJoint":
        """The joint of a JSON object."""
        return cls(
            name=str(document["name"]),
            line=_line(document["line"]),
            mimic=_text(document["mimic"]),
            command=tuple(ControlInterface.from_dict(i) for i in document["command_interfaces"]),
            state=tuple(ControlInterface.from_dict(i) for i in document["state_interfaces"]),
            limits_enabled=bool(document["limits_enabled"]),
        )


class ControlHardware(NamedTuple):
    """One ``<ros2_control>`` element: a hardware component and the joints it drives.

    Attributes:
        name: Its ``name``.
        type: Its ``type`` (``system``, ``actuator``, ``sensor``).
        plugin: Its ``<hardware><plugin>`` text, or None.
        line: Its line, or None.
        joints: Its joints, in file order.
        sensors: How many ``<sensor>`` elements it has (not read further).
        gpios: How many ``<gpio>`` elements it has (not read further).
    """

    name: str
    type: str
    plugin: str | None = None
    line: int | None = None
    joints: tuple[ControlJoint, ...] = ()
    sensors: int = 0
    gpios: int = 0

    def to_dict(self) -> dict[str, Any]:
        """The JSON object."""
        return {
            "name": self.name,
            "type": self.type,
            "plugin": self.plugin,
            "line": self.line,
            "sensors": self.sensors,
            "gpios": self.gpios,
            "joints": [j.to_dict() for j in self.joints],
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "ControlHardware":
        """The hardware component of a JSON object."""
        return cls(
            name=str(document["name"]),
            type=str(document["type"]),
            plugin=_text(document["plugin"]),
            line=_line(document["line"]),
            joints=tuple(ControlJoint.from_dict(j) for j in document["joints"]),
            sensors=int(document["sensors"]),
            gpios=int(document["gpios"]),
        )


def position_bounds(joint: ControlJoint) -> tuple[str | None, str | None, int | None] | None:
    """The ``min`` and ``max`` of the joint's position command interface, with its line.

    None when it has none, gives neither bound, or its limits are turned off (then
    ros2_control does not apply them).
    """
    found = joint.interface("command", "position")
    if found is None or not joint.limits_enabled or not found.limits_enabled:
        return None
    if found.min is None and found.max is None:
        return None
    return found.min, found.max, found.line


def _line(value: Any) -> int | None:
    return None if value is None else int(value)


def _text(value: Any) -> str | None:
    return None if value is None else str(value)
