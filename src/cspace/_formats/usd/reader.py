"""OpenUSD stages (Isaac Sim, Isaac Lab) read as UsdPhysics describes them.

- OpenUSD runs in a confined child (`usd._worker`), one per process that serves its
  stages in turn (`usd.child`): composition, and every file it or a value's asset path
  opens, stays in the stage's allowed folders (no value clips), at most 256 layers
  (256 entries a layer stack), 200,000 composed sites (counted before composing) and
  100,000 prims, 6 s of CPU and 8 s of wall clock a stage, no plugin, no network;
- bodies are prims with ``PhysicsRigidBodyAPI``; a joint's body that is no rigid body
  (the converter's default prim) is the world; a body target naming no prim is refused
  (``missing-link``: PhysX skips such a joint, UsdPhysics makes it the world's);
- each joint as `usd._joints` reads it (units, locked axes, cone limits, D6 joints), and
  mimic joints from ``NewtonMimicAPI`` or ``PhysxMimicJointAPI`` (`usd._mimic`);
- joints have no direction: the tree is a spanning forest taken in priority order
  (fixed, then moving, then excluded from the articulation); a joint that closes a loop
  is a cut of the mechanism (`usd._cuts`: at most `robot_size.MAX_CUTS`), a self-joint,
  or a closing joint no cut can hold, named and left out (``joint-left-out``); every
  joint of the stage counts against `robot_size.MAX_JOINTS`;
- a rigid body no joint holds floats (a free joint, named after the body, as SDF's);
- every joint is placed as UsdPhysics places it (`usd._frames` in the child, then
  `usd._joints.placed`): its frame in body0 is ``localPos0``/``localRot0`` (no body0:
  in the world), in body1 ``localPos1``/``localRot1``, positions scaled by the body's
  world scale, then by ``metersPerUnit``; at zero the child is at ``X_P_J0 *
  inverse(X_C_J1)`` in its parent: the joint frames decide, not the bodies' authored
  transforms (PhysX and Newton move a body there), a root bolted to the world too
  (Newton keeps such a root's authored pose where the world-side frame is the
  identity: the two agree on a consistent file). A free body's joint is the world's
  frame: its value is the body's pose (its authored transform without scale). A pose
  that cannot be computed (not finite, a zero scale) leaves its joint unplaced (no
  `cspace.pinocchio_model`; the C-space is reported);
- the joints are listed by prim path, as UsdPhysics lists them, and the tree is grown
  breadth first, the joints at a body in that order: PhysX's (Isaac's) order;
- each body's colliders are its links' collision shapes (`usd._colliders`,
  `usd._collision`), their meshes named, read only when asked for.

Several articulations in one stage are one robot (their product), as an MJCF scene's
bodies are.
"""

from __future__ import annotations

import json
import math
import os
from collections import Counter
from collections.abc import Sequence
from typing import Any

from cspace._findings import Diagnostic
from cspace._formats.shared.description import JointSpec, JointToAdd, LinkSpec
from cspace._formats.shared.pose import IDENTITY
from cspace._formats.shared.reading import Reading, ReadRequest, joint_list
from cspace._formats.shared.robot_size import check_count
from cspace._formats.shared.structure import build_description
from cspace._formats.usd._collision import link_shapes
from cspace._formats.usd._cuts import cuts_of, left_out
from cspace._formats.usd._joints import in_metres, refuse_dangling, specs_of
from cspace._formats.usd._layers import named
from cspace._formats.usd._mimic import with_mimics
from cspace._joint_kind import JointKind
from cspace.errors import InvalidElementError, NotARobotError, RobotFileError

USD_SUFFIXES = (".usd", ".usda", ".usdc", ".usdz")
"""The file names OpenUSD reads."""

WORLD = "world"


def looks_like(path: str, data: bytes) -> bool:
    """Whether ``data``, which begins as a USD layer does (`table.FORMATS`), is one.

    A ``.usdz`` is a zip archive: a zip file is USD only when so named.
    """
    return not data.startswith(b"PK\x03\x04") or named(path, (".usdz",))


