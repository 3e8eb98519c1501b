"""Turn one ``Machine.block`` call into a checked :class:`Block`.

rs274 reads a line into a block (``read_items``), completes it
(``enhance_block``: which motion the axis words belong to) and checks it
(``check_items``) before executing anything. This module does the same for
the codes and words the generated code passes, with rs274's messages, so an
erroneous line fails before any of its canonical calls are made.

The read-time value checks are runtime.codes' (one definition for the
parser and the runtime); this module adds rs274's later, block-level ones.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, Mapping, Optional

from runtime import arcs
from runtime.codes import (  # the codes this module reasons about, and helpers
    G0,
    G1,
    G2,
    G3,
    G4,
    G5,
    G5_1,
    G5_2,
    G5_3,
    G10,
    G28,
    G30,
    G33,
    G33_1,
    G41,
    G41_1,
    G42,
    G42_1,
    G43,
    G43_1,
    G43_2,
    G52,
    G53,
    G64,
    G70,
    G71,
    G71_1,
    G71_2,
    G72,
    G72_1,
    G72_2,
    G73,
    G74,
    G76,
    G80,
    G81,
    G82,
    G83,
    G84,
    G85,
    G86,
    G87,
    G88,
    G89,
    G90,
    G91,
    G92,
    G96,
    CHECKED_LETTERS,
    M_OFFSET,
    check_word,
    group_codes,
)
from runtime.errors import GCodeError

#: rs274's G modal groups (the numbers runtime.codes.modal_group returns).
NON_MODAL, MOTION, PLANE, DISTANCE, ARC_DISTANCE, FEED_MODE, UNITS = 0, 1, 2, 3, 4, 5, 6
CUTTER_COMP, TOOL_OFFSET, RETRACT, G92_RESET, COORD_SYSTEM = 7, 8, 10, 11, 12
PATH_CONTROL, SPINDLE_MODE, LATHE_MODE = 13, 14, 15
#: rs274's M modal groups.
M_STOP, M_IO, M_TOOL, M_SPINDLE, M_COOLANT, M_OVERRIDE, M_USER = 4, 5, 6, 7, 8, 9, 10

#: Words that move an axis (the polar words count as axis words too).
AXIS_WORDS = frozenset("xyzabcuvw")
POLAR_WORDS = frozenset(("polar_dist", "polar_angle"))

#: Group 0 codes that use the axis words of their line.
_MODE0_COVETS_AXES = (G10, G28, G30, G52, G92)

#: G7x lathe cycles: G70 finishes, the others (G71, G72 and their .1/.2
#: variants) rough. Which words each kind takes was checked against rs274.
ROUGHING_CYCLES = (G71, G71_1, G71_2, G72, G72_1, G72_2)
LATHE_CYCLES = (G70,) + ROUGHING_CYCLES

#: Drilling cycles (G73, G74, G81-G89): no rotary axis words allowed.
DRILL_CYCLES = (G73, G74, G81, G82, G83, G84, G85, G86, G87, G88, G89)

#: Motions whose line may have no axis word.
_NO_AXES_NEEDED = (G0, G1, G2, G3, G5_2) + LATHE_CYCLES

#: rs274's motion mode after G5.3: none at all (not even G80).
NO_MOTION = -1

#: rs274 reads at most this many M codes on a line.
MAX_M_CODES = 4


def g_name(code: int) -> str:
    """A G code number (times ten) as written: 50 -> "G5", 711 -> "G71.1"."""
    return f"G{code // 10}" + (f".{code % 10}" if code % 10 else "")


def round_to_int(value: float) -> int:
    """rs274's round_to_int: to the nearest integer, halves upwards."""
    return int(math.floor(value + 0.5))


class Block:
    """One line's codes and words, grouped as rs274's block structure has them.

    ``g``/``m`` map modal group -> code; ``words`` maps letter -> value;
    ``motion`` is rs274's ``motion_to_be`` (the motion code the axis words
    are for, or None); ``m98`` says the line is a Fanuc-style call, whose
    M98 (in no modal group) uses the P and L words.
    """

    __slots__ = ("g", "m", "words", "motion", "m98")

    def __init__(self, g: Dict[int, int], m: Dict[int, int], words: Dict[str, float]):
        self.g = g
        self.m = m
        self.words = words
        self.motion: Optional[int] = None
        self.m98 = False

    @property
    def has_axes(self) -> bool:
        return not AXIS_WORDS.isdisjoint(self.words)

    @property
    def has_polar(self) -> bool:
        return not POLAR_WORDS.isdisjoint(self.words)


