"""`cspace sample`, `interpolate` and `distance` with large counts and bad input.

Large counts are computed and written in chunks: memory stays bounded (the command's
peak for many rows against its peak for a few chunks, each measured forked with
conftest.measured) and the bytes do not depend on the chunking. A command that two
tests need (the few chunks' run, whose output a test of the chunking reads) runs once
(`_measured`), each test making its own assertions of it.
Bad counts and bad configurations end in one line on stderr and exit 2, never an
internal error or a traceback.
"""

from __future__ import annotations

import io
import json
import os
import subprocess
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import cspace

import forked_cli
from conftest import (
    REPO,
    ROBOTS,
    Measured,
    command_env,
    cspace_command,
    environment_folder,
    measured,
    run_cli,
)

ARM = str(ROBOTS / "arm7.urdf")  # 7 coordinates: 37,449 rows per chunk
QUAD = str(ROBOTS / "quadrotor_floating.urdf")
BOX = [
    "--bounds",
    "body_free.x=-1:1",
    "--bounds",
    "body_free.y=-1:1",
    "--bounds",
    "body_free.z=0:1",
]
LARGE = 300_000
"""CSV rows for the memory bound: 2.1 million numbers, 9 chunks. Their peak is within a
few MiB of 80,000 rows'; written as one chunk (``CHUNK_NUMBERS`` unbounded), 116-131 MiB
above it, twice `GROWTH_MIB`."""
LARGE_NPY = 2_400_000
"""Rows for the memory bound of npy output, which holds no text: 16.8 million numbers,
65 chunks. Their peak is within 2 MiB of 80,000 rows'; written as one chunk, 124 MiB
above it."""
GROWTH_MIB = 64
"""How much more peak memory LARGE rows may take than a few chunks' worth."""
SAMPLE_CSV = ("sample", ARM, "--seed", "5", "--format", "csv", "-n")
"""A seeded sample of the arm as CSV, of as many rows as the count that follows."""
INTERPOLATE_CSV = (
    *("interpolate", ARM, '{"wrist_roll": 3}', '{"elbow": -1}', "--partial"),
    *("--format", "csv", "--steps"),
)
"""A path of the arm as CSV, of as many steps as the count that follows."""

_RUNS: dict[tuple[str, ...], Measured] = {}


def _measured(*args: str) -> Measured:
    """`cspace ARGS...` (in the checkout) measured forked (`conftest.measured`), run once
    a session: the tests that need one command share its run."""
    if args not in _RUNS:
        _RUNS[args] = measured(*args, cwd=REPO, forked=True)
    return _RUNS[args]


@pytest.fixture(scope="module")
def arm() -> cspace.ConfigurationSpace:
    return cspace.load(ARM)


