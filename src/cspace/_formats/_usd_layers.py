"""A USD stage's layers, checked, opened and counted with ``Sdf`` before anything composes.

`usd_worker` runs these in its confined child, before OpenUSD composes the stage:

1. `layer_stack` walks every sublayer, reference and payload: each must resolve inside
   the stage's own allowed folders (beneath an entry that is not hidden, after links),
   at most `MAX_LAYERS` layers, each a regular file; one that the child's Landlock rules
   (fixed when it started, `REACHABLE`) do not cover makes the parent start a child
   that may read it (`NeedsWider`);
2. `count_sites` counts what composition would make, and refuses past `MAX_SITES`.

OpenUSD composes a prim from every site that contributes to it: each layer of a layer
stack with a spec there, and what each of those specs' references, payloads, inherits
and specializes bring, with their namespace children. Nothing bounds that: 30 layers
each referencing the next twice make 2^30 sites, and one layer whose prims reference
their neighbours twice does the same (OpenUSD took 10 s and 1.2 GiB on 30 such layers
before the prim count could be read). So the sites are counted first, from the layers
`layer_stack` has opened, in milliseconds:

- a site is a layer stack (a layer and its sublayers) and a prim path; it counts one for
  each layer of the stack with a spec at the path, plus what each spec's arcs bring, plus
  its namespace children (their names taken from every layer of the stack); a subtree
  with no arc in any layer of the stack counts its specs, and is walked no further;
- a site reached by two paths counts twice (a reference of the same layer from two prims
  too), as OpenUSD composes it twice;
- every variant's arcs and children count (OpenUSD composes the selected ones only);
- an arc back to a site being counted is a cycle, which OpenUSD drops: it counts nothing.

The walk is iterative, and a site's count is kept once it needs no site above it (an
acyclic structure is walked once, however often it is reached); it stops as soon as the
count passes the bound, or after `MAX_STEPS` steps.

`layer_arcs` (folder discovery) opens one layer alone and lists the files it names.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from typing import Any

MAX_LAYERS = 256
"""Most layers one stage may compose (sublayers, references and payloads counted)."""


class StageRefused(Exception):
    """The stage breaks a rule of `usd_worker` (the message says which)."""


def _inside(path: str, allowed: list[str]) -> bool:
    """Whether ``path`` (after links) is beneath an allowed folder, as Landlock reads it.

    Beneath a folder's entries that are no hidden ones (`landlock.readable_entries`):
    ``.git`` beside a stage is outside, whatever folders the serving child may read.
    """
    real = os.path.realpath(path)
    for folder in allowed:
        top = folder.rstrip("/") + "/"
        if real.startswith(top) and not real[len(top) :].startswith("."):
            return True
    return False


class NeedsWider(Exception):
    """A file the request may read is beyond what this child may read (`TooNarrow`)."""


REACHABLE: frozenset[str] | None = None
"""The entries this child's Landlock rules allow (None: no Landlock, nothing to check)."""


def _reachable(path: str) -> bool:
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


def layer_key(layer: Any, asset: str) -> str:
    """The file an asset path of ``layer`` names (``archive.usdz[inner]`` inside a zip)."""
    resolved = str(layer.ComputeAbsolutePath(asset))
    return resolved if "[" in resolved else os.path.abspath(resolved)


def layer_stack(path: str, allowed: list[str]) -> dict[str, Any]:
    """Every layer the stage at ``path`` composes, checked and opened, none composed.

    Raises:
        StageRefused: A layer outside the allowed folders, or more than `MAX_LAYERS`.
        NeedsWider: A layer inside them that this child may not read.
    """
    from pxr import Sdf  # type: ignore[import-untyped]

    seen: dict[str, Any] = {}
    queue = [os.path.abspath(path)]
    while queue:
        current = queue.pop()
        if current in seen:
            continue
        file = current.split("[", 1)[0]  # a layer inside a .usdz: the archive is the file
        if not _inside(file, allowed):
            raise StageRefused(f"the stage composes '{current}', outside the allowed folders")
        if len(seen) >= MAX_LAYERS:
            raise StageRefused(f"the stage composes more than {MAX_LAYERS} layers")
        if os.path.exists(file) and not stat.S_ISREG(os.stat(file).st_mode):
            raise StageRefused(f"the stage composes '{file}', which is no regular file")
        if os.path.exists(file) and not _reachable(file):
            raise NeedsWider(file)
        layer = Sdf.Layer.FindOrOpen(current)
        if layer is None:
            raise StageRefused(f"OpenUSD cannot open '{current}'")
        seen[current] = layer
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


