"""`cspace sample`, `cspace distance` and `cspace interpolate`, run as a user runs them."""

from __future__ import annotations

import csv
import io
import json
import math

import pytest

import cspace

from conftest import HASH_SEED, ROBOTS, run_cli

ARM = str(ROBOTS / "arm7.urdf")
QUAD = str(ROBOTS / "quadrotor_floating.urdf")
ARM_JOINTS = [
    "shoulder_pan",
    "shoulder_lift",
    "upper_arm_roll",
    "elbow",
    "forearm_roll",
    "wrist_pitch",
]


def arm(**values: float) -> str:
    return json.dumps({**dict.fromkeys(ARM_JOINTS, 0.0), "wrist_roll": 0.0, **values})


def test_sample_csv_has_a_header_and_is_reproducible() -> None:
    run = run_cli("sample", ARM, "-n", "5", "--seed", "3", "--format", "csv")
    assert run.code == 0, run.stderr
    rows = list(csv.reader(io.StringIO(run.stdout)))
    space = cspace.load(ARM)
    assert rows[0] == list(space.names)
    values = [[float(v) for v in row] for row in rows[1:]]
    assert len(values) == 5
    assert all(space.contains(v) for v in values)
    again = run_cli("sample", ARM, "-n", "5", "--seed", "3", "--format", "csv", env=HASH_SEED[1])
    assert again.stdout == run.stdout  # reproducible by another interpreter too
    assert run_cli("sample", ARM, "-n", "5", "--seed", "4", "--format", "csv").stdout != run.stdout


def test_sample_json_of_a_floating_robot_needs_bounds_for_its_position() -> None:
    run = run_cli("sample", QUAD, "-n", "2")
    assert run.code == 2
    assert run.stderr.count("\n") == 1
    assert "body_free.x" in run.stderr and "--bounds" in run.stderr
    bounds = ["--bounds", "body_free.x=-1:1", "--bounds", "body_free.y=-1:1"]
    run = run_cli("sample", QUAD, "-n", "3", *bounds, "--bounds", "body_free.z=0:2")
    assert run.code == 0, run.stderr
    doc = json.loads(run.stdout)
    assert doc["coordinates"][3:7] == [
        "body_free.qw",
        "body_free.qx",
        "body_free.qy",
        "body_free.qz",
    ]
    for row in doc["configurations"]:
        assert -1 <= row[0] <= 1 and 0 <= row[2] <= 2
        assert sum(v * v for v in row[3:7]) == pytest.approx(1.0)
        assert row[3] >= 0  # upper hemisphere


def test_distance_goes_the_short_way_round() -> None:
    run = run_cli("distance", ARM, arm(wrist_roll=3.1), arm(wrist_roll=-3.1))
    assert run.code == 0, run.stderr
    assert float(run.stdout) == pytest.approx(2 * math.pi - 6.2)
    weighted = run_cli(
        "distance", ARM, arm(wrist_roll=3.1), arm(wrist_roll=-3.1), "--weight", "wrist_roll=2"
    )
    assert float(weighted.stdout) == pytest.approx(2 * (2 * math.pi - 6.2))


def test_distance_treats_h_and_minus_h_as_one_rotation(tmp_path) -> None:
    a = tmp_path / "a.json"
    a.write_text(json.dumps({"body_free": [0, 0, 0, 0, 0, 0, 1]}))
    b = json.dumps({"body_free": [0, 0, 0, 0, 0, 0, -1]})
    run = run_cli("distance", QUAD, f"@{a}", b, "--partial", "--format", "json")
    assert run.code == 0, run.stderr
    assert json.loads(run.stdout)["distance"] == 0.0


def test_interpolate_crosses_pi_and_ends_exactly_at_the_inputs() -> None:
    run = run_cli(
        "interpolate",
        ARM,
        arm(wrist_roll=3.0),
        arm(wrist_roll=-3.0),
        "--steps",
        "5",
        "--format",
        "csv",
    )
    assert run.code == 0, run.stderr
    rows = list(csv.reader(io.StringIO(run.stdout)))
    roll = [float(r[-1]) for r in rows[1:]]
    assert len(roll) == 5
    assert roll[0] == 3.0 and roll[-1] == -3.0
    assert all(abs(r) >= 3.0 for r in roll)  # through pi ~ -pi, never through 0


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("distance", ARM, '{"shoulder_pan": 0}', "{}"), "no value for joint"),
        (("distance", ARM, arm(shoulder_pan=9.0), arm()), "outside its limits"),
        (("distance", ARM, '{"nope": 1}', "{}", "--partial"), "valid: shoulder_pan"),
        (("distance", ARM, "{not json", "{}"), "not valid JSON"),
        (("distance", ARM, arm(elbow=[1, 2]), arm()), "needs a number"),
        (("distance", QUAD, '{"body_free": [0,0,0,2,0,0,0]}', "{}", "--partial"), "norm"),
        (("interpolate", ARM, arm(), arm(), "--steps", "1"), "--steps"),
        (("sample", ARM, "-n", "-1"), "-n"),
        (("sample", QUAD, "--bounds", "body_free.x=1"), "LOWER:UPPER"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args: tuple[str, ...], needle: str) -> None:
    run = run_cli(*args)
    assert run.code == 2
    assert run.stdout == ""
    assert run.stderr.startswith("cspace: error: ") and run.stderr.count("\n") == 1
    assert needle in run.stderr
