"""Advice to add a root joint is given only where following it is right, and joints that
already give a body its pose (a planar or spatial root written as slides and hinges) are
named as such.

Every suggestion cspace makes on the robot files the sweeps read (pybullet's, Drake's and
robosuite's URDF files, the MJCF files of the six packages of tests/test_mjcf_sweep.py,
robots/) is followed: inspected again with the ``--root-joint`` it names, the robot must
gain one rigid-body pose (dimension +6 or +3, the factors of SE(3) or SE(2)) where no
joint moved it before; for an MJCF file, MuJoCo compiles the file with the same root
written into it (a body with a ``<freejoint/>``, or two slides and a hinge, around
everything in the world) and must count the same coordinates and factors.
"""

from __future__ import annotations

import importlib.util
import json
import math
import re
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import mujoco
import pytest
from lxml import etree
from test_mjcf_sweep import PACKAGES, _package_files
from test_urdf_sweep import DRAKE, PYBULLET, ROBOSUITE

import cspace
from cspace._findings import CODES
from cspace._manifold import NormalForm

from conftest import REPO, ROBOTS, run_cli

ADVICE = "root-joint-suggested"
ADDED = {"floating": Counter(R=3, RP3=1), "planar": Counter(R=2, T=1)}
"""The factors a followed suggestion adds: SE(3) = R^3 × RP^3, SE(2) = R^2 × S^1."""
DIMENSION = {"floating": 6, "planar": 3}
NQ = {"floating": 7, "planar": 4}
"""Pinocchio's coordinates of the root joint added (a planar joint keeps cos and sin)."""


def _package(name: str) -> Path:
    spec = importlib.util.find_spec(name)  # found, not imported
    assert spec is not None and spec.submodule_search_locations
    return Path(next(iter(spec.submodule_search_locations)))


PLANAR_ROOTS = [
    _package("dm_control") / "suite" / "cheetah.xml",
    _package("dm_control") / "suite" / "walker.xml",
    _package("dm_control") / "suite" / "hopper.xml",
    _package("gymnasium") / "envs" / "mujoco" / "assets" / "half_cheetah.xml",
    _package("gymnasium") / "envs" / "mujoco" / "assets" / "walker2d.xml",
    _package("gymnasium") / "envs" / "mujoco" / "assets" / "hopper.xml",
]
"""Robots whose torso two slides and a hinge (rootx, rootz, rooty) move in a plane."""

BIPED_ON_THE_WORLD = """<mujoco model="biped_on_the_world">
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    {legs}
  </worldbody>
</mujoco>"""
"""Two legs, each a body of the world with a hip and a knee: a robot that walks, bolted."""
LEG = """<body name="{side}_thigh" pos="0 {y} 1">
      <joint name="{side}_hip" type="hinge" axis="0 1 0" range="-1 1"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.05"/>
      <body name="{side}_shin" pos="0 0 -0.4">
        <joint name="{side}_knee" type="hinge" axis="0 1 0" range="-2 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04"/>
      </body>
    </body>"""


def _biped(folder: Path) -> Path:
    path = folder / "biped_on_the_world.xml"
    legs = "\n    ".join(LEG.format(side=s, y=y) for s, y in (("left", 0.1), ("right", -0.1)))
    path.write_text(BIPED_ON_THE_WORLD.format(legs=legs))
    return path


def _corpus() -> list[Path]:
    """Every robot file the sweeps and tests/test_robots.py read."""
    mjcf = [path for package in PACKAGES for path in _package_files(package)]
    own = sorted(p for p in ROBOTS.iterdir() if p.suffix in (".urdf", ".xml", ".sdf"))
    return [*PYBULLET, *DRAKE, *ROBOSUITE, *mjcf, *own]


def _inspect(path: Path) -> cspace.Report | None:
    try:
        return cspace.inspect(path)
    except cspace.RobotFileError:  # the sweeps hold these refusals to Pinocchio's, MuJoCo's
        return None


def _suggested(report: cspace.Report) -> str | None:
    """The ``--root-joint`` the report suggests, or None."""
    said = [d.message for d in report.diagnostics if d.code == ADVICE]
    if not said:
        return None
    (message,) = said
    found = re.search(r"--root-joint (floating|planar)\b", message)
    assert found is not None, message
    return found.group(1)


