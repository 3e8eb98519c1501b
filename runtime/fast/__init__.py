"""The fast paths: the reference path's results, sooner, for the common cases.

``Machine.block`` (runtime/machine.py) is the reference path: it reads,
checks and executes a block the way rs274 does, in rs274's order, and
raises its errors. Everything here handles one common case faster and
otherwise *steps aside*, having changed nothing, so that ``Machine.block``
runs the line (and raises whatever rs274 raises). Which case a part takes
rests on one flag, the machine's plain state, derived in one place
(:meth:`moves.FastPathMixin.refresh_plain`).

* :mod:`.moves`: single straight moves and arcs in the plain state (the
  machine's ``move``, ``feed``, ``rapid`` and ``arc`` methods);
* :mod:`.rows`: the loop over the code generator's data tables
  (``run_rows``, the one name generated modules import from here), with
  batches of straight moves for canons that take them;
* :mod:`.printed_rows`: rows written as the trace prints them, straight to
  trace text;
* :mod:`.arc_rows`: runs of arc rows, their centres and checks worked out a
  column at a time (the geometry itself is :mod:`runtime.arcs`');
* :mod:`.hole_rows`: rows of hole positions under a canned cycle, one hole
  drilled by the reference path and recorded, the next ones replayed.

docs/ARCHITECTURE.md ("Fast paths") says why each is fast and how a canon
takes moves in batches.
"""

from runtime.fast.rows import run_rows

__all__ = ["run_rows"]
