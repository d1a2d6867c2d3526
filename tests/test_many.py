"""Many files at once: cspace.inspect_many on process pools, threads and a Dask cluster,
and ``cspace inspect --jobs``. Results come in input order and equal one-at-a-time
inspection; errors cross process boundaries with their attributes."""

from __future__ import annotations

import functools
import json
import os
import pickle
import shutil
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

import cspace
from cspace._model import many

from conftest import HANG_SECONDS, ROBOTS, run_cli

TEACHING = [
    *sorted(str(p) for p in ROBOTS.glob("*.urdf")),
    str(ROBOTS / "sdf_every_joint.sdf"),
    str(ROBOTS / "mjcf_every_joint.xml"),
]


def _broken(tmp_path: Path) -> list[str]:
    """Files without a report: not XML, a missing link, a missing file."""
    not_xml = tmp_path / "notes.urdf"
    not_xml.write_text("# not a robot\n")
    missing_link = tmp_path / "missing_link.urdf"
    missing_link.write_text(
        '<robot name="r">\n  <link name="a"/>\n'
        '  <joint name="j" type="revolute">\n    <parent link="a"/>\n'
        '    <child link="b"/>\n    <limit lower="-1" upper="1" effort="1" velocity="1"/>\n'
        "  </joint>\n</robot>\n"
    )
    return [str(not_xml), str(missing_link), str(tmp_path / "absent.urdf")]


def _mixed(tmp_path: Path) -> list[str]:
    broken = _broken(tmp_path)
    return [TEACHING[0], broken[0], *TEACHING[1:5], broken[1], TEACHING[5], broken[2]]


def _expected(path: str) -> tuple[str, str]:
    try:
        return "report", cspace.inspect(path).to_json()
    except cspace.CspaceError as exc:
        return type(exc).__name__, str(exc)


def _seen(result: cspace.Inspected) -> tuple[str, str]:
    if result.report is not None:
        assert result.error is None
        return "report", result.report.to_json()
    assert result.error is not None
    return type(result.error).__name__, str(result.error)


@pytest.mark.parametrize("jobs", [1, 2])
def test_results_come_in_input_order_and_equal_one_at_a_time(tmp_path: Path, jobs: int) -> None:
    paths = _mixed(tmp_path) * 3
    results = list(cspace.inspect_many(paths, jobs=jobs))
    assert [r.path for r in results] == paths
    assert [_seen(r) for r in results] == [_expected(p) for p in paths]


def test_errors_keep_their_attributes_across_processes(tmp_path: Path) -> None:
    not_xml, missing_link, absent = _broken(tmp_path)
    results = {
        r.path: r.error for r in cspace.inspect_many([not_xml, missing_link, absent], jobs=2)
    }
    assert isinstance(results[not_xml], cspace.errors.XmlSyntaxError)
    assert isinstance(results[missing_link], cspace.errors.RobotStructureError)
    assert isinstance(results[absent], cspace.errors.FileUnreadableError)
    for path, error in results.items():
        assert error is not None
        assert error.code and error.code != "cspace"
        try:
            cspace.inspect(path)
        except cspace.CspaceError as exc:
            assert vars(error) == vars(exc) and error.args == exc.args
            copy = pickle.loads(pickle.dumps(exc))
            assert (type(copy), vars(copy), str(copy)) == (type(exc), vars(exc), str(exc))


def test_any_executor_runs_it_and_is_left_open() -> None:
    with ThreadPoolExecutor(2) as pool:
        results = list(cspace.inspect_many(TEACHING, executor=pool, window=3))
        assert [r.path for r in results] == TEACHING
        assert pool.submit(len, "still open").result() == 10
    assert all(r.report is not None for r in results)


def test_paths_are_read_lazily_within_the_window() -> None:
    read: list[int] = []

    def paths():  # type: ignore[no-untyped-def]
        for i in range(1000):
            read.append(i)
            yield TEACHING[i % len(TEACHING)]

    results = cspace.inspect_many(paths(), jobs=2, window=8)
    first = next(results)
    assert first.path == TEACHING[0]
    assert len(read) <= 8 + many.PER_TASK  # not the 1000 paths
    results.close()  # the pool is shut down, pending work cancelled


