"""The kinematic tree alone, as one SVG image: ``inspect --format svg``.

Each joint is coloured by its space, as on the HTML page (`html`), with a legend of the
spaces it uses; names from the file are made printable and shortened (`shown`), and
every text is escaped as XML.
"""

from __future__ import annotations

from html import escape
from typing import TYPE_CHECKING

from cspace._render.drawing import SPACES, shown, space_class
from cspace._render.tree import tree_svg
from cspace._safetext import printable

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.report import Report


def render_svg(report: Report) -> str:
    """The kinematic tree with each joint's space and a legend, as one SVG image."""
    document = report.to_dict()
    tree, width, height = tree_svg(document, collapse_fixed=True)
    used = sorted({space_class(j) for j in document["joints"]}, key=list(SPACES).index)
    notation = printable(str(document["manifold"]["notation"]), limit=None)
    title = f"{shown(document['robot'])}: C = {notation}"
    legend = [
        f'<g transform="translate(16,{52 + 18 * k})"><rect width="22" height="6" y="-6" '
        f'fill="{SPACES[name][0]}"/><text x="30" font-size="12">{_xml(SPACES[name][1])}</text></g>'
        for k, name in enumerate(used)
    ]
    top = 60 + 18 * len(used)
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{max(width, 420)}" '
        f'height="{height + top}" font-family="sans-serif">'
        f'<rect width="100%" height="100%" fill="#fff"/>'
        f'<text x="16" y="28" font-size="18" font-weight="600">{_xml(title)}</text>'
        + "".join(legend)
        + f'<g transform="translate(0,{top})">{tree}</g></svg>\n'
    )


def _xml(value: str) -> str:
    return escape(value, quote=True)


def inspect_one(report: Report, options: Options) -> str:
    """``inspect --format svg`` of one robot: its tree (`render_svg`)."""
    return render_svg(report)


def inspect_piece(report: Report) -> str:
    """One robot's tree, for a folder of pictures (``--output-dir``)."""
    return render_svg(report)
