"""MuJoCo's actuators: the layout of the ctrl vector, one record an actuator.

An MJCF model's ``ctrl`` has one entry per actuator, in the order the file declares
them (``<actuator>``'s children). Each actuator drives one object through its
transmission (``actuator_trntype``, ``actuator_trnid``): a joint, a tendon, a site, a
body, a slider-crank; its force is ``gain * ctrl + bias`` after its dynamics, and
MuJoCo's shortcut elements (``<position>``, ``<velocity>``, ``<motor>``, ...) are
``<general>`` actuators with these parameters set as MuJoCo sets them. `kind_of`
reads the kind back from the compiled parameters, so a ``<general>`` written as a
position servo is one.

A position actuator on a hinge or slide holds the joint where its length equals ctrl:
``gain * ctrl - kp * length = 0`` with ``length = gear * qpos``, so ``ctrl = gear *
qpos``. This module is shared by the MJCF reader, the reports, the renderers and the
``mujoco-ctrl`` convention: no NumPy, nothing of any layer.
"""

import math
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._record import NamedTuple

TRANSMISSIONS = ("joint", "jointinparent", "slidercrank", "tendon", "site", "body")
"""MuJoCo's transmission types, by ``mjtTrn`` value (``mjTRN_JOINT`` is 0)."""

KINDS = (
    "position",
    "velocity",
    "motor",
    "intvelocity",
    "damper",
    "cylinder",
    "muscle",
    "adhesion",
    "general",
)
"""What an actuator is, as the MJCF element that writes its parameters is named."""

_FIXED, _AFFINE, _MUSCLE = 0, 1, 2  # mjtGain (and mjtBias: 0 none, 1 affine, 2 muscle)
_NONE, _INTEGRATOR, _FILTER, _FILTEREXACT = 0, 1, 2, 3  # mjtDyn


def kind_of(
    trntype: int,
    dyntype: int,
    gaintype: int,
    gain: Sequence[float],
    biastype: int,
    bias: Sequence[float],
) -> str:
    """The kind of an actuator from its compiled parameters, as MuJoCo's elements set them.

    ``<position kp kv>``: fixed gain ``kp`` (> 0), affine bias ``(0, -kp, -kv)``, no
    dynamics (or ``filterexact``, its ``timeconst``; a ``<general>`` servo behind a
    ``filter`` is one too); ``<velocity kv>``: gain ``kv``, bias ``(0, 0, -kv)``;
    ``<motor>``: fixed gain, no bias, no dynamics; ``<intvelocity>``: a position servo
    behind an integrator; ``<damper>``: affine gain ``(0, 0, -kv)``, no bias;
    ``<cylinder>``: a filter, fixed gain, affine bias (not a servo's); ``<muscle>``:
    muscle gain; ``<adhesion>``: a body transmission, fixed gain, no bias. Anything
    else is ``general``.
    """
    kp = gain[0] if gain else 0.0
    if gaintype == _MUSCLE:
        return "muscle"
    if gaintype == _FIXED and biastype == _AFFINE and len(bias) >= 3:
        servo = kp > 0 and bias[0] == 0 and bias[1] == -kp
        if servo and dyntype in (_NONE, _FILTER, _FILTEREXACT):
            return "position"  # a filter delays ctrl; the joint still comes to rest at it
        if servo and dyntype == _INTEGRATOR:
            return "intvelocity"
        if dyntype == _NONE and kp > 0 and bias[0] == 0 and bias[1] == 0 and bias[2] == -kp:
            return "velocity"
        if dyntype == _FILTER:
            return "cylinder"
    if gaintype == _FIXED and biastype == _NONE and dyntype == _NONE:
        return "adhesion" if trntype == TRANSMISSIONS.index("body") else "motor"
    damping = len(gain) >= 3 and gain[0] == 0 and gain[1] == 0 and gain[2] < 0
    if gaintype == _AFFINE and biastype == _NONE and dyntype == _NONE and damping:
        return "damper"
    return "general"


_JOINT_GEARS = {0: 6, 1: 3}  # mjtJoint: a free joint's six numbers, a ball joint's three


def gear_count(transmission: str, joint_type: int | None) -> int:
    """How many of an actuator's six gear numbers MuJoCo reads (``mj_transmission``).

    A hinge's, a slide's, a tendon's, a slider-crank's and a body's one; a ball joint's
    three (an axis); a free joint's and a site's six (a force and a torque).

    Args:
        transmission: Its transmission (`TRANSMISSIONS`).
        joint_type: The ``mjtJoint`` of the joint it drives, or None.
    """
    if transmission in ("joint", "jointinparent"):
        return _JOINT_GEARS.get(-1 if joint_type is None else joint_type, 1)
    return 6 if transmission == "site" else 1


def gear_tuple(values: Sequence[float]) -> tuple[float, ...]:
    """An actuator's `Actuator.gears`: the numbers MuJoCo reads, when more than one."""
    return tuple(float(x) for x in values) if len(values) > 1 else ()


def _number(value: float) -> float | None:
    """A number for JSON: None for one that is not finite."""
    return value if math.isfinite(value) else None


