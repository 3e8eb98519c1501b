"""``ngc2py stats``: extents, path lengths, counts and an estimated cycle time.

The program runs against ``runtime.stats.StatsCanon``: no trace is written
or formatted. The model is described in that module and in ``--help``.
"""

from __future__ import annotations

import sys

from ngc2py.simulate import EXIT_ERROR, EXIT_OK, add_rs274_options, run_program
from runtime.stats import DEFAULT_ACCELERATION, DEFAULT_RAPID_RATE, Model, StatsCanon
from runtime.lazy_re import Pattern
from runtime.toolpath import MM_PER_INCH

# argparse, re and typing cost a small program's stats a tenth of its time:
# the plain command line is read without argparse (ngc2py.cli.quick_args)
TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse
    from typing import Dict

EPILOG = """\
cycle time model: every move starts and ends at rest, with a trapezoidal
speed profile (accelerate at --accel to the move's speed, brake to a stop);
rapids run at --rapid-rate, feeds and arcs at the programmed feed (G93
inverse time is turned into a rate by the interpreter; G95 feed per rev is
multiplied by S in rpm; moves with no usable rate are reported as untimed);
dwells add their time, each M6 adds --tool-change-time. Blending (G64) on a
real machine makes short segments faster than this estimate.

Rates take a unit: 3000 or 3000mm (mm/min, mm/s^2) or 120in (in/min,
in/s^2). Lengths and extents are reported in the program's units (those in
force at its first move); extents include the bulge of arcs.

exit status: 0 the program ran to its end; 1 a G-code error (rs274's
message on stderr, no report) or a bad file or option."""

_RATE = Pattern(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(mm|in|inch)?\s*$")


def rate(text: str) -> float:
    """A rate in millimetres from ``3000``, ``3000mm`` or ``120in``."""
    import argparse

    match = _RATE.match(text)
    if match is None:
        raise argparse.ArgumentTypeError("%r is not a number with mm or in" % text)
    value = float(match.group(1))
    return value * MM_PER_INCH if match.group(2) in ("in", "inch") else value


def seconds(text: str) -> float:
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("%r is not a number of seconds" % text)
    if value < 0:
        raise argparse.ArgumentTypeError("%r is negative" % text)
    return value


def register(commands) -> None:
    import argparse

    parser = commands.add_parser(
        "stats",
        help="extents, path lengths, counts and estimated cycle time",
        description="Run PROG.ngc (no trace) and report the extents of its "
        "toolpath per axis, path length by move type, counts of moves, arcs, "
        "tool changes and dwells, and an estimated cycle time.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "program", metavar="PROG.ngc", help="the G-code file ('-': standard input)"
    )
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    parser.add_argument(
        "--rapid-rate",
        type=rate,
        metavar="RATE",
        help="rapid (G0) speed per minute (default %g mm/min)" % DEFAULT_RAPID_RATE,
    )
    parser.add_argument(
        "--accel",
        type=rate,
        metavar="RATE",
        help="acceleration per second squared, 0 for instant "
        "(default %g mm/s^2)" % DEFAULT_ACCELERATION,
    )
    parser.add_argument(
        "--tool-change-time",
        type=seconds,
        metavar="SECONDS",
        help="time added for each tool change (default 0)",
    )
    add_rs274_options(parser)
    parser.set_defaults(**DEFAULTS)


def command(args: argparse.Namespace) -> int:
    model = Model(args.rapid_rate, args.accel, args.tool_change_time)
    canon = StatsCanon(model)
    status = run_program(args, canon)
    if status != EXIT_OK:
        return EXIT_ERROR
    report = canon.report()
    if args.json:
        import json

        json.dump(report, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        sys.stdout.write(format_report(report))
    return EXIT_OK


#: What no option of the command line sets (argparse's defaults, and those
#: of ngc2py.cli.quick_args), the command's handler among them.
DEFAULTS = {
    "handler": command,
    "rapid_rate": DEFAULT_RAPID_RATE,
    "accel": DEFAULT_ACCELERATION,
    "tool_change_time": 0.0,
}


def clock(total: float) -> str:
    """Seconds as h:mm:ss.s."""
    hours, rest = divmod(total, 3600.0)
    minutes, secs = divmod(rest, 60.0)
    return "%d:%02d:%04.1f" % (hours, minutes, secs)


def format_report(report: Dict) -> str:
    units = report["units"]
    lines = ["units: %s" % units, "extents:"]
    if not report["extents"]:
        lines.append("  (no moves)")
    for axis, (low, high) in report["extents"].items():
        unit = "deg" if axis in "abc" else units
        lines.append(
            "  %s %12.4f .. %12.4f  (%.4f %s)"
            % (axis.upper(), low, high, high - low, unit)
        )
    lengths, moves = report["length"], report["moves"]
    lines.append("path length (%s):" % units)
    for kind in ("rapid", "feed", "arc", "total"):
        lines.append("  %-6s %14.4f  (%d moves)" % (kind, lengths[kind], moves[kind]))
    if moves["probe"]:
        lines.append("  (%d probe moves counted as feed)" % moves["probe"])
    lines.append("tool changes: %d" % report["tool_changes"])
    lines.append("dwells: %d (%.3f s)" % (report["dwells"], report["dwell_time"]))
    model = report["model"]
    lines.append(
        "cycle time: %s (%.1f s; rapid %g %s/min, accel %g %s/s^2, tool change %g s)"
        % (
            clock(report["cycle_time"]),
            report["cycle_time"],
            round(model["rapid_rate"], 4),
            units,
            round(model["acceleration"], 4),
            units,
            model["tool_change_time"],
        )
    )
    if report["untimed_moves"]:
        lines.append(
            "  %d moves had no feed rate to time them (G95 with S0?)"
            % report["untimed_moves"]
        )
    return "\n".join(lines) + "\n"


__all__ = ["register", "command", "format_report"]
