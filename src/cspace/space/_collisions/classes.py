"""The report of ``cspace collisions`` from its samples: classes, shares and findings.

Each pair takes the first of MoveIt's classes that fits (`PAIR_KINDS`). A pair's share
has the 95% Wilson interval, or the exact Clopper-Pearson bound when no sample (or
every sample) collides. The findings hold the samples against the file's matrix:

- SRDF: a pair it disables that collides in some samples and is neither adjacent nor
  always, nor in collision at the default configuration and disabled as ``Default``
  (`collision-disabled-but-reachable`, with a witness); a pair it checks that is always
  in collision, in `ALWAYS_SHARE` of the samples or more (`collision-always`), or at the
  default configuration (`collision-at-default`).
- MJCF and OpenUSD: a body pair MuJoCo's (PhysX's) filters let through that is always
  in contact (`collision-filter-always`); one they filter that collides in some samples
  and is neither adjacent, nor in collision at the default configuration, nor always,
  nor filtered by MuJoCo's parent-child rule (`collision-filtered-reachable`).
- Every file: a stored pose with a checked pair in collision (`collision-pose`).
"""

from collections.abc import Sequence

import numpy as np

from cspace._findings import Diagnostic, finding
from cspace._model._collision_pairs import LinkPair
from cspace._model._collision_stats import clopper_pearson_upper, wilson
from cspace._reports.collisions import (
    ALWAYS_SHARE,
    MUJOCO_PARENT,
    CollidingRange,
    CollisionReport,
    FileRule,
    PairReport,
    PoseCollision,
    Share,
    Witness,
    disabled_but_reachable,
)
from cspace.space._collisions.setup import Prepared
from cspace.space._collisions.tally import BINS, Tally

MIN_RANGE_SAMPLES = 30
"""Fewest samples in a bin for it to be called always in collision."""

TOOLS = {"mjcf": "MuJoCo", "usd": "PhysX"}
"""The simulator whose contact filters a matrix is."""

SHOWN_COORDINATES = 16
"""Most coordinates of a witness a finding's message names."""


def share(hits: int, samples: int) -> Share:
    """``hits`` of ``samples`` with its 95% interval (exact at 0 and at all)."""
    if hits == 0:
        return Share(0, samples, 0.0, clopper_pearson_upper(samples))
    if hits == samples:
        return Share(hits, samples, 1.0 - clopper_pearson_upper(samples), 1.0)
    low, high = wilson(hits, samples)
    return Share(hits, samples, low, high)


def _kind(prepared: Prepared, pair: LinkPair, hits: int, samples: int) -> str:
    if pair in prepared.adjacent:
        return "adjacent"
    if pair in prepared.default:
        return "default"
    if hits >= ALWAYS_SHARE * samples:
        return "always"
    return "never" if hits == 0 else "sometimes"


def report_of(prepared: Prepared, counted: Tally, samples: int, seed: int) -> CollisionReport:
    """The report of ``prepared``'s ``samples`` samples of ``seed`` (`Tally`)."""
    names = prepared.sampler.space.names
    pairs = []
    index = {pair: k for k, pair in enumerate(prepared.engine.pairs)}
    for pair in prepared.pairs:
        rule = None if prepared.rules is None else prepared.rules.get(pair)
        k = index.get(pair)
        if k is None:  # an adjacent pair no file checks: not sampled
            pairs.append(PairReport(*pair, "adjacent", None, None, rule))
            continue
        first = counted.first.get(k)
        witness = None
        if first is not None:
            configuration = tuple((n, (v,)) for n, v in zip(names, first[1], strict=True))
            witness = Witness(first[0], configuration)
        kind = _kind(prepared, pair, counted.counts[k], samples)
        pairs.append(PairReport(*pair, kind, share(counted.counts[k], samples), witness, rule))
    free, hits, bins = counted.arrays()
    kind_of = {(p.link1, p.link2): p.kind for p in pairs}
    sometimes = np.array([kind_of[p] == "sometimes" for p in prepared.engine.pairs], dtype=bool)
    mask = np.packbits(sometimes) if len(sometimes) else np.zeros(0, dtype=np.uint8)
    suggested = ~np.any(hits & mask, axis=1) if len(mask) else np.ones(len(hits), dtype=bool)
    ranges = _ranges(prepared, suggested, bins)
    poses = _poses(prepared)
    findings = [
        *prepared.findings,
        *_pair_findings(prepared, pairs),
        *_pose_findings(poses, prepared.srdf),
    ]
    report = prepared.report
    return CollisionReport(
        report.source,
        report.robot,
        report.tool_version,
        seed,
        prepared.matrix,
        prepared.srdf,
        prepared.shapes.with_geometry,
        tuple(pairs),
        share(int(free.sum()), samples),
        share(int(suggested.sum()), samples),
        tuple(ranges),
        tuple(poses),
        tuple(findings),
    )


def _ranges(prepared: Prepared, free: "np.ndarray", bins: "np.ndarray") -> list[CollidingRange]:
    """Each binned coordinate's runs of bins with samples, none of them free."""
    sampler = prepared.sampler
    out = []
    for column, k in enumerate(sampler.columns):
        coordinate = sampler.space.coordinates[k]
        counts = np.bincount(bins[:, column], minlength=BINS)
        frees = np.bincount(bins[:, column], weights=free, minlength=BINS)
        full = [bool(counts[b] >= MIN_RANGE_SAMPLES and frees[b] == 0) for b in range(BINS)]
        runs = _runs(full, wraps=coordinate.factor == "S^1")
        low, width = sampler.low[column], sampler.width[column]
        for a, b in runs:
            inside = int(sum(counts[i % BINS] for i in range(a, b)))
            out.append(
                CollidingRange(
                    coordinate.name,
                    float(low + width * (a % BINS) / BINS),
                    float(low + width * (((b - 1) % BINS) + 1) / BINS),
                    inside,
                    clopper_pearson_upper(inside),
                )
            )
    return out


