"""Every record of the package is the class ``typing.NamedTuple`` makes of its declaration.

Records derive from `cspace._record.NamedTuple`, which makes them without compiling a
constructor per class. Each record's source is declared again here with
``typing.NamedTuple`` as its base, in its own module's namespace, and the two classes are
compared: fields, defaults, type hints, signature, documentation, attributes, what their
instances do (construction by position and keyword, defaults, ``repr``, ``_replace``,
``_asdict``, ``_make``, pickling, copying), the errors of calls that do not fit, and
their subclasses. ``NormalForm`` is held to the frozen ordered dataclass of its fields.
"""

import ast
import copy
import dataclasses
import importlib
import inspect
import pickle
import textwrap
import typing
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from cspace import NormalForm, _record
from cspace._record import NamedTuple

SOURCE = Path(__file__).resolve().parent.parent / "src" / "cspace"

OWN = pytest.mark.skipif(
    NamedTuple is typing.NamedTuple, reason="this Python's records are typing.NamedTuple's"
)


def _trees() -> dict[Path, ast.Module]:
    return {path: ast.parse(path.read_text()) for path in sorted(SOURCE.rglob("*.py"))}


def _declared() -> list[tuple[str, str]]:
    """(module, class) of every ``class X(NamedTuple)`` in the package's sources."""
    found = []
    for path, tree in _trees().items():
        module = ".".join(("cspace", *path.relative_to(SOURCE).with_suffix("").parts))
        module = module.removesuffix(".__init__")
        for node in ast.walk(tree):
            if isinstance(node, ast.ClassDef) and any(
                getattr(base, "id", None) == "NamedTuple" for base in node.bases
            ):
                found.append((module, node.name))
    return found


RECORDS = _declared()


def _declare(record: type, base: object) -> type:
    """A class of ``record``'s own declaration, made anew with ``base`` for NamedTuple."""
    module = importlib.import_module(record.__module__)
    source = textwrap.dedent(inspect.getsource(record))
    declared = f"class {record.__name__}(NamedTuple):"
    assert declared in source
    source = source.replace(declared, f"class {record.__name__}(_NT):", 1)
    space: dict[str, Any] = dict(vars(module), _NT=base)
    exec(compile(source, inspect.getsourcefile(record) or "?", "exec"), space)
    made: type = space[record.__name__]
    return made


def _twin(record: type) -> type:
    """The class ``typing.NamedTuple`` makes of ``record``'s own declaration."""
    return _declare(record, typing.NamedTuple)


def _hints(cls: type) -> dict[str, object]:
    """The annotations, a forward reference as its text (NamedTuple wraps it, we do not)."""
    return {
        name: hint.__forward_arg__ if isinstance(hint, typing.ForwardRef) else hint
        for name, hint in cls.__annotations__.items()
    }


def _outcome(call: Callable[[type], object], cls: type) -> object:
    """What a call gives: its result as a plain tuple, or its error's type and message."""
    try:
        made = call(cls)
    except Exception as exc:  # the error itself is what is compared
        return type(exc), str(exc)
    return tuple(made) if isinstance(made, tuple) else made


def test_every_record_is_declared_with_the_packages_named_tuple() -> None:
    assert len(RECORDS) > 80  # the walk found them (84 when this was written)
    wrong = []
    for path, tree in _trees().items():
        if path.name == "_record.py":
            continue
        for node in ast.walk(tree):
            typing_one = isinstance(node, ast.ImportFrom) and node.module == "typing"
            if typing_one and any(a.name == "NamedTuple" for a in node.names):
                wrong.append(f"{path.name}: from typing import NamedTuple")
            if isinstance(node, ast.Attribute) and node.attr in ("NamedTuple", "namedtuple"):
                wrong.append(f"{path.name}: {ast.unparse(node)}")
    assert wrong == []  # typing's compiles a constructor per class at import


