"""MuJoCo compiles the document the pre-scan read, or the file is refused.

lxml (the pre-scan) and tinyxml2 (MuJoCo's XML parser) read some bytes differently: a
DOCTYPE that tinyxml2 ends at its first ``>``, a namespace lxml puts every tag in, a tab
lxml turns into a space. MuJoCo is therefore given lxml's serialisation of what the
pre-scan read, and a DOCTYPE or a namespace is refused; one base name (as MuJoCo keys
the files it is given) for two files is refused too. MuJoCo's error lines still name
the file's lines. Every case runs the installed `cspace` command, within the bounds.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import PEAK_MIB, SECONDS, Measured, assert_bounded_error, measured

pytestmark = pytest.mark.bounded
"""Every test here runs the command within the time and memory bounds."""

SECRET = "TOP-SECRET-77a1"

BOMB = (
    '<replicate count="100"><replicate count="100">'
    '<body><joint/><geom size=".1"/></body></replicate></replicate>'
)
"""10,000 bodies: past what the pre-scan lets MuJoCo build (MuJoCo ran out of memory)."""

HIDDEN = (
    '<mujoco model="hidden"><worldbody><body name="h"><freejoint name="evil_free"/>'
    f'<geom size=".1"/></body>{BOMB}<include file="{{outside}}/secret.xml"/>'
    "</worldbody></mujoco>"
)
"""What a hostile file hides from one parser: a free joint, a replicate bomb, an include
of a file outside the tree."""

BENIGN = (
    '<mujoco model="benign"><worldbody><body name="b"><joint name="j"/><geom size=".1"/>'
    "</body></worldbody></mujoco>"
)


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    """The robot's folder, with a secret folder beside it."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.xml").write_text(
        f'<mujocoinclude><body name="{SECRET}"><joint/><geom size=".1"/></body></mujocoinclude>'
    )
    inside = tmp_path / "tree"
    inside.mkdir()
    return inside


