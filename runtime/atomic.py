"""What a file written atomically (a temporary file renamed over it) keeps.

A temporary file is created private (0600); renamed over its target as it
is, it would change the target's mode, or give a new file a mode that a
plain ``open(path, "w")`` (rs274's fopen) would not. And only a regular
file (or a new one) is replaced: a device or a pipe (``-o /dev/null``, a
FIFO a reader waits on) is written to, as rs274's fopen writes to it.
"""

from __future__ import annotations

import os
import stat


def special_file(target: str) -> bool:
    """Whether ``target`` is there and not a regular file (a device, a
    pipe, a socket: written to, never replaced)."""
    try:
        return not stat.S_ISREG(os.stat(target).st_mode)
    except OSError:
        return False


def file_mode(target: str) -> int:
    """The mode ``target`` gets: the one it has, or a new file's (0666 less
    the umask), not the private 0600 of a temporary file."""
    try:
        return os.stat(target).st_mode & 0o7777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask
