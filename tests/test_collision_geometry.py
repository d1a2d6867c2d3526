"""Collision geometry as the readers read it, and an SRDF's collision pairs.

Each link's ``<collision>`` shapes (URDF, xacro, SDF) are held to the tools' own reading:
Pinocchio's ``buildGeomFromUrdf`` (urdfdom) and yourdfpy for URDF, Drake's parser for
SDF; the SRDF's ``<disable_collisions>`` pairs to Pinocchio's ``removeCollisionPairs``
and to srdfdom's rules. Nothing here changes a report: the readers only keep the shapes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pydrake
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

from cspace._formats.detect import detect
from cspace._formats.shared import mesh_paths
from cspace._formats.shared.collisions import MAX_COLLISIONS
from cspace._formats.shared.description import CollisionSpec, LinkSpec, RobotDescription
from cspace._formats.shared.erd import robots_dir
from cspace._formats.shared.pose import Pose
from cspace._formats.shared.reading import ReadRequest, read
from cspace._formats.shared.xmlio import ReadBudget, parse_xml, read_source, source_from_bytes
from cspace._formats.srdf.reader import CollisionPair, parse_srdf, with_links
from cspace._formats.xacro.expand import XacroOptions, ros_packages
from cspace.errors import InvalidElementError, RobotFileError

ERD = robots_dir()
SHARE = ERD.parent.parent
URDFS = {
    "panda": ERD / "panda_description" / "urdf" / "panda.urdf",
    "ur5": ERD / "ur_description" / "urdf" / "ur5_robot.urdf",
    "talos": ERD / "talos_data" / "robots" / "talos_reduced.urdf",
}
SRDFS = {
    "panda": ERD / "panda_description" / "srdf" / "panda.srdf",
    "ur5": ERD / "ur_description" / "srdf" / "ur5.srdf",
    "talos": ERD / "talos_data" / "srdf" / "talos.srdf",
}


def describe(path: Path, *, xacro: bool = False) -> RobotDescription:
    """The description the format's reader makes of ``path``, as the loader asks for it."""
    source = read_source(str(path))
    budget = ReadBudget(source.path)
    budget.charge(source)
    root = parse_xml(source)
    row = detect(source.path, root, force_xacro=xacro, data=source.data)
    options = XacroOptions.from_cli((), ()) if row.name == "xacro" else None
    request = ReadRequest(source.path, source, root, str(path), budget, options=options)
    return read(row, request).description


def of_text(text: str, name: str = "robot.urdf") -> RobotDescription:
    """The description of a URDF or SDF document given as text."""
    source = source_from_bytes(name, text.encode())
    root = parse_xml(source)
    row = detect(name, root, force_xacro=False, data=source.data)
    return read(row, ReadRequest(name, source, root, None, ReadBudget(name))).description


def placement(pose: Pose) -> pin.SE3:
    w, x, y, z = pose.rotation_wxyz
    return pin.SE3(pin.Quaternion(w, x, y, z).toRotationMatrix(), np.array(pose.position))


def pinocchio_shapes(path: Path) -> tuple[pin.Model, dict[str, list[pin.GeometryObject]]]:
    """Pinocchio's collision objects of ``path``, by link, in its order."""
    model = pin.buildModelFromUrdf(str(path))
    geometry = pin.buildGeomFromUrdf(model, str(path), pin.COLLISION, package_dirs=[str(SHARE)])
    by_link: dict[str, list[pin.GeometryObject]] = {}
    for item in geometry.geometryObjects:
        by_link.setdefault(model.frames[item.parentFrame].name, []).append(item)
    return model, by_link


def assert_shape_is(model: pin.Model, ours: CollisionSpec, theirs: pin.GeometryObject) -> None:
    frame = model.frames[theirs.parentFrame].placement  # the link in its joint's frame
    expected = frame * placement(ours.origin)
    assert np.allclose(expected.homogeneous, theirs.placement.homogeneous, atol=1e-9)
    shape = theirs.geometry
    if ours.kind == "mesh":
        assert ours.mesh is not None
        rest = ours.mesh.removeprefix("package://")  # example-robot-data's, or a path
        assert Path(theirs.meshPath).resolve() == (SHARE / rest).resolve()
        assert np.allclose(theirs.meshScale, ours.scale)
    elif ours.kind == "box":
        assert np.allclose(2 * shape.halfSide, ours.sizes)
    elif ours.kind == "cylinder":
        assert (shape.radius, 2 * shape.halfLength) == pytest.approx(ours.sizes)
    else:
        assert ours.kind == "sphere"
        assert (shape.radius,) == pytest.approx(ours.sizes)


