"""Arcs in the machine's plain state: the geometry inlined, the checks made
once per shape, the state kept in local variables for a run of rows.

An arc block in the plain state (see :mod:`runtime.fast.moves`) needs, from
rs274's pipeline, only:

* the checks that depend on which words the block has (R or I J K, the
  centre letters of the plane, an end point for R): the same for every row
  of a shape, so :func:`arc_recipe` makes them once per shape and plane;
* a feed rate that is not zero (feed per minute is part of "plain");
* the centre, by exactly the floating-point operations of rs274's
  ``arc_data_ijk`` / ``arc_data_r`` in the same order (runtime/arcs.py is
  the reference; the helpers here must give the same doubles);
* the radius checks of the centre format. Their radii are not printed, so
  they are taken with ``math.hypot``, which may differ from the C library's
  ``hypot`` in the last bit: an arc is accepted here only when the checks
  pass with a margin far beyond that bit, and anything closer goes to the
  general path, which decides with the C library's rounding.

Anything else -- an error, a spiral near its tolerance, a modal motion that
is not an arc, a plane of U V W -- makes these functions step aside, having
done nothing, so ``Machine.block`` runs the line and raises rs274's errors
in rs274's order.
"""

from __future__ import annotations

from itertools import repeat, takewhile
from math import hypot
from operator import add, sub

from runtime import arcs
from runtime.canon import Canon, TraceCanon, ignores_numbers, own_method, trace_rows
from runtime.codes import G0, G1, G2, G3
from runtime.errors import GCodeError


def python_column_floats(texts: List[str]) -> List[float]:
    """The floats of a column of table cells."""
    return list(map(float, texts))


def python_radius_bounds(c1, c2, s1, s2, e1, e2) -> Optional[Tuple[float, ...]]:
    """The smallest and largest radius of arcs of centres (c1, c2) from
    (s1, s2) to (e1, e2), and the largest difference between an arc's start
    and end radius."""
    r1 = list(map(hypot, map(sub, c1, s1), map(sub, c2, s2)))
    r2 = list(map(hypot, map(sub, c1, e1), map(sub, c2, e2)))
    return (
        min(min(r1), min(r2)),
        max(max(r1), max(r2)),
        max(map(abs, map(sub, r1, r2))),
    )


def table_lines(cells: List[str], at: int, stop: int, stride: int) -> List[int]:
    """The G-code lines of the table rows from ``cells[at]`` to before
    ``cells[stop]``. A table's rows are lines of one region, in order: when
    the last is as many lines after the first as there are rows in between,
    the rows are every line from first to last, and no cell is parsed."""
    first, last = int(cells[at]), int(cells[stop - stride])
    if last - first == (stop - at) // stride - 1:
        return list(range(first, last + 1))
    return list(map(int, cells[at:stop:stride]))


try:  # the same in C, without a map per step (None: a value not finite)
    from runtime._libm_trig import floats as column_floats
    from runtime._libm_trig import radius_bounds
except ImportError:  # not built
    column_floats, radius_bounds = python_column_floats, python_radius_bounds


TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional, Tuple

    Recipe = Tuple[Tuple[Tuple[int, int], ...], int, int, int]

#: plane -> indexes, in the 9-axis point, of its first and second axis and
#: of the third (the helix axis).
PLANE_AXES = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}

_AXES = "xyzabc"

#: Relative slack of the radius checks: math.hypot and the C library's hypot
#: differ by a few units in the last place at most (1e-16 relative).
_MARGIN = 1e-14
_BELOW = 1 - _MARGIN

#: Rows of arcs in a row, at least, for the batch form; at most per batch.
_BATCH = 8
_MOST = 4096

#: The trace's rotation column for G2 and G3 (one turn: no P word here).
_ROTATION = {G2: "-1", G3: "1"}


def arc_recipe(letters, plane: str, absolute: bool) -> Optional[Recipe]:
    """What an arc with the words ``letters`` (lower case, no N) needs in
    ``plane`` with G90.1 (``absolute``) or G91.1: ``(slots, r_at, first_at,
    second_at)``, the (value index, axis index) pairs of its axis words and
    the value indexes of R and of the two centre words (-1: absent). None
    when the words alone make the block an error (the general path says
    which)."""
    if plane not in PLANE_AXES:
        return None
    present = dict.fromkeys(letters, 0.0)
    try:
        arcs.check_arc_format(plane, present)
        arcs.arc_center_words(plane, present, absolute)
    except GCodeError:
        return None
    letters = list(letters)
    slots = tuple((i, _AXES.index(x)) for i, x in enumerate(letters) if x in _AXES)

    def where(letter: str) -> int:
        return letters.index(letter) if letter in present else -1

    if "r" in present:
        return slots, where("r"), -1, -1
    first, second = arcs._CENTER_LETTERS[plane]
    return slots, -1, where(first), where(second)


