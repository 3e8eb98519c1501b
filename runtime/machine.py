"""The machine: modal state and rs274's per-block execution.

Generated code drives a :class:`Machine` (see docs/ARCHITECTURE.md for the
contract): ``m.block(...)`` for each ordinary line, ``m.call(...)`` for
subroutine calls, ``m.run(main)`` around the whole program. For every block
the machine does what rs274 does after reading a line:

1. read-time checks, ``enhance_block`` and ``check_items``
   (:mod:`runtime.blockcheck`), so a bad line fails before it does anything;
2. execution in ``execute_block``'s order: comment, feed mode, F, S, T,
   M codes (tool change, spindle, coolant, overrides), G codes (dwell,
   plane, units, cutter comp, tool length offset, coordinate system, path
   control, distance modes, group 0, motion) and last the stopping M codes.

The work is split over mixins by subject: :mod:`runtime.motion` (end points,
moves, arcs, homing), :mod:`runtime.cycles` (drilling canned cycles),
:mod:`runtime.offsets` (coordinate systems, G92, units) and
:mod:`runtime.tools` (T, M6, M61, G43). This module has the public API,
the execution order and the simple modal codes.

Threading (:mod:`runtime.lathe`), probing (:mod:`runtime.probing`),
splines (:mod:`runtime.splines`), lathe cycles (:mod:`runtime.lathe_cycles`)
and cutter radius compensation (:mod:`runtime.cutter_comp`) are mixins of
their own. Codes not implemented yet (M70-M73) raise a GCodeError that says
so, at the point rs274 would execute them.
"""

from __future__ import annotations

import io
import sys
from collections import namedtuple

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Callable, Dict, Iterator, Optional, TextIO

from runtime import blockcheck, fanuc_subs, loopflags, oflow, olabels, remap
from runtime.canon import Canon, TraceCanon
from runtime.blockcheck import (
    DRILL_CYCLES,
    LATHE_CYCLES,
    g_name,
    ARC_DISTANCE,
    COORD_SYSTEM as COORD_SYSTEM_GROUP,
    CUTTER_COMP,
    DISTANCE,
    FEED_MODE,
    G92_RESET,
    LATHE_MODE,
    M_STOP,
    NON_MODAL,
    PATH_CONTROL,
    PLANE,
    RETRACT,
    SPINDLE_MODE,
    TOOL_OFFSET,
    UNITS,
    Block,
    round_to_int,
)
from runtime.codes import (
    G0,
    G1,
    G2,
    G3,
    G4,
    G7,
    G10,
    G17,
    G17_1,
    G18,
    G18_1,
    G19,
    G19_1,
    G20,
    G28,
    G28_1,
    G30,
    G30_1,
    G33,
    G33_1,
    G38_2,
    G38_3,
    G38_4,
    G38_5,
    G40,
    G5,
    G5_1,
    G5_2,
    G41,
    G42,
    G5_3,
    G76,
    G52,
    G54,
    G55,
    G56,
    G57,
    G58,
    G59,
    G59_1,
    G59_2,
    G59_3,
    G61,
    G61_1,
    G80,
    G90_1,
    G91,
    G92,
    G92_2,
    G92_3,
    G93,
    G94,
    G95,
    G97,
    G98,
    g_code,
    m_code,
    to_integer,
)
from runtime.comments import CommentLines, execute_comment
from runtime.cutter_comp import LEFT, RIGHT, CutterCompMixin
from runtime.cycles import CyclesMixin
from runtime.errors import GCodeError, Location, g_code_frames_of_stack
from runtime.fast.moves import FastPathMixin
from runtime.inifile import IniSettings, load_ini
from runtime.mcodes import MCodesMixin, ProgramEnd, not_supported
from runtime.modal_save import ModalSaveMixin
from runtime.state import MachineState
from runtime.budget import DEFAULT_MAX_STEPS, StepBudgetMixin
from runtime.motion import (
    AXES,
    INVERSE_TIME,
    UNITS_PER_MINUTE,
    UNITS_PER_REVOLUTION,
    MotionMixin,
)
from runtime.lathe import ThreadingMixin
from runtime.lathe_cycles import LatheCyclesMixin
from runtime.probing import ProbingMixin
from runtime.rotary import RotaryMixin, rotary_rules
from runtime.spindle_select import (
    CLOCKWISE,
    CONSTANT_RPM,
    CONSTANT_SURFACE,
    STOPPED,
    check_dollar,
    chosen,
    dollar,
)
from runtime.splines import SplinesMixin
from runtime.offsets import COORD_SYSTEM, G92_ENABLED, OffsetsMixin
from runtime.params import (
    CALL_ARGS,
    ArgCountLocals,
    Globals,
    Locals,
    Params,
    unset_variable,
)
from runtime.tooltable import ToolTable, tool_table_for
from runtime.tools import ToolsMixin
from runtime.varfile import default_parameters, initial_parameters, save_parameter_file
from runtime.world import World

#: Plane codes -> the plane names runtime.arcs and the canon use.
_PLANES = {G17: "XY", G18: "XZ", G19: "YZ", G17_1: "UV", G18_1: "UW", G19_1: "VW"}
_PLANE_CODES = {name: code for code, name in _PLANES.items()}
#: What rs274 prints for planes it has no canon name for.
_CANON_PLANE = {
    "XY": "XY",
    "XZ": "XZ",
    "YZ": "YZ",
    "UV": "UNKNOWN",
    "UW": "UNKNOWN",
    "VW": "UNKNOWN",
}

