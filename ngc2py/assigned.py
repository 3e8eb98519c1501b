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

from typing import Dict, FrozenSet, Iterable, List

from ngc2py import nodes
from ngc2py import structure as st
from ngc2py.parser import RowLine
from ngc2py.rowrun import RowRun

Known = FrozenSet[str]


def settled_names(program: st.Program) -> Dict[int, Known]:
    """``id(line) -> names`` certainly set before each ordinary line runs."""
    before: Dict[int, Known] = {}
    try:
        _flow(program.body, frozenset(), before)
        for sub in list(program.subs) + list(program.externals):
            _flow(sub.body, frozenset(), before)
    except RecursionError:
        # Nesting deeper than Python's stack (hostile input): know nothing,
        # so every declare stays, as without this pass.
        return {}
    return before


def _flow(stmts: Iterable[st.Stmt], known: Known, before: Dict[int, Known]) -> Known:
    for stmt in stmts:
        if isinstance(stmt, st.Block):
            if type(stmt.line) in (RowLine, RowRun):
                continue  # literal words only: no settings (and kept compact)
            before[id(stmt.line)] = known
            known = known | line_settings(stmt.line)
        elif isinstance(stmt, st.If):
            arms: List[Known] = [_flow(b.body, known, before) for b in stmt.branches]
            if stmt.orelse is not None:
                arms.append(_flow(stmt.orelse.body, known, before))
                known = known | frozenset.intersection(*arms)
        elif isinstance(stmt, st.Loop):
            _flow(stmt.body, known, before)
        elif isinstance(stmt, st.FanucCall):
            known = frozenset(name for name in known if name.startswith("_"))
    return known


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
