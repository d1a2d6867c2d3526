"""LaValle's figure 4.8 with a real planner: one that does not know the cylinder fails.

A planar arm (``planar_arm.urdf``) turns its shoulder without limits and its elbow within
+-2.5 rad: its C-space is R^1 x S^1, a cylinder. A post of radius 0.25 m stands 0.6 m in
front of the shoulder, so every configuration whose shoulder angle is within about 0.43
rad of 0 is in collision, whatever the elbow: an obstacle across the middle of
[-pi, pi). Start (shoulder -2) and goal (shoulder 2) lie on either side of it.

- In the space cspace builds (``space.to_ompl()``: SO(2) for the shoulder) RRTConnect
  finds a path, through shoulder = pi.
- In the interval [-pi, pi] x [-2.5, 2.5] (a continuous joint as an interval, as many
  planners' configurations make it) the obstacle separates start from goal: the same
  planner finds none, however long it runs.

Run: ``python docs/examples/cylinder.py [--svg FILE]`` (needs ``ompl``); it prints what
each planner found and, with ``--svg``, draws the C-space, the obstacle and the path.
"""

from __future__ import annotations

import argparse
import itertools
import math
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

import cspace

ROBOT = Path(__file__).with_name("planar_arm.urdf")
POST, RADIUS = np.array([0.6, 0.0, 0.0]), 0.25
"""The obstacle: a post at (0.6, 0) m in the arm's plane, of radius 0.25 m."""
START, GOAL = (-2.0, 0.5), (2.0, -0.5)
"""(shoulder, elbow) in rad."""


class Arm:
    """The arm's space and its collision check (Pinocchio's forward kinematics)."""

    def __init__(self) -> None:
        self.space = cspace.load(ROBOT)
        self.conventions = self.space.conventions()
        self.model = cspace.pinocchio_model(ROBOT)
        self.data = self.model.createData()
        self.points = [self.model.getFrameId(n) for n in ("upper", "fore", "hand")]

    def free(self, x: np.ndarray) -> bool:
        """Whether configuration ``x`` (shoulder, elbow) keeps both links off the post."""
        pin.framesForwardKinematics(self.model, self.data, self.conventions.to_pinocchio(x))
        ends = [self.data.oMf[i].translation for i in self.points]
        return all(_distance(a, b) > RADIUS for a, b in itertools.pairwise(ends))


