"""MoveIt's ``joint_limits.yaml``, read as MoveIt 2 reads it, without the robot.

The file is untrusted: read once through `cspace.files.read_input` (at most
`MAX_LIMITS_BYTES`), parsed by the bounded loader (`cspace._formats.shared.yamlio`).
Three shapes are MoveIt users': the Setup Assistant's, with ``joint_limits:`` at the
top (``MoveItConfigsBuilder`` puts it under ``robot_description_planning``), that
namespace written out, ``robot_description_planning: {joint_limits: ...}``, and either
in a ROS 2 parameter file (``/**: {ros__parameters: ...}``, or a node's name in place of
``/**``). Beside ``joint_limits`` the default scaling factors are read.

Each joint's keys are those MoveIt 2's ``RobotModelLoader`` reads (``min_position``,
``max_position``, ``has_velocity_limits`` and ``max_velocity``, the same for
acceleration and jerk) and those ros2_control's and Pilz's readers of the same file
know (effort, deceleration, soft limits); any other is said (``limits-file-ignored``).
What the file alone shows is found here: a negative maximum, a ``has_*_limits: true``
without its value, a maximum MoveIt does not read without ``has_*_limits: true``, an
integer where ROS 2 wants a double. A value of the wrong type (text, a list, a boolean
for a number), a non-finite number or a name longer than `MAX_NAME` refuses the file in
one line.
"""

import math
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.robot_size import MAX_NAME
from cspace._formats.shared.yamlio import Entry, YamlMap, load_yaml
from cspace._record import NamedTuple
from cspace.errors import InvalidElementError

MAX_LIMITS_BYTES = 256 << 10
"""Largest joint_limits.yaml read: a 50-joint robot's is about 10 kB, and PyYAML's pure-Python
loader reads about 200 kB a second (a file of this size and 35,000 nodes: 1.2 s of CPU)."""

WHAT = "joint limits file"

NUMBERS = (
    "min_position",
    "max_position",
    "max_velocity",
    "max_acceleration",
    "max_deceleration",
    "max_jerk",
    "max_effort",
    "soft_lower_limit",
    "soft_upper_limit",
    "k_position",
    "k_velocity",
)
"""The numeric keys of a joint's entry."""

FLAGS = {
    "has_position_limits": "max_position",
    "has_velocity_limits": "max_velocity",
    "has_acceleration_limits": "max_acceleration",
    "has_deceleration_limits": "max_deceleration",
    "has_jerk_limits": "max_jerk",
    "has_effort_limits": "max_effort",
    "has_soft_limits": "soft_lower_limit",
    "angle_wraparound": "",
}
"""The boolean keys of a joint's entry, and the value each switches on."""

RATES = ("velocity", "acceleration", "jerk", "effort")
"""The rate limits shown beside a joint (MoveIt reads the first three)."""

MOVEIT_READS = frozenset({"velocity", "acceleration", "jerk"})
"""The rates MoveIt 2's ``RobotModelLoader`` takes from the file (with ``has_*``)."""

MOVEIT_ORDER = (
    "max_position",
    "min_position",
    "has_velocity_limits",
    "has_acceleration_limits",
    "has_jerk_limits",
    "max_velocity",
    "max_acceleration",
    "max_jerk",
)
"""The keys of a joint ``RobotModelLoader`` reads, in its order (``max_X`` only where
``has_X_limits`` is true): the first integer among them stops its reading of the joint."""

MUST_NOT_BE_NEGATIVE = ("max_velocity", "max_acceleration", "max_jerk", "max_effort")

SCALING = ("default_velocity_scaling_factor", "default_acceleration_scaling_factor")


class Given(NamedTuple):
    """A value the file gives, the line of its key, and whether it is written as an integer."""

    value: float
    line: int
    integer: bool = False


class JointEntry(NamedTuple):
    """One joint's entry under ``joint_limits``.

    Attributes:
        name: The joint's name as written (a planar or floating joint's variable is
            ``joint/x``).
        line: The line of its key.
        numbers: Its numeric keys' values.
        flags: Its boolean keys' values, as (value, line).
        unread: The keys MoveIt 2 does not take: from the first integer it reads on
            (`MOVEIT_ORDER`).
    """

    name: str
    line: int
    numbers: dict[str, Given]
    flags: dict[str, tuple[bool, int]]
    unread: frozenset[str] = frozenset()

    def taken(self, key: str) -> Given | None:
        """The number ``key`` as MoveIt 2 takes it (None when not given or not read)."""
        return None if key in self.unread else self.numbers.get(key)

    def rate(self, name: str) -> Given | None:
        """The maximum ``name`` (``velocity``...) MoveIt takes from the file, or None.

        MoveIt 2 reads ``max_X`` only where ``has_X_limits`` is true; effort it does not
        read, and it is given as written.
        """
        value = self.taken(f"max_{name}")
        if name not in MOVEIT_READS:
            return value
        flag = self._switch(name)
        return value if flag is not None and flag[0] else None

    def switched_off(self, name: str) -> int | None:
        """The line of ``has_X_limits: false`` (MoveIt drops the URDF's limit), or None."""
        flag = self._switch(name)
        return flag[1] if name in MOVEIT_READS and flag is not None and not flag[0] else None

    def _switch(self, name: str) -> tuple[bool, int] | None:
        """``has_NAME_limits`` as MoveIt 2 takes it (value, line), or None."""
        key = f"has_{name}_limits"
        return None if key in self.unread else self.flags.get(key)