@pytest.fixture(scope="module")
def npy_folder(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """Where the npy files are written: in memory where there is room (the largest is
    134 MB, written to a disk at a cost of CPU time that is not the command's work)."""
    with environment_folder(tmp_path_factory.mktemp("npy")) as folder:
        yield folder


def _sample_npy(folder: Path, count: int) -> tuple[Path, Measured]:
    """A seeded sample of ``count`` rows of the arm written to an npy file (`_measured`)."""
    target = folder / f"{count}.npy"
    args = ("sample", ARM, "-n", str(count), "--seed", "5", "--format", "npy", "-o", str(target))
    return target, _measured(*args)


def floats(csv_text: str) -> np.ndarray:
    """The numbers of CSV rows below a header, each parsed as ``float`` parses it (NumPy's
    reader, correctly rounded: every ``repr`` of a double gives back that double)."""
    return np.loadtxt(io.StringIO(csv_text), delimiter=",", skiprows=1, ndmin=2)


def assert_usage_error(args: tuple[str, ...], needle: str) -> str:
    run = run_cli(*args)
    assert run.code == 2, run
    assert run.stdout == ""
    assert run.stderr.startswith("cspace: error: ") and run.stderr.count("\n") == 1, run.stderr
    assert "internal error" not in run.stderr and "Traceback" not in run.stderr
    assert needle in run.stderr, run.stderr
    return run.stderr


@pytest.mark.bounded
@pytest.mark.parametrize("command", [SAMPLE_CSV, INTERPOLATE_CSV], ids=["sample", "interpolate"])
def test_large_counts_stay_within_a_memory_bound(command: tuple[str, ...]) -> None:
    def run(count: int) -> float:
        result = _measured(*command, str(count))
        assert result.run.code == 0, result.run.stderr
        assert result.run.stdout.count("\n") == count + 1  # the header, then every row
        return result.peak_mib

    # 80,000 rows: past the first chunk, so numba's kernels are loaded in both runs
    small, large = run(80_000), run(LARGE)
    print(f"peak memory: {small:.0f} MiB for 80,000 rows, {large:.0f} MiB for {LARGE:,}")
    assert large - small < GROWTH_MIB, (small, large)


@pytest.mark.bounded  # its run is the memory test's, measured (a hang guard)
def test_sample_is_the_same_whatever_the_chunking(arm: cspace.ConfigurationSpace) -> None:
    # -n 40000 and -n 80000 cross the chunk boundary (37,449 rows) at different places
    run = _measured(*SAMPLE_CSV, "80000").run
    shorter = _measured(*SAMPLE_CSV, "40000").run
    assert run.code == shorter.code == 0
    assert run.stdout.startswith(shorter.stdout)  # the first rows do not depend on n
    expected = arm.sample(80000, np.random.default_rng(5))
    assert floats(run.stdout).tobytes() == expected.tobytes()  # one call for all rows


def test_json_output_is_the_whole_document_written_in_pieces() -> None:
    # 23,831 rows a chunk: the configurations are written in three pieces
    run = run_cli("sample", QUAD, "-n", "50000", "--seed", "2", *BOX)
    assert run.code == 0, run.stderr
    document = json.loads(run.stdout)
    assert run.stdout == json.dumps(document) + "\n"
    assert list(document) == ["robot", "seed", "coordinates", "configurations"]
    assert len(document["configurations"]) == 50000


def test_interpolate_in_chunks_gives_every_step_exactly(arm: cspace.ConfigurationSpace) -> None:
    a, b = '{"wrist_roll": 3.0, "elbow": -2.5}', '{"wrist_roll": -3.0, "shoulder_pan": 1}'
    steps = 90001
    run = run_cli("interpolate", ARM, a, b, "--partial", "--steps", str(steps))
    assert run.code == 0, run.stderr
    document = json.loads(run.stdout)
    assert run.stdout == json.dumps(document) + "\n"
    t = np.linspace(0.0, 1.0, steps)
    assert np.array(document["t"]).tobytes() == t.tobytes()
    ends = [arm.from_dict(json.loads(x), default=arm.neutral()) for x in (a, b)]
    expected = arm.interpolate(*ends, t)
    assert np.array(document["configurations"]).tobytes() == expected.tobytes()


@pytest.mark.parametrize(
    ("option", "value", "command"),
    [
        ("-n", "0", "sample"),
        ("-n", "-1", "sample"),
        ("-n", "1.5", "sample"),
        ("-n", "1e3", "sample"),
        ("-n", "1_000", "sample"),
        ("-n", "\u0661\u0662", "sample"),  # Arabic-Indic digits, which int() takes
        ("-n", "99999999999999999999", "sample"),
        ("-n", "", "sample"),
        ("--seed", "-1", "sample"),
        ("--seed", "0.5", "sample"),
        ("--steps", "1", "interpolate"),
        ("--steps", "0", "interpolate"),
        ("--steps", "many", "interpolate"),
    ],
)
def test_counts_must_be_whole_numbers_in_range(option: str, value: str, command: str) -> None:
    pair = ("{}", "{}", "--partial") if command == "interpolate" else ()
    assert_usage_error((command, ARM, *pair, option, value), f"argument {option}:")


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("distance", QUAD, '{"body_free": [0,0,0,0,0,0,0]}', "{}", "--partial"), "norm 0.0"),
        (("interpolate", QUAD, "{}", '{"body_free": [0,0,0,0,0,0,0]}', "--partial"), "norm 0.0"),
        (("distance", ARM, '{"elbow": NaN}', "{}", "--partial"), "is nan"),
        (("distance", ARM, '{"elbow": 1e400}', "{}", "--partial"), "is inf"),
        (("distance", ARM, '{"elbow": 1' + "0" * 5000 + "}", "{}", "--partial"), "not valid JSON"),
        (("distance", ARM, "[" * 100_000, "{}", "--partial"), "nested too deeply"),
        (("distance", ARM, "{}", "{}", "--partial", "--weight", "elbow=1e300"), "overflows"),
        (("distance", ARM, "{}", "{}", "--partial", "--weight", "elbow=nan"), "finite"),
        (("distance", ARM, "{}", "{}", "--partial", "--weight", "elbow=-1"), ">= 0"),
        (("sample", ARM, "--bounds", "elbow=-5:5"), "limits"),
        (("sample", ARM, "--bounds", "elbow=nan:0"), "finite"),
        (("sample", ARM, "--bounds", "wrist_roll=-7:7"), "turn"),
        (("sample", QUAD, *BOX, "--bounds", "body_free.x=-1e308:1e308"), "wider than a double"),
    ],
)
def test_bad_configurations_weights_and_bounds_are_one_line(
    args: tuple[str, ...], needle: str
) -> None:
    assert_usage_error(args, needle)


def test_a_configuration_file_is_read_only_up_to_its_limit(tmp_path: Path) -> None:
    big = tmp_path / "big.json"
    big.write_text('{"elbow": 0.0' + " " * (2 << 20) + "}")
    limit = "larger than the 1,048,576-byte limit"
    assert_usage_error(("distance", ARM, f"@{big}", "{}", "--partial"), limit)
    assert_usage_error(("distance", ARM, f"@{tmp_path}", "{}", "--partial"), "is a directory")
    small = tmp_path / "small.json"
    small.write_text('{"elbow": -1.0}')
    run = run_cli("distance", ARM, f"@{small}", '{"elbow": -0.5}', "--partial")
    assert (run.code, run.stdout) == (0, "0.5\n")


