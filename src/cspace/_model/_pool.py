"""The process pool `cspace.inspect_many` makes for itself, and how it survives.

A worker that dies (a parser's crash, the kernel's OOM killer) breaks the whole pool:
every task in flight fails with it. `Pool` is then made anew (started as the
first was) and the broken task runs again a file at a time (`Pool.run_alone`).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

if TYPE_CHECKING:
    from concurrent.futures import Executor, Future
    from multiprocessing.context import BaseContext

T = TypeVar("T")

PRELOAD = (
    "cspace._model.loader",
    "cspace._model.adapter",
    "cspace._model.analysis",
    "cspace._formats.urdf.reader",
    "cspace._formats.sdf.reader",
    "cspace._reports.report",
)
"""What an inspection imports (Pinocchio and NumPy among them), imported once before the
workers start rather than in each."""


class Pool:
    """A process pool that `renew` makes anew when a worker's death breaks it."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self.context = _context()  # chosen once: a new pool starts as the first did
        self.pool = self._new()

    def _new(self) -> Executor:
        from concurrent.futures import ProcessPoolExecutor  # (imports multiprocessing)

        forked = self.context.get_start_method() == "fork"
        return ProcessPoolExecutor(
            self.workers,
            mp_context=self.context,
            initializer=_worker_start,
            initargs=(os.getpid() if forked else None,),
        )

    def submit(self, run: Callable[..., T], *args: Any) -> Future[T]:
        """``run(*args)`` on the current pool (as ``Executor.submit``).

        A pool already broken refuses new work; the task's future then holds that
        error, to be handled when its turn comes, as for a task in flight.
        """
        from concurrent.futures import Future
        from concurrent.futures.process import BrokenProcessPool

        try:
            return self.pool.submit(run, *args)
        except BrokenProcessPool as exc:
            failed: Future[T] = Future()
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

    def run_alone(
        self,
        run: Callable[[list[str], Any], list[T]],
        task: list[str],
        options: Any,
        died: Callable[[str], T],
    ) -> list[T]:
        """Each file of a task that broke the pool, ``run`` in a task of its own.

        Args:
            run: The task's function, of a list of files and ``options``.
            task: The files.
            options: Its second argument.
            died: The result of a file whose worker died even alone.
        """
        from concurrent.futures.process import BrokenProcessPool

        self.renew()
        done = []
        for path in task:
            try:
                done.extend(self.submit(run, [path], options).result())
            except BrokenProcessPool:
                done.append(died(path))
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


def _worker_start(parent: int | None = None) -> None:
    """In each worker: Ctrl-C is the caller's to handle (the pool is shut down there).

    The worker dies with the process that started it (Linux's ``PR_SET_PDEATHSIG``): a
    worker forked as Ctrl-C stopped the caller, before the pool knew of it, would run
    on, orphaned, holding the caller's output open. ``parent`` is the caller's id when
    the worker is forked from it: a caller already gone ends the worker at once.
    """
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # not Linux: the caller's shutdown ends the workers
        pass
    if parent is not None and os.getppid() != parent:
        os._exit(1)


def _threads() -> int:
    """The threads of this process, native ones too (0 when unknown)."""
    try:
        return len(os.listdir("/proc/self/task"))
    except OSError:
        return 0
