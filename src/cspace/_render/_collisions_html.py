"""``cspace collisions --format html``: what the page of a self-collision report shows.

The page (template ``collisions.html``, filled by `cspace._render.html.collisions`) holds
the MATRIX of link pairs: the links with collision shapes on both axes in the report's
order (`CollisionReport.links`; rows from the second, columns up to the last but one), a
cell for each pair below the diagonal, coloured by the pair's share of samples in
collision on a sequential scale of `BUCKETS` (a legend beside it). Letters mark the
classes a planner skips (``A`` adjacent, ``D`` in collision at the default
configuration, ``X`` always, ``·`` never in the samples); a hatch marks a pair the file
skips (an SRDF's ``<disable_collisions>``, MuJoCo's or PhysX's filters), a blue frame
one that goes against its file (`_collisions_shared.against_file`); hovering a cell lights its
row's and column's links, and its tooltip says the pair, its class, its share with the
95% interval, and what the file says. Then the pairs to look at first, the findings,
the ranges in which every sample collides and the stored poses in collision.

Names are made printable, drawn shortened (`shown`) and HTML-escaped (``markupsafe``);
the matrix is built here as one string (up to `MATRIX_LINKS` links: 11,175 cells), the
rest by the template, which escapes every value. The page loads nothing and runs no
script (its Content-Security-Policy says so).
"""

from collections.abc import Sequence
from typing import Any

from cspace._render._collisions_shared import FILES, against_file, checked_word, split, where
from cspace._render._collisions_text import percent
from cspace._render._columns import location
from cspace._render.drawing import shown, whole_if_shortened
from cspace._reports.collisions import CollisionReport, PairReport
from cspace._safetext import printable

BUCKETS = (
    (0.0, "#ffffff", "0"),
    (0.005, "#ffffcc", "under 0.5%"),
    (0.01, "#ffeda0", "0.5-1%"),
    (0.02, "#fed976", "1-2%"),
    (0.05, "#feb24c", "2-5%"),
    (0.1, "#fd8d3c", "5-10%"),
    (0.2, "#fc4e2a", "10-20%"),
    (0.5, "#e31a1c", "20-50%"),
    (1.0, "#bd0026", "over 50%"),
    (1.0, "#800026", "100%"),
)
"""The colour scale of a pair's share of samples in collision (ColorBrewer's YlOrRd):
each bucket's upper end, colour and label; the first is no sample, the last every one.
Self-collision shares are mostly small, so the buckets grow about geometrically."""

DARK = 6
"""The first bucket dark enough for white letters."""

MARKS = {"adjacent": "A", "default": "D", "always": "X", "never": "·"}
"""The letter of each class a planner may skip (``sometimes`` has none)."""

MATRIX_LINKS = 150
"""Most links drawn in the matrix; beyond, the page lists the pairs to look at first."""

FIRST_ROWS = 200
"""Most rows of the table of the pairs to look at first."""

SKIPPED_BY = {
    "srdf": "disabled by the SRDF's <disable_collisions>",
    "mjcf": "filtered by MuJoCo's contact filters",
    "usd": "filtered by PhysX's collision filters",
    "none": "adjacent, no SRDF read",
}
"""Why a hatched pair is not checked, by `CollisionReport.matrix`."""

NAME_CHARS = 200
"""Longest name in a tooltip."""


def bucket(pair: PairReport) -> int | None:
    """The index in `BUCKETS` of the pair's share, or None when it was not sampled."""
    share = pair.collisions
    if share is None:
        return None
    if share.hits == 0:
        return 0
    if share.hits == share.samples:
        return len(BUCKETS) - 1
    return next(k for k in range(1, len(BUCKETS) - 1) if share.share <= BUCKETS[k][0])


def _name(text: str) -> str:
    return printable(text, limit=NAME_CHARS)


def tooltip(pair: PairReport, matrix: str) -> str:
    """The pair's tooltip, plain text (a line each: the pair, its share, the file's word)."""
    share = pair.collisions
    if share is None:
        sampled = f"{pair.kind}: not sampled"
    else:
        sampled = (
            f"{pair.kind}: in collision in {share.hits:,} of {share.samples:,} samples, "
            f"{100 * share.share:.2f}% (95% interval {100 * share.low:.2f}-{100 * share.high:.2f}%)"
        )
    lines = [f"{_name(pair.link1)} - {_name(pair.link2)}", sampled]
    word = checked_word(pair, matrix)
    if word:
        reason = pair.rule.reason if pair.rule is not None else None
        said = ", ".join(printable(x, limit=NAME_CHARS) for x in (reason, where(pair)) if x)
        lines.append(f"{FILES.get(matrix, matrix)}: {word}" + (f" ({said})" if said else ""))
    if against_file(pair, matrix):
        lines.append("the file says otherwise than the samples: see the findings")
    if pair.witness is not None:
        lines.append(f"first in collision at sample {pair.witness.sample:,}")
    return "\n".join(lines)