@OWN
@pytest.mark.parametrize(("module", "name"), RECORDS, ids=[n for _, n in RECORDS])
def test_a_record_is_what_named_tuple_makes_of_it(module: str, name: str) -> None:
    record = getattr(importlib.import_module(module), name)
    twin = _twin(record)
    assert type(record) is type(twin) is type
    assert record.__bases__ == twin.__bases__ == (tuple,)
    same = ("_fields", "_field_defaults", "__match_args__", "__doc__", "__slots__")
    for attribute in (*same, "__module__", "__qualname__", "__orig_bases__"):
        assert getattr(record, attribute) == getattr(twin, attribute), attribute
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

    fields = record._fields
    values = [f"value {i}" for i in range(len(fields))]
    by_name = dict(zip(fields, values, strict=True))
    required = [v for f, v in by_name.items() if f not in twin._field_defaults]
    made, built = record(*values), twin(*values)
    assert tuple(made) == tuple(built) and repr(made) == repr(built)
    assert made._asdict() == built._asdict()
    assert made.__getnewargs__() == built.__getnewargs__()
    assert not hasattr(made, "__dict__")
    for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
        copied = pickle.loads(pickle.dumps(made, protocol))
        assert copied == made and type(copied) is record
    for copied in (copy.copy(made), copy.deepcopy(made)):
        assert copied == made and type(copied) is record
    for field, value in by_name.items():
        assert getattr(made, field) == value
    with pytest.raises(AttributeError):
        made.__signature__  # noqa: B018 (a NamedTuple's instances have none)

    last = fields[-1]
    calls: list[Callable[[type], object]] = [
        lambda cls: cls(*values),
        lambda cls: cls(**by_name),
        lambda cls: cls(*required),
        lambda cls: cls(*required[:-1]),
        lambda cls: cls(),
        lambda cls: cls(*values, 1),
        lambda cls: cls(*values, 1, 2),
        lambda cls: cls(*values, nothing=1),
        lambda cls: cls(*values, 1, nothing=1),
        lambda cls: cls(*values[:1], nothing=1, **{fields[0]: 1}),
        lambda cls: cls(*required, **{fields[0]: 1}),
        lambda cls: cls(*values[:-1], **{last: 1}),
        lambda cls: cls._make(values),
        lambda cls: cls._make(values[:-1]),
        lambda cls: cls(*values)._replace(**{last: 1}),
        lambda cls: cls(*values)._replace(nothing=1),
    ]
    for call in calls:
        assert _outcome(call, record) == _outcome(call, twin)
    # A class binds keywords and defaults in Python until it has done so often enough to
    # compile its own constructor (as NamedTuple's): both ways, as NamedTuple's does.
    fresh = _declare(record, NamedTuple)
    for binding in ("Python's", "compiled"):
        assert (fresh.__new__.__qualname__ == f"{name}.__new__") is (binding == "compiled")
        for call in calls:
            assert _outcome(call, fresh) == _outcome(call, twin), binding
        assert str(inspect.signature(fresh)) == str(inspect.signature(record)), binding
        for _ in range(_record._COMPILE_AFTER):
            fresh(**by_name)


def _subclasses(base: type) -> dict[str, type]:
    class Plain(base):  # type: ignore[misc]
        pass

    class OwnNew(base):  # type: ignore[misc]
        def __new__(cls, first: str) -> Any:
            return super().__new__(cls, *[first] * len(base._fields))  # type: ignore[attr-defined]

    class OwnInit(base):  # type: ignore[misc]
        def __init__(self, *args: object, extra: int = 0, **kwargs: object) -> None:
            pass

    return {"plain": Plain, "own __new__": OwnNew, "own __init__": OwnInit}


