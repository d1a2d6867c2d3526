"""A root joint declared in one file and added by cspace to the other is one joint.

``cspace diff solo12.urdf tests/pairs/solo12.xml --old-root-joint floating``: the URDF
with the free joint ``root_joint`` that the flag adds, against the MJCF whose file
declares the free joint ``root_joint`` above the same link. The configurations are the
same, so the verdict is ``same`` (exit 0, the JSON as for two identical files) and where
each is declared is a note, in every format. A flag, ``--new-root-joint`` and an SRDF's
virtual joint add it alike, in either direction. Another link, another kind, or a body
welded to the world on one side and floating with the root on the other stays a change.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

import cspace
from cspace._formats.erd import robots_dir
from cspace.diff import Change, ReportDiff, diff_reports

from conftest import REPO, Run, run_cli_many

SOLO = robots_dir() / "solo_description" / "robots" / "solo12.urdf"
SOLO_MJCF = REPO / "tests" / "pairs" / "solo12.xml"
SAME = "no C-space change: R^15 × RP^3 (dimension 18)"
ADDED = "floating 'root_joint' (added by cspace)"
IN_FILE = "floating 'root_joint' (in the file)"

_SRDF = """<?xml version="1.0"?>
<robot name="solo">
  <virtual_joint name="world_joint" type="floating" parent_frame="world" child_link="base_link"/>
</robot>
"""
_DECLARED = (
    '<link name="world"/><joint name="root_joint" type="floating">'
    '<parent link="world"/><child link="base_link"/></joint><link name="base_link">'
)


def _mjcf(top: str) -> str:
    """An MJCF robot: body ``a`` (its first element ``top``) with a hinged child ``b``."""
    return (
        "<mujoco><worldbody><body name='a'>"
        f"{top}<geom size='0.1'/><body name='b'><joint name='j1' range='-1 1'/>"
        "<geom size='0.1'/></body></body></worldbody></mujoco>"
    )


_CART_URDF = """<robot name="cart">
  <link name="base"/><link name="arm"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""
_CART_PLANAR_URDF = _CART_URDF.replace(
    '<link name="base"/>',
    '<link name="world"/><link name="base"/><joint name="root_joint" type="planar">'
    '<parent link="world"/><child link="base"/><axis xyz="0 0 1"/></joint>',
)
_CART_MJCF = """<mujoco><compiler angle="radian"/><worldbody><body name="base">
  <joint name="root_joint_TX" type="slide" axis="1 0 0"/>
  <joint name="root_joint_TY" type="slide" axis="0 1 0"/>
  <joint name="root_joint_RZ" type="hinge" axis="0 0 1"/><geom size="0.1"/>
  <body name="arm"><joint name="j1" axis="0 0 1" range="-1 1"/><geom size="0.1"/></body>
</body></worldbody></mujoco>
"""


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The robot files the cases read, beside the two of the issue."""
    folder = tmp_path_factory.mktemp("roots")
    solo = SOLO.read_text()
    mjcf = SOLO_MJCF.read_text()
    assert '<link name="base_link">' in solo and '<body name="base_link">' in mjcf
    texts = {
        "solo_srdf.srdf": _SRDF,
        "solo_declared.urdf": solo.replace('<link name="base_link">', _DECLARED, 1),
        "solo_trunk.xml": mjcf.replace('<body name="base_link">', '<body name="trunk">'),
        "solo_floating_base.xml": mjcf.replace(
            '<freejoint name="root_joint"/>', '<freejoint name="floating_base"/>'
        ),
        "one.xml": _mjcf(""),
        "free.xml": _mjcf("<freejoint name='root_joint'/>"),
        "cart.urdf": _CART_URDF,
        "cart_planar.urdf": _CART_PLANAR_URDF,
        "cart.xml": _CART_MJCF,
    }
    # a second body at the top, hinged to the world: cspace's root joint on this MJCF
    # floats the world body, which carries it; the file's free joint floats 'a' alone
    second = "<body name='c' pos='1 0 0'><joint name='jc' range='-1 1'/><geom size='0.1'/></body>"
    texts["two.xml"] = texts["one.xml"].replace("</worldbody>", f"{second}</worldbody>")
    texts["two_free.xml"] = texts["free.xml"].replace("</worldbody>", f"{second}</worldbody>")
    for name, text in texts.items():
        (folder / name).write_text(text)
    return {Path(name).stem if name.endswith(".srdf") else name: folder / name for name in texts}


@pytest.fixture(scope="module")
def reports(files: dict[str, Path]) -> dict[str, cspace.Report]:
    """Each side's report, made by the public API."""
    return {
        "flag": cspace.inspect(SOLO, "floating"),
        "planar flag": cspace.inspect(SOLO, "planar"),
        "srdf": cspace.inspect(SOLO, srdf=files["solo_srdf"]),
        "mjcf": cspace.inspect(SOLO_MJCF),
        "urdf declared": cspace.inspect(files["solo_declared.urdf"]),
        "mjcf trunk": cspace.inspect(files["solo_trunk.xml"]),
        "mjcf floating_base": cspace.inspect(files["solo_floating_base.xml"]),
        "one flag": cspace.inspect(files["one.xml"], "floating"),
        "free": cspace.inspect(files["free.xml"]),
        "two flag": cspace.inspect(files["two.xml"], "floating"),
        "two free": cspace.inspect(files["two_free.xml"]),
        "cart flag": cspace.inspect(files["cart.urdf"], "planar"),
        "cart declared": cspace.inspect(files["cart_planar.urdf"]),
        "cart mjcf": cspace.inspect(files["cart.xml"]),
    }


