"""The visual report: ``cspace inspect --format html`` and ``--format svg``.

The page is checked as text (self-contained, deterministic, every name escaped) and in
a real browser: Debian's Chromium (``make browser`` installs it) driven by Playwright,
with no console error, every joint in the DOM and in the diagram, hover highlighting a
joint everywhere, and screenshots of the teaching robots and of talos compared with
goldens in ``tests/golden/html`` (``CSPACE_UPDATE_GOLDENS=1`` writes them anew).
"""

from __future__ import annotations

import io
import json
import os
import re
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

import cspace
from cspace._render.html import render_html
from cspace._render.svg import render_svg

from conftest import HASH_SEED, REPO, ROBOTS, run_cli

GOLDEN = REPO / "tests" / "golden" / "html"
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
ROBOT_CASES = [  # paths relative to the repository (the page shows them): same pixels anywhere
    *[(p.name, f"robots/{p.name}", None) for p in sorted(ROBOTS.glob("*.urdf"))],
    ("mjcf_every_joint.xml", "robots/mjcf_every_joint.xml", None),
    ("sdf_every_joint.sdf", "robots/sdf_every_joint.sdf", None),
    ("quadruped_nobase.floating", "robots/quadruped_nobase.urdf", "floating"),
    ("talos", "erd:talos", None),
    ("fourbar.xml", "tests/closed/fourbar.xml", None),  # a loop, drawn on the tree
    ("chain_loops.xml", "tests/closed/chain_loops.xml", None),  # loops on an outline
]
HOSTILE = """<robot name="evil\u202e">
  <link name="a"/><link name="b&lt;script&gt;alert(1)&lt;/script&gt;"/>
  <joint name="j&lt;/svg&gt;&lt;script&gt;alert(2)&lt;/script&gt;\u2066\u009b31m" type="revolute">
    <parent link="a"/><child link="b&lt;script&gt;alert(1)&lt;/script&gt;"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""


@pytest.fixture(autouse=True)
def _in_the_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)


def _report(path: str, root_joint: str | None) -> cspace.Report:
    return cspace.inspect(path, root_joint)


@pytest.mark.parametrize(("name", "path", "root"), ROBOT_CASES, ids=[c[0] for c in ROBOT_CASES])
def test_the_page_is_self_contained_deterministic_and_names_every_joint(
    name: str, path: str, root: str | None
) -> None:
    report = _report(path, root)
    page = render_html(report)
    assert page == render_html(_report(path, root))  # the same bytes every time
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)  # no network
    assert "<link" not in page and "<script src" not in page and "@import" not in page
    document = etree.fromstring(page.encode(), etree.HTMLParser())
    cards = document.xpath("//div[@class='card']/@data-joint")
    chips = document.xpath("//span[@class='chip']/@data-joint")  # folded into their cards
    fixed = {j.name for j in report.joints if j.kind.value == "fixed"}
    assert cards == [j.name for j in report.joints if j.name not in fixed]
    assert sorted(chips) == sorted(fixed)
    drawn: set[str] = set()
    for names in document.xpath("//div[contains(@class,'full')]//*[@data-joints]/@data-joints"):
        drawn.update(json.loads(names))
    assert drawn == {j.name for j in report.joints}  # every joint in the full diagram
    assert report.manifold.notation in page


def test_svg_is_the_tree_with_its_spaces_and_a_legend() -> None:
    report = _report(str(ROBOTS / "mjcf_every_joint.xml"), None)
    svg = render_svg(report)
    root = etree.fromstring(svg.encode())  # well-formed XML
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    assert "R^10 × S^1 × (RP^3)^2" in svg and "the circle S^1" in svg
    drawn = {n for g in root.iter("{*}g") for n in json.loads(g.get("data-joints", "[]"))}
    assert {j.name for j in report.joints if j.kind.value != "fixed"} <= drawn
    run = run_cli("inspect", str(ROBOTS / "mjcf_every_joint.xml"), "--format", "svg")
    assert run.code == 0 and run.stdout == svg


def test_hostile_names_are_escaped_in_the_page_and_the_svg(tmp_path: Path) -> None:
    robot = tmp_path / "evil.urdf"
    robot.write_text(HOSTILE)
    for fmt in ("html", "svg"):
        run = run_cli("inspect", str(robot), "--format", fmt)
        assert run.code == 0, run.stderr
        assert "<script>alert" not in run.stdout and "</svg><script>" not in run.stdout
        assert all(line.isprintable() for line in run.stdout.splitlines())
        assert "\\u202e" in run.stdout and "\\x9b" in run.stdout  # shown, escaped


def test_several_files_are_refused_for_a_picture() -> None:
    run = run_cli(
        "inspect", str(ROBOTS / "arm7.urdf"), str(ROBOTS / "arm7.urdf"), "--format", "html"
    )
    assert run.code == 2 and "draws one robot" in run.stderr


# --- in a browser ---------------------------------------------------------------------

_ARGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]  # fmt: skip


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    if not os.path.exists(CHROMIUM):
        # never skipped: `make test` installs it (make browser), as it does zsh and fish
        pytest.fail("no Chromium on this machine (make browser: apt-get install chromium)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=_ARGS)
        yield chromium
        chromium.close()


@pytest.mark.parametrize(("name", "path", "root"), ROBOT_CASES, ids=[c[0] for c in ROBOT_CASES])
def test_the_page_in_a_browser(
    browser: Any, tmp_path: Path, name: str, path: str, root: str | None
) -> None:
    report = _report(path, root)
    page_file = tmp_path / "report.html"
    page_file.write_text(render_html(report))
    page = browser.new_page(viewport={"width": 1100, "height": 760})
    problems: list[str] = []
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: problems.append(str(e)))
    page.on("request", lambda r: None if r.url.startswith("file:") else problems.append(r.url))
    page.goto(page_file.as_uri())
    fixed = [j for j in report.joints if j.kind.value == "fixed"]
    assert page.locator(".card[data-joint]").count() == len(report.joints) - len(fixed)
    assert page.locator(".chip").count() == len(fixed)
    _assert_readable(page)
    moving = [j for j in report.joints if j.kind.value not in ("fixed", "mimic")]
    if moving:
        joint = moving[-1].name
        edge = page.locator(f"div.collapsed g.edge[data-joint={json.dumps(joint)}]")
        edge.locator("text").hover()  # the label: a curve is hit only on its stroke
        card = page.locator(f".card[data-joint={json.dumps(joint)}]")
        assert "hot" in (card.get_attribute("class") or "")  # highlighted everywhere
        page.mouse.move(1, 1)
        assert "hot" not in (card.get_attribute("class") or "")
    assert page.locator("div.full").is_hidden()
    page.locator("#show-fixed").check()
    assert page.locator("div.full").is_visible() and page.locator("div.collapsed").is_hidden()
    page.locator("#show-fixed").uncheck()
    shot = page.screenshot()
    page.close()
    assert problems == []
    _compare(shot, GOLDEN / f"{name}.png")


_LABELS_CLEAR = """() => {
  // Each tree's labels against every edge: points along each path, 2 px apart, must
  // fall outside every label's box (in the SVG's own coordinates).
  const hits = [];
  for (const svg of document.querySelectorAll("svg.tree")) {
    if (svg.getBoundingClientRect().width === 0) continue;  // the hidden tree
    const boxes = [...svg.querySelectorAll("text")].map(t => [t.textContent, t.getBBox()]);
    for (const path of svg.querySelectorAll("path")) {
      const length = path.getTotalLength();
      for (let at = 0; at <= length; at += 2) {
        const p = path.getPointAtLength(at);
        for (const [label, b] of boxes) {
          if (p.x > b.x && p.x < b.x + b.width && p.y > b.y && p.y < b.y + b.height) {
            hits.push(label);
          }
        }
      }
    }
  }
  return [...new Set(hits)];
}"""

_BROKEN_NAMES = """() => {
  // A name may wrap only where a <wbr> allows: each run of ASCII text between them is on
  // one line (one box). (CJK text wraps between its characters, as it should.) A name
  // wider than its box is listed apart: a single word too long for its card is cut.
  const broken = [], wide = [];
  for (const el of document.querySelectorAll(".card h3, .chip")) {
    if (el.scrollWidth > el.clientWidth + 1) wide.push(el.textContent);
    for (const node of el.childNodes) {
      if (node.nodeType !== Node.TEXT_NODE || !/^[\\x21-\\x7e]+$/.test(node.textContent)) continue;
      const range = document.createRange();
      range.selectNodeContents(node);
      const lines = new Set([...range.getClientRects()].map(r => Math.round(r.top)));
      if (lines.size > 1) broken.push(el.textContent);
    }
  }
  return {broken, wide};
}"""


_LABELS_INSIDE = """() => [...document.querySelectorAll("svg.tree")]
  .filter(svg => svg.getBoundingClientRect().width > 0)
  .flatMap(svg => [...svg.querySelectorAll("text")]
    .filter(t => t.getBBox().x + t.getBBox().width > svg.viewBox.baseVal.width)
    .map(t => t.textContent))"""


def _assert_readable(page: Any) -> None:
    """Labels clear of edges and inside their picture, no name broken inside a word."""
    for shown_fixed in (False, True):
        page.locator("#show-fixed").set_checked(shown_fixed)
        assert page.evaluate(_LABELS_CLEAR) == []
        assert page.evaluate(_LABELS_INSIDE) == []
    page.locator("#show-fixed").set_checked(False)
    assert page.evaluate(_BROKEN_NAMES) == {"broken": [], "wide": []}


def test_a_humanoid_reads_at_1400_pixels_without_scrolling_sideways(browser: Any) -> None:
    """Talos (60 joints, 27 fixed): the page fits 1,400 px, both trees within their
    boxes, fixed joints folded into the cards of the joints they hang from."""
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.set_content(render_html(_report("erd:talos", None)))
    for shown_fixed in (False, True):
        page.locator("#show-fixed").set_checked(shown_fixed)
        wide = page.evaluate(
            "() => [document.documentElement, ...document.querySelectorAll('.scroll')]"
            ".filter(e => e.getClientRects().length && e.scrollWidth > e.clientWidth)"
            ".map(e => e.className || e.tagName)"
        )
        assert wide == []
    assert page.locator(".card[data-joint]").count() == 33  # the moving joints
    hand = page.locator(".card[data-joint='arm_left_7_joint'] .chip")
    assert hand.count() == 9 and hand.first.text_content() == "wrist_left_ft_joint"
    hand.first.hover()  # a folded joint still highlights in the tree
    assert "hot" in (
        page.locator("div.full g.edge[data-joint='wrist_left_ft_joint']").get_attribute("class")
        or ""
    )
    page.close()


def _compare(shot: bytes, golden: Path) -> None:
    """The screenshot matches its golden: same size, under 1% of pixels visibly different."""
    from PIL import Image, ImageChops

    if os.environ.get("CSPACE_UPDATE_GOLDENS") or not golden.exists():
        golden.parent.mkdir(parents=True, exist_ok=True)
        golden.write_bytes(shot)
        assert os.environ.get("CSPACE_UPDATE_GOLDENS"), f"{golden} was missing: written now"
        return
    new = Image.open(io.BytesIO(shot)).convert("RGB")
    old = Image.open(golden).convert("RGB")
    assert new.size == old.size
    difference = ImageChops.difference(new, old).convert("L").point(lambda v: 255 if v > 40 else 0)
    changed = sum(difference.histogram()[255:]) / (new.size[0] * new.size[1])
    assert changed < 0.01, f"{changed:.1%} of the pixels differ from {golden.name}"


def test_the_diff_page_marks_the_changes_on_both_sides(browser: Any, tmp_path: Path) -> None:
    changed = tmp_path / "arm7.urdf"
    changed.write_text((ROBOTS / "arm7.urdf").read_text().replace('upper="3.7"', 'upper="3.0"'))
    run = run_cli("diff", "robots/arm7.urdf", str(changed), "--format", "html")
    assert run.code == 1, run.stderr  # a change
    page_file = tmp_path / "diff.html"
    page_file.write_text(run.stdout)
    again = run_cli("diff", "robots/arm7.urdf", str(changed), "--format", "html", env=HASH_SEED[1])
    assert run.stdout == again.stdout  # the same bytes from another interpreter
    page = browser.new_page(viewport={"width": 1300, "height": 800})
    problems: list[str] = []
    page.on("pageerror", lambda e: problems.append(str(e)))
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.goto(page_file.as_uri())
    marked = page.locator(".card.changed")
    assert marked.count() == 2  # wrist_pitch, old side and new side
    assert set(marked.evaluate_all("cards => cards.map(c => c.dataset.joint)")) == {"wrist_pitch"}
    assert page.locator("div.collapsed g.edge.changed").count() == 2
    page.locator("#old .card[data-joint='wrist_pitch']").hover()
    assert "hot" in (
        page.locator("#new .card[data-joint='wrist_pitch']").get_attribute("class") or ""
    )
    page.close()
    assert problems == []


def test_a_folder_of_pages_has_one_per_robot_and_an_index(tmp_path: Path) -> None:
    """``--output-dir``: a page (or SVG) per robot, named by its place and its file's
    name made safe, and an index linking each; a file without a report is listed with
    its reason; the summary table goes to standard output."""
    robots = tmp_path / "robots"
    robots.mkdir()
    shutil.copy(ROBOTS / "arm7.urdf", robots / "arm7.urdf")
    shutil.copy(ROBOTS / "arm7.urdf", robots / 'a "b"<i>.urdf')
    (robots / "broken.urdf").write_text('<robot name="b"><link name="a"/><joint name="j"/></robot>')
    run = run_cli("inspect", "robots", "--format", "html", "--output-dir", "pages", cwd=tmp_path)
    assert run.code == 2, run.stderr  # the broken file
    assert run.stdout.startswith("robot ") and "2 without a report" not in run.stdout
    pages = sorted(p.name for p in (tmp_path / "pages").iterdir())
    assert pages == ["1-a__b__i_.urdf.html", "2-arm7.urdf.html", "index.html"]
    assert (tmp_path / "pages" / "2-arm7.urdf.html").read_text() == render_html(
        cspace.inspect(robots / "arm7.urdf")
    ).replace(str(robots / "arm7.urdf"), "robots/arm7.urdf")
    index = etree.fromstring((tmp_path / "pages" / "index.html").read_bytes(), etree.HTMLParser())
    links = [(a.get("href"), a.text) for a in index.iter("a")]
    assert links == [
        ("1-a__b__i_.urdf.html", 'robots/a "b"<i>.urdf'),
        ("2-arm7.urdf.html", "robots/arm7.urdf"),
    ]
    assert (
        "broken.urdf" in "".join(index.itertext())
        and "<i>" not in (tmp_path / "pages" / "index.html").read_text()
    )
    svg = run_cli(
        "inspect", "robots/arm7.urdf", "--format", "svg", "--output-dir", "trees", cwd=tmp_path
    )
    assert svg.code == 0 and (tmp_path / "trees" / "1-arm7.urdf.svg").read_text().startswith("<svg")
    text = run_cli("inspect", "robots/arm7.urdf", "--output-dir", "x", cwd=tmp_path)
    assert text.code == 2 and "--output-dir is for --format html or svg" in text.stderr


def _branching_urdf(names: list[str]) -> str:
    """A URDF: the first joint's child link holds the others (each name a joint)."""
    joints = [(names[0], "base", "hub")] + [(n, "hub", f"l{k}") for k, n in enumerate(names[1:])]
    links = "".join(
        f'<link name="{link}"/>' for link in ["base", "hub"] + [j[2] for j in joints[1:]]
    )
    return (
        f'<robot name="r">{links}'
        + "".join(
            f'<joint name="{n}" type="revolute"><parent link="{p}"/><child link="{c}"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
            for n, p, c in joints
        )
        + "</robot>"
    )


