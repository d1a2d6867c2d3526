"""The layers of src/cspace hold: imports go downhill, and neither a module nor a package
depends on itself through others (counting imports in functions and for types).

The pipeline is _formats/ -> _model/ -> _reports/ -> _render/, with space/ built from a
report and _confine/ running child processes for _formats/; errors, _findings, _manifold,
notation, _safetext, _sizes, _joint_kind, _joint_report, _joint_table, _slots,
_drake_order and _tools at the top are shared by all (see docs/architecture.md). Read
from the source (ast), so no module is imported.
"""

from __future__ import annotations

import ast
from functools import cache
from itertools import pairwise
from pathlib import Path

import pytest

from conftest import REPO

SRC = REPO / "src" / "cspace"
LAYERS = ("_formats", "_confine", "_model", "_reports", "_render", "space")

FORBIDDEN = {
    "_formats": ("cspace._model", "cspace._reports", "cspace._render", "cspace.space", "pinocchio"),
    "_confine": (
        "cspace._formats",
        "cspace._model",
        "cspace._reports",
        "cspace._render",
        "cspace.space",
    ),
    "_model": ("cspace._render", "cspace.space", "cspace.conventions"),
    "_reports": (
        "cspace._model",
        "cspace._render",
        "cspace._formats",
        "cspace.space",
        "cspace.conventions",
    ),
    "_render": ("cspace._model", "cspace.space", "cspace._formats", "cspace.conventions"),
    "space": ("cspace._render", "cspace._cli", "cspace.conventions"),
}
"""What each layer must not import (anywhere in the module, lazily too)."""

SHARED = ("cspace._formats.table", "cspace._record")
"""Modules every layer may read, which import nothing of cspace but one another: the
format table and the base of records."""

KNOWN: set[tuple[str, str]] = set()
"""Edges allowed for now, each a debt to pay (none)."""


