"""Hypothesis strategies for CAM output: long runs of literal-only lines.

A CAM post-processor writes a program as a few set-up lines and then
thousands of blocks of literal words: ``G1 X12.345 Y-0.5 F800``, an axis
word alone in the modal motion, an N number on every line or on none,
numbers with any count of decimals and written every way G-code allows
(``-.5``, ``+2``, ``007.250``, ``12.``). ngc2py keeps such runs as data
tables (runtime/fast/rows.py), and as the trace's own text when every value has
at most four decimals (runtime/fast/printed_rows.py); these programs exercise
both, the modes that turn the fast paths off (incremental distance, offsets,
inverse time, units), the blocks that interrupt a run (dwell, spindle,
coolant, plane), arcs in each plane (Machine.plain_arc), long stretches
of one row shape (written in batches) and the value errors a run can hit (no feed rate, a negative F, a zero F under G1).

Chains of arcs (`arc_chain`, runtime/fast/arc_rows.py) are computed from a
known start point so that most of them are valid: centre (I J K, offsets
or G90.1 centres) or radius (+R short, -R long) format, full circles,
quarter, half and odd sweeps, radii from 0.002 to 20000, P turns, helical
moves, modal continuation, F changes, N numbers, long stretches of one
row layout alternating G2 and G3 (the batch form), and now and then an
arc rs274 rejects: radii differing beyond the tolerance, a zero radius,
an R arc ending where it starts, a missing G90.1 centre word, F0.
"""

from __future__ import annotations

import math
import re

from hypothesis import strategies as st

from ngc2py.codegen import MIN_PROGRAM_ROWS

ARC = re.compile(r"\bG0?[23]\b")


def cam_sized(text: str) -> str:
    """``text`` (which ends with M2) and, past its M2, rows enough to make
    it CAM-sized for the code generator (codegen.MIN_PROGRAM_ROWS): then
    its runs of eight constant blocks and more become data tables, as in a
    real CAM file, where a short program's read as statements. rs274 never
    reads past M2, and neither does the generated module run them."""
    assert text.endswith("M2\n"), "rows past M2 only"
    return text + "G0 X0\n" * MIN_PROGRAM_ROWS


AXES = "XYZABC"


@st.composite
def numbers(draw, places: int = 6) -> str:
    """A literal as a CAM post (or a person) may write it, with at most
    ``places`` decimals."""
    whole = draw(st.integers(-400, 400))
    decimals = min(places, draw(st.sampled_from([0, 1, 2, 3, 3, 3, 4, 4, 5, 6])))
    fraction = draw(st.integers(0, 10**decimals - 1)) if decimals else 0
    sign = "-" if whole < 0 or (whole == 0 and draw(st.booleans()) and fraction) else ""
    digits = str(abs(whole))
    style = draw(st.integers(0, 5))
    if style == 1 and digits == "0" and decimals:
        digits = ""  # -.5
    elif style == 2:
        digits = "00" + digits  # leading zeros
    elif style == 3 and not sign:
        sign = "+"
    text = sign + digits
    if decimals:
        text += "." + str(fraction).rjust(decimals, "0")
    elif style == 4:
        text += "."  # 12.
    return text


@st.composite
def feed(draw, places: int = 6) -> str:
    """An F word; now and then one rs274 rejects (negative) or that leaves
    G1 without a feed rate (zero)."""
    if draw(st.integers(0, 30)) == 0:
        return "F" + draw(st.sampled_from(["0", "-5"]))
    rates = ["800", "1200.5", "60.25", "0.1234"] + (["99.87654"] if places > 4 else [])
    return "F" + draw(st.sampled_from(rates))


#: plane code -> (its two axes, the centre letters, the third axis)
PLANES = {"G17": ("XY", "IJ", "Z"), "G18": ("ZX", "KI", "Y"), "G19": ("YZ", "JK", "X")}


