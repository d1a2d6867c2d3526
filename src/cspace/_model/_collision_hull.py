"""Convex hulls of collision meshes' points, computed by coal (qhull) in a confined child.

A USD mesh whose ``physics:approximation`` PhysX makes a convex hull
(`cspace._formats.usd._colliders`: a ``usd-hull:`` mesh name) comes from its reader as
its points alone; `with_hulls` makes each the hull of its points. coal's
``buildConvexHull`` runs qhull, which crashes the process on points that lie in a plane
or on a line (coal 3.0 dereferences what qhull did not make): so the points are first
held to span space (`flat`), and the hulls are computed in a child (``python -I -m
cspace._model._collision_hull``) that caps its CPU time, memory and output and reads no
file once confined, as cspace's mesh readers' child does. A child stopped as a whole
(a limit reached) is no reason to lose every hull: its point sets are given again in
halves, each half to its own child (at most `MAX_HULL_CHILDREN` children and
`MAX_SPLIT_SECONDS` of splitting), so that a set gets the child's one-line problem only
when it (or the half it is in once those are spent) breaks a limit.
"""

from __future__ import annotations

import base64
import json
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from cspace._confine.sandbox import answer_reading_nothing
from cspace._formats.meshes._bounds import MAX_TOTAL_TRIANGLES, MAX_TOTAL_VERTICES, Mesh
from cspace._formats.usd._colliders import HULL

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

THIN = 1e-10
"""Points whose covariance's least eigenvalue is below this share of its largest span no
volume (qhull's input is joggled: it handles thinner, but not flat)."""

_Key = tuple[str, tuple[float, float, float]]

QHULL = "QJ"
"""qhull's options: joggled input, every facet a triangle."""

CPU_SECONDS = 20
WALL_SECONDS = 30.0
MEMORY_BYTES = 2 * 1024**3

MAX_HULL_CHILDREN = 64
"""Most children that compute one robot's hulls (the first, then halves of those it
could not finish): a point set that stops a child alone is found in about 2 log2 n."""

MAX_SPLIT_SECONDS = 120.0
"""Most wall-clock seconds spent computing halves again after a child was stopped."""


def flat(points: npt.NDArray[np.float64]) -> str | None:
    """Why ``points`` (``(n, 3)``, finite) have no convex hull of their own, or None."""
    import numpy as np

    if len(points) < 4:
        return f"its {len(points)} points make no convex hull (4 at least)"
    low, high = points.min(axis=0), points.max(axis=0)
    span = float(np.max(high - low))
    if span == 0.0:
        return "its points are all one point: no convex hull"
    centred = (points - (low + high) / 2) / span  # in [-1/2, 1/2]: no overflow
    eigen = np.linalg.eigvalsh(centred.T @ centred / len(points))
    if not eigen[-1] > 0 or eigen[0] < THIN * eigen[-1]:
        return "its points lie in a plane or on a line: no convex hull"
    return None


def with_hulls(meshes: dict[_Key, Mesh | str]) -> dict[_Key, Mesh | str]:
    """``meshes`` with each ``usd-hull:`` mesh's points made their convex hull (or why not).

    Args:
        meshes: Each mesh (a hull's: its points, no triangles) by its key
            (`_collision_shapes.MeshKey`), or its problem.
    """
    hulls = [k for k, got in meshes.items() if k[0].startswith(HULL) and isinstance(got, Mesh)]
    points = [got.vertices for k in hulls if isinstance(got := meshes[k], Mesh)]
    return {**meshes, **dict(zip(hulls, convex_hulls(points), strict=True))}


def convex_hulls(meshes: Sequence[npt.NDArray[np.float64]]) -> list[Mesh | str]:
    """The convex hull of each point set (``(n, 3)`` float64, finite, scaled), or why not.

    The sets that span space go to one child; when it is stopped, to halves of them
    each in its own child (see the module), so that only a set that stops a child alone
    gets its problem.
    """
    import time

    results: list[Mesh | str | None] = [flat(p) for p in meshes]
    given = [k for k, r in enumerate(results) if r is None]
    budget = [MAX_HULL_CHILDREN, time.monotonic() + MAX_SPLIT_SECONDS]
    for k, hull in zip(given, _split([meshes[k] for k in given], budget), strict=True):
        results[k] = hull
    return [r if r is not None else "no convex hull" for r in results]