def test_bad_jobs_and_window_are_refused() -> None:
    for kwargs in ({"jobs": 0}, {"window": 0}, {"jobs": True}):
        with pytest.raises(cspace.errors.ArgumentError):
            cspace.inspect_many(TEACHING, **kwargs)  # type: ignore[arg-type]


_DASK = """
import json, sys
import cspace
import distributed

paths = json.loads(sys.argv[1])
with (
    distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster,
    distributed.Client(cluster) as client,
):
    results = list(cspace.inspect_many(paths, executor=client.get_executor()))
seen = [
    [r.path, "report", r.report.to_json()] if r.report is not None
    else [r.path, type(r.error).__name__, str(r.error)]
    for r in results
]
print(json.dumps(seen))
"""
"""A dask cluster's run, in a process of its own: importing distributed changes how
every exception of the process pickles (tblib's support), which other tests rely on."""


@pytest.mark.bounded
def test_a_local_dask_cluster_runs_the_same_call() -> None:
    paths = TEACHING * 2
    done = subprocess.run(
        [sys.executable, "-c", _DASK, json.dumps(paths)],
        capture_output=True,
        text=True,
        timeout=HANG_SECONDS,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    seen = json.loads(done.stdout.splitlines()[-1])
    assert [path for path, *_ in seen] == paths
    assert [tuple(rest) for _, *rest in seen] == [_expected(p) for p in paths]


def test_the_command_line_gives_the_same_bytes_with_any_number_of_jobs(tmp_path: Path) -> None:
    paths = _mixed(tmp_path)
    runs = [run_cli("inspect", *paths, "--format", "jsonl", "--jobs", j) for j in ("1", "2", "5")]
    assert len({(r.code, r.stdout, r.stderr) for r in runs}) == 1, runs
    assert runs[0].code == 2 and runs[0].stdout.count("\n") == len(TEACHING[:6])
    assert runs[0].stderr.count("\n") == 3
    table = run_cli("inspect", *paths, "--jobs", "2", "--width", "100")
    assert table.stdout == run_cli("inspect", *paths, "--jobs", "1", "--width", "100").stdout
    bad = run_cli("inspect", *paths, "--jobs", "0")
    assert bad.code == 2 and "--jobs" in bad.stderr


def test_one_path_is_refused_and_bad_counts_are_named() -> None:
    with pytest.raises(cspace.errors.ArgumentTypeError, match="not one path"):
        cspace.inspect_many(TEACHING[0])  # type: ignore[arg-type]
    with pytest.raises(cspace.errors.ArgumentTypeError, match="jobs must be a whole number"):
        cspace.inspect_many(TEACHING, jobs="2")  # type: ignore[arg-type]


def test_a_child_forked_during_a_build_is_not_left_locked() -> None:
    import multiprocessing

    from cspace._model import native

    with native._QUIET:  # as if another thread were capturing Pinocchio's output
        child = multiprocessing.get_context("fork").Process(
            target=cspace.inspect, args=(TEACHING[0],)
        )
        child.start()
        child.join(timeout=60)
    assert child.exitcode == 0  # it inspected, instead of waiting for a lock forever


@pytest.mark.bounded
def test_ctrl_c_stops_several_jobs_quietly(tmp_path: Path) -> None:
    import os
    import select
    import signal
    import subprocess
    import time

    from conftest import HANG_SECONDS, cspace_command

    # SIGINT at its default, as in a terminal's foreground job: a suite started as a
    # background job (`make test &`) ignores it, and the command inherits and keeps that
    with_sigint = "import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); "
    with_sigint += "os.execv(sys.argv[1], sys.argv[1:])"
    command = [*cspace_command(), "inspect", *(TEACHING * 200), "--jobs", "2", "--format", "jsonl"]
    started = subprocess.Popen(
        [sys.executable, "-c", with_sigint, *command],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,  # a process group, as a terminal's Ctrl-C reaches
    )
    # Ctrl-C once the jobs run (the first report is out), however late a busy machine
    # starts them; the wall-clock deadline is only a guard against a hang.
    assert started.stdout is not None
    deadline = time.monotonic() + HANG_SECONDS
    while not select.select([started.stdout], [], [], 0.05)[0]:
        assert time.monotonic() < deadline and started.poll() is None, "no report came"
    assert started.stdout.readline().startswith(b"{")
    os.killpg(started.pid, signal.SIGINT)
    _, err = started.communicate(timeout=HANG_SECONDS)
    assert started.returncode == 130
    assert b"Traceback" not in err and err.count(b"\n") <= 1, err


def test_then_runs_in_the_worker_and_its_value_comes_back(tmp_path: Path) -> None:
    paths = _mixed(tmp_path)
    results = list(cspace.inspect_many(paths, jobs=2, then=_notation))  # module-level: pickles
    expected = [e[1] if e[0] == "report" else None for e in map(_expected, paths)]
    assert [r.value for r in results] == [
        json.loads(e)["manifold"]["notation"] if e else None for e in expected
    ]


def _notation(report: cspace.Report) -> str:
    return report.manifold.notation


def _dies_on(name: str, report: cspace.Report) -> str:
    """A worker killed while it holds ``name``'s report, as by the kernel's OOM killer."""
    if Path(report.source.path).name == name:
        os.kill(os.getpid(), signal.SIGKILL)
    return report.manifold.notation


def test_a_file_that_kills_its_worker_is_reported_and_the_rest_go_on(tmp_path: Path) -> None:
    # A dead worker breaks the whole pool: every task in flight fails with it. The
    # files are run again, the dead worker's task a file at a time; only the file that
    # kills its worker alone gets WorkerDiedError.
    paths = _mixed(tmp_path) * 3
    killer = Path(TEACHING[2]).name
    then = functools.partial(_dies_on, killer)
    results = list(cspace.inspect_many(paths, jobs=2, then=then))
    assert [r.path for r in results] == paths
    for path, result in zip(paths, results, strict=True):
        if Path(path).name == killer:
            assert result.report is None and isinstance(result.error, cspace.errors.WorkerDiedError)
            assert result.error.code == "worker-died" and result.error.path == path
            assert str(result.error).startswith(f"{path}: the worker process")
        else:
            assert _seen(result) == _expected(path)
    assert sum(isinstance(r.error, cspace.errors.WorkerDiedError) for r in results) == 3


@pytest.mark.bounded
def test_a_worker_death_while_the_caller_is_busy_is_survived_too(tmp_path: Path) -> None:
    # The caller is slow: the pool breaks while finished tasks wait to be taken, so
    # submitting the next task meets a broken pool (not only waiting for a result).
    killer = tmp_path / "killer.urdf"
    shutil.copy(TEACHING[0], killer)
    paths = [*TEACHING[:8], *TEACHING[:3], str(killer), *TEACHING[:12]]
    then = functools.partial(_dies_on, killer.name)
    results = []
    for result in cspace.inspect_many(paths, jobs=2, window=16, then=then):
        if not results:
            time.sleep(1.5)  # the killer's task (the third) runs meanwhile
        results.append(result)
    assert [r.path for r in results] == paths
    died = [r.path for r in results if isinstance(r.error, cspace.errors.WorkerDiedError)]
    assert died == [str(killer)]
    assert all(_seen(r) == _expected(r.path) for r in results if r.path != str(killer))


def test_a_script_without_a_main_guard_stays_on_fork_after_a_death(tmp_path: Path) -> None:
    # A one-thread caller forks its workers (no `if __name__ == "__main__":` needed, and
    # `then` may live in __main__); a pool made anew after a death must fork too, not
    # start a forkserver that would run the script again in every worker.
    killer = tmp_path / "killer.urdf"
    shutil.copy(TEACHING[0], killer)
    runs = tmp_path / "runs.txt"
    paths = [*TEACHING[:5], str(killer), *TEACHING[:6]]
    script = tmp_path / "script.py"
    script.write_text(
        "import collections, os, signal, cspace\n"
        f"open({str(runs)!r}, 'a').write('run\\n')\n"
        "def then(report):\n"
        "    if report.source.path.endswith('killer.urdf'):\n"
        "        os.kill(os.getpid(), signal.SIGKILL)\n"
        "    return report.manifold.notation\n"
        f"results = list(cspace.inspect_many({paths!r}, jobs=2, then=then))\n"
        "print(dict(collections.Counter(type(r.error).__name__ for r in results)))\n"
    )
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "{'NoneType': 11, 'WorkerDiedError': 1}"
    assert runs.read_text() == "run\n"  # the script ran once: no worker re-ran it
    assert "Traceback" not in done.stderr
