"""The public Hypothesis strategies (swarmproof.strategies).

First against the strategies' own bounded oracle (independent of the
checker), then, when the checker is present, as the checker's oracle:
generated lattices are valid, and deleting an edge (with its inverse) that
the pattern still needs makes the check fail naming that edge.
"""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmproof.models import library
from swarmproof.models.se2 import SE2
from swarmproof.strategies import (MUTATION_KINDS, bounded_defects, finite_lattices,
                                   lattice_graph_documents, mutated_lattice_documents,
                                   periodic_lattices, sample_pattern)

lattices = st.one_of(periodic_lattices(), finite_lattices())


def _pair_distances(g, radius):
    pts, clashes = sample_pattern(g, radius)
    assert clashes == []
    xy = np.array([[t.x, t.y] for _, t in pts])
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    return pts, d[np.triu_indices(len(pts), 1)]


@settings(max_examples=40)
@given(lattices)
def test_generated_graphs_have_exactly_the_pairs_closer_than_range(g):
    phi = g.range
    assert g.edges, "a generated graph has at least one edge"
    assert nx.is_strongly_connected(g.graph)
    assert all(g.find_inverse(e) is not None for e in g.edges)
    assert all(0 < e.transform.norm() < phi for e in g.edges)
    # every pair closer than phi in the sampled pattern is an edge (001 Def. 4) ...
    assert bounded_defects(g) == []
    # ... and phi is well inside a gap: the next pair distance is missing from the graph
    _, d = _pair_distances(g, 3 * phi + 2 * g.max_edge_length() + 1)
    nxt = d[d >= phi]
    assert d[d < phi].max() < phi * (1 - 1e-6)
    if nxt.size:
        assert nxt.min() > phi * (1 + 1e-6)
        assert bounded_defects(g, float(nxt.min()) * (1 + 1e-9)) != []


@settings(max_examples=30)
@given(periodic_lattices(headings=False))
def test_periodic_lattices_without_headings_translate_only(g):
    assert all(e.transform.theta == 0.0 for e in g.edges)
    assert g.source == "strategy:periodic_lattices" and g.roles[0] == "A"


@settings(max_examples=30)
@given(finite_lattices(min_points=3, max_points=5))
def test_finite_lattices_respect_sizes_and_are_finite(g):
    assert 3 <= len(g.roles) <= 5
    pts, clashes = sample_pattern(g, 100.0)
    assert clashes == [] and len(pts) == len(g.roles)  # one robot per role: a finite formation


def test_strategies_are_deterministic_given_a_seed():
    def run():
        seen = []

        @settings(max_examples=15, derandomize=True, database=None)
        @given(lattices)
        def collect(g):
            seen.append(g)

        collect()
        return seen

    first = run()
    assert len(first) == 15 and first == run()


@pytest.mark.parametrize("kind", MUTATION_KINDS)
def test_every_mutation_kind_is_rejected_by_the_loader(kind):
    import json

    from swarmproof.models.errors import InputFileError
    from swarmproof.models.lattice_io import loads_lattice

    @settings(max_examples=8)
    @given(mutated_lattice_documents(with_kind=True, kinds=[kind]))
    def check(dk):
        doc, got = dk
        assert got == kind
        with pytest.raises(InputFileError):
            loads_lattice(json.dumps(doc), "json")

    check()


def test_unknown_mutation_kind_is_refused():
    @settings(max_examples=1)
    @given(mutated_lattice_documents(kinds=["typo"]))
    def draw_one(doc):
        pass

    with pytest.raises(ValueError, match=r"kinds=\['typo'\]"):
        draw_one()


@settings(max_examples=50)
@given(lattice_graph_documents())
def test_documents_are_plain_json_data(doc):
    import json

    assert json.loads(json.dumps(doc, allow_nan=False)) == doc
    assert doc["format"] == "lattice-graph/1" and doc["roles"]


def test_bounded_oracle_sees_defects_of_known_graphs():
    sq = library.load("square")
    assert bounded_defects(sq) == []
    assert any("no edge A -> A (1, 1, 0deg)" in p for p in bounded_defects(sq, 1.5))
    assert bounded_defects(sq, 1.0)[0].startswith("edges[0]: A -> A (1, 0, 0deg) has length 1 >= range 1")
    half = sq.without_edges([0])  # (1, 0) gone: the pattern still has that neighbor
    assert any("no edge A -> A (1, 0, 0deg)" in p for p in bounded_defects(half))


