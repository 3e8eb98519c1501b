"""The syntax tree shared by the parser and the code generator.

Every node is a record (``records.py``) compared and hashed by value, so
trees can be compared, hashed and cached; treat them as immutable.  They
are not ``Frozen``: setting each field through ``object.__setattr__``
costs three times as much, and building nodes is most of the time spent
parsing a large CAM file.
The parser produces one :class:`Line` per physical line of the source; the
structure pass (``structure.py``) groups lines into subroutines and control
flow; the code generator turns both into Python text.

Values in G-code are always floats; the tree keeps literals as floats too, so
the code generator never has to guess about integer/float semantics.
"""

from __future__ import annotations


from ngc2py.records import HashedValue

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Optional, Tuple, Union


class Node(HashedValue):
    """Base class of every node: compared and hashed by value."""

    __slots__ = ()


# --------------------------------------------------------------------------
# Expressions
# --------------------------------------------------------------------------


class Expr(Node):
    """Base class of expression nodes (a value read while a line is read)."""

    __slots__ = ()


class Num(Expr):
    """A literal number, already converted the way rs274 converts it."""

    __slots__ = ("value",)

    def __init__(self, value: float) -> None:
        self.value = value


class NumParam(Expr):
    """``#n``: a numbered parameter; ``index`` is itself an expression (``##2``)."""

    __slots__ = ("index",)

    def __init__(self, index: Expr) -> None:
        self.index = index


class NamedParam(Expr):
    """``#<name>``: ``name`` is normalised (lower case, white space removed).

    Names starting with ``_`` are global; all others are local to the
    subroutine call (or the main program) that set them.
    """

    __slots__ = ("name",)

    def __init__(self, name: str) -> None:
        self.name = name

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


class Bracket(Expr):
    """``[inner]`` read as a value: rs274 checks it at the closing ``]``.

    rs274 tests a bracketed value once, when it has finished reading it, and
    fails with ``Calculation resulted in 'not a number'`` (NaN) or
    ``Calculation resulted in 'infinity'`` (+/-inf), tested in that order.
    Results inside the brackets are not checked: ``[10**400*0]`` fails with
    'not a number' (inf*0) while ``[[10**400]*0]`` fails with 'infinity' at
    the inner ``]``.  (rs274 makes the same check on every value it reads
    as an operand or word value -- a parameter read such as ``#31`` holding
    inf from a var file, or ``#<_value>`` after ``return [10**400]``, fails
    too; that is the runtime's job when it reads a parameter, and function
    values are checked by ``runtime.ops``.)

    The parser produces a Bracket for every ``[...]`` in a value position:
    word values (``X[..]``, ``G[..]``), parameter settings and indices
    (``#1=[..]``, ``#[..]``, ``EXISTS[#[..]]``) and operands inside other
    expressions (``[[..]*0]``, ``-[..]``).  Not for brackets rs274 reads
    without the check, whose expression is stored bare:

    * a function's own argument brackets (``SIN[..]``, ``ATAN[..]/[..]``,
      ``EXISTS[..]``): ``runtime.ops`` checks arguments and results itself;
    * O-word brackets: the condition of if/elseif/while, the count of
      repeat, the value of return/endsub and the arguments of call
      (``o1 if [10**400*0]`` runs; ``o1 call [10**400]`` passes inf in #1).

    The parser also leaves it out where the check cannot fail or repeats
    one just made: around a literal (``[2]``; ``[1+2]`` is folded to
    ``Num(3.0)`` and the parser only folds to finite values) and around
    another Bracket (``[[x]]`` is one Bracket).  So ``inner`` is never a
    ``Num`` or a ``Bracket``.
    """

    __slots__ = ("inner",)

    def __init__(self, inner: Expr) -> None:
        self.inner = inner


class Unary(Expr):
    """A one-argument function (``op`` in UNARY_FUNCTIONS) or a sign (``neg``/``pos``)."""

    __slots__ = ("op", "arg")

    def __init__(self, op: str, arg: Expr) -> None:
        self.op = op
        self.arg = arg


