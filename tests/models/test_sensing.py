"""The shared neighbor rule: strictly closer than phi, the same with or without the k-d tree."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings, strategies as st

import swarmproof.models.sensing as sensing


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 60), st.integers(0, 2**31), st.floats(0.2, 2.0), st.booleans())
def test_brute_force_and_tree_agree_exactly(n, seed, phi, grid):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(0, 3, (n, 2))
    if grid:  # exact distances on a grid hit the strict boundary
        xy = np.round(xy * 2) / 2
    brute = sensing.neighbor_pairs(xy, phi) if n <= sensing._BRUTE_MAX else None
    old = sensing._BRUTE_MAX
    try:
        sensing._BRUTE_MAX = 0
        tree = sensing.neighbor_pairs(xy, phi)
        sensing._BRUTE_MAX = 10**9
        allpairs = sensing.neighbor_pairs(xy, phi)
    finally:
        sensing._BRUTE_MAX = old
    for a, b in zip(tree, allpairs):
        assert np.array_equal(a, b)
    if brute is not None:
        assert all(np.array_equal(a, b) for a, b in zip(brute, tree))
    i, j, d = tree
    assert (i < j).all() and (d < phi).all()


def test_strict_range():
    i, j, d = sensing.neighbor_pairs(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.999]]), 1.0)
    assert list(zip(i.tolist(), j.tolist())) == [(0, 2)]
