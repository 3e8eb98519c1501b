"""Plain record classes: what the compiler's data classes share.

The syntax tree (nodes.py), the statement tree (structure.py) and a few
helper classes of the lexer, parser and code generator used to be
dataclasses. Every conversion paid for that before reading a line:
``import dataclasses`` brings ``inspect`` (with ast, dis, tokenize...),
12-15 ms, and decorating the 42 classes (each runs ``exec`` three or four
times) took another 24-30 ms. Measured in a bare venv, the compiler's
imports were 50-60 ms of a 480 ms first parse of a 100k-line CAM file.

So each class is written out: it names its fields in ``__slots__`` and
sets them in its own ``__init__`` (written out, not generic: the parser
builds nodes for every line it reads). What a dataclass derived from the
field names is here, once, with the same meaning:

* :class:`Record`: a dataclass's ``repr`` (``Word(letter='g',
  value=Num(value=1.0), col=0)``); equal only to itself, hashed by
  identity (``@dataclass(eq=False)``).
* :class:`Value`: equal to a record of exactly the same class whose fields,
  as a tuple in declaration order, are equal; unhashable, as a mutable
  value should be (``@dataclass``).
* :class:`HashedValue`: a value hashed by its fields too (``@dataclass(
  unsafe_hash=True)``), for objects treated as immutable.
* :class:`Frozen`: a hashed value whose fields cannot be set once made
  (``@dataclass(frozen=True)``); its ``__init__`` sets them with
  ``object.__setattr__``.
* :func:`replace`: ``dataclasses.replace``.

A class's fields are its ``__slots__`` after those of its bases, in that
order: its constructor's parameters (a ``__dict__`` slot, for a class whose
objects carry other attributes too, is not a field). Fields named in
``_hidden`` are left out of ``==``, the hash and ``repr`` (a dataclass
field with ``compare=False, repr=False``).
"""

from __future__ import annotations

from _thread import get_ident
from operator import attrgetter

#: (id, thread) of the records whose repr is being made: a record reached
#: again inside its own repr shows as ``...`` (as in a dataclass's repr).
_in_repr = set()


def _getter(names):
    """A function from a record to the tuple of its fields ``names``."""
    if len(names) > 1:
        return attrgetter(*names)  # a tuple for two names or more
    if names:
        get = attrgetter(names[0])
        return lambda record: (get(record),)
    return lambda record: ()


class Record:
    """A class of named fields with a dataclass's ``repr``, compared and
    hashed by identity."""

    __slots__ = ()

    #: Every field, in order (set for each class from its ``__slots__``).
    _fields = ()
    #: Fields that ``==``, the hash and ``repr`` leave out.
    _hidden = ()

    def __init_subclass__(cls, **options) -> None:
        super().__init_subclass__(**options)
        fields = []
        for klass in reversed(cls.__mro__):
            fields.extend(vars(klass).get("__slots__", ()))
        if "__dict__" in fields:
            fields.remove("__dict__")
        cls._fields = cls.__match_args__ = tuple(fields)
        # what ==, the hash and repr read, and a function reading them
        cls._shown = tuple(name for name in fields if name not in cls._hidden)
        cls._key = staticmethod(_getter(cls._shown))

    def __repr__(self) -> str:
        key = id(self), get_ident()
        if key in _in_repr:
            return "..."
        _in_repr.add(key)
        try:
            shown = ", ".join(
                "%s=%r" % (name, getattr(self, name)) for name in self._shown
            )
        finally:
            _in_repr.discard(key)
        return "%s(%s)" % (self.__class__.__qualname__, shown)


class Value(Record):
    """A record equal to another of exactly its class with equal fields;
    unhashable."""

    __slots__ = ()

    def __eq__(self, other):
        if other.__class__ is self.__class__:
            return self._key(self) == other._key(other)
        return NotImplemented

    __hash__ = None


class HashedValue(Value):
    """A value hashed by its fields: never change one once it is made."""

    __slots__ = ()

    def __hash__(self) -> int:
        return hash(self._key(self))


class FrozenError(AttributeError):
    """A field of a :class:`Frozen` record set or deleted
    (``dataclasses.FrozenInstanceError``)."""


class Frozen(HashedValue):
    """A hashed value whose fields cannot be set or deleted once made."""

    __slots__ = ()

    def __setattr__(self, name: str, value) -> None:
        raise FrozenError("cannot assign to field %r" % name)

    def __delattr__(self, name: str) -> None:
        raise FrozenError("cannot delete field %r" % name)

    def __reduce__(self):
        # made again by the constructor (pickle and copy would set fields)
        return self.__class__, tuple(getattr(self, name) for name in self._fields)


def replace(record: Record, **changes) -> Record:
    """A new record of ``record``'s class: its fields, but ``changes``
    (``dataclasses.replace``)."""
    for name in record._fields:
        if name not in changes:
            changes[name] = getattr(record, name)
    return record.__class__(**changes)