class LimitsFile(NamedTuple):
    """A joint_limits.yaml as read.

    Attributes:
        path: The file, as named.
        joints: Each joint's entry, in file order.
        scaling: The default scaling factors given (by key).
        findings: What the file alone shows (each on its line, in this file).
    """

    path: str
    joints: tuple[JointEntry, ...]
    scaling: dict[str, Given]
    findings: tuple[Diagnostic, ...]


def read_limits(path: str, allow_dirs: Any = ()) -> LimitsFile:
    """Read MoveIt's joint_limits.yaml at ``path`` (see the module).

    Raises:
        FileUnreadableError: Missing, a link out of its folder, not a regular file, or
            larger than `MAX_LIMITS_BYTES`.
        InvalidElementError: Not the YAML of a joint_limits.yaml (``yaml-invalid``,
            ``limits-file-invalid``).
    """
    from cspace.files import read_input

    data = read_input(path, max_bytes=MAX_LIMITS_BYTES, allow_dirs=allow_dirs, what=WHAT)
    return parse_limits(path, data)


def parse_limits(path: str, data: bytes) -> LimitsFile:
    """`read_limits` of bytes already read."""
    document = load_yaml(path, data, WHAT)
    reader = _Reader(path)
    if not isinstance(document, dict):
        raise reader.refuse("is not a YAML mapping with a 'joint_limits' key", 1)
    top: YamlMap = document
    if "joint_limits" not in top and len(top) == 1:  # a ROS 2 parameter file: /**: ...
        node = next(iter(top.values()))
        inner = node.value.get("ros__parameters") if isinstance(node.value, dict) else None
        if inner is not None and isinstance(inner.value, dict):
            top = inner.value
    if "joint_limits" not in top and "robot_description_planning" in top:
        inner = top["robot_description_planning"]
        if not isinstance(inner.value, dict):
            raise reader.refuse("robot_description_planning is not a mapping", inner.line)
        top = inner.value
    limits = top.get("joint_limits")
    if limits is None:
        raise reader.refuse(
            "has no 'joint_limits' mapping (MoveIt's joint_limits.yaml has one at the top, "
            "or under robot_description_planning)",
            1,
        )
    if not isinstance(limits.value, dict):
        raise reader.refuse("joint_limits is not a mapping of joint names", limits.line)
    scaling = {}
    for key, entry in top.items():
        if key in SCALING:
            scaling[key] = reader.number(None, key, entry)
            if not 0.0 < scaling[key].value <= 1.0:
                reader.say(
                    "limits-file-scaling",
                    None,
                    f"{key} is {entry.value!r}: MoveIt scales by a factor in (0, 1]",
                    entry.line,
                )
        elif key != "joint_limits":
            reader.say(
                "limits-file-ignored", None, f"key '{key}' is no key MoveIt reads", entry.line
            )
    joints = tuple(reader.joint(name, entry) for name, entry in limits.value.items())
    return LimitsFile(path, joints, scaling, tuple(reader.findings))


