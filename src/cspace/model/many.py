"""Many robot files at once, on any ``concurrent.futures.Executor``, in input order.

:func:`inspect_many` runs :func:`cspace.inspect` on each file and yields one
:class:`Inspected` per file, in the order the files were given, as soon as it and every
file before it are done. The work goes to an executor: by default a process pool with
one worker per core (Pinocchio's parser holds the GIL, so threads would not help),
forked from the caller when it runs one thread, else from a forkserver (a script then
needs the usual ``if __name__ == "__main__":`` guard); or
the caller's own, such as a Dask cluster's ``Client.get_executor()`` or Ray's, with no
other change. At most ``window`` files are in flight, so memory stays bounded for any
number of files, and a generator of paths is read only as far as needed.

Each file's report or error crosses the process boundary pickled: reports and every
:class:`~cspace.errors.CspaceError` pickle (see ``CspaceError.__reduce__``).
"""

from __future__ import annotations

import os
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from itertools import islice
from typing import TYPE_CHECKING, Any

from cspace.errors import ArgumentError, ArgumentTypeError, CspaceError, WorkerDiedError
from cspace.formats.xmlio import path_text

if TYPE_CHECKING:
    from concurrent.futures import Executor, Future
    from multiprocessing.context import BaseContext

    from cspace.formats.xacrofile import XacroOptions
    from cspace.reports.report import Report


PRELOAD = (
    "cspace.model.loader",
    "cspace.model.adapter",
    "cspace.model.analysis",
    "cspace.formats.urdf",
    "cspace.formats.sdf",
    "cspace.reports.report",
)
"""What an inspection imports (Pinocchio and NumPy among them), imported once before the
workers start rather than in each."""

PER_TASK = 4
"""Files per task sent to a worker (a file takes about a millisecond; a task's round trip
a tenth of one)."""


