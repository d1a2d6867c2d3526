"""Every output format of ``cspace collisions``, run as a user runs it.

On example-robot-data's UR5 with its SRDF (``--srdf auto``: three ``<disable_collisions>``
at lines 15, 19 and 20 disable pairs that collide): the SARIF log validates against
the SARIF 2.1.0 schema and has a result per finding on the SRDF's line, the annotations
are one workflow command per finding and nothing else, the Markdown lists the pairs to
look at first, the page draws the matrix of link pairs with one cell per pair. On a
hostile robot (boxes only) whose link, joint, group and pose names, SRDF reason and file
names hold ``::error::``, ``##[group]``, a bidi override, C1, a newline, ``|``,
backticks, ``@mention`` and HTML: no format writes a workflow command of a name, every
line is printable, the Markdown holds no raw HTML of a name and its tables keep their
cells, the page escapes every name. The pages are opened in Debian's Chromium (``make
browser``) through Playwright: no script, no request, the matrix readable for 8 and 40
links.
"""

from __future__ import annotations

import json
import os
import re
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import jsonschema
import pytest
from lxml import etree
from test_ci_formats import COMMAND, SARIF_SCHEMA
from test_ci_log import assert_no_command, assert_printable, run_safely

from cspace._findings import CODES, MEANINGS
from cspace._render.formats import FORMATS, choices
from cspace._safetext import printable

from conftest import run_cli

SAMPLES = "300"
UR5 = ("collisions", "erd:ur5", "--srdf", "auto", "-n", SAMPLES)
FORMATS_OF_COLLISIONS = ["text", "json", "markdown", "sarif", "github", "html"]
"""The formats tested here (``cspace collisions`` may offer more: each is held to the CI
log's rules on the hostile robot all the same)."""
LEVEL = {"error": "error", "warning": "warning", "info": "note"}

BASE = "::error::base|<script>alert(1)</script>"
A = "##[group]a\u202e\u0085|x"
B = "b`tick`@mention\n::warning::nl%25<b>x</b>"
C = "c<i>@x</i>"
J1, J2, J3 = "::error::j1", "##[group]j2\u202e", "j3"
GROUP = "##[group]arm|<i>"
POSE = "::error::pose|<script>"
REASON = "::error::why|<i>"
ROBOT_FILE = "::error::evil|<i>.urdf"
SRDF_FILE = "##[group]evil.srdf"
HOSTILE = (BASE, A, B, C)


def _link(name: str) -> str:
    x = 0.0 if name == BASE else 0.5
    size = 0.2 if name == BASE else 0.3
    return (
        f'<link name={quoteattr(name)}><collision><origin xyz="{x} 0 0"/><geometry>'
        f'<box size="{size} {size} {size}"/></geometry></collision></link>\n'
    )


def _joint(name: str, child: str, yaw: float) -> str:
    return (
        f'<joint name={quoteattr(name)} type="revolute"><origin rpy="0 0 {yaw}"/>'
        f"<parent link={quoteattr(BASE)}/><child link={quoteattr(child)}/>"
        '<axis xyz="0 0 1"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>\n'
    )


def _hostile_urdf() -> str:
    """Three boxes turning about the base's axis, each overlapping the others at some
    angles (A and B never at zero: B starts half a turn away, C a quarter)."""
    return (
        f"<robot name={quoteattr('::error::robot##[x]')}>\n"
        + "".join(_link(n) for n in HOSTILE)
        + _joint(J1, A, 0.0)
        + _joint(J2, B, 3.14159)
        + _joint(J3, C, 1.5708)
        + "</robot>\n"
    )


def _hostile_srdf() -> str:
    """A group state with A over C (checked: a pose in collision, line 3); A and B
    disabled though they overlap at some angles (line 4)."""
    joints = "".join(f"<joint name={quoteattr(j)}/>" for j in (J1, J2, J3))
    values = "".join(
        f"<joint name={quoteattr(j)} value={quoteattr(v)}/>"
        for j, v in ((J1, "1.5708"), (J2, "0"), (J3, "0"))
    )
    return (
        f"<robot name={quoteattr('::error::robot##[x]')}>\n"
        f"<group name={quoteattr(GROUP)}>{joints}</group>\n"
        f"<group_state name={quoteattr(POSE)} group={quoteattr(GROUP)}>{values}</group_state>\n"
        f"<disable_collisions link1={quoteattr(A)} link2={quoteattr(B)} "
        f"reason={quoteattr(REASON)}/>\n"
        "</robot>\n"
    )


