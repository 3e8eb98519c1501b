"""One line of G-code -> :class:`ngc2py.nodes.Line`, as rs274 reads it.

rs274 reads a line left to right with one small reader per item, and
evaluates every value as soon as it has read it.  This module mirrors those
readers over the normalised line (see :mod:`ngc2py.lexer`) but builds
expression trees instead of values, so the generated code can evaluate them
later in the same order.  Checks that depend only on what is written (a
second X word, an unknown character, a malformed number, a constant G code
that does not exist, ...) are made here with rs274's exact messages; the
position of the first failure decides ``Line.items`` (what rs274 read, and
therefore evaluated, before failing) and ``Line.error``.

Checks that depend on values known only at run time (``F[#1]`` negative,
``G[#1]`` unknown) are the runtime's; for literal values they are made here
so their order relative to later read errors is rs274's.  When reading
fails inside an item, the values rs274 had already computed there are kept
in ``Line.partial`` so their errors (a division by zero, say) still come
first.

Value rules (G/M validity, modal groups, negative F/S/H/L/T, ...) are
``runtime.codes``'s and comment rules ``runtime.comments``'s: the parser
applies them to literals, the runtime to computed values.  Lines of the
common CAM shape (``N10 G1 X1.5 Y2 (c)``) take a fast path that builds the
same Line with the same checks (:func:`read_simple_line`).
"""

from __future__ import annotations

import gc
import math
import re
from contextlib import contextmanager
from functools import lru_cache

from ngc2py import source
from ngc2py.lexer import Normalised, normalise
from ngc2py.nodes import (
    Assign,
    Atan2,
    Binary,
    Bracket,
    Comment,
    Exists,
    Expr,
    Line,
    NamedParam,
    Num,
    NumParam,
    OWord,
    Unary,
    Word,
)
from ngc2py.records import Frozen, Value, replace
from runtime import codes, comments
from runtime.errors import GCodeError

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, FrozenSet, Iterator, List, Optional, Tuple, Union

#: Axis letters rs274 reads when no INI file configures others.
DEFAULT_AXES = "xyzabc"

#: Numbered parameters are 1 .. MAX_PARAMETER (RS274NGC_MAX_PARAMETERS - 1).
MAX_PARAMETER = 5601

#: Numbered parameters a program may read but not set.
READ_ONLY_PARAMETERS = frozenset(range(5400, 5414)) | frozenset(range(5420, 5429))

#: rs274 allows at most this many ``[arg]`` on an ``o... call`` line.
MAX_CALL_ARGUMENTS = 30

#: Word letters whose repetition on a line rs274 rejects (u, v, w only when
#: they are configured axes; they are added per parse).
_REPEAT_CHECKED = frozenset("abcdefhijklrstxyz")

#: Binary operators by precedence (higher binds tighter); "]" ends a group.
_PRECEDENCE = {
    "]": 1,
    "and": 2,
    "or": 2,
    "xor": 2,
    "eq": 3,
    "ne": 3,
    "gt": 3,
    "ge": 3,
    "lt": 3,
    "le": 3,
    "+": 4,
    "-": 4,
    "*": 5,
    "/": 5,
    "mod": 5,
    "**": 6,
}

#: After the first letter of a binary operator name, the rest rs274 accepts.
_OPERATOR_NAMES = {
    "a": ("nd",),
    "m": ("od",),
    "o": ("r",),
    "x": ("or",),
    "e": ("q",),
    "n": ("e",),
    "g": ("e", "t"),
    "l": ("e", "t"),
}

#: Unary function names by first letter, in the order rs274 tries them.
_UNARY_NAMES = {
    "a": ("abs", "acos", "asin", "atan"),
    "c": ("cos",),
    "e": ("exp", "exists"),
    "f": ("fix", "fup"),
    "l": ("ln",),
    "r": ("round",),
    "s": ("sin", "sqrt"),
    "t": ("tan",),
}

#: O-word keywords in the order rs274 compares them (prefix matches).
_OWORD_ORDER = (
    "sub",
    "endsub",
    "call",
    "do",
    "while",
    "repeat",
    "if",
    "elseif",
    "else",
    "endif",
    "break",
    "continue",
    "endwhile",
    "endrepeat",
    "return",
)

#: O-word keywords followed by a mandatory ``[condition]``.
_OWORD_CONDITION = ("while", "repeat", "if", "elseif")
#: Letters whose legal repetition replaces the earlier literal word.
_OVERWRITTEN_BY_REPEAT = frozenset("pq@^")

#: The characters rs274 hands to its number conversion.
_NUMBER_SPAN = re.compile(r"[+-]*[0-9.]*")

#: What rs274's istream conversion accepts of such a span.
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)")

