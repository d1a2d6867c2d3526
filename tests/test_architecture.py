"""The layers of src/cspace hold: imports go downhill, and no module depends on itself
through others (counting imports in functions and for types).

The pipeline is _formats/ -> _model/ -> _reports/ -> _render/, with space/ built from a
report and _confine/ running child processes for _formats/; errors, _findings, _manifold,
notation, _safetext, _sizes and _joint_kind at the top are shared by all (see
docs/architecture.md). Read from the source (ast), so no module is imported.
"""

from __future__ import annotations

import ast
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
    "_model": ("cspace._render", "cspace.space"),
    "_reports": ("cspace._model", "cspace._render", "cspace._formats"),
    "_render": ("cspace._model", "cspace.space", "cspace._formats"),
}
"""What each layer must not import (anywhere in the module, lazily too)."""

KNOWN: set[tuple[str, str]] = set()
"""Edges allowed for now, each a debt to pay (none)."""


def _module(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(tree: ast.AST, top_level_only: bool) -> set[str]:
    found: set[str] = set()
    nodes = ast.iter_child_nodes(tree) if top_level_only else ast.walk(tree)
    for node in nodes:
        if isinstance(node, ast.ImportFrom) and node.module:
            found.add(node.module)
            found.update(f"{node.module}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return found


MODULES = {_module(p): ast.parse(p.read_text()) for p in sorted(SRC.rglob("*.py"))}


def test_every_layer_exists_and_holds_modules() -> None:
    for layer in LAYERS:
        assert sum(m.startswith(f"cspace.{layer}.") for m in MODULES) >= 2, layer


@pytest.mark.parametrize("layer", sorted(FORBIDDEN))
def test_imports_go_downhill(layer: str) -> None:
    wrong = []
    for module, tree in MODULES.items():
        if not module.startswith(f"cspace.{layer}"):
            continue
        for target in sorted(_imports(tree, top_level_only=False)):
            banned = any(target == f or target.startswith(f"{f}.") for f in FORBIDDEN[layer])
            if banned and (module, target) not in KNOWN:
                wrong.append(f"{module} imports {target}")
    assert wrong == []


def _edges(tree: ast.AST) -> set[str]:
    """The modules of cspace a module imports anywhere: at module level, in a function,
    under ``TYPE_CHECKING``. ``from P import m`` of a submodule m is an edge to ``P.m``
    (a package's own ``__init__`` is not what its submodules depend on)."""
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            for alias in node.names:
                submodule = f"{node.module}.{alias.name}"
                found.add(submodule if submodule in MODULES else node.module)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return found


def test_no_import_cycles_anywhere() -> None:
    """No two modules depend on each other, however late or only for types they import:
    the space's helpers read it through a protocol (`space._shape`), a report's joint is a
    module of its own (`_reports._joint`), the sampling plan too."""
    graph = {
        module: {t for t in _edges(tree) if t in MODULES and t != module}
        for module, tree in MODULES.items()
    }
    state: dict[str, int] = {}

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        for target in sorted(graph[module]):
            if state.get(target) == 1:
                raise AssertionError(" -> ".join([*path, module, target]))
            if target not in state:
                visit(target, [*path, module])
        state[module] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module, [])


def test_readers_import_neither_pinocchio_nor_numpy_at_module_level() -> None:
    for module, tree in MODULES.items():
        if module.startswith("cspace._formats.") and not module.endswith(
            ("mjcf_compile", "mjcf_worker")  # the child's side: MuJoCo, in its own process
        ):
            assert not {"pinocchio", "numpy"} & _imports(tree, top_level_only=True), module
