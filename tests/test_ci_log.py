"""No committed file can write a workflow command into a CI log, in any output.

GitHub's runner acts on a line that starts, after white space, with ``::``
(``::error::``, ``::add-mask::``, ``::stop-commands::TOKEN``, after which it ignores
every later annotation) and on the older ``##[command]`` anywhere in a line. A pull
request can name a robot, a link, a joint, a keyframe, an SRDF group or state, and the
file itself with such text. Every command and every format is run here on such files,
stdout and stderr alike, and every line is held to one rule: no ``::`` at a line's start
and no ``##[`` anywhere, except the annotations ``--format github`` means to write, each
of which must be one well-formed command of cspace's. The names still show, escaped
(``\\x3a:error::``, ``##\\x5b``), and JSON keeps them exact.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path
from urllib.parse import unquote_to_bytes

import pytest
from test_ci_formats import COMMAND

from conftest import REPO, cspace_command, run_cli

FORGED_JOINT = "::warning file=.github/workflows/x.yml,line=1::forged"
STOP = "##[stop-commands]TOKEN"
ROBOT = "::error::robot"
MASK = "##[add-mask]secret"
KEY = "::error::key"
HINGE = "##[group]hinge"

URDF = f"""<robot name="{ROBOT}">
  <link name="base"/>
  <link name="{MASK}"/>
  <link name="::notice::tip"/>
  <joint name="{FORGED_JOINT}" type="revolute">
    <parent link="base"/><child link="{MASK}"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="UPPER" effort="1" velocity="1"/>
  </joint>
  <joint name="{STOP}" type="revolute">
    <parent link="{MASK}"/><child link="::notice::tip"/>
    <axis xyz="0 0 1"/><limit lower="1" upper="LOCK" effort="1" velocity="1"/>
  </joint>
</robot>
"""

SRDF = f"""<robot name="{ROBOT}">
  <group name="##[group]G"><joint name="{FORGED_JOINT}"/></group>
  <group name="::error::ghost"><joint name="::error::nojoint"/></group>
  <group_state name="::error::state" group="##[group]G">
    <joint name="{FORGED_JOINT}" value="0.5"/>
  </group_state>
  <group_state name="##[endgroup]far" group="##[group]G">
    <joint name="{FORGED_JOINT}" value="5"/>
  </group_state>
</robot>
"""

MJCF = f"""<mujoco model="::error::model">
  <worldbody>
    <body name="::notice::body">
      <joint name="{HINGE}" type="hinge" range="-1 1" limited="true"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <keyframe><key name="{KEY}" qpos="3"/></keyframe>
