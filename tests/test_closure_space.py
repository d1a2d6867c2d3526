"""Configurations on a mechanism with loops: ``space.closure`` and OMPL's constrained planning.

Through the public API only (`cspace.load`, ``space.closure``). The residual's Jacobian
is held to finite differences of the residual along the space's own ``integrate``;
projected and sampled configurations to MuJoCo, the oracle: at them, the equality rows'
``efc_pos`` (MuJoCo's own loop-closure residual) vanish, while at the random
configurations they came from they do not. A planar four-bar's crank (tests/closed/
fourbar.xml, a Grashof crank-rocker) is planned through a full turn on OMPL's
``ProjectedStateSpace``, every state of the path on the mechanism.
"""

from __future__ import annotations

import math
import pickle
import resource

import mujoco
import numpy as np
import pytest

import cspace
from cspace.errors import (
    ArgumentError,
    ArgumentTypeError,
    ConfigurationShapeError,
    NonFiniteValueError,
)

from conftest import REPO, ROBOTS

CLOSED = REPO / "tests" / "closed"

BOUNDS = {"platform.x": (-0.5, 0.5), "platform.y": (-0.5, 0.5), "platform.z": (-1.5, 0.5)}
"""Where the delta robot's free platform is drawn (its lines have no limits)."""


@pytest.fixture(scope="module")
def fourbar() -> cspace.ConfigurationSpace:
    return cspace.load(CLOSED / "fourbar.xml")


@pytest.fixture(scope="module")
def delta() -> cspace.ConfigurationSpace:
    return cspace.load(CLOSED / "delta.xml")


def _closure(space: cspace.ConfigurationSpace) -> cspace.space.Closure:
    closure = space.closure
    assert closure is not None
    return closure


def test_a_tree_and_a_saved_reports_space_have_no_closure() -> None:
    assert cspace.load(ROBOTS / "arm7.urdf").closure is None
    report = cspace.inspect(CLOSED / "fourbar.xml")
    assert report.closure is not None  # the report knows the mechanism ...
    assert cspace.ConfigurationSpace.from_report(report).closure is None  # ... not its model


def test_the_rows_are_the_cuts_and_the_file_pose_closes(fourbar: cspace.ConfigurationSpace) -> None:
    closure = _closure(fourbar)
    assert closure.cuts == ("ground_pivot",) and closure.cut_rows == (3,) and closure.rows == 3
    x = fourbar.neutral()  # the connect pins the rocker's tip where it is at qpos0
    assert closure.is_closed(x) is True
    assert closure.residual(x).shape == (3,)
    moved = x + np.array([0.3, 0.0, 0.0])
    assert closure.is_closed(moved) is False
    assert np.max(np.abs(closure.residual(moved))) > 0.05  # m


@pytest.mark.parametrize("name", ["fourbar.xml", "bennett.xml", "delta.xml"])
def test_the_jacobian_is_the_residuals_rate_along_the_tangent(name: str) -> None:
    space = cspace.load(CLOSED / name)
    closure = _closure(space)
    rng = np.random.default_rng(3)
    bounds = BOUNDS if name == "delta.xml" else None
    points = np.concatenate([closure.sample(2, rng, bounds=bounds), space.sample(2, rng, bounds)])
    h = 1e-6
    for x in points:
        jacobian = closure.jacobian(x)
        assert jacobian.shape == (closure.rows, space.dimension)
        steps = h * np.eye(space.dimension)
        ahead = closure.residual(space.integrate(x, steps))
        behind = closure.residual(space.integrate(x, -steps))
        numeric = ((ahead - behind) / (2 * h)).T
        np.testing.assert_allclose(jacobian, numeric, atol=1e-6 * max(1.0, np.abs(numeric).max()))
        assert np.abs(jacobian).max() > 0.1  # not a Jacobian of zeros


