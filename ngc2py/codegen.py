"""Statement tree -> Python module text, black-stable, with a line map.

Text is emitted directly (libcst and black are far too slow per statement);
black is the oracle in the tests. Statements
that fit in 88 columns are written on one line, which is what black does;
the rare longer one is laid out by black itself.

Safety: nothing from the source reaches the output except through
``repr()`` escaping (strings, floats) or :func:`identifier` (names), and G-code text
in comments is reduced to printable characters, so no input can inject code.

Big CAM files: the main program is split into chunk functions of bounded
size, and runs of constant blocks become data (see ``runtime/fast/rows.py``): a
module-level ``SHAPES`` table of (codes, word letters) and, per run, one
text table with one G-code line per text line (``24 0 1.0 2.0``: line,
shape, values), which compiles as one string constant; see runtime/fast/rows.py
for why, and runtime/fast/printed_rows.py for tables written as the trace prints
their numbers.

Deep nesting: Python allows 20 statically nested blocks per function and
about 100 indentation levels; G-code has no limit. An if or loop that starts
deeper than ``NEST_LIMIT`` is written as a module-level helper function
``nest_N(m)`` (written after the function that calls it, so code generation
recursion stays bounded too). A helper returns None when control falls out
of it; a ``break``/``continue`` of a loop outside it returns ``(kind, loop
number)`` and a subroutine ``return`` returns ``("return", value)``, and the
call site performs that jump or return itself.

Skipping: rs274 reads every line it skips over (an untaken arm, the arms
after a taken one, a loop body when the loop ends or breaks), and a line it
cannot read at all (``structure.TEXT_ERRORS``: too long, bad comments) fails
even then. Where such a line would be skipped, the generated code fails with
its error: after a taken arm, in an ``else`` for an untaken one, and after a
loop. Programs without such lines get none of this.
"""

from __future__ import annotations

import base64
import builtins
import keyword
import math
import re
import zlib

from ngc2py import __version__, assigned, fastlocals, nodes, parser, rowtable
from ngc2py.wrap import split_call
from ngc2py.parser import DEFAULT_AXES
from ngc2py import structure as st
from ngc2py.parser import RowLine
from ngc2py.records import Value
from ngc2py.rowrun import RowRun
from runtime import codes
from runtime.comments import LINE_METHODS
from runtime.errors import GCodeError
from runtime.params import MAX_PARAMETERS, POSITION_PARAMS, Params

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, Iterable, Iterator, List, Optional, Sequence, Tuple, Union

LINE_LENGTH = 88
INDENT = "    "
CHUNK_STATEMENTS = 500  # statements per main chunk function
# Python allows 20 statically nested blocks per function (and ~100
# indentation levels): an if/loop starting deeper than this moves into a
# helper function of its own (see CodeGen.nest).
NEST_LIMIT = 8
#: An if whose arms (more than this many) hold M98 lines that may fail to
#: read: its skips do not read them (CodeGen.s_if).
MOST_READ_ARMS = 8
# Named locals become Python variables (ngc2py.fastlocals) only in functions
# whose ifs and loops nest at most this deep: none of them needs a helper
# (each nesting level indents at most twice).
FAST_LOCALS_DEPTH = NEST_LIMIT // 2
MIN_ROWS = 8  # shortest run of constant blocks kept as data
#: A shorter run of codes alone (``G17``, ``G21``, ``G90``...: a macro's
#: set-up, not CAM data) stays statements, which read better.
MIN_VALUE_ROWS = 64
#: A program with fewer constant blocks than this is no CAM file: only its
#: long runs (MIN_VALUE_ROWS) become tables, the rest reads as statements,
#: as a person would have written them (a table pays off in long files).
MIN_PROGRAM_ROWS = 64
#: What a function binds for its code: numbered parameters (the list), named
#: globals, named locals (CodeGen.bind_stores binds only those it uses).
STORES = {"p": "m.params.values", "g": "m.globals", "v": "m.locals"}
STORES_LINE = "p, g, v = m.params.values, m.globals, m.locals"
#: A use of a store in generated code (``p[1]``, ``g._x``, ``v["a b"]``);
#: text of a string that looks like one only keeps the binding.
STORE_USE = {name: re.compile(r"(?<![\w.])%s[.\[]" % name) for name in STORES}
ROWS_PER_TABLE = 20000  # rows of one table: bounds the memory of running one

BINARY_HELPERS = {
    "/": "div",
    "mod": "mod",
    "**": "power",
    "eq": "eq",
    "ne": "ne",
    "gt": "gt",
    "ge": "ge",
    "lt": "lt",
    "le": "le",
    "and": "and_",
    "or": "or_",
    "xor": "xor",
}
UNARY_HELPERS = {"abs": "abs_", "round": "round_"}  # others keep their name
COMPARISONS = frozenset(("eq", "ne", "gt", "ge", "lt", "le", "and", "or", "xor"))
PYTHON_COMPARISONS = {"gt": ">", "ge": ">=", "lt": "<", "le": "<="}
WORD_KEYWORDS = {"@": "polar_dist", "^": "polar_angle", "$": "dollar"}
AXIS_LETTERS = frozenset("xyzabcuvw")
GCODE_LETTERS = {keyword: letter for letter, keyword in WORD_KEYWORDS.items()}
RESERVED = frozenset(
    keyword.kwlist + dir(builtins) + ["m", "p", "g", "v", "main", "run", "rows"]
)


# --------------------------------------------------------------------------
# Names and literals
# --------------------------------------------------------------------------


def identifier(text: str, prefix: str, taken: set) -> str:
    """A unique Python identifier for ``text``: ``[a-z0-9_]`` only, never a
    keyword or builtin, never one already in ``taken`` (which it joins)."""
    body = re.sub(r"[^a-z0-9_]", "_", text.lower())
    name = prefix + body
    if name in RESERVED or not name.isidentifier():
        name += "_"
    unique, count = name, 2
    while unique in taken:
        unique = "%s_%d" % (name, count)
        count += 1
    taken.add(unique)
    return unique


def number(value: float) -> str:
    """A float literal as black prints it (repr, lower-case exponent)."""
    if math.isnan(value) or math.isinf(value):
        return "float(%s)" % string(repr(value))
    return repr(float(value))


def string(text: str) -> str:
    """A string literal as black writes it: ``ascii()`` escaping (so nothing
    in ``text`` can end the literal, and every character is one column wide,
    which keeps our line-length arithmetic equal to black's), double quotes
    unless that adds escapes."""
    if "'" not in text and '"' not in text:
        return ascii(text).replace("'", '"')  # (a source map's megabytes)
    single = ascii(text)
    if single.startswith('"'):
        return single  # ascii() chose double quotes: text has a '
    body = single[1:-1]
    double = body.replace("\\'", "'").replace('"', '\\"')
    if double.count('\\"') <= body.count("\\'"):
        return '"%s"' % double
    return single


def printable(text: str) -> str:
    """``text`` made safe for a ``#`` comment: tabs as the spaces an editor
    shows for them, other non-printables escaped."""
    if "\t" in text:
        text = text.expandtabs()
    return "".join(c if c.isprintable() else "\\x%02x" % ord(c) for c in text)


def attr_safe(name: str) -> bool:
    """May ``store.name`` be used for the named parameter ``name``?

    The rule belongs to runtime.params (the store's own attributes must not
    be shadowed); without it, item syntax is always correct.
    """
    try:
        from runtime.params import attr_safe as runtime_attr_safe
    except ImportError:
        return False
    return runtime_attr_safe(name)


# --------------------------------------------------------------------------
# Expressions
# --------------------------------------------------------------------------


def _walk_bodies(stmt):
    """The statements inside ``stmt`` (not into definitions)."""
    return st.walk([s for body in st.children(stmt, False) for s in body], False)


def l0_span(stmts: List[st.Stmt]) -> Optional[Tuple[int, int]]:
    """``(i, j)``: ``stmts[i]`` an M98 that may enter a frame without a call
    (``structure.m98_may_strand``), ``stmts[j]`` the first M99 after it (a block, its
    failure, or a Fanuc subroutine's return), with no break or continue
    between (the loop :meth:`CodeGen.m99_loop` writes would catch it)."""
    start = None
    for k, stmt in enumerate(stmts):
        if start is None:
            if isinstance(stmt, st.FanucCall) and st.m98_may_strand(stmt.line):
                start = k
            continue
        word = getattr(stmt, "line", None) and stmt.line.oword
        if (
            isinstance(stmt, (st.Block, st.Fail, st.Return))
            and word
            and word.keyword == "m99"
        ):
            between = stmts[start + 1 : k]
            if any(isinstance(inner, st.Jump) for inner in st.walk(between, False)):
                return None
            return start, k
    return None


class ExprWriter:
    """Renders expressions; records which runtime.ops helpers are used."""

    def __init__(self) -> None:
        self.helpers: set = set()
        #: Locals of the function being written that are Python variables,
        #: and their variables (ngc2py.fastlocals).
        self.fast: Dict[str, str] = {}
        #: Reading a definition's own return values: unset names read 0.
        self.defining = False
        #: Locals the function being written never sets (fastlocals.never_set):
        #: reading past a definition, they read 0.
        self.never_set: frozenset = frozenset()

    def helper(self, name: str) -> str:
        self.helpers.add(name)
        return name

    def expr(self, e: nodes.Expr) -> str:
        method = getattr(self, "_" + type(e).__name__.lower())
        return method(e)

    def condition(self, e: nodes.Expr) -> str:
        """An if/while test: comparison helpers already return 1.0/0.0."""
        if isinstance(e, nodes.Bracket) and not may_overflow(e.inner):
            e = e.inner
        if isinstance(e, nodes.Binary) and e.op in PYTHON_COMPARISONS:
            # GT GE LT LE have no tolerance: Python's operators are exact.
            op = PYTHON_COMPARISONS[e.op]
            return "%s %s %s" % (self.expr(e.left), op, self.expr(e.right))
        if isinstance(e, nodes.Binary) and e.op in COMPARISONS:
            return self.expr(e)
        return "%s(%s)" % (self.helper("truth"), self.expr(e))

    def _num(self, e: nodes.Num) -> str:
        return number(e.value)

    def _numparam(self, e: nodes.NumParam) -> str:
        index = e.index
        if isinstance(index, nodes.Num) and plain_read_index(index.value):
            return "p[%d]" % int(index.value)
        # rs274's checks: rounding to an index, its range, the position
        # parameters (held apart, unreadable under cutter compensation)
        return "m.params[%s]" % self.index(index)

    def index(self, e: nodes.Expr) -> str:
        """A parameter number: a whole constant as an integer (``5420``)."""
        if (
            isinstance(e, nodes.Num)
            and float(e.value).is_integer()
            and abs(e.value) < 2**53
        ):
            return "%d" % int(e.value)
        return self.expr(e)

    def _namedparam(self, e: nodes.NamedParam) -> str:
        if e.name in self.fast:
            return self.fast[e.name]
        store = "g" if e.is_global else "v"
        if self.defining:
            if e.name in self.never_set:
                return "0.0"  # the store never holds it
            return "%s.read_or_zero(%s)" % (store, string(e.name))
        if attr_safe(e.name):
            return "%s.%s" % (store, e.name)
        return "%s[%s]" % (store, string(e.name))

    def _exists(self, e: nodes.Exists) -> str:
        store = "g" if e.name.startswith("_") else "v"
        return "%s.exists(%s)" % (store, string(e.name))

    def _atan2(self, e: nodes.Atan2) -> str:
        return "%s(%s, %s)" % (self.helper("atan2"), self.expr(e.y), self.expr(e.x))

    def _bracket(self, e: nodes.Bracket) -> str:
        """rs274 checks a bracketed value when it reads the closing ``]``;
        only arithmetic can make a new inf/nan there (parameter reads and
        functions are checked by the runtime)."""
        if may_overflow(e.inner):
            return "%s(%s)" % (self.helper("finite"), self.expr(e.inner))
        return self.expr(e.inner)

    def _unary(self, e: nodes.Unary) -> str:
        if e.op == "pos":
            return self.expr(e.arg)
        if e.op == "neg":
            return "-" + self._operand(e.arg, unary=True)
        name = self.helper(UNARY_HELPERS.get(e.op, e.op))
        return "%s(%s)" % (name, self.expr(e.arg))

    def _binary(self, e: nodes.Binary) -> str:
        if e.op in ("+", "-", "*"):
            left = self._operand(e.left, outer=e.op)
            right = self._operand(e.right, outer=e.op, right=True)
            return "%s %s %s" % (left, e.op, right)
        name = self.helper(BINARY_HELPERS[e.op])
        return "%s(%s, %s)" % (name, self.expr(e.left), self.expr(e.right))

    def _operand(
        self, e: nodes.Expr, unary: bool = False, outer: str = "", right: bool = False
    ) -> str:
        """An operand of ``+ - *`` (``outer``; ``right``: its right operand)
        or unary minus: inner operators (and, for unary minus, negative
        literals) get parentheses where Python would group otherwise than
        the parser did (``a * b + c``, ``a - b + c``, ``a - (b + c)``,
        ``a * (b * c)``: the same operations in the same order)."""
        text = self.expr(e)
        if isinstance(e, nodes.Bracket) and not may_overflow(e.inner):
            e = e.inner  # written bare: group by what is inside
        if isinstance(e, nodes.Binary) and e.op in ("+", "-", "*"):
            tighter = e.op == "*" and outer in ("+", "-")
            same_level = (e.op == "*") == (outer == "*")
            if outer and (tighter or (same_level and not right)):
                return text
            return "(%s)" % text
        if isinstance(e, nodes.Unary) and e.op == "neg":
            return "(%s)" % text
        if unary and text.startswith("-"):
            return "(%s)" % text
        return text


def is_constant(e: nodes.Expr) -> bool:
    return isinstance(e, nodes.Num)


ARITHMETIC = frozenset(("+", "-", "*", "/", "mod", "**"))

#: Functions that fail for some arguments (domain) or overflow.
_PARTIAL = frozenset(("sqrt", "ln", "acos", "asin", "exp"))


def may_fail(e: nodes.Expr) -> bool:
    """Can evaluating ``e`` raise (an unset name, a bad index, a division by
    zero, an argument out of a function's domain)?"""
    pending = [e]
    while pending:
        e = pending.pop()
        if isinstance(e, nodes.NamedParam):
            return True
        if isinstance(e, nodes.NumParam):
            if not is_constant(e.index):
                return True
        elif isinstance(e, nodes.Binary):
            if e.op in ("/", "mod", "**"):
                return True
            pending += [e.left, e.right]
        elif isinstance(e, nodes.Unary):
            if e.op in _PARTIAL:
                return True
            pending.append(e.arg)
        elif isinstance(e, nodes.Atan2):
            pending += [e.y, e.x]
        elif isinstance(e, nodes.Bracket):
            pending.append(e.inner)
    return False


def _m98_reads_between(
    bodies: List[List[st.Stmt]], after: int, before: Optional[int]
) -> Iterator[nodes.Line]:
    """The M98 lines of ``bodies`` after line ``after`` and before line
    ``before`` whose words may fail to read (see CodeGen.skipped_reads)."""
    for body in bodies:
        for stmt in st.walk(body):
            if type(stmt) is not st.FanucCall:
                continue
            line = stmt.line
            if line.number <= after:
                continue
            if before is not None and line.number >= before:
                return
            if _m98_values(line):
                yield line


