"""Hypothesis strategies that write G-code programs for differential testing.

``valid_programs()`` writes programs that rs274 runs to the end: motion with
arcs built so they are always geometrically valid, parameters (numbered,
named local, named global) and expressions that cannot fail (no division by
a value that may be zero, no roots of negatives), subroutines with arguments
and return values, loops with bounded iteration counts, comments of every
active kind, modal changes (units, distance mode, planes, coordinate
systems, offsets, spindle, coolant, path control), drilling canned cycles in
every plane with the lines that repeat them, threading, probing, splines,
lathe cycles, cutter compensation, and the rest of the language: tool
changes and length offsets, G10 L1/L10/L11, M19, override switches,
digital/analog I/O and M66, M70-M73, (py,...) comments, Fanuc M98 calls
(also as a computed M value).

``whole_language_programs()`` writes job-shop programs with their own tool
table (pockets under compensation, drilling patterns, lathe profiles,
probing, splines, modal subroutines, I/O), written from the language's
chapters rather than from ngc2py; ``broken_whole_language_programs()``
breaks one of their lines.

``invalid_programs()`` takes such a program and breaks one line: junk
characters, unbalanced brackets, unknown letters, repeated words, bad or
mismatched O-words, undefined parameters, arithmetic errors, broken canned
cycles, truncation. The
result may or may not be an error in rs274 -- the point is that ngc2py must
behave the same either way.

Everything is drawn through Hypothesis, so examples shrink to small programs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import List

from hypothesis import strategies as st

from long_programs import RandomChooser, error_program, long_program

# --------------------------------------------------------------------------
# numbers and expressions
# --------------------------------------------------------------------------


def fmt(value: float, style: int = 0) -> str:
    """A number in one of several legal spellings."""
    text = f"{value:.4f}".rstrip("0")
    if text.endswith("."):
        text = text[:-1] if style % 3 == 0 else text  # "2" or "2."
    if text in ("-0", "-0."):
        text = "0"
    if style == 1 and text.startswith("0.") and len(text) > 2:
        text = text[1:]  # ".5"
    elif style == 1 and text.startswith("-0.") and len(text) > 3:
        text = "-" + text[2:]  # "-.5"
    elif style == 2 and not text.startswith("-"):
        text = "+" + text
    elif style == 4 and "." in text:
        text = text + "00"  # trailing zeros
    return text


@st.composite
def numbers(draw, lo: int = -500, hi: int = 500, scale: int = 10) -> str:
    value = draw(st.integers(lo, hi)) / scale
    return fmt(value, draw(st.integers(0, 5)))


@dataclass
class Scope:
    """What the program may read safely at this point."""

    numbered: List[int] = field(default_factory=list)  # set #n
    named: List[str] = field(default_factory=list)  # set #<name> (local or _global)
    args: int = 0  # inside a subroutine: #1..#args were passed


def _leaf(draw, scope: Scope) -> str:
    choices = ["num", "num"]
    if scope.numbered or scope.args:
        choices.append("numbered")
    if scope.named:
        choices.append("named")
    kind = draw(st.sampled_from(choices))
    if kind == "numbered":
        pool = list(scope.numbered) + list(range(1, scope.args + 1))
        return f"#{draw(st.sampled_from(pool))}"
    if kind == "named":
        return f"#<{draw(st.sampled_from(scope.named))}>"
    return draw(numbers(-200, 200, 10))


@st.composite
def expressions(draw, scope: Scope, depth: int = 2) -> str:
    """A bracketed expression that cannot raise an error in rs274."""
    if depth <= 0 or draw(st.integers(0, 3)) == 0:
        inner = _leaf(draw, scope)
        return inner if draw(st.booleans()) else f"[{inner}]"
    a = draw(expressions(scope, depth - 1))
    b = draw(expressions(scope, depth - 1))
    kind = draw(st.integers(0, 9))
    if kind <= 3:
        op = draw(st.sampled_from(["+", "-", "*", "+", "-"]))
        return f"[{a} {op} {b}]"
    if kind == 4:
        divisor = draw(st.sampled_from(["2", "3", "4", "0.5", "7", "-8"]))
        op = draw(st.sampled_from(["/", "MOD", "mod"]))
        return f"[{a} {op} {divisor}]"
    if kind == 5:
        op = draw(st.sampled_from(["EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "XOR", "eq", "lt"]))
        return f"[{a} {op} {b}]"
    if kind == 6:
        fn = draw(st.sampled_from(["ABS", "SIN", "COS", "FIX", "FUP", "ROUND", "abs", "cos"]))
        return f"{fn}[{a}]"
    if kind == 7:
        fn = draw(st.sampled_from(["SQRT", "LN", "EXP"]))
        if fn == "SQRT":
            return f"SQRT[ABS[{a}]]"
        if fn == "LN":
            return f"LN[ABS[{a}] + 1]"
        return f"EXP[[{a}] MOD 5]"
    if kind == 8:
        return f"ATAN[{a}]/[{b}]"
    # bounded power, and asin/acos of a value in range
    fn = draw(st.sampled_from(["pow", "asin", "acos", "neg"]))
    if fn == "pow":
        return f"[[ABS[{a}] MOD 10] ** {draw(st.sampled_from(['2', '3', '0.5', '0']))}]"
    if fn == "neg":
        return f"[-{a}]"
    return f"{fn.upper()}[SIN[{a}]]"


# --------------------------------------------------------------------------
# programs
# --------------------------------------------------------------------------


class Writer:
    """Accumulates lines and the generator state needed to keep them valid."""

    def __init__(self, draw, feed_modes: bool = False):
        self.draw = draw
        #: also write G93/G95 moves and UVW planes (see stmt_modal)
        self.feed_modes = feed_modes
        self.lines: List[str] = []
        self.label = 100
        self.scope = Scope()
        self.dist = 90
        self.subs: List[tuple] = []  # (name, nargs, returns)
        self.depth = 0
        self.fanuc = False  # a Fanuc subroutine O9001 follows the program end
        #: cycles may fail part way (run with -n 0: cycle_programs)
        self.failing = False

    def emit(self, line: str) -> None:
        self.lines.append("  " * self.depth + line)

    def new_label(self) -> int:
        self.label += 1
        return self.label

    def expr(self, depth: int = 2) -> str:
        return self.draw(expressions(self.scope, depth))

    def value(self) -> str:
        """A word value: a plain number, a parameter, or an expression."""
        kind = self.draw(st.integers(0, 4))
        if kind == 0 and (self.scope.numbered or self.scope.named or self.scope.args):
            return _leaf(self.draw, self.scope)
        if kind == 1:
            return self.expr(1)
        return self.draw(numbers())


def _axes(w: Writer, letters: str = "XYZ", at_least: int = 1) -> str:
    chosen = w.draw(st.lists(st.sampled_from(list(letters)), min_size=at_least, max_size=len(letters), unique=True))
    spacing = w.draw(st.sampled_from([" ", "", "  "]))
    return spacing.join(f"{c}{w.value()}" for c in chosen)


def _restore_dist(w: Writer) -> None:
    w.emit(f"G{w.dist}")


def stmt_move(w: Writer) -> None:
    code = w.draw(st.sampled_from(["G0", "G1", "G1", "g1", "G00", "G01"]))
    extra = ""
    if code.lower() in ("g1", "g01") and w.draw(st.booleans()):
        extra = f" F{w.draw(numbers(10, 3000, 1))}"
    letters = w.draw(st.sampled_from(["XYZ", "XY", "XYZA", "XYZABC", "Z"]))
    w.emit(f"{code} {_axes(w, letters)}{extra}")


def stmt_arc(w: Writer) -> None:
    """An arc that is valid wherever the tool is: written in G91."""
    plane = w.draw(st.sampled_from([17, 18, 19]))
    a1, a2 = {17: ("X", "Y"), 18: ("Z", "X"), 19: ("Y", "Z")}[plane]
    c1, c2 = {17: ("I", "J"), 18: ("K", "I"), 19: ("J", "K")}[plane]
    lin = {17: "Z", 18: "Y", 19: "X"}[plane]
    r = w.draw(st.integers(5, 400)) / 10
    alpha = math.radians(w.draw(st.integers(0, 359)))
    beta = math.radians(w.draw(st.integers(0, 359)))
    i, j = -r * math.cos(alpha), -r * math.sin(alpha)
    d1 = i + r * math.cos(beta)
    d2 = j + r * math.sin(beta)
    code = w.draw(st.sampled_from(["G2", "G3"]))
    words = f"{a1}{d1:.6f} {a2}{d2:.6f}"
    if w.draw(st.integers(0, 3)) == 0:
        words += f" {lin}{w.draw(numbers(-50, 50, 10))}"  # helix
    chord = math.hypot(d1, d2)
    if w.draw(st.integers(0, 15)) == 0:
        # an end within the radius tolerance of the start, R 0 or tiny: rs274
        # divides 0 by 0 for an R 0 centre (it prints -nan) and takes a tiny
        # R as a semicircle
        tiny = w.draw(st.sampled_from(["0.000001", "-0.00002", "0.00001"]))
        rr = w.draw(st.sampled_from(["0", "-0", "0.00001", "-0.000005"]))
        w.emit(f"G{plane} G91 {code} {a1}{tiny} R{rr}")
    elif chord > 1.0 and w.draw(st.integers(0, 3)) == 0:
        # radius format, R a bit more than half the chord (either sign)
        rr = chord / 2 + w.draw(st.integers(1, 50)) / 10
        sign = w.draw(st.sampled_from(["", "-"]))
        w.emit(f"G{plane} G91 {code} {words} R{sign}{rr:.4f}")
    else:
        turns = ""
        if w.draw(st.integers(0, 5)) == 0:
            turns = f" P{w.draw(st.integers(1, 3))}"
        w.emit(f"G{plane} G91 {code} {words} {c1}{i:.6f} {c2}{j:.6f}{turns}")
    _restore_dist(w)
    if plane != 17:
        w.emit("G17")


def stmt_assign(w: Writer) -> None:
    kind = w.draw(st.integers(0, 3))
    value = w.expr(2)
    if kind == 0:
        n = w.draw(st.integers(31, 60))
        target = f"#{n}"
        new = ("numbered", n)
    elif kind == 1 and w.depth == 0 and not w.scope.args:
        n = w.draw(st.integers(1, 30))
        target = f"#{n}"
        new = ("numbered", n)
    else:
        name = w.draw(st.sampled_from(["depth", "x0", "step", "_safe", "_count", "rad", "Feed Rate", "_a.b"]))
        target = f"#<{name}>"
        new = ("named", name.lower().replace(" ", ""))
    # sometimes two settings on one line (line-buffered semantics)
    if w.draw(st.integers(0, 4)) == 0 and w.scope.numbered:
        other = w.draw(st.sampled_from(w.scope.numbered))
        w.emit(f"{target} = {value} #{other} = [#{other} + 1]")
    else:
        w.emit(f"{target} = {value}")
    if new[0] == "numbered":
        if new[1] not in w.scope.numbered:
            w.scope.numbered.append(new[1])
    elif new[1] not in w.scope.named:
        w.scope.named.append(new[1])


def stmt_comment(w: Writer) -> None:
    kind = w.draw(st.integers(0, 5))
    refs = []
    if w.scope.numbered:
        refs.append(f"#{w.draw(st.sampled_from(w.scope.numbered))}")
    if w.scope.named:
        refs.append(f"#<{w.draw(st.sampled_from(w.scope.named))}>")
    refs.append("#<_x>")
    ref = w.draw(st.sampled_from(refs))
    text = w.draw(st.sampled_from(["roughing pass", "Check Clamp", "depth=", "a;b", "x y  z"]))
    if kind == 0:
        w.emit(f"({text})")
    elif kind == 1:
        w.emit(f"(MSG, {text})")
    elif kind == 2:
        w.emit(f"(debug, {text} {ref})")
    elif kind == 3:
        w.emit(f"(print, {text} {ref})")
    elif kind == 4:
        w.emit(f"G0 {_axes(w, 'XY')} ({text}) ; trailing {text}")
    else:
        w.emit(f"(one) (DEBUG,{ref} last one wins)")


def stmt_modal(w: Writer) -> None:
    # Kinds 12-14 only when asked for: adding them to every program would
    # change every derandomised example of the existing tests.
    kind = w.draw(st.integers(0, 14 if w.feed_modes else 11))
    if kind == 0:
        w.emit(w.draw(st.sampled_from(["G20", "G21"])))
    elif kind == 1:
        w.dist = w.draw(st.sampled_from([90, 91]))
        w.emit(f"G{w.dist}")
    elif kind == 2:
        w.emit(w.draw(st.sampled_from(["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"])))
    elif kind == 3:
        p = w.draw(st.integers(0, 9))
        w.emit(f"G10 L2 P{p} {_axes(w, 'XYZ')}")
    elif kind == 4:
        w.emit(f"G92 {_axes(w, 'XYZ')}")
    elif kind == 5:
        w.emit(w.draw(st.sampled_from(["G92.1", "G92.2", "G92.3", "G61", "G61.1", "G64", "G64 P0.01"])))
    elif kind == 6:
        # $ (spindle selection): rs274 keeps it as a truncated int; one
        # spindle, so 0 or -1 run (these programs must run to their end;
        # other numbers fail at their step: invalid_programs, golden/spindle).
        dollar = w.draw(st.sampled_from(["", "", "", " $0", " $-1", " $0.5", " $-0.9"]))
        w.emit(f"S{w.draw(numbers(0, 5000, 1))} {w.draw(st.sampled_from(['M3', 'M4', 'M5']))}{dollar}")
    elif kind == 7:
        w.emit(w.draw(st.sampled_from(["M7", "M8", "M9"])))
    elif kind == 8:
        w.emit(f"G4 P{w.draw(numbers(0, 30, 10))}")
    elif kind == 9:
        w.emit(w.draw(st.sampled_from(["G43.1 Z1.5", "G49", "T0 M6", "M61 Q0", "G90.1", "G91.1", "G94 F200"])))
    elif kind == 10:
        if w.dist == 90:
            w.emit(f"G1 @{w.draw(numbers(0, 300, 10))} ^{w.draw(numbers(-360, 360, 1))} F100")
        else:
            w.emit("G90 G53 G0 X0" if w.draw(st.booleans()) else "G28.1")
            _restore_dist(w)
    elif kind == 11:
        w.emit(w.draw(st.sampled_from(["G52 X1 Y2", "G52 X0 Y0", "G30.1", "M0", "M1", "M60"])))
    elif kind == 12:
        # inverse time: every feed move needs its own F (minutes^-1)
        w.emit(f"G93 G1 {_axes(w, 'XYZ')} F{w.draw(numbers(1, 50, 1))}")
        w.emit("G94 F200")
    elif kind == 13:
        # feed per revolution needs a turning spindle
        w.emit(f"S{w.draw(numbers(100, 5000, 1))} M3")
        w.emit(f"G95 G1 {_axes(w, 'XYZ')} F{w.draw(numbers(1, 20, 100))}")
        w.emit("G94 F200")
    else:
        # the UVW planes (straight moves only: the arcs choose their plane)
        w.emit(w.draw(st.sampled_from(["G17.1", "G18.1", "G19.1"])))
        w.emit(f"G1 {_axes(w, 'XYZ')}")
        w.emit("G17")


#: Canned cycles: the plane's in-plane letters and its hole-axis letter.
_CYCLE_PLANES = {17: ("XY", "Z"), 18: ("ZX", "Y"), 19: ("YZ", "X")}


def stmt_cycle(w: Writer) -> None:
    """A drilling cycle that rs274 runs: R at or above the bottom, the P, Q
    or I/J/K the cycle needs, the spindle turning the way it must (M codes
    run before G codes on a line), no L with G74; then maybe lines with only
    in-plane words, which repeat the cycle with the same R and depth."""
    plane = w.draw(st.sampled_from([17, 17, 18, 19]))
    in_plane, hole = _CYCLE_PLANES[plane]
    code = w.draw(st.sampled_from(["G81", "G82", "G83", "G73", "G84", "G74", "G85", "G86", "G87", "G88", "G89"]))
    dist = w.dist if w.draw(st.integers(0, 3)) else 181 - w.dist  # 90 <-> 91
    r = w.draw(st.integers(-30, 50)) / 10
    depth = w.draw(st.integers(1, 40)) / 10
    bottom = -depth if dist == 91 else r - depth
    words = []
    if dist == 90 and plane == 17 and w.draw(st.integers(0, 4)) == 0:
        words.append(f"@{w.draw(numbers(0, 100, 10))} ^{w.draw(numbers(-360, 360, 1))}")
    else:
        words.append(_axes(w, in_plane, at_least=0))
    words += [f"{hole}{fmt(bottom)}", f"R{fmt(r)}"]
    if code in ("G82", "G86", "G88", "G89") or (code in ("G74", "G84") and w.draw(st.booleans())):
        words.append(f"P{w.draw(numbers(0, 20, 10))}")
    # a cycle that fails after its first moves: the spindle the wrong way or
    # stopped, a Q of zero or less
    fails = w.failing and w.draw(st.integers(0, 2)) == 0
    if code in ("G73", "G83"):
        q = w.draw(st.integers(-10, 0)) if fails else w.draw(st.integers(2, 20))
        words.append(f"Q{fmt(q / 10)}")
    if code == "G87":
        words += [f"{letter}{w.draw(numbers(-30, 30, 10))}" for letter in "IJK"]
    if code != "G74" and w.draw(st.integers(0, 2)) == 0:
        words.append(f"L{w.draw(st.integers(1, 3))}")
    prefix = []
    if code in ("G74", "G84", "G86", "G87", "G88"):
        clockwise = code == "G84" or (code != "G74" and w.draw(st.booleans()))
        turning = "M3" if clockwise != (fails and code in ("G74", "G84")) else "M4"
        if fails and code not in ("G74", "G84"):
            turning = "M5"
        prefix.append(f"S{w.draw(numbers(0, 2000, 1))} {turning}")
    if w.draw(st.booleans()):
        prefix.append(w.draw(st.sampled_from(["G98", "G99"])))
    w.emit(" ".join(prefix + [f"G{plane}", f"G{dist}", code] + [x for x in words if x]))
    if fails:
        # where the failed line left the current point, as the next lines see it
        w.emit("(debug, #5420 #5421 #5422)")
    for _ in range(w.draw(st.integers(0, 2))):
        w.emit(_axes(w, in_plane))  # the same cycle again, elsewhere
    if w.draw(st.booleans()):
        w.emit("G80")
    if dist != w.dist:
        _restore_dist(w)
    if plane != 17:
        w.emit("G17")


def stmt_codes(w: Writer) -> None:
    """Tool table, offsets, spindle orient, override switches, I/O, modal
    state save/restore, Python comments (the default tool table holds tools
    1, 2, 3 and 99999)."""
    kind = w.draw(st.integers(0, 9))
    tool = w.draw(st.integers(0, 3))
    if kind == 0:
        w.emit(w.draw(st.sampled_from([
            f"T{tool} M6", f"T{tool} M6 G43", "G43", f"G43 H{tool}", f"G43.2 H{max(tool, 1)}",
            "G49", f"M61 Q{tool}", f"T{tool}", f"G43.1 Z{w.draw(numbers())}",
            # (G43.2 with axis words fails in rs274 2.9: "Requested tool -1")
            f"G43.1 X{w.draw(numbers())}",
            # refused while a tool is loaded (as rs274's own spindle slot
            # says: an M6 on the same line not yet, M61 Q0 not cleared)
            "G10 L0", f"T{tool} M6 G10 L0",
        ])))
    elif kind == 1:
        letter = w.draw(st.sampled_from(["Z", "X", "Z", "R", "I", "J"]))
        level = w.draw(st.sampled_from(["1", "10", "11"]))
        words = f"{letter}{w.draw(numbers(0, 100, 10))}"
        if level == "1" and w.draw(st.booleans()):
            words += f" Q{w.draw(st.integers(0, 9))}"
        w.emit(f"G10 L{level} P{max(tool, 1)} {words}")
        if w.draw(st.booleans()):
            # an edit of the loaded tool is copied to the spindle entry,
            # which #<_selected_pocket> reads before any T word
            w.emit("(debug, #<_selected_pocket> #<_current_pocket> #5400 #5403)")
    elif kind == 2:
        w.emit(f"M19 R{w.draw(st.integers(0, 360))} P{w.draw(st.integers(0, 2))}"
               f" Q{w.draw(st.integers(1, 9))}")
    elif kind == 3:
        code = w.draw(st.sampled_from(["M48", "M49", "M50", "M51", "M52", "M53"]))
        if code not in ("M48", "M49") and w.draw(st.booleans()):
            code += f" P{w.draw(st.integers(0, 1))}"
        w.emit(code)
    elif kind == 4:
        index = w.draw(st.integers(0, 3))
        w.emit(w.draw(st.sampled_from([
            f"M62 P{index}", f"M63 P{index}", f"M64 P{index}", f"M65 P{index}",
            f"M66 P{index} L0", f"M66 E{index} L0", f"M66 P{index} L{w.draw(st.integers(1, 4))} Q2",
            f"M67 E{index} Q{w.draw(numbers())}", f"M68 E{index} Q{w.draw(numbers())}",
        ])))
        w.emit("(debug, input #5399)")
    elif kind in (5, 6):
        # save, change some modes, restore (M72 must find a saved state)
        w.emit("M70")
        for _ in range(w.draw(st.integers(1, 3))):
            w.emit(w.draw(st.sampled_from([
                "G20", "G21", "G18", "G19", "G91", "G93", f"F{w.draw(numbers(1, 900, 1))}",
                f"S{w.draw(numbers(0, 5000, 1))} M4", "M3", "M5", "M7", "M8", "M9",
                "G64 P0.05 Q0.02", "G61", "G61.1", "M50 P0", "M52 P1", "M53 P0",
                "G55", "G43.1 Z1", "G49", "G91.1", "G98", "G8", "G7", "G96 S100", "G97",
            ])))
        w.emit(w.draw(st.sampled_from(["M72", "M72", "M72 G0 X1", "M71"])))
        # back to the modes the other statements assume (G94 zeroes F)
        w.emit(f"G17 G90 G94 G21 G54 G91.1 G97 G8 F{w.draw(numbers(50, 1000, 1))}")
        w.dist = 90
    elif kind == 7:
        w.emit(w.draw(st.sampled_from([
            "(py,pyvar = 1)", "(PY,other = 2 * 3 + 1)", "(pyrun,ignored)", "(pyreload)",
            "(py,pyvar = 1)\n(py,total = pyvar + 1)",
            # a line beginning exactly ';py,' runs as (py,...); others are plain
            ";py,semi = (2 + 1) * 2", ";py,semi = 1\n(py,twice = semi * 2)",
            ";py,oops = nowhere", "  ;py,unread = nowhere", ";PY,unread = nowhere",
            "G0 X1 ;py,unread = nowhere",
            # checks of the interpreter's state, as LinuxCNC's tests write them
            ";py,from interpreter import *\n;py,assert this.call_level == 0",
            ";py,assert this.call_level == 0",  # (this is bound without import)
            ";py,from interpreter import *\n;py,assert equal(this.params[5400], 0)",
            "(py,import interpreter)\n;py,assert interpreter.this.params[5220] == 1",
            ";py,from interpreter import *\n;py,assert this.params[\"_metric\"] == 1",
        ])))
    elif kind == 8:
        # a Fanuc call: M98 P9001 (the sub follows the program end), also
        # as a computed M value
        w.fanuc = True
        if w.draw(st.booleans()):
            times = w.draw(st.integers(0, 2))
            w.emit(f"M98 P9001 L{times}" if w.draw(st.booleans()) else "M98 P9001")
            if times == 0 and w.draw(st.integers(0, 3)) == 0:
                # M99 in the frame M98 L0 entered: back to the line after
                # the M98, one level up; met again at level 0, the end
                w.emit("G91 G0 Y1")
                w.emit("G90")
                w.emit("M99")
        else:
            w.emit("#9 = 98")
            w.emit("M#9 P9001")
    else:
        w.emit(w.draw(st.sampled_from(["M71", "(debug, #<_current_tool> #<_current_pocket> "
                                       "#<_selected_tool> #<_selected_pocket> #5400 #5403)"])))


def _body(w: Writer, size: int) -> None:
    """Statements that may not run (untaken branch, zero-trip loop): what
    they assign is not counted as defined afterwards."""
    saved = (list(w.scope.numbered), list(w.scope.named))
    n = w.draw(st.integers(1, size))
    for _ in range(n):
        stmt(w, nested=True)
    w.scope.numbered, w.scope.named = saved


def stmt_if(w: Writer) -> None:
    lab = w.new_label()
    w.emit(f"o{lab} if [{w.expr(2)}]")
    w.depth += 1
    _body(w, 2)
    w.depth -= 1
    for _ in range(w.draw(st.integers(0, 2))):
        w.emit(f"o{lab} elseif [{w.expr(2)}]")
        w.depth += 1
        _body(w, 2)
        w.depth -= 1
    if w.draw(st.booleans()):
        w.emit(f"o{lab} else")
        w.depth += 1
        _body(w, 2)
        w.depth -= 1
    w.emit(f"o{lab} endif")


def stmt_loop(w: Writer) -> None:
    lab = w.new_label()
    count = w.draw(st.integers(0, 4))
    kind = w.draw(st.integers(0, 2))
    var = f"_i{lab}"
    if kind == 0:
        w.emit(f"#<{var}> = 0")
        w.scope.named.append(var)
        w.emit(f"o{lab} while [#<{var}> LT {count}]")
        w.depth += 1
        w.emit(f"#<{var}> = [#<{var}> + 1]")
        _body(w, 2)
        if w.draw(st.integers(0, 3)) == 0:
            w.emit(f"o{lab}1 if [#<{var}> GE 2]")
            w.emit(f"  o{lab} {w.draw(st.sampled_from(['break', 'continue']))}")
            w.emit(f"o{lab}1 endif")
        w.depth -= 1
        w.emit(f"o{lab} endwhile")
    elif kind == 1:
        w.emit(f"#<{var}> = 0")
        w.scope.named.append(var)
        w.emit(f"o{lab} do")
        w.depth += 1
        w.emit(f"#<{var}> = [#<{var}> + 1]")
        _body(w, 2)
        w.depth -= 1
        w.emit(f"o{lab} while [#<{var}> LT {count}]")
    else:
        w.emit(f"o{lab} repeat [{count}]")
        w.depth += 1
        _body(w, 2)
        w.depth -= 1
        w.emit(f"o{lab} endrepeat")


def stmt_call(w: Writer) -> None:
    if not w.subs:
        stmt_move(w)
        return
    name, nargs, returns = w.draw(st.sampled_from(w.subs))
    given = w.draw(st.integers(0, nargs))
    args = " ".join(f"[{w.expr(1)}]" for _ in range(given))
    w.emit(f"o{name} call {args}".rstrip())
    if returns and w.draw(st.booleans()):
        w.emit("G0 X[#<_value> MOD 100]")
    if w.draw(st.integers(0, 3)) == 0:
        w.emit("(debug, value #<_value> returned #<_value_returned> level #<_call_level>)")


def stmt_thread(w: Writer) -> None:
    """G33, G33.1 or G76 with the spindle turning (rs274 refuses them otherwise)."""
    w.emit(f"S{w.draw(numbers(100, 2000, 1))} {w.draw(st.sampled_from(['M3', 'M4']))}")
    kind = w.draw(st.integers(0, 3))
    if kind == 0:
        w.emit(f"G33 {_axes(w, 'XZ')} K{w.draw(numbers(1, 40, 10))}")
    elif kind == 1:
        scale = f" I{w.draw(numbers(0, 40, 10))}" if w.draw(st.booleans()) else ""
        w.emit(f"G33.1 Z{w.value()} K{w.draw(numbers(1, 30, 10))}{scale}")
    else:
        # G76 needs I non-zero, J > 0 and K > J; the other words are optional.
        j = w.draw(st.integers(1, 20)) / 100
        k = j + w.draw(st.integers(1, 150)) / 100
        i = w.draw(st.sampled_from([-1, 1])) * w.draw(st.integers(1, 30)) / 10
        words = [f"P{w.draw(numbers(2, 40, 10))}", f"Z{w.value()}", f"I{fmt(i)}", f"J{fmt(j)}", f"K{fmt(k)}"]
        optional = {
            "Q": numbers(0, 600, 10),
            "R": numbers(5, 30, 10),
            "H": st.integers(0, 2).map(str),
            "E": numbers(-10, 30, 10),
            "L": st.integers(0, 3).map(str),
        }
        for letter, values in optional.items():
            if w.draw(st.booleans()):
                words.append(f"{letter}{w.draw(values)}")
        words = w.draw(st.permutations(words))
        diameter = w.draw(st.integers(0, 3)) == 0
        if diameter:
            w.emit("G7")  # X, I, J and K are diameters
        w.emit("G76 " + " ".join(words))
        if diameter:
            w.emit("G8")
    if w.draw(st.booleans()):
        w.emit("M5")


def stmt_probe(w: Writer) -> None:
    """G38.2-G38.5 (the program's feed rate is never zero), then the results."""
    code = w.draw(st.sampled_from(["G38.2", "G38.3", "G38.4", "G38.5"]))
    if code in ("G38.2", "G38.4"):
        # These refuse to probe towards the current point: move for sure.
        w.emit(f"G91 {code} Z-{w.draw(numbers(1, 100, 10))} {_axes(w, 'XYA', 0)}".rstrip())
        _restore_dist(w)
    else:
        w.emit(f"{code} {_axes(w, 'XYZ')}")
    w.emit("(debug, #5061 #5062 #5063 #5064 #5070 #5420 #5421 #5422)")


def stmt_spline(w: Writer) -> None:
    """G5, G5.1, or a G5.2 ... G5.3 NURBS, in the XY plane without Z."""
    kind = w.draw(st.integers(0, 2))
    if kind == 0:
        ij = f"I{w.value()} J{w.value()} " if w.draw(st.integers(0, 3)) else ""
        w.emit(f"G5 {ij}P{w.value()} Q{w.value()} X{w.value()} Y{w.value()}")
    elif kind == 1:
        w.emit(f"G5.1 I{w.value()} J{w.value()} X{w.value()} Y{w.value()}")
    else:
        order = w.draw(st.integers(3, 5))
        first = f"G5.2 X{w.value()} Y{w.value()} P{w.draw(numbers(1, 30, 10))}"
        w.emit(first + (f" L{order}" if order > 3 else ""))
        for _ in range(w.draw(st.integers(order - 1, order + 2))):
            w.emit(f"X{w.value()} Y{w.value()} P{w.draw(numbers(1, 30, 10))}")
        w.emit("G5.3")
    w.emit("(debug, #5420 #5421)")


def stmt_lathe_cycle(w: Writer) -> None:
    """A G70/G71/G72 cycle and its profile subroutine, defined just before it.

    The profile runs with X growing and Z falling, in diagonal or stepped
    pieces long enough for the small corner fillets (A) and chamfers (C).
    rs274 only allows a definition where it is read once, so cycles are
    written at the top level only.
    """
    if w.depth or w.scope.args:
        stmt_move(w)
        return
    label = 9000 + w.new_label()
    cycle = w.draw(st.sampled_from(["G70", "G71", "G71.1", "G71.2", "G72", "G72.1", "G72.2"]))
    # rs274 finds a G70 or G72 (facing) profile with corners "not monotonic"
    # more often than not.
    corners = [""] if cycle == "G70" or cycle.startswith("G72") else ["", "", " A0.2", " C0.2"]
    x = w.draw(st.integers(0, 30)) / 10
    z = 0.0
    w.emit(f"o{label} sub")
    w.emit(f"  G1 X{fmt(x)} Z0")
    slope = None  # of the last diagonal: two in a row must not be parallel
    for _ in range(w.draw(st.integers(1, 4))):
        dx = w.draw(st.integers(5, 30)) / 10
        dz = w.draw(st.integers(10, 50)) / 10
        corner = w.draw(st.sampled_from(corners))
        if w.draw(st.booleans()):
            if slope is not None and abs(dx / dz - slope) < 0.05:
                dx += 0.5
            slope = dx / dz
            x, z = x + dx, z - dz
            if w.draw(st.integers(0, 3)) == 0:  # U and W: increments of X and Z
                w.emit(f"  G1 U{fmt(dx)} W{fmt(-dz)}{corner}")
            else:
                w.emit(f"  G1 X{fmt(x)} Z{fmt(z)}{corner}")
        else:
            slope = None
            z -= dz
            w.emit(f"  G1 Z{fmt(z)}{corner}")
            x += dx
            w.emit(f"  X{fmt(x)}")
    w.emit(f"o{label} endsub")
    words = [f"Q{label}", f"D{w.draw(numbers(0, 5, 10))}"]
    if cycle == "G70":
        words.append(f"P{w.draw(st.integers(1, 3))}")
    else:
        words += [f"I{w.draw(numbers(3, 20, 10))}", f"R{w.draw(numbers(1, 10, 10))}"]
    w.emit(f"G18 G90 G0 X{fmt(x + 2)} Z2")
    w.emit(f"{cycle} " + " ".join(w.draw(st.permutations(words))))
    w.emit("G17")
    _restore_dist(w)


def stmt(w: Writer, nested: bool = False) -> None:
    weights = [
        (stmt_move, 6),
        (stmt_arc, 3),
        (stmt_assign, 4),
        (stmt_comment, 2),
        (stmt_modal, 3),
        (stmt_call, 2),
        (stmt_cycle, 2),
        (stmt_thread, 1),
        (stmt_probe, 1),
        (stmt_spline, 1),
        (stmt_lathe_cycle, 1),
        (stmt_codes, 2),
    ]
    if w.depth < 2:
        weights += [(stmt_if, 1), (stmt_loop, 1)]
    fns = [f for f, k in weights for _ in range(k)]
    w.draw(st.sampled_from(fns))(w)


def define_sub(w: Writer, index: int) -> None:
    name = w.draw(st.sampled_from([f"<sub{index}>", f"<Pocket {index}>", f"{1000 + index}"]))
    label = name.lower().replace(" ", "") if name.startswith("<") else name
    nargs = w.draw(st.integers(0, 4))
    returns = w.draw(st.booleans())
    saved_scope = w.scope
    w.scope = Scope(numbered=[n for n in saved_scope.numbered if n > 30],
                    named=[n for n in saved_scope.named if n.startswith("_")],
                    args=nargs)
    w.emit(f"o{name} sub")
    w.depth += 1
    if w.draw(st.integers(0, 3)) == 0:
        w.emit("M73")  # the caller's modes come back at the return
    for _ in range(w.draw(st.integers(1, 4))):
        stmt(w, nested=True)
    # Values rs274 reads past the definition: no named local (undefined
    # then; rs274 reads whatever its memory held for it).
    defining = Scope(numbered=w.scope.numbered, named=[], args=nargs)
    if w.draw(st.integers(0, 3)) == 0:
        # an early return with a value
        guard = w.new_label()
        w.emit(f"o{guard} if [{w.expr(1)} GT 0]")
        w.emit(f"o{name} return [{w.draw(expressions(defining, 1))}]")
        w.emit(f"o{guard} endif")
    w.depth -= 1
    if returns:
        w.emit(f"o{name} endsub [{w.draw(expressions(defining, 1))}]")
    else:
        w.emit(f"o{name} endsub")
    w.scope = saved_scope
    w.subs.append((label if name.startswith("<") else name, nargs, returns))
    if w.draw(st.booleans()):
        w.emit("(DEBUG, definition left #<_value> #<_value_returned>)")


@st.composite
def valid_programs(draw, max_statements: int = 12, feed_modes: bool = False) -> str:
    """A whole program, as text, that rs274 accepts (``feed_modes``: with
    inverse time and feed per revolution moves and UVW planes too)."""
    w = Writer(draw, feed_modes)
    w.subs = []
    ending = draw(st.sampled_from(["M2", "M30", "m2", "%"]))
    if ending == "%":
        w.lines.append("%")
    w.emit(draw(st.sampled_from(["G21 G90 G17 G94", "G20 G90", "g21", "G17 G21 G40 G49 G54 G80 G90 G94"])))
    w.emit(f"F{draw(numbers(50, 1000, 1))}")
    for i in range(draw(st.integers(0, 2))):
        define_sub(w, i)
    for _ in range(draw(st.integers(1, max_statements))):
        stmt(w)
    if ending == "%":
        if w.fanuc:
            w.emit("M2")  # the Fanuc subroutine must come before the closing %
        else:
            w.lines.append("%")
    else:
        w.emit(ending)
    if w.fanuc:
        w.lines += ["O9001", "G91 G0 X1", "G90", "M99"]
        if ending == "%":
            w.lines.append("%")
    if draw(st.integers(0, 5)) == 0:
        w.lines.append("G0 X[1/0] (after the end: never read)")
    return "\n".join(w.lines) + "\n"


@st.composite
def cycle_programs(draw, max_statements: int = 8, failing: bool = False) -> str:
    """A program that is mostly canned cycles, with moves and modal changes
    (units, distance mode, offsets, spindle, path control) in between.
    ``failing``: some cycles fail after their first moves (for rs274's
    ``-n 0``, which goes on from what the failed line left)."""
    w = Writer(draw)
    w.failing = failing
    w.emit(draw(st.sampled_from(["G21 G90 G17 G94", "G20 G90", "G21 G90 G64 P0.01"])))
    w.emit(f"F{draw(numbers(50, 1000, 1))}")
    w.emit(f"G0 {_axes(w, 'XYZ')}")
    fns = [stmt_cycle] * 4 + [stmt_move, stmt_modal, stmt_assign]
    for _ in range(draw(st.integers(1, max_statements))):
        draw(st.sampled_from(fns))(w)
    w.emit(draw(st.sampled_from(["M2", "M30"])))
    return "\n".join(w.lines) + "\n"


# --------------------------------------------------------------------------
# invalid programs: break one line of a valid one
# --------------------------------------------------------------------------

JUNK = list("$!?{}|&\"'`=<>,:")


@st.composite
def mutated_line(draw, line: str) -> str:
    kind = draw(st.integers(0, 11))
    stripped = line.rstrip()
    if kind == 0:  # a junk character somewhere
        pos = draw(st.integers(0, len(stripped)))
        return stripped[:pos] + draw(st.sampled_from(JUNK)) + stripped[pos:]
    if kind == 1 and "]" in stripped:  # drop a closing bracket
        pos = draw(st.sampled_from([i for i, c in enumerate(stripped) if c == "]"]))
        return stripped[:pos] + stripped[pos + 1:]
    if kind == 2:  # an extra opening bracket
        return stripped + " [" if draw(st.booleans()) else stripped.replace("[", "[[", 1)
    if kind == 3:  # an unknown or unusable letter
        word = draw(st.sampled_from(["E5", "Q1", "R2", "I3", "H1", "D2", "L1", "P5", "U1", "N5", "O"]))
        return f"{stripped} {word}"
    if kind == 4:  # a repeated word
        word = draw(st.sampled_from(["X1 X2", "G0 G1", "G20 G21", "M3 M4", "F1 F2", "G17 G18", "S1 S2"]))
        return f"{stripped} {word}"
    if kind == 5:  # bad o-words
        return draw(st.sampled_from([
            "o999 endif", "o999 endwhile", "o<nosuch> call", "o999 else", "o999 break",
            "o1 endsub", "o<x> return", "o999 repeat", "o999 foo", "o999 if 1", "o[1 call",
            "o999 continue", "o<unterminated call", "o999 endrepeat",
        ]))
    if kind == 6:  # arithmetic errors
        return stripped + " " + draw(st.sampled_from([
            "#1=[1/0]", "#1=SQRT[-1]", "#1=LN[0]", "#1=ACOS[2]", "#1=[-2**0.5]", "#1=[3 MOD 0]",
        ]))
    if kind == 7:  # undefined or read-only parameters
        return stripped + " " + draw(st.sampled_from([
            "X#<undefined_thing>", "#<_x>=1", "#5400=1", "#0=1", "#6000=1", "Y#<_nope>",
        ]))
    if kind == 8 and len(stripped) > 2:  # truncation
        pos = draw(st.integers(1, len(stripped) - 1))
        return stripped[:pos]
    if kind == 9:  # words no G code uses
        return draw(st.sampled_from(["G80 X1", "X1 G4", "G2 X1", "G1 @1 X1", "G10 L9 P1", "G92", "G4"]))
    if kind == 10 and draw(st.booleans()):  # broken canned cycles
        return stripped + " " + draw(st.sampled_from([
            "G81 X1 Z-1", "G82 X1 Z-1 R1", "G83 X1 Z-1 R1 Q0", "G73 X1 Z-1 R1", "G81 X1 Z1 R0",
            "G84 X1 Z-1 R1", "G74 X1 Z-1 R1 L2", "G87 X1 Z-1 R1 I1 J1", "G81 X1 Z-1 R1 A1",
            "G81 X1 Z-1 R1 L0", "G86 Z-1 R1 P1", "G18 G81 X1 Z-1 R1", "G91 G81 ^30 Z-1 R0 L2",
            "G81 X1 Z-1 R1 P1", "G89 X1 Z-1 R1 Q1", "R1", "G93 G81 X1 Z-1 R1 F1",
        ]))
    if kind == 10:  # unbalanced comments
        return stripped + draw(st.sampled_from([" (unclosed", " (a (nested) b)", " )"]))
    return "%" if draw(st.booleans()) else stripped + " G" + draw(st.sampled_from(["6", "100", "-1", "1.5", "[1/3]"]))


@st.composite
def invalid_programs(draw, max_statements: int = 10) -> str:
    text = draw(valid_programs(max_statements))
    lines = text.splitlines()
    # never the increment of a loop counter: a broken one could loop forever
    candidates = [i for i, ln in enumerate(lines) if "#<_i" not in ln or " while " in ln]
    idx = draw(st.sampled_from(candidates))
    lines[idx] = draw(mutated_line(lines[idx]))
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------
# the language: every kind of line, and O-word structures in every nesting
# --------------------------------------------------------------------------
#
# Written from the G Code Overview's "Format of a line" (an optional block
# delete slash, an optional line number, words, parameter settings and
# comments in any number; `;` comments to the end of the line; only the
# last comment is acted on) and the O Codes chapter (while/endwhile,
# do/while, repeat/endrepeat, if/elseif/else/endif, break and continue of
# a while or do loop, return and endsub inside a subroutine), not from
# ngc2py's implementation. Every O-word line may carry an N number and
# comments too.
#
# Loops always terminate: each has its own counter, incremented first thing
# in its body, and its condition is `counter LT n`. Labels are unique unless
# the generator deliberately reuses one (a `do` label reused by a later
# `do`, an `if`/`while` label reused: rs274 jumps back to the first `do`, or
# fails "duplicate O-word label"); a closing line may be left out on purpose
# (an unclosed `while` inside an `if`). Such programs may end in an error:
# the differential test only requires ngc2py to behave as rs274 does.

#: Comments as written after a line's words (or alone on a line): plain,
#: empty, blank, active (MSG, DEBUG, PRINT, LOG) and several on one line.
LINE_COMMENTS = [
    "()",
    "( )",
    "(  )",
    "(plain words)",
    "(Mixed Case; with semicolon)",
    "(MSG,a message)",
    "(msg, spaced message)",
    "(MSG,)",
    "(DEBUG,one=#1 two=#<_g>)",
    "(DEBUG,at line #<_line>)",  # where the line is, from the module's map
    "(debug,)",
    "(PRINT,printed #1)",
    "(PRINT,%f#1 then #<_g> %d#1 %.2f#1 100% %.x)",
    "(DEBUG,%f stays for #1 and #1)",
    "(LOG,logged #2)",
    "(first) ()",
    "() (MSG,after an empty one)",
    "(MSG,not acted on) (later plain)",
    "(plain) (DEBUG,last wins #1)",
    "() ()",
]

#: `;` comments: to the end of the line (a `(` in them is no comment).
SEMICOLON_COMMENTS = ["; trailing", ";", "; (not a comment", "; MSG,no"]


class LanguageWriter:
    """Lines of a program, and what the generator must know to keep its
    loops finite: the open loops of the current subroutine or main body."""

    def __init__(self, draw, block_delete: bool):
        self.draw = draw
        self.block_delete = block_delete
        self.lines: List[str] = []
        self.depth = 0
        self.next_label = 100
        self.next_counter = 0
        # open loops of the body being written: (label, kind)
        self.loops: List[tuple] = []
        # labels of constructs already closed in this body: (label, kind)
        self.closed: List[tuple] = []
        # the ifs around this point: (label, depth of their arms' lines)
        self.open_ifs: List[tuple] = []
        self.counters: List[str] = []  # loop counters visible here
        self.sub: str = ""  # name of the subroutine being written
        self.subs: List[str] = []  # callable subroutines
        self.size = 0  # statements written (bounds the program)
        self.globals: List[str] = []  # do-loop counters, set at the top
        self.landing = False  # a jump aimed at a finished loop was written

    def pick(self, options):
        return self.draw(st.sampled_from(options))

    def chance(self, one_in: int) -> bool:
        return self.draw(st.integers(0, one_in - 1)) == 0

    def number_prefix(self) -> str:
        """An optional line number: N, a number, maybe leading zeros, a
        decimal part, either case."""
        if not self.chance(3):
            return ""
        n = self.draw(st.integers(0, 9999))
        spelled = self.pick([f"N{n}", f"n{n}", f"N{n:05d}", f"N{n}.5", f"N {n}"])
        return spelled + self.pick([" ", "", "  "])

    def comment_suffix(self, required: bool = False) -> str:
        parts = []
        if required or self.chance(3):
            parts.append(self.pick(LINE_COMMENTS))
        if self.chance(5):
            parts.append(self.pick(SEMICOLON_COMMENTS))
        if not parts:
            return ""
        return self.pick([" ", "", "\t"]) + " ".join(parts)

    def emit(self, body: str, slash_ok: bool = True, oline: bool = False) -> None:
        """One line: [/] [N..] body [comments]. An O-word line (``slash_ok``
        False) is block-deleted rarely: under -b rs274 reads it as a blank
        line, so its construct no longer nests (ngc2py/lineflow.py)."""
        slash = "/" if self.chance(6 if slash_ok else 40) else ""
        text = slash + self.number_prefix() + body + self.comment_suffix()
        self.lines.append("  " * self.depth + text)

    def label(self) -> str:
        """A label for a new construct: usually new, sometimes one already
        used by a closed construct of this body."""
        if self.closed and (self.chance(2) if self.landing else self.chance(10)):
            self.landing = False
            return self.pick(self.closed)[0]
        self.next_label += 1
        return str(self.next_label)

    def condition(self) -> str:
        options = ["[1]", "[0]", "[#1 GT 0]", "[#<_g> LT 2]", "[1 EQ 1]"]
        if self.chance(12):
            # fails wherever rs274 evaluates it (#3 is 0 outside calls)
            options = ["[1/#3]", "[#<_unset> GT 0]"]
        for c in self.counters:
            options += [f"[#<{c}> EQ 2]", f"[#<{c}> GT 1]", f"[#<{c}> LT 2]"]
        return self.pick(options)


def lang_plain(w: LanguageWriter) -> None:
    """An ordinary line of some kind."""
    kind = w.draw(st.integers(0, 8 if w.chance(8) else 7))
    if kind == 0:
        w.emit(f"G1 X{w.draw(numbers(-50, 50, 10))} F{w.draw(numbers(10, 900, 1))}")
    elif kind == 1:
        w.emit(f"G0 Y{w.draw(numbers(-50, 50, 10))} Z{w.draw(numbers(0, 50, 10))}")
    elif kind == 2:
        target = w.pick(["#1", "#2", "#<_g>", "#<local>"])
        w.emit(f"{target} = [#1 + {w.draw(numbers(-20, 20, 10))}]")
    elif kind == 3:
        # a comment alone on a line, with or without a line number
        slash = "/" if w.chance(5) else ""
        w.lines.append("  " * w.depth + slash + w.number_prefix() + w.pick(LINE_COMMENTS))
    elif kind == 4:
        w.lines.append(w.pick(["", "  ", "\t"]))
    elif kind == 5:
        w.lines.append("  " * w.depth + w.pick(["/", "N20", "/N30", "; only a comment", "/()"]))
    elif kind == 6:
        w.emit(w.pick(["M3 S1000", "M5", "G91 G0 X1", "G90", "M8", "M9"]))
    elif kind == 7:
        w.emit("(DEBUG,counters " + " ".join(f"#<{c}>" for c in w.counters) + ")")
    else:
        # O-word lines rs274 cannot read: it reads the O-word even of a
        # line it skips over (an untaken arm, a definition)
        bad = ["o[1 call", "o9 foo", "o7777", "o<s0> return [1", "o9 endif G1"]
        # and M98 lines it cannot read, or whose values fail: read_o reads
        # them in full (values evaluated) before it asks whether it skips
        bad += ["M98 L2", "M98 P1.5", "N7 M98 P100 Q", "M98 P1 X[1/#3]"]
        bad += ["M98 P1 Q#<_unset>", "M98 P[#1 + 0.5]"]
        # both kinds together keep the file in the nested form (a Fanuc-style
        # O-line beside an M98), whose skips must read the M98 line too
        bad.append("M98 P1 X[1/#3]\n" + "  " * w.depth + "o7777")
        if w.depth:
            # a definition that never ends, where rs274 may skip it
            bad.append("o<nowhere> sub")
        if w.sub:
            bad.append(f"o{w.sub} return [1")
        w.lines.append("  " * w.depth + w.pick(bad))


def closer_words(w: LanguageWriter) -> str:
    """Now and then words after a closing O-word: rs274 checks them only
    when it runs into the line, not when it skips to it."""
    return w.pick([" G1", " X1"]) if w.chance(30) else ""


def lang_if(w: LanguageWriter) -> None:
    label = w.label()
    if w.open_ifs and w.chance(40):
        # an enclosing if's label: a skip of that if's arm stops here
        label = w.pick(w.open_ifs)[0]
    w.emit(f"o{label} if {w.condition()}", slash_ok=False)
    w.open_ifs.append((label, w.depth + 1))
    arms = 1 + w.draw(st.integers(0, 2))
    for arm in range(arms):
        if arm:
            # now and then one rs274 cannot read: it reads it wherever it
            # reaches the line, also where a skip to the label lands
            condition = w.pick(_UNREADABLE) if w.chance(25) else w.condition()
            w.emit(f"o{label} elseif {condition}{closer_words(w)}", slash_ok=False)
        lang_body(w)
    if w.chance(2):
        w.emit(f"o{label} else{closer_words(w)}", slash_ok=False)
        lang_body(w)
        if w.chance(15):
            # an arm line after the else: rs274 always skips its arm
            w.emit(f"o{label} " + w.pick(["else", f"elseif {w.condition()}"]), slash_ok=False)
            lang_body(w)
    w.open_ifs.pop()
    w.emit(f"o{label} endif{closer_words(w)}", slash_ok=False)
    w.closed.append((label, "if"))


#: conditions rs274 cannot read (what it computed before the error first)
_UNREADABLE = ["[[#<", "[#1 + ]", "[1/#3 + [#<]"]


def lang_landing_if(w: LanguageWriter) -> None:
    """An if with a do of its own label in one arm, never closed: a skip
    of an arm before it (a false condition, the arms after a taken one)
    lands on the do, which runs on into the later elseif and else lines.
    rs274 decides there by its one flag "an arm of an if has run"."""
    label = w.label()
    w.emit(f"o{label} if {w.condition()}", slash_ok=False)
    w.open_ifs.append((label, w.depth + 1))
    arms = w.draw(st.integers(0, 2))  # arms before the one with the do
    for arm in range(arms):
        lang_body(w)
        w.emit(f"o{label} elseif {w.condition()}{closer_words(w)}", slash_ok=False)
    w.depth += 1
    if w.chance(2):
        lang_statement(w)
    w.emit(f"o{label} do", slash_ok=False)
    w.depth -= 1
    lang_body(w)
    for _ in range(w.draw(st.integers(0, 2))):
        w.emit(f"o{label} elseif {w.condition()}{closer_words(w)}", slash_ok=False)
        lang_body(w)
    if not w.chance(4):
        w.emit(f"o{label} else{closer_words(w)}", slash_ok=False)
        lang_body(w)
    w.open_ifs.pop()
    if w.chance(6):
        # no endif: the do is never closed either, and the later elseif
        # and else lines have no line with the label after them (the
        # label is not used again): after an arm has run, rs274 skips
        # from them past whatever construct ends the do (its closing
        # line, a return, the program end) to the end of the file
        return
    w.emit(f"o{label} endif{closer_words(w)}", slash_ok=False)
    w.closed.append((label, "if"))


def lang_stray_label(w: LanguageWriter) -> None:
    """A loop never closed that does not run (a repeat of none, a false
    while): rs274 skips forward to the next line with its label, which
    stands inside another construct (an opener or a closing line of
    another kind, which fail there). (Not a do, which would run on from
    the middle of a construct never entered: ngc2py does not follow that.)"""
    label = w.label()
    if w.chance(2):
        w.emit(f"o{label} repeat [0]", slash_ok=False)
    else:
        w.emit(f"o{label} while [#<_g> GT 5]", slash_ok=False)
    lang_body(w)
    lang_statement(w)
    other = str(w.next_label + 1)
    w.next_label += 1
    kind = w.pick(["if", "while"])
    if kind == "if":
        w.emit(f"o{other} if {w.condition()}", slash_ok=False)
    else:
        w.lines.append("  " * w.depth + "#<stray> = 0")
        w.emit(f"o{other} while [#<stray> LT 1]", slash_ok=False)
        w.lines.append("  " * (w.depth + 1) + "#<stray> = [#<stray> + 1]")
    w.depth += 1
    landing = w.pick(["if", "while", "repeat", "endif", "endwhile", "else"])
    if landing == "if":
        w.emit(f"o{label} if {w.condition()}", slash_ok=False)
        w.emit(f"o{label} endif", slash_ok=False)
    elif landing == "while":
        w.emit(f"o{label} while [#<_unset> LT 1]", slash_ok=False)
        w.emit(f"o{label} endwhile", slash_ok=False)
    elif landing == "repeat":
        w.emit(f"o{label} repeat [1]", slash_ok=False)
        w.emit(f"o{label} endrepeat", slash_ok=False)
    else:
        w.emit(f"o{label} {landing}", slash_ok=False)
    lang_statement(w)
    w.depth -= 1
    w.emit(f"o{other} end{kind}", slash_ok=False)
    w.closed.append((other, kind))


def lang_stray_arm(w: LanguageWriter) -> None:
    """An else or elseif line of an if that has ended: rs274 takes it for an
    arm line run into (an elseif reads its condition first, which may
    fail). Where an arm has run it skips to the next line of its label:
    out of the construct holding it (a loop, an if), or to the end of the
    file when none follows; where none has, it runs on."""
    ifs = [label for label, kind in w.closed if kind == "if"]
    if not ifs:
        lang_plain(w)
        return
    label = w.pick(ifs)
    # not reused before the landing chosen here (see the end)
    w.closed = [entry for entry in w.closed if entry[0] != label]
    holder = w.pick(["", "repeat", "while", "if"])
    other = ""
    if holder:
        w.next_label += 1
        other = str(w.next_label)
    if holder == "repeat":
        w.emit(f"o{other} repeat [{w.draw(st.integers(0, 2))}]", slash_ok=False)
    elif holder == "while":
        w.next_counter += 1
        counter = f"k{w.next_counter}"
        w.lines.append("  " * w.depth + f"#<{counter}> = 0")
        w.emit(f"o{other} while [#<{counter}> LT 2]", slash_ok=False)
        w.lines.append("  " * (w.depth + 1) + f"#<{counter}> = [#<{counter}> + 1]")
    elif holder == "if":
        w.emit(f"o{other} if {w.condition()}", slash_ok=False)
    w.depth += bool(holder)
    if w.chance(2):
        w.emit(f"o{label} else", slash_ok=False)
    else:
        w.emit(f"o{label} elseif {w.condition()}", slash_ok=False)
    lang_statement(w)
    w.depth -= bool(holder)
    if holder:
        w.emit(f"o{other} end{holder}", slash_ok=False)
        w.closed.append((other, holder))
    if not w.chance(3):
        lang_statement(w)
        w.emit(f"o{label} endif", slash_ok=False)
        w.closed.append((label, "if"))
    # else no later line of the label: the skip runs to the end of the file
    # (a later construct reusing the label would be a landing inside it,
    # lang_landing_if's and lang_stray_label's business)


def lang_loop(w: LanguageWriter) -> None:
    kind = w.pick(["while", "do", "repeat"])
    label = w.label()
    arm_of = [name for name, _ in w.open_ifs]
    if arm_of and (w.chance(12) if kind == "do" else w.chance(40)):
        # the label of an if around it, in one of its arms however deep: a
        # skip of that arm lands on the do, which runs; a while or repeat
        # fails there as a duplicate
        label = w.pick(arm_of)
    finished_dos = [name for name, done in w.closed if done == "do"]
    if kind != "repeat" and finished_dos and w.chance(6):
        # the label of a finished do-loop, maybe of a body around this one:
        # a do line there does nothing and a while line ends that do-loop
        # again, going back to its do line (rs274 keeps its place)
        label = w.pick(finished_dos)
    w.next_counter += 1
    counter = f"k{w.next_counter}"
    count = w.draw(st.integers(0, 3))
    if kind == "do" or label in finished_dos:
        # a global counter set once at the top and never reset: a do-loop
        # whose label was used before jumps back to the first one
        # (rs274), and must still end
        counter = "_" + counter
        w.globals.append(counter)
        if kind == "while":
            # counted before the line too: going back to the do, the while
            # line runs again, and must not forever
            w.lines.append("  " * w.depth + f"#<{counter}> = [#<{counter}> + 1]")
    else:
        w.lines.append("  " * w.depth + f"#<{counter}> = 0")
    if kind == "while":
        w.emit(f"o{label} while [#<{counter}> LT {count}]", slash_ok=False)
    elif kind == "do":
        w.emit(f"o{label} do", slash_ok=False)
    else:
        w.emit(f"o{label} repeat [{count}]", slash_ok=False)
    w.depth += 1
    w.lines.append("  " * w.depth + f"#<{counter}> = [#<{counter}> + 1]")
    w.depth -= 1
    w.loops.append((label, kind))
    w.counters.append(counter)
    lang_body(w)
    if kind != "do" and w.chance(30):
        # a closing line of another kind with the loop's label, in an if
        # never taken: running out, the loop skips to it, and fails there
        w.depth += 1
        w.next_label += 1
        w.emit(f"o{w.next_label} if [0]", slash_ok=False)
        closer = "endrepeat" if kind == "while" else "endwhile"
        line = f"  o{label} " + w.pick([closer, "else", "endif", "elseif [#<_unset> GT 0]"])
        w.emit(line, slash_ok=False)
        w.emit(f"o{w.next_label} endif", slash_ok=False)
        w.depth -= 1
    if kind != "repeat" and w.chance(2):
        # the usual last statement: a guarded break or continue
        w.depth += 1
        lang_guarded_jump(w)
        w.depth -= 1
    w.counters.pop()
    w.loops.pop()
    unclosed = w.chance(25)
    if kind == "while" and not unclosed:
        w.emit(f"o{label} endwhile{closer_words(w)}", slash_ok=False)
    elif kind == "do" and not unclosed and w.chance(25):
        # a break or continue skips to it, and fails reading it
        w.emit(f"o{label} while [#<{counter}> LT [{count} +]]", slash_ok=False)
    elif kind == "do" and not unclosed:
        w.emit(f"o{label} while [#<{counter}> LT {count}]{closer_words(w)}", slash_ok=False)
    elif kind == "repeat" and not unclosed:
        w.emit(f"o{label} endrepeat{closer_words(w)}", slash_ok=False)
    w.closed.append((label, kind))


def lang_jump(w: LanguageWriter) -> None:
    """break or continue of an enclosing loop (any of them), or return."""
    if w.sub and (not w.loops or w.chance(3)):
        value = w.pick(["", " [7]", " [#1 + 1]"])
        w.emit(f"o{w.sub} return{value}", slash_ok=False)
        return
    loops = [entry for entry in w.loops if entry[1] != "repeat" or w.chance(8)]
    finished = [entry for entry in w.closed if entry[1] in ("while", "do")]
    if finished and w.chance(15):
        # aimed at a loop that has ended: rs274 skips forward to its label
        # and runs the next line with it (a later construct reusing it)
        loops = finished
        w.landing = True
    if w.open_ifs and w.chance(40):
        # an enclosing if's label: fails when run, or when a skip of that
        # if's arm stops at it
        loops = [(name, "if") for name, _ in w.open_ifs]
    if not loops:
        lang_plain(w)
        return
    label, _ = w.pick(loops)
    w.emit(f"o{label} {w.pick(['break', 'continue'])}", slash_ok=False)


def lang_guarded_jump(w: LanguageWriter) -> None:
    """The usual shape: ``if [counter test]`` around a break or continue
    (which then may never run: rs274 still skips over its line)."""
    label = w.label()
    w.emit(f"o{label} if {w.condition()}", slash_ok=False)
    w.depth += 1
    lang_jump(w)
    w.depth -= 1
    w.emit(f"o{label} endif", slash_ok=False)
    w.closed.append((label, "if"))


def lang_call(w: LanguageWriter) -> None:
    if not w.subs:
        lang_plain(w)
        return
    name = w.pick(w.subs)
    args = w.pick(["", " [1]", " [2] [3]", " [#1]"])
    w.emit(f"o{name} call{args}", slash_ok=False)


def lang_statement(w: LanguageWriter) -> None:
    w.size += 1
    options = [lang_plain] * 4 + [lang_call]
    if w.depth < 3 and w.size < 40:
        options += [lang_if, lang_loop, lang_loop]
        if w.chance(3):
            # a skip landing inside another construct
            options += [lang_landing_if, lang_stray_label]
        if w.closed and w.chance(4):
            options += [lang_stray_arm]
    if w.loops or w.sub:
        options += [lang_jump, lang_guarded_jump]
    if w.loops:
        options += [lang_guarded_jump]
    w.pick(options)(w)


def lang_body(w: LanguageWriter) -> None:
    w.depth += 1
    for _ in range(w.draw(st.integers(1, 3))):
        lang_statement(w)
    w.depth -= 1


def lang_sub(w: LanguageWriter, index: int) -> None:
    name = w.pick([f"<s{index}>", f"{900 + index}"])
    w.emit(f"o{name} sub", slash_ok=False)
    w.sub, w.closed, w.counters = name, [], []
    lang_body(w)
    if w.chance(3):
        # read (and evaluated) as rs274 reads past the definition
        w.emit(f"o{name} return" + w.pick(_DEFINITION_VALUES), slash_ok=False)
    w.emit(f"o{name} endsub" + w.pick(_DEFINITION_VALUES), slash_ok=False)
    w.sub, w.closed = "", []
    w.subs.append(name)
    if w.chance(2):
        w.emit("(DEBUG, value #<_value> returned #<_value_returned>)")


#: Values of a definition's endsub/return: rs274 reads them while it reads
#: past the definition. (Not a name undefined then: rs274 does not fail on
#: it there, but the value it reads is whatever its memory held.)
_DEFINITION_VALUES = [
    "",
    "",
    " [2]",
    " [#<_g> + 1]",
    " [#1 * 2 + #<_value>]",
    " [#<_g> / [#<_g> - 1]]",
    " [SQRT[#<_value> + 4]]",
]


@st.composite
def language_programs(draw, max_statements: int = 8) -> tuple:
    """(program text, rs274 options): a program exercising the line format
    and the O-word structures, run with or without block delete (-b)."""
    block_delete = draw(st.booleans())
    w = LanguageWriter(draw, block_delete)
    w.lines.append("#<_g> = 1")
    for index in range(draw(st.integers(0, 2))):
        lang_sub(w, index)
    for _ in range(draw(st.integers(1, max_statements))):
        lang_statement(w)
    w.lines.append(draw(st.sampled_from(["M2", "m30", "N999 M2", "M2 ()", "M2 (end)"])))
    w.lines[1:1] = [f"#<{name}> = 0" for name in w.globals]
    # each -b flips block delete, as rs274's option loop does
    times = draw(st.sampled_from([1, 1, 3] if block_delete else [0, 0, 2]))
    return "\n".join(w.lines) + "\n", ["-b"] * times


def long_programs(min_subs: int = 20, max_subs: int = 60):
    """(program text, rs274 options): a long core-language program
    (tests/long_programs.py: many subroutines calling each other, loops and
    conditionals nested deeply with break, continue and return at every
    depth, every kind of line). Drawn from one seed, not choice by choice:
    such a program takes tens of thousands of choices, more than Hypothesis
    keeps for one example; a failure prints the whole program instead of a
    shrunk one."""
    return st.integers(0, 2**32 - 1).map(
        lambda seed: long_program(RandomChooser(seed), min_subs, max_subs)
    )


def long_error_programs():
    """(program text, rs274 options): a long program with one mistake at a
    random depth (tests/long_programs.py: bad words and codes, unclosed
    brackets and comments, arithmetic errors, undefined parameters, modal
    group conflicts, O-words that are wrong, unreadable, unmatched or
    missing, missing subroutines, a line cut short)."""
    return st.integers(0, 2**32 - 1).map(lambda seed: error_program(RandomChooser(seed)))


# --------------------------------------------------------------------------
# cutter radius compensation
# --------------------------------------------------------------------------


def _comp_edge(draw, start, end, plane_words, scale, axis) -> str:
    """A move from ``start`` to ``end`` in the compensation plane: a line, a
    rapid, or an arc (radius or centre format, either direction, sometimes a
    helix), in absolute or incremental distance mode."""
    a1, a2, c1, c2 = plane_words
    incremental = draw(st.integers(0, 4)) == 0
    if incremental:
        d1, d2 = end[0] - start[0], end[1] - start[1]
        target = f"{a1}{d1:.4f} {a2}{d2:.4f}"
        # rs274 reads G91 before the motion: the words are offsets already
        wrap = ("G91 ", "\nG90")
    else:
        target = f"{a1}{end[0]:.4f} {a2}{end[1]:.4f}"
        wrap = ("", "")
    if end[0] == start[0] and not incremental and draw(st.booleans()):
        target = f"{a2}{end[1]:.4f}"  # the unchanged word left out
    kind = draw(st.integers(0, 5))
    chord = math.hypot(end[0] - start[0], end[1] - start[1])
    if kind <= 1 or chord < 1e-3:
        return f"{wrap[0]}G1 {target}{wrap[1]}"
    if kind == 2:
        return f"{wrap[0]}G0 {target}{wrap[1]}"
    code = draw(st.sampled_from(["G2", "G3"]))
    if draw(st.integers(0, 5)) == 0:
        target += f" {axis}{draw(st.integers(-10, 10)) / 10 * scale:.4f}"
    if kind == 3:
        r = chord / 2 + draw(st.integers(0, 30)) / 10 * scale
        sign = draw(st.sampled_from(["", "-"]))
        return f"{wrap[0]}{code} {target} R{sign}{r:.4f}{wrap[1]}"
    # centre on the chord's perpendicular bisector, either side
    h = draw(st.integers(-30, 30)) / 10 * scale
    mx, my = (start[0] + end[0]) / 2, (start[1] + end[1]) / 2
    nx, ny = -(end[1] - start[1]) / chord, (end[0] - start[0]) / chord
    cx, cy = mx + h * nx, my + h * ny
    return f"{wrap[0]}{code} {target} {c1}{cx - start[0]:.4f} {c2}{cy - start[1]:.4f}{wrap[1]}"


def _comp_extra(draw, axis: str, scale: float) -> str:
    """Something between compensated moves: calls rs274 queues, a move along
    the axis, a stop that flushes the queue, a plane or unit word."""
    return draw(
        st.sampled_from(
            [
                "(a comment)",
                "(MSG, a message)",
                f"F{draw(st.integers(5, 50)) * scale:g}",
                "M3 S1000",
                "M5",
                "M8",
                "M9",
                "G4 P0.5",
                f"G1 {axis}{draw(st.integers(-10, 10)) / 10 * scale:.4f}",
                f"G0 {axis}{draw(st.integers(0, 10)) / 10 * scale:.4f}",
                "M1",
                "M0",
                "G17" if axis == "Z" else "G18",
                "G21" if scale == 1.0 else "G20",
                "(debug, #<_ccomp> #<_x>)",
            ]
            + _NON_MOTION
        )
    )


#: Non-motion codes between compensated moves (LinuxCNC's G-code chapter):
#: offsets of coordinate systems not in use, tool table edits, the G92
#: family, digital and analog outputs, modal state, messages. Some are
#: refused under compensation (G92, G52, G43, changing the active system):
#: then both must fail alike.
_NON_MOTION = [
    "G10 L2 P2 X1 Y2",
    "G10 L2 P3 R15",
    "G10 L20 P4 X0 Y0",
    "G10 L20 P5 Z[#<_z>]",
    "G10 L1 P2 R0.01",
    "G10 L10 P2 Z0",
    "G92.1",
    "G92.2",
    "G92.3",
    "M62 P1",
    "M65 P1",
    "M68 E0 Q2",
    "M70",
    "M72",
    "(PRINT, at #<_x>)",
    "(DEBUG, #<_value>)",
    "G64 P0.01",
    "G92 X0",
    "G52 Y1",
    "G43 H1",
    "G10 L2 P0 X1",
    "G49",
    "T2",
    "S500",
    "G33 Y0 K1",
]


def _profile(draw, scale: float, n: int) -> list:
    """The corners of a closed profile: a star-shaped polygon around the
    origin, or a rectilinear one (straight-on lines, square corners)."""
    if draw(st.booleans()):
        angles = sorted(draw(st.lists(st.integers(0, 359), min_size=n, max_size=n, unique=True)))
        points = []
        for a in angles:
            r = draw(st.integers(10, 50)) / 10 * scale
            points.append((r * math.cos(math.radians(a)), r * math.sin(math.radians(a))))
    else:
        w = draw(st.integers(2, 8)) * scale / 2
        h = draw(st.integers(2, 8)) * scale / 2
        points = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
        if draw(st.booleans()):
            points.insert(1, (w / 2, 0.0))  # straight on through a point
        if draw(st.booleans()):
            points.insert(-1, (w / 2, h * 1.5))
    if draw(st.booleans()):
        points.reverse()
    return points


#: golden/cutter_comp/tools.tbl: mill tools (one undersize, one with no
#: diameter) and lathe tools with tool orientations.
_COMP_MILL_TOOLS = (1, 2, 3, 4)
_COMP_LATHE_TOOLS = (5, 6, 7)


def _comp_start(draw, plane: int, tool_table: bool, scale: float) -> str:
    """The line that turns compensation on."""
    if tool_table:
        side = draw(st.sampled_from(["G41", "G42"]))
        tools = _COMP_MILL_TOOLS + (_COMP_LATHE_TOOLS if plane == 18 else ())
        choice = draw(st.sampled_from(("", " D0") + tuple(f" D{t}" for t in tools)))
        return f"{side}{choice}"
    diameter = draw(st.integers(-10, 40)) / 100 * scale
    side = draw(st.sampled_from(["G41.1", "G42.1"]))
    orientation = ""
    if plane == 18 and draw(st.booleans()):
        orientation = f" L{draw(st.integers(0, 9))}"
    return f"{side} D{diameter:.4f}{orientation}"


@st.composite
def compensated_programs(draw, tool_table: bool = False) -> str:
    """Closed profiles (polygons whose edges may be arcs or rapids) cut with
    G41.1/G42.1 and random tool diameters (negative ones switch sides),
    entered and left with G40, with queued calls, axis moves, stops and
    distance-mode changes between the moves; in XY, or XZ with a lathe tool
    orientation. The tool may not fit every corner: then both must fail the
    same way. With ``tool_table``, G41/G42 take the diameter from the tools
    in golden/cutter_comp/tools.tbl (D, D0 or no D)."""
    inch = draw(st.booleans())
    scale = 1.0 if inch else 25.0
    plane = draw(st.sampled_from([17, 17, 17, 18]))
    words = ("X", "Y", "I", "J") if plane == 17 else ("Z", "X", "K", "I")
    axis = "Z" if plane == 17 else "Y"
    out = -8 * scale
    lines = [f"T{draw(st.sampled_from(_COMP_MILL_TOOLS))} M6"] if tool_table else []
    lines += [
        f"G{20 if inch else 21} G{plane} G90 F{10 * scale:g}",
        f"G0 {words[0]}{out:.4f} {words[1]}{out:.4f}",
    ]
    subs = []
    for index in range(draw(st.integers(1, 2))):
        points = _profile(draw, scale, draw(st.integers(3, 7)))
        lines.append(_comp_start(draw, plane, tool_table, scale))
        lines.append(_comp_edge(draw, (out, out), points[0], words, scale, axis))
        n = len(points)
        edges = []
        for k in range(n):
            start, end = points[k], points[(k + 1) % n]
            edges.append(_comp_edge(draw, start, end, words, scale, axis))
            if draw(st.integers(0, 3)) == 0:
                edges.append(_comp_extra(draw, axis, scale))
        if draw(st.booleans()):
            lines.extend(edges)
        else:
            # the profile is a subroutine, called around it in a loop
            name = f"<edge{index}>"
            subs += [f"o{name} sub", *edges, f"o{name} endsub"]
            lines.append(f"o{100 + index} repeat [{draw(st.integers(1, 3))}]")
            lines.append(f"o{name} call")
            lines.append(f"o{100 + index} endrepeat")
        exit_move = draw(st.sampled_from(["G0", "G1"]))
        lines.append(f"G40 {exit_move} {words[0]}{out:.4f} {words[1]}{out:.4f}")
    lines.append(draw(st.sampled_from(["M2", "M30"])))
    lines = subs + lines
    text = "\n".join(lines).split("\n")
    return "\n".join(f"N{10 * (i + 1)} {line}" for i, line in enumerate(text)) + "\n"


# --------------------------------------------------------------------------
# whole-language programs: realistic jobs mixing every code family
# --------------------------------------------------------------------------

# Written from the G Codes, M Codes, Canned Cycles, Cutter Compensation and
# Tool Table chapters of the LinuxCNC 2.9 documentation, not from ngc2py's
# runtime: each "job" below is what a part program does with a family of
# codes (a pocket cut under G41/G42 with a lead-in and arc corners, a
# drilling pattern in a plane, a lathe profile roughed with G71 and finished
# with G70, tool changes measured from a tool table drawn with the program,
# a probe whose results are used through #5061-#5070, splines, modal state
# saved and restored in a subroutine, the I/O M codes). Every job leaves the
# machine in G17 G90 G94 G40 G80 with the tool clear above the work, so jobs
# combine in any order. With ``errors``, a program may also carry one
# deliberately wrong use (a code the documentation rejects in that context);
# the differential test only asks that ngc2py fail as rs274 does.


class JobWriter:
    """Lines of a whole-language program and what the jobs need to know."""

    def __init__(self, draw, tools: dict, inch: bool):
        self.draw = draw
        self.tools = tools  # tool number -> (pocket, diameter, lathe?)
        self.inch = inch
        self.scale = 1.0 if inch else 25.0
        self.lines: List[str] = []
        self.subs: List[str] = []  # subroutine definitions, written first
        self.label = 200
        self.spindle = 0  # 0 stopped, 3 clockwise, 4 counter-clockwise
        self.numbered = False

    def emit(self, line: str) -> None:
        self.lines.append(line)

    def num(self, lo: float, hi: float, step: float = 0.1) -> str:
        """A value between lo and hi (times the unit scale), on a grid."""
        steps = int(round((hi - lo) / step))
        return fmt((lo + self.draw(st.integers(0, steps)) * step) * self.scale)

    def new_label(self) -> int:
        self.label += 1
        return self.label

    def pick(self, options):
        return self.draw(st.sampled_from(list(options)))

    def mill_tools(self) -> list:
        return [t for t, (_, _, lathe) in self.tools.items() if not lathe]

    def lathe_tools(self) -> list:
        return [t for t, (_, _, lathe) in self.tools.items() if lathe]

    def spindle_on(self, direction: int = 3) -> None:
        if self.spindle != direction:
            self.emit(f"S{self.pick([500, 1200, 3000])} M{direction}")
            self.spindle = direction

    def clear(self) -> None:
        """Back to the common state: clear of the work, absolute, XY plane."""
        # (a feed rate again: G94 and the tapping cycles leave none)
        self.emit(f"G17 G90 G94 G0 Z{fmt(self.scale)} F{fmt(10 * self.scale)}")


@st.composite
def tool_tables(draw) -> dict:
    """Mill tools (diameters, lengths) and lathe tools (orientation Q,
    X and Z offsets) for a program to change between; pockets are
    distinct from the tool numbers sometimes."""
    tools = {}
    numbers_ = draw(st.lists(st.integers(1, 30), min_size=2, max_size=5, unique=True))
    for i, t in enumerate(numbers_):
        lathe = i > 0 and draw(st.integers(0, 3)) == 0
        diameter = draw(st.integers(1, 10)) / 20  # 0.05 .. 0.5 (table units: inch)
        pocket = t if draw(st.booleans()) else t + 40
        tools[t] = (pocket, diameter, lathe)
    return tools


def tool_table_text(draw, tools: dict) -> str:
    lines = ["; drawn by tests/strategies.py whole_language_programs"]
    for t, (pocket, diameter, lathe) in tools.items():
        z = draw(st.integers(-20, 40)) / 10
        words = [f"T{t}", f"P{pocket}", f"Z{fmt(z)}", f"D{fmt(diameter)}"]
        if lathe:
            words += [f"X{fmt(draw(st.integers(-10, 10)) / 10)}", f"Q{draw(st.integers(1, 9))}"]
        lines.append(" ".join(words) + draw(st.sampled_from(["", " ;tool", " ; a comment"])))
    return "\n".join(lines) + "\n"


def job_tool_change(w: JobWriter) -> None:
    """Tool changes and length offsets, and the G10 table writes."""
    t = w.pick(w.mill_tools())
    how = w.draw(st.integers(0, 2))
    if how == 0:
        w.emit(f"T{t} M6")
    elif how == 1:
        w.emit(f"M6 T{t} G43")  # the change happens before G43 on a line
    else:
        w.emit(f"M61 Q{t}")
    other = w.pick(w.tools)
    w.emit(w.pick(["G43", f"G43 H{other}", f"G43.1 Z{w.num(-1, 1)}", "G49", f"G43 H0"]))
    if w.draw(st.booleans()):
        w.emit(f"G43.2 H{w.pick(w.tools)}")
    if w.draw(st.booleans()):
        kind = w.pick(["L1", "L10", "L11"])
        extra = f" R{w.num(0, 0.2, 0.05)}" if kind == "L1" and w.draw(st.booleans()) else ""
        w.emit(f"G10 {kind} P{other} Z{w.num(-1, 2)}{extra}")
        if w.draw(st.booleans()):
            w.emit(f"T{other} M6 G43")
    w.emit("(debug, tool #<_current_tool> pocket #<_current_pocket> #<_selected_pocket> offset #5403 #5410)")
    w.emit(f"G0 X{w.num(0, 2)} Y{w.num(0, 2)}")


def job_pocket(w: JobWriter) -> None:
    """A rounded-rectangle pocket or boss cut under compensation: a lead-in
    line or arc onto the first side, lines and corner arcs, a lead-out with
    G40. Inside a pocket the corner radius exceeds every tool radius."""
    s = w.scale
    t = w.pick(w.mill_tools())
    w.emit(f"T{t} M6 G43")
    w.spindle_on(3)
    width = w.draw(st.integers(20, 60)) / 10 * s
    height = w.draw(st.integers(20, 60)) / 10 * s
    r = w.draw(st.integers(3, 9)) / 10 * s  # corner radius > 0.25 inch
    x0, y0 = w.draw(st.integers(-20, 20)) / 10 * s, w.draw(st.integers(-20, 20)) / 10 * s
    inside = w.draw(st.booleans())
    ccw = w.draw(st.booleans())
    side = ("G41" if ccw else "G42") if inside else ("G42" if ccw else "G41")
    dword = w.pick([f" D{t}", "", f" D{w.pick(w.mill_tools())}"])
    if w.draw(st.integers(0, 3)) == 0:
        side += ".1"
        dword = f" D{fmt(w.draw(st.integers(0, 10)) / 20 * s)}"
    depth = w.num(0.1, 0.5)
    x1, y1, x2, y2 = x0, y0, x0 + width, y0 + height
    # corners, going counter-clockwise from the middle of the bottom side
    mid = ((x1 + x2) / 2, y1)
    path = [
        ("G1", (x2 - r, y1), None),
        ("G3", (x2, y1 + r), (0, r)),
        ("G1", (x2, y2 - r), None),
        ("G3", (x2 - r, y2), (-r, 0)),
        ("G1", (x1 + r, y2), None),
        ("G3", (x1, y2 - r), (0, -r)),
        ("G1", (x1, y1 + r), None),
        ("G3", (x1 + r, y1), (r, 0)),
        ("G1", mid, None),
    ]
    if not ccw:  # the same sides backwards: clockwise
        points = [mid] + [p for _, p, _ in path]
        rev = []
        for k in range(len(path) - 1, -1, -1):
            code, end, ij = path[k]
            start = points[k]
            if code == "G3":
                cx, cy = start[0] + ij[0], start[1] + ij[1]
                rev.append(("G2", start, (cx - end[0], cy - end[1])))
            else:
                rev.append(("G1", start, None))
        path = rev
    start = (mid[0], mid[1] + r) if inside else (mid[0], mid[1] - 2 * r)
    w.emit(f"G0 X{start[0]:.4f} Y{start[1]:.4f}")
    w.emit(f"G0 Z{fmt(0.1 * s)}")
    w.emit(f"G1 Z-{depth} F{fmt(5 * s)}")
    feed = f" F{fmt(w.draw(st.integers(5, 40)) * s)}"
    if w.draw(st.booleans()):
        w.emit(f"{side}{dword} G1 X{mid[0]:.4f} Y{mid[1]:.4f}{feed}")
    else:
        # an arc lead-in tangent to the side
        w.emit(f"{side}{dword}")
        # (a quarter circle whose centre is `start`, entered by a line
        # longer than any tool radius)
        side_x = mid[0] - r if ccw else mid[0] + r
        w.emit(f"G1 X{side_x:.4f} Y{start[1]:.4f}{feed}")
        if inside:
            code = "G3" if ccw else "G2"
            w.emit(f"{code} X{mid[0]:.4f} Y{mid[1]:.4f} " + w.pick([f"R{r:.4f}", f"I{mid[0] - side_x:.4f} J0"]))
        else:
            w.emit(f"G1 X{mid[0]:.4f} Y{mid[1]:.4f}")
    incremental = w.draw(st.integers(0, 4)) == 0
    here = mid
    for code, end, ij in path:
        if incremental:
            words = f"X{end[0] - here[0]:.4f} Y{end[1] - here[1]:.4f}"
        else:
            words = f"X{end[0]:.4f} Y{end[1]:.4f}"
        if ij is not None:
            if w.draw(st.booleans()):
                words += f" I{ij[0]:.4f} J{ij[1]:.4f}"
            else:
                words += f" R{r:.4f}"
        w.emit(("G91 " if incremental else "") + f"{code} {words}")
        here = end
        if w.draw(st.integers(0, 6)) == 0:
            w.emit(w.pick(["(corner)", "M8", "M9", "G4 P0.1", f"F{fmt(10 * s)}", "(debug, #<_ccomp>)"]))
    if incremental:
        w.emit("G90")
    w.emit(f"G40 G1 X{start[0]:.4f} Y{start[1]:.4f}")
    w.clear()


#: Canned cycles: the plane, its two in-plane letters and the hole axis.
_HOLE_AXES = {17: ("X", "Y", "Z"), 18: ("Z", "X", "Y"), 19: ("Y", "Z", "X")}


def job_drill(w: JobWriter) -> None:
    """A drilling pattern: a row repeated with L in G91, a list of holes
    each on its own line, a grid from a loop, or holes drilled by a
    subroutine called with their positions, with every cycle's words; or a
    rigid tap (G33.1) into and out of a hole."""
    s = w.scale
    if w.draw(st.integers(0, 5)) == 1:
        w.spindle_on(3)
        w.emit(f"G0 X{w.num(0, 1)} Y{w.num(0, 1)} Z{fmt(0.1 * s)}")
        scale_i = w.pick(["", " I1.1", " I0.9"])
        w.emit(f"G33.1 Z{w.num(-0.5, -0.1)} K{fmt(0.05 * s)}{scale_i}")
        w.clear()
        return
    plane = w.pick([17, 17, 18, 19])
    a, b, hole = _HOLE_AXES[plane]
    cycle = w.pick(["G81", "G82", "G83", "G73", "G84", "G74", "G85", "G86", "G87", "G88", "G89"])
    if cycle in ("G84", "G86", "G87", "G88"):
        w.spindle_on(3)
    elif cycle == "G74":
        w.spindle_on(4)
    elif w.draw(st.booleans()):
        w.spindle_on(3)
    retract = w.pick(["G98", "G99"])
    top = 1.0 * s
    w.emit(f"G{plane} G0 {hole}{fmt(top)}")
    extra = ""
    if cycle in ("G82", "G86", "G88", "G89"):
        extra += f" P{w.num(0, 1)}"  # the dwell these cycles require
    if cycle in ("G83", "G73"):
        extra += f" Q{w.num(0.05, 0.3, 0.05)}"
    if cycle == "G87":
        # back boring: the offsets in the plane, then the level to bore up to
        off1, off2, level = {17: ("I", "J", "K"), 18: ("K", "I", "J"), 19: ("J", "K", "I")}[plane]
        extra += f" {off1}{w.num(0.05, 0.2, 0.05)} {off2}0 {level}{w.num(-0.4, -0.2)}"
    feed = f" F{fmt(w.draw(st.integers(2, 30)) * s)}"
    z = w.num(-0.5, -0.1)
    rr = w.num(0.05, 0.3, 0.05)
    pattern = w.draw(st.integers(0, 3))
    if pattern == 0 and cycle != "G74":
        n = w.draw(st.integers(1, 4))
        step = w.num(0.2, 1)
        w.emit(f"G0 {a}0 {b}0")
        w.emit(f"G91 {retract} {cycle} {a}{step} {b}0 {hole}{fmt(-0.6 * s)} R{fmt(-0.4 * s)}{extra} L{n}{feed}")
        w.emit("G90 G80")
    elif pattern == 1:
        w.emit(f"{retract} {cycle} {a}{w.num(0, 1)} {b}{w.num(0, 1)} {hole}{z} R{rr}{extra}{feed}")
        for _ in range(w.draw(st.integers(0, 3))):
            words = [f"{a}{w.num(-1, 2)}", f"{b}{w.num(-1, 2)}"]
            if w.draw(st.integers(0, 3)) == 0:
                words.append(f"{hole}{w.num(-0.6, -0.1)}")  # a new depth sticks
            if w.draw(st.integers(0, 4)) == 0:
                words.append(w.pick(["G98", "G99"]))
            w.emit(" ".join(w.draw(st.permutations(words))))
        w.emit(w.pick(["G80", "G0 " + hole + fmt(top)]))
    elif pattern == 3:
        name = f"<holes{w.new_label()}>"
        w.subs += [
            f"o{name} sub",
            f"  {retract} {cycle} {a}#1 {b}#2 {hole}{z} R{rr}{extra}{feed}",
            f"  {a}[#1 + {fmt(0.3 * s)}]",
            "  G80",
            f"o{name} endsub",
        ]
        for _ in range(w.draw(st.integers(1, 3))):
            w.emit(f"o{name} call [{w.num(-1, 1)}] [{w.num(-1, 1)}]")
    else:
        label = w.new_label()
        w.emit(f"#<row> = 0")
        w.emit(f"o{label} while [#<row> LT {w.draw(st.integers(1, 3))}]")
        w.emit(
            f"  {retract} {cycle} {a}[#<row> * {fmt(0.5 * s)}] {b}{w.num(0, 1)} {hole}{z} R{rr}{extra}{feed}"
        )
        w.emit("  #<row> = [#<row> + 1]")
        w.emit(f"o{label} endwhile")
        w.emit("G80")
    w.clear()


def job_lathe(w: JobWriter) -> None:
    """Turning in XZ: a lathe tool, diameter or radius mode, constant surface
    speed with a limit, a profile roughed by G71 (or faced by G72) and
    finished by G70, a thread (G33 or G76), back to rpm mode."""
    s = w.scale
    lathe = w.lathe_tools() or w.mill_tools()
    t = w.pick(lathe)
    mode = w.pick(["G7", "G8"])
    w.emit(f"G18 {mode}")
    w.emit(f"T{t} M6 G43")
    if w.draw(st.booleans()):
        w.emit(f"G96 D{w.pick([1500, 2500])} S{w.pick([100, 250])} M3")
    else:
        w.emit(f"G97 S{w.pick([400, 800])} M3")
    w.spindle = 3
    label = w.new_label()
    x, z = 0.4, 0.0
    profile = [f"o{label} sub", f"  G1 X{fmt(x * s)} Z0"]
    for _ in range(w.draw(st.integers(1, 3))):
        dx = w.draw(st.integers(2, 6)) / 10
        dz = w.draw(st.integers(3, 10)) / 10
        corner = w.pick(["", "", f" C{fmt(0.02 * s)}"])
        if w.draw(st.booleans()):
            x, z = x + dx, z - dz
            profile.append(f"  G1 X{fmt(x * s)} Z{fmt(z * s)}")
        else:
            z -= dz
            profile.append(f"  G1 Z{fmt(z * s)}{corner}")
            x += dx
            profile.append(f"  G1 X{fmt(x * s)}")
    profile.append(f"o{label} endsub")
    w.subs += profile
    w.emit(f"G0 X{fmt((x + 0.2) * s)} Z{fmt(0.2 * s)}")
    cycle = w.pick(["G71", "G71", "G71.1", "G72"])
    words = [f"Q{label}", f"D{fmt(w.draw(st.integers(1, 5)) / 50 * s)}", f"F{fmt(4 * s)}"]
    if w.draw(st.booleans()):
        words.append(f"I{fmt(0.02 * s)}")
    w.emit(f"{cycle} " + " ".join(w.draw(st.permutations(words))))
    if w.draw(st.booleans()):
        w.emit(f"G70 Q{label} P{w.draw(st.integers(1, 2))}")
    if w.draw(st.integers(0, 2)) == 1:
        # a finishing pass along the profile under nose-radius compensation
        w.emit(f"G0 X{fmt((x + 0.3) * s)} Z{fmt(0.3 * s)}")
        orient = w.draw(st.integers(0, 9))
        w.emit(w.pick([f"G42 D{t}", f"G41 D{t}", f"G42.1 D{fmt(0.02 * s)} L{orient}", f"G41.1 D{fmt(0.02 * s)} L{orient}"]))
        w.emit(f"G1 X{fmt(0.4 * s)} Z{fmt(0.1 * s)} F{fmt(4 * s)}")
        w.lines += [ln.strip() for ln in profile[1:-1]]
        w.emit(f"G40 G0 X{fmt((x + 0.3) * s)}")
    thread = w.draw(st.integers(0, 2))
    w.emit(f"G0 X{fmt((x + 0.2) * s)} Z{fmt(0.2 * s)}")
    if thread == 0:
        w.emit(f"G33 Z{fmt(-0.5 * s)} K{fmt(0.05 * s)}")
    elif thread == 1:
        w.emit(
            f"G76 P{fmt(0.05 * s)} Z{fmt(-0.5 * s)} I{fmt(-0.05 * s)} J{fmt(0.01 * s)} K{fmt(0.03 * s)}"
            + w.pick(["", f" Q29.5 R1.5 H2 E{fmt(0.02 * s)} L2"])
        )
    w.emit(f"G97 S{w.pick([400, 800])}")
    if mode == "G7":
        w.emit("G8")
    w.emit(f"G0 X{fmt((x + 0.5) * s)}")
    w.clear()


def job_probe(w: JobWriter) -> None:
    """Probe down to the surface, then use the result (#5061-#5070) to set a
    work offset and move relative to it; sometimes a sideways probe too."""
    s = w.scale
    w.emit(f"G0 X{w.num(0, 1)} Y{w.num(0, 1)} Z{fmt(0.5 * s)}")
    code = w.pick(["G38.2", "G38.3", "G38.4", "G38.5"])
    if w.draw(st.booleans()):
        w.emit(f"G91 {code} Z{fmt(-w.draw(st.integers(1, 10)) / 10 * s)} F{fmt(2 * s)}")
        w.emit("G90")
    else:
        w.emit(f"{code} Z{w.num(-1, 0.4)} F{fmt(2 * s)}")
    w.emit("(debug, probed #5061 #5062 #5063 ok #5070)")
    use = w.draw(st.integers(0, 3))
    if use == 0:
        label = w.new_label()
        w.emit(f"o{label} if [#5070 EQ 0]")
        w.emit("  (MSG, probe did not trip)")
        w.emit(f"o{label} endif")
    elif use == 1:
        w.emit(f"G10 L20 P{w.draw(st.integers(1, 3))} Z[#5063 - #5063]")
    elif use == 2:
        w.emit("#<surface> = #5063")
        w.emit(f"G0 Z[#<surface> + {fmt(0.2 * s)}]")
    else:
        w.emit(f"G38.3 X[#5061 + {fmt(0.5 * s)}] F{fmt(3 * s)}")
        w.emit("(debug, side #5061 #5062 #5070)")
    w.clear()


def job_spline(w: JobWriter) -> None:
    """Splines in the XY plane at feed: a cubic G5 chain (the second one
    without I and J), a quadratic G5.1, a NURBS G5.2 ... G5.3."""
    s = w.scale
    w.emit(f"G0 X0 Y0")
    w.emit(f"G1 Z{fmt(-0.1 * s)} F{fmt(10 * s)}")
    kind = w.draw(st.integers(0, 2))
    if kind == 0:
        w.emit(f"G5 I{w.num(0, 1)} J{w.num(0, 1)} P{w.num(-1, 0)} Q{w.num(0, 1)} X{w.num(1, 2)} Y{w.num(0, 1)}")
        if w.draw(st.booleans()):
            w.emit(f"G5 P{w.num(-1, 0)} Q{w.num(0, 1)} X{w.num(2, 3)} Y{w.num(0, 1)}")
    elif kind == 1:
        w.emit(f"G5.1 I{w.num(0, 1)} J{w.num(0.1, 1)} X{w.num(1, 2)} Y{w.num(-1, 1)}")
    else:
        order = w.pick([3, 4])
        w.emit(f"G5.2 X{w.num(0, 1)} Y{w.num(0, 1)} P1" + (f" L{order}" if order != 3 else ""))
        for _ in range(order):
            w.emit(f"X{w.num(0, 3)} Y{w.num(0, 3)} P{w.pick(['1', '0.5', '2'])}")
        w.emit("G5.3")
    w.emit("(debug, after the spline #5420 #5421)")
    w.emit(f"G0 Z{fmt(s)}")
    w.emit("G1 X0 Y0")  # a known point again
    w.clear()


def job_modal_sub(w: JobWriter) -> None:
    """A subroutine that changes modes and puts them back: M70/M72 around
    the changes, or M73 for an automatic restore at its return; M71 makes a
    saved state unusable."""
    s = w.scale
    name = f"<modes{w.new_label()}>"
    how = w.draw(st.integers(0, 1)) if w.draw(st.integers(0, 5)) else 2
    body = [f"o{name} sub"]
    body.append("  M70" if how == 0 else "  M73" if how == 1 else "  M70")
    changes = w.draw(
        st.lists(
            st.sampled_from(["G20", "G21", "G91", "G18", "G61", "G64 P0.01", "F77", "M8", "G95", "G93", "G90.1", "S900 M4", "G55"]),
            min_size=1,
            max_size=4,
            unique=True,
        )
    )
    # one code of a modal group per line
    for first, second in (("G93", "G95"), ("G61", "G64 P0.01"), ("G20", "G21")):
        if first in changes and second in changes:
            changes.remove(second)
    body.append("  " + " ".join(changes) if w.draw(st.booleans()) else "\n".join("  " + c for c in changes))
    body.append("  (debug, inside #<_metric> #<_absolute> #<_plane> #<_feed> #<_coord_system>)")
    if how == 0:
        body.append("  M72")
    elif how == 2:
        body.append("  M71")
        body.append("  M72")  # an error: the state was forgotten (M71)
    body.append(f"o{name} endsub")
    w.subs += "\n".join(body).split("\n")
    if how == 2 and not w.errors:
        w.subs[-3:-1] = ["  G90 G17 G94 G54 G64 G91.1 M9"]
    w.emit(f"o{name} call")
    w.emit("(debug, after #<_metric> #<_absolute> #<_plane> #<_feed> #<_coord_system> #<_flood>)")
    w.emit(f"G{20 if w.inch else 21} F{fmt(10 * s)}")
    w.spindle = -1
    w.clear()


def job_io(w: JobWriter) -> None:
    """Spindle orientation, override switches and digital/analog I/O."""
    for _ in range(w.draw(st.integers(1, 4))):
        w.emit(
            w.pick(
                [
                    f"M19 R{w.draw(st.integers(0, 360))} Q{w.draw(st.integers(1, 5))} P{w.draw(st.integers(0, 2))}",
                    "M48",
                    "M49",
                    f"M50 P{w.draw(st.integers(0, 1))}",
                    f"M51 P{w.draw(st.integers(0, 1))}",
                    "M52 P1",
                    "M53 P0",
                    f"M{w.pick([62, 63, 64, 65])} P{w.draw(st.integers(0, 3))}",
                    f"M66 P{w.draw(st.integers(0, 3))} L{w.draw(st.integers(0, 4))} Q{w.draw(st.integers(1, 5))}",
                    f"M66 E{w.draw(st.integers(0, 3))} L0",
                    f"M67 E{w.draw(st.integers(0, 3))} Q{w.num(-1, 1)}",
                    f"M68 E{w.draw(st.integers(0, 3))} Q{w.num(-1, 1)}",
                    f"G1 X{w.num(0, 1)} F{fmt(10 * w.scale)} M62 P1",
                ]
            )
        )
    w.emit("(debug, input #5399)")
    w.spindle = -1  # M19 stops the spindle turning


def job_frames(w: JobWriter) -> None:
    """Units, distance modes, coordinate systems and G92, and the three feed
    modes (inverse time needs F on every feed move; per revolution needs a
    turning spindle)."""
    s = w.scale
    for _ in range(w.draw(st.integers(1, 4))):
        kind = w.draw(st.integers(0, 7))
        if kind == 0:
            w.emit(w.pick(["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"]))
        elif kind == 1:
            w.emit(f"G10 L2 P{w.draw(st.integers(0, 9))} X{w.num(-1, 1)} Y{w.num(-1, 1)}" + w.pick(["", " R15"]))
        elif kind == 2:
            w.emit(f"G92 X{w.num(-1, 1)} Y{w.num(-1, 1)}")
            w.emit(w.pick(["G92.1", "G92.2", "G92.3", "(keep it)"]))
        elif kind == 3:
            other = "G21" if w.inch else "G20"
            w.emit(f"{other} G0 X1 Y1")
            w.emit(f"G{20 if w.inch else 21}")
        elif kind == 4:
            w.emit(f"G91 G1 X{w.num(-1, 1)} Y{w.num(-1, 1)} F{fmt(10 * s)}")
            w.emit("G90")
        elif kind == 5:
            w.emit(f"G93 G1 X{w.num(-1, 1)} Y{w.num(-1, 1)} F{w.draw(st.integers(1, 60))}")
            w.emit(f"G2 X{w.num(-1, 1)} Y{w.num(-1, 1)} R{fmt(3 * s)} F{w.draw(st.integers(1, 60))}")
            w.emit(f"G94 F{fmt(10 * s)}")
        elif kind == 6:
            w.spindle_on(3)
            w.emit(f"G95 G1 X{w.num(-1, 1)} F{fmt(0.004 * s)}")
            w.emit(f"G94 F{fmt(10 * s)}")
        else:
            w.emit(f"G53 G0 Z0")
            w.emit(w.pick(["G28", "G30", "G28.1", "G30.1"]))
    w.emit("(debug, at #<_x> #<_y> #<_z> in #<_coord_system>)")
    w.emit("G54")
    w.clear()


def job_comp_mix(w: JobWriter) -> None:
    """Outside compensation around a convex outline whose edges mix every
    kind of feed move: lines, arcs along the outline, inverse-time moves
    (F on each), a NURBS block, moves along Z, and calls rs274 queues."""
    s = w.scale
    radius = w.draw(st.integers(15, 40)) / 10 * s
    angles = sorted(w.draw(st.lists(st.integers(0, 35), min_size=3, max_size=7, unique=True)))
    ccw = w.draw(st.booleans())
    if not ccw:
        angles.reverse()
    points = [(radius * math.cos(math.radians(a * 10)), radius * math.sin(math.radians(a * 10))) for a in angles]
    side = "G42" if ccw else "G41"  # the tool outside the outline
    diameter = fmt(w.draw(st.integers(1, 10)) / 20 * s)
    side += w.pick([f".1 D{diameter}", f" D{w.pick(w.mill_tools())}", ""])
    out = (points[0][0] * 1.6, points[0][1] * 1.6)
    w.emit(f"G0 X{out[0]:.4f} Y{out[1]:.4f}")
    w.emit(f"G1 Z{fmt(-0.1 * s)} F{fmt(10 * s)}")
    w.emit(f"{side} G1 X{points[0][0]:.4f} Y{points[0][1]:.4f}")
    inverse = False
    for k in range(1, len(points) + 1):
        end = points[k % len(points)]
        kind = w.draw(st.integers(0, 6))
        target = f"X{end[0]:.4f} Y{end[1]:.4f}"
        if inverse and kind != 1:
            w.emit(f"G94 F{fmt(10 * s)}")
            inverse = False
        if kind == 0:
            w.emit(f"{'G3' if ccw else 'G2'} {target} R{radius:.4f}")
        elif kind == 1:
            inverse = True
            w.emit(f"G93 G1 {target} F{w.draw(st.integers(5, 60))}")
        elif kind == 2:
            start = points[k - 1]
            mid = ((start[0] + end[0]) / 2 * 1.05, (start[1] + end[1]) / 2 * 1.05)
            w.emit(f"G5.2 X{start[0]:.4f} Y{start[1]:.4f} P1")
            w.emit(f"X{mid[0]:.4f} Y{mid[1]:.4f} P{w.pick(['1', '2', '0.5'])}")
            w.emit(f"{target} P1")
            w.emit("G5.3")
            w.emit("G1")
        elif kind == 3:
            w.emit(f"G1 {target} Z{fmt(-w.draw(st.integers(1, 3)) / 10 * s)}")
        else:
            w.emit(f"G1 {target}")
        if w.draw(st.integers(0, 4)) == 0:
            w.emit(w.pick(["(edge)", "M8", "M9", "G4 P0.2", f"F{fmt(12 * s)}", "M3 S800"]))
    if inverse:
        w.emit(f"G94 F{fmt(10 * s)}")
    w.emit(f"G40 G0 X{out[0]:.4f} Y{out[1]:.4f}")
    w.clear()


#: Deliberately wrong lines: each breaks a rule of the chapters above.
def _wrong_lines(w: JobWriter) -> list:
    s = w.scale
    missing = max(w.tools) + 7
    return [
        f"G41 D{missing}",  # no such tool
        f"G41 D{w.pick(w.mill_tools())}\nG1 X{fmt(s)} Y0\nG42 D{w.pick(w.mill_tools())}",  # already on
        "G41.1 D0.1\nG1 X1 Y1\nG18",  # plane change under comp
        "G41.1 D0.2\nG1 X0 Y0\nG2 X0.1 Y0 R0.05",  # arc radius under the tool's
        "G41.1 D0.2 G1 X1 Y1\nG81 X0 Y0 Z-1 R1",  # cycle under comp
        "G40 G2 X1 Y0 I0.5 J0",  # an arc that ends compensation
        f"G83 X0 Y0 Z{fmt(-0.5 * s)} R{fmt(0.1 * s)} F10",  # no Q
        f"M5\nG84 X0 Y0 Z{fmt(-0.5 * s)} R{fmt(0.1 * s)} F10",  # spindle stopped
        f"G81 X0 Y0 Z{fmt(0.5 * s)} R{fmt(0.1 * s)} F10",  # R below Z
        f"G81 X0 Y0 A10 Z-1 R0.1 F10",  # rotary axis in a cycle
        "G74 X0 Y0 Z-1 R0.1 L2 F10",  # L with G74
        "G38.2 Z[#<_z>] F10",  # probe to where the tool is
        "G1 F0\nG38.2 Z-1",  # zero feed probe
        "G18\nG5 I1 J1 P1 Q1 X1 Z1",  # spline out of its plane
        "G5.1 I1 X1 Y1",  # no J
        "G5.2 X1 Y1 P1\nX2 Y2\nG5.3",  # a NURBS point without weight
        "G18\nG71 Q999 D0.1",  # profile subroutine never defined
        "G41.1 D0.1\nG1 X1 Y1\nG5 I1 J0 P1 Q0 X2 Y2",  # cubic spline under comp
        "G18 G41.1 D0.1\nG1 X1 Z1\nG71 Q999 D0.1",  # lathe cycle under comp
        "G41.1 D0.1\nG1 X1 Y1\nG38.2 X2",  # probing under comp
        "G96 D2000 M3",  # constant surface speed without S
        f"G43 H{missing}",
        f"T{missing} M6",
        "M66 L1",
        "M67 Q1",
        "M19 R400",
        f"M{w.draw(st.integers(100, 199))} P1 Q2",
        "S500 M3\nG76 P0.1 Z-1 I-0.1 J0 K0.1",  # J must be positive
        "S500 M3\nG33 Z-1",  # no K
        "G10 L1 P0 Z1",
        "T1 M6\nG10 L0",  # a tool loaded
        "M72",  # nothing saved
        "G93\nG1 X1 Y1",  # inverse time move without F
        f"G1 X1 D{w.pick(w.mill_tools())}",  # D with nothing to use it
        "G43.1 X0.1 Y0.1",  # Y offsets are not allowed
        "$1 S200 M3",  # a spindle that does not exist
        # O-word lines as rs274 reads them (tests/test_language_generators):
        # an else after its if ended (an arm ran: it skips to the end of the
        # file), an elseif's condition read before its label, one that
        # cannot be read where a skip lands, a second else
        f"o9001 if [1]\nG0 Z{fmt(s)}\no9001 endif\no9001 else\nG0 Z{fmt(2 * s)}",
        "o9002 elseif [#<_not_set> GT 0]",
        f"o9003 if [0]\nG0 Z{fmt(s)}\no9003 elseif [[#<\no9003 endif",
        f"o9004 if [0]\no9004 else\nG0 Z{fmt(s)}\no9004 else\nG0 Z{fmt(3 * s)}\no9004 endif",
    ]


JOBS = [
    (job_tool_change, 2),
    (job_pocket, 3),
    (job_drill, 3),
    (job_lathe, 2),
    (job_probe, 2),
    (job_spline, 1),
    (job_modal_sub, 2),
    (job_io, 1),
    (job_frames, 2),
    (job_comp_mix, 2),
]


@st.composite
def whole_language_programs(draw, errors: bool = True, max_jobs: int = 7) -> tuple:
    """A job-shop program and its tool table: ``(program text, table text)``.

    The program runs with ``-t`` and the table in its folder. With
    ``errors``, about one program in five has a wrong line somewhere
    between its jobs (and may end there)."""
    tools = draw(tool_tables())
    inch = draw(st.booleans())
    w = JobWriter(draw, tools, inch)
    w.errors = errors
    s = w.scale
    w.emit(draw(st.sampled_from([f"G{20 if inch else 21} G17 G40 G49 G54 G80 G90 G94", f"G{20 if inch else 21} G90"])))
    w.emit(f"F{fmt(10 * s)}")
    w.emit(f"G0 Z{fmt(s)}")
    fns = [f for f, k in JOBS for _ in range(k)]
    jobs = draw(st.lists(st.sampled_from(fns), min_size=1, max_size=max_jobs))
    # (a middle value: Hypothesis draws the ends of a range more often)
    wrong_at = draw(st.integers(0, len(jobs))) if errors and draw(st.integers(0, 4)) == 2 else None
    for k, job in enumerate(jobs):
        if k == wrong_at:
            w.lines += draw(st.sampled_from(_wrong_lines(w))).split("\n")
        job(w)
    if wrong_at == len(jobs):
        w.lines += draw(st.sampled_from(_wrong_lines(w))).split("\n")
    w.emit(draw(st.sampled_from(["M5 M9\nM2", "M30", "M2"])))
    lines = w.subs + "\n".join(w.lines).split("\n")
    if draw(st.integers(0, 3)) == 0:
        lines = [f"N{10 * (i + 1)} {ln}" if not ln.lstrip().lower().startswith("o") else ln for i, ln in enumerate(lines)]
    return "\n".join(lines) + "\n", tool_table_text(draw, tools)


@st.composite
def broken_whole_language_programs(draw) -> tuple:
    """A whole-language program (with its tool table) with one line broken
    as ``invalid_programs`` breaks them, or a line's words shuffled onto a
    code family that does not take them: errors in the middle of a cycle,
    a compensated outline, a lathe cycle's profile."""
    text, table = draw(whole_language_programs(errors=False))
    lines = text.splitlines()
    k = draw(st.integers(0, len(lines) - 1))
    if draw(st.integers(0, 3)) == 1:
        # words of other families added to a line of this program
        extra = draw(st.sampled_from([
            "G41.1 D0.1", "G40", "G43 H1", "G80", "G96 S100", "G93", "G95", "M70", "M72",
            "G38.2 Z-1", "G5.3", "G7", "G33 K1", "G76 P1", "M19 R10", "M66 P0 L0", "L2", "K0.1",
            "G18", "G20", "G91", "G92 X0", "G10 L1 P1 Z0", "M6", "T1", "M61 Q1", "$0 M3", "D1",
        ]))
        lines[k] = f"{lines[k].rstrip()} {extra}"
    else:
        lines[k] = draw(mutated_line(lines[k]))
    return "\n".join(lines) + "\n", table


# --------------------------------------------------------------------------
# subroutine files holding several subroutines
# --------------------------------------------------------------------------

# From the O Codes chapter ("Calling Files", "Subroutines") and how probing
# macros are written in practice: a file NAME.ngc found on the subroutine
# path defines o<NAME> and, before or after it, helper subs it calls; a
# helper may be numbered, may be written inside the main sub, may call
# another helper further on, and may be called from outside once the file
# has defined it. rs274 finds a sub it does not know yet by opening
# NAME.ngc, else by reading forward from the call in the file it is
# reading: calls before the helper's definition, helpers defined before
# their caller and calls from the main program before the file was opened
# all end in rs274's errors, which ngc2py must give the same way.


def _file_sub_body(draw, args: int, calls: list) -> list:
    """A few lines of a helper: moves from its arguments, a message, calls."""
    body = []
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.integers(0, 4))
        arg = f"#{draw(st.integers(1, max(args, 1)))}"
        if kind == 0:
            body.append(f"G1 X[{arg} + {draw(st.integers(0, 9))}] F{draw(st.integers(10, 90))}")
        elif kind == 1:
            body.append(f"G0 Y[{arg} * 2] Z{draw(st.integers(0, 5))}")
        elif kind == 2:
            body.append(f"(DEBUG, in [{arg}] value #<_value>)")
        elif kind == 3 and calls:
            body.append(f"o{draw(st.sampled_from(calls))} call [{arg} + 1] [2]")
        else:
            body.append(f"#<_seen> = [#<_seen> + {arg}]")
    return body


