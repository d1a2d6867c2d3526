"""Markdown for pull-request comments (public name).

The renderers of :mod:`cspace.render.markdown`, where they live.
"""

from cspace.render.markdown import (
    render_diff_markdown,
    render_markdown,
    render_summary_markdown,
)

__all__ = ["render_diff_markdown", "render_markdown", "render_summary_markdown"]
