"""Tests for runtime.arcs: fixed cases taken from rs274 runs, and a randomised
comparison with the installed rs274 (marked ``rs274``)."""

from __future__ import annotations

import math
import re
import tempfile
from pathlib import Path

import pytest

import rs274 as harness
from runtime import arcs, ops
from runtime.errors import GCodeError

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings, strategies as st  # noqa: E402

# --------------------------------------------------------------------------
# Fixed cases (expected values observed in `rs274 -g` traces and messages)
# --------------------------------------------------------------------------


def test_spiral_error_message_names_plane_axes():
    # G19 from Y10 Z0: G3 Y0 Z5 J3 K3
    with pytest.raises(GCodeError) as err:
        arcs.arc_from_center(
            False, "YZ", (10.0, 0.0), (0.0, 5.0), (3.0, 3.0), False, 1, inch=False
        )
    assert err.value.message == (
        "Radius to end of arc differs from radius to start: start=(Y10.0000,Z0.0000) "
        "center=(Y13.0000,Z3.0000) end=(Y0.0000,Z5.0000) r1=4.2426 r2=13.1529 "
        "abs_err=8.91 rel_err=67.7438%"
    )


def test_zero_radius_message():
    with pytest.raises(GCodeError) as err:
        arcs.arc_from_center(
            True, "XY", (0.0, 0.0), (1.0, 0.0), (0.0001, 0.0), False, 1, inch=False
        )
    assert err.value.message == (
        "Zero-radius arc: start=(X0.0000,Y0.0000) center=(X0.0001,Y0.0000) "
        "end=(X1.0000,Y0.0000) r1=0.0001 r2=0.9999"
    )


def test_xz_radius_arc_centre_and_rotation():
    # G18 from X0 Y10 Z3: G2 X5 Z0 R5 -> ARC_FEED(0, 5, 4.9832, 4.5899, -1, 10, ...)
    start = arcs.to_plane("XZ", 0.0, 10.0, 3.0)[:2]
    end = arcs.to_plane("XZ", 5.0, 10.0, 0.0)[:2]
    arc = arcs.arc_from_radius(True, start, end, 5.0, 1, inch=False)
    got = [round(v, 4) for v in (arc.end1, arc.end2, arc.center1, arc.center2)]
    assert got == [0.0, 5.0, 4.9832, 4.5899]
    assert arc.rotation == -1


def test_turns_give_signed_rotation():
    arc = arcs.arc_from_center(
        False, "XY", (10.0, 0.0), (0.0, 10.0), (-10.0, 0.0), False, 2, inch=False
    )
    assert (arc.center1, arc.center2, arc.rotation) == (0.0, 0.0, 2)
    arc = arcs.arc_from_center(
        True, "XY", (0.0, 0.0), (1.0, 1.0), (0.5, 0.5), False, 3, inch=False
    )
    assert arc.rotation == -3


@pytest.mark.parametrize(
    "p, message",
    [
        (0.0, "P value should be 1 or greater with G2 or G3"),
        (-1.0, "P value should be 1 or greater with G2 or G3"),
        (1.4, "P value not an integer with M19 G2 or G3"),
        (1.01, "P value not an integer with M19 G2 or G3"),
    ],
)
def test_bad_turns(p, message):
    with pytest.raises(GCodeError, match=re.escape(message)):
        arcs.check_arc_turns(p)


def test_turns_default_and_near_integer():
    assert arcs.check_arc_turns(None) == 1
    assert arcs.check_arc_turns(1.001) == 1
    assert arcs.check_arc_turns(3.0) == 3


