"""MuJoCo's compiler as the MJCF front end: parse, drop geometry files, compile, read facts.

This module runs inside the confined child process (`mjcf._worker`); it is
importable on its own so that it can be read and tested, but the parent never calls it
on a user's file in its own process (MuJoCo's compile time and memory are bounded only
by the child's limits).

MuJoCo parses the document with every include and attached model taken from memory
(the pre-scan, `mjcf._prescan`, read them), and every mesh, texture, height
field and skin file replaced by an empty placeholder. Before compiling, geometry that
the configuration space does not depend on is made file-free: a mesh, height-field or
SDF geom becomes a small sphere that touches nothing (``contype``/``conaffinity`` 0),
materials lose their textures, and meshes, height fields, skins and textures are
deleted. ``alignfree`` is turned off (it would move a free body's frame to an inertial
frame that depends on the meshes), and the simulation arena's size (``<size>``) is
MuJoCo's default (dm_control's rodent asks for more than the child may map). What
MuJoCo then compiles has the joints, limits, frames and ``qpos`` layout of the real
model (measured: identical ``nq``, ``nv``, ``jnt_qposadr``, ``jnt_dofadr``,
``jnt_type``, ``jnt_range``, body and joint frames).

The facts come back as plain JSON-ready values (`facts`), MuJoCo's conventions
kept: quaternions ``(w, x, y, z)``, angles in rad (``angle="degree"`` applied),
``jnt_range`` as compiled (a ball's ``[0, max angle]``).
"""

from collections.abc import Mapping, Sequence
from typing import Any

from cspace._record import NamedTuple

PLACEHOLDER_RADIUS = 0.01
"""Radius (m) of the sphere that stands in for a mesh, height-field or SDF geom."""


def strip_geometry(spec: Any, geoms: Any = None) -> None:
    """Make a parsed ``MjSpec`` independent of every geometry and texture file (in place).

    ``geoms`` is ``spec.geoms`` when already listed (MuJoCo lists them in quadratic time).
    """
    import mujoco

    file_types = (
        mujoco.mjtGeom.mjGEOM_MESH,
        mujoco.mjtGeom.mjGEOM_HFIELD,
        mujoco.mjtGeom.mjGEOM_SDF,
    )
    for geom in spec.geoms if geoms is None else geoms:
        if geom.type in file_types or geom.meshname or geom.hfieldname:
            geom.type = mujoco.mjtGeom.mjGEOM_SPHERE
            geom.meshname = ""
            geom.hfieldname = ""
            geom.size = [PLACEHOLDER_RADIUS, 0.0, 0.0]
            geom.contype = 0
            geom.conaffinity = 0
            geom.fromto = [float("nan")] * 6
    for material in spec.materials:
        material.textures = [""] * len(material.textures)
    for group in (spec.meshes, spec.hfields, spec.skins, spec.textures):
        for asset in list(group):
            spec.delete(asset)
    spec.compiler.alignfree = False
    spec.compiler.usethread = False  # the child may start no thread
    # The simulation's arena (<size memory njmax nconmax nstack>) is allocated at compile
    # time and is no part of the configuration space: MuJoCo's defaults instead.
    spec.memory = spec.njmax = spec.nconmax = spec.nstack = -1


def compile_model(
    main: str, includes: Mapping[str, bytes], placeholders: Sequence[str]
) -> "tuple[Any, Any, Written]":
    """Parse and compile an MJCF document whose every file is in memory.

    Args:
        main: The main document's text.
        includes: Each included or attached file, by the name the document uses.
        placeholders: Base names of the mesh, texture, height-field and skin files the
            document names (they are given to MuJoCo empty, then deleted).

    Returns:
        The compiled ``mujoco.MjModel``, the ``mujoco.MjSpec`` it was compiled from (its
        name, ``<compiler angle>``), and the qpos and ctrl of each keyframe the file
        declares, as written (compiling adds a blank keyframe for each of ``<size nkey>``
        and fills what a keyframe leaves out from qpos0), with the geoms as written.

    Raises:
        ValueError: MuJoCo refused the document (its own message).
    """
    import mujoco

    assets = {name: b"" for name in placeholders}
    spec = mujoco.MjSpec.from_string(main, include=dict(includes), assets=assets)
    from cspace._formats.mjcf._geom_facts import originals

    geoms = spec.geoms
    kept = originals(spec, geoms)  # the collision geometry, before it is stripped
    strip_geometry(spec, geoms)
    # as written: compiling adds <size nkey>'s blank keyframes and fills each from qpos0;
    # MuJoCo's Python vectors convert at about 50 us each, so at most MAX_KEYS are read
    keys = spec.keys
    written = [[list(key.qpos), list(key.ctrl)] for key in keys[:MAX_KEYS]]
    return spec.compile(), spec, Written(len(keys), written, kept)


