"""The command line of a generated module: ``python prog.py [-t TBL] ...``.

It behaves like ``rs274 -g PROG``: the canonical-call trace on stdout,
``executing`` on stderr, and on an error rs274's message and the offending
line's text on stderr and exit status 1. After those two lines (which are
rs274's) it adds what rs274 does not say: where, as ``file:line``, and the
O-call stack that led there.
"""

from __future__ import annotations

import os
import sys

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Callable, List, Optional, Sequence, TextIO

from runtime import continue_mode
from runtime.errors import GCodeError, SourceMap, describe, format_traceback, locate

USAGE = (
    "usage: %s [-t tool.tbl] [-v file.var] [-i file.ini] [-b] [-n 0|1|2]"
    " [--max-steps N] [output file]"
)


class UsageError(Exception):
    """The command line is not one rs274 (or ``--max-steps``) accepts."""


def parse_options(argv: Sequence[str]) -> dict:
    """rs274's options (getopt style, so ``-tfile.tbl`` works too), and
    ngc2py's ``--max-steps N`` (see runtime.budget; 0: no limit).

    ``-n`` is returned as ``continue_mode`` (see runtime.continue_mode); like
    rs274's atoi, a value that is not a number counts as 0.
    """
    options = {"block_delete": False}
    if not argv:
        return options  # the usual run: getopt's import is not paid for
    output = plain_output(argv)
    if output is not None:
        options["output"] = output
        return options
    import getopt

    try:
        opts, rest = getopt.getopt(list(argv), "t:v:i:bn:", ["max-steps="])
    except getopt.GetoptError as error:
        raise UsageError(str(error)) from None
    if len(rest) > 1:
        raise UsageError("unexpected argument %r" % rest[1])
    if rest:  # rs274's output file: the trace goes there, not to stdout
        options["output"] = rest[0]
    names = {"-t": "tool_table", "-v": "var_file", "-i": "ini"}
    for flag, value in opts:
        if flag == "-b":
            options["block_delete"] = not options["block_delete"]  # rs274 toggles
        elif flag == "-n":
            options["continue_mode"] = _atoi(value)
        elif flag == "--max-steps":
            try:
                options["max_steps"] = int(value)
            except ValueError:
                raise UsageError("--max-steps needs a whole number") from None
        else:
            options[names[flag]] = value
    return options


def plain_output(argv: Sequence[str]) -> Optional[str]:
    """rs274's output file given alone (``OUT``, or ``-- OUT`` as the ngc2py
    command passes it), as getopt reads it; None for anything else. Read
    without getopt, whose import (gettext, re, enum) costs a run that
    writes its trace to a file about 8 ms."""
    if len(argv) == 1 and not argv[0].startswith("-"):
        return argv[0]
    if len(argv) == 2 and argv[0] == "--":
        return argv[1]
    return None


def _atoi(text: str) -> int:
    """C's atoi: leading blanks, a sign and digits; anything else is 0."""
    import re

    match = re.match(r"\s*([+-]?\d+)", text)
    return int(match.group(1)) if match else 0


def write_raw(stream: TextIO, text: str) -> None:
    """Write ``text`` as the bytes it was read from: the front end decodes
    G-code with surrogateescape, and rs274 echoes a line's bytes unchanged.
    A stream without a byte buffer (a StringIO) gets the text itself."""
    buffer = getattr(stream, "buffer", None)
    if buffer is None:
        stream.write(text)
        return
    stream.flush()
    buffer.write(text.encode("utf-8", "surrogateescape"))
    buffer.flush()


#: rs274 keeps an error's text in a buffer of LinuxCNC's LINELEN (255)
#: bytes and prints at most this many of them.
MESSAGE_BYTES = 254


def rs274_message(message: str) -> str:
    """``message`` as rs274 prints it: its first MESSAGE_BYTES bytes (a long
    name, path or number in it is cut off there, mid-character if it falls
    so, as C cuts it)."""
    data = message.encode("utf-8", "surrogateescape")
    if len(data) <= MESSAGE_BYTES:
        return message
    return data[:MESSAGE_BYTES].decode("utf-8", "surrogateescape")


def report(error: GCodeError, stderr: TextIO) -> None:
    """rs274's two lines (message, line text: parity checks read the first),
    then a caret under the word the error is about (when it is known),
    ``file:line[:column]`` and the O-calls that led there."""
    from runtime.caret import column

    frames = locate(error)
    write_raw(stderr, rs274_message(error.message) + "\n")
    if not frames:
        return
    here = frames[-1]
    write_raw(stderr, here.text + "\n")
    col = column(error, here.text) if here.line else None
    if col is not None:
        # tabs kept so the caret lines up under the word on any terminal
        pad = "".join(c if c == "\t" else " " for c in here.text[: col - 1])
        write_raw(stderr, pad + "^\n")
        stderr.write("  at %s:%d\n" % (here, col))
    else:
        stderr.write("  at %s\n" % here)
    for caller in reversed(frames[:-1]):
        stderr.write("  called from %s: %s\n" % (caller, caller.text))


