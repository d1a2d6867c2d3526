"""Hostile USD stages against what this reader grew: mimic relations, display names,
Isaac's order, and the discovery of a folder's layers (whose arcs OpenUSD lists in a
confined child).

The reader's first hostile stages (layers outside the folder, bombs, cycles, 100,001
prims, a FIFO, links, expressions) are in ``tests/test_usd.py``.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

import cspace
from cspace._formats.usd import child as _usd_child
from cspace._model import _records

from conftest import HANG_SECONDS, OpenWatch, run_cli, usd_stages

CONVERTED = Path(__file__).parent / "usd" / "converted"
HEAD = '#usda 1.0\n(\n    metersPerUnit = 1\n)\ndef Xform "r"\n{\n'
BODY = '    def Xform "{0}" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])\n    {{\n    }}\n'
MOUNT = '    def PhysicsFixedJoint "mount"\n    {\n        rel physics:body1 = </r/b0>\n    }\n'


def _revolute(name: str, parent: str, child: str, *more: str, meta: str = "") -> str:
    lines = [
        f'    def PhysicsRevoluteJoint "{name}"{meta}',
        "    {",
        '        uniform token physics:axis = "Z"',
        f"        rel physics:body0 = </r/{parent}>",
        f"        rel physics:body1 = </r/{child}>",
        "        float physics:lowerLimit = -90",
        "        float physics:upperLimit = 90",
        *(f"        {line}" for line in more),
        "    }",
    ]
    return "\n".join(lines) + "\n"


def _mimic(leader: str) -> dict[str, str]:
    return {"meta": ' (prepend apiSchemas = ["NewtonMimicAPI"])'} | {
        "more": f"rel newton:mimicJoint = </r/{leader}>"
    }


@pytest.fixture(scope="module")
def _stages(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """Where this file's tests that inspect stages in this process write them."""
    yield from usd_stages(tmp_path_factory)


def _stage(tmp_path: Path, joints: str, bodies: int, name: str = "stage.usda") -> Path:
    path = tmp_path / name
    path.write_text(HEAD + "".join(BODY.format(f"b{i}") for i in range(bodies)) + joints + "}\n")
    return path


