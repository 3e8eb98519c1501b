"""Bad and hostile input: the product's guarantees, tested honestly.

1. Any input ends cleanly: the same stdout / exit status / first error line
   as ``rs274 -g`` where rs274 answers, a clean exit-1 error where rs274
   crashes or hangs -- never a Python traceback, an "internal error" or a hang.
2. Code generation cannot be injected: comments, messages, parameter names,
   subroutine names and file names never become code; generated modules
   compile, are black-stable, use only the runtime API, and trace like rs274.
3. Determinism: same input -> same module text and same output, whatever the
   working directory or hash seed.
4. Nothing the user had is lost: failed conversions leave an existing output
   alone, the source is never overwritten, the ``-v`` file is rewritten like
   rs274 rewrites it.

Helpers live in tests/hostile_inputs.py. Tests that need rs274 are marked
``rs274`` and skip (with a reason) when it is not installed.
"""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parent))

import hostile_inputs as h  # noqa: E402
from hostile_inputs import Workdir, compare_programs  # noqa: E402

HAVE_RS274 = h.rs274_exe() is not None
needs_rs274 = [
    pytest.mark.rs274,
    pytest.mark.skipif(not HAVE_RS274, reason="rs274 not on PATH: needs LinuxCNC's rs274"),
]


def rs274_test(fn):
    for mark in needs_rs274:
        fn = mark(fn)
    return fn


def assert_same_as_rs274(files, program="prog.ngc", options=()):
    problems = compare_programs(files, program, options)
    assert not problems, "\n".join(problems)


FUZZ = dict(
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
    database=None,
)

# ==========================================================================
# 1. Malformed input: same answer as rs274, never a traceback or a hang
# ==========================================================================

NESTED_BRACKETS_FIT = "#1=" + "[" * 120 + "1" + "]" * 120 + "\n(DEBUG,#1)\nM2\n"
NESTED_BRACKETS_5000 = "G0 X1\n#1=" + "[" * 5000 + "1" + "]" * 5000 + "\nM2\n"

MALFORMED = {
    "cr_only_line_endings": b"G0 X1\rG1 X2 F10\rM2\r",
    "crlf_line_endings": b"G0 X1\r\nG1 X2 F10\r\nM2\r\n",
    "nul_byte_mid_line": b"G0 X1\x00junk\nM2\n",
    "nul_bytes_only_line": b"G0 X1\n\x00\x00\x00\nM2\n",
    "invalid_utf8": b"G0 X1\xff\xfe\nM2\n",
    "invalid_utf8_in_comment": b"G0 X1 (\xff\xfe\xc3)\n(MSG,\xc3\x28)\nM2\n",
    "unterminated_comment": b"G0 X1 (unterminated\nM2\n",
    "unterminated_comment_last_line": b"G0 X1\nM2 (",
    "unclosed_bracket": b"G0 X[1+2\nM2\n",
    "unopened_bracket": b"G0 X1+2]\nM2\n",
    "unterminated_named_param": b"#<abc = 1\nM2\n",
    "unknown_letter": b"G0 X1\nQ1\nM2\n",
    "unknown_letter_u_in_word": b"G0 X1 \xc2\xa7 Y2\nM2\n",
    "exponent_1e400": b"G0 X1e400\nM2\n",
    "number_240_digits": ("#1=" + "9" * 240 + "\n(DEBUG,#1)\nG0 X#1\nM2\n").encode(),
    "product_overflows_to_inf": (
        "#1=[" + "9" * 120 + "*" + "9" * 120 + "]\n(DEBUG,#1)\nM2\n"
    ).encode(),
    "nested_brackets_120_levels": NESTED_BRACKETS_FIT.encode(),
    "nested_brackets_5000_levels_line_2": NESTED_BRACKETS_5000.encode(),
    "line_2_of_253_chars": ("G21\nG0 X1 (" + "a" * 245 + ")\nM2\n").encode(),
    "line_2_of_254_chars": ("G21\nG0 X1 (" + "a" * 246 + ")\nM2\n").encode(),
    "ten_mb_single_line_2": b"G0 X1\n#1=" + b"9" * 10_000_000 + b"\nM2\n",
    "ten_mb_comment_line_2": b"G0 X1\n(" + b"a" * 10_000_000 + b"\nM2\n",
    "only_percent": b"%\n",
    "percent_unclosed": b"%\nG0 X1\nM2\n",
    "form_feed_vertical_tab": b"G0\x0cX1\x0b\nM2\n",
    "tabs_and_spaces": b"\t G0 \t X 1 \t\nM2\n",
    "control_chars": b"G0 X1\x01\nM2\n",
    "del_char": b"G0 X1\x7f\nM2\n",
    "only_blank_lines": b"\n\n   \n\t\n",
    "no_trailing_newline": b"G0 X1\nM2",
    "no_program_end": b"G0 X1\n",
    "o_word_garbage": b"o<> sub\nM2\n",
    "o_word_unclosed_name": b"o<abc sub\nM2\n",
    "endsub_without_sub": b"o100 endsub\nM2\n",
    "endif_without_if": b"o100 endif\nM2\n",
    "if_without_endif": b"o100 if [1]\nG0 X1\nM2\n",
    "while_without_endwhile": b"o100 while [0]\nG0 X1\nM2\n",
    "call_undefined_sub": b"o<nowhere> call\nM2\n",
    "huge_n_number": b"N99999999999999999999 G0 X1\nM2\n",
    "huge_g_code": b"G99999999999999999999\nM2\n",
    "g_code_from_huge_expression": ("G[" + "9" * 200 + "]\nM2\n").encode(),
    "numbered_param_huge_index": ("#" + "9" * 200 + "=1\nM2\n").encode(),
    "numbered_param_negative_index": b"#-1=1\nM2\n",
    "undefined_named_param": b"G0 X#<nowhere>\nM2\n",
    "dynamic_call_of_huge_number": ("o[" + "9" * 100 + "] call\nM2\n").encode(),
    "logopen_hostile_name": b'(LOGOPEN,a"b\\c\x27d.log)\n(LOG,"""x)\n(LOGCLOSE)\nM2\n',
    "division_by_zero": b"#1=[1/0]\nM2\n",
    "sqrt_negative": b"#1=SQRT[-1]\nM2\n",
    "exp_overflow": b"#1=EXP[1000]\n(DEBUG,#1)\nM2\n",
    "power_overflow": b"#1=[10**400]\n(DEBUG,#1)\nM2\n",
    "bare_o_number_line": b"G21\nO8\nG0 X1\nM2\n",
    "m98_call_of_missing_program": b"G21\nM98 P8\nM2\n",
    "utf8_named_param": "#<\u00e9t\u00e9>=1\n(DEBUG,#<\u00e9t\u00e9>)\nM2\n".encode(),
}


