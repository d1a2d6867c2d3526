"""What a saved report must say consistently, where its JSON Schema cannot say it.

The normal form, its ASCII form, the fundamental group and the dimension are those of
the factor counts; a joint follows a joint the report has, not itself; a joint's limits
have as many upper bounds as lower ones; the joints' ``slots`` name at most
`MAX_SLOT_NAMES` entries of each vector; a joint's ``origin`` is a floating joint's,
turned by a unit quaternion, within `MAX_ORIGIN_METRES` of the world's origin, and
``at_world_origin`` is said of the root joint only, never true of one with an
``origin``; the coordinates section's sizes agree; the ``closure`` agrees with itself
and the report (`_closure_check`); MuJoCo's actuators belong to an MJCF report, drive
its joints and are named once each; the ``limits_file`` names joints of the report and
states their limits (`_limits_check`).
"""

from __future__ import annotations

import math
from typing import Any

from cspace._reports._closure_check import check_closure
from cspace._reports._limits_check import check_limits_file
from cspace._reports._refusal import invalid, only_in
from cspace._reports._ros2_control_check import check_ros2_control
from cspace._reports._strict_json import describe
from cspace._reports.matching import SPLIT_PLANAR

MAX_SLOT_NAMES = 14_000
"""Most entries of one convention's vector (canonical coordinates, Pinocchio's q, MuJoCo's
qpos, ...) named in the joints' ``slots``, like the 14,000 coordinates the schema allows:
a robot of 5,000 joints and 10,000 degrees of freedom has at most 13,340 (3,333 ball
joints of four each, and a floating root joint). The page draws a cell for each."""


ORIGIN_TOLERANCE = 1e-9
"""How far from 1 the norm of a joint origin's quaternion may be: cspace writes them
unit to rounding, and the Drake convention composes them as they are."""


MAX_ORIGIN_METRES = 1e6
"""Farthest a root joint's ``origin`` may be from the world's origin, along each axis (m):
a thousand kilometres is no robot's placement, and composed into Drake's q a double there
keeps only about a tenth of a nanometre."""

_SPLIT_SUFFIXES = tuple(suffix for suffix, _ in SPLIT_PLANAR)
"""MuJoCo's URDF converter's joints of a planar joint: ``_TX``, ``_TY``, ``_RZ``."""


def check_consistency(path: str, document: dict[str, Any]) -> None:
    """Refuse a document that contradicts itself (see the module's docstring).

    Raises:
        ReportFileError: The first contradiction, with its JSON Pointer.
    """
    from cspace._manifold import NormalForm

    manifold = document["manifold"]
    counts = manifold["factors"]
    form = NormalForm(r=counts["R"], t=counts["T"], rp3=counts["RP3"])
    derived = {
        "/manifold/notation": (manifold["notation"], form.notation),
        "/manifold/ascii": (manifold["ascii"], form.ascii),
        "/manifold/fundamental_group": (manifold["fundamental_group"], form.fundamental_group),
        "/manifold/simply_connected": (manifold["simply_connected"], form.simply_connected),
        "/dimension": (document["dimension"], form.dimension),
    }
    for where, (found, expected) in derived.items():
        if found != expected:
            problem = f"{describe(found)} contradicts the factors, which give {describe(expected)}"
            invalid(path, problem, where)
    slot_names: dict[str, int] = {}
    names = {joint["name"] for joint in document["joints"]}
    roots = _root_names(document["joints"], names)
    for index, joint in enumerate(document["joints"]):
        mimic = joint["mimic"]
        if mimic is not None and (mimic["joint"] not in names or mimic["joint"] == joint["name"]):
            problem = f"joint {describe(joint['name'])} follows {describe(mimic['joint'])}, " + (
                "itself" if mimic["joint"] == joint["name"] else "which the report does not have"
            )
            invalid(path, problem, f"/joints/{index}/mimic/joint")
        _check_origin(path, joint, index, roots)
        limits = joint["limits"]
        if limits is not None and len(limits["lower"]) != len(limits["upper"]):
            problem = f"{len(limits['upper'])} upper bounds for {len(limits['lower'])} lower bounds"
            invalid(path, problem, f"/joints/{index}/limits/upper")
        for convention, slot in joint.get("slots", {}).items():
            slot_names[convention] = slot_names.get(convention, 0) + len(slot["names"])
            if slot_names[convention] > MAX_SLOT_NAMES:
                problem = (
                    f"more than {MAX_SLOT_NAMES:,} entries in {convention} (a vector of "
                    "coordinates); cspace inspect writes at most that many"
                )
                invalid(path, problem, f"/joints/{index}/slots/{convention}/names")
    coordinates = document["coordinates"]
    sizes = (coordinates["size"], len(coordinates["entries"]), len(coordinates["neutral"]))
    if len(set(sizes)) != 1:
        problem = (
            f"the coordinates section has size {sizes[0]}, {sizes[1]} entries and "
            f"{sizes[2]} neutral values"
        )
        invalid(path, problem, "/coordinates/neutral")
    check_closure(path, document)
    check_ros2_control(path, document)
    check_limits_file(path, document)
    _check_actuators(path, document, names)


