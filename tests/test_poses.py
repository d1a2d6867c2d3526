"""The poses an MJCF file stores (keyframes), checked as configurations of its C-space.

MuJoCo is the reader (``<key>`` as compiled, quaternions as written); each finding names
the keyframe, the joint, the value and the bounds at the keyframe's line. A pose outside
the space fails ``cspace check`` but leaves the space defined. Hostile keyframes (NaN,
1e308, thousands of them, the wrong length) are refused or bounded, in one line.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import cspace

from conftest import run_cli

ROBOT = """<mujoco model="arm">
  <compiler angle="radian"/>
  <size nkey="{blank}"/>
  <worldbody>
    <body name="base">
      <joint name="spin" type="hinge" axis="0 0 1"/>
      <geom size="0.1"/>
      <body name="upper">
        <joint name="lift" type="hinge" axis="0 1 0" range="-1 1"/>
        <geom size="0.1"/>
        <body name="hand">
          <joint name="wrist" type="ball" range="0 0.5"/>
          <geom size="0.1"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe>
{keys}
  </keyframe>
</mujoco>
"""


def _write(tmp_path: Path, keys: str, blank: int = 0) -> Path:
    path = tmp_path / "arm.xml"
    path.write_text(ROBOT.format(keys=keys, blank=blank))
    return path


def _poses(path: Path) -> list[tuple[str, str, int | None, str]]:
    report = cspace.inspect(path)
    return [
        (d.severity.value, d.code, d.line, d.message)
        for d in report.diagnostics
        if d.code.startswith("pose")
    ]


def test_a_keyframe_inside_the_space_says_nothing(tmp_path: Path) -> None:
    path = _write(tmp_path, '    <key name="home" qpos="4.0 0.5 0.9999 0.01 0 0"/>')
    assert _poses(path) == []  # spin turns freely: 4 rad is fine; |q| within 1e-3 of 1


def test_each_stored_pose_outside_is_named_with_its_joint_value_bounds_and_line(
    tmp_path: Path,
) -> None:
    path = _write(
        tmp_path,
        '    <key name="home" qpos="0 1.5 1 0 0 0"/>\n    <key qpos="0 0 0.7071 0.7071 0 0"/>',
    )
    assert _poses(path) == [
        ("error", "pose-out-of-limits", 19,
         "keyframe 'home': joint 'lift' is 1.5, outside [-1, 1] rad"),
        ("error", "pose-out-of-limits", None,
         "keyframe 'key1': ball joint 'wrist' is turned 1.5708 rad, more than its range 0.5 rad"),
    ]  # fmt: skip
    space = cspace.load(path)  # the C-space is still defined
    assert space.dimension == 5
    run = run_cli("check", str(path), "--dimension", "5")  # the space is as expected
    assert run.code == 1 and run.stderr == (
        f"cspace: check failed: {path}: keyframe 'home': joint 'lift' is 1.5, outside "
        "[-1, 1] rad [pose-out-of-limits]\n"
    )


def test_blank_keyframes_of_size_nkey_are_not_poses_the_file_stores(tmp_path: Path) -> None:
    """`<size nkey>` makes MuJoCo allocate keyframes at qpos0 (gymnasium's humanoid has
    five, its knees outside their range): not poses anyone wrote."""
    path = _write(tmp_path, '    <key name="home" qpos="0 0.5 1 0 0 0"/>', blank=4)
    path.write_text(path.read_text().replace('range="-1 1"', 'range="0.2 1"'))
    assert _poses(path) == []


@pytest.mark.parametrize(
    ("qpos", "said"),
    [
        ("nan 0 1 0 0 0", "joint 'spin' is nan"),
        ("0 nan 1 0 0 0", "joint 'lift' is nan, outside [-1, 1] rad"),
        ("0 1e308 1 0 0 0", "joint 'lift' is 1e+308, outside [-1, 1] rad"),
        ("0 0 nan 0 0 0", "joint 'wrist' is (nan, 0, 0, 0): not finite"),
    ],
)
def test_values_that_are_no_numbers_of_the_space(tmp_path: Path, qpos: str, said: str) -> None:
    path = _write(tmp_path, f'    <key name="k" qpos="{qpos}"/>')
    run = run_cli("inspect", str(path), "--format", "json")
    assert run.code == 1, run.stderr
    messages = [d["message"] for d in json.loads(run.stdout)["diagnostics"]]
    assert any(said in m for m in messages), messages


def test_a_keyframe_of_the_wrong_length_is_mujocos_refusal_in_one_line(tmp_path: Path) -> None:
    path = _write(tmp_path, '    <key name="short" qpos="0 0 1"/>\n    <key qpos="0 0 1 0 0 0 7"/>')
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert "arm.xml" in run.stderr


def test_thousands_of_keyframes_are_bounded(tmp_path: Path) -> None:
    """200,000 numbers are checked; the rest are counted, in an info finding."""
    keys = "\n".join(f'    <key qpos="0 {k % 3 - 1} 1 0 0 0"/>' for k in range(40_000))
    path = _write(tmp_path, keys)
    report = cspace.inspect(path)
    codes = [d.code for d in report.diagnostics]
    assert codes.count("poses-not-checked") == 1
    (note,) = [d.message for d in report.diagnostics if d.code == "poses-not-checked"]
    assert note.startswith("6,667 of 40,000 keyframes not checked")
