"""Many robot files at once, on any ``concurrent.futures.Executor``, in input order.

`inspect_many` runs `cspace.inspect` on each file and yields one
`Inspected` per file, in the order the files were given, as soon as it and every
file before it are done. The work goes to an executor: by default a process pool with
one worker per core (Pinocchio's parser holds the GIL, so threads would not help),
forked from the caller when it runs one thread, else from a forkserver (a script then
needs the usual ``if __name__ == "__main__":`` guard); or
the caller's own, such as a Dask cluster's ``Client.get_executor()`` or Ray's, with no
other change. At most ``window`` files are in flight, so memory stays bounded for any
number of files, and a generator of paths is read only as far as needed.

Each file's report or error crosses the process boundary pickled: reports and every
`CspaceError` pickle (see ``CspaceError.__reduce__``).

A batch survives any one file. Whatever goes wrong with a file is that file's error, and
the other files go on: a `CspaceError` as raised; any other
exception (a bug, ``MemoryError`` and ``RecursionError`` too) raised while the file is
inspected, while ``then`` runs on its report, or while its result is pickled in the
worker or unpickled here, as an `InternalError` that names the
file; a worker that dies, as a `WorkerDiedError`. Only
``KeyboardInterrupt`` and ``SystemExit`` (no ``Exception`` subclasses) stop the run.
"""

from __future__ import annotations

import dataclasses
import os
import pickle
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from itertools import islice
from typing import TYPE_CHECKING, Any

from cspace._formats.shared.xmlio import path_text
from cspace._model._pool import Pool
from cspace._model.options import LoadOptions
from cspace.errors import (
    ArgumentError,
    ArgumentTypeError,
    CspaceError,
    InternalError,
    WorkerDiedError,
)

if TYPE_CHECKING:
    from concurrent.futures import Executor, Future

    from cspace._formats.xacro.expand import XacroOptions
    from cspace._reports.report import Report

PER_TASK = 4
"""Files per task sent to a worker (a file takes about a millisecond; a task's round trip
a tenth of one)."""


@dataclass(frozen=True)
class Inspected:
    """What became of one file: its report, or the error that stopped it.

    Attributes:
        path: The file as given (``erd:NAME`` too).
        report: The report, or None when the file has none.
        error: Why there is no report, or None: a `CspaceError`,
            an `InternalError` for a bug (then's too).
        value: What ``then`` made of the report in the worker (see
            `inspect_many`), or None.
    """

    path: str
    report: Report | None
    error: CspaceError | None
    value: Any = None


def default_jobs() -> int:
    """The cores this process may run on (its CPU affinity), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


@dataclass(frozen=True)
class _Options:
    """How every file is loaded, and what is done with its report; pickled into each task.

    ``load`` is the loading options. ``pickled``: each file's result is pickled in the
    worker (see `_inspect_files`), as for any executor but one of threads, where nothing
    is pickled.
    """

    load: LoadOptions
    then: Callable[[Report], Any] | None = None
    pickled: bool = True
    usd_scope: tuple[str, ...] = ()  # the folders one OpenUSD child may serve (`usd.child`)


_STOPS = (KeyboardInterrupt, SystemExit)
"""What stops a whole run; every other exception is one file's error."""


def _inspect_one(path: str, options: _Options) -> Inspected:
    """`cspace.inspect` of one file, and ``then`` of its report; any error caught.

    A `CspaceError` of the inspection is the file's error; any
    other exception (a bug in cspace, or in ``then``; ``MemoryError`` and
    ``RecursionError`` too) is the file's `InternalError`.
    Only ``KeyboardInterrupt`` and ``SystemExit`` go through (`_STOPS`); any other
    ``BaseException`` (a ``GeneratorExit`` raised by ``then``) is the file's error.
    """
    from cspace._model.loader import inspect_with

    try:
        report = inspect_with(path, options.load)
    except CspaceError as exc:
        return Inspected(path, None, exc)
    except _STOPS:
        raise
    except BaseException as exc:  # a bug: this file's error, not the end of the batch
        return Inspected(path, None, InternalError.of(path, exc))
    if options.then is None:
        return Inspected(path, report, None)
    try:
        value = options.then(report)
    except _STOPS:
        raise
    except BaseException as exc:  # a CspaceError too: then's, not the file's
        return Inspected(path, None, InternalError.of(path, exc, stage="then"))
    return Inspected(path, report, None, value)


_Sent = Inspected | bytes
"""A file's result as a task returns it: pickled in the worker, or as it is."""


