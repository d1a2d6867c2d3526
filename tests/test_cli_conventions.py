"""``cspace convert`` and ``cspace unwrap`` as a user runs them, on CSV and JSON Lines."""

from __future__ import annotations

import io
import json
import os
from pathlib import Path

import numpy as np
import pytest

import cspace

from conftest import REPO, ROBOTS, run_cli

ARM = str(ROBOTS / "arm7.urdf")
ARM_MJCF = str(REPO / "tests" / "pairs" / "arm7.xml")
QUADRUPED = str(ROBOTS / "quadruped_nobase.urdf")


def _csv(names, rows) -> str:  # type: ignore[no-untyped-def]
    rows = np.asarray(rows).tolist()
    return ",".join(names) + "\n" + "".join(",".join(map(repr, r)) + "\n" for r in rows)


def _read_csv(text: str) -> tuple[list[str], np.ndarray]:
    lines = text.splitlines()
    return lines[0].split(","), np.loadtxt(
        io.StringIO("\n".join(lines[1:])), delimiter=",", ndmin=2
    )


@pytest.fixture
def samples(tmp_path: Path) -> Path:
    space = cspace.load(ARM)
    x = space.sample(50, np.random.default_rng(0))
    path = tmp_path / "x.csv"
    path.write_text(_csv(space.names, x))
    return path


def _through(text: str, steps: list[tuple[str, str]]) -> str:
    for source, target in steps:
        run = run_cli(
            "convert", ARM, "-", "--from", source, "--to", target, "--mujoco", ARM_MJCF,
            stdin=text.encode(),
        )  # fmt: skip
        assert run.code == 0, run.stderr
        text = run.stdout
    return text


def test_a_round_trip_through_every_convention(samples: Path) -> None:
    """Exact through MuJoCo's qpos and named values; through Pinocchio's (cos, sin) of the
    continuous joint, atan2 gives the angle back to within a rounding."""
    text = samples.read_text()
    steps = [("canonical", "mujoco"), ("mujoco", "named"), ("named", "canonical")]
    assert _through(text, steps) == text
    back = _through(text, [("canonical", "pinocchio"), ("pinocchio", "canonical")])
    np.testing.assert_allclose(_read_csv(back)[1], _read_csv(text)[1], rtol=0, atol=4e-16)


def test_pinocchio_q_has_cos_and_sin_for_the_continuous_joint(samples: Path) -> None:
    run = run_cli("convert", ARM, str(samples), "--from", "canonical", "--to", "pinocchio")
    names, q = _read_csv(run.stdout)
    assert names[-2:] == ["wrist_roll.cos", "wrist_roll.sin"]
    x = _read_csv(samples.read_text())[1]
    np.testing.assert_allclose(q[:, -2], np.cos(x[:, -1]), rtol=0, atol=1e-15)


def test_a_file_in_another_convention_is_refused_not_misread(samples: Path) -> None:
    pinocchio = run_cli("convert", ARM, str(samples), "--from", "canonical", "--to", "pinocchio")
    wrong = samples.with_name("q.csv")
    wrong.write_text(pinocchio.stdout)
    run = run_cli("convert", ARM, str(wrong), "--from", "canonical", "--to", "named")
    assert run.code == 2
    line = run.stderr.strip()
    assert line.count("\n") == 0 and line.endswith("[bad-vector-file]")
    assert f"{wrong}:1: column 7 is 'wrist_roll.cos'" in line


def test_named_values_in_any_order_and_partial(tmp_path: Path) -> None:
    path = tmp_path / "state.csv"
    path.write_text("wrist_roll,elbow\n9.5,-1\n")  # a ROS driver's unwrapped angle
    run = run_cli("convert", ARM, str(path), "--from", "named", "--to", "canonical")
    assert run.code == 2 and "no value for joint(s) shoulder_pan" in run.stderr
    assert f"{path}:2:" in run.stderr and run.stderr.strip().endswith("[joint-match]")
    run = run_cli("convert", ARM, str(path), "--from", "named", "--to", "canonical", "--partial")
    assert run.code == 0, run.stderr
    names, x = _read_csv(run.stdout)
    assert x[0, names.index("elbow")] == -1.0
    assert x[0, names.index("wrist_roll")] == pytest.approx(9.5 - 4 * np.pi)


def test_joint_state_json_lines_in_and_out(tmp_path: Path) -> None:
    space = cspace.load(ARM)
    names = list(space.joints)
    lines = [
        json.dumps({"name": names[::-1], "position": list(map(float, row[::-1]))})
        for row in space.sample(3, np.random.default_rng(1))
    ]
    path = tmp_path / "states.jsonl"
    path.write_text("\n".join(lines) + "\n")
    run = run_cli("convert", ARM, str(path), "--from", "named", "--to", "named",
                  "--names", "elbow,wrist_roll")  # fmt: skip
    assert run.code == 0, run.stderr
    out = [json.loads(line) for line in run.stdout.splitlines()]
    assert all(o["name"] == ["elbow", "wrist_roll"] and len(o["position"]) == 2 for o in out)
    first = json.loads(lines[0])
    assert out[0]["position"][0] == first["position"][first["name"].index("elbow")]


