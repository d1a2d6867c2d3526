"""One minimum Python version everywhere a user meets one: the package's metadata, the
type checker, the linter, the README, the getting-started page and the Action's check."""

from __future__ import annotations

import re
import sys
import tomllib

from conftest import REPO


def test_one_minimum_python_version_everywhere() -> None:
    project = tomllib.loads((REPO / "pyproject.toml").read_text())
    minimum = project["project"]["requires-python"].removeprefix(">=")
    major, minor = (int(n) for n in minimum.split("."))
    assert sys.version_info[:2] >= (major, minor)  # the tests run on a supported one
    assert project["tool"]["mypy"]["python_version"] == minimum
    assert project["tool"]["ruff"]["target-version"] == f"py{major}{minor}"
    for page in ("README.md", "docs/getting-started.md"):
        said = set(re.findall(r"Python (3\.\d+)\+", (REPO / page).read_text()))
        assert said == {minimum}, (page, said)
    action = (REPO / "action.yml").read_text()
    assert f"sys.version_info < ({major}, {minor})" in action
    assert f"cspace needs Python {minimum} or later" in action