class _Reader:
    def __init__(self, path: str) -> None:
        self.path = path
        self.findings: list[Diagnostic] = []

    def refuse(self, problem: str, line: int | None) -> InvalidElementError:
        return InvalidElementError(
            self.path, f"{WHAT} {problem}", line=line, code="limits-file-invalid"
        )

    def say(self, code: str, joint: str | None, message: str, line: int) -> None:
        self.findings.append(finding(code, joint, message, line, self.path))

    def number(self, joint: str | None, key: str, entry: Entry, said: bool = True) -> Given:
        owner = f"joint '{joint}': " if joint is not None else ""
        value = entry.value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.refuse(f"gives {owner}{key} {_shown(value)}, not a number", entry.line)
        if not math.isfinite(value):
            raise self.refuse(f"gives {owner}{key} {value}, not a finite number", entry.line)
        if isinstance(value, int) and said:
            self.say(
                "limits-file-integer",
                joint,
                f"{owner}{key} is the integer {value}: MoveIt 2 reads it as a ROS 2 parameter "
                f"of type double and refuses an integer (write {value}.0)",
                entry.line,
            )
        return Given(float(value), entry.line, isinstance(value, int))

    def joint(self, name: str, entry: Entry) -> JointEntry:
        if len(name) > MAX_NAME:
            raise self.refuse(f"names a joint of more than {MAX_NAME} characters", entry.line)
        if not isinstance(entry.value, dict):
            raise self.refuse(
                f"gives joint '{name}' {_shown(entry.value)}, not a mapping", entry.line
            )
        numbers: dict[str, Given] = {}
        flags: dict[str, tuple[bool, int]] = {}
        for key, item in entry.value.items():
            if key in NUMBERS:
                numbers[key] = self.number(name, key, item, said=False)
            elif key in FLAGS:
                if not isinstance(item.value, bool):
                    raise self.refuse(
                        f"gives joint '{name}': {key} {_shown(item.value)}, not true or false",
                        item.line,
                    )
                flags[key] = (item.value, item.line)
            else:
                self.say(
                    "limits-file-ignored",
                    name,
                    f"joint '{name}': key '{key}' is no key MoveIt or ros2_control reads",
                    item.line,
                )
        unread = self._integers(name, numbers, flags)
        self._check(name, numbers, flags)
        return JointEntry(name, entry.line, numbers, flags, unread)

    def _integers(
        self, name: str, numbers: dict[str, Given], flags: dict[str, tuple[bool, int]]
    ) -> frozenset[str]:
        """Say each integer; the keys MoveIt does not read from the first it reads on."""
        read = [
            key
            for key in MOVEIT_ORDER
            if not key.startswith("max_")
            or key == "max_position"
            or flags.get(f"has_{key[4:]}_limits", (False, 0))[0]
        ]
        stop = next((k for k in read if k in numbers and numbers[k].integer), None)
        unread = frozenset(MOVEIT_ORDER[MOVEIT_ORDER.index(stop) :]) if stop else frozenset()
        for key, given in numbers.items():
            if not given.integer:
                continue
            shown = f"{given.value:.0f}"
            if key == stop:
                later = [k for k in read[read.index(key) + 1 :] if k in numbers or k in flags]
                rest = f" nor {', '.join(later)}" if later else ""
                effect = (
                    f"refuses it, logs an error and reads neither it{rest}: the robot "
                    "file's limits stand"
                )
            else:
                effect = "refuses an integer"
            self.say(
                "limits-file-integer",
                name,
                f"joint '{name}': {key} is the integer {shown}: MoveIt 2 reads it as a ROS 2 "
                f"parameter of type double and {effect} (write {shown}.0)",
                given.line,
            )
        return unread

    def _check(
        self, name: str, numbers: dict[str, Given], flags: dict[str, tuple[bool, int]]
    ) -> None:
        for key in MUST_NOT_BE_NEGATIVE:
            if key in numbers and numbers[key].value < 0:
                self.say(
                    "limits-file-negative",
                    name,
                    f"joint '{name}': {key} is {numbers[key].value:g}, negative: the range "
                    f"[-{key[4:]}, +{key[4:]}] it bounds is empty",
                    numbers[key].line,
                )
        for flag, key in FLAGS.items():
            said = flags.get(flag)
            if key and said is not None and said[0] and key not in numbers:
                if flag == "has_position_limits":
                    continue  # said below: MoveIt does not read it
                self.say(
                    "limits-file-missing-value",
                    name,
                    f"joint '{name}': {flag} is true and {key} is not given: MoveIt logs an "
                    "error and keeps the URDF's value (0 where the URDF has none)",
                    said[1],
                )
        position = flags.get("has_position_limits")
        if position is not None:
            self.say(
                "limits-file-ignored",
                name,
                f"joint '{name}': has_position_limits is {str(position[0]).lower()}, which "
                "MoveIt 2 does not read: min_position and max_position, where given, replace "
                "the URDF's limits, and the URDF's stand otherwise",
                position[1],
            )
        for rate in (r for r in RATES if r in MOVEIT_READS):
            given = numbers.get(f"max_{rate}")
            if given is not None and f"has_{rate}_limits" not in flags:
                self.say(
                    "limits-file-ignored",
                    name,
                    f"joint '{name}': max_{rate} is read only with has_{rate}_limits: true, "
                    "which is not given: MoveIt keeps the URDF's",
                    given.line,
                )


def _shown(value: Any) -> str:
    """A value of the file, for a message: short, and a mapping by its keys."""
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