#: The end-of-line sentinel (C's NUL terminator).
_END = "\0"


class _ReadError(Exception):
    """rs274 stopped reading the line with ``message``."""

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message


# --------------------------------------------------------------------------
# Helpers on expressions
# --------------------------------------------------------------------------


def _literal(expr: Expr) -> Optional[float]:
    """The value of ``expr`` if it is a literal number, else None."""
    return expr.value if isinstance(expr, Num) else None


def _fold(op: str, left: Expr, right: Expr) -> Expr:
    """Binary node, computed now when both sides are literal and IEEE
    arithmetic gives rs274's answer without any error (+ - * and / by a
    non-zero number with a finite result); everything else is left to
    ``runtime.ops`` so its error messages stay in one place."""
    a, b = _literal(left), _literal(right)
    if a is not None and b is not None and op in "+-*/" and not (op == "/" and b == 0):
        value = {"+": a + b, "-": a - b, "*": a * b}[op] if op != "/" else a / b
        if math.isfinite(value):
            return Num(value)
    return Binary(op, left, right)


def _comment(body: str) -> Comment:
    """The Comment for the text between the parentheses."""
    active = comments.classify(body)
    return Comment(active.kind, active.text)


def _oword_number(value: Expr) -> Union[str, Expr]:
    """An O-word's (or M98's P) number as its label, if it is a literal."""
    number = _literal(value)
    if number is None:
        return value
    try:
        return "%d" % codes.to_integer(number)
    except GCodeError as error:
        raise _ReadError(error.message) from None


def _bracket(inner: Expr) -> Expr:
    """``[inner]`` as a :class:`Bracket`, unless its check cannot fail or
    would repeat one already made (see ``Bracket``)."""
    if isinstance(inner, (Num, Bracket)):
        return inner
    return Bracket(inner)


def _negate(expr: Expr) -> Expr:
    value = _literal(expr)
    return Num(-value) if value is not None else Unary("neg", expr)


def _bad_character(char: str) -> str:
    """rs274's message for a character no reader accepts."""
    byte = source.first_byte(char)
    if 33 <= byte <= 122:
        return "Bad character '%s' used" % char
    return "Bad character '\\%03o' used" % byte


# --------------------------------------------------------------------------
# The line reader
# --------------------------------------------------------------------------


class _Block(Value):
    """What has been read from the line so far."""

    __slots__ = ("n", "items", "comments", "oword", "oword_unread", "seen", "groups")

    def __init__(
        self,
        n: Optional[float] = None,
        items: Optional[List[Union[Word, Assign]]] = None,  # None: a new list
        comments: Optional[List[Comment]] = None,  # None: a new list
        oword: Optional[OWord] = None,
        oword_unread: bool = False,
        seen: Optional[Dict[str, Word]] = None,  # None: a new dict
        groups: Optional[Dict[str, Dict[int, int]]] = None,  # None: a new one
    ) -> None:
        self.n = n
        self.items = [] if items is None else items
        self.comments = [] if comments is None else comments
        self.oword = oword
        self.oword_unread = oword_unread  # reading an O-word's label or keyword, or N
        self.seen = {} if seen is None else seen  # letter -> last word
        #: "g"/"m" -> modal group -> code, for the literal codes read so far.
        self.groups = {"g": {}, "m": {}} if groups is None else groups


@lru_cache(maxsize=None)
def _letters(axes: str) -> Tuple[FrozenSet[str], FrozenSet[str]]:
    """(word letters rs274 reads, letters it allows once per line)."""
    axis_letters = frozenset(axes)
    return (
        frozenset("defghijklmpqrst$@^") | axis_letters,
        _REPEAT_CHECKED | axis_letters,
    )


