"""A repository's folder of robots read by a confined child: USD and MJCF against URDF.

``cspace inspect --format jsonl FOLDER``, the command as CI runs it (its default jobs:
one worker per core it may use), on a folder of ``--count`` small robots of one format:
USD (copies of ``tests/usd/converted/arm7.usda``, read by OpenUSD) and MJCF (copies of
``robots/mjcf_every_joint.xml``, compiled by MuJoCo), each against as many URDFs
(``robots/arm7.urdf``, read in the process), run alternately (median of ``--runs``), on
2 cores and on 1 (the command's CPU affinity). Two layouts: every robot in the folder
itself (``flat``), and each in a folder of its own (``nested``: ``robots/NAME/NAME.usda``,
as asset libraries lay them out).

USD and MJCF robots are read in a confined child; one child per process serves them all
(before, one child per robot: 53 s for 200 USD robots). Target: 200 USD robots within
5 s on 2 cores; the ratio to the URDFs says what the child costs on top.

Run: `.venv/bin/python bench/bench_folders.py [--count N] [--runs K]`.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
USD = REPO / "tests" / "usd" / "converted" / "arm7.usda"
URDF = REPO / "robots" / "arm7.urdf"
MJCF = REPO / "robots" / "mjcf_every_joint.xml"
_PINNED = "import os, sys; os.sched_setaffinity(0, {%s}); os.execv(sys.argv[1], sys.argv[1:])"


def make(folder: Path, source: Path, count: int, nested: bool) -> Path:
    """A folder of ``count`` copies of ``source``, flat or each in a folder of its own."""
    for i in range(count):
        name = f"robot{i:04d}"
        target = (
            folder / name / f"{name}{source.suffix}"
            if nested
            else folder / f"{name}{source.suffix}"
        )
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(source, target)
    return folder


def timed(folder: Path, cores: str) -> float:
    """Seconds of ``cspace inspect --format jsonl FOLDER`` on ``cores``; it must read all."""
    cspace = str(Path(sys.executable).with_name("cspace"))
    command = [sys.executable, "-c", _PINNED % cores, cspace, "inspect", "--format", "jsonl"]
    start = time.perf_counter()
    done = subprocess.run([*command, str(folder)], capture_output=True, check=False)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"cspace failed on {folder}: {done.stderr.decode()[-500:]}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--count", type=int, default=200)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    cores = sorted(os.sched_getaffinity(0))
    choices = {"2 cores": ",".join(map(str, cores[:2])), "1 core": str(cores[-1])}
    with tempfile.TemporaryDirectory() as scratch:
        for layout in ("flat", "nested"):
            nested = layout == "nested"
            urdf = make(Path(scratch) / f"urdf-{layout}", URDF, args.count, nested)
            for kind, source in (("USD", USD), ("MJCF", MJCF)):
                folder = make(Path(scratch) / f"{kind}-{layout}", source, args.count, nested)
                for label, chosen in choices.items():
                    timed(folder, chosen)  # warm the file cache
                    seconds: dict[str, list[float]] = {"child": [], "urdf": []}
                    for _ in range(args.runs):
                        seconds["child"].append(timed(folder, chosen))
                        seconds["urdf"].append(timed(urdf, chosen))
                    pairs = zip(seconds["child"], seconds["urdf"], strict=True)
                    ratio = statistics.median(a / b for a, b in pairs)
                    print(
                        f"{args.count} robots, {layout}, {label}: {kind} "
                        f"{statistics.median(seconds['child']):.2f} s, URDF "
                        f"{statistics.median(seconds['urdf']):.2f} s | {kind}/URDF "
                        f"{ratio:.2f} (target: USD within 5 s on 2 cores)"
                    )


if __name__ == "__main__":
    main()
