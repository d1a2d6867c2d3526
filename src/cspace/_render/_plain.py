"""Text, JSON, JSON Lines, Markdown, HTML and SVG behind the signatures of `FORMATS`.

Their renderers were there before the table; these functions adapt them.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.report import Report
    from cspace._reports.summary import SummaryRow


def one_text(report: Report, options: Options) -> str:
    """The text report (`render_text`)."""
    from cspace._render.text import render_text

    return render_text(
        report, color=options.color, hide_fixed=options.hide_fixed, width=options.width
    )


def end_text(rows: Sequence[SummaryRow], pieces: Sequence[str], options: Options) -> str:
    """The summary table of several files."""
    from cspace._render.text import render_summary_text

    return render_summary_text(rows, options.width)


def one_json(report: Report, options: Options) -> str:
    """The JSON report, indented."""
    return report.to_json()


def one_jsonl(report: Report, options: Options) -> str:
    """The JSON report on one line."""
    return report.to_json(indent=None)


def piece_json(report: Report) -> str:
    """One line of JSON Lines."""
    return report.to_json(indent=None)


def one_markdown(report: Report, options: Options) -> str:
    """The Markdown report."""
    from cspace._render.markdown import render_markdown

    return render_markdown(report)


def end_markdown(rows: Sequence[SummaryRow], pieces: Sequence[str], options: Options) -> str:
    """The Markdown summary of several files."""
    from cspace._render.markdown import render_summary_markdown

    return render_summary_markdown(rows)


def one_html(report: Report, options: Options) -> str:
    """The self-contained HTML report."""
    from cspace._render.html import render_html

    return render_html(report)


def one_svg(report: Report, options: Options) -> str:
    """The tree as SVG."""
    from cspace._render.html import render_svg

    return render_svg(report)


def piece_html(report: Report) -> str:
    """One robot's page, for a folder of pages (``--output-dir``)."""
    from cspace._render.html import render_html

    return render_html(report)


def piece_svg(report: Report) -> str:
    """One robot's tree, for a folder of pictures (``--output-dir``)."""
    from cspace._render.html import render_svg

    return render_svg(report)
