"""Drilling canned cycles: G73, G74, G81-G89 (G80 cancels them in machine.py).

A mixin of :class:`runtime.machine.Machine`. A cycle stays the motion mode:
a later line with only axis words drills again, with the R, hole-axis, P, Q
and I/J/K values of the last cycle block unless the line gives new ones.
What happens follows rs274 2.9 (interp_cycles.cc), including what the
manual does not say:

* The "initial level" a G98 cycle retracts to is the hole-axis position
  before the *first* of a series of cycle blocks; only a non-cycle motion
  (G0, G1, G2, G3, G80, ...) starts a new series. Changing the cycle, the
  plane or running other codes in between keeps the old level.
* The interpreter's position after a cycle is the last hole at the
  clearance level, even where the tool really stopped elsewhere (G88 stops
  at the bottom of the hole for a manual retract).
* G74/G84 outside the XY plane feed along the wrong axes: rs274 hands its
  plane-relative feed routine the three coordinates in a shuffled order.
* Every cycle block switches the canon to exact path and back (read back
  from the canon's own model, which starts out continuous).
* The retract distance of the G73 and G83 pecks is fixed (0.010 inch or
  0.254 mm), not read from the INI file.
* A Q so small that a peck no longer changes the depth makes rs274 peck
  forever; ngc2py stops with an error after the first peck instead.

Moves leave through ``_emit_move`` only; dwell, spindle and override calls
go straight to the canon.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, Optional, Tuple

from runtime.blockcheck import DRILL_CYCLES, Block
from runtime.codes import (
    G73,
    G74,
    G81,
    G82,
    G83,
    G84,
    G85,
    G86,
    G87,
    G88,
    G89,
    check_word,
)
from runtime.errors import GCodeError
from runtime.motion import AXES, INVERSE_TIME
from runtime.ops import c_hypot
from runtime.spindle_select import (
    CLOCKWISE,
    COUNTERCLOCKWISE,
    STOPPED,
    check_dollar,
    dollar,
)

#: For each plane, the position indexes of the two in-plane coordinates the
#: cycle moves between holes ("aa", "bb" in rs274) and of the hole axis.
_GEOMETRY: Dict[str, Tuple[int, int, int]] = {
    "XY": (0, 1, 2),
    "YZ": (1, 2, 0),
    "XZ": (2, 0, 1),
}

#: The U/V/W planes: their G code and hole axis. rs274's stand-alone build
#: has no U, V or W axis, so a cycle there always fails.
_UVW_PLANES = {"UV": ("G17.1", "W"), "UW": ("G18.1", "V"), "VW": ("G19.1", "U")}

#: G73/G83 back-off after each peck, in inches (rs274's G83_RAPID_DELTA).
PECK_CLEARANCE_INCH = 0.010

#: rs274 reads a missing P or Q as this value, so writing it means "missing".
_ABSENT = -1.0

_DWELL_CYCLES = (G82, G86, G88, G89)  # P is required when the cycle starts
_PECK_CYCLES = (G73, G83)  # Q is required when the cycle starts
_P_CYCLES = _DWELL_CYCLES + (G74, G84)  # P is kept for the next lines


def _code_name(code: int) -> str:
    return f"G{code // 10}"


def _radians(degrees: float) -> float:
    # rs274's D2R: multiply by pi, then divide (not math.radians' one factor).
    return degrees * math.pi / 180.0


#: The words such a row may have; an axis (X, Y or Z) must be among them.
ROW_CYCLE_LETTERS = frozenset("xyzrpqlf")

#: Of those, the words each cycle uses (rs274's check_other_codes: P only
#: with the cycles that dwell or tap, Q only with the peck cycles, L with
#: any but G74). A row with another word is rs274's error: block() says it.
_ROW_WORDS = {
    motion: frozenset(
        "xyzrf"
        + ("l" if motion != G74 else "")
        + ("p" if motion in (G74, G82, G84, G86, G88, G89) else "")
        + ("q" if motion in _PECK_CYCLES else "")
    )
    for motion in (G73, G74, G81, G82, G83, G84, G85, G86, G87, G88, G89)
}


class CyclesMixin:
    """Canned cycle execution (part of Machine)."""

    #: Fields of a subclass's own that :meth:`hole_replayed` sets for a
    #: row (besides the position and the line, which the replay sets).
    replayed_fields: frozenset = frozenset()

    def hole_replayed(self, line: int) -> None:
        """A row of hole words at ``line`` was drilled by replaying a
        recorded hole (runtime.fast.hole_rows) rather than by
        :meth:`cycle_row`: a subclass keeps here what it keeps for each row
        (the preview, its line state)."""

    def cycle_row(self, line: int, words, n: Optional[str] = None) -> bool:
        """A data row of X, Y, Z, R, P, Q, L or F words alone (an axis among
        them) while a canned cycle is the modal motion: what ``block`` does
        with it (announce, copy the point, set F, drill, publish), without
        reading, enhancing and checking a line whose only possible outcome
        is this cycle. False, having done nothing, where ``block`` must
        decide (no cycle, a word the cycle does not use, G7 diameters, a
        tool change or probe pending, a G7x profile being read, the blocks of
        RETAIN_G43). ``n``: the row's N number (its digits as written)."""
        if self.cycle_row_refused(words):
            return False
        motion = self.motion_mode
        self.line = line
        self.announce_block(n)
        self.current = list(self.current)
        for letter, value in words.items():
            words[letter] = check_word(letter, value)
        if "f" in words and self.feed_mode != INVERSE_TIME:
            self._set_feed_rate(words["f"])
        block = Block({}, {}, words)
        block.motion = motion
        self._cycle(motion, block)
        self._publish_position()
        self.refresh_plain()
        return True

    def cycle_row_refused(self, words) -> bool:
        """Whether ``block`` must decide what a row of ``words`` does (see
        :meth:`cycle_row`)."""
        motion = self.motion_mode
        return (
            motion not in DRILL_CYCLES
            or not _ROW_WORDS[motion].issuperset(words)
            or self.lathe_diameter
            or self.toolchange_flag
            or self.probe_flag
            or self.reading_profile  # a G7x profile's lines go to its reader
            or "_execute" in self.__dict__
        )

    def _end_cycle_series(self) -> None:
        """A motion that is not a cycle: the next cycle measures its initial level anew."""
        self.cycle_initial_level = None

    # ------------------------------------------------------------------
    # convert_cycle
    # ------------------------------------------------------------------
    def _cycle(self, motion: int, block: Block) -> None:
        """One canned cycle block, with its L repeats."""
        words = block.words
        if self.feed_rate == 0.0:
            raise GCodeError("Cannot feed with zero feed rate")
        if self.feed_mode == INVERSE_TIME:
            raise GCodeError("Cannot use inverse time feed with canned cycles")
        if self.cutter_comp:
            raise GCodeError("Cannot use canned cycles with cutter compensation on")
        r_word = words.get("r")
        if r_word is None:
            if self.motion_mode != motion:
                raise GCodeError("R clearance plane unspecified in cycle")
            r_word = self.cycle_r
        repeats = int(words.get("l", 1))
        if repeats == 0:
            raise GCodeError("Cannot do zero repeats of cycle")
        if self.plane in _UVW_PLANES:
            self._uvw_cycle(words)
        start = self.current
        try:
            self._plane_cycle(motion, block, r_word, repeats)
        except GCodeError:
            # rs274 sets its current point once, after the last hole: a cycle
            # that fails part way (the spindle's direction, a peck's Q) leaves
            # it where the line began, though the canon made the moves before
            # the error, and -n 0 goes on from there
            self.current = start
            raise
        self.cycle_r = r_word
        self.motion_mode = motion

    def _uvw_cycle(self, words) -> None:
        for letter in "XYZ":
            if letter.lower() in words:
                article = "an" if letter == "X" else "a"
                raise GCodeError(
                    f"Cannot put {article} {letter} in a canned cycle"
                    f" in the {self.plane} plane"
                )
        code, axis = _UVW_PLANES[self.plane]
        raise GCodeError(
            f"{code} canned cycle is not possible on a machine without {axis} axis"
        )

    # ------------------------------------------------------------------
    # convert_cycle_xy / _yz / _zx
    # ------------------------------------------------------------------
    def _plane_cycle(self, motion: int, block: Block, r_word: float, repeats: int):
        words = block.words
        plane = self.plane
        ia, ib, ic = _GEOMETRY[plane]
        hole_letter = AXES[ic]
        if self.motion_mode != motion and hole_letter not in words:
            raise GCodeError(
                f"{hole_letter.upper()} value unspecified in {plane.lower()}"
                " plane canned cycle"
            )
        depth_word = words.get(hole_letter, self.cycle_depth)
        cur = self.current
        current_cc = cur[ic]
        if self.cycle_initial_level is None:
            self.cycle_initial_level = current_cc
        old_cc = self.cycle_initial_level
        # The row runner may ask what this line's hole tells of the rows of
        # hole words after it (runtime.fast.hole_rows): marks at its stages.
        capture = self._hole_capture
        if capture is not None and (repeats != 1 or self.distance_incremental):
            capture = None
        if capture is not None:
            capture.mark(self)

        step_a = step_b = 0.0
        radius_step = angle_step = 0.0
        if self.distance_incremental:
            step_a = words.get(AXES[ia], 0.0)
            step_b = words.get(AXES[ib], 0.0)
            radius_step = words.get("polar_dist", 0.0)
            angle_step = _radians(words.get("polar_angle", 0.0))
            r = r_word + old_cc
            bottom = r + depth_word
            aa, bb = cur[ia], cur[ib]
        else:
            r = r_word
            bottom = depth_word
            aa, bb = self._absolute_hole(words, ia, ib)
        if r < bottom:
            raise GCodeError(
                f"R less than {hole_letter} in cycle in {plane.lower()} plane"
            )

        # Below the R plane: straight up to it first.
        if old_cc < r:
            end = list(cur)
            end[ic] = r
            self._emit_move(True, end)
            old_cc = current_cc = r
        clear = r if self.retract_r_plane else old_cc

        world = self.world
        saved = (world.control_mode, world.control_tolerance, world.naivecam_tolerance)
        if saved[0] != "EXACT_PATH":
            self._canon_control_mode("EXACT_PATH", 0.0)

        drill = self._cycle_body(motion, words, plane, r, clear, bottom)
        run = getattr(drill, _HOLES[motion])
        for repeat in range(repeats):
            aa += step_a
            bb += step_b
            if radius_step:
                aa, bb = _polar_step(aa, bb, radius_step, 0.0)
            if angle_step:
                aa, bb = _polar_step(aa, bb, 0.0, angle_step)
            if capture is not None:
                capture.mark(self)
            if repeat == 0 and current_cc > r:
                self._cycle_move(True, aa, bb, current_cc)
                self._cycle_move(True, aa, bb, r)
            else:
                self._cycle_move(True, aa, bb, clear)
                if clear > r:
                    self._cycle_move(True, aa, bb, r)
            if capture is not None:
                capture.mark(self)
            run(aa, bb)

        end = list(self.current)
        end[ia], end[ib], end[ic] = aa, bb, clear
        self.current = end
        self.cycle_depth = depth_word
        # P and Q stay for the next lines only once every hole is drilled
        if motion in _PECK_CYCLES:
            self.cycle_q = drill.delta
        elif motion in _P_CYCLES:
            self.cycle_p = drill.dwell
        if saved[0] != "EXACT_PATH":
            self._canon_control_mode(saved[0], saved[1])
            self._canon_naivecam(saved[2])
        if capture is not None:
            capture.ended(self, r, clear)

    def _absolute_hole(self, words, ia: int, ib: int) -> Tuple[float, float]:
        """The hole position in G90: the plane's words, or polar words (XY only)."""
        cur = self.current
        radius = words.get("polar_dist")
        angle = words.get("polar_angle")
        if radius is None and angle is None:
            return words.get(AXES[ia], cur[ia]), words.get(AXES[ib], cur[ib])
        # Unlike a G0/G1 end point, no "at the origin" check here.
        if radius is None:
            radius = c_hypot(cur[1], cur[0])
        theta = math.atan2(cur[1], cur[0]) if angle is None else _radians(angle)
        return radius * math.cos(theta), radius * math.sin(theta)

    def _cycle_move(self, rapid: bool, end1: float, end2: float, end3: float) -> None:
        """rs274's cycle_traverse/cycle_feed: the three values go to the
        plane's first, second and hole axis; nothing else moves."""
        ia, ib, ic = _GEOMETRY[self.plane]
        end = self.current[:]
        end[ia] = end1
        end[ib] = end2
        end[ic] = end3
        self._emit_move(rapid, end)

    # ------------------------------------------------------------------
    # The cycles themselves (one hole each)
    # ------------------------------------------------------------------
    def _cycle_body(self, motion, words, plane, r, clear, bottom):
        """Check and settle the cycle's own words (in rs274's order, after
        the first moves): the :class:`_Drill` of this line's holes."""
        name = _code_name(motion)
        first = self.motion_mode != motion
        drill = _Drill(self, motion, name, r, clear, bottom)
        if motion in _DWELL_CYCLES:
            p = words.get("p", _ABSENT)
            if first and p == _ABSENT:
                raise GCodeError(f"Dwell time p word missing with {name.lower()}")
            drill.dwell = self.cycle_p if p == _ABSENT else p
        elif motion in _PECK_CYCLES:
            q = words.get("q", _ABSENT)
            if first and q == _ABSENT:
                raise GCodeError(f"Q word missing with {name.lower()}")
            drill.delta = self.cycle_q if q == _ABSENT else q
        elif motion in (G74, G84):
            p = words.get("p", _ABSENT)
            drill.direction = self._tapping_spindle(words, plane)
            drill.spindle = self.active_spindle
            drill.dwell = self.cycle_p if p == _ABSENT else p
        elif motion == G87:
            if first:
                for letter in "ijk":
                    if letter not in words:
                        raise GCodeError(f"{letter.upper()} word missing with g87")
            self.cycle_i = words.get("i", self.cycle_i)
            self.cycle_j = words.get("j", self.cycle_j)
            self.cycle_k = words.get("k", self.cycle_k)
            offsets = (self.cycle_i, self.cycle_j, self.cycle_k)
            ia, ib, ic = _GEOMETRY[plane]
            middle = offsets[ic] + bottom if self.distance_incremental else offsets[ic]
            drill.offsets = (offsets[ia], offsets[ib], middle)
        return drill

    # ------------------------------------------------------------------
    # Spindle
    # ------------------------------------------------------------------
    def _tapping_spindle(self, words, plane: str) -> int:
        """G74/G84's $ becomes the active spindle; the direction the cycle
        checks is that spindle's, but in the YZ plane rs274 reads the
        direction of the spindle active before the line."""
        direction = self.spindles.turning(self.active_spindle)
        if "dollar" in words:
            check_dollar(words, "tap XZ" if plane == "XZ" else "tap", self.num_spindles)
            self.active_spindle = dollar(words)
        if plane == "YZ":
            return direction
        return self.spindles.turning(self.active_spindle)

    def _spindle_direction(self, name: str) -> bool:
        """G86-G88 need the active spindle turning; True when it turns
        clockwise."""
        direction = self.spindles.turning(self.active_spindle)
        if direction not in (CLOCKWISE, COUNTERCLOCKWISE):
            raise GCodeError(f"Spindle not turning in {name.lower()}")
        return direction == CLOCKWISE

    def _start_spindle(self, clockwise: bool) -> None:
        """The canon call only: the interpreter's spindle state stays as it was."""
        if clockwise:
            self.canon.start_spindle_clockwise(self.active_spindle)
        else:
            self.canon.start_spindle_counterclockwise(self.active_spindle)