def _m98_values(line: nodes.Line) -> List[Tuple[nodes.Expr, bool]]:
    """What reading an M98 line may fail on (interp_read.cc read_o): the
    values that may fail, in order, then a computed P, which must be near
    an integer (True: converted by ``to_integer``)."""
    values = [(item.value, False) for item in line.items if may_fail(item.value)]
    for item in line.items:
        if isinstance(item, nodes.Word) and item.letter == "p":
            if not is_constant(item.value):
                values.append((item.value, True))
    return values


def _has_m98_reads(bodies: List[List[st.Stmt]]) -> bool:
    """Is there an M98 line in ``bodies`` whose reading may fail?"""
    return any(
        type(stmt) is st.FanucCall and _m98_values(stmt.line)
        for body in bodies
        for stmt in st.walk(body)
    )


def _stop_line(stop) -> Optional[int]:
    """The line number where a skip stops (a line, or the statements of a
    line reusing the label: its first line), or None."""
    if stop is None:
        return None
    if isinstance(stop, list):
        return _first_line(stop)
    return stop.number


def may_overflow(e: nodes.Expr) -> bool:
    """Can ``e`` make an inf/nan that nothing has checked yet?"""
    return value_bound(e) is None


#: Past this, a bound proves nothing: a sum or product may overflow.
_LARGEST_BOUND = 1e300
#: Below half the spacing of doubles at the largest one (2**970): added to
#: any finite double, it rounds to a finite one.
_NEGLIGIBLE_TERM = 2.0**960
#: Results of the checked functions: at most this in magnitude.
_FUNCTION_BOUNDS = {"sin": 1.0, "cos": 1.0, "acos": 180.0, "asin": 180.0, "atan": 180.0}


def value_bound(e: nodes.Expr) -> Optional[float]:
    """A bound on ``|e|`` when ``e`` is certainly finite; ``math.inf`` when
    it is finite but unbounded (a parameter, a checked function); None when
    arithmetic may make an inf or nan that only a ``finite`` check catches.

    ``[30 * COS[#<a>] + [#<i> MOD 3]]`` is below 33 whatever the
    parameters hold, so it needs no check; ``[#<i> * 0.3]`` does.
    """
    if isinstance(e, nodes.Num):
        return abs(e.value) if abs(e.value) <= _LARGEST_BOUND else None
    if isinstance(e, nodes.Bracket):
        inner = value_bound(e.inner)
        return math.inf if inner is None else inner  # else checked at its ]
    if isinstance(e, nodes.Unary):
        if e.op in ("neg", "pos"):
            return value_bound(e.arg)
        if e.op in _FUNCTION_BOUNDS:
            return _FUNCTION_BOUNDS[e.op]
        if e.op in ("abs", "fix", "fup", "round"):
            inner = value_bound(e.arg)
            return math.inf if inner is None else inner + 1.0
        return math.inf  # the helper checks its result
    if isinstance(e, nodes.Atan2):
        return 180.0
    if isinstance(e, nodes.Binary):
        if e.op not in ARITHMETIC:
            return 1.0  # comparisons and logic give 0.0 or 1.0
        left, right = value_bound(e.left), value_bound(e.right)
        if e.op == "mod":
            if left is None or not isinstance(e.right, nodes.Num) or not e.right.value:
                return None
            return abs(e.right.value)
        if left is None or right is None:
            return None
        if e.op in ("+", "-"):
            total = left + right
            if total <= _LARGEST_BOUND:
                return total
            # A finite value plus a small one cannot round past the largest
            # double: ``[#<i> + 1]`` needs no check.
            return math.inf if min(left, right) <= _NEGLIGIBLE_TERM else None
        if e.op == "*":
            product = left * right
            if product <= _LARGEST_BOUND:
                return product
            # Nor can a finite value times at most 1 in size: ``[#<i> * 0.3]``.
            return math.inf if min(left, right) <= 1.0 else None
        return None
    return math.inf  # parameter reads, EXISTS: checked where they are read


# --------------------------------------------------------------------------
# The line map
# --------------------------------------------------------------------------


#: The G-code line of a module line that is none (runtime.errors.SourceMap).
OWN_LINE = -1


class LineMap:
    """(python line, file index, G-code line) entries, encoded compactly.

    The encoding is ``;``-separated ``py,file,line[,count]`` runs: ``count``
    consecutive Python lines map to consecutive G-code lines. A G-code line
    of 0 means "read the line from the frame's ``line`` variable" (the loop
    over constant rows); -1 (``OWN_LINE``), a line of no G-code line (main
    calling its chunks: no O-call, which a traceback would name).
    """

    def __init__(self) -> None:
        self.entries: List[Tuple[int, int, int]] = []

    def add(self, py: int, file: int, line: int) -> None:
        self.entries.append((py, file, line))

    def encode(self) -> str:
        runs: List[List[int]] = []
        for py, file, line in self.entries:
            if runs:
                last = runs[-1]
                span = last[3]
                if (
                    last[1] == file
                    and py == last[0] + span
                    and line == last[2] + span
                    and line
                ):
                    last[3] += 1
                    continue
            runs.append([py, file, line, 1])
        return ";".join(
            ",".join(str(x) for x in (run if run[3] > 1 else run[:3])) for run in runs
        )


# --------------------------------------------------------------------------
# The module writer
# --------------------------------------------------------------------------


class ModuleWriter:
    """Accumulates output lines, indentation, and the line map."""

    def __init__(self, files: Sequence[str]):
        self.out: List[str] = []
        self.depth = 0
        self.files = list(files)
        self.file_index = 0
        self.map = LineMap()
        self.texts: List[Dict[int, str]] = [{} for _ in self.files]
        #: per file, (first line, the texts of consecutive lines joined by
        #: newlines): a row run's texts in one piece
        self.blocks: List[List[Tuple[int, str]]] = [[] for _ in self.files]

    def raw(self, text: str = "") -> None:
        # one entry a line: the source map counts entries as module lines
        self.out.extend(text.split("\n"))

    def comment(self, line: nodes.Line) -> None:
        """``# 12: G1 X[#<i>*10]``: the G-code line, as a comment."""
        self.out.append(
            "%s# %d: %s" % (INDENT * self.depth, line.number, printable(line.text))
        )

    def stmt(self, code: str, line: Optional[nodes.Line] = None) -> None:
        """One statement at the current depth, mapped to ``line``."""
        indent = INDENT * self.depth
        text = indent + code
        lines = [text] if len(text) <= LINE_LENGTH else fit(code, len(indent))
        if line is not None:
            self.texts[self.file_index][line.number] = line.text
            first = len(self.out) + 1
            for i in range(len(lines)):
                self.map.add(first + i, self.file_index, line.number)
        self.out.extend(lines)

    def row_loop(self, code: str) -> None:
        """A statement running data rows: its G-code line is the failing
        row's, which ``runtime.fast.rows.run_rows`` attaches to the error."""
        self.map.add(len(self.out) + 1, self.file_index, 0)
        self.out.append(INDENT * self.depth + code)

    def text(self) -> str:
        self.out.append("")  # the final newline, without copying the text again
        try:
            return "\n".join(self.out)
        finally:
            self.out.pop()


def fit(code: str, indent: int) -> List[str]:
    """Black's layout of one over-long statement at ``indent`` columns.

    Calls, nearly all of them, are laid out by ``ngc2py.wrap`` (black's
    rule, without black's cost); anything else by black itself. A compound
    statement's header (``elif x:``) cannot be formatted alone: it is given
    a ``pass`` body (and ``elif`` is written as ``if``, two columns
    narrower) which is dropped again afterwards.
    """
    lines = split_call(code, indent)
    if lines is not None:
        return lines
    import black

    header = code.endswith(":")
    elif_ = code.startswith("elif ")
    source = "if " + code[5:] if elif_ else code
    width = LINE_LENGTH - indent - (2 if elif_ else 0)
    mode = black.Mode(line_length=max(width, 1))
    formatted = black.format_str(source + ("\n    pass" if header else ""), mode=mode)
    lines = formatted.rstrip("\n").split("\n")
    if header:
        lines.pop()
    if elif_:
        lines[0] = "el" + lines[0]
    return [" " * indent + part for part in lines]


class Coll:
    """A bracketed, comma-separated display (call, tuple, dict) of literals,
    laid out the way black lays it out, without running black:

    1. on one line if it fits;
    2. else the items on one indented line between the brackets, if that fits
       and the display has no magic trailing comma;
    3. else one item per line, each laid out recursively, with a trailing comma.
    """

    def __init__(self, open_: str, items: Sequence, close: str):
        self.open = open_
        self.items = list(items)
        self.close = close

    def one_tuple(self) -> bool:
        """A one-element tuple: its comma is no magic trailing comma."""
        return len(self.items) == 1 and self.close == ")" and self.open == "("

    def flat(self) -> str:
        inner = ", ".join(flat(item) for item in self.items)
        if self.one_tuple():
            inner += ","
        return self.open + inner + self.close

    def width(self) -> int:
        """``len(self.flat())``, without making it (a source map's texts
        can be tens of megabytes)."""
        items = sum(width(item) for item in self.items)
        commas = 2 * max(len(self.items) - 1, 0) + self.one_tuple()
        return len(self.open) + items + commas + len(self.close)

    def magic(self) -> bool:
        return any(isinstance(i, Coll) and i.magic() for i in self.items)

    def layout(self, indent: int, suffix: str = "") -> List[str]:
        pad = " " * indent
        size = self.width()
        if indent + size + len(suffix) <= LINE_LENGTH:
            return [pad + self.flat() + suffix]
        body_size = size - len(self.open) - len(self.close)
        if indent + 4 + body_size <= LINE_LENGTH and not self.magic():
            body = self.flat()[len(self.open) : -len(self.close)]
            if not body.endswith(","):
                inner = " " * (indent + 4) + body
                return [pad + self.open, inner, pad + self.close + suffix]
        lines = [pad + self.open]
        for item in self.items:
            lines.extend(layout(item, indent + 4, ","))
        lines.append(pad + self.close + suffix)
        return lines


def flat(item) -> str:
    return item.flat() if isinstance(item, Coll) else item


def width(item) -> int:
    return item.width() if isinstance(item, Coll) else len(item)


def layout(item, indent: int, suffix: str = "") -> List[str]:
    if isinstance(item, Coll):
        return item.layout(indent, suffix)
    return [" " * indent + item + suffix]


# --------------------------------------------------------------------------
# Statements
# --------------------------------------------------------------------------


