"""Drake's MJCF parser against MuJoCo, and the ``drake-mjcf-differs`` finding.

Drake's parser (``Parser(plant).AddModels``) makes a body with several joints a chain in
which all joints but the last act in the parent's frame, before the body's own pos and
quat; MuJoCo applies them all in the body's frame, after. It ignores ``<frame>``,
``<replicate>`` and ``<attach>`` with all they hold. cspace reports where this makes
Drake's model of a file another mechanism than MuJoCo's, and ``--to drake`` says so.

The oracle is the two tools: every body MuJoCo names, at random configurations written
as MuJoCo's qpos and as Drake's q through cspace's maps, at the same pose in both (1e-9),
and Drake's q as long as cspace's. The finding is given exactly where they are not: on
small files, one feature each (several joints, joint pos, ref, turned and moved bodies,
a ball; each read in Drake once), on the teaching files and on a representative part of
the MJCF corpus (every file of which ``bench/sweep_drake.py mjcf`` checks: of 304, 112
that MuJoCo compiles and Drake parses, 18 where Drake's model differs, each said, and
no other; one more file aborts Drake).
"""

from __future__ import annotations

import importlib.util
import logging
import re
from functools import cache
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

import cspace

from conftest import REPO, ROBOTS, run_cli

logging.getLogger("drake").setLevel(logging.CRITICAL)  # its notes on what it ignores

CODE = "drake-mjcf-differs"


def _document(name: str, body: str, compiler: str = "") -> str:
    """A model: a base, then body ``b`` (one feature, ``body``) with a child ``tip``."""
    return f"""<mujoco model="{name}">{compiler}<worldbody>
  <body name="base" pos="0 0 0.5"><geom size="0.05"/>
    <body name="b" {body}
      <geom size="0.05" pos="0.1 0.2 0.3"/>
      <body name="tip" pos="0.3 0 0.1"><geom size="0.05"/></body>
    </body>
  </body>
</worldbody></mujoco>"""


def _hinge(name: str, attributes: str = "") -> str:
    return f'<joint name="{name}" type="hinge" {attributes}/>'


def _slide(name: str, attributes: str = "") -> str:
    return f'<joint name="{name}" type="slide" {attributes}/>'


def _ball(name: str, attributes: str = "") -> str:
    return f'<joint name="{name}" type="ball" {attributes}/>'


SMALL = {
    # (body b's attributes and joints, Drake's model differs)
    "two_hinges_moved": ('pos="0.5 0 1">' + _hinge("j1", 'axis="0 0 1"') + _hinge("j2"), True),
    "one_hinge_pos_ref": (
        'pos="0.5 0 1" euler="10 20 30">' + _hinge("j1", 'axis="1 1 0" pos="0.1 0.2 0.3" ref="30"'),
        False,
    ),
    "two_hinges_in_place": (
        ">" + _hinge("j1", 'axis="0 0 1" pos="0.2 0 0"') + _hinge("j2", 'pos="0 0.3 0"'),
        False,
    ),
    "moved_along_the_first_axis": (
        'pos="0 0 0.7">' + _hinge("j1", 'axis="0 0 1" pos="0.2 0 0"') + _hinge("j2"),
        False,
    ),
    "moved_off_the_first_axis": (
        'pos="0.3 0 0">' + _hinge("j1", 'axis="0 0 1" pos="0.2 0 0"') + _hinge("j2"),
        True,
    ),
    "turned_about_the_first_axis": (
        'pos="0 0 0.4" euler="0 0 40">' + _hinge("j1", 'axis="0 0 1"') + _hinge("j2"),
        False,
    ),
    "turned_off_the_first_axis": (
        'pos="0 0 0.4" euler="40 0 0">' + _hinge("j1", 'axis="0 0 1"') + _hinge("j2"),
        True,
    ),
    "slides_then_hinge_moved": (  # dm_control's cheetah, walker, hopper
        'pos="0.3 0.2 1">'
        + _slide("x", 'axis="1 0 0"')
        + _slide("z", 'axis="0 0 1"')
        + _hinge("r", 'axis="0 1 0"'),
        False,
    ),
    "slide_then_hinge_turned": (
        'pos="0.3 0.2 1" euler="0 0 30">' + _slide("x", 'axis="1 0 0"') + _hinge("r"),
        True,
    ),
    "refs_turned_about_the_slide": (
        'pos="0.3 0.2 1" euler="30 0 0">'
        + _slide("x", 'axis="1 0 0" ref="0.2"')
        + _hinge("r", 'axis="0 1 0" ref="10"'),
        False,
    ),
    "refs_moved_off_the_first_axis": (
        'pos="0.3 0 0">' + _hinge("j1", 'axis="0 0 1" ref="45"') + _hinge("j2", 'ref="-20"'),
        True,
    ),
    "ball_then_slide_in_place": (">" + _ball("ball", 'pos="0.1 0 0"') + _slide("s"), False),
    "ball_then_slide_moved": ('pos="0.3 0 0">' + _ball("ball") + _slide("s"), True),
    "hinge_then_ball_moved": (
        'pos="0.3 0 0">' + _hinge("j1", 'axis="0 0 1"') + _ball("ball", 'pos="0 0.2 0"'),
        True,
    ),
    "three_hinges_moved": (
        'pos="0 0 0.5">'
        + _hinge("a", 'axis="0 0 1"')
        + _hinge("b1", 'axis="1 0 0"')
        + _hinge("c", 'axis="0 1 0"'),
        True,
    ),
}
"""Small models, one feature each, and whether Drake's model of each differs (the
oracle says so too: this is what the finding is held to)."""


