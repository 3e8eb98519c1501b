"""The INI file given to ``rs274 -i``: the lookups rs274 2.9 makes, and the
settings among them that change what ``rs274 -g`` prints.

Lookup rules (LinuxCNC's IniFile reader):

* ``find(key, section)`` searches only the *first* line whose first
  non-blank text starts with ``[section]``, up to the next line starting
  with ``[``. Lines whose first non-blank character is ``;`` or ``#`` are
  comments; there are no end-of-line comments (``4 # four`` is the value).
* A line matches ``key`` when it starts with the key followed by a space,
  tab or ``=``; the value is what follows the first ``=``, without leading
  and trailing blanks; no ``=`` or an empty value counts as absent. The
  first matching line wins. A line ending in ``\\``
  continues on the next one.
* Keys and sections are case-sensitive.

What ``rs274 -g`` uses (everything else, e.g. [RS274NGC]PARAMETER_FILE,
[EMCIO]TOOL_TABLE, [TRAJ]COORDINATES, USER_M_PATH, is ignored by it): see
:class:`IniSettings`. rs274 also reads [RS274NGC]HAL_PIN_VARS (the
stand-alone rs274 has no HAL pins to find) and NO_DOWNCASE_OWORD (it looks
names up regardless of case), which change nothing it prints, and
OWORD_WARNONLY, which ngc2py does not model (rs274 goes on past a bad
O-word label with values it never set). Integer settings must be plain integers (``yes`` or
``1x`` leave the default, silently). An arc tolerance outside its allowed
range, or not a number, keeps the default and makes rs274 print
``invalid [RS274NGC]<KEY> in INI file`` and an empty line on stderr. A file
that cannot be opened makes rs274 print ``Unable to open inifile:<path>:``
on stderr and run without settings; a folder reads as an empty file. A
carriage return inside a line makes every lookup fail with an error on
stderr; CR-LF line ends only add a warning before the other reports.
"""

from __future__ import annotations

import os
from collections import namedtuple

from runtime.lazy_re import Pattern

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Optional, Tuple

from runtime.arcs import (
    CENTER_ARC_RADIUS_TOLERANCE_INCH,
    CENTER_ARC_RADIUS_TOLERANCE_MM,
)

#: Smallest arc tolerances the INI file may set (the largest are the defaults).
MIN_CENTER_ARC_RADIUS_TOLERANCE_INCH = 0.00004
MIN_CENTER_ARC_RADIUS_TOLERANCE_MM = 0.001

#: rs274 keeps at most this many SUBROUTINE_PATH directories.
MAX_SUBROUTINE_DIRS = 10

#: LOCKING_INDEXER_JOINT's "none".
NO_INDEXER = -1

#: FEATURES bit that enables #<_ini[SECTION]KEY> parameters.
FEATURE_INI_VARS = 4

#: A carriage return that does not end a line: LinuxCNC's reader refuses
#: such a file. A CR before LF (or at the end) only earns a warning.
_AMBIGUOUS_CR = Pattern(r"\r(?!\n|\Z)")
AMBIGUOUS_CR_ERROR = "inifile: error: File contains ambiguous carriage returns\n"
DOS_LINE_ENDINGS_WARNING = "inifile: warning: File contains DOS-style line endings.\n"

#: How many INI lookups rs274 2.9 makes while starting (each one reports an
#: unreadable file), counted from its output.
RS274_INI_LOOKUPS = 31

