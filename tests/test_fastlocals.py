"""ngc2py.fastlocals: named locals held in Python variables (``i``, ``v_jump``).

The choice is checked on small programs (which names become variables, and
which stay in the store because something could tell the difference), and
programs drawn by a generator made for it -- settings inside loops and ifs,
reads before and after them, break and continue around the setting, do-loop
conditions, subroutines, unset names -- run against rs274.
"""

from __future__ import annotations

import ast
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rs274 as harness
import test_differential as differential
from ngc2py.compiler import compile_text
from test_differential import PROFILE


#: Python variables the code generator writes for itself.
GENERATED = re.compile(r"[ti]\d+|exit_\d+|jump|_|p|g|v")


def variables(text: str) -> set:
    """The G-code names the generated module keeps in Python variables."""
    code = compile_text(text, "p.ngc")
    names = set()
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            if node.id.isupper() or node.id.startswith("__"):
                continue  # module level: SHAPES, ROWS_1, __ngc__
            if not GENERATED.fullmatch(node.id):
                names.add(node.id[2:] if node.id.startswith("v_") else node.id)
    return names


def test_names_are_their_own_variables_unless_taken():
    text = (
        "#<x_start> = 1\n#<jump> = 2\n#<v_a> = 3\n#<t1> = 4\n#<div> = 5\n"
        "#<print> = 6\nG0 X[#<x_start> + #<jump> + #<v_a> + #<t1> + #<div> / 2]\n"
        "G0 X#<print>\nM2\n"
    )
    code = compile_text(text, "p.ngc")
    for line in (
        "x_start = 1.0",
        "v_jump = 2.0",
        "v_v_a = 3.0",
        "v_t1 = 4.0",
        "v_div = 5.0",
        "v_print = 6.0",
    ):
        assert "    %s\n" % line in code
    assert variables(text) == {"x_start", "jump", "v_a", "t1", "div", "print"}


def test_a_name_python_would_fold_stays_in_the_store():
    # Python reads identifiers NFKC-normalised: the ligature would be "fi"
    assert variables("#<\ufb01> = 1\n#<fi> = 2\nG0 X#<\ufb01>\nM2\n") == {"fi"}


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
        ("#<i> = [#<i> + 1]\nM2\n", "rs274 creates it as it reads the setting"),
        ("(debug, #<a>)\n#<a> = 1\nM2\n", "a comment prints it unset"),
        ("#<a> = 1\nG0 X1 (debug, #<a>)\nM2\n", "a block's comment reads the store"),
        ("#<a> = 1\n(py, x = 1)\nM2\n", "embedded Python"),
        ("#<a> = 1\n#<b> = EXISTS[#<a>]\nM2\n", "EXISTS"),
        ("#<_g> = 1\nG0 X#<_g>\nM2\n", "a global"),
        ("o<s> sub\nG0 X#<a>\no<s> endsub\nM2\n", "never set: read from the store"),
        ("o1 if [1]\n#<a> = 1\no1 endif\n(debug, #<a>)\nM2\n", "printed maybe unset"),
        ("o<s> sub\no<s> endsub [#<a>]\n#<a> = 1\nM2\n", "a definition's value"),
        ("o<s> sub\n#<n_args> = 5\no<s> endsub\nM2\n", "OWORD_NARGS: read-only"),
    ],
)
def test_names_that_stay_in_the_store(text, why):
    assert (
        "a" not in variables(text)
        and "i" not in variables(text)
        and "_g" not in variables(text)
    ), why


@pytest.mark.parametrize(
    "text",
    [
        "o1 while [#<i> LT 3]\n#<i> = 1\no1 endwhile\nM2\n",
        "o1 if [1]\n#<i> = 1\no1 endif\nG0 X#<i>\nM2\n",
        "o1 do\n#<i> = 1\no1 while [#<i> LT 0]\nM2\n",
        "G0 X1 #<i> = 2\nG0 X#<i>\nM2\n",
        "/#<i> = 2\nG0 X#<i>\nM2\n",
    ],
)
def test_names_read_maybe_unset_are_variables(text):
    # read unset, the variable fails as the store would (the safety net)
    assert variables(text) == {"i"}


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
        elif kind == 2 and draw(st.booleans()):
            # a comment that prints locals: set ones as values, unset ones
            # as rs274's ######
            names = draw(st.lists(st.sampled_from(_NAMES), min_size=1, max_size=2))
            lines.append("(print, %s)" % " and ".join("#<%s>" % n for n in names))
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


# A name set in one arm of an if and read after it is a Python variable too:
# read unset, the UnboundLocalError becomes the store's error (the safety
# net, runtime.params.unset_variable), also where rs274 goes on after it.
UNSET_AFTER_AN_IF = (
    "o<s> sub\n  o1 if [#1 GT 1]\n    #<geo> = 4\n  o1 endif\n  G0 X#<geo>\n"
    "o<s> endsub\nG21\no<s> call [2]\no<s> call [0]\nG0 X7\nM2\n"
)


def test_a_name_set_in_one_arm_is_a_python_variable():
    assert variables(UNSET_AFTER_AN_IF) == {"geo"}


@pytest.mark.rs274
@pytest.mark.parametrize("args", [[], ["-n", "0"]])
def test_a_python_variable_read_unset_fails_as_rs274(args, tmp_path):
    program = tmp_path / "unset.ngc"
    expected = harness.run_rs274(program, args, text=UNSET_AFTER_AN_IF)
    actual = harness.run_ngc2py(program, args, text=UNSET_AFTER_AN_IF, mode="run")
    assert harness.compare(expected, actual) == []
