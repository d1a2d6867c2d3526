"""The documentation's examples, run by the suite with Sybil.

Every ```python block of the README and of ``docs/`` is executed (from the repository's
folder, so ``robots/...`` is found); every ```console block is run line by line, each
``$ command`` in bash with its output (standard output and error, as a terminal shows
them) compared with the lines below it, a line ``...`` standing for any lines. Console
examples run in a scratch folder holding ``robots/``, ``tests/pairs/`` and the example files
of ``docs/examples/`` (``wrist.csv``, ``old.urdf``, ...), under the names the
documentation uses. An example that drifts from the code fails ``make test``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from sybil import Example, Sybil
from sybil.parsers.markdown import CodeBlockParser, PythonCodeBlockParser, SkipParser

REPO = Path(__file__).resolve().parent


def _matches(expected: list[str], got: list[str]) -> bool:
    """``got`` is ``expected``, where a line ``...`` stands for any lines (none too)."""
    if not expected:
        return not got
    if expected[0] == "...":
        return any(_matches(expected[1:], got[k:]) for k in range(len(got) + 1))
    return bool(got) and got[0] == expected[0] and _matches(expected[1:], got[1:])


def _run_console(example: Example) -> str | None:
    """Run each ``$ command`` of a console block; say how its output differs, if it does."""
    folder = example.namespace["console_folder"]
    commands: list[tuple[str, list[str]]] = []
    for line in str(example.parsed).splitlines():
        if line.startswith("$ "):
            commands.append((line[2:], []))
        elif commands:
            commands[-1][1].append(line.rstrip())
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "200"}
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    for command, expected in commands:
        done = subprocess.run(
            ["bash", "--noprofile", "--norc", "-c", command],
            cwd=folder,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            timeout=120,
            check=False,
        )
        got = [line.rstrip() for line in done.stdout.splitlines()]
        while expected and not expected[-1]:
            expected.pop()
        if not _matches(expected, got):
            return f"$ {command}\nexpected:\n" + "\n".join(expected) + "\ngot:\n" + done.stdout
    return None


def _setup(namespace: dict[str, Any]) -> None:
    folder = Path(tempfile.mkdtemp(prefix="cspace-docs-"))
    shutil.copytree(REPO / "robots", folder / "robots")  # copies: cspace refuses a
    shutil.copytree(REPO / "tests" / "pairs", folder / "tests" / "pairs")  # linked folder
    for example in (REPO / "docs" / "examples").iterdir():
        shutil.copy(example, folder / example.name)
    namespace["console_folder"] = folder
    namespace["previous_folder"] = os.getcwd()
    os.chdir(REPO)  # the Python examples name robots/... as a user in the checkout does


def _teardown(namespace: dict[str, Any]) -> None:
    os.chdir(namespace["previous_folder"])
    shutil.rmtree(namespace["console_folder"], ignore_errors=True)


pytest_collect_file = Sybil(
    parsers=[
        PythonCodeBlockParser(),
        CodeBlockParser(language="console", evaluator=_run_console),
        SkipParser(),
    ],
    patterns=["README.md", "docs/*.md"],
    setup=_setup,
    teardown=_teardown,
).pytest()