class _Drill:
    """One cycle block's settled words and levels, and how each kind of
    cycle drills one hole at (aa, bb) with them (rs274's convert_cycle_g8x
    and company, which the hole's own moves follow)."""

    __slots__ = (
        "machine",
        "move",
        "canon",
        "motion",
        "name",
        "r",
        "clear",
        "bottom",
        "dwell",
        "delta",
        "offsets",
        "spindle",
        "direction",
    )

    def __init__(self, machine, motion: int, name: str, r, clear, bottom) -> None:
        self.machine = machine
        self.move = machine._cycle_move
        self.canon = machine.canon
        self.motion, self.name = motion, name
        self.r, self.clear, self.bottom = r, clear, bottom
        self.dwell = self.delta = 0.0
        self.offsets = (0.0, 0.0, 0.0)
        self.spindle = machine.active_spindle
        self.direction = STOPPED  # (the tapping cycles' own, from the line)

    def g81(self, aa, bb):
        self.move(False, aa, bb, self.bottom)
        self.move(True, aa, bb, self.clear)

    def g82(self, aa, bb):
        self.move(False, aa, bb, self.bottom)
        self.canon.dwell(self.dwell)
        self.move(True, aa, bb, self.clear)

    def pecks(self, aa, bb):
        """G73 and G83: down a peck at a time, backing off (G73) or out to
        R (G83) between pecks."""
        delta, bottom, r, move = self.delta, self.bottom, self.r, self.move
        if delta <= 0.0:
            raise GCodeError("Negative or zero q value used")
        back_off = PECK_CLEARANCE_INCH * (1.0 if self.machine.inches else 25.4)
        depth = r - delta
        while depth > bottom:
            move(False, aa, bb, depth)
            if self.motion == G83:
                move(True, aa, bb, r)
            move(True, aa, bb, depth + back_off)
            if depth - delta == depth:
                # rs274 pecks at the same depth forever; say why instead.
                raise GCodeError(
                    f"Q value too small with {self.name.lower()}:"
                    " the pecks never reach the bottom"
                )
            depth -= delta
        move(False, aa, bb, bottom)
        move(True, aa, bb, self.clear)

    def tap(self, aa, bb):
        """G84 (right hand) and G74 (left hand)."""
        m, canon, motion, spindle = self.machine, self.canon, self.motion, self.spindle
        plane = m.plane
        _check_tapping_direction(motion, self.direction)
        # The override switches are the canon's, which follow M48-M51 (and
        # keep one speed switch for all spindles).
        feed_override, speed_override = m.feed_override, m.world.speed_override
        canon.disable_feed_override()
        m._speed_override(spindle, False)
        self.move(False, *_tapping_order(plane, aa, bb, self.bottom))
        canon.stop_spindle_turning(spindle)
        m._start_spindle(motion == G74)
        canon.dwell(self.dwell)
        self.move(False, *_tapping_order(plane, aa, bb, self.clear))
        canon.stop_spindle_turning(spindle)
        m._start_spindle(motion == G84)
        if feed_override:
            canon.enable_feed_override()
        if speed_override:
            m._speed_override(spindle, True)

    def g85(self, aa, bb):
        self.move(False, aa, bb, self.bottom)
        self.move(False, aa, bb, self.r)
        self.move(True, aa, bb, self.clear)

    def g86(self, aa, bb):
        clockwise = self.machine._spindle_direction(self.name)
        self.move(False, aa, bb, self.bottom)
        self.canon.dwell(self.dwell)
        self.canon.stop_spindle_turning(self.spindle)
        self.move(True, aa, bb, self.clear)
        self.machine._start_spindle(clockwise)

    def g87(self, aa, bb):
        """Back boring: in beside the hole with the spindle oriented, over
        to it, cut up to the middle level and back, out the same way."""
        m, canon, move = self.machine, self.canon, self.move
        bottom = self.bottom
        clockwise = m._spindle_direction(self.name)
        direction = 2 if clockwise else 3  # rs274's CANON_DIRECTION values
        off_a, off_b, middle = self.offsets
        out_a, out_b = aa + off_a, bb + off_b
        move(True, out_a, out_b, self.r)
        canon.stop_spindle_turning(self.spindle)
        canon.orient_spindle(self.spindle, 0.0, direction)
        move(True, out_a, out_b, bottom)
        move(True, aa, bb, bottom)
        m._start_spindle(clockwise)
        move(False, aa, bb, middle)
        move(False, aa, bb, bottom)
        canon.stop_spindle_turning(self.spindle)
        canon.orient_spindle(self.spindle, 0.0, direction)
        move(True, out_a, out_b, bottom)
        move(True, out_a, out_b, self.clear)
        move(True, aa, bb, self.clear)
        m._start_spindle(clockwise)

    def g88(self, aa, bb):
        clockwise = self.machine._spindle_direction(self.name)
        self.move(False, aa, bb, self.bottom)
        self.canon.dwell(self.dwell)
        self.canon.stop_spindle_turning(self.spindle)
        self.canon.program_stop()  # the operator retracts by hand
        self.machine._start_spindle(clockwise)

    def g89(self, aa, bb):
        self.move(False, aa, bb, self.bottom)
        self.canon.dwell(self.dwell)
        self.move(False, aa, bb, self.clear)


