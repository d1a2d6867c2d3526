"""Names and paths from untrusted files reach no terminal, log or PR comment raw.

A robot file's names (through XML character references) and a file's own name can hold
ANSI and OSC 8 escape sequences, carriage returns and line breaks, C1 controls (U+009B is
CSI), bidi controls (U+202E, U+2066) and zero-width characters. Every output (the text,
JSON, JSON Lines and Markdown reports, summaries, diffs, ``check``, the configuration
commands and the one-line error) must show them escaped: every line of stdout and stderr
is ``str.isprintable()``, and JSON still gives back the exact text.
"""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cspace
from cspace._render.markdown import (
    code,
    render_diff_markdown,
    render_markdown,
    render_summary_markdown,
)
from cspace._render.text import render_diff_text, render_summary_text, render_text
from cspace._reports.diff import diff_reports
from cspace._reports.summary import SummaryRow
from cspace._safetext import json_text, printable

import forked_cli
from conftest import HASH_SEED, command_env, cspace_command

# What XML lets a name hold (no C0 but tab, CR, LF): DEL, C1 CSI and OSC/ST, bidi
# controls, zero-width characters, line and paragraph separators.
NAME = (
    "j\x9b31m\u202etxt.exe\u2066\u200b\u200d\ufeff\r\nforged line\t\x7f\x85"
    "\u2028\u2029\x9d8;;https://evil.example\x9clink\x9d8;;\x9c\u061c\u200e\u200f"
)
# A file name can hold anything but NUL and /: ESC sequences too.
PATH_NAME = (
    "\x1b[31mred\x1b]8;;https:evil.example\x07link\x1b]8;;\x07\r\n\x9b2J\u202etxt\u2066"
    "\u200b\x01\x7f.urdf"
)
# Saved reports (JSON) can hold every character, ESC included.
JSON_NAME = NAME + "\x1b[2J\x1b]8;;https://evil.example\x1b\\x\x1b]8;;\x1b\\\x00\x08"

UNSAFE = re.compile(
    "[\x00-\x08\x0b-\x1f\x7f-\x9f\u061c\u200b-\u200f\u2028-\u202e\u2066-\u2069\ufeff]"
)


def xml_refs(text: str) -> str:
    """``text`` as XML attribute content: every character outside printable ASCII a reference."""
    return "".join(
        ch if " " <= ch <= "~" and ch not in "<&\"'" else f"&#x{ord(ch):x};" for ch in text
    )


def robot(name: str, upper: str = "1") -> str:
    return (
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        f'<joint name="{xml_refs(name)}" type="revolute"><parent link="a"/><child link="b"/>'
        f'<axis xyz="0 0 1"/><limit lower="-1" upper="{upper}" effort="1" velocity="1"/></joint>'
        '<joint name="plain" type="revolute"><parent link="b"/><child link="c"/>'
        '<limit lower="1" upper="-1" effort="1" velocity="1"/></joint></robot>'
    )


def run(*args: str, cwd: Path, env: dict[str, str] | None = None) -> tuple[int, bytes, bytes]:
    """`cspace ARGS...`: its exit status, and its standard output and error as bytes.

    The bytes as written, not decoded: `assert_safe` checks that they are UTF-8. The
    command is forked as `conftest.run_cli` forks it (a new process, given the
    command's arguments, folder, environment and streams), unless ``env`` changes what
    an interpreter reads as it starts (`HASH_SEED`): then the installed script runs in
    a new interpreter. The timeout only guards against a hang.
    """
    full_env = command_env(env)
    if forked_cli.forkable(full_env):
        return forked_cli.run(list(args), str(cwd), None, 120, full_env)
    done = subprocess.run(
        [*cspace_command(), *args],
        cwd=cwd,
        capture_output=True,
        timeout=120,
        env=full_env,
        check=False,
    )
    return done.returncode, done.stdout, done.stderr


def assert_safe(data: bytes) -> str:
    """Valid UTF-8 whose every line is printable: no control, C1, bidi or zero-width char."""
    text = data.decode("utf-8")
    assert UNSAFE.search(text.replace("\n", "")) is None, text
    for line in text.split("\n"):
        assert line.isprintable(), repr(line)
    return text


