"""Hostile actuators: thousands of them, numbers that are not finite, names that are
workflow commands or bidi overrides, and saved reports that lie about them.

Every name an actuator brings (its own, its joint's, its tendon's) reaches the CI log
escaped in every output (`test_ci_log`'s rule, on stdout and stderr); a gear or ctrlrange
that is not finite is null in JSON, never compared; a saved report whose actuators
contradict it is refused in one line.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_ci_log import CARRIED, EVIL, assert_no_command, assert_printable, run_safely

from conftest import assert_bounded_error, measured, run_cli

MANY = 5_000


def _evil() -> str:
    """A servo, a tendon's servo and a motor, every name EVIL; the servo's ctrlrange
    beyond its joint's range (a finding naming both)."""
    return f"""<mujoco model="m"><compiler angle="radian"/><worldbody>
  <body name="{EVIL}b"><joint name="{EVIL}j" range="-1 1"/><geom size=".1"/>
    <body><joint name="{EVIL}k" range="-1 1"/><geom size=".1"/></body></body></worldbody>
  <tendon><fixed name="{EVIL}t"><joint joint="{EVIL}j" coef="1"/></fixed></tendon>
  <actuator>
    <position name="{EVIL}servo" joint="{EVIL}j" kp="5" ctrlrange="-2 2"/>
    <position name="{EVIL}pull" tendon="{EVIL}t" kp="5"/>
    <motor name="{EVIL}m" joint="{EVIL}k"/>
  </actuator></mujoco>
"""


