"""G-code operators and functions, computed exactly as rs274 computes them.

Generated code uses Python's ``+ - *`` on floats directly (they are IEEE
double operations, as in rs274) and these helpers for everything else.

Facts measured against rs274 (LinuxCNC 2.9) that shape this module:

* ``EQ``/``NE`` compare within 0.0001 (``abs(a - b) < 0.0001``); ``GT GE LT
  LE`` are plain comparisons with no tolerance.
* ``MOD`` is C ``fmod`` made non-negative by adding ``abs(b)``.
* ``ROUND`` adds +-0.5 and truncates through a C ``int`` (so values beyond
  the int range come out as -2147483648).
* Angles: rs274 converts with the *long double* constant ``M_PIl`` on x86-64,
  and ``SIN COS TAN`` call ``sinl cosl tanl`` on the long double radians.
  That is why ``SIN[30]`` is exactly 0.5 and ``COS[90]`` is -2.5e-20 there,
  where plain double arithmetic gives 0.49999999999999994 and 6.1e-17. The
  80-bit arithmetic is emulated below with exact integer arithmetic.
* rs274 rejects an infinite or NaN value each time it finishes reading an
  operand (a bracketed expression, a function value), not after each binary
  operation: ``[10**400*0]`` fails with 'not a number' while
  ``[[10**400]*0]`` fails with 'infinity'. Hence binary helpers return
  inf/nan like C does, unary helpers check their bracketed argument and their
  result, and generated code wraps other bracketed expressions in
  :func:`finite`.
"""

from __future__ import annotations

import math

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Tuple

from runtime.errors import GCodeError

#: rs274's TOLERANCE_EQUAL, used by EQ and NE.
TOLERANCE_EQUAL = 0.0001

_INT_MIN = -(2**31)


# --------------------------------------------------------------------------
# Checking values
# --------------------------------------------------------------------------


def finite(x: float) -> float:
    """``x`` if it is finite; otherwise rs274's error for an inf/nan operand.

    Generated code applies this to every bracketed expression whose value is
    not already checked (function arguments are checked by the functions).
    """
    if x - x == 0.0:  # false for inf and nan; cheaper than math.isfinite
        return x
    if x != x:
        raise GCodeError("Calculation resulted in 'not a number'")
    raise GCodeError("Calculation resulted in 'infinity'")


def truth(x: float) -> bool:
    """Is a condition true: any non-zero value (no tolerance, as in rs274)."""
    return x != 0.0


def neg(x: float) -> float:
    """Unary minus."""
    return -x


# --------------------------------------------------------------------------
# Binary operators
# --------------------------------------------------------------------------


def div(a: float, b: float) -> float:
    if b == 0.0:
        raise GCodeError("Attempt to divide by zero")
    return a / b


def mod(a: float, b: float) -> float:
    """rs274's MOD: ``fmod`` shifted to be non-negative (``-7 MOD 3 == 2``)."""
    try:
        result = math.fmod(a, b)
    except ValueError:  # an infinite a or a zero b: C's fmod gives NaN
        return math.nan
    if result < 0.0:
        result += abs(b)
    return result


def power(a: float, b: float) -> float:
    if a < 0.0 and not _is_integral(b):
        raise GCodeError("Attempt to raise negative to non integer power")
    return _c_pow(a, b)


def eq(a: float, b: float) -> float:
    return 1.0 if abs(a - b) < TOLERANCE_EQUAL else 0.0


def ne(a: float, b: float) -> float:
    return 1.0 if abs(a - b) >= TOLERANCE_EQUAL else 0.0


def gt(a: float, b: float) -> float:
    return 1.0 if a > b else 0.0


def ge(a: float, b: float) -> float:
    return 1.0 if a >= b else 0.0


def lt(a: float, b: float) -> float:
    return 1.0 if a < b else 0.0


def le(a: float, b: float) -> float:
    return 1.0 if a <= b else 0.0


def and_(a: float, b: float) -> float:
    return 0.0 if a == 0.0 or b == 0.0 else 1.0


def or_(a: float, b: float) -> float:
    return 1.0 if a != 0.0 or b != 0.0 else 0.0


def xor(a: float, b: float) -> float:
    return 1.0 if (a == 0.0) != (b == 0.0) else 0.0


# --------------------------------------------------------------------------
# Unary functions. Each argument is a bracketed expression in G-code, so it
# is checked first; then the domain; then the result.
# --------------------------------------------------------------------------


