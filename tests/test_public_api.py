"""The public API is what the documentation shows: every path it names resolves.

Each ``cspace.x.y`` the README and the docs name in code resolves from ``import cspace``
alone, as a user writes it (submodules are imported on first use); every import line of
their Python examples runs; every name in ``cspace.__all__`` exists.
"""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

import cspace

from conftest import REPO

DOCUMENTS = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]

_PATH = re.compile(r"`(cspace(?:\.[A-Za-z_][A-Za-z0-9_]*)+)")


def _documented_paths() -> list[str]:
    found = {m.group(1) for doc in DOCUMENTS for m in _PATH.finditer(doc.read_text())}
    return sorted(found)


def _import_lines() -> list[str]:
    lines = []
    for doc in DOCUMENTS:
        for block in re.findall(r"```python\n(.*?)```", doc.read_text(), re.DOTALL):
            lines += [
                line.strip()
                for line in block.splitlines()
                if re.match(r"\s*(import cspace|from cspace)", line)
            ]
    return sorted(set(lines))


def test_the_documents_name_paths() -> None:
    assert len(_documented_paths()) > 20 and _import_lines()


@pytest.mark.parametrize("path", _documented_paths())
def test_every_documented_path_resolves_after_import_cspace(path: str) -> None:
    # in a fresh interpreter: nothing imported before but `import cspace`
    parts = path.split(".")[1:]
    probe = "import cspace\nvalue = cspace\n" + "".join(
        f"value = getattr(value, {part!r})\n" for part in parts
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, cwd=REPO, timeout=120
    )
    assert done.returncode == 0, done.stderr.splitlines()[-1:]


@pytest.mark.parametrize("line", _import_lines())
def test_every_import_of_the_examples_runs(line: str) -> None:
    done = subprocess.run(
        [sys.executable, "-c", line], capture_output=True, text=True, cwd=REPO, timeout=120
    )
    assert done.returncode == 0, done.stderr.splitlines()[-1:]


def test_every_name_in_all_exists() -> None:
    missing = [name for name in cspace.__all__ if not hasattr(cspace, name)]
    assert missing == []


def test_no_page_speaks_of_issue_numbers_or_keeps_section_markers() -> None:
    # history belongs in the CHANGELOG; a user cannot follow "issue 14"
    for doc in DOCUMENTS:
        text = doc.read_text()
        assert not re.search(r"\bissues? \d+", text), doc
        assert "<!-- section" not in text and "<!-- /section" not in text, doc


def test_the_readme_is_a_front_page() -> None:
    assert len((REPO / "README.md").read_text().splitlines()) <= 300