class Actuator(NamedTuple):
    """One actuator: one entry of MuJoCo's ``ctrl``, in order.

    Attributes:
        name: Its name, or None (MuJoCo allows an actuator without one).
        line: Its element's line in the robot file (a named actuator of the main file),
            or None.
        kind: What it is (`KINDS`): ``position``, ``velocity``, ``motor``, ...
        transmission: What it drives through (`TRANSMISSIONS`): ``joint``, ``tendon``, ...
        target: The joint, tendon, site or body it drives (by name; a slider-crank's
            crank site), or None when that has no name.
        gear: The transmission's gear (its first number; NaN when not finite).
        ctrlrange: ``(lower, upper)`` when MuJoCo clamps its ctrl to them
            (``ctrllimited``), else None (as when the model disables ``clampctrl``).
        gears: Every number of the gear MuJoCo reads (``actuator_gear``, the first
            being ``gear``) when it reads more than one: a ball joint's three (the axis
            its torque turns about), a free joint's or a site's six (a force, then a
            torque, in the site's or joint's frame); ``()`` when it reads one (a hinge,
            a slide, a tendon, a slider-crank, a body). NaN where not finite.
    """

    name: str | None
    line: int | None
    kind: str
    transmission: str
    target: str | None
    gear: float
    ctrlrange: tuple[float, float] | None
    gears: tuple[float, ...] = ()

    def label(self, index: int) -> str:
        """How messages name it: ``'name'``, or ``#index`` for one without a name."""
        return f"'{self.name}'" if self.name else f"#{index}"

    def gear_text(self) -> str:
        """``2``, or ``[0, 0, 1, 0, 0, 0]`` when MuJoCo reads several numbers of its gear."""
        if not self.gears:
            return f"{self.gear:g}"
        return "[" + ", ".join(f"{g:g}" for g in self.gears) + "]"

    def ctrlrange_text(self) -> str | None:
        """``[-1, 1]``, its ctrlrange; None when MuJoCo does not clamp its ctrl."""
        if self.ctrlrange is None:
            return None
        return f"[{self.ctrlrange[0]:g}, {self.ctrlrange[1]:g}]"

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this actuator (a number not finite is null)."""
        return {
            "name": self.name,
            "line": self.line,
            "kind": self.kind,
            "transmission": self.transmission,
            "target": self.target,
            "gear": _number(self.gear),
            "ctrlrange": None
            if self.ctrlrange is None
            else [_number(self.ctrlrange[0]), _number(self.ctrlrange[1])],
        } | ({"gears": [_number(g) for g in self.gears]} if self.gears else {})

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Actuator":
        """The actuator of a JSON object `to_dict` wrote (null numbers as NaN)."""

        def number(value: Any) -> float:
            return math.nan if value is None else float(value)

        low_high = document.get("ctrlrange")
        return cls(
            name=None if document.get("name") is None else str(document["name"]),
            line=None if document.get("line") is None else int(document["line"]),
            kind=str(document["kind"]),
            transmission=str(document["transmission"]),
            target=None if document.get("target") is None else str(document["target"]),
            gear=number(document.get("gear")),
            ctrlrange=None if low_high is None else (number(low_high[0]), number(low_high[1])),
            gears=tuple(number(g) for g in document.get("gears") or ()),
        )

    def drives_joint(self) -> bool:
        """Whether it is a position actuator whose ctrl is a joint's target (gear * qpos)."""
        return (
            self.kind == "position"
            and self.transmission in ("joint", "jointinparent")
            and self.target is not None
        )


def model_actuators(model: Any) -> tuple[Actuator, ...]:
    """The actuators of a ``mujoco.MjModel`` (a ``--mujoco`` model given in Python).

    Read as the MJCF reader reads a compiled model's, without lines.
    """
    import mujoco

    objects = {
        "joint": mujoco.mjtObj.mjOBJ_JOINT,
        "jointinparent": mujoco.mjtObj.mjOBJ_JOINT,
        "tendon": mujoco.mjtObj.mjOBJ_TENDON,
        "body": mujoco.mjtObj.mjOBJ_BODY,
        "site": mujoco.mjtObj.mjOBJ_SITE,
        "slidercrank": mujoco.mjtObj.mjOBJ_SITE,  # its crank site
    }
    clamped = not int(model.opt.disableflags) & int(mujoco.mjtDisableBit.mjDSBL_CLAMPCTRL)
    out = []
    for a in range(int(model.nu)):
        trntype = int(model.actuator_trntype[a])
        transmission = TRANSMISSIONS[trntype] if 0 <= trntype < len(TRANSMISSIONS) else "other"
        trnid = int(model.actuator_trnid[a][0])
        kind = objects.get(transmission)
        target = mujoco.mj_id2name(model, kind, trnid) if kind is not None and trnid >= 0 else None
        low, high = (float(x) for x in model.actuator_ctrlrange[a])
        on_joint = transmission in ("joint", "jointinparent") and 0 <= trnid < model.njnt
        joint = int(model.jnt_type[trnid]) if on_joint else None
        out.append(
            Actuator(
                name=mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a) or None,
                line=None,
                kind=kind_of(
                    trntype,
                    int(model.actuator_dyntype[a]),
                    int(model.actuator_gaintype[a]),
                    [float(x) for x in model.actuator_gainprm[a][:3]],
                    int(model.actuator_biastype[a]),
                    [float(x) for x in model.actuator_biasprm[a][:3]],
                ),
                transmission=transmission,
                target=target or None,
                gear=float(model.actuator_gear[a][0]),
                gears=gear_tuple(model.actuator_gear[a][: gear_count(transmission, joint)]),
                ctrlrange=(low, high) if clamped and bool(model.actuator_ctrllimited[a]) else None,
            )
        )
    return tuple(out)
