"""Geometry of the No Child Left Behind (NCLB) motion of Song & O'Kane 2016.

Pure functions in a robot's body frame (the robot at the origin, facing +x),
used by :mod:`swarmproof.reference_impl.song2016`:

* :func:`bounded_range_radius`: the radius ``phi - v*dt`` of a bounded range
  (001 Lemma 7, Def. 8);
* :func:`closest_point_in_discs`: the point of the *safe region* (the
  intersection of the children's bounded ranges, 001 Sec. V-C) closest to a
  goal, or ``None`` when the safe region is empty; this is the
  "intermediate goal" g_i of 001 Fig. 9 [right] and g_p of Fig. 11 [right];
* :func:`reachable_point`: where a differential-drive command "turn toward
  the point, then drive" ends after one step under the engine's limits
  (protocol.py: ``|turn| <= omega*dt``, ``forward <= v*(dt - |turn|/omega)``).

All functions use plain floats (the number of children is small), so they
are fast per call and exact to floating point.

References
----------
001_7a4e517b856331bc.txt, Sec. IV (Lemma 7, Definition 8), Sec. V-C
(safe region, NCLB, Figs. 9 and 11).
"""

from __future__ import annotations

import math
from typing import Sequence

__all__ = ["bounded_range_radius", "in_discs", "closest_point_in_discs", "reachable_point",
           "SAFE_MARGIN"]

#: Relative margin by which bounded ranges are shrunk before use, so that a
#: position chosen inside the safe region stays inside it after the engine
#: recomputes it in global coordinates (floating-point error ~1e-15).
SAFE_MARGIN = 1e-9

#: Absolute tolerance for membership tests of points computed on a boundary.
_TOL = 1e-12


def bounded_range_radius(phi: float, v: float, dt: float) -> float:
    """Radius of a bounded range, ``phi - v*dt`` (001 Def. 8).

    Examples
    --------
    >>> bounded_range_radius(1.2, 0.05, 1.0)
    1.15

    References
    ----------
    001_7a4e517b856331bc.txt, Lemma 7 and Definition 8.
    """
    return phi - v * dt


def in_discs(x: float, y: float, centers: Sequence[tuple[float, float]], radius: float,
             tol: float = _TOL) -> bool:
    """Whether ``(x, y)`` lies in every disc of ``radius`` around ``centers``.

    An empty list of centers is the whole plane (a robot without children
    has no NCLB constraint).

    Examples
    --------
    >>> in_discs(0.5, 0.0, [(0.0, 0.0), (1.0, 0.0)], 0.6)
    True
    >>> in_discs(0.0, 0.0, [(1.0, 0.0)], 0.6)
    False
    >>> in_discs(9.0, 9.0, [], 0.6)
    True
    """
    lim = (radius + tol) ** 2
    for cx, cy in centers:
        dx, dy = x - cx, y - cy
        if dx * dx + dy * dy > lim:
            return False
    return True


def closest_point_in_discs(goal: tuple[float, float], centers: Sequence[tuple[float, float]],
                           radius: float) -> tuple[float, float] | None:
    """The point of ``intersection of discs(center, radius)`` closest to ``goal``.

    This is the intermediate goal of 001 Sec. V-C (Figs. 9 and 11): a moving
    robot stays inside the intersection of its children's bounded ranges
    (the *safe region*) and heads for the point of it nearest its goal.

    The intersection of discs is convex, so the closest point is unique.  It
    is either ``goal`` itself (when inside), or the projection of ``goal``
    onto one disc (one active constraint), or a point where two boundary
    circles cross (two active constraints); all candidates are enumerated and
    the feasible one nearest ``goal`` is returned, which is exact.

    Parameters
    ----------
    goal : (float, float)
        Body-frame point the robot wants to reach.
    centers : sequence of (float, float)
        Body-frame positions of the children; empty means no constraint.
    radius : float
        Common radius (``phi - v*dt``, possibly shrunk by :data:`SAFE_MARGIN`).

    Returns
    -------
    (float, float) or None
        The intermediate goal, or ``None`` when the safe region is empty
        ("In that case, the robot does not move", 001 Sec. V-C).

    Examples
    --------
    >>> closest_point_in_discs((3.0, 0.0), [(0.0, 0.0)], 1.0)
    (1.0, 0.0)
    >>> closest_point_in_discs((0.5, 0.0), [(0.0, 0.0)], 1.0)
    (0.5, 0.0)
    >>> x, y = closest_point_in_discs((0.0, 5.0), [(-0.5, 0.0), (0.5, 0.0)], 1.0)
    >>> round(x, 12), round(y, 12)
    (0.0, 0.866025403784)
    >>> closest_point_in_discs((0.0, 0.0), [(-3.0, 0.0), (3.0, 0.0)], 1.0) is None
    True

    References
    ----------
    001_7a4e517b856331bc.txt, Sec. V-C, Figs. 9 [right] and 11 [right].
    """
    gx, gy = float(goal[0]), float(goal[1])
    if not centers:
        return (gx, gy)
    if in_discs(gx, gy, centers, radius):
        return (gx, gy)
    r = radius
    candidates: list[tuple[float, float]] = []
    for cx, cy in centers:
        dx, dy = gx - cx, gy - cy
        d = math.hypot(dx, dy)
        if d <= r:  # goal inside this disc: its projection is goal, already infeasible
            continue
        px, py = cx + r * dx / d, cy + r * dy / d
        if in_discs(px, py, centers, r):
            candidates.append((px, py))
    k = len(centers)
    for i in range(k):
        ax, ay = centers[i]
        for j in range(i + 1, k):
            bx, by = centers[j]
            dx, dy = bx - ax, by - ay
            d = math.hypot(dx, dy)
            if d > 2 * r + _TOL:
                return None  # two disjoint discs: the intersection is empty
            if d == 0.0:
                continue
            a = min(d / 2.0, r)
            h = math.sqrt(max(r * r - a * a, 0.0))
            mx, my = ax + dx / 2.0, ay + dy / 2.0
            ux, uy = -dy / d, dx / d
            for s in (1.0, -1.0):
                px, py = mx + s * h * ux, my + s * h * uy
                if in_discs(px, py, centers, r):
                    candidates.append((px, py))
    if not candidates:
        return None
    return min(candidates, key=lambda p: (p[0] - gx) ** 2 + (p[1] - gy) ** 2)


