"""Named locals kept in Python variables: ``#<i>`` as ``v_i``.

A G-code loop reads and sets its named locals several times an iteration;
as attributes of the locals store (``v.i``) each costs about 25 ns more than
a Python local variable, a tenth of a simple loop's time. Where it is safe,
the code generator writes such a name as the local variable ``v_i`` of the
generated function, and the store never holds it.

Safe means that nothing can tell the difference, which this pass decides for
each generated function from its statements alone:

* the function is one Python function: no part of it nested deep enough to
  become a helper function (``codegen.NEST_LIMIT``), and not a main program
  split into chunks (the code generator asks only when it is not);
* nothing reads the locals store by name while the program runs: no comment
  that could expand a parameter (any comment text with ``#``, any embedded
  Python), no ``EXISTS`` of the name, and no M98 call (whose ``L0`` form
  hands the caller's store to the new call level);
* the name is first mentioned, in the text, by a line that only sets
  parameters and sets it without reading it, and every other mention comes
  after that line in the same statement list (the function's body, an arm of
  an if, a loop's body), or inside a statement after it there. Such a list
  is entered at its start and run in order (ifs and loops nest, a break or
  continue goes to a loop's start or end; an if whose skip lands inside an
  arm, ``st.If.lands``, turns the pass off), so every mention runs after the
  setting in the same pass: every read finds the name set (no "not defined"
  error to raise), and no setting needs rs274's rule that reading
  ``#<i> =`` creates the name (``v.declare``).

Names the store must keep (globals, ``n_args``, and names ``v.name`` cannot
spell) are never candidates.
"""

from __future__ import annotations

from typing import Dict, FrozenSet, Iterator, List, Set, Tuple

from ngc2py import nodes
from ngc2py import structure as st
from ngc2py.parser import RowLine
from ngc2py.rowrun import RowRun
from runtime.params import attr_safe

#: The prefix of the Python variable that holds ``#<name>``: no name the code
#: generator writes otherwise starts with it.
PREFIX = "v_"


#: Locals the store itself defines: with OWORD_NARGS a call's ``#<n_args>``,
#: which a setting must fail to change (runtime.params.ArgCountLocals).
_STORE_KEEPS = frozenset({"n_args"})


def variable(name: str) -> str:
    """The Python variable of the G-code local ``name``."""
    return PREFIX + name


def fast_locals(body: List[st.Stmt], max_depth: int) -> FrozenSet[str]:
    """The local names of a function body (``body``) that may be Python
    variables; ``max_depth``: the deepest if/loop nesting the code generator
    writes in one function."""
    if _deeper_than(body, max_depth) or _lands(body):
        return frozenset()
    first: Dict[str, nodes.Line] = {}  # name -> the first line mentioning it
    mentioned: Dict[str, Set[int]] = {}  # name -> ids of the lines
    for line in _lines(body):
        if line is None:  # something that reads the store by name
            return frozenset()
        for name in _names(line):
            first.setdefault(name, line)
            mentioned.setdefault(name, set()).add(id(line))
    tainted = _exists_names(body)
    places: Dict[int, Tuple[List[st.Stmt], int]] = {}
    _settings_lines(body, places)
    chosen: Set[str] = set()
    for name, line in first.items():
        place = places.get(id(line))
        if (
            place is None
            or name.startswith("_")
            or name in _STORE_KEEPS
            or not attr_safe(name)
            or name in tainted
            or name not in _set_by(line)
            or nodes.reads_name(line.items, name)
        ):
            continue
        # Every mention must come after the setting in its own statement
        # list: reaching them means passing it (ifs and loops nest; a jump
        # goes to a loop's start or end).
        stmts, index = place
        after = {id(later) for later in _lines(stmts[index:]) if later is not None}
        if mentioned[name] <= after:
            chosen.add(name)
    return frozenset(chosen)


def _settings_lines(stmts: List[st.Stmt], places: Dict[int, Tuple[List[st.Stmt], int]]):
    """Where each line of settings alone is: (its statement list, index)."""
    for index, stmt in enumerate(stmts):
        if type(stmt) is st.Block and _settings_only(stmt.line):
            places[id(stmt.line)] = (stmts, index)
        elif isinstance(stmt, st.If):
            for branch in stmt.branches:
                _settings_lines(branch.body, places)
            if stmt.orelse is not None:
                _settings_lines(stmt.orelse.body, places)
        elif isinstance(stmt, st.Loop):
            _settings_lines(stmt.body, places)


def _lands(stmts: List[st.Stmt]) -> bool:
    """Does an if make rs274 enter one of its arms in the middle (a skip that
    lands on a do-loop: st.If.lands)?"""
    for stmt in stmts:
        if isinstance(stmt, st.If):
            arms = [b.body for b in stmt.branches]
            if stmt.orelse is not None:
                arms.append(stmt.orelse.body)
            if stmt.lands is not None or any(_lands(arm) for arm in arms):
                return True
        elif isinstance(stmt, st.Loop) and _lands(stmt.body):
            return True
    return False


def _deeper_than(stmts: List[st.Stmt], limit: int) -> bool:
    """Do ifs and loops nest more than ``limit`` deep (stops looking there:
    G-code nesting has no bound)?"""
    for stmt in stmts:
        if isinstance(stmt, st.If):
            arms = [b.body for b in stmt.branches]
            if stmt.orelse is not None:
                arms.append(stmt.orelse.body)
        elif isinstance(stmt, st.Loop):
            arms = [stmt.body]
        else:
            continue
        if limit == 0 or any(_deeper_than(arm, limit - 1) for arm in arms):
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
    for comment in line.comments:
        if "#" in comment.text or "py" in comment.kind:
            yield None
            return
    if line.oword is not None and line.oword.keyword in ("m98", "m99"):
        yield None
        return
    yield line


def _expressions(line: nodes.Line) -> Iterator[nodes.Expr]:
    for item in line.items:
        yield item.value
        yield item.target if isinstance(item, nodes.Assign) else item.value
    word = line.oword
    if word is not None:
        if isinstance(word.name, nodes.Expr):
            yield word.name
        if word.expr is not None:
            yield word.expr
        yield from word.args
    yield from line.partial


def _names(line: nodes.Line) -> Iterator[str]:
    for expr in _expressions(line):
        for e in nodes.subexpressions(expr):
            if isinstance(e, (nodes.NamedParam, nodes.Exists)):
                yield e.name


def _settings_only(line: nodes.Line) -> bool:
    return (
        type(line) not in (RowLine, RowRun)
        and not line.error
        and not line.block_delete
        and line.oword is None
        and bool(line.items)
        and all(isinstance(item, nodes.Assign) for item in line.items)
    )


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
