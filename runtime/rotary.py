"""Rotary axes the INI file makes special: wrapped axes and locking indexers.

A mixin of :class:`runtime.machine.Machine`. rs274 2.9 reads, for each of
A, B and C, ``[AXIS_<letter>] WRAPPED_ROTARY`` and ``LOCKING_INDEXER_JOINT``
(runtime.inifile).

A *wrapped* axis counts its angles modulo 360:

* an absolute A, B or C word (also under G53, and the G28/G30 reference
  point) is a place on the circle, not a position: rs274's unwrap_rotary
  goes there from the current angle, forwards for a positive word and
  backwards for a negative one (the word's sign, ``-0`` included, not the
  sign of the angle once the offsets are taken off), and a word of 360 or
  more either way is "Invalid absolute position ...". Incremental words
  move by their value, unchecked;
* G92, G52 and G10 L20 refuse such words the same way (G10 L2 does not);
* G28.1/G30.1 and the probe's #5064-#5066 store angles in [0, 360).

A *locking indexer* moves only by itself, with G0 ("Indexing axis %c can
only be moved with G0" / "... alone"), unlocked, moved and locked in exact
path mode, the canon's path mode put back after (the stand-alone canon
prints nothing for the unlocking and locking). G28, G30 and a tool change
at G30 first index each indexer that must move, one at a time, A B C.

An indexer move whose end point fails (a wrapped indexer told to go a turn
or more) is rs274's "BUG: An axis incorrectly moved along with an indexer":
rs274 ignores the failure and finds the axes it never computed differ from
where they are. A reference point of 360 degrees or more that G28/G30 uses
on a wrapped axis is left out: rs274 moves to values it never computed, and
ngc2py says it does not support the case instead of moving somewhere.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional, Sequence

from runtime.blockcheck import Block
from runtime.codes import G0
from runtime.errors import GCodeError
from runtime.inifile import NO_INDEXER

#: The rotary axes: their indexes in a nine-axis point, and their words.
ROTARY_AXES = (3, 4, 5)
_LETTERS = "abc"
#: The axis words other than A, B and C (an indexer must move alone).
_OTHER_AXES = "xyzuvw"

_INVALID = "Invalid absolute position %5.2f for wrapped rotary axis %c"
_MOVED_ALONG = "BUG: An axis incorrectly moved along with an indexer"


def unwrap(sign_of: float, commanded: float, current: float, letter: str) -> float:
    """rs274's unwrap_rotary: where a wrapped axis goes for ``commanded``
    (taken without its sign), the direction given by the sign of
    ``sign_of``, the word as written."""
    if sign_of <= -360.0 or sign_of >= 360.0:
        raise GCodeError(_INVALID % (sign_of, letter.upper()))
    result = abs(commanded) + math.floor(current / 360.0) * 360.0
    backwards = math.copysign(1.0, sign_of) < 0.0
    if not backwards and result < current:
        result += 360.0
    if backwards and result > current:
        result -= 360.0
    return result


def wrap_angle(angle: float) -> float:
    """An angle in [0, 360) as rs274 stores it (fmod; -0.0 stays)."""
    angle = math.fmod(angle, 360.0)
    return angle + 360.0 if angle < 0 else angle


def check_wrapped_words(wrapped: Sequence[bool], words) -> None:
    """G92, G52, G10 L20: a wrapped axis' word must be less than 360 either way."""
    for on, letter in zip(wrapped, _LETTERS):
        value = words.get(letter)
        if on and value is not None and (value <= -360.0 or value >= 360.0):
            raise GCodeError(_INVALID % (value, letter.upper()))


def _unsupported(what: str) -> GCodeError:
    from runtime.mcodes import not_supported  # (mcodes imports runtime.motion)

    return not_supported(what)


def defined_point(point: List[Optional[float]]) -> List[float]:
    """``point``, when rs274 computed all of it (see _find_relative)."""
    if None in point:
        raise _unsupported(
            "a reference point of 360 degrees or more on a wrapped rotary axis"
            " (rs274 moves to values it never computed)"
        )
    return point


def rotary_rules(settings) -> bool:
    """Whether the INI makes any rotary axis wrapped or an indexer."""
    return any(settings.wrapped_rotary) or any(
        joint != NO_INDEXER for joint in settings.indexer_joints
    )


