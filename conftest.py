"""The documentation's examples, run by the suite with Sybil.

Every ```python block of the README and of ``docs/`` is executed; every ```console block
is run line by line, each ``$ command`` in bash with its output (standard output and
error, as a terminal shows them) compared with the lines below it, a line ``...``
standing for any lines. Examples run in a scratch folder laid out as the checkout
(``robots/``, ``tests/pairs/``, ``tests/closed/``, ``docs/examples/``), with the example files of
``docs/examples/`` also at its top (``wrist.csv``, ``old.urdf``, ...), where the pages
use them as a user's own files. An example that drifts from
the code fails ``make test``.

With ``CSPACE_DOCS_PYTHON`` set to another interpreter (the fresh environment the wheel is
installed in, by ``tests/test_installed.py``), every example runs there instead: each
document's Python blocks in one interpreter of it, one after another in one namespace
(as Sybil keeps one namespace a document), each console block with that interpreter's ``bin``
first on ``PATH``.
"""

from __future__ import annotations

import json
import os
import select
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from sybil import Example, Sybil
from sybil.parsers.markdown import CodeBlockParser, PythonCodeBlockParser, SkipParser

REPO = Path(__file__).resolve().parent
OTHER_PYTHON = os.environ.get("CSPACE_DOCS_PYTHON")
"""The interpreter the examples run in, when not this one (the installed wheel's)."""


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
    env["PATH"] = f"{Path(OTHER_PYTHON or sys.executable).parent}{os.pathsep}{env['PATH']}"
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


_SESSION = r"""
def _serve():  # its names apart from the examples' (which are __main__'s, as a script's)
    import contextlib, io, json, os, sys, traceback

    answers = int(sys.argv[1])
    namespace = sys.modules["__main__"].__dict__  # functions defined there pickle
    while header := sys.stdin.buffer.readline():
        code = sys.stdin.buffer.read(int(header)).decode("utf-8")
        said = io.StringIO()
        ok = True
        with contextlib.redirect_stderr(said):
            try:
                exec(compile(code, "<example>", "exec"), namespace)
            except SystemExit as stop:
                ok = stop.code in (None, 0)
            except BaseException:
                traceback.print_exc()
                ok = False
        sys.stdout.flush()
        os.write(answers, json.dumps({"ok": ok, "stderr": said.getvalue()}).encode() + b"\n")

_serve()
"""
"""Runs a document's Python blocks one after another in the namespace of ``__main__``, as
Sybil keeps one namespace a document: each block is its length on a line then its text
on standard input; each answer a line of JSON on the file descriptor given as its
argument (whether it ran, and what it wrote on standard error), apart from the output
the examples and their children make."""


def _session(example: Example) -> tuple[subprocess.Popen[bytes], int]:
    """The document's interpreter of OTHER_PYTHON, and where its answers are read."""
    if "python_session" not in example.namespace:
        answers, theirs = os.pipe()
        log = tempfile.TemporaryFile()  # noqa: SIM115  (closed in _teardown)
        session = subprocess.Popen(
            [str(OTHER_PYTHON), "-I", "-c", _SESSION, str(theirs)],
            cwd=example.namespace["console_folder"],
            stdin=subprocess.PIPE,
            stdout=subprocess.DEVNULL,
            stderr=log,
            pass_fds=(theirs,),
        )
        os.close(theirs)
        example.namespace["python_session"] = (session, answers, log)
    session, answers, _ = example.namespace["python_session"]
    return session, answers


def _run_python_elsewhere(example: Example) -> str | None:
    """Run a Python block in OTHER_PYTHON, in its document's one interpreter."""
    session, answers = _session(example)
    assert session.stdin is not None
    code = str(example.parsed).encode("utf-8")
    session.stdin.write(b"%d\n%s" % (len(code), code))
    session.stdin.flush()
    answer = b""
    while not answer.endswith(b"\n"):
        if not select.select([answers], [], [], 300)[0]:  # a guard against a hang
            break
        more = os.read(answers, 1 << 16)
        if not more:
            break
        answer += more
    if not answer.endswith(b"\n"):
        session.kill()
        session.wait()
        log = example.namespace["python_session"][2]
        log.seek(0)
        said = log.read().decode("utf-8", "replace")
        return f"no answer from {OTHER_PYTHON} (it ended, or took over 300 s):\n{said}"
    result = json.loads(answer)
    return None if result["ok"] else f"failed in {OTHER_PYTHON}:\n{result['stderr']}"


def _setup(namespace: dict[str, Any]) -> None:
    folder = Path(tempfile.mkdtemp(prefix="cspace-docs-"))
    shutil.copytree(REPO / "robots", folder / "robots")  # copies: cspace refuses a
    shutil.copytree(REPO / "tests" / "pairs", folder / "tests" / "pairs")  # linked folder
    shutil.copytree(REPO / "tests" / "closed", folder / "tests" / "closed")  # mechanisms
    shutil.copytree(REPO / "docs" / "examples", folder / "docs" / "examples")
    for example in (REPO / "docs" / "examples").iterdir():  # as a user's own files too
        shutil.copy(example, folder / example.name)
    namespace["console_folder"] = folder
    namespace["__name__"] = "__main__"  # as a script the user runs
    namespace["previous_folder"] = os.getcwd()
    os.chdir(folder)  # the Python examples name robots/... as a user in a checkout does


def _teardown(namespace: dict[str, Any]) -> None:
    try:
        if "python_session" in namespace:
            session, answers, log = namespace["python_session"]
            try:
                session.stdin.close()
                session.wait(timeout=60)
            finally:
                session.kill()
                os.close(answers)
                log.close()
    finally:
        os.chdir(namespace["previous_folder"])
        shutil.rmtree(namespace["console_folder"], ignore_errors=True)


pytest_collect_file = Sybil(
    parsers=[
        CodeBlockParser(language="python", evaluator=_run_python_elsewhere)
        if OTHER_PYTHON
        else PythonCodeBlockParser(),
        CodeBlockParser(language="console", evaluator=_run_console),
        SkipParser(),
    ],
    patterns=["README.md", "docs/*.md"],
    setup=_setup,
    teardown=_teardown,
).pytest()
