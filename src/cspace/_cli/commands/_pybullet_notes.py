"""What ``cspace convert`` says on standard error when PyBullet's vectors are one side.

PyBullet's model of a URDF is not always the file's C-space: ``p.loadURDF`` floats the
base link unless ``useFixedBase=True`` (or its mass is 0), ignores ``<mimic>`` and makes
a floating joint fixed (`Conventions.pybullet`). The vectors are written all the same,
in PyBullet's joint order; these lines say where its C-space differs, as Drake's notes
do (`_drake_notes`).
"""

from __future__ import annotations

from typing import Any

from ..output import finding, note


def say_pybullet(robot: str, conventions: Any) -> None:
    """A note when PyBullet would float the base; a warning for each of its findings.

    Args:
        robot: The robot file, as named on the command line (each warning starts with it,
            and the line of the finding where it has one).
        conventions: The robot's `Conventions`.
    """
    order = conventions.pybullet
    if order.floats is not None:
        note(
            f"PyBullet floats link '{order.floats}' unless p.loadURDF(..., useFixedBase=True) "
            "(or its mass is 0); these are PyBullet's vectors with it fixed"
        )
    for said in order.findings:
        at = f"{robot}:{said.line}" if said.line is not None else robot
        finding("warning", f"{at}: {said.message} [{said.code}]")
