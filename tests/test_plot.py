"""``ngc2py plot``: the path it draws, and the pictures it writes.

(The README's picture was checked by eye; these tests check what can be
checked mechanically: geometry, formats, colours present, exit statuses.)
"""

from __future__ import annotations

import io
import math
import os
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
from PIL import Image
import pytest

import rs274 as harness
from test_stats import scratch_run

from ngc2py import cli
from ngc2py.drawing import STYLES, arc_polyline, polyline, project
from ngc2py.moves import ARC, FEED, RAPID, toolpath

matplotlib = pytest.importorskip(
    "matplotlib", reason="matplotlib is a dependency of ngc2py plot"
)

FLANGE = harness.REPO / "examples" / "flange.ngc"


def toolpath_of(tmp_path, text: str):
    path = tmp_path / "prog.ngc"
    path.write_text(text)
    with scratch_run(path) as s:
        return toolpath(s.program.name)


def main(argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        rc = cli.main(argv)
    return rc, out.getvalue(), err.getvalue()


def _pieces(vertices):
    """The NaN-separated runs of a polyline, as lists of (x, y, z)."""
    runs, run = [], []
    for point in vertices.tolist():
        if any(math.isnan(v) for v in point):
            runs.append(run)
            run = []
        else:
            run.append(tuple(point))
    return [r for r in runs + [run] if r]


def test_arcs_are_drawn_as_arcs_in_their_plane(tmp_path):
    path = toolpath_of(
        tmp_path,
        "G21 F100\nG0 X10 Y3\nG18 G2 X-10 Z0 I-10 K0\nG19 G3 Y3 Z0 J0 K2 P2\nM2\n",
    )
    arcs = np.flatnonzero(path.kind == ARC)
    xz, yz = _pieces(arc_polyline(path, arcs, 0.001))
    assert len(xz) > 20 and len(yz) > 100  # sampled, not a chord
    for x, y, z in xz:
        assert y == pytest.approx(3.0)  # in the XZ plane
        assert math.hypot(x, z) == pytest.approx(10.0)
    assert max(z for _, _, z in xz) == pytest.approx(
        10.0, abs=0.01
    )  # G2 in XZ bulges to +Z
    for x, y, z in yz:
        assert x == pytest.approx(-10.0)
        assert math.hypot(y - 3.0, z - 2.0) == pytest.approx(2.0)


@pytest.mark.parametrize("radius", [0.5, 10.0, 2000.0])
def test_arc_points_stay_within_the_resolution(tmp_path, radius):
    path = toolpath_of(
        tmp_path, "G21 F100\nG0 X%s Y0\nG3 X0 Y%s I-%s J0\nM2\n" % ((radius,) * 3)
    )
    resolution = radius / 1000.0
    (arc,) = _pieces(arc_polyline(path, np.flatnonzero(path.kind == ARC), resolution))
    assert arc[0] == pytest.approx((radius, 0, 0)) and arc[-1] == pytest.approx(
        (0, radius, 0)
    )
    for (x0, y0, _), (x1, y1, _) in zip(arc, arc[1:]):
        middle = math.hypot((x0 + x1) / 2, (y0 + y1) / 2)
        assert radius - middle <= resolution * (1 + 1e-9)


def test_rapids_and_feeds_are_kept_apart(tmp_path):
    path = toolpath_of(tmp_path, "G0 X1\nG0 Y1\nG1 X2 F10\nG0 Z1\nM2\n")
    rapid = path.kind == RAPID
    assert _pieces(polyline(path.start[rapid, :3], path.end[rapid, :3])) == [
        [(0, 0, 0), (1, 0, 0), (1, 1, 0)],
        [(2, 1, 0), (2, 1, 1)],
    ]
    feed = path.kind == FEED
    assert _pieces(polyline(path.start[feed, :3], path.end[feed, :3])) == [
        [(1, 1, 0), (2, 1, 0)]
    ]


def test_inch_program_is_drawn_in_inches(tmp_path):
    path = toolpath_of(tmp_path, "G20 G0 X1\nM2\n")
    assert path.units == "inch"
    assert path.end[0, 0] == pytest.approx(25.4)  # kept in mm, drawn /25.4


def test_views():
    point = np.array([[1.0, 2.0, 3.0]])
    assert [list(c) for c in project(point, "xy")] == [[1], [2]]
    assert [list(c) for c in project(point, "xz")] == [[1], [3]]
    assert [list(c) for c in project(point, "yz")] == [[2], [3]]
    u, v = project(np.array([[1.0, 0.0, 0.0]]), "iso")
    assert u[0] > 0 and v[0] > 0  # X to the upper right, as --help says
    u, v = project(np.array([[0.0, 1.0, 0.0]]), "iso")
    assert u[0] < 0 and v[0] > 0


def _colour(hex_colour):
    return tuple(int(hex_colour[i : i + 2], 16) / 255 for i in (1, 3, 5))


@pytest.mark.parametrize("view", ["xy", "xz", "yz", "iso"])
def test_png_shows_rapids_feeds_and_arcs(tmp_path, view):
    import matplotlib.image

    out = tmp_path / ("flange-%s.png" % view)
    with scratch_run(FLANGE) as s:
        rc, _, err = main(["plot", s.program.name, "-o", str(out), "--view", view])
    assert rc == 0, err
    pixels = matplotlib.image.imread(str(out))[:, :, :3]
    for kind, (_, colour, _, _) in STYLES.items():
        target = _colour(colour)
        close = (abs(pixels - target) < 0.03).all(axis=2).sum()
        assert close > 50, "no %s pixels in the %s view" % (kind, view)


def test_svg_pdf_and_standard_output(tmp_path, capfdbinary):
    with scratch_run(FLANGE) as s:
        assert main(["plot", s.program.name, "-o", str(tmp_path / "a.svg")])[0] == 0
        assert main(["plot", s.program.name, "-o", str(tmp_path / "a.pdf")])[0] == 0
    assert (tmp_path / "a.svg").read_text().lstrip().startswith("<?xml")
    assert (tmp_path / "a.pdf").read_bytes().startswith(b"%PDF")


def test_png_to_standard_output(tmp_path):
    import subprocess
    import sys

    with scratch_run(FLANGE) as s:
        proc = subprocess.run(
            [sys.executable, "-m", "ngc2py", "plot", s.program.name, "-o", "-"],
            cwd=s.work,
            env=s.env({"NGC2PY_CACHE": str(s.tmp / "cache")}),
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith(b"\x89PNG\r\n")


def test_errors_write_no_picture(tmp_path):
    bad = tmp_path / "bad.ngc"
    bad.write_text("G1 X1 F10\nG1 X[1/0]\nM2\n")
    out = tmp_path / "bad.png"
    with scratch_run(bad) as s:
        rc, _, err = main(["plot", s.program.name, "-o", str(out)])
    assert rc == 1 and err.startswith("Attempt to divide by zero")
    assert not out.exists()
    rc, _, err = main(["plot", str(FLANGE), "-o", str(tmp_path / "x.gif")])
    assert rc == 1 and "extension" in err
    rc, _, _ = main(["plot", str(FLANGE)])  # -o is required
    assert rc == 1


def test_help():
    rc, out, _ = main(["plot", "--help"])
    assert rc == 0 and "--view" in out and "exit status" in out


def test_program_from_standard_input(tmp_path, monkeypatch):
    monkeypatch.setattr(
        "sys.stdin", io.TextIOWrapper(io.BytesIO(b"G0 X3\nG1 Y2 F9\nM2\n"))
    )
    out = tmp_path / "stdin.svg"
    with scratch_run(tmp_path / "x.ngc", ""):
        rc, _, err = main(["plot", "-", "-o", str(out)])
    assert rc == 0, err
    assert "standard input" in out.read_text()


def _mask(png: bytes, colour: str, tolerance: float) -> np.ndarray:
    import matplotlib.image

    pixels = matplotlib.image.imread(io.BytesIO(png))[:, :, :3]
    return (abs(pixels - _colour(colour)) < tolerance).all(axis=2)


def _grown(mask: np.ndarray, by: int) -> np.ndarray:
    grown = mask.copy()
    for dy in range(-by, by + 1):
        for dx in range(-by, by + 1):
            grown |= np.roll(np.roll(mask, dy, axis=0), dx, axis=1)
    return grown


@pytest.mark.parametrize("view", ["xy", "iso"])
def test_a_dense_path_is_rasterised_where_its_lines_would_be_drawn(
    tmp_path, monkeypatch, view
):
    """The same path drawn as vectors and, past RASTER_FROM, as an image of
    its pixels: the two pictures' feed and arc pixels coincide (within the
    lines' width), so the raster sits at the right place, the right way up,
    in every view."""
    from ngc2py import drawing

    text = ["G21 G90 G17 F500 G0 X0 Y0"]
    for k in range(60):
        text.append("G1 X%d Y%d Z-%d" % (k % 7 * 10, (k * 13) % 40, k % 3))
        text.append("G2 X%d Y%d R30" % (k % 7 * 10 + 5, (k * 13) % 40))
    text.append("M2")
    path = toolpath_of(tmp_path, "\n".join(text) + "\n")
    pictures = {}
    for name, threshold in (("vector", 10**9), ("raster", 0)):
        monkeypatch.setattr(drawing, "RASTER_FROM", threshold)
        out = io.BytesIO()
        drawing.draw(path, view, "dense", out, "png")
        pictures[name] = out.getvalue()
    for kind in ("feed", "arc"):
        colour = STYLES[kind][1]
        raster = _mask(pictures["raster"], colour, 0.02)
        # the vector lines' cores, and with their antialiased edges
        core = _mask(pictures["vector"], colour, 0.1)
        inked = _mask(pictures["vector"], colour, 0.45)
        assert raster.sum() > 500 and core.sum() > 500
        assert raster.shape == core.shape
        # every raster pixel lies on a drawn line, and every line's core
        # within a pixel of the raster
        assert (raster & _grown(inked, 1)).sum() >= 0.99 * raster.sum()
        assert (core & _grown(raster, 1)).sum() >= 0.99 * core.sum()


@pytest.mark.parametrize("view", ["xy", "xz"])
def test_feeds_and_arcs_in_one_image_look_as_in_two(tmp_path, monkeypatch, view):
    """Dense feeds and arcs share one raster image, arcs over feeds
    (drawing._raster_groups): the very pixels of an image for each, where
    feeds and arcs cross and lie on top of one another."""
    from ngc2py import drawing

    text = ["G21 G90 G17 F500 G0 X0 Y0"]
    for k in range(40):
        text.append("G1 X%d Y%d Z-%d" % (k % 5 * 10, (k * 7) % 30, k % 3))
        text.append("G3 X%d Y%d R%d" % (k % 5 * 10 + 8, (k * 7) % 30, 5 + k % 9))
        # back along the arc's chord
        text.append("G1 X%d Y%d" % (k % 5 * 10, (k * 7) % 30))
    text.append("M2")
    path = toolpath_of(tmp_path, "\n".join(text) + "\n")
    monkeypatch.setattr(drawing, "RASTER_FROM", 0)
    merging = drawing._raster_groups
    assert merging({"rapid": 0, "feed": 0, "arc": 0}) == [["rapid"], ["feed", "arc"]]
    pictures = []
    for groups in (
        drawing._raster_groups,
        lambda dense: [[k] for k in sorted(dense, key=drawing.ZORDER.get)],
    ):
        monkeypatch.setattr(drawing, "_raster_groups", groups)
        out = io.BytesIO()
        drawing.draw(path, view, "layers", out, "png")
        pictures.append(out.getvalue())
    merged, separate = pictures
    merged_pixels, separate_pixels = (
        np.asarray(Image.open(io.BytesIO(p))) for p in pictures
    )
    assert merged_pixels.shape == separate_pixels.shape
    assert (merged_pixels == separate_pixels).all()
    for kind in ("feed", "arc"):
        assert _mask(merged, STYLES[kind][1], 0.02).sum() > 500


@pytest.mark.parametrize("view", ["xy", "iso"])
def test_agg_draws_the_raster_where_an_image_of_it_would_be(
    tmp_path, monkeypatch, view
):
    """A PNG's raster is drawn by Agg pixel for pixel (no resampling); the
    same picture with the raster drawn as an AxesImage (what vector
    formats get) has its pixels at most a pixel away, and nothing else
    changes."""
    from ngc2py import drawing

    text = ["G21 G90 G17 F500 G0 X0 Y0"]
    for k in range(50):
        text.append("G1 X%d Y%d" % (k % 6 * 9, (k * 11) % 37))
        text.append("G2 X%d Y%d R%d" % (k % 6 * 9 + 6, (k * 11) % 37, 4 + k % 7))
    text.append("M2")
    path = toolpath_of(tmp_path, "\n".join(text) + "\n")
    monkeypatch.setattr(drawing, "RASTER_FROM", 0)
    pictures = []
    directly = drawing._draws_directly
    calls = []
    for chosen in (True, False):

        def draws(*args, chosen=chosen):
            calls.append(directly(*args))
            return chosen and calls[-1]

        monkeypatch.setattr(drawing, "_draws_directly", draws)
        out = io.BytesIO()
        drawing.draw(path, view, "agg", out, "png")
        pictures.append(out.getvalue())
    assert calls and all(calls)  # a PNG's raster is the axes' size
    direct, image = (np.asarray(Image.open(io.BytesIO(p))) for p in pictures)
    assert direct.shape == image.shape
    for kind in ("feed", "arc"):
        ours, theirs = (_mask(p, STYLES[kind][1], 0.02) for p in pictures)
        assert ours.sum() > 500
        # (a pixel may differ where the arcs' layer covers the feeds')
        assert (ours & _grown(theirs, 1)).sum() >= 0.999 * ours.sum()
        assert (theirs & _grown(ours, 1)).sum() >= 0.999 * theirs.sum()
    # outside the axes (labels, legend, title) the pictures are the same
    rows, columns = np.nonzero((direct != image).any(axis=2))
    assert len(rows) < 0.05 * direct.shape[0] * direct.shape[1]


def test_the_rasters_pens_draw_what_imagedraws_own_methods_draw(monkeypatch):
    """rasterise draws with Pillow's drawing core where it can
    (drawing._pens): the very pixels of ImageDraw.line and point, runs of
    one point and NaN breaks included, in every width."""
    from ngc2py import drawing

    rng = np.random.default_rng(5)
    flat = rng.uniform(-20.0, 20.0, size=(400, 2))
    flat[rng.choice(400, 60, replace=False)] = np.nan  # breaks, lone points
    limits, size = ((-21.0, 21.0), (-21.0, 21.0)), (160, 120)
    masks = [drawing.rasterise(flat, limits, size, width) for width in (1, 3)]
    pens = drawing._pens
    used = []

    class WithoutCore:  # an ImageDraw whose drawing core is not to be seen
        def __init__(self, pen):
            self.line, self.point = pen.line, pen.point
            used.append(pens(pen)[0].__code__ is not pens(self)[0].__code__)

    monkeypatch.setattr(drawing, "_pens", lambda pen: pens(WithoutCore(pen)))
    for mask, width in zip(masks, (1, 3)):
        assert mask.sum() > 1000
        assert (drawing.rasterise(flat, limits, size, width) == mask).all()
    assert used and all(used)  # the second time, ImageDraw's methods drew


@pytest.mark.parametrize("view", ["xy", "iso"])
def test_the_box_found_before_the_rasters_is_savefigs_tight_box(
    tmp_path, monkeypatch, view
):
    """A PNG's tight box is found before the raster layers are added (so
    that they are drawn once): the very picture savefig's "tight" makes."""
    from ngc2py import drawing

    text = ["G21 G90 G17 F500 G0 X0 Y0"]
    for k in range(40):
        text.append("G1 X%d Y%d" % (k % 5 * 10, (k * 7) % 30))
        text.append("G3 X%d Y%d R25" % (k % 5 * 10 + 4, (k * 7) % 30))
    path = toolpath_of(tmp_path, "\n".join(text + ["M2"]) + "\n")
    monkeypatch.setattr(drawing, "RASTER_FROM", 0)
    merging = drawing._raster_groups
    assert merging({"rapid": 0, "feed": 0, "arc": 0}) == [["rapid"], ["feed", "arc"]]
    pictures = []
    for formats in (drawing.BOX_BEFORE_RASTERS, set()):
        monkeypatch.setattr(drawing, "BOX_BEFORE_RASTERS", formats)
        out = io.BytesIO()
        drawing.draw(path, view, "box", out, "png")
        pictures.append(
            np.asarray(Image.open(io.BytesIO(out.getvalue())).convert("RGBA"))
        )
    assert pictures[0].shape == pictures[1].shape
    assert (pictures[0] == pictures[1]).all()


# --- the program runs beside matplotlib's import (ngc2py.plot._sketch_beside)


def _plot_bytes(tmp_path, name: str, text: str):
    program = tmp_path / "p.ngc"
    program.write_text(text)
    out = tmp_path / name
    with scratch_run(program) as s:
        rc, printed, err = main(["plot", s.program.name, "-o", str(out)])
    return rc, printed, err, out.read_bytes() if out.exists() else None


PRINTING = "G0 X3\n(PRINT,hello)\n(DEBUG,x=#5420)\nG2 X0 Y3 R3 F100\nG1 Y9\nM2\n"


def test_the_program_run_beside_the_import_draws_what_it_draws_here(
    tmp_path, monkeypatch
):
    """In a child process (while matplotlib is imported) or here (no fork):
    the same picture, the same exit status and the same printed text."""
    import os
    import sys

    from ngc2py import plot

    recorded = plot._recorded

    def printing(args):  # (the plot prints nothing of its own while it runs)
        (tmp_path / "ran_in").write_text(str(os.getpid()))
        print("printed while it ran")
        sys.stderr.write("and on stderr\n")
        return recorded(args)

    monkeypatch.setattr(plot, "_recorded", printing)
    beside = _plot_bytes(tmp_path, "beside.png", PRINTING)
    assert (tmp_path / "ran_in").read_text() != str(os.getpid())  # in a child
    monkeypatch.delattr(plot.os, "fork")
    here = _plot_bytes(tmp_path, "here.png", PRINTING)
    assert beside == here
    assert beside[0] == 0 and beside[3].startswith(b"\x89PNG")
    assert beside[1:3] == ("printed while it ran\n", "and on stderr\n")


@pytest.mark.parametrize(
    "text, count",
    [
        ("G0 X3\nG2 X0 Y3 R3 F100\nG1 Y9\nG1 X1\nG1 X2\nG1 X3\nM2\n", 6),
        # rows of holes (enough for a row table), recorded in batches
        # (Recorder.hole_moves): the G0, 4 moves at the cycle's own line
        # (over, down to R, in, out), then 3 at each row
        ("G0 Z5\nG81 X0 Y0 Z-1 R1 F100\n" + "".join("X%d\n" % k for k in range(1, 81))
         + "G80\nM2\n", 1 + 4 + 80 * 3),
    ],
)  # fmt: skip
def test_the_child_records_without_numpy(tmp_path, text, count):
    """The program runs into stdlib arrays (NumPy, a tenth of a second to
    import, comes after the run, for the sketch): drilled holes too."""
    program = tmp_path / "p.ngc"
    program.write_text(text)
    code = (
        "import sys, argparse\n"
        "from ngc2py import plot\n"
        "args = argparse.Namespace(program=sys.argv[1], tool_table=None,"
        " var_file=None, ini=None, block_delete=False)\n"
        "status, report, moves = plot._recorded(args)\n"
        "assert status == 0 and len(moves.kinds) == %d, (status, report,"
        " len(moves.kinds))\n"
        "print('numpy' in sys.modules)\n" % count
    )
    env = dict(os.environ, PYTHONPATH=str(harness.REPO), NGC2PY_CACHE=str(tmp_path))
    proc = subprocess.run(
        [sys.executable, "-c", code, str(program)],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "False\n"


def test_a_child_that_dies_leaves_the_program_to_run_here(tmp_path, monkeypatch):
    """A child that hands nothing back (killed, crashed): the program runs
    in this process, and the picture is the same."""
    import os

    from ngc2py import plot

    expected = _plot_bytes(tmp_path, "expected.png", PRINTING)
    parent, recorded = os.getpid(), plot._recorded

    def dying(args):
        if os.getpid() != parent:
            os._exit(9)
        return recorded(args)

    monkeypatch.setattr(plot, "_recorded", dying)
    assert _plot_bytes(tmp_path, "again.png", PRINTING) == expected


def test_an_error_raised_in_the_child_is_raised_here(tmp_path, monkeypatch):
    from ngc2py import plot

    def failing(args):
        raise KeyboardInterrupt("stopped")

    monkeypatch.setattr(plot, "_recorded", failing)
    with pytest.raises(KeyboardInterrupt, match="stopped"):
        _plot_bytes(tmp_path, "no.png", PRINTING)
