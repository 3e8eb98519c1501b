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
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple, Union

from ngc2py import source
from ngc2py.lexer import ascii_lower, normalise
from ngc2py.nodes import (
    Assign,
    Atan2,
    Binary,
    Comment,
    Exists,
    Expr,
    Line,
    NamedParam,
    Num,
    NumParam,
    OWord,
    ParamRef,
    Unary,
    Word,
)
from runtime import codes
from runtime.errors import GCodeError

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

#: Letters read with read_integer_value (the value must be near an integer).
_INTEGER_LETTERS = frozenset("hlmt")

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

#: Our own message for a construct rs274 accepts that ngc2py cannot compile.
_UNSUPPORTED = "ngc2py: unsupported: %s"


class _ReadError(Exception):
    """rs274 stopped reading the line with ``message``."""

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message


# --------------------------------------------------------------------------
# Comments
# --------------------------------------------------------------------------

#: Comment prefix -> kind, in the order rs274's convert_comment tests them.
#: PROBEOPEN/PROBECLOSE are plain comments in the installed rs274.
_COMMENT_PREFIXES = (
    ("msg,", "msg"),
    ("debug,", "debug"),
    ("print,", "print"),
    ("log,", "log"),
    ("logopen,", "logopen"),
    ("logappend,", "logappend"),
    ("abort,", "abort"),
)

#: Kinds whose text has #n / #<name> references expanded when executed.
_EXPANDING_COMMENTS = frozenset(("debug", "print", "log", "abort"))

#: C's isspace in the "C" locale.
_C_SPACE = " \t\n\v\f\r"


def classify_comment(body: str) -> Comment:
    """The Comment for the text between ``(`` and ``)``.

    rs274 skips leading white space, then matches the prefixes in any case;
    ``LOGCLOSE`` must be the whole remaining comment.  ``text`` is what rs274
    passes on, in the original case.
    """
    text = body.lstrip(_C_SPACE)
    lowered = ascii_lower(text)
    for prefix, kind in _COMMENT_PREFIXES:
        if lowered.startswith(prefix):
            rest = text[len(prefix) :]
            parts = split_parameters(rest) if kind in _EXPANDING_COMMENTS else ()
            return Comment(kind, rest, parts)
    if lowered == "logclose":
        return Comment("logclose", "")
    return Comment("plain", text)


def split_parameters(text: str) -> Tuple[Union[str, ParamRef], ...]:
    """Split comment text into literals and parameter references.

    Mirrors convert_param_comment: ``#`` + digits is a numbered parameter,
    ``#<name>`` a named one (blanks dropped, lower-cased, up to ``>``), and a
    ``#`` followed by anything else stays literal.  For a reference rs274
    cannot finish (``#`` at the very end, ``#<`` without ``>``) it prints
    uninitialised memory; ngc2py keeps what came before and stops there.
    """
    parts: List[Union[str, ParamRef]] = []
    literal: List[str] = []
    i = 0
    while i < len(text):
        if text[i] != "#":
            literal.append(text[i])
            i += 1
            continue
        i += 1
        if i >= len(text):
            break
        if "0" <= text[i] <= "9":
            start = i
            while i < len(text) and "0" <= text[i] <= "9":
                i += 1
            ref = ParamRef(int(text[start:i]))
        elif text[i] == "<":
            end = text.find(">", i + 1)
            if end == -1:
                break
            name = "".join(c for c in text[i + 1 : end] if c not in _C_SPACE)
            ref = ParamRef(ascii_lower(name))
            i = end + 1
        else:
            literal.append("#")
            continue
        if literal:
            parts.append("".join(literal))
            literal = []
        parts.append(ref)
    if literal:
        parts.append("".join(literal))
    return tuple(parts)


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


@dataclass
class _Block:
    """What has been read from the line so far."""

    n: Optional[float] = None
    items: List[Union[Word, Assign]] = field(default_factory=list)
    comments: List[Comment] = field(default_factory=list)
    oword: Optional[OWord] = None
    seen: Dict[str, Word] = field(default_factory=dict)  # letter -> last word
    g_groups: Dict[int, int] = field(default_factory=dict)  # group -> code
    m_groups: Dict[int, int] = field(default_factory=dict)


