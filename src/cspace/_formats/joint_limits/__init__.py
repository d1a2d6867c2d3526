"""MoveIt's ``joint_limits.yaml``: the limits a planner reads beside the URDF."""
