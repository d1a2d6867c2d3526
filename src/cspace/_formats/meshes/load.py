"""A robot's meshes: their bytes read through the one way in, parsed in a confined child.

`load_meshes` reads each mesh file with `cspace.files.read_input` (a regular file, no
link out of its folder, `MAX_MESH_BYTES` a file and `MAX_ROBOT_MESH_BYTES` in all) and
hands the bytes to `parse_meshes`, which parses them all in one child process
(`_worker`) bounded by `MeshLimits`. Each mesh comes back as its arrays or as the one
error that names it. A child stopped as a whole (its CPU, time, memory or output spent)
is no reason to lose every mesh: the meshes are parsed again in halves, each half in its
own child, until the ones that break a limit alone are found (at most
`MAX_MESH_CHILDREN` children and `MAX_SPLIT_SECONDS` of splitting a robot), so that one
heavy mesh a file adds cannot leave every other link without its shapes.
"""

import os
from collections.abc import Sequence

from cspace._formats.meshes._bounds import (
    MAX_MESH_BYTES,
    MAX_ROBOT_MESH_BYTES,
    MAX_TOTAL_TRIANGLES,
    MAX_TOTAL_VERTICES,
    Mesh,
)
from cspace._record import NamedTuple
from cspace.errors import RobotFileError

MESH_CODE = "bad-mesh"
"""The code of every error about a mesh file."""

MAX_MESH_CHILDREN = 64
"""Most children that parse one robot's meshes (the first, then halves of those it
could not parse): a mesh that stops a child alone is found among n in about 2 log2 n."""

MAX_SPLIT_SECONDS = 120.0
"""Most wall-clock seconds spent parsing halves again after a child was stopped."""


class MeshLimits(NamedTuple):
    """The bounds of the child that parses one robot's meshes.

    Attributes:
        cpu_seconds: CPU time the child may use (``RLIMIT_CPU``).
        wall_seconds: Wall-clock time before the child is killed.
        memory_bytes: Address space the child may map (``RLIMIT_AS``); Python, NumPy
            and lxml take about 150 MB of it before any mesh.
    """

    cpu_seconds: int = 20
    wall_seconds: float = 30.0
    memory_bytes: int = 2 * 1024**3


class MeshFile(NamedTuple):
    """A mesh file a robot names.

    Attributes:
        path: The file (as the robot file resolves it).
        scale: The robot file's scale of it, x, y, z.

    Its format is the one its name says (`_read.mesh_format`).
    """

    path: str
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)


class MeshBytes(NamedTuple):
    """A mesh file's bytes, read, and how to parse them.

    Attributes:
        path: The file, for messages.
        kind: Its format.
        scale: Its scale, x, y, z.
        data: Its bytes.
    """

    path: str
    kind: str
    scale: tuple[float, float, float]
    data: bytes


def mesh_error(path: str, problem: str, line: int | None = None) -> RobotFileError:
    """The one-line error of a mesh file (code `MESH_CODE`)."""
    return RobotFileError(path, f"mesh: {problem}", line=line, code=MESH_CODE)


def problem_of(error: RobotFileError) -> str:
    """A mesh file's error as the reason its shape is left out, in one line.

    The problem without its ``mesh:`` prefix (the reason is given beside the mesh's
    name), at the mesh file's line when it has one: ``line 4: a face names vertex 9``.
    """
    problem = error.problem.removeprefix("mesh: ")
    return problem if error.line is None else f"line {error.line}: {problem}"


def load_meshes(
    files: Sequence[MeshFile],
    *,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    limits: MeshLimits | None = None,
    robot_bytes: int = MAX_ROBOT_MESH_BYTES,
) -> "list[Mesh | RobotFileError]":
    """Read and parse a robot's mesh files: for each, its mesh or its error.

    A file that cannot be read, or is too large, gets its error without being parsed;
    the file that passes the robot's ``robot_bytes`` gets its error unparsed, and every
    file after it without being read (so no robot makes cspace read more than
    ``robot_bytes`` and one file, whatever names or scales it repeats).

    Args:
        files: The mesh files, in the robot file's order.
        allow_dirs: Folders beside the files' own that links may lead into.
        limits: The child's bounds (default `MeshLimits()`).
        robot_bytes: Most bytes of all the files (default `MAX_ROBOT_MESH_BYTES`).
    """
    from cspace._formats.meshes._read import mesh_format
    from cspace.files import read_input

    results: list[Mesh | RobotFileError | None] = []
    given: list[MeshBytes] = []
    spent = 0
    for file in files:
        kind = mesh_format(file.path)
        if kind is None:
            results.append(mesh_error(file.path, "not a mesh format cspace reads (by its name)"))
            continue
        if spent > robot_bytes:  # spent: read no more
            results.append(_past(file.path, robot_bytes))
            continue
        try:
            data = read_input(
                file.path, max_bytes=MAX_MESH_BYTES, allow_dirs=allow_dirs, what="mesh file"
            )
        except RobotFileError as exc:
            results.append(exc)  # FileUnreadableError, naming the file
            continue
        spent += len(data)
        if spent > robot_bytes:
            results.append(_past(file.path, robot_bytes))
            continue
        results.append(None)
        given.append(MeshBytes(file.path, kind, file.scale, data))
    parsed = iter(parse_meshes(given, limits=limits))
    return [next(parsed) if r is None else r for r in results]


