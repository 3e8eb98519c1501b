"""A generated module's bytecode, compiled without reading its tables.

Most of a CAM program's module is text in a few triple-quoted literals: its
tables of rows and its compressed G-code. Python's tokenizer reads such a
literal a character at a time, so compiling a 100k-move program's module
takes about 45 ms, 3 ms of it for the code. :func:`compile_module` compiles
the module with each large literal's text stood in for by a short marker
string spread over as many lines (every line and column of the code after
it stays where it was), then puts each literal's value, which is its text
as written, in place of its marker among the code's constants. The code
object is equal to what ``compile`` makes of the module (the tests compare
them on every kind of generated program).

Only literals whose value is their text as written are taken: triple
quotes (of a string or of bytes) opening a module-level assignment, no
backslash inside (but the one that may follow the opening quotes, joining
the first line), no quote, carriage return or NUL, the closing quotes on a
line of their own. Equal literals (one constant of the code), a module
whose text holds a marker's, anything else, and a marker not found once as
a whole constant: the module is compiled as it is.

Used where the compile cache writes a new entry (ngc2py/cache.py), whose
import then reads the bytecode: about 30 ms less for a new 100k-move
program's first run or preview; and by :class:`QuickLoader`, where a module
is imported without bytecode (a program read from stdin, a cache that
cannot be written).
"""

from __future__ import annotations

from importlib.machinery import ModuleSpec, SourceFileLoader

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, List

#: Literals shorter than this are left for the tokenizer (a few lines).
LONG = 4096

#: What a marker's text begins with.
_MARKER = "ngc2py stand-in "

#: An assignment opening a literal at the start of a line: its opening.
_OPENINGS = ('"""\n', '"""\\\n', 'b"""\n', 'b"""\\\n')


def compile_module(text: str, filename: str):
    """``compile(text, filename, "exec", dont_inherit=True)``, quicker for a
    module with long literals (see the module's doc)."""
    skeleton, values = _stand_in(text)
    if values:
        try:
            code = compile(skeleton, filename, "exec", dont_inherit=True)
        except (SyntaxError, ValueError):
            code = None  # (the module's own error is compile's to tell)
        placed = None if code is None else _put_back(code, values)
        if placed is not None:
            return placed
    return compile(text, filename, "exec", dont_inherit=True)


class QuickLoader(SourceFileLoader):
    """Python's loader of a source file, compiling it by
    :func:`compile_module` where it finds no bytecode."""

    def source_to_code(self, data, path, *, _optimize=-1):
        from importlib.util import decode_source

        return compile_module(decode_source(data), path)

    def load(self):
        """The module at the loader's path, imported (not put in
        ``sys.modules``): what ``importlib.util``'s ``module_from_spec(
        spec_from_file_location(...))`` and ``exec_module`` do, with
        importlib.machinery's spec: importlib.util's own import (with
        contextlib and importlib's abstract classes) cost a cached run
        1.5 to 4 ms. tests/test_bytecode.py holds the module's attributes
        to importlib.util's."""
        from types import ModuleType

        spec = ModuleSpec(self.name, self, origin=self.path)
        spec.has_location = True  # (so __file__ and __cached__ are set)
        module = ModuleType(self.name)
        module.__spec__, module.__loader__ = spec, self
        module.__package__ = spec.parent
        module.__file__, module.__cached__ = spec.origin, spec.cached
        self.exec_module(module)
        return module


def _stand_in(text: str):
    """``text`` with each long literal's text replaced by a marker on as
    many lines, and ``{the literal's value in that text: its value}``;
    ``(text, {})`` when none is."""
    out: List[str] = []
    values: Dict[object, object] = {}
    if _MARKER in text:  # (a marker must be no other constant's text)
        return text, values
    done = at = 0
    while True:
        opening = _next_opening(text, at)
        if opening is None:
            break
        quotes, head = opening
        body_start = quotes + len(head)
        close = text.find('\n"""\n', body_start - 1)
        if close < 0:
            break
        at = close + 5
        joined = head.endswith("\\\n")  # (its first newline escaped away)
        # its value: the text after the opening quotes (and the join)
        value = text[body_start if joined else body_start - 1 : close + 1]
        if len(value) < LONG or not _as_written(value):
            continue
        if head[0] == "b" and not value.isascii():
            continue  # (compile's error to tell)
        # the marker on the literal's first line, its other lines empty
        stand_in = _MARKER + "%d" % len(values) + "\n" * value.count("\n")
        seen = stand_in if joined else "\n" + stand_in[:-1]
        if head[0] == "b":
            value, seen = value.encode("ascii"), seen.encode("ascii")
        values[seen] = value
        out += (text[done:quotes], head, stand_in if joined else stand_in[:-1])
        done = close + 1
    lengths = [len(value) for value in values.values()]
    if not values or (
        len(set(lengths)) < len(lengths) and len(set(values.values())) < len(values)
    ):
        # (equal literals are one constant of the module's code: left alone)
        return text, {}
    out.append(text[done:])
    return "".join(out), values


def _as_written(value: str) -> bool:
    """Is a literal's value its text as written (no escape, nothing the
    tokenizer changes or refuses)?"""
    return not any(mark in value for mark in ("\\", '"', "\r", "\0"))


def _next_opening(text: str, at: int):
    """The next literal opening a module-level assignment from ``at``:
    (where its quotes are, its opening as written: one of _OPENINGS), or
    None."""
    while True:
        found = text.find('"""', at)
        if found < 0:
            return None
        at = found + 3
        quotes = found - 1 if text[found - 1 : found] == "b" else found
        line_start = text.rfind("\n", 0, quotes) + 1
        name, equals, space = text[line_start:quotes].rpartition(" = ")
        if not equals or space or not name.isidentifier():
            continue
        for head in _OPENINGS:
            if text.startswith(head, quotes):
                return quotes, head


def _put_back(code, values: Dict[str, object]):
    """``code`` with each marker constant replaced by its value, or None
    unless each marker is found once, as a whole constant."""
    found: Dict[str, int] = {}
    placed = _replace(code, values, found)
    if len(found) != len(values) or any(count != 1 for count in found.values()):
        return None
    return placed


def _replace(code, values: Dict[str, object], found: Dict[str, int]):
    constants = list(code.co_consts)
    changed = False
    for k, constant in enumerate(constants):
        if type(constant) in (str, bytes) and constant in values:
            found[constant] = found.get(constant, 0) + 1
            constants[k] = values[constant]
            changed = True
        elif hasattr(constant, "co_consts"):
            inner = _replace(constant, values, found)
            if inner is not constant:
                constants[k] = inner
                changed = True
    return code.replace(co_consts=tuple(constants)) if changed else code