@pytest.fixture
def hostile(tmp_path: Path) -> Path:
    """A robot file with a hostile name, holding a joint with a hostile name."""
    path = tmp_path / PATH_NAME
    path.write_text(robot(NAME), encoding="utf-8")
    return path


@pytest.mark.parametrize("fmt", ["text", "json", "jsonl", "markdown"])
def test_one_report_in_every_format(hostile: Path, fmt: str) -> None:
    code, out, err = run("inspect", PATH_NAME, "--format", fmt, cwd=hostile.parent)
    assert code == 1  # the plain joint's empty limits: a report with findings
    assert err == b""
    text = assert_safe(out)
    if fmt in ("json", "jsonl"):
        document = json.loads(text)
        assert document["joints"][0]["name"] == NAME
        assert document["source"]["path"] == PATH_NAME
        assert (text.count("\n") == 1) is (fmt == "jsonl")
    else:
        assert printable(PATH_NAME) in text
        assert printable(NAME) in text


@pytest.mark.parametrize("fmt", ["text", "markdown", "json"])
def test_several_files_and_their_errors(hostile: Path, fmt: str) -> None:
    broken = hostile.parent / ("broken\x1b[1m\u202e.urdf")
    broken.write_text("<robot", encoding="utf-8")
    missing = "missing\x1b]8;;https:x\x07\n\u2066.urdf"
    code, out, err = run(
        "inspect", PATH_NAME, broken.name, missing, "--format", fmt, cwd=hostile.parent
    )
    assert code == 2
    text = assert_safe(out)
    said = assert_safe(err).splitlines()
    found = f"cspace: error: {printable(PATH_NAME)}:"  # its findings that fail the run
    errors = [line for line in said if not line.startswith(found)]
    assert len(errors) == 2 and len(said) > 2, said
    assert errors[0].startswith(f"cspace: error: {printable(broken.name)}:")
    assert errors[0].endswith("[xml-syntax]")
    assert errors[1].startswith(f"cspace: error: {printable(missing)}: ")
    assert errors[1].endswith("[file-unreadable]")
    if fmt == "json":
        assert json.loads(text)["joints"][0]["name"] == NAME
    else:
        assert printable(missing) in text


def test_the_one_line_error_escapes_the_path(tmp_path: Path) -> None:
    (tmp_path / PATH_NAME).write_text("<robot", encoding="utf-8")  # exists: not a glob
    code, out, err = run("inspect", PATH_NAME, cwd=tmp_path)
    assert (code, out) == (2, b"")
    line = assert_safe(err)
    assert line.startswith(f"cspace: error: {printable(PATH_NAME)}:1:")
    assert line.endswith("[xml-syntax]\n") and line.count("\n") == 1
    assert "\\x1b[31mred" in line and "\\u202e" in line and "\\r\\n" in line


@pytest.mark.parametrize("fmt", ["text", "markdown", "json"])
def test_diff_of_hostile_files(hostile: Path, fmt: str) -> None:
    (hostile.parent / "new.urdf").write_text(robot(NAME, upper="2"), encoding="utf-8")
    code, out, err = run("diff", PATH_NAME, "new.urdf", "--format", fmt, cwd=hostile.parent)
    assert (code, err) == (1, b"")
    text = assert_safe(out)
    if fmt == "json":
        document = json.loads(text)
        assert document["old"]["path"] == PATH_NAME
        assert document["changes"][0]["joint"] == NAME
    else:
        assert printable(NAME) in text


def saved_report(folder: Path, name: str, path: str, upper: str = "1") -> Path:
    """A saved JSON report whose joint name and source path hold ``name`` and ``path``."""
    (folder / "plain.urdf").write_text(robot("j", upper), encoding="utf-8")
    document = cspace.inspect(str(folder / "plain.urdf")).to_dict()
    document["source"]["path"] = path
    document["joints"][0]["name"] = name
    document["coordinates"]["entries"][0]["name"] = name
    document["coordinates"]["entries"][0]["joint"] = name
    target = folder / f"report-{upper}.json"
    target.write_text(json.dumps(document), encoding="utf-8")
    return target