@rs274_test
@pytest.mark.parametrize("name", sorted(MALFORMED))
def test_malformed_input_matches_rs274(name):
    assert_same_as_rs274({"prog.ngc": MALFORMED[name]})


@rs274_test
def test_empty_file_matches_rs274():
    """rs274: 5 init calls, then "File ended with no percent sign", exit 1."""
    assert_same_as_rs274({"prog.ngc": b""})


@rs274_test
def test_random_binary_first_line_too_long_matches_rs274():
    """A first line longer than rs274's buffer fails while the file is
    opened: rs274 prints only the 5 init calls (no ON_RESET) and exits 1."""
    line = bytes(b for b in range(1, 256) if b != 10) * 8
    assert_same_as_rs274({"prog.ngc": line + b"\nM2\n"})


@rs274_test
def test_nested_brackets_5000_levels_on_first_line_matches_rs274():
    assert_same_as_rs274({"prog.ngc": ("#1=" + "[" * 5000 + "1" + "]" * 5000 + "\nM2\n").encode()})


@rs274_test
def test_ten_mb_single_line_first_line_matches_rs274():
    assert_same_as_rs274({"prog.ngc": b"G0 X" + b"1" * 10_000_000 + b"\nM2\n"})


@rs274_test
def test_invalid_utf8_offending_line_is_echoed_as_raw_bytes_like_rs274():
    """rs274 echoes the offending line's bytes; escaping them (\\udcff) is
    not what rs274 prints."""
    files = {"prog.ngc": b"G0 X1\xff\xfe\nM2\n"}
    with Workdir(files) as a, Workdir(files) as b:
        expected = a.rs274("prog.ngc")
        actual = b.ngc2py("run", "prog.ngc")
    h.assert_clean(actual)
    assert expected.error_lines()[:2] == actual.error_lines()[:2]


def nested_blocks(depth: int, kind: str) -> bytes:
    opening = {"if": "o%d if [1]", "while": "o%d while [#<n%d> LT 1]", "do": "o%d do"}
    lines = []
    for i in range(depth):
        if kind == "while":
            lines.append("#<n%d> = 0" % i)
            lines.append("o%d while [#<n%d> LT 1]" % (100 + i, i))
            lines.append("#<n%d> = 1" % i)
        else:
            lines.append(opening[kind] % (100 + i))
    lines.append("G0 X1")
    for i in reversed(range(depth)):
        closing = {"if": "o%d endif", "while": "o%d endwhile", "do": "o%d while [0]"}
        lines.append(closing[kind] % (100 + i))
    lines.append("M2")
    return ("\n".join(lines) + "\n").encode()


@rs274_test
@pytest.mark.parametrize(
    "depth,kind",
    [(18, "if"), (19, "if"), (25, "while"), (25, "do"), (100, "if"), (5000, "if")],
)
def test_deeply_nested_o_word_blocks_match_rs274(depth, kind):
    """rs274 has no nesting limit for if/while/do; Python does (about 20
    statically nested blocks, and the recursion limit)."""
    assert_same_as_rs274({"prog.ngc": nested_blocks(depth, kind)})


@rs274_test
def test_deeply_nested_subroutine_definitions_match_rs274():
    lines = []
    for i in range(40):
        lines.append("o<s%d> sub" % i)
    lines.append("G0 X1")
    for i in reversed(range(40)):
        lines.append("o<s%d> endsub" % i)
    lines.append("o<s0> call")
    lines.append("M2")
    assert_same_as_rs274({"prog.ngc": ("\n".join(lines) + "\n").encode()})


@rs274_test
def test_unbounded_recursion_matches_rs274():
    prog = b"o<r> sub\no<r> call\no<r> endsub\no<r> call\nM2\n"
    assert_same_as_rs274({"prog.ngc": prog})


