"""Run a G-code program against any canon: what the workflows built on the
canonical calls (``stats``, ``plot``) share with ``run``.

The program is compiled (cached) as for ``ngc2py run``; it runs with rs274's
options; on a G-code error rs274's report goes to stderr. What rs274 prints
while reading its files (tool table and ini complaints) goes to stderr
too, since stdout belongs to the workflow's own output.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager

from runtime.canon import Canon
from runtime.errors import GCodeError, describe

TYPE_CHECKING = False  # typing and tempfile cost milliseconds at every start
if TYPE_CHECKING:
    import argparse
    from typing import Callable, Iterator, Optional, TextIO

#: Exit statuses every workflow command documents.
EXIT_OK = 0
EXIT_ERROR = 1


def add_rs274_options(parser: argparse.ArgumentParser) -> None:
    """The options a program runs with, as ``ngc2py run`` takes them."""
    from ngc2py.flags import add_block_delete  # (argparse: not on a run's way)

    parser.add_argument("-t", dest="tool_table", metavar="TBL", help="tool table file")
    parser.add_argument(
        "-v", dest="var_file", metavar="VAR", help="parameter (.var) file"
    )
    parser.add_argument("-i", dest="ini", metavar="INI", help="ini file")
    add_block_delete(parser, "turn block delete on")
    parser.add_argument(
        "-n",
        dest="continue_mode",
        metavar="0|1|2",
        help="after an error: 0 report it on stderr and go on with the next line, "
        "1 rs274's MDI prompt, 2 stop (default), as rs274's -n",
    )


@contextmanager
def program_path(program: str) -> Iterator[str]:
    """The program's file name; ``-`` is standard input, kept in a
    temporary file for the compiler (which reads files)."""
    if program != "-":
        yield program
        return
    import tempfile

    data = sys.stdin.buffer.read()
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "stdin.ngc")
        with open(path, "wb") as handle:
            handle.write(data)
        yield path


def run_program(
    args: argparse.Namespace,
    canon: Canon,
    stderr: Optional[TextIO] = None,
    on_machine: Optional[Callable] = None,
) -> int:
    """Run ``args.program`` against ``canon``; the exit status (0, or 1 after
    an error was reported on ``stderr``). ``on_machine`` is given the
    machine before the program runs (a canon that reads its line numbers)."""
    from ngc2py.loading import load_program, unopened
    from ngc2py.compiler import CompileError, OpenError
    from runtime.machine import Machine
    from runtime import continue_mode
    from runtime.main import _atoi, report, start

    stderr = stderr or sys.stderr
    with program_path(args.program) as path:
        try:
            try:
                module = load_program(path, args.ini, args.block_delete)
                main, source_map = module.main, module.__ngc__
            except OpenError as error:
                main, source_map = None, unopened(path, error)
            machine = Machine(
                canon,
                tool_table=args.tool_table,
                var_file=args.var_file,
                ini=args.ini,
                block_delete=args.block_delete,
                source=source_map,
            )
            machine.messages = stderr
            if on_machine is not None:
                on_machine(machine)
            stderr.write(machine.tool_table_report)
            stderr.write(machine.settings.stderr_report)
            mode = getattr(args, "continue_mode", None)
            if mode is not None:
                continue_mode.enable(
                    machine, _atoi(mode), lambda e: report(e, stderr), sys.stdin, stderr
                )
            start(machine, main)
        except GCodeError as error:
            if not getattr(error, "reported", False):  # -n 1 has reported it
                report(error, stderr)
            return EXIT_ERROR
        except CompileError as error:
            stderr.write("%s\n" % error)
            return EXIT_ERROR
        except OSError as error:
            stderr.write(
                "ngc2py: %s: %s\n" % (error.filename or path, error.strerror or error)
            )
            return EXIT_ERROR
        except Exception as error:  # noqa: BLE001 - never a bare traceback
            stderr.write(describe(error) + "\n")
            return EXIT_ERROR
    return EXIT_OK


__all__ = ["EXIT_ERROR", "EXIT_OK", "add_rs274_options", "program_path", "run_program"]
