"""Files whose O-words do not nest run line by line (ngc2py/lineflow.py,
runtime/oflow.py): which files do, what their module looks like, and that
they run as rs274 runs them.

The programs below are the minimal forms of what the language campaign
found the nested form could not express (issue 14); golden/oword/lineflow_*
holds them with rs274's recordings.
"""

from __future__ import annotations

import importlib.util
import re

import pytest

import rs274 as harness
import test_differential as differential
from ngc2py import lineflow, parser
from ngc2py.compiler import compile_text
from runtime.errors import SourceMap
from test_codegen import assert_black_stable

_PROGRAM = harness.REPO / "tests" / "_generated" / "lineflow.ngc"

#: name -> (program, rs274's options): files whose O-words do not nest
IRREGULAR = {
    # a do line only the run can tell never ran (behind a counter): the
    # later while line of its label opens a loop of its own
    "do_never_run_behind_a_counter": (
        "#<k> = 0\n#<j> = 0\no2 while [#<k> LT 0]\n  o3 do\n    G0 X9\n  o3 while [0]\n"
        "o2 endwhile\n#<j> = [#<j> + 1]\no3 while [#<j> LT 3]\n  #<j> = [#<j> + 1]\n"
        "  G0 X#<j>\no3 endwhile\nM2\n",
        [],
    ),
    # a skip landing on a do line inside a construct whose opener it
    # passed: rs274 goes on from the do, and the closing line of the
    # opener it skipped finds no label
    "skip_lands_inside_a_construct_it_skipped": (
        "o1 if [1]\n  G0 X1\no1 else\n  o2 while [1]\n    o1 do\n    G0 X2\n"
        "  o2 endwhile\no1 endif\nM2\n",
        [],
    ),
    "jump_lands_inside_a_construct_opened_after_it": (
        "o1 do\n  o1 break\n  G0 X1\no1 while [1]\no1 continue\no5 if [0]\n  o1 do\n"
        "  G0 X2\no5 endif\nM2\n",
        [],
    ),
    # seed 18001 #10: the else after a taken arm lands on an if reusing
    # the label inside a loop of the else arm (a duplicate)
    "else_lands_on_if_in_later_arm": (
        "o1 if [0]\no1 elseif [1]\n  o1 do\n  G0 X1\no1 else\n  o2 do\n"
        "    o1 if [1]\n    o1 endif\n  o2 while [0]\no1 endif\nM2\n",
        [],
    ),
    # seed 18001 #909: a while line reusing a finished do's label ends
    # the do-loop (false: on into its body), so its endwhile is run into
    "while_ending_finished_do_runs_into_endwhile": (
        "#<k> = 0\no1 do\n  #<k> = [#<k> + 1]\no1 while [#<k> LT 2]\no1 while [0]\n"
        "  G0 X1\no1 endwhile X1\nM2\n",
        [],
    ),
    # seed 18001 #1085, #1724: a break's skip lands on an elseif (its
    # condition read) or an endif reusing the loop's label
    "break_lands_on_elseif": (
        "o1 while [1]\n  o1 break\n  o2 if [0]\n    o1 elseif [#<_unset> GT 0]\n"
        "  o2 endif\no1 endwhile\nM2\n",
        [],
    ),
    "break_lands_on_endif": (
        "o1 while [1]\n  o1 break\n  o2 if [0]\n    o1 endif\n  o2 endif\no1 endwhile\nM2\n",
        [],
    ),
    # a block-deleted O-word line under -b is a blank line to rs274
    "deleted_else_under_b": (
        "o1 if [0]\n  G0 X1\n/o1 else\n  G0 X2\no1 endif\nG0 X3\nM2\n",
        ["-b"],
    ),
    "deleted_else_without_b": (
        "o1 if [0]\n  G0 X1\n/o1 else\n  G0 X2\no1 endif\nG0 X3\nM2\n",
        [],
    ),
    # rs274 reads an M98 line in full (its values evaluated) even where
    # it skips over it: in an arm not taken, a definition
    "m98_values_read_while_skipping": (
        "o101 if [0]\n  M98 P1 X[1/#2]\no101 endif\nG0 X3\nM2\n",
        [],
    ),
    "m98_value_read_in_a_definition": (
        "o<s> sub\n  M98 P5 Q[#<_nope> + 1]\no<s> endsub\nM98 P5 Q[#<_nope>]\nM2\n",
        [],
    ),
    # seed 16001 #1984: a Fanuc O-line no M98 runs does nothing, in a file
    # whose O-words do not nest
    "fanuc_line_in_irregular_file": (
        "o77\no1 do\n  o1 break\no2 if [1]\n  o1 if [0]\n  o1 endif\no2 endif\nM2\n",
        [],
    ),
    # a definition read past evaluates its endsub's value (#<_value>)
    "definition_value_in_irregular_file": (
        "o<s> sub\n  o1 if [1]\n  o1 endif\no<s> endsub [7]\n"
        "(DEBUG, v=#<_value> r=#<_value_returned>)\no2 if [1]\no2 else\no2 endif\n"
        "o<s> call\n(DEBUG, v=#<_value>)\no3 do\no3 break\no3 if [1]\nM2\n",
        [],
    ),
    # #<_line> on ordinary lines run together in one branch, after a
    # three-line docstring: the module's map must count every line
    # (LinuxCNC's tests/interp/return-value found it off by two)
    "line_numbers_in_a_run": (
        "o1 sub\no2 if [#1 GT 0]\no2 return [5]\no2 endif\no1 endsub [7]\no1 call [1]\n"
        "(debug,a #<_line>)\n\n(debug,b #<_line>)\nG0 X1\n(debug,c #<_line>)\nM2\n",
        [],
    ),
}