@pytest.fixture(scope="module")
def runs(files: dict[str, Path]) -> dict[str, Run]:
    """``cspace diff`` of the issue's pair in each format, as a user runs it."""
    forward = ("diff", str(SOLO), str(SOLO_MJCF), "--old-root-joint", "floating")
    reverse = ("diff", str(SOLO_MJCF), str(SOLO), "--new-root-joint", "floating")
    commands = {
        "text": (*forward, "--width", "300"),
        "json": (*reverse, "--format", "json"),
        "markdown": (*forward, "--format", "markdown"),
        "html": (*reverse, "--format", "html"),
        "trunk": ("diff", str(SOLO), str(files["solo_trunk.xml"]), "--old-root-joint", "floating"),
    }
    done = run_cli_many(list(commands.values()))
    return dict(zip(commands, done, strict=True))


def _rows(text: str, header: str) -> list[list[str]]:
    """The cells of each row of the text table whose header starts with ``header``."""
    lines = text.splitlines()
    start = next(k for k, line in enumerate(lines) if re.match(rf"{header}\s{{2,}}joint\s", line))
    rows = []
    for line in lines[start + 2 :]:
        if not line.strip():
            break
        rows.append(re.split(r"\s{2,}", line.strip()))
    return rows


def _paired(diff: ReportDiff) -> list[tuple[str | None, str, str]]:
    return [(n.joint, n.before, n.after) for n in diff.notes if n.kind == "root-joint-paired"]


def test_the_issues_pair_is_the_same_in_text(runs: dict[str, Run]) -> None:
    run = runs["text"]
    assert (run.code, run.stderr) == (0, ""), run.stdout + run.stderr
    assert run.stdout.startswith(f"{SAME}\n"), run.stdout
    assert "C-space changed" not in run.stdout and "\nchange " not in run.stdout
    assert "notes (how the two files store or name it; the C-space is the same):" in run.stdout
    assert ["root joints paired", "root_joint", ADDED, IN_FILE] in _rows(run.stdout, "note")


def test_the_issues_pair_reversed_is_the_same_in_json(
    runs: dict[str, Run], reports: dict[str, cspace.Report]
) -> None:
    """The JSON verdict is the one of a file diffed against itself."""
    run = runs["json"]
    assert run.code == 0, run.stdout + run.stderr
    document = json.loads(run.stdout)
    itself = diff_reports(reports["mjcf"], reports["mjcf"]).to_dict()
    assert itself["verdict"] == "same"
    for key in ("verdict", "changed", "changes", "old", "tolerance", "rel_tolerance"):
        expected = itself[key] | {"path": str(SOLO_MJCF)} if key == "old" else itself[key]
        assert document[key] == expected, key
    assert {
        "kind": "root-joint-paired",
        "joint": "root_joint",
        "before": IN_FILE,
        "after": ADDED,
    } in document["notes"]


def test_the_issues_pair_is_the_same_in_markdown(runs: dict[str, Run]) -> None:
    run = runs["markdown"]
    assert run.code == 0, run.stdout + run.stderr
    assert run.stdout.startswith("### cspace: no C-space change in "), run.stdout
    assert "| change |" not in run.stdout
    assert f"| root joints paired | `root_joint` | `{ADDED}` | `{IN_FILE}` |" in run.stdout


def test_the_issues_pair_reversed_is_the_same_in_html(runs: dict[str, Run]) -> None:
    run = runs["html"]
    assert run.code == 0, run.stdout + run.stderr
    page = etree.fromstring(run.stdout.encode(), etree.HTMLParser())
    assert "".join(page.find(".//h1").itertext()) == "No C-space change"
    assert not page.xpath("//table[@class='changes']")
    notes = ["".join(li.itertext()) for li in page.xpath("//h2[.='Notes']/following::ul[1]/li")]
    assert f"root joints paired root_joint: {IN_FILE} → {ADDED}" in notes


SAME_PAIRS = [
    ("flag", "mjcf", ADDED, IN_FILE),
    ("srdf", "mjcf", "floating 'root_joint' (the SRDF's virtual joint 'world_joint')", IN_FILE),
    ("flag", "urdf declared", ADDED, IN_FILE),
    ("one flag", "free", ADDED, IN_FILE),
    ("cart flag", "cart declared", "planar 'root_joint' (added by cspace)", None),
    ("cart flag", "cart mjcf", "planar 'root_joint' (added by cspace)", None),
]