def centre_checks_pass(s1, s2, e1, e2, c1, c2, zero: float, spiral: float) -> bool:
    """True when rs274's radius checks of a centre-format arc surely pass
    (see the module docstring); False: let the general path decide."""
    r1 = hypot(c1 - s1, c2 - s2)
    r2 = hypot(c1 - e1, c2 - e2)
    if r1 < r2:
        small, big = r1, r2
    else:
        small, big = r2, r1
    return small * _BELOW >= zero and (big - small) + big * _MARGIN <= spiral


def radius_centre(clockwise: bool, s1, s2, e1, e2, radius: float, zero: float):
    """:func:`runtime.arcs.radius_centre` for an arc the fast path may take;
    None (step aside) also where rs274 fails on the arc (its end point is
    its start point) or divides by zero (R 0)."""
    if radius == 0.0 or (e1 == s1 and e2 == s2):
        return None
    return arcs.radius_centre(clockwise, s1, s2, e1, e2, radius, zero)


def quick_radius_centre(clockwise: bool, s1, s2, e1, e2, radius: float, zero: float):
    """:func:`radius_centre`, in C where it is built (the rows' own,
    runtime/fast/_arc_row.c): for Machine.plain_arc's R arcs, one line at
    a time."""
    if radius == 0.0 or (e1 == s1 and e2 == s2):
        return None
    return _radius_centre(clockwise, s1, s2, e1, e2, radius, zero)


def _row_number(cells: List[str], at: int, has_n: bool):
    """The N of the row at ``at`` (None without one), and where its other
    words begin."""
    if has_n:
        return cells[at + 2], at + 3
    return None, at + 2


def python_arc_row(cells, at, recipe, motion_mode, cur, feed_rate, geometry):
    """The arc of the row at ``at``: (motion, N, F or None, end point,
    centre's two coordinates), or None where the general path must decide (no
    feed, a radius not surely within the tolerances, an R arc it
    rejects). The same checks and floating-point steps as
    Machine.plain_arc."""
    motion, has_n, f_at, _, slots, r_at, i1, i2 = recipe
    if motion is None:  # modal: an arc only in G2 or G3
        motion = motion_mode
        if motion != G2 and motion != G3:
            return None
    p1, p2, _, absolute, zero, spiral = geometry
    n, start = _row_number(cells, at, has_n)
    if f_at >= 0:
        f = float(cells[start + f_at])
        if f <= 0.0:  # negative, or an arc without feed: errors
            return None
    else:
        f = None
        if feed_rate == 0.0:
            return None
    point = cur[:]
    for i, axis in slots:
        point[axis] = float(cells[start + i])
    s1, s2, e1, e2 = cur[p1], cur[p2], point[p1], point[p2]
    if r_at < 0:
        v1 = float(cells[start + i1]) if i1 >= 0 else 0.0
        v2 = float(cells[start + i2]) if i2 >= 0 else 0.0
        if absolute:
            c1, c2 = v1, v2
        else:
            c1, c2 = s1 + v1, s2 + v2
        # centre_checks_pass, inlined
        r1 = hypot(c1 - s1, c2 - s2)
        r2 = hypot(c1 - e1, c2 - e2)
        if r1 < r2:
            r1, r2 = r2, r1
        if not (r2 * _BELOW >= zero and (r1 - r2) + r1 * _MARGIN <= spiral):
            return None
        return motion, n, f, point, c1, c2
    centre = radius_centre(
        motion == G2, s1, s2, e1, e2, float(cells[start + r_at]), zero
    )
    if centre is None:
        return None
    return (motion, n, f, point) + centre


try:  # the same in C, ten times quicker (runtime/fast/_arc_row.c)
    from runtime.fast._arc_row import arc_row
    from runtime.fast._arc_row import rows as rows_in_c
    from runtime.fast._arc_row import radius_centre as _radius_centre
except ImportError:  # not built: the loop's Python alone
    arc_row, rows_in_c = python_arc_row, None
    _radius_centre = arcs.radius_centre


