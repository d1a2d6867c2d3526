"""Batch configuration operations against per-pair baselines, as ratios in one run.

Robot: talos_reduced from example-robot-data with a floating base (39 canonical
coordinates, Pinocchio nq = 39). N = 200,000 pairs of configurations, sampled uniformly
(the base position in [-2, 2]^3).

- cspace batch distance / interpolate (t uniform in [0, 1], one per pair) / canonicalize;
- Pinocchio per pair in a Python loop: ``pinocchio.distance``, ``pinocchio.interpolate``,
  ``pinocchio.normalize`` (measured on a subsample of ``--pin-pairs`` pairs and scaled to
  N, the loop's cost being linear);
- OMPL's Python bindings (the ``bench`` extra) per pair on the equivalent compound state
  space SE3 x R^32, with every state filled beforehand (not timed);
- one streaming pass over the same two arrays, ``np.einsum('ij,ij->i', A, B)``.

Targets (issues 3 and 14): each batch operation >= 10x the Pinocchio loop; batch
distance >= 3x OMPL; each operation against its streaming floor, the least memory
traffic it needs: distance <= 1.3x one pass over both inputs, interpolate <= 1.5x
``np.add(A, B, out=C)``, canonicalize <= 1.1x ``np.copyto(C, A)``, sample <= 2x drawing
its uniform numbers. The batch operations and the streaming passes are timed in turn,
round after round (so a busy machine slows them alike), and the best of ``--repeat``
rounds is kept. Interpolation and canonicalization are timed twice: writing into a new
array (its pages are fresh memory, which the kernel faults in) and into a reused one
(``out=``), as a planner's loop does.

``--load`` keeps one core busy with a process of its own meanwhile: two threads must
not be slower than one then (a helper that is not scheduled leaves its chunks).

Run: `.venv/bin/python bench/bench_configurations.py [--pairs N] [--repeat R] [--load]`.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np

import cspace
from cspace._formats.shared import erd


def interleaved(calls: dict[str, Callable[[], object]], rounds: int) -> dict[str, float]:
    """Best seconds of each call, timing them in turn, round after round."""
    times: dict[str, list[float]] = {name: [] for name in calls}
    for _ in range(rounds):
        for name, call in calls.items():
            start = time.perf_counter()
            call()
            times[name].append(time.perf_counter() - start)
    return {name: min(t) for name, t in times.items()}


def pinocchio_loops(
    path: str, qa: np.ndarray, qb: np.ndarray, t: np.ndarray
) -> dict[str, Callable[[], object]]:
    """Loops of pinocchio.distance / interpolate / normalize over (qa[i], qb[i], t[i])."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer(), "root_joint", mimic=True)
    if model.nq != qa.shape[1]:
        raise RuntimeError("Pinocchio's model does not match the configuration space")
    rows = list(zip(list(qa), list(qb), t.tolist(), strict=True))

    def loop(call: Callable[[np.ndarray, np.ndarray, float], object]) -> Callable[[], object]:
        def run() -> None:
            for a, b, s in rows:
                call(a, b, s)

        return run

    return {
        "distance": loop(lambda a, b, s: pin.distance(model, a, b)),
        "interpolate": loop(lambda a, b, s: pin.interpolate(model, a, b, s)),
        "canonicalize": loop(lambda a, b, s: pin.normalize(model, a)),
    }


