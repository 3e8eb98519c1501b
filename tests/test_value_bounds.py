"""Expressions the code generator proves finite (codegen.value_bound) are
written without a ``finite`` check; every other one keeps it. Both kinds are
run against rs274 here, including the ones at the edge: huge literals, MOD
of an overflowed value, sums of bounded terms that could still overflow."""

from __future__ import annotations

import pytest

from test_differential import check_same

HUGE = "9" * 200
#: About 1.7976e308, just below the largest double (a line holds at most 256
#: characters, so it takes two settings).
NEAR_LARGEST = "[1%s * 1%s]\n#2 = [#2 * 1%s * 1.7976]" % ("0" * 120, "0" * 120, "0" * 68)

EXPRESSIONS = [
    "[30 * COS[#2] + [#2 MOD 3]]",
    "[-[#2 MOD 4] * 0.5]",
    "[[#2 * #2] MOD 3]",
    "[[%s * %s] MOD 3]" % (HUGE, HUGE),
    "[%s * %s * 0]" % (HUGE, HUGE),
    "[[%s * %s] - [%s * %s]]" % (HUGE, HUGE, HUGE, HUGE),
    "[SIN[#2] * %s]" % HUGE,
    "[ABS[#2 MOD 7] + FIX[2.5] * ROUND[#2 MOD 2]]",
    "[[#2 GT 1] + [#2 EQ 0] * 5]",
    "[ATAN[1]/[#2] * 2 + ACOS[0.5]]",
    "[#2 MOD 0]",
    "[#2 MOD [0 * 1]]",
    "[#2 * 0.3]",
    "[#2 * -1]",
    "[#2 + 1]",
    "[#2 - %s]" % HUGE,
    "[[#2 * 0.3] + [#2 * 0.7]]",
    "[#2 * 1.0001]",
    "[[#2 * %s] * 0.5]" % HUGE,
]


@pytest.mark.rs274
@pytest.mark.parametrize("expression", EXPRESSIONS)
@pytest.mark.parametrize("value", ["0", "1.5", "-" + HUGE, NEAR_LARGEST])
def test_checked_and_unchecked_expressions_match_rs274(expression, value):
    check_same(
        "#2 = %s\n#1 = %s\n(debug, #1)\nG0 X#1\nM2\n" % (value, expression), "inprocess"
    )


def test_bounded_arithmetic_is_written_without_a_check():
    from ngc2py.compiler import compile_text

    code = compile_text(
        "#2 = 1\n#1 = [30 * COS[#2] + [#2 MOD 3]]\n#3 = [#2 * #2]\nM2\n"
    )
    assert "p[1] = 30.0 * cos(p[2]) + mod(p[2], 3.0)\n" in code
    assert "p[3] = finite(p[2] * p[2])\n" in code
    code = compile_text("#2 = 1\n#1 = [#2 * 0.3]\n#3 = [#2 + 1]\n#4 = [#2 * 2]\nM2\n")
    assert "p[1] = p[2] * 0.3\n" in code and "p[3] = p[2] + 1.0\n" in code
    assert "p[4] = finite(p[2] * 2.0)\n" in code
