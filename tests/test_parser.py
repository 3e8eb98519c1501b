"""The front end: source.py, lexer.py, parser.py.

Unit tests pin the tree shapes the code generator relies on; the ``rs274``
tests run the installed rs274 on the same text and compare the read-time
error message (and the echoed line) with what the parser produces.
"""

from __future__ import annotations

import os
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from typing import List, Tuple

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ngc2py import lexer, source
from ngc2py.nodes import (
    Assign,
    Atan2,
    Binary,
    Bracket,
    Comment,
    Exists,
    NamedParam,
    Num,
    NumParam,
    OWord,
    Unary,
    Word,
)
from ngc2py.parser import parse_line, parse_text

from rs274 import rs274_path

# --------------------------------------------------------------------------
# Tree shapes
# --------------------------------------------------------------------------


def value_of(text: str):
    """The value expression of the single X word in ``G0 X<text>``, without
    the Bracket of an outer ``[...]`` (test_brackets pins those)."""
    line = parse_line("G0 X" + text, 1)
    assert line.error is None, line.error
    value = line.words[1].value
    return value.inner if isinstance(value, Bracket) else value


def test_blanks_and_case_are_ignored_outside_comments():
    line = parse_line("g 1 x 1 . 5 Y-2", 1)
    assert line.items == (
        Word("g", Num(1.0), 0),
        Word("x", Num(1.5), 4),
        Word("y", Num(-2.0), 12),
    )


def test_precedence_and_left_associativity():
    one, two, three = Num(1.0), Num(2.0), Num(3.0)
    p1 = NumParam(one)
    assert value_of("[#1 + #2 * #3]") == Binary(
        "+", p1, Binary("*", NumParam(two), NumParam(three))
    )
    assert value_of("[#1 - #2 - #3]") == Binary(
        "-", Binary("-", p1, NumParam(two)), NumParam(three)
    )
    # ** is left-associative in rs274 too: [2 ** 3 ** 2] is 64.
    assert value_of("[#1 ** #2 ** #3]") == Binary(
        "**", Binary("**", p1, NumParam(two)), NumParam(three)
    )
    assert value_of("[#1 LT #2 AND #3]") == Binary(
        "and", Binary("lt", p1, NumParam(two)), NumParam(three)
    )


def test_literal_arithmetic_is_folded_only_when_exact():
    assert value_of("[1 + 2 * 3]") == Num(7.0)
    assert value_of("[1 / 0]") == Binary("/", Num(1.0), Num(0.0))
    assert value_of("[2 ** 3]") == Binary("**", Num(2.0), Num(3.0))


def test_signs_numbers_and_functions():
    assert value_of("-.5") == Num(-0.5)
    assert value_of("--1") == Num(1.0)
    assert value_of("-#1") == Unary("neg", NumParam(Num(1.0)))
    assert value_of("007.250") == Num(7.25)
    assert value_of("sin[#1]") == Unary("sin", NumParam(Num(1.0)))
    assert value_of("ATAN[#1]/[2]") == Atan2(NumParam(Num(1.0)), Num(2.0))
    assert value_of("exists[#<_A b>]") == Exists("_ab")
    assert value_of("exists[#5]") == Num(1.0)
    assert value_of("##2") == NumParam(NumParam(Num(2.0)))


def test_named_parameters_are_normalised():
    line = parse_line("#<My Var> = #<_GLOBAL>", 1)
    assert line.items == (Assign(NamedParam("myvar"), NamedParam("_global"), 0),)
    assert line.items[0].target.is_global is False


def test_items_before_an_error_are_kept():
    line = parse_line("G1 X[1/0] Y$", 1)
    assert [w.letter for w in line.words] == ["g", "x"]
    assert line.error == "bad number format (conversion failed) parsing ''"


def test_line_number_and_block_delete():
    line = parse_line(" / N0012.5 G0 X1", 7, "f.ngc")
    assert (line.number, line.file, line.block_delete, line.n) == (
        7,
        "f.ngc",
        True,
        12.0,
    )
    assert line.text == " / N0012.5 G0 X1"


