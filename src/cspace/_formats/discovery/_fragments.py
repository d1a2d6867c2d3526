"""Which XML files of a folder's search are left to the robot files that include them.

A file is a fragment only when a file that is itself inspected reads it, directly or
through fragments, as it reads itself when inspected alone: an inspected file (a root)
is a robot description that no other inspected file includes. So a fragment that
nothing inspected includes (a ``<mujocoinclude>``, a xacro library, a file only they
include) hides nothing: a ``<mujoco>`` file that no root reaches is inspected on its
own, and so is each file of a cycle of includes that no root reaches (its reader says
what is wrong with it), as a folder's USD layers are. ``<mujocoinclude>`` files and
xacro libraries are never inspected on their own (they hold no robot), included or not.

A xacro library (`discovery._look`: a nameless ``<robot>`` that makes nothing at its top
level) is no library when it includes, at its top level, a file of the search that is
a ``<robot>`` and no library (directly or through other libraries): xacro splices that
robot into it, under its own ``<xacro:arg>`` defaults (the first default set wins), so
it is a robot of its own, and inspected.

What counts as an include (`discovery._look`): an MJCF ``<include>`` of an MJCF file (root
``<mujoco>`` or ``<mujocoinclude>``, not named ``.urdf``, ``.xacro`` or ``.sdf``), and a
``<xacro:include>``, in a ``.xacro`` file, of a ``.xacro`` file whose root is
``<robot>``: a ``.urdf``, ``.sdf`` or ``.xml`` name is a robot description of its own,
inspected whoever includes it. An include makes a fragment only when the file's reader
reads the target as the target reads itself alone, so that what it includes in turn is
what the search found; else the target is inspected on its own:

- MuJoCo reads every ``<include>`` from the folder of the model it compiles, not of the
  file it stands in: an include counts when the target lies in its includer's folder
  (so in its root's), or surely names no file of its own (`discovery._look`'s
  ``self_contained``: no include, attached model or ``<flexcomp>``, read whole;
  dm_control's ``common/`` files), as then it reads the same from either folder.
- xacro reads a file only inside the root's package (the nearest folder above the
  root's with a ``package.xml``, as `xacro.expand` finds it on disk, up to
  ``MAX_PACKAGE_SEARCH`` folders up; else the root's folder), not under a hidden entry
  at its top (`xacro._worker`); ``--package-path`` folders are not known here. It skips
  an ``optional`` include it cannot read, and drops one whose content fails to read:
  such an include never counts. A xacro include counts when the target is in the
  includer's package (the same one, or both none and the target in the includer's
  folder or below), readable there, and not a link to a file in another folder (its
  own includes would be read from the link's folder). ``$(find PKG)/PATH`` is followed
  as xacro resolves it: PKG is the including file's own package, whose ``package.xml``
  is one of the files searched; another package (given with ``--package-path``) is not
  looked for, and what it names is inspected on its own.

Files are the same when their real paths are (every link followed), as the readers open
them: an include names the real path of the file opened (`discovery._look`), and is an edge to
each file of the search of that real path.

All of this is linear in the files and includes: the libraries that include a robot are
found by one search backwards from the robots, and the strongly connected components of
the includes that count (Tarjan's algorithm, with a stack of its own) are decided in
topological order, each once: a component is left out when an include from a component
before it reaches it, and its files are roots otherwise.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Hashable, Iterable, Mapping
from typing import Protocol, TypeVar

from cspace._formats.discovery._look import FRAGMENT_ROOTS, MJCF_ROOTS, ROBOT_SUFFIXES, opened


class Looked(Protocol):
    """What the search read of a file (`discovery.search._Seen`)."""

    @property
    def root(self) -> str | None: ...
    @property
    def includes(self) -> tuple[str, ...]: ...
    @property
    def tails(self) -> tuple[str, ...]: ...
    @property
    def library(self) -> bool: ...
    @property
    def self_contained(self) -> bool: ...


def left_to_others(seen: Mapping[str, Looked]) -> set[str]:
    """The XML files of ``seen`` not inspected on their own, as normalised paths.

    Files that read alike (`_Files.key`: one real path, read from one folder, names of
    one kind) are decided together, once, so that a file reached by many links costs
    what one costs.

    Args:
        seen: Every file of the search (its package.xml files too), by path.
    """
    nodes: dict[str, Looked] = {}
    for path, looked in seen.items():
        if looked.root == "robot" or looked.root in MJCF_ROOTS:
            nodes.setdefault(os.path.normpath(path), looked)
    files = _Files(nodes)
    packages = _Packages(seen, files)
    edges: dict[_Key, list[_Key]] = {}
    spliced: dict[str, list[_Key]] = {}  # a real path -> the xacro files that include it
    for key in files.members:
        edges[key] = _edges(key, files, packages, spliced)
    libraries = _libraries(files, spliced)
    reached: set[_Key] = set()
    left: set[_Key] = set()
    for component in reversed(_components(list(files.members), edges)):  # topological
        whole = any(key in reached for key in component)
        read = whole
        for key in component:
            if whole or files.looked(key).root in FRAGMENT_ROOTS or key in libraries:
                left.add(key)
            else:  # a root: nothing inspected reads it
                read = True
        if read:  # a root's reader reads every file of its component
            for key in component:
                reached.update(edges[key])
    return {node for key in left for node in files.members[key]}


def _libraries(files: _Files, spliced: Mapping[str, list[_Key]]) -> set[_Key]:
    """The xacro libraries that include no robot, directly or through other libraries."""
    libraries = {key for key in files.members if files.looked(key).library}
    robots = list(
        dict.fromkeys(
            key[0]
            for key in files.members
            if files.looked(key).root == "robot" and key not in libraries
        )
    )
    done = set(robots)
    while robots:
        for includer in spliced.get(robots.pop(), ()):
            if includer in libraries:
                libraries.discard(includer)
                if includer[0] not in done:
                    done.add(includer[0])
                    robots.append(includer[0])
    return libraries


_Key = tuple[str, str, bool, bool]
"""Files that read alike: a real path, the real folder its includes are read from
(``""`` for an MJCF file that reads the same from any folder), whether its name is a
robot file's (``.urdf``, ``.xacro``, ``.sdf``, in any case), whether it ends in
``.xacro``."""


class _Files:
    """The files of the search, grouped by what they read alike (`_Key`)."""

    def __init__(self, nodes: Mapping[str, Looked]) -> None:
        self.nodes = nodes
        self.folders: dict[str, str] = {}
        self.members: dict[_Key, list[str]] = {}
        self.at: dict[tuple[str, str], list[_Key]] = {}  # (real path, folder) -> keys
        for node, looked in nodes.items():
            real = opened(node, xacro=False)
            folder = self.folder(node)
            if looked.root in MJCF_ROOTS and looked.self_contained:
                folder = ""  # it names no file: MuJoCo reads it alike from any folder
            named = (node.lower().endswith(ROBOT_SUFFIXES), node.endswith(".xacro"))
            key = (real[0] if real else "\0" + node, folder, *named)
            if key not in self.members:
                self.members[key] = []
                if real:
                    self.at.setdefault((real[0], folder), []).append(key)
            self.members[key].append(node)

    def looked(self, key: _Key) -> Looked:
        """What the search read of the files of ``key`` (each read alike)."""
        return self.nodes[self.members[key][0]]

    def keys(self, real: str, folder: str) -> list[_Key]:
        """The files of real path ``real`` whose includes are read from ``folder``."""
        return self.at.get((real, folder), [])

    def folder(self, node: str) -> str:
        """The real path of ``node``'s folder, the one its includes were read from."""
        folder = os.path.dirname(node)
        if folder not in self.folders:
            self.folders[folder] = os.path.realpath(folder)
        return self.folders[folder]


