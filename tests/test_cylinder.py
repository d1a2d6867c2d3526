"""LaValle's figure 4.8, run: the planner that knows the cylinder finds the path through
theta = pi; on the interval [-pi, pi] the obstacle separates start from goal.

``docs/examples/cylinder.py`` is run as a user runs it, and its picture is the one in the
docs (``python docs/examples/cylinder.py --svg docs/images/cylinder.svg`` draws it anew).
"""

from __future__ import annotations

import importlib.util
import itertools
import math
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

import cspace

from conftest import REPO

SCRIPT = REPO / "docs" / "examples" / "cylinder.py"
PICTURE = REPO / "docs" / "images" / "cylinder.svg"


@pytest.fixture(scope="session")
def example() -> ModuleType:
    spec = importlib.util.spec_from_file_location("cylinder_example", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_example_says_what_the_docs_say_and_draws_their_picture(tmp_path: Path) -> None:
    run = subprocess.run(
        [sys.executable, str(SCRIPT), "--svg", str(tmp_path / "cylinder.svg")],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout == (
        "on the cylinder (cspace's space): a path of 120 states, through shoulder = pi\n"
        "on the interval [-pi, pi]: no path\n"
    )
    drawn = (tmp_path / "cylinder.svg").read_text(encoding="utf-8")
    assert drawn == PICTURE.read_text(encoding="utf-8"), "docs/images/cylinder.svg is stale"


def test_the_obstacle_separates_the_interval_whatever_the_elbow(example: ModuleType) -> None:
    """Why no planner on the interval can succeed: at shoulder 0 every elbow angle is in
    collision, a wall from one end of the elbow's range to the other."""
    arm = example.Arm()
    assert cspace.inspect(example.ROBOT).manifold.notation == "R^1 × S^1"  # a cylinder
    for elbow in np.linspace(-2.5, 2.5, 501):
        assert not arm.free(np.array([0.0, elbow]))
    assert arm.free(np.array(example.START)) and arm.free(np.array(example.GOAL))
    assert example.START[0] < 0 < example.GOAL[0]


def test_the_path_on_the_cylinder_is_free_and_crosses_pi(example: ModuleType) -> None:
    from ompl import util as ou

    ou.RNG.setSeed(3)  # another seed than the docs': any path will do
    arm = example.Arm()
    path = example.on_the_cylinder(arm)
    assert path is not None and example.crosses_pi(path)
    np.testing.assert_allclose(path[0], example.START, atol=1e-9)
    np.testing.assert_allclose(path[-1], example.GOAL, atol=1e-9)
    for a, b in itertools.pairwise(path):  # every motion, the short way round
        assert arm.space.distance(a, b) < 0.2
        for x in arm.space.interpolate(a, b, np.linspace(0.0, 1.0, 11)):
            assert arm.space.contains(x) and arm.free(x)
    assert not any(abs(x[0]) < 0.4 for x in path)  # never through the post's side
    assert max(abs(x[0]) for x in path) > math.pi - 0.05


def test_the_same_planner_on_the_interval_finds_nothing(example: ModuleType) -> None:
    assert example.on_the_interval(example.Arm(), seconds=0.5) is False
