"""``cspace collisions`` as a user runs it, and `cspace.collisions` as a program calls it.

The robots are written here, primitives only, each shape placed for a purpose: a rig
whose pairs fall in every one of MoveIt's classes (adjacent through a link without
geometry, in collision at the default configuration where 0 is outside a joint's
range, always, never, sometimes), whose elbow has a range where it always hits the
base, and an SRDF that exercises the allowed collision matrix as MoveIt builds it
(``<disable_default_collisions>``, then ``<enable_collisions>``, then
``<disable_collisions>`` last; a pair's own entry before the links' defaults). The
oracle of every count is Pinocchio's own pipeline on the same URDF
(``buildModelFromUrdf`` + ``buildGeomFromUrdf`` + ``computeCollisions``, every pair),
sample by sample, on the samples drawn again from the seed as the report says they
are (block ``b`` of ``SeedSequence(seed, spawn_key=(b,))``, canonical, mapped to q by
`ConfigurationSpace.conventions`); the intervals are scipy's.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
import scipy.stats
from test_collision_engine import SHARE

import cspace
from cspace._formats.shared.erd import resolve
from cspace._formats.shared.xmlio import read_source
from cspace._formats.srdf.reader import parse_srdf
from cspace._model._collision_pairs import link_pair
from cspace._reports.collisions import CollisionReport, PairReport, Share
from cspace.errors import ArgumentError

from conftest import HASH_SEED, REPO, run_cli

SEED = 7
N = 1200
"""Samples of the library's run: one whole block and part of the next."""
BLOCK = 1000
BINS = 20
MIN_RANGE_SAMPLES = 30
"""The report's bins of a coordinate's range, and the fewest samples of a full bin."""

RIG = """<?xml version="1.0"?>
<robot name="rig">
  <link name="base"><collision><geometry><box size="4 4 0.2"/></geometry></collision></link>
  <link name="hollow"/>
  <link name="arm1"><collision><origin xyz="0 0 0.6"/>
    <geometry><cylinder radius="0.05" length="1"/></geometry></collision></link>
  <link name="arm2"><collision><origin xyz="0 0 1.0"/>
    <geometry><cylinder radius="0.05" length="2"/></geometry></collision></link>
  <link name="post"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="fin"><collision><geometry><box size="0.2 1.0 0.2"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="hollow"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="mount" type="fixed"><parent link="hollow"/><child link="arm1"/></joint>
  <joint name="j2" type="revolute"><parent link="arm1"/><child link="arm2"/>
    <origin xyz="0 0 1.1"/><axis xyz="0 1 0"/>
    <limit lower="0.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="stand" type="fixed"><parent link="base"/><child link="post"/>
    <origin xyz="1 0 1.2"/></joint>
  <joint name="j3" type="revolute"><parent link="post"/><child link="fin"/>
    <origin xyz="-2.5 0 -0.99999"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""
"""base: a slab, top at z = 0.1. arm1 stands on it (j1 turns it about z), joined through
`hollow`, which has no geometry: base-arm1 are adjacent. arm2 (2 m) hangs from arm1's
top at j2 in [0.5, 2.5]: 0 is outside, so the default is 1.5, where it passes through
`post`; beyond about 2.2 it reaches down into the base whatever j1 is. `fin`, on j3,
lies 1e-5 m above the base: level (j3 = 0, the default) it is free, turned by more than
about 2e-5 rad a corner sinks into the base: always in collision in the samples."""

SRDF = """<?xml version="1.0"?>
<robot name="rig">
  <group name="arm"><joint name="j1"/><joint name="j2"/></group>
  <group_state name="bump" group="arm">
    <joint name="j1" value="0"/><joint name="j2" value="1.5"/></group_state>
  <group_state name="clear" group="arm">
    <joint name="j1" value="0"/><joint name="j2" value="0.6"/></group_state>
  <disable_default_collisions link="fin"/>
  <enable_collisions link1="base" link2="fin"/>
  <disable_collisions link1="arm1" link2="post" reason="Never"/>
  <enable_collisions link1="post" link2="arm1"/>
  <disable_collisions link1="arm1" link2="arm2" reason="Adjacent"/>
  <disable_collisions link1="arm1" link2="base" reason="Adjacent"/>
  <disable_collisions link1="base" link2="post" reason="Adjacent"/>
  <disable_collisions link1="arm2" link2="base" reason="Never"/>
  <disable_collisions link1="base" link2="ghost" reason="Never"/>
  <disable_default_collisions link="phantom"/>
