"""Tools: T selection, M6 and M61 changes, G43/G43.1/G43.2/G49 length offsets.

A mixin of :class:`runtime.machine.Machine`. With ``[EMCIO]RANDOM_TOOLCHANGER``
rs274 keeps the same table (its stand-alone tool table is always laid out
for a non-random changer) but reports pockets as table indices, marks an
empty spindle as tool -1, never copies a G10 L1 edit to the spindle entry,
and reads ``G43 H<loaded tool>`` from the tool's pocket. The machine keeps its own
copy of the tool table as ``self.tools`` (a ToolTable whose ``slots`` map
table index -> ToolEntry and change as tools move), index 0 being the spindle (rs274 2.9's non-random tool changer; CHANGE_TOOL prints
the index, not the P word). Table values are in user units (inches).

rs274 quirks reproduced here, all confirmed against rs274:

* M6 copies the new tool into the spindle entry (the canon does it); M61
  does not, so after M61 the #5400 parameters and a G43 without H still use
  the tool of the last M6.
* After either change the next line starts by re-reading the current
  position from the canon's world model.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List

from runtime.blockcheck import TOOL_OFFSET, Block, round_to_int
from runtime.codes import G43, G43_1, G49
from runtime.errors import GCodeError
from runtime.motion import AXES, rotate
from runtime.offsets import G92_ENABLED, system_base
from runtime.rotary import defined_point
from runtime.spindle_select import STOPPED
from runtime.tooltable import ToolEntry, ToolTable

#: G10 L11 measures tool offsets against this coordinate system (G59.3).
FIXTURE_SYSTEM = 9

#: A placeholder M group that makes a block without M codes go through the
#: M code step (RETAIN_G43); no M code has it.
RETAIN_STEP = -1

TOOL_PARAMS = 5400  # 5400 tool number, 5401-5409 offsets, 5410 diameter, ...


class ToolsMixin:
    """Tool selection, changes and length offsets (part of Machine)."""

    tools: ToolTable

    def _pocket_of(self, tool: int) -> int:
        """rs274's find_tool_pocket: tool 0 is always the spindle."""
        # -1 marks a table line without a T word: never a tool to find.
        pocket = 0 if tool == 0 else self.tools.find(tool) if tool > 0 else None
        if pocket is None:
            raise GCodeError(f"Requested tool {tool} not found in the tool table")
        return pocket

    def _entry(self, pocket: int) -> ToolEntry:
        return self.tools.slots.get(pocket) or ToolEntry()

    def _select_tool(self, tool: int) -> None:
        """T: find the tool now (errors show here), change it at M6."""
        self.selected_pocket = self._pocket_of(tool)
        self.selected_tool = tool
        self.canon.select_tool(tool)

    def _change_tool(self) -> None:
        """M6 as rs274's convert_tool_change does it with the default settings."""
        if self.cutter_comp:
            raise GCodeError("Cannot change tools with cutter radius compensation on")
        settings = self.settings
        self.canon.start_change()
        if not settings.tool_change_with_spindle_on:
            for spindle in range(self.num_spindles):
                self.canon.stop_spindle_turning(spindle)
                self.spindles.set_turning(spindle, STOPPED)
        if settings.tool_change_quill_up:
            up = list(self.current)
            up[2] = self._find_relative([0.0] * 9)[2]
            self._hidden_traverse(up)
        if settings.tool_change_at_g30:
            stored = [self.params[5181 + i] for i in range(9)]
            end = self._find_relative(self._user_to_program(stored))
            self._hidden_traverse(defined_point(end), index_first=True)
        self.canon.change_tool(self.selected_pocket)
        # rs274's own copy of the spindle entry changes only on the next line.
        self._spindle_before_change = self._entry(0)
        if self.selected_pocket != 0:
            self._canon_spindle_pocket = self._entry(self.selected_pocket).pocket
        self.tools.slots[0] = self._entry(self.selected_pocket)._replace(
            pocket=self._canon_spindle_pocket
        )
        self.current_pocket = self.selected_pocket
        self.toolchange_flag = True
        self._store_tool_parameters()

    def current_pocket_number(self) -> int:
        """``#<_current_pocket>``: a random changer reports the table index,
        the non-random one the P word of the tool there."""
        if self.settings.random_toolchanger:
            return self.current_pocket
        return self._entry(self.current_pocket).pocket

    def selected_pocket_number(self) -> int:
        """``#<_selected_pocket>``: as :meth:`current_pocket_number`, except
        that on a non-random changer a P word of 0 reads -1. Before any T
        word the selected index is 0, the spindle entry: -1 while the spindle
        entry has no pocket, but the loaded tool's pocket once a G10 L1/L10/
        L11 edit of that tool has been copied there."""
        if self.settings.random_toolchanger:
            return self.selected_pocket
        pocket = self._entry(self.selected_pocket).pocket
        return -1 if pocket == 0 else pocket

    # ------------------------------------------------------------------
    # [RS274NGC]RETAIN_G43
    # ------------------------------------------------------------------
    def _retain_g43(self, block: Block) -> None:
        """rs274's RETAIN_G43 step, after the tool change codes of *every*
        block: while any tool offset is in force it applies G43 (G49 when
        the selected pocket is the spindle) and writes that code into the
        block's tool offset group, so the block's G codes apply it again
        (replacing a G43.x of the line's own)."""
        if not any(self.tool_offset):
            return
        code = G43 if self.selected_pocket > 0 else G49
        self._tool_length_offset(code, {})
        block.g[TOOL_OFFSET] = code

    def _execute_retaining_g43(self, block: Block, comment) -> None:
        """Machine._execute for RETAIN_G43: the M code step runs for every
        block (installed per machine, so other machines pay nothing)."""
        if not block.m:
            block.m[RETAIN_STEP] = 0
        type(self)._execute(self, block, comment)

    def _hidden_traverse(self, end: List[float], index_first: bool = False) -> None:
        """A move the INI asks for around a tool change, hidden from AXIS's
        preview; to G30's point, locking indexers move first, alone."""
        self.canon.comment("AXIS,hide")
        if index_first and self._rotary_rules:
            self._index_first(end)
        self._emit_move(True, end)
        self.canon.comment("AXIS,show")

    def _set_tool_number(self, q) -> None:
        """M61 Qn: declare which tool is in the spindle, without moving anything."""
        tool = round_to_int(q) if q is not None else -1
        if tool < 0:
            raise GCodeError("Need non-negative Q-word to specify tool number with M61")
        self.current_pocket = self._pocket_of(tool)
        self.toolchange_flag = True
        self.canon.change_tool_number(self.current_pocket)
        self._store_tool_parameters()

    def _after_tool_change(self) -> None:
        """What rs274 does when it reads the line after a tool change."""
        self.toolchange_flag = False
        self._spindle_before_change = None
        # rs274 reloads its table from the canon's (load_tool_table).
        spindle = self.tools.slots.get(0)
        if spindle is not None:
            self.tools.slots[0] = spindle._replace(pocket=self._canon_spindle_pocket)
        self.current = self.world.reported_position()
        # rs274 refreshes #5420-#5428 too, before the line's words are read.
        self._publish_position()

    # ------------------------------------------------------------------
    # G10 L1 / L10 / L11
    # ------------------------------------------------------------------
    def _set_tool_entry(self, words) -> None:
        """rs274's convert_setup_tool: change a tool table entry."""
        p = words.get("p", -1.0)
        pocket = self._pocket_of(int(p + 0.5))
        if not any(letter in words for letter in "xyzabcuvwrqij"):
            raise GCodeError("G10 L1 without offsets has no effect")
        entry = self._entry(pocket)
        if int(words["l"]) == 1:
            offsets = self._direct_tool_offsets(entry, words)
        else:
            offsets = self._measured_tool_offsets(entry, words, int(words["l"]) == 11)
        changes = {"offsets": tuple(offsets)}
        if "r" in words:
            changes["diameter"] = self._program_to_user([words["r"]])[0] * 2.0
        if "i" in words:
            changes["frontangle"] = words["i"]
        if "j" in words:
            changes["backangle"] = words["j"]
        if words.get("q", -1.0) != -1.0:  # rs274's "no Q" is -1
            q = words["q"]
            if abs(int(q + 0.5) - q) >= 0.0001:
                raise GCodeError("Q number in G10 is not an integer")
            if int(q + 0.5) > 9:
                raise GCodeError("Invalid tool orientation")
            changes["orientation"] = int(q + 0.5)
        entry = entry._replace(**changes)
        self.tools.slots[pocket] = entry
        self._announce_tool_entry(pocket, entry)
        # A random changer's loaded tool has no home pocket to copy from.
        loaded = pocket == self.current_pocket and not self.settings.random_toolchanger
        if loaded:
            self.tools.slots[0] = entry
        self._store_tool_parameters()
        if loaded:
            self._announce_tool_entry(0, entry)

    def _announce_tool_entry(self, pocket: int, entry: ToolEntry) -> None:
        self.canon.set_tool_table_entry(
            pocket,
            entry.tool,
            entry.offsets,
            entry.diameter,
            entry.frontangle,
            entry.backangle,
            entry.orientation,
        )

    def _direct_tool_offsets(self, entry: ToolEntry, words) -> List[float]:
        """G10 L1: the words are the offsets (program units)."""
        given = self._program_to_user([words.get(letter, 0.0) for letter in AXES])
        return [
            given[i] if letter in words else entry.offsets[i]
            for i, letter in enumerate(AXES)
        ]

    def _measured_tool_offsets(
        self, entry: ToolEntry, words, to_fixture: bool
    ) -> List[float]:
        """G10 L10/L11: offsets that make the current point read as the words."""
        system = FIXTURE_SYSTEM if to_fixture else self.origin_index
        here = self._current_in_system(system, without_tool=True)
        if to_fixture and self.params[G92_ENABLED]:
            # L11 does not want the fixture to move with G92: undo it.
            here = [h + g for h, g in zip(here, self._stored_g92())]
        rotation = self.params[system_base(system) + 10]
        old = self._user_to_program(entry.offsets)
        new = list(old)
        if "x" in words or "y" in words:
            new[0], new[1] = _measured_xy(words, here, old, rotation)
        for i in range(2, 9):
            if AXES[i] in words:
                new[i] = here[i] - words[AXES[i]]
        return self._program_to_user(new)

    def _store_tool_parameters(self) -> None:
        """#5400-#5413 describe the spindle entry."""
        spindle = self._entry(0)
        if self.settings.random_toolchanger:
            # An empty spindle is tool -1 there (rs274 2.9's convention).
            values: List[float] = [float(max(spindle.tool, -1))]
        else:
            values = [float(max(spindle.tool, 0))]
        values += spindle.offsets
        values += [
            spindle.diameter,
            spindle.frontangle,
            spindle.backangle,
            float(spindle.orientation),
        ]
        for i, value in enumerate(values):
            self.params.set_internal(TOOL_PARAMS + i, value)

    # ------------------------------------------------------------------
    # G43 family
    # ------------------------------------------------------------------
    def _tool_length_offset(self, code: int, words) -> None:
        if self.cutter_comp:
            raise GCodeError(
                "Cannot change tool offset with cutter radius compensation on"
            )
        if code == G49:
            offset = [0.0] * 9
        elif code == G43:
            offset = self._user_to_program(
                self._entry(self._offset_pocket(words)).offsets
            )
        elif code == G43_1:
            offset = list(self.tool_offset)
            for i, letter in enumerate("xyzabcuvw"):
                if letter in words:
                    offset[i] = words[letter]
        else:
            offset = self._added_tool_offset(words)
        self._apply_tool_offset(offset)

    def _added_tool_offset(self, words) -> List[float]:
        """G43.2: the offsets in force plus a tool's (H) or the axis words."""
        axes = [letter in words for letter in "xyzabcuvw"]
        if "h" in words and any(axes):
            raise GCodeError("G43.2: Can not have both H and axis words")
        if "h" not in words and not any(axes):
            raise GCodeError("G43.2: No axes specified and H word missing")
        # rs274 looks the H word up even when there is none, as tool -1,
        # which is never found: axis words alone always fail.
        pocket = self._pocket_of(int(words.get("h", -1)))
        if "h" in words:
            extra = self._user_to_program(self._entry(pocket).offsets)
        else:
            extra = [words[a] if given else 0.0 for a, given in zip("xyzabcuvw", axes)]
        return [a + b for a, b in zip(self.tool_offset, extra)]

    def _offset_pocket(self, words) -> int:
        if "h" in words:
            pocket = self._pocket_of(int(words["h"]))
            if pocket == 0 and self.settings.random_toolchanger:
                return self.current_pocket  # "T12 M6 G43 H12" is tool 12's offset
            return pocket
        # During a change (same line as M6/M61) the tool is still in its pocket.
        return self.current_pocket if self.toolchange_flag else 0

    def _apply_tool_offset(self, offset: List[float]) -> None:
        self.canon.use_tool_length_offset(*offset)
        self.world.tool_offset = list(offset)
        old = self.tool_offset
        dx, dy = rotate(old[0] - offset[0], old[1] - offset[1], -self.rotation)
        cur = self.current
        cur[0] += dx
        cur[1] += dy
        for i in range(2, 9):
            cur[i] += old[i] - offset[i]
        self.tool_offset = offset


def _measured_xy(words, here, old, rotation):
    """X/Y tool offsets for G10 L10/L11, keeping an unnamed axis's component."""
    if "x" in words and "y" in words:
        return rotate(here[0] - words["x"], here[1] - words["y"], rotation)
    # Keep the part of the old offset along the axis not named (in the
    # possibly rotated system), replace the other.
    ox, oy = rotate(old[0], old[1], -rotation)
    if "x" in words:
        ox, oy = rotate(0.0, oy, rotation)
        tx, ty = rotate(here[0] - words["x"], 0.0, rotation)
    else:
        ox, oy = rotate(ox, 0.0, rotation)
        tx, ty = rotate(0.0, here[1] - words["y"], rotation)
    return tx + ox, ty + oy