def _edges(
    key: _Key, files: _Files, packages: _Packages, spliced: dict[str, list[_Key]]
) -> list[_Key]:
    """The files that ``key``'s reader surely reads as each reads itself alone.

    ``key`` is added to ``spliced`` for each real path it includes that is a ``<robot>``.
    """
    node, looked = files.members[key][0], files.looked(key)
    if looked.root in MJCF_ROOTS:
        folder = files.folder(node)
        return [
            target  # MuJoCo reads the target's includes from the root's folder
            for real in dict.fromkeys(looked.includes)
            for target in (*files.keys(real, folder), *files.keys(real, ""))
            if files.looked(target).root in MJCF_ROOTS and not target[2]
        ]
    if not key[3]:  # not expanded: a URDF that uses xacro is refused
        return []
    home = packages.home(node)
    region = home if home is not None else files.folder(node)  # what xacro may read
    out: list[_Key] = []
    for real in dict.fromkeys((*looked.includes, *packages.resolve(node, looked.tails))):
        spliced.setdefault(real, []).append(key)
        for target in files.keys(real, os.path.dirname(real)):  # no link elsewhere
            if (
                files.looked(target).root == "robot"
                and target[3]
                and packages.home(files.members[target][0]) == home  # $(find): its own
                and _readable(real, region)
            ):
                out.append(target)
    return out


