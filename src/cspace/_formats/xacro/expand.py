"""Expanding xacro files to URDF, through the ``xacrodoc`` package (no ROS needed).

xacro is a program, not a format: ``${...}`` is evaluated by Python's ``eval``, and
``xacro:include``, ``load_yaml`` and ``$(find ...)`` read files. So a file is expanded
only when the user asks for it (a ``.xacro`` name, or ``force_xacro``/``--xacro``), and
then in a confined child process (`xacro._sandbox`): it may read only the
files of the xacro file's own package (the nearest folder above it with a
``package.xml``; else its folder) and of the ``package_paths`` folders; it sees no
environment variable; it cannot write, start a program or reach the network; CPU time,
memory, output size and the files it includes are capped (`XacroLimits`).

``$(find PKG)`` is resolved from the file's own package and from the folders given with
``package_paths`` (each searched for ``package.xml`` files); relative ``xacro:include``
file names are relative to the file that includes them; ``args`` set ``<xacro:arg>``
values (``name:=value`` on the command line).
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from cspace._formats.shared.xmlio import (
    ReadBudget,
    SourceFile,
    parse_xml,
    read_source,
    source_from_bytes,
)
from cspace._formats.xacro._sandbox import XacroLimits, XacroRefused, run_xacro
from cspace._paths import check_granted_folder, real_path
from cspace.errors import ArgumentError, XacroError

MAX_PACKAGE_SEARCH = 64
"""Most folders walked up from a xacro file looking for its ``package.xml``."""


@dataclass(frozen=True)
class XacroOptions:
    """How to expand xacro files.

    Attributes:
        package_paths: Folders searched for ROS packages (``package.xml``), in order;
            xacro may read files inside them.
        args: xacro argument values by name.
        limits: CPU, wall-clock, memory, output and include bounds of one expansion.
        require_confinement: Refuse to expand when the kernel cannot confine the
            expanding process (Linux Landlock, kernel 5.13 and later, and a seccomp
            filter, on x86-64 or AArch64). With False, expansion still runs in a child
            process with the limits, an empty environment and a Python audit hook, which
            a hostile file can get around: it could then read what the user can read.
    """

    package_paths: tuple[str, ...] = ()
    args: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))
    limits: XacroLimits = field(default_factory=XacroLimits)
    require_confinement: bool = True

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickle with a plain dict for ``args`` (a mapping proxy cannot be pickled)."""
        return (
            _options,
            (self.package_paths, dict(self.args), self.limits, self.require_confinement),
        )

    @classmethod
    def from_cli(
        cls, package_paths: Sequence[str], args: Sequence[str], *, require_confinement: bool = True
    ) -> XacroOptions:
        """Options from ``--package-path DIR`` and ``--arg NAME:=VALUE`` strings.

        Raises:
            ArgumentError: An argument is not ``NAME:=VALUE`` (a ``ValueError`` too).
        """
        parsed: dict[str, str] = {}
        for arg in args:
            name, sep, value = arg.partition(":=")
            if not sep or not name.strip():
                raise ArgumentError(f"xacro argument '{arg}' is not NAME:=VALUE", argument="args")
            parsed[name.strip()] = value
        return cls(
            tuple(package_paths), MappingProxyType(parsed), require_confinement=require_confinement
        )


def _options(
    package_paths: tuple[str, ...], args: dict[str, str], limits: XacroLimits, confined: bool
) -> XacroOptions:
    """`XacroOptions` rebuilt from its pickled parts."""
    return XacroOptions(package_paths, MappingProxyType(args), limits, confined)


def expand_xacro(source: SourceFile, options: XacroOptions, file: str | None) -> SourceFile:
    """Expand a xacro document to URDF, in a confined child process.

    Args:
        source: The xacro file's bytes (the child is given these; it never reads the
            main file again).
        options: Package folders, argument values and limits.
        file: The file on disk the bytes came from (relative includes and the
            ``package.xml`` search start from its folder), or None for the current folder.

    Returns:
        The URDF document, under the same path.

    Raises:
        XacroError: xacro failed (unknown package, missing include, bad expression, a
            limit reached, something the sandbox refuses).
    """
    start = os.path.abspath(file) if file is not None else os.path.join(os.getcwd(), "-")
    packages, home, folders = ros_packages(source.path, start, options.package_paths)
    try:
        text = run_xacro(
            source.text,
            file=start,
            folders=[home, *folders],
            packages=packages,
            args=options.args,
            limits=options.limits,
            require_confinement=options.require_confinement,
        )
    except XacroRefused as exc:
        said = str(exc)
        missing = re.search(r"Package not found: (\S+)", said)
        if missing:
            said = (
                f"$(find {missing.group(1)}): no such package (give a folder that holds it "
                "with --package-path, or put its package.xml above the file)"
            )
        if said.startswith("the kernel cannot confine xacro"):
            said += "; --xacro-unconfined expands with the other limits only"
        raise XacroError(source.path, f"xacro cannot expand the file: {said}") from None
    return source_from_bytes(source.path, text.encode("utf-8"))


