"""The registry of conventions is the one list: the command line, the types, the maps,
the report's slots and the labels all come from it or agree with it."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import get_args

import numpy as np
import pytest

import cspace
from cspace._cli.main import build_parser
from cspace.conventions import TOOLS, Conventions
from cspace.space._conventions._conventions import Convention, Named

from conftest import REPO, run_cli

ROBOT = REPO / "robots" / "mjcf_every_joint.xml"
"""Free, ball (limited and not), hinge, slide and a joint without a name: every tool's
storage but the planar joint."""
ISAAC_ROBOT = REPO / "robots" / "mjcf_scene_objects.xml"
"""A hinge and three free bodies (Isaac keeps no ball): the pairs with Isaac use it."""
ISAAC_PYBULLET_ROBOT = REPO / "robots" / "mjcf_unnamed_joints.xml"
"""One free body and hinges: Isaac keeps no ball, PyBullet one free base (their pair)."""
SERVO_ROBOT = REPO / "tests" / "actuators" / "servo_arm.xml"
"""Hinges and a slide, each driven by a position actuator: MuJoCo's ctrl holds a whole
configuration, so the pairs with ``mujoco-ctrl`` use it."""


def _choices(command: str, dest: str) -> tuple[str, ...]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    action = next(a for a in sub.choices[command]._actions if a.dest == dest)
    return tuple(action.choices or ())


def test_the_command_line_offers_exactly_the_registry() -> None:
    assert _choices("convert", "source") == (*TOOLS, "named")
    assert _choices("convert", "target") == (*TOOLS, "named")
    assert _choices("unwrap", "convention") == tuple(TOOLS)


def test_the_python_types_are_the_registry() -> None:
    assert get_args(Convention) == tuple(TOOLS)
    assert get_args(Named) == (*TOOLS, "named")


def test_every_tool_has_its_maps_both_ways() -> None:
    for name in TOOLS:
        if name == "canonical":
            continue
        for verb in ("to", "from"):
            method = f"{verb}_{name.replace('-', '_')}"
            assert callable(getattr(Conventions, method))
            assert callable(getattr(Conventions, f"{method}_velocity"))


def test_the_reports_slots_are_the_registrys() -> None:
    schema = json.loads((REPO / "src/cspace/_schema/report-v1.schema.json").read_text())
    slots = set(schema["$defs"]["joint"]["properties"]["slots"]["properties"])
    declared = {key for tool in TOOLS.values() if tool.slots for key in tool.slots}
    assert slots == declared


def test_each_tool_is_one_module_with_its_maps() -> None:
    """The registry names the module; its ``Maps`` has the five maps (`_maps.Maps`)."""
    import importlib
    import inspect

    from cspace.space._conventions._maps import Maps

    wanted = {n for n, v in vars(Maps).items() if inspect.isfunction(v) and n[0] != "_"}
    assert wanted == {"names", "to_tool", "from_tool", "to_velocity", "from_velocity"}
    for tool in TOOLS.values():
        module = importlib.import_module(f"cspace.space._conventions.{tool.module}")
        for method in wanted:
            assert callable(getattr(module.Maps, method)), (tool.name, method)


PAIRS = [(a, b) for a in TOOLS for b in TOOLS]


@pytest.mark.parametrize(("source", "target"), PAIRS, ids=[f"{a}-{b}" for a, b in PAIRS])
def test_every_pair_converts_both_ways_in_python_and_on_the_command_line(
    source: str, target: str, tmp_path: Path
) -> None:
    """A floating MJCF robot with a ball, a hinge and a slide: positions and velocities
    from every convention to every other and back, in Python and through ``cspace
    convert``, against the maps to and from canonical ones."""
    robot = (
        SERVO_ROBOT
        if "mujoco-ctrl" in (source, target)
        else ISAAC_ROBOT
        if "isaac" in (source, target)
        else ROBOT
    )
    if {source, target} == {"isaac", "pybullet"}:
        robot = ISAAC_PYBULLET_ROBOT
    space = cspace.load(robot)
    conventions = space.conventions()
    rng = np.random.default_rng(7)
    unbounded = {c.name: (-2.0, 2.0) for c in space.coordinates if np.isinf(c.lower)}
    x = space.sample(4, rng, bounds=unbounded)
    dx = rng.normal(size=(4, space.dimension))
    values = conventions.from_canonical(x, source)
    out = conventions.convert(values, source, target)
    np.testing.assert_allclose(out, conventions.from_canonical(x, target), atol=1e-12)
    back = conventions.convert(out, target, source)
    np.testing.assert_allclose(conventions.to_canonical(back, source), x, atol=1e-12)
    v = conventions.convert(dx, "canonical", source, velocity=True, at=x)
    w = conventions.convert(v, source, target, velocity=True, at=x)
    np.testing.assert_allclose(
        w, conventions.convert(dx, "canonical", target, velocity=True, at=x), atol=1e-12
    )
    np.testing.assert_allclose(
        conventions.convert(w, target, "canonical", velocity=True, at=x), dx, atol=1e-12
    )
    (tmp_path / "in.jsonl").write_text("".join(json.dumps(row.tolist()) + "\n" for row in values))
    run = run_cli("convert", str(robot), "in.jsonl", "--from", source, "--to", target, cwd=tmp_path)
    assert run.code == 0, run.stderr
    rows = [json.loads(line) for line in run.stdout.splitlines()]
    np.testing.assert_allclose(rows, out, atol=1e-12)
