"""What a file written atomically (a temporary file renamed over it) keeps.

A temporary file is created private (0600); renamed over its target as it
is, it would change the target's mode, or give a new file a mode that a
plain ``open(path, "w")`` (rs274's fopen) would not. And only a regular
file (or a new one) is replaced: a device or a pipe (``-o /dev/null``, a
FIFO a reader waits on) is written to, as rs274's fopen writes to it.

The temporary file is made here (:func:`temporary_beside`), not by
``tempfile``, whose import (with shutil and random) costs a run that writes
its trace to a file 10 to 30 ms, more than the rest of a small run's start.
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


def temporary_beside(target: str, prefix: str = "", suffix: str = ""):
    """A new private (0600) file in ``target``'s folder, named ``prefix``
    (a dot, the target's name and a dot, by default), a random part and
    ``suffix``, with ``tempfile.mkstemp``'s guarantee (made by this call
    alone: ``O_EXCL``): ``(descriptor, path)``."""
    folder, name = os.path.split(os.path.abspath(target))
    prefix = prefix or "." + name + "."
    flags = os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    for _ in range(100):
        path = os.path.join(folder, prefix + os.urandom(6).hex() + suffix)
        try:
            return os.open(path, flags, 0o600), path
        except FileExistsError:
            continue
    raise FileExistsError("no free temporary name beside %s" % target)
