"""G and M code numbering, modal groups, and rs274's read-time code checks.

Codes are plain ints so generated code can compare and hash them cheaply:
a G code is its number times ten (``G1 == 10``, ``G59_3 == 593``) and an M
code is its number plus 10000 (``M3 == 10003``), so the two never collide.

The tables list every code the installed rs274 (LinuxCNC 2.9) accepts when
reading a line, with the modal group rs274 files it under.  They were
established by asking rs274 itself which values it rejects as unknown and
which pairs it rejects as "from same modal group"; where that disagrees with
the manual (G92.1-G92.3 are *not* in group 0), rs274 wins.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, Iterable, Tuple, Union

from runtime.errors import GCodeError

#: Offset that keeps M code numbers apart from G code numbers.
M_OFFSET = 10000

#: The group rs274 uses for G92.1, G92.2 and G92.3.  The manual puts them in
#: group 0, but rs274 lets them share a line with G4/G10/G28/... while
#: rejecting two of them together, so they form a group of their own.
G92_RESET_GROUP = 11

#: G code (times ten) -> modal group, as rs274's read_g has it.
G_GROUPS: Dict[int, int] = {
    # group 0: non-modal
    **dict.fromkeys((40, 53, 100, 280, 281, 300, 301, 520, 530, 920), 0),
    # group 1: motion (G80 included; read_g lets it share a line with one)
    **dict.fromkeys(
        (0, 10, 20, 30, 50, 51, 52, 330, 331, 382, 383, 384, 385)
        + (700, 710, 711, 712, 720, 721, 722, 730, 740, 760)
        + (800, 810, 820, 830, 840, 850, 860, 870, 880, 890),
        1,
    ),
    **dict.fromkeys((170, 171, 180, 181, 190, 191), 2),  # plane
    **dict.fromkeys((900, 910), 3),  # distance mode
    **dict.fromkeys((901, 911), 4),  # arc IJK distance mode
    **dict.fromkeys((930, 940, 950), 5),  # feed rate mode
    **dict.fromkeys((200, 210), 6),  # units
    **dict.fromkeys((400, 410, 411, 420, 421), 7),  # cutter compensation
    **dict.fromkeys((430, 431, 432, 490), 8),  # tool length offset
    **dict.fromkeys((980, 990), 10),  # canned cycle return mode
    **dict.fromkeys((921, 922, 923), G92_RESET_GROUP),
    **dict.fromkeys((540, 550, 560, 570, 580, 590, 591, 592, 593), 12),
    **dict.fromkeys((610, 611, 640), 13),  # path control
    **dict.fromkeys((960, 970), 14),  # spindle speed mode
    **dict.fromkeys((70, 80), 15),  # lathe diameter/radius mode
}

#: M code number (without offset) -> modal group, as rs274's read_m has it.
#: M98 is absent: rs274 only accepts it at the start of a line (as a call).
M_GROUPS: Dict[int, int] = {
    **dict.fromkeys((0, 1, 2, 30, 60, 99), 4),  # stopping
    **dict.fromkeys((62, 63, 64, 65, 66, 67, 68), 5),  # I/O
    **dict.fromkeys((6, 61), 6),  # tool change
    **dict.fromkeys((3, 4, 5, 19, 70, 71, 72, 73), 7),  # spindle, modal state
    **dict.fromkeys((7, 8, 9), 8),  # coolant
    **dict.fromkeys((48, 49, 50, 51, 52, 53), 9),  # override switches
    # user-defined M100-M199: accepted when read; whether a program for
    # one exists is checked later, when the block is executed.
    **dict.fromkeys(range(100, 200), 10),
}

# Module constants: G0, G1, ..., G59_3, M0, ..., M199 (see module docstring).
for _code in G_GROUPS:
    _name = "G%d" % (_code // 10) + ("_%d" % (_code % 10) if _code % 10 else "")
    globals()[_name] = _code
for _number in M_GROUPS:
    globals()["M%d" % _number] = _number + M_OFFSET
M98 = 98 + M_OFFSET  # only ever a Fanuc-style call at the start of a line
del _code, _number, _name

#: C's conversion of an out-of-range double to int on the machines rs274 runs
#: on (x86-64 yields INT_MIN), which is what makes G[1e300] "negative".
_INT_MIN = -(2**31)


def _c_int(value: float) -> int:
    """``(int) value`` for an already integral ``value``, as x86-64 C does it."""
    if math.isnan(value) or not (_INT_MIN <= value < 2**31):
        return _INT_MIN
    return int(value)


def _nearest_int(value: float, near_above: float, near_below: float, error: str) -> int:
    """Round ``value`` to an int if it is close to one, else raise ``error``.

    This is rs274's floor-then-maybe-ceil rule: a fractional part above
    ``near_above`` rounds up, one up to ``near_below`` truncates; the two
    thresholds are rs274's literal constants (``1 - tolerance`` computed in
    floating point would differ in the last bit).
    """
    low = _c_int(math.floor(value)) if math.isfinite(value) else _INT_MIN
    if value - low > near_above:
        return _c_int(math.ceil(value)) if math.isfinite(value) else _INT_MIN
    if value - low > near_below:
        raise GCodeError(error)
    return low


def to_integer(value: float) -> int:
    """rs274's read_integer_value: accept values within 0.0001 of an integer."""
    return _nearest_int(value, 0.9999, 0.0001, "Non integer value for integer")


def g_code(value: float) -> int:
    """Convert the value of a G word to a code, validating it as rs274's reader does."""
    code = _nearest_int(10.0 * value, 0.999, 0.001, "G-code out of range")
    if code > 999:
        raise GCodeError("G-code out of range")
    if code < 0:
        raise GCodeError("Negative g code used")
    if code not in G_GROUPS:
        raise GCodeError("Unknown g code used")
    return code


def m_code(value: float) -> int:
    """Convert the value of an M word to a code, validating it as rs274's reader does."""
    number = to_integer(value)
    if number < 0:
        raise GCodeError("Negative m code used")
    if number > 199:
        raise GCodeError("M-code greater than 199: M%d" % number)
    if number not in M_GROUPS:
        raise GCodeError("Unknown m code used: M%d" % number)
    return number + M_OFFSET


def check_word(letter: str, value: float) -> Union[int, float]:
    """rs274's read-time check of one word's value; returns what it keeps.

    ``letter`` is lower case.  G and M values become codes (:func:`g_code`,
    :func:`m_code`), H, L and T values the integer rs274's
    read_integer_value makes of them; any other value is returned as is.
    The parser calls this for literal values, the runtime for computed ones
    (``F[#1]``), so both fail with the same message.
    """
    if letter == "g":
        return g_code(value)
    if letter == "m":
        return m_code(value)
    if letter in _INTEGER_WORDS:
        number = to_integer(value)
        if number < _INTEGER_WORDS[letter][0]:
            raise GCodeError(_INTEGER_WORDS[letter][1])
        return number
    if letter in _NON_NEGATIVE_WORDS and value < 0.0:
        raise GCodeError(_NON_NEGATIVE_WORDS[letter])
    return value


#: Integer words: letter -> (smallest value rs274 accepts, its message).
#: H may be -1 (rs274's "no H" value).
_INTEGER_WORDS: Dict[str, Tuple[int, str]] = {
    "h": (-1, "Negative h word used"),
    "l": (0, "Negative l word used"),
    "t": (0, "Negative tool id (tool not found)"),
}

#: Real words that may not be negative: letter -> rs274's message.
_NON_NEGATIVE_WORDS = {
    "f": "Negative f word used",
    "s": "Negative spindle speed used",
}


#: The letters whose values check_word checks or changes: any other word's
#: value it returns as it is.
CHECKED_LETTERS = frozenset(("g", "m", *_INTEGER_WORDS, *_NON_NEGATIVE_WORDS))


def record_code(seen: Dict[int, int], code: int) -> None:
    """Add one G or M code of a line to ``seen`` (modal group -> code), with
    rs274's rule for two codes of one group on a line.

    Keep one dict for a line's G codes and another for its M codes (their
    group numbers overlap).  G80 gives way to another motion code on the
    same line, before or after it; any other pair fails.
    """
    group = modal_group(code)
    current = seen.get(group)
    if current is None or current == G80:
        seen[group] = code
    elif code != G80:
        kind = "m" if is_m_code(code) else "g"
        raise GCodeError("Two %s codes used from same modal group" % kind)


def group_codes(codes: Iterable[int]) -> Tuple[Dict[int, int], Dict[int, int]]:
    """A line's codes as (G group -> code, M group -> code), checked in order
    with :func:`record_code`."""
    g_groups: Dict[int, int] = {}
    m_groups: Dict[int, int] = {}
    for code in codes:
        record_code(m_groups if is_m_code(code) else g_groups, code)
    return g_groups, m_groups


def is_m_code(code: int) -> bool:
    return code >= M_OFFSET


def modal_group(code: int) -> int:
    """The modal group of a G or M code (as returned by g_code/m_code)."""
    if is_m_code(code):
        return M_GROUPS[code - M_OFFSET]
    return G_GROUPS[code]


def code_name(code: int) -> str:
    """``"G1"``, ``"G59.3"``, ``"M3"``: the code as a person writes it."""
    if is_m_code(code):
        return "M%d" % (code - M_OFFSET)
    whole, tenth = divmod(code, 10)
    return "G%d" % whole + (".%d" % tenth if tenth else "")


def constant_name(code: int) -> str:
    """The module constant for a code: ``"G59_3"``, ``"M3"``."""
    return code_name(code).replace(".", "_")
