"""runtime._fast_format.percent must give exactly Python's ``template % args``.

The extension is optional (setup.py builds it where a C compiler is found;
CI does); where it is missing the runtime uses ``str.__mod__`` itself and
these tests are skipped with that reason.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import math
import struct

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

try:
    from runtime._fast_format import percent
except ImportError:  # pragma: no cover - depends on the build
    percent = None

pytestmark = pytest.mark.skipif(
    percent is None,
    reason="runtime._fast_format not built here (no C compiler or headers)",
)


def c_printf(template: str, x: float) -> str:
    """The C library's printf of one double (ctypes: no code of ours)."""
    buffer = ctypes.create_string_buffer(128)
    _LIBC.snprintf(buffer, len(buffer), template.encode(), ctypes.c_double(x))
    return buffer.value.decode()


_LIBC = ctypes.CDLL(ctypes.util.find_library("c"))


def same_as_python(template: str, args: tuple) -> None:
    """percent() is Python's ``%``, but for a NaN, which it prints as C's
    printf does (``-nan`` with the sign bit set: rs274's trace)."""
    if (
        template == "%.4f"
        and args
        and isinstance(args[0], float)
        and math.isnan(args[0])
    ):
        assert percent(template, args) == c_printf(template, args[0])
        return
    try:
        expected = template % args
    except Exception as exc:  # the same error, with the same words
        with pytest.raises(type(exc)) as raised:
            percent(template, args)
        assert str(raised.value) == str(exc)
    else:
        assert percent(template, args) == expected


def any_double(bits: int) -> float:
    return struct.unpack("<d", struct.pack("<Q", bits))[0]


@given(st.integers(min_value=0, max_value=2**64 - 1))
@settings(max_examples=1500, deadline=None)
def test_every_bit_pattern(bits):
    same_as_python("%.4f", (any_double(bits),))


@given(st.floats(allow_nan=True, allow_infinity=True))
@settings(max_examples=1500, deadline=None)
@example(0.03125)  # 312.5 ten-thousandths exactly: a tie, printed to even
@example(-0.03125)
@example(0.00005)  # just above or below a tie, as its binary value is
@example(-0.0)
@example(5e-324)
@example(99999999999.99998)  # the largest magnitude the fast path takes
@example(1e11)  # the first one it hands to Python
def test_any_float(x):
    same_as_python("%.4f", (x,))


@given(
    st.integers(min_value=-(10**12), max_value=10**12),
    st.sampled_from([-2, -1, 0, 1, 2]),
)
@settings(max_examples=1500, deadline=None)
def test_numbers_next_to_a_rounding_tie(k, steps):
    # The hard cases: x * 10000 within an ulp of a half. math.nextafter walks
    # a few representable numbers either side of the nearest double.
    x = (k + 0.5) / 10000
    for _ in range(abs(steps)):
        x = math.nextafter(x, math.inf if steps > 0 else -math.inf)
    same_as_python("%.4f", (x,))


@given(st.integers(min_value=-(2**40), max_value=2**40), st.integers(0, 45))
@settings(max_examples=1500, deadline=None)
def test_dyadic_fractions(odd, shift):
    # Values with few binary digits are where exact ties live.
    same_as_python("%.4f", ((2 * odd + 1) / 2**shift,))


_ARGUMENT = st.one_of(
    st.floats(),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.text(max_size=8),
    st.booleans(),
    st.none(),
)
_SPEC = st.sampled_from(
    [
        "%s",
        "%d",
        "%5d",
        "%-5d",
        "%.4f",
        "%-6s",
        "%6s",
        "%%",
        "%05d",
        "%+.4f",
        "%.3f",
        "%10.4f",
        "%r",
        "%x",
        "%",
    ]
)


@given(
    st.lists(st.tuples(st.text(max_size=4), _SPEC), max_size=6),
    st.lists(_ARGUMENT, max_size=7),
)
@settings(max_examples=1500, deadline=None)
def test_templates_and_arguments_of_any_kind(pieces, args):
    template = "".join(text.replace("%", "") + spec for text, spec in pieces)
    same_as_python(template, tuple(args))


def test_a_trace_line():
    line = "%5d %sSTRAIGHT_FEED(%.4f, %.4f, %.4f, %s)\n"
    args = (123456, "N10    ", 1.23456789, -0.00004, 1e300, "0.0000, 0.0000, 0.0000")
    assert percent(line, args) == line % args
    assert percent(line, args).startswith(
        "123456 N10    STRAIGHT_FEED(1.2346, -0.0000, 1"
    )


def test_lines_longer_than_the_inline_buffer():
    template = "%s|" * 40 + "%.4f"
    args = tuple("x" * k for k in range(40)) + (2.5,)
    same_as_python(template, args)


