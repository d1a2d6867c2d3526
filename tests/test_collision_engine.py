"""The self-collision engine: shapes built by hand, MoveIt's pair classes, seeded counts.

The shapes are the readers' `CollisionSpec`s with their meshes read by cspace's own
readers, on the model cspace builds; the oracle is Pinocchio's own pipeline on the
same files (``buildModelFromUrdf`` + ``buildGeomFromUrdf``, meshes loaded by assimp) and
``computeCollisions``, pair by pair and sample by sample. Adjacency and the default pose
are held to the SRDF MoveIt's setup assistant wrote for the panda, and the confidence
bounds to scipy.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
import scipy.stats
from test_collision_geometry import SRDFS, URDFS, describe

import cspace
from cspace._formats.shared.description import CollisionSpec, LinkSpec, RobotDescription
from cspace._formats.shared.erd import robots_dir
from cspace._formats.shared.xmlio import read_source
from cspace._formats.srdf.reader import parse_srdf
from cspace._model._collision_meshes import ShapeProblem, read_shape_meshes
from cspace._model._collision_pairs import (
    SAMPLE_BLOCK,
    SelfCollision,
    adjacent_pairs,
    default_configuration,
    link_pair,
    link_pairs,
    samples,
)
from cspace._model._collision_shapes import Shapes, build_shapes
from cspace._model._collision_stats import clopper_pearson_upper, wilson

ERD = robots_dir()
SHARE = ERD.parent.parent
PACKAGES = {"example-robot-data": str(ERD.parent)}


class Robot:
    """A robot file's model, shapes and the engine over its non-adjacent pairs."""

    def __init__(self, path: Path) -> None:
        self.description: RobotDescription = describe(path)
        self.model: Any = cspace.pinocchio_model(str(path))
        self.shapes: Shapes = build_shapes(self.model, self.description.links, _meshes(path))
        edges = [(j.parent, j.child) for j in self.description.joints]
        self.adjacent = adjacent_pairs(self.shapes.with_geometry, edges)
        pairs = [p for p in link_pairs(self.shapes.with_geometry) if p not in self.adjacent]
        self.engine = SelfCollision(self.model, self.shapes, pairs)


def _meshes(path: Path) -> dict[Any, Any]:
    """Every mesh shape's mesh, read by cspace's readers (in their confined child)."""
    found = read_shape_meshes(describe(path).links, str(path), PACKAGES)
    assert found.problems == ()
    return found.meshes


@pytest.fixture(scope="module", params=["panda", "ur5"])
def robot(request: pytest.FixtureRequest) -> Robot:
    return Robot(URDFS[request.param])


@pytest.fixture(scope="module")
def panda() -> Robot:
    return Robot(URDFS["panda"])


def _oracle(path: Path, robot: Robot) -> tuple[Any, Any, Any, Any, list[tuple[str, str]]]:
    """Pinocchio's own model and geometry of ``path`` (assimp), with the same link pairs."""
    model = pin.buildModelFromUrdf(str(path), mimic=True)  # as cspace keeps mimic joints
    geometry = pin.buildGeomFromUrdf(model, str(path), pin.COLLISION, package_dirs=[str(SHARE)])
    links = [model.frames[g.parentFrame].name for g in geometry.geometryObjects]
    wanted = set(robot.engine.pairs)
    owners = []
    for i in range(len(links)):
        for j in range(i + 1, len(links)):
            pair = link_pair(links[i], links[j])
            if pair in wanted:
                geometry.addCollisionPair(pin.CollisionPair(i, j))
                owners.append(pair)
    return model, model.createData(), geometry, pin.GeometryData(geometry), owners