@dataclass(frozen=True)
class Inspected:
    """What became of one file: its report, or the error that stopped it.

    Attributes:
        path: The file as given (``erd:NAME`` too).
        report: The report, or None when the file has none.
        error: Why there is no report, or None.
        value: What ``then`` made of the report in the worker (see
            :func:`inspect_many`), or None.
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
    """How every file is loaded (see :func:`cspace.inspect`); pickled into each task."""

    root_joint: str | None
    xacro: XacroOptions | None
    force_xacro: bool
    allow_dirs: tuple[str, ...]
    then: Callable[[Report], Any] | None = None


def _inspect_one(path: str, options: _Options) -> Inspected:
    """:func:`cspace.inspect` of one file, its error caught."""
    from cspace.model.loader import inspect

    try:
        report = inspect(
            path,
            options.root_joint,
            xacro=options.xacro,
            force_xacro=options.force_xacro,
            allow_dirs=options.allow_dirs,
        )
    except CspaceError as exc:
        return Inspected(path, None, exc)
    return Inspected(path, report, None, None if options.then is None else options.then(report))


def _inspect_files(paths: Sequence[str], options: _Options) -> list[Inspected]:
    """The task each worker runs: a few files (sparing the per-task cost), one by one."""
    return [_inspect_one(path, options) for path in paths]


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
) -> Iterator[Inspected]:
    """Inspect many robot files in parallel; one :class:`Inspected` per file, in order.

    Args:
        paths: Robot files or ``erd:NAME`` names (any iterable, read lazily).
        root_joint: As for :func:`cspace.inspect`, for every file.
        xacro: As for :func:`cspace.inspect`.
        force_xacro: As for :func:`cspace.inspect`.
        allow_dirs: As for :func:`cspace.inspect`.
        executor: Where to run the files (any ``concurrent.futures.Executor`` whose
            workers can import cspace; it is not shut down here). None: a process pool
            of ``jobs`` workers, made and shut down here.
        jobs: Workers of the default pool (default: the cores this process may use).
            1 runs every file in this process, one after the other.
        window: Files in flight at once (default: 4 per job, or 64 on the caller's
            executor). Memory holds at most this many reports waiting to be yielded.
        then: A function of each report, run in the worker (it must pickle: a
            module-level function, or a ``functools.partial`` of one); its result is
            the ``value`` of the file's :class:`Inspected`. Work on reports, such as
            writing them, then runs in parallel too.

    Yields:
        One :class:`Inspected` per path, in the order of ``paths``.

    Raises:
        ArgumentTypeError: ``paths`` is one path, or ``jobs`` or ``window`` not a whole
            number.
        ArgumentError: ``jobs`` or ``window`` below 1.
        Whatever the executor raises for a task that failed without a CspaceError (a
        bug; on the caller's executor, a worker that died). On the default pool a file
        whose worker dies gets a :class:`~cspace.errors.WorkerDiedError`, and the
        other files go on (run again: ``then`` may see a report more than once).
    """
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
    dirs = tuple(path_text(d) for d in allow_dirs)
    options = _Options(root_joint, xacro, force_xacro, dirs, then)
    workers = jobs if jobs is not None else default_jobs()
    if executor is None and workers == 1:
        return (_inspect_one(name, options) for name in names)
    if executor is not None:
        return _in_order(executor, names, options, window or 64)
    return _on_own_pool(workers, names, options, window or 4 * workers)


def _on_own_pool(
    workers: int, names: Iterator[str], options: _Options, window: int
) -> Iterator[Inspected]:
    """:func:`_in_order` on a process pool made for the call, shut down after it.

    A worker that dies (a parser's crash, the kernel's OOM killer) breaks the whole
    pool: every task in flight fails with it. The pool is then made anew (started as
    the first was) and the tasks run again, a broken one a file at a time: only a file
    that kills its worker alone is reported, by a :class:`~cspace.errors.WorkerDiedError`.
    ``then`` may therefore run more than once on a file's report.
    """
    pool = _Pool(workers)
    try:
        yield from _in_order(pool, names, options, window)
    finally:
        pool.shutdown()


class _Pool:
    """A process pool that :meth:`renew` makes anew when a worker's death breaks it."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self.context = _context()  # chosen once: a new pool starts as the first did
        self.pool = self._new()

    def _new(self) -> Executor:
        from concurrent.futures import ProcessPoolExecutor  # (imports multiprocessing)

        return ProcessPoolExecutor(self.workers, mp_context=self.context, initializer=_worker_start)

    def submit(
        self,
        run: Callable[[list[str], _Options], list[Inspected]],
        task: list[str],
        options: _Options,
    ) -> Future[list[Inspected]]:
        """``run(task, options)`` on the current pool (as ``Executor.submit``).

        A pool already broken refuses new work; the task's future then holds that
        error, to be handled when its turn comes, as for a task in flight.
        """
        from concurrent.futures import Future
        from concurrent.futures.process import BrokenProcessPool

        try:
            return self.pool.submit(run, task, options)
        except BrokenProcessPool as exc:
            failed: Future[list[Inspected]] = Future()
            failed.set_exception(exc)
            return failed

    def shutdown(self) -> None:
        self.pool.shutdown(cancel_futures=True)

    def renew(self) -> None:
        """A new pool in place of a broken one (whose workers are gone).

        The broken pool's threads are waited for (they end at once), so that a fork
        context forks with no thread of theirs left.
        """
        self.pool.shutdown(wait=True, cancel_futures=True)
        self.pool = self._new()

    def run_alone(self, task: list[str], options: _Options) -> list[Inspected]:
        """Each file of a task that broke the pool, in a task of its own."""
        from concurrent.futures.process import BrokenProcessPool

        self.renew()
        done = []
        for path in task:
            try:
                done.extend(self.submit(_inspect_files, [path], options).result())
            except BrokenProcessPool:
                message = (
                    "the worker process inspecting this file died (it crashed or was "
                    "killed, perhaps for memory); no report"
                )
                done.append(Inspected(path, None, WorkerDiedError(path, message)))
                self.renew()
        return done


def _context() -> BaseContext:
    """How to start workers: fork a one-thread process, else fork from a clean server.

    Forking copies the caller as it is, cspace and Pinocchio imported first (workers
    start in milliseconds), but is only safe with no other thread that might hold a
    lock; else a forkserver, which imports cspace once and forks from that. (NumPy's
    OpenBLAS starts threads when imported, unless ``OPENBLAS_NUM_THREADS=1``, as the
    ``cspace`` command sets.)
    """
    import multiprocessing

    if _threads() == 1 and "fork" in multiprocessing.get_all_start_methods():
        import importlib

        for module in PRELOAD:  # workers start with them (Pinocchio too)
            importlib.import_module(module)

        if _threads() == 1:  # importing NumPy starts OpenBLAS's threads, unless limited
            return multiprocessing.get_context("fork")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(list(PRELOAD))
    return context


def _worker_start() -> None:
    """In each worker: Ctrl-C is the caller's to handle (the pool is shut down there)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _threads() -> int:
    """The threads of this process, native ones too (0 when unknown)."""
    try:
        return len(os.listdir("/proc/self/task"))
    except OSError:
        return 0


def _succeeded(future: Future[list[Inspected]]) -> bool:
    """The task is done and did not fail (its worker was not lost with the pool)."""
    return future.done() and not future.cancelled() and future.exception() is None


def _in_order(
    executor: Executor | _Pool, names: Iterator[str], options: _Options, window: int
) -> Iterator[Inspected]:
    """Each file's result in order, tasks of :data:`PER_TASK` files submitted ahead.

    At most ``window`` files are in flight (submitted and not yet yielded), and one task
    more while the first result is handed over. On a :class:`_Pool`, a task that broke
    the pool runs again a file at a time, and the tasks behind it are submitted again.
    """
    from concurrent.futures.process import BrokenProcessPool

    pool = executor if isinstance(executor, _Pool) else None

    def submit(task: list[str]) -> tuple[list[str], Future[list[Inspected]]]:
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
                done = pool.run_alone(task, options)
                pending = deque(
                    (waiting, was) if _succeeded(was) else submit(waiting)
                    for waiting, was in pending
                )
            for more in islice(tasks, 1):
                pending.append(submit(more))
            yield from done
    finally:  # the caller stopped early, or a task failed: drop what has not started
        for _, future in pending:
            future.cancel()