def _fanuc_body(draw) -> list:
    """The lines of a Fanuc-style program (it sees its caller's #1-#30)."""
    options = ["G91 G0 X1", "G90", "G0 Y[#1 + 1]", "(DEBUG, fanuc #1 #<_seen>)", "#<_seen> = [#<_seen> + 1]"]
    return draw(st.lists(st.sampled_from(options), min_size=1, max_size=3))


@st.composite
def subroutine_file_programs(draw) -> tuple:
    """(files, args): ``files`` maps a path relative to the program's folder
    to its text (``main.ngc`` is the program); ``args`` are rs274's options
    (``-i subs.ini`` when a file lives on the SUBROUTINE_PATH)."""
    files = {}
    on_path = draw(st.booleans())
    main_lines = ["G21 G90 G17", "#<_seen> = 0"]
    outside_calls = []
    # Fanuc-style programs (O<n> ... M99) for M98 calls: one per macro file
    # (8f0, after its subs), one in the main program after its M2 (900),
    # and 950.ngc, opened by M98 P950. An M98 finds what an earlier M98
    # found, else <n>.ngc, else reads ahead in the file it is in.
    fanuc_in_file = [draw(st.integers(0, 2)) == 0 for _ in range(2)]
    fanuc_in_main = draw(st.integers(0, 2)) == 0
    if draw(st.integers(0, 3)) == 0:
        body = _fanuc_body(draw) + ["M98 P951" if draw(st.integers(0, 2)) == 0 else "G0 Z1"]
        number_file = ["(a Fanuc-style program file)", "O950"] + body + ["M99", "O951", "G0 Y9", "M99"]
        files["subs/950.ngc" if on_path else "950.ngc"] = "\n".join(number_file) + "\n"
    m98_targets = ["800", "810", "900", "950", "800"]
    for f in range(draw(st.integers(1, 2))):
        fname = f"macro{f}"
        helpers = []
        for h in range(draw(st.integers(1, 3))):
            if draw(st.booleans()):
                helpers.append(f"<{fname}_h{h}>")
            else:
                helpers.append(f"{500 + 10 * f + h}")
        order = draw(st.permutations(helpers + [f"<{fname}>"]))
        called = []  # helpers the main sub calls (defined once it has run)
        lines = [draw(st.sampled_from(["(a probing macro)", "; macro file", ""]))]
        for pos, name in enumerate(order):
            later = [n for n in order[pos + 1 :] if n != f"<{fname}>"]
            earlier = [n for n in order[:pos] if n != f"<{fname}>"]
            # mostly helpers defined further on (found by reading forward),
            # sometimes one defined before its caller (rs274 fails)
            callable_ = later + (earlier if draw(st.integers(0, 4)) == 0 else [])
            lines.append(f"o{name} sub")
            if name == f"<{fname}>":
                body = _file_sub_body(draw, 2, [])
                for callee in draw(st.lists(st.sampled_from(callable_), max_size=3)) if callable_ else []:
                    called.append(callee)
                    body.append(f"o{callee} call [#1 + 1] [#2]")
                    body.append(f"(DEBUG, {callee} gave #<_value> #<_value_returned>)")
                if draw(st.integers(0, 2)) == 0:
                    # an M98 read in the macro file (its own Fanuc program
                    # mostly, sometimes one it cannot find from there)
                    target = f"{800 + 10 * f}" if draw(st.booleans()) else draw(st.sampled_from(m98_targets))
                    times = draw(st.sampled_from(["", "", " L2", " L0"]))
                    body.append(f"M98 P{target}{times}")
                if draw(st.integers(0, 3)) == 0:
                    # a numbered sub written inside the main sub: run in the
                    # call, its sub line does nothing and its endsub returns
                    inner = f"{700 + f}"
                    body += [f"o{inner} sub", f"  G1 Z[#1 + 1] F20", f"o{inner} endsub [#1]"]
                    body.append(f"o{inner} call [3]")
                for line in body:
                    lines.append("  " + line)
                value = draw(st.sampled_from(["", " [#1 + #2]", " [#<_seen>]"]))
                lines.append(f"o{name} endsub{value}")
            else:
                for line in _file_sub_body(draw, 2, callable_):
                    lines.append("  " + line)
                if draw(st.integers(0, 3)) == 0:
                    lines.append(f"  o{name} return [#1 * 3]")
                value = draw(st.sampled_from(["", " [#1]", " [#2 + 1]"]))
                lines.append(f"o{name} endsub{value}")
            if draw(st.integers(0, 2)) == 0:
                lines.append("")
        if fanuc_in_file[f]:
            lines += [f"O{800 + 10 * f}"] + _fanuc_body(draw) + ["M99"]
        lines.append(draw(st.sampled_from(["M2", "M2", "(no end)"])))
        if draw(st.integers(0, 4)) == 0:
            # between % lines: under a demarcated main program any lone %
            # ends what rs274 reads; under another it is an ordinary line
            lines = ["%"] + lines + ["%"]
        path = f"subs/{fname}.ngc" if on_path else f"{fname}.ngc"
        files[path] = "\n".join(lines) + "\n"
        # the macro, then helpers called from outside: mostly ones the macro
        # has defined by then
        outside_calls.append(
            [f"<{fname}>"]
            + [n for n in helpers if draw(st.integers(0, 1 if n in called else 5)) == 0]
        )
    # the main program: its own sub with a value read past its definition,
    # the macros called (in a loop, or not), helpers called from outside
    if draw(st.booleans()):
        main_lines += [
            "o<local> sub",
            "  G0 X#1",
            f"o<local> endsub [{draw(st.sampled_from(['7', '#<_seen> + 1', '#1 * 2']))}]",
            "(DEBUG, after local #<_value> #<_value_returned>)",
        ]
    first = outside_calls[0][0]
    if draw(st.integers(0, 3)) == 0:
        main_lines.append(f"M98 P{draw(st.sampled_from(m98_targets))}")
    if draw(st.booleans()):
        main_lines += ["o10 repeat [2]", f"  o{first} call [1] [2]", "o10 endrepeat"]
    else:
        main_lines.append(f"o{first} call [1] [2]")
    main_lines.append("(DEBUG, macro gave #<_value> #<_value_returned>)")
    order = []
    for group in draw(st.permutations(outside_calls)):
        order += group[:1] + draw(st.permutations(group[1:]))
    for name in order:
        main_lines.append(f"o{name} call [{draw(st.integers(0, 9))}] [1]")
        main_lines.append("(DEBUG, #<_value> #<_value_returned> #<_seen>)")
    if draw(st.integers(0, 3)) == 0:
        main_lines.append(f"M98 P{draw(st.sampled_from(m98_targets))}")
    main_lines.append("M2")
    if fanuc_in_main:
        main_lines += ["O900"] + _fanuc_body(draw) + ["M99"]
    if draw(st.integers(0, 4)) == 0:
        main_lines = ["%"] + main_lines + ["%"]
    files["main.ngc"] = "\n".join(main_lines) + "\n"
    args = []
    if on_path:
        files["subs.ini"] = "[RS274NGC]\nSUBROUTINE_PATH = subs\n"
        args = ["-i", "subs.ini"]
    if draw(st.integers(0, 2)) == 0:
        # block-deleted lines (O-lines, M98 and M99 among them), run with
        # and without -b: with it rs274 reads them as empty lines, and the
        # O-words of a subroutine file or a Fanuc-style file pair otherwise
        for path in sorted(p for p in files if p.endswith(".ngc")):
            lines = files[path].split("\n")
            for at in draw(st.lists(st.integers(0, len(lines) - 1), max_size=3)):
                if lines[at].strip() not in ("", "%") and not lines[at].startswith("/"):
                    lines[at] = "/" + lines[at]
            files[path] = "\n".join(lines)
        # each -b flips block delete, as rs274's option loop does
        args += ["-b"] * draw(st.sampled_from([0, 1, 1, 2, 3]))
    return files, args