# --------------------------------------------------------------------------
# as the checker's oracle
# --------------------------------------------------------------------------

def _row_is(row, e) -> bool:
    return (row is not None and row[0] == e.source and row[1] == e.target
            and SE2(row[2], row[3], math.radians(row[4])).isclose(e.transform, 1e-6, 1e-6))


def _count_near(g, radius):
    pts, _ = sample_pattern(g, radius)
    return sum(1 for _, t in pts if math.hypot(t.x, t.y) <= radius / 2)


@settings(max_examples=60)
@given(lattices)
def test_checker_accepts_generated_lattices(g):
    lc = pytest.importorskip("swarmproof.checkers.lattice_check")
    r = lc.check_lattice(g)
    assert r.valid and r.self_consistent, r.format_human()
    assert r.defects == [] and r.suggested_edges == []
    kind = "finite" if g.source == "strategy:finite_lattices" else "periodic"
    assert r.classification["kind"] == kind, r.format_human()


@settings(max_examples=60)
@given(lattices, st.data())
def test_checker_names_a_deleted_edge(g, data):
    """Delete one edge and its inverse.  Three cases, told apart without the checker:
    the roles fall apart (not strongly connected); the rest still generates the
    same pattern (then the deleted pair is still closer than phi: a Def. 4 defect
    whose fix is that edge); or it generates a smaller pattern (a strip or a
    sub-lattice, which may well be self-consistent: nothing to assert)."""
    lc = pytest.importorskip("swarmproof.checkers.lattice_check")
    e = g.edges[data.draw(st.integers(0, len(g.edges) - 1), label="edge")]
    inv = g.find_inverse(e)
    h = g.without_edges({e.index, inv.index})
    r = lc.check_lattice(h)
    if not nx.is_strongly_connected(h.graph):
        assert not r.valid
        assert "not_strongly_connected" in [d.kind for d in r.defects], r.format_human()
        return
    radius = 4 * g.range + 2
    if _count_near(h, radius) == _count_near(g, radius):
        assert not r.valid
        named = [d for d in r.defects if d.kind == "self_consistency"
                 and (_row_is(d.details.get("fix_edge"), e) or _row_is(d.details.get("fix_edge"), inv))]
        assert named, f"deleted {e.describe()}; report:\n{r.format_human()}"
        assert any(_row_is(row, e) for row in r.suggested_edges)
        assert any(_row_is(row, inv) for row in r.suggested_edges)


OBLIQUE_TWO_DIRECTIONS = """\
format: lattice-graph/1
name: periodic-1
range: 1.3660254037844388
angle_unit: rad
roles: [A]
edges:
- [A, A, -0.1756712969287757, -0.9844488790360632, 0.0]
- [A, A, 0.7647220895079571, -0.6443602453741106, 0.0]
- [A, A, 0.1756712969287757, 0.9844488790360632, 0.0]
- [A, A, -0.7647220895079571, 0.6443602453741106, 0.0]
"""


def test_checker_decides_a_triangular_lattice_missing_one_direction():
    """Found by test_checker_names_a_deleted_edge: a triangular lattice (unit
    vectors 60 degrees apart) with the third direction deleted.  The pattern is
    unchanged, so the pair at v1 - v2 (length 1 < phi) needs an edge."""
    lc = pytest.importorskip("swarmproof.checkers.lattice_check")
    from swarmproof.models.lattice_io import loads_lattice

    g = loads_lattice(OBLIQUE_TWO_DIRECTIONS, "yaml", "oblique.yaml")
    assert len(bounded_defects(g)) > 0  # the independent oracle sees the missing pair
    r = lc.check_lattice(g)
    assert r.verdict.value == "violated", r.format_human()
    assert r.classification["kind"] == "periodic"
    e0, e1 = g.edges[0].transform, g.edges[1].transform
    want = {(round(e0.x - e1.x, 6), round(e0.y - e1.y, 6)), (round(e1.x - e0.x, 6), round(e1.y - e0.y, 6))}
    assert {(round(row[2], 6), round(row[3], 6)) for row in r.suggested_edges} == want
