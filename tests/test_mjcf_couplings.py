"""MJCF joint equalities read as mimic joints: chains, second ties, circles, switches.

Each model is written here and compiled by MuJoCo, whose own constraint residuals
(``efc_pos``) judge the relations cspace reads: at every configuration cspace writes as
qpos, the ties that made mimic joints must hold exactly.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest
from test_mujoco_oracle import sampled, tie_residuals

import cspace
from cspace.conventions import Conventions

from conftest import run_cli

_CHAIN = """<mujoco model="ties"><compiler angle="radian"/><worldbody>
<body name="a"><joint name="A" range="-1 1" ref="0.2"/><geom size=".1"/>
<body name="b"><joint name="B" range="-1 1" ref="-0.1"/><geom size=".1"/>
<body name="c"><joint name="C" type="slide" axis="0 1 0" ref="0.05"/><geom size=".1"/>
<body name="d"><joint name="D" range="-1 1"/><geom size=".1"/>
</body></body></body></body></worldbody>{options}<equality>{ties}</equality></mujoco>"""


def _model(tmp_path: Path, ties: str, options: str = "") -> tuple[Path, mujoco.MjModel]:
    path = tmp_path / "ties.xml"
    path.write_text(_CHAIN.format(ties=ties, options=options))
    return path, mujoco.MjModel.from_xml_path(str(path))


def _mimics(report: cspace.Report) -> dict[str, tuple[str, float, float]]:
    return {
        j.name: (j.mimic.joint, j.mimic.multiplier, j.mimic.offset)
        for j in report.joints
        if j.mimic is not None
    }


def _held(path: Path, model: mujoco.MjModel, held: list[int]) -> None:
    """MuJoCo finds no error in the constraints ``held`` at configurations cspace writes."""
    space = cspace.load(path)
    for row in Conventions.of(space).to_mujoco(sampled(space, 10)):
        residuals = tie_residuals(model, row)
        assert all(abs(residuals[e]) < 1e-12 for e in held), residuals


B_OF_A = '<joint joint1="B" joint2="A" polycoef="0.1 2 0 0 0"/>'
C_OF_B = '<joint joint1="C" joint2="B" polycoef="-0.3 -0.5 0 0 0"/>'


@pytest.mark.parametrize("ties", [B_OF_A + C_OF_B, C_OF_B + B_OF_A], ids=["down", "up"])
def test_a_chain_of_ties_is_composed_whatever_the_order(tmp_path: Path, ties: str) -> None:
    path, model = _model(tmp_path, ties)
    report = cspace.inspect(path)
    mimics = _mimics(report)
    assert set(mimics) == {"B", "C"} and {m[0] for m in mimics.values()} == {"A"}
    assert report.manifold.notation == "R^2" and report.nq == 2  # A and D
    _held(path, model, [0, 1])
    said = {d.joint: d.message for d in report.diagnostics if d.code == "equality-mimic"}
    assert "follow joint 'A' through 'B'" in said["C"]


CROSSING = (
    '<joint joint1="D" joint2="A" polycoef="0 0.5 0 0 0"/>'
    '<joint joint1="C" joint2="B" polycoef="0 -1 0 0 0"/>'
)


def test_crossing_ties_keep_their_own_leaders(tmp_path: Path) -> None:
    """C follows B and D follows A: C comes first, its leader second (Pinocchio lists
    followers and leaders each sorted: zipped, they swapped C's and D's leaders)."""
    path, model = _model(tmp_path, CROSSING)
    report = cspace.inspect(path)
    assert {f: m[0] for f, m in _mimics(report).items()} == {"C": "B", "D": "A"}
    _held(path, model, [0, 1])
    urdf = tmp_path / "cross.urdf"
    joint = (
        '<joint name="{n}" type="{t}"><parent link="l{p}"/><child link="l{c}"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{m}</joint>'
    )
    urdf.write_text(
        '<robot name="x">'
        + "".join(f'<link name="l{k}"/>' for k in range(5))
        + joint.format(n="A", t="revolute", p=0, c=1, m="")
        + joint.format(n="B", t="prismatic", p=1, c=2, m="")
        + joint.format(n="C", t="prismatic", p=2, c=3, m='<mimic joint="B" multiplier="-1"/>')
        + joint.format(n="D", t="revolute", p=3, c=4, m='<mimic joint="A" multiplier="0.5"/>')
        + "</robot>"
    )
    assert {f: m[0] for f, m in _mimics(cspace.inspect(urdf)).items()} == {"C": "B", "D": "A"}


def test_a_second_tie_and_a_circle_stay_findings(tmp_path: Path) -> None:
    second = '<joint joint1="B" joint2="D"/>'
    back = '<joint joint1="A" joint2="B"/>'
    path, model = _model(tmp_path, B_OF_A + second + back)
    report = cspace.inspect(path)
    assert _mimics(report) == {"B": ("A", 2.0, pytest.approx(0.1 - 0.1 - 2 * 0.2))}
    said = {d.joint: d.message for d in report.diagnostics if d.code == "equality-joint"}
    assert "a second tie on a joint that already follows another" in said["B"]
    assert "the ties go round in a circle" in said["A"]
    _held(path, model, [0])


@pytest.mark.parametrize(
    ("ties", "options", "why"),
    [
        (
            '<joint joint1="B" joint2="A" active="false"/>',
            "",
            'inactive at the start: active="false"',
        ),
        (B_OF_A, '<option><flag equality="disable"/></option>', "it constrains nothing"),
        ('<joint joint1="B" joint2="A" polycoef="0 1 0.5 0 0"/>', "", "degree above 1"),
        ('<joint joint1="B" joint2="A" polycoef="nan 1 0 0 0"/>', "", "not finite"),
        ('<joint joint1="B"/>', "", "holds joint 'B' at a fixed value"),
    ],
    ids=["inactive", "switched-off", "quadratic", "nan", "held"],
)
def test_ties_that_are_no_mimic_joint_say_why(
    tmp_path: Path, ties: str, options: str, why: str
) -> None:
    path, _ = _model(tmp_path, ties, options)
    report = cspace.inspect(path)
    assert _mimics(report) == {} and report.dimension == 4
    (finding,) = [d for d in report.diagnostics if d.code == "equality-joint"]
    assert why in finding.message


def test_a_leader_later_in_the_tree_keeps_the_followers_q_entry(tmp_path: Path) -> None:
    path, model = _model(tmp_path, '<joint joint1="A" joint2="D" polycoef="0 -1 0 0 0"/>')
    report = cspace.inspect(path)
    a = next(j for j in report.joints if j.name == "A")
    assert a.kind is cspace.JointKind.MIMIC and a.q_index == 0  # Pinocchio keeps it
    assert report.dimension == 3 and report.nq == 4
    assert "mimic-kept-free" in {d.code for d in report.diagnostics}
    _held(path, model, [0])
    space = cspace.load(path)  # Pinocchio's q: A's entry set from D, A's ref folded in
    x = sampled(space, 3)
    q = space.to_pinocchio(x)
    np.testing.assert_allclose(q[:, 0], -x[:, space.names.index("D")] + 0.2)


def test_an_unranged_slide_follower_is_a_slide_to_other_files(tmp_path: Path) -> None:
    """C has no range: its MuJoCo type comes from MuJoCo, not from its limits' unit."""
    path, _ = _model(tmp_path, C_OF_B)
    report = cspace.inspect(path)
    assert next(j for j in report.joints if j.name == "C").mujoco_type == "slide"
    other = tmp_path / "free.xml"
    other.write_text(path.read_text().replace(C_OF_B, ""))  # C a joint of its own
    space = cspace.load(other)
    qpos = Conventions.of(space, path).to_mujoco(sampled(space, 2))
    assert qpos.shape == (2, 4)


