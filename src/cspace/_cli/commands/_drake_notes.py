"""What ``cspace convert`` says on standard error when Drake's vectors are one side.

Drake's model of a robot file is not always the one cspace converts for: its URDF and
SDF parsers float a root link no joint holds (cspace's vectors are those of the plant
with it welded), its MJCF parser builds some files otherwise than MuJoCo and its URDF
parser some otherwise than Pinocchio (the report's ``drake-mjcf-differs`` and
``drake-urdf-differs`` findings). The vectors are written all the same, in Drake's names
and order; these lines say where the model differs.
"""

from __future__ import annotations

from typing import Any

from ..output import finding, note


def say_drake(robot: str, conventions: Any) -> None:
    """A note for each root link Drake would float; a warning for each model difference.

    Args:
        robot: The robot file, as named on the command line (each warning starts with it,
            and the line of the finding where it has one).
        conventions: The robot's `Conventions`.
    """
    if conventions.drake.welded:
        links = ", ".join(f"'{link}'" for link in conventions.drake.welded)
        note(
            f"Drake's parser would float link(s) {links}, which no joint holds to the world; "
            "these are Drake's vectors with them welded (plant.WeldFrames before Finalize)"
        )
    for said in conventions.drake.findings:
        at = f"{robot}:{said.line}" if said.line is not None else robot
        finding("warning", f"{at}: {said.message} [{said.code}]")