def read(request: ReadRequest) -> Reading:
    """Read the stage ``request`` names in a confined child (the format's reader).

    The stage's layers may come from the file's folder and ``request.allow_dirs``.

    Raises:
        RobotFileError: The stage is read from standard input, OpenUSD or the child
            refused it, or it describes no robot.
    """
    import importlib.util

    from cspace._confine.sandbox import ChildRefused
    from cspace._formats.shared.xmlio import path_text
    from cspace._formats.usd.child import ask

    path, file = request.path, request.on_disk
    if file is None:
        raise NotARobotError(path, "a USD file is read from a file, not standard input")
    allowed = [os.path.dirname(os.path.abspath(file)), *map(path_text, request.allow_dirs)]
    if not named(file, USD_SUFFIXES):  # OpenUSD tells a layer's format by its name
        raise RobotFileError(
            path,
            "a USD file must be named .usd, .usda, .usdc or .usdz: OpenUSD reads a "
            "layer's format from its name",
            code="usd-name",
        )
    if importlib.util.find_spec("pxr") is None:
        raise RobotFileError(
            path,
            "a USD file needs OpenUSD, which is not installed: pip install 'cspace[usd]'",
            code="usd-missing",
        )
    try:
        answer = ask({"path": os.path.abspath(file)}, [os.path.abspath(a) for a in allowed])
    except ChildRefused as exc:
        raise RobotFileError(path, str(exc), code="usd-refused") from None
    return describe(path, json.loads(answer))


def layer_arcs(
    files: Sequence[str], allowed: Sequence[str]
) -> tuple[dict[str, list[str]], list[str]]:
    """The files each USD layer composes and leaves to it, read by OpenUSD in a child.

    For folder discovery. The layers go `ARC_BATCH` at a time to this process's OpenUSD
    child (`usd.child`: each batch a request, bounded in CPU and wall clock); a batch
    the child cannot finish (its CPU, memory or output bound) is tried again in smaller
    ones (`ARC_RETRY`), down to one layer. Each layer's arcs are its sublayers, and the
    references and payloads of its prims, those of every variant included. A layer
    another one composes is left to it only when it is no robot on its own (`_alone`):
    those that are, and those no child could list, are named by no layer here, so each
    is read. Returns what was found, by layer, and the layers no child could list.
    Nothing when OpenUSD is not installed.
    """
    import importlib.util

    from cspace._confine.sandbox import ChildRefused
    from cspace._formats.usd.child import ask

    if not files or importlib.util.find_spec("pxr") is None:
        return {}, []
    absolute = {os.path.abspath(f): f for f in files}
    found: dict[str, list[str]] = {}
    holds: dict[str, str] = {}
    failed: list[str] = []
    todo = [(layers, 0) for layers in _batches(list(absolute), ARC_BATCH)]
    while todo:
        layers, tries = todo.pop(0)
        try:
            raw = ask({"arcs": layers}, [os.path.abspath(a) for a in allowed])
            if len(raw) > ARC_ANSWER_BYTES:
                raise ValueError("more arcs than a listing holds")
            answer = json.loads(raw)
        except (ChildRefused, ValueError):
            if len(layers) > 1 and tries < len(ARC_RETRY):
                todo += [(part, tries + 1) for part in _batches(layers, ARC_RETRY[tries])]
            else:
                failed += [absolute[p] for p in layers]
            continue
        for path, (plain, variants, held) in answer.items():
            if path in absolute:
                found[absolute[path]] = [*plain, *variants]
                holds[os.path.normpath(path)] = str(held)
    read = _alone(found, holds, allowed) | {os.path.normpath(os.path.abspath(f)) for f in failed}
    kept = {
        layer: [t for t in targets if os.path.normpath(t) not in read]
        for layer, targets in found.items()
    }
    return kept, failed


def _alone(found: dict[str, list[str]], holds: dict[str, str], allowed: Sequence[str]) -> set[str]:
    """The layers another layer composes that are robots on their own (absolute, normal).

    A layer that defines a joint, a rigid body or an articulation root
    (`usd._alone.ROBOT`) is one. A layer that holds one otherwise (`usd._alone.PARTS`),
    or that composes, directly or through others, a layer that holds one, a layer the
    walk does not hold or one that could not be listed, is composed on its own as it
    would be read (its variants as selected: a request each, bounded as a stage's
    reading) and is one when the stage has a joint, a rigid body or an articulation
    root, or when OpenUSD cannot compose it (its reading then says what is wrong). A
    partial reference, an inactive or an unselected prim thus never hides a robot: the
    layer that holds it is read.
    """
    from cspace._confine.sandbox import ChildRefused
    from cspace._formats.usd._alone import NOTHING, ROBOT
    from cspace._formats.usd.child import ask

    arcs = {
        os.path.normpath(os.path.abspath(layer)): [os.path.normpath(t) for t in targets]
        for layer, targets in found.items()
    }
    composed = {t for layer, targets in arcs.items() for t in targets if t != layer}
    robots = {layer for layer in composed if holds.get(layer) == ROBOT}
    unknown = _reaching(arcs, {t for t in composed | set(arcs) if holds.get(t, "?") != NOTHING})
    folders = [os.path.abspath(a) for a in allowed]
    for layer in sorted(composed - robots):
        if layer not in arcs or layer not in unknown:
            continue  # not listed (read, as failed), or only parts that make no robot
        try:
            answer = json.loads(ask({"alone": layer}, folders))
        except (ChildRefused, ValueError):
            answer = None
        if answer is not False:
            robots.add(layer)
    return robots