@pytest.mark.parametrize("fmt", ["text", "markdown", "json"])
def test_diff_of_saved_reports_with_escape_sequences(tmp_path: Path, fmt: str) -> None:
    old = saved_report(tmp_path, JSON_NAME, JSON_NAME, "1")
    new = saved_report(tmp_path, JSON_NAME + "2", "\x1b[0m\u202e", "2")
    code, out, err = run("diff", old.name, new.name, "--format", fmt, cwd=tmp_path)
    assert (code, err) == (1, b"")
    text = assert_safe(out)
    if fmt == "json":
        document = json.loads(text)
        assert (document["old"]["path"], document["new"]["path"]) == (JSON_NAME, "\x1b[0m\u202e")
        assert {c["joint"] for c in document["changes"]} == {JSON_NAME, JSON_NAME + "2"}


def test_check_output_is_escaped(hostile: Path, tmp_path: Path) -> None:
    code, out, err = run("check", PATH_NAME, "--dimension", "2", cwd=hostile.parent)
    assert (code, err) == (0, b"")
    assert assert_safe(out) == f"ok: {printable(PATH_NAME)}: R^2, dimension 2\n"
    report = saved_report(tmp_path, JSON_NAME, JSON_NAME)
    code, out, err = run("check", report.name, "--expect", "R^3", cwd=tmp_path)
    assert (code, out) == (1, b"")
    assert assert_safe(err) == (
        f"cspace: check failed: {printable(JSON_NAME)}: C-space is R^2, expected R^3\n"
    )


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_configuration_commands_escape_coordinate_names(hostile: Path, fmt: str) -> None:
    (hostile.parent / "ok.urdf").write_text(
        robot(NAME).replace('lower="1" upper="-1"', 'lower="-1" upper="1"'), encoding="utf-8"
    )
    code, out, err = run("sample", "ok.urdf", "-n", "2", "--format", fmt, cwd=hostile.parent)
    assert (code, err) == (0, b"")
    text = assert_safe(out)
    if fmt == "json":
        assert json.loads(text)["coordinates"] == [NAME, "plain"]
    else:
        assert text.splitlines()[0] == f"{printable(NAME, limit=None)},plain"


def test_same_input_same_bytes(hostile: Path) -> None:
    """Two interpreters whose string hashes differ write the same bytes."""
    for fmt in ("text", "json", "markdown"):
        first, second = (
            run("inspect", PATH_NAME, "--format", fmt, cwd=hostile.parent, env=seed)
            for seed in HASH_SEED
        )
        assert first == second


# The library: the renderers escape what they are given, whoever calls them.


def test_library_renderers_escape(hostile: Path) -> None:
    report = cspace.inspect(str(hostile))
    document = report.to_dict()
    diff = diff_reports(document, {**document, "source": {**document["source"], "path": "x"}})
    rows = [SummaryRow.of_report(report, failed=True), SummaryRow.of_error(PATH_NAME, NAME)]
    for text in (
        render_text(report),
        render_markdown(report),
        render_summary_text(rows),
        render_summary_markdown(rows),
        render_diff_text(diff),
        render_diff_markdown(diff),
        report.to_json(),
        report.to_json(indent=None),
        diff.to_json(),
    ):
        assert_safe(text.encode("utf-8"))
    assert json.loads(report.to_json())["joints"][0]["name"] == NAME


def test_json_text_keeps_every_value_and_escapes_what_is_not_printable() -> None:
    # Every code point; surrogates alone (a high one next to a low one is, in JSON, the
    # astral character they encode: JSON cannot tell them apart).
    everything = "".join(chr(c) for c in range(0x110000) if not 0xD800 <= c <= 0xDFFF)
    everything += "\ud800x\udfff\udc80"
    text = json_text({everything: [everything, 1.5]}, indent=2)
    assert json.loads(text) == {everything: [everything, 1.5]}
    assert all(line.isprintable() for line in text.split("\n"))
    assert json_text("\U000e0001") == '"\\udb40\\udc01"'  # a tag character: a surrogate pair
    assert json_text("é × 中") == '"é × 中"'  # printable text stays readable


