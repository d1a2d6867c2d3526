"""Closed chains in SDF and Drake's ball constraint (URDF, SDF): the cuts and their numbers.

SDF writes a loop as a joint whose child already has a parent: cspace keeps the first
parent joint of each link (file order) and cuts the loop at the others. Drake's
``<drake:ball_constraint>`` holds a point of one body on a point of another. Oracles: the
MJCF four-bar's mobility for the same geometry; the file's own poses, which draw
Cassie's legs closed (the residual at the tree's zero configuration is nothing); Drake's
plant of the same URDF and SDF file, whose kinematics put the constraint's two points
where cspace's residual says, and together at the configurations cspace projects onto
the mechanism. Hostile inputs get one-line errors or a ``closure-invalid`` finding.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from lxml import etree
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import DiscreteContactApproximation, MultibodyPlant

import cspace
from cspace._formats.sdf.reader import read_sdf
from cspace._formats.shared.erd import robots_dir
from cspace._formats.urdf.reader import read_urdf
from cspace._model.closure import LoopConstraints

from conftest import REPO, assert_bounded_error, measured, run_cli

CLOSED = REPO / "tests" / "closed"
CASSIE = robots_dir() / "cassie_description" / "robots"
FOURBAR_SDF = CLOSED / "fourbar.sdf"
FOURBAR_URDF = CLOSED / "fourbar_drake.urdf"


def closure_of(path: Path) -> dict[str, object]:
    """The JSON report's ``closure`` of a file, as the CLI writes it."""
    run = run_cli("inspect", "--format", "json", str(path))
    assert run.code in (0, 1), run.stderr
    closure: dict[str, object] = json.loads(run.stdout)["closure"]
    return closure


def constraints_of(path: Path) -> LoopConstraints:
    """The loop constraints of an SDF or URDF file: its reader's cuts on cspace's model."""
    text = path.read_text()
    root = etree.fromstring(text.encode())
    reading = (
        read_sdf(str(path), root) if path.suffix == ".sdf" else read_urdf(str(path), root, text)
    )
    description = reading.description
    return LoopConstraints(cspace.pinocchio_model(path), description.cuts, description.root_link)


def _numbers(closure: dict[str, object]) -> tuple[object, ...]:
    keys = ("loops", "constraint_rows", "grubler", "mobility", "rank", "assembled")
    return tuple(closure[key] for key in keys)


def test_the_sdf_fourbar_moves_as_the_mjcf_one() -> None:
    closure = closure_of(FOURBAR_SDF)
    # 3 hinges in the tree; the revolute loop joint makes 5 equations (Grübler 3 - 5 = -2),
    # of rank 2 in the plane: the out-of-plane translation and the two tilts never move
    assert _numbers(closure) == (1, 5, -2, 1, {"lowest": 2, "highest": 2}, True)
    (cut,) = closure["cuts"]  # type: ignore[misc]
    geometry = {key: cut.pop(key) for key in ("free", "frame_a", "frame_b", "axis")}
    assert cut == {
        "kind": "revolute",
        "name": "ground_pivot",
        "links": ["world", "rocker_link"],
        "rows": 5,
        "file": str(FOURBAR_SDF),
        "line": 32,
    }
    # the pivot at (2, 0, 0) in the world, at the rocker's tip in the rocker, about y
    assert geometry["free"] == "revolute" and geometry["axis"] == [0.0, 1.0, 0.0]
    assert np.allclose(geometry["frame_a"]["position"], [2, 0, 0], atol=1e-12)
    assert np.allclose(geometry["frame_b"]["position"], [0.25548, 0, -1.47808], atol=1e-12)
    assert closure_of(CLOSED / "fourbar.xml")["mobility"] == closure["mobility"] == 1
    assert cspace.inspect(FOURBAR_SDF).dimension == 3  # the cut adds no coordinates


def _fourbar(tmp_path: Path, pivot: str, axis: str = "<xyz>0 1 0</xyz>") -> Path:
    text = FOURBAR_SDF.read_text()
    start = text.index('      <pose relative_to="__model__">')
    end = text.index("      <parent>world", start)
    text = text[:start] + f"      {pivot}\n" + text[end:]
    text = text.replace('<xyz expressed_in="__model__">0 1 0</xyz>', axis)
    path = tmp_path / "fourbar.sdf"
    path.write_text(text)
    return path


