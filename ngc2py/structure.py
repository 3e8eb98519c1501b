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
each one's text and O-word, so a line with a :data:`TEXT_ERRORS` problem or
an unreadable O-word fails even in an untaken arm (:func:`skip_error`;
``first_text_error`` finds it; codegen.py places the failure), reading past
a definition has its own rules (:func:`define_error`), and a skipped opener
reusing the label being skipped to fails as a duplicate
(``_Builder._duplicate``). Other errors in skipped lines (bad words,
expressions) are never noticed. :func:`opening_error` is what fails already
while rs274 opens the file, before the program starts.

The tree is plain data (nodes compare by identity); ``codegen.py`` turns it
into Python. Every traversal is iterative: blocks may nest thousands deep.
"""

from __future__ import annotations


from ngc2py import lexer, nodes, source
from ngc2py.records import Record, Value
from ngc2py.rowrun import RowRun

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, Iterator, List, Optional, Tuple, Union

# --------------------------------------------------------------------------
# Statements
# --------------------------------------------------------------------------


class Block(Value):
    """An ordinary line: words, parameter settings, comments, or a read error."""

    __slots__ = ("line",)

    def __init__(self, line: nodes.Line) -> None:
        self.line = line


class Fail(Value):
    """Raise ``message`` here; ``line`` is the line rs274 names in its report."""

    __slots__ = ("line", "message", "finish", "reads", "check")

    def __init__(
        self,
        line: nodes.Line,
        message: str,
        finish: bool = False,
        reads: Optional[nodes.Expr] = None,
        check: Optional["LabelCheck"] = None,
    ) -> None:
        self.line = line
        self.message = message
        #: rs274 meets the closing ``%`` first: FINISH() comes before the
        #: error.
        self.finish = finish
        #: A condition rs274 reads first (an opener failing as a duplicate).
        self.reads = reads
        #: A reused label: what rs274 recorded decides the message at run
        #: time (this check fails; the message above is the fallback).
        self.check = check


class Sub(Record):
    """``o<name> sub`` ... ``o<name> endsub``.

    ``fn`` is the Python function name chosen by the code generator.
    ``define_error`` is set when merely *reading* the definition fails in
    rs274 (a nested ``sub``, or end of file before ``endsub``): the error is
    raised at the definition point instead of defining the subroutine.

    A Fanuc-style subroutine (``fanuc``: an ``O100`` line to ``M99``) is
    also ordinary code where it stands: rs274 runs its lines when the normal
    flow reaches them, so its body statements stay in the enclosing body too.
    """

    __slots__ = ("line", "name", "body", "end", "define_error", "fn", "fanuc")

    def __init__(
        self,
        line: nodes.Line,
        name: str,
        body: Optional[List["Stmt"]] = None,  # None: a new empty list
        end: Optional[nodes.Line] = None,
        define_error: Optional[Fail] = None,
        fn: str = "",
        fanuc: bool = False,
    ) -> None:
        self.line = line
        self.name = name
        self.body = [] if body is None else body
        self.end = end
        self.define_error = define_error
        self.fn = fn
        self.fanuc = fanuc


class Define(Value):
    """The point in the program where rs274 reads a ``sub`` line."""

    __slots__ = ("sub",)

    def __init__(self, sub: Sub) -> None:
        self.sub = sub


class Branch(Record):
    """One arm of an ``if``: ``line`` is the if/elseif/else line."""

    __slots__ = ("line", "body")

    def __init__(self, line: nodes.Line, body: Optional[List["Stmt"]] = None) -> None:
        self.line = line
        self.body = [] if body is None else body  # None: a new empty list


class If(Record):
    """``if`` / ``elseif`` ... / ``else`` / ``endif``."""

    __slots__ = ("branches", "orelse", "end", "landings")

    def __init__(
        self,
        branches: List[Branch],
        orelse: Optional[Branch] = None,
        end: Optional[nodes.Line] = None,
        landings: Optional[Dict[int, List["Stmt"]]] = None,  # None: a new dict
    ) -> None:
        self.branches = branches
        self.orelse = orelse
        self.end = end
        #: Lines reusing this if's label inside an arm, however deeply
        #: nested: arm index -> the statements of the first such line in
        #: that arm. rs274 skips an arm (a false condition, or the arms
        #: after a taken one) to the next line with the label, wherever it
        #: is: a ``do`` there runs its loop (whose closing ``while`` then
        #: fails: the label is the if's), an opener, break, continue,
        #: endwhile or endrepeat fails.
        self.landings = {} if landings is None else landings


class Loop(Record):
    """``while``/``endwhile``, ``do``/``while`` or ``repeat``/``endrepeat``.

    ``kind`` is ``"while"``, ``"do"`` or ``"repeat"``; ``end`` is the closing
    line (for ``do`` the ``while`` line carrying the condition).

    A labelled ``break``/``continue`` may leave several loops at once (rs274
    skips to the next line with the label). Python cannot, so such a target
    gets a flag (``flagged``) and every loop crossed lists, in ``exits``, the
    outer targets whose flag must be checked right after it.
    """

    __slots__ = (
        "kind",
        "line",
        "body",
        "end",
        "flagged",
        "exits",
        "eof",
        "skip_fail",
        "key",
        "back",
        "reuses",
        "skip",
        "back_into",
        "landing",
        "anew",
    )

    def __init__(
        self,
        kind: str,
        line: nodes.Line,
        body: Optional[List["Stmt"]] = None,  # None: a new empty list
        end: Optional[nodes.Line] = None,
        flagged: bool = False,
        exits: Optional[List["Loop"]] = None,  # None: a new empty list
        eof: Optional[Union[Fail, "LabelCheck"]] = None,
        skip_fail: Optional[Union[Fail, "LabelCheck"]] = None,
        key: str = "",
        back: bool = False,
        reuses: Optional["Loop"] = None,
        skip: bool = False,
        back_into: Optional[tuple] = None,
        landing: Optional[List["Stmt"]] = None,
        anew: Optional[Union[Fail, "LabelCheck"]] = None,
    ) -> None:
        self.kind = kind
        self.line = line
        self.body = [] if body is None else body
        self.end = end
        self.flagged = flagged
        self.exits = [] if exits is None else exits
        #: Never closed (``o1 if`` ... ``o2 while`` ... ``o1 endif``, or
        #: open at the end of the file): rs274 runs the rest of the body
        #: once, and when it does not enter the loop, or a break or
        #: continue of it runs, it skips to the end of the file looking for
        #: the label; this is that failure.
        self.eof = eof
        #: A repeat loop with a break or continue line of its own label:
        #: when the count runs out rs274 skips forward to the first such
        #: line, and fails there (break and continue are for while and do
        #: loops only).
        self.skip_fail = skip_fail
        #: rs274's name of the label (``subroutine#label``).
        self.key = key
        #: No loop of the text: where a ``while`` line ending an earlier
        #: do-loop (:class:`DoEnd`) jumps back to, from that do line on.
        self.back = back
        #: A do line reusing the label of this finished do-loop of a body
        #: around it (rs274 keeps that one's place): see _Builder.on_while.
        self.reuses = reuses
        #: No loop of the text: the statements a break or continue skips
        #: over to a later line of its label where rs274 goes on (a do
        #: line), run once; its jumps (Jump.flag) leave it
        #: (_Builder._jumps_land_here).
        self.skip = skip
        #: Its while line true goes back into an earlier construct: (the
        #: :attr:`back` loop it continues, what runs first, the loop a
        #: break there leaves: DoEnd.resume, DoEnd.leaves); see
        #: _Builder._loop_back_into.
        self.back_into = back_into
        #: A do line reusing this while or repeat loop's label in its body:
        #: ending by its condition or count, rs274 skips forward to it and
        #: goes on from there (the statements from it on, as If.landings).
        self.landing = landing
        #: A do-loop whose body holds an M98 that may enter a frame without
        #: a call (m98_may_strand): its while line, run in that frame, is
        #: one whose label rs274 does not find there, so it reads the line
        #: as a new while-loop -- true, it goes on past it; false, it skips
        #: ahead for the label, and this is where that skip fails.
        self.anew = anew


class Jump(Value):
    """``break`` or ``continue`` of the enclosing loop ``target`` (which
    is ``flagged`` when inner loops are left on the way)."""

    __slots__ = ("line", "kind", "target", "flag")

    def __init__(
        self, line: nodes.Line, kind: str, target: Loop, flag: str = ""
    ) -> None:
        self.line = line
        self.kind = kind
        self.target = target
        #: A jump to a :attr:`Loop.skip` loop: the keyword of the line
        #: (break or continue), whose rs274 flag it sets.
        self.flag = flag


class DoEnd(Jump):
    """A ``while`` line whose label rs274 recorded for a finished do-loop
    in a body around it: it ends that loop again. With its condition true
    (and no break pending) rs274 goes back to the do line, running it all
    again (``target``: a :attr:`Loop.back` loop from the do line to the
    construct holding this line); else it goes on with the next line.

    The do-loop may also end an earlier construct of this line's body (the
    last statement of its last arm, or of its loop body): going back runs
    ``resume`` (the do-loop, then what the construct's closing line does,
    :meth:`_Builder._back_into`) before ``target`` goes on after it."""

    __slots__ = ("resume", "leaves")  # after Jump's fields

    def __init__(
        self,
        line: nodes.Line,
        kind: str,
        target: Loop,
        flag: str = "",
        resume: Optional[List["Stmt"]] = None,  # None: a new empty list
        leaves: Optional[List["Loop"]] = None,  # None: a new empty list
    ) -> None:
        self.line = line
        self.kind = kind
        self.target = target
        self.flag = flag
        self.resume = [] if resume is None else resume
        #: A loop a break in ``resume`` leaves: it continues ``target``.
        self.leaves = [] if leaves is None else leaves


class IfEnd(Value):
    """The endif line of an if run into again (:attr:`DoEnd.resume`):
    rs274's flag "an arm has run" is set."""

    __slots__ = ("line",)

    def __init__(self, line: nodes.Line) -> None:
        self.line = line


class ArmAgain(Value):
    """An elseif or else line of an if run into again after an earlier arm
    (:attr:`DoEnd.resume`), and its arm: as :class:`FlatArm`, where an arm
    has run rs274 skips on to the next line of the if; else it runs on (an
    elseif whatever its condition, a true one setting the flag)."""

    __slots__ = ("line", "body")

    def __init__(self, line: nodes.Line, body: List["Stmt"]) -> None:
        self.line = line
        self.body = body


class Again(Value):
    """The closing line of a loop run into again (:attr:`DoEnd.resume`):
    a do-loop's while line goes back to its do line when its condition is
    true; a while-loop's endwhile goes back to its while line, a repeat
    loop's endrepeat to its repeat line (a finished repeat counts anew).
    ``loop`` then runs as it does where it stands."""

    __slots__ = ("loop",)

    def __init__(self, loop: "Loop") -> None:
        self.loop = loop


class LabelCheck(Value):
    """rs274 remembers the first line each label was *executed* on (per
    subroutine) and fails when another opener reuses it. Where a label is
    reused in the text this is decided at run time, here: ``kind`` is the
    opener's keyword (``if``, ``while``, ``repeat``, ``do``) or ``do-end``
    for the ``while`` line that closes a do-loop."""

    __slots__ = ("line", "key", "kind", "loop", "eof", "leave")

    def __init__(
        self,
        line: nodes.Line,
        key: str,
        kind: str,
        loop: Optional["Loop"] = None,
        eof: Optional["Fail"] = None,
        leave: Optional["Loop"] = None,
    ) -> None:
        self.line = line
        self.key = key
        self.kind = kind
        #: A break or continue of this do-loop: rs274 skips to its closing
        #: ``while`` line, checked here (``do-end``) before the jump.
        self.loop = loop
        #: An else or elseif with no later line of its label before the end
        #: of the file: where an arm has run, rs274 skips to the end of the
        #: file and fails there (this failure; see :func:`flat_arms`).
        self.eof = eof
        #: An else or elseif whose next line of its label stands after the
        #: construct holding it: where an arm has run, rs274 skips there,
        #: out of that construct; this run-once loop, ending before that
        #: line, is what the skip leaves (_Builder._arm_skips_out).
        self.leave = leave


