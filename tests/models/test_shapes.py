"""004 shapes (issue 15): text and PNG shape files, scaling to n connected goal cells (Sec. V-A),
bundled letters N and U (Figs. 1, 9), arenas and random starts, and the centralized
distance-optimal assignment (Sec. V, Fig. 10) against brute force and z3."""

from __future__ import annotations

import itertools
import json
import re

import numpy as np
import pytest

from swarmproof.checkers.assignment_check import (MAX_Z3_ROBOTS, Z3Inconclusive, check_optimal_assignment,
                                                  z3_optimal_assignment)
from swarmproof.models import shapes
from swarmproof.models.assignment import assignment_cost, manhattan_matrix, optimal_assignment
from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.models.shapes import (DARK_THRESHOLD, MAX_SIDE, arena_cells, bundled_shape_names, centered_arena,
                                      components, connected, load_shape_file, random_shape, random_start_cells,
                                      scale_details, scale_to, shape_for)
from swarmproof.models.targets import GoalSet, resolve_target, target_from_description


def _png(path, rows, mode="L", alpha=None):
    """A PNG from a list of strings: '#' black, '.' white (alpha: 0 where alpha[r][c] == '.')."""
    from PIL import Image

    h, w = len(rows), len(rows[0])
    if mode == "L":
        a = np.array([[0 if ch == "#" else 255 for ch in r] for r in rows], dtype=np.uint8)
        Image.fromarray(a, "L").save(path)
    else:
        rgba = np.zeros((h, w, 4), dtype=np.uint8)
        for r, line in enumerate(rows):
            for c, ch in enumerate(line):
                rgba[r, c] = (0, 0, 0, 255) if ch == "#" else (255, 255, 255, 255)
                if alpha is not None and alpha[r][c] == ".":
                    rgba[r, c, 3] = 0
        Image.fromarray(rgba, "RGBA").save(path)
    return str(path)


def _grid(cells):
    cells = sorted(cells)
    xs = [c[0] for c in cells]
    ys = [c[1] for c in cells]
    return ["".join("#" if (x, y) in set(cells) else "." for x in range(min(xs), max(xs) + 1))
            for y in range(max(ys), min(ys) - 1, -1)]


# ----------------------------------------------------------------------------
# connectivity
# ----------------------------------------------------------------------------

def test_connected_means_sharing_an_edge_not_a_corner():
    assert connected({(0, 0), (1, 0), (1, 1)})
    assert not connected({(0, 0), (1, 1)})               # diagonal contact only
    assert not connected(set())
    comps = components({(0, 0), (0, 1), (5, 5), (9, 0), (9, 1), (9, 2)})
    assert [len(c) for c in comps] == [3, 2, 1] and min(comps[1]) == (0, 0)
    # a very sparse set takes the breadth-first path, with the same answer
    far = {(0, 0), (0, 1), (10 ** 7, 0)}
    assert [sorted(c) for c in components(far)] == [[(0, 0), (0, 1)], [(10 ** 7, 0)]]


# ----------------------------------------------------------------------------
# text and PNG files
# ----------------------------------------------------------------------------

def test_a_text_bitmap_reads_top_row_as_largest_y(tmp_path):
    p = tmp_path / "tee.txt"
    p.write_text("###\r\n.#.\n.#\n\n\n")                 # CRLF, a short row, trailing blank lines
    g = load_shape_file(p)
    assert isinstance(g, GoalSet) and g.name == "tee" and g.kind == "shape"
    assert sorted(g.cells) == [(0, 2), (1, 0), (1, 1), (1, 2), (2, 2)]
    assert (g.spacing, g.range) == (0.2, 0.6)
    g2 = load_shape_file(p, spacing=0.5, name="T")
    assert (g2.name, g2.spacing, g2.range) == ("T", 0.5, 1.5)