# --------------------------------------------------------------------------
# rotary axes the INI makes special (runtime/rotary.py)
# --------------------------------------------------------------------------

#: WRAPPED_ROTARY values: rs274 reads an int (lexical_cast): 2 and -1 wrap,
#: "yes", "1.0" and a number past 32 bits leave it off.
WRAPPED_VALUES = ["1", "1", "0", "2", "-1", "yes", "1.0", "4294967297", ""]
#: LOCKING_INDEXER_JOINT values: rs274 takes atol's int, -1 meaning none.
INDEXER_VALUES = ["4", "0", "3abc", "abc", "-1", "-2", "4294967295", ""]


@st.composite
def rotary_inis(draw) -> str:
    """INI texts: some of A, B, C wrapped and/or locking indexers (odd
    values too), now and then under the old [AXIS_3]..[AXIS_5] names, which
    rs274 2.9 does not read."""
    sections = []
    for letter, joint in zip("ABC", "345"):
        lines = []
        if draw(st.integers(0, 2)):
            lines.append("WRAPPED_ROTARY = " + draw(st.sampled_from(WRAPPED_VALUES)))
        if draw(st.integers(0, 3)) == 0:
            lines.append("LOCKING_INDEXER_JOINT = " + draw(st.sampled_from(INDEXER_VALUES)))
        if lines:
            name = joint if draw(st.integers(0, 9)) == 0 else letter
            sections.append(f"[AXIS_{name}]\n" + "\n".join(lines) + "\n")
    extra = ""
    if draw(st.booleans()):
        extra = "[EMCIO]\nTOOL_CHANGE_AT_G30 = 1\n"
    return "".join(draw(st.permutations(sections))) + extra


