"""Benchmark of ``cspace collisions`` against a plain Pinocchio loop, as ratios.

Three figures on example-robot-data's panda and UR5 (meshes read by cspace's readers,
their SRDFs read), each a ratio within one run:

- ``ratio``: the CPU time of cspace's sampling loop (`tally`: canonical samples drawn in
  seeded blocks and mapped to Pinocchio's q, each pair's count and first witness, each
  sample's free flags and bins) over a plain loop of ``pin.computeCollisions`` on the
  same configurations and the same pairs of shapes. Target: <= 1.5.
- ``linear``: the loop's CPU time per sample at ``2 N`` samples over that at ``N``.
  Target: about 1 (a run's memory and time grow linearly in its samples).
- ``processes``: the wall-clock time of the whole command (``cspace collisions ROBOT
  --srdf auto -n 4N``) with ``-j 2`` over ``-j 1``, on 2 cores. Target: below 1.

Run: `.venv/bin/python bench/bench_collisions.py [--samples N] [--repeat N]`.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import pinocchio as pin

from cspace._model.options import LoadOptions
from cspace.space._collisions.run import checked_flags
from cspace.space._collisions.setup import Prepared, prepare
from cspace.space._collisions.tally import tally

ROBOTS = ("panda", "ur5")
CSPACE = str(Path(sys.executable).with_name("cspace"))


def _loop(prepared: Prepared, n: int) -> float:
    """CPU seconds of cspace's sampling loop over ``n`` samples."""
    checked = checked_flags(prepared)
    start = time.process_time()
    tally(prepared.sampler, prepared.engine, checked, 0, 0, n)
    return time.process_time() - start


def _plain(prepared: Prepared, n: int) -> float:
    """CPU seconds of a plain ``computeCollisions`` loop over the same samples."""
    engine = prepared.engine
    blocks = [prepared.sampler.block(0, b) for b in range(-(-n // 1000))]
    qs = [q for x in blocks for q in prepared.sampler.to_q(x)][:n]
    data = engine.model.createData()
    geometry_data = pin.GeometryData(engine.geometry)
    for request in geometry_data.collisionRequests:  # as the engine asks (no missed overlap)
        request.enable_contact = True
        request.gjk_initial_guess = pin.coal.GJKInitialGuess.DefaultGuess
    start = time.process_time()
    for q in qs:
        pin.computeCollisions(engine.model, data, engine.geometry, geometry_data, q, False)
    return time.process_time() - start


def _command(robot: str, n: int, jobs: int) -> float:
    """Wall-clock seconds of the whole command."""
    start = time.perf_counter()
    subprocess.run(
        [CSPACE, "collisions", f"erd:{robot}", "--srdf", "auto", "-n", str(n), "-j", str(jobs)],
        check=False,
        stdout=subprocess.DEVNULL,
        env=os.environ | {"CSPACE_PROGRESS": "off"},
    )
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    n = args.samples
    results = {}
    for name in ROBOTS:
        prepared = prepare(f"erd:{name}", LoadOptions(srdf=True))
        runs = [(_loop(prepared, n), _plain(prepared, n)) for _ in range(args.repeat)]
        double = [_loop(prepared, 2 * n) for _ in range(args.repeat)]
        one = [_command(name, 4 * n, 1) for _ in range(args.repeat)]
        two = [_command(name, 4 * n, 2) for _ in range(args.repeat)]
        results[name] = {
            "samples": n,
            "shape_pairs": len(prepared.engine.geometry.collisionPairs),
            "cpu_seconds": statistics.median(r[0] for r in runs),
            "plain_cpu_seconds": statistics.median(r[1] for r in runs),
            "ratio": statistics.median(r[0] / r[1] for r in runs),
            "linear": statistics.median(double) / 2 / statistics.median(r[0] for r in runs),
            "command_seconds_j1": statistics.median(one),
            "command_seconds_j2": statistics.median(two),
            "processes": statistics.median(two) / statistics.median(one),
        }
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