def _distance(a: np.ndarray, b: np.ndarray) -> float:
    """Distance from the post's centre to the segment from a to b."""
    t = np.clip(np.dot(POST - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.linalg.norm(a + t * (b - a) - POST))


def on_the_cylinder(arm: Arm, seconds: float = 5.0) -> list[np.ndarray] | None:
    """RRTConnect in the space cspace builds: the path's configurations, or None."""
    space = arm.space.to_ompl()
    setup = og.SimpleSetup(space.space)
    setup.setStateValidityChecker(
        lambda state: space.valid(state) and arm.free(space.from_state(state))
    )
    setup.setStartAndGoalStates(space.to_state(np.array(START)), space.to_state(np.array(GOAL)))
    setup.setPlanner(og.RRTConnect(setup.getSpaceInformation()))
    if not setup.solve(seconds) or not setup.haveExactSolutionPath():
        return None
    path = setup.getSolutionPath()
    og.PathSimplifier(setup.getSpaceInformation()).reduceVertices(path, 200, 200, 0.33)
    path.interpolate(120)
    return [space.from_state(path.getState(k)) for k in range(path.getStateCount())]


def on_the_interval(arm: Arm, seconds: float = 1.0) -> bool:
    """RRTConnect on [-pi, pi] x [-2.5, 2.5]: whether it finds a path."""
    space = ob.RealVectorStateSpace(2)
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(0, -math.pi)
    bounds.setHigh(0, math.pi)
    bounds.setLow(1, -2.5)
    bounds.setHigh(1, 2.5)
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    setup.setStateValidityChecker(lambda state: arm.free(np.array([state[0], state[1]])))
    start, goal = space.allocState(), space.allocState()
    start[0], start[1] = START
    goal[0], goal[1] = GOAL
    setup.setStartAndGoalStates(start, goal)
    setup.setPlanner(og.RRTConnect(setup.getSpaceInformation()))
    setup.solve(seconds)
    return bool(setup.haveExactSolutionPath())


def crosses_pi(path: list[np.ndarray]) -> bool:
    """Whether the path crosses shoulder = pi (a step of the angle by more than pi)."""
    return any(abs(b[0] - a[0]) > math.pi for a, b in itertools.pairwise(path))


WIDTH, HEIGHT, MARGIN = 720, 300, 40


def _x(theta: float) -> float:
    return MARGIN + (theta + math.pi) / (2 * math.pi) * WIDTH


def _y(elbow: float) -> float:
    return MARGIN + (2.5 - elbow) / 5.0 * HEIGHT


def picture(arm: Arm, path: list[np.ndarray]) -> str:
    """The C-space unrolled (shoulder across, elbow up), the obstacle grey, the path."""
    columns, rows = 180, 75
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {WIDTH + 2 * MARGIN} '
        f'{HEIGHT + 2 * MARGIN + 30}" font-family="sans-serif" font-size="13">',
        f'<rect x="{MARGIN}" y="{MARGIN}" width="{WIDTH}" height="{HEIGHT}" fill="#fff" '
        'stroke="#888"/>',
    ]
    cell_w, cell_h = WIDTH / columns, HEIGHT / rows
    for r in range(rows):
        elbow = 2.5 - (r + 0.5) * 5.0 / rows
        run = None
        for c in range(columns + 1):
            blocked = c < columns and not arm.free(
                np.array([-math.pi + (c + 0.5) * 2 * math.pi / columns, elbow])
            )
            if blocked and run is None:
                run = c
            elif not blocked and run is not None:
                out.append(
                    f'<rect x="{MARGIN + run * cell_w:.1f}" y="{MARGIN + r * cell_h:.1f}" '
                    f'width="{(c - run) * cell_w:.1f}" height="{cell_h:.1f}" fill="#bbb" '
                    'shape-rendering="crispEdges"/>'
                )
                run = None
    pieces: list[list[np.ndarray]] = [[path[0]]]
    for a, b in itertools.pairwise(path):
        if abs(b[0] - a[0]) > math.pi:  # through the seam: to one edge, on from the other
            edge = math.copysign(math.pi, a[0])
            step = b[0] - a[0] - math.copysign(2 * math.pi, b[0] - a[0])
            share = (edge - a[0]) / step
            elbow = a[1] + share * (b[1] - a[1])
            pieces[-1].append(np.array([edge, elbow]))
            pieces.append([np.array([-edge, elbow])])
        pieces[-1].append(b)
    for piece in pieces:
        points = " ".join(f"{_x(p[0]):.1f},{_y(p[1]):.1f}" for p in piece)
        out.append(f'<polyline points="{points}" fill="none" stroke="#1f6fd0" stroke-width="2.5"/>')
    for (theta, elbow), label in ((START, "start"), (GOAL, "goal")):
        out.append(f'<circle cx="{_x(theta):.1f}" cy="{_y(elbow):.1f}" r="5" fill="#d03a1f"/>')
        out.append(f'<text x="{_x(theta) + 8:.1f}" y="{_y(elbow) - 8:.1f}">{label}</text>')
    for theta in (-math.pi, math.pi):
        out.append(
            f'<line x1="{_x(theta):.1f}" y1="{MARGIN}" x2="{_x(theta):.1f}" '
            f'y2="{MARGIN + HEIGHT}" stroke="#d03a1f" stroke-dasharray="6 4" stroke-width="2"/>'
        )
    for elbow in (-2.5, 0.0, 2.5):
        out.append(f'<text x="{MARGIN + WIDTH + 6}" y="{_y(elbow) + 4:.1f}">{elbow:g}</text>')
    for theta, label in ((-math.pi, "−π"), (0.0, "0"), (math.pi, "π")):
        out.append(
            f'<text x="{_x(theta):.1f}" y="{MARGIN + HEIGHT + 18}" text-anchor="middle">'
            f"{label}</text>"
        )
    out.append(
        f'<text x="{MARGIN + WIDTH / 2:.1f}" y="{MARGIN + HEIGHT + 40}" text-anchor="middle">'
        "shoulder (rad); the dashed edges are one line of the cylinder, θ = π ~ −π</text>"
    )
    out.append(
        f'<text x="{MARGIN - 8}" y="{MARGIN + HEIGHT / 2:.1f}" text-anchor="middle" '
        f'transform="rotate(-90 {MARGIN - 8} {MARGIN + HEIGHT / 2:.1f})">elbow (rad)</text>'
    )
    out.append(
        f'<text x="{MARGIN}" y="{MARGIN - 12}">grey: the arm touches the post; blue: the '
        "path RRTConnect finds on the cylinder</text>"
    )
    return "\n".join(out) + "\n</svg>\n"


def main(argv: list[str]) -> int:
    """Plan both ways and say what each found; 0 when the cylinder's planner found a path."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--svg", type=Path, help="draw the C-space, obstacle and path here")
    args = parser.parse_args(argv)
    ou.setLogLevel(ou.LOG_WARN)
    ou.RNG.setSeed(1)
    arm = Arm()
    path = on_the_cylinder(arm)
    if path is None:
        print("on the cylinder: no path")
        return 1
    print(f"on the cylinder (cspace's space): a path of {len(path)} states", end="")
    print(", through shoulder = pi" if crosses_pi(path) else "")
    found = on_the_interval(arm)
    print(f"on the interval [-pi, pi]: {'a path' if found else 'no path'}")
    if args.svg is not None:
        args.svg.write_text(picture(arm, path), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
