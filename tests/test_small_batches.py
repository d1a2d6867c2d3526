"""Small batches run in plain Python (cspace.space._compute.rowwise), large ones in numba kernels.

The two paths must give the same answers: canonical forms and interpolated points
bit for bit (distances too), the same error for the same bad row. A one-pair
call must not import numba at all, and a read-only input must not compile a new kernel.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from test_space import CASES, case_id, other_representatives, space_of, tangent, unbounded

import cspace
from cspace.space._compute import kernels as kernels  # kernels loaded: larger batches run in them
from cspace.space._compute import rowwise as rowwise
from cspace.space._geometry.factors import Circle, Rotation

ROWS = 3 * rowwise.SMALL_ROWS + 5  # a batch for the kernels; each row alone is small


def _pairs(space: cspace.ConfigurationSpace, seed: int) -> tuple[np.ndarray, ...]:
    """Rows a (other representatives), b (some antipodal or half a turn away) and t."""
    rng = np.random.default_rng(seed)
    a = space.sample(ROWS, rng, unbounded(space))
    b = space.integrate(a, tangent(space, rng, (ROWS,), "antipodal"))
    b[::3] = space.integrate(a[::3], tangent(space, rng, (len(b[::3]),), "near"))
    for s in space.slots:  # exact half turns, both ways round
        if isinstance(s.factor, Circle):
            a[::4, s.column] = -math.pi
            b[::4, s.column] = 0.0
            b[1::4, s.column] = a[1::4, s.column] + math.pi
    t = rng.uniform(-0.5, 1.5, ROWS)
    t[::5], t[1::5] = 0.0, 1.0
    return other_representatives(space, a, rng), b, t


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_one_row_at_a_time_agrees_with_the_kernels(case: tuple[str, str | None]) -> None:
    space = space_of(*case)
    a, b, t = _pairs(space, seed=len(case[0]))
    assert len(a) > rowwise.SMALL_ROWS  # the batch runs in the kernels
    one = range(ROWS)
    canonical = np.array([space.canonicalize(a[i]) for i in one])
    assert canonical.tobytes() == space.canonicalize(a).tobytes()
    points = np.array([space.interpolate(a[i], b[i], t[i]) for i in one])
    assert points.tobytes() == space.interpolate(a, b, t).tobytes()
    small = np.array([space.distance(a[i], b[i]) for i in one])
    assert small.tobytes() == space.distance(a, b).tobytes()
    # one configuration broadcast against several, on both paths
    spread = space.interpolate(a[0], b, t)
    assert space.interpolate(a[0], b[:3], t[:3]).tobytes() == spread[:3].tobytes()
    spread_d = space.distance(a[0], b)
    assert space.distance(a[0], b[:3]).tobytes() == spread_d[:3].tobytes()


def _bad_inputs(space: cspace.ConfigurationSpace) -> list[tuple[str, np.ndarray]]:
    x = space.neutral()
    bad = []
    nan = x.copy()
    nan[-1] = math.nan
    bad.append(("NonFiniteValueError", nan))
    huge = x.copy()
    huge[-1] = math.inf
    bad.append(("NonFiniteValueError", huge))
    for s in space.slots:
        if isinstance(s.factor, Rotation):
            off = x.copy()
            off[s.column : s.column + 4] = 0.0  # a zero quaternion: 1 / 0 in the kernels
            bad.append(("NotUnitQuaternionError", off))
            break
    return bad


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_both_paths_raise_the_same_error_for_the_same_row(case: tuple[str, str | None]) -> None:
    space = space_of(*case)
    good = np.repeat(space.neutral()[None], ROWS, axis=0)
    for expected, row in _bad_inputs(space):
        batch = good.copy()
        batch[7] = row
        calls = {
            "distance": lambda x: space.distance(x, good[: len(x)]),
            "interpolate": lambda x: space.interpolate(good[: len(x)], x, 0.5),
            "canonicalize": lambda x: space.canonicalize(x),
        }
        for name, call in calls.items():
            with pytest.raises(cspace.ConfigurationError) as large:
                call(batch)
            with pytest.raises(cspace.ConfigurationError) as small:
                call(batch[5:8])
            assert type(large.value).__name__ == type(small.value).__name__ == expected, name
            assert (large.value.row, small.value.row) == (7, 2), name


def test_an_overflowing_interpolation_is_named_on_both_paths() -> None:
    space = space_of(*CASES[0])
    a = np.repeat(space.neutral()[None], ROWS, axis=0)
    b = a.copy()
    a[:, 0], b[:, 0] = -1e308, 1e308
    for rows in (a, a[:2]):
        with pytest.raises(cspace.errors.ValueOverflowError):
            space.interpolate(rows, b[: len(rows)], 1e10)


def _in_a_new_interpreter(lines: list[str], robot: str) -> None:
    """Run these lines of Python in a fresh interpreter (sys.argv[1] = robot); must pass."""
    script = "import sys, numpy as np, cspace\nfrom cspace.space._compute import rowwise\n"
    script += "space = cspace.load(sys.argv[1])\nx = space.neutral()\n" + "\n".join(lines)
    done = subprocess.run(
        [sys.executable, "-c", script, robot], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr


def test_a_one_pair_command_does_not_import_numba() -> None:
    lines = [
        "space.distance(x, x); space.interpolate(x, x, [0.0, 0.5]); space.canonicalize(x)",
        "space.sample(1, np.random.default_rng(0))",
        "assert 'numba' not in sys.modules, 'numba was imported'",
        "assert 'scipy' not in sys.modules, 'scipy was imported'",
    ]
    _in_a_new_interpreter(lines, CASES[-2][0])  # talos


def test_a_short_interpolation_waits_for_numba_only_after_many_points() -> None:
    lines = [
        "space.interpolate(x, x, np.linspace(0, 1, 1000))",
        "assert 'numba' not in sys.modules, 'numba was imported for 1000 points'",
        "space.distance(np.repeat(x[None], 9, 0), x)",
        "assert 'numba' in sys.modules, 'distances of 9 rows run in the kernels'",
    ]
    _in_a_new_interpreter(lines, CASES[0][0])


def test_after_the_plain_budget_the_kernels_take_over() -> None:
    lines = [
        "rows = rowwise.PLAIN_NUMBERS // space.size // 2 + 1",
        "space.canonicalize(np.repeat(x[None], rows, 0))",
        "assert 'numba' not in sys.modules",
        "space.canonicalize(np.repeat(x[None], rows, 0))",
        "assert 'numba' in sys.modules, 'the budget is spent: the kernels load'",
    ]
    _in_a_new_interpreter(lines, CASES[0][0])


def test_read_only_input_loads_the_same_compiled_kernel() -> None:
    space = space_of(*CASES[0])
    rng = np.random.default_rng(3)
    a = space.sample(ROWS, rng)
    b = space.sample(ROWS, rng)
    expected = space.distance(a, b)
    before = len(kernels._distance_range.signatures)
    frozen_a, frozen_b = a.copy(), b.copy()
    frozen_a.flags.writeable = False
    frozen_b.flags.writeable = False
    np.testing.assert_array_equal(space.distance(frozen_a, frozen_b), expected)
    single = b.astype(np.float32)
    np.testing.assert_array_equal(
        space.distance(np.asfortranarray(a), single), space.distance(a, single.astype(np.float64))
    )
    assert len(kernels._distance_range.signatures) == before
    assert before == 1


def test_kernels_share_their_helpers_between_threads_and_work_after_fork() -> None:
    import multiprocessing
    from concurrent.futures import ThreadPoolExecutor

    space = space_of(*CASES[-2])  # talos: 39 coordinates
    rng = np.random.default_rng(9)
    box = unbounded(space)
    rows = 20 * kernels.chunk_rows(space.size)
    a, b = space.sample(rows, rng, box), space.sample(rows, rng, box)
    expected = space.distance(a, b)
    with ThreadPoolExecutor(4) as callers:  # several callers at once, one helper pool
        results = list(callers.map(lambda _: space.distance(a, b), range(8)))
    for result in results:
        assert result.tobytes() == expected.tobytes()
    child = multiprocessing.get_context("fork").Process(target=space.distance, args=(a, b))
    child.start()  # its copy of the helper pool has no threads: it must make its own
    child.join(timeout=60)
    assert child.exitcode == 0


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_sampling_is_the_same_on_both_paths_and_as_the_factors_define(
    case: tuple[str, str | None],
) -> None:
    from cspace.space._geometry.layout import assemble
    from cspace.space._sampling import resolve_bounds

    space = space_of(*case)
    box = unbounded(space)
    rows = 3 * kernels.chunk_rows(space.size) + 7  # the kernels, over several chunks
    batch = space.sample(rows, np.random.default_rng(11), box)
    rng = np.random.default_rng(11)
    pieces = [space.sample(rowwise.SMALL_ROWS, rng, box) for _ in range(rows // 8)]
    pieces.append(space.sample(rows % 8, rng, box))
    assert np.concatenate(pieces).tobytes() == batch.tobytes()
    u = np.random.default_rng(11).random((rows, space.layout.draws))
    chosen = resolve_bounds(space, box)
    reference = assemble(
        space.slots,
        np.empty((rows, space.size)),
        "columns",
        lambda slot: slot.factor.from_uniform(u[:, slot.draws], chosen.get(slot.name)),
    )
    np.testing.assert_allclose(batch, reference, rtol=0, atol=4e-16)
    assert np.all(space.contains(batch))
