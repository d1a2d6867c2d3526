"""A mechanism's ``closure`` in saved reports, diffs and baselines, through the command.

A report with loops saves and reads back whole (the record's round trip too), a tree's
report has no ``closure`` key, and a saved report whose ``closure`` contradicts itself or
the report, or is too large, is refused with one line (``[bad-report]``, the JSON
Pointer of the value). ``cspace diff`` and ``cspace check --baseline`` fail a pull request
that breaks a loop: the constraint removed, renamed, or moved where no configuration
closes it.
"""

from __future__ import annotations

import copy
import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from cspace._reports.report import Report
from cspace._reports.savedreport import read_report_document
from cspace.errors import ReportFileError

from conftest import REPO, run_cli, run_cli_many

FOURBAR = REPO / "tests" / "closed" / "fourbar.xml"
TREE = REPO / "robots" / "arm7.urdf"


@pytest.fixture(scope="module")
def saved() -> dict[str, Any]:
    """The four-bar's JSON report, as ``cspace inspect --format json`` writes it."""
    run = run_cli("inspect", str(FOURBAR), "--format", "json")
    assert run.code == 0, run.stderr
    document: dict[str, Any] = json.loads(run.stdout)
    return document


def test_a_mechanism_report_reads_back_whole(saved: dict[str, Any], tmp_path: Path) -> None:
    """The closure is what the four-bar is, and a saved report of it reads back equal."""
    closure = saved["closure"]
    assert (closure["loops"], closure["grubler"], closure["mobility"]) == (1, 0, 1)
    assert closure["cuts"][0]["links"] == ["rocker", "world"]
    assert closure["cuts"][0]["line"] == 20 and closure["actuated"] == ["crank"]
    text = json.dumps(saved).encode()
    checked = read_report_document("fourbar.json", text)
    assert Report.from_dict(checked).to_dict() == saved
    (tmp_path / "fourbar.json").write_bytes(text)
    run = run_cli("diff", str(tmp_path / "fourbar.json"), str(FOURBAR))
    assert run.code == 0 and run.stdout.startswith("no C-space change"), run.stdout + run.stderr


def test_a_tree_report_has_no_closure() -> None:
    run = run_cli("inspect", str(TREE), "--format", "json")
    assert run.code == 0 and "closure" not in json.loads(run.stdout)


def _set(pointer: str, value: Any) -> Callable[[dict[str, Any]], None]:
    """A change that sets the value at a JSON Pointer (its last step created if absent)."""

    def change(document: dict[str, Any]) -> None:
        *steps, last = pointer.strip("/").split("/")
        node: Any = document
        for step in steps:
            node = node[int(step)] if isinstance(node, list) else node[step]
        node[int(last) if isinstance(node, list) else last] = value

    return change


def _many_cuts(document: dict[str, Any]) -> None:
    cut = document["closure"]["cuts"][0]
    document["closure"]["cuts"] = [dict(cut, name=f"c{k}") for k in range(5001)]


HOSTILE: dict[str, tuple[Callable[[dict[str, Any]], None], str]] = {
    "Grübler not dimension less rows": (_set("/closure/grubler", 2), "/closure/grubler"),
    "mobility not dimension less rank": (_set("/closure/mobility", 3), "/closure/mobility"),
    "rank above the rows": (
        _set("/closure/rank", {"lowest": 2, "highest": 4}),
        "/closure/rank",
    ),
    "rank lowest above highest": (
        _set("/closure/rank", {"lowest": 3, "highest": 2}),
        "/closure/rank",
    ),
    "rows not the cuts' sum": (_set("/closure/constraint_rows", 6), "/closure/constraint_rows"),
    "assembled without samples": (_set("/closure/samples", 0), "/closure/rank"),
    "more samples than attempts": (_set("/closure/samples", 40), "/closure/samples"),
    "a huge cuts array": (_many_cuts, "/closure/cuts"),
    "a cut on a link not in the report": (
        _set("/closure/cuts/0/links/1", "elsewhere"),
        "/closure/cuts/0/links/1",
    ),
    "a cut of three links": (
        _set("/closure/cuts/0/links", ["rocker", "world", "crank"]),
        "/closure/cuts/0/links",
    ),
    "a cut of 9 equations": (_set("/closure/cuts/0/rows", 9), "/closure/cuts/0/rows"),
    "a cut in another file": (_set("/closure/cuts/0/file", "/etc/passwd"), "/closure/cuts/0/file"),
    "a name too long": (_set("/closure/cuts/0/name", "&" * 257), "/closure/cuts/0/name"),
    "an actuated joint not in the report": (
        _set("/closure/actuated", ["crank", "motor"]),
        "/closure/actuated/1",
    ),
    "a singularity of the wrong size": (
        _set("/closure/singularities", [{"rank": 1, "configuration": [0.0, 0.0]}]),
        "/closure/singularities/0",
    ),
    "a singularity at the highest rank": (
        _set("/closure/singularities", [{"rank": 2, "configuration": [0.0, 0.0, 0.0]}]),
        "/closure/singularities/0/rank",
    ),
    "a key cspace does not write": (_set("/closure/run", "code"), "/closure"),
    "a residual below zero": (_set("/closure/max_residual", -1.0), "/closure/max_residual"),
    "loops as text": (_set("/closure/loops", "1"), "/closure/loops"),
    "no loop with a cut": (_set("/closure/loops", 0), "/closure/loops"),
    "a mobility below the rank's without a shaky finding": (
        _set("/closure/mobility", 0),
        "/closure/mobility",
    ),
    "a residual no configuration on it has": (
        _set("/closure/max_residual", 5.0),
        "/closure/max_residual",
    ),
}
"""Saved reports whose closure cspace never writes, and where each is refused."""


