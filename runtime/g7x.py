"""The geometry of the G70/G71/G72 lathe cycles, as rs274's interp_g7x computes it.

Points are complex numbers ``z + x*1j`` (Z is the real part). A profile is a
list of segments -- straight lines, arcs, and the corner fillets (A word)
and chamfers (C word) between them. The cycles turn the profile so that it
runs with Z and X decreasing, offset it by the finishing allowance, and then
cut it: G70 follows it, G71/G72 rough the stock away above it in passes of
depth I, escaping by R after each pass.

rs274 computes this with C++ ``std::complex<double>``; the arithmetic here
follows it operation for operation, because the trace prints the results to
four decimals:

* a complex times or divided by a real works on the two parts;
* complex products are ``(ac - bd) + (ad + bc)i`` (Python's, too);
* complex quotients are libgcc's ``__divdc3`` (:func:`cdiv`);
* ``abs`` is C's ``hypot`` and ``norm`` the sum of the squared parts.

Where rs274 itself never finishes (a pocket that makes no progress, an
offset that can no longer grow), :class:`G7xError` says so instead.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Callable, List, Optional

from runtime.ops import c_hypot

#: rs274's tolerance for points and intersections.
TOLERANCE = 1e-6

_DBL_MIN = 2.2250738585072014e-308

#: More passes or pockets than this are taken as a cycle that never ends.
MAX_STEPS = 1_000_000


class G7xError(Exception):
    """A failure of the cycle's geometry (rs274 reports "G7X error: ...")."""


# ----------------------------------------------------------------------
# Complex arithmetic as the C++ rs274 was compiled with
# ----------------------------------------------------------------------
def cabs(z: complex) -> float:
    return c_hypot(z.real, z.imag)


def norm(z: complex) -> float:
    return z.real * z.real + z.imag * z.imag


def scale(factor: float, z: complex) -> complex:
    """real * complex: each part multiplied."""
    return complex(factor * z.real, factor * z.imag)


def shrink(z: complex, divisor: float) -> complex:
    """complex / real: each part divided."""
    return complex(z.real / divisor, z.imag / divisor)


def cdiv(n: complex, d: complex) -> complex:
    """complex / complex as libgcc's __divdc3 (Smith's method, and the
    alternative order it takes when the ratio is zero or subnormal)."""
    a, b, c, e = n.real, n.imag, d.real, d.imag
    if abs(c) < abs(e):
        ratio = c / e
        denom = (c * ratio) + e
        if abs(ratio) > _DBL_MIN:
            return complex(((a * ratio) + b) / denom, ((b * ratio) - a) / denom)
        return complex(((c * (a / e)) + b) / denom, ((c * (b / e)) - a) / denom)
    ratio = e / c
    denom = (e * ratio) + c
    if abs(ratio) > _DBL_MIN:
        return complex(((b * ratio) + a) / denom, (b - (a * ratio)) / denom)
    return complex((a + (e * (b / c))) / denom, (b - (e * (a / c))) / denom)


def conj(z: complex) -> complex:
    return complex(z.real, -z.imag)


def with_real(z: complex, real: float) -> complex:
    return complex(real, z.imag)


def with_imag(z: complex, imag: float) -> complex:
    return complex(z.real, imag)


_I = complex(0.0, 1.0)


def _turn(z: complex) -> complex:
    """``-z*I``: the profile turned by 90 degrees."""
    return (-z) * _I


def _point_text(z: complex) -> str:
    """A complex as C++ streams print it: ``(z,x)`` with six significant digits."""
    return f"({z.real:g},{z.imag:g})"


# ----------------------------------------------------------------------
# Where the cycle's moves go
# ----------------------------------------------------------------------
class Motion:
    """The three kinds of move a cycle makes (points in profile space)."""

    def __init__(self, straight, rapid, arc) -> None:
        self.straight_move: Callable[[complex], None] = straight
        self.straight_rapid: Callable[[complex], None] = rapid
        self.circular_move: Callable[[bool, complex, complex], None] = arc


def _mirrored(out: Motion, state: int) -> Motion:
    """Moves of a turned/flipped profile mapped back to the real one."""
    maps = {
        0: (lambda z: z, False),
        1: (lambda z: -conj(z), True),
        2: (conj, True),
        3: (lambda z: -z, False),
        4: (lambda z: _I * z, False),
        5: (lambda z: conj(_I * z), True),
        6: (lambda z: -conj(_I * z), True),
        7: (lambda z: complex(-0.0, -1.0) * z, False),
    }
    fn, flips = maps[state]
    return Motion(
        lambda end: out.straight_move(fn(end)),
        lambda end: out.straight_rapid(fn(end)),
        lambda ccw, centre, end: out.circular_move(
            (not ccw) if flips else ccw, fn(centre), fn(end)
        ),
    )


