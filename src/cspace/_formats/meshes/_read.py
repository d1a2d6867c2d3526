"""One mesh file's bytes to a mesh, by its format, the robot's totals counted."""

from __future__ import annotations

from typing import TYPE_CHECKING

from cspace._formats.meshes._bounds import (
    FORMATS,
    MAX_TOTAL_TRIANGLES,
    MAX_TOTAL_VERTICES,
    MeshProblem,
)

if TYPE_CHECKING:
    from cspace._formats.meshes._bounds import Mesh


def mesh_format(name: str) -> str | None:
    """The format a mesh file's name says (``stl``, ``obj``, ``msh``, ``dae``), or None."""
    ending = name.rsplit(".", 1)[-1].lower() if "." in name else ""
    return ending if ending in FORMATS else None


def read_mesh(kind: str, data: bytes, scale: tuple[float, float, float]) -> Mesh:
    """The mesh of a file of format ``kind``, scaled.

    Raises:
        MeshProblem: The file is not one of that format, or breaks a bound.
    """
    from cspace._formats.meshes import _dae, _msh, _obj, _stl

    readers = {
        "stl": _stl.read_stl,
        "obj": _obj.read_obj,
        "msh": _msh.read_msh,
        "dae": _dae.read_dae,
    }
    if kind not in readers:
        raise MeshProblem(f"not a mesh format cspace reads ({', '.join(FORMATS)})")
    if not data.strip():
        raise MeshProblem("the file is empty")
    return readers[kind](data, scale)


class Totals:
    """The vertices and triangles of a robot's meshes read so far, against their bounds."""

    def __init__(self) -> None:
        self.vertices = 0
        self.triangles = 0

    def add(self, mesh: Mesh) -> None:
        """Count a mesh.

        Raises:
            MeshProblem: The robot's meshes now pass `MAX_TOTAL_VERTICES` or
                `MAX_TOTAL_TRIANGLES` (the mesh is not counted).
        """
        vertices = self.vertices + len(mesh.vertices)
        triangles = self.triangles + len(mesh.triangles)
        if vertices > MAX_TOTAL_VERTICES or triangles > MAX_TOTAL_TRIANGLES:
            raise MeshProblem(
                f"the robot's meshes reach {vertices:,} vertices and {triangles:,} triangles "
                f"with this one, more than the {MAX_TOTAL_VERTICES:,} and "
                f"{MAX_TOTAL_TRIANGLES:,} cspace reads for one robot"
            )
        self.vertices, self.triangles = vertices, triangles
