"""Numbered parameters (``#n``) and named parameters (``#<name>``).

Facts measured against rs274 (LinuxCNC 2.9) that shape this module:

* Numbered parameters are ``#1`` .. ``#5601``. An index is any value within
  0.0001 of an integer (``#1.00005`` and ``#0.99995`` both mean ``#1``);
  otherwise 'Non integer value for integer'. Outside 1..5601 (including
  anything beyond a C int, or NaN) it is 'Parameter number out of range'.
* ``#5400``-``#5413`` (tool data) and ``#5420``-``#5428`` (current position)
  cannot be set by a program: 'Parameter is readonly'. The index of a setting
  is checked when it is read, before the value after ``=``.
* Reading ``#5420``-``#5428`` while cutter radius compensation is on fails.
* A call saves ``#1``-``#30``, sets them to the arguments (missing ones are
  0.0) and restores all thirty on return.
* Named parameters starting with ``_`` are global; others are local to the
  call frame (main-program locals are not visible inside subroutines).
  Reading an unset one fails with 'Named parameter #<name> not defined';
  assigning a predefined one fails with 'Cannot assign to read-only
  parameter #<name>' (when the line is executed, after it is read).
* Once a line has read a setting ``#<name>=``, the name exists for the rest
  of that line (holding 0.0 if it was new): ``#<n>=[#<n>+1]`` is not an
  error for an unset ``n``. See :meth:`NamedStore.declare`.
"""

from __future__ import annotations

import keyword
import math
from operator import attrgetter

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, Iterable, List, Optional, Sequence

from runtime import remap
from runtime.errors import GCodeError
from runtime.ops import c_int

#: RS274NGC_MAX_PARAMETERS: valid numbers are 1 .. MAX_PARAMETERS - 1.
MAX_PARAMETERS = 5602
#: Subroutine arguments ``#1``..``#30``.
CALL_ARGS = 30
#: The current-position parameters (read-only, unreadable under cutter comp).
POSITION_PARAMS = range(5420, 5429)
_FIRST_POSITION, _LAST_POSITION = POSITION_PARAMS[0], POSITION_PARAMS[-1]
#: Parameters a program may read but not set.
READ_ONLY_PARAMS = frozenset(range(5400, 5414)) | frozenset(POSITION_PARAMS)


def _plain_index(n: float) -> int:
    """``n`` as an index when it is an integral number in range, else 0: the
    common case, which needs none of rs274's rounding and checks."""
    try:
        index = int(n)
    except (TypeError, ValueError, OverflowError):  # None, NaN, infinities
        return 0
    return index if index == n and 0 < index < MAX_PARAMETERS else 0


def parameter_index(value: float) -> int:
    """rs274's read_integer_value plus the range check of a parameter index."""
    index = c_int(_floor(value))
    fraction = value - index
    if fraction > 0.9999:
        index = c_int(-_floor(-value))
    elif fraction > 0.0001:
        raise GCodeError("Non integer value for integer")
    if not 1 <= index < MAX_PARAMETERS:
        raise GCodeError("Parameter number out of range")
    return index


def _floor(value: float) -> float:
    """C ``floor`` (inf and NaN pass through instead of raising)."""
    return float(math.floor(value)) if math.isfinite(value) else value