</robot>
"""


def line_of(text: str, snippet: str) -> int:
    """The line of ``text`` that holds ``snippet`` (exactly one)."""
    found = [k for k, line in enumerate(text.splitlines(), 1) if snippet in line]
    assert len(found) == 1, snippet
    return found[0]


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("rig")
    (folder / "robot.urdf").write_text(RIG)
    (folder / "robot.srdf").write_text(SRDF)
    return folder


class Oracle:
    """Pinocchio's own model and geometry of a URDF of primitives, every link pair."""

    def __init__(self, path: Path) -> None:
        self.model = pin.buildModelFromUrdf(str(path))
        self.geometry = pin.buildGeomFromUrdf(self.model, str(path), pin.COLLISION)
        links = [self.model.frames[g.parentFrame].name for g in self.geometry.geometryObjects]
        self.owners: list[tuple[str, str]] = []
        for i, a in enumerate(links):
            for j in range(i + 1, len(links)):
                if a != links[j]:
                    self.geometry.addCollisionPair(pin.CollisionPair(i, j))
                    self.owners.append(link_pair(a, links[j]))
        self.data = self.model.createData()
        self.geometry_data = pin.GeometryData(self.geometry)

    def colliding(self, q: np.ndarray) -> set[tuple[str, str]]:
        """The link pairs in collision at Pinocchio's ``q``."""
        pin.computeCollisions(self.model, self.data, self.geometry, self.geometry_data, q, False)
        results = self.geometry_data.collisionResults
        return {self.owners[k] for k, r in enumerate(results) if r.isCollision()}


def drawn(space: Any, seed: int, n: int) -> np.ndarray:
    """Samples 0 to n of ``seed`` as the report says it draws them, canonical, (n, size):
    a line without finite limits (a floating joint's position) held at its neutral."""
    held = {
        c.name: (c.neutral, c.neutral)
        for c in space.coordinates
        if c.factor == "R^1" and not (math.isfinite(c.lower) and math.isfinite(c.upper))
    }
    blocks = []
    for b in range(-(-n // BLOCK)):
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(b,)))
        blocks.append(space.sample(BLOCK, rng, bounds=held or None))
    return np.concatenate(blocks)[:n]


class Sampled:
    """The rig's first N samples of SEED, and the link pairs in collision at each."""

    def __init__(self, path: Path) -> None:
        self.space = cspace.load(path)
        self.x = drawn(self.space, SEED, N)
        self.q = self.space.conventions().to_pinocchio(self.x)
        self.oracle = Oracle(path)
        assert list(self.oracle.model.names)[1:] == ["j1", "j2", "j3"]
        assert self.q.shape == (N, self.oracle.model.nq)
        self.hits = [self.oracle.colliding(q) for q in self.q]


@pytest.fixture(scope="module")
def sampled(rig: Path) -> Sampled:
    return Sampled(rig / "robot.urdf")


@pytest.fixture(scope="module")
def report(rig: Path) -> CollisionReport:
    return cspace.collisions(rig / "robot.urdf", samples=N, seed=SEED, srdf=rig / "robot.srdf")


def pairs_of(report: CollisionReport) -> dict[tuple[str, str], PairReport]:
    return {(p.link1, p.link2): p for p in report.pairs}


def cli(*args: str, cwd: Path, **kwargs: Any) -> Any:
    """`cspace collisions ARGS...` in ``cwd``."""
    return run_cli("collisions", *args, cwd=cwd, **kwargs)


def one_line_error(run: Any, *words: str) -> str:
    """Exit 2, nothing on standard output, one line on standard error holding ``words``."""
    assert run.code == 2, run
    assert run.stdout == ""
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("cspace: error: "), run.stderr
    assert "Traceback" not in run.stderr
    for word in words:
        assert word in run.stderr, run.stderr
    return str(run.stderr)


# --- determinism and chunking ----------------------------------------------------------


def test_the_same_seed_gives_the_same_bytes_in_text_and_json(rig: Path) -> None:
    args = ("robot.urdf", "--srdf", "robot.srdf", "-n", "1500", "--seed", "3")
    for fmt in ("text", "json"):
        first, second = (cli(*args, "--format", fmt, cwd=rig, env=env) for env in HASH_SEED)
        assert first.code == second.code == 1, first.stderr  # the rig's SRDF has errors
        assert first.stdout == second.stdout and first.stdout.strip()
    other = cli(*args[:-1], "4", "--format", "json", cwd=rig)
    assert json.loads(other.stdout)["pairs"] != json.loads(first.stdout)["pairs"]


def test_processes_do_not_change_the_report(rig: Path) -> None:
    # 5,000 samples: above the 4,000 from which a run is split across processes
    args = ("robot.urdf", "--srdf", "robot.srdf", "-n", "5000", "--seed", "11", "--format", "json")
    one, two = cli(*args, "-j", "1", cwd=rig), cli(*args, "-j", "2", cwd=rig)
    assert one.code == two.code == 1
    assert one.stdout == two.stdout
    document = json.loads(one.stdout)
    assert document["samples"] == 5000 and document["free_suggested"]["hits"] > 0