def _runs(full: Sequence[bool], *, wraps: bool) -> list[tuple[int, int]]:
    """Runs ``[a, b)`` of true bins; on a circle a run may pass the last bin (b > BINS)."""
    n = len(full)
    if all(full):
        return [(0, n)]
    runs, start = [], None
    for i, on in enumerate(full):
        if on and start is None:
            start = i
        if not on and start is not None:
            runs.append((start, i))
            start = None
    if start is not None:
        runs.append((start, n))
    if wraps and len(runs) > 1 and runs[0][0] == 0 and runs[-1][1] == n:
        last = runs.pop()
        first = runs.pop(0)
        runs.append((last[0], n + first[1]))
    return runs


def _poses(prepared: Prepared) -> list[PoseCollision]:
    """The stored poses with pairs in collision.

    Of the pairs sampled: an adjacent pair only when the file checks it.
    """
    report, engine = prepared.report, prepared.engine
    out = []
    to_q = prepared.sampler.to_q
    for pose in report.poses:
        if pose.configuration is None:
            continue
        q = to_q(np.asarray([pose.configuration], dtype=float))[0]
        hit = sorted(engine.pairs[k] for k in engine.colliding(q))
        if hit:
            checked = tuple(p for p in hit if prepared.checked(p))
            out.append(PoseCollision(pose.label, pose.source, pose.line, tuple(hit), checked))
    return out


def _example(witness: Witness | None) -> str:
    if witness is None:
        return ""
    shown = ", ".join(f"{n}={v[0]:.4g}" for n, v in witness.configuration[:SHOWN_COORDINATES])
    more = ", ..." if len(witness.configuration) > SHOWN_COORDINATES else ""
    return f"; e.g. sample {witness.sample}: {shown}{more}"


def _percent(s: Share) -> str:
    return (
        f"{s.hits:,} of {s.samples:,} samples ({100 * s.share:.2f}%, 95% interval "
        f"{100 * s.low:.2f}-{100 * s.high:.2f}%)"
    )


def _pair_findings(prepared: Prepared, pairs: Sequence[PairReport]) -> list[Diagnostic]:
    out = []
    srdf = prepared.matrix == "srdf"
    for p in pairs:
        rule, name = p.rule, f"'{p.link1}' and '{p.link2}'"
        if rule is None or prepared.matrix == "none" or p.collisions is None:
            continue
        line, file = rule.line, rule.file
        always = p.collisions.hits >= ALWAYS_SHARE * p.collisions.samples
        if srdf and disabled_but_reachable(p):
            out.append(
                finding(
                    "collision-disabled-but-reachable",
                    None,
                    f"the SRDF disables {name} (reason {rule.reason}), but they collide in "
                    f"{_percent(p.collisions)}{_example(p.witness)}",
                    line,
                    file,
                )
            )
        elif srdf and rule.checked and always:
            out.append(
                finding(
                    "collision-always",
                    None,
                    f"{name} collide in {_percent(p.collisions)} and the SRDF does not "
                    "disable them: MoveIt finds (nearly) every configuration in collision",
                    line,
                    file,
                )
            )
        elif srdf and rule.checked and p.kind == "default":
            out.append(
                finding(
                    "collision-at-default",
                    None,
                    f"{name} collide at the default configuration and the SRDF does not "
                    f"disable them (they collide in {_percent(p.collisions)})",
                    line,
                    file,
                )
            )
        elif not srdf and rule.checked and always:
            out.append(
                finding(
                    "collision-filter-always",
                    None,
                    f"{TOOLS[prepared.matrix]} checks bodies {name}, in contact in "
                    f"{_percent(p.collisions)}: contact forces between them (nearly) all the "
                    "time",
                    line,
                    file,
                )
            )
        elif (
            not srdf
            and not rule.checked
            and p.kind == "sometimes"
            and not _parent(rule, prepared.matrix)
        ):
            out.append(
                finding(
                    "collision-filtered-reachable",
                    None,
                    f"{TOOLS[prepared.matrix]}'s filters skip bodies {name} ({rule.reason}), "
                    "but they collide "
                    f"in {_percent(p.collisions)}{_example(p.witness)}: they pass through "
                    "each other in simulation",
                    line,
                    file,
                )
            )
    return out


def _parent(rule: FileRule, matrix: str) -> bool:
    """Whether ``rule`` is MuJoCo's parent-child filter (by weld bodies), no user's claim.

    Only that rule's own reason: a PhysX reason names the file's prims and joints, which
    may hold the word ("/World/transparent"), and spares no pair.
    """
    return matrix == "mjcf" and rule.reason == MUJOCO_PARENT


def _pose_findings(poses: Sequence[PoseCollision], srdf: str | None) -> list[Diagnostic]:
    """A finding for each pose with a checked pair in collision, on the pose's line."""
    return [
        finding(
            "collision-pose",
            None,
            f"stored pose '{pose.name}' ({pose.source}) has "
            + ", ".join(f"'{a}'-'{b}'" for a, b in pose.checked[:8])
            + (", ..." if len(pose.checked) > 8 else "")
            + " in collision",
            pose.line,
            srdf if pose.source == "group_state" else None,
        )
        for pose in poses
        if pose.checked
    ]