@st.composite
def arc_row(draw, plane: str, places: int = 6) -> str:
    """An arc that is valid wherever the tool is: a full circle given by its
    centre (no end point in the plane, so it ends where it starts, rising
    along the third axis), or an end point with a radius too big to miss."""
    axes, centre, third = PLANES[plane]
    words = [draw(st.sampled_from(["G2", "G3", "G02", "G03"]))]
    if draw(st.booleans()):
        words.append(third + draw(numbers(places)))
        radius = draw(st.sampled_from(["5", "12.5", "0.75", "-3.25"]))
        words.append(centre[0] + radius)
        words.append(centre[1] + draw(st.sampled_from(["0", "1.5", "-2"])))
    else:
        for letter in axes:
            words.append(letter + draw(numbers(places)))
        words.append("R" + draw(st.sampled_from(["1000", "-1000", "999.5"])))
    if draw(st.integers(0, 5)) == 0:
        words.append(draw(feed(places)))
    return " ".join(words)


@st.composite
def move_row(
    draw,
    numbered: bool,
    line: int,
    plane: str = "G17",
    after_arc: bool = False,
    places: int = 6,
) -> str:
    """A move; after an arc, mostly one that names its motion (an axis word
    alone would continue the arc and, without I J K or R, fail)."""
    words = []
    if numbered:
        words.append("N%d" % (line * 10))
    if draw(st.integers(0, 7)) == 0:
        words.append(draw(arc_row(plane, places)))
        return " ".join(words)
    motion = draw(st.sampled_from(["", "", "G1", "G0", "G01", "G00"]))
    if after_arc and not motion and draw(st.integers(0, 3)):
        motion = draw(st.sampled_from(["G1", "G0"]))
    if motion:
        words.append(motion)
    axes = draw(
        st.lists(
            st.sampled_from(AXES[:3] * 4 + AXES[3:]),
            min_size=1,
            max_size=4,
            unique=True,
        )
    )
    if draw(st.integers(0, 3)):  # else in the order drawn (G1 Z1 X2)
        axes.sort(key=AXES.index)
    for letter in axes:
        words.append(letter + draw(numbers(places)))
    if draw(st.integers(0, 7)) == 0:
        words.append(draw(feed(places)))
    return " ".join(words)


@st.composite
def same_shape_rows(
    draw, numbered: bool, line: int, places: int = 6, reorder: bool = False
) -> list:
    """Eight or more moves of one shape (the same motion code or none, the
    same axis letters, F on each or on none): what runtime.fast.printed_rows
    writes in one batch. Now and then one F is an error (zero under G1)."""
    motion = draw(st.sampled_from(["", "G1", "G0", "G01"]))
    axes = draw(st.lists(st.sampled_from(AXES), min_size=1, max_size=4, unique=True))
    axes.sort(key=AXES.index)
    with_f = draw(st.integers(0, 3)) == 0
    # now and then the words in another order, the same on every row
    # (G1 Y1 X2, F first): the batch's columns still go to their axes
    order = list(range(len(axes) + with_f))
    if reorder or draw(st.integers(0, 3)) == 0:
        order = draw(st.permutations(order))
    rows = []
    for k in range(draw(st.integers(8, 70))):
        words = ["N%d" % ((line + k) * 10)] if numbered else []
        words += [motion] if motion else []
        values = [letter + draw(numbers(places)) for letter in axes]
        if with_f:
            values.append(draw(feed(places)))
        words += [values[i] for i in order]
        rows.append(" ".join(words))
    return rows


def _text(value: float, places: int) -> str:
    text = "%.*f" % (places, value)
    return "0" if float(text) == 0 and text.startswith("-") and places < 4 else text