def test_a_follower_beyond_a_double_is_refused_not_written_as_inf(tmp_path: Path) -> None:
    path, _ = _model(tmp_path, '<joint joint1="B" joint2="A" polycoef="1e308 1e308 0 0 0"/>')
    rows = tmp_path / "x.csv"
    rows.write_text("A,C,D\n1.0,0.0,0.0\n")
    run = run_cli("convert", str(path), str(rows), "--from", "canonical", "--to", "mujoco")
    assert run.code == 2 and "inf" not in run.stdout
    assert run.stderr.strip().endswith("[value-overflow]") and "x.csv:2" in run.stderr


@pytest.mark.parametrize(
    ("multiplier", "follower", "warned"),
    [
        ("-0.5", "", True),
        ("2", "", False),
        ("2", ' type="slide"', True),
        ("0.5", ' range="-1 1"', True),
    ],
    ids=["half", "whole", "rack", "limited"],
)
def test_a_mimic_of_a_free_turn_that_does_not_come_back_is_a_warning(
    tmp_path: Path, multiplier: str, follower: str, warned: bool
) -> None:
    """D turns freely (S^1): a turn of D must bring B back, so only a rotating B with a
    whole-number multiplier is a function of D's angle (a rack, a slide, never is)."""
    path = tmp_path / "turn.xml"
    path.write_text(
        _CHAIN.format(
            ties=f'<joint joint1="B" joint2="D" polycoef="0 {multiplier} 0 0 0"/>', options=""
        )
        .replace('<joint name="D" range="-1 1"/>', '<joint name="D"/>')
        .replace('<joint name="B" range="-1 1" ref="-0.1"/>', f'<joint name="B"{follower}/>')
    )
    codes = [d.code for d in cspace.inspect(path).diagnostics]
    assert codes.count("mimic-not-periodic") == warned
    urdf = tmp_path / "turn.urdf"
    kind = (
        "prismatic" if "slide" in follower else "revolute" if "range" in follower else "continuous"
    )
    limit = '<limit lower="-9" upper="9" effort="1" velocity="1"/>' if kind != "continuous" else ""
    urdf.write_text(
        '<robot name="t"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="D" type="continuous"><parent link="a"/><child link="b"/></joint>'
        f'<joint name="B" type="{kind}"><parent link="b"/><child link="c"/>{limit}'
        f'<mimic joint="D" multiplier="{multiplier}"/></joint></robot>'
    )
    codes = [d.code for d in cspace.inspect(urdf).diagnostics]
    assert codes.count("mimic-not-periodic") == warned