def test_a_hostile_closure_is_refused_in_one_line(saved: dict[str, Any], tmp_path: Path) -> None:
    """Each is refused by ``cspace diff`` with one ``[bad-report]`` line at its value."""
    (tmp_path / "good.json").write_text(json.dumps(saved))
    commands = []
    for k, (change, _) in enumerate(HOSTILE.values()):
        document = copy.deepcopy(saved)
        change(document)
        (tmp_path / f"bad{k}.json").write_text(json.dumps(document))
        commands.append(("diff", str(tmp_path / f"bad{k}.json"), str(tmp_path / "good.json")))
    for (case, (_, where)), run in zip(HOSTILE.items(), run_cli_many(commands), strict=True):
        assert run.code == 2 and run.stdout == "", (case, run)
        assert run.stderr.count("\n") == 1 and run.stderr.endswith("[bad-report]\n"), (case, run)
        assert "Traceback" not in run.stderr
        found = re.search(r" at (/\S*)", run.stderr)
        assert found is not None and found.group(1).startswith(where), (case, run.stderr)


def test_rows_the_cuts_do_not_make_and_a_groups_closure_are_refused(
    saved: dict[str, Any],
) -> None:
    """A cut the analysis left out is in neither the cuts nor the rows; a group's report
    has no closure (its mechanism is the whole robot's)."""
    fewer = copy.deepcopy(saved)
    fewer["closure"]["cuts"].append(dict(fewer["closure"]["cuts"][0], name="self"))
    grouped = copy.deepcopy(saved)
    grouped["group"] = {"name": "arm", "joints": [], "held": [], "held_at": "neutral"}
    for document, said in (
        (fewer, "constraint rows"),
        (grouped, "a group.s report has no closure"),
    ):
        with pytest.raises(ReportFileError, match=said):
            read_report_document("r.json", json.dumps(document).encode())


def _variants(folder: Path) -> dict[str, Path]:
    """The four-bar without its loop, and with its pivot moved out of reach."""
    text = FOURBAR.read_text()
    connect = '<connect name="ground_pivot" body1="rocker" anchor="0.25548 0 -1.47808"/>'
    rocker = '<geom type="capsule" fromto="0 0 0 0.25548 0 -1.47808" size="0.02"/>'
    assert connect in text and rocker in text
    out = {
        "tree": text.replace(connect, ""),
        "broken": text.replace("<worldbody>", '<worldbody>\n    <site name="far" pos="10 0 0"/>')
        .replace(rocker, rocker + '\n          <site name="tip" pos="0.25548 0 -1.47808"/>')
        .replace(connect, '<connect name="ground_pivot" site1="tip" site2="far"/>'),
        "renamed": text.replace("ground_pivot", "pin"),
    }
    for name, variant in out.items():
        (folder / f"{name}.xml").write_text(variant)
    return {name: folder / f"{name}.xml" for name in out}


def _changes(stdout: str) -> list[dict[str, Any]]:
    changes: list[dict[str, Any]] = json.loads(stdout)["changes"]
    return changes


