"""The curve of a NURBS_FEED, as LinuxCNC's preview draws it.

Every spline (G5, G5.1, G5.2/G5.3) reaches the canon as one NURBS_FEED
with control points ``(x, y, weight)`` and an order ``k``. The stand-alone
canon prints only how many points there are; LinuxCNC's ``gcode`` module
(the preview of Axis and the other GUIs) turns the call into straight feeds
through points of the curve, and :func:`preview_points` gives those same
points: ``15`` per control point, evenly spaced in the curve's parameter,
then the last control point.

The curve is the rational B-spline over a clamped, uniform knot vector
(``k`` zeros, ``1 .. n-k+1``, ``k`` times ``n-k+2``, for ``n + 1`` points).
LinuxCNC's basis functions take each knot span closed at both ends, so at
an inner knot two spans count; that is kept, since the preview's points
depend on it. Standard library only.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import List, Sequence, Tuple

    ControlPoint = Tuple[float, float, float]

#: Straight feeds per control point in the preview's polyline.
SEGMENTS_PER_POINT = 15


def knot_vector(n: int, k: int) -> List[int]:
    """Knots for ``n + 1`` control points of order ``k`` (clamped, uniform)."""
    top = n - k + 2
    return [0 if i < k else (i - k + 1 if i <= n else top) for i in range(n + k + 1)]


def _basis(i: int, k: int, u: float, knots: Sequence[int]) -> float:
    """The B-spline basis N(i, k) at ``u`` (Cox-de Boor; a term whose
    denominator is zero is left out)."""
    if k == 1:
        return 1.0 if knots[i] <= u <= knots[i + 1] else 0.0
    left = knots[i + k - 1] - knots[i]
    right = knots[i + k] - knots[i + 1]
    total = 0.0
    if left == 0 and right == 0:
        return 0.0
    if left != 0:
        total = (u - knots[i]) * _basis(i, k - 1, u, knots) / left
    if right != 0:
        term = (knots[i + k] - u) * _basis(i + 1, k - 1, u, knots) / right
        total = term if left == 0 else total + term
    return total


def curve_point(
    u: float, k: int, points: Sequence[ControlPoint], knots: Sequence[int]
) -> Tuple[float, float]:
    """The curve at parameter ``u`` (0 .. n-k+2)."""
    basis = [_basis(i, k, u, knots) for i in range(len(points))]
    denominator = 0.0
    for b, p in zip(basis, points):
        denominator += b * p[2]
    x = y = 0.0
    for b, p in zip(basis, points):
        x += p[0] * b * p[2] / denominator
        y += p[1] * b * p[2] / denominator
    return x, y


def preview_points(
    points: Sequence[ControlPoint], order: int
) -> List[Tuple[float, float]]:
    """The ends of the straight feeds the preview makes of a NURBS_FEED."""
    n = len(points) - 1
    k = int(order)
    top = n - k + 2
    divisions = len(points) * SEGMENTS_PER_POINT
    knots = knot_vector(n, k)
    step = top / divisions
    out = []
    u = 0.0
    while u + step < top:
        out.append(curve_point(u + step, k, points, knots))
        u = u + step
    out.append((points[n][0], points[n][1]))
    return out


__all__ = ["curve_point", "knot_vector", "preview_points", "SEGMENTS_PER_POINT"]