@pytest.mark.parametrize("robot", sorted(URDFS))
def test_urdf_collisions_are_pinocchios(robot: str) -> None:
    description = describe(URDFS[robot])
    model, theirs = pinocchio_shapes(URDFS[robot])
    ours = {link.name: link.collisions for link in description.links if link.collisions}
    assert set(ours) == set(theirs)
    for name, shapes in ours.items():
        assert len(shapes) == len(theirs[name]), name
        for mine, other in zip(shapes, theirs[name], strict=True):
            assert_shape_is(model, mine, other)
    assert all(not link.unread for link in description.links)
    kinds = {shape.kind for shapes in ours.values() for shape in shapes}
    assert "mesh" in kinds


@pytest.mark.parametrize("robot", sorted(URDFS))
def test_urdf_collisions_are_yourdfpys(robot: str) -> None:
    yourdfpy = pytest.importorskip("yourdfpy")
    urdf = yourdfpy.URDF.load(
        str(URDFS[robot]), build_scene_graph=False, load_meshes=False, load_collision_meshes=False
    )
    ours = {link.name: link.collisions for link in describe(URDFS[robot]).links}
    for link in urdf.robot.links:
        shapes = ours[link.name]
        assert len(shapes) == len(link.collisions), link.name
        for mine, theirs in zip(shapes, link.collisions, strict=True):
            origin = np.eye(4) if theirs.origin is None else theirs.origin
            assert np.allclose(placement(mine.origin).homogeneous, origin, atol=1e-9)
            geometry = theirs.geometry
            if mine.kind == "mesh":
                assert mine.mesh == geometry.mesh.filename
                scale = 1.0 if geometry.mesh.scale is None else geometry.mesh.scale
                assert np.allclose(np.broadcast_to(scale, 3), mine.scale)
            elif mine.kind == "box":
                assert np.allclose(geometry.box.size, mine.sizes)
            elif mine.kind == "cylinder":
                cylinder = geometry.cylinder
                assert (cylinder.radius, cylinder.length) == pytest.approx(mine.sizes)
            else:
                assert (geometry.sphere.radius,) == pytest.approx(mine.sizes)