class Params:
    """The numbered parameters, as a list of floats indexed by number.

    ``p[n]`` reads and ``p[n] = x`` sets, validating ``n`` as rs274 does.
    To reproduce rs274's error order for ``#[expr] = value`` (the index is
    checked before ``value`` is evaluated), generated code may call
    :meth:`setting_index` first and then set ``p[index] = value``.

    ``cutter_comp`` must be kept true by the machine while cutter radius
    compensation is on: reading the position parameters is then an error.

    ``position`` holds #5420-#5428. The machine publishes its current point
    there after every block by handing over the sequence itself (no copy:
    nine stores per move would cost more than the move), so it must never
    change that sequence in place afterwards.
    """

    __slots__ = ("values", "cutter_comp", "position")

    #: The list itself: ``values[n]`` is ``#n`` for every number but the
    #: position parameters (those live in :attr:`position`). Generated code
    #: reads constant, unchecked numbers from it directly (``p[1]`` with
    #: ``p = m.params.values``): a Python ``__getitem__`` would cost ten
    #: times more, and a subroutine's arguments are read that way.
    values: List[float]

    def __init__(self, initial: Optional[Dict[int, float]] = None):
        self.values: List[float] = [0.0] * MAX_PARAMETERS
        for number, value in (initial or {}).items():
            self.values[number] = float(value)
        self.cutter_comp = False
        self.position: Sequence[float] = self.values[
            _FIRST_POSITION : _LAST_POSITION + 1
        ]

    def __getitem__(self, n: float) -> float:
        index = _plain_index(n)
        if not index or _FIRST_POSITION <= index <= _LAST_POSITION:
            index = self.reference_index(n)
            if _FIRST_POSITION <= index <= _LAST_POSITION:
                return self.position[index - _FIRST_POSITION]
        return self.values[index]

    def __setitem__(self, n: float, value: float) -> None:
        index = _plain_index(n)
        if not index or index in READ_ONLY_PARAMS:
            index = self.setting_index(n)
        self.values[index] = value

    def reference_index(self, n: float) -> int:
        """The index of a read ``#n``, or rs274's error."""
        index = parameter_index(n)
        if self.cutter_comp and index in POSITION_PARAMS:
            raise GCodeError(
                "Cannot read current position with cutter radius compensation on"
            )
        return index

    @staticmethod
    def setting_index(n: float) -> int:
        """The index of a setting ``#n=``, or rs274's error."""
        index = parameter_index(n)
        if index in READ_ONLY_PARAMS:
            raise GCodeError("Parameter is readonly")
        return index

    def get_internal(self, n: int) -> float:
        """The interpreter's own read (``#0`` included, as DEBUG shows it): no checks."""
        if _FIRST_POSITION <= n <= _LAST_POSITION:
            return self.position[n - _FIRST_POSITION]
        return self.values[n]

    def set_internal(self, n: int, value: float) -> None:
        """The interpreter's own write (offsets, tool data): no checks.
        (The position parameters are published through :attr:`position`.)"""
        self.values[n] = value

    def save_locals(self) -> List[float]:
        """``#1``-``#30``, to be given back to :meth:`restore_locals`."""
        return self.values[1 : CALL_ARGS + 1]

    def restore_locals(self, saved: List[float]) -> None:
        self.values[1 : CALL_ARGS + 1] = saved

    def set_call_args(self, args: Iterable[float]) -> None:
        """``#1``.. from the call's arguments; the rest of ``#1``-``#30`` become 0.0."""
        values = list(args)[:CALL_ARGS]
        self.values[1 : CALL_ARGS + 1] = values + [0.0] * (CALL_ARGS - len(values))


# --------------------------------------------------------------------------
# Named parameters
# --------------------------------------------------------------------------


class _Method:
    """A method that a stored value of the same name cannot shadow.

    Values live in the instance ``__dict__``, which beats ordinary methods in
    attribute lookup (a G-code local named ``exists`` would hide
    ``v.exists``). A data descriptor beats the instance ``__dict__``.
    """

    def __init__(self, func):
        self.func = func
        self.__doc__ = func.__doc__

    def __get__(self, obj, owner=None):
        return self.func if obj is None else self.func.__get__(obj, owner)

    def __set__(self, obj, value):
        raise AttributeError("read-only method")


class NamedStore:
    """Named parameter values, kept in the instance ``__dict__``.

    Every G-code name is data. The store's own state lives in ``__slots__``
    and its behaviour in methods, so the rule for generated code is
    :func:`attr_safe`: ``store.name`` may be used exactly when
    ``attr_safe(name)``; for every other name use ``store["name"]``, which
    always works (``g["__class__"]``, ``v["exists"]``, ``g["_a.b"]``).

    Reading ``store.name`` of a set name is a plain attribute lookup (fast);
    an unset name falls through to ``__getattr__``, which raises rs274's error.
    """

    __slots__ = ("__dict__",)

    def __getattr__(self, name: str) -> float:
        if name.startswith("__"):  # Python's protocols (copy, pickle...), never G-code
            raise AttributeError(name)
        return self[name]

    def __getitem__(self, name: str) -> float:
        try:
            return self.__dict__[name]
        except KeyError:
            raise GCodeError("Named parameter #<%s> not defined" % name) from None

    def __setitem__(self, name: str, value: float) -> None:
        self.__dict__[name] = value

    @_Method
    def exists(self, name: str) -> float:
        """``EXISTS[#<name>]``: 1.0 or 0.0."""
        return 1.0 if name in self.__dict__ else 0.0

    @_Method
    def read_or_zero(self, name: str) -> float:
        """``#<name>`` read while rs274 reads a subroutine definition: a
        name not defined reads 0 there instead of failing."""
        return self[name] if self.exists(name) else 0.0

    @_Method
    def declare(self, name: str) -> None:
        """A setting of ``name`` has been read: from now on it exists.

        Generated code calls this at the point where rs274 reads the setting
        target (before the value after ``=``), for names it cannot prove set.
        """
        self.__dict__.setdefault(name, 0.0)


class Locals(NamedStore):
    """The named locals of one call frame (or of the main program)."""

    __slots__ = ()


class ArgCountLocals(Locals):
    """The locals of a call when ``[RS274NGC]OWORD_NARGS`` is on: they start
    with ``#<n_args>``, the number of arguments, which cannot be assigned.
    (A property on the class beats the instance dict, so ``v.n_args = x``
    reaches the setter.)"""

    __slots__ = ()

    def __init__(self, count: int) -> None:
        self.__dict__["n_args"] = float(count)

    @property
    def n_args(self) -> float:
        return self.__dict__["n_args"]

    @n_args.setter
    def n_args(self, value: float) -> None:
        self["n_args"] = value

    def __setitem__(self, name: str, value: float) -> None:
        if name == "n_args":
            raise GCodeError("Cannot assign to read-only parameter #<n_args>")
        self.__dict__[name] = value


