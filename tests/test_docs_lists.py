"""Every list of robot formats, and every list of the maps between conventions, is whole.

The formats are taken from the format table (`cspace._formats.table.FORMATS`), and
the loader tells each (an XML format by its root element, xacro a ``<robot>`` asked for
by name, the others by their bytes); the report's schema enumerates the same
(``source.format``). The maps are taken from the conventions registry
(`cspace.conventions.TOOLS`: Pinocchio, MuJoCo, Drake, Isaac), with ``named`` (values
by joint, as a ROS JointState holds them) and OMPL's state space (``to_ompl``).

A *list* is three or more names in a run, joined by commas, semicolons, slashes, "and"
or "or" (a short parenthesis after a name allowed): "URDF, xacro, MJCF, SDF or
OpenUSD", "`canonical`, `pinocchio` or `mujoco`". Each list on a documentation page
names every format (or every map); so does each list in a docstring, a comment or a
``--help`` text of the package (there, the registry's tools). A list of the XML formats
(the word XML just before it) is whole with four. A list that means to be a part (the
tools that order joints depth first, the formats a test's corpus holds) is named in
`PARTS` with why (and a list of the conventions whose velocities need the configurations
is whole: `AT`); an entry of `PARTS` that no longer matches anything fails too. Besides,
the pages a user reads for the formats, or for the maps, name every one, and the tables
of formats (``source.format`` in the report's fields, the formats' table, the Pinocchio
models' table) have a row or a value for each.
"""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import pytest
from lxml import etree

from cspace._cli.commands.convert import CONVENTIONS
from cspace._cli.main import build_parser
from cspace._formats.detect import detect
from cspace._formats.table import FORMATS as TABLE
from cspace._formats.table import names, told_by_bytes
from cspace.conventions import TOOLS
from cspace.space import ConfigurationSpace

from conftest import REPO

DOCS = REPO / "docs"
PAGES = sorted(DOCS.rglob("*.md"))
SOURCES = sorted((REPO / "src" / "cspace").rglob("*.py"))

FORMAT_WORDS = {
    "urdf": ("URDF",),
    "xacro": ("xacro",),
    "mjcf": ("MJCF",),
    "sdf": ("SDF",),
    "usd": ("OpenUSD", "USD"),
}
"""How the pages write each format (``source.format`` on the left)."""

FORMAT_PAGES = ("index.md", "getting-started.md", "formats.md", "cli.md", "ci.md", "api.md")
"""The pages a user reads for what cspace reads: each names every format."""

SRDF_PAGES = ("index.md", "getting-started.md", "formats.md", "cli.md", "api.md")
"""The pages that say what cspace reads beside a URDF: each names the SRDF."""

MAP_PAGES = ("index.md", "conventions.md")
"""The pages a user reads for the maps: each lists every one."""

PARTS = {
    ("ci.md", "URDF, xacro, MJCF"): "the Action test's scratch repositories",
    ("conventions.md", "URDF, MJCF and SDF"): "the files Drake's tests read (Drake reads no USD)",
    ("conventions.md", "MuJoCo, Pinocchio and Drake"): "the tools that go depth first, not Isaac",
    ("_reports/diff.py", "URDF, xacro, SDF, OpenUSD"): "the formats Pinocchio stores, not MJCF",
}
"""Lists that are parts on purpose: (page or module under src/cspace, the list) -> why."""


def _formats() -> set[str]:
    """The formats of the table, each told by the loader as the table says."""
    for row in TABLE:
        if row.root:
            name = "r" + (row.suffixes[0] if row.on_request else ".x")
            element = etree.fromstring(f"<{row.root}/>".encode())
            assert detect(name, element, data=b"") is row
        else:
            for lead in row.magic:
                assert any(told_by_bytes("r" + s, lead + b"\n") is row for s in row.suffixes)
    return set(names())