def _module(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _absolute(module: str, node: ast.ImportFrom) -> str:
    """The module a ``from ... import`` names, relative ones resolved (``from .. import x``
    in ``cspace._cli.commands.inspect`` is ``cspace._cli``)."""
    if not node.level:
        return node.module or ""
    package = module.split(".") if module in PACKAGES else module.split(".")[:-1]
    base = package[: len(package) - (node.level - 1)]
    return ".".join([*base, node.module] if node.module else base)


def _imports(tree: ast.AST, top_level_only: bool, module: str = "") -> set[str]:
    found: set[str] = set()
    nodes = ast.iter_child_nodes(tree) if top_level_only else ast.walk(tree)
    for node in nodes:
        if isinstance(node, ast.ImportFrom):
            target = _absolute(module, node)
            found.add(target)
            found.update(f"{target}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return found


PACKAGES = {_module(p) for p in SRC.rglob("__init__.py")}


@cache
def _modules() -> dict[str, ast.Module]:
    """Each module of cspace and its syntax tree (parsed when a test first asks: both
    pytest workers import this file, one runs it)."""
    return {_module(p): ast.parse(p.read_text()) for p in sorted(SRC.rglob("*.py"))}


def test_every_layer_exists_and_holds_modules() -> None:
    for layer in LAYERS:
        assert sum(m.startswith(f"cspace.{layer}.") for m in _modules()) >= 2, layer


@pytest.mark.parametrize("layer", sorted(FORBIDDEN))
def test_imports_go_downhill(layer: str) -> None:
    wrong = []
    for module, tree in _modules().items():
        if not module.startswith(f"cspace.{layer}"):
            continue
        for target in sorted(_imports(tree, top_level_only=False, module=module)):
            banned = any(target == f or target.startswith(f"{f}.") for f in FORBIDDEN[layer])
            shared = any(target == s or target.startswith(f"{s}.") for s in SHARED)
            if banned and not shared and (module, target) not in KNOWN:
                wrong.append(f"{module} imports {target}")
    assert wrong == []


def test_shared_modules_import_nothing_of_cspace_at_run_time() -> None:
    for module in SHARED:
        imported = _imports(_modules()[module], top_level_only=True, module=module)
        ours = {i for i in imported if i.startswith("cspace")}
        assert not {i for i in ours if not any(i == s or i.startswith(f"{s}.") for s in SHARED)}, (
            module
        )


def _edges(module: str, tree: ast.AST) -> set[str]:
    """The modules of cspace a module imports anywhere: at module level, in a function,
    under ``TYPE_CHECKING``, relative imports resolved.

    ``from P import m`` of a submodule m is an edge to ``P.m``, and to ``P`` too when the
    importer is outside P (importing runs P's ``__init__`` first); a package's own
    modules do not depend on its ``__init__``.
    """
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            target = _absolute(module, node)
            outside = not module.startswith(f"{target}.")
            for alias in node.names:
                submodule = f"{target}.{alias.name}"
                if submodule in _modules():
                    found.add(submodule)
                    if outside:
                        found.add(target)
                else:
                    found.add(target)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return found


@cache
def _graph() -> dict[str, set[str]]:
    """Each module of cspace and the modules of cspace it imports (see `_edges`)."""
    modules = _modules()
    return {
        module: {t for t in _edges(module, tree) if t in modules and t != module}
        for module, tree in modules.items()
    }


def _cycle(graph: dict[str, set[str]]) -> list[str]:
    """A cycle of ``graph`` (its nodes in order, the first again at the end), or []."""
    state: dict[str, int] = {}  # 1: on the path being walked, 2: done, no cycle through it
    path: list[str] = []

    def visit(node: str) -> list[str]:
        state[node] = 1
        path.append(node)
        for target in sorted(graph.get(node, ())):
            if state.get(target) == 1:
                return [*path[path.index(target) :], target]
            found = [] if target in state else visit(target)
            if found:
                return found
        state[node] = 2
        path.pop()
        return []

    for node in sorted(graph):
        found = [] if node in state else visit(node)
        if found:
            return found
    return []


def test_no_import_cycles_anywhere() -> None:
    """No two modules depend on each other, however late or only for types they import:
    a report's joint is a module of its own (`_joint_report`), the sampling plan too."""
    assert _cycle(_graph()) == []


def _package(module: str) -> str:
    """What a module counts as between packages: ``cspace`` itself, a module at the top of
    the package (``cspace._slots``), or a sub-package with all it holds (``cspace.space``)."""
    return ".".join(module.split(".")[:2])


def test_no_import_cycles_between_packages() -> None:
    """Nor do two packages (`_package`) depend on each other, through any import of any of
    their modules: the reports read the joint record, Drake's order and the registry at
    the top (`_joint_report`, `_drake_order`, `_tools`), the conventions' maps are part of
    the space (`space._conventions`), and `cspace.conventions` names them from above."""
    graph: dict[str, set[str]] = {}
    why: dict[tuple[str, str], str] = {}
    for module, targets in sorted(_graph().items()):
        for target in sorted(targets):
            edge = _package(module), _package(target)
            if edge[0] != edge[1]:
                graph.setdefault(edge[0], set()).add(edge[1])
                why.setdefault(edge, f"{module} imports {target}")
    cycle = _cycle(graph)
    assert cycle == [], "; ".join(f"{a} -> {b} ({why[a, b]})" for a, b in pairwise(cycle))


def test_the_shared_modules_at_the_top_import_no_layer() -> None:
    """The private modules at the top of the package (`_joint_table`, `_slots`, ...) are
    below every layer: they import none (but the format table, `SHARED`)."""
    layers = tuple(f"cspace.{name}" for name in (*LAYERS, "_cli", "conventions"))
    wrong = [
        f"{module} imports {target}"
        for module in sorted(_modules())
        if module.count(".") == 1
        and module.split(".")[1].startswith("_")
        and module not in PACKAGES | {"cspace.__main__"}
        for target in sorted(_graph()[module])
        if _package(target) in layers and target not in SHARED
    ]
    assert wrong == []


def test_readers_import_neither_pinocchio_nor_numpy_at_module_level() -> None:
    for module, tree in _modules().items():
        if module.startswith("cspace._formats.") and not module.endswith(
            ("mjcf._compile", "mjcf._worker")  # the child's side: MuJoCo, in its own process
        ):
            imported = _imports(tree, top_level_only=True, module=module)
            assert not {"pinocchio", "numpy"} & imported, module


def test_each_command_module_gives_its_parser_the_line_of_the_table() -> None:
    """`cspace --help` lists the commands from `commands.COMMANDS` without importing
    them: each module's own parser carries the same line (it calls `commands.add`)."""
    from cspace._cli.commands import COMMANDS

    for name in COMMANDS:
        tree = _modules()[f"cspace._cli.commands.{name}"]
        calls = [
            node
            for node in ast.walk(tree)
            if isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id == "add"
            and len(node.args) >= 2
            and isinstance(node.args[1], ast.Constant)
        ]
        assert [c.args[1].value for c in calls] == [name], name  # type: ignore[attr-defined]
    modules = {m.rsplit(".", 1)[1] for m in _modules() if m.startswith("cspace._cli.commands.")}
    assert {m for m in modules if not m.startswith("_")} == set(COMMANDS)


# --- private names -----------------------------------------------------------------

NAMED_TUPLE_API = frozenset({"_asdict", "_field_defaults", "_fields", "_make", "_replace"})
"""A named tuple's public methods, spelt with ``_`` so that they cannot clash with fields."""

PRIVATE_READS_ALLOWED = frozenset(
    {
        # cspace.errors re-exports the function pickled errors name, so that a pickle
        # names the public module only (tests/test_errors.py)
        "cspace.errors: from cspace.errors._base import _restore",
    }
)
"""Reads of another module's private name that are allowed for now, as `_private_reads`
writes them."""


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _defined(tree: ast.AST) -> set[str]:
    """The private names a module defines: its functions and classes (methods and nested
    ones too), every name it assigns (at module level, in a class: fields, in a function)
    and every attribute it assigns (``obj._x = ...``). A name it imports is not its own."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Name | ast.Attribute) and not isinstance(node.ctx, ast.Load):
            names.add(node.id if isinstance(node, ast.Name) else node.attr)
    return {name for name in names if _private(name)}


def _own(receiver: ast.expr) -> bool:
    """``self``, ``cls`` or ``super()``: the object whose class the reading code is in."""
    if isinstance(receiver, ast.Name):
        return receiver.id in ("self", "cls")
    return (
        isinstance(receiver, ast.Call)
        and isinstance(receiver.func, ast.Name)
        and receiver.func.id == "super"
    )


def _private_reads(modules: dict[str, ast.AST]) -> dict[str, int]:
    """Where a module reads another module's private name, as ``"module: code"`` with its
    line.

    ``x._name`` is such a read when ``x`` is not ``self``, ``cls`` or ``super()``,
    ``_name`` is neither a dunder nor a named tuple's method, and the module does not
    define ``_name`` itself (`_defined`) while another of ``modules`` does (a private
    name of a library, ``etree._Element``, is not cspace's to hold). ``from M import
    _name`` of a name of another module (not a submodule ``M._name``) is one too. Names
    are compared, not objects: a module that defines ``_name`` may read ``x._name`` of
    any ``x``.
    """
    defined = {module: _defined(tree) for module, tree in modules.items()}
    anywhere = set().union(*defined.values())
    found: dict[str, int] = {}
    for module, tree in modules.items():
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load):
                name = node.attr
                if (
                    _private(name)
                    and name not in NAMED_TUPLE_API
                    and name not in defined[module]
                    and name in anywhere
                    and not _own(node.value)
                ):
                    found.setdefault(f"{module}: {ast.unparse(node)}", node.lineno)
            elif isinstance(node, ast.ImportFrom):
                target = _absolute(module, node)
                for alias in node.names:
                    if (
                        _private(alias.name)
                        and target in modules
                        and target != module
                        and f"{target}.{alias.name}" not in modules
                    ):
                        found.setdefault(
                            f"{module}: from {target} import {alias.name}", node.lineno
                        )
    return found


def test_no_module_reads_another_modules_private_names() -> None:
    """A module reads what another module keeps private neither through an object
    (``space._columns``) nor by importing it: the space's helpers take its data
    (`space._data.SpaceData`), not the space's private attributes."""
    found = _private_reads(_modules())
    wrong = [f"{code} (line {line})" for code, line in found.items()]
    assert sorted(w for w in wrong if w.rsplit(" (line", 1)[0] not in PRIVATE_READS_ALLOWED) == []
    assert sorted(PRIVATE_READS_ALLOWED - set(found)) == [], "paid: remove from the list"


def test_the_private_names_rule_finds_reads_through_objects_and_imports() -> None:
    """`_private_reads` on two toy modules: what it must find, and what it must not."""
    toy = {
        "toy.a": ast.parse("_hidden = 1\nclass A:\n    def __init__(self):\n        self._x = 1\n"),
        "toy.b": ast.parse(
            "from toy.a import A, _hidden\n"
            "import toy.a\n"
            "def f(a, p):\n"
            "    return a._x, toy.a._hidden, p._replace(x=1), p.__dict__, p._library_own\n"
            "class B(A):\n"
            "    def g(self):\n"
            "        self._y = 2\n"
            "        return self._x, super()._x, type(self)._y, B._y\n"
        ),
    }
    assert set(_private_reads(toy)) == {
        "toy.b: from toy.a import _hidden",
        "toy.b: a._x",
        "toy.b: toy.a._hidden",
    }