def test_a_png_reads_dark_pixels_over_white_and_honours_alpha(tmp_path):
    rows = ["#..", "##.", ".#."]
    g = load_shape_file(_png(tmp_path / "a.png", rows))
    assert _grid(g.cells) == ["#.", "##", ".#"] and sorted(g.cells) == [(0, 1), (0, 2), (1, 0), (1, 1)]
    # a black pixel made fully transparent is background; a grey one is judged by the threshold
    rgba = _png(tmp_path / "b.png", ["###", "..."], mode="RGBA", alpha=["##.", "..."])
    assert sorted(load_shape_file(rgba).cells) == [(0, 1), (1, 1)]
    from PIL import Image

    grey = np.full((1, 2), 255, dtype=np.uint8)
    grey[0, 0] = DARK_THRESHOLD - 1
    grey[0, 1] = DARK_THRESHOLD
    Image.fromarray(grey, "L").save(tmp_path / "g.png")
    assert sorted(load_shape_file(tmp_path / "g.png").cells) == [(0, 0)]
    # a palette image and a 16-bit grey image read the same way
    Image.open(tmp_path / "a.png").convert("P").save(tmp_path / "p.png")
    assert load_shape_file(tmp_path / "p.png").cells == g.cells
    sixteen = np.array([[0 if ch == "#" else 65535 for ch in r] for r in rows], dtype=np.uint16)
    Image.fromarray(sixteen).save(tmp_path / "i16.png")
    assert load_shape_file(tmp_path / "i16.png").cells == g.cells


def test_text_and_png_of_one_shape_agree_and_scale_alike(tmp_path):
    rows = ["##..", ".##.", "..##"]
    t = tmp_path / "s.txt"
    t.write_text("\n".join(rows) + "\n")
    p = _png(tmp_path / "s.png", rows)
    assert load_shape_file(t).cells == load_shape_file(p).cells
    assert load_shape_file(t, 40).cells == load_shape_file(p, 40).cells


BAD_FILES = [
    ("bad-char", "n.txt", "##\n#x\n", InputFileError, r"n\.txt:2: column 2: character 'x' is neither '#'.*fix: use only"),
    ("space", "n.txt", "# #\n", InputFileError, r"n\.txt:1: column 2: character ' '"),
    ("no-goal-txt", "e.txt", "...\n...\n", InputFileError, r"e\.txt: the shape has no '#' cell.*fix: mark the goal"),
    ("empty-file", "e.txt", "", InputFileError, r"no '#' cell"),
    ("disconnected", "d.txt", "#.#\n", InputFileError,
     r"d\.txt: the shape is not connected: 2 separate parts of 1, 1 cells \(cell \(2, 0\) is cut off.*fix: join"),
    ("diagonal", "d.txt", "#.\n.#\n", InputFileError, r"not connected.*diagonal contact does not count"),
    ("suffix", "s.bmp", "#\n", InputFileError, r"s\.bmp: suffix='\.bmp' is not a shape file type; fix: give a \.txt"),
    ("not-utf8", "u.txt", b"#\n\xff\n", InputFileError, r"u\.txt:2: the file is not UTF-8"),
    ("not-png", "x.png", "#\n", InputFileError, r"x\.png: the file is not a PNG image"),
    ("too-many-columns", "w.txt", "#" * (MAX_SIDE + 1) + "\n", InputFileError,
     rf"w\.txt:1: columns={MAX_SIDE + 1} is more than MAX_SIDE={MAX_SIDE}"),
    ("too-many-rows", "h.txt", "#\n" * (MAX_SIDE + 1), InputFileError, rf"rows={MAX_SIDE + 1} is more than"),
]


@pytest.mark.parametrize("name,content,exc,match", [b[1:] for b in BAD_FILES], ids=[b[0] for b in BAD_FILES])
def test_bad_shape_files_name_the_value_and_the_fix(tmp_path, name, content, exc, match):
    p = tmp_path / name
    (p.write_bytes if isinstance(content, bytes) else p.write_text)(content)
    with pytest.raises(exc, match=match):
        load_shape_file(p)


def test_bad_pngs_and_bad_arguments(tmp_path):
    with pytest.raises(InputFileError, match=r"w\.png: the shape has no dark pixel \(luminance below 128"):
        load_shape_file(_png(tmp_path / "w.png", ["...", "..."]))
    with pytest.raises(InputFileError, match=r"t\.png: the shape has no dark pixel"):
        load_shape_file(_png(tmp_path / "t.png", ["##"], mode="RGBA", alpha=[".."]))
    with pytest.raises(InputFileError, match=r"d\.png: the shape is not connected"):
        load_shape_file(_png(tmp_path / "d.png", ["#.#"]))
    # a huge image is refused from its header, before any pixel is decoded
    from PIL import Image

    Image.new("1", (MAX_SIDE + 1, 2), 1).save(tmp_path / "big.png")
    with pytest.raises(InputFileError, match=rf"big\.png: size={MAX_SIDE + 1}x2 pixels is more than MAX_SIDE"):
        load_shape_file(tmp_path / "big.png")
    (tmp_path / "cut.png").write_bytes((tmp_path / "w.png").read_bytes()[:40])
    with pytest.raises(InputFileError, match=r"cut\.png: cannot decode the PNG image"):
        load_shape_file(tmp_path / "cut.png")
    with pytest.raises(InputFileError, match=r"nope\.txt: no such file"):
        load_shape_file(tmp_path / "nope.txt")
    ok = tmp_path / "ok.txt"
    ok.write_text("#\n")
    for kwargs, match in [({"n": 0}, r"n=0 robots is outside 1\.\.16384"), ({"n": 2.5}, r"n=2\.5 must be int"),
                          ({"spacing": 0}, r"spacing=0 must be a finite number > 0"),
                          ({"spacing": True}, r"spacing=True")]:
        with pytest.raises(UsageError, match=match):
            load_shape_file(ok, **kwargs)


