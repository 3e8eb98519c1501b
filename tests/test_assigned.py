"""Definite assignment (ngc2py/assigned.py): ``declare`` is left out only
where the name is certainly set, and kept wherever it may not be."""

from __future__ import annotations

import pytest

from ngc2py.compiler import compile_text

INCREMENT = "#<i> = [#<i> + 1]\n"


def declares(program: str) -> int:
    return compile_text(program, "assigned.ngc").count('v.declare("i")')


def test_a_loop_counter_set_before_the_loop_needs_no_declare():
    program = "#<i> = 0\no1 while [#<i> LT 3]\n" + INCREMENT + "o1 endwhile\nM2\n"
    assert declares(program) == 0


@pytest.mark.parametrize(
    "program",
    [
        # never set before
        INCREMENT + "M2\n",
        # set in one arm only
        "o1 if [#1 GT 0]\n#<i> = 1\no1 endif\n" + INCREMENT + "M2\n",
        # set in the body of a loop that may not run
        "o1 while [#1 GT 0]\n#<i> = 1\n#1 = 0\no1 endwhile\n" + INCREMENT + "M2\n",
        # set in the main program, read in a subroutine (its own locals)
        "#<i> = 1\no<s> sub\n" + INCREMENT + "o<s> endsub\no<s> call\nM2\n",
        # set on a line that also moves (its block may fail and go on under -n 0)
        "#<i> = 1 G0 X1\n" + INCREMENT + "M2\n",
        # set on a block-delete line (skipped under -b)
        "/#<i> = 1\n" + INCREMENT + "M2\n",
    ],
    ids=["unset", "one_arm", "loop_body", "other_frame", "with_words", "block_delete"],
)
def test_declare_stays_where_the_name_may_be_unset(program):
    assert declares(program) == 1


def test_every_arm_with_an_else_settles_it():
    program = (
        "o1 if [#1 GT 0]\n#<i> = 1\no1 elseif [#1 LT 0]\n#<i> = 2\n"
        "o1 else\n#<i> = 3\no1 endif\n" + INCREMENT + "M2\n"
    )
    assert declares(program) == 0