class FlatArm(Value):
    """An ``else`` or ``elseif`` line that running code reaches outside the
    if it belongs to (a skip landed in a do-loop of the if's label, or an
    outer construct's closing line ended the if), and the statements after
    it up to the next line with the label (``body``). rs274 keeps one flag,
    "an arm of an if has run" (set by a true if or elseif, an endif, an
    else reached by skipping; cleared by a false if): when it is set, the
    line skips to the next line with its label; when it is not, an else
    runs on into what follows it, and an elseif runs on too, whatever its
    condition (a true one sets the flag). Codegen groups these
    (:func:`flat_arms`) and then tracks the flag (``m.executed_if``)."""

    __slots__ = ("check", "body", "landing", "eof")

    def __init__(
        self,
        check: "LabelCheck",
        body: List["Stmt"],
        landing: Optional[List["Stmt"]] = None,
        eof: Optional["Fail"] = None,
    ) -> None:
        self.check = check
        self.body = body
        #: Where the next line with the label stands inside a loop never
        #: closed that follows (``body`` ends with it): what rs274 runs
        #: after its skip lands there, from that line on (the loop is never
        #: entered).
        self.landing = landing
        #: No line with the label up to the end of the file: the skip fails
        #: there (:attr:`LabelCheck.eof`).
        self.eof = eof


def flat_arms(stmts: List["Stmt"]) -> List["Stmt"]:
    """``stmts`` with each else/elseif :class:`LabelCheck` and what follows
    it up to the next statement with its label made one :class:`FlatArm`
    (a check with no such statement after it is left as it is)."""
    out: List[Stmt] = []
    i = 0
    while i < len(stmts):
        stmt = stmts[i]
        if isinstance(stmt, LabelCheck) and stmt.kind in ("else", "elseif"):
            label = stmt.key.split("#")[-1]
            j = next(
                (
                    k
                    for k in range(i + 1, len(stmts))
                    if _has_label(stmts[k], stmt.key, label)
                ),
                None,
            )
            deep = _deep_landing(stmts[i + 1 :], stmt.key, label)
            if deep is not None and (j is None or deep[0] + i + 1 < j):
                k, landing = deep
                end = i + 1 + k + 1
                out.append(FlatArm(stmt, flat_arms(stmts[i + 1 : end]), landing))
                i = end
                continue
            if j is not None:
                end = j
                if type(stmts[j]) is Block and stmts[j].line.error == AFTER_OWORD:
                    # words after the O-word fail only when the line is run
                    # into, not when the skip lands on it
                    end = j + 1
                out.append(FlatArm(stmt, flat_arms(stmts[i + 1 : end])))
                i = end
                continue
            if deep is None and _unreadable_first(stmts[i + 1 :], stmt.key, label):
                # no line with the label before one rs274 cannot read: the
                # skip fails there (inside whatever holds it)
                out.append(FlatArm(stmt, flat_arms(stmts[i + 1 :])))
                break
            if deep is None and stmt.eof is not None:
                # no line with the label up to the end of the file: the
                # skip fails there (or on the way, _later_landing)
                out.append(FlatArm(stmt, flat_arms(stmts[i + 1 :]), eof=stmt.eof))
                break
        out.append(stmt)
        i += 1
    return out


def _deep_landing(
    stmts: List["Stmt"], key: str, label: str
) -> Optional[Tuple[int, List["Stmt"]]]:
    """The first line with ``label`` in ``stmts`` when it stands inside a
    loop never closed (however many): (the index of that loop, the
    statements from the line on, then what follows each loop around it);
    None when it is a statement of ``stmts`` itself, inside anything else,
    or a line rs274 cannot read comes first."""
    for k, stmt in enumerate(stmts):
        if _has_label(stmt, key, label):
            return None
        if type(stmt) is Block and skip_error(stmt.line):
            return None
        if isinstance(stmt, Loop) and stmt.end is None:
            rest = _landing_rest(stmt.body, key, label)
            if rest is not None:
                return k, rest + stmts[k + 1 :]
        if isinstance(stmt, If) and stmt.end is None:
            rest = _open_if_landing(stmt, key, label)
            if rest is not None:
                return k, rest + stmts[k + 1 :]
        hit = _failing_landing(stmt, key, label)
        if hit is not None:
            return (k, hit) if hit else None
        if _unreadable_inside(stmt):
            return None
    return None


def _open_if_landing(stmt: "If", key: str, label: str) -> Optional[List["Stmt"]]:
    """The first line with ``label`` when it stands in the last arm of an
    if never closed (``stmt``): the statements from it to the end of that
    arm (after it, the text goes on with what follows the if). None when
    the line is elsewhere, or something on the way stops the skip."""
    arms = stmt.branches + ([stmt.orelse] if stmt.orelse is not None else [])
    if stmt.orelse is not None and stmt.orelse.line is stmt.branches[-1].line:
        arms.pop()  # the end-of-file failure _abandon added, no line of its own
    for arm in arms[:-1]:
        for inner in walk(arm.body):
            if _has_label(inner, key, label) or (
                type(inner) is Block and skip_error(inner.line)
            ):
                return None
    return _landing_rest(arms[-1].body, key, label)


def _unreadable_first(stmts: List["Stmt"], key: str, label: str) -> bool:
    """Does a skip for ``label`` through ``stmts`` meet a line rs274 cannot
    read (however deeply nested) before any line with the label?"""
    for stmt in walk(stmts):
        if type(stmt) is Block and skip_error(stmt.line):
            return True
        if _has_label(stmt, key, label):
            return False
    return False


def _unreadable_inside(stmt: "Stmt") -> bool:
    """Does a skip passing over ``stmt`` (a construct without the label it
    looks for) fail at a line inside it that rs274 cannot read?"""
    if type(stmt) is Block:
        return False
    return first_text_error(children(stmt, False)) is not None


def _failing_landing(stmt: "Stmt", key: str, label: str) -> Optional[List["Stmt"]]:
    """The first line with ``label`` inside ``stmt`` (another construct):
    [its failure] when running it fails whatever the run (a break of an
    if's label, an opener reusing it), [] when it is something else (not
    followed), None when there is no such line. (A closing line whose
    label rs274 looks up at run time is such a failure where the label is
    recorded as what it does not fit.)"""
    for inner in walk([stmt], False):
        if _has_label(inner, key, label):
            if type(inner) is Fail:
                return [inner]
            if type(inner) is LabelCheck and inner.kind in ("break", "continue"):
                return [inner]
            return []
    return None


def _landing_rest(stmts: List["Stmt"], key: str, label: str) -> Optional[List["Stmt"]]:
    """From the first line with ``label`` in ``stmts`` (inside loops never
    closed) on, as :func:`_deep_landing`."""
    for k, stmt in enumerate(stmts):
        if _has_label(stmt, key, label):
            if type(stmt) is Block and stmt.line.error == AFTER_OWORD:
                return stmts[k + 1 :]  # landing there does not fail
            return stmts[k:]
        if type(stmt) is Block and skip_error(stmt.line):
            return None
        if isinstance(stmt, Loop) and stmt.end is None:
            rest = _landing_rest(stmt.body, key, label)
            if rest is not None:
                return rest + stmts[k + 1 :]
        if isinstance(stmt, If) and stmt.end is None:
            rest = _open_if_landing(stmt, key, label)
            if rest is not None:
                return rest + stmts[k + 1 :]
        hit = _failing_landing(stmt, key, label)
        if hit is not None:
            return hit or None
        if _unreadable_inside(stmt):
            return None
    return None


def _has_label(stmt: "Stmt", key: str, label: str) -> bool:
    """Does ``stmt`` start with a line carrying ``label`` (``key``)?"""
    if isinstance(stmt, LabelCheck):
        return stmt.key == key
    if isinstance(stmt, If):
        line = stmt.branches[0].line
    elif isinstance(stmt, (Loop, Block, Fail, Jump)):
        line = stmt.line
    else:
        return False
    word = getattr(line, "oword", None)
    return word is not None and str(word.name) == label


class TopReturn(Value):
    """``return`` or ``endsub`` outside any subroutine: rs274 fails as "not
    in a subroutine definition", unless a call has returned to the main
    program since the last definition (then ``return`` does nothing and
    ``endsub`` fails differently)."""

    __slots__ = ("line", "keyword", "value")

    def __init__(
        self, line: nodes.Line, keyword: str, value: Optional[nodes.Expr] = None
    ) -> None:
        self.line = line
        self.keyword = keyword
        self.value = value


class Return(Value):
    """``return [expr]`` or ``endsub [expr]`` inside a subroutine body."""

    __slots__ = ("line", "value")

    def __init__(self, line: nodes.Line, value: Optional[nodes.Expr]) -> None:
        self.line = line
        self.value = value


class Call(Value):
    """``o<name> call [args]``.

    ``sub`` is the statically known definition to call (one in this file
    whose definition has been passed when the call runs, or an external
    file's); when ``None`` the call is resolved by name at run time
    (``name`` is a string) or computed (``name`` is an expression).
    """

    __slots__ = ("line", "name", "args", "sub", "found")

    def __init__(
        self,
        line: nodes.Line,
        name: Union[str, nodes.Expr],
        args: Tuple[nodes.Expr, ...],
        sub: Optional[Sub] = None,
        found: Optional[Sub] = None,
    ) -> None:
        self.line = line
        self.name = name
        self.args = args
        self.sub = sub
        #: Where rs274 finds the subroutine when the call runs while
        #: ``name`` is not defined yet: ``<name>.ngc`` on the subroutine
        #: path, else the first ``o<name> sub`` after the call in this
        #: (subroutine) file, or a :class:`SeekFail` body. Set for calls of
        #: external files' code and for calls of the main file that find a
        #: file (see compiler.py).
        self.found = found


class SeekFail(Value):
    """rs274 skipped to the end of ``file`` (having read ``line`` last)
    looking for ``o<name> sub``, from line ``start`` of it (0: it had just
    opened the file)."""

    __slots__ = ("line", "file", "name", "start")

    def __init__(self, line: nodes.Line, file: str, name: str, start: int) -> None:
        self.line = line
        self.file = file
        self.name = name
        self.start = start


class FanucCall(Value):
    """``M98 P.. [L..]``: ``line.items`` are the words; ``sub`` is what
    rs274 finds for that constant name when it has not recorded one yet
    (the Fanuc subroutine of ``<P>.ngc``, else the first one further on in
    this file, else a body failing as rs274 does), or None (found by name
    at run time). ``found``: what compiler.py found in a file."""

    __slots__ = ("line", "sub", "found")

    def __init__(
        self,
        line: nodes.Line,
        sub: Optional[Sub] = None,
        found: Optional[Sub] = None,
    ) -> None:
        self.line = line
        self.sub = sub
        self.found = found


class Finish(Value):
    """The closing ``%`` of a demarcated file: the program ends here."""

    __slots__ = ("line",)

    def __init__(self, line: nodes.Line) -> None:
        self.line = line


class SubLine(Value):
    """A ``sub`` line inside a definition: nothing when a call runs it,
    except in the frame an ``M98 .. L0`` entered, where it fails."""

    __slots__ = ("line",)

    def __init__(self, line: nodes.Line) -> None:
        self.line = line


class EndOfFile(Value):
    """Execution ran past the last line (``line``) without a program end."""

    __slots__ = ("line",)

    def __init__(self, line: nodes.Line) -> None:
        self.line = line


if TYPE_CHECKING:
    Stmt = Union[
        Block,
        Fail,
        Define,
        If,
        Loop,
        Jump,
        DoEnd,
        IfEnd,
        ArmAgain,
        Again,
        LabelCheck,
        TopReturn,
        Return,
        Call,
        FanucCall,
        Finish,
        EndOfFile,
        SeekFail,
        SubLine,
    ]


