"""The GitHub Actions workflow in the documentation (docs/ci.md), run as GitHub would run its steps.

The workflow is read from docs/ci.md (never copied here): each ``run:`` step goes
through ``bash -eo pipefail`` in a scratch clone whose pull-request branch differs from
``origin/main`` in one way per scenario, with ``${{ github.base_ref }}`` set to main.
``uses:`` steps (checkout, Python, artifact upload) are GitHub's own. The install step
runs in its own test, with a ``git+file:`` URL of the commit under test and pip's
``--no-deps --target`` so that the test's environment is left alone; the other steps use
the cspace this test runs with, forked by the suite's command server: the ``cspace``
the steps' shell finds first on its ``PATH`` is ``served_cli``'s, which hands each
command, its folder, environment and streams to a process forked from one that has
imported cspace and leaves with its exit status. The shell, git, xargs, the
redirections and the exit statuses all run for real; only the interpreter start-up of
each command (about 0.25 s of CPU, some 40 commands) is skipped.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import served_cli
import yaml

from conftest import REPO, ROBOTS

BROKEN = '<robot name="b"><link name="a"/><joint name="j"/></robot>'
"""A URDF whose joint has no type (``missing-attribute``)."""
EXPRESSIONS = {"${{ github.base_ref }}": "main", "${{ vars.CSPACE }}": "(set by the test)"}
TEACHING_FILES = (
    "arm7.urdf",
    "mjcf_every_joint.xml",
    "sdf_every_joint.sdf",
    "xacro_demo",
)


def workflow() -> dict[str, Any]:
    blocks = re.findall(r"```yaml\n(.*?)```", (REPO / "docs" / "ci.md").read_text(), re.S)
    assert len(blocks) == 1
    document: dict[str, Any] = yaml.safe_load(blocks[0])
    return document


def steps() -> list[dict[str, Any]]:
    jobs = workflow()["jobs"]
    assert len(jobs) == 1
    return list(next(iter(jobs.values()))["steps"])


def git(cwd: Path, *args: str) -> str:
    done = subprocess.run(
        ["git", *args], cwd=cwd, capture_output=True, text=True, check=True, env=_git_env()
    )
    return done.stdout


def _git_env() -> dict[str, str]:
    return {
        **os.environ,
        "GIT_AUTHOR_NAME": "t",
        "GIT_AUTHOR_EMAIL": "t@example.org",
        "GIT_COMMITTER_NAME": "t",
        "GIT_COMMITTER_EMAIL": "t@example.org",
    }


def scratch_pull_request(
    tmp_path: Path, change: Callable[[Path], None], base: Callable[[Path], None] | None = None
) -> Path:
    """origin (main: the teaching robots, and ``base`` made) and a clone on a branch with
    ``change`` made."""
    origin = tmp_path / "origin"
    (origin / "robots").mkdir(parents=True)
    for name in TEACHING_FILES:
        source = ROBOTS / name
        target = origin / "robots" / name
        if source.is_dir():
            shutil.copytree(source, target)
        else:
            shutil.copy(source, target)
    if base is not None:
        base(origin)
    git(origin, "init", "-q", "-b", "main")
    git(origin, "add", ".")
    git(origin, "commit", "-q", "-m", "robots")
    clone = tmp_path / "work"
    git(tmp_path, "clone", "-q", str(origin), str(clone))
    git(clone, "checkout", "-q", "-b", "feature")
    change(clone)
    git(clone, "add", "-A")
    git(clone, "commit", "-q", "--allow-empty", "-m", "change")
    return clone


def run_workflow(clone: Path) -> tuple[str | None, int, str]:
    """Run the steps in order; return the failing step's name (or None), its code, its output.

    The steps' ``cspace`` is the served one (``served_cli``), the first on ``PATH``.
    """
    served = served_cli.script().parent
    path = os.pathsep.join([str(served), str(Path(sys.executable).parent), os.environ["PATH"]])
    env = {**os.environ, "PATH": path, "NO_COLOR": "1"}
    output = ""
    failed: tuple[str, int] | None = None
    for step in steps():
        if "uses" in step or (failed is not None and step.get("if") != "always()"):
            continue
        script = step["run"]
        if step.get("name") == "Install cspace":
            continue
        step_env = {k: _expand(str(v)) for k, v in step.get("env", {}).items()}
        done = subprocess.run(
            ["bash", "--noprofile", "--norc", "-eo", "pipefail", "-c", _expand(script)],
            cwd=clone,
            env={**env, **step_env},
            capture_output=True,
            text=True,
            timeout=300,
            check=False,
        )
        output += done.stdout + done.stderr
        if done.returncode != 0 and failed is None:
            failed = str(step.get("name")), done.returncode
    return (failed[0], failed[1], output) if failed else (None, 0, output)


def _expand(text: str) -> str:
    for expression, value in EXPRESSIONS.items():
        text = text.replace(expression, value)
    assert "${{" not in text, f"unknown GitHub expression in {text!r}"
    return text


def test_the_workflow_is_valid_yaml_with_a_pull_request_trigger() -> None:
    document = workflow()
    assert "pull_request" in document[True]  # YAML reads the key `on` as True
    names = [s.get("name") for s in steps() if "run" in s]
    assert names[0] == "Install cspace"
    assert any("uses" in s and s["uses"].startswith("actions/checkout") for s in steps())


def test_the_install_step_installs_cspace_from_a_git_url_pinned_at_a_commit(
    tmp_path: Path,
) -> None:
    (install,) = [s for s in steps() if s.get("name") == "Install cspace"]
    assert install["env"]["CSPACE"] == "${{ vars.CSPACE }}"
    commit = git(REPO, "rev-parse", "HEAD").strip()
    target = tmp_path / "site"
    # The step's own line, with pip kept out of this environment.
    shim = f'pip() {{ "{sys.executable}" -m pip "$@" --no-deps --quiet --target "{target}"; }}\n'
    done = subprocess.run(
        ["bash", "--noprofile", "--norc", "-eo", "pipefail", "-c", shim + install["run"]],
        cwd=tmp_path,
        env={**os.environ, "CSPACE": f"git+file://{REPO}@{commit}"},
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert (target / "cspace" / "py.typed").is_file()
    assert (target / "cspace" / "_cli" / "main.py").is_file()
    assert (target / "bin" / "cspace").is_file()
    (record,) = target.glob("cspace-*.dist-info/direct_url.json")
    assert commit in record.read_text()


def test_a_pull_request_that_keeps_the_c_space_passes(tmp_path: Path) -> None:
    def add_a_robot_and_a_comment(clone: Path) -> None:
        shutil.copy(ROBOTS / "mjcf_radian_autolimits.xml", clone / "robots" / "new.xml")
        arm = clone / "robots" / "arm7.urdf"
        arm.write_text(arm.read_text().replace("<robot", "<!-- reviewed -->\n<robot", 1))

    clone = scratch_pull_request(tmp_path, add_a_robot_and_a_comment)
    failed, code, output = run_workflow(clone)
    assert (failed, code) == (None, 0), output
    listed = (clone / "robot-files").read_text().split("\0")[:-1]
    assert sorted(listed) == [
        "robots/arm7.urdf",
        "robots/mjcf_every_joint.xml",
        "robots/new.xml",
        "robots/sdf_every_joint.sdf",
        "robots/xacro_demo/urdf/arm.urdf.xacro",
    ]
    reports = (clone / "cspace-reports.jsonl").read_text().splitlines()
    assert len(reports) == 5
    diff = (clone / "cspace-diff.md").read_text()
    assert diff.count("### cspace: no C-space change") == 4  # the new file has no old side


def test_a_pull_request_that_changes_the_c_space_fails_with_the_diff(tmp_path: Path) -> None:
    def free_the_elbow(clone: Path) -> None:
        arm = clone / "robots" / "arm7.urdf"
        text = arm.read_text()
        start = text.index('<joint name="elbow" type="revolute"')
        end = text.index("</joint>", start)
        elbow = text[start:end].replace('type="revolute"', 'type="continuous"')
        elbow = re.sub(r"<limit [^>]*/>", "", elbow)
        arm.write_text(text[:start] + elbow + text[end:])

    clone = scratch_pull_request(tmp_path, free_the_elbow)
    failed, code, output = run_workflow(clone)
    assert failed == "Diff each C-space against the base branch (fails on a change)", output
    assert code == 1
    diff = (clone / "cspace-diff.md").read_text()
    assert "### cspace: C-space changed in `robots/arm7.urdf`" in diff
    assert "| joint retyped | `elbow` | revolute (R^1) | continuous (S^1) |" in diff
    assert diff.count("### cspace: no C-space change") == 3


def test_a_strict_finding_fails_the_inspect_step(tmp_path: Path) -> None:
    def lock_a_joint(clone: Path) -> None:
        (clone / "robots" / "locked.urdf").write_text(
            '<robot name="locked"><link name="a"/><link name="b"/>'
            '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
            '<axis xyz="0 0 1"/><limit lower="0.3" upper="0.3" effort="1" velocity="1"/>'
            "</joint></robot>"
        )

    clone = scratch_pull_request(tmp_path, lock_a_joint)
    failed, code, output = run_workflow(clone)
    assert failed == "Inspect every robot file (fails on a strict finding)"
    assert code == 1
    assert "joint-locked" in (clone / "cspace-reports.jsonl").read_text()
    assert "robots/locked.urdf" in output and "findings" in output


@pytest.mark.parametrize("expression", sorted(EXPRESSIONS))
def test_every_github_expression_the_workflow_uses_is_known(expression: str) -> None:
    used = set(re.findall(r"\$\{\{[^}]*\}\}", yaml.safe_dump(workflow())))
    assert used <= set(EXPRESSIONS)
    assert expression in used


def test_a_file_without_a_report_is_named_and_no_name_is_a_workflow_command(
    tmp_path: Path,
) -> None:
    """A file without a report is named in the Markdown, with its error, and each problem
    is printed once. A committed name may hold line breaks: split at them, ``robots/
    arm7.urdf⏎robots/sdf_every_joint.sdf`` was two good files and its broken robot was
    never read. And once it is one name, a name like ``b.urdf⏎::error title=forged::⏎
    ##[warning]...`` must not reach the log as written: the steps print no name, and
    cspace escapes its own."""
    forged = "robots/b.urdf\n::error title=forged::B\n##[warning]x.urdf"
    hidden = "robots/arm7.urdf\nrobots/sdf_every_joint.sdf"

    def add_a_robot(origin: Path) -> None:
        shutil.copy(ROBOTS / "arm7.urdf", origin / forged)

    def break_them(clone: Path) -> None:
        path = clone / "robots" / "arm7.urdf"
        path.write_text(path.read_text()[:400])  # the XML ends early
        (clone / forged).write_text(BROKEN)
        (clone / hidden).parent.mkdir()  # a folder "robots/arm7.urdf⏎robots"
        (clone / hidden).write_text(BROKEN)

    clone = scratch_pull_request(tmp_path, break_them, base=add_a_robot)
    failed, code, output = run_workflow(clone)
    assert (failed, code) == ("Inspect every robot file (fails on a strict finding)", 1), output
    summary = (clone / "cspace-summary.md").read_text()
    assert "| `robots/arm7.urdf` | - | - | - | - | - | - | no report |" in summary
    diff = (clone / "cspace-diff.md").read_text()  # the diff step ran all the same
    assert "### cspace: no C-space for a file (named below)" in diff
    assert "    cspace: error: robots/arm7.urdf:" in diff
    assert "the XML ends before the document is complete" in diff
    inspect_log = output.split("### cspace")[0]  # the inspect step's own output
    assert inspect_log.count("the XML ends before the document is complete") == 1
    listed = (clone / "robot-files").read_text().split("\0")[:-1]
    assert forged in listed and hidden in listed and len(listed) == 6
    shown = hidden.replace("\n", "\\n")  # as cspace writes it
    assert inspect_log.count(f"cspace: error: {shown}:1: joint 'j'") == 1  # read, once
    assert "    cspace: error: robots/b.urdf\\n::error title=forged::B\\n##\\x5bwarning]" in diff
    for line in output.splitlines():
        assert not line.lstrip().startswith("::") and "##[" not in line, line


def test_a_usd_robot_is_listed_and_checked(tmp_path: Path) -> None:
    """The workflow installs OpenUSD: a USD robot a pull request adds is inspected, and its
    finding fails the run as a URDF's would."""
    usd = (REPO / "docs" / "examples" / "usd_joints.usda").read_text()

    def add_a_locked_usd_robot(clone: Path) -> None:
        locked = usd.replace("physics:lowerLimit = -90", "physics:lowerLimit = 45", 1)
        (clone / "robots" / "Arm.USDA").write_text(locked)

    clone = scratch_pull_request(tmp_path, add_a_locked_usd_robot)
    failed, code, output = run_workflow(clone)
    assert (failed, code) == ("Inspect every robot file (fails on a strict finding)", 1), output
    assert "robots/Arm.USDA" in (clone / "robot-files").read_text().split("\0")
    reports = [
        json.loads(line) for line in (clone / "cspace-reports.jsonl").read_text().splitlines()
    ]
    (arm,) = [r for r in reports if r["source"]["path"].endswith("Arm.USDA")]
    assert "joint-locked" in {d["code"] for d in arm["diagnostics"]}
