"""`Record`: dataclass-like value classes that cost almost nothing to define.

Why not `dataclasses`: `@dataclass` compiles six methods per class when the module is
imported (``__init__``, ``__repr__``, ``__eq__``, ``__hash__`` and a frozen class's
``__setattr__``/``__delattr__``). The syntax tree alone has 58 node classes, so importing
`melfa.lang` spent about a third of `melfa check`'s start-up compiling code for methods a
small check never calls (bench/bench_check.py). A `Record` shares one generic ``__eq__``,
``__hash__``, ``__repr__`` and frozen ``__setattr__`` among all classes, and compiles a
class's ``__init__`` (the one method that must be fast: the parser builds thousands of nodes)
on the first instantiation only.

Semantics are those of ``@dataclass(frozen=True)`` (or of a plain ``@dataclass`` with
``frozen=False``): fields from the annotations in order, defaults, `field(default_factory=…,
compare=False)`, ``__post_init__``, equality only between instances of the same class,
hashable when frozen, ``Name(field=value, …)`` repr. Type checkers see a dataclass
(PEP 681 `dataclass_transform`).

>>> class Point(Record):
...     x: int
...     y: int = 0
...     tag: str = field(default="", compare=False)
>>> Point(1, tag="a") == Point(1), Point(1, 2)
(True, Point(x=1, y=2, tag=''))
>>> Point(1).x = 5
Traceback (most recent call last):
...
melfa.lang.record.FrozenError: cannot assign to field 'x'
"""

from __future__ import annotations

from typing import Any, ClassVar, dataclass_transform


class FrozenError(AttributeError):
    """Assigning to or deleting a field of a frozen record."""


class _Missing:
    def __repr__(self) -> str:
        return "MISSING"


MISSING: Any = _Missing()


class Field:
    """What `field()` returns: a default and whether the field takes part in equality."""

    __slots__ = ("compare", "default", "default_factory")

    def __init__(self, default: Any, default_factory: Any, compare: bool) -> None:
        self.default = default
        self.default_factory = default_factory
        self.compare = compare


def field(*, default: Any = MISSING, default_factory: Any = MISSING, compare: bool = True) -> Any:
    """A field with a default factory, or left out of equality and hashing."""
    return Field(default, default_factory, compare)


@dataclass_transform(frozen_default=True, field_specifiers=(field,))
class Record:
    """Base of value classes; subclass with ``frozen=False`` for a mutable one."""

    __slots__ = ()
    __record_fields__: ClassVar[tuple[str, ...]] = ()
    __record_compared__: ClassVar[tuple[str, ...]] = ()
    __record_defaults__: ClassVar[dict[str, Field]] = {}
    __record_frozen__: ClassVar[bool] = True

    def __init_subclass__(cls, *, frozen: bool = True, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        names = list(cls.__record_fields__)
        specs = dict(cls.__record_defaults__)
        compared = set(cls.__record_compared__)
        own = cls.__dict__.get("__annotations__", {})  # noqa: RUF063  (inspect costs start-up)
        for name, annotation in own.items():
            if str(annotation).startswith(("ClassVar", "typing.ClassVar")):
                continue
            if name not in names:
                names.append(name)
            value = cls.__dict__.get(name, MISSING)
            if isinstance(value, Field):
                spec = value
                if spec.default is MISSING:
                    delattr(cls, name)
                else:
                    setattr(cls, name, spec.default)
            else:
                spec = Field(value, MISSING, True)
            if spec.default is not MISSING or spec.default_factory is not MISSING:
                specs[name] = spec
            elif name in specs:
                del specs[name]
            if spec.compare:
                compared.add(name)
            else:
                compared.discard(name)
        seen_default = False
        for name in names:
            if name in specs:
                seen_default = True
            elif seen_default:
                raise TypeError(f"non-default field {name!r} follows a default field")
        cls.__record_fields__ = tuple(names)
        cls.__record_compared__ = tuple(n for n in names if n in compared)
        cls.__record_defaults__ = specs
        cls.__record_frozen__ = frozen
        setattr(cls, "__match_args__", tuple(names))  # noqa: B010  (not declared on Record)
        if "__init__" not in cls.__dict__:  # not the compiled one of a parent, if used already
            cls.__init__ = Record.__init__  # type: ignore[method-assign]
        if not frozen:
            cls.__setattr__ = object.__setattr__  # type: ignore[method-assign,assignment]
            cls.__delattr__ = object.__delattr__  # type: ignore[method-assign]
            cls.__hash__ = None  # type: ignore[assignment]  # mutable and compared: unhashable

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        """Compiles the class's own ``__init__`` on its first instance, then calls it."""
        cls = type(self)
        init = _compile_init(cls)
        cls.__init__ = init  # type: ignore[method-assign]
        init(self, *args, **kwargs)

    def _key(self) -> tuple[Any, ...]:
        return tuple([getattr(self, name) for name in self.__record_compared__])

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        shown = ", ".join(f"{name}={getattr(self, name)!r}" for name in self.__record_fields__)
        return f"{type(self).__qualname__}({shown})"

    def __setattr__(self, name: str, value: Any) -> None:
        raise FrozenError(f"cannot assign to field {name!r}")

    def __delattr__(self, name: str) -> None:
        raise FrozenError(f"cannot delete field {name!r}")


def _compile_init(cls: type[Record]) -> Any:
    """``def __init__(self, a, b=<default>): self.__dict__['a'] = a …`` for `cls`."""
    params: list[str] = []
    body: list[str] = []
    namespace: dict[str, Any] = {"MISSING": MISSING}
    for name in cls.__record_fields__:
        spec = cls.__record_defaults__.get(name)
        if spec is None:
            params.append(name)
        elif spec.default_factory is not MISSING:
            namespace[f"_factory_{name}"] = spec.default_factory
            params.append(f"{name}=MISSING")
            body.append(f"    if {name} is MISSING: {name} = _factory_{name}()")
        else:
            namespace[f"_default_{name}"] = spec.default
            params.append(f"{name}=_default_{name}")
        body.append(f"    d[{name!r}] = {name}")
    if hasattr(cls, "__post_init__"):
        body.append("    self.__post_init__()")
    source = f"def __init__(self, {', '.join(params)}):\n    d = self.__dict__\n" + "\n".join(body)
    exec(source, namespace)
    init = namespace["__init__"]
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    return init