def test_owords():
    assert parse_line("o101 if [#1 LT 3]", 1).oword == OWord(
        "if", "101", expr=Binary("lt", NumParam(Num(1.0)), Num(3.0))
    )
    assert parse_line("O<Drill> CALL [1] (c) [#2]", 1).oword == OWord(
        "call", "drill", args=(Num(1.0), NumParam(Num(2.0)))
    )
    assert parse_line("o0100 endsub [2]", 1).oword == OWord(
        "endsub", "100", expr=Num(2.0)
    )
    assert parse_line("o[#1] call", 1).oword == OWord(
        "call", Bracket(NumParam(Num(1.0)))
    )
    line = parse_line("o100 return [1/0] X", 1)
    assert line.oword.expr == Binary("/", Num(1.0), Num(0.0))
    assert line.error == "Unexpected character after O-word"


def test_comments_are_kept_and_classified():
    line = parse_line("G0 X1 (first) ( MSG, Hello ) ; (not a comment)", 1)
    assert line.comments == (Comment("plain", "first"), Comment("msg", " Hello "))
    assert line.comment == Comment("msg", " Hello ")


@pytest.mark.parametrize(
    "body, kind, text",
    [
        ("  hello", "plain", "hello"),
        ("Msg ,x", "plain", "Msg ,x"),
        ("DEBUG,a", "debug", "a"),
        ("print,", "print", ""),
        ("LOGOPEN,f.txt", "logopen", "f.txt"),
        ("logappend,f.txt", "logappend", "f.txt"),
        ("LogClose", "logclose", ""),
        ("logclose ", "plain", "logclose "),
        ("abort,no", "abort", "no"),
        ("PROBEOPEN f.txt", "plain", "PROBEOPEN f.txt"),
    ],
)
def test_comment_kinds(body, kind, text):
    """The parser's comments are runtime.comments.classify's."""
    (comment,) = parse_line("G0 (%s)" % body, 1).comments
    assert comment == Comment(kind, text)


def test_lexer_keeps_comment_text_and_columns():
    result = lexer.normalise("G1 (A b) x 2")
    assert result.text == "g1(A b)x2"
    assert result.columns[result.text.index("x")] == 9
    assert lexer.normalise("(a(b))").error == "Nested comment found"
    assert lexer.normalise("G0 (a").error == "Unclosed comment found"


# --------------------------------------------------------------------------
# Files
# --------------------------------------------------------------------------


def test_percent_demarcation():
    parsed = parse_text(b"\n%\nG0 X1\n%\nthis is never read\n", "p.ngc")
    assert parsed.demarcated and parsed.closed
    assert [line.number for line in parsed.lines] == [1, 2, 3, 4]
    assert [line.percent for line in parsed.lines] == [False, True, False, True]


def test_percent_without_demarcation_is_a_bad_character():
    parsed = parse_text("G0 X1\n%\nM2\n")
    assert not parsed.demarcated and not parsed.closed
    assert parsed.lines[1].error == "Bad character '%' used"


def test_line_endings_and_trailing_blanks():
    parsed = parse_text(b"G0 X1 \t\r\nG0 X2\rM2")
    assert [line.text for line in parsed.lines] == ["G0 X1", "G0 X2\rM2"]


def test_too_long_lines():
    limit = source.LINE_LIMIT
    ok = parse_text(b"(" + b"a" * (limit - 4) + b")\n").lines[0]  # 252 + newline
    assert ok.error is None
    long = parse_text(b"(" + b"a" * 300 + b")\nM2\n").lines
    assert long[0].error == "Command too long"
    assert len(source.encode(long[0].text)) == limit
    assert long[1].number == 2


def test_binary_junk_is_a_gcode_error():
    line = parse_text(b"G0 X1 \xe9\xff\n").lines[0]
    assert line.error == "Bad character '\\351' used"
    assert source.encode(line.text) == b"G0 X1 \xe9\xff"
    assert parse_text(b"G0 X1\x00 Y$\n").lines[0].error is None


# --------------------------------------------------------------------------
# Robustness
# --------------------------------------------------------------------------

GCODE_ALPHABET = (
    "GMXYZFSTPQNO#<>[]()=+-*/.;@^$ 0123456789abceimnorstwxAEIMNOR\t\r%\x00é"
)


@settings(max_examples=3000, deadline=None)
@given(st.text(alphabet=GCODE_ALPHABET, max_size=60))
def test_parse_line_never_raises_on_gcode_like_text(text):
    line = parse_line(text, 1)
    assert line.error is None or isinstance(line.error, str)


