"""The code generator: black-stable, safe, readable, compact for CAM files.

black is the oracle: every generated module must be unchanged by
``black.format_str``. The rs274-marked tests compare runs with rs274.
"""

from __future__ import annotations

import ast
import re
import keyword
import pickle

import black
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hs

from cam_strategies import cam_sized
from ngc2py import codegen, compiler
from ngc2py.codegen import MIN_PROGRAM_ROWS, MIN_VALUE_ROWS
from ngc2py.compiler import compile_text
from runtime.errors import Location, SourceMap

import rs274 as harness


def assert_black_stable(code: str) -> None:
    assert black.format_str(code, mode=black.Mode()) == code


def deep_program(depth: int) -> str:
    """Ifs nested ``depth`` deep inside two loops and a subroutine, with
    breaks, continues and a return from the innermost level (deeper than
    Python nests blocks: the code generator moves inner parts into helpers)."""

    def nest(body: str) -> str:
        opening = "".join("o%d if [1]\n" % (500 + i) for i in range(depth))
        closing = "".join("o%d endif\n" % (500 + i) for i in reversed(range(depth)))
        return opening + body + closing

    return (
        "o<s> sub\n"
        + nest("o<s> return [#1*2]\n")
        + "o<s> endsub [-1]\n#<c>=0\no1 while [#<c> LT 4]\n#<c>=[#<c>+1]\n"
        "#<d>=0\no2 while [#<d> LT 3]\n#<d>=[#<d>+1]\n"
        + nest(
            "(debug,c=#<c> d=#<d>)\no3 if [#<d> EQ 2]\no2 continue\no3 endif\n"
            "o4 if [#<c> EQ 2]\no1 continue\no4 endif\n"
            "o5 if [#<c> EQ 3]\no1 break\no5 endif\nG1 X#<d> F100\n"
        )
        + "o2 endwhile\no1 endwhile\no<s> call [5]\n(debug,v=#<_value>)\nM2\n"
    )


PROGRAMS = {
    "subs_and_loops": (
        "o<drill> sub\nG0 Z[#1]\no<drill> endsub\nG21 G90 (hello)\n#<i> = 0\n"
        "o101 while [#<i> LT 3]\nG1 X[#<i>*10] Y0 F100\no<drill> call [5]\n"
        "#<i> = [#<i> + 1]\no101 endwhile\nM2\n"
    ),
    "conditionals": (
        "#1=2\no1 if [#1 GT 1]\n(debug, one #1)\no1 elseif [#1 EQ 0]\nG0 X1\n"
        "o1 else\nG0 X2\no1 endif\nM2\n"
    ),
    "do_repeat": (
        "#<n>=0\no1 do\n#<n>=[#<n>+1]\no2 if [#<n> EQ 2]\no1 continue\no2 endif\n"
        "o1 while [#<n> LT 4]\no3 repeat [2]\nG91 G0 X1\no3 endrepeat\nM2\n"
    ),
    "long_expressions": (
        "#<a_rather_long_parameter_name>=1\n"
        "G1 X[#<a_rather_long_parameter_name>*2+#<a_rather_long_parameter_name>/3] "
        "Y[SIN[#<a_rather_long_parameter_name>]+COS[#<a_rather_long_parameter_name>]] "
        "Z[ATAN[1]/[2]] F100\nM2\n"
    ),
    "long_headers": (
        "#<a_long_parameter_name>=1\no1 if [#<a_long_parameter_name> GT 1 AND "
        "#<a_long_parameter_name> LT 10 OR #<a_long_parameter_name>]\nG0 X1\n"
        "o1 elseif [#<a_long_parameter_name> GT 1 AND #<a_long_parameter_name> LT 10"
        " OR #<a_long_parameter_name>]\no1 endif\no2 while [#<a_long_parameter_name>"
        " GT 1 AND #<a_long_parameter_name> LT 10 OR #<a_long_parameter_name>]\n"
        "o2 endwhile\nM2\n"
    ),
    "hostile_text": (
        '(msg, """ \'\'\' \\ \\n )\n(print, \')+__import__("os")#)\n'
        "o<x'y> call\n(comment with \x0b and \x1c)\nM2\n"
    ),
    "errors": "G0 Q$\nG1 X[1/0]\no1 endif\nG7.7\nM2\n",
    "labelled_jumps": (
        "o1 do\no2 while [1]\no3 repeat [2]\no1 continue\no2 break\no3 endrepeat\n"
        "o2 endwhile\no1 while [0]\nM2\n"
    ),
    "demarcated": "%\nG0 X1\n%\nG0 X2\n",
    "deep_nesting": deep_program(30),
    "cam": "G21\n" + "".join("G1 X%d Y%d F100\n" % (i, -i) for i in range(30)) + "M2\n",
}


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_generated_modules_are_black_stable_and_compile(name):
    code = compile_text(PROGRAMS[name], name + ".ngc")
    assert_black_stable(code)
    compile(code, name + ".py", "exec")


