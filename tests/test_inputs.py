"""Bad input to the configuration operations: a specific CspaceError, never anything else.

Every public operation of ConfigurationSpace and every function of cspace.space._geometry.rotations,
fed wrong types, dtypes, shapes, NaN and infinities, zero and non-unit quaternions, and
values whose results overflow (the other arguments: test_arguments.py), and a sweep of
hostile inputs over every operation. Each must raise its own CspaceError subclass
(which is also the matching builtin: ValueError, TypeError, MemoryError, OverflowError)
with a one-line message, or give a finite answer: never a NumPy, numba or Python error,
a RuntimeWarning, or NaN.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cspace
from cspace import rotations
from cspace.space import ConfigurationSpace
from cspace.space._geometry.factors import Line

from conftest import ROBOTS

QUAD = cspace.load(str(ROBOTS / "quadrotor_floating.urdf"))  # R^3 x SO(3) x (S^1)^4
MJCF = cspace.load(str(ROBOTS / "mjcf_every_joint.xml"))  # a limited ball, a free joint, ...
ARM = cspace.load(str(ROBOTS / "arm7.urdf"))  # intervals and one S^1
POINT = cspace.load(str(ROBOTS / "sensor_head_fixed.urdf"))  # no coordinates at all
BOX = {"body_free.x": (-1.0, 1.0), "body_free.y": (-1.0, 1.0), "body_free.z": (0.0, 2.0)}
IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def rng() -> np.random.Generator:
    return np.random.default_rng(7)


def unbounded(space: ConfigurationSpace) -> dict[str, tuple[float, float]]:
    return {
        s.name: (-2.0, 2.0)
        for s in space.slots
        if isinstance(s.factor, Line) and not s.factor.bounded
    }


def with_quaternion(h: np.ndarray, rows: int | None = None, row: int = 0) -> np.ndarray:
    """QUAD's neutral configuration (or a batch of them) whose base quaternion is h."""
    x = QUAD.neutral() if rows is None else np.tile(QUAD.neutral(), (rows, 1))
    (x if rows is None else x[row])[3:7] = h
    return x


def one_line(error: BaseException) -> str:
    text = str(error)
    assert text and "\n" not in text and len(text) < 400, text
    return text