@pytest.mark.parametrize("name", ["panda", "ur5", "talos"])
def test_collisions_are_pinocchios_sample_by_sample(name: str) -> None:
    """talos_reduced: 52 links with meshes, 1,248 pairs of them not adjacent."""
    robot = Robot(URDFS[name])
    model, data, geometry, geometry_data, owners = _oracle(URDFS[name], robot)
    assert list(model.names) == list(robot.model.names)
    assert len(geometry.geometryObjects) == len(robot.shapes.links)
    seen = 0
    qs = samples(robot.model, 7, 0, 100 if name == "talos" else 300)
    for q in qs:
        pin.computeCollisions(model, data, geometry, geometry_data, q, False)
        expected = {
            owners[k] for k, r in enumerate(geometry_data.collisionResults) if r.isCollision()
        }
        ours = {robot.engine.pairs[i] for i in robot.engine.colliding(q)}
        assert ours == expected, q
        seen += len(ours)
    assert seen >= 30  # collisions were there to be found


def test_adjacent_pairs_are_the_setup_assistants(panda: Robot) -> None:
    srdf = parse_srdf(read_source(str(SRDFS["panda"])))
    adjacent = {link_pair(p.link1, p.link2) for p in srdf.collision_pairs if p.reason == "Adjacent"}
    assert len(adjacent) == 10
    assert panda.adjacent == adjacent
    assert ("panda_hand", "panda_link7") in adjacent  # through panda_link8, with no geometry
    assert ("panda_leftfinger", "panda_rightfinger") not in adjacent  # siblings


def test_default_pose_pairs_are_the_setup_assistants(panda: Robot) -> None:
    srdf = parse_srdf(read_source(str(SRDFS["panda"])))
    default = {link_pair(p.link1, p.link2) for p in srdf.collision_pairs if p.reason == "Default"}
    q = default_configuration(panda.model)
    assert q[3] == pytest.approx(-1.5708, abs=1e-4)  # panda_joint4: 0 is outside, mid-range
    assert {panda.engine.pairs[i] for i in panda.engine.colliding(q)} == default


def test_adjacency_looks_through_links_without_geometry() -> None:
    edges = [("a", "b"), ("b", "c"), ("c", "d"), ("a", "e"), ("e", "f"), ("e", "g")]
    # b and c have no geometry: a-d adjacent through both; e has: f and g are siblings
    assert adjacent_pairs(["a", "d", "e", "f", "g"], edges) == {
        ("a", "d"),
        ("a", "e"),
        ("e", "f"),
        ("e", "g"),
    }


def test_samples_do_not_depend_on_how_they_are_cut(panda: Robot) -> None:
    whole = samples(panda.model, 3, 0, 2 * SAMPLE_BLOCK + 5)
    cut = [(0, 7), (7, SAMPLE_BLOCK + 1), (SAMPLE_BLOCK + 1, 2 * SAMPLE_BLOCK + 5)]
    assert np.array_equal(whole, np.concatenate([samples(panda.model, 3, a, b) for a, b in cut]))
    assert not np.array_equal(whole, samples(panda.model, 4, 0, 2 * SAMPLE_BLOCK + 5))
    low, high = panda.model.lowerPositionLimit, panda.model.upperPositionLimit
    assert np.all((whole >= low) & (whole <= high))
    spread = (whole.max(axis=0) - whole.min(axis=0)) / (high - low)
    assert np.all(spread > 0.99)


def test_counts_and_witnesses(robot: Robot) -> None:
    n = 1200
    counts = robot.engine.count(11, n)
    assert counts == robot.engine.count(11, n, chunk=97)
    qs = samples(robot.model, 11, 0, n)
    for pair, hits, witness in counts:
        index = robot.engine.pairs.index(pair)
        assert (hits == 0) == (witness is None)
        if witness is not None:
            first, q = witness
            assert np.array_equal(qs[first], q)
            assert index in robot.engine.colliding(np.array(q))
            assert all(index not in robot.engine.colliding(qs[i]) for i in range(first))
    assert sum(c.hits for c in counts) > 0


def test_a_mesh_not_read_is_refused(panda: Robot) -> None:
    link = LinkSpec("panda_link1", collisions=(CollisionSpec("mesh", mesh="absent.stl"),))
    with pytest.raises(LookupError, match=r"absent\.stl"):
        build_shapes(panda.model, [link], {})
    with pytest.raises(LookupError, match="not a body"):
        build_shapes(
            panda.model, [LinkSpec("nowhere", collisions=(CollisionSpec("sphere", (1.0,)),))], {}
        )


