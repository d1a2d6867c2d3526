"""The layers of src/cspace hold: imports go downhill, and no two modules import each other.

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


def test_no_import_cycles_at_module_level() -> None:
    graph = {
        module: {t for t in _imports(tree, top_level_only=True) if t in MODULES}
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
