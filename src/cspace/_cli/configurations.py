"""What the configuration commands (sample, distance, interpolate) share.

Configurations on the command line are JSON objects ``{joint: value}`` (a number, or a
list for a multi-coordinate joint: planar [x, y, theta], floating
[x, y, z, qw, qx, qy, qz], spherical [qw, qx, qy, qz]), given inline or as ``@FILE``.
Output: canonical configurations with a header naming the coordinates, as JSON or CSV;
numbers in Python's shortest round-trip form, so the same input gives the same bytes.
Batches are computed and written in chunks of `CHUNK_NUMBERS` numbers, so memory
stays bounded whatever ``-n`` or ``--steps`` asks for; the bytes written do not depend
on the chunking.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from typing import IO, TYPE_CHECKING, Any

from cspace._safetext import json_text, printable
from cspace.errors import ArgumentError, ConfigurationError

from .progress import Progress

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from cspace.space import ConfigurationSpace

CHUNK_NUMBERS = 1 << 18
"""Coordinates computed and formatted at a time (2 MiB of float64, a few MiB of text)."""

MAX_CONFIGURATION_BYTES = 1 << 20
"""Largest ``@FILE`` configuration read (1 MiB; a 5000-joint robot's takes 200 kB)."""

FORMATS = ("json", "csv", "jsonl", "npy")
"""Output formats of the configuration commands."""

Chunks = Iterable["NDArray[np.float64]"]
"""Consecutive pieces of a batch: arrays (k, ...) whose rows, in order, are the batch."""


def count(minimum: int) -> Callable[[str], int]:
    """An argparse type: a whole number, ASCII digits only, from ``minimum`` to 2^63 - 1.

    ``int`` alone would take ``1_000``, ``" 5 "`` and non-ASCII digits.
    """

    def parse(text: str) -> int:
        shown = text if len(text) <= 40 else text[:37] + "..."
        if not (text.isascii() and text.isdigit()) or len(text) > 19:
            raise argparse.ArgumentTypeError(
                f"expected a whole number from {minimum} to {sys.maxsize}, got {shown!r}"
            )
        value = int(text)
        if not minimum <= value <= sys.maxsize:
            raise argparse.ArgumentTypeError(
                f"expected a whole number from {minimum} to {sys.maxsize}, got {value}"
            )
        return value

    return parse


def spans(total: int, step: int) -> Iterator[tuple[int, int]]:
    """(start, stop) of consecutive pieces of ``range(total)``, each ``step`` long or less."""
    for start in range(0, total, step):
        yield start, min(total, start + step)


def chunk_rows(space: ConfigurationSpace) -> int:
    """Rows per chunk for this space: `CHUNK_NUMBERS` coordinates, at least one row."""
    return max(1, CHUNK_NUMBERS // max(1, space.size))


def add_robot_arguments(parser: argparse.ArgumentParser, *, stdin: bool = True) -> None:
    """The robot file, and how to load it (as ``inspect`` loads it).

    ``-`` is standard input, unless ``stdin`` is False.
    """
    from cspace._formats.table import titles

    from .robots import add_loading_arguments

    where = ", erd:NAME, or - for standard input" if stdin else " or erd:NAME"
    parser.add_argument("robot", help=f"robot file ({titles()}){where}")
    add_loading_arguments(parser)


def add_format_argument(parser: argparse.ArgumentParser) -> None:
    """``--format json|csv|jsonl|npy`` and ``--output FILE``."""
    parser.add_argument(
        "--format",
        choices=FORMATS,
        default="json",
        help="json: {coordinates: [names], configurations: [[...]]} (default); csv: a "
        "header row of coordinate names, then one row per configuration; jsonl: one JSON "
        "array per configuration (what `cspace convert` reads); npy: NumPy's binary "
        "format, an (N, n) float64 array",
    )
    parser.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        default=None,
        help="write to FILE instead of standard output (- for standard output; needed for "
        "npy on a terminal)",
    )


def load_space(args: argparse.Namespace) -> ConfigurationSpace:
    """The configuration space of ``args.robot``, loaded as ``inspect`` loads it.

    Raises:
        ValueError: An ``--arg`` is not ``NAME:=VALUE``.
    """
    from cspace.space import ConfigurationSpace

    from .robots import load_report

    return ConfigurationSpace.from_report(load_report(args.robot, args))


def parse_pairs(items: Sequence[str], option: str) -> dict[str, str]:
    """``NAME=VALUE`` items as a mapping; one-line errors for anything else."""
    pairs: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise ConfigurationError(f"{option} takes NAME=VALUE, got '{item}'")
        pairs[name] = value
    return pairs


def parse_configuration(
    space: ConfigurationSpace, text: str, label: str, partial: bool
) -> NDArray[np.float64]:
    """A canonical configuration from a JSON object (or ``@FILE``), checked against limits."""
    source = text
    if text.startswith("@"):
        from cspace.files import read_input

        data = read_input(text[1:], max_bytes=MAX_CONFIGURATION_BYTES, what="configuration file")
        try:
            source = data.decode("utf-8")
        except UnicodeDecodeError:
            raise ConfigurationError(f"{label}: {printable(text[1:])} is not UTF-8 text") from None
    try:
        values = json.loads(source)
    except (ValueError, RecursionError) as exc:  # ValueError: JSONDecodeError, huge ints
        reason = "nested too deeply" if isinstance(exc, RecursionError) else exc
        raise ConfigurationError(f"{label} is not valid JSON: {reason}") from None
    if not isinstance(values, dict):
        raise ConfigurationError(f"{label} must be a JSON object {{joint: value}}")
    try:
        x = space.from_dict(values, default=space.neutral() if partial else None)
        space.check(x)
    except ConfigurationError as exc:
        raise ConfigurationError(f"{label}: {exc}") from None
    return x


def write_configurations(
    space: ConfigurationSpace,
    rows: Chunks,
    args: argparse.Namespace,
    count: int,
    header: Mapping[str, Any],
    lists: Mapping[str, Callable[[], Chunks]] | None = None,
) -> None:
    """Write ``count`` configurations, given in chunks (k, n), as ``args.format`` says.

    Each chunk is written as soon as it is computed: memory stays bounded. JSON:
    ``{"robot", **header, **lists, "coordinates", "configurations"}``, the same bytes
    as ``json.dumps`` of the whole document; ``lists`` are flat number arrays written
    chunk by chunk too (each a function giving its chunks). CSV: a header row of names,
    then a row per configuration. JSON Lines: an array per configuration. npy: a
    version 1.0 header for a C-order (count, n) ``<f8`` array, then the rows' bytes.
    Output goes to ``args.output`` or standard output.

    Raises:
        ArgumentError: npy to a terminal, or the output file cannot be written.
    """
    to_terminal = args.output in (None, "-") and sys.stdout.isatty()
    with (
        _opened(args.output, binary=args.format == "npy") as out,
        Progress(
            count,
            "row",
            shown=not to_terminal,  # rows on the terminal show themselves
        ) as progress,
    ):
        rows = progress.counted(rows)
        if args.format == "npy":
            _write_npy(out, rows, (count, space.size))
        elif args.format == "csv":
            out.write(",".join(csv_field(printable(n, limit=None)) for n in space.names) + "\n")
            for chunk in rows:
                out.write("".join(",".join(map(repr, row)) + "\n" for row in chunk.tolist()))
        elif args.format == "jsonl":
            for chunk in rows:
                out.write("".join("[" + ", ".join(map(repr, r)) + "]\n" for r in chunk.tolist()))
        else:
            out.write(json_text({"robot": space.robot, **header})[:-1])
            for key, values in (lists or {}).items():
                out.write(f", {json_text(key)}: ")
                _write_array(out, values(), repr)
            out.write(f', "coordinates": {json_text(list(space.names))}, "configurations": ')
            _write_array(out, rows, lambda row: "[" + ", ".join(map(repr, row)) + "]")
            out.write("}\n")


@contextlib.contextmanager
def _opened(path: str | None, binary: bool) -> Iterator[Any]:
    """The output stream: the file at ``path`` (replaced once written), or standard output."""
    if path is None or path == "-":
        if binary and sys.stdout.isatty():
            raise ArgumentError(_NOT_ON_A_TERMINAL, argument="--output")
        yield sys.stdout.buffer if binary else sys.stdout
        return
    from cspace.files import open_output

    with _terminated_as_exit(), open_output(path, binary) as stream:
        yield stream  # (OutputError: not a file to write over)


@contextlib.contextmanager
def _terminated_as_exit() -> Iterator[None]:
    """SIGTERM (a CI job cancelled or timed out) ends the run as an exception would.

    The output being written is then removed as on any error, not left beside FILE.
    """
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def terminate(signum: int, frame: object) -> None:
        raise SystemExit(128 + signum)

    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


_NOT_ON_A_TERMINAL = "npy is binary: give --output FILE, or redirect standard output"


def _write_npy(out: IO[bytes], chunks: Chunks, shape: tuple[int, int]) -> None:
    """NumPy's .npy format, written as the rows come: the header knows the row count."""
    import numpy as np

    np.lib.format.write_array_header_1_0(
        out, {"descr": "<f8", "fortran_order": False, "shape": shape}
    )
    for chunk in chunks:
        out.write(np.ascontiguousarray(chunk, dtype="<f8").data)


def csv_field(text: str) -> str:
    """``text`` as one CSV field (RFC 4180): quoted when it holds a comma or a quote."""
    return f'"{text.replace(chr(34), chr(34) * 2)}"' if ("," in text or '"' in text) else text


def _write_array(out: IO[str], chunks: Chunks, item: Callable[[Any], str]) -> None:
    """A JSON array of every row of ``chunks``, each formatted by ``item``."""
    out.write("[")
    separator = ""
    for chunk in chunks:
        items = chunk.tolist()
        if items:
            out.write(separator + ", ".join(map(item, items)))
            separator = ", "
    out.write("]")