@pytest.mark.bounded  # its run is the memory test's, measured (a hang guard)
def test_npy_output_is_the_sample_written_as_it_is_drawn(
    npy_folder: Path, arm: cspace.ConfigurationSpace
) -> None:
    target, result = _sample_npy(npy_folder, 80000)
    assert (result.run.code, result.run.stdout, result.run.stderr) == (0, "", "")
    stored = np.load(target)  # NumPy's own reader: the header's shape matches the bytes
    expected = arm.sample(80000, np.random.default_rng(5))
    assert stored.dtype == np.float64 and stored.flags.c_contiguous
    assert stored.tobytes() == expected.tobytes()
    to_stdout = run_cli("sample", ARM, "-n", "80000", "--seed", "5", "--format", "npy")
    # the same bytes on standard output (a pipe, not a terminal)
    assert to_stdout.code == 0 and len(to_stdout.stdout) > 0


def test_interpolate_writes_npy_and_json_lines(
    tmp_path: Path, arm: cspace.ConfigurationSpace
) -> None:
    a, b = '{"wrist_roll": 3.0}', '{"wrist_roll": -3.0, "elbow": -1}'
    common = ("interpolate", ARM, a, b, "--partial", "--steps", "50001")
    run = run_cli(*common, "--format", "npy", "-o", str(tmp_path / "path.npy"))
    assert run.code == 0, run.stderr
    lines = run_cli(*common, "--format", "jsonl")
    assert lines.code == 0, lines.stderr
    rows = np.array([json.loads(line) for line in lines.stdout.splitlines()])
    ends = [arm.from_dict(json.loads(x), default=arm.neutral()) for x in (a, b)]
    expected = arm.interpolate(*ends, np.linspace(0.0, 1.0, 50001))
    assert np.load(tmp_path / "path.npy").tobytes() == expected.tobytes()
    assert rows.tobytes() == expected.tobytes()


def test_json_lines_of_a_sample_are_what_convert_reads() -> None:
    sample = run_cli("sample", ARM, "-n", "4", "--format", "jsonl")
    assert sample.code == 0 and sample.stdout.count("\n") == 4
    back = run_cli(
        "convert", ARM, "-", "--from", "canonical", "--to", "canonical",
        stdin=sample.stdout.encode(),
    )  # fmt: skip
    assert (back.code, back.stdout) == (0, sample.stdout), back.stderr


@pytest.mark.bounded
def test_large_npy_output_stays_within_the_memory_bound(npy_folder: Path) -> None:
    def run(count: int) -> float:
        target, result = _sample_npy(npy_folder, count)
        assert result.run.code == 0, result.run.stderr
        assert target.stat().st_size == 128 + count * 7 * 8  # the header, then the rows
        return result.peak_mib

    small, large = run(80_000), run(LARGE_NPY)  # numba's kernels are loaded in both
    (npy_folder / f"{LARGE_NPY}.npy").unlink()
    assert large - small < GROWTH_MIB, (small, large)


def _on_terminal(terminal: int, *args: str) -> tuple[int, bytes]:
    """`cspace ARGS...` whose standard output is ``terminal``: its exit status and standard
    error. Forked as `run_cli` forks commands (descriptor 1 of the new process is the
    terminal), or the installed script when the environment asks for a new interpreter."""
    env = command_env()
    if forked_cli.forkable(env):
        code, _, err = forked_cli.run(list(args), str(REPO), None, 60, env, stdout=terminal)
        return code, err
    done = subprocess.run(
        [*cspace_command(), *args],
        stdout=terminal,
        stderr=subprocess.PIPE,
        timeout=60,
        env=env,
        check=False,
    )
    return done.returncode, done.stderr


def test_binary_output_is_refused_on_a_terminal_and_bad_output_files_are_named(
    tmp_path: Path,
) -> None:
    primary, secondary = os.openpty()
    try:
        code, err = _on_terminal(secondary, "sample", ARM, "--format", "npy")
    finally:
        os.close(secondary)
        os.close(primary)
    assert code == 2
    assert b"npy is binary: give --output FILE" in err
    primary, secondary = os.openpty()  # -o naming a terminal: refused too (not a file)
    try:
        terminal = os.ttyname(secondary)
        line = assert_usage_error(("sample", ARM, "--format", "npy", "-o", terminal), terminal)
        assert "is a character device, not a regular file" in line and "[bad-output]" in line
    finally:
        os.close(secondary)
        os.close(primary)
    dash = run_cli("sample", ARM, "-n", "3", "--format", "csv", "-o", "-", cwd=tmp_path)
    assert dash.code == 0 and dash.stdout.count("\n") == 4  # - is standard output
    assert not (tmp_path / "-").exists()
    missing = tmp_path / "no-such-dir" / "x.npy"
    assert_usage_error(
        ("sample", ARM, "--format", "npy", "-o", str(missing)), f"{missing}: cannot write"
    )