def farthest_point_toward(goal: tuple[float, float], centers: Sequence[tuple[float, float]],
                          radius: float) -> tuple[float, float] | None:
    """The point of the segment from the robot (the origin) to ``goal`` that lies in every
    disc of ``radius`` around ``centers`` and is nearest ``goal``; None when none does.

    This is the way point of a robot of the moving subtree, 001 Sec. V-C case 3: it "moves
    directly toward its parent while staying within its own NCLB safe region" -- along the
    straight line to the parent, never off it (unlike :func:`closest_point_in_discs`, the
    intermediate goal Figs. 9 and 11 give the relocate robot, which may slide along the
    region's border).  A robot that starts outside its safe region (a child farther than
    phi - v*dt) goes to where the line re-enters the region, and waits when the line misses
    it (as "the robot does not move" for an empty region).

    Examples
    --------
    >>> farthest_point_toward((3.0, 0.0), [(0.0, 0.0)], 1.0)
    (1.0, 0.0)
    >>> farthest_point_toward((0.5, 0.0), [(0.0, 0.0)], 1.0)
    (0.5, 0.0)
    >>> farthest_point_toward((3.0, 0.0), [(2.0, 0.0)], 0.5)     # starts outside, enters
    (2.5, 0.0)
    >>> farthest_point_toward((3.0, 0.0), [(-1.0, 0.0)], 0.5) is None  # child behind: wait
    True
    >>> farthest_point_toward((1.0, 1.0), [], 0.5)
    (1.0, 1.0)

    References
    ----------
    001_7a4e517b856331bc.txt, Sec. V-C (case 3; "the children ... will only move toward the
    robot"), Lemma 11.
    """
    gx, gy = float(goal[0]), float(goal[1])
    lo, hi = 0.0, 1.0
    gg = gx * gx + gy * gy
    if gg == 0.0:
        return (0.0, 0.0) if in_discs(0.0, 0.0, centers, radius) else None
    for cx, cy in centers:
        # |t g - c|^2 <= r^2  <=>  gg t^2 - 2 (g.c) t + (|c|^2 - r^2) <= 0
        b = gx * cx + gy * cy
        c = cx * cx + cy * cy - radius * radius
        disc = b * b - gg * c
        if disc < 0.0:
            return None
        root = math.sqrt(disc)
        lo = max(lo, (b - root) / gg)
        hi = min(hi, (b + root) / gg)
        if lo > hi:
            return None
    t = hi
    x, y = t * gx, t * gy
    if not in_discs(x, y, centers, radius):
        # rounding at the border: step back a hair along the line
        t = max(lo, hi * (1.0 - 1e-12))
        x, y = t * gx, t * gy
        if not in_discs(x, y, centers, radius):
            return None
    return (x, y)


def reachable_point(target: tuple[float, float], v: float, omega: float, dt: float
                    ) -> tuple[float, float, float, float]:
    """Where "turn toward ``target``, then drive" ends after one step.

    Mirrors the engine's differential-drive limits (protocol.py): the turn is
    at most ``omega*dt``; the time left drives at most ``v*(dt - |turn|/omega)``,
    and never past the target.

    Returns
    -------
    (turn, forward, x, y)
        The command (turn in radians, forward distance) and the body-frame
        end position.

    Examples
    --------
    >>> t, f, x, y = reachable_point((0.0, 1.0), 0.1, math.pi, 1.0)
    >>> round(t, 6), round(f, 6), round(x, 6), round(y, 6)
    (1.570796, 0.05, 0.0, 0.05)
    >>> reachable_point((0.02, 0.0), 0.1, math.pi, 1.0)
    (0.0, 0.02, 0.02, 0.0)
    >>> reachable_point((-1.0, 0.0), 0.1, math.pi / 4, 1.0)[1:]
    (0.0, 0.0, 0.0)
    """
    tx, ty = float(target[0]), float(target[1])
    dist = math.hypot(tx, ty)
    if dist == 0.0:
        return (0.0, 0.0, 0.0, 0.0)
    turn = math.atan2(ty, tx)
    max_turn = omega * dt
    if abs(turn) >= max_turn:
        return (math.copysign(max_turn, turn) if abs(turn) > max_turn else turn, 0.0, 0.0, 0.0)
    forward = min(dist, v * (dt - abs(turn) / omega))
    if forward <= 0.0:
        return (turn, 0.0, 0.0, 0.0)
    if forward == dist:
        return (turn, forward, tx, ty)
    return (turn, forward, forward * math.cos(turn), forward * math.sin(turn))