def test_a_loop_joint_is_placed_by_its_pose_in_its_child_or_where_relative_to_says(
    tmp_path: Path,
) -> None:
    (written,) = constraints_of(FOURBAR_SDF).cuts
    # the same pivot written in the rocker's frame (a joint's default), axis in its own
    (child,) = constraints_of(_fourbar(tmp_path, "<pose>0.25548 0 -1.47808 0 0 0</pose>")).cuts
    for a, b in ((written.frame_a, child.frame_a), (written.frame_b, child.frame_b)):
        assert np.allclose(a.position, b.position, atol=1e-12)
        assert np.allclose(a.rotation_wxyz, b.rotation_wxyz, atol=1e-12)
    assert written.frame_a.position == (2.0, 0.0, 0.0) and written.axis == child.axis == (0, 1, 0)
    # the joint frame turned a quarter about x: its z axis is the hinges' (the world's -y),
    # its y axis the world's z, about which the rocker never turns in the plane
    turned = '<pose relative_to="__model__">2 0 0 1.5707963267948966 0 0</pose>'
    along = closure_of(_fourbar(tmp_path, turned, "<xyz>0 0 1</xyz>"))
    across = closure_of(_fourbar(tmp_path, turned, "<xyz>0 1 0</xyz>"))
    assert (along["mobility"], across["mobility"]) == (1, 0)


@pytest.mark.parametrize(
    "name",
    ["cassie_reduced.sdf", "cassie_simple.sdf", "cassie_v2.sdf", "cassie_wo_gearbox_spring.sdf"],
)
def test_cassie_legs_are_cut_where_a_link_has_a_second_parent_and_drawn_closed(name: str) -> None:
    constraints = constraints_of(CASSIE / name)
    kinds = sorted(c.kind for c in constraints.cuts)
    assert len(kinds) == 4 and set(kinds) <= {"ball", "revolute"}
    assert {c.name.split("-", 1)[0] for c in constraints.cuts} == {"left", "right"}
    # the file draws the legs assembled: at the tree's zero configuration the cuts' two
    # frames, each placed by the joint's pose from its own link, coincide
    residual = constraints.residual(pin.neutral(constraints.model))
    assert np.max(np.abs(residual)) < 1e-12


def test_cassie_mobility_by_rank() -> None:
    closure = closure_of(CASSIE / "cassie_wo_gearbox_spring.sdf")
    kinds = [(c["kind"], c["name"]) for c in closure["cuts"]]  # type: ignore[union-attr]
    assert kinds == [
        ("revolute", "right-achilles-spring-joint"),
        ("ball", "right-plantar-foot-joint"),
        ("revolute", "left-achilles-spring-joint"),
        ("ball", "left-plantar-foot-joint"),
    ]
    # tree 27; 2 x (5 + 3) rows; each foot four-bar (three parallel hinges closed by a
    # ball) is planar, so one of its 3 rows is always 0: rank 14, mobility 27 - 14 = 13
    assert _numbers(closure) == (4, 16, 11, 13, {"lowest": 14, "highest": 14}, True)


def test_cassie_gearboxes_are_refused_in_one_line() -> None:
    run = run_cli("inspect", str(CASSIE / "cassie.sdf"))
    assert run.code == 2 and "is a gearbox, which cspace does not model" in run.stderr