_INTEGER = Pattern(r"[+-]?\d+")
_FLOAT = Pattern(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


#: LinuxCNC's LINELEN: IniFile::Find reads lines with fgets(line, LINELEN + 1).
_LINE_LENGTH = 255


def _fgets_lines(text: str):
    """``text`` in the pieces fgets reads with room for 255 characters:
    up to and with a newline, or 255 characters."""
    start, size = 0, len(text)
    while start < size:
        newline = text.find("\n", start, start + _LINE_LENGTH)
        end = newline + 1 if newline >= 0 else min(start + _LINE_LENGTH, size)
        yield text[start:end]
        start = end


class IniFile(namedtuple("IniFile", "lines", defaults=((),))):
    """An INI file's logical lines (continuations joined), for lookups."""

    __slots__ = ()

    @classmethod
    def parse(cls, text: str) -> "IniFile":
        """The lines as LinuxCNC's IniFile::Find reads them: by fgets into a
        buffer of 256, so a line of more than 255 characters (its newline
        counted) goes on as the next line; a backslash before the line's
        last character (its newline, or the 255th) joins the next line to
        it, without the backslash or that character, and the joined line's
        last piece loses its last character too (a newline, or not); a
        file that ends while joining ends the joined line unread."""
        lines, pending = [], None
        for chunk in _fgets_lines(text):
            last = len(chunk) - 1
            if last > 0 and chunk[last - 1] == "\\":
                pending = (pending or "") + chunk[: last - 1]
                continue
            if pending is None:
                lines.append(chunk[:last] if chunk.endswith("\n") else chunk)
            else:  # (a joined line's last piece loses its last character)
                lines.append(pending + chunk[:last])
                pending = None
        return cls(tuple(lines))

    def find(self, key: str, section: str) -> Optional[str]:
        """The value of ``key`` in ``section`` as rs274 finds it, or None."""
        header = f"[{section}]"
        in_section = False
        for line in self.lines:
            text = line.lstrip(" \t\r")
            if not text or text[0] in ";#":
                continue
            if not in_section:
                in_section = text.startswith(header)
                continue
            if text.startswith("["):
                return None
            if text.startswith(key) and text[len(key) : len(key) + 1] in (
                " ",
                "\t",
                "\r",
                "=",
            ):
                value = text.partition("=")[2].strip(" \t\r\n")
                return value or None  # "KEY =" with no value counts as absent
        return None


#: The INI settings that change what ``rs274 -g`` prints: (name, default).
_SETTINGS = (
    #: [RS274NGC]SUBROUTINE_PATH: existing directories, absolute, in order.
    #: Relative entries are relative to the *current directory*; ``~/`` is
    #: expanded; entries that do not exist are dropped.
    ("subroutine_path", ()),
    #: [DISPLAY]PROGRAM_PREFIX, resolved the same way (None if absent/missing).
    ("program_prefix", None),
    #: [RS274NGC]FEATURES bit mask (see FEATURE_INI_VARS).
    ("features", 0),
    #: [RS274NGC]CENTER_ARC_RADIUS_TOLERANCE_INCH / _MM (see runtime.arcs).
    ("center_arc_radius_tolerance_inch", CENTER_ARC_RADIUS_TOLERANCE_INCH),
    ("center_arc_radius_tolerance_mm", CENTER_ARC_RADIUS_TOLERANCE_MM),
    #: [RS274NGC]DISABLE_G92_PERSISTENCE: clear #5210-#5219 at start-up.
    ("disable_g92_persistence", False),
    #: [RS274NGC]ORIENT_OFFSET (M19).
    ("orient_offset", 0.0),
    #: [EMCIO] tool change behaviour of M6.
    ("tool_change_at_g30", False),
    ("tool_change_quill_up", False),
    ("tool_change_with_spindle_on", False),
    ("random_toolchanger", False),
    #: [TRAJ]SPINDLES: how many spindles M2, M6, M48/M49, M51 and $-1 reach
    #: (rs274 keeps any int, even 0, negative or past its eight spindles).
    ("num_spindles", 1),
    #: [AXIS_A], [AXIS_B], [AXIS_C] WRAPPED_ROTARY: angles taken modulo 360
    #: (runtime.rotary).
    ("wrapped_rotary", (False, False, False)),
    #: [AXIS_A], [AXIS_B], [AXIS_C] LOCKING_INDEXER_JOINT: the joint of a
    #: locking indexer, -1 for none (runtime.rotary).
    ("indexer_joints", (NO_INDEXER, NO_INDEXER, NO_INDEXER)),
    #: [RS274NGC]INI_VARS (on unless "0"): #<_ini[SECTION]KEY> parameters.
    ("ini_vars", True),
    #: [RS274NGC]RETAIN_G43 ("1"): G43 follows every tool change.
    ("retain_g43", False),
    #: [RS274NGC]OWORD_NARGS ("1"): a called sub gets #<n_args>.
    ("oword_nargs", False),
    #: [RS274NGC]DISABLE_FANUC_STYLE_SUB (an integer, non-zero): M98 fails.
    ("disable_fanuc_style_sub", False),
    #: The file itself, for #<_ini[SECTION]KEY>.
    ("ini", IniFile()),
    #: What rs274 prints on stderr while reading the file (after "executing").
    ("stderr_report", ""),
    #: False when the file could not be opened (rs274 then runs as without -i).
    ("opened", True),
)


class IniSettings(
    namedtuple(
        "IniSettings",
        [name for name, _ in _SETTINGS],
        defaults=[default for _, default in _SETTINGS],
    )
):
    """The INI settings that change what ``rs274 -g`` prints."""

    __slots__ = ()

    def ini_value(self, section: str, key: str) -> Optional[str]:
        """The raw text of an INI entry, or None."""
        return self.ini.find(key, section)

    def ini_parameter(self, name: str) -> Optional[float]:
        """The value of ``#<_ini[...]>`` parameter ``name``, or None."""
        return ini_parameter(self.ini, name) if self.ini_vars else None


def load_ini(path: str) -> IniSettings:
    """Read the ``-i`` file the way rs274 does."""
    if os.path.isdir(path):
        return settings_from(IniFile())  # rs274 opens a folder; it reads empty
    try:
        with open(path, "rb") as f:
            text = f.read().decode("latin-1")
    except OSError:
        return IniSettings(
            stderr_report=f"Unable to open inifile:{path}:\n", opened=False
        )
    if _AMBIGUOUS_CR.search(text):
        # Every lookup fails, and each one says so.
        return IniSettings(stderr_report=AMBIGUOUS_CR_ERROR * RS274_INI_LOOKUPS)
    settings = settings_from(IniFile.parse(text))
    if "\r" in text:
        report = DOS_LINE_ENDINGS_WARNING + settings.stderr_report
        settings = settings._replace(stderr_report=report)
    return settings


def settings_from(ini: IniFile) -> IniSettings:
    """The settings an INI file's contents give."""
    report = []

    def integer(key: str, section: str) -> int:
        value = ini.find(key, section)
        return int(value) if value is not None and _INTEGER.fullmatch(value) else 0

    def number(key: str, section: str, default: float) -> float:
        value = ini.find(key, section)
        return (
            float(value) if value is not None and _FLOAT.fullmatch(value) else default
        )

    def tolerance(key: str, low: float, high: float) -> float:
        value = ini.find(key, "RS274NGC")
        if value is None:
            return high
        if _FLOAT.fullmatch(value) and low <= float(value) <= high:
            return float(value)
        report.append(f"invalid [RS274NGC]{key} in INI file\n\n")
        return high

    def flag(key: str, section: str, default: bool) -> bool:
        # rs274 reads these with boost::lexical_cast<bool>: "0" or "1" only.
        value = ini.find(key, section)
        return value == "1" if value in ("0", "1") else default

    def rotary(key: str, read) -> tuple:
        return tuple(read(ini.find(key, f"AXIS_{axis}")) for axis in "ABC")

    # Keys are read in rs274's order, so the stderr report comes out in order.
    settings = IniSettings(
        tool_change_at_g30=bool(integer("TOOL_CHANGE_AT_G30", "EMCIO")),
        tool_change_quill_up=bool(integer("TOOL_CHANGE_QUILL_UP", "EMCIO")),
        tool_change_with_spindle_on=bool(
            integer("TOOL_CHANGE_WITH_SPINDLE_ON", "EMCIO")
        ),
        wrapped_rotary=rotary("WRAPPED_ROTARY", _wraps),
        random_toolchanger=bool(integer("RANDOM_TOOLCHANGER", "EMCIO")),
        num_spindles=_lexical_int(ini.find("SPINDLES", "TRAJ"), 1),
        features=integer("FEATURES", "RS274NGC"),
        ini_vars=flag("INI_VARS", "RS274NGC", True),
        retain_g43=flag("RETAIN_G43", "RS274NGC", False),
        oword_nargs=flag("OWORD_NARGS", "RS274NGC", False),
        indexer_joints=rotary("LOCKING_INDEXER_JOINT", _atol_int),
        orient_offset=number("ORIENT_OFFSET", "RS274NGC", 0.0),
        program_prefix=_existing_dir(ini.find("PROGRAM_PREFIX", "DISPLAY")),
        subroutine_path=_subroutine_dirs(ini.find("SUBROUTINE_PATH", "RS274NGC")),
        center_arc_radius_tolerance_inch=tolerance(
            "CENTER_ARC_RADIUS_TOLERANCE_INCH",
            MIN_CENTER_ARC_RADIUS_TOLERANCE_INCH,
            CENTER_ARC_RADIUS_TOLERANCE_INCH,
        ),
        center_arc_radius_tolerance_mm=tolerance(
            "CENTER_ARC_RADIUS_TOLERANCE_MM",
            MIN_CENTER_ARC_RADIUS_TOLERANCE_MM,
            CENTER_ARC_RADIUS_TOLERANCE_MM,
        ),
        disable_g92_persistence=bool(integer("DISABLE_G92_PERSISTENCE", "RS274NGC")),
        disable_fanuc_style_sub=bool(integer("DISABLE_FANUC_STYLE_SUB", "RS274NGC")),
        ini=ini,
    )
    return settings._replace(stderr_report="".join(report))


#: What C's atol reads: blanks, a sign and digits, the rest ignored.
_ATOL = Pattern(r"[ \t\n\v\f\r]*([+-]?\d+)")


def _atol_int(value: Optional[str]) -> int:
    """``(int) atol(value)``: the leading number (0 when there is none),
    held at the range of a long, then cut to an int's 32 bits."""
    if value is None:
        return NO_INDEXER  # the key absent: rs274 keeps its default
    match = _ATOL.match(value)
    number = int(match.group(1)) if match else 0
    number = max(-(2**63), min(2**63 - 1, number))
    number &= 0xFFFFFFFF
    return number - 2**32 if number >= 2**31 else number


#: The range of a C int (boost::lexical_cast<int> refuses anything past it).
_INT_RANGE = range(-(2**31), 2**31)


def _lexical_int(value: Optional[str], default: int) -> int:
    """An INI int as boost::lexical_cast<int> reads it: a plain integer in
    range, or the default (silently)."""
    if value is None or not _INTEGER.fullmatch(value):
        return default
    number = int(value)
    return number if number in _INT_RANGE else default


def _wraps(value: Optional[str]) -> bool:
    """WRAPPED_ROTARY, an int setting (lexical_cast) read as a truth value."""
    return bool(_lexical_int(value, 0))


def _existing_dir(entry: Optional[str]) -> Optional[str]:
    """rs274's realpath() of a path entry: None if it does not exist."""
    if not entry:
        return None
    path = os.path.realpath(
        os.path.expanduser(entry) if entry.startswith("~/") else entry
    )
    return path if os.path.exists(path) else None


def _subroutine_dirs(value: Optional[str]) -> Tuple[str, ...]:
    if value is None:
        return ()
    dirs = [d for d in (_existing_dir(entry) for entry in value.split(":")) if d]
    return tuple(dirs[:MAX_SUBROUTINE_DIRS])


#: What boost::lexical_cast<double> accepts (how rs274 reads an INI number).
_LEXICAL_DOUBLE = Pattern(
    r"(?i)[+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf(?:inity)?|nan)"
)


def ini_parameter(ini: IniFile, name: str) -> Optional[float]:
    """The value of ``#<_ini[SECTION]KEY>`` (``name`` as the program spells
    it, lower case), or None when rs274 would find no number.

    Section and key are looked up in upper case; the shortest form is
    ``_ini[s]k``. A value that is not a number counts as not found.
    """
    close = name.find("]", 6)
    if len(name) <= 7 or close < 0:
        return None
    upper = name.upper()
    value = ini.find(upper[close + 1 :], upper[5:close])
    if value is None or not _LEXICAL_DOUBLE.fullmatch(value):
        return None
    return float(value)
