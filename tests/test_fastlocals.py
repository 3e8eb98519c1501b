"""ngc2py.fastlocals: named locals held in Python variables (``v_i``).

The choice is checked on small programs (which names become variables, and
which stay in the store because something could tell the difference), and
programs drawn by a generator made for it -- settings inside loops and ifs,
reads before and after them, break and continue around the setting, do-loop
conditions, subroutines, unset names -- run against rs274.
"""

from __future__ import annotations

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rs274 as harness
import test_differential as differential
from ngc2py.compiler import compile_text
from test_differential import PROFILE


def variables(text: str) -> set:
    """The G-code names the generated module keeps in Python variables."""
    code = compile_text(text, "p.ngc")
    compile(code, "p.py", "exec")
    return set(re.findall(r"\bv_(\w+)", code))


def test_a_loop_counter_and_a_value_set_in_the_body():
    text = (
        "#<i> = 0\n"
        "o1 while [#<i> LT 3]\n"
        "  #<a> = [#<i> * 2]\n"
        "  G1 X#<a> F100\n"
        "  #<i> = [#<i> + 1]\n"
        "o1 endwhile\n"
        "M2\n"
    )
    assert variables(text) == {"i", "a"}


def test_a_subroutines_locals():
    text = "o<s> sub\n  #<t> = [#1 + 1]\n  o<s> return [#<t>]\no<s> endsub\no<s> call [2]\nM2\n"
    assert variables(text) == {"t"}


@pytest.mark.parametrize(
    "text, why",
    [
        ("o1 while [#<i> LT 3]\n#<i> = 1\no1 endwhile\nM2\n", "read first"),
        ("#<i> = [#<i> + 1]\nM2\n", "rs274 creates it as it reads the setting"),
        ("o1 if [1]\n#<a> = 1\no1 endif\nG0 X#<a>\nM2\n", "read after the if"),
        ("o1 do\n#<a> = 1\no1 while [#<a> LT 0]\nM2\n", "the do's condition"),
        ("#<a> = 1\n(debug, #<a>)\nM2\n", "a comment may expand it"),
        ("#<a> = 1\n#<b> = EXISTS[#<a>]\nM2\n", "EXISTS"),
        ("#<_g> = 1\nG0 X#<_g>\nM2\n", "a global"),
        ("G0 X1 #<a> = 2\nG0 X#<a>\nM2\n", "set by a line that also moves"),
        ("/#<a> = 2\nG0 X#<a>\nM2\n", "block delete may skip the setting"),
        ("o<s> sub\n#<n_args> = 5\no<s> endsub\nM2\n", "OWORD_NARGS: read-only"),
    ],
)
def test_names_that_stay_in_the_store(text, why):
    assert (
        "a" not in variables(text)
        and "i" not in variables(text)
        and "_g" not in variables(text)
    ), why


def test_no_variables_where_an_m98_call_could_rebind_the_locals():
    # (the Fanuc subroutine's own q may: each call has fresh locals)
    text = "O100\n#<q> = 1\nM99\n#<a> = 1\nM98 P100\nG0 X#<a>\nM2\n"
    assert "a" not in variables(text)


# --------------------------------------------------------------------------
# Against rs274
# --------------------------------------------------------------------------

_NAMES = ["a", "b", "c"]


@st.composite
def _expr(draw):
    kind = draw(st.integers(0, 3))
    if kind == 0:
        return str(draw(st.integers(-3, 5)))
    name = draw(st.sampled_from(_NAMES))
    if kind == 1:
        return "#<%s>" % name
    return "[#<%s> %s %d]" % (
        name,
        draw(st.sampled_from(["+", "-", "*", "MOD"])),
        draw(st.integers(1, 4)),
    )


@st.composite
def _statements(draw, depth, loop, labels):
    lines = []
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.integers(0, 9 if depth < 3 else 4))
        if kind <= 1:
            lines.append("#<%s> = %s" % (draw(st.sampled_from(_NAMES)), draw(_expr())))
        elif kind == 2:
            lines.append("G1 X%s F100" % draw(_expr()))
        elif kind == 3 and loop is not None:
            lines.append(
                "o%d %s" % (loop, draw(st.sampled_from(["break", "continue"])))
            )
        elif kind == 4:
            lines.append(
                "#<%s> = %s #<%s> = %s"
                % (
                    draw(st.sampled_from(_NAMES)),
                    draw(_expr()),
                    draw(st.sampled_from(_NAMES)),
                    draw(_expr()),
                )
            )
        elif kind <= 6:
            label = labels.pop()
            lines.append(
                "o%d if [%s GT %d]" % (label, draw(_expr()), draw(st.integers(-1, 3)))
            )
            lines.extend("  " + x for x in draw(_statements(depth + 1, loop, labels)))
            if draw(st.booleans()):
                lines.append("o%d else" % label)
                lines.extend(
                    "  " + x for x in draw(_statements(depth + 1, loop, labels))
                )
            lines.append("o%d endif" % label)
        elif kind <= 8:
            label = labels.pop()
            counter = "n%d" % label  # every loop ends: its own counter
            lines.append("#<%s> = 0" % counter)
            lines.append(
                "o%d while [#<%s> LT %d]" % (label, counter, draw(st.integers(0, 3)))
            )
            lines.append("  #<%s> = [#<%s> + 1]" % (counter, counter))
            lines.extend("  " + x for x in draw(_statements(depth + 1, label, labels)))
            lines.append("o%d endwhile" % label)
        else:
            label = labels.pop()
            counter = "n%d" % label
            lines.append("#<%s> = 0" % counter)
            lines.append("o%d do" % label)
            lines.append("  #<%s> = [#<%s> + 1]" % (counter, counter))
            lines.extend("  " + x for x in draw(_statements(depth + 1, label, labels)))
            lines.append(
                "o%d while [#<%s> LT %d]" % (label, counter, draw(st.integers(1, 3)))
            )
    return lines


@st.composite
def local_programs(draw):
    """Settings and reads of a few named locals around loops and ifs, in the
    main program and in a subroutine; unset reads fail as in rs274."""
    labels = list(range(900, 100, -1))
    sub = draw(_statements(1, None, labels))
    main = draw(_statements(0, None, labels))
    text = ["G21 G90", "o<s> sub"]
    text += ["  " + x for x in sub]
    text += ["  o<s> return [%s]" % draw(_expr()), "o<s> endsub"]
    text += main
    text += ["o<s> call [1] [2]", "G1 X#<_value> F100"]
    text += draw(_statements(0, None, labels))
    text.append("M2")
    return "\n".join(text) + "\n"


_PROGRAM = harness.REPO / "tests" / "_generated" / "fastlocals.ngc"


@pytest.mark.rs274
@settings(PROFILE, max_examples=PROFILE.max_examples * 2)
@given(local_programs())
def test_local_programs_match_rs274(text):
    differential.check_same(text, "inprocess", (), _PROGRAM, 5.0, slack=6)


def test_the_generator_reaches_variables():
    # Not a vacuous comparison: the drawn programs do use Python variables.
    from hypothesis import find

    found = find(local_programs(), lambda text: len(variables(text)) >= 2)
    assert variables(found)
