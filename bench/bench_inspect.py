"""Benchmarks of `cspace inspect` against Pinocchio's own loading, as ratios in one run.

1. Start-up and load of a 7-joint arm: the wall time of the `cspace inspect` command
   against `python -c "import pinocchio; pinocchio.buildModelFromUrdf(PATH)"` on the same
   file, run alternately (import cost counts). Target: ratio <= 1.2.
2. A generated URDF of 2,000 joints: cspace's own work (safe XML parse, URDF reading
   and structural checks, copying the model, classification and diagnostics) against
   Pinocchio's parse of the same text. Target: ratio < 1.
3. Start-up and load of an MJCF model (robots/mjcf_every_joint.xml): the `cspace
   inspect` command (pre-scan, MuJoCo's compile in its confined child process while
   Pinocchio is imported, the model assembled, the analysis) against `python -c "import
   mujoco; mujoco.MjModel.from_xml_path(PATH)"`, MuJoCo's own load of the same file,
   run alternately. Target: ratio <= 1.75 (cspace starts a second interpreter that
   imports MuJoCo while its own imports Pinocchio: on 2 cores the two contend).

Run: `.venv/bin/python bench/bench_inspect.py [--repeat N]`.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
ARM = REPO / "robots" / "arm7.urdf"
MJCF = REPO / "robots" / "mjcf_every_joint.xml"


def _wall(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def startup_ratio(repeat: int, path: Path = ARM, load: str = "") -> dict[str, float]:
    """Median and best wall times of ``cspace inspect path`` and ``load``, run alternately."""
    python = sys.executable
    cspace = str(Path(python).with_name("cspace"))
    ours = [cspace, "inspect", str(path), "--format", "json"]
    load = load or f"import pinocchio; pinocchio.buildModelFromUrdf({str(path)!r})"
    theirs = [python, "-c", load]
    for command in (ours, theirs):  # warm the file cache
        _wall(command)
    a: list[float] = []
    b: list[float] = []
    for _ in range(repeat):
        a.append(_wall(ours))
        b.append(_wall(theirs))
    return {
        "cspace_median_s": statistics.median(a),
        "baseline_median_s": statistics.median(b),
        "ratio_median": statistics.median(a) / statistics.median(b),
        "ratio_best": min(a) / min(b),
    }


def generated_urdf(n_joints: int) -> str:
    """A tree of ``n_joints`` joints: chains of 10 revolute/continuous/prismatic/fixed joints."""
    types = ("revolute", "continuous", "prismatic", "fixed")
    links = ['<link name="l0"/>']
    joints = []
    for i in range(1, n_joints + 1):
        parent = 0 if i % 10 == 1 else i - 1
        kind = types[i % 4]
        limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
        links.append(f'<link name="l{i}"/>')
        joints.append(
            f'<joint name="j{i}" type="{kind}"><parent link="l{parent}"/>'
            f'<child link="l{i}"/><origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>'
            f"{limit if kind != 'fixed' else ''}</joint>"
        )
    return f'<robot name="gen{n_joints}">\n' + "\n".join(links + joints) + "\n</robot>\n"


def analysis_ratio(n_joints: int, repeat: int) -> dict[str, float]:
    """Best times of cspace's own work and of Pinocchio's parse on a generated URDF."""
    import pinocchio as pin

    from cspace._formats.shared.xmlio import parse_xml, source_from_bytes
    from cspace._formats.urdf.reader import read_urdf
    from cspace._model.adapter import record_of
    from cspace._model.analysis import analyse

    text = generated_urdf(n_joints)
    source = source_from_bytes("generated.urdf", text.encode())
    ours: list[float] = []
    theirs: list[float] = []
    for _ in range(repeat):
        start = time.perf_counter()
        model = pin.buildModelFromXML(text, mimic=True)
        theirs.append(time.perf_counter() - start)
        start = time.perf_counter()
        description = read_urdf(source.path, parse_xml(source), text).description
        report = analyse(source, "urdf", description, record_of(model), None)
        ours.append(time.perf_counter() - start)
    if len(report.joints) != n_joints:
        raise RuntimeError("the generated robot lost joints")
    return {
        "joints": n_joints,
        "cspace_analysis_best_s": min(ours),
        "pinocchio_parse_best_s": min(theirs),
        "ratio_best": min(ours) / min(theirs),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=21)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory():
        startup = startup_ratio(args.repeat)
        big = analysis_ratio(2000, max(3, args.repeat // 4))
        mjcf = startup_ratio(
            args.repeat, MJCF, f"import mujoco; mujoco.MjModel.from_xml_path({str(MJCF)!r})"
        )
    print(
        f"inspect arm7 vs pinocchio load: ratio {startup['ratio_median']:.2f} (median), "
        f"{startup['ratio_best']:.2f} (best); cspace {startup['cspace_median_s'] * 1e3:.0f} ms, "
        f"pinocchio {startup['baseline_median_s'] * 1e3:.0f} ms (median of {args.repeat})"
    )
    print(
        f"analysis of 2,000 joints vs pinocchio parse: ratio {big['ratio_best']:.2f}; "
        f"cspace {big['cspace_analysis_best_s'] * 1e3:.1f} ms, "
        f"pinocchio {big['pinocchio_parse_best_s'] * 1e3:.1f} ms (best of runs)"
    )
    print(
        f"inspect mjcf_every_joint vs mujoco load: ratio {mjcf['ratio_median']:.2f} (median), "
        f"{mjcf['ratio_best']:.2f} (best); cspace {mjcf['cspace_median_s'] * 1e3:.0f} ms, "
        f"mujoco {mjcf['baseline_median_s'] * 1e3:.0f} ms (median of {args.repeat})"
    )


if __name__ == "__main__":
    main()
