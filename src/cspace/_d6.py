"""A generic (D6) joint's axes, and the links cspace makes to split one per axis.

OpenUSD's generic joint (``PhysicsJoint``, PhysX's D6) names its axes as its
``PhysicsLimitAPI`` instances do. Where one of several free axes is limited, the USD
reader chains them through links of their own, ``body::joint.axis``; Isaac's convention
tells those links by that name. No import beyond the standard library: the confined
USD child uses the axes too.
"""

from __future__ import annotations

D6_AXES = ("transX", "transY", "transZ", "rotX", "rotY", "rotZ")
"""A generic joint's axes, in PhysX's order of its limits."""


def axis_link(child: str, joint: str, axis: str) -> str:
    """The link after ``axis`` of ``joint`` in its chain towards ``child``."""
    return f"{child}::{joint}.{axis}"


def is_axis_link(link: str) -> bool:
    """Whether ``link`` is one `axis_link` made (``body::joint.rotX``)."""
    return "::" in link and link.rsplit(".", 1)[-1] in D6_AXES