class _LineReader:
    """rs274's readers over one normalised line; fills a :class:`_Block`."""

    def __init__(self, text: str, columns: List[int], axes: str):
        self.text = text
        self.columns = columns
        self.pos = 0
        self.letters, self.repeat_checked = _letters(axes)
        self.block = _Block()
        # Values rs274 has computed inside items still being read, one list
        # per open construct; what is left here when reading fails is
        # Line.partial.  Constructs pop their list when they complete.
        self.open_values: List[List[Expr]] = []

    # -- characters ---------------------------------------------------------

    def peek(self, offset: int = 0) -> str:
        index = self.pos + offset
        return self.text[index] if index < len(self.text) else _END

    def take(self) -> str:
        char = self.peek()
        self.pos += 1
        return char

    def looking_at(self, word: str) -> bool:
        return self.text.startswith(word, self.pos)

    def partial(self) -> Tuple[Expr, ...]:
        """Line.partial: computed values of the items left unfinished."""
        values = (v for frame in self.open_values for v in frame)
        return tuple(v for v in values if not isinstance(v, Num))

    def column(self) -> int:
        return self.columns[self.pos] if self.pos < len(self.columns) else 0

    # -- the line -------------------------------------------------------------

    def read_line(self) -> None:
        """rs274's read_items: optional N, then an O-word line or items."""
        if self.peek() == "/":
            self.pos += 1
        if self.peek() == "n":
            self.read_line_number()
        if self.peek() == "o":
            self.read_oword()
            return
        fanuc = self.fanuc_m_code()
        if fanuc == 98:
            self.read_m98()
            return
        if fanuc == 99:
            self.block.oword = OWord("m99", "", in_call_error=self.m99_call_error())
        while self.pos < len(self.text):
            self.read_item()

    def read_line_number(self) -> None:
        # rs274 reads the N word before it asks whether it is skipping: a
        # bad one fails even in a definition or an arm not taken (it counts
        # as a line it cannot skip, like an O-word it cannot read).
        self.block.oword_unread = True
        self.pos += 1
        self.block.n = float(self.read_unsigned())
        if self.peek() == ".":  # fractional line numbers are read and ignored
            self.pos += 1
            self.read_unsigned()
        self.block.oword_unread = False

    def read_unsigned(self) -> int:
        start = self.pos
        while "0" <= self.peek() <= "9":
            self.pos += 1
        if self.pos == start:
            raise _ReadError("Bad format unsigned integer")
        return int(self.text[start : self.pos])

    def fanuc_m_code(self) -> Optional[int]:
        """98 or 99 when the line's first item is that M code (a literal).

        rs274 reads the M value ahead to decide whether the line is a
        Fanuc-style call or return (see ``OWord``); a value it cannot read
        here is read again, with its error, as an ordinary word.
        """
        if self.peek() != "m":
            return None
        saved, frames = self.pos, len(self.open_values)
        self.pos += 1
        try:
            value = _literal(self.read_real_value())
            number = None if value is None else codes.to_integer(value)
        except (_ReadError, GCodeError):
            number = None
        finally:
            self.pos = saved
            del self.open_values[frames:]
        return number if number in (98, 99) else None

    def read_m98(self) -> None:
        """``M98 P.. [L..]``: rs274 skips three characters for ``m98`` and
        reads the rest of the line as ordinary items. It does so in read_o,
        before it asks whether it is skipping: a line it cannot read fails
        even in an arm not taken or a definition (``oword_unread``)."""
        self.block.oword_unread = True
        self.pos += 3
        while self.pos < len(self.text):
            self.read_item()
        program = self.block.seen.get("p")
        if program is None:
            raise _ReadError("Found 'm98' code with no P-word")
        repeat = self.block.seen.get("l")
        self.block.oword = OWord(
            "m98",
            _oword_number(program.value),
            expr=None if repeat is None else repeat.value,
        )
        self.block.oword_unread = False

    def m99_call_error(self) -> Optional[str]:
        """What reading ``M99`` as a return fails with: after the three
        characters of ``m99`` only comments may follow."""
        rest = self.text[self.pos + 3 :]
        while rest.startswith("("):
            rest = rest[rest.index(")") + 1 :]
        if rest and not rest.startswith(";"):
            return "Unexpected character after O-word"
        return None

    def read_item(self) -> None:
        """rs274's read_one_item: dispatch on the item's first character."""
        char = self.peek()
        if char == "#":
            self.read_parameter_setting()
        elif char == "(":
            self.read_comment()
        elif char == ";":
            self.pos = len(self.text)
        elif char in self.letters:
            self.read_word(char)
        else:
            raise _ReadError(_bad_character(char))

    def read_comment(self) -> None:
        end = self.text.index(")", self.pos)  # the lexer guarantees one
        self.block.comments.append(_comment(self.text[self.pos + 1 : end]))
        self.pos = end + 1

    # -- words ----------------------------------------------------------------

    def read_word(self, letter: str) -> None:
        column = self.column()
        self.pos += 1
        self.check_repeat(letter)
        self.store_word(Word(letter, self.read_real_value(), column))

    def store_word(self, word: Word) -> None:
        """Check a word just read and add it to the block."""
        self.check_value(word)
        letter = word.letter
        previous = self.block.seen.get(letter)
        if (
            previous is not None
            and letter in _OVERWRITTEN_BY_REPEAT
            and _literal(previous.value) is not None
        ):
            # A legal repeat (P/Q after a negative literal, @, ^) overwrites;
            # G and M words repeat too, but each one counts.
            self.block.items.remove(previous)
        self.block.items.append(word)
        self.block.seen[letter] = word

    def check_repeat(self, letter: str) -> None:
        previous = self.block.seen.get(letter)
        if previous is None:
            return
        if letter in self.repeat_checked:
            raise _ReadError("Multiple %s words on one line" % letter)
        if letter == "$":
            raise _ReadError("Multiple spindle choice ($) words on one line")
        if letter in "pq":
            # rs274 marks "no P/Q yet" with -1.0, so a value <= -1 can be
            # followed by another P/Q.
            value = _literal(previous.value)
            if value is None or value > -1.0:
                raise _ReadError("Multiple %s words on one line" % letter)

    def check_value(self, word: Word) -> None:
        """rs274's checks on a word's value, made now when it is a literal."""
        value = _literal(word.value)
        if value is None:
            return
        try:
            checked = codes.check_word(word.letter, value)
            if word.letter in "gm":
                codes.record_code(self.block.groups[word.letter], checked)
        except GCodeError as error:
            raise _ReadError(error.message) from None

    # -- parameter settings ---------------------------------------------------

    def read_parameter_setting(self) -> None:
        column = self.column()
        self.pos += 1
        if self.peek() == "<":
            target: Union[NumParam, NamedParam] = NamedParam(self.read_name())
        else:
            index = self.read_real_value()
            self.check_parameter_index(index, setting=True)
            target = NumParam(index)
            # rs274 has range-checked the index; reading the parameter
            # repeats that check if the setting is cut short.
            self.open_values.append([target])
        if self.peek() != "=":
            raise _ReadError("Equal sign missing in parameter setting")
        self.pos += 1
        value = self.read_real_value()
        if isinstance(target, NumParam):
            self.open_values.pop()
        self.block.items.append(Assign(target, value, column))

    @staticmethod
    def check_parameter_index(index: Expr, setting: bool = False) -> None:
        value = _literal(index)
        if value is None:
            return
        try:
            number = codes.to_integer(value)
        except GCodeError as error:
            raise _ReadError(error.message) from None
        if not 1 <= number <= MAX_PARAMETER:
            raise _ReadError("Parameter number out of range")
        if setting and number in READ_ONLY_PARAMETERS:
            raise _ReadError("Parameter is readonly")

    def read_name(self) -> str:
        """``<name>`` after ``#`` or ``o``: everything up to ``>``."""
        end = self.text.find(">", self.pos + 1)
        if end == -1:
            raise _ReadError("Named parameter not terminated")
        name = self.text[self.pos + 1 : end]
        self.pos = end + 1
        return name

    # -- values -----------------------------------------------------------------

    def read_real_value(self) -> Expr:
        char, after = self.peek(), self.peek(1)
        if char == _END:
            raise _ReadError("No characters found in reading real value")
        if char == "[":
            return self.read_bracket()
        if char == "#":
            return self.read_parameter()
        if char in "+-" and after != _END and not after.isdigit() and after != ".":
            self.pos += 1
            value = self.read_real_value()
            return _negate(value) if char == "-" else value
        if "a" <= char <= "z":
            return self.read_unary()
        return self.read_number()

    def read_number(self) -> Num:
        span = _NUMBER_SPAN.match(self.text, self.pos).group()
        self.pos += len(span)
        match = _NUMBER.match(span)
        if match is None:
            raise _ReadError(
                "bad number format (conversion failed) parsing '%s'" % span
            )
        if match.end() != len(span):
            raise _ReadError(
                "bad number format (trailing characters) parsing '%s'" % span
            )
        return Num(float(match.group()))

    def read_parameter(self) -> Expr:
        self.pos += 1
        if self.peek() == "<":
            return NamedParam(self.read_name())
        index = self.read_real_value()
        self.check_parameter_index(index)
        return NumParam(index)

    def read_bracket(self) -> Expr:
        """A bracketed value, which rs274 checks for inf/NaN at its ``]``."""
        return _bracket(self.read_expression())

    def read_expression(self) -> Expr:
        """``[v op v op ... ]`` with rs274's precedence, left-associative.

        The value unchecked for inf/NaN, as rs274 reads a function's
        argument or an O-word's condition, count, value or call argument.
        """
        self.pos += 1
        values: List[Expr] = []
        self.open_values.append(values)
        values.append(self.read_real_value())
        operators: List[str] = []
        while True:
            operator = self.read_operator()
            while operators and _PRECEDENCE[operator] <= _PRECEDENCE[operators[-1]]:
                right = values.pop()
                values[-1] = _fold(operators.pop(), values[-1], right)
            if operator == "]":
                self.open_values.pop()
                return values[0]
            operators.append(operator)
            values.append(self.read_real_value())

    def read_operator(self) -> str:
        char = self.take()
        if char in "+-/]":
            return char
        if char == "*":
            if self.peek() == "*":
                self.pos += 1
                return "**"
            return "*"
        for rest in _OPERATOR_NAMES.get(char, ()):
            if self.looking_at(rest):
                self.pos += len(rest)
                return char + rest
        if char in _OPERATOR_NAMES:
            raise _ReadError("Unknown operation name starting with %s" % char)
        if char == _END:
            raise _ReadError("Unclosed expression")
        raise _ReadError("Unknown operation")

    def read_unary(self) -> Expr:
        name = self.read_unary_name()
        if self.peek() != "[":
            raise _ReadError("Left bracket missing after unary operation name")
        if name == "exists":
            return self.read_exists()
        argument = self.read_expression()
        if name != "atan":
            return Unary(name, argument)
        self.open_values.append([argument])
        if self.peek() != "/":
            raise _ReadError("Slash missing after first atan argument")
        self.pos += 1
        if self.peek() != "[":
            raise _ReadError("Left bracket missing after slash with atan")
        result = Atan2(argument, self.read_expression())
        self.open_values.pop()
        return result

    def read_unary_name(self) -> str:
        char = self.peek()
        for name in _UNARY_NAMES.get(char, ()):
            if self.looking_at(name):
                self.pos += len(name)
                return name
        if char in _UNARY_NAMES:
            raise _ReadError("Unknown word starting with %s" % char)
        raise _ReadError("Unknown word where unary operation could be")

    def read_exists(self) -> Expr:
        """``EXISTS[#<name>]``; for ``EXISTS[#n]``, whether n is a valid index."""
        self.pos += 1
        if self.peek() != "#":
            raise _ReadError("Expected # reading parameter")
        self.pos += 1
        if self.peek() == "<":
            result: Expr = Exists(self.read_name())
        else:
            result = self.numbered_exists(self.read_real_value())
        self.open_values.append([result])
        if self.peek() != "]":
            raise _ReadError("Expected ] reading bracketed parameter")
        self.pos += 1
        self.open_values.pop()
        return result

    @staticmethod
    def numbered_exists(index: Expr) -> Expr:
        value = _literal(index)
        if value is None:
            low, high = Num(1.0), Num(float(MAX_PARAMETER))
            return Binary("and", Binary("ge", index, low), Binary("le", index, high))
        try:
            number = codes.to_integer(value)
        except GCodeError as error:
            raise _ReadError(error.message) from None
        return Num(1.0 if 1 <= number <= MAX_PARAMETER else 0.0)

    # -- O-words ----------------------------------------------------------------

    def read_oword(self) -> None:
        """rs274's read_o, then only comments may follow."""
        self.block.oword_unread = True
        self.pos += 1
        if self.peek() == "<":
            if self.text.find(">", self.pos + 1) == -1:
                # rs274 ignores read_name's failure here: the name is the
                # rest of the line and the line a bare O-word.
                self.block.oword = OWord("fanuc_sub", self.text[self.pos + 1 :])
                self.block.oword_unread = False
                self.pos = len(self.text)
                return
            name: Union[str, Expr] = self.read_name()
        else:
            number = self.read_real_value()
            name = _oword_number(number)
            # Until the O-word is recognised, its computed name is partial.
            self.open_values.append([number])
        keyword = next((k for k in _OWORD_ORDER if self.looking_at(k)), None)
        if keyword is None and self.peek() not in ("(", ";", _END):
            raise _ReadError("Unknown control command in o word")
        self.pos += len(keyword or "")
        self.block.oword = OWord(keyword or "fanuc_sub", name)
        self.block.oword_unread = False
        if not isinstance(name, str):
            self.open_values.pop()
        if keyword is not None:
            self.read_oword_arguments(keyword, name)
        while self.pos < len(self.text):
            if self.peek() == ";":
                self.pos = len(self.text)
            elif self.peek() == "(":
                self.read_comment()
            else:
                raise _ReadError("Unexpected character after O-word")

    def read_oword_arguments(self, keyword: str, name: Union[str, Expr]) -> None:
        """The bracketed values that follow some keywords."""
        if keyword in ("endsub", "return") and self.peek() == "[":
            self.block.oword = OWord(keyword, name, expr=self.read_expression())
        elif keyword in _OWORD_CONDITION:
            if self.peek() != "[":
                raise _ReadError("Left bracket missing after '%s'" % keyword)
            self.block.oword = OWord(keyword, name, expr=self.read_expression())
        elif keyword == "call":
            args: List[Expr] = []
            while self.peek() in "[(":
                if self.peek() == "(":
                    self.read_comment()
                    continue
                if len(args) >= MAX_CALL_ARGUMENTS:
                    raise _ReadError("Too many subroutine parameters")
                args.append(self.read_expression())
                self.block.oword = OWord(keyword, name, args=tuple(args))