class Program(Value):
    """A compiled file: its main body and every subroutine it defines.

    ``externals`` are subroutines read from other files (``<name>.ngc`` on
    the subroutine path); they are filled in by ``compiler.py``.
    """

    __slots__ = (
        "file",
        "body",
        "subs",
        "externals",
        "found",
        "last",
        "open_error",
        "block_delete",
        "__dict__",  # other attributes: lineflow.flat_program adds ``lines``
    )

    def __init__(
        self,
        file: str,
        body: List[Stmt],
        subs: List[Sub],
        externals: Optional[List[Sub]] = None,  # None: a new empty list
        found: Optional[Dict[str, Sub]] = None,  # None: a new dict
        last: Optional[nodes.Line] = None,
        open_error: Optional[Tuple[str, Optional[nodes.Line]]] = None,
        block_delete: Optional[bool] = None,
    ) -> None:
        self.file = file
        self.body = body
        self.subs = subs
        self.externals = [] if externals is None else externals
        #: What a call of the main file finds in ``<name>.ngc`` (compiler.py)
        self.found = {} if found is None else found
        #: The last line rs274 reads before running off the end of the file
        #: (blank ones count: rs274 echoes it with the end-of-file error).
        self.last = last
        #: (message, line) when rs274 fails already while opening the file.
        self.open_error = open_error
        #: The block delete setting (rs274's -b) the program is compiled
        #: for, where block-deleted O-word lines make it matter
        #: (compiler.py); None: it runs with either.
        self.block_delete = block_delete


# --------------------------------------------------------------------------
# rs274's messages (texts measured against rs274 -g, LinuxCNC 2.9)
# --------------------------------------------------------------------------

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
FANUC_NEEDS_M98 = "Fanuc 'O....' subroutine must be called with 'M98'"
O_SUB_NEEDS_CALL = "'O.... sub' subroutine must be called with 'O.... call'"
M99_IN_O_SUB = (
    "'O.... endsub' or 'O.... return' must follow 'O.... sub' subroutine definition"
)


#: Errors rs274 finds while merely reading a line's text (close_and_downcase
#: and the length check), so also in lines it skips over unexecuted.
TEXT_ERRORS = frozenset(
    (lexer.NESTED_COMMENT, lexer.UNCLOSED_COMMENT, source.COMMAND_TOO_LONG)
)


UNKNOWN_O_COMMAND = "Unknown control command in o word"
AFTER_OWORD = "Unexpected character after O-word"


def skip_error(line: nodes.Line) -> bool:
    """Does rs274 fail on ``line`` while skipping over it in running code?

    It reads every line's text (:data:`TEXT_ERRORS`) and the O-word of
    every line it skips over: its label (a computed one is evaluated) and
    its keyword, but not what follows."""
    return line.error in TEXT_ERRORS or line.oword_unread


def define_error(line: nodes.Line, sub_name: str) -> Optional[str]:
    """rs274's error on ``line`` while it reads past a subroutine definition
    (``o<sub_name> sub`` ... ``endsub``), or None.

    Reading a definition differs from other skipping: an unknown O-word
    keyword is only noticed when the line runs, a bare (Fanuc) O-word is a
    nested definition, and the definition's own ``return`` and ``endsub``
    lines have their value read."""
    if line.error in TEXT_ERRORS:
        return line.error
    if line.oword_unread:
        return None if line.error == UNKNOWN_O_COMMAND else line.error
    word = line.oword
    if word is None:
        return None
    if word.keyword == "fanuc_sub":
        return NESTED_SUB
    if (
        word.keyword in ("return", "endsub")
        and line.error not in (None, AFTER_OWORD)
        and str(word.name) == sub_name
    ):
        return line.error
    return None


#: O-words reached by skipping as often as by running into them.
_CLOSERS = frozenset(("elseif", "else", "endif", "endwhile", "endrepeat", "while"))


def eof_message(demarcated: bool) -> str:
    """What rs274 says when it reads past the last line of a file."""
    return EOF_NO_PERCENT if demarcated else EOF_NO_END


# --------------------------------------------------------------------------
# The pairing pass
# --------------------------------------------------------------------------


class _Open(Value):
    """A construct whose closing O-word has not been read yet."""

    __slots__ = ("label", "node", "body", "condition")
    _hidden = ("condition",)  # a cache: not compared, not shown

    def __init__(
        self,
        label: str,
        node: Union[Sub, If, Loop],
        body: List[Stmt],
        condition: Optional[tuple] = None,
    ) -> None:
        self.label = label
        self.node = node
        self.body = body
        #: (body, what _condition_start answers for it), settled once asked
        self.condition = condition


class _Stack(list):
    """The open constructs, innermost last, counting those that are
    subroutines: with none open (most programs), the subroutine around a
    line and the constructs of its scope are known without a walk down the
    whole stack, which every O-word line asks (deep nesting made that
    quadratic). Changed only by append, insert and pop."""

    __slots__ = ("subs",)

    def __init__(self) -> None:
        super().__init__()
        self.subs = 0

    def append(self, entry: "_Open") -> None:
        super().append(entry)
        self.subs += isinstance(entry.node, Sub)

    def insert(self, index: int, entry: "_Open") -> None:
        super().insert(index, entry)
        self.subs += isinstance(entry.node, Sub)

    def pop(self, index: int = -1) -> "_Open":
        entry = super().pop(index)
        self.subs -= isinstance(entry.node, Sub)
        return entry


def _condition_start(node, body: List[Stmt]) -> Optional[nodes.Line]:
    """The opening line of the construct whose ``body`` this is, when its
    conditions keep running code out of that body (a repeat of none, a
    while whose condition is a false constant, an arm whose condition is,
    or one after an arm whose condition is a true constant); else None.
    (What else decides it is asked each time: _Builder._never_entered.)"""
    if isinstance(node, Loop):
        if node.line.oword is None or node.kind not in ("while", "repeat"):
            return None
        value = _constant(node.line.oword.expr)
        if value is None or (value > 0.0 if node.kind == "repeat" else value != 0.0):
            return None
        return node.line
    if isinstance(node, If):
        arms = node.branches + ([node.orelse] if node.orelse else [])
        index = next((k for k, arm in enumerate(arms) if arm.body is body), None)
        if index is None:
            return None
        values = [_constant(arm.line.oword.expr) for arm in node.branches[:index]]
        if any(value is not None and value != 0.0 for value in values):
            return node.branches[0].line  # an arm before always runs
        if index < len(node.branches):
            value = _constant(node.branches[index].line.oword.expr)
            if value is None or value != 0.0:
                return None
            return node.branches[index].line
    return None


