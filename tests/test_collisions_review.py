"""``cspace collisions`` against what a hostile file, a careless caller or a dying process
does to it: each test is a defect found by review, held to what the command must do.

Each test loads real files written here; none mocks Pinocchio, coal or MuJoCo.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_collisions_hostile import box_stl, heavy_obj

import cspace
from cspace.errors import ArgumentError, RobotFileError

from conftest import (
    HANG_SECONDS,
    PEAK_MIB,
    SECONDS,
    assert_bounded_error,
    command_env,
    cspace_command,
    measured,
    run_cli,
)

pytestmark = pytest.mark.bounded

SPHERE = '<collision><geometry><sphere radius="0.001"/></geometry></collision>'


def test_a_link_of_too_many_shapes_is_refused_before_it_is_built(tmp_path: Path) -> None:
    """Pinocchio's GeometryModel costs the cube of its objects to build (2,000 spheres 6 s,
    3,000 21 s): 50,000 <collision> elements, which a robot file may hold, took a day."""
    robot = tmp_path / "spheres.urdf"
    robot.write_text(f'<robot name="spheres"><link name="a">{SPHERE * 2_001}</link></robot>')
    stderr = assert_bounded_error(
        measured("collisions", str(robot), "-n", "1", cwd=tmp_path), "too-many-elements"
    )
    assert "2,001 collision shapes, more than the 2,000" in stderr


def test_an_mjcf_model_of_too_many_collision_geoms_is_refused_before_it_is_built(
    tmp_path: Path,
) -> None:
    geom = '<geom type="sphere" size="0.001" pos="{} 0 0"/>'
    geoms = "".join(geom.format(0.003 * k) for k in range(2_001))
    robot = tmp_path / "spheres.xml"
    robot.write_text(
        '<mujoco><worldbody><body name="a"><joint type="hinge" range="-1 1"/>'
        f"{geoms}</body></worldbody></mujoco>"
    )
    stderr = assert_bounded_error(
        measured("collisions", str(robot), "-n", "1", cwd=tmp_path), "too-many-elements"
    )
    assert "2,001 collision shapes, more than the 2,000" in stderr


ARM = Path(__file__).parent.parent / "docs/examples/folding_arm.urdf"


def test_allow_dirs_given_as_one_string_is_refused_not_read_as_its_characters(
    tmp_path: Path,
) -> None:
    """``allow_dirs="/some/folder"`` was the folders '/', 's', 'o', ...: '/' allowed every
    file of the machine as a mesh. A mesh out of the project stays unread."""
    outside, project = tmp_path / "outside", tmp_path / "project"
    outside.mkdir()
    project.mkdir()
    (outside / "fore.stl").write_bytes(box_stl(0.05, 0.05, 0.4))
    robot = project / "arm.urdf"
    robot.write_text(
        ARM.read_text().replace(
            '<box size="0.05 0.05 0.4"/>', f'<mesh filename="{outside / "fore.stl"}"/>'
        )
    )
    unread = cspace.collisions(robot, samples=10)
    assert unread.links == ("base", "upper")  # fore's mesh is out of the project
    for given in (str(tmp_path / "elsewhere"), tmp_path / "elsewhere"):
        with pytest.raises(ArgumentError, match="allow_dirs must be a list of folders"):
            cspace.collisions(robot, samples=10, allow_dirs=given)  # type: ignore[arg-type]
    allowed = cspace.collisions(robot, samples=10, allow_dirs=[outside])
    assert allowed.links == ("base", "upper", "fore")


def _usd_arm(path: Path, names: list[str]) -> Path:
    """An OpenUSD chain of cubes, one body a name (its displayName), revolute joints."""
    pytest.importorskip("pxr")
    from pxr import Gf, Usd, UsdGeom, UsdPhysics

    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, "/r").GetPrim())
    for k, name in enumerate(names):
        body = UsdGeom.Xform.Define(stage, f"/r/b{k}")
        body.AddTranslateOp().Set(Gf.Vec3d(0.3 * k, 0, 0))
        UsdPhysics.RigidBodyAPI.Apply(body.GetPrim())
        body.GetPrim().SetMetadata("displayName", name)
        cube = UsdGeom.Cube.Define(stage, f"/r/b{k}/box")
        cube.CreateSizeAttr(0.35)
        UsdPhysics.CollisionAPI.Apply(cube.GetPrim())
        if k == 0:
            UsdPhysics.FixedJoint.Define(stage, "/r/mount").CreateBody1Rel().SetTargets(["/r/b0"])
            continue
        joint = UsdPhysics.RevoluteJoint.Define(stage, f"/r/j{k}")
        joint.CreateBody0Rel().SetTargets([f"/r/b{k - 1}"])
        joint.CreateBody1Rel().SetTargets([f"/r/b{k}"])
        joint.CreateAxisAttr("Z")
        joint.CreateLocalPos0Attr(Gf.Vec3f(0.15, 0, 0))
        joint.CreateLocalPos1Attr(Gf.Vec3f(-0.15, 0, 0))
        joint.CreateLowerLimitAttr(-170.0)
        joint.CreateUpperLimitAttr(170.0)
    stage.GetRootLayer().Save()
    return path


def test_an_srdf_of_names_xml_cannot_hold_is_one_line_not_an_internal_error(
    tmp_path: Path,
) -> None:
    """An OpenUSD body's displayName may hold any character: --write-srdf failed with
    'internal error: ValueError' on a control character."""
    stage = _usd_arm(tmp_path / "arm.usda", ["base", "esc\x1b[2J", "tip"])
    written = tmp_path / "arm.srdf"
    run = run_cli("collisions", str(stage), "-n", "20", "--write-srdf", str(written))
    assert run.code == 2 and run.stdout == "", run
    assert run.stderr.count("\n") == 1 and "internal error" not in run.stderr, run.stderr
    assert run.stderr.rstrip().endswith("[bad-output]"), run.stderr
    assert "holds a character XML cannot hold" in run.stderr and "\x1b" not in run.stderr
    assert not written.exists()


ARM_SRDF = ARM.with_suffix(".srdf")


def _arm_folder(folder: Path) -> tuple[Path, Path]:
    robot, srdf = folder / "arm.urdf", folder / "arm.srdf"
    robot.write_text(ARM.read_text())
    srdf.write_text(ARM_SRDF.read_text())
    return robot, srdf


def test_write_srdf_to_standard_output_is_refused_not_a_file_named_dash(tmp_path: Path) -> None:
    """``--write-srdf -`` wrote a file named '-' where the run stood, while cspace's own
    message for a FIFO says to give - for standard output (which holds the report)."""
    robot, _ = _arm_folder(tmp_path)
    run = run_cli("collisions", str(robot), "-n", "20", "--write-srdf", "-", cwd=tmp_path)
    assert run.code == 2 and run.stdout == "", run
    assert run.stderr.count("\n") == 1 and run.stderr.rstrip().endswith("[bad-output]"), run
    assert "standard output holds the report" in run.stderr
    assert not (tmp_path / "-").exists()
    named = run_cli("collisions", str(robot), "-n", "20", "--write-srdf", "./-", cwd=tmp_path)
    assert named.code == 0 and (tmp_path / "-").read_text().startswith("<?xml"), named


def test_write_srdf_over_the_robot_or_the_srdf_it_reads_is_refused(tmp_path: Path) -> None:
    """--write-srdf over the robot file replaced the URDF by an SRDF, and over the SRDF
    --srdf read (MoveIt's, with its groups, end effectors and virtual joints) replaced it
    by <disable_collisions> alone, exit 0 both."""
    robot, srdf = _arm_folder(tmp_path)
    before = {robot: robot.read_text(), srdf: srdf.read_text()}
    (tmp_path / "sub").mkdir()
    for target, more in [
        (robot, ()),
        (tmp_path / "sub" / ".." / "arm.urdf", ()),
        (srdf, ("--srdf", str(srdf))),
        (srdf, ("--srdf", "auto")),  # found beside the robot
    ]:
        run = run_cli("collisions", str(robot), "-n", "20", *more, "--write-srdf", str(target))
        assert run.code == 2 and run.stdout == "", (target, more, run)
        assert run.stderr.rstrip().endswith("[bad-output]"), run.stderr
        assert "a file this run reads" in run.stderr and run.stderr.count("\n") == 1
        assert {path: path.read_text() for path in before} == before
    elsewhere = tmp_path / "suggested.srdf"
    run = run_cli(
        "collisions", str(robot), "-n", "20", "--srdf", "auto", "--write-srdf", str(elsewhere)
    )
    assert run.code == 0 and "<disable_collisions" in elsewhere.read_text(), run


def test_a_worker_not_forked_reads_what_the_caller_read_or_the_run_fails(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """With a second thread alive (NumPy's OpenBLAS, unless limited), the pool starts its
    workers from a fork server: each reads the robot again. A forearm grown meanwhile
    (the caller's read done, the workers' not yet) made a report of the caller's file
    (its sha256, its default pose) with the workers' counts: 'always' for a pair the
    file's forearm meets in 1% of the samples."""
    import threading

    from cspace.space._collisions import run as running

    robot = tmp_path / "arm.urdf"
    text = ARM.read_text()
    robot.write_text(text)
    read = running.prepare

    def read_then_changed(path: object, options: object) -> object:
        prepared = read(path, options)  # type: ignore[arg-type]
        robot.write_text(text.replace('<box size="0.05 0.05 0.4"/>', '<box size="2 2 2"/>'))
        return prepared

    monkeypatch.setattr(running, "prepare", read_then_changed)
    stop = threading.Event()
    other = threading.Thread(target=stop.wait)  # not a one-thread process: no fork
    other.start()
    try:
        with pytest.raises(RobotFileError, match="changed while cspace collisions read them"):
            cspace.collisions(robot, samples=8_000, jobs=2)
    finally:
        stop.set()
        other.join()
    monkeypatch.undo()
    robot.write_text(text)  # unchanged files: the same report from a fork server
    other = threading.Thread(target=stop.wait)
    stop.clear()
    other.start()
    try:
        served = cspace.collisions(robot, samples=8_000, jobs=2)
    finally:
        stop.set()
        other.join()
    assert served == cspace.collisions(robot, samples=8_000, jobs=1)


def _pool_workers(pid: int) -> list[int]:
    """The processes ``pid`` forked as it is (its pool's workers), not its confined
    children (a mesh parser, OpenUSD's), which run other programs."""
    me = Path(f"/proc/{pid}/cmdline").read_bytes()
    found = []
    for child in Path(f"/proc/{pid}/task/{pid}/children").read_text().split():
        try:
            if Path(f"/proc/{child}/cmdline").read_bytes() == me:
                found.append(int(child))
        except OSError:  # ended meanwhile
            continue
    return found


def _sampling(*args: str) -> tuple[subprocess.Popen[bytes], list[int]]:
    """``cspace collisions ARGS`` started in a session of its own, once its workers run."""
    process = subprocess.Popen(
        [*cspace_command(), "collisions", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=command_env(),
        start_new_session=True,
    )
    workers: list[int] = []
    for _ in range(600):  # a hang guard: the robot is read in about a second
        workers = _pool_workers(process.pid) if process.poll() is None else []
        if len(workers) == 2 or process.poll() is not None:
            break
        time.sleep(0.1)
    assert len(workers) == 2, process.communicate()
    return process, workers


def test_a_worker_killed_mid_run_is_one_line_not_an_internal_error() -> None:
    """A worker killed (the OOM killer, a crash) was 'internal error: BrokenProcessPool'."""
    process, workers = _sampling("erd:panda", "-n", "200000", "-j", "2")
    os.kill(workers[0], signal.SIGKILL)
    out, err = process.communicate(timeout=HANG_SECONDS)
    assert process.returncode == 2 and out == b"", (process.returncode, err)
    stderr = err.decode()
    assert stderr.count("\n") == 1 and stderr.rstrip().endswith("[worker-died]"), stderr
    assert "internal error" not in stderr
    assert not any(Path(f"/proc/{pid}").exists() for pid in workers)


def needles_stl(count: int, along: int, seed: int, odd: int) -> bytes:
    """A binary STL of ``count`` thin triangles across the unit cube along axis ``along``
    (x: 0, y: 1), one a plane z = (2k + odd) / 2 count, in a random order: two such meshes
    along x and y never touch, yet every bounding volume of one overlaps the other's, so
    coal tests about every pair of their triangles (3,000 each: about a second)."""
    rng = np.random.default_rng(seed)
    z = (2 * rng.permutation(count) + odd) / (2.0 * count)
    c = rng.random(count)
    corners = np.zeros((count, 3, 3), dtype="<f4")
    corners[:, :, 2] = z[:, None]
    across = 1 - along
    corners[:, 0, across] = c
    corners[:, 1, across], corners[:, 1, along] = c, 1.0
    corners[:, 2, across], corners[:, 2, along] = c + 1e-4, 0.5
    records = np.zeros(count, dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    records["v"] = corners
    return b"\0" * 80 + np.uint32(count).tobytes() + records.tobytes()


def needles_robot(folder: Path, count: int = 3_000) -> Path:
    """Two links of needle meshes that overlap (a link between them, far off, keeps
    them from being adjacent), their joints almost still."""
    (folder / "a.stl").write_bytes(needles_stl(count, 0, 1, 0))
    (folder / "b.stl").write_bytes(needles_stl(count, 1, 2, 1))
    limit = '<limit lower="-0.001" upper="0.001" effort="1" velocity="1"/>'
    robot = folder / "needles.urdf"
    robot.write_text(
        '<robot name="needles">'
        '<link name="a"><collision><geometry><mesh filename="a.stl"/></geometry></collision>'
        "</link>"
        '<link name="mid"><collision><origin xyz="5 5 5"/><geometry><box size="0.01 0.01 0.01"/>'
        "</geometry></collision></link>"
        '<link name="b"><collision><geometry><mesh filename="b.stl"/></geometry></collision>'
        "</link>"
        f'<joint name="j1" type="revolute"><parent link="a"/><child link="mid"/>{limit}</joint>'
        f'<joint name="j2" type="revolute"><parent link="mid"/><child link="b"/>{limit}</joint>'
        "</robot>"
    )
    return robot


@pytest.mark.xfail(
    strict=False,
    reason="known defect: in the full suite's run (pytest -n 2, make test) the command has "
    "been seen not to end within the guard after Ctrl-C (3 of 3 fresh-clone runs), while "
    "alone, and in a 12-try reproducer with the pool workers dying with their caller, it "
    "ends in about a second; not yet understood",
)
def test_ctrl_c_during_a_parallel_run_ends_it_now_not_after_its_workers_parts(
    tmp_path: Path,
) -> None:
    """Workers ignore Ctrl-C and the pool's shutdown waited for the parts they ran: 1,000
    samples of a robot whose checks take a second each (minutes of a heavy robot) went on
    after Ctrl-C. The guard is a hang guard: the run ends in about a second now."""
    robot = needles_robot(tmp_path)
    process, workers = _sampling(str(robot), "-n", "8000", "-j", "2")
    try:
        os.killpg(process.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the whole group
        out, err = process.communicate(timeout=20)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 130 and out == b"" and err == b"", (process.returncode, err)
    assert not any(Path(f"/proc/{pid}").exists() for pid in workers)


def test_a_mesh_named_by_many_links_is_built_once(tmp_path: Path) -> None:
    """Each shape built its own BVH of its mesh (about 575 bytes a triangle): a 3 MB OBJ
    of 100,000 triangles named by 20 links took 1.2 GB; 2,000 shapes of a 32 MiB mesh,
    hundreds of GB."""
    rng = np.random.default_rng(0)
    lines = [f"v {x:.4f} {y:.4f} {z:.4f}" for x, y, z in rng.random((50_000, 3)) * 0.1]
    lines += [f"f {a} {b} {c}" for a, b, c in rng.integers(1, 50_001, (100_000, 3))]
    (tmp_path / "m.obj").write_text("\n".join(lines) + "\n")
    mesh = '<collision><geometry><mesh filename="m.obj"/></geometry></collision>'
    links = "".join(f'<link name="l{k}">{mesh}</link>' for k in range(20))
    joints = "".join(
        f'<joint name="j{k}" type="fixed"><parent link="l0"/><child link="l{k}"/>'
        f'<origin xyz="{k} 0 0"/></joint>'
        for k in range(1, 20)
    )
    robot = tmp_path / "many.urdf"
    robot.write_text(f'<robot name="many">{links}{joints}</robot>')
    result = measured("collisions", str(robot), "-n", "10", cwd=tmp_path)
    assert result.run.code == 0 and "links with collision shapes: 20" in result.run.stdout, result
    assert result.peak_mib < PEAK_MIB and result.cpu_seconds < SECONDS, result


def test_the_mesh_parsers_halves_stop_at_the_childrens_bound(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A child stopped is run again on halves, 'at most 64 children and 120 s': the
    bounds were looked at only when a child was stopped, so each half left on the way
    down still started a child once they were spent (here 5 of a bound of 3)."""
    from cspace._formats.meshes import load

    started: list[int] = []
    parse = load._parse_in_child

    def counted(meshes: Any, limits: Any) -> Any:
        started.append(len(meshes))
        return parse(meshes, limits)

    monkeypatch.setattr(load, "_parse_in_child", counted)
    monkeypatch.setattr(load, "MAX_MESH_CHILDREN", 3)
    heavy = heavy_obj(400_000)  # about a second of the parser's CPU
    meshes = [load.MeshBytes(f"m{k}.obj", "obj", (1.0, 1.0, 1.0), heavy) for k in range(8)]
    results = load.parse_meshes(meshes, limits=load.MeshLimits(cpu_seconds=1))
    assert started == [8, 4, 2], started
    assert all(isinstance(r, RobotFileError) and "CPU" in r.problem for r in results), results


def test_the_hull_makers_halves_stop_at_the_childrens_bound(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from cspace._confine import sandbox
    from cspace._model import _collision_hull

    started: list[int] = []
    run_child = sandbox.run_child

    def counted(module: str, request: Any, *more: Any) -> Any:
        if module == "cspace._model._collision_hull":
            started.append(len(request["points"]))
        return run_child(module, request, *more)

    monkeypatch.setattr(sandbox, "run_child", counted)
    monkeypatch.setattr(_collision_hull, "MAX_HULL_CHILDREN", 3)
    monkeypatch.setattr(_collision_hull, "CPU_SECONDS", 1)
    rng = np.random.default_rng(0)
    spheres = []
    for _ in range(8):  # every point a vertex of its hull: about 2 s of qhull each
        points = rng.normal(size=(200_000, 3))
        spheres.append(points / np.linalg.norm(points, axis=1)[:, None])
    hulls = _collision_hull.convex_hulls(spheres)
    assert started == [8, 4, 2], started
    assert all(isinstance(h, str) and "CPU" in h for h in hulls), hulls


def test_limits_further_apart_than_a_double_holds_are_no_refusal(tmp_path: Path) -> None:
    """Limits of +-1e308 (inspect reads them, as sentinels) made the run's samples
    'wider than a double holds: give narrower bounds' (bad-argument), bounds the command
    takes none of: the translation is now held (collision-held), the angle sampled over
    one turn."""
    limit = '<limit lower="-1e308" upper="1e308" effort="1" velocity="1"/>'
    robot = tmp_path / "wide.urdf"
    robot.write_text(
        '<robot name="wide">'
        '<link name="base"><collision><geometry><box size="0.4 0.4 0.1"/></geometry>'
        "</collision></link>"
        '<link name="a"><collision><origin xyz="0 0 0.2"/><geometry>'
        '<box size="0.05 0.05 0.4"/></geometry></collision></link>'
        '<link name="b"><collision><origin xyz="0 0 0.2"/><geometry>'
        '<box size="0.05 0.05 0.4"/></geometry></collision></link>'
        '<joint name="slide" type="prismatic"><parent link="base"/><child link="a"/>'
        f'<axis xyz="1 0 0"/>{limit}</joint>'
        '<joint name="turn" type="revolute"><parent link="a"/><child link="b"/>'
        f'<origin xyz="0 0 0.4"/><axis xyz="0 1 0"/>{limit}</joint>'
        "</robot>"
    )
    report = cspace.collisions(robot, samples=500)
    held = [d for d in report.diagnostics if d.code == "collision-held"]
    assert [d.joint for d in held] == ["slide"], report.diagnostics
    (pair,) = [p for p in report.pairs if (p.link1, p.link2) == ("b", "base")]
    assert pair.collisions is not None and 0 < pair.collisions.hits < 500, pair
    assert pair.witness is not None
    angle = dict(pair.witness.configuration)["turn"][0]
    assert -np.pi <= angle <= np.pi and dict(pair.witness.configuration)["slide"] == (0.0,)


def _grouped_stage(path: Path, bodies: int, per: int, groups: int) -> Path:
    """A chain of ``bodies`` cubes, each cube in ``per`` of ``groups`` collision groups
    (a window of them, so that no two cubes share their groups), no group filtering."""
    text = ['#usda 1.0\n(\n    defaultPrim = "r"\n    metersPerUnit = 1\n)\ndef Xform "r"\n{']
    for k in range(bodies):
        text.append(
            f'def Xform "b{k}" (prepend apiSchemas = ["PhysicsRigidBodyAPI"]) {{\n'
            f"double3 xformOp:translate = ({2.0 * k}, 0, 0)\n"
            'uniform token[] xformOpOrder = ["xformOp:translate"]\n'
            'def Cube "c" (prepend apiSchemas = ["PhysicsCollisionAPI"]) {\ndouble size = 0.5\n}\n'
            "}"
        )
        if k == 0:
            text.append('def PhysicsFixedJoint "mount" {\nrel physics:body1 = </r/b0>\n}')
            continue
        text.append(
            f'def PhysicsRevoluteJoint "j{k}" {{\nrel physics:body0 = </r/b{k - 1}>\n'
            f'rel physics:body1 = </r/b{k}>\nuniform token physics:axis = "Z"\n'
            "point3f physics:localPos0 = (1, 0, 0)\npoint3f physics:localPos1 = (-1, 0, 0)\n"
            "float physics:lowerLimit = -1\nfloat physics:upperLimit = 1\n}"
        )
    text.append('}\ndef Xform "g"\n{')
    members: dict[int, list[str]] = {g: [] for g in range(groups)}
    for k in range(bodies):
        for step in range(per):
            members[(k + step) % groups].append(f"</r/b{k}/c>")
    for g, colliders in members.items():
        text.append(
            f'def PhysicsCollisionGroup "G{g}" (prepend apiSchemas = '
            f'["CollectionAPI:colliders"]) {{\n'
            f"rel collection:colliders:includes = [{', '.join(colliders)}]\n}}"
        )
    path.write_text("\n".join([*text, "}"]) + "\n")
    return path


def test_collision_groups_are_read_within_a_bound_of_work(tmp_path: Path) -> None:
    """Each pair of links' group sets was compared group by group, unbounded: 150 links
    in 100 groups each took 25 s of CPU, 700 links in 280 groups each (a 3 MB stage)
    hours. The groups' pairs now spend filteredPairs' budget (4 million), a warning
    past it."""
    pytest.importorskip("pxr")
    stage = _grouped_stage(tmp_path / "groups.usda", 150, 100, 300)
    result = measured("collisions", str(stage), "-n", "1", cwd=tmp_path)
    assert result.run.code == 0, result
    assert "more collider pairs to look at than the 4,000,000" in result.run.stdout, result
    assert result.cpu_seconds < SECONDS, result


def test_a_robot_of_many_degrees_of_freedom_is_refused_before_pinocchios_data(
    tmp_path: Path,
) -> None:
    """Pinocchio's Data holds 32 nv^3 bytes whatever the tree (its second-order
    derivatives): a 60 KB URDF, a chain of 300 joints without a shape, took 860 MB, one of
    700 11 GB (1,000 joints, within a robot file's bounds, 32 GB)."""
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    links = "".join(f'<link name="l{k}"/>' for k in range(301))
    joints = "".join(
        f'<joint name="j{k}" type="revolute"><parent link="l{k}"/><child link="l{k + 1}"/>'
        f'<axis xyz="0 0 1"/>{limit}</joint>'
        for k in range(300)
    )
    robot = tmp_path / "chain.urdf"
    robot.write_text(f'<robot name="chain">{links}{joints}</robot>')
    stderr = assert_bounded_error(
        measured("collisions", str(robot), "-n", "1", cwd=tmp_path), "too-many-dofs"
    )
    assert "300 degrees of freedom" in stderr and "at most 200" in stderr


@pytest.mark.bounded
def test_checks_slow_by_design_are_stopped_at_the_commands_cpu_budget(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two meshes of needles whose bounding volumes all overlap take about a second a
    check (days at the bounds' largest meshes): with ``cpu_limit`` (the command's), the
    sampling process is stopped at its CPU budget, one line, instead of running on."""
    from cspace.errors import WorkerDiedError
    from cspace.space._collisions import run

    monkeypatch.setattr(run, "CPU_FLOOR", 2.0)
    robot = needles_robot(tmp_path)
    before = _tree_cpu()
    with pytest.raises(WorkerDiedError, match="spent its 2 s of CPU"):
        cspace.collisions(robot, samples=200, cpu_limit=True)
    assert _tree_cpu() - before < 60  # CPU of this process and its children: 200 s otherwise


def _tree_cpu() -> float:
    """CPU seconds of this process and of its children waited for (the run's workers)."""
    import resource

    return sum(
        usage.ru_utime + usage.ru_stime
        for usage in (
            resource.getrusage(resource.RUSAGE_SELF),
            resource.getrusage(resource.RUSAGE_CHILDREN),
        )
    )


def test_meshes_past_the_robots_triangle_budget_leave_their_links_out(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A built triangle costs coal about 575 bytes: past the robot's budget (here 30
    triangles, three boxes of 12), a link's mesh is left out (collision-skipped, an
    error), not built. One mesh named twice is counted once."""
    from cspace.space._collisions import setup

    monkeypatch.setattr(setup, "MAX_CHECKED_TRIANGLES", 30)
    (tmp_path / "box.stl").write_bytes(box_stl(0.1, 0.1, 0.1))
    (tmp_path / "other.stl").write_bytes(box_stl(0.2, 0.1, 0.1))
    (tmp_path / "third.stl").write_bytes(box_stl(0.3, 0.1, 0.1))
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    links = "".join(
        f'<link name="{name}"><collision><origin xyz="0 0 {z}"/><geometry>'
        f'<mesh filename="{mesh}"/></geometry></collision></link>'
        for name, mesh, z in (
            ("a", "box.stl", 0),
            ("b", "box.stl", 1),
            ("c", "other.stl", 2),
            ("d", "third.stl", 3),
        )
    )
    joints = "".join(
        f'<joint name="j{k}" type="revolute"><parent link="{p}"/><child link="{c}"/>{limit}</joint>'
        for k, (p, c) in enumerate((("a", "b"), ("b", "c"), ("c", "d")))
    )
    (tmp_path / "r.urdf").write_text(f'<robot name="r">{links}{joints}</robot>')
    report = cspace.collisions(tmp_path / "r.urdf", samples=20)
    assert report.links == ("a", "b", "c")
    [skipped] = [d for d in report.diagnostics if d.code == "collision-skipped"]
    assert "link 'd'" in skipped.message and "30 cspace checks" in skipped.message
    assert report.has(cspace.Severity.ERROR)
