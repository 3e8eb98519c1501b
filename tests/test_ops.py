"""runtime.ops: operators and functions, checked against rs274.

The differential tests print ``value * 2**k`` through ``(debug,...)``, with
``k`` chosen so the product is about 2**60: DEBUG prints six decimals, so a
difference in the last bit of a double shows up in the printed integer.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import math
import random
import re
import struct
from pathlib import Path
from typing import List, Sequence, Tuple

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rs274 as harness
from runtime import ops
from runtime.errors import GCodeError

TRACE_CALL = re.compile(r"^ *\d+ N\S* *([A-Z_0-9]+)\((.*)\)$")


def rs274_calls(
    tmp_path: Path, program: str
) -> Tuple[List[Tuple[str, str]], harness.Result]:
    """Run ``program`` with rs274; its trace as (call, raw arguments) pairs."""
    result = harness.run_rs274(tmp_path / "prog.ngc", text=program)
    calls = []
    for line in result.stdout.decode("latin-1").splitlines():
        match = TRACE_CALL.match(line)
        if match:
            calls.append((match.group(1), match.group(2)))
    return calls, result


def rs274_messages(tmp_path: Path, program: str) -> List[str]:
    """The texts of rs274's MESSAGE(...) calls for ``program``."""
    calls, result = rs274_calls(tmp_path, program)
    assert result.rc == 0, result.err
    return [args[1:-1] for name, args in calls if name == "MESSAGE"]


def rs274_error(tmp_path: Path, program: str) -> str:
    """rs274's error message for ``program`` ("" when it runs cleanly)."""
    return harness.run_rs274(tmp_path / "prog.ngc", text=program).err


def literal(x: float) -> str:
    """``x`` as a G-code number (G-code has no exponent notation)."""
    text = repr(x)
    return text if "e" not in text else "%.30f" % x


def scaled_debug(expr: str, value: float) -> Tuple[List[str], str]:
    """G-code lines printing ``expr`` scaled to ~2**60, and what that prints."""
    k = 60 - math.frexp(value)[1] if value and math.isfinite(value) else 0
    scale = "*2**%d" % k if k >= 0 else "/2**%d" % -k
    shown = math.ldexp(value, k)
    expected = "%f" % (0.0 if abs(shown) < ops.TOLERANCE_EQUAL else shown)
    return ["#1=[[%s]%s]" % (expr, scale), "(debug,#1)"], expected


def assert_same_values(tmp_path: Path, cases: Sequence[Tuple[str, float]]) -> None:
    """Every G-code expression of ``cases`` prints what our value does."""
    lines: List[str] = []
    expected: List[str] = []
    for expr, value in cases:
        code, shown = scaled_debug(expr, value)
        lines += code
        expected.append(shown)
    got = rs274_messages(tmp_path, "\n".join(lines + ["M2"]) + "\n")
    mismatches = [(c[0], e, g) for c, e, g in zip(cases, expected, got) if e != g]
    assert len(got) == len(cases)
    assert mismatches == []


# --------------------------------------------------------------------------
# Facts observed with rs274 (no rs274 needed to run these)
# --------------------------------------------------------------------------


def test_long_double_angles_give_exact_results():
    # rs274 printed SIN[30]*2=1 through FIX, and exact 0 differences below
    assert ops.sin(30.0) == 0.5
    assert ops.cos(60.0) == 0.5
    assert ops.tan(45.0) == 1.0
    assert ops.acos(0.5) == 60.0
    assert ops.fix(ops.sin(30.0) * 2.0) == 1.0


def test_cos_90_is_the_long_double_residue():
    # rs274: COS[90]*10**24 printed -25082.788063
    assert "%f" % (ops.cos(90.0) * 1e24) == "-25082.788063"
    assert ops.fix(ops.cos(90.0)) == -1.0


def test_zero_keeps_its_sign():
    assert math.copysign(1.0, ops.sin(-0.0)) == -1.0
    assert ops.cos(-0.0) == 1.0


def test_comparisons_use_tolerance_only_for_eq_ne():
    # rs274: 1.0001 EQ 1 -> 1, 1.00005 LE 1 -> 0, 0.99995 GE 1 -> 0
    assert ops.eq(1.0001, 1.0) == 1.0
    assert ops.ne(1.0, 1.0001) == 0.0
    assert ops.le(1.00005, 1.0) == 0.0
    assert ops.ge(0.99995, 1.0) == 0.0
    assert ops.gt(1.00005, 1.0) == 1.0
    assert ops.lt(0.99995, 1.0) == 1.0


