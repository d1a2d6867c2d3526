"""Saved reports are untrusted like robot files: their tree and sizes are checked, and
every renderer is linear in them.

Each case of issue 22 that made ``cspace diff --format html`` unbounded (two fixed joints
in a loop, a loop of moving joints, 9,980 joints between two links, 60,000-character
names of ``&``) is built here and run through the installed command: one line
``[bad-report]`` within 10 s of CPU and 600 MiB (measured forked: what the reports make
cspace do, the interpreter's start-up left out). The largest report the checks allow (5,001
joints, names of 256 ``&``, findings) diffs in every format within the same bounds; a
report made to fill the page (42,000 coordinate cells, 10,000 findings) draws within
them too. Names are shortened where drawn, whole in the JSON. Every report cspace
writes passes the checks (root joints, several joints on one MJCF body, MJCF scenes of
several top-level bodies, SDF, an ERD robot).
"""

from __future__ import annotations

import functools
import json
import re
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cspace
from cspace._findings import finding
from cspace._joint_kind import JointKind
from cspace._joint_table import canonical_coordinates
from cspace._manifold import NormalForm
from cspace._reports.report import JointReport, Limits, Report, Source
from cspace._reports.savedreport import read_report_document
from cspace._schema import report_schema

from conftest import (
    PEAK_MIB,
    REPO,
    ROBOTS,
    SECONDS,
    assert_bounded_error,
    manifold_section,
    measured,
    run_cli,
)

NAME = 256
"""The longest name a robot file may have (``name-too-long``), and so a saved report."""


def name(prefix: str, k: object, length: int = NAME, char: str = "&") -> str:
    """A name of ``length`` characters: ``char`` repeated, then ``prefix`` and ``k``."""
    tail = f"{prefix}{k}"
    return char * (length - len(tail)) + tail


def joint_dict(
    joint: str, parent: str | None, child: str, kind: str = "fixed", **more: Any
) -> dict[str, Any]:
    """A joint's JSON object: fixed, or a revolute one with a place in q."""
    moving = kind != "fixed"
    return {
        "name": joint,
        "kind": kind,
        "parent_link": parent,
        "child_link": child,
        "manifold": "R^1" if moving else "point",
        "dimension": int(moving),
        "limits": None,
        "q_index": None,
        "nq": 0,
        "v_index": None,
        "nv": 0,
        "mimic": None,
        "pinocchio_model": None,
        "line": None,
        **more,
    }


def saved(joints: list[dict[str, Any]], fmt: str = "urdf", robot: str = "r") -> bytes:
    """A saved report of these joints, consistent where the checks look (a point)."""
    document = json.loads((REPO / "tests" / "golden" / "arm7.json").read_text())
    form = NormalForm()
    document.update(joints=joints, robot=robot, dimension=0, nq=0, nv=0, diagnostics=[])
    document["source"]["format"] = fmt
    document["manifold"] = manifold_section(form)
    document["coordinates"] = {"size": 0, "dimension": 0, "entries": [], "neutral": []}
    return json.dumps(document).encode()


def diff_html(tmp_path: Path, data: bytes) -> Any:
    """``cspace diff --format html old.json new.json`` of a report against itself."""
    (tmp_path / "old.json").write_bytes(data)
    (tmp_path / "new.json").write_bytes(data)
    return measured("diff", "--format", "html", "old.json", "new.json", cwd=tmp_path, forked=True)


# --- the measured cases of issue 22 ---------------------------------------------------


@pytest.mark.bounded
def test_two_fixed_joints_in_a_loop(tmp_path: Path) -> None:
    # Was: no answer in 13 s, 700 MiB and growing (the fixed run never ended).
    joints = [joint_dict("j0", "r", "a"), joint_dict("j1", "a", "b"), joint_dict("j2", "b", "a")]
    message = assert_bounded_error(diff_html(tmp_path, saved(joints)), "bad-report")
    assert "link 'a' has two parents (joints 'j0' and 'j2') at /joints/2/child_link" in message
    bare = [joint_dict("j1", "a", "b"), joint_dict("j2", "b", "a")]  # no root at all
    message = assert_bounded_error(diff_html(tmp_path, saved(bare)), "bad-report")
    assert "link 'a' is the root and the child of joint 'j2': the joints close a loop" in message


