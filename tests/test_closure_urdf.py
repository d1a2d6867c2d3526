"""Closed chains in URDF: the joints its transmissions drive are the ones to command, and
an SRDF group's report leaves the mechanism to the whole robot's."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import cspace

from conftest import REPO

FOURBAR = (REPO / "tests" / "closed" / "fourbar_drake.urdf").read_text()


def _with(tmp_path: Path, extra: str) -> Path:
    path = tmp_path / "fourbar.urdf"
    path.write_text(FOURBAR.replace("</robot>", extra + "</robot>"))
    return path


def _srdf(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "fourbar.srdf"
    path.write_text(f'<robot name="fourbar_drake">{body}</robot>')
    return path


def _transmission(*joints: str) -> str:
    named = "".join(f'<joint name="{joint}"/>' for joint in joints)
    return f'<transmission name="t"><type>SimpleTransmission</type>{named}</transmission>'


@pytest.mark.parametrize(
    ("joints", "actuated", "chart"),
    [
        (("crank_joint",), ("crank_joint",), True),
        (("crank_joint", "nothing", "crank_joint"), ("crank_joint",), True),
        (("crank_joint", "rocker_joint"), ("crank_joint", "rocker_joint"), False),
        ((), (), None),
    ],
    ids=["crank", "unknown-and-repeated", "two-for-one-degree", "none"],
)
def test_the_transmissions_joints_are_the_actuated_ones(
    tmp_path: Path, joints: tuple[str, ...], actuated: tuple[str, ...], chart: bool | None
) -> None:
    report = cspace.inspect(_with(tmp_path, _transmission(*joints) if joints else ""))
    closure = report.closure
    assert closure is not None and closure.mobility == 1
    assert closure.actuated == actuated and closure.chart is chart
    invalid = [d for d in report.diagnostics if d.code == "closure-chart-invalid"]
    assert len(invalid) == (chart is False)
    if invalid:  # two commanded for one degree of freedom: no configuration is a chart
        assert "mobility 1, 2 actuated coordinates" in invalid[0].message


def test_a_xacro_mechanism_keeps_its_loop_and_its_actuated_joints(tmp_path: Path) -> None:
    """xacro's output is read by the URDF reader: its ball constraint and transmission too."""
    source = FOURBAR.replace(
        'xmlns:drake="http://drake.mit.edu"',
        'xmlns:drake="http://drake.mit.edu" xmlns:xacro="http://www.ros.org/wiki/xacro"',
    ).replace("</robot>", _transmission("crank_joint") + "</robot>")
    path = tmp_path / "fourbar.urdf.xacro"
    path.write_text(source)
    closure = cspace.inspect(path).closure
    plain = cspace.inspect(_with(tmp_path, _transmission("crank_joint"))).closure
    assert closure is not None and plain is not None
    assert (closure.loops, closure.mobility, closure.actuated, closure.chart) == (
        plain.loops,
        plain.mobility,
        ("crank_joint",),
        True,
    )
    assert [cut.line for cut in closure.cuts] == [None]  # lines of xacro's output: none


def test_a_groups_report_leaves_the_mechanism_to_the_whole_robots(tmp_path: Path) -> None:
    path = _with(tmp_path, "")
    srdf = _srdf(tmp_path, '<group name="crank"><joint name="crank_joint"/></group>')
    whole = cspace.inspect(path, srdf=srdf)
    group = cspace.inspect(path, srdf=srdf, group="crank")
    assert whole.closure is not None and group.closure is None
    (found,) = [d for d in group.diagnostics if d.code == "closure-whole-robot"]
    assert "1 loop(s)" in found.message and "without --group" in found.message
    assert cspace.load(path, srdf=srdf, group="crank").closure is None


def test_a_mechanism_without_joints_has_a_closure_of_no_tangent(tmp_path: Path) -> None:
    """Every joint fixed, one ball constraint between two links: residual rows, no columns."""
    path = tmp_path / "fixed.urdf"
    path.write_text(
        '<robot name="u" xmlns:drake="http://drake.mit.edu"><link name="base"/><link name="l1"/>'
        '<joint name="f" type="fixed"><parent link="base"/><child link="l1"/>'
        '<origin xyz="1 0 0"/></joint><drake:ball_constraint>'
        '<drake:ball_constraint_body_A name="base"/><drake:ball_constraint_body_B name="l1"/>'
        '<drake:ball_constraint_p_AP value="1 0 0"/><drake:ball_constraint_p_BQ value="0 0 0"/>'
        "</drake:ball_constraint></robot>"
    )
    space = cspace.load(path)
    closure = space.closure
    assert closure is not None and space.dimension == 0
    assert closure.jacobian(space.neutral()).shape == (3, 0)
    assert np.allclose(closure.residual(space.neutral()), 0.0)
    assert closure.sample(2, np.random.default_rng(0)).shape == (2, 0)


def test_an_srdf_state_off_the_loop_is_named_in_the_srdf(tmp_path: Path) -> None:
    path = _with(tmp_path, "")
    srdf = _srdf(
        tmp_path,
        '\n<group name="all"><joint name="crank_joint"/>'
        '<joint name="coupler_joint"/><joint name="rocker_joint"/></group>\n'
        '<group_state name="closed" group="all"><joint name="crank_joint" value="0"/>'
        '<joint name="coupler_joint" value="0"/><joint name="rocker_joint" value="0"/>'
        "</group_state>\n"
        '<group_state name="open" group="all"><joint name="crank_joint" value="0.5"/>'
        '<joint name="coupler_joint" value="0"/><joint name="rocker_joint" value="0"/>'
        "</group_state>\n",
    )
    report = cspace.inspect(path, srdf=srdf)
    (found,) = [d for d in report.diagnostics if d.code == "pose-not-closed"]
    assert "'all/open'" in found.message and "ball_constraint0" in found.message
    assert (found.line, found.file) == (4, str(srdf))
