"""A folder's search, and --robots-only's names, leave out no robot its readers read.

Each broken robot here is one a reader takes for a robot (MuJoCo, urdfdom, Pinocchio's
MJCF parser, lxml, xacro; the tests ask them where they can), where a search that reads
less than they do would miss it without a word: junk before its root, which tinyxml2
reads; a top-level root after a long first element, which urdfdom and rapidxml read; a
document type whose internal subset holds ``]`` or ``>``, or whose entities make the
robot; a UTF-16 file; an include in an element named in non-ASCII letters, through a
link to a folder, or past a model's end; an include from another folder of a model that
names files of its own (an attached model, an include the search cannot name or does
not reach); a file of millions of comments, literals or attributes. Each is inspected
and fails (exit 2), in a folder's search and among the names a pull request changes
(``--robots-only -- NAMES``).
"""

from __future__ import annotations

import os
import subprocess
import tempfile
from pathlib import Path

import mujoco
import pinocchio
import pytest
import xacro
from lxml import etree

from conftest import Run, environment_folder, measured, mujoco_compiles
from conftest import robots_only_both_ways as _both
from conftest import summary_rows as _rows

ARM = (
    '<robot name="a"><link name="b"/><link name="c"/><joint name="j" type="revolute">'
    '<parent link="b"/><child link="c"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
    "</joint></robot>"
)
BROKEN_URDF = ARM.replace('lower="-1" upper="1"', 'lower="2" upper="1"')
"""A URDF whose limits are reversed: an error finding (``findings``)."""
MJCF = (
    '<mujoco model="arm"><worldbody><body name="b"><joint name="j" type="hinge"/>'
    '<geom size="0.1"/></body></worldbody></mujoco>'
)
BROKEN_MJCF = MJCF.replace('type="hinge"', 'type="hinge" range="2 1" limited="true"')
"""An MJCF model MuJoCo refuses (``range[0] should be smaller``): no report."""
XACRO = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
INERTIAL = (
    '<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/>'
    "</inertial>"
)
INERTIAL_URDF = ARM.replace('<link name="b"/><link name="c"/>', "").replace(
    "<joint", f'<link name="b">{INERTIAL}</link><link name="c">{INERTIAL}</link><joint'
)
"""A URDF MuJoCo compiles (its links have mass)."""


def _cpu(*args: str, cwd: Path) -> tuple[Run, float]:
    """A run of `cspace ARGS...` forked, and its CPU seconds (`conftest.measured`): what
    the files make cspace do, the interpreter's start-up (the same for every run) left out."""
    result = measured(*args, cwd=cwd, forked=True)
    return result.run, result.cpu_seconds


def _mujoco_reads(data: bytes) -> bool:
    """Whether MuJoCo compiles a file of these bytes (as ``MjModel.from_xml_path``)."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "model.xml"
        path.write_bytes(data)
        return mujoco_compiles(path)


def _urdfdom_reads(text: str) -> bool:
    """Whether Pinocchio's URDF parser (urdfdom, on tinyxml2) builds a model of ``text``."""
    try:
        pinocchio.buildModelFromXML(text)
    except (RuntimeError, ValueError):
        return False
    return True


