"""A batch survives any one file: whatever goes wrong with a file is that file's error.

An exception that is not a CspaceError (a bug), raised while a file is inspected, while
``then`` runs on its report, or while its result is pickled back, is that file's
InternalError, naming it; every other file gets its report, in input order, on one core,
on the default pool and on a caller's executor. ``cspace inspect`` on several files
writes that file's error line and every other report, summary and exit code as usual.
"""

from __future__ import annotations

import functools
import json
import pickle
import threading
from concurrent.futures import Executor, ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest

import cspace
import cspace.errors

from conftest import ROBOTS, run_cli

FILES = [
    str(ROBOTS / "arm7.urdf"),
    str(ROBOTS / "gripper_mimic.urdf"),
    str(ROBOTS / "sdf_every_joint.sdf"),
    str(ROBOTS / "mjcf_every_joint.xml"),
    str(ROBOTS / "quadrotor_floating.urdf"),
]
BAD = Path(FILES[2]).name
"""The file ``then`` fails on."""


class _NeedsTwo(Exception):
    """Pickles (as its class and one argument) but cannot be unpickled (it needs two)."""

    def __init__(self, first: str, second: str) -> None:
        super().__init__(first)
        self.second = second


class _Halt(BaseException):
    """Not an Exception: only KeyboardInterrupt and SystemExit may stop a run."""


class _WontPickle:
    def __reduce__(self) -> Any:
        raise _Halt("no pickling")


def _notation(report: cspace.Report) -> str:
    return report.manifold.notation


def _then(how: str, report: cspace.Report) -> Any:
    """The report's notation, except for :data:`BAD`, where it goes wrong as ``how`` says."""
    if Path(report.source.path).name != BAD:
        return report.manifold.notation
    if how == "raises":
        raise ValueError(f"then refuses {BAD}")
    if how == "memory":
        raise MemoryError
    if how == "cspace-error":
        raise cspace.errors.ArgumentError("then's own mistake", argument="then")
    if how == "unpicklable":
        return threading.Lock()
    if how == "unloadable":
        return _NeedsTwo("one", "two")
    if how == "generator-exit":
        raise GeneratorExit("then's own")
    if how == "halts-pickling":
        return _WontPickle()
    raise KeyboardInterrupt  # "interrupt"


def _run(where: str, how: str, paths: list[str] = FILES, **kwargs: Any) -> list[cspace.Inspected]:
    then = functools.partial(_then, how)
    if where in ("jobs=1", "jobs=2"):
        return list(cspace.inspect_many(paths, jobs=int(where[-1]), then=then, **kwargs))
    pool: Executor
    pool = ProcessPoolExecutor(2) if where == "processes" else ThreadPoolExecutor(2)
    with pool:
        return list(cspace.inspect_many(paths, executor=pool, then=then, **kwargs))


def _check(results: list[cspace.Inspected], stage: str, kind: str, paths: list[str]) -> None:
    """Every file but BAD has its report and value, in order; BAD has an InternalError."""
    assert [r.path for r in results] == paths
    for path, result in zip(paths, results, strict=True):
        if Path(path).name != BAD:
            assert result.error is None and result.report is not None, result.error
            assert result.value == result.report.manifold.notation
            continue
        error = result.error
        assert result.report is None and result.value is None
        assert isinstance(error, cspace.InternalError), error
        assert (error.code, error.path, error.stage) == ("internal-error", path, stage)
        assert error.exception_type == kind
        assert str(error).startswith(f"{path}: internal error")
        assert f": {kind}" in str(error) and "\n" not in str(error)
        assert "Traceback (most recent call last)" in error.traceback
        copy = pickle.loads(pickle.dumps(error))
        assert (type(copy), vars(copy), str(copy)) == (type(error), vars(error), str(error))


WHERE = ["jobs=1", "jobs=2", "processes", "threads"]