def _moving(report: cspace.Report) -> list[cspace.JointReport]:
    fixed = (cspace.JointKind.FIXED, cspace.JointKind.MIMIC)
    return [j for j in report.joints if j.kind not in fixed and j.parent_link is not None]


def _joint_moving_the_rest(report: cspace.Report) -> str | None:
    """A joint every other moving joint is above, beside (MJCF: of its body) or below.

    Such a joint already moves the robot as a whole, so a root joint added above the root
    link would move it in the same directions a second time (a slide on a slide)."""
    parent = {j.child_link: j.parent_link for j in report.joints if j.parent_link is not None}
    children: dict[str, list[str]] = {}
    for child, up in parent.items():
        if up is not None:
            children.setdefault(up, []).append(child)
    moving = _moving(report)
    for joint in moving:
        below, frontier = {joint.child_link}, [joint.child_link]
        while frontier:
            for child in children.get(frontier.pop(), []):
                below.add(child)
                frontier.append(child)
        above: set[str] = set()
        link: str | None = joint.parent_link
        while link is not None and link not in above:
            above.add(link)
            link = parent.get(link)
        if all(k.child_link in below or k.child_link in above for k in moving):
            return joint.name
    return None


def _mujoco_counts(model: mujoco.MjModel) -> Counter[str]:
    """The factors of MuJoCo's joints, by the rules of docs/cspace-math.md."""
    counts: Counter[str] = Counter()
    for k in range(model.njnt):
        kind, limited = mujoco.mjtJoint(model.jnt_type[k]), bool(model.jnt_limited[k])
        if kind == mujoco.mjtJoint.mjJNT_FREE:
            counts.update(R=3, RP3=1)
        elif kind == mujoco.mjtJoint.mjJNT_BALL and limited and model.jnt_range[k][1] < math.pi:
            counts.update(R=3)  # a limited ball: a 3-ball
        elif kind == mujoco.mjtJoint.mjJNT_BALL:
            counts.update(RP3=1)
        elif kind == mujoco.mjtJoint.mjJNT_HINGE and not limited:
            counts.update(T=1)
        else:
            counts.update(R=1)
    return counts


def _mujoco_followed(path: Path, root: str) -> mujoco.MjModel:
    """MuJoCo's model of ``path`` with the root written in: a body around everything in the
    world (mocap bodies stay, MuJoCo keeps them there) with a free joint, or with two
    slides and a hinge about the vertical."""
    spec = mujoco.MjSpec.from_file(str(path))
    spec.compile()
    document = etree.fromstring(spec.to_xml().encode())  # includes read in
    world = document.find("worldbody")
    assert world is not None
    around = etree.Element("body", name="followed_root")
    etree.SubElement(around, "inertial", pos="0 0 0", mass="1", diaginertia="1 1 1")
    if root == "floating":
        etree.SubElement(around, "freejoint", name="followed_free")
    else:
        for name, kind, axis in (("x", "slide", "1 0 0"), ("y", "slide", "0 1 0")):
            etree.SubElement(around, "joint", name=f"followed_{name}", type=kind, axis=axis)
        etree.SubElement(around, "joint", name="followed_yaw", type="hinge", axis="0 0 1")
    for child in list(world):
        if child.tag in ("body", "frame") and child.get("mocap") != "true":
            around.append(child)
    world.append(around)
    followed = mujoco.MjSpec.from_string(etree.tostring(document).decode())
    followed.modelfiledir = str(path.parent)  # meshes and textures where the file has them
    return followed.compile()


