"""LinuxCNC tool table files (``rs274 -t FILE``), read the way rs274 2.9 reads them.

A line is ``T<n> P<n> [X Y Z A B C U V W D I J <float>] [Q<int>] [;comment]``
with words separated by spaces. Facts about rs274's reader this reproduces:

* Words are split on spaces only; each word's number is read like C's
  ``sscanf`` (leading white space skipped, the longest numeric prefix used,
  trailing junk ignored: ``T7.5`` is tool 7, ``T7P9`` is tool 7 with no P).
* A line whose first character is ``;``, or with at most one character
  before its first ``;``, is ignored.
* Any unknown word, or a word without a number, rejects the whole line;
  rs274 then prints ``File: <path> Unrecognized line skipped:`` and the raw
  line (newline included, if it had one) on **stdout**, before the trace.
* rs274 runs a non-random tool changer: the n-th line that has a P word goes
  to table index n (1, 2, ...) whatever its P value; ``CHANGE_TOOL`` prints
  that index. A line without a P word goes to index 0, the spindle.
  After each line, if the spindle holds the same tool number, the spindle
  entry is replaced by the new one.
* Looking a tool up searches indices 1, 2, ... first (the first match wins)
  and the spindle (index 0) last.
* Offsets and diameters are stored as written (rs274 treats table values as
  inches when it applies them; that conversion is the machine's business).
* A table file that cannot be opened gives an empty table, silently.
"""

from __future__ import annotations

from collections import namedtuple

from runtime.lazy_re import Pattern

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, Optional, Tuple

#: Where rs274 2.9 reads its tool table from when no ``-t`` is given: the
#: "common" sample configuration's tool.tbl that ships with LinuxCNC.
DEFAULT_TOOL_TABLE_PATH = (
    "/usr/share/doc/linuxcnc/examples/sample-configs/common/tool.tbl"
)

#: Offset word letters, in the order of ToolEntry.offsets.
OFFSET_AXES = "XYZABCUVW"

_C_INT = Pattern(r"[ \t\n\v\f\r]*([+-]?\d+)")
_C_FLOAT = Pattern(
    r"(?i)[ \t\n\v\f\r]*([+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf(?:inity)?|nan))"
)


class ToolEntry(
    namedtuple(
        "ToolEntry",
        "tool pocket offsets diameter frontangle backangle orientation comment",
        defaults=(-1, -1, (0.0,) * len(OFFSET_AXES), 0.0, 0.0, 0.0, 0, ""),
    )
):
    """One tool: its number, pocket (the P word as written) and data;
    ``offsets`` in X Y Z A B C U V W order."""

    __slots__ = ()

    def offset(self, axis: str) -> float:
        """The offset for one axis letter (``"z"`` or ``"Z"``)."""
        return self.offsets[OFFSET_AXES.index(axis.upper())]


class ToolTable(namedtuple("ToolTable", "slots load_report")):
    """Tool entries by table index (0 is the spindle), plus load messages.

    ``load_report`` is what rs274 prints on stdout while reading the file
    (before the first trace line); usually empty.
    """

    __slots__ = ()

    def __new__(cls, slots: Optional[Dict[int, ToolEntry]] = None, load_report=""):
        return super().__new__(cls, {} if slots is None else slots, load_report)

    def find(self, tool: int) -> Optional[int]:
        """The table index of ``tool`` as rs274 looks it up, or None."""
        for index in sorted(self.slots, key=lambda i: (i == 0, i)):
            if self.slots[index].tool == tool:
                return index
        return None

    def with_spindle(self, index: int) -> "ToolTable":
        """The table after a tool change loads the entry at ``index``.

        rs274 copies the loaded tool into index 0, replacing whatever a
        P-less table line had put there (that tool can no longer be found).
        """
        return self._replace(slots={**self.slots, 0: self.slots[index]})

    def lookup(self, tool: int) -> Optional[ToolEntry]:
        """The entry rs274 uses for ``tool``, or None if it is not in the table."""
        index = self.find(tool)
        return None if index is None else self.slots[index]


def load_tool_table(path: str) -> ToolTable:
    """Read the tool table file ``path`` (named in messages exactly as given)."""
    try:
        with open(path, "rb") as f:
            data = f.read().decode("latin-1")
    except OSError:
        return ToolTable()
    return parse_tool_table(data, path)


def tool_table_for(path: Optional[str]) -> ToolTable:
    """The table rs274 reads for ``-t path``, or its default without one."""
    return default_tool_table() if path is None else load_tool_table(path)