class Written(NamedTuple):
    """The keyframes a file declares: how many, and the first `MAX_KEYS` as written.

    Attributes:
        declared: How many ``<key>`` the file declares.
        keys: The qpos and ctrl of each of the first `MAX_KEYS`, as written.
        geoms: The geoms and meshes as written (`_geom_facts.originals`), or None.
    """

    declared: int
    keys: list[list[list[float]]]
    geoms: "dict[str, Any] | None" = None


MAX_KEYS = 5_000
"""Most keyframes read as written (and checked): the rest are counted."""


def _name(model: Any, kind: Any, index: int) -> str | None:
    import mujoco

    name = mujoco.mj_id2name(model, kind, index)
    return name or None


MAX_KEY_NUMBERS = 200_000
"""Most keyframe numbers (qpos and ctrl) sent back to be checked; the keyframes beyond
are counted (``nkey``), not checked."""


def _key_extra(model: Any, k: int, mquat: list[float]) -> dict[str, Any]:
    """What is wrong in keyframe ``k``'s qvel, mpos and mquat, by index (most are fine).

    ``qvel``: [dof, value] not finite; ``mpos``: [mocap body, xyz] not finite; ``mquat``:
    [mocap body, wxyz as written] not finite, or of norm off 1 by more than 1e-3.
    """
    import math

    qvel = [[d, float(v)] for d, v in enumerate(model.key_qvel[k]) if not math.isfinite(v)]
    mpos = []
    mquats = []
    for b in range(model.nmocap):
        pos = [float(x) for x in model.key_mpos[k][3 * b : 3 * b + 3]]
        if not all(math.isfinite(x) for x in pos):
            mpos.append([b, pos])
        quat = [float(x) for x in mquat[4 * b : 4 * b + 4]]
        norm = math.sqrt(sum(x * x for x in quat)) if quat else 1.0
        if not math.isfinite(norm) or abs(norm - 1.0) > 1e-3:
            mquats.append([b, quat])
    return {"qvel": qvel[:20], "mpos": mpos[:20], "mquat": mquats[:20]}


