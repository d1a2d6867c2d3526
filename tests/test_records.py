"""Every record of the package is the class ``typing.NamedTuple`` makes of its declaration.

`cspace._record.Record` builds records without compiling a constructor per class. Each
record's source is declared again here with ``typing.NamedTuple`` as its base, in its own
module's namespace, and the two classes are compared: fields, defaults, type hints,
signature, documentation, attributes, and what their instances do (construction by
position and keyword, defaults, ``repr``, ``_replace``, ``_asdict``, ``_make``, pickling,
copying, hashing) including the errors of a call that does not fit.
"""

import ast
import copy
import importlib
import inspect
import pickle
import textwrap
import typing
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from cspace._record import Record

SOURCE = Path(__file__).resolve().parent.parent / "src" / "cspace"


def _declared() -> list[tuple[str, str]]:
    """(module, class) of every ``class X(Record)`` in the package's sources."""
    found = []
    for path in sorted(SOURCE.rglob("*.py")):
        module = ".".join(("cspace", *path.relative_to(SOURCE).with_suffix("").parts))
        module = module.removesuffix(".__init__")
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef) and any(
                getattr(base, "id", None) == "Record" for base in node.bases
            ):
                found.append((module, node.name))
    return found


RECORDS = _declared()


def _twin(record: type) -> type:
    """The class ``typing.NamedTuple`` makes of ``record``'s own declaration."""
    module = importlib.import_module(record.__module__)
    source = textwrap.dedent(inspect.getsource(record))
    source = source.replace(
        f"class {record.__name__}(Record):", f"class {record.__name__}(_NT):", 1
    )
    space: dict[str, Any] = dict(vars(module), _NT=typing.NamedTuple)
    exec(compile(source, inspect.getsourcefile(record) or "?", "exec"), space)
    twin: type = space[record.__name__]
    twin.__qualname__ = record.__qualname__
    return twin


def _hints(cls: type) -> dict[str, object]:
    """The annotations, a forward reference as its text (NamedTuple wraps it, Record not)."""
    return {
        name: hint.__forward_arg__ if isinstance(hint, typing.ForwardRef) else hint
        for name, hint in cls.__annotations__.items()
    }


def _error(call: Callable[[type], object], cls: type) -> tuple[type, str] | None:
    try:
        call(cls)
    except Exception as exc:  # the error itself is what is compared
        return type(exc), str(exc)
    return None


def test_the_package_declares_its_records_with_record() -> None:
    assert len(RECORDS) > 80  # the walk found them (84 when this was written)
    named = []
    for path in sorted(SOURCE.rglob("*.py")):
        if path.name == "_record.py":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef) and any(
                getattr(base, "id", getattr(base, "attr", None)) == "NamedTuple"
                for base in node.bases
            ):
                named.append(f"{path.name}: {node.name}")
    assert named == []  # a NamedTuple would compile its constructor at import: use Record


@pytest.mark.parametrize(("module", "name"), RECORDS, ids=[n for _, n in RECORDS])
def test_a_record_is_what_named_tuple_makes_of_it(module: str, name: str) -> None:
    record = getattr(importlib.import_module(module), name)
    twin = _twin(record)
    assert type(record) is type(twin) is type
    assert record.__bases__ == twin.__bases__ == (tuple,)
    for attribute in ("_fields", "_field_defaults", "__match_args__", "__doc__", "__slots__"):
        assert getattr(record, attribute) == getattr(twin, attribute), attribute
    assert record.__module__ == twin.__module__ and record.__name__ == twin.__name__
    assert _hints(record) == _hints(twin)
    assert set(dir(twin)) - set(dir(record)) == set()
    # __slotnames__: pickle's cache, set on a class once one of its records is pickled
    assert set(dir(record)) - set(dir(twin)) - {"__slotnames__"} == {"__signature__"}
    for field in record._fields:
        assert getattr(record, field).__doc__ == getattr(twin, field).__doc__

    ours, theirs = inspect.signature(record), inspect.signature(twin)
    assert [(p.name, p.kind, p.default) for p in ours.parameters.values()] == [
        (p.name, p.kind, p.default) for p in theirs.parameters.values()
    ]
    assert [p.annotation for p in ours.parameters.values()] == list(_hints(twin).values())

    values = [f"value {i}" for i in range(len(record._fields))]
    required = [
        v for f, v in zip(record._fields, values, strict=True) if f not in twin._field_defaults
    ]
    by_name = dict(zip(record._fields, values, strict=True))
    made, built = record(*values), twin(*values)
    assert tuple(made) == tuple(built) and repr(made) == repr(built)
    assert tuple(record(**by_name)) == tuple(made)
    assert tuple(record(*required)) == tuple(twin(*required))
    assert made._asdict() == built._asdict()
    assert tuple(made._replace(**{record._fields[-1]: 1})) == tuple(
        built._replace(**{record._fields[-1]: 1})
    )
    assert tuple(record._make(values)) == tuple(made) and type(record._make(values)) is record
    assert made.__getnewargs__() == built.__getnewargs__()
    assert hash(made) == hash(built) and made == built
    assert not hasattr(made, "__dict__")
    for copied in (pickle.loads(pickle.dumps(made)), copy.copy(made), copy.deepcopy(made)):
        assert copied == made and type(copied) is record
    for field, value in by_name.items():
        assert getattr(made, field) == value

    calls: list[Callable[[type], object]] = [
        lambda cls: cls(*required[:-1]),
        lambda cls: cls(),
        lambda cls: cls(*values, 1),
        lambda cls: cls(*values, 1, 2),
        lambda cls: cls(*values, nothing=1),
        lambda cls: cls(*required, **{record._fields[0]: 1}),
        lambda cls: cls._make(values[:-1]),
        lambda cls: cls(*values)._replace(nothing=1),
    ]
    for call in calls:
        assert _error(call, record) == _error(call, twin)