class Globals(NamedStore):
    """Named globals (``#<_name>``), with the machine's predefined ones.

    A name in ``machine.PREDEFINED`` is read through
    ``machine.predefined(name)`` and cannot be assigned.
    """

    __slots__ = ("_machine_",)

    def __init__(self, machine) -> None:
        object.__setattr__(self, "_machine_", machine)

    def __getitem__(self, name: str) -> float:
        value = self.__dict__.get(name)  # a float, never None, once set
        if value is not None:
            return value
        machine = self._machine_
        if name in machine.PREDEFINED:  # #<_value> after every call: no raise
            return machine.predefined(name)
        if name.startswith("_ini[") and _from_ini(self, name):
            return self.__dict__[name]
        if remap.loads_python(machine.settings.ini):
            raise GCodeError(remap.PYTHON_PARAM % name)
        raise GCodeError("Named parameter #<%s> not defined" % name)

    @classmethod
    def install_predefined(cls, names, direct) -> None:
        """Make each predefined name a read-only attribute (a data
        descriptor beats the instance dict, as for ``n_args``), so that
        ``g._name = x`` needs no ``__setattr__`` on every global's assignment.
        ``direct``: names whose value is simply the machine attribute given."""
        for name in names:
            setattr(cls, name, _predefined_property(name, direct.get(name)))

    def __setitem__(self, name: str, value: float) -> None:
        if name in self._machine_.PREDEFINED or (
            name.startswith("_ini[") and _from_ini(self, name)
        ):
            raise GCodeError("Cannot assign to read-only parameter #<%s>" % name)
        self.__dict__[name] = value

    @_Method
    def exists(self, name: str) -> float:
        if name in self.__dict__ or name in self._machine_.PREDEFINED:
            return 1.0
        return 1.0 if name.startswith("_ini[") and _from_ini(self, name) else 0.0

    @_Method
    def declare(self, name: str) -> None:
        # A predefined name is not created here: its assignment fails later,
        # when the line is executed, exactly as in rs274.
        if name not in self._machine_.PREDEFINED and not (
            name.startswith("_ini[") and _from_ini(self, name)
        ):
            self.__dict__.setdefault(name, 0.0)


def _predefined_property(name: str, attribute: Optional[str]) -> property:
    if attribute is None:

        def read(store: Globals) -> float:
            return store._machine_.predefined(name)

    else:  # in C: a property's getter is called on every read
        read = attrgetter("_machine_." + attribute)

    def write(store: Globals, value: float) -> None:
        raise GCodeError("Cannot assign to read-only parameter #<%s>" % name)

    return property(read, write, doc="#<%s>, read-only" % name)


def _from_ini(store: "Globals", name: str) -> bool:
    """``#<_ini[SECTION]KEY>``: rs274 looks a name it does not know up in the
    INI file, and keeps a number it finds there as a read-only global.
    (A function, not a method: a G-code name could shadow a method.)"""
    machine = store._machine_
    if name in machine.ini_globals:
        return True
    value = machine.ini_parameter(name)
    if value is None:
        return False
    machine.ini_globals.add(name)
    store.__dict__[name] = value
    return True


#: Names ``store.name`` must not be used for: every attribute the classes have.
_RESERVED = frozenset(dir(Globals)) | frozenset(dir(Locals)) | {"_machine_", "__dict__"}


def unset_variable(error: UnboundLocalError) -> BaseException:
    """rs274's error for a named local that generated code keeps in a Python
    variable (``i`` for ``#<i>``, ``v_jump`` for ``#<jump>``: see
    ngc2py/fastlocals.py) read before it was set, with the traceback that
    names the G-code line. The code generator only does that where the name
    is certainly set first: this is the safety net. Any other
    UnboundLocalError (not raised by a generated module's own code) is left
    as it is."""
    words = str(error).split("'")
    tb = error.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    if len(words) >= 2 and tb is not None and "__ngc__" in tb.tb_frame.f_globals:
        name = words[1][2:] if words[1].startswith("v_") else words[1]
        named = GCodeError("Named parameter #<%s> not defined" % name)
        return named.with_traceback(error.__traceback__)
    return error


def attr_safe(name: str) -> bool:
    """May generated code write ``store.name`` for the G-code name ``name``?

    True for Python identifiers that are not keywords, not dunder-like and
    not an attribute of the stores; use ``store["name"]`` otherwise.
    """
    return (
        name.isidentifier()
        and not keyword.iskeyword(name)
        and not name.startswith("__")
        and name not in _RESERVED
    )


__all__ = [
    "MAX_PARAMETERS",
    "READ_ONLY_PARAMS",
    "POSITION_PARAMS",
    "Params",
    "NamedStore",
    "Locals",
    "Globals",
    "attr_safe",
    "parameter_index",
]
