"""What the sampling kernels take: one record, apart from the kernels and their caller.

`_sampling` makes it, the row-wise and the numba kernels read it; here it imports
neither, so no two of them import each other.
"""

import numpy as np

from cspace._record import NamedTuple
from cspace.space._checks import FloatArray

IntArray = np.typing.NDArray[np.int64]


class SamplingPlan(NamedTuple):
    """The sampling kernels' arguments: columns, draws, lower bounds and spans by kind."""

    lines: IntArray
    line_draws: IntArray
    line_low: FloatArray
    line_span: FloatArray
    circles: IntArray
    circle_draws: IntArray
    circle_low: FloatArray
    circle_span: FloatArray
    rotations: IntArray
    rotation_draws: IntArray