def test_a_pull_request_that_breaks_a_loop_fails_the_diff(
    saved: dict[str, Any], tmp_path: Path
) -> None:
    """The loop removed, or its pivot moved out of reach: the C-space changed (exit 1).

    A cut renamed is the same mechanism; a cut that holds another link is a change.
    """
    files = _variants(tmp_path)
    moved = copy.deepcopy(saved)
    moved["closure"]["cuts"][0]["links"] = ["coupler", "world"]
    (tmp_path / "moved.json").write_text(json.dumps(moved))
    (tmp_path / "old.json").write_text(json.dumps(saved))
    old = str(tmp_path / "old.json")  # the four-bar's report, saved: read, not built again
    runs = run_cli_many(
        [
            ("diff", old, str(files["tree"]), "--format", "json"),
            ("diff", old, str(files["broken"]), "--format", "json"),
            ("diff", old, str(files["renamed"]), "--format", "json"),
            ("diff", old, str(tmp_path / "moved.json"), "--format", "json"),
            ("diff", old, str(files["broken"]), "--format", "markdown"),
            ("diff", old, str(tmp_path / "moved.json"), "--format", "html"),
        ]
    )
    tree, broken, renamed, moved_run, markdown, page = runs
    assert (tree.code, broken.code, renamed.code, moved_run.code) == (1, 1, 0, 1), runs
    assert json.loads(tree.stdout)["verdict"] == "changed"
    assert [(c["kind"], c["before"], c["after"]) for c in _changes(tree.stdout)] == [
        ("mechanism", "1 loop, mobility 1 (Grübler 0); actuated crank: a chart", "no loops"),
        ("cut-removed", "connect 'ground_pivot': rocker to world (3 equations)", "-"),
    ]
    assert [(c["kind"], c["after"]) for c in _changes(broken.stdout)] == [
        ("mechanism", "1 loop, not assembled (Grübler 0)"),
        (
            "cut-changed",
            "connect 'ground_pivot': rocker to world (3 equations) at "
            "(0.25548, 0, -1.47808) in rocker and (10, 0, 0) in world",
        ),
    ]
    assert _changes(renamed.stdout) == []
    assert [(c["kind"], c["after"]) for c in _changes(moved_run.stdout)] == [
        ("cut-changed", "connect 'ground_pivot': coupler to world (3 equations)")
    ]
    assert "| mechanism | - | `1 loop, mobility 1 (Grübler 0); actuated crank: a chart` |" in (
        markdown.stdout
    )
    assert page.stdout.count('<g class="loop changed">') == 4  # both sides, both trees


def test_check_baseline_fails_a_broken_loop(tmp_path: Path) -> None:
    """The baseline's four-bar, its file then changed so that the loop cannot close."""
    robot = tmp_path / "fourbar.xml"
    robot.write_text(FOURBAR.read_text())
    baseline = run_cli("inspect", "fourbar.xml", "--format", "jsonl", cwd=tmp_path)
    assert baseline.code == 0, baseline.stderr
    (tmp_path / "baseline.jsonl").write_text(baseline.stdout)
    robot.write_text(_variants(tmp_path)["broken"].read_text())
    run = run_cli("check", "--baseline", "baseline.jsonl", "fourbar.xml", cwd=tmp_path)
    assert run.code == 1 and run.stdout.startswith("changed: fourbar.xml: "), run
    assert "mechanism" in run.stdout