def _publish(machine, line: int, cur, motion_mode, block_n) -> None:
    """What a run of rows leaves: the line and N of its last row and, if it
    moved, the end point and the motion."""
    machine.line = line
    machine._block_n = block_n
    if cur is not machine.current:
        machine.current = machine.world.position = cur
        machine.params.position = cur
        machine.motion_mode = motion_mode


class _Pending:
    """Arc rows held for one ``arc_moves`` call (a canon that defines it):
    ``columns``, the G-code lines then arc_feed's arguments, as the call
    takes them, of arcs from ``start``. For a canon that takes contours
    (``Canon.contour_moves``; ``contours`` true), the C loop holds the plain
    straight feeds between the arcs too, as rows of rotation 0. For a canon
    that takes N numbers with its batches (``numbered``), each row's N is
    held too (a fourteenth column), and no N hands the held rows over. For
    a canon that takes restated planes with its batches (``takes_planes``),
    ``planes`` lists the held rows that restate G17 (its SELECT_PLANE is
    the canon's to make, after the row's line begins): such a row hands
    nothing over; else ``planes`` is None."""

    __slots__ = (
        "machine",
        "arc_moves",
        "columns",
        "start",
        "contours",
        "numbered",
        "planes",
    )

    #: the line, then arc_feed's twelve arguments
    WIDTH = 13

    @classmethod
    def for_canon(cls, machine) -> "Optional[_Pending]":
        canon = machine.canon
        kind = type(canon)
        contours = kind.contour_moves is not Canon.contour_moves
        if kind is TraceCanon:
            return None
        if kind.arc_moves is Canon.arc_moves and not contours:
            # the protocol's default contours (one arc_feed or straight_feed
            # a row, made in C) serve any other canon (a user's, NullCanon);
            # one that looks at the machine's line as its calls are made
            # gets each row alone, and so does one keeping N numbers (its
            # own set_block_number, not takes_numbers): each N would cut its
            # batches, a batch a numbered row
            if canon.reads_lines or not (ignores_numbers(canon) or canon.takes_numbers):
                return None
            contours = True
        pending = cls()
        pending.machine, pending.arc_moves = machine, canon.arc_moves
        # (a canon reading lines has each held row's in the batch's lines)
        pending.contours = contours
        if pending.contours:
            pending.arc_moves = canon.contour_moves
        pending.numbered = bool(canon.takes_numbers)
        pending.planes = [] if canon.takes_planes else None
        pending.columns = pending._empty()
        pending.start = machine.current
        return pending

    def _empty(self) -> list:
        return [[] for _ in range(self.WIDTH + self.numbered)]

    def __bool__(self) -> bool:
        """Whether any arc is held."""
        return bool(self.columns[0])

    def hold(self, line: int, point, c1: float, c2: float, rotation: int, axes, cur, n):
        """One more arc: to ``point`` about (c1, c2), from ``cur``, its
        row's N ``n``."""
        if not self.columns[0]:
            self.start = cur
        p1, p2, p3 = axes
        row = (line, point[p1], point[p2], c1, c2, rotation, point[p3], *point[3:], n)
        for column, value in zip(self.columns, row):
            column.append(value)

    def flush(self) -> None:
        """The held rows to the canon, the machine at their start (the row
        loop keeps its point in a local variable)."""
        machine = self.machine
        machine.current = machine.world.position = self.start
        machine.params.position = self.start
        # new lists: the canon may keep the ones it is given
        columns, self.columns = self.columns, self._empty()
        numbers = columns.pop() if self.numbered else None
        if self.contours:
            columns.insert(0, PLANE_AXES[machine.plane])
        told = {}
        if numbers is not None:
            told["numbers"] = numbers
        if self.planes:
            told["planes"], self.planes = self.planes, []
        self.arc_moves(*columns, **told)


