"""Differential tests from the language: the line format and O-word structures.

``strategies.language_programs()`` writes programs from the G Code
Overview's line format and the O Codes chapter (see the comment above it in
tests/strategies.py): every kind of line with or without a block delete
slash, a line number, comments (empty, blank, plain, active, several, `;`),
O-word lines carrying line numbers and comments, and while / do-while /
repeat loops and if / elseif / else nested in each other, with break,
continue and return at every depth, in subroutines and the main program.
Some reuse a label or leave a loop unclosed on purpose. Each program runs
through the live rs274 and ngc2py (half of them with block delete on, -b);
stdout must be byte-identical, with the same exit status and error message.

``long_programs()`` and ``long_error_programs()`` (tests/long_programs.py)
write long programs, with one mistake in the second kind.

Profiles as in tests/test_differential.py: ``ci`` (the default) is
derandomised, so CI sees the same examples every run.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings

import rs274 as harness
import strategies
import test_differential as differential
from test_differential import PROFILE

pytestmark = pytest.mark.rs274

#: rs274 on a generated program: a reused do-label can make it loop for a
#: long time; such examples are discarded (no reference to compare with).
TIMEOUT = 5.0

_PROGRAM = harness.REPO / "tests" / "_generated" / "lang.ngc"


def check_same(text: str, args, mode: str) -> None:
    differential.check_same(text, mode, args, _PROGRAM, TIMEOUT, slack=6)


@settings(PROFILE, max_examples=PROFILE.max_examples * 3)
@given(strategies.language_programs())
def test_language_programs(program):
    text, args = program
    check_same(text, args, "inprocess")


@settings(PROFILE, max_examples=max(5, PROFILE.max_examples // 4))
@given(strategies.language_programs(max_statements=5))
def test_language_programs_converted(program):
    """The generated module on its own, not only `ngc2py run`."""
    text, args = program
    check_same(text, args, "convert")


@settings(PROFILE, max_examples=max(3, PROFILE.max_examples // 8))
@given(strategies.long_programs())
def test_long_programs(program):
    """Long programs: 20-60 subroutines, deep nesting (past the code
    generator's nesting limit), jumps at every depth. Few examples: each is
    thousands of lines."""
    text, args = program
    check_same(text, args, "inprocess")


@settings(PROFILE, max_examples=max(3, PROFILE.max_examples // 8))
@given(strategies.long_error_programs())
def test_long_error_programs(program):
    """The same with one mistake somewhere: same failure, same point."""
    text, args = program
    check_same(text, args, "inprocess")


# A skip that lands inside another construct. rs274 skips an untaken arm to
# the next line with the arm's label and runs on from there even when that
# line (a `do` reusing the label) sits inside another, unevaluated `if`;
# its `while` then fails as a duplicate of the first `if`. Found by
# test_language_programs (once a strict xfail: ngc2py landed a skip only on
# a do directly in a lone first arm); golden/oword/skip_lands_* pin the
# other shapes of the class (st.If.landings).
NESTED_LANDING = """\
o101 if [#1 GT 0]
  G0 X1
o101 elseif [1 EQ 1]
  G0 Y1
o101 elseif [1 EQ 1]
  G0 Y2
o101 else
  o110 if [0]
    o101 do
      #<_k5> = [#<_k5> + 1]
    o101 while [#<_k5> LT 3]
  o110 endif
o101 endif
o113 else X1
M2
"""


@pytest.mark.rs274
def test_a_skip_lands_on_a_do_inside_a_nested_if():
    check_same("#<_k5> = 0\n" + NESTED_LANDING, [], "inprocess")


# The strict known gaps of issue 14 (an M98 line read while skipping, a do
# line only the run can tell never ran, skips landing inside a construct
# whose opener they passed) went when files whose O-words do not nest began
# to run line by line: their minimal programs are in tests/test_lineflow.py.


# Found by the long_error campaign of seed 19201 (#2984), reduced by hand:
# reading past a definition sets #<_value> and #<_value_returned> from its
# endsub's value, and a call of that subroutine keeps them (rs274 clears
# the flag as a call begins only for Python subs: interp_o_word.cc), so
# inside it rs274 prints 5 and 1.
VALUE_KEPT_BY_A_CALL = """\
o<s3> sub
(DEBUG,returned #<_value> #<_value_returned>)
o<s3> endsub [5]
o<s3> call
(DEBUG,after #<_value> #<_value_returned>)
o<s3> call [2]
M2
"""


@pytest.mark.rs274
def test_a_call_keeps_the_value_a_skipped_endsub_returned():
    check_same(VALUE_KEPT_BY_A_CALL, [], "inprocess")