def _readable(real: str, folder: str) -> bool:
    """Whether xacro may read ``real`` when it may read ``folder`` (`xacro._worker`)."""
    if os.path.commonpath((real, folder)) != folder:
        return False
    relative = os.path.relpath(real, folder)
    return relative == "." or not relative.startswith(".")


_T = TypeVar("_T", bound=Hashable)


def _components(order: list[_T], edges: Mapping[_T, list[_T]]) -> list[list[_T]]:
    """The strongly connected components, each after every one it leads to (Tarjan)."""
    index: dict[_T, int] = {}
    low: dict[_T, int] = {}
    stack: list[_T] = []
    on_stack: set[_T] = set()
    out: list[list[_T]] = []
    for start in order:
        if start in index:
            continue
        work = [(start, 0)]
        while work:
            node, at = work.pop()
            if at == 0:
                index[node] = low[node] = len(index)
                stack.append(node)
                on_stack.add(node)
            targets = edges[node]
            while at < len(targets):
                target = targets[at]
                at += 1
                if target not in index:
                    work += [(node, at), (target, 0)]
                    break
                if target in on_stack:
                    low[node] = min(low[node], index[target])
            else:
                if low[node] == index[node]:
                    component: list[_T] = []
                    while not component or component[-1] != node:
                        component.append(stack.pop())
                        on_stack.discard(component[-1])
                    out.append(component)
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
    return out


class _Packages:
    """The ROS packages xacro finds for the files of the search, as `xacro.expand` does.

    A file's package is the nearest folder above its real folder with a
    ``package.xml`` on disk, up to ``MAX_PACKAGE_SEARCH`` folders up; its name is read
    only from a ``package.xml`` that is one of the files searched.
    """

    def __init__(self, files: Iterable[str], found: _Files) -> None:
        self.found = found
        self.manifests = {
            real
            for p in files
            if os.path.basename(p) == "package.xml"
            for real in opened(p, xacro=False)
        }
        self.homes: dict[str, str | None] = {}  # a real folder -> its package's
        self.has_manifest: dict[str, bool] = {}
        self.names: dict[str, str | None] = {}

    def resolve(self, node: str, finds: tuple[str, ...]) -> list[str]:
        """The real paths ``PKG/PATH`` names for ``node``: its own package's, when PKG is it."""
        if not finds:
            return []
        home = self.home(node)
        name = self._name(home) if home is not None else None
        out = []
        for find in finds:
            package, _, rest = find.partition("/")
            if home is not None and package == name:
                out += opened(os.path.join(home, rest), xacro=True)
        return out

    def home(self, node: str) -> str | None:
        """The real folder of ``node``'s package, or None."""
        folder = self.found.folder(node)
        if folder not in self.homes:
            self.homes[folder] = self._nearest(folder)
        return self.homes[folder]

    def _nearest(self, folder: str) -> str | None:
        from cspace._formats.xacro.expand import MAX_PACKAGE_SEARCH

        here = folder
        for _ in range(MAX_PACKAGE_SEARCH):
            if here not in self.has_manifest:
                self.has_manifest[here] = os.path.isfile(os.path.join(here, "package.xml"))
            if self.has_manifest[here]:
                return here
            if os.path.dirname(here) == here:
                break
            here = os.path.dirname(here)
        return None

    def _name(self, home: str) -> str | None:
        """The package's name, read as xacro's reader reads it (None: not one name).

        None too when its ``package.xml`` is not one of the files searched.
        """
        if home not in self.names:
            from cspace._formats.shared.xmlio import ReadBudget
            from cspace._formats.xacro.expand import MAX_MANIFEST_BYTES, package_name
            from cspace.errors import CspaceError

            manifest = os.path.join(home, "package.xml")
            self.names[home] = None
            if os.path.realpath(manifest) in self.manifests:
                budget = ReadBudget(manifest, max_files=1, max_bytes=MAX_MANIFEST_BYTES)
                with contextlib.suppress(CspaceError):
                    self.names[home] = package_name(manifest, manifest, budget)
        return self.names[home]