def facts(model: Any, spec: Any, written: Written | None = None) -> dict[str, Any]:
    """What `cspace` reads of a compiled model, as JSON-ready lists.

    Args:
        model: A compiled ``mujoco.MjModel``.
        spec: The ``mujoco.MjSpec`` it was compiled from.
        written: The keyframes the file declares, as written.

    Returns:
        ``nq``, ``nv``, ``bodies`` (name or None, parent id, pos, quat w-first),
        ``joints`` (name or None, type, body id, qposadr, dofadr, limited, range,
        anchor, axis, qpos0 of the joint's first coordinate), ``equalities`` (type,
        the two objects as joint, body or tendon ids, object type, active at start,
        name, and for a joint equality its ``polycoef``, five numbers),
        ``equality_disabled`` (``<flag equality="disable"/>``), ``tendons`` (names),
        ``closures`` (each ``connect`` and ``weld``: its index and the two frames it
        holds together, see `_closure`),
        ``degree`` (the file's angles are in degrees, MuJoCo's default), ``keys`` (of
        each keyframe the file declares, ``<key>``, not ``<size nkey>``'s blank ones:
        its name, qpos and ctrl as written, each empty unless written whole, up to
        `MAX_KEY_NUMBERS` numbers), ``nkey`` (how many it
        declares; each keyframe's qvel, mpos and mquat problems, see `_key_extra`),
        ``actuators`` (see `_actuator`),
        ``mocap`` (each mocap body's name),
        ``dofs`` (each degree of freedom's joint id), ``framed`` (the ids of the
        bodies a ``<frame>``, ``<replicate>`` or ``<attach>`` places; None past
        `FRAMED_BODIES` bodies) and ``collision`` (the geoms and contact filters,
        `_geom_facts.collision_facts`).
    """
    import mujoco

    from cspace._formats.mjcf._geom_facts import collision_facts

    obj = mujoco.mjtObj
    bodies = [
        [
            _name(model, obj.mjOBJ_BODY, b),
            int(model.body_parentid[b]),
            [float(x) for x in model.body_pos[b]],
            [float(x) for x in model.body_quat[b]],
        ]
        for b in range(model.nbody)
    ]
    joints = [
        [
            _name(model, obj.mjOBJ_JOINT, j),
            int(model.jnt_type[j]),
            int(model.jnt_bodyid[j]),
            int(model.jnt_qposadr[j]),
            int(model.jnt_dofadr[j]),
            bool(model.jnt_limited[j]),
            [float(x) for x in model.jnt_range[j]],
            [float(x) for x in model.jnt_pos[j]],
            [float(x) for x in model.jnt_axis[j]],
            float(model.qpos0[model.jnt_qposadr[j]]),
        ]
        for j in range(model.njnt)
    ]
    equalities = []
    joint_equality = int(mujoco.mjtEq.mjEQ_JOINT)
    for e in range(model.neq):
        objtype = int(model.eq_objtype[e])
        ids = [int(model.eq_obj1id[e]), int(model.eq_obj2id[e])]
        if objtype == int(obj.mjOBJ_SITE):  # a site ties the body it is on
            ids = [int(model.site_bodyid[i]) if i >= 0 else -1 for i in ids]
            objtype = int(obj.mjOBJ_BODY)
        equalities.append(
            [
                int(model.eq_type[e]),
                ids,
                objtype,
                bool(model.eq_active0[e]),
                _name(model, obj.mjOBJ_EQUALITY, e),
                [float(x) for x in model.eq_data[e][:5]]
                if int(model.eq_type[e]) == joint_equality
                else [],
            ]
        )
    tendons = [_name(model, obj.mjOBJ_TENDON, t) for t in range(model.ntendon)]
    closures = [_closure(model, e) for e in range(model.neq) if int(model.eq_type[e]) < 2]
    keys, room = [], MAX_KEY_NUMBERS
    given = written.keys if written is not None else []
    # MuJoCo normalises a mocap quaternion when it compiles: read them as written, for
    # models that have mocap bodies only (each vector costs about 50 us)
    mquats = [list(key.mquat) for key in spec.keys[: len(given)]] if model.nmocap else []
    declared = written.declared if written is not None else 0  # not <size nkey>'s blank ones
    for k in range(min(len(given), model.nkey)):
        room -= model.nq + model.nu
        if room < 0:
            break
        qpos, ctrl = ([float(x) for x in part] for part in given[k])
        # only what the file writes, whole: a keyframe that leaves qpos (or ctrl) out
        # takes MuJoCo's qpos0 (or zeros), which are not the file's pose
        keys.append(
            [
                _name(model, obj.mjOBJ_KEY, k),
                qpos if len(qpos) == model.nq else [],
                ctrl if len(ctrl) == model.nu else [],
                _key_extra(model, k, mquats[k] if mquats else []),
                len(qpos),  # what it writes: MuJoCo fills the rest from qpos0
            ]
        )
    # <flag clampctrl="disable"/>: MuJoCo clamps no ctrl, whatever each ctrlrange says
    clamped = not int(model.opt.disableflags) & int(mujoco.mjtDisableBit.mjDSBL_CLAMPCTRL)
    actuators = [_actuator(model, a, clamped) for a in range(model.nu)]
    return {
        "name": str(spec.modelname),
        "keys": keys,
        "nkey": declared,
        "actuators": actuators,
        "mocap": [
            _name(model, obj.mjOBJ_BODY, int(b))
            for b in sorted(range(model.nbody), key=lambda b: int(model.body_mocapid[b]))
            if int(model.body_mocapid[b]) >= 0
        ],
        "dofs": [int(j) for j in model.dof_jntid],
        "nq": int(model.nq),
        "nv": int(model.nv),
        "bodies": bodies,
        "joints": joints,
        "equalities": equalities,
        "equality_disabled": bool(
            int(model.opt.disableflags) & int(mujoco.mjtDisableBit.mjDSBL_EQUALITY)
        ),
        "tendons": tendons,
        "closures": closures,
        "degree": bool(spec.compiler.degree),
        "framed": _framed(model, spec),
        "collision": collision_facts(model, written.geoms if written is not None else None),
    }