def test_every_format_says_what_the_mechanism_is(tmp_path: Path) -> None:
    """Text and Markdown: the mechanism under the C-space; github: in the file's notice;
    SARIF: a cut left out (``closure-invalid``) at its line; HTML: the loop on the tree."""
    connect = '<connect name="ground_pivot" body1="rocker" anchor="0.25548 0 -1.47808"/>'
    far = tmp_path / "far.xml"
    far.write_text(
        FOURBAR.read_text().replace(
            connect, connect + '\n    <connect name="far" body1="coupler" anchor="1e7 0 0"/>'
        )
    )
    fourbar = "tests/closed/fourbar.xml"  # as a user names it, from the repository
    text, markdown, github, html, sarif = run_cli_many(
        [
            ("inspect", fourbar),
            ("inspect", fourbar, "--format", "markdown"),
            ("inspect", fourbar, "--format", "github"),
            ("inspect", fourbar, "--format", "html"),
            ("inspect", str(far), "--format", "sarif"),
        ]
    )
    lines = text.stdout.splitlines()
    at = lines.index("  C = T^3  (the tree's, with its loops cut: the mechanism lies in it)")
    assert lines[at + 1 : at + 3] == [
        "  closed chains: 1 loop, mobility 1 (Grübler 0)",
        "    cut connect 'ground_pivot': rocker to world (line 20)",
    ]
    assert "    actuated crank: a chart of the mechanism" in lines
    assert "**Closed chains: 1 loop, mobility 1 (Grübler 0)**" in markdown.stdout
    assert "- cut `connect` `ground_pivot`: `rocker` to `world` (line 20)" in markdown.stdout
    assert github.stdout.startswith(
        "::notice file=tests/closed/fourbar.xml,title=cspace::C = T^3, dimension 3; "
        "closed chains: 1 loop, mobility 1 (Grübler 0)\n"
    )
    results = json.loads(sarif.stdout)["runs"][0]["results"]
    (invalid,) = [r for r in results if r["ruleId"] == "closure-invalid"]
    line = (
        far.read_text()
        .splitlines()
        .index('    <connect name="far" body1="coupler" anchor="1e7 0 0"/>')
    )
    assert invalid["locations"][0]["physicalLocation"]["region"] == {"startLine": line + 1}
    loops = re.findall(
        r'<g class="loop"><title>([^<]*)</title><path [^>]*/><text [^>]*>([^<]*)<', html.stdout
    )
    assert loops == [("loop closed by connect 'ground_pivot': rocker to world", "ground_pivot")] * 2
    assert "<b>closed chains: 1 loop, mobility 1 (Grübler 0)</b>" in html.stdout


HOSTILE_NAME = "pin\n::error::x</svg><script>alert(1)</script>\u202e`|*"
"""A cut's name made to break each output: a line, a workflow command, markup, bidi."""


def test_a_hostile_cut_name_is_escaped_everywhere(saved: dict[str, Any], tmp_path: Path) -> None:
    """A saved report's cut names and kinds are printable and escaped in every diff format."""
    hostile = copy.deepcopy(saved)
    cut = hostile["closure"]["cuts"][0]
    cut["name"], cut["kind"] = HOSTILE_NAME, "<b>weld</b>\x1b[31m"
    (tmp_path / "old.json").write_text(json.dumps(saved))
    (tmp_path / "new.json").write_text(json.dumps(hostile))
    runs = run_cli_many(
        [
            ("diff", str(tmp_path / "old.json"), str(tmp_path / "new.json"), "--format", fmt)
            for fmt in ("text", "markdown", "html", "json")
        ],
    )
    assert [r.code for r in runs] == [1, 1, 1, 1], runs
    for run in runs:
        assert "\x1b" not in run.stdout and "\u202e" not in run.stdout
        assert not re.search(r"^\s*::", run.stdout, re.MULTILINE)
    text, markdown, html, _ = runs
    assert "loop cut added" in text.stdout and "pin\\n" in text.stdout
    assert "<script>" not in html.stdout.replace("<script>\n", "")  # the page's own only
    assert "&lt;/svg&gt;&lt;script&gt;" in html.stdout
    assert "| loop cut added | - | - | `" in markdown.stdout


