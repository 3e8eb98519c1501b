"""Definite assignment: which named parameters are certainly set before a line.

rs274 creates a named parameter when it reads ``#<name> =``, so a line like
``#<i> = [#<i> + 1]`` may read the name even if it was never set (it is 0).
The generated code says so with ``v.declare("i")`` before the value; a pass
over the statement tree lets the code generator leave that call out where
the name is certainly set already, as it is in the usual loop counter.

The facts are names (a leading ``_`` makes one global). They are only ever added by a line
of parameter settings alone (whose failure stops the program, so after it
the names are set), and they flow forward conservatively:

* after an if, what every arm sets, when there is an ``else``; else nothing
  new;
* after a loop, nothing new (its body may not run); inside the body, what
  held before it (later iterations know more, never less);
* a subroutine body starts with nothing known (callers differ); a call
  never unsets anything, except a Fanuc M98 call, which may rebind the
  locals (its L0 form keeps the caller on the old ones), so locals are
  forgotten after one.
"""

from __future__ import annotations


from ngc2py import nodes
from ngc2py import structure as st
from ngc2py.parser import RowLine
from ngc2py.rowrun import RowRun

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, FrozenSet, List

    Known = FrozenSet[str]


def settled_names(program: st.Program) -> Dict[int, Known]:
    """``id(line) -> names`` certainly set before each line runs."""
    before: Dict[int, Known] = {}
    try:
        known_before(program.body, frozenset(), before)
        for sub in list(program.subs) + list(program.externals):
            known_before(sub.body, frozenset(), before)
    except RecursionError:
        # Nesting deeper than Python's stack (hostile input): know nothing,
        # so every declare stays, as without this pass.
        return {}
    return before


def known_before(stmts: List[st.Stmt], known: Known, out: Dict[int, Known]) -> Known:
    """Record in ``out`` (``id(line)`` -> names) the names certainly set
    before each line of ``stmts`` runs, starting from ``known``, and return
    what is known after them. A loop's closing condition and the later
    conditions of an if know what held before the loop or the if; a line met
    twice keeps what holds both times."""
    for stmt in stmts:
        if isinstance(stmt, st.Block):
            line = stmt.line
            if type(line) in (RowLine, RowRun):
                continue  # literal words only: no settings (and kept compact)
            _note(out, line, known)
            known = known | line_settings(line)
        elif isinstance(stmt, st.If):
            for branch in stmt.branches:
                _note(out, branch.line, known)
            arms = [known_before(b.body, known, out) for b in stmt.branches]
            if stmt.orelse is not None:
                _note(out, stmt.orelse.line, known)
                arms.append(known_before(stmt.orelse.body, known, out))
                known = known | frozenset.intersection(*arms)
            _note(out, stmt.end, known)
        elif isinstance(stmt, st.Loop):
            _note(out, stmt.line, known)
            for fail in (stmt.eof, stmt.skip_fail):  # lines read elsewhere
                _note(out, getattr(fail, "line", None), known)
            known_before(stmt.body, known, out)
            _note(out, stmt.end, known)
        elif isinstance(stmt, st.ArmAgain):
            _note(out, stmt.line, known)
            known_before(stmt.body, known, out)  # may not run
        elif isinstance(stmt, st.Define):
            for line in st.definition_values(stmt.sub):
                _note(out, line, known)
        else:
            _note(out, getattr(stmt, "line", None), known)
            if isinstance(stmt, st.FanucCall):
                known = frozenset(name for name in known if name.startswith("_"))
    return known


def _note(out: Dict[int, Known], line, known: Known) -> None:
    if line is not None:
        key = id(line)
        out[key] = out[key] & known if key in out else known


def line_settings(line: nodes.Line) -> Known:
    """The named parameters a line of settings alone certainly sets."""
    if line.error or line.block_delete or not line.items:
        return frozenset()
    if not all(isinstance(item, nodes.Assign) for item in line.items):
        return frozenset()
    return frozenset(
        item.target.name
        for item in line.items
        if isinstance(item.target, nodes.NamedParam)
    )