def test_a_robot_after_what_tinyxml2_reads_before_a_root_is_inspected(tmp_path: Path) -> None:
    """tinyxml2 (MuJoCo's parser, urdfdom's, sdformat's) reads text before the root, a
    ``<`` and white space before its name, CDATA, and (urdfdom, sdformat) elements before
    a top-level ``<robot>``, a ``<Robot>`` (MuJoCo reads its root's name in any case):
    each such file is a robot to them, and inspected (lxml then
    refuses it); so is one whose junk goes on past the first 64 KiB. A file tinyxml2
    refuses (its text runs to its end, as in a README or a Python file holding a model;
    a NUL byte before the root) is no robot, and stays out."""
    robots = {
        "text.xml": b"A model of the arm.\n" + BROKEN_MJCF.encode(),
        "spaced.xml": b"< " + BROKEN_MJCF.encode()[1:],
        "cdata.xml": b"<![CDATA[<x>]]>" + BROKEN_MJCF.encode(),
        "long.xml": b"junk " * 20_000 + BROKEN_MJCF.encode(),
        "before.xml": b"<notes/>\n" + BROKEN_URDF.encode(),
        "upper.xml": INERTIAL_URDF.replace("robot", "Robot").encode(),  # MuJoCo: any case
    }
    for name, data in robots.items():
        (tmp_path / name).write_bytes(data)
        good = data.replace(b' range="2 1" limited="true"', b"").replace(
            b'lower="2"', b'lower="-1"'
        )
        assert _mujoco_reads(good) or _urdfdom_reads(good.decode()), name  # a robot to them
    others = {
        "README.md": f"# Arm\n\n```xml\n{MJCF}\n```\n\nIts one joint.\n".encode(),
        "model.py": f'MODEL = """{ARM}"""\nprint(MODEL)\n'.encode(),
        "nul.xml": b"x\0" + MJCF.encode(),
    }
    for name, data in others.items():
        (tmp_path / name).write_bytes(data)
        assert not _mujoco_reads(data) and not _urdfdom_reads(data.decode()), name
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == dict.fromkeys(robots, "no report"), run.stdout + run.stderr
        assert "text.xml:1:1: not XML (Start tag expected, '<' not found) [xml-syntax]\n" in (
            run.stderr
        )


def test_a_document_types_internal_subset_hides_no_root(tmp_path: Path) -> None:
    """``]`` or ``>`` in a quoted literal, a comment or a processing instruction of the
    internal subset does not end it: the root after it is found (lxml reads it; the
    readers then refuse the document type's entity, or MuJoCo the model)."""
    fake = "]><notes/>"  # where the subset would end if ] ended it: <notes/> the root
    files = {
        "literal.xml": f'<!DOCTYPE mujoco [<!ENTITY e "{fake}">]>{BROKEN_MJCF}',
        "comment.xml": f"<!DOCTYPE mujoco [<!-- {fake} -->]>{BROKEN_MJCF}",
        "pi.xml": f"<!DOCTYPE mujoco [<?pi {fake} ?>]>{BROKEN_MJCF}",
        "system.xml": f'<!DOCTYPE mujoco SYSTEM "a[b>">{BROKEN_MJCF}',
        "gt.xml": f"<!DOCTYPE mujoco [<!ENTITY e '>'>]>{BROKEN_MJCF}",
    }
    parser = etree.XMLParser(resolve_entities=False, load_dtd=False, no_network=True)
    for name, text in files.items():
        (tmp_path / name).write_text(text)
        assert etree.fromstring(text.encode(), parser).tag == "mujoco", name
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == dict.fromkeys(files, "no report"), run.stdout + run.stderr


def test_utf16_and_byte_order_marks_are_read_as_xml_reads_them(tmp_path: Path) -> None:
    """A byte order mark tells the encoding, as in XML: a UTF-16 (either order) or
    UTF-32 robot is found; the MJCF reader refuses UTF-16, as MuJoCo does, with one line,
    and the URDF reader reads the characters."""
    files = {
        "le.xml": ("utf-16-le", BROKEN_MJCF, "no report"),
        "be.xml": ("utf-16-be", BROKEN_URDF, "findings"),
        "wide.xml": ("utf-32-le", BROKEN_URDF, "findings"),
        "mark.xml": ("utf-8", BROKEN_MJCF, "no report"),
    }
    for name, (encoding, text, _) in files.items():
        (tmp_path / name).write_bytes(("\ufeff" + text).encode(encoding))
    assert not _mujoco_reads(("\ufeff" + MJCF).encode("utf-16-le"))
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == {n: s for n, (_, _, s) in files.items()}, run.stderr
        assert (
            "cspace: error: le.xml:1: the file is UTF-16 or UTF-32, not UTF-8: MuJoCo reads "
            "every MJCF file as UTF-8"
        ) in run.stderr


