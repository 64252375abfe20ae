"""Lee & Chong (003) Algorithms 1 and 4 on hand-made configurations, and the exact formula checks."""

import math

import numpy as np
import pytest

from swarmproof.reference_impl.leechong.checks import allocated_ids, id_formula, neighbor_links
from swarmproof.models.errors import UsageError
from swarmproof.reference_impl.leechong.algorithm import agree, allocate_ids, neighbor_id


def _rot(points, ang, shift=(0.0, 0.0)):
    c, s = math.cos(ang), math.sin(ang)
    p = np.asarray(points, dtype=float)
    return p @ np.array([[c, s], [-s, c]]) + np.asarray(shift)


def test_alg1_origin_leader_direction_and_common_coordinates():
    pts = np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 1.0], [1.0, -2.0]])
    a = agree(pts)
    assert a.origin == (1.5, -0.25)                              # Eq. (1): the centroid
    assert a.leader == 1                                         # farthest from p_o
    assert a.u == pytest.approx((2.5 / math.hypot(2.5, 0.25), 0.25 / math.hypot(2.5, 0.25)))
    # Eq. (3): the leader lies on the positive u axis
    assert a.common[1, 0] == pytest.approx(math.hypot(2.5, 0.25)) and abs(a.common[1, 1]) < 1e-12


def test_alg1_is_the_same_in_every_robots_frame():
    """Each robot runs Alg. 1 in its own frame (rotated, shifted, rows permuted): same IDs per robot."""
    rng = np.random.default_rng(3)
    pts = rng.uniform(0, 5, (9, 2))
    base = agree(pts).ids
    for k in range(5):
        perm = rng.permutation(9)
        view = _rot(pts[perm], rng.uniform(-3, 3), rng.uniform(-9, 9, 2))
        ids = agree(view).ids
        assert [ids[list(perm).index(j)] for j in range(9)] == list(base)


def test_alg1_formula_ranks_within_each_half_plane_by_increasing_u():
    # leader at row 0; upper half plane rows 1, 3 (u = 0.5, -0.1), lower rows 2, 4 (u = 0.2, -0.6)
    common = [(1.0, 0.0), (0.5, 0.3), (0.2, -0.4), (-0.1, 0.2), (-0.6, -0.1)]
    assert allocate_ids(common, 0, numbering="formula") == [0, 4, 3, 2, 1]      # 2 x rank / 2 x rank - 1
    assert allocate_ids(common, 0, numbering="formula", order="leader-first") == [0, 2, 1, 4, 3]
    # v = 0 counts as the upper half plane (Alg. 1 line 11: v_i >= 0)
    assert allocate_ids([(1.0, 0.0), (0.3, 0.0), (0.1, -1.0)], 0, numbering="formula") == [0, 2, 1]
    # balanced half planes: the default (Sec. 2.1's prose) gives the same IDs
    assert allocate_ids(common, 0) == [0, 4, 3, 2, 1]


def test_alg1_formula_is_not_a_bijection_when_the_half_planes_are_unbalanced_but_the_prose_is():
    common = [(1.0, 0.0), (0.5, 0.3), (0.2, 0.4), (-0.1, 0.2)]   # three robots above u, none below
    assert sorted(allocate_ids(common, 0, numbering="formula")) == [0, 2, 4, 6]
    assert sorted(allocate_ids(common, 0, numbering="prose")) == [0, 1, 2, 3]
    assert allocate_ids(common, 0) == allocate_ids(common, 0, numbering="prose")     # the default (issue 31)


def test_alg1_tie_of_leader_candidates_is_reported():
    square = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    assert agree(square).tie == (0, 1, 2, 3)
    assert agree(np.vstack((square, [[0.0, 0.0]]))).tie == (0, 1, 2, 3)
    assert agree(np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.01]])).tie == ()


def test_alg1_fixed_leader_for_the_f_team():
    a = agree(np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 1.0]]), leader=2)
    assert a.leader == 2 and a.ids[2] == 0


def test_bad_numbering_and_order_are_usage_errors():
    with pytest.raises(UsageError, match="id_numbering='odd'"):
        allocate_ids([(1.0, 0.0)], 0, numbering="odd")
    with pytest.raises(UsageError, match="id_order='x'"):
        allocate_ids([(1.0, 0.0)], 0, order="x")


def test_alg4_neighbor_ids():
    assert [neighbor_id(i, "uni") for i in range(1, 8)] == [0, 0, 1, 2, 3, 4, 5]
    # Fig. 17b: 12 robots in four lines; the third line's robots find their neighbor in the first
    assert neighbor_id(3, "multi", 4) == 1 and neighbor_id(7, "multi", 4) == 5
    assert neighbor_id(4, "multi", 4) == 0 and neighbor_id(8, "multi", 4) == 4    # LiOrder 0: ID - NoLine
    assert neighbor_id(5, "multi", 4) == 4 and neighbor_id(6, "multi", 4) == 5


def test_exact_id_formula_check():
    # a bijection exactly when the halves balance (a = b) or the lower holds one more (b = a + 1)
    for n in range(2, 40):
        bad = id_formula(n)["non_bijective_splits"]
        assert bad == [[a, n - 1 - a] for a in range(n) if not (a == n - 1 - a or n - 1 - a == a + 1)]
        assert id_formula(n, "prose")["status"] == "held"
    assert allocated_ids(2, 2) == [2, 4, 1, 3]


def test_exact_neighbor_links_check_finds_unallocated_neighbors_under_the_formula():
    assert neighbor_links(12, "uni", None)["status"] == "held"
    assert neighbor_links(12, "uni", None, "prose")["status"] == "held"
    r = neighbor_links(6, "multi", 2)
    assert r["status"] == "violated"
    assert r["counterexample"] == {"n": 6, "split": [0, 5], "id": 3, "n_id": 2,
                                   "why": "N_id=2 is not an allocated ID (allocated: [0, 1, 3, 5, 7, 9])"}
    assert neighbor_links(6, "multi", 2, "prose")["status"] == "held"