_FEED_MODES = {G93: INVERSE_TIME, G94: UNITS_PER_MINUTE, G95: UNITS_PER_REVOLUTION}
_FEED_MODE_COMMENTS = {
    INVERSE_TIME: "interpreter: feed mode set to inverse time",
    UNITS_PER_MINUTE: "interpreter: feed mode set to units per minute",
    UNITS_PER_REVOLUTION: "interpreter: feed mode set to units per revolution",
}
#: G54 ... G59.3 -> coordinate system index 1 ... 9.
_SYSTEM_CODES = (G54, G55, G56, G57, G58, G59, G59_1, G59_2, G59_3)
_SYSTEMS = {code: index for index, code in enumerate(_SYSTEM_CODES, start=1)}

#: What rs274's stand-alone canon reports as its length units (inches per
#: mm, written as this rounded literal there).
USER_UNITS_PER_MM = 0.03937007874016

#: Numbered parameters run from 1 to MAX_PARAMETER - 1.
MAX_PARAMETER = 5602

#: rs274 refuses a call made from this call level (nine nested calls at most).
MAX_CALL_LEVEL = 9
#: A call's #1-#30: the slice of the parameter list, and what a call that
#: passes fewer arguments sets the rest to.
_CALL_ARGS_END = CALL_ARGS + 1
_NO_ARGS = (0.0,) * CALL_ARGS


class _Subroutine(namedtuple("_Subroutine", "fn file", defaults=(None,))):
    """A known subroutine: its function, and the file its definition was
    read in (None when rs274 found it by reading ahead for a call)."""

    __slots__ = ()


