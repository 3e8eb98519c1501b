"""runtime.canon.call_rows: a batch's canon calls made from its columns.

The C extension ``runtime._call_rows`` and its twin
``runtime.canon.python_call_rows`` must make the very same calls, in the
same order, with the same objects; a method's error must stop both at the
same call. Where the extension is not built the C side is skipped (the
twin's own tests still run) and the runtime uses the twin.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from runtime.canon import Canon, python_call_rows

try:
    from runtime._call_rows import call_rows as c_call_rows
except ImportError:  # pragma: no cover - depends on the build
    c_call_rows = None

needs_c = pytest.mark.skipif(
    c_call_rows is None,
    reason="runtime._call_rows not built here (no C compiler or headers)",
)


class Code(tuple):
    """A tuple type as the preview's line codes are: no fields of its own."""

    __slots__ = ()


class Log:
    """Methods that write down every call: (step, arguments)."""

    def __init__(self, fail_at=None, error=ValueError):
        self.calls = []
        self.fail_at = fail_at
        self.error = error

    def method(self, name):
        def call(*args):
            if len(self.calls) == self.fail_at:
                raise self.error("stop here")
            self.calls.append((name, args, type(args[0]) if args else None))

        return call


@st.composite
def batches(draw):
    rows = draw(st.integers(0, 12))
    start = draw(st.integers(0, rows))
    stop = draw(st.integers(start, rows))
    # a column (or mask) of one value serves every row
    sizes = st.sampled_from((rows, 1)) if rows else st.just(0)
    values = st.floats(allow_nan=False) | st.integers()
    flags = st.sampled_from([0, 1, -1, True, False, 0.0])
    specs = []
    for index in range(draw(st.integers(1, 3))):
        columns = tuple(
            draw(st.lists(values, min_size=size, max_size=size))
            for size in [draw(sizes) for _ in range(draw(st.integers(0, 12)))]
        )
        kind = Code if columns and draw(st.booleans()) else None
        mask = None
        if draw(st.booleans()):
            size = draw(sizes)
            mask = draw(st.lists(flags, min_size=size, max_size=size))
        specs.append((index, columns, kind, mask))
    fail_at = draw(st.none() | st.integers(0, 20))
    return start, stop, specs, fail_at


def run(call_rows, start, stop, specs, fail_at, error=ValueError):
    log = Log(fail_at, error)
    steps = []
    for index, columns, kind, mask in specs:
        step = (log.method(index), columns)
        if kind is not None or mask is not None:
            step += (kind,)
        if mask is not None:
            step += (mask,)
        steps.append(step)
    try:
        call_rows(start, stop, steps)
        raised = None
    except Exception as caught:  # noqa: BLE001 - compared below
        raised = (type(caught), str(caught))
    return log.calls, raised


def at(column, row):
    return column[0] if len(column) == 1 else column[row]


def expected(start, stop, specs):
    """The calls as the docstring says, row by row, step by step."""
    calls = []
    for row in range(start, stop):
        for index, columns, kind, mask in specs:
            if mask is not None and not at(mask, row):
                continue
            values = tuple(at(column, row) for column in columns)
            args = (Code(values),) if kind is not None else values
            calls.append((index, args, type(args[0]) if args else None))
    return calls


@settings(max_examples=300)
@given(batches())
def test_the_twin_makes_the_calls_its_docstring_names(batch):
    start, stop, specs, _ = batch
    calls, raised = run(python_call_rows, start, stop, specs, None)
    assert raised is None
    assert calls == expected(start, stop, specs)


@needs_c
@settings(max_examples=500)
@given(batches())
def test_c_makes_the_calls_the_twin_makes(batch):
    start, stop, specs, fail_at = batch
    assert run(c_call_rows, start, stop, specs, fail_at) == run(
        python_call_rows, start, stop, specs, fail_at
    )


@pytest.mark.parametrize(
    "call_rows",
    [python_call_rows, pytest.param(c_call_rows, marks=needs_c)],
    ids=["python", "c"],
)
def test_a_method_raising_stop_iteration_does_not_end_the_batch_in_silence(call_rows):
    specs = [
        (0, ([1.0, 2.0, 3.0],), None, None),
        (1, ([4.0, 5.0, 6.0],), None, [1, 0, 1]),
    ]
    calls, raised = run(call_rows, 0, 3, specs, 2, error=StopIteration)
    assert raised == (RuntimeError, "a canon method raised StopIteration")
    assert [call[:2] for call in calls] == [(0, (1.0,)), (1, (4.0,))]


@needs_c
def test_c_refuses_columns_it_cannot_read():
    with pytest.raises(ValueError, match="shorter than the rows"):
        c_call_rows(0, 3, [(print, ([1.0, 2.0],))])
    with pytest.raises(TypeError, match="tuple subclass"):
        c_call_rows(0, 1, [(print, ([1.0],), dict)])
    with pytest.raises(TypeError, match="at most 16"):
        c_call_rows(0, 1, [(print, tuple([[1.0]] * 17))])
    with pytest.raises(ValueError, match="start <= stop"):
        c_call_rows(2, 1, [(print, ())])


@needs_c
def test_c_survives_a_method_that_empties_its_own_column():
    column = [1.0, 2.0, 3.0]
    seen = []

    def greedy(value):
        seen.append(value)
        column.clear()

    with pytest.raises(RuntimeError, match="changed size"):
        c_call_rows(0, 3, [(greedy, (column,))])
    assert seen == [1.0]


@needs_c
def test_c_reads_any_sequence_as_a_column():
    class Values(list):
        pass

    calls, raised = run(
        c_call_rows,
        0,
        3,
        [(0, (Values([1, 2, 3]), range(3), (7, 8, 9)), None, None)],
        None,
    )
    assert raised is None
    assert [call[1] for call in calls] == [(1, 0, 7), (2, 1, 8), (3, 2, 9)]


class Counting(Canon):
    """A user's canon that defines only the single calls."""

    def __init__(self):
        self.made = []

    def straight_feed(self, *args):
        self.made.append(("feed",) + args)

    def arc_feed(self, *args):
        self.made.append(("arc",) + args)


def test_the_protocols_default_batches_make_one_call_a_row():
    canon = Counting()
    nine = [[float(axis * 10 + row) for row in range(3)] for axis in range(9)]
    canon.straight_moves(True, range(3), *nine)
    assert canon.made == [
        ("feed",) + tuple(column[row] for column in nine) for row in range(3)
    ]
    canon.made.clear()
    ends = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [0.5, 0.6, 0.7], [0.8, 0.9, 1.0]]
    rotation = [1, 0, -2]
    rest = [[9.0, 8.0, 7.0]] + [[float(k)] * 3 for k in range(6)]
    canon.contour_moves((0, 1, 2), [1, 2, 3], *ends, rotation, *rest)
    assert canon.made == [
        ("arc", 1.0, 4.0, 0.5, 0.8, 1, 9.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0),
        ("feed", 2.0, 5.0, 8.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0),
        ("arc", 3.0, 6.0, 0.7, 1.0, -2, 7.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0),
    ]