# --------------------------------------------------------------------------
# Lines and files
# --------------------------------------------------------------------------


def parse_line(
    text: str, number: int, file: str = "", axes: str = DEFAULT_AXES
) -> Line:
    """Read one line (no newline, trailing blanks already removed).

    ``axes`` are the axis letters rs274 accepts (from the INI file's
    coordinates; rs274 without one reads X Y Z A B C).
    """
    line = read_simple_line(text, number, file, axes)
    if line is None:
        line = read_any_line(text, normalise(text), number, file, axes)
    return line


def read_any_line(
    text: str, normalised: Normalised, number: int, file: str, axes: str
) -> Line:
    """Read one line with rs274's readers (``normalised`` is ``text``'s)."""
    block_delete = normalised.text.startswith("/")
    if normalised.error:
        # rs274 fails in close_and_downcase, before it looks for a block
        # delete slash: the line fails with block delete on too
        return Line(number, text, file, False, error=normalised.error)
    reader = _LineReader(normalised.text, normalised.columns, axes)
    error = None
    try:
        reader.read_line()
    except _ReadError as failure:
        error = failure.message
    if text.startswith(";py,") and error is None:
        # rs274 (read_semicolon) runs a line that begins exactly so as a
        # (py,...) comment: the raw text after the ';', parentheses and all
        reader.block.comments.append(_comment(text[1:]))
    line = _line(reader.block, text, number, file, block_delete, error, reader)
    alternative = _computed_m98(normalised, text, number, file, axes)
    if alternative is not None:
        line = replace(line, fanuc_value=alternative[0], fanuc_alt=alternative[1])
    return line


