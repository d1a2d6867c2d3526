"""A USD stage's layers, checked and opened with ``Sdf`` before anything composes.

`usd._worker` runs `layer_stack` in its confined child, before OpenUSD composes the
stage (then `usd._count.count_sites` counts what composition would make). Nothing
OpenUSD opens while it composes and reads the stage is left unchecked:

- every sublayer, reference and payload must resolve inside the stage's own allowed
  folders (beneath an entry that is not hidden, after links; a layer in a ``.usdz``
  package is its package's file, a layer named with file format arguments its file),
  at most `MAX_LAYERS` layers, each a regular file; one that the child's Landlock rules
  (fixed when it started, `REACHABLE`) do not cover makes the parent start a child that
  may read it (`NeedsWider`);
- value clips (``clips`` metadata) are refused: OpenUSD opens their files (a list, a
  manifest, or a template that names one file per time step) as it composes, and a
  C-space reads no time-varying value;
- an asset path held in a value (an attribute's default or time samples, a prim's
  metadata) is resolved as the value is read, by cspace and by UsdPhysics's parser
  (which reads many attributes); resolving a path into a ``.usdz`` package
  (``a.usdz[b.png]``) opens the package, which is held to the same rules as a layer.
  Every value is looked at, whatever the type its attribute declares (a crate file may
  hold an asset path where a float is declared); other asset paths are only looked up,
  never opened.

Folder discovery opens one layer alone (`usd._alone.layer_arcs`).
"""

from __future__ import annotations

import mmap
import os
import stat
import string
from typing import Any

MAX_LAYERS = 256
"""Most layers one stage may compose (sublayers, references and payloads counted)."""


_FOLD = str.maketrans(string.ascii_uppercase, string.ascii_lowercase)


def named(path: str, suffixes: tuple[str, ...]) -> bool:
    """Whether ``path`` ends in one of ``suffixes`` (lower case) as OpenUSD reads a name.

    OpenUSD tells a layer's format by its extension folded to lower case in ASCII
    (``TfStringToLowerAscii``, in its file format registry): ``ARM.USDA`` is a text
    layer; a non-ASCII letter is never folded.
    """
    return path.translate(_FOLD).endswith(suffixes)


class StageRefused(Exception):
    """The stage breaks a rule of `usd._worker` (the message says which)."""


def _inside(path: str, allowed: list[str]) -> bool:
    """Whether ``path`` (after links) is beneath an allowed folder, as Landlock reads it.

    Beneath a folder's entries that are no hidden ones (`landlock.readable_entries`):
    ``.git`` beside a stage is outside, whatever folders the serving child may read; so
    is anything in a ``.git``, ``.hg`` or ``.svn`` folder further down (a second
    checkout's ``other/.git/config``, reached through a link).
    """
    from cspace._paths import in_version_control

    real = os.path.realpath(path)
    for folder in allowed:
        top = folder.rstrip("/") + "/"
        if real.startswith(top) and not real[len(top) :].startswith("."):
            return not in_version_control(real, [top.rstrip("/") or "/"])
    return False


class NeedsWider(Exception):
    """A file the request may read is beyond what this child may read (`TooNarrow`)."""


REACHABLE: frozenset[str] | None = None
"""The entries this child's Landlock rules allow (None: no Landlock, nothing to check)."""


def reachable(path: str) -> bool:
    """Whether ``path`` (after links) is an allowed entry or beneath one."""
    if REACHABLE is None:
        return True
    real = os.path.realpath(path)
    while real not in REACHABLE:
        above = os.path.dirname(real)
        if above == real:
            return False
        real = above
    return True


def file_of(identifier: str) -> str:
    """The file OpenUSD opens for a layer's identifier.

    Without file format arguments, and a package's own file for a path into it
    (``a.usdz[b.usda]`` is ``a.usdz``): only a path ending in ``]`` is one into a package
    (OpenUSD's own rule), so ``arm[v2]/a.usda`` is that very file.
    """
    from pxr import Ar, Sdf  # type: ignore[import-untyped]

    path = str(Sdf.Layer.SplitIdentifier(identifier)[0])
    if Ar.IsPackageRelativePath(path):
        return str(Ar.SplitPackageRelativePathOuter(path)[0])
    return path


