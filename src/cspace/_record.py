"""``NamedTuple``: the base of cspace's records, ``typing.NamedTuple`` built more cheaply.

A record is declared as with ``typing.NamedTuple`` (``class Limits(NamedTuple):`` with
annotated fields, defaults, methods and a docstring), only imported from here. To mypy
this ``NamedTuple`` *is* ``typing.NamedTuple``; at run time a record is the class
``typing.NamedTuple`` would make: a subclass of ``tuple`` with ``__slots__ = ()``,
``_fields``, ``_field_defaults``, ``__annotations__``, ``__match_args__``, ``_make``,
``_replace``, ``_asdict``, the same ``repr``, signature, pickling and errors.
`tests/test_records.py` holds every record of the package to the NamedTuple made of the
same declaration.

Why not ``typing.NamedTuple`` itself: it makes each class through
``collections.namedtuple``, which compiles a constructor from source for every class, and
checks every annotation again. A URDF's ``inspect`` defines some forty records, and those
compiles were a sixth of what it executes beyond Pinocchio's own load. Here every record
shares one constructor, which takes the fast path a NamedTuple's takes for a full
positional call and binds keywords and defaults as Python binds arguments, with Python's
errors. Differences that remain: an annotation written as a string stays a string where
NamedTuple wraps it in ``typing.ForwardRef`` (``typing.get_type_hints`` gives the same),
and ``help()`` shows the shared constructor's ``(cls, /, *args, **kwargs)``.

On Python versions this was not checked against (3.14 evaluates annotations lazily),
``NamedTuple`` is ``typing.NamedTuple``.
"""

import sys
from typing import TYPE_CHECKING, Any

__all__ = ["NamedTuple"]

if TYPE_CHECKING or sys.version_info >= (3, 14):
    from typing import NamedTuple as NamedTuple
