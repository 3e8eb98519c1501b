"""``ngc2py plot``: draw a program's toolpath to a PNG, SVG or PDF file.

The program runs against :class:`PlotCanon` (a ``runtime.toolpath``
back end, so the picture shows the same path ``ngc2py stats`` measures):
rapids dashed, straight feeds and arcs solid in their own colours, arcs and
helices drawn as arcs (sampled every few degrees in their own plane).
matplotlib is imported only when a picture is drawn.
"""

from __future__ import annotations

import argparse
import importlib
import io
import math
import os
import sys
from typing import Dict, List, Sequence, Tuple

from ngc2py.cache import write_atomic
from ngc2py.simulate import EXIT_ERROR, EXIT_OK, add_rs274_options, run_program
from runtime.toolpath import MM_PER_INCH, Arc, Point, ToolpathCanon

VIEWS = ("xy", "xz", "yz", "iso")
FORMATS = ("png", "svg", "pdf")
#: How each kind of move is drawn: legend label, colour, line style, width.
STYLES = {
    "rapid": ("rapid (G0)", "#d62728", (0, (4, 3)), 0.9),
    "feed": ("feed (G1)", "#1f77b4", "solid", 1.3),
    "arc": ("arc (G2/G3)", "#2ca02c", "solid", 1.3),
}
#: Angle between the points an arc is drawn through.
ARC_STEP = math.radians(2.0)
_COS30 = math.cos(math.radians(30.0))
_SIN30 = 0.5

EPILOG = """\
views: xy (top), xz (front), yz (side), iso (isometric: X to the upper
right, Y to the upper left, Z up). Positions are program coordinates in the
program's units (those in force at its first move).

exit status: 0 the picture was written; 1 a G-code error (rs274's message on
stderr, no picture), a bad file or option, or matplotlib missing."""


class PlotCanon(ToolpathCanon):
    """Collects the toolpath as 3-D polylines per kind of move (millimetres)."""

    def __init__(self) -> None:
        super().__init__()
        self.paths: Dict[str, List[List[Tuple[float, float, float]]]] = {
            kind: [] for kind in STYLES
        }
        self.moves = {kind: 0 for kind in STYLES}

    def line(self, kind: str, start: Point, end: Point) -> None:
        kind = "rapid" if kind == "rapid" else "feed"
        self.moves[kind] += 1
        paths = self.paths[kind]
        # Consecutive moves of one kind make one polyline (fewer, faster lines).
        if paths and paths[-1][-1] == start[:3]:
            paths[-1].append(end[:3])
        else:
            paths.append([start[:3], end[:3]])

    def spline(self, path) -> None:
        self.moves["feed"] += 1  # one move, drawn as the curve's polyline
        self.paths["feed"].append([p[:3] for p in path])

    def arc(self, arc: Arc) -> None:
        self.moves["arc"] += 1
        # 2 degrees: 5 showed corners on large arcs and on spirals
        self.paths["arc"].append([p[:3] for p in arc.sample(ARC_STEP)])


def project(points: Sequence[Tuple[float, float, float]], view: str):
    """2-D coordinates of ``points`` seen from ``view``."""
    if view == "xy":
        return [(x, y) for x, y, _ in points]
    if view == "xz":
        return [(x, z) for x, _, z in points]
    if view == "yz":
        return [(y, z) for _, y, z in points]
    return [((x - y) * _COS30, (x + y) * _SIN30 + z) for x, y, z in points]


def axis_labels(view: str, units: str) -> Tuple[str, str]:
    if view == "iso":
        return (
            "isometric: X to the upper right, Y to the upper left, Z up (%s)" % units,
            "",
        )
    return ("%s (%s)" % (view[0].upper(), units), "%s (%s)" % (view[1].upper(), units))


def draw(canon: PlotCanon, view: str, title: str, out, fmt: str) -> None:
    """Draw the collected toolpath and save it to ``out`` (a path or binary file)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    inches = bool(canon.first_units)
    units = "inch" if inches else "mm"
    scale = 1.0 / MM_PER_INCH if inches else 1.0
    figure, axes = pyplot.subplots(figsize=(8, 6.5), dpi=150)
    handles = []
    low = [math.inf] * 3
    high = [-math.inf] * 3
    for kind, (label, colour, style, width) in STYLES.items():
        paths = [
            [tuple(v * scale for v in p) for p in path] for path in canon.paths[kind]
        ]
        for path in paths:
            for p in path:
                for i in range(3):
                    low[i] = min(low[i], p[i])
                    high[i] = max(high[i], p[i])
        count = canon.moves[kind]
        if paths:
            flat = [project(path, view) for path in paths]
            lines = LineCollection(
                flat,
                colors=colour,
                linestyles=style,
                linewidths=width,
                zorder={"rapid": 1, "feed": 2, "arc": 3}[kind],
            )
            axes.add_collection(lines)
            if kind != "rapid":
                # A plunge seen end-on (a drilled hole from the top) is a dot.
                dots = [
                    path[i]
                    for path in flat
                    for i in range(len(path) - 1)
                    if path[i] == path[i + 1]
                ]
                if dots:
                    axes.plot(*zip(*dots), "o", color=colour, markersize=3, zorder=4)
        handles.append(
            Line2D(
                [],
                [],
                color=colour,
                linestyle=style,
                linewidth=width,
                label="%s: %d move%s" % (label, count, "" if count == 1 else "s"),
            )
        )
    axes.autoscale()
    axes.set_aspect("equal", adjustable="datalim")
    axes.margins(0.05)
    xlabel, ylabel = axis_labels(view, units)
    axes.set_xlabel(xlabel)
    axes.set_ylabel(ylabel)
    if view == "iso":
        axes.set_xticks([])
        axes.set_yticks([])
    axes.grid(True, linewidth=0.3, alpha=0.5)
    axes.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    axes.set_title("%s - %s view" % (title, view.upper()), fontsize=11)
    if low[0] != math.inf:
        extent = "   ".join(
            "%s %.4g .. %.4g" % (name, low[i], high[i]) for i, name in enumerate("XYZ")
        )
        figure.text(
            0.5, 0.015, "extents (%s):   %s" % (units, extent), ha="center", fontsize=8
        )
    else:
        figure.text(0.5, 0.015, "no moves", ha="center", fontsize=8)
    figure.savefig(out, format=fmt, bbox_inches="tight")
    pyplot.close(figure)


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
        importlib.import_module("matplotlib")  # fail before running the program
    except (ValueError, ImportError) as error:
        sys.stderr.write("ngc2py plot: %s\n" % error)
        return EXIT_ERROR
    canon = PlotCanon()
    if run_program(args, canon) != EXIT_OK:
        return EXIT_ERROR
    title = "standard input" if args.program == "-" else os.path.basename(args.program)
    if args.output == "-":
        buffer = io.BytesIO()
        draw(canon, args.view, title, buffer, fmt)
        sys.stdout.flush()
        sys.stdout.buffer.write(buffer.getvalue())
        sys.stdout.buffer.flush()
        return EXIT_OK
    buffer = io.BytesIO()
    draw(canon, args.view, title, buffer, fmt)
    try:
        write_atomic(args.output, buffer.getvalue())
    except OSError as error:
        sys.stderr.write(
            "ngc2py plot: %s: %s\n" % (args.output, error.strerror or error)
        )
        return EXIT_ERROR
    return EXIT_OK


__all__ = ["PlotCanon", "register", "command", "draw", "project"]
