"""MuJoCo's compile, from this process: the child that compiles, its cache, its refusals.

`start_compile` reads every file the model needs, bounded and once (`_prescan`), and
hands MuJoCo the documents the pre-scan read, as lxml serialises them (MuJoCo's XML
parser would read some bytes otherwise: `_models`), in a confined child process kept
for the next model (`_worker`, `_compile`); `Compiling.finish` waits for its answer.
The same bytes compile to the same model, so answers are kept by the digest of what
MuJoCo was given. A refusal becomes one line (`_refused`), its line mapped back to the
file's.
"""

import base64
import os
import re
import threading
from collections.abc import Sequence
from typing import Any

from lxml import etree

from cspace._confine.kept import KeptChild
from cspace._confine.sandbox import ChildLimits, ChildRefused
from cspace._formats.mjcf._models import mujoco_document, original_line
from cspace._formats.mjcf._prescan import PreScan, prescan
from cspace._formats.shared.xmlio import MAX_FILE_BYTES, ReadBudget, SourceFile
from cspace._record import NamedTuple
from cspace.errors import MujocoError

MJCF_LIMITS = ChildLimits(
    cpu_seconds=5, wall_seconds=6.0, memory_bytes=512 * 2**20, output_bytes=MAX_FILE_BYTES
)
"""The bounds of MuJoCo's compile. The child maps 187 MiB once MuJoCo is imported; every
model of dm_control and Gymnasium compiles within 250 MiB; 512 MiB keeps the child's
resident memory under the 600 MiB a robot file may cost. A 1,000-deep chain (the
deepest the pre-scan allows) compiles in 1.2 s of CPU, 1.5-2.5 s on a busy 2-core machine."""

# MUJOCO_GL=disable: MuJoCo skips loading an OpenGL library (40 ms) it would not use.
COMPILER = KeptChild(
    "cspace._formats.mjcf._worker", MJCF_LIMITS, "MuJoCo", env={"MUJOCO_GL": "disable"}
)
"""This process's MuJoCo child: it compiles one model a request, confined (`_worker`)."""


CACHE_SIZE = 16
"""Compiled models kept in memory, by the digest of everything MuJoCo was given: the same
bytes compile to the same model, so ``inspect`` then ``pinocchio_model`` (or ``load``) of
one file compiles it once."""

_compiled: dict[str, bytes] = {}
_compiled_lock = threading.Lock()


class MainDocument(NamedTuple):
    """The main file, as read and as MuJoCo was given it (for the lines of its messages).

    Attributes:
        root: Its parsed root element.
        data: Its bytes.
        text: The document MuJoCo was given
            (`mujoco_document`).
    """

    root: etree._Element
    data: bytes
    text: str


class Compiling:
    """A model for MuJoCo to compile in its child process (started); `finish` compiles it."""

    def __init__(
        self,
        path: str,
        scan: PreScan,
        request: dict[str, Any] | None,
        key: str,
        answer: bytes = b"",
        main: MainDocument | None = None,
    ) -> None:
        self.path = path
        self.scan = scan
        self.main = main
        self.request = request
        self.key = key
        self.answer = answer

    def finish(self) -> bytes:
        """The facts of the model MuJoCo compiled, as its child wrote them (JSON).

        Raises:
            MujocoError: MuJoCo refused the model (its own reason, with the line where
                it gives one), or the compile hit a limit.
        """
        answer = self.answer
        if self.request is not None:
            try:
                answer = COMPILER.ask(self.request)
            except ChildRefused as exc:
                raise _refused(self.path, str(exc), self.scan, self.main) from None
            with _compiled_lock:
                while len(_compiled) >= CACHE_SIZE:
                    _compiled.pop(next(iter(_compiled)))
                _compiled[self.key] = answer
        return answer


