"""Cutter radius compensation (G40, G41, G42, G41.1, G42.1) as rs274 does it.

rs274 compensates in the interpreter, in the selected plane (XY, or XZ for
lathes), and needs to see the next move before it knows where the current
one ends: an inside corner trims the previous move back, an outside corner
gets an arc around the programmed corner point. So while compensation is on
every move is *queued* (rs274's ``qc`` queue) and only handed to the canon
when the next move, G40 or a program stop settles its end point. Canon calls
that rs274 queues behind a pending move (comments, feed rate, spindle,
coolant, dwell, feed mode) wait with it; every other call goes out at once.
The trace shows each call with the N number of the line being executed when
it is printed, so flushed moves carry the *next* line's N.

Everything is computed in plane coordinates (first, second, axis) as
:mod:`runtime.arcs` defines them, with rs274's formulas, including its mix of
double and long double arithmetic (:func:`runtime.ops.long_double_sum`).

A mixin of :class:`runtime.machine.Machine`: :mod:`runtime.motion` hands
moves here from its single exits while compensation is engaged; the machine
calls :meth:`CutterCompMixin._comp_flush_for_stop` for M0/M1/M2/M30/M60.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional

from runtime import arcs
from runtime.arcs import from_plane, to_plane
from runtime.codes import G2, G3, G40, G41, G41_1, G42_1, G53
from runtime.errors import GCodeError
from runtime import ops
from runtime.ops import c_hypot, long_double_sum

LEFT, RIGHT = 1, 2

#: A canon without a ``motion_line`` attribute (see _emit_queued).
_NO_LINE = object()

#: rs274's TOLERANCE_CONCAVE_CORNER (radians) and TOLERANCE_EQUAL.
_SMALL = 0.05
_TOLERANCE_EQUAL = 0.0001

_TOOL_RADIUS_TOO_BIG = "Tool radius not less than arc radius with comp"
_ARC_CONCAVE = (
    "Arc move in concave corner cannot be reached by the tool without gouging"
)

#: The canon calls rs274 queues behind a pending compensated move.
QUEUED_CALLS = frozenset(
    """comment set_feed_rate dwell set_feed_mode mist_on mist_off flood_on
    flood_off start_spindle_clockwise start_spindle_counterclockwise
    stop_spindle_turning orient_spindle wait_spindle_orient_complete
    set_spindle_mode set_spindle_speed""".split()
)


class _Move:
    """A queued move in plane coordinates: x, y the plane point, z the axis.

    ``dx, dy`` is the programmed direction of a straight move (to detect a
    trim that reverses it); ``sweep`` the angle an arc turned when queued.
    """

    __slots__ = ("kind", "x", "y", "z", "rest", "dx", "dy", "c1", "c2", "turn", "sweep", "line")

    def __init__(
        self, kind, x, y, z, rest, dx=0.0, dy=0.0, c1=0.0, c2=0.0, turn=0, sweep=0.0
    ):
        self.kind = kind  # "traverse", "feed" or "arc"
        self.x, self.y, self.z = x, y, z
        self.rest = list(rest)  # A B C U V W
        self.dx, self.dy = dx, dy
        self.c1, self.c2, self.turn, self.sweep = c1, c2, turn, sweep
        self.line = 0  # the line that queued it (rs274's block->line_number)


class CompState:
    """rs274's compensation settings and its queue."""

    def __init__(self) -> None:
        self.side = 0  # 0 (off), LEFT or RIGHT
        #: Moves are compensated: a side is set and the radius is not 0.
        self.engaged = False
        self.radius = 0.0
        self.orientation = 0
        self.firstmove = True
        #: The programmed (uncompensated) X, Y, Z of the last compensated move.
        self.program = [0.0, 0.0, 0.0]
        self.arc_not_allowed = False
        self.queue: list = []
        self.endpoint = [0.0, 0.0]
        self.endpoint_valid = False
        #: What rs274's ``qc().front()`` reads once the queue is empty again:
        #: the stale first element (a cleared std::vector keeps its memory).
        self.stale_front: Optional[_Move] = None