def test_a_longer_run_begins_with_the_shorter_one(rig: Path) -> None:
    short, long = (
        json.loads(cli("robot.urdf", "-n", n, "--seed", "5", "--format", "json", cwd=rig).stdout)
        for n in ("1000", "3000")
    )
    seen = 0
    for a, b in zip(short["pairs"], long["pairs"], strict=True):
        assert (a["link1"], a["link2"], a["kind"] == "adjacent") == (
            b["link1"],
            b["link2"],
            b["kind"] == "adjacent",
        )
        if a["collisions"] is None:
            continue
        assert a["collisions"]["hits"] <= b["collisions"]["hits"]
        if b["witness"] is not None and b["witness"]["sample"] < 1000:
            assert a["witness"] == b["witness"]  # the same sample, the same configuration
            seen += 1
        else:
            assert a["witness"] is None
    assert seen >= 3


# --- statistics --------------------------------------------------------------------------


def _assert_share_is_scipys(share: Share, hits: int, n: int) -> None:
    assert (share.hits, share.samples) == (hits, n)
    assert share.share == hits / n
    test = scipy.stats.binomtest(hits, n)
    method = "exact" if hits in (0, n) else "wilson"  # Clopper-Pearson at the ends
    expected = test.proportion_ci(0.95, method=method)
    assert (share.low, share.high) == pytest.approx((expected.low, expected.high), abs=1e-12)


def test_each_pairs_share_and_interval_are_the_samples_and_scipys(
    report: CollisionReport, sampled: Sampled
) -> None:
    kinds = set()
    for pair in report.pairs:
        key = (pair.link1, pair.link2)
        hits = sum(key in hit for hit in sampled.hits)
        if pair.collisions is None:  # an adjacent pair the SRDF disables: not sampled
            assert pair.kind == "adjacent" and not pair.checked
            continue
        _assert_share_is_scipys(pair.collisions, hits, N)
        kinds.add(pair.kind)
    assert kinds == {"default", "always", "never", "sometimes"}


def test_the_free_shares_are_the_samples_free_of_the_pairs_each_matrix_checks(
    report: CollisionReport, sampled: Sampled
) -> None:
    checked = {(p.link1, p.link2) for p in report.pairs if p.checked}
    sometimes = {(p.link1, p.link2) for p in report.pairs if p.kind == "sometimes"}
    assert ("base", "fin") in checked and ("arm2", "base") not in checked  # the SRDF's
    free = sum(not (hit & checked) for hit in sampled.hits)
    suggested = sum(not (hit & sometimes) for hit in sampled.hits)
    assert free == 0  # base and fin always collide, and the SRDF checks them
    assert 0.5 * N < suggested < N
    _assert_share_is_scipys(report.free, free, N)
    _assert_share_is_scipys(report.free_suggested, suggested, N)


def _runs(full: list[bool]) -> list[tuple[int, int]]:
    runs, start = [], None
    for i, on in enumerate([*full, False]):
        if on and start is None:
            start = i
        elif not on and start is not None:
            runs.append((start, i))
            start = None
    return runs


def test_the_ranges_are_the_bins_where_every_sample_collides(
    report: CollisionReport, sampled: Sampled
) -> None:
    sometimes = {(p.link1, p.link2) for p in report.pairs if p.kind == "sometimes"}
    free = np.array([not (hit & sometimes) for hit in sampled.hits])
    expected = []
    for column, coordinate in enumerate(sampled.space.coordinates):  # every one bounded R^1
        low, high = coordinate.lower, coordinate.upper
        bins = np.clip(np.floor((sampled.x[:, column] - low) / (high - low) * BINS), 0, BINS - 1)
        counts = [int(np.sum(bins == b)) for b in range(BINS)]
        full = [counts[b] >= MIN_RANGE_SAMPLES and not free[bins == b].any() for b in range(BINS)]
        for a, b in _runs(full):
            width = (high - low) / BINS
            expected.append((coordinate.name, low + a * width, low + b * width, sum(counts[a:b])))
    got = [(r.coordinate, r.low, r.high, r.samples) for r in report.ranges]
    assert got == [(n, pytest.approx(a), pytest.approx(b), k) for n, a, b, k in expected]
    [(name, low, high, inside)] = got  # the elbow, where arm2 reaches into the base
    assert name == "j2" and low == pytest.approx(2.2) and high == pytest.approx(2.5)
    bound = report.ranges[0].free_high
    assert bound == pytest.approx(scipy.stats.binomtest(0, inside).proportion_ci().high)


# --- MoveIt's semantics ------------------------------------------------------------------


