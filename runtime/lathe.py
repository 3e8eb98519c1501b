"""Spindle-synchronized motion: G33, G33.1 (rigid tapping) and the G76
threading cycle, as rs274's convert_straight and convert_threading_cycle
make them.

A mixin of :class:`runtime.machine.Machine`. Straight moves leave through
``_emit_move``; the rigid tap has its own canonical call and, as in rs274,
leaves the tool where it was (only the rotary and UVW positions take the
block's values).
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List

from runtime.blockcheck import Block
from runtime.codes import G33, G76
from runtime.errors import GCodeError
from runtime.ops import c_hypot, long_double_product, PI_L_OVER_180
from runtime.spindle_select import CLOCKWISE, COUNTERCLOCKWISE, check_dollar, dollar


class ThreadingMixin:
    """G33, G33.1 and G76 (part of Machine)."""

    def _spindle_synchronized(self, motion: int, block: Block) -> None:
        """convert_straight for the three spindle-synchronized motions."""
        self.motion_mode = motion
        end = self._find_ends(block)
        words = block.words
        if motion != G76 and self._cc.engaged:
            # rs274's convert_straight compensates G33 and G33.1 like G1,
            # before their spindle checks (and fails: see _comp_straight)
            self._comp_straight(None, end)
            return
        name = {G33: "G33", G76: "G76"}.get(motion, "G33.1")
        if "dollar" in words:
            # the line's spindle stays the active one (G95 and the cycles)
            check_dollar(words, name, self.num_spindles)
            self.active_spindle = dollar(words)
        if motion == G76:
            self._check_spindle_turning_for_g76()
            if end[3:] != self.current[3:]:
                raise GCodeError("Cannot move rotary axes with G76")
            self._threading_cycle(words, end)
            return
        self._check_spindle_turning(name)
        canon = self.canon
        canon.start_speed_feed_synch(self.active_spindle, words["k"], False)
        if motion == G33:
            self._emit_move(False, end)
            canon.stop_speed_feed_synch()
            return
        scale = max(words.get("i", 1.0), 1.0)
        self._emit_rigid_tap(end, scale)
        canon.stop_speed_feed_synch()

    def _emit_rigid_tap(self, end: List[float], scale: float) -> None:
        """RIGID_TAP goes down and comes back: X, Y and Z stay where they
        were; rs274 still takes the block's A, B, C, U, V and W."""
        self.canon.rigid_tap(end[0], end[1], end[2], scale)
        self.current = self.current[:3] + end[3:]

    def _active_spindle_turning(self) -> bool:
        direction = self.spindles.turning(self.active_spindle)
        return direction in (CLOCKWISE, COUNTERCLOCKWISE)

    def _check_spindle_turning(self, name: str) -> None:
        if not self._active_spindle_turning():
            raise GCodeError(f"Spindle not turning in {name}")

    def _check_spindle_turning_for_g76(self) -> None:
        if not self._active_spindle_turning():
            raise GCodeError(
                "Chosen spindle (%d) not turning in G76" % self.active_spindle
            )

    # ------------------------------------------------------------------
    # G76
    # ------------------------------------------------------------------
    def _threading_cycle(self, words, end: List[float]) -> None:
        """convert_threading_cycle: passes of growing depth, then the spring
        passes at full depth, then a traverse to the block's end point."""
        if self.cutter_comp:
            raise GCodeError(
                "Cannot use G76 threading cycle with cutter radius compensation on"
            )
        i_word, j_word, k_word = words["i"], words["j"], words["k"]
        if i_word == 0:
            raise GCodeError("In G76, I must not be 0")
        if j_word <= 0:
            raise GCodeError("In G76, J must be greater than 0")
        if k_word <= j_word:
            raise GCodeError("In G76, K must be greater than J")
        if self.lathe_diameter:
            i_word, j_word, k_word = i_word / 2, j_word / 2, k_word / 2
        start_z = self.current[2]
        full_dia_depth = abs(i_word)
        cut = _ThreadCut(
            boring=i_word > 0.0,
            safe_x=self.current[0],
            start_y=self.current[1],
            start_z=start_z,
            end_depth=abs(k_word) + abs(i_word),
            full_threadheight=abs(k_word),
            pitch=words["p"],
        )
        cut.entry_taper, cut.exit_taper = _taper_flags(words.get("l", -1.0))
        angle = words.get("q", -1.0)
        if angle == -1:
            angle = 0.0
        # rs274 multiplies by the long double M_PIl/180.
        angle = long_double_product(angle, PI_L_OVER_180)
        if end[2] > start_z:
            angle = -angle
        taper_dist = max(words.get("e", 0.0), 0.0)
        cut.taper_pitch = (
            cut.pitch * c_hypot(taper_dist, cut.full_threadheight) / taper_dist
            if taper_dist > 0.0
            else cut.pitch
        )
        cut.taper_dist = -taper_dist if end[2] > start_z else taper_dist
        tangent = math.tan(angle)
        cut.target_z = end[2] + abs(k_word) * tangent
        degression = words.get("r", 1.0)
        if degression < 1.0:
            degression = 1.0
        spring_cuts = int(words.get("h", 0.0))
        cut_increment = abs(j_word)
        depth = abs(i_word) + abs(j_word)
        passes = 1
        while depth < cut.end_depth:
            self._threading_pass(cut, depth, (depth - full_dia_depth) * tangent)
            passes += 1
            depth = full_dia_depth + cut_increment * math.pow(passes, 1.0 / degression)
        depth = cut.end_depth
        zoff = (depth - full_dia_depth) * tangent
        for _ in range(spring_cuts + 1):
            self._threading_pass(cut, depth, zoff)
        self._emit_move(True, end)

    def _threading_pass(self, cut: "_ThreadCut", depth: float, zoff: float) -> None:
        """rs274's threading_pass: back, in, over (tapered ends as asked), out."""
        canon = self.canon
        rest = self.current[3:]

        def move(rapid: bool, x: float, z: float) -> None:
            self._emit_move(rapid, [x, cut.start_y, z] + rest)

        def x_at(inset: float) -> float:
            # In from the safe X by ``depth``, less ``inset``; boring goes outwards.
            if cut.boring:
                return cut.safe_x + depth - inset
            return cut.safe_x - depth + inset

        start_z = cut.start_z - zoff
        move(True, x_at(cut.end_depth), start_z)  # back
        if cut.taper_dist and cut.entry_taper:
            canon.disable_feed_override()
            canon.start_speed_feed_synch(self.active_spindle, cut.taper_pitch, False)
            move(False, x_at(cut.full_threadheight), start_z)  # in
            move(False, x_at(0.0), start_z - cut.taper_dist)  # angled in
            canon.start_speed_feed_synch(self.active_spindle, cut.pitch, False)
        else:
            move(True, x_at(0.0), start_z)  # in
            canon.disable_feed_override()
            canon.start_speed_feed_synch(self.active_spindle, cut.pitch, False)
        end_z = cut.target_z - zoff
        if cut.taper_dist and cut.exit_taper:
            move(False, x_at(0.0), end_z + cut.taper_dist)  # over
            canon.start_speed_feed_synch(self.active_spindle, cut.taper_pitch, False)
            move(False, x_at(cut.full_threadheight), end_z)  # angled out
        else:
            move(False, x_at(0.0), end_z)  # over
        canon.stop_speed_feed_synch()
        move(True, x_at(cut.end_depth), end_z)  # out
        canon.enable_feed_override()


class _ThreadCut:
    """The quantities every pass of one G76 cycle shares."""

    def __init__(self, **values: float) -> None:
        self.__dict__.update(values)
        self.entry_taper = self.exit_taper = False
        self.taper_dist = 0.0
        self.taper_pitch = self.target_z = 0.0


def _taper_flags(l_word: float):
    """L: 1 tapers the entry, 2 the exit, 3 both; negative means none."""
    flags = max(int(l_word), 0)
    return bool(flags & 1), bool(flags & 2)


__all__ = ["ThreadingMixin"]
