"""A USD layer as folder discovery sees it: what it composes, and whether it is a robot.

Run in `usd._worker`'s confined child. `layer_arcs` opens one layer alone with ``Sdf``
(nothing composed) and answers the files its sublayers, references and payloads name
(outside variants, and only in variants) and what its own specs hold (`holds`):

- `ROBOT`: it defines a UsdPhysics joint, rigid body or articulation root (what the
  reader reads a robot from: a rigid body no joint holds floats), a ``def`` prim whose
  every ancestor in the layer is a ``def`` too, none of them made inactive or
  instanceable there and none inside a variant: opened alone, OpenUSD has it, so the
  layer is a robot on its own, whoever composes it;
- `PARTS`: one of them is there otherwise (below an ``over`` or a
  ``class``, in a variant, below an inactive or instanceable prim: an Isaac physics
  layer of overs), or it names a layer cspace cannot tell (an expression, a URL, a path
  into a package, file format arguments), or it cannot be opened: only composing it
  (`robot_alone`) says whether it is a robot on its own;
- `NOTHING`: no joint, rigid body or articulation root (geometry, materials, a layout):
  it is a robot on its own only through a layer it composes.
"""

from __future__ import annotations

import os
from typing import Any

JOINT_TYPES = (
    "PhysicsRevoluteJoint",
    "PhysicsPrismaticJoint",
    "PhysicsSphericalJoint",
    "PhysicsFixedJoint",
    "PhysicsDistanceJoint",
    "PhysicsJoint",
)
"""The prim types the reader reads as joints (`usd._worker.stage_facts`)."""

ROBOT_APIS = ("PhysicsArticulationRootAPI", "PhysicsRigidBodyAPI")
"""The applied schemas the reader reads a robot from (`usd._worker.stage_facts`)."""

ROBOT = "robot"
PARTS = "parts"
NOTHING = ""


def layer_arcs(path: str) -> list[Any]:
    """What the layer at ``path`` composes directly, and what it holds, in three items.

    The files its sublayers and the references and payloads outside its variants name
    (absolute), those only a variant names, and `ROBOT`, `PARTS` or `NOTHING`. The layer
    alone is opened (no stage is composed); one OpenUSD cannot open composes nothing and
    holds `PARTS` (composing it says what it is).

    Raises:
        NeedsWider: The layer is beyond what this child may read.
    """
    from pxr import Sdf  # type: ignore[import-untyped]

    from cspace._formats.usd._layers import NeedsWider, file_of, reachable

    if os.path.isfile(path) and not reachable(path):
        raise NeedsWider(path)
    try:
        layer = Sdf.Layer.FindOrOpen(path)
        if layer is None:
            return [[], [], PARTS]
        assets = [a for a in dict.fromkeys(layer.GetCompositionAssetDependencies()) if a]
        plain, held = _walk(layer)
        told = {a: str(layer.ComputeAbsolutePath(a)) for a in assets}
        absolute = {
            a: t
            for a, t in told.items()
            if "://" not in a and not a.startswith("`") and os.path.isabs(t)
        }
        named = [a for a in assets if a in absolute]
    except Exception:
        return [[], [], PARTS]
    if len(named) < len(assets) or any(file_of(t) != t for t in absolute.values()):
        held = held or PARTS  # where such an arc leads is not told here
    return [
        [absolute[a] for a in named if a in plain],
        [absolute[a] for a in named if a not in plain],
        held,
    ]


def _walk(layer: Any) -> tuple[set[str], str]:
    """The asset paths (as written) of a layer's arcs outside variants, and `holds`.

    Its sublayers and the references and payloads of its prims outside any variant;
    every prim spec is looked at, those of variants too, iteratively.
    """
    from pxr import Sdf

    found = set(layer.subLayerPaths)
    held = NOTHING
    # (spec, every ancestor defined here and none inactive or instanceable, in a variant)
    todo = [(spec, True, False) for spec in layer.pseudoRoot.nameChildren.values()]
    while todo:
        spec, defined, in_variant = todo.pop()
        here = (
            defined
            and not in_variant
            and spec.specifier == Sdf.SpecifierDef
            and not (spec.HasInfo("active") and not spec.GetInfo("active"))
        )
        if held != ROBOT and (spec.typeName in JOINT_TYPES or _robot_api(spec)):
            held = ROBOT if here else PARTS
        if not in_variant:
            for listed in (spec.referenceList, spec.payloadList):
                found.update(item.assetPath for item in listed.GetAddedOrExplicitItems())
        below = here and not (spec.HasInfo("instanceable") and spec.GetInfo("instanceable"))
        todo.extend((child, below, in_variant) for child in spec.nameChildren.values())
        for variant_set in spec.variantSets.values():
            todo.extend((v.primSpec, False, True) for v in variant_set.variants.values())
    return found, held


def _robot_api(spec: Any) -> bool:
    """Whether a prim spec applies one of `ROBOT_APIS` (adds it, in any way)."""
    if not spec.HasInfo("apiSchemas"):
        return False
    schemas = spec.GetInfo("apiSchemas")
    added = (
        *schemas.explicitItems,
        *schemas.prependedItems,
        *schemas.appendedItems,
        *schemas.addedItems,
    )
    return any(api in added for api in ROBOT_APIS)


def robot_in(stage: Any, most: int) -> bool:
    """Whether a composed stage has a joint, a rigid body or an articulation root.

    Instances' prims too; a rigid body counts whether simulated or not.

    At most ``most`` prims are looked at.

    Raises:
        StageRefused: The stage has more than ``most`` prims before one is found.
    """
    from pxr import Usd, UsdPhysics

    from cspace._formats.usd._layers import StageRefused

    for count, prim in enumerate(stage.Traverse(Usd.TraverseInstanceProxies()), 1):
        if count > most:
            raise StageRefused(f"the stage has more than {most:,} prims")
        if prim.GetTypeName() in JOINT_TYPES or any(
            prim.HasAPI(api) for api in (UsdPhysics.ArticulationRootAPI, UsdPhysics.RigidBodyAPI)
        ):
            return True
    return False
