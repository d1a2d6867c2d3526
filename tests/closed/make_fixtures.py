"""Writes the closed-chain fixtures' SDF, URDF and OpenUSD files from their MJCF files.

``python tests/closed/make_fixtures.py`` rewrites them here; `texts` is what it writes
(tests/test_closure_formats.py holds the committed files to it). The MJCF files are the
mechanisms (their numbers, 17 significant digits, are taken as written); every number
written here has 17 significant digits too, so a float64 reads it back exactly.

- bennett.xml and fourr_rigid.xml: four hinges (about each body's z), the fourth body's
  ``end`` frame welded to the world. SDF and OpenUSD close the loop with a fixed joint
  between the world and ``l4`` at ``end``'s frame in ``l4``: the same tree (4 hinges) and
  the same 6 equations as the weld. SDF places the joints where the links' poses put
  them, so its links are written where the mechanism is assembled (`assembled`: the
  hinges' angles that close the loop, solved to float64's precision); OpenUSD's joint
  frames decide (UsdPhysics), so its joints are the MJCF's, its bodies' authored
  transforms those same assembled poses. URDF has no weld: neither is written in URDF.
- delta.xml: each rod's two hinges become two joints through a link of their own
  (``<rod>_u``), the platform floats (SDF: a link no joint holds; URDF: a ``floating``
  joint; OpenUSD: a generic joint no limit holds), each connect a ball: Drake's
  ``drake:ball_constraint`` in SDF and URDF, a spherical joint excluded from the
  articulation in OpenUSD.

OpenUSD's joint frames are float32 (``point3f``, ``quatf``: the schema's types): those
numbers are as close as float32 holds them, 9 significant digits.
"""

from __future__ import annotations

import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import NamedTuple

import numpy as np
from scipy.spatial.transform import Rotation

HERE = Path(__file__).resolve().parent


def g(x: float) -> str:
    """A float64 in 17 significant digits (no negative zero)."""
    return format(float(x) + 0.0, ".17g")


def f32(x: float) -> str:
    """A float32 value of x in 9 significant digits (enough to read it back)."""
    return format(float(np.float32(x)) + 0.0, ".9g")


def vec(values: np.ndarray) -> str:
    return " ".join(g(v) for v in values)


def numbers(text: str | None) -> np.ndarray:
    return np.array([float(w) for w in (text or "").split()])


def matrix(position: np.ndarray, rotation: Rotation) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = rotation.as_matrix()
    m[:3, 3] = position
    return m


def rot_z(angle: float) -> np.ndarray:
    return matrix(np.zeros(3), Rotation.from_rotvec([0.0, 0.0, angle]))


# --- the four-hinge loops (bennett.xml, fourr_rigid.xml) ---------------------------------


def chain(path: Path) -> list[tuple[str, np.ndarray, float]]:
    """The nested bodies l1 .. l4, end: (name, position in the parent, twist about x)."""
    body = ET.parse(path).getroot().find("worldbody/body")
    bodies = []
    while body is not None:
        euler = numbers(body.get("euler", "0 0 0"))
        if euler[1] != 0.0 or euler[2] != 0.0:
            raise ValueError(f"{path}: {body.get('name')}: a twist about x only")
        bodies.append((str(body.get("name")), numbers(body.get("pos", "0 0 0")), euler[0]))
        body = body.find("body")
    return bodies


def local(position: np.ndarray, twist: float) -> np.ndarray:
    return matrix(position, Rotation.from_rotvec([twist, 0.0, 0.0]))


def poses(bodies: list[tuple[str, np.ndarray, float]], q: np.ndarray) -> list[np.ndarray]:
    """The world poses of l1 .. l4 (each turned by its hinge) and of end, at q."""
    out, pose = [], np.eye(4)
    for k, (_, position, twist) in enumerate(bodies):
        pose = pose @ local(position, twist)
        if k < len(q):
            pose = pose @ rot_z(q[k])
        out.append(pose)
    return out


def gap(bodies: list[tuple[str, np.ndarray, float]], q: np.ndarray) -> np.ndarray:
    end = poses(bodies, q)[-1]
    return np.concatenate([end[:3, 3], Rotation.from_matrix(end[:3, :3]).as_rotvec()])


