"""`cspace.pinocchio_model()` of an OpenUSD robot puts every body where the file does.

Every USD robot file of the test corpora (``tests/usd`` and its folders, the docs'
example) is held, body by body, to:

1. OpenUSD's composed transforms (``UsdGeom.XformCache``, scale removed, in metres) at
   the state the file is authored in: the joints at zero or at their authored
   ``PhysicsJointStateAPI`` state, a free root at its authored pose. UsdPhysics stores
   joint frames in single precision (``point3f``, ``quatf``), so the bodies agree with
   them to float32 rounding: within 1e-6.
2. A float64 composition of OpenUSD's own joint frames, computed here from each joint's
   ``localPos``/``localRot`` and the bodies' composed transforms (its own code, not the
   reader's), at random configurations: within 1e-9 m and rad. A D6 joint moves by
   PhysX's value of each free axis, whichever way the tree runs through it; a ball is
   held to what it leaves fixed.
3. UsdPhysics' own parsed joint frames (``UsdPhysicsLoadStageFromPrimRange``: its
   ``localPose0``/``localPose1``, which it keeps in float32), composed likewise: within
   1e-6. An independent reference where this test's own anchor is not one: a body with
   a sheared transform (an uneven scale above a turn), whose scale UsdPhysics takes
   otherwise than column by column.
4. Newton's forward kinematics (``newton.eval_fk`` on ``ModelBuilder.add_usd``, in a
   child process), at the same configurations converted to Newton's joints through
   cspace's Isaac convention: Newton computes in float32 (``wp.transformf``), so within
   1e-5. Newton works in stage units (it does not convert ``metersPerUnit``): its
   lengths are scaled here.

And each of urdf-usd-converter's stages (``tests/usd/converted``) puts every body where
its URDF does, as Pinocchio's own URDF parser builds it.

``tests/usd/placed`` holds the hand-made cases (``make.py`` writes them): centimetres,
turned frames, axes X and Y, prismatic and fixed joints, a free root under scaled
Xforms, a joint named through a prim below its body, joints whose body0 is the child,
D6 and spherical joints, D6 joints whose body0 is the child, an authored joint state,
and a body authored off its joint frames (the joint frames decide, as in PhysX and
Newton).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
from pxr import Sdf, Usd, UsdGeom, UsdPhysics

import cspace
from cspace.errors import JointMatchError, ModelBuildError

from conftest import REPO, run_cli

HERE = REPO / "tests" / "usd"


def _key(stage: Path) -> str:
    return str(stage.relative_to(HERE)) if stage.is_relative_to(HERE) else stage.name


STAGES = sorted(
    [*HERE.glob("*.usda"), *HERE.glob("*/*.usda"), REPO / "docs/examples/usd_joints.usda"]
)
REFUSED = {"cases/mpu0.usda": "metersPerUnit 0: refused (tests/test_usd.py)"}
CHECKED = [s for s in STAGES if _key(s) not in REFUSED]
OFF = {"placed/snapped.usda": {"fore": (0.1, 0.0)}}
"""Bodies authored off their joint frames, and by how much (m, rad)."""
SAMPLES = 6
FLOAT32 = 1e-5
PARSED = 1e-6
"""How far from UsdPhysics' own joint frames a body may be: it keeps them in float32."""


def _polar(m: np.ndarray) -> np.ndarray:
    u, _, vt = np.linalg.svd(m)
    return u @ vt


def _pose(position: Any, wxyz: Any) -> np.ndarray:
    out = np.eye(4)
    w, x, y, z = (float(c) for c in wxyz)
    out[:3, :3] = pin.Quaternion(w, x, y, z).normalized().matrix()
    out[:3, 3] = [float(c) for c in position]
    return out


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    """Distance (m) plus angle (rad) between two poses."""
    turn = np.linalg.norm(pin.log3(_polar(a[:3, :3].T @ b[:3, :3])))
    return float(np.linalg.norm(a[:3, 3] - b[:3, 3]) + turn)


