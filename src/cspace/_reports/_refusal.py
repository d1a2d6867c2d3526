"""How the checks of a saved report past its schema refuse it: one message, one pointer.

`_consistency` and each part's check (`_closure_check`, `_limits_check`,
`_ros2_control_check`) refuse through `invalid`; a section only some formats' reports
have is held to them by `only_in`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, NoReturn

from cspace._reports._strict_json import describe
from cspace.errors import ReportFileError


def invalid(path: str, problem: str, where: str) -> NoReturn:
    """Refuse the report: ``problem``, at the JSON Pointer ``where``.

    Raises:
        ReportFileError: Always.
    """
    raise ReportFileError(path, f"not a valid cspace report: {problem}", pointer=where)


def only_in(
    path: str, document: Mapping[str, Any], formats: tuple[str, ...], what: str, where: str
) -> None:
    """Refuse a report of another format than ``formats`` that has ``what`` at ``where``.

    Raises:
        ReportFileError: The report's format is not one of ``formats``.
    """
    found = document["source"]["format"]
    if found not in formats:
        invalid(path, f"a {describe(found)} report with {what}", where)