def assembled(path: Path, start: list[float], moves: bool) -> np.ndarray:
    """Hinge angles at which end's frame is the world's (Gauss-Newton from ``start``).

    Args:
        path: The MJCF file.
        start: The first guess; its first angle is kept when the mechanism moves.
        moves: Whether the mechanism moves (Bennett's) or is rigid (its solutions isolated).
    """
    bodies = chain(path)
    q, free = np.array(start), slice(1 if moves else 0, 4)
    for _ in range(100):
        r = gap(bodies, q)
        jacobian = np.empty((6, 4))
        for i in range(4):
            step = np.zeros(4)
            step[i] = 1e-7
            jacobian[:, i] = (gap(bodies, q + step) - gap(bodies, q - step)) / 2e-7
        step = np.linalg.lstsq(jacobian[:, free], r, rcond=None)[0]
        q[free] -= step
        if np.max(np.abs(step)) < 1e-16:
            break
    if np.max(np.abs(gap(bodies, q))) > 1e-14:
        raise ValueError(f"{path}: no assembled configuration found from {start}")
    return np.array([_snap(math.remainder(a, 2 * math.pi)) for a in q])


def _snap(angle: float) -> float:
    """An angle within 1e-12 of a multiple of pi/2 as that multiple (a solve leaves 1e-31)."""
    k = round(angle / (math.pi / 2))
    return k * (math.pi / 2) if abs(angle - k * (math.pi / 2)) < 1e-12 else angle


def quat_xyzw(m: np.ndarray) -> np.ndarray:
    return np.asarray(Rotation.from_matrix(m[:3, :3]).as_quat())


def hinges_sdf(name: str, path: Path, q: np.ndarray) -> str:
    bodies = chain(path)
    world = poses(bodies, q)
    (end, end_position, end_twist) = bodies[-1]
    links = "".join(
        f'    <link name="{b[0]}">\n      <pose rotation_format="quat_xyzw">'
        f"{vec(w[:3, 3])} {vec(quat_xyzw(w))}</pose>\n    </link>\n"
        for b, w in zip(bodies[:4], world, strict=False)
    )
    joints = "".join(
        f'    <joint name="j{k + 1}" type="continuous">\n'
        f"      <parent>{'world' if k == 0 else bodies[k - 1][0]}</parent>\n"
        f"      <child>{bodies[k][0]}</child>\n      <axis><xyz>0 0 1</xyz></axis>\n"
        "    </joint>\n"
        for k in range(4)
    )
    closing_pose = quat_xyzw(local(end_position, end_twist))
    closing = (
        '    <joint name="ground" type="fixed">\n'
        f'      <pose rotation_format="quat_xyzw">{vec(end_position)} {vec(closing_pose)}</pose>\n'
        "      <parent>world</parent>\n      <child>l4</child>\n    </joint>\n"
    )
    angles = ", ".join(g(a) for a in q)
    return (
        '<?xml version="1.0"?>\n'
        f"<!-- {name}.xml in SDF, written by make_fixtures.py: the same four hinges (about each\n"
        "     link's z), the links placed where the hinges' angles from the MJCF file's zero\n"
        f"     are {angles} (rad),\n"
        "     where the loop is closed. The fixed joint 'ground' gives l4 a second parent\n"
        f"     (the world) at the frame that is '{end}' in the MJCF file: a cut of 6 equations,\n"
        "     as the weld's. -->\n"
        f'<sdf version="1.9">\n  <model name="{name}">\n'
        f"{links}{joints}{closing}  </model>\n</sdf>\n"
    )


def quat_wxyz32(rotation: Rotation) -> str:
    x, y, z, w = rotation.as_quat()
    return f"({f32(w)}, {f32(x)}, {f32(y)}, {f32(z)})"


def point32(p: np.ndarray) -> str:
    return f"({f32(p[0])}, {f32(p[1])}, {f32(p[2])})"


def body_usd(name: str, pose: np.ndarray, indent: str = "    ") -> str:
    x, y, z, w = quat_xyzw(pose)
    t = pose[:3, 3]
    return (
        f'{indent}def Xform "{name}" (\n{indent}    prepend apiSchemas = ["PhysicsRigidBodyAPI"]\n'
        f"{indent})\n{indent}{{\n"
        f"{indent}    double3 xformOp:translate = ({g(t[0])}, {g(t[1])}, {g(t[2])})\n"
        f"{indent}    quatd xformOp:orient = ({g(w)}, {g(x)}, {g(y)}, {g(z)})\n"
        f'{indent}    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:orient"]\n'
        f"{indent}}}\n\n"
    )


