"""Every URDF teaching case in robots/: its normal form, its joints' kinds, golden JSON.

The expectations are written from each robot's physical meaning (see the comment at the
top of each file), not copied from the tool's output. The golden JSON files pin the
whole report byte for byte, so that any change in output shows up in review; rewrite
them with `CSPACE_UPDATE_GOLDEN=1 .venv/bin/pytest tests/test_robots.py` and read the diff.
"""

from __future__ import annotations

import itertools
import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import jsonschema
import pytest

import cspace
from cspace._schema import report_schema

from conftest import HASH_SEED, REPO, ROBOTS, run_cli

GOLDEN = Path(__file__).parent / "golden"


@dataclass(frozen=True)
class Case:
    file: str
    notation: str
    kinds: dict[str, str]
    nq: int
    nv: int
    root_joint: str | None = None
    codes: frozenset[str] = field(default_factory=frozenset)

    @property
    def id(self) -> str:
        stem = Path(self.file).stem
        return stem if self.root_joint is None else f"{stem}.{self.root_joint}"


REV, CONT, PRIS, FIX, MIM = "revolute", "continuous", "prismatic", "fixed", "mimic"
QUAD_JOINTS = {f"{leg}_{j}": REV for leg in ("lf", "lh", "rf", "rh") for j in ("hip_pitch", "knee")}

CASES = [
    Case(
        "arm7.urdf",
        "R^6 × S^1",
        {
            "shoulder_pan": REV,
            "shoulder_lift": REV,
            "upper_arm_roll": REV,
            "elbow": REV,
            "forearm_roll": REV,
            "wrist_pitch": REV,
            "wrist_roll": CONT,
            "flange_mount": FIX,
            "tool_mount": FIX,
        },
        nq=8,
        nv=7,
    ),
    Case(
        "gripper_mimic.urdf",
        "R^1",
        {"palm_mount": FIX, "left_finger_joint": PRIS, "right_finger_joint": MIM},
        nq=1,
        nv=1,
    ),
    Case(
        "mobile_manipulator.urdf",
        "R^4 × S^1",
        {"base_planar": "planar", "arm_joint_1": REV, "arm_joint_2": REV},
        nq=6,
        nv=5,
    ),
    Case(
        "quadrotor_floating.urdf",
        "R^3 × T^4 × RP^3",
        {
            "body_free": "floating",
            "prop_fl_spin": CONT,
            "prop_fr_spin": CONT,
            "prop_rl_spin": CONT,
            "prop_rr_spin": CONT,
        },
        nq=15,
        nv=10,
    ),
    Case(
        "turntable_multiturn.urdf",
        "R^2",
        {"turntable": REV, "tilt": REV},
        nq=2,
        nv=2,
        codes=frozenset({"multi-turn"}),
    ),
    Case(
        "sensor_head_fixed.urdf",
        "point",
        {"camera_mount": FIX, "imu_mount": FIX, "lidar_mount": FIX},
        nq=0,
        nv=0,
    ),
    Case(
        "quadruped_nobase.urdf",
        "R^8",
        QUAD_JOINTS,
        nq=8,
        nv=8,
        codes=frozenset({"root-joint-suggested"}),  # four legs on a trunk bolted down
    ),
    Case(
        "quadruped_nobase.urdf",
        "R^11 × RP^3",
        {"root_joint": "floating", **QUAD_JOINTS},
        nq=15,
        nv=14,
        root_joint="floating",
        codes=frozenset({"root-joint-added"}),
    ),
    Case(
        "diffdrive_nobase.urdf",
        "T^3",
        {
            "caster_swivel": CONT,
            "caster_axle": FIX,
            "left_wheel_joint": CONT,
            "right_wheel_joint": CONT,
        },
        nq=6,
        nv=3,
        codes=frozenset({"root-joint-suggested"}),  # wheels under a chassis bolted down
    ),
    Case(
        "diffdrive_nobase.urdf",
        "R^2 × T^4",
        {
            "root_joint": "planar",
            "caster_swivel": CONT,
            "caster_axle": FIX,
            "left_wheel_joint": CONT,
            "right_wheel_joint": CONT,
        },
        nq=10,
        nv=6,
        root_joint="planar",
        codes=frozenset({"root-joint-added"}),
    ),
]


def _args(case: Case) -> list[str]:
    args = ["inspect", f"robots/{case.file}", "--format", "json"]
    return args if case.root_joint is None else [*args, "--root-joint", case.root_joint]


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.id)
def test_library_report(case: Case) -> None:
    report = cspace.inspect(str(ROBOTS / case.file), root_joint=case.root_joint)
    assert report.manifold.notation == case.notation
    assert {j.name: j.kind.value for j in report.joints} == case.kinds
    assert (report.nq, report.nv) == (case.nq, case.nv)
    assert {d.code for d in report.diagnostics} == case.codes
    # Joint spaces multiply to the whole space, and coordinates tile Pinocchio's q and v.
    assert cspace.NormalForm.product([j.space for j in report.joints]) == report.manifold
    q_slots = sorted((j.q_index, j.nq) for j in report.joints if j.q_index is not None)
    assert sum(n for _, n in q_slots) == report.nq
    assert all(a + n == b for (a, n), (b, _) in itertools.pairwise(q_slots))


