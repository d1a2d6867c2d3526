"""What a saved report's ``limits_file`` must agree with: the report it is in.

Only a URDF's (or xacro's) report has one; each joint it names is a joint of the report
with one coordinate (revolute, continuous, prismatic or a mimic joint), or one a group's
report holds, named once; and the position limits of each that is not held are the
joint's: the C-space the report states is the one of the limits it says MoveIt plans
with.
"""

from __future__ import annotations

from typing import Any

from cspace._reports._refusal import invalid, only_in
from cspace._reports._strict_json import describe

_TAKES = ("urdf", "xacro")
_ONE_COORDINATE = ("revolute", "continuous", "prismatic", "mimic")


def check_limits_file(path: str, document: dict[str, Any]) -> None:
    """Refuse a ``limits_file`` that contradicts its report (see the module).

    Raises:
        ReportFileError: The first contradiction, with its JSON Pointer.
    """
    summary = document.get("limits_file")
    if summary is None:
        return
    only_in(path, document, _TAKES, "a joint_limits.yaml", "/limits_file")
    joints = {j["name"]: j for j in document["joints"]}
    group = document.get("group")
    held = {h["joint"] for h in group["held"]} if group else set()
    seen: set[str] = set()
    for index, entry in enumerate(summary["joints"]):
        where = f"/limits_file/joints/{index}"
        name = entry["joint"]
        joint = joints.get(name)
        kind = None if joint is None else joint["kind"]
        if joint is None or (kind not in _ONE_COORDINATE and name not in held):
            problem = f"limits of {describe(name)}, no joint of one coordinate of the report"
            invalid(path, problem, f"{where}/joint")
        if name in seen:
            invalid(path, f"{describe(name)} given twice", f"{where}/joint")
        seen.add(name)
        if name in held:  # a group's report: held, fixed here, its limits the robot's
            continue
        limits = joint["limits"]
        for side in ("lower", "upper"):
            value = entry[side]["value"]
            kept = None if limits is None or not limits[side] else limits[side][0]
            if value != kept:
                problem = f"a {side} limit of {describe(name)} other than the joint's"
                invalid(path, problem, f"{where}/{side}/value")