def _follow(path: Path, before: cspace.Report, root: str) -> list[str]:
    """What is wrong with following the suggestion ``--root-joint ROOT`` (nothing: [])."""
    wrong = []
    stacked = _joint_moving_the_rest(before)
    if stacked is not None:
        wrong.append(f"joint '{stacked}' already moves the robot as a whole")
    after = cspace.inspect(path, root_joint=root)
    if after.dimension - before.dimension != DIMENSION[root]:
        wrong.append(f"dimension {before.dimension} -> {after.dimension}")
    gained = Counter(after.manifold.counts()) - Counter(before.manifold.counts())
    if gained != ADDED[root] or after.nq - before.nq != NQ[root]:
        wrong.append(f"{before.manifold.notation} -> {after.manifold.notation}, nq {after.nq}")
    if any(d.code == ADVICE for d in after.diagnostics):
        wrong.append("suggested again once followed")
    if before.source.format == "mjcf":
        original = mujoco.MjModel.from_xml_path(str(path))
        model = _mujoco_followed(path, root)
        if model.nq - original.nq != {"floating": 7, "planar": 3}[root]:
            wrong.append(f"MuJoCo's nq {original.nq} -> {model.nq}")
        if _mujoco_counts(model) - _mujoco_counts(original) != ADDED[root]:
            wrong.append(f"MuJoCo's factors {_mujoco_counts(model)}")
        theirs = _mujoco_counts(model)
        if not model.neq and NormalForm(theirs["R"], theirs["T"], theirs["RP3"]) != after.manifold:
            wrong.append(f"MuJoCo's {theirs} is not {after.manifold.notation}")
    return wrong


def test_every_suggestion_on_the_corpus_is_right_once_followed(tmp_path: Path) -> None:
    files = [*_corpus(), _biped(tmp_path)]
    assert len(files) >= 1_300
    with ThreadPoolExecutor(2) as pool:  # MJCF compiles in a child: two at a time
        reports = dict(zip(files, pool.map(_inspect, files), strict=True))
    read = {path: report for path, report in reports.items() if report is not None}
    suggested = {path: root for path, report in read.items() if (root := _suggested(report))}
    # the advice is still given where it is meant: legs and wheels on a root bolted down
    assert suggested[ROBOTS / "quadruped_nobase.urdf"] == "floating"
    assert suggested[ROBOTS / "diffdrive_nobase.urdf"] == "planar"
    assert suggested[Path(PYBULLET[0]).parent / "racecar" / "racecar.urdf"] == "planar"
    assert suggested[tmp_path / "biped_on_the_world.xml"] == "floating"  # MuJoCo's side
    assert not set(PLANAR_ROOTS) & set(suggested)
    wrong = {
        str(path): problems
        for path, root in suggested.items()
        if (problems := _follow(path, read[path], root))
    }
    assert wrong == {}


def _names(message: str) -> list[str]:
    found = re.match(r"joints (.*?) together are a planar root of link '\w+' \(SE\(2\)\)", message)
    assert found is not None, message
    return sorted(found.group(1).split(", "))


def test_the_planar_roots_of_dm_control_and_gymnasium_are_named_in_every_ci_format() -> None:
    files = [str(p) for p in PLANAR_ROOTS]
    lines = run_cli("inspect", *files, "--format", "json")
    github = run_cli("inspect", *files, "--format", "github")
    sarif = run_cli("inspect", *files, "--format", "sarif")
    for run in (lines, github, sarif):
        assert run.code == 0, run.stderr
        assert ADVICE not in run.stdout and "--root-joint" not in run.stdout
    reports = [json.loads(line) for line in lines.stdout.splitlines()]
    assert [r["source"]["path"] for r in reports] == files
    for report in reports:
        assert report["manifold"]["factors"]["T"] == 1 and report["root_joint"] is None
        named = [d for d in report["diagnostics"] if d["code"] == "planar-root"]
        assert len(named) == 1 and named[0]["severity"] == "info", report["source"]
        assert _names(named[0]["message"]) == ["rootx", "rooty", "rootz"]
        assert named[0]["message"].endswith("no root joint is needed")
    notices = re.findall(
        r"^::notice file=([^,]*),line=\d+,title=cspace planar-root::(.*)$", github.stdout, re.M
    )
    assert [(f, _names(m)) for f, m in notices] == [(f, ["rootx", "rooty", "rootz"]) for f in files]
    results = json.loads(sarif.stdout)["runs"][0]["results"]
    named = [r for r in results if r["ruleId"] == "planar-root"]
    uris = [r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in named]
    assert [_names(r["message"]["text"]) for r in named] == [["rootx", "rooty", "rootz"]] * 6
    assert uris == [p.as_uri() for p in PLANAR_ROOTS]