class _Builder:
    """Reads lines in order, keeping a stack of open constructs."""

    def __init__(self, file: str, demarcated: bool):
        self.file = file
        self.demarcated = demarcated
        self.main: List[Stmt] = []
        self.stack: _Stack = _Stack()
        self.subs: List[Sub] = []
        # Labels of if/loop openers seen so far, per scope (main or a sub):
        # rs274 remembers each label's first line and complains on reuse.
        # Values: (keyword, line number, the body it is in, the node).
        self.labels: Dict[str, tuple] = {}
        self.main_labels = self.labels
        # Labels reused by openers, checked at run time ("scope#label").
        self.tracked: set = set()
        # The Fanuc definition being read: (sub, the body it is in, where
        # its lines start in that body).
        self.fanuc: Optional[Tuple[Sub, List[Stmt], int]] = None
        # Failures at the end of the file, for abandoned constructs.
        self.eof_fails: List[Tuple[Fail, str]] = []  # and the label's key
        # where each of those skips starts (id of the Fail -> line)
        self.eof_origins: Dict[int, nodes.Line] = {}
        # every line with a label, and every line rs274 cannot read while
        # skipping (key None), in order: (number, key, line, word, what
        # the label was recorded as before the line)
        self.labelled: List[tuple] = []
        # break/continue lines aimed at a finished loop: (label, failure)
        self.stale_jumps: List[Tuple[str, Fail]] = []
        # constructs opened by lines failing as duplicates (_duplicate)
        self.dead: set = set()
        # sub name -> line numbers of its endsub lines (set by build)
        self.endsubs: Dict[str, List[int]] = {}
        # sub lines in an if or loop whose definition never ends: (name,
        # the failure of reading it, known at a line or at the end)
        self.orphans: List[Tuple[str, Fail]] = []
        # else/elseif lines of reused labels fitting no open if (_arms_to_eof)
        self.arm_checks: List[LabelCheck] = []
        # breaks of finished do-loops skipping past a while line: (that
        # line, the loop standing for the skip: _break_to_do_end)
        self.skips_to: List[tuple] = []

    # -- helpers ----------------------------------------------------------

    @property
    def body(self) -> List[Stmt]:
        return self.stack[-1].body if self.stack else self.main

    def open_sub(self) -> Optional[Sub]:
        if not self.stack.subs:
            return None
        for entry in reversed(self.stack):
            if isinstance(entry.node, Sub):
                return entry.node
        return None

    def fail(self, line: nodes.Line, message: str) -> None:
        self.body.append(Fail(line, message))

    # -- dispatch ---------------------------------------------------------

    def add(self, line: nodes.Line) -> None:
        word = line.oword
        if skip_error(line):
            self.labelled.append((line.number, None, line, word, None))
        elif word is not None and isinstance(word.name, str):
            seen = self.labels.get(str(word.name))
            self.labelled.append(
                (line.number, self._key(str(word.name)), line, word, seen)
            )
        if self.stale_jumps and skip_error(line):
            # skipping forward for a finished loop's label, rs274 fails at
            # a line it cannot read
            for _, fail in self.stale_jumps:
                fail.line, fail.message = line, line.error
            self.stale_jumps = []
        for name, fail in self.orphans:
            if fail.line is None:
                message = define_error(line, name)
                if message is not None:
                    fail.line, fail.message = line, message
        if (
            word is not None
            and self.stale_jumps
            and word.keyword not in ("break", "continue")
        ):
            # (on another break or continue of the label rs274 skips on)
            name = str(word.name)
            for key, fail in self.stale_jumps:
                if key.split("#")[-1] == name:
                    self._land(fail, line, word)
            self.stale_jumps = [
                j for j in self.stale_jumps if j[0].split("#")[-1] != name
            ]
        sub = self.open_sub()
        if sub is not None and sub.define_error is None:
            message = define_error(line, sub.name)
            if message is not None:
                sub.define_error = Fail(line, message)
        if sub is not None and word is not None and word.keyword == "fanuc_sub":
            # A nested definition: the outer one fails (above). Run inside
            # an ``o.. call`` (a sub found by reading ahead), the line fails.
            self.fail(line, FANUC_NEEDS_M98)
            return
        if (
            word is not None
            and line.error == AFTER_OWORD
            and word.keyword in _CLOSERS
            and self.stack
        ):
            # rs274 checks what follows an O-word only when it does not
            # skip: running into this line fails (after reading its
            # condition), skipping to it (an arm not taken, a loop's
            # continue) does not.
            self.body.append(Block(line))
            getattr(self, "on_" + word.keyword)(line, word)
            return
        if word is not None and word.keyword == "endsub" and line.error is not None:
            # Skipping over a definition, rs274 reads only the O-word: the
            # endsub closes it, and the rest of the line fails when run.
            self.on_endsub(line, word, failing=True)
            return
        if (
            word is not None
            and word.keyword == "m99"
            and line.error is not None
            and word.in_call_error is not None
            and self.fanuc is not None
            and self.fanuc[1] is self.body
        ):
            # M99 ending a Fanuc definition, with words after it: run as the
            # return of an M98 call rs274 reads no further than "Unexpected
            # character after O-word"; in the main flow the line's own error
            self.on_m99(line, word)
            return
        if (
            word is not None
            and word.keyword == "elseif"
            and line.error is not None
            and not line.oword_unread
            and self._enclosing(str(word.name), lambda node: isinstance(node, If))
        ):
            # An elseif of an open if whose condition cannot be read: rs274
            # reads it wherever it reaches the line, running into it or
            # skipping to its label (an arm not taken, or after one that
            # ran), so every way through the if ends here, failing.
            self.on_endif(line, word)
            self.body.append(Block(line))
            return
        if (
            word is not None
            and word.keyword == "while"
            and line.error is not None
            and not line.oword_unread
            and self._enclosing(str(word.name), _plain_do)
        ):
            # The while line of an open do-loop whose condition cannot be
            # read: running into it, or skipping to it (a break or continue
            # of the loop), rs274 reads the condition and fails. The loop
            # runs once; its break and continue lines leave it for the line.
            loop = self.stack.pop().node
            for stmt in walk(loop.body, False):
                if isinstance(stmt, Jump) and stmt.target is loop:
                    stmt.kind = "break"
            self.body.append(Block(line))
            return
        if (
            word is not None
            and word.keyword in ("if", "while", "repeat")
            and line.error is not None
            and line.error != AFTER_OWORD
            and not line.oword_unread
        ):
            landing = self._landing_if(word)
            if landing is not None:
                # an opener with an open if's label whose condition cannot be
                # read: skipping an arm of that if, rs274 stops here, reads the
                # condition and fails (If.landings), as when running into it
                start = len(self.body)
                self.body.append(Block(line))
                node = landing.node
                arm = len(node.branches) - (node.orelse is None)
                node.landings.setdefault(arm, self.body[start:])
                return
        if word is None or line.error is not None:
            if not line.is_blank:
                self.body.append(Block(line))
            return
        self._arm_skips_out(line, word)
        handler = getattr(self, "on_" + word.keyword)
        landing = self._landing_if(word)
        loop_landing = self._landing_loop(line, word)
        body, start = self.body, len(self.body)
        handler(line, word)
        while self.skips_to and self.skips_to[-1][0] is line:
            # the line a break skips past is written: the skip ends here
            _, node = self.skips_to.pop()
            while self.stack and self.stack[-1].node is not node:
                self.stack.pop()
            if self.stack:
                self.stack.pop()
        if landing is not None and body[start:]:
            node = landing.node
            arm = len(node.branches) - (node.orelse is None)
            node.landings.setdefault(arm, body[start:])
        if loop_landing is not None and body[start:] and loop_landing.landing is None:
            loop_landing.landing = body[start:]

    # -- subroutines ------------------------------------------------------

    def on_sub(self, line: nodes.Line, word: nodes.OWord) -> None:
        outer = self.open_sub()
        if outer is not None:
            # rs274 fails while *reading* the outer definition.
            if outer.define_error is None:
                outer.define_error = Fail(line, NESTED_SUB)
            self.body.append(SubLine(line))  # run in a call (entry_sub)
            return
        name = str(word.name)
        if self.stack and not any(n > line.number for n in self.endsubs.get(name, ())):
            # Inside an if or loop, with no endsub of it further on: run,
            # rs274 reads the definition to the end of the file (or to a
            # line it cannot read) and fails; skipped, the line is nothing.
            fail = Fail(None, "")
            self.body.append(fail)
            self.orphans.append((name, fail))
            return
        sub = Sub(line, str(word.name))
        self.subs.append(sub)
        self.body.append(Define(sub))
        self.stack.append(_Open(sub.name, sub, sub.body))
        self.labels = {}

    def on_endsub(
        self, line: nodes.Line, word: nodes.OWord, failing: bool = False
    ) -> None:
        sub = self.open_sub()
        if sub is None or failing and word.name != sub.name:
            if failing:  # words after it: a block that fails when reached
                self.body.append(Block(line))
            else:
                self.body.append(TopReturn(line, "endsub", word.expr))
            return
        if word.name != sub.name:
            # Reading the definition, rs274 keeps skipping for the right
            # endsub: nothing closes here. Run in a call, any endsub returns.
            self.body.append(Return(line, word.expr))
            return
        # Constructs left open inside the body end with it.
        while not isinstance(self.stack[-1].node, Sub):
            self._abandon(self.stack.pop())
        self.stack.pop()
        sub.end = line
        sub.body.append(Block(line) if failing else Return(line, word.expr))
        self.labels = self.main_labels

    def on_return(self, line: nodes.Line, word: nodes.OWord) -> None:
        if self.open_sub() is None:
            self.body.append(TopReturn(line, "return", word.expr))
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
        self._register(line, word, node)
        self.stack.append(_Open(str(word.name), node, node.branches[0].body))

    def _if_arm(self, line: nodes.Line, word: nodes.OWord) -> Optional[_Open]:
        """The open ``if`` an elseif/else/endif belongs to, or None after failing."""
        label = str(word.name)
        top = self._enclosing(label, lambda node: isinstance(node, If))
        if top is not None:
            return top
        self._label_error(line, word)
        return None

    def _after_else(self, top: _Open, line: nodes.Line) -> bool:
        """An elseif or else line after the else line of its if: whether
        an arm ran or rs274 skipped to the else, its flag is set, so it
        skips from here to the next line of the label; the arm runs only
        where the flag was cleared since (:class:`ArmAgain`)."""
        if top.node.orelse is None:
            return False
        arm = ArmAgain(line, [])
        top.body.append(arm)
        top.body = arm.body
        return True

    def on_elseif(self, line: nodes.Line, word: nodes.OWord) -> None:
        top = self._if_arm(line, word)
        if top is not None and self._after_else(top, line):
            return
        if top is not None:
            branch = Branch(line)
            top.node.branches.append(branch)
            top.body = branch.body

    def on_else(self, line: nodes.Line, word: nodes.OWord) -> None:
        top = self._if_arm(line, word)
        if top is not None and self._after_else(top, line):
            return
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
        node = Loop(kind, line, key=self._key(str(word.name)))
        self.body.append(node)
        self._register(line, word, node)
        self.stack.append(_Open(str(word.name), node, node.body))

    def on_do(self, line: nodes.Line, word: nodes.OWord) -> None:
        label = str(word.name)
        seen = self.labels.get(label)
        self._jumps_land_here(label, seen, line)
        if self._reopens_do(label, seen):
            self._reopen_do(label, seen[3])
            return
        if self._inside_do(label, seen):
            # rs274 keeps the first do-loop's place for the label (open
            # around this line): this line does nothing, and the closing
            # while goes back to that do line
            return
        outer = self._outer_do(label, seen) is not None or self._resumable(label, seen)
        self._open_loop("do", line, word)
        if outer:
            # the label of a finished do-loop in a body around this one:
            # rs274 keeps that do's place; unless a break or continue needs
            # this loop, its while line dissolves it (on_while)
            self.stack[-1].node.reuses = seen[3]

    def _jumps_land_here(self, label: str, seen, line: nodes.Line) -> None:
        """A do line inside the open do-loop that first used its label,
        after break or continue lines of that loop in this body (or in ifs
        in it): their skip stops at this line (the next with the label),
        where rs274 goes on (the do line does nothing). The statements from
        the first of them to here become a loop run once that they leave
        (``Loop.skip``), setting rs274's flag as the jump would."""
        if seen is None or seen[0] != "do" or not self.stack:
            return
        loop = seen[3]
        for entry in self._scope_entries():
            if entry.label == label:
                if entry.node is not loop or id(loop) in self.dead:
                    return
                break
            if isinstance(entry.node, Loop):
                return  # a loop between: its own end comes first
        else:
            return
        key = self._key(label)
        between = [
            number
            for number, line_key, _, _, _ in self.labelled
            if line_key == key and number < line.number
        ]
        jumps = []
        for index, stmt in enumerate(self.body):
            candidates = (
                [stmt]
                if type(stmt) is Jump
                else [inner for inner in walk([stmt], False) if type(inner) is Jump]
            )
            for jump in candidates:
                if jump.target is not loop or any(
                    n > jump.line.number for n in between
                ):
                    continue
                holder = self.body if jump is stmt else _holder(stmt, jump)
                if holder is not None:
                    jumps.append((index, jump))
        if not jumps:
            return
        start = jumps[0][0]
        skip = Loop("do", jumps[0][1].line, self.body[start:], key="", skip=True)
        del self.body[start:]
        self.body.append(skip)
        for _, jump in jumps:
            holder = skip.body if any(s is jump for s in skip.body) else None
            if holder is None:
                holder = next(
                    h for h in (_holder(s, jump) for s in skip.body) if h is not None
                )
            position = next(k for k, inner in enumerate(holder) if inner is jump)
            holder[position] = Jump(jump.line, "break", skip, flag=jump.kind)

    def _inside_do(self, label: str, seen) -> bool:
        """Is the innermost open construct of this scope with ``label`` the
        do-loop that first used it (open around this line)?"""
        if seen is None or seen[0] != "do":
            return False
        for entry in self._scope_entries():
            if entry.label == label:
                if entry.node is not seen[3] or id(entry.node) in self.dead:
                    return False
                # a break or continue of that loop before this line would
                # skip to this line, not to the loop's end: a loop of its own
                return not any(
                    (isinstance(s, Jump) and s.target is entry.node)
                    or (isinstance(s, LabelCheck) and s.loop is entry.node)
                    for s in walk(entry.node.body, into_subs=False)
                )
        return False

    #: Lines a skip to their label stops at without ending an if: rs274
    #: runs a ``do`` and fails on the others (the label is the if's).
    _LANDING = frozenset(
        ("if", "while", "repeat", "do", "break", "continue", "endwhile", "endrepeat")
    )

    def _landing_if(self, word: nodes.OWord) -> Optional[_Open]:
        """The open ``if`` whose skip would stop at this line: the innermost
        open construct of this scope with the line's label, if an if."""
        if word.keyword not in self._LANDING:
            return None
        label = str(word.name)
        for entry in self._scope_entries():
            if entry.label == label:
                return entry if isinstance(entry.node, If) else None
        return None

    def _landing_loop(self, line: nodes.Line, word: nodes.OWord) -> Optional[Loop]:
        """The open while or repeat loop whose end skip would stop at this
        do line, standing directly in its body, unless a line of the label
        before it stops it first. (A do inside a construct opened in the
        body is not followed: running on from it, rs274 meets the closing
        lines of openers it skipped.)"""
        if word.keyword != "do":
            return None
        label = str(word.name)
        for entry in self._scope_entries():
            if entry.label == label:
                node = entry.node
                if (
                    node is self.stack[-1].node  # (not inside a construct it skipped)
                    and isinstance(node, Loop)
                    and node.kind in ("while", "repeat")
                    and not (node.back or node.skip)
                    and node.skip_fail is None
                    and node.eof is None
                    and not any(
                        node.line.number < number < line.number
                        and key == self._key(label)
                        for number, key, _, _, _ in self.labelled
                    )
                ):
                    return node
                return None
        return None

    def _reopens_do(self, label: str, seen) -> bool:
        """Is ``label`` that of a finished do-loop earlier in this body (so
        rs274 has recorded that do-loop's place for it)?"""
        return (
            seen is not None
            and seen[0] == "do"
            and seen[2] is self.body
            and seen[3].end is not None
            and not any(entry.label == label for entry in self._scope_entries())
        )

    def _reopen_do(self, label: str, first: Loop) -> None:
        """A second ``do`` with the label of an earlier do-loop in the same
        body: rs274 keeps the first one's place, so the closing ``while`` of
        the second loop jumps back to the *first* ``do``. Everything from
        the first do-loop on becomes the body of one loop that the second
        ``while`` closes; the second ``do`` line itself does nothing."""
        start = next(i for i, stmt in enumerate(self.body) if stmt is first)
        outer = Loop("do", first.line, self.body[start:], key=first.key)
        del self.body[start:]
        self.body.append(outer)
        # the labels of the openers moved stand in the new loop's body now
        for name, seen in self.labels.items():
            if seen[2] is self.body and any(stmt is seen[3] for stmt in outer.body):
                self.labels[name] = seen[:2] + (outer.body, seen[3])
        # rs274 still knows the label by the first do: a later do or while
        # with it loops back there, so it wraps this loop in turn.
        seen = self.labels.get(label)
        if seen is not None and seen[3] is first:
            self.labels[label] = seen[:2] + (self.body, outer)
        self.stack.append(_Open(label, outer, outer.body))

    def on_repeat(self, line: nodes.Line, word: nodes.OWord) -> None:
        self._open_loop("repeat", line, word)

    def on_while(self, line: nodes.Line, word: nodes.OWord) -> None:
        top = self._enclosing(
            str(word.name), lambda node: isinstance(node, Loop) and node.kind == "do"
        )
        if top is not None and self._dissolves(top.node):
            # its do line did nothing: the body is plain code, and this
            # line ends the first do-loop of the label again (DoEnd)
            self.stack.pop()
            depth = self._outer_do(str(word.name), self.labels.get(str(word.name)))
            if depth is not None and self.body and self.body[-1] is top.node:
                self.body.pop()
                self.body.extend(top.node.body)
                self._do_end(line, top.node.reuses, depth)
                return
            if depth is None and self.body and self.body[-1] is top.node:
                # the first do-loop of the label stands in an earlier
                # construct of this body: back into it
                self.body.pop()
                count = len(self.body)
                self.body.extend(top.node.body)
                if self._back_into(
                    line, str(word.name), self.labels.get(str(word.name))
                ):
                    return
                del self.body[count:]
                self.body.append(top.node)
            self.stack.append(top)
        if top is not None:
            top.node.end = line
            key = self._key(str(word.name))
            if any(
                type(stmt) is FanucCall and m98_may_strand(stmt.line)
                for stmt in walk(top.node.body, False)
            ):
                top.node.anew = self._eof_fail(key, line)
            if key in self.tracked:
                top.node.body.append(LabelCheck(line, key, "do-end"))
            self.stack.pop()
            if (
                top.node.reuses is not None
                and self._outer_do(str(word.name), self.labels.get(str(word.name)))
                is None
            ):
                self._loop_back_into(top.node)
            return
        label = str(word.name)
        seen = self.labels.get(label)
        if self._reopens_do(label, seen):
            # rs274 takes it for the end of that do-loop: it loops back to
            # the first ``do``, or goes on into what follows.
            start = next(i for i, stmt in enumerate(self.body) if stmt is seen[3])
            if any(
                any(stmt is check for check in self.arm_checks)
                for stmt in self.body[start + 1 :]
            ):
                # an else or elseif line between, run into: where an arm
                # has run it skips past this line to the next of its label
                # (structure.FlatArm), so this line is a jump back (DoEnd)
                # in the statements after it, not the end of a loop
                self._do_end(line, seen[3], len(self.stack))
                return
            self._reopen_do(label, seen[3])
            self.stack.pop().node.end = line
            return
        depth = self._outer_do(label, seen)
        if depth is not None:
            self._do_end(line, seen[3], depth)
            return
        if self._back_into(line, label, seen):
            return
        self._open_loop("while", line, word)

    def _resumable(self, label: str, seen) -> bool:
        """Is ``label`` that of a do-loop in an earlier construct of this
        body that a while line can go back into (:meth:`_back_into`)?"""
        if seen is None or seen[0] != "do":
            return False
        if any(entry.label == label for entry in self._scope_entries()):
            return False
        return any(self._resume(stmt, seen[3]) for stmt in self.body)

    def _back_into(self, line: nodes.Line, label: str, seen) -> bool:
        """A ``while`` line whose label rs274 recorded for a do-loop inside
        an earlier construct of this body or of a body around it (an if
        closed by its endif, a closed do or while loop, however deeply).
        True, rs274 goes back to that do line: it runs the rest of each body
        from the do-loop on and each closing line again (an endif sets the
        arm flag, later arm lines consult it, a loop's while or endwhile
        line may run the loop again), then what follows up to this line
        again: a :class:`DoEnd` with ``resume``, continuing a
        :attr:`Loop.back` loop from after that construct (as
        :meth:`_do_end`). Only where the jumps on the way stay inside what
        runs again (else False: not followed)."""
        if seen is None or seen[0] != "do":
            return False
        first = seen[3]
        if any(entry.label == label for entry in self._scope_entries()):
            return False
        found = self._resume_point(first)
        if found is None:
            return False
        depth, index, resume = found
        body = self.stack[depth - 1].body if depth else self.main
        left = body[index]
        outer = Loop("do", first.line, body[index + 1 :], key=first.key, back=True)
        del body[index + 1 :]
        body.append(outer)
        # open (with no label a line can carry) until the body around ends
        self.stack.insert(depth, _Open("", outer, outer.body))
        crossed = [
            entry.node
            for entry in self.stack[depth + 1 :]
            if isinstance(entry.node, Loop)
        ]
        if crossed:
            outer.flagged = True
            for inner in crossed:
                inner.exits.append(outer)
        leaves = self._leaving(left, resume, outer)
        if first.key in self.tracked:
            self.body.append(LabelCheck(line, first.key, "do-end"))
        self.body.append(DoEnd(line, "continue", outer, resume=resume, leaves=leaves))
        return True

    def _leaving(self, left: Stmt, resume: List[Stmt], outer: Loop) -> List[Loop]:
        """A break of the loop ``left`` (the construct gone back into) in
        ``resume`` leaves it: what follows it is the start of ``outer``, so
        it continues ``outer`` (codegen), and the loops it crosses there
        check ``outer``'s flag too."""
        if not isinstance(left, Loop):
            return []
        stmts = list(walk(resume, False))
        if not any(isinstance(s, Jump) and s.target is left for s in stmts):
            return []
        outer.flagged = True
        for inner in stmts:
            if (
                isinstance(inner, Loop)
                and left in inner.exits
                and outer not in inner.exits
            ):
                inner.exits.append(outer)
        return [left]

    def _loop_back_into(self, loop: Loop) -> None:
        """A do-loop whose do line does nothing (``reuses``: the label's
        first do-loop stands in an earlier construct), kept as a loop for
        its break lines, just closed: where its while line is true, rs274
        goes back into that construct (:meth:`_back_into`), then runs on to
        this loop again (``Loop.back_into``: codegen's do test). A break
        ends the loop as usual. Only where no continue of it comes from a
        loop inside it, and the jumps on the way back stay inside what
        runs again."""
        if any(
            isinstance(inner, Loop)
            and any(
                isinstance(s, Jump) and s.target is loop
                for s in walk(inner.body, False)
            )
            for inner in walk(loop.body, False)
        ):
            return
        found = self._resume_point(loop.reuses)
        if found is None:
            return
        depth, index, resume = found
        body = self.stack[depth - 1].body if depth else self.main
        left = body[index]
        outer = Loop("do", loop.reuses.line, body[index + 1 :], key=loop.key, back=True)
        del body[index + 1 :]
        body.append(outer)
        self.stack.insert(depth, _Open("", outer, outer.body))
        outer.flagged = True
        for entry in self.stack[depth + 1 :]:
            if isinstance(entry.node, Loop):
                entry.node.exits.append(outer)
        loop.exits.append(outer)
        loop.back_into = (outer, resume, self._leaving(left, resume, outer))

    def _resume_point(self, first: Loop) -> Optional[Tuple[int, int, List[Stmt]]]:
        """The earlier construct holding ``first`` in this body or a body
        around it (of this subroutine or the main program): (the depth of
        that body as :meth:`_do_end` counts it, the construct's index in
        it, what runs going back to ``first``: :meth:`_resume`)."""
        for depth in range(len(self.stack), -1, -1):
            if depth == 0 and self.stack and isinstance(self.stack[0].node, Sub):
                return None
            body = self.stack[depth - 1].body if depth else self.main
            stop = len(body) - (depth < len(self.stack))  # not the open one
            for index in range(stop):
                leaves = body[index] if isinstance(body[index], Loop) else None
                resume = self._resume(body[index], first, leaves)
                if resume is not None:
                    return depth, index, resume
            if depth and isinstance(self.stack[depth - 1].node, Sub):
                return None
        return None

    def _resume(
        self, stmt: Stmt, first: Loop, leaves: Optional[Loop] = None
    ) -> Optional[List[Stmt]]:
        """When ``first`` stands in an arm of the if ``stmt`` (closed), or in
        the body of the do or while loop ``stmt`` (closed), however deeply:
        what runs going back to it, from it to the end of that arm or body
        (and of each construct between), then what each closing line does
        when run into again. None elsewhere, or where a break or continue
        on the way aims outside the statements run."""
        if isinstance(stmt, If) and id(stmt) not in self.dead:
            arms = stmt.branches + ([stmt.orelse] if stmt.orelse else [])
            if stmt.orelse is not None and stmt.orelse.line is stmt.branches[-1].line:
                arms.pop()  # the end-of-file failure _abandon added
            for k, arm in enumerate(arms):
                head = self._resume_in(arm.body, first, leaves)
                if head is None:
                    continue
                if not head:
                    return None
                if stmt.end is None:
                    # ended by an outer closing line (abandoned): from its
                    # last arm rs274 runs on into that line
                    return head if k == len(arms) - 1 else None
                key = self._key(str(stmt.end.oword.name))
                closing: List[Stmt] = list(head)
                for later in arms[k + 1 :]:
                    if key in self.tracked:
                        closing.append(
                            LabelCheck(later.line, key, later.line.oword.keyword)
                        )
                    closing.append(ArmAgain(later.line, later.body))
                if key in self.tracked:
                    return closing + [LabelCheck(stmt.end, key, "endif")]
                return closing + [IfEnd(stmt.end)]
            return None
        if (
            isinstance(stmt, Loop)
            and (stmt.kind in ("do", "while", "repeat") or stmt.end is None)
            and not stmt.back
            and stmt.reuses is None
            and id(stmt) not in self.dead
        ):
            head = self._resume_in(stmt.body, first, leaves)
            if not head:
                return None
            if stmt.end is None:
                return head  # abandoned: rs274 runs on into the outer line
            if stmt.kind == "do" and stmt.key in self.tracked:
                return head + [LabelCheck(stmt.end, stmt.key, "do-end"), Again(stmt)]
            return head + [Again(stmt)]
        return None

    def _resume_in(
        self, body: List[Stmt], first: Loop, leaves: Optional[Loop] = None
    ) -> Optional[List[Stmt]]:
        """What runs going back to ``first`` in ``body`` (see :meth:`_resume`)
        to the end of ``body``; None when it is not there, [] when it is
        there but cannot be followed."""
        for j, inner in enumerate(body):
            if inner is first:
                head = [first]
            elif isinstance(inner, (If, Loop)) and any(
                s is first for s in walk([inner], False)
            ):
                head = self._resume(inner, first, leaves) or []
            else:
                continue
            rest = body[j + 1 :]
            if not head or not _self_contained(head[:1] + rest, leaves):
                return []
            return head + rest
        return None

    def _dissolves(self, node: Loop) -> bool:
        """Is ``node`` a do-loop whose do line does nothing (``reuses``)
        with no break or continue of it, ending now?"""
        if node.reuses is None:
            return False
        return not any(
            (isinstance(s, Jump) and s.target is node)
            or (isinstance(s, LabelCheck) and s.loop is node)
            or (isinstance(s, Loop) and node in s.exits)
            for s in walk(node.body, into_subs=False)
        )

    def _outer_do(self, label: str, seen) -> Optional[int]:
        """Is ``label`` that of a finished do-loop in a body around this
        one (of this subroutine, holding the open construct at the depth
        returned)? rs274 has recorded the label for it: it ran first."""
        if seen is None or seen[0] != "do" or seen[3].end is None or seen[3].back:
            return None
        if any(entry.label == label for entry in self._scope_entries()):
            return None
        body = seen[2]
        if not any(stmt is seen[3] for stmt in body):
            return None
        if body is self.main and self.stack and not isinstance(self.stack[0].node, Sub):
            return 0
        for depth, entry in enumerate(self.stack[:-1]):
            if entry.body is body and not isinstance(self.stack[depth + 1].node, Sub):
                return depth + 1
        return None

    def _do_end(self, line: nodes.Line, first: Loop, depth: int) -> None:
        """A ``while`` line ending the do-loop ``first`` of an outer body
        (:meth:`_outer_do`): everything from that do-loop on to the
        construct holding this line becomes one :attr:`Loop.back` loop,
        which the line continues when it goes back to the do."""
        body = self.stack[depth - 1].body if depth else self.main
        start = next(i for i, stmt in enumerate(body) if stmt is first)
        outer = Loop("do", first.line, body[start:], key=first.key, back=True)
        del body[start:]
        body.append(outer)
        # open (with no label a line can carry) until the body around ends
        self.stack.insert(depth, _Open("", outer, outer.body))
        crossed = [
            entry.node
            for entry in self.stack[depth + 1 :]
            if isinstance(entry.node, Loop)
        ]
        if crossed:
            outer.flagged = True
            for inner in crossed:
                inner.exits.append(outer)
        if first.key in self.tracked:
            self.body.append(LabelCheck(line, first.key, "do-end"))
        self.body.append(DoEnd(line, "continue", outer))

    def _close_loop(self, kind: str, line: nodes.Line, word: nodes.OWord) -> None:
        label = str(word.name)
        top = self._enclosing(
            label, lambda node: isinstance(node, Loop) and node.kind == kind
        )
        if top is not None:
            top.node.end = line
            self.stack.pop()
            return
        self._label_error(line, word)

    def on_endwhile(self, line: nodes.Line, word: nodes.OWord) -> None:
        self._close_loop("while", line, word)

    def on_endrepeat(self, line: nodes.Line, word: nodes.OWord) -> None:
        self._close_loop("repeat", line, word)

    def _jump(self, line: nodes.Line, word: nodes.OWord) -> None:
        label = str(word.name)
        crossed: List[Loop] = []
        repeat: Optional[Loop] = None
        for entry in reversed(self.stack):
            if isinstance(entry.node, Sub):
                break
            if not isinstance(entry.node, Loop):
                continue
            if entry.label == label:
                target = entry.node
                if target.kind == "repeat":
                    repeat = target  # rs274: break/continue only for while and do
                    break
                if crossed:
                    target.flagged = True
                    for inner in crossed:
                        if target not in inner.exits:
                            inner.exits.append(target)
                key = self._key(label)
                if key in self.tracked:
                    # a do-loop reusing a label finds what rs274 recorded
                    self.body.append(LabelCheck(line, key, word.keyword))
                    if target.kind == "do":
                        # and skips to the do's closing while line, which
                        # acts on the record too (an opener's: a duplicate)
                        self.body.append(LabelCheck(line, key, "do-end", target))
                self.body.append(Jump(line, word.keyword, target))
                return
            crossed.append(entry.node)
        key = self._key(label)
        if repeat is not None and key in self.tracked:
            # a break or continue of a repeat loop around it whose label is
            # reused: it fails naming whichever opener rs274 recorded (the
            # repeat's, or another's that ran first), decided at run time;
            # it is no jump aimed at a finished loop
            check = LabelCheck(line, key, word.keyword)
            self.body.append(check)
            if repeat.skip_fail is None:
                repeat.skip_fail = check
            return
        self._label_error(line, word)
        if repeat is not None and repeat.skip_fail is None:
            repeat.skip_fail = self.body[-1]

    on_break = _jump
    on_continue = _jump

    def _label_error(self, line: nodes.Line, word: nodes.OWord) -> None:
        """A closing line (elseif, else, endif, endwhile, endrepeat, break,
        continue) whose label is not open as it needs: rs274 names what the
        label was recorded as. For a reused label that depends on which
        opener ran, so it is looked up at run time (:class:`LabelCheck`)."""
        label = str(word.name)
        key = self._key(label)
        seen = self.labels.get(label)
        reads = len(self.body)
        try:
            self._label_checks(line, word, label, key, seen)
        finally:
            if word.keyword == "elseif":
                # rs274 reads an elseif's condition (interp_read.cc read_o)
                # before it looks the label up (convert_control_functions):
                # a condition that fails to evaluate is the error
                for stmt in self.body[reads:]:
                    if isinstance(stmt, Fail) and stmt.reads is None:
                        stmt.reads = word.expr
        failing = [s for s in self.body[reads:] if isinstance(s, (Fail, LabelCheck))]
        if failing and word.keyword not in ("break", "continue"):
            # A while or repeat loop of this label around the line: ending by
            # its condition or count, rs274 skips forward to its label and
            # lands here first, failing as when running into it.
            for entry in self._scope_entries():
                node = entry.node
                if entry.label == label and isinstance(node, Loop):
                    if node.kind in ("while", "repeat") and not (
                        node.back or node.skip
                    ):
                        if node.skip_fail is None:
                            node.skip_fail = failing[-1]
                    break

    def _label_checks(self, line, word, label, key, seen) -> None:
        if key in self.tracked:
            self.body.append(LabelCheck(line, key, word.keyword))
            if word.keyword in ("else", "elseif"):
                self.arm_checks.append(self.body[-1])
            if word.keyword in ("break", "continue") and seen is not None:
                # passed: the label is a finished loop's, and rs274 skips
                # forward to its next line (as below)
                found = (seen[0], seen[1])
                self.fail(line, NO_MATCHING_LOOP % ((line.number, line.text) + found))
                self.stale_jumps.append((key, self.body[-1]))
            return
        if seen is None:
            self.fail(line, UNDEFINED_LABEL % (line.number, line.text))
            return
        found = (seen[0], seen[1])
        if word.keyword not in ("break", "continue"):
            # The construct with this label is no longer open here (or is
            # another kind): rs274 knows the label only if its opener ran
            # (not inside an arm not taken or a loop never entered), else
            # it is undefined. Run time decides.
            if self._track(key, seen):
                self.body.append(LabelCheck(line, key, word.keyword))
                if word.keyword in ("else", "elseif"):
                    # where the if ran, this is an arm line run into: where
                    # an arm has run it skips to the next line of its label
                    self.arm_checks.append(self.body[-1])
                return
        if word.keyword == "endif":
            message = NO_MATCHING_ENDIF % ((line.number, key) + found + (line.text,))
        elif word.keyword in ("elseif", "else"):
            message = NO_MATCHING_IF % ((line.number, line.text) + found)
        elif word.keyword in ("break", "continue"):
            message = NO_MATCHING_LOOP % ((line.number, line.text) + found)
            if seen[0] in ("while", "do"):
                # rs274 skips forward to the label: with no line carrying it
                # later in the file, that is the end of the file (finish).
                # Unless that opener never ran (an arm not taken): then rs274
                # knows no such label, which only the run can tell.
                if self._track(key, seen):
                    self.body.append(LabelCheck(line, key, word.keyword))
                self.fail(line, message)
                self.stale_jumps.append((key, self.body[-1]))
                return
        else:
            message = NO_MATCHING_END % ((line.number, line.text) + found)
        self.fail(line, message)

    def _break_to_do_end(self, fail: Fail, line: nodes.Line, word: nodes.OWord) -> bool:
        """A break of a finished do-loop (``fail``) whose skip lands on a
        while line of the label (``line``), which ends that do-loop: the
        break pending, rs274 does not loop back, and goes on after the
        line. Where the break stands in this body (or in ifs in it), the
        statements from it to the line become a loop run once that the
        break leaves (the line itself, run into, ends the do-loop as
        usual). False elsewhere: not followed."""
        seen = self.labels.get(str(word.name))
        if seen is None or seen[0] != "do" or fail.line is None:
            return False
        if fail.line.oword is None or fail.line.oword.keyword != "break":
            return False
        skip = self._run_once_from(fail, None)
        if skip is None:
            return False
        self.stack.append(_Open("", skip, skip.body))
        self.skips_to.append((line, skip))
        return True

    def _jump_to_do(self, fail: Fail) -> bool:
        """A break or continue of a finished loop (``fail``) whose skip
        lands on a do line of the label, where rs274 goes on (the do line
        does nothing): where the jump stands in this body (or in ifs in
        it), the statements from it to the do line become a loop run once
        that it leaves, setting rs274's flag as the jump would (as
        :meth:`_jumps_land_here`). False elsewhere: not followed."""
        if fail.line is None or fail.line.oword is None:
            return False
        kind = fail.line.oword.keyword
        if kind not in ("break", "continue"):
            return False
        return self._run_once_from(fail, kind) is not None

    def _run_once_from(self, fail: Fail, flag: Optional[str]) -> Optional[Loop]:
        """Where ``fail`` (a jump's line) stands in this body, or in ifs in
        it: the statements from it on become a loop run once (returned),
        which the jump, now in ``fail``'s place, leaves (a landing jump with
        rs274's ``flag`` to set, or None for a plain break of it). None,
        nothing changed, where ``fail`` is not there."""
        for index, stmt in enumerate(self.body):
            holder = self.body if stmt is fail else _holder(stmt, fail)
            if holder is not None:
                break
        else:
            return None
        skip = Loop("do", fail.line, self.body[index:], key="", skip=flag is not None)
        del self.body[index:]
        self.body.append(skip)
        self._moved_into(skip)
        if holder is self.body:
            holder = skip.body
        position = next(k for k, inner in enumerate(holder) if inner is fail)
        holder[position] = Jump(fail.line, "break", skip, flag=flag or "")
        return skip

    def _land(self, fail: Fail, line: nodes.Line, word: nodes.OWord) -> None:
        """A break or continue of a finished loop (``fail``): rs274 takes it
        for a real one and skips forward to the next line with the label,
        ``line``, which it then executes as what it is. Where that fails
        whatever the run, ``fail`` becomes that failure (a do, an endwhile
        of the while or another break or continue would carry on: left)."""
        if word.keyword == "while" and self._break_to_do_end(fail, line, word):
            return
        if word.keyword == "do" and self._jump_to_do(fail):
            return
        message = self._land_message(self.labels.get(str(word.name)), line, word)
        if message is None:
            return
        fail.line, fail.message = line, message
        if word.keyword in ("if", "elseif", "while", "repeat"):
            # rs274 reads the condition (and fails there) before the label
            fail.reads = word.expr

    def _land_message(
        self, seen, line: nodes.Line, word: nodes.OWord, key: Optional[str] = None
    ) -> Optional[str]:
        """How a line with a label recorded as ``seen`` fails when a skip
        for the label stops there, or None where it would carry on."""
        if seen is None:
            return None
        kind, first = seen[0], seen[1]
        number, text = line.number, line.text
        keyword = word.keyword
        if kind == "if" and keyword in ("elseif", "else", "endif"):
            return None  # the if's own lines: the skip goes on or ends
        if keyword == "if":
            message = DUPLICATE_IF % (number, first, text)
        elif keyword == "repeat" or (keyword == "while" and kind != "do"):
            message = DUPLICATE_LOOP % (number, text, first)
        elif keyword in ("elseif", "else"):
            message = NO_MATCHING_IF % (number, text, kind, first)
        elif keyword == "endif":
            key = key or self._key(str(word.name))
            message = NO_MATCHING_ENDIF % (number, key, kind, first, text)
        elif keyword == "endrepeat" or (keyword == "endwhile" and kind != "while"):
            message = NO_MATCHING_END % (number, text, kind, first)
        else:
            return None
        return message

    # -- constructs left open ----------------------------------------------

    def _enclosing(self, label: str, fits) -> Optional[_Open]:
        """The open construct a closing line with ``label`` belongs to, now
        on top of the stack, or None.

        rs274 pairs nothing: a closing line acts on whatever its label was
        last opened as. So an ``o1 endif`` also closes ``o1 if`` when an
        ``o2 while`` inside it was never closed; the constructs between are
        abandoned (:meth:`_abandon`)."""
        for depth in range(len(self.stack) - 1, -1, -1):
            entry = self.stack[depth]
            if isinstance(entry.node, Sub):
                return None
            if entry.label == label:
                if id(entry.node) in self.dead and not fits(entry.node):
                    continue  # not its closing line: the outer one's
                if not fits(entry.node) or self._reopened(label, depth):
                    return None
                while len(self.stack) > depth + 1:
                    self._abandon(self.stack.pop())
                return entry
        return None

    def _scope_entries(self) -> List[_Open]:
        """The open constructs of the current subroutine (or main body),
        innermost first."""
        if not self.stack.subs:
            return self.stack[::-1]
        entries: List[_Open] = []
        for entry in reversed(self.stack):
            if isinstance(entry.node, Sub):
                break
            entries.append(entry)
        return entries

    def _reopened(self, label: str, depth: int) -> bool:
        """Is ``label`` also open above ``depth`` (a reused label)?"""
        return any(
            entry.label == label and id(entry.node) not in self.dead
            for entry in self.stack[depth + 1 :]
        )

    def _abandon(self, entry: _Open) -> None:
        """A construct whose closing line never comes: where rs274 would
        skip forward to its label, it reads to the end of the file and fails
        there (the line is known at :meth:`finish`)."""
        node = entry.node
        key = self._key(entry.label)
        if isinstance(node, Loop) and node.back:
            return  # it ends where the body around it ends
        if isinstance(node, Loop):
            node.eof = self._eof_fail(key, node.line)
        elif isinstance(node, If):
            arms = node.branches + ([node.orelse] if node.orelse else [])
            for k, arm in enumerate(arms[:-1]):
                # after a taken arm, the next arm's line starts the skip
                # (which fails earlier at a line it cannot read, or stops at
                # a line reusing the label: codegen)
                later = range(k + 1, len(arms))
                if first_text_error([arms[j].body for j in later]) is None and not any(
                    j in node.landings for j in later
                ):
                    arm.body.append(self._eof_fail(key, arms[k + 1].line))
            if node.orelse is None:
                last = node.branches[-1].line
                node.orelse = Branch(last, [self._eof_fail(key, last)])

    def _eof_fail(self, key: str, origin: Optional[nodes.Line] = None) -> Fail:
        """Skipping to ``key``'s label from ``origin``, rs274 reaches the end
        of the file (the message and line are known at :meth:`finish`),
        unless a later line carries the label (:meth:`_later_landing`)."""
        fail = Fail(None, eof_message(self.demarcated))
        self.eof_fails.append((fail, key))
        if origin is not None:
            self.eof_origins[id(fail)] = origin
        return fail

    def _later_landing(self, fail: Fail, key: str) -> bool:
        """A skip for ``key`` that no closing line of its own ends stops at
        the next line with the label wherever it is (inside another
        construct): where that line fails whatever the run, ``fail`` becomes
        that failure. A line rs274 cannot read on the way fails first."""
        origin = self.eof_origins.get(id(fail))
        if origin is None:
            return False
        for number, line_key, line, word, seen in self.labelled:
            if number <= origin.number or (line.file or "") != (origin.file or ""):
                continue
            if line_key is None:  # unreadable: the skip fails there
                fail.line, fail.message = line, line.error
                return True
            if line_key != key:
                continue
            if (
                word.keyword in ("break", "continue")
                and seen is not None
                and seen[0] in ("while", "do")
            ):
                # the loop's own break or continue: rs274 skips on from it
                continue
            message = self._land_message(seen, line, word, key)
            if message is None:
                if key in self.tracked and word.keyword in ("elseif", "else", "endif"):
                    # an if's own line, where the if ran: the skip ends or
                    # goes on there (not followed); where another opener
                    # recorded the label (or none did), it fails there
                    fail.check = LabelCheck(line, key, word.keyword)
                return False
            fail.line, fail.message = line, message
            if word.keyword in ("if", "elseif", "while", "repeat"):
                fail.reads = word.expr
            if key in self.tracked:
                fail.check = LabelCheck(line, key, word.keyword)
            return True
        return False

    # -- labels -----------------------------------------------------------

    def _key(self, label: str) -> str:
        """rs274's name for a label: the subroutine's name, ``#``, the label."""
        sub = self.open_sub()
        return "%s#%s" % (sub.name if sub is not None else "", label)

    def _register(self, line: nodes.Line, word: nodes.OWord, node) -> None:
        """Remember an opener's label. A label already used by a closed
        opener is checked at run time (:class:`LabelCheck`), at every opener
        with it: whether rs274 fails depends on which of them it executed."""
        label = str(word.name)
        seen = self.labels.get(label)
        if seen is None:
            if self._unreachable():
                # never run (and no skip for a label no line has used yet
                # lands here): rs274 records the label at the first opener
                # that does run, a later one
                return
            self.labels[label] = (word.keyword, line.number, self.body, node)
            return
        key = self._key(label)
        self._track(key, seen)
        self.body.insert(len(self.body) - 1, LabelCheck(line, key, word.keyword))

    def _unreachable(self) -> bool:
        """Does an unconditional break, continue or return come before
        this line in its body or in a body around it (of this subroutine
        or the main program)? Then running code never reaches the line."""
        entries = self._scope_entries()
        bodies = [entry.body for entry in entries]
        if len(entries) == len(self.stack):
            bodies.append(self.main)
        else:
            bodies.append(self.stack[-len(entries) - 1].body)  # the subroutine's
        for body in bodies:
            for stmt in body:
                if type(stmt) is Return:
                    return True
                if type(stmt) is Jump and not self._landed_after(stmt):
                    return True
        for entry in entries:
            known = entry.condition
            if known is not None and known[1] is None and known[0] is entry.body:
                continue  # (the usual case, in a line)
            if self._never_entered(entry):
                return True
        return False

    def _never_entered(self, entry: _Open) -> bool:
        """Is the open construct ``entry`` one running code never enters
        (a repeat of none, a while whose condition is a false constant, an
        arm whose condition is, or one after an arm whose condition is a
        true constant)? Unless a skip for an earlier label can land inside
        it: a line in it with a label used before its opener."""
        node = entry.node
        known = entry.condition
        if known is None or known[0] is not entry.body:
            known = entry.condition = (entry.body, _condition_start(node, entry.body))
        start = known[1]
        if start is None:
            return False
        if isinstance(node, Loop) and (
            node.back or node.skip or node.reuses is not None
        ):
            return False
        earlier = {
            key for number, key, _, _, _ in self.labelled if number <= start.number
        }
        own = set()
        if isinstance(node, If):  # its arm lines: where its skips land, no further
            own = {arm.line.number for arm in node.branches}
            if node.orelse is not None:
                own.add(node.orelse.line.number)
        return not any(
            key in earlier
            for number, key, _, _, _ in self.labelled
            if number > start.number and number not in own
        )

    def _landed_after(self, jump: "Jump") -> bool:
        """Does a line with the label of ``jump`` come after it (so far)?
        Its skip stops there, and running code goes on from that line."""
        label = str(jump.line.oword.name)
        key = self._key(label)
        return any(
            number > jump.line.number and line_key == key
            for number, line_key, _, _, _ in self.labelled
        )

    def _track(self, key: str, seen: tuple) -> bool:
        """From now on, look ``key`` up at run time: the opener first seen
        with it (``seen``) records it when it runs (runtime.olabels). False
        when that opener is no longer a statement of its body (a construct
        abandoned or replaced by a failure): nothing is tracked."""
        if key in self.tracked:
            return True
        _, _, body, first = seen
        index = next((i for i, stmt in enumerate(body) if stmt is first), None)
        if index is None:
            return False
        self.tracked.add(key)
        line1 = first.branches[0].line if isinstance(first, If) else first.line
        body.insert(index, LabelCheck(line1, key, seen[0]))
        if isinstance(first, Loop) and first.kind == "do" and first.end:
            first.body.append(LabelCheck(first.end, key, "do-end"))
        return True

    def _duplicate(self, line: nodes.Line, word: nodes.OWord, message: str) -> bool:
        """Fail (and return True) if an opener reuses the label of a
        construct still open around it; a closed one's label is checked at
        run time (:meth:`_register`)."""
        label = str(word.name)
        seen = self.labels.get(label)
        if seen is None or not any(
            entry.label == label and not isinstance(entry.node, Sub)
            for entry in self._scope_entries()
        ):
            return False
        if message == DUPLICATE_IF:
            text = message % (line.number, seen[1], line.text)
        else:
            text = message % (line.number, line.text, seen[1])
        key = self._key(label)

        def failure() -> Stmt:
            # A label reused elsewhere too: the line names whichever opener
            # rs274 recorded first, which only the run can tell.
            if key in self.tracked:
                return LabelCheck(line, key, word.keyword)
            return Fail(line, text, reads=word.expr)

        self.body.append(failure())
        top = self.stack[-1] if self.stack else None
        if top is not None and top.label == label and not isinstance(top.node, Sub):
            # rs274 stops skipping at the next line with the label being
            # skipped to, so this line fails on every path through ``top``:
            # also when its condition is false or an earlier arm ran.
            self.stack.pop()
            self.body.append(failure())
            if isinstance(top.node, Loop) and top.node.eof is None:
                # a break or continue skipping forward for the loop's label
                # (or its condition failing) lands here too
                top.node.eof = failure()
        else:
            # Deeper inside: run, or landed on, the line fails; skipped with
            # what holds it, its lines up to its own closing line are never
            # looked at. Those closing lines are its, not the outer one's.
            dead = (
                If([Branch(line)]) if word.keyword == "if" else Loop(word.keyword, line)
            )
            body = dead.branches[0].body if isinstance(dead, If) else dead.body
            outer = next(e.node for e in self._scope_entries() if e.label == label)
            if (
                isinstance(outer, Loop)
                and outer.kind in ("while", "repeat")
                and not (outer.back or outer.skip)
                and outer.skip_fail is None
            ):
                # ending by its condition or count, the loop skips forward
                # to its label and lands here first (Loop.skip_fail)
                outer.skip_fail = failure()
            self.stack.append(_Open(label, dead, body))
            self.dead.add(id(dead))
        return True

    # -- end of file ------------------------------------------------------

    def _arm_skips_out(self, line: nodes.Line, word: nodes.OWord) -> None:
        """``line`` is the next line of the label of an else or elseif line
        run into inside an earlier construct of this body (a loop, an if,
        however deep): where an arm has run, rs274 skips from that line to
        this one, out of the construct, reading what lies between (no
        closing line on the way acts, no loop goes round again). The
        statements from that construct on become a loop run once
        (:attr:`LabelCheck.leave`) that the skip leaves; where no arm has
        run, the code runs on as written, to this line."""
        if not isinstance(word.name, str) or not self.arm_checks:
            return
        key = self._key(str(word.name))
        for check in self.arm_checks:
            if check.key != key or check.leave is not None or check.eof is not None:
                continue
            start = check.line.number
            if (check.line.file or "") != (line.file or "") or start >= line.number:
                continue
            if any(
                start < number < line.number
                and (later.file or "") == (line.file or "")
                and (found == key or found is None)
                for number, found, later, _, _ in self.labelled
            ):
                continue  # it lands earlier, or fails on the way (unreadable)
            index = next(
                (
                    i
                    for i, stmt in enumerate(self.body)
                    if stmt is not check
                    and any(s is check for s in walk([stmt], False))
                ),
                None,
            )
            if index is None:
                continue  # in this body itself (flat_arms), or not in it
            crossed = [
                stmt
                for stmt in walk(self.body[index:], False)
                if isinstance(stmt, Loop)
                and any(s is check for s in walk([stmt], False))
            ]
            skip = Loop("do", check.line, self.body[index:], key="")
            del self.body[index:]
            self.body.append(skip)
            self._moved_into(skip)
            self._wrapped_jumps(skip)
            if crossed:
                skip.flagged = True
                for loop in crossed:
                    loop.exits.append(skip)
            check.leave = skip

    def _moved_into(self, loop: Loop) -> None:
        """Statements of this body now stand in ``loop``'s: so do the
        labels of the openers among them (a later line finds them there)."""
        for name, seen in self.labels.items():
            if seen[2] is self.body and any(stmt is seen[3] for stmt in loop.body):
                self.labels[name] = seen[:2] + (loop.body, seen[3])

    def _wrapped_jumps(self, skip: Loop) -> None:
        """Jumps inside the new loop ``skip`` to loops around it now cross it
        too: they leave it by their target's flag (Loop.exits)."""
        inside = {id(stmt) for stmt in walk(skip.body, False) if isinstance(stmt, Loop)}
        for stmt in walk(skip.body, False):
            if isinstance(stmt, Jump) and id(stmt.target) not in inside:
                stmt.target.flagged = True
                if stmt.target not in skip.exits:
                    skip.exits.append(stmt.target)
            if isinstance(stmt, Loop):
                for target in stmt.exits:
                    if id(target) not in inside and target not in skip.exits:
                        skip.exits.append(target)

    def _arms_to_eof(self) -> None:
        """An else or elseif line of a reused label that fits no open if
        (a skip landed in a do-loop of the label) with no line of its label
        after it in the file: where an arm has run, rs274 skips from it to
        the end of the file (past whatever holds the line), and fails
        there, or at a line it cannot read on the way."""
        for check in self.arm_checks:
            line = check.line
            if any(
                number > line.number
                and key == check.key
                and (later.file or "") == (line.file or "")
                for number, key, later, _, _ in self.labelled
            ):
                continue
            check.eof = self._eof_fail(check.key, line)

    def finish(
        self, last: Optional[nodes.Line], closing: Optional[nodes.Line] = None
    ) -> None:
        """The end of the file (``closing``: the closing ``%`` line)."""
        self._arms_to_eof()
        while self.stack:
            entry = self.stack.pop()
            if isinstance(entry.node, If):
                # an arm taken, the next arm's line skips to the end
                self._abandon(entry)
            elif isinstance(entry.node, Loop) and entry.node.back:
                pass  # no loop of the text (DoEnd)
            elif isinstance(entry.node, Loop) and last is not None:
                # its break and continue lines skip to the end of the file
                entry.node.eof = self._eof_fail(entry.node.key, entry.node.line)
            elif isinstance(entry.node, Sub):
                self.stack.append(entry)
                break
        self.eof_fails += [(fail, key) for key, fail in self.stale_jumps]
        self.eof_fails += [
            (fail, name) for name, fail in self.orphans if fail.line is None
        ]
        for fail, key in self.eof_fails:
            if self._later_landing(fail, key):
                continue
            if closing is not None:
                # rs274 meets the closing % while it skips
                fail.line, fail.finish = closing, True
                fail.message = "Failed to find sub 'O%s' before EOF" % key
            else:
                fail.line, fail.message = last, eof_message(self.demarcated)
        if self.fanuc is not None and last is not None:
            # A call runs the definition into the end of the file.
            sub, body, start = self.fanuc
            sub.body = body[start:] + [Fail(last, eof_message(self.demarcated))]
        while self.stack:
            entry = self.stack.pop()
            if (
                isinstance(entry.node, Loop)
                and last is not None
                and not entry.node.back
            ):
                # its break and continue lines skip to the end of the file
                entry.node.eof = Fail(last, eof_message(self.demarcated))
            elif isinstance(entry.node, If):
                self._abandon(entry)
                for fail, _ in self.eof_fails:
                    fail.line = fail.line or last
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