class Cursor:
    """The tool's place in profile space, moved by the segments' methods."""

    __slots__ = ("at",)

    def __init__(self, at: complex) -> None:
        self.at = at


# ----------------------------------------------------------------------
# Segments
# ----------------------------------------------------------------------
class Segment:
    """A piece of the profile from ``start`` to ``end``. ``finish`` is the
    size of a corner fillet or chamfer still to be fitted (0 when done)."""

    def __init__(self, start: complex, end: complex) -> None:
        self.start = start
        self.end = end
        self.finish = 0.0

    def dup(self) -> "Segment":
        import copy  # here: only lathe cycles need it (start-up cost)

        return copy.copy(self)

    def monotonic(self) -> bool:
        return (self.end - self.start).real <= 1e-3

    def flip_imag(self) -> None:
        self.start, self.end = conj(self.start), conj(self.end)

    def flip_real(self) -> None:
        self.start, self.end = -conj(self.start), -conj(self.end)

    def rotate(self) -> None:
        self.start, self.end = _turn(self.start), _turn(self.end)

    def move(self, d: complex) -> None:
        self.start += d
        self.end += d

    def do_finish(self, prev: "Segment", nxt: "Segment") -> None:
        pass

    def intersect(self, other: "Segment") -> None:
        """Make this segment's end and ``other``'s start meet."""
        other.intersect_end(self)

    def corner_finish(self, prev: "Segment", nxt: "Segment") -> complex:
        """Fit this corner piece between ``prev`` and ``nxt``; returns the
        point the offset neighbours meet at (a fillet's centre)."""
        p, n = self._offset_pair(prev, nxt)
        if (p.end - n.start).real > 1e-2:
            self.finish = -self.finish
            p, n = self._offset_pair(prev, nxt)
        if (p.end - n.start).real > 1e-2:
            raise G7xError("Corner finish failed at " + _point_text(prev.end))
        p.intersect(n)
        centre = shrink(p.end + n.start, 2.0)
        p.offset(-self.finish)
        n.offset(-self.finish)
        self.start = prev.end = p.end
        self.end = nxt.start = n.start
        return centre

    def _offset_pair(self, prev: "Segment", nxt: "Segment"):
        p, n = prev.dup(), nxt.dup()
        p.offset(self.finish)
        n.offset(self.finish)
        return p, n


class Straight(Segment):
    def draw(self, out: Motion) -> None:
        out.straight_move(self.end)

    def offset(self, distance: float) -> None:
        chord = self.start - self.end
        d = shrink(complex(0.0 * distance, 1.0 * distance) * chord, cabs(chord))
        self.start += d
        self.end += d

    def radius(self) -> float:
        return cabs(self.start - self.end)

    def intersection_z(self, x: float) -> List[float]:
        s, e = self.start, self.end
        if min(s.imag, e.imag) > x + TOLERANCE or max(s.imag, e.imag) < x - TOLERANCE:
            return []
        if abs((s - e).imag) < TOLERANCE:
            return [s.real, e.real]
        return [(x - s.imag) / (e.imag - s.imag) * (e.real - s.real) + s.real]

    def climb(self, cur: Cursor, out: Motion) -> bool:
        if self.end.imag + TOLERANCE < self.start.imag:
            return True  # not climbing
        if cabs(cur.at - self.start) > TOLERANCE:
            raise G7xError("How did we get here?")
        out.straight_move(self.end)
        cur.at = self.end
        return False

    def climb_only(self, cur: Cursor, out: Motion) -> None:
        if self.end.imag < self.start.imag:
            return
        hits = self.intersection_z(cur.at.imag)
        if not hits:
            return
        cur.at = with_real(cur.at, hits[0])
        out.straight_move(cur.at)
        out.straight_move(self.end)
        cur.at = self.end

    def dive(self, cur: Cursor, x: float, out: Motion, fast: bool) -> bool:
        if self.start.imag <= self.end.imag + TOLERANCE:
            return True  # not a diving segment
        move = out.straight_rapid if fast else out.straight_move
        if x < self.end.imag:
            move(self.end)
            cur.at = self.end
            return False
        hits = self.intersection_z(x)
        if not hits:
            raise G7xError("x too large in straight dive")
        cur.at = complex(hits[0], x)
        move(cur.at)
        return False

    def intersect_end(self, p: Segment) -> None:
        if isinstance(p, Round):
            self._after_arc(p)
            return
        rot = shrink(conj(self.start - self.end), cabs(self.start - self.end))
        ps = (p.start - self.end) * rot
        pe = (p.end - self.end) * rot
        if (ps - pe).imag == 0:
            raise G7xError("Cannot intersect parallel lines")
        f = ps.imag / (ps - pe).imag
        point = cdiv(ps + scale(f, pe - ps), rot) + self.end
        self.start = p.end = point

    def _after_arc(self, p: "Round") -> None:
        if cabs(self.start - p.end) < TOLERANCE:
            return
        rot = shrink(conj(self.start - self.end), cabs(self.start - self.end))
        self.start = p.end = _line_circle(
            self.start,
            rot,
            self.end,
            (p.end - self.end) * rot,
            (p.center - self.end) * rot,
        )