class QueueingCanon:
    """Stands in for the machine's canon while compensation is on: the calls
    rs274 queues wait behind a pending move, all others pass straight on."""

    def __init__(self, inner, queue: list) -> None:
        self.inner = inner
        self.queue = queue

    def __getattr__(self, name):
        attr = getattr(self.inner, name)
        if name not in QUEUED_CALLS:
            return attr
        queue = self.queue

        def call(*args):
            if queue:
                queue.append((attr, args))
            else:
                attr(*args)

        return call


def _tool_inside_arc(side: int, turn: int) -> bool:
    return (side == LEFT and turn > 0) or (side == RIGHT and turn < 0)


def _find_turn(x1, y1, cx, cy, turn, x2, y2) -> float:
    """rs274's find_turn: the signed angle an arc sweeps (long double sums)."""
    if turn == 0:
        return 0.0
    alpha = math.atan2(y1 - cy, x1 - cx)
    beta = math.atan2(y2 - cy, x2 - cx)
    if turn > 0:
        if beta <= alpha:
            beta = long_double_sum(beta, 2 * ops.PI_L)
        return long_double_sum(beta - alpha, (turn - 1) * 2 * ops.PI_L)
    if alpha <= beta:
        alpha = long_double_sum(alpha, 2 * ops.PI_L)
    return long_double_sum(beta - alpha, (turn + 1) * 2 * ops.PI_L)


