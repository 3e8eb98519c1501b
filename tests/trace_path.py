"""The toolpath read back from an ``rs274 -g`` trace: a reference that the
statistics and plot back ends are checked against.

It shares no code with ``runtime.toolpath``: it reads the printed trace
(four decimals), follows units, plane and offsets the way the canon
documents them, and samples arcs densely instead of computing their
extremes. So its extents agree with the exact ones to within the printing
and sampling error, which the tests allow for.
"""

from __future__ import annotations

import math
import re
from typing import Dict, List, Optional, Tuple

_CALL = re.compile(r"^\s*\d+ N\S*\s*([A-Z_0-9]+)\((.*)\)\s*$")
_NUMBER = re.compile(r"-?\d+(?:\.\d+)?|-?nan")
#: Points per full turn when sampling an arc.
_SAMPLES_PER_TURN = 2880

#: Offset calls and how many leading numbers they carry that are not axes.
_OFFSETS = {"SET_G5X_OFFSET": 1, "SET_G92_OFFSET": 0, "USE_TOOL_LENGTH_OFFSET": 0}


class TracePath:
    """Extents (X Y Z A B C, millimetres and degrees) of a trace's moves,
    reported in the units in force at the first move."""

    def __init__(self, trace: str):
        self.position = [0.0] * 6
        self.inches = False
        self.first_inches: Optional[bool] = None
        self.plane = "XY"
        self.offsets: Dict[str, List[float]] = {name: [0.0] * 6 for name in _OFFSETS}
        self.low = [math.inf] * 6
        self.high = [-math.inf] * 6
        self.moves = 0
        self.arcs = 0
        #: NURBS_FEED calls: the trace prints only their number of control
        #: points, so their curve (and where they end) is not in it
        self.splines = 0
        for line in trace.splitlines():
            match = _CALL.match(line)
            if match:
                self._call(match.group(1), match.group(2))

    def _mm(self, values: List[float]) -> List[float]:
        scale = 25.4 if self.inches else 1.0
        return [v * scale if i < 3 else v for i, v in enumerate(values)]

    def _add(self, point: List[float]) -> None:
        for i in range(6):
            self.low[i] = min(self.low[i], point[i])
            self.high[i] = max(self.high[i], point[i])

    def _call(self, name: str, args: str) -> None:
        numbers = [float(n) for n in _NUMBER.findall(args)]
        if name == "USE_LENGTH_UNITS":
            self.inches = "INCHES" in args
        elif name == "SELECT_PLANE":
            self.plane = args.replace("CANON_PLANE_", "")
        elif name in _OFFSETS:
            new = self._mm(numbers[_OFFSETS[name] :][:6])
            old = self.offsets[name]
            self.position = [p - (n - o) for p, n, o in zip(self.position, new, old)]
            self.offsets[name] = new
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE"):
            self._first()
            self.position = self._mm(numbers[:6])
            self._add(self.position)
        elif name == "RIGID_TAP":
            # In to X Y Z and back out along the same line (the spindle
            # reverses at the bottom): the tool ends where it started. Two
            # moves, as runtime.toolpath draws and times it.
            self._first()
            self._first()
            self._add(self.position)
            self._add(self._mm(numbers[:3]) + self.position[3:])
        elif name == "ARC_FEED":
            self._first()
            self._arc(numbers)
        elif name == "NURBS_FEED":
            self._first()
            self.splines += 1

    def _first(self) -> None:
        self.moves += 1
        if self.first_inches is None:
            self.first_inches = self.inches

    def _arc(self, numbers: List[float]) -> None:
        self.arcs += not math.isnan(numbers[2])  # an R 0 arc's path is its chord
        scale = 25.4 if self.inches else 1.0
        fe, se, fc, sc = (v * scale for v in numbers[:4])
        turn, ne = numbers[4], numbers[5] * scale
        f, s, n = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}[self.plane]
        start = list(self.position)
        end = list(start[:3]) + numbers[6:9]
        end[f], end[s], end[n] = fe, se, ne
        if math.isnan(fc):  # an R 0 arc (its end within tolerance): its chord
            self._add(start)
            self._add(end)
            self.position = end
            return
        a0 = math.atan2(start[s] - sc, start[f] - fc)
        a1 = math.atan2(end[s] - sc, end[f] - fc)
        r0 = math.hypot(start[s] - sc, start[f] - fc)
        r1 = math.hypot(end[s] - sc, end[f] - fc)
        # Whole turns: from the start angle to the end angle going the
        # arc's way, at least a sliver more than nothing (a closed arc is a circle).
        turn = int(turn)
        if turn > 0:
            sweep = a1 - a0
            while sweep <= 1e-12:
                sweep += 2 * math.pi
            if math.hypot(end[f] - start[f], end[s] - start[s]) < 1e-9:
                sweep = 2 * math.pi
            sweep += 2 * math.pi * (turn - 1)
        else:
            sweep = a1 - a0
            while sweep >= -1e-12:
                sweep -= 2 * math.pi
            if math.hypot(end[f] - start[f], end[s] - start[s]) < 1e-9:
                sweep = -2 * math.pi
            sweep -= 2 * math.pi * (-turn - 1)
        count = max(8, int(abs(sweep) / (2 * math.pi) * _SAMPLES_PER_TURN))
        for i in range(count + 1):
            t = i / count
            point = [a + (b - a) * t for a, b in zip(start, end)]
            radius = r0 + (r1 - r0) * t
            point[f] = fc + radius * math.cos(a0 + sweep * t)
            point[s] = sc + radius * math.sin(a0 + sweep * t)
            self._add(point)
        self.position = end

    def extents(self) -> Dict[str, Tuple[float, float]]:
        """Per axis (x y z, and a b c when they move): (low, high) in the
        units of the first move."""
        if self.low[0] == math.inf:
            return {}
        scale = 1 / 25.4 if self.first_inches else 1.0
        found = {}
        for i, name in enumerate("xyzabc"):
            low, high = self.low[i], self.high[i]
            if name in "xyz" or low != 0.0 or high != 0.0:
                k = scale if i < 3 else 1.0
                found[name] = (low * k, high * k)
        return found