@rs274_test
def test_many_lines_run_in_bounded_time():
    """100k short lines: no quadratic blow-up, no hang (60 s limit)."""
    body = b"".join(b"G1 X%d F100\n" % (i % 50) for i in range(100_000))
    assert_same_as_rs274({"prog.ngc": b"G21\n" + body + b"M2\n"})


# --- the program file itself is unusable ----------------------------------


@rs274_test
def test_missing_program_matches_rs274():
    """rs274 prints the 5 init calls, then "Unable to open file <x>"."""
    with Workdir() as a, Workdir() as b:
        expected = a.rs274("missing.ngc")
        actual = b.ngc2py("run", "missing.ngc")
    assert not h.differences(expected, actual), "\n".join(h.differences(expected, actual))


@rs274_test
def test_directory_as_program_matches_rs274():
    """rs274 opens a directory, reads nothing: "File ended with no percent
    sign" after the 5 init calls."""
    with Workdir() as a, Workdir() as b:
        (a.work / "dir.ngc").mkdir()
        (b.work / "dir.ngc").mkdir()
        expected = a.rs274("dir.ngc")
        actual = b.ngc2py("run", "dir.ngc")
    assert not h.differences(expected, actual), "\n".join(h.differences(expected, actual))


@pytest.mark.parametrize("command", ["run", "convert"])
def test_directory_or_missing_program_is_clean(command):
    """A clean error that names the file. The first error line is rs274's
    wording where rs274 has one (for a directory: 'File ended with no
    percent sign', see test_directory_as_program_matches_rs274), so the
    name is looked for in the whole of stderr."""
    with Workdir() as w:
        (w.work / "dir.ngc").mkdir()
        for name in ("dir.ngc", "missing.ngc"):
            out = w.ngc2py(command, name)
            h.assert_clean(out)
            assert out.rc == 1 and name.encode() in out.stderr


def _rs274_on_unreadable_file() -> h.Outcome:
    """rs274 on a chmod-000 program, as an unprivileged user (root reads
    anything, so as root the run is done as ``nobody``)."""
    w = Workdir({"prog.ngc": b"G0 X1\nM2\n"})
    try:
        os.chmod(w.work / "prog.ngc", 0)
        if os.geteuid() != 0:
            return w.rs274("prog.ngc")
        import pwd

        nobody = pwd.getpwnam("nobody").pw_uid
        for p in (w.root, w.work, w.home):
            os.chmod(p, 0o777)
        return w.rs274("prog.ngc", user=nobody)
    finally:
        w.cleanup()


