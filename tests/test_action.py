"""The GitHub Action (``action.yml``), run for real.

The Action's steps run as GitHub runs a composite action's: each ``run`` script in bash,
its ``env`` with ``${{ inputs.* }}`` and ``${{ github.action_path }}`` put in, and
``GITHUB_PATH``, ``GITHUB_OUTPUT``, ``GITHUB_STEP_SUMMARY`` and ``RUNNER_TEMP`` files of
a scratch run. The install step builds a venv and installs cspace from a clean copy of
this checkout (dependencies from pip's cache, as on a runner; pip byte-compiles nothing,
``PIP_COMPILE=false``, and Python compiles what each command imports once, as a runner
keeps what it compiles: no ``PYTHONDONTWRITEBYTECODE``). The check step then runs
on scratch git repositories: URDF, xacro, MJCF with a ``<mujocoinclude>`` fragment, a
``package.xml``; a broken file; a warning under ``strict``; ``paths`` of several lines,
and of names like options and patterns. The visual reports (the ``html`` input) are
written where a test reads them, and turned off elsewhere, since nothing else looks at
them. The pre-commit hook's test is ``test_pre_commit.py``.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import jsonschema
import pytest
import yaml
from test_ci_formats import COMMAND, SARIF_SCHEMA

from conftest import REPO, checkout_copy, environment_folder

ACTION: dict[str, Any] = yaml.safe_load((REPO / "action.yml").read_text())
EXPRESSION = re.compile(r"\$\{\{\s*([^}]*?)\s*\}\}")
BROKEN = '<robot name="b"><link name="a"/><joint name="j"/></robot>'
"""A URDF whose joint has no type (``missing-attribute``)."""
LOCKED = (
    '<robot name="l"><link name="a"/><link name="b"/><joint name="j" type="revolute">'
    '<parent link="a"/><child link="b"/><limit lower="0.5" upper="0.5" effort="1" '
    'velocity="1"/></joint></robot>'
)


def _env(step: dict[str, Any], inputs: dict[str, str], action_path: Path) -> dict[str, str]:
    """A step's ``env``, its expressions evaluated as GitHub does for these two contexts."""
    values = {f"inputs.{k}": v for k, v in inputs.items()} | {
        "github.action_path": str(action_path),
        "strategy.job-index": "3",  # the fourth job of a matrix
    }
    out = {}
    for key, value in step.get("env", {}).items():
        out[key] = EXPRESSION.sub(lambda m: values[m.group(1)], str(value))
    return out


def _defaults(**given: str) -> dict[str, str]:
    return {name: spec.get("default", "") for name, spec in ACTION["inputs"].items()} | given


class Runner:
    """A scratch GitHub runner: its files, PATH, and a way to run the Action's steps."""

    def __init__(self, root: Path, action_path: Path) -> None:
        self.root, self.action_path = root, action_path
        self.temp = root / "runner-temp"
        self.temp.mkdir(parents=True, exist_ok=True)
        self.files = {
            name: root / name.lower()
            for name in ("GITHUB_PATH", "GITHUB_OUTPUT", "GITHUB_STEP_SUMMARY")
        }
        for path in self.files.values():
            path.write_text("")

    def step(
        self, index: int, inputs: dict[str, str], cwd: Path
    ) -> subprocess.CompletedProcess[str]:
        step = ACTION["runs"]["steps"][index]
        assert step["shell"] == "bash" and not EXPRESSION.search(step["run"])  # env only
        added = [p for p in self.files["GITHUB_PATH"].read_text().splitlines() if p]
        env = {
            **os.environ,
            **{k: str(v) for k, v in self.files.items()},
            "RUNNER_TEMP": str(self.temp),
            "GITHUB_JOB": "check",
            "PATH": os.pathsep.join([*reversed(added), "/usr/bin", "/bin"]),
            **_env(step, inputs, self.action_path),
            "PIP_COMPILE": "false",
        }
        env.pop("VIRTUAL_ENV", None)
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        return subprocess.run(
            ["bash", "-e", "-c", step["run"]],
            cwd=cwd,
            env=env,
            capture_output=True,
            text=True,
            timeout=900,
            check=False,
        )


@pytest.fixture(scope="module")
def runner(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Runner]:
    """A runner on which the Action's install step ran, from a clean copy of the checkout
    (in memory where there is room: ``conftest.environment_folder``)."""
    with environment_folder(tmp_path_factory.mktemp("runner")) as root:
        action = checkout_copy(root / "action")
        run = Runner(root, action)
        python = shutil.which("python3.11") or "python3"
        done = run.step(0, _defaults(python=python), cwd=root)
        assert done.returncode == 0, done.stdout + done.stderr
        assert (run.temp / "cspace-venv" / "bin" / "cspace").exists()
        yield run