class _Derived:
    """What ArcRows works out from a table's plans alone, kept for every
    table of the module's SHAPES: a program that comments, calls or
    conditions cut into many tables (a shop's) would work it out again for
    each of them."""

    __slots__ = ("plans", "groups", "straight", "plane_arcs", "known")

    def __init__(self, plans) -> None:
        self.plans = plans
        #: shape cell text -> the shape cells of the same words with G2 or
        #: G3 (their rows can share a batch)
        by_words: dict = {}
        for index, plan in enumerate(plans):
            if plan.arc and plan.motion is not None:
                # The same words and N or none: the same width.
                words = (plan.letters, plan.has_n)
                by_words.setdefault(words, set()).add(str(index))
        self.groups = {
            shape: frozenset(shapes) for shapes in by_words.values() for shape in shapes
        }
        #: shape cell text -> (motion, has_n, f_at, width, slots) of the
        #: plain straight moves (runtime.fast.rows._Plan.slots).
        self.straight = {
            str(index): (plan.motion, plan.has_n, plan.f_at, plan.width, plan.slots)
            for index, plan in enumerate(plans)
            if plan.slots is not None
        }
        #: shape cells of arcs that restate G17 (``G17 G2 X Y R``, as some
        #: posts write every arc): in the XY plane, a SELECT_PLANE before
        #: the motion, as Machine.plain_arc makes it
        self.plane_arcs = frozenset(
            str(index) for index, plan in enumerate(plans) if plan.plane_arc
        )
        #: (plane, absolute IJK) -> {shape cell text: row recipe or None}
        self.known: dict = {}


#: id of a module's plans -> their _Derived (kept with them, so that their
#: id is not another's); at most _MOST_DERIVED (one program has one)
_DERIVED: dict = {}
_MOST_DERIVED = 64


def _derived(plans) -> _Derived:
    kept = _DERIVED.get(id(plans))
    if kept is None or kept.plans is not plans:
        if len(_DERIVED) >= _MOST_DERIVED:
            _DERIVED.clear()
        kept = _DERIVED[id(plans)] = _Derived(plans)
    return kept