def _line_circle(
    near: complex, rot: complex, origin: complex, pe: complex, pc: complex
) -> complex:
    """Where a line (turned onto the real axis by ``rot`` about ``origin``)
    meets a circle through ``pe`` about ``pc``: the point nearer ``near``."""
    b = norm(pc - pe) - pc.imag * pc.imag
    b = 0.0 if b < 0 else math.sqrt(b)
    s1 = cdiv(complex(pc.real + b, 0.0), rot) + origin
    s2 = cdiv(complex(pc.real - b, 0.0), rot) + origin
    return s1 if cabs(near - s1) < cabs(near - s2) else s2


class Round(Segment):
    def __init__(
        self, ccw: bool, start: complex, center: complex, end: complex
    ) -> None:
        super().__init__(start, end)
        self.ccw = bool(ccw)
        self.center = center

    def draw(self, out: Motion) -> None:
        out.circular_move(self.ccw, self.center, self.end)

    def offset(self, distance: float) -> None:
        r = cabs(self.start - self.center)
        factor = (r + (distance if self.ccw else -distance)) / r
        c = self.center
        self.start = scale(factor, self.start - c) + c
        self.end = scale(factor, self.end - c) + c

    def radius(self) -> float:
        return min(cabs(self.start - self.end), cabs(self.start - self.center))

    def flip_imag(self) -> None:
        self.ccw = not self.ccw
        super().flip_imag()
        self.center = conj(self.center)

    def flip_real(self) -> None:
        self.ccw = not self.ccw
        super().flip_real()
        self.center = -conj(self.center)

    def rotate(self) -> None:
        super().rotate()
        self.center = _turn(self.center)

    def move(self, d: complex) -> None:
        super().move(d)
        self.center += d

    def monotonic(self) -> bool:
        if self.finish != 0:
            return True
        entry = (self.start - self.center).imag
        leave = (self.end - self.center).imag
        dz = (self.end - self.start).real
        if self.ccw:
            return entry >= -1e-3 and leave >= -1e-3 and dz <= -1e-3
        return entry <= 1e-3 and leave <= 1e-3 and dz <= -1e-3

    def _on_segment(self, p: complex) -> bool:
        c = self.center
        a = (conj(self.start - c) * (p - c)).imag
        b = (conj(self.end - c) * (p - c)).imag
        if self.ccw:
            return a >= -TOLERANCE and b <= TOLERANCE
        return a <= TOLERANCE and b >= -TOLERANCE

    def intersection_z(self, x: float) -> List[float]:
        r = cabs(self.start - self.center)
        ci = self.center.imag
        s = -(x - r - ci) * (x + r - ci)
        if s < -TOLERANCE:
            return []
        s = math.sqrt(max(s, 0.0))
        hits = []
        for z in (self.center.real + s, self.center.real - s):
            if self._on_segment(complex(z, x)):
                hits.append(z)
        return hits

    def _top(self) -> complex:
        """Where a G3 arc that passes over its centre's Z stops climbing."""
        if self.end.real < self.center.real:
            return complex(
                self.center.real, self.center.imag + cabs(self.start - self.center)
            )
        return self.end

    def climb(self, cur: Cursor, out: Motion) -> bool:
        if not self.ccw:
            if cur.at.real > self.center.real:
                return True
            if cabs(cur.at - self.end) > 1e-3:
                out.circular_move(self.ccw, self.center, self.end)
            cur.at = self.end
            return False
        if cur.at.real < self.center.real:
            return True
        ep = self._top()
        if cabs(cur.at - ep) > 1e-3:
            out.circular_move(self.ccw, self.center, ep)
        cur.at = ep
        return True

    def dive(self, cur: Cursor, x: float, out: Motion, fast: bool) -> bool:
        if cabs(cur.at - self.end) < TOLERANCE or (cur.at - self.end).real <= TOLERANCE:
            cur.at = self.end
            return False
        hits = self.intersection_z(x) or self.intersection_z(x - TOLERANCE)
        c = self.center
        if self.ccw:
            if cur.at.real - TOLERANCE > c.real:
                return True
            if not hits or hits[-1] > c.real:
                out.circular_move(self.ccw, c, self.end)
                cur.at = self.end
                return False
            cur.at = complex(hits[-1], x)
            out.circular_move(self.ccw, c, cur.at)
            return False
        if cur.at.real <= c.real:
            return True  # already climbing
        if not hits:
            out.circular_move(self.ccw, c, self.end)
            cur.at = self.end
            return False
        if hits[0] < c.real:
            return False  # hit on the back side only: the pocket goes on
        cur.at = complex(hits[0], x)
        out.circular_move(self.ccw, c, cur.at)
        return False

    def climb_only(self, cur: Cursor, out: Motion) -> None:
        hits = self.intersection_z(cur.at.imag)
        if not hits:
            return
        c = self.center
        if not self.ccw:
            if hits[-1] > c.real:
                return
            cur.at = with_real(cur.at, hits[-1])
            out.straight_move(cur.at)
            if cabs(cur.at - self.end) > 1e-3:
                out.circular_move(self.ccw, c, self.end)
            cur.at = self.end
            return
        if hits[0] < c.real:
            return
        cur.at = with_real(cur.at, hits[0])
        out.straight_move(cur.at)
        ep = self._top()
        if cabs(cur.at - ep) > 1e-3:
            out.circular_move(self.ccw, c, ep)
        cur.at = ep

    def intersect_end(self, p: Segment) -> None:
        if isinstance(p, Round):
            a = cabs(self.start - self.center)
            b = cabs(p.start - p.center)
            c = cabs(self.center - p.center)
            cos_b = (c * c + a * a - b * b) / 2.0 / a / c
            cos_b2 = min(cos_b * cos_b, 1.0)
            rot = complex(cos_b, math.sqrt(1 - cos_b2))
            point = scale(a, shrink(rot * (p.center - self.center), c)) + self.center
            p.end = self.start = point
            return
        if cabs(self.start - p.end) < TOLERANCE:
            return
        rot = shrink(conj(p.start - p.end), cabs(p.start - p.end))
        self.start = p.end = _line_circle(
            self.start,
            rot,
            p.end,
            (self.end - p.end) * rot,
            (self.center - p.end) * rot,
        )


