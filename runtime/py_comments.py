"""``(py,...)``, ``(pyrun,...)`` and ``(pyreload)`` comments.

The stand-alone rs274 has an embedded Python: ``(py,CODE)`` runs CODE as a
statement in one namespace kept for the whole run, and a Python error stops
the program with ``run_string(CODE): `` and the Python traceback as the
message; ``(pyrun,CODE)`` runs CODE as a file and ignores its errors;
``(pyreload)`` reloads the (absent) Python modules. None of them makes a
canonical call. CODE cannot contain parentheses (they end the comment), so
it cannot call functions.

ngc2py never runs code found in a G-code file. It parses CODE (``ast.parse``
only builds a syntax tree) and evaluates the small part of Python that such
comments can usefully hold -- names bound to numbers, strings, booleans and
None, arithmetic, comparisons, ``pass``, ``assert`` -- in a private
namespace, so ``(py,x=5)`` then ``(py,y=x*2)`` behave as in rs274 and
``(py,y=z)`` fails as it does (NameError). Programs check the interpreter's
state with LinuxCNC's ``interpreter`` module (``;py,from interpreter import
*`` then ``;py,assert this.params["_mist"] == 1.0``): its import binds a
read-only view of the machine offering what such checks read -- ``this.params``
(named and numbered parameters), ``this.call_level``, ``this.return_value``,
``this.value_returned`` and ``equal(a, b)`` (rs274's 0.0001 tolerance). A
syntax error or a failing statement fails with rs274's first line; code
outside that subset (other imports and attributes, calls, loops...) stops
with an error that says ngc2py does not run it. ``(pyrun,...)`` and ``(pyreload)``
do nothing: rs274's only visible effect of them is none (errors are
ignored). The message's later lines (Python's traceback) are not copied.
"""

from __future__ import annotations

import ast
import operator
from typing import Any, Callable, Dict

from runtime import remap
from runtime.comments import ascii_lower
from runtime.errors import GCodeError
from runtime.params import MAX_PARAMETERS

_BINARY: Dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.FloorDiv: operator.floordiv,
    ast.Mod: operator.mod,
}
_UNARY: Dict[type, Callable[[Any], Any]] = {
    ast.USub: operator.neg,
    ast.UAdd: operator.pos,
    ast.Not: operator.not_,
}
_COMPARE: Dict[type, Callable[[Any, Any], Any]] = {
    ast.Eq: operator.eq,
    ast.NotEq: operator.ne,
    ast.Lt: operator.lt,
    ast.LtE: operator.le,
    ast.Gt: operator.gt,
    ast.GtE: operator.ge,
}
#: Strings longer than this are refused (``"x"*10**9`` must not eat memory).
_MAX_TEXT = 10_000


class _Unsupported(Exception):
    """Python that ngc2py does not evaluate."""


class _Failed(Exception):
    """What makes rs274's Python raise (an assertion, a missing parameter)."""


#: rs274's equality of doubles (interp_internal.hh: TOLERANCE_EQUAL).
_TOLERANCE_EQUAL = 0.0001
#: Numbered parameters rs274's ``params[n]`` reads (it does not check n).
_NUMBERED = range(MAX_PARAMETERS)
#: What ``from interpreter import *`` binds to something ngc2py offers; any
#: other name the import may have bound is refused, not a NameError.
_STAR_IMPORTED = "<from interpreter import *>"
#: Set once ``this`` is bound (at the first Python line of a run).
_BOUND = "<this bound>"
#: ``this``'s attributes: the predefined parameter each one reads.
_THIS = {
    "call_level": "_call_level",
    "return_value": "_value",
    "value_returned": "_value_returned",
}


class _Interpreter:
    """LinuxCNC's ``interpreter`` module, as far as checks use it."""

    __slots__ = ("this",)

    def __init__(self, machine) -> None:
        self.this = _This(machine)


class _This:
    """``interpreter.this``: the running interpreter, read only."""

    __slots__ = ("machine",)

    def __init__(self, machine) -> None:
        self.machine = machine


class _Params:
    """``this.params``: ``params["name"]`` and ``params[5400]``."""

    __slots__ = ("machine",)

    def __init__(self, machine) -> None:
        self.machine = machine

    def __getitem__(self, key: Any) -> float:
        machine = self.machine
        if isinstance(key, str):
            # rs274's find_named_param: a global or the call's local, the
            # name's ASCII letters in any case (G-code's are lower case)
            name = ascii_lower(key)
            store = machine.globals if name.startswith("_") else machine.locals
            if not store.exists(name):
                if remap.loads_python(machine.settings.ini):
                    raise _Unsupported()  # perhaps one the INI's Python defines
                raise _Failed()
            return float(store[name])
        if isinstance(key, int) and not isinstance(key, bool):
            if key not in _NUMBERED:
                raise _Unsupported()  # rs274 reads outside its array there
            return float(machine.params.get_internal(key))
        raise _Failed()  # "params subscript type must be integer or string"


def _equal(a: Any, b: Any) -> bool:
    if not all(isinstance(x, (int, float)) for x in (a, b)):
        raise _Failed()  # boost.python refuses the call
    return abs(float(a) - float(b)) < _TOLERANCE_EQUAL


