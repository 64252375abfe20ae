"""Tests of the lattice-graph checker (001 Defs. 1 and 4; docs/lattice-checker.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from swarmproof.checkers.lattice_check import DEFECT_KINDS, check_lattice, plot_lattice_check, unroll
from swarmproof.models import library
from swarmproof.models.errors import UsageError
from swarmproof.models.lattice import LatticeGraph
from swarmproof.models.se2 import SE2
from swarmproof.models.verdict import Verdict

S2, S3, S5 = math.sqrt(2), math.sqrt(3), math.sqrt(5)


def G(name, roles, rows, rng=None):
    """A graph from rows ``(from, to, x, y, theta_deg)``."""
    return LatticeGraph(name, roles, [(a, b, SE2(x, y, math.radians(t))) for a, b, x, y, t in rows],
                        range=rng)


def ring_rows(alpha_deg, role="A"):
    a = math.radians(alpha_deg)
    return [(role, role, 1, 0, alpha_deg), (role, role, -math.cos(a), math.sin(a), -alpha_deg)]


SQUARE = G("square", ["A"], [("A", "A", 1, 0, 0), ("A", "A", 0, 1, 0), ("A", "A", -1, 0, 0),
                             ("A", "A", 0, -1, 0)])


def kinds(report):
    return [d.kind for d in report.defects]


def row_close(r1, r2, tol=1e-6):
    return (r1[0] == r2[0] and r1[1] == r2[1]
            and SE2(r1[2], r1[3], math.radians(r1[4])).isclose(SE2(r2[2], r2[3], math.radians(r2[4])),
                                                               tol, tol))


def with_rows(graph, rows):
    return graph.with_edges([(a, b, SE2(x, y, math.radians(t))) for a, b, x, y, t in rows])


def completed(graph):
    """The completed graph exactly as the checker builds it (missing inverses appended in order)."""
    missing = [e for e in graph.edges if graph.find_inverse(e, 1e-7, 1e-7) is None]
    return graph.with_edges([(e.target, e.source, e.transform.inverse()) for e in missing])


def walk_pose(graph, walk):
    t = SE2.identity()
    for i in walk:
        t = t @ graph.edges[i].transform
    return t


def assert_witnesses_replay(graph, report):
    """Every Def. 4 defect's two paths really end at the poses it states, start at the
    start role, end at the roles it names, and the fix edge is T_A^-1 T_B."""
    full = completed(graph)
    for d in report.defects:
        if d.kind not in ("self_consistency", "contradiction") or "paths" not in d.details:
            continue
        pa, pb = d.details["paths"]
        ta, tb = walk_pose(full, pa), walk_pose(full, pb)
        for walk, t, pose, role in ((pa, ta, d.details["poses"][0], d.details["roles"][0]),
                                    (pb, tb, d.details["poses"][1], d.details["roles"][1])):
            assert t.isclose(SE2(pose[0], pose[1], math.radians(pose[2])), 1e-6, 1e-6)
            if walk:
                assert full.edges[walk[0]].source == d.details["start_role"]
                assert full.edges[walk[-1]].target == role
                for e1, e2 in zip(walk, walk[1:]):
                    assert full.edges[e1].target == full.edges[e2].source
            else:
                assert role == d.details["start_role"]
        rel = ta.inverse() @ tb
        assert abs(rel.norm() - d.details["distance"]) < 1e-6
        if d.kind == "contradiction":
            assert rel.norm() < 1e-6
            assert d.details["roles"][0] != d.details["roles"][1] or abs(rel.theta) > 1e-6
        if d.kind == "self_consistency":
            # a genuine Def. 4 violation: the completed graph has no such edge
            assert full.find_edge(d.details["roles"][0], d.details["roles"][1], rel, 1e-6, 1e-6) is None
            fx = d.details["fix_edge"]
            assert row_close(fx, [d.details["roles"][0], d.details["roles"][1], rel.x, rel.y,
                                  math.degrees(rel.theta)])
            assert rel.norm() < report.range


# ----------------------------------------------------------------------
# The bundled library and the valid ranges
# ----------------------------------------------------------------------

EXPECTED = {  # name: (kind, rotation order, rank, lowest range (excl.), highest range (incl.))
    "square": ("periodic", 1, 2, 1.0, S2),
    "hexagon": ("periodic", 1, 2, 1.0, S3),
    "octagon-square": ("periodic", 1, 2, 1.0, S2),
    "triangle": ("periodic", 1, 2, 1.0, S3),
    "kagome": ("periodic", 1, 2, 1.0, S3),
    "honeycomb-rotating": ("periodic", 2, 2, 1.0, S3),
    "hexagon-ring": ("finite", 6, 0, 1.0, S3),
    "letter-f": ("finite", 1, 0, S5, math.inf),
}


def test_every_bundled_lattice_is_in_the_table():
    assert sorted(EXPECTED) == library.names()


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_bundled_lattice_valid_at_its_recommended_range(name):
    g = library.load(name)
    r = check_lattice(g)
    kind, order, rank, _, _ = EXPECTED[name]
    assert r.verdict is Verdict.HELD and r.valid and r.self_consistent is True
    assert r.defects == [] and r.suggested_edges == []
    assert (r.classification["kind"], r.classification["rotation_order"],
            r.classification["translation_rank"]) == (kind, order, rank)
    assert len(r.classification["translation_basis"]) == rank


def _range_cases():
    for name, (_, _, _, lo, hi) in sorted(EXPECTED.items()):
        yield pytest.param(name, lo, False, id=f"{name}-at-lowest")
        yield pytest.param(name, lo + 1e-6, True, id=f"{name}-just-above-lowest")
        yield pytest.param(name, lo - 1e-3, False, id=f"{name}-below-lowest")
        if math.isfinite(hi):
            yield pytest.param(name, hi, True, id=f"{name}-at-highest")
            yield pytest.param(name, hi - 1e-6, True, id=f"{name}-just-below-highest")
            yield pytest.param(name, hi + 1e-6, False, id=f"{name}-just-above-highest")
        else:
            yield pytest.param(name, 1000.0, True, id=f"{name}-huge-range")


@pytest.mark.parametrize("name,phi,valid", list(_range_cases()))
def test_valid_exactly_inside_the_range_interval(name, phi, valid):
    r = check_lattice(library.load(name), phi)
    assert r.valid is valid
    assert r.verdict is (Verdict.HELD if valid else Verdict.VIOLATED)
    if not valid:
        assert set(kinds(r)) <= {"out_of_range_edge", "self_consistency"}
        if phi > EXPECTED[name][3]:     # too large: missing neighbors, each with a fix
            assert kinds(r) and set(kinds(r)) == {"self_consistency"}
            assert r.suggested_edges
            assert check_lattice(with_rows(library.load(name), r.suggested_edges), phi).valid
        else:                           # too small: the edges cannot be sensed
            assert "out_of_range_edge" in kinds(r)


def test_square_with_diagonals_is_valid_up_to_two():
    r = check_lattice(SQUARE, 1.5)
    assert len(r.suggested_edges) == 4
    eight = with_rows(SQUARE, r.suggested_edges)
    assert check_lattice(eight, 1.5).valid and check_lattice(eight, 2.0).valid
    assert not check_lattice(eight, 2.0 + 1e-6).valid


def test_supercell_of_the_square_lattice():
    n = 6
    roles = [f"r{i}_{j}" for i in range(n) for j in range(n)]
    rows = [(f"r{i}_{j}", f"r{(i + dx) % n}_{(j + dy) % n}", dx, dy, 0)
            for i in range(n) for j in range(n) for dx, dy in ((1, 0), (0, 1), (-1, 0), (0, -1))]
    g = G("supercell", roles, rows)
    r = check_lattice(g, 1.2)
    assert r.valid and r.classification["translation_rank"] == 2
    basis = np.array(r.classification["translation_basis"])
    assert abs(abs(np.linalg.det(basis)) - n * n) < 1e-6  # the supercell period
    r = check_lattice(g, 1.5)
    assert len(r.suggested_edges) == 4 * n * n


# ----------------------------------------------------------------------
# Finite formations, strips, rotating edges
# ----------------------------------------------------------------------

def test_octagon_ring_is_a_finite_formation_of_order_eight():
    """001 Fig. 6 left / Fig. 7 left: one role, 'next' turns by 45 degrees."""
    g = G("octagon", ["A"], ring_rows(45))
    r = check_lattice(g, 1.2)
    assert r.valid
    assert r.classification == {"kind": "finite", "rotation_order": 8, "translation_rank": 0,
                                "translation_basis": []}
    pts = unroll(g, radius=10)
    assert len(pts) == 8
    # the next distance on a unit octagon is 2 cos(22.5 deg)
    d2 = 2 * math.cos(math.radians(22.5))
    assert check_lattice(g, d2).valid and not check_lattice(g, d2 + 1e-6).valid


def test_letter_f_complete_graph_missing_one_pair_fails():
    g = library.load("letter-f")
    idx = [e.index for e in g.edges if (e.source, e.target) in (("F1", "F4"), ("F4", "F1"))]
    r = check_lattice(g.without_edges(idx), 2.5)
    assert kinds(r) == ["self_consistency", "self_consistency"]
    assert {tuple(row[:2]) for row in r.suggested_edges} == {("F1", "F4"), ("F4", "F1")}
    assert check_lattice(g.without_edges(idx), 2.2).valid  # F1-F4 is sqrt 5 apart


def test_strip():
    g = G("line", ["A"], [("A", "A", 1, 0, 0), ("A", "A", -1, 0, 0)])
    r = check_lattice(g, 1.5)
    assert r.valid and r.classification["kind"] == "strip"
    assert r.classification["translation_rank"] == 1
    assert check_lattice(g, 2.0).valid and not check_lattice(g, 2.0 + 1e-6).valid


def test_one_role_with_rotating_self_inverse_edges_is_the_honeycomb():
    g = library.load("honeycomb-rotating")
    assert all(g.find_inverse(e) is e for e in g.edges)  # each edge is its own inverse
    h = library.load("hexagon")
    pa = sorted((round(p.x, 6), round(p.y, 6)) for _, p in unroll(g, radius=4.0))
    pb = sorted((round(p.x, 6), round(p.y, 6)) for _, p in unroll(h, radius=4.0))
    assert pa == pb
    headings = {round(math.degrees(p.theta)) % 360 for _, p in unroll(g, radius=4.0)}
    assert headings == {0, 180}


def test_single_role_without_edges_is_a_formation_of_one():
    g = G("alone", ["A"], [])
    r = check_lattice(g, 1.0)
    assert r.valid and r.classification["kind"] == "finite"


# ----------------------------------------------------------------------
# Definition 1 defects
# ----------------------------------------------------------------------

def test_missing_inverse_names_the_edge_and_suggests_its_inverse():
    g = G("sq3", ["A"], [("A", "A", 1, 0, 0), ("A", "A", 0, 1, 0), ("A", "A", -1, 0, 0)])
    r = check_lattice(g, 1.2)
    assert kinds(r) == ["missing_inverse"]
    d = r.defects[0]
    assert d.details["edge"] == 1 and "edges[1]: A -> A (0, 1, 0deg)" in d.message
    assert r.suggested_edges == [["A", "A", 0.0, -1.0, 0.0]]
    assert r.self_consistent is True and r.valid is False
    assert any("completed" in n for n in r.notes)
    assert check_lattice(with_rows(g, r.suggested_edges), 1.2).valid


def test_not_strongly_connected():
    g = G("two", ["A", "B"], [("A", "A", 1, 0, 0), ("A", "A", -1, 0, 0),
                              ("B", "B", 1, 0, 0), ("B", "B", -1, 0, 0)])
    r = check_lattice(g, 1.5)
    assert kinds(r) == ["not_strongly_connected"]
    assert r.defects[0].details["unreachable_from_v0"] == ["B"]
    assert r.self_consistent is True  # on the part reachable from v0, said in a note
    assert any("reachable" in n for n in r.notes)


def test_one_way_edge_is_both_not_strongly_connected_and_missing_inverse():
    g = G("oneway", ["A", "B"], [("A", "B", 1, 0, 0)])
    r = check_lattice(g, 1.5)
    assert kinds(r) == ["not_strongly_connected", "missing_inverse"]
    assert r.suggested_edges == [["B", "A", -1.0, 0.0, 0.0]]
    assert check_lattice(with_rows(g, r.suggested_edges), 1.5).valid


def test_zero_length_and_duplicate_position_edges():
    g = G("z", ["A", "B"], [("A", "B", 0, 0, 0), ("B", "A", 0, 0, 0)])
    r = check_lattice(g, 1.0)
    assert "zero_length_edge" in kinds(r) and "contradiction" in kinds(r)
    g = G("dup", ["A"], [("A", "A", 1, 0, 0), ("A", "A", -1, 0, 0), ("A", "A", 1, 0, 90),
                         ("A", "A", 0, 1, -90)])
    r = check_lattice(g, 1.5)
    assert "duplicate_position" in kinds(r) and "contradiction" in kinds(r)
    d = next(d for d in r.defects if d.kind == "duplicate_position")
    assert d.details["edges"] == [0, 2]


def test_edge_of_length_exactly_range_is_out_of_range():
    r = check_lattice(SQUARE, 1.0)
    assert kinds(r) == ["out_of_range_edge"] * 4
    assert [d.details["edge"] for d in r.defects] == [0, 1, 2, 3]


# ----------------------------------------------------------------------
# Contradictions and dense patterns
# ----------------------------------------------------------------------

def test_two_roles_forced_onto_one_spot():
    g = G("two", ["A", "B"], [("A", "B", 1, 0, 0), ("B", "A", -1, 0, 0), ("A", "A", 1, 0, 0),
                              ("A", "A", -1, 0, 0)])
    r = check_lattice(g, 1.5)
    assert "contradiction" in kinds(r) and not r.valid
    c = next(d for d in r.defects if d.kind == "contradiction")
    assert sorted(c.details["roles"]) == ["A", "B"] and c.details["distance"] == 0.0
    assert any("no finite set" in n for n in r.notes)
    assert_witnesses_replay(g, r)
    # adding every suggested edge cannot help: the contradiction stays
    r2 = check_lattice(with_rows(g, r.suggested_edges), 1.5)
    assert "contradiction" in kinds(r2)


def test_two_headings_forced_onto_one_spot():
    # a square of one role whose 'up' edge turns the robot: going right-up and up-right
    # reach (1, 1) with headings 90 and 0 degrees
    g = G("twist", ["A"], [("A", "A", 1, 0, 0), ("A", "A", -1, 0, 0), ("A", "A", 0, 1, 90),
                           ("A", "A", -1, 0, -90)])
    r = check_lattice(g, 1.2)
    assert "contradiction" in kinds(r) or "dense" in kinds(r)
    assert not r.valid


def test_fig6_right_style_ring_that_does_not_close():
    """001 Fig. 6/7 right: 'next' turns so that the sixth robot lands near the first."""
    g = G("fig6-right", ["A"], ring_rows(67.5))
    r = check_lattice(g, 1.2)
    assert not r.valid and set(kinds(r)) == {"self_consistency"}
    assert_witnesses_replay(g, r)
    # the sixth robot (five 'next' steps) is the one too close to the start robot
    assert any(d.details["paths"] == [[], [0] * 5] or d.details["paths"] == [[], [1] * 5]
               for d in r.defects)
    fixed = with_rows(g, r.suggested_edges)
    assert check_lattice(fixed, 1.2).valid


GOLDEN_DEG = 360 * (1 - 2 / (1 + S5))


@pytest.mark.parametrize("rows", [
    pytest.param(ring_rows(GOLDEN_DEG), id="irrational-rotation"),
    pytest.param([("A", "A", 1, 0, 0), ("A", "A", -1, 0, 0), ("A", "A", S2, 0, 0),
                  ("A", "A", -S2, 0, 0), ("A", "A", 0, 1, 0), ("A", "A", 0, -1, 0)],
                 id="incommensurate-translations"),
    pytest.param(ring_rows(72) + [("A", "A", 0, 1.2, 0), ("A", "A", 0, -1.2, 0)],
                 id="five-fold-rotation-with-translation"),
])
def test_dense_patterns(rows):
    g = G("dense", ["A"], rows)
    r = check_lattice(g, 1.5)
    assert "dense" in kinds(r) and r.classification["kind"] == "dense"
    assert r.verdict is Verdict.VIOLATED and r.self_consistent is False
    assert any("no finite set" in n for n in r.notes)


def test_tolerance_decides_whether_nearly_equal_translations_are_equal():
    """A file that writes 2.0000005 for 2: incommensurate with 1 at the default tolerance
    (2e-7 here), one translation at pos_tol=1e-5."""
    rows = [("A", "A", 1, 0, 0), ("A", "A", -1, 0, 0), ("A", "A", 2.0000005, 0, 0),
            ("A", "A", -2.0000005, 0, 0)]
    g = G("line-rounded", ["A"], rows)
    assert kinds(check_lattice(g, 2.5)) == ["dense"]
    r = check_lattice(g, 2.5, pos_tol=1e-5)
    assert r.valid and r.classification["kind"] == "strip"


# ----------------------------------------------------------------------
# Deleting a needed edge fails and names it; budgets end inconclusive
# ----------------------------------------------------------------------

def _deletion_cases():
    for name in sorted(EXPECTED):
        for e in library.load(name).edges:
            yield pytest.param(name, e.index, id=f"{name}-edges[{e.index}]")


@pytest.mark.parametrize("name,index", list(_deletion_cases()))
def test_deleting_any_edge_fails_naming_it(name, index):
    g = library.load(name)
    gone = g.edges[index]
    r = check_lattice(g.without_edges([index]))
    if g.find_inverse(gone) is gone and r.valid:
        # A self-inverse edge (honeycomb-rotating): without it the walks generate a
        # different pattern (a zigzag strip), which is itself self-consistent; the edge
        # was not needed by *that* pattern.  Check that the pattern really changed.
        assert r.classification["translation_rank"] < EXPECTED[name][2]
        return
    assert not r.valid and r.verdict is Verdict.VIOLATED
    row = gone.as_row("deg")
    assert any(row_close(s, row) for s in r.suggested_edges), (row, r.suggested_edges)
    inv = g.find_inverse(gone)
    if inv is not gone:   # its inverse edge is now the one without an inverse, by name
        h = g.without_edges([index])
        named = [d for d in r.defects if d.kind == "missing_inverse"
                 and row_close(d.details["fix_edge"], row)]
        assert len(named) == 1
        assert h.edges[named[0].details["edge"]].transform.isclose(inv.transform)
        assert f"edges[{named[0].details['edge']}]" in named[0].message
    assert_witnesses_replay(g.without_edges([index]), r)
    assert check_lattice(with_rows(g.without_edges([index]), r.suggested_edges)).valid


def test_budget_spent_is_inconclusive_never_a_pass():
    r = check_lattice(SQUARE, 1.2, budget=5)
    assert r.verdict is Verdict.INCONCLUSIVE and r.valid is False and r.self_consistent is None
    assert "budget" in r.inconclusive_reason
    assert r.verdict.exit_code == 3


def test_rotation_order_above_the_cap_is_inconclusive():
    r = check_lattice(G("octagon", ["A"], ring_rows(45)), 1.2, max_rotation_order=4)
    assert r.verdict is Verdict.INCONCLUSIVE and "max_rotation_order" in r.inconclusive_reason


def test_a_defect_found_wins_over_inconclusive():
    g = G("sq3", ["A"], [("A", "A", 1, 0, 0), ("A", "A", 0, 1, 0), ("A", "A", -1, 0, 0)])
    r = check_lattice(g, 1.2, budget=5)
    assert r.verdict is Verdict.VIOLATED and r.self_consistent is None
    assert any("undecided" in n for n in r.notes)


# ----------------------------------------------------------------------
# Property tests with the public strategies (an independent oracle)
# ----------------------------------------------------------------------

from swarmproof.strategies import finite_lattices, periodic_lattices, sample_pattern  # noqa: E402

_PROP = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@_PROP
@given(st.one_of(periodic_lattices(), finite_lattices()), st.data())
def test_generated_lattices_are_valid_and_each_deletion_fails(g, data):
    r = check_lattice(g)
    assert r.valid, r.format_human()
    if r.classification["kind"] == "periodic":
        assert r.classification["rotation_order"] in (1, 2, 3, 4, 6)
    if not g.edges:
        return
    i = data.draw(st.integers(0, len(g.edges) - 1), label="deleted edge")
    gone = g.edges[i].as_row("deg")
    h = g.without_edges([i])
    r2 = check_lattice(h)
    if g.find_inverse(g.edges[i]) is g.edges[i] and r2.valid:  # pragma: no cover - see above
        return
    assert not r2.valid
    assert any(row_close(s, gone) for s in r2.suggested_edges)
    assert_witnesses_replay(h, r2)
    assert check_lattice(with_rows(h, r2.suggested_edges)).valid


@_PROP
@given(periodic_lattices())
def test_unroll_matches_an_independent_walk_sample(g):
    radius = 2.0 * g.max_edge_length()
    ours = unroll(g, radius=radius)
    theirs, clashes = sample_pattern(g, radius + 6 * g.max_edge_length() + 2 * g.range)
    assert clashes == []
    a = sorted((r, round(p.x, 5), round(p.y, 5)) for r, p in ours)
    b = sorted((r, round(p.x, 5), round(p.y, 5)) for r, p in theirs if p.norm() <= radius - 1e-6)
    a = [x for x in a if math.hypot(x[1], x[2]) <= radius - 1e-5]
    b = [x for x in b if math.hypot(x[1], x[2]) <= radius - 1e-5]
    assert a == b


@_PROP
@given(periodic_lattices(), st.floats(1.05, 2.5))
def test_a_larger_range_never_drops_a_needed_edge(g, factor):
    """Every missing edge at phi is still missing at a larger phi (monotone in phi)."""
    phi = g.range
    r1 = check_lattice(g, phi * factor)
    r2 = check_lattice(g, phi * factor * 1.1)
    for row in r1.suggested_edges:
        assert any(row_close(row, s) for s in r2.suggested_edges)


# ----------------------------------------------------------------------
# Report, JSON, human text, errors, plot
# ----------------------------------------------------------------------

def test_json_has_the_design_fields():
    doc = check_lattice(library.load("square"), 1.5).to_json()
    for k in ("file", "range", "valid", "self_consistent", "classification", "defects",
              "suggested_edges", "verdict"):
        assert k in doc
    assert doc["file"] == "library:square" and doc["range"] == 1.5 and doc["valid"] is False
    assert set(doc["classification"]) >= {"kind", "rotation_order", "translation_rank"}
    assert all({"kind", "message"} <= set(d) for d in doc["defects"])
    assert all(d["kind"] in DEFECT_KINDS for d in doc["defects"])
    assert doc["verdict"] == "violated" and len(doc["suggested_edges"]) == 4
    import json
    json.dumps(doc, allow_nan=False)


def test_exact_human_output_for_a_missing_inverse():
    g = G("sq3", ["A"], [("A", "A", 1, 0, 0), ("A", "A", 0, 1, 0), ("A", "A", -1, 0, 0)])
    assert check_lattice(g, 1.2).format_human().splitlines() == [
        "sq3: 1 defect for range 1.2 (periodic pattern, rotation order 1, translation rank 2)",
        "- missing_inverse: edges[1]: A -> A (0, 1, 0deg) has no inverse edge A -> A "
        "(0, -1, 0deg) (001 Def. 1)",
        "  fix: add the edge row  - [A, A, 0, -1, 0]",
        "note: self-consistency was decided on the graph completed with its 1 missing inverse "
        "edge(s) (indices >= 3 in paths are those added inverses)",
        "verdict: violated",
    ]


def test_human_output_of_a_valid_lattice():
    assert check_lattice(library.load("hexagon-ring")).format_human().splitlines() == [
        "hexagon-ring (library:hexagon-ring): valid and self-consistent for range 1.5 "
        "(finite pattern, rotation order 6, translation rank 0)",
        "verdict: held",
    ]


def test_human_output_is_capped():
    n = 6
    roles = [f"r{i}_{j}" for i in range(n) for j in range(n)]
    rows = [(f"r{i}_{j}", f"r{(i + dx) % n}_{(j + dy) % n}", dx, dy, 0)
            for i in range(n) for j in range(n) for dx, dy in ((1, 0), (0, 1), (-1, 0), (0, -1))]
    text = check_lattice(G("sc", roles, rows), 1.5).format_human()
    assert "... and 134 more self_consistency defects (all are in --json)" in text
    assert len(text.splitlines()) < 40


@pytest.mark.parametrize("kwargs,match", [
    (dict(range=None), r"range is not given .*fix: pass --range PHI or set `range:` in the file"),
    (dict(range=0.0), r"range=0.0 must be > 0"),
    (dict(range=float("nan")), r"range=nan must be a finite number"),
    (dict(range=1.2, pos_tol=-1.0), r"pos_tol=-1.0 must be > 0"),
    (dict(range=1.2, max_rotation_order=0), r"max_rotation_order=0"),
    (dict(range=1.2, budget=0), r"budget=0"),
], ids=["no-range", "zero-range", "nan-range", "negative-tol", "zero-rotation-cap", "zero-budget"])
def test_bad_arguments(kwargs, match):
    with pytest.raises(UsageError, match=match):
        check_lattice(SQUARE, **kwargs)


def test_unroll_square_and_start_role():
    pts = unroll(SQUARE, radius=S2)
    assert len(pts) == 9 and pts[0] == ("A", SE2.identity())
    h = library.load("hexagon")
    pts = unroll(h, start_role="B", radius=1.0)
    assert pts[0][0] == "B" and sorted(r for r, _ in pts) == ["A", "A", "A", "B"]
    with pytest.raises(UsageError, match="role='Z'"):
        unroll(h, start_role="Z")


def test_unroll_of_a_dense_pattern_is_bounded():
    pts = unroll(G("dense", ["A"], ring_rows(GOLDEN_DEG)), radius=3.0, max_points=500)
    assert 0 < len(pts) <= 500


def test_plot_is_written_and_deterministic(tmp_path):
    g = G("fig6-right", ["A"], ring_rows(67.5))
    r = check_lattice(g, 1.2)
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    plot_lattice_check(g, r, a)
    plot_lattice_check(g, r, b)
    data = a.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data == b.read_bytes()
    g2 = G("two", ["A", "B"], [("A", "B", 1, 0, 0), ("B", "A", -1, 0, 0), ("A", "A", 1, 0, 0),
                               ("A", "A", -1, 0, 0)])
    plot_lattice_check(g2, check_lattice(g2, 0.8), tmp_path / "c.png")
    assert (tmp_path / "c.png").stat().st_size > 1000


_STEPS = [(1, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 90), (1, 0, 180), (0, 1, 60), (1, 0, 60),
          (0.5, 0.5, 45), (2, 0, 0), (1, 0, 120)]


@st.composite
def small_graphs(draw):
    """Arbitrary small graphs with inverse edges: valid, inconsistent, contradictory or dense."""
    n = draw(st.integers(1, 3))
    roles = ["A", "B", "C"][:n]
    rows = []
    for _ in range(draw(st.integers(1, 4))):
        a, b = draw(st.sampled_from(roles)), draw(st.sampled_from(roles))
        x, y, t = draw(st.sampled_from(_STEPS))
        e = SE2(x, y, math.radians(t))
        i = e.inverse()
        rows += [(a, b, e.x, e.y, t), (b, a, i.x, i.y, math.degrees(i.theta))]
    return G("small", roles, rows)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(small_graphs(), st.sampled_from([0.83, 1.37, 2.13]))
def test_checker_agrees_with_the_bounded_oracle_and_its_fixes_work(g, phi):
    r = check_lattice(g, phi)
    assert r.verdict in (Verdict.HELD, Verdict.VIOLATED, Verdict.INCONCLUSIVE)
    assert_witnesses_replay(g, r)
    seen = first_visible_problem(g, phi)
    if seen:
        assert r.verdict is not Verdict.HELD, seen
    if r.verdict is Verdict.HELD:
        assert r.valid and not r.suggested_edges
    only_missing = r.defects and all(d.kind in ("self_consistency", "missing_inverse")
                                     and "fix_edge" in d.details for d in r.defects)
    if only_missing:
        r2 = check_lattice(with_rows(g, r.suggested_edges), phi)
        assert r2.verdict is not Verdict.VIOLATED or r2.defects == [], r2.format_human()


def first_visible_problem(g, phi, check_radius=2.5, max_points=3000):
    """An independent, bounded oracle: the first Def. 1/4 problem seen in a walk sample
    (swarmproof.strategies.sample_pattern), or None.  Anything it finds is genuine."""
    for e in g.edges:
        if e.transform.norm() >= phi:
            return f"{e.describe()} out of range"
    pts, clashes = sample_pattern(g, check_radius + phi + 3.0, max_points=max_points)
    if clashes:
        return f"clash {clashes[0]}"
    xy = np.array([[p.x, p.y] for _, p in pts])
    for a, (ra, ta) in enumerate(pts):
        if ta.norm() > check_radius:
            continue
        d = np.hypot(xy[:, 0] - ta.x, xy[:, 1] - ta.y)
        for b in np.nonzero((d < phi - 1e-6) & (d > 1e-6))[0]:
            rb, tb = pts[b]
            if g.find_edge(ra, rb, ta.inverse() @ tb, 1e-6, 1e-6) is None:
                return f"{ra}@{ta} sees {rb}@{tb} without an edge"
    return None


# -- issue 13, item 1: the point budget bounds memory before anything is allocated --------

ROUNDED_RING_VALUES = ("0.866", "0.8660", "0.86603", "0.866025", "0.8661", "0.8662", "0.8665")

#: One child process checks every rounded ring under the address-space cap, one `check-lattice
#: --json` after another, and prints ``[{code, out, err}, ...]``: seven Python start-ups (imports)
#: were most of the seven subprocesses' 8 s of CPU.  Each check runs in a process that already ran
#: the ones before it, under the same cap: no more memory than a fresh one has.
_RING_CHILD = """
import contextlib, io, json, sys, traceback
from swarmproof.cli import main
runs = []
for path in sys.argv[1:]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(["check-lattice", path, "--json"])
        except BaseException:          # a MemoryError (or anything) that escaped main: its traceback
            code = None
            traceback.print_exc(file=err)
    runs.append({"code": code, "out": out.getvalue(), "err": err.getvalue()})