def test_classes_and_the_srdfs_matrix_are_moveits(report: CollisionReport, rig: Path) -> None:
    srdf = str(rig / "robot.srdf")
    pairs = pairs_of(report)
    assert report.matrix == "srdf" and report.srdf == srdf
    assert report.links == ("base", "arm1", "arm2", "post", "fin")  # not `hollow`
    kinds = {key: p.kind for key, p in pairs.items()}
    assert kinds == {
        ("arm1", "arm2"): "adjacent",
        ("arm1", "base"): "adjacent",  # through `hollow`, which has no geometry
        ("base", "post"): "adjacent",
        ("fin", "post"): "adjacent",
        ("arm2", "post"): "default",  # j2 at 1.5, mid-range: 0 is outside [0.5, 2.5]
        ("base", "fin"): "always",  # not at the default: fin level, 1e-5 above the base
        ("arm2", "base"): "sometimes",
        ("arm2", "fin"): "sometimes",
        ("arm1", "fin"): "never",
        ("arm1", "post"): "never",
    }

    def rule(a: str, b: str) -> tuple[bool, str | None, int | None]:
        said = pairs[(a, b)].rule
        assert said is not None and said.file == srdf
        return said.checked, said.reason, said.line

    default = line_of(SRDF, '<disable_default_collisions link="fin"/>')
    assert rule("fin", "post") == (False, "disable_default_collisions", default)
    assert rule("arm1", "fin") == (False, "disable_default_collisions", default)
    # the pair's own entry before the links' defaults
    assert rule("base", "fin") == (True, "enable_collisions", line_of(SRDF, 'link2="fin"'))
    # <disable_collisions> is applied last: it wins over an <enable_collisions> after it
    assert rule("arm1", "post") == (False, "Never", line_of(SRDF, 'link2="post" reason="Never"'))
    assert rule("arm2", "post") == (True, None, None)  # no entry, no default: checked
    assert rule("arm1", "base") == (False, "Adjacent", line_of(SRDF, 'link2="base" reason="Adj'))


def test_the_default_configuration_is_moveits(rig: Path) -> None:
    oracle = Oracle(rig / "robot.urdf")
    # j1 and j3 at 0, j2 mid-range: arm2 through the post, the fin level and free
    assert oracle.colliding(np.array([0.0, 1.5, 0.0])) >= {("arm2", "post")}
    assert ("base", "fin") not in oracle.colliding(np.array([0.0, 1.5, 0.0]))
    assert ("base", "fin") in oracle.colliding(np.array([0.0, 1.5, 1e-3]))
    assert ("arm2", "post") not in oracle.colliding(np.array([0.0, 0.5, 0.0]))  # j2 at 0.5


def test_the_findings_say_what_moveit_would_miss_each_on_its_srdf_line(
    report: CollisionReport, rig: Path
) -> None:
    srdf = str(rig / "robot.srdf")
    found = [(d.code, d.severity.value, d.line, d.file) for d in report.diagnostics]
    assert found == [
        ("collision-unknown-link", "warning", line_of(SRDF, "ghost"), srdf),
        ("collision-unknown-link", "warning", line_of(SRDF, "phantom"), srdf),
        ("collision-disabled-but-reachable", "error", line_of(SRDF, '"arm2" link2="base"'), srdf),
        ("collision-disabled-but-reachable", "error", line_of(SRDF, 'link="fin"'), srdf),
        ("collision-at-default", "warning", None, srdf),
        ("collision-always", "error", line_of(SRDF, 'link2="fin"'), srdf),
        ("collision-pose", "warning", line_of(SRDF, '"bump"'), srdf),
    ]
    messages = {d.code: d.message for d in report.diagnostics}  # the last of each code
    arm2_base = pairs_of(report)[("arm2", "base")]
    assert arm2_base.collisions is not None and arm2_base.witness is not None
    reachable = report.diagnostics[2].message
    assert "'arm2' and 'base' (reason Never)" in reachable
    assert f"{arm2_base.collisions.hits:,} of {N:,} samples" in reachable
    assert f"{100 * arm2_base.collisions.share:.2f}%" in reachable
    assert f"e.g. sample {arm2_base.witness.sample}: j1=" in reachable
    assert "<disable_collisions> names 'ghost'" in report.diagnostics[0].message
    assert "<disable_default_collisions> names 'phantom'" in messages["collision-unknown-link"]
    assert "(reason disable_default_collisions)" in report.diagnostics[3].message
    assert "'arm/bump' (group_state) has 'arm2'-'post'" in messages["collision-pose"]
    [pose] = report.poses  # `clear` is free
    assert (pose.name, pose.pairs, pose.checked) == (
        "arm/bump",
        (("arm2", "post"),),
        (("arm2", "post"),),
    )


def test_exit_codes_follow_the_findings(rig: Path) -> None:
    args = ("robot.urdf", "--srdf", "robot.srdf", "-n", "300")
    errors = ("collision-disabled-but-reachable", "collision-always")
    ignored = [a for code in errors for a in ("--ignore", code)]
    assert cli(*args, cwd=rig).code == 1
    quiet = cli(*args, *ignored, cwd=rig)
    assert quiet.code == 0, quiet.stderr
    assert "collision-always" not in quiet.stdout and "collision-at-default" in quiet.stdout
    assert cli(*args, *ignored, "--strict", cwd=rig).code == 1  # warnings remain
    every = [a for code in (*errors, "collision-unknown-link", "collision-at-default",
                            "collision-pose") for a in ("--ignore", code)]  # fmt: skip
    assert cli(*args, *every, "--strict", cwd=rig).code == 0
    bad = cli(*args, "--ignore", "collision-nonsense", cwd=rig)
    assert bad.code == 2 and "invalid choice" in bad.stderr


