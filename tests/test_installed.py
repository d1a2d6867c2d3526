"""What a user installs is what the tests run.

The sdist is built, and the wheel from the sdist (``python -m build``, as a packager
does); the wheel is installed into a fresh virtual environment outside the source tree
(made without a pip of its own: this interpreter's pip installs into it, resolving the
wheel's dependencies from pip's cache, nothing editable; pip byte-compiles nothing,
Python compiles what the command imports when it first runs; in memory where there is
room, ``conftest.environment_folder``), and there the command is run as a user runs it:
``--version``, ``inspect`` of every bundled robot in every format (each answer the same
bytes as the development install's), and every subcommand once. A wheel missing a module
or a data file fails here.
"""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

import cspace

from conftest import REPO, ROBOTS, Run, checkout_copy, environment_folder, run_cli

FORMATS = ("text", "json", "jsonl", "markdown", "html", "svg")

BUNDLED = sorted(
    [
        *ROBOTS.glob("*.urdf"),
        *ROBOTS.glob("*.xml"),
        *ROBOTS.glob("*.sdf"),
        ROBOTS / "mjcf_include" / "scene.xml",
        ROBOTS / "mjcf_mujocoinclude" / "scene.xml",
        ROBOTS / "mjcf_attach" / "arm.xml",
        ROBOTS / "xacro_demo" / "urdf" / "arm.urdf.xacro",
    ]
)
"""Every robot the repository ships, as a user would name it."""


class Installed:
    """A fresh virtual environment with the wheel installed, outside the source tree."""

    def __init__(self, root: Path, wheel: Path) -> None:
        self.root, self.wheel = root, wheel
        self.venv = root / "venv"
        self.home = root / "home"  # where the user runs it: nothing of the source here
        self.home.mkdir()

    def run(self, *args: str) -> subprocess.CompletedProcess[str]:
        # as in a user's shell, Python keeps what it compiles (PYTHONDONTWRITEBYTECODE unset)
        unset = ("PYTHONPATH", "VIRTUAL_ENV", "PYTHONDONTWRITEBYTECODE")
        env = {k: v for k, v in os.environ.items() if k not in unset}
        return subprocess.run(
            [str(self.venv / "bin" / "cspace"), *args],
            cwd=self.home,
            capture_output=True,
            text=True,
            env={**env, "NO_COLOR": "1"},
            timeout=120,
            check=False,
        )


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Installed]:
    dist = tmp_path_factory.mktemp("dist")
    tree = checkout_copy(tmp_path_factory.mktemp("checkout"))  # no build/ output in it
    subprocess.run(
        [sys.executable, "-m", "build", "--outdir", str(dist), str(tree)],
        capture_output=True,
        timeout=600,
        check=True,
    )
    (wheel,) = dist.glob("cspace-*.whl")
    with environment_folder(tmp_path_factory.mktemp("user")) as root:
        user = Installed(root, wheel)
        # no pip of its own (ensurepip would install and byte-compile one): this
        # interpreter's pip installs into it (``--python``)
        subprocess.run(
            [sys.executable, "-m", "venv", "--without-pip", str(user.venv)],
            check=True,
            timeout=120,
        )
        done = _pip_install(user.venv / "bin" / "python", str(wheel))
        assert done.returncode == 0, done.stderr
        yield user


def _pip_install(python: Path, *requirements: str) -> subprocess.CompletedProcess[str]:
    """pip's install (resolving the dependencies) into ``python``'s environment,
    byte-compiling nothing (half its CPU time: Python compiles each module a command
    imports, once, when it runs)."""
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "--python",
            str(python),
            "install",
            "-q",
            "--no-compile",
            *requirements,
        ],
        capture_output=True,
        text=True,
        timeout=900,
        check=False,
    )


def test_the_installed_command_is_the_wheels(installed: Installed) -> None:
    version = installed.run("--version")
    assert (version.returncode, version.stdout) == (0, f"cspace {cspace.__version__}\n")
    where = subprocess.run(
        [str(installed.venv / "bin" / "python"), "-c", "import cspace; print(cspace.__file__)"],
        cwd=installed.home,
        capture_output=True,
        text=True,
        check=True,
    )
    assert where.stdout.startswith(str(installed.venv)), where.stdout
    # OpenUSD is an extra: without it, a USD file gets one line that says how to add it
    usd = installed.run("inspect", str(REPO / "docs" / "examples" / "usd_joints.usda"))
    assert usd.returncode == 2 and "pip install 'cspace[usd]'" in usd.stderr, usd.stderr
    assert usd.stderr.count("\n") == 1
    # and a folder's USD files are left out, said once, while its URDF is read
    from test_discover import _usd_folder

    folder = installed.home / "mixed"
    folder.mkdir()
    _usd_folder(folder)
    mixed = installed.run("inspect", str(folder))
    assert mixed.returncode == 0 and "arm.urdf" in mixed.stdout, mixed.stdout + mixed.stderr
    assert "USD files left out, as OpenUSD is not installed" in mixed.stderr


