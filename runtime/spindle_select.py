"""Spindles: how many there are, the $ word that picks one, and what
rs274 remembers of each.

rs274 reads the number of spindles from ``[TRAJ]SPINDLES`` (one when the
INI file does not say) and keeps it as it is: 0 or a negative number leaves
no spindle for the codes that go through them all, while the codes without
$ still act on spindle 0. Its arrays have room for eight spindles
(EMCMOT_MAX_SPINDLES); with more, each spindle past the eighth is written
over the arrays that follow in memory, and rs274's answers then depend on
those bytes. :class:`Spindles` keeps the arrays as rs274 lays them out, so
such a machine reads back what rs274 reads back.

Where a code allows it, $-1 means "every spindle". Any other number outside
the machine's spindles fails when rs274 executes the step that reads it
(not when it checks the line), each step with its own message; G33, G33.1,
G76 and the tapping cycles are checked where they run. rs274 keeps $ as an
int, so a fraction is truncated towards zero first.
"""

from __future__ import annotations

from struct import Struct

from runtime.errors import GCodeError

#: rs274's room for spindles (EMCMOT_MAX_SPINDLES).
MAX_SPINDLES = 8

#: rs274's CANON_DIRECTION values. A spindle past the first that nothing
#: has stopped or started reads 0: neither stopped nor turning.
STOPPED, CLOCKWISE, COUNTERCLOCKWISE = 1, 2, 3

#: rs274's SPINDLE_MODE values (G97, G96).
CONSTANT_RPM, CONSTANT_SURFACE = 0, 1

#: rs274's CANON_SPEED_FEED_MODE at start-up (CANON_INDEPENDENT), kept
#: between the modes and the override switches.
_INDEPENDENT = 2

_DOUBLE = Struct("<d")
_INT = Struct("<i")

# The spindle fields of rs274's setup struct, in order: speed (double[8]),
# spindle_mode (int[8]), speed_feed_mode (int), speed_override (bool[8]),
# spindle_turning (int[8]), then the error-report stack (char[50][80]) that
# a spindle past the eighth overwrites. Offsets in bytes.
_SPEED = 0
_MODE = _SPEED + 8 * MAX_SPINDLES
_FEED_MODE = _MODE + 4 * MAX_SPINDLES
_OVERRIDE = _FEED_MODE + 4
_TURNING = _OVERRIDE + MAX_SPINDLES
_END = _TURNING + 4 * MAX_SPINDLES + 50 * 80


class Spindles:
    """rs274's per-spindle state: speed, G96/G97 mode, override switch and
    direction, as it keeps them after start-up (every speed 0, every mode
    G97, every override on, spindle 0 stopped). Writes beyond the modelled
    bytes are lost and reads there give 0 (rs274 would reach its tool
    offsets and tables, from about 500 spindles on)."""

    __slots__ = ("memory",)

    def __init__(self) -> None:
        self.memory = bytearray(_END)
        _INT.pack_into(self.memory, _FEED_MODE, _INDEPENDENT)
        self.memory[_OVERRIDE : _OVERRIDE + MAX_SPINDLES] = b"\1" * MAX_SPINDLES
        _INT.pack_into(self.memory, _TURNING, STOPPED)

    def __eq__(self, other) -> bool:
        return isinstance(other, Spindles) and self.memory == other.memory

    __hash__ = None

    def __repr__(self) -> str:
        shown = range(MAX_SPINDLES)
        return "Spindles(speed=%r, mode=%r, override=%r, turning=%r)" % tuple(
            [get(s) for s in shown]
            for get in (self.speed, self.mode, self.override, self.turning)
        )

    def _read(self, layout: Struct, offset: int):
        if offset + layout.size > _END:
            return 0
        return layout.unpack_from(self.memory, offset)[0]

    def _write(self, layout: Struct, offset: int, value) -> None:
        if offset + layout.size <= _END:
            layout.pack_into(self.memory, offset, value)

    def speed(self, spindle: int) -> float:
        return float(self._read(_DOUBLE, _SPEED + 8 * spindle))

    def set_speed(self, spindle: int, rpm: float) -> None:
        self._write(_DOUBLE, _SPEED + 8 * spindle, rpm)

    def mode(self, spindle: int) -> int:
        """CONSTANT_RPM, CONSTANT_SURFACE (or whatever overwrote it)."""
        return self._read(_INT, _MODE + 4 * spindle)

    def set_mode(self, spindle: int, mode: int) -> None:
        self._write(_INT, _MODE + 4 * spindle, mode)

    def override(self, spindle: int) -> int:
        """The speed override switch: 1 or 0, or the byte that overwrote it
        (rs274 reads a C++ bool as its byte)."""
        offset = _OVERRIDE + spindle
        return self.memory[offset] if offset < _END else 0

    def set_override(self, spindle: int, on: bool) -> None:
        offset = _OVERRIDE + spindle
        if offset < _END:
            self.memory[offset] = 1 if on else 0

    def turning(self, spindle: int) -> int:
        """STOPPED, CLOCKWISE, COUNTERCLOCKWISE, or another number."""
        return self._read(_INT, _TURNING + 4 * spindle)

    def set_turning(self, spindle: int, direction: int) -> None:
        self._write(_INT, _TURNING + 4 * spindle, direction)


