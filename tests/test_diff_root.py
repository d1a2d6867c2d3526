"""A root joint declared in one file and added by cspace to the other is one joint.

``cspace diff solo12.urdf tests/pairs/solo12.xml --old-root-joint floating``: the URDF
with the free joint ``root_joint`` that the flag adds, against the MJCF whose file
declares the free joint ``root_joint`` above the same link. The configurations are the
same, so the verdict is ``same`` (exit 0, the JSON as for two identical files) and where
each is declared is a note, in every format. A flag, ``--new-root-joint`` and an SRDF's
virtual joint add it alike, in either direction. Another link, another kind, other links
carried (a body welded to the world on one side, floating with the root on the other),
or a file's joint placed off the world's origin (a URDF ``<origin>``, a fixed joint above
it, MuJoCo's slides on a body placed elsewhere) stays a change: the same q puts the robot
elsewhere. Saved reports diff as their files do.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

import cspace
from cspace._formats.shared.erd import robots_dir
from cspace.diff import Change, ReportDiff, diff_reports

from conftest import PEAK_MIB, REPO, Run, measured, run_cli_many

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


_ARM_URDF = """<robot name="r">
  <link name="base_link"/><link name="arm"/>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _arm_rooted(joint: str, links: str = '<link name="world"/>') -> str:
    """The arm with ``links`` and a joint ``joint`` (a URDF <joint> element) above it."""
    return _ARM_URDF.replace('<link name="base_link"/>', f'{links}<link name="base_link"/>{joint}')


def _arm_root(kind: str, origin: str = "", parent: str = "world") -> str:
    """A root joint ``root_joint`` of ``kind`` from ``parent`` to the arm's base_link."""
    return (
        f'<joint name="root_joint" type="{kind}">{origin}<parent link="{parent}"/>'
        '<child link="base_link"/><axis xyz="0 0 1"/></joint>'
    )


