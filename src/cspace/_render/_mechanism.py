"""What the text and Markdown reports say of a mechanism's closed chains, in a few lines.

After the C-space (the tree's: the mechanism's ambient space) comes the mechanism:
`Closure.summary` (``closed chains: 1 loop, mobility 1 (Grübler 0)``), the cuts that
close its loops (`MOST_CUTS` at most, then how many more), the rank found at the
configurations on it, and the actuated joints. Each text from the file (a cut's kind and
name, links, joints) goes through the caller's ``plain`` or ``quote`` (`printable` for
the terminal, a code span for Markdown).
"""

from __future__ import annotations

from collections.abc import Callable

from cspace._reports.closure import Closure, Cut

MOST_CUTS = 8
"""Most cuts listed in the text and Markdown reports (the JSON report has them all)."""

MOST_ACTUATED = 12
"""Most actuated joints named (the JSON report has them all)."""

AMBIENT = "the tree's, with its loops cut: the mechanism lies in it"
"""What the C-space line adds for a mechanism."""


def cut_line(cut: Cut, plain: Callable[[str], str], quote: Callable[[str], str]) -> str:
    """``connect 'ground_pivot': rocker to world (line 20)``.

    ``quote`` is applied to its name, ``plain`` to its kind and links.
    """
    first, second = cut.links
    at = "" if cut.line is None else f" (line {cut.line})"
    return f"{plain(cut.kind)} {quote(cut.name)}: {plain(first)} to {plain(second)}{at}"


def mechanism_lines(
    closure: Closure, plain: Callable[[str], str], quote: Callable[[str], str]
) -> list[str]:
    """The mechanism's summary, then a line per cut and the rank and actuated joints.

    ``quote`` is applied to a cut's name, ``plain`` to every other text from the file.
    """
    lines = [closure.summary]
    lines += [f"cut {cut_line(cut, plain, quote)}" for cut in closure.cuts[:MOST_CUTS]]
    if len(closure.cuts) > MOST_CUTS:
        lines.append(f"and {len(closure.cuts) - MOST_CUTS:,} more cuts")
    if closure.rank is not None:
        low, high = closure.rank
        ranks = f"rank {high}" if low == high else f"rank {low} to {high}"
        singular = len(closure.singularities)
        lines.append(
            f"{ranks} at the {closure.samples} configurations found ({closure.attempts} "
            "projected)" + (f", {singular} singular listed" if singular else "")
        )
    if closure.actuated:
        names = ", ".join(plain(name) for name in closure.actuated[:MOST_ACTUATED])
        more = len(closure.actuated) - MOST_ACTUATED
        names += f" and {more:,} more" if more > 0 else ""
        chart = {True: ": a chart of the mechanism", False: ": not a chart of it", None: ""}
        lines.append(f"actuated {names}{chart[closure.chart]}")
    return lines
