"""``ngc2py.toolpath()``: a program's moves as NumPy arrays, for people who
simulate in Python (material removal, collision checks, cycle-time models,
previews of their own).

    >>> path = ngc2py.toolpath("part.ngc")
    >>> path.end[path.kind == ngc2py.ARC]      # every arc's end, 9 axes, mm
    >>> path.length.sum()                      # mm of travel

One row per move, in program order, in millimetres (and degrees for A, B,
C) whatever units the program uses, in program coordinates as
``runtime.toolpath`` defines them (offsets taken off, as rs274's canon
reports positions). The program runs on the compiled fast path: its moves
reach ``ngc2py.recorder.Recorder`` in batches of columns (``Canon.straight_moves`` /
``arc_moves``) or one call each, and are kept in typed arrays of the
standard library until the end, when they become NumPy arrays: no Python
object per move survives the run.
"""

from __future__ import annotations

import argparse
import math
from typing import Optional

import numpy as np

from ngc2py.recorder import ARC, FEED, KINDS, PROBE, RAPID, Recorder, record


class ProgramError(Exception):
    """The program stopped at a G-code error: ``str()`` is rs274's report
    (message, file and line); :attr:`toolpath` holds the moves made before."""

    def __init__(self, message: str, toolpath: "Toolpath") -> None:
        super().__init__(message)
        self.toolpath = toolpath


