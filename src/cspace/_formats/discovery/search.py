"""Robot descriptions found by what they are, among the files of a folder.

A folder given to ``cspace inspect`` stands for the robot files in it: files named
``.urdf``, ``.xacro`` or ``.sdf`` (in any case), and any file whose root element is
``<robot>``, ``<mujoco>`` or ``<sdf>`` (past a prolog of any length, up to the size cap;
a longer one is inspected, and refused: `discovery._look`, `discovery.prolog`), or in which only
tinyxml2 or rapidxml (the parsers of MuJoCo, urdfdom and Pinocchio's MJCF reader) finds
such a root (`discovery._tiny`, `discovery._rapid`: inspected, and refused). A fragment is left to
the robot file that includes it, and is only one when the reader of a file that is
itself inspected reads it, directly or through fragments, as it reads itself alone
(`discovery._fragments`): an MJCF file that an inspected model includes (``<include
file=...>``), a ``.xacro`` file that an inspected ``.xacro`` file includes at its top
level (``<xacro:include filename=...>``, relative, or ``$(find PKG)/PATH`` of its own
package) where xacro's sandbox may read it; a ``<mujocoinclude>`` file and a xacro
macro library (a ``.xacro`` file, a ``<robot>`` without a name that makes nothing at
its top level: no ``<link>``, no macro call, no ``<xacro:attribute>``, no include of a
robot) are never inspected on their own. A ``<mujoco>`` file that only fragments
nothing inspected include is inspected, and so is each file of a cycle no inspected
file's reader reads. Comments are not read for any of this. Every scan is a single
pass over the bytes read (no backtracking pattern over the whole file), and only each
file's root element and the names it includes are kept.

An SRDF (MoveIt's semantic description, a ``<robot>`` too) is no robot of its own: one
whose content is surely an SRDF's (`srdf.bytes_scan`: SRDF elements, and no ``<link>``,
``<joint>`` or xacro call outside them; a name ``.srdf`` or ``.srdf.xacro`` decides only
a ``<robot>`` that holds neither) is left out of the robots (``Found.srdf``), read with
its URDF when asked (``--srdf``), and what it includes makes no file a fragment. Its
name alone never leaves a file out: a ``.srdf`` file that holds a link is a robot, and
one the scan cannot be sure of (a xacro call, an entity) is inspected, its reader
telling an SRDF (`srdf.kind`).

A file of a format told by its bytes (`table.told_by_bytes`: USD) is a robot description too,
unless a root layer of the walk composes it, directly or through others (a converter's
payload layers): a root layer is one no other USD file of the walk composes, and what
each composes (sublayers, references, payloads) is OpenUSD's answer, read in a confined
child (the ``arcs`` of `robot_files`). A layer that is a robot on its own is named by
none there (`usd.layer_arcs`), so it is read whoever composes it. A layer in a cycle
that no root reaches is read, and an XML file's includes never make a USD file a
fragment.
"""

import os
from collections.abc import Callable, Sequence

from cspace._formats.discovery._fragments import left_to_others
from cspace._formats.discovery._look import (
    FRAGMENT_ROOTS,
    PEEK_BYTES,
    ROBOT_SUFFIXES,
    UNDECIDED,
    XML_ROOTS,
    look_xml,
    root_tag,
)
from cspace._record import NamedTuple

__all__ = ["FRAGMENT_ROOTS", "PEEK_BYTES", "ROBOT_SUFFIXES", "Found", "robot_files", "root_tag"]


def _content() -> tuple[str, ...]:
    """The formats told by their bytes (`table.FORMATS`), as `_Seen.root` names them."""
    from cspace._formats.table import FORMATS

    return tuple(row.name for row in FORMATS if row.magic)


class _Seen(NamedTuple):
    root: str | None
    includes: tuple[str, ...]  # paths, normalised
    tails: tuple[str, ...]  # PKG/PATH of $(find PKG)/PATH
    library: bool
    self_contained: bool = False  # MJCF read the same from any folder (`XmlLook`)
    srdf: bool = False  # surely an SRDF by its content (`XmlLook`)
    name: str | None = None  # a <robot>'s name, as written