def _angle(draw, small: bool) -> str:
    """An A/B/C value: mostly within a turn, at times a turn or more
    (rs274's "Invalid absolute position" for a wrapped axis), -0 too."""
    if small or draw(st.integers(0, 4)):
        value = draw(st.sampled_from(["0", "-0", "10", "-10", "90", "180", "-180", "359.9999", "-359.9999", "45.5"]))
        return value if draw(st.integers(0, 2)) else fmt(draw(st.floats(-359.9, 359.9)), 1)
    return draw(st.sampled_from(["360", "-360", "400", "-720.5", "1000"]))


def _rotary_words(draw, small: bool) -> str:
    letters = draw(st.lists(st.sampled_from("ABC"), min_size=1, max_size=2, unique=True))
    return " ".join(letter + _angle(draw, small) for letter in sorted(letters))


@st.composite
def rotary_programs(draw, max_statements: int = 14) -> tuple:
    """(files, args): a program of A/B/C moves (G0 G1 G2 G3, G91, G53,
    G28/G30 and G28.1/G30.1, G92/G52, G10 L2/L20, canned cycles and probes
    with A words, M6 at G30, path control modes) run with an INI from
    :func:`rotary_inis`. Reference points stay within a turn: beyond it rs274
    homes a wrapped axis to a value it never computed."""
    ini = draw(rotary_inis())
    lines = ["G21 G90 G17 F100"]
    for _ in range(draw(st.integers(1, max_statements))):
        kind = draw(st.integers(0, 15))
        xy = draw(st.sampled_from(["", "", "X1 ", "Y-2 ", "X3 Y1 "]))
        rotary = _rotary_words(draw, draw(st.booleans()))
        if kind <= 3:
            lines.append(f"{draw(st.sampled_from(['G0', 'G0', 'G1', '']))} {xy}{rotary}".strip())
        elif kind == 4:
            lines.append(f"G{draw(st.sampled_from(['2', '3']))} X1 Y0 I0.5 J0 {rotary}")
            lines.append("G0 X0 Y0")
        elif kind == 5:
            lines += ["G91", f"G0 {rotary}", "G90"]
        elif kind == 6:
            lines.append(f"G53 G0 {xy}{rotary}")
        elif kind == 7:
            lines.append(f"G{draw(st.sampled_from(['28', '30']))} {draw(st.sampled_from(['', xy, rotary]))}".strip())
        elif kind == 8:
            lines.append(draw(st.sampled_from(["G28.1", "G30.1"])))
        elif kind == 9:
            lines.append(f"{draw(st.sampled_from(['G92', 'G52']))} {rotary}")
            if draw(st.booleans()):
                lines.append(draw(st.sampled_from(["G92.1", "G92.2", "G52 A0 B0 C0"])))
        elif kind == 10:
            lines.append(f"G10 L{draw(st.sampled_from(['2', '20']))} P{draw(st.integers(0, 2))} {rotary}")
        elif kind == 11 and draw(st.integers(0, 3)) == 0:  # an error always
            lines.append(f"G81 X1 Y1 Z-1 R1 {rotary}")
            lines.append("G80")
        elif kind in (11, 12):
            lines.append(f"G38.{draw(st.sampled_from(['2', '3']))} X{draw(st.integers(1, 5))} {rotary}")
            lines.append("(debug, probe #5061 #5064 #5065 #5066)")
        elif kind == 13:
            axis = draw(st.sampled_from(["5164", "5165", "5166", "5184", "5185", "5186"]))
            lines.append(f"#{axis} = {_angle(draw, True)}")
        elif kind == 14:
            lines.append(draw(st.sampled_from(["G64 P0.5 Q0.1", "G64", "G61", "G61.1"])))
        else:
            lines.append(f"T{draw(st.integers(0, 2))} M6")
        if draw(st.integers(0, 3)) == 0:
            lines.append("(debug, at #5420 #5423 #5424 #5425 ref #5164 #5165 #5184)")
    lines.append("M2")
    files = {"prog.ngc": "\n".join(lines) + "\n", "rotary.ini": ini}
    return files, ["-i", "rotary.ini"]
