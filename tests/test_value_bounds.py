"""Expressions the code generator proves finite (codegen.value_bound) are
written without a ``finite`` check; every other one keeps it. Both kinds are
run against rs274 here, including the ones at the edge: huge literals, MOD
of an overflowed value, sums of bounded terms that could still overflow."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from test_differential import PROFILE, check_same

HUGE = "9" * 200
#: About 1.7976e308, just below the largest double (a line holds at most 256
#: characters, so it takes two settings).
NEAR_LARGEST = "[1%s * 1%s]\n#2 = [#2 * 1%s * 1.7976]" % (
    "0" * 120,
    "0" * 120,
    "0" * 68,
)

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


_MAGNITUDE = st.builds(
    lambda mantissa, exponent: "[%s*10**%d]" % (mantissa, exponent),
    st.sampled_from(["1", "-1", "2.5", "-3.75", "7"]),
    st.sampled_from([-320, -300, -200, -160, -20, 0, 20, 150, 200, 300]),
)


@st.composite
def _extreme_geometry(draw) -> str:
    """Moves and arcs whose words are of any size a double holds: chords
    whose squares underflow or overflow, radii far smaller or larger than
    the chord (rs274 fails those: the message must match)."""
    lines = ["G21 G17 F100", "G0 X0 Y0"]
    for _ in range(draw(st.integers(1, 4))):
        x, y = draw(_MAGNITUDE), draw(_MAGNITUDE)
        kind = draw(st.sampled_from(["G1", "G2", "G3"]))
        if kind == "G1":
            lines.append("G1 X%s Y%s" % (x, y))
            continue
        if draw(st.booleans()):
            centre = "R%s" % draw(_MAGNITUDE)
        else:
            centre = "I%s J%s" % (draw(_MAGNITUDE), draw(_MAGNITUDE))
        turns = " P1" if draw(st.booleans()) else ""  # the general path
        lines.append("%s X%s Y%s %s%s" % (kind, x, y, centre, turns))
    return "\n".join(lines + ["M2"]) + "\n"


@pytest.mark.rs274
@PROFILE
@given(_extreme_geometry())
def test_geometry_of_any_magnitude_matches_rs274(text):
    """The class of c_hypot's division by zero: arithmetic that Python
    raises on where C rounds to zero or infinity."""
    check_same(text, "inprocess")


@pytest.mark.rs274
@pytest.mark.parametrize(
    "text",
    [
        "#1 = #<%s>\nM2\n" % ("a" * 240),  # the name in the message
        "#<%s> = 1\n#1 = #<%s>\nM2\n" % ("b" * 200, "c" * 230),
        "G21 G17 F100\nG0 X0 Y0\nG2 X1 Y[7*10**150] I0 J0\nM2\n",  # numbers in it
        "(m\u00e9ssage)\n#1 = #<%s\u00e9>\nM2\n" % ("d" * 242),  # cut in a character
    ],
)
def test_messages_longer_than_rs274s_buffer_are_cut_as_it_cuts_them(text):
    """rs274 keeps an error's text in LINELEN (255) bytes and prints 254 of
    them: a long name or number in a message is cut there."""
    check_same(text, "inprocess")