class Stage:
    """A stage as OpenUSD composes it: names, bodies' poses, joints' frames (m)."""

    def __init__(self, path: Path) -> None:
        self.stage = Usd.Stage.Open(str(path))
        self.mpu = UsdGeom.GetStageMetersPerUnit(self.stage)
        self.cache = UsdGeom.XformCache()
        prims = list(self.stage.Traverse(Usd.TraverseInstanceProxies()))
        self.bodies = [p for p in prims if self._simulated(p)]  # the others are the world's
        self.still = {str(p.GetPath()) for p in prims if p.HasAPI(UsdPhysics.RigidBodyAPI)}
        self.still -= {str(p.GetPath()) for p in self.bodies}
        joints = [p for p in prims if p.IsA(UsdPhysics.Joint)]
        self.name = self._names(self.bodies) | self._names(joints)
        self.joint = {self.name[str(p.GetPath())]: p for p in joints}
        self.parsed = self._parsed()

    def _parsed(self) -> dict[str, tuple[tuple[str | None, np.ndarray], ...]]:
        """Each joint's frames on its two sides as UsdPhysics parses them (its own
        ``localPose0``/``localPose1``, float32, scaled by its body's world scale): the
        body's name (None: the world) and the frame in the body's rigid frame (m)."""
        load = getattr(UsdPhysics, "UsdPhysicsLoadStageFromPrimRange", None)
        parsed = (load or UsdPhysics.LoadUsdPhysicsFromRange)(self.stage, [Sdf.Path("/")])
        out = {}
        for paths, descriptions in parsed.values():
            for path, said in zip(paths, descriptions, strict=True):
                if str(path) in self.name and hasattr(said, "localPose0Position"):
                    out[self.name[str(path)]] = tuple(self._side(said, k) for k in (0, 1))
        return out

    def _side(self, said: Any, side: int) -> tuple[str | None, np.ndarray]:
        rotation = getattr(said, f"localPose{side}Orientation")
        local = _pose(
            np.array(getattr(said, f"localPose{side}Position"), float) * self.mpu,
            (rotation.GetReal(), *rotation.GetImaginary()),
        )
        body = self.stage.GetPrimAtPath(getattr(said, f"body{side}"))
        if not body or str(body.GetPath()) not in self.name:  # the world, or a body held still
            return None, (self.body_pose(body) if body else np.eye(4)) @ local
        return self.name[str(body.GetPath())], local

    @staticmethod
    def _names(prims: list[Any]) -> dict[str, str]:
        own = {str(p.GetPath()): p.GetDisplayName() or p.GetName() for p in prims}
        counts = list(own.values())
        return {k: v if counts.count(v) == 1 else k for k, v in own.items()}

    def world(self, prim: Any) -> np.ndarray:
        return np.array(self.cache.GetLocalToWorldTransform(prim)).T

    def body_pose(self, prim: Any) -> np.ndarray:
        m = self.world(prim)
        out = np.eye(4)
        out[:3, :3], out[:3, 3] = _polar(m[:3, :3]), m[:3, 3] * self.mpu
        return out

    def anchor(self, joint: Any, side: int) -> tuple[str | None, np.ndarray]:
        """The joint's frame on one side: its body's name (None: the world), the frame in
        the body's (rigid) frame, from the raw attributes and the composed transforms."""
        get = joint.GetAttribute
        pos = get(f"physics:localPos{side}").Get() if get(f"physics:localPos{side}") else None
        rot = get(f"physics:localRot{side}").Get() if get(f"physics:localRot{side}") else None
        local = _pose(
            pos if pos is not None else (0, 0, 0),
            (rot.GetReal(), *rot.GetImaginary()) if rot is not None else (1, 0, 0, 0),
        )
        targets = joint.GetRelationship(f"physics:body{side}").GetTargets()
        if not targets:
            local[:3, 3] *= self.mpu
            return None, local
        target = self.stage.GetPrimAtPath(targets[0])
        body = target
        while body and not body.IsPseudoRoot() and not self._simulated(body):
            body = body.GetParent()
        held = body if body and not body.IsPseudoRoot() else None
        frame = self.world(held) if held else np.eye(4)
        inside = np.linalg.inv(frame) @ self.world(target)  # the target in its body
        anchor = np.eye(4)
        anchor[:3, 3] = (inside @ np.append(local[:3, 3], 1.0))[:3]
        anchor[:3, :3] = _polar(inside[:3, :3]) @ local[:3, :3]
        anchor[:3, 3] *= np.linalg.norm(frame[:3, :3], axis=0) * self.mpu  # physics: no scale
        return (self.name[str(held.GetPath())] if held else None), anchor

    @staticmethod
    def _simulated(prim: Any) -> bool:
        enabled = prim.GetAttribute("physics:rigidBodyEnabled")
        return bool(prim.HasAPI(UsdPhysics.RigidBodyAPI)) and not (enabled and not enabled.Get())

    def state(self, joint: Any) -> float:
        """The joint's authored state (rad, m), 0 where none is authored."""
        for kind, unit in (("angular", math.radians(1)), ("linear", self.mpu)):
            value = joint.GetAttribute(f"state:{kind}:physics:position")
            if value and value.Get() is not None:
                return float(value.Get()) * unit
        return 0.0


D6_ORDER = ("transX", "transY", "transZ", "rotX", "rotY", "rotZ")


