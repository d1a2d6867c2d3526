"""MJCF ranges whose unit looks slipped: radians written where the file says degrees.

MuJoCo reads a hinge's or ball's ``range`` in the unit of ``<compiler angle>``, degrees
unless the file says ``radian``. A range such as ``-2.79 -0.03`` in degrees (0.05 rad
wide) is almost always radians written in a file that forgot ``<compiler
angle="radian"/>`` (gz-physics#1003 and IsaacLab#663 are this mistake): MuJoCo reads
it, so does cspace, and the finding ``range-looks-like-radians`` says what was probably
meant and how to say it. The reverse slip, degrees in a radian file, is
``limits-in-degrees`` (every format).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec

_ANGLES = ("hinge", "ball")
"""MJCF joint types whose range is an angle."""


WHOLE = 1e-4
"""How near a whole number of degrees a bound is whole (a range converted from radians
to degrees and written with its rounding, dm_control's fruit fly's -4.99999985, is)."""


def _looks_like_radians(written: Sequence[float]) -> bool:
    """Within one turn in radians (|x| <= 2 pi) and not all whole numbers of degrees."""
    biggest = max(abs(x) for x in written)
    whole = all(abs(x - round(x)) <= WHOLE for x in written)
    return 0.0 < biggest <= 2 * math.pi + 1e-9 and not whole


def radian_slips(joints: Sequence[JointSpec], degree: bool) -> list[Diagnostic]:
    """``range-looks-like-radians`` for each angle range that looks like radians.

    Args:
        joints: The MJCF file's joints, their limits in rad as MuJoCo compiled them.
        degree: The file's angles are in degrees (``<compiler angle>``).
    """
    if not degree:
        return []
    found = []
    for joint in joints:
        if joint.type not in _ANGLES or not joint.lower:
            continue
        bounds = (joint.upper[0],) if joint.type == "ball" else (joint.lower[0], joint.upper[0])
        if not all(math.isfinite(x) for x in bounds):
            continue
        written = [math.degrees(x) for x in bounds]
        if not _looks_like_radians(written):
            continue
        said = ", ".join(f"{x:.6g}" for x in written)
        rad = ", ".join(f"{x:.4g}" for x in bounds)
        found.append(
            finding(
                "range-looks-like-radians",
                joint.name,
                f"{joint.type} '{joint.name}' has range {said} in degrees (the file's "
                f"<compiler angle>, degrees unless it says radian), {rad} rad: it looks "
                'like radians. If radians are meant, say <compiler angle="radian"/>',
                joint.line,
            )
        )
    return found
