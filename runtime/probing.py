"""Straight probing, G38.2-G38.5, as rs274 and its stand-alone canon do it.

A mixin of :class:`runtime.machine.Machine`. rs274's convert_probe checks
the block and sends TURN_PROBE_ON, STRAIGHT_PROBE, TURN_PROBE_OFF. Where the
probe stops is not the interpreter's to know: when it reads the next line it
asks the canon (``set_probe_data``). The stand-alone canon pretends the probe
tripped exactly at the programmed point and that the machine then backed off
0.254 mm (0.01 inch) towards where it came from, so

* #5061-#5066 become the programmed X, Y, Z, A, B, C, #5067-#5069 (U, V, W)
  and #5070 (probe tripped) 0;
* the current point becomes the canon's own idea of the position, which is
  the backed-off one (see :mod:`runtime.world`).

(PROBEOPEN/PROBECLOSE comments only mean something to the real machine's
canon; rs274 prints them as ordinary comments.)
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List

from runtime.arcs import UNITS_PER_REVOLUTION
from runtime.blockcheck import Block
from runtime.codes import G38_2
from runtime.errors import GCodeError

#: First of the probe result parameters #5061-#5070.
PROBE_PARAMS = 5061

#: How far the stand-alone canon backs off, in its length units.
_BACKOFF_MM, _BACKOFF_INCH = 0.254, 0.01


class ProbingMixin:
    """G38.2-G38.5 (part of Machine)."""

    def _probe(self, motion: int, block: Block) -> None:
        """convert_probe. G38.3 and G38.5 (bit 1 of the type: no error when
        the probe does not trip) may probe towards the current point."""
        probe_type = motion - G38_2
        if self.cutter_comp:
            raise GCodeError("Cannot probe with cutter radius comp on")
        if self.feed_rate == 0.0:
            raise GCodeError("Cannot probe with zero feed rate")
        if self.feed_mode == UNITS_PER_REVOLUTION:
            raise GCodeError("Cannot probe with feed per rev mode")
        end = self._find_ends(block)
        if not probe_type & 1 and end == self.current:
            raise GCodeError("Start point too close to probe point")
        canon = self.canon
        canon.turn_probe_on()
        self._emit_probe(end, probe_type)
        canon.turn_probe_off()
        self.motion_mode = motion
        self.probe_flag = True

    def _emit_probe(self, end: List[float], probe_type: int) -> None:
        """STRAIGHT_PROBE, and what the stand-alone canon makes of it."""
        self.canon.straight_probe(*end, probe_type)
        world = self.world
        pos = world.position
        self._probe_point = end[:6] + [0.0, 0.0, 0.0]
        dx, dy, dz = pos[0] - end[0], pos[1] - end[1], pos[2] - end[2]
        distance = math.sqrt((dx * dx) + (dy * dy) + (dz * dz))
        xyz = list(pos[:3])
        if distance != 0:
            backoff = _BACKOFF_INCH if world.inches else _BACKOFF_MM
            xyz = [
                end[0] + (backoff * (dx / distance)),
                end[1] + (backoff * (dy / distance)),
                end[2] + (backoff * (dz / distance)),
            ]
        # A new list: the machine may share the old one (runtime.fast.moves).
        world.position = xyz + list(end[3:6])

    def _after_probe(self) -> None:
        """rs274's set_probe_data, done as it reads the next line."""
        self.probe_flag = False
        self.current = self.world.reported_position()
        set_param = self.params.set_internal
        point = list(self._probe_point)
        if self._rotary_rules:
            point = self._saved_angles(point)
        for i, value in enumerate(point):
            set_param(PROBE_PARAMS + i, value)
        set_param(PROBE_PARAMS + 9, 0.0)  # the canon's probe never trips
        self._publish_position()


__all__ = ["ProbingMixin", "PROBE_PARAMS"]