@st.composite
def arc_chain(draw, plane: str, numbered: bool, line: int, places: int = 4) -> list:
    """A G0 to a known point, then a chain of arcs in ``plane`` (see the
    module docstring), each starting where the previous one ended."""
    axes, centre_letters, third = PLANES[plane]
    absolute = draw(st.integers(0, 3)) == 0
    lines = []

    # Now and then N on some rows only: rows of the same words, two widths;
    # or now and then a row with the N of the row before (no N change).
    some = numbered and draw(st.integers(0, 3)) == 1
    again = numbered and draw(st.integers(0, 3)) == 2

    def number(k: int) -> list:
        if some and k % 3 == 2:
            return []
        if again and k % 4 == 3:
            k -= 1
        return ["N%d" % ((line + k) * 10)] if numbered else []

    start = [float(_text(draw(st.floats(-300, 300)), places)) for _ in range(2)]
    lines.append(
        " ".join(
            number(0)
            + ["G0 G90 G94 G8" + (" G90.1" if absolute else "")]
            + ["F" + draw(st.sampled_from(["300", "1200.5"]))]
            + [a + _text(v, places) for a, v in zip(axes, start)]
        )
    )
    uniform = draw(st.booleans())  # one row layout: the batch form
    # now and then every arc's words written last first (G2 J.. I.. Y.. X..)
    backwards = draw(st.integers(0, 4)) == 0
    radius_format = draw(st.integers(0, 4)) == 0
    helical = draw(st.booleans())
    with_f = draw(st.integers(0, 3)) == 0
    count = draw(st.integers(8, 40) if uniform else st.integers(1, 12))
    # Now and then one arc of the chain is an error rs274 reports (after
    # it, the program ends): which arc, and which error.
    errors = {}
    if draw(st.integers(0, 7)) == 5:  # not 0: the generator's favourite
        errors[draw(st.integers(0, count - 1))] = draw(st.integers(0, 3))
    after_line = False
    for k in range(count):
        if not uniform:
            radius_format = draw(st.integers(0, 3)) == 0
            helical = draw(st.integers(0, 2)) == 0
            with_f = draw(st.integers(0, 5)) == 0
        r = draw(
            st.sampled_from(
                [0.002, 0.5, 3.0, 12.5, 250.0, 20000.0]
                if not uniform
                else [2.0, 7.5, 40.0]
            )
        )
        phi = draw(st.sampled_from([0.0, 90.0, 180.0, 270.0, 30.0, 135.0, 200.5]))
        offset = [
            float(_text(r * math.cos(math.radians(phi)), places)),
            float(_text(r * math.sin(math.radians(phi)), places)),
        ]
        centre = [start[0] + offset[0], start[1] + offset[1]]
        radius = math.hypot(*offset)
        sweep = draw(st.sampled_from([0.0, 90.0, 180.0, 45.0, 270.0, 123.4, -60.0]))
        if radius_format and sweep == 0.0:
            sweep = 90.0
        angle = math.atan2(-offset[1], -offset[0]) + math.radians(sweep)
        end = [
            centre[0] + radius * math.cos(angle),
            centre[1] + radius * math.sin(angle),
        ]
        end = [float(_text(v, places)) for v in end] if sweep else list(start)
        error = errors[k] if k in errors else 99
        if error == 0:  # the end off the circle: beyond the spiral tolerance
            end[0] += draw(st.sampled_from([0.05, 0.0282, 0.0283, 3.0]))
        words = number(k + 1)
        clockwise = draw(st.booleans()) if not uniform else k % 2 == 0
        if uniform or k == 0 or after_line or draw(st.integers(0, 3)):
            words.append(
                ("G2" if clockwise else "G3")
                if uniform or draw(st.booleans())
                else ("G02" if clockwise else "G03")
            )
        if uniform or sweep or draw(st.booleans()) or radius_format:
            words += [a + _text(v, places) for a, v in zip(axes, end)]
        if helical:
            words.append(third + _text(draw(st.floats(-50, 50)), places))
        if radius_format:
            if error == 1:  # ends where it starts
                words = (
                    words[: len(words) - 2 - helical]
                    + [a + _text(v, places) for a, v in zip(axes, start)]
                    + words[len(words) - helical :]
                )
            sign = "-" if draw(st.booleans()) else ""
            words.append("R" + sign + _text(radius + 10.0**-places, places))
        else:
            given = centre if absolute else offset
            for letter, value in zip(centre_letters, given):
                if value == 0.0 and not (absolute or uniform) and draw(st.booleans()):
                    continue  # a missing offset is 0
                if absolute and error == 2:
                    continue  # a G90.1 centre needs both words
                words.append(letter + _text(value, places))
        if with_f:
            words.append(
                "F"
                + draw(
                    st.sampled_from(
                        ["500", "1200.5", "75.25", "0"]
                        if error == 3
                        else ["500", "1200.5", "75.25"]
                    )
                )
            )
        if not uniform and draw(st.integers(0, 15)) == 0:
            words.append("P" + draw(st.sampled_from(["2", "3"])))
        if backwards:  # the words after N and the motion code, last first
            lead = [w for w in words if w[0] in "NG"]
            words = lead + words[len(lead) :][::-1]
        lines.append(" ".join(words))
        if not (error == 0 and radius_format):
            start = end if not (radius_format and error == 1) else start
        # a contour's line between arcs, now and then (G0 or G1, one axis
        # or both): the next arc names its motion again
        # (in a uniform chain, a CAM post's G1 of both axes: one more shape)
        after_line = draw(st.integers(0, 3 if uniform else 2)) == 0
        if after_line:
            step = draw(st.sampled_from([(1.5, 0.0), (0.0, -2.25), (3.0, 4.0)]))
            if uniform:
                step = (step[0] + 0.5, step[1] - 0.5)
            start = [float(_text(v + d, places)) for v, d in zip(start, step)]
            moved = [a + _text(v, places) for a, v, d in zip(axes, start, step) if d]
            motion = "G1" if uniform else draw(st.sampled_from(["G1", "G0", "G01"]))
            lines.append(" ".join(number(k + 1) + [motion] + moved))
    if absolute:
        lines.append("G91.1")
    return lines