def _reaching(arcs: dict[str, list[str]], seeds: set[str]) -> set[str]:
    """The layers from which a seed is reached through ``arcs`` (seeds included).

    One search over the arcs reversed: linear in the layers and arcs.
    """
    back: dict[str, list[str]] = {}
    for layer, targets in arcs.items():
        for target in targets:
            back.setdefault(target, []).append(layer)
    reached, todo = set(seeds), list(seeds)
    while todo:
        for layer in back.get(todo.pop(), ()):
            if layer not in reached:
                reached.add(layer)
                todo.append(layer)
    return reached


def _batches(items: list[str], size: int) -> list[list[str]]:
    return [items[k : k + size] for k in range(0, len(items), size)]


ARC_ANSWER_BYTES = 16 * 1024 * 1024
"""Largest answer of a listing of layers' arcs (16 MiB: 4,000 arcs of 4,000 characters);
the child may answer more, for collision meshes' arrays."""

ARC_BATCH = 500
"""USD layers whose arcs one request lists (6 s of CPU for them all): 5,000 small crate
layers took 1.2 s in one child."""

ARC_RETRY = (20, 1)
"""The sizes a batch is split into, in turn, when its child could not finish it."""


def prim_names(paths: Sequence[str], shown: dict[str, str]) -> dict[str, str]:
    """Each prim's name: its ``displayName`` where set, else its own.

    A converter encodes a name that is no USD identifier (``joint_0.0`` is the prim
    ``tn__joint_00_nC``) and keeps it as the display name. Where two share a name, their
    paths.
    """
    own = {p: shown.get(p) or p.rsplit("/", 1)[-1] for p in paths}
    short = Counter(own.values())
    return {p: own[p] if short[own[p]] == 1 else p for p in paths}


def _forest(edges: list[tuple[int, str, str]]) -> tuple[list[tuple[int, str, str]], list[int]]:
    """The edges that make a forest, taken in the order given, and those that close a loop.

    The order is the joints' priority (fixed first, excluded last): an edge whose two
    ends are already joined closes a loop, whatever its distance from the world.
    """
    parent: dict[str, str] = {}

    def find(node: str) -> str:
        root = node
        while parent.get(root, root) != root:
            root = parent[root]
        while parent.get(node, node) != root:  # path compression
            parent[node], node = root, parent[node]
        return root

    tree, loops = [], []
    for index, a, b in edges:
        ra, rb = find(a), find(b)
        if ra == rb:
            loops.append(index)
        else:
            parent[ra] = rb
            tree.append((index, a, b))
    return tree, loops


def _orient(
    edges: list[tuple[int, str, str]], roots: Sequence[str], world: str = WORLD
) -> tuple[list[tuple[int, str, str]], list[int], list[str]]:
    """UsdPhysics joints have no direction: each edge oriented away from the root.

    Breadth first from the world, then from each body the world does not reach (the
    articulation roots first): those float. An edge that closes a loop is left out.

    Returns:
        The oriented edges (index, parent, child), the loop edges' indices, the bodies
        that float.
    """
    around: dict[str, list[tuple[int, str]]] = {}
    for index, a, b in sorted(edges):  # the joints at a body in their order
        around.setdefault(a, []).append((index, b))
        around.setdefault(b, []).append((index, a))
    seen, used, oriented, floating = {world}, set(), [], []
    starts = [world, *roots, *sorted(n for n in around if n != world)]
    for start in starts:
        if start in seen and start != world:
            continue
        if start != world:
            seen.add(start)
            floating.append(start)
        queue = [start]
        while queue:
            node = queue.pop(0)
            for index, other in around.get(node, ()):
                if index in used:
                    continue
                used.add(index)
                if other in seen:
                    continue  # closes a loop
                seen.add(other)
                oriented.append((index, node, other))
                queue.append(other)
    loops = [i for i, _, _ in edges if i not in {o[0] for o in oriented}]
    return oriented, loops, floating


