"""How `cspace inspect` grows with the robot: every stage of ours linear, as joints double.

1. Stages, in this process, on generated trees (``bench_inspect.generated_urdf``: chains
   of 10 joints) of 500 to 8,000 joints, best of ``--repeat``: reading and parsing,
   format detection, the URDF reader, Pinocchio's build (theirs, for scale), copying
   its model, the analysis, the JSON and text reports, ``ConfigurationSpace``. For each
   stage, the growth per doubling (2 = linear, 4 = quadratic). The 5,000-joint limit
   (``cspace._formats.shared.robot_size.MAX_JOINTS``) is lifted in this process only, for 8,000.
   Target: every stage of ours <= 2.3 per doubling.
2. The command as a user runs it: ``cspace inspect PATH --format json`` against
   ``python -c "import pinocchio; pinocchio.buildModelFromUrdf(PATH)"`` at 100 and
   4,000 joints, run alternately (median of ``--runs``). Targets: <= 1.1 at 100 joints,
   <= 1.3 at 4,000.

Run: `.venv/bin/python bench/bench_scaling.py [--repeat R] [--runs K]`.
"""

from __future__ import annotations

import argparse
import gc
import sys
import tempfile
import time
from collections.abc import Callable
from itertools import pairwise
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_inspect import generated_urdf, startup_ratio

SIZES = (500, 1000, 2000, 4000, 8000)


def stages(path: str, repeat: int) -> dict[str, float]:
    """Best seconds of each stage of inspecting ``path``."""
    import pinocchio as pin

    from cspace._formats.detect import detect
    from cspace._formats.shared.xmlio import parse_xml, read_source
    from cspace._formats.urdf.reader import read_urdf
    from cspace._model.adapter import record_of
    from cspace._model.analysis import analyse
    from cspace._render.text import render_text
    from cspace.space._configuration_space import ConfigurationSpace

    best: dict[str, float] = {}

    def timed(name: str, call: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
        gc.collect()
        start = time.perf_counter()
        result = call(*args, **kwargs)
        best[name] = min(best.get(name, float("inf")), time.perf_counter() - start)
        return result

    for _ in range(repeat):
        source = read_source(path)
        root = timed("parse XML", parse_xml, source)
        timed("detect format", detect, path, root, data=source.data)
        reading = timed("read URDF", read_urdf, path, root, source.text)
        model = timed(
            "Pinocchio build (theirs)", pin.buildModelFromXML, reading.recipe.text, mimic=True
        )
        record = timed("copy the model", record_of, model)
        report = timed("analyse", analyse, source, "urdf", reading.description, record, None)
        timed("JSON report", report.to_json)
        timed("text report", render_text, report, color=False)
        timed("ConfigurationSpace", ConfigurationSpace.from_report, report)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--runs", type=int, default=9)
    args = parser.parse_args()

    from cspace._formats.shared import robot_size

    with tempfile.TemporaryDirectory() as folder:
        files = {}
        for n in (100, *SIZES):
            files[n] = Path(folder) / f"tree{n}.urdf"
            files[n].write_text(generated_urdf(n))
        for n in (100, 4000):
            r = startup_ratio(args.runs, files[n])
            print(
                f"cspace inspect --format json, {n:,} joints: {r['cspace_median_s'] * 1e3:.0f} ms"
                f" | Pinocchio load {r['baseline_median_s'] * 1e3:.0f} ms | ratio "
                f"{r['ratio_median']:.2f} (target <= {1.1 if n == 100 else 1.3})"
            )
        robot_size.MAX_JOINTS = 100_000  # 8,000 joints: this process only
        table = {n: stages(str(files[n]), args.repeat) for n in SIZES}
    names = list(table[SIZES[0]])
    print(f"\n{'stage (ms)':<26}" + "".join(f"{n:>9,}" for n in SIZES) + "   growth per doubling")
    for name in names:
        times = [table[n][name] for n in SIZES]
        growth = " ".join(f"{b / a:.1f}" for a, b in pairwise(times))
        print(f"{name:<26}" + "".join(f"{t * 1e3:9.1f}" for t in times) + f"   {growth}")


if __name__ == "__main__":
    main()
