"""The public API is what the documentation shows: every path it names resolves.

Each ``cspace.x.y`` the README and the docs name in code resolves from ``import cspace``
alone, as a user writes it (submodules are imported on first use); every import line of
their Python examples runs; every name in ``cspace.__all__`` exists.
"""

from __future__ import annotations

import importlib
import inspect
import re
import subprocess
import sys

import pytest

import cspace

from conftest import REPO

DOCUMENTS = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]

_PATH = re.compile(r"`(cspace(?:\.[A-Za-z_][A-Za-z0-9_]*)+)")
_PRIVATE_PATH = re.compile(r"cspace(?:[./][A-Za-z]\w*)*[./]_[a-z]\w*")


def _documented_paths() -> list[str]:
    found = {m.group(1) for doc in DOCUMENTS for m in _PATH.finditer(doc.read_text())}
    return sorted(found)


def _import_lines() -> list[str]:
    lines = []
    for doc in DOCUMENTS:
        for block in re.findall(r"```python\n(.*?)```", doc.read_text(), re.DOTALL):
            lines += [
                line.strip()
                for line in block.splitlines()
                if re.match(r"\s*(import cspace|from cspace)", line)
            ]
    return sorted(set(lines))


def test_the_documents_name_paths() -> None:
    assert len(_documented_paths()) > 20 and _import_lines()


@pytest.mark.parametrize("path", _documented_paths())
def test_every_documented_path_resolves_after_import_cspace(path: str) -> None:
    # in a fresh interpreter: nothing imported before but `import cspace`
    parts = path.split(".")[1:]
    probe = "import cspace\nvalue = cspace\n" + "".join(
        f"value = getattr(value, {part!r})\n" for part in parts
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, cwd=REPO, timeout=120
    )
    assert done.returncode == 0, done.stderr.splitlines()[-1:]


@pytest.mark.parametrize("line", _import_lines())
def test_every_import_of_the_examples_runs(line: str) -> None:
    done = subprocess.run(
        [sys.executable, "-c", line], capture_output=True, text=True, cwd=REPO, timeout=120
    )
    assert done.returncode == 0, done.stderr.splitlines()[-1:]


def test_every_name_in_all_exists() -> None:
    missing = [name for name in cspace.__all__ if not hasattr(cspace, name)]
    assert missing == []


def test_no_page_speaks_of_issue_numbers_or_keeps_section_markers() -> None:
    # history belongs in the CHANGELOG; a user cannot follow "issue 14"
    for doc in DOCUMENTS:
        text = doc.read_text()
        assert not re.search(r"\bissues? \d+", text), doc
        assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text), doc  # no dated session log
        assert "<!-- section" not in text and "<!-- /section" not in text, doc


def test_the_readme_is_a_front_page() -> None:
    assert len((REPO / "README.md").read_text().splitlines()) <= 300


PUBLIC = {"cspace", *(f"cspace.{name}" for name in cspace.PUBLIC_MODULES)}
"""The public modules; the API page documents exactly these."""

USER_PAGES = [
    d
    for d in DOCUMENTS
    if d.name not in ("architecture.md", "development.md") and "notes" not in d.parts
]
"""The pages a user reads; the developers' pages may name private modules."""


def _modules() -> list[str]:
    found = []
    for path in sorted((REPO / "src" / "cspace").rglob("*.py")):
        parts = path.relative_to(REPO / "src").with_suffix("").parts
        found.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return found


def test_every_module_is_public_and_listed_or_private_by_name() -> None:
    # a module a user may import is on the list (and the API page); any other has a
    # name (or a package) beginning with _
    unlisted = [
        m
        for m in _modules()
        if m not in PUBLIC and not any(p.startswith("_") for p in m.split(".")[1:])
    ]
    assert unlisted == []
    assert len(_modules()) - len(PUBLIC) > 80  # the rest are private


def test_the_api_page_documents_public_paths_only_and_every_public_module() -> None:
    page = (REPO / "docs" / "api.md").read_text()
    documented = re.findall(r"^::: (\S+)", page, re.MULTILINE)
    private = [p for p in documented if any(part.startswith("_") for part in p.split("."))]
    assert private == []
    for module in PUBLIC - {"cspace"}:
        assert any(p == module or p.startswith(f"{module}.") for p in documented), module
    for name in cspace.__all__:
        value = getattr(cspace, name)
        if name == "__version__" or (isinstance(value, type) and issubclass(value, Exception)):
            continue  # the errors are documented with every error, under cspace.errors
        shown = {f"cspace.{name}", f"cspace.space.{name}", f"cspace.conventions.{name}"}
        assert shown & set(documented), name


def test_the_user_pages_name_no_private_module() -> None:
    for doc in USER_PAGES:
        private = _PRIVATE_PATH.findall(doc.read_text())
        assert private == [], doc.name