def usd_header(doc: str, name: str) -> str:
    return (
        f'#usda 1.0\n(\n    doc = """{doc}"""\n    defaultPrim = "{name}"\n'
        '    metersPerUnit = 1\n    upAxis = "Z"\n)\n\n'
        f'def Xform "{name}" (\n    prepend apiSchemas = ["PhysicsArticulationRootAPI"]\n)\n{{\n'
    )


def joint_usd(
    kind: str,
    name: str,
    bodies: tuple[str | None, str],
    frames: tuple[np.ndarray, Rotation, np.ndarray, Rotation],
    extra: str = "",
) -> str:
    pos0, rot0, pos1, rot1 = frames
    lines = [f'        def {kind} "{name}"\n        {{\n']
    if bodies[0] is not None:
        lines.append(f"            rel physics:body0 = <{bodies[0]}>\n")
    lines.append(f"            rel physics:body1 = <{bodies[1]}>\n")
    lines.append(f"            point3f physics:localPos0 = {point32(pos0)}\n")
    lines.append(f"            quatf physics:localRot0 = {quat_wxyz32(rot0)}\n")
    lines.append(f"            point3f physics:localPos1 = {point32(pos1)}\n")
    lines.append(f"            quatf physics:localRot1 = {quat_wxyz32(rot1)}\n")
    return "".join(lines) + extra + "        }\n\n"


def hinges_usd(name: str, path: Path, q: np.ndarray) -> str:
    bodies = chain(path)
    world = poses(bodies, q)
    root = f"/{name}"
    none = Rotation.identity()
    zero = np.zeros(3)
    axis = '            uniform token physics:axis = "Z"\n'
    text = usd_header(
        f"{name}.xml in OpenUSD, written by make_fixtures.py: the same four hinges, each\n"
        "joint's frames the MJCF file's (UsdPhysics places the bodies by them); the bodies\n"
        "are authored where the loop is closed (the SDF file's poses). The fixed joint\n"
        f"'ground', excluded from the articulation, holds the frame that is '{bodies[-1][0]}'\n"
        "in the MJCF file on the world's: a cut of 6 equations, as the weld's.",
        name,
    )
    text += "".join(body_usd(b[0], w) for b, w in zip(bodies[:4], world, strict=False))
    text += '    def Scope "joints"\n    {\n'
    for k in range(4):
        parent = None if k == 0 else f"{root}/{bodies[k - 1][0]}"
        position, twist = bodies[k][1], bodies[k][2]
        frames = (position, Rotation.from_rotvec([twist, 0, 0]), zero, none)
        text += joint_usd(
            "PhysicsRevoluteJoint", f"j{k + 1}", (parent, f"{root}/{bodies[k][0]}"), frames, axis
        )
    end_position, end_twist = bodies[-1][1], bodies[-1][2]
    frames = (zero, none, end_position, Rotation.from_rotvec([end_twist, 0, 0]))
    text += joint_usd(
        "PhysicsFixedJoint",
        "ground",
        (None, f"{root}/l4"),
        frames,
        "            bool physics:excludeFromArticulation = 1\n",
    )
    return text.rstrip("\n") + "\n    }\n}\n"


# --- the delta robot (delta.xml) ----------------------------------------------------------


class Rod(NamedTuple):
    name: str
    position: np.ndarray
    """In its arm's frame."""
    axes: list[np.ndarray]


class Arm(NamedTuple):
    name: str
    position: np.ndarray
    axis: np.ndarray
    rods: list[Rod]


class Delta(NamedTuple):
    arms: list[Arm]
    platform: np.ndarray
    connects: list[tuple[str, np.ndarray]]
    """Each connect's rod and anchor in the rod's frame."""


def delta() -> Delta:
    """delta.xml's arms, platform and connects (every body turned as the world)."""
    root = ET.parse(HERE / "delta.xml").getroot()
    arms, platform = [], np.zeros(3)
    for body in root.findall("worldbody/body"):
        if body.find("freejoint") is not None:
            platform = numbers(body.get("pos"))
            continue
        rods = [
            Rod(
                str(rod.get("name")),
                numbers(rod.get("pos")),
                [numbers(j.get("axis")) for j in rod.findall("joint")],
            )
            for rod in body.findall("body")
        ]
        hinge = body.find("joint")
        axis = numbers(None if hinge is None else hinge.get("axis"))
        arms.append(Arm(str(body.get("name")), numbers(body.get("pos")), axis, rods))
    connects = [
        (str(c.get("body1")), numbers(c.get("anchor"))) for c in root.findall("equality/connect")
    ]
    return Delta(arms, platform, connects)