def build(
    file: str, lines: List[nodes.Line], demarcated: bool = False, opened: bool = False
) -> Program:
    """Pair the O-words of one file's ``lines`` into a :class:`Program`.

    A lone closing ``%`` line ends the program with :class:`Finish`; lines
    after it are never read by rs274 and are dropped. ``opened``: ``lines``
    start after the opening ``%`` of a demarcated file.
    """
    builder = _Builder(file, demarcated)
    for line in lines:
        word = getattr(line, "oword", None)
        if word is not None and word.keyword == "endsub":
            builder.endsubs.setdefault(str(word.name), []).append(line.number)
    seen_open = opened
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
    if type(last) is RowRun:
        last = last.final()
    builder.finish(last, closing)
    if last is None and demarcated and lines:
        # Only the opening %: rs274 then reads nothing more, and echoes "".
        last = nodes.Line(lines[0].number + 1, "", file)
    program = Program(
        file,
        builder.main,
        builder.subs,
        last=last,
        open_error=opening_error(lines),
    )
    # rs274 reads an M98 line's words wherever it skips over it, even a
    # line of a construct that failed as a whole (codegen.skipped_reads)
    read = closing.number if closing is not None else None
    program.m98_lines = [
        line
        for line in lines
        if type(line) is not RowRun
        and line.oword is not None
        and line.oword.keyword == "m98"
        and (read is None or line.number < read)
    ]
    return program


