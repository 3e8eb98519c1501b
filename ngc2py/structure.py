"""Pair O-words into a statement tree: subroutines, conditionals and loops.

rs274 never builds such a tree: it executes a file line by line and *seeks*
(skips forward or jumps back) when an O-word says so. A well-formed program
behaves exactly like the structured program this module builds. A malformed
one (an ``endif`` without ``if``, a ``return`` outside a subroutine, a nested
``sub``) is never rejected here: the problem becomes a :class:`Fail` statement
placed where rs274 would notice it, carrying rs274's exact message, so the
error happens at run time at the same point (the golden rule of
docs/ARCHITECTURE.md).

What rs274 does while it *skips* lines also shapes the tree: it still reads
each one, so a line with a :data:`TEXT_ERRORS` problem fails even in an
untaken arm (``first_text_error`` finds it; codegen.py places the failure),
and a skipped opener reusing the label being skipped to fails as a duplicate
(``_Builder._duplicate``). Other errors in skipped lines (bad words,
expressions) are never noticed. :func:`opening_error` is what fails already
while rs274 opens the file, before the program starts.

The tree is plain data (nodes compare by identity); ``codegen.py`` turns it
into Python. Every traversal is iterative: blocks may nest thousands deep.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, Iterator, List, Optional, Tuple, Union

from ngc2py import lexer, nodes, source

# --------------------------------------------------------------------------
# Statements
# --------------------------------------------------------------------------


@dataclass
class Block:
    """An ordinary line: words, parameter settings, comments, or a read error."""

    line: nodes.Line


@dataclass
class Fail:
    """Raise ``message`` here; ``line`` is the line rs274 names in its report."""

    line: nodes.Line
    message: str
    #: rs274 meets the closing ``%`` first: FINISH() comes before the error.
    finish: bool = False


@dataclass(eq=False)
class Sub:
    """``o<name> sub`` ... ``o<name> endsub``.

    ``fn`` is the Python function name chosen by the code generator.
    ``define_error`` is set when merely *reading* the definition fails in
    rs274 (a nested ``sub``, or end of file before ``endsub``): the error is
    raised at the definition point instead of defining the subroutine.

    A Fanuc-style subroutine (``fanuc``: an ``O100`` line to ``M99``) is
    also ordinary code where it stands: rs274 runs its lines when the normal
    flow reaches them, so its body statements stay in the enclosing body too.
    """

    line: nodes.Line
    name: str
    body: List["Stmt"] = field(default_factory=list)
    end: Optional[nodes.Line] = None
    define_error: Optional[Fail] = None
    fn: str = ""
    fanuc: bool = False


@dataclass
class Define:
    """The point in the program where rs274 reads a ``sub`` line."""

    sub: Sub


@dataclass(eq=False)
class Branch:
    """One arm of an ``if``: ``line`` is the if/elseif/else line."""

    line: nodes.Line
    body: List["Stmt"] = field(default_factory=list)


@dataclass(eq=False)
class If:
    """``if`` / ``elseif`` ... / ``else`` / ``endif``."""

    branches: List[Branch]
    orelse: Optional[Branch] = None
    end: Optional[nodes.Line] = None


@dataclass(eq=False)
class Loop:
    """``while``/``endwhile``, ``do``/``while`` or ``repeat``/``endrepeat``.

    ``kind`` is ``"while"``, ``"do"`` or ``"repeat"``; ``end`` is the closing
    line (for ``do`` the ``while`` line carrying the condition).

    A labelled ``break``/``continue`` may leave several loops at once (rs274
    skips to the next line with the label). Python cannot, so such a target
    gets a flag (``flagged``) and every loop crossed lists, in ``exits``, the
    outer targets whose flag must be checked right after it.
    """

    kind: str
    line: nodes.Line
    body: List["Stmt"] = field(default_factory=list)
    end: Optional[nodes.Line] = None
    flagged: bool = False
    exits: List["Loop"] = field(default_factory=list)


@dataclass
class Jump:
    """``break`` or ``continue`` of the enclosing loop ``target`` (which
    is ``flagged`` when inner loops are left on the way)."""

    line: nodes.Line
    kind: str
    target: Loop


@dataclass
class Return:
    """``return [expr]`` or ``endsub [expr]`` inside a subroutine body."""

    line: nodes.Line
    value: Optional[nodes.Expr]


@dataclass
class Call:
    """``o<name> call [args]``.

    ``sub`` is the statically known definition to call (one in this file
    whose definition has been passed when the call runs, or an external
    file's); when ``None`` the call is resolved by name at run time
    (``name`` is a string) or computed (``name`` is an expression).
    """

    line: nodes.Line
    name: Union[str, nodes.Expr]
    args: Tuple[nodes.Expr, ...]
    sub: Optional[Sub] = None


@dataclass
class FanucCall:
    """``M98 P.. [L..]``: ``line.items`` are the words; ``sub`` is the Fanuc
    subroutine of this file with that constant name, else None (found by
    name at run time)."""

    line: nodes.Line
    sub: Optional[Sub] = None


@dataclass
class Finish:
    """The closing ``%`` of a demarcated file: the program ends here."""

    line: nodes.Line


@dataclass
class EndOfFile:
    """Execution ran past the last line (``line``) without a program end."""

    line: nodes.Line


Stmt = Union[
    Block, Fail, Define, If, Loop, Jump, Return, Call, FanucCall, Finish, EndOfFile
]


@dataclass
class Program:
    """A compiled file: its main body and every subroutine it defines.

    ``externals`` are subroutines read from other files (``<name>.ngc`` on
    the subroutine path); they are filled in by ``compiler.py``.
    """

    file: str
    body: List[Stmt]
    subs: List[Sub]
    externals: List[Sub] = field(default_factory=list)
    #: The last line rs274 reads before running off the end of the file
    #: (blank ones count: rs274 echoes it with the end-of-file error).
    last: Optional[nodes.Line] = None
    #: (message, line) when rs274 fails already while opening the file.
    open_error: Optional[Tuple[str, Optional[nodes.Line]]] = None


# --------------------------------------------------------------------------
# rs274's messages (texts measured against rs274 -g, LinuxCNC 2.9)
# --------------------------------------------------------------------------

NOT_IN_SUB = "%d: not in a subroutine definition: '%s'"
UNDEFINED_LABEL = "%d: undefined O-word label: '%s'"
NO_MATCHING_IF = "%d: no matching 'if' label: '%s' (found '%s' in line %d)"
NO_MATCHING_END = "%d: no matching label: '%s' (found '%s' in line %d)"
NO_MATCHING_ENDIF = "%d: no matching label: '%s' (found '%s' in line %d): '%s'"
NO_MATCHING_LOOP = "%d: no matching while/do label: '%s' (found '%s' in line %d)"
DUPLICATE_IF = "%d: duplicate O-word label - already defined in line %d: '%s'"
DUPLICATE_LOOP = "%d: duplicate O-word label: '%s' - defined in line %d"
NESTED_SUB = "Nested subroutine definition"
EOF_NO_END = "File ended with no percent sign or program end"
EOF_NO_PERCENT = "File ended with no percent sign"
M99_IN_O_SUB = (
    "'O.... endsub' or 'O.... return' must follow 'O.... sub' subroutine definition"
)


#: Errors rs274 finds while merely reading a line's text (close_and_downcase
#: and the length check), so also in lines it skips over unexecuted.
TEXT_ERRORS = frozenset(
    (lexer.NESTED_COMMENT, lexer.UNCLOSED_COMMENT, source.COMMAND_TOO_LONG)
)


def eof_message(demarcated: bool) -> str:
    """What rs274 says when it reads past the last line of a file."""
    return EOF_NO_PERCENT if demarcated else EOF_NO_END


# --------------------------------------------------------------------------
# The pairing pass
# --------------------------------------------------------------------------


@dataclass
class _Open:
    """A construct whose closing O-word has not been read yet."""

    label: str
    node: Union[Sub, If, Loop]
    body: List[Stmt]


class _Builder:
    """Reads lines in order, keeping a stack of open constructs."""

    def __init__(self, file: str, demarcated: bool):
        self.file = file
        self.demarcated = demarcated
        self.main: List[Stmt] = []
        self.stack: List[_Open] = []
        self.subs: List[Sub] = []
        # Labels of if/loop openers seen so far, per scope (main or a sub):
        # rs274 remembers each label's first line and complains on reuse.
        self.labels: Dict[str, Tuple[str, int]] = {}
        self.main_labels = self.labels
        # The Fanuc definition being read: (sub, the body it is in, where
        # its lines start in that body).
        self.fanuc: Optional[Tuple[Sub, List[Stmt], int]] = None

    # -- helpers ----------------------------------------------------------

    @property
    def body(self) -> List[Stmt]:
        return self.stack[-1].body if self.stack else self.main

    def open_sub(self) -> Optional[Sub]:
        for entry in reversed(self.stack):
            if isinstance(entry.node, Sub):
                return entry.node
        return None

    def fail(self, line: nodes.Line, message: str) -> None:
        self.body.append(Fail(line, message))

    # -- dispatch ---------------------------------------------------------

    def add(self, line: nodes.Line) -> None:
        word = line.oword
        if line.error in TEXT_ERRORS:
            self._text_error(line)
        if word is None or line.error is not None:
            if not line.is_blank:
                self.body.append(Block(line))
            return
        handler = getattr(self, "on_" + word.keyword)
        handler(line, word)

    def _text_error(self, line: nodes.Line) -> None:
        """rs274 reads a definition's lines when it passes the ``sub`` line:
        the first one with a text error fails the definition."""
        sub = self.open_sub()
        if sub is not None and sub.define_error is None:
            sub.define_error = Fail(line, line.error)

    # -- subroutines ------------------------------------------------------

    def on_sub(self, line: nodes.Line, word: nodes.OWord) -> None:
        outer = self.open_sub()
        if outer is not None:
            # rs274 fails while *reading* the outer definition.
            if outer.define_error is None:
                outer.define_error = Fail(line, NESTED_SUB)
            return
        sub = Sub(line, str(word.name))
        self.subs.append(sub)
        self.body.append(Define(sub))
        self.stack.append(_Open(sub.name, sub, sub.body))
        self.labels = {}

    def on_endsub(self, line: nodes.Line, word: nodes.OWord) -> None:
        sub = self.open_sub()
        if sub is None:
            self.fail(line, NOT_IN_SUB % (line.number, line.text))
            return
        if word.name != sub.name:
            # rs274 keeps skipping for the right endsub; nothing closes here.
            return
        # Constructs left open inside the body end with it.
        while not isinstance(self.stack.pop().node, Sub):
            pass
        sub.end = line
        sub.body.append(Return(line, word.expr))
        self.labels = self.main_labels

    def on_return(self, line: nodes.Line, word: nodes.OWord) -> None:
        if self.open_sub() is None:
            self.fail(line, NOT_IN_SUB % (line.number, line.text))
            return
        self.body.append(Return(line, word.expr))

    def on_call(self, line: nodes.Line, word: nodes.OWord) -> None:
        self.body.append(Call(line, word.name, word.args))

    # -- Fanuc-style subroutines -------------------------------------------

    def on_fanuc_sub(self, line: nodes.Line, word: nodes.OWord) -> None:
        sub = Sub(line, str(word.name), fanuc=True)
        self.subs.append(sub)
        self.fanuc = (sub, self.body, len(self.body))

    def on_m98(self, line: nodes.Line, word: nodes.OWord) -> None:
        self.body.append(FanucCall(line))

    def on_m99(self, line: nodes.Line, word: nodes.OWord) -> None:
        """Ends a Fanuc definition; in the main flow it is an ordinary block
        (M99 at call level 0 ends the program like M2)."""
        if self.fanuc is not None and self.fanuc[1] is self.body:
            sub, body, start = self.fanuc
            if word.in_call_error is not None:
                end: Stmt = Fail(line, word.in_call_error)
            else:
                end = Return(line, None)
            sub.body = body[start:] + [end]
            sub.end = line
            self.fanuc = None
        if self.open_sub() is not None:
            self.fail(line, M99_IN_O_SUB)
        else:
            self.body.append(Block(line))

    # -- conditionals -----------------------------------------------------

    def on_if(self, line: nodes.Line, word: nodes.OWord) -> None:
        if self._duplicate(line, word, DUPLICATE_IF):
            return
        node = If([Branch(line)])
        self.body.append(node)
        self.stack.append(_Open(str(word.name), node, node.branches[0].body))

    def _if_arm(self, line: nodes.Line, word: nodes.OWord) -> Optional[_Open]:
        """The open ``if`` an elseif/else/endif belongs to, or None after failing."""
        label = str(word.name)
        top = self.stack[-1] if self.stack else None
        if top is not None and top.label == label and isinstance(top.node, If):
            return top
        seen = self.labels.get(label)
        if seen is None:
            self.fail(line, UNDEFINED_LABEL % (line.number, line.text))
        elif word.keyword == "endif":
            self.fail(
                line,
                NO_MATCHING_ENDIF % (line.number, label, seen[0], seen[1], line.text),
            )
        else:
            self.fail(line, NO_MATCHING_IF % (line.number, line.text, seen[0], seen[1]))
        return None

    def on_elseif(self, line: nodes.Line, word: nodes.OWord) -> None:
        top = self._if_arm(line, word)
        if top is not None:
            branch = Branch(line)
            top.node.branches.append(branch)
            top.body = branch.body

    def on_else(self, line: nodes.Line, word: nodes.OWord) -> None:
        top = self._if_arm(line, word)
        if top is not None:
            top.node.orelse = Branch(line)
            top.body = top.node.orelse.body

    def on_endif(self, line: nodes.Line, word: nodes.OWord) -> None:
        top = self._if_arm(line, word)
        if top is not None:
            top.node.end = line
            self.stack.pop()

    # -- loops ------------------------------------------------------------

    def _open_loop(self, kind: str, line: nodes.Line, word: nodes.OWord) -> None:
        if kind != "do" and self._duplicate(line, word, DUPLICATE_LOOP):
            return
        node = Loop(kind, line)
        self.body.append(node)
        self.stack.append(_Open(str(word.name), node, node.body))

    def on_do(self, line: nodes.Line, word: nodes.OWord) -> None:
        self._open_loop("do", line, word)

    def on_repeat(self, line: nodes.Line, word: nodes.OWord) -> None:
        self._open_loop("repeat", line, word)

    def on_while(self, line: nodes.Line, word: nodes.OWord) -> None:
        top = self.stack[-1] if self.stack else None
        if (
            top is not None
            and top.label == str(word.name)
            and isinstance(top.node, Loop)
            and top.node.kind == "do"
        ):
            top.node.end = line
            self.stack.pop()
            return
        self._open_loop("while", line, word)

    def _close_loop(self, kind: str, line: nodes.Line, word: nodes.OWord) -> None:
        label = str(word.name)
        top = self.stack[-1] if self.stack else None
        if top is not None and top.label == label and isinstance(top.node, Loop):
            if top.node.kind == kind:
                top.node.end = line
                self.stack.pop()
                return
        seen = self.labels.get(label)
        if seen is None:
            self.fail(line, UNDEFINED_LABEL % (line.number, line.text))
        else:
            self.fail(
                line, NO_MATCHING_END % (line.number, line.text, seen[0], seen[1])
            )

    def on_endwhile(self, line: nodes.Line, word: nodes.OWord) -> None:
        self._close_loop("while", line, word)

    def on_endrepeat(self, line: nodes.Line, word: nodes.OWord) -> None:
        self._close_loop("repeat", line, word)

    def _jump(self, line: nodes.Line, word: nodes.OWord) -> None:
        label = str(word.name)
        crossed: List[Loop] = []
        for entry in reversed(self.stack):
            if isinstance(entry.node, Sub):
                break
            if not isinstance(entry.node, Loop):
                continue
            if entry.label == label:
                target = entry.node
                if target.kind == "repeat":
                    break  # rs274: break/continue only for while and do
                if crossed:
                    target.flagged = True
                    for inner in crossed:
                        if target not in inner.exits:
                            inner.exits.append(target)
                self.body.append(Jump(line, word.keyword, target))
                return
            crossed.append(entry.node)
        seen = self.labels.get(label)
        if seen is None:
            self.fail(line, UNDEFINED_LABEL % (line.number, line.text))
        else:
            self.fail(
                line, NO_MATCHING_LOOP % (line.number, line.text, seen[0], seen[1])
            )

    on_break = _jump
    on_continue = _jump

    # -- labels -----------------------------------------------------------

    def _duplicate(self, line: nodes.Line, word: nodes.OWord, message: str) -> bool:
        """Record an opener's label; fail (and return True) if it is reused."""
        label = str(word.name)
        seen = self.labels.get(label)
        if seen is None:
            self.labels[label] = (word.keyword, line.number)
            return False
        if message == DUPLICATE_IF:
            text = message % (line.number, seen[1], line.text)
        else:
            text = message % (line.number, line.text, seen[1])
        self.fail(line, text)
        top = self.stack[-1] if self.stack else None
        if top is not None and top.label == label and not isinstance(top.node, Sub):
            # rs274 stops skipping at the next line with the label being
            # skipped to, so this line fails on every path through ``top``:
            # also when its condition is false or an earlier arm ran.
            self.stack.pop()
            self.fail(line, text)
        return True

    # -- end of file ------------------------------------------------------

    def finish(
        self, last: Optional[nodes.Line], closing: Optional[nodes.Line] = None
    ) -> None:
        """The end of the file (``closing``: the closing ``%`` line)."""
        if self.fanuc is not None and last is not None:
            # A call runs the definition into the end of the file.
            sub, body, start = self.fanuc
            sub.body = body[start:] + [Fail(last, eof_message(self.demarcated))]
        while self.stack:
            entry = self.stack.pop()
            if isinstance(entry.node, Sub) and closing is not None:
                # Skipping the definition reaches the closing %.
                entry.node.define_error = entry.node.define_error or Fail(
                    closing,
                    "Failed to find sub 'O%s' before EOF" % entry.node.name,
                    finish=True,
                )
            elif isinstance(entry.node, Sub) and last is not None:
                # Reading the definition runs into the end of the file.
                entry.node.define_error = entry.node.define_error or Fail(
                    last, eof_message(self.demarcated)
                )


def opening_error(
    lines: List[nodes.Line],
) -> Optional[Tuple[str, Optional[nodes.Line]]]:
    """What rs274 says when it fails while *opening* a file, or None.

    Opening reads up to the first non-blank line: end of file before it
    ("File ended with no percent sign", naming the last blank line read),
    or that line being too long, fails before the program starts.
    """
    last: Optional[nodes.Line] = None
    for line in lines:
        if not line.is_blank:
            if line.error == source.COMMAND_TOO_LONG:
                return line.error, line
            return None
        last = line
    return EOF_NO_PERCENT, last


def build(file: str, lines: List[nodes.Line], demarcated: bool = False) -> Program:
    """Pair the O-words of one file's ``lines`` into a :class:`Program`.

    A lone closing ``%`` line ends the program with :class:`Finish`; lines
    after it are never read by rs274 and are dropped.
    """
    builder = _Builder(file, demarcated)
    seen_open = False
    last: Optional[nodes.Line] = None
    closing: Optional[nodes.Line] = None
    for line in lines:
        if line.percent and line.error is None:
            if not seen_open and demarcated:
                seen_open = True
                continue
            builder.body.append(Finish(line))
            closing = line
            break
        builder.add(line)
        last = line
    builder.finish(last, closing)
    if last is None and demarcated and lines:
        # Only the opening %: rs274 then reads nothing more, and echoes "".
        last = nodes.Line(lines[0].number + 1, "", file)
    return Program(
        file,
        builder.main,
        builder.subs,
        last=last,
        open_error=opening_error(lines),
    )


def children(stmt: Stmt, into_subs: bool = True) -> List[List[Stmt]]:
    """The statement lists directly inside ``stmt``, in source order (a
    definition's body only with ``into_subs``)."""
    if isinstance(stmt, If):
        arms = stmt.branches + ([stmt.orelse] if stmt.orelse else [])
        return [arm.body for arm in arms]
    if isinstance(stmt, Loop):
        return [stmt.body]
    if isinstance(stmt, Define) and into_subs:
        return [stmt.sub.body]
    return []


def walk(stmts: List[Stmt], into_subs: bool = True) -> Iterator[Stmt]:
    """Yield every statement of ``stmts``, depth first, in source order.

    Iterative: G-code may nest thousands of blocks deep, past Python's
    recursion limit."""
    pending = [iter(stmts)]
    while pending:
        stmt = next(pending[-1], None)
        if stmt is None:
            pending.pop()
            continue
        yield stmt
        if type(stmt) is not Block:  # most statements: nothing inside
            pending.extend(iter(body) for body in reversed(children(stmt, into_subs)))


def first_text_error(bodies: List[List[Stmt]]) -> Optional[nodes.Line]:
    """The first line in ``bodies`` (source order) with a :data:`TEXT_ERRORS`
    error: rs274 fails on it even when only skipping over it."""
    for body in bodies:
        for stmt in walk(body):
            if isinstance(stmt, Block) and stmt.line.error in TEXT_ERRORS:
                return stmt.line
    return None


def called_names(program: Program) -> List[str]:
    """Names of ``o<name> call`` targets, in first-use order (for file lookup)."""
    names: List[str] = []
    for stmt in walk(program.body):
        if isinstance(stmt, Call) and isinstance(stmt.name, str):
            if stmt.name not in names:
                names.append(stmt.name)
    return names


def resolve_calls(program: Program) -> None:
    """Bind each named call to a definition when that is safe to do statically.

    A definition at the top level of the main program binds calls on lines
    after it (rs274 has read the ``sub`` line by then). An external
    subroutine binds every call to a name this file does not define. Any
    other call (a name defined later, or inside an ``if``) is resolved by
    name at run time, which is what rs274 does.
    """
    top_level = {
        stmt.sub.name: stmt.sub
        for stmt in program.body
        if isinstance(stmt, Define) and stmt.sub.define_error is None
    }
    defined_here = {sub.name for sub in program.subs}
    external = {sub.name: sub for sub in program.externals}
    everywhere = list(walk(program.body))
    for sub in program.externals:
        everywhere.extend(walk(sub.body))
    fanuc = {sub.name: sub for sub in program.subs if sub.fanuc}
    for stmt in everywhere:
        if isinstance(stmt, FanucCall) and isinstance(stmt.line.oword.name, str):
            stmt.sub = fanuc.get(stmt.line.oword.name)
        if not isinstance(stmt, Call) or not isinstance(stmt.name, str):
            continue
        sub = top_level.get(stmt.name)
        if sub is not None and sub.line.number < stmt.line.number:
            stmt.sub = sub
        elif stmt.name not in defined_here and stmt.name in external:
            stmt.sub = external[stmt.name]