def raises(kind: type[BaseException], call: Callable[[], object], match: str | None = None) -> Any:
    """The error ``call`` raises: ``kind``, a CspaceError, with a one-line message."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a RuntimeWarning is a failure too
        with pytest.raises(kind, match=match) as info:
            call()
    assert isinstance(info.value, cspace.CspaceError)
    one_line(info.value)
    return info.value


# --- quaternions -------------------------------------------------------------------


def quaternion_operations(bad: np.ndarray) -> Iterator[tuple[str, Callable[[], object]]]:
    """Every operation that takes a configuration (or a quaternion), given ``bad`` in it."""
    x, q = with_quaternion(bad), QUAD.neutral()
    pin = QUAD.to_pinocchio(q)
    pin[3:7] = np.roll(bad, -1)
    yield "canonicalize", lambda: QUAD.canonicalize(x)
    yield "distance a", lambda: QUAD.distance(x, q)
    yield "distance b", lambda: QUAD.distance(q, x)
    for t in (0.0, 0.5, 1.0):
        yield f"interpolate a t={t}", lambda t=t: QUAD.interpolate(x, q, t)
        yield f"interpolate b t={t}", lambda t=t: QUAD.interpolate(q, x, t)
    yield "difference", lambda: QUAD.difference(x, q)
    yield "integrate", lambda: QUAD.integrate(x, np.zeros(QUAD.dimension))
    yield "contains", lambda: QUAD.contains(x)
    yield "check", lambda: QUAD.check(x)
    yield "to_pinocchio", lambda: QUAD.to_pinocchio(x)
    yield "from_pinocchio", lambda: QUAD.from_pinocchio(pin)
    yield "to_dict", lambda: QUAD.to_dict(x)
    yield "from_dict", lambda: QUAD.from_dict({"body_free": [0, 0, 0, *bad]}, default=q)
    yield "matrix", lambda: QUAD.matrix(x, "body_free")
    yield "with_matrix", lambda: QUAD.with_matrix(x, "body_free", np.eye(3))
    for name in ("canonicalize", "conjugate", "log", "xyzw_from_wxyz", "matrix_from_quaternion"):
        yield f"rotations.{name}", functools.partial(getattr(rotations, name), bad)
    yield "rotations.wxyz_from_xyzw", lambda: rotations.wxyz_from_xyzw(np.roll(bad, -1))
    for name in ("multiply", "angle_between"):
        f = getattr(rotations, name)
        yield f"rotations.{name} h1", lambda f=f: f(bad, IDENTITY)
        yield f"rotations.{name} h2", lambda f=f: f(IDENTITY, bad)
    yield "rotations.slerp", lambda: rotations.slerp(bad, IDENTITY, 0.5)


@pytest.mark.parametrize("scale", [0.0, 1e-300, 0.5, 1.0 + 1e-5, 2.0, 1e200])
def test_a_zero_or_non_unit_quaternion_is_refused_everywhere(scale: float) -> None:
    bad = scale * np.array([0.5, 0.5, 0.5, 0.5])
    for name, call in quaternion_operations(bad):
        error = raises(cspace.errors.NotUnitQuaternionError, call)
        assert error.tolerance == rotations.UNIT_TOLERANCE, name
        assert "norm" in str(error), name


@settings(max_examples=80, derandomize=True, database=None, deadline=None)
@given(
    st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4),
    st.one_of(st.floats(0.0, 1.0 - 2e-6), st.floats(1.0 + 2e-6, 1e150)),
    st.integers(0, 4),
)
def test_non_unit_quaternions_in_a_batch_name_their_row(
    direction: list[float], norm: float, row: int
) -> None:
    h = np.array(direction)
    length = float(np.linalg.norm(h))
    h = IDENTITY * norm if length < 1e-3 else h / length * norm
    batch = with_quaternion(h, rows=5, row=row)
    good = np.tile(QUAD.neutral(), (5, 1))
    for call in (
        lambda: QUAD.distance(batch, good),
        lambda: QUAD.interpolate(good, batch, 0.25),
        lambda: QUAD.canonicalize(batch),
        lambda: rotations.angle_between(batch[:, 3:7], good[:, 3:7]),
    ):
        assert raises(cspace.errors.NotUnitQuaternionError, call).row == row


# --- types, dtypes, shapes, non-finite values --------------------------------------

WRONG_DTYPES = {
    "strings": np.full(ARM.size, "1.0"),
    "objects": np.array([0.0] * ARM.size, dtype=object),
    "complex": np.zeros(ARM.size, dtype=complex),
    "bools": np.zeros(ARM.size, dtype=bool),
    "bytes": np.zeros(ARM.size, dtype="S3"),
    "none": None,
    "huge ints": [10**400] * ARM.size,
    "ragged": [[0.0] * ARM.size, [0.0]],
}


@pytest.mark.parametrize("value", list(WRONG_DTYPES.values()), ids=list(WRONG_DTYPES))
def test_arrays_of_anything_but_real_numbers_are_refused(value: object) -> None:
    x = ARM.neutral()
    for call in (
        lambda: ARM.canonicalize(value),
        lambda: ARM.distance(x, value),
        lambda: ARM.interpolate(value, x, 0.5),
        lambda: ARM.interpolate(x, x, value),
        lambda: ARM.difference(x, value),
        lambda: ARM.integrate(x, value),
        lambda: ARM.contains(value),
        lambda: ARM.to_pinocchio(value),
        lambda: ARM.from_pinocchio(value),
        lambda: ARM.with_matrix(x, "wrist_roll", value),
    ):
        error = raises(cspace.errors.ArgumentTypeError, call, "array of")
        assert isinstance(error, TypeError) and isinstance(error, ValueError)


def test_real_dtypes_and_lists_give_the_float64_answer() -> None:
    a = ARM.sample(4, rng())
    b = ARM.sample(4, np.random.default_rng(8))
    expected = ARM.distance(a, b)
    for convert in (np.float32, np.longdouble):
        np.testing.assert_allclose(ARM.distance(a.astype(convert), b), expected, rtol=1e-6)
    assert ARM.distance(np.zeros(ARM.size, dtype=np.int8), [0] * ARM.size) == 0.0
    assert ARM.distance(a.tolist(), b.tolist()).tolist() == expected.tolist()


@pytest.mark.parametrize(
    "shape", [(), (QUAD.size - 1,), (QUAD.size + 1,), (3, 2), (2, QUAD.size, 1)]
)
def test_wrong_shapes_are_refused(shape: tuple[int, ...]) -> None:
    x = np.zeros(shape)
    q = QUAD.neutral()
    for call in (
        lambda: QUAD.canonicalize(x),
        lambda: QUAD.distance(q, x),
        lambda: QUAD.interpolate(x, q, 0.5),
        lambda: QUAD.from_pinocchio(x),
        lambda: rotations.canonicalize(x),
        lambda: rotations.exp(x),
        lambda: rotations.quaternion_from_matrix(x),
        lambda: rotations.is_rotation_matrix(x),
    ):
        raises(cspace.errors.ConfigurationShapeError, call)
    raises(cspace.ConfigurationError, lambda: QUAD.distance(np.zeros((2, 11)), np.zeros((3, 11))))


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_values_are_named_with_their_coordinate_and_row(value: float) -> None:
    batch = np.tile(QUAD.neutral(), (3, 1))
    batch[2, 7] = value
    for call in (
        lambda: QUAD.distance(batch, QUAD.neutral()),
        lambda: QUAD.interpolate(batch, batch, 0.0),
        lambda: QUAD.difference(batch, batch),
        lambda: QUAD.check(batch),
    ):
        error = raises(cspace.errors.NonFiniteValueError, call, QUAD.names[7])
        assert (error.coordinate, error.row) == (QUAD.names[7], 2)
    raises(cspace.errors.NonFiniteValueError, lambda: rotations.exp(np.array([0.0, value, 0.0])))
    raises(cspace.errors.NonFiniteValueError, lambda: rotations.slerp(IDENTITY, IDENTITY, value))


def test_results_beyond_a_double_are_an_overflow_error() -> None:
    low, high = np.full(ARM.size, -1e308), np.full(ARM.size, 1e308)
    calls = {
        "difference": lambda: ARM.difference(low, high),
        "integrate": lambda: ARM.integrate(high, high),
        "distance": lambda: ARM.distance(low, high),
        "interpolate": lambda: ARM.interpolate(ARM.neutral(), np.full(ARM.size, 100.0), 1e308),
        "exp": lambda: rotations.exp(np.array([1e300, 1e300, 0.0])),
        "slerp": lambda: rotations.slerp(IDENTITY, IDENTITY, 1e308),
    }
    for name, call in calls.items():
        error = raises(cspace.errors.ValueOverflowError, call)
        assert isinstance(error, OverflowError), name
    assert "1e154" in str(raises(cspace.errors.ValueOverflowError, calls["distance"]))


# --- every operation against a menu of hostile inputs ---------------------------------


def hostile(n: int) -> list[object]:
    z = np.zeros(n)
    return [
        None, "abc", 3, [], [[]], np.zeros(0), np.zeros((0, n)), np.zeros((2, 0)),
        z.astype(np.float32), z.astype(np.int8), np.full(n, np.longdouble("1e400")),
        np.full(n, np.nan), np.full(n, np.inf), np.full(n, 1e308), np.full(n, -1e308),
        np.full(n, 1e200), np.full(n, 5e-324), z, np.zeros((3, n)), np.zeros((2, 3, n)),
        np.zeros(n + 1), np.ones((n, n)), np.zeros((3, 2 * n))[:, ::2], {"a": 1},
        np.broadcast_to(z, (10**9 if n else 10**5, n)),  # no memory; 1e9 empty rows take time
    ]  # fmt: skip


def operations(space: ConfigurationSpace, bad: object) -> Iterator[Callable[[], object]]:
    x = space.neutral()
    yield lambda: space.canonicalize(bad)  # type: ignore[arg-type]
    yield lambda: space.distance(bad, x)  # type: ignore[arg-type]
    yield lambda: space.interpolate(x, bad, 0.5)  # type: ignore[arg-type]
    yield lambda: space.interpolate(x, x, bad)  # type: ignore[arg-type]
    yield lambda: space.difference(bad, x)  # type: ignore[arg-type]
    yield lambda: space.integrate(x, bad)  # type: ignore[arg-type]
    yield lambda: space.contains(bad)  # type: ignore[arg-type]
    yield lambda: space.check(bad)  # type: ignore[arg-type]
    yield lambda: space.to_pinocchio(bad)  # type: ignore[arg-type]
    yield lambda: space.from_pinocchio(bad)  # type: ignore[arg-type]
    yield lambda: space.to_dict(bad)  # type: ignore[arg-type]
    yield lambda: space.from_dict({}, default=bad)  # type: ignore[arg-type]
    yield lambda: space.canonicalize(x, out=bad)  # type: ignore[arg-type]
    yield lambda: space.distance(x, x, out=bad)  # type: ignore[arg-type]
    yield lambda: space.sample(2, rng(), bad)  # type: ignore[arg-type]
    yield lambda: space.with_weights(bad)  # type: ignore[arg-type]
    for slot in space.slots:
        if not isinstance(slot.factor, Line):
            yield lambda s=slot.name: space.matrix(bad, s)  # type: ignore[arg-type]
            yield lambda s=slot.name: space.with_matrix(x, s, bad)  # type: ignore[arg-type]
    for name in ("canonicalize", "log", "exp", "quaternion_from_matrix", "is_rotation_matrix"):
        yield functools.partial(getattr(rotations, name), bad)
    yield lambda: rotations.slerp(IDENTITY, IDENTITY, bad)  # type: ignore[arg-type]


@pytest.mark.parametrize("space", [QUAD, MJCF, ARM, POINT], ids=lambda s: s.robot)
def test_hostile_inputs_give_a_cspace_error_or_a_finite_answer(space: ConfigurationSpace) -> None:
    for bad in hostile(space.size):
        for call in operations(space, bad):
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                try:
                    result = call()
                except cspace.CspaceError as error:
                    one_line(error)
                    continue
            if isinstance(result, np.ndarray) and result.dtype.kind == "f":
                assert np.isfinite(result).all(), (space.robot, bad)
