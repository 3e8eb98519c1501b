"""Coordinate systems and offsets: G54-G59.3, G10 L2/L20, G92 family, G52, G20/G21.

A mixin of :class:`runtime.machine.Machine`. The offsets live in program
units on the machine (``origin`` for G5x, ``g92`` for G92/G52, plus
``rotation`` in degrees); the numbered parameters keep them in *user* units,
which for rs274 are inches whatever G20/G21 says (so G21 programs see
parameters scaled by 25.4). The conversions are ``_user_to_program`` and
``_program_to_user``.

Each canonical offset call also goes to the world model, because rs274's
canon shifts its idea of the current position when offsets change.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Sequence

from runtime.errors import GCodeError
from runtime.motion import AXES, LINEAR, rotate
from runtime.rotary import check_wrapped_words

MM_PER_INCH = 25.4


def system_base(index: int) -> int:
    """Parameter number just below coordinate system ``index``'s X offset.

    System n (1 = G54 ... 9 = G59.3) keeps X..W in base+1..base+9 and its XY
    rotation in base+10: G54 uses 5221-5230.
    """
    return 5200 + 20 * index


G92_ENABLED = 5210  # non-zero while G92 offsets are in force
G92_FIRST = 5211  # 5211-5219: G92 offsets X..W
COORD_SYSTEM = 5220  # the active system, 1-9


class OffsetsMixin:
    """Offsets, coordinate systems and unit conversions (part of Machine)."""

    # ------------------------------------------------------------------
    # Units
    # ------------------------------------------------------------------
    # rs274 converts in two steps through mm, with the canon's user units
    # per mm (an inexact literal); the steps are kept so results round alike.
    def _user_to_program(self, values: Sequence[float]) -> List[float]:
        per_mm = self.user_units_per_mm
        prog = MM_PER_INCH if self.inches else 1.0
        return [v / per_mm / prog if i in LINEAR else v for i, v in enumerate(values)]

    def _program_to_user(self, values: Sequence[float]) -> List[float]:
        per_mm = self.user_units_per_mm
        prog = MM_PER_INCH if self.inches else 1.0
        return [v * prog * per_mm if i in LINEAR else v for i, v in enumerate(values)]

    def _set_units(self, inches: bool) -> None:
        """G20/G21: the canon call always; the conversions only on a real change."""
        self.canon.use_length_units(inches)
        self.world.use_units(inches)
        if inches == self.inches:
            return
        factor = 1.0 / MM_PER_INCH if inches else MM_PER_INCH
        self.inches = inches
        for values in (self.current, self.g92, self.origin):
            for i in LINEAR:
                values[i] *= factor
        self._comp_scale(factor)
        # rs274 re-reads these from its canon, which never converts them.
        self.tool_offset = list(self.world.tool_offset)
        self.feed_rate = self.world.feed_rate

    # ------------------------------------------------------------------
    # Canonical offset calls (with the world model)
    # ------------------------------------------------------------------
    def _announce_g5x(self) -> None:
        self.canon.set_g5x_offset(self.origin_index, *self.origin)
        self.world.set_g5x(self.origin[:6])

    def _announce_g92(self) -> None:
        self.canon.set_g92_offset(*self.g92)
        self.world.set_g92(self.g92[:6])

    # ------------------------------------------------------------------
    # G54 - G59.3
    # ------------------------------------------------------------------
    def _select_system(self, index: int) -> None:
        if self.cutter_comp:
            raise GCodeError(
                "Cannot change coordinate systems with cutter radius compensation on"
            )
        if index == self.origin_index:
            self.canon.comment("interpreter: continuing to use same coordinate system")
            return
        self.current = self._current_in_system(index)
        self.origin_index = index
        self.params.set_internal(COORD_SYSTEM, float(index))
        self._load_system(index)
        self._announce_g5x()
        self._announce_g92()
        self.canon.set_xy_rotation(self.rotation)

    def _load_system(self, index: int) -> None:
        """Copy system ``index``'s offsets and rotation from the parameters."""
        base = system_base(index)
        self.origin = self._user_to_program(
            [self.params[base + 1 + i] for i in range(9)]
        )
        self.rotation = self.params[base + 10]

    def _stored_g92(self) -> List[float]:
        return self._user_to_program([self.params[G92_FIRST + i] for i in range(9)])

    def _current_in_system(self, index: int, without_tool: bool = False) -> List[float]:
        """rs274's find_current_in_system: where we would be in system ``index``.

        ``without_tool``: as if no tool length offset were applied
        (find_current_in_system_without_tlo, for G10 L10/L11).
        """
        cur = [c + o for c, o in zip(self.current, self.g92)]
        cur[0], cur[1] = rotate(cur[0], cur[1], self.rotation)
        base = system_base(index)
        target = self._user_to_program([self.params[base + 1 + i] for i in range(9)])
        cur = [c + o for c, o in zip(cur, self.origin)]
        if without_tool:
            cur = [c + t for c, t in zip(cur, self.tool_offset)]
        cur = [c - t for c, t in zip(cur, target)]
        cur[0], cur[1] = rotate(cur[0], cur[1], -self.params[base + 10])
        if self.params[G92_ENABLED]:
            cur = [c - g for c, g in zip(cur, self._stored_g92())]
        return cur

    # ------------------------------------------------------------------
    # G10 L2 / L20
    # ------------------------------------------------------------------
    def _set_system(self, words) -> None:
        """rs274's convert_setup: change a coordinate system's offsets."""
        if "i" in words or "j" in words:
            raise GCodeError("I J words not allowed with G10 L2")
        index = int(words.get("p", -1.0) + 0.0001) or self.origin_index
        relative = int(words["l"]) == 20
        if relative:
            check_wrapped_words(self.settings.wrapped_rotary, words)
        if self.cutter_comp and index == self.origin_index:
            raise GCodeError(
                "Cannot change the active coordinate system with cutter radius compensation on"
            )
        here = self._current_in_system(index)
        base = system_base(index)
        stored = self._user_to_program([self.params[base + 1 + i] for i in range(9)])
        if "r" in words:
            if relative:
                raise GCodeError("R not allowed in G10 L20")
            self.params.set_internal(base + 10, words["r"])
        rotation = self.params[base + 10]
        offsets = list(stored)
        if relative:
            self._relative_xy(words, here, stored, rotation, offsets)
        else:
            for i in (0, 1):
                if AXES[i] in words:
                    offsets[i] = words[AXES[i]]
        for i in range(2, 9):
            letter = AXES[i]
            if letter in words:
                offsets[i] = (
                    here[i] + stored[i] - words[letter] if relative else words[letter]
                )
        for i, value in enumerate(self._program_to_user(offsets)):
            if AXES[i] in words or (relative and i < 2):
                self.params.set_internal(base + 1 + i, value)
        if index == self.origin_index:
            self._apply_active_system(offsets, rotation, relative)
        else:
            self.canon.comment("interpreter: setting coordinate system origin")

    @staticmethod
    def _relative_xy(words, here, stored, rotation, offsets) -> None:
        """G10 L20 in X/Y: offsets that make the current point read as the words."""
        x, y = here[0], here[1]
        old_x, old_y = rotate(x, y, rotation)
        new_x, new_y = rotate(words.get("x", x), words.get("y", y), rotation)
        offsets[0] = old_x + stored[0] - new_x
        offsets[1] = old_y + stored[1] - new_y

    def _apply_active_system(
        self, offsets: List[float], rotation: float, relative: bool
    ) -> None:
        cur = self.current
        if relative:
            # rs274 un-rotates the current point here, then rotates it again below.
            cur[0], cur[1] = rotate(cur[0], cur[1], self.rotation)
            self.rotation = 0.0
        cur[0], cur[1] = rotate(cur[0], cur[1], self.rotation)
        self.current = [c + o - n for c, o, n in zip(cur, self.origin, offsets)]
        self.origin = offsets
        self._announce_g5x()
        self.current[0], self.current[1] = rotate(
            self.current[0], self.current[1], -rotation
        )
        self.rotation = rotation
        self.canon.set_xy_rotation(rotation)

    # ------------------------------------------------------------------
    # G92, G92.1, G92.2, G92.3, G52
    # ------------------------------------------------------------------
    def _check_axis_offsets_allowed(self, words=None) -> None:
        if self.cutter_comp:
            raise GCodeError("Cannot change axis offsets with cutter radius comp")
        if words is not None:
            check_wrapped_words(self.settings.wrapped_rotary, words)

    def _g92(self, words) -> None:
        """Offset so the current point reads as the given values."""
        self._check_axis_offsets_allowed(words)
        self.params.set_internal(G92_ENABLED, 1.0)
        for i, letter in enumerate(AXES):
            if letter in words:
                self.g92[i] = self.current[i] + self.g92[i] - words[letter]
                self.current[i] = words[letter]
        self._announce_g92()
        self._store_g92()

    def _g52(self, words) -> None:
        """A local offset: the G92 offsets become the given values."""
        self._check_axis_offsets_allowed(words)
        self.params.set_internal(G92_ENABLED, 1.0)
        for i, letter in enumerate(AXES):
            if letter in words:
                self.current[i] = self.current[i] + self.g92[i] - words[letter]
                self.g92[i] = words[letter]
        self._announce_g92()
        self._store_g92()

    def _store_g92(self) -> None:
        for i, value in enumerate(self._program_to_user(self.g92)):
            self.params.set_internal(G92_FIRST + i, value)

    def _g92_cancel(self, keep_parameters: bool) -> None:
        """G92.1 (clear the parameters too) and G92.2 (keep them)."""
        self._check_axis_offsets_allowed()
        self.params.set_internal(G92_ENABLED, 0.0)
        self.current = [c + g for c, g in zip(self.current, self.g92)]
        self.g92 = [0.0] * 9
        self._announce_g92()
        if not keep_parameters:
            for i in range(9):
                self.params.set_internal(G92_FIRST + i, 0.0)

    def _g92_restore(self) -> None:
        """G92.3: reinstate the offsets stored in the parameters."""
        self._check_axis_offsets_allowed()
        self.params.set_internal(G92_ENABLED, 1.0)
        stored = self._stored_g92()
        self.current = [c + g - s for c, g, s in zip(self.current, self.g92, stored)]
        self.g92 = stored
        self._announce_g92()
