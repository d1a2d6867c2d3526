"""Each mechanism with known answers, in every format that can write it, is the same mechanism.

The MJCF files of ``tests/closed`` (the four-bar, the Bennett linkage, the rigid four-hinge
loop, the delta robot; tests/test_closure_mjcf.py holds them to their known answers and to
MuJoCo) are written in SDF, URDF and OpenUSD too (``tests/closed/make_fixtures.py`` writes
all but the four-bar's, which are by hand). For each file: the tree's dimension, the loops
(one cut each), each cut's rows as counted by hand for the kind the format writes (a
revolute loop joint leaves one rotation free: 5 rows; a fixed joint or a weld: 6; a ball,
Drake's ball constraint or MJCF's connect: 3), Grübler-Kutzbach's count from them (tree
minus rows), and the mobility and the constraint Jacobian's rank, which must be the MJCF
file's. URDF has no weld and no revolute loop joint: it cannot write the Bennett or the
rigid loop (Drake's ball constraint is its only cut). Drake, the oracle of its own
dialect, reads the delta's SDF and URDF files to the same tree and constraints.
"""

from __future__ import annotations

import importlib.util
import re
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import NamedTuple

import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import DiscreteContactApproximation, MultibodyPlant

import cspace
from cspace import Report

from conftest import REPO, usd_stages

CLOSED = REPO / "tests" / "closed"

ROWS = {
    "connect": 3,
    "weld": 6,
    "revolute": 5,
    "fixed": 6,
    "spherical": 3,
    "drake:ball_constraint": 3,
}
"""A cut's rows by its kind: 6 less the motions it leaves free."""


class Mechanism(NamedTuple):
    mjcf: str
    tree: int
    mobility: int
    rank: int
    files: dict[str, tuple[str, ...]]
    """Each other format's file and the kinds of its cuts."""


MECHANISMS = {
    "fourbar": Mechanism(
        "fourbar.xml",
        3,
        1,
        2,
        {
            "fourbar.xml": ("connect",),
            "fourbar.sdf": ("revolute",),
            "fourbar_drake.urdf": ("drake:ball_constraint",),
            "fourbar.usda": ("revolute",),
            "fourbar_cut.usda": ("revolute",),
        },
    ),
    "bennett": Mechanism(
        "bennett.xml",
        4,
        1,
        3,
        {"bennett.xml": ("weld",), "bennett.sdf": ("fixed",), "bennett.usda": ("fixed",)},
    ),
    "fourr_rigid": Mechanism(
        "fourr_rigid.xml",
        4,
        0,
        4,
        {
            "fourr_rigid.xml": ("weld",),
            "fourr_rigid.sdf": ("fixed",),
            "fourr_rigid.usda": ("fixed",),
        },
    ),
    "delta": Mechanism(
        "delta.xml",
        21,
        3,
        18,
        {
            "delta.xml": ("connect",) * 6,
            "delta.sdf": ("drake:ball_constraint",) * 6,
            "delta_drake.urdf": ("drake:ball_constraint",) * 6,
            "delta.usda": ("spherical",) * 6,
        },
    ),
}

CASES = [
    pytest.param(name, file, id=file)
    for name, mechanism in MECHANISMS.items()
    for file in mechanism.files
]


@pytest.fixture(scope="module", autouse=True)
def _stages(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """One OpenUSD child for the file's stages, all in ``tests/closed``."""
    yield from usd_stages(tmp_path_factory, CLOSED)


@pytest.fixture(scope="module")
def mjcf() -> dict[str, Report]:
    """Each mechanism's MJCF report, inspected once."""
    return {name: cspace.inspect(CLOSED / m.mjcf) for name, m in MECHANISMS.items()}


@pytest.mark.parametrize(("name", "file"), CASES)
def test_every_format_s_file_is_the_mjcf_mechanism(
    name: str, file: str, mjcf: dict[str, Report]
) -> None:
    mechanism = MECHANISMS[name]
    report = cspace.inspect(CLOSED / file)
    closure = report.closure
    assert closure is not None
    kinds = mechanism.files[file]
    rows = [ROWS[kind] for kind in kinds]
    assert report.manifold.dimension == mechanism.tree
    assert [(c.kind, c.rows) for c in closure.cuts] == list(zip(kinds, rows, strict=True))
    assert closure.loops == len(kinds) and closure.constraint_rows == sum(rows)
    assert closure.grubler == mechanism.tree - sum(rows)
    assert closure.assembled is True
    reference = mjcf[name].closure
    assert reference is not None and reference.rank is not None
    assert (reference.mobility, max(reference.rank)) == (mechanism.mobility, mechanism.rank)
    assert closure.mobility == mechanism.mobility
    assert closure.rank is not None and max(closure.rank) == mechanism.rank


@pytest.mark.parametrize(("file", "weld"), [("delta.sdf", None), ("delta_drake.urdf", "base")])
def test_drake_reads_the_delta_s_drake_files_as_cspace_does(file: str, weld: str | None) -> None:
    """Drake's own plant: the tree's 21 velocities (a URDF's root floats in Drake: welded
    here) and the six ball constraints."""
    plant = MultibodyPlant(0.001)
    plant.set_discrete_contact_approximation(DiscreteContactApproximation.kSap)
    Parser(plant).AddModels(str(CLOSED / file))
    if weld is not None:
        plant.WeldFrames(plant.world_frame(), plant.GetFrameByName(weld))
    plant.Finalize()
    assert plant.num_velocities() == MECHANISMS["delta"].tree
    assert plant.num_constraints() == len(MECHANISMS["delta"].files[file])


def _maker() -> ModuleType:
    spec = importlib.util.spec_from_file_location("make_fixtures", CLOSED / "make_fixtures.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def _split(text: str) -> tuple[list[str], list[float]]:
    """A text's words other than numbers, and its numbers."""
    return NUMBER.split(text), [float(n) for n in NUMBER.findall(text)]


def test_the_committed_files_are_what_make_fixtures_writes() -> None:
    """Numbers within 1e-12: the assembled angles come from a float64 solve, whose last
    bits another machine's BLAS may change."""
    for file, text in _maker().texts().items():
        words, numbers = _split((CLOSED / file).read_text())
        made_words, made_numbers = _split(text)
        assert words == made_words, file
        assert numbers == pytest.approx(made_numbers, rel=0, abs=1e-12), file


@pytest.mark.parametrize("file", ["fourbar.xml", "fourbar.sdf", "fourbar_drake.urdf"])
def test_a_root_joint_added_carries_the_ground_of_the_loop(file: str) -> None:
    """With a floating root joint the ground floats with the loop: 6 + 1 degrees of freedom,
    in every format (MJCF's world has no body frame: the cut is on the root joint's)."""
    closure = cspace.inspect(CLOSED / file, root_joint="floating").closure
    assert closure is not None and (closure.mobility, closure.rank) == (7, (2, 2))