@pytest.mark.parametrize(
    "names",
    [
        ["W" * 32, "b", "c", "d"],  # wide capitals, drawn left to right
        ["LeftShoulderPitchActuatorJointA", "LeftShoulderPitchActuatorJointB", "x"],
        ["关节一号" * 8, "%@" * 16, "m" * 32],
        [f"joint_{k}_{'M' * 20}" for k in range(12)],  # an outline of wide names
    ],
    ids=["wide", "camel", "cjk", "outline"],
)
def test_hard_names_stay_readable(browser: Any, tmp_path: Path, names: list[str]) -> None:
    """Labels were sized at 7.2 px a character, so capitals
    and CJK ran through dots, edges and other labels, and a camel-case name without
    separators was cut with no way to read it."""
    robot = tmp_path / "r.urdf"
    robot.write_text(_branching_urdf(names))
    page = browser.new_page(viewport={"width": 1100, "height": 760})
    page.set_content(render_html(cspace.inspect(robot)))
    for shown_fixed in (False, True):
        page.locator("#show-fixed").set_checked(shown_fixed)
        assert page.evaluate(_LABELS_CLEAR) == []
        assert page.evaluate(_LABELS_INSIDE) == []
    names_as_shown = page.evaluate(_BROKEN_NAMES)
    assert names_as_shown["broken"] == []
    camel = {n for n in names if n.startswith("Left")}  # words a card can wrap between
    assert not camel & set(names_as_shown["wide"])  # wider words end in "…", titled
    titles = page.locator(".card h3").evaluate_all("hs => hs.map(h => h.title)")
    assert sorted(titles) == sorted(names)  # every whole name is a card's tooltip
    page.close()


