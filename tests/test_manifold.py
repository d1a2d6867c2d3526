"""The normal form R^a × T^b × (RP^3)^c: notation, dimension, fundamental group."""

from __future__ import annotations

import dataclasses

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cspace import NormalForm

counts = st.integers(min_value=0, max_value=50)


@pytest.mark.parametrize(
    ("form", "notation", "ascii", "group"),
    [
        (NormalForm(), "point", "point", "1"),
        (NormalForm(r=1), "R^1", "R^1", "1"),
        (NormalForm(t=1), "S^1", "S^1", "Z"),
        (NormalForm(t=2), "T^2", "T^2", "Z^2"),
        (NormalForm(rp3=1), "RP^3", "RP^3", "Z/2"),
        (NormalForm(rp3=2), "(RP^3)^2", "(RP^3)^2", "(Z/2)^2"),
        (NormalForm(8, 2, 1), "R^8 × T^2 × RP^3", "R^8 x T^2 x RP^3", "Z^2 × Z/2"),
        (NormalForm(r=3, rp3=1), "R^3 × RP^3", "R^3 x RP^3", "Z/2"),
        (NormalForm(r=2, t=1), "R^2 × S^1", "R^2 x S^1", "Z"),
    ],
)
def test_notation(form: NormalForm, notation: str, ascii: str, group: str) -> None:
    assert form.notation == notation
    assert form.ascii == ascii
    assert form.fundamental_group == group
    assert form.simply_connected == (group == "1")


@given(counts, counts, counts, counts, counts, counts)
def test_product_adds_counts_and_dimensions(a: int, b: int, c: int, d: int, e: int, f: int) -> None:
    x, y = NormalForm(a, b, c), NormalForm(d, e, f)
    product = x * y
    assert product == NormalForm(a + d, b + e, c + f)
    assert product.dimension == x.dimension + y.dimension
    assert product == y * x
    assert NormalForm.product([x, y, NormalForm()]) == product


@given(counts, counts, counts)
def test_dimension_is_a_plus_b_plus_3c(a: int, b: int, c: int) -> None:
    form = NormalForm(a, b, c)
    assert form.dimension == a + b + 3 * c
    assert form.is_point == (a + b + c == 0)
    assert form.counts() == {"R": a, "T": b, "RP3": c}


def test_negative_counts_are_refused() -> None:
    with pytest.raises(ValueError, match="non-negative"):
        NormalForm(r=-1)


def test_a_form_cannot_be_changed() -> None:
    form = NormalForm(1, 2, 3)
    with pytest.raises(dataclasses.FrozenInstanceError):
        form.r = 4  # type: ignore[misc]
    with pytest.raises(AttributeError):
        del form.t
    assert form == NormalForm(1, 2, 3)
