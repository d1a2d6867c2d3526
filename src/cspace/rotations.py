"""Rotations: quaternions, matrices and their exact conversions (public name).

The functions and types of `_rotations`, where they live.
"""

from cspace.space._geometry.rotations import *  # noqa: F403
from cspace.space._geometry.rotations import __all__ as __all__