class Fillet(Round):
    """A rounded corner of radius ``size`` (A word), fitted later."""

    def __init__(self, size: float, at: complex) -> None:
        super().__init__(False, at, at, at)
        self.finish = size

    def do_finish(self, prev: Segment, nxt: Segment) -> None:
        self.center = self.corner_finish(prev, nxt)
        self.ccw = (self.start - self.center).imag > 0 or (
            self.end - self.center
        ).imag > 0
        self.finish = 0.0


class Chamfer(Straight):
    """A bevelled corner of size ``size`` (C word), fitted later."""

    def __init__(self, size: float, at: complex) -> None:
        super().__init__(at, at)
        self.finish = size

    def do_finish(self, prev: Segment, nxt: Segment) -> None:
        self.corner_finish(prev, nxt)


# ----------------------------------------------------------------------
# The profile and the cycles
# ----------------------------------------------------------------------
class Profile:
    """The segments of a G7x profile, the first one being the approach from
    the cycle's start point."""

    def __init__(self, segments: Optional[List[Segment]] = None, note=None) -> None:
        self.segments: List[Segment] = segments if segments is not None else []
        self.delta = 0.5
        self.escape = complex(0.3, 0.3)
        self.flip_state = 0
        self.pocket_starts: List[complex] = []
        #: Where rs274's diagnostic "Oops" lines go (it prints them on stdout).
        self.note = note or (lambda text: None)
        self._steps = 0

    def copy(self) -> "Profile":
        other = Profile([s.dup() for s in self.segments], self.note)
        other.delta, other.escape, other.flip_state = (
            self.delta,
            self.escape,
            self.flip_state,
        )
        return other

    def __len__(self) -> int:
        return len(self.segments)

    # --- orientation ----------------------------------------------------
    def rotate(self) -> None:
        for s in self.segments:
            s.rotate()
        self.flip_state ^= 4

    def swap(self) -> None:
        """Flip the profile so that Z and X both decrease along it."""
        span = self.segments[0].end - self.segments[-1].end
        if span.imag > 0:
            for s in self.segments:
                s.flip_imag()
            self.flip_state ^= 2
        if span.real < 0:
            for s in self.segments:
                s.flip_real()
            self.flip_state ^= 1

    def check_monotonic(self) -> None:
        first = self.segments[0]
        if (first.end - first.start).real > 0:
            first.start = with_real(first.start, first.end.real)
        for s in self.segments:
            if not s.monotonic():
                raise G7xError("Not monotonic")

    def do_finish(self) -> None:
        segs = self.segments
        for h in range(1, len(segs) - 1):
            segs[h].do_finish(segs[h - 1], segs[h + 1])
        self.segments = [s for s in segs if s.radius() >= 1e-3]

    # --- offsetting -----------------------------------------------------
    def add_distance(self, distance: float) -> None:
        """Offset the profile (not its approach) by ``distance``, in steps
        no larger than half the smallest segment, joining gaps with arcs."""
        segs = self.segments
        v1 = segs[0].end - segs[0].start
        v2 = segs[-1].start - segs[0].start
        if cdiv(v1, v2).imag < 0:
            distance = -distance
        approach = segs.pop(0)
        done = 0.0
        while done != distance:
            self._count_step()
            if not segs:
                raise G7xError("the profile vanished while offsetting it")
            step = 1e9
            for s in segs:
                step = min(step, s.radius() / 2)
            step = min(step, abs(distance - done))
            if distance < 0:
                step = -step
            for s in segs:
                s.offset(step)
            segs[:] = [s for s in segs if s.radius() >= 1e-3]
            self._join_gaps(segs, step, distance > 0)
            self._intersect_all(segs)
            if done + step == done:
                raise G7xError("the offset no longer grows (rs274 loops forever here)")
            done += step
        for a, b in zip(segs, segs[1:]):
            mid = shrink(a.end + b.start, 2.0)
            a.end = b.start = mid
        approach.end = segs[0].start if segs else approach.end
        segs.insert(0, approach)

    @staticmethod
    def _join_gaps(segs: List[Segment], step: float, ccw: bool) -> None:
        i = 0
        while i < len(segs) - 1:
            p, n = segs[i], segs[i + 1]
            if (p.end - n.start).real > 1e-2:
                s, e = p.dup(), n.dup()
                s.offset(-step)
                e.offset(-step)
                centre = shrink(s.end + e.start, 2.0)
                segs.insert(i + 1, Round(ccw, p.end, centre, n.start))
                i += 1
            i += 1

    def _intersect_all(self, segs: List[Segment]) -> None:
        i = 0
        while i < len(segs) - 1:
            self._count_step()
            if not segs[i].monotonic():
                self.note("Oops " + _point_text(segs[i].start - segs[i].end))
                if i == 0:
                    raise G7xError("Not monotonic")
                if segs[i].radius() < segs[i - 1].radius():
                    del segs[i]
                else:
                    del segs[i - 1]
                i = 0
            if len(segs) < 2:
                raise G7xError("the profile vanished while offsetting it")
            if segs[i].radius() < 1e-3:
                del segs[i]
                i = 0
            else:
                segs[i].intersect(segs[i + 1])
            i += 1

    def _count_step(self) -> None:
        self._steps += 1
        if self._steps > MAX_STEPS:
            raise G7xError("the cycle makes no progress (rs274 loops forever here)")

    # --- the cycles -----------------------------------------------------
    def g70(
        self, out: Motion, x: float, z: float, d: float, e: float, p: float
    ) -> None:
        """Finishing: ``p`` passes from allowance ``d`` down to ``e``."""
        self.segments[0].start = complex(z, x)
        path = self.copy()
        path.segments.pop(0)
        path.swap()
        if not all(s.monotonic() for s in path.segments):
            path.rotate()
            path.swap()
        path.check_monotonic()
        if path.flip_state & 4:
            self.rotate()
        self.swap()
        self.do_finish()
        self.check_monotonic()
        real_out = _mirrored(out, self.flip_state)
        passes = int(p)
        for pass_ in range(passes, 0, -1):
            distance = (pass_ - 1) * (d - e) / p + e
            path = self.copy()
            path.add_distance(distance)
            segs = path.segments
            real_out.straight_rapid(segs[0].start)
            real_out.straight_rapid(segs[0].end)
            for s in segs[1:-1]:
                s.draw(real_out)
            segs[-1].draw(real_out)

    def g71(
        self,
        out: Motion,
        cycle: int,
        x: float,
        z: float,
        u: float,
        w: float,
        d: float,
        i: float,
        r: float,
        turn: bool = False,
    ) -> None:
        """Roughing: ``cycle`` 0 cuts everything, 1 skips the pockets, 2
        only the pockets. G72 is G71 on the profile turned by 90 degrees."""
        self.segments[0].start = complex(z, x)
        if turn:
            self.rotate()
        self.swap()
        self.do_finish()
        self.check_monotonic()
        self.add_distance(d)
        displacement = complex(w, u)
        for s in self.segments:
            s.move(displacement)
        real_out = _mirrored(out, self.flip_state)
        self.delta = max(i, 2 * TOLERANCE)
        self.escape = complex(r * 1.0, r * 1.0)
        first, last = self.segments[0], self.segments[-1]
        real_out.straight_rapid(first.start)
        if last.end.imag < first.start.imag:
            self.segments.append(
                Straight(last.end, with_imag(last.end, first.start.imag))
            )
        self.pocket_starts.append(first.start)
        self._pocket(cycle, Cursor(first.start), 0, real_out, 0)

    def _pocket(self, cycle: int, cur: Cursor, p: int, out: Motion, depth: int) -> None:
        if depth > 500:
            raise G7xError("too many nested pockets (rs274 loops forever here)")
        segs = self.segments
        x = self.pocket_starts[-1].imag
        if cycle == 2:
            while p < len(segs) and not segs[p].dive(cur, -1e9, out, p == 0):
                p += 1
            cycle = 3
        seen = set()
        while p < len(segs):
            state = (p, x, cur.at)
            if state in seen:
                raise G7xError("the cycle makes no progress (rs274 loops forever here)")
            seen.add(state)
            self._count_step()
            while x - TOLERANCE > cur.at.imag:
                x -= self.delta
            if segs[p].dive(cur, x, out, p == 0):
                if cycle == 1:
                    for s in segs[p:]:
                        s.climb_only(cur, out)
                    return
                while p < len(segs):
                    if segs[p].climb(cur, out):
                        if cycle == 3:
                            starts = self.pocket_starts
                            if cur.at.imag > starts[-1].imag and len(starts) > 1:
                                starts.pop()
                            if len(starts) == 1:
                                starts.append(cur.at)
                        self._pocket(cycle, Cursor(cur.at), p, out, depth + 1)
                        return
                    p += 1
                return
            if abs(cur.at.imag - x) > TOLERANCE:
                p += 1  # beyond this segment: on to the next
                continue
            p, x = self._cut_across(p, x, cur, out)

    def _cut_across(self, p: int, x: float, cur: Cursor, out: Motion):
        """One roughing pass at height ``x``: feed across to the profile,
        escape, and come back for the next pass."""
        segs = self.segments
        here = cur.at
        for ip in range(p, len(segs)):
            hits = segs[ip].intersection_z(here.imag)
            if not hits:
                continue
            dest_z = hits[0] if ip != p else hits[-1]
            distance = abs(dest_z - here.real)
            if dest_z - TOLERANCE > here.real:
                continue  # hits the diving curve at the starting point only
            if distance < TOLERANCE:
                if p == ip:
                    continue
                if cabs(here - segs[ip].start) < TOLERANCE:
                    return ip, x  # at the entry of another curve: follow it
                return p, x - self.delta  # a zero-length cut: done
            dest = with_real(here, dest_z)
            out.straight_move(dest)
            escape_scale = min(1.0, distance / 2 / self.escape.real)
            escape = scale(escape_scale, self.escape)
            out.straight_rapid(dest + escape)
            out.straight_rapid(here - conj(escape))
            if p == 0:
                out.straight_rapid(here)
            else:
                out.straight_move(here)
            return p, x - self.delta
        return p, x


__all__ = [
    "Chamfer",
    "Fillet",
    "G7xError",
    "Motion",
    "Profile",
    "Round",
    "Straight",
]