def run_py_comment(machine, code: str) -> None:
    """``(py,CODE)``: evaluate CODE as rs274's embedded Python would."""
    failed = GCodeError("run_string(%s): " % code)
    try:
        tree = ast.parse(code)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise failed from None  # ValueError: a NUL byte in the code
    namespace = machine.python_namespace
    if _BOUND not in namespace:
        # rs274's Python namespace has ``this`` (the running interpreter)
        # from the start; ``interpreter``, ``equal`` & co. come by import
        namespace[_BOUND] = True
        namespace["this"] = _This(machine)
    try:
        for statement in tree.body:
            _statement(statement, namespace, machine)
    except _Unsupported:
        raise GCodeError(
            "ngc2py does not run embedded Python beyond simple statements: (py,%s)"
            % code
        ) from None
    except (ArithmeticError, NameError, TypeError, ValueError, OverflowError, _Failed):
        raise failed from None


def _statement(node: ast.stmt, namespace: dict, machine) -> None:
    if isinstance(node, ast.Pass):
        return
    if isinstance(node, ast.Assert):
        if not _value(node.test, namespace):
            if node.msg is not None:
                _value(node.msg, namespace)
            raise _Failed()
    elif isinstance(node, (ast.Import, ast.ImportFrom)):
        _import(node, namespace, machine)
    elif isinstance(node, ast.Expr):
        _value(node.value, namespace)
    elif isinstance(node, ast.Assign):
        value = _value(node.value, namespace)
        for target in node.targets:
            namespace[_name(target)] = value
    elif isinstance(node, ast.AugAssign) and type(node.op) in _BINARY:
        name = _name(node.target)
        if name not in namespace:
            raise NameError(name)
        value = _BINARY[type(node.op)](namespace[name], _value(node.value, namespace))
        namespace[name] = _checked(value)
    else:
        raise _Unsupported()


def _import(node, namespace: dict, machine) -> None:
    """``import interpreter`` and ``from interpreter import *``; LinuxCNC's
    module, so they always succeed in rs274. Any other import is refused."""
    if isinstance(node, ast.Import):
        if [(a.name, a.asname) for a in node.names] != [("interpreter", None)]:
            raise _Unsupported()
        namespace["interpreter"] = _Interpreter(machine)
        return
    if (
        node.module != "interpreter"
        or node.level
        or [a.name for a in node.names] != ["*"]
    ):
        raise _Unsupported()
    namespace["this"] = _Interpreter(machine).this
    namespace["equal"] = _equal
    namespace[_STAR_IMPORTED] = True


def _name(target: ast.expr) -> str:
    if not isinstance(target, ast.Name):
        raise _Unsupported()
    return target.id


def _value(node: ast.expr, namespace: dict) -> Any:
    if isinstance(node, ast.Constant) and isinstance(
        node.value, (int, float, str, bool, type(None))
    ):
        return _checked(node.value)
    if isinstance(node, ast.Name):
        if node.id in namespace:
            return namespace[node.id]
        if node.id in ("True", "False", "None"):
            return {"True": True, "False": False, "None": None}[node.id]
        if _STAR_IMPORTED in namespace:
            raise _Unsupported()  # perhaps one of the module's own names
        raise NameError(node.id)
    if isinstance(node, ast.Attribute):
        base = _value(node.value, namespace)
        if isinstance(base, _Interpreter) and node.attr == "this":
            return base.this
        if isinstance(base, _This):
            if node.attr == "params":
                return _Params(base.machine)
            if node.attr in _THIS:
                return float(base.machine.globals[_THIS[node.attr]])
        raise _Unsupported()
    if isinstance(node, ast.Subscript):
        base = _value(node.value, namespace)
        if not isinstance(base, _Params):
            raise _Unsupported()
        return base[_value(node.slice, namespace)]
    if isinstance(node, ast.Call):
        if node.keywords or _value(node.func, namespace) is not _equal:
            raise _Unsupported()
        if len(node.args) != 2:
            raise _Failed()  # boost.python: no such signature
        return _equal(*(_value(arg, namespace) for arg in node.args))
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left = _value(node.left, namespace)
        right = _value(node.right, namespace)
        if isinstance(node.op, ast.Mult) and (
            isinstance(left, str) or isinstance(right, str)
        ):
            raise _Unsupported()  # string repetition: keep memory bounded
        return _checked(_BINARY[type(node.op)](left, right))
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_value(node.operand, namespace))
    if isinstance(node, ast.Compare) and all(type(op) in _COMPARE for op in node.ops):
        left = _value(node.left, namespace)
        for op, right_node in zip(node.ops, node.comparators):
            right = _value(right_node, namespace)
            if not _COMPARE[type(op)](left, right):
                return False
            left = right
        return True
    if isinstance(node, ast.BoolOp):
        result = None
        for operand in node.values:
            result = _value(operand, namespace)
            if isinstance(node.op, ast.And) and not result:
                return result
            if isinstance(node.op, ast.Or) and result:
                return result
        return result
    if isinstance(node, ast.Tuple):
        return tuple(_value(element, namespace) for element in node.elts)
    raise _Unsupported()


def _checked(value: Any) -> Any:
    """Refuse values that would grow without bound (huge integers, texts)."""
    if isinstance(value, str) and len(value) > _MAX_TEXT:
        raise _Unsupported()
    if (
        isinstance(value, int)
        and not isinstance(value, bool)
        and value.bit_length() > 4096
    ):
        raise _Unsupported()
    return value


__all__ = ["run_py_comment"]