def test_batches_keep_their_leading_shape(fourbar: cspace.ConfigurationSpace) -> None:
    closure = _closure(fourbar)
    x = fourbar.sample(6, np.random.default_rng(1)).reshape(2, 3, fourbar.size)
    assert closure.residual(x).shape == (2, 3, 3)
    assert closure.jacobian(x).shape == (2, 3, 3, fourbar.dimension)
    assert np.asarray(closure.is_closed(x)).shape == (2, 3)
    projected, closed = closure.project(x)
    assert projected.shape == x.shape and np.asarray(closed).shape == (2, 3)
    for i in range(2):  # a batch is its rows, one by one
        np.testing.assert_array_equal(closure.residual(x[i, 1]), closure.residual(x)[i, 1])
        alone, ok = closure.project(x[i, 1])
        np.testing.assert_allclose(alone, projected[i, 1], atol=1e-12)
        assert ok == closed[i, 1]


def test_projection_lands_on_the_mechanism_in_canonical_form(
    fourbar: cspace.ConfigurationSpace,
) -> None:
    closure = _closure(fourbar)
    starts = fourbar.sample(40, np.random.default_rng(7))
    assert not np.any(closure.is_closed(starts))
    projected, closed = closure.project(starts)
    closed = np.asarray(closed)
    assert closed.mean() > 0.8  # a crank-rocker assembles at every crank angle
    assert np.max(np.abs(closure.residual(projected[closed]))) <= 1e-9
    np.testing.assert_array_equal(fourbar.canonicalize(projected), projected)  # wrapped
    few, closed_few = closure.project(starts, max_iterations=2)
    after = np.linalg.norm(closure.residual(few), axis=-1)
    before = np.linalg.norm(closure.residual(starts), axis=-1)
    assert np.all(after <= before) and np.any(after < before)  # steps only lower it
    assert not np.all(closed_few)  # two steps are not enough for every start


def test_samples_are_closed_within_limits_and_cover_the_crank(
    fourbar: cspace.ConfigurationSpace,
) -> None:
    closure = _closure(fourbar)
    found = closure.sample(40, np.random.default_rng(11))
    assert found.shape == (40, fourbar.size)
    assert np.all(closure.is_closed(found)) and np.all(fourbar.contains(found))
    crank = found[:, fourbar.names.index("crank")]
    quarters = np.floor((crank + math.pi) / (math.pi / 2)).astype(int)
    assert set(quarters) == {0, 1, 2, 3}  # the crank turns all the way round
    again = closure.sample(40, np.random.default_rng(11))
    np.testing.assert_array_equal(found, again)  # the generator is the only randomness
    assert closure.sample(0, np.random.default_rng(1)).shape == (0, fourbar.size)
    assert len(closure.sample(5, np.random.default_rng(1), attempts=0)) == 0


def test_bad_arguments_are_the_spaces_errors(fourbar: cspace.ConfigurationSpace) -> None:
    closure = _closure(fourbar)
    with pytest.raises(ConfigurationShapeError):
        closure.residual(np.zeros(4))
    with pytest.raises(ConfigurationShapeError):
        closure.jacobian(np.zeros((2, 2)))
    with pytest.raises(NonFiniteValueError):
        closure.project(np.array([0.0, math.nan, 0.0]))
    with pytest.raises(ArgumentError):
        closure.is_closed(fourbar.neutral(), tolerance=-1.0)
    with pytest.raises(ArgumentError):
        closure.project(fourbar.neutral(), max_iterations=0)
    with pytest.raises(ArgumentError):
        closure.project(fourbar.neutral(), max_iterations=10**6)
    with pytest.raises(ArgumentTypeError):
        closure.sample(3, 42)  # type: ignore[arg-type]
    with pytest.raises(ArgumentError):
        closure.sample(-1, np.random.default_rng(0))


