"""MoveIt's SRDF: the semantic description beside a URDF, and what tells a file is one."""