def m98_may_strand(line: nodes.Line) -> bool:
    """An M98 line whose L word is not a non-zero number (``L0``, or a
    value known only at run time): rs274 may enter the call's frame and
    never run or leave it."""
    for w in line.words:
        if w.letter == "l":
            return not (isinstance(w.value, nodes.Num) and w.value.value != 0)
    return False


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
    if isinstance(stmt, ArmAgain):
        return [stmt.body]
    return []


def _constant(expr: Optional[nodes.Expr]) -> Optional[float]:
    """The value of a condition or count made of numbers alone (compared,
    combined), or None. Comparisons are decided only where rs274's
    tolerance cannot matter."""
    if isinstance(expr, nodes.Num):
        return expr.value
    if isinstance(expr, nodes.Bracket):
        return _constant(expr.inner)
    if not isinstance(expr, nodes.Binary):
        return None
    a, b = _constant(expr.left), _constant(expr.right)
    if a is None or b is None:
        return None
    if expr.op in ("eq", "ne", "gt", "ge", "lt", "le"):
        if a != b and abs(a - b) < 1e-3:
            return None
        result = {
            "eq": a == b,
            "ne": a != b,
            "gt": a > b,
            "ge": a >= b,
            "lt": a < b,
            "le": a <= b,
        }[expr.op]
        return 1.0 if result else 0.0
    if expr.op == "and":
        return 1.0 if a != 0.0 and b != 0.0 else 0.0
    if expr.op == "or":
        return 1.0 if a != 0.0 or b != 0.0 else 0.0
    return None


