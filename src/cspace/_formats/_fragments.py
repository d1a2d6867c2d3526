"""Which XML files of a folder's search are left to the robot files that include them.

A file is a fragment only when a file that is itself inspected includes it, directly or
through fragments: an inspected file (a root) is a robot description that no other
inspected file includes. So a fragment that nothing inspected includes (a
``<mujocoinclude>``, a xacro library, a file only they include) hides nothing: a
``<mujoco>`` file that no root reaches is inspected on its own, and so is each file of a
cycle of includes that no root reaches (its reader says what is wrong with it), as a
folder's USD layers are. ``<mujocoinclude>`` files and xacro libraries are never
inspected on their own (they hold no robot), included or not.

What counts as an include (`_xml_look`): an MJCF ``<include>`` of an MJCF file (root
``<mujoco>`` or ``<mujocoinclude>``, not named ``.urdf``, ``.xacro`` or ``.sdf``), and a
``<xacro:include>``, in a ``.xacro`` file, of a ``.xacro`` file whose root is
``<robot>``: a ``.urdf``, ``.sdf`` or ``.xml`` name is a robot description of its own,
inspected whoever includes it. MuJoCo reads every ``<include>`` from the folder of the
model it compiles, not of the file it stands in: an include is followed from a fragment
only when the fragment lies in its root's folder (elsewhere, where it leads is not
known here, and what it would hide is inspected). ``$(find PKG)/PATH`` is followed as
xacro resolves it: PKG is the including file's own package, the nearest folder above
it with a ``package.xml``, and that ``package.xml`` is one of the files searched;
another package (given with ``--package-path``) is not looked for, and what it names is
inspected on its own. Since xacro resolves ``$(find)`` with the package of the file it
expands, the includes of a file of another package than its includer's are not
followed.

Files are the same when their real paths are (every link followed), as the readers open
them: an include names the real path of the file opened (`_xml_look`), and is an edge to
each file of the search of that real path. MuJoCo's includes of a fragment are followed
from it when its folder and its root's are one real folder; xacro's, when the folder of
the name included is the real folder of the file of the search (a link to a file in
another folder: its includes would be read from the name's folder, not the file's).

All of this is linear in the files and includes: the includes' strongly connected
components (Tarjan's algorithm, with a stack of its own) are decided in topological
order, each once.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from typing import Protocol

from ._xml_look import FRAGMENT_ROOTS, MJCF_ROOTS, ROBOT_SUFFIXES, opened


class Looked(Protocol):
    """What the search read of a file (`_discover._Seen`)."""

    @property
    def root(self) -> str | None: ...
    @property
    def includes(self) -> tuple[str, ...]: ...
    @property
    def tails(self) -> tuple[str, ...]: ...
    @property
    def library(self) -> bool: ...


_Edge = tuple[str, bool]
"""An include's target, and whether the target's own includes are followed from it."""


def left_to_others(seen: Mapping[str, Looked]) -> set[str]:
    """The XML files of ``seen`` not inspected on their own, as normalised paths.

    Args:
        seen: Every file of the search (its package.xml files too), by path.
    """
    nodes: dict[str, Looked] = {}
    for path, looked in seen.items():
        if looked.root == "robot" or looked.root in MJCF_ROOTS:
            nodes.setdefault(os.path.normpath(path), looked)
    files = _Files(nodes)
    packages = _Packages(seen)
    edges = {node: _edges(node, looked, files, packages) for node, looked in nodes.items()}
    reached: dict[str, bool] = {}  # node -> its includes are followed
    left: set[str] = set()
    for component in reversed(_components(list(nodes), edges)):  # topological order
        whole = any(node in reached for node in component)
        for node in component:
            alone = nodes[node].root in FRAGMENT_ROOTS or nodes[node].library
            if whole or alone:
                left.add(node)
            else:  # a root: nothing inspected includes it
                reached[node] = True
        for node in component:
            if reached.get(node, False):
                for target, follows in edges[node]:
                    reached[target] = reached.get(target, False) or follows
    return left


class _Files:
    """The nodes of the search by their real paths, and the real folder of each."""

    def __init__(self, nodes: Mapping[str, Looked]) -> None:
        self.nodes = nodes
        self.folders: dict[str, str] = {}
        self.by_real: dict[str, list[str]] = {}
        for node in nodes:
            real = opened(node, xacro=False)
            for one in real:
                self.by_real.setdefault(one, []).append(node)

    def named(self, real: str) -> list[str]:
        """The nodes whose real path is ``real``."""
        return self.by_real.get(real, [])

    def folder(self, node: str) -> str:
        """The real path of ``node``'s folder, the one its includes were read from."""
        folder = os.path.dirname(node)
        if folder not in self.folders:
            self.folders[folder] = os.path.realpath(folder)
        return self.folders[folder]


def _edges(node: str, looked: Looked, files: _Files, packages: _Packages) -> list[_Edge]:
    """What ``node`` surely includes, among the nodes."""
    nodes = files.nodes
    if looked.root in MJCF_ROOTS:
        folder = files.folder(node)
        return [
            (target, files.folder(target) == folder)  # MuJoCo reads from the root's folder
            for real in looked.includes
            for target in files.named(real)
            if nodes[target].root in MJCF_ROOTS and not target.lower().endswith(ROBOT_SUFFIXES)
        ]
    if not node.endswith(".xacro"):  # not expanded: a URDF that uses xacro is refused
        return []
    home = packages.home(node)
    return [
        # xacro's $(find) knows the root's package, and reads from the folder of the name
        (target, packages.home(target) == home and files.folder(target) == os.path.dirname(real))
        for real in (*looked.includes, *packages.resolve(node, looked.tails))
        for target in files.named(real)
        if target.endswith(".xacro") and nodes[target].root == "robot"
    ]


def _components(order: list[str], edges: Mapping[str, list[_Edge]]) -> list[list[str]]:
    """The strongly connected components, each after every one it leads to (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []
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
                target = targets[at][0]
                at += 1
                if target not in index:
                    work += [(node, at), (target, 0)]
                    break
                if target in on_stack:
                    low[node] = min(low[node], index[target])
            else:
                if low[node] == index[node]:
                    component: list[str] = []
                    while not component or component[-1] != node:
                        component.append(stack.pop())
                        on_stack.discard(component[-1])
                    out.append(component)
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
    return out


class _Packages:
    """The ROS packages of the search: its ``package.xml`` files, by folder."""

    def __init__(self, files: Iterable[str]) -> None:
        normal = map(os.path.normpath, files)
        self.manifests = {
            os.path.dirname(p) for p in normal if os.path.basename(p) == "package.xml"
        }
        self.homes: dict[str, str | None] = {}
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

    def home(self, path: str) -> str | None:
        """The folder of ``path``'s package, or None.

        The nearest folder above it with a ``package.xml`` among the files searched.
        """
        folder = os.path.dirname(path)
        passed = []
        while folder not in self.homes:
            if folder in self.manifests:
                self.homes[folder] = folder
                break
            passed.append(folder)
            parent = os.path.dirname(folder)
            if parent == folder:
                self.homes[folder] = None
                break
            folder = parent
        for one in passed:
            self.homes[one] = self.homes[folder]
        return self.homes[folder]

    def _name(self, home: str) -> str | None:
        """The package's name, read as xacro's reader reads it (None: not one name)."""
        if home not in self.names:
            from cspace._formats.xacrofile import MAX_MANIFEST_BYTES, _package_name
            from cspace._formats.xmlio import ReadBudget
            from cspace.errors import CspaceError

            manifest = os.path.join(home, "package.xml")
            budget = ReadBudget(manifest, max_files=1, max_bytes=MAX_MANIFEST_BYTES)
            try:
                self.names[home] = _package_name(manifest, manifest, budget)
            except CspaceError:
                self.names[home] = None
        return self.names[home]
