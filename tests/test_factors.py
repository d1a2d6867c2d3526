"""One harness: one test per law, each over every factor, batch shape and edge case.

Points are drawn from a seed that Hypothesis chooses, in one of several modes: generic
points; pairs near each other (near-identity rotations, angles a hair apart); pairs near
antipodal (rotations by nearly pi, angles across pi ~ -pi); values exactly at +-pi.
Inputs are deliberately not canonical (angles beyond [-pi, pi), quaternions in either
hemisphere).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cspace import rotations
from cspace.space._geometry.factors import Circle, Line, Rotation

FACTORS = {
    "interval": Line(-1.0, 2.0, "m"),
    "line": Line(),
    "circle": Circle("cos_sin"),
    "circle-angle": Circle("angle"),
    "rotation": Rotation(),
    "ball": Rotation(max_angle=1.0),
}
SHAPES = [(), (3,), (2, 4)]
MODES = ["generic", "near", "antipodal", "pi"]


def raw_points(factor, rng: np.random.Generator, shape, mode: str):
    """A pair (a, b) of non-canonical inputs of shape (*shape, size), in a given mode."""
    eps = 10.0 ** rng.uniform(-12, -3, size=shape)
    if isinstance(factor, Line):
        a = rng.uniform(-3, 3, size=shape)
        b = a + eps if mode == "near" else rng.uniform(-3, 3, size=shape)
        return a[..., None], b[..., None]
    if isinstance(factor, Circle):
        a = rng.uniform(-math.pi, math.pi, size=shape)
        if mode == "near":
            b = a + eps
        elif mode == "antipodal":
            b = a + math.pi - eps
        elif mode == "pi":
            a = np.where(rng.random(shape) < 0.5, math.pi, -math.pi)
            b = rng.choice([math.pi, -math.pi, math.pi - 1e-12, -math.pi + 1e-12], size=shape)
        else:
            b = rng.uniform(-math.pi, math.pi, size=shape)
        k = rng.integers(-3, 4, size=shape)  # other representatives: theta + 2 k pi
        return (a + 2 * math.pi * k)[..., None], b[..., None]
    a = factor.sample(rng, shape)
    axis = rng.standard_normal((*shape, 3))
    axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
    if mode == "near":
        b = rotations.multiply(a, rotations.exp(axis * eps[..., None]))
    elif mode in ("antipodal", "pi"):
        angle = math.pi - (eps if mode == "antipodal" else 0.0)
        b = rotations.multiply(a, rotations.exp(axis * np.asarray(angle)[..., None]))
    else:
        b = factor.sample(rng, shape)
    flip = np.where(rng.random(shape) < 0.5, -1.0, 1.0)[..., None]  # either hemisphere
    return a * flip, b


def equivalent(factor, x: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Another representative of the same configurations."""
    if isinstance(factor, Circle):
        return x + 2 * math.pi * rng.integers(-3, 4, size=x.shape)
    if isinstance(factor, Rotation):
        return -x
    return x.copy()


case = st.tuples(
    st.sampled_from(sorted(FACTORS)),
    st.sampled_from(SHAPES),
    st.sampled_from(MODES),
    st.integers(0, 2**32 - 1),
)


class Draw(NamedTuple):
    """One drawn case: a factor, a batch shape, two non-canonical points and a third."""

    f: Any
    shape: tuple[int, ...]
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    rng: np.random.Generator


def draw(args) -> Draw:
    name, shape, mode, seed = args
    f = FACTORS[name]
    rng = np.random.default_rng(seed)
    a, b = raw_points(f, rng, shape, mode)
    c, _ = raw_points(f, rng, shape, "generic")
    return Draw(f, shape, a, b, c, rng)


LAW = settings(max_examples=120, deadline=None)
"""Each law over every factor, batch shape and mode (Hypothesis picks the cases)."""

TOL = 1e-9