def test_the_sdist_builds_the_wheel_the_tree_builds(
    installed: Installed, tree_wheel: tuple[Path, str]
) -> None:
    from_tree, _ = tree_wheel
    names = set(zipfile.ZipFile(installed.wheel).namelist())
    assert names == set(zipfile.ZipFile(from_tree).namelist())


def _both(installed: Installed, *args: str) -> tuple[subprocess.CompletedProcess[str], Run]:
    """The same command from the wheel and from the development install."""
    return installed.run(*args), run_cli(*args)


def test_every_bundled_robot_as_the_development_install_says(installed: Installed) -> None:
    """Every robot's whole report (JSON Lines, one process each side)."""
    user, ours = _both(installed, "inspect", *map(str, BUNDLED), "--format", "jsonl")
    assert user.returncode in (0, 1), user.stderr
    assert (user.returncode, user.stdout) == (ours.code, ours.stdout)
    assert user.stdout.count("\n") == len(BUNDLED)


@pytest.mark.parametrize("robot", ["arm7.urdf", "mjcf_every_joint.xml", "sdf_every_joint.sdf"])
def test_every_format_as_the_development_install_says(installed: Installed, robot: str) -> None:
    """Each renderer from the wheel, on a robot of each format the wheel reads itself."""
    with ThreadPoolExecutor(2) as pool:
        runs = pool.map(
            lambda f: _both(installed, "inspect", str(ROBOTS / robot), "--format", f), FORMATS
        )
        for fmt, (user, ours) in zip(FORMATS, runs, strict=True):
            assert user.returncode in (0, 1), (fmt, user.stderr)
            assert (user.returncode, user.stdout) == (ours.code, ours.stdout), fmt


SUBCOMMANDS = {
    "inspect": ("inspect", "ARM", "MJCF"),
    "diff": ("diff", "ARM", "ARM"),
    "check": ("check", "ARM", "--dimension", "7"),
    "schema": ("schema",),
    "sample": ("sample", "ARM", "-n", "3", "--format", "csv", "-o", "samples.csv"),
    "distance": ("distance", "ARM", "{}", '{"elbow": -0.5}', "--partial"),
    "interpolate": ("interpolate", "ARM", "{}", '{"elbow": -0.5}', "--partial"),
    "collisions": ("collisions", "ARM", "-n", "10"),
    "convert": ("convert", "ARM", "samples.csv", "--from", "canonical", "--to", "pinocchio"),
    "unwrap": ("unwrap", "ARM", "samples.csv"),
    "completion": ("completion", "bash"),
}
"""Every subcommand, once, in an order where each finds what it needs (samples.csv);
ARM and MJCF stand for bundled robots."""


def test_every_subcommand_runs_from_the_wheel(installed: Installed) -> None:
    from cspace._cli.main import COMMANDS

    assert set(COMMANDS) == set(SUBCOMMANDS)
    where = {"ARM": str(ROBOTS / "arm7.urdf"), "MJCF": str(ROBOTS / "mjcf_balls.xml")}
    for name, template in SUBCOMMANDS.items():
        args = [where.get(a, a) for a in template]
        run = installed.run(*args)
        assert run.returncode == 0, (name, run.stderr)
        assert run.stdout or name == "sample", name
    assert (installed.home / "samples.csv").read_text().count("\n") == 4


def test_both_schemas_come_with_the_wheel(installed: Installed) -> None:
    for args in (("schema",), ("schema", "--collisions")):
        user, ours = _both(installed, *args)
        assert (user.returncode, user.stdout) == (0, ours.stdout), (args, user.stderr)


def test_every_documentation_example_runs_in_the_wheels_environment(installed: Installed) -> None:
    # the same Sybil run as the suite's (conftest.py), each example in the fresh
    # environment: Python blocks by its interpreter, console blocks with its cspace
    python = installed.venv / "bin" / "python"
    dask = _pip_install(python, "distributed", "usd-core>=24.8")  # as the examples tell
    assert dask.returncode == 0, dask.stderr
    # as in a user's shell, the environment's Python keeps what it compiles (the runner's
    # own, -B, writes nothing into the development environment)
    unset = ("PYTHONPATH", "VIRTUAL_ENV", "PYTHONDONTWRITEBYTECODE")
    env = {k: v for k, v in os.environ.items() if k not in unset}
    done = subprocess.run(
        [
            sys.executable,
            "-B",
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "-p",
            "no:xdist",
            "-o",
            "addopts=",
            "README.md",
            "docs",
        ],
        cwd=REPO,
        env={**env, "CSPACE_DOCS_PYTHON": str(python)},
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stdout[-3000:]
    passed = int(done.stdout.strip().splitlines()[-1].split(" passed")[0].split()[-1])
    assert passed >= 16, done.stdout[-500:]  # every example ran, none was skipped
    assert "skipped" not in done.stdout.splitlines()[-1]
