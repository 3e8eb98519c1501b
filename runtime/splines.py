"""Splines: G5 (cubic), G5.1 (quadratic), G5.2/G5.3 (NURBS), as rs274's
convert_spline and convert_nurbs make them.

A mixin of :class:`runtime.machine.Machine`. Every spline reaches the canon
as one NURBS_FEED call with its control points ``(x, y, weight)``; the
stand-alone canon prints only how many there are.

rs274 facts kept on purpose:

* splines are XY only; G5 and G5.1 leave the motion mode alone (a following
  ``X.. Y..`` line continues the mode from before them);
* G5 without I and J takes its first control point from the previous G5's
  second one, mirrored (rs274's ``cycle_i``/``cycle_j``);
* G5.2 lines only collect control points (the current point does not move,
  so incremental points are all relative to where G5.2 started); G5.3
  sends them and leaves no motion mode at all;
* one list of points serves all four codes, and a G5.2 list abandoned by
  another motion is only emptied by the next G5.2 line, after its checks.
* after NURBS_FEED the stand-alone canon reads its position past the end of
  the point list (undefined behaviour in C); rs274 as built reads X = Y = 0
  there, which a later tool change or probe then sees.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Tuple

    ControlPoint = Tuple[float, float, float]

from runtime.arcs import INVERSE_TIME, UNITS_PER_MINUTE
from runtime.blockcheck import NO_MOTION, Block
from runtime.codes import G5_1, G5_2
from runtime.errors import GCodeError


class SplinesMixin:
    """G5, G5.1, G5.2 and G5.3 (part of Machine)."""

    def _spline(self, motion: int, block: Block) -> None:
        """convert_spline: G5 and G5.1."""
        words = block.words
        if self.cutter_comp:
            raise GCodeError("Cannot convert spline with cutter radius compensation")
        if self.feed_mode == UNITS_PER_MINUTE and self.feed_rate == 0.0:
            raise GCodeError("Cannot make arc with zero feed rate")
        if self.feed_mode == INVERSE_TIME and "f" not in words:
            raise GCodeError("F word missing with inverse time arc move")
        if self.plane != "XY":
            raise GCodeError("Splines must be in the XY plane")
        if any(letter in words for letter in "zabc"):
            raise GCodeError("Splines may not have motion in Z, A, B, or C")
        x0, y0 = self.current[0], self.current[1]
        has_i, has_j = "i" in words, "j" in words
        if motion == G5_1:
            if not (has_i and has_j):
                raise GCodeError("Must specify both I and J with G5.1")
            first = (x0 + words["i"], y0 + words["j"])
            end = self._find_ends(block)
            points = [(x0, y0), first, (end[0], end[1])]
            order = 3
        else:
            if has_i and has_j:
                i, j = words["i"], words["j"]
            elif has_i or has_j:
                raise GCodeError("Must specify both I and J, or neither")
            else:
                i, j = self._spline_ij
            first = (x0 + i, y0 + j)
            end = self._find_ends(block)
            if "p" not in words or "q" not in words:
                raise GCodeError("Must specify both P and Q with G5")
            p, q = words["p"], words["q"]
            second = (end[0] + p, end[1] + q)
            points = [(x0, y0), first, second, (end[0], end[1])]
            order = 4
            self._spline_ij = (-p, -q)
        self._nurbs_points = self._nurbs_points + [(x, y, 1.0) for x, y in points]
        self._emit_nurbs(order)
        self.current = [end[0], end[1]] + self.current[2:]

    def _nurbs(self, block: Block) -> None:
        """convert_nurbs for G5.2: collect one control point."""
        words = block.words
        has_x, has_y = "x" in words, "y" in words
        weight = words.get("p", -1.0)  # rs274's "no P" is -1
        points = self._nurbs_points
        if has_x != has_y:
            raise GCodeError(
                "You must specify both X and Y coordinates for Control Points"
            )
        if not has_x and weight > 0 and points:
            raise GCodeError(
                "Can specify P without X and Y only for the first control point"
            )
        if weight <= 0 and points:
            raise GCodeError("Must specify positive weight P for every Control Point")
        if self.feed_mode == UNITS_PER_MINUTE and self.feed_rate == 0.0:
            raise GCodeError("Cannot make a NURBS with 0 feedrate")
        if self.motion_mode != G5_2:
            points = []
        if not points:
            first_weight = weight if not has_x and weight > 0 else 1.0
            points = [(self.current[0], self.current[1], first_weight)]
            self._nurbs_order = 3
        order = words.get("l", -1.0)
        if order > 3:
            self._nurbs_order = int(order)
        if has_x:
            end = self._find_ends(block)
            points = points + [(end[0], end[1], weight)]
        self._nurbs_points = points
        self.motion_mode = G5_2

    def _nurbs_end(self) -> None:
        """G5.3: send the collected control points."""
        if self.motion_mode != G5_2:
            raise GCodeError("Cannot use G5.3 without G5.2 first")
        points = self._nurbs_points
        if len(points) < self._nurbs_order:
            raise GCodeError(
                "You must specify a number of control points at least equal"
                " to the order L = %d" % self._nurbs_order
            )
        last = points[-1]
        self.current = [last[0], last[1]] + self.current[2:]
        self._emit_nurbs(self._nurbs_order)
        self.motion_mode = NO_MOTION

    def _emit_nurbs(self, order: int) -> None:
        """NURBS_FEED with the collected points, then an empty list."""
        self.canon.nurbs_feed(list(self._nurbs_points), order)
        self._nurbs_points = []
        # The stand-alone canon's read past the end of the list (see above).
        self.world.position = [0.0, 0.0] + list(self.world.position[2:6])


__all__ = ["SplinesMixin", "NO_MOTION"]