def test_errors_live_in_cspace_errors_with_the_root_errors_at_the_top_level() -> None:
    errors = {
        name: value
        for name, value in vars(cspace.errors).items()
        if isinstance(value, type) and issubclass(value, Exception) and not name.startswith("_")
    }
    assert set(errors) <= set(cspace.errors.__all__)
    assert all(issubclass(e, cspace.CspaceError) for e in errors.values())
    roots = {
        n for n, e in errors.items() if e is cspace.CspaceError or cspace.CspaceError in e.__bases__
    }
    at_top = {
        n
        for n in cspace.__all__
        if isinstance(getattr(cspace, n), type) and issubclass(getattr(cspace, n), Exception)
    }
    assert at_top == roots and {"RobotFileError", "ConfigurationError"} <= roots
    assert all(getattr(cspace, n) is errors[n] for n in roots)
    # every public module's errors are the ones of cspace.errors (notation's too)
    notation = importlib.import_module("cspace.notation")
    assert notation.NotationError is cspace.errors.NotationError


def test_only_the_root_errors_are_at_the_top_level() -> None:
    with pytest.raises(AttributeError, match="OutOfLimitsError"):
        cspace.OutOfLimitsError  # type: ignore[attr-defined]  # noqa: B018
    with pytest.raises(AttributeError):
        cspace.no_such_name  # type: ignore[attr-defined]  # noqa: B018
    with pytest.raises(AttributeError):
        cspace.space.rowwise  # type: ignore[attr-defined]  # noqa: B018


def test_the_public_modules_import_without_numpy() -> None:
    # Conventions and ConfigurationSpace are imported on first use, and with them NumPy;
    # the factors and the rotations are NumPy's arithmetic
    numeric = {"cspace.factors", "cspace.rotations"}
    probe = (
        "import sys\nimport cspace\n"
        + "".join(f"import {m}\n" for m in sorted(PUBLIC - numeric))
        + "assert 'numpy' not in sys.modules, 'numpy'\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr.splitlines()[-1:]


def _public_objects() -> dict[str, object]:
    found: dict[str, object] = {}
    for module_name in sorted(PUBLIC):
        module = importlib.import_module(module_name)
        found[module_name] = module
        for name in getattr(module, "__all__", ()):
            value = getattr(module, name)
            found[f"{module_name}.{name}"] = value
            if isinstance(value, type):
                for member, attribute in vars(value).items():
                    if not member.startswith("_") and getattr(attribute, "__doc__", None):
                        found[f"{module_name}.{name}.{member}"] = attribute
    return found


def test_the_public_docstrings_are_markdown_naming_no_private_module() -> None:
    # the API page renders them as Markdown: a Sphinx role would show as written, and a
    # private path would send a user into modules that may change in any release
    private = re.compile(r"cspace(?:\.\w+)*\._[a-z]\w*|cspace/_[a-z]")
    role = re.compile(r":(?:py:)?(?:func|class|mod|data|meth|attr|exc|obj):`")
    objects = _public_objects()
    assert len(objects) > 150
    wrong = [
        name
        for name, value in objects.items()
        if isinstance(value.__doc__, str)
        and (private.search(value.__doc__) or role.search(value.__doc__))
        and not (isinstance(value, type) and value.__doc__ == type.__doc__)
    ]
    assert wrong == []


def test_dir_offers_the_public_names_and_nothing_private() -> None:
    offered = set(dir(cspace))
    assert set(cspace.__all__) | set(cspace.PUBLIC_MODULES) <= offered
    assert not [n for n in offered if n.startswith("_") and not n.startswith("__")]


WAYS_IN = {
    "cspace.inspect": cspace.inspect,
    "cspace.inspect_source": cspace.inspect_source,
    "cspace.pinocchio_model": cspace.pinocchio_model,
    "cspace.space.load": cspace.space.load,
    "cspace.inspect_many": cspace.inspect_many,
}
"""Every function that loads robot files, each taking the loading options."""

NOT_TAKEN = {"cspace.pinocchio_model": {"group", "hold", "limits"}}
"""The options a way in does not take (a group's model is not one of its own; the
Pinocchio model keeps the robot file's limits, which a joint_limits.yaml does not change)."""


@pytest.mark.parametrize("name", sorted(WAYS_IN))
def test_every_way_in_takes_the_loading_options_with_the_records_defaults(name: str) -> None:
    # one record of the loading options (cspace._model.options): each function takes
    # every option, root_joint by position too and the others by keyword only, with the
    # record's default
    from cspace._model.options import LoadOptions

    record = LoadOptions._field_defaults
    parameters = inspect.signature(WAYS_IN[name]).parameters
    taken = {n: p.default for n, p in parameters.items() if n in record}
    assert taken == {n: d for n, d in record.items() if n not in NOT_TAKEN.get(name, ())}
    kinds = {n: parameters[n].kind for n in taken}
    assert kinds.pop("root_joint") is inspect.Parameter.POSITIONAL_OR_KEYWORD
    assert set(kinds.values()) == {inspect.Parameter.KEYWORD_ONLY}
    assert cspace.load is cspace.space.load


def test_the_command_lines_loading_options_default_to_the_records() -> None:
    from cspace._cli.main import build_parser
    from cspace._cli.robots import load_options
    from cspace._model.options import LoadOptions

    for command in ("inspect", "diff", "check"):
        args = build_parser().parse_args([command, "a.urdf", "b.urdf"])
        assert load_options(args) == LoadOptions(), command
    options = ["--root-joint", "planar", "--xacro", "--allow-dir", "d", "--srdf", "auto"]
    given = build_parser().parse_args(["inspect", *options, "--group", "g", "--hold", "h", "a"])
    assert load_options(given) == LoadOptions("planar", None, True, ("d",), True, "g", "h")
