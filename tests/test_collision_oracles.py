"""The self-collision engine held to other collision libraries, pair by pair, sample by sample.

cspace's engine (`SelfCollision`: coal through Pinocchio, on shapes cspace's readers
read) is asked which non-adjacent link pairs collide at seeded samples. Each robot is
then read again without cspace: the URDF's ``<collision>`` elements by lxml here, its
meshes by trimesh, its links placed by yourdfpy's forward kinematics (of the URDF with
its shapes taken out: yourdfpy knows no capsule), and each pair asked of FCL
(python-fcl); on the robot of primitives, of PyBullet's ``getClosestPoints`` too.
Robots: example-robot-data's panda and UR5 (STL meshes, the panda's finger boxes), a
robot of its meshes in STL, COLLADA and OBJ, scaled, and the primitive robot of
`collision_robots` (boxes, spheres, cylinders, capsules). URDF has no capsule (cspace's
URDF reader drops a link holding one, as urdfdom does), so the engine reads the
primitive robot's SDF twin, and its URDF without the capsules' links. With its shapes
turned at random the engine misses overlaps FCL finds: that test is an expected failure
until `SelfCollision` asks coal for contacts (see its reason).

A sample on which a library and the engine disagree about a pair is allowed only where
the pair grazes, by how far the side that says *apart* puts its closest shapes: within
`FCL_GRAZE` for FCL (FCL's distance, or coal's when the engine is the one saying apart).
PyBullet's URDF importer gives every shape a 1 mm collision margin, `BULLET_MARGIN`,
which ``changeDynamics(collisionMargin=0)`` removes from the base alone (PyBullet 3.2.7
leaves the links' as they are): its boxes and cylinders (``URDF_USE_IMPLICIT_CYLINDER``;
without it a cylinder is a 32-sided prism grown by the margin) keep their sizes with
edges and corners rounded off by it, so they lie inside the exact shapes, and a box's
corner is up to (sqrt(3) - 1) mm in, a cylinder's rim (sqrt(2) - 1) mm; spheres and
capsules are exact. So where PyBullet alone sees a collision, coal's distance must be
within `BULLET_GRAZE`; where the engine alone does, the depth of each overlapping pair
of shapes must be within `BULLET_GRAZE` of what their rounding hides.
"""

from __future__ import annotations

import io
import math
import os
from collections import Counter
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, NamedTuple

import fcl
import numpy as np
import pinocchio as pin
import pybullet as p
import pytest
import trimesh
import yourdfpy
from collision_robots import (
    JOINTS,
    LINKS,
    mesh_urdf,
    primitive_sdf,
    primitive_urdf,
    turned_links,
)
from lxml import etree
from test_collision_engine import SHARE, Robot
from test_collision_geometry import SRDFS, URDFS

import cspace
from cspace._formats.shared.xmlio import read_source
from cspace._formats.srdf.reader import parse_srdf
from cspace._model._collision_pairs import LinkPair, SelfCollision, link_pair, samples

FCL_GRAZE = 1e-6
"""Metres: how close the shapes of a pair that FCL and coal disagree on must be."""

BULLET_GRAZE = 1e-5
"""Metres: the same for PyBullet, beyond the depth its rounded edges hide."""

BULLET_MARGIN = 0.001
"""Metres: the collision margin PyBullet's URDF importer gives every shape
(``gUrdfDefaultCollisionMargin``); ``changeDynamics(collisionMargin=...)`` changes only
the base's in PyBullet 3.2.7, so the links keep it."""

# ---------------------------------------------------------------------------------------
# The URDF read without cspace: shapes by lxml and trimesh, links and joints by yourdfpy.


