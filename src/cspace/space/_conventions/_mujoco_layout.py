"""MuJoCo's layout of a robot, from what a user gives for it.

``ConfigurationSpace.conventions(mujoco=...)`` (and ``--mujoco MJCF``) takes an MJCF
file, its report, a ``mujoco.MjModel`` or a `MujocoLayout`; this module turns each into
the `MujocoLayout` (data) the MuJoCo maps (`_mujoco`) take. It is the one module of the
conventions that reads a robot file (through the loader) or knows the report.
"""

from __future__ import annotations

import os

from cspace._slots import MujocoLayout
from cspace.errors import JointMatchError


def mujoco_layout(mujoco: object) -> MujocoLayout:
    """A MuJoCo layout from an MJCF path, an MJCF report, a ``mujoco.MjModel`` or a layout.

    Raises:
        JointMatchError: ``mujoco`` is none of these (or a report of another format).
        RobotFileError: The MJCF file cannot be read.
    """
    from cspace._reports.report import Report

    if isinstance(mujoco, MujocoLayout):
        return mujoco
    if isinstance(mujoco, Report):
        return MujocoLayout.from_report(mujoco)
    if isinstance(mujoco, str | os.PathLike):
        from cspace._model.loader import inspect

        return MujocoLayout.from_report(inspect(mujoco))
    if hasattr(mujoco, "njnt") and hasattr(mujoco, "jnt_qposadr"):
        return MujocoLayout.from_model(mujoco)
    raise JointMatchError(
        f"mujoco must be an MJCF file, its report, a mujoco.MjModel or a MujocoLayout, "
        f"not {type(mujoco).__name__}"
    )
