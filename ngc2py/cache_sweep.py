"""Keeping the compile cache to a size: the entries used least recently go.

Every program compiled adds an entry (ngc2py/cache.py), and a program that
changes, a CAM tool's fresh output, or a new compiler (which keys every
program anew) adds more: left alone, the cache of a shop that runs its
library every night grows without end. So after a miss has written its
entry, now and then (at most once every :data:`INTERVAL` seconds, told by
the mtime of a stamp file) the cache is swept, by a process of its own that
no run waits for: when its entries together are larger than the limit, the
least recently used go until they fill :data:`AFTER` of it.

An entry's last use is the mtime of its ``.json`` file, which a hit touches
(the module's own mtime stays: its bytecode is checked against it). An
entry used within the last :data:`GRACE` seconds is never removed, so a run
that has just found one finds it still there to load; a run that loses
that race anyway compiles the program again (ngc2py/loading.py). The limit
is ``$NGC2PY_CACHE_SIZE`` (bytes, or with K, M, G: ``500M``; ``0`` for no
limit), :data:`DEFAULT_SIZE` otherwise.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys

from ngc2py.cache import SIZE_ENV
from ngc2py.compiler import CompileError

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Dict, List, Optional

DEFAULT_SIZE = 1 << 30
#: A sweep leaves the entries filling this much of the limit (so that the
#: next misses do not each find it over again).
AFTER = 0.8
#: Seconds between sweeps, and the age of an entry (or of a left-over
#: temporary file) below which it is never removed.
INTERVAL = 3600.0
GRACE = 600.0
#: Entries removed by one sweep, at most (a few thousand files: a second or
#: two); a cache further over its limit is swept again by a miss
#: :data:`AGAIN` seconds later, not an interval later (a cache grown large
#: before it had a limit shrinks a sweep at a time).
MOST = 2000
AGAIN = 60.0
STAMP = ".swept"

_SIZE = re.compile(r"\s*(\d+(?:\.\d*)?)\s*([kKmMgG]?)[bB]?\s*")
_UNITS = {"": 1, "k": 1 << 10, "m": 1 << 20, "g": 1 << 30}
#: m_<key>.py, m_<key>_<probes>.py, m_<key>.json, and their bytecode
_ENTRY_FILE = re.compile(r"m_([0-9a-f]{64})(?:_[0-9a-f]+)?[.]")


class SizeError(CompileError):
    """``$NGC2PY_CACHE_SIZE`` is not a size."""


def size_limit() -> int:
    """The limit in bytes (0: none)."""
    text = os.environ.get(SIZE_ENV, "")
    if not text.strip():
        return DEFAULT_SIZE
    match = _SIZE.fullmatch(text)
    if match is None:
        raise SizeError(
            "%s=%r: not a size (bytes, or e.g. 500M, 2G; 0 for no limit)"
            % (SIZE_ENV, text)
        )
    return int(float(match.group(1)) * _UNITS[match.group(2).lower()])


def maybe_sweep(folder: str, limit: int) -> Optional[subprocess.Popen]:
    """Sweep ``folder`` to ``limit`` bytes (0: none) if the last sweep is
    :data:`INTERVAL` old; called just after an entry was written into it.
    A cache without a stamp yet (new, or older than sweeps) is stamped,
    and swept an interval later. The sweep runs in a process of its own,
    not waited for (as ``git gc --auto`` does): reading the sizes of tens
    of thousands of files took a run 3 to 5 s. Returns that process (None:
    no sweep). Never fails a run: a cache that cannot be swept is left.
    Times are the cache's file system's, which its mtimes are in (a
    network share's clock may not be this machine's): the folder's mtime
    is the moment the entry went in."""
    stamp = os.path.join(folder, STAMP)
    try:
        now = os.stat(folder).st_mtime
        if now - os.stat(stamp).st_mtime < INTERVAL:
            return None
        due = True
    except FileNotFoundError:
        due = False  # no stamp: counted from now
    except OSError:
        return None
    try:
        with open(stamp, "w"):
            pass  # (first: another run starting now does not sweep too)
    except OSError:
        return None
    if not (due and limit):
        return None
    return _spawn(folder, limit)


def _spawn(folder: str, limit: int) -> Optional[subprocess.Popen]:
    """:func:`main` on ``folder`` in a new process, not waited for."""
    # the package's folder and the arguments are data (argv), never code
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    code = "import sys; sys.path.insert(0, sys.argv[1]); import " + __name__
    code += "; %s.main(sys.argv[2:])" % __name__
    try:
        process = subprocess.Popen(
            [sys.executable, "-c", code, root, folder, str(limit)],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            close_fds=True,
            start_new_session=True,  # (not stopped by the run's Ctrl-C)
        )
    except OSError:
        return None
    # kept, so that a long-lived process (a library's golden check) reaps
    # it rather than dropping it running (Python's ResourceWarning)
    _RUNNING[:] = [p for p in _RUNNING if p.poll() is None] + [process]
    return process


#: The sweeps this process started that may still run.
_RUNNING: List[subprocess.Popen] = []


def main(argv: List[str]) -> None:
    """The sweep's own process: ``FOLDER LIMIT``. When it removed all it
    may (:data:`MOST`), the stamp is set for another sweep soon."""
    folder, limit = argv[0], int(argv[1])
    stamp = os.path.join(folder, STAMP)
    try:
        now = os.stat(stamp).st_mtime
        if len(sweep(folder, limit, now)) == MOST:
            soon = now - INTERVAL + AGAIN  # (more to do)
            os.utime(stamp, (soon, soon))
    except OSError:
        pass


def sweep(folder: str, limit: int, now: float) -> List[str]:
    """Remove the least recently used entries of ``folder`` (at most
    :data:`MOST`) while they are over ``limit`` bytes on disk, down to
    :data:`AFTER` of it, and temporary files a crashed write left; returns
    the keys removed."""
    sizes: Dict[str, int] = {}
    used: Dict[str, float] = {}  # an entry's .json's mtime
    newest: Dict[str, float] = {}  # of its newest file
    files: Dict[str, List[str]] = {}
    for where in (folder, os.path.join(folder, "__pycache__")):
        try:
            listing = list(os.scandir(where))
        except OSError:
            continue
        for item in listing:
            try:
                status = item.stat(follow_symlinks=False)
            except OSError:
                continue
            if item.name.startswith(".tmp-"):
                if now - status.st_mtime > GRACE:
                    _remove(item.path)
                continue
            match = _ENTRY_FILE.match(item.name)
            if match is None or not item.is_file(follow_symlinks=False):
                continue
            key = match.group(1)
            sizes[key] = sizes.get(key, 0) + _disk_size(status)
            files.setdefault(key, []).append(item.path)
            if item.name.endswith(".json"):
                used[key] = status.st_mtime
            newest[key] = max(newest.get(key, 0.0), status.st_mtime)
    total = sum(sizes.values())
    removed: List[str] = []
    if total <= limit:
        return removed
    # an entry without its .json (being written, or bytecode left behind)
    # was last used when its newest file was written
    last = {key: used.get(key, newest[key]) for key in sizes}
    for key in sorted(last, key=last.__getitem__):
        if total <= limit * AFTER or len(removed) == MOST:
            break
        if now - last[key] < GRACE:
            break  # the rest were used as recently
        for path in sorted(files[key], key=lambda path: path.endswith(".json")):
            _remove(path)  # (the .json last: the entry is gone when it is)
        total -= sizes[key]
        removed.append(key)
    return removed


def _disk_size(status: os.stat_result) -> int:
    """What a file takes on disk: its blocks where the system says (a small
    module takes a whole block), else its size."""
    blocks = getattr(status, "st_blocks", None)
    return status.st_size if blocks is None else blocks * 512


def _remove(path: str) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass
