"""Where a user waits on the configuration commands, as ratios in one run.

Robot: talos_reduced from example-robot-data (``--root-joint floating`` for sampling,
the base position bounded to [-1, 1]^3).

1. One pair: ``cspace distance``, ``cspace interpolate`` (2 steps) and ``cspace sample
   -n 1`` against ``cspace inspect`` of the same robot, the four run in turn, wall time
   and peak memory of each process. Target: <= 1.3 (numba and scipy off the small path).
2. Streaming: ``cspace sample -n N --format npy -o FILE`` (N = ``--samples``, default
   10^7, a 3.1 GB file) against the in-memory sampling time of N configurations
   (``space.sample`` in pieces of 10^6, the most it allocates at once being 1 GiB).
   Target: < 2.
3. ``--huge N``: the peak memory of ``cspace sample -n N --format npy -o - > /dev/null``
   (10^8 writes 31 GB: some minutes). Target: <= 200 MB.

Run: `.venv/bin/python bench/bench_commands.py [--repeat R] [--samples N (0: skip)] [--huge N]`.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import cspace
from cspace._formats.shared import erd

BOX = ["--bounds", "root_joint.x=-1:1", "--bounds", "root_joint.y=-1:1"]
BOX += ["--bounds", "root_joint.z=-1:1"]
_MEASURE = """
import json, resource, subprocess, sys, time
start = time.perf_counter()
subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL)
peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
print(json.dumps({"seconds": time.perf_counter() - start, "peak_mib": peak}))
"""


def measure(command: list[str]) -> tuple[float, float]:
    """Wall seconds and peak resident MiB of a command (in a fresh measuring process)."""
    done = subprocess.run(
        [sys.executable, "-c", _MEASURE, *command], check=True, capture_output=True, text=True
    )
    result = json.loads(done.stdout)
    return float(result["seconds"]), float(result["peak_mib"])


def one_pair(robot: str, repeat: int) -> None:
    command = str(Path(sys.executable).with_name("cspace"))
    commands = {
        "inspect": [command, "inspect", robot, "--format", "json"],
        "distance": [command, "distance", robot, "{}", "{}", "--partial"],
        "interpolate": [command, "interpolate", robot, "{}", "{}", "--partial"],
        "sample -n 1": [command, "sample", robot, "-n", "1"],
    }
    for c in commands.values():
        measure(c)  # warm the file cache and numba's cache
    runs: dict[str, list[tuple[float, float]]] = {name: [] for name in commands}
    for _ in range(repeat):
        for name, c in commands.items():
            runs[name].append(measure(c))
    base = statistics.median(s for s, _ in runs["inspect"])
    for name, values in runs.items():
        seconds = statistics.median(s for s, _ in values)
        peak = max(m for _, m in values)
        print(
            f"{name:>12}: {seconds * 1e3:6.0f} ms, peak {peak:4.0f} MiB | ratio to inspect "
            f"{seconds / base:.2f} (target <= 1.3)"
        )


def streaming(robot: str, samples: int) -> None:
    space = cspace.load(robot, root_joint="floating")
    bounds = {f"root_joint.{c}": (-1.0, 1.0) for c in "xyz"}
    rng = np.random.default_rng(0)
    piece = 1_000_000
    start = time.perf_counter()
    done = 0
    while done < samples:
        space.sample(min(piece, samples - done), rng, bounds)
        done += piece
    in_memory = time.perf_counter() - start
    command = str(Path(sys.executable).with_name("cspace"))
    with tempfile.TemporaryDirectory() as folder:
        target = str(Path(folder) / "sample.npy")
        seconds, peak = measure(
            [command, "sample", robot, "--root-joint", "floating", *BOX, "-n", str(samples),
             "--format", "npy", "-o", target]
        )  # fmt: skip
        size = Path(target).stat().st_size
    print(
        f"sample -n {samples:,} --format npy: {seconds:.2f} s ({size / 1e9:.2f} GB, peak "
        f"{peak:.0f} MiB) | in-memory sampling {in_memory:.2f} s | ratio "
        f"{seconds / in_memory:.2f} (target < 2)"
    )


def huge(robot: str, samples: int) -> None:
    command = str(Path(sys.executable).with_name("cspace"))
    seconds, peak = measure(
        [command, "sample", robot, "--root-joint", "floating", *BOX, "-n", str(samples),
         "--format", "npy", "-o", "-"]  # standard output: /dev/null
    )  # fmt: skip
    print(
        f"sample -n {samples:,} --format npy -o - > /dev/null: {seconds:.0f} s, peak {peak:.0f} "
        "MiB (target <= 200)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=11)
    parser.add_argument(
        "--samples", type=int, default=10_000_000, help="streaming run size (0: skip it)"
    )
    parser.add_argument("--huge", type=int, default=0)
    args = parser.parse_args()
    robot = str(erd.robots_dir() / "talos_data/robots/talos_reduced.urdf")
    one_pair(robot, args.repeat)
    if args.samples > 0:
        streaming(robot, args.samples)
    if args.huge:
        huge(robot, args.huge)


if __name__ == "__main__":
    main()
