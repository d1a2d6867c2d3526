"""Conversion throughput between conventions, as ratios against cspace's own kernel.

Robot: talos_reduced from example-robot-data with a floating base (39 canonical
coordinates; Pinocchio's q 39, MuJoCo's qpos 39, Drake's q 39). MuJoCo's layout is
built here (the URDF's meshes are not MuJoCo's to load): the free joint first, then
every hinge, in Pinocchio's order.
N = 1,000,000 configurations, sampled uniformly (the base position in [-2, 2]^3), each
stored in every convention beforehand.

For every ordered pair of conventions (canonical, pinocchio, mujoco, drake), the time of
``conventions.convert(values, source, target)`` on the N configurations, and its ratio
to ``space.canonicalize`` of the same N canonical configurations, the compiled kernel
that every conversion ends or starts in (one read and one write of the array: the least
a conversion can do). Velocities likewise for each tool to and from the canonical
tangent, at the N configurations. Timed in turn, round after round, the best of
``--repeat`` rounds (9) kept; ``--threads`` sets numba's threads (1 or 2 on these machines).

Run: `.venv/bin/python bench/bench_conventions.py [--n N] [--repeat R] [--threads T]`.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

import numba
import numpy as np
from bench_configurations import interleaved  # this folder is on the path of its scripts

import cspace
from cspace._formats.shared import erd
from cspace.conventions import TOOLS, MujocoJoint, MujocoLayout


def mujoco_layout(space: cspace.ConfigurationSpace) -> MujocoLayout:
    """The free joint first, then every hinge (in Pinocchio's order), as MuJoCo lays them."""
    joints = [MujocoJoint("root_joint", "free", 0, 0)]
    nq, nv = 7, 6
    for joint in space.report_joints:
        if joint.name != "root_joint" and joint.q_index is not None:
            joints.append(MujocoJoint(joint.name, "hinge", nq, nv))
            nq, nv = nq + 1, nv + 1
    return MujocoLayout(tuple(joints), nq, nv)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=9)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    numba.set_num_threads(args.threads)
    path = str(erd.robots_dir() / "talos_data/robots/talos_reduced.urdf")
    space = cspace.load(path, root_joint="floating")
    conventions = space.conventions(mujoco=mujoco_layout(space))
    rng = np.random.default_rng(0)
    box = {f"root_joint.{c}": (-2.0, 2.0) for c in "xyz"}
    x = space.sample(args.n, rng, box)
    dx = rng.normal(size=(args.n, space.dimension))
    tools = list(TOOLS)
    stored = {tool: conventions.from_canonical(x, tool) for tool in tools}
    velocities = {
        tool: conventions.convert(dx, "canonical", tool, velocity=True, at=x) for tool in tools
    }
    calls: dict[str, Callable[[], object]] = {"kernel": lambda: space.canonicalize(x)}
    for source in tools:
        for target in tools:
            calls[f"{source} -> {target}"] = lambda s=source, t=target: conventions.convert(
                stored[s], s, t
            )
    for tool in tools[1:]:
        calls[f"v canonical -> {tool}"] = lambda t=tool: conventions.convert(
            dx, "canonical", t, velocity=True, at=x
        )
        calls[f"v {tool} -> canonical"] = lambda t=tool: conventions.convert(
            velocities[t], t, "canonical", velocity=True, at=x
        )
    for call in calls.values():
        call()  # load the compiled kernels and start numba's threads before timing
    best = interleaved(calls, args.repeat)
    kernel = best.pop("kernel")
    print(
        f"talos_reduced + floating base: {space.size} coordinates, N = {args.n:,}, "
        f"{args.threads} thread(s); canonicalize (the kernel) {kernel * 1e3:.0f} ms, "
        f"{args.n / kernel / 1e6:.1f} M/s"
    )
    for name, seconds in best.items():
        print(
            f"{name:>24}: {seconds * 1e3:7.0f} ms  {args.n / seconds / 1e6:6.2f} M/s  "
            f"ratio to the kernel {seconds / kernel:5.1f}"
        )


if __name__ == "__main__":
    main()