def test_a_fixed_body_in_mjcf_folds_into_the_last_joint_of_its_parent(tmp_path: Path) -> None:
    """MuJoCo applies a body's joints in order: a welded child hangs from the last."""
    robot = tmp_path / "r.xml"
    robot.write_text(
        '<mujoco><worldbody><body name="arm"><joint name="first" axis="0 0 1"/>'
        '<joint name="second" axis="0 1 0"/><geom size="0.1"/>'
        '<body name="tool"><geom size="0.05"/></body></body></worldbody></mujoco>'
    )
    report = cspace.inspect(robot)
    fixed = [j.name for j in report.joints if j.kind.value == "fixed"]
    assert len(fixed) == 1
    page = etree.fromstring(render_html(report).encode(), etree.HTMLParser())
    assert page.xpath("//div[@data-joint='second']//span[@class='chip']/@data-joint") == fixed


def test_label_widths_are_an_upper_bound_of_every_ascii_character(browser: Any) -> None:
    """``!`` and a backquote stay within their bound."""
    from cspace._render.tree import _text_width

    page = browser.new_page()
    page.set_content(render_html(cspace.inspect(ROBOTS / "arm7.urdf")))
    printable_ascii = [chr(c) for c in range(0x20, 0x7F)]
    measured = page.evaluate(
        """(chars) => {
          const svg = document.querySelector("svg.tree");
          const t = document.createElementNS("http://www.w3.org/2000/svg", "text");
          t.setAttribute("class", "joint-label");
          svg.appendChild(t);
          return chars.map(ch => {
            t.textContent = ch.repeat(20);
            return t.getComputedTextLength() / 20;
          });
        }""",
        printable_ascii,
    )
    page.close()
    over = [
        (ch, w, _text_width(ch))
        for ch, w in zip(printable_ascii, measured, strict=True)
        if w > _text_width(ch)
    ]
    assert over == []
