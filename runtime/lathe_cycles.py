"""G70, G71, G72 (and G71.1/.2, G72.1/.2): lathe finishing and roughing
cycles, as rs274's convert_g7x runs them.

A mixin of :class:`runtime.machine.Machine`. The cycle's profile is the
subroutine ``o<Q>``: rs274 calls it and reads its lines one by one, running
their O-words and parameter settings but taking nothing from the other
lines except the motion code and the X, Z, U and W (increments of X and
Z, read only here), I, K, R, A (fillet) and C (chamfer) words. Here the subroutine's compiled function runs with the
machine's ``block`` replaced by a recorder that does the same, so control
flow and parameters work as they do everywhere else.

While it reads the profile rs274 works in absolute distance and absolute
IJK modes (the words are converted back as it reads), and it makes its
moves through its ordinary straight and arc code -- so they fail, print and
update the position as any G0/G1/G2/G3 does, and leave that motion mode.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Optional

from runtime import blockcheck
from runtime.blockcheck import Block
from runtime.codes import G0, G1, G2, G3, G70, G72, to_integer
from runtime.errors import GCodeError
from runtime.g7x import (
    Chamfer,
    Fillet,
    G7xError,
    Motion,
    Profile,
    Round,
    Straight,
    norm,
    shrink,
)


class LatheCyclesMixin:
    """convert_g7x (part of Machine)."""

    def _lathe_cycle(self, motion: int, block: Block) -> None:
        words = block.words
        if "q" not in words:
            raise GCodeError("G7x.x  requires a Q word")  # sic: two spaces
        # rs274 always writes the decimal here: "G70.0".
        name = f"G{motion // 10}.{motion % 10}"
        if self.cutter_comp and motion != G70:
            raise GCodeError(f"{name} cannot be used with cutter compensation enabled")
        if self.plane != "XZ":
            raise GCodeError(f"{name} can only be used in XZ plane (G18)")
        incremental, ijk_absolute = self.distance_incremental, self.ijk_absolute
        self.distance_incremental, self.ijk_absolute = False, True
        try:
            self._run_lathe_cycle(motion, block, incremental, ijk_absolute)
        finally:
            self.distance_incremental, self.ijk_absolute = incremental, ijk_absolute

    def _run_lathe_cycle(
        self, motion: int, block: Block, incremental: bool, ijk_absolute: bool
    ) -> None:
        words = block.words
        x, z = self.current[0], self.current[2]
        if incremental:
            x += words.get("x", 0.0)
            z += words.get("z", 0.0)
        else:
            x, z = words.get("x", x), words.get("z", z)
        # rs274 moves there in absolute mode, whatever G90/G91 says.
        self._straight(G0, block)
        reader = _ProfileReader(self, complex(z, x), incremental, ijk_absolute)
        reader.read(words["q"])
        self.canon.set_block_number(None)  # the moves print as the endsub line
        segments = reader.segments
        if len(segments) <= 1:
            return
        i = words.get("i", 1.0)
        if i <= 0:
            raise GCodeError("G7X error: I must be greater than zero.")
        profile = Profile(segments, note=self.canon.print_text)
        out = Motion(self._g7x_straight, self._g7x_rapid, self._g7x_arc)
        d, e, p = words.get("d", 0.0), words.get("e", 0.0), words.get("p", 1.0)
        r, u, w = words.get("r", 0.5), words.get("u", 0.0), words.get("w", 0.0)
        cycle, subcycle = motion // 10 * 10, motion % 10
        try:
            if cycle == G70:
                profile.g70(out, x, z, d, e, p)
            else:
                profile.g71(out, subcycle, x, z, u, w, d, i, r, turn=cycle == G72)
        except G7xError as error:
            raise GCodeError(f"G7X error: {error}") from None
        except RecursionError:
            raise GCodeError(
                "G7X error: too many nested pockets (rs274 loops forever here)"
            ) from None

    # --- the moves, through the ordinary G0/G1/G2/G3 code ------------------
    def _g7x_rapid(self, end: complex) -> None:
        self._straight(G0, Block({}, {}, {"x": end.imag, "z": end.real}))

    def _g7x_straight(self, end: complex) -> None:
        self._straight(G1, Block({}, {}, {"x": end.imag, "z": end.real}))

    def _g7x_arc(self, ccw: bool, centre: complex, end: complex) -> None:
        # rs274 leaves out arcs that end where the tool is.
        cur = self.current
        if abs(cur[2] - end.real) < 0.0001 and abs(cur[0] - end.imag) < 0.0001:
            return
        words = {"x": end.imag, "z": end.real, "i": centre.imag, "k": centre.real}
        self._arc(G3 if ccw else G2, Block({}, {}, words))


class _ProfileReader:
    """Stands in for ``Machine.block`` while rs274 reads a G7x profile."""

    def __init__(self, machine, start: complex, incremental: bool, ijk_absolute: bool):
        self.m = machine
        self.start = start
        self.incremental = incremental
        self.ijk_absolute = ijk_absolute
        self.segments: List = []

    def read(self, q: float) -> None:
        m = self.m
        # rs274 writes the call out as text ("O100.000000 CALL") and reads it.
        name = "%d" % to_integer(float("%f" % q))
        # The generated code calls m.block for each line, or m.move for
        # plain moves, which falls back to m.block when _plain is off.
        m.block = self.block
        m.reading_profile = True
        m.refresh_plain()  # the profile's lines go to its reader
        m._publish_position()
        try:
            m.call_named(name)
        finally:
            del m.block
            m.reading_profile = False
            m.refresh_plain()

    def block(
        self, line: int, *codes: int, n: Optional[str] = None, comment=None, **words
    ) -> None:
        """One profile line: checked as rs274 reads it, then only its motion
        code and profile words are used."""
        m = self.m
        m.line = line
        if m.lathe_diameter and "x" in words:
            words["x"] /= 2
        block = blockcheck.read_block(codes, words)
        blockcheck.enhance(block, m.plane, m.motion_mode)
        blockcheck.check(block, False)
        self._add(block)
        m._publish_position()

    def _add(self, block: Block) -> None:
        m, words, start = self.m, block.words, self.start
        end = complex(0.0, 0.0) if self.incremental else start
        if "u" in words:
            self._check_incremental_word("U", "X", words)
            u = words["u"] / 2 if m.lathe_diameter else words["u"]
            end = complex(end.real, end.imag + u)
        elif "x" in words:
            end = complex(end.real, words["x"])
        if "w" in words:
            self._check_incremental_word("W", "Z", words)
            end = complex(end.real + words["w"], end.imag)
        elif "z" in words:
            end = complex(words["z"], end.imag)
        centre = complex(words.get("k", 0.0), words.get("i", 0.0))
        if self.incremental:
            end += start
        motion = block.g.get(blockcheck.MOTION)
        if motion is not None:
            m.motion_mode = motion
        if start == end:
            return
        mode = m.motion_mode
        if mode in (G0, G1):
            self.segments.append(Straight(start, end))
        elif mode in (G2, G3):
            self.segments.append(self._arc(mode, words, start, end, centre))
        if mode in (G0, G1, G2, G3):
            if "a" in words and "c" in words:
                raise GCodeError("G7X error: Both A and C parameters on a corner")
            if "a" in words:
                self.segments.append(Fillet(words["a"], end))
            if "c" in words:
                self.segments.append(Chamfer(words["c"], end))
        m.current = [end.imag, m.current[1], end.real] + m.current[3:]
        self.start = end

    def _check_incremental_word(self, letter: str, axis: str, words) -> None:
        """U and W are increments of X and Z, for absolute mode only."""
        if self.incremental:
            raise GCodeError(
                f"G7x error: Cannot use {letter} in incremental mode (G91)"
            )
        if axis.lower() in words:
            raise GCodeError(
                f"G7x error: Cannot use {letter} and {axis} in the same block"
            )

    def _arc(self, mode: int, words, start: complex, end: complex, centre: complex):
        if "r" in words:
            if "i" in words or "k" in words:
                raise GCodeError("G7X error: both R and I or K flag used for arc")
            r = words["r"]
            chord = end - start
            root = _c_sqrt((r * r - norm(chord) / 4) / norm(chord))
            offset = complex(0.0 * root, 1.0 * root) * chord
            centre = shrink(start + end, 2.0)
            centre = centre + offset if mode == G3 else centre - offset
        else:
            if "i" not in words and "k" not in words:
                raise GCodeError("G7X error: either I or K must be present for arc")
            if not self.ijk_absolute:
                centre += start
        return Round(mode == G3, start, centre, end)


def _c_sqrt(value: float) -> float:
    """C's sqrt: NaN, not an exception, for a negative argument."""
    return math.sqrt(value) if value >= 0 else math.nan


__all__ = ["LatheCyclesMixin"]