def _computed_m98(
    normalised: Normalised, text: str, number: int, file: str, axes: str
) -> Optional[Tuple[Expr, Line]]:
    """(M value, the line read as M98) for a line whose first item is an M
    word with a computed value: whether it is an M98 call is decided at run
    time (see Line.fanuc_alt). None for any other line."""
    reader = _LineReader(normalised.text, normalised.columns, axes)
    block_delete = reader.peek() == "/"
    if block_delete:
        reader.pos += 1
    try:
        if reader.peek() == "n":
            reader.read_line_number()
        if reader.peek() != "m":
            return None
        start = reader.pos
        reader.pos += 1
        value = reader.read_real_value()
    except (_ReadError, GCodeError):
        return None  # rs274's look-ahead fails: an ordinary line
    if _literal(value) is not None:
        return None  # a literal M98 is read as a call already
    reader.pos = start
    del reader.open_values[:]
    error = None
    try:
        reader.read_m98()
    except _ReadError as failure:
        error = failure.message
    alt = _line(reader.block, text, number, file, block_delete, error, reader)
    return value, alt


def _line(
    block: _Block,
    text: str,
    number: int,
    file: str,
    block_delete: bool = False,
    error: Optional[str] = None,
    reader: Optional[_LineReader] = None,
) -> Line:
    """The Line for what was read; ``reader`` supplies partial values."""
    return Line(
        number=number,
        text=text,
        file=file,
        block_delete=block_delete,
        n=block.n,
        n_text=None if block.n is None else trace_number(text),
        items=tuple(block.items),
        comments=tuple(block.comments),
        oword=block.oword,
        error=error,
        partial=reader.partial() if error and reader else (),
        oword_unread=bool(error) and block.oword_unread,
    )