SHAPES = """<robot name="r">
  <link name="a">
    <collision name="one"><origin xyz="1 2 3" rpy="0.1 0.2 0.3"/>
      <geometry><box size="0.1 0.2 0.3"/></geometry></collision>
    <collision><geometry><!-- a comment first --><sphere radius="0.5"/></geometry></collision>
    <collision><origin quat_xyzw="0 0 1 1"/>
      <geometry><cylinder radius="0.25" length="2"/></geometry></collision>
    <collision><geometry><mesh filename="MESH" scale="2 2 -1"/></geometry></collision>
  </link>
  <link name="b">
    <collision><geometry><box size="1 2"/></geometry></collision>
    <collision><geometry><capsule radius="1" length="2"/></geometry></collision>
    <collision><geometry><sphere radius="nan"/></geometry></collision>
    <collision><geometry><cylinder radius="-1" length="1"/></geometry></collision>
    <collision><origin xyz="1 2"/><geometry><sphere radius="1"/></geometry></collision>
    <collision><geometry/></collision>
    <collision><geometry><sphere radius="0.125"/></geometry></collision>
    <collision/>
  </link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_every_urdf_shape_and_what_urdfdom_drops(tmp_path: Path) -> None:
    mesh = str(ERD / "panda_description" / "meshes" / "collision" / "link0.stl")
    (tmp_path / "robot.urdf").write_text(SHAPES.replace("MESH", mesh))
    links = {link.name: link for link in describe(tmp_path / "robot.urdf").links}
    a, b = links["a"], links["b"]
    assert [(c.kind, c.sizes, c.line) for c in a.collisions] == [
        ("box", (0.1, 0.2, 0.3), 3),
        ("sphere", (0.5,), 5),
        ("cylinder", (0.25, 2.0), 6),
        ("mesh", (), 8),
    ]
    assert a.collisions[2].origin == Pose()  # quat_xyzw: urdfdom and Pinocchio ignore it
    assert (a.collisions[3].mesh, a.collisions[3].scale) == (mesh, (2.0, 2.0, -1.0))
    rotation = pin.rpy.rpyToMatrix(0.1, 0.2, 0.3)
    assert np.allclose(placement(a.collisions[0].origin).rotation, rotation)
    assert a.collisions[0].origin.position == (1.0, 2.0, 3.0)
    # urdfdom fails on b's first <collision>, and Pinocchio gives b no shape at all.
    assert b.collisions == ()
    assert [line for line, _ in b.unread] == [11, 12, 13, 14, 15, 16, 18]
    problems = [problem for _, problem in b.unread]
    assert '<box size="1 2"> is not three finite numbers' in problems[0]
    assert "<capsule>" in problems[1]
    assert "not a finite number" in problems[2]
    assert "<cylinder radius> is negative" in problems[3]
    assert all(problem.startswith("link 'b': ") for problem in problems)
    model, theirs = pinocchio_shapes(tmp_path / "robot.urdf")
    assert "b" not in theirs
    assert len(theirs["a"]) == 4
    for mine, other in zip(a.collisions, theirs["a"], strict=True):
        assert_shape_is(model, mine, other)


def test_a_link_without_collisions_has_none() -> None:
    text = '<robot name="r"><link name="a"><visual><geometry><sphere radius="1"/></geometry>'
    description = of_text(text + "</visual></link></robot>")
    assert description.links == (LinkSpec("a", 1),)


def test_collision_elements_past_the_limit_are_refused_in_one_line() -> None:
    links = "".join(
        f'<link name="l{i}">{"<collision/>" * 1000}</link>'
        for i in range(MAX_COLLISIONS // 1000 + 1)
    )
    with pytest.raises(RobotFileError) as caught:
        of_text(f'<robot name="r">\n{links}</robot>')
    assert isinstance(caught.value, InvalidElementError)
    assert caught.value.code == "too-many-elements"
    assert f"more than {MAX_COLLISIONS:,} <collision> elements" in caught.value.problem
    assert len(getattr(caught.value, "errors", [caught.value])) == 1


def test_xacro_collisions_are_those_of_its_urdf(tmp_path: Path) -> None:
    macro = (
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:macro name="ball" params="name r">\n'
        '<link name="${name}"><collision><origin xyz="0 0 ${r}"/>'
        '<geometry><sphere radius="${r}"/></geometry></collision></link>\n'
        "</xacro:macro>\n"
        '<xacro:ball name="a" r="0.5"/><xacro:ball name="b" r="0.25"/>\n'
        '<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>\n'
        "</robot>\n"
    )
    (tmp_path / "robot.urdf.xacro").write_text(macro)
    links = {link.name: link for link in describe(tmp_path / "robot.urdf.xacro").links}
    assert links["a"].collisions == (CollisionSpec("sphere", (0.5,), Pose((0.0, 0.0, 0.5))),)
    assert links["b"].collisions == (CollisionSpec("sphere", (0.25,), Pose((0.0, 0.0, 0.25))),)


# The SRDF's collision pairs.


@pytest.mark.parametrize("robot", sorted(SRDFS))
def test_srdf_disabled_pairs_are_pinocchios(robot: str) -> None:
    srdf = parse_srdf(read_source(str(SRDFS[robot])))
    model = pin.buildModelFromUrdf(str(URDFS[robot]))
    geometry = pin.buildGeomFromUrdf(
        model, str(URDFS[robot]), pin.COLLISION, package_dirs=[str(SHARE)]
    )
    geometry.addAllCollisionPairs()
    every = {(p.first, p.second) for p in geometry.collisionPairs}
    pin.removeCollisionPairs(model, geometry, str(SRDFS[robot]))
    left = {(p.first, p.second) for p in geometry.collisionPairs}
    link_of = [model.frames[g.parentFrame].name for g in geometry.geometryObjects]
    removed = {frozenset((link_of[i], link_of[j])) for i, j in every - left}
    # Pinocchio pairs only shapes on different joints: links welded together never are.
    candidates = {frozenset((link_of[i], link_of[j])) for i, j in every}
    ours = {frozenset((p.link1, p.link2)) for p in srdf.collision_pairs if p.disable}
    assert removed == ours & candidates
    assert removed  # the oracle has something to say
    assert len(srdf.collision_pairs) == {"panda": 35, "ur5": 10, "talos": 459}[robot]


def test_srdf_pairs_keep_reasons_lines_and_unknown_links(tmp_path: Path) -> None:
    (tmp_path / "r.srdf").write_text(
        '<robot name="r">\n'
        '<disable_collisions link1=" a " link2="b" reason="Adjacent"/>\n'
        '<enable_collisions link1="a" link2="ghost"/>\n'
        '<disable_default_collisions link="b"/>\n'
        '<disable_collisions link1="a"/>\n'
        "<disable_default_collisions/>\n"
        "</robot>\n"
    )
    srdf = with_links(parse_srdf(read_source(str(tmp_path / "r.srdf"))), ["a", "b"])
    assert srdf.collision_pairs == (
        CollisionPair(True, "a", "b", "Adjacent", 2),
        CollisionPair(False, "a", "ghost", None, 3, unknown=("ghost",)),
    )
    assert [(n.name, n.line) for n in srdf.no_default] == [("b", 4)]
    assert [line for line, _ in srdf.collision_notes] == [5, 6]
    assert srdf.notes == ()  # a report's srdf-ignored findings stay as they were


def test_srdf_collision_elements_are_bounded(tmp_path: Path) -> None:
    from cspace._formats.srdf._collisions import MAX_COLLISION_ELEMENTS

    pair = '<disable_collisions link1="a" link2="b"/>'
    (tmp_path / "r.srdf").write_text(
        f'<robot name="r">{pair * (MAX_COLLISION_ELEMENTS + 1)}</robot>'
    )
    with pytest.raises(InvalidElementError) as caught:
        parse_srdf(read_source(str(tmp_path / "r.srdf")))
    assert caught.value.code == "too-many-elements"
    long = "x" * 300
    (tmp_path / "n.srdf").write_text(
        f'<robot name="r"><disable_collisions link1="{long}" link2="b"/></robot>'
    )
    with pytest.raises(RobotFileError) as named:
        parse_srdf(read_source(str(tmp_path / "n.srdf")))
    assert named.value.code == "name-too-long"


# SDF, against Drake's parser (libsdformat inside).

DRAKE = Path(pydrake.__file__).parent / "share" / "drake" / "examples"
SDF_SHAPES = """<?xml version="1.0"?>
<sdf version="1.9">
  <model name="m">
    <frame name="f" attached_to="b"><pose>0 0 1 0 0 1.5707963267948966</pose></frame>
    <link name="a">
      <collision name="box"><pose>1 2 3 0.1 0.2 0.3</pose>
        <geometry><box><size>0.1 0.2 0.3</size></box></geometry></collision>
      <collision name="ball"><geometry><sphere><radius>0.5</radius></sphere></geometry>
      </collision>
    </link>
    <link name="b"><pose>0 1 0 0 0 0.5</pose>
      <collision name="can"><pose relative_to="f">0.5 0 0 0 0 0</pose>
        <geometry><cylinder><radius>0.25</radius><length>2</length></cylinder></geometry>
      </collision>
      <collision name="pill"><pose relative_to="a">0 0 0.5 0 0.3 0</pose>
        <geometry><capsule><radius>0.125</radius><length>0.5</length></capsule></geometry>
      </collision>
      <collision name="shell"><pose degrees="true">0 0 0 90 0 0</pose>
        <geometry><mesh><uri>MESH</uri><scale>2 2 0.5</scale></mesh></geometry>
      </collision>
    </link>
    <joint name="j" type="revolute"><parent>a</parent><child>b</child>
      <axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>
  </model>
