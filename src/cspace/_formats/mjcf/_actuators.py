"""MJCF actuators: the ctrl vector's layout, and where it disagrees with the joints.

Read from the compiled model's facts (`_compile._actuator`): each actuator in order,
what it is (`cspace._actuators.kind_of`), what it drives and its gear and ctrlrange.
The findings:

- ``actuator-ctrlrange-exceeds`` (warning): a position actuator on a limited hinge or
  slide whose ctrlrange reaches beyond the joint's range in ctrl units (``gear *
  range``) by more than `SLACK` (times the gear): targets the joint cannot reach;
- ``actuator-joint-unlimited`` (warning): a position actuator with a ctrlrange on a
  hinge or slide without a range: the controller bounds what the C-space leaves free;
- ``actuator-order`` (info): the joints the actuators drive, each counted where an
  actuator first drives it, are not in qpos order (legal; ctrl and qpos index joints
  differently).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._actuators import TRANSMISSIONS, Actuator, gear_count, gear_tuple, kind_of
from cspace._findings import Diagnostic, finding

SLACK = 1e-4
"""How far (in joint units: rad or m) a ctrlrange may pass its joint's range: files write
one of them rounded (pi/2 as 1.5708)."""

_UNITS = {2: "m", 3: "rad"}  # mjtJoint: slide, hinge


def read_actuators(
    facts: Mapping[str, Any],
    joint_names: Sequence[str],
    body_names: Sequence[str],
    lines: Mapping[tuple[str, str], int],
) -> tuple[Actuator, ...]:
    """Each actuator of the compiled model, in ctrl order.

    Args:
        facts: What the child read of the compiled model (``actuators``, ``tendons``).
        joint_names: Each joint's name (made-up ones too), in MuJoCo's order.
        body_names: Each body's name, by id.
        lines: ``("actuator", name)`` -> the actuator's line in the main file.
    """
    joints = facts.get("joints", [])
    targets: dict[str, Sequence[str | None]] = {
        "joint": joint_names,
        "jointinparent": joint_names,
        "tendon": facts.get("tendons", []),
        "body": body_names,
    }
    out = []
    for entry in facts.get("actuators", []):
        name, limited, (low, high), _, trntype, trnid, gear = entry[:7]
        dyntype, gaintype, gain, biastype, bias = entry[7:12]
        transmission = TRANSMISSIONS[int(trntype)] if 0 <= int(trntype) < 6 else "other"
        names = targets.get(transmission, ())
        target = names[int(trnid)] if 0 <= int(trnid) < len(names) else None
        on_joint = transmission.startswith("joint") and 0 <= int(trnid) < len(joints)
        joint_type = int(joints[int(trnid)][1]) if on_joint else None
        if transmission in ("site", "slidercrank"):
            target = entry[12] if len(entry) > 12 else None
        out.append(
            Actuator(
                name=str(name) if name else None,
                line=lines.get(("actuator", str(name))) if name else None,
                kind=kind_of(int(trntype), int(dyntype), int(gaintype), gain, int(biastype), bias),
                transmission=transmission,
                target=None if target is None else str(target),
                gear=float(gear),
                gears=gear_tuple(entry[13][: gear_count(transmission, joint_type)]),
                ctrlrange=(float(low), float(high)) if limited else None,
            )
        )
    return tuple(out)


def actuator_findings(
    facts: Mapping[str, Any],
    actuators: Sequence[Actuator],
    joint_names: Sequence[str],
    joint_lines: Mapping[str, int | None],
) -> list[Diagnostic]:
    """The findings on the actuators against their joints (see the module docstring)."""
    joints = facts["joints"]
    index = {name: k for k, name in enumerate(joint_names)}
    found: list[Diagnostic] = []
    first: dict[int, int] = {}  # joint -> the first actuator that drives it
    for number, actuator in enumerate(actuators):
        k = index.get(actuator.target or "") if actuator.transmission.startswith("joint") else None
        if k is None:
            continue
        first.setdefault(k, number)
        _, jtype, _, _, _, limited, (low, high), *_ = joints[k]
        if not actuator.drives_joint() or int(jtype) not in _UNITS or actuator.ctrlrange is None:
            continue
        label, joint = actuator.label(number), joint_names[k]
        where = f" (line {actuator.line})" if actuator.line else ""
        if not limited:
            found.append(
                finding(
                    "actuator-joint-unlimited",
                    joint,
                    f"position actuator {label}{where} has ctrlrange "
                    f"{_range(actuator.ctrlrange)} but joint '{joint}' has no range: the "
                    "controller bounds a joint the C-space leaves free",
                    actuator.line,
                )
            )
            continue
        gear = actuator.gear
        reach = sorted((gear * float(low), gear * float(high)))
        slack = SLACK * abs(gear)
        c_low, c_high = actuator.ctrlrange
        if not all(math.isfinite(x) for x in (gear, c_low, c_high, *reach)):
            continue
        if c_low < reach[0] - slack or c_high > reach[1] + slack:
            joint_line = joint_lines.get(joint)
            found.append(
                finding(
                    "actuator-ctrlrange-exceeds",
                    joint,
                    f"position actuator {label}{where} has ctrlrange "
                    f"{_range(actuator.ctrlrange)}, but joint '{joint}'"
                    + (f" (line {joint_line})" if joint_line else "")
                    + f" has range {_range((float(low), float(high)))} {_UNITS[int(jtype)]}, "
                    f"{_range((reach[0], reach[1]))} in ctrl units (gear {gear:g}): "
                    "targets the joint cannot reach",
                    actuator.line,
                )
            )
    order = sorted(first, key=first.__getitem__)  # joints in the order actuators drive them
    qposadr = [int(joints[k][3]) for k in order]
    late = next((i for i in range(1, len(order)) if qposadr[i] < qposadr[i - 1]), None)
    if late is not None:
        number = first[order[late]]
        actuator = actuators[number]
        found.append(
            finding(
                "actuator-order",
                joint_names[order[late]],
                f"actuator {actuator.label(number)} (ctrl[{number}]) drives joint "
                f"'{joint_names[order[late]]}' (qpos[{qposadr[late]}]), which qpos holds "
                f"before '{joint_names[order[late - 1]]}' (qpos[{qposadr[late - 1]}]) that an "
                "earlier actuator drives: ctrl and qpos order the joints differently",
                actuator.line,
            )
        )
    return found


def _range(pair: tuple[float, float]) -> str:
    return f"[{pair[0]:.8g}, {pair[1]:.8g}]"