def abs_(x: float) -> float:
    x = finite(x)
    return -x if x < 0.0 else x  # keeps -0.0, as rs274's ``if (x < 0)`` does


def acos(x: float) -> float:
    x = finite(x)
    if x < -1.0 or x > 1.0:
        raise GCodeError("Argument to acos out of range")
    return _degrees(math.acos(x))


def asin(x: float) -> float:
    x = finite(x)
    if x < -1.0 or x > 1.0:
        raise GCodeError("Argument to asin out of range")
    return _degrees(math.asin(x))


def atan2(y: float, x: float) -> float:
    """``ATAN[y]/[x]``: four-quadrant arc tangent in degrees."""
    return _degrees(math.atan2(finite(y), finite(x)))


def cos(x: float) -> float:
    return _cos(finite(x))


def sin(x: float) -> float:
    return _sin(finite(x))


def tan(x: float) -> float:
    return _tan(finite(x))


def exp(x: float) -> float:
    x = finite(x)
    try:
        return math.exp(x)
    except OverflowError:  # C returns inf; rs274 then rejects it
        return finite(math.inf)


def fix(x: float) -> float:
    """Round down (towards minus infinity): ``FIX[-2.8] == -3``. A zero
    result keeps the argument's sign, as C's floor does (``FIX[-0]`` is
    -0, printed ``-0.0000``)."""
    x = finite(x)
    return math.copysign(float(math.floor(x)), x)


def fup(x: float) -> float:
    """Round up (towards plus infinity): ``FUP[-2.8] == -2``. A zero result
    keeps the argument's sign, as C's ceil does (``FUP[-0.5]`` is -0)."""
    x = finite(x)
    return math.copysign(float(math.ceil(x)), x)


def ln(x: float) -> float:
    x = finite(x)
    if x <= 0.0:
        raise GCodeError("Zero or negative argument to ln")
    return math.log(x)


def round_(x: float) -> float:
    """Half away from zero, through a C int: ``ROUND[-2.5] == -3``."""
    x = finite(x)
    return float(c_int(x + (-0.5 if x < 0.0 else 0.5)))


def sqrt(x: float) -> float:
    x = finite(x)
    if x < 0.0:
        raise GCodeError("Negative argument to sqrt")
    return math.sqrt(x)


# --------------------------------------------------------------------------
# C semantics where Python's float functions differ (exceptions instead of
# inf/nan, ints instead of floats)
# --------------------------------------------------------------------------


def c_int(x: float) -> int:
    """C's ``(int) x`` on x86-64: truncation; out of range or NaN gives INT_MIN."""
    if x != x or not -2147483649.0 < x < 2147483648.0:
        return _INT_MIN
    return int(x)


def c_hypot(x: float, y: float) -> float:
    """``hypot(x, y)`` as the C library rs274 runs on (glibc 2.35+) computes
    it, which matters where a sign of a rounded zero shows in the trace.

    Python's math.hypot is rounded differently in about one case in six
    hundred. glibc takes the root of the rounded sum of squares and then
    corrects it by the error of that sum, found exactly (Borges' algorithm,
    without fused multiply-add: :func:`_hypot_kernel`). Sides so large that
    the squares would overflow, or so small that they would underflow (the
    root would be 0, and the correction divide by it), are scaled by a
    power of two first and back after, as glibc scales them; an infinite
    side gives infinity, else a NaN gives NaN, as in C.
    """
    big, small = abs(x), abs(y)
    if big == math.inf or small == math.inf:
        return math.inf
    if big != big or small != small:
        return x + y  # NaN
    if big < small:
        big, small = small, big
    if big > _HUGE_SIDE:
        if small <= big * _HALF_EPSILON:
            return big + small
        return _hypot_kernel(big * _SIDE_SCALE, small * _SIDE_SCALE) / _SIDE_SCALE
    if small < _TINY_SIDE:
        if big >= small / _HALF_EPSILON:
            return big + small
        return _hypot_kernel(big / _SIDE_SCALE, small / _SIDE_SCALE) * _SIDE_SCALE
    if small <= big * _HALF_EPSILON:
        return big + small
    return _hypot_kernel(big, small)