@pytest.mark.parametrize("x", [math.nan, -math.nan, -(0.0 * math.inf)])
def test_nan_as_c_prints_it(x):
    """A NaN is printed as printf prints it, by the extension and by the
    Python fallback (runtime.canon.c_nans) alike."""
    from runtime.canon import c_nans

    want = "    3 X(" + c_printf("%.4f", x) + ", 1.0000) %"
    assert percent("%5d X(%.4f, %.4f) %%", (3, x, 1.0)) == want
    assert c_nans("%5d X(%.4f, %.4f) %%", (3, x, 1.0)) == want


def test_bad_call():
    with pytest.raises(TypeError):
        percent("%s", ["not a tuple"])


# --------------------------------------------------------------------------
# TraceCanon's C calls against runtime.canon.PythonTraceLines
# --------------------------------------------------------------------------

_AXIS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1.5, 0.03125, 1e11, -2.5e-5]),
    st.integers(min_value=-5, max_value=5),  # not a float: Python's % decides
)
_CALL = st.one_of(
    st.tuples(st.just("straight_feed"), st.lists(_AXIS, min_size=9, max_size=9)),
    st.tuples(st.just("straight_traverse"), st.lists(_AXIS, min_size=9, max_size=9)),
    st.tuples(
        st.just("arc_feed"),
        st.tuples(
            _AXIS, _AXIS, _AXIS, _AXIS, st.integers(-3, 3), _AXIS, _AXIS, _AXIS, _AXIS
        ).map(lambda t: list(t) + [0.0, 0.0, 0.0]),
    ),
    st.tuples(st.just("set_feed_rate"), st.lists(_AXIS, min_size=1, max_size=1)),
    st.tuples(
        st.just("set_block_number"),
        st.lists(st.sampled_from([None, "10", "7.5"]), min_size=1, max_size=1),
    ),
    st.tuples(st.just("same_rotary_axes"), st.lists(_AXIS, min_size=3, max_size=3)),
    # calls whose text TraceCanon makes in Python, numbered by _emit (a
    # comment's undecodable bytes are lone surrogates: no UTF-8 of its own)
    st.tuples(
        st.just("comment"), st.lists(st.text(max_size=8), min_size=1, max_size=1)
    ),
    st.tuples(st.just("dwell"), st.lists(_AXIS, min_size=1, max_size=1)),
    st.tuples(st.just("_emit"), st.lists(st.text(max_size=8), min_size=1, max_size=1)),
    st.tuples(
        st.just("comment"),
        st.lists(
            st.text(
                st.characters(min_codepoint=0xDC80, max_codepoint=0xDCFF), max_size=3
            ),
            min_size=1,
            max_size=1,
        ),
    ),
)


def _traces(calls, buffered):
    import io

    from runtime import canon

    class Python(canon.PythonTraceLines, canon.TraceCanon):
        pass

    outputs = []
    for cls in (canon.TraceCanon, Python):
        out = io.StringIO()
        trace = cls(out)
        trace._drain_at = buffered
        last = [0.0] * 9
        for name, args in calls:
            if name == "same_rotary_axes":  # a move passing the last A/B/C on
                args = [*args, *last[3:]]
                name = "straight_feed"
            if name.startswith("straight"):
                last = args
            try:
                getattr(trace, name)(*args)
            except Exception as exc:  # the same error either way
                out.write("! %s: %s\n" % (type(exc).__name__, exc))
        trace.flush()
        outputs.append(out.getvalue())
    return outputs


@pytest.mark.skipif(percent is None, reason="runtime._fast_format not built here")
@given(st.lists(_CALL, max_size=40), st.integers(min_value=1, max_value=5))
@settings(max_examples=400, deadline=None)
def test_trace_lines_in_c_print_what_the_python_versions_print(calls, buffered):
    c_text, python_text = _traces(calls, buffered)
    assert c_text == python_text


@pytest.mark.skipif(percent is None, reason="runtime._fast_format not built here")
@given(
    st.lists(st.tuples(st.text(max_size=3), _SPEC), max_size=4),
    st.lists(st.lists(_ARGUMENT, max_size=6), max_size=5),
)
@settings(max_examples=1000, deadline=None)
def test_rows_of_lines_are_pythons_join(pieces, columns):
    from runtime._fast_format import percent_rows

    template = "".join(text.replace("%", "") + spec for text, spec in pieces)
    try:
        expected = "".join(template % row for row in zip(*columns))
    except Exception as exc:
        with pytest.raises(type(exc)):
            percent_rows(template, columns)
    else:
        assert percent_rows(template, columns) == expected