print(json.dumps(runs))
"""


@pytest.fixture(scope="module")
def rounded_ring_runs(tmp_path_factory):
    """``{value: (exit code, stdout, stderr)}`` of ``check-lattice --json`` on hexagon-ring with
    sqrt(3)/2 rounded to each of :data:`ROUNDED_RING_VALUES`, under a 3 GB address-space cap."""
    import json
    import resource
    import subprocess
    import sys

    text = library.text("hexagon-ring")
    assert "0.8660254037844386" in text
    folder = tmp_path_factory.mktemp("rounded-ring")
    paths = []
    for value in ROUNDED_RING_VALUES:
        f = folder / f"ring-rounded-{value}.yaml"
        f.write_text(text.replace("0.8660254037844386", value), encoding="utf-8")
        paths.append(str(f))

    def cap():
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))

    proc = subprocess.run([sys.executable, "-c", _RING_CHILD, *paths], capture_output=True, text=True,
                          timeout=300, preexec_fn=cap)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr[-2000:]
    runs = json.loads(proc.stdout)
    return {value: (r["code"], r["out"], r["err"]) for value, r in zip(ROUNDED_RING_VALUES, runs)}


@pytest.mark.xdist_group("rounded-ring")
@pytest.mark.parametrize("value", ROUNDED_RING_VALUES, ids=lambda v: f"sqrt3/2-as-{v}")
def test_rounded_hexagon_ring_is_decided_within_bounded_memory(rounded_ring_runs, value):
    """hexagon-ring with sqrt(3)/2 rounded: its translations become tiny, the pattern window
    would hold billions of points.  The budget is counted before the window is allocated,
    so the check ends (here: missing inverses, and the self-consistency defect of a pattern
    that repeats too densely) under a 3 GB address-space cap instead of a MemoryError."""
    import json

    code, out, err = rounded_ring_runs[value]
    assert "Traceback" not in err and "MemoryError" not in err, err[-2000:]
    doc = json.loads(out)
    assert code == 1
    assert doc["valid"] is False
    kinds = [d["kind"] for d in doc["defects"]]
    assert kinds.count("missing_inverse") == 2 and "self_consistency" in kinds


# -- issue 13, item 9: the plot shows a missing inverse; a dense pattern is not a solid disc --

def _pixels(path):
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB")).reshape(-1, 3).astype(int)


def test_plot_highlights_an_edge_without_inverse(tmp_path):
    g = G("square-missing-inverse", ["A"], [("A", "A", 1, 0, 0), ("A", "A", 0, 1, 0), ("A", "A", -1, 0, 0)])
    r = check_lattice(g, 1.2)
    assert "missing_inverse" in kinds(r)
    plot_lattice_check(g, r, tmp_path / "bad.png")
    good = G("square", ["A"], [("A", "A", 1, 0, 0), ("A", "A", 0, 1, 0), ("A", "A", -1, 0, 0),
                               ("A", "A", 0, -1, 0)])
    plot_lattice_check(good, check_lattice(good, 1.2), tmp_path / "good.png")
    magenta = lambda px: int(((px[:, 0] > 200) & (px[:, 1] < 80) & (px[:, 2] > 200)).sum())
    assert magenta(_pixels(tmp_path / "bad.png")) > 300
    assert magenta(_pixels(tmp_path / "good.png")) == 0


def test_plot_of_a_dense_pattern_is_not_a_filled_disc(tmp_path):
    g = G("dense", ["A"], ring_rows(GOLDEN_DEG))
    r = check_lattice(g, 1.5)
    assert r.classification["kind"] == "dense"
    plot_lattice_check(g, r, tmp_path / "dense.png")
    px = _pixels(tmp_path / "dense.png")
    role_blue = int(((abs(px[:, 0] - 31) < 40) & (abs(px[:, 1] - 119) < 40) & (px[:, 2] > 150)).sum())
    assert role_blue < 0.02 * len(px), f"{role_blue} of {len(px)} pixels are pattern points"
    assert int(((px[:, 0] > 200) & (px[:, 1] < 60) & (px[:, 2] < 60)).sum()) > 50  # the red note