def test_elements_named_in_non_ascii_letters_count_where_they_open(tmp_path: Path) -> None:
    """XML's names take any letter: ``<名前>`` opens an element, so a ``<xacro:include>``
    in it is no child of the root (what it splices in lands where the URDF reader reads
    nothing), and ``<xacro:includé>`` is no include. The files they name are robots."""
    (tmp_path / "a.xacro").write_text(
        f'<robot name="a" {XACRO}><名前><xacro:include filename="b.xacro"/></名前>'
        '<link name="l"/></robot>',
        encoding="utf-8",
    )
    (tmp_path / "c.xacro").write_text(
        f'<robot name="c" {XACRO}><xacro:includé filename="d.xacro"/><link name="l"/></robot>',
        encoding="utf-8",
    )
    broken = BROKEN_URDF.replace("<robot ", f"<robot {XACRO} ")
    for name in ("b.xacro", "d.xacro"):
        (tmp_path / name).write_text(broken)
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        rows = _rows(run.stdout)
        assert set(rows) == {"a.xacro", "b.xacro", "c.xacro", "d.xacro"}, run.stderr
        assert rows["b.xacro"] == rows["d.xacro"] == "findings", run.stdout + run.stderr


def test_an_include_through_a_link_names_the_file_the_reader_opens(tmp_path: Path) -> None:
    """``lnk/../arm.xml`` is beside where ``lnk`` leads, as the system and the readers
    resolve it, not beside ``lnk``: the file the include opens is left to its model, and
    the broken robot beside the link is inspected (MJCF and xacro)."""
    root = tmp_path / "repo"
    for folder in ("models", "parts/sub", "pkg/urdf/deep/er"):
        (root / folder).mkdir(parents=True)
    (root / "models" / "lnk").symlink_to("../parts/sub")
    (root / "models" / "scene.xml").write_text(
        '<mujoco model="s"><include file="lnk/../arm.xml"/></mujoco>'
    )
    (root / "parts" / "arm.xml").write_text(MJCF)  # what the include opens
    (root / "models" / "arm.xml").write_text(BROKEN_MJCF)
    urdf = root / "pkg" / "urdf"
    (urdf / "lnk").symlink_to("deep/er")
    (urdf / "robot.xacro").write_text(
        f'<robot name="r" {XACRO}><xacro:include filename="lnk/../arm.xacro"/></robot>'
    )
    body = ARM[ARM.index("<link") : ARM.index("</robot>")]
    (urdf / "deep" / "arm.xacro").write_text(f'<robot name="x" {XACRO}>{body}</robot>')
    (urdf / "arm.xacro").write_text(BROKEN_URDF.replace("<robot ", f"<robot {XACRO} "))
    subprocess.run(["git", "init", "-q"], cwd=root, check=True)  # the readers' project
    for run in _both(root):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == {
            "models/arm.xml": "no report",
            "models/scene.xml": "ok",
            "pkg/urdf/arm.xacro": "findings",
            "pkg/urdf/robot.xacro": "ok",
        }, run.stdout + run.stderr
        assert "parts/arm.xml" in run.stderr and "pkg/urdf/deep/arm.xacro" in run.stderr  # left


