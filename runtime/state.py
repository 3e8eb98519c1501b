"""The interpreter's state, every field declared in one place.

LinuxCNC's interpreter keeps all of its state in one ``setup`` struct. Here
it is the fields of :class:`MachineState`, which :class:`runtime.machine.Machine`
inherits: each is declared below with a line saying what it is, and given
its first value by ``_start_state`` (or, for what the constructor is told,
by ``Machine.__init__``). The mixins Machine is made of (motion, cycles,
probing, splines, tools, cutter compensation, modal save, ...) read and
change these fields and create none (tests/test_state.py runs programs and
checks that a machine holds nothing undeclared).

``_plain``, the flag every fast path tests, is not a mode of its own: it is
derived from the modes by ``refresh_plain`` (runtime.fast.moves).
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Callable, Dict, List, Optional, Set, TextIO, Tuple

    from runtime.canon import Canon
    from runtime.cutter_comp import CompState
    from runtime.inifile import IniSettings
    from runtime.params import Globals, Locals, Params
    from runtime.tools import ToolTable
    from runtime.world import World

from runtime.arcs import UNITS_PER_MINUTE
from runtime.codes import G64, G80
from runtime.spindle_select import Spindles


class MachineState:
    """Every field of the interpreter's state (see the module docstring)."""

    # --- the session: what the machine was started with -------------------
    canon: Canon  # where the canonical calls go (default: the rs274 trace)
    world: World  # the canon's side of the modes (what it was last told)
    block_delete: bool  # rs274's -b: generated code skips "/" lines
    source: object  # the program's SourceMap (file names, line map, text)
    settings: IniSettings  # the INI file's [RS274NGC] settings
    num_spindles: int  # [TRAJ]SPINDLES, as rs274 keeps it (any int)
    var_file: Optional[str]  # the parameter file (-v), rewritten at the end
    messages: TextIO  # rs274's complaints while running (parameter file)
    params: Params  # numbered parameters (#1-#5xxx), bound to p in code
    globals: Globals  # named globals (#<_name>), bound to g
    locals: Locals  # the running call's named locals (#<name>), bound to v
    ini_globals: Set[str]  # #<_ini[...]> names read from the INI (read-only)
    tools: ToolTable  # the tool table, by pocket
    tool_table_report: str  # what rs274 prints while loading the table
    user_units_per_mm: float  # rs274's machine units per mm (its canon: inch)
    _closing_resets: int  # ON_RESET calls at the end: 1 with an INI read, else 2
    max_steps: int  # the step budget: loop iterations and calls (0: none)
    step: Callable[[], None]  # takes one step (StopIteration: budget spent)
    # RETAIN_G43 only: every block runs the M code step (runtime.tools)
    _execute: Callable
    _rotary_rules: bool  # the INI has wrapped rotary axes or indexers

    # --- where the program is ----------------------------------------------
    line: int  # the G-code line executing (errors and tracebacks name it)
    call_level: int  # O-word call depth (0: the main program)
    _subroutines: Dict[str, object]  # defined subroutines by name
    _arg_count: int  # the arguments of the call being made (#<n_args>)
    value: float  # #<_value>: the last endsub/return value
    value_returned: float  # #<_value_returned>: 1.0 after a value came back
    _plain_frames: bool  # calls need only fresh locals (no n_args, no M70/M73)
    _saved_contexts: Dict[int, object]  # M70/M73 modal states by call level
    returned_to_main: bool  # a return at the top level ended a call early
    doing_break: bool  # a break is leaving its loop (rs274's flag)
    doing_continue: bool  # a continue is going round again (rs274's flag)
    executed_if: bool  # an arm of an if has run (rs274's flag)
    _olabels: Dict[str, object]  # O-word labels seen executing (reuse checks)
    _oflow_labels: Dict[str, list]  # rs274's label table, line-by-line files
    _repeat_counts: Dict[str, int]  # counts left of repeat loops left early
    fanuc_levels: List[int]  # call levels of running M98 calls (and M98 L0 frames)
    _fanuc_found: Dict[str, object]  # Fanuc subroutines an M98 search found, by number
    _l0_frames: List[tuple]  # frames M98 .. L0 entered: (level, caller's locals, their values)
    _frame_marks: Dict[str, int]  # call level where each if/loop around M98 L0 opened
    python_namespace: Dict[str, object]  # (py, ...) comments' variables

    # --- modes (rs274's Interp::init values: _reset_modes) ------------------
    motion_mode: Optional[int]  # G0-G3, G33.x, G38.x, G5.x, G7x, G8x or None
    plane: str  # "XY", "YZ", "XZ", "UV", "VW" or "UW" (G17-G19.1)
    inches: bool  # G20 (True) or G21
    distance_incremental: bool  # G91 (True) or G90
    ijk_absolute: bool  # G90.1 (True) or G91.1
    feed_mode: int  # G93, G94 or G95
    feed_rate: float  # F, in program units (per minute or per rev)
    active_spindle: int  # the spindle G95, G33, G76 and the cycles use ($)
    spindles: Spindles  # each spindle's S, G96/G97, M48-M51 and M3-M5
    mist: bool  # M7
    flood: bool  # M8
    feed_override: bool  # M50 (M48/M49 set both overrides)
    adaptive_feed: bool  # M52
    feed_hold: bool  # M53
    control_mode: int  # G61, G61.1 or G64
    path_tolerance: float  # G64 P
    naivecam_tolerance: float  # G64 Q
    retract_r_plane: bool  # G99 (True) or G98
    lathe_diameter: bool  # G7 (True) or G8
    _cc: CompState  # cutter radius compensation (G40-G42.1) and its queue
    reading_profile: bool  # a G7x profile's lines are being read

    # --- tools ----------------------------------------------------------------
    selected_pocket: int  # the pocket T selected (#<_selected_pocket>)
    selected_tool: int  # the tool T selected
    current_pocket: int  # the pocket in the spindle
    toolchange_flag: bool  # M6 done: the next line reads the new tool first
    # the spindle entry's pocket in the canon's own table (set from the tool
    # table; only CHANGE_TOOL changes it, a G10 edit does not)
    _canon_spindle_pocket: int
    _spindle_before_change: Optional[object]  # the spindle's state before M6

    # --- position and offsets (program units) -------------------------------
    origin_index: int  # the coordinate system: 1 (G54) .. 9 (G59.3)
    origin: List[float]  # its offset, nine axes
    g92: List[float]  # the G92 offset
    rotation: float  # the coordinate system's XY rotation (G10 L2 R)
    tool_offset: List[float]  # the tool length offset (G43, G43.1, G43.2)
    current: List[float]  # where the tool is, nine axes

    # --- canned cycles (rs274's cycle memory) --------------------------------
    cycle_initial_level: Optional[float]  # hole axis before this series, or None
    cycle_depth: float  # the last hole-axis word (rs274's cycle_cc)
    cycle_r: float  # R
    cycle_p: float  # P (dwell)
    cycle_q: float  # Q (peck)
    cycle_i: float  # I (G87 offsets)
    cycle_j: float  # J
    cycle_k: float  # K

    # --- probing and splines -------------------------------------------------
    probe_flag: bool  # a probe move was made: the next line reads its result
    _probe_point: List[float]  # where the probe tripped (#5061-#5069)
    _nurbs_points: List[object]  # G5.2 control points collected so far
    _nurbs_order: int  # G5.2 L
    _spline_ij: Tuple[float, float]  # G5's remembered I and J

    # --- fast paths (runtime.fast.moves, runtime.fast.rows) ------------------------
    _plain: bool  # the modes let plain moves skip the general path
    _batchable: bool  # a BatchesOnly machine's plain flag, set aside
    _block_n: Optional[str]  # the N column last announced to the canon
    _hole_capture: Optional[object]  # a cycle line's hole being told (hole_rows)
    rows_run: Optional[object]  # the run_rows call running (a token), or None

    def _start_state(self) -> None:
        """Every field the constructor is not told, as a new interpreter has it."""
        self.line = 0
        self.call_level = 0
        self._subroutines = {}
        self._arg_count = 0
        self.value = 0.0
        self.value_returned = 0.0
        self._saved_contexts = {}
        self.returned_to_main = False
        self.doing_break = False
        self.doing_continue = False
        self.executed_if = False
        self._olabels = {}
        self._oflow_labels = {}
        self._repeat_counts = {}
        self.fanuc_levels = []
        self._fanuc_found = {}
        self._l0_frames = []
        self._frame_marks = {}
        self.python_namespace = {}
        self._spindle_before_change = None
        self.cycle_initial_level = None
        self.cycle_depth = 0.0
        self.cycle_r = 0.0
        self.cycle_p = 0.0
        self.cycle_q = 0.0
        self.cycle_i = 0.0
        self.cycle_j = 0.0
        self.cycle_k = 0.0
        self.probe_flag = False
        self._probe_point = [0.0] * 9
        self._nurbs_points = []
        self._nurbs_order = 3
        self._spline_ij = (0.0, 0.0)
        self._plain = False
        self._batchable = False
        self._block_n = None
        self._hole_capture = None
        self.rows_run = None
        self._reset_modes()

    def _reset_modes(self) -> None:
        """The modes at start-up (rs274's Interp::init)."""
        from runtime.cutter_comp import CompState

        self.motion_mode = G80
        self.plane = "XY"
        self.inches = False
        self.distance_incremental = False
        self.ijk_absolute = False
        self.feed_mode = UNITS_PER_MINUTE
        self.feed_rate = 0.0
        self.active_spindle = 0
        self.spindles = Spindles()
        self.mist = False
        self.flood = False
        self.feed_override = True
        self.adaptive_feed = False
        self.feed_hold = True
        # The stand-alone canon starts in G64 without tolerances.
        self.control_mode = G64
        self.path_tolerance = 0.0
        self.naivecam_tolerance = 0.0
        self.retract_r_plane = True
        self.lathe_diameter = False
        self.cutter_comp = False
        self._cc = CompState()
        # Before any T word M6 changes to index 0 (#<_selected_pocket> reads
        # the spindle entry's pocket); the canon reports slot 1 as loaded.
        self.selected_pocket = 0
        self.selected_tool = 0
        self.current_pocket = 1
        self.toolchange_flag = False
        self.reading_profile = False
        self.origin_index = 1
        self.origin = [0.0] * 9
        self.g92 = [0.0] * 9
        self.rotation = 0.0
        self.tool_offset = [0.0] * 9
        self.current = [0.0] * 9


#: The names of every field (what tests/test_state.py holds machines to).
FIELDS = frozenset(MachineState.__annotations__)

__all__ = ["FIELDS", "MachineState"]
