"""``cspace diff``: one pair of hand-written files per kind of change (tests/diff_cases/).

Each case runs the installed command in the case's folder, as a CI job would, and pins
the exit code and the Markdown a pull-request comment would show.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import cspace
from cspace._reports.diff import diff_reports

from conftest import REPO, ROBOTS, run_cli

CASES = REPO / "tests" / "diff_cases"

UNCHANGED = (
    "### cspace: no C-space change in `{name}`\n\n"
    "`R^3`, dimension 3. Limits compared within 1e-06 or 1e-05 relative.\n"
)

EXPECTED: dict[str, tuple[str, int, str]] = {
    "unchanged": (
        "new.urdf",
        0,
        UNCHANGED.format(name="new.urdf"),
    ),
    "limits_within_tolerance": (
        "new.urdf",
        0,
        UNCHANGED.format(name="new.urdf"),
    ),
    "fixed_added": (
        "new.urdf",
        0,
        UNCHANGED.format(name="new.urdf"),
    ),
    "format_change": (
        "new.xml",
        0,
        UNCHANGED.format(name="new.xml")
        + "\nNotes (how the two files store or name it; the C-space is the same):\n\n"
        "| note | joint | old | new |\n| --- | --- | --- | --- |\n"
        "| Drake floats | - | base | none |\n",  # MuJoCo's and Drake's MJCF parsers weld
    ),
    "retyped": (
        "new.urdf",
        1,
        """### cspace: C-space changed in `new.urdf`

`R^3` (dimension 3) → `R^2 × S^1` (dimension 3)

| change | joint | before | after |
| --- | --- | --- | --- |
| C-space | - | R^3 (dimension 3) | R^2 × S^1 (dimension 3) |
| q/v size | - | nq 3, nv 3 | nq 4, nv 3 |
| joint retyped | `j2` | revolute (R^1) | continuous (S^1) |
| limits | `j2` | [-2, 2] rad | - |
| q/v layout | `j2` | q 1, v 1 | q 1..2, v 1 |
| q/v layout | `j3` | q 2, v 2 | q 3, v 2 |

Limits compared within 1e-06 or 1e-05 relative.
""",
    ),
    "retyped_same_form": (
        "new.urdf",
        1,
        """### cspace: C-space changed in `new.urdf`

Same normal form, `R^3` (dimension 3), but not the same configurations:

| change | joint | before | after |
| --- | --- | --- | --- |
| joint retyped | `j2` | revolute (R^1) | prismatic (R^1) |
| limits | `j2` | [-2, 2] rad | [-0.1, 0.1] m |

Limits compared within 1e-06 or 1e-05 relative.
""",
    ),
    "added": (
        "new.urdf",
        1,
        """### cspace: C-space changed in `new.urdf`

`R^3` (dimension 3) → `R^4` (dimension 4)

| change | joint | before | after |
| --- | --- | --- | --- |
| C-space | - | R^3 (dimension 3) | R^4 (dimension 4) |
| q/v size | - | nq 3, nv 3 | nq 4, nv 4 |
| joint added | `j4` | - | revolute (R^1) |

Limits compared within 1e-06 or 1e-05 relative.
""",
    ),
    "removed": (
        "new.urdf",
        1,
        """### cspace: C-space changed in `new.urdf`

`R^4` (dimension 4) → `R^3` (dimension 3)

| change | joint | before | after |
| --- | --- | --- | --- |
| C-space | - | R^4 (dimension 4) | R^3 (dimension 3) |
| q/v size | - | nq 4, nv 4 | nq 3, nv 3 |
| joint removed | `j4` | revolute (R^1) | - |

Limits compared within 1e-06 or 1e-05 relative.
""",
    ),
    "limits": (
        "new.urdf",
        1,
        """### cspace: limits differ in `new.urdf`

The same C-space, `R^3` (dimension 3), but limits differ:

| change | joint | before | after |
| --- | --- | --- | --- |
| limits | `j2` | [-2, 2] rad | [-2.5, 2] rad |

Limits compared within 1e-06 or 1e-05 relative.
""",
    ),
    "layout": (
        "new.urdf",
        1,
        """### cspace: q/v layout differs in `new.urdf`

The same C-space, `R^3` (dimension 3), but q/v layout differs:

| change | joint | before | after |
| --- | --- | --- | --- |
| q/v layout | `j3` | q 2, v 2 | q 1, v 1 |
| q/v layout | `j2` | q 1, v 1 | q 2, v 2 |