SKIPPED = """<robot name="sk">
  <link name="a"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="b"><collision><origin xyz="0 0 0.3"/>
    <geometry><sphere radius="0.1"/></geometry></collision></link>
  <link name="c"><collision><geometry><mesh filename="missing.stl"/></geometry></collision></link>
  <link name="d"><collision><origin xyz="0 0 0.3"/>
    <geometry><sphere radius="0.1"/></geometry></collision></link>
  <link name="e"><collision><geometry><mesh filename="../outside.stl"/></geometry></collision>
    <collision><geometry><sphere radius="0.01"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.1"/>
    <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="k" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0 0 0.4"/>
    <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="l" type="fixed"><parent link="c"/><child link="d"/></joint>
  <joint name="m" type="fixed"><parent link="a"/><child link="e"/></joint>
</robot>
"""


def test_links_whose_meshes_cannot_be_had_are_left_out_with_a_finding(tmp_path: Path) -> None:
    project = tmp_path / "project"
    project.mkdir()
    (project / "robot.urdf").write_text(SKIPPED)
    facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
    (tmp_path / "outside.stl").write_text(f"solid x\n{facet}endloop\nendfacet\nendsolid x\n")
    run = cli("robot.urdf", "-n", "400", "--format", "json", cwd=project)
    assert run.code == 1, run.stderr  # the robot gets its report, a pair left out fails
    document = json.loads(run.stdout)
    assert document["links"] == ["a", "b", "d"]
    assert {(p["link1"], p["link2"]) for p in document["pairs"]} == {
        ("a", "b"),
        ("a", "d"),
        ("b", "d"),
    }
    kinds = {(p["link1"], p["link2"]): p["kind"] for p in document["pairs"]}
    assert kinds[("b", "d")] != "adjacent"  # c has geometry, unread: not looked through
    skipped = [(d["code"], d["line"], d["message"]) for d in document["diagnostics"]]
    assert [s[:2] for s in skipped] == [
        ("collision-skipped", line_of(SKIPPED, "missing.stl")),
        ("collision-skipped", line_of(SKIPPED, "outside.stl")),
    ]
    assert "link 'c': mesh 'missing.stl': no such file" in skipped[0][2]
    assert "link 'e': mesh '../outside.stl': it leads out of the folders" in skipped[1][2]
    ignored = cli("robot.urdf", "-n", "400", "--ignore", "collision-skipped", cwd=project)
    assert ignored.code == 0, ignored.stderr


def test_an_unreadable_robot_or_srdf_is_one_line_naming_the_file(rig: Path) -> None:
    (rig / "broken.urdf").write_text('<robot name="x"><link name="a"></robot>\n')
    (rig / "broken.srdf").write_text('<robot name="rig"><disable_collisions link1="a"\n')
    one_line_error(cli("broken.urdf", cwd=rig), "broken.urdf")
    one_line_error(cli("absent.urdf", cwd=rig), "absent.urdf", "[file-unreadable]")
    one_line_error(cli("robot.urdf", "--srdf", "broken.srdf", cwd=rig), "broken.srdf")
    one_line_error(cli("robot.urdf", "--srdf", "absent.srdf", cwd=rig), "absent.srdf")


# --- --write-srdf --------------------------------------------------------------------------


def test_the_srdf_written_reads_back_and_leaves_nothing_to_fix(rig: Path) -> None:
    args = ("robot.urdf", "--srdf", "robot.srdf", "-n", "1200", "--seed", "2")
    first = cli(*args, "--write-srdf", "suggested.srdf", "--format", "json", cwd=rig)
    assert first.code == 1, first.stderr
    written = (rig / "suggested.srdf").read_bytes()
    again = cli(*args, "--write-srdf", "again.srdf", cwd=rig, env=HASH_SEED[1])
    assert again.code == 1 and (rig / "again.srdf").read_bytes() == written
    parsed = parse_srdf(read_source(str(rig / "suggested.srdf")))
    disabled = {(p.link1, p.link2): p.reason for p in parsed.collision_pairs if p.disable}
    reasons = {"adjacent": "Adjacent", "default": "Default", "always": "Always", "never": "Never"}
    pairs = json.loads(first.stdout)["pairs"]
    assert disabled == {
        (p["link1"], p["link2"]): reasons[p["kind"]] for p in pairs if p["kind"] in reasons
    }
    assert ("base", "fin") in disabled and ("arm2", "base") not in disabled
    # the next run, with the same seed, reads it as its matrix
    checked = cli("robot.urdf", "--srdf", "suggested.srdf", *args[3:], "--format", "json", cwd=rig)
    document = json.loads(checked.stdout)
    codes = {d["code"] for d in document["diagnostics"]}
    assert not codes & {"collision-disabled-but-reachable", "collision-always"}
    assert checked.code == 0, checked.stdout
    assert document["free"] == document["free_suggested"]