def _package_file(package: str, relative: str) -> Path:
    spec = importlib.util.find_spec(package)  # found, not imported
    assert spec is not None and spec.submodule_search_locations, package
    return Path(next(iter(spec.submodule_search_locations))) / relative


CORPUS = [
    *sorted(p for p in ROBOTS.rglob("*.xml") if re.search(rb"<mujoco[\s>]", p.read_bytes())),
    *sorted((REPO / "tests" / "pairs").glob("*.xml")),
    *(
        _package_file("dm_control", f"suite/{name}.xml")
        for name in ("humanoid", "fish", "quadruped", "cheetah", "walker", "point_mass")
    ),
    _package_file("dm_control", "locomotion/soccer/assets/boxhead/boxhead.xml"),
    *(
        _package_file("gymnasium", f"envs/mujoco/assets/{name}.xml")
        for name in ("humanoidstandup", "reacher", "swimmer", "pusher")
    ),
]
"""The teaching files and a part of the corpus: the files Drake's model differs for
(several joints in humanoids, a fish, a quadruped, a camera's head; <frame>, <replicate>
and <attach> in the teaching files) and files with several joints in a body that Drake
reads as MuJoCo does (slides then a hinge in a moved body, hinges in place)."""


@cache
def _report(path: Path) -> cspace.Report:
    return cspace.inspect(path)


@cache
def _oracle(path: Path) -> bool:
    """Whether Drake's model of the file differs from MuJoCo's, measured (see above)."""
    model = mujoco.MjModel.from_xml_path(str(path))
    space = cspace.ConfigurationSpace.from_report(_report(path))
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    return drake_differs(model, plant, space)


def drake_differs(model: Any, plant: MultibodyPlant, space: cspace.ConfigurationSpace) -> bool:
    """Whether Drake's finalized plant places a body MuJoCo's model names elsewhere (1e-9,
    at 3 random configurations written as qpos and as Drake's q through cspace's maps),
    lacks one, or has a q of another length (bodies and joints Drake left out)."""
    conventions = space.conventions()
    if plant.num_positions() != len(conventions.names("drake")):
        return True
    context, data = plant.CreateDefaultContext(), mujoco.MjData(model)
    free = {c.name: (-2.0, 2.0) for c in space.coordinates if np.isinf(c.lower) and not c.wraps}
    for x in space.sample(3, np.random.default_rng(5), bounds=free):
        data.qpos[:] = conventions.to_mujoco(x)
        mujoco.mj_kinematics(model, data)
        plant.SetPositions(context, conventions.to_drake(x))
        for body in range(1, model.nbody):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body)
            if not name:
                continue
            if not plant.HasBodyNamed(name):
                return True
            pose = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(name))
            rotation = data.xmat[body].reshape(3, 3)
            if not (
                np.allclose(pose.translation(), data.xpos[body], rtol=0, atol=1e-9)
                and np.allclose(pose.rotation().matrix(), rotation, rtol=0, atol=1e-9)
            ):
                return True
    return False


def _said(path: Path) -> list[cspace.Diagnostic]:
    return [d for d in _report(path).diagnostics if d.code == CODE]


@pytest.mark.parametrize("name", sorted(SMALL))
def test_the_finding_is_given_exactly_where_drake_places_bodies_otherwise(
    name: str, tmp_path: Path
) -> None:
    body, differs = SMALL[name]
    path = tmp_path / f"{name}.xml"
    path.write_text(_document(name, body))
    assert _oracle(path) is differs  # the case is what it says
    said = _said(path)
    assert bool(said) is differs
    if differs:
        (finding,) = said
        assert "'b'" in finding.message and finding.severity is cspace.Severity.INFO
        assert finding.line == 3  # the body's


