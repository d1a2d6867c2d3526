"""Benchmarks of what is read beside the robot file, as ratios in one run.

1. ``--limits``: the wall time of ``cspace inspect panda.urdf --limits
   tests/limits/panda_joint_limits.yaml`` (example-robot-data's panda, MoveIt Setup
   Assistant's joint_limits.yaml with moveit_resources' values: PyYAML imported, the
   file read and applied) against ``cspace inspect panda.urdf``, run alternately.
   Target: ratio <= 1.3.
2. The YAML loader at its bound, for information: the CPU time of `cspace.inspect`
   with ``limits=`` a joint_limits.yaml of 255 KiB (the panda's joints, then thousands
   of others, with velocity and acceleration limits) against the same call with the
   panda's own file, in one process.
3. ``<ros2_control>``: the wall time of ``cspace inspect`` on
   tests/ros2_control/arm.urdf against the same file with its ``<ros2_control>``
   elements removed. Target: ratio <= 1.2.
4. The conventions beside: ``cspace convert --to pybullet`` and ``--to mujoco-ctrl``
   of 1,000 configurations against ``--to drake`` and ``--to mujoco`` of the same rows
   (PyBullet's vectors are a Drake layout; ctrl is a map of qpos). Target: ratio <= 1.2.

Run: `.venv/bin/python bench/bench_beside.py [--repeat N]`, with ``OMP_NUM_THREADS``,
``OPENBLAS_NUM_THREADS`` and ``NUMBA_NUM_THREADS`` set to 1 and to 2 (the figures in
docs/benchmarks.md).
"""

from __future__ import annotations

import argparse
import json
import re
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import cspace
from cspace._formats.shared.erd import robots_dir

REPO = Path(__file__).resolve().parent.parent
CSPACE = str(Path(sys.executable).with_name("cspace"))
PANDA_LIMITS = REPO / "tests" / "limits" / "panda_joint_limits.yaml"
ARM = REPO / "tests" / "ros2_control" / "arm.urdf"
SERVO = REPO / "tests" / "actuators" / "servo_arm.xml"


def _wall(command: list[str]) -> float:
    start = time.perf_counter()
    done = subprocess.run(command, check=False, stdout=subprocess.DEVNULL)
    seconds = time.perf_counter() - start
    if done.returncode not in (0, 1):  # 1: findings (warnings with --strict, errors)
        raise SystemExit(f"{' '.join(command)} failed with exit code {done.returncode}")
    return seconds


def _paired(a: list[str], b: list[str], repeat: int) -> dict[str, float]:
    """Median wall seconds of ``a`` and ``b`` run alternately, and the median ratio."""
    _wall(a), _wall(b)  # warm the page cache and MuJoCo's compile cache
    ratios, times_a, times_b = [], [], []
    for _ in range(repeat):
        ta, tb = _wall(a), _wall(b)
        times_a.append(ta)
        times_b.append(tb)
        ratios.append(ta / tb)
    return {
        "seconds": statistics.median(times_a),
        "baseline_seconds": statistics.median(times_b),
        "ratio": statistics.median(ratios),
    }


def _cpu(call: Callable[[], object], repeat: int) -> float:
    out = []
    for _ in range(repeat):
        start = time.process_time()
        call()
        out.append(time.process_time() - start)
    return statistics.median(out)


def _big_limits(folder: Path, robot: Path) -> Path:
    """A joint_limits.yaml near its 256 KiB bound: the panda's joints, then about 2,000 more."""
    lines = ["joint_limits:"]
    names = [f"panda_joint{i}" for i in range(1, 8)] + [f"extra_joint_{i}" for i in range(5000)]
    for name in names:
        lines += [
            f"  {name}:",
            "    has_velocity_limits: true",
            "    max_velocity: 2.0",
            "    has_acceleration_limits: true",
            "    max_acceleration: 3.0",
        ]
    text = "\n".join(lines) + "\n"
    path = folder / "joint_limits.yaml"
    path.write_text(text[: 255 * 1024].rsplit("\n  ", 1)[0] + "\n")
    return path


def _rows(folder: Path, robot: Path, count: int) -> Path:
    """``count`` seeded configurations of ``robot`` as canonical CSV."""
    space = cspace.load(robot)
    samples = space.sample(count, np.random.default_rng(7))
    path = folder / f"{robot.stem}.csv"
    header = ",".join(space.names)
    body = "\n".join(",".join(repr(float(x)) for x in row) for row in samples)
    path.write_text(header + "\n" + body + "\n")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=11)
    args = parser.parse_args()
    panda = robots_dir() / "panda_description" / "urdf" / "panda.urdf"
    out: dict[str, object] = {}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        out["limits"] = _paired(
            [CSPACE, "inspect", str(panda), "--limits", str(PANDA_LIMITS)],
            [CSPACE, "inspect", str(panda)],
            args.repeat,
        )
        big = _big_limits(folder, panda)
        with_big = _cpu(lambda: cspace.inspect(panda, limits=big), 3)
        plain = _cpu(lambda: cspace.inspect(panda, limits=PANDA_LIMITS), 3)
        out["limits_at_bound_cpu"] = {
            "bytes": big.stat().st_size,
            "seconds": with_big,
            "baseline_seconds": plain,
        }
        bare = folder / "arm_bare.urdf"
        text = ARM.read_text()
        bare.write_text(re.sub(r"<ros2_control\b.*?</ros2_control>", "", text, flags=re.S))
        out["ros2_control"] = _paired(
            [CSPACE, "inspect", str(ARM)], [CSPACE, "inspect", str(bare)], args.repeat
        )
        rows = _rows(folder, panda, 1000)
        convert = [CSPACE, "convert", str(panda), str(rows), "--from", "canonical", "--to"]
        out["pybullet"] = _paired([*convert, "pybullet"], [*convert, "drake"], args.repeat)
        servo_rows = _rows(folder, SERVO, 1000)
        convert = [CSPACE, "convert", str(SERVO), str(servo_rows), "--from", "canonical", "--to"]
        out["mujoco_ctrl"] = _paired([*convert, "mujoco-ctrl"], [*convert, "mujoco"], args.repeat)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
