"""``cspace collisions``: which link pairs of a robot collide, over seeded uniform samples.

`collisions` reads the robot (`setup.prepare`), samples its C-space
(`tally.tally`, in several processes for a large run), sorts each link pair
into MoveIt's classes with its share of samples in collision and a 95% interval, and
checks what the robot's files say against it (`classes`).
"""

import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from cspace._model.options import LoadOptions
from cspace.errors import ArgumentError, RobotFileError
from cspace.space._collisions.setup import Prepared, prepare
from cspace.space._collisions.tally import MAX_BIN_CELLS, MAX_SAMPLES, Tally, tally

if TYPE_CHECKING:
    from cspace._formats.xacro.expand import XacroOptions
    from cspace._reports.collisions import CollisionReport

MAX_SEED = 2**63 - 1
"""The largest seed (a report's ``seed`` is a signed 64-bit integer)."""

CPU_FLOOR = 300.0
"""Least CPU seconds a sampling process may spend with ``cpu_limit`` (the command's)."""

CPU_PER_CHECK = 2e-5
"""CPU seconds a check of a pair of shapes may take on average with ``cpu_limit``: 20
times what the panda's meshes take (about 1 us); a pair of meshes built to be slow to
check (needles whose bounding volumes all overlap) takes seconds a check."""

PARALLEL_SAMPLES = 4_000
"""Runs of at least this many samples are split across processes (``jobs`` > 1)."""

MAX_CHECKS = 500_000_000
"""Most checks of a pair of shapes in one run (samples times pairs of shapes): at a few
microseconds a check for primitives, an hour of CPU; 10,000 samples of example-robot-
data's talos (1,326 pairs) are 13 million."""

_READY: "dict[tuple[str, LoadOptions], Prepared]" = {}
"""The robot a worker process has read, by (path, options): read once for all its parts
(a forked worker finds the caller's here and reads nothing)."""


def collisions(
    path: str | os.PathLike[str],
    *,
    samples: int = 10_000,
    seed: int = 0,
    srdf: str | os.PathLike[str] | bool | None = None,
    root_joint: str | None = None,
    xacro: "XacroOptions | None" = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    jobs: int = 1,
    progress: Callable[[int], None] | None = None,
    cpu_limit: bool = False,
) -> "CollisionReport":
    """Sample the robot at ``path`` and report which of its link pairs collide.

    Each pair of links with collision shapes is sorted as MoveIt's setup assistant
    sorts it (adjacent, in collision at the default configuration, in collision in 95%
    of the samples or more, at none, the rest), with its share of samples in collision
    and a 95% interval; the report gives the share of the C-space free of
    self-collision, the coordinate ranges where the robot always collides with itself,
    the stored poses in collision, and findings where the SRDF's
    ``<disable_collisions>``, MuJoCo's contact filters (MJCF) or PhysX's collision
    filters (OpenUSD) disagree with the samples. The same arguments give the same
    report.

    Args:
        path: A robot file (or ``erd:NAME``), as for `cspace.inspect`.
        samples: How many configurations, 1 to 1,000,000 (MoveIt's default: 10,000).
        seed: The samples' seed (>= 0): sample ``i`` of a seed is always the same.
        srdf: The robot's SRDF (True: look for it, as `cspace.inspect` does).
        root_joint: As for `cspace.inspect` (a root's pose does not change which links
            collide: its position is held at neutral).
        xacro: As for `cspace.inspect`.
        force_xacro: As for `cspace.inspect`.
        allow_dirs: Folders meshes (and MJCF includes) may be read from, beside the
            robot's project and its ROS packages.
        jobs: Processes for a run of at least `PARALLEL_SAMPLES` samples.
        progress: Called with each number of samples done, or None.
        cpu_limit: Sample in worker processes (one at least, whatever ``jobs``), each
            stopped past ``max(CPU_FLOOR, checks * CPU_PER_CHECK)`` seconds of CPU, so
            that a file cannot make the run take unbounded time (``cspace collisions``
            sets it; a library caller's own process is never limited).

    Raises:
        RobotFileError: The robot file or its SRDF cannot be read; a robot with closed
            loops (``collisions-loops``: its samples would not close them); more pairs
            of collision shapes than cspace checks, or an MJCF model of more geoms than
            it reads (``too-many-elements``); the robot's files changed while a worker
            process read them again (``file-unreadable``).
        WorkerDiedError: A worker process died (``jobs`` > 1 or ``cpu_limit``: a crash,
            the OOM killer, its CPU budget spent).
        RobotHasErrorsError: The robot's report has error findings (no C-space to
            sample).
        ArgumentError: ``samples``, ``seed`` or ``jobs`` out of range, ``allow_dirs`` one
            path rather than a list of them (a string's characters, ``/`` among them,
            would each be a folder allowed), or more checks of
            pairs of shapes (samples times pairs) than `MAX_CHECKS`.
    """
    from cspace.space._collisions.classes import report_of

    for name, value, low in (("samples", samples, 1), ("seed", seed, 0), ("jobs", jobs, 1)):
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            raise ArgumentError(f"{name} must be an integer >= {low}, got {value!r}")
    if seed > MAX_SEED:
        raise ArgumentError(f"seed must be at most {MAX_SEED:,}, got {seed:,}")
    if samples > MAX_SAMPLES:
        raise ArgumentError(f"samples must be at most {MAX_SAMPLES:,}, got {samples:,}")
    if isinstance(allow_dirs, (str, bytes, os.PathLike)):  # its characters are no folders
        raise ArgumentError(
            f"allow_dirs must be a list of folders, not one: give [{allow_dirs!r}]",
            argument="allow_dirs",
        )
    options = LoadOptions(root_joint, xacro, force_xacro, tuple(allow_dirs), srdf)
    prepared = prepare(path, options)
    checks = samples * len(prepared.engine.geometry.collisionPairs)
    if checks > MAX_CHECKS:
        raise ArgumentError(
            f"{samples:,} samples of {len(prepared.engine.geometry.collisionPairs):,} pairs of "
            f"collision shapes are {checks:,} checks, more than the {MAX_CHECKS:,} cspace "
            "makes in one run: ask for fewer samples (-n)"
        )
    columns = MAX_BIN_CELLS // samples
    prepared = prepared._replace(sampler=prepared.sampler.first(columns))
    budget = max(CPU_FLOOR, checks * CPU_PER_CHECK) if cpu_limit else None
    counted = _run(prepared, path, options, samples, seed, jobs, progress, columns, budget)
    return report_of(prepared, counted, samples, seed)


