"""Jiang et al. (002) Defs. 4-9 computed exactly (models/formation_quality.py), against a brute
force over every partition of small configurations."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest

from swarmproof.models.formation_quality import formation_quality

TOL = 1e-9


def _partitions(items):
    """Every set partition of ``items`` (Bell-number many)."""
    if not items:
        yield []
        return
    first, rest = items[0], items[1:]
    for p in _partitions(rest):
        yield [[first]] + p
        for k in range(len(p)):
            yield p[:k] + [[first] + p[k]] + p[k + 1:]


def _translations(part, xy, basic):
    """Every v with p + v in B for all p of the part (Def. 4)."""
    out = []
    p0 = xy[part[0]]
    for bj in basic:
        v = bj - p0
        if all(np.min(np.hypot(*(basic - (xy[p] + v)).T)) <= TOL for p in part):
            out.append(v)
    return out


def brute_gamma(xy, basic):
    xy, basic = np.asarray(xy, float), np.asarray(basic, float)
    b = len(basic)
    best = Fraction(-1)
    for part in _partitions(list(range(len(xy)))):
        beta = sum((Fraction(len(s), b) for s in part if _translations(s, xy, basic)), Fraction(0)) / len(part)
        best = max(best, beta)
    return best


SEG = [(0, 0), (1, 0)]
TRI = [(0, 0), (1, 0), (0.5, math.sqrt(3) / 2)]
SQ = [(0, 0), (1, 0), (0, 1), (1, 1)]


@pytest.mark.parametrize("basic", [SEG, TRI, SQ], ids=["segment", "triangle", "square"])
@pytest.mark.parametrize("seed", range(12))
def test_gamma_equals_brute_force_on_small_configurations(basic, seed):
    """Points on a small integer grid (so that parts of copies really occur), 3..7 robots."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 8))
    cells = [(x, y) for x in range(4) for y in range(3)]
    if basic is TRI:
        cells = [(x + 0.5 * (y % 2), y * math.sqrt(3) / 2) for x in range(4) for y in range(3)]
    pick = rng.choice(len(cells), size=n, replace=False)
    xy = [cells[k] for k in sorted(pick)]
    q = formation_quality(xy, basic, [(0, 0), (2, 0)], tol=TOL)
    assert q.exact
    assert q.gamma == brute_gamma(xy, basic), (xy, q)
    assert q.epsilon == q.gamma * q.delta


def test_an_incompatible_rest_can_beat_lone_robots():
    """Def. 6 over *all* partitions: lumping the leftovers into one incompatible part (alpha 0)
    scores better than leaving them alone (alpha 1/|B| each) when the copies are many -- a
    consequence of Eq. 1's mean that the exact optimum must and does find."""
    basic = [(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0)]
    xy = [(x, 0) for x in range(6)] + [(100, 0), (200, 0)]          # one full copy, two strays
    q = formation_quality(xy, basic, [(0, 1)], tol=TOL)
    # {copy}, {stray}, {stray}: (1 + 1/6 + 1/6) / 3 = 4/9;  {copy}, {both strays}: (1 + 0) / 2 = 1/2
    assert q.gamma == Fraction(1, 2) == brute_gamma(xy, basic)
    assert sum(1 for c, _ in q.parts if c is None) == 1


def test_perfect_formation_and_one_robot_off():
    basic = SQ
    centers = [(0, 0), (2, 0), (0, 2), (2, 2)]
    xy = [(cx + x, cy + y) for cx, cy in centers for x, y in basic]
    A = [(0, 0), (2, 0), (0, 2)]
    q = formation_quality(xy, basic, A)
    assert (q.exact, q.gamma, q.delta, q.epsilon, q.method) == (True, 1, 1, 1, "perfect-cover")
    assert q.optimal_partitions == "one" and q.components == 1
    moved = list(xy)
    moved[5] = (50, 50)
    q2 = formation_quality(moved, basic, A)
    assert q2.exact and q2.gamma < 1 and q2.method == "milp"
    # far apart copies: gamma 1 but two components
    far = [(cx + x + (100 if cx else 0), cy + y) for cx, cy in centers for x, y in basic]
    q3 = formation_quality(far, basic, A)
    assert q3.gamma == 1 and q3.delta == Fraction(1, 2) and q3.epsilon == Fraction(1, 2)


def test_tolerance_is_declared_and_used():
    xy = [(0, 0), (1 + 1e-3, 0)]
    assert formation_quality(xy, SEG, [(0, 1)], tol=1e-2).gamma == 1
    assert formation_quality(xy, SEG, [(0, 1)], tol=1e-6).gamma == Fraction(1, 2)


def test_budgets_give_inconclusive_with_bounds_never_a_wrong_number():
    rng = np.random.default_rng(3)
    xy = rng.integers(0, 6, size=(40, 2)).astype(float)
    xy = np.unique(xy, axis=0)
    q = formation_quality(xy, SQ, [(0, 2)], max_milp_nodes=1, max_cover_nodes=1)
    full = formation_quality(xy, SQ, [(0, 2)])
    assert full.exact
    if not q.exact:
        assert q.gamma is None and q.epsilon is None
        lo, hi = q.gamma_bounds
        assert lo <= full.gamma <= hi


def test_no_robots_is_inconclusive():
    q = formation_quality([], SEG, [(0, 1)])
    assert not q.exact and q.epsilon is None and q.message == "no robots"


def test_among_optimal_partitions_whole_copies_are_preferred():
    """n = 3 k + 1 on triangles: k full copies and a lone robot, or k - 1 copies and two pairs,
    give the same gamma; the partition reported keeps the whole copies, whose centers (and the
    lone robot's, on its slot) are linked by A, so delta = 1."""
    from swarmproof.models.repeating_pattern import load_pattern

    pat = load_pattern("rhombus-triangles")
    pts = pat.formation(31)
    q = formation_quality(pts, pat.basic, pat.assembling, tol=pat.tol)
    assert q.exact and q.gamma == Fraction(31, 33)
    assert q.completion_rates() == {"1": 10, "1/3": 1} and q.delta == 1 and q.epsilon == q.gamma