@settings(max_examples=500, deadline=None)
@given(st.text(st.characters(blacklist_categories=()), max_size=80))
def test_parse_line_never_raises_on_any_text(text):
    parse_line(text, 1)


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=600))
def test_parse_text_never_raises_on_bytes(data):
    parsed = parse_text(data)
    assert all(line.number >= 1 for line in parsed.lines)


# --------------------------------------------------------------------------
# Against rs274
# --------------------------------------------------------------------------


def _run_rs274(data: bytes) -> Tuple[int, List[str]]:
    """(exit status, stderr lines without the ``executing`` banner)."""
    status, _, errors = _run_rs274_stdout(data)
    return status, errors


def _run_lines(lines):
    programs = [source.encode(line) + b"\nM2\n" for line in lines]
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 4) as pool:
        return list(pool.map(_run_rs274, programs))


@pytest.mark.rs274
def test_read_errors_match_rs274():
    """Message and echoed line, for every program in READ_ERROR_LINES."""
    mismatches = []
    for text, (rc, err) in zip(READ_ERROR_LINES, _run_lines(READ_ERROR_LINES)):
        line = parse_text(text + "\nM2\n").lines[0]
        expected = (1, err[0], err[1]) if rc else (rc, None, None)
        if (1, line.error, line.text) != expected:
            mismatches.append((text, expected, line.error))
    assert mismatches == []


@pytest.mark.rs274
def test_accepted_lines_read_cleanly():
    results = _run_lines(ACCEPTED_LINES)
    assert [rc for rc, _ in results] == [0] * len(ACCEPTED_LINES)
    assert [parse_line(text, 1).error for text in ACCEPTED_LINES] == [None] * len(
        ACCEPTED_LINES
    )


FILE_CASES = [
    b"G0 X1\n(" + b"a" * 260 + b")\nM2\n",
    b"G0 X1\n(" + b"a" * 251 + b")\r\nM2\n",
    b"G0 X1\n(" + b"a" * 250 + b")\nM2\n",
    b"G0 X1\n(" + b"a" * 252 + b")",
    b"G0 X1\t \r\n\tG1 X$\t  \r\nM2\n",
    b"G0 X1\r\rG1 X2\rM2\r",
    b"G0 X1 \xe9\nM2\n",
    b"G0 X1\nG0 X2 \x0b\nM2\n",
    b"%\nG0 X1\n%(c)\nM2\n",
    b"(c)\n%\nG0X1\n%\n",
    b"G0 /X1\nM2\n",
    b"/%\nM2\n",
]


@pytest.mark.rs274
@pytest.mark.parametrize("data", FILE_CASES)
def test_file_level_errors_match_rs274(data):
    """The first failing line rs274 reports is the first parsed line with an error."""
    rc, err = _run_rs274(data)
    parsed = parse_text(data)
    failing = [line for line in parsed.lines if line.error]
    if rc == 0:
        assert failing == []
    else:
        assert (failing[0].error, failing[0].text) == (err[0], err[1])


# -- Random lines, with the values the parser kept evaluated as rs274 would --

_UNARY = {
    "abs": "abs_",
    "round": "round_",
}
_BINARY = {
    "/": "div",
    "mod": "mod",
    "**": "power",
    "and": "and_",
    "or": "or_",
    "xor": "xor",
}
_ATOMS = (
    "[ ] [ ] 1 0 2.5 - + * ** / and mod or xor eq ne gt lt ge le sin[ cos[ atan[ ]/[ "
    "abs[ sqrt[ exists[ #1 #2 # round[ fix[ fup[ ln[ exp[ acos[ asin[ tan[ x $ (c) ; "
    "99 -1 0.5"
).split() + [" "]
_STARTS = (
    "G0 X",
    "#1=",
    "o100 if ",
    "o100 call ",
    "G1 F1 Y",
    "o[1] do ",
    "#",
    "G0 X[1/0] Y",
)