def _free(joint: Any) -> list[str]:
    """A generic joint's free axes: no limit, or a limit whose low is not above its high."""
    free = []
    for axis in D6_ORDER:
        low = joint.GetAttribute(f"limit:{axis}:physics:low")
        high = joint.GetAttribute(f"limit:{axis}:physics:high")
        if not (low and high and low.Get() is not None and low.Get() > high.Get()):
            free.append(axis)
    return free


def _motion(axis: str, value: float) -> np.ndarray:
    """``transX`` ... ``rotZ`` (or a revolute ``X`` ...) by ``value``."""
    out = np.eye(4)
    unit = np.eye(3)["XYZ".index(axis[-1])]
    if axis.startswith("trans"):
        out[:3, 3] = value * unit
    else:
        out[:3, :3] = pin.exp3(value * unit)
    return out


IN_PLANE = {"Z": ("X", "Y"), "X": ("Y", "Z"), "Y": ("Z", "X")}
"""A planar D6 joint's rotation axis: its plane's axes, as its ``x`` and ``y`` take them."""


def _d6_values(
    base: str, chain: list[Any], free: list[str], one: Any, value: dict[str, float]
) -> dict[str, float] | None:
    """PhysX's value of each free axis of a D6 joint, from cspace's coordinates.

    ``one``: a joint's value (a mimic joint's from its leader); ``value``: each canonical
    coordinate's. A chain holds one joint per axis (``joint.rotX``); one joint of one
    axis holds it; a universal joint's ``axis1`` and ``axis2`` are its free rotations in
    PhysX's order, a planar one's ``x``, ``y`` and ``theta`` its plane's axes and its
    rotation, a translation's ``x``, ``y`` and ``z`` its axes. None for a ball or a free
    joint (a turn, not a value per axis).
    """
    if len(chain) > 1:
        return {axis: one(f"{base}.{axis}") for axis in free}
    if len(free) == 1:
        return {free[0]: one(base)}
    kind = chain[0].kind.value
    names: dict[str, str] = {}
    if kind == "universal":
        turns = [a for a in free if a.startswith("rot")]
        names = dict(zip(turns, ("axis1", "axis2"), strict=True))
    elif kind == "planar":
        (turn,) = [a[-1] for a in free if a.startswith("rot")]
        u, v = IN_PLANE[turn]
        names = {f"trans{u}": "x", f"trans{v}": "y", f"rot{turn}": "theta"}
    elif kind == "translation":
        names = {f"trans{a}": a.lower() for a in "XYZ"}
    else:
        return None
    return {axis: float(value[f"{base}.{name}"]) for axis, name in names.items()}


