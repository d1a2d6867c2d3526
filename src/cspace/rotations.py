"""Rotations: quaternions, matrices and their exact conversions (public name).

The functions and types of :mod:`cspace.space.rotations`, where they live.
"""

from cspace.space.rotations import *  # noqa: F403
from cspace.space.rotations import __all__ as __all__
