"""What a folder, or a list of file names, stands for: the robot descriptions in it.

The files are told by `cspace._formats.discovery.search.robot_files` (by name and content; a
fragment left to the inspected file that includes it); a file that is a link is taken
as when it is named (`_discovered`), and one that leads out of its folder is never
read: it stands for a robot when its name says so, or when what it leads to lies in the
tree searched and is a robot description (`_into_tree`). What is left out is said on
standard error: the fragments, the USD files when OpenUSD is not installed, the other
links out of their folder, the links to folders the search does not enter.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import cspace

from .patterns import Searched, expand_pattern

if TYPE_CHECKING:
    from cspace._formats.discovery.search import Found


def in_folder(folder: str) -> tuple[list[str], list[str]]:
    """The robot descriptions in a folder and its subfolders, and the files left out.

    Left out, and said on standard error: the fragments, left to what includes them
    (see `robot_files`), and the SRDF files, read with their robot (`note_srdf`; one
    whose robot no robot file found is, is named in a note of its own: `_note_unpaired`).
    The walk is a pattern's (`expand_pattern`): no linked folder, no hidden one,
    bounded; a file that is a link is taken as when it is named (`_discovered`).

    Raises:
        FileUnreadableError: The walk names too many files or folders.
    """
    import glob

    linked: list[str] = []
    files = expand_pattern(os.path.join(glob.escape(folder), "**", "*"), linked)
    if linked:
        from . import output

        more = f", ... ({len(linked)} in all)" if len(linked) > 10 else ""
        output.note(
            "links to folders, not searched (name the folder they lead to): "
            f"{', '.join(linked[:10])}{more}"
        )
    robots, left, found = _discovered(files, [folder], _trees([folder]))
    _note_unpaired(found, robots)
    return robots, left


def robots_among(names: list[str], searched: Sequence[str] = ()) -> list[str]:
    """The robot descriptions among files named, as in a folder (`robot_files`).

    Names that are no file (``-``, ``erd:NAME``, a missing file) are kept for their errors,
    and those a folder's search found (`Searched`) as they are: that search told them.
    The robot descriptions told here come back `Searched` too: a search told them, as one
    it was not sure of (a xacro ``.srdf.xacro``), whose reader may find an SRDF.
    The tree the other names stand in, for their links out of their folder
    (`_into_tree`), is the current folder, the folders of the names and the folders
    ``searched`` (those named beside them).
    """
    files = [
        n for n in names if not isinstance(n, Searched) and (os.path.isfile(n) or os.path.islink(n))
    ]
    folders = sorted({os.path.dirname(n) or "." for n in files})
    robots, _, _ = _discovered(files, folders, _trees([os.curdir, *folders, *searched]))
    kept, looked = set(robots), set(files)
    return [Searched(n) if n in kept else n for n in names if n in kept or n not in looked]


def _discovered(
    files: list[str], allowed: list[str], trees: list[str]
) -> tuple[list[str], list[str], Found]:
    """The robot descriptions among ``files`` (in order), the files left out, the search.

    A file that is a link is read as the file it leads to when that lies in the link's
    folder (as `cspace.files.open_input` reads a file named); one that leads out of its
    folder is never read: it is a robot (inspecting it then refuses it, ``outside-tree``)
    when its name says so (``.urdf``, ``.xacro``, ``.sdf``, a USD name) or when it leads
    to a robot description in ``trees`` (real folders: `_into_tree`), and is named in a
    note on standard error otherwise. The fragments and the SRDF files, left out, are
    said in notes too.
    """
    from cspace._formats.discovery.search import robot_files

    out = [f for f in files if os.path.islink(f) and _leads_out(f)]
    unread = set(out)
    found = robot_files([f for f in files if f not in unread], _usd_arcs(allowed))
    note_fragments(found.fragments)
    note_srdf(found.srdf)
    robots = set(_readable(found.robots, found.by_content)) | _links_out(out, trees)
    return [f for f in files if f in robots], [*found.fragments, *found.srdf], found


def _links_out(links: list[str], trees: list[str]) -> set[str]:
    """The links out of their folder that stand for robots; the others said in a note.

    A link stands for a robot when it is named like a robot file, or when it leads to a
    robot description in ``trees`` (`_into_tree`).
    """
    if not links:
        return set()
    from cspace._formats.table import FORMATS

    from . import output

    suffixes = tuple(s for row in FORMATS for s in row.suffixes)  # names that say a robot
    named = {f for f in links if f.lower().endswith(suffixes)}
    named |= _into_tree([f for f in links if f not in named], trees)
    said = [f for f in links if f not in named]
    if said:
        more = f", ... ({len(said)} in all)" if len(said) > 10 else ""
        output.note(
            "links that lead out of their folder, not read (name the file they lead to, if "
            f"it is a robot file): {', '.join(said[:10])}{more}"
        )
    return named


def _into_tree(links: list[str], trees: list[str]) -> set[str]:
    """The links out of their folder that lead to a robot description in ``trees``.

    A link's target, followed to its real path, is looked at only when it lies in one
    of ``trees`` (real folders: the folder searched, or the folders of a list of names)
    and in no version-control folder below it (``.git``, ``.hg``, ``.svn``); it is then
    looked at as the search looks at a file (`robot_files`, on its own: no other file's
    includes make it a fragment), so a robot committed out of the search's sight (a
    hidden file, ``arm.xml -> ../.store/arm.xml``) is not passed over. A target outside
    them is never opened.
    """
    from cspace._formats.discovery.search import robot_files
    from cspace._paths import in_version_control, real_path, within
    from cspace.errors import FileUnreadableError

    targets: dict[str, list[str]] = {}
    for link in links:
        try:
            real = real_path(link)
        except FileUnreadableError:  # a chain too long to follow: never read
            continue
        if within(real, trees) and not in_version_control(real, trees):
            targets.setdefault(real, []).append(link)
    return {link for real, named in targets.items() if robot_files([real]).robots for link in named}


def _trees(folders: list[str]) -> list[str]:
    """The real paths of ``folders``, but those whose chain of links is too long."""
    from cspace._paths import real_path

    trees: list[str] = []
    for folder in folders:
        try:
            trees.append(real_path(folder))
        except cspace.errors.FileUnreadableError:
            continue
    return trees


def _leads_out(link: str) -> bool:
    """Whether a link leads out of its folder (or cannot be followed): it is not read."""
    from cspace._paths import check_links

    try:
        check_links(link)
    except (cspace.errors.FileUnreadableError, OSError):
        return True
    return False


def _usd_arcs(allowed: list[str]) -> Callable[[list[str]], dict[str, list[str]]]:
    """What lists the files each USD layer composes, saying which it could not.

    OpenUSD, in confined children that read only the ``allowed`` folders.
    """

    def arcs(files: list[str]) -> dict[str, list[str]]:
        from cspace._formats.usd.reader import layer_arcs

        from . import output

        found, failed = layer_arcs(files, allowed)
        if failed:  # each is then read as a robot, and its reading says what is wrong
            more = f", ... ({len(failed)} in all)" if len(failed) > 10 else ""
            output.note(
                "OpenUSD could not list what these USD layers compose (beyond its bounds), "
                f"so each is read as a robot: {', '.join(failed[:10])}{more}"
            )
        return found

    return arcs


def _readable(robots: list[str], by_content: dict[str, str]) -> list[str]:
    """The robots found, less those whose format's library is not installed (said once).

    A folder or a pull request's files may hold USD scenes next to URDF robots; without
    the ``usd`` extra (a format's ``extra`` in `table.FORMATS`) they are left out, and
    standard error says so and how to add it.
    """
    import importlib.util

    from cspace._formats.table import FORMATS

    from . import output

    for row in FORMATS:
        files = [r for r in robots if by_content.get(r) == row.name]
        if not files or not row.library or importlib.util.find_spec(row.library) is not None:
            continue
        more = f", ... ({len(files)} in all)" if len(files) > 10 else ""
        output.note(
            f"{row.name.upper()} files left out, as {row.title} is not installed "
            f"(pip install 'cspace[{row.extra}]'): {', '.join(files[:10])}{more}"
        )
        robots = [r for r in robots if r not in set(files)]
    return robots


def note_fragments(fragments: list[str]) -> None:
    """Say on standard error which fragments were left to what includes them."""
    from . import output

    if fragments:
        more = f", ... ({len(fragments)} in all)" if len(fragments) > 10 else ""
        output.note(f"left to the files that include them: {', '.join(fragments[:10])}{more}")


def note_srdf(srdf: list[str]) -> None:
    """Say on standard error which SRDF files were left out: each is read with its URDF."""
    from . import output

    if srdf:
        more = f", ... ({len(srdf)} in all)" if len(srdf) > 10 else ""
        output.note(
            "SRDF files, read with their robot's URDF (--srdf auto, or --srdf FILE), not "
            f"on their own: {', '.join(srdf[:10])}{more}"
        )


def _note_unpaired(found: Found, robots: list[str]) -> None:
    """Name the SRDF files of a folder whose robot no robot file found there is.

    An SRDF goes with a robot file of the folder when that robot has the SRDF's ``<robot
    name>``, or the robot file's name (less ``.urdf``, ``.xacro``, ...) is the SRDF's
    (less ``.srdf``) or begins with it (``icub.srdf``, ``icub_reduced.urdf``): as
    ``--srdf auto`` may pair them (`cspace._model.semantics.find_srdf`). The others may
    belong to a robot elsewhere (a URDF that xacro makes at build time): a note, never an
    error.
    """
    from cspace._formats.shared.roots import file_stem

    from . import output

    names = {found.names[r] for r in robots if r in found.names}
    stems = [file_stem(r) for r in robots]
    alone = []
    for srdf in found.srdf:
        name, stem = found.names.get(srdf), file_stem(srdf)
        if name in names or any(s.startswith(stem) for s in stems):
            continue
        alone.append(f"{srdf} (robot '{name}')" if name is not None else srdf)
    if alone:
        more = f", ... ({len(alone)} in all)" if len(alone) > 10 else ""
        output.note(
            "SRDF files whose robot no robot file here is (by <robot name>, or by a file "
            f"named after the SRDF): {', '.join(alone[:10])}{more}"
        )
