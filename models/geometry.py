"""Planar geometry kernels used by the reference implementations and the proofs.

The one kernel here is the motion step of Song & O'Kane 2014 (000 Sec. IV-C,
Lemma 7, Fig. 6): a descendant robot ``r_i`` may reach the disc ``P_i`` of
radius ``v*dt`` around its own position, must stay in the disc ``P_p`` of
radius ``phi - v*dt`` around its parent's position, and goes to the point of
``P_i`` intersected with ``P_p`` nearest its ultimate destination.

:func:`nearest_point_in_disc_intersection` is exact on every case (target
inside both discs, one disc inside the other, tangent discs, empty
intersection, coincident centres, zero radii) up to floating-point rounding.

Why it is exact.  ``K = D1 & D2`` is convex, so the nearest point ``q`` of
``K`` to ``t`` is unique and is characterised by which constraints are
active at ``q``: none (``q = t``), only ``D1`` (then ``q`` is the projection
of ``t`` on ``D1``, because ``D1`` is convex and contains ``K``), only ``D2``
(symmetrically), or both (``q`` is one of the at most two points where the
circles cross).  The kernel therefore builds these at most four candidates,
keeps those that lie in ``K`` and returns the nearest.  Containment and
emptiness are decided first so that degenerate lenses never reach the
circle-intersection formulas.

References
----------
000_3ad33c5b62f11d5f.txt (Song & O'Kane, ICRA 2014), Sec. IV-C, Lemma 7,
Fig. 6 ("On the boundary of the intersection of P_p and P_i we choose the
nearest point to the desired ultimate destination position").
"""

from __future__ import annotations

import math

import numpy as np

from .errors import UsageError, check_finite

__all__ = ["nearest_point_in_disc_intersection", "nearest_xy"]

#: Relative tolerance (times the problem's scale) used when deciding that a
#: projection onto one disc also lies in the other.  A candidate accepted with
#: this slack is outside the other disc by at most ``_REL_TOL * scale``.
_REL_TOL = 8.0 * np.finfo(float).eps


def _point(name: str, value) -> tuple[float, float]:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise UsageError(f"{name}={value!r} must be a point (x, y) of two real numbers",
                         fix="pass a sequence or array of two finite floats") from None
    if arr.shape != (2,):
        raise UsageError(f"{name}={value!r} must be a point (x, y) of two real numbers, "
                         f"got shape {arr.shape}",
                         fix="pass a sequence or array of two finite floats")
    if not np.all(np.isfinite(arr)):
        raise UsageError(f"{name}={value!r} must have finite coordinates",
                         fix="pass a sequence or array of two finite floats")
    return float(arr[0]), float(arr[1])


def _radius(name: str, value) -> float:
    r = check_finite(name, value, fix="give a finite radius >= 0")
    if r < 0:
        raise UsageError(f"{name}={value!r} must be >= 0", fix="give a finite radius >= 0")
    return r


def _project_disc(cx: float, cy: float, r: float, tx: float, ty: float) -> tuple[float, float]:
    """Nearest point of the closed disc ``(c, r)`` to ``t``."""
    dx, dy = tx - cx, ty - cy
    dist = math.hypot(dx, dy)
    if dist <= r:
        return tx, ty
    # dist > r >= 0, so dist > 0.
    s = r / dist
    return cx + dx * s, cy + dy * s