def test_logic_results():
    assert (
        ops.and_(0.00001, 1),
        ops.or_(0, 0.000001),
        ops.xor(1, 2),
        ops.xor(1, 0),
    ) == (
        1.0,
        1.0,
        0.0,
        1.0,
    )


def test_mod_and_round_rules():
    # rs274: -7 MOD 3 = 2, 7 MOD -3 = 1, -7 MOD -3 = 2, -7.5 MOD 2 = 0.5
    assert [ops.mod(-7, 3), ops.mod(7, -3), ops.mod(-7, -3), ops.mod(-7.5, 2)] == [
        2,
        1,
        2,
        0.5,
    ]
    # rs274: ROUND[-2.5] = -3, ROUND[2.5] = 3, ROUND[3000000000] = INT_MIN
    assert [ops.round_(-2.5), ops.round_(2.5), ops.round_(3e9)] == [-3, 3, -2147483648]


def test_tiny_values_are_true():
    assert ops.truth(0.00001) and ops.truth(-0.5) and not ops.truth(-0.0)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: ops.div(1, 0), "Attempt to divide by zero"),
        (lambda: ops.sqrt(-1), "Negative argument to sqrt"),
        (lambda: ops.ln(0), "Zero or negative argument to ln"),
        (lambda: ops.acos(2), "Argument to acos out of range"),
        (lambda: ops.asin(-1.5), "Argument to asin out of range"),
        (lambda: ops.power(-2, 0.5), "Attempt to raise negative to non integer power"),
        (lambda: ops.exp(1000), "Calculation resulted in 'infinity'"),
        (lambda: ops.finite(ops.power(10, 400)), "Calculation resulted in 'infinity'"),
        (lambda: ops.finite(ops.power(0, -1)), "Calculation resulted in 'infinity'"),
        (lambda: ops.finite(ops.mod(5, 0)), "Calculation resulted in 'not a number'"),
        (
            lambda: ops.finite(ops.power(10, 400) * 0),
            "Calculation resulted in 'not a number'",
        ),
        (
            lambda: ops.abs_(ops.power(10, 400) * 0),
            "Calculation resulted in 'not a number'",
        ),
    ],
)
def test_error_messages(call, message):
    with pytest.raises(GCodeError) as info:
        call()
    assert info.value.message == message


def test_binary_helpers_return_c_values_unchecked():
    assert ops.power(10, 400) == math.inf
    assert ops.power(-0.0, -1) == -math.inf
    assert ops.power(-10, 401) == -math.inf
    assert math.isnan(ops.mod(5, 0))


# --------------------------------------------------------------------------
# Differential tests
# --------------------------------------------------------------------------


def angle_inputs() -> List[float]:
    rng = random.Random(274)
    xs = [0.1 * i for i in range(-3700, 3700, 37)] + [
        float(i) for i in range(-720, 721, 15)
    ]
    xs += [rng.uniform(-1e6, 1e6) for _ in range(60)] + [
        rng.uniform(-10, 10) for _ in range(60)
    ]
    # tenths of a degree: where the C library's tanl is not correctly
    # rounded (TAN[271], TAN[-236.1]) and rs274 prints what it returns
    xs += [i / 10 for i in range(-3607, 3607, 13)] + [271.0, -236.1]
    return xs + [1e10 + 0.5, 123456789.123, 1e15, 3e17, 0.001, 1e-5]


def unit_inputs() -> List[float]:
    rng = random.Random(5599)
    return [rng.uniform(-1, 1) for _ in range(100)] + [i / 20 for i in range(-20, 21)]


@pytest.mark.rs274
@pytest.mark.parametrize(
    "name, func", [("SIN", ops.sin), ("COS", ops.cos), ("TAN", ops.tan)]
)
def test_trig_matches_rs274(tmp_path, name, func):
    cases = [("%s[%s]" % (name, literal(x)), func(x)) for x in angle_inputs()]
    assert_same_values(tmp_path, cases)


@pytest.mark.rs274
def test_inverse_trig_matches_rs274(tmp_path):
    us = unit_inputs()
    cases = [("ACOS[%s]" % literal(u), ops.acos(u)) for u in us]
    cases += [("ASIN[%s]" % literal(u), ops.asin(u)) for u in us]
    cases += [
        ("ATAN[%s]/[%s]" % (literal(y), literal(x)), ops.atan2(y, x))
        for y, x in zip(us, reversed(us))
    ]
    grid = (-2.0, -1.0, 0.0, 1.0, 3.0)
    cases += [("ATAN[%s]/[%s]" % (y, x), ops.atan2(y, x)) for y in grid for x in grid]
    assert_same_values(tmp_path, cases)


