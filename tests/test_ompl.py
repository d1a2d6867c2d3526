"""A robot's C-space as an OMPL state space, with OMPL itself as the oracle.

On every teaching robot: a configuration becomes an OMPL state and comes back exactly;
OMPL's interpolation of two states is cspace's interpolation of the configurations;
OMPL's distance equals cspace's for configurations that differ in one factor, and lies
between cspace's and sqrt(k) times it when k factors differ (OMPL sums the factors'
weighted distances, cspace takes the root of the sum of squares; a floating or planar
joint is OMPL's SE(3) or SE(2), whose translation is one Euclidean part, as in cspace);
OMPL's own uniform samples are configurations within the limits.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import cspace
from cspace.errors import UnboundedSamplingError

from conftest import ROBOTS

POINTS = {"sensor_head_fixed.urdf", "mjcf_static_scene.xml"}
"""Robots that cannot move: OMPL has no space of dimension 0 (tested apart)."""

CASES = [
    (p.name, None)
    for p in sorted([*ROBOTS.glob("*.urdf"), *ROBOTS.glob("*.xml"), *ROBOTS.glob("*.sdf")])
    if p.name not in POINTS
] + [("quadruped_nobase.urdf", "floating"), ("arm7.urdf", "floating")]
IDS = [f"{n}-{r}" if r else n for n, r in CASES]


def _space(
    name: str, root: str | None
) -> tuple[cspace.ConfigurationSpace, dict[str, tuple[float, float]]]:
    space = cspace.load(ROBOTS / name, root)
    free = {c.name: (-2.0, 2.0) for c in space.coordinates if np.isinf(c.lower) and not c.wraps}
    return space, free


@pytest.mark.parametrize(("name", "root"), CASES, ids=IDS)
def test_ompl_states_distances_and_interpolation_agree(name: str, root: str | None) -> None:
    space, free = _space(name, root)
    planner_space = space.to_ompl(bounds=free)
    ompl = planner_space.space
    rng = np.random.default_rng(11)
    for a, b in space.sample(12, rng, bounds=free).reshape(6, 2, space.size):
        sa, sb = planner_space.to_state(a), planner_space.to_state(b)
        np.testing.assert_array_equal(planner_space.from_state(sa), a)
        between = ompl.allocState()
        for t in (0.0, 0.25, 0.5, 1.0):
            ompl.interpolate(sa, sb, t, between)
            np.testing.assert_allclose(
                planner_space.from_state(between), space.interpolate(a, b, t), atol=1e-12
            )
        d, dist = ompl.distance(sa, sb), float(space.distance(a, b))
        k = sum(2 if kind in ("se2", "se3") else 1 for kind in planner_space.kinds)
        assert dist - 1e-12 <= d <= math.sqrt(k) * dist + 1e-12
        for slot in space.slots:  # one factor apart: the same distance
            c = a.copy()
            c[slot.columns] = b[slot.columns]
            assert ompl.distance(sa, planner_space.to_state(c)) == pytest.approx(
                float(space.distance(a, c)), abs=1e-12
            )


@pytest.mark.parametrize(
    ("name", "root", "joint", "kind"),
    [
        ("quadrotor_floating.urdf", None, "body_free", "SE3StateSpace"),
        ("arm7.urdf", "floating", "root_joint", "SE3StateSpace"),
        ("mobile_manipulator.urdf", None, "base_planar", "SE2StateSpace"),
    ],
)
def test_a_floating_or_planar_joint_is_omples_se3_or_se2(
    name: str, root: str | None, joint: str, kind: str
) -> None:
    """OMPL's own rigid-body spaces, translation and turn weighed as cspace weighs them:
    a move of the base by (dx, dy, dz) is at cspace's (Euclidean) distance in both."""
    space, free = _space(name, root)
    planner_space = space.to_ompl(bounds=free)
    index = planner_space.kinds.index(kind[:3].lower())
    sub = planner_space.space.getSubspace(index)
    assert type(sub).__name__ == kind and sub.getName() == joint
    a = space.sample(1, np.random.default_rng(5), bounds=free)[0]
    b = a.copy()
    start = space.names.index(f"{joint}.x")
    b[start : start + 2] += (0.3, -0.4)  # 0.5 m in the plane
    assert planner_space.space.distance(
        planner_space.to_state(a), planner_space.to_state(b)
    ) == pytest.approx(0.5, abs=1e-12)
    assert float(space.distance(a, b)) == pytest.approx(0.5, abs=1e-12)


