"""MJCF keyframes, checked as configurations of the robot's C-space.

A ``<key qpos ctrl>`` is a configuration MuJoCo starts from (``mj_resetDataKeyframe``)
and users keep as "home": nothing checks it against the space it lives in, and files
ship keyframes outside a joint's range or with quaternions that are not unit
(mujoco_menagerie#296 and #147). Each keyframe MuJoCo compiled is read as a point of
the C-space:

- ``pose-out-of-limits`` (error): a limited hinge or slide outside its range, a limited
  ball turned further than its range, or any value not finite: not a point of the space;
- ``pose-not-unit`` (warning): a ball's or free joint's quaternion whose norm is off 1
  by more than `UNIT_SLACK` (MuJoCo normalises it; the file does not say what it means);
- ``pose-ctrl-out-of-range`` (warning): a ctrl outside a limited actuator's ctrlrange
  (MuJoCo clamps it) or not finite;
- ``pose-mimic-inconsistent`` (warning): a mimic follower (a linear joint equality)
  whose value is not ``multiplier * leader + offset`` (MuJoCo's constraint pulls it);
- ``pose-partial`` (warning): a keyframe that writes fewer qpos numbers than the model
  has (MuJoCo fills the rest from qpos0 without a word), naming the joints filled;
- ``poses-not-checked`` (info): keyframes beyond the numbers MuJoCo's child sends back.

Only what a keyframe writes is checked, and only whole: a keyframe that leaves qpos
(or ctrl) out takes MuJoCo's qpos0 (or zeros), which are no pose the file stores. Each
finding names the keyframe (``key<N>`` when it has no name), the joint, the value, the
bounds and the keyframe's line (when the main file declares it by name).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import PoseSpec

UNIT_SLACK = 1e-3
"""How far a keyframe's quaternion norm may be from 1 (keyframes are written with few
digits; MuJoCo normalises them)."""

SLACK = 1e-4
"""How far past a bound a keyframe value may be (rad or m): keyframes are written rounded
(pi/2 as 1.5708) or saved from a simulation, whose limits are soft (franka_kitchen's
knob at 1.3e-5 past 0)."""

_UNITS = {"hinge": "rad", "slide": "m"}


def key_label(
    index: int, given: str | None, lines: Mapping[tuple[str, str], int]
) -> tuple[str, int | None]:
    """A keyframe's name (``key<N>`` when it has none) and its line (a named one's)."""
    key = str(given) if given else f"key{index}"
    return key, lines.get(("key", key)) if given else None


_SIZES = {"hinge": 1, "slide": 1, "ball": 4, "free": 7}
"""How many qpos numbers each MuJoCo joint type holds (in canonical order: w first)."""


def key_poses(
    facts: Mapping[str, Any],
    joint_names: Sequence[str],
    types: Sequence[str],
    lines: Mapping[tuple[str, str], int],
) -> tuple[PoseSpec, ...]:
    """The poses the keyframes store: each keyframe that writes qpos, by joint.

    Args:
        facts: As for `key_findings`.
        joint_names: Each joint's name, in MuJoCo's order.
        types: MuJoCo's joint type names, by ``mjtJoint`` value.
        lines: ``("key", name)`` -> the keyframe's line in the main file.
    """
    poses = []
    joints = [(name, types[int(j[1])], int(j[3]))
              for name, j in zip(joint_names, facts["joints"], strict=True)]  # fmt: skip
    for index, (given, qpos, *_) in enumerate(facts.get("keys", [])):
        if not qpos:  # no qpos written: qpos0, which is no pose the file stores
            continue
        key, line = key_label(index, given, lines)
        values = tuple(
            (name, tuple(float(v) for v in qpos[adr : adr + _SIZES[kind]]))
            for name, kind, adr in joints
        )
        poses.append(PoseSpec(key, "keyframe", line, values))
    return tuple(poses)


def key_findings(
    facts: Mapping[str, Any],
    joint_names: Sequence[str],
    types: Sequence[str],
    lines: Mapping[tuple[str, str], int],
    ties: Mapping[int, tuple[int, float, float]] | None = None,
) -> list[Diagnostic]:
    """Every keyframe's findings (see the module docstring).

    Args:
        facts: What MuJoCo's child read of the compiled model (``keys``, ``nkey``,
            ``joints``, ``actuators``).
        joint_names: Each joint's name, in MuJoCo's order (made up for unnamed ones).
        types: MuJoCo's joint type names, by ``mjtJoint`` value.
        lines: ``("key", name)`` -> the keyframe's line in the main file.
        ties: Each mimic follower's joint id -> (leader's joint id, multiplier, offset):
            ``follower = multiplier * leader + offset`` in qpos (MJCF joint equalities).
    """
    found: list[Diagnostic] = []
    joints = [(name, types[int(j[1])], int(j[3]), bool(j[5]), j[6])
              for name, j in zip(joint_names, facts["joints"], strict=True)]  # fmt: skip
    actuators = facts.get("actuators", [])
    keys = facts.get("keys", [])
    nq = max((adr + _SIZES[kind] for _, kind, adr, *_ in joints), default=0)
    for index, (given, qpos, ctrl, *more) in enumerate(keys):
        key, line = key_label(index, given, lines)

        def say(
            code: str, joint: str | None, problem: str, key: str = key, line: int | None = line
        ) -> None:
            found.append(finding(code, joint, f"keyframe '{key}': {problem}", line))

        written = int(more[1]) if len(more) > 1 else len(qpos)
        if 0 < written < nq:
            filled = [name for name, kind, adr, *_ in joints if adr + _SIZES[kind] > written]
            shown = ", ".join(f"'{name}'" for name in filled[:10])
            more_said = f", ... ({len(filled):,} in all)" if len(filled) > 10 else ""
            say(
                "pose-partial",
                filled[0] if len(filled) == 1 else None,
                f"writes {written:,} of the model's {nq:,} qpos numbers: MuJoCo fills the "
                f"rest from qpos0, for {shown}{more_said}",
            )

        for name, kind, adr, limited, (low, high) in joints if qpos else ():  # written
            if kind in _UNITS:
                value = float(qpos[adr])
                outside = limited and not (low - SLACK <= value <= high + SLACK)
                if outside or not math.isfinite(value):
                    bounds = f", outside [{low:.8g}, {high:.8g}] {_UNITS[kind]}" if limited else ""
                    say("pose-out-of-limits", name, f"joint '{name}' is {value:.8g}{bounds}")
                continue
            start = adr + 3 if kind == "free" else adr
            if not all(math.isfinite(float(x)) for x in qpos[adr : start + 4]):
                numbers = ", ".join(f"{float(x):g}" for x in qpos[adr : start + 4])
                say("pose-out-of-limits", name, f"joint '{name}' is ({numbers}): not finite")
                continue
            w, x, y, z = (float(v) for v in qpos[start : start + 4])
            norm = math.sqrt(w * w + x * x + y * y + z * z)
            if abs(norm - 1.0) > UNIT_SLACK:
                say(
                    "pose-not-unit",
                    name,
                    f"joint '{name}' has quaternion ({w:g}, {x:g}, {y:g}, {z:g}) of norm "
                    f"{norm:.6g}, not 1 (MuJoCo normalises it)",
                )
            if kind == "ball" and limited and norm > 0.0:
                angle = 2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w))
                if angle > high + SLACK:
                    say(
                        "pose-out-of-limits",
                        name,
                        f"ball joint '{name}' is turned {angle:.6g} rad, more than its "
                        f"range {high:g} rad",
                    )
        for follower, (leader, multiplier, offset) in (ties or {}).items() if qpos else ():
            value, lead = float(qpos[joints[follower][2]]), float(qpos[joints[leader][2]])
            wanted = multiplier * lead + offset
            if math.isfinite(value) and math.isfinite(wanted) and abs(value - wanted) > SLACK:
                name = joints[follower][0]
                say(
                    "pose-mimic-inconsistent",
                    name,
                    f"joint '{name}' is {value:.8g}, but it follows '{joints[leader][0]}' "
                    f"({multiplier:g} x {lead:.8g} + {offset:.8g} = {wanted:.8g}; MuJoCo's "
                    "equality pulls it there)",
                )
        for number, ((actuator, limited, (low, high), *_), value) in enumerate(
            zip(actuators, ctrl, strict=False)
        ):
            said = f"actuator '{actuator}'" if actuator else f"actuator {number}"
            if not math.isfinite(float(value)):
                say("pose-ctrl-out-of-range", None, f"ctrl of {said} is {value}: not a number")
            elif limited and not (low - SLACK <= float(value) <= high + SLACK):
                say(
                    "pose-ctrl-out-of-range",
                    None,
                    f"ctrl of {said} is {float(value):.8g}, outside its ctrlrange "
                    f"[{low:.8g}, {high:.8g}] (MuJoCo clamps it unless clampctrl is disabled)",
                )
    if int(facts.get("nkey", len(keys))) > len(keys):
        found.append(
            finding(
                "poses-not-checked",
                None,
                f"{int(facts['nkey']) - len(keys):,} of {int(facts['nkey']):,} keyframes not "
                "checked: cspace reads 5,000 keyframes or 200,000 numbers at most",
            )
        )
    return found