def _evaluate(expr, params=None):
    """An expression's value on a fresh machine (numbered parameters 0
    unless given in ``params``, no named parameters), with runtime.ops
    supplying rs274's arithmetic errors."""
    from runtime import codes, ops
    from runtime.errors import GCodeError

    if isinstance(expr, Num):
        return expr.value
    if isinstance(expr, NumParam):
        index = codes.to_integer(_evaluate(expr.index, params))
        if not 1 <= index <= 5601:
            raise GCodeError("Parameter number out of range")
        return (params or {}).get(index, 0.0)
    if isinstance(expr, NamedParam):
        raise GCodeError("Named parameter #<%s> not defined" % expr.name)
    if isinstance(expr, Exists):
        return 0.0
    if isinstance(expr, Bracket):
        return ops.finite(_evaluate(expr.inner, params))
    if isinstance(expr, Unary):
        function = getattr(ops, _UNARY.get(expr.op, expr.op))
        return ops.finite(function(ops.finite(_evaluate(expr.arg, params))))
    if isinstance(expr, Atan2):
        y, x = _evaluate(expr.y, params), _evaluate(expr.x, params)
        return ops.atan2(ops.finite(y), ops.finite(x))
    left, right = _evaluate(expr.left, params), _evaluate(expr.right, params)
    if expr.op in "+-*":
        return {"+": left + right, "-": left - right, "*": left * right}[expr.op]
    return getattr(ops, _BINARY.get(expr.op, expr.op))(left, right)


def _first_failure(line):
    """What running the line's reading would report: an evaluation error of
    items, then O-word values, then partial values; else the read error."""
    from runtime.errors import GCodeError

    values = []
    for item in line.items:
        if isinstance(item, Assign) and isinstance(item.target, NumParam):
            values.append(item.target.index)
        values.append(item.value)
    if line.oword is not None:
        if not isinstance(line.oword.name, str):
            values.append(line.oword.name)
        values.extend(line.oword.args)
        values.extend([line.oword.expr] if line.oword.expr is not None else [])
    try:
        for value in values:
            _evaluate(value)
        for value in line.partial:
            _evaluate(value)
    except GCodeError as error:
        return error.message
    return line.error


@pytest.mark.rs274
def test_random_expression_lines_fail_like_rs274():
    import random

    rng = random.Random(274)
    texts = [
        rng.choice(_STARTS)
        + "".join(rng.choice(_ATOMS) for _ in range(rng.randint(1, 10)))
        for _ in range(1500)
    ]
    mismatches = []
    for text, (rc, err) in zip(texts, _run_lines(texts)):
        predicted = _first_failure(parse_text(text + "\nM2\n").lines[0])
        if predicted is not None and (rc, err[0]) != (1, predicted):
            mismatches.append((text, err[0] if rc else None, predicted))
    assert mismatches == []