# -- The fast path ---------------------------------------------------------
#
# Most lines of CAM output are a few words with plain numbers.  For them the
# general readers only split the line at letters; this path does the split
# with one regular expression and then stores the words with the very same
# checks.  It declines (returns None) whenever the line has anything else
# or any check fails, so errors always come from the general readers.

#: Blanks only between words, written ``X1.5`` (no blank inside a word), an
#: optional leading ``N123``, an optional comment at the end.
_SIMPLE_LINE = re.compile(
    r"[ \t]*(?:[nN]([0-9]+))?"
    r"((?:[ \t]*[A-Za-z][+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))*)"
    r"[ \t]*(\([^()]*\))?"
)
#: One word of such a line: (blanks before it, letter, number).
_SIMPLE_WORD = re.compile(r"([ \t]*)([A-Za-z])([+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))")

#: Letters whose values rs274 checks while reading (see codes.check_word).
_CHECKED_LETTERS = frozenset("gmhltfs")


@lru_cache(maxsize=None)
def _simple_letters(axes: str) -> Dict[str, str]:
    """Letter as written -> word letter, for the letters rs274 reads as words."""
    letters = _letters(axes)[0]
    return {c: c.lower() for c in letters | frozenset(c.upper() for c in letters)}


def _scan_simple(text: str, axes: str):
    """The words of a simple-shaped line that reads without error:
    ``(n_digits, [(letter, digits, value, checked, column)], comment)``, or
    None for any other line (the general readers then read it)."""
    shape = _SIMPLE_LINE.fullmatch(text)
    if shape is None:
        return None
    n_digits, words, comment = shape.groups()
    letters = _simple_letters(axes)
    found = []
    once: set = set()  # letters seen that may not repeat (G and M may)
    groups: Dict[str, Dict[int, int]] = {"g": {}, "m": {}}
    column = shape.start(2)
    for blanks, written, digits in _SIMPLE_WORD.findall(words):
        column += len(blanks)
        letter = letters.get(written)
        if letter is None or letter in once or letter == "m" and not found:
            return None  # N/O or not a word, a repeat, or maybe M98/M99
        value = checked = float(digits)
        if letter in _CHECKED_LETTERS:
            try:
                checked = codes.check_word(letter, value)
                if letter in groups:
                    codes.record_code(groups[letter], checked)
            except GCodeError:
                return None
        if letter not in groups:
            once.add(letter)
        found.append((letter, digits, value, checked, column))
        column += 1 + len(digits)
    return n_digits, found, comment