@pytest.mark.bounded
def test_a_loop_of_moving_joints(tmp_path: Path) -> None:
    # Was: 2 GiB in 4 s.
    joints = [
        joint_dict("j0", "r", "a", "revolute"),
        joint_dict("j1", "a", "b", "revolute"),
        joint_dict("j2", "b", "a", "revolute"),
    ]
    message = assert_bounded_error(diff_html(tmp_path, saved(joints)), "bad-report")
    assert "has two parents" in message and "/joints/2/child_link" in message


@pytest.mark.bounded
def test_thousands_of_joints_between_two_links(tmp_path: Path) -> None:
    # Was: no answer in 13 s (9,980 joints, a 2.7 MB report).
    many = [joint_dict(f"j{k}", "base", "arm", "revolute") for k in range(9980)]
    message = assert_bounded_error(diff_html(tmp_path, saved(many, "mjcf")), "bad-report")
    assert "an array of 9,980 items, more than 5,001 at /joints" in message
    two = saved(many[:2], "urdf")  # two joints on one link: MJCF alone writes that
    message = assert_bounded_error(diff_html(tmp_path, two), "bad-report")
    assert "only MJCF puts several joints on one link at /joints/1/child_link" in message


@pytest.mark.bounded
def test_an_mjcf_body_of_five_thousand_joints_draws_as_one_edge(tmp_path: Path) -> None:
    # What cspace inspect reads (a body may hold as many joints as a robot), bounded.
    joints = [
        joint_dict(name("j", k, 128), "world", "body", "revolute", q_index=k, nq=1)
        for k in range(5000)
    ]
    result = diff_html(tmp_path, saved(joints, "mjcf"))
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    page = result.run.stdout
    assert page.count('<g class="edge') == 4  # one edge a tree, two trees a side
    assert " + 4,994 more" in page


@pytest.mark.bounded
def test_names_of_sixty_thousand_ampersands(tmp_path: Path) -> None:
    # Was: 397 MB of HTML, 1.5 GiB (a 16 MB report).
    amp = "&" * 60_000
    joints = [joint_dict(amp[: -len(str(k))] + str(k), amp, f"{amp}{k}") for k in range(88)]
    message = assert_bounded_error(diff_html(tmp_path, saved(joints, robot=amp)), "bad-report")
    assert "a string of 60,000 characters, more than 256 at /robot" in message


@pytest.mark.bounded
def test_names_that_print_alike_keep_their_own_findings(tmp_path: Path) -> None:
    # The control character and its escape typed out print
    # alike, so 2^8 names shared one key, and each card listed every finding of it;
    # (7 MB of report: 30 s, 7.4 GiB, 2 GB of HTML).
    import itertools

    names = ["".join(p) for p in itertools.product(["\x01", "\\x01"], repeat=7)]
    joints = [joint_dict(n, "base", f"l{k}") for k, n in enumerate(names)]
    document = json.loads(saved(joints))
    warning = {"severity": "warning", "code": "x", "joint": names[0], "line": None}
    document["diagnostics"] = [{**warning, "message": "&" * 600}] * 10_000
    result = diff_html(tmp_path, json.dumps(document).encode())
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    page = result.run.stdout
    assert len(page) < 200_000_000  # 10,000 findings listed twice, and one card's
    assert (
        len({k for k in re.findall(r'class="(?:card|chip)[^"]*" data-joint="([^"]*)"', page)})
        == 128
    )  # one key a name


