"""The two subroutine styles must not be mixed (facts from rs274).

A Fanuc-style subroutine (an ``O100`` line ... ``M99``) is called with
``M98 P100``; an ``o100 sub`` ... ``o100 endsub`` one with ``o100 call``.
rs274 finds out about a mix-up when it reaches the definition (it reads
ahead for one it does not know yet), and names the definition's line:

* ``o100 call`` finding ``O100``: "Fanuc 'O....' subroutine must be called
  with 'M98'";
* ``M98 P100`` finding ``o100 sub`` (read ahead, or read before): "'O....
  sub' subroutine must be called with 'O.... call'";
* a Fanuc subroutine running into ``endsub`` or ``return`` (any label)
  while called: "Fanuc 'O....' subroutine definition must end with 'M99'"
  (the same line read in the main flow is an ordinary top-level endsub).
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Callable, Optional

from .lazy_re import Pattern
from .errors import GCodeError, Location

FANUC_NEEDS_M98 = "Fanuc 'O....' subroutine must be called with 'M98'"
O_SUB_NEEDS_CALL = "'O.... sub' subroutine must be called with 'O.... call'"
FANUC_END_M99 = "Fanuc 'O....' subroutine definition must end with 'M99'"

# Each generated subroutine's docstring ends "(lines FIRST-LAST)".
_LINES = Pattern(r"\(lines (\d+)-\d+\)")


def definition_line(fn: Callable) -> Optional[int]:
    """The line of the main file where ``fn``'s definition starts."""
    found = _LINES.search(fn.__doc__ or "")
    return int(found.group(1)) if found is not None else None


def _definition(source, fn: Callable) -> Optional[Location]:
    """Where ``fn``'s definition starts in the main file, as rs274 reports it."""
    found = _LINES.search(fn.__doc__ or "")
    if source is None or found is None:
        return None
    line = int(found.group(1))
    return Location(source.files[0], line, source.text(0, line))


def check_ocall(machine, name: str) -> None:
    """``o<name> call`` of a sub not read yet: fail if reading ahead would
    find only a Fanuc definition of that number."""
    source = machine.source
    if source is None or name in source.subs:
        return
    fanuc = source.subs.get("O" + name)
    if fanuc is not None:
        raise GCodeError(FANUC_NEEDS_M98, _definition(source, fanuc))


def m98_find(machine, fn: Optional[Callable], number: int, read_ahead) -> Callable:
    """The subroutine ``M98 P<number>`` runs, as rs274 finds it: one an
    earlier M98 found (rs274 records it then, whichever file it is in); else
    an ``o<number> sub`` already read fails; else ``fn``, what the search
    from this call finds (compiled: in ``<number>.ngc``, else further on in
    the file the call is in; None: P is computed, or the main file has none
    further on). A definition found is recorded."""
    name = "%d" % number
    found = machine._fanuc_found.get(name)
    if found is not None:
        return found
    if fn is None:
        fn = m98_target(machine, name, read_ahead)
    else:
        known = machine._subroutines.get(name)
        if known is not None and known.fn is not None:
            raise GCodeError(O_SUB_NEEDS_CALL, _definition(machine.source, known.fn))
        source = machine.source
        if source is not None and source.unskippable and _in_main(source, fn):
            machine._skip_to(fn)  # reading ahead to it, rs274 may fail first
    if definition_line(fn) is not None:
        machine._fanuc_found[name] = fn
    return fn


def _in_main(source, fn: Callable) -> bool:
    """Is ``fn`` a subroutine defined in the main file?"""
    return any(sub is fn for sub in source.subs.values())


def m98_target(machine, name: str, read_ahead: Callable[[str], Callable]) -> Callable:
    """The subroutine ``M98 P<name>`` runs, found by name: a Fanuc one
    further on in the main file, else fail on an ``o<name> sub`` (defined
    already or further on), else what reading ahead finds (the usual
    end-of-file errors)."""
    source = machine.source
    fanuc = source.subs.get("O" + name) if source is not None else None
    if fanuc is not None and machine._after_the_call(fanuc):
        machine._skip_to(fanuc)  # reading ahead to it, rs274 may fail first
        return fanuc
    known = machine._subroutines.get(name)
    osub = known.fn if known is not None else None
    if osub is None and source is not None:
        osub = source.subs.get(name)
    if osub is not None:
        raise GCodeError(O_SUB_NEEDS_CALL, _definition(source, osub))
    return read_ahead(name)


def run_fanuc(machine, run_sub: Callable, fn: Callable) -> None:
    """Run ``fn`` as a Fanuc call, so an endsub/return in it can tell."""
    levels = machine.fanuc_levels
    levels.append(machine.call_level + 1)
    try:
        run_sub(fn)
    finally:
        levels.pop()


def in_fanuc_call(machine) -> bool:
    """Is the innermost running call an M98 call?"""
    levels = machine.fanuc_levels
    return bool(levels) and levels[-1] == machine.call_level
