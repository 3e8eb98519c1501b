"""Hypothesis strategies that write G-code programs for differential testing.

``valid_programs()`` writes programs that rs274 runs to the end: motion with
arcs built so they are always geometrically valid, parameters (numbered,
named local, named global) and expressions that cannot fail (no division by
a value that may be zero, no roots of negatives), subroutines with arguments
and return values, loops with bounded iteration counts, comments of every
active kind, and modal changes (units, distance mode, planes, coordinate
systems, offsets, spindle, coolant, path control), and the rest of the
language: tool changes and length offsets, G10 L1/L10/L11, M19, override
switches, digital/analog I/O and M66, M70-M73, (py,...) comments, Fanuc
M98 calls (also as a computed M value).

``invalid_programs()`` takes such a program and breaks one line: junk
characters, unbalanced brackets, unknown letters, repeated words, bad or
mismatched O-words, undefined parameters, arithmetic errors, truncation. The
result may or may not be an error in rs274 -- the point is that ngc2py must
behave the same either way.

Everything is drawn through Hypothesis, so examples shrink to small programs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import List

from hypothesis import strategies as st

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

    def __init__(self, draw):
        self.draw = draw
        self.lines: List[str] = []
        self.label = 100
        self.scope = Scope()
        self.dist = 90
        self.subs: List[tuple] = []  # (name, nargs, returns)
        self.depth = 0
        self.fanuc = False  # a Fanuc subroutine O9001 follows the program end

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
    if chord > 1.0 and w.draw(st.integers(0, 3)) == 0:
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
    kind = w.draw(st.integers(0, 11))
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
        w.emit(f"S{w.draw(numbers(0, 5000, 1))} {w.draw(st.sampled_from(['M3', 'M4', 'M5']))}")
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
    else:
        w.emit(w.draw(st.sampled_from(["G52 X1 Y2", "G52 X0 Y0", "G30.1", "M0", "M1", "M60"])))


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
            f"G43.2 Z{w.draw(numbers())}",
        ])))
    elif kind == 1:
        letter = w.draw(st.sampled_from(["Z", "X", "Z", "R", "I", "J"]))
        level = w.draw(st.sampled_from(["1", "10", "11"]))
        words = f"{letter}{w.draw(numbers(0, 100, 10))}"
        if level == "1" and w.draw(st.booleans()):
            words += f" Q{w.draw(st.integers(0, 9))}"
        w.emit(f"G10 L{level} P{max(tool, 1)} {words}")
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
        ])))
    elif kind == 8:
        # a Fanuc call: M98 P9001 (the sub follows the program end), also
        # as a computed M value
        w.fanuc = True
        if w.draw(st.booleans()):
            w.emit(f"M98 P9001 L{w.draw(st.integers(0, 2))}" if w.draw(st.booleans())
                   else "M98 P9001")
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


def stmt(w: Writer, nested: bool = False) -> None:
    weights = [
        (stmt_move, 6),
        (stmt_arc, 3),
        (stmt_assign, 4),
        (stmt_comment, 2),
        (stmt_modal, 3),
        (stmt_call, 2),
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
    w.depth -= 1
    if returns:
        w.emit(f"o{name} endsub [{w.expr(1)}]")
    else:
        w.emit(f"o{name} endsub")
    w.scope = saved_scope
    w.subs.append((label if name.startswith("<") else name, nargs, returns))


@st.composite
def valid_programs(draw, max_statements: int = 12) -> str:
    """A whole program, as text, that rs274 accepts."""
    w = Writer(draw)
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