def _pinocchio_mjcf_reads(data: bytes) -> bool:
    """Whether Pinocchio's MJCF parser (rapidxml) builds a model of a file of these bytes."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "model.xml"
        path.write_bytes(data)
        try:
            pinocchio.buildModelFromMJCF(str(path))
        except (RuntimeError, ValueError):
            return False
        return True


def _good(data: bytes) -> bytes:
    return data.replace(b' range="2 1" limited="true"', b"").replace(b'lower="2"', b'lower="-1"')


def test_a_top_level_root_after_any_first_element_is_inspected(tmp_path: Path) -> None:
    """urdfdom takes a top-level ``<robot>`` wherever it stands, and Pinocchio's MJCF
    parser (rapidxml) a top-level ``<mujoco>``: after a first element that ends past the
    first 64 KiB, among other elements, or after one tinyxml2 refuses and rapidxml reads
    (an attribute given twice), the file is inspected (its reader refuses it: not XML).
    A ``<robot>`` or ``<mujoco>`` within an element, or in a file its parser refuses
    (text that runs to its end; a space after rapidxml's ``<``), stays out."""
    pad = "\n" * 70_000
    robots = {
        "after.xml": f"<a/>{pad}{BROKEN_URDF}",  # 70,000 newlines, then the robot
        "long.xml": f"<notes>{'x' * 70_000}</notes>{BROKEN_URDF}",
        "among.xml": f"<a/><b/>{BROKEN_MJCF}<c/>",
        "twice.xml": f"<a x='1' x='2'>{pad}</a>{BROKEN_MJCF}",
    }
    others = {
        "nested.xml": f"<notes>{pad}{ARM}{MJCF}</notes>",
        "model.py": f'MODEL = """<a/>{pad}{ARM}{MJCF}"""\n',
        "spaced.xml": f"<a/>{pad}< {MJCF[1:]}",
    }
    for name, text in {**robots, **others}.items():
        (tmp_path / name).write_text(text)
        good = _good(text.encode())
        reads = _urdfdom_reads(good.decode()) or _pinocchio_mjcf_reads(good)
        assert reads == (name in robots) and not _mujoco_reads(good), name
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == dict.fromkeys(robots, "no report"), run.stdout + run.stderr


def test_a_xacro_file_whose_entities_make_its_content_is_inspected(tmp_path: Path) -> None:
    """A nameless ``<robot>`` whose links come from an entity of its document type is a
    robot to xacro (which expands it), not a library: it is inspected, and refused
    (xml-unsafe). An ``&`` in a library's comment, or ``&amp;`` in a value, changes
    nothing: the library is left out."""
    body = BROKEN_URDF[BROKEN_URDF.index("<link") : BROKEN_URDF.index("</robot>")]
    entity = (
        f'<!DOCTYPE robot [<!ENTITY body \'<xacro:attribute name="name" value="r"/>{body}\'>]>'
        f"<robot {XACRO}>&body;</robot>"
    )
    (tmp_path / "entity.xacro").write_text(entity)
    (tmp_path / "lib.xacro").write_text(
        f'<robot {XACRO}><!-- arms & legs --><xacro:macro name="m" params="">'
        '<link name="a&amp;b"/></xacro:macro></robot>'
    )
    (tmp_path / "arm.urdf").write_text(ARM)
    document = xacro.process_file(str(tmp_path / "entity.xacro")).documentElement
    assert document.getAttribute("name") == "r" and document.getElementsByTagName("link")
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        rows = {"arm.urdf": "ok", "entity.xacro": "no report"}
        assert _rows(run.stdout) == rows, run.stdout + run.stderr
        assert "[xml-unsafe]" in run.stderr and "lib.xacro" in run.stderr  # left out


def test_an_include_past_a_models_end_names_no_fragment(tmp_path: Path) -> None:
    """MuJoCo reads nothing after the root element's end (tinyxml2 stops there): an
    ``<include>`` past it makes no fragment, and the broken model it names is inspected."""
    (tmp_path / "scene.xml").write_text(f'{MJCF}\n<include file="arm.xml"/>\n')
    (tmp_path / "arm.xml").write_text(BROKEN_MJCF)
    assert _mujoco_reads((tmp_path / "scene.xml").read_bytes())  # arm.xml is never read
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == {"arm.xml": "no report", "scene.xml": "no report"}, (
            run.stdout + run.stderr
        )
        assert "range[0] should be smaller" in run.stderr  # arm.xml's own error


def _hand(joint: str) -> str:
    return (
        f'<mujocoinclude><body name="l1"><joint name="{joint}" type="hinge" range="-1 1"/>'
        '<geom size="0.1"/></body></mujocoinclude>'
    )


def _part(include: str, before: str = "") -> str:
    """A model whose joint ``j0`` meets the ``j0`` of the ``parts/`` file it includes."""
    return (
        '<mujoco model="t"><worldbody><body name="base"><joint name="j0" type="slide"/>'
        f'<geom size="0.1"/>{before}{include}</body></worldbody></mujoco>'
    )


def test_an_include_in_another_folder_counts_only_of_a_file_naming_no_other(
    tmp_path: Path,
) -> None:
    """MuJoCo reads every file a model names from the model's folder: ``parts/t.xml``,
    included by ``scene.xml``, reads the ``arm.xml`` beside the scene, and alone the one
    beside itself. So the include leaves ``t.xml`` to the scene only when it names no
    file: not when it attaches a model (``<model file>``), includes a file whose name
    holds an entity, includes one past a 70 KB comment, or writes ``< include`` (an
    element to tinyxml2, not XML to lxml). Each such ``t.xml`` alone reads its own
    folder's file, MuJoCo refuses it (a joint's name repeated), and it is inspected.
    dm_control's ``common/skybox.xml`` and a file of textures (texture and mesh files
    make no joint) are left to the model that includes them from another folder."""
    attach = (
        '<mujoco model="t"><asset><model name="arm" file="arm.xml"/></asset><worldbody>'
        '<body name="base"><joint name="a_j" type="slide"/><geom size="0.1"/>'
        '<attach model="arm" body="link1" prefix="a_"/></body></worldbody></mujoco>'
    )
    comment = f"<!--{'x' * 70_000}-->"
    cases = {
        "attach": (attach, "arm.xml"),
        "entity": (_part('<include file="arm&amp;hand.xml"/>'), "arm&hand.xml"),
        "far": (_part('<include file="hand.xml"/>', comment), "hand.xml"),
        "spaced": (_part('< include file="hand.xml"/>'), "hand.xml"),
    }
    for case, (part, name) in cases.items():
        (tmp_path / case / "parts").mkdir(parents=True)
        (tmp_path / case / "scene.xml").write_text(
            '<mujoco model="scene"><include file="parts/t.xml"/></mujoco>'
        )
        (tmp_path / case / "parts" / "t.xml").write_text(part)
        if case == "attach":  # a_ + j: a_j again, in parts/ only
            for folder, joint in ((tmp_path / case, "k"), (tmp_path / case / "parts", "j")):
                (folder / name).write_text(
                    MJCF.replace('name="b"', 'name="link1"').replace('name="j"', f'name="{joint}"')
                )
        else:
            (tmp_path / case / name).write_text(_hand("j1"))
            (tmp_path / case / "parts" / name).write_text(_hand("j0"))
        if case != "attach":  # MuJoCo finds its <model file> by the path the scene is opened by
            assert mujoco.MjModel.from_xml_path(str(tmp_path / case / "scene.xml")).njnt == 2
        with pytest.raises(ValueError, match="repeated name"):
            mujoco.MjModel.from_xml_path(str(tmp_path / case / "parts" / "t.xml"))
    common = tmp_path / "suite" / "common"
    common.mkdir(parents=True)
    (common / "skybox.xml").write_text(
        '<mujoco><asset><texture name="skybox" type="skybox" builtin="gradient" '
        'rgb1=".4 .6 .8" rgb2="0 0 0" width="800" height="800"/></asset></mujoco>'
    )
    (common / "materials.xml").write_text(
        '<mujoco><compiler texturedir="textures"/><asset><texture name="grid" type="2d" '
        'file="grid.png"/><material name="grid" texture="grid"/></asset></mujoco>'
    )
    (tmp_path / "suite" / "cartpole.xml").write_text(
        MJCF.replace(
            "<worldbody>",
            '<include file="./common/skybox.xml"/><include file="./common/materials.xml"/>'
            "<worldbody>",
        ).replace("<geom ", '<geom material="grid" ')
    )
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == {
            "attach/arm.xml": "ok",
            "attach/parts/arm.xml": "ok",
            "attach/parts/t.xml": "no report",
            "attach/scene.xml": "ok",
            "entity/parts/t.xml": "no report",
            "entity/scene.xml": "ok",
            "far/parts/t.xml": "no report",
            "far/scene.xml": "ok",
            "spaced/parts/t.xml": "no report",
            "spaced/scene.xml": "no report",  # lxml: not XML
            "suite/cartpole.xml": "ok",  # suite/common/*.xml left to it: no rows
        }, run.stdout + run.stderr
        assert run.stderr.count("repeated name") == 3, run.stderr  # attach, entity, far


@pytest.mark.bounded
def test_a_million_comments_or_includes_cost_a_bounded_search(tmp_path: Path) -> None:
    """Comments and processing instructions count among the constructs a file's search
    looks at (250,000): a xacro library of 9.5 million comments (64 MiB), a prolog of as
    many, junk then as many are looked at in a bounded time, and taken for robots (their
    reader refuses them); of 300 includes, 256 are followed: the 300th names a robot.
    Each run costs at most 6 times the CPU of one over files as large, each a robot by
    its first tag (measured: about 2; 10 to 14 where the comments of a prolog, of a
    library's content or of what tinyxml2 reads are not counted). The files are written
    in memory where there is room (``conftest.environment_folder``): 400 MB."""
    with environment_folder(tmp_path) as root:
        _bounded_comments(root / "hostile", root / "small")


def _bounded_comments(hostile: Path, small: Path) -> None:
    hostile.mkdir()
    small.mkdir()
    comments = b"<!---->" * 9_500_000
    robot = f"<robot {XACRO}>".encode()
    (hostile / "lib.xacro").write_bytes(robot + comments + b"</robot>")
    (hostile / "prolog.xml").write_bytes(comments + MJCF.encode())
    (hostile / "junk.xml").write_bytes(b"junk" + comments + MJCF.encode())
    includes = "".join(f'<include file="part{k}.xml"/>' for k in range(299))
    (hostile / "many.xml").write_text(
        f'<mujoco model="m">{includes}<include file="broken.xml"/></mujoco>'
    )
    # as large, and read as far by their readers, but each a robot by its first tag
    (small / "lib.xacro").write_bytes(robot.replace(b"<robot ", b'<robot name="r" ') + comments)
    for name in ("prolog.xml", "junk.xml"):
        (small / name).write_bytes(b"<mujoco>" + comments + b"</mujoco>")
    (small / "many.xml").write_text(BROKEN_MJCF)
    for folder in (hostile, small):
        (folder / "broken.xml").write_text(BROKEN_MJCF)
    options = ("inspect", "--robots-only", "--width", "400")
    _, reference = _cpu(*options, ".", cwd=small)
    for args in ((".",), ("--", *sorted(os.listdir(hostile)))):
        run, cpu = _cpu(*options, *args, cwd=hostile)
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == {
            "broken.xml": "no report",
            "junk.xml": "no report",
            "lib.xacro": "no report",
            "many.xml": "no report",
            "prolog.xml": "no report",
        }, run.stdout + run.stderr
        assert cpu < 6 * reference, (cpu, reference)


@pytest.mark.bounded
def test_a_long_document_type_or_start_tag_costs_a_bounded_search(tmp_path: Path) -> None:
    """The quoted literals of a document type and the attributes of a start tag count
    among the constructs a file's search looks at (250,000): a document type of 2 million
    literals (8 MiB) before a ``<mujoco>``, a first start tag of 800,000 attributes, a
    nameless xacro ``<robot>`` start tag of 1.6 million, each read in a bounded time; the
    first and the last are inspected (their readers refuse them), the second holds no
    robot. Each run costs at most 2.5 times the CPU of one over files as large, each a
    robot by its first tag (measured: about 1.2; 4.6 with no bound on the constructs).
    The files are written in memory where there is room (``conftest.environment_folder``)."""
    with environment_folder(tmp_path) as root:
        _bounded_tags(root / "hostile", root / "small")


def _bounded_tags(hostile: Path, small: Path) -> None:
    hostile.mkdir()
    small.mkdir()
    (hostile / "doctype.xml").write_bytes(
        b"<!DOCTYPE mujoco " + b'"a" ' * 2_000_000 + b">" + MJCF.encode()
    )
    (hostile / "attrs.xml").write_bytes(
        b"<a" + b"".join(b' a%x=""' % k for k in range(800_000)) + b"/>"
    )
    (hostile / "root.xacro").write_bytes(f"<robot {XACRO}".encode() + b' b=""' * 1_600_000 + b"/>")
    for name in ("doctype.xml", "attrs.xml", "root.xacro"):  # robots by their first tag
        size = (hostile / name).stat().st_size
        first = f'<robot name="r" {XACRO}>' if name.endswith(".xacro") else "<mujoco>"
        last = "</robot>" if name.endswith(".xacro") else "</mujoco>"
        (small / name).write_bytes(f"{first}<!--".encode() + b"x" * size + f"-->{last}".encode())
    options = ("inspect", "--robots-only", "--width", "400")
    _, reference = _cpu(*options, ".", cwd=small)
    for args in ((".",), ("--", *sorted(os.listdir(hostile)))):
        run, cpu = _cpu(*options, *args, cwd=hostile)
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == {"doctype.xml": "no report", "root.xacro": "no report"}, (
            run.stdout + run.stderr
        )
        assert cpu < 2.5 * reference, (cpu, reference)
