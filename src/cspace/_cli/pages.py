"""``cspace inspect --format html --output-dir DIR``: a folder of pages, one per robot.

Each robot's page (or SVG tree) is ``DIR/NN-NAME.html``: ``NN`` its place in the run
(so two files of one name, and a name no file system takes, never meet) and ``NAME``
the file's name with every character but letters, digits, ``.``, ``_`` and ``-`` made
``_``, at most 80 of them. ``DIR/index.html`` is the run's summary, each robot linked to
its page. Every file is written as ``-o`` files are (`cspace.files.open_output`): never
through a link, never over anything but a regular file, put in place when whole. The
folder is made if missing (its parent must exist); pages an earlier run left are kept,
and only this run's are in the index.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING

from cspace._paths import check_folder_links
from cspace.errors import FileUnreadableError, OutputError
from cspace.files import open_output

if TYPE_CHECKING:
    from cspace._reports.summary import SummaryRow

_UNSAFE = re.compile(r"[^A-Za-z0-9._-]")
_NAME_CHARS = 80


class Pages:
    """The folder the pages of a run go to."""

    def __init__(self, folder: str, suffix: str, count: int) -> None:
        """Make the folder if it is missing.

        Args:
            folder: The folder, as the user named it.
            suffix: ``.html`` or ``.svg``.
            count: How many files the run has (the width of ``NN``).

        Raises:
            OutputError: The folder is something else, cannot be made, or is reached
                through a link out of the folder it stands in.
        """
        self.folder, self.suffix = folder, suffix
        self.digits = len(str(max(count, 1)))
        self.pages: list[str | None] = []
        try:  # its folders on the way that are links must lead inside, before it is made
            check_folder_links(os.path.join(folder, "index.html"))
        except FileUnreadableError as exc:
            raise OutputError(folder, exc.problem) from None
        try:
            os.mkdir(folder)
        except FileExistsError:
            if not os.path.isdir(folder):
                raise OutputError(folder, "is not a folder") from None
        except OSError as exc:
            raise OutputError(folder, f"cannot make the folder: {exc.strerror or exc}") from None

    def write(self, path: str, page: str | None) -> None:
        """Write the next file's page (None: it has none, as a file without a report)."""
        if page is None:
            self.pages.append(None)
            return
        stem = _UNSAFE.sub("_", os.path.basename(path))[:_NAME_CHARS] or "robot"
        name = f"{len(self.pages) + 1:0{self.digits}d}-{stem}{self.suffix}"
        with open_output(os.path.join(self.folder, name), binary=False) as out:
            out.write(page)
        self.pages.append(name)

    def index(self, rows: Sequence[SummaryRow]) -> str:
        """Write ``index.html`` (the summary, each robot linked); return its path."""
        from cspace._render.html import render_index_html

        path = os.path.join(self.folder, "index.html")
        with open_output(path, binary=False) as out:
            out.write(render_index_html(rows, self.pages))
        return path
