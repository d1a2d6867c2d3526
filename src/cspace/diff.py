"""What changed in the C-space between two reports (public name).

:func:`diff_reports` and its records, from :mod:`cspace.reports.diff`, where they live.
"""

from cspace.reports.diff import *  # noqa: F403
from cspace.reports.diff import __all__ as __all__