def _past(path: str, robot_bytes: int) -> RobotFileError:
    """The error of a mesh file at or after the one that passes the robot's bytes."""
    return mesh_error(
        path,
        f"the robot's mesh files pass the {robot_bytes:,} bytes cspace reads for one robot "
        "by this one or before it",
    )


def parse_meshes(
    meshes: Sequence[MeshBytes], *, limits: MeshLimits | None = None
) -> "list[Mesh | RobotFileError]":
    """Parse meshes' bytes in confined children: for each, its mesh or its error.

    All are parsed in one child; when it is stopped as a whole (a limit reached), they
    are parsed again in halves, each in its own child, so that a mesh gets the child's
    error only when it (or the half it is parsed in once the splitting's bounds are
    spent) breaks a limit. The robot's totals (`MAX_TOTAL_VERTICES`,
    `MAX_TOTAL_TRIANGLES`) hold across the children, in the meshes' order.
    """
    import time

    if not meshes:
        return []
    limits = limits or MeshLimits()
    budget = _Budget(MAX_MESH_CHILDREN, time.monotonic() + MAX_SPLIT_SECONDS)
    return _within_totals(meshes, _parse_split(list(meshes), limits, budget))


class _Budget:
    """What is left for parsing one robot's meshes: children, and the deadline of splits."""

    def __init__(self, children: int, deadline: float) -> None:
        self.children = children
        self.deadline = deadline

    def spent(self) -> bool:
        import time

        return self.children <= 0 or time.monotonic() > self.deadline


def _parse_split(
    meshes: list[MeshBytes], limits: MeshLimits, budget: _Budget, stopped: str | None = None
) -> "list[Mesh | RobotFileError]":
    """``meshes`` parsed in one child, or in halves when it is stopped (see `parse_meshes`).

    ``stopped`` is the problem of the child these meshes are a half of: once the
    splitting's children or time are spent, a half not yet parsed gets it, with no child
    of its own (else each half left on the way down still ran one).
    """
    from cspace._confine.sandbox import ChildRefused

    if stopped is not None and budget.spent():
        return [mesh_error(m.path, stopped) for m in meshes]
    budget.children -= 1
    try:
        return _parse_in_child(meshes, limits)
    except ChildRefused as exc:
        if len(meshes) == 1 or budget.spent():
            return [mesh_error(m.path, str(exc)) for m in meshes]
        stopped = str(exc)
    half = len(meshes) // 2
    first = _parse_split(meshes[:half], limits, budget, stopped)
    return first + _parse_split(meshes[half:], limits, budget, stopped)


def _within_totals(
    meshes: Sequence[MeshBytes], results: "list[Mesh | RobotFileError]"
) -> "list[Mesh | RobotFileError]":
    """``results`` with each mesh past the robot's totals an error, as the child counts."""
    from cspace._formats.meshes._bounds import MeshProblem
    from cspace._formats.meshes._read import Totals

    totals = Totals()
    out: list[Mesh | RobotFileError] = []
    for mesh, result in zip(meshes, results, strict=True):
        if not isinstance(result, RobotFileError):
            try:
                totals.add(result)
            except MeshProblem as exc:
                result = mesh_error(mesh.path, exc.problem)
        out.append(result)
    return out


def _parse_in_child(
    meshes: Sequence[MeshBytes], limits: MeshLimits
) -> "list[Mesh | RobotFileError]":
    """Parse meshes' bytes in one confined child.

    Raises:
        ChildRefused: The child gave no answer (a limit reached).
    """
    import base64
    import json

    import numpy as np

    from cspace._confine.sandbox import ChildLimits, run_child

    output = 64 * 1024 + 24 * MAX_TOTAL_VERTICES + 12 * MAX_TOTAL_TRIANGLES + 1024 * len(meshes)
    child = ChildLimits(limits.cpu_seconds, limits.wall_seconds, limits.memory_bytes, output)
    request = {
        "meshes": [
            {
                "kind": m.kind,
                "scale": list(m.scale),
                "data": base64.b64encode(m.data).decode("ascii"),
            }
            for m in meshes
        ]
    }
    answer = run_child("cspace._formats.meshes._worker", request, child, "the mesh parser")
    size = int.from_bytes(answer[:8], "little")
    header = json.loads(answer[8 : 8 + size])
    at = 8 + size
    results: list[Mesh | RobotFileError] = []
    for mesh, told in zip(meshes, header, strict=True):
        if "problem" in told:
            results.append(mesh_error(mesh.path, str(told["problem"]), told.get("line")))
            continue
        nv, nt = int(told["vertices"]), int(told["triangles"])
        vertices = np.frombuffer(answer, dtype="<f8", count=3 * nv, offset=at).reshape(nv, 3)
        at += 24 * nv
        triangles = np.frombuffer(answer, dtype="<i4", count=3 * nt, offset=at).reshape(nt, 3)
        at += 12 * nt
        results.append(
            Mesh(vertices.astype(np.float64), triangles.astype(np.int32))  # own, writable copies
        )
    return results
