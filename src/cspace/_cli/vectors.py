"""Files of vectors for ``convert`` and ``unwrap``: CSV with a header, or JSON Lines.

CSV: a header row naming each column, then one row of numbers per vector. The header is
checked against the convention's names (``base.qx`` is not ``base.qw``): a file in
another convention than the one given is refused, not misread. For values named by
joint (``named``), the header *is* the list of joints, in any order.

JSON Lines: one vector per line, a JSON array of numbers; for ``named``, a JSON object
shaped like a ROS ``sensor_msgs/JointState``: ``{"name": [...], "position": [...]}``
(``"velocity"`` with ``--velocity``), each line in any order of names.

Lines are read one at a time, at most `MAX_LINE_BYTES` each, and vectors are
converted and written in chunks of `CHUNK_ROWS`: memory stays bounded whatever the
file's length. Errors name the file and the line.
"""

from __future__ import annotations

import csv
import json
import math
import sys
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import IO, TYPE_CHECKING, Any

from cspace import CspaceError

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

MAX_LINE_BYTES = 1 << 20
"""Longest line read (1 MiB: a vector of 40,000 numbers)."""

CHUNK_ROWS = 4096
"""Most vectors converted and written at a time."""

CHUNK_NUMBERS = 1 << 16
"""Most numbers read into one chunk (the rows of a wide robot are fewer: a 5,000-joint
robot's 4,096 rows held 2.3 GB as lists, arrays and text)."""

csv.field_size_limit(MAX_LINE_BYTES)  # a field may take a whole line (the default is 128 KiB)


class VectorFileError(CspaceError):
    """A vector file cannot be read: the file, the line and the problem."""

    code = "bad-vector-file"

    def __init__(self, path: str, line: int | None, problem: str, code: str | None = None) -> None:
        self.path, self.line, self.problem = path, line, problem
        if code is not None:  # the library's own code for what went wrong there
            self.code = code
        where = f"{path}:{line}" if line is not None else path
        super().__init__(f"{where}: {problem}")


@dataclass
class Chunk:
    """Consecutive vectors read from a file.

    Attributes:
        lines: The file line of each vector.
        rows: The vectors, (k, width).
        names: For JointState-like JSON Lines, the rows' names (one order per chunk).
    """

    lines: list[int]
    rows: NDArray[np.float64]
    names: tuple[str, ...] | None = None

    def line(self, row: int | None) -> int:
        """The file line of a row (of the first when None)."""
        return self.lines[row if row is not None and 0 <= row < len(self.lines) else 0]


NameCheck = Callable[[Sequence[str]], None]
"""Refuses names the robot cannot take (raises a CspaceError)."""


def _lines(stream: IO[bytes], path: str) -> Iterator[tuple[int, str]]:
    number = 0
    while True:
        raw = stream.readline(MAX_LINE_BYTES + 1)
        if not raw:
            return
        number += 1
        if len(raw) > MAX_LINE_BYTES:
            raise VectorFileError(path, number, f"line is longer than {MAX_LINE_BYTES:,} bytes")
        if number == 1 and raw.startswith(b"\xef\xbb\xbf"):  # a UTF-8 byte-order mark
            raw = raw[3:]
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise VectorFileError(path, number, "is not UTF-8 text") from None
        if text.strip():
            yield number, text


def _csv_fields(path: str, line: int, text: str) -> list[str]:
    try:
        return next(csv.reader([text.rstrip("\r\n")], strict=True))
    except (csv.Error, StopIteration) as exc:
        raise VectorFileError(path, line, f"is not a CSV row: {exc}") from None


def _numbers(path: str, line: int, fields: Sequence[object], width: int) -> list[float]:
    if len(fields) != width:
        raise VectorFileError(path, line, f"has {len(fields)} values, the header {width}")
    out: list[float] = []
    for k, value in enumerate(fields):
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            raise VectorFileError(path, line, f"value {k + 1} is not a number: {value!r}")
        try:
            number = float(value)
        except (ValueError, OverflowError):
            raise VectorFileError(path, line, f"value {k + 1} is not a number: {value!r}") from None
        if not math.isfinite(number):
            raise VectorFileError(path, line, f"value {k + 1} is not finite: {value!r}")
        out.append(number)
    return out


