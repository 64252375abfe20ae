"""Tests of swarmproof.models.geometry: the nearest point of two discs' intersection.

The oracle is independent of the kernel's case analysis: it samples the
boundary arcs of the intersection densely (points of each circle that lie in
the other disc) plus the target when it lies in both discs, and the kernel's
answer must (1) lie in both discs and (2) be no farther from the target than
any sampled feasible point.  Since the intersection is convex, (1) and (2)
over a dense boundary sample pin the answer down.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from swarmproof.models.errors import UsageError
from swarmproof.models.geometry import nearest_point_in_disc_intersection, nearest_xy

N_ARC = 4096
TOL = 1e-9


def in_disc(p, c, r, tol=TOL):
    return math.hypot(p[0] - c[0], p[1] - c[1]) <= r + tol * max(1.0, r)


def oracle_samples(c1, r1, c2, r2, t):
    """Feasible points: dense samples of both boundary circles kept when in the other disc."""
    ang = np.linspace(0.0, 2 * math.pi, N_ARC, endpoint=False)
    pts = []
    for (c, r), (co, ro) in (((c1, r1), (c2, r2)), ((c2, r2), (c1, r1))):
        circ = np.stack([c[0] + r * np.cos(ang), c[1] + r * np.sin(ang)], axis=1)
        ok = np.hypot(circ[:, 0] - co[0], circ[:, 1] - co[1]) <= ro
        pts.append(circ[ok])
    if math.hypot(t[0] - c1[0], t[1] - c1[1]) <= r1 and math.hypot(t[0] - c2[0], t[1] - c2[1]) <= r2:
        pts.append(np.array([t], dtype=float))
    return np.concatenate(pts) if pts else np.zeros((0, 2))


def check_against_oracle(c1, r1, c2, r2, t):
    res = nearest_point_in_disc_intersection(c1, r1, c2, r2, t)
    d = math.hypot(c1[0] - c2[0], c1[1] - c2[1])
    if d > r1 + r2:
        assert res is None
        return None
    assert res is not None, (c1, r1, c2, r2, t)
    scale = max(1.0, *map(abs, (*c1, *c2, *t, r1, r2)))
    assert in_disc(res, c1, r1, TOL * scale)
    assert in_disc(res, c2, r2, TOL * scale)
    dres = math.hypot(res[0] - t[0], res[1] - t[1])
    samples = oracle_samples(c1, r1, c2, r2, t)
    if len(samples):
        dmin = float(np.min(np.hypot(samples[:, 0] - t[0], samples[:, 1] - t[1])))
        assert dres <= dmin + TOL * scale, (res, dres, dmin)
    return res


coord = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
radius = st.floats(0, 10, allow_nan=False, allow_infinity=False)
point = st.tuples(coord, coord)


@settings(max_examples=300, deadline=None)
@given(point, radius, point, radius, point)
def test_random_discs_match_the_sampling_oracle(c1, r1, c2, r2, t):
    check_against_oracle(c1, r1, c2, r2, t)


@settings(max_examples=200, deadline=None)
@given(point, radius, radius, st.floats(0, 2 * math.pi), point,
       st.sampled_from(["external", "internal", "coincident"]))
def test_degenerate_configurations_match_the_oracle(c1, r1, r2, ang, t, kind):
    """Tangent (externally, internally) and coincident-centre discs, built on purpose."""
    d = {"external": r1 + r2, "internal": abs(r1 - r2), "coincident": 0.0}[kind]
    c2 = (c1[0] + d * math.cos(ang), c1[1] + d * math.sin(ang))
    # Rounding may put an externally tangent pair a hair apart: the kernel then
    # must say empty, which check_against_oracle verifies via |c1-c2| > r1+r2.
    check_against_oracle(c1, r1, c2, r2, t)


@settings(max_examples=200, deadline=None)
@given(point, radius, point, radius)
def test_empty_exactly_when_centres_farther_than_radii_sum(c1, r1, c2, r2):
    res = nearest_point_in_disc_intersection(c1, r1, c2, r2, c1)
    assert (res is None) == (math.hypot(c1[0] - c2[0], c1[1] - c2[1]) > r1 + r2)


@settings(max_examples=200, deadline=None)
@given(point, radius, point, radius, point)
def test_target_inside_both_is_returned_unchanged(c1, r1, c2, r2, t):
    inside = (math.hypot(t[0] - c1[0], t[1] - c1[1]) <= r1
              and math.hypot(t[0] - c2[0], t[1] - c2[1]) <= r2)
    res = nearest_point_in_disc_intersection(c1, r1, c2, r2, t)
    if inside:
        assert res.tolist() == [float(t[0]), float(t[1])]


@pytest.mark.parametrize(
    "c1, r1, c2, r2, t, expected",
    [
        ((0, 0), 1, (1, 0), 1, (0.5, 0.1), (0.5, 0.1)),
        ((0, 0), 5, (1, 0), 1, (10, 0), (2.0, 0.0)),
        ((0, 0), 1, (1, 0), 5, (-10, 0), (-1.0, 0.0)),
        ((0, 0), 1, (1, 0), 1, (0.5, 5), (0.5, math.sqrt(3) / 2)),
        ((0, 0), 1, (1, 0), 1, (0.5, -5), (0.5, -math.sqrt(3) / 2)),
        ((0, 0), 1, (1, 0), 1, (-5, 0), (0.0, 0.0)),
        ((0, 0), 1, (3, 0), 2, (0, 9), (1.0, 0.0)),
        ((0, 0), 1, (2, 0), 1, (5, 5), (1.0, 0.0)),
        ((0, 0), 2, (1, 0), 1, (0, 5), (1 - 1 / math.sqrt(26), 5 / math.sqrt(26))),
        ((2, 2), 0, (2, 2), 0, (9, 9), (2.0, 2.0)),
        ((2, 2), 0, (2, 3), 1, (9, 9), (2.0, 2.0)),
        ((1, 1), 3, (1, 1), 2, (1, 11), (1.0, 3.0)),
        ((0, 0), 1, (1, 0), 1, (0.5, 0.0), (0.5, 0.0)),
    ],
    ids=["target-inside", "small-inside-big", "big-around-small", "lens-top-corner",
         "lens-bottom-corner", "lens-left-arc", "tangent-external", "tangent-unit",
         "tangent-internal", "two-points", "point-in-disc", "coincident-centres",
         "target-on-chord"],
)
def test_exact_cases(c1, r1, c2, r2, t, expected):
    res = nearest_point_in_disc_intersection(c1, r1, c2, r2, t)
    assert res is not None
    np.testing.assert_allclose(res, expected, atol=1e-12)


@pytest.mark.parametrize(
    "c1, r1, c2, r2",
    [((0, 0), 1, (3, 0), 1.5), ((0, 0), 0, (1e-9, 0), 0), ((0, 0), 1, (0, 2.0000001), 1)],
    ids=["disjoint", "distinct-points", "barely-apart"],
)
def test_empty_cases(c1, r1, c2, r2):
    assert nearest_point_in_disc_intersection(c1, r1, c2, r2, (0, 0)) is None


def test_lemma7_shape_far_destination_stays_within_parent_range():
    """The song2014 use: reach v*dt around the robot, phi - v*dt around the parent."""
    phi, s = 1.0, 0.05
    robot, parent, dest = (0.9, 0.0), (0.0, 0.0), (5.0, 3.0)
    res = nearest_point_in_disc_intersection(robot, s, parent, phi - s, dest)
    assert math.hypot(*res) <= phi - s + 1e-12
    assert math.hypot(res[0] - 0.9, res[1]) <= s + 1e-12


def test_scalar_core_agrees_with_public_function():
    args = ((0.3, -0.2), 0.7, (0.9, 0.4), 0.5, (4.0, -3.0))
    res = nearest_point_in_disc_intersection(*args)
    core = nearest_xy(*args[0], args[1], *args[2], args[3], *args[4])
    assert res.tolist() == list(core)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(c1=(0, 0, 0)), r"c1=\(0, 0, 0\) must be a point .* got shape \(3,\)"),
        (dict(c2="ab"), r"c2='ab' must be a point"),
        (dict(target=(0, float("nan"))), r"target=\(0, nan\) must have finite coordinates"),
        (dict(r1=-1), r"r1=-1 must be >= 0"),
        (dict(r2=float("inf")), r"r2=inf must be a finite number"),
        (dict(r1=None), r"r1=None must be a finite number"),
    ],
    ids=["c1-3d", "c2-string", "target-nan", "r1-negative", "r2-infinite", "r1-none"],
)
def test_invalid_inputs(kwargs, match):
    args = dict(c1=(0, 0), r1=1.0, c2=(1, 0), r2=1.0, target=(0, 0))
    args.update(kwargs)
    with pytest.raises(UsageError, match=match):
        nearest_point_in_disc_intersection(**args)
