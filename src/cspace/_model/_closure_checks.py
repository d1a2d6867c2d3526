"""What the configurations found on a mechanism say: its motions, its chart, its poses.

`closure_analysis` finds configurations on a mechanism; these read them: whether the
motions its Jacobian allows are motions (`confirmed`), whether the actuated joints are
coordinates of it (`chart`), whether the poses the file stores close its loops
(`poses`), and why none closes them (`outside`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import CutSpec, RobotDescription
from cspace._model._closure_values import pinocchio_q
from cspace._reports.closure import Cut
from cspace._reports.report import Report

POSE_TOLERANCE = 1e-5
"""Largest residual (m, rad) of a stored pose that closes the loops: keyframes are
written with six or so digits."""


def outside(report: Report, constraints: Any, bounds: tuple[Any, Any], tolerance: float) -> str:
    """Why: the loops close outside the joint limits (named), or the cuts are misplaced."""
    import pinocchio as pin

    free, worst, _ = constraints.project(pin.neutral(constraints.model))
    misplaced = "; the cuts may be misplaced, or the loops' links too short to meet"
    if worst > tolerance:
        return misplaced
    names = [
        j.name
        for j in report.joints
        if j.q_index is not None
        and j.nq == 1
        and not bounds[0][j.q_index] <= free[j.q_index] <= bounds[1][j.q_index]
    ]
    if not names:
        return misplaced
    shown = ", ".join(f"'{n}'" for n in names[:4]) + (" and more" if len(names) > 4 else "")
    return f"; they close with the limits of {shown} left out: the limits keep the loops open"


STEP = 1e-2
"""How far (rad, m) a configuration found is moved along a direction its constraints'
Jacobian allows, to see whether the mechanism moves that way (`confirmed`)."""


SHORTEST = 1e-3
"""The shortest step (rad, m) that tells a motion: where the joints' limits allow less
both ways, the direction counts as a motion, as the first order says."""


def confirmed(
    constraints: Any,
    kept: Sequence[tuple[Any, int, float]],
    bounds: tuple[Any, Any],
    budget: int,
) -> tuple[int, int]:
    """How many of the mechanism's motions to first order are motions; how many unchecked.

    At the first configuration of the highest rank found (then the next two, while one
    finds fewer): each direction of the Jacobian's null space is a motion when a step
    along it (either way: `STEP`, or less where the joints' limits stop it, but not less
    than `SHORTEST`) projects back onto the mechanism at least half the step away, as
    closed as the configuration itself (within four times its residual, or
    `CLOSED_TOLERANCE`). At a regular point every one is; at a singular point of a
    locked linkage the step projects back where it started. ``budget`` bounds the
    Levenberg-Marquardt steps spent; the directions of the first configuration it leaves
    unchecked are counted as motions (as the first order says) and returned second; a
    later configuration's count is taken only when it was checked whole.
    """
    import pinocchio as pin

    from cspace._model.closure import CLOSED_TOLERANCE, rank

    model = constraints.model
    high = max(r for _, r, _ in kept)
    counts: list[tuple[int, int]] = []
    for q, _, residual in [k for k in kept if k[1] == high][:3]:
        _, jacobian = constraints.residual_and_jacobian(q)
        null = np.linalg.svd(jacobian)[2][rank(jacobian) :] if jacobian.size else np.eye(0)
        closed = max(CLOSED_TOLERANCE, 4.0 * residual)
        moves = unchecked = 0
        for index, direction in enumerate(null):
            if budget <= 0:
                unchecked = len(null) - index
                break
            tried = False
            for sign in (1.0, -1.0):
                length = constraints.longest_step(q, sign * direction, STEP, bounds)
                if length < SHORTEST:  # the limits stop it this way
                    continue
                tried = True
                start = pin.integrate(model, q, sign * length * direction)
                moved, worst, steps = constraints.project(start, bounds)
                budget -= steps + 1
                away = float(np.linalg.norm(pin.difference(model, q, moved)))
                if worst <= closed and away >= length / 2:
                    moves += 1
                    break
            else:
                moves += not tried  # stopped both ways: as the first order says
        if unchecked and counts:  # cut short: the whole checks found before stand
            break
        counts.append((moves + unchecked, unchecked))
        if moves + unchecked == len(null) or unchecked:
            break
    return max(counts)


def names(cuts: Sequence[Cut]) -> str:
    shown = ", ".join(f"'{c.name}'" for c in cuts[:4])
    return shown + (f" and {len(cuts) - 4} more" if len(cuts) > 4 else "")


def chart(
    report: Report,
    description: RobotDescription,
    kept: Sequence[tuple[Any, int, float]],
    jacobians: Sequence[Any],
    mobility: int,
) -> tuple[bool | None, list[Diagnostic]]:
    """Whether the actuated joints (and those on no loop) are coordinates of the mechanism.

    At each configuration found, by `closure.is_chart`.
    """
    from cspace._model.closure import RANK_TOLERANCE, is_chart

    actuated = set(description.actuated)
    if not actuated:
        return None, []
    on_loops = np.zeros(jacobians[0].shape[1], dtype=bool)
    for jacobian in jacobians:
        on_loops |= np.abs(jacobian).max(axis=0, initial=0.0) > RANK_TOLERANCE
    given: list[int] = []
    names: list[str] = []
    for joint in report.joints:
        if joint.v_index is None:
            continue
        columns = list(range(joint.v_index, joint.v_index + joint.nv))
        if joint.name in actuated:
            given.extend(columns)
        elif any(on_loops[c] for c in columns):
            names.append(joint.name)
    bad = [i for i, jacobian in enumerate(jacobians) if not is_chart(jacobian, given)]
    if not bad:
        return True, []
    commanded = sum(j.nv for j in report.joints if j.name in actuated and j.v_index is not None)
    shown = ", ".join(sorted(actuated))
    counts = (
        f"mobility {mobility}, {commanded} actuated coordinates, {len(names)} passive "
        "joints on the loops"
    )
    if len(bad) < len(kept):  # a chart but for some configurations: its singularities
        return True, [
            finding(
                "closure-chart-singular",
                None,
                f"the actuated joints ({shown}) fix the mechanism's configuration at "
                f"{len(kept) - len(bad)} of {len(kept)} configurations found, not at the "
                f"other {len(bad)} (actuation singularities; {counts})",
            )
        ]
    return False, [
        finding(
            "closure-chart-invalid",
            None,
            f"the actuated joints ({shown}) fix the mechanism's configuration at none of "
            f"the {len(kept)} configurations found ({counts}): command other joints",
        )
    ]


def poses(report: Report, constraints: Any) -> list[Diagnostic]:
    """A ``pose-not-closed`` finding for each stored pose off the loops."""
    import pinocchio as pin

    neutral = pin.neutral(constraints.model)
    found = []
    for pose in report.poses:
        if pose.configuration is None:
            continue
        q = pinocchio_q(report, pose.configuration, neutral)
        if q is None:
            continue
        residual = constraints.residual(np.asarray(q))
        worst = float(np.max(np.abs(residual), initial=0.0))
        if not worst <= POSE_TOLERANCE:
            at = int(np.argmax(np.abs(residual)))
            cut = _cut_of_row(constraints.cuts, at)
            found.append(
                finding(
                    "pose-not-closed",
                    None,
                    f"{pose.source} '{pose.label}' leaves the loop of <{cut.kind}> "
                    f"'{cut.name}' open by {worst:.3g} (m or rad; closed is within "
                    f"{POSE_TOLERANCE:g})",
                    pose.line,
                    None if report.srdf is None or pose.group is None else report.srdf.path,
                )
            )
    return found


def _cut_of_row(cuts: Sequence[CutSpec], row: int) -> CutSpec:
    for cut in cuts:
        if row < cut.rows:
            return cut
        row -= cut.rows
    return cuts[-1]
