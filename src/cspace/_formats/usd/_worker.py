"""The process that reads USD stages with OpenUSD, confined (run as ``python -I -m``).

OpenUSD's parsers (text, crate, zip) and its composition engine have no limits of their
own, and composition follows sublayers, references and payloads to other files. So the
parent runs it here, in a serving child (`serving`, kept by `usd.child`) that:

1. imports ``pxr`` (usd-core or usd-exchange) with an empty environment: no
   ``PXR_PLUGINPATH_NAME``, so no plugin but OpenUSD's own is found; one work thread;
2. caps itself (`serving.take_setup`), gives up capabilities, installs the seccomp
   filter (no socket, no new process) and confines reads to the folders of its setup
   (Landlock), once;
3. then, for each request (each bounded in CPU by its own soft limit, and by the
   parent in CPU and wall clock): walks the stage's layers with ``Sdf`` before
   composing (`usd._layers.layer_stack`: every sublayer, reference and payload inside
   the request's own allowed folders, at most 256 layers, no value clips, and no value
   whose asset path would make OpenUSD open a package outside them), counts what
   composition would make (`usd._count.count_sites`), composes the stage and reads at
   most `MAX_PRIMS` prims. No stage or layer is kept from one request to the next: a
   layer still open after one makes the child retire.

It answers ``U`` and the stage's facts as JSON (`stage_facts`: its bodies, its joints and
their frames in their bodies, `usd._frames`, its colliders, `usd._colliders`, and when
asked what filters their collisions), ``E`` and a message, or
``R`` (the stage needs a file its Landlock rules, fixed at start, do not cover). Asked
for ``arcs`` instead (folder discovery), it opens each layer alone, composing nothing,
and answers the files each composes, outside variants and only in variants, and
whether it defines a joint (`usd._alone.layer_arcs`); asked whether a layer is
``alone`` a robot, it composes it as for its facts and answers whether the stage has a
joint, a rigid body or an articulation root (`alone`); asked for ``meshes``, it
composes the stage as for its facts and answers those collision meshes' arrays
(`usd._colliders.mesh_arrays`).
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
from typing import Any

from cspace._confine.landlock import readable_entries
from cspace._confine.sandbox import confine_to_entries, quiet_stdout
from cspace._confine.serving import next_request, send, should_retire, take_setup
from cspace._d6 import D6_AXES
from cspace._formats.shared.collisions import MAX_COLLISIONS
from cspace._formats.shared.robot_size import MAX_JOINTS
from cspace._formats.usd import _layers as _usd_layers  # imported while its file may be read
from cspace._formats.usd._alone import JOINT_TYPES, layer_arcs, robot_in
from cspace._formats.usd._colliders import (
    collider_facts,
    enabled,
    filter_facts,
    mesh_arrays,
    owner,
    parsed_physics,
)
from cspace._formats.usd._count import count_sites
from cspace._formats.usd._frames import joint_frame
from cspace._formats.usd._layers import NeedsWider, StageRefused, layer_key, layer_stack

MAX_PRIMS = 100_000
"""Most prims read from one stage."""

MAX_ARC_LAYERS = 10_000
"""Most layers whose arcs one request lists (a folder's walk is bounded below that)."""


def _number(value: Any) -> float | None:
    return None if value is None else float(value)


def _is_body(prim: Any) -> bool:
    """A rigid body that is simulated (``physics:rigidBodyEnabled`` not false)."""
    from pxr import UsdPhysics  # type: ignore[import-untyped]

    if not prim.HasAPI(UsdPhysics.RigidBodyAPI):
        return False
    enabled = prim.GetAttribute("physics:rigidBodyEnabled")
    return not (enabled and enabled.Get() is False)


def _body_of(stage: Any, target: str) -> str:
    """The rigid body a joint's target is: itself or its nearest rigid-body ancestor."""
    from pxr import Sdf

    path = Sdf.Path(target)
    while not path.isEmpty and path != Sdf.Path.absoluteRootPath:
        prim = stage.GetPrimAtPath(path)
        if prim and _is_body(prim):
            return str(path)
        path = path.GetParentPath()
    return target


def _targets(prim: Any, name: str) -> list[str]:
    relation = prim.GetRelationship(name)
    return [str(t) for t in relation.GetTargets()] if relation else []


def _joint(prim: Any) -> dict[str, Any]:
    """What a UsdPhysics joint says: type, bodies, axis, limits, flags."""
    get = prim.GetAttribute
    facts: dict[str, Any] = {
        "path": str(prim.GetPath()),
        "name": prim.GetName(),
        "type": prim.GetTypeName(),
        "body0": _targets(prim, "physics:body0"),
        "body1": _targets(prim, "physics:body1"),
        "enabled": bool(get("physics:jointEnabled").Get()) if get("physics:jointEnabled") else True,
        "excluded": bool(get("physics:excludeFromArticulation").Get())
        if get("physics:excludeFromArticulation")
        else False,
    }
    for attribute in ("physics:axis",):
        if get(attribute):
            facts["axis"] = str(get(attribute).Get())
    for attribute in ("physics:lowerLimit", "physics:upperLimit"):
        if get(attribute) and get(attribute).Get() is not None:
            facts[attribute.split(":")[1]] = float(get(attribute).Get())
    for attribute in ("physics:coneAngle0Limit", "physics:coneAngle1Limit"):
        if get(attribute) and get(attribute).Get() is not None:
            facts[attribute.split(":")[1]] = float(get(attribute).Get())
    mimic = _mimic(prim)
    if mimic is not None:
        facts["mimic"] = mimic
    if prim.GetTypeName() == "PhysicsJoint":  # a generic (D6) joint: limits per axis
        axes = {}
        for axis in D6_AXES:
            low = get(f"limit:{axis}:physics:low")
            high = get(f"limit:{axis}:physics:high")
            if low and high and low.Get() is not None and high.Get() is not None:
                axes[axis] = [float(low.Get()), float(high.Get())]
        facts["limits"] = axes
    return facts


def _mimic(prim: Any) -> dict[str, Any] | None:
    """A joint's mimic relation, as ``follower = multiplier * leader + offset``.

    Newton's ``NewtonMimicAPI`` first, else PhysX's ``PhysxMimicJointAPI`` (see
    `usd._mimic`). The schemas are read from the prim's ``apiSchemas``: neither is
    registered here.
    """
    listop = prim.GetMetadata("apiSchemas")
    schemas = [str(s) for s in listop.ApplyOperations([])] if listop else []

    def value(name: str, default: float) -> float:
        attribute = prim.GetAttribute(name)
        got = attribute.Get() if attribute else None
        return default if got is None else float(got)

    if "NewtonMimicAPI" in schemas:
        enabled = prim.GetAttribute("newton:mimicEnabled")
        if enabled and enabled.Get() is False:
            return None
        return {
            "api": "NewtonMimicAPI",
            "leader": _targets(prim, "newton:mimicJoint"),
            "offset": value("newton:mimicCoef0", 0.0),
            "multiplier": value("newton:mimicCoef1", 1.0),
        }
    for schema in schemas:
        if schema.startswith("PhysxMimicJointAPI:"):
            axis = schema.split(":", 1)[1]
            return {
                "api": schema,
                "leader": _targets(prim, f"physxMimicJoint:{axis}:referenceJoint"),
                "offset": -value(f"physxMimicJoint:{axis}:offset", 0.0),
                "multiplier": -value(f"physxMimicJoint:{axis}:gearing", 1.0),
            }
    return None


def _articulation_roots(parsed: dict[Any, Any]) -> list[str]:
    """The root body of each articulation, as UsdPhysics's own parser picks it.

    An ``ArticulationRootAPI`` on a body makes that body the root; on an ancestor
    (a robot's top Xform), UsdPhysics's parser, which PhysX's is, picks the body at the
    centre of its joints (Newton instead roots at the source of the joints' body0 to
    body1 directions: the two agree where the API is on the base body). Empty where
    this OpenUSD has no parser or it fails (``parsed`` is {}): the reader then starts
    from the bodies that carry the API.
    """
    from pxr import UsdPhysics

    try:
        _, descriptions = parsed.get(UsdPhysics.ObjectType.Articulation, ([], []))
        return [str(root) for d in descriptions for root in d.rootPrims if not root.isEmpty]
    except Exception:
        return []


def _display(prim: Any, shown: dict[str, str]) -> None:
    """Keep a prim's ``displayName``, the name a converter had to encode.

    ``joint_0.0`` is the prim ``tn__joint_00_nC``.
    """
    name = prim.GetMetadata("displayName") if prim.HasAuthoredMetadata("displayName") else None
    if isinstance(name, str) and name:
        shown[str(prim.GetPath())] = name


def _composed(path: str, allowed: list[str]) -> tuple[Any, dict[str, Any]]:
    """The stage at ``path``, composed with every payload loaded, and its layers.

    Its layers are checked and its composition counted first.
    """
    from pxr import Usd

    layers = layer_stack(path, allowed)
    count_sites(os.path.abspath(path), layers, layer_key)  # refused here, before composing
    stage = Usd.Stage.Open(path, Usd.Stage.LoadAll)
    if stage is None:
        raise StageRefused("OpenUSD cannot open the stage")
    return stage, layers


def alone(path: str, allowed: list[str]) -> bool | None:
    """Whether the stage at ``path``, composed alone, has a joint, body or articulation.

    For discovery (`usd._alone`): composed as for its facts, its variants as selected.
    None when the stage is refused (its reading then says why).

    Raises:
        NeedsWider: A file it composes is beyond what this child may read.
    """
    try:
        stage, _ = _composed(path, allowed)
        return robot_in(stage, MAX_PRIMS)
    except (NeedsWider, MemoryError):
        raise
    except Exception:  # StageRefused, or OpenUSD's Tf.ErrorException
        return None


def stage_facts(path: str, allowed: list[str], filters: bool = False) -> dict[str, Any]:
    """The facts of the stage at ``path`` (see the module docstring).

    With its colliders (`usd._colliders`; none past `collisions.MAX_COLLISIONS`, their
    count says so), and with ``filters`` what filters their collisions.
    """
    from pxr import Usd, UsdGeom, UsdPhysics

    stage, layers = _composed(path, allowed)
    bodies, roots, joints = [], [], []
    shown: dict[str, str] = {}
    count = 0
    colliders: list[Any] = []
    # instance proxies too: bodies and joints inside instances are the robot's as well
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        count += 1
        if count > MAX_PRIMS:
            raise StageRefused(f"the stage has more than {MAX_PRIMS:,} prims")
        if _is_body(prim):
            bodies.append(str(prim.GetPath()))
            _display(prim, shown)
        if prim.HasAPI(UsdPhysics.ArticulationRootAPI):
            roots.append(str(prim.GetPath()))
        if prim.GetTypeName() in JOINT_TYPES:
            joints.append(_joint(prim))
            _display(prim, shown)
        if prim.HasAPI(UsdPhysics.CollisionAPI):
            colliders.append(prim)
    cache = UsdGeom.XformCache()
    known = set(bodies)
    placed = len(joints) <= MAX_JOINTS  # more are refused, by name, without their frames
    for joint in joints:  # a body target below a rigid body is that body (as PhysX)
        prim = stage.GetPrimAtPath(joint["path"])
        frames = []
        for k, side in enumerate(("body0", "body1")):
            targets = joint[side]
            joint[side] = [_body_of(stage, t) for t in targets]
            body = joint[side][0] if joint[side] and joint[side][0] in known else None
            target = targets[0] if targets else None
            frames.append(joint_frame(stage, cache, prim, k, target, body) if placed else None)
            if target is not None and not stage.GetPrimAtPath(target):
                joint.setdefault("dangling", []).append([side, target])
        joint["frames"] = frames
    meters = UsdGeom.GetStageMetersPerUnit(stage)
    parsed = parsed_physics(stage)
    placed_bodies: dict[str, Any] = {}
    found = [  # past the bound the stage is refused (`usd._collision`): none read
        collider_facts(collider, its, cache, placed_bodies)
        for collider in (colliders if len(colliders) <= MAX_COLLISIONS else ())
        if enabled(collider) and (its := owner(collider, known)) is not None
    ]
    more = {"filters": filter_facts(stage, parsed)} if filters else {}
    return {
        "layers": len(layers),
        "prims": count,
        "meters_per_unit": meters if math.isfinite(meters) else None,
        "default_prim": str(stage.GetDefaultPrim().GetPath()) if stage.GetDefaultPrim() else None,
        "bodies": bodies,
        "roots": [*_articulation_roots(parsed), *roots],
        "joints": joints,
        "display_names": shown,
        "collision_prims": len(colliders),
        "colliders": found,
        **more,
    }


def _warm_up() -> None:
    """Make OpenUSD load what it loads on first use, while its own files may be read.

    Its plugins, the physics schemas, the text, crate and zip formats.
    """
    import tempfile

    from pxr import Ar, Sdf, Usd, UsdGeom, UsdPhysics

    Ar.IsPackageRelativePath("a.usdz[b.usda]")  # its module, loaded
    stage = Usd.Stage.CreateInMemory()
    UsdGeom.Xform.Define(stage, "/r")
    joint = UsdPhysics.RevoluteJoint.Define(stage, "/r/j")
    joint.CreateAxisAttr("Z")
    UsdPhysics.RigidBodyAPI.Apply(stage.GetPrimAtPath("/r"))
    UsdPhysics.ArticulationRootAPI.Apply(stage.GetPrimAtPath("/r"))
    UsdGeom.GetStageMetersPerUnit(stage)
    with tempfile.TemporaryDirectory() as folder:
        for ext in ("usda", "usdc"):
            stage.GetRootLayer().Export(os.path.join(folder, f"w.{ext}"))
            Usd.Stage.Open(os.path.join(folder, f"w.{ext}"))
        Sdf.FileFormat.FindById("usdz")


def _said(exc: BaseException) -> str:
    """An exception as one line: OpenUSD's own words, without its source file and line."""
    if isinstance(exc, MemoryError):
        return "OpenUSD needed more memory than it may use"
    text = " ".join(str(exc).split())
    quoted = re.findall(r" : '(.*?)'(?= Error in |$)", text)  # Tf's "Error in 'f' ... : 'msg'"
    said = "; ".join(quoted) if quoted else text
    said = re.sub(r"pxrInternal_v[0-9_]+__pxrReserved__(::|_)*(pegtl::internal::)?", "", said)
    return said[:4096] or type(exc).__name__


def _answer(request: dict[str, Any]) -> bytes:
    """One request's answer: ``U`` and JSON, ``E`` and a message, or ``R`` (`NeedsWider`).

    ``M`` and a message when OpenUSD ran out of the memory it may use.
    """
    allowed = [os.path.realpath(a) for a in request["allowed"]]
    try:
        if "arcs" in request:  # which layers each of these layers composes
            facts: Any = {path: layer_arcs(path) for path in request["arcs"][:MAX_ARC_LAYERS]}
        elif "alone" in request:  # whether a stage composed alone is a robot
            facts = alone(request["alone"], allowed)
        elif "meshes" in request:  # the arrays of collision meshes (binary)
            stage, _ = _composed(request["meshes"], allowed)
            return b"U" + mesh_arrays(stage, request["prims"], request["spent"])
        else:
            facts = stage_facts(request["path"], allowed, bool(request.get("filters")))
        return b"U" + json.dumps(facts).encode("utf-8")
    except NeedsWider:
        return b"R"
    except BaseException as exc:  # OpenUSD raises Tf.ErrorException; memory and the rest
        return (b"M" if isinstance(exc, MemoryError) else b"E") + _said(exc).encode("utf-8")


def _layers_left() -> bool:
    """Whether a layer of a file is still open (the next request would find it, stale)."""
    import gc

    from pxr import Sdf

    if not any(not layer.anonymous for layer in Sdf.Layer.GetLoadedLayers()):
        return False
    gc.collect()
    return any(not layer.anonymous for layer in Sdf.Layer.GetLoadedLayers())


def main() -> int:
    """Import OpenUSD, confine this process, then read one stage (or layers) a request."""
    from pxr import Work

    Work.SetConcurrencyLimit(1)  # one core a child, and no thread to start once confined
    _warm_up()  # trusted code, loaded before the setup is read

    setup = take_setup()
    limits = setup["limits"]
    out = quiet_stdout()
    folders = [os.path.realpath(f) for f in setup["folders"]]
    entries = [e for f in folders if os.path.isdir(f) for e in readable_entries(f)]
    if confine_to_entries(entries) > 0:
        _usd_layers.REACHABLE = frozenset(entries)
    send(out, b"ready", int(limits["output_bytes"]))
    served = 0
    while (request := next_request(limits)) is not None:
        served += 1
        answer = _answer(request)
        retire = should_retire(limits, served) or _layers_left()
        send(out, answer, int(limits["output_bytes"]), retire)
        if retire:
            break
    return 0


if __name__ == "__main__":
    sys.exit(main())