class Atan2(Expr):
    """``ATAN[y]/[x]``: four-quadrant arc tangent in degrees."""

    __slots__ = ("y", "x")

    def __init__(self, y: Expr, x: Expr) -> None:
        self.y = y
        self.x = x


class Exists(Expr):
    """``EXISTS[#<name>]``: 1.0 if the named parameter exists, else 0.0."""

    __slots__ = ("name",)

    def __init__(self, name: str) -> None:
        self.name = name


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


class Binary(Expr):
    """``left op right``; the parser has already applied precedence."""

    __slots__ = ("op", "left", "right")

    def __init__(self, op: str, left: Expr, right: Expr) -> None:
        self.op = op
        self.left = left
        self.right = right


# --------------------------------------------------------------------------
# Items on a line
# --------------------------------------------------------------------------


class Word(Node):
    """A letter and its value: ``G1``, ``X[#1+2]``.

    ``letter`` is lower case; ``@`` and ``^`` are the polar distance and angle.
    ``N`` line numbers are not words (see ``Line.n``).
    """

    __slots__ = ("letter", "value", "col")

    def __init__(self, letter: str, value: Expr, col: int = 0) -> None:
        self.letter = letter
        self.value = value
        self.col = col  # 0-based column in the raw text, for error carets


class Assign(Node):
    """``#n = expr`` or ``#<name> = expr``: takes effect after the line is read."""

    __slots__ = ("target", "value", "col")

    def __init__(
        self, target: Union[NumParam, NamedParam], value: Expr, col: int = 0
    ) -> None:
        self.target = target
        self.value = value
        self.col = col


class Comment(Node):
    """A comment; only the last one on a line is acted on.

    ``kind`` and ``text`` are what ``runtime.comments.classify`` makes of the
    text between the parentheses (one definition of rs274's rules): for
    ``plain``, the whole comment without leading white space; for ``msg`` the
    text after ``MSG,``; for file commands the file name.  The runtime splits
    the text of the expanding kinds into literals and parameters itself.
    """

    __slots__ = ("kind", "text")

    def __init__(self, kind: str, text: str) -> None:
        self.kind = kind
        self.text = text


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
    "fanuc_sub",  # a bare ``O100`` line
    "m98",  # a line starting with M98: Fanuc-style call
    "m99",  # a line starting with M99: Fanuc-style return (in a call)
)


