"""Which link pairs of a robot collide: MoveIt's classes, over seeded samples.

The setup assistant of MoveIt sorts the pairs of links that have collision geometry
(names sorted, ``link1 < link2``) in this order, a pair keeping its first class:
*adjacent* (joined by a joint, looked through links with no geometry, `adjacent_pairs`),
*default* (in collision at the default configuration, `default_configuration`), then by
random samples. Here the samples are seeded and reproducible: `samples` draws them in
fixed blocks of `SAMPLE_BLOCK`, block ``b`` from ``SeedSequence(seed, spawn_key=(b,))``,
so sample ``i`` is the same however the range is cut into chunks. `SelfCollision`
checks each sample with coal through Pinocchio (``computeCollisions`` over the pairs,
results read only for a sample in collision) and keeps each pair's count and the first
sample that collides.
"""

from collections.abc import Collection, Iterable, Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from cspace._model._collision_shapes import Shapes
from cspace._record import NamedTuple

SAMPLE_BLOCK = 1000
"""Samples a block draws from its own seed sequence."""

MAX_SHAPE_PAIRS = 250_000
"""Most pairs of shapes checked at each sample: about 0.25 s a sample at 1 us a pair.
Talos, the largest robot of example-robot-data, has 1,326."""

MAX_DOFS = 200
"""Most degrees of freedom (Pinocchio's ``nv``) of a robot cspace checks for self-collision.
Pinocchio's ``Data``, which its kinematics need, holds four nv-by-nv-by-nv tensors (its
second-order derivatives), whatever the tree: 32 nv^3 bytes, 256 MB at 200, 2.1 GB at 400
and 11 GB at 700 (measured). example-robot-data's talos has 38, romeo 61."""

NO_BOUND = 1e9
"""A limit this large or larger (or not a number) is no bound: Pinocchio's default limits
are the largest floats, and a range that wide is not sampled."""

LinkPair = tuple[str, str]
"""Two link names, sorted."""


def link_pair(a: str, b: str) -> LinkPair:
    """The pair of links ``a`` and ``b``, names sorted as MoveIt writes them."""
    return (a, b) if a < b else (b, a)


def adjacent_pairs(with_geometry: Iterable[str], edges: Iterable[tuple[str, str]]) -> set[LinkPair]:
    """MoveIt's adjacent pairs: joined by a joint, looking through links with no geometry.

    An undirected graph has one edge a joint (parent, child), of every type. Each link
    with no geometry joins all its neighbours to each other, until nothing changes; the
    edges whose ends both have geometry are the adjacent pairs.

    Args:
        with_geometry: The links that have collision geometry.
        edges: Each joint's (parent link, child link).
    """
    solid = set(with_geometry)
    neighbours: dict[str, set[str]] = {}
    for parent, child in edges:
        if parent == child:
            continue
        neighbours.setdefault(parent, set()).add(child)
        neighbours.setdefault(child, set()).add(parent)
    hollow = [link for link in neighbours if link not in solid]
    changed = True
    while changed:
        changed = False
        for link in hollow:
            around = neighbours[link]
            for a in around:
                extra = around - neighbours[a] - {a}
                if extra:
                    neighbours[a] |= extra
                    changed = True
    return {link_pair(a, b) for a in solid for b in neighbours.get(a, ()) if b in solid and a != b}


class _Plan(NamedTuple):
    """How a sample fills q: the columns drawn and what each becomes."""

    neutral: "npt.NDArray[np.float64]"
    bounded: "npt.NDArray[np.int64]"  # q indices drawn uniform in [low, high]
    low: "npt.NDArray[np.float64]"
    high: "npt.NDArray[np.float64]"
    circles: "npt.NDArray[np.int64]"  # q indices of (cos, sin) pairs, angle in [-pi, pi)
    balls: "npt.NDArray[np.int64]"  # q indices of (x, y, z, w) quaternions, uniform on SO(3)


