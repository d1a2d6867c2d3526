"""Many files: files per second on 2 cores against 1, as ratios in one run.

The robots: every URDF of example-robot-data and of ``robots/``, repeated ``--copies``
times (so that the run is long enough to measure the steady rate).

1. The command: ``cspace inspect FILES --format jsonl --jobs 2`` against ``--jobs 1``,
   run alternately (median of ``--runs``), start-up and worker start-up included.
2. The library in a long-running program: ``cspace.inspect_many`` on a process pool of
   2 workers that is already running, against ``jobs=1`` in this process (best of
   ``--runs``).

3. The machine's own ceiling for this work: two independent processes, each
   inspecting every file in turn, against one alone (throughput ratio). No scheduling,
   no messages: what two cores give this workload (inspection allocates a lot, and the
   two cores share caches and memory).

Target: files per second on 2 cores >= 1.8x one core.

Run: `.venv/bin/python bench/bench_many.py [--copies C] [--runs K]`.
"""

from __future__ import annotations

import argparse
import multiprocessing
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import cspace
from cspace._formats.shared import erd

REPO = Path(__file__).resolve().parent.parent


def robot_files() -> list[str]:
    files = sorted(str(p) for p in erd.robots_dir().rglob("*.urdf"))
    files += sorted(str(p) for p in (REPO / "robots").glob("*.urdf"))
    return files  # a file without a report counts too: it is work as well


def command(files: list[str], runs: int) -> None:
    cspace_command = str(Path(sys.executable).with_name("cspace"))
    seconds: dict[int, list[float]] = {1: [], 2: []}
    for _ in range(runs):
        for jobs in (1, 2):
            start = time.perf_counter()
            subprocess.run(
                [cspace_command, "inspect", *files, "--format", "jsonl", "--jobs", str(jobs)],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                check=False,
            )
            seconds[jobs].append(time.perf_counter() - start)
    one, two = statistics.median(seconds[1]), statistics.median(seconds[2])
    print(
        f"cspace inspect of {len(files)} files: --jobs 1 {len(files) / one:.0f} files/s, "
        f"--jobs 2 {len(files) / two:.0f} files/s | ratio {one / two:.2f} (target >= 1.8)"
    )


def library(files: list[str], runs: int) -> None:
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["cspace._model.loader"])
    with ProcessPoolExecutor(2, mp_context=context) as pool:
        list(cspace.inspect_many(files[:50], executor=pool))  # start and warm the workers
        list(cspace.inspect_many(files[:50], jobs=1))
        one = min(_timed(lambda: list(cspace.inspect_many(files, jobs=1))) for _ in range(runs))
        two = min(
            _timed(lambda: list(cspace.inspect_many(files, executor=pool, window=64)))
            for _ in range(runs)
        )
    print(
        f"inspect_many of {len(files)} files: jobs=1 {len(files) / one:.0f} files/s, a running "
        f"pool of 2 {len(files) / two:.0f} files/s | ratio {one / two:.2f} (target >= 1.8)"
    )


def _timed(call: Callable[[], object]) -> float:
    start = time.perf_counter()
    call()
    return time.perf_counter() - start


_ALONE = """
import sys, time, cspace
files = sys.argv[1:]
start = time.perf_counter()
for name in files:
    try:
        cspace.inspect(name)
    except cspace.CspaceError:
        pass
print(time.perf_counter() - start)
"""


def ceiling(files: list[str], runs: int) -> None:
    def run(copies: int) -> float:
        command = [sys.executable, "-c", _ALONE, *files]
        started = [
            subprocess.Popen(command, stdout=subprocess.PIPE, text=True) for _ in range(copies)
        ]
        return max(float(p.communicate()[0]) for p in started)

    one = min(run(1) for _ in range(runs))
    two = min(run(2) for _ in range(runs))
    print(
        f"ceiling: two independent processes inspect {2 * one / two:.2f}x the files of one "
        "in the same time"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--copies", type=int, default=5)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    files = robot_files() * args.copies
    command(files, args.runs)
    library(files, args.runs)
    ceiling(files, args.runs)


if __name__ == "__main__":
    main()
