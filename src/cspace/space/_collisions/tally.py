"""The loop over samples of ``cspace collisions``: counts, witnesses, and each sample's part.

Samples are drawn uniformly in the canonical coordinates (`ConfigurationSpace.sample`)
in blocks of `SAMPLE_BLOCK`, block ``b`` from ``SeedSequence(seed, spawn_key=(b,))``,
so sample ``i`` is the same however the range is cut (between processes, too); each is
mapped to Pinocchio's q and checked pair by pair (`SelfCollision.colliding`). A
`Tally` keeps each pair's count and first witness, and for each sample whether the
file's matrix sees it free, the pairs in collision in it, a bit each (the pairs cspace's
own matrix checks are only known once every sample is seen) and the bin of each
coordinate it lies in.
"""

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from cspace._model._collision_pairs import SAMPLE_BLOCK, SelfCollision

BINS = 20
"""Bins of one coordinate's range, for the ranges that always collide."""

MAX_SAMPLES = 1_000_000
"""Most samples of one run."""

MAX_BIN_CELLS = 50_000_000
"""Most (sample, coordinate) bins a run keeps, a byte each: a run of many samples of a
robot of many joints looks for ranges that always collide in its first coordinates only
(10,000 samples: 5,000 coordinates)."""


class Sampler:
    """Seeded canonical samples of a robot and their Pinocchio q.

    Args:
        space: The robot's `ConfigurationSpace`.
        held: Bounds by coordinate name for its R^1 coordinates without finite limits
            (equal ends: the coordinate held, a free root's position), and narrower
            bounds for others (MoveIt's soft limits): samples and bins lie within them.
    """

    def __init__(self, space: Any, held: dict[str, tuple[float, float]]) -> None:
        self.space = space
        self.held = held
        self.to_q = space.conventions().to_pinocchio
        columns, low, width = [], [], []
        for k, c in enumerate(space.coordinates):
            if c.factor == "S^1":
                columns.append(k)
                low.append(-np.pi)
                width.append(2 * np.pi)
            elif c.factor == "R^1":
                lower, upper = held.get(c.name, (c.lower, c.upper))
                if np.isfinite(lower) and np.isfinite(upper) and upper > lower:
                    columns.append(k)
                    low.append(lower)
                    width.append(upper - lower)
        self.columns = np.array(columns, dtype=np.int64)
        self.low = np.array(low, dtype=float)
        self.width = np.array(width, dtype=float)

    def first(self, columns: int) -> "Sampler":
        """The same samples, with only the first ``columns`` binned coordinates binned."""
        other = Sampler.__new__(Sampler)
        other.space, other.held, other.to_q = self.space, self.held, self.to_q
        other.columns = self.columns[:columns]
        other.low, other.width = self.low[:columns], self.width[:columns]
        return other

    def block(self, seed: int, block: int) -> "npt.NDArray[np.float64]":
        """The canonical samples of block ``block`` of ``seed``, shape (SAMPLE_BLOCK, n)."""
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(block,)))
        x: npt.NDArray[np.float64] = self.space.sample(SAMPLE_BLOCK, rng, bounds=self.held)
        return x

    def bins(self, x: "npt.NDArray[np.float64]") -> "npt.NDArray[np.uint8]":
        """Each sample's bin of each binned coordinate (`columns`), shape (rows, columns)."""
        if not len(self.columns):
            return np.zeros((len(x), 0), dtype=np.uint8)
        where = (x[:, self.columns] - self.low) / self.width
        out: npt.NDArray[np.uint8] = np.clip(np.floor(where * BINS), 0, BINS - 1).astype(np.uint8)
        return out


class Tally:
    """What samples ``start`` to ``stop`` showed (see the module's docstring).

    Attributes:
        start: The first sample's index.
        counts: Each pair's samples in collision, by pair index.
        first: Each pair's first sample in collision: (index, canonical x).
        free: Per sample: no pair of the file's matrix collides.
        hits: Per sample, the pairs in collision, a bit each (``np.packbits`` of a row
            over the pairs): at most `MAX_CHECKS` bits in a run.
        bins: Per sample, its bin of each binned coordinate.
    """

    def __init__(self, start: int, pairs: int, columns: int) -> None:
        self.start = start
        self.counts = [0] * pairs
        self.first: dict[int, tuple[int, tuple[float, ...]]] = {}
        self.free: list[npt.NDArray[np.bool_]] = []
        self.hits: list[npt.NDArray[np.uint8]] = [np.zeros((0, -(-pairs // 8)), dtype=np.uint8)]
        self.bins: list[npt.NDArray[np.uint8]] = [np.zeros((0, columns), dtype=np.uint8)]

    def add(self, other: "Tally") -> None:
        """Take in the tally of the samples that follow this one's."""
        for k, c in enumerate(other.counts):
            self.counts[k] += c
        for k, w in other.first.items():
            self.first.setdefault(k, w)
        self.free += other.free
        self.hits += other.hits
        self.bins += other.bins

    def arrays(
        self,
    ) -> "tuple[npt.NDArray[np.bool_], npt.NDArray[np.uint8], npt.NDArray[np.uint8]]":
        """``free``, ``hits`` and ``bins`` as arrays over every sample."""
        free = np.concatenate(self.free) if self.free else np.zeros(0, dtype=bool)
        return free, np.concatenate(self.hits), np.concatenate(self.bins)


def tally(
    sampler: Sampler,
    engine: SelfCollision,
    checked: Sequence[bool],
    seed: int,
    start: int,
    stop: int,
    step: Callable[[int], None] | None = None,
) -> Tally:
    """Check samples ``start`` to ``stop`` (excluded) of ``seed``.

    Args:
        sampler: The robot's samples.
        engine: The checker of its pairs (`SelfCollision`), pair ``k`` its ``pairs[k]``.
        checked: Per pair: the file's matrix checks it.
        seed: The seed.
        start: The first sample's index.
        stop: One past the last.
        step: Called with the number of samples done after each block, or None.
    """
    pairs = len(engine.pairs)
    result = Tally(start, pairs, len(sampler.columns))
    seen_checked = {k for k, c in enumerate(checked) if c}
    for block in range(start // SAMPLE_BLOCK, -(-stop // SAMPLE_BLOCK)):
        base = block * SAMPLE_BLOCK
        x = sampler.block(seed, block)[max(start - base, 0) : min(stop - base, SAMPLE_BLOCK)]
        first_index = max(start, base)
        q = sampler.to_q(x)
        free = np.ones(len(x), dtype=bool)
        hits = np.zeros((len(x), pairs), dtype=bool)
        for row in range(len(x)):
            hit = engine.colliding(q[row])
            for k in hit:
                result.counts[k] += 1
                hits[row, k] = True
                if k not in result.first:
                    result.first[k] = (first_index + row, tuple(float(v) for v in x[row]))
            free[row] = not (hit & seen_checked)
        result.free.append(free)
        result.hits.append(np.packbits(hits, axis=1))
        result.bins.append(sampler.bins(x))
        if step is not None:
            step(len(x))
    return result