def test_a_picture_of_any_document_ends() -> None:
    # render_html_document takes any document: loops, a link reached twice, a link named
    # like the drawing's world, drawn each once, in time linear in the joints.
    from cspace._render.html import render_html_document

    loops = [
        [joint_dict("j0", "r", "a"), joint_dict("j1", "a", "b"), joint_dict("j2", "b", "a")],
        [joint_dict(f"j{k}", "r", "a" if k % 2 else "b", "revolute") for k in range(3000)],
        [joint_dict("j0", None, "(world)"), joint_dict("j1", "(world)", "(world)")],
    ]
    for joints in loops:
        page = render_html_document(json.loads(saved(joints)))
        assert page.endswith("</html>\n") and len(page) < 10_000_000
    for kind in ("fixed", "revolute"):  # a ring under the root: fixed ones are collapsed
        ring = [joint_dict("j", "r", "l0")]
        ring += [joint_dict(f"j{k}", f"l{k}", f"l{(k + 1) % 3000}", kind) for k in range(3000)]
        page = render_html_document(json.loads(saved(ring)))
        assert page.endswith("</html>\n") and len(page) < 10_000_000


# --- the tree a report may have -------------------------------------------------------

TREES = {
    "duplicate-name": (
        [joint_dict("j", "r", "a"), joint_dict("j", "a", "b")],
        "joint 'j' appears twice (joints 0 and 1) at /joints/1/name",
    ),
    "second-root": (
        [joint_dict("j0", "r", "a"), joint_dict("j1", "x", "b")],
        "joint 'j1' hangs from link 'x', a second root (the root is 'r'): a robot's links "
        "make one tree",
    ),
    "under-a-second-root": (
        [joint_dict("j0", "r", "a"), joint_dict("j1", "b", "c"), joint_dict("j2", "x", "b")],
        "joint 'j1' hangs from link 'b', under a second root, 'x' (the root is 'r')",
    ),
    "parent-later": (
        [joint_dict("j0", "r", "a"), joint_dict("j1", "b", "c"), joint_dict("j2", "a", "b")],
        "joint 'j1' hangs from link 'b', which a later joint leads to: the joints are in "
        "tree order, parents first at /joints/1/parent_link",
    ),
    "unreachable-loop": (
        [joint_dict("j0", "r", "a"), joint_dict("j1", "b", "c"), joint_dict("j2", "c", "b")],
        "joint 'j1' hangs from link 'b', on a loop of joints that no root reaches",
    ),
    "self-loop": (
        [joint_dict("j0", "a", "a")],
        "joint 'j0' connects link 'a' to itself at /joints/0/child_link",
    ),
    "null-parent-later": (
        [joint_dict("j0", "r", "a"), joint_dict("j1", None, "b")],
        "joint 'j1' has no parent link: only the first joint (a root joint cspace added) "
        "may have none at /joints/1/parent_link",
    ),
    "mjcf-body-joints-apart": (
        [
            joint_dict("j0", "world", "b", "revolute"),
            joint_dict("j1", "world", "c", "revolute"),
            joint_dict("j2", "world", "b", "revolute"),
        ],
        "link 'b' has two parents (joints 'j0' and 'j2'): an MJCF body's joints come one "
        "after another at /joints/2/child_link",
    ),
    "long-names-quoted-short": (
        [joint_dict(name("j", 0), "r", "a"), joint_dict(name("j", 0), "a", "b")],
        f"joint '{'&' * 40}...' (256 characters) appears twice",
    ),
}


@pytest.mark.parametrize(("joints", "said"), TREES.values(), ids=list(TREES))
def test_a_report_is_a_tree(joints: list[dict[str, Any]], said: str) -> None:
    fmt = "mjcf" if joints[0]["parent_link"] == "world" else "urdf"
    with pytest.raises(cspace.errors.ReportFileError) as caught:
        read_report_document("old.json", saved(joints, fmt))
    assert said in str(caught.value)
    assert caught.value.code == "bad-report" and "\n" not in str(caught.value)


def test_the_tree_error_through_the_command(tmp_path: Path) -> None:
    joints, said = TREES["second-root"]
    (tmp_path / "old.json").write_bytes(saved(joints))
    run = run_cli("check", "old.json", "--dimension", "0", cwd=tmp_path)
    assert run.code == 2 and run.stdout == ""
    assert run.stderr == (
        f"cspace: error: old.json: not a valid cspace report: {said} at "
        "/joints/1/parent_link [bad-report]\n"
    )


