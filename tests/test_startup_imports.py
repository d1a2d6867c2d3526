"""Start-up pays only for what the file needs: what `cspace inspect` of a URDF imports.

A URDF's inspect imports nothing of the other formats, of the conventions, of the other
commands or renderers, nor their libraries (MuJoCo, OpenUSD, Jinja2, numba, jsonschema,
xacro's), nor what would only cost time (shutil and its compression modules). The list
of cspace's modules it imports is written out: a module that appears in it is a cost
every URDF pays, and this test fails until it is either made lazy or added here.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys

from conftest import ROBOTS

URDF_INSPECT = frozenset(
    {
        "cspace",
        "cspace._cli",
        "cspace._cli.commands",
        "cspace._cli.commands.inspect",
        "cspace._cli.exit_codes",
        "cspace._cli.found",
        "cspace._cli.main",
        "cspace._cli.output",
        "cspace._cli.patterns",
        "cspace._cli.progress",
        "cspace._cli.robots",
        "cspace._factor_kinds",
        "cspace._findings",
        "cspace._formats",
        "cspace._formats.detect",
        "cspace._formats.shared",
        "cspace._formats.shared.description",
        "cspace._formats.shared.erd",
        "cspace._formats.shared.kinematic_tree",
        "cspace._formats.shared.pose",
        "cspace._formats.shared.reading",
        "cspace._formats.shared.robot_size",
        "cspace._formats.shared.roots",
        "cspace._formats.shared.structure",
        "cspace._formats.shared.xmlio",
        "cspace._formats.srdf",
        "cspace._formats.srdf.kind",  # any <robot> may be an SRDF, refused in one line
        "cspace._formats.table",
        "cspace._formats.urdf",
        "cspace._formats.urdf._drake",
        "cspace._formats.urdf._elements",
        "cspace._formats.urdf._recipe",
        "cspace._formats.urdf._world",
        "cspace._formats.urdf.numbers",
        "cspace._formats.urdf.reader",
        "cspace._joint_kind",
        "cspace._joint_report",
        "cspace._joint_table",
        "cspace._manifold",
        "cspace._model",
        "cspace._model._assemble",
        "cspace._model._records",
        "cspace._model._root_advice",
        "cspace._model._root_chains",
        "cspace._model._root_place",
        "cspace._model.adapter",
        "cspace._model.analysis",
        "cspace._model.diagnostics",
        "cspace._model.loader",
        "cspace._model.native",
        "cspace._model.options",
        "cspace._paths",
        "cspace._record",
        "cspace._render",
        "cspace._render._columns",
        "cspace._render.formats",
        "cspace._render.text",
        "cspace._reports",
        "cspace._reports.matching",
        "cspace._reports.poses",
        "cspace._reports.report",
        "cspace._safetext",
        "cspace._sizes",
        "cspace._slots",
        "cspace._version",
        "cspace.errors",
        "cspace.errors._base",
        "cspace.errors._configurations",
        "cspace.errors._files",
        "cspace.errors._internal",
        "cspace.files",
        "cspace.space",
    }
)
"""Every module of cspace that ``cspace inspect robots/arm7.urdf`` imports."""

NOT_FOR_A_URDF = (
    "mujoco",
    "pxr",
    "jinja2",
    "numba",
    "jsonschema",
    "xacrodoc",
    "yaml",
    "pydrake",
    "ompl",
    "shutil",
    "bz2",
    "lzma",
    "csv",
    "difflib",
    "traceback",
    "threading",  # the build thread comes from _thread
    "hashlib",  # OpenSSL's loading, for one SHA-256 (Python's own module gives it)
)
"""Libraries, and costly standard modules, that a URDF's inspect has no use for."""

_SCRIPT = """
import contextlib, io, json, sys
from cspace._cli.main import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    code = main(["inspect", sys.argv[1]])
print(json.dumps({"code": code, "text": out.getvalue(), "modules": sorted(sys.modules)}))
"""


def _imported(*args: str) -> dict[str, object]:
    done = subprocess.run(
        [sys.executable, "-c", _SCRIPT, *args], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    result: dict[str, object] = json.loads(done.stdout)
    return result


def test_a_urdf_inspect_imports_only_what_a_urdf_needs() -> None:
    run = _imported(str(ROBOTS / "arm7.urdf"))
    assert run["code"] == 0 and "R^" in str(run["text"])  # the report was made
    modules = set(run["modules"])  # type: ignore[call-overload]
    ours = {m for m in modules if m == "cspace" or m.startswith("cspace.")}
    assert sorted(ours - URDF_INSPECT) == []  # new at start-up: make it lazy, or list it
    assert sorted(URDF_INSPECT - ours) == []  # no longer imported: take it off the list
    own_sha256 = any(importlib.util.find_spec(m) for m in ("_sha256", "_sha2"))
    not_needed = set(NOT_FOR_A_URDF) - (set() if own_sha256 else {"hashlib"})
    assert sorted(m for m in modules if m.split(".")[0] in not_needed) == []


_FREEZE = """
import contextlib, gc, io, sys
from cspace._cli.main import main
with contextlib.redirect_stdout(io.StringIO()):
    main(["inspect", sys.argv[1]])
called = gc.get_freeze_count()
sys.argv = ["cspace", "inspect", sys.argv[1]]
with contextlib.redirect_stdout(io.StringIO()):
    main()
print(called, gc.get_freeze_count())
"""


def test_the_program_freezes_what_it_imported_and_a_caller_keeps_its_collector() -> None:
    # Run as the program, the command leaves what is imported by then out of every
    # collection (2.5 % of a URDF inspect); called with arguments, it freezes nothing.
    done = subprocess.run(
        [sys.executable, "-c", _FREEZE, str(ROBOTS / "arm7.urdf")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    called, program = map(int, done.stdout.split())
    assert called == 0 and program > 10_000
