"""Where the ``example-robot-data`` package keeps its robot files.

The package installs its robots as data under ``cmeel.prefix/share`` in site-packages;
it has no Python module to ask, so the installed distribution's metadata is asked.
"""

from __future__ import annotations

from pathlib import Path

from cspace._safetext import printable
from cspace.errors import ExampleRobotDataError
from cspace.errors._base import did_you_mean

ERD_PREFIX = "erd:"
"""``erd:NAME`` names a robot bundled with example-robot-data."""

_ROBOTS = "cmeel.prefix/share/example-robot-data/robots"


def robots_dir() -> Path:
    """The folder that holds example-robot-data's robot descriptions.

    Raises:
        ExampleRobotDataError: The package is not installed, or its robot folder is missing.
    """
    # Imported here: importlib.metadata costs about 30 ms, which every command would pay,
    # since the CLI and the loader import this module for `ERD_PREFIX`.
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        path = Path(str(distribution("example-robot-data").locate_file(_ROBOTS)))
    except PackageNotFoundError:
        raise ExampleRobotDataError(
            f"{ERD_PREFIX} names need the example-robot-data package, which is not installed: "
            "pip install 'cspace[erd]' (or example-robot-data)"
        ) from None
    if not path.is_dir():
        raise ExampleRobotDataError(f"example-robot-data has no robot folder at {path}")
    return path


def urdf_files() -> list[Path]:
    """Every URDF file example-robot-data installs, sorted by path."""
    return sorted(robots_dir().rglob("*.urdf"))


# name -> (file under robots_dir(), whether example-robot-data's own loader puts a
# free-flyer root joint under it). Our table, from the upstream loader's choices: legged
# robots, humanoids, flying robots and mobile manipulators float; arms and hands do not.
_BY_NAME: dict[str, tuple[str, bool]] = {
    "a1": ("a1_description/urdf/a1.urdf", True),
    "allegro_left_hand": ("allegro_hand_description/urdf/allegro_left_hand.urdf", False),
    "allegro_right_hand": ("allegro_hand_description/urdf/allegro_right_hand.urdf", False),
    "alex_nub_hands": ("alex_description/urdf/alex_nub_hands.urdf", False),
    "alex_psyonic_hands": ("alex_description/urdf/alex_psyonic_hands.urdf", False),
    "alex_sake_hands": ("alex_description/urdf/alex_sake_hands.urdf", False),
    "anymal": ("anymal_b_simple_description/robots/anymal.urdf", True),
    "anymal_c": ("anymal_c_simple_description/urdf/anymal.urdf", True),
    "anymal_kinova": ("anymal_b_simple_description/robots/anymal-kinova.urdf", True),
    "asr_twodof": ("asr_twodof_description/urdf/TwoDofs.urdf", False),
    "b1": ("b1_description/urdf/b1.urdf", True),
    "b1_z1": ("b1_description/urdf/b1-z1.urdf", True),
    "baxter": ("baxter_description/urdf/baxter.urdf", False),
    "bolt": ("bolt_description/robots/bolt.urdf", True),
    "borinot": ("borinot_description/urdf/borinot_flying_arm_2.urdf", True),
    "cassie": ("cassie_description/robots/cassie.sdf", True),
    "double_pendulum": ("double_pendulum_description/urdf/double_pendulum.urdf", False),
    "double_pendulum_continuous": (
        "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
        False,
    ),
    "double_pendulum_simple": (
        "double_pendulum_description/urdf/double_pendulum_simple.urdf",
        False,
    ),
    "finger_edu": ("finger_edu_description/robots/finger_edu.urdf", False),
    "go1": ("go1_description/urdf/go1.urdf", True),
    "go2": ("go2_description/urdf/go2.urdf", True),
    "hector": ("hector_description/robots/quadrotor_base.urdf", True),
    "hextilt": ("hextilt_description/urdf/hextilt_flying_arm_5.urdf", True),
    "human": ("human_description/robots/human.urdf", True),
    "hyq": ("hyq_description/robots/hyq_no_sensors.urdf", True),
    "icub": ("icub_description/robots/icub.urdf", True),
    "icub_reduced": ("icub_description/robots/icub_reduced.urdf", True),
    "iris": ("iris_description/robots/iris_simple.urdf", True),
    "kinova": ("kinova_description/robots/kinova.urdf", False),
    "laikago": ("laikago_description/urdf/laikago.urdf", True),
    "panda": ("panda_description/urdf/panda.urdf", False),
    "panda_collision": ("panda_description/urdf/panda_collision.urdf", False),
    "pr2": ("pr2_description/urdf/pr2.urdf", True),
    "quadruped": ("quadruped_description/urdf/quadruped.urdf", True),
    "romeo": ("romeo_description/urdf/romeo.urdf", True),
    "simple_humanoid": ("simple_humanoid_description/urdf/simple_humanoid.urdf", True),
    "simple_humanoid_classical": (
        "simple_humanoid_description/urdf/simple_humanoid_classical.urdf",
        True,
    ),
    "solo8": ("solo_description/robots/solo.urdf", True),
    "solo12": ("solo_description/robots/solo12.urdf", True),
    "talos": ("talos_data/robots/talos_reduced.urdf", True),
    "talos_arm": ("talos_data/robots/talos_left_arm.urdf", False),
    "talos_box": ("talos_data/robots/talos_reduced_box.urdf", True),
    "talos_full": ("talos_data/robots/talos_full_v2.urdf", True),
    "talos_full_box": ("talos_data/robots/talos_full_v2_box.urdf", True),
    "tiago": ("tiago_description/robots/tiago.urdf", False),
    "tiago_dual": ("tiago_description/robots/tiago_dual.urdf", False),
    "tiago_no_hand": ("tiago_description/robots/tiago_no_hand.urdf", False),
    "tiago_pro": ("tiago_pro_description/robots/tiago_pro.urdf", False),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", False),
    "ur3_gripper": ("ur_description/urdf/ur3_gripper.urdf", False),
    "ur3_limited": ("ur_description/urdf/ur3_joint_limited_robot.urdf", False),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", False),
    "ur5_gripper": ("ur_description/urdf/ur5_gripper.urdf", False),
    "ur5_limited": ("ur_description/urdf/ur5_joint_limited_robot.urdf", False),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", False),
    "ur10_limited": ("ur_description/urdf/ur10_joint_limited_robot.urdf", False),
    "z1": ("z1_description/urdf/z1.urdf", False),
}

ERD_ROBOTS = tuple(sorted(_BY_NAME))
"""The names ``erd:NAME`` accepts."""


def available() -> list[str]:
    """The names of `ERD_ROBOTS` whose files the installed package has."""
    folder = robots_dir()
    return [n for n in ERD_ROBOTS if (folder / _BY_NAME[n][0]).is_file()]


def resolve(name: str) -> tuple[Path, str | None]:
    """The file of example-robot-data's robot ``name`` and the root joint its loader adds.

    Args:
        name: A robot name such as ``talos`` (without the ``erd:`` prefix).

    Returns:
        The robot file, and ``"floating"`` or None.

    Raises:
        ExampleRobotDataError: Unknown name, or the package or the file is missing.
    """
    entry = _BY_NAME.get(name)
    if entry is None:
        names = available()
        raise ExampleRobotDataError(
            f"unknown example-robot-data robot '{printable(name, limit=80)}' "
            f"(known: {', '.join(names)})" + did_you_mean(name, names)
        )
    path = robots_dir() / entry[0]
    if not path.is_file():
        raise ExampleRobotDataError(f"example-robot-data has no file {entry[0]} for robot '{name}'")
    return path, "floating" if entry[1] else None