def test_slots_name_at_most_what_inspect_writes() -> None:
    joints = [
        joint_dict(
            f"j{k}",
            "r" if k == 0 else f"l{k - 1}",
            f"l{k}",
            "revolute",
            slots={"pinocchio_q": {"index": 7 * k, "names": [f"j{k}.{c}" for c in "abcdefg"]}},
        )
        for k in range(2001)
    ]
    with pytest.raises(cspace.errors.ReportFileError) as caught:
        read_report_document("old.json", saved(joints))
    assert "more than 14,000 entries in pinocchio_q" in str(caught.value)
    assert caught.value.pointer == "/joints/2000/slots/pinocchio_q/names"


def test_the_caps_are_the_robot_files_caps() -> None:
    from cspace._formats.shared.robot_size import MAX_JOINTS, MAX_NAME
    from cspace._model.analysis import MAX_FINDINGS

    schema = report_schema()
    definitions = schema["$defs"]
    assert schema["properties"]["joints"]["maxItems"] == MAX_JOINTS + 1  # and a root joint
    assert definitions["name"]["maxLength"] == definitions["name_or_null"]["maxLength"] == MAX_NAME
    assert definitions["part_name"]["maxLength"] >= MAX_NAME + len(".theta.cos")
    assert schema["properties"]["diagnostics"]["maxItems"] == MAX_FINDINGS


# --- every report cspace writes passes ----------------------------------------------

WRITTEN = [
    *[(f"robots/{p.name}", None) for p in sorted(ROBOTS.glob("*.urdf"))],
    *[(f"robots/{p.name}", "floating") for p in sorted(ROBOTS.glob("*_nobase.urdf"))],
    ("robots/diffdrive_nobase.urdf", "planar"),
    ("robots/mjcf_every_joint.xml", None),  # two joints on one body
    ("robots/mjcf_top_level_bodies.xml", None),  # several bodies under the world
    ("robots/mjcf_scene_objects.xml", None),
    ("robots/mjcf_top_level_bodies.xml", "floating"),
    ("robots/mjcf_include/scene.xml", None),
    ("robots/sdf_every_joint.sdf", None),
    ("robots/sdf_every_joint.sdf", "floating"),
    ("erd:talos", None),
]


@pytest.mark.parametrize(("path", "root"), WRITTEN, ids=[f"{p}-{r}" for p, r in WRITTEN])
def test_every_report_cspace_writes_is_a_tree(path: str, root: str | None) -> None:
    target = path if path.startswith("erd:") else str(REPO / path)
    report = cspace.inspect(target, root)
    document = read_report_document(path, report.to_json().encode())
    assert len(document["joints"]) == len(report.joints)


# --- the largest reports the checks allow ---------------------------------------------


def _revolute_chain(n: int, fmt: str, findings: int) -> Report:
    """A floating root joint and ``n`` revolute joints in a chain, every name 256 ``&``."""
    joints = [
        JointReport(
            name="root_joint",
            kind=JointKind.FLOATING,
            parent_link=None,
            child_link=name("L", "w"),
            space=NormalForm(r=3, rp3=1),
            q_index=0,
            nq=7,
            v_index=0,
            nv=6,
            pinocchio_model="JointModelFreeFlyer",
        )
    ]
    for k in range(n):
        joints.append(
            JointReport(
                name=name("j", k),
                kind=JointKind.REVOLUTE,
                parent_link=joints[-1].child_link,
                child_link=name("L", k),
                space=NormalForm(r=1),
                limits=Limits((-1.5,), (1.5,), "rad"),
                q_index=7 + k,
                nq=1,
                v_index=6 + k,
                nv=1,
                pinocchio_model="JointModelRZ",
                line=k + 1,
                qposadr=7 + k if fmt == "mjcf" else None,
                dofadr=6 + k if fmt == "mjcf" else None,
            )
        )
    return _report(joints, fmt, findings)