def test_check_baseline_annotates_a_cut_changed_at_its_line(tmp_path: Path) -> None:
    """The connect moved to another body: ``github`` annotates the change at its line."""
    robot = tmp_path / "fourbar.xml"
    text = FOURBAR.read_text()
    robot.write_text(text)
    baseline = run_cli("inspect", "fourbar.xml", "--format", "jsonl", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(baseline.stdout)
    robot.write_text(text.replace('body1="rocker" anchor', 'body1="coupler" anchor'))
    run = run_cli(
        "check", "--baseline", "baseline.jsonl", "fourbar.xml", "--format", "github", cwd=tmp_path
    )
    line = 1 + text.splitlines().index(
        '    <connect name="ground_pivot" body1="rocker" anchor="0.25548 0 -1.47808"/>'
    )
    assert run.code == 1, run
    assert f"::error file=fourbar.xml,line={line},title=cspace baseline%3A loop cut changed::" in (
        run.stdout
    )


def test_a_mechanism_not_searched_is_not_said_unassembled(
    saved: dict[str, Any], tmp_path: Path
) -> None:
    """No configuration sought (too large, or no model): read back, and diffed as such."""
    document = copy.deepcopy(saved)
    document["closure"].update(
        mobility=None,
        samples=0,
        attempts=0,
        rank=None,
        max_residual=None,
        assembled=None,
        singularities=[],
        chart=None,
    )
    (tmp_path / "old.json").write_text(json.dumps(saved))
    (tmp_path / "new.json").write_text(json.dumps(document))
    run = run_cli(
        "diff", str(tmp_path / "old.json"), str(tmp_path / "new.json"), "--format", "json"
    )
    assert run.code == 1, run
    assert [(c["kind"], c["after"]) for c in _changes(run.stdout)] == [
        ("mechanism", "1 loop, Grübler 0, mobility not sought")
    ]


def test_a_cut_moved_on_the_same_links_is_a_change(tmp_path: Path) -> None:
    """The same links held elsewhere are another four-bar, though it moves as much."""
    moved = tmp_path / "fourbar.xml"
    moved.write_text(
        FOURBAR.read_text().replace('anchor="0.25548 0 -1.47808"', 'anchor="0.25548 0 -0.5"')
    )
    run = run_cli("diff", str(FOURBAR), str(moved), "--format", "json")
    assert run.code == 1, run
    changes = [(c["kind"], c["after"]) for c in _changes(run.stdout)]
    assert changes == [
        (
            "cut-changed",
            "connect 'ground_pivot': rocker to world (3 equations) at "
            "(0.25548, 0, -0.5) in rocker and (2, 0, 0.97808) in world",
        )
    ]


def _ball(urdf: str, a: str, b: str, p_ap: str, p_bq: str) -> str:
    start = urdf.index("<drake:ball_constraint>", urdf.index("<robot"))
    end = urdf.index("</drake:ball_constraint>") + len("</drake:ball_constraint>")
    ball = (
        f'<drake:ball_constraint><drake:ball_constraint_body_A name="{a}"/>'
        f'<drake:ball_constraint_body_B name="{b}"/>'
        f'<drake:ball_constraint_p_AP value="{p_ap}"/>'
        f'<drake:ball_constraint_p_BQ value="{p_bq}"/></drake:ball_constraint>'
    )
    return urdf[:start] + ball + urdf[end:]


def test_a_cut_written_end_for_end_is_the_same_and_its_links_swapped_are_not(
    tmp_path: Path,
) -> None:
    """The ball constraint's bodies exchanged with its points: the same loop; the bodies
    exchanged alone: another (the tip held 2 m out on the ground, the pivot on the rocker)."""
    urdf = (REPO / "tests" / "closed" / "fourbar_drake.urdf").read_text()
    tip, pivot = "0.25548 0 -1.47808", "2 0 0"
    files = {
        "old": _ball(urdf, "rocker", "ground", tip, pivot),
        "same": _ball(urdf, "ground", "rocker", pivot, tip),
        "swapped": _ball(urdf, "ground", "rocker", tip, pivot),
    }
    for name, text in files.items():
        (tmp_path / f"{name}.urdf").write_text(text)
    old = str(tmp_path / "old.urdf")
    same, swapped = run_cli_many(
        [("diff", old, str(tmp_path / f"{name}.urdf"), "--format", "json") for name in files][1:]
    )
    assert same.code == 0 and _changes(same.stdout) == [], same
    assert swapped.code == 1 and [c["kind"] for c in _changes(swapped.stdout)] == ["cut-changed"]


def test_a_weld_turned_is_the_same_as_itself_at_a_tight_tolerance(tmp_path: Path) -> None:
    """A weld's frame turned by a unit quaternion whose squares sum to just below 1 (as
    rounding leaves many): the report against itself at ``--tolerance 1e-12`` is no
    change, the angle between the two frames being 0, not the ``acos`` of a rounded 1."""
    run = run_cli("inspect", str(REPO / "tests" / "closed" / "fourr_rigid.xml"), "--format", "json")
    assert run.code == 0, run.stderr
    document = json.loads(run.stdout)
    turned = [0.2926333321367466, 0.7986193006627497, 0.05030076913226407, 0.523490953270625]
    assert sum(x * x for x in turned) < 1.0
    (cut,) = document["closure"]["cuts"]
    assert cut["free"] == "none"  # its rotation counts
    cut["frame_a"]["rotation_wxyz"] = turned
    saved = tmp_path / "weld.json"
    saved.write_text(json.dumps(document))
    same = run_cli("diff", str(saved), str(saved), "--tolerance", "1e-12", "--format", "json")
    assert same.code == 0 and _changes(same.stdout) == [], same