def test_a_root_joint_given_is_never_suggested_again_and_a_planar_root_says_it_stacks() -> None:
    report = cspace.inspect(PLANAR_ROOTS[0], root_joint="floating")
    assert report.root_joint == "floating" and report.dimension == 15
    codes = [d.code for d in report.diagnostics]
    assert ADVICE not in codes and codes.count("planar-root") == 1
    (named,) = [d.message for d in report.diagnostics if d.code == "planar-root"]
    assert named.endswith(
        "the floating root joint added above link 'world' moves it a second time, on top of these"
    )
    legged = cspace.inspect(ROBOTS / "quadruped_nobase.urdf", root_joint="planar")
    assert ADVICE not in [d.code for d in legged.diagnostics]


def test_an_srdf_virtual_joint_gives_the_root_its_joint_even_a_fixed_one(tmp_path: Path) -> None:
    urdf = tmp_path / "quadruped_nobase.urdf"
    urdf.write_bytes((ROBOTS / "quadruped_nobase.urdf").read_bytes())
    assert _suggested(cspace.inspect(urdf)) == "floating"
    for kind in ("fixed", "floating"):
        srdf = tmp_path / f"{kind}.srdf"
        srdf.write_text(
            f'<robot name="quadruped_nobase"><virtual_joint name="v" type="{kind}" '
            'parent_frame="world" child_link="trunk"/></robot>'
        )
        report = cspace.inspect(urdf, srdf=srdf)
        assert report.root_joint == (None if kind == "fixed" else "floating")
        assert ADVICE not in [d.code for d in report.diagnostics], kind


# --- recognised roots, and what is not one -------------------------------------------

LEGS = "".join(
    f'<link name="{leg}"/><joint name="{leg}_hip" type="continuous"><parent link="trunk"/>'
    f'<child link="{leg}"/><origin xyz="{x} {y} 0"/><axis xyz="0 1 0"/></joint>'
    for leg, x, y in (("lf", 0.2, 0.1), ("rf", 0.2, -0.1), ("lh", -0.2, 0.1), ("rh", -0.2, -0.1))
)


def _chain_urdf(folder: Path, name: str, chain: list[tuple[str, ...]]) -> Path:
    """A quadruped whose trunk hangs from ``world`` by a chain of links that carry nothing
    else: one joint ``(name, type, axis, rpy)`` a link, and what else its element holds
    (a fifth entry: by default a slide's limits, -5 to 5)."""
    links = ["world", *(f"{n}_link" for n, *_ in chain[:-1]), "trunk"]
    joints = "".join(
        f'<link name="{links[k + 1]}"/>'
        * (k < len(chain) - 1)
        + f'<joint name="{n}" type="{t}"><parent link="{links[k]}"/><child link="{links[k + 1]}"/>'
        f'<origin rpy="{rpy}"/><axis xyz="{axis}"/>'
        + (extra[0] if extra else (_LIMIT.format(-5, 5) if t == "prismatic" else ""))
        + "</joint>"
        for k, (n, t, axis, rpy, *extra) in enumerate(chain)
    )
    path = folder / f"{name}.urdf"
    path.write_text(
        f'<robot name="{name}"><link name="world"/><link name="trunk"/>{joints}{LEGS}</robot>'
    )
    return path


_LIMIT = '<limit lower="{}" upper="{}" effort="1" velocity="1"/>'
_MIMIC_X = '<mimic joint="x"/>'
QUARTER = f"0 0 {math.pi / 2!r}"
"""A frame turned a quarter about z: its x axis is the world's y."""
SLIDE_X = ("x", "prismatic", "1 0 0", "0 0 0")
SLIDE_Y = ("y", "prismatic", "1 0 0", QUARTER)  # along x of a turned frame: the world's y
YAW = ("yaw", "continuous", "0 0 1", "0 0 0")