class CodeGen:
    """Turns a :class:`structure.Program` into module text."""

    def __init__(
        self,
        program: st.Program,
        source_name: str,
        opening: Optional[nodes.Line] = None,
        pack: bool = True,
    ):
        self.program = program
        #: a large file's G-code text goes in compressed (source_map_lines)
        self.pack = pack
        #: names certainly set before each line (ngc2py.assigned)
        self.settled = assigned.settled_names(program)
        self.source_name = source_name
        self.opening = opening
        self.demarcated = opening is not None
        files = [program.file] + [
            s.line.file or program.file for s in program.externals
        ]
        self.files = list(dict.fromkeys(files))
        self.w = ModuleWriter(self.files)
        self.x = ExprWriter()
        self.codes: set = set()  # runtime.codes constants used
        self.break_flag = stale_break_flag(program)
        self.continue_flag = stale_continue_flag(program)
        self.if_flag = executed_if_flag(program)
        #: can a subroutine leave rs274's executed_if flag clear?
        self.calls_clear = self.if_flag and any(
            clears_flag(stmt)
            for sub in list(program.subs) + list(program.externals)
            for stmt in st.walk(sub.body)
        )
        self.code_functions: set = set()  # runtime.codes functions used
        self.names: set = set()
        self.shapes: Dict[Shape, int] = {}  # row shape -> index in SHAPES
        self.row_tables: List[List[str]] = []  # ROWS_n = (...) definitions
        self.temp = 0
        self.loops: List[st.Loop] = []  # enclosing loops, innermost last
        # self.loops[:self.frame] enclose the Python function being written
        # from outside it (it is a nesting helper): jumps to them return.
        self.frame = 0
        self.in_helper = False
        self.helpers: List[Helper] = []  # nesting helpers not written yet
        self.helper_count = 0
        # Does any line fail to be read at all? (Then skipping fails too.)
        bodies = [program.body] + [sub.body for sub in program.externals]
        self.text_errors = st.first_text_error(bodies) is not None
        # Any M98 line whose words may fail to read? rs274 reads them even
        # skipping over the line (skipped_reads); most programs have none.
        self.m98_reads = _has_m98_reads(bodies) or any(
            _m98_values(line) for line in self._file_m98_lines()
        )
        # any M98 that may never return (see strands): most programs have none
        #: Enough constant blocks for short runs to become tables too.
        self.cam_sized = constant_rows(bodies) >= MIN_PROGRAM_ROWS
        self.any_strand = any(
            isinstance(stmt, st.FanucCall) and st.m98_may_strand(stmt.line)
            for body in bodies
            for stmt in st.walk(body)
        )
        self.loop_numbers: Dict[int, int] = {}
        self.flags: Dict[int, str] = {}
        #: ifs and loops holding an M98 that may not return (strands)
        self.stranding: set = set()
        #: Writing where a skip lands (skipped_to): the loops it enters;
        #: a jump to any other loop names a label rs274 never recorded.
        self.landing_loops: Optional[set] = None
        #: loops a break leaves while code goes back into them -> the back
        #: loop it continues (structure.DoEnd.leaves)
        self.resumed: Dict[int, st.Loop] = {}

    # -- entry point ------------------------------------------------------

    def module(self) -> str:
        subs = list(self.program.subs) + list(self.program.externals)
        for sub in subs:
            sub.fn = identifier(sub.name, "o_", self.names)
        body = ModuleWriter(self.files)
        self.w = body
        if self.opening is not None:
            # M2 in a file that opens with % but never closes it makes rs274
            # add a comment; the machine finds the opening % in these texts.
            body.texts[0][self.opening.number] = self.opening.text
        for sub in subs:
            self.function(sub)
        self.main()
        return self.assemble(body)

    def assemble(self, body: ModuleWriter) -> str:
        """Header (docstring, imports) + body + source map + entry points."""
        head = [
            '"""%s, compiled by ngc2py %s. Edit the .ngc, not this file."""'
            % (safe_doc(self.source_name), __version__),
            "",
        ]
        head.append("from runtime import Machine, SourceMap, run_cli, start")
        if self.codes or self.code_functions:
            names = sorted(self.codes, key=code_order) + sorted(self.code_functions)
            head.extend(import_lines("runtime.codes", names))
        if self.x.helpers:
            head.extend(import_lines("runtime.ops", sorted(self.x.helpers)))
        if self.row_tables:
            head.append("from runtime.fast import run_rows")
        shift = len(head)
        final = ModuleWriter(self.files)
        final.out = head + body.out
        final.map.entries = [(py + shift, f, g) for py, f, g in body.map.entries]
        final.texts = body.texts
        final.blocks = body.blocks
        if self.row_tables:
            final.out.extend(shapes_table(self.shapes))
        for table in self.row_tables:
            final.out.extend(table)
        final.raw("")
        final.raw("")
        opening = self.opening_error(final)
        map_lines = source_map_lines(
            final,
            self.sub_table(),
            self.end_of_main(),
            opening,
            self.unskippable(final),
            self.program.block_delete,
            self.pack,
        )
        for line in map_lines:
            final.raw(line)
        final.raw("")
        final.raw("")
        final.raw("def run(canon=None, **options):")
        final.raw(
            '    """Run the program against ``canon`` (default: the rs274 trace)."""'
        )
        final.raw("    return start(Machine(canon, source=__ngc__, **options), main)")
        final.raw("")
        final.raw("")
        final.raw('if __name__ == "__main__":')
        final.raw("    raise SystemExit(run_cli(main, __ngc__))")
        return final.text()

    def opening_error(self, w: ModuleWriter) -> Optional[str]:
        """``(message, line)`` for the source map when rs274 fails opening
        the file (see ``structure.opening_error``); the line's text is kept
        for the report."""
        if self.program.open_error is None:
            return None
        message, line = self.program.open_error
        if line is None:
            return "(%s, 0)" % string(message)
        w.texts[0][line.number] = line.text
        return "(%s, %d)" % (string(message), line.number)

    def unskippable(self, w: ModuleWriter) -> Optional[Coll]:
        """``{line: message}`` for the main file's lines rs274 fails on even
        while it only skips over them (``structure.skip_error``): reading
        ahead for a sub not defined yet stops there. None when there are
        none. Their texts go into the source map for the report."""
        pairs = []
        for stmt in st.walk(self.program.body):
            line = getattr(stmt, "line", None)
            if (
                isinstance(stmt, st.Block)
                and type(line) is nodes.Line
                and st.skip_error(line)
                and (line.file or self.program.file) == self.program.file
            ):
                w.texts[0][line.number] = line.text
                pairs.append("%d: %s" % (line.number, string(line.error or "")))
        return Coll("unskippable={", pairs, "}") if pairs else None

    def sub_table(self) -> Coll:
        """``{"name": fn}`` for the main file's subroutines (for seeking);
        Fanuc-style ones as ``"O<number>"`` (an o-call never finds them).
        Reading ahead stops at the first definition of a name, so that one
        is kept when a name is defined twice."""
        first = {}
        for sub in self.program.subs:
            first.setdefault("O" + sub.name if sub.fanuc else sub.name, sub.fn)
        pairs = ["%s: %s" % (string(name), fn) for name, fn in first.items()]
        return Coll("{", pairs, "}")

    def end_of_main(self) -> Tuple[int, bool]:
        """(last line read, is it the closing %) of the main file."""
        # (the closing % may sit in a construct left open before it)
        walked = st.walk(self.program.body, False)
        closed = [s for s in walked if isinstance(s, st.Finish)]
        if closed:
            return closed[0].line.number, True
        last = self.last_line()
        return (last.number if last else 0), False

    # -- functions --------------------------------------------------------

    def function(self, sub: st.Sub) -> None:
        self.w.file_index = self.files.index(sub.line.file or self.program.file)
        end = sub.end.number if sub.end else sub.line.number
        self.w.raw("")
        self.w.raw("")
        for text in def_header(sub.fn, " -> None"):
            self.w.raw(text)
        self.w.depth = 1
        form = "O%s, Fanuc style" if sub.fanuc else "o<%s> sub"
        word = sub.line.oword
        if sub.fanuc or word is not None and word.keyword == "sub":
            doc = "%s (lines %d-%d)" % (form % safe_doc(sub.name), sub.line.number, end)
        else:
            # rs274 fails seeking the definition for a call (SeekFail, Fail)
            doc = "o<%s> call: where seeking its sub line fails" % safe_doc(sub.name)
        self.w.raw('%s"""%s"""' % (INDENT, doc))
        stores = self.stores()
        body = sub.body
        if (
            body
            and isinstance(body[-1], st.Return)
            and body[-1].value is None
            and not self.any_strand  # (see m99_loop and s_return)
        ):
            body = body[:-1]  # falling off the end is the plain endsub
        self.x.fast = self.fast_locals(body)
        self.x.never_set = fastlocals.never_set(body)
        self.block(body)
        self.x.fast, self.x.never_set = {}, frozenset()
        self.bind_stores(stores)
        self.w.depth = 0
        self.write_helpers()
        self.w.file_index = 0

    def main(self) -> None:
        body = list(self.program.body)
        if not any(isinstance(s, st.Finish) for s in body):
            last = self.program.last or self.last_line()
            if last is not None:
                body.append(st.EndOfFile(last))
        chunks = self.chunked(body)
        names = []
        for i, chunk in enumerate(chunks):
            name = "main" if len(chunks) == 1 else "main_%d" % (i + 1)
            names.append(name)
            self.w.raw("")
            self.w.raw("")
            self.w.raw("def %s(m: Machine) -> None:" % name)
            self.w.depth = 1
            if len(chunks) == 1:
                self.w.raw('%s"""The main program."""' % INDENT)
            stores = self.stores()
            if i == 0 and self.break_flag:
                self.w.raw(
                    INDENT + "m.doing_break = False  # set by a while-loop break"
                )
            if i == 0 and self.continue_flag:
                self.w.raw(
                    INDENT + "m.doing_continue = False  # set by a do-loop continue"
                )
            if len(chunks) == 1:  # chunks would share the variables
                self.x.fast = self.fast_locals(chunk)
                self.x.never_set = fastlocals.never_set(chunk)
            self.block(chunk)
            self.x.fast, self.x.never_set = {}, frozenset()
            self.bind_stores(stores)
            self.w.depth = 0
            self.write_helpers()
        if len(chunks) > 1:
            self.w.raw("")
            self.w.raw("")
            self.w.raw("def main(m: Machine) -> None:")
            self.w.raw('%s"""The main program, in chunks of bounded size."""' % INDENT)
            for name in names:
                self.w.map.add(len(self.w.out) + 1, self.w.file_index, OWN_LINE)
                self.w.raw("%s%s(m)" % (INDENT, name))

    def stores(self) -> int:
        """A function's first statement binds the stores its code uses
        (``p = m.params.values``): this places it (:meth:`bind_stores`
        writes it once the code is written)."""
        self.w.raw(INDENT + STORES_LINE)
        return len(self.w.out) - 1

    def bind_stores(self, at: int) -> None:
        """``p, v = m.params.values, m.locals``: the stores the function's
        code (from line ``at`` on) uses, or no line at all."""
        code = "\n".join(self.w.out[at + 1 :])
        used = [name for name in STORES if STORE_USE[name].search(code)]
        if used:
            self.w.out[at] = "%s%s = %s" % (
                INDENT,
                ", ".join(used),
                ", ".join(STORES[name] for name in used),
            )
            return
        del self.w.out[at]
        entries = self.w.map.entries
        for k in range(len(entries) - 1, -1, -1):
            py, file, line = entries[k]
            if py <= at + 1:
                break
            entries[k] = (py - 1, file, line)

    def last_line(self) -> Optional[nodes.Line]:
        for stmt in reversed(list(st.walk(self.program.body))):
            line = stmt_line(stmt)
            if line is not None:
                return line
        return None

    @staticmethod
    def chunked(body: List[st.Stmt]) -> List[List[st.Stmt]]:
        """Split the main program into functions of bounded size; a run of
        data rows weighs one statement per table it fills."""
        chunks: List[List[st.Stmt]] = [[]]
        weight = rows = 0
        for stmt in body:
            run = stmt.line if type(stmt) is st.Block else None
            if type(run) is RowRun:
                # row by row as below, a row run cut where a chunk ends
                count = run.count
                i = start = 0
                while i < count:
                    if rows % ROWS_PER_TABLE:
                        step = min(count - i, ROWS_PER_TABLE - rows % ROWS_PER_TABLE)
                        rows += step
                        i += step
                        continue
                    weight += 1
                    rows += 1
                    if weight > CHUNK_STATEMENTS:
                        if i > start:
                            head, run = run.split(i - start)
                            chunks[-1].append(st.Block(head))
                        chunks.append([])
                        weight = rows = 1
                        start = i
                    i += 1
                chunks[-1].append(stmt if start == 0 else st.Block(run))
                continue
            if constant_row(stmt) is None:
                weight += 1
                rows = 0
            else:
                weight += rows % ROWS_PER_TABLE == 0
                rows += 1
            if weight > CHUNK_STATEMENTS:
                chunks.append([])
                weight = 1
                rows = rows and 1
            chunks[-1].append(stmt)
        return chunks

    # -- statement lists --------------------------------------------------

    def block(self, stmts: List[st.Stmt]) -> None:
        """A statement list; runs of constant blocks become data rows."""
        if not stmts:
            self.w.raw(INDENT * self.w.depth + "pass")
            return
        if self.if_flag:
            stmts = st.flat_arms(stmts)
        if not self.any_strand:
            # a sub line run in a call does nothing (see s_subline)
            stmts = [stmt for stmt in stmts if type(stmt) is not st.SubLine]
            if not stmts:
                self.w.raw(INDENT * self.w.depth + "pass")
                return
        span = l0_span(stmts) if self.any_strand else None
        if span is not None:
            self.m99_loop(stmts, *span)
            return
        run: List = []  # row runs and (line, row) pairs
        for stmt in stmts:
            if type(stmt) is st.Block and type(stmt.line) is RowRun:
                run.append(stmt.line)
                continue
            row = constant_row(stmt)
            if row is not None:
                run.append((stmt.line, row))
                continue
            self.flush(run)
            run = []
            self.statement(stmt)
        self.flush(run)

    def m99_loop(self, stmts: List[st.Stmt], i: int, j: int) -> None:
        """``stmts[i]`` is an M98 that may enter a frame without a call (L0)
        and ``stmts[j]`` an M99: run in that frame, the M99 leaves it and
        rs274 goes back to the line after the M98, one call level up."""
        self.block(stmts[: i + 1])
        self.w.stmt("while True:", stmts[i].line)
        self.w.depth += 1
        self.block(stmts[i + 1 : j])
        self.w.stmt("if not m.m99_back(%d):" % stmts[j].line.number, stmts[j].line)
        self.w.raw(INDENT * (self.w.depth + 1) + "break")
        self.w.depth -= 1
        self.block(stmts[j:])

    def flush(self, run: List) -> None:
        """Emit a run of constant blocks (row runs and (line, row) pairs):
        as statements when short, else as data tables executed by
        ``runtime.fast.rows.run_rows``."""
        total = sum(item.count if type(item) is RowRun else 1 for item in run)
        short = total < MIN_VALUE_ROWS
        if total < MIN_ROWS or short and not (self.cam_sized and row_values(run)):
            for item in run:
                for line in item.lines() if type(item) is RowRun else [item[0]]:
                    self.line_block(line.full() if isinstance(line, RowLine) else line)
            return
        for part in tables(run):
            self.table(part)

    def table(self, part: List) -> None:
        """One ``ROWS_n`` table of at most ROWS_PER_TABLE rows."""
        name = "ROWS_%d" % (len(self.row_tables) + 1)
        pieces: List = []  # row runs, and lists of consecutive pairs
        for item in part:
            if type(item) is RowRun:
                pieces.append(item)
            elif pieces and type(pieces[-1]) is list:
                pieces[-1].append(item)
            else:
                pieces.append([item])
        runs = [p for p in pieces if type(p) is RowRun]
        texts: Dict[int, bytes] = {}  # a run's cells (rowtable.cells), once made
        present = {id(run): list(dict.fromkeys(run.kinds)) for run in runs}
        # (shape indexes given in the order the rows below are written, piece
        # by piece: a run's rows made in one pass need theirs first)
        indexes: Dict[int, Dict[int, int]] = {}

        def index_of(run: RowRun) -> Dict[int, int]:
            if id(run) not in indexes:
                shapes = run.lane.kind_shapes
                kinds = present[id(run)]
                indexes[id(run)] = {kind: self.shape(shapes[kind]) for kind in kinds}
            return indexes[id(run)]

        values: List = []
        for piece in pieces:
            if type(piece) is RowRun:
                quick = rowtable.quick_rows(piece, index_of(piece))
                if quick is not None:
                    values.append(quick)
                    continue
                texts[id(piece)] = rowtable.cells(piece.data)
                facts = rowtable.kinds(piece, present[id(piece)])
                values.append(rowtable.printed(piece, texts[id(piece)], facts))
            else:
                for _, (shape, _) in piece:
                    self.shape(shape)
                values.append(as_printed(piece))
            if values[-1] is None:
                break
        printed = values[-1] is not None
        file = self.w.file_index
        lines: List[str] = []
        for k, piece in enumerate(pieces):
            if type(piece) is RowRun:
                index = index_of(piece)
                if printed and type(values[k]) is str:
                    lines.append(values[k])  # (rowtable.quick_rows)
                else:
                    if printed:
                        cells, numbers = values[k]
                    else:
                        if id(piece) not in texts:
                            texts[id(piece)] = rowtable.cells(piece.data)
                        cells, numbers = rowtable.written(texts[id(piece)]), None
                    lines.append(rowtable.rows(piece, index, cells, numbers))
                self.w.blocks[file].append((piece.number, piece.text()))
                continue
            printed_piece = values[k] if printed else [None] * len(piece)
            for (line, (shape, cells)), cells_printed in zip(piece, printed_piece):
                cells = cells_printed if printed else cells
                head = "%d %d" % (line.number, self.shape(shape))
                lines.append(head + " " + cells if cells else head)
                self.w.texts[file][line.number] = line.text
        self.row_tables.append(row_table(name, lines, printed))
        if printed:
            self.w.row_loop("run_rows(m, SHAPES, %s, as_printed=True)" % name)
        else:
            self.w.row_loop("run_rows(m, SHAPES, %s)" % name)

    def shape(self, shape: Shape) -> int:
        """The index of ``shape`` in the module's SHAPES table."""
        if shape not in self.shapes:
            self.shapes[shape] = len(self.shapes)
            self.codes.update(code_name(code) for code in shape[0])
        return self.shapes[shape]

    # -- single statements ------------------------------------------------

    def statement(self, stmt: st.Stmt) -> None:
        if isinstance(stmt, (st.If, st.Loop)) and self.w.depth > NEST_LIMIT:
            self.nest(stmt)
            return
        getattr(self, "s_" + type(stmt).__name__.lower())(stmt)

    # -- nesting helpers --------------------------------------------------

    def nest(self, stmt: st.Stmt) -> None:
        """Move ``stmt`` (an if or loop nested too deep) into a helper
        function written later, and call it here.

        A helper returns None when control falls out of it; a ``break`` or
        ``continue`` of a loop outside it returns ``(kind, loop number)``
        and a subroutine ``return`` returns ``("return", value)``; the call
        site then does the jump or return itself.
        """
        if self.x.fast:  # fastlocals.fast_locals chose a too deep function
            raise AssertionError("a nesting helper cannot see Python variables")
        self.helper_count += 1
        name = "nest_%d" % self.helper_count
        self.helpers.append(Helper(name, stmt, list(self.loops), self.w.file_index))
        jumps, returns = outward_exits(stmt, self.continue_flag)
        if not jumps and not returns:
            self.w.stmt("%s(m)" % name, opening_line(stmt))
            return
        self.w.stmt("jump = %s(m)" % name, opening_line(stmt))
        for kind, target in jumps:
            self.w.raw(
                "%sif jump == (%s, %d):"
                % (self.indent(), string(kind), self.loop_number(target))
            )
            self.w.depth += 1
            self.jump_to(kind, target, opening_line(stmt))
            self.w.depth -= 1
        if returns:
            self.w.raw("%sif jump is not None:" % self.indent())
            self.w.raw(
                "%s    return %s"
                % (self.indent(), "jump" if self.in_helper else "jump[1]")
            )

    def write_helpers(self) -> None:
        """Write the nesting helpers the last function asked for (and those
        they ask for in turn), each at module level."""
        while self.helpers:
            helper = self.helpers.pop(0)
            self.w.file_index = helper.file_index
            self.loops, self.frame, self.in_helper = (
                helper.loops,
                len(helper.loops),
                True,
            )
            first = opening_line(helper.stmt).number
            last = stmt_line(helper.stmt).number
            self.w.raw("")
            self.w.raw("")
            self.w.raw("def %s(m: Machine):" % helper.name)
            self.w.raw(
                '%s"""Lines %d-%d, nested too deep for one function."""'
                % (INDENT, first, last)
            )
            self.w.depth = 1
            stores = self.stores()
            self.statement(helper.stmt)
            self.bind_stores(stores)
            self.w.depth = 0
        self.loops, self.frame, self.in_helper = [], 0, False

    def indent(self) -> str:
        return INDENT * self.w.depth

    def loop_number(self, loop: st.Loop) -> int:
        """A number naming ``loop`` in the jumps helpers return."""
        return self.loop_numbers.setdefault(id(loop), len(self.loop_numbers) + 1)

    def s_block(self, stmt: st.Block) -> None:
        line = stmt.line
        if type(line) is RowRun:
            # the parser's run of row lines, met one statement at a time
            # (lines run again going back into a construct): as data rows
            self.block([stmt])
            return
        if line.fanuc_alt is None:
            self.line_block(line)
            return
        # "M#1 P100": an M98 call when the M value is 98 as the line is read.
        value = self.x.expr(line.fanuc_value)
        self.w.stmt("if m.is_m98(%s):" % value, line)
        self.w.depth += 1
        if line.fanuc_alt.error is None:
            self.s_fanuccall(st.FanucCall(line.fanuc_alt))
        else:  # what rs274 reads after "m#1" cannot be read
            self.line_block(line.fanuc_alt)
        self.w.depth -= 1
        self.w.stmt("else:", line)
        self.w.depth += 1
        self.line_block(line)
        self.w.depth -= 1

    def s_labelcheck(self, stmt: st.LabelCheck, condition_read: bool = False) -> None:
        """``condition_read``: an elseif's condition was read just before."""
        if stmt.leave is not None:
            self._arm_skipping_out(stmt)
            return
        reads = stmt.kind in ("if", "while", "repeat") or (
            stmt.kind == "do-end" and stmt.loop is None  # a do-loop's while line
        )
        # an elseif line run into where no skip of its label stops (the
        # next such line stands inside another construct): read all the same
        reads = reads or (stmt.kind == "elseif" and not condition_read)
        expr = stmt.line.oword.expr if reads else None
        if expr is not None and may_fail(expr):
            # rs274 reads the condition (and fails there) before the label
            self.w.stmt(self.x.condition(expr), stmt.line)
        checked = stmt.line
        if stmt.loop is not None:
            # a jump skipping to the do-loop's while line (none: to the end)
            checked = stmt.loop.end
            if checked is None:
                return
        args = (string(stmt.key), string(stmt.kind), checked.number)
        text = string(checked.text)
        self.w.stmt("m.check_label(%s, %s, %d, %s)" % (args + (text,)), checked)
        if self.if_flag and stmt.kind == "endif":
            self.w.stmt("m.executed_if = True", checked)

    def s_flatarm(self, stmt: st.FlatArm) -> None:
        """See structure.FlatArm: rs274 reads an elseif's condition, checks
        the label, then skips to the next line with it if an arm has run."""
        line = stmt.check.line
        self._arm_run_into(line, stmt.check.kind, stmt.body, stmt.check)
        # Where an arm has run, rs274 skips from this line, reading on the
        # way the M98 lines' words (skipped_reads) up to where it stops.
        if stmt.landing is not None:
            # the skip lands inside a loop never closed, never entered
            self.w.stmt("else:", line)
            self.w.depth += 1
            landing = next(st.walk(stmt.landing), None)
            stop = landing.line.number if landing is not None else None
            self.skipped_reads([stmt.body], line.number, stop)
            self.skipped_to(stmt.landing)
            self.w.depth -= 1
            return
        unreadable = self.skip_error([stmt.body])
        if unreadable is not None:
            self.w.stmt("else:", line)
            self.w.depth += 1
            self.skipped_reads([stmt.body], line.number, unreadable.number)
            self.fail_skipped(unreadable)
            self.w.depth -= 1
        elif stmt.eof is not None:
            # the skip runs to the end of the file (past what holds this
            # line: the file's lines after it), or fails at a line on the way
            self.w.stmt("else:", line)
            self.w.depth += 1
            stop = _reads_stop(stmt.eof)
            self.skipped_reads(
                self._rest_of_file(line),
                line.number,
                stop,
                lines=self._own_m98_lines(line),
            )
            self.statement(stmt.eof)
            self.w.depth -= 1
        elif self.m98_reads and any(_m98_reads_between([stmt.body], line.number, None)):
            self.w.stmt("else:", line)
            self.w.depth += 1
            self.skipped_reads([stmt.body], line.number)
            self.w.depth -= 1

    def _own_m98_lines(self, line: nodes.Line) -> Optional[List[nodes.Line]]:
        """The M98 lines of ``line``'s file, where it is the main file."""
        if (line.file or self.program.file) == self.program.file:
            return self._file_m98_lines()
        return None

    def _rest_of_file(self, line: nodes.Line) -> List[List[st.Stmt]]:
        """The statements a skip from ``line`` to the end of its file may
        pass: the file's whole body (skipped_reads takes the lines after
        ``line``)."""
        if (line.file or self.program.file) == self.program.file:
            return [self.program.body]
        return [
            sub.body
            for sub in self.program.externals
            if (sub.line.file or "") == (line.file or "")
        ]

    def s_topreturn(self, stmt: st.TopReturn) -> None:
        self.w.comment(stmt.line)
        value = "" if stmt.value is None else ", %s" % self.x.expr(stmt.value)
        args = (stmt.line.number, string(stmt.keyword), string(stmt.line.text), value)
        self.w.stmt("m.top_level_return(%d, %s, %s%s)" % args, stmt.line)

    def s_fail(self, stmt: st.Fail) -> None:
        if stmt.reads is not None and may_fail(stmt.reads):
            # rs274 reads the condition (and fails there) before the label
            self.w.stmt(self.x.condition(stmt.reads), stmt.line)
        if stmt.check is not None:
            # a reused label: the opener rs274 recorded names the failure
            self.s_labelcheck(stmt.check, condition_read=stmt.reads is not None)
        self.w.comment(stmt.line)
        call = fail_call(stmt.line.number, stmt.message)
        if stmt.finish:
            call = call[:-1] + ", finish=True)"
        self.w.stmt(call, stmt.line)

    def s_seekfail(self, stmt: st.SeekFail) -> None:
        self.w.comment(stmt.line)
        call = "m.seek_failed(%d, %s, %s, %d)" % (
            stmt.line.number,
            string(stmt.file),
            string(stmt.name),
            stmt.start,
        )
        self.w.stmt(call, stmt.line)

    def s_endoffile(self, stmt: st.EndOfFile) -> None:
        self.w.stmt(
            "m.end_of_file(%s, False)  # no program end" % self.demarcated, stmt.line
        )

    def s_define(self, stmt: st.Define) -> None:
        sub = stmt.sub
        err = sub.define_error
        if err is None:
            self.w.stmt("m.define(%s, %s)" % (string(sub.name), sub.fn), sub.line)
        # what rs274 reads reading past the definition: its own return and
        # endsub values, and the words of its M98 lines, in text order
        stop = _reads_stop(err) if err is not None else None
        last = sub.line.number
        # (the file's own M98 lines where the definition is the main file's:
        # a construct that failed as a whole keeps no statements of them)
        lines = self._own_m98_lines(sub.line)
        reads_stop = stop
        if lines is not None and stop is None and sub.end is not None:
            reads_stop = sub.end.number  # (read to its endsub)
        for line in st.definition_values(sub):
            if stop is not None and line.number >= stop:
                break
            self.skipped_reads(
                [sub.body], last, line.number, defining=not sub.fanuc, lines=lines
            )
            self.definition_value(line)
            last = line.number
        if not sub.fanuc:
            self.skipped_reads([sub.body], last, reads_stop, defining=True, lines=lines)
        if err is not None:
            if err.line.error == err.message and err.line.partial:
                # the sub's own return/endsub line, whose value fails to
                # read: what rs274 computed before the error comes first
                # (a division by zero inside it)
                self.x.defining = True
                try:
                    for value in err.line.partial:
                        if not is_constant(value):
                            self.w.stmt(self.x.expr(value), err.line)
                finally:
                    self.x.defining = False
            call = fail_call(err.line.number, err.message)
            if err.finish:
                call = call[:-1] + ", finish=True)"
            self.w.stmt(call, err.line)

    def definition_value(self, line: nodes.Line) -> None:
        """Reading past the definition, rs274 reads the value of the sub's
        own ``return``/``endsub`` lines into ``#<_value>`` (a name not
        defined reads 0 there)."""
        expr = line.oword.expr
        if expr is None:
            self.w.stmt("m.definition_value(%d)" % line.number, line)
            return
        self.x.defining = True
        try:
            value = self.x.expr(expr)
        finally:
            self.x.defining = False
        self.w.stmt("m.definition_value(%d, %s)" % (line.number, value), line)

    def s_call(self, stmt: st.Call) -> None:
        args = [self.x.expr(a) for a in stmt.args]
        if stmt.sub is not None:
            head = ["m.call(%s" % stmt.sub.fn]  # definition already read
        elif stmt.found is not None:
            # the name as defined when the call runs, else what seeking finds
            found = stmt.found
            head = [
                "m.call_found(%s, %s, %s"
                % (
                    string(stmt.name),
                    found.fn,
                    string(found.line.file or self.program.file),
                )
            ]
        elif isinstance(stmt.name, str):
            head = ["m.call_named(%s" % string(stmt.name)]
        else:
            # A computed label is the value as an integer: o[100+100] is o200.
            self.code_functions.add("to_integer")
            label = '"%%d" %% to_integer(%s)' % self.x.expr(stmt.name)
            head = ["m.call_named(%s" % label]
        self.w.stmt(", ".join(head + args) + ")", stmt.line)

    def s_fanuccall(self, stmt: st.FanucCall) -> None:
        """``M98``: the machine checks the words as a block, then calls the
        subroutine (``fn``, or the one named by P when None) L times."""
        line = stmt.line
        codes, words = [], []
        for w in line.words:
            value = self.x.expr(w.value)
            if w.letter in "gm":  # a line may have several
                codes.append(self.code_arg(w, value))
            else:
                words.append("%s=%s" % (WORD_KEYWORDS.get(w.letter, w.letter), value))
        fn = stmt.sub.fn if stmt.sub is not None else "None"
        args = ["%d" % line.number, fn] + codes + words
        self.w.stmt("m.m98(%s)" % ", ".join(args), line)

    def s_subline(self, stmt: st.SubLine) -> None:
        """A sub line run in a call: in the frame an M98 .. L0 entered it
        fails as in an M98 call (only written when the file has such M98s)."""
        self.w.stmt("m.m98_frame_end(%d, sub=True)" % stmt.line.number, stmt.line)

    def s_return(self, stmt: st.Return) -> None:
        word = stmt.line.oword
        if self.any_strand and word is not None and word.keyword != "m99":
            # in the frame an M98 .. L0 entered, rs274 wants an M99
            self.w.stmt("m.m98_frame_end(%d)" % stmt.line.number, stmt.line)
        value = None if stmt.value is None else self.x.expr(stmt.value)
        if self.in_helper:
            self.w.stmt('return ("return", %s)' % value, stmt.line)
        elif value is None:
            self.w.stmt("return", stmt.line)
        else:
            self.w.stmt("return %s" % value, stmt.line)

    def s_finish(self, stmt: st.Finish) -> None:
        self.w.stmt("m.end_of_file(True, True)", stmt.line)

    def s_jump(self, stmt: st.Jump) -> None:
        if self.landing_loops is not None and id(stmt.target) not in self.landing_loops:
            # a loop whose opener a skip passed over: rs274 has no such label
            message = st.UNDEFINED_LABEL % (stmt.line.number, stmt.line.text)
            self.w.stmt(fail_call(stmt.line.number, message), stmt.line)
            return
        if self.break_flag and (
            (stmt.kind == "break" and stmt.target.kind == "while")
            or (stmt.kind == "continue" and break_after(stmt))
        ):
            # A continue skips forward past a later break line of its loop.
            self.w.stmt("m.doing_break = True", stmt.line)
        elif (
            self.break_flag
            and stmt.kind == "break"
            and stmt.target.kind == "do"
            and stmt.target.end is not None
        ):
            # rs274 skips to the loop's closing while, which clears the flag
            # (set by this break, or left over from a while-loop's).
            self.w.stmt("m.doing_break = False", stmt.line)
        if stmt.target.skip:
            # a skip to a later do line of the label (structure Loop.skip)
            if stmt.flag == "break" and self.break_flag:
                self.w.stmt("m.doing_break = True", stmt.line)
            if stmt.flag == "continue" and self.continue_flag:
                self.w.stmt("m.doing_continue = True", stmt.line)
            self.jump_to("break", stmt.target, stmt.line)
            return
        outer = self.resumed.get(id(stmt.target))
        if outer is not None:
            # gone back into the loop this break leaves: what follows it
            # is the start of ``outer`` (structure.DoEnd.leaves)
            self.jump_to("continue", outer, stmt.line)
            return
        self.frame_check(stmt.target, stmt.line)
        if self.continue_flag:
            self.stale_continue(stmt)
        if self.reads_in([stmt.target.body]):
            # rs274 skips forward over the rest of the loop's body
            unreadable = self.skip_error([stmt.target.body])
            until = None if unreadable is None else unreadable.number
            self.skipped_reads([stmt.target.body], stmt.line.number, until)
        if stmt.target.end is None and stmt.target.eof is not None:
            # no line with the loop's label follows: rs274 skips to the end
            self.statement(stmt.target.eof)
            return
        end = stmt.target.end
        if stmt.kind == "break" and stmt.target.kind == "do" and end is not None:
            expr = end.oword.expr if end.oword is not None else None
            if expr is not None and may_fail(expr):
                # rs274 skips to the closing while line and reads its
                # condition there (it fails on a name not set yet)
                self.w.stmt(self.x.condition(expr), end)
        if stmt.kind == "continue":
            unreadable = self.skip_error([stmt.target.body])
            if unreadable is not None:
                # rs274 skips to the loop's end, reading the rest of its
                # body: it fails at the first line it cannot read (one
                # before this line would have failed already).
                self.fail_skipped(unreadable)
                return
        self.jump_to(stmt.kind, stmt.target, stmt.line)

    def s_doend(self, stmt: st.DoEnd) -> None:
        """A while line ending an outer do-loop again (structure.DoEnd):
        true, rs274 goes back to the do line; else on with the next line."""
        test = self.x.condition(stmt.line.oword.expr)
        if self.break_flag:
            test = "%s and not m.doing_break" % test
        self.w.stmt("if %s:" % test, stmt.line)
        self.w.depth += 1
        self.resume(stmt.resume, stmt.leaves, stmt.target)
        self.jump_to("continue", stmt.target, stmt.line)
        self.w.depth -= 1
        if self.break_flag:
            self.w.stmt("m.doing_break = False", stmt.line)

    def resume(
        self, stmts: List[st.Stmt], leaves: List[st.Loop], outer: st.Loop
    ) -> None:
        """Back into an earlier construct (structure.DoEnd.resume): a break
        of a loop it ``leaves`` continues ``outer``, which starts after it."""
        saved = dict(self.resumed)
        for loop in leaves:
            self.resumed[id(loop)] = outer
        for inner in stmts:
            self.statement(inner)
        self.resumed = saved

    def s_ifend(self, stmt: st.IfEnd) -> None:
        """An endif run into again (structure.DoEnd.resume)."""
        if self.if_flag:
            self.w.stmt("m.executed_if = True", stmt.line)

    def s_armagain(self, stmt: st.ArmAgain) -> None:
        """A later arm's line run into again (structure.DoEnd.resume)."""
        self._arm_run_into(stmt.line, stmt.line.oword.keyword, stmt.body)

    def _arm_run_into(self, line, keyword: str, body, check=None) -> None:
        """An elseif or else line run into outside its if: an elseif's
        condition read first (then its label checked, given ``check``);
        ``body`` runs where no arm has run, an elseif's only when true
        (which sets rs274's flag)."""
        test = None
        if keyword == "elseif":
            self.temp += 1
            test = "t%d" % self.temp
            self.w.stmt("%s = %s" % (test, self.x.condition(line.oword.expr)), line)
        if check is not None:
            self.s_labelcheck(check, condition_read=True)
        self.w.stmt("if not m.executed_if:", line)
        self.w.depth += 1
        if test is not None:
            self.w.stmt("if %s:" % test, line)
            self.w.depth += 1
            self.w.stmt("m.executed_if = True", line)
            self.w.depth -= 1
        self.block(body)
        self.w.depth -= 1

    def _arm_skipping_out(self, stmt: st.LabelCheck) -> None:
        """An else or elseif run into whose next line of its label follows
        the construct holding it (structure.LabelCheck.leave): where an arm
        has run rs274 skips there, out of it; else it runs on (a true
        elseif sets the flag)."""
        line = stmt.line
        test = None
        if stmt.kind == "elseif":
            self.temp += 1
            test = "t%d" % self.temp
            self.w.stmt("%s = %s" % (test, self.x.condition(line.oword.expr)), line)
        leave, stmt.leave = stmt.leave, None
        try:
            self.s_labelcheck(stmt, condition_read=True)
        finally:
            stmt.leave = leave
        self.w.stmt("if m.executed_if:", line)
        self.w.depth += 1
        self.jump_to("break", leave, line)
        self.w.depth -= 1
        if test is not None:
            self.w.stmt("if %s:" % test, line)
            self.w.depth += 1
            self.w.stmt("m.executed_if = True", line)
            self.w.depth -= 1

    def s_again(self, stmt: st.Again) -> None:
        """A loop's closing line run into again (structure.DoEnd.resume)."""
        loop = stmt.loop
        if loop.kind != "do":
            # the endwhile (endrepeat) goes back to the while (repeat) line,
            # which tests its condition (counts anew: a finished repeat)
            self.statement(loop)
            return
        test = self.x.condition(loop.end.oword.expr)
        if self.break_flag:
            test = "%s and not m.doing_break" % test
        self.w.stmt("if %s:" % test, loop.end)
        self.w.depth += 1
        self.statement(loop)
        self.w.depth -= 1
        if self.break_flag:
            self.w.stmt("m.doing_break = False", loop.end)

    def stale_continue(self, stmt: st.Jump) -> None:
        """rs274's ``doing_continue`` (runtime.loopflags) at a break or
        continue: a while-loop break with the flag set is a continue."""
        if stmt.kind == "continue":
            value = "True" if stmt.target.kind == "do" else "False"
            self.w.stmt("m.doing_continue = %s" % value, stmt.line)
        elif stmt.target.kind == "while":
            self.w.stmt("if m.doing_continue:", stmt.line)
            self.w.depth += 1
            self.w.stmt("m.doing_continue = False", stmt.line)
            self.jump_to("continue", stmt.target, stmt.line)
            self.w.depth -= 1

    def jump_to(self, kind: str, target: st.Loop, line: nodes.Line) -> None:
        """``break``/``continue`` of ``target`` from the current point."""
        if not self.in_function(target):
            # A loop around this nesting helper: its caller jumps.
            self.w.stmt(
                "return (%s, %d)" % (string(kind), self.loop_number(target)), line
            )
        elif target is not self.loops[-1]:
            # Leave the inner loops; each checks the flag after it ends.
            self.w.stmt("%s = %s" % (self.flag(target), string(kind)), line)
            self.w.stmt("break", line)
        elif kind == "continue":
            self.continue_(target, line)
        else:
            self.w.stmt("break", line)

    def in_function(self, loop: st.Loop) -> bool:
        """Is ``loop`` written in the current Python function?"""
        return any(inner is loop for inner in self.loops[self.frame :])

    def continue_(self, loop: st.Loop, line: nodes.Line) -> None:
        """``continue``; rs274 continues a do-loop at its closing ``while``,
        which tests the condition."""
        if loop.kind == "do" and loop.end is not None:
            self.do_test(loop)
        self.w.stmt("continue", line)

    def anew_test(self, loop: st.Loop) -> None:
        """The closing ``while`` of a do-loop left one call level down by an
        ``M98 .. L0`` in its body: rs274 does not find the do's label in
        that frame and reads the line as a new while-loop (structure
        Loop.anew) -- true, it goes on past the line; false, it skips ahead
        for the label."""
        line = loop.end
        self.w.stmt("if m.left_frame(%s):" % string(self.frame_key(loop)), line)
        self.w.depth += 1
        self.w.stmt("if %s:" % self.x.condition(line.oword.expr), line)
        self.w.depth += 1
        self.w.stmt("break", line)
        self.w.depth -= 1
        self.statement(loop.anew)
        self.w.depth -= 1

    def do_test(self, loop: st.Loop) -> None:
        """``if not <cond>: break`` for the closing ``while`` of a do-loop
        (which also ends the loop, once, after a while-loop's break)."""
        if loop.back_into is not None:
            # true, rs274 goes back into an earlier construct (structure
            # Loop.back_into); either way this loop ends here
            outer, resume, leaves = loop.back_into
            test = self.x.condition(loop.end.oword.expr)
            if self.break_flag:
                test += " and not m.doing_break"
            self.w.stmt("if %s:" % test, loop.end)
            self.w.depth += 1
            self.resume(resume, leaves, outer)
            self.jump_to("continue", outer, loop.end)
            self.w.depth -= 1
            if self.break_flag:
                self.w.stmt("m.doing_break = False", loop.end)
            self.w.stmt("break", loop.end)
            return
        test = "not %s" % self.x.condition(loop.end.oword.expr)
        if self.break_flag:
            test += " or m.doing_break"
        self.w.stmt("if %s:" % test, loop.end)
        self.w.depth += 1
        if self.break_flag:
            self.w.stmt("m.doing_break = False", loop.end)
        self.w.stmt("break", loop.end)
        self.w.depth -= 1

    def flag(self, loop: st.Loop) -> str:
        """The flag variable of a loop left by a labelled jump from inside."""
        if id(loop) not in self.flags:
            self.flags[id(loop)] = "exit_%d" % (len(self.flags) + 1)
        return self.flags[id(loop)]

    def check_exits(self, loop: st.Loop, enclosing: Optional[st.Loop]) -> None:
        """After ``loop``: act on flags set by labelled jumps inside it."""
        for target in loop.exits:
            if id(target) in self.resumed:
                continue  # its break continues the loop gone back from
            if not self.in_function(target):
                continue  # the jump returned from this nesting helper
            flag = self.flag(target)
            if target is not enclosing:
                self.w.raw("%sif %s:" % (INDENT * self.w.depth, flag))
                self.w.raw("%sbreak" % (INDENT * (self.w.depth + 1)))
                continue
            self.w.raw('%sif %s == "break":' % (INDENT * self.w.depth, flag))
            self.w.raw("%sbreak" % (INDENT * (self.w.depth + 1)))
            self.w.raw('%sif %s == "continue":' % (INDENT * self.w.depth, flag))
            self.w.depth += 1
            self.w.raw('%s%s = ""' % (INDENT * self.w.depth, flag))
            self.continue_(target, target.end or target.line)
            self.w.depth -= 1

    def strands(self, stmt) -> bool:
        """Does ``stmt`` (an if or a loop) hold an ``M98`` whose L may be 0?
        Such a call never returns: the rest runs one call level down, where
        rs274 no longer finds the construct's label (runtime same_frame)."""
        if not self.any_strand:
            return False
        for inner in _walk_bodies(stmt):
            if isinstance(inner, st.FanucCall) and st.m98_may_strand(inner.line):
                return True
        return False

    def frame_key(self, stmt) -> str:
        line = stmt.branches[0].line if isinstance(stmt, st.If) else stmt.line
        return "%d:%d" % (self.w.file_index, line.number)

    def frame_check(self, stmt, line: Optional[nodes.Line]) -> None:
        """``line`` (a closing line of ``stmt``) runs: see :meth:`strands`."""
        if line is None or id(stmt) not in self.stranding:
            return
        args = (string(self.frame_key(stmt)), line.number, string(line.text))
        self.w.stmt("m.same_frame(%s, %d, %s)" % args, line)

    def s_if(self, stmt: st.If) -> None:
        arms = stmt.branches + ([stmt.orelse] if stmt.orelse else [])
        if self.runs_into(stmt, arms):
            self.arm_steps(stmt, arms)
            return
        if self.strands(stmt):
            self.stranding.add(id(stmt))
            self.w.stmt(
                "m.frame_mark(%s)" % string(self.frame_key(stmt)), stmt.branches[0].line
            )
        opened = 0  # else-blocks opened to read a skipped arm's M98 lines
        # (each such arm deepens the elif chain and is read after every
        # arm before it: past a few, rs274's reads are not followed)
        reading = self.reads_in([arm.body for arm in arms])
        if reading:
            reading = sum(self.reads_in([arm.body]) for arm in arms) <= MOST_READ_ARMS
        for i, branch in enumerate(stmt.branches):
            keyword_ = "if" if i == 0 else "elif"
            if i and reading and self.reads_in([stmt.branches[i - 1].body]):
                # a false condition: rs274 skips the arm before reading the
                # next condition (reading its M98 lines)
                self.w.stmt("else:", branch.line)
                self.w.depth += 1
                opened += 1
                self.skipped_reads([stmt.branches[i - 1].body])
                keyword_ = "if"
            test = self.x.condition(branch.line.oword.expr)
            self.w.stmt("%s %s:" % (keyword_, test), branch.line)
            following = arms[i + 1].line if i + 1 < len(arms) else stmt.end
            # rs274 skips the arms after a taken one: where it stops
            stop, at = self.skip_stop(stmt, arms, i + 1)
            later = list(stmt.branches[i + 1 : at + 1])
            skipped = [arm.body for arm in arms[i + 1 : at + 1]] if reading else []
            if stop is None and stmt.orelse is not None:
                # past the else line too, reading elseif lines after it
                later += _after_else(stmt.orelse.body)
            self.nested(
                branch,
                then=stop,
                later=later,
                check=(stmt, following),
                rest=(stmt, i + 1) if i + 1 < len(real_arms(stmt)) else None,
                skipped=skipped,
            )
            stop, _ = self.skip_stop(stmt, arms, i, i + 1)
            if stop is not None:
                # A false condition makes rs274 skip this arm, and stop in
                # it: the later arms are never reached.
                self.w.stmt("else:", branch.line)
                self.w.depth += 1
                if self.if_flag and isinstance(stop, list):
                    # no arm has run: the skip lands with the flag clear
                    self.w.stmt("m.executed_if = False", branch.line)
                if reading:
                    self.skipped_reads([branch.body], before=_stop_line(stop))
                self.skipped_to(stop)
                self.w.depth -= 1 + opened
                return
        last = stmt.branches[-1]
        if stmt.orelse is not None:
            self.w.stmt("else:", stmt.orelse.line)
            if reading and self.reads_in([last.body]):
                self.w.depth += 1
                self.skipped_reads([last.body])
                self.w.depth -= 1
            self.nested(stmt.orelse, check=(stmt, stmt.end))
        elif reading and self.reads_in([last.body]):
            self.w.stmt("else:", stmt.end or last.line)
            self.w.depth += 1
            self.skipped_reads([last.body])
            self.w.depth -= 1
        self.w.depth -= opened
        if self.if_flag and stmt.end is not None:
            # the if ends at its endif, which sets the flag
            self.w.stmt("m.executed_if = True", stmt.end)

    def skip_stop(
        self, stmt: st.If, arms: List[st.Branch], first: int, end: Optional[int] = None
    ) -> Tuple[Union[None, nodes.Line, List[st.Stmt]], int]:
        """Where rs274, skipping the arms ``arms[first:end]`` of ``stmt`` to
        its label, stops before its end: a line it cannot read (a line) or a
        line reusing the label (its statements, ``stmt.landings``); and the
        index of the arm that holds it (None, the last index: no stop)."""
        end = len(arms) if end is None else end
        for k in range(first, end):
            unreadable = self.skip_error([arms[k].body])
            landing = stmt.landings.get(k)
            if landing is not None and (
                unreadable is None or _first_line(landing) < unreadable.number
            ):
                return landing, k
            if unreadable is not None:
                return unreadable, k
        return None, end - 1

    def skipped_to(self, stop: Union[nodes.Line, List[st.Stmt]]) -> None:
        """rs274 stops skipping at ``stop`` (see :meth:`skip_stop`)."""
        if isinstance(stop, list):
            # the line reusing the label runs as what it is; the loops
            # around it were skipped, never entered
            saved = self.landing_loops
            entered = {id(s) for s in st.walk(stop) if isinstance(s, st.Loop)}
            # (and the loops around this point, entered before the skip)
            entered |= {id(loop) for loop in self.loops}
            self.landing_loops = entered | (saved or set())
            self.block(stop)
            self.landing_loops = saved
        else:
            self.fail_skipped(stop)

    def nested(
        self,
        branch: st.Branch,
        then: Union[None, nodes.Line, List[st.Stmt]] = None,
        later: Sequence[Union[st.Branch, st.ArmAgain]] = (),
        check: Optional[tuple] = None,
        rest: Optional[Tuple[st.If, int]] = None,
        skipped: Sequence[List[st.Stmt]] = (),
    ) -> None:
        """An arm's body; ``then`` fails after it (rs274 skipping the
        arms after a taken one reads that line); ``check``: the if and the
        line after the arm, whose label rs274 looks up (:meth:`frame_check`);
        ``rest``: the if and the index of the arm after this one;
        ``skipped``: the bodies of the arms skipped after it."""
        self.w.depth += 1
        if self.if_flag:  # an arm runs: rs274's flag (structure.FlatArm)
            self.w.stmt("m.executed_if = True", branch.line)
        self.block(branch.body)
        if rest is not None and self.may_clear(branch.body):
            self.run_into(*rest)
            self.w.depth -= 1
            return
        self.skip_tail(later, check, then, skipped)
        self.w.depth -= 1

    def runs_into(self, stmt: st.If, arms: List[st.Branch]) -> bool:
        """Can an arm of ``stmt`` other than the last leave rs274's flag
        clear, so that it runs on into the next arm (:meth:`arm_steps`)?
        (Not where a skip stops inside an arm or an M98 may not return:
        there :meth:`run_into` writes the arms after such an arm again.)"""
        if not self.if_flag or stmt.end is None or self.strands(stmt):
            return False
        if not any(self.may_clear(arm.body) for arm in arms[:-1]):
            return False
        return all(
            self.skip_stop(stmt, arms, i, i + 1)[0] is None for i in range(len(arms))
        )

    def arm_steps(self, stmt: st.If, arms: List[st.Branch]) -> None:
        """An if whose arms can run one into the next (:meth:`runs_into`):
        ``arm`` is the arm to run, each arm's code runs when it is that
        arm's number, and an arm that leaves the flag clear moves it on to
        the next arm (reading its condition: true sets the flag), as
        rs274 runs on into the next arm's line. Each arm written once."""
        self.temp += 1
        arm = "arm_%d" % self.temp
        for i, branch in enumerate(stmt.branches):
            keyword_ = "if" if i == 0 else "elif"
            test = self.x.condition(branch.line.oword.expr)
            self.w.stmt("%s %s:" % (keyword_, test), branch.line)
            self.w.stmt(INDENT + "%s = %d" % (arm, i), branch.line)
        self.w.stmt("else:", stmt.orelse.line if stmt.orelse else stmt.end)
        self.w.stmt(INDENT + "%s = %d" % (arm, len(stmt.branches)), stmt.end)
        self.w.stmt("m.executed_if = True", stmt.branches[0].line)
        run_on = False  # can this arm be run into with the flag clear?
        for i, branch in enumerate(arms):
            self.w.stmt("if %s == %d:" % (arm, i), branch.line)
            self.w.depth += 1
            self.block(branch.body)
            later = stmt.branches[i + 1 :]
            run_on = i + 1 < len(arms) and (run_on or self.may_clear(branch.body))
            if run_on:
                nxt = arms[i + 1]
                self.w.stmt("if not m.executed_if:", nxt.line)
                self.w.depth += 1
                self.w.stmt("%s = %d" % (arm, i + 1), nxt.line)
                if nxt is not stmt.orelse:
                    cond = self.x.condition(nxt.line.oword.expr)
                    self.w.stmt("if %s:" % cond, nxt.line)
                    self.w.stmt(INDENT + "m.executed_if = True", nxt.line)
                self.w.depth -= 1
                if any(may_fail(b.line.oword.expr) for b in later):
                    self.w.stmt("else:", nxt.line)
                    self.w.depth += 1
                    self.skip_tail(later, None, None)
                    self.w.depth -= 1
            else:
                self.skip_tail(later, None, None)
            self.w.depth -= 1
        self.w.stmt("m.executed_if = True", stmt.end)

    def run_into(self, stmt: st.If, index: int) -> None:
        """Running code reaches the line of arm ``index`` of ``stmt`` (the
        arm before it may have left rs274's flag clear: a call, a skip that
        landed): with the flag clear, rs274 runs into the arm whatever the
        condition (a true one sets the flag), and on into the next arm's
        line; with it set, it skips to the endif (:meth:`skip_tail`)."""
        arms = real_arms(stmt)
        arm = arms[index]
        test = None
        if arm is not stmt.orelse:
            self.temp += 1
            test = "t%d" % self.temp
            self.w.stmt(
                "%s = %s" % (test, self.x.condition(arm.line.oword.expr)), arm.line
            )
        self.w.stmt("if not m.executed_if:", arm.line)
        self.w.depth += 1
        if test is not None:
            self.w.stmt("if %s:" % test, arm.line)
            self.w.stmt(INDENT + "m.executed_if = True", arm.line)
        self.block(arm.body)
        if index + 1 < len(arms):
            self.run_into(stmt, index + 1)
        self.w.depth -= 1
        stop, at = self.skip_stop(stmt, arms, index)
        size = len(self.w.out)
        self.w.stmt("else:", arm.line)
        self.w.depth += 1
        self.skip_tail(stmt.branches[index + 1 : at + 1], None, stop)
        self.w.depth -= 1
        if len(self.w.out) == size + 1:
            self.w.out.pop()  # nothing to do: the skip reaches the endif

    def fast_locals(self, body: List[st.Stmt]) -> Dict[str, str]:
        """fastlocals.fast_locals, but none where an if runs into its later
        arms (:meth:`run_into`): that code nests deeper than the tree."""
        if self.if_flag and any(
            isinstance(stmt, st.If)
            and any(self.may_clear(arm.body) for arm in stmt.branches)
            for stmt in st.walk(body, into_subs=False)
        ):
            return {}
        return fastlocals.fast_locals(body, FAST_LOCALS_DEPTH)

    def may_clear(self, body: List[st.Stmt]) -> bool:
        """Can running ``body`` leave rs274's flag "an arm of an if has run"
        clear (:func:`clears_flag`; a call, where a subroutine can)?"""
        if not self.if_flag:
            return False
        for inner in st.walk(body, into_subs=False):
            if clears_flag(inner):
                return True
            if self.calls_clear and isinstance(inner, (st.Call, st.FanucCall)):
                return True
        return False

    def skip_tail(
        self,
        later: Sequence[Union[st.Branch, st.ArmAgain]],
        check: Optional[tuple],
        then: Union[None, nodes.Line, List[st.Stmt]],
        skipped: Sequence[List[st.Stmt]] = (),
    ) -> None:
        """rs274 skips the arms after one that ran: it reads the later
        elseif lines' conditions and the M98 lines of the ``skipped``
        bodies, and stops at ``then``."""
        skipped, stop, last = list(skipped), _stop_line(then), 0
        for k, arm in enumerate(later):
            # (the M98 lines before it first, in text order)
            number = arm.line.number
            if stop is None or number < stop:
                self.skipped_reads(skipped, last, number)
                last = number
            # rs274 still reads the condition of each later elseif (it
            # skips the arm, not the line): only its errors matter.
            if may_fail(arm.line.oword.expr):
                self.w.comment(arm.line)
                self.w.stmt(self.x.condition(arm.line.oword.expr), arm.line)
            if k == 0 and check is not None:
                self.frame_check(*check)
        if not later and check is not None:
            self.frame_check(*check)
        self.skipped_reads(skipped, last, stop)
        if then is not None:
            self.skipped_to(then)

    # -- lines read while skipping ----------------------------------------

    def _file_m98_lines(self) -> List[nodes.Line]:
        """The main file's M98 lines, every one (structure.build)."""
        return getattr(self.program, "m98_lines", None) or []

    def skipped_reads(
        self,
        bodies: List[List[st.Stmt]],
        after: int = 0,
        before: Optional[int] = None,
        defining: bool = False,
        lines: Optional[List[nodes.Line]] = None,
    ) -> None:
        """rs274 reads an M98 line's words even when it skips over the line
        (interp_read.cc read_o): the values that may fail of the M98 lines
        in ``bodies`` (or of ``lines``, a file's own) after line ``after``
        and before line ``before`` (where the skip stops), in text order;
        ``defining``: read past a definition (a name not set reads 0)."""
        if not self.m98_reads:
            return  # the usual case: nothing to read
        if lines is not None:
            found = [
                line
                for line in lines
                if line.number > after
                and (before is None or line.number < before)
                and _m98_values(line)
            ]
        else:
            found = _m98_reads_between(bodies, after, before)
        for line in found:
            self.w.raw(
                "%s# rs274 reads line %d while skipping it"
                % (self.indent(), line.number)
            )
            for code in self.m98_reads_of(line, defining):
                self.w.stmt(code, line)

    def m98_reads_of(self, line: nodes.Line, defining: bool = False) -> List[str]:
        """The code of what reading M98 ``line`` may fail on (_m98_values);
        ``defining``: read past a definition (a name not set reads 0)."""
        codes = []
        self.x.defining = defining
        try:
            for value, integer in _m98_values(line):
                code = self.x.expr(value)
                if integer:
                    self.code_functions.add("to_integer")
                    code = "to_integer(%s)" % code
                codes.append(code)
        finally:
            self.x.defining = False
        return codes

    def reads_in(self, bodies: List[List[st.Stmt]]) -> bool:
        """Does skipping ``bodies`` read an M98 line's words that may fail?"""
        return self.m98_reads and _has_m98_reads(bodies)

    def skip_error(self, bodies: List[List[st.Stmt]]) -> Optional[nodes.Line]:
        """The first line in ``bodies`` rs274 cannot even read (see
        structure.TEXT_ERRORS): skipping over it fails."""
        if not self.text_errors:
            return None  # the usual case: nothing to look for
        return st.first_text_error(bodies)

    def fail_skipped(self, line: nodes.Line) -> None:
        self.w.raw(
            "%s# rs274 skips ahead, reading line %d" % (self.indent(), line.number)
        )
        self.w.stmt(fail_call(line.number, line.error), line)

    def s_loop(self, stmt: st.Loop) -> None:
        if self.strands(stmt):
            self.stranding.add(id(stmt))
            self.w.stmt("m.frame_mark(%s)" % string(self.frame_key(stmt)), stmt.line)
        if stmt.flagged:
            self.w.stmt('%s = ""' % self.flag(stmt))
        word = stmt.line.oword
        if stmt.kind == "while":
            self.w.stmt("while %s:" % self.x.condition(word.expr), stmt.line)
        elif stmt.kind == "repeat":
            count = self.x.expr(word.expr)
            # Skipping to its end when the count runs out, rs274 fails on the
            # way (loop_else): the loop never runs its count again.
            fails = (stmt.eof or stmt.skip_fail) is not None
            if left_early(stmt):
                # rs274 keeps the count left for the next time
                repeat = "m.repeat_kept(%s, %s%s)" % (
                    string(stmt.key),
                    count,
                    ", again=False" if fails else "",
                )
            elif self.continue_flag and not fails:
                repeat = "m.repeat_again(%s)" % count
            else:
                repeat = "m.repeat(%s)" % count
            self.w.stmt("for _ in %s:" % repeat, stmt.line)
        else:
            self.w.stmt("while True:", stmt.line)
        self.w.depth += 1
        if stmt.kind != "repeat":  # m.repeat counts its own steps
            self.w.stmt("m.step()", stmt.line)  # runtime.budget
        self.loops.append(stmt)
        self.block(stmt.body)
        if stmt.kind != "do":  # (a do's while is read as a new while)
            self.frame_check(stmt, stmt.end)
        if stmt.end is None:
            # No closing line: rs274 reads on into what follows the body
            # (the end of the file or of the subroutine), never looping.
            self.w.raw(self.indent() + "break")
        elif stmt.kind == "do":
            if stmt.anew is not None and id(stmt) in self.stranding:
                self.anew_test(stmt)
            self.do_test(stmt)
        self.loops.pop()
        self.w.depth -= 1
        self.loop_else(stmt)
        self.check_exits(stmt, self.loops[-1] if self.loops else None)
        if self.continue_flag and stmt.kind == "while":
            # Ending by its condition, a while-loop clears rs274's flag (a
            # jump to an outer loop skips past the endwhile: checked above).
            self.w.raw(self.indent() + "m.doing_continue = False")
        unreadable = self.skip_error([stmt.body])
        if unreadable is not None:
            # The loop ends by skipping (the rest of) its body: rs274 reads
            # it and fails at its first unreadable line.
            self.fail_skipped(unreadable)

    def loop_else(self, stmt: st.Loop) -> None:
        """What rs274 does when a loop ends by skipping forward to its label
        (a false while condition, a repeat count run out): it stops at every
        line with that label on the way."""
        # the first of them in the file (a repeat's own break or continue
        # comes before the end of the file an unclosed loop skips to)
        fails = [
            f for f in (stmt.skip_fail, stmt.eof if stmt.kind != "do" else None) if f
        ]
        fail = min(fails, key=_fail_order) if fails else None
        unreadable = self.skip_error([stmt.body])
        if fail is not None and unreadable is not None:
            if unreadable.number < _fail_order(fail):
                fail = None  # the skip fails first there (after the loop)
        landing = stmt.landing
        if landing is not None and (
            (fail is not None and _fail_order(fail) < _first_line(landing))
            or (unreadable is not None and unreadable.number < _first_line(landing))
        ):
            landing = None  # the skip stops earlier
        # skipping the body, rs274 reads its M98 lines (a do-loop ends at
        # its closing line: nothing skipped); skipping to the end of the
        # file, every M98 line of the file after the loop's (lines)
        reads = stmt.kind != "do" and self.reads_in([stmt.body])
        lines = None
        if stmt.kind != "do" and fail is not None and _to_end_of_file(fail):
            lines = self._own_m98_lines(stmt.line)
            if lines is not None and self.m98_reads:
                reads = any(
                    line.number > stmt.line.number and _m98_values(line)
                    for line in lines
                )
        # (up to where the skip stops: a line it cannot read, or one with
        # its label where it fails)
        stops = [unreadable.number] if unreadable is not None else []
        if fail is not None and _reads_stop(fail) is not None:
            stops.append(_reads_stop(fail))
        until = min(stops) if stops else None
        if reads and until is not None and lines is None:  # (it may stop first)
            reads = any(_m98_reads_between([stmt.body], 0, until))
        if landing is not None:
            # it stops at a do line of its label in the body, and rs274
            # goes on from there (the loops around it never entered)
            self.w.stmt("else:", stmt.line)
            self.w.depth += 1
            if reads:
                self.skipped_reads([stmt.body], before=_first_line(landing))
            self.skipped_to(landing)
            self.w.depth -= 1
            return
        sets_break = (
            self.break_flag
            and stmt.kind == "while"
            and any(j.kind == "break" for j in own_jumps(stmt))
        )
        if fail is None and not sets_break and not reads:
            return
        self.w.stmt("else:", stmt.line)
        self.w.depth += 1
        if reads:
            self.skipped_reads([stmt.body], stmt.line.number, before=until, lines=lines)
        if sets_break:
            # a break line of this loop on the way sets doing_break
            self.w.stmt("m.doing_break = True", stmt.line)
        if fail is not None:
            self.statement(fail)  # (an elseif's condition read first)
        self.w.depth -= 1

    # -- ordinary lines ---------------------------------------------------

    def line_block(self, line: nodes.Line) -> None:
        """One ordinary line: values read in order, settings, then the block.
        The statements show the line (``m.block(7, G91, x=..)``, ``x = 1.0``,
        ``m.comment(3, "text")``): only a line rs274 cannot read, written as
        the values read before the error and ``m.fail``, gets its text above
        it as a ``# n:`` comment."""
        if line.error is not None:
            self.w.comment(line)
        if line.block_delete:
            self.w.stmt("if not m.block_delete:", line)
            self.w.depth += 1
            self.line_body(line)
            self.w.depth -= 1
        else:
            self.line_body(line)

    def line_body(self, line: nodes.Line) -> None:
        if line.error is not None:
            profile = profile_reading(line)
            if profile is not None:
                # rs274 reads U and W while it reads a G7x profile only.
                self.w.stmt("if m.reading_profile:", line)
                self.w.depth += 1
                self.line_body(profile)
                self.w.depth -= 1
                self.w.stmt("else:", line)
                self.w.depth += 1
                self.read_error(line)
                self.w.depth -= 1
                return
            self.read_error(line)
            return
        reads = self.item_reads(line)
        # Values read before a check must be kept in temporaries so the
        # check runs after them; so must every value when words and settings
        # mix (settings take effect before the block uses the words).
        last_check = max((i for i, r in enumerate(reads) if r.checks), default=-1)
        mixed = bool(line.words) and bool(line.assigns)
        for i, read in enumerate(reads):
            for check in read.checks:
                self.w.stmt(check, line)
            if (mixed or i < last_check) and not read.constant:
                self.temp += 1
                temp = "t%d" % self.temp
                self.w.stmt("%s = %s" % (temp, read.value), line)
                read.value = temp
        settings = [r for r in reads if r.target is not None]
        if settings:
            targets = ", ".join(r.target for r in settings)
            sources = ", ".join(r.value for r in settings)
            self.w.stmt("%s = %s" % (targets, sources), line)
        if fastlocals.comment_line(line):
            self.w.stmt(self.comment_call(line), line)
        elif (
            line.words or line.comment is not None or line.n is not None or not settings
        ):
            words = [r for r in reads if r.target is None]
            self.w.stmt(
                self.block_call(line, line.words, [r.value for r in words]), line
            )

    def read_error(self, line: nodes.Line) -> None:
        """A line rs274 fails to read: the values (and setting checks) it
        computed before meeting the error come first, with their own errors
        (a division by zero); nothing is set."""
        for read in self.item_reads(line):
            for check in read.checks:
                self.w.stmt(check, line)
            if not read.constant:
                self.w.stmt(read.value, line)
        for value in oword_values(line) + list(line.partial):
            if not is_constant(value):
                self.w.stmt(self.x.expr(value), line)
        self.w.stmt(fail_call(line.number, line.error), line)

    def item_reads(self, line: nodes.Line) -> List[ItemRead]:
        """The code for reading each item of ``line``, in order."""
        reads = []
        # names set before this line need no declare (ngc2py.assigned)
        declared = set(self.settled.get(id(line), ()))
        for i, item in enumerate(line.items):
            read = ItemRead(self.x.expr(item.value), is_constant(item.value))
            if isinstance(item, nodes.Assign):
                read.target = self.setting_target(item.target, read.checks)
                name = item.target
                if (
                    isinstance(name, nodes.NamedParam)
                    and name.name not in declared
                    and name.name not in self.x.fast  # certainly set: fastlocals
                    and nodes.reads_name(line.items[i:], name.name)
                ):
                    # rs274 creates the name when it reads "#<n>=", so the
                    # rest of the line may read it.
                    declared.add(name.name)
                    store = "g" if name.is_global else "v"
                    read.checks.append("%s.declare(%s)" % (store, string(name.name)))
            reads.append(read)
        return reads

    def setting_target(self, target: nodes.Expr, checks: List[str]) -> str:
        """The assignment target for a setting; a numbered one's index is
        checked as rs274 reads it, before the value (into ``checks``)."""
        if not isinstance(target, nodes.NumParam):
            return self.x.expr(target)
        index = target.index
        if isinstance(index, nodes.Num) and plain_write_index(index.value):
            return "p[%d]" % int(index.value)
        self.temp += 1
        temp = "i%d" % self.temp
        checks.append("%s = m.params.setting_index(%s)" % (temp, self.x.index(index)))
        return "p[%s]" % temp

    def block_call(self, line: nodes.Line, words, values: List[str]) -> str:
        move = self.move_call(line, words, values)
        if move is None:
            move = self.arc_call(line, words, values)
        if move is not None:
            return move
        args = ["%d" % line.number]
        kwargs = []
        for word, value in zip(words, values):
            if word.letter in "gm":
                args.append(self.code_arg(word, value))
            else:
                kwargs.append(
                    "%s=%s" % (WORD_KEYWORDS.get(word.letter, word.letter), value)
                )
        if line.n_text is not None:
            kwargs.append("n=%s" % string(line.n_text))
        if line.comment is not None:
            kwargs.append("comment=%s" % self.comment_arg(line.comment))
        return "m.block(%s)" % ", ".join(args + kwargs)

    def move_call(self, line: nodes.Line, words, values: List[str]) -> Optional[str]:
        """``m.move(line, G1, x=..)`` for a plain straight move: G0, G1 or no
        motion code, axis words, F and N only (runtime.fast.moves); else None."""
        return self.motion_call(
            "m.move", line, words, values, (codes.G0, codes.G1), "xyzabcuvwf", False
        )

    def arc_call(self, line: nodes.Line, words, values: List[str]) -> Optional[str]:
        """``m.arc(line, G2, x=.., i=..)`` for an arc: G2 or G3 written as
        a literal, axis words (X Y Z A B C), I J K or R, F and N only
        (``Machine.arc``); else None."""
        return self.motion_call(
            "m.arc", line, words, values, (codes.G2, codes.G3), "xyzabcijkrf", True
        )

    def motion_call(
        self, call, line, words, values, motions, letters, motion_needed
    ) -> Optional[str]:
        """``call(line[, motion], word=..)`` when the line has one literal
        code of ``motions`` (or none, unless ``motion_needed``), words of
        ``letters`` including an axis, an N number, a plain comment and
        nothing else."""
        comment = line.comment
        if comment is not None and comment.kind != "plain":
            return None  # (messages, prints and logs: the general path)
        motion = None
        kwargs = []
        for word, value in zip(words, values):
            letter = word.letter
            if letter in letters:
                kwargs.append("%s=%s" % (letter, value))
            elif letter == "g" and motion is None and is_constant(word.value):
                motion = convert_code(letter, word.value.value)
                if motion not in motions:
                    return None
            else:
                return None
        if motion is None and motion_needed:
            return None
        if not any(
            word.letter in AXIS_LETTERS and word.letter in letters for word in words
        ):
            return None
        args = ["%d" % line.number]
        if (
            call == "m.move"
            and motion in (codes.G0, codes.G1)
            and line.n_text is None
            and comment is None
            and all(word.letter in "xyz" for word in words if word.letter != "g")
        ):
            # Machine.feed / Machine.rapid: the commonest move, lighter
            call = "m.feed" if motion == codes.G1 else "m.rapid"
            return "%s(%s)" % (call, ", ".join(args + kwargs))
        if motion is not None:
            name = code_name(motion)
            self.codes.add(name)
            args.append(name)
        if line.n_text is not None:
            kwargs.append("n=%s" % string(line.n_text))
        if comment is not None:
            kwargs.append("comment=%s" % self.comment_arg(comment))
        return "%s(%s)" % (call, ", ".join(args + kwargs))

    def code_arg(self, word: nodes.Word, value: str) -> str:
        """A G/M code: its constant's name, or a run-time conversion."""
        if is_constant(word.value):
            code = convert_code(word.letter, word.value.value)
            if code is not None:
                name = code_name(code)
                self.codes.add(name)
                return name
        return "m.%scode(%s)" % (word.letter, value)

    def comment_arg(self, comment: nodes.Comment) -> str:
        """A block's comment: a plain one's text, else ``(kind, text)``; the
        runtime splits out the parameters (runtime.comments)."""
        if comment.kind == "plain":
            return string(comment.text)
        return "(%s, %s)" % (string(comment.kind), string(comment.text))

    def comment_call(self, line: nodes.Line) -> str:
        """A line of one comment alone: ``m.comment(3, "text")``,
        ``m.debug(5, "x is #<x>", x=x)`` (runtime.comments.CommentLines).
        The names the text expands that are Python variables here are
        handed over by name; the runtime reads the others from the stores."""
        comment = line.comment
        args = ["%d" % line.number]
        if comment.kind != "logclose":
            args.append(string(comment.text))
        given = [
            (name, self.x.fast[name])
            for name in fastlocals.comment_names(comment)
            if name in self.x.fast
        ]
        odd = [
            (n, var) for n, var in given if not n.isidentifier() or keyword.iskeyword(n)
        ]
        args += ["%s=%s" % (n, var) for n, var in given if (n, var) not in odd]
        if odd:  # names no keyword argument can spell: #<pass>, #<z-end>
            args.append("**{%s}" % ", ".join("%s: %s" % (string(n), v) for n, v in odd))
        return "m.%s(%s)" % (LINE_METHODS[comment.kind], ", ".join(args))


