"""The bundled library (swarmproof.models.library).

Each lattice's geometry is checked against an independent bounded oracle
(:func:`swarmproof.strategies.bounded_defects`) just inside and just outside
its valid range interval, and, when the checker is present, decided by it.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from swarmproof.models import library
from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.models.lattice import LatticeGraph
from swarmproof.strategies import bounded_defects, sample_pattern

S2, S3, S5 = math.sqrt(2), math.sqrt(3), math.sqrt(5)

# name: (roles, edges, classification, rotation order, valid range (lo, hi], recommended)
# lo: the longest edge (edges must be strictly shorter than phi); hi: the next
# pattern distance (None: no upper end, a complete finite formation).
TABLE = {
    "square": (1, 4, "periodic", 1, (1.0, S2), 1.2),
    "hexagon": (2, 6, "periodic", 1, (1.0, S3), 1.5),
    "octagon-square": (4, 12, "periodic", 1, (1.0, S2), 1.2),
    "triangle": (1, 6, "periodic", 1, (1.0, S3), 1.5),
    "kagome": (3, 12, "periodic", 1, (1.0, S3), 1.5),
    "honeycomb-rotating": (1, 3, "periodic", 2, (1.0, S3), 1.5),
    "hexagon-ring": (1, 2, "finite", 6, (1.0, S3), 1.5),
    "letter-f": (5, 20, "finite", 1, (S5, None), 2.5),
}


def test_names_are_sorted_and_complete():
    assert library.names() == sorted(TABLE)


@pytest.mark.parametrize("name", sorted(TABLE))
def test_bundled_lattice_loads_with_its_table_entry(name):
    roles, edges, _, _, (lo, hi), rec = TABLE[name]
    g = library.load(name)
    assert isinstance(g, LatticeGraph)
    assert (len(g.roles), len(g.edges), g.range) == (roles, edges, rec)
    assert g.name == name and g.source == f"library:{name}"
    assert lo < rec and (hi is None or rec < hi)  # recommended range strictly inside
    assert all(g.find_inverse(e) is not None for e in g.edges)
    assert math.isclose(g.max_edge_length(), lo, rel_tol=1e-12)


@pytest.mark.parametrize("name", sorted(TABLE))
def test_bundled_files_cite_their_source(name):
    text = library.text(name)
    assert text.startswith("# ")
    if name in ("square", "hexagon", "octagon-square", "letter-f"):
        assert "000_3ad33c5b62f11d5f.txt" in text and "Fig." in text
    else:
        assert "Not in the papers" in text


@pytest.mark.parametrize("name", sorted(TABLE))
def test_oracle_valid_range_interval(name):
    """Just inside both ends: no problem seen; just outside: a problem."""
    *_, (lo, hi), rec = TABLE[name]
    g = library.load(name)
    assert bounded_defects(g, rec) == []
    assert bounded_defects(g, lo * (1 + 1e-6)) == []
    assert bounded_defects(g, lo) != []  # the longest edge is not shorter than phi
    if hi is not None:
        assert bounded_defects(g, hi * (1 - 1e-6)) == []
        assert bounded_defects(g, hi * (1 + 1e-6)) != []
    else:
        assert bounded_defects(g, 100.0) == []


def _xy(points):
    return np.array([[t.x, t.y] for _, t in points])


def _same_sets(a, b, tol=1e-6):
    if len(a) != len(b):
        return False
    return all(np.min(np.hypot(*(b - p).T)) < tol for p in a)


def test_honeycomb_rotating_generates_the_honeycomb():
    rot, _ = sample_pattern(library.load("honeycomb-rotating"), 6.0)
    hexa, _ = sample_pattern(library.load("hexagon"), 6.0)
    inner = lambda pts: [(r, t) for r, t in pts if math.hypot(t.x, t.y) <= 4.0]  # noqa: E731
    assert _same_sets(_xy(inner(rot)), _xy(inner(hexa)))
    assert len(inner(rot)) > 30
    # headings alternate: robots where `hexagon` puts role B face the other way
    by_pos = {(round(t.x, 6) + 0.0, round(t.y, 6) + 0.0): r for r, t in hexa}
    for _, t in inner(rot):
        role = by_pos[(round(t.x, 6) + 0.0, round(t.y, 6) + 0.0)]
        assert math.isclose(abs(t.theta), 0.0 if role == "A" else math.pi, abs_tol=1e-9)


def test_hexagon_ring_is_six_robots_on_a_unit_hexagon():
    pts, clashes = sample_pattern(library.load("hexagon-ring"), 100.0)
    assert clashes == [] and len(pts) == 6
    xy = _xy(pts)
    centre = xy.mean(axis=0)
    assert np.allclose(np.hypot(*(xy - centre).T), 1.0)  # circumradius = side = 1
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    assert sorted(np.round(d[np.triu_indices(6, 1)], 9)) == sorted([1.0] * 6 + [round(S3, 9)] * 6 + [2.0] * 3)


def test_octagon_square_is_the_truncated_square_tiling():
    pts, clashes = sample_pattern(library.load("octagon-square"), 8.0)
    assert clashes == []
    xy = _xy(pts)
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    inner = np.hypot(*xy.T) <= 5.0
    for i in np.nonzero(inner)[0]:
        near = np.nonzero(np.abs(d[i] - 1.0) < 1e-9)[0]
        assert len(near) == 3  # three unit neighbors
        ang = sorted(np.round(np.degrees(np.arctan2(*(xy[near] - xy[i])[:, ::-1].T)) % 360, 6))
        gaps = sorted(np.round(np.diff(ang + [ang[0] + 360]), 6))
        assert gaps == [90.0, 135.0, 135.0]  # a square corner and two octagon corners
        assert round(np.min(d[i][d[i] > 1 + 1e-9]), 9) == round(S2, 9)


def test_letter_f_robots_all_see_each_other():
    g = library.load("letter-f")
    pts, _ = sample_pattern(g, 100.0)
    assert len(pts) == 5
    xy = _xy(pts)
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    assert math.isclose(d.max(), S5) and d.max() < g.range
    assert len(g.edges) == 5 * 4  # complete graph


# --------------------------------------------------------------------------
# load / resolve
# --------------------------------------------------------------------------

def test_unknown_name_lists_the_valid_ones():
    with pytest.raises(UsageError, match=r"lattice='hex' is not a bundled lattice; fix: use one of "
                                         r"\['hexagon', 'hexagon-ring', .*'triangle'\]"):
        library.load("hex")


def test_resolve_prefers_an_existing_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "square").write_text("format: lattice-graph/1\nname: mine\nroles: [A]\nedges: []\n")
    assert library.resolve("square").name == "mine"  # the file wins over the bundled name
    assert library.resolve("hexagon").source == "library:hexagon"
    assert library.resolve(tmp_path / "square").name == "mine"  # os.PathLike


def test_resolve_reports_file_errors_of_existing_files(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("format: lattice-graph/1\nroles: [A]\nedges:\n  - [A, B, 1, 0, 0]\n")
    with pytest.raises(InputFileError, match=r"bad\.yaml:4: field 'edges\[0\]\[1\]'"):
        library.resolve(str(p))


@pytest.mark.parametrize("arg", ["sqaure", "lattices/square.yaml", ""], ids=["typo", "missing-path", "empty"])
def test_resolve_neither_file_nor_name(arg):
    with pytest.raises(InputFileError, match=r"no such file and no bundled lattice of that name(; did you mean "
                                             r"'square'\?)?; fix: give the path of a lattice-graph/1 file or one of the "
                                             r"bundled names \['hexagon'"):
        library.resolve(arg)


def test_resolve_a_directory_is_an_input_error(tmp_path):
    with pytest.raises(InputFileError, match="is a directory"):
        library.resolve(str(tmp_path))


def test_bundled_files_are_package_data():
    from importlib import resources

    folder = resources.files("swarmproof.models") / "library"
    assert sorted(p.name for p in folder.iterdir() if p.name.endswith(".yaml")) == \
        sorted(f"{n}.yaml" for n in TABLE)
    assert os.path.basename(str(folder)) == "library"


# --------------------------------------------------------------------------
# with the checker (another part of the project)
# --------------------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(TABLE))
def test_checker_accepts_every_bundled_lattice_at_its_recommended_range(name):
    lc = pytest.importorskip("swarmproof.checkers.lattice_check")
    _, _, kind, order, (lo, hi), rec = TABLE[name]
    r = lc.check_lattice(library.load(name))
    assert r.valid and r.self_consistent and r.range == rec, r.format_human()
    assert r.classification["kind"] == kind
    assert r.classification["rotation_order"] == order
    assert r.classification["translation_rank"] == {"periodic": 2, "finite": 0}[kind]


@pytest.mark.parametrize("name", sorted(TABLE))
def test_checker_valid_range_interval(name):
    lc = pytest.importorskip("swarmproof.checkers.lattice_check")
    *_, (lo, hi), _ = TABLE[name]
    g = library.load(name)
    assert lc.check_lattice(g, lo * (1 + 1e-6)).valid
    out = lc.check_lattice(g, lo)
    assert not out.valid and "out_of_range_edge" in [d.kind for d in out.defects]
    if hi is not None:
        assert lc.check_lattice(g, hi * (1 - 1e-6)).valid
        beyond = lc.check_lattice(g, hi * (1 + 1e-6))
        assert not beyond.valid and "self_consistency" in [d.kind for d in beyond.defects]
        assert beyond.suggested_edges, beyond.format_human()
        assert all(math.isclose(math.hypot(r[2], r[3]), hi, rel_tol=1e-6) for r in beyond.suggested_edges)
    else:
        assert lc.check_lattice(g, 1e3).valid