def describe(path: str, facts: dict[str, Any]) -> Reading:
    """The reading of a stage's facts (see the module docstring)."""
    meters = facts.get("meters_per_unit")
    meters = 1.0 if meters is None else float(meters)
    if not (math.isfinite(meters) and meters > 0.0):
        raise InvalidElementError(
            path, f"metersPerUnit is {meters:g}: lengths cannot be read", code="bad-number"
        )
    if not facts["bodies"] and not facts["joints"] and facts.get("prims", 0) == 0:
        raise InvalidElementError(path, "the stage has no prim: no robot", code="no-links")
    bodies = list(facts["bodies"])
    static = not bodies  # nothing simulated (a URDF of fixed joints, converted): a point
    if static:
        bodies = [facts.get("default_prim") or "/robot"]
    shown = facts.get("display_names", {})
    names = prim_names(bodies, shown)
    world = WORLD if WORLD not in names.values() else "<world>"
    # every joint counts, a loop's too: the child places at most this many
    check_count(path, "USD joints", len(facts["joints"]), None)
    # by prim path, as UsdPhysics lists an articulation's joints (and PhysX orders
    # the joints below one link)
    joints = sorted((j for j in facts["joints"] if j["enabled"]), key=_path_key)
    joint_names = prim_names([j["path"] for j in joints], shown)
    refuse_dangling(path, joints, joint_names)
    found: list[Diagnostic] = []
    edges = []
    body0: dict[int, str] = {}
    body1: dict[int, str] = {}
    for index, joint in enumerate(joints):
        ends = [names.get(joint[side][0], world) if joint[side] else world
                for side in ("body0", "body1")]  # fmt: skip
        body0[index], body1[index] = ends
        if ends[0] == ends[1]:
            found.append(left_out(joint_names[joint["path"]], f"joins '{ends[0]}' to itself"))
            continue
        # a fixed joint holds before a moving one; a joint excluded from the
        # articulation (a loop closure in PhysX) only holds what nothing else does
        rank = (joint["excluded"], joint["type"] != "PhysicsFixedJoint")
        edges.append((rank, index, ends[0], ends[1]))
    edges.sort(key=lambda e: e[0])
    tree, loops = _forest([(i, a, b) for _, i, a, b in edges])
    roots = [names[r] for r in facts.get("roots", []) if r in names]
    oriented, _, floats = _orient(tree, roots, world)
    # by prim path, as the tree's joints
    closing = [(joints[i], joint_names[joints[i]["path"]], (body0[i], body1[i]))
               for i in sorted(loops)]  # fmt: skip
    cuts, left = cuts_of(path, closing, meters)
    found += left
    pairs: list[tuple[JointSpec, JointToAdd | None]] = []
    for index, parent, child in oriented:
        joint = {**joints[index], "name": joint_names[joints[index]["path"]]}
        frames = [in_metres(f, meters) for f in joint.get("frames", (None, None))]
        reverse = parent != body0[index]  # the tree runs from body1 to body0
        ours = (frames[1], frames[0]) if reverse else (frames[0], frames[1])
        pairs.extend(specs_of(path, joint, (parent, child), meters, ours, reverse))
    pairs, ignored = with_mimics(pairs, joints, joint_names, meters)
    found += ignored
    taken = {spec.name for spec, _ in pairs} | {cut.name for cut in cuts}
    held = {c for _, _, c in oriented}
    free = list(dict.fromkeys([*floats, *(n for n in names.values() if n not in held)]))
    floating: list[tuple[JointSpec, JointToAdd | None]] = []
    for body in [] if static else free:  # first, in the order the roots were found
        name, k = body, 0
        while name in taken:
            k += 1
            name = f"{body}_free" if k == 1 else f"{body}_free{k}"
        taken.add(name)
        # its value is the body's pose in the world: the joint frame is the world's
        spec = JointSpec(name, "floating", world, body, JointKind.FLOATING, origin=IDENTITY)
        floating.append((spec, JointToAdd(name, None, "floating")))
    pairs = floating + pairs
    virtual = [spec.child for spec, _ in pairs if spec.child not in names.values()]
    shapes = link_shapes(path, facts, names, meters)  # each body's colliders
    links = [] if static else [LinkSpec(world)]
    links += [LinkSpec(n, None, *shapes.get(n, ((), ()))) for n in names.values()]
    links += [LinkSpec(v) for v in virtual]
    description = build_description(
        path,
        name=(facts.get("default_prim") or "").rsplit("/", 1)[-1],
        format="usd",
        links=links,
        joints=[spec for spec, _ in pairs],
    )
    if found or cuts:
        findings = (*description.findings, *found)
        description = description.replace(findings=findings, cuts=tuple(cuts))
    to_add = {spec.name: add for spec, add in pairs if add is not None}
    return Reading(description, joint_list(description, to_add))


def _path_key(joint: dict[str, Any]) -> tuple[str, ...]:
    """A prim path compared as ``SdfPath`` compares them: element by element."""
    return tuple(str(joint["path"]).split("/"))