class ArcRows:
    """The loop over a run of arc rows of one table (runtime.fast.rows): made
    once per ``run_rows`` call, it keeps each shape's recipe per plane and
    IJK mode."""

    __slots__ = (
        "machine",
        "plans",
        "recipes",
        "printed",
        "groups",
        "straight",
        "pending",
        "plane_arcs",
        "known",
    )

    def __init__(self, machine, plans, printed: bool = False) -> None:
        self.machine = machine
        self.plans = plans
        #: (plane, absolute IJK, inches) -> ({shape cell text: row recipe
        #: or None}, geometry: first and second axis, absolute IJK, radius
        #: tolerance, spiral tolerance); the recipes are the plans' own
        #: (_Derived), the geometry the machine's
        self.recipes: dict = {}
        #: The table's values are written as the trace prints them
        #: (runtime.fast.printed_rows): the batch form copies their text.
        self.printed = printed
        derived = _derived(plans)
        self.groups = derived.groups
        self.straight = derived.straight
        self.plane_arcs = derived.plane_arcs
        self.known = derived.known
        #: The arcs held for the canon's arc_moves (_Pending), None for a
        #: canon without it, False until the first run asks.
        self.pending = False

    def _row_recipe(self, key: str, plane: str, absolute: bool):
        plan = self.plans[int(key)]
        if plan.plane_arc and plane == "XY":  # (G17 restated: its G2 or G3)
            motion = plan.restating[0]
        elif plan.arc:
            motion = plan.motion
        else:
            return None
        recipe = arc_recipe(plan.letters, plane, absolute)
        if recipe is None:
            return None
        letters = plan.letters
        f_at = letters.index("f") if "f" in letters else -1
        return (motion, plan.has_n, f_at, plan.width) + recipe

    def _context(self, cells: List[str], at: int):
        """What a run of rows from ``cells[at]`` needs that is fixed while it
        runs: (recipes by shape, geometry, whether only arcs are taken), or
        None when the row at ``at`` is not an arc this loop takes."""
        machine = self.machine
        plane = machine.plane
        if plane not in PLANE_AXES:
            return None
        # A BatchesOnly machine (runtime.fast.rows) takes only runs of arc rows
        # without N or F here, as one arc_moves batch each (the canon sees
        # each of their lines begin); any other row goes back to run_rows.
        arcs_only = not machine._plain
        if arcs_only and not (
            machine._batchable
            and (
                machine._block_n is None
                or ignores_numbers(machine.canon)
                or machine.canon.takes_numbers
            )
            and type(machine.canon).arc_moves is not Canon.arc_moves
        ):
            return None
        absolute = machine.ijk_absolute
        # per plane, IJK mode and units: the recipes and the geometry (a
        # run of arcs between straight rows starts here again and again)
        modes = (plane, absolute, machine.inches)
        context = self.recipes.get(modes)
        if context is None:
            zero = arcs.radius_tolerance(machine.inches)
            geometry = PLANE_AXES[plane] + (absolute, zero)
            geometry += (machine.spiral_tolerance(),)
            known = self.known.setdefault((plane, absolute), {})
            context = self.recipes[modes] = (known, geometry)
        known = context[0]
        key = cells[at + 1]
        if key not in known:
            known[key] = self._row_recipe(key, plane, absolute)
        if known[key] is None:
            return None
        return context + (arcs_only,)

    def run(self, cells: List[str], at: int, end: int) -> int:
        """Run the rows from ``cells[at]``, an arc, while they are plain arcs
        or plain straight moves between them, with the machine's state in
        local variables (the calls of Machine.plain_arc and plain_rows row by
        row); returns where it stopped (a row for the general path or for
        runtime.fast.printed_rows, or ``end``)."""
        plan = self.plans[int(cells[at + 1])]
        if not (plan.arc or plan.plane_arc):
            return at  # (what _context finds out, at once: rows between arcs)
        machine = self.machine
        if plan.plane_arc and not (machine._plain or machine.canon.takes_planes):
            # (what both loops find out at this row: taking arcs only, they
            # leave an arc restating G17 to its line, whose canon sees the
            # line begin, unless the canon takes planes with its batches; the
            # set-up and the hand-over would cost as much as the line)
            return at
        context = self._context(cells, at)
        if context is None:
            return at
        # A canon's own arc_moves takes every arc between its other calls.
        if self.pending is False:
            self.pending = _Pending.for_canon(machine)
        # what the loop leaves, exception or not: point, motion, the row it
        # reached, N, feed rate, whether an F set it, and where _loop may
        # look for a batch again
        state = [
            machine.current,
            machine.motion_mode,
            at,
            machine._block_n,
            machine.feed_rate,
            False,
            at,
        ]
        # A contour's rows in C (runtime/fast/_arc_row.c): the trace's calls,
        # or the arcs a batch canon's arc_moves takes (held).
        canon, pending = machine.canon, self.pending
        in_c = rows_in_c
        if pending is not None:  # arcs only: none in the modal motion
            extra = (pending, context[2], machine if canon.reads_lines else None)
            # a batches-only machine's canon takes a row between arcs as a
            # batch of one (runtime.fast.rows.BatchesOnly.plain_rows)
            takes_rows = type(canon).straight_moves is not Canon.straight_moves
            extra += (canon.straight_moves if context[2] and takes_rows else None,)
            extra += (pending.contours,)
        elif not context[2] and (type(canon) is TraceCanon or not canon.reads_lines):
            # each move a call made in C: the trace's, and a canon that keeps
            # N numbers (its own set_block_number: every N would cut a batch)
            # and does not read the machine's line as its calls are made
            extra = ()
        else:
            in_c = None
        if in_c is not None:
            fixed = context[0], self.straight, context[1], state
            calls = (canon.arc_feed, canon.straight_feed, canon.straight_traverse)
            # (None: a canon that ignores N, which an N then does not cut;
            # one that takes them with its arcs gets them held, the C loop
            # told by the pending's columns)
            announce = own_method(canon, "set_block_number")
            # (None: no SELECT_PLANE for an arc restating G17, no batch cut)
            calls += (announce, canon.set_feed_rate, own_method(canon, "select_plane"))
            calls += (self.plane_arcs,) + extra
        try:
            while at < end:
                if in_c is not None:
                    stop = in_c(cells, at, end, *fixed, *calls)
                    if stop != at:
                        at = stop
                        continue
                stop = self._loop(cells, at, end, context, state, in_c is not None)
                if stop == at:
                    break
                at = stop
        finally:
            pending = self.pending
            if pending:
                # (a canon reading lines finds the last row's, as row by row)
                machine.line = int(cells[state[2]])
                pending.flush()
            cur, motion_mode, row, block_n, feed_rate, feed_given = state[:6]
            _publish(machine, int(cells[row]), cur, motion_mode, block_n)
            if feed_given:
                machine.feed_rate = machine.world.feed_rate = feed_rate
        return at

    def _loop(self, cells: List[str], at: int, end: int, context, state, once) -> int:
        """run's loop in Python, from the state it is given to the one it
        leaves; ``once``: back to run after one row when the C loop may take
        the next."""
        known, geometry, arcs_only = context
        p1, p2, p3, absolute = geometry[:4]
        axes = geometry[:3]
        machine = self.machine
        plane = machine.plane
        canon = machine.canon
        arc_feed, set_feed_rate = canon.arc_feed, canon.set_feed_rate
        straight_feed, straight_traverse = canon.straight_feed, canon.straight_traverse
        cur, motion_mode, row, block_n, feed_rate, feed_given, batch_from = state
        # Runs of one shape: written at once (_batch) from batch_from on.
        first = at
        groups = self.groups
        row_lines = canon.reads_lines  # (ngc2py.moves reads machine.line)
        pending = self.pending
        holding = pending is not None
        ignores_n = ignores_numbers(canon)
        plane_arcs = self.plane_arcs
        select_plane = own_method(canon, "select_plane")
        # arcs held with their N (pending.numbered): no N hands them over
        numbered = holding and pending.numbered
        try:
            while at < end:
                if once and at != first:
                    break  # the C loop may take this row
                row = at
                if row_lines:
                    machine.line = int(cells[at])
                key = cells[at + 1]
                recipe = known.get(key, False)
                if recipe is False:
                    recipe = known[key] = self._row_recipe(key, plane, absolute)
                if recipe is None:
                    if arcs_only:
                        break
                    move = self._straight_row(
                        cells, at, end, key, motion_mode, feed_rate, cur
                    )
                    if move is None:
                        break
                    stride, motion, n, f, point = move
                    arc = None
                    selects = told_plane = False
                else:
                    motion, has_n, f_at, width, slots, r_at, i1, i2 = recipe
                    # (G17 restated: SELECT_PLANE before the motion)
                    selects = key in plane_arcs
                    # (held with the restated plane, for a canon taking
                    # planes: it makes the SELECT_PLANE after the line begins)
                    told_plane = selects and holding and pending.planes is not None
                    if arcs_only and (
                        (has_n and not (ignores_n or numbered))
                        or f_at >= 0
                        or motion is None
                        or (selects and not told_plane)
                    ):
                        break
                    selects = selects and select_plane is not None and not told_plane
                    if (
                        at >= batch_from
                        and (block_n is None or type(canon) is TraceCanon or ignores_n)
                        # the quick test: the eighth row from here is an arc
                        # of these words too (_batch checks all of them)
                        and end - at >= (2 + width) * _BATCH
                        and cells[at + 1 + (2 + width) * (_BATCH - 1)]
                        in groups.get(key, ())
                    ):
                        done = self._batch(
                            cells, at, end, recipe, cur, feed_rate, geometry, pending
                        )
                        if type(done) is int:
                            batch_from = done
                        else:
                            at, cur, rate, motion_mode, block_n = done
                            row = at - 2 - width
                            if rate is not None:
                                feed_rate, feed_given = rate, True
                            continue
                    arc = arc_row(
                        cells, at, recipe, motion_mode, cur, feed_rate, geometry
                    )
                    if arc is None:
                        break
                    motion, n, f, point, c1, c2 = arc
                    rotation = -1 if motion == G2 else 1
                    stride = 2 + width
                # held arcs go to the canon before any other call (an N
                # held with its arc is not one, unless an F follows it)
                told = ignores_n or (numbered and arc is not None and f is None)
                if (
                    holding
                    and pending
                    and (
                        arc is None
                        or (n != block_n and not told)
                        or f is not None
                        or selects
                    )
                ):
                    pending.flush()
                if n != block_n:
                    if not told:
                        canon.set_block_number(n)
                    block_n = n
                if f is not None:
                    feed_rate = f
                    feed_given = True
                    set_feed_rate(f)
                if selects:
                    select_plane("XY")
                if arc is None:
                    if motion == G1:
                        straight_feed(*point)
                    else:
                        straight_traverse(*point)
                elif holding:
                    if told_plane:
                        pending.planes.append(len(pending.columns[0]))
                    pending.hold(int(cells[at]), point, c1, c2, rotation, axes, cur, n)
                else:
                    arc_feed(
                        point[p1], point[p2], c1, c2, rotation, point[p3], *point[3:]
                    )
                cur = point
                motion_mode = motion
                at += stride
        finally:
            state[:] = cur, motion_mode, row, block_n, feed_rate, feed_given, batch_from
        return at

    def _straight_row(self, cells, at, end, key, motion_mode, feed_rate, cur):
        """The straight move of the row at ``at`` (of shape ``key``): (stride,
        motion, N, F or None, end point), or None where the row loop must
        stop (not a plain straight move, a stretch printed_rows writes at
        once, a feed of no rate). Between arcs, the lines of a contour are
        taken here as Machine.plain_rows takes them, rather than leaving the
        loop for one row."""
        line = self.straight.get(key)
        if line is None:
            return None
        motion, has_n, f_at, width, slots = line
        stride = 2 + width
        if end - at >= stride * _BATCH and (
            cells[at + 1 + stride * (_BATCH - 1)] == key
        ):
            return None  # a stretch runtime.fast.printed_rows writes at once
        if motion is None:
            motion = motion_mode
        n, start = _row_number(cells, at, has_n)
        f = None if f_at < 0 else float(cells[start + f_at])
        if motion == G1:
            if (feed_rate if f is None else f) <= 0.0:
                return None
        elif motion != G0 or (f is not None and f < 0.0):
            return None
        point = cur[:]
        for i, axis in slots:
            point[axis] = float(cells[start + i])
        return stride, motion, n, f, point

    def _batch(self, cells, at, end, recipe, cur, feed_rate, geometry, pending):
        """The run of rows of the shape at ``at`` in one go (_columns), the
        arcs held before it handed over first: (where it ended, end point,
        last F or None, last motion, last N). Having done nothing, where the
        row loop may look for a run again: past this stretch, so that its
        rows are not scanned again and again."""
        if pending:
            pending.flush()
        done = self._columns(cells, at, end, recipe, cur, feed_rate, geometry)
        stride = recipe[3] + 2
        if type(done) is int:
            return at + stride * max(done, _BATCH)
        rows, cur, rate, motion, n = done
        return at + rows * stride, cur, rate, motion, n

    def _columns(self, cells, at, end, recipe, cur, feed_rate, geometry):
        """The trace of the run of arc rows of the shape of the
        row at ``at`` (or the same words with the other of G2/G3), made in
        one go and written: ``(rows, end point, last F or None, last motion,
        last N)``. Having done nothing, the number of rows of the stretch
        (< _BATCH: too few) where any row is one the row loop would not take (a zero or
        negative F, radii not surely within the tolerances, an R arc
        the general path must decide).

        Rows of one width sit ``width + 2`` cells apart, so each word is
        one slice of ``cells``; each start point is the previous row's
        end point. Every step is a ``map`` over whole columns, with the
        same floating-point operations as the row loop."""
        _, has_n, f_at, width, slots, r_at, i1, i2 = recipe
        group = self.groups.get(cells[at + 1])
        if group is None:
            return 0
        stride = width + 2
        shapes = cells[at + 1 : min(end, at + 1 + stride * _MOST) : stride]
        rows = len(list(takewhile(group.__contains__, shapes)))
        if rows < _BATCH:
            return rows
        del shapes[rows:]
        stop = at + rows * stride
        values = at + 2 + has_n
        texts = [cells[values + i : stop : stride] for i in range(width - has_n)]
        named = {axis: i for i, axis in slots}
        p1, p2, p3, absolute, zero, spiral = geometry

        def floats(axis: int) -> List[float]:
            i = named.get(axis)
            return [cur[axis]] * rows if i is None else column_floats(texts[i])

        e1, e2 = floats(p1), floats(p2)
        s1, s2 = [cur[p1]] + e1[:-1], [cur[p2]] + e2[:-1]
        if r_at >= 0:
            clockwise = {k: self.plans[int(k)].motion == G2 for k in group}
            centres = list(
                map(
                    radius_centre,
                    map(clockwise.__getitem__, shapes),
                    s1,
                    s2,
                    e1,
                    e2,
                    map(float, texts[r_at]),
                    repeat(zero, rows),
                )
            )
            if None in centres:
                return rows
            c1, c2 = map(list, zip(*centres))
        else:
            v1 = [0.0] * rows if i1 < 0 else column_floats(texts[i1])
            v2 = [0.0] * rows if i2 < 0 else column_floats(texts[i2])
            if absolute:
                c1, c2 = v1, v2
            else:
                c1, c2 = list(map(add, s1, v1)), list(map(add, s2, v2))
            bounds = radius_bounds(c1, c2, s1, s2, e1, e2)
            if bounds is None:
                return rows
            small, big, difference = bounds
            if not (small * _BELOW >= zero and difference + big * _MARGIN <= spiral):
                return rows
        canon = self.machine.canon
        if type(canon) is not TraceCanon:
            if has_n or f_at >= 0 or feed_rate == 0.0:  # row by row
                return rows
            return self._arc_moves(
                canon,
                cells,
                at,
                stop,
                stride,
                shapes,
                texts,
                named,
                cur,
                e1,
                e2,
                c1,
                c2,
            )
        return self._trace_text(
            canon,
            cells,
            at,
            stop,
            recipe,
            shapes,
            texts,
            named,
            cur,
            feed_rate,
            (e1, e2, c1, c2),
        )

    def _trace_text(
        self, canon, cells, at, stop, recipe, shapes, texts, named, cur, feed_rate, ends
    ):
        """_columns' answer for the trace: the rows' lines made from one
        pattern (the words each row gives as columns, the rest constant)
        and written at once."""
        _, has_n, f_at, width, slots, _, _, _ = recipe
        rows, stride = len(shapes), width + 2
        e1, e2, c1, c2 = ends
        group = self.groups[cells[at + 1]]
        p1, p2, p3 = PLANE_AXES[self.machine.plane]
        rate = None
        if f_at >= 0:
            rates = list(map(float, texts[f_at]))
            if min(rates) <= 0.0:
                return rows
            rate = rates[-1]
        elif feed_rate == 0.0:
            return rows
        # The line pattern: each end coordinate a column (its text when the
        # table is written as printed) or, when no row names it, constant.
        parts, columns = [], []
        for axis, known in (
            (p1, e1),
            (p2, e2),
            (-1, c1),
            (-2, c2),
            (-3, None),
            (p3, None),
            (3, None),
            (4, None),
            (5, None),
        ):
            if axis == -3:
                parts.append("%s")
                rotation = {k: _ROTATION[self.plans[int(k)].motion] for k in group}
                columns.append(list(map(rotation.__getitem__, shapes)))
            elif axis < 0:
                parts.append("%.4f")
                columns.append(known)
            elif axis not in named:
                parts.append("%.4f" % cur[axis])
            elif self.printed:
                parts.append("%s")
                columns.append(texts[named[axis]])
            else:
                parts.append("%.4f")
                columns.append(
                    known if known is not None else column_floats(texts[named[axis]])
                )
        count = canon._count
        if has_n:
            column = "N%-6s"
            numbers = cells[at + 2 : stop : stride]
        else:
            column = "N..... "
        move = "%%5d %sARC_FEED(%s)\n" % (column, ", ".join(parts))
        if f_at >= 0:
            fmt = (
                "%%5d %sSET_FEED_RATE(%s)\n"
                % (column, "%s" if self.printed else "%.4f")
                + move
            )
            parts = [range(count + 1, count + 2 * rows, 2)]
            parts += [numbers] if has_n else []
            parts.append(texts[f_at] if self.printed else rates)
            parts.append(range(count + 2, count + 2 * rows + 1, 2))
            count += 2 * rows
        else:
            fmt = move
            parts = [range(count + 1, count + rows + 1)]
            count += rows
        parts += [numbers] if has_n else []
        canon._write_batch(trace_rows(fmt, [*parts, *columns]))
        canon._count = count
        if count >= canon._drain_at:  # TraceCanon's own batching
            canon._drain()
        n = numbers[-1] if has_n else None
        canon._column = "N..... " if n is None else "N%-6s" % n
        point = cur[:]
        for i, axis in slots:
            point[axis] = float(texts[i][-1])
        return rows, point, rate, self.plans[int(shapes[-1])].motion, n

    def _arc_moves(
        self, canon, cells, at, stop, stride, shapes, texts, named, cur, e1, e2, c1, c2
    ):
        """The batch as one ``arc_moves`` call of columns (the canon's own,
        or the protocol's one ``arc_feed`` a row): ``_columns``' answer."""
        rows = len(shapes)
        p1, p2, p3 = PLANE_AXES[self.machine.plane]
        motion = {k: self.plans[int(k)].motion for k in set(shapes)}
        rotation = [-1 if motion[k] == G2 else 1 for k in shapes]
        columns = []
        for axis in (p3, 3, 4, 5, 6, 7, 8):
            i = named.get(axis)
            columns.append([cur[axis]] * rows if i is None else column_floats(texts[i]))
        lines = table_lines(cells, at, stop, stride)
        # the machine at the batch's start (held arcs flushed before it
        # left it at theirs)
        machine = self.machine
        machine.current = machine.world.position = machine.params.position = cur
        canon.arc_moves(lines, e1, e2, c1, c2, rotation, *columns)
        point = cur[:]
        point[p1], point[p2] = e1[-1], e2[-1]
        for axis, column in zip((p3, 3, 4, 5, 6, 7, 8), columns):
            point[axis] = column[-1]
        return rows, point, None, motion[shapes[-1]], None
