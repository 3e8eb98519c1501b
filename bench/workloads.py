"""The benchmark programs, generated (never stored): each a function of size.

Deterministic: the same size gives the same program, so runs compare.
"""

from __future__ import annotations

import math
import random


def cam(moves: int) -> str:
    """CAM output: straight moves in passes, rapids between them, F changes."""
    rng = random.Random(moves)
    lines = ["(synthetic CAM output)", "G21 G90 G17 G94", "G0 X0 Y0 Z5", "G1 Z-1 F800"]
    for k in range(moves):
        if k % 500 == 499:
            lines += [
                "G0 Z5",
                "X%.3f Y%.3f" % (rng.uniform(0, 100), rng.uniform(0, 80)),
            ]
            lines.append(
                "G1 Z%.3f F%d" % (-rng.uniform(0.5, 3), rng.choice((600, 800, 1200)))
            )
            continue
        x = (k * 7919 % 100000) / 1000.0
        y = (k * 104729 % 80000) / 1000.0
        lines.append("X%.3f Y%.3f" % (x, y))
    lines += ["G0 Z5", "M2"]
    return "\n".join(lines) + "\n"


def arcs(count: int) -> str:
    """Centre-format arcs (IJ), alternating direction, with a helical Z."""
    lines = ["(many arcs)", "G21 G90 G17 F600", "G0 X10 Y0"]
    for k in range(count):
        code = "G3" if k % 2 == 0 else "G2"
        lines.append(f"{code} X10 Y0 I-10 J0 Z{-(k % 10) / 10:.1f}")
    lines.append("M2")
    return "\n".join(lines) + "\n"


def cam_arcs(count: int) -> str:
    """CAM-style contouring: arcs whose centres, radii and sweeps vary from
    row to row, in IJ and R form, some helical, between straight moves, with
    a feed change now and then (what a CAM post writes for a 2.5D profile)."""
    rng = random.Random(count)
    lines = [
        "(CAM arcs, varying geometry)",
        "G21 G90 G17 G94",
        "G0 X0 Y0 Z5",
        "G1 Z-1 F700",
    ]
    x = y = 0.0
    z = -1.0
    for k in range(count):
        if k % 400 == 399:
            lines.append("G1 X%.4f Y%.4f F%d" % (x, y, rng.choice((500, 700, 900))))
            continue
        radius = rng.uniform(0.5, 40.0)
        start = rng.uniform(-3.14159, 3.14159)
        sweep = rng.uniform(0.2, 2.8)
        ccw = rng.random() < 0.5
        cx, cy = x - radius * math.cos(start), y - radius * math.sin(start)
        end = start + (sweep if ccw else -sweep)
        ex, ey = cx + radius * math.cos(end), cy + radius * math.sin(end)
        code = "G3" if ccw else "G2"
        helix = ""
        if k % 7 == 3:
            z = -rng.uniform(0.2, 3.0)
            helix = " Z%.4f" % z
        if k % 3 == 0:
            # R form: the short way round, so |sweep| stays below 180 degrees
            lines.append("%s X%.4f Y%.4f R%.4f%s" % (code, ex, ey, radius, helix))
        else:
            lines.append(
                "%s X%.4f Y%.4f I%.4f J%.4f%s" % (code, ex, ey, cx - x, cy - y, helix)
            )
        x, y = round(ex, 4), round(ey, 4)
        if k % 5 == 4:
            x, y = x + rng.uniform(-2, 2), y + rng.uniform(-2, 2)
            lines.append("G1 X%.4f Y%.4f" % (x, y))
            x, y = round(x, 4), round(y, 4)
    lines += ["G0 Z5", "M2"]
    return "\n".join(lines) + "\n"