@pytest.mark.parametrize(
    "plane, words, absolute, message",
    [
        (
            "UV",
            {"x": 1.0, "i": 1.0},
            False,
            "Cannot do an arc in planes G17.1, G18.1, or G19.1",
        ),
        ("XY", {"x": 1.0}, False, "R i j k words all missing for arc"),
        (
            "XY",
            {"x": 1.0, "i": 0.5, "r": 3.0},
            False,
            "Mixed radius ijk format for arc",
        ),
        (
            "XY",
            {"x": 1.0, "i": 0.5, "k": 0.5},
            False,
            "K word given for arc in xy plane",
        ),
        ("YZ", {"x": 1.0, "i": 0.5}, False, "I word given for arc in yz plane"),
        ("XZ", {"x": 1.0, "j": 0.5}, False, "J word given for arc in xz plane"),
        (
            "XY",
            {"z": 3.0, "r": 0.5},
            False,
            "X and y words missing for arc in xy plane",
        ),
        (
            "XZ",
            {"y": 1.0, "r": 3.0},
            False,
            "X and z words missing for arc in xz plane",
        ),
        (
            "YZ",
            {"x": 1.0, "r": 3.0},
            False,
            "Y and z words missing for arc in yz plane",
        ),
        ("XY", {"x": 1.0, "i": 0.5}, True, "J word missing in absolute center arc"),
        ("XY", {"x": 1.0, "j": 3.0}, True, "I word missing in absolute center arc"),
        ("YZ", {"y": 1.0, "j": 3.0}, True, "K word missing in absolute center arc"),
        ("YZ", {"y": 1.0, "k": 3.0}, True, "J word missing in absolute center arc"),
        ("XZ", {"x": 1.0, "k": 3.0}, True, "I word missing in absolute center arc"),
        ("XZ", {"x": 1.0, "i": 3.0}, True, "K word missing in absolute center arc"),
    ],
)
def test_word_errors(plane, words, absolute, message):
    with pytest.raises(GCodeError, match=re.escape(message)):
        arcs.check_arc_format(plane, words)
        arcs.arc_center_words(plane, words, absolute)


def test_missing_incremental_center_word_is_zero():
    assert arcs.arc_center_words("XZ", {"x": 1.0, "i": 0.5}, False) == (0.0, 0.5)
    assert arcs.arc_center_words("XY", {"x": 1.0, "r": 2.0}, False) is None
    assert arcs.arc_center_words("XY", {"polar_dist": 1.0, "r": 2.0}, False) is None


@pytest.mark.parametrize(
    "mode, rate, speed, has_f, message",
    [
        (arcs.UNITS_PER_MINUTE, 0.0, 0.0, False, "Cannot make arc with zero feed rate"),
        (
            arcs.INVERSE_TIME,
            0.0,
            0.0,
            False,
            "F word missing with inverse time arc move",
        ),
        (
            arcs.UNITS_PER_REVOLUTION,
            1.0,
            0.0,
            True,
            "Cannot feed with zero spindle speed in feed per rev mode",
        ),
    ],
)
def test_feed_errors(mode, rate, speed, has_f, message):
    with pytest.raises(GCodeError, match=re.escape(message)):
        arcs.check_arc_feed(mode, rate, speed, has_f)


def test_radius_errors():
    with pytest.raises(GCodeError, match="Current point same as end point of arc"):
        arcs.arc_from_radius(True, (0.0, 0.0), (0.0, 0.0), 5.0, 1, inch=False)
    with pytest.raises(GCodeError, match="Arc radius too small to reach end point"):
        arcs.arc_from_radius(True, (0.0, 0.0), (20.0, 0.0), 5.0, 1, inch=False)


def test_arc_length_three_quarter_turn():
    # G18 G93 F2 G2 from Z-3 X0 around Z-3.5 X0.5 to Z-3 X1: rs274 set F 6.6643.
    start = (-3.0, 0.0)
    arc = arcs.Arc(-3.0, 1.0, -3.5, 0.5, -1)
    assert f"{arcs.arc_length(start, 1.0, arc, 1.0) * 2:.4f}" == "6.6643"


def test_plane_round_trip():
    for plane in arcs.PLANE_AXES:
        assert arcs.from_plane(plane, *arcs.to_plane(plane, 1.0, 2.0, 3.0)) == (
            1.0,
            2.0,
            3.0,
        )


# --------------------------------------------------------------------------
# Randomised comparison with rs274
# --------------------------------------------------------------------------

_PLANE_CODE = {"XY": "G17", "XZ": "G18", "YZ": "G19"}
_ARC_FEED = re.compile(r"ARC_FEED\(([^)]*)\)")


def _run_rs274(program: str) -> tuple[list[str], str]:
    """Run rs274 on ``program``; (ARC_FEED argument lists, error message)."""
    with tempfile.TemporaryDirectory() as folder:
        result = harness.run_rs274(Path(folder) / "arc.ngc", text=program)
    return _ARC_FEED.findall(result.stdout.decode()), result.err


def _num(value: float) -> str:
    return f"{value:.4f}"