MAX_ARC_LAYERS = 10_000
"""Most layers whose arcs one request lists (a folder's walk is bounded below that)."""


def layer_arcs(path: str) -> list[str]:
    """The files a layer composes directly (sublayers, references, payloads), absolute.

    The layer alone is opened (no stage is composed); a layer OpenUSD cannot open
    composes nothing.
    """
    from pxr import Sdf

    if os.path.isfile(path) and not _reachable(path):
        raise NeedsWider(path)
    try:
        layer = Sdf.Layer.FindOrOpen(path)
        assets = list(layer.GetCompositionAssetDependencies()) if layer else []
    except Exception:
        return []
    return [layer.ComputeAbsolutePath(a) for a in assets if a and "://" not in a]


MAX_SITES = 200_000
"""Most sites a stage's composition may make (twice `usd_worker.MAX_PRIMS`: a converter
writes each prim in two or three layers)."""

MAX_STEPS = 1_000_000
"""Most steps of the count (sites entered, arcs and children followed)."""

_Site = tuple[str, str]  # (the layer stack's root layer, a prim path)


class TooMuchComposition(Exception):
    """The stage's composition is beyond `MAX_SITES` or `MAX_STEPS` (the message says)."""


class _Layer:
    """One layer's prims, variant selections stripped: specs, children, arcs.

    ``own``: the specs at each prim path (a variant's counts too); ``below``: at it and
    beneath it; ``hot``: the paths with arcs, and those above them (a cold subtree counts
    its specs, walked no further).
    """

    __slots__ = ("arcs", "below", "children", "hot", "own")

    def __init__(self, layer: Any) -> None:
        from pxr import Sdf

        paths: list[Any] = []
        layer.Traverse(Sdf.Path.absoluteRootPath, paths.append)
        self.own: dict[str, int] = {}
        self.children: dict[str, dict[str, None]] = {}
        self.arcs: dict[str, list[tuple[str | None, str | None]]] = {}
        for path in paths:
            if not (path.IsPrimPath() or path.IsPrimVariantSelectionPath()):
                continue
            spec = layer.GetPrimAtPath(path)
            if spec is None:  # a variant set's own path
                continue
            text = str(path)
            key = str(path.StripAllVariantSelections()) if "{" in text else text
            self.own[key] = self.own.get(key, 0) + 1
            if path.IsPrimPath():
                self.children.setdefault(_parent(key), {})[key] = None
            if (
                spec.hasReferences
                or spec.hasPayloads
                or spec.hasInheritPaths
                or spec.hasSpecializes
            ):
                self.arcs[key] = _arcs(spec)
        self.below = dict(self.own)
        for key in sorted(self.own, key=lambda k: k.count("/"), reverse=True):
            if key != "/":
                parent = _parent(key)
                self.below[parent] = self.below.get(parent, 0) + self.below[key]
        self.hot: set[str] = set()
        for key in self.arcs:
            while key not in self.hot:
                self.hot.add(key)
                if key == "/":
                    break
                key = _parent(key)


def _parent(key: str) -> str:
    return key.rsplit("/", 1)[0] or "/"


def _arcs(spec: Any) -> list[tuple[str | None, str | None]]:
    """A prim spec's references, payloads, inherits and specializes: (asset, prim path)."""
    arcs: list[tuple[str | None, str | None]] = []
    for listed in (spec.referenceList, spec.payloadList):
        for item in listed.GetAddedOrExplicitItems():
            target = str(item.primPath.StripAllVariantSelections()) if item.primPath else None
            arcs.append((item.assetPath or None, target))
    for listed in (spec.inheritPathList, spec.specializesList):
        for path in listed.GetAddedOrExplicitItems():
            arcs.append((None, str(path.StripAllVariantSelections())))
    return arcs