# --------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------


def convert_code(letter: str, value: float) -> Optional[int]:
    """The runtime code number of a literal G/M word, or None if invalid
    (the run-time conversion then raises rs274's error)."""
    try:
        return codes.g_code(value) if letter == "g" else codes.m_code(value)
    except GCodeError:
        return None


# Constant blocks as data: a row is (line, shape index, values...) and a
# shape is (codes, word letters). Rows of one run are one flat tuple of
# literals, which compiles in one constant (nested row tuples take twice as
# long; see the module docstring).
if TYPE_CHECKING:
    Shape = Tuple[Tuple[int, ...], Tuple[str, ...]]
    Row = Tuple[Shape, str]  # the shape and the row's value cells


def constant_row(stmt: st.Stmt) -> Optional[Row]:
    """(shape, value literals) if ``stmt`` is a block of literal, valid words
    only (no settings, comments, block delete or error); else None."""
    if not isinstance(stmt, st.Block):
        return None
    line = stmt.line
    if isinstance(line, RowLine):
        return line.shape, line.cells
    if type(line) is RowRun:
        return None  # many rows: see CodeGen.block
    if line.error or line.comment is not None or line.block_delete or line.oword:
        return None
    codes_: List[int] = []
    letters: List[str] = []
    values: List[str] = []
    for word in line.items:
        if not isinstance(word, nodes.Word) or not is_constant(word.value):
            return None
        if word.letter in "gm":
            code = convert_code(word.letter, word.value.value)
            if code is None:
                return None
            codes_.append(code)
        else:
            letters.append(WORD_KEYWORDS.get(word.letter, word.letter))
            values.append(repr(float(word.value.value)))
    if line.n_text is not None:
        if not line.n_text or line.n_text.split() != [line.n_text]:
            return None  # not one cell of a text table
        letters.insert(0, "n")  # first, as it is written
        values.insert(0, line.n_text)
    return (tuple(codes_), tuple(letters)), " ".join(values)