@pytest.fixture(scope="module")
def hostile(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder with the hostile robot and its SRDF, under names that are commands."""
    folder = tmp_path_factory.mktemp("hostile")
    (folder / ROBOT_FILE).write_text(_hostile_urdf())
    (folder / SRDF_FILE).write_text(_hostile_srdf())
    return folder


def _hostile_args(fmt: str) -> tuple[str, ...]:
    return ("collisions", ROBOT_FILE, "--srdf", SRDF_FILE, "-n", SAMPLES, "--format", fmt)


@pytest.fixture(scope="module")
def hostile_outputs(hostile: Path) -> dict[str, str]:
    """Each format's output of the hostile robot, held to the CI log's rules: no
    workflow command but cspace's own annotations, every line printable, exit 1 (the
    SRDF disables a pair that collides)."""
    outputs = {}
    for fmt in choices("collisions"):
        code, out, err = run_safely(hostile, *_hostile_args(fmt), ours=fmt == "github")
        assert code == 1, err
        outputs[fmt] = out
    return outputs


@pytest.fixture(scope="module")
def ur5() -> dict[str, str]:
    """Each format's output of the UR5 with its SRDF (exit 1: its errors)."""
    outputs = {}
    for fmt in FORMATS_OF_COLLISIONS:
        done = run_cli(*UR5, "--format", fmt)
        assert done.code == 1 and "Traceback" not in done.stderr, done.stderr
        assert_no_command(done.stdout, ours=fmt == "github")
        outputs[fmt] = done.stdout
    return outputs


def test_every_format_of_collisions_comes_from_the_table() -> None:
    assert set(FORMATS_OF_COLLISIONS) <= set(choices("collisions"))
    for name in choices("collisions"):
        assert hasattr(FORMATS[name].renderer(), "collisions"), name
    done = run_cli("collisions", "--help")
    help_text = " ".join(done.stdout.split())
    assert done.code == 0
    for name in choices("collisions"):
        assert " ".join(FORMATS[name].collisions.split()) in help_text, name


# --- the UR5 and its SRDF --------------------------------------------------------------


def test_ur5_sarif_is_a_result_per_finding_on_the_srdfs_lines(ur5: dict[str, str]) -> None:
    report = json.loads(ur5["json"])
    log = json.loads(ur5["sarif"])
    jsonschema.Draft4Validator(SARIF_SCHEMA).validate(log)
    (run,) = log["runs"]
    results = run["results"]
    assert len(results) == len(report["diagnostics"]) == 4
    for result, finding in zip(results, report["diagnostics"], strict=True):
        assert result["ruleId"] == finding["code"]
        assert result["level"] == LEVEL[finding["severity"]]
        location = result["locations"][0]["physicalLocation"]
        assert location["artifactLocation"]["uri"].endswith("/srdf/ur5.srdf")
        assert location["artifactLocation"]["uri"].startswith("file:///")  # an absolute path
        assert location.get("region", {}).get("startLine") == finding["line"]
        rule = run["tool"]["driver"]["rules"][result["ruleIndex"]]
        assert rule["id"] == finding["code"]
        assert rule["shortDescription"]["text"] == MEANINGS[finding["code"]]
        assert rule["defaultConfiguration"]["level"] == LEVEL[CODES[finding["code"]].value]
    reachable = [
        r["locations"][0]["physicalLocation"]["region"]["startLine"]
        for r in results
        if r["ruleId"] == "collision-disabled-but-reachable"
    ]
    assert reachable == [15, 19, 20]


def test_ur5_annotations_are_the_findings_and_nothing_else(ur5: dict[str, str]) -> None:
    report = json.loads(ur5["json"])
    lines = ur5["github"].splitlines()
    matched = [COMMAND.fullmatch(line) for line in lines]
    assert all(matched), lines
    assert len(lines) == len(report["diagnostics"])
    found = [(m.group(1), m.group(3), m.group(4)) for m in matched if m]
    assert found == [
        (
            {"error": "error", "warning": "warning", "info": "notice"}[d["severity"]],
            None if d["line"] is None else str(d["line"]),
            f"cspace {d['code']}",
        )
        for d in report["diagnostics"]
    ]
    assert all(m.group(2).endswith("/srdf/ur5.srdf") for m in matched if m)
    lines_of_reachable = [m.group(3) for m in matched if m and "reachable" in m.group(4)]
    assert lines_of_reachable == ["15", "19", "20"]


