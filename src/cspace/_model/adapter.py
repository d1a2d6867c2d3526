"""The one place that talks to Pinocchio.

It builds a Pinocchio model: from a URDF with Pinocchio's parser (mimic joints kept
dependent; what its C++ parser prints is silenced and kept), from an MJCF file's
kinematic tree as MuJoCo compiled it, and joint by joint for SDF and OpenUSD (both in
`_assemble`). It returns our own records (`PinModel`, in `_records`), so that nothing
else in `cspace` depends on Pinocchio's types.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pinocchio as pin

from cspace._formats.shared.description import RobotDescription
from cspace._formats.shared.kinematic_tree import KinematicTree
from cspace._formats.shared.reading import JointList, Reading
from cspace._joint_kind import JointKind
from cspace._model._assemble import build_model, build_tree_model, tree_model
from cspace._model._records import (
    ROOT_JOINT_NAME,
    ROOT_JOINTS,
    PinJoint,
    PinMimic,
    PinModel,
    dependent,
    record_of,
    root_joint_model,
)
from cspace._model.native import on_own_stack, parser_messages, quietly
from cspace.errors import ModelBuildError

__all__ = [
    "ROOT_JOINTS",
    "ROOT_JOINT_NAME",
    "PinJoint",
    "PinMimic",
    "PinModel",
    "build",
    "build_model",
    "build_tree_model",
    "build_urdf_model",
    "exception_text",
    "record_of",
    "tree_model",
]


def build(path: str, reading: Reading, root_joint: str | None) -> PinModel:
    """The Pinocchio model of any reader's `Reading`.

    Args:
        path: The file, for messages.
        reading: What the format reader found, with its recipe.
        root_joint: None, ``"floating"`` or ``"planar"``.

    Raises:
        ModelBuildError: Pinocchio refused the model.
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    recipe, description = reading.recipe, reading.description
    if isinstance(recipe, KinematicTree):
        mimics = {j.name: j.mimic for j in description.joints if j.mimic is not None}
        return build_tree_model(recipe, root_joint, mimics)
    if isinstance(recipe, JointList):
        mimics = {j.name: j.mimic for j in description.joints if j.mimic is not None}
        return build_model(description.name, recipe.joints, root_joint, mimics, recipe.links)
    has_mimic = any(j.mimic is not None for j in description.joints)
    return build_urdf_model(
        path, recipe.text, root_joint, has_mimic=has_mimic, description=description
    )


def build_urdf_model(
    path: str,
    text: str,
    root_joint: str | None,
    *,
    has_mimic: bool = False,
    description: RobotDescription | None = None,
) -> PinModel:
    """Build a Pinocchio model from URDF text, mimic joints kept dependent.

    Pinocchio keeps a mimic joint dependent only when its leader comes earlier in its
    joint order; when it refuses for that reason, the model is built again with mimic
    joints as free joints, and ``mimic_fallback`` says why.

    Args:
        path: The file, for messages.
        text: The URDF document.
        root_joint: None, ``"floating"`` or ``"planar"``: a joint added above the root link.
        has_mimic: The file declares mimic joints (enables the fallback).
        description: The file as our reader read it: when Pinocchio refuses it, the
            joint or link its message names gives the error its line.

    Returns:
        The model's joints and sizes.

    Raises:
        ModelBuildError: Pinocchio refused the file; its messages are kept.
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    args: tuple[Any, ...] = ()
    if root_joint is not None:
        args = (root_joint_model(root_joint), ROOT_JOINT_NAME)

    def build(mimic: bool) -> Callable[[], Any]:
        return lambda: pin.buildModelFromXML(text, *args, mimic=mimic)

    swaps = _swaps(description)  # mimic joints made dependent after the swap, if any
    model, error, printed = on_own_stack(lambda: quietly(build(not swaps)))
    messages = parser_messages(printed)
    fallback = None
    if error is not None and has_mimic:
        model, second_error, printed = on_own_stack(lambda: quietly(build(False)))
        if second_error is None:
            fallback = _error_text(error, messages)
            messages = parser_messages(printed)
    if model is None:
        said = _error_text(error, messages)
        named = " ".join((said, *messages))  # the element may be named by a later message
        line, element = (None, None) if description is None else description.locate(named)
        raise ModelBuildError(
            path,
            f"Pinocchio's URDF parser refused the file: {said}",
            messages,
            line=line,
            element=element,
        )
    if swaps and description is not None:
        from cspace._model._swap import swap_joints

        mimics = {j.name: j.mimic for j in description.joints if j.mimic is not None}
        model, fallback = dependent(swap_joints(model, swaps), mimics)
    return record_of(model, messages, fallback)


_SWAPPED = {JointKind.SPHERICAL: "spherical", JointKind.UNIVERSAL: "universal"}
"""The kinds of ``<drake:joint>`` Pinocchio's URDF parser is given as floating joints."""


def _swaps(description: RobotDescription | None) -> dict[str, str]:
    """The joints whose models `swap_joints` puts in place, by name."""
    if description is None:
        return {}
    return {
        j.name: _SWAPPED[j.kind]
        for j in description.joints
        if j.type.startswith("drake:") and j.kind in _SWAPPED
    }


def _error_text(error: BaseException | None, messages: tuple[str, ...]) -> str:
    if messages:
        return messages[0]
    if error is None:
        return "unknown error"
    return exception_text(str(error)) or type(error).__name__


def exception_text(text: str) -> str:
    """What a Pinocchio C++ exception says, on one line, without its source location.

    Pinocchio's checks raise ``From file: ... in function: <template signature> at
    line: N message: <what> hint: <why>``; only the message and the hint are about the
    robot file.
    """
    lines = [line.strip() for line in text.strip().splitlines() if line.strip()]
    if "message:" in lines:
        kept = lines[lines.index("message:") + 1 :]
        return "; ".join(line.removeprefix("hint: ") for line in kept)
    return " ".join(lines)