def _repository(root: Path) -> Path:
    repo = root / "repo"
    shutil.copytree(REPO / "robots" / "xacro_demo", repo / "xacro_demo")
    shutil.copytree(REPO / "robots" / "mjcf_mujocoinclude", repo / "mjcf")
    shutil.copy(REPO / "robots" / "arm7.urdf", repo / "arm7.urdf")
    (repo / "package.xml").write_text("<package><name>scratch</name></package>")
    subprocess.run(["git", "init", "-q"], cwd=repo, check=True)
    subprocess.run(["git", "add", "."], cwd=repo, check=True)
    return repo


def _check(runner: Runner, repo: Path, **inputs: str) -> subprocess.CompletedProcess[str]:
    for name, path in runner.files.items():
        if name != "GITHUB_PATH":  # the install step's, kept
            path.write_text("")
    return runner.step(1, _defaults(**inputs), cwd=repo)


def test_the_action_checks_a_repository_and_annotates_its_files(
    runner: Runner, tmp_path: Path
) -> None:
    repo = _repository(tmp_path)
    done = _check(runner, repo, sarif="cspace.sarif")
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    assert lines and all(COMMAND.fullmatch(line) for line in lines), done.stdout
    notices = sorted(line.split(",")[0] for line in lines if ",title=cspace::C = " in line)
    assert notices == [
        "::notice file=arm7.urdf",
        "::notice file=mjcf/scene.xml",
        "::notice file=xacro_demo/urdf/arm.urdf.xacro",
    ]
    summary = runner.files["GITHUB_STEP_SUMMARY"].read_text()
    assert summary.startswith("### cspace: robot files") and "`mjcf/scene.xml`" in summary
    said = dict(
        line.split("=", 1) for line in runner.files["GITHUB_OUTPUT"].read_text().splitlines()
    )
    pages = Path(said.pop("html"))
    assert pages.parent == runner.temp and pages.name.startswith("cspace-html.")
    assert said == {"sarif": "cspace.sarif", "html-name": "cspace-report-check-3"}
    log = json.loads((repo / "cspace.sarif").read_text())
    jsonschema.Draft4Validator(SARIF_SCHEMA).validate(log)
    # The artifact: a page per robot, and an index linking each.
    index = (pages / "index.html").read_text()
    linked = re.findall(r'<a href="([^"]+)">([^<]+)</a>', index)
    assert [robot for _, robot in linked] == [
        "arm7.urdf",
        "mjcf/scene.xml",
        "xacro_demo/urdf/arm.urdf.xacro",
    ]
    for page, robot in linked:
        assert f"{robot} (" in (pages / page).read_text()  # the page's source line
    upload = ACTION["runs"]["steps"][2]
    assert upload["uses"] == "actions/upload-artifact@v4"
    assert upload["with"] == {
        "name": "${{ steps.check.outputs.html-name }}",
        "path": "${{ steps.check.outputs.html }}",
    }
    assert "!cancelled()" in upload["if"]  # uploaded when the check fails too


def test_the_action_fails_on_a_broken_file_with_an_error_on_it(
    runner: Runner, tmp_path: Path
) -> None:
    repo = _repository(tmp_path)
    (repo / "broken.urdf").write_text('<robot name="b"><link name="a"/><joint name="j"/></robot>')
    done = _check(runner, repo, html="")
    assert done.returncode == 2
    errors = [line for line in done.stdout.splitlines() if line.startswith("::error ")]
    assert len(errors) == 1 and errors[0].startswith("::error file=broken.urdf,line=1,")


@pytest.mark.parametrize(("strict", "code"), [("false", 0), ("true", 1)])
def test_strict_fails_the_action_on_a_warning(
    runner: Runner, tmp_path: Path, strict: str, code: int
) -> None:
    repo = _repository(tmp_path)
    (repo / "locked.urdf").write_text(LOCKED)
    done = _check(runner, repo, strict=strict, paths="locked.urdf arm7.urdf", html="")
    assert done.returncode == code, done.stdout + done.stderr
    assert "::warning file=locked.urdf,line=1,title=cspace joint-locked::" in done.stdout


def test_a_path_that_looks_like_an_option_is_a_path(runner: Runner, tmp_path: Path) -> None:
    repo = _repository(tmp_path)
    shutil.copy(repo / "arm7.urdf", repo / "--help.urdf")
    done = _check(runner, repo, paths="--help.urdf", html="")
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith("::notice file=--help.urdf,title=cspace::C = R^6")


