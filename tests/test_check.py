"""``cspace check``: pinning a robot's C-space, and the notation it reads."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

import cspace
from cspace._manifold import NormalForm
from cspace.notation import NotationError, expectation_failures, parse_notation

from conftest import ROBOTS, run_cli

ARM7 = str(ROBOTS / "arm7.urdf")  # R^6 × S^1


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("R^6 × T^1", NormalForm(r=6, t=1)),
        ("R^6 x T^1", NormalForm(r=6, t=1)),
        ("R^6xT^1", NormalForm(r=6, t=1)),
        ("R^6 × S^1", NormalForm(r=6, t=1)),
        ("T^1 × R^6", NormalForm(r=6, t=1)),  # factors commute
        ("R⁶ × S¹", NormalForm(r=6, t=1)),
        ("R^2 x R^4 x S^1", NormalForm(r=6, t=1)),
        ("R", NormalForm(r=1)),
        ("T^2", NormalForm(t=2)),
        ("(S^1)^3", NormalForm(t=3)),
        ("RP^3", NormalForm(rp3=1)),
        ("(RP^3)^2 x R^3", NormalForm(r=3, rp3=2)),
        ("SO(3)", NormalForm(rp3=1)),
        ("SO(2)", NormalForm(t=1)),
        ("SE(3) x R^12", NormalForm(r=15, rp3=1)),
        ("SE(2)", NormalForm(r=2, t=1)),
        ("point", NormalForm()),
        ("R^3*RP^3", NormalForm(r=3, rp3=1)),
    ],
)
def test_notation_is_read_up_to_the_order_of_factors(text: str, expected: NormalForm) -> None:
    assert parse_notation(text) == expected


@pytest.mark.parametrize("text", ["", "  ", "R^6 ×", "x R", "S^2", "Q", "R^-1", "T", "RP^2"])
def test_notation_that_is_not_a_product_is_refused(text: str) -> None:
    with pytest.raises(NotationError):
        parse_notation(text)


@given(st.integers(0, 30), st.integers(0, 30), st.integers(0, 5))
def test_notation_round_trips_what_cspace_writes(r: int, t: int, rp3: int) -> None:
    form = NormalForm(r=r, t=t, rp3=rp3)
    assert parse_notation(form.notation) == form
    assert parse_notation(form.ascii) == form


def test_expectation_failures_say_what_differs() -> None:
    form = NormalForm(r=6, t=1)
    assert expectation_failures(form, NormalForm(r=6, t=1), 7) == []
    assert expectation_failures(form, NormalForm(r=7), 8) == [
        "C-space is R^6 × S^1, expected R^7",
        "dimension is 7, expected 8",
    ]


def test_check_passes_and_says_so() -> None:
    run = run_cli("check", ARM7, "--expect", "R^6 × T^1", "--dimension", "7")
    assert (run.code, run.stderr) == (0, "")
    assert run.stdout == f"ok: {ARM7}: R^6 × S^1, dimension 7\n"


def test_check_fails_with_one_line() -> None:
    # "our arm is 7-DOF and has no continuous joints": arm7's wrist is continuous.
    run = run_cli("check", ARM7, "--expect", "R^7", "--dimension", "7")
    assert run.code == 1
    assert run.stdout == ""
    assert run.stderr == f"cspace: check failed: {ARM7}: C-space is R^6 × S^1, expected R^7\n"
    run = run_cli("check", ARM7, "--dimension", "6")
    assert run.code == 1
    assert "dimension is 7, expected 6" in run.stderr


def test_check_reads_saved_reports_and_other_formats(tmp_path: Path) -> None:
    saved = tmp_path / "arm7.json"
    saved.write_text(cspace.inspect(ARM7).to_json())
    assert run_cli("check", str(saved), "--expect", "R^6xS^1").code == 0
    mjcf = str(ROBOTS / "mjcf_every_joint.xml")
    assert run_cli("check", mjcf, "--expect", "SE(3) x R^7 x S^1 x RP^3").code == 0
    run = run_cli("check", "-", "--dimension", "7", stdin=(ROBOTS / "arm7.urdf").read_bytes())
    assert run.code == 0


def test_check_usage_errors_exit_2() -> None:
    assert run_cli("check", ARM7).code == 2
    run = run_cli("check", ARM7, "--expect", "S^2 x R")
    assert run.code == 2
    assert "'S^2' is not a factor" in run.stderr
    run = run_cli("check", "missing.urdf", "--dimension", "1")
    assert run.code == 2 and "missing.urdf" in run.stderr


@pytest.mark.parametrize("bad", ["-1", "seven", "7.5"])
def test_a_dimension_that_is_not_a_whole_number_is_a_usage_error(bad: str) -> None:
    run = run_cli("check", "robots/arm7.urdf", "--dimension", bad)
    assert run.code == 2
    assert run.stderr.count("\n") == 1
    assert f"invalid dimension value: '{bad}'" in run.stderr
