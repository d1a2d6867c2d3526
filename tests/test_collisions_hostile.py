"""Hostile robots for ``cspace collisions``: files a pull request writes so that a broken
robot would pass, or cspace would fail, each held to what it must do instead.

Each test loads real files (meshes, URDF, SRDF, saved reports) written here.
"""

from __future__ import annotations

import json
import shutil
import struct
from pathlib import Path

import numpy as np
import pytest

import cspace
from cspace._formats.meshes._bounds import Mesh
from cspace._formats.meshes.load import MeshFile, MeshLimits, load_meshes
from cspace.errors import RobotFileError

pytestmark = pytest.mark.bounded

_FACES = [
    (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
    (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3),
]  # fmt: skip


def _box_corners(sx: float, sy: float, sz: float) -> list[tuple[float, float, float]]:
    return [(x * sx / 2, y * sy / 2, z * sz / 2) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]


def box_stl(sx: float, sy: float, sz: float) -> bytes:
    """A binary STL of a box of sides ``sx``, ``sy``, ``sz`` (m), centred."""
    corners = _box_corners(sx, sy, sz)
    out = [b"\0" * 80, struct.pack("<I", len(_FACES))]
    for face in _FACES:
        out.append(struct.pack("<3f", 0, 0, 0))
        out += [struct.pack("<3f", *corners[i]) for i in face]
        out.append(b"\0\0")
    return b"".join(out)


def heavy_obj(faces: int) -> bytes:
    """An OBJ of one triangle written ``faces`` times: cheap bytes, seconds to parse."""
    return b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * faces


def test_a_mesh_that_stops_the_parser_does_not_take_the_others_with_it(
    tmp_path: Path,
) -> None:
    """One mesh heavy enough to spend the child's CPU: the robot's other meshes are still
    read (it was every mesh of the robot refused, so every link left out)."""
    small = tmp_path / "small.stl"
    small.write_bytes(box_stl(0.1, 0.1, 0.1))
    heavy = tmp_path / "heavy.obj"
    heavy.write_bytes(heavy_obj(1_500_000))
    tight = MeshLimits(cpu_seconds=2, wall_seconds=20.0)
    files = [MeshFile(str(small)), MeshFile(str(heavy)), MeshFile(str(small), (2.0, 2.0, 2.0))]
    results = load_meshes(files, limits=tight)
    assert isinstance(results[0], Mesh) and isinstance(results[2], Mesh), results
    assert np.allclose(results[2].vertices, 2 * results[0].vertices)
    error = results[1]
    assert isinstance(error, RobotFileError) and "CPU" in error.problem, error


ARM = Path(__file__).parent.parent / "docs/examples/folding_arm.urdf"
ARM_SRDF = Path(__file__).parent.parent / "docs/examples/folding_arm.srdf"


def mesh_arm(folder: Path, fore: str, data: bytes) -> Path:
    """docs/examples/folding_arm with its forearm the mesh ``fore`` holding ``data``, and
    its SRDF (which disables base-fore, a pair that collides) beside it."""
    (folder / fore).write_bytes(data)
    (folder / "base.stl").write_bytes(box_stl(0.4, 0.4, 0.1))
    text = ARM.read_text()
    text = text.replace('<box size="0.4 0.4 0.1"/>', '<mesh filename="base.stl"/>')
    text = text.replace('<box size="0.05 0.05 0.4"/>', f'<mesh filename="{fore}"/>')
    robot = folder / "arm.urdf"
    robot.write_text(text)
    (folder / "arm.srdf").write_text(ARM_SRDF.read_text())
    return robot


@pytest.mark.parametrize(
    ("name", "data"),
    [
        ("empty.stl", b"\0" * 80 + struct.pack("<I", 0)),
        ("points.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"),
    ],
    ids=["empty-stl", "points-obj"],
)
def test_a_mesh_without_triangles_is_a_link_skipped_not_a_crash(
    tmp_path: Path, name: str, data: bytes
) -> None:
    """coal builds no BVH of a mesh without triangles and Pinocchio's check then failed:
    an internal error of cspace for a file a pull request writes."""
    report = cspace.collisions(mesh_arm(tmp_path, name, data), samples=50, srdf=True)
    skipped = [d for d in report.diagnostics if d.code == "collision-skipped"]
    assert len(skipped) == 1 and "'fore'" in skipped[0].message, report.diagnostics
    assert "no triangles" in skipped[0].message
    assert report.links == ("base", "upper")


def _collada(primitives: str, scene: str, library: str = "") -> bytes:
    """A COLLADA file of one geometry ``g``: the forearm's box (0.05 x 0.05 x 0.4 m, its
    base at z = 0), its faces given by ``primitives``, placed by ``scene``."""
    corners = [(x, y, z) for z in (0.0, 0.4) for y in (-0.025, 0.025) for x in (-0.025, 0.025)]
    numbers = " ".join(f"{v:g}" for c in corners for v in c)
    return f"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<library_geometries><geometry id="g"><mesh>
<source id="s"><float_array id="a" count="24">{numbers}</float_array>
<technique_common><accessor source="#a" count="8" stride="3"/></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#s"/></vertices>
{primitives}
</mesh></geometry></library_geometries>{library}
<library_visual_scenes><visual_scene id="sc">{scene}</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#sc"/></scene></COLLADA>""".encode()


_INPUT = '<input semantic="VERTEX" source="#v" offset="0"/>'
# the box's 12 triangles; as 3 strips (sides, top, bottom); as 6 fans (one a face)
_TRIANGLES = (
    f'<triangles count="12">{_INPUT}<p>0 1 3 0 3 2 4 6 7 4 7 5 0 4 5 0 5 1 2 3 7 2 7 6 '
    "0 2 6 0 6 4 1 5 7 1 7 3</p></triangles>"
)
_STRIPS = (
    f'<tristrips count="3">{_INPUT}<p>0 4 1 5 3 7 2 6 0 4</p><p>4 5 6 7</p><p>0 2 1 3</p>'
    "</tristrips>"
)
_FANS = (
    f'<trifans count="6">{_INPUT}<p>0 1 3 2</p><p>4 6 7 5</p><p>0 4 5 1</p><p>2 3 7 6</p>'
    "<p>0 2 6 4</p><p>1 5 7 3</p></trifans>"
)
_PLACED = '<node id="n"><instance_geometry url="#g"/></node>'
_LIBRARY = '<library_nodes><node id="lib"><instance_geometry url="#g"/></node></library_nodes>'
_BY_INSTANCE = '<node id="top"><instance_node url="#lib"/></node>'


def _faces(mesh: Mesh) -> set[frozenset[tuple[float, ...]]]:
    return {frozenset(tuple(mesh.vertices[i]) for i in t) for t in mesh.triangles}


@pytest.mark.parametrize(
    ("primitives", "scene", "library"),
    [(_STRIPS, _PLACED, ""), (_FANS, _PLACED, ""), (_TRIANGLES, _BY_INSTANCE, _LIBRARY)],
    ids=["tristrips", "trifans", "instance_node"],
)
def test_collada_parts_assimp_reads_are_read(primitives: str, scene: str, library: str) -> None:
    """Triangle strips, fans and nodes placed by <instance_node> are read (assimp, so
    MoveIt, reads them): a box written so was no triangle at all, and one part of a mesh
    written so would go missing without a word, its collisions with it."""
    from cspace._formats.meshes._read import read_mesh

    reference = read_mesh("dae", _collada(_TRIANGLES, _PLACED), (1.0, 1.0, 1.0))
    mesh = read_mesh("dae", _collada(primitives, scene, library), (1.0, 1.0, 1.0))
    assert len(mesh.triangles) == 12
    corners = mesh.vertices[mesh.triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    area = np.linalg.norm(normals, axis=1).sum() / 2  # the box's surface, once
    assert area == pytest.approx(2 * 0.05 * 0.05 + 4 * 0.05 * 0.4)
    if primitives != _STRIPS:  # strips split the sides on other diagonals
        assert _faces(mesh) == _faces(reference)


def test_a_forearm_of_triangle_strips_is_checked(tmp_path: Path) -> None:
    """The SRDF disables base-fore, which collide: found with the forearm's mesh in strips."""
    robot = mesh_arm(tmp_path, "fore.dae", _collada(_STRIPS, _PLACED))
    report = cspace.collisions(robot, samples=2000, srdf=True)
    codes = [d.code for d in report.diagnostics]
    assert "collision-disabled-but-reachable" in codes, report.diagnostics


ALWAYS_97 = """<?xml version="1.0"?>
<robot name="always97">
  <link name="base"><collision><geometry><box size="1 1 1"/></geometry></collision></link>
  <link name="mid"><collision><origin xyz="0 0 5"/><geometry><sphere radius="0.05"/></geometry>
  </collision></link>
  <link name="tip"><collision><origin xyz="0.62 0 0"/><geometry><sphere radius="0.1"/>
  </geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="mid"/><axis xyz="0 0 1"/>
    <limit lower="-0.01" upper="0.01" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="mid"/><child link="tip"/><axis xyz="1 0 0"/>
    <limit lower="-0.62" upper="0" effort="1" velocity="1"/></joint>
</robot>
"""
"""base and tip collide when j2 < -0.02: in about 97% of samples, free at the default."""


def test_a_report_with_a_pair_always_in_collision_short_of_every_sample_is_a_baseline(
    tmp_path: Path,
) -> None:
    """cspace classes a pair in collision in 95% of samples or more ``always`` (MoveIt's
    share): its own report of such a pair was refused as a baseline line (exit 2)."""
    from conftest import run_cli

    (tmp_path / "a.urdf").write_text(ALWAYS_97)
    drawn = run_cli("collisions", "a.urdf", "-n", "1000", "--format", "jsonl", cwd=tmp_path)
    assert drawn.code == 0, drawn.stderr
    (pair,) = [p for p in json.loads(drawn.stdout)["pairs"] if p["kind"] != "adjacent"]
    assert pair["kind"] == "always" and 950 <= pair["collisions"]["hits"] < 1000, pair
    (tmp_path / "b.jsonl").write_text(drawn.stdout)
    run = run_cli("check", "--baseline", "b.jsonl", "a.urdf", cwd=tmp_path)
    assert run.code == 1 and run.stderr == "", run.stdout + run.stderr  # 1: no C-space line
    assert "same: a.urdf: self-collision: 3 pairs, classes and rules as accepted" in run.stdout


def test_an_srdf_added_since_the_accepted_report_is_read_when_the_check_names_it(
    tmp_path: Path,
) -> None:
    """A baseline's line drawn without an SRDF, then an SRDF disabling a pair that
    collides: ``check --srdf auto`` (or ``--srdf FILE``) read no SRDF and said ``same``."""
    from conftest import run_cli

    shutil.copy(ARM, tmp_path / "arm.urdf")
    lines = [
        run_cli("inspect", "arm.urdf", "--format", "jsonl", cwd=tmp_path).stdout,
        run_cli("collisions", "arm.urdf", "-n", "500", "--format", "jsonl", cwd=tmp_path).stdout,
    ]
    (tmp_path / "b.jsonl").write_text("".join(lines))
    shutil.copy(ARM_SRDF, tmp_path / "arm.srdf")
    for srdf in ("auto", "arm.srdf"):
        run = run_cli("check", "--baseline", "b.jsonl", "arm.urdf", "--srdf", srdf, cwd=tmp_path)
        assert run.code == 1, run.stdout + run.stderr
        assert "changed: arm.urdf: self-collision matrix: matrix none -> srdf" in run.stdout
        assert "'base'-'fore' rule no file says -> disabled (Never)" in run.stdout
    github = run_cli(
        "check", "--baseline", "b.jsonl", "arm.urdf", "--srdf", "auto", "--format", "github",
        cwd=tmp_path,
    )  # fmt: skip
    assert "cspace collisions arm.urdf --srdf auto -n 500 --seed 0" in github.stdout


def test_an_srdf_found_first_beside_the_robot_cannot_stand_in_for_the_accepted_one(
    tmp_path: Path,
) -> None:
    """The accepted line read config/arm.srdf; a pull request copies it beside the robot
    (where --srdf auto looks first) and makes config/arm.srdf, MoveIt's, disable a pair
    that collides: the check read the copy and said ``same``."""
    from conftest import run_cli

    shutil.copy(ARM, tmp_path / "arm.urdf")
    (tmp_path / "config").mkdir()
    good = "".join(line for line in ARM_SRDF.open() if "Never" not in line)
    (tmp_path / "config" / "arm.srdf").write_text(good)
    drawn = [("inspect",), ("collisions", "--srdf", "auto", "-n", "500")]
    lines = [run_cli(c[0], "arm.urdf", *c[1:], "--format", "jsonl", cwd=tmp_path) for c in drawn]
    (tmp_path / "b.jsonl").write_text("".join(run.stdout for run in lines))
    (tmp_path / "arm.srdf").write_text(good)
    shutil.copy(ARM_SRDF, tmp_path / "config" / "arm.srdf")
    run = run_cli("check", "--baseline", "b.jsonl", "arm.urdf", cwd=tmp_path)
    assert run.code == 1, run.stdout + run.stderr
    assert "matrix srdf config/arm.srdf -> srdf arm.srdf" in run.stdout


def test_a_point_set_that_stops_the_hull_child_does_not_take_the_others_with_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """OpenUSD meshes PhysX collides as hulls: one cloud whose hull spends the child's CPU
    left every hull of the stage uncomputed (every such link unchecked)."""
    from cspace._model import _collision_hull

    monkeypatch.setattr(_collision_hull, "CPU_SECONDS", 2)
    tetra = np.array([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], dtype=float)
    sphere = np.random.default_rng(0).normal(size=(400_000, 3))
    sphere /= np.linalg.norm(sphere, axis=1)[:, None]  # every point a vertex of the hull
    hulls = _collision_hull.convex_hulls([tetra, sphere, tetra * 2])
    assert isinstance(hulls[0], Mesh) and isinstance(hulls[2], Mesh), hulls
    assert len(hulls[0].triangles) == 4 and np.allclose(hulls[2].vertices.max(axis=0), 2)
    assert isinstance(hulls[1], str) and "CPU" in hulls[1], hulls[1]
