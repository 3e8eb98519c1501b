"""Long core-language programs, and the same programs with one mistake.

Written from the G Code Overview's line format and the O Codes chapter of
the LinuxCNC documentation, not from ngc2py's implementation:

* many subroutines (numbered and named), each defined before it is called,
  calling earlier ones with arguments (``#1``..``#n`` in the callee) and
  returning values (``#<_value>``); call chains stay within rs274's ten
  levels;
* while/endwhile, do/while, repeat/endrepeat and if/elseif/else/endif nested
  deeply in every combination, with break and continue (of any enclosing
  while or do loop) and return at every depth;
* numbered parameters (``#1``-``#30`` local to a call, ``#31`` and up
  global), named locals and ``#<_globals>``;
* every line may carry a block delete slash, an N number, comments (empty,
  plain, MSG, DEBUG, PRINT; only the last acts) and a ``;`` comment; O-word
  lines carry N numbers and comments too.

Every loop terminates: its counter is incremented first in its body and a
``continue`` is always guarded by that counter, so the condition is
re-tested with a larger count. The estimated number of lines run is kept
bounded (loop counts and calls multiply it).

The random choices go through a *chooser* (``randint``, ``pick``), so the
same generator serves Hypothesis (``strategies.long_programs``) and plain
seeded ``random.Random`` runs.
"""

from __future__ import annotations

from typing import List, Optional, Tuple

COMMENTS = [
    "()",
    "( )",
    "(plain comment)",
    "(MSG,long program message)",
    "(msg, lower case)",
    "(DEBUG,g=#<_g> n=#31)",
    "(DEBUG,line #<_line>)",
    "(debug,)",
    "(PRINT,printed #<_g>)",
    "(first) (DEBUG,second #31)",
    "(MSG,ignored) ()",
    "() (PRINT,after empty)",
]

SEMICOLONS = ["; trailing note", ";", "; (not a comment"]

#: the most lines a program may run (estimated); rs274 stays quick
BUDGET = 4000


class Sub:
    def __init__(self, name: str, nargs: int, cost: int, level: int):
        self.name = name  # as written after o, e.g. "<s3>" or "1003"
        self.nargs = nargs
        self.cost = cost  # estimated lines run by one call
        self.level = level  # call depth it reaches (1: calls nothing)