@LAW
@given(case)
def test_canonical_form_is_idempotent_and_one_per_point(args) -> None:
    f, shape, a, _, _, rng = draw(args)
    ca = f.canonicalize(a)
    assert ca.shape == (*shape, f.size)
    assert f.canonicalize(ca).tobytes() == ca.tobytes()
    # theta + 2 k pi: equal to rounding, which near +-pi means equal modulo 2 pi
    np.testing.assert_allclose(
        f.distance(f.canonicalize(equivalent(f, a, rng)), ca), 0.0, atol=1e-12
    )
    if isinstance(f, Circle):
        assert np.all((ca >= -math.pi) & (ca < math.pi))
        away = np.abs(np.abs(ca) - math.pi) > 1e-9
        np.testing.assert_allclose(
            f.canonicalize(equivalent(f, a, rng))[away], ca[away], atol=1e-12
        )
    if isinstance(f, Rotation):
        assert f.canonicalize(-a).tobytes() == ca.tobytes()


@LAW
@given(case)
def test_distance_is_a_metric_on_points_not_representatives(args) -> None:
    f, _, a, b, c, rng = draw(args)
    d = f.distance
    assert np.all(d(a, a) <= TOL)
    np.testing.assert_allclose(d(a, equivalent(f, a, rng)), 0.0, atol=TOL)
    np.testing.assert_allclose(d(a, b), d(b, a), atol=1e-12)
    assert np.all(d(a, b) <= d(a, c) + d(c, b) + TOL)
    np.testing.assert_allclose(d(f.canonicalize(a), f.canonicalize(b)), d(a, b), atol=TOL)
    if f.wraps:
        assert np.all(d(a, b) <= math.pi + 1e-12)


@LAW
@given(case)
def test_interpolation_ends_exactly_and_halves_the_distance(args) -> None:
    f, shape, a, b, _, _ = draw(args)
    d = f.distance
    assert f.interpolate(a, b, np.zeros(shape)).tobytes() == f.canonicalize(a).tobytes()
    assert f.interpolate(a, b, np.ones(shape)).tobytes() == f.canonicalize(b).tobytes()
    mid = f.interpolate(a, b, np.full(shape, 0.5))
    np.testing.assert_allclose(f.canonicalize(mid), mid, atol=1e-15)
    np.testing.assert_allclose(d(a, mid), d(mid, b), atol=1e-8)
    np.testing.assert_allclose(d(a, mid), 0.5 * d(a, b), atol=1e-8)


@LAW
@given(case)
def test_difference_integrates_back_and_its_norm_is_the_distance(args) -> None:
    f, shape, a, b, _, _ = draw(args)
    ca, cb = f.canonicalize(a), f.canonicalize(b)
    v = f.difference(ca, cb)
    assert v.shape == (*shape, f.dimension)
    np.testing.assert_allclose(np.linalg.norm(v, axis=-1), f.distance(a, b), atol=TOL)
    np.testing.assert_allclose(f.distance(f.integrate(ca, v), cb), 0.0, atol=TOL)


@LAW
@given(case)
def test_pinocchio_q_round_trips(args) -> None:
    f, shape, a, _, _, _ = draw(args)
    ca = f.canonicalize(a)
    q = f.to_pinocchio(ca)
    assert q.shape == (*shape, f.pinocchio_size)
    np.testing.assert_allclose(f.from_pinocchio(q), ca, atol=1e-15)


@pytest.mark.parametrize("name", sorted(FACTORS))
@pytest.mark.parametrize("shape", SHAPES)
def test_samples_are_canonical_and_contained(name: str, shape: tuple[int, ...]) -> None:
    f = FACTORS[name]
    bounds = (-5.0, 5.0) if name == "line" else None
    x = f.sample(np.random.default_rng(1), (*shape, 50), bounds)
    assert x.shape == (*shape, 50, f.size)
    assert f.contains(x).all()
    np.testing.assert_array_equal(f.canonicalize(x), x)