Limits compared within 1e-06 or 1e-05 relative.
""",
    ),
}


def test_every_case_folder_is_pinned() -> None:
    assert {p.name for p in CASES.iterdir() if p.is_dir()} == set(EXPECTED)


@pytest.mark.parametrize("case", sorted(EXPECTED))
def test_diff_case_markdown_and_exit_code(case: str) -> None:
    new, code, markdown = EXPECTED[case]
    run = run_cli("diff", "old.urdf", new, "--format", "markdown", cwd=CASES / case)
    assert (run.code, run.stderr) == (code, "")
    assert run.stdout == markdown


@pytest.mark.parametrize("case", sorted(EXPECTED))
def test_diff_case_json_agrees_with_the_exit_code(case: str) -> None:
    new, code, _ = EXPECTED[case]
    run = run_cli("diff", "old.urdf", new, "--format", "json", cwd=CASES / case)
    document = json.loads(run.stdout)
    assert run.code == code
    title = run_cli("diff", "old.urdf", new, cwd=CASES / case).stdout.split(":")[0]
    verdict = {"C-space changed": "changed", "C-space the same": "differs"}
    assert document["verdict"] == verdict.get(title, "same")
    assert document["changed"] is (document["verdict"] == "changed")
    assert bool(document["changes"]) is (code == 1)


def test_a_saved_report_diffs_like_the_file_it_came_from(tmp_path: Path) -> None:
    case = CASES / "retyped"
    saved = run_cli("inspect", "--format", "json", "old.urdf", cwd=case)
    report = tmp_path / "old.json"
    report.write_text(saved.stdout)
    from_report = run_cli("diff", str(report), "new.urdf", "--format", "markdown", cwd=case)
    assert from_report.code == 1
    assert from_report.stdout == EXPECTED["retyped"][2]


def test_root_joint_change_against_a_saved_report(tmp_path: Path) -> None:
    case = CASES / "unchanged"
    saved = run_cli("inspect", "--format", "json", "--root-joint", "floating", "old.urdf", cwd=case)
    report = tmp_path / "old.json"
    report.write_text(saved.stdout)
    run = run_cli("diff", str(report), "old.urdf", "--format", "json", cwd=case)
    assert run.code == 1
    kinds = [(c["kind"], c["joint"]) for c in json.loads(run.stdout)["changes"]]
    assert ("manifold", None) in kinds
    assert ("root-joint", None) in kinds
    assert ("joint-removed", "root_joint") in kinds
    assert ("layout", "j1") in kinds  # every joint moved down 7 places in q


def test_tolerance_option_decides_what_counts_as_a_limit_change() -> None:
    case = CASES / "limits"
    assert run_cli("diff", "old.urdf", "new.urdf", cwd=case).code == 1
    assert run_cli("diff", "old.urdf", "new.urdf", "--tolerance", "0.6", cwd=case).code == 0


def test_library_diff_of_reports() -> None:
    old = cspace.inspect(str(CASES / "retyped" / "old.urdf")).to_dict()
    new = cspace.inspect(str(CASES / "retyped" / "new.urdf")).to_dict()
    assert not diff_reports(old, old).differs
    changes = diff_reports(old, new).changes
    assert [(c.kind, c.joint) for c in changes][:3] == [
        ("manifold", None),
        ("size", None),
        ("joint-retyped", "j2"),
    ]


def test_text_output_names_both_sides() -> None:
    run = run_cli("diff", "old.urdf", "new.urdf", cwd=CASES / "added")
    assert run.code == 1
    assert run.stdout.splitlines()[:3] == [
        "C-space changed: R^3 -> R^4",
        "  old old.urdf",
        "  new new.urdf",
    ]


def test_not_a_report_and_missing_files_give_no_diff(tmp_path: Path) -> None:
    bogus = tmp_path / "bogus.json"
    for text in ('{"hello": 1}', "[]", " [1, 2]"):
        bogus.write_text(text)
        run = run_cli("diff", str(bogus), str(CASES / "added" / "new.urdf"))
        assert run.code == 2 and "JSON, but not a cspace report" in run.stderr
    old_version = tmp_path / "old.json"
    saved = json.loads(
        run_cli("inspect", "--format", "json", str(CASES / "added" / "new.urdf")).stdout
    )
    saved["schema_version"] = 99
    old_version.write_text(json.dumps(saved))
    run = run_cli("diff", str(old_version), str(CASES / "added" / "new.urdf"))
    assert run.code == 2 and "schema_version 99" in run.stderr
    run = run_cli("diff", "missing.urdf", str(CASES / "added" / "new.urdf"))
    assert run.code == 2 and "missing.urdf" in run.stderr
    assert run_cli("diff", "-", "-").code == 2


def test_one_side_from_standard_input() -> None:
    case = CASES / "added"
    run = run_cli("diff", "old.urdf", "-", cwd=case, stdin=(case / "new.urdf").read_bytes())
    assert run.code == 1
    assert "joint added" in run.stdout


def test_a_small_limit_change_shows_every_digit(tmp_path: Path) -> None:
    urdf = (
        '<robot name="a"><link name="l0"/><link name="l1"/><joint name="j" type="revolute">'
        '<parent link="l0"/><child link="l1"/>'
        '<limit lower="-1" upper="UPPER" effort="1" velocity="1"/></joint></robot>'
    )
    (tmp_path / "a.urdf").write_text(urdf.replace("UPPER", "1"))
    (tmp_path / "b.urdf").write_text(urdf.replace("UPPER", "1.0000001"))
    run = run_cli(
        "diff", "a.urdf", "b.urdf", "--tolerance", "1e-9", "--rel-tolerance", "0", cwd=tmp_path
    )
    assert run.code == 1
    assert "[-1, 1] rad" in run.stdout
    assert "[-1, 1.0000001] rad" in run.stdout


def test_a_report_reads_back_from_its_json() -> None:
    from cspace._reports.report import Report

    files = sorted(ROBOTS.rglob("*.urdf")) + sorted(ROBOTS.glob("*.xml"))
    files += sorted((ROBOTS.parent / "tests" / "findings").glob("*.urdf"))
    read = 0
    for path in files:
        try:
            report = cspace.inspect(path)
        except cspace.CspaceError:
            continue  # a file with no report (a broken finding case)
        back = Report.from_dict(json.loads(report.to_json()))
        assert back.to_json() == report.to_json(), path
        if "nan" not in repr(report.joints) and "inf" not in repr(report.joints):
            assert back == report, path  # every field, exactly
        assert not diff_reports(report, back).differs
        read += 1
    assert read >= 30


def test_the_notes_header_says_the_c_space_is_the_same_only_when_it_is(tmp_path: Path) -> None:
    """Every line of a diff agrees with its verdict, notes header included.

    A hinge turned into a slide changes the C-space (same normal form, other
    configurations); a moved limit leaves it the same, though the diff still fails; the
    file MuJoCo users write for the same arm differs only in notes.
    """
    from cspace._render.markdown import render_diff_markdown
    from cspace._render.text import render_diff_text
    from cspace._reports.diff import diff_reports

    old = cspace.inspect(REPO / "robots" / "arm7.urdf")
    text = (REPO / "tests" / "pairs" / "arm7.xml").read_text()
    pan = '<joint name="shoulder_pan" axis="0 0 1" range="-166.158 166.158"/>'
    sides = {
        "changed": pan.replace("axis", 'type="slide" axis').replace("166.158", "0.5"),
        "differs": pan.replace('range="-166.158', 'range="-150'),
        "same": pan,
    }
    for verdict, joint in sides.items():
        mjcf = tmp_path / f"{verdict}.xml"
        mjcf.write_text(text.replace(pan, joint, 1))
        diff = diff_reports(old, cspace.inspect(mjcf))
        assert (diff.verdict, bool(diff.notes)) == (verdict, True)
        said = render_diff_text(diff)
        first = {"changed": "C-space changed", "differs": "C-space the same", "same": "no C-"}
        assert said.startswith(first[verdict]), said
        for shown in (said, render_diff_markdown(diff)):
            assert ("the C-space is the same" in shown) is (verdict != "changed"), shown
        assert diff.to_dict()["verdict"] == verdict


def _renamed(tmp_path: Path) -> tuple[str, str]:
    """arm7 and the same arm, every joint's name given a new prefix."""
    text = (ROBOTS / "arm7.urdf").read_text()
    names = [j.name for j in cspace.inspect(ROBOTS / "arm7.urdf").joints]
    for name in names:
        text = text.replace(f'name="{name}"', f'name="left_{name}"')
    out = tmp_path / "left.urdf"
    out.write_text(text)
    return str(ROBOTS / "arm7.urdf"), str(out)


