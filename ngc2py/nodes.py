"""The syntax tree shared by the parser and the code generator.

Every node is a frozen dataclass so trees can be compared, hashed and cached.
The parser produces one :class:`Line` per physical line of the source; the
structure pass (``structure.py``) groups lines into subroutines and control
flow; the code generator turns both into Python text.

Values in G-code are always floats; the tree keeps literals as floats too, so
the code generator never has to guess about integer/float semantics.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple, Union


# --------------------------------------------------------------------------
# Expressions
# --------------------------------------------------------------------------


class Expr:
    """Base class of expression nodes (a value read while a line is read)."""

    __slots__ = ()


@dataclass(frozen=True)
class Num(Expr):
    """A literal number, already converted the way rs274 converts it."""

    value: float


@dataclass(frozen=True)
class NumParam(Expr):
    """``#n``: a numbered parameter; ``index`` is itself an expression (``##2``)."""

    index: Expr


@dataclass(frozen=True)
class NamedParam(Expr):
    """``#<name>``: ``name`` is normalised (lower case, white space removed).

    Names starting with ``_`` are global; all others are local to the
    subroutine call (or the main program) that set them.
    """

    name: str

    @property
    def is_global(self) -> bool:
        return self.name.startswith("_")


#: Unary functions and sign operators, by the name used in ``Unary.op``.
UNARY_FUNCTIONS = (
    "abs",
    "acos",
    "asin",
    "atan",  # only ever as the one-argument form if rs274 allows it; see Atan2
    "cos",
    "exp",
    "fix",
    "fup",
    "ln",
    "round",
    "sin",
    "sqrt",
    "tan",
)


@dataclass(frozen=True)
class Unary(Expr):
    """A one-argument function (``op`` in UNARY_FUNCTIONS) or a sign (``neg``/``pos``)."""

    op: str
    arg: Expr


@dataclass(frozen=True)
class Atan2(Expr):
    """``ATAN[y]/[x]``: four-quadrant arc tangent in degrees."""

    y: Expr
    x: Expr


@dataclass(frozen=True)
class Exists(Expr):
    """``EXISTS[#<name>]``: 1.0 if the named parameter exists, else 0.0."""

    name: str


#: Binary operators in ``Binary.op``, lower case as in the source.
BINARY_OPERATORS = (
    "**",
    "*",
    "/",
    "mod",
    "+",
    "-",
    "eq",
    "ne",
    "gt",
    "ge",
    "lt",
    "le",
    "and",
    "or",
    "xor",
)


@dataclass(frozen=True)
class Binary(Expr):
    """``left op right``; the parser has already applied precedence."""

    op: str
    left: Expr
    right: Expr


# --------------------------------------------------------------------------
# Items on a line
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class Word:
    """A letter and its value: ``G1``, ``X[#1+2]``.

    ``letter`` is lower case; ``@`` and ``^`` are the polar distance and angle.
    ``N`` line numbers are not words (see ``Line.n``).
    """

    letter: str
    value: Expr
    col: int = 0  # 0-based column in the raw text, for error carets


@dataclass(frozen=True)
class Assign:
    """``#n = expr`` or ``#<name> = expr``: takes effect after the line is read."""

    target: Union[NumParam, NamedParam]
    value: Expr
    col: int = 0


#: What a comment does, by ``Comment.kind``.
COMMENT_KINDS = (
    "plain",  # COMMENT("text")
    "msg",  # MESSAGE("text")
    "debug",  # MESSAGE with parameters expanded
    "print",  # stderr, with parameters expanded
    "log",  # log file line, with parameters expanded
    "logopen",
    "logappend",
    "logclose",
    "probeopen",
    "probeclose",
    "abort",
)


@dataclass(frozen=True)
class ParamRef:
    """A parameter reference inside a DEBUG/PRINT/LOG/ABORT comment."""

    name: Union[int, str]  # int: numbered parameter; str: normalised named parameter


@dataclass(frozen=True)
class Comment:
    """A comment; only the last one on a line is acted on.

    ``text`` is what rs274 passes on (for ``plain``, the whole comment text; for
    ``msg`` the text after ``MSG,``; for file commands the file name).
    ``parts`` is ``text`` split into literal strings and :class:`ParamRef` for
    the kinds that expand parameters (debug, print, log, abort); otherwise ``()``.
    """

    kind: str
    text: str
    parts: Tuple[Union[str, ParamRef], ...] = ()


#: O-word keywords, by ``OWord.keyword``.
OWORD_KEYWORDS = (
    "sub",
    "endsub",
    "call",
    "return",
    "if",
    "elseif",
    "else",
    "endif",
    "while",
    "endwhile",
    "do",
    "repeat",
    "endrepeat",
    "break",
    "continue",
)


@dataclass(frozen=True)
class OWord:
    """An O-word statement.

    ``name`` is the normalised label: ``"101"`` for ``o101``, ``"drill"`` for
    ``o<drill>``; for ``o[expr] call`` it is the expression.
    ``args`` are the ``[expr]`` arguments of ``call``; ``expr`` is the condition
    of if/elseif/while, the count of repeat, or the value of return/endsub.
    """

    keyword: str
    name: Union[str, Expr]
    args: Tuple[Expr, ...] = ()
    expr: Optional[Expr] = None


@dataclass(frozen=True)
class Line:
    """One physical line of a source file, as read.

    ``items`` holds the words and parameter settings in source order, so the
    generated code evaluates them in the order rs274 reads them. When the line
    has a read-time error, ``error`` holds rs274's message and ``items`` what
    was read before the error (those values are still evaluated first, which
    is how rs274 reports, say, a division by zero before a later syntax error;
    settings are never applied on such a line), then the values of ``oword``
    that were read (name expression, ``expr``, ``args``), then ``partial``.
    """

    number: int  # 1-based physical line number in ``file``
    text: str  # the line as rs274 echoes it in error reports
    file: str = ""
    block_delete: bool = False
    n: Optional[float] = None  # the N word, if any
    items: Tuple[Union[Word, Assign], ...] = ()
    comments: Tuple[Comment, ...] = ()
    oword: Optional[OWord] = None
    error: Optional[str] = None
    percent: bool = False  # the line is a lone ``%`` demarcation line
    #: With ``error``: values rs274 had already computed inside the item it
    #: was reading when it failed (``X[1/0 + $]`` divides before it meets
    #: ``$``; ``##1 X`` reads #1 for the index before missing the ``=``).
    #: Evaluate them, in order, after ``items`` and before raising ``error``.
    partial: Tuple[Expr, ...] = ()

    @property
    def comment(self) -> Optional[Comment]:
        """The comment rs274 acts on: the last one."""
        return self.comments[-1] if self.comments else None

    @property
    def words(self) -> Tuple[Word, ...]:
        return tuple(i for i in self.items if isinstance(i, Word))

    @property
    def assigns(self) -> Tuple[Assign, ...]:
        return tuple(i for i in self.items if isinstance(i, Assign))

    @property
    def is_blank(self) -> bool:
        return not (
            self.items
            or self.comments
            or self.oword
            or self.error
            or self.percent
            or self.n is not None
        )


__all__ = [
    "Expr",
    "Num",
    "NumParam",
    "NamedParam",
    "Unary",
    "Atan2",
    "Exists",
    "Binary",
    "Word",
    "Assign",
    "Comment",
    "ParamRef",
    "OWord",
    "Line",
    "UNARY_FUNCTIONS",
    "BINARY_OPERATORS",
    "COMMENT_KINDS",
    "OWORD_KEYWORDS",
]
