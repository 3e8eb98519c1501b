"""``sinl``/``cosl``/``tanl`` from the C library, on rs274's long double radians.

(Where the optional C extension ``runtime._libm_trig`` was built, its
functions are used instead: the same computation, written in C as rs274
writes it, without Python forming the radians. See :func:`trig_functions`.)

rs274 computes ``SIN[d]`` as ``sinl((d * M_PIl) / 180.0)`` in 80-bit x87
arithmetic and stores the result into a double. :mod:`runtime.ops` emulates
that exactly with integers, at about 16 us a call. This module is the fast
path: the radians are still formed exactly with integers (two roundings to a
64-bit significand, as the x87 does), packed into the 80-bit format, and
handed to the very ``sinl`` rs274 calls through :mod:`ctypes`; converting the
returned long double to a Python float is the same rounding as rs274's store
into a double. About 1.5 us a call.

The fast path is used only where ``c_longdouble`` is the x87 format and the
library's answers agree with the integer emulation on a set of probe angles
(checked once, at a program's first SIN, COS or TAN); otherwise
:mod:`runtime.ops` keeps its emulation.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import struct

from runtime.ops import round_bits

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Callable, Optional, Tuple

#: The 80-bit format: 64-bit significand (explicit leading bit) and a 15-bit
#: exponent biased by 16383, sign on top, padded to 16 bytes on x86-64.
_BIAS = 16383
_PACK = struct.Struct("<QH6x").pack


class _LongDouble(ctypes.c_longdouble):
    """A subclass, so ctypes passes our raw bytes instead of converting a float."""


def _libm_functions() -> Optional[Tuple[Callable, Callable, Callable]]:
    if ctypes.sizeof(ctypes.c_longdouble) != 16:
        return None
    name = ctypes.util.find_library("m")
    try:
        libm = ctypes.CDLL(name)
        functions = []
        for fname in ("sinl", "cosl", "tanl"):
            fn = getattr(libm, fname)
            fn.restype = ctypes.c_longdouble  # converted to a float: rs274's store
            fn.argtypes = [_LongDouble]
            functions.append(fn)
    except (OSError, AttributeError, TypeError):
        return None
    return tuple(functions)


def make_radians(pi_significand: int, pi_exponent: int) -> Callable[[float], object]:
    """A function: degrees (a non-zero double) -> rs274's long double radians.

    ``pi_significand * 2**pi_exponent`` is ``M_PIl`` (64-bit significand).
    Both roundings are to nearest, ties to even, on 64 bits.
    """
    from_bytes = _LongDouble.from_buffer_copy
    # SIN[a] and COS[a] of one angle often come together: keep the last one.
    last = [None, None]

    def radians(degrees: float):
        if degrees == last[0]:
            return last[1]
        num, den = degrees.as_integer_ratio()
        negative = num < 0
        if negative:
            num = -num
        exponent = pi_exponent - den.bit_length() + 1
        # d * M_PIl, rounded to 64 bits
        product = num * pi_significand
        shift = product.bit_length() - 64
        if shift > 0:
            q, shift = round_bits(product, 64)
        else:
            q = product << -shift
        exponent += shift
        # ... / 180.0, rounded to 64 bits (the quotient has 128 or 129 bits)
        quotient, remainder = divmod(q << 72, 180)
        shift = quotient.bit_length() - 64
        low = quotient & ((1 << shift) - 1)
        quotient >>= shift
        half = 1 << (shift - 1)
        if low > half or (low == half and (remainder or quotient & 1)):
            quotient += 1
            if quotient >> 64:
                quotient >>= 1
                shift += 1
        exponent += shift - 72
        biased = exponent + 63 + _BIAS
        if not 0 < biased < 0x7FFF:
            return None  # beyond what a double's degrees can give: not expected
        value = from_bytes(_PACK(quotient, biased | (negative << 15)))
        last[0], last[1] = degrees, value
        return value

    return radians


def trig_functions(
    pi_significand: int, pi_exponent: int, reference, use_extension: bool = True
) -> Optional[dict]:
    """``{"sin": f, "cos": f, "tan": f}`` computing through the C library, or
    None when this platform's long double cannot do it exactly.

    The optional C extension ``runtime._libm_trig`` (setup.py) when it was
    built, else ctypes. ``reference(degrees, name)`` is the integer
    emulation; the library must agree with it on sin and cos of ordinary
    probe angles or the fast path is not used. (Not on tan: rs274's tanl is
    not always correctly rounded, and the library, not the emulation, is
    what rs274 prints.)
    """
    made = _extension_functions() if use_extension else None
    if made is None:
        functions = _libm_functions()
        if functions is None:
            return None
        radians = make_radians(pi_significand, pi_exponent)
        made = {
            name: _wrap(name, fn, radians, reference)
            for name, fn in zip(("sin", "cos", "tan"), functions)
        }
    from runtime.ops import library_agrees

    return made if library_agrees(made, reference) else None


def _extension_functions() -> Optional[dict]:
    """The C extension's functions (rs274's very expression, compiled), or
    None where it was not built."""
    try:
        from runtime import _libm_trig
    except ImportError:
        return None
    return {"sin": _libm_trig.sin, "cos": _libm_trig.cos, "tan": _libm_trig.tan}


def _wrap(name: str, libm_fn, radians, reference) -> Callable[[float], float]:
    def compute(degrees: float) -> float:
        # Zero keeps its sign (sin, tan) or gives exactly 1 (cos); the
        # emulation handles that and the extreme exponents.
        if degrees == 0.0:
            return reference(degrees, name)
        value = radians(degrees)
        if value is None:
            return reference(degrees, name)
        return libm_fn(value)

    compute.__name__ = name
    return compute