#: Which of _Drill's methods drills a hole of each cycle.
_HOLES = {
    G73: "pecks",
    G74: "tap",
    G81: "g81",
    G82: "g82",
    G83: "pecks",
    G84: "tap",
    G85: "g85",
    G86: "g86",
    G87: "g87",
    G88: "g88",
    G89: "g89",
}


def _check_tapping_direction(motion: int, direction: int) -> None:
    """G84 taps right-hand (spindle clockwise), G74 left-hand; a spindle
    never started or stopped has no direction rs274 knows."""
    name = _code_name(motion)
    if direction == STOPPED:
        raise GCodeError(f"Spindle not turning in {name}")
    if direction == CLOCKWISE:
        if motion == G74:
            raise GCodeError("Spindle turning clockwise in G74")
    elif direction == COUNTERCLOCKWISE:
        if motion == G84:
            raise GCodeError("Spindle turning counterclockwise in G84")
    else:
        raise GCodeError(f"Spindle state unknown for {name}")


def _tapping_order(plane: str, aa: float, bb: float, level: float):
    """The order rs274's tapping cycle hands its three values to the plane's
    feed routine: right in XY, shuffled in YZ and XZ."""
    if plane == "YZ":
        return level, aa, bb
    if plane == "XZ":
        return bb, level, aa
    return aa, bb, level


def _polar_step(aa: float, bb: float, radius_step: float, angle_step: float):
    """One incremental polar step of a repeat (XY plane, G91)."""
    if aa == 0 and bb == 0:
        raise GCodeError(
            "Incremental motion with polar coordinates is indeterminate when at the origin"
        )
    theta = math.atan2(bb, aa) + angle_step
    radius = c_hypot(bb, aa) + radius_step
    return radius * math.cos(theta), radius * math.sin(theta)
