"""The output formats are one table: a renderer is one module and one row of `FORMATS`.

Each row's module has the functions of the commands the row says it serves, and only
those; ``inspect``, ``diff`` and ``check`` offer exactly the rows that serve them, with
each row's help, and call nothing but the row's module. A toy format added from outside
the package, a module and a row, is offered and used by all three commands at once.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import inspect
import shutil
import sys
import textwrap
from pathlib import Path
from typing import get_args

import pytest

import cspace
from cspace._cli.main import build_parser, main
from cspace._render.formats import FORMATS, FUNCTIONS, Command, Format, Renderer

from conftest import ROBOTS

COMMANDS: tuple[Command, ...] = get_args(Command)


def _format_option(command: str) -> argparse.Action:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return next(a for a in sub.choices[command]._actions if a.dest == "format")


def _parameters(function: object) -> list[str]:
    names = list(inspect.signature(function).parameters)  # type: ignore[arg-type]
    return names[1:] if names[:1] == ["self"] else names


@pytest.mark.parametrize("name", sorted(FORMATS))
def test_each_rows_module_has_the_functions_of_the_commands_it_serves(name: str) -> None:
    row = FORMATS[name]
    module = importlib.import_module(row.module)
    for command in COMMANDS:
        present = [f for f in FUNCTIONS[command] if hasattr(module, f)]
        if not row.help_for(command):
            assert present == [], f"{name}: {present} without serving {command}"
            continue
        assert FUNCTIONS[command][0] in present, f"{name} serves {command}"
        for function in present:
            expected = _parameters(getattr(Renderer, function))
            assert _parameters(getattr(module, function)) == expected, (name, function)


def test_the_commands_offer_exactly_the_rows_that_serve_them() -> None:
    assert set(FUNCTIONS) == set(COMMANDS)
    for command in COMMANDS:
        action = _format_option(command)
        serving = tuple(n for n, f in FORMATS.items() if f.help_for(command))
        assert tuple(action.choices or ()) == serving
        assert action.help is not None
        for name in serving:
            assert FORMATS[name].help_for(command) in action.help
    assert _format_option("diff").choices == ("text", "json", "markdown", "html")
    assert _format_option("check").choices == ("text", "markdown", "github")


TOY = """
def inspect_one(report, options):
    return f"toy one: {report.robot}: {report.manifold.notation}\\n::warning::toy"


def inspect_piece(report):
    return f"toy piece: {report.robot}"


def inspect_end(rows, pieces, options):
    return f"toy end: {len(rows)} rows, {len(pieces)} pieces"


def diff(old, new, changes, options):
    return f"toy diff: {changes.verdict}: {old['robot']} -> {new['robot']}"


def check(rows, options):
    return "\\n".join(f"toy check: {r.verdict}: {r.path}" for r in rows)


def collisions(report, options):
    return f"toy collisions: {report.robot}: {report.samples} samples, {len(report.pairs)} pairs"
"""
"""A renderer outside the package; its one robot's output holds a workflow command."""


def test_a_toy_format_is_one_module_and_one_row(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "toy_renderer.py").write_text(textwrap.dedent(TOY))
    spec = importlib.util.spec_from_file_location("toy_renderer", tmp_path / "toy_renderer.py")
    assert spec is not None and spec.loader is not None
    toy = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(toy)
    monkeypatch.setitem(sys.modules, "toy_renderer", toy)  # both removed after the test
    row = Format(
        "toy_renderer",
        inspect="toy to inspect",
        diff="toy to diff",
        check="toy to check",
        collisions="toy to collisions",
    )
    monkeypatch.setitem(FORMATS, "toy", row)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "r").mkdir()
    for name in ("arm7.urdf", "turntable_multiturn.urdf"):
        shutil.copy(ROBOTS / name, tmp_path / "r" / name)
    arm = cspace.inspect(ROBOTS / "arm7.urdf")
    turntable = cspace.inspect(ROBOTS / "turntable_multiturn.urdf")

    def run(*args: str) -> tuple[int, str]:
        try:
            code = main(list(args))
        except SystemExit as exc:  # --help
            code = int(exc.code or 0)
        return code, capsys.readouterr().out

    for command in COMMANDS:
        code, out = run(command, "--help")
        words = " ".join(out.split())  # as argparse wraps it
        assert code == 0 and f"toy to {command}" in words
        assert ",toy}" in words, command  # the last of the choices

    code, out = run("inspect", "r/arm7.urdf", "--format", "toy")
    assert code == 0
    # written through output.write: the toy's workflow command is neutralised
    assert out == f"toy one: {arm.robot}: {arm.manifold.notation}\n\\x3a:warning::toy\n"

    code, out = run(
        "inspect", "r/arm7.urdf", "r/turntable_multiturn.urdf", "-j", "1", "--format", "toy"
    )
    assert code == 0
    assert out.splitlines() == [
        f"toy piece: {arm.robot}",
        f"toy piece: {turntable.robot}",
        "toy end: 2 rows, 0 pieces",
    ]

    code, out = run("diff", "r/arm7.urdf", "r/turntable_multiturn.urdf", "--format", "toy")
    assert (code, out) == (1, f"toy diff: changed: {arm.robot} -> {turntable.robot}\n")

    shapes = cspace.collisions(ROBOTS / "arm7.urdf", samples=20)
    code, out = run("collisions", "r/arm7.urdf", "-n", "20", "--format", "toy")
    assert (code, out) == (
        0,
        f"toy collisions: {arm.robot}: 20 samples, {len(shapes.pairs)} pairs\n",
    )

    code, baseline = run("inspect", "--format", "jsonl", "r")
    (tmp_path / "base.jsonl").write_text(baseline)
    (tmp_path / "r" / "turntable_multiturn.urdf").unlink()
    code, out = run("check", "--baseline", "base.jsonl", "r", "--format", "toy")
    assert code == 1
    assert out.splitlines() == [
        "toy check: same: r/arm7.urdf",
        "toy check: gone: r/turntable_multiturn.urdf",
    ]
