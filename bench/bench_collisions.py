"""Benchmark of the self-collision engine against a plain Pinocchio loop, as a ratio.

The CPU time of `SelfCollision.count` (samples drawn in blocks, each pair's count and
first witness kept) on example-robot-data's panda and UR5, meshes read by cspace's
readers, against a plain loop of ``pin.computeCollisions`` over the same
configurations and the same pairs of shapes (adjacent pairs left out as MoveIt leaves
them out), in one process. Target: ratio <= 1.5.

Run: `.venv/bin/python bench/bench_collisions.py [--samples N] [--repeat N]`.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import pinocchio as pin

import cspace
from cspace._formats.detect import detect
from cspace._formats.shared.description import RobotDescription
from cspace._formats.shared.erd import robots_dir
from cspace._formats.shared.reading import ReadRequest, read
from cspace._formats.shared.xmlio import ReadBudget, parse_xml, read_source
from cspace._model._collision_meshes import read_shape_meshes
from cspace._model._collision_pairs import SelfCollision, adjacent_pairs, link_pairs, samples
from cspace._model._collision_shapes import build_shapes

ERD = robots_dir()
ROBOTS = {
    "panda": ERD / "panda_description" / "urdf" / "panda.urdf",
    "ur5": ERD / "ur_description" / "urdf" / "ur5_robot.urdf",
}
PACKAGES = {"example-robot-data": str(ERD.parent)}


def _describe(path: str) -> RobotDescription:
    source = read_source(path)
    budget = ReadBudget(source.path)
    budget.charge(source)
    root = parse_xml(source)
    row = detect(source.path, root, force_xacro=False, data=source.data)
    return read(row, ReadRequest(source.path, source, root, path, budget)).description


def _engine(name: str) -> SelfCollision:
    path = str(ROBOTS[name])
    description = _describe(path)
    model = cspace.pinocchio_model(path)
    found = read_shape_meshes(description.links, path, PACKAGES)
    shapes = build_shapes(model, description.links, found.meshes)
    edges = [(j.parent, j.child) for j in description.joints]
    adjacent = adjacent_pairs(shapes.with_geometry, edges)
    pairs = [p for p in link_pairs(shapes.with_geometry) if p not in adjacent]
    return SelfCollision(model, shapes, pairs)


def _measure(engine: SelfCollision, n: int) -> tuple[float, float]:
    start = time.process_time()
    engine.count(0, n)
    ours = time.process_time() - start
    qs = samples(engine.model, 0, 0, n)
    data = engine.model.createData()
    geometry_data = pin.GeometryData(engine.geometry)
    start = time.process_time()
    for q in qs:
        pin.computeCollisions(engine.model, data, engine.geometry, geometry_data, q, False)
    return ours, time.process_time() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    results = {}
    for name in ROBOTS:
        engine = _engine(name)
        runs = [_measure(engine, args.samples) for _ in range(args.repeat)]
        results[name] = {
            "samples": args.samples,
            "shape_pairs": len(engine.geometry.collisionPairs),
            "cpu_seconds": statistics.median(r[0] for r in runs),
            "baseline_cpu_seconds": statistics.median(r[1] for r in runs),
            "ratio": statistics.median(r[0] / r[1] for r in runs),
        }
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