def _rotation(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF's rpy: about the fixed x, then y, then z axes, ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    cr, sr, cp, sp, cy, sy = (f(a) for a in (roll, pitch, yaw) for f in (math.cos, math.sin))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _numbers(element: Any, key: str, default: str) -> list[float]:
    return [float(word) for word in element.get(key, default).split()]


def _geometry(shape: Any, base: Path) -> Any:
    """An FCL geometry of a URDF shape element, in the shape's frame."""
    tag = shape.tag
    if tag == "box":
        return fcl.Box(*_numbers(shape, "size", ""))
    if tag == "sphere":
        return fcl.Sphere(float(shape.get("radius")))
    if tag == "cylinder":
        return fcl.Cylinder(float(shape.get("radius")), float(shape.get("length")))
    if tag == "capsule":
        return fcl.Capsule(float(shape.get("radius")), float(shape.get("length")))
    if tag == "mesh":
        name = str(shape.get("filename"))
        package = name.startswith("package://")  # example-robot-data's, in SHARE
        path = SHARE / name.removeprefix("package://") if package else base / name
        mesh = trimesh.load(str(path), force="mesh")
        vertices = np.asarray(mesh.vertices) * _numbers(shape, "scale", "1 1 1")
        bvh = fcl.BVHModel()
        bvh.beginModel(len(vertices), len(mesh.faces))
        bvh.addSubModel(vertices, np.asarray(mesh.faces))
        bvh.endModel()
        return bvh
    raise ValueError(f"no FCL geometry for <{tag}>")


def _skeleton(path: Path) -> yourdfpy.URDF:
    """yourdfpy's model of the URDF's links and joints, its shapes taken out."""
    root = etree.parse(str(path)).getroot()
    for link in root.iter("link"):
        for element in [*link.findall("visual"), *link.findall("collision")]:
            link.remove(element)
    return yourdfpy.URDF.load(
        io.BytesIO(etree.tostring(root)),
        build_collision_scene_graph=False,
        load_meshes=False,
        load_collision_meshes=False,
    )


def positions(model: Any, q: np.ndarray) -> dict[str, float]:
    """Each 1-DoF joint's position (a continuous joint's angle) in Pinocchio's ``q``,
    by joint name; a mimic joint has none of its own."""
    out: dict[str, float] = {}
    for joint, name in zip(list(model.joints)[1:], list(model.names)[1:], strict=True):
        if joint.nq == 1:
            out[name] = float(q[joint.idx_q])
        elif joint.nq == 2:
            out[name] = math.atan2(q[joint.idx_q + 1], q[joint.idx_q])
    return out


def _turn(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation by ``angle`` about the unit vector ``axis`` (Rodrigues)."""
    x, y, z = axis
    cross = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle) * cross + (1.0 - math.cos(angle)) * cross @ cross


class Kinematics:
    """Forward kinematics of a URDF's links and joints as yourdfpy parses them: each
    link's placement (4x4) in the root link's frame, from 1-DoF joint positions by name,
    a mimic joint at its multiplier times its joint's position plus its offset (as
    yourdfpy's own, `test_forward_kinematics_is_yourdfpys`, in a tenth of its time)."""

    def __init__(self, urdf: yourdfpy.URDF) -> None:
        joints = list(urdf.robot.joints)
        self.root = urdf.base_link
        self.order: list[Any] = []
        reached = {self.root}
        while len(self.order) < len(joints):
            step = [j for j in joints if j.parent in reached and j.child not in reached]
            assert step, "the joints do not make a tree"
            self.order += step
            reached |= {j.child for j in step}

    def placements(self, values: dict[str, float]) -> dict[str, np.ndarray]:
        out = {self.root: np.eye(4)}
        for joint in self.order:
            value = values.get(joint.name, 0.0)
            if joint.mimic is not None:
                multiplier = 1.0 if joint.mimic.multiplier is None else joint.mimic.multiplier
                offset = 0.0 if joint.mimic.offset is None else joint.mimic.offset
                value = multiplier * values[joint.mimic.joint] + offset
            motion = np.eye(4)
            if joint.type in ("revolute", "continuous", "prismatic"):
                axis = np.asarray(joint.axis, dtype=float)
                axis = axis / np.linalg.norm(axis)
                if joint.type == "prismatic":
                    motion[:3, 3] = value * axis
                else:
                    motion[:3, :3] = _turn(axis, value)
            origin = np.eye(4) if joint.origin is None else joint.origin
            out[joint.child] = out[joint.parent] @ origin @ motion
        return out


class Fcl:
    """A URDF's collision shapes as FCL objects (read by lxml, meshes by trimesh), placed
    by `Kinematics` at a configuration of cspace's model (``model``: its joints' names
    are the URDF's)."""

    def __init__(self, path: Path, model: Any) -> None:
        self.model = model
        self.kinematics = Kinematics(_skeleton(path))
        self.shapes: dict[str, list[tuple[Any, np.ndarray]]] = {}
        for link in etree.parse(str(path)).getroot().iter("link"):
            for collision in link.iterchildren("collision"):
                origin = collision.find("origin")
                placement = np.eye(4)
                if origin is not None:
                    placement[:3, :3] = _rotation(*_numbers(origin, "rpy", "0 0 0"))
                    placement[:3, 3] = _numbers(origin, "xyz", "0 0 0")
                shape = next(collision.find("geometry").iterchildren(etree.Element))
                item = fcl.CollisionObject(_geometry(shape, path.parent), fcl.Transform())
                self.shapes.setdefault(str(link.get("name")), []).append((item, placement))

    def place(self, q: np.ndarray) -> None:
        frames = self.kinematics.placements(positions(self.model, q))
        for link, items in self.shapes.items():
            frame = frames[link]
            for item, placement in items:
                world = frame @ placement
                item.setTransform(fcl.Transform(world[:3, :3], world[:3, 3]))

    def collide(self, pair: LinkPair) -> bool:
        request = fcl.CollisionRequest()
        return any(
            fcl.collide(a, b, request, fcl.CollisionResult()) > 0
            for a, _ in self.shapes[pair[0]]
            for b, _ in self.shapes[pair[1]]
        )

    def colliding(self, q: np.ndarray, pairs: Sequence[LinkPair]) -> set[LinkPair]:
        self.place(q)
        return {pair for pair in pairs if self.collide(pair)}

    def excess(self, robot: Robot, q: np.ndarray, pair: LinkPair, engine: bool) -> float:
        """How far from touching the side that says "apart" puts the pair's closest shapes
        at ``q`` (m, unsigned): FCL's distance when the engine alone sees a collision,
        coal's when FCL alone does (an overlap coal measures but did not report counts)."""
        if not engine:
            return abs(min(d for d, _ in coal_distances(robot, q, pair)))
        self.place(q)
        request = fcl.DistanceRequest()
        return abs(
            min(
                fcl.distance(a, b, request, fcl.DistanceResult())
                for a, _ in self.shapes[pair[0]]
                for b, _ in self.shapes[pair[1]]
            )
        )


class Bullet:
    """A URDF loaded by PyBullet (fixed base, self-collision on, implicit cylinders), its
    joints set from a configuration of cspace's model."""

    def __init__(self, client: int, path: Path, model: Any) -> None:
        self.client, self.model = client, model
        flags = p.URDF_USE_SELF_COLLISION | p.URDF_USE_IMPLICIT_CYLINDER
        self.body = p.loadURDF(str(path), useFixedBase=True, flags=flags, physicsClientId=client)
        self.links = {p.getBodyInfo(self.body, physicsClientId=client)[0].decode(): -1}
        self.joints: dict[str, int] = {}
        for index in range(p.getNumJoints(self.body, physicsClientId=client)):
            info = p.getJointInfo(self.body, index, physicsClientId=client)
            self.links[info[12].decode()] = index
            if info[2] != p.JOINT_FIXED:
                self.joints[info[1].decode()] = index

    def place(self, q: np.ndarray) -> None:
        for name, value in positions(self.model, q).items():
            p.resetJointState(self.body, self.joints[name], value, physicsClientId=self.client)

    def closest(self, pair: LinkPair, within: float) -> float:
        """The least signed distance PyBullet finds between the pair's links (inf if none
        is ``within``)."""
        points = p.getClosestPoints(
            self.body,
            self.body,
            within,
            linkIndexA=self.links[pair[0]],
            linkIndexB=self.links[pair[1]],
            physicsClientId=self.client,
        )
        return min((point[8] for point in points), default=math.inf)

    def colliding(self, q: np.ndarray, pairs: Sequence[LinkPair]) -> set[LinkPair]:
        self.place(q)
        return {pair for pair in pairs if self.closest(pair, 0.0) <= 0.0}

    def excess(self, robot: Robot, q: np.ndarray, pair: LinkPair, engine: bool) -> float:
        """How far beyond PyBullet's rounding the engine's verdict on ``pair`` is (m): when
        the engine alone sees a collision, the deepest of the pair's shape pairs less
        what the two shapes' rounded edges can hide; when PyBullet alone does, coal's
        distance, unsigned (its rounded shapes lie inside the exact ones)."""
        distances = coal_distances(robot, q, pair)
        if not engine:
            return abs(min(d for d, _ in distances))
        return max((-d - hidden for d, hidden in distances if d <= 0.0), default=math.inf)


ROUNDED = {"Box": math.sqrt(3) - 1, "Cylinder": math.sqrt(2) - 1}
"""How deep (in PyBullet margins) an edge or corner of each kind is rounded off: a box's
corner by sqrt(3) - 1, a cylinder's rim by sqrt(2) - 1; spheres and capsules are kept
exactly (a margin is their radius)."""


def coal_distances(robot: Robot, q: np.ndarray, pair: LinkPair) -> list[tuple[float, float]]:
    """coal's signed distance of each pair of the two links' shapes at ``q``, as the
    engine holds them, with the depth PyBullet's rounding can hide between them (m)."""
    geometry = robot.engine.geometry
    data, geometry_data = robot.model.createData(), pin.GeometryData(geometry)
    pin.updateGeometryPlacements(robot.model, data, geometry, geometry_data, q)
    links, objects = robot.shapes.links, geometry.geometryObjects
    out = []
    for k, shapes in enumerate(geometry.collisionPairs):
        if link_pair(links[shapes.first], links[shapes.second]) == pair:
            kinds = (type(objects[i].geometry).__name__ for i in (shapes.first, shapes.second))
            hidden = BULLET_MARGIN * sum(ROUNDED.get(kind, 0.0) for kind in kinds)
            out.append((pin.computeDistance(geometry, geometry_data, k).min_distance, hidden))
    return out


class Disagreement(NamedTuple):
    """One pair at one sample on which the engine and an oracle differ."""

    sample: int
    pair: LinkPair
    engine: bool  # the engine says the pair collides
    excess: float  # how far from grazing (m): the oracle's ``excess``


class Comparison(NamedTuple):
    """The engine against one oracle over samples."""

    checked: int  # pairs x samples
    engine: Counter[LinkPair]  # samples in collision, by pair
    oracle: Counter[LinkPair]
    disagreements: list[Disagreement]


def fresh(robot: Robot) -> SelfCollision:
    """A new engine on the robot's shapes and pairs, no query answered yet."""
    return SelfCollision(robot.model, robot.shapes, robot.engine.pairs)


def compare(
    robot: Robot, oracle: Fcl | Bullet, qs: np.ndarray, pairs: Sequence[LinkPair] = ()
) -> Comparison:
    """The engine and ``oracle`` on ``pairs`` (all the engine's by default) at each q.

    The engine is made anew (`fresh`): its verdicts depend on the queries it answered
    before (see `test_turned_primitives_are_fcls_sample_by_sample`), so each comparison
    starts from the same state whatever ran before it.
    """
    engine_now = fresh(robot)
    pairs = tuple(pairs) or engine_now.pairs
    index = {pair: i for i, pair in enumerate(engine_now.pairs)}
    ours, theirs, differ = Counter[LinkPair](), Counter[LinkPair](), []
    for sample, q in enumerate(qs):
        hits = engine_now.colliding(q)
        engine = {pair for pair in pairs if index[pair] in hits}
        other = oracle.colliding(q, pairs)
        ours.update(engine)
        theirs.update(other)
        for pair in sorted(engine ^ other):
            excess = oracle.excess(robot, q, pair, pair in engine)
            differ.append(Disagreement(sample, pair, pair in engine, excess))
    return Comparison(len(pairs) * len(qs), ours, theirs, differ)


def assert_grazing(comparison: Comparison, graze: float) -> None:
    """Every disagreement is within ``graze`` (m) of what the oracle's shapes explain."""
    beyond = [d for d in comparison.disagreements if d.excess > graze]
    assert beyond == [], beyond


def assert_counts(counts: dict[LinkPair, int], comparison: Comparison) -> None:
    """The engine's ``counts`` (`SelfCollision.count`) are its sample-by-sample verdicts,
    and the oracle's differ from them by the grazing disagreements alone."""
    assert counts == {pair: comparison.engine[pair] for pair in counts}
    grazing = Counter(d.pair for d in comparison.disagreements)
    for pair, hits in counts.items():
        assert abs(hits - comparison.oracle[pair]) <= grazing[pair], pair


# ---------------------------------------------------------------------------------------


class Primitives(NamedTuple):
    """The primitive robot's URDF and the engine on its two readings."""

    urdf: Path
    sdf: Robot  # the engine on the SDF twin (all shapes)
    without_capsules: Robot  # the engine on the URDF (links holding a capsule: none)


@pytest.fixture(scope="module")
def primitives(tmp_path_factory: pytest.TempPathFactory) -> Primitives:
    folder = tmp_path_factory.mktemp("primitives")
    (folder / "primitives.urdf").write_text(primitive_urdf())
    (folder / "primitives.sdf").write_text(primitive_sdf())
    return Primitives(
        folder / "primitives.urdf",
        Robot(folder / "primitives.sdf"),
        Robot(folder / "primitives.urdf"),
    )


@pytest.fixture(scope="module")
def client() -> Iterator[int]:
    """One PyBullet server in this process, without a window; its C printing silenced."""
    saved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    try:
        handle = p.connect(p.DIRECT)
    finally:
        os.dup2(saved, 1)
    yield handle
    p.disconnect(handle)
    os.close(saved)
    os.close(null)


class Erd(NamedTuple):
    """An example-robot-data robot: the engine, and FCL on its URDF."""

    robot: Robot
    fcl: Fcl


@pytest.fixture(scope="module")
def erds() -> dict[str, Erd]:
    built = {name: Robot(URDFS[name]) for name in ("panda", "ur5")}
    return {name: Erd(robot, Fcl(URDFS[name], robot.model)) for name, robot in built.items()}


@pytest.fixture(params=["panda", "ur5"])
def erd(request: pytest.FixtureRequest, erds: dict[str, Erd]) -> Erd:
    return erds[request.param]


def test_primitive_robot_is_read_as_written(primitives: Primitives) -> None:
    sdf, urdf = primitives.sdf, primitives.without_capsules
    assert sdf.model.nq == 9  # 8 joints move (not j6), the continuous one (cos, sin)
    with_geometry = [link for link, shapes in LINKS.items() if shapes]
    assert list(sdf.shapes.with_geometry) == with_geometry
    assert sdf.adjacent == {
        link_pair(parent, child)
        for _, _, parent, child, *_ in JOINTS
        if LINKS[parent] and LINKS[child]
    } | {("hand", "slider")}
    assert len(sdf.engine.pairs) == 9 * 8 // 2 - 8
    capsules = {link for link, shapes in LINKS.items() if any(s[0] == "capsule" for s in shapes)}
    assert list(urdf.shapes.with_geometry) == [k for k in with_geometry if k not in capsules]
    assert ("arm1", "arm4") in urdf.adjacent  # through arm2 and arm3, now without shapes


@pytest.mark.parametrize("name", ["panda", "ur5", "primitives"])
def test_forward_kinematics_is_yourdfpys(name: str, primitives: Primitives) -> None:
    path = primitives.urdf if name == "primitives" else URDFS[name]
    model = primitives.sdf.model if name == "primitives" else cspace.pinocchio_model(str(path))
    skeleton = _skeleton(path)
    ours = Kinematics(skeleton)
    for q in samples(model, 2, 0, 30):
        values = positions(model, q)
        skeleton.update_cfg({joint: values[joint] for joint in skeleton.actuated_joint_names})
        frames = ours.placements(values)
        assert set(frames) == set(skeleton.link_map)
        for link, frame in frames.items():
            assert frame == pytest.approx(skeleton.get_transform(link), abs=1e-12), link


def test_primitives_are_fcls_sample_by_sample(primitives: Primitives) -> None:
    robot = primitives.sdf
    oracle = Fcl(primitives.urdf, robot.model)
    comparison = compare(robot, oracle, samples(robot.model, 5, 0, 600))
    assert_grazing(comparison, FCL_GRAZE)
    assert comparison.checked == 600 * 28
    assert sum(comparison.engine.values()) > 1000
    assert len(comparison.engine) >= 20  # most pairs collide somewhere


def test_primitives_from_the_urdf_are_fcls(primitives: Primitives) -> None:
    robot = primitives.without_capsules
    oracle = Fcl(primitives.urdf, robot.model)
    comparison = compare(robot, oracle, samples(robot.model, 6, 0, 1000))
    assert_grazing(comparison, FCL_GRAZE)
    assert sum(comparison.engine.values()) > 300
    assert set(comparison.engine) == set(robot.engine.pairs)  # each pair collides somewhere


def test_turned_primitives_are_fcls_sample_by_sample(tmp_path: Path) -> None:
    """Shapes turned at random: coal with Pinocchio's default requests (GJK from the guess
    cached at the sample before, no contact) missed a 2.1 cm capsule-box overlap here."""
    (tmp_path / "turned.urdf").write_text(primitive_urdf(turned_links()))
    (tmp_path / "turned.sdf").write_text(primitive_sdf(turned_links()))
    robot = Robot(tmp_path / "turned.sdf")
    oracle = Fcl(tmp_path / "turned.urdf", robot.model)
    comparison = compare(robot, oracle, samples(robot.model, 9, 0, 800))
    assert sum(comparison.engine.values()) > 2000
    assert_grazing(comparison, FCL_GRAZE)


def test_primitives_are_pybullets_sample_by_sample(primitives: Primitives, client: int) -> None:
    robot = primitives.sdf
    oracle = Bullet(client, primitives.urdf, robot.model)
    for link in oracle.links.values():  # the margin the rounding allowance assumes
        info = p.getDynamicsInfo(oracle.body, link, physicsClientId=client)
        assert info[11] == pytest.approx(BULLET_MARGIN)
    comparison = compare(robot, oracle, samples(robot.model, 5, 0, 600))
    assert_grazing(comparison, BULLET_GRAZE)
    assert sum(comparison.engine.values()) > 1000


def test_meshes_are_fcls_sample_by_sample(erd: Erd) -> None:
    comparison = compare(erd.robot, erd.fcl, samples(erd.robot.model, 7, 0, 400))
    assert_grazing(comparison, FCL_GRAZE)
    assert sum(comparison.engine.values()) >= 50


def test_scaled_meshes_of_three_formats_are_fcls(tmp_path: Path) -> None:
    path = tmp_path / "meshes.urdf"
    path.write_text(mesh_urdf())
    robot = Robot(path)
    comparison = compare(robot, Fcl(path, robot.model), samples(robot.model, 3, 0, 300))
    assert_grazing(comparison, FCL_GRAZE)
    assert comparison.checked == 300 * 6
    assert sum(comparison.engine.values()) > 150


def test_panda_counts_are_fcls(erds: dict[str, Erd]) -> None:
    robot, oracle = erds["panda"]
    comparison = compare(robot, oracle, samples(robot.model, 11, 0, 2000))
    assert_grazing(comparison, FCL_GRAZE)
    assert_counts({c.pair: c.hits for c in fresh(robot).count(11, 2000)}, comparison)
    assert len(comparison.oracle) >= 10  # pairs that collide somewhere


def test_ur5_srdf_disabled_pairs_collide_for_fcl_too(erds: dict[str, Erd]) -> None:
    # the UR5's SRDF disables 10 pairs: 4 are not adjacent, and 3 of those collide
    robot, oracle = erds["ur5"]
    srdf = parse_srdf(read_source(str(SRDFS["ur5"])))
    disabled = {link_pair(d.link1, d.link2) for d in srdf.collision_pairs}
    pairs = sorted(disabled & set(robot.engine.pairs))
    n = 10_000
    comparison = compare(robot, oracle, samples(robot.model, 0, 0, n), pairs)
    assert_grazing(comparison, FCL_GRAZE)
    assert_counts(
        {c.pair: c.hits for c in fresh(robot).count(0, n) if c.pair in disabled}, comparison
    )
    shares = {pair: comparison.oracle[pair] / n for pair in pairs}
    assert shares == pytest.approx(
        {
            ("base_link", "upper_arm_link"): 0.038,
            ("forearm_link", "wrist_2_link"): 0.044,
            ("forearm_link", "wrist_3_link"): 0.077,
            ("wrist_1_link", "wrist_3_link"): 0.0,
        },
        abs=0.001,
    )


def test_the_oracle_sees_a_shape_one_centimetre_off(tmp_path: Path) -> None:
    # the comparison can fail: the engine reads a robot whose base box sits 1 cm higher
    moved = {**LINKS, "base": [("box", (0.24, 0.24, 0.1), (0, 0, 0.06), (0, 0, 0))]}
    (tmp_path / "moved.sdf").write_text(primitive_sdf(moved))
    (tmp_path / "primitives.urdf").write_text(primitive_urdf())
    robot = Robot(tmp_path / "moved.sdf")
    oracle = Fcl(tmp_path / "primitives.urdf", robot.model)
    comparison = compare(robot, oracle, samples(robot.model, 5, 0, 300))
    beyond = [d for d in comparison.disagreements if d.excess > 1e-3]
    assert len(beyond) >= 10
    assert {d.pair for d in beyond} <= {pair for pair in robot.engine.pairs if "base" in pair}