</sdf>
"""


def drake_shapes(path: Path) -> dict[str, list[tuple[str, tuple[float, ...], object, object]]]:
    """Drake's collision geometries of ``path``, by body: shape, sizes, pose, mesh."""
    from pydrake.geometry import Box, Capsule, Cylinder, Mesh, SceneGraph, Sphere
    from pydrake.multibody.tree import BodyIndex

    plant = MultibodyPlant(0.0)
    scene = SceneGraph()
    plant.RegisterAsSourceForSceneGraph(scene)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    inspector = scene.model_inspector()
    shapes: dict[str, list[tuple[str, tuple[float, ...], object, object]]] = {}
    for index in range(plant.num_bodies()):
        body = plant.get_body(BodyIndex(index))
        for geometry in plant.GetCollisionGeometriesForBody(body):
            shape = inspector.GetShape(geometry)
            pose = inspector.GetPoseInFrame(geometry).GetAsMatrix4()
            if isinstance(shape, Box):
                item = ("box", (shape.width(), shape.depth(), shape.height()), pose, None)
            elif isinstance(shape, Sphere):
                item = ("sphere", (shape.radius(),), pose, None)
            elif isinstance(shape, Cylinder | Capsule):
                kind = "cylinder" if isinstance(shape, Cylinder) else "capsule"
                item = (kind, (shape.radius(), shape.length()), pose, None)
            else:
                assert isinstance(shape, Mesh)
                item = ("mesh", (), pose, (shape.source().path(), tuple(shape.scale3())))
            shapes.setdefault(body.name(), []).append(item)
    return shapes


