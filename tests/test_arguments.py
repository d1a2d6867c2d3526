"""Bad arguments to the configuration operations, other than the configurations.

Counts, generators, sampling bounds, metric weights, tolerances, the interpolation
parameter t, ``out=`` arrays, batches beyond ``cspace.MAX_ARRAY_BYTES``; and sampling
that does not depend on chunking nor touch global random state. Each bad argument
raises its own CspaceError subclass, also the matching builtin.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_inputs import ARM, BOX, IDENTITY, MJCF, QUAD, raises, rng, unbounded

import cspace
from cspace import rotations
from cspace.space import ConfigurationSpace

# --- counts, generators, bounds, weights, tolerances, t ----------------------------


@pytest.mark.parametrize("n", [2.0, "2", True, None, np.float64(2)])
def test_a_count_must_be_an_integer(n: object) -> None:
    raises(cspace.errors.ArgumentTypeError, lambda: ARM.sample(n, rng()), "integer")  # type: ignore[arg-type]


@pytest.mark.parametrize("n", [-1, np.int64(-5), 2**63, 10**400])
def test_a_count_must_be_in_range(n: int) -> None:
    error = raises(cspace.errors.ArgumentError, lambda: ARM.sample(n, rng()))
    assert isinstance(error, ValueError) and not isinstance(error, TypeError)


@pytest.mark.parametrize(
    "generator", [42, None, "seed", np.random.RandomState(0), np.random.PCG64(0)]
)
def test_randomness_comes_only_from_a_generator(generator: object) -> None:
    error = raises(
        cspace.errors.ArgumentTypeError,
        lambda: ARM.sample(2, generator),  # type: ignore[arg-type]
        "rng must be a numpy.random.Generator",
    )
    assert isinstance(error, TypeError)


@pytest.mark.parametrize(
    ("bounds", "kind"),
    [
        ([1, 2], cspace.errors.ArgumentTypeError),
        ({"body_free.x": 1.0}, cspace.errors.ArgumentTypeError),
        ({"body_free.x": ("a", 1.0)}, cspace.errors.ArgumentTypeError),
        ({"body_free.x": (True, 1.0)}, cspace.errors.ArgumentTypeError),
        ({"body_free.x": (np.nan, 1.0)}, cspace.errors.ArgumentError),
        ({"body_free.x": (-np.inf, 1.0)}, cspace.errors.ArgumentError),
        ({"body_free.x": (2.0, 1.0)}, cspace.errors.ArgumentError),
        ({"body_free.x": (-1e308, 1e308)}, cspace.errors.ArgumentError),  # the span overflows
        ({"prop_fl_spin": (-4.0, 4.0)}, cspace.errors.ArgumentError),  # more than a turn
        ({"body_free.qw": (0.0, 1.0)}, cspace.errors.UnknownJointError),
    ],
)
def test_bad_bounds_are_refused_before_drawing(bounds: object, kind: type) -> None:
    full = {**BOX, **bounds} if isinstance(bounds, dict) else bounds
    generator = rng()
    raises(kind, lambda: QUAD.sample(3, generator, full))  # type: ignore[arg-type]
    assert generator.random() == rng().random()  # nothing was drawn


def test_bounds_can_narrow_limits_but_not_leave_them() -> None:
    x = ARM.sample(200, rng(), {"elbow": (-1.0, -0.5)})
    assert np.all((x[:, 3] >= -1.0) & (x[:, 3] <= -0.5))
    error = raises(
        cspace.errors.ArgumentError, lambda: ARM.sample(2, rng(), {"elbow": (-5.0, 5.0)})
    )
    assert error.coordinate == "elbow" and "limits" in str(error)


@pytest.mark.parametrize(
    ("weight", "kind"),
    [
        (-1.0, cspace.errors.ArgumentError),
        (np.nan, cspace.errors.ArgumentError),
        (np.inf, cspace.errors.ArgumentError),
        (1e200, cspace.errors.ArgumentError),  # its square overflows
        (10**400, cspace.errors.ArgumentError),
        ("2", cspace.errors.ArgumentTypeError),
        (True, cspace.errors.ArgumentTypeError),
        (None, cspace.errors.ArgumentTypeError),
    ],
)
def test_bad_weights_are_refused(weight: object, kind: type) -> None:
    error = raises(kind, lambda: QUAD.with_weights({"body_free": weight}))  # type: ignore[dict-item]
    assert error.coordinate == "body_free"


def test_weights_are_checked_however_the_space_is_made() -> None:
    raises(cspace.errors.ArgumentTypeError, lambda: QUAD.with_weights([1.0, 2.0]))  # type: ignore[arg-type]
    raises(cspace.errors.UnknownJointError, lambda: QUAD.with_weights({"nope": 1.0}))
    n = len(QUAD.slots)
    raises(cspace.errors.ArgumentError, lambda: dataclasses.replace(QUAD, weights=(1.0,) * (n - 1)))
    raises(cspace.errors.ArgumentError, lambda: dataclasses.replace(QUAD, weights=(np.nan,) * n))
    raises(cspace.errors.ArgumentTypeError, lambda: dataclasses.replace(QUAD, weights=None))
    for tolerance in (1.0, -1e-9, np.nan):  # at 1, a zero quaternion would pass as unit
        raises(
            cspace.errors.ArgumentError, lambda t=tolerance: dataclasses.replace(QUAD, tolerance=t)
        )
    heavy = QUAD.with_weights({"body_free.rotation": 1e150})
    assert heavy.distance(QUAD.neutral(), QUAD.neutral()) == 0.0


@pytest.mark.parametrize("tolerance", [np.nan, -0.1, np.inf, "0.1", None])
def test_bad_tolerances_are_refused(tolerance: object) -> None:
    for call in (
        lambda: ARM.contains(ARM.neutral(), tolerance),  # type: ignore[arg-type]
        lambda: ARM.check(ARM.neutral(), tolerance),  # type: ignore[arg-type]
        lambda: rotations.is_rotation_matrix(np.eye(3), tolerance),  # type: ignore[arg-type]
    ):
        raises(cspace.errors.ArgumentError, call, "tolerance")


def test_bad_interpolation_parameters_are_refused() -> None:
    a, b = ARM.neutral(), ARM.sample(1, rng())[0]
    raises(cspace.errors.ArgumentTypeError, lambda: ARM.interpolate(a, b, "0.5"))
    raises(cspace.errors.ArgumentTypeError, lambda: ARM.interpolate(a, b, 0.5 + 0j))
    raises(cspace.errors.ArgumentTypeError, lambda: ARM.interpolate(a, b, True))
    error = raises(
        cspace.errors.NonFiniteValueError, lambda: ARM.interpolate(a, b, [0.0, 0.5, np.nan])
    )
    assert error.row == 2
    raises(cspace.ConfigurationError, lambda: ARM.interpolate(np.tile(a, (3, 1)), b, [0.0, 1.0]))
    assert ARM.interpolate(a, b, []).shape == (0, ARM.size)


# --- out= ----------------------------------------------------------------------------


def test_out_may_not_overlap_what_is_read() -> None:
    a = QUAD.sample(6, rng(), BOX)
    b = QUAD.sample(6, rng(), BOX)
    raises(cspace.errors.ArgumentError, lambda: QUAD.interpolate(a, b, 0.5, out=a), "overlaps")
    raises(cspace.errors.ArgumentError, lambda: QUAD.interpolate(a, b, 0.5, out=b), "overlaps")
    raises(cspace.errors.ArgumentError, lambda: QUAD.distance(a, b, out=a.reshape(-1)[:6]))
    buffer = np.vstack([a, a[:1]])
    raises(cspace.errors.ArgumentError, lambda: QUAD.canonicalize(buffer[:-1], out=buffer[1:]))
    raises(cspace.errors.ConfigurationShapeError, lambda: QUAD.distance(a, b, out=np.empty(6, int)))
    raises(cspace.errors.ConfigurationShapeError, lambda: QUAD.distance(a, b, out=[0.0] * 6))
    flipped = a.copy()
    flipped[:, 3:7] *= -1.0
    assert QUAD.canonicalize(flipped, out=flipped) is flipped  # in place is fine
    np.testing.assert_array_equal(flipped, a)


# --- sizes ---------------------------------------------------------------------------


def test_sizes_are_checked_before_allocating() -> None:
    error = raises(MemoryError, lambda: ARM.sample(10**9, rng()))
    assert isinstance(error, cspace.errors.SizeLimitError)
    assert (error.requested, error.limit) == (10**9 * ARM.size * 8, cspace.MAX_ARRAY_BYTES)
    assert str(error) == (
        "sample(1,000,000,000) would need 52.2 GiB, more than the 1.0 GiB cspace allocates "
        "at once; ask for fewer or in chunks"
    )
    x, n = ARM.neutral(), ARM.size
    rows = np.broadcast_to(x, (10**9, n))  # a view: no memory of its own
    many = np.broadcast_to(x, (10**5, 1, n))
    h = np.broadcast_to(IDENTITY, (10**5, 1, 4))
    for call in (
        lambda: ARM.canonicalize(rows),
        lambda: ARM.distance(many, many.reshape(1, 10**5, n)),
        lambda: ARM.interpolate(x, x, np.broadcast_to(0.5, (10**9,))),
        lambda: ARM.interpolate(many, x, np.broadcast_to(0.5, (1, 10**5))),
        lambda: ARM.to_pinocchio(rows),
        lambda: rotations.multiply(h, h.reshape(1, 10**5, 4)),
        lambda: rotations.angle_between(h, h.reshape(1, 10**5, 4)),
        lambda: rotations.matrix_from_quaternion(np.broadcast_to(IDENTITY, (10**8, 4))),
    ):
        raises(cspace.errors.SizeLimitError, call, "more than the 1.0 GiB")


# --- empty batches, other arguments ---------------------------------------------------


def test_empty_batches_give_empty_results() -> None:
    none, x = np.zeros((0, QUAD.size)), QUAD.neutral()
    assert QUAD.sample(0, rng(), BOX).shape == (0, QUAD.size)
    assert QUAD.canonicalize(none).shape == (0, QUAD.size)
    assert QUAD.distance(none, x).shape == (0,)
    assert QUAD.interpolate(x, none, 0.5).shape == (0, QUAD.size)
    assert QUAD.difference(none, x).shape == (0, QUAD.dimension)
    assert QUAD.integrate(x, np.zeros((0, QUAD.dimension))).shape == (0, QUAD.size)
    assert QUAD.contains(none).shape == (0,)
    assert QUAD.to_pinocchio(none).shape == (0, QUAD.nq)
    assert rotations.exp(np.zeros((0, 3))).shape == (0, 4)


def test_mappings_names_and_reports_of_the_wrong_kind_are_refused() -> None:
    x = ARM.neutral()
    raises(cspace.errors.JointValueError, lambda: ARM.from_dict({"elbow": 10**400}, default=x))
    raises(cspace.errors.JointValueError, lambda: ARM.from_dict([("elbow", 0.0)]))  # type: ignore[arg-type]
    raises(
        cspace.errors.ConfigurationShapeError, lambda: ARM.from_dict({}, default=np.tile(x, (2, 1)))
    )
    raises(cspace.errors.ArgumentTypeError, lambda: ARM.matrix(x, np.zeros(3)))  # type: ignore[arg-type]
    raises(cspace.errors.ArgumentTypeError, lambda: ConfigurationSpace.from_report(3))  # type: ignore[arg-type]


# --- sampling: chunks, determinism, no global state -----------------------------------


@settings(max_examples=40, derandomize=True, database=None, deadline=None)
@given(
    st.sampled_from([QUAD, MJCF, ARM]),
    st.lists(st.integers(0, 40), min_size=1, max_size=6),
    st.integers(0, 2**63 - 1),
)
def test_sampling_in_chunks_gives_the_same_configurations(
    space: ConfigurationSpace, chunks: list[int], seed: int
) -> None:
    bounds = unbounded(space)
    whole = space.sample(sum(chunks), np.random.default_rng(seed), bounds)
    generator = np.random.default_rng(seed)
    parts = [space.sample(k, generator, bounds) for k in chunks]
    assert np.concatenate(parts).tobytes() == whole.tobytes()
    first = space.sample(chunks[0], np.random.default_rng(seed), bounds)
    assert first.tobytes() == whole[: chunks[0]].tobytes()  # a prefix, whatever follows


def test_sampling_leaves_global_random_state_alone() -> None:
    import random

    numpy_state, python_state = np.random.get_state(), random.getstate()
    QUAD.sample(100, rng(), BOX)
    MJCF.sample(100, rng(), unbounded(MJCF))
    after = np.random.get_state()
    assert all(np.array_equal(x, y) for x, y in zip(numpy_state, after, strict=True))
    assert random.getstate() == python_state
    assert QUAD.sample(5, rng(), BOX).tobytes() == QUAD.sample(5, rng(), BOX).tobytes()


def test_the_argument_errors_are_exported_and_match_their_builtins() -> None:
    for name, builtin in (
        ("ArgumentError", ValueError),
        ("ArgumentTypeError", TypeError),
        ("SizeLimitError", MemoryError),
        ("ValueOverflowError", OverflowError),
    ):
        assert name in cspace.errors.__all__
        kind = getattr(cspace.errors, name)
        assert issubclass(kind, cspace.ConfigurationError)
        assert issubclass(kind, builtin) and issubclass(kind, ValueError)
    assert "MAX_ARRAY_BYTES" in cspace.__all__ and cspace.MAX_ARRAY_BYTES == 2**30
