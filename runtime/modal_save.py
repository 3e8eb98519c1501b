"""M70-M73: saving and restoring the modal state, as rs274 2.9 does it.

A mixin of :class:`runtime.machine.Machine`. rs274 keeps one saved state per
call level (the O-call stack frame). ``M70`` saves into the current frame,
``M73`` does too and marks the frame to be restored when the subroutine
returns, ``M71`` forgets the frame's state and ``M72`` restores it.

Restoring does not set variables: rs274 compares the saved state with the
current one, writes the difference as G-code text and *executes* that text,
so every change makes its ordinary canonical calls. Facts of that text that
show in the trace (all confirmed against rs274):

* a units change (G20/G21) runs first, on a line of its own;
* then one line: F (printed ``%.1f``) and S (``%.0f``) when they differ,
  the differing G codes (plane, cutter compensation, distance mode, feed
  mode, coordinate system, G43/G49, retract mode, G61/G61.1, spindle mode,
  arc distance mode, lathe mode, G92.3/G92.2 from #5210), G64 with its
  tolerances (``%f``), and the first differing M code; every further
  differing M code (spindle, mist/M9, flood, overrides, adaptive feed,
  feed hold) runs on a line of its own. The override switches are saved as
  M48 or M51 by the feed switch alone, so restoring a state with the feed
  override off runs "M51", which turns the *speed* override on. The motion mode is never restored,
  nor an M code whose saved value is "none" (e.g. flood off);
* those lines have no N word, so the trace shows ``N.....`` for them;
* rs274 reads the restore lines into the block it is executing: once any
  restore line ran, the rest of the ``M72`` line (its coolant, override and
  G codes, its motion, its stop code) is lost.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, List, Optional, Tuple

from collections import namedtuple

from runtime import blockcheck
from runtime.codes import (
    G7,
    G8,
    G17,
    G17_1,
    G18,
    G18_1,
    G19,
    G19_1,
    G20,
    G21,
    G40,
    G41,
    G42,
    G43,
    G49,
    G54,
    G55,
    G56,
    G57,
    G58,
    G59,
    G59_1,
    G59_2,
    G59_3,
    G64,
    G90,
    G90_1,
    G91,
    G91_1,
    G92_2,
    G92_3,
    G93,
    G94,
    G95,
    G96,
    G97,
    G98,
    G99,
    M_OFFSET,
)
from runtime.errors import GCodeError
from runtime.motion import INVERSE_TIME, UNITS_PER_MINUTE
from runtime.offsets import G92_ENABLED
from runtime.spindle_select import CONSTANT_RPM, m_code_of

_PLANE_CODES = {"XY": G17, "XZ": G18, "YZ": G19, "UV": G17_1, "UW": G18_1, "VW": G19_1}
_SYSTEM_CODES = (G54, G55, G56, G57, G58, G59, G59_1, G59_2, G59_3)

#: An M code slot whose value rs274 cannot write back ("none").
NONE = -1


class ModalState(namedtuple("ModalState", "units feed speed tolerance naivecam g m")):
    """What rs274's save_settings keeps, in the order it writes it back.

    ``g``: (plane, cutter comp, distance, feed mode, coordinate system, tool
    offset, retract mode, control mode, spindle mode, arc distance, lathe
    mode, G92 applied), rs274's active_g_codes order; ``m``: (spindle, mist,
    flood, overrides, adaptive feed, feed hold)."""

    __slots__ = ()


class SavedContext:
    """One call frame's saved state (None once M71 forgot it) and whether a
    return restores it. rs274 keeps the two as separate flags: M70 and M71
    leave an M73's auto-restore mark alone, so after "M73 ... M70" the M70
    state comes back at the return, and after "M73 M71 ... M70" too."""

    __slots__ = ("state", "auto_restore")

    def __init__(self, state: Optional[ModalState], auto_restore: bool):
        self.state = state
        self.auto_restore = auto_restore


class ModalSaveMixin:
    """M70-M73 (part of Machine)."""

    def _modal_state(self) -> ModalState:
        feed_modes = {INVERSE_TIME: G93, UNITS_PER_MINUTE: G94}
        g = (
            _PLANE_CODES[self.plane],
            # the side in force (a negative diameter swapped it), never the
            # .1 form: restored as G41/G42 without D, which fails while
            # compensation is on and takes the tool's diameter when off
            (G40, G41, G42)[self._cc.side],
            G91 if self.distance_incremental else G90,
            feed_modes.get(self.feed_mode, G95),
            _SYSTEM_CODES[self.origin_index - 1],
            G43 if any(self.tool_offset) else G49,
            G99 if self.retract_r_plane else G98,
            self.control_mode,
            G97 if self.spindles.mode(0) == CONSTANT_RPM else G96,
            G90_1 if self.ijk_absolute else G91_1,
            G7 if self.lathe_diameter else G8,
            G92_3 if self.params[G92_ENABLED] else G92_2,
        )
        spindle = m_code_of(self.spindles.turning(0))
        # rs274 means to encode both switches (M48-M51), but it tests the
        # address of its per-spindle speed switches, always true: only the
        # feed switch counts, as M48 (on) or M51 (off).
        overrides = 48 if self.feed_override else 51
        m = (
            spindle,
            7 if self.mist else (NONE if self.flood else 9),
            8 if self.flood else NONE,
            overrides,
            52 if self.adaptive_feed else NONE,
            53 if self.feed_hold else NONE,
        )
        return ModalState(
            G20 if self.inches else G21,
            self.feed_rate,
            self.spindles.speed(0),
            self.path_tolerance,
            self.naivecam_tolerance,
            g,
            m,
        )

    @property
    def _contexts(self) -> Dict[int, SavedContext]:
        # Once a state may be saved, calls take the general frame path.
        self._plain_frames = False
        return self._saved_contexts

    # ------------------------------------------------------------------
    # The M codes
    # ------------------------------------------------------------------
    def _save_context(self, auto_restore: bool) -> None:
        """M70, or M73 (auto_restore): only a call frame can be returned from."""
        frame = self._contexts.get(self.call_level)
        auto = auto_restore and self.call_level > 0
        if frame is None:
            self._contexts[self.call_level] = SavedContext(self._modal_state(), auto)
        else:
            frame.state = self._modal_state()
            frame.auto_restore = frame.auto_restore or auto

    def _forget_context(self) -> None:
        """M71."""
        frame = self._contexts.get(self.call_level)
        if frame is not None:
            frame.state = None

    def _restore_context(self) -> bool:
        """M72; True when restore lines ran (the rest of the line is lost)."""
        saved = self._contexts.get(self.call_level)
        if saved is None or saved.state is None:
            raise GCodeError(
                "Cannot restore context from invalid stack frame - missing M70/M73?"
            )
        return self._restore(saved.state)

    # ------------------------------------------------------------------
    # Call frames
    # ------------------------------------------------------------------
    def _new_frame(self, level: int) -> None:
        """A call frame starts with nothing saved."""
        if self._saved_contexts:  # (not _contexts: reading is not saving)
            self._saved_contexts.pop(level, None)

    def _left_frame(self, level: int) -> None:
        """After a subroutine at ``level`` returned: an M73 state comes back."""
        if not self._contexts:
            return
        saved = self._contexts.get(level)
        if saved is not None and saved.auto_restore and saved.state is not None:
            self._restore(saved.state)
            # Outside any block: do what the end of a block does.
            self._publish_position()
            self.refresh_plain()

    # ------------------------------------------------------------------
    # Restoring
    # ------------------------------------------------------------------
    def _restore(self, saved: ModalState) -> bool:
        current = self._modal_state()
        ran = False
        if saved.units != current.units:
            self._run_restore_line([saved.units], {})
            ran = True
            current = self._modal_state()
        codes, words = _settings_line(saved, current)
        lines = _m_lines(saved.m, current.m)
        if lines:
            codes.append(lines[0])
        if codes or words:
            self._run_restore_line(codes, words)
            ran = True
        for code in lines[1:]:
            self._run_restore_line([code], {})
            ran = True
        return ran

    def _run_restore_line(self, codes: List[int], words: Dict[str, float]) -> None:
        """Execute one line of restore text, as rs274's execute(text) does.
        A failing line is reported with its text (e.g. G42 restored while
        compensation is on)."""
        self.announce_block(None)
        # The fast path shares the current point: work on a copy.
        self.current = list(self.current)
        try:
            block = blockcheck.read_block(codes, words)
            blockcheck.enhance(block, self.plane, self.motion_mode)
            blockcheck.check(block, self.distance_incremental)
            self._execute(block, None)
        except GCodeError as error:
            if codes in ([G20], [G21]) and not words:
                raise  # (units cannot fail)
            raise GCodeError(
                "M7x: restore_settings failed executing: '%s': %s"
                % (_restore_text(codes, words), error.message),
                error.location,
            ) from None


def _restore_text(codes: List[int], words: Dict[str, float]) -> str:
    """The text rs274 writes for a restore line (gen_settings, then the
    first M code: `` F10.0 G42 G64 P0.010000M5``)."""
    text = ""
    if "f" in words:
        text += " F%.1f" % words["f"]
    if "s" in words:
        text += " S%.0f" % words["s"]
    for code in codes:
        if code >= M_OFFSET:
            text += "M%d" % (code - M_OFFSET)
        elif code == G64:
            text += " G64"
            if "p" in words:
                text += " P%f" % words["p"]
                if "q" in words:
                    text += " Q%f" % words["q"]
        elif code % 10:
            text += " G%d.%d" % (code // 10, code % 10)
        else:
            text += " G%d" % (code // 10)
    return text


def _settings_line(saved: ModalState, current: ModalState):
    """rs274's gen_settings: F, S, the differing G codes, then G64."""
    codes: List[int] = []
    words: Dict[str, float] = {}
    if saved.feed != current.feed:
        words["f"] = float("%.1f" % saved.feed)
    if saved.speed != current.speed:
        words["s"] = float("%.0f" % saved.speed)
    g64_changed = (saved.tolerance, saved.naivecam) != (
        current.tolerance,
        current.naivecam,
    )
    for was, now in zip(saved.g, current.g):
        if was == now:
            continue
        if was == G64:
            g64_changed = True  # written last, with its tolerances
        else:
            codes.append(was)
    if saved.g[_CONTROL] == G64 and g64_changed:
        codes.append(G64)
        if saved.tolerance >= 0:
            words["p"] = float("%f" % saved.tolerance)
            if saved.naivecam >= 0:
                words["q"] = float("%f" % saved.naivecam)
    return codes, words


#: Index of the control mode in ModalState.g.
_CONTROL = 7


def _m_lines(saved: Tuple[int, ...], current: Tuple[int, ...]) -> List[int]:
    """rs274's gen_m_codes: each differing M code it can write, in order."""
    return [
        M_OFFSET + was for was, now in zip(saved, current) if was != now and was != NONE
    ]


__all__ = ["ModalSaveMixin", "ModalState"]