class RotaryMixin:
    """Wrapped rotary axes and locking indexers (part of Machine)."""

    # ------------------------------------------------------------------
    # Wrapped axes
    # ------------------------------------------------------------------
    def _unwrap_words(self, words, end: List[float]) -> None:
        """find_ends in absolute mode: the wrapped axes' words, unwrapped."""
        cur = self.current
        for on, i, letter in zip(self.settings.wrapped_rotary, ROTARY_AXES, _LETTERS):
            if on and letter in words:
                value = words[letter]
                end[i] = unwrap(value, value, cur[i], letter)

    def _unwrap_machine(self, i: int, value: float) -> float:
        """A wrapped axis' machine coordinate in the active system (G53,
        and G28/G30's reference point): the tool's offset comes off too."""
        commanded = value - self.origin[i] - self.g92[i] - self.tool_offset[i]
        return unwrap(value, commanded, self.current[i], _LETTERS[i - 3])

    def _saved_angles(self, values: List[float]) -> List[float]:
        """G28.1/G30.1: a wrapped axis' angle is kept in [0, 360)."""
        for on, i in zip(self.settings.wrapped_rotary, ROTARY_AXES):
            if on:
                values[i] = wrap_angle(values[i])
        return values

    # ------------------------------------------------------------------
    # Locking indexers
    # ------------------------------------------------------------------
    def _indexer_axis(self, motion: int, words) -> Optional[int]:
        """convert_motion's checks: the indexer this block moves, or None."""
        moved = [
            joint != NO_INDEXER and letter in words
            for joint, letter in zip(self.settings.indexer_joints, _LETTERS)
        ]
        if motion != G0:
            for on, letter in zip(moved, _LETTERS):
                if on:
                    raise GCodeError(
                        "Indexing axis %s can only be moved with G0" % letter.upper()
                    )
        others = any(letter in words for letter in _OTHER_AXES)
        for on, letter in zip(moved, _LETTERS):
            rotary = [other for other in _LETTERS if other != letter]
            if on and (others or any(other in words for other in rotary)):
                raise GCodeError(
                    "Indexing axis %s can only be moved alone" % letter.upper()
                )
        return ROTARY_AXES[moved.index(True)] if any(moved) else None

    def _straight_indexer(self, axis: int, block: Block) -> None:
        """A G0 of one indexer: rs274's convert_straight_indexer (the motion
        mode stays as it was)."""
        try:
            end = self._find_ends(block)
        except GCodeError:
            # rs274 ignores find_ends' failure and compares the values it
            # left unset (at least U, V and W, found after A, B and C) with
            # the current point: they differ, in every case tried
            raise GCodeError(_MOVED_ALONG) from None
        cur = self.current
        if any(end[i] != cur[i] for i in range(9) if i != axis):
            raise GCodeError(_MOVED_ALONG)
        self._index(axis, end[axis])

    def _index_first(self, end: Sequence[float]) -> None:
        """G28, G30, a tool change at G30: each indexer that must move, alone."""
        for joint, i in zip(self.settings.indexer_joints, ROTARY_AXES):
            if joint != NO_INDEXER and end[i] != self.current[i]:
                self._index(i, end[i])

    def _index(self, axis: int, target: float) -> None:
        """rs274's issue_straight_index: one axis unlocked, moved in exact
        path mode and locked; the canon's path mode put back."""
        world = self.world
        saved = (world.control_mode, world.control_tolerance, world.naivecam_tolerance)
        if saved[0] != "EXACT_PATH":
            self._canon_control_mode("EXACT_PATH", 0.0)
        end = list(self.current)
        end[axis] = target
        # Not a move of the program's path: cutter compensation never sees it.
        self.canon.straight_traverse(*end)
        self.current = world.position = end
        if saved[0] != "EXACT_PATH":
            self._canon_control_mode(saved[0], saved[1])
            self._canon_naivecam(saved[2])


__all__ = [
    "ROTARY_AXES",
    "RotaryMixin",
    "check_wrapped_words",
    "defined_point",
    "rotary_rules",
    "unwrap",
    "wrap_angle",
]
