"""Remake this folder: stages whose joint frames are as written below, and whose bodies
are authored where those frames put them (``tests/test_usd_placements.py`` reads them).

Not run by the tests: run it when a case changes (``.venv/bin/python
tests/usd/placed/make.py``). Each joint's ``localPos``/``localRot`` are written as given
(single precision, as UsdPhysics stores them); each body's transform (a
``xformOp:transform``, double precision) is composed from the world through the joints
at their authored state, its position in a body's frame scaled by the body's world scale
as UsdPhysics reads it, so that the file is consistent, except where ``offsets`` moves a
body off its joint frames on purpose.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics

HERE = Path(__file__).resolve().parent
NONE = (1.0, 0.0, 0.0, 0.0)
"""No turn."""
ORIGIN = (0.0, 0.0, 0.0)
LOCK = (1.0, -1.0)
"""A D6 axis limit whose low is above its high: the axis is locked."""
BODY = {"body": True}


def turn(axis: tuple[float, ...], degrees: float) -> tuple[float, ...]:
    """The quaternion (w, x, y, z) of a turn about ``axis``."""
    unit = np.array(axis, float) / np.linalg.norm(axis)
    half = math.radians(degrees) / 2
    return (math.cos(half), *(math.sin(half) * unit))


def pose(position: Any, wxyz: Any) -> np.ndarray:
    """A 4x4 transform (column vectors) of a position and a quaternion."""
    w, x, y, z = np.array(wxyz, float) / np.linalg.norm(wxyz)
    out = np.eye(4)
    out[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    out[:3, 3] = position
    return out


def single(values: Any) -> list[float]:
    """Values rounded as a ``point3f`` or ``quatf`` stores them."""
    return [float(np.float32(v)) for v in values]


def motion(joint: dict[str, Any]) -> np.ndarray:
    """Body1's joint frame in body0's at the joint's authored state."""
    value = joint.get("state", 0.0)
    unit = np.eye(3)["XYZ".index(joint.get("axis", "X"))]
    if joint["kind"] == "revolute":
        return pose(ORIGIN, turn(unit, math.degrees(value)))
    if joint["kind"] == "prismatic":
        return pose(value * unit, NONE)
    return np.eye(4)


