"""Exact decision of 001 Def. 2 (satisfies_lattice) and the fulfillment ratios built on it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from swarmproof.invariants.metrics import fulfillment_ratio, non_fulfillment_ratio
from swarmproof.invariants.satisfaction import satisfies_lattice
from swarmproof.models.lattice import LatticeGraph
from swarmproof.models.library import resolve
from swarmproof.models.se2 import SE2, compose_many

S3 = math.sqrt(3) / 2
HEX_RING = [[0, 0, 0], [0, 1, 0], [S3, 1.5, 0], [2 * S3, 1, 0], [2 * S3, 0, 0], [S3, -0.5, 0]]


def test_hexagon_ring_two_roles_and_q():
    hexa = resolve("hexagon")
    r = satisfies_lattice(range(6), HEX_RING, hexa, 1.5)
    assert r.held
    assert [r.roles[k] for k in range(6)] == ["A", "B", "A", "B", "A", "B"]
    assert fulfillment_ratio(range(6), HEX_RING, hexa, 1.5) == pytest.approx(2 / 3)
    assert non_fulfillment_ratio(range(6), HEX_RING, hexa, 1.5) == pytest.approx(1 / 3)


def test_same_formation_rotated_and_translated_still_satisfies():
    frame = np.array([[3.0, -2.0, 1.1]])
    moved = compose_many(frame, np.array(HEX_RING, dtype=float))
    assert satisfies_lattice(range(6), moved, resolve("hexagon"), 1.5).held
    # a robot whose heading differs from the lattice's breaks Def. 2
    moved[3, 2] += 0.1
    bad = satisfies_lattice(range(6), moved, resolve("hexagon"), 1.5)
    assert bad.violated and 3 in bad.witness["pair"]


def test_backtracking_finds_the_second_candidate():
    # robot 1 can be A or B relative to robot 0; only B lets robot 2 have a role.
    g = LatticeGraph("trap", ["S", "A", "B"], [
        ("S", "A", SE2(1, 0, 0)), ("A", "S", SE2(-1, 0, 0)),
        ("S", "B", SE2(1, 0, 0)), ("B", "S", SE2(-1, 0, 0)),
        ("B", "S", SE2(1, 0, 0)), ("S", "B", SE2(-1, 0, 0))])
    r = satisfies_lattice([0, 1, 2], [[0, 0, 0], [1, 0, 0], [2, 0, 0]], g, 1.2)
    assert r.held and r.roles == {0: "S", 1: "B", 2: "S"}


def test_inconsistent_roles_give_a_witness_pair():
    # every directed pair matches some edge, but no role function exists
    g = LatticeGraph("oneway", ["A", "B"], [("A", "B", SE2(1, 0, 0)), ("B", "B", SE2(-1, 0, 0))])
    r = satisfies_lattice([4, 9], [[0, 0, 0], [1, 0, 0]], g, 1.2)
    assert r.violated and r.witness["reason"] == "no_consistent_role_function"
    assert sorted(r.witness["pair"]) == [4, 9]
    assert "no role function fits" in r.message


def test_non_neighbors_impose_nothing_and_components_are_independent():
    sq = resolve("square")
    # two far-apart pairs with different orientations each satisfy on their own
    poses = [[0, 0, 0], [1, 0, 0], [10, 10, 0.7], [10 + math.cos(0.7), 10 + math.sin(0.7), 0.7]]
    assert satisfies_lattice([0, 1, 2, 3], poses, sq, 1.2).held
    # the square lattice is satisfied by 4 robots of a unit square (001 Fig. 8 right, Q = 0.5)
    four = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    assert fulfillment_ratio(range(4), four, sq, 1.2) == 0.5
    # a line of four: ends have 1 neighbor, middles 2: Q = 6/16
    line = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]
    assert fulfillment_ratio(range(4), line, sq, 1.2) == pytest.approx(6 / 16)


def test_tolerance_is_respected():
    sq = resolve("square")
    near = [[0, 0, 0], [1 + 1e-8, 0, 0]]
    assert satisfies_lattice([0, 1], near, sq, 1.2).held
    assert satisfies_lattice([0, 1], near, sq, 1.2, pos_tol=1e-10).violated


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=1, max_size=12, unique=True),
       st.floats(-math.pi, math.pi), st.floats(-5, 5), st.floats(-5, 5))
def test_any_subset_of_the_square_grid_satisfies(cells, theta, tx, ty):
    grid = np.array([[x, y, 0.0] for x, y in cells])
    poses = compose_many(np.array([[tx, ty, theta]]), grid)
    r = satisfies_lattice(range(len(cells)), poses, resolve("square"), 1.2)
    assert r.held


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=2, max_size=10, unique=True),
       st.data())
def test_a_perturbed_grid_robot_with_a_neighbor_is_caught(cells, data):
    grid = np.array([[x, y, 0.0] for x, y in cells])
    d = np.hypot(*(grid[:, None, :2] - grid[None, :, :2]).transpose(2, 0, 1))
    has_nb = np.flatnonzero(((d > 0) & (d < 1.2)).any(axis=1))
    if len(has_nb) == 0:
        return
    k = int(data.draw(st.sampled_from(has_nb.tolist())))
    grid[k, 0] += 0.05
    assert satisfies_lattice(range(len(cells)), grid, resolve("square"), 1.2).violated