def _split(
    points: list[npt.NDArray[np.float64]], budget: list[float], stopped: str | None = None
) -> list[Mesh | str]:
    """The hulls of ``points`` from one child, or from halves when it is stopped.

    ``budget`` is the children left and the splitting's deadline (`time.monotonic`);
    ``stopped``, the problem of the child these sets are a half of: once the budget is
    spent, a half not yet computed gets it, with no child of its own.
    """
    import time

    import numpy as np

    from cspace._confine.sandbox import ChildLimits, ChildRefused, run_child

    if not points:
        return []
    if stopped is not None and (budget[0] <= 0 or time.monotonic() > budget[1]):
        return [stopped] * len(points)
    output = 64 * 1024 + 24 * MAX_TOTAL_VERTICES + 12 * MAX_TOTAL_TRIANGLES
    limits = ChildLimits(CPU_SECONDS, WALL_SECONDS, MEMORY_BYTES, output)
    request = {
        "points": [
            base64.b64encode(np.ascontiguousarray(p, "<f8").tobytes()).decode() for p in points
        ]
    }
    budget[0] -= 1
    try:
        return _hulls(
            run_child("cspace._model._collision_hull", request, limits, "the convex hull")
        )
    except ChildRefused as exc:
        stopped = f"its convex hull could not be computed: {exc}"
        if len(points) == 1 or budget[0] <= 0 or time.monotonic() > budget[1]:
            return [stopped] * len(points)
    half = len(points) // 2
    return _split(points[:half], budget, stopped) + _split(points[half:], budget, stopped)


def _hulls(answer: bytes) -> list[Mesh | str]:
    import numpy as np

    size = int.from_bytes(answer[:8], "little")
    header = json.loads(answer[8 : 8 + size])
    at = 8 + size
    out: list[Mesh | str] = []
    for told in header:
        if "problem" in told:
            out.append(f"its convex hull could not be computed: {told['problem']}")
            continue
        nv, nt = int(told["vertices"]), int(told["triangles"])
        vertices = np.frombuffer(answer, "<f8", 3 * nv, at).reshape(nv, 3)
        at += 24 * nv
        triangles = np.frombuffer(answer, "<i4", 3 * nt, at).reshape(nt, 3)
        at += 12 * nt
        low = int(triangles.min()) if nt else 0
        high = int(triangles.max()) if nt else -1
        if nt == 0 or low < 0 or high >= nv:
            out.append("its convex hull came back malformed")
            continue
        out.append(Mesh(vertices.astype(np.float64), triangles.astype(np.int32)))
    return out


def _compute(request: dict[str, Any]) -> bytes:
    import numpy as np
    import pinocchio as pin

    header: list[dict[str, Any]] = []
    chunks: list[bytes] = []
    for text in request["points"]:
        points = np.frombuffer(base64.b64decode(text), "<f8").reshape(-1, 3)
        try:
            bvh = pin.coal.BVHModelOBBRSS()
            bvh.beginModel(0, len(points))
            bvh.addVertices(np.ascontiguousarray(points))
            bvh.endModel()
            bvh.buildConvexHull(True, QHULL)
            hull = bvh.convex
            vertices = np.asarray(hull.points(), dtype="<f8").reshape(-1, 3)
            triangles = np.array(
                [[hull.polygons(i)[k] for k in range(3)] for i in range(hull.num_polygons)],
                dtype="<i4",
            ).reshape(-1, 3)
        except Exception as exc:  # qhull's refusal, as coal raises it
            header.append({"problem": " ".join(str(exc).split())[-300:]})
            continue
        header.append({"vertices": len(vertices), "triangles": len(triangles)})
        chunks += [vertices.tobytes(), triangles.tobytes()]
    told = json.dumps(header).encode("utf-8")
    return b"".join([b"U", len(told).to_bytes(8, "little"), told, *chunks])


def _warm() -> None:
    """Coal's and qhull's first use, before the child confines itself."""
    import numpy as np
    import pinocchio as pin

    cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    warm = pin.coal.BVHModelOBBRSS()
    warm.beginModel(0, 8)
    warm.addVertices(cube)
    warm.endModel()
    warm.buildConvexHull(True, QHULL)


def main() -> int:
    """Read the request, confine this process, compute the hulls, write the answer."""
    return answer_reading_nothing(_warm, _compute, "computing the convex hulls")


if __name__ == "__main__":
    sys.exit(main())