DECLARATIONS = {
    "underscore field": "class Bad(_B):\n    _a: int\n",
    "default before required": "class Bad(_B):\n    a: int = 0\n    b: int\n",
    "own constructor": "class Bad(_B):\n    a: int\n    def __new__(cls, a): ...\n",
    "own fields": "class Bad(_B):\n    a: int\n    _fields = ('a',)\n",
    "two bases": "class Bad(_B, int):\n    a: int\n",
}


@pytest.mark.parametrize("source", DECLARATIONS.values(), ids=DECLARATIONS)
def test_a_declaration_named_tuple_refuses_is_refused_alike(source: str) -> None:
    def declare(base: object) -> tuple[type, str] | None:
        return _error(lambda _: exec(source, {"_B": base}), type)

    refused = declare(Record)
    assert refused is not None
    assert refused[0] is declare(typing.NamedTuple)[0]  # type: ignore[index]


def test_record_is_a_base_only() -> None:
    with pytest.raises(TypeError):
        Record("Point", [("x", float)])  # type: ignore[call-arg]


def test_normal_form_is_the_frozen_ordered_dataclass_of_its_fields() -> None:
    import dataclasses

    from cspace import NormalForm

    @dataclasses.dataclass(frozen=True, order=True)
    class Twin:
        r: int = 0
        t: int = 0
        rp3: int = 0

    Twin.__qualname__ = "Twin"  # its repr shows the qualified name, as NormalForm's does
    assert dataclasses.is_dataclass(NormalForm)
    assert [(f.name, f.default) for f in dataclasses.fields(NormalForm)] == [
        (f.name, f.default) for f in dataclasses.fields(Twin)
    ]
    assert NormalForm.__match_args__ == Twin.__match_args__
    shown = [str(inspect.signature(c)).replace("'", "") for c in (NormalForm, Twin)]
    assert shown[0] == shown[1]  # the annotations as text: the module's are not evaluated
    counts = [(r, t, rp3) for r in range(3) for t in range(3) for rp3 in range(2)]
    ours = [NormalForm(*c) for c in counts]
    theirs = [Twin(*c) for c in counts]
    assert [repr(a) for a in ours] == [repr(b).replace("Twin", "NormalForm") for b in theirs]
    assert [hash(a) for a in ours] == [hash(b) for b in theirs]
    for a, b in zip(ours, theirs, strict=True):
        for c, d in zip(ours, theirs, strict=True):
            compared = (a == c, a != c, a < c, a <= c, a > c, a >= c)
            assert compared == (b == d, b != d, b < d, b <= d, b > d, b >= d)
        assert (a == b, a == a.counts(), a != (a.r, a.t, a.rp3)) == (False, False, True)
        for order in ("__lt__", "__le__", "__gt__", "__ge__"):
            assert getattr(a, order)(b) is NotImplemented is getattr(b, order)(a)
        assert dataclasses.asdict(a) == dataclasses.asdict(b)
        assert dataclasses.replace(a, t=5) == NormalForm(a.r, 5, a.rp3)
        with pytest.raises(dataclasses.FrozenInstanceError):
            a.r = 1  # type: ignore[misc]
        assert pickle.loads(pickle.dumps(a)) == a and copy.deepcopy(a) == a
    with pytest.raises(ValueError, match="non-negative"):
        NormalForm(t=-1)
    with pytest.raises(TypeError):
        NormalForm(1, 2, 3, 4)  # type: ignore[call-arg]
