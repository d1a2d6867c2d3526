"""What a USD stage's composition would make, counted with ``Sdf`` before it composes.

`usd._worker` runs `count_sites` in its confined child on the layers `usd._layers`
has opened and checked, and refuses past `MAX_SITES`.

OpenUSD composes a prim from every site that contributes to it: each layer of a layer
stack with a spec there, and what each of those specs' references, payloads, inherits
and specializes bring, with their namespace children. Nothing bounds that: 30 layers
each referencing the next twice make 2^30 sites, and one layer whose prims reference
their neighbours twice does the same (OpenUSD took 10 s and 1.2 GiB on 30 such layers
before the prim count could be read). So the sites are counted first, in milliseconds:

- a layer stack is a layer and, in order, the stacks of its sublayers, as Pcp builds
  it: a sublayer named twice (or reached by two ways) is there twice, each time with
  its own sublayers (22 layers each naming the next twice make 4 million entries, which
  took OpenUSD over a minute); a sublayer already on the way down from the stack's root
  is a cycle, left out. A stack of more than `MAX_STACK` entries is refused;
- a site is a layer stack and a prim path; it counts one for each entry of the stack
  with a spec at the path, plus what each spec's arcs bring (once for each layer: Pcp
  merges the same arc listed again), plus its namespace children (their names taken from
  every layer of the stack); a subtree with no arc in any layer of the stack counts its
  specs, and is walked no further;
- a site reached by two paths counts twice (a reference of the same layer from two prims
  too), as OpenUSD composes it twice;
- every variant's arcs and children count (OpenUSD composes the selected ones only);
- an arc back to a site being counted is a cycle, which OpenUSD drops: it counts nothing.

The walk is iterative, and a site's count is kept once it needs no site above it (an
acyclic structure is walked once, however often it is reached); it stops as soon as the
count passes the bound, or after `MAX_STEPS` steps.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

MAX_SITES = 200_000
"""Most sites a stage's composition may make (twice `usd._worker.MAX_PRIMS`: a converter
writes each prim in two or three layers)."""

MAX_STACK = 256
"""Most entries of one layer stack, a sublayer counted each time it is there (as many as
the distinct layers a stage may compose, `usd._layers.MAX_LAYERS`)."""

MAX_STEPS = 1_000_000
"""Most steps of the count (sites entered, arcs, children and sublayers followed)."""

_Site = tuple[str, str]  # (the layer stack's root layer, a prim path)


class TooMuchComposition(Exception):
    """The stage's composition is beyond a bound of this module (the message says which)."""


class _Layer:
    """One layer's prims, variant selections stripped: specs, children, arcs.

    ``own``: the specs at each prim path (a variant's counts too); ``below``: at it and
    beneath it; ``hot``: the paths with arcs, and those above them (a cold subtree counts
    its specs, walked no further).
    """

    __slots__ = ("arcs", "below", "children", "hot", "own")

    def __init__(self, layer: Any) -> None:
        from pxr import Sdf  # type: ignore[import-untyped]

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
    """The opened layers, indexed as the count needs them; ``work``: the steps taken."""

    def __init__(self, layers: dict[str, Any], resolve: Callable[[Any, str], str]) -> None:
        self.layers = layers
        self.resolve = resolve
        self.indexes: dict[str, _Layer] = {}
        self.stacks: dict[str, list[tuple[str, int]]] = {}
        self.sublayers: dict[str, list[str]] = {}
        self.work = 0

    def index(self, key: str) -> _Layer:
        if key not in self.indexes:
            self.indexes[key] = _Layer(self.layers[key])
        return self.indexes[key]

    def _sublayers(self, key: str) -> list[str]:
        if key not in self.sublayers:
            layer = self.layers[key]
            found = [self.resolve(layer, s) for s in layer.subLayerPaths if s]
            self.sublayers[key] = [s for s in found if s in self.layers]
        return self.sublayers[key]

    def stack(self, key: str) -> list[tuple[str, int]]:
        """The layer stack rooted at ``key``: each layer of it, and how often it is there.

        Raises:
            TooMuchComposition: More than `MAX_STACK` entries.
        """
        if key not in self.stacks:
            counts = {key: 1}
            entries = 1
            down = {key}  # the layers on the way from the root to the current one
            frames = [(key, iter(self._sublayers(key)))]
            while frames:
                current, below = frames[-1]
                sub = next(below, None)
                if sub is None:
                    frames.pop()
                    down.discard(current)
                    continue
                self.work += 1
                if sub in down:  # a cycle: Pcp leaves it out
                    continue
                entries += 1
                if entries > MAX_STACK:
                    raise TooMuchComposition(
                        f"the layer stack of '{key}' has more than {MAX_STACK} layers (a "
                        "sublayer counted each time it is named, with its own sublayers): "
                        "refused before composing"
                    )
                counts[sub] = counts.get(sub, 0) + 1
                down.add(sub)
                frames.append((sub, iter(self._sublayers(sub))))
            self.stacks[key] = list(counts.items())
        return self.stacks[key]

    def default(self, key: str) -> str | None:
        name = self.layers[key].defaultPrim if key in self.layers else ""
        return f"/{name}" if name else None

    def expand(self, site: _Site) -> tuple[int, int, list[_Site]]:
        """A site's count but for the sites below it, the work done, and those sites.

        The count is its own specs and its cold children's subtrees, in every entry of
        its layer stack; the sites below are its children with arcs at or beneath them,
        then its arcs' targets.
        """
        stack, path = site
        indexed = [(key, times, self.index(key)) for key, times in self.stack(stack)]
        count, work = 0, 0
        hot: dict[str, None] = {}
        targets: list[_Site] = []
        for key, times, layer in indexed:
            count += times * layer.own.get(path, 0)
            for child in layer.children.get(path, ()):
                work += 1
                if any(child in other.hot for _, _, other in indexed):
                    hot[child] = None
                else:
                    count += times * layer.below[child]
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
        TooMuchComposition: Past `MAX_SITES` sites, `MAX_STACK` entries of a layer stack
            or `MAX_STEPS` steps.
    """
    stage = _Stage(layers, resolve)
    kept: dict[_Site, int] = {}
    depth: dict[_Site, int] = {}  # the sites being counted, by depth
    own, steps, below = stage.expand((root, "/"))
    _check(own, steps + stage.work)
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
            _check(frames[-1][2], steps + stage.work)
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
        _check(frame[2], steps + stage.work)


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