def drill_cycles(holes: int) -> str:
    """Canned cycles as a CAM post writes them: every drilling cycle (G81,
    G82, G83, G73, G84, G85, G86, G88, G89) with R, Q, P and sometimes L,
    G98 and G99 retracts, and rows of holes as bare X Y lines."""
    rng = random.Random(holes)
    lines = ["(canned cycles)", "G21 G90 G17 G94", "G0 Z20", "M3 S1200", "F250"]
    cycles = (
        "G81",
        "G82 P0.2",
        "G83 Q1.2",
        "G73 Q0.8",
        "G84 P0.1",
        "G85",
        "G86 P0.3",
        "G88 P0.1",
        "G89 P0.2",
    )
    k = 0
    group = 0
    while k < holes:
        cycle = cycles[group % len(cycles)]
        retract = "G98" if group % 2 else "G99"
        depth = -rng.uniform(2, 12)
        clear = rng.uniform(1, 4)
        x, y = rng.uniform(0, 200), rng.uniform(0, 150)
        repeat = " L%d" % rng.randint(2, 4) if group % 11 == 5 else ""
        if cycle.startswith("G84"):
            lines.append("M3 S%d" % rng.choice((300, 400, 500)))
        if group % 11 == 5:
            lines.append("G91")
            lines.append(
                "%s %s X5 Y0 Z%.3f R%.3f%s" % (retract, cycle, depth, clear, repeat)
            )
            lines.append("G90")
        else:
            lines.append(
                "%s %s X%.3f Y%.3f Z%.3f R%.3f" % (retract, cycle, x, y, depth, clear)
            )
        k += 1
        for _ in range(rng.randint(10, 40)):
            if k >= holes:
                break
            x += rng.choice((5.0, 7.5, 10.0))
            lines.append("X%.3f Y%.3f" % (x, y + rng.uniform(-0.5, 0.5)))
            k += 1
        lines.append("G80")
        group += 1
    lines += ["M5", "G0 Z20", "M2"]
    return "\n".join(lines) + "\n"


def drill_lines(holes: int) -> str:
    """Canned cycles as other posts write them: every hole a cycle line of
    its own (``G99 G81 X.. Y.. Z-3 R2``, then the same line at the next
    hole), a few hundred holes of each cycle and retract mode before the
    next, with now and then a G80 and a move between."""
    rng = random.Random(holes)
    lines = [
        "(canned cycles, a line a hole)",
        "G21 G90 G17 G94",
        "G0 Z20",
        "M3 S1200",
        "F250",
    ]
    cycles = ("G81", "G82 P0.2", "G83 Q1.2", "G73 Q0.8", "G85", "G86 P0.3", "G89 P0.2")
    k = 0
    group = 0
    while k < holes:
        cycle = cycles[group % len(cycles)]
        retract = "G98" if group % 2 else "G99"
        levels = "Z%.3f R%.3f" % (-rng.uniform(2, 12), rng.uniform(1, 4))
        for _ in range(rng.randint(100, 400)):
            if k >= holes:
                break
            x, y = rng.uniform(0, 200), rng.uniform(0, 150)
            lines.append("%s %s X%.3f Y%.3f %s" % (retract, cycle, x, y, levels))
            k += 1
        lines += ["G80", "G0 Z20"]
        group += 1
    lines += ["M5", "M2"]
    return "\n".join(lines) + "\n"


def numbered(text: str) -> str:
    """``text`` with every line numbered N10, N20..., as posts that number
    their lines write it (comments left as they are)."""
    lines = text.splitlines()
    number = 0
    for k, line in enumerate(lines):
        if line and not line.startswith("("):
            number += 10
            lines[k] = "N%d %s" % (number, line)
    return "\n".join(lines) + "\n"


def drill_cycles_numbered(holes: int) -> str:
    """:func:`drill_cycles` with every line numbered."""
    return numbered(drill_cycles(holes))


def cam_numbered(moves: int) -> str:
    """:func:`cam` with every line numbered."""
    return numbered(cam(moves))


def cam_arcs_numbered(count: int) -> str:
    """:func:`cam_arcs` with every line numbered."""
    return numbered(cam_arcs(count))


def shop(lines: int) -> str:
    """What shops' programs add to CAM rows, each a tenth or more of the
    lines: moves and arcs with a comment, modes restated on every line
    (G90 G1, G17 G2) and holes drilled a line at a time with a G4 pause."""
    rng = random.Random(lines)
    out = ["(shop program)", "G21 G90 G17 G94", "G0 Z5", "M3 S1500", "G1 Z-1 F600"]
    x = y = 0.0
    k = 0
    while len(out) < lines:
        kind = k % 4
        k += 1
        for _ in range(rng.randint(10, 30)):
            x, y = rng.uniform(0, 150), rng.uniform(0, 100)
            if kind == 0:
                out.append("G1 X%.3f Y%.3f (pass %d)" % (x, y, k))
            elif kind == 1:
                out.append("G90 G1 X%.3f Y%.3f" % (x, y))
            elif kind == 2:
                ex, ey = x + rng.uniform(-5, 5), y + rng.uniform(-5, 5)
                out.append("G1 X%.3f Y%.3f" % (x, y))
                out.append(
                    "G17 G%d X%.3f Y%.3f R%.3f" % (rng.choice((2, 3)), ex, ey, 8.0)
                )
            else:
                out += [
                    "G0 X%.3f Y%.3f" % (x, y),
                    "G1 Z%.3f" % -rng.uniform(2, 8),
                    "G4 P%.1f" % rng.choice((0.2, 0.5)),
                    "G0 Z2",
                ]
    out += ["M5", "G0 Z5", "M2"]
    return "\n".join(out) + "\n"