def test_the_srdf_is_never_written_through_a_link(rig: Path, tmp_path: Path) -> None:
    target = tmp_path / "target.srdf"
    target.write_text("old\n")
    link = rig / "linked.srdf"
    link.symlink_to(target)
    try:
        run = cli("robot.urdf", "-n", "50", "--write-srdf", "linked.srdf", cwd=rig)
        one_line_error(run, "linked.srdf", "[bad-output]")
        assert target.read_text() == "old\n" and link.is_symlink()
    finally:
        link.unlink()


def test_names_that_xml_escapes_are_written_and_read_back(tmp_path: Path) -> None:
    name = 'b"<&c'
    escaped = "b&quot;&lt;&amp;c"
    (tmp_path / "r.urdf").write_text(
        '<robot name="r&amp;s"><link name="a"><collision><geometry><box size="1 1 1"/>'
        f'</geometry></collision></link><link name="{escaped}"><collision><geometry>'
        '<sphere radius="0.1"/></geometry></collision></link><joint name="j" type="prismatic">'
        f'<parent link="a"/><child link="{escaped}"/><axis xyz="0 0 1"/>'
        '<limit lower="0" upper="2" effort="1" velocity="1"/></joint></robot>\n'
    )
    assert cli("r.urdf", "-n", "200", "--write-srdf", "r.srdf", cwd=tmp_path).code == 0
    parsed = parse_srdf(read_source(str(tmp_path / "r.srdf")))
    assert [(p.link1, p.link2, p.reason) for p in parsed.collision_pairs] == [
        ("a", name, "Adjacent")
    ]
    back = cli("r.urdf", "--srdf", "r.srdf", "-n", "200", "--format", "json", cwd=tmp_path)
    [pair] = json.loads(back.stdout)["pairs"]
    assert (pair["link1"], pair["link2"], pair["rule"]["checked"]) == ("a", name, False)
    assert json.loads(back.stdout)["diagnostics"] == []


# --- witnesses ---------------------------------------------------------------------------


def test_each_witness_is_the_first_sample_of_its_pair_and_collides(
    report: CollisionReport, sampled: Sampled
) -> None:
    names = sampled.space.names
    witnessed = 0
    for pair in report.pairs:
        key = (pair.link1, pair.link2)
        if pair.collisions is None:
            continue
        first = next((i for i, hit in enumerate(sampled.hits) if key in hit), None)
        if first is None:
            assert pair.witness is None
            continue
        assert pair.witness is not None and pair.witness.sample == first
        x = np.array([dict(pair.witness.configuration)[n][0] for n in names])
        assert np.array_equal(x, sampled.x[first])  # the sample its index draws
        q = sampled.space.conventions().to_pinocchio(x)
        assert key in sampled.oracle.colliding(q)
        witnessed += 1
    assert witnessed == 4  # default, always and both sometimes


