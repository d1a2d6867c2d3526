"""Hostile mesh files: each refused with one line naming the mesh (and its line where it
has one), in bounded time, and the robot's other meshes still read.

Every file here is parsed in one confined child (`load_meshes`), as a robot's meshes
are; the CPU time of the whole run, the child's included, is bounded.
"""

from __future__ import annotations

import os
import resource
import struct
from pathlib import Path

import numpy as np
import pytest

from cspace._formats.meshes._bounds import (
    MAX_DAE_DEPTH,
    MAX_DAE_NODES,
    MAX_MESH_BYTES,
    MAX_OBJ_LINES,
    MAX_TOTAL_VERTICES,
    Mesh,
    MeshProblem,
)
from cspace._formats.meshes._read import Totals
from cspace._formats.meshes.load import MeshFile, MeshLimits, load_meshes
from cspace._formats.shared.erd import robots_dir
from cspace.errors import RobotFileError

from conftest import SECONDS

pytestmark = pytest.mark.bounded

GOOD = robots_dir() / "panda_description/meshes/collision/link3.stl"


def _binary_stl(triangles: int, told: int | None = None) -> bytes:
    header = b"\0" * 80 + struct.pack("<I", triangles if told is None else told)
    return header + b"\0" * (50 * triangles)


def _ascii_stl(*corners: str) -> bytes:
    lines = ["solid s", " facet normal 0 0 1", "  outer loop"]
    lines += [f"   vertex {c}" for c in corners]
    return ("\n".join([*lines, "  endloop", " endfacet", "endsolid s"]) + "\n").encode()


def _msh(nvertex: int, nnormal: int, ntexcoord: int, nface: int, floats: int = 0) -> bytes:
    return struct.pack("<4i", nvertex, nnormal, ntexcoord, nface) + b"\0" * (4 * floats)


def _dae(nodes: str, positions: str = "0 0 0 1 0 0 0 1 0", p: str = "0 1 2") -> bytes:
    count = len(positions.split())
    return f"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<library_geometries><geometry id="g"><mesh>
<source id="s"><float_array id="a" count="{count}">{positions}</float_array></source>
<vertices id="v"><input semantic="POSITION" source="#s"/></vertices>
<triangles count="{len(p.split()) // 3}"><input semantic="VERTEX" source="#v" offset="0"/>
<p>{p}</p></triangles></mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="scene">{nodes}</visual_scene>
</library_visual_scenes></COLLADA>
""".encode()


PLACED = '<node><instance_geometry url="#g"/></node>'

LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE c [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]>
<COLLADA>&b;</COLLADA>
"""