def nearest_xy(c1x: float, c1y: float, r1: float, c2x: float, c2y: float, r2: float,
               tx: float, ty: float) -> tuple[float, float] | None:
    """Unchecked scalar core of :func:`nearest_point_in_disc_intersection`.

    Takes and returns plain floats (no validation, no numpy) for the
    simulation hot path; the arguments must already be finite with
    ``r1, r2 >= 0``.

    Examples
    --------
    >>> nearest_xy(0.0, 0.0, 1.0, 3.0, 0.0, 1.0, 0.0, 5.0) is None
    True
    """
    dx, dy = c2x - c1x, c2y - c1y
    d = math.hypot(dx, dy)
    # Empty exactly when the centres are farther apart than the radii sum.
    if d > r1 + r2:
        return None
    # One disc inside the other (includes coincident centres and zero radii
    # whenever the intersection is not empty): the intersection is that disc.
    if d + r1 <= r2:
        return _project_disc(c1x, c1y, r1, tx, ty)
    if d + r2 <= r1:
        return _project_disc(c2x, c2y, r2, tx, ty)
    # Here |r1 - r2| < d <= r1 + r2, so d > 0 and the circles cross (or touch
    # externally when d == r1 + r2: a single point).
    ux, uy = dx / d, dy / d
    if d == r1 + r2:
        return c1x + r1 * ux, c1y + r1 * uy
    scale = max(abs(c1x), abs(c1y), abs(c2x), abs(c2y), abs(tx), abs(ty), r1, r2)
    tol = _REL_TOL * scale
    # The target itself, if it lies in both discs.
    in1 = math.hypot(tx - c1x, ty - c1y) <= r1
    in2 = math.hypot(tx - c2x, ty - c2y) <= r2
    if in1 and in2:
        return tx, ty
    best: tuple[float, float] | None = None
    best_d2 = math.inf
    # Only D1 active: projection on D1, valid when it lies in D2.
    if not in1:
        px, py = _project_disc(c1x, c1y, r1, tx, ty)
        if math.hypot(px - c2x, py - c2y) <= r2 + tol:
            best, best_d2 = (px, py), (px - tx) ** 2 + (py - ty) ** 2
    if not in2:
        px, py = _project_disc(c2x, c2y, r2, tx, ty)
        if math.hypot(px - c1x, py - c1y) <= r1 + tol:
            d2 = (px - tx) ** 2 + (py - ty) ** 2
            if d2 < best_d2:
                best, best_d2 = (px, py), d2
    # Both active: the crossing points of the two circles (always in K).
    # a = signed distance from c1 to the radical line along u; h = half chord.
    a = (d * d + (r1 - r2) * (r1 + r2)) / (2.0 * d)
    if r2 < r1:
        # the half chord from the smaller circle: r1^2 - a^2 cancels catastrophically when the
        # small disc sits just inside the big circle (r2 = 1e-12 next to r1 = 6.6 lost 1e-7)
        b = (d * d - (r1 - r2) * (r1 + r2)) / (2.0 * d)     # signed distance from c2, back along u
        b = min(max(b, -r2), r2)
        h = math.sqrt(max((r2 - b) * (r2 + b), 0.0))
        mx, my = c2x - b * ux, c2y - b * uy
    else:
        a = min(max(a, -r1), r1)
        h = math.sqrt(max((r1 - a) * (r1 + a), 0.0))
        mx, my = c1x + a * ux, c1y + a * uy
    for sgn in (1.0, -1.0):
        px, py = mx - sgn * h * uy, my + sgn * h * ux
        d2 = (px - tx) ** 2 + (py - ty) ** 2
        if d2 < best_d2:
            best, best_d2 = (px, py), d2
    return best


def nearest_point_in_disc_intersection(c1, r1, c2, r2, target) -> np.ndarray | None:
    """The point of the intersection of two closed discs nearest to ``target``.

    Parameters
    ----------
    c1, c2 : array_like, shape (2,)
        Centres of the two discs.
    r1, r2 : float
        Their radii, finite and ``>= 0`` (a zero radius is a single point).
    target : array_like, shape (2,)
        The point to approach (000 Sec. IV-C: the ultimate destination).

    Returns
    -------
    numpy.ndarray of shape (2,), or None
        The unique nearest point of ``D(c1, r1) & D(c2, r2)`` to ``target``;
        ``target`` itself when it lies in both discs; None exactly when the
        intersection is empty, that is when ``|c1 - c2| > r1 + r2``.  The
        result lies in both discs up to a relative rounding slack of about
        ``1e-15`` times the largest coordinate or radius.

    Raises
    ------
    UsageError
        If a point is not two finite numbers or a radius is negative or not
        finite.

    References
    ----------
    000_3ad33c5b62f11d5f.txt, Sec. IV-C steps 1-3, Lemma 7 and Fig. 6: the
    descendant's reach ``P_i`` (radius ``v*dt``) intersected with the disc
    ``P_p`` of radius ``phi - v*dt`` around the parent.

    Examples
    --------
    Target inside both discs:

    >>> nearest_point_in_disc_intersection((0, 0), 1, (1, 0), 1, (0.5, 0.1)).tolist()
    [0.5, 0.1]

    One disc inside the other: the intersection is the small disc.

    >>> nearest_point_in_disc_intersection((0, 0), 5, (1, 0), 1, (10, 0)).tolist()
    [2.0, 0.0]

    The lens: a target straight above the lens reaches its top corner.

    >>> p = nearest_point_in_disc_intersection((0, 0), 1, (1, 0), 1, (0.5, 5))
    >>> [round(float(x), 12) for x in p]
    [0.5, 0.866025403784]

    Tangent discs meet in one point; disjoint ones do not meet.

    >>> nearest_point_in_disc_intersection((0, 0), 1, (3, 0), 2, (0, 9)).tolist()
    [1.0, 0.0]
    >>> nearest_point_in_disc_intersection((0, 0), 1, (3, 0), 1.5, (0, 0)) is None
    True
    """
    c1x, c1y = _point("c1", c1)
    c2x, c2y = _point("c2", c2)
    tx, ty = _point("target", target)
    r1f = _radius("r1", r1)
    r2f = _radius("r2", r2)
    res = nearest_xy(c1x, c1y, r1f, c2x, c2y, r2f, tx, ty)
    if res is None:
        return None
    return np.array(res, dtype=float)
