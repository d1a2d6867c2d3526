"""Shared test helpers: where things are, and running the `cspace` command as a user does."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import inotify_simple
import pytest
from hypothesis import settings

from cspace._manifold import NormalForm

import forked_cli

# Every property test tries the same examples on every run and every machine: a failure
# in CI is reproducible, and no test passes or fails by the luck of the draw.
settings.register_profile("cspace", derandomize=True, database=None, deadline=None)
settings.load_profile("cspace")

REPO = Path(__file__).resolve().parent.parent

# pytest-xdist sets COLUMNS=80 in its workers; cspace honours COLUMNS in a pipe, so the
# commands the tests run must not inherit the runner's width (a test that wants one sets it)
os.environ.pop("COLUMNS", None)
ROBOTS = REPO / "robots"


@dataclass(frozen=True)
class Run:
    """What one run of the `cspace` command did."""

    code: int
    stdout: str
    stderr: str


def cspace_command() -> list[str]:
    """The installed `cspace` script next to this interpreter (the one a user runs)."""
    script = Path(sys.executable).with_name("cspace")
    if script.exists():
        return [str(script)]
    found = shutil.which("cspace")
    if found is None:
        raise RuntimeError("the cspace command is not installed (run `make test`)")
    return [found]


def command_env(env: dict[str, str] | None = None) -> dict[str, str]:
    """The environment the suite runs `cspace` in: this process's, colour off, ``env``."""
    return {**os.environ, "NO_COLOR": "1", **(env or {})}


HASH_SEED = ({"PYTHONHASHSEED": "1"}, {"PYTHONHASHSEED": "2"})
"""Environments of two interpreters whose string hashes differ: a test that compares two
runs' bytes gives them these (forked commands share their server's hash seed)."""