# the world holds the arm's base (bolt) and a table beside it (tbl); then the arm floats
# from the world (root_joint) and the table stays
_BOLT = '<joint name="bolt" type="fixed"><parent link="world"/><child link="base_link"/></joint>'
_TABLE = (
    '<link name="table"/><joint name="tbl" type="fixed"><parent link="world"/>'
    '<child link="table"/><origin xyz="2 0 0"/></joint>'
)
_W_MJCF = """<mujoco><compiler angle="radian"/><worldbody>
  <body name="base_link">ROOT<geom size="0.1"/>
    <body name="arm"><joint name="j1" axis="0 0 1" range="-1 1"/><geom size="0.1"/></body>
  </body>
  <body name="table" pos="2 0 0"><geom type="box" size="0.5 0.5 0.5"/></body>
</worldbody></mujoco>
"""
# the arm's base with a free joint of its own, its body's pose its starting value
_ARM_FREE_MJCF = """<mujoco><compiler angle="radian"/><worldbody>
  <body name="base_link" pos="0.5 0 1" euler="0.3 0 0.2"><freejoint name="root_joint"/>
    <geom size="0.1"/>
    <body name="arm"><joint name="j1" axis="0 0 1" range="-1 1"/><geom size="0.1"/></body>
  </body>
</worldbody></mujoco>
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
        # MuJoCo's planar triple, its body off the world's origin, turned to stand on
        # its side, or its hinge turning about another point than the body's origin
        "cart_high.xml": _CART_MJCF.replace('<body name="base">', '<body name="base" pos="0 0 1">'),
        "cart_tilted.xml": _CART_MJCF.replace(
            '<body name="base">', '<body name="base" euler="1.5707963 0 0">'
        ),
        "cart_anchored.xml": _CART_MJCF.replace(
            'type="hinge" axis="0 0 1"', 'type="hinge" axis="0 0 1" pos="0.5 0 0"'
        ),
        "arm.urdf": _ARM_URDF,
        "arm_tilted.urdf": _arm_rooted(
            _arm_root("planar", '<origin xyz="0 0 0" rpy="1.5707963 0 0"/>')
        ),
        "arm_high.urdf": _arm_rooted(_arm_root("floating", '<origin xyz="0 0 1"/>')),
        "arm_higher.urdf": _arm_rooted(
            _arm_root("floating", '<origin xyz="0 0 5" rpy="1.5 0 0"/>')
        ),
        "arm_declared.urdf": _arm_rooted(_arm_root("floating")),
        "arm_planar.urdf": _arm_rooted(_arm_root("planar")),
        # URDF and Drake move it in the y-z plane, Pinocchio in the x-y one
        "arm_planar_x.urdf": _arm_rooted(_arm_root("planar").replace("0 0 1", "1 0 0")),
        # the root joint at the identity, on a mount a fixed joint lifts by 1 m
        "arm_mounted.urdf": _arm_rooted(
            _arm_root("floating", parent="mount")
            + '<joint name="lift" type="fixed"><parent link="world"/><child link="mount"/>'
            '<origin xyz="0 0 1"/></joint>',
            '<link name="world"/><link name="mount"/>',
        ),
        "arm_free.xml": _ARM_FREE_MJCF,
        "w_fixed.urdf": _arm_rooted(_BOLT, f'<link name="world"/>{_TABLE}'),
        "w_float.urdf": _arm_rooted(_arm_root("floating"), f'<link name="world"/>{_TABLE}'),
        "w_fixed.xml": _W_MJCF.replace("ROOT", ""),
        "w_float.xml": _W_MJCF.replace("ROOT", '<freejoint name="root_joint"/>'),
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
        "cart mjcf high": cspace.inspect(files["cart_high.xml"]),
        "cart mjcf tilted": cspace.inspect(files["cart_tilted.xml"]),
        "cart mjcf anchored": cspace.inspect(files["cart_anchored.xml"]),
        "arm flag": cspace.inspect(files["arm.urdf"], "floating"),
        "arm planar flag": cspace.inspect(files["arm.urdf"], "planar"),
        "arm tilted": cspace.inspect(files["arm_tilted.urdf"]),
        "arm high": cspace.inspect(files["arm_high.urdf"]),
        "arm higher": cspace.inspect(files["arm_higher.urdf"]),
        "arm declared": cspace.inspect(files["arm_declared.urdf"]),
        "arm planar": cspace.inspect(files["arm_planar.urdf"]),
        "arm planar x": cspace.inspect(files["arm_planar_x.urdf"]),
        "arm mounted": cspace.inspect(files["arm_mounted.urdf"]),
        "arm free": cspace.inspect(files["arm_free.xml"]),
        "w flag": cspace.inspect(files["w_fixed.urdf"], "floating"),
        "w float": cspace.inspect(files["w_float.urdf"]),
        "w mjcf flag": cspace.inspect(files["w_fixed.xml"], "floating"),
        "w mjcf float": cspace.inspect(files["w_float.xml"]),
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
    # MuJoCo's free joint is in the world's frame wherever its body starts
    ("arm flag", "arm free", ADDED, IN_FILE),
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
    # the flag floats the world and the table welded to it; the file's joint, the arm
    # alone: the table moves with q on one side and stays on the other (URDF, MJCF)
    ("w flag", "w float", ("floating", "-"), ["root-joint"]),
    ("w mjcf flag", "w mjcf float", ("floating", "-"), ["root-joint"]),
    # the flag floats MJCF's world body, which the file's free joint leaves in place
    ("one flag", "free", ("floating", "-"), ["root-joint"]),
    # the file's joint off the world's origin: the same q puts the arm elsewhere
    ("arm planar flag", "arm tilted", ("planar", "-"), ["root-joint"]),
    ("arm flag", "arm high", ("floating", "-"), ["root-joint"]),
    ("arm flag", "arm mounted", ("floating", "-"), ["root-joint"]),
    # a planar joint whose <axis> is not +z: Pinocchio ignores it, URDF and Drake do not
    ("arm planar flag", "arm planar x", ("planar", "-"), ["root-joint"]),
    ("cart flag", "cart mjcf high", ("planar", "-"), ["root-joint"]),
    ("cart flag", "cart mjcf tilted", ("planar", "-"), ["root-joint"]),
    ("cart flag", "cart mjcf anchored", ("planar", "-"), ["root-joint"]),
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


_HIGH = "origin xyz (0, 0, 1), quaternion wxyz (1, 0, 0, 0)"
_HIGHER = "origin xyz (0, 0, 5), quaternion wxyz (0.731688869, 0.68163876, 0, 0)"
_AT_ORIGIN = "at the world's origin"
PLACED = [
    # one joint, both declared, placed by another <origin>: the same q, elsewhere
    ("arm high", "arm higher", _HIGH, _HIGHER),
    ("arm declared", "arm higher", _AT_ORIGIN, _HIGHER),
    # a fixed joint above it lifts the link (its origin in the world), where the other
    # is at the world's origin
    ("arm declared", "arm mounted", _AT_ORIGIN, _HIGH),
    # the plane normal to +z, and normal to +x
    ("arm planar", "arm planar x", _AT_ORIGIN, "placed off the world's origin"),
]


@pytest.mark.parametrize(("old", "new", "before", "after"), PLACED, ids=lambda v: str(v)[:12])
@pytest.mark.parametrize("reverse", [False, True], ids=["forward", "reverse"])
def test_a_root_joint_placed_elsewhere_is_a_change(
    reports: dict[str, cspace.Report],
    old: str,
    new: str,
    before: str,
    after: str,
    reverse: bool,
) -> None:
    """One root joint (one name, one kind, declared on both sides) placed otherwise on
    one side: the same q puts the robot elsewhere, a change that says both placements."""
    a, b = (reports[new], reports[old]) if reverse else (reports[old], reports[new])
    if reverse:
        before, after = after, before
    diff = diff_reports(a, b)
    assert diff.verdict == "changed" and not _paired(diff), diff.notes
    assert diff.changes == (Change("root-placed", "root_joint", before, after),)
    assert diff_reports(_document(a), _document(b)).to_dict() == diff.to_dict()


def test_a_root_joint_placed_alike_is_no_change(reports: dict[str, cspace.Report]) -> None:
    for name in ("arm high", "arm higher", "arm planar x", "arm mounted"):
        assert diff_reports(reports[name], _document(reports[name])).verdict == "same", name
    assert _file_root(reports["arm planar x"]).at_world_origin is False
    assert _file_root(reports["arm planar"]).at_world_origin is True


def test_a_root_joint_placed_elsewhere_in_every_format(files: dict[str, Path]) -> None:
    pair = (str(files["arm_high.urdf"]), str(files["arm_higher.urdf"]))
    formats = ("text", "json", "markdown", "html")
    done = run_cli_many([("diff", *pair, "--format", f, "--width", "300") for f in formats])
    text, document, markdown, page = (run.stdout for run in done)
    assert [run.code for run in done] == [1] * 4, [run.stderr for run in done]
    assert ["root joint placed", "root_joint", _HIGH, _HIGHER] in _rows(text, "change")
    assert json.loads(document)["changes"] == [
        {"kind": "root-placed", "joint": "root_joint", "before": _HIGH, "after": _HIGHER}
    ]
    assert f"| root joint placed | `root_joint` | {_HIGH} | {_HIGHER} |" in markdown
    tree = etree.fromstring(page.encode(), etree.HTMLParser())
    rows = [
        ["".join(td.itertext()) for td in row.findall("td")]
        for row in tree.iterfind(".//table[@class='changes']/tr")
    ]
    assert ["root joint placed", "root_joint", _HIGH, _HIGHER] in rows


PAIRS = [(old, new) for old, new, *_ in SAME_PAIRS + CHANGED + PLACED]


@pytest.mark.parametrize(("old", "new"), PAIRS, ids=lambda v: str(v))
@pytest.mark.parametrize("reverse", [False, True], ids=["forward", "reverse"])
def test_saved_reports_pair_as_the_files_do(
    reports: dict[str, cspace.Report], old: str, new: str, reverse: bool
) -> None:
    """A report saved as JSON (``inspect --format json``) keeps where its root joint came
    from, and whether it is at the world's origin: the diff of saved reports is the diff
    of the files, paired or not."""
    a, b = (reports[new], reports[old]) if reverse else (reports[old], reports[new])
    saved = diff_reports(_document(a), _document(b))
    assert saved.to_dict() == diff_reports(a, b).to_dict()


def _file_root(report: cspace.Report) -> cspace.JointReport:
    return next(j for j in report.joints if j.q_index == 0)


def test_the_report_says_whether_the_files_root_joint_is_at_the_worlds_origin(
    reports: dict[str, cspace.Report],
) -> None:
    placed = {
        name: _file_root(reports[name]).at_world_origin
        for name in ("flag", "mjcf", "urdf declared", "arm free", "arm tilted", "arm high")
    }
    assert placed == {
        "flag": True,
        "mjcf": True,
        "urdf declared": True,
        "arm free": True,
        "arm tilted": False,
        "arm high": False,
    }
    for name, answer in (("cart mjcf", True), ("cart mjcf high", False)):
        parts = [j for j in reports[name].joints if j.name.startswith("root_joint_")]
        assert [j.at_world_origin for j in parts] == [answer] * 3, name
    assert all(j.at_world_origin is None for j in reports["mjcf"].joints[1:])
    assert "at_world_origin" not in reports["mjcf"].to_dict()["joints"][1]


def test_a_saved_report_that_does_not_say_is_not_paired(
    reports: dict[str, cspace.Report],
) -> None:
    """A report saved by an earlier cspace has no ``at_world_origin``: a file's root joint
    is then not known to be at the world's origin, and not paired; the one cspace added
    is, by its record (no parent link)."""
    older = _document(reports["mjcf"])
    del older["joints"][0]["at_world_origin"]
    diff = diff_reports(reports["flag"], older)
    assert diff.verdict == "changed" and not _paired(diff)
    assert Change("root-joint", None, "floating", "-") in diff.changes
    added = _document(reports["flag"])
    del added["joints"][0]["at_world_origin"]
    assert diff_reports(added, reports["mjcf"]).verdict == "same"


@pytest.fixture(scope="module")
def saved_runs(
    reports: dict[str, cspace.Report], tmp_path_factory: pytest.TempPathFactory
) -> dict[str, Run]:
    """``cspace diff`` of saved reports (read as untrusted input) and of the files."""
    folder = tmp_path_factory.mktemp("saved")
    for name in ("flag", "mjcf", "w flag", "w float", "arm planar flag", "arm tilted"):
        (folder / f"{name.replace(' ', '_')}.json").write_text(reports[name].to_json())
    lying = reports["arm tilted"].to_dict()
    lying["joints"][0]["at_world_origin"] = "yes"
    (folder / "lying.json").write_text(json.dumps(lying))
    high = reports["arm high"].to_dict()
    high["joints"][0]["at_world_origin"] = True  # and its origin 1 m up
    (folder / "high_at_origin.json").write_text(json.dumps(high))
    arm = reports["arm declared"].to_dict()
    arm["joints"][1]["at_world_origin"] = False  # j1, not the root joint
    (folder / "not_root.json").write_text(json.dumps(arm))
    far = reports["arm high"].to_dict()
    far["joints"][0]["origin"][1] = -2e6
    (folder / "far.json").write_text(json.dumps(far))
    w_files = [str(reports[n].source.path) for n in ("w flag", "w float")]
    commands = {
        "same": ("diff", f"{folder}/flag.json", f"{folder}/mjcf.json", "--format", "json"),
        "welded": ("diff", f"{folder}/w_flag.json", f"{folder}/w_float.json", "--format", "json"),
        "welded files": ("diff", *w_files, "--old-root-joint", "floating", "--format", "json"),
        "tilted": (
            "diff",
            f"{folder}/arm_tilted.json",
            f"{folder}/arm_planar_flag.json",
            "--format",
            "json",
        ),
        "lying": ("diff", f"{folder}/arm_planar_flag.json", f"{folder}/lying.json"),
        "high at origin": ("diff", f"{folder}/flag.json", f"{folder}/high_at_origin.json"),
        "not root": ("diff", f"{folder}/not_root.json", f"{folder}/flag.json"),
        "far": ("diff", f"{folder}/far.json", f"{folder}/flag.json"),
    }
    done = run_cli_many(list(commands.values()))
    return dict(zip(commands, done, strict=True))


def _verdict(run: Run) -> tuple[int, str, list[dict[str, Any]]]:
    document = json.loads(run.stdout)
    return run.code, document["verdict"], document["changes"]


def test_saved_reports_on_the_command_line(saved_runs: dict[str, Run]) -> None:
    assert _verdict(saved_runs["same"]) == (0, "same", [])
    root = {"kind": "root-joint", "joint": None, "before": "floating", "after": "-"}
    assert _verdict(saved_runs["welded"]) == (1, "changed", [root])
    assert _verdict(saved_runs["welded files"]) == _verdict(saved_runs["welded"])
    planar = {"kind": "root-joint", "joint": None, "before": "-", "after": "planar"}
    assert _verdict(saved_runs["tilted"]) == (1, "changed", [planar])


def test_a_saved_report_that_says_it_wrongly_is_refused(saved_runs: dict[str, Run]) -> None:
    run = saved_runs["lying"]
    assert run.code == 2 and run.stdout == "", run.stdout + run.stderr
    assert "/joints/0/at_world_origin" in run.stderr and "[bad-report]" in run.stderr


@pytest.mark.parametrize(
    ("name", "file", "said"),
    [
        ("high at origin", "high_at_origin.json", "/joints/0/at_world_origin"),
        ("not root", "not_root.json", "/joints/1/at_world_origin"),
        ("far", "far.json", "/joints/0/origin"),
    ],
)
def test_a_saved_reports_placement_that_cannot_be_is_refused(
    saved_runs: dict[str, Run], name: str, file: str, said: str
) -> None:
    """``at_world_origin`` true of a joint with an origin, said of a joint not the root,
    or an origin 2,000 km away: one line, naming the file and the value."""
    run = saved_runs[name]
    assert run.code == 2 and run.stdout == "", run.stdout + run.stderr
    assert len(run.stderr.strip().splitlines()) == 1, run.stderr
    assert file in run.stderr and said in run.stderr and "[bad-report]" in run.stderr


@pytest.mark.bounded
def test_the_largest_floating_robot_is_placed_within_the_memory_bound(tmp_path: Path) -> None:
    """5,000 joints below a floating root joint (100 branches of 50 from the base): the
    root joint's placement is found from its own joints, not the whole model's data
    (Pinocchio's takes 6 by nv numbers per joint, 1.2 GB here)."""
    parts = [
        '<robot name="r"><link name="world"/><link name="base_link"/>',
        '<joint name="root_joint" type="floating"><parent link="world"/>'
        '<child link="base_link"/></joint>',
    ]
    for k in range(4999):
        parent = "base_link" if k % 50 == 0 else f"l{k - 1}"
        parts.append(
            f'<link name="l{k}"/><joint name="j{k}" type="revolute"><parent link="{parent}"/>'
            f'<child link="l{k}"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        )
    (tmp_path / "wide.urdf").write_text("".join(parts) + "</robot>")
    result = measured("inspect", "wide.urdf", "--format", "json", cwd=tmp_path)
    assert result.run.code == 0, result.run.stderr
    assert result.peak_mib < PEAK_MIB, result.peak_mib
    root = json.loads(result.run.stdout)["joints"][0]
    assert (root["name"], root["at_world_origin"]) == ("root_joint", True)
