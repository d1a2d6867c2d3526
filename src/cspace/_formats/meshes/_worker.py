"""The process that parses one robot's meshes, confined (run as ``python -I -m``).

The parent (`child`) sends one JSON request on standard input: each mesh's name, format,
scale and bytes (base64). This process caps itself (CPU, address space, output size, no
core), imports all it needs, gives up capabilities, installs the seccomp filter and
confines itself with Landlock to reading no file at all, then parses. It answers ``U``,
the length of a JSON header (8 bytes, little-endian), the header (for each mesh its
counts, or its problem and line) and the arrays' bytes, float64 vertices then int32
triangles, mesh after mesh; or ``E`` and a one-line message.
"""

from __future__ import annotations

import base64
import json
import sys
from typing import Any

from cspace._confine.sandbox import answer_reading_nothing

MAX_MESSAGE_CHARS = 1000
"""Longest problem sent back for one mesh."""


def _parse(request: dict[str, Any]) -> bytes:
    from cspace._formats.meshes._bounds import MeshProblem
    from cspace._formats.meshes._read import Totals, read_mesh

    header: list[dict[str, Any]] = []
    chunks: list[bytes] = []
    totals = Totals()
    for entry in request["meshes"]:
        data = base64.b64decode(entry["data"])
        entry["data"] = None  # the base64 text is garbage from here
        scale = tuple(float(s) for s in entry["scale"])
        try:
            mesh = read_mesh(str(entry["kind"]), data, (scale[0], scale[1], scale[2]))
            totals.add(mesh)
        except MeshProblem as exc:
            header.append({"problem": exc.problem[:MAX_MESSAGE_CHARS], "line": exc.line})
            continue
        except MemoryError:
            header.append({"problem": "parsing it needed more memory than cspace allows"})
            continue
        except Exception as exc:  # a bug in a reader: this mesh's error, not the others'
            said = f"{type(exc).__name__}: {exc}"[:MAX_MESSAGE_CHARS]
            header.append({"problem": f"cspace's mesh reader failed on it, a bug ({said})"})
            continue
        header.append({"vertices": len(mesh.vertices), "triangles": len(mesh.triangles)})
        chunks += [mesh.vertices.astype("<f8").tobytes(), mesh.triangles.astype("<i4").tobytes()]
    told = json.dumps(header).encode("utf-8")
    return b"".join([b"U", len(told).to_bytes(8, "little"), told, *chunks])


def _preload() -> None:
    """Import all parsing needs: nothing can be read from disk once confined."""
    import numpy  # noqa: F401
    from lxml import etree  # noqa: F401

    from cspace._formats.meshes import _dae, _msh, _obj, _read, _stl  # noqa: F401
    from cspace._formats.shared import xmlio  # noqa: F401

    _read.read_mesh("dae", b"<COLLADA/>", (1.0, 1.0, 1.0))  # lxml's and NumPy's first use


def main() -> int:
    """Read the request, confine this process, parse, write the answer."""
    return answer_reading_nothing(_preload, _parse, "parsing the meshes")


if __name__ == "__main__":
    sys.exit(main())