@pytest.mark.rs274
def test_other_functions_and_operators_match_rs274(tmp_path):
    cases = []
    for x in angle_inputs()[::2] + unit_inputs()[::3]:
        cases += [
            ("SQRT[%s]" % literal(abs(x)), ops.sqrt(abs(x))),
            ("ROUND[%s]" % literal(x), ops.round_(x)),
            ("FIX[%s]" % literal(x), ops.fix(x)),
            ("FUP[%s]" % literal(x), ops.fup(x)),
            ("ABS[%s]" % literal(x), ops.abs_(x)),
            ("%s MOD 2.5" % literal(x), ops.mod(x, 2.5)),
            ("%s MOD -3.7" % literal(x), ops.mod(x, -3.7)),
            ("%s / 7.3" % literal(x), ops.div(x, 7.3)),
        ]
        if x > 0:
            cases.append(("LN[%s]" % literal(x), ops.ln(x)))
        if abs(x) < 100:  # keeps EXP and ** finite
            cases.append(("EXP[%s]" % literal(x), ops.exp(x)))
            cases.append(("%s ** 2.7" % literal(abs(x)), ops.power(abs(x), 2.7)))
            cases.append(("%s ** 3" % literal(x), ops.power(x, 3.0)))
    assert_same_values(tmp_path, cases)


@pytest.mark.rs274
def test_comparisons_and_logic_match_rs274(tmp_path):
    ops_by_name = {
        "EQ": ops.eq,
        "NE": ops.ne,
        "GT": ops.gt,
        "GE": ops.ge,
        "LT": ops.lt,
        "LE": ops.le,
        "AND": ops.and_,
        "OR": ops.or_,
        "XOR": ops.xor,
    }
    values = [0.0, 1.0, 1.00005, 1.0001, 1.00011, 0.99995, 0.9999, -1.0, 0.00001, 2.0]
    cases = [
        ("%s %s %s" % (literal(a), name, literal(b)), func(a, b))
        for name, func in ops_by_name.items()
        for a in values
        for b in values
    ]
    assert_same_values(tmp_path, cases)


@pytest.mark.rs274
@pytest.mark.parametrize(
    "expr, compute",
    [
        ("[1/0]", lambda: ops.div(1, 0)),
        ("[SQRT[-1]]", lambda: ops.sqrt(-1)),
        ("[LN[-1]]", lambda: ops.ln(-1)),
        ("[ACOS[2]]", lambda: ops.acos(2)),
        ("[ASIN[-1.5]]", lambda: ops.asin(-1.5)),
        ("[[0-8]**[1/3]]", lambda: ops.power(-8, ops.div(1, 3))),
        ("[EXP[1000]]", lambda: ops.exp(1000)),
        ("[EXP[1000]-EXP[1000]]", lambda: ops.exp(1000) - ops.exp(1000)),
        ("[10**400]", lambda: ops.finite(ops.power(10, 400))),
        ("[0**-1]", lambda: ops.finite(ops.power(0, -1))),
        ("[5 MOD 0]", lambda: ops.finite(ops.mod(5, 0))),
        ("[10**400*0]", lambda: ops.finite(ops.power(10, 400) * 0)),
        ("[[10**400]*0]", lambda: ops.finite(ops.finite(ops.power(10, 400)) * 0)),
        (
            "[10**400 - 10**400]",
            lambda: ops.finite(ops.power(10, 400) - ops.power(10, 400)),
        ),
        ("[ABS[10**400*0]]", lambda: ops.abs_(ops.power(10, 400) * 0)),
        ("[1/0 + SQRT[-1]]", lambda: ops.div(1, 0) + ops.sqrt(-1)),
        ("[SQRT[-1] + 1/0]", lambda: ops.sqrt(-1) + ops.div(1, 0)),
    ],
)
def test_errors_match_rs274(tmp_path, expr, compute):
    with pytest.raises(GCodeError) as info:
        compute()
    assert info.value.message == rs274_error(tmp_path, "#1=%s\nM2\n" % expr)


@pytest.mark.rs274
def test_extreme_angles_match_rs274(tmp_path):
    # huge arguments need exact reduction; tiny ones the small-angle shortcut
    cases = []
    for e in (300, 100, 30, 19, 17, -5, -15, -30, -200):
        for m in (1.0, -3.7, 7.25):
            x = m * ops.power(10.0, e)
            for name, func in (("SIN", ops.sin), ("COS", ops.cos), ("TAN", ops.tan)):
                cases.append(("%s[%s*10**%d]" % (name, m, e), func(x)))
    assert_same_values(tmp_path, cases)