def parse_tool_table(text: str, path: str) -> ToolTable:
    """Parse tool table ``text``; ``path`` is only used in the load report."""
    slots: Dict[int, ToolEntry] = {}
    report = []
    next_index = 1
    for line in _c_lines(text):
        scan = scan_tool_line(line)
        if scan is None:
            continue
        # Every valid P word takes the next index (the last one wins), even
        # on a line that is then rejected.
        index = next_index + scan.pocket_words - 1 if scan.pocket_words else 0
        next_index += scan.pocket_words
        if scan.entry is None:
            report.append(f"File: {path} Unrecognized line skipped:\n    {line}")
            continue
        slots[index] = scan.entry
        spindle = slots.get(0)
        if spindle is not None and spindle.tool == scan.entry.tool:
            slots[0] = scan.entry
    return ToolTable(slots, "".join(report))


class LineScan(namedtuple("LineScan", "entry pocket_words")):
    """A tool table line rs274 does not ignore: its entry (None if rs274
    rejects the line) and how many valid P words it has (each uses up a
    table index)."""

    __slots__ = ()


def scan_tool_line(line: str) -> Optional[LineScan]:
    """Read one line as rs274 does; None for a line it ignores."""
    if line.startswith(";"):
        return None
    words, _, rest = line.partition(";")
    if len(words) <= 1:
        return None
    fields = {}
    pocket_words = 0
    valid = True
    for word in (w for w in words.split(" ") if w):
        letter = word[0].upper()
        if letter == "\n":
            continue
        value = _word_value(letter, word[1:])
        if value is None:
            valid = False
        else:
            fields[letter] = value
            pocket_words += letter == "P"
    if not valid:
        return LineScan(None, pocket_words)
    entry = ToolEntry(
        tool=fields.get("T", -1),
        pocket=fields.get("P", 0),
        offsets=tuple(fields.get(axis, 0.0) for axis in OFFSET_AXES),
        diameter=fields.get("D", 0.0),
        frontangle=fields.get("I", 0.0),
        backangle=fields.get("J", 0.0),
        orientation=fields.get("Q", 0),
        comment=rest.split("\n", 1)[0],
    )
    return LineScan(entry, pocket_words)


def _word_value(letter: str, text: str):
    """A word's value read like sscanf (%d or %lf); None if not a valid word."""
    if letter in "TPQ":
        scanned = scan_c_int(text)
    elif letter in OFFSET_AXES or letter in "DIJ":
        scanned = scan_c_float(text)
    else:
        return None
    return None if scanned is None else scanned[0]


def scan_c_int(text: str) -> Optional[Tuple[int, int]]:
    """C's sscanf "%d" at the start of ``text``: (value, end offset) or None."""
    match = _C_INT.match(text)
    return None if match is None else (int(match.group(1)), match.end())


def scan_c_float(text: str) -> Optional[Tuple[float, int]]:
    """C's sscanf "%lf" at the start of ``text``: (value, end offset) or None."""
    match = _C_FLOAT.match(text)
    return None if match is None else (float(match.group(1)), match.end())


def _c_lines(text: str):
    """Split like repeated fgets: only "\n" ends a line, and it is kept."""
    parts = text.split("\n")
    lines = [part + "\n" for part in parts[:-1]]
    if parts[-1]:
        lines.append(parts[-1])
    return lines


def default_tool_table() -> ToolTable:
    """The table rs274 uses without ``-t``.

    rs274 reads DEFAULT_TOOL_TABLE_PATH, which ships with LinuxCNC's
    documentation; its tools are reproduced here so generated programs
    behave the same on machines without LinuxCNC installed. (Its comments
    are left out: nothing rs274 prints depends on them.)
    """
    entries = [
        ToolEntry(tool=1, pocket=1, diameter=0.125),
        ToolEntry(tool=2, pocket=2, diameter=0.0625),
        ToolEntry(tool=3, pocket=3, diameter=0.201),
        ToolEntry(tool=99999, pocket=123),
    ]
    lengths = [0.511, 0.1, 1.273, 0.1]
    slots = {
        index: entry._replace(offsets=_z_offsets(length))
        for index, (entry, length) in enumerate(zip(entries, lengths), start=1)
    }
    return ToolTable(slots)


def _z_offsets(z: float) -> Tuple[float, ...]:
    return tuple(z if axis == "Z" else 0.0 for axis in OFFSET_AXES)
