"""What changed in the C-space between two reports (public name).

`diff_reports` and its records, from `diff`, where they live.
"""

from cspace._reports.diff import *  # noqa: F403
from cspace._reports.diff import __all__ as __all__