def test_c_hypot_rounds_like_the_c_library():
    # rs274 calls the C library's hypot (polar words, arc radii); compare
    # with it directly, on values of the sizes G-code positions take.
    libm = ctypes.CDLL(ctypes.util.find_library("m"))
    libm.hypot.restype = ctypes.c_double
    libm.hypot.argtypes = [ctypes.c_double, ctypes.c_double]
    rng = random.Random(7)
    for _ in range(20000):
        x = rng.uniform(-3, 3) * 10.0 ** rng.randint(-6, 6)
        y = rng.uniform(-3, 3) * 10.0 ** rng.randint(-6, 6)
        assert ops.c_hypot(x, y) == libm.hypot(x, y), (x, y)
    assert ops.c_hypot(0.0, 0.0) == 0.0


_SIDES = st.builds(
    lambda mantissa, exponent, sign: sign * mantissa * 2.0**exponent,
    st.floats(1.0, 2.0, exclude_max=True),
    st.integers(-1074, 1023),
    st.sampled_from([1.0, -1.0]),
) | st.sampled_from([0.0, -0.0, 5e-324, 2.0**-511, 2.0**511, math.inf, -math.inf])


@given(_SIDES, _SIDES)
@settings(max_examples=3000)
def test_c_hypot_is_the_c_librarys_over_every_size(x, y):
    """c_hypot against the C library's hypot on every exponent: sides whose
    squares would overflow or underflow (a chord of 1e-200 once made it
    divide by zero: an internal error where rs274 drew the arc), infinities
    and zeros, to the bit."""
    libm = ctypes.CDLL(ctypes.util.find_library("m"))
    libm.hypot.restype = ctypes.c_double
    libm.hypot.argtypes = [ctypes.c_double, ctypes.c_double]
    made, theirs = ops.c_hypot(x, y), libm.hypot(x, y)
    assert struct.pack("<d", made) == struct.pack("<d", theirs), (x, y)
    assert ops.c_hypot(math.nan, 1.0) != ops.c_hypot(math.nan, 1.0)  # NaN
    assert ops.c_hypot(math.nan, math.inf) == math.inf  # as in C


@pytest.mark.rs274
def test_arcs_of_tiny_and_huge_chords_match_rs274(tmp_path):
    """R arcs whose chord squares underflow or overflow, by the general path
    (P turns) and by the fast one: rs274's trace, not an internal error."""
    from test_differential import check_same

    check_same(
        "G21 G17 F100\nG0 X0 Y0\n"
        "G2 X[10**-200] Y[10**-200] R1 P1\n"
        "G3 X[2*10**-200] Y0 R[10**-300]\n"
        "G2 X[10**200] Y0 R[10**200] P1\n"
        "G2 X0 Y0 R[10**200]\n"
        "G1 X[10**300] Y[10**300]\nM2\n"
    )


@pytest.mark.skipif(
    ops.trig_backend() != "library", reason="no x87 long double C library here"
)
def test_library_sin_cos_agree_with_the_exact_emulation():
    """sinl/cosl through ctypes (the fast path) against the integer emulation."""
    rng = random.Random(87)
    for _ in range(3000):
        x = rng.choice(
            [
                rng.uniform(-720, 720),
                round(rng.uniform(-720, 720), 2),
                rng.uniform(-1e5, 1e5),
            ]
        )
        assert ops.sin(x) == ops._trig(x, "sin"), x
        assert ops.cos(x) == ops._trig(x, "cos"), x


def test_the_c_extension_computes_what_the_ctypes_path_computes():
    """runtime._libm_trig (built by setup.py where a C compiler is found)
    against sinl/cosl/tanl through ctypes on the same long double radians;
    where it was not built, the ctypes path is what runs, and this says so."""
    from runtime import x87

    extension = x87._extension_functions()
    if extension is None:
        pytest.skip("runtime._libm_trig not built here (no C compiler or headers)")
    through_ctypes = x87.trig_functions(
        ops._PI_L[0], ops._PI_L[1], ops._trig, use_extension=False
    )
    assert through_ctypes is not None
    rng = random.Random(5)
    angles = [271.0, -236.1, 0.0, -0.0, 90.0, 1e-300, 5e15]
    angles += [rng.uniform(-1e5, 1e5) for _ in range(20000)]
    angles += [round(rng.uniform(-720, 720), 3) for _ in range(20000)]
    for x in angles:
        for name in ("sin", "cos", "tan"):
            got, want = extension[name](x), through_ctypes[name](x)
            assert got == want or (got != got and want != want), (name, x)
            assert math.copysign(1, got) == math.copysign(1, want), (name, x)


