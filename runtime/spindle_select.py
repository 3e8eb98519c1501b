"""The $ word: which spindle a code is for.

The stand-alone rs274 has one spindle, number 0. Where a code allows it,
$-1 means "every spindle", which for one spindle is the same as $0. Any
other number fails when rs274 executes the step that reads it (not when it
checks the line), each step with its own message; G33, G33.1 and G76 are
checked in runtime.lathe. rs274 keeps $ as an int, so a fraction is
truncated towards zero first.
"""

from __future__ import annotations

from runtime.errors import GCodeError

#: The spindles of the stand-alone interpreter.
NUM_SPINDLES = 1

#: step -> (is -1 allowed, message)
_RULES = {
    "mode": (False, "Invalid spindle ($) number in Spindle Mode command"),
    "feed": (False, "Invalid spindle ($) number in Spindle Feed command"),
    "speed": (True, "Invalid spindle ($) number in Spindle speed command"),
    "m19": (False, "Spindle ($) number out of range in M19 Command"),
}


def check_dollar(words, step: str) -> None:
    """Raise rs274's error when the line's $ names no spindle for ``step``
    ("mode", "feed", "speed", "m3", "m4", "m5", "m19" or "m51")."""
    if "dollar" not in words:
        return
    number = int(words["dollar"])
    if step == "m51":
        # M51 takes one spindle, never "all", and not spindle 0 either
        if number <= 0 or number >= NUM_SPINDLES:
            raise GCodeError("Invalid spindle ($) number in M51 command")
        return
    if step in ("m3", "m4", "m5"):
        if not -1 <= number < NUM_SPINDLES:
            raise GCodeError(
                "Spindle ($) number out of range in %s Command\nnum_spindles =%d. $=%d\n"
                % (step.upper(), NUM_SPINDLES, number)
            )
        return
    all_allowed, message = _RULES[step]
    if not (-1 if all_allowed else 0) <= number < NUM_SPINDLES:
        raise GCodeError(message)
