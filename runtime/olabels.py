"""rs274's table of O-word labels, for programs that reuse a label.

rs274 records a label (``subroutine#label``) the first time it *executes*
an opener with it (``if``, ``while``, ``repeat``, ``do``) and never forgets
it. A later opener with the same label on another line fails as a
duplicate, except a ``do`` (which silently keeps the old record) and a
``while`` after a ``do``. The ``while`` closing a do-loop fails when the
label was recorded by an opener other than a ``do``. Whether a program
fails therefore depends on which openers ran: the compiler emits these
checks only for labels it sees reused.
"""

from __future__ import annotations

from runtime import fanuc_subs

UNDEFINED_LABEL = "%d: undefined O-word label: '%s'"
NO_MATCHING = {
    "elseif": "%d: no matching 'if' label: '%s' (found '%s' in line %d)",
    "else": "%d: no matching 'if' label: '%s' (found '%s' in line %d)",
    "break": "%d: no matching while/do label: '%s' (found '%s' in line %d)",
    "continue": "%d: no matching while/do label: '%s' (found '%s' in line %d)",
    "endwhile": "%d: no matching label: '%s' (found '%s' in line %d)",
    "endrepeat": "%d: no matching label: '%s' (found '%s' in line %d)",
}
#: The openers each closing line needs (runtime.oflow's flow reads it too).
FITTING = {
    "elseif": ("if",),
    "else": ("if",),
    "endif": ("if",),
    "break": ("while", "do"),
    "continue": ("while", "do"),
    "endwhile": ("while",),
    "endrepeat": ("repeat",),
}
NO_MATCHING_ENDIF = "%d: no matching label: '%s' (found '%s' in line %d): '%s'"
DUPLICATE_IF = "%d: duplicate O-word label - already defined in line %d: '%s'"
DUPLICATE_LOOP = "%d: duplicate O-word label: '%s' - defined in line %d"


def check_label(machine, key: str, kind: str, line: int, text: str) -> None:
    """An opener (or a do-loop's closing ``while``: ``kind`` ``do-end``)
    with a reused label is executed on ``line``; or a closing line with a
    reused label that fits no open construct (``kind`` is its keyword)."""
    table = machine._olabels
    seen = table.get(key)
    if kind == "endif" or kind in NO_MATCHING:
        # a closing line: it needs the label recorded by a fitting opener
        if seen is None:
            machine.fail(line, UNDEFINED_LABEL % (line, text))
        if seen[0] in FITTING[kind]:
            return
        if kind == "endif":
            machine.fail(line, NO_MATCHING_ENDIF % ((line, key) + seen + (text,)))
        machine.fail(line, NO_MATCHING[kind] % ((line, text) + seen))
    if seen is None:
        if kind != "do-end":
            table[key] = (kind, line)
        return
    seen_kind, seen_line = seen
    if seen_line == line or kind == "do" or (kind == "while" and seen_kind == "do"):
        return
    if kind == "do-end":
        if seen_kind != "do":
            machine.fail(line, DUPLICATE_LOOP % (line, text, seen_line))
        return
    if kind == "if":
        machine.fail(line, DUPLICATE_IF % (line, seen_line, text))
    machine.fail(line, DUPLICATE_LOOP % (line, text, seen_line))


NOT_IN_SUB = "%d: not in a subroutine definition: '%s'"
NOT_IN_SUB_DEFINITION = "Not in subroutine definition"


def top_level_return(machine, line: int, keyword: str, text: str, value=None) -> None:
    """``return``/``endsub`` in the main program. rs274 fails unless it
    still knows a subroutine name, which it does from the first return of
    a call to the main program until it next reads a definition; then
    ``return`` only sets ``#<_value>`` and ``endsub`` fails for not
    defining one."""
    if fanuc_subs.in_fanuc_call(machine):
        machine.fail(line, fanuc_subs.FANUC_END_M99)
    machine.value = 0.0 if value is None else value
    machine.value_returned = 0.0 if value is None else 1.0
    if not machine.returned_to_main:
        machine.fail(line, NOT_IN_SUB % (line, text))
    if keyword == "endsub":
        machine.fail(line, NOT_IN_SUB_DEFINITION)