class Robot:
    """One stage, as cspace reads it and as OpenUSD composes it."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.usd = Stage(path)
        self.space = cspace.load(path)
        self.model = cspace.pinocchio_model(path)
        self.data = self.model.createData()
        self.joints_in_order = self.space.report_joints  # every joint, fixed ones too
        self.joints = {j.name: j for j in self.joints_in_order}
        self.root = next(f.name for f in self.model.frames if f.type == pin.FrameType.BODY)

    def configurations(self, rng: np.random.Generator) -> np.ndarray:
        """The authored state, then random ones (canonical)."""
        names = list(self.space.names)
        authored = np.array([1.0 if n.endswith(".qw") else 0.0 for n in names])
        bounds = {}
        for joint in self.joints_in_order:
            prim = self.usd.joint.get(joint.name)
            if joint.kind.value == "floating" and prim is None:
                body = next(b for b in self.usd.bodies if self._named(b) == joint.child_link)
                pose = self.usd.body_pose(body)
                wxyz = pin.Quaternion(pose[:3, :3]).coeffs()[[3, 0, 1, 2]]
                for suffix, value in zip(
                    ("x", "y", "z", "qw", "qx", "qy", "qz"), [*pose[:3, 3], *wxyz], strict=True
                ):
                    authored[names.index(f"{joint.name}.{suffix}")] = value
            elif prim is not None and joint.name in names:
                authored[names.index(joint.name)] = self.usd.state(prim)
            for coordinate in names:
                if coordinate.split(".")[0] == joint.name and coordinate[-2:] in (".x", ".y", ".z"):
                    bounds[coordinate] = (-1.0, 1.0)
            if joint.kind.value == "prismatic" and joint.limits is None and joint.name in names:
                bounds[joint.name] = (-1.0, 1.0)
        return np.vstack([authored, self.space.sample(SAMPLES, rng, bounds=bounds)])

    def mimics_broken(self) -> set[str]:
        """The links below a mimic joint authored off its relation (``mimics.usda``'s
        offsets: its leader at 0, itself at 0): no configuration of the robot is there."""
        below: dict[str, list[str]] = {}
        for joint in self.joints_in_order:
            below.setdefault(joint.parent_link or "", []).append(joint.child_link)
        broken: list[str] = []
        for joint in self.joints_in_order:
            if joint.mimic is None:
                continue
            said = joint.mimic.multiplier * self.usd.state(self.usd.joint[joint.mimic.joint])
            if abs(said + joint.mimic.offset - self.usd.state(self.usd.joint[joint.name])) > 0:
                broken.append(joint.child_link)
        for link in broken:
            broken.extend(below.get(link, ()))
        return set(broken)

    def _named(self, prim: Any) -> str:
        return self.usd.name[str(prim.GetPath())]

    def body_poses(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """Pinocchio's BODY frames in the world at ``x``, by link."""
        pin.framesForwardKinematics(self.model, self.data, self.space.to_pinocchio(x))
        return {
            frame.name: self.data.oMf[k].homogeneous
            for k, frame in enumerate(self.model.frames)
            if frame.type == pin.FrameType.BODY
        }

    def composed(
        self, x: np.ndarray, found: dict[str, np.ndarray], parsed: bool = False
    ) -> dict[str, np.ndarray]:
        """Every body's pose, OpenUSD's joint frames composed from the world in float64.

        A joint of one coordinate moves by its value (a mimic joint's from its leader),
        a D6 joint by PhysX's value of each free axis (`_d6_values`), whichever way the
        tree runs through it; a ball (or a free D6 joint) is held to what it leaves
        fixed, its motion then taken from ``found`` (Pinocchio's) to go on. ``parsed``:
        the joint frames UsdPhysics parses (float32, `PARSED`), not this test's own.
        """
        value = dict(zip(self.space.names, x, strict=True))

        def one(name: str) -> float:
            mimic = self.joints[name].mimic
            if mimic is not None:
                return mimic.multiplier * one(mimic.joint) + mimic.offset
            return float(value.get(name, 0.0))

        groups: dict[str, list[Any]] = {}
        for joint in self.joints_in_order:
            base = joint.name if joint.name in self.usd.joint else joint.name.rsplit(".", 1)[0]
            groups.setdefault(base if base in self.usd.joint else joint.name, []).append(joint)
        world = {self.root: np.eye(4)}
        for base, chain in groups.items():
            parent, child = chain[0].parent_link, chain[-1].child_link
            if base not in self.usd.joint:  # a floating body's own joint
                q = [value[f"{base}.{s}"] for s in ("x", "y", "z", "qw", "qx", "qy", "qz")]
                world[child] = _pose(q[:3], q[3:])
                continue
            prim = self.usd.joint[base]
            if parsed:
                (b0, a0), (_, a1) = self.usd.parsed[base]
            else:
                (b0, a0), (_, a1) = self.usd.anchor(prim, 0), self.usd.anchor(prim, 1)
            forward = (b0 or self.root) == parent
            near, far = (a0, a1) if forward else (a1, a0)
            seen = np.linalg.inv(found[parent] @ near) @ found[child] @ far
            held = PARSED if parsed else 1e-9  # what the joint leaves fixed stays so
            motion = self._motion(
                base, chain, one, value, seen if forward else np.linalg.inv(seen), held
            )
            if chain[0].kind.value == "spherical" and forward:  # its value is the turn
                q = [value[f"{base}.{s}"] for s in ("qw", "qx", "qy", "qz")]
                assert _gap(motion, _pose((0, 0, 0), q)) < held, (base, motion)
            step = a0 @ motion @ np.linalg.inv(a1)
            world[child] = world[parent] @ (step if forward else np.linalg.inv(step))
        return world

    def _motion(
        self,
        base: str,
        chain: list[Any],
        one: Any,
        value: dict[str, float],
        seen: np.ndarray,
        held: float,
    ) -> np.ndarray:
        """Body1's joint frame in body0's: from the values, or ``seen`` held to the joint."""
        prim = self.usd.joint[base]
        kind = chain[0].kind.value
        if kind == "fixed":
            return np.eye(4)
        if prim.GetTypeName() == "PhysicsJoint":
            free = _free(prim)
            values = _d6_values(base, chain, free, one, value)
            if values is not None:  # one factor per axis, in PhysX's order
                motion = np.eye(4)
                for axis in free:
                    motion = motion @ _motion(axis, values[axis])
                return motion
            for k, axis in enumerate("XYZ"):  # a ball or a free joint: its turn is free
                if f"trans{axis}" not in free:
                    assert abs(seen[k, 3]) < held, (prim.GetPath(), axis, seen[k, 3])
            return seen
        if kind == "spherical":
            assert np.linalg.norm(seen[:3, 3]) < held, prim.GetPath()
            return seen
        axis = str(prim.GetAttribute("physics:axis").Get() or "X")
        letter = ("trans" if prim.IsA(UsdPhysics.PrismaticJoint) else "rot") + axis
        return _motion(letter, one(chain[0].name))