def _maps() -> tuple[str, ...]:
    """The registry's tools, ROS's values by joint and OMPL's state space."""
    assert "named" in CONVENTIONS  # convert --to named: values by joint, a ROS JointState
    assert callable(getattr(ConfigurationSpace, "to_ompl", None))  # OMPL's state space
    return (*_tools(), "ROS", "OMPL")


def _tools() -> tuple[str, ...]:
    return tuple(tool.title for name, tool in TOOLS.items() if name != "canonical")


def _schema_formats() -> set[str]:
    schema = json.loads((REPO / "src" / "cspace" / "_schema" / "report-v1.schema.json").read_text())
    found: list[list[str]] = []

    def walk(node: object) -> None:
        if isinstance(node, dict):
            if "format" in node and isinstance(node["format"], dict) and "enum" in node["format"]:
                found.append(node["format"]["enum"])
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(schema)
    assert len(found) == 1
    return set(found[0])


FORMATS = _formats()
MAPS = _maps()


class Kind:
    """One kind of list: its words, and which of them a whole list names."""

    def __init__(self, words: dict[str, tuple[str, ...]], code: bool = False) -> None:
        self.words = words
        spelled = sorted({w for ws in words.values() for w in ws}, key=len, reverse=True)
        name = "|".join(re.escape(w) for w in spelled)
        one = rf"`(?:{name})`" if code else rf"(?<![\w.-])(?:{name})(?![\w-])"
        one = rf"(?:{one})(?:\s*\([^()]{{0,60}}\))?"
        join = r"\s*(?:,|;|/|\band\b|\bor\b)\s*(?:(?:and|or)\s+)?"
        self.run = re.compile(rf"{one}(?:{join}{one})+")
        self.word = re.compile(rf"`({name})`" if code else rf"(?<![\w.-])({name})(?![\w-])")

    def named(self, text: str) -> set[str]:
        """The keys of the words ``text`` names."""
        found = set(self.word.findall(text))
        return {key for key, ws in self.words.items() if found & set(ws)}

    def lists(self, text: str) -> list[tuple[str, set[str]]]:
        """Each list in ``text`` (a run of three names or more), and the keys it names."""
        out = []
        for match in self.run.finditer(text):
            keys = self.named(match.group(0))
            before = text[max(0, match.start() - 40) : match.start()]
            if len(keys) >= 3 and "XML" not in before:
                out.append((" ".join(match.group(0).split()), keys))
        return out


FORMAT_NAMES = Kind(FORMAT_WORDS)
FORMAT_CODES = Kind({f: (f,) for f in FORMAT_WORDS}, code=True)
MAP_NAMES = Kind({m: (m,) for m in MAPS})
TOOL_NAMES = Kind({t: (t,) for t in _tools()})
CONVENTION_CODES = Kind({c: (c,) for c in CONVENTIONS}, code=True)


AT = {name for name, tool in TOOLS.items() if tool.velocity_needs_at}
"""The conventions whose velocities need the configurations (``convert --at``): a list
of them is whole too."""


def _short(kind: Kind, keys: set[str], whole: set[str], where: str, text: str) -> str | None:
    """Why a list is short, or None when it is whole or a part on purpose."""
    missing = whole - keys
    if not missing or (where, text) in PARTS or (kind is CONVENTION_CODES and keys == AT):
        return None
    return f"{where}: {text!r} leaves out {sorted(missing)}"


def _where(path: Path) -> str:
    if path.is_relative_to(DOCS):
        return str(path.relative_to(DOCS))
    return str(path.relative_to(REPO / "src" / "cspace"))


def test_the_format_words_are_the_readers_formats_and_the_schemas() -> None:
    assert FORMATS == set(FORMAT_WORDS) == _schema_formats()


@pytest.mark.parametrize("page", PAGES, ids=lambda p: _where(p))
def test_each_list_on_a_page_names_every_format_and_every_map(page: Path) -> None:
    text = page.read_text(encoding="utf-8")
    where = _where(page)
    checks = (
        (FORMAT_NAMES, FORMATS),
        (FORMAT_CODES, FORMATS),
        (MAP_NAMES, set(MAPS)),
        (CONVENTION_CODES, set(TOOLS)),
    )
    assert _short_lists(text, where, checks) == []


