"""Arc extents are exact and O(1): against a dense sampling of the same arc.

runtime.toolpath.Arc.extreme_points finds where an arc or spiral is furthest
out along its plane's axes by a formula (no sampling); these tests draw
arcs of every kind (both directions, many turns, helices, spirals whose
radius grows or shrinks, tiny and huge radii) and hold the bounding box of
those points to the box of thousands of points along the arc.
"""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from runtime.toolpath import PLANE_AXES, make_arc

finite = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False)


def box(points, axes):
    return [(min(p[a] for p in points), max(p[a] for p in points)) for a in axes]


def dense_box(arc, per_turn=20000):
    """The box of thousands of points along ``arc``: its parametrisation
    (Arc.point's: the plane's axes by angle and radius, the others
    linearly, kept between their ends) evaluated at once with NumPy."""
    count = max(2000, int(abs(arc.sweep) / (2 * math.pi) * per_turn))
    t = np.arange(count + 1) / count
    f, s, _ = arc.axes
    theta = arc.theta0 + arc.sweep * t
    radius = arc.r0 + (arc.r1 - arc.r0) * t
    columns = []
    for axis, (a, b) in enumerate(zip(arc.start, arc.end)):
        if axis == f:
            column = arc.centre[0] + radius * np.cos(theta)
        elif axis == s:
            column = arc.centre[1] + radius * np.sin(theta)
        else:
            column = np.clip(a + (b - a) * t, min(a, b), max(a, b))
        columns.append((float(column.min()), float(column.max())))
    return columns


@st.composite
def arcs(draw):
    plane = draw(st.sampled_from(sorted(PLANE_AXES)))
    axes = PLANE_AXES[plane]
    f, s, n = axes
    scale = draw(st.sampled_from((1e-3, 1.0, 50.0, 5000.0)))
    cf, cs = draw(finite), draw(finite)
    r0 = draw(st.floats(0.01, 1.0)) * scale
    r1 = r0 * draw(st.sampled_from((1.0, 1.0 + 1e-9, 1.0001, 1.2, 3.0, 0.3, 0.01)))
    a0 = draw(st.floats(-math.pi, math.pi))
    a1 = draw(st.floats(-math.pi, math.pi))
    start, end = [0.0] * 9, [0.0] * 9
    start[f], start[s] = cf + r0 * math.cos(a0), cs + r0 * math.sin(a0)
    end[f], end[s] = cf + r1 * math.cos(a1), cs + r1 * math.sin(a1)
    start[n], end[n] = draw(finite), draw(finite)
    rotation = draw(st.sampled_from((1, -1, 2, -2, 5, -7)))
    return make_arc(tuple(start), tuple(end), axes, (cf, cs), rotation)


@settings(max_examples=300, deadline=None)
@given(arcs())
def test_extents_bound_the_arc_and_are_reached(arc):
    exact = box(arc.extreme_points(), range(9))
    sampled = dense_box(arc)
    size = max(arc.r0, arc.r1, 1e-9)
    for (lo, hi), (slo, shi) in zip(exact, sampled):
        # Every sampled point lies inside the exact box ...
        # (give or take the rounding of a coordinate's own size)
        rounding = 1e-9 * size + 1e-12 * max(abs(lo), abs(hi), 1.0)
        assert lo <= slo + rounding and shi <= hi + rounding
        # ... and the exact box is no bigger than the arc: sampling 20k
        # points a turn misses a peak by at most half its curvature times
        # the half step squared, (r + 2|dr/dθ|) (pi / 20000)² / 2 (for a
        # circle, r (1 - cos(pi / 20000))).
        spiral = 2.0 * abs(arc.r1 - arc.r0) / abs(arc.sweep) if arc.sweep else 0.0
        slack = (size + spiral) * 2e-8 + 1e-9 * max(abs(lo), abs(hi), 1.0)
        assert slo - lo <= slack and hi - shi <= slack


def test_a_quarter_arc_crosses_one_quadrant_point():
    arc = make_arc((1.0, 0.0) + (0.0,) * 7, (0.0, 1.0) + (0.0,) * 7, (0, 1, 2), (0.0, 0.0), 1)
    assert box(arc.extreme_points(), (0, 1)) == [(0.0, 1.0), (0.0, 1.0)]
    arc = make_arc((1.0, -0.5) + (0.0,) * 7, (1.0, 0.5) + (0.0,) * 7, (0, 1, 2), (0.0, 0.0), 1)
    xs = [p[0] for p in arc.extreme_points()]
    assert max(xs) == math.hypot(1.0, 0.5)


def test_many_turns_cost_no_more_points():
    one = make_arc((1.0,) + (0.0,) * 8, (2.0,) + (0.0,) * 8, (0, 1, 2), (0.0, 0.0), 1)
    many = make_arc((1.0,) + (0.0,) * 8, (2.0,) + (0.0,) * 8, (0, 1, 2), (0.0, 0.0), 100000)
    assert len(many.extreme_points()) <= 2 + 8
    assert len(one.extreme_points()) <= 2 + 8
    # the spiral grows from radius 1 to 2: the last turn reaches about -2 in X
    assert min(p[0] for p in many.extreme_points()) < -1.99999


def test_a_far_normal_axis_is_bounded_within_its_rounding():
    # Found by a run: a tiny arc whose Z travels a thousand millimetres
    # (a sample's Z rounds a little past the end's).
    arc = make_arc(
        (6.25e-05, 0.0, 884.0) + (0.0,) * 6,
        (3.376889411675873e-05, 5.2591936550493535e-05, -140.4879501394438) + (0.0,) * 6,
        (0, 1, 2),
        (0.0, 0.0),
        1,
    )
    test_extents_bound_the_arc_and_are_reached.hypothesis.inner_test(arc)


def test_a_sweep_too_small_to_divide_by_is_bounded_by_its_ends():
    # Found by CI: the change of radius over a subnormal sweep overflows
    # dr/dθ; such an arc is a radial segment between its ends.
    start = (0.0005, 1.112536929256e-312) + (0.0,) * 7
    end = (0.00015, 3.3376107878e-313) + (0.0,) * 7
    arc = make_arc(start, end, (0, 1, 2), (0.0, 0.0), 1)
    assert 0.0 < arc.sweep < 1e-300
    assert box(arc.extreme_points(), range(9)) == box([start, end], range(9))
