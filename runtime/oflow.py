"""A file's O-words run line by line, as rs274 runs them.

rs274 never pairs O-words. It reads a file one line at a time and keeps a
little global state: the label it is skipping to (if any), the table of
labels it has met (which line opened each, and a repeat count), and three
flags (an arm of an if has run, a break or a continue is under way). An
O-word line either changes that state or, for the end of a loop, seeks
back to the line its label was recorded on. Most programs behave exactly
like the nested Python the compiler writes for them; a program whose
O-words do not nest (a skip landing inside a construct it never opened, a
label reused by constructs of different kinds) is compiled instead into a
loop over its lines that asks :class:`Flow` which line comes next
(``ngc2py/lineflow.py`` decides which programs, and writes them).

The rules are those of rs274's ``read_o`` (what a line's O-word reads, and
when it evaluates a condition or value) and ``convert_control_functions``
(what the O-word then does), LinuxCNC 2.9: interp_read.cc and
interp_o_word.cc. Labels are named as rs274 names them: a subroutine's
name for ``sub``, ``endsub``, ``return`` and ``call``, and for the others
``<sub>#<label>`` (``#<label>`` in the main program).

The table a module hands over (``LINES``) has an entry for every line that
does something:

* a number: the first of a run of ordinary lines, the number the line
  after the run (no skip lands inside one, so they run or pass together);
* ``""`` an ordinary line, ``"/"`` one with a block-delete slash, ``"x"``
  one whose text rs274 cannot read, ``"u"`` one whose O-word it cannot
  read (``"uk"``: an unknown keyword; ``/`` added when block-deleted);
* ``"%"`` the closing ``%`` line, ``"eof"`` (``"eof%"`` in a file that
  opens with ``%``) the end of the file;
* ``(keyword, label, flags)`` an O-word line. Flags: ``v`` the module has
  code for the line's reading (a condition, a value, a call, a definition,
  a failure), ``t`` something follows the O-word (rs274 fails when it reads
  the line while not skipping), ``/`` block delete, ``x`` a text rs274
  cannot read, ``u`` an O-word it cannot read (``k``: an unknown keyword,
  which reading past a definition does not notice).
"""

from __future__ import annotations

from runtime.blockcheck import round_to_int
from runtime.errors import GCodeError, Location
from runtime.olabels import (
    DUPLICATE_IF,
    DUPLICATE_LOOP,
    FITTING,
    NO_MATCHING,
    NO_MATCHING_ENDIF,
    UNDEFINED_LABEL,
)

NESTED_SUB = "Nested subroutine definition"
AFTER_OWORD = "Unexpected character after O-word"
FINISHED_SKIPPING = "Failed to find sub 'O%s' before EOF"
FANUC_NEEDS_M98 = "Fanuc 'O....' subroutine must be called with 'M98'"

#: O-words whose label is a subroutine's name, not a local label.
_GLOBAL = frozenset(("sub", "endsub", "return", "call", "fanuc_sub", "m98"))


class _LineFailed(Exception):
    """A line failed and rs274's -n 0 goes on with the next one
    (runtime.continue_mode returned from Machine.fail): the rest of what
    the line would have done is dropped."""