@pytest.fixture(scope="module")
def robots() -> dict[str, Robot]:
    return {_key(stage): Robot(stage) for stage in CHECKED}


def test_every_body_is_where_openusd_composes_it(robots: dict[str, Robot]) -> None:
    """At the authored state, each body's pose is its composed transform (scale removed,
    in metres), but for a body authored off its joint frames: there the joint frames
    decide, and the gap is the one the file was made with."""
    worst, bodies, broken = 0.0, 0, 0
    for key, robot in robots.items():
        found = robot.body_poses(robot.configurations(np.random.default_rng(0))[0])
        skipped = robot.mimics_broken()
        for body in robot.usd.bodies:
            name = robot.usd.name[str(body.GetPath())]
            if name in skipped:
                broken += 1
                continue
            gap = _gap(found[name], robot.usd.body_pose(body))
            off = OFF.get(key, {}).get(name)
            if off is not None:
                assert gap == pytest.approx(sum(off), abs=1e-6), (key, name)
                continue
            assert gap < 1e-6, (key, name, gap)
            worst, bodies = max(worst, gap), bodies + 1
    print(
        f"authored state: {len(robots)} files, {bodies} bodies, largest gap {worst:.2e} "
        f"({broken} below a mimic joint whose authored state breaks its relation)"
    )


def test_every_body_is_where_the_joint_frames_compose_it(robots: dict[str, Robot]) -> None:
    """At random configurations, each body's pose is OpenUSD's joint frames composed
    from the world in float64 (`Robot.composed`), within 1e-9 m and rad."""
    worst, poses = 0.0, 0
    for seed, (key, robot) in enumerate(robots.items()):
        for x in robot.configurations(np.random.default_rng(seed)):
            found = robot.body_poses(x)
            for name, pose in robot.composed(x, found).items():
                gap = _gap(found[name], pose)
                assert gap < 1e-9, (key, name, gap, x)
                worst, poses = max(worst, gap), poses + 1
    print(f"float64 composition: {len(robots)} files, {poses} poses, largest gap {worst:.2e}")


def test_every_body_is_where_usdphysics_joint_frames_compose_it(robots: dict[str, Robot]) -> None:
    """At random configurations, each body's pose is UsdPhysics' own parsed joint frames
    composed from the world (float32 frames: within 1e-6 m and rad)."""
    worst, poses = 0.0, 0
    for seed, (key, robot) in enumerate(robots.items()):
        assert robot.usd.parsed.keys() == robot.usd.joint.keys(), key
        for x in robot.configurations(np.random.default_rng(seed)):
            found = robot.body_poses(x)
            for name, pose in robot.composed(x, found, parsed=True).items():
                gap = _gap(found[name], pose)
                assert gap < PARSED, (key, name, gap, x)
                worst, poses = max(worst, gap), poses + 1
    print(f"UsdPhysics' joint frames: {len(robots)} files, {poses} poses, largest gap {worst:.2e}")


SHEARED = """#usda 1.0
(
    defaultPrim = "robot"
    metersPerUnit = 1
)
def Xform "robot"
{
    def Xform "holder"
    {
        float3 xformOp:scale = (1, 3, 0.5)
        float3 xformOp:rotateXYZ = (0, 0, 30)
        uniform token[] xformOpOrder = ["xformOp:scale", "xformOp:rotateXYZ"]
        def Xform "base" (
            prepend apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsArticulationRootAPI"]
        )
        {
            double3 xformOp:translate = (0.1, 0, 0.2)
            float3 xformOp:rotateXYZ = (20, 0, 10)
            uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateXYZ"]
            def Xform "anchor"
            {
                double3 xformOp:translate = (0.1, 0.2, 0.0)
                float3 xformOp:rotateXYZ = (0, 40, 0)
                float3 xformOp:scale = (1, 2, 1)
                uniform token[] xformOpOrder = [
                    "xformOp:translate", "xformOp:rotateXYZ", "xformOp:scale"
                ]
            }
        }
        def Xform "arm" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
        {
            double3 xformOp:translate = (0.3, 0, 0.2)
            uniform token[] xformOpOrder = ["xformOp:translate"]
        }
    }
    def PhysicsFixedJoint "mount"
    {
        rel physics:body1 = </robot/holder/base>
        point3f physics:localPos0 = (0.1, 0, 0.2)
    }
    def PhysicsRevoluteJoint "hinge"
    {
        rel physics:body0 = </robot/holder/base/anchor>
        rel physics:body1 = </robot/holder/arm>
        point3f physics:localPos0 = (0.1, 0.1, 0.2)
        point3f physics:localPos1 = (0, 0.1, 0)
        token physics:axis = "Z"
    }
}
"""
"""Bodies below an Xform scaled unevenly and then turned: their transforms are sheared;
the hinge names a prim below its body, itself turned and scaled."""