def _write(tree: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        (tree / name).parent.mkdir(parents=True, exist_ok=True)
        (tree / name).write_text(text.replace("{outside}", str(tree.parent / "outside")))


def _refused(tree: Path, files: dict[str, str], code: str, main: str = "main.xml") -> str:
    _write(tree, files)
    error = assert_bounded_error(measured("inspect", main, cwd=tree), code)
    for hidden in ("hidden", "evil_free", SECRET):
        assert hidden not in error
    return error


def _inspected(tree: Path, main: str = "main.xml") -> dict[str, object]:
    result: Measured = measured("inspect", main, "--format", "json", cwd=tree)
    assert result.run.code == 0, result
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    report: dict[str, object] = json.loads(result.run.stdout)
    return report


# --- 1 (a): a DOCTYPE ---------------------------------------------------------------


@pytest.mark.parametrize(
    "doctype",
    [
        # lxml: a comment in the internal subset; tinyxml2: the DOCTYPE ends at "]>".
        f"<!DOCTYPE mujoco [ <!-- ]>\n{HIDDEN}\n--> ]>",
        # lxml: a quoted system id; tinyxml2: the DOCTYPE ends at "x>".
        f"<!DOCTYPE mujoco SYSTEM 'x>\n{HIDDEN}\n'>",
        "<!DOCTYPE mujoco>",  # harmless, but MuJoCo's parser would read it otherwise
    ],
    ids=["internal subset", "system id", "plain"],
)
def test_a_doctype_is_refused(doctype: str, tree: Path) -> None:
    error = _refused(tree, {"main.xml": f"{doctype}\n{BENIGN}\n"}, "xml-unsafe")
    assert error.startswith("cspace: error: main.xml:1: the file has a DOCTYPE")


def test_a_doctype_in_an_included_file_is_refused(tree: Path) -> None:
    part = f"<!DOCTYPE x [ <!-- ]>\n{HIDDEN}\n--> ]>\n<mujocoinclude/>\n"
    main = '<mujoco model="m"><worldbody><include file="part.xml"/></worldbody></mujoco>'
    error = _refused(tree, {"main.xml": main, "part.xml": part}, "xml-unsafe")
    assert "DOCTYPE" in error and "(in part.xml, line 1)" in error


# --- 1 (b): namespaces --------------------------------------------------------------


def test_an_included_root_in_a_namespace_is_refused(tree: Path) -> None:
    # lxml reads {urn:x}replicate and {urn:x}include: neither counted nor read; MuJoCo
    # knows no namespaces and would build both.
    part = (
        f'<mujoco xmlns="urn:x"><worldbody>{BOMB}<include file="{{outside}}/secret.xml"/>'
        "</worldbody></mujoco>"
    )
    main = '<mujoco model="m"><worldbody><include file="part.xml"/></worldbody></mujoco>'
    error = _refused(tree, {"main.xml": main, "part.xml": part}, "xml-unsafe")
    assert "namespace" in error and "(in part.xml, line 1)" in error


@pytest.mark.parametrize(
    ("main", "line"),
    [
        ('<mujoco model="m" xmlns:q="urn:q"><worldbody/></mujoco>', 1),  # declared, unused
        ('<mujoco model="m"><worldbody>\n<q:body xmlns:q="urn:q"/></worldbody></mujoco>', 2),
        ('<mujoco model="m"><worldbody>\n<xml:include file="x.xml"/></worldbody></mujoco>', 2),
    ],
    ids=["declared", "prefixed", "xml prefix"],
)
def test_a_namespace_in_the_main_file_is_refused(main: str, line: int, tree: Path) -> None:
    error = _refused(tree, {"main.xml": main}, "xml-unsafe")
    assert error.startswith(f"cspace: error: main.xml:{line}: <") and "XML namespace" in error


def test_a_main_root_in_a_namespace_is_no_mjcf(tree: Path) -> None:
    main = f'<mujoco model="m" xmlns="urn:x"><worldbody>{BOMB}</worldbody></mujoco>'
    _refused(tree, {"main.xml": main}, "not-a-robot")


def test_a_namespace_in_an_attached_model_is_refused(tree: Path) -> None:
    main = (
        '<mujoco model="r"><asset><model name="M" file="m.xml"/></asset>'
        '<worldbody><attach model="M" prefix="p"/></worldbody></mujoco>'
    )
    # lxml reads {urn:x}worldbody and {urn:x}replicate: nothing counted (MuJoCo's schema
    # happens to refuse an xmlns attribute but on the root of an include: refused first).
    inner = '<replicate count="60"><body><joint/><geom size=".1"/></body></replicate>'
    model = f'<mujoco model="M">\n<worldbody xmlns="urn:x"><replicate count="100">{inner}'
    model += "</replicate></worldbody></mujoco>"
    error = _refused(tree, {"main.xml": main, "m.xml": model}, "xml-unsafe")
    assert "(in m.xml, line 2)" in error


# --- 1 (c): white space lxml normalises ---------------------------------------------


def test_a_tab_in_an_include_name_finds_the_file_cspace_read(tree: Path) -> None:
    # lxml reads "a b.xml" (a tab in an attribute is a space to XML); MuJoCo, given the
    # raw bytes, kept the tab, missed the file in memory and went to the disk.
    main = '<mujoco model="m"><worldbody><include file="a\tb.xml"/></worldbody></mujoco>'
    benign = '<mujocoinclude><body name="b"><joint name="j"/><geom size=".1"/></body>'
    _write(
        tree,
        {
            "main.xml": main,
            "a b.xml": benign + "</mujocoinclude>",
            "a\tb.xml": f"<mujocoinclude>{BOMB}<body name='hidden'/></mujocoinclude>",
        },
    )
    report = _inspected(tree)
    assert report["robot"] == "m" and report["dimension"] == 1
    assert "hidden" not in json.dumps(report)


def test_names_with_references_reach_mujoco_as_lxml_read_them(tree: Path) -> None:
    # A tab, a line break and markup characters written as references: MuJoCo is given
    # lxml's serialisation, and names the joint as the pre-scan does.
    main = (
        '<mujoco model="m&amp;&lt;&#233;"><worldbody><body name="b&#9;1">'
        '<joint name="j&#10;&quot;1&apos;"/><geom size=".1"/></body></worldbody></mujoco>'
    )
    _write(tree, {"main.xml": main})
    report = _inspected(tree)
    assert report["robot"] == "m&<é"
    joints = json.dumps(report)
    assert json.dumps("j\n\"1'")[1:-1] in joints


# --- 2: one base name, two files ----------------------------------------------------


def _as_mujoco_reads_it_from_the_disk(tree: Path, files: dict[str, str]) -> None:
    """cspace's report and MuJoCo's own compile of the files on disk: the same joints."""
    import mujoco

    report = _inspected(tree)
    model = mujoco.MjModel.from_xml_path(str(tree / "main.xml"))
    assert (report["nq"], report["nv"]) == (model.nq, model.nv)
    names = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, i) for i in range(model.njnt)}
    ours = {j["name"] for j in report["joints"] if j["nv"]}  # type: ignore[index, union-attr]
    assert ours == names


