"""Between canonical configurations and MuJoCo's ctrl: the targets of position actuators.

MuJoCo's ``ctrl`` has one entry per actuator, in the order the file declares them. A
position actuator (``<position>``, or a ``<general>`` with its gain and bias) on a hinge
or slide pulls its joint to where its length, ``gear * qpos``, equals its ctrl; so a
configuration's ctrl is ``gear * qpos`` of each position actuator's joint, through
MuJoCo's qpos (`_mujoco`). The rest, said here once and in the docs:

- every other actuator (a motor, a velocity servo, a muscle, ...) has no joint target:
  its ctrl is 0 in the configurations' ctrl, and is not read back;
- from ctrl, a joint no position actuator drives takes its value in the neutral
  configuration (0 within its limits, identity rotations); a joint several drive
  takes the first one's ctrl / gear; MuJoCo clamps a ctrl to a limited actuator's
  ctrlrange, which this map does not (``cspace convert`` warns of the ctrl MuJoCo
  clamps; the report's ``actuator-ctrlrange-exceeds`` says where a ctrlrange reaches
  beyond its joint's range);
- a position actuator whose ctrl is not a joint's value (a tendon's, a site's, a
  slider-crank's length, a ball or free joint) or whose gear is 0 or not finite is
  refused when the map is built, in one line naming it;
- a lifted trajectory's ctrl (``wrap``) follows its angles unwrapped: MuJoCo does
  not wrap a hinge, and a target past pi wrapped would turn the joint the other way;
- velocities are ctrl's rates: ``gear * qvel`` of each position actuator's joint
  (0 for the others), and back.
"""

import math

import numpy as np
from numpy.typing import ArrayLike

from cspace._record import NamedTuple
from cspace.errors import JointMatchError
from cspace.space._checks import as_rows, check_finite, check_overflow
from cspace.space._conventions import _mujoco
from cspace.space._conventions._maps import Robot
from cspace.space._data import neutral
from cspace.space._geometry.rotations import FloatArray


class Target(NamedTuple):
    """A position actuator's joint: ``ctrl[entry] = gear * qpos[qposadr]``."""

    entry: int
    qposadr: int
    dofadr: int
    gear: float