class _Stage:
    """The opened layers, indexed as the count needs them."""

    def __init__(self, layers: dict[str, Any], resolve: Callable[[Any, str], str]) -> None:
        self.layers = layers
        self.resolve = resolve
        self.indexes: dict[str, _Layer] = {}
        self.stacks: dict[str, list[str]] = {}

    def index(self, key: str) -> _Layer:
        if key not in self.indexes:
            self.indexes[key] = _Layer(self.layers[key])
        return self.indexes[key]

    def stack(self, key: str) -> list[str]:
        """The layer stack rooted at ``key``: it and its sublayers, depth first, once each."""
        if key not in self.stacks:
            order: list[str] = []
            todo = [key]
            while todo:
                current = todo.pop()
                if current in order or current not in self.layers:
                    continue
                order.append(current)
                layer = self.layers[current]
                todo += reversed([self.resolve(layer, s) for s in layer.subLayerPaths if s])
            self.stacks[key] = order
        return self.stacks[key]

    def default(self, key: str) -> str | None:
        name = self.layers[key].defaultPrim if key in self.layers else ""
        return f"/{name}" if name else None

    def expand(self, site: _Site) -> tuple[int, int, list[_Site]]:
        """A site's count but for the sites below it, the work done, and those sites.

        The count is its own specs and its cold children's subtrees; the sites below
        are its children with arcs at or beneath them, then its arcs' targets.
        """
        stack, path = site
        indexed = [(key, self.index(key)) for key in self.stack(stack)]
        count, work = 0, 0
        hot: dict[str, None] = {}
        targets: list[_Site] = []
        for key, layer in indexed:
            count += layer.own.get(path, 0)
            for child in layer.children.get(path, ()):
                work += 1
                if any(child in other.hot for _, other in indexed):
                    hot[child] = None
                else:
                    count += layer.below[child]
            for asset, target in layer.arcs.get(path, ()):
                if asset is None:  # internal: the same layer stack
                    where: str | None = stack
                    target = target or self.default(stack)
                else:
                    where = self.resolve(self.layers[key], asset)
                    target = target or self.default(where)
                if target is not None and where in self.layers:
                    targets.append((where, target))
        return count, work, [(stack, child) for child in hot] + targets


def count_sites(root: str, layers: dict[str, Any], resolve: Callable[[Any, str], str]) -> int:
    """The sites the stage rooted at layer ``root`` composes (see the module docstring).

    Args:
        root: The root layer's key in ``layers``.
        layers: Every layer the stage composes, opened, by key.
        resolve: The key of an asset path written in a layer.

    Raises:
        TooMuchComposition: Past `MAX_SITES` sites or `MAX_STEPS` steps.
    """
    stage = _Stage(layers, resolve)
    kept: dict[_Site, int] = {}
    depth: dict[_Site, int] = {}  # the sites being counted, by depth
    own, steps, below = stage.expand((root, "/"))
    frames: list[list[Any]] = [[(root, "/"), iter(below), own, 0]]  # site, next, total, low
    depth[(root, "/")] = 0
    while True:
        frame = frames[-1]
        site = next(frame[1], None)
        if site is None:  # done: its count goes to the site above
            frames.pop()
            del depth[frame[0]]
            if frame[3] >= len(frames):  # no arc back above it: its count holds anywhere
                kept[frame[0]] = frame[2]
            if not frames:
                return int(frame[2])
            frames[-1][2] += frame[2]
            frames[-1][3] = min(frames[-1][3], frame[3])
            _check(frames[-1][2], steps)
            continue
        steps += 1
        if site in kept:
            frame[2] += kept[site]
        elif site in depth:  # a cycle: OpenUSD drops the arc
            frame[3] = min(frame[3], depth[site])
        else:
            own, work, below = stage.expand(site)
            steps += work
            depth[site] = len(frames)
            frames.append([site, iter(below), own, len(frames)])
            frame = frames[-1]
        _check(frame[2], steps)


def _check(total: int, steps: int) -> None:
    """Stop as soon as a site's count passes the bound (the stage's is at least as large)."""
    if total > MAX_SITES:
        raise TooMuchComposition(
            f"the stage's composition makes more than {MAX_SITES:,} prim sites (each layer "
            "and prim counted as often as references, payloads and sublayers reach it): "
            "refused before composing"
        )
    if steps > MAX_STEPS:
        raise TooMuchComposition(
            f"the stage's composition takes more than {MAX_STEPS:,} steps to count: refused "
            "before composing"
        )