INTERRUPTIONS = [
    "G4 P0.25",
    "S1500 M3",
    "M8",
    "M9",
    "G17",
    "G18",
    "G19",
    "G91 X1.5",
    "G90",
    "G20",
    "G21",
    "G92 X1 Y2",
    "G92.1",
    "G55",
    "G54",
    "G93",
    "G94",
    "M5",
]

SETUPS = [
    "G21 G90 G17 G94",
    "G20 G90",
    "G21 G90 F600",
    "G91 F300",
    "G10 L2 P1 X5 Y-3 Z1 (G54 offset)",
    "G10 L2 P1 R30",
    "G92 X10 Y10",
    "G0 X1 Y1 Z1 A10",
    "F1000",
    "G8",
    "G7",
]


@st.composite
def cam_programs(draw) -> str:
    """Set-up lines, then one or more runs of move rows (each long enough
    to become a data table in a CAM-sized program: three in four are), with
    the odd interruption between rows."""
    lines = draw(st.lists(st.sampled_from(SETUPS), min_size=0, max_size=3))
    numbered = draw(st.booleans())
    plane = "G17"
    # Most CAM posts write 3 or 4 decimals: such tables are written as the
    # trace prints them (runtime/fast/printed_rows.py); others are not.
    places = draw(st.sampled_from([3, 4, 4, 6]))
    for _ in range(draw(st.integers(1, 3))):
        for _ in range(draw(st.integers(8, 40))):
            if draw(st.integers(0, 25)) == 0:
                lines.append(draw(st.sampled_from(INTERRUPTIONS)))
                plane = lines[-1] if lines[-1] in PLANES else plane
            elif draw(st.integers(0, 12)) == 0:
                lines.extend(draw(same_shape_rows(numbered, len(lines) + 1, places)))
            elif draw(st.integers(0, 10)) == 0:
                lines.extend(draw(arc_chain(plane, numbered, len(lines) + 1, places)))
            else:
                after_arc = bool(lines) and ARC.search(lines[-1]) is not None
                row = move_row(numbered, len(lines) + 1, plane, after_arc, places)
                lines.append(draw(row))
        if draw(st.booleans()):
            lines.append(draw(st.sampled_from(INTERRUPTIONS)))
            plane = lines[-1] if lines[-1] in PLANES else plane
    lines.append("M2")
    text = "\n".join(lines) + "\n"
    return cam_sized(text) if draw(st.integers(0, 3)) else text


@st.composite
def reordered_row_programs(draw) -> str:
    """Runs of rows of one shape whose words come in an order of their own
    (G1 Y1 X2, Z A X F), in a CAM-sized program: each run is one batch of
    runtime/fast/printed_rows.py or runtime.fast.rows.straight_batch."""
    lines = [draw(st.sampled_from(["G21 G90 F500", "G20 G90 F40", "G21 G91 F500"]))]
    numbered = draw(st.booleans())
    places = draw(st.sampled_from([3, 4, 4, 6]))
    for _ in range(draw(st.integers(1, 3))):
        lines.extend(
            draw(same_shape_rows(numbered, len(lines) + 1, places, reorder=True))
        )
    lines.append("M2")
    return cam_sized("\n".join(lines) + "\n")


