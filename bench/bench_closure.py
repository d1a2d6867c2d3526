"""Benchmarks of the closed chains' analysis, as ratios in one run.

1. What the loops add to the command: the wall time of `cspace inspect` on the delta
   robot (tests/closed/delta.xml: 6 connects, 18 equations, 21 velocities: the search
   for configurations projects 33 of them) against the same file with its
   ``<equality>`` removed (the tree alone), run alternately. Target: ratio <= 1.5.
2. The same for the planar four-bar (tests/closed/fourbar.xml). Target: ratio <= 1.5.
3. The analysis alone, for information: the CPU time of `cspace.inspect` of each in one
   process (MuJoCo's compile in its child, cached after the first, left out), mechanism
   against tree.

Run: `.venv/bin/python bench/bench_closure.py [--repeat N]`, with ``OMP_NUM_THREADS``
and ``OPENBLAS_NUM_THREADS`` set to 1 and to 2 (the figures in docs/benchmarks.md).
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

import cspace

REPO = Path(__file__).resolve().parent.parent
CLOSED = REPO / "tests" / "closed"


def _tree_of(path: Path, folder: Path) -> Path:
    """The file with its ``<equality>`` block removed: the tree of the mechanism."""
    text = path.read_text()
    start, end = text.index("<equality>"), text.index("</equality>") + len("</equality>")
    tree = folder / f"tree_{path.name}"
    tree.write_text(text[:start] + text[end:])
    return tree


def _cpu(path: Path) -> float:
    start = time.process_time()
    cspace.inspect(path)
    return time.process_time() - start


def _wall(path: Path) -> float:
    command = [str(Path(sys.executable).with_name("cspace")), "inspect", str(path)]
    start = time.perf_counter()
    subprocess.run(command, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def closure_ratio(path: Path, repeat: int) -> dict[str, float]:
    """Median seconds of inspecting the mechanism and its tree, and their ratios."""
    with tempfile.TemporaryDirectory() as folder:
        tree = _tree_of(path, Path(folder))
        out: dict[str, float] = {}
        for label, measure in (("command_wall", _wall), ("analysis_cpu", _cpu)):
            measure(path), measure(tree)  # warm: the file cache, imports, MuJoCo's child
            ours, theirs = [], []
            for _ in range(repeat):
                ours.append(measure(path))
                theirs.append(measure(tree))
            out[f"{label}_mechanism_s"] = statistics.median(ours)
            out[f"{label}_tree_s"] = statistics.median(theirs)
            out[f"{label}_ratio"] = statistics.median(ours) / statistics.median(theirs)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=11)
    args = parser.parse_args()
    results = {
        name: closure_ratio(CLOSED / name, args.repeat) for name in ("delta.xml", "fourbar.xml")
    }
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