#: files whose O-words nest: the nested form, as before
REGULAR = {
    "loops_and_ifs": (
        "o<s> sub\n  o1 if [#1 GT 1]\n    o<s> return [1]\n  o1 endif\no<s> endsub [2]\n"
        "#<i> = 0\no2 while [#<i> LT 3]\n  #<i> = [#<i> + 1]\n  o3 if [#<i> EQ 2]\n"
        "    o2 continue\n  o3 elseif [#<i> EQ 5]\n    o2 break\n  o3 else\n"
        "    G0 X#<i>\n  o3 endif\no2 endwhile\no4 do\n  o<s> call [#<i>]\n"
        "o4 while [0]\no5 repeat [2]\n  G1 X1 F100\no5 endrepeat\nM2\n"
    ),
    "fanuc_with_reused_label": (
        "o1 if [1]\no1 endif\no1 if [1]\no1 endif\nM98 P100\nM2\nO100\nG0 X1\nM99\n"
    ),
}


def _nests(text: str) -> bool:
    parsed = parser.parse_text(text, "t.ngc", runs=False)
    lines = lineflow._file_lines(list(parsed.lines), parsed.demarcated)
    return lines is None or lineflow.nests(lines)


@pytest.mark.parametrize("name", sorted(IRREGULAR))
def test_irregular_files_run_line_by_line(name):
    text, _ = IRREGULAR[name]
    assert not _nests(text)
    module = compile_text(text, "t.ngc")
    assert "f = m.flow(LINES, at, sub)" in module
    assert_black_stable(module)


@pytest.mark.parametrize("name", sorted(REGULAR))
def test_regular_files_keep_the_nested_form(name):
    module = compile_text(REGULAR[name], "t.ngc")
    assert "m.flow(" not in module


@pytest.mark.parametrize(
    "text",
    [
        "o1 if [1]\no1 endif\no1 if [1]\no1 endif\nM2\n",  # a label used twice
        "o1 while [1]\no2 if [1]\no1 endwhile\no2 endif\nM2\n",  # crossed
        "o1 if [1]\no1 else\no1 elseif [1]\no1 endif\nM2\n",  # elseif after else
        "o1 repeat [2]\no1 break\no1 endrepeat\nM2\n",  # break of a repeat
        "o1 if [1]\no<s> sub\no<s> endsub\no1 endif\nM2\n",  # a definition in an if
        "o<s> return\nM2\n",  # return outside its sub
        "o1 do\no1 endwhile\nM2\n",  # a do closed by endwhile
        "o1 if [1]\nM2\n",  # never closed
    ],
)
def test_what_does_not_nest(text):
    assert not _nests(text)


def _source_map(module: str, tmp_path) -> SourceMap:
    path = tmp_path / "lineflow_module.py"
    path.write_text(module)
    spec = importlib.util.spec_from_file_location("lineflow_module", path)
    loaded = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(loaded)
    return loaded.__ngc__


def _mapped(module: str, tmp_path, pattern: str, after: int = 0):
    """(the G-code line a module line matching ``pattern`` names, the line
    the module's map gives the module line ``after`` lines below it)."""
    source_map = _source_map(module, tmp_path)
    for number, code_line in enumerate(module.splitlines(), 1):
        found = re.match(pattern, code_line)
        if found:
            yield int(found.group(1)), source_map.lookup(number + after).line


def test_every_line_of_the_module_maps_to_its_g_code_line(tmp_path):
    """Each line's branch maps to that line (errors, the O-call stack)."""
    module = compile_text(IRREGULAR["break_lands_on_endif"][0], "t.ngc")
    pairs = list(_mapped(module, tmp_path, r"\s+if at == ([1-9]\d*):$", after=1))
    assert len(pairs) == 3  # the while, the if, M2
    assert all(named == mapped for named, mapped in pairs)


@pytest.mark.parametrize("name", sorted(IRREGULAR))
def test_every_call_maps_to_the_line_it_names(name, tmp_path):
    """A machine call given its G-code line (``m.debug(9, ...)``) sits on a
    module line the map takes to that G-code line: also inside a branch
    that runs several ordinary lines together."""
    module = compile_text(IRREGULAR[name][0], "t.ngc")
    pairs = list(_mapped(module, tmp_path, r"\s+m\.\w+\(([1-9]\d*)[,)]"))
    assert pairs
    assert all(named == mapped for named, mapped in pairs), pairs


@pytest.mark.rs274
@pytest.mark.parametrize("mode", ["inprocess", "convert"])
@pytest.mark.parametrize("name", sorted(IRREGULAR))
def test_irregular_files_run_as_rs274_runs_them(name, mode):
    text, args = IRREGULAR[name]
    differential.check_same(text, mode, args, _PROGRAM)


@pytest.mark.parametrize("irregular", [False, True])
def test_long_names_are_laid_out_as_black_lays_them_out(irregular):
    """A long subroutine name makes the def line and (line by line) its
    LINES entries too long for one line."""
    name = "a" * 70
    text = "o<%s> sub\n  G0 X1\no<%s> endsub\no<%s> call\n" % (name, name, name)
    if irregular:
        text += "/o2 if [0]\no2 endif\n"
    module = compile_text(text + "M2\n", "t.ngc")
    assert ("f = m.flow(LINES, at, sub)" in module) == irregular
    assert_black_stable(module)