def test_the_closure_survives_pickling(fourbar: cspace.ConfigurationSpace) -> None:
    x = fourbar.sample(3, np.random.default_rng(2))
    fourbar.conventions()  # caches in the layout what a pickle leaves out
    copy = pickle.loads(pickle.dumps(fourbar))
    np.testing.assert_array_equal(_closure(copy).residual(x), _closure(fourbar).residual(x))


def _mujoco_residual(space: cspace.ConfigurationSpace, name: str, x: np.ndarray) -> np.ndarray:
    """The largest |efc_pos| of MuJoCo's equality rows at each configuration."""
    model = mujoco.MjModel.from_xml_path(str(CLOSED / name))
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    data = mujoco.MjData(model)
    conventions = space.conventions()
    worst = []
    for row in x:
        data.qpos[:] = conventions.to_mujoco(row)
        mujoco.mj_forward(model, data)
        rows = data.efc_type[: data.nefc] == int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)
        assert rows.sum() == _closure(space).rows
        worst.append(float(np.max(np.abs(data.efc_pos[: data.nefc][rows]))))
    return np.array(worst)


@pytest.mark.parametrize("name", ["fourbar.xml", "delta.xml"])
def test_mujoco_finds_the_samples_closed(name: str) -> None:
    space = cspace.load(CLOSED / name)
    rng = np.random.default_rng(5)
    bounds = BOUNDS if name == "delta.xml" else None
    found = _closure(space).sample(12, rng, bounds=bounds)
    assert len(found) == 12
    assert np.all(_mujoco_residual(space, name, found) < 1e-8)
    starts = space.sample(12, rng, bounds)  # where projections start: open, to MuJoCo too
    assert np.all(_mujoco_residual(space, name, starts) > 1e-4)


@pytest.mark.bounded
def test_ompl_plans_the_four_bars_crank_through_a_full_turn(
    fourbar: cspace.ConfigurationSpace,
) -> None:
    og = pytest.importorskip("ompl.geometric")
    ou = pytest.importorskip("ompl.util")
    ou.setLogLevel(ou.LOG_WARN)
    closure = _closure(fourbar)
    before = resource.getrusage(resource.RUSAGE_SELF)
    ompl = closure.to_ompl(
        {"crank": (-1.0, 2 * math.pi + 1.0), "coupler": (-2 * math.pi - 1.0, 1.5)}
    )
    assert ompl.rank == 2  # 3 rows, one of them (along the hinges) always 0
    assert ompl.constraint.getCoDimension() == 2
    assert ompl.constraint.getManifoldDimension() == 1  # the four-bar's mobility
    start = fourbar.neutral()
    # a crank-rocker's crank turns once, its coupler once the other way relative to it
    goal = start + np.array([2 * math.pi, -2 * math.pi, 0.0])
    assert closure.is_closed(goal)
    setup = og.SimpleSetup(ompl.information)
    setup.setStartAndGoalStates(ompl.to_state(start), ompl.to_state(goal))
    setup.setPlanner(og.RRTConnect(ompl.information))
    setup.setup()
    assert setup.solve(20.0)
    path = setup.getSolutionPath()
    path.interpolate()
    lift = np.array([ompl.values(path.getState(i)) for i in range(path.getStateCount())])
    np.testing.assert_allclose(lift[0], start, atol=1e-12)
    np.testing.assert_allclose(lift[-1], goal, atol=1e-9)
    assert np.max(np.abs(closure.residual(lift))) <= ompl.constraint.getTolerance()
    assert np.max(np.linalg.norm(np.diff(lift, axis=0), axis=1)) < 0.1  # small steps
    crank = lift[:, 0]
    assert crank.min() <= 1e-9 and crank.max() >= 2 * math.pi - 1e-9
    wrapped = np.array([ompl.from_state(path.getState(i)) for i in range(0, len(lift), 7)])
    assert np.all(closure.is_closed(wrapped, 1e-6))
    np.testing.assert_array_equal(fourbar.canonicalize(wrapped), wrapped)
    after = resource.getrusage(resource.RUSAGE_SELF)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    assert cpu < 15.0  # about 1 s on an idle machine; a bound, not a speed target