def read_block(codes, words: Dict[str, float]) -> Block:
    """Group the codes by modal group and check the word values.

    The parser checks literal codes and words at read time, in rs274's
    left-to-right order, and the compiler turns a failure into ``m.fail``;
    so these checks (the same functions) can only fail for values computed
    at run time, such as ``G[#1]`` next to ``G1`` or ``F[#1]``.
    """
    grouped = _GROUPED.get(codes) if type(codes) is tuple else None
    if grouped is None:
        g, m = group_codes(codes)
        grouped = g, {group: code - M_OFFSET for group, code in m.items()}
        if type(codes) is tuple and len(_GROUPED) < _MOST_GROUPED:
            _GROUPED[codes] = grouped
    for letter in words:
        if letter in CHECKED_LETTERS:  # (check_word returns the others as they are)
            words[letter] = check_word(letter, words[letter])
    # copies: executing the block may change them (runtime.tools)
    return Block(dict(grouped[0]), dict(grouped[1]), words)


#: A line's codes (a tuple, as generated code passes them) -> what
#: group_codes made of them: a program has a few combinations of codes
#: (``G80``, ``G99 G81``, ``M3``) on many lines. (Codes that fail are never
#: kept: they fail again.)
_GROUPED: Dict[tuple, tuple] = {}
_MOST_GROUPED = 4096


def enhance(block: Block, plane: str, motion_mode: Optional[int]) -> None:
    """rs274's enhance_block: decide ``block.motion`` and check axis-word use."""
    polar = block.has_polar
    if polar:
        if plane != "XY":
            raise GCodeError("Cannot use polar coordinate except in G17 plane")
        if "x" in block.words:
            raise GCodeError("Cannot specify both polar coordinate and X word")
        if "y" in block.words:
            raise GCodeError("Cannot specify both polar coordinate and Y word")
    axes = block.has_axes
    mode0 = block.g.get(NON_MODAL)
    mode1 = block.g.get(MOTION)
    covets = mode0 in _MODE0_COVETS_AXES
    if mode1 is not None:
        if mode1 == G80:
            if (polar or axes) and not covets:
                raise GCodeError("Cannot use axis values with g80")
            _check_g52_g92(block, mode0, polar, axes)
        else:
            if covets:
                raise GCodeError("Cannot use two g codes that both use axis values")
            if not axes and not polar and mode1 not in _NO_AXES_NEEDED:
                raise GCodeError("All axes missing with motion code")
        block.motion = mode1
    elif covets:
        _check_g52_g92(block, mode0, polar, axes)
    elif axes or polar:
        tool_offset = block.g.get(TOOL_OFFSET)
        if motion_mode in (None, NO_MOTION, G80) and tool_offset not in (G43_1, G43_2):
            raise GCodeError("Cannot use axis values without a g code that uses them")
        if tool_offset != G43_1:  # G43.2's axis words move as well
            block.motion = motion_mode
    elif motion_mode in (G2, G3) and any(letter in block.words for letter in "ijk"):
        # A line like "I1" continues the arc mode.
        block.motion = motion_mode
    if polar and block.motion is None:
        raise GCodeError("Polar coordinates can only be used for motion")


def _check_g52_g92(block: Block, mode0: Optional[int], polar: bool, axes: bool) -> None:
    if polar and mode0 == G92:
        raise GCodeError("Polar coordinates can only be used for motion")
    if not axes and mode0 in (G52, G92):
        raise GCodeError("All axes missing with g52 or g92")


def check(block: Block, distance_incremental: bool) -> None:
    """rs274's check_items: group 0 codes, the M code count, then other words."""
    _check_g_codes(block, distance_incremental)
    if len(block.m) > MAX_M_CODES:
        raise GCodeError("Too many m codes on line")
    _check_other_words(block)