def build(name: str, doc: str, prims: dict[str, dict[str, Any]], joints: list[dict[str, Any]],
          meters: float = 1.0, offsets: dict[str, np.ndarray] | None = None) -> None:  # fmt: skip
    """Write ``name``.usda: ``prims`` by name (``parent``, ``body``, ``root``, ``scale``,
    ``local`` for a prim that is no body, ``pose`` for a free body), ``joints`` in order."""
    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageMetersPerUnit(stage, meters)
    UsdGeom.SetStageUpAxis(stage, "Z")
    stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, "/robot").GetPrim())
    stage.GetRootLayer().documentation = doc

    def path(prim: str) -> str:
        parent = prims[prim].get("parent")
        return f"{path(parent) if parent else '/robot'}/{prim}"

    def scale(prim: str) -> np.ndarray:
        own = np.array(prims[prim].get("scale", (1, 1, 1)), float)
        parent = prims[prim].get("parent")
        return own * scale(parent) if parent else own

    def anchor(joint: dict[str, Any], side: int) -> np.ndarray:
        frame = pose(single(joint[f"pos{side}"]), single(joint[f"rot{side}"]))
        body = joint.get(f"body{side}")
        target = joint.get(f"target{side}", body)
        while target != body:  # a prim below its body: its own transform carries it
            frame = prims[target]["local"] @ frame
            target = prims[target]["parent"]
        if body is not None:
            frame[:3, 3] *= scale(body)
        return frame

    world = {p: np.array(d["pose"]) for p, d in prims.items() if "pose" in d}
    grown = True
    while grown:
        grown = False
        for joint in joints:
            b0, b1 = joint.get("body0"), joint.get("body1")
            step = anchor(joint, 0) @ motion(joint) @ np.linalg.inv(anchor(joint, 1))
            w0 = world.get(b0) if b0 else np.eye(4)
            w1 = world.get(b1) if b1 else np.eye(4)
            if w0 is not None and b1 and b1 not in world:
                world[b1], grown = w0 @ step, True
            elif w1 is not None and b0 and b0 not in world:
                world[b0], grown = w1 @ np.linalg.inv(step), True
    for prim, offset in (offsets or {}).items():
        world[prim] = world[prim] @ offset
    full: dict[str, np.ndarray] = {}
    for prim in sorted(prims, key=lambda p: path(p).count("/")):
        given = prims[prim]
        parent = given.get("parent")
        if given.get("body"):
            full[prim] = world[prim] @ np.diag([*scale(prim), 1.0])
        else:
            above = full[parent] if parent else np.eye(4)
            own = np.diag([*given.get("scale", (1, 1, 1)), 1.0])
            full[prim] = above @ given.get("local", np.eye(4)) @ own
        local = np.linalg.inv(full[parent]) @ full[prim] if parent else full[prim]
        xform = UsdGeom.Xform.Define(stage, path(prim))
        if not np.array_equal(local, np.eye(4)):
            xform.AddTransformOp().Set(Gf.Matrix4d(*[float(c) for c in local.T.flatten()]))
        if given.get("body"):
            rigid = UsdPhysics.RigidBodyAPI.Apply(xform.GetPrim())
            if given.get("disabled"):
                rigid.CreateRigidBodyEnabledAttr(False)
        if given.get("root"):
            UsdPhysics.ArticulationRootAPI.Apply(xform.GetPrim())
    UsdGeom.Scope.Define(stage, "/robot/joints")
    kinds = {
        "revolute": UsdPhysics.RevoluteJoint,
        "prismatic": UsdPhysics.PrismaticJoint,
        "fixed": UsdPhysics.FixedJoint,
        "ball": UsdPhysics.SphericalJoint,
        "d6": UsdPhysics.Joint,
    }
    for joint in joints:
        made = kinds[joint["kind"]].Define(stage, f"/robot/joints/{joint['name']}")
        for side, relation in ((0, made.CreateBody0Rel), (1, made.CreateBody1Rel)):
            target = joint.get(f"target{side}", joint.get(f"body{side}"))
            if target:
                relation().SetTargets([path(target)])
        for side in (0, 1):
            position, rotation = joint[f"pos{side}"], joint[f"rot{side}"]
            made.GetPrim().CreateAttribute(f"physics:localPos{side}", Sdf.ValueTypeNames.Point3f)
            made.GetPrim().GetAttribute(f"physics:localPos{side}").Set(Gf.Vec3f(*position))
            quaternion = Gf.Quatf(float(rotation[0]), Gf.Vec3f(*rotation[1:]))
            made.GetPrim().CreateAttribute(f"physics:localRot{side}", Sdf.ValueTypeNames.Quatf)
            made.GetPrim().GetAttribute(f"physics:localRot{side}").Set(quaternion)
        for axis, (low, high) in joint.get("d6", {}).items():
            limit = UsdPhysics.LimitAPI.Apply(made.GetPrim(), axis)
            limit.CreateLowAttr(low)
            limit.CreateHighAttr(high)
        if joint["kind"] in ("revolute", "prismatic"):
            made.CreateAxisAttr(joint.get("axis", "X"))
            if "limits" in joint:
                made.CreateLowerLimitAttr(joint["limits"][0])
                made.CreateUpperLimitAttr(joint["limits"][1])
        if "state" in joint:
            kind = "angular" if joint["kind"] == "revolute" else "linear"
            value = math.degrees(joint["state"]) if kind == "angular" else joint["state"]
            made.GetPrim().AddAppliedSchema(f"PhysicsJointStateAPI:{kind}")
            state = f"state:{kind}:physics:position"
            made.GetPrim().CreateAttribute(state, Sdf.ValueTypeNames.Float).Set(value)
    (HERE / f"{name}.usda").write_text(stage.GetRootLayer().ExportToString())