def _check_actuators(path: str, document: dict[str, Any], names: set[str]) -> None:
    """MuJoCo's actuators: an MJCF report's, driving its joints, each name once.

    MuJoCo refuses a repeated name, and the diff pairs actuators by name.
    """
    actuators = document.get("actuators") or []
    if actuators:
        only_in(path, document, ("mjcf",), "MuJoCo's actuators", "/actuators")
    named: dict[str, int] = {}
    for index, actuator in enumerate(actuators):
        name = actuator["name"]
        if name is not None and named.setdefault(name, index) != index:
            problem = f"actuators {named[name]} and {index} are both named {describe(name)}"
            invalid(path, problem, f"/actuators/{index}/name")
        target = actuator["target"]
        on_joint = actuator["transmission"] in ("joint", "jointinparent")
        if on_joint and target is not None and target not in names:
            problem = f"actuator {index} drives joint {describe(target)}, which the report lacks"
            invalid(path, problem, f"/actuators/{index}/target")


def _root_names(joints: list[dict[str, Any]], names: set[str]) -> set[str]:
    """The joints ``at_world_origin`` may be said of: the root joint's (as `_root_place`).

    The first joint with coordinates when it is at q 0 and floating or planar, or, when
    it is one of MuJoCo's three joints of a planar joint ``P`` (``P_TX``, ``P_TY``,
    ``P_RZ``), those three.
    """
    first = next((j for j in joints if j["q_index"] is not None), None)
    if first is None or first["q_index"] != 0:
        return set()
    if first["kind"] in ("floating", "planar"):
        return {first["name"]}
    name = first["name"]
    suffix = next((s for s in _SPLIT_SUFFIXES if name.endswith(s)), None)
    if suffix is None:
        return set()
    base = name.removesuffix(suffix)
    return {f"{base}{s}" for s in _SPLIT_SUFFIXES} & names


def _check_origin(path: str, joint: dict[str, Any], index: int, roots: set[str]) -> None:
    """A joint's placement, as cspace writes it.

    ``at_world_origin`` is said of the root joint only (`_root_names`) and is not true of
    a joint with an ``origin``; an ``origin`` is a floating joint's, turned by a unit
    quaternion, within `MAX_ORIGIN_METRES` of the world's origin along each axis.
    """
    name = describe(joint["name"])
    pointer = f"/joints/{index}/at_world_origin"
    origin = joint.get("origin")
    problem = None
    if "at_world_origin" in joint and joint["name"] not in roots:
        problem = f"joint {name} is not the root joint: only the root joint is at_world_origin"
    elif origin is None:
        return
    elif joint.get("at_world_origin") is True:
        problem = f"joint {name} is at_world_origin, yet has an origin off the world's"
    else:
        pointer = f"/joints/{index}/origin"
        if joint["kind"] != "floating":
            problem = f"joint {name} is {joint['kind']}: only a floating one has an origin"
        elif abs(math.hypot(*origin[3:]) - 1.0) > ORIGIN_TOLERANCE:
            problem = f"joint {name}'s origin turns by a quaternion that is not unit"
        elif any(abs(v) > MAX_ORIGIN_METRES for v in origin[:3]):
            problem = (
                f"joint {name}'s origin is farther than {MAX_ORIGIN_METRES:g} m from the "
                "world's origin"
            )
    if problem is not None:
        invalid(path, problem, pointer)
