"""``cspace diff --format html`` names each change and note as the text diff does.

The HTML page of a diff lists the changes in a table and the notes in a list; a user
who reads the text diff in a log and the page in an artifact must meet the same words
(``C-space``, ``q/v size``, ``q/v layout``), not the JSON's kinds (``manifold``,
``size``, ``layout``). Each pair below is diffed both ways by the command a user runs.
"""

from __future__ import annotations

import re

import pytest
from lxml import etree

from cspace._reports.diff import CHANGE_LABELS

from conftest import REPO, run_cli_many

CASES = REPO / "tests" / "diff_cases"

PAIRS = {
    "retyped": (str(CASES / "retyped" / "old.urdf"), str(CASES / "retyped" / "new.urdf")),
    "added": (str(CASES / "added" / "old.urdf"), str(CASES / "added" / "new.urdf")),
    "root joint added": (
        "robots/quadruped_nobase.urdf",
        "robots/quadruped_nobase.urdf",
        "--new-root-joint",
        "floating",
    ),
    "urdf to mjcf": ("robots/arm7.urdf", "tests/pairs/arm7.xml"),
    "root joints paired": (
        "robots/quadruped_nobase.urdf",
        "tests/pairs/quadruped.xml",
        "--old-root-joint",
        "floating",
    ),
}
"""Pairs whose diffs hold every kind of change the issue named, and notes."""


def _text_rows(text: str, header: str) -> list[tuple[str, str]]:
    """(name, joint) of each row of the text table whose header row starts with ``header``."""
    lines = text.splitlines()
    starts = [k for k, line in enumerate(lines) if re.match(rf"{header}\s{{2,}}joint\s", line)]
    if not starts:
        return []
    rows = []
    for line in lines[starts[0] + 2 :]:
        if not line.strip():
            break
        cells = re.split(r"\s{2,}", line.strip())
        rows.append((cells[0], cells[1]))
    return rows


def _html_rows(page: str) -> tuple[list[tuple[str, str]], list[str]]:
    """(name, joint) of each row of the page's change table, and the text of each note."""
    tree = etree.fromstring(page.encode(), etree.HTMLParser())
    changes = []
    for row in tree.iterfind(".//table[@class='changes']/tr"):
        cells = ["".join(td.itertext()) for td in row.findall("td")]
        if cells:
            changes.append((cells[0], cells[1] or "-"))
    notes = [
        "".join(li.itertext()) for li in tree.xpath("//h2[.='Notes']/following-sibling::ul[1]/li")
    ]
    return changes, notes


@pytest.fixture(scope="module")
def diffs() -> dict[str, tuple[str, str]]:
    """Each pair's text diff and HTML diff, run as a user runs them."""
    commands = []
    for pair in PAIRS.values():
        commands += [("diff", *pair), ("diff", *pair, "--format", "html")]
    runs = run_cli_many(commands)
    for command, run in zip(commands, runs, strict=True):
        assert run.code in (0, 1), (command, run.stderr)
    return {name: (runs[2 * k].stdout, runs[2 * k + 1].stdout) for k, name in enumerate(PAIRS)}


@pytest.mark.parametrize("pair", list(PAIRS))
def test_the_html_diff_names_each_change_and_note_as_the_text_diff(
    diffs: dict[str, tuple[str, str]], pair: str
) -> None:
    text, page = diffs[pair]
    changes, notes = _html_rows(page)
    assert changes == _text_rows(text, "change")
    expected = _text_rows(text, "note")
    assert len(notes) == len(expected)
    for note, (name, joint) in zip(notes, expected, strict=True):
        assert note.startswith(f"{name}:" if joint == "-" else f"{name} {joint}:"), note


def test_the_pairs_hold_the_words_that_differed(diffs: dict[str, tuple[str, str]]) -> None:
    """The pairs show the changes the HTML page named otherwise (``manifold``, ``size``,
    ``layout``), in changes and in notes, and no page shows a kind the text does not."""
    names = set()
    for _, page in diffs.values():
        changes, notes = _html_rows(page)
        names |= {name for name, _ in changes}
        names |= {label for label in CHANGE_LABELS.values() for n in notes if n.startswith(label)}
        kinds = {kind for kind, label in CHANGE_LABELS.items() if kind != label}
        assert not {name for name, _ in changes} & kinds
    wanted = {"C-space", "q/v size", "q/v layout", "root joint", "joint retyped", "limits"}
    assert wanted | {"joint added", "stored as", "root joints paired", "Drake floats"} <= names