def checked_flags(prepared: Prepared) -> list[bool]:
    """Per pair sampled: the file's matrix checks it."""
    return [prepared.checked(p) for p in prepared.engine.pairs]


def _run(
    prepared: Prepared,
    path: str | os.PathLike[str],
    options: LoadOptions,
    samples: int,
    seed: int,
    jobs: int,
    progress: Callable[[int], None] | None,
    columns: int,
    budget: float | None = None,
) -> Tally:
    checked = checked_flags(prepared)
    if budget is None and (jobs == 1 or samples < PARALLEL_SAMPLES):
        return tally(prepared.sampler, prepared.engine, checked, seed, 0, samples, progress)
    if samples < PARALLEL_SAMPLES:
        jobs = 1
    from concurrent.futures.process import BrokenProcessPool

    from cspace._model._pool import Pool
    from cspace.errors import WorkerDiedError

    parts = _parts(samples, jobs)
    key = (os.fspath(path), options)
    _READY.clear()
    _READY[key] = prepared  # before the pool forks
    import multiprocessing

    before = {child.pid for child in multiprocessing.active_children()}
    pool = Pool(min(jobs, len(parts)))
    # a worker not forked from here reads the robot again: it must read what this one did
    digest = None if pool.context.get_start_method() == "fork" else _digest(prepared)
    try:
        futures = [
            pool.submit(_part, key[0], options, seed, a, b, columns, digest, budget)
            for a, b in parts
        ]
        result = Tally(0, len(prepared.engine.pairs), len(prepared.sampler.columns))
        for (a, b), future in zip(parts, futures, strict=True):
            try:
                result.add(future.result())
            except BrokenProcessPool:
                spent = "" if budget is None else f", or spent its {budget:,.0f} s of CPU"
                raise WorkerDiedError(
                    prepared.report.source.path,
                    "a worker process sampling the robot died (it crashed or was killed, "
                    f"perhaps for memory{spent}): no report",
                ) from None
            if progress is not None:
                progress(b - a)
    except BaseException:  # Ctrl-C, a worker's error: its siblings' parts are not waited for
        _end_workers(pool, before)
        pool.pool.shutdown(wait=False, cancel_futures=True)
        _READY.clear()
        raise
    pool.shutdown()
    _READY.clear()
    return result


