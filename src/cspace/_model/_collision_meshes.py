"""The meshes of a robot's collision shapes, found and read, or why not.

A USD stage's meshes are its own data (``usd:`` names, `usd._collision`): the stage's
OpenUSD child reads their arrays. Each other mesh shape's file name leads to a file
(`cspace._formats.shared.mesh_paths.place`: ROS packages, ``model://``, relative and
absolute names, held to the robot's project, its packages and the folders the user
allows), and every file found is read and parsed
once, at each scale it is used at, by cspace's own readers in their confined child
(`cspace._formats.meshes.load.load_meshes`). A mesh that leads nowhere or is refused
is a `ShapeProblem` naming the link, the ``<collision>`` line and the mesh, and so is a
mesh without triangles (coal makes no shape of it); the others are ready for
`cspace._model._collision_shapes.build_shapes`.
"""

import os
from collections.abc import Mapping, Sequence

from cspace._formats.meshes._bounds import Mesh
from cspace._formats.meshes.load import MeshFile, MeshLimits, load_meshes, problem_of
from cspace._formats.shared import mesh_paths
from cspace._formats.shared.description import LinkSpec
from cspace._formats.usd._collision import is_inline
from cspace._model._collision_shapes import MeshKey, mesh_key
from cspace._record import NamedTuple
from cspace.errors import RobotFileError

NO_TRIANGLES = "no triangles cspace reads in it, so nothing to collide"
"""The problem of a mesh read whole that holds no triangle (vertices only, or none)."""


class ShapeProblem(NamedTuple):
    """A mesh shape whose mesh cannot be had.

    Attributes:
        link: The shape's link.
        line: Its ``<collision>`` element's line, or None.
        mesh: The mesh's file name as written (not escaped: escape it to print it).
        problem: Why, in one line (the reason it leads nowhere, or the reader's error at
            the mesh file's line when it has one, `problem_of`).
    """

    link: str
    line: int | None
    mesh: str
    problem: str


class ShapeMeshes(NamedTuple):
    """The meshes of a robot's shapes.

    Attributes:
        meshes: Each mesh read, by `mesh_key`.
        problems: Each mesh shape without its mesh, in the file's order.
    """

    meshes: dict[MeshKey, Mesh]
    problems: tuple[ShapeProblem, ...]


def read_shape_meshes(
    links: Sequence[LinkSpec],
    robot_file: str,
    packages: Mapping[str, str],
    *,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    limits: MeshLimits | None = None,
) -> ShapeMeshes:
    """Find and read the meshes of ``links``' collision shapes.

    Args:
        links: The description's links.
        robot_file: The robot file on disk (its folder and project lead to meshes).
        packages: The ROS packages known, name to folder.
        allow_dirs: Folders the user allows beside the project's and the packages'.
        limits: The mesh parser's bounds (default `MeshLimits()`).

    Raises:
        FileUnreadableError: An ``allow_dirs`` folder reached through a link out of it.
    """
    allowed = mesh_paths.folders(robot_file, packages, [str(d) for d in allow_dirs])
    why_not: dict[MeshKey, str] = {}
    wanted: dict[MeshKey, MeshFile] = {}
    inline: dict[MeshKey, None] = {}  # a USD stage's own meshes
    stage = _usd_stage(robot_file)  # a URDF's "usd:..." is a file name
    for link in links:
        for shape in link.collisions:
            key = mesh_key(shape)
            if shape.kind != "mesh" or key in why_not or key in wanted or key in inline:
                continue
            if stage and is_inline(key[0]):
                inline[key] = None
                continue
            place = mesh_paths.place(key[0], robot_file, packages, allowed)
            if place.path is None:
                why_not[key] = place.reason or "it leads to no file"
            else:
                wanted[key] = MeshFile(place.path, shape.scale)
    meshes: dict[MeshKey, Mesh] = {}
    if inline:
        from cspace._formats.usd._collision import read_inline_meshes
        from cspace._model._collision_hull import with_hulls

        folders = [os.path.dirname(os.path.abspath(robot_file)), *map(str, allow_dirs)]
        for key, got in with_hulls(read_inline_meshes(robot_file, list(inline), folders)).items():
            if isinstance(got, str):
                why_not[key] = got
            elif not len(got.triangles):
                why_not[key] = NO_TRIANGLES
            else:
                meshes[key] = got
    read = load_meshes(list(wanted.values()), allow_dirs=allowed, limits=limits)
    for key, result in zip(wanted, read, strict=True):
        if isinstance(result, RobotFileError):
            why_not[key] = problem_of(result)
        elif not len(result.triangles):  # coal builds no BVH of it: a crash when checked
            why_not[key] = NO_TRIANGLES
        else:
            meshes[key] = result
    problems = tuple(
        ShapeProblem(link.name, shape.line, shape.mesh or "", why_not[mesh_key(shape)])
        for link in links
        for shape in link.collisions
        if shape.kind == "mesh" and mesh_key(shape) in why_not
    )
    return ShapeMeshes(meshes, problems)


def _usd_stage(robot_file: str) -> bool:
    """Whether the robot file is a USD stage, whose ``usd:`` meshes are its own data."""
    from cspace._formats.usd._layers import named
    from cspace._formats.usd.reader import USD_SUFFIXES

    return named(robot_file, USD_SUFFIXES)
