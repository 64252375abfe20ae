"""Lee & Chong's patterns (issue 17): 003 Table 1 + Alg. 2 and Alg. 3 as target points, the
``lines`` targets built on them, and the exact distinctness checks."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest

from swarmproof.reference_impl.leechong import patterns_check as chk
from swarmproof.models import line_patterns as lp
from swarmproof.models.errors import UsageError
from swarmproof.models.line_patterns import (PATTERN_NAMES, interval_for_span, line_count, pattern_info,
                                             target_points)
from swarmproof.models.targets import LinePattern, resolve_target, target_from_description, target_names

R3 = math.sqrt(3)


def _rot(xy, ang, shift):
    c, s = math.cos(ang), math.sin(ang)
    xy = np.asarray(xy, dtype=float)
    return np.column_stack((c * xy[:, 0] - s * xy[:, 1] + shift[0], s * xy[:, 0] + c * xy[:, 1] + shift[1]))


# --- targets worked out by hand from the printed formulas --------------------------------------

HAND = [
    # Alg. 3, NoLine = 2: L = floor((ID%2 + 1)/2) d_u, u = u_l - floor(ID/2) d_u
    ("two-row", 4, 2.0, 3.0, {}, [(3, 0), (3, -2), (1, 0), (1, -2)]),
    # Alg. 3, NoLine = 3 (odd): ranks 0 and 1, the odd rank through lines 16-19
    ("three-row", 6, 1.0, 0.0, {}, [(0, 0), (0, -1), (0, 1), (-1, 0), (-1, 1), (-1, -1)]),
    # column type, n=5, k=2: NoLine = floor(5/2) + 1 = 3
    ("two-column", 5, 1.0, 0.0, {}, [(0, 0), (0, -1), (0, 1), (-1, 0), (-1, 1)]),
    # k=3, n=6: NoLine = 2
    ("three-column", 6, 1.0, 0.0, {}, [(0, 0), (0, -1), (-1, 0), (-1, -1), (-2, 0), (-2, -1)]),
    ("one-row", 3, 1.0, 0.0, {}, [(0, 0), (-1, 0), (-2, 0)]),
    ("one-column", 4, 1.0, 0.0, {}, [(0, 0), (0, -1), (0, 1), (0, -2)]),
    # wedge: theta = -30, L = -d_o, T = u_l; u = cos(-30)(-d_o), v = sin(-30)(-d_o) mark
    ("wedge", 5, 1.0, 0.0, {"alpha_star": 30}, [(0, 0), (-R3 / 2, -0.5), (-R3 / 2, 0.5), (-R3, -1), (-R3, 1)]),
    ("horizontal-line", 3, 1.0, 0.0, {}, [(0, 0), (0, -1), (0, 1)]),
    ("vertical-line", 3, 2.0, 5.0, {}, [(5, 0), (3, 0), (7, 0)]),
    # circle, n=4, d_u = 2 pi: radius n d_u / (2 pi) = 4, alpha = 90 j, T = u_l - 4
    ("circle", 4, 2 * math.pi, 0.0, {}, [(0, 0), (-4, -4), (-4, 4), (-8, 0)]),
    # printed radius 360 d_u / (2 pi n): with d_u = 2 pi, n = 4: 90
    ("circle", 4, 2 * math.pi, 0.0, {"radius": "printed"}, [(0, 0), (-90, -90), (-90, 90), (-180, 0)]),
    # arc, n=4, m=3: radius m d_c = 12, theta = 30 j
    ("arc", 4, 2 * math.pi, 0.0, {}, [(0, 0), (12 * (R3 / 2 - 1), -6), (12 * (R3 / 2 - 1), 6), (-6, -6 * R3)]),
    # fan-shape: theta = 180 - 30 j, so the leader's own row is (u_l - 2L, 0)
    ("fan-shape", 4, 2 * math.pi, 0.0, {}, [(-24, 0), (-12 * (1 + R3 / 2), -6), (-12 * (1 + R3 / 2), 6), (-18, -6 * R3)]),
    # triangle n=6: d_c = 6; k_m = 1/2 at 60 and 180 degrees, 1 at 0 and 120; T = u_l - L (table)
    ("triangle", 6, 2 * math.pi, 0.0, {}, [(0, 0), (-1.5, -1.5 * R3), (-1.5, 1.5 * R3), (-9, -3 * R3),
                                           (-9, 3 * R3), (-6, 0)]),
    # ... and with the circumcentre fixed (T = u_l - d_c): an equilateral triangle of side 6 sqrt 3
    ("triangle", 6, 2 * math.pi, 0.0, {"center": "fixed"}, [(0, 0), (-4.5, -1.5 * R3), (-4.5, 1.5 * R3),
                                                             (-9, -3 * R3), (-9, 3 * R3), (-9, 0)]),
    # diamond with n = k: every robot on a vertex, the circle's points
    ("diamond", 4, 2 * math.pi, 0.0, {}, [(0, 0), (-4, -4), (-4, 4), (-8, 0)]),
]


@pytest.mark.parametrize("name, n, d_u, u_l, params, want", HAND,
                         ids=[f"{h[0]}-n{h[1]}-{'-'.join(map(str, h[4].values())) or 'default'}" for h in HAND])
def test_targets_match_the_formulas_worked_by_hand(name, n, d_u, u_l, params, want):
    got = target_points(name, n, d_u, u_l, **params)
    assert got.shape == (n, 2)
    np.testing.assert_allclose(got, np.array(want, dtype=float), atol=1e-9)


def test_multi_line_targets_are_exact_integer_multiples_of_d_u():
    for name in [p for p in PATTERN_NAMES if pattern_info(p)["type"] == "multi"]:
        for n in range(1, 30):
            pts = target_points(name, n, 0.5, 2.0)
            offs = lp.multi_line_offsets(name, n)
            assert pts.tolist() == [[2.0 - 0.5 * a, 0.5 * b] for a, b in offs]


def test_line_count_alg3_and_alg4_readings():
    assert [line_count("three-column", n) for n in (3, 4, 6, 7, 12)] == [1, 2, 2, 3, 4]
    assert [line_count("two-column", n) for n in (2, 5, 12)] == [1, 3, 6]
    assert line_count("three-column", 12, reading="alg4") == 3 and line_count("two-row", 12) == 2
    assert line_count("rows", 12, k=5) == 5 and line_count("columns", 12, k=5) == 3
    # under Alg. 4's NoLine = k, 'two-column' computes the 'two-row' targets
    np.testing.assert_array_equal(target_points("two-column", 9, 1.0, noline="alg4"),
                                  target_points("two-row", 9, 1.0))


def test_the_leader_row_is_u_l_except_for_the_fan():
    for name in PATTERN_NAMES:
        row0 = target_points(name, 9, 1.0, 4.0)[0]
        if name == "fan-shape":
            L = 3 * 9 / (2 * math.pi)
            np.testing.assert_allclose(row0, (4.0 - 2 * L, 0.0), atol=1e-12)
        else:
            np.testing.assert_allclose(row0, (4.0, 0.0), atol=1e-12)


def test_uni_line_patterns_are_symmetric_even_ids_on_the_left():
    for name in [p for p in PATTERN_NAMES if pattern_info(p)["type"] == "uni" and p != "vertical-line"]:
        pts = target_points(name, 9, 1.0)
        for j in range(1, 5):
            odd, even = pts[2 * j - 1], pts[2 * j]
            np.testing.assert_allclose(odd, even * (1, -1), atol=1e-12)
            assert even[1] > 0
    # the vertical line (theta = 0, L = d_o mark) puts even IDs ahead of the leader, odd ones behind
    pts = target_points("vertical-line", 5, 1.0)
    assert pts[:, 1].tolist() == [0.0] * 5 and pts[:, 0].tolist() == [0, -1, 1, -2, 2]


def test_circle_type_patterns_keep_arc_length_d_u_between_neighbours():
    d_u, n = 0.7, 12
    r = n * d_u / (2 * math.pi)
    c = np.array([-r, 0.0])
    pts = target_points("circle", n, d_u) - c
    assert np.allclose(np.hypot(*pts.T), r)
    ang = np.sort(np.mod(np.arctan2(pts[:, 1], pts[:, 0]), 2 * math.pi))
    assert np.allclose(np.diff(ang) * r, d_u)
    arc = target_points("arc", n, d_u) - np.array([-3 * r, 0.0])      # radius m d_c, m = 3
    ang = np.sort(np.arctan2(arc[:, 1], arc[:, 0]))
    assert np.allclose(np.hypot(*arc.T), 3 * r) and np.allclose(np.diff(ang) * 3 * r, d_u)


def test_a_span_keeps_the_size_d_u_is_span_over_n_minus_1():
    assert interval_for_span(12.0, 7) == 2.0 and interval_for_span(12.0, 4) == 4.0
    w = LinePattern("w", "wedge", span=12.0)
    np.testing.assert_array_equal(w.points(7), target_points("wedge", 7, 2.0))
    np.testing.assert_array_equal(w.points(4), target_points("wedge", 4, 4.0))
    # the vertical line's two ends stay span apart after a robot is lost (003 Sec. 3.5)
    v = LinePattern("v", "one-row", span=10.0)
    for n in (6, 5, 3):
        assert np.ptp(v.points(n)[:, 0]) == pytest.approx(10.0)
    # tolerance and messages scale with the interval of this n
    assert "at interval 2" in w.satisfied(range(7), w.points(7)).message


@pytest.mark.parametrize("name", PATTERN_NAMES)
def test_every_bundled_pattern_holds_up_to_a_rigid_motion_and_one_moved_robot_violates(name):
    t = resolve_target(f"lines:{name}")
    assert t.kind == "lines" and t.shape == name and t.range is None
    n = 7
    pts = t.points(n)
    perm = [3, 6, 0, 5, 1, 4, 2]
    moved = _rot(pts, 1.234, (5.0, -2.0))[perm]
    poses = np.column_stack((moved, np.arange(n)))          # headings are not judged
    check = t.satisfied(range(n), poses)
    assert check.held, check.message
    assert t.progress(range(n), poses) == pytest.approx(0.0, abs=1e-6)
    off = poses.copy()
    off[4, :2] += (0.03, -0.04)
    bad = t.satisfied(range(n), off)
    # the witness is an upper bound of the best rigid fit's error (models.targets._rigid_fit)
    assert bad.violated and 0.005 < bad.witness["max_error"] < 0.5


def test_satisfaction_is_on_shape_not_name_rows_and_columns_agree_at_twelve():
    # Fig. 6 names 'two row' and 'three column', Tables 2-5 'Two columns' and 'Three rows': at
    # n = 12 these are the same 2 x 6 and 3 x 4 grids, turned by 90 degrees
    for a, b in (("two-row", "two-column"), ("three-row", "three-column")):
        ta, tb = resolve_target(f"lines:{a}"), resolve_target(f"lines:{b}")
        assert ta.satisfied(range(12), tb.points(12)).held
        assert ta.satisfied(range(5), tb.points(5)).violated
    assert resolve_target("lines:circle").satisfied(range(6), resolve_target("lines:hexagon").points(6)).held
    assert resolve_target("lines:circle").satisfied(range(12), resolve_target("lines:hexagon").points(12)).violated


def test_describe_round_trips_for_bundled_and_custom_patterns():
    for kind, name in target_names("lines"):
        t = resolve_target(f"lines:{name}")
        d = json.loads(json.dumps(t.describe()))
        assert target_from_description(d) == t and d == {"kind": "lines", "name": name, "shape": name,
                                                         "interval": 1.0, **({"range": 1.5} if name == "line" else {})}
    custom = LinePattern("my-diamond", "diamond", span=6.0, range=3.0,
                         params={"rotation": 45.0, "center": "fixed"})
    d = json.loads(json.dumps(custom.describe()))
    assert d == {"kind": "lines", "name": "my-diamond", "shape": "diamond", "span": 6.0,
                 "params": {"center": "fixed", "rotation": 45.0}, "range": 3.0}
    back = target_from_description(d)
    assert back == custom and np.array_equal(back.points(9), custom.points(9))
    # a description naming a bundled pattern without 'shape' is that pattern
    assert target_from_description({"kind": "lines", "name": "wedge"}).shape == "wedge"


def test_bare_names_shared_with_lattices_are_ambiguous_and_the_prefix_decides():
    for name in ("hexagon", "triangle"):
        with pytest.raises(UsageError, match=rf"target='{name}' is ambiguous: bundled as lattice, lines; "
                                             rf"fix: say which: lattice:{name} or lines:{name}"):
            resolve_target(name)
        assert resolve_target(f"lines:{name}").kind == "lines"
        assert resolve_target(f"lattice:{name}").kind == "lattice"
        assert resolve_target(name, prefer="lattice").kind == "lattice"
    assert resolve_target("wedge").kind == "lines"


BAD = [
    (lambda: target_points("hexagn", 5, 1.0), r"pattern name='hexagn' is not a Lee & Chong pattern; fix: use one of "
                                              r"\['wedge', .*'hexagon'"),
    (lambda: target_points("wedge", 0, 1.0), r"n=0 must be an integer >= 1"),
    (lambda: target_points("wedge", 2.5, 1.0), r"n=2.5 must be an integer >= 1"),
    (lambda: target_points("wedge", 5, 0.0), r"d_u=0.0 must be > 0"),
    (lambda: target_points("wedge", 5, float("nan")), r"d_u=nan must be a finite number"),
    (lambda: target_points("wedge", 5, 1.0, alpha_star=90), r"alpha_star=90 must be a number of degrees with 0 < "),
    (lambda: target_points("arc", 5, 1.0, m=0), r"m=0 must be an integer >= 1"),
    (lambda: target_points("circle", 5, 1.0, radius="big"), r"radius='big' is not a reading of pattern 'circle'; "
                                                            r"fix: use one of \['arc-length', 'printed'\]"),
    (lambda: target_points("circle", 5, 1.0, m=3), r"m=3 is not a parameter of pattern 'circle'; fix: use only"),
    (lambda: target_points("horizontal-line", 5, 1.0, k=3), r"k=3 is not a parameter of pattern 'horizontal-line'; "
                                                            r"fix: pattern 'horizontal-line' takes no parameters"),
    (lambda: target_points("polygon", 5, 1.0), r"k=None: pattern 'polygon' needs k"),
    (lambda: target_points("polygon", 5, 1.0, k=2), r"pattern 'polygon' is undefined for n=5 at ID 0"),
    (lambda: target_points("hexagon", 5, 1.0, index="integer"), r"undefined for n=5 at ID 0: j mod floor\(n/k\)"),
    (lambda: line_count("wedge", 5), r"name='wedge' is a uni-line pattern"),
    (lambda: line_count("two-row", 5, reading="alg5"), r"reading='alg5' is not a NoLine reading"),
    (lambda: interval_for_span(10.0, 1), r"n=1 must be an integer >= 2 \(a span needs at least two robots"),
    (lambda: interval_for_span(-1.0, 4), r"span=-1.0 must be a finite number > 0"),
    (lambda: pattern_info("Wedge"), r"pattern name='Wedge' is not a Lee & Chong pattern"),
    (lambda: LinePattern("x", "hex"), r"shape='hex' is not a known line pattern; fix: use one of \['line', 'wedge'"),
    (lambda: LinePattern("x", "wedge", interval=1.0, span=4.0), r"interval=1.0 and span=4.0 are both given"),
    (lambda: LinePattern("x", "wedge", span=0), r"span=0 must be a finite number > 0"),
    (lambda: LinePattern("x", "line", params={"m": 3}), r"params=\{'m': 3\}: shape 'line' takes no parameters"),
    (lambda: LinePattern("x", "wedge", params={"alpha_star": 0}), r"alpha_star=0 must be"),
    (lambda: target_from_description({"kind": "lines", "name": "x", "shape": "wedge", "params": [1]}),
     r"params=\[1\] must be an object"),
    (lambda: chk.check_all(1), r"max_n=1 must be an integer >= 2"),
    (lambda: chk.check_distinct("nope", 4), r"pattern name='nope'"),
]


@pytest.mark.parametrize("call, match", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_input_is_a_usage_error_naming_the_value_and_the_fix(call, match):
    with pytest.raises(UsageError, match=match):
        call()


# --- exact distinctness ------------------------------------------------------------------------

def test_every_pattern_is_pairwise_distinct_for_n_up_to_64():
    rows = chk.check_all(64)
    assert len(rows) == len(PATTERN_NAMES) * 63
    assert {r["status"] for r in rows} == {"held"}
    assert all(r["collisions"] == [] and r["undefined"] is None for r in rows)


def test_pinned_findings_undefined_formulas_and_fewer_lines_than_named():
    r = chk.check_distinct("polygon", 9, k=2)                    # k_m = cos 90 / cos 90 = 0/0 at ID 0
    assert r["status"] == "inconclusive" and r["undefined"]["id"] == 0 and "denominator is 0" in r["reason"]
    r = chk.check_distinct("hexagon", 5, index="integer")        # j mod floor(5/6) = j mod 0
    assert r["status"] == "inconclusive" and r["undefined"]["id"] == 0
    assert chk.check_distinct("hexagon", 6, index="integer")["status"] == "held"
    r = chk.check_distinct("polygon", 6, k=1)                    # negative radius: not decided
    assert r["status"] == "inconclusive" and r["undefined"] is None and "negative" in r["reason"]
    assert chk.check_distinct("three-column", 4)["notes"] == [
        "Alg. 3 column type k=3 with n=4: NoLine = 2, so the robots form 2 columns (lines parallel to v), not 3"]
    assert chk.check_distinct("three-column", 12)["notes"] == []
    assert "not 3" in chk.check_distinct("three-row", 2)["notes"][0]
    assert "u_l - 2L" in chk.check_distinct("fan-shape", 12)["notes"][0]
    assert chk.check_distinct("pentagon", 12)["notes"] == [
        "n=12 is not a multiple of k=5: only some of the 5 vertices hold a robot"]


def test_the_check_can_fail(monkeypatch):
    real = lp.multi_line_offsets
    monkeypatch.setattr(lp, "multi_line_offsets", lambda name, n, **p: real(name, n, **p)[:-1] + [(0, 0)])
    r = chk.check_distinct("two-row", 5)
    assert r["status"] == "violated" and r["collisions"] == [[0, 4]]


VARIANTS = [(name, {}) for name in PATTERN_NAMES] + [
    ("circle", {"radius": "printed"}), ("arc", {"m": 1}), ("fan-shape", {"m": 2}), ("wedge", {"alpha_star": 89.5}),
    ("hexagon", {"center": "fixed"}), ("diamond", {"rotation": 45.0}), ("pentagon", {"index": "integer"}),
    ("polygon", {"k": 7, "rotation": 10.0}), ("two-column", {"noline": "alg4"}), ("rows", {"k": 5}),
    ("columns", {"k": 4}), ("polygon", {"k": 1}), ("polygon", {"k": 2})]


@pytest.mark.parametrize("name, params", VARIANTS, ids=[f"{v[0]}-{i}" for i, v in enumerate(VARIANTS)])
def test_the_exact_verdict_agrees_with_the_float_targets(name, params):
    """Held <=> the float targets are at least 1e-6 d_u apart; violated <=> some coincide."""
    for n in range(2, 25):
        r = chk.check_distinct(name, n, **params)
        if r["status"] == "inconclusive":
            continue
        pts = target_points(name, n, 1.0, 0.3, **params)
        gaps = [float(np.hypot(*(pts[i] - pts[j]))) for i, j in itertools.combinations(range(n), 2)]
        assert (min(gaps) > 1e-6) == (r["status"] == "held"), (name, params, n)