def test_printable_escapes_once_and_shortens_idempotently() -> None:
    assert printable("a\x1b[31mb\u202ec\r\n") == "a\\x1b[31mb\\u202ec\\r\\n"
    huge = printable("\x1b" * 10_000)
    assert len(huge) <= 600 and huge.isprintable()
    assert printable(huge) == huge
    assert printable("x" * 10_000, limit=None) == "x" * 10_000


MARKDOWN_NAMES = (
    "a|b",
    "back`tick",
    "``two``",
    "<img src=x onerror=alert(1)>",
    "[click](https://evil.example)",
    "@org/team",
    "www.evil.example",
    "line\nbreak",
    "*bold* _it_ ~~s~~",
    "&lt;entity&gt;",
    "`lead",
    "`",
)


def _outside_code_spans(line: str) -> str:
    """The line with every code span (and escaped pipe) taken out."""
    return re.sub(r"(`+)(?!`).*?(?<!`)\1(?!`)", "", line.replace("\\|", ""))


@pytest.mark.parametrize("name", MARKDOWN_NAMES)
def test_markdown_names_stay_in_their_code_span_and_cell(tmp_path: Path, name: str) -> None:
    (tmp_path / "m.urdf").write_text(robot(name), encoding="utf-8")
    (tmp_path / "n.urdf").write_text(robot(name, upper="2"), encoding="utf-8")
    report = cspace.inspect(str(tmp_path / "m.urdf"))
    new = cspace.inspect(str(tmp_path / "n.urdf"))
    diff = render_diff_markdown(diff_reports(report.to_dict(), new.to_dict()))
    for text, columns in ((render_markdown(report), 6), (diff, 4)):
        for line in text.splitlines():
            outside = _outside_code_spans(line)
            for marker in ("<", "@", "](", "www.", "`", "&", "_", "~"):
                assert marker not in outside, (line, marker)
            if line.startswith("|"):
                assert outside.count("|") == columns + 1, line
    assert code(name) in render_markdown(report).replace("\\|", "|")


def test_mjcf_names_and_mujocos_own_messages_are_escaped(tmp_path: Path) -> None:
    """A hostile name reaches the output two new ways: through MuJoCo's compiled model,
    and inside MuJoCo's own error message; both are escaped like every other output."""
    name = xml_refs(NAME)
    good = tmp_path / "good.xml"
    good.write_text(
        f'<mujoco><worldbody><body name="b"><joint name="{name}" range="0 1"/>'
        '<geom size=".1"/></body></worldbody></mujoco>',
        encoding="utf-8",
    )
    for fmt in ("text", "markdown", "json"):
        code, out, err = run("inspect", "good.xml", "--format", fmt, cwd=tmp_path)
        assert (code, err) == (0, b"")
        text = assert_safe(out)
        if fmt == "json":
            assert json.loads(text)["joints"][0]["name"] == NAME  # the exact value, escaped
    refused = tmp_path / "refused.xml"
    refused.write_text(
        f'<mujoco><worldbody><body name="b"><joint class="{name}"/>'
        '<geom size=".1"/></body></worldbody></mujoco>',
        encoding="utf-8",
    )
    code, out, err = run("inspect", "refused.xml", cwd=tmp_path)
    assert (code, out) == (2, b"")
    line = assert_safe(err)
    assert line.count("\n") == 1 and line.rstrip().endswith("[mujoco-refused]")
    assert "unknown default class" in line and "\\u202e" in line


_JSON = st.recursive(
    st.none()
    | st.booleans()
    | st.integers()
    | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(),
    lambda children: st.lists(children) | st.dictionaries(st.text(), children),
    max_leaves=40,
)


@settings(max_examples=300, deadline=None)
@given(_JSON, st.sampled_from([None, 1, 2, 4]))
def test_json_text_is_json_dumps_with_every_unprintable_character_escaped(value, indent) -> None:
    from cspace._safetext import json_text

    text = json_text(value, indent=indent)
    assert json.loads(text) == value
    assert all(line.isprintable() for line in text.split("\n"))
    plain = json.dumps(value, indent=indent, ensure_ascii=False, allow_nan=False)
    if plain.replace("\n", "").isprintable():  # nothing to escape: the very same bytes
        assert text == plain
