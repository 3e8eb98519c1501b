"""Reading a G-code file into physical lines exactly as rs274 reads it.

rs274 reads with ``fgets`` into a 255-byte buffer, so everything here works
on bytes first:

* lines end at ``\\n`` only (a lone ``\\r`` is not a line break; it is
  dropped later like a blank);
* a line that fills the buffer (254 bytes, counting its ``\\n``) is
  "Command too long"; only the first 254 bytes are echoed;
* a NUL byte ends the line's text (C strings);
* trailing white space (C ``isspace``) is removed before anything else.

Bytes are decoded as UTF-8 with ``surrogateescape`` so text round-trips to
the exact original bytes (``encode("utf-8", "surrogateescape")``) while valid
UTF-8 stays readable in the generated Python.
"""

from __future__ import annotations

from collections import namedtuple

# typing is for the checker only: importing it costs a conversion 5 ms
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Iterator, Tuple

#: fgets reads at most this many bytes of one line (LINELEN - 1 in rs274);
#: a chunk of exactly this length means the line did not fit.
LINE_LIMIT = 254

COMMAND_TOO_LONG = "Command too long"

#: C's isspace in the "C" locale.
C_SPACE = b" \t\n\v\f\r"


class RawLine(namedtuple("RawLine", "number text too_long", defaults=(False,))):
    """One line as rs274's read_text sees it, before any normalisation:
    its ``number`` (1-based), its ``text`` (trailing white space removed:
    what rs274 echoes on error), and whether it was ``too_long``."""

    __slots__ = ()


def decode(data: bytes) -> str:
    """Bytes -> str losslessly (see module docstring)."""
    return data.decode("utf-8", "surrogateescape")


def encode(text: str) -> bytes:
    """The inverse of :func:`decode`: the bytes rs274 would print.

    Text that did not come from :func:`decode` may hold other lone
    surrogates; they are kept as their (invalid) UTF-8 bytes.
    """
    try:
        return text.encode("utf-8", "surrogateescape")
    except UnicodeEncodeError:
        return text.encode("utf-8", "surrogatepass")


def first_byte(char: str) -> int:
    """The first byte of ``char`` in the file: what a C ``char`` loop sees."""
    return encode(char)[0]


def split_lines(data: bytes) -> Iterator[RawLine]:
    """Yield the lines of a file the way rs274's fgets loop meets them."""
    pos, number = 0, 0
    while pos < len(data):
        number += 1
        raw, pos = read_line(data, pos, number)
        yield raw


def read_line(data: bytes, pos: int, number: int) -> Tuple[RawLine, int]:
    """The line ``number`` starting at ``pos`` (``pos < len(data)``), and
    where the next one starts."""
    newline = data.find(b"\n", pos, pos + LINE_LIMIT)
    end = newline + 1 if newline != -1 else min(len(data), pos + LINE_LIMIT)
    chunk = data[pos:end].split(b"\0", 1)[0]
    if len(chunk) == LINE_LIMIT:
        # rs274 discards the rest of the physical line before failing.
        if not chunk.endswith(b"\n"):
            rest = data.find(b"\n", end)
            end = len(data) if rest == -1 else rest + 1
        return RawLine(number, decode(chunk.rstrip(b"\n")), too_long=True), end
    return RawLine(number, decode(chunk.rstrip(C_SPACE))), end


def read_file(path: str) -> bytes:
    """The file's bytes; OSError propagates (a compile-time failure)."""
    with open(path, "rb") as handle:
        return handle.read()