@st.composite
def arc_programs(draw) -> str:
    """Units, a plane and a feed rate, then chains of arcs (`arc_chain`) with
    straight moves, plane changes and the odd interruption between them;
    three in four CAM-sized (their runs of rows become tables)."""
    plane = draw(st.sampled_from(list(PLANES)))
    units = draw(st.sampled_from(["G21", "G21", "G20"]))
    lines = ["%s %s F%s" % (units, plane, draw(st.sampled_from(["300", "1200.5"])))]
    numbered = draw(st.booleans())
    places = draw(st.sampled_from([3, 4, 4, 6]))
    for _ in range(draw(st.integers(1, 4))):
        lines.extend(draw(arc_chain(plane, numbered, len(lines) + 1, places)))
        choice = draw(st.integers(0, 3))
        if choice == 0:
            plane = draw(st.sampled_from(list(PLANES)))
            lines.append(plane)
        elif choice == 1:
            lines.append("G1 " + PLANES[plane][2] + draw(numbers(places)))
            for _ in range(draw(st.integers(1, 10))):
                lines.append(
                    draw(move_row(numbered, len(lines) + 1, plane, True, places))
                )
        elif choice == 2:
            lines.append(draw(st.sampled_from(INTERRUPTIONS)))
            plane = lines[-1] if lines[-1] in PLANES else plane
    lines.append("M2")
    text = "\n".join(lines) + "\n"
    return cam_sized(text) if draw(st.integers(0, 3)) else text


# -- CAM text with odd lines: the edges of the parser's fast lane --------------
#
# ngc2py/rowrun.py recognises whole regions of row lines at once (by each
# line's template) and leaves every other line to the line reader. These
# programs mix long stretches of rows with the lines it must leave alone or
# read exactly as the line reader does: comments, parameters, unreadable
# numbers, N words anywhere, blanks and tabs, lower case, block delete, CR
# line ends and lone CRs, trailing blanks, lines too long for rs274's
# buffer, checked values (negative F/S, H L T, invalid or conflicting G/M
# codes), repeated words, O-words, NUL bytes and non-ASCII text.

#: Lines a stretch of rows may meet that rs274 runs without failing.
HARMLESS_ODD = [
    "",
    "   ",
    "\t",
    "(a comment)",
    "G1 X1 (trailing comment)",
    "G1 X1 ; semicolon comment",
    "#1 = 2.5",
    "G1 X#1",
    "#<depth> = -0.5",
    "G1 Z#<depth>",
    "G1 X[1 + 2]",
    "N0012 G1 X1.5",
    "n5 x1 y2",
    "N10.5 X1",
    "G 1 X 1 . 5",
    "X 1.25",
    "\tG1\tX1\tY2",
    "g1 x-1.5 y+.5",
    "/G1 X9",
    "G1 /X1",
    "G1 X1  ",
    "G1 X1\t",
    "G1 X1\r",
    "G1 X1\rY2",
    "F-0",
    "S-0",
    "F+5.",
    "G80 G1 X1",
    "X007.5 Y-00.25",
    "X.5 Y-.5 Z5.",
    "X1.23456 Y7.654321",
    "X123456789012 Y0.0001",
    "X-0 Y-0.0",
    "G1 X1\0Y$",
    "(é comment)",
    "T1 M6",
    "H1",
    "M3 S1000",
    "M5",
    "G4 P0.1",
    "G17 G90",
    "D1 E2",
    "G1 X1 @1 ^30",
    "N5",
]

#: Lines rs274 fails on (reading or running them).
FAILING_ODD = [
    "X1.2.3",
    "X--1",
    "G1 X",
    "G1 X.",
    "N-5 X1",
    "N.5 X1",
    "G1 N10 X1",
    "G1 X1 X2",
    "G1 G0 X1",
    "G4.5",
    "G99 X1",
    "M3 M4",
    "F-5",
    "S-1",
    "T1.5",
    "T-1",
    "H-2",
    "L-1",
    "X1 M98",
    "U1",
    "O100",
    "o1 if [1]",
    "G1 X1 Y2 $",
    "G1 X1 (open",
    "G1 X1 ((nested))",
    "x" * 253,
    "G1 X" + "1" * 251,
    "G1 X" + "1" * 249,
    "(" + "c" * 251 + ")",
    "%",
]


@st.composite
def odd_lines(draw, failing: bool) -> str:
    """One odd line (a failing one only when ``failing``)."""
    if failing and draw(st.integers(0, 3)) == 0:
        return draw(st.sampled_from(FAILING_ODD))
    return draw(st.sampled_from(HARMLESS_ODD))