def ompl_distance(a: np.ndarray, b: np.ndarray) -> Callable[[], object] | None:
    """A loop of OMPL's compound-space distance over all pairs, or None without OMPL."""
    try:
        from ompl import base as ob
    except ImportError:
        return None
    se3 = ob.SE3StateSpace()
    box = ob.RealVectorBounds(3)
    box.setLow(-2.0)
    box.setHigh(2.0)
    se3.setBounds(box)
    joints = ob.RealVectorStateSpace(a.shape[1] - 7)
    limits = ob.RealVectorBounds(a.shape[1] - 7)
    limits.setLow(-np.pi)
    limits.setHigh(np.pi)
    joints.setBounds(limits)
    space = ob.CompoundStateSpace()
    space.addSubspace(se3, 1.0)
    space.addSubspace(joints, 1.0)
    space.setup()

    def states(x: np.ndarray) -> list[object]:
        # OMPL's SE3 reals: x, y, z, then the quaternion as (x, y, z, w)
        reals = np.concatenate((x[:, :3], x[:, 4:7], x[:, 3:4], x[:, 7:]), axis=1)
        out = []
        for row in reals.tolist():
            s = space.allocState()
            space.copyFromReals(s, row)
            out.append(s)
        return out

    pairs = list(zip(states(a), states(b), strict=True))
    distance = space.distance

    def run() -> None:
        for s, t in pairs:
            distance(s, t)

    return run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--pairs", type=int, default=200_000)
    parser.add_argument("--repeat", type=int, default=25)
    parser.add_argument("--pin-pairs", type=int, default=20_000)
    parser.add_argument(
        "--load", action="store_true", help="keep one core busy with another process meanwhile"
    )
    args = parser.parse_args()
    if args.load:
        import atexit
        import subprocess
        import sys

        busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
        atexit.register(busy.kill)
    n = args.pairs
    path = str(erd.robots_dir() / "talos_data/robots/talos_reduced.urdf")
    space = cspace.load(path, root_joint="floating")
    rng = np.random.default_rng(0)
    box = {f"root_joint.{c}": (-2.0, 2.0) for c in "xyz"}
    a = space.sample(n, rng, box)
    b = space.sample(n, rng, box)
    t = rng.uniform(0.0, 1.0, n)
    raw = a.copy()
    raw[:, 3:7] *= -1.0  # canonicalize sees the other hemisphere
    out = np.empty(n)
    buffer = np.empty_like(a)
    sampler = np.random.default_rng(1)
    draws = np.empty((n, space.layout.draws))
    calls: dict[str, Callable[[], object]] = {
        "distance": lambda: space.distance(a, b, out=out),
        "interpolate": lambda: space.interpolate(a, b, t),
        "interpolate_out": lambda: space.interpolate(a, b, t, out=buffer),
        "canonicalize": lambda: space.canonicalize(raw),
        "canonicalize_out": lambda: space.canonicalize(raw, out=buffer),
        "stream": lambda: np.einsum("ij,ij->i", a, b, out=out),
        "floor_interpolate": lambda: np.add(a, b, out=buffer),
        "floor_canonicalize": lambda: np.copyto(buffer, raw),
        "sample": lambda: space.sample(n, sampler, box),
        "floor_sample": lambda: sampler.random(out=draws),
    }
    m = min(args.pin_pairs, n)
    pin_loops = pinocchio_loops(path, space.to_pinocchio(a[:m]), space.to_pinocchio(b[:m]), t[:m])
    calls.update({f"pinocchio_{name}": loop for name, loop in pin_loops.items()})
    ompl = ompl_distance(a, b)
    if ompl is not None:
        calls["ompl"] = ompl
    for call in calls.values():
        call()  # load the compiled kernels and start numba's threads before timing
    ours = interleaved(calls, args.repeat)
    stream = ours.pop("stream")
    floors = {name: ours.pop(f"floor_{name}") for name in ("interpolate", "canonicalize", "sample")}
    sampled = ours.pop("sample")
    ompl_seconds = ours.pop("ompl", None)
    per_pair = {name: ours.pop(f"pinocchio_{name}") / m for name in pin_loops}

    print(f"talos_reduced + floating base: {space.size} coordinates, nq {space.nq}, N = {n:,}")
    for name, seconds in ours.items():
        pin_total = per_pair[name.removesuffix("_out")] * n
        print(
            f"{name:>16}: cspace {seconds * 1e3:6.1f} ms | pinocchio loop "
            f"{pin_total * 1e3:5.0f} ms (scaled from {m:,} pairs) | ratio "
            f"{pin_total / seconds:5.1f}x (target >= 10x)"
        )
    print(
        f"distance vs one streaming pass np.einsum('ij,ij->i', A, B): {stream * 1e3:.1f} ms | "
        f"ratio {ours['distance'] / stream:.2f} (target <= 1.3)"
    )
    for name, target, what in (
        ("interpolate_out", 1.5, "np.add(A, B, out=C): read two arrays, write one"),
        ("canonicalize_out", 1.1, "np.copyto(C, A): read one array, write one"),
    ):
        floor = floors[name.removesuffix("_out")]
        print(
            f"{name} vs its floor {what}: {floor * 1e3:.1f} ms | ratio "
            f"{ours[name] / floor:.2f} (target <= {target})"
        )
    print(
        f"sample {sampled * 1e3:.1f} ms vs its floor rng.random(out=U), the uniform numbers "
        f"it draws: {floors['sample'] * 1e3:.1f} ms | ratio {sampled / floors['sample']:.2f} "
        "(target <= 2)"
    )
    if ompl_seconds is None:
        print("OMPL not installed (pip install -e '.[bench]'): no OMPL ratio")
    else:
        print(
            f"distance vs OMPL compound SE3 x R^{space.size - 7}, per pair: "
            f"{ompl_seconds * 1e3:.0f} ms | ratio {ompl_seconds / ours['distance']:.1f}x "
            "(target >= 3x)"
        )


if __name__ == "__main__":
    main()