def layer_key(layer: Any, asset: str) -> str:
    """The identifier of the layer an asset path of ``layer`` names, absolute."""
    from pxr import Ar, Sdf

    resolved = str(layer.ComputeAbsolutePath(asset))
    path, arguments = Sdf.Layer.SplitIdentifier(resolved)
    if Ar.IsPackageRelativePath(path):
        return resolved
    return str(Sdf.Layer.CreateIdentifier(os.path.abspath(path), arguments))


def _check_file(file: str, allowed: list[str], verb: str, shown: str, where: str = "") -> None:
    """Refuse a file the stage would open unless it is a regular file in ``allowed``.

    The message says the stage ``verb`` ``shown`` (the path as written), ``where``.

    Raises:
        StageRefused: Outside the allowed folders, or no regular file.
        NeedsWider: Inside them, but beyond this child's Landlock rules.
    """
    if not _inside(file, allowed):
        raise StageRefused(f"the stage {verb} '{shown}'{where}, outside the allowed folders")
    if os.path.exists(file) and not stat.S_ISREG(os.stat(file).st_mode):
        raise StageRefused(f"the stage {verb} '{file}'{where}, which is no regular file")
    if os.path.exists(file) and not reachable(file):
        raise NeedsWider(file)


def layer_stack(path: str, allowed: list[str]) -> dict[str, Any]:
    """Every layer the stage at ``path`` composes, checked and opened, none composed.

    Each layer's values are checked too (`_check_values`).

    Raises:
        StageRefused: A layer outside the allowed folders, more than `MAX_LAYERS`, value
            clips, or a value naming a package outside the allowed folders.
        NeedsWider: A file inside them that this child may not read.
    """
    from pxr import Sdf

    root = os.path.abspath(path)
    if file_of(root) != root:
        raise StageRefused("OpenUSD reads this file's name as another file's (with ':' or [])")
    seen: dict[str, Any] = {}
    queue = [root]
    while queue:
        current = queue.pop()
        if current in seen:
            continue
        _check_file(file_of(current), allowed, "composes", current)
        if len(seen) >= MAX_LAYERS:
            raise StageRefused(f"the stage composes more than {MAX_LAYERS} layers")
        layer = Sdf.Layer.FindOrOpen(current)
        if layer is None:
            raise StageRefused(f"OpenUSD cannot open '{current}'")
        seen[current] = layer
        if not _plain_text(current):
            _check_values(layer, current, allowed, os.path.dirname(root))
        for asset in layer.GetCompositionAssetDependencies():
            if not asset:  # an internal reference: this very layer
                continue
            if "://" in asset:
                raise StageRefused(f"the stage composes '{asset}', which is no local file")
            if asset.startswith("`"):
                raise StageRefused(
                    f"the stage composes {asset}, an expression cspace does not evaluate yet"
                )
            queue.append(layer_key(layer, asset))
    return seen


_MARKS = (b"clips", b"]@", b"@`")
"""What a text layer's bytes must hold for one of its values to be clips, an asset path
into a package (``@a.usdz[b]@``: the path ends in ``]``, then its closing ``@``), or an
expression (``@`...`@``)."""


def _plain_text(key: str) -> bool:
    """Whether the layer ``key`` is a text file holding none of `_MARKS`.

    Text writes every asset path between ``@`` (or ``@@@``) whatever the value's type,
    so such a layer has nothing for `_check_values` to see; a crate file, or a layer in
    a package, is walked value by value.
    """
    from pxr import Ar, Sdf

    path = str(Sdf.Layer.SplitIdentifier(key)[0])
    if Ar.IsPackageRelativePath(path) or not named(path, (".usda", ".usd")):
        return False
    with open(path, "rb") as stream:
        size = os.fstat(stream.fileno()).st_size
        if size < 1 << 22:  # a small layer read whole, a large one mapped
            return _unmarked(stream.read())
        with mmap.mmap(stream.fileno(), 0, access=mmap.ACCESS_READ) as data:
            return _unmarked(data)


