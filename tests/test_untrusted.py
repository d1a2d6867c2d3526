"""Untrusted robot files: nothing runs, nothing leaks, everything is bounded.

Each hostile case is a small set of files written into a tree, run through the installed
`cspace` command as CI runs it, and held to the same promises:

- it ends within the time and memory bounds (``conftest.measured``, forked: what the
  file makes cspace do, the interpreter's start-up left out; the xacro child is counted
  in the peak), with exit 0, 1 or 2, and exit 2 is one line naming the code;
- the marker file that its code would create does not exist afterwards;
- no content of the secret files beside the tree appears in any output;
- no file in the secret folder is opened at all: an inotify watch on that folder sees
  every open by any process, Pinocchio's C++ parsers and xacro's child included.
"""

from __future__ import annotations

import csv
import io
import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

import cspace
from cspace._formats.xacro._sandbox import XacroLimits

from conftest import (
    PEAK_MIB,
    ROBOTS,
    SECONDS,
    OpenWatch,
    Run,
    assert_bounded_error,
    measured,
    run_cli,
)

SECRET = "TOP-SECRET-5d1e"
XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'

ESCAPE = """<xacro:property name="V" value="${python.vars}"/>
<xacro:property name="T" value="${python.type}"/>
<xacro:property name="C" value="${[c for c in V(T)['__subclasses__'](T(1).mro()[1])
  if 'wrap_close' in python.repr(c)][0]}"/>
<xacro:property name="F" value="${V(C)['__init__']}"/>
<xacro:property name="D" value="${V(T(F))['__globals__']}"/>
<xacro:property name="OS" value="${V(T(D))['__get__'](D, F)}"/>
"""
"""A walk from xacro's exposed helpers to the ``os`` module's namespace, using no
attribute name xacro's filter refuses. On plain xacro, ``${OS['system']('...')}`` runs a
shell command (checked by hand when this test was written)."""


def _xacro(body: str, name: str = "r") -> str:
    return f'<robot name="{name}" {XACRO_NS}>{body}<link name="base"/></robot>\n'


def _include_fan_out(levels: int, width: int) -> dict[str, str]:
    files = {}
    for level in range(levels):
        includes = "".join(f'<include file="f{level + 1}.xml"/>' for _ in range(width))
        files[f"f{level}.xml"] = f"<mujoco>{includes}</mujoco>\n"
    files[f"f{levels}.xml"] = (
        '<mujoco><worldbody><body name="b"><joint/></body></worldbody></mujoco>\n'
    )
    files["robot.xml"] = '<mujoco><include file="f0.xml"/></mujoco>\n'
    return files


def _mjcf(body: str, head: str = "") -> str:
    return f'<mujoco model="m">{head}<worldbody>{body}</worldbody></mujoco>\n'


NESTED_ATTRIBUTES = 'damping="1" armature="0.1" stiffness="2" frictionloss="0.5" range="0 1"'
NESTED_DEFAULTS = (
    "<default>"
    + "".join(f'<default class="d{k}"><joint {NESTED_ATTRIBUTES}/>' for k in range(250))
    + "</default>" * 251
)
STAR = "".join(
    f'<link name="l{k}"/><joint name="j{k}" type="floating"><parent link="base"/>'
    f'<child link="l{k}"/></joint>'
    for k in range(4999)
)
LONG = "x" * 3000
FLOOD = "".join(
    f'<link name="l{k}"/><joint name="j{k}" type="revolute"><parent link="base"/>'
    f'<child link="l{k}"/><origin xyz="inf nan inf" rpy="nan inf nan"/>'
    '<limit lower="-1" upper="1" effort="inf" velocity="nan"/>'
    '<dynamics damping="inf" friction="nan"/><calibration rising="inf" falling="nan"/></joint>'
    for k in range(5000)
)
DEEP = (
    "".join(
        f'<body name="d{k}">'
        + (f'<joint name="h{k}"/>' if k % 3 == 0 else "")
        + '<geom size=".1"/>'
        for k in range(250)
    )
    + "</body>" * 250
)
TIES = '<connect body1="d249" body2="d0" anchor="0 0 0"/>'
WELDED = "".join(f'<body name="w{k}"/>' for k in range(6000))
SIBLINGS = "".join(
    f'<body name="b{k}"><joint name="j{k}"/><geom size=".1"/></body>' for k in range(1000)
)
REPLICATED = (
    '<replicate count="100"><replicate count="100"><replicate count="100">'
    '<body><joint/><geom size=".1"/></body></replicate></replicate></replicate>'
)