_BOUND = st.integers(-(2**45), 2**45) | st.integers(-20, 20)
_RANGE = st.builds(range, _BOUND, _BOUND, _BOUND.filter(bool) | st.integers(1, 3))


@st.composite
def _lines_with_ranges(draw):
    """A template and one column for each of its conversions: a list, or a
    range (of ten items at most) as the lines' numbers are given."""
    pieces = draw(st.lists(st.tuples(st.text(max_size=3), _SPEC), max_size=4))
    rows = draw(st.integers(0, 6))
    columns = []
    for _ in pieces:
        if draw(st.booleans()):
            columns.append(draw(_RANGE.filter(lambda r: len(r) < 10)))
        else:
            columns.append(draw(st.lists(_ARGUMENT, min_size=rows, max_size=rows)))
    template = "".join(text.replace("%", "") + spec for text, spec in pieces)
    return template, columns


@pytest.mark.skipif(percent is None, reason="runtime._fast_format not built here")
@given(_lines_with_ranges())
@settings(max_examples=1000, deadline=None)
def test_rows_of_lines_with_ranges_are_pythons_join(lines):
    """A range column (the lines' numbers) is read as its start and step:
    the same text as Python's, for any conversion and any size of number."""
    from runtime._fast_format import percent_rows

    template, columns = lines
    try:
        expected = "".join(template % tuple(row) for row in zip(*columns))
    except Exception as exc:
        with pytest.raises(type(exc)):
            percent_rows(template, columns)
    else:
        assert percent_rows(template, columns) == expected


@pytest.mark.skipif(percent is None, reason="runtime._fast_format not built here")
def test_rows_of_trace_lines():
    from runtime._fast_format import percent_rows

    template = "%5d N%-6sARC_FEED(%s, %.4f, %s)\n"
    columns = [
        range(7, 5007),
        ["10", "2"] * 2500,
        ["1.5000"] * 5000,
        [0.1 * k for k in range(5000)],
        ["-1", "1"] * 2500,
    ]
    assert percent_rows(template, columns) == "".join(
        template % row for row in zip(*columns)
    )


@st.composite
def _numbered_lines(draw):
    """A hole's template as runtime.fast.hole_rows makes it: ``lines``
    lines, each conversion a line's number or one of a few columns."""
    lines = draw(st.integers(1, 5))
    rows = draw(st.integers(0, 6))
    groups = [
        draw(st.lists(_ARGUMENT, min_size=rows, max_size=rows + 2))
        for _ in range(draw(st.integers(0, 4)))
    ]
    pieces = draw(st.lists(st.tuples(st.text(max_size=3), _SPEC), max_size=6))
    layout = tuple(draw(st.integers(0, lines + len(groups) - 1)) for _ in pieces)
    template = "".join(text.replace("%", "") + spec for text, spec in pieces)
    first = draw(st.integers(0, 2**40))  # a trace's line numbers
    return template, first, lines, rows, layout, groups


@pytest.mark.skipif(percent is None, reason="runtime._fast_format not built here")
@given(_numbered_lines())
@settings(max_examples=1000, deadline=None)
def test_numbered_rows_are_pythons_join(case):
    """numbered_rows: each line's number worked out in C, where the Python
    twin makes a range for each line: the same text, or the same error."""
    from runtime._fast_format import numbered_rows
    from runtime.canon import python_numbered_rows

    template, first, lines, rows, layout, groups = case
    span = lines * rows
    pool = [range(b, b + span, lines) for b in range(first, first + lines)]
    pool += [group[:rows] for group in groups]
    columns = [pool[i] for i in layout]
    try:
        expected = "".join(template % tuple(row) for row in zip(*columns))
        if not layout:
            expected = ""
        assert (
            python_numbered_rows(template, first, lines, rows, layout, groups)
            == expected
        )
    except Exception as exc:
        with pytest.raises(type(exc)):
            numbered_rows(template, first, lines, rows, layout, groups)
    else:
        assert numbered_rows(template, first, lines, rows, layout, groups) == expected


# --- words(prefix, values): flatten's numbers, a column at a time ----------

#: Numbers as G-code writes them: at most four decimals (words' quick path),
#: next to and beyond its edges, and any double at all.
_WORD_VALUES = (
    st.integers(-(10**15), 10**15).map(lambda n: n / 10000)
    | st.integers(-(10**15), 10**15).map(lambda n: n / 10000 + 1e-9)
    | st.sampled_from(
        [0.0, -0.0, 1e-4, -1e-4, 5e-5, 1e11, 1e11 - 1e-4, 1e15, 0.1 + 0.2]
    )
    | st.integers(min_value=0, max_value=2**64 - 1).map(any_double)
)