def m_code_of(direction: int) -> int:
    """The M code rs274 reports for a direction (write_m_codes): anything
    not stopped or clockwise reads as M4."""
    if direction == STOPPED:
        return 5
    return 3 if direction == CLOCKWISE else 4


#: step -> (is -1 allowed, message)
_RULES = {
    "mode": (False, "Invalid spindle ($) number in Spindle Mode command"),
    "feed": (False, "Invalid spindle ($) number in Spindle Feed command"),
    "speed": (True, "Invalid spindle ($) number in Spindle speed command"),
    "m19": (False, "Spindle ($) number out of range in M19 Command"),
    "G33": (False, "Invalid spindle ($) number in G33 move"),
    "G33.1": (False, "Invalid spindle ($) number in G33.1 move"),
    "G76": (False, "Invalid D-number in G76 cycle"),
    "tap": (False, "Invalid spindle ($) number in G74/G84 cycle"),
    # (the XZ plane's tapping cycle has a message of its own)
    "tap XZ": (False, "Invalid E-number in G74/G84 cycle"),
}


def dollar(words):
    """The line's $ as rs274 keeps it (an int), or None."""
    value = words.get("dollar")
    return None if value is None else int(value)


def check_dollar(words, step: str, count: int) -> None:
    """Raise rs274's error when the line's $ names no spindle of the
    ``count`` spindles for ``step`` ("mode", "feed", "speed", "m3", "m4",
    "m5", "m19", "m51", "G33", "G33.1", "G76", "tap" or "tap XZ")."""
    number = dollar(words)
    if number is None:
        return
    if step == "m51":
        # M51 takes one spindle, never "all", and not spindle 0 either
        if number <= 0 or number >= count:
            raise GCodeError("Invalid spindle ($) number in M51 command")
        return
    if step in ("m3", "m4", "m5"):
        if not -1 <= number < count:
            raise GCodeError(
                "Spindle ($) number out of range in %s Command\nnum_spindles =%d. $=%d\n"
                % (step.upper(), count, number)
            )
        return
    all_allowed, message = _RULES[step]
    if not (-1 if all_allowed else 0) <= number < count:
        raise GCodeError(message)


def chosen(words, count: int):
    """The spindles a code with "all" for $-1 acts on: M3, M4, M5 and S
    (spindle 0 without $, even on a machine of no spindles)."""
    number = dollar(words)
    if number is None:
        return (0,)
    return range(count) if number == -1 else (number,)


__all__ = [
    "CLOCKWISE",
    "CONSTANT_RPM",
    "CONSTANT_SURFACE",
    "COUNTERCLOCKWISE",
    "MAX_SPINDLES",
    "STOPPED",
    "Spindles",
    "check_dollar",
    "chosen",
    "dollar",
    "m_code_of",
]