def _hypot_kernel(big: float, small: float) -> float:
    """The corrected root of big**2 + small**2 (big >= small, neither so
    large nor so small that a square leaves the range of doubles)."""
    root = math.sqrt(big * big + small * small)
    if root <= 2.0 * small:
        delta = root - small
        error = big * (2.0 * delta - big) + (delta - 2.0 * (big - small)) * delta
    else:
        delta = root - big
        error = 2.0 * delta * (big - 2.0 * small)
        error += (4.0 * delta - small) * small + delta * delta
    return root - error / (2.0 * root)


#: Sides beyond which c_hypot scales them (by _SIDE_SCALE) before squaring.
_HUGE_SIDE = 2.0**511
_TINY_SIDE = 2.0**-511
_SIDE_SCALE = 2.0**-600

#: Below this ratio the smaller side cannot change the hypotenuse.
_HALF_EPSILON = 2.0**-54


def _is_integral(x: float) -> bool:
    """C's ``floor(x) == x`` (true for infinities, false for NaN)."""
    return math.isinf(x) or float(x).is_integer()


def _c_pow(a: float, b: float) -> float:
    try:
        return math.pow(a, b)
    except OverflowError:
        negative = a < 0.0 and _is_odd_integer(b)
        return -math.inf if negative else math.inf
    except ValueError:  # zero to a negative power: a pole, C returns +-inf
        negative = math.copysign(1.0, a) < 0.0 and _is_odd_integer(b)
        return -math.inf if negative else math.inf


def _is_odd_integer(x: float) -> bool:
    return float(x).is_integer() and math.fmod(x, 2.0) != 0.0


# --------------------------------------------------------------------------
# x87 long double emulation for angles.
#
# A long double is an integer significand of 64 bits times a power of two; we
# keep it as ``(m, e)`` meaning ``m * 2**e``. Every long double operation is
# computed exactly with integers and rounded to 64 bits (round half to even,
# as the x87 does); storing the result into a double rounds again to 53 bits.
# --------------------------------------------------------------------------

_LD_BITS = 64
_FIXED_BITS = 256  # working precision of the sin/cos series
_PI_BITS = 1400  # enough to reduce the largest radians a double can give


def _rounded_ratio(num: int, den: int, exp: int, bits: int) -> Tuple[int, int]:
    """``num / den * 2**exp`` rounded to ``bits`` significant bits: ``(m, e)``."""
    if num == 0:
        return 0, 0
    sign = -1 if num < 0 else 1
    num = abs(num)
    shift = bits - (num.bit_length() - den.bit_length()) + 1
    if shift >= 0:
        q, r = divmod(num << shift, den)
    else:
        q, r = divmod(num, den << -shift)
    extra = q.bit_length() - bits  # 1 or 2 bits beyond the precision
    low = q & ((1 << extra) - 1)
    half = 1 << (extra - 1)
    q >>= extra
    if low > half or (low == half and (r or q & 1)):
        q += 1
        if q.bit_length() > bits:
            q >>= 1
            extra += 1
    return sign * q, exp - shift + extra


def _double_parts(x: float) -> Tuple[int, int]:
    """A double as ``(m, e)`` with ``x == m * 2**e`` exactly."""
    num, den = x.as_integer_ratio()
    return num, 1 - den.bit_length()


def _to_double(m: int, e: int) -> float:
    """Store a long double into a double (one correctly rounded conversion)."""
    if e >= 0:
        return float(m << e)
    return m / (1 << -e)