@st.composite
def odd_cam_programs(draw, failing: bool = True) -> str:
    """Set-up lines, stretches of rows (N numbers, spacing, letter case and
    line ends varied per stretch) and odd lines between and inside them;
    CR LF line ends now and then, a ``%`` demarcation now and then."""
    lines = draw(st.lists(st.sampled_from(SETUPS[:4]), min_size=1, max_size=2))
    places = draw(st.sampled_from([3, 4, 6]))
    for _ in range(draw(st.integers(1, 4))):
        numbered = draw(st.integers(0, 3)) == 0
        style = draw(st.sampled_from(["", "", "lower", "tight", "spaced"]))
        for _ in range(draw(st.integers(4, 40))):
            if draw(st.integers(0, 12)) == 0:
                lines.append(draw(odd_lines(failing)))
                continue
            row = draw(move_row(numbered, len(lines) + 1, "G17", True, places))
            if ARC.search(row):
                row = re.sub(r"\bG0?[23]\b", "G1", row)
                row = re.sub(r" [IJKR]\S*", "", row)
            if style == "lower":
                row = row.lower()
            elif style == "tight":
                row = row.replace(" ", "")
            elif style == "spaced":
                row = "  " + row.replace(" ", " \t")
            lines.append(row)
    lines.append("M2")
    ends = draw(st.sampled_from(["\n", "\n", "\n", "\r\n"]))
    text = ends.join(lines) + ends
    if draw(st.integers(0, 5)) == 0:
        text = "%" + ends + text + "%" + ends
    return text


@st.composite
def commented(draw, programs):
    """A program with plain comments after some of its lines' words (what
    hand-written programs and some posts write: ``G1 X1 Y2 (pass 3)``)."""
    lines = draw(programs).split("\n")
    for k, line in enumerate(lines):
        if line.strip() and "(" not in line and ";" not in line and draw(st.booleans()):
            lines[k] = line + draw(st.sampled_from([" (pass %d)" % k, "(x)", " ( )"]))
    return "\n".join(lines)


@st.composite
def hand_drilling(draw):
    """A hole at a time without canned cycles, as simple posts and people
    write it: G0 over the hole, G1 down, a G4 pause (any P: 0, negative,
    rs274's "no P" -1), G0 up, with an N now and then and lines that change
    the state between holes (G91, G20, a cycle, cutter compensation)."""
    lines = ["G21 G90 G17 F200"]
    for k in range(draw(st.integers(2, 12))):
        x, y = draw(st.integers(0, 99)), draw(st.integers(0, 99))
        lines += ["G0 X%d.5 Y%d" % (x, y), "G1 Z-%d.25" % draw(st.integers(1, 9))]
        p = draw(st.sampled_from(["0.5", "0", "-0.25", "-1", "-1.0", "2", "0.0001"]))
        n = draw(st.sampled_from(["", "", "N%d " % (10 * k)]))
        lines += [n + "G4 P" + p, "G0 Z2"]
        lines += draw(
            st.sampled_from(
                [
                    [],
                    [],
                    ["G91"],
                    ["G90"],
                    ["G20"],
                    ["G21"],
                    ["G81 X1 Y1 Z-1 R1"],
                    ["G80"],
                    ["G41 D0"],
                    ["G40"],
                    ["M3 S100"],
                ]
            )
        )
    return cam_sized("\n".join(lines + ["M2"]) + "\n")


@st.composite
def restating(draw, programs):
    """A program whose moves and arcs restate modes now and then, as some
    posts write them on every line (``G90 G1 X1 Y2``, ``G17 G2 X.. R..``),
    with lines that change those modes among them (G91, G18, G90, G17)."""
    lines = draw(programs).split("\n")
    prefixes = ["G90 ", "G17 ", "G90 G17 ", "G17 G90 "]
    # or a post writes the same on every line (runs of rows of one shape)
    every = draw(st.sampled_from([None, None] + prefixes))
    out = []
    for line in lines:
        words = line.split()
        if words and words[0][:1] in "GXYZ" and "M2" not in line:
            if every is not None:
                line = every + line
            elif draw(st.booleans()):
                line = draw(st.sampled_from(prefixes)) + line
        out.append(line)
        if draw(st.integers(0, 30)) == 0:
            out.append(draw(st.sampled_from(["G91", "G90", "G18", "G17"])))
    return "\n".join(out)
