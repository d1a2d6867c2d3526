"""Every test with a time or memory bound carries the ``bounded`` marker.

``tests/load_check.sh`` runs the marked tests (``pytest -m bounded``) beside processes
that keep every core busy, to show that no bound fails on a busy machine. A test left
unmarked would escape that check, so this one reads the test modules' source (ast,
nothing imported or run) and finds every test that measures: one that uses the suite's
measuring helpers (``measured``, ``cpu_of``, ``assert_bounded_error``, ``SECONDS``,
``PEAK_MIB``, ``HANG_SECONDS``), a clock, a sleep or a process's resource usage, in its
own body or through a helper function of its module. Each must be marked, on itself,
its class or its module (``pytestmark``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from conftest import REPO

BOUND_NAMES = frozenset(
    {"measured", "cpu_of", "assert_bounded_error", "SECONDS", "PEAK_MIB", "HANG_SECONDS"}
)
"""The suite's measuring helpers and bounds (tests/conftest.py), however imported."""
BOUND_ATTRIBUTES = frozenset(
    {
        "monotonic",
        "perf_counter",
        "process_time",
        "sleep",
        "getrusage",
        "wait4",
        "ru_maxrss",
        "ru_utime",
        "cpu_seconds",
        "wall_seconds",
        "peak_mib",
    }
)
"""Clocks, sleeps, resource usage, and the bounds of cspace's confined children."""


def _marker_names(decorators: list[ast.expr]) -> set[str]:
    """The ``pytest.mark.NAME`` markers among decorators (or a ``pytestmark`` value)."""
    names = set()
    for decorator in decorators:
        for node in ast.walk(decorator):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Attribute)
                and node.value.attr == "mark"
            ):
                names.add(node.attr)
    return names


def _uses(node: ast.AST, bound_names: frozenset[str]) -> tuple[bool, set[str]]:
    """Whether ``node`` measures by itself, and the names it calls or reads.

    A bound's name (``bound_names``: those of `BOUND_NAMES` and the module's aliases of
    them) counts where it is read, unless the function binds it itself (a variable).
    """
    measures, names = False, set()
    stored = {
        child.id
        for child in ast.walk(node)
        if isinstance(child, ast.Name) and not isinstance(child.ctx, ast.Load)
    }
    for child in ast.walk(node):
        if isinstance(child, ast.Name):
            names.add(child.id)
            measures |= child.id in bound_names and child.id not in stored
        elif isinstance(child, ast.Attribute):
            measures |= child.attr in BOUND_ATTRIBUTES or child.attr in BOUND_NAMES
            measures |= ast.unparse(child) == "time.time"
        elif isinstance(child, ast.keyword):
            measures |= child.arg in BOUND_ATTRIBUTES
        elif isinstance(child, ast.alias):
            measures |= child.name in BOUND_NAMES or child.name in BOUND_ATTRIBUTES
    return measures, names


def unmarked_bounded_tests(source: str) -> tuple[list[str], list[str]]:
    """The tests of a module that measure, and those of them without the marker.

    Args:
        source: A test module's text.

    Returns:
        The names of the tests that measure (``Class.test`` in a class), and of those
        not marked ``bounded``.
    """
    tree = ast.parse(source)
    bound_names = BOUND_NAMES | {
        alias.asname
        for node in tree.body
        if isinstance(node, ast.ImportFrom)
        for alias in node.names
        if alias.name in BOUND_NAMES and alias.asname
    }
    module_marks: set[str] = set()
    helpers: dict[str, ast.AST] = {}
    tests: list[tuple[str, ast.FunctionDef | ast.AsyncFunctionDef, set[str]]] = []
    for node in tree.body:
        if isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            if any(isinstance(t, ast.Name) and t.id == "pytestmark" for t in targets):
                module_marks |= _marker_names([node.value] if node.value else [])
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            if node.name.startswith("test"):
                tests.append((node.name, node, set()))
            else:
                helpers[node.name] = node
        elif isinstance(node, ast.ClassDef):
            class_marks = _marker_names(node.decorator_list)
            tests += [
                (f"{node.name}.{item.name}", item, class_marks)
                for item in node.body
                if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef)
                and item.name.startswith("test")
            ]
    # which helpers measure, themselves or through the helpers they name
    measuring, calls = {}, {}
    for name, node in helpers.items():
        measuring[name], names = _uses(node, bound_names)
        calls[name] = names & helpers.keys()
    while grown := [n for n in helpers if not measuring[n] and any(map(measuring.get, calls[n]))]:
        measuring.update(dict.fromkeys(grown, True))
    found, unmarked = [], []
    for name, node, class_marks in tests:
        direct, names = _uses(node, bound_names)
        if direct or any(measuring[called] for called in names & helpers.keys()):
            found.append(name)
            marks = module_marks | class_marks | _marker_names(node.decorator_list)
            if "bounded" not in marks:
                unmarked.append(name)
    return found, unmarked


def test_the_check_finds_a_measuring_test_left_unmarked() -> None:
    source = (
        "import time, pytest\n"
        "from conftest import cpu_of as timed, measured\n"
        "def _deep(x):\n    return _deeper(x)\n"
        "def _deeper(x):\n    return time.process_time()\n"
        "def _plain(x):\n    return x\n"
        "def test_direct(tmp_path):\n    assert measured('inspect', cwd=tmp_path)\n"
        "def test_aliased(tmp_path):\n    assert timed('inspect', cwd=tmp_path)\n"
        "def test_through_helpers():\n    assert _deep(1)\n"
        "def test_wall_clock():\n    assert time.time()\n"
        "def test_child_limits(m):\n    m.setattr(X, 'limits', L._replace(wall_seconds=1))\n"
        "@pytest.mark.bounded\ndef test_marked():\n    time.sleep(1)\n"
        "def test_plain():\n    assert _plain(1)\n"
        "def test_a_variable_so_named():\n    measured = _plain(1)\n    assert measured\n"
        "class TestGroup:\n    def test_in_class(self):\n        time.monotonic()\n"
    )
    found, unmarked = unmarked_bounded_tests(source)
    expected = [
        "test_direct",
        "test_aliased",
        "test_through_helpers",
        "test_wall_clock",
        "test_child_limits",
        "test_marked",
        "TestGroup.test_in_class",
    ]
    assert found == expected
    assert unmarked == [name for name in expected if name != "test_marked"]
    marked_module = "import pytest\npytestmark = [pytest.mark.bounded]\n" + source
    assert unmarked_bounded_tests(marked_module) == (expected, [])
    marked_class = source.replace("class TestGroup", "@pytest.mark.bounded\nclass TestGroup")
    assert unmarked_bounded_tests(marked_class)[1][-1] == "test_child_limits"


def test_every_test_with_a_time_or_memory_bound_is_marked(pytestconfig: pytest.Config) -> None:
    assert any(line.startswith("bounded:") for line in pytestconfig.getini("markers"))
    found, unmarked = {}, {}
    for path in sorted((REPO / "tests").glob("test_*.py")):
        name = Path(path).name
        found[name], unmarked[name] = unmarked_bounded_tests(path.read_text())
    assert {name: tests for name, tests in unmarked.items() if tests} == {}
    # the check sees the suite's measured tests (a check that found none would pass)
    assert "test_tens_of_thousands_of_joints" in found["test_hostile.py"]
    assert "test_finding_the_root_takes_one_pass" in found["test_discover.py"]
    assert sum(map(len, found.values())) > 50