class Toolpath:
    """Every move of a program, one row each (``len(path)`` rows):

    ``kind``      RAPID, FEED, ARC or PROBE (int8)
    ``start``     (n, 9) the point the move starts from: X Y Z A B C U V W
    ``end``       (n, 9) where it ends (mm; degrees for A B C)
    ``centre``    (n, 2) an arc's centre in its plane's first and second axis
                  (X Y for G17, Z X for G18, Y Z for G19); NaN for straight moves
    ``normal``    the axis normal to an arc's plane (0 X, 1 Y, 2 Z; -1 straight)
    ``turns``     an arc's turns as ARC_FEED gives them: > 0 counter-clockwise,
                  < 0 clockwise, abs(turns) - 1 extra full turns; 0 straight
    ``feed``      the feed rate in force (mm/min; mm/rev under G95); NaN for rapids
    ``line``      the G-code line the move comes from (in the file running it)
    ``tool``      the tool number in the spindle
    ``units``     "inch" or "mm": the program's units at its first move
    """

    def __init__(
        self, kind, start, end, centre, normal, turns, feed, line, tool, units
    ):
        self.kind = kind
        self.start = start
        self.end = end
        self.centre = centre
        self.normal = normal
        self.turns = turns
        self.feed = feed
        self.line = line
        self.tool = tool
        self.units = units

    @classmethod
    def from_recorder(cls, recorder) -> "Toolpath":
        """The moves a ``Recorder`` kept (or its ``Recorder.moves()``)."""
        count = len(recorder.kinds)
        end = np.frombuffer(recorder.ends, dtype=np.float64, count=count * 9)
        end = end.reshape(count, 9).copy()
        start = np.empty_like(end)
        start[1:] = end[:-1]
        if count:
            start[0] = 0.0
        for row, point in recorder.shifts:
            if row < count:
                start[row] = point
        centre = np.frombuffer(recorder.centre, dtype=np.float64, count=count * 2)
        centre = centre.reshape(count, 2).copy()
        return cls(
            kind=np.array(recorder.kinds, dtype=np.int8),
            start=start,
            end=end,
            centre=centre,
            normal=np.array(recorder.normal, dtype=np.int8),
            turns=np.array(recorder.turns, dtype=np.int32),
            feed=np.frombuffer(recorder.feeds, dtype=np.float64, count=count).copy(),
            line=np.array(recorder.lines, dtype=np.int64),
            tool=np.array(recorder.tools, dtype=np.int64),
            units="inch" if recorder.first_units else "mm",
        )

    def __len__(self) -> int:
        return len(self.kind)

    def __repr__(self) -> str:
        counts = ", ".join(
            "%d %s" % (int((self.kind == k).sum()), name)
            for k, name in enumerate(KINDS)
        )
        return "<Toolpath of %d moves: %s>" % (len(self), counts)

    # --- arc geometry, every arc at once ------------------------------
    def arc_frame(self):
        """For the arcs (``kind == ARC``): their row indexes, the plane's
        first and second axis indexes per arc, the start angle, the signed
        sweep (radians) and the start and end radius, as
        ``runtime.toolpath.make_arc`` works them out for one arc."""
        rows = np.flatnonzero(self.kind == ARC)
        normal = self.normal[rows]
        first = np.choose(normal, [1, 2, 0])
        second = np.choose(normal, [2, 0, 1])
        s1 = self.start[rows, first] - self.centre[rows, 0]
        s2 = self.start[rows, second] - self.centre[rows, 1]
        f1 = self.end[rows, first] - self.centre[rows, 0]
        f2 = self.end[rows, second] - self.centre[rows, 1]
        theta0 = np.arctan2(s2, s1)
        theta1 = np.arctan2(f2, f1)
        chord = np.hypot(
            self.end[rows, first] - self.start[rows, first],
            self.end[rows, second] - self.start[rows, second],
        )
        closed = chord < 1e-9
        turns = self.turns[rows]
        ccw = turns >= 0
        tau = 2.0 * math.pi
        sweep = np.where(
            ccw, np.mod(theta1 - theta0, tau), -np.mod(theta0 - theta1, tau)
        )
        whole = closed | (sweep == 0.0)
        sweep = np.where(whole, np.where(ccw, tau, -tau), sweep)
        extra = np.maximum(np.abs(turns) - 1, 0)
        sweep = sweep + np.where(ccw, tau, -tau) * extra
        return rows, first, second, theta0, sweep, np.hypot(s1, s2), np.hypot(f1, f2)

    @property
    def length(self):
        """Each move's path length (mm): straight moves over X, Y and Z;
        arcs and helices as ``runtime.toolpath.Arc.length``."""
        delta = self.end[:, :3] - self.start[:, :3]
        length = np.sqrt((delta * delta).sum(axis=1))
        rows, _, _, _, sweep, r0, r1 = self.arc_frame()
        if len(rows):
            normal = self.normal[rows]
            rise = self.end[rows, normal] - self.start[rows, normal]
            length[rows] = np.hypot(np.abs(sweep) * (r0 + r1) / 2.0, rise)
        return length

    def points(self, rows, resolution: float, most: Optional[int] = None, frame=None):
        """Points of X, Y and Z along the arcs ``rows`` (row indexes of
        arcs), each arc from its start to its end through points no further
        than ``resolution`` (mm) off the true curve, at least one every
        quarter turn (and, if ``most`` is given, no more than ``most`` a
        turn): ``(points (m, 3), owner (m,))``, ``owner`` giving each
        point's row. ``frame``: :meth:`arc_frame`, if the caller has it."""
        every, first, second, theta0, sweep, r0, r1 = frame or self.arc_frame()
        rows = np.asarray(rows, dtype=np.int64)
        where = np.searchsorted(every, rows)
        first, second = first[where], second[where]
        theta0, sweep, r0, r1 = theta0[where], sweep[where], r0[where], r1[where]
        radius = np.maximum(np.maximum(r0, r1), 1e-12)
        # a chord of angle a is r (1 - cos(a / 2)) off the arc at its middle
        ratio = np.clip(1.0 - resolution / radius, -1.0, 1.0)
        finest = 2.0 * math.pi / most if most else 1e-6
        step = np.clip(2.0 * np.arccos(ratio), finest, math.pi / 2)
        counts = np.maximum(np.ceil(np.abs(sweep) / step).astype(np.int64), 1)
        local = np.repeat(np.arange(len(rows)), counts + 1)
        offsets = np.concatenate(([0], np.cumsum(counts + 1)[:-1]))
        t = (np.arange(len(local)) - offsets[local]) / counts[local]
        start = self.start[rows, :3][local]
        points = start + (self.end[rows, :3][local] - start) * t[:, None]
        theta = theta0[local] + sweep[local] * t
        r = r0[local] + (r1 - r0)[local] * t
        centre = self.centre[rows][local]
        index = np.arange(len(local))
        points[index, first[local]] = centre[:, 0] + r * np.cos(theta)
        points[index, second[local]] = centre[:, 1] + r * np.sin(theta)
        return points, rows[local]


def toolpath(
    program: str,
    *,
    tool_table: Optional[str] = None,
    var_file: Optional[str] = None,
    ini: Optional[str] = None,
    block_delete: bool = False,
) -> Toolpath:
    """Run ``program`` (a G-code file, compiled and cached as ``ngc2py run``
    does, with rs274's options) and return its moves as a :class:`Toolpath`.
    A G-code error raises :class:`ProgramError` (rs274's report; the moves
    made before it on ``.toolpath``)."""
    from ngc2py.simulate import EXIT_OK

    recorder, status, report = record(
        argparse.Namespace(
            program=program,
            tool_table=tool_table,
            var_file=var_file,
            ini=ini,
            block_delete=block_delete,
        )
    )
    if status != EXIT_OK:
        raise ProgramError(report.strip(), recorder.toolpath())
    return recorder.toolpath()


__all__ = [
    "ARC",
    "FEED",
    "KINDS",
    "PROBE",
    "RAPID",
    "ProgramError",
    "Recorder",
    "Toolpath",
    "record",
    "toolpath",
]