def _plan(model: Any, bounds: "Mapping[str, tuple[float, float]] | None" = None) -> _Plan:
    """How samples fill q; ``bounds`` replace some 1-DoF joints' limits, by joint name."""
    neutral = np.array(_neutral(model), dtype=float)
    bounded: list[int] = []
    circles: list[int] = []
    balls: list[int] = []
    low: list[float] = []
    high: list[float] = []
    for joint in list(model.joints)[1:]:
        lo = float(model.lowerPositionLimit[joint.idx_q]) if joint.nq else 0.0
        hi = float(model.upperPositionLimit[joint.idx_q]) if joint.nq else 0.0
        if joint.nq == 1 and bounds is not None and model.names[joint.id] in bounds:
            lo, hi = bounds[model.names[joint.id]]
        if joint.nq == 1 and joint.shortname().startswith("JointModelR"):
            # a revolute joint without a bound turns all round on that side
            lo = lo if abs(lo) < NO_BOUND else -np.pi
            hi = hi if abs(hi) < NO_BOUND else np.pi
        if joint.nq == 1 and abs(lo) < NO_BOUND and abs(hi) < NO_BOUND and lo <= hi:
            bounded.append(joint.idx_q)
            low.append(lo)
            high.append(hi)
        elif joint.nq == 2 and joint.nv == 1:
            circles.append(joint.idx_q)
        elif joint.nq == 4 and joint.nv == 3:
            balls.append(joint.idx_q)
        # other joints (free, planar, unbounded prismatic, ...) keep their neutral value:
        # the root's pose does not change which links collide
    return _Plan(
        neutral,
        np.array(bounded, dtype=np.int64),
        np.array(low, dtype=float),
        np.array(high, dtype=float),
        np.array(circles, dtype=np.int64),
        np.array(balls, dtype=np.int64),
    )


def _neutral(model: Any) -> "npt.NDArray[np.float64]":
    import pinocchio as pin

    return np.asarray(pin.neutral(model), dtype=float)


def default_configuration(
    model: Any, bounds: "Mapping[str, tuple[float, float]] | None" = None
) -> "npt.NDArray[np.float64]":
    """MoveIt's default configuration: each 1-DoF joint at 0, or mid-range when 0 is outside.

    Other joints are at Pinocchio's neutral (a continuous joint at angle 0); a mimic
    joint follows its leader, as MoveIt's ``updateMimicJoints`` places it.

    Args:
        model: The ``pin.Model``.
        bounds: (lower, upper) of some 1-DoF joints by name, in place of the model's
            limits: the bounds MoveIt's robot model gives them
            (`cspace.space._collisions.setup.moveit_limits`).
    """
    plan = _plan(model, bounds)
    q = plan.neutral.copy()
    middle = (plan.low + plan.high) / 2
    inside = (plan.low <= 0.0) & (plan.high >= 0.0)
    q[plan.bounded] = np.where(inside, 0.0, middle)
    return q


def _block(plan: _Plan, seed: int, block: int) -> "npt.NDArray[np.float64]":
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(block,)))
    nb, nc = len(plan.bounded), len(plan.circles)
    draws = rng.random((SAMPLE_BLOCK, nb + nc + 3 * len(plan.balls)))
    q = np.tile(plan.neutral, (SAMPLE_BLOCK, 1))
    q[:, plan.bounded] = plan.low + (plan.high - plan.low) * draws[:, :nb]
    angle = np.pi * (2.0 * draws[:, nb : nb + nc] - 1.0)
    q[:, plan.circles] = np.cos(angle)
    q[:, plan.circles + 1] = np.sin(angle)
    # Shoemake's uniform unit quaternion from three uniform numbers
    u = draws[:, nb + nc :].reshape(SAMPLE_BLOCK, len(plan.balls), 3)
    r1, r2 = np.sqrt(1.0 - u[..., 0]), np.sqrt(u[..., 0])
    t1, t2 = 2.0 * np.pi * u[..., 1], 2.0 * np.pi * u[..., 2]
    for k, value in enumerate((r1 * np.sin(t1), r1 * np.cos(t1), r2 * np.sin(t2), r2 * np.cos(t2))):
        q[:, plan.balls + k] = value
    return q


def samples(model: Any, seed: int, start: int, stop: int) -> "npt.NDArray[np.float64]":
    """Samples ``start`` to ``stop`` (excluded) of ``seed``, one q a row.

    Each bounded 1-DoF coordinate is uniform in its limits (a revolute joint's missing
    bound -pi or pi), each continuous joint's angle uniform in [-pi, pi), each ball
    joint's rotation uniform on SO(3); other joints (a free or planar root, a prismatic
    joint without both bounds) keep their neutral value.
    """
    return _samples(_plan(model), seed, start, stop)


