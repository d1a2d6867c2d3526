"""MuJoCo's collision geometry and contact filters, read in the compiling child.

This module runs in the confined child (`mjcf._worker`), beside `mjcf._compile`. The
child compiles a model whose mesh, height-field and SDF geoms were made placeholder
spheres (`_compile.strip_geometry`), so what those geoms were is read from the parsed
``MjSpec`` before they are changed (`originals`), and the rest from the compiled
``MjModel`` after (`collision_facts`): each geom's body, type, size, frame in its body
(``geom_pos``, ``geom_quat``: for a placeholder, the frame the file gives the geom, in
which its mesh's vertices stand once MuJoCo's ``refpos``, ``refquat`` and ``scale`` are
applied), ``contype`` and ``conaffinity``; each mesh asset's file name and transform;
the bodies' weld ids and degrees of freedom; ``<contact><exclude>`` and ``<pair>``;
and the flags that turn contacts off. Lines are MuJoCo's ``info`` (``line N`` of the
document MuJoCo was given; 0 for an element of an included file).

Everything comes back as JSON-ready lists, bounded: at most `MAX_GEOMS` geoms (a model
with more sends only its count) and `MAX_INLINE_NUMBERS` numbers of vertices written
inline in ``<mesh vertex>``.
"""

from typing import Any

MAX_GEOMS = 5_000
"""Most geoms whose facts are read (about 100,000 numbers); a model with more is counted,
not read. MuJoCo's ``spec.geoms`` takes time quadratic in the geoms (44 ms for 5,000)."""

MAX_INLINE_NUMBERS = 300_000
"""Most coordinates of vertices written inline (``<mesh vertex>``) sent back, all meshes
together; a mesh past them is sent without its vertices."""


def _line(info: str) -> int:
    """The line of MuJoCo's ``info`` (``"line 12"``), 0 when it gives none."""
    head, _, number = info.partition(" ")
    return int(number) if head == "line" and number.isdigit() else 0


def originals(spec: Any, geoms: Any) -> "dict[str, Any] | None":
    """What the geoms and meshes are before `_compile.strip_geometry` changes them.

    Never raises: the collision geometry is no reason to refuse a model.

    Args:
        spec: The parsed ``MjSpec``.
        geoms: Its ``spec.geoms`` (listed once: MuJoCo takes time quadratic in them).

    Returns:
        ``geoms`` (the spec's geom objects, whose compiled ids are read after
        compiling), ``rows`` (of each: type, mesh name, contype, conaffinity, line),
        ``meshes`` (of each mesh asset: name, file, meshdir, scale, refpos, refquat,
        maxhullvert, inline vertices or None past `MAX_INLINE_NUMBERS`, has a plugin),
        ``excludes`` and ``pairs`` (the spec's objects); only ``{"geoms": None}`` for
        more than `MAX_GEOMS` geoms; None when they cannot be read.
    """
    try:
        return _originals(spec, geoms)
    except Exception:  # MuJoCo's bindings raise what they raise
        return None


def _originals(spec: Any, geoms: Any) -> dict[str, Any]:
    if len(geoms) > MAX_GEOMS:
        return {"geoms": None}
    rows = [
        [int(g.type), str(g.meshname), int(g.contype), int(g.conaffinity), _line(str(g.info))]
        for g in geoms
    ]
    meshes = []
    room = MAX_INLINE_NUMBERS
    for mesh in spec.meshes:
        inline = mesh.uservert
        count = len(inline)
        vertices = None
        if count <= room:
            room -= count
            vertices = [float(x) for x in inline]
        meshes.append(
            [
                str(mesh.name),
                str(mesh.file),
                str(mesh.compiler.meshdir),
                [float(x) for x in mesh.scale],
                [float(x) for x in mesh.refpos],
                [float(x) for x in mesh.refquat],
                int(mesh.maxhullvert),
                vertices,
                bool(mesh.plugin.active) if mesh.plugin is not None else False,
            ]
        )
    return {
        "geoms": geoms,
        "rows": rows,
        "meshes": meshes,
        "excludes": list(spec.excludes),
        "pairs": list(spec.pairs),
    }