def test_m_pil_is_pi_rounded_to_a_long_double():
    pi = ops._pi_fixed(ops._PI_BITS)
    assert ops._PI_L == ops._rounded_ratio(pi, 1, -ops._PI_BITS, ops._LD_BITS)


def test_the_c_extension_mod_sin_cos_tan_are_the_python_ones():
    """Where runtime._libm_trig was built, generated code calls its MOD and
    checked SIN/COS/TAN directly; they must give the Python versions'
    answers and errors (inf/nan operands, signed zeros, zero divisors)."""
    if ops.mod is ops.PYTHON_VERSIONS["mod"]:
        pytest.skip("runtime._libm_trig not built here: the Python versions run")
    inf, nan = math.inf, math.nan
    special = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        3.0,
        -7.0,
        0.5,
        1e-300,
        -1e300,
        5e15,
        inf,
        -inf,
        nan,
    ]
    rng = random.Random(11)
    pairs = [(a, b) for a in special for b in special]
    pairs += [
        (rng.uniform(-1e4, 1e4), rng.choice([3.0, -3.0, 0.7, 360.0]))
        for _ in range(5000)
    ]
    for a, b in pairs:
        got, want = ops.mod(a, b), ops.PYTHON_VERSIONS["mod"](a, b)
        if want != want:  # a NaN's sign is never seen: a bracket rejects it
            assert got != got, (a, b)
            continue
        assert got == want and math.copysign(1, got) == math.copysign(1, want), (a, b)
    for name in ("sin", "cos", "tan"):
        fast, python = getattr(ops, name), ops.PYTHON_VERSIONS[name]
        for x in [0.0, -0.0, 90.0, -33.3] + [
            rng.uniform(-720, 720) for _ in range(2000)
        ]:
            assert fast(x) == python(x), (name, x)
        for bad, message in (
            (inf, "infinity"),
            (-inf, "infinity"),
            (nan, "not a number"),
        ):
            with pytest.raises(GCodeError, match=message):
                fast(bad)
    fast, python = ops.finite, ops.PYTHON_VERSIONS["finite"]
    assert fast is not python
    for x in special[:-3] + [3, -(2**80), True]:  # ints pass, as in Python
        assert fast(x) is python(x) or fast(x) == python(x), x
    for bad, message in ((inf, "infinity"), (-inf, "infinity"), (nan, "not a number")):
        with pytest.raises(GCodeError, match=message):
            fast(bad)


def test_the_c_extension_column_helpers_are_the_python_ones():
    """runtime.fast.arc_rows takes floats() and radius_bounds() from the extension
    where it was built: the same floats, and bounds that differ at most in
    the last bits hypot may round differently (arc_rows keeps a margin of
    1e-14 for that)."""
    from runtime.fast import arc_rows

    if arc_rows.radius_bounds is arc_rows.python_radius_bounds:
        pytest.skip("runtime._libm_trig not built here: the Python versions run")
    rng = random.Random(5)
    texts = ["%.*f" % (rng.randint(0, 6), rng.uniform(-1e4, 1e4)) for _ in range(3000)]
    for _ in range(20000):  # up to 15 digits, up to 15 of them decimals
        digits = str(rng.randrange(10 ** rng.randint(1, 15)))
        cut = rng.randint(0, len(digits))
        texts.append(rng.choice("-+ ").strip() + digits[:cut] + "." + digits[cut:])
    texts += [
        "1e308",
        "-0.0",
        "-0",
        "7",
        "1.",
        ".5",
        " 2.5 ",
        "1_0",
        "9007199254740993",
    ]
    texts += ["0.1234567890123456", "1234567890123456", "inf", "-nan"]
    got = arc_rows.column_floats(texts)
    want = arc_rows.python_column_floats(texts)
    assert [(x, math.copysign(1, x)) for x in got if x == x] == [
        (x, math.copysign(1, x)) for x in want if x == x
    ]
    assert sum(x != x for x in got) == sum(x != x for x in want) == 1
    with pytest.raises(ValueError):
        arc_rows.column_floats(["1.0", "x"])
    for size in (1, 2, 50, 4096):
        columns = [[rng.uniform(-100, 100) for _ in range(size)] for _ in range(6)]
        got = arc_rows.radius_bounds(*columns)
        want = arc_rows.python_radius_bounds(*columns)
        assert got == pytest.approx(want, rel=1e-15, abs=1e-12)
    inf_column = [[1.0, math.inf]] + [[0.0, 0.0]] * 5
    assert arc_rows.radius_bounds(*inf_column) is None
    assert arc_rows.radius_bounds(*[[1]] * 6) is None  # not floats
