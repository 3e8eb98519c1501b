"""Cutter radius compensation as seen from Python (rs274 itself is compared
in golden/cutter_comp and tests/test_differential.py).

These pin down the runtime's side of the contract: a canon passed in by the
user receives the held-back calls in rs274's order and with the N number of
the line that released them, the machine's canon is the user's again once
compensation is off, and the long double sums the geometry relies on.
"""

from __future__ import annotations

import math

from runtime.canon import RecordingCanon
from runtime.codes import G1, G40, G41_1, M2
from runtime.comments import Comment
from runtime.cutter_comp import QueueingCanon
from runtime.machine import Machine
from runtime.mcodes import ProgramEnd
from runtime.ops import HALF_PI_L, PI_L, long_double_sum, plus_half_pi


def _run(blocks):
    canon = RecordingCanon()
    m = Machine(canon)
    m._initialise()
    m._start()
    canon.calls.clear()
    canon.numbers.clear()
    try:
        for line, (codes, n, words, comment) in enumerate(blocks, start=1):
            m.block(line, *codes, n=n, comment=comment, **words)
    except ProgramEnd:
        pass
    return m, canon


def test_queued_calls_reach_a_user_canon_in_rs274_order():
    m, canon = _run(
        [
            ((), None, {"f": 100.0}, None),
            ((G41_1,), "1", {"d": 2.0}, None),
            ((G1,), "2", {"x": 10.0, "y": 0.0}, None),
            ((), "3", {}, Comment("comment", "held")),
            ((G1,), "4", {"y": 10.0}, None),
        ]
    )
    assert isinstance(m.canon, QueueingCanon) and m.canon.inner is canon
    names = [name for name, _ in canon.calls]
    # The entry move waits for line 4; the comment waits behind it.
    assert names == ["set_feed_rate", "comment", "straight_feed", "comment"]
    assert canon.calls[3][1] == ("held",)
    assert canon.numbers[2:] == ["4", "4"]
    m.block(6, G40, n="6")
    assert m.canon is canon
    assert [name for name, _ in canon.calls[4:]] == ["straight_feed", "comment"]
    assert canon.numbers[4:] == ["6", "6"]


def test_program_end_flushes_and_restores_the_canon():
    m, canon = _run(
        [
            ((G41_1,), None, {"d": 2.0, "f": 100.0}, None),
            ((G1,), None, {"x": 10.0, "y": 0.0}, None),
            ((M2,), "9", {}, None),
        ]
    )
    assert m.canon is canon
    feeds = [i for i, (name, _) in enumerate(canon.calls) if name == "straight_feed"]
    assert len(feeds) == 1
    x, y = canon.calls[feeds[0]][1][:2]
    assert math.isclose(x, 10.0) and math.isclose(y, 1.0)
    assert canon.numbers[feeds[0]] == "9"


def test_long_double_sum_rounds_like_x87():
    # Each partial sum is a long double; only the result becomes a double.
    for x in (0.3, -2.1, 1e-9, 3.0, -math.pi):
        assert long_double_sum(x, HALF_PI_L) == plus_half_pi(x)
        assert long_double_sum(x, -HALF_PI_L) == plus_half_pi(x, -1)
    assert long_double_sum(0.0, 2 * PI_L) == 2 * math.pi
    assert long_double_sum(-1.0, PI_L, 1.0 - math.pi) != 0.0  # not cancelled in doubles


def test_sin_of_a_long_double_sum_is_sinl_of_the_unrounded_sum():
    # rs274's arc_radius * sin(beta - M_PI_2l): sinl of the long double sum,
    # a long double product stored into a double. With beta a double just
    # below pi, the double route gives -27.5 exactly, rs274 a last-bit
    # smaller magnitude (golden/cutter_comp/concave_line_to_arc_sinl).
    from runtime.ops import long_double_sin_product

    assert long_double_sin_product(2.0, 0.0) == 0.0
    assert math.copysign(1.0, long_double_sin_product(2.0, -0.0)) == -1.0
    # sinl(pi_l/2 - pi_l/2 + tiny) == tiny: small arguments come back exactly
    assert long_double_sin_product(1.0, 1e-30) == 1e-30
    # against the C library's sinl where this platform has the x87 format
    import ctypes

    if ctypes.sizeof(ctypes.c_longdouble) == 16:
        libm = ctypes.CDLL(None)
        sinl = libm.sinl
        sinl.restype, sinl.argtypes = ctypes.c_longdouble, [ctypes.c_longdouble]
        for beta in (0.1, 1.0, 2.5, 3.0, 4.0, 5.5):
            # a double argument: no long double sum needed to compare
            assert long_double_sin_product(1.0, beta) == sinl(beta)