def _unmarked(data: bytes | mmap.mmap) -> bool:
    return data[:5] == b"#usda" and not any(data.find(m) >= 0 for m in _MARKS)


def _check_values(layer: Any, key: str, allowed: list[str], folder: str) -> None:
    """Refuse value clips, and a value's asset path into a package outside ``allowed``.

    ``folder`` is the root layer's, where OpenUSD also looks for a search path
    (``@a.usdz[b]@``), after the current folder.
    """
    from pxr import Sdf

    paths: list[Any] = []
    layer.Traverse(Sdf.Path.absoluteRootPath, paths.append)
    holders = (Sdf.AssetPath, Sdf.AssetPathArray, list, tuple, dict)
    for path in paths:
        values: list[Any]
        if path.IsAbsoluteRootOrPrimPath() or path.IsPrimVariantSelectionPath():
            spec = layer.GetPrimAtPath(path)
            if spec is None:  # a variant set's own path
                continue
            if spec.HasInfo("clips"):
                raise StageRefused(
                    f"<{path}> in '{key}' has value clips, which open files as the stage "
                    "composes and hold only time-varying values (a C-space reads none)"
                )
            values = [_info(spec, name) for name in spec.ListInfoKeys() if name not in _ARCS]
        elif path.IsPrimPropertyPath():
            attribute = layer.GetAttributeAtPath(path)
            if attribute is None:  # a relationship
                continue
            values = [attribute.default]
            if layer.GetNumTimeSamplesForPath(path):
                times = layer.ListTimeSamplesForPath(path)
                values += [layer.QueryTimeSample(path, t) for t in times]
        else:
            continue
        if any(isinstance(v, holders) for v in values):
            for asset in _assets(values):
                where = f"an asset path at <{path}> in '{key}'"
                _check_asset(layer, asset, where, allowed, folder)


_ARCS = frozenset(
    ("references", "payload", "inheritPaths", "specializes", "subLayers", "subLayerOffsets")
)
"""Metadata that holds no value to resolve (the arcs `layer_stack` follows, and theirs)."""


def _info(spec: Any, name: str) -> Any:
    """A spec's metadata ``name``; None for a type Python cannot hold (no asset path)."""
    try:
        return spec.GetInfo(name)
    except Exception:
        return None


def _assets(values: list[Any]) -> list[str]:
    """The asset paths written in ``values`` (in arrays and dictionaries too)."""
    from pxr import Sdf

    found: list[str] = []
    todo = list(values)
    while todo:
        value = todo.pop()
        if isinstance(value, Sdf.AssetPath):
            found.append(value.path)
        elif isinstance(value, (Sdf.AssetPathArray, list, tuple)):
            todo.extend(value)
        elif isinstance(value, dict):
            todo.extend(value.values())
    return [a for a in found if a]


def _check_asset(layer: Any, asset: str, where: str, allowed: list[str], folder: str) -> None:
    """Refuse an asset path whose resolving would open a package outside ``allowed``."""
    from pxr import Ar

    if asset.startswith("`"):
        raise StageRefused(f"{where} is {asset}, an expression cspace does not evaluate yet")
    anchored = str(layer.ComputeAbsolutePath(asset))
    if not Ar.IsPackageRelativePath(anchored):
        return  # resolving only looks the file up
    package = str(Ar.SplitPackageRelativePathOuter(anchored)[0])
    places = [package] if os.path.isabs(package) else [os.path.abspath(package)]
    if not os.path.isabs(package):
        places.append(os.path.join(folder, package))
    for place in places:
        if os.path.exists(place):  # else OpenUSD finds nothing to open
            _check_file(place, allowed, "reads", anchored, f" ({where})")
