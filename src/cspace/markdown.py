"""Markdown for pull-request comments (public name).

The renderers of `markdown`, where they live.
"""

from cspace._render.markdown import (
    render_diff_markdown,
    render_markdown,
    render_summary_markdown,
)

__all__ = ["render_diff_markdown", "render_markdown", "render_summary_markdown"]
