"""The registry of conventions: each tool a configuration crosses, declared once.

A tool's entry says what it calls its vectors, how it orders joints and stores each
factor, whether its velocity map needs the configuration (a velocity expressed in
another frame), and where its maps live. The command line's choices, the HTML
report's strips and the diff's labels come from this table; adding a tool is one
module of maps (in `cspace.space._conventions`) and one entry here. No NumPy, and
nothing of the space: the reports, the renderers and the command line read it
(`cspace.conventions.TOOLS` is its public name).
"""

from cspace._record import NamedTuple


class Tool(NamedTuple):
    """One convention.

    Attributes:
        name: Its name on the command line and in Python (``pinocchio``).
        title: The tool, for people (``Pinocchio``).
        positions: What the tool calls a configuration vector (``q``, ``qpos``).
        velocities: What it calls a velocity vector (``v``, ``qvel``).
        slots: The report's JSON slot keys for its positions and velocities, or None
            when reports do not carry them.
        order: How the tool orders joints.
        storage: How it stores each factor, in one line.
        module: The name of the module that holds its maps (a class ``Maps``),
            imported when the tool is first used.
        velocity_needs_at: Its velocities need the configuration they are taken at.
    """

    name: str
    title: str
    positions: str
    velocities: str
    slots: tuple[str, str] | None
    order: str
    storage: str
    module: str
    velocity_needs_at: bool = False

    def label(self, velocity: bool = False) -> str:
        """``Pinocchio q``, ``MuJoCo qvel``: the tool and its vector's name."""
        return f"{self.title} {self.velocities if velocity else self.positions}"


TOOLS: dict[str, Tool] = {
    tool.name: tool
    for tool in (
        Tool(
            "canonical",
            "cspace's canonical",
            "coordinates",
            "tangent",
            ("canonical", "tangent"),
            "Pinocchio's (depth first, siblings as Pinocchio's parser orders them)",
            "an angle in [-pi, pi) per circle, a quaternion (w, x, y, z) with w >= 0",
            "_canonical",
        ),
        Tool(
            "pinocchio",
            "Pinocchio",
            "q",
            "v",
            ("pinocchio_q", "pinocchio_v"),
            "Pinocchio's model (depth first)",
            "a continuous joint as (cos, sin), a quaternion (x, y, z, w); a floating or "
            "planar joint's linear velocity in the body frame",
            "_pinocchio",
            velocity_needs_at=True,
        ),
        Tool(
            "mujoco",
            "MuJoCo",
            "qpos",
            "qvel",
            ("mujoco_qpos", "mujoco_qvel"),
            "MuJoCo's model (bodies in file order); a mimic follower keeps its entry",
            "one angle per hinge, a quaternion (w, x, y, z); a free joint's linear "
            "velocity in the world frame",
            "_mujoco",
        ),
        Tool(
            "drake",
            "Drake",
            "q",
            "v",
            ("drake_q", "drake_v"),
            "Drake's parser: depth first, children in the order their joints are "
            "declared; a mimic follower keeps its entry; a root welded unless floating",
            "one angle per revolute joint, a floating body as (qw, qx, qy, qz, x, y, z) "
            "with velocities (wx, wy, wz, vx, vy, vz) in the world frame; a planar joint "
            "(x, y, qz)",
            "_drake",
            velocity_needs_at=True,
        ),
        Tool(
            "isaac",
            "Isaac",
            "joint_pos",
            "joint_vel",
            None,
            "PhysX's: breadth first from each articulation's root, the joints below a link "
            "by prim path (by name for a robot not read from USD); a mimic follower keeps "
            "its entry",
            "one value per revolute or prismatic joint; a floating root first, as Isaac "
            "Lab 3's root pose (x, y, z, qx, qy, qz, qw) and velocity (linear, angular, "
            "both in the world frame)",
            "_isaac",
            velocity_needs_at=True,
        ),
        Tool(
            "pybullet",
            "PyBullet",
            "q",
            "u",
            None,
            "p.loadURDF's joint indices: depth first from the base, children in the order "
            "their joints are declared; fixed joints have an index and no entry; a mimic "
            "follower keeps its entry",
            "one value per revolute or prismatic joint, a spherical joint's quaternion (x, y, "
            "z, w); a free base first as its link's position and quaternion (x, y, z, w), its "
            "velocities (linear, angular) in the world frame",
            "_pybullet",
            velocity_needs_at=True,
        ),
        Tool(
            "mujoco-ctrl",
            "MuJoCo",
            "ctrl",
            "ctrl rate",
            None,
            "MuJoCo's actuators, in the order the file declares them",
            "a position actuator's target on a hinge or slide, gear * qpos; 0 for every other "
            "actuator (a joint no position actuator drives comes back neutral)",
            "_mujoco_ctrl",
        ),
    )
}
"""Every convention of whole vectors, by name (``named``, values by joint, is not one)."""