class LongWriter:
    """Writes one long program through a chooser."""

    def __init__(self, rnd, block_delete: bool = False):
        self.r = rnd
        self.block_delete = block_delete
        self.lines: List[str] = []
        self.depth = 0  # indentation only
        self.next_label = 100
        self.next_counter = 0
        self.subs: List[Sub] = []
        # state of the body being written
        self.sub: Optional[str] = None
        self.nargs = 0
        self.loops: List[Tuple[str, str, str, int]] = []  # (label, kind, counter, count)
        self.counters: List[str] = []
        self.locals: List[str] = []
        self.mult = 1  # how often the current line runs per entry of the body
        self.cost = 0  # estimated lines run by the body
        self.level = 1
        self.max_nest = 12
        self.room = 0  # no new nesting once the body has this many lines
        self.value_only = False  # a return value: no local names (value)

    # -- choices --------------------------------------------------------
    def randint(self, a: int, b: int) -> int:
        return self.r.randint(a, b)

    def pick(self, seq):
        return self.r.pick(seq)

    def chance(self, n: int) -> bool:
        return self.r.randint(0, n - 1) == 0

    # -- lines ----------------------------------------------------------
    def nword(self) -> str:
        if not self.chance(3):
            return ""
        n = self.randint(0, 99999)
        return self.pick([f"N{n} ", f"n{n} ", f"N{n:05d}", f"N{n} "])

    def tail(self) -> str:
        parts = []
        if self.chance(4):
            parts.append(self.pick(COMMENTS))
        if self.chance(8):
            parts.append(self.pick(SEMICOLONS))
        return (" " + " ".join(parts)) if parts else ""

    def line(self, body: str, oword: bool = False, slash: bool = True) -> None:
        """[/][N..] body [comments]; the slash only where skipping the line
        keeps the program's termination intact: an O-word line rarely, and
        never a break or continue (a loop's only way out). Under -b rs274
        reads a deleted O-word line as a blank one, so its construct no
        longer nests (ngc2py/lineflow.py)."""
        prefix = ""
        if slash and not oword and self.chance(10):
            prefix = "/"
        elif slash and oword and self.chance(60):
            if " break" not in body and " continue" not in body:
                prefix = "/"
        self.lines.append("  " * self.depth + prefix + self.nword() + body + self.tail())
        self.cost += self.mult

    def bare(self, text: str) -> None:
        self.lines.append("  " * self.depth + text)
        self.cost += self.mult

    # -- values ---------------------------------------------------------
    def ref(self) -> str:
        pool = ["#<_g>", "#31", "#32", "#<_h>"]
        pool += [f"#{i}" for i in range(1, self.nargs + 1)]
        if not self.value_only:
            pool += [f"#<{c}>" for c in self.counters]
            pool += [f"#<{n}>" for n in self.locals]
        return self.pick(pool)

    def value(self) -> str:
        """A return or endsub value: rs274 also reads it as it reads past
        the definition, where a local name is not defined and the value
        is whatever its memory held (interp_namedparams.cc: defining_sub),
        so no local names."""
        self.value_only = True
        try:
            return self.expr(1)
        finally:
            self.value_only = False

    def num(self) -> str:
        v = self.randint(-300, 300) / 10
        return self.pick([f"{v:g}", f"{v:.1f}", f"{v:.3f}"])

    def expr(self, depth: int = 2) -> str:
        if depth <= 0 or self.chance(3):
            return self.ref() if self.chance(2) else self.num()
        a, b = self.expr(depth - 1), self.expr(depth - 1)
        k = self.randint(0, 6)
        if k <= 2:
            return f"[{a} {self.pick(['+', '-', '*'])} {b}]"
        if k == 3:
            return f"[{a} / {self.pick(['2', '4', '-5', '0.5'])}]"
        if k == 4:
            return f"[{a} MOD {self.pick(['3', '7'])}]"
        if k == 5:
            return f"{self.pick(['ABS', 'FIX', 'FUP', 'ROUND', 'SIN', 'COS'])}[{a}]"
        return f"[{a} {self.pick(['EQ', 'NE', 'GT', 'LT', 'GE', 'LE', 'AND', 'OR'])} {b}]"

    def condition(self) -> str:
        options = [f"[{self.ref()} GT {self.num()}]", f"[{self.expr(1)} LT {self.expr(1)}]", "[1]", "[0]", "[1]", "[#<_g> EQ 1]"]
        for c in self.counters:
            options += [f"[#<{c}> EQ 1]", f"[#<{c}> GT 1]", f"[#<{c}> LT 2]"]
        return self.pick(options)

    def label(self) -> str:
        self.next_label += 1
        if self.chance(3):
            return f"<l{self.next_label}>"
        return str(self.next_label)

    # -- statements -----------------------------------------------------
    def plain(self) -> None:
        k = self.randint(0, 11)
        if k == 0:
            self.line(f"G1 X{self.expr(1)} Y{self.num()} F{self.randint(10, 900)}")
        elif k == 1:
            self.line(f"G0 X{self.num()} Z{self.expr(1)}")
        elif k == 2:
            self.line(f"#<_g> = {self.expr()}")
        elif k == 3:
            self.line(f"#{self.randint(31, 40)} = {self.expr()}")
        elif k == 4:
            self.line(f"#<{self.pick(['a', 'b'])}> = {self.expr()}")
        elif k == 5 and self.sub:
            self.line(f"#{self.randint(1, 30)} = {self.expr()}")
            self.nargs = 30  # every #1-#30 is set in a call
        elif k == 6:
            self.bare(self.pick(["", "  ", "/", "()", "(a whole-line comment)", "; only this"]))
        elif k == 7:
            self.line(self.pick(COMMENTS))
        elif k == 8:
            self.line(self.pick(["M3 S1000", "M5", "M8", "M9", "G17", "G4 P0.1", "F300", "S200", "G61", "G64"]))
        elif k == 9:
            self.line(f"G91 G2 X0 Y0 I{self.randint(1, 9)} J0 F100")
            self.line("G90", slash=False)
        elif k == 10:
            self.line(f"(DEBUG,{' '.join(self.ref() for _ in range(self.randint(1, 3)))})")
        else:
            self.line(f"G1 X{self.num()} (inline) Y{self.num()}")

    def call(self) -> None:
        budget_ok = [s for s in self.subs[-6:] if s.cost * self.mult < BUDGET // 4 and s.level < 9]
        if not budget_ok:
            self.plain()
            return
        s = self.pick(budget_ok)
        n = self.randint(0, s.nargs)
        args = "".join(f" [{self.expr(1)}]" for _ in range(n))
        self.line(f"o{s.name} call{args}", oword=True)
        self.cost += s.cost * self.mult
        self.level = max(self.level, s.level + 1)
        if self.chance(3):
            self.line("(DEBUG,returned #<_value> #<_value_returned>)")

    def jump(self) -> None:
        """break / continue of some enclosing while or do, or return."""
        loops = [lp for lp in self.loops if lp[1] != "repeat"]
        if self.sub and (not loops or self.chance(3)):
            value = self.pick(["", f" [{self.value()}]"])
            guard = self.chance(2)
            self._guarded(f"o{self.sub} return{value}", guard)
            return
        if not loops:
            self.plain()
            return
        label, kind, counter, _ = self.pick(loops)
        if self.chance(2):
            self._guarded(f"o{label} break", self.chance(2))
        else:
            # continue only while the counter of its loop is small: the
            # loop's condition is tested again with a larger count
            self._guarded(f"o{label} continue", True, f"[#<{counter}> LT 2]")

    def _guarded(self, text: str, guard: bool, cond: Optional[str] = None) -> None:
        if not guard:
            self.line(text, oword=True)
            return
        lab = self.label()
        self.line(f"o{lab} if {cond or self.condition()}", oword=True)
        self.depth += 1
        self.line(text, oword=True)
        self.depth -= 1
        self.line(f"o{lab} endif", oword=True)

    def if_(self, nest: int) -> None:
        lab = self.label()
        self.line(f"o{lab} if {self.condition()}", oword=True)
        self.body(nest)
        for _ in range(self.randint(0, 2)):
            self.line(f"o{lab} elseif {self.condition()}", oword=True)
            if self.chance(8):
                # a do of the if's label, never closed: the skips of the
                # arms before land on it and run on into the later elseif
                # and else lines (rs274's executed_if flag decides there)
                self.depth += 1
                self.line(f"o{lab} do", oword=True)
                self.depth -= 1
            self.body(nest)
        if self.chance(2):
            self.line(f"o{lab} else", oword=True)
            self.body(nest)
        self.line(f"o{lab} endif", oword=True)

    def loop(self, nest: int) -> None:
        kind = self.pick(["while", "do", "repeat"])
        lab = self.label()
        self.next_counter += 1
        counter = f"c{self.next_counter}"
        room = max(1, BUDGET // (self.mult * 8))
        count = min(self.randint(0, 3), room)
        self.line(f"#<{counter}> = 0", slash=False)
        if kind == "while":
            self.line(f"o{lab} while [#<{counter}> LT {count}]", oword=True)
        elif kind == "do":
            self.line(f"o{lab} do", oword=True)
        else:
            self.line(f"o{lab} repeat [{count}]", oword=True)
        saved = self.mult
        self.mult *= max(1, count + (kind == "do"))
        self.depth += 1
        self.line(f"#<{counter}> = [#<{counter}> + 1]", slash=False)
        self.depth -= 1
        self.loops.append((lab, kind, counter, count))
        self.counters.append(counter)
        self.body(nest)
        self.counters.pop()
        self.loops.pop()
        self.mult = saved
        if kind == "while":
            self.line(f"o{lab} endwhile", oword=True)
        elif kind == "do":
            self.line(f"o{lab} while [#<{counter}> LT {count}]", oword=True)
        else:
            self.line(f"o{lab} endrepeat", oword=True)

    def statement(self, nest: int) -> None:
        options = ["plain"] * 5 + ["call"] * 2
        if nest < self.max_nest and self.mult < BUDGET // 20 and len(self.lines) < self.room:
            options += ["if", "if", "loop", "loop"]
        if self.loops or self.sub:
            options += ["jump"]
        kind = self.pick(options)
        if kind == "plain":
            self.plain()
        elif kind == "call":
            self.call()
        elif kind == "if":
            self.if_(nest + 1)
        elif kind == "loop":
            self.loop(nest + 1)
        else:
            self.jump()

    def body(self, nest: int) -> None:
        self.depth += 1
        # a deep spine now and then: one construct nested in the next
        if nest < self.max_nest and len(self.lines) < self.room and self.chance(3):
            self.pick([self.if_, self.loop])(nest + 1)
        for _ in range(self.randint(1, 3)):
            self.statement(nest)
        self.depth -= 1

    def subroutine(self, index: int) -> None:
        name = self.pick([f"<s{index}>", f"{1000 + index}", f"<Sub_{index}>"])
        nargs = self.randint(0, 4)
        self.sub, self.nargs, self.locals, self.counters = name, nargs, [], []
        self.cost, self.level, self.mult = 0, 1, 1
        self.room = len(self.lines) + self.randint(8, 60)
        self.line(f"o{name} sub", oword=True)
        self.depth += 1
        self.bare("#<a> = 1 #<b> = 2")
        self.locals = ["a", "b"]
        self.depth -= 1
        self.body(0)
        if self.chance(4):
            # last, an if whose only arm ends with a do of its label, never
            # closed: false, the skip lands on the do and the call returns
            # with rs274's flag "an arm of an if has run" clear, which the
            # elseif and else lines of an if around the call then follow
            lab = self.label()
            self.line(f"o{lab} if {self.condition()}", oword=True)
            self.depth += 1
            self.plain()
            self.line(f"o{lab} do", oword=True)
            self.plain()
            self.depth -= 1
        end = f"o{name} endsub" + self.pick(["", f" [{self.value()}]"])
        self.line(end, oword=True)
        label = name.lower() if name.startswith("<") else name
        self.subs.append(Sub(label, nargs, max(self.cost, 1), self.level))
        self.sub = None
        self.nargs = 0

    def program(self, nsubs: int, nmain: int) -> str:
        self.bare("#<_g> = 1")
        self.bare("#<_h> = 2")
        self.bare("#31 = 0")
        self.bare("#32 = 5")
        self.line("G21 G90 G17 F500", slash=False)
        for index in range(nsubs):
            self.subroutine(index)
        self.locals, self.counters = ["a", "b"], []
        self.cost, self.mult = 0, 1
        self.bare("#<a> = 3 #<b> = 4")
        self.room = len(self.lines) + self.randint(20, 150)
        for _ in range(nmain):
            self.statement(0)
            if self.subs and self.chance(2):
                s = self.pick(self.subs)
                if s.cost * self.mult < BUDGET // 4 and s.level < 9:
                    args = "".join(f" [{self.expr(1)}]" for _ in range(s.nargs))
                    self.line(f"o{s.name} call{args}", oword=True)
        self.bare(self.pick(["M2", "M30", "N9999 M2", "M2 ()", "M2 (end)"]))
        return "\n".join(self.lines) + "\n"


def long_program(rnd, min_subs: int = 20, max_subs: int = 60) -> Tuple[str, list]:
    """(text, rs274 options) of one long program."""
    block_delete = rnd.randint(0, 3) == 0
    w = LongWriter(rnd, block_delete)
    text = w.program(rnd.randint(min_subs, max_subs), rnd.randint(5, 20))
    return text, (["-b"] if block_delete else [])


# --------------------------------------------------------------------------
# one mistake in a long program
# --------------------------------------------------------------------------

#: lines that are errors wherever rs274 executes them
MISTAKES = [
    "G1 X1 $",
    "G1 X[1 + 2",
    "G1 X[1 + 2]]",
    "#1 = [1 / 0]",
    "#1 = SQRT[-4]",
    "#1 = LN[0]",
    "#1 = ACOS[2]",
    "#1 = [3 MOD 0]",
    "G1 X#<_undefined_global>",
    "G1 X#<undefined_local>",
    "G0 G1 X1",
    "M3 M4",
    "G20 G21",
    "G6",
    "G100",
    "M200",
    "G1 X1 X2",
    "Q1",
    "G2 X1",
    "G4",
    "G1 U1",
    "#5400 = 1",
    "#0 = 1",
    "#6000 = 1",
    "#<_x> = 1",
    "G92",
    "G10 L9 P1",
    "(unclosed comment",
    "G1 X1 (nested (comment) )",
    "o<nosuch> call",
    "o123456 call",
    "G1 X1 )",
    "G1 X-",
    "G1 X1 E5",
    "SIN[0]",
    "G[1/3]",
    "M[1.5]",
    "X1 G4 P1 G0",
    "N1 N2 G0",
    "G0 @1 X1",
    "#1 = [1 EQ]",
    "#<a b c = 1",
    "#1 = ATAN[1]",
    "#1 = EXP[1000]",
    "G1 F-1",
    "S-10",
    "T-1",
]

#: O-word mistakes; {L} is a label that exists nowhere, {C} one of an
#: enclosing construct, {S} the enclosing subroutine (or a made-up one)
OWORD_MISTAKES = [
    "o{L} endif",
    "o{L} endwhile",
    "o{L} endrepeat",
    "o{L} else",
    "o{L} elseif [1]",
    "o{L} break",
    "o{L} continue",
    "o{L} return",
    "o{L} endsub",
    "o{L} foo",
    "o{L} if",
    "o{L} while",
    "o{L} repeat",
    "o{C} else",
    "o{C} elseif [1]",
    # an elseif's condition is read before its label is looked up
    "o{L} elseif [#<_undefined_c> EQ 1]",
    "o{C} elseif [#<undefined_c> GT 0]",
    "o{C} elseif [1 / 0]",
    # and read where a skip to its label lands (an unreadable one fails)
    "o{C} elseif [[#<",
    "o{C} while [#<_x> LT [1 +]",
    "o{C} endif",
    "o{C} break",
    "o{C} continue",
    "o{C} endwhile",
    "o{C} endrepeat",
    "o{S} endsub",
    "o{S} return [1",
    "o{L} sub",
    "o[1 call",
    "o<unterminated call",
    "o{L}",
]


def error_program(rnd, min_subs: int = 3, max_subs: int = 20) -> Tuple[str, list]:
    """A long program with one mistake: a bad line inserted at a random
    point (any depth, in a subroutine or the main program), a closing
    O-word removed or relabelled, or a line cut short."""
    text, args = long_program(rnd, min_subs, max_subs)
    lines = text.splitlines()
    k = rnd.randint(0, 9)
    # a point after the set-up lines, and before the last one (the end)
    pos = rnd.randint(5, len(lines) - 1)
    indent = lines[pos - 1][: len(lines[pos - 1]) - len(lines[pos - 1].lstrip())]
    if k <= 4:
        bad = rnd.pick(MISTAKES)
        lines.insert(pos, indent + bad)
    elif k <= 7:
        labels = _labels(lines[:pos])
        sub = _enclosing_sub(lines[:pos])
        bad = rnd.pick(OWORD_MISTAKES).format(
            L=rnd.pick(["7777", "<nowhere>"]),
            C=rnd.pick(labels) if labels else "7777",
            S=sub or "<nosub>",
        )
        lines.insert(pos, indent + bad)
    elif k == 8:
        closers = [i for i, ln in enumerate(lines) if _oword_verb(ln) in ("endif", "endwhile", "endrepeat", "endsub", "while", "else")]
        if closers:
            i = rnd.pick(closers)
            if rnd.randint(0, 1):
                del lines[i]
            else:
                lines[i] = lines[i].replace("o", "o9", 1)
        else:
            lines.insert(pos, indent + rnd.pick(MISTAKES))
    else:
        i = rnd.randint(5, len(lines) - 2)
        stripped = lines[i].rstrip()
        if len(stripped) > 3:
            lines[i] = stripped[: rnd.randint(2, len(stripped) - 1)]
    return "\n".join(lines) + "\n", args


def _oword_verb(line: str) -> str:
    words = line.strip().lstrip("/").split()
    while words and words[0][:1] in "Nn" and words[0][1:].isdigit():
        words = words[1:]
    if len(words) >= 2 and words[0][:1] in "oO":
        return words[1].lower()
    return ""


def _labels(lines: List[str]) -> List[str]:
    found = []
    for ln in lines:
        verb = _oword_verb(ln)
        if verb in ("if", "while", "do", "repeat"):
            words = ln.strip().lstrip("/").split()
            while words[0][:1] in "Nn":
                words = words[1:]
            found.append(words[0][1:])
    return found


def _enclosing_sub(lines: List[str]) -> Optional[str]:
    name = None
    for ln in lines:
        verb = _oword_verb(ln)
        words = ln.strip().split()
        while words and words[0][:1] in "Nn" and words[0][1:].isdigit():
            words = words[1:]
        if verb == "sub":
            name = words[0][1:]
        elif verb == "endsub":
            name = None
    return name


class RandomChooser:
    """The chooser interface over random.Random."""

    def __init__(self, seed):
        import random

        self.random = random.Random(seed)

    def randint(self, a: int, b: int) -> int:
        return self.random.randint(a, b)

    def pick(self, seq):
        return self.random.choice(list(seq))