@settings(max_examples=500)
@given(st.lists(_WORD_VALUES, max_size=12), st.sampled_from(["", "X", "G1 Y", "é"]))
@example([1.0, -0.0, 0.5, 1234.5678, -0.0001], "X")
def test_words_are_flattens_numbers(values, prefix):
    """words() writes each value as ngc2py.flatten.number does, after the
    prefix, or answers None (an exponent, not finite, 1e15 or more, a
    prefix that is not ASCII) and leaves it to number(); so does its
    Python twin."""
    from ngc2py.flatten import _python_words, _words, number
    from runtime._fast_format import words

    if not all(map(math.isfinite, values)):  # (no move goes there)
        assert words(prefix, list(values)) is None
        assert _python_words(prefix, values) is None
        return
    expected = [prefix + number(value) for value in values]
    assert _words(prefix, values) == expected
    for made in (words(prefix, list(values)), values and _python_words(prefix, values)):
        assert made is None or made == expected
    plain = all(
        math.isfinite(v) and abs(v) < 1e15 and "e" not in repr(v) for v in values
    )
    assert (words(prefix, list(values)) is not None) == (plain and prefix.isascii())


@settings(max_examples=500)
@given(
    st.lists(_WORD_VALUES, min_size=9, max_size=9),
    st.lists(
        _WORD_VALUES | st.sampled_from([float("nan"), float("inf")]),
        min_size=6,
        max_size=6,
    ),
    st.lists(st.booleans(), min_size=6, max_size=6),
    st.sampled_from(["G0", "G1", "G38.2"]),
)
@example([0.0] * 9, [-0.0] * 6, [False] * 6, "G1")
@example([1.5] * 9, [1.5] * 6, [False] * 6, "G0")
def test_a_moves_text_in_c_is_flattens(args, pos, shared, code):
    """move_text(code, args, pos) writes a straight move's line as
    flatten's Python twin does (the axes that changed from pos: not the
    same float, not equal, a zero of the other sign; X alone when none
    did), and leaves pos as it does; or answers None, pos untouched, and
    leaves it to the twin (a value number() itself must write)."""
    from ngc2py.flatten import FlattenCanon
    from runtime._fast_format import move_text

    # an axis the move leaves alone passes the very same float object on
    args = tuple(pos[k] if shared[k] else args[k] for k in range(6)) + tuple(args[6:])
    theirs = list(pos)
    try:
        expected = FlattenCanon._python_move(None, code, args, theirs)
    except ValueError:  # number() of nan or inf (no move goes there)
        expected = None
    ours = list(pos)
    made = move_text(code, args, ours)
    if made is None:
        assert all(a is b for a, b in zip(ours, pos))  # untouched
        plain = all(
            math.isfinite(v) and abs(v) < 1e15 and "e" not in repr(v) for v in args[:6]
        )
        assert not plain or expected is None
    else:
        assert made == expected
        assert all(a is b for a, b in zip(ours, theirs))


@settings(max_examples=300)
@given(
    st.lists(
        st.tuples(_WORD_VALUES, _WORD_VALUES | st.sampled_from([0.2, -17.303, 2.3456])),
        max_size=10,
    ),
    st.data(),
)
def test_short_offsets_in_c_are_its_python_twin(pairs, data):
    """short_offsets(starts, centres) gives, to the bit, what flatten's
    Python twin gives: each centre - start, or its four decimals where
    added to the start they give the very centre back."""
    from ngc2py.flatten import _python_short_offsets
    from runtime._fast_format import short_offsets

    starts = [start for start, _ in pairs]
    # a centre: any value, or one a short offset from its start
    centres = [
        start + offset if data.draw(st.booleans()) else offset
        for start, offset in pairs
    ]
    made, twin = short_offsets(starts, centres), _python_short_offsets(starts, centres)
    assert [struct.pack("<d", v) for v in made] == [struct.pack("<d", v) for v in twin]
    for start, centre, offset in zip(starts, centres, made):
        if start + offset == centre and offset != centre - start:
            assert offset == round(offset, 4)  # shortened only to four decimals


@pytest.mark.skipif(percent is None, reason="runtime._fast_format not built here")
@given(
    st.lists(st.floats() | st.integers(-(2**53), 2**53), max_size=12),
    st.integers(-15, 15),
    st.integers(-15, 15),
)
def test_float_bits_are_the_arrays_bytes(values, start, stop):
    """float_bits(values, start, stop), flatten's look at the parameters
    after every block, gives the bytes of array("d", values[start:stop]):
    every bit (-0.0, NaN payloads), ints as their floats, slices as Python
    reads them."""
    from ngc2py.flatten import python_float_bits
    from runtime._fast_format import float_bits

    assert float_bits(values, start, stop) == python_float_bits(values, start, stop)