def assert_sdf_is_drakes(path: Path) -> None:
    ours = {link.name: link for link in describe(path).links}
    theirs = drake_shapes(path)
    assert {name for name, link in ours.items() if link.collisions} == set(theirs)
    for name, shapes in theirs.items():
        mine = ours[name].collisions
        assert [c.kind for c in mine] == [s[0] for s in shapes]
        for spec, (kind, sizes, pose, mesh) in zip(mine, shapes, strict=True):
            assert spec.sizes == pytest.approx(sizes)
            assert np.allclose(placement(spec.origin).homogeneous, pose, atol=1e-9)
            if kind == "mesh":
                assert spec.mesh is not None and mesh is not None
                assert Path(mesh[0]).resolve() == (path.parent / spec.mesh).resolve()
                assert spec.scale == pytest.approx(mesh[1])


def test_sdf_shapes_and_poses_are_drakes(tmp_path: Path) -> None:
    (tmp_path / "shell.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "robot.sdf").write_text(SDF_SHAPES.replace("MESH", "shell.obj"))
    assert_sdf_is_drakes(tmp_path / "robot.sdf")
    links = {link.name: link for link in describe(tmp_path / "robot.sdf").links}
    assert [c.line for c in links["b"].collisions] == [12, 15, 18]


@pytest.mark.parametrize(
    "path",
    [DRAKE / "acrobot" / "Acrobot.sdf", DRAKE / "planar_gripper" / "planar_gripper.sdf"],
    ids=lambda p: p.stem,
)
def test_drakes_example_sdf_shapes_are_drakes(path: Path) -> None:
    assert_sdf_is_drakes(path)


def test_sdf_shapes_cspace_does_not_check_are_kept_unread() -> None:
    text = SDF_SHAPES.replace(
        '<collision name="ball"><geometry><sphere><radius>0.5</radius></sphere></geometry>',
        '<collision name="ball"><geometry><plane><normal>0 0 1</normal></plane></geometry>'
        '</collision><collision name="nan"><geometry><sphere><radius>nan</radius></sphere>'
        "</geometry>",
    ).replace('relative_to="f"', 'relative_to="nowhere"')
    links = {link.name: link for link in of_text(text, "robot.sdf").links}
    assert [c.kind for c in links["a"].collisions] == ["box"]
    assert [line for line, _ in links["a"].unread] == [8, 8]
    assert "<plane>" in links["a"].unread[0][1]
    assert "not a finite number" in links["a"].unread[1][1]
    assert [c.kind for c in links["b"].collisions] == ["capsule", "mesh"]  # the rest kept
    assert "relative_to='nowhere'" in links["b"].unread[0][1]


# Where a mesh's file name leads.


def test_erd_meshes_lead_where_pinocchio_finds_them() -> None:
    path = URDFS["talos"]
    packages, _, _ = ros_packages(str(path), str(path), ())
    allowed = mesh_paths.folders(str(path), packages)
    _, theirs = pinocchio_shapes(path)
    seen = 0
    for link in describe(path).links:
        for shape, other in zip(link.collisions, theirs.get(link.name, []), strict=True):
            mesh = shape.mesh
            if mesh is None:
                continue
            placed = mesh_paths.place(mesh, str(path), packages, allowed)
            assert placed.reason is None, placed
            assert placed.path == str(Path(other.meshPath).resolve())
            seen += 1
    assert seen > 40


def test_mesh_names_that_lead_nowhere_cspace_reads(tmp_path: Path) -> None:
    robot = tmp_path / "pkg" / "urdf" / "robot.urdf"
    (tmp_path / "pkg" / "meshes").mkdir(parents=True)
    robot.parent.mkdir()
    (tmp_path / "pkg" / "package.xml").write_text("<package><name>mine</name></package>")
    (tmp_path / "pkg" / "meshes" / "a.stl").write_bytes(b"solid a\nendsolid a\n")
    (tmp_path / "pkg" / "meshes" / "out.stl").symlink_to("/etc/hostname")
    (tmp_path / "pkg" / ".git").mkdir()
    (tmp_path / "pkg" / ".git" / "config").write_text("[core]\n")
    (tmp_path / "pkg" / "meshes" / "git").symlink_to("../.git")
    (tmp_path / "other.stl").write_bytes(b"")
    packages, _, _ = ros_packages(str(robot), str(robot), ())
    assert packages == {"mine": str((tmp_path / "pkg").resolve())}
    allowed = mesh_paths.folders(str(robot), packages)
    mesh = str((tmp_path / "pkg" / "meshes" / "a.stl").resolve())

    def where(name: str) -> str | None:
        placed = mesh_paths.place(name, str(robot), packages, allowed)
        assert (placed.path is None) != (placed.reason is None)
        return placed.path or placed.reason

    named = (
        "package://mine/meshes/a.stl",
        "model://mine/meshes/a.stl",
        "package://pkg/meshes/a.stl",
    )
    for name in (*named, "../meshes/a.stl", f"file://{mesh}", mesh):
        assert where(name) == mesh, name
    assert "package 'ros' is not known" in str(where("package://ros/meshes/a.stl"))
    assert "reads no network" in str(where("https://example.com/a.stl"))
    outside = "leads out of the folders cspace reads"
    escapes = ("package://mine/../../other.stl", "package://mine//etc/hostname")
    for name in (*escapes, "../../other.stl", "/etc/hostname", "file:///etc/hostname"):
        assert outside in str(where(name)), name
    assert outside in str(where("../meshes/out.stl"))  # a link out, followed
    assert "version-control" in str(where("../meshes/git/config"))
    assert str(where("../meshes/b.stl")).startswith("no such file")
    assert "empty" in str(where(" "))
    assert "NUL" in str(where("a\0.stl"))
    assert "standard input" in str(mesh_paths.place("a.stl", None, packages, allowed).reason)


def test_sdf_collisions_count_against_the_same_limit() -> None:
    links = "".join(
        f'<link name="l{i}">{"<collision/>" * 1000}</link>'
        for i in range(MAX_COLLISIONS // 1000 + 1)
    )
    with pytest.raises(InvalidElementError) as caught:
        of_text(f'<sdf version="1.9"><model name="m">{links}</model></sdf>', "robot.sdf")
    assert caught.value.code == "too-many-elements"


def test_a_mesh_name_longer_than_a_path_is_unread() -> None:
    long = "m" * 5000
    urdf = of_text(
        f'<robot name="r"><link name="a"><collision><geometry><mesh filename="{long}"/>'
        "</geometry></collision></link></robot>"
    )
    assert urdf.links[0].collisions == ()
    assert "longer than 4,096 characters" in urdf.links[0].unread[0][1]
    sdf = of_text(
        f'<sdf version="1.9"><model name="m"><link name="a"><collision name="c"><geometry>'
        f"<mesh><uri>{long}</uri></mesh></geometry></collision></link></model></sdf>",
        "robot.sdf",
    )
    link = next(link for link in sdf.links if link.name == "a")  # after the world's
    assert "longer than 4,096 characters" in link.unread[0][1]