def test_ur5_markdown_puts_the_pairs_against_the_srdf_first(ur5: dict[str, str]) -> None:
    text = ur5["markdown"]
    assert text.startswith("### cspace collisions: `ur5`\n")
    assert "**Free of self-collision**" in text and "**With the pairs cspace checks**" in text
    first, _, rest = text.partition("<details>")
    rows = [line for line in first.splitlines() if line.startswith("| `")]
    assert len(rows) == 18  # 17 pairs that collide sometimes, and one adjacent always
    assert all("⚠" in row for row in rows[:4]) and not any("⚠" in row for row in rows[4:])
    assert sorted(re.findall(r"ur5\.srdf:(\d+)", "".join(rows[:3]))) == ["15", "19", "20"]
    folded, _, findings = rest.partition("</details>")
    assert folded.startswith("<summary>10 other pairs: never in collision, adjacent</summary>")
    assert len([line for line in folded.splitlines() if line.startswith("| `")]) == 10
    assert findings.count("- **error** `collision-disabled-but-reachable` (`ur5.srdf:") == 3


def test_ur5_page_draws_one_cell_per_pair(ur5: dict[str, str]) -> None:
    report = json.loads(ur5["json"])
    page = ur5["html"]
    document = etree.fromstring(page.encode(), etree.HTMLParser())
    links = report["links"]
    assert document.xpath("//table[@class='matrix']//th[@class='row']/@title") == links[1:]
    assert document.xpath("//table[@class='matrix']//th[@class='col']/@title") == links[:-1]
    cells = document.xpath("//table[@class='matrix']//td[contains(@class,'p ')]")
    assert len(cells) == len(report["pairs"]) == 28
    titles = {tuple(c.get("title").split("\n")[0].split(" - ")) for c in cells}
    assert titles == {(p["link1"], p["link2"]) for p in report["pairs"]}
    framed = [c.get("title").split("\n")[0] for c in cells if "bad" in c.get("class").split()]
    assert sorted(framed) == [
        "base_link - upper_arm_link",
        "ee_link - wrist_3_link",
        "forearm_link - wrist_2_link",
        "forearm_link - wrist_3_link",
    ]
    hatched = [c for c in cells if "off" in c.get("class").split()]
    assert len(hatched) == sum(not p["rule"]["checked"] for p in report["pairs"])
    csp = document.xpath("//meta[@http-equiv='Content-Security-Policy']/@content")
    assert csp and "default-src 'none'" in csp[0]
    assert not document.xpath("//script") and "<link" not in page
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert len(document.xpath("//section[@id='findings']//li")) == 4


# --- a hostile robot -------------------------------------------------------------------


def test_no_name_writes_a_workflow_command_in_any_format(
    hostile: Path, hostile_outputs: dict[str, str]
) -> None:
    """`run_safely` holds each output to the CI log's rules; here the names still show."""
    report = json.loads(hostile_outputs["json"])
    assert report["links"] == list(HOSTILE)  # JSON keeps every name exact
    kinds = {(p["link1"], p["link2"]): p["kind"] for p in report["pairs"]}
    assert kinds[(A, B)] == "sometimes"
    codes = [d["code"] for d in report["diagnostics"]]
    assert codes == ["collision-disabled-but-reachable", "collision-pose"]
    for fmt in ("text", "markdown", "html"):
        assert "\\x3a:error::robot" in hostile_outputs[fmt]  # the robot's name, shown escaped
        assert "##\\x5bgroup]" in hostile_outputs[fmt]
    assert "##\\\\x5bgroup]" in hostile_outputs["sarif"]  # in a JSON string


def test_hostile_annotations_one_command_per_finding(hostile_outputs: dict[str, str]) -> None:
    report = json.loads(hostile_outputs["json"])
    lines = hostile_outputs["github"].splitlines()
    matched = [COMMAND.fullmatch(line) for line in lines]
    assert all(matched) and len(lines) == len(report["diagnostics"]) == 2
    assert [(m.group(2), m.group(3)) for m in matched if m] == [
        ("##[group]evil.srdf", "4"),  # the file named as it is, for the annotation to land
        ("##[group]evil.srdf", "3"),
    ]
    text = hostile_outputs["github"]
    assert "\n::warning::nl" not in text and "%0A" not in text  # the newline shown as \n


