"""Loading a program's generated module: the one step every workflow (the
``run`` command, ``ngc2py.parse``, stats, flatten, golden checks) shares.

It lives apart from the command line so that the Python APIs import no
argument parser: ``ngc2py.parse`` is timed against ``gcode.parse``, which
a GUI calls for every file it previews.
"""

from __future__ import annotations

import os

from ngc2py.compiler import OpenError, compile_file
from runtime.errors import SourceMap

TYPE_CHECKING = False  # the run path imports this: no typing
if TYPE_CHECKING:
    from typing import Optional


def load_module(path: str):
    """Import a generated module from ``path`` under a private name."""
    from ngc2py.bytecode import QuickLoader

    return QuickLoader("ngc2py_program", str(path)).load()


def load_program(program: str, ini: Optional[str], block_delete: bool = False):
    """The generated module for ``program`` (to run with block delete
    ``block_delete``): from the cache, or compiled in a temporary directory
    when the cache cannot be written (or keeps losing the entry)."""
    from ngc2py.cache import cached_module, load_cached
    from ngc2py.stdin import STDIN, compile_stdin

    if program == STDIN:
        return load_text(compile_stdin(ini, block_delete))
    try:
        for _ in range(2):
            try:
                return load_cached(cached_module(program, ini, block_delete), program)
            except FileNotFoundError:
                # the entry went between finding and loading it (another
                # run swept the cache: ngc2py/cache_sweep.py): compiled again
                continue
    except PermissionError:
        pass
    return load_text(compile_file(program, ini, block_delete))


def load_text(text: str):
    """Import generated module ``text`` through a temporary file."""
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "program.py")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(text)
        return load_module(path)


def unopened(program: str, error: OpenError) -> SourceMap:
    """The source map of a program rs274 cannot open: running it only
    reports ``error`` after the start-up calls, as rs274 does."""
    return SourceMap((program,), "", ("",), open_error=(error.rs274_message, 0))