def test_every_path_of_several_lines_is_checked_and_none_is_a_pattern(
    runner: Runner, tmp_path: Path
) -> None:
    repo = _repository(tmp_path)
    for folder in ("robots", "more"):
        (repo / folder).mkdir()
    shutil.copy(repo / "arm7.urdf", repo / "robots" / "x.urdf")
    for name in ("more/broken.urdf", "robots/[x].urdf", "--allow-dir=y.urdf"):
        (repo / name).write_text(BROKEN)
    done = _check(runner, repo, paths="robots\nmore\n", html="")
    assert done.returncode == 2
    annotated = sorted(line.split(",")[0] for line in done.stdout.splitlines())
    assert annotated == [
        "::error file=more/broken.urdf",
        "::error file=robots/[x].urdf",
        "::notice file=robots/x.urdf",
    ]
    # Names like an option and a pattern: those files, not robots/x.urdf the pattern matches.
    done = _check(runner, repo, paths="  --allow-dir=y.urdf\n\trobots/[x].urdf ", html="")
    assert done.returncode == 2
    annotated = sorted(line.split(",")[0] for line in done.stdout.splitlines())
    assert annotated == ["::error file=--allow-dir=y.urdf", "::error file=robots/[x].urdf"]
    done = _check(runner, repo / "more", paths=" \n ", html="")  # none given: the folder
    assert done.stdout.startswith("::error file=broken.urdf,"), done.stdout


def test_an_old_python_is_named_in_one_error(tmp_path: Path) -> None:
    fake = tmp_path / "python3.8"
    fake.write_text('#!/bin/sh\nexec python3 -c "import sys; sys.exit(1)"\n')
    fake.chmod(0o755)
    done = Runner(tmp_path, REPO).step(0, _defaults(python=str(fake)), cwd=tmp_path)
    assert done.returncode == 1
    assert done.stdout.startswith("::error title=cspace::cspace needs Python 3.11 or later")


def test_the_baseline_accepts_what_was_agreed_and_fails_on_the_rest(
    runner: Runner, tmp_path: Path
) -> None:
    """Pull requests against the committed baseline, as a reviewer sees them.

    A limit changed in a URDF and a joint added to a xacro fail, each as an error on the
    line (or file) that differs; a file only renamed passes as moved; writing the
    baseline again in the pull request accepts the rest. A line naming a file outside
    the checkout is a warning on that line, the file unread; a second line for a file
    under another spelling, with a changed report, fails the step.
    """
    repo = _repository(tmp_path)
    secret = "TOKEN-ghp-4ct10n"
    (tmp_path / "outside").mkdir()
    arm7 = (repo / "arm7.urdf").read_text()
    (tmp_path / "outside" / "secret.urdf").write_text(arm7.replace("elbow", secret))
    cspace_bin = runner.temp / "cspace-venv" / "bin" / "cspace"

    def write_baseline() -> None:
        done = subprocess.run(
            [str(cspace_bin), "inspect", "--format", "jsonl", "."],
            cwd=repo,
            capture_output=True,
            text=True,
            check=False,
        )
        (repo / "cspace-baseline.jsonl").write_text(done.stdout)

    write_baseline()
    baseline = repo / "cspace-baseline.jsonl"
    lines = baseline.read_text().splitlines()
    accepted = next(line for line in lines if '"path": "arm7.urdf"' in line)
    stray = accepted.replace('"path": "arm7.urdf"', '"path": "../outside/secret.urdf"')
    baseline.write_text("\n".join([*lines, stray]) + "\n")
    (repo / "mjcf" / "scene.xml").rename(repo / "mjcf" / "stage.xml")  # only renamed
    done = _check(runner, repo, baseline="cspace-baseline.jsonl", html="")
    assert done.returncode == 0, done.stdout + done.stderr
    assert (
        f"::warning file=cspace-baseline.jsonl,line={len(lines) + 1},title=cspace baseline%3A "
        "outside::../outside/secret.urdf: in the baseline, but outside the folders checked: "
        "not read (remove the line, or check its folder)"
    ) in done.stdout.splitlines()
    summary = runner.files["GITHUB_STEP_SUMMARY"].read_text()
    assert "| `../outside/secret.urdf` | outside |" in summary
    assert secret not in done.stdout + done.stderr + summary
    assert "| `mjcf/stage.xml` | moved | from mjcf/scene.xml, the same R^3 |" in summary
    changed = accepted.replace('"path": "arm7.urdf"', '"path": "./arm7.urdf"').replace("2.9", "2.5")
    baseline.write_text("\n".join([*lines, changed]) + "\n")
    done = _check(runner, repo, baseline="cspace-baseline.jsonl", html="")
    assert (
        done.returncode == 2
        and (
            f"a second report of 'arm7.urdf' as './arm7.urdf' (the first at "
            f"cspace-baseline.jsonl:{lines.index(accepted) + 1})"
        )
        in done.stderr
    ), done.stderr
    baseline.write_text("\n".join(lines) + "\n")  # as written, before the rename
    arm = repo / "arm7.urdf"
    arm.write_text(arm.read_text().replace('upper="2.9"', 'upper="2.5"', 1))
    xacro = repo / "xacro_demo" / "urdf" / "arm.urdf.xacro"
    tool = '<xacro:segment name="tool" parent="wrist_link" type="prismatic"/>\n</robot>'
    xacro.write_text(xacro.read_text().replace("</robot>", tool))
    done = _check(runner, repo, baseline="cspace-baseline.jsonl", html="")
    assert done.returncode == 1
    errors = [line for line in done.stdout.splitlines() if "title=cspace baseline" in line]
    assert all(COMMAND.fullmatch(line) for line in errors), errors
    assert (
        "::error file=arm7.urdf,line=23,title=cspace baseline%3A limits::shoulder_pan: "
        "[-2.9, 2.9] rad in the baseline, [-2.9, 2.5] rad now "
        "(write the baseline again to accept it)"
    ) in errors
    added = "::error file=xacro_demo/urdf/arm.urdf.xacro,title=cspace baseline%3A joint added::"
    assert any(
        line.startswith(added + "tool: prismatic (R^1), not in the baseline") for line in errors
    )
    summary = runner.files["GITHUB_STEP_SUMMARY"].read_text()
    assert "### cspace: against the baseline" in summary
    assert "| `arm7.urdf` | differs | R^6 × S^1, but limits differ |" in summary
    assert "| `xacro_demo/urdf/arm.urdf.xacro` | changed | `R^4 -> R^5: C-space," in summary
    write_baseline()  # the changes accepted, in the same pull request
    assert _check(runner, repo, baseline="cspace-baseline.jsonl", html="").returncode == 0