class OWord(Node):
    """An O-word statement, or a Fanuc-style subroutine line.

    ``name`` is the normalised label: ``"101"`` for ``o101``, ``"drill"`` for
    ``o<drill>``; for ``o[expr] ...`` it is the expression (its value is
    rounded to an integer label at run time, rs274's read_integer_value).
    ``args`` are the ``[expr]`` arguments of ``call``; ``expr`` is the condition
    of if/elseif/while, the count of repeat, or the value of return/endsub.

    Fanuc-style subroutines (LinuxCNC 2.9 runs them; facts from rs274):

    ``OWord("fanuc_sub", "100")`` -- a line ``O100`` with no keyword (only
    comments may follow; they are not acted on).  It starts the definition
    of subroutine ``100``, which ends at an ``M99`` line.  Read in the normal
    flow of a program it does nothing: the lines after it run as usual (an
    ``O100 ... M99`` at the top of the main program runs inline, and that
    M99 then ends the program).  Also produced for ``o<name`` without ``>``:
    rs274 then takes the whole rest of the line as the name (``o<abc sub``
    -> name ``"abcsub"``) and reads nothing else, not even comments.

    ``OWord("m98", "100", expr=<L value or None>)`` -- a line whose first
    item (after N) is the literal M98.  rs274 reads the rest of the line as
    ordinary items (``Line.items`` holds all of them, P and L included, in
    order; their values are evaluated and the block's word checks apply --
    ``M98 P100 X1`` fails with "Cannot use axis values without a g code that
    uses them", ``M98 P100 H2`` with "H word with no G43 or G76 to use it" --
    but nothing else on the line is executed: ``M98 P100 G1 X7 F1`` moves
    nowhere).  ``name`` is P's value as a label (an Expr when P is
    computed; convert it with ``runtime.codes.to_integer``); the subroutine
    is then called L times (L absent: once; ``L0``: not at all).  A call
    does not save, set or restore ``#1``-``#30`` (a sub that increments #1
    leaves it incremented), but does get a fresh set of named locals
    (``#<a>`` of the caller reads as "Named parameter #<a> not defined"),
    counts as a call level (``Too many subroutine levels``) and leaves
    ``#<_value>`` 0.  Like ``o100 call``, M98 finds a subroutine not yet
    defined by reading ahead in the file; at end of file it fails with
    ``EOF in file:NAME seeking o-word: o<100> from line: N`` (N the M98
    line).  Errors: ``M98`` without P -> "Found 'm98' code with no
    P-word" (Line.error, after the items); P not near an integer -> "Non
    integer value for integer"; M98 anywhere but first -> "Unknown m code
    used: M98"; calling an ``o100 sub`` with M98 fails at that sub line with
    "'O.... sub' subroutine must be called with 'O.... call'"; calling a
    Fanuc ``O100`` with ``o100 call`` fails at the O100 line with "Fanuc
    'O....' subroutine must be called with 'M98'".

    ``OWord("m99", "")`` -- a line whose first item (after N) is the literal
    M99.  What it means depends on the call level when it runs:

    * in the main program (call level 0) it is an ordinary block and
      ``Line.items`` holds the whole line, M99 included: M99 ends the
      program exactly like M2 (``M99 G0 X1`` moves, then ends);
    * inside a call it is a return: nothing else on the line is read or
      run, and when more than comments follow ``M99``, rs274 fails with
      ``in_call_error`` ("Unexpected character after O-word") instead.
      Returning from a Fanuc subroutine continues after the M98 line (or
      repeats the sub for the next L).  An M99 reached inside an
      ``o... sub`` called with ``o... call`` fails with "'O.... endsub' or
      'O.... return' must follow 'O.... sub' subroutine definition"; a
      Fanuc subroutine ended by ``o100 endsub`` fails at that line with
      "Fanuc 'O....' subroutine definition must end with 'M99'".

    An M99 word that is not first on its line is an ordinary M code; inside
    a call rs274 then fails with "Bug:  Reached convert_stop() from M99 as
    subprogram return" (two spaces).  Running into the end of the file
    inside a Fanuc subroutine fails with "File ended with no percent sign or
    program end".
    """

    __slots__ = ("keyword", "name", "args", "expr", "in_call_error")

    def __init__(
        self,
        keyword: str,
        name: Union[str, Expr],
        args: Tuple[Expr, ...] = (),
        expr: Optional[Expr] = None,
        in_call_error: Optional[str] = None,
    ) -> None:
        self.keyword = keyword
        self.name = name
        self.args = args
        self.expr = expr
        #: For "m99": rs274's read error when the line runs inside a call.
        self.in_call_error = in_call_error