TUMBLER = """<robot name="tumbler">
  <link name="a"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="m"/>
  <link name="b"><collision><origin xyz="0 0 0.3"/>
    <geometry><sphere radius="0.15"/></geometry></collision></link>
  <link name="c"><collision><origin xyz="0 0 0.3"/>
    <geometry><box size="0.1 0.1 0.3"/></geometry></collision></link>
  <joint name="spin" type="continuous"><parent link="a"/><child link="m"/>
    <axis xyz="1 0 0"/></joint>
  <joint name="free" type="floating"><parent link="m"/><child link="b"/></joint>
  <joint name="tip" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""
"""A continuous joint, a floating joint (its position held, its rotation sampled on SO(3))
and a revolute joint: coordinates of every kind in a witness."""


def test_a_witness_of_circles_and_rotations_collides(tmp_path: Path) -> None:
    path = tmp_path / "tumbler.urdf"
    path.write_text(TUMBLER)
    report = cspace.collisions(path, samples=400, seed=4)
    [pair] = [p for p in report.pairs if p.kind == "sometimes"]
    assert (pair.link1, pair.link2) == ("a", "c") and pair.witness is not None
    configuration = dict(pair.witness.configuration)
    space = cspace.load(path)
    assert list(configuration) == list(space.names)
    assert [configuration[f"free.{k}"][0] for k in "xyz"] == [0.0, 0.0, 0.0]
    rotation = np.array([configuration[f"free.q{k}"][0] for k in "wxyz"])
    assert np.linalg.norm(rotation) == pytest.approx(1.0)
    x = np.array([values[0] for values in configuration.values()])
    assert np.array_equal(x, drawn(space, 4, pair.witness.sample + 1)[-1])
    oracle = Oracle(path)
    assert ("a", "c") in oracle.colliding(space.conventions().to_pinocchio(x))


def test_a_witness_on_meshes_collides_in_pinocchios_own_pipeline() -> None:
    report = cspace.collisions("erd:ur5", samples=300, seed=1, srdf=True)
    [*reachable] = (d for d in report.diagnostics if d.code == "collision-disabled-but-reachable")
    assert reachable
    space = cspace.load("erd:ur5")
    urdf = str(resolve("ur5")[0])
    model = pin.buildModelFromUrdf(urdf)
    geometry = pin.buildGeomFromUrdf(model, urdf, pin.COLLISION, package_dirs=[str(SHARE)])
    geometry.addAllCollisionPairs()
    data, geometry_data = model.createData(), pin.GeometryData(geometry)
    links = [model.frames[g.parentFrame].name for g in geometry.geometryObjects]
    checked = 0
    for pair in report.pairs:
        if pair.kind != "sometimes" or pair.rule is None or pair.rule.checked:
            continue
        assert pair.witness is not None
        x = np.array([dict(pair.witness.configuration)[n][0] for n in space.names])
        q = space.conventions().to_pinocchio(x)
        pin.computeCollisions(model, data, geometry, geometry_data, q, False)
        hit = {
            link_pair(links[p.first], links[p.second])
            for p, r in zip(geometry.collisionPairs, geometry_data.collisionResults, strict=True)
            if r.isCollision()
        }
        assert (pair.link1, pair.link2) in hit
        checked += 1
    assert checked == len(reachable)


def test_talos_srdf_disables_wrist_pairs_that_collide() -> None:
    """example-robot-data's talos.srdf disables each arm's fifth link against its wrist's
    force sensor as Never; they collide in about 12% of samples. The finding is on the
    SRDF's own line of that element, found here by reading the file."""
    report = cspace.collisions("erd:talos", samples=400, seed=3, srdf=True)
    assert report.matrix == "srdf" and report.srdf is not None
    lines = Path(report.srdf).read_text().splitlines()
    for side in ("left", "right"):
        names = (f"arm_{side}_5_link", f"wrist_{side}_ft_link")
        [line] = [
            k + 1
            for k, text in enumerate(lines)
            if "disable_collisions" in text and all(f'"{n}"' in text for n in names)
        ]
        [found] = [
            d
            for d in report.diagnostics
            if d.code == "collision-disabled-but-reachable" and all(n in d.message for n in names)
        ]
        assert (found.line, found.file) == (line, report.srdf)
        [pair] = [p for p in report.pairs if (p.link1, p.link2) == tuple(sorted(names))]
        assert pair.kind == "sometimes" and pair.collisions is not None
        assert 0.05 < pair.collisions.share < 0.25


# --- arguments ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("-n", "0"), ["argument -n", "got 0"]),
        (("-n", "1000001"), ["at most 1,000,000", "[bad-argument]"]),
        (("--seed", "-1"), ["argument --seed", "'-1'"]),
        (("-j", "0"), ["argument -j/--jobs"]),
        (("--limits", "limits.yaml"), ["--limits does not apply", "[bad-argument]"]),
        (("--group", "arm"), ["--group does not apply"]),
        (("--hold", "bump"), ["--hold does not apply"]),
    ],
)
def test_arguments_out_of_range_are_refused_in_one_line(
    rig: Path, args: tuple[str, ...], words: list[str]
) -> None:
    one_line_error(cli("robot.urdf", "--srdf", "robot.srdf", *args, cwd=rig), *words)


def test_standard_input_is_refused_and_a_file_named_dash_is_read(rig: Path) -> None:
    run = cli("-", "-n", "10", cwd=rig, stdin=RIG.encode())
    one_line_error(run, "not standard input", "[bad-argument]")
    (rig / "-").write_text(RIG)
    try:
        one_line_error(cli("-", "-n", "10", cwd=rig), "[ambiguous-name]")
        named = cli("-n", "10", "--", "-", cwd=rig)
        assert named.code == 0 and named.stdout.startswith("rig: "), named.stderr
    finally:
        (rig / "-").unlink()


def test_a_robot_with_closed_loops_is_refused() -> None:
    run = cli("tests/closed/fourbar.sdf", "-n", "10", cwd=REPO)
    one_line_error(run, "fourbar.sdf", "closed loops", "[collisions-loops]")