def constant_rows(bodies: List[List[st.Stmt]]) -> int:
    """How many constant blocks (rows of data tables) ``bodies`` hold."""
    count = 0
    for body in bodies:
        for stmt in st.walk(body):
            if type(stmt) is st.Block and type(stmt.line) is RowRun:
                count += stmt.line.count
            elif constant_row(stmt) is not None:
                count += 1
    return count


def row_values(run: List) -> bool:
    """Does a row of ``run`` (row runs and (line, row) pairs) have a word
    value (any word but G and M)?"""
    for item in run:
        if type(item) is RowRun:
            if any(line.cells for line in item.lines()):
                return True
        elif item[1][1]:
            return True
    return False


def tables(run: List) -> List[List]:
    """``run`` (row runs and (line, row) pairs) cut into tables of
    ROWS_PER_TABLE rows, a row run split where a table ends."""
    parts: List[List] = [[]]
    room = ROWS_PER_TABLE
    for item in run:
        count = item.count if type(item) is RowRun else 1
        while True:
            if room == 0:
                parts.append([])
                room = ROWS_PER_TABLE
            if count <= room:
                break
            head, item = item.split(room)
            parts[-1].append(head)
            count -= room
            room = 0
        parts[-1].append(item)
        room -= count
    return parts


def shape_text(shape: Shape) -> str:
    """``G1 X Y``: what a row of this shape looks like in G-code."""
    words = [codes.code_name(code) for code in shape[0]]
    words += [GCODE_LETTERS.get(letter, letter.upper()) for letter in shape[1]]
    return " ".join(words) or "(nothing)"


