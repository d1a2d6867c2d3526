"""What a saved report's ``ros2_control`` section must satisfy that the schema cannot say.

The section is a URDF's or xacro's alone; its components together name at most as many
joints and interfaces as the reader reads (`MAX_JOINTS`, `MAX_INTERFACES`); a pose whose
source is ``ros2_control`` is one of its components'.
"""

from typing import Any

from cspace._reports._refusal import invalid, only_in
from cspace._reports._strict_json import describe

MAX_JOINTS = 5000
"""Most joints the components name together (the URDF reader's bound)."""

MAX_INTERFACES = 4 * MAX_JOINTS
"""Most interfaces their joints have together (the URDF reader's bound)."""


def check_ros2_control(path: str, document: dict[str, Any]) -> None:
    """Refuse a report whose ``ros2_control`` section contradicts the rest of it.

    Raises:
        ReportFileError: The first contradiction, with its JSON Pointer.
    """
    hardware = document.get("ros2_control") or []
    if hardware:
        only_in(path, document, ("urdf", "xacro"), "<ros2_control>", "/ros2_control")
    joints = interfaces = 0
    for index, component in enumerate(hardware):
        joints += len(component["joints"])
        if joints > MAX_JOINTS:
            problem = f"more than {MAX_JOINTS:,} <ros2_control> joints (cspace reads no more)"
            invalid(path, problem, f"/ros2_control/{index}/joints")
        for joint in component["joints"]:
            interfaces += len(joint["command_interfaces"]) + len(joint["state_interfaces"])
        if interfaces > MAX_INTERFACES:
            problem = (
                f"more than {MAX_INTERFACES:,} <ros2_control> interfaces (cspace reads no more)"
            )
            invalid(path, problem, f"/ros2_control/{index}/joints")
    names = {component["name"] for component in hardware}
    for index, pose in enumerate(document.get("poses") or []):
        if pose["source"] == "ros2_control" and pose["name"] not in names:
            problem = f"pose {describe(pose['name'])} is no <ros2_control> component's"
            invalid(path, problem, f"/poses/{index}/name")