def _look(path: str) -> _Seen:
    """What `robot_files` needs of one file: its first `PEEK_BYTES`, and on (`look_xml`)."""
    from cspace.errors import FileUnreadableError
    from cspace.files import open_input

    try:
        with open_input(path, max_bytes=None, what="robot file") as stream:
            head = stream.read(PEEK_BYTES)
            from cspace._formats.table import told_by_bytes

            content = told_by_bytes(path, head)
            if content is not None:  # a USD layer: what it composes is asked of OpenUSD
                return _Seen(content.name, (), (), False)
            return _Seen(*look_xml(path, stream, head))
    except (FileUnreadableError, OSError):
        return _Seen(None, (), (), False)


def _composed(seen: dict[str, _Seen]) -> set[str]:
    """The USD layers that a root layer of the walk composes, directly or through others.

    A root is a USD file no other one composes. A layer in a cycle that no root reaches
    is no fragment: it is read, and its reader says what is wrong with it.
    """
    usd = {os.path.normpath(p): s.includes for p, s in seen.items() if s.root in _content()}
    targets = {t for includes in usd.values() for t in includes}
    reached: set[str] = set()
    stack = [p for p in usd if p not in targets]
    while stack:
        for target in usd.get(stack.pop(), ()):
            if target in usd and target not in reached:  # a USD layer, never a URDF
                reached.add(target)
                stack.append(target)
    return reached


class Found(NamedTuple):
    """The robot descriptions of a walk, and the fragments left to what includes them.

    ``by_content`` names the format of each robot told by its bytes (USD), whose reader
    needs an extra. ``srdf`` holds the SRDF files, read with their robot (``--srdf``),
    never on their own, and ``names`` the ``<robot name>`` of each SRDF and robot file
    that gives one, as written.
    """

    robots: list[str]
    fragments: list[str]
    by_content: dict[str, str]
    srdf: list[str]
    names: dict[str, str]


def robot_files(
    paths: Sequence[str], arcs: Callable[[list[str]], dict[str, list[str]]] | None = None
) -> Found:
    """The robot descriptions among ``paths`` (files of one walk), in their order.

    Args:
        paths: Files, as a folder's walk names them.
        arcs: What reads the layers each USD layer composes (`usd.layer_arcs`, OpenUSD
            in a confined child), or None: no USD layer is then known as a fragment.
    """
    seen = {path: _look(path) for path in paths}
    formats = _content()
    layers = [p for p, s in seen.items() if s.root in formats]
    if arcs is not None and len(layers) > 1:  # one layer alone is a fragment of none
        spelt = {os.path.abspath(p): os.path.normpath(p) for p in paths}  # as the walk spells it
        for path, targets in arcs(layers).items():
            named = {spelt.get(os.path.abspath(t), os.path.normpath(t)) for t in targets}
            named.discard(os.path.normpath(path))
            seen[path] = seen[path]._replace(includes=tuple(sorted(named)))
    composed = _composed(seen)
    srdf = [path for path, s in seen.items() if s.srdf]
    # XML files left to the files that include them; an SRDF is read by no robot's reader
    left = left_to_others({p: s for p, s in seen.items() if p not in set(srdf)})
    robots: list[str] = []
    fragments: list[str] = []
    content = {path: s.root for path, s in seen.items() if s.root in formats and s.root}
    told = (*XML_ROOTS, *FRAGMENT_ROOTS, *formats, UNDECIDED)  # roots that say a robot file
    for path, s in seen.items():
        if path in srdf or not (path.lower().endswith(ROBOT_SUFFIXES) or s.root in told):
            continue
        if os.path.normpath(path) in composed or os.path.normpath(path) in left:
            fragments.append(path)
        else:
            robots.append(path)
    by_content = {p: f for p, f in content.items() if p in robots}
    names = {p: s.name for p, s in seen.items() if s.name is not None}
    return Found(robots, fragments, by_content, srdf, names)