def shapes_table(shapes: Dict[Shape, int]) -> List[str]:
    """``SHAPES = (...)``: the (codes, word letters) of each row shape."""
    lines = [
        "",
        "",
        "# Row shapes: G/M codes, then the letters of the words that follow.",
    ]
    lines.append("SHAPES = (")
    for shape, index in shapes.items():
        codes_ = Coll("(", [code_name(code) for code in shape[0]], ")")
        letters = Coll("(", [string(letter) for letter in shape[1]], ")")
        note = "# %d: %s" % (index, shape_text(shape))
        item = layout(Coll("(", [codes_, letters], ")"), 4, ",")
        # (a one-shape tuple has no magic trailing comma: black would join
        # it into one line but for a comment line inside)
        fits = len(item) == 1 and len(item[0]) + 2 + len(note) <= LINE_LENGTH
        if fits and len(shapes) > 1:
            lines.append("%s  %s" % (item[0], note))  # black keeps it there
            continue
        lines.append(INDENT + note)
        lines.extend(item)
    lines.append(")")
    return lines


def as_printed(rows: List[Tuple[nodes.Line, Row]]) -> Optional[List[str]]:
    """The rows' value cells written as rs274's trace prints numbers (four
    decimals), if that is exact for every value; else None.

    ``12.345`` becomes ``12.3450``: the same float, and the very text of the
    trace line, so runtime.fast.printed_rows writes a CAM file's trace without
    reading or formatting a float per value. (Done for the whole table at
    once: a million-line file pays for it in C loops, not per cell.)"""
    cells = " ".join([values for _, (_, values) in rows]).split()
    numbers = list(map(float, cells))
    printed = list(map("%.4f".__mod__, numbers))
    if list(map(float, printed)) != numbers:
        return None
    lines = []
    at = 0
    for _, (shape, _) in rows:
        width = len(shape[1])
        if shape[1][:1] == ("n",):
            printed[at] = cells[at]  # the N number stays as written
        lines.append(" ".join(printed[at : at + width]))
        at += width
    return lines