class Machine(
    FastPathMixin,
    MCodesMixin,
    MotionMixin,
    CyclesMixin,
    ThreadingMixin,
    ProbingMixin,
    SplinesMixin,
    LatheCyclesMixin,
    CutterCompMixin,
    OffsetsMixin,
    ToolsMixin,
    ModalSaveMixin,
    RotaryMixin,
    StepBudgetMixin,
    CommentLines,
    MachineState,
):
    """rs274's interpreter and its block execution, printing through
    ``canon``; its state is declared in runtime.state."""

    #: Predefined read-only named parameters (computed by :meth:`predefined`).
    PREDEFINED = frozenset(
        """_vmajor _vminor _line _motion_mode _plane _ccomp _metric _imperial
        _absolute _incremental _inverse_time _units_per_minute _units_per_rev
        _coord_system _tool_offset _retract_r_plane _retract_old_z
        _spindle_rpm_mode _spindle_css_mode _ijk_absolute_mode
        _lathe_diameter_mode _lathe_radius_mode _spindle_on _spindle_cw _mist
        _flood _speed_override _feed_override _adaptive_feed _feed_hold _feed
        _rpm _x _y _z _a _b _c _u _v _w _current_tool _current_pocket
        _selected_tool _selected_pocket _value _value_returned _task
        _call_level _remap_level _abs_x _abs_y _abs_z _abs_a _abs_b
        _abs_c _metric_machine""".split()
    )

    def __init__(
        self,
        canon: Optional[Canon] = None,
        tool_table=None,
        var_file=None,
        ini=None,
        block_delete=False,
        source=None,
        max_steps=DEFAULT_MAX_STEPS,
    ):
        """``canon`` defaults to the rs274 trace on stdout; the file options are
        paths, as rs274's ``-t``, ``-v`` and ``-i`` take them."""
        self.canon = TraceCanon(sys.stdout) if canon is None else canon
        self.world = World()
        #: rs274's -b switch: generated code skips "/" lines while it is set.
        self.block_delete = block_delete
        self.source = source
        self._set_budget(max_steps)
        self.settings = IniSettings() if ini is None else load_ini(ini)
        self.num_spindles = self.settings.num_spindles
        #: Calls need no more than fresh locals: no #<n_args> to set and no
        #: M70/M73 state to manage (then _enter_sub and _left_frame do).
        self._plain_frames = not self.settings.oword_nargs
        #: Wrapped rotary axes or locking indexers: moves of A, B and C
        #: take the general path (runtime.rotary).
        self._rotary_rules = rotary_rules(self.settings)
        # rs274 closes with one ON_RESET when it could read an INI file, two otherwise.
        ini_read = ini is not None and self.settings.opened
        self._closing_resets = 1 if ini_read else 2
        #: #<_ini[...]> names read from the INI file (read-only globals).
        self.ini_globals = set()
        #: rs274's user (machine) units per mm: its canon reports inches.
        self.user_units_per_mm = USER_UNITS_PER_MM
        self.var_file = var_file
        #: Where rs274's own complaints while running go (the parameter
        #: file's perror lines): kept here for a library caller, whose
        #: stderr stays untouched; the command line points it at stderr.
        self.messages: TextIO = io.StringIO()
        # The parameter stores generated code binds to p (params.values), g
        # and v: plain attributes, read at every function's start.
        self.params = Params(default_parameters())
        self.globals = Globals(self)
        #: The named locals of the running call (another store in each call).
        self.locals = Locals()
        table = tool_table_for(tool_table)
        #: What rs274 prints while loading the table (the CLI prints it).
        self.tool_table_report = table.load_report
        self.tools = ToolTable(dict(table.slots))
        # The canon keeps its own table, reloaded into rs274's after every tool
        # change: its spindle entry's pocket changes only by CHANGE_TOOL
        # (SET_TOOL_TABLE_ENTRY keeps pockets), while rs274's own copy of a
        # G10-edited loaded tool takes that tool's pocket until the reload.
        self._canon_spindle_pocket = self._entry(0).pocket
        if self.settings.retain_g43:
            # Every block takes the general path (runtime.tools).
            self._execute = self._execute_retaining_g43
        self._start_state()

    # ------------------------------------------------------------------
    # Parameter stores
    # ------------------------------------------------------------------
    @property
    def cutter_comp(self) -> bool:
        """Whether cutter radius compensation is on. The parameters keep the
        flag, since it makes reading the current position an error."""
        return self.params.cutter_comp

    @cutter_comp.setter
    def cutter_comp(self, on: bool) -> None:
        self.params.cutter_comp = on

    # ------------------------------------------------------------------
    # Running a program
    # ------------------------------------------------------------------
    def run(self, main: Callable[["Machine"], None]) -> None:
        """Run ``main`` between rs274's start-up and closing sequences.

        A bad parameter file stops rs274 during start-up, before its closing
        ON_RESET calls; everything later is followed by them, error or not.
        (The CLI prints the INI's ``settings.stderr_report``, not the machine.)
        """
        try:
            self._initialise()
            try:
                self._start()
                remap.refuse_standard_remaps(self.settings)
                self.refresh_plain()
                main(self)
            except ProgramEnd:
                pass
            except UnboundLocalError as error:
                raise unset_variable(error) from None
            except StopIteration as spent:  # the step budget (runtime.budget)
                if not self.budget_spent():
                    raise
                raise self.runaway().with_traceback(spent.__traceback__) from None
            finally:
                self.announce_block(None)
                for _ in range(self._closing_resets):
                    self.canon.on_reset()
                if self.var_file is not None:
                    self._save_parameters()
        finally:
            self.canon.flush()  # a trace canon keeps lines back (runtime.canon)

    def fail_open(self, message: str, location: Optional[Location] = None) -> None:
        """What rs274 does when it cannot open the program: the main file is
        missing ("Unable to open file <NAME>"), or holds nothing but blank
        lines ("File ended with no percent sign", ``location`` the last of
        them). It initialises, then stops: no ON_RESET, no closing save of
        the parameter file."""
        try:
            self._initialise()
        finally:
            self.canon.flush()
        raise GCodeError(message, location)

    def _save_parameters(self) -> None:
        """rs274 rewrites the -v file when it exits, even after an error.
        What it says about a failed link or rename goes to ``messages``."""
        values = self.params
        save_parameter_file(
            self.var_file,
            {n: values.get_internal(n) for n in range(1, MAX_PARAMETER)},
            self.messages,
        )

    def _initialise(self) -> None:
        """The canonical calls rs274 makes when it initialises, from the parameters."""
        canon = self.canon
        canon.use_length_units(False)
        if self.var_file is not None:
            self.params = Params(initial_parameters(self.var_file, self.messages))
        p = self.params
        if self.settings.disable_g92_persistence:
            for number in range(G92_ENABLED, G92_ENABLED + 10):
                p.set_internal(number, 0.0)
        index = int(p[COORD_SYSTEM] + 0.0001)  # 1-9: the var file reader repairs it
        self.origin_index = index
        self._load_system(index)
        self._announce_g5x()
        if p[G92_ENABLED]:
            self.g92 = self._stored_g92()
        self._announce_g92()
        canon.set_xy_rotation(self.rotation)
        canon.set_feed_reference(False)

    def _start(self) -> None:
        """What rs274 does once the program is open, before its first line."""
        self.canon.on_reset()
        self.current = self.world.reported_position()
        self._store_tool_parameters()

    def end_of_file(self, demarcated: bool, closed: bool) -> None:
        """The program ran off the end of the file without M2/M30."""
        if closed:
            self.announce_block(None)
            self.canon.finish()
            raise ProgramEnd()
        if demarcated:
            raise GCodeError("File ended with no percent sign")
        raise GCodeError("File ended with no percent sign or program end")

    def fail(self, line: int, message: str, finish: bool = False) -> None:
        """An error rs274 reports when it reaches ``line`` (``finish``: after
        the FINISH() of a closing ``%`` it met on the way)."""
        self.line = line
        if self.settings.ini.lines:
            frames = g_code_frames_of_stack()
            remap.refuse_in_line(
                self.settings, message, frames[-1].text if frames else ""
            )
        if finish:
            self.announce_block(None)
            self.canon.finish()
        raise GCodeError(message)

    def gcode(self, value: float) -> int:
        """A G code given by an expression, validated as rs274's reader does."""
        try:
            return g_code(value)
        except GCodeError as error:
            remap.refuse_unknown(self.settings, "g", value, error)
            raise

    @staticmethod
    def is_m98(value: float) -> bool:
        """Does a computed M value at the start of a line make it an M98
        call? rs274 reads the value as an integer, silently giving up."""
        try:
            return to_integer(value) == 98
        except GCodeError:
            return False

    def mcode(self, value: float) -> int:
        """An M code given by an expression, validated as rs274's reader does."""
        try:
            return m_code(value)
        except GCodeError as error:
            remap.refuse_unknown(self.settings, "m", value, error)
            raise

    # ------------------------------------------------------------------
    # Subroutines
    # ------------------------------------------------------------------
    def define(self, name: str, fn: Callable) -> None:
        """Record ``o<name> sub`` as rs274 does when it reads the sub line.

        rs274 refuses a definition of a name it already knows: one it read
        before ("redefining"), or one it found by reading ahead for an
        earlier call -- the very definition now reached in the normal flow
        ("illegal location"). Both messages name the sub line's file and line.
        """
        if fanuc_subs.in_fanuc_call(self):
            # run in an M98 call (or the frame an M98 .. L0 entered)
            raise GCodeError(fanuc_subs.O_SUB_NEEDS_CALL)
        here = g_code_frames_of_stack()[-1]
        known = self._subroutines.get(name)
        if known is not None:
            if known.file is None:
                raise GCodeError(
                    "File:%s line:%d sub: o|%s| found in illegal location"
                    % (here.file, here.line, name)
                )
            raise GCodeError(
                "File:%s line:%d redefining sub: o|%s| already defined in file:%s"
                % (here.file, here.line, name, known.file)
            )
        self._subroutines[name] = _Subroutine(fn, here.file)
        self.returned_to_main = False  # see runtime.olabels.top_level_return

    def call_named(self, name: str, *args: float):
        """Call a subroutine by name (for calls the compiler could not resolve)."""
        known = self._subroutines.get(name)
        if known is None:
            fanuc_subs.check_ocall(self, name)
            known = self._subroutines[name] = _Subroutine(self._read_ahead(name))
        return self.call(known.fn, *args)

    def definition_value(self, line: int, value: Optional[float] = None) -> None:
        """rs274 read the value of a ``return``/``endsub`` of the definition
        it is reading past (none: it clears ``#<_value>``)."""
        self.line = line
        if value is None:
            self.value = self.value_returned = 0.0
        else:
            self.value = value
            self.value_returned = 1.0

    def call_found(self, name: str, fn: Callable, file: str, *args: float):
        """Call ``name``: what is defined by now, else ``fn``, which is what
        rs274 finds seeking it (in ``<name>.ngc`` or further on in the
        subroutine file of the call; ``file`` is where), now defined."""
        known = self._subroutines.get(name)
        if known is None:
            known = self._subroutines[name] = _Subroutine(fn, file)
        return self.call(known.fn, *args)

    def seek_failed(self, line: int, file: str, name: str, start: int) -> None:
        """rs274 read to the end of ``file`` (its last line ``line``)
        seeking ``o<name> sub`` from line ``start``. It names a file found
        on the SUBROUTINE_PATH by the directory's real path."""
        import os

        self.line = line
        folder, base = os.path.split(file)
        if any(os.path.join(d, base) == file for d in self.settings.subroutine_path):
            file = os.path.join(os.path.realpath(folder), base)
        raise GCodeError(
            "EOF in file:%s seeking o-word: o<%s> from line: %d" % (file, name, start)
        )

    def _read_ahead(self, name: str) -> Callable:
        """rs274 reads ahead in the main file for a sub not defined yet.

        Reaching the closing ``%`` without finding it ends the program
        (FINISH) before the error.
        """
        if self.source is None:
            raise GCodeError(f"Failed to find sub 'O{name}' before EOF")
        fn = self.source.subs.get(name)
        if fn is not None and not self._after_the_call(fn):
            fn = None  # rs274 reads forward from the call: it never gets there
        self._skip_to(fn)
        if fn is None:
            remap.refuse_python_sub(self.settings, name)
            if self.source.end[1]:
                self.announce_block(None)
                self.canon.finish()
            raise self.source.missing_sub(name, self.line)
        return fn

    def _skip_to(self, fn: Optional[Callable]) -> None:
        """Reading ahead from the call (in the main file) to where ``fn`` is
        defined (None: to the end), rs274 fails at a line it cannot even
        skip (an unclosed comment, an O-word it cannot read)."""
        lines = self.source.unskippable
        if not lines:
            return
        calls = g_code_frames_of_stack(self.line)
        if not calls or calls[-1].file != self.source.files[0]:
            return
        start = calls[-1].line
        end = fanuc_subs.definition_line(fn) if fn is not None else None
        for line in sorted(lines):
            if line > start and (end is None or line <= end):
                text = self.source.text(0, line)
                raise GCodeError(
                    lines[line], Location(self.source.files[0], line, text)
                )

    def _after_the_call(self, fn: Callable) -> bool:
        """Is the definition of ``fn`` further on in the main file than the
        call being made (made from the main file)? A definition before it
        was passed unread (in an if not taken, a loop not entered)."""
        line = fanuc_subs.definition_line(fn)
        calls = g_code_frames_of_stack(self.line)
        if line is None or not calls or calls[-1].file != self.source.files[0]:
            return True
        return line > calls[-1].line

    def call(self, fn: Callable, *args: float) -> None:
        """An O-word call: fresh #1-#30 and locals, restored afterwards."""
        # A loop of calls spends its time here, so the usual case is written
        # out in one method: Params.save_locals/set_call_args/restore_locals,
        # step() and _run_sub's frame, inline.
        values = self.params.values
        saved = values[1:_CALL_ARGS_END]
        count = len(args)
        values[1:_CALL_ARGS_END] = (
            args + _NO_ARGS[count:] if count <= CALL_ARGS else args[:CALL_ARGS]
        )
        if self._plain_frames and self.call_level < MAX_CALL_LEVEL:
            caller_locals = self.locals
            try:
                self.step()
                self.locals = Locals()
                self.call_level += 1
                try:
                    result = fn(self)
                finally:
                    self.call_level -= 1
                    self.locals = caller_locals
                    if not self.call_level:
                        self.returned_to_main = True  # see olabels.top_level_return
            finally:
                values[1:_CALL_ARGS_END] = saved
            if self._saved_contexts:
                self._left_frame(self.call_level + 1)  # M73's restore
        else:
            self._arg_count = count
            try:
                result = self._run_sub(fn)
            finally:
                values[1:_CALL_ARGS_END] = saved
        # A call that returns nothing resets _value too.
        if result is None:
            self.value = self.value_returned = 0.0
        else:
            self.value = float(result)
            self.value_returned = 1.0

    def m98(
        self, line: int, fn: Optional[Callable], *codes: int, **words: float
    ) -> None:
        """``M98 P.. [L..]``: a Fanuc-style call of subroutine P, L times.

        rs274 reads and checks the line's words as a block (M98 uses P and
        L), then runs nothing of it but the calls. ``fn`` is the subroutine,
        or None to find it by P's value; ``codes`` are the line's G and M
        codes (checked, never executed). Unlike ``o.. call`` the calls leave
        #1-#30 alone and ``#<_value>`` 0, but do get fresh named locals.
        """
        self.line = line
        if self.settings.disable_fanuc_style_sub:
            raise GCodeError("DISABLE_FANUC_STYLE_SUB set in INI file, but found m98")
        block = blockcheck.read_block(codes, words)
        block.m98 = True
        blockcheck.enhance(block, self.plane, self.motion_mode)
        blockcheck.check(block, self.distance_incremental)
        times = words.get("l", 1)
        if times != 0:  # (with L0 rs274 looks for nothing)
            fn = fanuc_subs.m98_find(self, fn, to_integer(words["p"]), self._read_ahead)
        if times == 0:
            # rs274 enters the call but never runs or leaves it: the rest of
            # the program runs one call level down, in the new frame. The
            # caller's code keeps its locals store bound, so that very store
            # becomes the new frame's (emptied: the old locals are gone).
            caller_locals = self._enter_sub()
            kept = dict(caller_locals.__dict__)  # the caller's, after an M99
            caller_locals.__dict__.clear()
            self.locals = caller_locals
            # an M98 frame: a sub line run in it fails, as in an M98 call
            self.fanuc_levels.append(self.call_level)
            self._l0_frames.append((self.call_level, caller_locals, kept))
        for _ in range(times):
            fanuc_subs.run_fanuc(self, self._run_sub, fn)
        self.value = self.value_returned = 0.0

    def m99_back(self, line: int) -> bool:
        """An M99 runs after an ``M98 .. L0``: in the frame that M98 entered
        (and never called anything in), rs274 returns from it to where the
        M98 would have returned, the line after it, one call level up (with
        the caller's named locals). True when it did so; False: not in such
        a frame, the M99 does what it does there."""
        frames = self._l0_frames
        if not frames or frames[-1][0] != self.call_level:
            return False
        self.line = line
        level, caller_locals, kept = frames.pop()
        self.fanuc_levels.pop()
        self.call_level -= 1
        caller_locals.__dict__.clear()
        caller_locals.__dict__.update(kept)
        self.locals = caller_locals
        if not self.call_level:
            self.returned_to_main = True  # see olabels.top_level_return
        if self._saved_contexts:
            self._left_frame(level)  # M73's restore
        return True

    def m98_frame_end(self, line: int, sub: bool = False) -> None:
        """An o-sub's ``endsub`` or ``return`` runs (``sub``: a sub line run
        in a call): in the frame an ``M98 .. L0`` entered, rs274 wants the
        M99 of a Fanuc subroutine (an o-sub called with o.. call)."""
        if fanuc_subs.in_fanuc_call(self):
            message = fanuc_subs.O_SUB_NEEDS_CALL if sub else fanuc_subs.FANUC_END_M99
            self.fail(line, message)

    def frame_mark(self, key: str) -> None:
        """An if or loop around an ``M98 .. L0`` opens: note the call level
        (rs274 records its label under the frame's subroutine name)."""
        self._frame_marks[key] = self.call_level

    def left_frame(self, key: str) -> bool:
        """Whether an ``M98 .. L0`` inside the construct ``key`` has left
        the call level where the construct opened (see frame_mark)."""
        marks = self._frame_marks
        return bool(marks) and marks.get(key, self.call_level) != self.call_level

    def same_frame(self, key: str, line: int, text: str) -> None:
        """A closing line (else, endif, endwhile, endrepeat, break,
        continue) of the construct ``key`` runs: after an ``M98 .. L0``
        inside it, rs274 looks its label up under the new frame's name and
        does not find it."""
        if self.left_frame(key):
            self.fail(line, olabels.UNDEFINED_LABEL % (line, text))

    def _run_sub(self, fn: Callable) -> Optional[float]:
        """Run subroutine ``fn`` one call level down, with fresh named locals."""
        self.step()
        caller_locals = self._enter_sub()  # (`call` has the usual case inline)
        try:
            result = fn(self)
        finally:
            self.call_level -= 1
            self.locals = caller_locals
            if not self.call_level:
                self.returned_to_main = True  # see olabels.top_level_return
        if self._saved_contexts:
            self._left_frame(self.call_level + 1)  # M73's restore
        return result

    def _enter_sub(self) -> Locals:
        """Go one call level down, with fresh named locals; returns the caller's."""
        if self.call_level >= MAX_CALL_LEVEL:
            raise GCodeError("Too many subroutine levels")
        caller_locals = self.locals
        if self.settings.oword_nargs:  # M98 calls count no arguments
            self.locals = ArgCountLocals(self._arg_count)
            self._arg_count = 0
        else:
            self.locals = Locals()
        self.call_level += 1
        self._new_frame(self.call_level)
        # (#<_value_returned> is kept: rs274 clears it only for Python
        # subs, and an endsub or return sets it, with a value or not)
        return caller_locals

    def top_level_return(
        self, line: int, keyword: str, text: str, value: Optional[float] = None
    ) -> None:
        """``return``/``endsub`` outside a subroutine (see runtime.olabels)."""
        olabels.top_level_return(self, line, keyword, text, value)

    def flow(self, lines: dict, at: int, sub: Optional[str] = None) -> oflow.Flow:
        """A frame running a file line by line from line ``at`` (in a call
        of ``sub``), its O-words followed as rs274 follows them
        (runtime.oflow: for programs whose O-words do not nest)."""
        return oflow.Flow(self, lines, at, sub)

    def check_label(self, key: str, kind: str, line: int, text: str) -> None:
        """A reused O-word label (see runtime.olabels)."""
        olabels.check_label(self, key, kind, line, text)

    def repeat_kept(self, key: str, n: float, again: bool = True) -> Iterator[int]:
        """``repeat`` that may be left early (see runtime.loopflags);
        ``again=False``: never runs its count again (a stale continue)."""
        return loopflags.repeat_keeping_count(self, key, round_to_int(n), again)

    def repeat_again(self, n: float) -> Iterator[int]:
        """``repeat`` where a do-loop's continue may have left rs274's
        ``doing_continue`` set (see runtime.loopflags)."""
        return loopflags.repeat_with_stale_continue(self, round_to_int(n))

    # ------------------------------------------------------------------
    # Blocks
    # ------------------------------------------------------------------
    def block(
        self,
        line: int,
        *codes: int,
        n: Optional[str] = None,
        comment=None,
        **words: float,
    ) -> None:
        """Check and execute one line's codes and words (see module docstring).

        ``n`` is what rs274's trace shows after ``N``: the N word's digits as
        written, or None for ``N.....``."""
        self.line = line
        self.announce_block(n)
        # The fast path shares its end point with the canon model and the
        # position parameters (runtime.fast.moves): change a copy from here.
        self.current = list(self.current)
        if self.lathe_diameter and "x" in words:
            words["x"] /= 2  # rs274 halves X as it reads it in G7
        block = blockcheck.read_block(codes, words)
        blockcheck.enhance(block, self.plane, self.motion_mode)
        blockcheck.check(block, self.distance_incremental)
        self._execute(block, comment)
        self._publish_position()
        if self.probe_flag:
            self._after_probe()  # as for a tool change, below
        if self.toolchange_flag:
            # rs274 does this as it reads the next line, before evaluating any
            # of its expressions; nothing can happen in between, so do it now.
            self._after_tool_change()
        self.refresh_plain()

    def _publish_position(self) -> None:
        """#5420-#5428: the current point, as rs274 keeps them after each block."""
        self.params.position = tuple(self.current)

    def _execute(self, block: Block, comment) -> None:
        """rs274's execute_block order."""
        g, words = block.g, block.words
        if comment is not None:
            execute_comment(self, comment)
        if SPINDLE_MODE in g:
            self._choose_spindle(words, "mode")
            self._spindle_mode(g[SPINDLE_MODE], words)
        if FEED_MODE in g:
            self._choose_spindle(words, "feed")
            self._feed_mode(g[FEED_MODE])
        if "f" in words and self.feed_mode != INVERSE_TIME:
            self._set_feed_rate(words["f"])
        if "s" in words and not self._spindle_speed(words):
            if not self._stepped_before_speed(block, comment):
                # rs274's step status is still its initial "exit": the
                # program ends there, without M2's calls
                raise ProgramEnd()
        if "t" in words:
            self._select_tool(int(words["t"]))
        if block.m and self._execute_m(block):
            return  # M72 replaced the rest of the line (runtime.modal_save)
        self._execute_g(block)
        if M_STOP in block.m:
            self._stop(block.m[M_STOP])

    def _set_feed_rate(self, rate: float) -> None:
        self.feed_rate = rate
        self.canon.set_feed_rate(rate)
        self.world.feed_rate = rate

    # ------------------------------------------------------------------
    # G codes
    # ------------------------------------------------------------------
    def _execute_g(self, block: Block) -> None:
        """rs274's convert_g order."""
        g, words = block.g, block.words
        if g.get(NON_MODAL) == G4:
            self.canon.dwell(words["p"])
        if PLANE in g:
            self._set_plane(_PLANES[g[PLANE]])
        if UNITS in g:
            self._set_units(g[UNITS] == G20)
        if LATHE_MODE in g:
            self._lathe_mode(g[LATHE_MODE], words)
        if CUTTER_COMP in g:
            self._cutter_comp(g[CUTTER_COMP], words)
        if TOOL_OFFSET in g:
            self._tool_length_offset(g[TOOL_OFFSET], words)
        if COORD_SYSTEM_GROUP in g:
            self._select_system(_SYSTEMS[g[COORD_SYSTEM_GROUP]])
        if PATH_CONTROL in g:
            self._control_mode(g[PATH_CONTROL], words)
        if DISTANCE in g:
            self._distance_mode(g[DISTANCE] == G91)
        if ARC_DISTANCE in g:
            self._ijk_mode(g[ARC_DISTANCE] == G90_1)
        if RETRACT in g:
            self._retract_mode(g[RETRACT] == G98)
        if NON_MODAL in g:
            self._modal_0(g[NON_MODAL], block)
        if G92_RESET in g:
            self._g92_family(g[G92_RESET])
        if block.motion is not None:
            self._motion(block.motion, block)

    def _set_plane(self, plane: str) -> None:
        if self.cutter_comp and plane != self.plane:
            raise GCodeError("Cannot change planes with cutter radius compensation on")
        self.canon.select_plane(_CANON_PLANE[plane])
        self.plane = plane

    def _lathe_mode(self, code: int, words) -> None:
        """G7/G8: X words are diameters in G7; this line's X was read before."""
        diameter = code == G7
        if diameter == self.lathe_diameter:
            return
        self.lathe_diameter = diameter
        if "x" in words:
            words["x"] = words["x"] / 2 if diameter else words["x"] * 2
        kind = "diameter" if diameter else "radius"
        # rs274 never queues this comment behind a compensated move.
        self.unqueued_canon().comment(
            f"interpreter: Lathe diameter mode changed to {kind}"
        )

    def _control_mode(self, code: int, words) -> None:
        if self.cutter_comp:
            raise GCodeError(
                "Cannot change control mode with cutter radius compensation on"
            )
        if code == G61:
            self._canon_control_mode("EXACT_PATH", 0.0)
        elif code == G61_1:
            self._canon_control_mode("EXACT_STOP", 0.0)
        else:
            tolerance = words.get("p", -1.0)
            naive = words.get("q", -1.0)
            # A negative (or absent) P or Q means "none": 0, and Q defaults to P.
            tolerance = max(tolerance, 0.0)
            naive = naive if naive >= 0 else tolerance
            self._canon_control_mode("CONTINUOUS", tolerance)
            self._canon_naivecam(naive)
            self.path_tolerance, self.naivecam_tolerance = tolerance, naive
        self.control_mode = code

    def _canon_control_mode(self, mode: str, tolerance: float) -> None:
        """SET_MOTION_CONTROL_MODE, remembered as the canon remembers it
        (canned cycles read it back)."""
        self.canon.set_motion_control_mode(mode, tolerance)
        self.world.set_control_mode(mode, tolerance)

    def _canon_naivecam(self, tolerance: float) -> None:
        self.canon.set_naivecam_tolerance(tolerance)
        self.world.naivecam_tolerance = tolerance

    def _distance_mode(self, incremental: bool) -> None:
        if incremental != self.distance_incremental:
            kind = "incremental" if incremental else "absolute"
            self.canon.comment(f"interpreter: distance mode changed to {kind}")
            self.distance_incremental = incremental

    def _ijk_mode(self, absolute: bool) -> None:
        if absolute != self.ijk_absolute:
            kind = "absolute" if absolute else "incremental"
            self.canon.comment(f"interpreter: IJK distance mode changed to {kind}")
            self.ijk_absolute = absolute

    def _retract_mode(self, old_z: bool) -> None:
        if self.cutter_comp:
            raise GCodeError(
                "Cannot change retract mode with cutter radius compensation on"
            )
        self.canon.comment(
            "interpreter: retract mode set to " + ("old_z" if old_z else "r_plane")
        )
        self.retract_r_plane = not old_z

    def _choose_spindle(self, words, step: str) -> None:
        """G93-G97 make their line's $ (spindle 0 without one) the spindle
        feed per revolution, threading and the cycles use from then on."""
        self.active_spindle = 0
        check_dollar(words, step, self.num_spindles)
        if "dollar" in words:
            self.active_spindle = dollar(words)

    def _spindle_mode(self, code: int, words) -> None:
        """G96/G97 for the active spindle, if the machine has it."""
        spindle = self.active_spindle
        if not 0 <= spindle < self.num_spindles:
            return
        if code == G97:
            self.spindles.set_mode(spindle, CONSTANT_RPM)
            self.canon.set_spindle_mode(spindle, 0.0)
        else:
            self.spindles.set_mode(spindle, CONSTANT_SURFACE)
            rate = abs(words["d"]) if "d" in words else 1e30
            self.canon.set_spindle_mode(spindle, rate)

    def _spindle_speed(self, words) -> bool:
        """S for spindle 0, the line's $, or every spindle ($-1); a spindle
        the machine does not have takes none. False when rs274 went through
        no spindle at all ($-1 on a machine of none)."""
        check_dollar(words, "speed", self.num_spindles)
        rpm = words["s"]
        spindles = chosen(words, self.num_spindles)
        for spindle in spindles:
            if 0 <= spindle < self.num_spindles:
                self.canon.set_spindle_speed(spindle, rpm)
                self.spindles.set_speed(spindle, rpm)
        return len(spindles) > 0

    def _stepped_before_speed(self, block: Block, comment) -> bool:
        """Did one of the steps rs274 takes before S run on this line (a
        comment, G93-G97, F)?"""
        return (
            comment is not None
            or SPINDLE_MODE in block.g
            or FEED_MODE in block.g
            or ("f" in block.words and self.feed_mode != INVERSE_TIME)
        )

    def _feed_mode(self, code: int) -> None:
        mode = _FEED_MODES[code]
        self.canon.comment(_FEED_MODE_COMMENTS[mode])
        self.feed_mode = mode
        if mode == UNITS_PER_REVOLUTION:
            self.canon.set_feed_mode(self.active_spindle, 1)
        else:
            self.canon.set_feed_mode(0, 0)
        if mode != INVERSE_TIME:
            self._set_feed_rate(0.0)

    def _modal_0(self, code: int, block: Block) -> None:
        words = block.words
        if code == G10:
            if int(words["l"]) in (2, 20):
                self._set_system(words)
            elif int(words["l"]) == 0:
                # rs274 reads its own spindle slot's tool number, which an M6
                # changes on the next line (and M61 Q0 does not clear)
                spindle = self._spindle_before_change or self._entry(0)
                loaded = spindle.tool
                if loaded > 0:
                    raise GCodeError(
                        "G10 L0 not allowed with loaded tool <%d>\n" % loaded
                    )
                self.canon.reload_tooldata()  # the stand-alone canon only prints it
            else:
                self._set_tool_entry(words)
        elif code in (G28, G30):
            self._home(code, block)
        elif code in (G28_1, G30_1):
            self._save_home(code)
        elif code == G92:
            self._g92(words)
        elif code == G52:
            self._g52(words)
        elif code == G5_3:
            self._nurbs_end()
        # G4 and G53 are handled elsewhere (dwell first, G53 with the motion).

    def _g92_family(self, code: int) -> None:
        if self.cutter_comp:
            # rs274 (interp_convert.cc, convert_g) never checks what
            # convert_g92_is_applied returns: under compensation the refusal
            # is dropped, and G92.1/G92.2/G92.3 silently do nothing.
            return
        if code == G92_3:
            self._g92_restore()
        else:
            self._g92_cancel(keep_parameters=code == G92_2)

    def _motion(self, motion: int, block: Block) -> None:
        """rs274's convert_motion."""
        if self._rotary_rules:
            indexer = self._indexer_axis(motion, block.words)
            if indexer is not None:
                self._end_cycle_series()
                self._straight_indexer(indexer, block)
                return
        if motion in DRILL_CYCLES:
            self._cycle(motion, block)
            return
        self._end_cycle_series()
        if motion in (G0, G1):
            self._straight(motion, block)
        elif motion in (G2, G3):
            self._arc(motion, block)
        elif motion in (G33, G33_1, G76):
            self._spindle_synchronized(motion, block)
        elif motion in (G38_2, G38_3, G38_4, G38_5):
            self._probe(motion, block)
        elif motion == G80:
            self.canon.comment("interpreter: motion mode set to none")
            self.motion_mode = G80
        elif motion in LATHE_CYCLES:
            self._lathe_cycle(motion, block)
        elif motion in (G5, G5_1):
            self._spline(motion, block)
        elif motion == G5_2:
            self._nurbs(block)
        else:  # every motion code of rs274 2.9 is handled above
            raise not_supported(f"motion {g_name(motion)}")

    # ------------------------------------------------------------------
    # Predefined named parameters
    # ------------------------------------------------------------------
    def spiral_tolerance(self) -> float:
        """The centre-format arc radius tolerance for the active units (INI or default)."""
        settings = self.settings
        if self.inches:
            return settings.center_arc_radius_tolerance_inch
        return settings.center_arc_radius_tolerance_mm

    def current_line(self) -> int:
        """``#<_line>``: the number of the line being read.

        Lines of only parameter settings or O-words make no ``block`` call,
        and a block's word values are computed before it, so the line comes
        from the generated code's frames on the stack.
        """
        frames = g_code_frames_of_stack()
        return frames[-1].line if frames else self.line

    def ini_parameter(self, name: str) -> Optional[float]:
        """``#<_ini[SECTION]KEY>`` from the -i file, or None."""
        return self.settings.ini_parameter(name)

    def predefined(self, name: str) -> Optional[float]:
        """The value of predefined parameter ``name`` (None if it is not one)."""
        if name not in self.PREDEFINED:
            return None
        axis = name[1:]
        if len(axis) == 1 and axis in AXES:
            return self.current[AXES.index(axis)]
        if axis.startswith("abs_"):
            # rs274 2.9 knows _abs_x.._abs_c only (no _abs_u/v/w).
            return self.machine_position()[AXES.index(axis[4:])]
        return float(_PREDEFINED_VALUES[name](self))


