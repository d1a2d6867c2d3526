"""Packaging as a user meets it: a wheel that builds without warnings, and types that a
user's type checker sees.

An editable install (what ``make`` does for development) hides the package behind an
import hook that mypy cannot follow; a user installs a wheel. So the wheel is built
(``tree_wheel``, once a run: test_installed compares it with the sdist's), unpacked, and
mypy checks a small user script against it.
"""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

from conftest import REPO


def test_the_wheel_builds_without_deprecation_warnings(tree_wheel: tuple[Path, str]) -> None:
    built, log = tree_wheel
    assert "DeprecationWarning" not in log, [s for s in log.splitlines() if "Deprecation" in s]
    names = zipfile.ZipFile(built).namelist()
    assert "cspace/py.typed" in names
    assert any(n.endswith("licenses/LICENSE") for n in names)


def test_a_users_type_checker_sees_the_types(tree_wheel: tuple[Path, str], tmp_path: Path) -> None:
    site = tmp_path / "site"
    zipfile.ZipFile(tree_wheel[0]).extractall(site)
    script = tmp_path / "user.py"
    script.write_text(
        "import cspace\n"
        'report = cspace.inspect("robots/arm7.urdf")\n'
        "reveal_type(report)\n"
        "dimension: int = report.dimension\n"
        "name: str = report.dimension  # a user's mistake: mypy must see it\n"
    )
    run = subprocess.run(
        [sys.executable, "-m", "mypy", "--no-incremental", "--follow-imports=silent", str(script)],
        capture_output=True,
        text=True,
        env={**os.environ, "MYPYPATH": str(site)},
        cwd=tmp_path,
        timeout=300,
    )
    assert 'fallback=cspace._reports.report.Report]"' in run.stdout, run.stdout  # a NamedTuple
    errors = [line for line in run.stdout.splitlines() if ": error:" in line]
    assert len(errors) == 1 and "user.py:5" in errors[0], run.stdout


def test_the_wheel_holds_every_package_of_the_source(tree_wheel: tuple[Path, str]) -> None:
    # packages were listed by hand, and cspace.errors was missing: the installed
    # command failed with ModuleNotFoundError while the editable install hid it
    names = set(zipfile.ZipFile(tree_wheel[0]).namelist())
    missing = [
        "/".join(path.relative_to(REPO / "src").parts)
        for path in (REPO / "src" / "cspace").rglob("*.py")
        if "__pycache__" not in path.parts
        and "/".join(path.relative_to(REPO / "src").parts) not in names
    ]
    assert missing == []


def test_the_wheel_holds_no_module_the_source_does_not(tree_wheel: tuple[Path, str]) -> None:
    # a module renamed or removed must not live on in the wheel (setuptools' build/ kept
    # the old names of every renamed module, and a wheel built in place shipped them)
    source = {"/".join(p.relative_to(REPO / "src").parts) for p in (REPO / "src").rglob("*.py")}
    names = zipfile.ZipFile(tree_wheel[0]).namelist()
    extra = [n for n in names if n.endswith(".py") and n not in source]
    assert extra == []
    assert any("_render/templates/" in n for n in names)
    schemas = {"cspace/_schema/report-v1.schema.json", "cspace/_schema/collisions-v1.schema.json"}
    assert schemas <= set(names)  # cspace schema, cspace schema --collisions


def test_the_command_runs_from_the_wheel_alone(
    tree_wheel: tuple[Path, str], tmp_path: Path
) -> None:
    site = tmp_path / "site"
    zipfile.ZipFile(tree_wheel[0]).extractall(site)
    script = (
        "import sys\n"
        "sys.meta_path[:] = [f for f in sys.meta_path if 'editable' not in repr(f)]\n"
        f"sys.path.insert(0, {str(site)!r})\n"
        "from cspace._cli.main import main\n"
        "import cspace\n"
        f"assert cspace.__file__.startswith({str(site)!r}), cspace.__file__\n"
        f"sys.exit(main(['inspect', {str(REPO / 'robots' / 'arm7.urdf')!r}, '--format', 'html']))\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=tmp_path, timeout=120
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("<!DOCTYPE html>") and "arm7" in run.stdout