class _LineReader:
    """rs274's readers over one normalised line; fills a :class:`_Block`."""

    def __init__(self, text: str, columns: List[int], axes: str):
        self.text = text
        self.columns = columns
        self.pos = 0
        self.letters = frozenset("defghijklmpqrst$@^") | frozenset(axes)
        self.repeat_checked = _REPEAT_CHECKED | frozenset(axes)
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
        if self.starts_with_m98():
            raise _ReadError(_UNSUPPORTED % "Fanuc-style M98 subroutine call")
        while self.pos < len(self.text):
            self.read_item()

    def read_line_number(self) -> None:
        self.pos += 1
        self.block.n = float(self.read_unsigned())
        if self.peek() == ".":  # fractional line numbers are read and ignored
            self.pos += 1
            self.read_unsigned()

    def read_unsigned(self) -> int:
        start = self.pos
        while "0" <= self.peek() <= "9":
            self.pos += 1
        if self.pos == start:
            raise _ReadError("Bad format unsigned integer")
        return int(self.text[start : self.pos])

    def starts_with_m98(self) -> bool:
        """rs274 treats a line starting with M98 as a Fanuc-style call."""
        if self.peek() != "m":
            return False
        saved, frames = self.pos, len(self.open_values)
        self.pos += 1
        try:
            value = _literal(self.read_real_value())
            return value is not None and codes.to_integer(value) == 98
        except (_ReadError, GCodeError):
            return False
        finally:
            self.pos = saved
            del self.open_values[frames:]

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
        self.block.comments.append(classify_comment(self.text[self.pos + 1 : end]))
        self.pos = end + 1

    # -- words ----------------------------------------------------------------

    def read_word(self, letter: str) -> None:
        column = self.column()
        self.pos += 1
        self.check_repeat(letter)
        value = self.read_real_value()
        word = Word(letter, value, column)
        self.check_value(word)
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
        letter = word.letter
        try:
            if letter == "g":
                self.record_g(codes.g_code(value))
            elif letter == "m":
                self.record_m(codes.m_code(value))
            elif letter in _INTEGER_LETTERS:
                self.check_integer_word(letter, codes.to_integer(value))
        except GCodeError as error:
            raise _ReadError(error.message) from None
        if letter == "f" and value < 0.0:
            raise _ReadError("Negative f word used")
        if letter == "s" and value < 0.0:
            raise _ReadError("Negative spindle speed used")

    @staticmethod
    def check_integer_word(letter: str, number: int) -> None:
        if letter == "h" and number < -1:
            raise _ReadError("Negative h word used")
        if letter == "l" and number < 0:
            raise _ReadError("Negative l word used")
        if letter == "t" and number < 0:
            raise _ReadError("Negative tool id (tool not found)")

    def record_g(self, code: int) -> None:
        """rs274's modal group rule; G80 gives way to another motion code."""
        group = codes.modal_group(code)
        current = self.block.g_groups.get(group)
        if code == codes.G80 and current is not None:
            return
        if current is not None and current != codes.G80:
            raise _ReadError("Two g codes used from same modal group")
        self.block.g_groups[group] = code

    def record_m(self, code: int) -> None:
        group = codes.modal_group(code)
        if group in self.block.m_groups:
            raise _ReadError("Two m codes used from same modal group")
        self.block.m_groups[group] = code

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
            return self.read_expression()
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

    def read_expression(self) -> Expr:
        """``[v op v op ... ]`` with rs274's precedence, left-associative."""
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
        self.pos += 1
        if self.peek() == "<":
            end = self.text.find(">", self.pos + 1)
            if end == -1:
                # rs274 ignores the missing ">" and reads a bare O-word.
                raise _ReadError(_UNSUPPORTED % "O-word name without '>'")
            name: Union[str, Expr] = self.read_name()
        else:
            number = self.read_real_value()
            value = _literal(number)
            try:
                name = "%d" % codes.to_integer(value) if value is not None else number
            except GCodeError as error:
                raise _ReadError(error.message) from None
            # Until the O-word is recognised, its computed name is partial.
            self.open_values.append([number])
        keyword = next((k for k in _OWORD_ORDER if self.looking_at(k)), None)
        if keyword is None and self.peek() not in ("(", ";", _END):
            raise _ReadError("Unknown control command in o word")
        if keyword is not None:
            self.pos += len(keyword)
            self.block.oword = OWord(keyword, name)
            if not isinstance(name, str):
                self.open_values.pop()
            self.read_oword_arguments(keyword, name)
        while self.pos < len(self.text):
            if self.peek() == ";":
                self.pos = len(self.text)
            elif self.peek() == "(":
                self.read_comment()
            else:
                raise _ReadError("Unexpected character after O-word")
        if keyword is None:
            # "O100" alone starts a Fanuc-style subroutine (ended by M99).
            raise _ReadError(_UNSUPPORTED % "Fanuc-style bare O-word subroutine")

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
    normalised = normalise(text)
    block_delete = normalised.text.startswith("/")
    if normalised.error:
        return Line(number, text, file, block_delete, error=normalised.error)
    reader = _LineReader(normalised.text, normalised.columns, axes)
    error = None
    try:
        reader.read_line()
    except _ReadError as failure:
        error = failure.message
    block = reader.block
    partial = reader.partial() if error else ()
    return Line(
        number=number,
        text=text,
        file=file,
        block_delete=block_delete,
        n=block.n,
        items=tuple(block.items),
        comments=tuple(block.comments),
        oword=block.oword,
        error=error,
        partial=partial,
    )


@dataclass(frozen=True)
class ParsedFile:
    """A whole file as rs274 would read it.

    ``demarcated``: the first non-blank line is ``%`` (rs274 then requires a
    closing ``%`` line).  ``closed``: that closing line exists; ``lines`` stops
    there (both ``%`` lines are included, with ``percent=True``).
    """

    file: str
    lines: List[Line]
    demarcated: bool
    closed: bool


def _is_percent(text: str) -> bool:
    return normalise(text).text == "%"


def parse_text(
    data: Union[bytes, str], file: str = "", axes: str = DEFAULT_AXES
) -> ParsedFile:
    """Parse a file's contents (bytes as read, or already-decoded text)."""
    if isinstance(data, str):
        data = source.encode(data)
    lines: List[Line] = []
    demarcated = closed = False
    seen_content = False
    for raw in source.split_lines(data):
        if raw.too_long:
            lines.append(
                Line(raw.number, raw.text, file, error=source.COMMAND_TOO_LONG)
            )
            seen_content = True
            continue
        if not seen_content and normalise(raw.text).text:
            seen_content = True
            if _is_percent(raw.text):
                demarcated = True
                lines.append(Line(raw.number, raw.text, file, percent=True))
                continue
        if demarcated and _is_percent(raw.text):
            closed = True
            lines.append(Line(raw.number, raw.text, file, percent=True))
            break
        lines.append(parse_line(raw.text, raw.number, file, axes))
    return ParsedFile(file, lines, demarcated, closed)


def parse_file(path: str, axes: str = DEFAULT_AXES) -> ParsedFile:
    """Read and parse ``path``; OSError propagates (compile-time failure)."""
    return parse_text(source.read_file(path), path, axes)