def test_velocities_to_pinocchio_need_the_configurations(tmp_path: Path) -> None:
    space = cspace.load(QUADRUPED, "floating")
    rng = np.random.default_rng(2)
    x = space.sample(4, rng, bounds={f"root_joint.{a}": (-1.0, 1.0) for a in "xyz"})
    dx = rng.normal(size=(4, space.dimension))
    (tmp_path / "x.csv").write_text(_csv(space.names, x))
    (tmp_path / "dx.csv").write_text(_csv(space.tangent_names, dx))
    args = ("convert", QUADRUPED, "dx.csv", "--root-joint", "floating", "--velocity",
            "--from", "canonical", "--to", "pinocchio")  # fmt: skip
    missing = run_cli(*args, cwd=tmp_path)
    assert missing.code == 2 and "--at FILE" in missing.stderr
    run = run_cli(*args, "--at", "x.csv", cwd=tmp_path)
    assert run.code == 0, run.stderr
    names, v = _read_csv(run.stdout)
    assert names[:3] == ["root_joint.vx", "root_joint.vy", "root_joint.vz"]
    expected = space.conventions().to_pinocchio_velocity(x, dx)
    np.testing.assert_allclose(v, expected, rtol=0, atol=0)


def test_unwrap_in_chunks_is_the_lift_of_the_whole_file(tmp_path: Path) -> None:
    space = cspace.load(QUADRUPED, "floating")
    conventions = space.conventions()
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 60.0, 10_000)  # crosses the chunks of 4,096 rows
    x = np.tile(space.neutral(), (len(t), 1))
    angle = 3.0 * t + 0.1 * rng.normal(size=len(t))  # turns about z, many times over
    x[:, 3:7] = np.stack([np.cos(angle / 2), 0 * t, 0 * t, np.sin(angle / 2)], axis=-1)
    x = space.canonicalize(x)
    (tmp_path / "walk.csv").write_text(_csv(space.names, x))
    run = run_cli("unwrap", QUADRUPED, "walk.csv", "--root-joint", "floating", cwd=tmp_path)
    assert run.code == 0, run.stderr
    lift = _read_csv(run.stdout)[1]
    np.testing.assert_allclose(lift, conventions.unwrap(x), rtol=0, atol=1e-12)
    dots = np.sum(lift[1:, 3:7] * lift[:-1, 3:7], axis=-1)
    assert (dots > 0).all()
    (tmp_path / "lift.csv").write_text(run.stdout)
    back = run_cli("unwrap", QUADRUPED, "lift.csv", "--root-joint", "floating", "--inverse",
                   cwd=tmp_path)  # fmt: skip
    np.testing.assert_allclose(_read_csv(back.stdout)[1], x, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("body", "problem"),
    [
        ("1,2,3,4,5,6\n", "has 6 values, the header 7"),
        ("0,0,0,0,0,0,nan\n", "value 7 is not finite: 'nan'"),
        ("0,0,0,0,0,0,1e999\n", "value 7 is not finite: '1e999'"),
        ("0,0,0,0,0,0,x\n", "value 7 is not a number: 'x'"),
        ("0,0,0,9,0,0,0\n", "coordinate 'elbow'"),  # out of nothing: canonical form is fine
    ],
)
def test_bad_rows_name_the_file_and_line(tmp_path: Path, body: str, problem: str) -> None:
    space = cspace.load(ARM)
    path = tmp_path / "bad.csv"
    path.write_text(",".join(space.names) + "\n" + "0,0,0,0,0,0,0\n" + body)
    run = run_cli("convert", ARM, str(path), "--from", "canonical", "--to", "pinocchio")
    if problem.startswith("coordinate"):  # not a limit check: convert keeps the value
        assert run.code == 0
        return
    assert run.code == 2
    assert f"{path}:3: {problem}" in run.stderr and run.stderr.count("\n") == 1


def test_hostile_inputs_are_refused_with_one_line(tmp_path: Path) -> None:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    run = run_cli("unwrap", ARM, str(fifo))  # the default timeout: a hang guard
    assert run.code == 2 and "not a regular file" in run.stderr
    long = tmp_path / "long.csv"
    long.write_bytes(b"a," * (1 << 20) + b"\n")
    run = run_cli("unwrap", ARM, str(long))
    assert run.code == 2 and "line is longer than 1,048,576 bytes" in run.stderr
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    assert "is empty" in run_cli("unwrap", ARM, str(empty)).stderr
    bidi = tmp_path / "bidi.csv"
    bidi.write_text("shoulder_pan\u202e,x\n")
    run = run_cli("unwrap", ARM, str(bidi))
    assert run.code == 2 and "\u202e" not in run.stderr and "\\u202e" in run.stderr