def test_nesting_of_any_depth_compiles_with_bounded_python_nesting():
    code = compile_text(deep_program(2000), "deep.ngc")
    compile(code, "deep.py", "exec")
    deepest = max(len(line) - len(line.lstrip()) for line in code.splitlines())
    assert deepest <= 4 * (codegen.NEST_LIMIT + 6)


def test_module_shape_follows_the_contract():
    code = compile_text(PROGRAMS["subs_and_loops"], "pocket.ngc")
    assert code.startswith('"""pocket.ngc, compiled by ngc2py')
    assert "def o_drill(m: Machine) -> None:" in code
    assert "    m.move(7, G1, x=finite(i * 10.0), y=0.0, f=100.0)\n" in code
    assert "# 7:" not in code  # the call shows the line: no comment above it
    assert "while i < 3.0:" in code  # a Python variable (ngc2py.fastlocals)
    assert "m.call(o_drill, 5.0)" in code
    assert code.rstrip().endswith("raise SystemExit(run_cli(main, __ngc__))")
    assert "def run(canon=None, **options):" in code


def test_no_source_text_reaches_code_outside_literals_and_comments():
    code = compile_text(PROGRAMS["hostile_text"], "hostile.ngc")
    tree = ast.parse(code)
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    assert "__import__" not in names and "os" not in names
    calls = {
        n.func.attr
        for n in ast.walk(tree)
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)
    }
    assert calls <= {
        "block",
        "call",
        "call_named",
        "define",
        "fail",
        "end_of_file",
        "run",
        "repeat",
        "exists",
        "comment",
        "message",
    }


@settings(max_examples=30, deadline=None)
@given(hs.text(hs.characters(blacklist_categories=("Cs",)), max_size=40))
def test_any_comment_text_is_safe_and_black_stable(text):
    text = text.replace("\n", " ").replace("\r", " ").replace(")", " ")
    code = compile_text("(msg,%s)\n(%s)\nM2\n" % (text, text), "fuzz.ngc")
    compile(code, "fuzz.py", "exec")
    assert_black_stable(code)


@given(hs.text(max_size=30))
def test_string_literals_round_trip(text):
    literal = codegen.string(text)
    assert ast.literal_eval(literal) == text
    assert (
        black.format_str("x = %s\n" % literal, mode=black.Mode())
        == "x = %s\n" % literal
    )


@pytest.mark.parametrize(
    "name", ["drill", "Drill-2", "class", "print", "9lives", "a b", "é"]
)
def test_identifiers_are_sanitised_and_unique(name):
    taken = {"o_drill"}
    ident = codegen.identifier(name, "o_", taken)
    assert ident.isidentifier() and not keyword.iskeyword(ident)
    assert set(ident) <= set("abcdefghijklmnopqrstuvwxyz0123456789_")
    assert ident != "o_drill" and ident in taken


def test_collections_are_laid_out_like_black():
    long = ['"%s"' % ("x" * 30)] * 4
    for items in (["1", "2"], long, [codegen.Coll("(", long, ")"), "3"]):
        for opener in ("value = (", "value = f("):
            code = "\n".join(codegen.Coll(opener, items, ")").layout(0)) + "\n"
            assert_black_stable(code)