def test_a_prefix_rule_maps_every_renamed_joint(tmp_path: Path) -> None:
    old, new = _renamed(tmp_path)
    plain = run_cli("diff", old, new)
    assert plain.code == 1
    assert (
        plain.stderr == "cspace: note: the joints differ only by a prefix: try --map '*=left_*'\n"
    )
    mapped = run_cli("diff", old, new, "--map", "*=left_*")
    assert mapped.code == 0 and mapped.stderr == "", mapped.stdout
    assert mapped.stdout.startswith("no C-space change: R^6 × S^1")
    bad = run_cli("diff", old, new, "--map", "*=left")
    assert bad.code == 2 and "a rule has one * on each side" in bad.stderr


def test_diff_tables_fit_the_width(tmp_path: Path) -> None:
    old, new = _renamed(tmp_path)
    run = run_cli("diff", old, new, "--width", "50")
    assert max(len(line) for line in run.stdout.splitlines()[4:]) <= 50
    assert "…" in run.stdout


def test_a_mimic_follower_removed_from_an_mjcf_shifts_qpos_and_differs(tmp_path: Path) -> None:
    """A follower has no q entry but has a qpos one, so its
    removal moves every later joint in MuJoCo's qpos, and a saved qpos would be misread;
    the diff said "no C-space change"."""
    text = (ROBOTS / "mjcf_equality.xml").read_text()
    body = text[
        text.index('        <body name="finger_right"') : text.index('      <body name="rod"')
    ]
    tie = '    <joint joint1="finger_right" joint2="finger_left"/>\n'
    assert body.count("</body>") == 2 and tie in text  # the finger's, and the arm's
    shorter = tmp_path / "eq.xml"
    shorter.write_text(text.replace(body, "      </body>\n").replace(tie, ""))
    diff = diff_reports(cspace.inspect(ROBOTS / "mjcf_equality.xml"), cspace.inspect(shorter))
    assert diff.verdict == "differs", diff.changes
    cam = [c for c in diff.changes if c.joint == "cam"]
    assert [(c.kind, c.before.split(", ")[-1], c.after.split(", ")[-1]) for c in cam] == [
        ("layout", "qpos 7", "qpos 6")
    ]
    urdf_like = diff_reports(
        cspace.inspect(ROBOTS / "arm7.urdf"), cspace.inspect(REPO / "tests" / "pairs" / "arm7.xml")
    )
    layout = [c for c in urdf_like.notes if c.kind == "layout"]
    assert all("qpos" not in c.before + c.after for c in layout)  # only MJCF to MJCF