#: One-line programs rs274 rejects while reading the line.
READ_ERROR_LINES = (
    "G0 {",
    "G0 N10",
    "G0 o100",
    "G0 ~",
    "G0 X1 \\x7f",
    "G0 ]",
    "G0 `",
    "G0 $1 $2",
    "D1 D2",
    "H-2",
    "H1.5",
    "L-1",
    "L1.5",
    "T-1",
    "T1.5",
    "F-1",
    "S-1",
    "P1 P2",
    "Q1 Q2",
    "E1 E2",
    "L1 L2",
    "H1 H2",
    "#1=",
    "#1",
    "#1 2",
    "#0=1",
    "#5602=1",
    "#5400=1",
    "#5420=1",
    "#5413=1",
    "#1.5=1",
    "#<a",
    "#<a>",
    "#<a>=",
    "G0 X[1",
    "G0 X[1+",
    "G0 X[1}",
    "G0 X[1 ab 2]",
    "G0 X[1 mx 2]",
    "G0 X[1 o 2]",
    "G0 X[1 xa 2]",
    "G0 X[1 ex 2]",
    "G0 X[1 nx 2]",
    "G0 X[1 gx 2]",
    "G0 X[1 lx 2]",
    "G0 X[1 a]",
    "G0 X ax[1]",
    "G0 X cx[1]",
    "G0 X ex[1]",
    "G0 X fx[1]",
    "G0 X lx[1]",
    "G0 X rx[1]",
    "G0 X sx[1]",
    "G0 X tx[1]",
    "G0 X bx[1]",
    "G0 X sin 1",
    "G0 X td[1]",
    "G0 X atan[1]",
    "G0 X atan[1]/2",
    "G0 X exists[1]",
    "G0 X exists[#1",
    "G0 X exists[#<a>",
    "G0 X",
    "G0 X-",
    "G0 X+",
    "G0 X.",
    "G0 X1.2.3",
    "G0 X..5",
    "G0 X-.",
    "G0 X1..",
    "N",
    "N1.",
    "N1.x",
    "Nx",
    "N1 N2",
    "G0 X1 N2",
    "o",
    "o100 foo",
    "o100 if",
    "o100 if 1",
    "o100 while",
    "o100 repeat",
    "o100 elseif",
    "o<a> sub G0",
    "o1.5 sub",
    "O100 ENDSUB [1",
    "(a(b))",
    "(abc",
    "G0 X1 (abc",
    "G0 X1 )",
    "G0 X1 X2",
    "G0 Y1 Y2",
    "G0 Z1 Z2",
    "G0 A1 A2",
    "G0 B1 B2",
    "G0 C1 C2",
    "G0 U1",
    "G0 V1",
    "G0 W1",
    "G2 I1 I2",
    "G2 J1 J2",
    "G2 K1 K2",
    "G2 R1 R2",
    "F1 F2",
    "S1 S2",
    "T1 T2",
    "M3 M4 X$",
    "G0 G1 X$",
    "G0 X$ G0 G1",
    "T-1 X$",
    "H-2 X$",
    "F-1 X$",
    "S-1 X$",
    "L-1 X$",
    "M200 X$",
    "M1.5 X$",
    "M10 X$",
    "M-1",
    "M[-0.00001] X$",
    "G[-0.00001] X$",
    "M2.00001 X$",
    "G100",
    "G-1",
    "G1.05",
    "G 99.99",
    "G15",
    "G0 G80 X$",
    "G80 G0 X$",
    "G80 G80 X$",
    "G1 G80 G2",
    "G17 G18",
    "G20 G21",
    "G90 G91",
    "G90.1 G91.1",
    "G93 G94",
    "G40 G41",
    "G43 G49",
    "G98 G99",
    "G54 G59.3",
    "G61 G64",
    "G96 G97",
    "G7 G8",
    "G92.1 G92.2",
    "G4 G53",
    "M0 M1",
    "M7 M9",
    "M48 M53",
    "M62 M65",
    "M6 M61",
    "M3 M19",
    "M100 M101",
    "o100 call [1] [2] (c) [3] G0",
    "O100 return [1] X",
    "X[1/0 G0 $",
    "G0 @[1 ^",
    "#1=5 G0 X#1 X2",
    "#1=5 G0 X[#1+] ",
    "N10 G0 X1 N20",
    "N1.5 G0 X[",
    "G0 X1 Y2 %",
    "/%",
    "o<a> sub ) ",
    "o<a b> sub [1]",
    "o100 do x",
    "o100 else 1",
    "o100 endif [1]",
    "o100 break x",
    "o100 endwhile 1",
    "o100 endrepeat [1]",
    "o100 endsub 1",
    "o100 call [1] [2",
    "o100 call [1] 2",
    "o100 call [1](c)[2] x",
    "o100 callx",
    "o100 subroutine",
    "o100 ifx[1]",
    "o100 if[1]x",
    "o100 while [1] [2]",
    "o100 repeat [1",
    "o[100] do x",
    "o#1 do x",
    "o-5 do x",
    "o100.00001 do x",
    "o100.5 do x",
    "o 1 0 0 do x",
    "o<>do x",
    "G0 X1 o100 if [1]",
    "N5 o100 do x",
    "/ o100 do x",
    "G0 X1 G1 Y2",
    "g0 x1 y2 z3 a4 b5 c6 x7",
    "G 0 X 1 . 5 Y 2 X 3",
    "G0 X1.5 E3 E4",
    "G0 X 00001.50000 X0",
    "G0 X12345678901234567890123 X0",
    "G0 X0.000000000000000000001 X0",
    "G0 X[1]] ",
    "G0 X[[[1]]] X0",
    "G0 X[1 + [2 * [3 - 4]]] X0",
    "G0 X[1 and 2 or 3 xor 4 eq 5 ne 6 gt 7 ge 8 lt 9 le 10 mod 11] X0",
    "G0 X[ABS[1]+ACOS[1]+ASIN[1]+COS[1]+EXP[1]+FIX[1]+FUP[1]+LN[1]+ROUND[1]+SIN[1]+SQRT[1]+TAN[1]] X0",
    "G0 X[atan[1]/[1]] X0",
    "G0 X[EXISTS[#<_a>]] X0",
    "G0 X[EXISTS[#5]] X0",
    "G0 X[EXISTS[#[1+1]]] X0",
    "G0 X[EXISTS[#1.5]] X0",
    "G0 X[EXISTS[#<a>] X0",
    "G0 X[EXISTS #<a>] X0",
    "G0 X[EXISTS[#<a>]+] X0",
    "G0 X[1**] X0",
    "G0 X[1*/2] X0",
    "G0 X[*2] X0",
    "G0 X[] X0",
    "G0 X[1 2] X0",
    "G0 X#",
    "G0 X##",
    "G0 X#[1] X0",
    "G0 X#<a X0",
    "#<a>=1 #<a>",
    "#<a>=1 = ",
    "#[1+1]=3 X$",
    "#[5400]=1 X$",
    "#-1=3",
    "#1=-",
    "#1=+",
    "#1==1",
    "#<a (B)>=1 X$",
    "G0 X[1 (c) + 2]",
    "G0 X1 (a) (b) (c",
    "G0 X1 (a;b) Y$",
    "G0 X1 (a))",
    "(((",
    "M3 M4",
    "M3 M3",
    "G0 G0",
    "G4 G4 P1",
    "G4 P1 P2",
    "P-0.5 P2 G4",
    "H-1 H2",
    "L0 L1",
    "D1.5 D2",
    "$1 $2",
    "E1 E2",
    "A1 A2",
    "X1 x2",
    "G1 F[0-1] X$",
    "G1 F-0 X$",
    "S-0 X$",
    "T0 X$",
    "T-0.00001 X$",
    "H-1.00001 X$",
    "H-1 X$",
    "L-0.00001 X$",
    "G1 X1 F10 G2",
    "M2 M30",
    "M0 M98",
    "M200",
    "M199 X$",
    "M-0.5 X$",
    "G-0.05 X$",
    "G-0.04 X$",
    "G99.95 X$",
    "G99.949 X$",
    "G59.3 X$",
    "G59.29999 X$",
    "G59.2999 X$",
    "G38.2 G38.3",
    "G[1] G[0] X$",
    "G33.1 G76",
    "G5.1 G5.2",
    "G64 G61.1",
)

