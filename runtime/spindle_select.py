"""The ``$`` word (spindle selection) against the stand-alone rs274's one spindle.

rs274 keeps ``$`` as a C int (the value truncated toward zero: ``$0.5`` is
spindle 0, ``$-1.5`` is -1) and checks it only when the step of the block
that uses it runs, so whatever the block did before still happens. With
one spindle the valid numbers are 0, and -1 ("every spindle") where rs274
allows it; a valid ``$`` then acts exactly like no ``$`` at all. Each step
has its own test and message (rs274's wording, its bounds):

* G96/G97 (spindle mode) and G93-G95 (feed mode): 0 only;
* S: -1 or 0;
* M3, M4, M5: -1 or 0, a three-line message naming the count and the number;
* M19: 0 only;
* M51: never valid (rs274 refuses spindle 0 there too).

G33, G33.1 and G76 check it in runtime.lathe; the read-time check (a ``$``
with nothing to use it) is runtime.blockcheck's.
"""

from __future__ import annotations

from .errors import GCodeError

#: The stand-alone interpreter's spindle count.
SPINDLES = 1


def number(words) -> int:
    """``$`` as rs274 stores it."""
    return int(words["dollar"])


def check_spindle_mode(words) -> None:
    if not 0 <= number(words) < SPINDLES:
        raise GCodeError("Invalid spindle ($) number in Spindle Mode command")


def check_feed_mode(words) -> None:
    if not 0 <= number(words) < SPINDLES:
        raise GCodeError("Invalid spindle ($) number in Spindle Feed command")


def check_speed(words) -> None:
    if not -1 <= number(words) < SPINDLES:
        raise GCodeError("Invalid spindle ($) number in Spindle speed command")


def check_m(code: int, words) -> None:
    """M3, M4, M5, M19 and M51 with a ``$``."""
    n = number(words)
    if code in (3, 4, 5):
        if not -1 <= n < SPINDLES:
            raise GCodeError(
                "Spindle ($) number out of range in M%d Command\n"
                "num_spindles =%d. $=%d\n" % (code, SPINDLES, n)
            )
    elif code == 19:
        if not 0 <= n < SPINDLES:
            raise GCodeError("Spindle ($) number out of range in M19 Command")
    elif code == 51:
        if not 0 < n < SPINDLES:
            raise GCodeError("Invalid spindle ($) number in M51 command")