def row_table(name: str, cells: List[str], printed: bool = False) -> List[str]:
    """``ROWS_n`` as a triple-quoted string: one G-code line per text line
    (see runtime.fast.rows for why a table is text)."""
    lines = [
        "",
        "",
        "# G-code line, shape (see SHAPES), word values%s"
        % (" as the trace prints them" if printed else ""),
        '%s = """' % name,
    ]
    lines.extend(cells)
    lines.append('"""')
    return lines


def code_name(code: int) -> str:
    """The ``runtime.codes`` constant generated code imports for ``code``."""
    return codes.constant_name(code)


def code_order(name: str) -> Tuple[str, float]:
    """G codes before M codes, numerically (G1, G2, G10, G59_1...)."""
    return (name[0], float(name[1:].replace("_", ".")))


def executed_if_flag(program: st.Program) -> bool:
    """Must the code track rs274's ``executed_if`` (structure.FlatArm)?
    Only programs with an else or elseif line checked at run time pay, and
    those where something can leave the flag clear (:func:`clears_flag`)
    while an if with more than one arm is around."""
    bodies = [program.body] + [sub.body for sub in program.externals]
    stmts = [s for body in bodies for s in st.walk(body)]
    if any(
        isinstance(s, st.LabelCheck) and s.kind in ("else", "elseif") for s in stmts
    ):
        return True
    if any(
        isinstance(s, st.ArmAgain)
        or (
            isinstance(s, st.DoEnd)
            and any(isinstance(r, st.ArmAgain) for r in s.resume)
        )
        for s in stmts
    ):
        return True  # later arms run into again
    return any(clears_flag(s) for s in stmts) and any(
        isinstance(s, st.If) and len(s.branches) + (s.orelse is not None) > 1
        for s in stmts
    )


