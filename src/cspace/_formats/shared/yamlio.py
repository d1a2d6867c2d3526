"""Safe YAML input: an untrusted YAML file read into plain values with their lines.

PyYAML's pure-Python `yaml.SafeLoader` (never the C one: the bounds below live in the
composer) with bounds of its own, each counted while the file is composed, before any
value is built:

- `MAX_YAML_NODES` nodes in all, an alias counting as many nodes as the node it names
  expands to (a billion-laughs file is refused after that many, in little memory);
- `MAX_YAML_DEPTH` nested collections;
- explicit tags only YAML's core schema's (``!!str``, ``!!int``, ``!!float``, ``!!bool``,
  ``!!null``, ``!!map``, ``!!seq``): ``!!python/object`` and any local tag are refused;
- a key written twice in one mapping is refused (YAML forbids it; PyYAML keeps the last);
- a plain scalar that YAML 1.2 reads as a float (``1e3``) is one, as ROS 2 reads it;
- a number's text at most `MAX_NUMBER_TEXT` characters, and an integer within 64 bits
  (ROS 2's parameters' integers): YAML 1.1's sexagesimal (``1:30``), binary and long
  decimal integers are otherwise unbounded Python integers, which a float cannot hold.

The file itself is read by the caller through `cspace.files.read_input` with its own size
cap. What comes out is `YamlMap`, `list` and scalars (``str``, ``int``, ``float``,
``bool``, None); a mapping keeps each key's line. Every problem is a one-line
`InvalidElementError` naming the file and line.
"""

import re
from typing import Any

from cspace._record import NamedTuple
from cspace.errors import InvalidElementError

MAX_YAML_NODES = 100_000
"""Most nodes of one YAML file, aliases counted as what they expand to (MoveIt's
joint_limits.yaml of a 50-joint robot has about 1,000)."""

MAX_YAML_DEPTH = 32
"""Most nested collections (MoveIt's files nest 3 deep)."""

MAX_NUMBER_TEXT = 100
"""Longest text of an integer or float read (a double's 17 significant digits and an
exponent take about 25)."""