def _report(joints: list[JointReport], fmt: str, findings: int) -> Report:
    moving = [j for j in joints if j.nq]
    diagnostics = tuple(
        finding("axis-default", moving[k % len(moving)].name, "&" * 600) for k in range(findings)
    )
    return Report(
        tool_version="*",
        source=Source("&" * 4096, fmt, "0" * 64),
        robot=name("robot", ""),
        root_joint="floating",
        manifold=NormalForm.product([j.space for j in joints]),
        nq=sum(j.nq for j in joints),
        nv=sum(j.nv for j in joints),
        joints=tuple(joints),
        diagnostics=diagnostics,
        coordinates=canonical_coordinates(tuple(joints)),
    )


@pytest.fixture(scope="session")
def largest(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """old.json, new.json: 5,001 joints, names of 256 ``&``, 1,500 findings of 600.

    The new side's limits differ for every joint, and its last 1,000 joints are renamed:
    4,000 changes of limits, 1,000 joints removed, 1,000 added.
    """
    folder = tmp_path_factory.mktemp("largest")
    old = _revolute_chain(5000, "urdf", findings=1500)
    joints = list(old.joints[:1])
    for k, joint in enumerate(old.joints[1:]):
        renamed = name("k", k) if k >= 4000 else joint.name
        joints.append(joint._replace(name=renamed, limits=Limits((-1.0,), (1.0,), "rad")))
    new = old._replace(joints=tuple(joints))
    for side, report in (("old", old), ("new", new)):
        data = report.to_json(indent=None).encode()
        assert 18_000_000 < len(data) <= 24 * 1024 * 1024  # at the joint, name and byte caps
        (folder / f"{side}.json").write_bytes(data)
    return folder


@pytest.mark.bounded
@pytest.mark.parametrize("fmt", ["text", "json", "markdown", "html"])
def test_the_largest_reports_diff_in_every_format(largest: Path, fmt: str) -> None:
    result = measured("diff", "--format", fmt, "old.json", "new.json", cwd=largest, forked=True)
    assert result.run.code == 1, result.run.stderr  # changed
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    out = result.run.stdout
    whole = name("k", 4999)  # a joint the new side adds
    if fmt == "json":
        changes = json.loads(out)["changes"]  # names whole
        assert len(changes) == 6000 and {"joint": whole, "kind": "joint-added"} in [
            {"joint": c["joint"], "kind": c["kind"]} for c in changes
        ]
    elif fmt == "html":
        # Drawn shortened (start…end) everywhere, whole only in its card's tooltip.
        shortened = "&amp;" * 21 + "…" + "&amp;" * 5 + "k4999"
        assert out.count(f'<h3 title="{whole.replace("&", "&amp;")}">{shortened}</h3>') == 1
        assert out.count(whole.replace("&", "&amp;")) == 1
        inputs = sum(len((largest / f"{side}.json").read_bytes()) for side in ("old", "new"))
        assert len(out.encode()) < 2 * inputs
    else:
        assert whole in out  # the text and Markdown keep names of up to 600 characters


def _page_filler() -> Report:
    """What a page costs most for, within every cap: 2,000 floating joints (14,000 cells
    in each of three strips), 3,001 fixed joints of long names, 10,000 findings of 600
    ``&``."""
    joints: list[JointReport] = []
    parent = name("L", "w", 32)
    for k in range(2000):
        joints.append(
            JointReport(
                name=name("j", k, 32),
                kind=JointKind.FLOATING,
                parent_link=parent,
                child_link=name("L", k, 32),
                space=NormalForm(r=3, rp3=1),
                q_index=7 * k,
                nq=7,
                v_index=6 * k,
                nv=6,
                pinocchio_model="JointModelFreeFlyer",
                qposadr=7 * k,
                dofadr=6 * k,
            )
        )
        parent = joints[-1].child_link
    for k in range(3001):
        fixed = JointReport(
            name("f", k, 200), JointKind.FIXED, parent, name("F", k, 200), NormalForm()
        )
        joints.append(fixed)
        parent = fixed.child_link
    return _report(joints, "mjcf", findings=10_000)._replace(root_joint=None)


@pytest.mark.bounded
def test_the_fullest_page_draws_within_the_bounds(tmp_path: Path) -> None:
    data = _page_filler().to_json(indent=None).encode()
    assert len(data) <= 24 * 1024 * 1024
    result = diff_html(tmp_path, data)
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    assert result.run.stdout.count('<div class="slot"') == 2 * 3 * 14_000


def test_long_names_are_shortened_in_the_picture_and_whole_in_its_tooltip(
    tmp_path: Path,
) -> None:
    joint = name("elbow", "", 256, "e")
    shortened = "e" * 21 + "…" + "e" * 5 + "elbow"
    robot = tmp_path / "long.urdf"
    robot.write_text(
        f'<robot name="r"><link name="a"/><link name="b"/><joint name="{joint}" '
        'type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    svg = run_cli("inspect", "long.urdf", "--format", "svg", cwd=tmp_path).stdout
    assert re.findall(r'class="joint-label">([^<]*)</text>', svg) == [shortened]
    assert f"<title>{joint}: revolute (R^1)</title>" in svg  # no cards: whole tooltips
    page = run_cli("inspect", "long.urdf", "--format", "html", cwd=tmp_path).stdout
    assert page.count(joint) == 1 and f'<h3 title="{joint}">{shortened}</h3>' in page
    assert page.count(f'class="joint-label">{shortened}</text>') == 2  # both trees
    report = json.loads(run_cli("inspect", "long.urdf", "--format", "json", cwd=tmp_path).stdout)
    assert report["joints"][0]["name"] == joint


# --- the quick schema check agrees with jsonschema ------------------------------------

_GOOD_TEXT = (REPO / "tests" / "golden" / "mjcf_every_joint.json").read_text()
_ODD = st.sampled_from(
    [None, True, 0, -1, 1.0, 2**31, "", "x" * 300, "R^1", [], {}, [1], {"a": 1}, "\n"]
)


def _paths(value: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    items = (
        value.items() if isinstance(value, dict) else enumerate(value)
        if isinstance(value, list) else ()
    )  # fmt: skip
    found = []
    for key, child in items:
        found.append((*path, key))
        found += _paths(child, (*path, key))
    return found


_GOOD_PATHS = _paths(json.loads(_GOOD_TEXT))
"""Every path of the good report, where the first change of each mutant is drawn."""


@st.composite
def _mutants(draw: st.DrawFn) -> dict[str, Any]:
    document = json.loads(_GOOD_TEXT)
    for k in range(draw(st.integers(1, 3))):
        paths = _GOOD_PATHS if k == 0 else _paths(document)
        path = paths[draw(st.integers(0, len(paths) - 1))]
        parent = document
        for key in path[:-1]:
            parent = parent[key]
        if draw(st.booleans()):
            parent[path[-1]] = draw(_ODD)
        elif isinstance(parent, dict):
            del parent[path[-1]]
    return document


@functools.cache
def _reference_validator() -> Any:
    """jsonschema's validator of the report schema, read as cspace reads it: made once,
    its references resolved once for every example."""

    def pattern(validator: Any, regex: str, instance: Any, schema: Any) -> Any:
        if validator.is_type(instance, "string"):
            found = re.search(regex, instance)
            if found is None or (regex.endswith("$") and found.end() != len(instance)):
                yield jsonschema.ValidationError("pattern")

    base = jsonschema.Draft202012Validator
    types = base.TYPE_CHECKER.redefine(
        "integer", lambda _c, v: isinstance(v, int) and not isinstance(v, bool)
    )
    strict = jsonschema.validators.extend(base, {"pattern": pattern}, type_checker=types)
    return strict(report_schema())


def _reference_pointer(document: dict[str, Any]) -> str | None:
    """The pointer of jsonschema's first error, read as cspace reads the schema."""
    error = next(iter(_reference_validator().iter_errors(document)), None)
    if error is None:
        return None
    return "".join(f"/{part}" for part in error.absolute_path)


@settings(max_examples=400, derandomize=True, database=None, deadline=None)
@given(_mutants())
def test_the_quick_check_reports_what_jsonschema_reports(document: dict[str, Any]) -> None:
    version = document.get("schema_version")
    checked_before = (
        "joints" not in document or "manifold" not in document or type(version) is not int
    )
    expected = _reference_pointer(document)
    try:
        read_report_document("old.json", json.dumps(document).encode())
    except cspace.errors.ReportFileError as error:
        if expected is not None and not checked_before:  # jsonschema's first error
            assert error.pointer == expected, (error, expected)
        return
    assert expected is None


@pytest.mark.parametrize("field", ["qposadr", "dofadr"])
def test_an_mjcf_layout_far_beyond_its_joints_is_refused(field: str) -> None:
    """A saved report may say any qposadr up to 2^31: MuJoCo's layout is rebuilt from
    the joints' sizes, so an edited one is refused at once (it was a 16 GB name list)."""
    document = cspace.inspect(REPO / "robots" / "mjcf_equality.xml").to_dict()
    next(j for j in document["joints"] if j["name"] == "cam")[field] = 2_000_000_000
    report = cspace.Report.from_dict(document)
    with pytest.raises(cspace.errors.JointMatchError, match="MuJoCo would place it at 7 and 7"):
        cspace.ConfigurationSpace.from_report(report)


@pytest.mark.parametrize("leader", ["nonexistent", "finger_right", "base_fixed", "gear_out"])
def test_a_mimic_of_no_one_coordinate_joint_gives_no_configurations(
    tmp_path: Path, leader: str
) -> None:
    """An edited mimic leader once made qpos silently from 0 or from another follower."""
    document = cspace.inspect(REPO / "robots" / "mjcf_equality.xml").to_dict()
    next(j for j in document["joints"] if j["name"] == "finger_right")["mimic"]["joint"] = leader
    with pytest.raises(cspace.errors.UnsupportedConfigurationError, match=f"'{leader}'"):
        cspace.ConfigurationSpace.from_report(cspace.Report.from_dict(document))
    saved = tmp_path / "edited.json"
    saved.write_text(json.dumps(document))
    run = run_cli("diff", str(saved), str(saved))
    if leader in ("nonexistent", "finger_right"):  # not a report cspace could write
        assert run.code == 2 and run.stderr.strip().endswith("[bad-report]"), run.stderr
        assert "/joints/3/mimic/joint" in run.stderr
    else:
        assert run.code == 0


def _ball_forest() -> Report:
    """The report of most bytes cspace writes: 3,333 ball joints (9,999 degrees of
    freedom, each named in six slots), a continuous joint and 1,666 fixed ones, in chains
    of 50 from one link, every name 256 ``&``, 1,500 findings."""
    joints: list[JointReport] = []
    q = v = 0
    for k in range(5000):
        parent = name("L", "r") if k % 50 == 0 else joints[-1].child_link
        kind, space, nq, nv, model = (
            (JointKind.SPHERICAL, NormalForm(rp3=1), 4, 3, "JointModelSpherical")
            if k < 3333
            else (JointKind.CONTINUOUS, NormalForm(t=1), 2, 1, "JointModelRUBZ")
            if k == 3333
            else (JointKind.FIXED, NormalForm(), 0, 0, "")
        )
        joints.append(
            JointReport(
                name=name("j", k),
                kind=kind,
                parent_link=parent,
                child_link=name("L", k),
                space=space,
                q_index=q if nq else None,
                nq=nq,
                v_index=v if nv else None,
                nv=nv,
                pinocchio_model=model or None,
                line=k + 2,
            )
        )
        q, v = q + nq, v + nv
    return _report(joints, "urdf", findings=1500)._replace(root_joint=None)


def test_the_largest_report_cspace_writes_is_read_back(tmp_path: Path) -> None:
    data = _ball_forest().to_json(indent=None).encode()
    assert 30_000_000 < len(data) <= 48 * 1024 * 1024
    path = tmp_path / "largest.json"
    path.write_bytes(data)
    document = read_report_document(str(path), data)
    assert len(document["joints"]) == 5000