def test_line_map_round_trips():
    line_map = codegen.LineMap()
    entries = [(10, 0, 1), (11, 0, 2), (12, 0, 3), (14, 0, 3), (20, 1, 7), (30, 0, 0)]
    for entry in entries:
        line_map.add(*entry)
    source = SourceMap(
        ("a.ngc", "b.ngc"), line_map.encode(), ("l1\nl2\nl3", "\n" * 6 + "l7")
    )
    assert source.lookup(12).line == 3 and source.lookup(12).text == "l3"
    assert source.lookup(15).line == 3
    assert (source.lookup(20).file, source.lookup(20).text) == ("b.ngc", "l7")
    assert source.lookup(30, row_line=2).line == 2
    assert source.lookup(5) is None


def test_a_looked_up_location_reads_its_text_only_when_asked():
    """Flatten names a line on every block: a lookup must not unpack a
    large file's text, yet the location compares, hashes and pickles as
    one made with its text (errors cross process boundaries)."""
    line_map = codegen.LineMap()
    line_map.add(10, 0, 2)
    text = "G0 X1\n(second line)\nM2"
    source = SourceMap(("big.ngc",), line_map.encode(), (text,))
    asked = []
    read = source.text
    source.text = lambda file, line: asked.append(line) or read(file, line)
    found = source.lookup(10)
    assert (found.file, found.line, str(found)) == ("big.ngc", 2, "big.ngc:2")
    assert asked == []
    eager = Location("big.ngc", 2, "(second line)")
    assert found == eager and hash(found) == hash(eager) and asked == [2]
    assert pickle.loads(pickle.dumps(source.lookup(10))) == eager
    assert repr(source.lookup(10)) == repr(eager)


def test_big_cam_files_become_data_rows():
    lines = ["G21 G90"] + ["G1 X%d.5 Y%d F1200" % (i, i % 7) for i in range(3000)]
    lines[1500] = "(halfway)"
    code = compile_text("\n".join(lines + ["M2"]) + "\n", "cam.ngc")
    assert "run_rows(m, SHAPES, ROWS_1, as_printed=True)" in code
    assert "run_rows(m, SHAPES, ROWS_2, as_printed=True)" in code  # after the comment
    # line 3 is "G1 X1.5 Y1 F1200": shape 1 (G1 X Y F) and its values as written
    assert '    ((G1,), ("x", "y", "f")),  # 1: G1 X Y F\n' in code
    # four decimals at most: written as the trace prints them (test_rows.py)
    assert '\nROWS_1 = """\n1 0\n2 1 0.5000 0.0000 1200.0000\n3 1 1.5000 1.0000' in code
    table = code.split('ROWS_1 = """')[1].split('"""')[0]
    assert "G1" not in table and "X" not in table  # no G-code text to parse
    assert_black_stable(code)
    compile(code, "cam.py", "exec")


def test_long_programs_become_chunks_of_bounded_size():
    lines = ["G21 G90 F100"] + ["G1 X[#1 + %d] Y1" % i for i in range(1200)]
    code = compile_text("\n".join(lines + ["M2"]) + "\n", "long.ngc")
    assert code.count("\ndef main_") == 3  # 1201 statements, 500 a function
    assert "\n    main_3(m)\n" in code
    assert_black_stable(code)


def test_row_tables_are_bounded():
    lines = ["G1 X%d Y1 F100" % i for i in range(codegen.ROWS_PER_TABLE + 10)]
    code = compile_text("\n".join(lines + ["M2"]) + "\n", "big.ngc")
    assert "run_rows(m, SHAPES, ROWS_2, as_printed=True)" in code
    assert "ROWS_3" not in code


def test_line_reads_declare_names_and_check_indices_in_order():
    code = compile_text("#<n> = [#<n> + 1]\n#[#1+1]=[#2*3] G0 X#1\nM2\n", "p.ngc")
    assert '    v.declare("n")\n    v.n = v.n + 1.0\n' in code
    assert (
        "    i1 = m.params.setting_index(p[1] + 1.0)\n"
        "    t2 = finite(p[2] * 3.0)\n"
        "    t3 = p[1]\n"
        "    p[i1] = t2\n"
        "    m.rapid(2, x=t3)\n"
    ) in code
    assert_black_stable(code)


