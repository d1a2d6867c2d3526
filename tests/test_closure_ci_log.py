"""A mechanism's names reach no CI log as a workflow command, in any output.

The closed chains bring names of their own into every output: a cut's name and kind,
the two links it holds, the actuated joints, the keyframe that leaves a loop open, an
SDF loop joint whose limits no cut holds, and a missing body a ball constraint names in
the one-line error. Each is written here as a workflow command (``::`` at a line's
start, ``##[`` anywhere), with a line break, a bidi override and C1 controls, and every
command that shows it (``inspect`` in every format, ``diff`` in every format, ``check
--baseline --format github``) is held to `test_ci_log`'s rule on stdout and stderr alike:
no command but cspace's own annotations, every line printable, the names escaped and,
in JSON, kept exactly.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_ci_log import CARRIED, EVIL, run_safely

SDF_EVIL = "##[group]z&#10;&#x202e;&#x85;&#x9b;"
"""SDFormat refuses ``::`` in a name: the rest of `EVIL` then."""

ANCHOR = "0.25548 0 -1.47808"


def _mjcf(anchor: str = ANCHOR) -> str:
    """The four-bar, every name of its mechanism EVIL: bodies, joints, the connect, the
    actuator's joint, a keyframe that opens the loop, a tendon equality beside it."""
    return f"""<mujoco model="{EVIL}m"><worldbody>
  <body name="{EVIL}crank"><joint name="{EVIL}j1" axis="0 1 0"/>
    <geom type="capsule" fromto="0 0 0 0 0 0.5" size="0.02"/>
    <body name="{EVIL}coupler" pos="0 0 0.5"><joint name="{EVIL}j2" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 1.74452 0 0.97808" size="0.02"/>
      <body name="{EVIL}rocker" pos="1.74452 0 0.97808"><joint name="{EVIL}j3" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 {ANCHOR}" size="0.02"/>
      </body></body></body></worldbody>
  <tendon><fixed name="{EVIL}t"><joint joint="{EVIL}j1" coef="1"/></fixed></tendon>
  <equality><connect name="{EVIL}c" body1="{EVIL}rocker" anchor="{anchor}"/>
    <tendon tendon1="{EVIL}t"/></equality>
  <actuator><motor name="{EVIL}a" joint="{EVIL}j1"/></actuator>
  <keyframe><key name="{EVIL}k" qpos="0.5 0 0"/></keyframe>
</mujoco>
"""


SDF = f"""<?xml version="1.0"?><sdf version="1.9"><model name="m">
  <link name="{SDF_EVIL}crank"/><link name="{SDF_EVIL}coupler">
    <pose relative_to="__model__">0 0 0.5 0 0 0</pose></link>
  <link name="{SDF_EVIL}rocker"><pose relative_to="__model__">1.74452 0 1.47808 0 0 0</pose>
  </link>
  <joint name="{SDF_EVIL}j1" type="continuous"><parent>world</parent>
    <child>{SDF_EVIL}crank</child><axis><xyz>0 1 0</xyz></axis></joint>
  <joint name="{SDF_EVIL}j2" type="continuous"><parent>{SDF_EVIL}crank</parent>
    <child>{SDF_EVIL}coupler</child><axis><xyz>0 1 0</xyz></axis></joint>
  <joint name="{SDF_EVIL}j3" type="continuous"><parent>{SDF_EVIL}coupler</parent>
    <child>{SDF_EVIL}rocker</child><axis><xyz>0 1 0</xyz></axis></joint>
  <joint name="{SDF_EVIL}pivot" type="revolute"><parent>world</parent>
    <child>{SDF_EVIL}rocker</child><pose>{ANCHOR} 0 0 0</pose>
    <axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>
</model></sdf>
"""

MISSING = f"""<robot name="r" xmlns:drake="http://drake.mit.edu"><link name="a"/><link name="b"/>
  <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>
  <drake:ball_constraint><drake:ball_constraint_body_A name="b"/>
    <drake:ball_constraint_body_B name="{EVIL}gone"/>
    <drake:ball_constraint_p_AP value="0 0 0"/><drake:ball_constraint_p_BQ value="0 0 0"/>
  </drake:ball_constraint></robot>
"""


@pytest.fixture(scope="module")
def pr(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A pull request's mechanisms, every name of theirs a workflow command."""
    root = tmp_path_factory.mktemp("mechanisms")
    (root / "old.xml").write_text(_mjcf())
    (root / "new.xml").write_text(_mjcf("0.25548 0 -0.5"))  # the connect held elsewhere
    (root / "loop.sdf").write_text(SDF)
    (root / "missing.urdf").write_text(MISSING)
    return root


@pytest.mark.parametrize(
    ("file", "codes"),
    [
        ("old.xml", {"pose-not-closed", "closure-partial", "closure-grubler-differs"}),
        ("loop.sdf", {"closure-limits-ignored", "closure-grubler-differs"}),
    ],
)
@pytest.mark.parametrize(
    "fmt", ["text", "markdown", "json", "jsonl", "sarif", "github", "html", "svg"]
)
def test_a_mechanism_in_every_format(pr: Path, file: str, codes: set[str], fmt: str) -> None:
    code, out, err = run_safely(pr, "inspect", "--format", fmt, file, ours=fmt == "github")
    assert code == 0 and err == "", err
    if fmt == "json":
        document = json.loads(out)
        assert codes <= {d["code"] for d in document["diagnostics"]}
        links = {link for cut in document["closure"]["cuts"] for link in cut["links"]}
        assert any("##[group]z" in link for link in links), links  # kept exactly
    elif fmt in ("text", "markdown", "html"):
        assert CARRIED[1] in out, out  # shown, escaped


@pytest.mark.parametrize("fmt", ["text", "json", "markdown", "html"])
def test_a_cut_held_elsewhere_in_every_diff(pr: Path, fmt: str) -> None:
    code, out, _ = run_safely(pr, "diff", "--format", fmt, "old.xml", "new.xml")
    assert code == 1 and "cut" in out, out
    if fmt != "json":
        assert CARRIED[1] in out, out


def test_check_against_a_baseline_annotates_the_cut_safely(pr: Path, tmp_path: Path) -> None:
    _, report, _ = run_safely(pr, "inspect", "--format", "jsonl", "old.xml")
    baseline = tmp_path / "baseline.jsonl"
    baseline.write_text(report.replace('"old.xml"', '"new.xml"'))
    code, out, _ = run_safely(
        pr, "check", "--baseline", str(baseline), "--format", "github", "new.xml", ours=True
    )
    assert code == 1 and "loop cut changed" in out, out


def test_a_missing_body_in_the_one_line_error(pr: Path) -> None:
    code, out, err = run_safely(pr, "inspect", "missing.urdf")
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "[missing-link]" in err and CARRIED[1] in err, err