class Flow:
    """One call frame running a file line by line (the main program, or a
    subroutine called by name, ``sub``). The state rs274 keeps globally
    lives on the machine (labels, flags); what a frame alone can change
    (skipping, reading a definition) lives here, since a call ends any
    skip and a definition is read only in the main program."""

    __slots__ = (
        "m",
        "lines",
        "at",
        "sub",
        "skipping",
        "defining",
        "pending",
        "read_skipping",
        "value",
        "returned",
    )

    def __init__(self, machine, lines: dict, at: int, sub=None):
        self.m = machine
        self.lines = lines
        self.at = at  # the next line to read; 0 once the frame returns
        self.sub = sub  # the subroutine this frame runs (None: main)
        self.skipping = None  # the label rs274 skips to
        self.defining = None  # the subroutine whose definition is read
        self.pending = None  # the O-word line the module is reading
        self.read_skipping = False
        self.value = None  # what a return or endsub gave
        self.returned = False

    # -- where the module goes next --------------------------------------

    def next(self) -> int:
        """The next line the module runs code for (0: the frame returns).

        Lines rs274 passes over while skipping, and O-words that read
        nothing, are dealt with here."""
        m = self.m
        lines = self.lines
        while True:
            at = self.at
            if self.returned:
                return 0
            self.at = at + 1
            entry = lines.get(at)
            if entry is None:
                continue
            if entry.__class__ is int:
                # ordinary lines up to line ``entry``, run (or passed) together
                self.at = entry
                if self.skipping is None:
                    return at
                continue
            if entry.__class__ is str:
                if not entry:
                    if self.skipping is None:
                        return at
                    continue
                if entry == "x":
                    return at  # its text fails, skipping or not
                if entry[0] == "u":
                    if "/" in entry and m.block_delete:
                        continue
                    if "k" in entry and self.defining is not None:
                        continue  # reading a definition, rs274 reads no keyword
                    return at  # an O-word it cannot read fails, skipping or not
                if entry == "/":
                    if self.skipping is not None or m.block_delete:
                        continue
                    return at
                try:
                    self._end(at, entry)
                except _LineFailed:  # (-n 0: nothing follows the end)
                    pass
                return 0
            keyword, label, flags = entry
            try:
                at = self._o_line(at, keyword, label, flags)
            except _LineFailed:
                continue
            if at:
                return at

    def _o_line(self, at: int, keyword: str, label: str, flags: str) -> int:
        """Read the O-word line ``at`` (read_o, then convert_control_functions
        where nothing is left to evaluate): the line when the module has
        code for its reading, else 0 (done here, or passed over)."""
        m = self.m
        if flags:
            if "x" in flags:
                return at
            if "/" in flags and m.block_delete:
                return 0  # rs274 reads a deleted line as a blank one
            if "u" in flags:
                if "k" in flags and self.defining is not None:
                    return 0
                return at
        if keyword in _GLOBAL:
            key = label
        else:
            key = "%s#%s" % (self._scope(), label)
        skipping = self.skipping
        self.read_skipping = skipping is not None
        self.pending = (at, keyword, key, flags)
        if keyword == "fanuc_sub":
            # "O100": only an M98 runs it (none in this file can)
            if self.defining is not None:
                self._fail(at, NESTED_SUB)
            if skipping is None and self.sub is not None:
                self._fail(at, FANUC_NEEDS_M98)
            return 0
        if keyword == "sub":
            if self.defining is not None:
                self._fail(at, NESTED_SUB)
            self._trailing(at, flags)
            if skipping is not None and skipping != key or self.sub is not None:
                return 0  # (run in a call, the sub line does nothing)
            return at  # the module defines it: define()
        if keyword in ("return", "endsub"):
            if skipping is not None and skipping != key:
                return 0
            if "v" in flags:
                return at
            self.o(None)
            return 0
        if keyword == "m98":
            return at  # read in full wherever it is: runs() says if it calls
        if self.defining is not None:
            return 0  # rs274 reads no other O-word of a definition
        if keyword == "call":
            return at if skipping is None else 0  # the module calls
        if skipping is not None and skipping != key:
            return 0
        if "v" in flags:
            return at  # the module evaluates the condition: o(value)
        self.o(None)
        return 0

    def _scope(self) -> str:
        if self.sub is not None:
            return self.sub
        return self.defining or ""

    def _trailing(self, at: int, flags: str) -> None:
        if "t" in flags and not self.read_skipping:
            self._fail(at, AFTER_OWORD)

    def _end(self, at: int, entry: str) -> None:
        """The closing ``%`` (rs274 stops reading, FINISH first), or the
        end of the file."""
        if entry == "%":
            if self.skipping is not None:
                self._fail(at, FINISHED_SKIPPING % self.skipping, finish=True)
            self.m.end_of_file(True, True)
        self.m.line = at - 1
        try:
            self.m.end_of_file(entry == "eof%", False)
        except GCodeError as error:
            error.ngc_row_line = at - 1
            raise

    def _fail(self, at: int, message: str, finish: bool = False) -> None:
        m = self.m
        try:
            m.fail(at, message, finish)
        except GCodeError as error:
            self._located(error, at)
            raise
        # -n 0 goes on (runtime.continue_mode): rs274 has stopped skipping
        # and reading a definition (unwind_call), and the line is done
        self.skipping = self.defining = None
        raise _LineFailed()

    def _located(self, error: GCodeError, at: int) -> None:
        """An error of line ``at`` raised here, not by the line's code: the
        module's ``f.next()`` maps to the line the error names
        (``ngc_row_line``, as a data row's error), and the report shows it."""
        m = self.m
        text = m.source.text(0, at) if m.source is not None else ""
        error.location = Location(m.source.files[0] if m.source else "", at, text)
        if getattr(error, "ngc_row_line", None) is None:
            error.ngc_row_line = at

    def _text(self, at: int) -> str:
        return self.m.source.text(0, at) if self.m.source is not None else ""

    # -- what the module hands back ----------------------------------------

    def runs(self) -> bool:
        """Does the M98 line just read call (rs274 is not skipping)?"""
        return self.skipping is None

    def define(self, fn) -> None:
        """The sub line of a definition rs274 reads in the main program."""
        at, _, key, _ = self.pending
        self.m.define(key, fn)  # (under -n 0, a failed define goes on)
        self.skipping = key
        self.defining = key

    def o(self, value) -> None:
        """The O-word line ``next`` handed over has been read: ``value`` is
        its condition, count or returned value (None: it has none)."""
        try:
            self._convert(value)
        except _LineFailed:
            pass

    def _convert(self, value) -> None:
        at, keyword, key, flags = self.pending
        self._trailing(at, flags)
        m = self.m
        if keyword in ("return", "endsub"):
            if value is None:
                m.value = m.value_returned = 0.0
            else:
                m.value, m.value_returned = value, 1.0
            self._leave(at, keyword, key, value)
            return
        handler = getattr(self, "_" + keyword)
        handler(at, key, value)

    # -- rs274's convert_control_functions, per keyword ----------------------

    def _leave(self, at: int, keyword: str, key: str, value) -> None:
        if self.sub is None and self.defining is None:
            # not in a subroutine: see runtime.olabels.top_level_return
            try:
                self.m.top_level_return(at, keyword, self._text(at), value)
            except GCodeError as error:
                self._located(error, at)
                raise
            return
        if self.skipping is not None and keyword == "endsub":
            self.skipping = None
        if self.sub is not None:
            self.value = value
            self.returned = True
        elif keyword == "endsub":
            self.defining = None

    def _record(self, key: str, kind: str, at: int) -> list:
        labels = self.m._oflow_labels
        seen = labels.get(key)
        if seen is None:
            seen = labels[key] = [kind, at, -1]
        return seen

    def _closing_line(self, at: int, keyword: str) -> list:
        """A closing line (else, break, endwhile, ...) looks its label up."""
        seen = self.m._oflow_labels.get(self._key_of(at))
        text = self._text(at)
        if seen is None:
            self._fail(at, UNDEFINED_LABEL % (at, text))
        if seen[0] not in FITTING[keyword]:
            if keyword == "endif":
                message = NO_MATCHING_ENDIF % (
                    at,
                    self._key_of(at),
                    seen[0],
                    seen[1],
                    text,
                )
            else:
                message = NO_MATCHING[keyword] % (at, text, seen[0], seen[1])
            self._fail(at, message)
        return seen

    def _key_of(self, at: int) -> str:
        return self.pending[2]

    def _back(self, seen: list) -> None:
        """rs274 seeks back to the line the label was recorded on."""
        self.m.step()
        self.at = seen[1]

    def _do(self, at: int, key: str, value) -> None:
        self.skipping = None
        self._record(key, "do", at)

    def _repeat(self, at: int, key: str, value) -> None:
        seen = self.m._oflow_labels.get(key)
        if seen is not None and seen[1] != at:
            self._fail(at, DUPLICATE_LOOP % (at, self._text(at), seen[1]))
        seen = self._record(key, "repeat", at)
        self.skipping = None
        if seen[2] == -1:
            seen[2] = round_to_int(value)
        if seen[2] > 0:
            seen[2] -= 1
        else:
            self.skipping = key
            seen[2] = -1

    def _while(self, at: int, key: str, value) -> None:
        m = self.m
        seen = m._oflow_labels.get(key)
        if seen is not None and seen[0] != "do" and seen[1] != at:
            self._fail(at, DUPLICATE_LOOP % (at, self._text(at), seen[1]))
        seen = self._record(key, "while", at)
        self.skipping = None
        if seen[0] == "while":
            if value == 0.0:
                self.skipping = key
        elif value != 0.0 and not m.doing_break:
            self._back(seen)  # the end of a do-loop, going round again
        else:
            m.doing_break = False

    def _if(self, at: int, key: str, value) -> None:
        seen = self.m._oflow_labels.get(key)
        if seen is not None and seen[1] != at:
            self._fail(at, DUPLICATE_IF % (at, seen[1], self._text(at)))
        self._record(key, "if", at)
        if value != 0.0:
            self.skipping = None
            self.m.executed_if = True
        else:
            self.skipping = key
            self.m.executed_if = False

    def _elseif(self, at: int, key: str, value) -> None:
        self._closing_line(at, "elseif")
        if self.m.executed_if:
            self.skipping = key
        elif value != 0.0:
            self.skipping = None
            self.m.executed_if = True

    def _else(self, at: int, key: str, value) -> None:
        self._closing_line(at, "else")
        if self.m.executed_if:
            self.skipping = key
        elif self.skipping == key:
            self.skipping = None
            self.m.executed_if = True

    def _endif(self, at: int, key: str, value) -> None:
        self._closing_line(at, "endif")
        self.skipping = None
        self.m.executed_if = True

    def _break(self, at: int, key: str, value) -> None:
        self._closing_line(at, "break")
        self.skipping = key
        self.m.doing_break = True

    def _continue(self, at: int, key: str, value) -> None:
        self._closing_line(at, "continue")
        if self.skipping == key:
            return
        self.skipping = key
        self.m.doing_continue = True

    def _endwhile(self, at: int, key: str, value) -> None:
        self._loop_end(at, key, "endwhile")

    def _endrepeat(self, at: int, key: str, value) -> None:
        self._loop_end(at, key, "endrepeat")

    def _loop_end(self, at: int, key: str, keyword: str) -> None:
        seen = self._closing_line(at, keyword)
        if self.skipping == key:
            self.skipping = None
            if self.m.doing_continue:
                self.m.doing_continue = False
                self._back(seen)
        else:
            self._back(seen)