@pytest.mark.parametrize("path", CORPUS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_finding_follows_drake_on_the_corpus(path: Path) -> None:
    assert bool(_said(path)) is _oracle(path)


def test_the_corpus_part_holds_both_verdicts() -> None:
    """Not a vacuous pass: files Drake reads otherwise, and files with several joints in
    a body that it reads as MuJoCo does."""
    names = {p.name for p in CORPUS if _said(p)}
    assert {"humanoid.xml", "fish.xml", "quadruped.xml", "mjcf_replicate.xml"} <= names
    assert "cheetah.xml" not in names and "walker.xml" not in names


def test_the_issues_body_two_hinges_apart(tmp_path: Path) -> None:
    """j1 = 0.5: Drake puts the body at [0.4388, 0.2397, 1], MuJoCo at [0.5, 0, 1]."""
    path = tmp_path / "two.xml"
    path.write_text(
        '<mujoco model="two"><worldbody><body name="b" pos="0.5 0 1">'
        '<joint name="j1" axis="0 0 1"/><joint name="j2" axis="0 1 0"/><geom size="0.1"/>'
        "</body></worldbody></mujoco>"
    )
    space = cspace.load(path)
    conventions = space.conventions()
    x = np.array([0.5, 0.0])
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, conventions.to_drake(x))
    drake = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName("b")).translation()
    np.testing.assert_allclose(drake, [0.5 * np.cos(0.5), 0.5 * np.sin(0.5), 1.0], atol=1e-12)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    data.qpos[:] = conventions.to_mujoco(x)
    mujoco.mj_kinematics(model, data)
    np.testing.assert_allclose(data.xpos[1], [0.5, 0.0, 1.0], atol=1e-12)
    (finding,) = conventions.drake.findings  # the Drake convention carries it
    assert finding.code == CODE and finding.joint == "j1"
    assert "'b'" in finding.message and "'j1' of 'b'" in finding.message


def test_a_saved_report_keeps_what_drake_reads_otherwise() -> None:
    path = CORPUS[[p.name for p in CORPUS].index("fish.xml")]
    saved = cspace.Report.from_dict(_report(path).to_dict())
    space = cspace.ConfigurationSpace.from_report(saved)
    assert space.conventions().drake.findings == tuple(_said(path))


def test_convert_to_drake_warns_on_standard_error(tmp_path: Path) -> None:
    """The vectors are written as before, Drake's names and order; the warning, with the
    file, the line and the code, says where Drake's model is not the file's."""
    path = tmp_path / "two.xml"
    path.write_text(_document("two", SMALL["two_hinges_moved"][0]))
    (tmp_path / "x.csv").write_text("j1,j2\n0.5,0.25\n")
    run = run_cli(
        "convert", "two.xml", "x.csv", "--from", "canonical", "--to", "drake", cwd=tmp_path
    )
    assert run.code == 0, run.stderr
    assert run.stdout.splitlines() == ["j1_q,j2_q", "0.5,0.25"]
    (line,) = run.stderr.splitlines()
    assert line.startswith("cspace: warning: two.xml:3: Drake's MJCF parser places 1 body(ies)")
    assert line.endswith(f"[{CODE}]")


def test_convert_says_nothing_where_drake_agrees(tmp_path: Path) -> None:
    path = tmp_path / "walker.xml"
    path.write_text(_document("walker", SMALL["slides_then_hinge_moved"][0]))
    (tmp_path / "x.csv").write_text("x,z,r\n0.1,0.2,0.3\n")
    run = run_cli(
        "convert", "walker.xml", "x.csv", "--from", "canonical", "--to", "drake", cwd=tmp_path
    )
    assert run.code == 0 and run.stderr == "", run.stderr


def test_a_stored_pose_to_drake_warns_too(tmp_path: Path) -> None:
    text = _document("two", SMALL["two_hinges_moved"][0]).replace(
        "</worldbody>", '</worldbody><keyframe><key name="up" qpos="0.5 0.25"/></keyframe>'
    )
    (tmp_path / "two.xml").write_text(text)
    run = run_cli("convert", "two.xml#up", "--to", "drake", cwd=tmp_path)
    assert run.code == 0 and run.stdout.splitlines()[-1] == "0.5,0.25"
    assert run.stderr.startswith("cspace: warning: two.xml:3: ") and CODE in run.stderr


def test_the_finding_is_an_info_that_fails_no_run(tmp_path: Path) -> None:
    """A fact about the file for a Drake user: inspect --strict still passes."""
    (tmp_path / "two.xml").write_text(_document("two", SMALL["two_hinges_moved"][0]))
    run = run_cli("inspect", "two.xml", "--strict", cwd=tmp_path)
    assert run.code == 0, run.stderr
    assert f"info    {CODE} (line 3)" in run.stdout