# ----------------------------------------------------------------------------
# scaling to n
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["letter-n", "letter-u", "square-9", "letter-l"])
def test_scale_to_gives_exactly_n_connected_cells_deterministically(name):
    src = shapes.bundled_shape(name).cells
    for n in list(range(1, 41)) + [64, 100, 225, 256, 529, 1024]:
        out = scale_to(src, n)
        assert len(out) == n, (name, n)
        assert connected(out), (name, n)
        assert min(c[0] for c in out) == 0 and min(c[1] for c in out) == 0
    assert scale_to(src, 100) == scale_to(set(src), 100) == scale_to(sorted(src), 100)


def test_scaling_up_makes_blocks_and_the_native_size_is_kept():
    src = shapes.bundled_shape("letter-n").cells
    assert scale_to(src, len(src)) == src                      # already n goal pixels: scale 1
    for n, k in ((12, 2), (27, 3), (48, 4)):              # every cell becomes a k x k block
        cells, factor, dropped, rule = scale_details({(0, 0), (1, 0), (1, 1)}, n)
        assert (dropped, rule) == (0, "nearest") and k - 0.5 < factor <= k
        assert _grid(cells) == ["." * k + "#" * k] * k + ["#" * (2 * k)] * k
    # a translated shape scales to the same cells
    assert scale_to({(x + 7, y - 3) for x, y in src}, 300) == scale_to(src, 300)


def test_shrinking_a_thin_shape_falls_back_to_overlap_to_stay_connected():
    thin = {(x, x) for x in range(30)} | {(x + 1, x) for x in range(29)}     # a one-cell staircase
    cells, factor, dropped, rule = scale_details(thin, 10)
    assert len(cells) == 10 and connected(cells) and factor < 1
    # which rule is used is a consequence, checked against nearest sampling itself
    from swarmproof.models.shapes import _resample, _scale_search, _to_array

    a, _ = _to_array(frozenset(thin))
    table = np.zeros((a.shape[0] + 1, a.shape[1] + 1), dtype=np.int64)
    table[1:, 1:] = a.cumsum(0).cumsum(1)
    s = _scale_search(table, a.shape, 10, len(thin), "nearest")
    nearest = shapes._from_array(_resample(table, a.shape, s, "nearest"))
    assert rule == ("nearest" if connected(nearest) else "overlap")


def test_scale_to_refuses_bad_input():
    with pytest.raises(UsageError, match=r"the shape is not connected: 2 separate parts"):
        scale_to({(0, 0), (2, 0)}, 4)
    with pytest.raises(UsageError, match=r"cells=\[\] is empty"):
        scale_to(set(), 4)
    with pytest.raises(UsageError, match=r"n=16385 robots is outside 1\.\.16384"):
        scale_to({(0, 0)}, 16385)
    with pytest.raises(UsageError, match=r"cells=.* must be \(i, j\) integer pairs"):
        scale_to([(0,)], 3)


def test_trimming_keeps_connectivity_where_no_cell_is_locally_simple():
    ring = {(x, 0) for x in range(6)} | {(x, 5) for x in range(6)} | {(0, y) for y in range(6)} | \
           {(5, y) for y in range(6)}
    assert not any(shapes._locally_removable(ring, c) for c in ring)   # the global fallback is needed
    out = shapes._trim(frozenset(ring), 5)
    assert len(out) == len(ring) - 5 and connected(out)


# ----------------------------------------------------------------------------
# bundled shapes, the shape kind
# ----------------------------------------------------------------------------