def start(machine, main: Callable) -> None:
    """Run ``main`` on ``machine``, unless rs274 would already fail opening
    the program (its source map says so): then only the start-up calls are
    made before the error."""
    source = machine.source
    if source is not None and source.block_delete is not None:
        wrong = source.other_block_delete(machine.block_delete)
        if wrong is not None:
            raise ValueError(wrong)
    opening = source.opening_error() if source else None
    if opening is None:
        machine.run(main)
    else:
        machine.fail_open(*opening)


def run_cli(
    main: Callable,
    source_map: SourceMap,
    argv: Optional[List[str]] = None,
    stdout: Optional[TextIO] = None,
    stderr: Optional[TextIO] = None,
    wrap_canon: Optional[Callable] = None,
) -> int:
    """Run ``main`` like ``rs274 -g``; return the exit status (0 or 1).

    ``wrap_canon``, if given, takes the trace canon and returns the canon
    to use (the ngc2py command wraps it to draw a progress bar)."""
    from runtime.canon import TraceCanon
    from runtime.machine import Machine

    stdout = stdout or sys.stdout
    stderr = stderr or sys.stderr
    args = sys.argv[1:] if argv is None else argv
    try:
        options = parse_options(args)
    except UsageError as error:
        stderr.write("%s\n%s\n" % (error, USAGE % "program"))
        return 1
    wrong = source_map.other_block_delete(options["block_delete"])
    if wrong is not None:
        stderr.write("%s\n" % wrong)
        return 1
    stderr.write("executing\n")
    stderr.flush()
    mode = options.pop("continue_mode", continue_mode.STOP)
    output = options.pop("output", None)
    trace = stdout
    if output is not None:
        trace = _open_output(output)
        if trace is None:
            # rs274 has read its tool table (its complaints on stdout) and
            # not yet its ini or parameter file
            from runtime.tooltable import tool_table_for

            stdout.write(tool_table_for(options.get("tool_table")).load_report)
            stderr.write("could not open output file %s\n" % output)
            return 1
    # (PRINT text stays on stdout when the trace goes to a file)
    canon = TraceCanon(trace, text_out=None if output is None else stdout)
    try:
        machine = Machine(
            canon if wrap_canon is None else wrap_canon(canon),
            source=source_map,
            **options,
        )
        machine.messages = stderr
        # What rs274 says while reading its files: the tool table's
        # complaints on stdout (before the trace), the ini file's on stderr.
        stdout.write(machine.tool_table_report)
        stderr.write(machine.settings.stderr_report)

        def report_and_go_on(error: GCodeError) -> None:
            canon.flush()  # the trace so far comes before the message
            report(error, stderr)

        continue_mode.enable(machine, mode, report_and_go_on, sys.stdin, stderr)
        start(machine, main)
    except GCodeError as error:
        canon.flush()
        if not getattr(error, "reported", False):
            report(error, stderr)
        return 1
    except (KeyboardInterrupt, BrokenPipeError):
        return 1
    except Exception as error:  # noqa: BLE001 - never a bare traceback
        canon.flush()
        stderr.write(describe(error) + "\n")
        if os.environ.get("NGC2PY_TRACEBACK"):
            stderr.write(format_traceback(error))
        return 1
    finally:
        try:
            canon.flush()
        except BrokenPipeError:  # the reader went away (`| head`)
            return 1
        finally:
            if output is not None and not trace.commit(stderr):
                return 1
    return 0


class _Output:
    """rs274's output file, written atomically: the trace goes to a
    temporary file beside it, which takes its name when the run ends
    (errors or not: rs274's file then holds the trace up to the error)."""

    def __init__(self, path: str) -> None:
        from runtime.atomic import special_file, temporary_beside

        self.path = path
        self.temporary = None
        if special_file(path):  # a device or a pipe: written to, not replaced
            handle = path
        else:
            handle, self.temporary = temporary_beside(path)
        # the G-code's bytes as they were read (surrogateescape), lines as written
        self.file = open(
            handle, "w", encoding="utf-8", errors="surrogateescape", newline=""
        )
        self.write = self.file.write
        self.flush = self.file.flush

    def commit(self, stderr: TextIO) -> bool:
        """The trace takes the file's name; False (said on ``stderr``, the
        temporary file removed) where it cannot, say its folder went away."""
        from runtime.atomic import file_mode

        try:
            self.file.close()
            if self.temporary is not None:
                os.chmod(self.temporary, file_mode(self.path))  # as fopen makes it
                os.replace(self.temporary, self.path)
        except OSError as error:
            stderr.write("could not write output file %s: %s\n" % (self.path, error))
            try:
                if self.temporary is not None:
                    os.unlink(self.temporary)
            except OSError:
                pass
            return False
        return True


def _open_output(path: str) -> Optional[_Output]:
    """The output file, or None where rs274's fopen would fail (no such
    folder, a folder of that name, no permission)."""
    if os.path.isdir(path):
        return None
    try:
        return _Output(path)
    except OSError:
        return None


__all__ = ["run_cli", "parse_options", "report", "start"]