def _actuator(model: Any, a: int, clamped: bool = True) -> list[Any]:
    """An actuator as a list: its name, ctrl range, transmission and parameters.

    ``[name, ctrllimited, ctrlrange, joint id or -1, trntype, trnid, gear, dyntype,
    gaintype, gainprm[:3], biastype, biasprm[:3], site, gears]``. ``ctrllimited`` is whether
    MuJoCo clamps its ctrl: never when ``clamped`` is False (the model disables
    ``clampctrl``). The joint id is that of a joint transmission (``mjTRN_JOINT``) only,
    -1 otherwise; ``trnid`` is the transmission's first object (a joint, tendon, site or
    body id); ``gear`` its first number (a hinge's or slide's: length = gear * qpos);
    ``site`` the name of the site a site or slider-crank transmission drives (its crank
    site), else None; ``gears`` all six numbers of its gear.
    """
    import mujoco

    trntype = int(model.actuator_trntype[a])
    trnid = int(model.actuator_trnid[a][0])
    on_site = trntype in (int(mujoco.mjtTrn.mjTRN_SITE), int(mujoco.mjtTrn.mjTRN_SLIDERCRANK))
    return [
        _name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a),
        clamped and bool(model.actuator_ctrllimited[a]),
        [float(x) for x in model.actuator_ctrlrange[a]],
        trnid if trntype == int(mujoco.mjtTrn.mjTRN_JOINT) else -1,
        trntype,
        trnid,
        float(model.actuator_gear[a][0]),
        int(model.actuator_dyntype[a]),
        int(model.actuator_gaintype[a]),
        [float(x) for x in model.actuator_gainprm[a][:3]],
        int(model.actuator_biastype[a]),
        [float(x) for x in model.actuator_biasprm[a][:3]],
        _name(model, mujoco.mjtObj.mjOBJ_SITE, trnid) if on_site and trnid >= 0 else None,
        [float(x) for x in model.actuator_gear[a]],
    ]


def _closure(model: Any, e: int) -> list[Any]:
    """A ``connect`` or ``weld``: ``[index, frame in body1, frame in body2, torquescale]``.

    Each frame is ``[position, quaternion w-first]`` in its body's frame, placed as MuJoCo
    places the constraint: for bodies, ``eq_data`` (a connect's anchor in each body, the
    compiler having found body2's at qpos0; a weld's ``relpose`` in body1 against its
    anchor in body2); for sites, the sites' own frames.
    """
    import mujoco

    data = [float(x) for x in model.eq_data[e][:10]]
    if int(model.eq_objtype[e]) == int(mujoco.mjtObj.mjOBJ_SITE):
        sites = [int(model.eq_obj1id[e]), int(model.eq_obj2id[e])]
        frames = [
            [[float(x) for x in model.site_pos[s]], [float(x) for x in model.site_quat[s]]]
            for s in sites
        ]
    elif int(model.eq_type[e]) == int(mujoco.mjtEq.mjEQ_CONNECT):
        frames = [[data[0:3], [1.0, 0.0, 0.0, 0.0]], [data[3:6], [1.0, 0.0, 0.0, 0.0]]]
    else:
        frames = [[data[3:6], data[6:10]], [data[0:3], [1.0, 0.0, 0.0, 0.0]]]
    torquescale = float(model.eq_data[e][10]) if int(model.eq_type[e]) == 1 else 1.0
    return [e, *frames, torquescale]


FRAMED_BODIES = 2_000
"""Most bodies of a model whose bodies placed by a ``<frame>`` are listed: MuJoCo's
``spec.bodies`` takes time quadratic in the bodies (7 ms for 2,000, 2.7 s for 20,000)."""


def _framed(model: Any, spec: Any) -> list[int] | None:
    """The ids of the bodies a ``<frame>`` (``<replicate>``, ``<attach>``) places.

    None for a model of more than `FRAMED_BODIES` bodies: not looked at.
    """
    if int(model.nbody) > FRAMED_BODIES:
        return None
    return [int(b.id) for b in spec.bodies if b.frame is not None]
