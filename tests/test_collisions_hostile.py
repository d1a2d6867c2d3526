"""Hostile robots for ``cspace collisions``: files a pull request writes so that a broken
robot would pass, or cspace would fail, each held to what it must do instead.

Each test loads real files (meshes, URDF, SRDF, saved reports) written here.
"""

from __future__ import annotations

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