def test_bundled_letters_load_and_resolve_through_the_shape_kind(tmp_path):
    assert bundled_shape_names() == ["letter-n", "letter-u"]
    n = resolve_target("shape:letter-n")
    assert n.name == "letter-n" and connected(n.cells) and len(n.cells) == 82
    rows = _grid(n.cells)
    assert rows[0] == "###......##" and rows[-1] == "##......###"     # the N's corners
    u = resolve_target("letter-u")
    assert _grid(u.cells)[-1] == "#" * 11 and _grid(u.cells)[0] == "##.......##"
    # the older bundled shapes are unchanged
    assert sorted(resolve_target("shape:square-9").cells) == [(i, j) for i in range(3) for j in range(3)]
    assert sorted(resolve_target("shape:letter-l").cells) == [(0, 0), (0, 1), (0, 2), (1, 0), (2, 0)]
    # a description without cells rebuilds a bundled letter; with cells it round-trips
    assert target_from_description({"kind": "shape", "name": "letter-u"}) == u
    assert target_from_description(json.loads(json.dumps(n.describe()))) == n
    # files: KIND:FILE and a bare path
    p = tmp_path / "bar.txt"
    p.write_text("####\n")
    assert sorted(resolve_target(f"shape:{p}").cells) == sorted(resolve_target(str(p)).cells) == \
        [(0, 0), (1, 0), (2, 0), (3, 0)]
    png = _png(tmp_path / "bar.png", ["####"])
    assert resolve_target(png).cells == resolve_target(f"shape:{png}").cells
    d = tmp_path / "desc.json"
    d.write_text(json.dumps(resolve_target("shape:letter-l").describe()))
    assert resolve_target(f"shape:{d}") == resolve_target("shape:letter-l")
    bad = tmp_path / "bad.txt"
    bad.write_text("#.#\n")
    with pytest.raises(InputFileError, match=r"bad\.txt: the shape is not connected"):
        resolve_target(str(bad))


def test_shape_for_scales_a_name_or_a_path_to_n(tmp_path):
    for name in ("letter-n", "letter-u", "square-9", "letter-l"):
        g = shape_for(name, 256)
        assert len(g.cells) == 256 and connected(g.cells) and g.name == name and g.range == 0.6
    p = tmp_path / "blob.txt"
    p.write_text(".#.\n###\n.#.\n")
    assert len(shape_for(p, 50).cells) == 50 and shape_for(str(p), 50) == shape_for(f"shape:{p}", 50)
    with pytest.raises(UsageError, match=r"shape='letter-z' is neither a file nor a bundled shape; fix: .*'letter-n'"):
        shape_for("letter-z", 10)


def test_random_shapes_are_connected_seeded_and_distinct_across_seeds():
    a = random_shape(64, np.random.default_rng(5))
    assert len(a.cells) == 64 and connected(a.cells)
    assert a == random_shape(64, np.random.default_rng(5))
    assert a != random_shape(64, np.random.default_rng(6))
    with pytest.raises(UsageError, match=r"rng=3 must be a numpy.random.Generator"):
        random_shape(4, 3)


# ----------------------------------------------------------------------------
# arenas and random starts
# ----------------------------------------------------------------------------

def test_random_starts_are_distinct_in_the_arena_and_seeded():
    rng = np.random.default_rng(11)
    starts = random_start_cells(529, (32, 32), rng)
    assert len(set(starts)) == 529 and set(starts) <= arena_cells(32, 32)
    assert starts == random_start_cells(529, (32, 32), np.random.default_rng(11))
    full = random_start_cells(16, (4, 4), np.random.default_rng(0))
    assert sorted(full) == sorted(arena_cells(4))                      # every vertex taken
    goal = {(0, 0), (1, 0)}
    around = centered_arena(goal, 5)
    assert len(around) == 25 and (0, 0) in around and (1, 0) in around
    s = random_start_cells(5, around, np.random.default_rng(1), exclude=goal)
    assert not set(s) & goal


@pytest.mark.parametrize("args,match", [
    ((1025, (32, 32)), r"n=1025 robots is more than the arena=32x32 holds \(1024 free cells\); fix: give at most 1024"),
    ((5, {(0, 0), (5, 5)}), r"n=5 robots is more than the arena=2 cells holds"),
    ((0, (4, 4)), r"n=0 must be >= 1"),
    ((3, (0, 4)), r"width=0 is outside 1\.\.2048"),
], ids=["full-arena", "cell-set", "no-robots", "empty-arena"])
def test_too_many_robots_for_the_arena_is_a_usage_error(args, match):
    with pytest.raises(UsageError, match=match):
        random_start_cells(*args, rng=np.random.default_rng(0))