class Line(Node):
    """One physical line of a source file, as read.

    ``items`` holds the words and parameter settings in source order, so the
    generated code evaluates them in the order rs274 reads them. When the line
    has a read-time error, ``error`` holds rs274's message and ``items`` what
    was read before the error (those values are still evaluated first, which
    is how rs274 reports, say, a division by zero before a later syntax error;
    settings are never applied on such a line), then the values of ``oword``
    that were read (name expression, ``expr``, ``args``), then ``partial``.
    """

    __slots__ = (
        "number",
        "text",
        "file",
        "block_delete",
        "n",
        "items",
        "comments",
        "oword",
        "error",
        "percent",
        "partial",
        "n_text",
        "fanuc_value",
        "fanuc_alt",
        "oword_unread",
    )

    def __init__(
        self,
        number: int,
        text: str,
        file: str = "",
        block_delete: bool = False,
        n: Optional[float] = None,
        items: Tuple[Union[Word, Assign], ...] = (),
        comments: Tuple[Comment, ...] = (),
        oword: Optional[OWord] = None,
        error: Optional[str] = None,
        percent: bool = False,
        partial: Tuple[Expr, ...] = (),
        n_text: Optional[str] = None,
        fanuc_value: Optional[Expr] = None,
        fanuc_alt: Optional[Line] = None,
        oword_unread: bool = False,
    ) -> None:
        self.number = number  # 1-based physical line number in ``file``
        self.text = text  # the line as rs274 echoes it in error reports
        self.file = file
        self.block_delete = block_delete
        self.n = n  # the N word's value (integer part), if any
        self.items = items
        self.comments = comments
        self.oword = oword
        self.error = error
        self.percent = percent  # the line is a lone ``%`` demarcation line
        #: With ``error``: values rs274 had already computed inside the item
        #: it was reading when it failed (``X[1/0 + $]`` divides before it
        #: meets ``$``; ``##1 X`` reads #1 for the index before missing the
        #: ``=``). Evaluate them, in order, after ``items`` and before
        #: raising ``error``.
        self.partial = partial
        #: What rs274's trace prints after ``N`` for this line's calls, or
        #: None for ``N.....``.  rs274 takes it from the raw line text, not
        #: from the N word's value: after leading blanks, tabs and ``/``, if
        #: the next character is ``N`` or ``n``, the decimal digits that
        #: immediately follow it, as written (``N0012`` -> ``"0012"``,
        #: ``N20.5`` -> ``"20"``, ``N 12`` -> ``""`` although the N word is
        #: 12).  None when the line has no N word, or when the raw text hides
        #: it from that scan (``\rN5``).  The trace pads the digits with
        #: spaces to 6 columns and prints the call right after them, with no
        #: separator for 6 digits or more (``N0012  STRAIGHT_...``,
        #: ``N123456STRAIGHT_...``).
        self.n_text = n_text
        #: A line starting with a computed M word (``M#1 P100``): rs274
        #: decides when it reads the line whether that M value is 98, and
        #: then reads the line as an M98 call (skipping the first three
        #: characters). Then ``fanuc_value`` is the M value and
        #: ``fanuc_alt`` that M98 reading.
        self.fanuc_value = fanuc_value
        self.fanuc_alt = fanuc_alt
        #: With ``error``: it came while reading the O-word itself (its
        #: label or its keyword). rs274 reads the O-word of every line it
        #: skips over, so such a line fails even unexecuted
        #: (``structure.skip_error``).
        self.oword_unread = oword_unread

    @property
    def comment(self) -> Optional[Comment]:
        """The comment rs274 acts on: the last one, unless it is ``()``."""
        if not self.comments or self.comments[-1].kind == "none":
            return None
        return self.comments[-1]

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


# --------------------------------------------------------------------------
# Walking expressions
# --------------------------------------------------------------------------


def subexpressions(e: Expr):
    """``e`` and every expression inside it."""
    yield e
    for name in e._fields:
        child = getattr(e, name)
        if isinstance(child, Expr):
            yield from subexpressions(child)


def reads_name(items, name: str) -> bool:
    """Does reading ``items`` read (or test with EXISTS) the named parameter?"""
    for item in items:
        exprs = [item.value]
        if isinstance(item, Assign) and isinstance(item.target, NumParam):
            exprs.append(item.target.index)
        for expr in exprs:
            for e in subexpressions(expr):
                if isinstance(e, (NamedParam, Exists)) and e.name == name:
                    return True
    return False


__all__ = [
    "Node",
    "Expr",
    "Num",
    "NumParam",
    "NamedParam",
    "Bracket",
    "Unary",
    "Atan2",
    "Exists",
    "Binary",
    "Word",
    "Assign",
    "Comment",
    "OWord",
    "Line",
    "UNARY_FUNCTIONS",
    "BINARY_OPERATORS",
    "OWORD_KEYWORDS",
    "subexpressions",
    "reads_name",
]
