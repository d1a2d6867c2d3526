"""``cspace collisions`` for people: the free share, the pairs by class, ranges, findings.

Every name and path from a file passes through `printable`; pairs are listed by class
(those a planner must check first), each with its share of samples in collision, the
95% interval, and what the robot's SRDF, MuJoCo's or PhysX's filters say of it.
"""

from collections.abc import Sequence

from cspace._render._columns import location, table
from cspace._render.formats import Options
from cspace._reports.collisions import CollisionReport, PairReport, Share
from cspace._safetext import printable

ORDER = ("sometimes", "always", "default", "never", "adjacent")
"""The classes in the order they are listed: what a planner checks first."""

MATRICES = {
    "srdf": "the SRDF's <disable_collisions>",
    "mjcf": "MuJoCo's contact filters",
    "usd": "PhysX's collision filters (UsdPhysics)",
    "none": "every pair but adjacent ones (no SRDF read)",
}


def percent(s: Share | None) -> str:
    """``12.34% [11.0, 13.8]``: the share and its 95% interval, in percent."""
    if s is None:
        return "not sampled"
    return f"{100 * s.share:.2f}% [{100 * s.low:.2f}, {100 * s.high:.2f}]"


def _rule(pair: PairReport) -> str:
    rule = pair.rule
    if rule is None:
        return ""
    said = "checked" if rule.checked else "skipped"
    why = f" ({printable(rule.reason, limit=160)})" if rule.reason else ""
    where = f" line {rule.line}" if rule.line is not None else ""
    return f"{said}{why}{where}"


def _rows(pairs: Sequence[PairReport]) -> list[list[str]]:
    ordered = sorted(pairs, key=lambda p: (ORDER.index(p.kind), p.link1, p.link2))
    return [
        [
            f"{printable(p.link1, limit=60)} - {printable(p.link2, limit=60)}",
            p.kind,
            "-" if p.collisions is None else f"{p.collisions.hits:,}",
            percent(p.collisions),
            _rule(p),
        ]
        for p in ordered
    ]


def render(report: CollisionReport, options: Options) -> str:
    """The whole text output of one robot's self-collision report."""
    name = printable(report.robot, limit=80)
    lines = [
        f"{name}: self-collision over {report.samples:,} samples (seed {report.seed}) of "
        f"{printable(report.source.path)} ({report.source.format})",
        f"  links with collision shapes: {len(report.links)}, pairs: {len(report.pairs)}",
        f"  pairs checked: {MATRICES.get(report.matrix, report.matrix)}"
        + (f", {printable(report.srdf)}" if report.srdf else ""),
        f"  free of self-collision:       {percent(report.free)}",
        f"  with the pairs cspace checks: {percent(report.free_suggested)}"
        " (MoveIt's setup assistant's matrix, --write-srdf)",
        "",
    ]
    header = ["pair", "class", "samples", "in collision [95%]", "file says"]
    lines += table(header, _rows(report.pairs), options.width)
    if report.ranges:
        lines += ["", "Ranges in which every sample collides (the pairs cspace checks):"]
        for r in report.ranges:
            lines.append(
                f"  {printable(r.coordinate, limit=80)} in [{r.low:.4g}, {r.high:.4g}]: "
                f"{r.samples:,} samples, free share below {100 * r.free_high:.2f}%"
            )
    if report.poses:
        lines += ["", "Stored poses in collision:"]
        for pose in report.poses:
            pairs = ", ".join(
                f"{printable(a, limit=40)} - {printable(b, limit=40)}" for a, b in pose.pairs[:8]
            )
            more = f" and {len(pose.pairs) - 8} more" if len(pose.pairs) > 8 else ""
            lines.append(f"  {printable(pose.name, limit=80)} ({pose.source}): {pairs}{more}")
    if report.diagnostics:
        lines += ["", "Findings:"]
        for d in report.diagnostics:
            where = location(d)
            at = f" [{where}]" if where else ""
            lines.append(f"  {d.severity.value} {d.code}{at}: {printable(d.message)}")
    return "\n".join(lines)