def test_plain_settings_stay_plain():
    code = compile_text("#<a>=1\n#2=[#<a>] #<b>=2\n#3=#2\nM2\n", "p.ngc")
    assert "    a = 1.0\n" in code
    assert "    p[2], b = a, 2.0\n" in code
    assert "    p[3] = p[2]\n" in code
    assert "declare" not in code and "setting_index" not in code


# --- readability (issue 13) -------------------------------------------------

PROBE_MACRO = """\
(probe toward -X and store the edge: written for these tests)
o<edge_x> sub
  #<feed> = #1
  #<reach> = #2
  #<x_start> = #5420\t(where we start)
  (DEBUG, start at #<x_start>, reach #<reach>)
  o100 if [#<feed> LE 0]
    (abort, feed must be positive, got #<feed>)
  o100 endif
  G91 G38.2 X-[#<reach>] F[#<feed>]
  o110 if [#5070 EQ 0]
    G90 G0 X#<x_start>
    (abort, probe failed)
  o110 endif
  #<edge> = #5061
  (MSG, edge found)
  (PRINT, edge %.3f#<edge> from %.3f#<x_start>)
  #1005 = #<edge>
  G90 G0 X#<x_start>
o<edge_x> endsub

G21
o<edge_x> call [100] [20]
M2
"""


def code_of(module: str) -> str:
    """The module's code before its source map."""
    return module[: module.index("\n__ngc__ = ")]


def test_comment_lines_are_one_call_each():
    code = compile_text(PROBE_MACRO, "edge.ngc")
    assert (
        '    m.debug(6, " start at #<x_start>, reach #<reach>", x_start=x_start, '
        "reach=reach)\n" in code
    )
    assert '    m.comment(5, "where we start")\n' in code
    assert (
        '        m.abort(8, " feed must be positive, got #<feed>", feed=feed)\n' in code
    )
    assert '        m.abort(13, " probe failed")\n' in code
    assert '    m.message(16, " edge found")\n' in code
    assert (
        '    m.print(17, " edge %.3f#<edge> from %.3f#<x_start>", edge=edge, '
        "x_start=x_start)\n" in code
    )
    assert '    m.comment(1, "probe toward -X and store the edge: written for these tests")\n' in code  # fmt: skip
    assert "Comment(" not in code and "comment=" not in code
    assert_black_stable(code)


def test_each_comment_kind_has_its_own_call():
    text = (
        "(plain)\n(msg,m)\n(debug,d)\n(print,p)\n(log,l)\n(logopen,f)\n"
        "(logappend,f)\n(logclose)\n(pyrun,x)\n(abort,a)\nM2\n"
    )
    code = code_of(compile_text(text, "k.ngc"))
    for line in [
        'm.comment(1, "plain")',
        'm.message(2, "m")',
        'm.debug(3, "d")',
        'm.print(4, "p")',
        'm.log(5, "l")',
        'm.logopen(6, "f")',
        'm.logappend(7, "f")',
        "m.logclose(8)",
        'm.pyrun(9, "x")',
        'm.abort(10, "a")',
    ]:
        assert "    %s\n" % line in code


def test_a_comment_on_a_line_with_words_is_text_or_kind_and_text():
    """A plain comment keeps a move or an arc on its fast path (the comment
    is the block's first call, made there too); any other kind of comment
    sends the line to ``block``."""
    text = "G0 X1 (rapid)\nG0 X2 (msg, two)\nN5 (n)\nG2 X3 R4 (arc)\nM2\n"
    code = compile_text(text, "w.ngc")
    assert '    m.move(1, G0, x=1.0, comment="rapid")\n' in code
    assert '    m.block(2, G0, x=2.0, comment=("msg", " two"))\n' in code
    assert '    m.block(3, n="5", comment="n")\n' in code
    assert '    m.arc(4, G2, x=3.0, r=4.0, comment="arc")\n' in code


def test_interpolating_comments_keep_locals_in_python_variables():
    code = code_of(compile_text(PROBE_MACRO, "edge.ngc"))
    assert "v." not in code and "v[" not in code and "m.locals" not in code
    assert "    x_start = m.params[5420]\n" in code
    assert "    edge = p[5061]\n" in code


