"""The xacro reader: the document xacro makes, read as URDF.

xacro runs code: the expansion runs in a confined child (`expand`). Its output is one
more file of the robot (charged to the run's budget), and is refused if it is an SRDF,
as the loader refuses one. Line numbers point into xacro's output, not the file, and
are dropped.
"""

from __future__ import annotations

from cspace._formats.shared.description import RobotDescription
from cspace._formats.shared.reading import Reading, ReadRequest
from cspace._formats.shared.xmlio import parse_xml
from cspace._formats.srdf.kind import refuse_srdf
from cspace._formats.urdf.reader import read_urdf
from cspace._formats.xacro.expand import XacroOptions, expand_xacro
from cspace._ros2_control import ControlHardware


def read(request: ReadRequest) -> Reading:
    """Expand the xacro file ``request`` names and read what it makes as URDF.

    The reading's ``path`` names the robot ``"FILE (expanded by xacro)"`` in messages.

    Raises:
        RobotFileError: xacro refused the file, or what it made is no URDF robot.
    """
    options = request.options if isinstance(request.options, XacroOptions) else XacroOptions()
    urdf = expand_xacro(request.source, options, request.on_disk)
    request.budget.charge(urdf)  # xacro's output counts as one more file of the robot
    path = f"{request.path} (expanded by xacro)"
    root = parse_xml(urdf._replace(path=path))
    refuse_srdf(request.path, root, named=request.named_srdf, written=request.root)
    reading = read_urdf(path, root, urdf.text)
    poses = tuple(pose._replace(line=None) for pose in reading.poses)
    return reading._replace(description=_without_lines(reading.description), path=path, poses=poses)


def _without_lines(description: RobotDescription) -> RobotDescription:
    """The description with line numbers dropped (they point into xacro's output).

    Every other field is kept as read: the loops' cuts (Drake's ball constraints, without
    their lines), the joints the file drives, its ``<ros2_control>``.
    """
    return description.replace(
        links=tuple(
            link._replace(
                line=None,
                collisions=tuple(c._replace(line=None) for c in link.collisions),
                unread=tuple((None, problem) for _, problem in link.unread),
            )
            for link in description.links
        ),
        joints=tuple(
            joint._replace(line=None, limit_line=None, axis_line=None)
            for joint in description.joints
        ),
        findings=tuple(d._replace(line=None) for d in description.findings),
        cuts=tuple(cut._replace(line=None) for cut in description.cuts),
        ros2_control=tuple(_control_without_lines(h) for h in description.ros2_control),
    )


def _control_without_lines(hardware: ControlHardware) -> ControlHardware:
    """A ``<ros2_control>`` component with its lines dropped, its joints' and interfaces'."""
    joints = tuple(
        joint._replace(
            line=None,
            command=tuple(i._replace(line=None) for i in joint.command),
            state=tuple(i._replace(line=None) for i in joint.state),
        )
        for joint in hardware.joints
    )
    return hardware._replace(line=None, joints=joints)
