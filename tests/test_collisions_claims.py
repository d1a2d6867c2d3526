"""What the documentation says of ``cspace collisions``, held to the command.

Each test is a claim of a page (docs/safety.md, docs/cli.md, docs/formats.md) that the
code once broke: the command is run on real files written here, never mocked.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from cspace._formats.mjcf._geom_facts import MAX_GEOMS

from conftest import Run, run_cli

pytestmark = pytest.mark.bounded


def _one_line_error(run: Run, *words: str) -> None:
    """Exit 2, one line on standard error holding ``words``, no traceback."""
    assert run.code == 2, run
    assert run.stdout == ""
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("cspace: error: "), run
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr, run
    for word in words:
        assert word in run.stderr, run.stderr


def test_an_mjcf_model_of_more_geoms_than_read_is_refused_in_one_line(tmp_path: Path) -> None:
    """safety.md: 5,000 geoms a model, "a one-line refusal when cspace collisions asks
    for it" (it was an internal error, a bug's message, exit 2)."""
    path = tmp_path / "many.xml"
    path.write_text(
        '<mujoco><worldbody><body><joint/><replicate count="'
        f'{MAX_GEOMS + 1}" offset=".01 0 0"><geom size=".1"/></replicate></body>'
        "</worldbody></mujoco>"
    )
    assert run_cli("inspect", str(path)).code == 0  # the C-space report needs no geometry
    run = run_cli("collisions", str(path), "-n", "10")
    _one_line_error(run, "many.xml", f"{MAX_GEOMS + 1:,} geoms", "[too-many-elements]")
