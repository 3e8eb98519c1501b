"""The ``ngc2py`` command: ``convert`` a G-code file, or ``run`` it.

Every failure is one clear line on stderr and exit status 1; a Python
traceback never reaches the user.
"""

from __future__ import annotations

import importlib
import os
import sys

from ngc2py import __version__
from ngc2py.compiler import CompileError, OpenError, compile_file
from ngc2py.loading import load_module, load_program, unopened  # noqa: F401
from runtime.budget import DEFAULT_MAX_STEPS

TYPE_CHECKING = False  # `ngc2py run` is timed against rs274: no typing import
if TYPE_CHECKING:
    import argparse
    from typing import List, Optional, Sequence

DESCRIPTION = """\
Compile LinuxCNC G-code (RS274/NGC, LinuxCNC 2.9) into a readable Python
module, or run it. A generated module prints exactly what `rs274 -g PROG.ngc`
prints, and fails where and how rs274 fails."""


QUIET_HELP = "no progress bar (one is drawn only when stderr is a terminal)"

#: Modules that each add a sub-command: ``register(commands)`` adds the
#: parser and ``set_defaults(handler=...)``, the handler returns the exit status.
WORKFLOWS = ("ngc2py.golden", "ngc2py.flatten", "ngc2py.stats", "ngc2py.plot")

EPILOG = """\
exit status: 0 success; 1 the G-code program failed (as rs274 fails:
message on stderr), or ngc2py could not do what was asked (missing file,
bad usage); golden: 1 a program changed, 2 nothing to check. See the
README's "Exit status" section.

environment: NGC2PY_CACHE the compile cache's folder (default ngc2py in
$XDG_CACHE_HOME or ~/.cache; removing it is always safe);
NGC2PY_CACHE_SIZE its limit (default 1G; e.g. 500M; 0 for none): the
entries used least recently go first."""


def build_parser(workflows: Sequence[str] = WORKFLOWS) -> argparse.ArgumentParser:
    import argparse  # here: a program's plain run is parsed without it (quick_args)

    from ngc2py.flags import add_block_delete  # (argparse's too)

    parser = argparse.ArgumentParser(
        prog="ngc2py",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version="ngc2py " + __version__)
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    convert = commands.add_parser(
        "convert",
        help="write the Python module for a G-code file",
        description="Compile PROG.ngc into a Python module. Run the module "
        "with `python OUT.py [-t TBL] [-v VAR] [-i INI] [-b] [-n 0|1|2] "
        "[--max-steps N]`.",
    )
    convert.add_argument(
        "program", metavar="PROG.ngc", help="the G-code file ('-': stdin)"
    )
    convert.add_argument(
        "-o",
        "--output",
        metavar="OUT.py",
        help="where to write the module (default: PROG.py next to PROG.ngc; "
        "'-' for standard output). Written atomically.",
    )
    convert.add_argument(
        "-i",
        dest="ini",
        metavar="INI",
        help="ini file whose SUBROUTINE_PATH is searched",
    )
    add_block_delete(
        convert,
        "compile for block delete on: needed only where lines that "
        "start with '/' carry O-words in a file whose O-words the module "
        "pairs when it is written (it says so when run with the other setting)",
    )
    convert.add_argument("-q", "--quiet", action="store_true", help=QUIET_HELP)

    run = commands.add_parser(
        "run",
        help="compile (cached) and run a G-code file like `rs274 -g`",
        description="Compile PROG.ngc (cached on disk, see NGC2PY_CACHE) and run "
        "it: the canonical-call trace on stdout, errors on stderr, exit status "
        "1 on error -- the same as `rs274 -g`.",
    )
    run.add_argument("program", metavar="PROG.ngc", help="the G-code file ('-': stdin)")
    run.add_argument(
        "output",
        metavar="OUT",
        nargs="?",
        help="write the trace to this file instead of stdout, as rs274's "
        "output file (written atomically; PRINT text stays on stdout)",
    )
    run.add_argument("-t", dest="tool_table", metavar="TBL", help="tool table file")
    run.add_argument("-v", dest="var_file", metavar="VAR", help="parameter (.var) file")
    run.add_argument("-i", dest="ini", metavar="INI", help="ini file")
    add_block_delete(run, "turn block delete on")
    run.add_argument("-q", "--quiet", action="store_true", help=QUIET_HELP)
    for workflow in workflows:
        importlib.import_module(workflow).register(commands)  # its sub-command
    run.add_argument(
        "-n",
        dest="continue_mode",
        metavar="0|1|2",
        help="after an error: 0 continue, 1 MDI (not supported: asks to go "
        "on), 2 stop (default), as rs274's -n",
    )
    run.add_argument(
        "--max-steps",
        dest="max_steps",
        metavar="N",
        help="stop with an error after N loop iterations and calls "
        "(default %d; 0: no limit)" % DEFAULT_MAX_STEPS,
    )
    return parser