# several spindles: [TRAJ]SPINDLES and the $ word
# --------------------------------------------------------------------------

#: SPINDLES values for an INI file: the usual ones, and the odd ones rs274
#: takes as they are (none, negative, past its eight) or refuses (not a
#: plain int: one spindle).
SPINDLE_COUNTS = ["1", "2", "3", "4", "8"]
ODD_SPINDLE_COUNTS = ["0", "-1", "9", "12", "2.5", "abc", "+2"]


def spindles_ini(count: str) -> str:
    return f"[TRAJ]\nSPINDLES = {count}\n"


def _spindle_number(count: str) -> int:
    """The number of spindles rs274 reads from ``SPINDLES = count``."""
    try:
        return int(count)
    except ValueError:
        return 1


class _SpindleWriter:
    """Lines of spindle codes for a machine of ``count`` spindles."""

    def __init__(self, draw, count: int):
        self.draw = draw
        self.count = count
        self.lines: List[str] = []

    def dollar(self, all_allowed: bool = True) -> str:
        """A $ word: mostly a spindle the machine has (or -1, "all"),
        sometimes one it has not, sometimes a fraction rs274 truncates;
        sometimes none."""
        draw = self.draw
        kind = draw(st.integers(0, 24))
        if kind < 4:
            return ""
        if kind == 4:
            return f" ${draw(st.sampled_from([-2, self.count, self.count + 1, 9]))}"
        if kind == 5:
            return f" ${draw(st.sampled_from(['-0.9', '0.5', '1.7', '-1.2']))}"
        low = -1 if all_allowed and draw(st.integers(0, 3)) == 0 else 0
        return f" ${draw(st.integers(low, max(self.count - 1, 0)))}"

    def speed(self) -> str:
        return f"S{self.draw(numbers(0, 3000, 1))}"

    def turn(self) -> None:
        code = self.draw(st.sampled_from(["M3", "M4", "M5", "M3", "M4"]))
        speed = self.speed() + " " if self.draw(st.booleans()) else ""
        self.lines.append(f"{speed}{code}{self.dollar()}")

    def mode(self) -> None:
        code = self.draw(st.sampled_from(["G96", "G97", "G95", "G94", "G93"]))
        extra = f" D{self.draw(numbers(1, 5000, 1))}" if code == "G96" and self.draw(st.booleans()) else ""
        self.lines.append(f"{code} {self.speed()}{self.dollar(False)}{extra}")
        if code in ("G95", "G93"):
            # a move under the mode: G95 reads the active spindle's speed
            self.lines.append(f"G1 X{self.draw(numbers(-20, 20, 1))} F{self.draw(numbers(1, 20, 10))}")
            if self.draw(st.booleans()):
                self.lines.append(f"G2 X0 Y0 R{self.draw(numbers(20, 40, 1))} F1")
            self.lines.append("G94 F100")

    def orient(self) -> None:
        words = [f"R{self.draw(numbers(0, 360, 1))}"]
        if self.draw(st.booleans()):
            words.append(f"P{self.draw(st.integers(0, 2))}")
        if self.draw(st.booleans()):
            words.append(f"Q{self.draw(numbers(1, 30, 10))}")
        self.lines.append("M19 " + " ".join(words) + self.dollar(False))

    def overrides(self) -> None:
        kind = self.draw(st.integers(0, 3))
        if kind == 0:
            self.lines.append(self.draw(st.sampled_from(["M48", "M49"])))
        elif kind == 1:
            self.lines.append(f"M50 P{self.draw(st.integers(0, 1))}")
        else:
            self.lines.append(f"M51 P{self.draw(st.integers(0, 1))}{self.dollar(False)}")

    def tool_change(self) -> None:
        self.lines.append(self.draw(st.sampled_from(["T1 M6", "T2 M6", "T0 M6", "M61 Q1"])))

    def thread(self) -> None:
        kind = self.draw(st.integers(0, 2))
        if kind == 0:
            line = f"G33 X{self.draw(numbers(-10, 10, 1))} K{self.draw(numbers(1, 20, 10))}"
        elif kind == 1:
            line = f"G33.1 Z{self.draw(numbers(-10, -1, 1))} K{self.draw(numbers(1, 20, 10))}"
        else:
            line = "G76 P0.1 Z-1 I-0.1 J0.05 K0.1"
        self.lines.append(line + self.dollar(False))
        self.lines.append("G0 X0 Y0 Z0")

    def cycle(self) -> None:
        draw = self.draw
        plane = draw(st.sampled_from(["G17", "G18", "G19"]))
        code = draw(st.sampled_from(["G84", "G74", "G86", "G87", "G88"]))
        words = {"G17": "X1 Y1 Z-1", "G18": "X1 Y-1 Z1", "G19": "X-1 Y1 Z1"}[plane]
        extra = {"G86": " P1", "G88": " P0.5", "G87": " I1 J1 K-0.5"}.get(code, "")
        # $ needs a word that uses it on the line: S or a spindle M code
        user = draw(st.sampled_from([" S100", " M3", " M4", ""]))
        dollar = self.dollar(False) if user else ""
        self.lines.append(f"{plane} {code} {words} R2{extra} F10{user}{dollar}")
        if draw(st.booleans()):
            self.lines.append("X2")
        self.lines.append("G80 G17 G0 X0 Y0 Z0")

    def report(self) -> None:
        self.lines.append(
            "(debug,#<_spindle_on> #<_spindle_cw> #<_rpm> #<_speed_override>"
            " #<_spindle_css_mode> #<_spindle_rpm_mode>)"
        )

    def modal_save(self) -> None:
        self.lines.append("M70")
        self.turn()
        self.mode()
        self.lines.append("M72")