@pytest.mark.parametrize(("k", "n"), [(0, 10_000), (1, 10_000), (191, 200), (5, 17), (17, 17)])
def test_bounds_are_scipys(k: int, n: int) -> None:
    test = scipy.stats.binomtest(k, n)
    expected = test.proportion_ci(0.95, method="wilson")
    assert wilson(k, n) == pytest.approx((expected.low, expected.high), abs=1e-12)
    if k == 0:
        exact = test.proportion_ci(0.95, method="exact")
        assert clopper_pearson_upper(n) == pytest.approx(exact.high, rel=1e-9)
        one_sided = scipy.stats.binomtest(0, n, alternative="less").proportion_ci(0.95)
        assert clopper_pearson_upper(n, two_sided=False) == pytest.approx(one_sided.high, rel=1e-9)


def test_bounds_refuse_impossible_counts() -> None:
    for k, n in [(1, 0), (-1, 5), (6, 5)]:
        with pytest.raises(ValueError, match="no share"):
            wilson(k, n)
    with pytest.raises(ValueError, match="no bound"):
        clopper_pearson_upper(0)


PRIMITIVES = """<?xml version="1.0"?>
<sdf version="1.9"><model name="m">
  <link name="a"><collision name="shape"><pose>0 0 0.25 0 0 0</pose>
    <geometry>SHAPE</geometry></collision></link>
  <link name="b"><collision name="ball">
    <geometry><sphere><radius>0.05</radius></sphere></geometry></collision></link>
  <joint name="j" type="prismatic"><parent>a</parent><child>b</child>
    <axis><xyz>0 0 1</xyz><limit><lower>0</lower><upper>2</upper></limit></axis></joint>
</model></sdf>
"""


@pytest.mark.parametrize(
    ("shape", "top"),
    [
        ("<capsule><radius>0.1</radius><length>1</length></capsule>", 0.85),
        ("<cylinder><radius>0.1</radius><length>1</length></cylinder>", 0.75),
        ("<box><size>0.2 0.2 1</size></box>", 0.75),
        ("<sphere><radius>0.3</radius></sphere>", 0.55),
    ],
)
def test_primitives_reach_as_far_as_their_sizes(tmp_path: Path, shape: str, top: float) -> None:
    # a ball of radius 0.05 slides up the z axis of a shape whose top is at ``top``
    path = tmp_path / "robot.sdf"
    path.write_text(PRIMITIVES.replace("SHAPE", shape))
    model = cspace.pinocchio_model(str(path))
    shapes = build_shapes(model, describe(path).links, {})
    engine = SelfCollision(model, shapes, [("a", "b")])
    assert model.nq == 8  # a free root, then j
    for z, hit in [(top + 0.04, True), (top + 0.06, False), (0.0, True), (1.9, False)]:
        q = default_configuration(model)
        q[-1] = z
        assert bool(engine.colliding(q)) == hit, z


def test_continuous_and_ball_joints_are_sampled_uniformly() -> None:
    model = pin.Model()
    hinge = model.addJoint(0, pin.JointModelRUBZ(), pin.SE3.Identity(), "hinge")
    ball = model.addJoint(hinge, pin.JointModelSpherical(), pin.SE3.Identity(), "ball")
    inf = np.full(1, np.inf)
    half = model.addJoint(
        ball, pin.JointModelRX(), pin.SE3.Identity(), "half", inf, inf, -inf, np.ones(1)
    )
    model.addJoint(half, pin.JointModelPX(), pin.SE3.Identity(), "slide")  # no bounds: kept at 0
    qs = samples(model, 5, 0, 4000)
    assert -np.pi <= qs[:, 6].min() < -3.1  # no lower bound: -pi
    assert 0.99 < qs[:, 6].max() <= 1.0
    assert np.all(qs[:, 7] == 0.0)
    angle = np.arctan2(qs[:, 1], qs[:, 0])
    assert np.allclose(np.hypot(qs[:, 0], qs[:, 1]), 1.0)
    assert np.histogram(angle, bins=4, range=(-np.pi, np.pi))[0] == pytest.approx(
        [1000] * 4, abs=120
    )
    ball = qs[:, 2:6]
    assert np.allclose(np.linalg.norm(ball, axis=1), 1.0)
    # Haar measure: w has density (2/pi) sqrt(1 - w^2), so E[w^2] = 1/4, E|w| = 4/(3 pi)
    assert np.mean(ball**2, axis=0) == pytest.approx([0.25] * 4, abs=0.02)
    assert np.mean(np.abs(ball[:, 3])) == pytest.approx(4 / (3 * np.pi), abs=0.02)