URDF_CASES = {
    "planar_turned_frames": ([SLIDE_X, SLIDE_Y, YAW], "planar-root"),
    "planar_yaw_first": ([YAW, SLIDE_X, SLIDE_Y], "planar-root"),
    # the hinge between the slides turns the second onto the first: not all of SE(2)
    "slide_hinge_slide": ([SLIDE_X, YAW, SLIDE_Y], None),
    # z of a frame turned about x is the world's -y: a hinge in the plane, not its normal
    "hinge_in_the_plane": (
        [SLIDE_X, SLIDE_Y, ("yaw", "continuous", "0 0 1", "1.5707963267948966 0 0")],
        None,
    ),
    "euler_xyz": (
        [
            SLIDE_X,
            SLIDE_Y,
            ("z", "prismatic", "0 0 1", "0 0 0"),
            ("roll", "continuous", "1 0 0", "0 0 0"),
            ("pitch", "continuous", "0 1 0", "0 0 0"),
            ("yaw", "continuous", "0 0 1", "0 0 0"),
        ],
        "spatial-root",
    ),
    # the middle hinge is not perpendicular to the first: a cone of orientations, not SO(3)
    "not_euler": (
        [
            SLIDE_X,
            SLIDE_Y,
            ("z", "prismatic", "0 0 1", "0 0 0"),
            ("roll", "continuous", "1 0 0", "0 0 0"),
            ("tilted", "continuous", "1 1 0", "0 0 0"),
            ("yaw", "continuous", "0 0 1", "0 0 0"),
        ],
        None,
    ),
    # the review's file: a slide locked (0 to 0, read as locked) leaves a line and a heading
    "locked_slide": ([(*SLIDE_X, _LIMIT.format(0, 0)), SLIDE_Y, YAW], None),
    # a locked joint moves nothing: passed over, as a fixed one, the others are a root
    "locked_slide_passed_over": (
        [SLIDE_X, ("lock", "prismatic", "0 0 1", "0 0 0", _LIMIT.format(0.3, 0.3)), SLIDE_Y, YAW],
        "planar-root",
    ),
    # a hinge locked at a quarter turn holds the second slide along the first (at 0 it
    # would not): the joints are placed where the lock holds them
    "locked_quarter_turn": (
        [
            SLIDE_X,
            ("lock", "revolute", "0 0 1", "0 0 0", _LIMIT.format(math.pi / 2, math.pi / 2)),
            ("y", "prismatic", "0 1 0", "0 0 0"),
            YAW,
        ],
        None,
    ),
    "locked_at_zero": (
        [
            SLIDE_X,
            ("lock", "revolute", "0 0 1", "0 0 0", _LIMIT.format(0, 0)),
            ("y", "prismatic", "0 1 0", "0 0 0"),
            YAW,
        ],
        "planar-root",
    ),
    # URDF ignores a continuous joint's limits, lower == upper too: the report keeps none,
    # so the joint turns (S^1) and is no lock
    "continuous_limits_ignored": (
        [SLIDE_X, SLIDE_Y, ("yaw", "continuous", "0 0 1", "0 0 0", _LIMIT.format(0, 0))],
        "planar-root",
    ),
    # a hinge turning with x turns y's slide: where y = cos(x) the trunk loses a direction
    "mimic_between_the_slides": (
        [
            SLIDE_X,
            ("m", "revolute", "0 0 1", "0 0 0", _LIMIT.format(-9, 9) + _MIMIC_X),
            ("y", "prismatic", "0 1 0", "0 0 0"),
            YAW,
        ],
        None,
    ),
}


@pytest.mark.parametrize("name", sorted(URDF_CASES))
def test_a_urdf_chain_from_the_world_is_a_root_only_when_it_gives_the_trunk_every_pose(
    name: str, tmp_path: Path
) -> None:
    chain, code = URDF_CASES[name]
    report = cspace.inspect(_chain_urdf(tmp_path, name, chain))
    codes = [d.code for d in report.diagnostics]
    assert ADVICE not in codes  # joints move the trunk: a root joint would move it again
    assert [c for c in codes if c.endswith("-root")] == ([code] if code else [])
    if code:
        (said,) = [d.message for d in report.diagnostics if d.code == code]
        names = ", ".join(n for n, *_ in chain if n != "lock")
        assert said.startswith(f"joints {names} together are a {code[:-5]} root of link 'trunk'")
        slides = ", ".join(n for n, kind, *_ in chain if kind == "prismatic" and n != "lock")
        assert f", but only within the limits of {slides} (the C-space is" in said
    bolted = cspace.inspect(_chain_urdf(tmp_path, "bolted", [("bolt", "fixed", "1 0 0", "0 0 0")]))
    assert _suggested(bolted) is None  # legs below a fixed joint from the world, as written