def joint(name: str, kind: str, bodies: tuple[str | None, str | None], frame0: Any,
          frame1: Any, **more: Any) -> dict[str, Any]:  # fmt: skip
    """A joint: its bodies (body0, body1), its frames in them ((position, turn) each)."""
    (pos0, rot0), (pos1, rot1) = frame0, frame1
    ends = {f"body{k}": b for k, b in enumerate(bodies) if b is not None}
    return {"name": name, "kind": kind, **ends, "pos0": pos0, "rot0": rot0, "pos1": pos1,
            "rot1": rot1, **more}  # fmt: skip


HOME = (ORIGIN, NONE)
"""A joint frame at its body's origin, unturned."""


def main() -> None:
    arm = {"base": {"body": True, "root": True}, "upper": BODY, "fore": BODY}
    build(
        "cm_arm",
        "metersPerUnit 0.01: a base fixed to the world by a joint with no body0 (its frame in "
        "world coordinates); rotated localRot0 and localRot1; revolute joints about X and Y; a "
        "prismatic joint along Z (cm); a fixed joint between moving ones; a joint turning freely "
        "about the X axis of a frame turned 40 degrees about (1, 1, 0), an axis off the "
        "bracket's own axes",
        {**arm, "slider": BODY, "bracket": BODY, "spinner": BODY},
        [
            joint(
                "mount",
                "fixed",
                (None, "base"),
                ((10, 20, 30), turn((0, 0, 1), 90)),
                ((0, 0, -5), NONE),
            ),
            joint(
                "shoulder",
                "revolute",
                ("base", "upper"),
                ((0, 0, 15), turn((0, 1, 0), 90)),
                ((2, 0, 0), turn((0, 1, 0), -60)),
                axis="X",
                limits=(-90, 90),
            ),
            joint(
                "elbow",
                "revolute",
                ("upper", "fore"),
                ((0, 0, 40), turn((1, 0, 0), 30)),
                ((0, 0, -3), NONE),
                axis="Y",
                limits=(-120, 10),
            ),
            joint(
                "slide",
                "prismatic",
                ("fore", "slider"),
                ((0, 5, 30), turn((1, 1, 1), 120)),
                (ORIGIN, turn((0, 0, 1), 45)),
                axis="Z",
                limits=(0, 25),
            ),
            joint(
                "weld",
                "fixed",
                ("slider", "bracket"),
                ((3, 0, 8), turn((1, 0, 0), -90)),
                ((0, 1, 0), turn((0, 1, 0), 15)),
            ),
            joint(
                "wrist",
                "revolute",
                ("bracket", "spinner"),
                ((0, 0, 6), turn((1, 1, 0), 40)),
                ((1, 0, 0), turn((0, 0, 1), -20)),
                axis="X",
            ),
        ],
        meters=0.01,
    )
    build(
        "scaled_free",
        "A free root body (no joint to the world) at an authored pose, below an Xform scaled by "
        "2, and a child body of its own non-uniform scale (1, 1.5, 0.5): UsdPhysics scales each "
        "joint's localPos by its body's world scale. The joint 'reach' names a prim below its "
        "body (the arm's marker), whose transform carries the anchor into the body's frame",
        {
            "frame": {"scale": (2, 2, 2)},
            "base": {
                "parent": "frame",
                "body": True,
                "root": True,
                "pose": pose((0.3, -0.2, 1.1), turn((1, 2, 3), 70)),
            },
            "arm": {"parent": "base", "body": True, "scale": (1, 1.5, 0.5)},
            "marker": {"parent": "arm", "local": pose((0.02, -0.03, 0.25), turn((0, 1, 0), 35))},
            "hand": {"parent": "base", "body": True},
        },
        [
            joint(
                "lift",
                "revolute",
                ("base", "arm"),
                ((0.1, 0.2, 0.3), turn((1, 0, 0), 20)),
                ((0.1, 0.1, 0.2), NONE),
                axis="Z",
                limits=(-170, 170),
            ),
            joint(
                "reach",
                "prismatic",
                ("arm", "hand"),
                ((0.05, 0, 0.1), turn((0, 0, 1), 30)),
                ((0, 0, -0.05), NONE),
                axis="Y",
                limits=(-0.2, 0.2),
                target0="marker",
            ),
        ],
    )
    build(
        "reversed",
        "Joints whose body0 is the child in the tree: a base fixed to the world through a joint "
        "whose body1 is empty (its localPos1 in world coordinates), a knee whose body0 is the "
        "shin, and a joint turning freely whose body0 is the wheel: each moves body1 in body0's "
        "frame, so the tree, which runs the other way, turns its axis round",
        {"base": {"body": True, "root": True}, "shin": BODY, "wheel": BODY},
        [
            joint(
                "anchor",
                "fixed",
                ("base", None),
                ((0, 0, -0.1), turn((0, 0, 1), 10)),
                ((1, 2, 0.5), turn((1, 0, 0), 25)),
            ),
            joint(
                "knee",
                "revolute",
                ("shin", "base"),
                ((0, 0, 0.2), turn((0, 0, 1), -30)),
                ((0.1, 0, -0.3), NONE),
                axis="Y",
                limits=(-100, 20),
            ),
            joint(
                "axle",
                "revolute",
                ("wheel", "shin"),
                ((0.02, 0, 0), turn((0, 1, 1), 50)),
                ((0, 0.05, -0.25), NONE),
                axis="X",
            ),
        ],
    )
    mount = joint("mount", "fixed", (None, "base"), ((0, 0, 0.5), NONE), HOME)
    shoulder = joint("shoulder", "revolute", ("base", "upper"), ((0, 0, 0.1), NONE), HOME,
                     axis="Y", limits=(-90, 90))  # fmt: skip
    elbow = joint("elbow", "revolute", ("upper", "fore"), ((0, 0, 0.4), NONE), HOME, axis="Y",
                  limits=(-90, 90))  # fmt: skip
    build(
        "snapped",
        "The forearm is authored 0.1 m off where its joint frames put it: the joint frames "
        "decide (PhysX and Newton move it there)",
        arm,
        [mount, shoulder, elbow],
        offsets={"fore": pose((0.1, 0, 0), NONE)},
    )
    build(
        "joint_state",
        "Joint states authored (PhysicsJointStateAPI): the slide at 0.05 m, the elbow at 30 "
        "degrees; the bodies are authored at that state",
        arm,
        [
            mount,
            joint(
                "slide",
                "prismatic",
                ("base", "upper"),
                ((0, 0, 0.1), turn((0, 0, 1), 15)),
                HOME,
                axis="X",
                limits=(-0.1, 0.1),
                state=0.05,
            ),
            {**elbow, "pos1": (0, 0, -0.02), "state": math.radians(30)},
        ],
    )
    build(
        "disabled",
        "A base welded to a pedestal whose rigid body is disabled (physics:rigidBodyEnabled "
        "false: it does not move, cspace takes it for the world) and which stands turned and "
        "scaled by 3: the weld's frame in it is carried into the world",
        {
            "pedestal": {
                "body": True,
                "disabled": True,
                "scale": (3, 3, 3),
                "pose": pose((0.5, -0.5, 0.2), turn((0, 0, 1), 120)),
            },
            **arm,
        },
        [
            joint(
                "weld", "fixed", ("pedestal", "base"), ((0, 0.1, 0.3), turn((1, 0, 0), 15)), HOME
            ),
            shoulder,
            elbow,
        ],
    )
    locked = dict.fromkeys(("transY", "transZ", "rotX", "rotY"), LOCK)
    build(
        "d6",
        "Generic (D6) and spherical joints between turned frames: 'sled' moves in the joint "
        "frame's y-z plane and turns about its x (planar about x: Pinocchio's planar joint is "
        "turned so that its z is that x); 'gimbal' slides along x within limits and turns "
        "freely about z (one joint a free axis, chained through a link of its own); 'ball' "
        "turns about a point",
        {"base": {"body": True, "root": True}, "sled": BODY, "gimbal": BODY, "head": BODY},
        [
            joint("mount", "fixed", (None, "base"), ((0.2, 0, 0.4), turn((0, 0, 1), -35)), HOME),
            joint(
                "sled",
                "d6",
                ("base", "sled"),
                ((0.1, 0.2, 0.05), turn((1, -1, 0), 50)),
                ((0, 0.03, 0), turn((0, 0, 1), 80)),
                d6={"transX": LOCK, "rotY": LOCK, "rotZ": LOCK},
            ),
            joint(
                "gimbal",
                "d6",
                ("sled", "gimbal"),
                ((0, 0, 0.1), turn((0, 1, 0), 20)),
                ((0.01, 0, 0), turn((1, 0, 0), -45)),
                d6={"transX": (-0.1, 0.1), **locked},
            ),
            joint(
                "ball",
                "ball",
                ("gimbal", "head"),
                ((0, 0.05, 0.05), turn((1, 1, 1), 45)),
                ((0, 0, -0.04), turn((0, 1, 0), 90)),
            ),
        ],
    )
    locks = {axis: LOCK for axis in ("transX", "transY", "transZ", "rotX", "rotY", "rotZ")}
    build(
        "d6_reversed",
        "Generic (D6) joints whose body0 is the child in the tree, between turned frames: "
        "'cardan' turns freely about x and z (universal), 'skid' moves in the x-z plane and "
        "turns about y (planar about y), 'gantry' slides along x, y and z (translation), "
        "'rail' slides along x within limits and turns freely about z: each value is "
        "PhysX's (body1's motion in body0's frame), so each is a chain of one joint per axis",
        {
            "base": {"body": True, "root": True},
            "yoke": BODY,
            "skid": BODY,
            "carriage": BODY,
            "slider": BODY,
        },
        [
            joint("mount", "fixed", (None, "base"), ((0, 0.1, 0.3), turn((1, 0, 0), 20)), HOME),
            joint(
                "cardan",
                "d6",
                ("yoke", "base"),
                ((0.02, -0.01, 0.05), turn((0, 1, 1), 35)),
                ((0.1, 0, 0.2), turn((1, 0, 0), -25)),
                d6={k: v for k, v in locks.items() if k not in ("rotX", "rotZ")},
            ),
            joint(
                "skid",
                "d6",
                ("skid", "yoke"),
                ((0, 0.03, -0.02), turn((1, 0, 1), 60)),
                ((0.05, 0.1, 0), turn((0, 0, 1), 15)),
                d6={k: v for k, v in locks.items() if k not in ("transX", "transZ", "rotY")},
            ),
            joint(
                "gantry",
                "d6",
                ("carriage", "skid"),
                ((0.01, 0, 0.02), turn((1, 1, 0), -40)),
                ((0, 0.2, 0.05), turn((0, 1, 0), 30)),
                d6={k: v for k, v in locks.items() if k.startswith("rot")},
            ),
            joint(
                "rail",
                "d6",
                ("slider", "carriage"),
                ((0, 0, -0.03), turn((0, 0, 1), 70)),
                ((0.1, 0.05, 0), turn((1, 2, 3), 50)),
                d6={
                    **{k: v for k, v in locks.items() if k not in ("transX", "rotZ")},
                    "transX": (-0.1, 0.1),
                },
            ),
        ],
    )


if __name__ == "__main__":
    main()