def test_interval_contains_respects_bounds_and_tolerance() -> None:
    f = FACTORS["interval"]
    x = np.array([[-1.0], [2.0], [2.0 + 1e-9], [-1.5]])
    assert f.contains(x).tolist() == [True, True, False, False]
    assert f.contains(x, tolerance=1e-6).tolist() == [True, True, True, False]


def test_neutral_is_zero_clipped_into_the_limits() -> None:
    assert Line(0.5, 2.0).neutral().tolist() == [0.5]
    assert Line(-1.0, 2.0).neutral().tolist() == [0.0]
    assert Rotation().neutral().tolist() == [1.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize("shape", SHAPES)
def test_circle_conversions_round_trip(shape: tuple[int, ...]) -> None:
    theta = np.random.default_rng(2).uniform(-math.pi, math.pi, size=(*shape, 1))
    theta.flat[0] = -math.pi
    cs = Circle.cos_sin_from_angle(theta)
    np.testing.assert_allclose(Circle.angle_from_cos_sin(cs), theta, atol=1e-15)
    r = Circle.matrix_from_angle(theta)
    assert r.shape == (*shape, 2, 2)
    np.testing.assert_allclose(Circle.angle_from_matrix(r), theta, atol=1e-15)
    # (cos pi, sin pi) is -pi in canonical form, never +pi
    assert Circle.angle_from_cos_sin(np.array([-1.0, 0.0])).tolist() == [-math.pi]


@pytest.mark.parametrize("shape", SHAPES)
def test_rotation_matrix_conversions_round_trip(shape: tuple[int, ...]) -> None:
    h = Rotation().sample(np.random.default_rng(4), shape)
    np.testing.assert_allclose(
        Rotation.wxyz_from_matrix(Rotation.matrix_from_wxyz(h)), h, atol=1e-14
    )


def test_circle_interpolation_crosses_pi_when_shorter() -> None:
    f = Circle()
    a, b = np.array([3.0]), np.array([-3.0])
    path = f.interpolate(a, b, np.linspace(0, 1, 5))
    # the short way is 2 pi - 6 = 0.283 rad through pi ~ -pi, never through 0
    assert np.all(np.abs(path[:, 0]) >= 3.0 - 1e-12)
    assert f.distance(a, b) == pytest.approx(2 * math.pi - 6)


def test_rotation_interpolation_takes_the_shorter_of_h_and_minus_h() -> None:
    f = Rotation()
    a = rotations.exp(np.array([0.0, 0.0, 3.0]))
    b = -rotations.exp(np.array([0.0, 0.0, -3.0]))  # a rotation 2 pi - 6 away, other sign
    mid = f.interpolate(a, b, np.array(0.5))
    # the midpoint is the half turn about z, not the identity
    np.testing.assert_allclose(mid, [0.0, 0.0, 0.0, 1.0], atol=1e-12)


def test_the_harness_covers_every_factor_kind_and_variant() -> None:
    import typing

    from cspace._factor_kinds import FactorKind
    from cspace.space._geometry.factors import FACTOR_CLASSES

    assert set(FACTOR_CLASSES) == set(FactorKind)  # every kind has its one class
    assert {type(f) for f in FACTORS.values()} == set(FACTOR_CLASSES.values())
    for kind, cls in FACTOR_CLASSES.items():  # sizes come from the kind, declared once
        assert (cls.size, cls.dimension, cls.wraps, cls.notation) == (
            kind.size,
            kind.dimension,
            kind.wraps,
            kind.notation,
        )
    # Every storage of a circle, bounded and unbounded lines, whole and limited rotations.
    encodings = set(typing.get_args(typing.get_type_hints(Circle)["pinocchio"]))
    assert {f.pinocchio for f in FACTORS.values() if isinstance(f, Circle)} == encodings
    assert {f.bounded for f in FACTORS.values() if isinstance(f, Line)} == {True, False}
    maxima = {f.max_angle for f in FACTORS.values() if isinstance(f, Rotation)}
    assert math.pi in maxima and any(m < math.pi for m in maxima)