@pytest.mark.parametrize(("name", "root"), CASES, ids=IDS)
def test_omples_own_samples_are_configurations_within_the_limits(
    name: str, root: str | None
) -> None:
    space, free = _space(name, root)
    planner_space = space.to_ompl(bounds=free)
    sampler = planner_space.space.allocDefaultStateSampler()
    state = planner_space.space.allocState()
    limited_ball = any(getattr(s.factor, "max_angle", math.pi) < math.pi for s in space.slots)
    kept = 0
    for _ in range(50):
        sampler.sampleUniform(state)
        x = planner_space.from_state(state)
        np.testing.assert_array_equal(space.canonicalize(x), x)
        kept += planner_space.valid(state)
        assert planner_space.valid(state) is bool(space.contains(x, tolerance=1e-12))
    # OMPL's SO(3) knows no largest angle: a limited ball's limit is the validity check
    assert kept == 50 or limited_ball


def test_a_line_without_limits_needs_bounds() -> None:
    space = cspace.load(ROBOTS / "quadruped_nobase.urdf", "floating")
    with pytest.raises(UnboundedSamplingError, match="root_joint"):
        space.to_ompl()


def test_a_robot_that_cannot_move_has_no_ompl_space() -> None:
    for name in sorted(POINTS):
        with pytest.raises(cspace.errors.ArgumentError, match="cannot move"):
            cspace.load(ROBOTS / name).to_ompl()


def test_a_planner_plans_in_it_from_a_start_cspace_would_accept() -> None:
    """A start angle of 4 rad (cspace's -2.28) went to OMPL
    as 4, out of SO(2)'s bounds, and RRTConnect refused the start."""
    from ompl import geometric as og

    space = cspace.load(ROBOTS / "mobile_manipulator.urdf")
    free = {c.name: (-2.0, 2.0) for c in space.coordinates if np.isinf(c.lower) and not c.wraps}
    planner_space = space.to_ompl(bounds=free)
    setup = og.SimpleSetup(planner_space.space)
    setup.setStateValidityChecker(planner_space.valid)
    start, goal = space.neutral(), space.neutral()
    start[space.names.index("base_planar.theta")] = 4.0
    goal[space.names.index("base_planar.x")] = 1.5
    setup.setStartAndGoalStates(planner_space.to_state(start), planner_space.to_state(goal))
    assert planner_space.space.satisfiesBounds(planner_space.to_state(start))
    assert setup.solve(5.0)
    path = setup.getSolutionPath()
    for k in range(path.getStateCount()):
        assert space.contains(planner_space.from_state(path.getState(k)))


def test_what_ompl_cannot_hold_is_refused_and_valid_keeps_the_bounds() -> None:
    space = cspace.load(ROBOTS / "arm7.urdf", "floating")
    free = {"root_joint.x": (-1.0, 1.0), "root_joint.y": (-1.0, 1.0), "root_joint.z": (0.0, 1.0)}
    with pytest.raises(cspace.errors.ArgumentError, match="SO\\(2\\) has no bounds"):
        space.to_ompl(bounds={**free, "wrist_roll": (0.0, 0.5)})
    with pytest.raises(cspace.errors.ArgumentError, match="weight 0"):
        space.with_weights({"elbow": 0.0}).to_ompl(bounds=free)
    narrowed = space.to_ompl(bounds={**free, "shoulder_pan": (0.0, 0.1)})
    x = space.neutral()
    x[space.names.index("shoulder_pan")] = -0.5  # within the joint's limits, not the bounds
    assert not narrowed.valid(narrowed.to_state(x))
    x[space.names.index("root_joint.qw")] = 2.0  # not a unit quaternion
    with pytest.raises(cspace.errors.NotUnitQuaternionError):
        narrowed.to_state(x)