def _check_g_codes(block: Block, distance_incremental: bool) -> None:
    mode0 = block.g.get(NON_MODAL)
    words = block.words
    if mode0 == G4:
        if words.get("p", -1.0) == -1.0:  # rs274 uses -1 as "no P"
            raise GCodeError("Dwell time missing with g4")
        if block.g.get(MOTION) in (G2, G3):
            raise GCodeError("G4 not allowed with G2 or G3 because they both use P")
    elif mode0 == G10:
        _check_g10(words)
    elif mode0 == G5_3:
        if block.g.get(MOTION) not in (None, G5_2):
            raise GCodeError(
                "Between G5.2 and G5.3 codes, only additional G5.2 codes are allowed."
            )
    elif mode0 == G53:
        if block.motion not in (G0, G1):
            raise GCodeError("Must use g0 or g1 with g53")
        distance = block.g.get(DISTANCE)
        if distance == G91 or (distance != G90 and distance_incremental):
            raise GCodeError("Cannot use g53 incremental")


def _check_g10(words: Mapping[str, float]) -> None:
    p = words.get("p", -1.0)
    p_int = int(p + 0.5) if p >= 0 else int(p - 0.5)
    l_word = int(words.get("l", -1.0))
    if l_word not in (0, 1, 2, 10, 11, 20):
        raise GCodeError("Line with G10 does not have L0, L1, L10, L11, L2, or L20")
    if (p + 0.0001) - p_int > 0.0002:
        raise GCodeError("P value not an integer with G10")
    if l_word in (2, 20) and not 0 <= p_int <= 9:
        raise GCodeError(f"P value out of range (0-9) with G10 L{l_word}")
    if l_word in (1, 10, 11) and p_int < 1:
        raise GCodeError(f"P value out of range with G10 L{l_word}")


# Motions that use the I, J and E words (rs274's check_other_codes).
_J_MOTIONS = (G2, G3, G5, G5_1, G76, G87)
_I_MOTIONS = _J_MOTIONS + (G33_1,) + ROUGHING_CYCLES
_E_MOTIONS = (G33, G33_1, G70, G76)


def _check_other_words(block: Block) -> None:
    """rs274's check_other_codes, with 2.9's message texts."""
    words = block.words
    motion = block.motion
    g = block.g
    if _OTHER_LETTERS.isdisjoint(words):
        # none of the words checked below (a line of modes, axes, F or S):
        # what is left are the checks that do not start from a word
        if "s" not in words and g.get(SPINDLE_MODE) == G96:
            raise GCodeError("S word missing with G96")
        _check_motion_words(motion, words)
        return
    m = block.m
    mode0 = g.get(NON_MODAL)
    comp = g.get(CUTTER_COMP)
    if motion in DRILL_CYCLES:
        for letter in "abc":
            if letter in words:
                article = "an" if letter == "a" else "a"
                raise GCodeError(f"Cannot put {article} {letter} in canned cycle")
    if (
        "d" in words
        and comp not in (G41, G42, G41_1, G42_1)
        and g.get(SPINDLE_MODE) != G96
        and motion not in LATHE_CYCLES
    ):
        raise GCodeError(
            "D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 or G96 to use it"
        )
    if "dollar" in words:
        _check_dollar_word(block)
    if "e" in words and motion not in _E_MOTIONS and m.get(M_IO) not in (66, 67, 68):
        raise GCodeError("E word with no G70, G76, M66, M67 or M68 to use it")
    if "h" in words and g.get(TOOL_OFFSET) not in (G43, G43_2) and motion != G76:
        raise GCodeError("H word with no G43 or G76 to use it")
    if "i" in words and motion not in _I_MOTIONS and mode0 != G10:
        raise GCodeError(
            "I word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to use it"
        )
    if "j" in words and motion not in _J_MOTIONS and mode0 != G10:
        raise GCodeError("J word with no G2, G3, G5, G5.1, G10, G76 or G87 to use it")
    if "k" in words and motion not in (G2, G3, G33, G33_1, G76, G87):
        raise GCodeError("K word with no G2, G3, G33, G33.1, G76, or G87 to use it")
    if "l" in words and not (block.m98 or _l_is_used(motion, mode0, comp, m)):
        raise GCodeError(
            "L word with no G10, cutter compensation, canned cycle, digital/analog input,"
            " M98 or NURBS code"
        )
    if "p" in words:
        _check_p_word(block)
    # rs274 reads Q-1 as "no Q" here (its marker for a missing Q).
    if words.get("q", -1.0) != -1.0 and not _q_is_used(motion, mode0, g, m):
        raise GCodeError(
            "Q word with no G5, G10, G64, G73, G76, G83, M19, M66, M67, M68 or user M code that uses it"
        )
    if "r" in words:
        if not _r_is_used(motion, mode0, comp, m):
            raise GCodeError("R word with no g code that uses it")
        if m.get(M_SPINDLE) == 19 and not 0.0 <= words["r"] <= 360.0:
            raise GCodeError("R value must be within 0..360 with M19")
    if "s" not in words and g.get(SPINDLE_MODE) == G96:
        raise GCodeError("S word missing with G96")
    _check_motion_words(motion, words)