def test_no_source_comment_above_a_statement_that_shows_the_line():
    code = code_of(compile_text(PROBE_MACRO, "edge.ngc"))
    assert not re.search(r"^ *# \d+:", code, re.M)
    assert "    m.block(10, G91, G38_2, x=-reach, f=feed)\n" in code


def test_a_macro_is_not_longer_than_its_g_code():
    code = code_of(compile_text(PROBE_MACRO, "edge.ngc"))
    function = code[code.index("def o_edge_x") : code.index("\n\n\ndef main")]
    assert function.count("\n") + 1 <= 19  # o<edge_x>'s lines: 2-20
    assert code.count("\n") <= 1.5 * PROBE_MACRO.count("\n") + 6  # + the header


def test_arithmetic_has_only_the_parentheses_python_needs():
    text = "#<a>=1\n#<b>=2\nG0 X[2470*#<a>+#<b>] Y[#<a>-#<b>+1] Z[#<a>-[#<b>+1]]\nM2\n"
    code = compile_text(text, "e.ngc")
    assert (
        "x=finite(2470.0 * a + b), y=finite(a - b + 1.0), z=finite(a - (b + 1.0))"
        in code
    )


def test_a_macros_set_up_codes_stay_statements():
    text = "o<s> sub\n" + "".join(
        "G%s\n" % g for g in "17 21 54 61 40 49 80 90".split()
    )
    code = compile_text(text + "o<s> endsub\nM2\n", "setup.ngc")
    assert "    m.block(8, G80)\n" in code and "run_rows" not in code
    moves = "G21\n" + "G0 X1\n" * 8 + "M2\n"
    code = compile_text(cam_sized(moves), "moves.ngc")
    assert "run_rows" in code  # moves: data rows from eight on, in a CAM file


def test_a_short_program_reads_as_statements():
    """Below codegen.MIN_PROGRAM_ROWS constant blocks a program is no CAM
    file: its runs of moves are statements, one a line, as a person would
    write them; only a run of MIN_VALUE_ROWS becomes a table there."""
    moves = "".join("G1 X%d Y2 F100\n" % k for k in range(MIN_PROGRAM_ROWS - 3))
    code = code_of(compile_text("G21\n" + moves + "M2\n", "short.ngc"))
    assert "run_rows" not in code
    assert "    m.move(3, G1, x=1.0, y=2.0, f=100.0)\n" in code
    long_run = "".join("G1 X%d Y2 F100\n" % k for k in range(MIN_VALUE_ROWS))
    assert "run_rows" in compile_text("G21\n" + long_run + "M2\n", "long.ngc")
    assert "run_rows" in compile_text(cam_sized("G21\n" + moves + "M2\n"), "cam.ngc")


def test_numbered_parameters_are_written_as_integers():
    code = code_of(compile_text("#<a> = #5420\n#<b> = #5061\n#5420 = 1\n#[5000] = 2\nM2\n", "n.ngc"))  # fmt: skip
    assert "    a = m.params[5420]\n" in code
    assert "    b = p[5061]\n" in code
    assert "5420.0" not in code


def test_functions_bind_only_the_stores_they_use():
    code = compile_text(
        "o<s> sub\nG0 X#1\no<s> endsub\no<s> call [1]\n#<_g> = 2\nG0 X#<_g>\nM2\n",
        "s.ngc",
    )
    assert "    p = m.params.values\n" in code
    assert "    g = m.globals\n" in code
    assert "m.locals" not in code
    code = compile_text("G0 X1\nM2\n", "plain.ngc")
    assert "m.params" not in code and "m.globals" not in code


# --- against rs274 ----------------------------------------------------------