def _samples(plan: _Plan, seed: int, start: int, stop: int) -> "npt.NDArray[np.float64]":
    rows = []
    for block in range(start // SAMPLE_BLOCK, -(-stop // SAMPLE_BLOCK)):
        base = block * SAMPLE_BLOCK
        q = _block(plan, seed, block)
        rows.append(q[max(start - base, 0) : min(stop - base, SAMPLE_BLOCK)])
    if not rows:
        return np.empty((0, len(plan.neutral)))
    return np.concatenate(rows)


class PairCount(NamedTuple):
    """How often one pair of links collides over the samples.

    Attributes:
        pair: The two links, sorted.
        hits: Samples in which they collide.
        witness: The first such sample's index and q, or None.
    """

    pair: LinkPair
    hits: int
    witness: "tuple[int, tuple[float, ...]] | None"


class SelfCollision:
    """Checks given link pairs of a robot, shape against shape, at configurations.

    Args:
        model: The ``pin.Model``.
        shapes: Its collision shapes (`build_shapes`).
        pairs: The link pairs to check (each shape of one against each of the other);
            a link against itself is never checked, as in MoveIt.
        only: For some of ``pairs``, the only pairs of shapes (object indices of
            ``shapes.geometry``) to check: MuJoCo's filters decide geom by geom.

    Raises:
        ValueError: The pairs hold more than `MAX_SHAPE_PAIRS` pairs of shapes.
    """

    def __init__(
        self,
        model: Any,
        shapes: Shapes,
        pairs: Sequence[LinkPair],
        only: "Mapping[LinkPair, Collection[tuple[int, int]]] | None" = None,
    ) -> None:
        import pinocchio as pin

        self.model = model
        self._plan = _plan(model)
        self.pairs = tuple(dict.fromkeys(link_pair(*p) for p in pairs if p[0] != p[1]))
        of_link: dict[str, list[int]] = {}
        for i, link in enumerate(shapes.links):
            of_link.setdefault(link, []).append(i)
        total = sum(len(of_link.get(a, ())) * len(of_link.get(b, ())) for a, b in self.pairs)
        if total > MAX_SHAPE_PAIRS:
            raise ValueError(
                f"{total:,} pairs of collision shapes to check, more than the "
                f"{MAX_SHAPE_PAIRS:,} cspace checks for one robot"
            )
        self.geometry = shapes.geometry.copy()
        owner: list[int] = []
        for which, (a, b) in enumerate(self.pairs):
            chosen = None if only is None else only.get((a, b))
            for i in of_link.get(a, ()):
                for j in of_link.get(b, ()):
                    if chosen is not None and (min(i, j), max(i, j)) not in chosen:
                        continue
                    self.geometry.addCollisionPair(pin.CollisionPair(min(i, j), max(i, j)))
                    owner.append(which)
        self._owner = owner
        self._data = model.createData()
        self._geometry_data = pin.GeometryData(self.geometry)
        for request in self._geometry_data.collisionRequests:
            # Pinocchio's default request starts GJK from the previous call's guess and
            # stops at a boolean answer; coal 3 then misses some overlaps (a capsule 21 mm
            # into a box), and an answer depends on the configuration checked before it.
            # From the default guess, with the contact computed, every sample is checked
            # alone, and none of 420,000 checks against FCL was missed.
            request.enable_contact = True
            request.gjk_initial_guess = pin.coal.GJKInitialGuess.DefaultGuess

    def colliding(self, q: "npt.NDArray[np.float64]") -> set[int]:
        """The indices in `pairs` of the link pairs in collision at ``q``."""
        import pinocchio as pin

        data = self._geometry_data
        if not pin.computeCollisions(self.model, self._data, self.geometry, data, q, False):
            return set()
        results = data.collisionResults
        return {owner for k, owner in enumerate(self._owner) if results[k].isCollision()}

    def count(self, seed: int, n: int, *, chunk: int = SAMPLE_BLOCK) -> list[PairCount]:
        """Each pair's count over samples 0 to ``n`` of ``seed``, and its first witness.

        ``chunk`` is how many samples are drawn at once; the result does not depend on it.
        """
        counts = [0] * len(self.pairs)
        first: dict[int, tuple[int, tuple[float, ...]]] = {}
        for start in range(0, n, max(chunk, 1)):
            qs = _samples(self._plan, seed, start, min(start + chunk, n))
            for offset, q in enumerate(qs):
                for which in self.colliding(q):
                    counts[which] += 1
                    if which not in first:
                        first[which] = (start + offset, tuple(float(v) for v in q))
        return [PairCount(p, counts[i], first.get(i)) for i, p in enumerate(self.pairs)]


def link_pairs(with_geometry: Sequence[str]) -> list[LinkPair]:
    """Every pair of the links with geometry, sorted."""
    return sorted(
        {link_pair(a, b) for i, a in enumerate(with_geometry) for b in with_geometry[i + 1 :]}
    )