def test_the_action_checks_usd_robots(runner: Runner, tmp_path: Path) -> None:
    """The Action installs OpenUSD: a USD robot whatever its name is checked, its finding
    an annotation on its file, failing a strict run (named other than .usd*, an error)."""
    repo = _repository(tmp_path)
    usd = (REPO / "docs" / "examples" / "usd_joints.usda").read_text()
    (repo / "robots" / "Arm.USDA").parent.mkdir()
    (repo / "robots" / "Arm.USDA").write_text(usd.replace("lowerLimit = -90", "lowerLimit = 45", 1))
    done = _check(runner, repo, strict="true", html="")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "USD files left out" not in done.stderr
    assert "::warning file=robots/Arm.USDA," in done.stdout and "joint-locked" in done.stdout


def _moveit_repository(root: Path) -> Path:
    """A MoveIt repository's layout: a description package, and a configuration package
    whose xacro includes the description by ``$(find)`` and whose SRDF names the robot."""
    repo = root / "moveit-repo"
    description, config = repo / "arm_description", repo / "arm_moveit_config"
    (description / "urdf").mkdir(parents=True)
    (config / "config").mkdir(parents=True)
    (description / "package.xml").write_text("<package><name>arm_description</name></package>")
    (config / "package.xml").write_text("<package><name>arm_moveit_config</name></package>")
    shutil.copy(REPO / "robots" / "arm7.urdf", description / "urdf" / "arm7.urdf")
    (config / "config" / "arm.urdf.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm7">'
        '<xacro:include filename="$(find arm_description)/urdf/arm7.urdf"/></robot>'
    )
    (config / "config" / "arm7.srdf").write_text(
        '<robot name="arm7"><group name="arm"><joint name="elbow"/></group></robot>'
    )
    subprocess.run(["git", "init", "-q"], cwd=repo, check=True)
    subprocess.run(["git", "add", "."], cwd=repo, check=True)
    return repo


@pytest.mark.parametrize(("packages", "code"), [("", 2), (".", 0)])
def test_a_moveit_repository_passes_with_its_package_paths(
    runner: Runner, tmp_path: Path, packages: str, code: int
) -> None:
    """The configuration package's xacro finds the description package only through
    ``package-paths``; the SRDF is a companion, never an error."""
    repo = _moveit_repository(tmp_path)
    done = _check(runner, repo, **{"package-paths": packages, "html": ""})
    assert done.returncode == code, done.stdout + done.stderr
    assert "no-links" not in done.stdout + done.stderr
    if code == 0:
        assert "::notice file=arm_moveit_config/config/arm.urdf.xacro," in done.stdout
    else:
        assert "$(find arm_description): no such package" in done.stdout