RUNS = [
    "#1=1 #2=2 G0 X#1 Y#2 #1=3\nG0 X#1\nM2\n",
    "#<a>=1\n#<a>=2 #<b>=#<a>\nG0 X#<b>\nM2\n",
    "o<s> sub\n#<x>=#1\no<s> return [#<x>*2]\no<s> endsub\no<s> call [4]\n"
    "G0 X#<_value>\nM2\n",
    "o<s> sub\nG0 X[1/#1]\no<s> endsub\no<s> call [1]\no<s> call [0]\nM2\n",
    "G21\n" + "".join("G1 X%d Y1 F100\n" % i for i in range(12)) + "G1 X1 Q[1/0]\nM2\n",
    "G21\n" + "".join("G1 X%d Y1 F100\n" % i for i in range(12)) + "G2 X10 Y10\nM2\n",
    "G0 X1\n/G0 X2\n/#1=5\nG0 Y#1\nM2\n",
    "%\nG0 X1\n%\nG0 X3\n",
    "G0 X1\n",
    # a name being set exists (as 0) for the rest of its line
    "#<a>=1 #2=#<a>\n(debug,#2 #<a>)\nM2\n",
    "#<n> = [#<n> + 1]\nG0 X#<n>\n#<_g>=[#<_g>+2] #<m>=[EXISTS[#<_g>]]\nG0 Y#<_g> Z#<m>\nM2\n",
    "G0 X#<n> #<n>=1\nM2\n",
    # a setting's index is checked before its value is read
    "#1=0\n#[#1]=[1/0]\nM2\n",
    "#1=5500\n#[#1]=[1/0]\nM2\n",
    "#2=[1/0] #[#1+5]=1\nM2\n",
    "#1=3 #[#1]=[#1+1] #2=#3\nG0 X#1 Y#2 Z#3\nM2\n",
    # checks at closing brackets
    "G0 X[[10**400]*0]\nM2\n",
    "G0 X[10**400*0]\nM2\n",
    "#1=[10**400*0]\nM2\n",
    # nested deeper than Python allows: jumps and returns leave helpers
    deep_program(25),
    # rs274 fails reading a bad line even while skipping over it
    "o100 if [0]\nG0 X1 (a \no100 elseif [1]\nG0 X2\no100 endif\nM2\n",
    "o100 if [0]\nG0 X1\no100 elseif [1]\nG0 X2\no100 else\n(a (b)\no100 endif\nM2\n",
    "o100 while [1]\no100 break\n(a (b))\no100 endwhile\nM2\n",
    "o100 repeat [2]\nG0 X1\no101 if [0]\n(a (b)\no101 endif\no100 endrepeat\nM2\n",
    "o1 if [0]\nG0 X" + "1" * 300 + "\no1 endif\nM2\n",
    # N words in data rows print as written
    "G21\n" + "".join("N%03d G1 X%d Y1 F100\n" % (i, i) for i in range(12)) + "M2\n",
    # comment lines: each kind, locals in Python variables handed to the
    # text (set, set on the line itself, unset, a global), in a subroutine
    "#5599=1\no<s> sub\n#<x> = #1 (debug, x=#<x> y=#<y> g=#<_g>)\n"
    "(print, %.2f#<x> #<x>)\n#<y> = [#<x> + 1]\n(debug, #<y>%d #<x>)\n"
    "(log, #<y>)\n(msg, #<y>)\n(logopen, f.txt)\n(logclose)\no<s> endsub\n"
    "#<_g> = 3\n#<x> = 7\no<s> call [2]\n(debug, main x=#<x> y=#<y>)\nM2\n",
    "o<s> sub\n#<a> = [#1 * 2]\no1 if [#<a> GT 3]\n  (abort, a is %d#<a>)\no1 endif\n"
    "o<s> endsub\no<s> call [1]\no<s> call [2]\nM2\n",
    "#<a> = 1 (a comment on a setting)\nN10 (print, n #<a>)\n( )\n()\nG0 X#<a> (print, #<a>)\nM2\n",
    "G21 (a)\n#5420 = 1\nM2\n",
    "G0 X1\n#<x> = #5420\nG41 D1\n#<y> = #5420\nM2\n",
    # grouping: Python's precedence where it equals the parser's, else ()
    "#<a>=3\n#<b>=0.1\nG0 X[#<a>*[#<b>*3]] Y[[#<a>*#<b>]*3] Z[#<a>-[#<b>-1]]\n"
    "G0 X[#<a>-#<b>-1] Y[#<a>*#<b>+#<a>*#<b>*#<b>] Z[-[#<a>-#<b>]*#<b>]\nM2\n",
]


@pytest.mark.rs274
@pytest.mark.parametrize("text", RUNS)
@pytest.mark.parametrize("mode", ["run", "convert"])
def test_generated_code_runs_like_rs274(text, mode, tmp_path):
    program = tmp_path / "t.ngc"
    for args in ([], ["-b"]):
        expected = harness.run_rs274(program, args, text=text)
        actual = harness.run_ngc2py(program, args, text=text, mode=mode)
        assert harness.compare(expected, actual) == []