def default_output(program: str) -> str:
    return os.path.splitext(program)[0] + ".py"


def same_file(a: str, b: str) -> bool:
    """Are paths ``a`` and ``b`` the same existing file?"""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def convert(args: argparse.Namespace) -> int:
    from ngc2py.cache import write_atomic

    from ngc2py.progress import spinner
    from ngc2py.stdin import STDIN, compile_stdin

    if args.program == STDIN:
        output = args.output or "-"
        text = compile_stdin(args.ini, args.block_delete)
    else:
        output = args.output or default_output(args.program)
        if output != "-" and same_file(output, args.program):
            raise CompileError(
                "%s: the output would overwrite the G-code file" % output
            )
        with spinner("converting " + args.program, args.quiet):
            text = compile_file(args.program, args.ini, args.block_delete)
    if output == "-":
        sys.stdout.write(text)
    else:
        write_atomic(output, text)
    return 0


def run(args: argparse.Namespace) -> int:
    from ngc2py.progress import spinner, watch_run
    from runtime.main import run_cli

    if args.output is not None:
        # rs274 would truncate it; a user's file is never lost to a trace
        for kept in (args.program, args.tool_table, args.var_file, args.ini):
            if kept is not None and same_file(args.output, kept):
                raise CompileError("%s: the trace would overwrite it" % args.output)
    try:
        with spinner("compiling " + args.program, args.quiet):
            module = load_program(args.program, args.ini, args.block_delete)
        main, source_map = module.main, module.__ngc__
    except OpenError as error:
        main, source_map = None, unopened(args.program, error)  # main never runs
    argv: List[str] = []
    for flag, value in (
        ("-t", args.tool_table),
        ("-v", args.var_file),
        ("-i", args.ini),
    ):
        if value is not None:
            argv += [flag, value]
    if args.block_delete:
        argv.append("-b")
    if args.continue_mode is not None:
        argv += ["-n", args.continue_mode]
    if args.max_steps is not None:
        argv.append("--max-steps=%s" % args.max_steps)
    if args.output is not None:
        argv += ["--", args.output]  # (a name starting with '-' is a name)
    bars = []

    def watched(canon):
        bars.append(watch_run(canon, args.quiet))
        return canon

    try:
        return run_cli(main, source_map, argv, wrap_canon=watched)
    finally:
        for bar in bars:
            bar.close()


#: The options of rs274 that every command running a program takes, each
#: with the attribute argparse gives its value (ngc2py.simulate).
_RS274_VALUES = {
    "-t": "tool_table",
    "-v": "var_file",
    "-i": "ini",
    "-n": "continue_mode",
}
_QUIET = {"-q": "quiet", "--quiet": "quiet"}

#: The commands :func:`quick_args` reads, each with: its options that take
#: a value, its flags (attribute names), whether rs274's output file may
#: follow the program, and the module of its ``DEFAULTS`` (every other
#: attribute argparse gives it, the handler among them; None: ``run``'s).
_QUICK = {
    "run": (
        dict(_RS274_VALUES, **{"--max-steps": "max_steps"}),
        dict(_QUIET, **{"-b": "block_delete"}),
        True,
        None,
    ),
    "stats": (_RS274_VALUES, {"-b": "block_delete", "--json": "json"}, False, "stats"),
    "flatten": (
        dict(_RS274_VALUES, **{"-o": "output", "--output": "output"}),
        dict(_QUIET, **{"-b": "block_delete"}),
        False,
        "flatten",
    ),
}