def test_omplss_constraint_on_a_delta_robot_has_its_mobility_and_its_jacobian(
    delta: cspace.ConfigurationSpace,
) -> None:
    pytest.importorskip("ompl.base")
    closure = _closure(delta)
    ompl = closure.to_ompl(BOUNDS)
    constraint = ompl.constraint
    # 18 rows of rank 18, and the platform's quaternion norm: manifold dimension 3
    assert (ompl.rank, constraint.getCoDimension()) == (18, 19)
    assert constraint.getManifoldDimension() == 3
    rng = np.random.default_rng(4)
    x = closure.sample(1, rng, bounds=BOUNDS)[0] + 0.01 * rng.normal(size=delta.size)
    rows, n = constraint.getCoDimension(), delta.size

    def function(y: np.ndarray) -> np.ndarray:
        out = np.zeros(rows)
        constraint.function(y, out)
        return out

    jacobian = np.zeros((rows, n))
    constraint.jacobian(x, jacobian)
    h = 1e-6
    numeric = np.stack([(function(x + h * e) - function(x - h * e)) / (2 * h) for e in np.eye(n)])
    np.testing.assert_allclose(jacobian, numeric.T, atol=1e-7)
    assert np.abs(function(x)).max() > 1e-3  # x is off the mechanism ...
    y = np.ascontiguousarray(x)
    assert constraint.project(y)  # ... and OMPL's own Newton steps bring it back
    back = delta.canonicalize(_unit(delta, y))
    assert closure.is_closed(back, 1e-6)


def _unit(space: cspace.ConfigurationSpace, y: np.ndarray) -> np.ndarray:
    out = y.copy()
    q = [space.names.index(f"platform.q{c}") for c in "wxyz"]
    out[q] /= np.linalg.norm(out[q])
    return out


def test_omplss_bounds_are_checked(fourbar: cspace.ConfigurationSpace) -> None:
    pytest.importorskip("ompl.base")
    closure = _closure(fourbar)
    with pytest.raises(ArgumentTypeError):
        closure.to_ompl([("crank", (0.0, 1.0))])  # type: ignore[arg-type]
    with pytest.raises(ArgumentError):
        closure.to_ompl({"crank": (1.0, 1.0)})
    with pytest.raises(ArgumentError):
        closure.to_ompl(tolerance=0.0)


@pytest.mark.parametrize(
    "name", ["fourbar.xml", "fourbar.sdf", "fourbar.usda", "fourbar_cut.usda", "fourbar_drake.urdf"]
)
def test_every_formats_four_bar_has_one_degree_of_freedom_at_its_samples(name: str) -> None:
    space = cspace.load(CLOSED / name)
    closure = _closure(space)
    found = closure.sample(6, np.random.default_rng(8))
    assert len(found) == 6 and np.all(closure.is_closed(found))
    ranks = {int(np.linalg.matrix_rank(j, tol=1e-8)) for j in closure.jacobian(found)}
    assert ranks == {space.dimension - 1}  # mobility 1: the tangent's one free direction


def test_the_crank_is_a_chart_of_the_four_bar_and_two_joints_are_not() -> None:
    space = cspace.load(CLOSED / "fourbar.xml")
    closure = _closure(space)
    found = closure.sample(8, np.random.default_rng(4))
    assert np.all(closure.chart(found, ["crank"]))  # a Grashof crank drives it everywhere
    assert not np.any(closure.chart(found, ["crank", "rocker"]))  # two for one freedom
    assert not np.any(closure.chart(found, []))  # none for one freedom
    assert closure.chart(found[0], "coupler") in (True, False)  # one configuration: a bool
    with pytest.raises(cspace.errors.ArgumentError, match="'motor' is no joint"):
        closure.chart(found, ["motor"])