@pytest.mark.parametrize("where", WHERE)
def test_then_raising_on_one_file_is_that_files_error(where: str) -> None:
    paths = FILES * 3  # several tasks, the failing file in each
    results = _run(where, "raises", paths, window=8)
    _check(results, "then", "ValueError", paths)
    error = results[2].error
    assert isinstance(error, cspace.InternalError)
    assert error.exception_message == f"then refuses {BAD}"
    assert str(error) == (
        f"{FILES[2]}: internal error in then: ValueError: then refuses {BAD} (a bug in the "
        "then function or in cspace; run with --debug for the traceback)"
    )
    assert "_then" in error.traceback  # formatted where it was raised


@pytest.mark.parametrize("where", ["jobs=1", "jobs=2"])
def test_memory_and_cspace_errors_in_then_are_that_files_error(where: str) -> None:
    # MemoryError is an Exception: one file that runs out of memory is that file's error.
    _check(_run(where, "memory", FILES), "then", "MemoryError", FILES)
    _check(_run(where, "cspace-error", FILES), "then", "cspace.errors.ArgumentError", FILES)


@pytest.mark.parametrize("where", ["jobs=2", "processes"])
@pytest.mark.parametrize(
    ("how", "kind"),
    [("unpicklable", "TypeError"), ("unloadable", "TypeError")],
)
def test_a_value_that_does_not_pickle_or_unpickle_is_that_files_error(
    where: str, how: str, kind: str
) -> None:
    # Pickled in the worker (a lock), or unpickled in the caller (an exception whose
    # class needs two arguments): either way only that file lacks its report.
    _check(_run(where, how, FILES), "return", kind, FILES)


@pytest.mark.parametrize("where", ["jobs=1", "threads"])
def test_nothing_is_pickled_in_this_process(where: str) -> None:
    results = _run(where, "unpicklable", FILES)
    assert all(r.error is None for r in results)
    assert isinstance(results[2].value, type(threading.Lock()))


@pytest.mark.parametrize("where", ["jobs=1", "jobs=2"])
def test_a_base_exception_other_than_a_stop_is_that_files_error(where: str) -> None:
    _check(_run(where, "generator-exit", FILES), "then", "GeneratorExit", FILES)
    if where == "jobs=2":  # pickled in the worker
        _check(_run(where, "halts-pickling", FILES), "return", f"{__name__}._Halt", FILES)


def test_keyboard_interrupt_still_stops_the_run() -> None:
    results = cspace.inspect_many(FILES, jobs=1, then=functools.partial(_then, "interrupt"))
    assert next(results).error is None
    assert next(results).error is None
    with pytest.raises(KeyboardInterrupt):
        next(results)


def test_a_then_that_cannot_reach_the_workers_is_refused_at_once() -> None:
    with pytest.raises(cspace.errors.ArgumentTypeError, match="then must pickle") as refused:
        cspace.inspect_many(FILES, jobs=2, then=lambda report: report.manifold.notation)
    assert refused.value.argument == "then"
    results = cspace.inspect_many(FILES, jobs=1, then=lambda report: report.manifold.notation)
    assert next(results).value == "R^6 × S^1"  # in this process nothing is pickled


def test_the_error_is_exported_and_one_line_whatever_the_exception_says() -> None:
    assert cspace.InternalError is cspace.errors.InternalError
    assert issubclass(cspace.InternalError, cspace.CspaceError)
    try:
        raise RecursionError("maximum recursion depth exceeded")
    except RecursionError as exc:
        error = cspace.InternalError.of("deep.xml", exc)
    assert str(error) == (
        "deep.xml: internal error: RecursionError: maximum recursion depth exceeded "
        "(a bug in cspace; run with --debug for the traceback)"
    )
    hostile = cspace.InternalError.of("a\x1b[31m.xml", ValueError("x\n\u202e" + "y" * 10**5))
    assert str(hostile).isprintable() and len(str(hostile)) < 1000
    assert "\\x1b" in str(hostile) and "\\u202e" in str(hostile)


# --- the command line -------------------------------------------------------------------