def _sdf(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "loop.sdf"
    path.write_text(f'<sdf version="1.9">\n<model name="m">\n{body}\n</model>\n</sdf>\n')
    return path


LINKS = '<link name="a"/><link name="b"/><link name="c"/>'
TREE = (
    '<joint name="j1" type="revolute"><parent>world</parent><child>a</child></joint>\n'
    '<joint name="j2" type="revolute"><parent>a</parent><child>b</child></joint>\n'
    '<joint name="j3" type="revolute"><parent>b</parent><child>c</child></joint>\n'
)


@pytest.mark.parametrize(
    ("kind", "rows"), [("ball", 3), ("fixed", 6), ("prismatic", 5), ("continuous", 5)]
)
def test_each_loop_joint_type_is_a_cut(tmp_path: Path, kind: str, rows: int) -> None:
    closing = f'<joint name="k" type="{kind}"><parent>a</parent><child>c</child></joint>'
    closure = closure_of(_sdf(tmp_path, LINKS + TREE + closing))
    (cut,) = closure["cuts"]  # type: ignore[misc]
    assert (cut["kind"], cut["name"], cut["links"], cut["rows"]) == (kind, "k", ["a", "c"], rows)
    assert closure["constraint_rows"] == rows


def test_a_joint_that_closes_a_cycle_of_single_parents_is_the_cut(tmp_path: Path) -> None:
    # in file order, 'k' gives 'a' its first parent, 'c', which already hangs below 'a':
    # it closes the cycle a -> b -> c -> a, and the joint from the world comes after it
    body = LINKS + (
        '<joint name="j2" type="revolute"><parent>a</parent><child>b</child></joint>\n'
        '<joint name="j3" type="revolute"><parent>b</parent><child>c</child></joint>\n'
        '<joint name="k" type="ball"><parent>c</parent><child>a</child></joint>\n'
        '<joint name="j1" type="revolute"><parent>world</parent><child>a</child></joint>\n'
    )
    run = run_cli("inspect", "--format", "json", str(_sdf(tmp_path, body)))
    document = json.loads(run.stdout)
    assert [j["name"] for j in document["joints"]] == ["j1", "j2", "j3"]
    (cut,) = document["closure"]["cuts"]
    assert (cut["name"], cut["links"], cut["line"]) == ("k", ["c", "a"], 5)


def test_a_joint_whose_child_is_the_world_is_no_cut(tmp_path: Path) -> None:
    # SDFormat refuses 'world' as a child (Drake too): the structure check says so
    closing = '<joint name="k" type="ball"><parent>c</parent><child>world</child></joint>'
    run = run_cli("inspect", str(_sdf(tmp_path, LINKS + TREE + closing)))
    assert run.code == 2 and run.stderr.rstrip().endswith("[cycle]"), run.stderr
    assert ":6: the joints form a cycle through links world -> a -> b -> c -> world" in run.stderr


def test_a_universal_loop_joint_is_refused_in_one_line(tmp_path: Path) -> None:
    closing = '<joint name="k" type="universal"><parent>a</parent><child>c</child></joint>'
    path = _sdf(tmp_path, LINKS + TREE + closing)
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1
    assert run.stderr.startswith(f"cspace: error: {path}:6: joint 'k' closes a kinematic loop")
    assert "link 'c' already hangs from joint 'j3' (line 5)" in run.stderr
    assert "is a universal joint" in run.stderr and "[unsupported-loop-joint]" in run.stderr


# Drake's ball constraint: URDF and SDF, against Drake's own plant.


def drake_plant(path: Path, weld: str | None) -> MultibodyPlant:
    """Drake's plant of the file (SAP: Drake's ball constraints need it), ``weld`` welded."""
    plant = MultibodyPlant(0.001)
    plant.set_discrete_contact_approximation(DiscreteContactApproximation.kSap)
    Parser(plant).AddModels(str(path))
    if weld is not None:
        plant.WeldFrames(plant.world_frame(), plant.GetFrameByName(weld))
    plant.Finalize()
    return plant


def written_points(path: Path) -> tuple[str, np.ndarray, str, np.ndarray]:
    """The one ball constraint's bodies and points as the file writes them (URDF)."""
    root = etree.parse(str(path)).getroot()
    (ball,) = [e for e in root if isinstance(e.tag, str) and e.tag.endswith("ball_constraint")]
    part = {etree.QName(e).localname.rsplit("_", 1)[-1]: e for e in ball}
    return (
        part["A"].get("name"),
        np.array(part["AP"].get("value").split(), dtype=float),
        part["B"].get("name"),
        np.array(part["BQ"].get("value").split(), dtype=float),
    )


def test_the_urdf_fourbar_ball_constraint_is_drakes(tmp_path: Path) -> None:
    closure = closure_of(FOURBAR_URDF)
    assert _numbers(closure) == (1, 3, 0, 1, {"lowest": 2, "highest": 2}, True)
    assert closure["cuts"][0]["kind"] == "drake:ball_constraint"  # type: ignore[index]
    plant = drake_plant(FOURBAR_URDF, "ground")  # a URDF's root link floats in Drake
    assert plant.num_constraints() == 1 and plant.num_positions() == 3
    context = plant.CreateDefaultContext()
    body_a, p_ap, body_b, p_bq = written_points(FOURBAR_URDF)
    frame_a, frame_b = plant.GetBodyByName(body_a), plant.GetBodyByName(body_b)
    constraints = constraints_of(FOURBAR_URDF)
    space = cspace.ConfigurationSpace.from_report(cspace.inspect(FOURBAR_URDF))
    conventions = space.conventions()
    generator = np.random.default_rng(7)
    closed = 0
    for x in space.sample(6, generator):
        q = conventions.to_pinocchio(x)
        plant.SetPositions(context, conventions.to_drake(x))
        gap = plant.EvalBodyPoseInWorld(context, frame_b).multiply(
            p_bq
        ) - plant.EvalBodyPoseInWorld(context, frame_a).multiply(p_ap)
        # the residual is Q - P in body A's frame: as long as Drake's gap
        assert math.isclose(
            np.linalg.norm(constraints.residual(q)), np.linalg.norm(gap), abs_tol=1e-12
        )
        assert np.linalg.norm(gap) > 1e-3  # a random configuration is off the mechanism
        projected, worst, _ = constraints.project(q)
        if worst > 1e-9:
            continue
        closed += 1
        drake_q = conventions.to_drake(conventions.from_pinocchio(projected))
        plant.SetPositions(context, drake_q)
        p = plant.EvalBodyPoseInWorld(context, frame_a).multiply(p_ap)
        q_point = plant.EvalBodyPoseInWorld(context, frame_b).multiply(p_bq)
        assert np.linalg.norm(p - q_point) < 1e-8
    assert closed >= 4


FOURBAR_BALL_SDF = """<sdf version="1.9" xmlns:drake="http://drake.mit.edu">
<model name="fourbar">
  <link name="ground"/><link name="crank_link"/>
  <link name="coupler_link"><pose>0 0 0.5 0 0 0</pose></link>
  <link name="rocker_link"><pose>1.74452 0 1.47808 0 0 0</pose></link>
  <joint name="bolt" type="fixed"><parent>world</parent><child>ground</child></joint>
  <joint name="crank" type="continuous"><parent>ground</parent><child>crank_link</child>
    <axis><xyz>0 1 0</xyz></axis></joint>
  <joint name="coupler" type="continuous"><parent>crank_link</parent><child>coupler_link</child>
    <axis><xyz>0 1 0</xyz></axis></joint>
  <joint name="rocker" type="continuous"><parent>coupler_link</parent><child>rocker_link</child>
    <axis><xyz>0 1 0</xyz></axis></joint>
  <drake:ball_constraint>
    <drake:ball_constraint_body_A>rocker_link</drake:ball_constraint_body_A>
    <drake:ball_constraint_body_B>ground</drake:ball_constraint_body_B>
    <drake:ball_constraint_p_AP>0.25548 0 -1.47808</drake:ball_constraint_p_AP>
    <drake:ball_constraint_p_BQ>2 0 0</drake:ball_constraint_p_BQ>
  </drake:ball_constraint>
</model>
</sdf>
"""


def test_an_sdf_ball_constraint_is_drakes(tmp_path: Path) -> None:
    path = tmp_path / "fourbar.sdf"
    path.write_text(FOURBAR_BALL_SDF)
    closure = closure_of(path)
    assert _numbers(closure) == (1, 3, 0, 1, {"lowest": 2, "highest": 2}, True)
    (cut,) = closure["cuts"]  # type: ignore[misc]
    assert (cut["kind"], cut["name"], cut["links"], cut["line"]) == (
        "drake:ball_constraint",
        "ball_constraint0",
        ["rocker_link", "ground"],
        13,
    )
    plant = drake_plant(path, None)
    assert plant.num_constraints() == 1 and plant.num_positions() == 3
    context = plant.CreateDefaultContext()
    constraints = constraints_of(path)
    space = cspace.ConfigurationSpace.from_report(cspace.inspect(path))
    conventions = space.conventions()
    rocker, ground = plant.GetBodyByName("rocker_link"), plant.GetBodyByName("ground")
    for x in space.sample(4, np.random.default_rng(3)):
        projected, worst, _ = constraints.project(conventions.to_pinocchio(x))
        assert worst < 1e-9
        plant.SetPositions(context, conventions.to_drake(conventions.from_pinocchio(projected)))
        p = plant.EvalBodyPoseInWorld(context, rocker).multiply([0.25548, 0, -1.47808])
        q = plant.EvalBodyPoseInWorld(context, ground).multiply([2.0, 0, 0])
        assert np.linalg.norm(p - q) < 1e-8


# Hostile inputs.


def _urdf_ball(tmp_path: Path, body_b: str = "ground", p_ap: str = "0.25548 0 -1.47808") -> Path:
    text = FOURBAR_URDF.read_text()
    text = text.replace('body_B name="ground"', f'body_B name="{body_b}"')
    text = text.replace('value="0.25548 0 -1.47808"', f'value="{p_ap}"')
    path = tmp_path / "fourbar.urdf"
    path.write_text(text)
    return path


@pytest.mark.parametrize("suffix", [".urdf", ".sdf"])
def test_a_ball_constraint_naming_no_link_is_refused_in_one_line(
    tmp_path: Path, suffix: str
) -> None:
    if suffix == ".urdf":
        path, line = _urdf_ball(tmp_path, body_b="grund"), 30
    else:
        path, line = tmp_path / "fourbar.sdf", 13
        path.write_text(FOURBAR_BALL_SDF.replace(">ground</drake", ">grund</drake"))
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert run.stderr == (
        f"cspace: error: {path}:{line}: <drake:ball_constraint> 'ball_constraint0' names "
        "body_B 'grund', which is no link [missing-link]\n"
    )


def test_a_loop_joint_naming_no_link_is_refused_as_any_joint(tmp_path: Path) -> None:
    closing = '<joint name="k" type="ball"><parent>ghost</parent><child>c</child></joint>'
    run = run_cli("inspect", str(_sdf(tmp_path, LINKS + TREE + closing)))
    assert run.code == 2 and ":6: joint 'k' names parent link 'ghost'" in run.stderr
    assert "[missing-link]" in run.stderr


@pytest.mark.parametrize(
    ("body_b", "p_ap", "why"),
    [
        ("rocker", "0.25548 0 -1.47808", "holds link 'rocker' to itself"),
        ("ground", "nan 0 -1.47808", "not finite"),
    ],
)
def test_a_ball_constraint_that_cannot_close_a_loop_is_closure_invalid(
    tmp_path: Path, body_b: str, p_ap: str, why: str
) -> None:
    report = cspace.inspect(_urdf_ball(tmp_path, body_b, p_ap))
    (invalid,) = [d for d in report.diagnostics if d.code == "closure-invalid"]
    assert why in invalid.message and invalid.line == 30
    assert report.closure is not None and report.closure.constraint_rows == 0
    assert report.dimension == 3


def test_a_ball_constraint_point_not_three_numbers_is_refused(tmp_path: Path) -> None:
    run = run_cli("inspect", str(_urdf_ball(tmp_path, p_ap="0.25 0")))
    assert run.code == 2 and run.stderr.rstrip().endswith("is not three numbers [bad-number]")


def _many_balls_urdf(count: int) -> str:
    ball = (
        '<drake:ball_constraint><drake:ball_constraint_body_A name="a"/>'
        '<drake:ball_constraint_body_B name="b"/><drake:ball_constraint_p_AP value="0 0 0"/>'
        '<drake:ball_constraint_p_BQ value="0 0 0"/></drake:ball_constraint>\n'
    )
    return (
        '<robot name="r" xmlns:drake="http://drake.mit.edu"><link name="a"/><link name="b"/>\n'
        '<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>\n'
        + ball * count
        + "</robot>\n"
    )


def _many_loops_sdf(count: int) -> str:
    loops = "".join(
        f'<joint name="k{n}" type="ball"><parent>a</parent><child>c</child></joint>\n'
        for n in range(count)
    )
    return f'<sdf version="1.9"><model name="m">\n{LINKS}\n{TREE}{loops}</model></sdf>\n'


def _many_balls_sdf(count: int) -> str:
    ball = (
        "<drake:ball_constraint><drake:ball_constraint_body_A>a</drake:ball_constraint_body_A>"
        "<drake:ball_constraint_body_B>c</drake:ball_constraint_body_B>"
        "<drake:ball_constraint_p_AP>0 0 0</drake:ball_constraint_p_AP>"
        "<drake:ball_constraint_p_BQ>0 0 0</drake:ball_constraint_p_BQ></drake:ball_constraint>\n"
    )
    return (
        '<sdf version="1.9" xmlns:drake="http://drake.mit.edu"><model name="m">\n'
        f"{LINKS}\n{TREE}{ball * count}</model></sdf>\n"
    )


@pytest.mark.bounded
@pytest.mark.parametrize(
    ("name", "text", "code", "said"),
    [
        ("balls.urdf", _many_balls_urdf(10_000), "too-many-constraints", "closes 10,000 kinematic"),
        ("balls.sdf", _many_balls_sdf(10_000), "too-many-constraints", "closes 10,000 kinematic"),
        ("loops.sdf", _many_loops_sdf(1_001), "too-many-constraints", "closes 1,001 kinematic"),
        ("loops.sdf", _many_loops_sdf(10_000), "too-many-joints", "declares 10,003 SDF joints"),
    ],
    ids=["urdf-10000-balls", "sdf-10000-balls", "sdf-1001-loop-joints", "sdf-10000-loop-joints"],
)
def test_ten_thousand_cuts_are_refused_within_bounds(
    tmp_path: Path, name: str, text: str, code: str, said: str
) -> None:
    path = tmp_path / name
    path.write_text(text)
    result = measured("inspect", str(path), cwd=tmp_path, forked=True)
    assert said in assert_bounded_error(result, code)


@pytest.mark.parametrize(
    ("name", "assembled"),
    [
        ("cassie_reduced.sdf", False),
        ("cassie_simple.sdf", False),
        ("cassie_v2.sdf", True),
        ("cassie_wo_gearbox_spring.sdf", True),
    ],
)
def test_cassie_loops_close_within_the_limits_or_the_limits_are_named(
    name: str, assembled: bool
) -> None:
    """Two of the files limit the tarsus crank and the foot's output joint to
    [-2.4435, -0.6109] rad, but draw their loops closed at 0: within those limits the
    loops stay open (200 projections from random configurations leave them 2.7 cm apart
    at best), and the report names the joints."""
    run = run_cli("inspect", "--format", "json", str(CASSIE / name))
    document = json.loads(run.stdout)
    assert document["closure"]["assembled"] is assembled
    found = [d for d in document["diagnostics"] if d["code"] == "closure-not-assembled"]
    assert run.code == (0 if assembled else 1) and len(found) == (0 if assembled else 1)
    if found:
        message = found[0]["message"]
        assert "'left-tarsus-crank-joint', 'left-foot-op'" in message
        assert "the limits keep the loops open" in message


def test_a_spherical_four_bar_moves(tmp_path: Path) -> None:
    """Four hinges whose axes meet at the origin, every link at the origin: every offset is
    0, and the mechanism moves (mobility 1, as a spherical four-bar does)."""
    path = tmp_path / "spherical.sdf"
    joint = (
        '<joint name="{0}" type="continuous"><parent>{1}</parent><child>{2}</child>'
        "<axis><xyz>{3}</xyz></axis></joint>"
    )
    path.write_text(
        '<?xml version="1.0"?><sdf version="1.9"><model name="spherical">'
        '<link name="crank_link"/><link name="coupler_link"/><link name="rocker_link"/>'
        + joint.format("crank", "world", "crank_link", "0 0 1")
        + joint.format("coupler", "crank_link", "coupler_link", "1 0 1")
        + joint.format("rocker", "coupler_link", "rocker_link", "0 1 1")
        + '<joint name="ground_pivot" type="revolute"><parent>world</parent>'
        '<child>rocker_link</child><axis><xyz expressed_in="__model__">1 1 1</xyz>'
        "</axis></joint></model></sdf>"
    )
    closure = closure_of(path)
    assert (closure["mobility"], closure["rank"]) == (1, {"lowest": 2, "highest": 2})


def test_a_half_turn_written_either_way_is_the_same_cut(tmp_path: Path) -> None:
    """The loop joint's frame turned by +pi or -pi about x: one rotation, one report."""
    text = FOURBAR_SDF.read_text()
    pose = '<pose relative_to="__model__">2 0 0 0 0 0</pose>'
    assert pose in text
    for name, roll in (("plus", "3.141592653589793"), ("minus", "-3.141592653589793")):
        turned = pose.replace("2 0 0 0 0 0", f"2 0 0 {roll} 0 0")
        (tmp_path / f"{name}.sdf").write_text(text.replace(pose, turned))
    run = run_cli("diff", str(tmp_path / "plus.sdf"), str(tmp_path / "minus.sdf"))
    assert run.code == 0 and run.stdout.startswith("no C-space change"), run
    # written to six digits, 3e-6 rad from a half turn: within --tolerance 1e-4, whatever
    # sign the quaternions are written with
    near = pose.replace("2 0 0 0 0 0", "2 0 0 3.14159 0 0")
    (tmp_path / "near.sdf").write_text(text.replace(pose, near))
    run = run_cli(
        "diff", "--tolerance", "1e-4", str(tmp_path / "minus.sdf"), str(tmp_path / "near.sdf")
    )
    assert run.code == 0 and run.stdout.startswith("no C-space change"), run