def read_simple_line(text: str, number: int, file: str, axes: str) -> Optional[Line]:
    """The Line for a line of the simple shape that reads without error,
    exactly as :func:`read_any_line` makes it; None for any other line."""
    scanned = _scan_simple(text, axes)
    if scanned is None:
        return None
    n_digits, found, comment = scanned
    items = tuple(
        Word(letter, Num(value), column) for letter, _, value, _, column in found
    )
    if n_digits is None:
        n = n_text = None
    else:
        n, n_text = float(int(n_digits)), trace_number(text)
    return Line(
        number,
        text,
        file,
        n=n,
        n_text=n_text,
        items=items,
        comments=() if comment is None else (_comment(comment[1:-1]),),
    )


def read_row_line(
    text: str, number: int, file: str, axes: str, shapes: Dict
) -> Optional["RowLine"]:
    """A :class:`RowLine` for a simple line of literal words only (no
    comment), with valid G and M codes; None otherwise. ``shapes`` interns
    the shapes of one file (a million rows share a handful)."""
    scanned = _scan_simple(text, axes)
    if scanned is None:
        return None
    n_digits, found, comment = scanned
    if comment is not None or not found:
        return None
    codes_: List[int] = []
    letters: List[str] = []
    cells: List[str] = []
    if n_digits is not None:
        n_text = trace_number(text)
        if not n_text:
            return None
        letters.append("n")
        cells.append(n_text)
    for letter, digits, _, checked, _ in found:
        if letter in "gm":
            codes_.append(checked)  # runtime.codes numbering
        else:
            letters.append(letter)
            cells.append(digits)  # float(digits) is the value read
    key = (tuple(codes_), tuple(letters))
    shape = shapes.setdefault(key, key)
    return RowLine(number, text, file, axes, shape, " ".join(cells))


class RowLine:
    """A line that is only literal words: kept as its data row (see
    ngc2py.codegen's row tables) instead of a :class:`Line` of nodes, so a
    million-line CAM file stays small. It reads like a Line that has no
    O-word, error or comment; anything else is read again on demand."""

    __slots__ = ("number", "text", "file", "axes", "shape", "cells")
    oword = error = None
    oword_unread = False
    percent = block_delete = is_blank = False
    comments = ()

    def __init__(self, number, text, file, axes, shape, cells):
        self.number = number
        self.text = text
        self.file = file
        self.axes = axes
        self.shape = shape
        self.cells = cells

    def full(self) -> Line:
        """The same line as :func:`read_simple_line` reads it."""
        line = read_simple_line(self.text, self.number, self.file, self.axes)
        assert line is not None
        return line

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        return getattr(self.full(), name)


#: What rs274's trace skips before looking for ``N`` in the raw line.
_TRACE_SKIPPED = " \t/"

#: The digits the trace copies after that ``N``.
_TRACE_DIGITS = re.compile(r"[0-9]*")


def trace_number(raw: str) -> Optional[str]:
    """``Line.n_text`` for a line with an N word: the digits the trace
    prints, read from the raw text as rs274's trace reads them."""
    text = raw.lstrip(_TRACE_SKIPPED)
    if text[:1] not in ("n", "N"):
        return None
    return _TRACE_DIGITS.match(text, 1).group()


class ParsedFile(Frozen):
    """A whole file as rs274 would read it.

    ``demarcated``: the first non-blank line is ``%`` (rs274 then requires a
    closing ``%`` line).  ``closed``: that closing line exists; ``lines`` stops
    there (both ``%`` lines are included, with ``percent=True``).
    """

    __slots__ = ("file", "lines", "demarcated", "closed")

    def __init__(
        self, file: str, lines: List[Line], demarcated: bool, closed: bool
    ) -> None:
        object.__setattr__(self, "file", file)
        object.__setattr__(self, "lines", lines)
        object.__setattr__(self, "demarcated", demarcated)
        object.__setattr__(self, "closed", closed)


