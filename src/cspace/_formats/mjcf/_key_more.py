"""More of what an MJCF file stores as poses, checked: keyframes' velocities and mocap.

Keyframes' qvel, mpos and mquat, their joint equalities that are not linear ties, and
qpos0 (the joints' ``ref``):

- ``pose-out-of-limits`` (error): a keyframe's qvel or mpos not finite, a mocap
  quaternion of zeros or not finite; a limited hinge or slide whose ``ref`` (its
  qpos0, where MuJoCo starts without a keyframe) is outside its range;
- ``pose-not-unit`` (warning): a mocap quaternion of norm off 1 (MuJoCo normalises it);
- ``pose-equality-violated`` (warning): a keyframe off an active joint equality that
  holds a joint or ties it by a polynomial (linear ties are mimic joints:
  ``pose-mimic-inconsistent``); MuJoCo's constraint pulls it there.

MuJoCo's child finds what is not finite or not unit (`mjcf._compile._key_extra`): the
other entries, most of them, never cross the process boundary.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.mjcf._keys import key_label

SLACK = 1e-4
"""How far off a keyframe may be (rad or m), as for the joints' limits."""

_HINGE, _SLIDE = 3, 2
_UNITS = {_HINGE: "rad", _SLIDE: "m"}


def more_key_findings(
    facts: Mapping[str, Any],
    joint_names: Sequence[str],
    lines: Mapping[tuple[str, str], int],
    ties: Mapping[int, tuple[int, float, float]],
    mimic_equalities: set[int],
) -> list[Diagnostic]:
    """The findings of the module docstring.

    Args:
        facts: What MuJoCo's child read (``keys``, ``joints``, ``equalities``, ``dofs``,
            ``mocap``).
        joint_names: Each joint's name, in MuJoCo's order.
        lines: ``("key", name)`` and ``("joint", name)`` -> the element's line.
        ties: The mimic followers (to tell a joint that follows from one held).
        mimic_equalities: The equalities that made mimic joints (checked elsewhere).
    """
    found = _qpos0_findings(facts, joint_names, lines)
    joints, dofs, mocap = facts["joints"], facts.get("dofs", []), facts.get("mocap", [])
    polynomials = [
        (index, first, second, poly)
        for index, (kind, (first, second), _, active, _, poly) in enumerate(facts["equalities"])
        if kind == 2 and active and index not in mimic_equalities and first not in ties
        and int(joints[first][1]) in _UNITS
        and (second < 0 or int(joints[second][1]) in _UNITS)
    ]  # fmt: skip
    if facts.get("equality_disabled"):
        polynomials = []
    for index, (given, qpos, _ctrl, *more) in enumerate(facts.get("keys", [])):
        key, line = key_label(index, given, lines)

        def say(
            code: str, joint: str | None, problem: str, key: str = key, at: int | None = line
        ) -> None:
            found.append(finding(code, joint, f"keyframe '{key}': {problem}", at))

        extra = more[0] if more else {}
        for dof, value in extra.get("qvel", []):
            name = joint_names[dofs[dof]] if dof < len(dofs) else f"dof {dof}"
            say("pose-out-of-limits", name, f"qvel of joint '{name}' is {value}: not finite")
        for body, xyz in extra.get("mpos", []):
            said = _body(mocap, body)
            numbers = ", ".join(f"{v:g}" for v in xyz)
            problem = f"mpos of mocap body {said} is ({numbers}): not finite"
            say("pose-out-of-limits", None, problem)
        for body, wxyz in extra.get("mquat", []):
            said = _body(mocap, body)
            norm = math.sqrt(sum(v * v for v in wxyz))
            numbers = ", ".join(f"{v:g}" for v in wxyz)
            if norm == 0.0 or not math.isfinite(norm):
                problem = f"mquat of mocap body {said} is ({numbers}): no rotation"
                say("pose-out-of-limits", None, problem)
            else:
                problem = (
                    f"mquat of mocap body {said} is ({numbers}) of norm {norm:.6g}, not 1 "
                    "(MuJoCo normalises it)"
                )
                say("pose-not-unit", None, problem)
        for equality, first, second, poly in polynomials if qpos else ():
            off = _residual(joints, qpos, first, second, poly)
            if off is not None and abs(off) > SLACK:
                name = joint_names[first]
                by = "held" if second < 0 else f"tied to '{joint_names[second]}' by a polynomial"
                problem = (
                    f"joint '{name}' is {off:+.6g} off its joint equality {equality} ({by}; "
                    "MuJoCo's constraint pulls it there)"
                )
                say("pose-equality-violated", name, problem)
    return found


def _body(mocap: Sequence[str | None], body: int) -> str:
    name = mocap[body] if body < len(mocap) else None
    return f"'{name}'" if name else f"{body}"


def _residual(
    joints: Sequence[Any], qpos: Sequence[float], first: int, second: int, poly: Sequence[float]
) -> float | None:
    """q1 - q1_0 - polynomial(q2 - q2_0), MuJoCo's joint equality (None if not finite)."""
    q1 = float(qpos[int(joints[first][3])]) - float(joints[first][9])
    d = 0.0 if second < 0 else float(qpos[int(joints[second][3])]) - float(joints[second][9])
    value = q1 - sum(c * d**k for k, c in enumerate(poly[:5]))
    return value if math.isfinite(value) else None


def _qpos0_findings(
    facts: Mapping[str, Any], joint_names: Sequence[str], lines: Mapping[tuple[str, str], int]
) -> list[Diagnostic]:
    """A limited hinge or slide whose qpos0 (its ``ref``) lies outside its range.

    Only a ``ref`` the file writes: the default 0 lies outside the range of 103 joints
    of the 282 MJCF files of the sweep (knees from 0.01), which MuJoCo starts there.
    """
    found = []
    for name, joint in zip(joint_names, facts["joints"], strict=True):
        kind, limited, (low, high), qpos0 = int(joint[1]), bool(joint[5]), joint[6], joint[9]
        if qpos0 == 0.0:  # no ref: MuJoCo's default, outside many ranges ([0.01, 2.97])
            continue
        if kind in _UNITS and limited and not (low - SLACK <= qpos0 <= high + SLACK):
            found.append(
                finding(
                    "pose-out-of-limits",
                    name,
                    f"qpos0 of joint '{name}' (its ref, where MuJoCo starts without a "
                    f"keyframe) is {qpos0:.8g}, outside [{low:.8g}, {high:.8g}] {_UNITS[kind]}",
                    lines.get(("joint", name)),
                )
            )
    return found
