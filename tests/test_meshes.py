"""The mesh readers against their oracles: trimesh's loaders (STL, OBJ, and DAE through
pycollada) on example-robot-data's collision meshes and on small files written here,
and MuJoCo's own MSH reader on dm_control's MSH files.

Every mesh is parsed as cspace parses them: read through the one way in and parsed in
one confined child (`load_meshes`), one child for the whole module.
"""

from __future__ import annotations

import io
import struct
from pathlib import Path

import mujoco
import numpy as np
import pytest
import trimesh

from cspace._formats.meshes._bounds import Mesh
from cspace._formats.meshes.load import MeshFile, load_meshes
from cspace._formats.shared.erd import robots_dir

ERD = robots_dir()
ERD_MESHES = [
    "panda_description/meshes/collision/link3.stl",  # binary
    "talos_data/meshes/arm/arm_5_collision.STL",  # upper case
    "simple_humanoid_description/meshes/box.stl",  # the corpora's one ASCII STL
    "ur_description/meshes/ur5/collision/forearm.stl",
    "alexander_description/meshes/Foot.obj",
    "laikago_description/meshes/thigh_mirror.obj",
    "ur_description/meshes/ur5/visual/wrist3.dae",
    "hyq_description/meshes/leg/lowerleg.dae",  # polylist
    "panda_description/meshes/visual/finger.dae",
]
"""A sample of example-robot-data's meshes, each format and its variants."""

DM_CONTROL = Path(mujoco.__file__).parent.parent / "dm_control"
MSH = [
    "mjcf/test_assets/meshes/cube.msh",
    "locomotion/walkers/assets/fruitfly_v2/haltere_left_body.msh",
    "locomotion/walkers/assets/fruitfly_v2/antenna_left_black.msh",
]
"""dm_control's MSH files (its fruit fly's meshes, of a few hundred vertices)."""

OBJ = b"""# two groups, a quad, slashes and negative indices
o first
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vn 0 0 1
f 1/1/1 2/1/1 3/1/1 4/1/1
g second
v 0 0 1
v 1 0 1
v 0.5 1 2
f -3//1 -2//1 -1//1
f 5/1 6/1 7/1
usemtl x
f 1 2 5 6 7
"""
"""An OBJ of the features the reader reads: groups, polygons, each corner form."""

DAE = """<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="centimeter" meter="0.01"/><up_axis>Y_UP</up_axis></asset>
<library_geometries><geometry id="g"><mesh>
<source id="g-pos"><float_array id="g-arr" count="15">0 0 0 10 0 0 10 10 0 0 10 0 5 5 8
</float_array><technique_common><accessor source="#g-arr" count="5" stride="3">
<param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor>
</technique_common></source>
<source id="g-nrm"><float_array id="g-n" count="3">0 0 1</float_array><technique_common>
<accessor source="#g-n" count="1" stride="3"><param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="g-vtx"><input semantic="POSITION" source="#g-pos"/></vertices>
<triangles count="2"><input semantic="VERTEX" source="#g-vtx" offset="0"/>
<input semantic="NORMAL" source="#g-nrm" offset="1"/><p>0 0 1 0 4 0 1 0 2 0 4 0</p></triangles>
<polylist count="2"><input semantic="VERTEX" source="#g-vtx" offset="0"/>
<vcount>4 3</vcount><p>0 1 2 3 2 3 4</p></polylist>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s">
<node id="a"><translate>1 2 3</translate><rotate>0 0 1 90</rotate>
<instance_geometry url="#g"/>
<node id="b"><scale>2 1 1</scale><matrix>1 0 0 5 0 0 -1 0 0 1 0 0 0 0 0 1</matrix>
<instance_geometry url="#g"/></node></node>
</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""
"""A COLLADA file of every part the reader reads: unit, nodes' transforms, nested
instances, triangles with two inputs, a polylist."""


def _same_corners(ours: Mesh, theirs: trimesh.Trimesh, atol: float) -> None:
    """The triangles' corners of two readers are the same points, whatever their order."""
    from scipy.spatial import cKDTree

    mine = ours.vertices[ours.triangles.reshape(-1)]
    other = np.asarray(theirs.vertices)[np.asarray(theirs.faces).reshape(-1)]
    assert cKDTree(other).query(mine)[0].max() <= atol
    assert cKDTree(mine).query(other)[0].max() <= atol