@st.composite
def spindle_programs(draw, count: int = 2, max_statements: int = 10) -> str:
    """A program of spindle codes with $ words, for a machine of ``count``
    spindles: M3-M5 and S for one or every spindle, G93-G97, M19, the
    override switches, tool changes, threading and the cycles that turn
    the spindle, and reports of the spindle parameters; then M2 or M30,
    which stop every spindle. Some $ words name a spindle the machine does
    not have (rs274's errors)."""
    w = _SpindleWriter(draw, count)
    w.lines.append(draw(st.sampled_from(["G21 G90 G17 G94 F100", "G20 G90 F10"])))
    steps = [w.turn] * 4 + [w.mode] * 2 + [w.orient, w.overrides, w.overrides, w.tool_change]
    steps += [w.thread, w.cycle, w.report, w.report, w.modal_save]
    for _ in range(draw(st.integers(1, max_statements))):
        draw(st.sampled_from(steps))()
    w.lines.append(draw(st.sampled_from(["M2", "M30"])))
    return "\n".join(w.lines) + "\n"


@st.composite
def spindle_ini_programs(draw) -> tuple:
    """(program, SPINDLES value): spindle programs for any INI setting,
    the odd values among them."""
    count = draw(st.sampled_from(SPINDLE_COUNTS + ODD_SPINDLE_COUNTS))
    return draw(spindle_programs(_spindle_number(count))), count


@st.composite
def valid_spindle_programs(draw) -> tuple:
    """(program, SPINDLES value): valid_programs() (whose $ words are 0 or
    -1) on a machine of several spindles, where M2, M6, M48/M49, M51 and
    $-1 reach every spindle."""
    count = draw(st.sampled_from(SPINDLE_COUNTS + ODD_SPINDLE_COUNTS))
    return draw(valid_programs(feed_modes=True)), count