@OWN
def test_a_records_subclass_is_what_a_named_tuples_subclass_is() -> None:
    from cspace._joint_report import Limits

    twin = _twin(Limits)
    ours, theirs = _subclasses(Limits), _subclasses(twin)
    for kind, sub in ours.items():
        other = theirs[kind]
        shown = (str(inspect.signature(c)).replace("'", "") for c in (sub, other))
        assert next(shown) == next(shown), kind
        assert _outcome(lambda c: c("a"), sub) == _outcome(lambda c: c("a"), other), kind
        assert _outcome(lambda c: c(), sub) == _outcome(lambda c: c(), other), kind
        args = ("a",) if kind == "own __new__" else ("a", "b", "c")
        made = sub(*args)
        assert tuple(made) == tuple(other(*args)) and repr(made) == repr(other(*args))
        if kind != "own __new__":  # a copy calls __new__ with every field
            assert copy.deepcopy(made) == made and type(copy.deepcopy(made)) is sub


DECLARATIONS = {
    "underscore field": "class Bad(_B):\n    _a: int\n",
    "default before required": "class Bad(_B):\n    a: int = 0\n    b: int\n",
    "own constructor": "class Bad(_B):\n    a: int\n    def __new__(cls, a): ...\n",
    "own fields": "class Bad(_B):\n    a: int\n    _fields = ('a',)\n",
    "two bases": "class Bad(_B, int):\n    a: int\n",
    "called": "Bad = _B('Bad', [('a', int)])\nBad(1)\nBad(a=1)\n",
}


@OWN
@pytest.mark.parametrize(("case", "source"), DECLARATIONS.items(), ids=DECLARATIONS)
def test_a_declaration_named_tuple_refuses_is_refused_alike(case: str, source: str) -> None:
    def declare(base: object) -> object:
        return _outcome(lambda _: exec(source, {"_B": base}), type)

    refused = declare(NamedTuple)
    if case != "called":  # typing's makes a class of the call; ours only subclasses
        assert refused == declare(typing.NamedTuple)
    assert isinstance(refused, tuple) and refused[0] in (TypeError, ValueError, AttributeError)


def test_normal_form_is_the_frozen_ordered_dataclass_of_its_fields() -> None:
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


def test_normal_forms_subclasses_compare_and_check_as_a_dataclasss_do() -> None:
    seen = []

    class Logged(NormalForm):
        def __post_init__(self) -> None:  # a subclass's hook runs, as the dataclass's
            seen.append(self.counts())

    @dataclasses.dataclass(frozen=True)
    class Wider(NormalForm):
        extra: int = 0

    assert Logged(t=-1).t == -1 and seen == [{"R": 0, "T": -1, "RP3": 0}]
    with pytest.raises(ValueError, match="non-negative"):
        Wider(t=-1)  # the inherited check runs from the subclass's generated constructor
    assert NormalForm(1) != Logged(1) and NormalForm(1).__lt__(Logged(2)) is NotImplemented


def test_a_saved_reports_keys_never_reach_a_compiled_constructor(tmp_path: Path) -> None:
    # A report read back builds records by keyword, often enough to compile their
    # constructors: only the declared field names are ever compiled, and a key that is
    # code, in every object of the file, is data that changes nothing and runs nothing.
    import json

    import cspace
    from cspace import JointReport, Report

    report = cspace.inspect(str(SOURCE.parent.parent / "robots" / "arm7.urdf"))
    marker = tmp_path / "ran"
    code = f"__import__('pathlib').Path({str(marker)!r}).touch()"
    document = json.loads(report.to_json())
    for joint in document["joints"]:
        joint[code] = 1
        joint["x=1): pass\nimport os\ndef f(y"] = 2
    document[code] = 1
    for _ in range(2 * _record._COMPILE_AFTER):
        assert Report.from_dict(document) == report
    assert not marker.exists()
    names = JointReport.__new__.__code__.co_varnames  # compiled by now: 7 joints a read
    assert JointReport.__new__.__qualname__ == "JointReport.__new__"
    assert names == ("_cls", *JointReport._fields)