</mujoco>
"""

BROKEN = """<robot name="b"><link name="a"/>
<joint name="::error::j" type="fixed"><parent link="a"/><child link="::error::missing"/></joint>
</robot>
"""

FRAGMENT = "<mujocoinclude><body name='::error::frag'/></mujocoinclude>\n"

FILE = "::error::file.urdf"
"""A file name that is a workflow command (a file name may hold ``:`` and ``[``)."""


@pytest.fixture(scope="module")
def repo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A pull request's files (its robots in ``robots/``): every name a workflow command."""
    root = tmp_path_factory.mktemp("pr")
    (root / "robots").mkdir()
    (root / "robots" / "hostile.urdf").write_text(URDF.replace("UPPER", "1").replace("LOCK", "1"))
    (root / "hostile.srdf").write_text(SRDF)
    (root / "robots" / FILE).write_text(URDF.replace("UPPER", "0.5").replace("LOCK", "1"))
    (root / "robots" / "moved.urdf").write_text(URDF.replace("UPPER", "1").replace("LOCK", "2"))
    (root / "robots" / "##[group]keys.xml").write_text(MJCF)
    (root / "robots" / "::error::broken.urdf").write_text(BROKEN)
    (root / "robots" / "::notice::fragment.xml").write_text(FRAGMENT)
    return root


def assert_no_command(text: str, *, ours: bool = False) -> list[str]:
    """Every line of ``text``: no workflow command, or (``ours``) one of cspace's own.

    Lines are split as the runner splits them (CR, LF); white space before ``::`` is
    what .NET's ``TrimStart`` drops, which Python's ``str.lstrip`` covers.
    """
    lines = re.split(r"\r\n|\r|\n", text)
    for line in lines:
        if line.lstrip().startswith("::"):
            assert ours and COMMAND.fullmatch(line), line
            continue
        assert "##[" not in line, line
    return lines


def run(folder: Path, *args: str) -> tuple[int, str, str]:
    """``cspace ARGS`` in ``folder/robots`` (a ``robots`` folder) or ``folder``."""
    done = run_cli(*args, cwd=folder / "robots" if (folder / "robots").is_dir() else folder)
    assert "Traceback" not in done.stderr
    assert_no_command(done.stdout)
    assert_no_command(done.stderr)
    return done.code, done.stdout, done.stderr


@pytest.mark.parametrize("fmt", ["text", "markdown", "json", "jsonl", "sarif", "html", "svg"])
def test_one_robot_in_every_format(repo: Path, fmt: str) -> None:
    code, out, _ = run(
        repo, "inspect", "--srdf", "../hostile.srdf", "--format", fmt, "hostile.urdf"
    )
    assert code == 1  # the SRDF state out of limits
    if fmt in ("json", "jsonl"):
        document = json.loads(out)
        assert document["robot"] == ROBOT  # the exact names, in JSON
        assert [j["name"] for j in document["joints"]] == [FORGED_JOINT, STOP]
        assert "##\\u005b" in out
    elif fmt == "sarif":
        messages = [r["message"]["text"] for r in json.loads(out)["runs"][0]["results"]]
        assert any("##\\x5bstop-commands]TOKEN" in m for m in messages)
    elif fmt in ("text", "markdown"):
        assert "\\x3a:error::robot" in out  # the name, still readable
        assert "##\\x5bstop-commands]TOKEN" in out
    if fmt == "text":
        assert "##\\x5bgroup]G/::error::state" in out  # the poses line


def test_a_robot_file_named_as_a_command_in_every_format(repo: Path) -> None:
    for fmt in ("text", "markdown", "jsonl", "html"):
        code, out, err = run(repo, "inspect", "--format", fmt, FILE)
        assert code == 0 and err == ""
    code, out, _ = run(repo, "inspect", "--format", "jsonl", FILE)
    assert json.loads(out)["source"]["path"] == FILE


def test_a_folder_of_them_in_every_format(repo: Path) -> None:
    """Summary rows, the errors and notes on stderr, a file without a report."""
    for fmt in ("text", "markdown", "jsonl", "sarif"):
        code, out, err = run(repo, "inspect", "--format", fmt, ".")
        assert code == 2  # the broken file
        assert "\\x3a:error::broken.urdf" in err  # its error, the file named
        assert "'::error::missing'" in err
        assert "./::notice::fragment.xml" in err  # the fragment's note
    code, out, _ = run(repo, "inspect", "--format", "text", ".")
    assert "\\x3a:error::file.urdf" in out and "##\\x5bgroup]keys.xml" in out


def test_github_annotations_are_cspaces_commands_only(repo: Path) -> None:
    """Each line is one of cspace's commands, on the file named by its real name."""
    done = run_cli("inspect", "--format", "github", ".", cwd=repo / "robots")
    lines = [line for line in assert_no_command(done.stdout, ours=True) if line]
    assert done.code == 2 and lines
    kinds = {COMMAND.fullmatch(line).group(1) for line in lines}  # type: ignore[union-attr]
    assert kinds == {"error", "warning", "notice"}  # broken; joint-locked; C-spaces
    files = {COMMAND.fullmatch(line).group(2) for line in lines}  # type: ignore[union-attr]
    assert "%3A%3Aerror%3A%3Afile.urdf" in files  # the file's own name, its ':' encoded
    assert "##[group]keys.xml" in files  # within cspace's own command, as it is named
    assert all("::error::robot" not in line.split("::", 2)[1] for line in lines)
    assert_no_command(done.stderr)


def test_mjcf_keyframes_and_their_findings(repo: Path) -> None:
    code, out, _ = run(repo, "inspect", "--", "##[group]keys.xml")
    assert code == 1  # the keyframe leaves the hinge's range
    assert "poses   \\x3a:error::key" in out
    assert "##\\x5bgroup]hinge" in out
    run(repo, "inspect", "--format", "markdown", "--", "##[group]keys.xml")


def test_groups(repo: Path) -> None:
    code, out, _ = run(
        repo, "inspect", "--srdf", "../hostile.srdf", "--group", "##[group]G", "hostile.urdf"
    )
    assert code == 1 and "group   ##\\x5bgroup]G: 1 joints move" in out


@pytest.mark.parametrize("fmt", ["text", "markdown", "json", "html"])
def test_diff(repo: Path, fmt: str) -> None:
    code, out, _ = run(repo, "diff", "--format", fmt, "hostile.urdf", "moved.urdf")
    assert code == 1  # the locked joint moves: a C-space change, named
    assert "##\\u005bstop" in out if fmt == "json" else "##\\x5bstop" in out


def test_check(repo: Path) -> None:
    code, out, err = run(repo, "check", "hostile.urdf", "--expect", "R^3")
    assert code == 1 and "check failed" in err
    code, out, err = run(repo, "check", FILE, "--expect", "R^1")
    assert code == 0 and out.startswith("ok: \\x3a:error::file.urdf: R^1")


def test_check_against_a_baseline(repo: Path, tmp_path: Path) -> None:
    work = tmp_path / "work"
    shutil.copytree(repo, work)
    work = work / "robots"
    (work / "::error::broken.urdf").unlink()
    code, baseline, _ = run(work, "inspect", "--format", "jsonl", "hostile.urdf", FILE)
    (work / "baseline.jsonl").write_text(baseline)
    (work / FILE).write_text(URDF.replace("UPPER", "0.25").replace("LOCK", "1"))
    for fmt in ("text", "markdown"):
        code, out, _ = run(work, "check", "--baseline", "baseline.jsonl", "--format", fmt, ".")
        assert code == 1 and "differs" in out
    done = run_cli("check", "--baseline", "baseline.jsonl", "--format", "github", ".", cwd=work)
    assert done.code == 1
    assert_no_command(done.stdout, ours=True)
    assert_no_command(done.stderr)


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_configuration_commands_name_the_joints_safely(repo: Path, fmt: str) -> None:
    """The coordinate names of a header, a JSON document and JSON Lines."""
    code, out, _ = run(repo, "sample", "-n", "2", "--format", fmt, "--", "##[group]keys.xml")
    assert code == 0 and out


def test_the_one_line_error(repo: Path) -> None:
    code, _, err = run(repo, "inspect", "::error::broken.urdf")
    assert code == 2 and err.startswith("cspace: error: \\x3a:error::broken.urdf")
    code, _, err = run(repo, "inspect", "##[add-mask]missing.urdf")
    assert code == 2 and "##\\x5badd-mask]missing.urdf" in err


def test_the_library_renderers_neutralise_too(repo: Path) -> None:
    """What a script prints from the library (a report's JSON, Markdown) is as safe."""
    import cspace
    from cspace.markdown import render_markdown

    report = cspace.inspect(repo / "robots" / "hostile.urdf", srdf=repo / "hostile.srdf")
    assert_no_command(report.to_json())
    assert_no_command(render_markdown(report))
    assert json.loads(report.to_json())["robot"] == ROBOT


def test_bundled_robot_outputs_are_unchanged_by_the_rule() -> None:
    """cspace's own text holds no ``::`` at a line's start or ``##[``: nothing to escape."""
    done = run_cli("inspect", "--format", "github", str(REPO / "robots" / "arm7.urdf"))
    assert done.code == 0 and done.stdout.startswith("::notice file=")


LOCKED = (
    '<robot name="l"><link name="a"/><link name="b"/><joint name="j" type="revolute">'
    '<parent link="a"/><child link="b"/><limit lower="0.5" upper="0.5" effort="1" '
    'velocity="1"/></joint></robot>'
)


@pytest.fixture(scope="module")
def latin1(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Files whose names are not UTF-8: one with a finding, one broken, one good."""
    root = tmp_path_factory.mktemp("latin1")
    shutil.copy(REPO / "robots" / "arm7.urdf", root / "good.urdf")
    with open(os.path.join(os.fsencode(root), b"bad\xff.urdf"), "w") as out:
        out.write(LOCKED)
    with open(os.path.join(os.fsencode(root), b"broken\xfe.urdf"), "w") as out:
        out.write("<robot")
    return root


@pytest.mark.parametrize("fmt", ["text", "markdown", "json", "jsonl", "sarif", "github", "html"])
def test_names_that_are_not_utf8_in_every_format(latin1: Path, fmt: str, tmp_path: Path) -> None:
    """Each format keeps every file: the bad names as their bytes escaped, none aborts."""
    pages = ["--output-dir", str(tmp_path / "pages")] if fmt == "html" else []
    done = subprocess.run(
        [*cspace_command(), "inspect", "--format", fmt, *pages, "."],
        cwd=latin1,
        capture_output=True,
        timeout=120,
        check=False,
    )
    out, err = done.stdout.decode("utf-8"), done.stderr.decode("utf-8")  # strict UTF-8
    assert done.returncode == 2 and "Traceback" not in err and "internal" not in err
    assert "broken\\xfe.urdf:1:7: " in err  # the broken one's error, its bytes shown
    assert_no_command(out, ours=fmt == "github")
    if fmt == "sarif":
        log = json.loads(out)
        uris = [
            r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
            for r in log["runs"][0]["results"]
        ]
        assert uris.count("bad%FF.urdf") == 2 and "broken%FE.urdf" in uris  # axis; locked
        assert [unquote_to_bytes(u) for u in uris if u.startswith("bad")] == [b"bad\xff.urdf"] * 2
    elif fmt in ("json", "jsonl"):
        paths = [json.loads(line)["source"]["path"] for line in out.splitlines()]
        assert [os.fsencode(p) for p in paths] == [b"bad\xff.urdf", b"good.urdf"]
    elif fmt == "html":
        assert sorted(os.listdir(tmp_path / "pages")) == [
            "1-bad_.urdf.html",
            "3-good.urdf.html",
            "index.html",
        ]
        assert "bad\\xff.urdf" in (tmp_path / "pages" / "index.html").read_text()
    else:
        assert "bad\\xff.urdf" in out and "good.urdf" in out and "broken\\xfe.urdf" in out


def test_a_baseline_of_names_that_are_not_utf8(latin1: Path, tmp_path: Path) -> None:
    """A report of such a file reads back: the baseline finds it, by its bytes."""
    work = tmp_path / "work"
    shutil.copytree(latin1, work)
    os.remove(os.path.join(os.fsencode(work), b"broken\xfe.urdf"))
    made = run_cli("inspect", "--format", "jsonl", ".", cwd=work)
    (work / "baseline.jsonl").write_text(made.stdout)
    done = run_cli("check", "--baseline", "baseline.jsonl", ".", cwd=work)
    assert done.code == 0, done.stderr
    assert done.stdout.splitlines() == ["same: bad\\xff.urdf: point", "same: good.urdf: R^6 × S^1"]


# Names that also break a line or turn text round: a newline, a bidi override, C1 (NEL,
# CSI), as XML character references in a file and as raw characters in a path.
EVIL = "::error::x&#10;::error::y&#x202e;&#x85;&#x9b;##[group]z"
EVIL_PATH = "::error::d\n##[group]\u202e\x85\x9bp"
CARRIED = ("\\x3a:error::x", "##\\x5bgroup]")
"""What any of EVIL's escaped text shows, in every format but JSON."""


def assert_printable(text: str) -> None:
    """Every line of ``text`` printable: no control, C1 or bidi character left raw."""
    for line in re.split(r"\r\n|\r|\n", text):
        assert all(c.isprintable() or c == "\t" for c in line), ascii(line)


def run_safely(folder: Path, *args: str, ours: bool = False) -> tuple[int, str, str]:
    """``cspace ARGS`` in ``folder``, its output held to the CI log's rules.

    No traceback, no workflow command on stdout (but cspace's own with ``ours``) or
    stderr, every line printable. Returns the exit code, stdout and stderr.
    """
    done = run_cli(*args, cwd=folder)
    assert "Traceback" not in done.stderr
    assert_no_command(done.stdout, ours=ours)
    assert_no_command(done.stderr)
    assert_printable(done.stdout)
    assert_printable(done.stderr)
    return done.code, done.stdout, done.stderr


def run_evil(folder: Path, *args: str) -> tuple[int, str, str]:
    """`run`, and no unescaped character in stdout or stderr either."""
    code, out, err = run(folder, *args)
    assert_printable(out)
    assert_printable(err)
    return code, out, err


def _arm(root: str, origin: str = "") -> str:
    """A URDF arm named EVIL with EVIL root joint ``root`` above it, placed by ``origin``."""
    return (
        f'<robot name="{EVIL}"><link name="{EVIL}w"/><link name="base"/><link name="arm"/>'
        f'<joint name="{EVIL}r" type="{root}">{origin}<parent link="{EVIL}w"/>'
        '<child link="base"/><axis xyz="1 0 0"/></joint>'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        "</robot>"
    )


PLANAR = f"""<robot name="{EVIL}"><link name="base"/><link name="{EVIL}1"/>
  <link name="{EVIL}2"/><link name="{EVIL}3"/>
  <joint name="{EVIL}x" type="prismatic"><parent link="base"/><child link="{EVIL}1"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="{EVIL}y" type="prismatic"><parent link="{EVIL}1"/><child link="{EVIL}2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="{EVIL}h" type="continuous"><parent link="{EVIL}2"/><child link="{EVIL}3"/>
    <axis xyz="0 0 1"/></joint>
</robot>
"""
WORLD = (
    f'<robot name="{EVIL}"><link name="base"/><joint name="{EVIL}j" type="revolute">'
    '<parent link="world"/><child link="base"/><axis xyz="0 0 1"/>'
    '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
)
TWO_HINGES = f"""<mujoco model="{EVIL}"><worldbody><body name="{EVIL}b" pos="0.5 0 1">
  <joint name="{EVIL}1" type="hinge" axis="0 0 1" range="-30 30" limited="true"/>
  <joint name="{EVIL}2" type="hinge" axis="1 0 0" range="-30 30" limited="true"/>
  <geom size="0.1"/></body></worldbody>
  <keyframe><key name="k" qpos="0.1 0.2"/></keyframe></mujoco>
"""


@pytest.fixture(scope="module")
def evil(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Robots whose findings name EVIL names, some in a folder whose name is EVIL_PATH."""
    root = tmp_path_factory.mktemp("evil")
    (root / "planar.urdf").write_text(PLANAR)
    (root / "world.urdf").write_text(WORLD)
    (root / "hinges.xml").write_text(TWO_HINGES)
    (root / "planar_axis.urdf").write_text(_arm("planar"))
    (root / "old.urdf").write_text(_arm("floating"))
    (root / "new.urdf").write_text(_arm("floating", '<origin xyz="0 0 1"/>'))
    folder = root / EVIL_PATH
    folder.mkdir()
    (folder / f"{EVIL_PATH}.urdf").write_text(_arm("fixed"))
    srdf = f'<robot name="{EVIL}other"><group name="g"><joint name="j1"/></group></robot>'
    (folder / f"{EVIL_PATH}.srdf").write_text(srdf)
    alone = root / f"{EVIL_PATH}alone"
    alone.mkdir()
    (alone / "arm.urdf").write_text(_arm("fixed"))
    return root


INSPECT_FORMATS = ["text", "markdown", "json", "jsonl", "sarif", "github", "html"]


def _inspect_all(folder: Path, *args: str) -> dict[str, str]:
    """``cspace inspect ARGS`` in every format: stdout by format, all of stderr joined."""
    outs = {}
    for fmt in INSPECT_FORMATS:
        done = run_cli("inspect", "--format", fmt, *args, cwd=folder)
        assert "Traceback" not in done.stderr and done.code in (0, 1), done.stderr
        assert_no_command(done.stdout, ours=fmt == "github")
        assert_no_command(done.stderr)
        assert_printable(done.stdout)
        assert_printable(done.stderr)
        outs[fmt] = done.stdout
        outs[f"{fmt} stderr"] = done.stderr
    return outs


def _codes(outs: dict[str, str]) -> set[str]:
    """The finding codes of the JSON report, which keeps every name exactly."""
    return {d["code"] for d in json.loads(outs["json"])["diagnostics"]}


@pytest.mark.parametrize(
    ("args", "code"),
    [
        (("planar.urdf",), "planar-root"),
        (("world.urdf",), "world-undeclared"),
        (("hinges.xml",), "drake-mjcf-differs"),
        (("planar_axis.urdf",), "drake-urdf-differs"),
        (
            ("--srdf", f"{EVIL_PATH}/{EVIL_PATH}.srdf", f"{EVIL_PATH}/{EVIL_PATH}.urdf"),
            "srdf-other-robot",
        ),
        (("--srdf", "auto", f"{EVIL_PATH}alone/arm.urdf"), "srdf-not-found"),
    ],
)
def test_new_findings_name_hostile_names_safely(
    evil: Path, args: tuple[str, ...], code: str
) -> None:
    """Each finding, in every format, its names shown escaped and kept in JSON."""
    outs = _inspect_all(evil, *args)
    assert code in _codes(outs), outs["json"]
    message = next(
        d["message"] for d in json.loads(outs["json"])["diagnostics"] if d["code"] == code
    )
    assert "::error::y" in message or "\\x5bgroup]" in message, message  # names, kept
    for fmt in ("text", "markdown"):
        assert all(s in outs[fmt] for s in CARRIED), outs[fmt]


def test_an_srdf_folder_scan_and_an_srdf_read_as_a_robot(evil: Path) -> None:
    """The folder's SRDF note names the hostile path; the SRDF alone is refused, safely."""
    for fmt in ("text", "jsonl", "github"):
        done = run_cli("inspect", "--format", fmt, ".", cwd=evil / EVIL_PATH)
        assert_no_command(done.stdout, ours=fmt == "github")
        assert_no_command(done.stderr)
        assert_printable(done.stdout)
        assert_printable(done.stderr)
        assert "SRDF" in done.stderr and "##\\x5bgroup]" in done.stderr, done.stderr
    code, _, err = run_evil(evil / EVIL_PATH, "inspect", "--", f"{EVIL_PATH}.srdf")
    assert code == 2 and "[srdf-not-robot]" in err and "##\\x5bgroup]" in err, err


@pytest.mark.parametrize("fmt", ["text", "json", "markdown", "html"])
def test_a_diff_of_a_hostile_root_joint_placed_elsewhere(evil: Path, fmt: str) -> None:
    _, out, _ = run_evil(evil, "diff", "--format", fmt, "old.urdf", "new.urdf")
    assert "placed" in out, out
    if fmt == "json":
        assert "\\n::error::y" in out  # the exact name, JSON-escaped
    else:
        assert all(s in out for s in CARRIED), out


def test_convert_to_drake_warns_with_hostile_names(evil: Path) -> None:
    code, _, err = run_evil(evil, "convert", "--to", "drake", "hinges.xml#k")
    assert (
        code != 2 and "[drake-mjcf-differs]" in err and "\\u202e\\x85\\x9b##\\x5bgroup]" in err
    ), err