def _plain_do(node) -> bool:
    """A do-loop of the text, with nothing reused or run again."""
    return (
        isinstance(node, Loop)
        and node.kind == "do"
        and node.reuses is None
        and not node.back
        and not node.skip
        and node.back_into is None
    )


def _holder(stmt: Stmt, target: Stmt) -> Optional[List[Stmt]]:
    """The statement list holding ``target`` in an arm of the if ``stmt``,
    however deep (not inside a loop); else None."""
    if isinstance(stmt, If):
        arms = stmt.branches + ([stmt.orelse] if stmt.orelse else [])
        for arm in arms:
            if any(inner is target for inner in arm.body):
                return arm.body
            for inner in arm.body:
                found = _holder(inner, target) if isinstance(inner, If) else None
                if found is not None:
                    return found
    return None


def _self_contained(body: List[Stmt], leaves: Optional[Loop] = None) -> bool:
    """Do the break and continue lines in ``body`` all aim at loops of it
    (so it can run anywhere: :meth:`_Builder._back_into`), or break
    ``leaves`` (the loop around it all, which running again they leave)?"""
    stmts = list(walk(body, False))
    inner = {id(stmt) for stmt in stmts if isinstance(stmt, Loop)}
    if leaves is not None:
        inner.add(id(leaves))
    for stmt in stmts:
        if isinstance(stmt, (DoEnd, Define)):
            return False
        if isinstance(stmt, Jump) and id(stmt.target) not in inner:
            return False
        if isinstance(stmt, Jump) and stmt.target is leaves and stmt.kind != "break":
            return False
        if isinstance(stmt, Loop) and any(id(e) not in inner for e in stmt.exits):
            return False
        if (
            isinstance(stmt, LabelCheck)
            and stmt.loop is not None
            and id(stmt.loop) not in inner
        ):
            return False
    return True


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