@pytest.mark.parametrize(("added", "declared", "added_text", "declared_text"), SAME_PAIRS)
@pytest.mark.parametrize("reverse", [False, True], ids=["added-old", "added-new"])
def test_a_root_joint_declared_or_added_is_one_joint(
    reports: dict[str, cspace.Report],
    added: str,
    declared: str,
    added_text: str,
    declared_text: str | None,
    reverse: bool,
) -> None:
    """Either side may hold the added one; the verdict and the JSON are those of a file
    against itself; the note says where each side's root joint is declared."""
    old, new = (
        (reports[declared], reports[added]) if reverse else (reports[added], reports[declared])
    )
    diff = diff_reports(old, new)
    assert diff.changes == () and diff.verdict == "same", diff.changes
    itself = diff_reports(new, new).to_dict()
    assert {k: diff.to_dict()[k] for k in ("verdict", "changed", "changes")} == {
        k: itself[k] for k in ("verdict", "changed", "changes")
    }
    kind = "planar" if added.startswith("cart") else "floating"
    declared_text = declared_text or f"{kind} 'root_joint' (in the file)"
    texts = (declared_text, added_text) if reverse else (added_text, declared_text)
    assert _paired(diff) == [("root_joint", *texts)]


def test_a_split_planar_root_is_folded_and_paired(reports: dict[str, cspace.Report]) -> None:
    diff = diff_reports(reports["cart flag"], reports["cart mjcf"])
    assert [n.kind for n in diff.notes][:2] == ["root-joint-paired", "planar-split"]


def test_both_sides_added_by_flags_alike_need_no_note(reports: dict[str, cspace.Report]) -> None:
    again = cspace.inspect(SOLO, "floating")
    diff = diff_reports(reports["flag"], again)
    assert (diff.verdict, diff.changes, diff.notes) == ("same", (), ())
    srdf = diff_reports(reports["srdf"], reports["flag"])  # an SRDF and a flag: both add it
    assert (srdf.verdict, srdf.changes, srdf.notes) == ("same", (), ())


CHANGED = [
    # the free joint above a link the URDF has not: another body
    ("flag", "mjcf trunk", ("floating", "-"), ["root-joint"]),
    # a planar root added against the file's free joint
    ("planar flag", "mjcf", ("planar", "-"), ["manifold", "root-joint", "joint-retyped"]),
    # the world body floats with the body 'c' hinged to it, where the file's 'c' stays put
    ("two flag", "two free", ("floating", "-"), ["root-joint"]),
    # two flags of two kinds
    ("planar flag", "flag", ("planar", "floating"), ["manifold", "root-joint", "joint-retyped"]),
]


@pytest.mark.parametrize(("old", "new", "root", "kinds"), CHANGED, ids=lambda v: str(v))
@pytest.mark.parametrize("reverse", [False, True], ids=["forward", "reverse"])
def test_another_body_or_kind_is_still_a_change(
    reports: dict[str, cspace.Report],
    old: str,
    new: str,
    root: tuple[str, str],
    kinds: list[str],
    reverse: bool,
) -> None:
    a, b = (reports[new], reports[old]) if reverse else (reports[old], reports[new])
    diff = diff_reports(a, b)
    assert diff.verdict == "changed" and not _paired(diff), diff.notes
    assert set(kinds) <= {c.kind for c in diff.changes}, diff.changes
    before, after = root[::-1] if reverse else root
    assert Change("root-joint", None, before, after) in diff.changes


def test_another_body_is_a_change_on_the_command_line(runs: dict[str, Run]) -> None:
    run = runs["trunk"]
    assert run.code == 1, run.stdout + run.stderr
    assert run.stdout.startswith(
        "C-space changed: same normal form, R^15 × RP^3 (dimension 18), "
        "but not the same configurations\n"
    )
    assert ["root joint", "-", "floating", "-"] in _rows(run.stdout, "change")


def test_a_root_joint_under_another_name_is_paired_as_renamed(
    reports: dict[str, cspace.Report],
) -> None:
    """The file's free joint ``floating_base`` above the same link: paired with the one
    cspace adds (its name is cspace's, not the user's), and the note names both; with
    ``--map root_joint=floating_base`` the same."""
    for renames in (None, {"root_joint": "floating_base"}):
        diff = diff_reports(reports["flag"], reports["mjcf floating_base"], renames=renames)
        assert diff.verdict == "same", diff.changes
        assert _paired(diff) == [("floating_base", ADDED, "floating 'floating_base' (in the file)")]


def _document(report: cspace.Report) -> dict[str, Any]:
    return json.loads(json.dumps(report.to_dict()))


def test_saved_reports_pair_as_the_files_do(reports: dict[str, cspace.Report]) -> None:
    """A report saved as JSON (``inspect --format json``) keeps where its root joint came
    from: the diff of saved reports is the diff of the files."""
    saved = diff_reports(_document(reports["srdf"]), _document(reports["mjcf"]))
    assert saved.to_dict() == diff_reports(reports["srdf"], reports["mjcf"]).to_dict()
    assert saved.verdict == "same"