def test_one_name_for_two_files_is_read_as_mujoco_reads_it(tree: Path) -> None:
    # ./part.xml (one body) for the main file and m/part.xml (four) for the model: MuJoCo
    # is given each under a name of its own, and builds what the pre-scan counted, as it
    # builds it from the disk (given by base name alone, it would read one for both)
    body = '<body name="b{k}"><joint name="j{k}"/><geom size=".1"/></body>'
    files = {
        "main.xml": (
            '<mujoco model="main"><asset><model name="M" file="m/model.xml"/></asset>\n'
            '<worldbody><include file="part.xml"/><body name="t"><joint name="tj"/>'
            '<geom size=".1"/><attach model="M" prefix="a_"/></body></worldbody></mujoco>'
        ),
        "part.xml": f"<mujocoinclude>{body.format(k=0)}</mujocoinclude>",
        "m/model.xml": '<mujoco model="M"><worldbody>\n<include file="part.xml"/></worldbody>'
        "</mujoco>",
        "m/part.xml": "<mujocoinclude>"
        + "".join(body.format(k=k) for k in range(1, 5))
        + "</mujocoinclude>",
    }
    _write(tree, files)
    _as_mujoco_reads_it_from_the_disk(tree, files)
    assert _inspected(tree)["dimension"] == 6


def test_one_name_in_another_case_for_two_files_is_read_as_mujoco_reads_it(tree: Path) -> None:
    body = '<body name="b{k}"><joint name="j{k}"/><geom size=".1"/></body>'
    files = {
        "main.xml": (
            '<mujoco model="main"><asset><model name="M" file="m/model.xml"/></asset>\n'
            '<worldbody><include file="sub/Part.xml"/><body name="t"><joint name="tj"/>'
            '<geom size=".1"/><attach model="M" prefix="a_"/></body></worldbody></mujoco>'
        ),
        "sub/Part.xml": f"<mujocoinclude>{body.format(k=0)}</mujocoinclude>",
        "m/model.xml": '<mujoco model="M"><worldbody><include file="PART.xml"/></worldbody>'
        "</mujoco>",
        "m/PART.xml": "<mujocoinclude>"
        + "".join(body.format(k=k) for k in range(1, 5))
        + "</mujocoinclude>",
    }
    _write(tree, files)
    _as_mujoco_reads_it_from_the_disk(tree, files)


def test_a_message_of_mujoco_names_a_file_as_the_document_does() -> None:
    # MuJoCo was given m/part.xml as part~2.xml: its message must not say part~2.xml
    from cspace._formats.mjcf._compiler import _refused
    from cspace._formats.mjcf._prescan import PreScan

    scan = PreScan(given={"part~2.xml": "m/part.xml"})
    error = _refused("main.xml", "XML Error: could not open file 'part~2.xml'", scan, None)
    assert "'m/part.xml'" in str(error) and "part~2" not in str(error)


def test_one_name_for_one_file_from_two_documents_is_read(tree: Path) -> None:
    # The main file and its attached model, in one folder, include the same file.
    part = '<mujocoinclude><body name="p"><joint name="pj"/><geom size=".1"/></body>'
    files = {
        "main.xml": (
            '<mujoco model="main"><asset><model name="M" file="model.xml"/></asset>'
            '<worldbody><include file="part.xml"/><body name="t"><joint name="tj"/>'
            '<geom size=".1"/><attach model="M" prefix="a_"/></body></worldbody></mujoco>'
        ),
        "part.xml": part + "</mujocoinclude>",
        "model.xml": '<mujoco model="M"><worldbody><include file="part.xml"/></worldbody></mujoco>',
    }
    _write(tree, files)
    assert _inspected(tree)["dimension"] == 3


# --- MuJoCo's lines are the file's --------------------------------------------------