#: The words _check_other_words checks by letter (S apart: it is checked
#: whether or not it is there).
_OTHER_LETTERS = frozenset(("dollar", *"abcdehijklpqr"))


def _check_dollar_word(block: Block) -> None:
    """$ (spindle selection). rs274 also names G95-G97, but compares them with
    the motion code, so they never count."""
    spindle_m = block.m.get(M_SPINDLE)
    used = (
        block.motion in (G33, G33_1, G76)
        or spindle_m in (3, 4, 5, 19)
        or block.m.get(M_OVERRIDE) == 51
        or "s" in block.words
    )
    if not used:
        raise GCodeError(
            "$ (spindle selection) word with no M3, M4, M5, M19, M51, G33, G33.1,"
            " G76, G95, G96 or G97 to use it"
        )
    # The number itself is checked by each step that uses it, as rs274
    # executes the line (runtime.spindle_select).


def _check_motion_words(motion: Optional[int], words) -> None:
    """The words G33, G33.1 and G76 require (or refuse), checked last."""
    if motion in (G33, G33_1):
        if "k" not in words:
            raise GCodeError("K word missing with g33/g33.1")
        if "f" in words:
            raise GCodeError("F word used with a g33/g33.1")
    elif motion == G76:
        if "p" not in words:
            raise GCodeError("P word missing with G76")
        if not all(letter in words for letter in "ijk"):
            raise GCodeError("I J or K words missing with G76")


def _is_cycle(motion: Optional[int]) -> bool:
    return motion is not None and G81 <= motion <= G89


def _l_is_used(motion, mode0, comp, m) -> bool:
    return (
        _is_cycle(motion)
        or motion in (G76, G5_2, G73)
        or mode0 == G10
        or comp in (G41, G41_1, G42, G42_1)
        or m.get(M_IO) == 66
    )


_P_MOTIONS = (G76, G82, G86, G88, G89, G5, G5_2, G2, G3, G70, G74, G84)


def _check_p_word(block: Block) -> None:
    g, m, motion = block.g, block.m, block.motion
    used = (
        M_USER in m  # a user M code (M100-M199) takes P and Q
        or block.m98
        or g.get(NON_MODAL) in (G10, G4)
        or g.get(PATH_CONTROL) == G64
        or motion in _P_MOTIONS
        or m.get(M_OVERRIDE) in (50, 51, 52, 53)
        or m.get(M_IO) in (62, 63, 64, 65, 66)
        or m.get(M_SPINDLE) == 19
    )
    if not used:
        raise GCodeError(
            "P word with no G2 G3 G4 G10 G64 G5 G5.2 G76 G82 G86 G88 G89"
            " or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M code to use it"
        )
    p = block.words["p"]
    if motion in (G2, G3):
        arcs.check_arc_turns(p)
    elif m.get(M_SPINDLE) == 19:
        if abs(round_to_int(p) - p) > 0.001:
            raise GCodeError("P value not an integer with M19 G2 or G3")
        if not 0 <= round_to_int(p) <= 2:
            raise GCodeError("P value must be 0,1,or 2 with M19")


def _q_is_used(motion, mode0, g, m) -> bool:
    return (
        M_USER in m
        or motion in (G83, G73, G5, G76) + LATHE_CYCLES
        or m.get(M_IO) in (66, 67, 68)
        or mode0 == G10
        or m.get(M_TOOL) == 61
        or g.get(PATH_CONTROL) == G64
        or m.get(M_SPINDLE) == 19
    )


def _r_is_used(motion, mode0, comp, m) -> bool:
    return (
        motion in (G2, G3, G76, G73, G74) + ROUGHING_CYCLES
        or _is_cycle(motion)
        or comp in (G41_1, G42_1)
        or mode0 == G10
        or m.get(M_SPINDLE) == 19
    )