def parse_text(
    data: Union[bytes, str],
    file: str = "",
    axes: str = DEFAULT_AXES,
    runs: bool = False,
    main_percent: Optional[bool] = None,
) -> ParsedFile:
    """Parse a file's contents (bytes as read, or already-decoded text).

    With ``runs``, stretches of data rows come as :class:`rowrun.RowRun`
    items (many lines each) instead of one :class:`RowLine` per line: what
    the compiler reads; without, every line is its own item.

    ``main_percent`` (not None): a subroutine file, read under a main
    program that is demarcated by ``%`` (True) or not. rs274 has one flag
    for the main file: under a demarcated one every lone ``%`` line of any
    file ends the program (``percent=True`` lines), else such a line is an
    ordinary one (a bad character when run); the whole file is read either
    way, and ``demarcated`` is the main's."""
    if isinstance(data, str):
        data = source.encode(data)
    with _no_cyclic_gc():
        return _parse_lines(data, file, axes, runs, main_percent)


@contextmanager
def _no_cyclic_gc() -> Iterator[None]:
    """Pause Python's cycle collector: a large file makes hundreds of
    thousands of nodes, none in a cycle, and the collector's repeated passes
    over them would otherwise double the parse time."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


class _Reader:
    """Reads a file's lines one at a time, with the state of its ``%``
    demarcation."""

    def __init__(self, file: str, axes: str, main_percent: Optional[bool] = None):
        self.file = file
        self.axes = axes
        self.main_percent = main_percent  # see parse_text
        self.lines: List = []
        self.demarcated = self.closed = False
        self.seen_content = False
        self.shapes: Dict = {}  # row shapes, interned

    def read(self, raw: source.RawLine) -> None:
        file, axes = self.file, self.axes
        if raw.too_long:
            self.lines.append(
                Line(raw.number, raw.text, file, error=source.COMMAND_TOO_LONG)
            )
            self.seen_content = True
            return
        row = read_row_line(raw.text, raw.number, file, axes, self.shapes)
        if row is not None:
            self.seen_content = True
            self.lines.append(row)
            return
        simple = read_simple_line(raw.text, raw.number, file, axes)
        if simple is not None:  # never a % line
            self.seen_content = self.seen_content or not simple.is_blank
            self.lines.append(simple)
            return
        normalised = normalise(raw.text)
        if self.main_percent is not None:
            if normalised.text == "%" and self.main_percent:
                self.lines.append(Line(raw.number, raw.text, file, percent=True))
            else:
                self.lines.append(
                    read_any_line(raw.text, normalised, raw.number, file, axes)
                )
            return
        if normalised.text == "%" and self.demarcated == self.seen_content:
            # The first content line opens the demarcation; a later one
            # closes it.
            self.lines.append(Line(raw.number, raw.text, file, percent=True))
            self.closed, self.demarcated = self.demarcated, True
            self.seen_content = True
            return
        self.seen_content = self.seen_content or bool(normalised.text)
        self.lines.append(read_any_line(raw.text, normalised, raw.number, file, axes))


def _parse_lines(
    data: bytes, file: str, axes: str, runs: bool, main_percent: Optional[bool] = None
) -> ParsedFile:
    from ngc2py import rowrun

    reader = _Reader(file, axes, main_percent)
    lane = rowrun.Lane(file, axes, reader.shapes) if runs else None
    pos, number = 0, 0
    while pos < len(data) and not reader.closed:
        if lane is not None:
            end = lane.region_end(data, pos)
            if end > pos:
                items, end, count = lane.scan(data, pos, end, number + 1)
                for item in items:
                    if type(item) is rowrun.RowRun:
                        reader.lines.append(item)
                        reader.seen_content = True
                    else:  # never a % line
                        reader.read(item)
                number += count
                if end > pos:
                    pos = end
                    continue
        number += 1
        raw, pos = source.read_line(data, pos, number)
        reader.read(raw)
    if main_percent is not None:
        return ParsedFile(file, reader.lines, main_percent, False)
    return ParsedFile(file, reader.lines, reader.demarcated, reader.closed)


def parse_file(
    path: str,
    axes: str = DEFAULT_AXES,
    runs: bool = False,
    main_percent: Optional[bool] = None,
) -> ParsedFile:
    """Read and parse ``path``; OSError propagates (compile-time failure).
    ``main_percent``: see :func:`parse_text`."""
    return parse_text(source.read_file(path), path, axes, runs, main_percent)
