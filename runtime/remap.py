"""``[RS274NGC]REMAP`` entries of the INI file: refused with a clear error.

rs274 runs a remapped code through the subroutine or Python handler the
entry names. ngc2py does not run remaps (they need LinuxCNC's embedded
Python and its interpreter hooks), so it says so instead of printing a
trace that silently differs:

* a code that is not a LinuxCNC code (``M400``, ``G88.1``) fails where the
  program uses it, with the message below instead of rs274's "M-code
  greater than 199" / "Unknown g code used" (which rs274 only gives
  without the remap);
* a remap of a code ngc2py would otherwise run (``M6``, ``T``, ``G76``)
  fails as the program starts, since running it unchanged would be wrong.

Likewise Python the INI file loads (``[PYTHON]TOPLEVEL``): a call of a
subroutine no G-code defines may be one of its ``oword`` functions, and a
global parameter no G-code set one of its ``namedparams``, so they fail
saying that ngc2py runs no embedded Python, not with rs274's "EOF ...
seeking o-word" or "not defined" (which rs274 gives only without it).
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Tuple

from .lazy_re import Pattern
from .codes import G_GROUPS, M_GROUPS
from .errors import GCodeError

MESSAGE = (
    "%s is remapped by the INI file ([RS274NGC]REMAP); "
    "ngc2py does not run remapped codes"
)


PYTHON_SUB = (
    "o<%s> is not a G-code subroutine, and the INI file loads Python "
    "([PYTHON]TOPLEVEL) that may define it; ngc2py does not run embedded Python"
)

PYTHON_PARAM = (
    "Named parameter #<%s> not defined in G-code, and the INI file loads "
    "Python ([PYTHON]TOPLEVEL) that may define it; ngc2py does not run "
    "embedded Python"
)


def loads_python(ini) -> bool:
    """Whether the INI file has rs274 load a Python module (``TOPLEVEL=``
    in ``[PYTHON]``), which may define O-word subroutines and parameters."""
    return ini.find("TOPLEVEL", "PYTHON") is not None


def refuse_python_sub(settings, name: str) -> None:
    """A call of ``name``, which no G-code defines: see the module's doc."""
    if loads_python(settings.ini):
        raise GCodeError(PYTHON_SUB % name)


def remapped_codes(ini) -> Tuple[str, ...]:
    """The codes the ``REMAP=`` lines of ``[RS274NGC]`` name, in upper case
    (``M400``, ``G88.1``, ``T``), in file order."""
    found = []
    in_section = False
    for line in ini.lines:
        text = line.strip(" \t\r")
        if not text or text[0] in ";#":
            continue
        if text.startswith("["):
            in_section = text.startswith("[RS274NGC]")
            continue
        key, eq, value = text.partition("=")
        if in_section and eq and key.strip().upper() == "REMAP":
            words = value.split()
            if words:
                found.append(_normal(words[0]))
    return tuple(found)


def _normal(code: str) -> str:
    """``m400`` -> ``M400``; ``G88.10`` -> ``G88.1``."""
    code = code.upper()
    try:
        return code[0] + ("%g" % float(code[1:])) if len(code) > 1 else code
    except ValueError:
        return code


def _is_standard(code: str) -> bool:
    if code[:1] in ("G", "M") and len(code) > 1:
        try:
            number = float(code[1:])
        except ValueError:
            return False
        if code[0] == "G":
            return round(number * 10) in G_GROUPS
        return number == int(number) and int(number) in M_GROUPS
    return code in ("T", "S", "F")


def refuse_standard_remaps(settings) -> None:
    """Fail at the start when the INI file remaps a code ngc2py would run."""
    for code in remapped_codes(settings.ini):
        if _is_standard(code):
            raise GCodeError(MESSAGE % code)


def refuse_unknown(settings, letter: str, value: float, error: GCodeError) -> None:
    """A G/M value rs274's reader rejects (``error``): if the INI file remaps
    it, report that instead."""
    if not math.isfinite(value):
        raise error
    code = "G%g" % (round(value * 10) / 10) if letter == "g" else "M%g" % round(value)
    if code in remapped_codes(settings.ini):
        raise GCodeError(MESSAGE % code) from None
    raise error


#: rs274's reader errors for a code it does not know.
_UNKNOWN_CODE = (
    "M-code greater than 199",
    "Unknown m code used",
    "Unknown g code used",
)
_COMMENTS = Pattern(r"\([^)]*\)|;.*")
_WORD = Pattern(r"(?i)([gm])\s*([0-9][0-9.\s]*)")


def refuse_in_line(settings, message: str, text: str) -> None:
    """A line the compiler already found an unknown code on (``message``,
    the line's ``text``): if a code written on it is remapped, say that."""
    if not message.startswith(_UNKNOWN_CODE):
        return
    remapped = remapped_codes(settings.ini)
    if not remapped:
        return
    for letter, digits in _WORD.findall(_COMMENTS.sub("", text)):
        try:
            code = _normal(letter + digits.replace(" ", "").replace("\t", ""))
        except (ValueError, IndexError):
            continue
        if code in remapped:
            raise GCodeError(MESSAGE % code)