def loop(iterations: int) -> str:
    """An O-word while loop with COS/SIN/MOD expressions and a move each time."""
    return f"""\
(while loop with trigonometry)
G21 G90 G17 F900
#<i> = 0
o1 while [#<i> LT {iterations}]
  #<a> = [#<i> * 0.3]
  G1 X[30 * COS[#<a>] + [#<i> MOD 3]] Y[30 * SIN[#<a>]] Z[-[#<i> MOD 4] * 0.5]
  #<i> = [#<i> + 1]
o1 endwhile
M2
"""


def calls(count: int) -> str:
    """Subroutine calls with arguments and return values."""
    return f"""\
(subroutine calls with arguments)
G21 G90 F500
o<cell> sub
  #<acc> = [#1 * 0.5 + #2]
  o<cell> return [#<acc> MOD 97]
o<cell> endsub
#<_total> = 0
#<i> = 0
o1 while [#<i> LT {count}]
  o<cell> call [#<i>] [#<i> MOD 13]
  #<_total> = [#<_total> + #<_value>]
  #<i> = [#<i> + 1]
o1 endwhile
G1 X[#<_total> MOD 100]
M2
"""


def drilling(holes: int) -> str:
    """A grid of holes drilled with G81/G83 canned cycles."""
    lines = ["(canned drilling)", "G21 G90 G17 G98 F300", "G0 Z10", "M3 S1000"]
    side = max(1, int(holes**0.5))
    for k in range(holes):
        x, y = (k % side) * 5.0, (k // side) * 5.0
        if k == 0:
            lines.append(f"G81 X{x:.1f} Y{y:.1f} Z-3 R2")
        elif k % 50 == 0:
            lines.append(f"G83 X{x:.1f} Y{y:.1f} Z-6 R2 Q1.5")
        else:
            lines.append(f"X{x:.1f} Y{y:.1f}")
    lines += ["G80", "M5", "M2"]
    return "\n".join(lines) + "\n"


def pocket(pockets: int) -> str:
    """A realistic pocketing job: a subroutine clears a rectangular pocket by
    step-downs and zig-zag step-overs with arc-blended corners, called for a
    grid of pockets."""
    return f"""\
(rectangular pockets)
G21 G90 G17 G94
#<_safe> = 5
o<pocket> sub
  (#1 x0, #2 y0, #3 width, #4 height, #5 depth, #6 step down, #7 step over)
  G0 Z#<_safe>
  G0 X#1 Y#2
  #<z> = 0
  o10 while [#<z> GT -#5]
    #<z> = [#<z> - #6]
    o11 if [#<z> LT -#5]
      #<z> = -#5
    o11 endif
    G1 Z#<z> F200
    #<y> = #2
    #<row> = 0
    o12 while [#<y> LE [#2 + #4]]
      o13 if [[#<row> MOD 2] EQ 0]
        G1 X[#1 + #3] Y#<y> F900
      o13 else
        G1 X#1 Y#<y> F900
      o13 endif
      #<y> = [#<y> + #7]
      #<row> = [#<row> + 1]
    o12 endwhile
    G1 X#1 Y#2
    G3 X[#1 + 1] Y[#2 - 1] I1 J0
    G2 X#1 Y#2 I0 J1
  o10 endwhile
  G0 Z#<_safe>
o<pocket> endsub
#<n> = 0
o1 while [#<n> LT {pockets}]
  o<pocket> call [[#<n> MOD 10] * 40] [FIX[#<n> / 10] * 30] [30] [20] [6] [1.5] [0.8]
  #<n> = [#<n> + 1]
o1 endwhile
G0 Z#<_safe>
M2
"""
