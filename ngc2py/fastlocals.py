"""Named locals kept in Python variables: ``#<x_start>`` as ``x_start``.

A G-code loop reads and sets its named locals several times an iteration;
as attributes of the locals store (``v.i``) each costs about 25 ns more than
a Python local variable, a tenth of a simple loop's time, and the code reads
worse. Where it is safe, the code generator writes such a name as a local
variable of the generated function (:func:`variable`: the name itself, or
``v_`` and the name where Python or the generated code takes it), and the
store never holds it.

Safe means that nothing can tell the difference, which this pass decides for
each generated function from its statements alone:

* the function is one Python function: no part of it nested deep enough to
  become a helper function (``codegen.NEST_LIMIT``), and not a main program
  split into chunks (the code generator asks only when it is not), and no if
  whose skip lands inside an arm (``st.If.landings``);
* nothing reads the store by name while the program runs: no embedded
  Python, no M98 call (whose ``L0`` form hands the caller's store to the new
  call level); a name is kept in the store where an ``EXISTS`` asks for it
  or where the comment of a line with words prints it (the block gets the
  comment as text). A line of a comment alone hands the values of the
  names it prints that are variables (``m.debug(5, "#<x>", x=x)``);
* the function sets the name somewhere (a name it only reads is read from
  the store, which fails as rs274 does);
* where the name may be unset (ngc2py.assigned's reckoning of what is
  certainly set before each line), nothing reads it with a meaning other
  than failing: not the rest of a line that sets it (rs274 creates the name
  as it reads ``#<i> =``, so that reads 0: ``v.declare``), not a comment
  (which prints ``######``), not a definition's value read past it (0).

Any other read of a variable still unset raises ``UnboundLocalError``,
which the runtime turns into the store's own error, "Named parameter #<i>
not defined", with the same traceback (``runtime.params.unset_variable``:
``Machine.run``, ``ngc2py.parse``, rs274's ``-n`` continuation).

Names the store must keep (globals, ``n_args``, names Python would fold to
another one: non-ASCII) are never candidates.
"""

from __future__ import annotations

import builtins
import keyword
import re

from ngc2py import assigned, nodes
from ngc2py import structure as st
from ngc2py.parser import RowLine
from ngc2py.rowrun import RowRun
from runtime import codes, comments, ops

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, FrozenSet, Iterator, List, Set

#: The prefix of the Python variable that holds ``#<name>`` when the name
#: itself is taken: no name the code generator writes otherwise starts with it.
PREFIX = "v_"

#: Names a generated function already uses for something else: Python's
#: keywords and builtins, the machine and its stores, what generated modules
#: import from the runtime (or may), and what the code generator writes:
#: temporaries ``t1``/``i1``, loop flags ``exit_1``, ``jump``, functions.
_TAKEN = frozenset(
    keyword.kwlist
    + dir(builtins)
    + dir(ops)
    + dir(codes)
    + ["m", "p", "g", "v", "jump", "start", "run_cli", "run_rows", "rows", "run"]
)
_WRITTEN = re.compile(r"[ti]\d+|exit_\d+|nest_\d+|main(_\d+)?|o_.*|v_.*")


#: Locals the store itself defines: with OWORD_NARGS a call's ``#<n_args>``,
#: which a setting must fail to change (runtime.params.ArgCountLocals).
_STORE_KEEPS = frozenset({"n_args"})


def variable(name: str) -> str:
    """The Python variable of the G-code local ``name``: the name itself
    (``#<x_start>`` is ``x_start``) unless that is taken (``#<jump>`` is
    ``v_jump``, ``#<v_x>`` is ``v_v_x``)."""
    if name in _TAKEN or _WRITTEN.fullmatch(name) or keyword.issoftkeyword(name):
        return PREFIX + name
    return name


def comment_line(line) -> bool:
    """Is ``line`` a comment with nothing else but settings (no words, N
    number, O-word or error)? The code generator writes its block as one
    call of runtime.comments.CommentLines, after the settings."""
    return (
        type(line) is nodes.Line
        and line.comment is not None
        and not line.words
        and line.n_text is None
        and line.oword is None
        and line.error is None
    )


def comment_names(comment: nodes.Comment) -> List[str]:
    """The local names whose values a comment prints (DEBUG, PRINT, LOG,
    ABORT expand ``#<name>``), each once, in order."""
    if comment.kind not in comments.EXPANDING_KINDS or "#" not in comment.text:
        return []
    names = [
        part.name
        for part in comments.split_parts(comment.text)
        if type(part) is comments.Name and not part.name.startswith("_")
    ]
    return list(dict.fromkeys(names))


