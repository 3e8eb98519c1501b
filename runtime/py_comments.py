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
None, arithmetic, comparisons, ``pass`` -- in a private namespace, so
``(py,x=5)`` then ``(py,y=x*2)`` behave as in rs274 and ``(py,y=z)`` fails
as it does (NameError). A syntax error fails with rs274's first line; code
outside that subset (imports, attribute access, loops...) stops with an
error that says ngc2py does not run it. ``(pyrun,...)`` and ``(pyreload)``
do nothing: rs274's only visible effect of them is none (errors are
ignored). The message's later lines (Python's traceback) are not copied.
"""

from __future__ import annotations

import ast
import operator
from typing import Any, Callable, Dict

from runtime.errors import GCodeError

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


def run_py_comment(machine, code: str) -> None:
    """``(py,CODE)``: evaluate CODE as rs274's embedded Python would."""
    failed = GCodeError("run_string(%s): " % code)
    try:
        tree = ast.parse(code)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise failed from None  # ValueError: a NUL byte in the code
    namespace = machine.python_namespace
    try:
        for statement in tree.body:
            _statement(statement, namespace)
    except _Unsupported:
        raise GCodeError(
            "ngc2py does not run embedded Python beyond simple assignments: (py,%s)"
            % code
        ) from None
    except (ArithmeticError, NameError, TypeError, ValueError, OverflowError):
        raise failed from None


def _statement(node: ast.stmt, namespace: dict) -> None:
    if isinstance(node, ast.Pass):
        return
    if isinstance(node, ast.Expr):
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
        raise NameError(node.id)
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