def collision_facts(model: Any, kept: "dict[str, Any] | None") -> "dict[str, Any] | None":
    """The compiled model's collision geometry and contact filters, as JSON-ready lists.

    Never raises: the collision geometry is no reason to refuse a model.

    Args:
        model: The compiled ``mujoco.MjModel`` (of the stripped spec).
        kept: What `originals` read before stripping.

    Returns:
        None when they cannot be read; else ``ngeom`` and, unless it is past
        `MAX_GEOMS`: ``geoms`` (each: body id, type as
        written (``mjtGeom``), size, pos, quat w-first, contype, conaffinity, mesh index
        or -1, fitted (a primitive MuJoCo fits to a mesh), line, name or None),
        ``meshes`` (see `originals`), ``weld`` and ``dofnum`` (each body's
        ``body_weldid`` and ``body_dofnum``), ``excludes`` (body1, body2, line),
        ``pairs`` (geom1, geom2, line), ``disabled`` (``contact``, ``constraint``,
        ``filterparent``: whether ``<flag>`` disables each).
    """
    if kept is None:
        return None
    try:
        return _collision_facts(model, kept)
    except Exception:  # MuJoCo's bindings raise what they raise
        return None


def _collision_facts(model: Any, kept: dict[str, Any]) -> dict[str, Any]:
    import mujoco

    ngeom = int(model.ngeom)
    if kept.get("geoms") is None or ngeom > MAX_GEOMS:
        return {"ngeom": ngeom}
    mesh_type = int(mujoco.mjtGeom.mjGEOM_MESH)
    mesh_index = {row[0]: k for k, row in enumerate(kept["meshes"])}
    types, contypes = model.geom_type.tolist(), model.geom_contype.tolist()
    affinities = model.geom_conaffinity.tolist()
    rows = [[types[g], "", contypes[g], affinities[g], 0] for g in range(ngeom)]
    for geom, row in zip(kept["geoms"], kept["rows"], strict=True):
        if 0 <= int(geom.id) < ngeom:
            rows[int(geom.id)] = row
    geoms = []
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or None for g in range(ngeom)]
    bodies, sizes = model.geom_bodyid.tolist(), model.geom_size.tolist()
    positions, quats = model.geom_pos.tolist(), model.geom_quat.tolist()
    for g, (kind, mesh_name, contype, conaffinity, line) in enumerate(rows):
        mesh = mesh_index.get(mesh_name, -1) if mesh_name else -1
        geoms.append(
            [
                int(bodies[g]),
                kind,
                sizes[g],
                positions[g],
                quats[g],
                contype,
                conaffinity,
                mesh,
                mesh >= 0 and kind != mesh_type,
                line,
                names[g],
            ]
        )
    excludes = []
    for exclude in kept["excludes"]:
        e = int(exclude.id)
        if 0 <= e < int(model.nexclude):
            signature = int(model.exclude_signature[e])
            excludes.append([signature >> 16, signature & 0xFFFF, _line(str(exclude.info))])
    pairs = []
    for pair in kept["pairs"]:
        p = int(pair.id)
        if 0 <= p < int(model.npair):
            g1, g2 = int(model.pair_geom1[p]), int(model.pair_geom2[p])
            pairs.append([g1, g2, _line(str(pair.info))])
    flags = int(model.opt.disableflags)
    bit = mujoco.mjtDisableBit
    return {
        "ngeom": ngeom,
        "geoms": geoms,
        "meshes": kept["meshes"],
        "weld": model.body_weldid.tolist(),
        "dofnum": model.body_dofnum.tolist(),
        "excludes": excludes,
        "pairs": pairs,
        "disabled": {
            "contact": bool(flags & int(bit.mjDSBL_CONTACT)),
            "constraint": bool(flags & int(bit.mjDSBL_CONSTRAINT)),
            "filterparent": bool(flags & int(bit.mjDSBL_FILTERPARENT)),
        },
    }