#: One-line programs rs274 reads and runs without error.
ACCEPTED_LINES = (
    "#5601=1",
    "#5414=1",
    "#<>=1",
    "G0 X+-1",
    "G0 X1 Y2 Z3 (ok)",
    "G0 X1 ; anything ( goes",
    "G0 X-[1] Y--2 Z+-3",
    "G0 X[-1]",
    "(print,hi) G0 X1",
    "#1=[ 2 ** 3 ** 2 ]",
    "#1=--1 #2=-+1 #3=+-1",
    "#1=1#2=2",
    "#<a>=1#<b>=2",
    "#<a(b)>=1",
    "#<a;b>=1",
    "G0 X1 ; (unclosed",
    "()",
    "F1 S1 T1 M3 M8 G0 X1",
    "P-1 P2 G4",
    "M99",
)


# -- inf/NaN checks happen where rs274 finishes reading a value ------------

#: (first line, lines that complete the program): values that overflow.
INF_NAN_PROGRAMS = (
    ("#1=[10**400*0]", ""),
    ("#1=[[10**400]*0]", ""),
    ("#1=[0-10**400]", ""),
    ("#1=[-10**400]", ""),
    ("G0 X-[10**400]", ""),
    ("#1=#[10**400]", ""),
    ("#1=exists[#[10**400]]", ""),
    ("#1=sin[10**400*0]", ""),
    ("#1=[10**200*10**200/10**300]", ""),
    ("#1=[[10**200*10**200]/10**300]", ""),
    ("G[10**400]", ""),
    ("o1 if [10**400*0]", "o1 endif"),
    ("o1 if [[10**400]*0]", "o1 endif"),
    ("o1 repeat [10**400*0]", "o1 endrepeat"),
    ("o1 while [[10**400]*0]", "o1 endwhile"),
)


@pytest.mark.rs274
def test_inf_and_nan_are_checked_where_rs274_checks_them():
    """Evaluating the tree (Bracket = check) fails exactly as rs274 does."""
    programs = [
        source.encode("%s\n%s\nM2\n" % (first, rest))
        for first, rest in INF_NAN_PROGRAMS
    ]
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 4) as pool:
        results = list(pool.map(_run_rs274, programs))
    mismatches = []
    for (first, _), (rc, err) in zip(INF_NAN_PROGRAMS, results):
        actual = err[0] if rc else None
        predicted = _first_failure(parse_line(first, 1))
        if predicted != actual:
            mismatches.append((first, actual, predicted))
    assert mismatches == []