def _end_workers(pool: Any, before: set[int | None]) -> None:
    """Terminate the workers of ``pool`` (a `cspace._model._pool.Pool`) now.

    They ignore Ctrl-C (the caller handles it), and the pool's shutdown waits for the
    parts they run: thousands of samples each, minutes of a heavy robot. A worker Ctrl-C
    caught between its start and its place in the pool's table is one of this process's
    children that ``before`` (their ids when the pool was made) lacks: multiprocessing
    would wait for it at exit.
    """
    import multiprocessing

    processes = list((getattr(pool.pool, "_processes", None) or {}).values())
    known = {process.pid for process in processes}
    processes += [
        child
        for child in multiprocessing.active_children()
        if child.pid not in before and child.pid not in known
    ]
    for process in processes:
        process.terminate()
    for process in processes:  # a worker that does not end at SIGTERM is killed
        process.join(2.0)
        if process.is_alive():
            process.kill()
            process.join(2.0)


def _parts(samples: int, jobs: int) -> list[tuple[int, int]]:
    """Sample ranges for ``jobs`` processes: whole blocks, a few per process."""
    from cspace._model._collision_pairs import SAMPLE_BLOCK

    blocks = -(-samples // SAMPLE_BLOCK)
    per = max(1, -(-blocks // (4 * jobs)))
    return [
        (b * SAMPLE_BLOCK, min((b + per) * SAMPLE_BLOCK, samples)) for b in range(0, blocks, per)
    ]


def _part(
    path: str,
    options: LoadOptions,
    seed: int,
    start: int,
    stop: int,
    columns: int,
    digest: str | None,
    budget: float | None = None,
) -> Tally:
    """Samples ``start`` to ``stop`` in a worker process (the robot read there once).

    A worker that was not forked from the caller reads the robot itself; ``digest`` is
    the caller's `_digest` of its own read, which this read must match.

    Raises:
        RobotFileError: The robot's files read otherwise here (changed meanwhile).
    """
    if budget is not None:
        _limit_cpu(budget)
    prepared = _READY.get((path, options))
    if prepared is None:
        _READY.clear()
        prepared = prepare(path, options)
        if digest is not None and _digest(prepared) != digest:
            raise RobotFileError(
                prepared.report.source.path,
                "the robot's files changed while cspace collisions read them (a worker "
                "process read them otherwise than the first read): run it again",
                code="file-unreadable",
            )
        _READY[(path, options)] = prepared
    sampler = prepared.sampler.first(columns)
    return tally(sampler, prepared.engine, checked_flags(prepared), seed, start, stop)


_LIMITED: list[bool] = []
"""Whether this worker process has limited its CPU time (once, at its first part)."""


def _limit_cpu(budget: float) -> None:
    """Stop this worker process (SIGXCPU) after ``budget`` more seconds of CPU."""
    import resource

    if _LIMITED:
        return
    _LIMITED.append(True)
    used = resource.getrusage(resource.RUSAGE_SELF)
    soft = int(used.ru_utime + used.ru_stime + budget) + 1
    hard = resource.getrlimit(resource.RLIMIT_CPU)[1]
    if hard != resource.RLIM_INFINITY:
        soft = min(soft, hard)
    resource.setrlimit(resource.RLIMIT_CPU, (soft, hard))


def _digest(prepared: Prepared) -> str:
    """A hash of what the samples of ``prepared`` depend on.

    The robot file's bytes, the pairs sampled and their shapes (coal's geometry, meshes
    included), the file's matrix and the bounds held: a worker's `Tally` is added to the
    caller's pair by pair.
    """
    import hashlib
    import pickle

    engine = prepared.engine
    said = (
        prepared.report.source.sha256,
        prepared.matrix,
        prepared.srdf,
        engine.pairs,
        sorted((prepared.rules or {}).items()),
        [(p.first, p.second) for p in engine.geometry.collisionPairs],
        sorted(prepared.sampler.held.items()),
    )
    hashed = hashlib.sha256(repr(said).encode("utf-8"))
    hashed.update(pickle.dumps(engine.geometry))  # Pinocchio's own serialization
    return hashed.hexdigest()