HOSTILE: dict[str, tuple[bytes, str, int | None]] = {
    "truncated.stl": (_binary_stl(10)[:-20], "neither binary STL", None),
    "lying.stl": (_binary_stl(2, told=1_000_000), "its header says 1,000,000 triangles", None),
    "nan.stl": (_ascii_stl("nan 0 0", "1 0 0", "0 1 0"), "vertex 1 is not finite", None),
    "word.stl": (_ascii_stl("0 0 0", "1 x 0", "0 1 0"), "three numbers ('x')", 5),
    "short.stl": (_ascii_stl("0 0 0", "1 0 0"), "truncated or malformed", None),
    "range.obj": (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "names vertex 9", 4),
    "zero.obj": (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 0 1 2\n", "names vertex 0", 5),
    "negative.obj": (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -2 -1\n", "names vertex -4", 4),
    "late.obj": (b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "0 vertices are defined before", 1),
    "inf.obj": (b"v 1e400 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "vertex 1 is not finite", None),
    "word.obj": (b"v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n", "not a number ('abc')", 2),
    "underscore.obj": (b"v 0 0 0\nv 1_0 0 0\nv 0 1 0\nf 1 2 3\n", "not a number ('1_0')", 2),
    "corner.obj": (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/3\n", "not a vertex index", 4),
    "lines.obj": (b"#\n" * MAX_OBJ_LINES, f"more than the {MAX_OBJ_LINES:,}", None),
    "empty.obj": (b" \n\n", "the file is empty", None),
    "truncated.msh": (_msh(4, 0, 0, 2, 12 + 6)[:-8], "truncated or not an MSH", None),
    "lying.msh": (_msh(2_000_000, 0, 0, 0, 12), "2,000,000 vertices, more than", None),
    "negative.msh": (_msh(4, -1, 0, 0, 12), "no negative count", None),
    "normals.msh": (_msh(4, 3, 0, 0, 21), "none or one a vertex", None),
    "deep.dae": (
        _dae("<node>" * (MAX_DAE_DEPTH + 1) + "</node>" * (MAX_DAE_DEPTH + 1)),
        f"nested deeper than {MAX_DAE_DEPTH}",
        8,
    ),
    "nodes.dae": (_dae("<node/>" * (MAX_DAE_NODES + 1)), f"more than {MAX_DAE_NODES:,}", 8),
    "instances.dae": (
        _dae("<node>" + '<instance_geometry url="#g"/>' * 9_000 + "</node>", "0 0 0 " * 120),
        "vertices, more than the 1,000,000 a mesh may have",
        None,
    ),
    "range.dae": (_dae(PLACED, p="0 1 7"), "beyond", 3),
    "count.dae": (
        _dae(PLACED, positions="0 0 0 1 0 0 0 1 0").replace(b'count="9"', b'count="30"'),
        "fewer than the 30",
        4,
    ),
    "digits.dae": (_dae(PLACED, positions="0 0 0 1_0 0 0 0 1 0"), "not a number", 4),
    "index.dae": (_dae(PLACED, p="0 1 \u0662"), "not an index", 7),
    "words.dae": (_dae(PLACED, positions="0 0 0 1 0 zero 0 1 0"), "not a number", 4),
    "entity.dae": (LAUGHS, "declares the XML entity 'a'", 2),
    "binary.dae": (b"\x00\xff" * 64, "not XML", 1),
}
"""Each hostile file: its bytes, what its one line says, the line it names."""


@pytest.fixture(scope="module")
def loaded(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, object], float]:
    """Each file's result, the good mesh's last, and the CPU seconds of the one run."""
    folder = tmp_path_factory.mktemp("hostile_meshes")
    for name, (data, _, _) in HOSTILE.items():
        (folder / name).write_bytes(data)
    os.mkfifo(folder / "fifo.stl")
    with open(folder / "huge.stl", "wb") as sparse:  # a file of holes: nothing written
        sparse.truncate(MAX_MESH_BYTES + 1)
    (folder / "mesh.ply").write_bytes(b"ply\n")
    names = [*HOSTILE, "fifo.stl", "huge.stl", "mesh.ply"]
    files = [MeshFile(str(folder / name)) for name in names] + [MeshFile(str(GOOD))]
    before = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    results = load_meshes(files)
    after = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = sum(
        a.ru_utime - b.ru_utime + a.ru_stime - b.ru_stime
        for a, b in zip(after, before, strict=True)
    )
    return dict(zip([*names, "good"], results, strict=True)), cpu


def _one_line(error: object, name: str) -> RobotFileError:
    assert isinstance(error, RobotFileError), error
    text = str(error)
    assert "\n" not in text and "\r" not in text
    assert Path(error.path).name == name and text.startswith(error.path)
    return error


@pytest.mark.parametrize("name", list(HOSTILE))
def test_a_hostile_mesh_is_one_line_naming_it(name: str, loaded: tuple[dict, float]) -> None:
    _, says, line = HOSTILE[name]
    error = _one_line(loaded[0][name], name)
    assert error.code == "bad-mesh"
    assert says in error.problem, error.problem
    assert error.line == line, error
    assert str(error).startswith(
        f"{error.path}:{line}: mesh: " if line else f"{error.path}: mesh: "
    )


@pytest.mark.parametrize(
    ("name", "code", "says"),
    [
        ("fifo.stl", "file-unreadable", "FIFO"),
        ("huge.stl", "file-unreadable", f"{MAX_MESH_BYTES:,}-byte limit"),
        ("mesh.ply", "bad-mesh", "not a mesh format"),
    ],
)
def test_a_mesh_file_is_read_through_the_one_way_in(
    name: str, code: str, says: str, loaded: tuple[dict, float]
) -> None:
    error = _one_line(loaded[0][name], name)
    assert error.code == code and says in error.problem, error


def test_the_robots_other_meshes_are_read_within_the_time_bound(
    loaded: tuple[dict, float],
) -> None:
    results, cpu = loaded
    good = results["good"]
    assert isinstance(good, Mesh) and good.triangles.shape == (len(good.vertices) // 3, 3)
    assert cpu < SECONDS, cpu


def test_a_robots_meshes_are_bounded_in_all() -> None:
    totals = Totals()
    part = Mesh(np.empty((MAX_TOTAL_VERTICES // 4, 3)), np.empty((0, 3), dtype=np.int32))
    for _ in range(4):
        totals.add(part)
    with pytest.raises(MeshProblem, match="4,000,001 vertices"):
        totals.add(Mesh(np.empty((1, 3)), np.empty((0, 3), dtype=np.int32)))


def test_a_child_that_reaches_its_limits_fails_each_mesh_in_one_line() -> None:
    tight = MeshLimits(cpu_seconds=5, wall_seconds=20.0, memory_bytes=24 * 1024**2)
    results = load_meshes([MeshFile(str(GOOD)), MeshFile(str(GOOD))], limits=tight)
    for result in results:
        error = _one_line(result, GOOD.name)
        assert error.code == "bad-mesh" and "the mesh parser" in error.problem, error


def test_a_robots_mesh_files_are_bounded_in_bytes() -> None:
    """The robot's bound, lowered to two of these files: the third is refused and never
    handed to the child; the two before it are parsed."""
    size = GOOD.stat().st_size
    files = [MeshFile(str(GOOD)), MeshFile(str(GOOD)), MeshFile(str(GOOD))]
    results = load_meshes(files, robot_bytes=2 * size)
    assert isinstance(results[0], Mesh) and isinstance(results[1], Mesh)
    error = _one_line(results[2], GOOD.name)
    assert error.code == "bad-mesh"
    assert f"pass the {2 * size:,} bytes cspace reads for one robot" in error.problem
