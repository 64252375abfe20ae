"""The shared neighbor rule: strictly closer than phi, the same with or without the k-d tree."""

from __future__ import annotations

import numpy as np
import pytest
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


def test_union_find_components_equal_scipy_on_random_graphs():
    """components() joins small graphs in plain Python (union-find, a speed-up: scipy's sparse
    matrix cost 1.7 ms a call) and big ones with scipy: both give the same components, sorted,
    ordered by their smallest index -- checked against scipy on random multigraphs with loops."""
    import numpy as np
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from swarmproof.models import sensing

    def scipy_components(n, i, j):
        g = coo_matrix((np.ones(len(i), dtype=np.int8), (i, j)), shape=(n, n))
        _, labels = connected_components(g, directed=False)
        groups: dict = {}
        for idx, lab in enumerate(labels.tolist()):
            groups.setdefault(lab, []).append(idx)
        return sorted(groups.values(), key=lambda c: c[0])

    rng = np.random.default_rng(0)
    for _ in range(2000):
        n = int(rng.integers(1, 60))
        m = int(rng.integers(0, 3 * n))
        i, j = rng.integers(0, n, m), rng.integers(0, n, m)
        assert sensing.components(n, i, j) == scipy_components(n, i, j)
    # past the union-find's edge limit the scipy path answers, the same way
    n, m = 300, sensing._UNION_FIND_MAX_EDGES + 1
    i, j = rng.integers(0, n, m), rng.integers(0, n, m)
    assert sensing.components(n, i, j) == scipy_components(n, i, j)
    with pytest.raises(ValueError, match="outside 0..2"):
        sensing.components(3, [0], [3])