def ros_packages(
    path: str, start: str, package_paths: Sequence[str]
) -> tuple[dict[str, str], str, list[str]]:
    """The ROS packages a file at ``start`` may name, as ``$(find PKG)`` finds them.

    Its own package (the nearest ``package.xml`` above it) and those under the
    ``package_paths`` folders, the first folder's first; meshes' ``package://`` names
    are resolved from the same (`shared.mesh_paths`).

    Args:
        path: The file as the user named it, for messages.
        start: The file on disk, absolute (its folder is where the search starts).
        package_paths: The ``--package-path`` folders.

    Returns:
        Each package's name and real folder, the file's home (its package's folder, or
        its own folder), and the package paths, real.

    Raises:
        XacroError: A package path that is no folder, more folders than
            `MAX_PACKAGE_FOLDERS`, or a ``package.xml`` that names no single package.
        FileUnreadableError: A package path reached through a link out of its folder, a
            ``package.xml`` too large, or too many of them.
    """
    folders: list[str] = []
    for folder in package_paths:
        if not os.path.isdir(folder):
            raise XacroError(path, f"package path '{folder}' is not a folder")
        check_granted_folder(folder)  # a committed `pp -> ~` is no package path
        folders.append(real_path(folder))
    manifests = ReadBudget(path, max_bytes=MAX_MANIFEST_BYTES_IN_ALL, max_files=MAX_PACKAGE_FOLDERS)
    own = _own_package(path, os.path.dirname(start), manifests)
    home = own[1] if own else os.path.realpath(os.path.dirname(start))
    packages: dict[str, str] = {}
    for folder in reversed(folders):  # the first folder that holds a package wins
        packages.update(_packages_in(path, folder, manifests))
    if own:
        packages[own[0]] = own[1]
    return packages, home, folders


MAX_PACKAGE_FOLDERS = 10_000
"""Most folders walked under the package paths looking for packages."""

MAX_MANIFEST_BYTES = 256 * 1024
"""Largest ``package.xml`` read (real ones are a few KiB)."""

MAX_MANIFEST_BYTES_IN_ALL = 16 * 1024 * 1024
"""Most bytes of ``package.xml`` files read for one robot (with 250,000 tags at most):
200 identical 1 MB manifests, tiny in git, took 25 s to parse before."""


def _packages_in(path: str, top: str, manifests: ReadBudget) -> dict[str, str]:
    """The ROS packages under ``top``: name -> folder (as ``rospkg`` finds them).

    Walked here, before xacro runs: the confined process may not list the package
    paths themselves. Links are not followed, hidden folders are skipped, and a folder
    with a ``package.xml`` is a package whose subfolders are not searched.

    Raises:
        XacroError: More than `MAX_PACKAGE_FOLDERS` folders, or a ``package.xml``
            that names no single package.
        FileUnreadableError: A ``package.xml`` larger than `MAX_MANIFEST_BYTES`,
            or past the ``manifests`` budget (``too-much-input``).
    """
    found: dict[str, str] = {}
    stack = [top]  # depth first, in name order, as os.walk: but no recursion (Python
    walked = 0  # 3.11's os.walk recurses once per folder level, and a tree can nest deep)
    while stack:
        folder = stack.pop()
        walked += 1
        if walked > MAX_PACKAGE_FOLDERS:
            raise XacroError(
                path, f"package path '{top}' has more than {MAX_PACKAGE_FOLDERS:,} folders"
            )
        subfolders, files = _entries(folder)
        if "package.xml" in files:
            name = package_name(path, os.path.join(folder, "package.xml"), manifests)
            found.setdefault(name, folder)
            continue
        stack.extend(os.path.join(folder, d) for d in reversed(subfolders))
    return found


def _entries(folder: str) -> tuple[list[str], set[str]]:
    """A folder's subfolders to search (sorted, not hidden, not links) and its other names.

    As `os.walk` without ``followlinks`` sees them; a folder that cannot be listed
    has none.
    """
    subfolders: list[str] = []
    files: set[str] = set()
    try:
        with os.scandir(folder) as entries:
            for entry in entries:
                try:
                    is_folder = entry.is_dir()
                except OSError:
                    is_folder = False
                if not is_folder:
                    files.add(entry.name)
                elif not entry.name.startswith(".") and not entry.is_symlink():
                    subfolders.append(entry.name)
    except OSError:
        return [], set()
    return sorted(subfolders), files


def package_name(path: str, manifest: str, budget: ReadBudget) -> str:
    source = read_source(manifest, max_bytes=MAX_MANIFEST_BYTES, budget=budget, what="package.xml")
    names = [n.text for n in parse_xml(source).iter("name")]
    if len(names) != 1 or not (names[0] or "").strip():
        raise XacroError(path, f"'{manifest}' names no single package")
    return str(names[0]).strip()


def _own_package(path: str, folder: str, manifests: ReadBudget) -> tuple[str, str] | None:
    """The package holding ``folder``: (name, real folder) of the nearest ``package.xml``.

    Raises:
        XacroError: That ``package.xml`` has no single ``<name>``.
    """
    here = os.path.realpath(folder)
    for _ in range(MAX_PACKAGE_SEARCH):
        manifest = os.path.join(here, "package.xml")
        if os.path.isfile(manifest):
            return package_name(path, manifest, manifests), here
        if os.path.dirname(here) == here:
            break
        here = os.path.dirname(here)
    return None