def test_a_sheared_body_is_where_usdphysics_puts_its_joint_frames(tmp_path: Path) -> None:
    """Where this test's own anchor is no reference (it takes a sheared body's scale
    column by column, as UsdPhysics does not, and puts the arm 0.47 from UsdPhysics'
    frames), UsdPhysics' parsed frames are: every body is where they compose it."""
    stage = tmp_path / "shear.usda"
    stage.write_text(SHEARED)
    robot = Robot(stage)
    parsed = own = 0.0
    for x in robot.configurations(np.random.default_rng(5)):
        found = robot.body_poses(x)
        parsed = max(
            [parsed] + [_gap(found[n], p) for n, p in robot.composed(x, found, True).items()]
        )
        own = max([own] + [_gap(found[n], p) for n, p in robot.composed(x, found).items()])
    assert parsed < PARSED and own > 0.1, (parsed, own)


def test_a_d6_joint_run_backwards_keeps_physx_values_per_axis() -> None:
    """A universal, planar or translation D6 joint whose body0 is the child: each of its
    coordinates is PhysX's value of one axis and named after it. One coordinate set,
    the others at zero: body1's joint frame in body0's is that axis's motion by it, as
    for the joint written the other way round (a universal joint's ``axis1`` held PhysX's
    second axis, a planar one's ``x`` moved body0 where PhysX moves body1)."""
    path = HERE / "placed" / "d6_reversed.usda"
    robot = Robot(path)
    assert robot.space.names == (
        "cardan.rotZ", "cardan.rotX", "skid.rotY", "skid.transZ", "skid.transX",
        "gantry.transZ", "gantry.transY", "gantry.transX", "rail.rotZ", "rail.transX",
    )  # fmt: skip
    assert cspace.inspect(path).manifold.notation == "R^6 × T^4"  # as written forwards
    for k, name in enumerate(robot.space.names):
        joint, axis = name.split(".")
        prim = robot.usd.joint[joint]
        (body0, a0), (body1, a1) = robot.usd.anchor(prim, 0), robot.usd.anchor(prim, 1)
        x = robot.space.neutral()
        x[k] = 0.05
        found = robot.body_poses(x)
        motion = np.linalg.inv(found[body0 or "world"] @ a0) @ found[body1 or "world"] @ a1
        assert _gap(motion, _motion(axis, 0.05)) < 1e-9, name


NEWTON_REFUSES = {
    **dict.fromkeys(
        ("cases/bfs_excl.usda", "cases/bfs_fixed.usda", "cases/float_clash.usda",
         "cases/loop.usda", "cases/world_body.usda"),
        "not belonging to any articulation",
    ),  # a joint outside every articulation (cspace reads it as UsdPhysics does)
    "cases/mimic_ignored.usda": "cannot mimic itself",  # cspace: mimic-ignored
    "cases/self.usda": "both endpoints resolve to the same rigid body",  # joint-left-out
    "placed/reversed.usda": "Reversed joints are not supported",
    "placed/d6_reversed.usda": "Reversed joints are not supported",
}  # fmt: skip
"""The stages Newton's importer refuses, and what it says."""

ISAAC_REFUSES = {
    "usd_joints.usda",
    "cases/ballapi.usda",
    "converted/mobile_manipulator.usda",
    "placed/d6.usda",
}
"""The stages whose balls, planar or D6 joints cspace's Isaac convention refuses: held to
Newton at the authored state only (and to the float64 composition everywhere)."""

NEWTON = """
import json, sys
import warp as wp
wp.config.quiet = True
wp.config.kernel_cache_dir = sys.argv[1]
wp.config.optimization_level = 0  # compiles in a third of the time, float32 all the same
wp.config.enable_backward = False
import newton
from newton import JointType, ModelBuilder
from newton._src.usd.schemas import SchemaResolverNewton, SchemaResolverPhysx
from pxr import Usd, UsdGeom
out = {}
for path, configurations in json.loads(sys.stdin.read()).items():
    try:
        stage = Usd.Stage.Open(path)
        builder = ModelBuilder(up_axis=UsdGeom.GetStageUpAxis(stage))
        builder.add_usd(stage, load_visual_shapes=False, skip_mesh_approximation=True,
                        schema_resolvers=[SchemaResolverNewton(), SchemaResolverPhysx()],
                        joint_ordering="bfs", bodies_follow_joint_ordering=True)
        model = builder.finalize(device="cpu", skip_validation_inertia=True)
    except Exception as exc:
        out[path] = str(exc).splitlines()[0]
        continue
    starts = list(builder.joint_q_start) + [len(builder.joint_q)]
    keys = [builder.joint_label[j] if builder.joint_type[j] != JointType.FREE
            else "free:" + builder.body_label[builder.joint_child[j]]
            for j in range(len(builder.joint_label))]
    poses = []
    for given in configurations if builder.joint_count else ():
        q = model.joint_q.numpy()
        for j, key in enumerate(keys):
            if given is not None and key in given:
                q[starts[j]:starts[j + 1]] = given[key]
        state = model.state()
        newton.eval_fk(model, wp.array(q, dtype=wp.float32, device="cpu"), model.joint_qd, state)
        poses.append(dict(zip(builder.body_label, state.body_q.numpy().tolist())))
    # eval_fk moves the bodies of articulations only: a joint outside one is left as built
    held = {builder.body_label[c] for j, c in enumerate(builder.joint_child)
            if builder.joint_articulation[j] >= 0}
    out[path] = {"poses": poses, "jointless": [b for b in builder.body_label if b not in held]}
print(json.dumps(out))
"""


