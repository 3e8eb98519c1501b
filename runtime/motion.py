"""Moves: end points, straight moves, arcs, G28/G30 homing.

A mixin of :class:`runtime.machine.Machine`; it reads and updates the
machine's position state (see ``Machine.__init__``). Every move leaves the
machine through :meth:`MotionMixin._emit_move` or :meth:`_emit_arc`; while
cutter radius compensation is engaged, moves go to :mod:`runtime.cutter_comp`
instead.

Positions are 9-element lists in axis order X Y Z A B C U V W, in program
units (mm or inch by G21/G20) and degrees.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional

from runtime import arcs
from runtime.blockcheck import Block
from runtime.codes import (
    G0,
    G1,
    G2,
    G28,
    G28_1,
    G53,
)
from runtime.errors import GCodeError
from runtime.rotary import defined_point
from runtime.ops import c_hypot

AXES = "xyzabcuvw"
#: Axis indexes that are lengths (A, B, C are angles and never scaled).
LINEAR = (0, 1, 2, 6, 7, 8)

#: rs274's feed modes.
UNITS_PER_MINUTE, INVERSE_TIME, UNITS_PER_REVOLUTION = (
    arcs.UNITS_PER_MINUTE,
    arcs.INVERSE_TIME,
    arcs.UNITS_PER_REVOLUTION,
)

#: rs274's find_straight_length: moves shorter than this on an axis group
#: count as not moving it.
_TINY = 1e-7


def rotate(x: float, y: float, degrees: float):
    """(x, y) rotated counter-clockwise by ``degrees`` (rs274's rotate())."""
    t = math.radians(degrees)
    c, s = math.cos(t), math.sin(t)
    return x * c - y * s, x * s + y * c


class MotionMixin:
    """End points and the canonical calls of motion (part of Machine)."""

    # ------------------------------------------------------------------
    # End points
    # ------------------------------------------------------------------
    def _find_ends(self, block: Block) -> List[float]:
        """rs274's find_ends: the block's end point in the active system."""
        words = block.words
        if block.g.get(0) == G53:
            return self._machine_ends(block)
        cur = self._comp_base() if self._cc.side else self.current
        end = list(cur)
        if self.distance_incremental:
            for i, letter in enumerate(AXES):
                if letter in words:
                    end[i] += words[letter]
            self._polar_incremental(words, end)
        else:
            for i, letter in enumerate(AXES):
                if letter in words:
                    end[i] = words[letter]
            self._polar_absolute(words, end)
            if self._rotary_rules:
                self._unwrap_words(words, end)
        return end

    @staticmethod
    def _polar_absolute(words, end: List[float]) -> None:
        radius = words.get("polar_dist")
        angle = words.get("polar_angle")
        if radius is None and angle is None:
            return
        x, y = end[0], end[1]
        if radius is not None and angle is not None:
            theta = math.radians(angle)
        elif radius is not None:
            if x == 0 and y == 0:
                raise GCodeError(
                    "Must specify angle in polar coordinate if at the origin"
                )
            theta = math.atan2(y, x)
        else:
            radius = c_hypot(y, x)
            theta = math.radians(angle)
        end[0] = radius * math.cos(theta)
        end[1] = radius * math.sin(theta)

    @staticmethod
    def _polar_incremental(words, end: List[float]) -> None:
        if "polar_dist" in words:
            x, y = end[0], end[1]
            if x == 0 and y == 0:
                raise GCodeError(
                    "Incremental motion with polar coordinates is indeterminate when at the origin"
                )
            theta = math.atan2(y, x)
            radius = c_hypot(y, x) + words["polar_dist"]
            end[0], end[1] = radius * math.cos(theta), radius * math.sin(theta)
        if "polar_angle" in words:
            x, y = end[0], end[1]
            if x == 0 and y == 0:
                raise GCodeError(
                    "G91 motion with polar coordinates is indeterminate when at the origin"
                )
            theta = math.atan2(y, x) + math.radians(words["polar_angle"])
            radius = c_hypot(y, x)
            end[0], end[1] = radius * math.cos(theta), radius * math.sin(theta)

    def _machine_ends(self, block: Block) -> List[float]:
        """G53: the words are machine coordinates; convert them to the active system."""
        words = block.words
        if block.has_polar:
            raise GCodeError("Cannot use polar coordinates with G53")
        cur, origin, g92, tool = self.current, self.origin, self.g92, self.tool_offset
        cx, cy = rotate(cur[0] + g92[0], cur[1] + g92[1], self.rotation)
        x = words["x"] - origin[0] - tool[0] if "x" in words else cx
        y = words["y"] - origin[1] - tool[1] if "y" in words else cy
        x, y = rotate(x, y, -self.rotation)
        end = list(cur)
        end[0], end[1] = x - g92[0], y - g92[1]
        wrapped = (False,) * 3 + self.settings.wrapped_rotary + (False,) * 3
        for i in range(2, 9):
            letter = AXES[i]
            if letter in words:
                if wrapped[i]:  # (and then it takes the tool offset off)
                    end[i] = self._unwrap_machine(i, words[letter])
                    continue
                # rs274 leaves the tool offset out for A, B and C here.
                tool_part = 0.0 if 3 <= i <= 5 else tool[i]
                end[i] = words[letter] - origin[i] - g92[i] - tool_part
        return end

    def _find_relative(self, absolute: List[float]) -> List[Optional[float]]:
        """rs274's find_relative: machine coordinates -> the active system.

        A wrapped axis' angle of 360 or more makes rs274 stop there and
        leave it and the axes after it unset: None here."""
        origin, g92, tool = self.origin, self.g92, self.tool_offset
        x, y = rotate(
            absolute[0] - origin[0] - tool[0],
            absolute[1] - origin[1] - tool[1],
            -self.rotation,
        )
        out = [x - g92[0], y - g92[1]]
        wrapped = (False,) * 3 + self.settings.wrapped_rotary + (False,) * 3
        for i in range(2, 9):
            if wrapped[i]:
                try:
                    out.append(self._unwrap_machine(i, absolute[i]))
                except GCodeError:
                    return out + [None] * (9 - i)
                continue
            tool_part = 0.0 if 3 <= i <= 5 else tool[i]
            out.append(absolute[i] - origin[i] - g92[i] - tool_part)
        return out

    # ------------------------------------------------------------------
    # Straight moves
    # ------------------------------------------------------------------
    def _straight(self, move: int, block: Block) -> None:
        """G0/G1 (and G53 moves): rs274's convert_straight."""
        words = block.words
        comp = self._cc
        comp.arc_not_allowed = False
        if move == G1:
            self._check_feed_for_g1("f" in words)
        self.motion_mode = move
        end = self._find_ends(block)
        if move == G1 and self.feed_mode == INVERSE_TIME:
            start = self._comp_feed_start()
            self._inverse_time_feed(_straight_length(start, end), words["f"])
        if comp.side:
            self._comp_check_straight(block)
        self._emit_move(move == G0, end)

    def _check_feed_for_g1(self, has_f: bool) -> None:
        if self.feed_mode == INVERSE_TIME:
            if not has_f:
                raise GCodeError("F word missing with inverse time g1 move")
            return
        if self.feed_rate == 0.0:
            raise GCodeError("Cannot do g1 with zero feed rate")
        if self.feed_mode == UNITS_PER_REVOLUTION and self._feed_spindle_speed() == 0.0:
            raise GCodeError("Cannot feed with zero spindle speed in feed per rev mode")

    def _feed_spindle_speed(self) -> float:
        """The speed feed per revolution follows: the active spindle's."""
        return self.spindles.speed(self.active_spindle)

    def _inverse_time_feed(self, length: float, f: float) -> None:
        rate = max(0.1, length * f)
        self._set_feed_rate(rate)

    def _emit_move(self, rapid: bool, end: List[float]) -> None:
        """The one exit of straight motion: canon call, world model, position."""
        if self._cc.engaged:
            self._comp_straight(rapid, end)
            return
        if rapid:
            self.canon.straight_traverse(*end)
        else:
            self.canon.straight_feed(*end)
        # The end list is new and never changed in place (a general block
        # copies the current point first): share it, as the fast path does.
        self.current = self.world.position = end

    # ------------------------------------------------------------------
    # Arcs
    # ------------------------------------------------------------------
    def _arc(self, move: int, block: Block) -> None:
        """G2/G3 in any of the three planes (rs274's convert_arc/convert_arc2)."""
        words = block.words
        plane = self.plane
        self._comp_check_arc_allowed()
        arcs.check_arc_format(plane, words)
        arcs.check_arc_feed(
            self.feed_mode, self.feed_rate, self._feed_spindle_speed(), "f" in words
        )
        centre_words = arcs.arc_center_words(plane, words, self.ijk_absolute)
        end = self._find_ends(block)
        self.motion_mode = move
        cur = self.current
        s1, s2, s3 = arcs.to_plane(plane, cur[0], cur[1], cur[2])
        e1, e2, e3 = arcs.to_plane(plane, end[0], end[1], end[2])
        turns = arcs.check_arc_turns(words.get("p"))
        if self._cc.engaged:
            self._comp_arc(move, block, centre_words, end, turns)
            return
        clockwise = move == G2
        if centre_words is None:
            arc = arcs.arc_from_radius(
                clockwise, (s1, s2), (e1, e2), words["r"], turns, self.inches
            )
        else:
            arc = arcs.arc_from_center(
                clockwise,
                plane,
                (s1, s2),
                (e1, e2),
                centre_words,
                self.ijk_absolute,
                turns,
                self.inches,
                self.spiral_tolerance(),
            )
        if self.feed_mode == INVERSE_TIME:
            self._inverse_time_feed(arcs.arc_length((s1, s2), s3, arc, e3), words["f"])
        self._emit_arc(arc, e3, end)

    def _emit_arc(self, arc: arcs.Arc, axis_end: float, end: List[float]) -> None:
        """The one exit of arc motion: canon call, world model, position."""
        self.canon.arc_feed(
            arc.end1,
            arc.end2,
            arc.center1,
            arc.center2,
            arc.rotation,
            axis_end,
            *end[3:],
        )
        self.world.move_to(*end[:6])
        self.current = end

    # ------------------------------------------------------------------
    # G28 / G30 and G28.1 / G30.1
    # ------------------------------------------------------------------
    def _home(self, code: int, block: Block) -> None:
        """Traverse to the programmed point, then to the stored reference point."""
        words = block.words
        waypoint = self._find_ends(block)
        if self.cutter_comp:
            raise GCodeError("Cannot use g28 or g30 with cutter radius comp")
        if self._rotary_rules:
            self._index_first(waypoint)
        self._emit_move(True, waypoint)
        first = 5161 if code == G28 else 5181
        stored = [self.params[first + i] for i in range(9)]
        home = self._find_relative(self._user_to_program(stored))
        named = [letter in words for letter in AXES]
        end = list(waypoint)
        for i in range(9):
            if named[i] or not any(named):
                end[i] = home[i]
        if self._rotary_rules:
            self._index_first(defined_point(end))
        self._emit_move(True, end)

    def _save_home(self, code: int) -> None:
        """Store the current point, in machine coordinates, as a reference point."""
        if self.cutter_comp:
            raise GCodeError(
                "Cannot set reference point with cutter compensation in effect"
            )
        first = 5161 if code == G28_1 else 5181
        values = self._program_to_user(self.machine_position())
        for i, value in enumerate(self._saved_angles(values)):
            self.params.set_internal(first + i, value)

    def machine_position(self) -> List[float]:
        """The current point in machine coordinates (program units), as G28.1
        stores it and ``#<_abs_x>``... report it.

        The exact inverse of `_find_relative`, so G28 comes back here.
        """
        cur, tool, origin, g92 = self.current, self.tool_offset, self.origin, self.g92
        absolute = [cur[i] + g92[i] + origin[i] + tool[i] for i in range(9)]
        x, y = rotate(cur[0] + g92[0], cur[1] + g92[1], self.rotation)
        absolute[0] = x + origin[0] + tool[0]
        absolute[1] = y + origin[1] + tool[1]
        return absolute


def _straight_length(start: List[float], end: List[float]) -> float:
    """rs274's find_straight_length: XYZ distance, else UVW, else ABC."""

    def distance(group) -> float:
        return math.sqrt(sum((end[i] - start[i]) ** 2 for i in group))

    for group in ((0, 1, 2), (6, 7, 8)):
        if any(abs(start[i] - end[i]) > _TINY for i in group):
            return distance(group)
    return distance((3, 4, 5))