def _inspect_files(paths: list[str], options: _Options) -> list[_Sent]:
    """The task each worker runs: a few files (sparing the per-task cost), one by one.

    Each file's result is pickled here (unless ``options.pickled`` is false): one that
    does not pickle (``then``'s value, or a bug) is then that file's error alone, not
    the whole task's when the executor pickles the task's result.
    """
    if options.usd_scope:
        from cspace._formats.usd.child import within

        within(options.usd_scope)
    if not options.pickled:
        return [_inspect_one(path, options) for path in paths]
    return [_pickled(_inspect_one(path, options)) for path in paths]


def _pickled(done: Inspected) -> bytes:
    """``done`` pickled, or an `InternalError` when it does not pickle."""
    try:
        return pickle.dumps(done, pickle.HIGHEST_PROTOCOL)
    except _STOPS:
        raise
    except BaseException as exc:  # RecursionError and MemoryError too
        failed = InternalError.of(done.path, exc, stage="return")
        return pickle.dumps(Inspected(done.path, None, failed), pickle.HIGHEST_PROTOCOL)


def _received(path: str, sent: _Sent) -> Inspected:
    """A file's result as a task sent it, unpickled (an error of its own if that fails)."""
    if not isinstance(sent, bytes):
        return sent
    try:
        done: Inspected = pickle.loads(sent)
    except _STOPS:
        raise
    except BaseException as exc:  # e.g. then's value is of a class the caller cannot import
        return Inspected(path, None, InternalError.of(path, exc, stage="return"))
    return done


def _died(path: str) -> _Sent:
    """The result of a file whose worker died even when it ran alone."""
    message = (
        "the worker process inspecting this file died (it crashed or was killed, perhaps "
        "for memory); no report"
    )
    return Inspected(path, None, WorkerDiedError(path, message))


def inspect_many(
    paths: Iterable[str | os.PathLike[str]],
    root_joint: str | None = None,
    *,
    xacro: XacroOptions | None = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    executor: Executor | None = None,
    jobs: int | None = None,
    window: int | None = None,
    then: Callable[[Report], Any] | None = None,
    srdf: str | bool | None = None,
    group: str | None = None,
    hold: str | None = None,
    limits: str | os.PathLike[str] | bool | None = None,
) -> Iterator[Inspected]:
    """Inspect many robot files in parallel; one `Inspected` per file, in order.

    A batch survives any one file: whatever goes wrong with a file is that file's
    ``error``, and the other files go on (see `many`). An exception
    that is not a `CspaceError` (a bug), raised while a file is
    inspected, while ``then`` runs on its report, or while its result is pickled or
    unpickled, is that file's `InternalError` (it has no report
    then, even when ``then`` failed). ``KeyboardInterrupt`` and ``SystemExit`` stop
    the run.

    Args:
        paths: Robot files or ``erd:NAME`` names (any iterable, read lazily).
        root_joint: As for `cspace.inspect`, for every file.
        xacro: As for `cspace.inspect`.
        force_xacro: As for `cspace.inspect`.
        allow_dirs: As for `cspace.inspect`.
        srdf: As for `cspace.inspect`: True finds each file's own SRDF.
        group: As for `cspace.inspect`, for every file.
        hold: As for `cspace.inspect`, for every file.
        limits: As for `cspace.inspect`, for every file.
        executor: Where to run the files (any ``concurrent.futures.Executor`` whose
            workers can import cspace; it is not shut down here). None: a process pool
            of ``jobs`` workers, made and shut down here.
        jobs: Workers of the default pool (default: the cores this process may use).
            1 runs every file in this process, one after the other.
        window: Files in flight at once (default: 4 per job, or 64 on the caller's
            executor). Memory holds at most this many reports waiting to be yielded.
        then: A function of each report, run in the worker (it must pickle: a
            module-level function, or a ``functools.partial`` of one); its result is
            the ``value`` of the file's `Inspected`, and must pickle too (except
            in this process: ``jobs=1``, or an executor of threads). Work on reports,
            such as writing them, then runs in parallel too.

    Yields:
        One `Inspected` per path, in the order of ``paths``.

    Raises:
        ArgumentTypeError: ``paths`` is one path, ``jobs`` or ``window`` not a whole
            number, or ``then`` does not pickle (for the default pool of several jobs).
        ArgumentError: ``jobs`` or ``window`` below 1.
        Exception: Whatever the caller's executor raises for a task that failed as a
            whole, not in one of its files (``then`` could not be sent to its workers,
            or a worker died). On the default pool a file whose worker dies gets a
            `WorkerDiedError`, and the other files go on (run
            again: ``then`` may see a report more than once).
    """
    options = LoadOptions(root_joint, xacro, force_xacro, allow_dirs, srdf, group, hold, limits)
    return inspect_many_with(paths, options, executor=executor, jobs=jobs, window=window, then=then)


