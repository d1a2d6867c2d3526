"""Hostile USD stages against what this reader grew: mimic relations, display names,
Isaac's order, and the discovery of a folder's layers (whose arcs OpenUSD lists in a
confined child).

The reader's first hostile stages (layers outside the folder, bombs, cycles, 100,001
prims, a FIFO, links, expressions) are in ``tests/test_usd.py``.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import cspace
from cspace._model import adapter

from conftest import OpenWatch, run_cli

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


def _stage(tmp_path: Path, joints: str, bodies: int, name: str = "stage.usda") -> Path:
    path = tmp_path / name
    path.write_text(HEAD + "".join(BODY.format(f"b{i}") for i in range(bodies)) + joints + "}\n")
    return path


def test_many_mimic_joints_are_made_dependent_within_a_bound(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each relation copies Pinocchio's model: past the bound the followers keep their
    entries (said), and the C-space is the same. 4,999 followers of a 5,000-joint stage
    took over a minute before the bound."""
    monkeypatch.setattr(adapter, "MIMIC_WORK", 2_000)  # 2,000 / 101 joints: 19 relations
    joints = _revolute("j1", "b0", "b1")
    for i in range(2, 101):
        mimic = _mimic("j1")
        joints += _revolute(f"j{i}", "b0", f"b{i}", mimic["more"], meta=mimic["meta"])
    report = cspace.inspect(_stage(tmp_path, MOUNT + joints, 101))
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


def test_a_display_name_cannot_inject_into_a_terminal_or_a_workflow(tmp_path: Path) -> None:
    """A joint's displayName is a name like any other: control and bidi characters are
    escaped, and GitHub's workflow commands get no command of the stage's making."""
    written = "evil\u202e\x1b[31m\\n::error file=x::pwned%0A"  # USD's own \\n escape
    meta = f' (\n        displayName = "{written}"\n    )'
    path = _stage(tmp_path, MOUNT + _revolute("j1", "b0", "b1", meta=meta), 2)
    names = [j.name for j in cspace.inspect(path).joints]
    assert "evil\u202e\x1b[31m\n::error file=x::pwned%0A" in names  # read as written
    text = run_cli("inspect", str(path))
    assert "\x1b" not in text.stdout and "\u202e" not in text.stdout
    github = run_cli("inspect", str(path), "--format", "github")
    assert not any(line.startswith("::error file=x") for line in github.stdout.splitlines())
    assert "pwned%0A" not in github.stdout  # GitHub's own escape of %: %25
    long = _stage(tmp_path, MOUNT + _revolute("j1", "b0", "b1", meta=' (\n        displayName = "'
                  + "x" * 5000 + '"\n    )'), 2, "long.usda")  # fmt: skip
    run = run_cli("inspect", str(long))
    assert run.code == 2 and "name-too-long" in run.stderr and run.stderr.count("\n") == 1


def test_isaacs_order_of_a_thousand_deep_chain(tmp_path: Path) -> None:
    """The walk is iterative: a chain of 999 joints (with its mount, the deepest tree
    cspace reads) converts, in order."""
    joints = "".join(_revolute(f"j{i:04d}", f"b{i}", f"b{i + 1}") for i in range(999))
    names = cspace.load(_stage(tmp_path, MOUNT + joints, 1000)).conventions().names("isaac")
    assert names == tuple(f"j{i:04d}" for i in range(999))


def test_discovery_never_opens_what_a_layer_names_outside_the_folder(tmp_path: Path) -> None:
    """A crate layer whose sublayer is outside the folder, a link to a layer outside it,
    and a FIFO named .usda: OpenUSD lists the crate's arcs without opening them, the
    walk skips the link and the FIFO, and nothing outside is opened at all."""
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
    assert "linked.usda" not in run.stdout and "pipe.usda" not in run.stdout
    assert "outside the allowed folders" in run.stdout + run.stderr