def _pi_fixed(bits: int) -> int:
    """pi * 2**bits, truncated, by Machin's formula in integer arithmetic."""
    guard = bits + 32

    def arctan_inv(n: int) -> int:
        total = term = (1 << guard) // n
        k, n2 = 1, n * n
        while term:
            term //= n2
            k += 2
            total += -(term // k) if k % 4 == 3 else term // k
        return total

    return (16 * arctan_inv(5) - 4 * arctan_inv(239)) >> 32


_HALF_PI: List[int] = []


def _half_pi_fixed() -> int:
    """pi/2 * 2**_PI_BITS (pi's low bit is lost: 2**-1400), computed the
    first time the emulation needs it (milliseconds a run would pay at
    import for nothing where the C library does the trigonometry)."""
    if not _HALF_PI:
        _HALF_PI.append(_pi_fixed(_PI_BITS) >> 1)
    return _HALF_PI[0]


#: M_PIl: pi rounded to a 64-bit significand, ``(m, e)``; test_ops checks
#: it against pi from Machin's formula above.
_PI_L = (0xC90FDAA22168C235, -62)


def round_bits(n: int, bits: int) -> Tuple[int, int]:
    """``n`` (> 0) rounded to ``bits`` significant bits, ties to even, as
    the x87 rounds: ``(q, shift)`` with ``q * 2**shift`` the result and
    ``q`` below ``2**bits``."""
    shift = n.bit_length() - bits
    if shift <= 0:
        return n, 0
    q = n >> shift
    rest = n - (q << shift)
    half = 1 << (shift - 1)
    if rest > half or (rest == half and q & 1):
        q += 1
        if q >> bits:
            q >>= 1
            shift += 1
    return q, shift


#: M_PI_2l (64-bit significand) times 2**128, and that scale.
_HALF_PI_SCALED = 0xC90FDAA22168C235 << 65
_SCALE = 2.0**128
_UNSCALE = 2.0**-128
#: M_PI_2l stored into a double.
_HALF_PI_DOUBLE = float(0xC90FDAA22168C235) * 2.0**-63


def plus_half_pi(x: float, sign: int = 1) -> float:
    """rs274's ``x + M_PI_2l`` (or minus, for ``sign=-1``) stored into a double.

    The arc code mixes a double with the long double constant, so the sum is
    rounded to a long double first and then to a double; doing it in doubles
    alone sometimes turns a centre rs274 prints as ``-0.0000`` into ``0.0000``.
    Worked in integers scaled by 2**128, about fifteen times faster than
    exact fractions (:func:`plus_half_pi_exact`, used outside that range).

    For 2**-66 <= |x| <= 4 (an angle from atan2) every double is a multiple
    of 2**-118, so the scaled sum is an exact integer: rounding it to 64
    significant bits (half to even) is the x87's addition, and ``float()``
    of an integer rounds half to even, as the store does."""
    if not 2.0**-66 <= abs(x) <= 4.0:
        if x == 0.0:  # a chord along an axis
            return _HALF_PI_DOUBLE if sign > 0 else -_HALF_PI_DOUBLE
        return plus_half_pi_exact(x, sign)
    total = int(x * _SCALE) + (_HALF_PI_SCALED if sign > 0 else -_HALF_PI_SCALED)
    negative = total < 0
    if negative:
        total = -total
    kept, shift = round_bits(total, 64)
    total = kept << shift
    value = float(total) * _UNSCALE
    return -value if negative else value


def plus_half_pi_exact(x: float, sign: int = 1) -> float:
    """:func:`plus_half_pi` in exact fractions, for any double."""
    from fractions import Fraction  # here: its import costs start-up time

    pm, pe = _PI_L
    exact = Fraction(x) + sign * Fraction(pm) * Fraction(2) ** (pe - 1)
    if exact == 0:
        return 0.0
    return _to_double(*_rounded_ratio(exact.numerator, exact.denominator, 0, _LD_BITS))


def __getattr__(name: str):
    # PI_L and HALF_PI_L: M_PIl and M_PI_2l exactly (Fractions), for
    # `long_double_sum`; made on first use, as fractions costs start-up time.
    if name in ("PI_L", "HALF_PI_L"):
        from fractions import Fraction

        pi = Fraction(_PI_L[0]) * Fraction(2) ** _PI_L[1]
        globals().update(PI_L=pi, HALF_PI_L=pi / 2)
        return globals()[name]
    raise AttributeError("module %r has no attribute %r" % (__name__, name))


def long_double_sum(first: float, *terms) -> float:
    """A C sum that mixes doubles with the long double ``M_PIl`` constants
    (`PI_L`, `HALF_PI_L`, or multiples), evaluated left to right as x86-64
    does: each partial sum rounded to a long double, the result stored into a
    double. Sums of doubles alone must be done before (they round to double).
    """
    acc = _long_double_partial_sums(first, terms)
    if acc == 0:
        return 0.0
    return _to_double(*_rounded_ratio(acc.numerator, acc.denominator, 0, _LD_BITS))


def _long_double_partial_sums(first: float, terms):
    """The exact value (a Fraction) of ``first + terms...`` left to right,
    each partial sum rounded to a long double."""
    from fractions import Fraction

    acc = Fraction(first)
    for term in terms:
        acc += Fraction(term)
        if acc:
            m, e = _rounded_ratio(acc.numerator, acc.denominator, 0, _LD_BITS)
            acc = Fraction(m) * Fraction(2) ** e
    return acc


def _degrees(radians: float) -> float:
    """rs274's ``(r * 180.0) / M_PIl``: a double product, a long double quotient."""
    product = radians * 180.0
    if product == 0.0:
        return product  # keeps the sign of zero
    m, e = _double_parts(product)
    pm, pe = _PI_L
    return _to_double(*_rounded_ratio(m, pm, e - pe, _LD_BITS))


def _radians(degrees: float) -> Tuple[int, int]:
    """rs274's ``(d * M_PIl) / 180.0`` as a long double."""
    m, e = _double_parts(degrees)
    pm, pe = _PI_L
    product = _rounded_ratio(m * pm, 1, e + pe, _LD_BITS)
    return _rounded_ratio(product[0], 180, product[1], _LD_BITS)


#: Below this size sinl(u) == tanl(u) == u and cosl(u) == 1 once rounded.
_TINY_EXPONENT = -34


def _trig(degrees: float, name: str) -> float:
    """``sinl``/``cosl``/``tanl`` of the long double radians, stored to a double."""
    if degrees == 0.0:
        return 1.0 if name == "cos" else degrees  # keeps the sign of zero
    m, e = _radians(degrees)
    if m.bit_length() + e < _TINY_EXPONENT:
        return 1.0 if name == "cos" else _to_double(m, e)
    s, c = _sin_cos(m, e)
    if name == "sin":
        result = _rounded_ratio(s, 1, -_FIXED_BITS, _LD_BITS)
    elif name == "cos":
        result = _rounded_ratio(c, 1, -_FIXED_BITS, _LD_BITS)
    else:
        result = (
            _rounded_ratio(s, c, 0, _LD_BITS)
            if c > 0
            else _rounded_ratio(-s, -c, 0, _LD_BITS)
        )
    return _to_double(*result)


def _sin_cos(m: int, e: int) -> Tuple[int, int]:
    """sin and cos of ``m * 2**e`` radians, as fixed-point ints (_FIXED_BITS)."""
    half_pi = _half_pi_fixed()
    scaled = m << (e + _PI_BITS) if e + _PI_BITS >= 0 else m >> -(e + _PI_BITS)
    quadrant = (2 * scaled + half_pi) // (2 * half_pi)
    rest = (scaled - quadrant * half_pi) >> (_PI_BITS - _FIXED_BITS)
    s, c = _sin_cos_series(rest)
    return ((s, c), (c, -s), (-s, -c), (-c, s))[quadrant % 4]


def _sin_cos_series(r: int) -> Tuple[int, int]:
    """Taylor series of sin and cos for a fixed-point ``|r| <= pi/4``."""
    r2 = (r * r) >> _FIXED_BITS
    sin_sum = term = r
    n = 1
    while term:
        term = -((term * r2) >> _FIXED_BITS) // ((n + 1) * (n + 2))
        sin_sum += term
        n += 2
    cos_sum = term = 1 << _FIXED_BITS
    n = 0
    while term:
        term = -((term * r2) >> _FIXED_BITS) // ((n + 1) * (n + 2))
        cos_sum += term
        n += 2
    return sin_sum, cos_sum


def _emulated(name: str):
    def compute(degrees: float) -> float:
        return _trig(degrees, name)

    return compute


def _choose_trig() -> None:
    """Bind ``_sin``, ``_cos``, ``_tan``: the C library's own sinl/cosl/tanl
    where this platform has the x87 long double (exact, and ten times
    faster), the integer emulation elsewhere. Done at the first SIN, COS or
    TAN a program evaluates, not at import: loading ctypes and checking the
    library costs every run a few milliseconds, and most programs (CAM
    output) never take a sine."""
    global _sin, _cos, _tan, _BACKEND
    fast = None
    if _extension is not None:  # no ctypes needed: the extension is sinl itself
        made = {"sin": _extension.sin, "cos": _extension.cos, "tan": _extension.tan}
        fast = made if library_agrees(made, _trig) else None
    if fast is None:
        from runtime import x87

        fast = x87.trig_functions(_PI_L[0], _PI_L[1], _trig, use_extension=False)
    fast = fast or {}
    _BACKEND = "library" if fast else "emulation"
    _sin, _cos, _tan = (
        fast.get(name) or _emulated(name) for name in ("sin", "cos", "tan")
    )


def library_agrees(made: dict, reference) -> bool:
    """Do the library's sin and cos (``made``) give the integer emulation's
    (``reference(degrees, name)``) answers on ordinary probe angles? (Not
    tan: rs274's tanl is not always correctly rounded, and the library, not
    the emulation, is what rs274 prints.)"""
    probes = (30.0, 45.0, 60.0, 90.0, 180.0, 270.0, -33.3, 0.3, 1e-3, 12345.678)
    for degrees in probes + tuple(k * 7.77 for k in range(1, 60)):
        for name in ("sin", "cos"):
            try:
                if made[name](degrees) != reference(degrees, name):
                    return False
            except Exception:  # noqa: BLE001 - any failure: not this library
                return False
    return True


def _first_call(name: str):
    def compute(degrees: float) -> float:
        _choose_trig()
        return globals()["_" + name](degrees)

    return compute


_sin, _cos, _tan = (_first_call(name) for name in ("sin", "cos", "tan"))


def trig_backend() -> str:
    """``"library"`` (sinl/cosl/tanl: the C extension or ctypes) or
    ``"emulation"``."""
    _choose_trig()
    return _BACKEND


# --------------------------------------------------------------------------
# The C extension's own entry points
# --------------------------------------------------------------------------
# Where setup.py built runtime._libm_trig, generated code calls its SIN, COS,
# TAN, MOD and finite() directly: a Python wrapper around each would cost more than
# the computation. It checks operands with `finite` and, at the first call,
# asks `_library_or_instead` whether the library may be used (the same
# check `_choose_trig` makes; if not, the emulation's functions answer).


def _library_or_instead():
    _choose_trig()
    if _BACKEND == "library" and _sin is getattr(_extension, "sin", None):
        return None
    return (lambda d: _sin(d), lambda d: _cos(d), lambda d: _tan(d))


try:
    from runtime import _libm_trig as _extension
except ImportError:  # not built here: the Python functions above serve
    _extension = None
#: The Python versions, which serve where the extension was not built (the
#: tests hold the extension's to them).
PYTHON_VERSIONS = {"sin": sin, "cos": cos, "tan": tan, "mod": mod, "finite": finite}
if hasattr(_extension, "checked_sin"):
    _extension.configure(finite, _library_or_instead)
    sin, cos, tan = (
        _extension.checked_sin,
        _extension.checked_cos,
        _extension.checked_tan,
    )
    mod = _extension.mod
    if hasattr(_extension, "finite"):  # (an extension built before it had one)
        finite = _extension.finite


#: M_PIl / 180.0 as a compiler folds it: a long double ``(m, e)``.
PI_L_OVER_180 = _rounded_ratio(_PI_L[0], 180, _PI_L[1], _LD_BITS)


def long_double_product(x: float, constant: Tuple[int, int]) -> float:
    """``x * constant`` computed as a long double and stored into a double
    (rs274's ``angle *= M_PIl/180.0``)."""
    if x == 0.0:
        return x
    m, e = _double_parts(x)
    cm, ce = constant
    return _to_double(*_rounded_ratio(m * cm, 1, e + ce, _LD_BITS))


def long_double_sin_product(factor: float, first: float, *terms) -> float:
    """``factor * sin(first + terms...)`` where the argument mixes doubles
    with the long double ``M_PIl`` constants (as :func:`long_double_sum`):
    C++ then calls the long double ``sin`` (``sinl``) on the unrounded sum,
    multiplies in long double and stores the product into a double
    (rs274's ``arc_radius * sin(beta - M_PI_2l)``). Computed with the
    integer emulation (a correctly rounded sinl)."""
    acc = _long_double_partial_sums(first, terms)
    if acc == 0:  # sinl(+-0) keeps the zero's sign (a sum of terms gives +0)
        return factor * (first if not terms else 0.0)
    if factor == 0.0:
        return factor * (1.0 if acc > 0 else -1.0)
    m, e = _rounded_ratio(acc.numerator, acc.denominator, 0, _LD_BITS)
    if m.bit_length() + e < _TINY_EXPONENT:
        s = (m, e)  # sinl(u) == u for such a tiny u
    else:
        s = _rounded_ratio(_sin_cos(m, e)[0], 1, -_FIXED_BITS, _LD_BITS)
    if s[0] == 0:
        return factor * 0.0
    fm, fe = _double_parts(factor)
    return _to_double(*_rounded_ratio(fm * s[0], 1, fe + s[1], _LD_BITS))