def definition_values(sub: Sub) -> List[nodes.Line]:
    """The lines whose value rs274 reads while it reads past the definition
    of ``sub`` (interp_read.cc read_o: skipping to the sub's own label, it
    evaluates the value of a ``return`` or ``endsub`` with that label, and
    sets ``#<_value>``, or clears it when there is none): in text order.
    A line with more than comments after its O-word (which fails when it
    runs) counts too: while skipping, rs274 reads no further than a value
    right after the keyword, so ``endsub G20`` clears the value and
    ``endsub [2] #1=3`` sets it to 2."""
    if sub.fanuc:
        return []
    found = []
    for stmt in walk(sub.body):
        failing = type(stmt) is Block and stmt.line.error == AFTER_OWORD
        if (failing or isinstance(stmt, Return)) and stmt.line.oword is not None:
            word = stmt.line.oword
            if word.keyword in ("return", "endsub") and word.name == sub.name:
                found.append(stmt.line)
    return found


def first_text_error(bodies: List[List[Stmt]]) -> Optional[nodes.Line]:
    """The first line in ``bodies`` (source order) that rs274 fails on even
    when only skipping over it (:func:`skip_error`)."""
    for body in bodies:
        for stmt in walk(body):
            if isinstance(stmt, Block) and skip_error(stmt.line):
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
    after it (rs274 has read the ``sub`` line by then). A call of a name
    that ``<name>.ngc`` defines goes through ``found`` (the machine calls
    what is defined by then, else that file's). Any other call (a name
    defined later, or inside an ``if``) is resolved by name at run time,
    which is what rs274 does. Calls in external files' code were given
    ``found`` by compiler.py.
    """
    top_level = {
        stmt.sub.name: stmt.sub
        for stmt in program.body
        if isinstance(stmt, Define) and stmt.sub.define_error is None
    }
    everywhere = list(walk(program.body))
    for sub in program.externals:
        everywhere.extend(walk(sub.body))
    for stmt in everywhere:
        if isinstance(stmt, FanucCall) and isinstance(stmt.line.oword.name, str):
            stmt.sub = stmt.found or fanuc_after(program.subs, stmt)
        if not isinstance(stmt, Call) or not isinstance(stmt.name, str):
            continue
        if stmt.found is not None:
            continue
        sub = top_level.get(stmt.name)
        if sub is not None and sub.line.number < stmt.line.number:
            stmt.sub = sub
        elif stmt.name in program.found:
            stmt.found = program.found[stmt.name]


def fanuc_after(subs: List[Sub], call: FanucCall) -> Optional[Sub]:
    """The Fanuc subroutine an ``M98`` of the main file finds reading ahead
    from its line: the first definition of that number further on (one
    before it is never found: rs274 records a Fanuc definition only when a
    search finds it)."""
    name = call.line.oword.name
    for sub in subs:
        if sub.fanuc and sub.name == name and sub.line.number > call.line.number:
            return sub
    return None


# --------------------------------------------------------------------------
# Finding a subroutine the way rs274 seeks it in a subroutine file
# --------------------------------------------------------------------------


def seek_sub(lines: list, after: int, name: str) -> Optional[Tuple[str, int]]:
    """rs274 skipping forward through a file's ``lines`` from line number
    ``after`` for ``o<name> sub`` (it has opened the file for the call, or
    the call is on line ``after`` of it and the name is not known yet).

    Returns ``("sub", i)`` for the definition at ``lines[i]``, ``("fanuc",
    i)`` for a bare ``O<name>`` (which an ``o.. call`` cannot run),
    ``("error", i)`` for a line rs274 fails on while merely skipping it
    (:func:`skip_error`), or None at the end of the file. Every other line,
    definitions of other names included, is passed over."""
    for index, line in enumerate(lines):
        if type(line) is RowRun or line.number <= after:
            continue
        if line.percent:
            return "percent", index  # (a subroutine file under a % main)
        if skip_error(line):
            return "error", index
        word = line.oword
        if word is None or not isinstance(word.name, str) or word.name != name:
            continue
        if word.keyword == "sub":
            return "sub", index
        if word.keyword == "fanuc_sub":
            return "fanuc", index
    return None


def entry_sub(file: str, lines: list, index: int, demarcated: bool = False) -> Sub:
    """The subroutine whose ``sub`` line is ``lines[index]``, as a call
    runs it once rs274 has found it there: from the next line on, until an
    ``endsub`` or ``return`` (of any name) runs; ``sub`` lines on the way
    do nothing. Running off the end of the file fails there."""
    first = lines[index]
    if first.error is not None:
        # Skipping to this line, rs274 reads only its O-word.
        first = nodes.Line(
            first.number, first.text, first.file, oword=first.oword, n_text=first.n_text
        )
    program = build(file, [first] + list(lines[index + 1 :]), demarcated, True)
    sub = program.subs[0]
    if sub.end is None and program.last is not None:
        closing = [s for s in program.body if isinstance(s, Finish)]
        if not closing:
            sub.body.append(Fail(program.last, eof_message(demarcated)))
    sub.define_error = None
    return sub


def seek_result(
    file: str,
    lines: list,
    last: Optional[nodes.Line],
    after: int,
    name: str,
    demarcated: bool = False,
) -> Sub:
    """What a call of ``name`` runs when rs274 seeks it in ``file`` from
    line ``after``: the subroutine found (:func:`entry_sub`), or a body
    that fails as rs274 does on the way."""
    found = seek_sub(lines, after, name)
    if found is None:
        where = last if last is not None else nodes.Line(0, "", file)
        return Sub(where, name, [SeekFail(where, file, name, after)], end=where)
    kind, index = found
    line = lines[index]
    if kind == "sub":
        return entry_sub(file, lines, index, demarcated)
    if kind == "percent":
        # the main file's closing % ends any file rs274 reads
        fail = Fail(line, "Failed to find sub 'O%s' before EOF" % name, finish=True)
        return Sub(line, name, [fail], end=line)
    message = FANUC_NEEDS_M98 if kind == "fanuc" else line.error
    return Sub(line, name, [Fail(line, message)], end=line)


def seek_fanuc(
    file: str,
    lines: list,
    last: Optional[nodes.Line],
    after: int,
    name: str,
    demarcated: bool = False,
) -> Sub:
    """What ``M98 P<name>`` runs when rs274 seeks ``O<name>`` in ``file``
    from line ``after`` (0: it has just opened ``<name>.ngc``): the Fanuc
    subroutine found there, from its ``O`` line to ``M99``; or a body that
    fails as rs274 does on the way (the end of the file, a line it cannot
    read, an ``o<name> sub``, which M98 cannot run)."""
    found = seek_sub(lines, after, name)
    if found is None or found[0] == "percent":
        return seek_result(file, lines, last, after, name, demarcated)
    kind, index = found
    line = lines[index]
    if kind == "fanuc":
        program = build(file, list(lines[index:]), demarcated, True)
        return program.subs[0]
    message = O_SUB_NEEDS_CALL if kind == "sub" else line.error
    return Sub(line, name, [Fail(line, message)], end=line)
