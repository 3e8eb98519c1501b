"""M codes: I/O, spindle, coolant, overrides, and the stopping codes.

A mixin of :class:`runtime.machine.Machine` (rs274's convert_m and
convert_stop). M6/M61 are in :mod:`runtime.tools`.
"""

from __future__ import annotations

from runtime.blockcheck import (
    M_COOLANT,
    M_IO,
    M_OVERRIDE,
    M_SPINDLE,
    M_TOOL,
    M_USER,
    Block,
    round_to_int,
)
from runtime.codes import G1
from runtime.errors import GCodeError
from runtime.motion import UNITS_PER_MINUTE, rotate
from runtime.offsets import COORD_SYSTEM
from runtime.spindle_select import (
    CLOCKWISE,
    COUNTERCLOCKWISE,
    STOPPED,
    check_dollar,
    chosen,
    dollar,
)

#: Where M66 leaves the value of the input it read.
INPUT_PARAM = 5399


#: What M3, M4 and M5 make of a spindle.
_DIRECTIONS = {3: CLOCKWISE, 4: COUNTERCLOCKWISE, 5: STOPPED}


class ProgramEnd(Exception):
    """M2/M30 ends the run wherever it happens (even inside a subroutine)."""


def not_supported(what: str) -> GCodeError:
    """The error for a code rs274 knows but ngc2py does not implement yet."""
    return GCodeError(f"ngc2py does not support {what} yet")


#: M62-M68 under cutter radius compensation: what rs274 refuses to set.
_IO_UNDER_COMP = {
    62: "motion output",
    63: "motion digital output",
    64: "auxiliary digital output",
    65: "auxiliary digital output",
    67: "motion analog output",
    68: "auxiliary analog output",
}