# name -> (files written into the tree, cspace arguments, exit code, error code or None)
Case = tuple[dict[str, str], tuple[str, ...], int, "str | None"]
CASES: dict[str, Case] = {
    # --- code runs -------------------------------------------------------------------
    "substitution in a .urdf is never expanded": (
        {"evil.urdf": _xacro("", name="${OS['system']('touch {marker}')}")},
        ("inspect", "evil.urdf"),
        2,
        "xacro-not-requested",
    ),
    "escape to os.system": (
        {"e.urdf.xacro": _xacro(ESCAPE + "<link name=\"${OS['system']('touch {marker}')}\"/>")},
        ("inspect", "e.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "escape to os.open for writing": (
        {"e.urdf.xacro": _xacro(ESCAPE + "<link name=\"${OS['open']('{marker}', 65)}\"/>")},
        ("inspect", "e.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "escape to fork": (
        {"e.urdf.xacro": _xacro(ESCAPE + "<link name=\"${OS['fork']()}\"/>")},
        ("inspect", "e.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "load_yaml of a file outside": (
        {"y.urdf.xacro": _xacro("", name="${xacro.load_yaml('{outside}/secret.yaml')}")},
        ("inspect", "y.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "env leaks": (
        {"v.urdf.xacro": _xacro("", name="$(env CSPACE_TEST_SECRET)")},
        ("inspect", "v.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "optenv sees nothing": (
        {"v.urdf.xacro": _xacro("", name="$(optenv CSPACE_TEST_SECRET unset)")},
        ("inspect", "v.urdf.xacro"),
        0,
        None,
    ),
    "include outside the package": (
        {"i.urdf.xacro": _xacro('<xacro:include filename="../outside/secret.xacro"/>')},
        ("inspect", "i.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "include through a link to outside": (
        {"i.urdf.xacro": _xacro('<xacro:include filename="link.xacro"/>'), "@link.xacro": ""},
        ("inspect", "i.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "package's .git/config through load_yaml": (
        {
            "package.xml": "<package><name>evil</name></package>",
            ".git/config": f"[http]\n  extraheader = AUTHORIZATION: basic {SECRET}\n",
            "robots/s.urdf.xacro": _xacro("", name="${xacro.load_yaml('../.git/config')}"),
        },
        ("inspect", "robots/s.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "package's .git/config through open": (
        {
            "package.xml": "<package><name>evil</name></package>",
            ".git/config": f"[http] extraheader = AUTHORIZATION: basic {SECRET}",
            "robots/s.urdf.xacro": _xacro(
                ESCAPE + "<link name=\"${xacro.fatal(OS['open']('../.git/config', 0))}\"/>"
            ),
        },
        ("inspect", "robots/s.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "listing a package's .git": (
        {
            "package.xml": "<package><name>evil</name></package>",
            f".git/refs/heads/{SECRET}": "0" * 40,
            "robots/s.urdf.xacro": _xacro(
                ESCAPE + "<link name=\"${OS['listdir']('../.git/refs/heads')}\"/>"
            ),
        },
        ("inspect", "robots/s.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "a package whose top-level links lead out": (
        {
            "package.xml": "<package><name>evil</name></package>",
            ".git/config": f"[http]\n  extraheader = AUTHORIZATION: basic {SECRET}\n",
            "root -> /": "",
            "out -> {outside}": "",
            "cfg -> .git/config": "",
            "robots/s.urdf.xacro": _xacro(
                "",
                name="${xacro.load_yaml('../out/secret.yaml')}"
                "${xacro.load_yaml('../cfg')}${xacro.load_yaml('../root/etc/hostname')}",
            ),
        },
        ("inspect", "robots/s.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "a 60-million-character error message": (
        {"e.urdf.xacro": _xacro("", name="${xacro.fatal(python.chr(27) * 60000000)}")},
        ("inspect", "e.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "80,000 findings": (
        {"f.urdf": f'<robot name="f"><link name="base"/>{FLOOD}</robot>'},
        ("inspect", "f.urdf", "--format", "json"),
        1,
        None,
    ),
    # --- unbounded work --------------------------------------------------------------
    "8 GB string": (
        {"m.urdf.xacro": _xacro("", name="${'a' * (2**32)}")},
        ("inspect", "m.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "CPU forever": (
        {"c.urdf.xacro": _xacro("", name="${10**(10**8)}")},
        ("inspect", "c.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "macros that double": (
        {
            "d.urdf.xacro": _xacro(
                '<xacro:macro name="m0"><link name="x"/></xacro:macro>'
                + "".join(
                    f'<xacro:macro name="m{k}"><xacro:m{k - 1}/><xacro:m{k - 1}/></xacro:macro>'
                    for k in range(1, 40)
                )
                + "<xacro:m39/>"
            )
        },
        ("inspect", "d.urdf.xacro"),
        2,
        "xacro-failed",
    ),
    "MJCF include fan-out": (
        _include_fan_out(levels=8, width=10),
        ("inspect", "robot.xml"),
        2,
        "too-much-input",
    ),
    "1000 sibling joints": (
        {"s.xml": _mjcf(f'<body name="root"><joint name="r"/><geom size=".1"/>{SIBLINGS}</body>')},
        ("inspect", "s.xml"),
        0,
        None,
    ),
    "replicate 100 x 100 x 100": (
        {"r.xml": _mjcf(REPLICATED)},
        ("inspect", "r.xml"),
        2,
        "too-many-joints",
    ),
    "replicate bomb in an included file": (
        {
            "big.xml": "<mujocoinclude>" + REPLICATED + "</mujocoinclude>",
            "m.xml": _mjcf(
                '<body name="a"><joint/><geom size=".1"/><include file="big.xml"/></body>'
            ),
        },
        ("inspect", "m.xml"),
        2,
        "too-many-joints",
    ),
    "replicate counts with a sign": (
        {"r.xml": _mjcf(REPLICATED.replace('count="100"', 'count="+100"'))},
        ("inspect", "r.xml"),
        2,
        "too-many-joints",
    ),
    "a replicate count of 5,000 digits (more than int() converts)": (
        {"r.xml": _mjcf(REPLICATED.replace('count="100"', f'count="{"9" * 5000}"', 1))},
        ("inspect", "r.xml"),
        2,
        "too-much-input",
    ),
    "a replicate count cspace cannot read": (
        {"r.xml": _mjcf(REPLICATED.replace('count="100"', 'count="1e3"'))},
        ("inspect", "r.xml"),
        2,
        "bad-number",
    ),
    "attach of an unnamed model named by its file": (
        {
            "p.xml": '<mujoco model="kid"><worldbody><body name="b">'
            + REPLICATED
            + "</body></worldbody></mujoco>",
            "a.xml": '<mujoco><asset><model file="p.xml"/></asset><worldbody><body name="t">'
            '<attach model="kid" body="b" prefix="k"/></body></worldbody></mujoco>',
        },
        ("inspect", "a.xml"),
        2,
        "too-many-joints",
    ),
    "attach of a body of the same file": (
        {
            "s.xml": _mjcf(
                '<body name="l0"><joint/><geom size=".1"/></body><body name="l1">'
                '<attach body="l0" prefix="a"/><attach body="l0" prefix="b"/></body>'
            )
        },
        ("inspect", "s.xml"),
        2,
        "unsupported-element",
    ),
    "flexcomp of 3,330 points given inline": (
        {
            "f.xml": _mjcf(
                '<flexcomp name="f" type="direct" dim="1" radius="0.001" point="'
                + " ".join(f"{k * 0.01} 0 {(k % 7) * 0.01}" for k in range(3330))
                + '" element="'
                + " ".join(f"{k} {k + 1}" for k in range(3329))
                + '"/>'
            )
        },
        ("inspect", "f.xml"),
        2,
        "too-many-joints",
    ),
    "120,000 sites": (
        {
            "s.xml": _mjcf(
                '<body name="b"><joint/><geom size=".1"/><replicate count="120">'
                '<replicate count="1000"><site size=".01"/></replicate></replicate></body>'
            )
        },
        ("inspect", "s.xml"),
        2,
        "mujoco-refused",  # out of the child's memory: a clear line, within the bound
    ),
    "a height field of 14,000 x 14,000 without a file": (
        {
            "h.xml": _mjcf(
                '<body name="b"><joint/><geom size=".1"/></body>',
                head='<asset><hfield name="h" nrow="14000" ncol="14000" size="1 1 1 1"/></asset>',
            )
        },
        ("inspect", "h.xml"),
        2,
        "mujoco-refused",
    ),
    "an include named with a trailing space": (
        {"part.xml": "<mujocoinclude/>", "r.xml": '<mujoco><include file="part.xml "/></mujoco>'},
        ("inspect", "r.xml"),
        2,
        "bad-include",
    ),
    "flexcomp of a million bodies": (
        {"f.xml": _mjcf('<flexcomp name="f" type="grid" count="1000 1000 1" dim="2"/>')},
        ("inspect", "f.xml"),
        2,
        "too-many-joints",
    ),
    "attach of a model attached 64 times": (
        {
            "a.xml": '<mujoco><asset><model name="m" file="m.xml"/></asset><worldbody>'
            + "".join(
                f'<body name="s{k}"><attach model="m" body="b" prefix="p{k}_"/></body>'
                for k in range(64)
            )
            + "</worldbody></mujoco>",
            "m.xml": _mjcf('<body name="b">' + "<body/>" * 100 + "</body>"),
        },
        ("inspect", "a.xml"),
        2,
        "too-many-joints",
    ),
    "60,000 equality constraints": (
        {
            "e.xml": _mjcf(DEEP).replace(
                "</mujoco>", f"<equality>{TIES * 60000}</equality></mujoco>"
            )
        },
        ("inspect", "e.xml"),
        2,
        "too-many-constraints",
    ),
    "1,000 equality constraints across a 250-deep chain": (
        {"e.xml": _mjcf(DEEP).replace("</mujoco>", f"<equality>{TIES * 1000}</equality></mujoco>")},
        ("inspect", "e.xml", "--format", "json"),
        0,
        None,
    ),
    "6000 welded bodies": (
        {"w.xml": _mjcf('<body name="r"><joint/>' + WELDED + "</body>")},
        ("inspect", "w.xml"),
        2,
        "too-many-joints",
    ),
    "250 nested default classes": (
        {
            "n.xml": _mjcf(
                '<body name="b"><joint class="d249"/><geom size=".1"/></body>', head=NESTED_DEFAULTS
            )
        },
        ("inspect", "n.xml"),
        0,
        None,
    ),
    "4,999 floating joints": (
        {"s.urdf": f'<robot name="s"><link name="base"/>{STAR}</robot>'},
        ("inspect", "s.urdf"),
        2,
        "too-many-dofs",
    ),
    "3,000-character names": (
        {
            "l.urdf": f'<robot name="r"><link name="a"/><link name="{LONG}"/>'
            f'<joint name="j" type="continuous"><parent link="a"/><child link="{LONG}"/>'
            "</joint></robot>"
        },
        ("inspect", "l.urdf"),
        2,
        "name-too-long",
    ),
    # --- blocking and other files ----------------------------------------------------
    "FIFO as the robot file": (
        {"|robot.urdf": ""},
        ("inspect", "robot.urdf"),
        2,
        "file-unreadable",
    ),
    "FIFO as an include": (
        {"|pipe.xml": "", "r.xml": '<mujoco><include file="pipe.xml"/></mujoco>'},
        ("inspect", "r.xml"),
        2,
        "file-unreadable",
    ),
    "attached model that is a FIFO": (
        {
            "|m.xml": "",
            "r.xml": '<mujoco><asset><model name="m" file="m.xml"/></asset><worldbody>'
            '<body name="b"><attach model="m" body="x" prefix="p"/></body></worldbody></mujoco>',
        },
        ("inspect", "r.xml"),
        2,
        "file-unreadable",
    ),
    "a MuJoCo plugin named by path": (
        {
            "r.xml": _mjcf(
                '<body name="b"><joint/><geom size=".1"/></body>',
                head='<extension><plugin plugin="{marker}.so"/></extension>',
            )
        },
        ("inspect", "r.xml"),
        2,
        "mujoco-refused",
    ),
    "include linked to a FIFO outside": (
        {"@link.xml": "", "r.xml": '<mujoco><include file="link.xml"/></mujoco>'},
        ("inspect", "r.xml"),
        2,
        "outside-tree",
    ),
    "include of a file outside": (
        {"r.xml": '<mujoco><include file="../outside/secret.xml"/></mujoco>'},
        ("inspect", "r.xml"),
        2,
        "outside-tree",
    ),
    "include of /etc/passwd": (
        {"r.xml": '<mujoco><include file="/etc/passwd"/></mujoco>'},
        ("inspect", "r.xml"),
        2,
        "outside-tree",
    ),
    "meshes, textures, height field and skin outside: never opened": (
        {
            "r.xml": _mjcf(
                '<body name="b"><joint/><geom type="mesh" mesh="m"/>'
                '<geom type="hfield" hfield="h"/></body>',
                head='<compiler meshdir="{outside}" texturedir="/etc"/><asset>'
                '<mesh name="m" file="../outside/secret.xml"/>'
                '<mesh name="abs" file="{outside}/secret.xml"/>'
                '<texture name="t" type="cube" fileright="../outside/fifo" file="passwd"/>'
                '<material name="mat" texture="t"/>'
                '<hfield name="h" file="{outside}/fifo" size="1 1 1 1"/>'
                '<skin file="../outside/secret.xml"/></asset>',
            )
        },
        ("inspect", "r.xml"),
        0,
        None,
    ),
    "attached model outside": (
        {
            "r.xml": '<mujoco><asset><model name="m" file="../outside/secret.xml"/></asset>'
            '<worldbody><attach model="m" body="b" prefix="p"/></worldbody></mujoco>'
        },
        ("inspect", "r.xml"),
        2,
        "outside-tree",
    ),
    "a mesh in an archive": (
        {"r.xml": _mjcf("", head='<asset><mesh name="m" file="../outside/a.zip/m.stl"/></asset>')},
        ("inspect", "r.xml"),
        2,
        "bad-include",
    ),
    "a URL": (
        {"r.xml": '<mujoco><include file="http://example.com/robot.xml"/></mujoco>'},
        ("inspect", "r.xml"),
        2,
        "bad-include",
    ),
    # --- hostile but plausible MJCF --------------------------------------------------
    "repeated default class": (
        {
            "r.xml": _mjcf(
                '<body name="b"><joint class="a"/></body>',
                head='<default><default class="a"><joint type="slide"/></default>'
                '<default class="a"><joint range="0 1"/></default></default>',
            )
        },
        ("inspect", "r.xml"),
        2,
        "mujoco-refused",
    ),
    "angle=degrees": (
        {
            "r.xml": _mjcf(
                '<body name="b"><joint range="0 90"/></body>', '<compiler angle="degrees"/>'
            )
        },
        ("inspect", "r.xml"),
        2,
        "mujoco-refused",
    ),
    "composite (gone from MuJoCo 4)": (
        {"r.xml": _mjcf('<body name="b"><composite type="grid" count="2 2 1"/></body>')},
        ("inspect", "r.xml"),
        2,
        "mujoco-refused",
    ),
    "flexcomp from a mesh file": (
        {"r.xml": _mjcf('<flexcomp name="f" type="mesh" file="/etc/passwd" dim="2"/>')},
        ("inspect", "r.xml"),
        2,
        "unsupported-element",
    ),
    # MuJoCo's XML parser ends a DOCTYPE at its first ">": the document it would read
    # hides a replicate bomb and an include outside from lxml's.
    "a DOCTYPE hiding another document": (
        {
            "r.xml": "<!DOCTYPE mujoco [ <!-- ]>\n"
            + _mjcf(REPLICATED + '<include file="{outside}/secret.xml"/>')
            + "--> ]>\n"
            + _mjcf('<body name="b"><joint/><geom size=".1"/></body>')
        },
        ("inspect", "r.xml"),
        2,
        "xml-unsafe",
    ),
    "an included root in a namespace": (
        {
            "r.xml": '<mujoco><worldbody><include file="part.xml"/></worldbody></mujoco>',
            "part.xml": f'<mujoco xmlns="urn:x">{REPLICATED}'
            '<include file="{outside}/secret.xml"/></mujoco>',
        },
        ("inspect", "r.xml"),
        2,
        "xml-unsafe",
    ),
    "a tab in an include name": (  # MuJoCo is given "a b.xml", as lxml read it
        {
            "r.xml": '<mujoco><worldbody><include file="a\tb.xml"/></worldbody></mujoco>',
            "a b.xml": '<mujocoinclude><body name="b"><joint/><geom size=".1"/></body>'
            "</mujocoinclude>",
            "a\tb.xml": f'<mujocoinclude>{REPLICATED}<include file="{{outside}}/secret.xml"/>'
            "</mujocoinclude>",
        },
        ("inspect", "r.xml"),
        0,
        None,
    ),
    "one include name for two files": (  # MuJoCo keys the files it is given by base name
        {
            "r.xml": '<mujoco><asset><model name="M" file="m/model.xml"/></asset><worldbody>'
            '<replicate count="1000"><include file="part.xml"/></replicate></worldbody></mujoco>',
            "part.xml": '<mujocoinclude><body><geom size=".1"/></body></mujocoinclude>',
            "m/model.xml": '<mujoco><worldbody><include file="part.xml"/></worldbody></mujoco>',
            "m/part.xml": "<mujocoinclude>"
            + '<body><geom size=".1"/></body>' * 4
            + "</mujocoinclude>",
        },
        ("inspect", "r.xml"),
        0,  # each given to MuJoCo under a name of its own: what the pre-scan counted
        None,
    ),
}


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    """The folder the robot files are in, with a secret folder beside it."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.yaml").write_text(f"key: {SECRET}\n")
    (outside / "secret.xml").write_text(f'<mujoco model="{SECRET}"/>\n')
    (outside / "secret.xacro").write_text(f'<robot {XACRO_NS}><link name="{SECRET}"/></robot>\n')
    os.mkfifo(outside / "fifo")
    inside = tmp_path / "tree"
    inside.mkdir()
    return inside


def _write(tree: Path, files: dict[str, str], marker: Path) -> None:
    for name, text in files.items():
        if name.startswith("|"):  # a FIFO
            os.mkfifo(tree / name[1:])
        elif " -> " in name:  # a link: "name -> target"
            link, target = name.split(" -> ")
            (tree / link).parent.mkdir(parents=True, exist_ok=True)
            (tree / link).symlink_to(target.replace("{outside}", str(tree.parent / "outside")))
        elif name.startswith("@"):  # a link out of the tree (to the secret FIFO)
            (tree / name[1:]).symlink_to(tree.parent / "outside" / "fifo")
        else:
            (tree / name).parent.mkdir(parents=True, exist_ok=True)
            text = text.replace("{marker}", str(marker)).replace(
                "{outside}", str(tree.parent / "outside")
            )
            (tree / name).write_text(text)


@pytest.fixture
def watch(tree: Path) -> Iterator[OpenWatch]:
    watcher = OpenWatch(tree.parent / "outside")
    yield watcher
    watcher.close()


def _assert_contained(run: Run, marker: Path, watch: OpenWatch) -> None:
    everything = run.stdout + run.stderr
    assert not marker.exists(), "the file's code ran"
    assert SECRET not in everything
    assert "root:x:0:0" not in everything
    assert watch.opened() == [], "a file outside the tree was opened"


@pytest.mark.bounded
@pytest.mark.parametrize("case", sorted(CASES))
def test_hostile_case(case: str, tree: Path, watch: OpenWatch) -> None:
    files, args, exit_code, code = CASES[case]
    marker = tree.parent / "MARKER"
    _write(tree, files, marker)
    result = measured(*args, cwd=tree, env={"CSPACE_TEST_SECRET": SECRET}, forked=True)
    if exit_code == 2:
        assert code is not None
        assert_bounded_error(result, code)
    else:
        assert result.run.code == exit_code, result
        assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    _assert_contained(result.run, marker, watch)


@pytest.mark.parametrize(
    "command",
    [
        ("check", "evil.urdf", "--dimension", "0"),
        ("sample", "evil.urdf", "-n", "1"),
        ("diff", "evil.urdf", "evil.urdf"),
        ("inspect", "-"),
        ("inspect", "evil.urdf", "other.urdf"),
    ],
)
def test_no_command_expands_an_unasked_substitution(
    command: tuple[str, ...], tree: Path, watch: OpenWatch
) -> None:
    marker = tree.parent / "MARKER"
    evil = _xacro("", name=f"${{OS['system']('touch {marker}')}}")
    _write(tree, {"evil.urdf": evil, "other.urdf": evil}, marker)
    run = run_cli(*command, cwd=tree, stdin=evil.encode())
    assert run.code == 2
    assert "[xacro-not-requested]" in run.stderr
    assert "Traceback" not in run.stderr
    _assert_contained(run, marker, watch)


def test_the_escape_is_stopped_by_the_sandbox_not_by_luck(tree: Path, watch: OpenWatch) -> None:
    # The walk reaches os.system: the refusal names the audit event it tripped.
    marker = tree.parent / "MARKER"
    _write(tree, CASES["escape to os.system"][0], marker)
    run = run_cli("inspect", "e.urdf.xacro", cwd=tree)
    assert "may not do this here (os.system)" in run.stderr
    _assert_contained(run, marker, watch)


def test_an_output_bomb_meets_the_output_limit(tmp_path: Path) -> None:
    small = cspace.XacroOptions(limits=XacroLimits(output_bytes=200))
    with pytest.raises(cspace.errors.XacroError, match="larger than the 200-byte limit"):
        cspace.inspect(ROBOTS / "xacro_demo" / "urdf" / "arm.urdf.xacro", xacro=small)


def test_xacro_still_expands_what_it_should() -> None:
    arm = ROBOTS / "xacro_demo" / "urdf" / "arm.urdf.xacro"  # includes, $(find), macros
    assert cspace.inspect(arm).manifold.notation == "R^4"
    options = cspace.XacroOptions(require_confinement=False)
    assert cspace.inspect(arm, xacro=options).manifold.notation == "R^4"


_CONFINED = """
import os, socket, sys
from cspace._confine.landlock import restrict_to_reading
allowed = sys.argv[1]
assert restrict_to_reading([allowed]) >= 1
open(os.path.join(allowed, "ok.txt")).read()
def refused(action):
    try:
        action()
    except PermissionError:
        return True
    return False
print(refused(lambda: open(sys.argv[2]).read()),
      refused(lambda: open(os.path.join(allowed, "root", sys.argv[2].lstrip("/"))).read()),
      refused(lambda: open(os.path.join(allowed, "new.txt"), "w")),
      refused(lambda: os.execv("/bin/true", ["true"])),
      refused(lambda: socket.create_connection(("127.0.0.1", int(sys.argv[3])), timeout=5)))
"""


def test_landlock_confines_a_process_without_any_audit_hook(tmp_path: Path) -> None:
    # The kernel layer alone: code that gets past xacro's filter and the audit hook
    # still cannot read, write, run a program or connect.
    import socket

    allowed = tmp_path / "allowed"
    allowed.mkdir()
    (allowed / "ok.txt").write_text("fine")
    (allowed / "root").symlink_to("/")  # a rule on a link would be a rule on /
    secret = tmp_path / "secret.txt"
    secret.write_text(SECRET)
    with socket.create_server(("127.0.0.1", 0)) as server:
        port = server.getsockname()[1]
        done = subprocess.run(
            [sys.executable, "-c", _CONFINED, str(allowed), str(secret), str(port)],
            capture_output=True,
            text=True,
            timeout=60,
            check=True,
        )
    assert done.stdout.split() == ["True"] * 5


def test_the_model_is_built_from_the_bytes_read(tmp_path: Path) -> None:
    # A file that changes after it was read: the report is the first version's alone.
    path = tmp_path / "r.xml"
    path.write_text(
        _mjcf('<body name="b"><joint name="j" type="slide" range="0 1"/><geom size="1"/></body>')
    )
    source = cspace.read_source(path)
    path.write_text(_mjcf('<body name="b"><joint name="j" type="ball"/><geom size="1"/></body>'))
    report = cspace.inspect_source(source, file=path)
    assert [(j.name, j.kind.value) for j in report.joints] == [("j", "prismatic")]
    assert report.source.sha256 == source.sha256


@pytest.mark.parametrize("axis", ["1e200 1e200 0", "1e-200 1e-200 0"])
def test_huge_and_tiny_axes_are_directions(axis: str, tmp_path: Path) -> None:
    path = tmp_path / "a.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="continuous">'
        f'<parent link="a"/><child link="b"/><axis xyz="{axis}"/></joint></robot>'
    )
    codes = [d.code for d in cspace.inspect(path).diagnostics]
    assert codes == ["axis-normalized"]


def test_paths_are_str_or_pathlike() -> None:
    arm = ROBOTS / "arm7.urdf"
    assert cspace.inspect(arm).manifold == cspace.inspect(str(arm)).manifold
    assert cspace.load(arm).names == cspace.load(str(arm)).names
    for wrong in (None, 3, b"robots/arm7.urdf"):
        with pytest.raises(cspace.errors.ArgumentTypeError, match=r"str or os\.PathLike"):
            cspace.inspect(wrong)  # type: ignore[arg-type]
        with pytest.raises(cspace.errors.ArgumentTypeError):
            cspace.load(wrong)  # type: ignore[arg-type]
    with pytest.raises(cspace.errors.FileUnreadableError, match="NUL"):
        cspace.inspect("robots/arm7.urdf\0.xacro")


def test_the_configuration_commands_load_as_inspect_does(tree: Path) -> None:
    xacro = str(ROBOTS / "xacro_demo" / "urdf" / "arm.urdf.xacro")
    sampled = run_cli("sample", xacro, "-n", "1", "--arg", "wrist:=continuous", cwd=tree)
    assert sampled.code == 0, sampled
    assert '"wrist"' in sampled.stdout
    bad = run_cli("sample", xacro, "-n", "1", "--arg", "wrist", cwd=tree)
    assert bad.code == 2
    assert bad.stderr == "cspace: error: xacro argument 'wrist' is not NAME:=VALUE [bad-argument]\n"


_FILTERED = """
import ctypes, fcntl, os, resource, socket, sys, tempfile, threading
from cspace._confine.seccomp import deny_escapes, drop_capabilities
scratch = tempfile.TemporaryFile()
drop_capabilities()
assert deny_escapes()
libc = ctypes.CDLL(None, use_errno=True)
def refused(action):
    try:
        action()
    except (PermissionError, RuntimeError):  # RuntimeError: "can't start new thread"
        return "refused"
    return "allowed"
def shmget():
    if libc.shmget(0, 4096, 0o1600) < 0:
        raise PermissionError(ctypes.get_errno(), "shmget")
resource.setrlimit(resource.RLIMIT_NOFILE, (64, 64))  # its own limits: allowed
print(refused(lambda: socket.socket(socket.AF_INET, socket.SOCK_DGRAM)),
      refused(lambda: socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)),
      refused(os.fork),
      refused(lambda: threading.Thread(target=print).start()),
      refused(lambda: os.memfd_create("x")),
      refused(lambda: os.execv("/bin/true", ["true"])),
      refused(lambda: socket.sethostname("x")),
      refused(lambda: os.kill(os.getppid(), 0)),
      refused(lambda: resource.prlimit(os.getppid(), resource.RLIMIT_CPU, (1, 1))),
      refused(shmget),
      refused(lambda: os.posix_fallocate(scratch.fileno(), 0, 1 << 30)),
      refused(lambda: os.ftruncate(scratch.fileno(), 1 << 30)),
      refused(lambda: os.chmod(sys.argv[1], 0o4777)),
      refused(lambda: os.utime(sys.argv[1], (0, 0))),
      refused(lambda: os.setxattr(sys.argv[1], "user.cspace", b"1")),
      refused(lambda: os.truncate(sys.argv[1], 0)),
      refused(lambda: fcntl.fcntl(scratch.fileno(), fcntl.F_SETOWN, os.getppid())),
      refused(lambda: fcntl.fcntl(scratch.fileno(), 10, 9)),  # F_SETSIG
      refused(lambda: os.setpriority(os.PRIO_PROCESS, os.getppid(), 19)),
      refused(lambda: os.sched_setaffinity(os.getppid(), {0})))
"""


def test_seccomp_refuses_what_landlock_does_not_cover(tmp_path: Path) -> None:
    # UDP and Unix sockets, processes and threads, anonymous memory, root's powers,
    # signals and limits of other processes, System V IPC, files grown past RLIMIT_FSIZE,
    # modes, times, attributes and sizes of files, signals through fcntl, priorities.
    victim = tmp_path / "victim.txt"
    victim.write_text("intact")
    before = victim.stat()
    done = subprocess.run(
        [sys.executable, "-c", _FILTERED, str(victim)],
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    assert done.stdout.split() == ["refused"] * 20
    after = victim.stat()
    assert (after.st_mode, after.st_mtime_ns, victim.read_text()) == (
        before.st_mode,
        before.st_mtime_ns,
        "intact",
    )


@pytest.mark.bounded
def test_a_quoted_pattern_never_follows_linked_folders(tree: Path, watch: OpenWatch) -> None:
    (tree / "robots" / "sub").mkdir(parents=True)
    for name in ("robots/arm.urdf", "robots/sub/arm.urdf"):
        (tree / name).write_bytes((ROBOTS / "arm7.urdf").read_bytes())
    (tree / "robots" / "self").symlink_to(".")  # each alone makes glob's walk exponential
    (tree / "robots" / "up").symlink_to("..")
    (tree / "robots" / "out").symlink_to(tree.parent / "outside")
    result = measured("inspect", "robots/**/*.urdf", "--format", "jsonl", cwd=tree, forked=True)
    assert result.run.code == 0, result
    assert result.cpu_seconds < 10
    sources = [json.loads(line)["source"]["path"] for line in result.run.stdout.splitlines()]
    assert sources == ["robots/arm.urdf", "robots/sub/arm.urdf"]
    _assert_contained(result.run, tree.parent / "MARKER", watch)


@pytest.mark.bounded
def test_a_linked_robot_file_stays_in_its_folder(tree: Path, watch: OpenWatch) -> None:
    (tree / "secret.urdf").symlink_to(tree.parent / "outside" / "secret.xml")
    (tree / "arm.urdf").write_bytes((ROBOTS / "arm7.urdf").read_bytes())
    (tree / "alias.urdf").symlink_to("arm.urdf")
    for command in (("inspect", "secret.urdf"), ("diff", "secret.urdf", "arm.urdf")):
        result = measured(*command, cwd=tree, forked=True)
        assert_bounded_error(result, "outside-tree")
        _assert_contained(result.run, tree.parent / "MARKER", watch)
    assert run_cli("inspect", "alias.urdf", cwd=tree).code == 0
    allowed = run_cli("inspect", "secret.urdf", "--allow-dir", "../outside", cwd=tree)
    assert allowed.code == 0  # read, since asked for: an MJCF scene without joints
    assert "[outside-tree]" not in allowed.stderr


@pytest.mark.bounded
@pytest.mark.parametrize(
    ("content", "said"),
    [
        (b'{"manifold": 1, "joints": [' + b"{}," * 2_000_000 + b"{}]}", "JSON values"),
        (b"[" + b"0," * 2_000_000 + b"0]", "JSON values"),
        (b'{"joints": [], "manifold": "' + b"x" * (50 << 20) + b'"}', "bytes, larger"),
    ],
)
def test_saved_reports_are_bounded_before_parsing(content: bytes, said: str, tree: Path) -> None:
    (tree / "old.json").write_bytes(content)
    (tree / "arm.urdf").write_bytes((ROBOTS / "arm7.urdf").read_bytes())
    message = assert_bounded_error(
        measured("diff", "old.json", "arm.urdf", cwd=tree, forked=True), "bad-report"
    )
    assert said in message


@pytest.mark.bounded
def test_a_pattern_through_a_linked_folder_is_refused(tree: Path, watch: OpenWatch) -> None:
    (tree / "robots").symlink_to(tree.parent / "outside")
    (tree.parent / "outside" / "secret.urdf").write_bytes((ROBOTS / "arm7.urdf").read_bytes())
    watch.opened()  # the write above, not cspace
    result = measured("inspect", "robots/**/*.urdf", cwd=tree, forked=True)
    assert "'robots' is a link" in assert_bounded_error(result, "outside-tree")
    _assert_contained(result.run, tree.parent / "MARKER", watch)


def test_a_folder_named_like_a_pattern_does_not_mask_it(tree: Path) -> None:
    # A committed robots/**/*.urdf would have been taken for the file the pattern names.
    (tree / "robots" / "**").mkdir(parents=True)
    (tree / "robots" / "**" / "*.urdf").write_bytes((ROBOTS / "arm7.urdf").read_bytes())
    (tree / "robots" / "bad.urdf").write_text("<robot name='r'>")  # truncated
    run = run_cli("inspect", "robots/**/*.urdf", "--format", "jsonl", cwd=tree)
    assert run.code == 2
    assert "robots/bad.urdf" in run.stderr


def test_csv_headers_keep_names_with_commas_and_quotes(tmp_path: Path) -> None:
    path = tmp_path / "comma.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/><joint name=\'x,"y\' '
        'type="continuous"><parent link="a"/><child link="b"/></joint></robot>'
    )
    run = run_cli("sample", str(path), "-n", "2", "--format", "csv", cwd=tmp_path)
    rows = list(csv.reader(io.StringIO(run.stdout)))
    assert rows[0] == ['x,"y'] and len(rows) == 3 and all(len(row) == 1 for row in rows)


@pytest.mark.bounded
@pytest.mark.parametrize(
    "call",
    [
        "OS['utime']('{victim}', (0, 0))",
        "OS['setxattr']('{victim}', 'user.cspace', b'1')",
        "OS['chmod']('{victim}', 0o4777)",
    ],
)
def test_xacro_cannot_touch_files_outside(call: str, tree: Path) -> None:
    victim = tree.parent / "outside" / "secret.yaml"
    before = victim.stat()
    body = ESCAPE + '<link name="${' + call.replace("{victim}", str(victim)) + '}"/>'
    (tree / "t.urdf.xacro").write_text(_xacro(body))
    assert_bounded_error(measured("inspect", "t.urdf.xacro", cwd=tree, forked=True), "xacro-failed")
    after = victim.stat()
    assert (after.st_mode, after.st_mtime_ns) == (before.st_mode, before.st_mtime_ns)
    assert os.listxattr(victim) == []


@pytest.mark.bounded
def test_five_thousand_broken_joints_give_a_hundred_lines(tree: Path, watch: OpenWatch) -> None:
    """Every problem in one run, but bounded: the first 99 and one line saying how many
    more, within the time and memory bounds, with every line escaped."""
    broken = "".join(
        f'<link name="l{k}"/><joint name="j{k}\u202e" type="revolut{k}"><parent link="base"/>'
        f'<child link="l{k}"/></joint>'
        for k in range(5000)
    )
    (tree / "many.urdf").write_text(f'<robot name="r"><link name="base"/>{broken}</robot>')
    result = measured("inspect", "many.urdf", cwd=tree, forked=True)
    assert result.run.code == 2 and result.run.stdout == ""
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    lines = result.run.stderr.splitlines()
    assert len(lines) == 100
    assert all(line.startswith("cspace: error: many.urdf") for line in lines)
    assert lines[-1].endswith("4,901 more problems are not listed [more-problems]")
    assert "\u202e" not in result.run.stderr and "\\u202e" in result.run.stderr
    _assert_contained(result.run, tree.parent / "MARKER", watch)