def test_hostile_sarif_validates_and_keeps_the_names_as_text(
    hostile_outputs: dict[str, str],
) -> None:
    log = json.loads(hostile_outputs["sarif"])
    jsonschema.Draft4Validator(SARIF_SCHEMA).validate(log)
    results = log["runs"][0]["results"]
    uris = [r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in results]
    assert uris == ["%23%23%5Bgroup%5Devil.srdf"] * 2  # relative, percent-encoded
    lines = [r["locations"][0]["physicalLocation"]["region"]["startLine"] for r in results]
    assert lines == [4, 3]
    for r in results:
        assert r["message"]["text"] == printable(r["message"]["text"], limit=None)
        assert "\n" not in r["message"]["text"] and "\u202e" not in r["message"]["text"]


_CODE_SPAN = re.compile(r"(`+)(?!`)(.*?)(?<!`)\1(?!`)")
_OURS = {"<details>", "</details>", "<summary>", "</summary>"}


def test_hostile_markdown_has_no_raw_html_and_whole_tables(
    hostile_outputs: dict[str, str],
) -> None:
    text = hostile_outputs["markdown"]
    for name in HOSTILE:
        assert printable(name) in text.replace("\\|", "|")
    outside = _CODE_SPAN.sub("CODE", text)  # what Markdown reads outside code spans
    assert set(re.findall(r"</?[A-Za-z][^>\s]*>?", outside)) <= _OURS, outside
    assert "@" not in outside and "<script" not in outside and "`" not in outside
    for line in text.splitlines():
        if line.startswith("|"):
            cells = re.split(r"(?<!\\)\|", line)
            assert len(cells) == 7, line  # five cells between the outer pipes


def test_hostile_page_escapes_every_name(hostile_outputs: dict[str, str]) -> None:
    page = hostile_outputs["html"]
    document = etree.fromstring(page.encode(), etree.HTMLParser())
    assert not document.xpath("//script") and "<script>alert" not in page
    assert not document.xpath("//i[not(@style)] | //b[text()='x'] | //*[@onerror]")
    rows = document.xpath("//table[@class='matrix']//th[@class='row']/@title")
    assert rows == [printable(n, limit=None) for n in HOSTILE[1:]]
    cells = document.xpath("//table[@class='matrix']//td[contains(@class,'p ')]")
    assert len(cells) == 6
    assert_printable(page)


# --- in a browser ----------------------------------------------------------------------

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run"]


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    if not os.path.exists(CHROMIUM):
        pytest.fail("no Chromium on this machine (make browser: apt-get install chromium)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield chromium
        chromium.close()


def _chain(links: int) -> str:
    """A planar chain of ``links`` boxes, each turning on the one before."""
    box = '<collision><origin xyz="0.1 0 0"/><geometry><box size="0.24 0.08 0.08"/></geometry>'
    return (
        f'<robot name="chain{links}">'
        + "".join(
            f'<link name="link_{k:02d}_segment">{box}</collision></link>' for k in range(links)
        )
        + "".join(
            f'<joint name="joint_{k:02d}" type="revolute"><origin xyz="0.2 0 0"/>'
            f'<parent link="link_{k - 1:02d}_segment"/><child link="link_{k:02d}_segment"/>'
            '<axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>'
            for k in range(1, links)
        )
        + "</robot>"
    )


_UNREADABLE = """() => {
  // Labels wider than their box (a cut name), column labels wider than their column,
  // and the page wider than the window.
  const out = [];
  for (const th of document.querySelectorAll("table.matrix th.row, table.matrix th.col div")) {
    if (th.scrollWidth > th.clientWidth + 1 || th.scrollHeight > th.clientHeight + 1) {
      out.push("cut: " + th.textContent);
    }
  }
  const cell = document.querySelector("table.matrix td.p").getBoundingClientRect();
  for (const div of document.querySelectorAll("table.matrix th.col div")) {
    if (div.getBoundingClientRect().width > cell.width + 1) out.push("wide: " + div.textContent);
  }
  if (document.documentElement.scrollWidth > window.innerWidth) out.push("page too wide");
  return out;
}"""


def _open(browser: Any, page_file: Path, width: int) -> tuple[Any, list[str]]:
    page = browser.new_page(viewport={"width": width, "height": 900})
    problems: list[str] = []
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: problems.append(str(e)))
    page.on("request", lambda r: None if r.url.startswith("file:") else problems.append(r.url))
    page.goto(page_file.as_uri())
    return page, problems