_CORE = "tag:yaml.org,2002:"
_ALLOWED_TAGS = frozenset(_CORE + t for t in ("str", "int", "float", "bool", "null", "map", "seq"))
_FLOAT_12 = re.compile(r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?")
"""A float of YAML 1.2's core schema: PyYAML (YAML 1.1) reads ``1e3`` and ``1.0e3`` as
text, where ROS 2's parameter files (and YAML 1.2) read 1000.0."""
_SCALARS = frozenset(_CORE + t for t in ("int", "float", "bool", "null"))


class Entry(NamedTuple):
    """A value of a YAML mapping and the 1-based line of its key."""

    value: Any
    line: int


YamlMap = dict[str, Entry]
"""A YAML mapping: each key (as text) with its value and line."""


def load_yaml(path: str, data: bytes, what: str = "YAML file") -> Any:
    """The document of the YAML file ``path`` holding ``data`` (see the module).

    Raises:
        InvalidElementError: Not UTF-8, not YAML, several documents, or a bound met
            (code ``yaml-invalid``), with the line where it was found.
    """
    yaml = _yaml()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        at = data[: exc.start].count(b"\n") + 1
        raise _refuse(path, f"{what} is not UTF-8 text", at) from None
    loader = _loader(yaml)(text, path, what)
    try:
        node = loader.get_single_node()
        return None if node is None else _value(loader, node)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = None if mark is None else mark.line + 1
        said = " ".join(p for p in (exc.context, exc.problem) if p) or "not YAML"
        raise _refuse(path, f"{what} is not valid YAML: {said}", line) from None
    except yaml.YAMLError as exc:
        raise _refuse(path, f"{what} is not valid YAML: {exc}", None) from None
    except RecursionError:  # the depth bound stops well before; kept for safety
        raise _refuse(path, f"{what} nests too deep", None) from None
    finally:
        loader.dispose()


def _refuse(path: str, problem: str, line: int | None) -> InvalidElementError:
    return InvalidElementError(path, problem, line=line, code="yaml-invalid")


def _loader(yaml: Any) -> Any:
    """The bounded loader class (made once PyYAML is imported, on first use)."""
    global _LOADER
    if _LOADER is not None:
        return _LOADER

    class Bounded(yaml.SafeLoader):  # type: ignore[misc]
        def __init__(self, text: str, path: str, what: str) -> None:
            super().__init__(text)
            self.path, self.what = path, what
            self.count, self.depth = 0, 0
            self.sizes: dict[str, int] = {}
            self.open: set[str] = set()  # anchors whose node is being composed

        def charge(self, nodes: int, mark: Any) -> None:
            self.count += nodes
            if self.count > MAX_YAML_NODES:
                raise _refuse(
                    self.path,
                    f"{self.what} expands to more than {MAX_YAML_NODES:,} YAML nodes "
                    "(aliases counted as what they stand for)",
                    mark.line + 1,
                )

        def compose_node(self, parent: Any, index: Any) -> Any:
            event = self.peek_event()
            if isinstance(event, yaml.AliasEvent):
                if str(event.anchor) in self.open:
                    raise _refuse(
                        self.path,
                        f"{self.what} has an alias inside the node it names (a cycle)",
                        event.start_mark.line + 1,
                    )
                self.charge(self.sizes.get(str(event.anchor), 1), event.start_mark)
                return super().compose_node(parent, index)
            tag = getattr(event, "tag", None)
            if tag not in (None, "!") and tag not in _ALLOWED_TAGS:
                raise _refuse(
                    self.path,
                    f"{self.what} has the tag '{tag}': only YAML's core tags are read",
                    event.start_mark.line + 1,
                )
            self.depth += 1
            if self.depth > MAX_YAML_DEPTH:
                raise _refuse(
                    self.path,
                    f"{self.what} nests more than {MAX_YAML_DEPTH} collections deep",
                    event.start_mark.line + 1,
                )
            start = self.count
            self.charge(1, event.start_mark)
            anchor = getattr(event, "anchor", None)
            if anchor is not None:
                self.open.add(str(anchor))
            node = super().compose_node(parent, index)
            self.depth -= 1
            if anchor is not None:
                self.open.discard(str(anchor))
                self.sizes[str(anchor)] = self.count - start
            return node

        def compose_mapping_node(self, anchor: Any) -> Any:
            """The mapping, with no key written twice.

            Checked as composed, before a merge key (``<<``) puts the keys it merges into
            the node, in place, which every alias of it then shares.
            """
            node = super().compose_mapping_node(anchor)
            seen: dict[str, int] = {}
            for key, _ in node.value:
                if key.tag == _CORE + "merge":
                    continue
                text = _key(self, key)
                line = key.start_mark.line + 1
                if text in seen:
                    raise _refuse(
                        self.path,
                        f"{self.what} gives key '{text}' twice in one mapping (first at line "
                        f"{seen[text]})",
                        line,
                    )
                seen[text] = line
            return node

    _LOADER = Bounded
    return Bounded


_LOADER: Any = None


def _yaml() -> Any:
    """PyYAML, imported on first use (only ``--limits`` reads YAML)."""
    import importlib

    return importlib.import_module("yaml")


def _value(loader: Any, node: Any) -> Any:
    """The plain value of a composed node (its size already bounded)."""
    yaml = _yaml()

    if isinstance(node, yaml.ScalarNode):
        if node.tag in _SCALARS:
            return _scalar(loader, node)
        if node.style is None and node.tag == _CORE + "str" and _FLOAT_12.fullmatch(node.value):
            return float(node.value)  # 1e3: YAML 1.2's float (and ROS 2's), 1.1's text
        return str(node.value)  # a string, or a timestamp's text
    if isinstance(node, yaml.SequenceNode):
        return [_value(loader, item) for item in node.value]
    loader.flatten_mapping(node)  # merge keys (<<): the explicit keys win
    out: YamlMap = {}
    for key, value in node.value:
        out[_key(loader, key)] = Entry(_value(loader, value), key.start_mark.line + 1)
    return out


def _scalar(loader: Any, node: Any) -> Any:
    """An integer, float, boolean or null scalar's value, within its bounds."""
    line = node.start_mark.line + 1
    shown = node.value if len(node.value) <= 40 else node.value[:37] + "..."
    kind = node.tag[len(_CORE) :]
    if kind in ("int", "float") and len(node.value) > MAX_NUMBER_TEXT:
        raise _refuse(
            loader.path,
            f"{loader.what} has a number written in {len(node.value):,} characters "
            f"(at most {MAX_NUMBER_TEXT} are read)",
            line,
        )
    try:
        value = loader.construct_object(node, deep=True)
    except (ValueError, OverflowError, KeyError, IndexError):
        raise _refuse(
            loader.path, f"{loader.what} has '{shown}', which is no YAML {kind}", line
        ) from None
    if isinstance(value, int) and not isinstance(value, bool) and not -(2**63) <= value < 2**63:
        raise _refuse(
            loader.path,
            f"{loader.what} has the integer '{shown}', beyond 64 bits (ROS 2's integers)",
            line,
        )
    return value


def _key(loader: Any, node: Any) -> str:
    if not isinstance(node, _yaml().ScalarNode):
        raise _refuse(
            loader.path, f"{loader.what} has a key that is not text", node.start_mark.line + 1
        )
    return str(node.value)