#: gcode.parse's calls as the trace calls they stand for (set_plane's number
#: is LinuxCNC's CANON_PLANE)
_GCODE_PLANES = {1: "XY", 2: "YZ", 3: "XZ"}


def trace_of_gcode_calls(calls) -> str:
    """LinuxCNC's ``gcode.parse`` calls (inches; as tests/gcode_reference.py
    records them) written as the trace lines TracePath reads. The gcode
    module draws a spline as straight feeds through points of its curve,
    so this path has the splines the rs274 trace cannot show."""
    lines = ["USE_LENGTH_UNITS(CANON_UNITS_INCHES)"]
    names = {
        "straight_traverse": "STRAIGHT_TRAVERSE",
        "straight_feed": "STRAIGHT_FEED",
        "straight_probe": "STRAIGHT_PROBE",
        "set_g92_offset": "SET_G92_OFFSET",
        "tool_offset": "USE_TOOL_LENGTH_OFFSET",
        "rigid_tap": "RIGID_TAP",
    }
    for name, args in calls:
        numbers = lambda values: ", ".join("%.12f" % v for v in values)
        if name == "set_plane":
            lines.append("SELECT_PLANE(CANON_PLANE_%s)" % _GCODE_PLANES.get(args[0], "UV"))
        elif name == "set_g5x_offset":
            lines.append("SET_G5X_OFFSET(%d, %s)" % (args[0], numbers(args[1:7])))
        elif name == "arc_feed":
            values = numbers(args[:4]) + ", %d, " % args[4] + numbers(args[5:9])
            lines.append("ARC_FEED(%s)" % values)
        elif name in names:
            lines.append("%s(%s)" % (names[name], numbers(args[:6])))
    return "\n".join("%5d N..... %s" % (i + 1, line) for i, line in enumerate(lines))