MAX_VECTOR_FILE_BYTES = 4 * 1024**3
"""Largest vector file read (4 GiB: 30 million rows of a 7-joint arm's numbers); standard
input is read to its end."""


def open_input(name: str) -> tuple[IO[bytes], str]:
    """The byte stream of a vector file, ``-`` standard input.

    The file is opened as every input is (`cspace.files.open_input`): a regular
    file, no link out of its folder, at most `MAX_VECTOR_FILE_BYTES`.

    Raises:
        FileUnreadableError: The file cannot be opened, is a link out of its folder, or
            is not a regular file (a FIFO or a device could block or never end).
    """
    if name == "-":
        return sys.stdin.buffer, "-"
    from cspace.files import open_input as open_untrusted

    return open_untrusted(name, max_bytes=MAX_VECTOR_FILE_BYTES, what="vector file"), name


class VectorReader:
    """Vectors from a CSV or JSON Lines stream, in chunks.

    Attributes:
        path: The file, for messages.
        kind: ``csv`` or ``jsonl`` (from the first line).
        header: The CSV header, or None for JSON Lines.
    """

    def __init__(self, stream: IO[bytes], path: str) -> None:
        self.path = path
        self._lines = _lines(stream, path)
        first = next(self._lines, None)
        if first is None:
            raise VectorFileError(path, None, "is empty")
        self._first: tuple[int, str] | None = first
        stripped = first[1].lstrip()
        self.kind = "jsonl" if stripped[:1] in ("[", "{") else "csv"
        self.header: list[str] | None = None
        if self.kind == "csv":
            self.header = _csv_fields(path, first[0], first[1])
            self._first = None

    def chunks(
        self, width: int | None, field: str = "position", names: NameCheck | None = None
    ) -> Iterator[Chunk]:
        """The vectors, ``width`` numbers each (None: the header's width).

        JSON Lines objects ``{"name": [...], field: [...]}`` (a ROS JointState) are read
        only when ``names`` is given: it checks each line's names before its values are
        kept, and a chunk holds rows of one set of names (a line naming them in another
        order is put in the chunk's order). A chunk holds at most `CHUNK_ROWS` rows
        and `CHUNK_NUMBERS` numbers (at least one row).
        """
        import numpy as np

        width = len(self.header) if width is None and self.header is not None else width
        rows: list[list[float]] = []
        lines: list[int] = []
        order: tuple[str, ...] | None = None

        def source() -> Iterator[tuple[int, str]]:
            if self._first is not None:
                yield self._first
            yield from self._lines

        for line, text in source():
            row_names: tuple[str, ...] | None = None
            if self.kind == "csv":
                fields: Sequence[object] = _csv_fields(self.path, line, text)
            else:
                row_names, fields = self._json(line, text, field, names)
            count = len(row_names) if row_names is not None else width
            if count is None:
                raise VectorFileError(self.path, line, "gives no names (use --input-names)")
            numbers = _numbers(self.path, line, fields, count)
            if rows and row_names and order and row_names != order and _same(row_names, order):
                numbers, row_names = _reordered(numbers, row_names, order), order
            full = len(rows) >= min(CHUNK_ROWS, max(1, CHUNK_NUMBERS // max(1, count)))
            if rows and (row_names != order or full):
                yield Chunk(lines, np.array(rows), order)
                rows, lines = [], []
            if not rows:
                order = row_names
            rows.append(numbers)
            lines.append(line)
        if rows:
            yield Chunk(lines, np.array(rows), order)

    def _json(
        self, line: int, text: str, field: str, check: NameCheck | None
    ) -> tuple[tuple[str, ...] | None, Sequence[object]]:
        try:
            value = json.loads(text)
        except (ValueError, RecursionError):
            raise VectorFileError(self.path, line, "is not valid JSON") from None
        if isinstance(value, list):
            return None, value
        if not isinstance(value, dict):
            raise VectorFileError(self.path, line, "is neither a JSON array nor an object")
        if check is None:
            raise VectorFileError(
                self.path,
                line,
                "is an object of names and values (a JointState): read it as named values",
                "bad-vector-file",
            )
        names, values = value.get("name"), value.get(field)
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise VectorFileError(self.path, line, '"name" is not a list of joint names')
        if not isinstance(values, list):
            raise VectorFileError(self.path, line, f'"{field}" is not a list of numbers')
        if len(values) != len(names):
            raise VectorFileError(
                self.path, line, f'"{field}" has {len(values)} values for {len(names)} names'
            )
        try:
            check(names)
        except CspaceError as exc:
            raise VectorFileError(self.path, line, str(exc), exc.code) from None
        return tuple(names), values


def _same(names: tuple[str, ...], order: tuple[str, ...]) -> bool:
    """The same names (each once: they were checked), in any order."""
    return len(names) == len(order) and set(names) == set(order)


def _reordered(numbers: list[float], names: tuple[str, ...], order: tuple[str, ...]) -> list[float]:
    """``numbers`` given for ``names``, put in ``order`` (the same names)."""
    value = dict(zip(names, numbers, strict=True))
    return [value[name] for name in order]


class VectorWriter:
    """Vectors to standard output as CSV (a header, then rows) or JSON Lines.

    Numbers are written in Python's shortest round-trip form, so the same input gives
    the same bytes.
    """

    def __init__(self, kind: str, names: Sequence[str], field: str | None = None) -> None:
        """``field``: write JSON Lines objects ``{"name": names, field: values}``."""
        from cspace._safetext import json_text, printable

        from .configurations import csv_field

        self.kind, self.names, self.field = kind, list(names), field
        self._names_json = json_text(self.names, indent=None).rstrip("\n") if field else ""
        if kind == "csv":
            sys.stdout.write(",".join(csv_field(printable(n, limit=None)) for n in names) + "\n")

    def write(self, rows: NDArray[np.float64]) -> None:
        """Write (k, width) vectors."""
        out = sys.stdout
        if self.kind == "csv":
            out.write("".join(",".join(map(repr, row)) + "\n" for row in rows.tolist()))
        elif self.field is not None:
            head = f'{{"name": {self._names_json}, "{self.field}": ['
            out.write("".join(head + ", ".join(map(repr, row)) + "]}\n" for row in rows.tolist()))
        else:
            out.write("".join("[" + ", ".join(map(repr, row)) + "]\n" for row in rows.tolist()))


def check_header(path: str, header: Sequence[str], expected: Sequence[str], what: str) -> None:
    """Refuse a CSV header that is not ``expected`` (a file in another convention).

    Raises:
        VectorFileError: The names differ; the message names the first difference.
    """
    if list(header) == list(expected):
        return
    for k, (given, wanted) in enumerate(zip(header, expected, strict=False)):
        if given != wanted:
            raise VectorFileError(
                path,
                1,
                f"column {k + 1} is '{given}', but {what} has '{wanted}' there: is the file "
                "in another convention?",
            )
    raise VectorFileError(
        path, 1, f"the header has {len(header)} columns, {what} has {len(expected)}"
    )


def split_names(names: str | None) -> list[str] | None:
    """``A,B,...`` as a list (empty items dropped), or None."""
    return None if names is None else [n for n in names.split(",") if n]


def checked_names(path: str, check: Any, names: list[str], what: str) -> None:
    """``check(names)``, its error naming ``what`` (before any row is read or written)."""
    from cspace import CspaceError

    try:
        check(names)
    except CspaceError as exc:
        raise VectorFileError(path, None, f"{what}: {exc}", exc.code) from None


def named_targets(path: str, space: Any, conventions: Any, names: str | None) -> list[str]:
    """``--names`` (checked), or every one-coordinate joint in tree order."""
    one = [j for j, cols in space.layout.joint_columns.items() if cols.stop - cols.start == 1]
    chosen = split_names(names) or one
    checked_names(path, conventions.check_names, chosen, "--names")
    return chosen