def _newton_input(robot: Robot, xs: np.ndarray) -> list[dict[str, list[float]] | None]:
    """Each configuration as Newton's joint coordinates, through cspace's Isaac vectors.

    None where cspace's Isaac convention refuses the robot (a ball, a planar or a D6
    joint): Newton then stays at its own initial state, which is the authored one.
    """
    try:
        maps = robot.space.conventions().maps("isaac")
    except JointMatchError:
        return [None]
    names, path = maps.names(False), {n: str(p.GetPath()) for n, p in robot.usd.joint.items()}
    body = {robot.usd.name[str(b.GetPath())]: str(b.GetPath()) for b in robot.usd.bodies}
    out: list[dict[str, list[float]] | None] = []
    for q in maps.to_tool(xs):
        given: dict[str, list[float]] = {}
        for joint in robot.joints_in_order:
            if joint.kind.value == "floating":
                root = (
                    joint.child_link if f"{joint.child_link}_x" in names else f"_{joint.child_link}"
                )
                at = [names.index(f"{root}_{s}") for s in ("x", "y", "z", "qx", "qy", "qz", "qw")]
                pose = [float(q[k]) for k in at]
                given["free:" + body[joint.child_link]] = [
                    c / robot.usd.mpu for c in pose[:3]
                ] + pose[3:]
            elif joint.name in names:
                value = float(q[names.index(joint.name)])
                linear = robot.usd.joint[joint.name].IsA(UsdPhysics.PrismaticJoint)
                given[path[joint.name]] = [value / robot.usd.mpu if linear else value]
        out.append(given)
    return out


