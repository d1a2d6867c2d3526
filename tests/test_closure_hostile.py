"""Hostile closed chains in MJCF: every constraint refused or bounded, never a hang.

A constraint naming a missing body or one body twice (MuJoCo refuses them), two sites
of one body welded, numbers that are not finite or too large, as many constraints as
cspace reads (the search for configurations stays within its budget of work) and one
more (refused before MuJoCo compiles).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import PEAK_MIB, REPO, SECONDS, assert_bounded_error, measured

FOURBAR = (REPO / "tests" / "closed" / "fourbar.xml").read_text()
PIVOT = '<connect name="ground_pivot" body1="rocker" anchor="0.25548 0 -1.47808"/>'


def _with(tmp_path: Path, constraint: str, *, site: str = "") -> Path:
    text = FOURBAR.replace(PIVOT, constraint)
    if site:
        text = text.replace('<body name="rocker" pos="1.74452 0 0.97808">', site)
    path = tmp_path / "hostile.xml"
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("constraint", "said"),
    [
        ('<connect name="x" body1="nobody" anchor="0 0 0"/>', "unknown element 'nobody'"),
        ('<connect name="x" body1="rocker" body2="rocker" anchor="0 0 0"/>', "repeated"),
    ],
    ids=["missing-body", "body-to-itself"],
)
@pytest.mark.bounded
def test_a_constraint_mujoco_refuses_is_one_line(
    tmp_path: Path, constraint: str, said: str
) -> None:
    result = measured("inspect", str(_with(tmp_path, constraint)), cwd=tmp_path, forked=True)
    message = assert_bounded_error(result, "mujoco-refused")
    assert said in message and "hostile.xml:20:" in message


@pytest.mark.parametrize(
    ("constraint", "problem"),
    [
        ('<connect name="x" body1="rocker" anchor="nan 0 0"/>', "not finite"),
        ('<connect name="x" body1="rocker" anchor="1e300 0 0"/>', "farther than"),
        ('<weld name="x" site1="s1" site2="s2"/>', "holds link 'rocker' to itself"),
    ],
    ids=["nan-anchor", "far-anchor", "two-sites-of-one-body"],
)
@pytest.mark.bounded
def test_a_constraint_that_cannot_be_evaluated_is_left_out_and_said(
    tmp_path: Path, constraint: str, problem: str
) -> None:
    sites = (
        '<body name="rocker" pos="1.74452 0 0.97808"><site name="s1"/><site name="s2" pos="0 0 1"/>'
    )
    path = _with(tmp_path, constraint, site=sites)
    result = measured("inspect", str(path), "--format", "json", cwd=tmp_path, forked=True)
    assert result.run.code == 1 and result.run.stderr == ""  # an error-level finding
    document = json.loads(result.run.stdout)
    (found,) = [d for d in document["diagnostics"] if d["code"] == "closure-invalid"]
    assert problem in found["message"] and found["severity"] == "error"
    assert document["closure"]["cuts"] == [] and document["closure"]["samples"] == 0


def _many(tmp_path: Path, count: int) -> Path:
    """A 50-hinge chain with ``count`` connects of its bodies to the world."""
    bodies = "".join(
        f'<body name="b{i}" pos="0.1 0 0"><joint name="j{i}" axis="0 {i % 2} {1 - i % 2}"/>'
        '<geom size="0.01"/>'
        for i in range(50)
    )
    connects = "".join(
        f'<connect body1="b{(7 * i) % 50}" anchor="0.05 0.01 0"/>' for i in range(count)
    )
    path = tmp_path / f"many{count}.xml"
    path.write_text(
        f"<mujoco><worldbody>{bodies}{'</body>' * 50}</worldbody>"
        f"<equality>{connects}</equality></mujoco>"
    )
    return path


@pytest.mark.bounded
def test_as_many_constraints_as_cspace_reads_stay_within_its_budget(
    tmp_path: Path,
) -> None:
    result = measured("inspect", str(_many(tmp_path, 1000)), "--format", "json", cwd=tmp_path)
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    document = json.loads(result.run.stdout)
    closure = document["closure"]
    assert closure["loops"] == 50 and closure["constraint_rows"] == 3000
    assert closure["grubler"] == 50 - 3000
    # one projection would cost more than the budget: none is tried, and the report says so
    assert closure["attempts"] == 0 and closure["assembled"] is None
    (found,) = [d for d in document["diagnostics"] if d["code"] == "closure-not-analysed"]
    assert "cost more than cspace spends" in found["message"]


@pytest.mark.bounded
def test_one_constraint_more_is_refused_before_mujoco_compiles(tmp_path: Path) -> None:
    result = measured("inspect", str(_many(tmp_path, 1001)), cwd=tmp_path, forked=True)
    assert "1,000" in assert_bounded_error(result, "too-many-constraints")


@pytest.mark.bounded
def test_a_weld_on_a_robot_without_joints_is_rigid_not_a_crash(tmp_path: Path) -> None:
    """Pinocchio's frame Jacobian crashes on a model without velocities: none is asked."""
    path = tmp_path / "welded.xml"
    path.write_text(
        '<mujoco model="w"><worldbody><body name="b"><geom size="0.1"/></body></worldbody>'
        '<equality><weld body1="b"/></equality></mujoco>'
    )
    result = measured("inspect", str(path), "--format", "json", cwd=tmp_path, forked=True)
    assert result.run.code == 0, result
    closure = json.loads(result.run.stdout)["closure"]
    assert (closure["mobility"], closure["grubler"], closure["rank"]["highest"]) == (0, -6, 0)


@pytest.mark.bounded
def test_one_loop_on_a_large_tree_is_not_searched_and_memory_stays_bounded(
    tmp_path: Path,
) -> None:
    """Pinocchio's data holds nv^3 numbers (1 GB at nv 240): beyond 160 velocities the
    mechanism is not searched, and the report says why."""
    bodies = "".join(
        f'<body name="b{i}" pos="0.01 0 0"><joint name="j{i}" axis="0 1 0"/><geom size="0.001"/>'
        for i in range(240)
    )
    path = tmp_path / "long.xml"
    path.write_text(
        f"<mujoco><worldbody>{bodies}{'</body>' * 240}</worldbody>"
        '<equality><connect body1="b239" anchor="0.01 0 0"/></equality></mujoco>'
    )
    result = measured("inspect", str(path), "--format", "json", cwd=tmp_path, forked=True)
    assert result.cpu_seconds < SECONDS and result.peak_mib < 300, result
    document = json.loads(result.run.stdout)
    assert document["closure"]["attempts"] == 0 and document["closure"]["grubler"] == 237
    (found,) = [d for d in document["diagnostics"] if d["code"] == "closure-not-analysed"]
    assert "240 velocities are more than the 160" in found["message"]


@pytest.mark.bounded
def test_constraints_are_counted_across_includes(tmp_path: Path) -> None:
    """600 connects in the file and 401 in the one it includes: 1,001 in all, refused
    before MuJoCo compiles."""
    many = _many(tmp_path, 600).read_text()
    connects = '<connect body1="b1" anchor="0 0 0"/>' * 401
    (tmp_path / "more.xml").write_text(
        f"<mujocoinclude><equality>{connects}</equality></mujocoinclude>"
    )
    path = tmp_path / "included.xml"
    path.write_text(many.replace("</mujoco>", '<include file="more.xml"/></mujoco>'))
    result = measured("inspect", str(path), cwd=tmp_path, forked=True)
    assert "(in more.xml, line 1)" in assert_bounded_error(result, "too-many-constraints")