def inspect_many_with(
    paths: Iterable[str | os.PathLike[str]],
    load: LoadOptions,
    *,
    executor: Executor | None = None,
    jobs: int | None = None,
    window: int | None = None,
    then: Callable[[Report], Any] | None = None,
) -> Iterator[Inspected]:
    """`inspect_many` with the loading options as one record (see `LoadOptions`)."""
    if isinstance(paths, str | bytes | os.PathLike):
        raise ArgumentTypeError(
            "paths must be an iterable of paths, not one path (use [path])", argument="paths"
        )
    for name, value in (("jobs", jobs), ("window", window)):
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int):
            raise ArgumentTypeError(
                f"{name} must be a whole number, got {type(value).__name__}", argument=name
            )
        if value < 1:
            raise ArgumentError(f"{name} must be a whole number >= 1, got {value!r}", argument=name)
    names = (path_text(p) for p in paths)
    dirs = tuple(path_text(d) for d in load.allow_dirs)
    options = _Options(load._replace(allow_dirs=dirs), then)
    if isinstance(paths, Sequence):  # known at once: one OpenUSD child serves their folders
        files = [os.path.abspath(n) for n in map(path_text, paths) if os.path.isfile(n)]
        scope = tuple(sorted({os.path.dirname(f) for f in files} | set(map(os.path.abspath, dirs))))
        options = dataclasses.replace(options, usd_scope=scope)
    workers = jobs if jobs is not None else default_jobs()
    if executor is None and workers == 1:
        if options.usd_scope:
            from cspace._formats.usd.child import within

            within(options.usd_scope)
        return (_inspect_one(name, options) for name in names)
    if executor is not None:
        from concurrent.futures import ThreadPoolExecutor

        if isinstance(executor, ThreadPoolExecutor):  # nothing crosses a process boundary
            options = dataclasses.replace(options, pickled=False)
        return _in_order(executor, names, options, window or 64)
    _check_pickles(then)
    return _on_own_pool(workers, names, options, window or 4 * workers)


def _check_pickles(then: Callable[[Report], Any] | None) -> None:
    """Refuse a ``then`` that cannot reach the default pool's workers (a lambda, a closure).

    Else every task would fail with the pool's pickling error, at the first result.
    """
    if then is None:
        return
    from multiprocessing.reduction import ForkingPickler  # as the pool pickles its tasks

    try:
        ForkingPickler.dumps(then)
    except Exception as exc:
        raise ArgumentTypeError(
            "then must pickle to reach the worker processes (a module-level function, or "
            f"a functools.partial of one): {type(exc).__name__}: {exc}",
            argument="then",
        ) from None


def _on_own_pool(
    workers: int, names: Iterator[str], options: _Options, window: int
) -> Iterator[Inspected]:
    """`_in_order` on a process pool made for the call, shut down after it.

    A worker that dies (a parser's crash, the kernel's OOM killer) breaks the whole
    pool: every task in flight fails with it. The pool is then made anew (started as
    the first was) and the tasks run again, a broken one a file at a time: only a file
    that kills its worker alone is reported, by a `WorkerDiedError`.
    ``then`` may therefore run more than once on a file's report.
    """
    pool = Pool(workers)
    try:
        yield from _in_order(pool, names, options, window)
    finally:
        pool.shutdown()


def _succeeded(future: Future[list[_Sent]]) -> bool:
    """The task is done and did not fail (its worker was not lost with the pool)."""
    return future.done() and not future.cancelled() and future.exception() is None


def _in_order(
    executor: Executor | Pool, names: Iterator[str], options: _Options, window: int
) -> Iterator[Inspected]:
    """Each file's result in order, tasks of `PER_TASK` files submitted ahead.

    At most ``window`` files are in flight (submitted and not yet yielded), and one task
    more while the first result is handed over. On a `Pool`,
    a task that broke the pool runs again a file at a time, and the tasks behind it are
    submitted again.
    """
    from concurrent.futures.process import BrokenProcessPool

    pool = executor if isinstance(executor, Pool) else None

    def submit(task: list[str]) -> tuple[list[str], Future[list[_Sent]]]:
        return task, executor.submit(_inspect_files, task, options)

    per_task = min(PER_TASK, window)
    tasks = iter(lambda: list(islice(names, per_task)), [])
    in_flight = max(1, window // per_task)
    pending = deque(submit(task) for task in islice(tasks, in_flight))
    try:
        while pending:
            task, future = pending.popleft()
            try:
                done = future.result()
            except BrokenProcessPool:
                if pool is None:
                    raise
                done = pool.run_alone(_inspect_files, task, options, _died)
                pending = deque(
                    (waiting, was) if _succeeded(was) else submit(waiting)
                    for waiting, was in pending
                )
            for more in islice(tasks, 1):
                pending.append(submit(more))
            for path, sent in zip(task, done, strict=True):
                yield _received(path, sent)
    finally:  # the caller stopped early, or a task failed: drop what has not started
        for _, future in pending:
            future.cancel()