class MCodesMixin:
    """rs274's M code execution (part of Machine)."""

    # ------------------------------------------------------------------
    # M codes
    # ------------------------------------------------------------------
    def _execute_m(self, block: Block) -> bool:
        """rs274's convert_m: I/O, tool change, spindle, coolant, overrides, user.

        Returns True when an M72 restore replaced the rest of the line."""
        m, words = block.m, block.words
        if M_IO in m:
            self._io(m[M_IO], words)
        if m.get(M_TOOL) == 6:
            self._change_tool()
        elif m.get(M_TOOL) == 61:
            self._set_tool_number(words.get("q"))
        if self.settings.retain_g43:
            self._retain_g43(block)
        if M_SPINDLE in m and self._spindle(m[M_SPINDLE], words):
            return True
        if M_COOLANT in m:
            self._coolant(m[M_COOLANT])
        if M_OVERRIDE in m:
            self._overrides(m[M_OVERRIDE], words)
        if M_USER in m:
            raise GCodeError(f"Unknown m code used: M{m[M_USER]}")
        return False

    def _io(self, code: int, words) -> None:
        canon = self.canon
        if self.cutter_comp and code in _IO_UNDER_COMP:
            raise GCodeError(
                f"Cannot set {_IO_UNDER_COMP[code]} with cutter radius compensation on"
            )
        if code in (62, 63, 64, 65):
            if "p" not in words:
                raise GCodeError(f"No valid P word with M{code}")
            index = round_to_int(words["p"])
            call = {
                62: canon.set_motion_output_bit,
                63: canon.clear_motion_output_bit,
                64: canon.set_aux_output_bit,
                65: canon.clear_aux_output_bit,
            }[code]
            call(index)
        elif code in (67, 68):
            e = words.get("e")
            if e is None or round_to_int(e) < 0:
                raise GCodeError(f"Invalid analog index with M{code}")
            value = words.get("q", -1.0)
            if code == 67:
                canon.set_motion_output_value(round_to_int(e), value)
            else:
                canon.set_aux_output_value(round_to_int(e), value)
        else:
            self._wait_input(words)

    def _spindle(self, code: int, words) -> bool:
        """Group 7: spindle and modal state; True when M72 replaced the line."""
        if code in (3, 4, 5):
            check_dollar(words, "m%d" % code, self.num_spindles)
            for spindle in chosen(words, self.num_spindles):
                self._turn_spindle(spindle, _DIRECTIONS[code])
        elif code == 19:
            self._orient_spindle(words)
        elif code in (70, 73):
            self._save_context(auto_restore=code == 73)
        elif code == 71:
            self._forget_context()
        elif code == 72:
            return self._restore_context()
        return False

    def _turn_spindle(self, spindle: int, direction: int) -> None:
        """M3, M4 or M5 for one spindle: the canon call and rs274's record."""
        canon = self.canon
        if direction == CLOCKWISE:
            canon.start_spindle_clockwise(spindle)
        elif direction == COUNTERCLOCKWISE:
            canon.start_spindle_counterclockwise(spindle)
        else:
            canon.stop_spindle_turning(spindle)
        self.spindles.set_turning(spindle, direction)

    def _orient_spindle(self, words) -> None:
        """M19 [R angle] [P direction] [Q timeout] [$ spindle]; the INI may
        offset the angle. rs274 records every spindle as stopped first."""
        for spindle in range(self.num_spindles):
            self.spindles.set_turning(spindle, STOPPED)
        check_dollar(words, "m19", self.num_spindles)
        spindle = dollar(words) or 0
        if "r" in words or "p" in words:
            angle = words.get("r", 0.0) + self.settings.orient_offset
            self.canon.orient_spindle(spindle, angle, int(words.get("p", 0.0)))
        if "q" in words:
            if words["q"] <= 0.0:
                raise GCodeError("Q word with M19 requires a value > 0")
            self.canon.wait_spindle_orient_complete(spindle, words["q"])

    def _wait_input(self, words) -> None:
        """M66: rs274's stand-alone canon has no inputs and never waits.

        Only the checks are visible, and #5399 (the input read back on the
        next line) keeps its value, normalised to 0/1 for a digital input.
        """
        p, e = words.get("p"), words.get("e")
        wait_type = int(words["l"]) if "l" in words else 0
        if p is not None and e is not None:
            raise GCodeError(
                "Invalid to select both a digital and an analog input with M66"
            )
        if words.get("q", -1.0) <= 0 and wait_type > 0:
            raise GCodeError("Zero timeout with wait type != immediate return")
        if e is not None and wait_type != 0:
            raise GCodeError(
                "Can't select analog input with wait type != immediate return"
            )
        if (
            (p is not None and round_to_int(p) < 0)
            or (e is not None and round_to_int(e) < 0)
            or (p is None and e is None)
        ):
            raise GCodeError("Need to have either a valid P or a valid E word with M66")
        if self.cutter_comp:
            kind = "digital" if p is not None else "analog"
            raise GCodeError(
                f"Cannot wait for {kind} input with cutter radius compensation on"
            )
        if p is not None:
            self.params.set_internal(
                INPUT_PARAM, 1.0 if self.params[INPUT_PARAM] else 0.0
            )

    def _coolant(self, code: int) -> None:
        canon = self.canon
        if code == 7:
            canon.mist_on()
            self.mist = True
        elif code == 8:
            canon.flood_on()
            self.flood = True
        else:
            canon.mist_off()
            canon.flood_off()
            self.mist = self.flood = False

    def _overrides(self, code: int, words) -> None:
        on = code == 48 or (code != 49 and words.get("p", -1.0) != 0)
        if code == 51:
            check_dollar(words, "m51", self.num_spindles)
        if self.cutter_comp:
            raise GCodeError(
                f"Cannot {'enable' if on else 'disable'} overrides"
                " with cutter radius compensation on"
            )
        canon = self.canon
        if code in (48, 49, 50):
            (canon.enable_feed_override if on else canon.disable_feed_override)()
            self.feed_override = on
        if code in (48, 49, 51):
            # M51 without $ switches every spindle, as M48 and M49 do
            only = dollar(words) if code == 51 else None
            for spindle in range(self.num_spindles):
                if only is None or spindle == only:
                    self._speed_override(spindle, on)
                    self.spindles.set_override(spindle, on)
        if code == 52:
            (canon.enable_adaptive_feed if on else canon.disable_adaptive_feed)()
            self.adaptive_feed = on
        if code == 53:
            (canon.enable_feed_hold if on else canon.disable_feed_hold)()
            self.feed_hold = on

    def _speed_override(self, spindle: int, on: bool) -> None:
        """ENABLE/DISABLE_SPEED_OVERRIDE: the canon keeps one switch for all
        spindles, the last one told (what a tapping cycle reads back)."""
        if on:
            self.canon.enable_speed_override(spindle)
        else:
            self.canon.disable_speed_override(spindle)
        self.world.speed_override = on

    # ------------------------------------------------------------------
    # M0, M1, M2, M30, M60
    # ------------------------------------------------------------------
    def _stop(self, code: int) -> None:
        self._comp_flush_for_stop()
        canon = self.canon
        if code == 0:
            canon.program_stop()
        elif code == 60:
            canon.pallet_shuttle()
            canon.program_stop()
        elif code == 1:
            canon.optional_program_stop()
        elif code in (2, 30) or (code == 99 and self.call_level == 0):
            # M99 outside any call ends the program exactly as M2 does (a
            # Fanuc subroutine's own M99 is compiled as its return).
            self._program_end(code == 30)

    def _program_end(self, pallet: bool) -> None:
        """M2/M30: rs274 resets these settings, then ends the program."""
        canon = self.canon
        cur = [c + o for c, o in zip(self.current, self.origin)]
        cur[0], cur[1] = rotate(cur[0], cur[1], self.rotation)
        self.origin_index = 1
        self.params.set_internal(COORD_SYSTEM, 1.0)
        self._load_system(1)
        cur[0], cur[1] = rotate(cur[0], cur[1], -self.rotation)
        self.current = [c - o for c, o in zip(cur, self.origin)]
        self._announce_g5x()
        canon.set_xy_rotation(self.rotation)
        if self.plane != "XY":
            canon.select_plane("XY")
            self.plane = "XY"
        self.distance_incremental = False
        self.feed_mode = UNITS_PER_MINUTE
        canon.set_feed_mode(0, 0)
        self._set_feed_rate(0.0)
        if not self.feed_override:
            canon.enable_feed_override()
            self.feed_override = True
        self._comp_stop()
        # Each spindle is stopped and told G97; rs274 marks its speed
        # override on without telling the canon, and keeps the G96 mode.
        for spindle in range(self.num_spindles):
            canon.stop_spindle_turning(spindle)
            self.spindles.set_turning(spindle, STOPPED)
            self.spindles.set_override(spindle, True)
            canon.set_spindle_mode(spindle, 0.0)
        self.motion_mode = G1
        if self.mist:
            canon.mist_off()
            self.mist = False
        if self.flood:
            canon.flood_off()
            self.flood = False
        if pallet:
            canon.pallet_shuttle()
        canon.program_end()
        if self._percent_unclosed():
            canon.comment("interpreter: percent sign missing from end of file")
        raise ProgramEnd()

    def _percent_unclosed(self) -> bool:
        """Does the main file open with a % line but never close with one?"""
        source = self.source
        if source is None or source.end[1]:
            return False
        # The file is demarcated when its first non-blank line is "%".
        return source.first_line() == "%"