def test_every_body_is_where_newton_puts_it(
    robots: dict[str, Robot], tmp_path: Path, pytestconfig: pytest.Config
) -> None:
    """Newton's forward kinematics at the same configurations, converted through cspace's
    Isaac convention (its joint order and units), within Newton's float32; a robot the
    convention refuses at the authored state only. The warp kernels Newton compiles are
    kept in pytest's cache (about 4 s of CPU the first time)."""
    kept = getattr(pytestconfig, "cache", None)  # None under -p no:cacheprovider
    cache = kept.mkdir("warp") if kept is not None else tmp_path
    xs = {
        key: robot.configurations(np.random.default_rng(k))
        for k, (key, robot) in enumerate(robots.items())
    }
    asked = {str(robot.path): _newton_input(robot, xs[key]) for key, robot in robots.items()}
    run = subprocess.run(
        [sys.executable, "-c", NEWTON, str(cache)],
        input=json.dumps(asked), capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    answers = json.loads(run.stdout.strip().splitlines()[-1])
    worst, poses, refused, mapped = 0.0, 0, {}, 0
    for key, robot in robots.items():
        answer = answers[str(robot.path)]
        if isinstance(answer, str):
            refused[key] = answer
            continue
        given = asked[str(robot.path)]
        assert (given[0] is None) == (key in ISAAC_REFUSES), key
        mapped += given[0] is not None
        for k, (x, placed) in enumerate(zip(xs[key], answer["poses"], strict=False)):
            found = robot.body_poses(x)
            for label, (px, py, pz, *xyzw) in placed.items():
                if label in robot.usd.still or (k and label in answer["jointless"]):
                    continue  # a disabled body (the world's), or one eval_fk does not move
                newton_pose = _pose(np.array([px, py, pz]) * robot.usd.mpu, np.roll(xyzw, 1))
                gap = _gap(found[robot.usd.name[label]], newton_pose)
                assert gap < FLOAT32, (key, label, gap, x)
                worst, poses = max(worst, gap), poses + 1
    assert refused.keys() == NEWTON_REFUSES.keys(), refused
    for key, why in NEWTON_REFUSES.items():
        assert why in refused[key], (key, refused[key])
    assert mapped == len(robots) - len(refused) - len(ISAAC_REFUSES)
    print(
        f"Newton: {len(robots) - len(refused)} files ({mapped} at random configurations), "
        f"{poses} poses, largest gap {worst:.2e}"
    )


UNPLACED = """#usda 1.0
(
    defaultPrim = "robot"
)
def Xform "robot"
{
    def Xform "base" (prepend apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsArticulationRootAPI"])
    {
    }
    def Xform "arm" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {
        float3 xformOp:scale = (1, 1, 1)
        uniform token[] xformOpOrder = ["xformOp:scale"]
    }
    def PhysicsRevoluteJoint "shoulder"
    {
        rel physics:body0 = </robot/base>
        rel physics:body1 = </robot/arm>
        point3f physics:localPos0 = (0, 0, 0.1)
        float physics:lowerLimit = -90
        float physics:upperLimit = 90
    }
}
"""


@pytest.mark.parametrize(
    ("change", "why"),
    [
        (("(0, 0, 0.1)", "(nan, 0, 0.1)"), "a localPos0 that is not a number"),
        (("scale = (1, 1, 1)", "scale = (0, 0, 0)"), "a body scaled to nothing"),
    ],
)
def test_a_joint_that_cannot_be_placed_gives_no_model(
    tmp_path: Path, change: tuple[str, str], why: str
) -> None:
    """Its C-space is reported, but `pinocchio_model` refuses the robot in one line,
    naming the joint, rather than return a model that puts a body nowhere."""
    stage = tmp_path / "robot.usda"
    stage.write_text(UNPLACED.replace(*change))
    assert cspace.inspect(stage).manifold.notation == "R^4 × RP^3", why
    with pytest.raises(ModelBuildError) as refused:
        cspace.pinocchio_model(stage)
    said = str(refused.value)
    assert "joint 'shoulder'" in said and "no Pinocchio model is returned" in said, why
    assert "\n" not in said
    stage.write_text(UNPLACED)
    assert cspace.pinocchio_model(stage).njoints == 3  # the universe, base's, the shoulder


def test_a_joint_naming_a_prim_that_is_not_there_is_refused(tmp_path: Path) -> None:
    """A body relationship to no prim: PhysX skips the joint, OpenUSD's UsdPhysics reads
    it as the world; cspace says so, in one line, exit 2."""
    stage = tmp_path / "robot.usda"
    stage.write_text(UNPLACED.replace("</robot/arm>", "</robot/amr>"))
    run = run_cli("inspect", str(stage))
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert (
        "joint 'shoulder' names body1 </robot/amr>, which does not exist (PhysX skips such "
        "a joint; OpenUSD's UsdPhysics reads it as the world) [missing-link]"
    ) in run.stderr


CONVERTED = [
    s for s in sorted((HERE / "converted").glob("*.usda")) if s.stem != "sensor_head_fixed"
]
"""The converted teaching robots with a body (sensor_head_fixed's links are all fixed)."""


@pytest.mark.parametrize("stage", CONVERTED, ids=lambda p: p.stem)
def test_a_converted_urdf_puts_every_link_where_the_urdf_does(stage: Path) -> None:
    """urdf-usd-converter's output and its URDF (built by Pinocchio's own URDF parser):
    every link at the same pose at random configurations, within the float32 the
    converter writes joint frames in."""
    urdf = REPO / "robots" / f"{stage.stem}.urdf"
    ours, theirs = cspace.load(stage), cspace.load(urdf)
    # the converter drops a URDF's floating joint: cspace names the free body's own
    assert [n.replace("_free.", ".") for n in theirs.names] == list(ours.names)
    bounds = {n: (-1.0, 1.0) for n in theirs.names if n.endswith((".x", ".y", ".z"))}
    xs = theirs.sample(SAMPLES, np.random.default_rng(7), bounds=bounds)
    models = [cspace.pinocchio_model(stage), cspace.pinocchio_model(urdf)]
    datas = [m.createData() for m in models]
    for x in xs:
        for model, data, space in zip(models, datas, (ours, theirs), strict=True):
            pin.framesForwardKinematics(model, data, space.to_pinocchio(x))
        # every body of the stage (the URDF's links the converter made plain Xforms are not)
        links = [f.name for f in models[0].frames if f.type == pin.FrameType.BODY][1:]
        assert links, stage.stem
        for link in links:
            got, want = (
                d.oMf[m.getFrameId(link, pin.FrameType.BODY)].homogeneous
                for m, d in zip(models, datas, strict=True)
            )
            assert _gap(got, want) < 1e-6, (stage.stem, link)