def quick_args(argv: List[str]):
    """``run``, ``stats`` or ``flatten`` with a program parsed without
    argparse, whose import (with gettext, re, enum and shutil's archive
    modules) and parser cost 8-15 ms of every run of a small program
    (rs274 starts in 10): the plain forms only -- each option spelled out,
    its value in the next argument, one program name and, for ``run``,
    perhaps rs274's output file after it. Anything else (help,
    abbreviations, ``-``, ``--``, joined flags, an option value starting
    with ``-``, a name too many) gives None, and argparse decides
    (:func:`parse_arguments`). tests/test_cli.py holds the answers to
    argparse's."""
    if len(argv) < 2 or argv[0] not in _QUICK:
        return None
    options, flags, output_allowed, module = _QUICK[argv[0]]
    values = dict.fromkeys(options.values())
    values.update(dict.fromkeys(flags.values(), False))
    values.update(command=argv[0], program=None)
    if output_allowed:
        values["output"] = None
    if module is not None:
        values.update(importlib.import_module("ngc2py." + module).DEFAULTS)
    output = None
    at = 1
    while at < len(argv):
        arg = argv[at]
        if arg in options:
            if at + 1 == len(argv) or argv[at + 1].startswith("-"):
                return None
            values[options[arg]] = argv[at + 1]
            at += 2
        elif arg in flags:
            # -b flips block delete each time, as rs274 and argparse's -b do
            name = flags[arg]
            values[name] = not values[name] if arg == "-b" else True
            at += 1
        elif arg.startswith("-") or output is not None:
            return None
        elif values["program"] is None:
            values["program"] = arg
            at += 1
        elif output_allowed:
            output = values["output"] = arg  # rs274's output file
            at += 1
        else:
            return None
    if values["program"] is None:
        return None
    from types import SimpleNamespace

    return SimpleNamespace(**values)


def _parser_for(argv: List[str]) -> argparse.ArgumentParser:
    """The parser, with only the sub-command ``argv`` names when it names
    one: importing every workflow module would add to every ``ngc2py run``
    or ``ngc2py stats`` (a few tens of milliseconds)."""
    command = argv[0] if argv else ""
    if command in ("run", "convert"):
        helps = bool({"-h", "--help"} & set(argv))
        return build_parser(WORKFLOWS if helps else ())
    module = "ngc2py." + command
    return build_parser((module,) if module in WORKFLOWS else WORKFLOWS)


def parse_arguments(argv: List[str]) -> argparse.Namespace:
    """The command line by argparse. ``run``'s output file may come after
    options that follow the program (``run P.ngc -t T.tbl OUT``), as rs274's
    getopt lets it; argparse takes positionals only where they stand
    together, so a single name it leaves over is that file."""
    parser = _parser_for(argv)
    if argv[:1] != ["run"]:
        return parser.parse_args(argv)
    args, extra = parser.parse_known_args(argv)
    if extra:
        if len(extra) > 1 or extra[0].startswith("-") or args.output is not None:
            return parser.parse_args(argv)  # argparse's own error
        args.output = extra[0]
    return args


def main(argv: Optional[List[str]] = None) -> int:
    """The command line; returns the exit status (never calls sys.exit), so
    it can be called in-process. Output goes to sys.stdout/sys.stderr as
    they are at call time."""
    arguments = sys.argv[1:] if argv is None else argv
    try:
        args = quick_args(arguments) or parse_arguments(arguments)
    except SystemExit as stop:  # argparse: --help, --version, or a usage error
        # A usage error exits 1, as rs274 does (argparse would say 2).
        return 0 if stop.code in (0, None) else 1
    handler = getattr(args, "handler", None)
    try:
        if handler is not None:
            return handler(args)
        return convert(args) if args.command == "convert" else run(args)
    except CompileError as error:
        if args.command == "run":
            sys.stderr.write("executing\n")  # rs274 says this before failing
        sys.stderr.write("%s\n" % error)
    except OSError as error:
        name = error.filename or getattr(args, "program", "ngc2py")
        sys.stderr.write("ngc2py: %s: %s\n" % (name, error.strerror or error))
    except Exception as error:  # noqa: BLE001 - one line, never a traceback
        sys.stderr.write(
            "ngc2py: internal error: %s: %s\n" % (type(error).__name__, error)
        )
    return 1


if __name__ == "__main__":
    sys.exit(main())