def test_many_mimic_joints_are_made_dependent_within_a_bound(
    folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each relation copies Pinocchio's model: past the bound the followers keep their
    entries (said), and the C-space is the same. 4,999 followers of a 5,000-joint stage
    would take over a minute without the bound."""
    monkeypatch.setattr(_records, "MIMIC_WORK", 2_000)  # 2,000 / 101 joints: 19 relations
    joints = _revolute("j1", "b0", "b1")
    for i in range(2, 101):
        mimic = _mimic("j1")
        joints += _revolute(f"j{i}", "b0", f"b{i}", mimic["more"], meta=mimic["meta"])
    report = cspace.inspect(_stage(folder, MOUNT + joints, 101))
    assert report.manifold.notation == "R^1" and report.dimension == 1
    kept = [d for d in report.diagnostics if d.code == "mimic-kept-free"]
    assert len(kept) == 1 and "80 more followers than Pinocchio makes dependent" in kept[0].message


def test_a_mimic_cycle_and_a_chain_of_followers_are_one_line_each(tmp_path: Path) -> None:
    a, b = _mimic("j2"), _mimic("j1")
    cycle = _revolute("j1", "b0", "b1", a["more"], meta=a["meta"])
    cycle += _revolute("j2", "b0", "b2", b["more"], meta=b["meta"])
    run = run_cli("inspect", str(_stage(tmp_path, MOUNT + cycle, 3)))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "mimic-cycle" in run.stderr
    c = _mimic("j2")
    chain = _revolute("j1", "b0", "b1") + _revolute("j2", "b0", "b2", b["more"], meta=b["meta"])
    chain += _revolute("j3", "b0", "b3", c["more"], meta=c["meta"])
    run = run_cli("inspect", str(_stage(tmp_path, MOUNT + chain, 4, "chain.usda")))
    assert run.code in (0, 1) and "Traceback" not in run.stderr and "internal" not in run.stderr


def test_a_display_name_cannot_inject_into_a_terminal_or_a_workflow(folder: Path) -> None:
    """A joint's displayName is a name like any other: control and bidi characters are
    escaped, and GitHub's workflow commands get no command of the stage's making."""
    written = "evil\u202e\x1b[31m\\n::error file=x::pwned%0A"  # USD's own \\n escape
    meta = f' (\n        displayName = "{written}"\n    )'
    path = _stage(folder, MOUNT + _revolute("j1", "b0", "b1", meta=meta), 2)
    names = [j.name for j in cspace.inspect(path).joints]
    assert "evil\u202e\x1b[31m\n::error file=x::pwned%0A" in names  # read as written
    text = run_cli("inspect", str(path))
    assert "\x1b" not in text.stdout and "\u202e" not in text.stdout
    github = run_cli("inspect", str(path), "--format", "github")
    assert not any(line.startswith("::error file=x") for line in github.stdout.splitlines())
    assert "pwned%0A" not in github.stdout  # GitHub's own escape of %: %25
    long = _stage(folder, MOUNT + _revolute("j1", "b0", "b1", meta=' (\n        displayName = "'
                  + "x" * 5000 + '"\n    )'), 2, "long.usda")  # fmt: skip
    run = run_cli("inspect", str(long))
    assert run.code == 2 and "name-too-long" in run.stderr and run.stderr.count("\n") == 1


def test_isaacs_order_of_a_thousand_deep_chain(folder: Path) -> None:
    """The walk is iterative: a chain of 999 joints (with its mount, the deepest tree
    cspace reads) converts, in order."""
    joints = "".join(_revolute(f"j{i:04d}", f"b{i}", f"b{i + 1}") for i in range(999))
    names = cspace.load(_stage(folder, MOUNT + joints, 1000)).conventions().names("isaac")
    assert names == tuple(f"j{i:04d}" for i in range(999))


def test_discovery_never_opens_what_a_layer_names_outside_the_folder(tmp_path: Path) -> None:
    """A crate layer whose sublayer is outside the folder, a link to a layer outside it,
    and a FIFO named .usda: OpenUSD lists the crate's arcs without opening them, the
    link is refused unread (as when named), the walk skips the FIFO, and nothing outside
    is opened at all."""
    from pxr import Sdf

    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.usda").write_text(HEAD + BODY.format("b0") + "}\n")
    folder = tmp_path / "repo"
    folder.mkdir()
    root = Sdf.Layer.CreateNew(str(folder / "robot.usd"))
    root.subLayerPaths = [str(outside / "secret.usda"), "../outside/secret.usda"]
    root.Save()
    (folder / "linked.usda").symlink_to(outside / "secret.usda")
    os.mkfifo(folder / "pipe.usda")
    watch = OpenWatch(outside)
    try:
        run = run_cli("inspect", str(folder), "--width", "400", timeout=60)
        opened = watch.opened()
    finally:
        watch.close()
    assert opened == [], opened
    assert str(folder / "robot.usd") in run.stdout  # read, and refused for its sublayer
    assert f"{folder / 'linked.usda'}: is a link to a file outside its folder" in run.stderr
    assert "pipe.usda" not in run.stdout + run.stderr
    assert "outside the allowed folders" in run.stdout + run.stderr


# --- many stages, one child: bounds, bombs, and what each stage may read -------------


def _bomb(folder: Path, layers: int = 30) -> Path:
    """Each layer references the next twice (from two prims): 2^30 prims composed."""
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(layers):
        nxt = f"@./l{i + 1}.usda@</r>"
        body = (
            f'def Xform "r"\n{{\n    def Xform "x" (references = {nxt}) {{}}\n'
            f'    def Xform "y" (references = {nxt}) {{}}\n}}\n'
            if i + 1 < layers
            else 'def Xform "r" {}\n'
        )
        (folder / f"l{i}.usda").write_text("#usda 1.0\n" + body)
    return folder / "l0.usda"


def _inner_bomb(path: Path, depth: int = 30) -> Path:
    """One layer whose prims' children reference the next prim, twice each."""
    prims = [
        f'def Xform "p{i}" {{\n    def Xform "x" (references = </p{i + 1}>) {{}}\n'
        f'    def Xform "y" (references = </p{i + 1}>) {{}}\n}}\n'
        for i in range(depth)
    ]
    path.write_text("#usda 1.0\n" + "".join(prims) + f'def Xform "p{depth}" {{}}\n')
    return path


_PINNED = "import os, sys; os.sched_setaffinity(0, {%d}); os.execv(sys.argv[1], sys.argv[1:])"
_BURN = "import os; os.sched_setaffinity(0, {%d})\nwhile True: pass"


def _on_one_core(core: int, *args: str) -> tuple[int, str, str, float]:
    """`cspace ARGS` on one core: exit code, stdout, stderr, and the CPU seconds of the
    command and the children it waited for (its OpenUSD child)."""
    import subprocess
    import sys
    import threading

    from conftest import cspace_command

    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        command = [sys.executable, "-c", _PINNED % core, *cspace_command(), *args]
        run = subprocess.Popen(command, stdout=out, stderr=err)
        guard = threading.Timer(120, run.kill)  # a hang fails the test, not the suite
        guard.start()
        _, status, usage = os.wait4(run.pid, 0)
        guard.cancel()
        run.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        text = out.read().decode(), err.read().decode()
    return run.returncode, *text, usage.ru_utime + usage.ru_stime


@pytest.mark.bounded
def test_composition_bombs_are_refused_before_composing_on_a_busy_core(tmp_path: Path) -> None:
    """30 layers each referencing the next twice (10 s and 1.2 GiB of OpenUSD's time
    before), and the same within one layer, on one core that another process keeps busy:
    refused with the bound's message before anything composes, the command and its
    child within the child's CPU bound."""
    import subprocess
    import sys

    from cspace._formats.usd.child import LIMITS

    core = max(os.sched_getaffinity(0))
    burner = subprocess.Popen([sys.executable, "-c", _BURN % core])
    try:
        for stage in (_bomb(tmp_path / "layers"), _inner_bomb(tmp_path / "inner.usda")):
            code, out, err, cpu = _on_one_core(core, "inspect", str(stage))
            assert code == 2 and out == "" and err.count("\n") == 1, err
            assert err.startswith(f"cspace: error: {stage}: the stage's composition makes more")
            assert "than 200,000 prim sites" in err and err.endswith("[usd-refused]\n")
            assert cpu < LIMITS.cpu_seconds, cpu
    finally:
        burner.kill()
        burner.wait()


def _slow(path: Path) -> Path:
    """A stage within every count that takes OpenUSD's child over 4 s of CPU to read
    (99,000 rigid bodies)."""
    body = '(prepend apiSchemas = ["PhysicsRigidBodyAPI"]) {}'
    path.write_text("#usda 1.0\n" + "".join(f'def Xform "p{i}" {body}\n' for i in range(99_000)))
    return path


def _startup_cpu() -> float:
    """The CPU seconds of starting an OpenUSD child and ending it (its import and warm-up).

    A child an earlier test left is ended first: its CPU time is none of the start-up's.
    """
    import resource

    _usd_child.close()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    _usd_child.ask({"arcs": []}, [str(Path(__file__).parent)])
    _usd_child.close()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def _cpu_of(stages: list[str]) -> tuple[list[cspace.Inspected], float]:
    """The stages inspected in this process, and the CPU seconds of the children it ended."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = list(cspace.inspect_many(stages, jobs=1))
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return done, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


@pytest.mark.bounded
def test_a_stage_past_its_cpu_bound_ends_its_child_not_the_next_stage(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The parent stops a request at its CPU bound (here 1 s); the child is killed and
    the next stage is read by a new one. The wall clock is only a hang guard here, so
    that a busy machine cannot stop the request by it first."""
    limits = _usd_child.LIMITS._replace(cpu_seconds=1, wall_seconds=float(HANG_SECONDS))
    monkeypatch.setattr(_usd_child.KEPT, "limits", limits)
    start = _startup_cpu()
    good = [shutil.copy(CONVERTED / "arm7.usda", tmp_path / f"arm{i}.usda") for i in range(2)]
    done, cpu = _cpu_of([str(_slow(tmp_path / "slow.usda")), good[0]])
    assert str(done[0].error).endswith("OpenUSD used more than 1 s of CPU and was stopped")
    assert done[1].report is not None and done[1].report.manifold.notation == "R^6 × S^1"
    assert cpu - start < 1.5, (cpu, start)  # it takes 4 s when let run
    first = _usd_child.live_pid()
    done, _ = _cpu_of([str(tmp_path / "slow.usda"), good[1]])
    assert done[1].report is not None and _usd_child.live_pid() not in (None, first)
    _usd_child.close()


@pytest.mark.bounded
def test_a_request_past_its_wall_clock_on_a_busy_core_is_stopped(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """On a core another process keeps busy the child gets half of it (less when more
    processes share it): the wall clock (here 1.5 s) stops the request before its CPU
    bound (3 s) would. The next stage, with the usual bounds, is read by a new child."""
    import subprocess
    import sys

    limits = _usd_child.LIMITS._replace(cpu_seconds=3, wall_seconds=1.5)
    monkeypatch.setattr(_usd_child.KEPT, "limits", limits)
    slow = str(_slow(tmp_path / "slow.usda"))
    good = str(shutil.copy(CONVERTED / "arm7.usda", tmp_path / "arm.usda"))
    core, cores = max(os.sched_getaffinity(0)), os.sched_getaffinity(0)
    start = _startup_cpu()  # CPU time: the same on a busy core (if anything, more there)
    burner = subprocess.Popen([sys.executable, "-c", _BURN % core])
    os.sched_setaffinity(0, {core})  # the children started here share the burner's core
    try:
        done, cpu = _cpu_of([slow])
        monkeypatch.setattr(_usd_child.KEPT, "limits", _usd_child.LIMITS)
        after, _ = _cpu_of([good])
    finally:
        os.sched_setaffinity(0, cores)
        burner.kill()
        burner.wait()
        _usd_child.close()
    assert str(done[0].error).endswith("OpenUSD took longer than 1.5 s and was stopped")
    assert cpu - start < limits.cpu_seconds, (cpu, start)
    assert after[0].report is not None, after[0].error


def test_a_stage_reads_only_its_own_folders_though_its_child_serves_others(
    tmp_path: Path,
) -> None:
    """One child confined to the whole tree serves a stage of each folder; a stage that
    names a layer of the other folder, or one under a hidden entry of its own (which the
    child's Landlock rules on the tree would let it read), is refused unopened."""
    (tmp_path / "a" / ".hidden").mkdir(parents=True)
    (tmp_path / "b").mkdir()
    good = shutil.copy(CONVERTED / "arm7.usda", tmp_path / "b" / "arm.usda")
    (tmp_path / "b" / "secret.usda").write_text(HEAD + BODY.format("b0") + "}\n")
    (tmp_path / "a" / ".hidden" / "x.usda").write_text(HEAD + BODY.format("b0") + "}\n")
    across = tmp_path / "a" / "across.usda"
    across.write_text("#usda 1.0\n(\n    subLayers = [@../b/secret.usda@]\n)\n")
    hidden = tmp_path / "a" / "hidden.usda"
    hidden.write_text('#usda 1.0\ndef Xform "r" (references = @./.hidden/x.usda@</r>) {}\n')
    _usd_child.close()
    _usd_child.within([str(tmp_path)])
    try:
        assert cspace.inspect(good).manifold.notation == "R^6 × S^1"
        served = _usd_child.live_pid()
        watches = [OpenWatch(tmp_path / "b"), OpenWatch(tmp_path / "a" / ".hidden")]
        done = list(cspace.inspect_many([str(across), str(hidden)], jobs=1))
        opened = [w.opened() for w in watches]
        assert _usd_child.live_pid() == served  # the same child read all three
    finally:
        for watch in watches:
            watch.close()
        _usd_child.within(())
        _usd_child.close()
    assert opened == [[], []], opened
    assert "composes '" + str(tmp_path / "b" / "secret.usda") + "', outside" in str(done[0].error)
    assert "x.usda', outside the allowed folders" in str(done[1].error)


def test_many_stages_give_the_bytes_of_one_child_each(tmp_path: Path) -> None:
    """Good stages and refused ones (a bomb, a layer of another folder, a syntax error)
    in two folders: the reports and error lines of one run, with --jobs 1 and 2, are
    those of each stage read on its own (a child each), in order."""
    from conftest import run_cli_many

    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    stages = [
        shutil.copy(CONVERTED / "arm7.usda", tmp_path / "a" / "arm.usda"),
        str(_bomb(tmp_path / "b" / "bomb")),
        str(tmp_path / "a" / "across.usda"),
        str(tmp_path / "b" / "broken.usda"),
        shutil.copy(CONVERTED / "gripper_mimic.usda", tmp_path / "b" / "gripper.usda"),
    ]
    (tmp_path / "a" / "across.usda").write_text(
        "#usda 1.0\n(\n    subLayers = [@../b/x.usda@]\n)\n"
    )
    (tmp_path / "b" / "broken.usda").write_text("#usda 1.0\ndef Xform (\n")
    runs = run_cli_many(
        [("inspect", "--format", "jsonl", s) for s in stages]
        + [("inspect", "--format", "jsonl", "--jobs", j, *stages) for j in ("1", "2")]
    )
    alone, together = runs[: len(stages)], runs[len(stages) :]
    assert [r.code for r in alone] == [0, 2, 2, 2, 0]
    for run in together:
        assert run.stdout == "".join(r.stdout for r in alone)
        assert run.stderr == "".join(r.stderr for r in alone)


# --- what OpenUSD may open beyond the layers, and what Pcp multiplies -----------------

CLIPS = """#usda 1.0
(
    defaultPrim = "r"
)
def Xform "r" (
    clips = {
        dictionary default = {
            %s
            string primPath = "/World"
            double2[] active = [(0, 0)]
            double2[] times = [(0, 0)]
        }
    }
)
{
}
"""


def test_a_stage_opens_no_file_its_checks_have_not_seen(tmp_path: Path) -> None:
    """Value clips (a list of files, and a template naming 100 million) are refused; an
    asset path into a .usdz package outside the stage's folder, in an attribute declared
    an asset or (in a crate file) a float, and a sublayer named with file format arguments
    through a link out, are refused: the stage's child may read the whole tree, yet
    nothing of the other folder is opened (OpenUSD opened the clip and printed its text
    in its parse error; it opened the package to resolve the value, in its parser too)."""
    from pxr import Sdf, UsdUtils

    other, proj = tmp_path / "other", tmp_path / "proj"
    other.mkdir()
    proj.mkdir()
    (other / "secret.usda").write_text('#usda 1.0\ndef "World"\n{\n}\nTOKEN_ghp_abcdef\n')
    (other / "a.usda").write_text('#usda 1.0\ndef "x" {}\n')
    assert UsdUtils.CreateNewUsdzPackage(str(other / "a.usda"), str(other / "x.usdz"))
    package = "../other/x.usdz[a.usda]"
    good = shutil.copy(CONVERTED / "arm7.usda", proj / "arm.usda")
    (proj / "clips.usda").write_text(CLIPS % "asset[] assetPaths = [@../other/secret.usda@]")
    (proj / "template.usda").write_text(
        CLIPS % 'string templateAssetPath = "../other/c.#.usda"\n'
        "double templateStartTime = 1\ndouble templateEndTime = 100000000\n"
        "double templateStride = 1"
    )
    named = _revolute("j1", "b0", "b1", f"asset physics:jointEnabled = @{package}@")
    asset = _stage(proj, MOUNT + named, 2, "asset.usda")
    plain = Sdf.Layer.FindOrOpen(str(_stage(proj, MOUNT + _revolute("j1", "b0", "b1"), 2)))
    crate = Sdf.Layer.CreateNew(str(proj / "float.usdc"))
    crate.TransferContent(plain)
    crate.GetAttributeAtPath("/r/j1.physics:lowerLimit").SetInfo("default", Sdf.AssetPath(package))
    crate.Save()
    (proj / "link.usda").symlink_to(other / "secret.usda")
    args = proj / "args.usda"
    args.write_text("#usda 1.0\n(\n    subLayers = [@./link.usda:SDF_FORMAT_ARGS:a=b@]\n)\n")
    stages = [proj / "clips.usda", proj / "template.usda", asset, proj / "float.usdc", args]
    _usd_child.close()
    _usd_child.within([str(tmp_path)])
    try:
        assert cspace.inspect(good).manifold.notation == "R^6 × S^1"  # the child, started
        watch = OpenWatch(other)
        done = list(cspace.inspect_many([str(s) for s in stages], jobs=1))
        opened = watch.opened()
    finally:
        watch.close()
        _usd_child.within(())
        _usd_child.close()
    assert opened == [], opened
    errors = [str(d.error) for d in done]
    assert all("TOKEN" not in e for e in errors), errors
    assert "</r> in '" + str(proj / "clips.usda") + "' has value clips" in errors[0]
    assert "</r> in '" + str(proj / "template.usda") + "' has value clips" in errors[1]
    reads = f"the stage reads '{other / 'x.usdz'}[a.usda]' (an asset path at </r/j1.physics:"
    assert reads + "jointEnabled>" in errors[2] and reads + "lowerLimit>" in errors[3], errors
    assert "link.usda:SDF_FORMAT_ARGS:a=b', outside the allowed folders" in errors[4]


def test_a_usd_path_holding_brackets_is_no_package_path(tmp_path: Path) -> None:
    """Only a path ending in ']' is one into a package: a stage named [x].usda, one in a
    folder arm[v2]/, and a stage whose sublayer is that one are read."""
    (tmp_path / "arm[v2]").mkdir()
    named = shutil.copy(CONVERTED / "arm7.usda", tmp_path / "[x].usda")
    folder = shutil.copy(CONVERTED / "arm7.usda", tmp_path / "arm[v2]" / "arm.usda")
    above = tmp_path / "above.usda"
    above.write_text("#usda 1.0\n(\n    subLayers = [@./arm[v2]/arm.usda@]\n)\n")
    for done in cspace.inspect_many([named, folder, str(above)], jobs=1):
        assert done.report is not None, done.error
        assert done.report.manifold.notation == "R^6 × S^1"


def _fan(folder: Path, depth: int, prims: int = 1) -> Path:
    """Layers l0..l{depth}, each naming the next twice as a sublayer: 2^(depth+1) - 1
    entries in l0's layer stack."""
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(depth + 1):
        below = f"@./l{i + 1}.usda@, @./l{i + 1}.usda@" if i < depth else ""
        body = "".join(f'def Xform "p{k}" {{}}\n' for k in range(prims))
        (folder / f"l{i}.usda").write_text(f"#usda 1.0\n(\n    subLayers = [{below}]\n)\n{body}")
    return folder / "l0.usda"


@pytest.mark.bounded
def test_sublayers_are_counted_each_time_they_are_named(tmp_path: Path) -> None:
    """22 layers each naming the next twice as sublayers (4 million layer-stack entries,
    over a minute of OpenUSD's time), and a stage that references such a layer, are
    refused in milliseconds, the layer named; a layer of 1,500 prims named 200 times as
    a sublayer is 300,000 sites. OpenUSD's own stack of 255 entries is read, of 511
    refused."""
    from pxr import Usd

    from cspace._formats.usd.child import LIMITS

    bomb = _fan(tmp_path / "bomb", 22)
    above = tmp_path / "above.usda"
    above.write_text('#usda 1.0\ndef Xform "r" (references = @./bomb/l0.usda@</p0>) {}\n')
    stack = "has more than 256 layers (a sublayer counted each time it is named"
    for stage, layer in ((bomb, bomb), (above, bomb)):
        code, _, err, cpu = _on_one_core(max(os.sched_getaffinity(0)), "inspect", str(stage))
        assert code == 2 and err.count("\n") == 1, err
        assert f"the layer stack of '{layer}' {stack}" in err and cpu < LIMITS.cpu_seconds / 2
    many = tmp_path / "many.usda"
    many.write_text("#usda 1.0\n(\n    subLayers = [" + ", ".join(["@./a.usda@"] * 200) + "]\n)\n")
    (tmp_path / "a.usda").write_text(
        "#usda 1.0\n" + "".join(f'def Xform "p{k}" {{}}\n' for k in range(1500))
    )
    small, large = _fan(tmp_path / "small", 7), _fan(tmp_path / "large", 8)
    assert [len(Usd.Stage.Open(str(s)).GetLayerStack(False)) for s in (small, large)] == [255, 511]
    done = list(cspace.inspect_many([str(many), str(small), str(large)], jobs=1))
    assert "more than 200,000 prim sites" in str(done[0].error)
    assert done[1].report is not None and stack in str(done[2].error)


def test_a_stage_opens_nothing_in_a_version_control_folder_below_its_own(tmp_path: Path) -> None:
    """A second checkout's ``other/.git/config`` (where it keeps its token) reached through
    a committed link is refused before OpenUSD opens it, although it lies beneath the
    stage's folder."""
    (tmp_path / "other" / ".git").mkdir(parents=True)
    (tmp_path / "other" / ".git" / "config").write_text('#usda 1.0\ndef Xform "TOKEN_x" {}\n')
    (tmp_path / "cfg.usda").symlink_to("other/.git/config")
    (tmp_path / "robot.usda").write_text(
        '#usda 1.0\n(\n    subLayers = [@./cfg.usda@]\n)\ndef Xform "r" {}\n'
    )
    watch = OpenWatch(tmp_path / "other" / ".git")
    try:
        run = run_cli("inspect", "--", "robot.usda", cwd=tmp_path)
        opened = watch.opened()
    finally:
        watch.close()
    assert opened == [] and run.code == 2, (opened, run.stderr)
    assert "cfg.usda', outside the allowed folders" in run.stderr and "TOKEN" not in run.stderr
