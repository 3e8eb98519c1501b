"""Numbered-parameter files (``rs274 -v FILE``), read and written as rs274 2.9 does.

Reading (`read_parameter_file`): each line that C's ``sscanf("%d %lf")``
accepts sets a parameter (``100.5 3`` reads as #100 = 0.5, like C); other
lines are ignored. Numbers must be 1..5601 ("Parameter number out of
range") and strictly increasing ("Parameter file out of order"); a missing
file is not an error. Parameters not in the file are 0.

Starting a run (`initial_parameters`): rs274 then forces #5220 (the active
coordinate system) to 1 unless it selects G54..G59.3, sets #5599 (the
switch for (DEBUG,...) output) to 1, saves the file
(`save_parameter_file`), and clears the current-tool parameters #5400-#5413
and the tool-changer fault parameters #5600-#5601.

Saving (`save_parameter_file`, at start-up and when rs274 exits, even after an
error): the file keeps exactly the parameters it lists plus the required ones
(`REQUIRED_PARAMETERS`), each written as ``"%d\\t%f\\n"`` with its current
value; the previous file becomes ``FILE.bak``.

Without ``-v`` rs274 reads and writes DEFAULT_PARAMETER_FILE, a path that
LinuxCNC 2.9 packages do not create, so it starts from `default_parameters`
and its saves fail silently; ngc2py does not touch that path.
"""

from __future__ import annotations

import os
import sys

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Dict, Iterable, Mapping, Optional, TextIO

from runtime.errors import GCodeError
from runtime.tooltable import scan_c_float, scan_c_int

#: The file rs274 uses when no -v is given.
DEFAULT_PARAMETER_FILE = "/etc/emc2/sample-configs/sim/sim.var"

#: Parameter numbers must be below this.
MAX_PARAMETERS = 5602

BACKUP_SUFFIX = ".bak"

#: rs274 writes the new file under this suffix, then renames it.
NEW_SUFFIX = ".new"


def _block(first: int, last: int) -> Iterable[int]:
    return range(first, last + 1)


#: Always written to the file: the G28/G30 home positions (#5161-#5169,
#: #5181-#5189), G92 state and offsets (#5210-#5219), the coordinate-system
#: index (#5220) and the nine coordinate systems G54..G59.3 (#5221-#5230,
#: ..., #5381-#5390: X Y Z A B C U V W and XY rotation).
REQUIRED_PARAMETERS = tuple(
    [*_block(5161, 5169), *_block(5181, 5189), *_block(5210, 5220)]
    + [n for system in range(9) for n in _block(5221 + 20 * system, 5230 + 20 * system)]
)

#: Cleared when a run starts (after the start-up save): the loaded tool's
#: data and the tool-changer fault state.
CLEARED_AT_START = (*_block(5400, 5413), 5600, 5601)


#: Set when a run starts, whatever the file says: (DEBUG,...) output on.
DEBUG_SWITCH = 5599


def default_parameters() -> Dict[int, float]:
    """Initial non-zero parameters of a run without ``-v``."""
    return {5220: 1.0, DEBUG_SWITCH: 1.0}


def read_parameter_file(path: str) -> Dict[int, float]:
    """The parameters a file sets, by number; {} if the file does not exist.

    Raises GCodeError with rs274's message for a bad file.
    """
    if not os.path.exists(path):
        return {}
    if os.path.isdir(path):
        return {}  # rs274's fopen opens a folder; reading it just ends
    try:
        with open(path, "rb") as f:
            text = f.read().decode("latin-1")
    except OSError:
        raise GCodeError(f"Unable to open parameter file: '{path}'") from None
    return _parse(text)


def initial_parameters(
    path: Optional[str], stderr: Optional[TextIO] = None
) -> Dict[int, float]:
    """The parameters a run starts with, doing what rs274's start-up does.

    ``path`` is the ``-v`` file (None: no -v, see `default_parameters`). The
    file is read, #5220 is repaired, #5599 set to 1, the file is saved (normalised, old copy
    to ``.bak``) and #5400-#5413, #5600-#5601 are cleared. Returns only the
    non-zero parameters; every other parameter starts at 0. Complaints
    about the save go to ``stderr`` (default sys.stderr).
    """
    if path is None:
        return default_parameters()
    values = read_parameter_file(path)
    if not 1 <= int(values.get(5220, 0.0) + 0.0001) <= 9:
        values[5220] = 1.0
    values[DEBUG_SWITCH] = 1.0
    save_parameter_file(path, values, stderr)
    for number in CLEARED_AT_START:
        values.pop(number, None)
    return {n: v for n, v in values.items() if v != 0.0}


def save_parameter_file(
    path: str, values: Mapping[int, float], stderr: Optional[TextIO] = None
) -> None:
    """Rewrite ``path`` with the current ``values`` the way rs274 does.

    The new file lists the parameters the existing file lists plus
    REQUIRED_PARAMETERS, ascending; numbers missing from ``values`` are 0.
    As rs274 does, the text goes to ``path + ".new"`` (created like any
    file, 0666 & ~umask), the previous file is hard-linked to ``path +
    ".bak"`` and ``.new`` is renamed over ``path``, so ``path`` always holds
    a complete file. A failing link or rename is reported on ``stderr``
    (default sys.stderr) as rs274's perror reports it, and the run goes on
    (a failed rename leaves ``.new`` behind, as rs274 does); a folder where
    ``.new`` cannot be created is silently left alone.
    """
    stderr = stderr or sys.stderr
    listed = set(read_parameter_file(path)) | set(REQUIRED_PARAMETERS)
    text = "".join(f"{n}\t{values.get(n, 0.0):f}\n" for n in sorted(listed))
    temporary = path + NEW_SUFFIX
    try:
        with open(temporary, "w", encoding="latin-1", newline="") as f:
            f.write(text)
    except OSError:
        return  # rs274 cannot write there either, and says nothing
    _report(stderr, "link", _backup(path))
    try:
        os.rename(temporary, path)
    except OSError as error:
        _report(stderr, "rename", error)


def _backup(path: str) -> Optional[OSError]:
    """Make ``path.bak`` a hard link to ``path`` (the link itself when it is
    a symlink, as C's link does); return the error if that fails."""
    backup = path + BACKUP_SUFFIX
    try:
        if os.path.lexists(backup):
            os.unlink(backup)
        os.link(path, backup, follow_symlinks=False)
    except OSError as error:
        return error
    return None


def _report(stderr: TextIO, step: str, error: Optional[OSError]) -> None:
    """perror's line for a failed step of rs274's update."""
    if error is not None:
        stderr.write(f"{step} (updating variable file): {os.strerror(error.errno)}\n")


def _parse(text: str) -> Dict[int, float]:
    values: Dict[int, float] = {}
    last = 0
    for line in text.split("\n"):
        scanned = _scan_line(line)
        if scanned is None:
            continue
        number, value = scanned
        if not 0 < number < MAX_PARAMETERS:
            raise GCodeError("Parameter number out of range")
        if number <= last:
            raise GCodeError("Parameter file out of order")
        values[number] = value
        last = number
    return values


def _scan_line(line: str):
    """``sscanf(line, "%d %lf")``: (number, value) or None."""
    number = scan_c_int(line)
    if number is None:
        return None
    value = scan_c_float(line[number[1] :])
    if value is None:
        return None
    return number[0], value[0]