@pytest.mark.parametrize("links", [8, 40])
def test_the_matrix_in_a_browser(
    browser: Any, tmp_path: Path, ur5: dict[str, str], links: int
) -> None:
    """A cell per pair, readable labels, hovering a cell lights its row's and column's
    links; 40 links fit a window of 1,400 pixels (a screenshot is kept beside the page)."""
    if links == 8:  # the UR5
        html, report = ur5["html"], json.loads(ur5["json"])
    else:
        (tmp_path / "chain.urdf").write_text(_chain(links))
        args = ("collisions", "chain.urdf", "-n", SAMPLES)
        done = run_cli(*args, "--format", "html", cwd=tmp_path)
        assert done.code == 0, done.stderr
        html = done.stdout
        report = json.loads(run_cli(*args, "--format", "json", cwd=tmp_path).stdout)
    assert len(report["links"]) == links
    page_file = tmp_path / "collisions.html"
    page_file.write_text(html)
    page, problems = _open(browser, page_file, 1400)
    assert page.locator("table.matrix td.p").count() == links * (links - 1) // 2
    assert page.locator("script").count() == 0
    assert page.evaluate(_UNREADABLE) == []
    cell = page.locator("table.matrix tbody tr").nth(links - 2).locator("td").nth(0)
    cell.hover()  # the last row's first pair: the last link with the first
    title = cell.get_attribute("title") or ""
    assert title.split("\n")[0] == " - ".join(sorted((report["links"][-1], report["links"][0])))
    lit = page.evaluate(
        "() => [...document.querySelectorAll('table.matrix th')]"
        ".filter(th => getComputedStyle(th).backgroundColor === 'rgb(255, 224, 138)')"
        ".map(th => th.title)"
    )
    assert sorted(lit) == sorted([report["links"][-1], report["links"][0]])
    page.screenshot(path=str(tmp_path / "collisions.png"))
    page.close()
    assert problems == []


def test_the_hostile_page_in_a_browser(
    browser: Any, tmp_path: Path, hostile_outputs: dict[str, str]
) -> None:
    """No script runs, no request is made; every name is text, its tooltip whole."""
    page_file = tmp_path / "hostile.html"
    page_file.write_text(hostile_outputs["html"])
    page, problems = _open(browser, page_file, 1100)
    assert page.locator("script").count() == page.locator("i:not([style])").count() == 0
    heads = page.locator("table.matrix th.row").evaluate_all("hs => hs.map(h => h.title)")
    assert heads == [printable(n, limit=None) for n in HOSTILE[1:]]
    assert page.locator("table.matrix td.p").count() == 6
    base = page.locator("table.matrix th.col").first
    assert base.get_attribute("title") == printable(BASE, limit=None)  # whole, as text
    assert (base.text_content() or "").startswith("\\x3a:error::base|<scr")  # drawn shortened
    page.close()
    assert problems == []


def test_the_page_is_deterministic(ur5: dict[str, str]) -> None:
    again = run_cli(*UR5, "--format", "html", env={"PYTHONHASHSEED": "2"})
    assert again.stdout == ur5["html"]


def test_repository_relative_paths_in_sarif(tmp_path: Path) -> None:
    """A robot given by a relative path: its SRDF's URI is relative too."""
    robot = tmp_path / "robots"
    robot.mkdir()
    (robot / "r.urdf").write_text(_hostile_urdf())
    (robot / "r.srdf").write_text(_hostile_srdf())
    done = run_cli(
        "collisions", "robots/r.urdf", "--srdf", "robots/r.srdf", "-n", SAMPLES, "--format",
        "sarif", cwd=tmp_path,
    )  # fmt: skip
    assert done.code == 1, done.stderr
    uris = {
        r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
        for r in json.loads(done.stdout)["runs"][0]["results"]
    }
    assert uris == {"robots/r.srdf"}