def fast_locals(body: List[st.Stmt], max_depth: int) -> Dict[str, str]:
    """The local names of a function body (``body``) that may be Python
    variables, each with its variable (``{"x-start": "x_start"}``);
    ``max_depth``: the deepest if/loop nesting the code generator writes in
    one function."""
    if _deeper_than(body, max_depth) or _lands(body):
        return {}
    set_somewhere: Set[str] = set()
    for line in _lines(body):
        if line is None:  # something that reads the store by name
            return {}
        set_somewhere.update(_set_by(line))
    known: Dict[int, assigned.Known] = {}
    assigned.known_before(body, frozenset(), known)
    unsafe = _exists_names(body) | _block_comment_names(body)
    defining = {id(line) for line in _definition_lines(body)}
    for line in _lines(body):
        before = known.get(id(line), frozenset())
        if id(line) in defining:
            # reading past a definition, an unset name reads 0
            unsafe.update(name for name in _reads(line) if name not in before)
            continue
        for i, item in enumerate(line.items):
            # rs274 creates the name as it reads "#<n> =": the rest of the
            # line reads 0 for it (v.declare)
            target = item.target if isinstance(item, nodes.Assign) else None
            if (
                isinstance(target, nodes.NamedParam)
                and target.name not in before
                and nodes.reads_name(line.items[i:], target.name)
            ):
                unsafe.add(target.name)
        if line.comment is not None:
            # an unset name prints ######: the comment needs it set (the
            # line's own settings come first)
            after = before | assigned.line_settings(line)
            unsafe.update(n for n in comment_names(line.comment) if n not in after)
    chosen = sorted(
        name
        for name in set_somewhere
        if not (
            name.startswith("_")
            or name in _STORE_KEEPS
            or not name.isascii()  # Python folds other names (NFKC): ﬁ is fi
            or name in unsafe
        )
    )
    return _variables(chosen)


def _variables(names: List[str]) -> Dict[str, str]:
    """Distinct Python variables for ``names``: a name itself where it is a
    free identifier, else its letters with ``_`` for the others (``#<z-end>``
    is ``z_end``), behind ``v_`` where that is taken (``#<pass>`` is
    ``v_pass``), and ``_`` added until it is unique."""
    variables: Dict[str, str] = {}
    used: Set[str] = set()
    for name in names:
        if variable(name) == name and name.isidentifier():
            variables[name] = name
            used.add(name)
    for name in names:
        if name in variables:
            continue
        var = variable(re.sub(r"[^a-z0-9_]", "_", name))
        if not var.isidentifier():
            var = PREFIX + var
        while var in used:
            var += "_"
        variables[name] = var
        used.add(var)
    return variables


def _definition_lines(stmts: List[st.Stmt]) -> Iterator[nodes.Line]:
    for stmt in st.walk(stmts, into_subs=False):
        if isinstance(stmt, st.Define):
            yield from st.definition_values(stmt.sub)


_NEVER_SET_DEPTH = 100


def never_set(body: List[st.Stmt]) -> FrozenSet[str]:
    """Local names a function body mentions but never sets: its own store
    never holds them (reading past a definition, ``#<x>`` there reads 0).
    Empty where something else may set the store (an M98 call)."""
    if _deeper_than(body, _NEVER_SET_DEPTH):
        return frozenset()  # (G-code nesting has no bound; Python's stack has)
    mentioned: Set[str] = set()
    set_: Set[str] = set()
    for line in _lines(body):
        if line is None:
            return frozenset()
        mentioned.update(_names(line))
        set_.update(_set_by(line))
    return frozenset(n for n in mentioned - set_ if not n.startswith("_"))


def _reads(line: nodes.Line) -> Set[str]:
    """The named parameters a line's values read (not its settings' targets)."""
    found: Set[str] = set()
    for expr in _values(line):
        for e in nodes.subexpressions(expr):
            if isinstance(e, (nodes.NamedParam, nodes.Exists)):
                found.add(e.name)
    return found


def _values(line: nodes.Line) -> Iterator[nodes.Expr]:
    for item in line.items:
        yield item.value
        if isinstance(item, nodes.Assign) and not isinstance(
            item.target, nodes.NamedParam
        ):
            yield item.target  # #[index] = ...: the index is read
    yield from _oword_and_partial(line)