def _trimesh(data: bytes, kind: str) -> trimesh.Trimesh:
    loaded = trimesh.load(io.BytesIO(data), file_type=kind, force="mesh", process=False)
    assert isinstance(loaded, trimesh.Trimesh)
    return loaded


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Small files of each feature, written once."""
    folder = tmp_path_factory.mktemp("meshes")
    files = {"feature.obj": OBJ, "feature.dae": DAE.encode()}
    box = _trimesh((ERD / ERD_MESHES[2]).read_bytes(), "stl")
    solid = b"solid" + b"\0" * 75 + struct.pack("<I", len(box.faces))  # a binary "solid"
    corners = box.vertices[box.faces].astype("<f4")
    record = np.dtype([("n", "<f4", (3,)), ("c", "<f4", (3, 3)), ("a", "<u2")])
    facets = np.zeros(len(box.faces), dtype=record)
    facets["c"] = corners
    files["solid.stl"] = solid + facets.tobytes()
    msh = struct.pack("<4i", 4, 0, 0, 0) + np.eye(4, 3, dtype="<f4").tobytes()
    files["cloud.msh"] = msh  # no faces: MuJoCo takes the hull of the points
    for name, data in files.items():
        (folder / name).write_bytes(data)
    return {name: folder / name for name in files}


@pytest.fixture(scope="module")
def parsed(written: dict[str, Path]) -> dict[str, Mesh]:
    """Every mesh of this module, parsed in one child; the last one scaled."""
    paths = [ERD / m for m in ERD_MESHES] + [DM_CONTROL / m for m in MSH] + list(written.values())
    files = [MeshFile(str(p)) for p in paths]
    files.append(MeshFile(str(written["feature.obj"]), scale=(2.0, -3.0, 0.5)))
    meshes = load_meshes(files)
    for file, mesh in zip(files, meshes, strict=True):
        assert isinstance(mesh, Mesh), (file, mesh)
    keys = [*ERD_MESHES, *MSH, *written, "scaled.obj"]
    return {key: mesh for key, mesh in zip(keys, meshes, strict=True) if isinstance(mesh, Mesh)}


@pytest.mark.parametrize("name", ERD_MESHES)
def test_example_robot_data_meshes_read_as_trimesh_reads_them(
    name: str, parsed: dict[str, Mesh]
) -> None:
    mesh = parsed[name]
    oracle = _trimesh((ERD / name).read_bytes(), name.rsplit(".", 1)[1].lower())
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape[1] == 3
    assert mesh.triangles.dtype == np.int32 and mesh.triangles.shape[1] == 3
    assert len(mesh.triangles) == len(oracle.faces) > 0
    np.testing.assert_allclose(
        mesh.vertices[mesh.triangles.reshape(-1)].min(axis=0), oracle.bounds[0], atol=1e-6
    )
    np.testing.assert_allclose(
        mesh.vertices[mesh.triangles.reshape(-1)].max(axis=0), oracle.bounds[1], atol=1e-6
    )
    _same_corners(mesh, oracle, atol=1e-6)


@pytest.mark.parametrize("name", ["feature.obj", "feature.dae", "solid.stl"])
def test_each_feature_reads_as_trimesh_reads_it(
    name: str, parsed: dict[str, Mesh], written: dict[str, Path]
) -> None:
    mesh = parsed[name]
    oracle = _trimesh(written[name].read_bytes(), name.rsplit(".", 1)[1])
    if name.endswith(".dae"):  # pycollada (and assimp) leave out <unit>: the file's is 0.01
        mesh = Mesh(mesh.vertices / 0.01, mesh.triangles)
    assert len(mesh.triangles) == len(oracle.faces)
    _same_corners(mesh, oracle, atol=1e-5 if name.endswith(".dae") else 1e-9)  # float32


def test_obj_polygons_fan_and_groups_make_one_mesh(parsed: dict[str, Mesh]) -> None:
    mesh = parsed["feature.obj"]
    assert len(mesh.vertices) == 7
    assert mesh.triangles.tolist() == [
        [0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 5, 6], [0, 1, 4], [0, 4, 5], [0, 5, 6]
    ]  # fmt: skip


def test_dae_places_each_instance_and_ignores_up_axis(parsed: dict[str, Mesh]) -> None:
    mesh = parsed["feature.dae"]
    assert len(mesh.vertices) == 10 and len(mesh.triangles) == 2 * 5
    # node a: a quarter turn about z, then (1, 2, 3); the file's unit is the centimetre
    np.testing.assert_allclose(mesh.vertices[1], [0.01, 0.02 + 0.1, 0.03], atol=1e-12)


def test_scale_multiplies_each_axis(parsed: dict[str, Mesh]) -> None:
    np.testing.assert_array_equal(
        parsed["scaled.obj"].vertices, parsed["feature.obj"].vertices * [2.0, -3.0, 0.5]
    )
    np.testing.assert_array_equal(parsed["scaled.obj"].triangles, parsed["feature.obj"].triangles)


@pytest.mark.parametrize("name", MSH)
def test_msh_reads_as_mujoco_reads_it(name: str, parsed: dict[str, Mesh]) -> None:
    """MuJoCo moves a mesh to its centre of mass and principal axes: the distances of the
    vertices from their centroid are what both keep."""
    mesh = parsed[name]
    spec = mujoco.MjSpec()
    asset = spec.add_mesh()
    asset.name, asset.file = "m", str(DM_CONTROL / name)
    geom = spec.worldbody.add_body().add_geom()
    geom.type, geom.meshname = mujoco.mjtGeom.mjGEOM_MESH, "m"
    model = spec.compile()
    theirs = model.mesh_vert[: model.mesh_vertnum[0]]
    assert len(mesh.triangles) == model.mesh_facenum[0] > 0
    assert len(mesh.vertices) == len(theirs)
    np.testing.assert_allclose(
        np.sort(np.linalg.norm(mesh.vertices - mesh.vertices.mean(axis=0), axis=1)),
        np.sort(np.linalg.norm(theirs - theirs.mean(axis=0), axis=1)),
        atol=1e-5,
    )


def test_msh_without_faces_is_its_vertices(parsed: dict[str, Mesh]) -> None:
    mesh = parsed["cloud.msh"]
    np.testing.assert_array_equal(mesh.vertices, np.eye(4, 3))
    assert mesh.triangles.shape == (0, 3)