def _short_lists(text: str, where: str, checks: tuple[tuple[Kind, set[str]], ...]) -> list[str]:
    """Why each list of ``text`` that ``checks`` finds falls short of its whole set."""
    return [
        why
        for kind, whole in checks
        for listed, keys in kind.lists(text)
        if (why := _short(kind, keys, whole, where, listed))
    ]


def _help_texts() -> str:
    """Every command's ``--help``, as a user reads it."""
    parser = build_parser()
    texts = [parser.format_help()]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            texts += [sub.format_help() for sub in action.choices.values()]
    return "\n".join(texts)


@pytest.mark.parametrize(
    "source", [*SOURCES, "--help"], ids=lambda p: p if isinstance(p, str) else _where(p)
)
def test_each_list_in_a_docstring_or_help_names_every_format_and_tool(source: Path | str) -> None:
    if isinstance(source, str):
        text, where = _help_texts(), source
    else:
        text, where = source.read_text(encoding="utf-8"), _where(source)
    checks = (
        (FORMAT_NAMES, FORMATS),
        (TOOL_NAMES, set(_tools())),
        (CONVENTION_CODES, set(TOOLS)),
    )
    assert _short_lists(text, where, checks) == []


def test_every_part_on_purpose_is_still_there() -> None:
    """An entry of `PARTS` that matches no list is stale: remove it."""
    found = set()
    for path in [*PAGES, *SOURCES]:
        text = path.read_text(encoding="utf-8")
        for kind in (FORMAT_NAMES, MAP_NAMES, TOOL_NAMES):
            found |= {(_where(path), listed) for listed, _ in kind.lists(text)}
        found |= {
            (_where(path), " ".join(m.group(0).split()))
            for m in FORMAT_NAMES.run.finditer(text)
            if "XML" in text[max(0, m.start() - 40) : m.start()]
        }
    assert set(PARTS) - found == set()


@pytest.mark.parametrize("name", FORMAT_PAGES)
def test_the_pages_about_formats_name_every_format_and_the_srdf(name: str) -> None:
    text = (DOCS / name).read_text(encoding="utf-8")
    assert FORMAT_NAMES.named(text) == FORMATS, name
    assert name not in SRDF_PAGES or re.search(r"\bSRDF\b", text), name


@pytest.mark.parametrize("name", MAP_PAGES)
def test_the_pages_about_maps_list_every_one(name: str) -> None:
    text = (DOCS / name).read_text(encoding="utf-8")
    assert any(keys == set(MAPS) for _, keys in MAP_NAMES.lists(text)), name


def test_the_reports_source_format_lists_the_schemas_formats() -> None:
    text = (DOCS / "getting-started.md").read_text(encoding="utf-8")
    row = next(line for line in text.splitlines() if line.startswith("| `source` |"))
    listed = re.search(r"`format` \(([^)]*)\)", row)
    assert listed is not None
    assert set(re.findall(r"`(\w+)`", listed.group(1))) == _schema_formats()


def test_the_formats_table_has_a_row_per_format() -> None:
    text = (DOCS / "formats.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `([\w:]+)` \|", text, flags=re.MULTILINE)
    assert set(rows) - {"erd:NAME"} == _schema_formats()


def test_the_api_page_says_what_the_model_of_every_format_carries() -> None:
    text = (DOCS / "api.md").read_text(encoding="utf-8")
    section = text.split("## What a Pinocchio model carries", 1)[1].split("\n## ", 1)[0]
    firsts = re.findall(r"^\| ([^|]+) \|", section, flags=re.MULTILINE)
    assert FORMAT_NAMES.named(" ".join(firsts[1:])) == FORMATS
    assert "ModelBuildError" in section
