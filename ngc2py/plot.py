"""``ngc2py plot``: draw a program's toolpath to a PNG, SVG or PDF file.

The command line of the plot: the program runs into ``ngc2py.moves``'
arrays, and ``ngc2py.drawing`` draws them. NumPy and matplotlib are
imported only when a picture is drawn (every other command registers
its options beside this one's, and must not pay for them).
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import io
import os
import sys

from ngc2py.cache import write_atomic
from ngc2py.simulate import EXIT_ERROR, EXIT_OK, add_rs274_options

VIEWS = ("xy", "xz", "yz", "iso")
FORMATS = ("png", "svg", "pdf")

EPILOG = """\
views: xy (top), xz (front), yz (side), iso (isometric: X to the upper
right, Y to the upper left, Z up). Positions are program coordinates in the
program's units (those in force at its first move).

exit status: 0 the picture was written; 1 a G-code error (rs274's message on
stderr, no picture), a bad file or option, or matplotlib missing."""


def register(commands) -> None:
    parser = commands.add_parser(
        "plot",
        help="draw the toolpath to a PNG/SVG/PDF file",
        description="Run PROG.ngc and draw its toolpath: rapids dashed, feeds "
        "and arcs solid (arcs and helices as arcs), with the extents, units "
        "and a legend.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "program", metavar="PROG.ngc", help="the G-code file ('-': standard input)"
    )
    parser.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        required=True,
        help="the picture: OUT.png, OUT.svg or OUT.pdf ('-': standard output, "
        "PNG unless --format says otherwise)",
    )
    parser.add_argument(
        "--view", choices=VIEWS, default="xy", help="projection (default xy)"
    )
    parser.add_argument(
        "--format",
        choices=FORMATS,
        help="picture format (default: from OUT's extension)",
    )
    add_rs274_options(parser)
    parser.set_defaults(handler=command)


def picture_format(args: argparse.Namespace) -> str:
    if args.format:
        return args.format
    if args.output == "-":
        return "png"
    extension = os.path.splitext(args.output)[1].lower().lstrip(".")
    if extension not in FORMATS:
        raise ValueError(
            "%s: cannot tell the format from the extension (use .png, .svg, "
            ".pdf or --format)" % args.output
        )
    return extension


def command(args: argparse.Namespace) -> int:
    try:
        fmt = picture_format(args)
        importlib.util.find_spec("matplotlib") or importlib.import_module("matplotlib")
    except (ValueError, ImportError) as error:  # fail before running the program
        sys.stderr.write("ngc2py plot: %s\n" % error)
        return EXIT_ERROR
    status, report, made = _sketch_beside(args, _prepare)
    sys.stderr.write(report)
    if status != EXIT_OK:
        return EXIT_ERROR
    from ngc2py.drawing import render

    title = "standard input" if args.program == "-" else os.path.basename(args.program)
    if args.output == "-":
        buffer = io.BytesIO()
        render(made, title, buffer, fmt)
        sys.stdout.flush()
        sys.stdout.buffer.write(buffer.getvalue())
        sys.stdout.buffer.flush()
        return EXIT_OK
    buffer = io.BytesIO()
    render(made, title, buffer, fmt)
    try:
        write_atomic(args.output, buffer.getvalue())
    except OSError as error:
        sys.stderr.write(
            "ngc2py plot: %s: %s\n" % (args.output, error.strerror or error)
        )
        return EXIT_ERROR
    return EXIT_OK


def _prepare() -> None:
    """Import NumPy, matplotlib and Pillow for the drawing. (Not before the
    fork: NumPy starts its BLAS threads on import, and a process that
    forks should have no other threads.)"""
    from ngc2py.drawing import prepare

    prepare()


def _recorded(args: argparse.Namespace):
    """Run the program: (exit status, rs274's stderr text, the recorded
    moves or None after an error). Imports no NumPy."""
    from ngc2py.recorder import record

    recorder, status, report = record(args)
    return status, report, recorder.moves() if status == EXIT_OK else None


def _sketched(args: argparse.Namespace):
    """:func:`_recorded`, the moves then made into the picture's
    drawing.Sketch (NumPy's work alone: the child makes it while the parent
    imports matplotlib)."""
    status, report, moves = _recorded(args)
    if moves is None:
        return status, report, None
    from ngc2py.drawing import sketch
    from ngc2py.moves import Toolpath

    return status, report, sketch(Toolpath.from_recorder(moves), args.view)


def _sketch_beside(args: argparse.Namespace, prepare):
    """:func:`_sketched`, run in a child process while this one runs
    ``prepare`` (importing matplotlib: half a second, as long as a 200k-move
    program takes), the sketch handed back through a pipe.
    Where there is no fork, or the child hands nothing back (it died), the
    program runs here, after ``prepare``: the same answer, later."""
    fork = getattr(os, "fork", None)
    if fork is None or args.program == "-":  # (standard input is read once)
        prepare()
        return _sketched(args)
    import pickle

    sys.stdout.flush()
    sys.stderr.flush()
    read, write = os.pipe()
    child = fork()
    if child == 0:  # pragma: no cover - runs in the child (coverage: the parent)
        os.close(read)
        # what the program prints is handed back too, and written by the
        # parent where it would have been (its stdout may be a test's buffer)
        printed = sys.stdout, sys.stderr = io.StringIO(), io.StringIO()
        try:
            result = ("done", _sketched(args))
        except BaseException as error:  # noqa: BLE001 - handed to the parent
            result = ("raised", error)
        texts = tuple(stream.getvalue() for stream in printed)
        try:
            with os.fdopen(write, "wb") as out:
                try:
                    pickle.dump(result + texts, out, protocol=pickle.HIGHEST_PROTOCOL)
                except Exception:  # noqa: BLE001 - an error that does not pickle
                    error = RuntimeError(repr(result[1]))
                    pickle.dump(("raised", error) + texts, out)
        finally:
            os._exit(0)
    os.close(write)
    try:
        prepare()
        with os.fdopen(read, "rb") as handed:
            try:
                how, what, out_text, err_text = pickle.load(handed)
            except (EOFError, pickle.UnpicklingError):
                how = None  # the child died: run the program here
    finally:
        os.waitpid(child, 0)
    if how is None:
        return _sketched(args)
    sys.stdout.write(out_text)
    sys.stderr.write(err_text)
    if how == "raised":
        raise what
    return what


__all__ = ["FORMATS", "VIEWS", "command", "register"]