def test_random_starts_need_an_explicit_generator():
    with pytest.raises(UsageError, match=r"rng=None must be a numpy.random.Generator"):
        random_start_cells(3, (4, 4))


# ----------------------------------------------------------------------------
# the centralized optimum (Fig. 10)
# ----------------------------------------------------------------------------

def _brute_force(starts, goals):
    d = manhattan_matrix(starts, goals)
    return min(sum(int(d[i, p[i]]) for i in range(len(starts))) for p in itertools.permutations(range(len(goals))))


def test_optimal_assignment_matches_brute_force_for_up_to_six_robots():
    rng = np.random.default_rng(2020)
    for n in range(1, 7):
        for _ in range(15):
            goals = sorted(random_shape(n, rng).cells)
            starts = random_start_cells(n, (8, 8), rng)
            a = optimal_assignment(starts, goals, spacing=0.2)
            total, pairs = a
            best = _brute_force(starts, goals)
            assert a.cells == best and total == pytest.approx(0.2 * best)
            assert [i for i, _ in pairs] == list(range(n)) and sorted(j for _, j in pairs) == list(range(n))
            assert assignment_cost(starts, goals, [j for _, j in pairs]) == best
            assert (a.method, a.size) == ("scipy.optimize.linear_sum_assignment", n)


def test_optimal_assignment_agrees_with_z3_for_tiny_swarms():
    rng = np.random.default_rng(7)
    for n in range(1, MAX_Z3_ROBOTS + 1):
        goals = sorted(random_shape(n, rng).cells)
        starts = random_start_cells(n, (10, 10), rng)
        exact = z3_optimal_assignment(starts, goals, spacing=0.2)
        assert exact.method == "z3.Optimize" and exact.cells == optimal_assignment(starts, goals).cells
        if n <= 6:
            assert exact.cells == _brute_force(starts, goals)
        r = check_optimal_assignment(starts, goals)
        assert r["status"] == "held" and r["scipy"]["cells"] == r["z3"]["cells"]


def test_the_cross_check_can_say_violated_and_inconclusive(monkeypatch):
    from swarmproof.checkers import assignment_check
    from swarmproof.models.assignment import Assignment

    starts, goals = [(0, 0), (5, 0)], [(4, 0), (1, 0)]
    real = assignment_check.optimal_assignment
    monkeypatch.setattr(assignment_check, "optimal_assignment",
                        lambda s, g: Assignment(9.0, real(s, g).pairs, cells=9, method="broken", size=2))
    r = check_optimal_assignment(starts, goals)
    assert r["status"] == "violated" and r["message"] == "scipy's optimum 9 cells != z3's 2 (z3's pairs cost 2)"
    monkeypatch.setattr(assignment_check, "optimal_assignment", real)

    def unknown(*a, **k):
        raise Z3Inconclusive("z3 answered unknown (timeout)")

    monkeypatch.setattr(assignment_check, "z3_optimal_assignment", unknown)
    r = check_optimal_assignment(starts, goals)
    assert r["status"] == "inconclusive" and r["z3"] is None


@pytest.mark.parametrize("starts,goals,kwargs,match", [
    ([(0, 0)], [(0, 0), (1, 0)], {}, r"start_cells has 1 cells and goal_cells 2: 004 Sec\. II-C assumes \|Q\| = \|A\|"),
    ([], [], {}, r"start_cells=\[\] is empty"),
    ([(0, 0), (1, 0)], [(2, 2), (2, 2)], {}, r"goal_cells has a repeated cell"),
    ([(0.5, 0)], [(0, 0)], {}, r"start_cells=\[\(0\.5, 0\)\] must be a sequence of \(i, j\) integer grid cells"),
    ([(0, 0)], [(0, 0)], {"spacing": -1}, r"spacing=-1 must be a finite number > 0"),
], ids=["sizes", "empty", "repeated-goal", "non-integer", "spacing"])
def test_optimal_assignment_refuses_bad_input(starts, goals, kwargs, match):
    with pytest.raises(UsageError, match=match):
        optimal_assignment(starts, goals, **kwargs)


def test_z3_refuses_large_swarms():
    cells = [(i, 0) for i in range(MAX_Z3_ROBOTS + 1)]
    with pytest.raises(UsageError, match=re.escape(f"size={MAX_Z3_ROBOTS + 1} robots is above MAX_Z3_ROBOTS")):
        z3_optimal_assignment(cells, cells)
