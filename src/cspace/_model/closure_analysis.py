"""What a report says of a mechanism's loops: its `Closure` and the findings on it.

The tree's model and the file's cuts give the constraints (`closure.LoopConstraints`).
Configurations on the mechanism are found by projecting the tree's neutral
configuration and `ATTEMPTS` random ones onto the constraints (a generator seeded with
`SEED`: the same file gives the same report); at each one found, the rank of the
constraint Jacobian gives the mobility (the tree's dimension minus the highest rank,
less the motions to first order a step shows it does not make), and a lower rank a
singularity; `_closure_checks` reads what else they say. The work is bounded:
`closure.MAX_ITERATIONS` steps a projection, as many projections as `MAX_WORK` pays for,
and no search above `MAX_NV` velocities (none: not analysed).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import CutSpec, RobotDescription
from cspace._model._closure_checks import chart, confirmed, names, outside, poses
from cspace._model._closure_values import canonical
from cspace._model.adapter import PinModel
from cspace._model.closure import problem

if TYPE_CHECKING:
    from cspace._model.closure import LoopModel
from cspace._reports.closure import (
    ASSEMBLED_TOLERANCE,
    MAX_SINGULARITIES,
    Closure,
    Cut,
    Singularity,
)
from cspace._reports.report import Report

ATTEMPTS = 24
"""Random configurations projected, besides the neutral one."""

SEED = 20_260_404
"""The seed of the generator that draws them."""

MAX_WORK = 2_000_000
"""The work of the search for configurations, in about-microseconds (`attempts_within`):
about 2 s of CPU at most; fewer configurations are tried when they would cost more."""

MIN_CONFIRMATIONS = 120
"""Fewest Levenberg-Marquardt steps spent seeing whether first-order motions are motions
(two projections' worth), whatever the budget."""

MAX_NV = 160
"""Most velocities (Pinocchio's nv) of a mechanism whose configurations are sought:
Pinocchio's data for a model holds tensors of nv^3 numbers (64 MB at nv 120, 1 GB at 240,
measured with Pinocchio 4.1)."""


def with_closure(
    report: Report, description: RobotDescription, model: PinModel
) -> tuple[Report, LoopModel | None]:
    """The report with its ``closure`` and findings, and what its constraints were searched with.

    The second is None when they were not (no usable cut, no model, too large); for a
    tree, the report is returned as it is, with None.
    """
    if not description.cuts:
        return report, None
    found: list[Diagnostic] = []
    usable: list[CutSpec] = []
    for cut in description.cuts:
        why = problem(cut)
        if why is None:
            usable.append(cut)
        else:
            found.append(_invalid(cut, why))
    cuts = tuple(_reported(c) for c in usable)
    rows = sum(c.rows for c in usable)
    dimension = report.dimension
    pairs = {frozenset((c.link_a, c.link_b)) for c in usable}
    closure = Closure(
        loops=len(pairs),
        cuts=cuts,
        constraint_rows=rows,
        grubler=dimension - rows,
        mobility=None,
        samples=0,
        attempts=0,
        rank=None,
        max_residual=None,
        assembled=None,
        actuated=description.actuated,
    )
    pin_model = model.pinocchio
    if not usable:
        return _done(report, closure, found), None
    nv = 0 if pin_model is None else int(pin_model.nv)
    if pin_model is None or attempts_within(len(usable), rows, nv) < 1:
        why = (
            "the file's reader does not place every joint"
            if pin_model is None
            else f"{nv:,} velocities are more than the {MAX_NV} cspace searches with (the "
            "memory Pinocchio's data takes grows as their cube)"
            if nv > MAX_NV
            else f"{len(usable):,} constraints of {rows:,} equations in {nv:,} velocities "
            f"cost more than cspace spends on one projection"
        )
        found.append(
            finding(
                "closure-not-analysed",
                None,
                f"the mechanism's {_loops(len(pairs))} not searched for configurations: "
                f"{why}; Grübler's count is {dimension - rows}",
            )
        )
        return _done(report, closure, found), None
    from cspace._model.closure import LoopModel

    rooted = report.root_joint is not None
    loops = LoopModel(pin_model, tuple(usable), description.root_link, rooted)
    constraints = loops.constraints()
    closure, extra = _search(report, constraints, closure, description)
    found.extend(extra)
    found.extend(poses(report, constraints))
    return _done(report, closure, found), loops


def _reported(cut: CutSpec) -> Cut:
    """A cut as the report says it.

    Its axis unit, its frames' quaternions unit and in one of their two signs
    (`_one_sign`).
    """
    frames: list[float] = []
    for pose in (cut.frame_a, cut.frame_b):
        frames += [*(p + 0.0 for p in pose.position), *_one_sign(pose.rotation_wxyz)]
    length = math.sqrt(sum(c * c for c in cut.axis))
    ax, ay, az = (c / length + 0.0 for c in cut.axis)
    links = (cut.link_a, cut.link_b)
    return Cut(cut.kind, cut.name, links, cut.rows, cut.line, cut.free, tuple(frames), (ax, ay, az))


def _one_sign(quaternion: tuple[float, float, float, float]) -> list[float]:
    """Of the two unit quaternions of one rotation, the one written the same every time.

    Its first part not within 1e-12 of 0 is positive: w >= 0, and a half turn is written
    one way only; no part is -0.
    """
    norm = math.sqrt(sum(c * c for c in quaternion))
    unit = [c / norm for c in quaternion]
    first = next((c for c in unit if abs(c) > 1e-12), 1.0)
    return [math.copysign(1.0, first) * c + 0.0 for c in unit]


def _loops(count: int) -> str:
    return "1 loop was" if count == 1 else f"{count:,} loops were"


def _invalid(cut: CutSpec, problem: str) -> Diagnostic:
    return finding(
        "closure-invalid",
        None,
        f"<{cut.kind}> '{cut.name}' {problem}: it is left out of the mechanism",
        cut.line,
    )


def _done(report: Report, closure: Closure, found: list[Diagnostic]) -> Report:
    return report._replace(closure=closure, diagnostics=(*report.diagnostics, *found))


def bounds_of(report: Report, nq: int) -> tuple[Any, Any]:
    """Lower and upper values of Pinocchio's q: each limited one-number joint's limits."""
    lower, upper = np.full(nq, -np.inf), np.full(nq, np.inf)
    for joint in report.joints:
        limits = joint.limits
        if joint.q_index is None or joint.nq != 1 or limits is None or len(limits.lower) != 1:
            continue
        if joint.mimic is None and limits.lower[0] <= limits.upper[0]:
            lower[joint.q_index], upper[joint.q_index] = limits.lower[0], limits.upper[0]
    return lower, upper


def attempts_within(cuts: int, rows: int, nv: int) -> int:
    """How many projections the search makes: `MAX_WORK`'s worth, at most 1 + `ATTEMPTS`.

    A projection takes `MAX_ITERATIONS` steps at most. A step costs about
    ``40 + 0.4 nv`` us a cut (its frames' Jacobians, measured) and
    ``rows * nv * min(rows, nv)`` floating-point operations (the damped normal
    equations), counted at 1,000 a us.
    """
    from cspace._model.closure import MAX_ITERATIONS

    return min(1 + ATTEMPTS, steps_within(cuts, rows, nv) // MAX_ITERATIONS)


def steps_within(cuts: int, rows: int, nv: int) -> int:
    """How many Levenberg-Marquardt steps `MAX_WORK` pays for (`attempts_within`)."""
    if nv > MAX_NV:
        return 0
    step = cuts * (40 + 0.4 * nv) + rows * nv * min(rows, nv) / 1000
    return int(MAX_WORK // max(step, 1.0))


def _starts(constraints: Any, bounds: tuple[Any, Any], generator: Any, count: int) -> list[Any]:
    """The neutral configuration and ``count - 1`` random ones, within the bounds."""
    import pinocchio as pin

    model = constraints.model
    neutral = pin.neutral(model)
    starts = [np.clip(neutral, *bounds)]
    lower, upper = bounds
    limited = np.isfinite(lower) & np.isfinite(upper)
    for _ in range(count - 1):
        q = pin.integrate(model, neutral, generator.uniform(-np.pi, np.pi, model.nv))
        q[limited] = generator.uniform(lower[limited], upper[limited])
        starts.append(q)
    return starts


def _search(
    report: Report, constraints: Any, closure: Closure, description: RobotDescription
) -> tuple[Closure, list[Diagnostic]]:
    """Configurations on the mechanism, the ranks there, and the findings they give."""
    from cspace._model.closure import rank

    bounds = bounds_of(report, constraints.nq)
    generator = np.random.default_rng(SEED)
    kept: list[tuple[Any, int, float]] = []
    count = attempts_within(len(constraints.cuts), constraints.rows, constraints.nv)
    starts = _starts(constraints, bounds, generator, count)
    jacobians = []
    tolerance = ASSEMBLED_TOLERANCE
    for start in starts:
        q, worst, _ = constraints.project(start, bounds)
        if worst <= tolerance:
            _, jacobian = constraints.residual_and_jacobian(q)
            kept.append((q, rank(jacobian), worst))
            jacobians.append(jacobian)
    closure = closure._replace(attempts=len(starts), samples=len(kept), assembled=bool(kept))
    found: list[Diagnostic] = []
    if not kept:
        found.append(
            finding(
                "closure-not-assembled",
                None,
                f"no configuration closes every loop: {len(starts)} configurations projected "
                f"onto the {closure.constraint_rows} equations of {names(closure.cuts)}, "
                f"none within {tolerance:.3g} (m, rad)"
                f"{outside(report, constraints, bounds, tolerance)}",
            )
        )
        return closure, found
    ranks = [r for _, r, _ in kept]
    low, high = min(ranks), max(ranks)
    first_order = constraints.nv - high
    steps = steps_within(len(constraints.cuts), constraints.rows, constraints.nv)
    moves, unchecked = confirmed(constraints, kept, bounds, max(steps, MIN_CONFIRMATIONS))
    mobility = report.dimension - high - (first_order - moves)
    singular = [
        Singularity(r, tuple(round(v, 6) + 0.0 for v in x))  # an example, to 1e-6
        for q, r, _ in kept
        if r < high and (x := canonical(report, list(q))) is not None
    ][:MAX_SINGULARITIES]
    closure = closure._replace(
        mobility=mobility,
        rank=(low, high),
        max_residual=float(f"{max(w for _, _, w in kept):.3g}"),  # an order of size
        singularities=tuple(singular),
    )
    if high < closure.constraint_rows:
        found.append(
            finding(
                "closure-grubler-differs",
                None,
                f"the {closure.constraint_rows} closure equations have rank {high}: "
                f"{closure.constraint_rows - high} "
                f"{'depends' if closure.constraint_rows - high == 1 else 'depend'} on the others "
                "(the loops' geometry, "
                f"as in a planar or a Bennett linkage); the mobility is the tree's "
                f"{report.dimension} less {high}, {mobility}, not Grübler's {closure.grubler}",
            )
        )
    if low < high:
        found.append(
            finding(
                "closure-singular",
                None,
                f"the constraints' rank drops from {high} to {low} at "
                f"{sum(r < high for r in ranks)} of {len(kept)} configurations found: "
                "singular configurations (a dead point or a change of branch)",
            )
        )
    if unchecked:
        found.append(
            finding(
                "closure-not-analysed",
                None,
                f"{unchecked} of the {first_order} motions to first order were not checked "
                "for motion (more work than cspace spends): the mobility counts them",
            )
        )
    if moves < first_order:
        found.append(
            finding(
                "closure-shaky",
                None,
                f"at the configurations found the loops' equations allow {first_order} "
                f"motion(s) to first order, but only {moves} take the mechanism anywhere: "
                "it is singular there (a locked or shaky linkage, as a four-bar whose "
                f"links are just long enough to reach); the mobility counts those: {mobility}",
            )
        )
    if mobility <= 0:
        found.append(
            finding(
                "closure-rigid",
                None,
                f"the loops leave the mechanism no motion: mobility {mobility} (the tree's "
                f"dimension {report.dimension}, the constraints' rank {high})",
            )
        )
    is_chart, extra = chart(report, description, kept, jacobians, mobility)
    found.extend(extra)
    return closure._replace(chart=is_chart), found