def _cell(pair: PairReport, matrix: str) -> str:
    from markupsafe import escape

    k = bucket(pair)
    classes = ["p", "ns" if k is None else f"s{k}"]
    if not pair.checked:
        classes.append("off")
    if against_file(pair, matrix):
        classes.append("bad")
    if k is not None and k >= DARK:
        classes.append("dark")
    title = str(escape(tooltip(pair, matrix))).replace("\n", "&#10;")
    mark = MARKS.get(pair.kind, "")
    return f'<td class="{" ".join(classes)}" title="{title}">{mark}</td>'


def matrix_html(report: CollisionReport) -> str:
    """The matrix of link pairs as an HTML table (see the module), "" for under 2 links."""
    from markupsafe import escape

    links = report.links
    if len(links) < 2:
        return ""
    by_names = {(p.link1, p.link2): p for p in report.pairs}

    def head(name: str, kind: str) -> str:
        title = escape(printable(name, limit=None if len(name) <= NAME_CHARS else NAME_CHARS))
        return f'<th class="{kind}" title="{title}"><div>{escape(shown(name))}</div></th>'

    rows = ['<thead><tr><th class="corner"></th>', *(head(n, "col") for n in links[:-1])]
    rows.append("</tr></thead><tbody>")
    for i in range(1, len(links)):
        cells = [f"<tr>{head(links[i], 'row')}"]
        for j in range(len(links) - 1):
            a, b = sorted((links[i], links[j]))
            pair = by_names.get((a, b)) if j < i else None
            cells.append('<td class="e"></td>' if pair is None else _cell(pair, report.matrix))
        rows.append("".join(cells) + "</tr>")
    size = max(18, min(34, 880 // len(links)))
    return f'<table class="matrix" style="--cell: {size}px">' + "\n".join(rows) + "</tbody></table>"


def hover_css(links: int) -> str:
    """CSS that lights a hovered cell's column head (its row's comes from ``tr:hover``)."""
    return "\n".join(
        f".matrix:has(td:nth-child({k}):hover) thead th:nth-child({k}) {{ background: #ffe08a; }}"
        for k in range(2, links + 1)
    )


def _pairs_rows(pairs: Sequence[PairReport], matrix: str) -> list[dict[str, Any]]:
    rows = []
    for p in pairs[:FIRST_ROWS]:
        reason = p.rule.reason if p.rule is not None else None
        said = ", ".join(printable(x) for x in (reason, where(p)) if x)
        word = checked_word(p, matrix) or "-"
        rows.append(
            {
                "pair": f"{shown(p.link1)} – {shown(p.link2)}",
                "title": f"{_name(p.link1)} - {_name(p.link2)}",
                "kind": p.kind,
                "share": percent(p.collisions),
                "hits": "-" if p.collisions is None else f"{p.collisions.hits:,}",
                "says": word + (f" ({said})" if said else ""),
                "bad": against_file(p, matrix),
            }
        )
    return rows


def view(report: CollisionReport) -> dict[str, Any]:
    """What the template shows of a self-collision report (the matrix as HTML)."""
    from markupsafe import Markup

    first, _ = split(report.pairs, report.matrix)
    drawn = len(report.links) <= MATRIX_LINKS
    return {
        "robot": shown(report.robot) or "(unnamed)",
        "robot_title": whole_if_shortened(report.robot),
        "source": printable(
            f"{report.source.path} ({report.source.format}, sha256 {report.source.sha256[:12]})"
        ),
        "srdf": printable(report.srdf) if report.srdf else None,
        "matrix_words": {
            "srdf": "the SRDF's <disable_collisions>",
            "mjcf": "MuJoCo's contact filters",
            "usd": "PhysX's collision filters",
            "none": "every pair but adjacent ones (no SRDF read)",
        }.get(report.matrix, printable(report.matrix)),
        "samples": f"{report.samples:,}",
        "seed": report.seed,
        "links": len(report.links),
        "pairs": len(report.pairs),
        "free": percent(report.free),
        "free_suggested": percent(report.free_suggested),
        "matrix": Markup(matrix_html(report) if drawn else ""),
        "matrix_left_out": not drawn,
        "hover_css": Markup(hover_css(len(report.links) - 1) if drawn else ""),
        "buckets": [(colour, label, k >= DARK) for k, (_, colour, label) in enumerate(BUCKETS)],
        "skipped_by": SKIPPED_BY.get(report.matrix, "as the file says"),
        "first": _pairs_rows(first, report.matrix),
        "first_more": max(0, len(first) - FIRST_ROWS),
        "findings": [
            {
                "severity": d.severity.value,
                "code": d.code,
                "at": location(d),
                "message": printable(d.message),
            }
            for d in report.diagnostics
        ],
        "ranges": [
            {
                "coordinate": shown(r.coordinate),
                "text": f"from {r.low:.4g} to {r.high:.4g}: {r.samples:,} samples, the free "
                f"share below {100 * r.free_high:.2f}%",
            }
            for r in report.ranges
        ],
        "poses": [
            {
                "name": shown(pose.name),
                "source": printable(pose.source),
                "line": pose.line,
                "pairs": [f"{shown(a)} – {shown(b)}" for a, b in pose.pairs[:8]],
                "more": max(0, len(pose.pairs) - 8),
                "checked": len(pose.checked),
            }
            for pose in report.poses
        ],
    }