def test_a_robot_without_collision_shapes_is_all_free() -> None:
    run = cli("robots/arm7.urdf", "-n", "50", "--format", "json", cwd=REPO)
    assert run.code == 0, run.stderr
    document = json.loads(run.stdout)
    assert (document["links"], document["pairs"], document["ranges"]) == ([], [], [])
    for free in (document["free"], document["free_suggested"]):
        assert (free["hits"], free["samples"], free["share"], free["high"]) == (50, 50, 1.0, 1.0)
        assert free["low"] == pytest.approx(0.025 ** (1 / 50))
    text = cli("robots/arm7.urdf", "-n", "50", cwd=REPO)
    assert text.code == 0 and "free of self-collision:       100.00%" in text.stdout


def test_the_library_refuses_bad_counts_before_reading(tmp_path: Path) -> None:
    absent = tmp_path / "absent.urdf"
    for keywords in (
        {"samples": 0},
        {"samples": True},
        {"samples": 1_000_001},
        {"seed": -1},
        {"seed": 1.5},
        {"jobs": 0},
    ):
        with pytest.raises(ArgumentError):
            cspace.collisions(absent, **keywords)
    with pytest.raises(cspace.RobotFileError, match=r"absent\.urdf"):
        cspace.collisions(absent)


def test_the_library_is_the_command(rig: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    args = ("robot.urdf", "--srdf", "robot.srdf", "-n", "700", "--seed", str(SEED))
    run = cli(*args, "--format", "json", cwd=rig)
    monkeypatch.chdir(rig)
    report = cspace.collisions("robot.urdf", samples=700, seed=SEED, srdf="robot.srdf")
    assert json.loads(run.stdout) == json.loads(json.dumps(report.to_dict()))


def test_an_mjcf_robot_is_checked_against_mujocos_filters() -> None:
    pytest.importorskip("cspace._model._collision_mjcf")
    args = ("robots/mjcf_balls.xml", "-n", "300", "--format", "json")
    first, second = (cli(*args, cwd=REPO, env=env) for env in HASH_SEED)
    assert first.code in (0, 1) and first.stdout == second.stdout, first.stderr
    document = json.loads(first.stdout)
    assert document["matrix"] == "mjcf" and document["srdf"] is None
    assert document["pairs"] and all(p["rule"] is not None for p in document["pairs"])
    assert math.isclose(document["free"]["share"], document["free"]["hits"] / 300)
    assert os.path.basename(document["source"]["path"]) == "mjcf_balls.xml"


HELD = """<robot name="held">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="mid"/>
  <link name="tip"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <joint name="spin" type="continuous"><parent link="base"/><child link="mid"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="float" type="floating"><parent link="mid"/><child link="tip"/>
    <origin xyz="1 0 0"/></joint>
</robot>
"""


def test_an_inner_joint_without_limits_is_held_and_said(tmp_path: Path) -> None:
    """A floating joint below another joint is held at neutral (its position unsampled),
    with a warning; the root's floating joint, added with --root-joint, is held silently."""
    (tmp_path / "held.urdf").write_text(HELD)
    report = cspace.collisions(tmp_path / "held.urdf", samples=50, root_joint="floating")
    held = [(d.code, d.joint) for d in report.diagnostics if d.code == "collision-held"]
    assert held == [("collision-held", "float")]
    assert report.has(cspace.Severity.WARNING) and not report.has(cspace.Severity.ERROR)


FOLDED = """<robot name="folded">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="mid"><collision><origin xyz="0 0 5"/><geometry><sphere radius="0.1"/></geometry>
    </collision></link>
  <link name="tip"><collision><origin xyz="-0.15 0 0"/><geometry><box size="0.2 0.2 0.2"/>
    </geometry></collision></link>
  <joint name="m" type="fixed"><parent link="base"/><child link="mid"/></joint>
  <joint name="t" type="revolute"><parent link="mid"/><child link="tip"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""


@pytest.mark.parametrize(("reason", "said"), [("Never", True), ("User", True), ("Default", False)])
def test_a_pair_disabled_as_never_that_collides_at_the_default_pose(
    tmp_path: Path, reason: str, said: bool
) -> None:
    """base and tip overlap at the default configuration (and in about a third of the
    samples): disabled as Default, that is the setup assistant's rule; as Never or by hand
    (User), the default configuration itself disproves the claim."""
    (tmp_path / "folded.urdf").write_text(FOLDED)
    (tmp_path / "folded.srdf").write_text(
        '<robot name="folded">\n'
        f'  <disable_collisions link1="base" link2="tip" reason="{reason}"/>\n</robot>\n'
    )
    report = cspace.collisions(tmp_path / "folded.urdf", samples=300, srdf=tmp_path / "folded.srdf")
    [pair] = [p for p in report.pairs if (p.link1, p.link2) == ("base", "tip")]
    assert pair.kind == "default" and pair.collisions is not None
    assert 0.1 < pair.collisions.share < 0.9
    found = [d for d in report.diagnostics if d.code == "collision-disabled-but-reachable"]
    assert [(d.line, d.file) for d in found] == (
        [(2, str(tmp_path / "folded.srdf"))] if said else []
    )