def test_brackets():
    """Which ``[...]`` carry rs274's inf/NaN check (see nodes.Bracket)."""
    p1 = NumParam(Num(1.0))
    product = Binary("*", p1, Num(2.0))
    assert parse_line("X[#1*2]", 1).items[0].value == Bracket(product)
    assert parse_line("X[[#1*2]]", 1).items[0].value == Bracket(product)
    assert parse_line("X[1+2]", 1).items[0].value == Num(3.0)
    assert parse_line("X-[#1*2]", 1).items[0].value == Unary("neg", Bracket(product))
    assert parse_line("X[[#1*2]+1]", 1).items[0].value == Bracket(
        Binary("+", Bracket(product), Num(1.0))
    )
    assert parse_line("X#[#1*2]", 1).items[0].value == NumParam(Bracket(product))
    assert parse_line("X sin[#1*2]", 1).items[0].value == Unary("sin", product)
    assert parse_line("X atan[#1]/[#1*2]", 1).items[0].value == Atan2(p1, product)
    assert parse_line("o1 if [#1*2]", 1).oword.expr == product
    assert parse_line("o1 call [#1*2]", 1).oword.args == (product,)
    assert parse_line("o1 return [#1*2]", 1).oword.expr == product


# -- The N column of the trace -------------------------------------------------

N_LINES = (
    "N0012 G0 X1",
    "N20.5 G0 X2",
    "N000 G0 X3",
    "N1234567 G0 X4",
    "N123456 G0 X5",
    "N 1 2 G0 X6",
    "\t/ N7 G0 X7",
    "\rN8 G0 X8",
    "n9 g0 x9",
    "G0 X10",
)


@pytest.mark.rs274
def test_n_text_is_what_the_trace_prints():
    program = source.encode("\n".join(N_LINES) + "\nM2\n")
    _, stdout, _ = _run_rs274_stdout(program)
    traverses = [
        source.decode(line[6:]).split("STRAIGHT_TRAVERSE")[0]
        for line in stdout.split(b"\n")
        if b"STRAIGHT_TRAVERSE" in line
    ]
    assert len(traverses) == len(N_LINES)
    for text, printed in zip(N_LINES, traverses):
        n_text = parse_line(text, 1).n_text
        expected = "N..... " if n_text is None else "N" + n_text.ljust(6)
        assert (text, printed) == (text, expected)


# -- Fanuc-style subroutines ----------------------------------------------------


def test_fanuc_subroutine_lines():
    assert parse_line("O100 (c)", 1).oword == OWord("fanuc_sub", "100")
    assert parse_line("o<abc sub", 1).oword == OWord("fanuc_sub", "abcsub")
    line = parse_line("o<abc (msg,hi)", 1)
    assert (line.oword, line.comments) == (OWord("fanuc_sub", "abc(msg,hi)"), ())
    line = parse_line("M98 P100 L3", 1)
    assert line.oword == OWord("m98", "100", expr=Num(3.0))
    assert line.items == (Word("p", Num(100.0), 4), Word("l", Num(3.0), 9))
    assert parse_line("M98 P[#1]", 1).oword == OWord("m98", Bracket(NumParam(Num(1.0))))
    line = parse_line("N5 M99 (c)", 1)
    assert line.oword == OWord("m99", "")
    assert line.words == (Word("m", Num(99.0), 3),)
    assert parse_line("M99 G0 X1", 1).oword == OWord(
        "m99", "", in_call_error="Unexpected character after O-word"
    )
    assert parse_line("G0 M99", 1).oword is None


#: Fanuc-style lines whose read error (or success) rs274 reports.
FANUC_LINES = (
    "M98",
    "M98 X$",
    "M98 P1.5",
    "M98 P100 P200",
    "m[98] p100",
    "G0 M98 P100",
    "O1.5",
    "O100 G0",
    "o<unterminated sub",
    "o100",
)


@pytest.mark.rs274
def test_fanuc_read_errors_match_rs274():
    mismatches = []
    for text, (rc, err) in zip(FANUC_LINES, _run_lines(FANUC_LINES)):
        line = parse_text(text + "\nM2\n").lines[0]
        expected = (err[0], err[1]) if rc else (None, None)
        if (line.error, line.text if line.error else None) != expected:
            mismatches.append((text, expected, line.error))
    assert mismatches == []


# -- The fast path for simple lines -------------------------------------------