VERSION = f'"version": "{cspace.__version__}"'
"""The tool's version in a report: goldens hold ``"version": "*"`` instead, so that a new
version does not rewrite every golden."""


def _assert_golden(golden: Path, output: str) -> None:
    unpinned = output.replace(VERSION, '"version": "*"', 1)
    if os.environ.get("CSPACE_UPDATE_GOLDEN"):
        golden.write_text(unpinned, encoding="utf-8")
    assert unpinned == golden.read_text(encoding="utf-8"), f"{golden.name} differs"


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.id)
def test_cli_json_matches_golden_and_schema(case: Case) -> None:
    run = run_cli(*_args(case))
    assert run.code == 0, run.stderr
    assert run.stderr == ""
    document = json.loads(run.stdout)
    jsonschema.Draft202012Validator(report_schema()).validate(document)
    assert document["manifold"]["notation"] == case.notation
    _assert_golden(GOLDEN / f"{case.id}.json", run.stdout)


OTHER_FORMATS = {
    # golden file stem: the command's arguments (their kinds are tested in test_formats.py)
    "mjcf_every_joint": ["robots/mjcf_every_joint.xml"],
    "mjcf_radian_autolimits": ["robots/mjcf_radian_autolimits.xml"],
    "mjcf_equality": ["robots/mjcf_equality.xml"],
    "mjcf_include.scene": ["robots/mjcf_include/scene.xml"],
    "mjcf_top_level_bodies": ["robots/mjcf_top_level_bodies.xml"],
    "mjcf_unnamed_joints": ["robots/mjcf_unnamed_joints.xml"],
    "mjcf_mujocoinclude.scene": ["robots/mjcf_mujocoinclude/scene.xml"],
    "mjcf_frame_childclass": ["robots/mjcf_frame_childclass.xml"],
    "mjcf_replicate": ["robots/mjcf_replicate.xml"],
    "mjcf_attach.arm": ["robots/mjcf_attach/arm.xml"],
    "mjcf_balls": ["robots/mjcf_balls.xml"],
    "mjcf_scene_objects": ["robots/mjcf_scene_objects.xml"],
    "mjcf_static_scene": ["robots/mjcf_static_scene.xml"],
    "sdf_every_joint": ["robots/sdf_every_joint.sdf"],
    "xacro_demo.arm": ["robots/xacro_demo/urdf/arm.urdf.xacro"],
    "xacro_demo.arm.continuous": [
        "robots/xacro_demo/urdf/arm.urdf.xacro",
        "--arg",
        "wrist:=continuous",
    ],
}


@pytest.mark.parametrize("stem", sorted(OTHER_FORMATS))
def test_other_formats_match_golden_and_schema(stem: str) -> None:
    run = run_cli("inspect", *OTHER_FORMATS[stem], "--format", "json")
    assert run.code == 0, run.stderr
    jsonschema.Draft202012Validator(report_schema()).validate(json.loads(run.stdout))
    _assert_golden(GOLDEN / f"{stem}.json", run.stdout)


def test_every_robot_file_has_a_golden_report() -> None:
    stems = {Path(args[0]).name for args in OTHER_FORMATS.values()}
    robot_files = {p.name for p in ROBOTS.rglob("*") if p.suffix in (".xml", ".sdf", ".xacro")}
    # Included MJCF parts and xacro macro files are covered through the files using them.
    assert robot_files - stems == {
        "gripper.xml",
        "gripper.xacro",
        "macros.xacro",
        "package.xml",
    }


def test_every_urdf_in_robots_has_a_case() -> None:
    covered = {c.file for c in CASES}
    assert {p.name for p in ROBOTS.glob("*.urdf")} == covered


def test_cases_cover_every_urdf_joint_kind_and_both_root_joints() -> None:
    kinds = {kind for case in CASES for kind in case.kinds.values()}
    assert {REV, CONT, PRIS, "planar", "floating", FIX, MIM} <= kinds
    assert {c.root_joint for c in CASES} == {None, "floating", "planar"}
    assert any(c.notation == "point" for c in CASES)
    assert any("multi-turn" in c.codes for c in CASES)


def test_output_is_deterministic() -> None:
    # two interpreters whose hash seeds differ, as two users' runs' do
    first = run_cli("inspect", "robots/arm7.urdf", "--format", "json", env=HASH_SEED[0])
    second = run_cli("inspect", "robots/arm7.urdf", "--format", "json", env=HASH_SEED[1])
    assert first.stdout == second.stdout
    assert REPO.joinpath("robots/arm7.urdf").exists()