else:
    import typing

    try:
        from _collections import _tuplegetter
    except ImportError:  # an interpreter without it: what collections.namedtuple uses then
        from operator import itemgetter

        def _tuplegetter(index: int, doc: str) -> Any:
            return property(itemgetter(index), doc=doc)

    _tuple_new = tuple.__new__

    # What a NamedTuple's body may not define (typing's list), and what it keeps to itself.
    _PROHIBITED = frozenset(
        (
            "__new__",
            "__init__",
            "__slots__",
            "__getnewargs__",
            "_fields",
            "_field_defaults",
            "_make",
            "_replace",
            "_asdict",
            "_source",
        )
    )
    _OWN = frozenset(("__module__", "__qualname__", "__annotations__", "__doc__"))

    # 3.13's namedtuple refuses an unknown field in _replace with a TypeError.
    _UNKNOWN_FIELD = TypeError if sys.version_info >= (3, 13) else ValueError

    def __new__(cls: Any, /, *args: Any, **kwargs: Any) -> Any:
        if not kwargs and len(args) == len(cls._fields):
            return _tuple_new(cls, args)
        return _bound_new(cls, args, kwargs)

    _COMPILE_AFTER = 16
    """Calls with keywords or defaults a record class takes before it compiles its own
    constructor, as ``collections.namedtuple`` would have at once: binding in Python
    costs 2-3 µs a call where Python's own binding costs 0.5, which tells when a class
    is made in bulk (a 2,000-joint robot), while most classes are made a few times."""

    _BOUND: dict[type, int] = {}
    """How many calls each record class has bound in Python so far."""

    def _bound_new(cls: Any, args: tuple[Any, ...], kwargs: dict[str, Any]) -> Any:
        record = _record(cls)
        calls = _BOUND.get(record, 0) + 1
        _BOUND[record] = calls
        if calls >= _COMPILE_AFTER and record.__dict__["__new__"].__func__ is __new__:
            record.__new__ = staticmethod(_compiled_new(record))
            return record.__new__(cls, *args, **kwargs)
        return _tuple_new(cls, _bind(record, args, kwargs))

    def _compiled_new(record: Any) -> Any:
        """The constructor ``collections.namedtuple`` compiles for the record's fields."""
        fields: tuple[str, ...] = record._fields
        listed = ", ".join(fields)
        values = f"({listed},)" if len(fields) == 1 else f"({listed})"  # () for none
        space = {"_tuple_new": _tuple_new, "__builtins__": {}}
        # field names are identifiers of cspace's own declarations
        made: Any = eval(
            f"lambda {', '.join(('_cls', *fields))}: _tuple_new(_cls, {values})", space
        )
        made.__name__ = "__new__"
        made.__qualname__ = f"{record.__name__}.__new__"
        made.__doc__ = f"Create new instance of {record.__name__}({listed})"
        made.__defaults__ = tuple(record._field_defaults.values()) or None
        made.__annotations__ = dict(record.__annotations__)
        return made

    def _record(cls: Any) -> Any:
        """The record class ``cls`` is or derives from (the one that declares the fields)."""
        return next(c for c in cls.__mro__ if "_fields" in c.__dict__)

    def _bind(record: Any, args: tuple[Any, ...], kwargs: dict[str, Any]) -> list[Any]:
        """The field values a call of ``record`` (or a subclass) gives, Python's errors."""
        fields: tuple[str, ...] = record._fields
        where = f"{record.__name__}.__new__()"
        for name in kwargs:  # each keyword in the order given, as CPython binds them
            if name not in fields:
                raise TypeError(f"{where} got an unexpected keyword argument '{name}'")
            if fields.index(name) < len(args):
                raise TypeError(f"{where} got multiple values for argument '{name}'")
        if len(args) > len(fields):
            most = len(fields) + 1
            least = most - len(record._field_defaults)
            takes = str(most) if least == most else f"from {least} to {most}"
            given = len(args) + 1
            raise TypeError(f"{where} takes {takes} positional arguments but {given} were given")
        values = list(args)
        missing = []
        defaults: dict[str, Any] = record._field_defaults
        for name in fields[len(args) :]:
            if name in kwargs:
                values.append(kwargs[name])
            elif name in defaults:
                values.append(defaults[name])
            else:
                missing.append(name)
        if missing:
            quoted = [f"'{name}'" for name in missing]
            listed = quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1])
            if len(quoted) > 1:
                listed += ("," if len(quoted) > 2 else "") + f" and {quoted[-1]}"
            plural = "argument" if len(missing) == 1 else "arguments"
            counted = f"{len(missing)} required positional {plural}"
            raise TypeError(f"{where} missing {counted}: {listed}")
        return values

    def _make(cls: Any, iterable: Any) -> Any:
        """Make a new record from a sequence or iterable."""
        result = _tuple_new(cls, iterable)
        if len(result) != len(cls._fields):
            raise TypeError(f"Expected {len(cls._fields)} arguments, got {len(result)}")
        return result

    def _replace(self: Any, /, **kwds: Any) -> Any:
        """Return a new record replacing specified fields with new values."""
        result = self._make(map(kwds.pop, self._fields, self))
        if kwds:
            raise _UNKNOWN_FIELD(f"Got unexpected field names: {list(kwds)!r}")
        return result

    def _asdict(self: Any) -> dict[str, Any]:
        """Return a new dict which maps field names to their values."""
        return dict(zip(self._fields, self))  # noqa: B905 (as namedtuple's)

    def __getnewargs__(self: Any) -> tuple[Any, ...]:
        """Return self as a plain tuple.  Used by copy and pickle."""
        return tuple(self)

    def __repr__(self: Any) -> str:
        """Return a nicely formatted representation string."""
        shown = ", ".join(f"{name}={value!r}" for name, value in zip(self._fields, self))  # noqa: B905
        return f"{self.__class__.__name__}({shown})"

    class _Signature:
        """``inspect.signature`` of a record class, made when asked (as NamedTuple's is).

        Only where a NamedTuple's comes from its constructor: not on an instance, nor on
        a subclass with a ``__new__`` or ``__init__`` of its own.
        """

        def __get__(self, instance: Any, owner: Any) -> Any:
            if instance is not None or owner.__new__ is not __new__:
                raise AttributeError("__signature__")
            if owner.__init__ is not object.__init__:
                raise AttributeError("__signature__")
            import inspect

            record = _record(owner)
            kind = inspect.Parameter.POSITIONAL_OR_KEYWORD
            empty = inspect.Parameter.empty
            return inspect.Signature(
                [
                    inspect.Parameter(
                        name,
                        kind,
                        default=record._field_defaults.get(name, empty),
                        annotation=record.__annotations__.get(name, empty),
                    )
                    for name in record._fields
                ]
            )

    _SIGNATURE = _Signature()

    class _RecordMeta(type):
        def __new__(mcls, typename: str, bases: tuple[type, ...], ns: dict[str, Any]) -> Any:
            if bases != (_Base,):
                raise TypeError("can only inherit from a NamedTuple type and Generic")
            types: dict[str, Any] = ns.get("__annotations__", {})
            fields = tuple(types)
            defaults: dict[str, Any] = {}
            for name in fields:
                if name.startswith("_"):
                    raise ValueError(f"Field names cannot start with an underscore: {name!r}")
                if name in ns:
                    defaults[name] = ns[name]
                elif defaults:
                    raise TypeError(
                        f"Non-default namedtuple field {name} cannot follow default field"
                        f"{'s' if len(defaults) > 1 else ''} {', '.join(defaults)}"
                    )
            body: dict[str, Any] = {
                "__doc__": f"{typename}({', '.join(fields)})",
                "__slots__": (),
                "_fields": fields,
                "_field_defaults": defaults,
                "__new__": __new__,
                "_make": classmethod(_make),
                "_replace": _replace,
                "__repr__": __repr__,
                "_asdict": _asdict,
                "__getnewargs__": __getnewargs__,
                "__match_args__": fields,
                "__signature__": _SIGNATURE,
            }
            if sys.version_info >= (3, 13):
                body["__replace__"] = _replace
            for index, name in enumerate(fields):
                body[name] = _tuplegetter(index, f"Alias for field number {index}")
            for key, value in ns.items():
                if key in _PROHIBITED:
                    raise AttributeError("Cannot overwrite NamedTuple attribute " + key)
                if key in _OWN or key not in fields:
                    body[key] = value
            if "__orig_bases__" in body:  # the base as written, for types.get_original_bases
                body["__orig_bases__"] = (typing.NamedTuple,)
            body["__annotations__"] = types
            return type.__new__(type, typename, (tuple,), body)

    _Base = type.__new__(_RecordMeta, "NamedTuple", (), {"__module__": __name__})

    def NamedTuple(typename: str, fields: Any = None, /, **kwargs: Any) -> Any:
        """Subclassed, never called: ``class Name(NamedTuple):`` with annotated fields."""
        raise TypeError("declare a record as a class: class Name(NamedTuple): ...")

    NamedTuple.__mro_entries__ = lambda bases: (_Base,)  # type: ignore[attr-defined]