def test_joint_state_objects_are_read_only_as_named_values() -> None:
    line = json.dumps({"name": ["wrist_roll", "shoulder_pan"], "position": [1.0, 0.5]})
    run = run_cli("convert", ARM, "-", "--from", "canonical", "--to", "pinocchio",
                  stdin=(line + "\n").encode())  # fmt: skip
    assert run.code == 2 and "a JointState" in run.stderr
    assert run_cli("unwrap", ARM, "-", stdin=(line + "\n").encode()).code == 2


def test_names_are_checked_before_any_row(tmp_path: Path) -> None:
    header_only = tmp_path / "h.csv"
    header_only.write_text(",".join(cspace.load(ARM).names) + "\n")
    run = run_cli("convert", ARM, str(header_only), "--from", "canonical", "--to", "named",
                  "--names", "bogus")  # fmt: skip
    assert run.code == 2 and run.stdout == "" and "--names: joint 'bogus' is unknown" in run.stderr
    run = run_cli("convert", ARM, "-", "--from", "named", "--to", "canonical",
                  stdin=b"bogus,nonsense\n")  # fmt: skip
    assert run.code == 2 and run.stdout == "" and "joint 'bogus' is unknown" in run.stderr


def test_lines_are_the_files_own_and_csv_errors_are_one_line(tmp_path: Path) -> None:
    names = ",".join(cspace.load(ARM).names)
    path = tmp_path / "gaps.csv"
    path.write_text(names + "\n\n0,0,0,0,0,0,0\n\n\n0,0,0,0,0,0,x\n")
    run = run_cli("unwrap", ARM, str(path))
    assert run.code == 2 and f"{path}:6: value 7 is not a number" in run.stderr
    path.write_text(names + "\n0,0,0,0,0,0,3.0\r5\n")  # a CR inside an unquoted field
    run = run_cli("unwrap", ARM, str(path))
    assert run.code == 2 and f"{path}:2: is not a CSV row" in run.stderr
    assert "internal error" not in run.stderr
    path.write_text(names + "\n" + "0," * 6 + "0." + "0" * 200_000 + "\n")  # a long field
    assert run_cli("unwrap", ARM, str(path)).code == 0


def test_at_file_errors_name_the_at_file(tmp_path: Path) -> None:
    space = cspace.load(QUADRUPED, "floating")
    x = np.tile(space.neutral(), (3, 1))
    x[2, 3:7] = 0.0  # not a rotation
    (tmp_path / "x.csv").write_text(_csv(space.names, x))
    (tmp_path / "dx.csv").write_text(_csv(space.tangent_names, np.zeros((2, space.dimension))))
    args = ("convert", QUADRUPED, "dx.csv", "--root-joint", "floating", "--velocity",
            "--from", "canonical", "--to", "pinocchio", "--at", "x.csv")  # fmt: skip
    run = run_cli(*args, cwd=tmp_path)
    assert run.code == 2 and "x.csv:4: quaternion" in run.stderr  # line 4 of x.csv
    (tmp_path / "x.csv").write_text(_csv(space.names, x[:2].tolist() * 2))
    run = run_cli(*args, cwd=tmp_path)
    assert run.code == 2 and "x.csv: has more configurations than dx.csv" in run.stderr
    run = run_cli(*args[:-1], "-", cwd=tmp_path, stdin=b"")
    assert run.code == 2  # FILE from a file, --at from stdin: allowed, but stdin is empty
    run = run_cli(*args[:2], "-", *args[3:-1], "-", cwd=tmp_path, stdin=b"")
    assert run.code == 2 and "FILE and --at cannot both be standard input" in run.stderr


@pytest.mark.parametrize(
    "extra",
    [["--names", "elbow"], ["--input-names", "elbow"], ["--partial"], ["--at", "x.csv"]],
    ids=lambda e: e[0],
)
def test_options_that_do_not_apply_are_refused(samples: Path, extra: list[str]) -> None:
    run = run_cli("convert", ARM, str(samples), "--from", "canonical", "--to", "pinocchio",
                  *extra)  # fmt: skip
    assert run.code == 2 and f"{extra[0]} does not apply" in run.stderr


def test_an_mjcf_robot_with_a_root_joint_converts_except_to_mujoco(tmp_path: Path) -> None:
    space = cspace.load(ARM_MJCF, "planar")
    (tmp_path / "x.csv").write_text(_csv(space.names, [space.neutral()]))
    base = ("convert", ARM_MJCF, "x.csv", "--root-joint", "planar", "--from", "canonical")
    assert run_cli(*base, "--to", "pinocchio", cwd=tmp_path).code == 0
    run = run_cli(*base, "--to", "mujoco", cwd=tmp_path)
    assert run.code == 2 and "has no joint 'root_joint'" in run.stderr