@rs274_test
def test_unreadable_program_matches_rs274(monkeypatch, tmp_path, capsys):
    """Emulated for root: ngc2py runs in-process with every open() of the
    program failing with EACCES (what chmod 000 does to a normal user);
    rs274 runs as ``nobody`` on a chmod-000 file."""
    import builtins
    import io

    from ngc2py import cli

    expected = _rs274_on_unreadable_file()
    program = tmp_path / "prog.ngc"
    program.write_bytes(b"G0 X1\nM2\n")
    real_open, real_io_open = builtins.open, io.open

    def denied(opener):
        def fake(file, *args, **kwargs):
            if isinstance(file, (str, bytes, os.PathLike)) and Path(os.fsdecode(file)).resolve() == program:
                raise PermissionError(13, "Permission denied", os.fsdecode(file))
            return opener(file, *args, **kwargs)

        return fake

    monkeypatch.setattr(builtins, "open", denied(real_open))
    monkeypatch.setattr(io, "open", denied(real_io_open))
    monkeypatch.setenv("NGC2PY_CACHE", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    rc = cli.main(["run", "prog.ngc"])
    captured = capsys.readouterr()
    actual = h.Outcome(captured.out.encode(), captured.err.encode(), rc)
    problems = h.differences(expected, actual)
    assert not problems, "\n".join(problems)


# --- the option files are missing or unusable -----------------------------

OPTION_CASES = {
    "missing_tool_table": ["-t", "nope.tbl"],
    "missing_var_file": ["-v", "nope.var"],
    "missing_ini": ["-i", "nope.ini"],
    "directory_tool_table": ["-t", "adir"],
    "directory_var_file": ["-v", "adir"],
    "directory_ini": ["-i", "adir"],
    "binary_tool_table": ["-t", "junk.bin"],
    "binary_var_file": ["-v", "junk.bin"],
    "binary_ini": ["-i", "junk.bin"],
}


@rs274_test
@pytest.mark.parametrize("case", sorted(OPTION_CASES))
def test_bad_option_files_match_rs274(case):
    options = OPTION_CASES[case]
    files = {"prog.ngc": b"G0 X1\nT1 M6\nM2\n", "junk.bin": bytes(range(256)) * 4}
    with Workdir(files) as a, Workdir(files) as b:
        (a.work / "adir").mkdir()
        (b.work / "adir").mkdir()
        expected = a.rs274(*options, "prog.ngc")
        actual = b.ngc2py("run", "prog.ngc", *options)
    problems = h.judge(expected, actual)
    assert not problems, "\n".join(problems)


@rs274_test
def test_binary_tool_table_where_rs274_segfaults_is_a_clean_error():
    """rs274 dies with SIGSEGV on a binary tool table followed by T1 M6;
    ngc2py must do better: exit 1 with a G-code message, no traceback."""
    files = {"prog.ngc": b"G0 X1\nT1 M6\nM2\n", "junk.bin": bytes(range(256)) * 4}
    with Workdir(files) as a, Workdir(files) as b:
        expected = a.rs274("-t", "junk.bin", "prog.ngc")
        actual = b.ngc2py("run", "prog.ngc", "-t", "junk.bin")
    problems = h.judge(expected, actual)
    assert not problems, "\n".join(problems)
    if expected.crashed:
        assert actual.rc == 1 and actual.err


@pytest.mark.parametrize("case", sorted(OPTION_CASES))
def test_bad_option_files_never_traceback(case):
    files = {"prog.ngc": b"G0 X1\nT1 M6\nM2\n", "junk.bin": bytes(range(256)) * 4}
    with Workdir(files) as w:
        (w.work / "adir").mkdir()
        h.assert_clean(w.ngc2py("run", "prog.ngc", *OPTION_CASES[case]))


# --- fuzzing ----------------------------------------------------------------


@rs274_test
@settings(max_examples=25, **FUZZ)
@given(st.binary(min_size=1, max_size=300))
def test_fuzz_random_bytes_match_rs274(data):
    # (the empty file has its own test)
    problems = compare_programs({"prog.ngc": data}, rs274_timeout=10)
    assert not problems, "\n".join(problems)


@rs274_test
@settings(max_examples=25, **FUZZ)
@given(st.binary(min_size=1, max_size=300))
def test_fuzz_random_bytes_after_a_valid_first_line_match_rs274(data):
    """Random bytes past the first line (which rs274 reads while opening
    the file, see the first-line tests)."""
    problems = compare_programs({"prog.ngc": b"G21\n" + data}, rs274_timeout=10)
    assert not problems, "\n".join(problems)


GCODEISH = "GMXYZIJKRFPQSTNgmxyz0123456789.-+*/[]()#<>=_ \t\n;%,ABC"


@rs274_test
@settings(max_examples=40, **FUZZ)
@given(st.text(alphabet=GCODEISH, max_size=160))
def test_fuzz_gcode_like_text_matches_rs274(text):
    # no O-words: a random while/do could loop forever in both tools. A
    # valid first line keeps the open-time cases (own tests) out of the way.
    problems = compare_programs({"prog.ngc": b"G21\n" + text.encode()}, rs274_timeout=10)
    assert not problems, "\n".join(problems)


O_LINES = [
    "o{n} if [{c}]", "o{n} elseif [{c}]", "o{n} else", "o{n} endif",
    "o{n} while [0]", "o{n} endwhile", "o{n} repeat [2]", "o{n} endrepeat",
    "o{n} break", "o{n} continue", "o{n} do", "o{n} while [0]",
    "o<s{k}> sub", "o<s{k}> endsub", "o<s{k}> call [{k}]", "o<s{k}> return [{k}]",
    "o{n} sub", "o{n} endsub", "o{n} call", "o{n} return",
    "G0 X{k}", "(DEBUG,{k} #1 #<_value>)", "M2", "%", "",
]


@st.composite
def o_word_programs(draw):
    lines = draw(
        st.lists(
            st.tuples(
                st.sampled_from(O_LINES),
                st.integers(100, 102),
                st.integers(0, 2),
                st.sampled_from(["0", "1", "#1"]),
            ),
            max_size=14,
        )
    )
    return "G21\n" + "".join(t.format(n=n, k=k, c=c) + "\n" for t, n, k, c in lines)


@rs274_test
@settings(max_examples=60, **FUZZ)
@given(o_word_programs())
def test_fuzz_o_word_structure_matches_rs274(program):
    """Random (often mismatched) O-word structure. Loops cannot iterate for
    ever (while [0], repeat [2]); a program where rs274 still loops for
    ever is a legitimate infinite loop and is not judged."""
    files = {"prog.ngc": program.encode()}
    with Workdir(files) as a, Workdir(files) as b:
        expected = a.rs274("prog.ngc", timeout=10)
        assume(not expected.timed_out)
        actual = b.ngc2py("run", "prog.ngc", timeout=30)
    problems = h.judge(expected, actual)
    assert not problems, "\n".join(problems)


@rs274_test
@pytest.mark.parametrize("kind", ["if", "while"])
def test_duplicate_o_word_label_in_untaken_block_matches_rs274(kind):
    """Found by the fuzzer: rs274 notices a reused label while it skips an
    untaken block (``o100 if [0]`` / ``o100 if [0]``)."""
    end = "endif" if kind == "if" else "endwhile"
    prog = "o100 {k} [0]\no100 {k} [0]\no100 {e}\no100 {e}\nM2\n".format(k=kind, e=end)
    assert_same_as_rs274({"prog.ngc": prog.encode()})


ANY_BYTE_TEXT = st.binary(max_size=120).map(lambda b: b.decode("utf-8", "surrogateescape"))


@settings(max_examples=200, **FUZZ)
@given(
    st.one_of(
        st.text(max_size=80),
        ANY_BYTE_TEXT,
        st.text(alphabet="\"'\\\n\r\x00\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029#;()<>[]{}%", max_size=40),
    ),
    st.sampled_from(["(%s)", "(MSG,%s)", "(DEBUG,%s)", "(PRINT,%s)", "G0 X1 ;%s", "(ABORT,%s)"]),
)
def test_fuzz_comment_text_never_breaks_generated_module(text, template):
    """In-process: any comment text -> a module that compiles, is
    black-stable and holds nothing but runtime-API code."""
    from ngc2py.compiler import compile_text

    code = compile_text("G0 X1\n" + (template % text) + "\nM2\n", "fuzz.ngc")
    problems = h.module_problems(code)
    assert not problems, "\n".join(problems)


NAME_CHARS = st.characters(
    blacklist_characters="<>()[];\n\r\x00 \t", blacklist_categories=("Cs",)
)


@settings(max_examples=150, **FUZZ)
@given(st.text(alphabet=NAME_CHARS, min_size=1, max_size=30))
def test_fuzz_parameter_and_sub_names_never_break_generated_module(name):
    from ngc2py.compiler import compile_text

    program = (
        "#<{n}> = 1\n#<_{n}> = 2\n(DEBUG,#<{n}> #<_{n}>)\n"
        "o<{n}> sub\nG0 X#1\no<{n}> endsub\no<{n}> call [#<{n}>]\nM2\n"
    ).format(n=name)
    code = compile_text(program, "fuzz.ngc")
    problems = h.module_problems(code)
    assert not problems, "\n".join(problems)


# ==========================================================================
# 2. Injection-proof code generation
# ==========================================================================

PAYLOADS = {
    "triple_double_quotes": '"""',
    "triple_single_quotes": "'''",
    "close_string_and_import": '"); import os; os.system("touch {marker}") #',
    "close_single_and_import": "'); import os; os.system('touch {marker}') #",
    "docstring_breakout": '""" + __import__("os").system("touch {marker}") + """',
    "backslash_at_end": "abc\\",
    "backslash_quote": '\\"\\\'',
    "escaped_newline_text": "\\n import os\\n",
    "unicode_line_separator": "a\u2028import os; os.system('touch {marker}')",
    "unicode_paragraph_separator": "a\u2029b",
    "nel_u0085": "a\u0085import os",
    "form_feed": "a\x0cimport os",
    "vertical_tab": "a\x0bimport os",
    "file_separators": "a\x1c\x1d\x1eb",
    "percent_formatting": "%s %d %(x)s {0} {x}",
    "hash_and_brace": "# {__import__} #<x>",
}


def payload_program(payload: str) -> str:
    templates = ["G21", "(%s)", "(MSG,%s)", "(DEBUG,%s)", "(PRINT,%s)", "G0 X1 (%s)", "G0 X2 ;%s", "M2"]
    return "".join((t % payload if "%s" in t else t) + "\n" for t in templates)


def check_generated(w: Workdir, program: str, markers=()) -> str:
    out = w.ngc2py("convert", program, "-o", "gen.py")
    h.assert_clean(out)
    assert out.rc == 0, out.describe()
    code = (w.work / "gen.py").read_text(encoding="utf-8")
    problems = h.module_problems(code, markers)
    assert not problems, "\n".join(problems)
    return code


@rs274_test
@pytest.mark.parametrize("name", sorted(PAYLOADS))
def test_comment_payload_cannot_inject_code(name, tmp_path):
    marker = tmp_path / "pwned"
    payload = PAYLOADS[name].replace("{marker}", str(marker))
    source = payload_program(payload).encode("utf-8")
    with Workdir({"prog.ngc": source}) as w:
        check_generated(w, "prog.ngc")
        ran = w.run([sys.executable, "gen.py"])
        h.assert_clean(ran)
        assert not marker.exists(), "the payload ran"
        assert not (w.work / "pwned").exists()
    assert_same_as_rs274({"prog.ngc": source})


@rs274_test
@pytest.mark.parametrize("byte", [b"\x00", b"\r", b"\n"])
def test_comment_with_raw_control_bytes_cannot_inject_code(byte):
    source = b'(MSG,"); import os #' + byte + b'import os; os.system("touch pwned"))\nM2\n'
    with Workdir({"prog.ngc": source}) as w:
        check_generated(w, "prog.ngc")
        h.assert_clean(w.run([sys.executable, "gen.py"]))
        assert not (w.work / "pwned").exists()
    assert_same_as_rs274({"prog.ngc": source})


HOSTILE_PARAM_NAMES = [
    "__import__", "__class__", "__builtins__", "__dict__", "_", "__init__",
    "exists", "v", "m", "p", "g", "self", "def", "class", "lambda", "import",
    "none", "true", "false", "None", "True", "print", "eval", "exec", "os",
    "run", "main", "block", "call", "params", "globals", "locals", "get",
    "keys", "items", "1abc", "a.b", "a-b", "a\"b", "a'b", "a\\b",
]


@rs274_test
@pytest.mark.parametrize("scope", ["local", "global"])
def test_hostile_named_parameters_are_data(scope):
    lines = []
    for i, name in enumerate(HOSTILE_PARAM_NAMES):
        ref = ("_" + name) if scope == "global" and not name.startswith("_") else name
        lines.append("#<%s> = %d" % (ref, i + 1))
        lines.append("(DEBUG,%s=#<%s>)" % (ref, ref))
        lines.append("#<%s> = [#<%s> + EXISTS[#<%s>]]" % (ref, ref, ref))
        lines.append("G0 X#<%s>" % ref)
    lines.append("M2")
    source = ("\n".join(lines) + "\n").encode()
    with Workdir({"prog.ngc": source}) as w:
        check_generated(w, "prog.ngc")
    assert_same_as_rs274({"prog.ngc": source})


HOSTILE_SUB_NAMES = [
    "__init__", "main", "run", "import", "def", "class", "m", "p", "g", "v",
    "o_main", "machine", "sourcemap", "run_cli", "__ngc__", "__name__",
    "exists", "none", "true", "self", "a\"b", "a'b", "a\\", "a\"\"\"b",
    "a'''b", "1", "x.y", "x-y", "#1",
]


@rs274_test
def test_hostile_subroutine_names_are_data():
    lines = []
    for i, name in enumerate(HOSTILE_SUB_NAMES):
        lines += ["o<%s> sub" % name, "G0 X[#1 + %d]" % i, "o<%s> endsub" % name]
    for i, name in enumerate(HOSTILE_SUB_NAMES):
        lines.append("o<%s> call [%d]" % (name, i))
    lines.append("M2")
    source = ("\n".join(lines) + "\n").encode()
    with Workdir({"prog.ngc": source}) as w:
        check_generated(w, "prog.ngc")
        ran = w.run([sys.executable, "gen.py"])
        h.assert_clean(ran)
    assert_same_as_rs274({"prog.ngc": source})


@rs274_test
def test_sub_name_with_semicolon_matches_rs274():
    """``o<x;y> sub``: the ``;`` starts a comment, rs274 rejects the line."""
    source = b"o<x;y> sub\nG0 X1\no<x;y> endsub\no<x;y> call\nM2\n"
    with Workdir({"prog.ngc": source}) as w:
        check_generated(w, "prog.ngc")
    assert_same_as_rs274({"prog.ngc": source})


@rs274_test
def test_external_subroutine_file_with_hostile_text_is_data():
    """A sub read from ``name.ngc`` is compiled into the module too."""
    sub = (
        'o<ext> sub\n(MSG,"""); import os; os.system("touch pwned") #)\n'
        "#<__import__> = 3\nG0 X#<__import__>\no<ext> endsub\n"
    ).encode()
    files = {"prog.ngc": b"o<ext> call\nM2\n", "ext.ngc": sub}
    with Workdir(files) as w:
        check_generated(w, "prog.ngc")
        h.assert_clean(w.run([sys.executable, "gen.py"]))
        assert not (w.work / "pwned").exists()
    assert_same_as_rs274(files)


HOSTILE_FILE_NAMES = [
    'q"""; import os; os.system("touch pwned"); x = """',
    "q'''; import os; os.system('touch pwned'); x = '''",
    "ends with backslash\\",
    "line\nbreak import os",
    "sep\u2028import os",
    "nel\u0085x",
    "quote\"and'apostrophe",
    "__init__",
    "-dash",
]


@rs274_test
@pytest.mark.parametrize("stem", HOSTILE_FILE_NAMES, ids=range(len(HOSTILE_FILE_NAMES)))
def test_hostile_file_names_are_data(stem):
    name = stem + ".ngc"
    # a missing-sub error makes both tools echo the file name
    source = b"G0 X1\n(DEBUG,hello)\no<absent> call\nM2\n"
    with Workdir({name: source}) as w:
        # "./" so a leading dash is not an option
        code = check_generated(w, "./" + name)
        ran = w.run([sys.executable, "gen.py"])
        h.assert_clean(ran)
        assert not (w.work / "pwned").exists()
        assert "pwned" not in {n for n in code.split() if n.isidentifier()}
    assert_same_as_rs274({name: source}, program="./" + name)


# ==========================================================================
# 3. Determinism
# ==========================================================================

DETERMINISM_PROGRAM = (
    "o<b> sub\n#<x> = [#1 * 2]\nG1 X#<x> F100\no<b> return [#<x>]\no<b> endsub\n"
    "o<a> sub\no<b> call [#1]\n(DEBUG,a=#<_value>)\no<a> endsub\n"
    "#<_g1> = 1\n#<_g2> = 2\n#<_g3> = 3\n"
    "o100 repeat [3]\no<a> call [#<_g1>]\n#<_g1> = [#<_g1> + 1]\no100 endrepeat\n"
    "G2 X0 Y0 I1 J1\nQ1\nM2\n"
)


def test_convert_twice_gives_identical_module_whatever_the_hash_seed():
    with Workdir({"prog.ngc": DETERMINISM_PROGRAM}) as w:
        texts = []
        for seed in ("0", "1", "12345"):
            out = w.ngc2py(
                "convert", "prog.ngc", "-o", "-", env_extra={"PYTHONHASHSEED": seed}
            )
            h.assert_clean(out)
            assert out.rc == 0
            texts.append(out.stdout)
    assert texts[0] == texts[1] == texts[2]


def test_convert_from_another_directory_gives_identical_module():
    """The same path argument from different working directories, and the
    same file name in two different folders, give the same module. (The
    path *as spelled* may appear in the module: rs274 echoes it.)"""
    with Workdir({"prog.ngc": DETERMINISM_PROGRAM}) as w, Workdir(
        {"prog.ngc": DETERMINISM_PROGRAM}
    ) as other:
        (w.root / "elsewhere").mkdir()
        absolute = str(w.work / "prog.ngc")
        here = w.ngc2py("convert", absolute, "-o", "-")
        there = w.ngc2py("convert", absolute, "-o", "-", cwd=w.root / "elsewhere")
        a = w.ngc2py("convert", "prog.ngc", "-o", "-")
        b = other.ngc2py("convert", "prog.ngc", "-o", "-")
    for out in (here, there, a, b):
        h.assert_clean(out)
    assert here.stdout == there.stdout
    assert a.stdout == b.stdout


def test_convert_default_output_equals_stdout_output():
    with Workdir({"prog.ngc": DETERMINISM_PROGRAM}) as w:
        to_stdout = w.ngc2py("convert", "prog.ngc", "-o", "-")
        w.ngc2py("convert", "prog.ngc")
        assert (w.work / "prog.py").read_bytes() == to_stdout.stdout


def test_run_twice_gives_identical_output_cached_or_not():
    with Workdir({"prog.ngc": DETERMINISM_PROGRAM}) as w:
        first = w.ngc2py("run", "prog.ngc")  # compiles into the cache
        second = w.ngc2py("run", "prog.ngc")  # from the cache
        third = w.ngc2py("run", "prog.ngc", env_extra={"PYTHONHASHSEED": "7"})
    for out in (first, second, third):
        h.assert_clean(out)
    assert first == second == third


@rs274_test
def test_determinism_program_matches_rs274():
    assert_same_as_rs274({"prog.ngc": DETERMINISM_PROGRAM.encode()})


# ==========================================================================
# 4. Nothing the user had is lost
# ==========================================================================

OLD_OUTPUT = b"# the user's precious file\n"


def test_convert_of_missing_source_keeps_existing_output():
    with Workdir({"out.py": OLD_OUTPUT}) as w:
        out = w.ngc2py("convert", "missing.ngc", "-o", "out.py")
        h.assert_clean(out)
        assert out.rc == 1
        assert (w.work / "out.py").read_bytes() == OLD_OUTPUT
        assert sorted(p.name for p in w.work.iterdir()) == ["out.py"]


def test_convert_of_directory_keeps_existing_output():
    with Workdir({"out.py": OLD_OUTPUT}) as w:
        (w.work / "dir.ngc").mkdir()
        out = w.ngc2py("convert", "dir.ngc", "-o", "out.py")
        h.assert_clean(out)
        assert out.rc == 1
        assert (w.work / "out.py").read_bytes() == OLD_OUTPUT


def test_convert_failing_midway_keeps_existing_output_and_no_temp_files(monkeypatch, tmp_path):
    """Simulated failure during code generation (in-process): the old
    output must survive, no temporary file may be left behind."""
    from ngc2py import cli, codegen

    (tmp_path / "prog.ngc").write_bytes(b"G0 X1\nM2\n")
    (tmp_path / "out.py").write_bytes(OLD_OUTPUT)

    def explode(*args, **kwargs):
        raise OSError(5, "Input/output error (simulated)")

    monkeypatch.setattr(codegen, "generate", explode)
    monkeypatch.chdir(tmp_path)
    rc = cli.main(["convert", "prog.ngc", "-o", "out.py"])
    assert rc == 1
    assert (tmp_path / "out.py").read_bytes() == OLD_OUTPUT
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.py", "prog.ngc"]


def test_convert_write_failure_keeps_existing_output_and_no_temp_files(monkeypatch, tmp_path):
    """The final rename fails (simulated): old output intact, no temp file."""
    from ngc2py import cli

    (tmp_path / "prog.ngc").write_bytes(b"G0 X1\nM2\n")
    (tmp_path / "out.py").write_bytes(OLD_OUTPUT)

    def failing_replace(src, dst):
        raise OSError(28, "No space left on device (simulated)")

    monkeypatch.setattr(os, "replace", failing_replace)
    monkeypatch.chdir(tmp_path)
    rc = cli.main(["convert", "prog.ngc", "-o", "out.py"])
    assert rc == 1
    assert (tmp_path / "out.py").read_bytes() == OLD_OUTPUT
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.py", "prog.ngc"]


def test_convert_into_missing_directory_is_clean():
    """Either a clean error or the folders are created and the module written."""
    with Workdir({"prog.ngc": b"G0 X1\nM2\n"}) as w:
        out = w.ngc2py("convert", "prog.ngc", "-o", "no/such/dir/out.py")
        h.assert_clean(out)
        assert out.rc == 1 or (w.work / "no/such/dir/out.py").is_file()


def test_convert_never_overwrites_its_own_source():
    """A G-code file named ``part.py``: the default output (``PROG.py``) is
    the source itself; converting must not destroy the user's G-code."""
    source = b"G0 X1\nM2\n"
    with Workdir({"part.py": source}) as w:
        out = w.ngc2py("convert", "part.py")
        h.assert_clean(out)
        assert (w.work / "part.py").read_bytes() == source


def test_convert_with_output_equal_to_source_does_not_destroy_it():
    source = b"G0 X1\nM2\n"
    with Workdir({"prog.ngc": source}) as w:
        out = w.ngc2py("convert", "prog.ngc", "-o", "prog.ngc")
        h.assert_clean(out)
        assert (w.work / "prog.ngc").read_bytes() == source


VAR_PROGRAM = b"#5161=1\n#5162=2\n#5163=3\n#5221=[#5221+1]\n#31=5\nG0 X1\nM2\n"
VAR_FILE = b"5161\t4.000000\n5220\t1.000000\n5221\t2.5\n"


def _run_with_var(tool: str, program: bytes, var: bytes, mode: int = 0o640):
    w = Workdir({"prog.ngc": program, "p.var": var, "p.var.bak": b"older backup\n"})
    os.chmod(w.work / "p.var", mode)
    old_inode = (w.work / "p.var").stat().st_ino
    if tool == "rs274":
        out = w.rs274("-v", "p.var", "prog.ngc")
    else:
        out = w.ngc2py("run", "prog.ngc", "-v", "p.var")
    files = {}
    for p in sorted(w.work.iterdir()):
        if p.is_file():
            st_ = p.stat()
            files[p.name] = (p.read_bytes(), stat.S_IMODE(st_.st_mode), st_.st_ino == old_inode)
    w.cleanup()
    return out, files


@rs274_test
@pytest.mark.parametrize("program", [VAR_PROGRAM, VAR_PROGRAM.replace(b"M2", b"Q1\nM2")],
                         ids=["ends_normally", "fails_midway"])
def test_var_file_rewritten_and_backed_up_like_rs274(program):
    expected_out, expected = _run_with_var("rs274", program, VAR_FILE)
    actual_out, actual = _run_with_var("ngc2py", program, VAR_FILE)
    h.assert_clean(actual_out)
    assert sorted(expected) == sorted(actual), "different files left behind"
    for name in ("p.var", "p.var.bak"):
        assert expected[name][0] == actual[name][0], name + " contents differ"


@rs274_test
def test_var_file_and_backup_permissions_like_rs274():
    """rs274 writes the new var file (and its backup) with fopen's
    0666 & ~umask; the user's file must not become private (0600)."""
    _, expected = _run_with_var("rs274", VAR_PROGRAM, VAR_FILE)
    _, actual = _run_with_var("ngc2py", VAR_PROGRAM, VAR_FILE)
    for name in ("p.var", "p.var.bak"):
        assert oct(expected[name][1]) == oct(actual[name][1]), name + " mode differs"


@rs274_test
def test_var_file_is_replaced_not_truncated_in_place():
    """Atomic rewrite: the var file is a new inode (a crash mid-write
    never leaves a half-written file), as with rs274."""
    _, expected = _run_with_var("rs274", VAR_PROGRAM, VAR_FILE)
    _, actual = _run_with_var("ngc2py", VAR_PROGRAM, VAR_FILE)
    assert expected["p.var"][2] is False
    assert actual["p.var"][2] is False


@rs274_test
def test_garbage_var_file_matches_rs274():
    garbage = b"\xff\xfe junk\n5161 abc\n99999999 1\n-5 2\n5220\n\n5161\t1e400\n"
    files = {"prog.ngc": b"(DEBUG,#5161 #5220)\nG0 X1\nM2\n", "p.var": garbage}
    with Workdir(files) as a, Workdir(files) as b:
        expected = a.rs274("-v", "p.var", "prog.ngc")
        actual = b.ngc2py("run", "prog.ngc", "-v", "p.var")
        exp_var = (a.work / "p.var").read_bytes()
        act_var = (b.work / "p.var").read_bytes()
    problems = h.differences(expected, actual)
    assert not problems, "\n".join(problems)
    assert exp_var == act_var


def test_converted_module_gets_normal_file_permissions():
    """A new OUT.py is created like any file the user writes (0666 & ~umask),
    not private 0600 (a temporary file's mode)."""
    with Workdir({"prog.ngc": b"G0 X1\nM2\n"}) as w:
        h.assert_clean(w.ngc2py("convert", "prog.ngc", "-o", "out.py"))
        umask = os.umask(0)
        os.umask(umask)
        assert oct(stat.S_IMODE((w.work / "out.py").stat().st_mode)) == oct(0o666 & ~umask)


def test_convert_onto_existing_output_keeps_its_permissions():
    """Replacing an existing OUT.py keeps the mode the user gave it."""
    with Workdir({"prog.ngc": b"G0 X1\nM2\n", "out.py": OLD_OUTPUT}) as w:
        os.chmod(w.work / "out.py", 0o755)
        h.assert_clean(w.ngc2py("convert", "prog.ngc", "-o", "out.py"))
        assert (w.work / "out.py").read_bytes() != OLD_OUTPUT
        assert oct(stat.S_IMODE((w.work / "out.py").stat().st_mode)) == oct(0o755)


@rs274_test
@pytest.mark.parametrize(
    "args", [["-x"], ["-t"], ["-v"], ["-i"]], ids=["unknown_option", "t_no_value", "v_no_value", "i_no_value"]
)
def test_bad_command_line_exits_1_like_rs274(args):
    """rs274 prints its usage and exits 1 on a bad option; so must
    ``ngc2py run`` (argparse's default is exit status 2) and a generated
    module run on its own."""
    with Workdir({"prog.ngc": b"G0 X1\nM2\n"}) as w:
        expected = w.rs274(*args, "prog.ngc") if args[0] == "-x" else w.rs274("prog.ngc", *args)
        assert expected.rc == 1
        h.assert_clean(w.ngc2py("convert", "prog.ngc", "-o", "gen.py"))
        module = w.run([sys.executable, "gen.py", *args])
        run = w.ngc2py("run", "prog.ngc", *args)
    h.assert_clean(module, "generated module")
    h.assert_clean(run)
    assert module.rc == 1, module.describe()
    assert run.rc == 1, run.describe()