def _block_comment_names(stmts: List[st.Stmt]) -> Set[str]:
    """Names printed by the comment of a line with words: the code hands the
    block its comment as text, and the runtime reads them from the store."""
    found: Set[str] = set()
    for line in _lines(stmts):
        if line is not None and line.comment is not None and not comment_line(line):
            found.update(comment_names(line.comment))
    return found


def _lands(stmts: List[st.Stmt]) -> bool:
    """Does an if make rs274 enter one of its arms in the middle (a skip that
    stops on a line reusing its label: st.If.landings)?"""
    return any(
        isinstance(stmt, st.If) and stmt.landings
        for stmt in st.walk(stmts, into_subs=False)
    )


def _deeper_than(stmts: List[st.Stmt], limit: int) -> bool:
    """Do ifs and loops nest more than ``limit`` deep (stops looking there:
    G-code nesting has no bound)?"""
    for stmt in stmts:
        arms = st.children(stmt, into_subs=False)
        if arms and (limit == 0 or any(_deeper_than(arm, limit - 1) for arm in arms)):
            return True
    return False


def _lines(stmts: List[st.Stmt]) -> Iterator[object]:
    """Every line of the statements in text order, and None for a statement
    or line after which the store may be read by name."""
    for stmt in stmts:
        if isinstance(stmt, st.FanucCall):
            yield None
            return
        if isinstance(stmt, st.Define):
            # the subroutine's own lines are another function, but the
            # values of its own return lines are read here (definition_values)
            for line in st.definition_values(stmt.sub):
                yield from _line(line)
            continue
        if isinstance(stmt, st.If):
            for branch in stmt.branches:
                yield from _line(branch.line)
                yield from _lines(branch.body)
            if stmt.orelse is not None:
                yield from _line(stmt.orelse.line)
                yield from _lines(stmt.orelse.body)
            yield from _line(stmt.end)
            continue
        if isinstance(stmt, st.ArmAgain):
            yield from _line(stmt.line)
            yield from _lines(stmt.body)
            continue
        if isinstance(stmt, st.Loop):
            yield from _line(stmt.line)
            for fail in (stmt.eof, stmt.skip_fail):  # lines read elsewhere
                yield from _line(getattr(fail, "line", None))
            yield from _lines(stmt.body)
            yield from _line(stmt.end)
            continue
        yield from _line(getattr(stmt, "line", None))


def _line(line) -> Iterator[object]:
    if line is None or type(line) in (RowLine, RowRun):
        return  # none, or literal words only
    if any("py" in comment.kind for comment in line.comments):
        yield None
        return
    if getattr(line, "fanuc_alt", None) is not None:
        yield None  # M#1 P100: an M98 call when #1 is 98
        return
    if line.oword is not None and line.oword.keyword in ("m98", "m99"):
        yield None
        return
    yield line


def _oword_and_partial(line: nodes.Line) -> Iterator[nodes.Expr]:
    """The expressions of a line's O-word (a computed name, the condition or
    value, the call's arguments) and of what was read before an error."""
    word = line.oword
    if word is not None:
        if isinstance(word.name, nodes.Expr):
            yield word.name
        if word.expr is not None:
            yield word.expr
        yield from word.args
    yield from line.partial


def _expressions(line: nodes.Line) -> Iterator[nodes.Expr]:
    for item in line.items:
        yield item.value
        yield item.target if isinstance(item, nodes.Assign) else item.value
    yield from _oword_and_partial(line)


def _names(line: nodes.Line) -> Iterator[str]:
    for expr in _expressions(line):
        for e in nodes.subexpressions(expr):
            if isinstance(e, (nodes.NamedParam, nodes.Exists)):
                yield e.name
    if line.comment is not None:
        yield from comment_names(line.comment)  # read when it is printed


def _set_by(line: nodes.Line) -> Set[str]:
    return {
        item.target.name
        for item in line.items
        if isinstance(item, nodes.Assign) and isinstance(item.target, nodes.NamedParam)
    }


def _exists_names(stmts: List[st.Stmt]) -> Set[str]:
    names = set()
    for line in _lines(stmts):
        if line is None:
            continue
        for expr in _expressions(line):
            for e in nodes.subexpressions(expr):
                if isinstance(e, nodes.Exists):
                    names.add(e.name)
    return names