def test_a_mimic_joint_before_a_root_does_not_hide_it(tmp_path: Path) -> None:
    """Pinocchio's Jacobian has a column for each mimic joint: a root after one, in
    Pinocchio's order, is placed by its own columns."""
    path = _chain_urdf(tmp_path, "fingers", [SLIDE_X, SLIDE_Y, YAW])
    finger = _LIMIT.format(-1, 1)
    path.write_text(
        path.read_text().replace(
            '<link name="world"/>',
            '<link name="world"/><link name="f1"/><link name="f2"/>'
            '<joint name="finger" type="revolute"><parent link="world"/><child link="f1"/>'
            f'<axis xyz="0 0 1"/>{finger}</joint>'
            '<joint name="follower" type="revolute"><parent link="f1"/><child link="f2"/>'
            f'<axis xyz="1 0 0"/>{finger}<mimic joint="finger"/></joint>',
        )
    )
    model = cspace.pinocchio_model(path)
    assert list(model.names)[1:4] == ["finger", "follower", "x"]  # the mimic comes first
    report = cspace.inspect(path)
    (said,) = [d.message for d in report.diagnostics if d.code == "planar-root"]
    assert said.startswith("joints x, y, yaw together are a planar root of link 'trunk'")


MJCF_BODY = """<mujoco model="{name}"><worldbody><body name="body" pos="0 0 1">{joints}
  <geom size="0.1"/>
  <body name="left" pos="0 0.1 0"><joint name="left_hip" axis="0 1 0"/><geom size="0.05"/></body>
  <body name="right" pos="0 -0.1 0"><joint name="right_hip" axis="0 1 0"/><geom size="0.05"/></body>
</body></worldbody></mujoco>"""


@pytest.mark.parametrize(
    ("joints", "code"),
    [
        ("sx:slide:1,0,0 sy:slide:0,1,0 sz:slide:0,0,1 turn:ball", "spatial-root"),
        ("turn:ball sx:slide:1,0,0 sy:slide:0,1,0 sz:slide:0,0,1", "spatial-root"),
        ("sx:slide:1,0,0 sy:slide:0,1,0 sz:slide:1,1,0 turn:ball", None),  # slides in a plane
        ("sx:slide:1,0,0 turn:hinge:0,1,0 sz:slide:0,0,1", None),  # the hinge between
        ("sx:slide:1,0,0 sz:slide:0,0,1 turn:hinge:0,1,0", "planar-root"),
    ],
)
def test_the_joints_of_one_mjcf_body_are_a_root_in_the_orders_that_give_every_pose(
    joints: str, code: str | None, tmp_path: Path
) -> None:
    written = "".join(
        f'<joint name="{n}" type="{t}"'
        + "".join(f' axis="{a.replace(",", " ")}"' for a in rest)
        + "/>"
        for n, t, *rest in (j.split(":") for j in joints.split())
    )
    path = tmp_path / "body.xml"
    path.write_text(MJCF_BODY.format(name="body", joints=written))
    report = cspace.inspect(path)
    assert report.dimension == mujoco.MjModel.from_xml_path(str(path)).nv
    codes = [d.code for d in report.diagnostics]
    assert ADVICE not in codes
    assert [c for c in codes if c.endswith("-root")] == ([code] if code else [])


def test_every_finding_code_is_documented_in_the_findings_table() -> None:
    text = (REPO / "docs" / "safety.md").read_text()
    table = text[text.index("## Findings") : text.index("## Safety")]
    rows = re.findall(r"^\| ([^|]*) \|", table, re.M)
    documented = {code for row in rows for code in re.findall(r"`([a-z0-9-]+)`", row)}
    assert set(CODES) - documented == set()