def _mjcf(body: str, equality: str = "") -> str:
    return (
        f"<mujoco><worldbody><body name='a'><geom size='0.1'/>{body}</body></worldbody>"
        f"<equality>{equality}</equality></mujoco>"
    )


_HINGE = "<body name='b'><joint name='j1' range='-1 1' limited='true'/><geom size='0.1'/></body>"
_FOLLOWER = "<body name='c'><joint name='j2' range='-1 1' limited='true'/><geom size='0.1'/></body>"


def test_mjcf_qpos_between_two_mjcf_files(tmp_path: Path) -> None:
    """A follower added at the end of qpos
    was "the same" (a saved qpos no longer fits); a root joint paired with the file's
    free joint, or a saved report without qposadr, made every joint "differ"."""
    files = {
        "one.xml": _mjcf(_HINGE),
        "follower.xml": _mjcf(_HINGE + _FOLLOWER, "<joint joint1='j2' joint2='j1'/>"),
        "free.xml": _mjcf(_HINGE).replace(
            "<geom size='0.1'/>", "<freejoint name='root'/><geom size='0.1'/>", 1
        ),
    }
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    grown = run_cli("diff", "one.xml", "follower.xml", "--format", "json", cwd=tmp_path)
    document = json.loads(grown.stdout)
    assert (grown.code, document["verdict"]) == (1, "differs")
    assert [(c["kind"], c["before"], c["after"]) for c in document["changes"]] == [
        ("layout", "MuJoCo qpos size 1", "MuJoCo qpos size 2")
    ]
    # the flag floats MuJoCo's world body, the file's free joint body 'a' alone: two root
    # joints, and no other joint's qpos said to differ
    floated = run_cli(
        "diff",
        "one.xml",
        "free.xml",
        "--old-root-joint",
        "floating",
        "--format",
        "json",
        cwd=tmp_path,
    )
    document = json.loads(floated.stdout)
    assert (floated.code, document["verdict"]) == (1, "changed"), floated.stdout
    assert [(c["kind"], c["joint"]) for c in document["changes"]] == [
        ("root-joint", None),
        ("joint-added", "root"),
        ("joint-removed", "root_joint"),
    ]
    saved = json.loads(run_cli("inspect", "one.xml", "--format", "json", cwd=tmp_path).stdout)
    for joint in saved["joints"]:  # as an earlier version wrote it
        for field in ("qposadr", "dofadr", "mujoco_type"):
            joint.pop(field, None)
    (tmp_path / "old.json").write_text(json.dumps(saved))
    older = run_cli("diff", "old.json", "one.xml", cwd=tmp_path)
    assert older.code == 0 and older.stdout.startswith("no C-space change"), older.stdout