coord = st.floats(-50, 50, allow_nan=False).map(lambda v: round(v, 4))


@st.composite
def arc_cases(draw):
    plane = draw(st.sampled_from(sorted(_PLANE_CODE)))
    inch = draw(st.booleans())
    clockwise = draw(st.booleans())
    start = (draw(coord), draw(coord))
    radius_mode = draw(st.booleans())
    turns = draw(st.integers(1, 3))
    radius = draw(st.floats(0.0005, 40)).__round__(4)
    angle = draw(st.floats(-7, 7))
    # Perturb the end point sometimes, to reach the tolerance errors.
    wobble = draw(st.sampled_from([0.0, 0.0, 0.0005, 0.004, 0.05, 2.0]))
    centre = (draw(coord), draw(coord))
    start_radius = math.hypot(start[0] - centre[0], start[1] - centre[1])
    end = (
        round(centre[0] + (start_radius + wobble) * math.cos(angle), 4),
        round(centre[1] + (start_radius + wobble) * math.sin(angle), 4),
    )
    absolute_ijk = draw(st.booleans())
    signed_r = radius * draw(st.sampled_from([1, -1]))
    return (
        plane,
        inch,
        clockwise,
        start,
        end,
        centre,
        absolute_ijk,
        radius_mode,
        signed_r,
        turns,
    )


def _expected(
    plane, inch, clockwise, start, end, centre, absolute_ijk, radius_mode, r, turns
):
    try:
        if radius_mode:
            arc = arcs.arc_from_radius(clockwise, start, end, r, turns, inch)
        else:
            words = (
                centre
                if absolute_ijk
                else (round(centre[0] - start[0], 4), round(centre[1] - start[1], 4))
            )
            arc = arcs.arc_from_center(
                clockwise, plane, start, end, words, absolute_ijk, turns, inch
            )
    except GCodeError as err:
        return None, err.message
    values = [arc.end1, arc.end2, arc.center1, arc.center2]
    return ", ".join([_num(v) for v in values] + [str(arc.rotation)]), ""


def _program(
    plane, inch, clockwise, start, end, centre, absolute_ijk, radius_mode, r, turns
):
    first, second, _ = arcs.PLANE_AXES[plane]
    letters = {"X": "I", "Y": "J", "Z": "K"}
    if radius_mode:
        format_words = f"R{_num(r)}"
    else:
        words = (
            centre
            if absolute_ijk
            else (round(centre[0] - start[0], 4), round(centre[1] - start[1], 4))
        )
        format_words = (
            f"{letters[first]}{_num(words[0])} {letters[second]}{_num(words[1])}"
        )
    return "\n".join(
        [
            f"{'G20' if inch else 'G21'} {_PLANE_CODE[plane]} {'G90.1' if absolute_ijk else 'G91.1'} F100",
            f"G0 {first}{_num(start[0])} {second}{_num(start[1])}",
            f"{'G2' if clockwise else 'G3'} {first}{_num(end[0])} {second}{_num(end[1])} {format_words} P{turns}",
            "M2",
            "",
        ]
    )


@pytest.mark.rs274
@settings(max_examples=300, deadline=None)
@given(arc_cases())
def test_random_arcs_match_rs274(case):
    feeds, error = _run_rs274(_program(*case))
    expected_args, expected_error = _expected(*case)
    assert error == expected_error
    if expected_args is not None:
        assert len(feeds) == 1
        # Drop the axis end point and a, b, c: not arcs.py's business.
        assert ", ".join(feeds[0].split(", ")[:5]) == expected_args


@given(
    st.one_of(
        st.floats(-math.pi, math.pi),
        st.floats(-1e-18, 1e-18),
        st.sampled_from([math.pi, -math.pi, math.pi / 2, -math.pi / 2, 0.0, -0.0]),
        st.integers(-200, 200).map(lambda k: math.pi / 2 + k * 2.0**-52),
        st.integers(-200, 200).map(lambda k: -math.pi / 2 + k * 2.0**-52),
    ),
    st.sampled_from([1, -1]),
)
def test_fast_half_pi_sum_is_the_exact_one(x, sign):
    """runtime.ops adds M_PI_2l with scaled integers: the same double as
    exact fractions, near the cancellations too."""
    assert ops.plus_half_pi(x, sign) == ops.plus_half_pi_exact(x, sign)