def delta_points() -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Each connect: (rod, anchor in the rod, the same point in the platform's frame)."""
    d = delta()
    where = {}
    for arm in d.arms:
        for rod in arm.rods:
            where[rod.name] = arm.position + rod.position
    return [(rod, anchor, where[rod] + anchor - d.platform) for rod, anchor in d.connects]


DELTA_DOC = (
    "delta.xml, written by make_fixtures.py: each rod's two hinges are two joints through\n"
    "a link of their own (<rod>_u), the platform floats, each connect is a ball"
)


def delta_sdf() -> str:
    d = delta()
    links, joints = "", ""
    for arm, arm_position, axis, rods in d.arms:
        links += (
            f'    <link name="{arm}_link">\n      <pose>{vec(arm_position)} 0 0 0</pose>\n'
            "    </link>\n"
        )
        joints += (
            f'    <joint name="{arm}" type="continuous">\n      <parent>world</parent>\n'
            f"      <child>{arm}_link</child>\n"
            f"      <axis><xyz>{vec(axis)}</xyz></axis>\n    </joint>\n"
        )
        for rod, rod_position, axes in rods:
            at = vec(arm_position + rod_position)
            for link in (f"{rod}_u", rod):
                links += f'    <link name="{link}">\n      <pose>{at} 0 0 0</pose>\n    </link>\n'
            for k, (parent, child) in enumerate(((f"{arm}_link", f"{rod}_u"), (f"{rod}_u", rod))):
                joints += (
                    f'    <joint name="{rod}_{k + 1}" type="continuous">\n'
                    f"      <parent>{parent}</parent>\n      <child>{child}</child>\n"
                    f"      <axis><xyz>{vec(axes[k])}</xyz></axis>\n    </joint>\n"
                )
    links += (
        f'    <link name="platform">\n      <pose>{vec(d.platform)} 0 0 0</pose>\n    </link>\n'
    )
    balls = "".join(
        "    <drake:ball_constraint>\n"
        f"      <drake:ball_constraint_body_A>{rod}</drake:ball_constraint_body_A>\n"
        "      <drake:ball_constraint_body_B>platform</drake:ball_constraint_body_B>\n"
        f"      <drake:ball_constraint_p_AP>{vec(p)}</drake:ball_constraint_p_AP>\n"
        f"      <drake:ball_constraint_p_BQ>{vec(q)}</drake:ball_constraint_p_BQ>\n"
        "    </drake:ball_constraint>\n"
        for rod, p, q in delta_points()
    )
    return (
        '<?xml version="1.0"?>\n'
        f"<!-- {DELTA_DOC.replace(chr(10), chr(10) + '     ')}:\n"
        "     Drake's ball constraint. The platform, a link no joint holds, floats; each\n"
        "     arm's link is <arm>_link (SDFormat names a model's links and joints apart). -->\n"
        '<sdf version="1.9" xmlns:drake="http://drake.mit.edu">\n  <model name="delta">\n'
        f"{links}{joints}{balls}  </model>\n</sdf>\n"
    )


def delta_urdf() -> str:
    d = delta()
    names = ["base"]
    joints = ""
    for arm, arm_position, axis, rods in d.arms:
        names.append(arm)
        joints += (
            f'  <joint name="{arm}" type="continuous">\n    <parent link="base"/>\n'
            f'    <child link="{arm}"/>\n    <origin xyz="{vec(arm_position)}"/>\n'
            f'    <axis xyz="{vec(axis)}"/>\n  </joint>\n'
        )
        for rod, rod_position, axes in rods:
            names += [f"{rod}_u", rod]
            for k, (parent, child) in enumerate(((arm, f"{rod}_u"), (f"{rod}_u", rod))):
                origin = f'    <origin xyz="{vec(rod_position)}"/>\n' if k == 0 else ""
                joints += (
                    f'  <joint name="{rod}_{k + 1}" type="continuous">\n'
                    f'    <parent link="{parent}"/>\n    <child link="{child}"/>\n{origin}'
                    f'    <axis xyz="{vec(axes[k])}"/>\n  </joint>\n'
                )
    names.append("platform")
    joints += (
        '  <joint name="platform" type="floating">\n    <parent link="base"/>\n'
        f'    <child link="platform"/>\n    <origin xyz="{vec(d.platform)}"/>\n  </joint>\n'
    )
    links = "".join(f'  <link name="{n}"/>\n' for n in names)
    balls = "".join(
        "  <drake:ball_constraint>\n"
        f'    <drake:ball_constraint_body_A name="{rod}"/>\n'
        '    <drake:ball_constraint_body_B name="platform"/>\n'
        f'    <drake:ball_constraint_p_AP value="{vec(p)}"/>\n'
        f'    <drake:ball_constraint_p_BQ value="{vec(q)}"/>\n'
        "  </drake:ball_constraint>\n"
        for rod, p, q in delta_points()
    )
    return (
        '<?xml version="1.0"?>\n'
        f"<!-- {DELTA_DOC.replace(chr(10), chr(10) + '     ')}:\n"
        "     Drake's ball constraint. The platform's joint is a floating one. -->\n"
        '<robot name="delta" xmlns:drake="http://drake.mit.edu">\n'
        f"{links}{joints}{balls}</robot>\n"
    )


def to_x(axis: np.ndarray) -> Rotation:
    """A rotation that takes x to the axis (a joint frame whose X is the axis)."""
    axis = axis / np.linalg.norm(axis)
    rotation, _ = Rotation.align_vectors([axis], [[1.0, 0.0, 0.0]])
    return rotation


def delta_usd() -> str:
    d = delta()
    root = "/delta"
    none = Rotation.identity()
    zero = np.zeros(3)
    bodies, joints = "", ""
    axis = '            uniform token physics:axis = "X"\n'
    for arm, arm_position, arm_axis, rods in d.arms:
        bodies += body_usd(arm, matrix(arm_position, none))
        turn = to_x(arm_axis)
        joints += joint_usd(
            "PhysicsRevoluteJoint",
            arm,
            (None, f"{root}/{arm}"),
            (arm_position, turn, zero, turn),
            axis,
        )
        for rod, rod_position, axes in rods:
            place = matrix(arm_position + rod_position, none)
            bodies += body_usd(f"{rod}_u", place) + body_usd(rod, place)
            turn = to_x(axes[0])
            joints += joint_usd(
                "PhysicsRevoluteJoint",
                f"{rod}_1",
                (f"{root}/{arm}", f"{root}/{rod}_u"),
                (rod_position, turn, zero, turn),
                axis,
            )
            turn = to_x(axes[1])
            joints += joint_usd(
                "PhysicsRevoluteJoint",
                f"{rod}_2",
                (f"{root}/{rod}_u", f"{root}/{rod}"),
                (zero, turn, zero, turn),
                axis,
            )
    platform = d.platform
    bodies += body_usd("platform", matrix(platform, none))
    joints += joint_usd(
        "PhysicsJoint", "platform", (None, f"{root}/platform"), (platform, none, zero, none)
    )
    excluded = "            bool physics:excludeFromArticulation = 1\n"
    for rod, p, q in delta_points():
        joints += joint_usd(
            "PhysicsSphericalJoint",
            f"{rod}_platform",
            (f"{root}/{rod}", f"{root}/platform"),
            (p, none, q, none),
            excluded,
        )
    text = usd_header(
        DELTA_DOC
        + ":\na spherical joint excluded from the articulation. The platform's joint is a\n"
        "generic one no limit holds (six free axes: floating). Each revolute joint's frames\n"
        "turn its X onto the MJCF hinge's axis.",
        "delta",
    )
    return text + bodies + '    def Scope "joints"\n    {\n' + joints.rstrip("\n") + "\n    }\n}\n"


def texts() -> dict[str, str]:
    """Each file this writes (its name in tests/closed) and its text."""
    out = {}
    starts = {
        "bennett": ([0.5, 1.0, -0.5, 1.0], True),
        "fourr_rigid": ([0.1, 3.0, 0.1, 3.0], False),
    }
    for name, (start, moves) in starts.items():
        path = HERE / f"{name}.xml"
        q = assembled(path, start, moves)
        out[f"{name}.sdf"] = hinges_sdf(name, path, q)
        out[f"{name}.usda"] = hinges_usd(name, path, q)
    out["delta.sdf"] = delta_sdf()
    out["delta_drake.urdf"] = delta_urdf()
    out["delta.usda"] = delta_usd()
    return out


if __name__ == "__main__":
    for file, text in texts().items():
        (HERE / file).write_text(text)
        sys.stdout.write(f"wrote {file}\n")