def start_compile(
    path: str,
    source: SourceFile,
    root: etree._Element,
    file: str | None,
    *,
    budget: ReadBudget,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
) -> Compiling:
    """Read what the model needs and start MuJoCo compiling it.

    Args:
        path: The file, for messages.
        source: The main file's bytes.
        root: Its parsed ``<mujoco>`` element.
        file: The main file on disk, or None (standard input).
        budget: The run's budget, already charged with the main file.
        allow_dirs: Folders, besides the file's own, that includes may come from.

    Raises:
        RobotFileError: An include or model cannot be read, or the model expands past
            the limits (see `prescan`).
    """
    scan = prescan(path, root, file, budget=budget, allow_dirs=allow_dirs, data=source.data)
    main = mujoco_document(root)  # what the pre-scan read, not the bytes: see _models
    request = {
        "main": main,
        "includes": {k: base64.b64encode(v).decode("ascii") for k, v in scan.includes.items()},
        "placeholders": sorted(scan.placeholders),
    }
    import hashlib

    digest = hashlib.sha256(main.encode("utf-8"))  # what MuJoCo is given
    for name, data in sorted(scan.includes.items()):
        digest.update(b"\0%d:%s\0" % (len(name), name.encode("utf-8", "surrogateescape")))
        digest.update(hashlib.sha256(data).digest())
    digest.update("\0".join(sorted(scan.placeholders)).encode("utf-8", "surrogateescape"))
    key = digest.hexdigest()
    with _compiled_lock:
        cached = _compiled.get(key)
    if cached is not None:
        return Compiling(path, scan, None, key, cached)
    COMPILER.start()  # MuJoCo loads in the child while this process works on
    return Compiling(path, scan, request, key, main=MainDocument(root, source.data, main))


_LINE = re.compile(r",? ?\bline\s*[=:]?\s*(\d+)")
_LINE_0 = re.compile(r",? ?\bline\s*[=:]?\s*0+\b")
_ELEMENT = re.compile(r"Element name '([^']+)'")
_AT = re.compile(r"Element (name )?'([^']*)'(?:, id -?\d+)?, line (\d+)")


def _refused(path: str, text: str, scan: PreScan, main: MainDocument | None) -> MujocoError:
    """MuJoCo's message as one line, with the file and line where it or the pre-scan knows.

    MuJoCo names an element (by tag or name) and its line in the document it was given;
    of a nested message (a model file MuJoCo could not parse), the last is the main
    document's, and only the last is read. That line is mapped back to the file's, when
    the main document has such an element there. An element of an included file is at
    line 0; then its name, when it has one, finds its file and line. A file given to
    MuJoCo under another name (two files of one base name) is called by its own.
    """
    for given, name in scan.given.items():
        text = text.replace(given, name)
    lines = [" ".join(part.split()) for part in text.splitlines()]
    message = "; ".join(part for part in lines if part)
    line = None
    # (where the line number stands, by name or by tag, the name or tag, the line)
    spots: list[tuple[int, int, bool, str | None, str]] = [
        (m.start(3), m.end(3), bool(m.group(1)), m.group(2), m.group(3))
        for m in _AT.finditer(message)
    ]
    if not spots and (bare := _LINE.search(message)) is not None:
        spots = [(bare.start(1), bare.end(1), False, None, bare.group(1))]
    # MuJoCo's own location is the last: an earlier one may be text of the file's (a
    # class name quoted in the message), and mapping each took a parse of the document
    for start, end, by_name, named_as, said in spots[-1:]:
        at = None if main is None else original_line(*main, int(said), by_name, named_as)
        if at is not None:
            line = at
            message = f"{message[:start]}{at}{message[end:]}"
    message = _LINE_0.sub("", message)  # "line 0": no line
    named = _ELEMENT.search(message)
    if line is None and named and named.group(1) in scan.where:
        file, at = scan.where[named.group(1)]
        if file is None:
            line = at
        else:
            message += f" (in {file}, line {at})"
    return MujocoError(path, f"MuJoCo refuses the model: {message}", line=line)