class CutterCompMixin:
    """G40/G41/G42 and the compensated moves (part of Machine)."""

    # ------------------------------------------------------------------
    # Modes
    # ------------------------------------------------------------------
    def unqueued_canon(self):
        """The canon itself, for the few calls rs274 makes unqueued even
        while a compensated move is pending."""
        canon = self.canon
        return canon.inner if isinstance(canon, QueueingCanon) else canon

    def _cutter_comp(self, code: int, words) -> None:
        if code == G40:
            self._comp_off()
        else:
            self._comp_on(code, words)

    def _comp_on(self, code: int, words) -> None:
        """rs274's convert_cutter_compensation_on."""
        plane = self.plane
        if plane not in ("XY", "XZ"):
            raise GCodeError("Cutter radius compensation allowed only in XY, XZ planes")
        if self.cutter_comp:
            raise GCodeError("Cannot turn cutter radius comp on when on")
        base = "G41" if code in (G41, G41_1) else "G42"
        side = LEFT if code in (G41, G41_1) else RIGHT
        if code in (G41_1, G42_1):
            if "d" not in words:
                raise GCodeError(f"{base}.1 with no D word")
            radius = words["d"] / 2
            orientation = 0
            if "l" in words:
                if plane != "XZ":
                    raise GCodeError(f"{base}.1 with L word, but plane is not G18")
                orientation = int(words["l"])
        else:
            index = 0
            if "d" in words:
                d = words["d"]
                tool = int(d + 0.5)  # C's (int) truncates towards zero
                if abs(tool - d) >= 0.0001:
                    raise GCodeError(f"{base} requires D word to be a whole number")
                if tool < 0:
                    raise GCodeError("Negative d word tool radius index used")
                index = self._pocket_of(tool)
            entry = self._entry(index)
            if index == 0 and self._spindle_before_change:
                entry = self._spindle_before_change
            units = 25.4 if self.inches else 1.0
            radius = entry.diameter / self.user_units_per_mm / units / 2.0
            orientation = entry.orientation
            if plane != "XZ" and orientation not in (0, 9):
                raise GCodeError(f"{base} with lathe tool, but plane is not G18")
        if radius < 0.0:  # a negative diameter cuts on the other side
            radius = -radius
            side = LEFT if side == RIGHT else RIGHT
        self.canon.comment(
            "interpreter: cutter radius compensation on "
            + ("right" if side == RIGHT else "left")
        )
        st = self._cc
        st.radius = radius
        st.orientation = orientation
        st.side = side
        st.engaged = radius > 0.0
        self.cutter_comp = True
        if not isinstance(self.canon, QueueingCanon):
            self.canon = QueueingCanon(self.canon, st.queue)

    def _comp_off(self) -> None:
        """rs274's convert_cutter_compensation_off: settle the last move."""
        st = self._cc
        self.canon.comment("interpreter: cutter radius compensation off")
        if st.side and st.radius > 0.0 and not st.firstmove:
            cx, cy, _ = to_plane(self.plane, *self.current[:3])
            self._move_endpoint_and_flush(cx, cy)
            self._dequeue()
            self.current[:3] = st.program
            st.arc_not_allowed = True
        self._comp_stop()

    def _comp_stop(self) -> None:
        """Compensation off (G40, program end); the queue is empty by now."""
        st = self._cc
        st.side = 0
        st.engaged = False
        st.firstmove = True
        self.cutter_comp = False
        if isinstance(self.canon, QueueingCanon):
            self.canon = self.canon.inner

    def _comp_flush_for_stop(self) -> None:
        """M0, M1, M2, M30, M60 (rs274's convert_stop) first flush the queue."""
        if self._cc.queue:
            cx, cy, _ = to_plane(self.plane, *self.current[:3])
            self._move_endpoint_and_flush(cx, cy)
        self._dequeue()

    def _comp_forget_queue(self) -> None:
        """After an error rs274 clears its queue (qc_reset in unwind_call):
        the pending move and the calls behind it are never made, while
        compensation itself stays on. Matters under ``-n 0``."""
        self._cc.queue.clear()
        self._cc.endpoint_valid = False

    def _comp_check_arc_allowed(self) -> None:
        if self._cc.arc_not_allowed:
            raise GCodeError(
                "The move just after exiting cutter compensation mode must be straight, not an arc"
            )

    def _comp_base(self) -> List[float]:
        """The point that a block's missing axis words (and G91) start from.

        After the first compensated move rs274 uses the programmed point for
        the plane's axes, not the compensated position."""
        cur = self.current
        st = self._cc
        if not self.cutter_comp or st.firstmove:
            return cur
        base = list(cur)
        base[0] = st.program[0]
        if self.plane == "XY":
            base[1] = st.program[1]
        else:
            base[2] = st.program[2]
        return base

    def _comp_feed_start(self) -> List[float]:
        """Where an inverse-time straight move's length is measured from."""
        if self._cc.engaged and not self._cc.firstmove:
            return list(self._cc.program) + self.current[3:]
        return self.current

    def _comp_scale(self, factor: float) -> None:
        """G20/G21 with compensation on (rs274's unit change and qc_scale)."""
        st = self._cc
        st.program = [v * factor for v in st.program]
        for item in st.queue:
            # rs274 rescales its saved end point once per queued item.
            st.endpoint = [v * factor for v in st.endpoint]
            if isinstance(item, _Move):
                item.x *= factor
                item.y *= factor
                item.z *= factor
                for i in (3, 4, 5):
                    item.rest[i] *= factor
                if item.kind == "arc":
                    item.c1 *= factor
                    item.c2 *= factor
        st.radius *= factor

    # ------------------------------------------------------------------
    # The queue
    # ------------------------------------------------------------------
    def _enqueue(self, move: _Move) -> None:
        if move.kind is None:
            # G33/G33.1 take the compensated path of a straight move, and
            # rs274 refuses them where that would queue a move or corner
            raise GCodeError("Bug code not g0 or g1")
        queue = self._cc.queue
        if not queue:
            self._cc.stale_front = move
        move.line = self.line
        queue.append(move)

    def _queue_front(self) -> _Move:
        st = self._cc
        front = st.queue[0] if st.queue else st.stale_front
        if front is None:  # rs274 reads unallocated memory here
            raise GCodeError("Bug in tool radius comp")
        return front

    def _set_endpoint(self, x: float, y: float) -> None:
        st = self._cc
        st.endpoint = [x, y]
        st.endpoint_valid = True

    def _dequeue(self) -> None:
        """rs274's dequeue_canons: hand every queued call to the canon."""
        st = self._cc
        st.endpoint_valid = False
        queue = st.queue
        if not queue:
            return
        canon = self.unqueued_canon()
        for item in queue:
            if isinstance(item, _Move):
                self._emit_queued(canon, item)
            else:
                call, args = item
                call(*args)
        queue.clear()

    def _lathe_origin(self, first: float, second: float):
        """Lathe tools are controlled at their tip, not their centre: shift
        (z, x) in the XZ plane by the radius as the orientation says."""
        st = self._cc
        if self.plane != "XZ":
            return first, second
        o, r = st.orientation, st.radius
        if o in (2, 6, 1):
            second -= r
        if o in (3, 8, 4):
            second += r
        if o in (2, 7, 3):
            first -= r
        if o in (1, 5, 4):
            first += r
        return first, second

    def _emit_queued(self, canon, item: _Move) -> None:
        # A canon that announces lines (ngc2py.preview) is told the move's
        # own: the motion calls of rs274's queue carry the line that queued
        # them (the trace prints the N of the line executing instead).
        announced = getattr(canon, "motion_line", _NO_LINE)
        if announced is _NO_LINE:
            self._emit_comp_move(canon, item)
            return
        canon.motion_line = item.line
        try:
            self._emit_comp_move(canon, item)
        finally:
            canon.motion_line = announced

    def _emit_comp_move(self, canon, item: _Move) -> None:
        plane = self.plane
        first, second = self._lathe_origin(item.x, item.y)
        rest = item.rest
        if item.kind == "arc":
            c1, c2 = self._lathe_origin(item.c1, item.c2)
            canon.arc_feed(first, second, c1, c2, item.turn, item.z, *rest)
        else:
            x, y, z = from_plane(plane, first, second, item.z)
            if item.kind == "feed":
                canon.straight_feed(x, y, z, *rest)
            else:
                canon.straight_traverse(x, y, z, *rest)
        x, y, z = from_plane(plane, first, second, item.z)
        self.world.move_to(x, y, z, *rest[:3])

    def _move_endpoint_and_flush(self, x: float, y: float) -> None:
        """Move the end of every queued move to (x, y), then flush.

        A trimmed straight move that now runs backwards, or a trimmed arc that
        now turns further than it did, would gouge the work: rs274's errors.
        """
        st = self._cc
        if not st.queue:
            return
        ex, ey = st.endpoint
        for item in st.queue:
            if not isinstance(item, _Move):
                continue
            if item.kind == "arc":
                r1 = c_hypot(item.x - item.c1, item.y - item.c2)
                r2 = c_hypot(x - item.c1, y - item.c2)
                l1 = item.sweep
                l2 = _find_turn(ex, ey, item.c1, item.c2, item.turn, x, y)
                if abs(r1 - r2) > 0.01:
                    raise GCodeError(
                        "BUG: cutter compensation has generated an invalid arc"
                        " with mismatched radii r1 %f r2 %f" % (r1, r2)
                    )
                slack = 0.001 if self.inches else 0.0254
                if l1 != 0.0 and st.endpoint_valid and abs(l2) > abs(l1) + slack:
                    raise GCodeError(_ARC_CONCAVE)
            else:
                dot = item.dx * (x - ex) + item.dy * (y - ey)
                if st.endpoint_valid and dot < 0:
                    kind = "feed" if item.kind == "feed" else "traverse"
                    raise GCodeError(
                        f"Straight {kind} in concave corner cannot be reached"
                        " by the tool without gouging"
                    )
            item.x, item.y = x, y
        self._dequeue()
        self._set_endpoint(x, y)

    # ------------------------------------------------------------------
    # Straight moves (rs274's convert_straight_comp1 and comp2)
    # ------------------------------------------------------------------
    def _comp_check_straight(self, block) -> None:
        if block.g.get(0) == G53 and self._cc.engaged:
            raise GCodeError("Cannot use g53 with cutter radius comp")

    def _comp_straight(self, rapid: Optional[bool], end: List[float]) -> None:
        """A compensated straight move (``rapid`` None: G33 or G33.1, which
        rs274 sends the same way until it would queue a move)."""
        st = self._cc
        plane = self.plane
        kind = None if rapid is None else "traverse" if rapid else "feed"
        cx, cy, cz = to_plane(plane, *self.current[:3])
        px, py, pz = to_plane(plane, *end[:3])
        rest = end[3:]
        radius = st.radius
        if st.firstmove:
            if c_hypot(px - cx, py - cy) <= radius:
                raise GCodeError(
                    "Length of cutter compensation entry move is not greater than the tool radius"
                )
            turn = ops.HALF_PI_L if st.side == LEFT else -ops.HALF_PI_L
            alpha = long_double_sum(math.atan2(py - cy, px - cx), turn)
            end_x = px + radius * math.cos(alpha)
            end_y = py + radius * math.sin(alpha)
            self._set_endpoint(cx, cy)
            self._enqueue(
                _Move(kind, end_x, end_y, pz, rest, math.cos(alpha), math.sin(alpha))
            )
            st.firstmove = False
        else:
            end_x, end_y = self._comp_straight_next(kind, cx, cy, cz, px, py, pz, rest)
        self.current = list(from_plane(plane, end_x, end_y, pz)) + list(rest)
        st.program = list(from_plane(plane, px, py, pz))

    def _comp_straight_next(self, kind, cx, cy, cz, px, py, pz, rest):
        st = self._cc
        opx, opy, opz = to_plane(self.plane, *st.program)
        if py == opy and px == opx:  # no motion in the plane
            self._enqueue(_Move(kind, cx, cy, pz, rest, px - opx, py - opy))
            return cx, cy
        side, radius = st.side, st.radius
        theta = math.atan2(cy - opy, cx - opx)
        alpha = math.atan2(py - opy, px - opx)
        if side == LEFT:
            if theta < alpha:
                theta = long_double_sum(theta, 2 * ops.PI_L)
            beta = long_double_sum(theta - alpha, -ops.HALF_PI_L)
            gamma = math.pi / 2
        else:
            if alpha < theta:
                alpha = long_double_sum(alpha, 2 * ops.PI_L)
            beta = long_double_sum(alpha - theta, -ops.HALF_PI_L)
            gamma = -math.pi / 2
        end_x = px + radius * math.cos(alpha + gamma)
        end_y = py + radius * math.sin(alpha + gamma)
        mid_x = opx + radius * math.cos(alpha + gamma)
        mid_y = opy + radius * math.sin(alpha + gamma)
        queue = st.queue
        if beta < -_SMALL or beta > math.pi + _SMALL:
            concave = True
        elif (
            beta > math.pi - _SMALL
            and queue
            and queue[0].kind == "arc"
            and _tool_inside_arc(RIGHT if side == LEFT else LEFT, queue[0].turn)
        ):
            # Tangent from an arc the tool is outside of (the top of an "h"):
            # stay outside rather than loop around.
            concave = True
        else:
            concave = False
        if not concave and beta > _SMALL:  # outside corner: go around it
            self._move_endpoint_and_flush(cx, cy)
            if kind == "feed":
                corner = _Move(
                    "arc",
                    mid_x,
                    mid_y,
                    cz,
                    rest,
                    c1=opx,
                    c2=opy,
                    turn=-1 if side == LEFT else 1,
                )
            else:
                # No rapid arcs: a straight traverse to the same point.
                corner = _Move(kind, mid_x, mid_y, cz, rest)
            self._enqueue(corner)
            self._dequeue()
            self._set_endpoint(mid_x, mid_y)
        elif concave:
            if self._queue_front().kind != "arc":  # line -> line: trim both
                halfcorner = long_double_sum(beta, ops.PI_L) / 2.0
                if halfcorner == 0.0:
                    raise GCodeError(
                        "Zero degree inside corner is invalid for cutter compensation"
                    )
                retreat = radius / math.tan(halfcorner)
                mid_x = cx + retreat * math.cos(theta + gamma)
                mid_y = cy + retreat * math.sin(theta + gamma)
            else:
                mid_x, mid_y = self._arc_to_line_corner(px, py, opx, opy)
            self._move_endpoint_and_flush(mid_x, mid_y)
        else:  # straight on, or a tangent arc -> line
            self._dequeue()
            self._set_endpoint(cx, cy)
        # (G33 and G33.1 get here as a feed: rs274 queues them as one)
        move = _Move(kind or "feed", end_x, end_y, pz, rest, px - opx, py - opy)
        self._enqueue(move)
        return end_x, end_y

    def _arc_to_line_corner(self, px, py, opx, opy):
        """Where a compensated arc meets the next compensated line inside a corner."""
        st = self._cc
        side, radius = st.side, st.radius
        prev = self._queue_front()
        oldrad = c_hypot(prev.c2 - prev.y, prev.c1 - prev.x)
        base_dir = math.atan2(py - opy, px - opx)
        theta = long_double_sum(
            base_dir, ops.HALF_PI_L if prev.turn > 0 else -ops.HALF_PI_L
        )
        phi = math.atan2(prev.c2 - opy, prev.c1 - opx)
        inside = _tool_inside_arc(side, prev.turn)
        oldrad_uncomp = oldrad + radius if inside else oldrad - radius
        d = oldrad_uncomp * math.cos(theta - phi)
        l = ((d - radius) if inside else (d + radius)) / oldrad
        if l > 1.0 or l < -1.0:
            raise GCodeError(
                "Arc to straight motion makes a corner the compensated tool can't fit in without gouging"
            )
        if inside == (prev.turn > 0):
            angle = long_double_sum(-math.acos(l) + theta, ops.PI_L)
        else:
            angle = long_double_sum(math.acos(l) + theta, ops.PI_L)
        return prev.c1 + oldrad * math.cos(angle), prev.c2 + oldrad * math.sin(angle)

    # ------------------------------------------------------------------
    # Arcs (rs274's convert_arc_comp1 and comp2)
    # ------------------------------------------------------------------
    def _comp_arc(self, move: int, block, centre_words, end: List[float], turns: int):
        plane = self.plane
        st = self._cc
        cx, cy, cz = to_plane(plane, *self.current[:3])
        ex, ey, ez = to_plane(plane, *end[:3])
        rest = end[3:]
        if st.firstmove:
            new_x, new_y = self._comp_arc_entry(
                move, block.words, centre_words, turns, (cx, cy, cz), (ex, ey, ez), rest
            )
        else:
            new_x, new_y = self._comp_arc_next(
                move, block.words, centre_words, turns, (cx, cy, cz), (ex, ey, ez), rest
            )
        st.program = list(from_plane(plane, ex, ey, ez))
        self.current = list(from_plane(plane, new_x, new_y, ez)) + list(rest)

    def _comp_arc_data(self, move, words, centre_words, turns, start, end):
        clockwise = move == G2
        if centre_words is None:
            return arcs.arc_from_radius(
                clockwise, start, end, words["r"], turns, self.inches
            )
        return arcs.arc_from_center(
            clockwise,
            self.plane,
            start,
            end,
            centre_words,
            self.ijk_absolute,
            turns,
            self.inches,
            self.spiral_tolerance(),
        )

    def _comp_arc_feed(self, words, start, start_axis, arc, end_axis) -> None:
        if self.feed_mode == arcs.INVERSE_TIME:
            self._inverse_time_feed(
                arcs.arc_length(start, start_axis, arc, end_axis), words["f"]
            )

    def _comp_arc_entry(self, move, words, centre_words, turns, current, end, rest):
        st = self._cc
        side, radius = st.side, st.radius
        cx, cy, cz = current
        ex, ey, ez = end
        if c_hypot(ex - cx, ey - cy) <= radius:
            raise GCodeError(
                "Radius of cutter compensation entry arc is not greater than the tool radius"
            )
        inside_move = (side == LEFT and move == G3) or (side == RIGHT and move == G2)
        if centre_words is None and abs(words["r"]) <= radius and inside_move:
            raise GCodeError(_TOOL_RADIUS_TOO_BIG)
        arc = self._comp_arc_data(move, words, centre_words, turns, (cx, cy), (ex, ey))
        if centre_words is not None and inside_move:
            if c_hypot(arc.center1 - cx, arc.center2 - cy) <= radius:
                raise GCodeError(_TOOL_RADIUS_TOO_BIG)
        self._comp_arc_feed(words, (cx, cy), cz, arc, ez)
        turn = arc.rotation
        centre_x, centre_y = arc.center1, arc.center2
        if _tool_inside_arc(side, turn):
            gamma = math.atan2(centre_y - ey, centre_x - ex)
        else:
            gamma = math.atan2(ey - centre_y, ex - centre_x)
        st.firstmove = False
        end_x = ex + radius * math.cos(gamma)
        end_y = ey + radius * math.sin(gamma)
        # The compensated arc starts at the tool and ends at (end_x, end_y);
        # its centre lies on the line from the end towards the programmed one.
        b_len = c_hypot(cy - end_y, cx - end_x) / 2.0
        ab_ang = math.atan2(centre_y - end_y, centre_x - end_x)
        a_ang = math.atan2(cy - end_y, cx - end_x) - ab_ang
        if abs(math.cos(a_ang)) < _TOLERANCE_EQUAL:
            raise GCodeError(_TOOL_RADIUS_TOO_BIG)
        c_len = b_len / math.cos(a_ang)
        centre_x = end_x + c_len * math.cos(ab_ang)
        centre_y = end_y + c_len * math.sin(ab_ang)
        if (
            abs(
                c_hypot(centre_x - end_x, centre_y - end_y)
                - c_hypot(centre_x - cx, centre_y - cy)
            )
            > self.spiral_tolerance()
        ):
            raise GCodeError("Bug in tool radius comp")
        if st.orientation not in (0, 9):
            # A lathe tool's origin moves first, or the arc is no arc.
            self._enqueue(_Move("feed", cx, cy, cz, rest))
            self._set_endpoint(cx, cy)
        self._enqueue(
            _Move(
                "arc",
                end_x,
                end_y,
                ez,
                rest,
                c1=centre_x,
                c2=centre_y,
                turn=turn,
                sweep=_find_turn(cx, cy, centre_x, centre_y, turn, end_x, end_y),
            )
        )
        return end_x, end_y

    def _comp_arc_next(self, move, words, centre_words, turns, current, end, rest):
        st = self._cc
        side, radius = st.side, st.radius
        cx, cy, cz = current
        ex, ey, ez = end
        opx, opy, opz = to_plane(self.plane, *st.program)
        arc = self._comp_arc_data(
            move, words, centre_words, turns, (opx, opy), (ex, ey)
        )
        self._comp_arc_feed(words, (opx, opy), opz, arc, ez)
        centre_x, centre_y, turn = arc.center1, arc.center2, arc.rotation
        arc_radius = c_hypot(centre_x - ex, centre_y - ey)
        theta = math.atan2(cy - opy, cx - opx)
        theta = long_double_sum(
            theta, -ops.HALF_PI_L if side == LEFT else ops.HALF_PI_L
        )
        delta = math.atan2(centre_y - opy, centre_x - opx)
        alpha = long_double_sum(delta, -ops.HALF_PI_L if move == G3 else ops.HALF_PI_L)
        beta = theta - alpha if side == LEFT else alpha - theta
        if beta > 1.5 * math.pi:
            beta = long_double_sum(beta, -2 * ops.PI_L)
        elif beta < -math.pi / 2:
            beta = long_double_sum(beta, 2 * ops.PI_L)
        if (side == LEFT and move == G3) or (side == RIGHT and move == G2):
            gamma = math.atan2(centre_y - ey, centre_x - ex)
            if arc_radius <= radius:
                raise GCodeError(_TOOL_RADIUS_TOO_BIG)
        else:
            gamma = math.atan2(ey - centre_y, ex - centre_x)
            delta = long_double_sum(delta, ops.PI_L)
        new_x = ex + radius * math.cos(gamma)
        new_y = ey + radius * math.sin(gamma)
        main = _Move(
            "arc",
            new_x,
            new_y,
            ez,
            rest,
            c1=centre_x,
            c2=centre_y,
            turn=turn,
            sweep=_find_turn(opx, opy, centre_x, centre_y, turn, ex, ey),
        )
        if (
            beta < -_SMALL
            or beta > math.pi + _SMALL
            # a tangent corner the tool is outside of (the middle of an "m")
            or (
                abs(long_double_sum(beta, -ops.PI_L)) < _SMALL
                and not _tool_inside_arc(side, turn)
            )
        ):
            if self._queue_front().kind != "arc":
                mid = self._line_to_arc_corner(
                    theta, beta, arc_radius, centre_x, centre_y, turn
                )
            else:
                mid = self._arc_to_arc_corner(arc_radius, centre_x, centre_y, turn)
            self._move_endpoint_and_flush(*mid)
            self._enqueue(main)
        elif beta > _SMALL:  # outside corner: an arc around it, then the arc
            mid_x = opx + radius * math.cos(delta)
            mid_y = opy + radius * math.sin(delta)
            self._dequeue()
            self._enqueue(
                _Move(
                    "arc",
                    mid_x,
                    mid_y,
                    cz,
                    rest,
                    c1=opx,
                    c2=opy,
                    turn=-1 if side == LEFT else 1,
                )
            )
            self._dequeue()
            self._set_endpoint(mid_x, mid_y)
            self._enqueue(main)
        else:
            self._dequeue()
            self._set_endpoint(cx, cy)
            self._enqueue(main)
        return new_x, new_y

    def _line_to_arc_corner(self, theta, beta, arc_radius, centre_x, centre_y, turn):
        st = self._cc
        radius = st.radius
        # rs274's sin(beta - M_PI_2l) is sinl of the unrounded long double
        across = ops.long_double_sin_product(arc_radius, beta, -ops.HALF_PI_L)
        if _tool_inside_arc(st.side, turn):
            dist = arc_radius - radius
            ratio = (across + radius) / dist
            if ratio > 1.0 or ratio < -1.0:
                raise GCodeError(_ARC_CONCAVE)
            if turn > 0:
                angle = theta + math.asin(ratio)
            else:
                angle = theta - math.asin(ratio)
        else:
            dist = arc_radius + radius
            ratio = (across - radius) / dist
            if ratio > 1.0 or ratio < -1.0:
                raise GCodeError(_ARC_CONCAVE)
            if turn > 0:
                angle = long_double_sum(theta, ops.PI_L, -math.asin(ratio))
            else:
                angle = long_double_sum(theta, ops.PI_L, math.asin(ratio))
        return centre_x + dist * math.cos(angle), centre_y + dist * math.sin(angle)

    def _arc_to_arc_corner(self, arc_radius, centre_x, centre_y, turn):
        st = self._cc
        side, radius = st.side, st.radius
        prev = self._queue_front()
        oldrad = c_hypot(prev.c2 - prev.y, prev.c1 - prev.x)
        if _tool_inside_arc(side, turn):
            newrad = arc_radius - radius
        else:
            newrad = arc_radius + radius
        arc_cc = c_hypot(prev.c2 - centre_y, prev.c1 - centre_x)
        if oldrad == 0 or arc_cc == 0:
            raise GCodeError(
                "Arc to arc motion is invalid because the arcs have the same center"
            )
        a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (
            2 * oldrad * arc_cc
        )
        if a > 1.0 or a < -1.0:
            raise GCodeError(
                "Arc to arc motion makes a corner the compensated tool can't fit in without gouging"
            )
        pullback = math.acos(a)
        cc_dir = math.atan2(centre_y - prev.c2, centre_x - prev.c1)
        if _tool_inside_arc(side, prev.turn) == (turn > 0):
            direction = cc_dir + pullback
        else:
            direction = cc_dir - pullback
        return prev.c1 + oldrad * math.cos(direction), prev.c2 + oldrad * math.sin(
            direction
        )
