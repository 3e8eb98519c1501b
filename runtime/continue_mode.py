"""rs274's ``-n`` option: what happens after an error.

``-n 2`` (the default) stops at the first error. ``-n 0`` reports the error
and goes on with the next line; ``-n 1`` reports it and enters rs274's MDI
mode (lines typed on stdin), then asks ``continue program? y/n =>`` and goes
on only after a ``y``.

ngc2py continues after errors raised while a line is executed or read
(everything ``Machine.block``, ``Machine.fail`` and ``Machine.m98`` raise:
the block checks, the execution errors, the read-time errors of a line).
It does not continue after an error in evaluating an expression or a
parameter in generated code, nor in an O-word line: control has left the
compiled line by then, so ngc2py stops there as with ``-n 2`` (rs274 would
carry on with its next line). An error inside a subroutine drops every call
level, as rs274 does, and the program goes on after the outermost call line
(rs274 also forgets the subroutines it has read; ngc2py does not). The
moves and calls held back by cutter compensation are dropped, as rs274
clears its queue. Where rs274 repeats an error forever (a file
that ends without ``%`` or M2, under ``-n 0``), ngc2py reports it once and
stops. ngc2py has no MDI: lines given in MDI mode are refused, one message
each, and ``quit`` or the end of stdin leaves MDI mode.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Callable, TextIO

from runtime.errors import GCodeError, g_code_frames_of_stack
from runtime.params import unset_variable

STOP, CONTINUE, MDI = 2, 0, 1


def enable(
    machine,
    mode: int,
    report: Callable[[GCodeError], None],
    stdin: TextIO,
    stderr: TextIO,
) -> None:
    """Make ``machine`` go on after line errors as rs274's ``-n mode`` does."""
    if mode not in (CONTINUE, MDI):
        return

    def after_error(error: GCodeError) -> None:
        report(error)
        if mode == MDI and not _mdi(stdin, stderr):
            raise _Stop(error)

    for name in ("block", "move", "fail", "m98", "call", "call_named"):
        wrapped = _continuing(machine, getattr(machine, name), after_error)
        setattr(machine, name, wrapped)


class _Reported(GCodeError):
    """An error already reported, on its way out."""

    def __init__(self, error: GCodeError):
        super().__init__(error.message, error.location)
        self.reported = True


class _Stop(_Reported):
    """The user did not want to go on after MDI: rs274 exits with status 1."""


class _Unwound(_Reported):
    """An error inside a subroutine: rs274 drops every call level and goes
    on after the outermost call line."""


def _continuing(machine, method: Callable, after_error: Callable) -> Callable:
    def call(*args, **kwargs):
        try:
            return method(*args, **kwargs)
        except _Stop:
            raise
        except _Unwound:
            if machine.call_level > 0:
                raise
        except (GCodeError, UnboundLocalError) as caught:
            # a named local held in a Python variable read unset: the same
            # error as the store's (runtime.params.unset_variable)
            error = unset_variable(caught) if type(caught) is UnboundLocalError else caught
            if not isinstance(error, GCodeError):
                raise
            error.ngc_outer_frames = g_code_frames_of_stack()
            after_error(error)
            machine._comp_forget_queue()
            # rs274 forgets the O-word labels it has met (unwind_call); a
            # file run line by line looks them up again (runtime.oflow)
            machine._oflow_labels.clear()
            if machine.call_level > 0:
                raise _Unwound(error) from None
        return None

    call.__name__ = method.__name__
    return call


def _mdi(stdin: TextIO, stderr: TextIO) -> bool:
    """rs274's MDI prompt loop, without MDI; True to continue the program."""
    stderr.write("starting MDI\n")
    stderr.flush()
    while True:
        line = _read_line(stdin)
        if line is None or line.rstrip("\n") == "quit":
            break
        if line.strip():
            stderr.write("ngc2py: no MDI; line ignored: %s\n" % line.rstrip("\n"))
    stderr.write("continue program? y/n =>")
    stderr.flush()
    answer = _read_line(stdin)
    return answer is not None and answer.startswith("y")


def _read_line(stdin: TextIO):
    """A line from stdin, or None at its end (or when there is none to read)."""
    try:
        line = stdin.readline() if stdin is not None else ""
    except (OSError, ValueError):  # closed, or captured (pytest)
        return None
    return line or None


__all__ = ["enable", "STOP", "CONTINUE", "MDI"]