@pytest.fixture(scope="module")
def pr(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("actuators")
    (root / "evil.xml").write_text(_evil())
    (root / "evil2.xml").write_text(_evil().replace('kp="5" ctrlrange="-2 2"', 'kp="5" gear="3"'))
    servos = "".join(
        f'<position name="a{i}" joint="j" kp="1" ctrlrange="-3 3"/>\n' for i in range(MANY)
    )
    (root / "many.xml").write_text(
        '<mujoco><compiler angle="radian"/><worldbody><body name="b"><joint name="j" '
        f'range="-1 1"/><geom size=".1"/></body></worldbody><actuator>\n{servos}</actuator>'
        "</mujoco>"
    )
    (root / "nan.xml").write_text(
        '<mujoco><compiler angle="radian"/><worldbody><body name="b"><joint name="j" '
        'range="-1 1"/><geom size=".1"/></body></worldbody><actuator><position name="p" '
        'joint="j" kp="1" gear="nan" ctrllimited="true" ctrlrange="-inf nan"/></actuator></mujoco>'
    )
    (root / "x.jsonl").write_text("[0.5, 0.25]\n")
    return root


@pytest.mark.parametrize("fmt", ["text", "markdown", "json", "jsonl", "sarif", "github", "html"])
def test_evil_actuator_names_in_every_format(pr: Path, fmt: str) -> None:
    code, out, err = run_safely(pr, "inspect", "--format", fmt, "evil.xml", ours=fmt == "github")
    assert code == 0 and err == "", err
    if fmt == "json":
        document = json.loads(out)
        names = [a["name"] for a in document["actuators"]]
        assert (
            names[0]
            == EVIL.replace("&#10;", "\n")
            .replace("&#x202e;", "\u202e")
            .replace("&#x85;", "\x85")
            .replace("&#x9b;", "\x9b")
            + "servo"
        )  # kept exactly
        assert "actuator-ctrlrange-exceeds" in {d["code"] for d in document["diagnostics"]}
    elif fmt in ("text", "markdown"):
        assert CARRIED[1] in out and "servo" in out, out


@pytest.mark.parametrize("fmt", ["text", "json", "markdown"])
def test_evil_actuator_names_in_every_diff(pr: Path, fmt: str) -> None:
    code, out, _ = run_safely(pr, "diff", "--format", fmt, "evil.xml", "evil2.xml")
    assert code == 1 and "gear 3" in out, out
    if fmt != "json":
        assert CARRIED[1] in out, out


def test_evil_names_in_the_one_line_refusal_of_a_tendons_servo(pr: Path) -> None:
    code, out, err = run_safely(
        pr, "convert", "evil.xml", "x.jsonl", "--from", "canonical", "--to", "mujoco-ctrl"
    )
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "drives tendon" in err and CARRIED[1] in err, err


@pytest.mark.bounded
def test_thousands_of_actuators_within_the_bounds(pr: Path) -> None:
    result = measured("inspect", "--format", "json", "many.xml", cwd=pr, forked=True)
    assert result.run.code == 0, result.run.stderr
    document = json.loads(result.run.stdout)
    assert len(document["actuators"]) == MANY
    codes = [d["code"] for d in document["diagnostics"]]
    assert codes.count("actuator-ctrlrange-exceeds") == MANY
    assert result.cpu_seconds < 5, result  # 0.6 s measured
    text = run_cli("inspect", "many.xml", cwd=pr).stdout
    assert f"({MANY - 200:,} more actuators not shown)" in text
    assert text.count("actuator-ctrlrange-exceeds") == 1  # one line for them all


def test_a_gear_and_ctrlrange_not_finite_are_null_and_refused_by_mujoco_ctrl(
    pr: Path, tmp_path: Path
) -> None:
    code, out, _ = run_safely(pr, "inspect", "--format", "json", "nan.xml")
    assert code == 0
    actuator = json.loads(out)["actuators"][0]
    assert actuator["gear"] is None and actuator["ctrlrange"] == [None, None]
    saved = tmp_path / "nan.json"
    saved.write_text(out)
    code, out, _ = run_safely(pr, "diff", str(saved), "nan.xml")
    assert code == 0, out  # NaN is NaN: no change
    (tmp_path / "x.jsonl").write_text("[0.5]\n")
    code, out, err = run_safely(
        tmp_path,
        "convert",
        str(pr / "nan.xml"),
        "x.jsonl",
        "--from",
        "canonical",
        "--to",
        "mujoco-ctrl",
    )
    assert code == 2 and err.count("\n") == 1 and "gear nan" in err, err


def _saved(pr: Path, tmp_path: Path, change: object) -> Path:
    document = json.loads(run_cli("inspect", "--format", "json", "evil.xml", cwd=pr).stdout)
    change(document)  # type: ignore[operator]
    path = tmp_path / "lie.json"
    path.write_text(json.dumps(document))
    return path


@pytest.mark.bounded
@pytest.mark.parametrize(
    ("what", "change", "said"),
    [
        ("joint", lambda d: d["actuators"][0].update(target="nowhere"), "/actuators/0/target"),
        ("format", lambda d: d["source"].update(format="urdf"), "/actuators"),
        ("kind", lambda d: d["actuators"][1].update(kind="teleport"), "/actuators/1/kind"),
        ("extra", lambda d: d["actuators"][2].update(run="x"), "/actuators/2"),
        ("gear", lambda d: d["actuators"][2].update(gear="2"), "/actuators/2/gear"),
        (  # a second actuator of one name would hide the first one's change from the diff
            "twice",
            lambda d: d["actuators"].append(dict(d["actuators"][0], gear=5.0)),
            "/actuators/3/name",
        ),
    ],
)
def test_a_saved_report_that_lies_about_its_actuators_is_refused(
    pr: Path, tmp_path: Path, what: str, change: object, said: str
) -> None:
    lie = _saved(pr, tmp_path, change)
    result = measured("diff", str(lie), "evil.xml", cwd=pr, forked=True)
    message = assert_bounded_error(result, "bad-report")
    assert said in message, message


@pytest.mark.bounded
def test_the_ctrl_mujoco_clamps_is_said_in_bounded_lines(pr: Path, tmp_path: Path) -> None:
    """5,000 actuators whose ctrlrange leaves out every target converted: twenty warnings
    and one counting the rest, each name escaped, within the CPU bound."""
    many = (pr / "many.xml").read_text().replace('ctrlrange="-3 3"', 'ctrlrange="0.5 3"')
    (tmp_path / "clamped.xml").write_text(many.replace('name="a', f'name="{EVIL}a'))
    (tmp_path / "x.csv").write_text("j\n" + "0.25\n" * 1000)
    args = ("convert", "clamped.xml", "x.csv", "--from", "canonical", "--to", "mujoco-ctrl")
    result = measured(*args, cwd=tmp_path, forked=True)
    assert result.run.code == 0, result.run.stderr
    warnings = result.run.stderr.splitlines()
    assert len(warnings) == 21 and all(w.startswith("cspace: warning: x.csv") for w in warnings)
    assert "in 1,000 vectors (the first here)" in warnings[0] and "x.csv:2:" in warnings[0]
    assert (
        warnings[-1] == "cspace: warning: x.csv: and the ctrl of 4,980 more actuators MuJoCo clamps"
    )
    assert_no_command(result.run.stderr)
    assert_printable(result.run.stderr)
    assert result.cpu_seconds < 10, result


def _long_names(kind: str) -> str:
    """A hinge, a tendon on it and a motor, the actuator's or the tendon's name 300
    characters long (MuJoCo takes both)."""
    long = "n" * 300
    actuator, tendon = (long, "t") if kind == "actuator" else ("m", long)
    return (
        '<mujoco><worldbody><body name="b"><joint name="h"/><geom size=".1"/></body>'
        f'</worldbody><tendon><fixed name="{tendon}"><joint joint="h" coef="1"/></fixed>'
        f'</tendon>\n<actuator>\n<motor name="{actuator}" tendon="{tendon}"/>\n'
        "</actuator></mujoco>\n"
    )


@pytest.mark.parametrize("kind", ["actuator", "tendon"])
def test_a_name_a_report_cannot_hold_is_refused_by_inspect(tmp_path: Path, kind: str) -> None:
    """An actuator's name, or the tendon it drives, longer than a saved report holds:
    inspect refuses it in one line (as a joint's) rather than writing a report that diff
    and check --baseline then refuse as a bad report."""
    (tmp_path / "long.xml").write_text(_long_names(kind))
    run = run_cli("inspect", "long.xml", "--format", "json", cwd=tmp_path)
    assert run.code == 2 and run.stdout == "", run.stdout[:200]
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("cspace: error: long.xml:3:"), (
        run.stderr
    )
    assert run.stderr.rstrip().endswith("[name-too-long]"), run.stderr