def _hostile(folder: Path) -> list[Path]:
    """Files that made cspace raise a bare exception when this test was written.

    A body chain 1,200 deep through five included files (``RecursionError`` in the MJCF
    pre-scan, which counts bodies recursively across includes), and a ``<replicate>``
    count of 5,000 digits (``ValueError``: Python converts at most 4,300 digits to an
    int). Once fixed they get an error of their own kind: the batch is checked all the
    same, the internal-error line whenever one still gives it.
    """
    deep = folder / "deep"
    deep.mkdir()
    for part in range(5):
        inner = f'<include file="d{part + 1}.xml"/>' if part < 4 else ""
        chain = "".join(
            f'<body name="b{part}_{i}"><joint name="j{part}_{i}"/><geom size=".1"/>'
            for i in range(240)
        )
        chain += inner + "</body>" * 240
        tag = "mujoco><worldbody" if part == 0 else "mujocoinclude"
        end = "worldbody></mujoco" if part == 0 else "mujocoinclude"
        (deep / f"d{part}.xml").write_text(f"<{tag}>{chain}</{end}>")
    count = folder / "count.xml"
    count.write_text(
        f'<mujoco><worldbody><replicate count="{"9" * 5000}" offset="0 0 1">'
        '<body name="b"><joint name="j"/><geom size=".1"/></body>'
        "</replicate></worldbody></mujoco>"
    )
    return [deep / "d0.xml", count]


def _error_line(stderr: str, name: str) -> str:
    """The one error line naming ``name``: the file's code, and the bug's own words."""
    lines = [line for line in stderr.splitlines() if name in line]
    assert len(lines) == 1, stderr
    line = lines[0]
    assert line.startswith(f"cspace: error: {name}") and line.endswith("]"), line
    if line.endswith("[internal-error]"):
        assert f"{name}: internal error: " in line, line
        assert line.endswith(
            "(a bug in cspace; run with --debug for the traceback) [internal-error]"
        )
    return line


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_the_command_line_keeps_every_other_report(tmp_path: Path, jobs: str) -> None:
    deep, count = (str(p.relative_to(tmp_path)) for p in _hostile(tmp_path))
    for path in FILES[:2]:
        (tmp_path / Path(path).name).write_bytes(Path(path).read_bytes())
    ok1, ok2 = (Path(p).name for p in FILES[:2])
    names = [ok1, deep, ok2, count, ok1]
    run = run_cli("inspect", *names, "--format", "jsonl", "-j", jobs, cwd=tmp_path)
    assert run.code == 2
    assert [json.loads(line)["source"]["path"] for line in run.stdout.splitlines()] == [
        ok1,
        ok2,
        ok1,
    ]
    assert run.stderr.count("\n") == 2
    _error_line(run.stderr, deep)
    _error_line(run.stderr, count)
    table = run_cli("inspect", *names, "-j", jobs, "--width", "200", cwd=tmp_path)
    assert table.code == 2 and table.stderr == run.stderr
    rows = table.stdout.splitlines()[2:7]
    assert [row.split()[0] for row in rows] == names
    assert [row.endswith("no report") for row in rows] == [False, True, False, True, False]
    assert "5 robot files: 3 ok, 0 failing, 2 without a report;" in table.stdout


def test_standard_input_and_debug(tmp_path: Path) -> None:
    _, count = _hostile(tmp_path)
    run = run_cli("inspect", FILES[0], "-", FILES[1], "--format", "jsonl", stdin=count.read_bytes())
    assert run.code == 2 and run.stdout.count("\n") == 2
    line = _error_line(run.stderr, "-")
    debug = run_cli("--debug", "inspect", FILES[0], str(count), FILES[1], "-j", "2")
    assert debug.code == 2 and debug.stdout.count(" ok\n") == 2
    if line.endswith("[internal-error]"):  # the traceback, as captured in the worker
        assert "Traceback (most recent call last)" in debug.stderr
        assert debug.stderr.rstrip().splitlines()[-1].startswith("ValueError: Exceeds")
