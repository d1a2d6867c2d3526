"""``cspace check --baseline``: a repository's accepted C-spaces, and what differs from them.

The baseline is what ``cspace inspect --format jsonl`` writes; the tests write it so,
then change a limit, add a robot, delete one, and accept by writing it again. The
baseline is untrusted: a line that is no report, two reports of one file, a file too
large are refused in one line, naming the file and line.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

from conftest import REPO, run_cli


def _repo(tmp_path: Path) -> Path:
    shutil.copytree(REPO / "robots", tmp_path / "robots")
    written = run_cli("inspect", "--format", "jsonl", "robots", cwd=tmp_path)
    assert written.code == 0
    (tmp_path / "baseline.jsonl").write_text(written.stdout)
    return tmp_path


def test_a_repository_matches_the_baseline_it_wrote(tmp_path: Path) -> None:
    repo = _repo(tmp_path)
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo)
    lines = run.stdout.splitlines()
    assert run.code == 0 and len(lines) == 23 and all(line.startswith("same: ") for line in lines)


def test_what_differs_fails_and_accepting_it_passes(tmp_path: Path) -> None:
    repo = _repo(tmp_path)
    arm = repo / "robots" / "arm7.urdf"
    arm.write_text(arm.read_text().replace('upper="2.9"', 'upper="2.5"', 1))
    shutil.copy(arm, repo / "robots" / "arm8.urdf")
    (repo / "robots" / "sensor_head_fixed.urdf").unlink()
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo)
    said = {line for line in run.stdout.splitlines() if not line.startswith("same: ")}
    assert run.code == 1
    assert said == {
        "differs: robots/arm7.urdf: R^6 × S^1, but limits differ",
        "new: robots/arm8.urdf: R^6 × S^1, not in the baseline",
        "gone: robots/sensor_head_fixed.urdf: in the baseline, but the file is gone",
    }
    markdown = run_cli(
        "check", "--baseline", "baseline.jsonl", "robots", "--format", "markdown", cwd=repo
    )
    assert markdown.code == 1 and "| `robots/arm8.urdf` | new |" in markdown.stdout
    rewritten = run_cli("inspect", "--format", "jsonl", "robots", cwd=repo)
    (repo / "baseline.jsonl").write_text(rewritten.stdout)  # the change accepted
    assert run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo).code == 0


def test_a_hostile_baseline_is_refused_in_one_line(tmp_path: Path) -> None:
    repo = _repo(tmp_path)
    lines = (repo / "baseline.jsonl").read_text().splitlines()
    cases = {
        "not-json.jsonl": lines[0] + "\n{not json\n",
        "twice.jsonl": lines[0] + "\n" + lines[0] + "\n",
        "not-a-report.jsonl": json.dumps({"joints": 1}) + "\n",
        "nested.jsonl": "[" * 100_000 + "]" * 100_000 + "\n",  # a JSON bomb of depth
    }
    for name, text in cases.items():
        (repo / name).write_text(text)
        run = run_cli("check", "--baseline", name, "robots", cwd=repo)
        assert run.code == 2 and run.stdout == "", run.stdout
        assert run.stderr.count("\n") == 1 and run.stderr.strip().endswith("[bad-report]"), name
        assert f"{name}:" in run.stderr
    assert (
        "a second report of 'robots/"
        in run_cli("check", "--baseline", "twice.jsonl", "robots", cwd=repo).stderr
    )
    huge = repo / "huge.jsonl"
    with open(huge, "wb") as out:  # sparse: 65 MiB of nothing on disk
        out.truncate(65 << 20)
    run = run_cli("check", "--baseline", "huge.jsonl", "robots", cwd=repo)
    assert run.code == 2 and "larger than the 67,108,864-byte limit" in run.stderr
    os.unlink(huge)


def test_several_robots_need_a_baseline() -> None:
    run = run_cli("check", "robots/arm7.urdf", "robots/arm7.urdf", "--expect", "R^7", cwd=REPO)
    assert run.code == 2 and "--baseline checks several" in run.stderr