MESHES = """<robot name="r">
  <link name="a">
    <collision><geometry><mesh filename="package://example-robot-data/robots/panda_description/meshes/collision/link0.stl"/></geometry></collision>
    <collision><geometry><mesh filename="missing.stl" scale="2 2 2"/></geometry></collision>
    <collision><geometry><mesh filename="/etc/passwd.stl"/></geometry></collision>
  </link>
  <link name="b">
    <collision><geometry><mesh filename="bad.stl"/></geometry></collision>
    <collision><geometry><mesh filename="missing.stl" scale="2 2 2"/></geometry></collision>
  </link>
  <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>
</robot>
"""


def test_meshes_found_read_or_said_why_not(tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_text(MESHES)
    (tmp_path / "bad.stl").write_bytes(bytes(80) + (1000).to_bytes(4, "little"))  # no triangles
    links = describe(tmp_path / "robot.urdf").links
    found = read_shape_meshes(links, str(tmp_path / "robot.urdf"), PACKAGES)
    assert [(p.link, p.line, p.mesh) for p in found.problems] == [
        ("a", 4, "missing.stl"),
        ("a", 5, "/etc/passwd.stl"),
        ("b", 8, "bad.stl"),
        ("b", 9, "missing.stl"),
    ]
    assert all(isinstance(p, ShapeProblem) and "\n" not in p.problem for p in found.problems)
    assert (
        found.problems[0].problem
        == found.problems[3].problem
        == "no such file (or not a regular file)"
    )
    assert "leads out of the folders cspace reads" in found.problems[1].problem
    link0 = ERD / "panda_description" / "meshes" / "collision" / "link0.stl"
    count = int.from_bytes(link0.read_bytes()[80:84], "little")
    assert "its header says 1,000 triangles" in found.problems[2].problem
    [(key, mesh)] = found.meshes.items()
    assert key[0].endswith("link0.stl")
    assert mesh.triangles.shape == (count, 3)


def test_too_many_shape_pairs_are_refused_before_any_is_made() -> None:
    model = pin.Model()
    model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "j")
    few = tuple(CollisionSpec("sphere", (0.1,)) for _ in range(500))
    many = (*few, CollisionSpec("sphere", (0.1,)))
    links = [LinkSpec("a", collisions=few), LinkSpec("b", collisions=many)]
    model.addBodyFrame("a", 0, pin.SE3.Identity(), 0)
    model.addBodyFrame("b", 1, pin.SE3.Identity(), 0)
    shapes = build_shapes(model, links, {})
    assert len(SelfCollision(model, shapes, [("b", "b")]).pairs) == 0  # a link never with itself
    with pytest.raises(ValueError, match=r"250,500 pairs of collision shapes .* the 250,000"):
        SelfCollision(model, shapes, [("a", "b")])


def test_block_b_draws_from_the_seed_sequences_child_b() -> None:
    # the stream is part of the result: a seed given to cspace gives the same samples
    model = pin.Model()
    model.addJoint(
        0,
        pin.JointModelRZ(),
        pin.SE3.Identity(),
        "j",
        *[np.ones(1)] * 2,
        -np.ones(1),
        3 * np.ones(1),
    )
    child = np.random.SeedSequence(3).spawn(3)[2]
    draws = np.random.default_rng(child).random((SAMPLE_BLOCK, 1))
    got = samples(model, 3, 2 * SAMPLE_BLOCK + 10, 2 * SAMPLE_BLOCK + 20)
    assert np.array_equal(got, -1.0 + 4.0 * draws[10:20])