def run_cli(
    *args: str,
    cwd: Path = REPO,
    stdin: bytes | None = None,
    timeout: float = 60,
    env: dict[str, str] | None = None,
    fresh: bool = False,
) -> Run:
    """Run `cspace ARGS...` in a new process and capture its exit code and output.

    The process is forked from one that has imported cspace already (``forked_cli``),
    unless the command's environment changes what an interpreter reads as it starts
    (`HASH_SEED` among it), or ``fresh`` asks for a new interpreter (a child of this
    process, the installed script). ``timeout`` (wall clock) only guards against a hang,
    as every subprocess timeout of the suite: many times what the command takes on a busy
    machine."""
    full_env = command_env(env)
    if not fresh and forked_cli.forkable(full_env):
        given = [os.fspath(arg) for arg in args]
        code, out, err = forked_cli.run(given, str(cwd), stdin, timeout, full_env)
        return Run(code, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"))
    done = subprocess.run(
        [*cspace_command(), *args],
        cwd=cwd,
        input=stdin,
        capture_output=True,
        timeout=timeout,
        env=full_env,
        check=False,
    )
    return Run(
        done.returncode,
        done.stdout.decode("utf-8", "replace"),
        done.stderr.decode("utf-8", "replace"),
    )


def cpu_of(*args: str, cwd: Path, timeout: float = 120) -> tuple[Run, float]:
    """A run of `cspace ARGS...`, and the CPU seconds (user and system) it and its
    children used: a figure another process on the machine cannot change. ``timeout`` is
    only a guard against a hang."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = run_cli(*args, cwd=cwd, timeout=timeout, fresh=True)  # a child of this process
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return run, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


def run_cli_many(commands: list[tuple[str, ...]], timeout: float = 60) -> list[Run]:
    """Run several `cspace` commands, as many at a time as there are cores; results in order."""
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=max(1, os.cpu_count() or 1)) as pool:
        return list(pool.map(lambda args: run_cli(*args, timeout=timeout), commands))


# --- the order of the run ------------------------------------------------------------

SLOW_FIRST = (
    "test_installed.py",
    "test_action.py",
    "test_pre_commit.py",
    "test_workflow.py",
    "test_hostile_reports.py",
    "test_file_arguments.py",
    "test_untrusted.py",
    "test_depth.py",
    "test_saved_reports.py",
    "test_ci_log.py",
    "test_mjcf_sweep.py",
    "test_isaac.py",
    "test_discover.py",
    "test_discover_xml.py",
    "test_cli_conventions.py",
    "test_formats.py",
)
"""The test files that take longest (installing cspace, building it, or running many
commands or an oracle), most first. `make test`'s two workers take whole files in the
order collected (``--dist loadfile --no-loadscope-reorder``): these start early, the
two longest side by side, and the many short files fill in after them, so that both
workers end together instead of one finishing a long file alone."""


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    rank = {name: k for k, name in enumerate(SLOW_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(SLOW_FIRST)))  # stable


# --- hostile input: bounded time and memory ------------------------------------------


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers",
        "bounded: the test holds a time or memory bound (CPU time of the process tree, a "
        "ratio to a reference of the same run, or a hang guard); tests/load_check.sh runs "
        "these beside a CPU hog, and tests/test_bounded_marks.py finds any left unmarked",
    )


SECONDS = 10.0
"""CPU-time bound per case, of the command and its children together (they take 0.1-0.6 s):
CPU time, so that another process on the machine cannot make a case fail."""
HANG_SECONDS = 120
"""Wall-clock guard of one measured run: a hang fails its test, not the suite. No test
bounds a wall-clock time: every ``timeout`` of the suite is such a guard."""
PEAK_MIB = 600
"""Peak resident memory bound per case (importing Pinocchio alone takes about 90 MiB)."""

_MEASURE = """
import json, os, resource, subprocess, sys

sys.path.insert(0, sys.argv[1])  # the tests' folder
from forked_cli import tree_peak

process = subprocess.Popen(sys.argv[3:], stdin=sys.stdin, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE)
stop = tree_peak(process.pid)
try:
    out, err = process.communicate(timeout=float(sys.argv[2]))
except subprocess.TimeoutExpired:
    process.kill()
    raise
peak = stop()
# this process's only child is the command, whose own figures include every child it
# waited for: the CPU time of the whole tree, whatever else the machine runs
tree = resource.getrusage(resource.RUSAGE_CHILDREN)
print(json.dumps({
    "code": process.returncode,
    "cpu_seconds": tree.ru_utime + tree.ru_stime,
    "peak_mib": max(peak, tree.ru_maxrss) / 1024,
    "stdout": out.decode("utf-8", "replace"),
    "stderr": err.decode("utf-8", "replace"),
}))
"""
"""Runs a command and measures its CPU time (user and system, of the command and every
child it waited for) and peak memory: the largest of the
resident memory of the whole process tree (the command and its children together, such
as MuJoCo's compiler and xacro's expansion, sampled every 20 ms) and of any one process
(the kernel's own peak). It runs without ``site`` (``-I -S``: the standard library
and ``forked_cli``'s `tree_peak`, which forked commands are measured by too), and
walks only the command's tree, so that measuring costs little of the suite's time."""


@dataclass(frozen=True)
class Measured:
    """A run of the command, its process tree's CPU seconds and peak memory in MiB."""

    run: Run
    cpu_seconds: float
    peak_mib: float


def measured(
    *args: str,
    cwd: Path,
    env: dict[str, str] | None = None,
    stdin: bytes | None = None,
    forked: bool = False,
) -> Measured:
    """Run `cspace ARGS...` and measure its CPU time and peak memory (its children too).

    ``forked``: the command is forked as `run_cli` forks it (``forked_cli.measure``), for
    a bound on what a file makes cspace do rather than on a user's whole run: its CPU time
    and memory are measured as here, from the fork on, the interpreter's start-up (about
    0.15 s of CPU) left out."""
    env = command_env(env)
    if forked and forked_cli.forkable(env):
        given = [os.fspath(arg) for arg in args]
        ended = forked_cli.measure(given, str(cwd), stdin or b"", HANG_SECONDS, env)
        out, err = (text.decode("utf-8", "replace") for text in (ended.stdout, ended.stderr))
        return Measured(Run(ended.code, out, err), ended.cpu_seconds, ended.peak_mib)
    tests, command = str(Path(__file__).parent), cspace_command()
    done = subprocess.run(
        [sys.executable, "-I", "-S", "-c", _MEASURE, tests, str(HANG_SECONDS), *command, *args],
        cwd=cwd,
        input=stdin if stdin is not None else b"",
        capture_output=True,
        timeout=HANG_SECONDS + 60,
        env=env,
        check=True,
    )
    out = json.loads(done.stdout)
    run = Run(out["code"], out["stdout"], out["stderr"])
    return Measured(run, out["cpu_seconds"], out["peak_mib"])


def assert_bounded_error(result: Measured, code: str) -> str:
    """Exit 2 with one line naming the error code, within the time and memory bounds."""
    assert result.cpu_seconds < SECONDS, result
    assert result.peak_mib < PEAK_MIB, result
    assert result.run.code == 2, result
    assert result.run.stdout == ""
    assert result.run.stderr.count("\n") == 1 and result.run.stderr.startswith("cspace: error: ")
    assert result.run.stderr.rstrip().endswith(f"[{code}]"), result.run.stderr
    return result.run.stderr


class OpenWatch:
    """Every open of a file in a folder, by any process, while the watch is on."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.inotify = inotify_simple.INotify()
        flags = inotify_simple.flags
        self.inotify.add_watch(folder, flags.OPEN | flags.ACCESS)

    def opened(self) -> list[str]:
        return [event.name for event in self.inotify.read(timeout=0)]

    def close(self) -> None:
        self.inotify.close()


def manifold_section(form: NormalForm) -> dict[str, object]:
    """The ``manifold`` section of a report of this normal form, as inspect writes it."""
    return {
        "notation": form.notation,
        "ascii": form.ascii,
        "factors": form.counts(),
        "fundamental_group": form.fundamental_group,
        "simply_connected": form.simply_connected,
    }


def checkout_copy(target: Path) -> Path:
    """A copy of the checkout as a user's clone holds it: the files git tracks or would
    (untracked but not ignored), none of the build output (``build/``, which setuptools
    would put into a wheel built in place, stale modules and all)."""
    listed = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=REPO,
        capture_output=True,
        check=True,
    ).stdout.split(b"\0")
    for name in filter(None, (n.decode() for n in listed)):
        source = REPO / name
        if source.is_file() and not source.is_symlink():
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target / name)
    return target


def build_wheel(out: Path, *pip_args: str) -> tuple[Path, str]:
    """The wheel ``pip wheel`` builds from a clean copy of the checkout, and pip's log."""
    tree = checkout_copy(out / "tree")
    done = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", *pip_args, "-w", str(out), str(tree)],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    (built,) = out.glob("cspace-*.whl")
    return built, done.stdout + done.stderr


@pytest.fixture(scope="session")
def tree_wheel(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The wheel ``pip wheel -v`` builds from a clean copy of the checkout, and pip's log:
    built once a run, the xdist workers sharing it (under a lock in the run's folder)."""
    import fcntl

    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # the run's folder, above each worker's own
    out, log = root / "tree-wheel", root / "tree-wheel" / "pip.log"
    with open(root / "tree-wheel.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when closed
        if not log.exists():  # not built yet, or a build that failed
            shutil.rmtree(out, ignore_errors=True)
            out.mkdir()
            _, text = build_wheel(out, "-v")
            log.write_text(text)
    (built,) = out.glob("cspace-*.whl")
    return built, log.read_text()


def summary_rows(stdout: str) -> dict[str, str]:
    """Path -> status of the summary table ``cspace inspect`` writes for several files."""
    lines = stdout.splitlines()[2:]
    rows = [line.split() for line in lines[: lines.index("")]] if "" in lines else []
    return {row[0]: row[-1] if row[-1] != "report" else "no report" for row in rows}


def robots_only_both_ways(root: Path) -> list[Run]:
    """``cspace inspect --robots-only`` of a folder, and of the names of its files (links
    too), as the GitHub Action and the pre-commit hook pass them."""
    names = sorted(
        str(p.relative_to(root)) for p in root.rglob("*") if p.is_file() or p.is_symlink()
    )
    options = ("inspect", "--robots-only", "--width", "400")
    return [run_cli(*options, ".", cwd=root), run_cli(*options, "--", *names, cwd=root)]


def mujoco_compiles(path: Path) -> bool:
    """Whether MuJoCo compiles the model at ``path`` (``MjModel.from_xml_path``)."""
    import mujoco

    try:
        mujoco.MjModel.from_xml_path(str(path))
    except ValueError:
        return False
    return True


# --- where the installing tests put their environments -------------------------------

IN_MEMORY = Path("/dev/shm")
ROOM = 4 << 30
"""Bytes free, of the memory folder and of the machine's memory, that an installing test
needs there: an environment with cspace's dependencies takes about 1 GiB."""


def _memory_has_room() -> bool:
    try:
        folder = os.statvfs(IN_MEMORY)
        with open("/proc/meminfo") as meminfo:
            sizes = dict(line.split(":", 1) for line in meminfo)
        available = int(sizes["MemAvailable"].split()[0]) * 1024
    except (OSError, KeyError, ValueError, IndexError):
        return False
    usable = not folder.f_flag & (os.ST_NOEXEC | os.ST_RDONLY)  # its scripts must run
    return usable and min(folder.f_bavail * folder.f_frsize, available) >= ROOM


@contextlib.contextmanager
def environment_folder(otherwise: Path) -> Iterator[Path]:
    """A folder for the virtual environments a test installs: in memory (``/dev/shm``, a
    tmpfs) when it lets programs run and it and the machine have `ROOM`, removed after;
    else ``otherwise``.

    An environment of cspace's dependencies is about 1 GiB in 26,000 files. Written to
    this machine's disk (ext4) it costs 1.4 s of system CPU when nothing else writes, and
    9-19 s while other processes do (``pip install`` of the wheel, or ``cp -r`` of the
    environment, measured); in memory, 1.0-1.5 s either way. A folder left by a run that
    was killed (its process gone) is removed by the next."""
    for stale in IN_MEMORY.glob("cspace-tests-*-*"):  # first: they take the room
        pid = stale.name.split("-")[2]
        if pid.isdigit() and not Path("/proc", pid).exists():
            shutil.rmtree(stale, ignore_errors=True)
    if not _memory_has_room():
        yield otherwise
        return
    folder = Path(tempfile.mkdtemp(prefix=f"cspace-tests-{os.getpid()}-", dir=IN_MEMORY))
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def usd_stages(factory: pytest.TempPathFactory, *also: Path) -> Iterator[Path]:
    """Where a file's tests that inspect stages in this process write them, for a
    module-scoped fixture: below one folder, so that one OpenUSD child reads them all, as
    one `cspace.inspect_many` run's (`usd.child.within`, with the folders in ``also``;
    its Landlock rules are on the entries a folder holds when it starts, so a new folder
    of its own for each test would start a child each: 0.3 s of CPU). Each stage is still
    read only from its own folder, checked in the child."""
    from cspace._formats.usd import child

    top = factory.mktemp("stages")
    (top / "tests").mkdir()
    child.close()
    child.within([str(top), *map(str, also)])
    yield top / "tests"
    child.within(())
    child.close()


@pytest.fixture
def folder(_stages: Path) -> Path:
    """A new folder of the test's own, below the stages folder of its file (`_stages`,
    a module fixture that yields from `usd_stages`)."""
    return Path(tempfile.mkdtemp(dir=_stages))
