"""The hot path: straight moves in the machine's common state.

Most blocks of real programs are plain moves: ``G1 X.. Y.. F..``, ``G0 Z..``
or axis words alone in G0/G1 mode. What such a block needs from rs274's
whole pipeline (read, enhance, check, execute in order, publish #5420-#5428)
depends on a handful of modes, so the machine keeps one flag, ``_plain``,
that is true when none of the cases that make a straight move more than
"set F, replace the named axes, emit" holds:

* distance mode absolute (G90) -- no increments, no polar geometry;
* lathe radius mode (G8) -- X is not halved;
* cutter radius compensation off -- no look-ahead -- and not just turned
  off (the first move after G40 clears rs274's "no arc yet" flag);
* feed mode units per minute (G94) -- no inverse-time or per-rev checks;
* no tool change waiting to be finished;
* no canned-cycle series open (the next motion that is not a cycle must
  end it: runtime.cycles);
* no G7x profile being read (its lines go to the profile reader), no
  RETAIN_G43 (every block runs the M code step), and no wrapped rotary
  axis or locking indexer in the INI (runtime.rotary).

The flag is recomputed by :meth:`refresh_plain` after every general block
(only a general block can change those modes), and written nowhere else
(but by runtime.fast.rows.BatchesOnly._single_line, for the one line a batches-only machine runs
on the fast path). :meth:`move` checks it and
the few value-dependent conditions (a negative F, a zero feed rate for G1,
a modal motion other than G0/G1) and otherwise falls back to
``Machine.block``, which makes rs274's checks and raises its errors; so the
fast path never has to reproduce an error itself.

The code generator calls :meth:`move` for every line that is only a G0/G1
(or no motion code), axis words, F and N; :mod:`runtime.fast.rows` uses it for
data rows.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional

from runtime import arcs
from runtime.fast import arc_rows
from runtime.canon import Canon, ignores_numbers
from runtime.codes import G0, G1, G2, G3, G4, G80
from runtime.fast.rows import BATCH, straight_batch
from runtime.motion import UNITS_PER_MINUTE

_AXIS_LETTERS = "xyzabcuvw"
#: (word letters, plane, G90.1) -> runtime.fast.arc_rows.arc_recipe's answer.
_ARC_RECIPES: dict = {}


def _xyz_move(motion: int):
    """``Machine.feed`` (G1) or ``Machine.rapid`` (G0): a line of that motion
    with X, Y and/or Z alone, ``move(line, motion, x=.., ..)`` made lighter."""

    def xyz_move(
        self,
        line: int,
        x: Optional[float] = None,
        y: Optional[float] = None,
        z: Optional[float] = None,
    ) -> None:
        if self._plain and (motion == G0 or self.feed_rate > 0.0):
            cur = self.current
            end = [
                cur[0] if x is None else x,
                cur[1] if y is None else y,
                cur[2] if z is None else z,
                cur[3],
                cur[4],
                cur[5],
                cur[6],
                cur[7],
                cur[8],
            ]
            self.line = line
            canon = self.canon
            if self._block_n is not None:
                canon.set_block_number(None)
                self._block_n = None
            if motion == G1:
                canon.straight_feed(*end)
            else:
                canon.straight_traverse(*end)
            self.motion_mode = motion
            self.current = self.world.position = self.params.position = end
            return
        self.move(line, motion, x=x, y=y, z=z)

    xyz_move.__name__ = xyz_move.__qualname__ = "feed" if motion == G1 else "rapid"
    xyz_move.__doc__ = (
        "``G%d`` with X, Y and/or Z only: ``move(line, G%d, x=.., ..)``."
        % (
            motion // 10,
            motion // 10,
        )
    )
    return xyz_move


class FastPathMixin:
    """``Machine.move``: the straight-move fast path (part of Machine)."""

    #: See runtime.fast.rows.BatchesOnly (properties of the class, not state).
    rows_by_move = False
    batches_only = False

    def refresh_plain(self) -> None:
        """Recompute ``_plain`` from the modes (see the module docstring):
        the one place it is derived. A batches-only machine (runtime.fast.rows)
        keeps it in ``_batchable``, its lines taking the fast path one at a
        time (runtime.fast.rows.BatchesOnly._single_line)."""
        plain = (
            not self.distance_incremental
            and not self.lathe_diameter
            and not self.cutter_comp
            and not self._cc.side
            and not self._cc.arc_not_allowed  # a straight move must clear it
            and self.feed_mode == UNITS_PER_MINUTE
            and not self.toolchange_flag
            and self.cycle_initial_level is None
            and not self.reading_profile  # a G7x profile's lines go to its reader
            and not self.settings.retain_g43  # every block runs the M step
            and not self._rotary_rules  # A, B, C words obey the INI (runtime.rotary)
        )
        if self.batches_only:
            self._batchable, self._plain = plain, False
        else:
            self._plain = plain

    def announce_block(self, n: Optional[str]) -> None:
        """Tell the canon the N number of the line now executing."""
        self.canon.set_block_number(n)
        self._block_n = n

    def move(
        self,
        line: int,
        motion: Optional[int] = None,
        x: Optional[float] = None,
        y: Optional[float] = None,
        z: Optional[float] = None,
        a: Optional[float] = None,
        b: Optional[float] = None,
        c: Optional[float] = None,
        u: Optional[float] = None,
        v: Optional[float] = None,
        w: Optional[float] = None,
        f: Optional[float] = None,
        n: Optional[str] = None,
        comment: Optional[str] = None,
    ) -> None:
        """A line of G0/G1 (``motion``; None: the modal one), axis words, F
        and a plain comment: what ``block(line, motion, x=.., f=.., n=..,
        comment=..)`` does, faster."""
        given = motion
        if motion is None:
            motion = self.motion_mode
        # One method, no helpers: a loop's moves come through here.
        if self._plain and (
            (self.feed_rate if f is None else f) > 0.0
            if motion == G1
            else motion == G0 and (f is None or f >= 0.0)
        ):
            cur = self.current
            end = [
                cur[0] if x is None else x,
                cur[1] if y is None else y,
                cur[2] if z is None else z,
                cur[3] if a is None else a,
                cur[4] if b is None else b,
                cur[5] if c is None else c,
                cur[6] if u is None else u,
                cur[7] if v is None else v,
                cur[8] if w is None else w,
            ]
            # _open_plain_block, inline
            self.line = line
            canon = self.canon
            if n != self._block_n:
                canon.set_block_number(n)
                self._block_n = n
            if comment is not None:  # (a block's first action, after its N)
                canon.comment(comment)
            if f is not None:
                self.feed_rate = f
                canon.set_feed_rate(f)
                self.world.feed_rate = f
            if motion == G1:
                canon.straight_feed(*end)
            else:
                canon.straight_traverse(*end)
            self.motion_mode = motion
            # One list shared as the current point, the canon model's
            # position and #5420-#5428: a general block copies it first.
            self.current = self.world.position = self.params.position = end
            return
        self._general_move(line, given, (x, y, z, a, b, c, u, v, w), f, n, comment)

    # The commonest lines of a loop, G1 or G0 with X, Y and/or Z alone (no F,
    # no N), have calls of their own (made by _xyz_move below): the same as
    # move()'s plain branch with the motion, F and N known, about a quarter
    # less work a line.
    feed = _xyz_move(G1)
    rapid = _xyz_move(G0)

    def plain_rows(self, cells: List[str], at: int, end: int, plans) -> int:
        """Run data rows (runtime.fast.rows) from ``cells[at]`` while they are
        plain straight moves; returns where it stopped (a row for the
        general path, or ``end``).

        The same steps as :meth:`move`, with the machine's state
        in local variables for the whole run: this loop is where a CAM
        file's time goes.
        """
        if not self._plain:
            return at
        canon = self.canon
        feed, traverse = canon.straight_feed, canon.straight_traverse
        cur = self.current
        motion_mode, feed_rate, block_n = (
            self.motion_mode,
            self.feed_rate,
            self._block_n,
        )
        # a canon that reads the line number in its calls (ngc2py.moves)
        row_lines = canon.reads_lines
        # a canon that ignores N numbers takes rows with one in batches too,
        # and one that keeps them, by the protocol's default straight_moves
        # (each row's N told where it changes, as row by row)
        ignores_n = ignores_numbers(canon)
        tells_n = not (
            ignores_n
            or row_lines
            or type(canon).straight_moves is not Canon.straight_moves
        )
        # a pause between moves (a hand-drilling program's G4 P at each
        # hole's bottom) is taken here too, as dwell_row takes it
        pauses = type(self).dwell_row is FastPathMixin.dwell_row
        row = at
        try:
            while at < end:
                row = at
                if row_lines:
                    self.line = int(cells[at])
                key = cells[at + 1]
                plan = plans[int(key)]
                slots = plan.slots
                if slots is None:
                    if not (plan.dwell and pauses):
                        break
                    seconds = float(cells[at + 3 if plan.has_n else at + 2])
                    if seconds == -1.0:  # (rs274's "no P": block() raises it)
                        break
                    block_n = cells[at + 2] if plan.has_n else None
                    canon.set_block_number(block_n)  # (every pause's line, as block())
                    canon.dwell(seconds)
                    at += 2 + plan.width
                    continue
                motion = motion_mode if plan.motion is None else plan.motion
                stride = plan.width + 2
                if (
                    (plan.batch or (plan.batch_n and (ignores_n or tells_n)))
                    and end - at >= stride * BATCH
                    # (a batch is of rows of one shape: the next row's first)
                    and cells[at + 1 + stride] == key
                    and (motion == G0 or (motion == G1 and feed_rate > 0.0))
                ):
                    if block_n is not None and plan.batch:
                        canon.set_block_number(None)
                        block_n = None
                    call = feed if motion == G1 else traverse
                    told = None
                    if plan.batch_n and tells_n:
                        told = canon.set_block_number, block_n
                    rows, point, error = straight_batch(
                        call, cells, at, end, plan, cur, motion == G1, told=told
                    )
                    if rows:
                        at += rows * (plan.width + 2)
                        cur, motion_mode = point, motion
                        if plan.has_n:  # (the N the last row announced)
                            block_n = cells[at - plan.width]
                    if error is not None:
                        row = at  # the row whose canon call failed
                        raise error
                    if rows:
                        continue
                start = at + 2
                if plan.has_n:
                    n = cells[start]
                    start += 1
                else:
                    n = None
                f = None if plan.f_at < 0 else float(cells[start + plan.f_at])
                if motion == G1:
                    if (feed_rate if f is None else f) <= 0.0:
                        break
                elif motion != G0 or (f is not None and f < 0.0):
                    break
                if n != block_n:
                    canon.set_block_number(n)
                    block_n = n
                if f is not None:
                    feed_rate = f
                    canon.set_feed_rate(f)
                point = cur[:]
                for i, axis in slots:
                    point[axis] = float(cells[start + i])
                if motion == G1:
                    feed(*point)
                else:
                    traverse(*point)
                cur = point
                motion_mode = motion
                at += 2 + plan.width
        finally:
            self.line = int(cells[row])
            # Publish only what the rows changed: the canon model's position
            # and feed rate may rightly differ from the interpreter's (tool
            # length offsets, unit changes: runtime/world.py), and this loop
            # is entered before every general row too.
            if cur is not self.current:
                self.current = self.world.position = self.params.position = cur
                self.motion_mode = motion_mode
            if feed_rate != self.feed_rate:
                self.feed_rate = self.world.feed_rate = feed_rate
            self._block_n = block_n
        return at

    def arc(
        self,
        line: int,
        motion: int,
        n: Optional[str] = None,
        comment: Optional[str] = None,
        **words,
    ) -> None:
        """A line of G2/G3, axis words, I J K or R, F and a plain comment (the
        code generator knows its shape): :meth:`plain_arc` where it can,
        else ``block``."""
        if not self.plain_arc(line, motion, words, n, comment):
            self.block(line, motion, n=n, comment=comment, **words)

    def plain_arc(
        self,
        line: int,
        motion: Optional[int],
        words,
        n,
        comment=None,
        restated_plane=False,
    ) -> bool:
        """A line of G2/G3 (``motion``; None: the modal motion), axis words,
        I J K or R, and F, in the plain state: what ``block`` does, without
        reading, enhancing and checking the line again (runtime.fast.arc_rows
        has the checks and geometry). Returns False, having done nothing,
        where the general path must decide: not plain, a modal motion that
        is not an arc, or any error, which ``block`` then raises in rs274's
        order. Like :meth:`move`, it makes the canon call itself (the plain
        state has no cutter compensation for ``_emit_arc`` to hand it to)."""
        if not self._plain:
            return False
        if motion is None:
            motion = self.motion_mode
            if motion != G2 and motion != G3:
                return False
        plane = self.plane
        key = (tuple(words), plane, self.ijk_absolute)
        recipe = _ARC_RECIPES.get(key, False)
        if recipe is False:
            recipe = arc_rows.arc_recipe(key[0], plane, key[2])
            if len(_ARC_RECIPES) < 4096:  # a program has few call sites
                _ARC_RECIPES[key] = recipe
        if recipe is None:
            return False
        f = words.get("f")
        if f is None:
            if self.feed_rate == 0.0:
                return False
        elif f <= 0.0:  # negative, or an arc without feed: errors
            return False
        slots, r_at, i1, i2 = recipe
        values = tuple(words.values())
        cur = self.current
        end = cur[:]
        for i, axis in slots:
            end[axis] = values[i]
        p1, p2, p3 = arc_rows.PLANE_AXES[plane]
        s1, s2, e1, e2 = cur[p1], cur[p2], end[p1], end[p2]
        if r_at < 0:
            v1 = values[i1] if i1 >= 0 else 0.0
            v2 = values[i2] if i2 >= 0 else 0.0
            if self.ijk_absolute:
                c1, c2 = v1, v2
            else:
                c1, c2 = s1 + v1, s2 + v2
            if not arc_rows.centre_checks_pass(
                s1,
                s2,
                e1,
                e2,
                c1,
                c2,
                arcs.radius_tolerance(self.inches),
                self.spiral_tolerance(),
            ):
                return False
        else:
            centre = arc_rows.quick_radius_centre(
                motion == G2,
                s1,
                s2,
                e1,
                e2,
                values[r_at],
                arcs.radius_tolerance(self.inches),
            )
            if centre is None:
                return False
            c1, c2 = centre
        self._open_plain_block(line, n, f, comment)
        if restated_plane:  # G17 (restating_row): after F, before the motion
            self.canon.select_plane("XY")
        self.motion_mode = motion
        self.canon.arc_feed(
            e1, e2, c1, c2, -1 if motion == G2 else 1, end[p3], *end[3:]
        )
        # One list shared, as for a straight move (see move()).
        self.current = self.world.position = self.params.position = end
        return True

    def _open_plain_block(
        self, line: int, n: Optional[str], f: Optional[float], comment=None
    ) -> None:
        """What a plain block does before its motion: its line, its N number
        (announced when it changes), its plain comment and its F word."""
        self.line = line
        if n != self._block_n:
            self.canon.set_block_number(n)
            self._block_n = n
        if comment is not None:
            self.canon.comment(comment)
        if f is not None:
            self.feed_rate = f
            self.canon.set_feed_rate(f)
            self.world.feed_rate = f

    def restating_row(self, line: int, codes, restating, n, words) -> None:
        """A row of a move or an arc whose other codes restate modes in
        force (runtime.fast.rows): G90 in absolute distance does nothing,
        G17 in the XY plane is a SELECT_PLANE between the F word and the
        motion. Anything else, or a line the fast paths step aside from
        (having done nothing), is ``block``'s with all its codes."""
        motion, plane, arc = restating
        if (
            not self._plain
            or self.distance_incremental
            or (plane and self.plane != "XY")
        ):
            return self.block(line, *codes, n=n, **words)
        if arc:
            if not self.plain_arc(line, motion, words, n, None, plane):
                self.block(line, *codes, n=n, **words)
        elif plane:  # (a move with G17: seldom written)
            self.block(line, *codes, n=n, **words)
        else:
            self.move(line, motion, n=n, **words)

    def cancel_row(self, line: int, n: Optional[str]) -> None:
        """A row of G80 alone (runtime.fast.rows; the end of each series of
        holes): what ``block(line, G80, n=n)`` does, no check of which can
        fail: the line announced, the point copied, the comment, the motion
        mode none and the cycles' series ended, the point published, the
        modes looked at again. Where anything else may take part (rotary
        axes' rules, cutter compensation, a pending tool change or probe, a
        G7x profile being read, RETAIN_G43's M step), ``block`` decides."""
        if (
            self._rotary_rules
            or self.cutter_comp
            or self.toolchange_flag
            or self.probe_flag
            or self.reading_profile
            or self.settings.retain_g43
            or "_execute" in self.__dict__
        ):
            return self.block(line, G80, n=n)
        self.line = line
        self.announce_block(n)
        self.current = list(self.current)
        self._end_cycle_series()
        self.canon.comment("interpreter: motion mode set to none")
        self.motion_mode = G80
        self._publish_position()
        self.refresh_plain()

    def dwell_row(self, line: int, n: Optional[str], seconds: float) -> None:
        """A row of G4 and P alone (runtime.fast.rows; a hand-drilling
        program's pause at each hole's bottom): what ``block(line, G4, n=n,
        p=seconds)`` does in the plain state, which such a line leaves as it
        found it: the line announced, then DWELL. Of the checks only one can
        fail, P -1 (rs274's "no P"; any other number, negative too, is a
        dwell): ``block`` raises it."""
        if not self._plain or seconds == -1.0:
            return self.block(line, G4, n=n, p=seconds)
        self.line = line
        self.announce_block(n)
        self.canon.dwell(seconds)

    def _general_move(self, line, motion, axes, f, n, comment=None) -> None:
        """The same line through the general path (checks and errors)."""
        words = {
            letter: value
            for letter, value in zip(_AXIS_LETTERS, axes)
            if value is not None
        }
        if f is not None:
            words["f"] = f
        codes = () if motion is None else (motion,)
        self.block(line, *codes, n=n, comment=comment, **words)