def _after_else(body: List[st.Stmt]) -> List[st.ArmAgain]:
    """The elseif lines after the else line of an if (structure.ArmAgain,
    each in the arm of the one before), in text order."""
    found = []
    while True:
        arm = next((s for s in body if isinstance(s, st.ArmAgain)), None)
        if arm is None:
            return found
        if arm.line.oword.keyword == "elseif":
            found.append(arm)
        body = arm.body


def real_arms(stmt: st.If) -> List[st.Branch]:
    """The arms of ``stmt`` that have a line of their own (not the end of
    the file an if never closed skips to: structure._Builder._abandon)."""
    arms = stmt.branches + ([stmt.orelse] if stmt.orelse else [])
    if stmt.orelse is not None and stmt.orelse.line is stmt.branches[-1].line:
        arms.pop()
    return arms


def clears_flag(stmt: st.Stmt) -> bool:
    """Can ``stmt`` leave rs274's flag "an arm of an if has run" clear when
    it is done? A false if clears it and its endif sets it again, unless
    the skip lands on a line reusing the label first (``If.landings``) and
    runs on from there; an else or elseif run into outside its if runs on
    with the flag clear (structure.FlatArm)."""
    if isinstance(stmt, st.If):
        return bool(stmt.landings)
    return isinstance(stmt, st.LabelCheck) and stmt.kind in ("else", "elseif")


def stale_break_flag(program: st.Program) -> bool:
    """Must the code track rs274's ``doing_break``?

    rs274 sets it on every ``break`` and clears it only at the closing
    ``while`` of a do-loop, which then does not loop back. A do-loop's own
    break clears it there, but a while-loop's break leaves it set, so the
    next do-loop to reach its ``while`` ends after one pass. rs274 also
    *skips* through break lines: a while-loop ending by its condition, or a
    continue, skips forward to the next line with the loop's label and a
    break line on the way sets the flag too. Only programs with breaks and
    do-loops pay for the flag (``m.doing_break``).
    """
    stmts = list(st.walk(program.body))
    for sub in program.externals:
        stmts.extend(st.walk(sub.body))
    jumps = any(isinstance(s, st.Jump) and s.kind == "break" for s in stmts)
    loops = any(isinstance(s, st.Loop) and s.kind == "do" for s in stmts)
    return jumps and loops


def left_early(loop: st.Loop) -> bool:
    """Can ``loop`` be left before it ends by itself: a return from inside,
    a jump to an outer loop, no closing line?"""
    if loop.end is None:
        return True
    inside = list(st.walk(loop.body, into_subs=False))
    loops = {id(s) for s in inside if isinstance(s, st.Loop)}
    return any(
        isinstance(s, (st.Return, st.TopReturn))
        or (isinstance(s, st.Jump) and id(s.target) not in loops)
        for s in inside
    )


def own_jumps(loop: st.Loop) -> List[st.Jump]:
    """The break and continue lines of ``loop``, at any depth of its body."""
    return [
        s for s in st.walk(loop.body) if isinstance(s, st.Jump) and s.target is loop
    ]


def break_after(jump: st.Jump) -> bool:
    """Is there a break line of ``jump``'s loop after ``jump``?"""
    return any(
        j.kind == "break" and j.line.number > jump.line.number
        for j in own_jumps(jump.target)
    )


def stale_continue_flag(program: st.Program) -> bool:
    """Must the code track rs274's ``doing_continue`` (runtime.loopflags)?
    Only when a do-loop's continue can leave it set for a while-loop's break
    or a repeat loop."""
    stmts = list(st.walk(program.body))
    for sub in program.externals:
        stmts.extend(st.walk(sub.body))
    sets = any(
        type(s) is st.Jump
        and (s.kind == "continue" and s.target.kind == "do" or s.flag == "continue")
        for s in stmts
    )
    hit = any(
        (isinstance(s, st.Jump) and s.kind == "break" and s.target.kind == "while")
        or (isinstance(s, st.Loop) and s.kind == "repeat")
        for s in stmts
    )
    return sets and hit


def oword_values(line: nodes.Line) -> List[nodes.Expr]:
    """The values of a line's O-word that rs274 reads: the name
    expression, the condition/count/value, then the call arguments."""
    word = line.oword
    if word is None:
        return []
    values = [word.name] if isinstance(word.name, nodes.Expr) else []
    if word.expr is not None:
        values.append(word.expr)
    return values + list(word.args)


class Helper(Value):
    """A nesting helper to write: function ``name`` runs ``stmt``, inside
    the enclosing ``loops`` of its call site, in file ``file_index``."""

    __slots__ = ("name", "stmt", "loops", "file_index")

    def __init__(
        self, name: str, stmt: st.Stmt, loops: List[st.Loop], file_index: int
    ) -> None:
        self.name = name
        self.stmt = stmt
        self.loops = loops
        self.file_index = file_index


def outward_exits(
    stmt: st.Stmt, stale_continue: bool = False
) -> Tuple[List[Tuple[str, st.Loop]], bool]:
    """The jumps out of ``stmt`` to loops around it, as (kind, loop) in
    first-use order, and whether a subroutine ``return`` is inside it.
    ``stale_continue``: the code tracks rs274's ``doing_continue``, with
    which a while-loop's break is a continue (:meth:`CodeGen.stale_continue`)."""
    inside = {id(s) for s in st.walk([stmt], into_subs=False)}
    jumps: List[Tuple[str, st.Loop]] = []
    returns = False
    for s in st.walk([stmt], into_subs=False):
        if isinstance(s, st.Return):
            returns = True
        elif isinstance(s, st.Jump) and id(s.target) not in inside:
            kinds = [s.kind]
            if stale_continue and s.kind == "break" and s.target.kind == "while":
                kinds.append("continue")
            for kind in kinds:
                if not any(k == kind and t is s.target for k, t in jumps):
                    jumps.append((kind, s.target))
    return jumps, returns


def opening_line(stmt: st.Stmt) -> nodes.Line:
    """The line an if or loop starts on."""
    return stmt.branches[0].line if isinstance(stmt, st.If) else stmt.line


class ItemRead(Value):
    """The code reading one item of a line: ``checks`` run first (a
    setting's index check, a name's creation), then ``value``; ``target`` is
    where a setting stores it (None for a word)."""

    __slots__ = ("value", "constant", "target", "checks")

    def __init__(
        self,
        value: str,
        constant: bool,
        target: Optional[str] = None,
        checks: Optional[List[str]] = None,  # None: a new empty list
    ) -> None:
        self.value = value
        self.constant = constant
        self.target = target
        self.checks = [] if checks is None else checks


def plain_read_index(n: float) -> bool:
    """Is ``#n`` (a constant) read straight from ``p = m.params.values``?"""
    return n == int(n) and 1 <= n < MAX_PARAMETERS and n not in POSITION_PARAMS


def plain_write_index(n: float) -> bool:
    """May ``#n = ...`` (a constant) be set straight into ``p``? Otherwise
    the index goes through rs274's checks, before the value is evaluated."""
    if n != int(n):
        return False
    try:
        Params.setting_index(n)
    except GCodeError:
        return False
    return True


#: The read errors a G7x profile line does not have: rs274 reads U and W
#: (as incremental X and Z) while it reads one.
_PROFILE_LETTERS = {"Bad character 'u' used", "Bad character 'w' used"}


def profile_reading(line: nodes.Line) -> Optional[nodes.Line]:
    """How rs274 reads ``line`` inside a G7x profile, if that differs."""
    if line.error not in _PROFILE_LETTERS:
        return None
    return parser.parse_line(line.text, line.number, line.file, DEFAULT_AXES + "uw")


def def_header(name: str, returns: str = "") -> List[str]:
    """``def name(m: Machine)<returns>:`` as black lays it out: a name too
    long for one line puts the parameter on a line of its own."""
    line = "def %s(m: Machine)%s:" % (name, returns)
    if len(line) <= LINE_LENGTH:
        return [line]
    return ["def %s(" % name, "%sm: Machine," % INDENT, ")%s:" % returns]


def fail_call(line: int, message: str) -> str:
    return "m.fail(%d, %s)" % (line, string(message))


def safe_doc(text: str) -> str:
    """Text for a docstring: printable, no quotes or backslashes."""
    return printable(text).replace("\\", "/").replace('"', "'")


def import_lines(module: str, names: Iterable[str]) -> List[str]:
    """``from module import a, b`` in black's layout."""
    names = list(names)
    one = "from %s import %s" % (module, ", ".join(names))
    if len(one) <= LINE_LENGTH:
        return [one]
    return (
        ["from %s import (" % module] + ["%s%s," % (INDENT, n) for n in names] + [")"]
    )


def stmt_line(stmt: st.Stmt) -> Optional[nodes.Line]:
    """The G-code line a statement starts on."""
    if isinstance(stmt, st.If):
        return stmt.end or stmt.branches[-1].line
    if isinstance(stmt, st.Define):
        return stmt.sub.end or stmt.sub.line
    if isinstance(stmt, st.Loop):
        return stmt.end or stmt.line
    if isinstance(stmt, st.Block) and type(stmt.line) is RowRun:
        return stmt.line.final()
    return getattr(stmt, "line", None)


def source_map_lines(
    w: ModuleWriter,
    subs: Coll,
    end: Tuple[int, bool],
    opening: Optional[str],
    unskippable: Optional[Coll] = None,
    block_delete: Optional[bool] = None,
    pack: bool = True,
) -> List[str]:
    """``__ngc__ = SourceMap(files, line map, texts, subs, end[, open error]
    [, unskippable=...][, block_delete=...])``, black's layout.

    Texts are one string per file, lines joined by newlines (only the lines
    the map refers to; others are empty), which compiles to one constant.
    A text longer than PACK_TEXT_OVER is packed (packed_literal) where
    ``pack`` is set, else written as it is where it can be (plain_literal).
    """
    texts = []
    packed: List[str] = []
    for table, blocks in zip(w.texts, w.blocks):
        text = joined_texts(table, blocks)
        if len(text) > PACK_TEXT_OVER:
            name = "_NGC_TEXT_%d" % len(packed)
            literal = None if pack else plain_literal(text)
            if literal is None:
                packed += ["# The G-code text of %s, compressed (it is large)." % name]
                literal = packed_literal(text)
            else:
                packed += ["# The G-code text of %s." % name]
            packed += ["%s = %s" % (name, literal), "", ""]
            texts.append(name)
        else:
            texts.append(string(text))
    call = Coll(
        "__ngc__ = SourceMap(",
        [
            Coll("(", [string(f) for f in w.files], ")"),
            string(w.map.encode()),
            Coll("(", texts, ")"),
            subs,
            Coll("(", ["%d" % end[0], str(end[1])], ")"),
        ]
        + ([opening] if opening else [])
        + ([unskippable] if unskippable else [])
        + ([] if block_delete is None else ["block_delete=%s" % block_delete]),
        ")",
    )
    return packed + call.layout(0)


#: A file's G-code text longer than this goes into the source map
#: compressed: a large CAM file's text would otherwise be a third of the
#: module that Python compiles on every ``python prog.py``.
PACK_TEXT_OVER = 1 << 16


def packed_literal(text: str) -> str:
    """A bytes literal of ``text`` deflated and in base64, 76 characters a
    line (runtime.errors.SourceMap unpacks it when an error needs a line).
    The fastest level: converting a million-line file must stay quick, and
    the literal's size costs a run little (about 5 ns a byte to compile)."""
    data = base64.b64encode(zlib.compress(text.encode("utf-8", "surrogateescape"), 1))
    # base64.encodebytes' lines, without its Python loop over 57-byte pieces
    lines = [data[at : at + 76] for at in range(0, len(data), 76)]
    return 'b"""\\\n%s\n"""' % b"\n".join(lines).decode("ascii")


def plain_literal(text: str) -> Optional[str]:
    """``text`` and a newline as a triple-quoted literal, written as it is,
    or None where the text holds what could end or change the literal (a
    quote, a backslash, a carriage return, NUL, a character that is not
    ASCII). For the compile cache's modules, which no one reads and which
    are compiled without tokenizing such a literal (ngc2py/bytecode.py): a
    100k-line file is not compressed on its first run (some 70 ms); the
    newline added is a line past the file's last, which has no text."""
    if not text.isascii() or any(mark in text for mark in ('"', "\\", "\r", "\0")):
        return None
    return '"""\\\n%s\n"""' % text


def joined_texts(table: Dict[int, str], blocks: List[Tuple[int, str]]) -> str:
    """One file's line texts (``table``: line -> text, ``blocks``: runs of
    lines) joined by newlines from line 1, lines not given empty."""
    pieces = [(number, 1, text) for number, text in table.items()]
    pieces += [(number, text.count("\n") + 1, text) for number, text in blocks]
    pieces.sort(key=lambda piece: piece[0])
    out: List[str] = []
    at = 1  # the next line to write
    for number, count, text in pieces:
        if number + count <= at:
            continue  # written already (a line can be mapped twice)
        if number < at:
            text = text.split("\n", at - number)[-1]
            number, count = at, count - (at - number)
        if number > at:
            out.append("\n" * (number - at - 1))
        out.append(text)
        at = number + count
    return "\n".join(out)


def generate(
    program: st.Program,
    source_name: str,
    opening: Optional[nodes.Line] = None,
    pack: bool = True,
) -> str:
    """The Python module text for ``program``; ``opening`` is the ``%`` line
    that demarcates the file, if it is demarcated; ``pack``: see
    :func:`source_map_lines`."""
    return CodeGen(program, source_name, opening, pack).module()


def _first_line(landing: List[st.Stmt]) -> int:
    """The number of the line a landing's statements come from."""
    line = opening_line(landing[-1]) if isinstance(landing[-1], st.Loop) else None
    return (line or landing[0].line).number


def _fail_order(stmt: st.Stmt) -> float:
    """Where a failure statement stands in the file (unknown: at the end)."""
    line = getattr(stmt, "line", None)
    return float("inf") if line is None else line.number


def _to_end_of_file(fail: st.Stmt) -> bool:
    """Is ``fail`` the end of the file a skip runs into?"""
    return getattr(fail, "message", None) in (st.EOF_NO_END, st.EOF_NO_PERCENT)


def _reads_stop(fail: st.Stmt) -> Optional[int]:
    """The line before which a skip that ends in ``fail`` reads M98 lines
    (skipped_reads): the line it fails at, but for the end of the file,
    named by its last line, which rs274 reads first (None: all of them)."""
    if _to_end_of_file(fail):
        return None
    order = _fail_order(fail)
    return None if order == float("inf") else int(order)