SPREAD = """<?xml version="1.0"?>
<!-- a comment
     over three lines -->
<mujoco
   model="lines">
  <compiler
     autolimits="false"/>
  <worldbody>
    <!-- another
    -->
    <body name="a"
          pos="0 0 1"><geom size=".1"/>
      <joint name="ok" range="-1 1" limited="true"/><joint
         name="bad"{attributes}/><joint name="after"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize(
    ("attributes", "reason"),
    [
        (' type="bogus"', "invalid keyword"),  # refused while parsing, by tag
        ('\n         range="-1 1"', "has `range` but not `limited`"),  # compiling, by name
    ],
    ids=["parse", "compile"],
)
def test_mujocos_line_is_where_the_start_tag_begins(
    attributes: str, reason: str, tree: Path
) -> None:
    _write(tree, {"main.xml": SPREAD.format(attributes=attributes)})
    error = assert_bounded_error(measured("inspect", "main.xml", cwd=tree), "mujoco-refused")
    # <joint name="bad" ... begins on line 13, as MuJoCo reads the file itself.
    assert error.startswith("cspace: error: main.xml:13: MuJoCo refuses the model: ")
    assert reason in error and "line 13" in error


def test_an_attached_models_error_is_at_its_model_element(tree: Path) -> None:
    main = (
        '<mujoco model="r">\n<!--\n-->\n<asset><model\n name="M" file="m.xml"/></asset>\n'
        '<worldbody><attach model="M" prefix="p"/></worldbody></mujoco>\n'
    )
    model = '<mujoco model="M"><worldbody><body name="a">\n<joint type="x"/>'
    model += '<geom size=".1"/></body></worldbody></mujoco>\n'
    _write(tree, {"main.xml": main, "m.xml": model})
    error = assert_bounded_error(measured("inspect", "main.xml", cwd=tree), "mujoco-refused")
    # MuJoCo names the joint at line 2 of m.xml, then the <model> at line 4 of main.xml.
    assert error.startswith("cspace: error: main.xml:4: MuJoCo refuses the model: ")


def test_comments_instructions_and_cdata_change_nothing(tree: Path) -> None:
    main = (
        '<?xml version="1.0"?>\n<?pi <mujoco model="hidden"/> ?>\n<!-- <body name="c"/> -->\n'
        '<mujoco model="m"><worldbody><![CDATA[<body name="hidden"/>]]>'
        '<body name="b"><joint name="j"/><geom size=".1"/></body></worldbody></mujoco>\n'
    )
    _write(tree, {"main.xml": main})
    report = _inspected(tree)
    assert report["robot"] == "m" and report["dimension"] == 1
    assert "hidden" not in json.dumps(report)


def test_a_replicated_elements_error_keeps_its_line(tree: Path) -> None:
    # MuJoCo names the copy "j00": the element named "j" at that line.
    main = (
        '<mujoco model="r">\n<compiler autolimits="false"/>\n<worldbody>\n'
        '<replicate count="30"><body name="b"><geom size=".1"/><joint\n name="j"\n'
        ' range="0 1"/></body></replicate></worldbody></mujoco>\n'
    )
    _write(tree, {"main.xml": main})
    error = assert_bounded_error(measured("inspect", "main.xml", cwd=tree), "mujoco-refused")
    assert error.startswith("cspace: error: main.xml:4: MuJoCo refuses the model: ")
    assert "Element name 'j00', id 0, line 4" in error


def test_an_included_files_error_names_the_file(tree: Path) -> None:
    main = (
        '<mujoco model="r">\n<compiler autolimits="false"/>\n<worldbody>\n'
        '<include file="part.xml"/></worldbody></mujoco>\n'
    )
    part = '<mujocoinclude>\n<body name="b"><geom size=".1"/>\n<joint name="k" range="0 1"/>'
    _write(tree, {"main.xml": main, "part.xml": part + "</body></mujocoinclude>\n"})
    error = assert_bounded_error(measured("inspect", "main.xml", cwd=tree), "mujoco-refused")
    assert error.startswith("cspace: error: main.xml: MuJoCo refuses the model: ")
    assert "(in part.xml, line 3)" in error


def test_line_references_planted_in_a_message_cost_nothing(tmp_path: Path) -> None:
    # MuJoCo quotes an unknown class name, and each "line N"
    # planted in it was mapped by a parse of the whole document (18.9 s for 2 MB); only
    # MuJoCo's own location, the last, is read now.
    planted = "A" + "Element '', line 3" * 300
    (tmp_path / "inc.xml").write_text(
        f'<mujoco><worldbody><body><joint class="{planted}"/><geom size=".1"/></body>'
        "</worldbody></mujoco>\n"
    )
    sites = "<site/>\n" * 245_000
    (tmp_path / "big.xml").write_text(
        f'<mujoco>\n<include file="inc.xml"/>\n<worldbody>\n{sites}</worldbody>\n</mujoco>\n'
    )
    result = measured("inspect", "big.xml", cwd=tmp_path)
    assert_bounded_error(result, "mujoco-refused")  # within 10 s: it took 18.9


def test_two_robots_each_named_robot_xml_attach_as_mujoco_attaches_them(tree: Path) -> None:
    # robosuite names every robot file robot.xml; a scene attaching two of them compiles
    arm = (
        '<mujoco model="{m}"><worldbody><body name="base">'
        '<body name="l1"><joint name="j1" range="-1 1"/><geom size=".1"/>'
        '<body name="l2"><joint name="j2"/><geom size=".1"/></body></body>'
        "</body></worldbody></mujoco>"
    )
    files = {
        "main.xml": (
            '<mujoco model="main"><asset><model name="panda" file="panda/robot.xml"/>'
            '<model name="iiwa" file="iiwa/robot.xml"/></asset><worldbody>'
            '<body name="left"><attach model="panda" prefix="left_"/></body>'
            '<body name="right"><attach model="iiwa" prefix="right_"/></body>'
            "</worldbody></mujoco>"
        ),
        "panda/robot.xml": arm.format(m="panda"),
        "iiwa/robot.xml": arm.format(m="iiwa").replace('range="-1 1"', ""),
    }
    _write(tree, files)
    _as_mujoco_reads_it_from_the_disk(tree, files)
    assert _inspected(tree)["manifold"]["notation"] == "R^1 × T^3"  # type: ignore[index]