def test_arcs_with_computed_words_call_machine_arc():
    code = compile_text(
        "G17 G1 X0 Y0 F100\nG2 X[1 + 1] Y0 I1 J0\nG3 X0 Y0 R5 F[50]\nG2 X1 P2 I1\nM2\n"
    )
    assert "m.arc(2, G2, x=2.0, y=0.0, i=1.0, j=0.0)" in code
    assert "m.arc(3, G3, x=0.0, y=0.0, r=5.0, f=50.0)" in code
    assert "m.block(4, G2, x=1.0, p=2.0, i=1.0)" in code  # P (turns): the general path


@pytest.mark.rs274
@pytest.mark.parametrize("where", ["row", "statement"])
def test_a_large_files_text_is_packed_and_errors_still_show_their_line(where, tmp_path):
    """Above codegen.PACK_TEXT_OVER the G-code text goes into the source map
    compressed; an error must still print rs274's message and line text,
    wherever the failing line is (a data row or a statement)."""
    rows = ["G1 X%d.25 Y%d (moving \u00e9 %d)" % (k, k % 7, k) for k in range(4000)]
    bad = "G1 X1 F0" if where == "row" else "#1 = [1 / 0]"
    rows[3210] = bad
    text = "G21 G90 G17 F100\nG0 Z5\n" + "\n".join(rows) + "\nM2\n"
    assert len(text) > codegen.PACK_TEXT_OVER
    code = compile_text(text, "big.ngc")
    assert "_NGC_TEXT_0 = b" in code and bad not in code.split("__ngc__")[-1]
    assert black.format_str(code, mode=black.Mode()) == code
    program = tmp_path / "big.ngc"
    program.write_text(text, encoding="utf-8")
    expected = harness.run_rs274(program)
    actual = harness.run_ngc2py(program, mode="convert")
    assert not harness.compare(expected, actual)
    assert bad in actual.stderr.decode()


@pytest.mark.rs274
@pytest.mark.parametrize("where", ["row", "statement", "last line"])
def test_the_caches_modules_keep_a_large_text_as_it_is(where, tmp_path, monkeypatch):
    """The compile cache's modules take a large G-code text as it is
    (codegen.plain_literal: it is never tokenized, and compressing it cost
    a large file's first run); errors still show rs274's message and the
    line's text, from a cached run and from a first one."""
    rows = ["G1 X%d.25 Y%d (moving %d)" % (k, k % 7, k) for k in range(4000)]
    bad = "G1 X1 F0" if where == "row" else "#1 = [1 / 0]"
    if where == "last line":
        rows.append(bad)  # (no M2 after it: the text's last line)
    else:
        rows[3210] = bad
    text = "G21 G90 G17 F100\nG0 Z5\n" + "\n".join(rows) + "\n"
    text += "" if where == "last line" else "M2\n"
    assert len(text) > codegen.PACK_TEXT_OVER
    program = tmp_path / "big.ngc"
    program.write_text(text, encoding="utf-8")
    compiled = compiler.compile_program(str(program), pack=False).text
    assert '_NGC_TEXT_0 = """\\\n' in compiled
    assert bad in compiled.split('_NGC_TEXT_0 = """')[1]  # (in the text)
    assert black.format_str(compiled, mode=black.Mode()) == compiled
    expected = harness.run_rs274(program)
    monkeypatch.setenv("NGC2PY_CACHE", str(tmp_path / "cache"))
    for _ in range(2):  # compiled into the cache, then from it
        actual = harness.run_ngc2py(program, mode="run")
        assert not harness.compare(expected, actual)
        assert bad in actual.stderr.decode()


