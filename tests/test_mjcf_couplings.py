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


@pytest.mark.parametrize("multiplier", ["-0.5", "2"])
def test_a_fraction_of_a_free_turn_is_a_warning(tmp_path: Path, multiplier: str) -> None:
    """D turns freely (S^1): D = 0.5 B... a half turn of B would follow a whole one of D."""
    path = tmp_path / "turn.xml"
    path.write_text(
        _CHAIN.format(
            ties=f'<joint joint1="B" joint2="D" polycoef="0 {multiplier} 0 0 0"/>', options=""
        ).replace('<joint name="D" range="-1 1"/>', '<joint name="D"/>')
    )
    report = cspace.inspect(path)
    warned = [d for d in report.diagnostics if d.code == "mimic-not-periodic"]
    assert len(warned) == (multiplier == "-0.5")
    urdf = tmp_path / "turn.urdf"
    urdf.write_text(
        '<robot name="t"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="D" type="continuous"><parent link="a"/><child link="b"/></joint>'
        '<joint name="B" type="revolute"><parent link="b"/><child link="c"/>'
        '<limit lower="-9" upper="9" effort="1" velocity="1"/>'
        f'<mimic joint="D" multiplier="{multiplier}"/></joint></robot>'
    )
    codes = [d.code for d in cspace.inspect(urdf).diagnostics]
    assert codes.count("mimic-not-periodic") == (multiplier == "-0.5")
