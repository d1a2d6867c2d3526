"""The MuJoCo child a process keeps (`mjcf._compiler.COMPILER`): one for many models, a new one
after a model that passed a bound, and answers that never depend on what came before.

The child's hostile models (bombs, escapes, what it may read) are in
``tests/test_hostile.py`` and ``tests/test_untrusted.py``; the same bounds hold for
each model it compiles as they did for a child of its own.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from test_depth import _mjcf_chain

import cspace
from cspace._confine import kept
from cspace._formats.mjcf import _compiler as mjcf

from conftest import HANG_SECONDS, ROBOTS


def _flat(path: Path, bodies: int) -> str:
    """A model of ``bodies`` bodies side by side, each with a hinge."""
    body = "".join(
        f'<body name="b{i}" pos="{i} 0 0"><joint name="j{i}"/><geom size="0.01"/></body>'
        for i in range(bodies)
    )
    path.write_text(f'<mujoco model="m"><worldbody>{body}</worldbody></mujoco>')
    return str(path)


@pytest.fixture
def starts(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The children started (their pids) while the test runs, from a clean slate."""
    started: list[int] = []
    original = kept.ServingChild.__init__

    def counted(self: kept.ServingChild, *args: object, **kwargs: object) -> None:
        original(self, *args, **kwargs)  # type: ignore[arg-type]
        if args and args[0] == "cspace._formats.mjcf._worker":
            started.append(self.child.pid)

    mjcf.COMPILER.close()
    mjcf._compiled.clear()
    monkeypatch.setattr(kept.ServingChild, "__init__", counted)
    yield started
    mjcf.COMPILER.close()
    mjcf._compiled.clear()


def test_one_child_compiles_every_model_of_a_process(starts: list[int]) -> None:
    files = sorted(str(p) for p in ROBOTS.glob("mjcf_*.xml"))
    done = list(cspace.inspect_many(files, jobs=1))
    assert len(files) >= 10 and all(d.report is not None for d in done)
    assert len(starts) == 1 and mjcf.COMPILER.live_pid() == starts[0]


@pytest.mark.bounded
def test_a_model_past_its_cpu_bound_ends_its_child_not_the_next(
    tmp_path: Path, starts: list[int], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The bound holds for each model; the next one gets a new child and its own report.
    The wall clock is only a hang guard here, so that a busy machine cannot stop the
    compile by it first."""
    limits = mjcf.MJCF_LIMITS._replace(cpu_seconds=1, wall_seconds=float(HANG_SECONDS))
    monkeypatch.setattr(mjcf.COMPILER, "limits", limits)
    deep = str(tmp_path / _mjcf_chain(tmp_path, 1000))  # 1.2 s of MuJoCo's CPU
    small, other = _flat(tmp_path / "small.xml", 3), _flat(tmp_path / "other.xml", 4)
    done = list(cspace.inspect_many([small, deep, other], jobs=1))
    assert done[0].report is not None and done[2].report is not None
    assert done[2].report.nq == 4
    assert str(done[1].error).endswith("MuJoCo used more than 1 s of CPU and was stopped")
    assert len(starts) == 2  # the one the bound killed, and the next model's


def test_a_used_child_out_of_memory_gives_way_to_a_fresh_one(
    tmp_path: Path, starts: list[int]
) -> None:
    """What earlier models left mapped must not decide an answer: a used child that runs
    out of memory hands the model to a fresh one, whose answer stands."""
    small = _flat(tmp_path / "small.xml", 3)
    large = _flat(tmp_path / "large.xml", 3000)  # beyond 512 MiB even in a fresh child
    done = list(cspace.inspect_many([small, large], jobs=1))
    assert done[0].report is not None
    assert "Could not allocate memory" in str(done[1].error)
    assert len(starts) == 2  # the used child, then a fresh one (whose refusal stands)
    mjcf.COMPILER.close()
    alone = list(cspace.inspect_many([large], jobs=1))
    assert str(alone[0].error) == str(done[1].error)
    assert len(starts) == 3  # a fresh child's refusal is not asked again