@pytest.mark.parametrize(
    "text",
    [
        'G0 X1 (a "quoted" word)\n',
        "G0 X1 (back\\slash)\n",
        "G0 X1\r\n",
        "G0 X1 (caf\u00e9)\n",
        "G0 X1 (\udcff)\n",
        "G0 X1 (\x00)\n",
    ],
)
def test_a_text_the_literal_cannot_hold_as_it_is_is_packed(text):
    """Whatever could end or change a plain literal (a quote, a backslash,
    a carriage return, a character past ASCII, NUL) sends the text to the
    packed literal, which holds anything."""
    assert codegen.plain_literal("G21\n" + text * 2000) is None
    assert codegen.plain_literal("G21\n" + "G0 X1 (plain)\n" * 2000) is not None


@pytest.mark.rs274
@pytest.mark.parametrize("blank_lines", [0, 3, 3000])
@pytest.mark.parametrize("closed", [False, True])
def test_a_large_percent_file_without_its_closing_percent(
    blank_lines, closed, tmp_path
):
    """A program end asks whether the main file opens with a % line (then a
    missing closing % earns rs274's comment): for a packed text that is read
    from the start of the packed bytes, or from the whole text when the
    start is all blank lines (``blank_lines`` before the %)."""
    rows = ["G0 X%d Y%d" % (k, k % 7) for k in range(8000)]
    text = (
        "\n" * blank_lines
        + "%\n"
        + "\n".join(rows)
        + "\nM2\n"
        + ("%\n" if closed else "")
    )
    code = compile_text(text, "big.ngc")
    assert "_NGC_TEXT_0 = b" in code
    program = tmp_path / "big.ngc"
    program.write_text(text)
    expected = harness.run_rs274(program)
    actual = harness.run_ngc2py(program, mode="convert")
    assert not harness.compare(expected, actual)
    assert (b"percent sign missing" in actual.stdout) is not closed


#: Modes in which Machine.feed/rapid must step aside to the general path
#: (not plain: runtime.fast.moves) or fail as rs274 does.
_FEED_CASES = [
    "G21 F100\n#<i>=1\nG1 X#<i> Y2\nG0 Z[#<i>+1]\nM2\n",
    "G21 G91 F100\n#<i>=1\nG1 X#<i> Y2\nG0 Z[#<i>]\nG1 X#<i>\nM2\n",  # incremental
    "G21\n#<i>=1\nG1 X#<i>\nM2\n",  # no feed rate: rs274's error
    "G21 G93\n#<i>=1\nG1 X#<i> F10\nG1 Y#<i>\nM2\n",  # inverse time: F on each line
    "G21 F100 T1 M6 G43\n#<i>=1\nG41 D1\nG1 X#<i> Y5\nG1 X[#<i>+4]\nG40\nG0 Z#<i>\nM2\n",
    "G21 F100\n#<i>=1\nG8 G1 X#<i>\nG7 G1 X#<i>\nG0 Z#<i>\nM2\n",  # diameter mode
    "G21 F100\nG81 X1 Y1 Z-1 R1\n#<i>=2\nG0 Z#<i>\nG1 X#<i>\nM2\n",  # ends a cycle
]


@pytest.mark.rs274
@pytest.mark.parametrize("text", _FEED_CASES)
def test_feed_and_rapid_calls_step_aside_like_move(text, tmp_path):
    code = compile_text(text, "t.ngc")
    assert "m.feed(" in code or "m.rapid(" in code
    program = tmp_path / "t.ngc"
    (tmp_path / "t.tbl").write_text("T1 P1 D2 Z1\n")
    expected = harness.run_rs274(program, ["-t", "t.tbl"], text=text)
    actual = harness.run_ngc2py(program, ["-t", "t.tbl"], text=text, mode="convert")
    assert harness.compare(expected, actual) == []


def test_tabs_in_the_source_comments_read_as_spaces(tmp_path):
    """A G-code line's tabs show in its ``# n:`` comment as an editor shows
    them, never as an escape; other control characters stay escaped. A
    comment's text keeps its tab (rs274 prints it) as black's ``\\t``."""
    from ngc2py.compiler import compile_file

    program = tmp_path / "tabs.ngc"
    program.write_bytes(b"G21\tG90\n(a\tcomment\x07)\nG0\tX1\nG0\tX[1\x07\nM2\n")
    text = compile_file(str(program))
    assert "# 4: G0      X[1\\x07\n" in text
    assert "\\x09" not in text and "\t" not in text
    assert '    m.comment(2, "a\\tcomment\\x07")\n' in text
