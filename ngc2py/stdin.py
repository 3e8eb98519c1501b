"""A G-code program given as ``-``: read from standard input.

The program is compiled from the bytes read (no cache: there is no file to
key it by) under the name ``<stdin>``, which is what error locations show.
External subroutines are still looked for in the current directory.
"""

from __future__ import annotations

import sys

TYPE_CHECKING = False  # the run path imports this: no typing
if TYPE_CHECKING:
    from typing import Optional

STDIN = "-"
NAME = "<stdin>"


def read_stdin() -> bytes:
    stream = getattr(sys.stdin, "buffer", sys.stdin)
    data = stream.read()
    return data.encode("utf-8", "surrogateescape") if isinstance(data, str) else data


def compile_stdin(ini: Optional[str] = None, block_delete: bool = False) -> str:
    """The generated module text for the program on standard input."""
    from ngc2py import parser
    from ngc2py.compiler import _compile

    parsed = parser.parse_text(read_stdin(), NAME, runs=True)
    return _compile(parsed, NAME, ini, block_delete).text
