"""``cspace collisions --format markdown``: a pull-request comment of a self-collision report.

The free shares first, then a table of the pairs to look at first (those that go against
their file, and those that collide sometimes or always: `_collisions_shared.split`),
the other pairs folded in a ``<details>`` block, the ranges in which every sample
collides, the stored poses in collision, and the findings. Every text from a file
(names, paths, an SRDF's ``reason``, messages) is escaped as in every Markdown cspace
writes (`cspace._render._markdown_escape`): printable, in a code span, every pipe of a
table escaped; cspace's own words and numbers stay plain. Long lists are cut (the JSON
report has them whole) so that a comment stays within GitHub's 65,536 characters.
"""

from collections.abc import Sequence

from cspace._render._collisions_shared import against_file, checked_word, split, where
from cspace._render._collisions_text import percent
from cspace._render._columns import location
from cspace._render._markdown_escape import cell, code
from cspace._reports.collisions import CollisionReport, PairReport

FIRST_ROWS = 60
"""Most pairs in the table of those to look at first."""
OTHER_ROWS = 100
"""Most pairs in the folded table of the others."""
SHOWN_FINDINGS = 50
"""Most findings listed (each up to 600 characters)."""
NAME_CHARS = 60
"""Longest name in a table or a list (longer ones keep their start and end)."""

_MATRIX = {
    "srdf": "the SRDF's `<disable_collisions>`",
    "mjcf": "MuJoCo's contact filters",
    "usd": "PhysX's collision filters",
    "none": "every pair but adjacent ones (no SRDF read)",
}
_KINDS = {
    "never": "never in collision",
    "adjacent": "adjacent",
    "default": "in collision at the default configuration",
    "always": "always in collision",
    "sometimes": "sometimes in collision",
}
_HEADER = ("pair", "class", "in collision [95%]", "samples", "file says")


def _name(text: str) -> str:
    return code(text if len(text) <= NAME_CHARS else _cut(text))


def _cut(text: str) -> str:
    half = (NAME_CHARS - 1) // 2
    return f"{text[:half]}…{text[-half:]}"


def _line(cells: Sequence[str]) -> str:
    """A table row of Markdown cells, every pipe escaped (code spans hold them too)."""
    return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"


def _says(pair: PairReport, matrix: str) -> str:
    word = checked_word(pair, matrix)
    if not word:
        return "-"
    said = f"**{word}** ⚠" if against_file(pair, matrix) else word
    reason = pair.rule.reason if pair.rule is not None else None
    at = where(pair)
    details = [cell(x) for x in (reason, at) if x]
    return f"{said} ({', '.join(details)})" if details else said


def _table(pairs: Sequence[PairReport], matrix: str, most: int) -> list[str]:
    rows = [
        _line(
            [
                f"{_name(p.link1)} – {_name(p.link2)}",
                p.kind,
                percent(p.collisions),
                "-" if p.collisions is None else f"{p.collisions.hits:,}",
                _says(p, matrix),
            ]
        )
        for p in pairs[:most]
    ]
    more = len(pairs) - most
    tail = [f"and {more:,} more pairs (`--format json` lists every pair)", ""] if more > 0 else []
    return [_line(_HEADER), _line(["---"] * len(_HEADER)), *rows, "", *tail]


def _head(report: CollisionReport) -> list[str]:
    matrix = _MATRIX.get(report.matrix, cell(report.matrix))
    srdf = f" ({code(report.srdf)})" if report.srdf else ""
    return [
        f"### cspace collisions: {code(report.robot or '(unnamed)')}",
        "",
        f"{code(report.source.path)} ({cell(report.source.format)}), {report.samples:,} "
        f"samples (seed {report.seed}): {len(report.links):,} links with collision shapes, "
        f"{len(report.pairs):,} pairs. Pairs checked: {matrix}{srdf}.",
        "",
        f"- **Free of self-collision**: {percent(report.free)} of the samples (95% interval), "
        "with the pairs checked",
        f"- **With the pairs cspace checks**: {percent(report.free_suggested)} (MoveIt's setup "
        "assistant's matrix, `--write-srdf`)",
        "",
    ]


def _pairs(report: CollisionReport) -> list[str]:
    first, rest = split(report.pairs, report.matrix)
    out: list[str] = []
    if first:
        out += [
            f"**Pairs to look at first** ({len(first):,}; ⚠: the file says otherwise than the "
            "samples, see the findings)",
            "",
            *_table(first, report.matrix, FIRST_ROWS),
        ]
    else:
        out += ["No pair collides in some samples and not in others.", ""]
    if rest:
        kinds = ", ".join(_KINDS[k] for k in dict.fromkeys(p.kind for p in rest))
        out += [
            f"<details><summary>{len(rest):,} other pairs: {kinds}</summary>",
            "",
            *_table(rest, report.matrix, OTHER_ROWS),
            "</details>",
            "",
        ]
    return out


def _ranges(report: CollisionReport) -> list[str]:
    if not report.ranges:
        return []
    return [
        "**Ranges in which every sample collides** (with the pairs cspace checks)",
        "",
        *(
            f"- {_name(r.coordinate)} from {r.low:.4g} to {r.high:.4g}: {r.samples:,} samples, "
            f"the free share below {100 * r.free_high:.2f}%"
            for r in report.ranges
        ),
        "",
    ]


def _poses(report: CollisionReport) -> list[str]:
    if not report.poses:
        return []
    out = ["**Stored poses in collision**", ""]
    for pose in report.poses:
        line = f", line {pose.line}" if pose.line is not None else ""
        pairs = ", ".join(f"{_name(a)} – {_name(b)}" for a, b in pose.pairs[:8])
        more = f" and {len(pose.pairs) - 8:,} more" if len(pose.pairs) > 8 else ""
        out.append(
            f"- {_name(pose.name)} ({cell(pose.source)}{line}): {pairs}{more}; "
            f"{len(pose.checked):,} of them checked"
        )
    return [*out, ""]


def _findings(report: CollisionReport) -> list[str]:
    if not report.diagnostics:
        return ["No findings."]
    out = ["**Findings**", ""]
    for d in report.diagnostics[:SHOWN_FINDINGS]:
        at = location(d)
        out.append(
            f"- **{d.severity.value}** {code(d.code)}"
            + ("" if at is None else f" ({cell(at)})")
            + f": {cell(d.message)}"
        )
    more = len(report.diagnostics) - SHOWN_FINDINGS
    return [*out, *([f"- and {more:,} more (`--format json` lists them all)"] if more > 0 else [])]


def render(report: CollisionReport) -> str:
    """The Markdown of a self-collision report (see the module). Ends with a newline."""
    out = [*_head(report), *_pairs(report), *_ranges(report), *_poses(report)]
    return "\n".join([*out, *_findings(report)]) + "\n"
