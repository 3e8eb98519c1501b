"""What rs274's stand-alone canon remembers, and reports back when asked.

rs274 is the interpreter plus a dummy "canon" world model (saicanon.cc). The
interpreter sometimes *reads back* from that model instead of trusting its
own state, and the model is deliberately simple, so the read-back values can
differ from the interpreter's own idea:

* at start-up and after a tool change (M6, M61) the current position is
  re-read; the model tracks the last programmed end point, shifted by every
  G5x/G92 offset change but never rotated and never moved by tool length
  offsets;
* on a G20/G21 change the tool length offset and the feed rate are re-read,
  and the model never converts them to the new units;
* a canned cycle reads back the path control mode (which starts as
  continuous with tolerance 0 in the model, while the interpreter starts in
  G61) to switch to exact path and restore it afterwards;
* a tapping cycle reads back the speed override switch, of which the model
  keeps one for all spindles (the interpreter keeps one per spindle).

:class:`World` models exactly that, independently of the canon back end, so
every back end (trace, null, recording) sees the same calls.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Sequence

MM_PER_INCH = 25.4


class World:
    """The saicanon model: program position, offsets, units, tool offset, feed."""

    __slots__ = (
        "position",
        "g5x",
        "g92",
        "inches",
        "tool_offset",
        "feed_rate",
        "control_mode",
        "control_tolerance",
        "naivecam_tolerance",
        "speed_override",
    )

    def __init__(self) -> None:
        # X Y Z A B C (U V W read as 0). The machine's fast path shares its
        # own end-point list here, so this list is replaced, never changed.
        self.position: Sequence[float] = [0.0] * 6
        self.g5x: List[float] = [0.0] * 6
        self.g92: List[float] = [0.0] * 6
        self.inches = False
        self.tool_offset: List[float] = [0.0] * 9
        self.feed_rate = 0.0
        self.control_mode = "CONTINUOUS"
        self.control_tolerance = 0.0
        self.naivecam_tolerance = 0.0
        # one switch for every spindle: the last ENABLE/DISABLE_SPEED_OVERRIDE
        self.speed_override = True

    def set_control_mode(self, mode: str, tolerance: float) -> None:
        """SET_MOTION_CONTROL_MODE: only the continuous mode keeps a tolerance."""
        self.control_mode = mode
        self.control_tolerance = tolerance if mode == "CONTINUOUS" else 0.0

    def set_g5x(self, offsets: Sequence[float]) -> None:
        self._shift(self.g5x, offsets)

    def set_g92(self, offsets: Sequence[float]) -> None:
        self._shift(self.g92, offsets)

    def _shift(self, old: List[float], new: Sequence[float]) -> None:
        pos = self.position
        self.position = [pos[i] + old[i] - new[i] for i in range(6)]
        old[:] = new[:6]

    def use_units(self, inches: bool) -> None:
        """Scale the linear values when the units really change."""
        if inches == self.inches:
            return
        self.inches = inches
        self.position = list(self.position[:6])
        for values in (self.position, self.g5x, self.g92):
            for i in range(3):
                # The canon divides (rounding differs from * (1 / 25.4)).
                values[i] = (
                    values[i] / MM_PER_INCH if inches else values[i] * MM_PER_INCH
                )

    def move_to(self, x, y, z, a, b, c) -> None:
        self.position = [x, y, z, a, b, c]

    def reported_position(self) -> List[float]:
        """GET_EXTERNAL_POSITION_X..W: the model never tracks U, V, W."""
        return list(self.position[:6]) + [0.0, 0.0, 0.0]