_SIMPLE_TOKENS = st.sampled_from(
    "G g M m X x Y Z A F f S T H L P Q R I J K D E N n O U @ ^ $ 0 1 2 3 98 99 "
    "1.5 -2 +3 .5 7. -0.5 80 38.2 59.3 1e3".split()
    + [" ", "\t", " ", "(c)", "(MSG,hi)", "( DEBUG,#1)", ";x"]
)


def _same_as_general_reader(text: str, axes: str = "xyzabc") -> bool:
    """Check the fast path's Line, if it takes the line; did it?"""
    from ngc2py.lexer import normalise
    from ngc2py.parser import read_any_line, read_simple_line

    simple = read_simple_line(text, 7, "f.ngc", axes)
    if simple is not None:
        assert simple == read_any_line(text, normalise(text), 7, "f.ngc", axes)
    return simple is not None


@settings(max_examples=3000, deadline=None)
@given(st.lists(_SIMPLE_TOKENS, max_size=12).map("".join))
def test_fast_path_matches_the_general_reader(text):
    _same_as_general_reader(text)
    _same_as_general_reader(text, "xyzuvw")


def test_fast_path_matches_on_the_golden_corpus():
    from pathlib import Path

    taken = 0
    for path in sorted(Path(__file__).parent.parent.glob("golden/*/*.ngc")):
        for raw in source.split_lines(path.read_bytes()):
            taken += _same_as_general_reader(raw.text)
    assert taken > 1000


# -- Signs, powers and precedence, by value ------------------------------------

#: Parameters the random expressions read (set first in each program).
_SIGN_PARAMS = {5: 3.0, 6: -0.5}


def _signed_expression(rng, depth: int = 0) -> str:
    """``atom (op atom)*`` with unary signs before numbers, parameters and
    brackets, which is where rs274's reading is least obvious."""
    atoms = ["2", "3", "0.5", "1.5", "#5", "#6", "#[5]"]

    def atom() -> str:
        sign = rng.choice(["", "", "-", "+", "--", "-+"])
        if depth < 2 and rng.random() < 0.3:
            return sign + "[" + _signed_expression(rng, depth + 1) + "]"
        return sign + rng.choice(atoms)

    ops_ = ["+", "-", "*", "/", "**", " mod "]
    text = atom()
    for _ in range(rng.randint(0, 3)):
        text += rng.choice(ops_) + atom()
    return text


def _run_rs274_stdout(data: bytes) -> Tuple[int, bytes, List[str]]:
    """(exit status, stdout, stderr lines without the ``executing`` banner),
    rs274 running in a private HOME."""
    with tempfile.TemporaryDirectory() as home:
        path = os.path.join(home, "t.ngc")
        with open(path, "wb") as handle:
            handle.write(data)
        proc = subprocess.run(
            [rs274_path(), "-g", path],
            capture_output=True,
            env={**os.environ, "HOME": home},
            stdin=subprocess.DEVNULL,
            timeout=60,
        )
    errors = [l for l in proc.stderr.split(b"\n") if l != b"executing"]
    return proc.returncode, proc.stdout, [source.decode(l) for l in errors]


@pytest.mark.rs274
def test_signs_and_powers_evaluate_like_rs274():
    """``-2**2`` is 4 (the sign belongs to the number), ``-#5**2`` is 9,
    ``2**3**2`` is 64 (left-associative): random expressions, by value."""
    import random

    from runtime.comments import format_value
    from runtime.errors import GCodeError

    rng = random.Random(2)
    texts = sorted({_signed_expression(rng) for _ in range(60)})
    setup = "".join("#%d=%r\n" % item for item in _SIGN_PARAMS.items())
    programs = [
        source.encode(setup + "#1=[%s]\n(print,#1)\nM2\n" % text) for text in texts
    ]
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 4) as pool:
        results = list(pool.map(_run_rs274_stdout, programs))
    mismatches = []
    for text, (rc, stdout, errors) in zip(texts, results):
        line = parse_line("#1=[%s]" % text, 1)
        try:
            predicted = format_value(_evaluate(line.items[0].value, _SIGN_PARAMS))
        except GCodeError as error:
            predicted = error.message
        printed = [l for l in stdout.decode().split("\n") if "N" not in l and l]
        actual = errors[0] if rc else printed[0]
        if predicted != actual:
            mismatches.append((text, actual, predicted))
    assert mismatches == []