_PREDEFINED_VALUES: Dict[str, Callable[[Machine], float]] = {
    "_vmajor": lambda m: 2.9,
    "_vminor": lambda m: 0.0,
    "_line": lambda m: m.current_line(),
    "_motion_mode": lambda m: m.motion_mode,
    "_plane": lambda m: _PLANE_CODES[m.plane],
    "_ccomp": lambda m: {LEFT: G41, RIGHT: G42}.get(m._cc.side, G40),
    "_metric": lambda m: not m.inches,
    "_imperial": lambda m: m.inches,
    "_absolute": lambda m: not m.distance_incremental,
    "_incremental": lambda m: m.distance_incremental,
    "_inverse_time": lambda m: m.feed_mode == INVERSE_TIME,
    "_units_per_minute": lambda m: m.feed_mode == UNITS_PER_MINUTE,
    "_units_per_rev": lambda m: m.feed_mode == UNITS_PER_REVOLUTION,
    "_coord_system": lambda m: _SYSTEM_CODES[m.origin_index - 1],
    # Any non-zero offset, not the G43/G49 mode: "G43 H0" reads 0.
    "_tool_offset": lambda m: any(m.tool_offset),
    "_retract_r_plane": lambda m: m.retract_r_plane,
    "_retract_old_z": lambda m: not m.retract_r_plane,
    # spindle 0's, whatever the number of spindles
    "_spindle_rpm_mode": lambda m: m.spindles.mode(0) == CONSTANT_RPM,
    "_spindle_css_mode": lambda m: m.spindles.mode(0) == CONSTANT_SURFACE,
    "_ijk_absolute_mode": lambda m: m.ijk_absolute,
    "_lathe_diameter_mode": lambda m: m.lathe_diameter,
    "_lathe_radius_mode": lambda m: not m.lathe_diameter,
    "_spindle_on": lambda m: m.spindles.turning(0) != STOPPED,
    "_spindle_cw": lambda m: m.spindles.turning(0) == CLOCKWISE,
    "_mist": lambda m: m.mist,
    "_flood": lambda m: m.flood,
    "_speed_override": lambda m: m.spindles.override(0),
    "_feed_override": lambda m: m.feed_override,
    "_adaptive_feed": lambda m: m.adaptive_feed,
    "_feed_hold": lambda m: m.feed_hold,
    "_feed": lambda m: m.feed_rate,
    "_rpm": lambda m: abs(m.spindles.speed(0)),
    "_current_tool": lambda m: m.params[5400],
    "_current_pocket": lambda m: m.current_pocket_number(),
    "_selected_tool": lambda m: m.selected_tool,
    "_selected_pocket": lambda m: m.selected_pocket_number(),
    "_value": lambda m: m.value,
    "_value_returned": lambda m: m.value_returned,
    "_task": lambda m: 0,
    "_call_level": lambda m: m.call_level,
    "_remap_level": lambda m: 0,
    # rs274 asks the INI file before it knows the file's name: always -1.
    "_metric_machine": lambda m: -1,
}

# ``g._value`` after every call: a plain attribute read where it can be one.
Globals.install_predefined(
    Machine.PREDEFINED, {"_value": "value", "_value_returned": "value_returned"}
)