class Maps:
    """MuJoCo ctrl's `Maps <cspace.space._conventions._maps.Maps>`: position actuators' targets.

    Raises:
        JointMatchError: No MuJoCo layout, no actuator, or a position actuator whose
            ctrl is not a hinge's or slide's value (named).
    """

    def __init__(self, robot: Robot) -> None:
        self.mujoco = _mujoco.Maps(robot)
        self.data = robot.data
        layout = self.mujoco.plan.layout
        if not layout.actuators:
            raise JointMatchError(
                f"robot '{robot.data.robot}' has no MuJoCo actuators: its ctrl vector is empty"
            )
        joints = {j.name: j for j in layout.joints}
        targets: list[Target] = []
        for index, actuator in enumerate(layout.actuators):
            if actuator.kind != "position":
                continue
            label = actuator.label(index)
            joint = joints.get(actuator.target or "") if actuator.drives_joint() else None
            if joint is None or joint.type not in ("hinge", "slide"):
                what = f"{actuator.transmission} '{actuator.target or '?'}'"
                kind = "" if joint is None else f" ({joint.type} joint)"
                raise JointMatchError(
                    f"position actuator {label} drives {what}{kind}: its ctrl is not a hinge's "
                    "or slide's value, which is all mujoco-ctrl converts"
                )
            if not math.isfinite(actuator.gear) or actuator.gear == 0:
                raise JointMatchError(
                    f"position actuator {label} has gear {actuator.gear}: its ctrl gives no "
                    f"value of joint '{joint.name}'",
                    joints=[joint.name],
                )
            targets.append(Target(index, joint.qposadr, joint.dofadr, actuator.gear))
        self.targets = tuple(targets)
        self.size = len(layout.actuators)
        self.labels = tuple(a.name or f"actuator{i}" for i, a in enumerate(layout.actuators))
        first: dict[int, Target] = {}
        for target in targets:
            first.setdefault(target.qposadr, target)
        self.readers = tuple(first.values())  # the first actuator of each joint
        self._neutral_qpos = self.mujoco.to_tool(neutral(self.data))

    def names(self, velocity: bool) -> tuple[str, ...]:
        """Each actuator's name (``actuator<K>`` for one without), in ctrl order."""
        return self.labels

    def to_tool(self, x: ArrayLike) -> FloatArray:
        """MuJoCo's ctrl (..., nu) of canonical configurations (..., n)."""
        qpos = self.mujoco.to_tool(x)
        return self._scaled(qpos, "qposadr", "MuJoCo's ctrl")

    def from_tool(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of MuJoCo ctrl (..., nu)."""
        rows, lead = as_rows(q, self.size, f"MuJoCo ctrl of robot '{self.data.robot}'")
        check_finite(rows, self.labels, lead)
        qpos = np.repeat(self._neutral_qpos[None, :], len(rows), axis=0)
        for target in self.readers:
            qpos[:, target.qposadr] = rows[:, target.entry] / target.gear
        return self.mujoco.from_tool(qpos).reshape(*lead, self.data.size)

    def lifted(self, lift: ArrayLike, canonical: FloatArray) -> FloatArray:
        """The ctrl (..., nu) of a lifted trajectory (..., T, n), its angles as they go.

        MuJoCo does not wrap a hinge's qpos, so a servo's target of a continuous joint
        is its lifted angle times the gear: the ctrl of the wrapped angle past pi would
        swing the joint a turn back. ``canonical`` is the lift's canonical form.
        """
        ctrl = self.to_tool(canonical)
        turns = np.asarray(lift, dtype=float) - canonical  # 0 but for unwrapped angles
        lead = turns.shape[:-1]
        rows = turns.reshape(math.prod(lead), turns.shape[-1])
        qpos = np.zeros((len(rows), self.mujoco.plan.layout.nq))
        plan = self.mujoco.plan
        for piece in plan.pieces:
            if piece.qpos.stop - piece.qpos.start == 1:  # a hinge or slide of one column
                qpos[:, piece.qpos] = rows[:, piece.columns]
        for f in plan.followers:
            if f.column is not None:
                qpos[:, f.qposadr] = f.multiplier * rows[:, f.column]
        flat = ctrl.reshape(len(rows), self.size)
        with np.errstate(over="ignore", invalid="ignore"):
            for target in self.targets:
                flat[:, target.entry] += target.gear * qpos[:, target.qposadr]
        check_overflow(flat, "MuJoCo's ctrl", lead)
        return flat.reshape(*lead, self.size)

    def to_velocity(self, at: ArrayLike, dx: ArrayLike) -> FloatArray:
        """The rates of ctrl (..., nu) of tangent vectors (``at`` is not needed)."""
        qvel = self.mujoco.to_velocity(at, dx)
        return self._scaled(qvel, "dofadr", "MuJoCo's ctrl rate")

    def from_velocity(self, at: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of ctrl rates (..., nu)."""
        rows, lead = as_rows(v, self.size, f"MuJoCo ctrl rates of robot '{self.data.robot}'")
        check_finite(rows, self.labels, lead)
        qvel = np.zeros((len(rows), self.mujoco.plan.layout.nv))
        for target in self.readers:
            qvel[:, target.dofadr] = rows[:, target.entry] / target.gear
        dx = self.mujoco.from_velocity(at, qvel)
        return dx.reshape(*lead, self.data.dimension)

    def _scaled(self, values: FloatArray, address: str, what: str) -> FloatArray:
        """``gear * values[address]`` of each position actuator, 0 for the others."""
        lead = values.shape[:-1]
        rows = values.reshape(math.prod(lead), values.shape[-1])
        ctrl = np.zeros((len(rows), self.size))
        with np.errstate(over="ignore", invalid="ignore"):
            for target in self.targets:
                ctrl[:, target.entry] = target.gear * rows[:, getattr(target, address)]
        check_overflow(ctrl, what, lead)
        return ctrl.reshape(*lead, self.size)
