"""Wang & Rubenstein 2020's collision theorems in z3 (reference_impl/wang2020/lemmas.py, issue 15) and
the runtime monitors of their premises (invariants/premises.py, grid_* monitors)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import z3

from swarmproof.checkers import proofs
from swarmproof.reference_impl.wang2020 import lemmas as w, monitors as grid
from swarmproof.checkers.proofs import LEMMAS
from swarmproof.invariants import premises
from swarmproof.models.trace import Trace

pytestmark = pytest.mark.proofs

IDS = list(w.LEMMAS)


def _holds(enc, values: dict) -> tuple:
    """Exact numbers into an encoding without cases: (all premises true, conclusion true)."""
    subs = [(v, z3.RealVal(str(values[str(v)]))) for v in enc.variables]
    prem = all(z3.is_true(z3.simplify(z3.substitute(t, *subs))) for _, t in enc.premises)
    return prem, z3.is_true(z3.simplify(z3.substitute(enc.conclusion, *subs)))


def test_registered_in_the_suite_in_order_with_unique_ids():
    assert IDS == ["wang2020_time_normalisation", "wang2020_planner_vertex_one_moment",
                   "wang2020_planner_edge_one_moment", "wang2020_lemma_iv_a_1", "wang2020_theorem_iv_a_2",
                   "wang2020_separation_equal_speeds", "wang2020_speed_buffer_v_b3_cases",
                   "wang2020_separation_speeds"]
    assert [i for i in LEMMAS if i.startswith("wang2020_")] == IDS   # in order (the examples' lemma follows)
    assert all(LEMMAS[i] is w.LEMMAS[i] for i in IDS)


# Proved, control refuted, vacuity "ok": tests/checkers/test_proofs.py's one z3 run per suite lemma
# asserts it for these lemmas too (they are in the suite, checked above; issue 29: this file proved
# each of them a second time, 26 s of CPU).  What is particular to them and needs no z3:
@pytest.mark.parametrize("lemma_id", IDS)
def test_lemma_cites_the_paper_and_says_what_it_does_not_prove(lemma_id):
    lem = LEMMAS[lemma_id]
    if lemma_id != "wang2020_time_normalisation":
        assert any("004" in c for c in lem.cites) and lem.not_proved


def test_kinds_follow_design_section_5():
    kinds = {i: LEMMAS[i].kind for i in IDS}
    assert {i for i, k in kinds.items() if k == "paper lemma"} == {"wang2020_lemma_iv_a_1",
                                                                  "wang2020_theorem_iv_a_2"}
    assert "Lemma IV-A.1" in LEMMAS["wang2020_lemma_iv_a_1"].cites[0]
    assert "Thm. IV-A.2" in LEMMAS["wang2020_theorem_iv_a_2"].cites[0]
    # the one-moment rule and the equal-speed geometry never carry the theorems' names
    for i in ("wang2020_planner_vertex_one_moment", "wang2020_planner_edge_one_moment"):
        assert "is not proved here" in LEMMAS[i].cites[0]
    assert "equal speeds only" in " ".join(LEMMAS["wang2020_separation_equal_speeds"].not_proved)
    # Sec. V-B3's buffer space is a geometric bound, not a numbered result: auxiliary
    for i in ("wang2020_speed_buffer_v_b3_cases", "wang2020_separation_speeds"):
        assert kinds[i] == "auxiliary" and "Sec. V-B3" in LEMMAS[i].cites[0]
        assert any("v_max = 1" in n and "(wang2020_time_normalisation)" in n for n in LEMMAS[i].normalisations)


# The suite lemmas' own proofs (same lemma, same timeout) are read through testkit.proved: the
# per-lemma test (tests/checkers/test_proofs.py, xdist group z3-suite) proves each once per worker
# and these tests check further facts about the same control counterexample.
@pytest.mark.xdist_group("z3-suite")
def test_ignoring_priority_sends_two_agents_to_one_waypoint():
    from testkit import proved

    r = proved(LEMMAS["wang2020_planner_vertex_one_moment"], timeout_s=10)
    cex = r.negative_control["counterexample"]
    ags = [(0.0, 0.0)] + [(cex[f"c{k}_x"], cex[f"c{k}_y"]) for k in range(1, 4)]
    nxt = [(c[0] + cex[f"d{k}_x"], c[1] + cex[f"d{k}_y"]) for k, c in enumerate(ags)]
    ready = [cex[f"ready{k}"] == 1 for k in range(4)]
    # the control's counterexample: two ready agents with one next waypoint, both stepping
    same = lambda p, q: math.dist(p, q) < 1e-9  # noqa: E731  (the model's rationals as floats)
    pairs = [(a, b) for a in range(4) for b in range(a + 1, 4)
             if ready[a] and ready[b] and same(nxt[a], nxt[b]) and not same(nxt[a], ags[a])
             and not same(nxt[b], ags[b])]
    assert pairs


def test_optimistic_planner_swaps_along_an_edge():
    ctrl = proofs.solve(w.planner_one_moment(rule="optimistic", conclusion="edge"), (("solver", "smt"),))
    assert ctrl["status"] == "counterexample" and "no_swap_along_an_edge" in ctrl["reason"]


@pytest.mark.parametrize("build", [w.lemma_iv_a_1, w.theorem_iv_a_2], ids=["lemma_iv_a_1", "theorem_iv_a_2"])
def test_timing_control_counterexample_breaks_only_the_weakened_window(build):
    # The model itself, exactly (its thirds do not survive a round trip through floats).
    window = 1 if build is w.lemma_iv_a_1 else 0.5
    weak = build(window)
    session = proofs._Session(proofs.Budget.of(None, 60), (("solver", "smt"),))
    res, model, _ = session.check(weak.premises, weak.conclusion)
    assert res == z3.sat
    holds = lambda t: z3.is_true(model.eval(session.term(t), model_completion=True))  # noqa: E731
    assert all(holds(t) for _, t in weak.premises) and not holds(weak.conclusion)
    # the paper's window Delta t = 2/f_comm excludes it: some premise fails, and it is a window premise
    failing = [n for n, t in build().premises if not holds(t)]
    assert failing and all("window" in n or "alg2_line30" in n for n in failing), failing


def test_lemma_iv_a_1_needs_two_periods_theorem_iv_a_2_one():
    smt = (("solver", "smt"),)
    assert proofs.solve(w.lemma_iv_a_1(1), smt)["status"] == "counterexample"
    assert proofs.solve(w.lemma_iv_a_1(2), smt)["status"] == "proved"
    assert proofs.solve(w.theorem_iv_a_2(1), smt)["status"] == "proved"
    assert proofs.solve(w.theorem_iv_a_2(0.5), smt)["status"] == "counterexample"


@pytest.mark.xdist_group("z3-suite")
def test_separation_control_is_the_orthogonal_hand_over_below_the_bound():
    from testkit import proved

    cex = proved(LEMMAS["wang2020_separation_equal_speeds"], timeout_s=10).negative_control["counterexample"]
    r = cex["r"]
    assert 1 / (2 * math.sqrt(2)) < r <= 1 / (2 * math.sqrt(2) * 0.99) + 1e-12   # l = 1 below 2 sqrt(2) r
    pi = np.array([cex["lam_i"] * cex["D_i_x"], cex["lam_i"] * cex["D_i_y"]])
    pj = np.array([cex["A_j_x"] + cex["lam_j"] * cex["D_j_x"], cex["A_j_y"] + cex["lam_j"] * cex["D_j_y"]])
    assert np.hypot(*(pi - pj)) < 2 * r


def _holds_in_case(enc, case: str, values: dict) -> tuple:
    """Exact numbers into one case of an encoding: (all its premises true, conclusion true)."""
    subs = [(v, z3.RealVal(str(values[str(v)]))) for v in enc.variables]
    extra = dict(enc.cases)[case]
    prem = all(z3.is_true(z3.simplify(z3.substitute(t, *subs))) for _, t in list(enc.premises) + extra)
    return prem, z3.is_true(z3.simplify(z3.substitute(enc.conclusion, *subs)))


def test_v_b3_bound_is_tight_in_the_orthogonal_case_with_the_papers_worst_speeds():
    """l = 1 exactly at the bound: v_min / v_max = 3/4 gives r = 3/10 (4 r^2 (1 + rho^2) = rho^2);
    the leaver at v_min, the enterer at v_max, at t* = v_max l / (v_max^2 + v_min^2) = 16/25 the
    discs touch: distance 3/5 = 2r.  A hair less l (larger r) and they overlap."""
    at = {"r": "3/10", "rho": "3/4", "a": "3/4", "b": 1, "t": "16/25", "lam_L": "12/25", "lam_F": "16/25",
          "L_x": 0, "L_y": "12/25"}
    assert _holds_in_case(w.speed_buffer_cases(), "orthogonal_adjacent_edges", at) == (True, True)
    over = {**at, "r": "301/1000"}
    assert _holds_in_case(w.speed_buffer_cases(), "orthogonal_adjacent_edges", over) == (False, False)
    assert _holds_in_case(w.speed_buffer_cases(0.99 ** 2), "orthogonal_adjacent_edges", over) == (True, False)
    # the collinear case at the same numbers is not tight: the enterer arrives (t = 1) with the leaver
    # 3/4 ahead, more than 2r = 3/5 (Sec. V-B3: 2 r v_max / v_min never exceeds the orthogonal bound)
    col = {**at, "t": 1, "lam_L": "3/4", "lam_F": 1, "L_x": "3/4", "L_y": 0}
    assert _holds_in_case(w.speed_buffer_cases(), "collinear_adjacent_edges", col) == (True, True)


# timeout 20 s (more than the per-lemma test's 10: wang2020_separation_speeds needs more on a loaded
# machine); testkit.proved reuses the per-lemma test's proof when it finished within 10 s
@pytest.mark.xdist_group("z3-suite")
@pytest.mark.parametrize("lemma_id", ["wang2020_speed_buffer_v_b3_cases", "wang2020_separation_speeds"])
def test_speed_controls_put_two_discs_closer_than_2r_below_the_v_b3_bound(lemma_id):
    from testkit import proved

    cex = proved(LEMMAS[lemma_id], timeout_s=20).negative_control["counterexample"]
    r, rho = cex["r"], cex["rho"]
    bound = 2 * r * math.sqrt(1 + rho * rho) / rho              # in units of l = 1
    assert 0 < rho <= 1 and 1 < bound <= 1 / 0.99 + 1e-9         # l = 1 just below the bound
    if lemma_id == "wang2020_speed_buffer_v_b3_cases":
        assert rho <= cex["a"] <= 1 and rho <= cex["b"] <= 1
        pl, pf = np.array([cex["L_x"], cex["L_y"]]), np.array([-1 + cex["lam_F"], 0.0])
    else:
        assert rho <= cex["w_i"] <= 1 and rho <= cex["w_j"] <= 1
        pl = np.array([cex["lam_i"] * cex["D_i_x"], cex["lam_i"] * cex["D_i_y"]])
        pf = np.array([cex["A_j_x"] + cex["lam_j"] * cex["D_j_x"], cex["A_j_y"] + cex["lam_j"] * cex["D_j_y"]])
    assert np.hypot(*(pl - pf)) < 2 * r + 1e-9


def test_separation_with_speeds_at_equal_speeds_is_the_equal_speed_lemma():
    """At v_min = v_max the V-B3 premise is 8 r^2 <= 1, the equal-speed lemma's: its control (l one
    per cent below 2 sqrt 2 r) still has a counterexample with every speed equal, and every speed is
    then v_max."""
    ctrl = w.separation_speeds(0.99 ** 2)
    ctrl.premises.append(("equal_speeds", z3.Real("rho") == 1))
    out = proofs.solve(ctrl)
    cex = out["counterexample"]
    assert out["status"] == "counterexample" and cex["rho"] == cex["w_i"] == cex["w_j"] == 1
    assert 1 / (2 * math.sqrt(2)) < cex["r"]


@pytest.mark.xdist_group("z3-suite")
def test_time_normalisation_control_is_a_negative_period():
    from testkit import proved

    r = proved(LEMMAS["wang2020_time_normalisation"], timeout_s=10)
    assert r.negative_control["counterexample"]["T"] < 0


# ------------------------------------------------------------------------ monitors

def _trace(cells_nexts, poses=None, extra=None, ids=None):
    """A trace of grid states: one (cell, next) list per recorded step; poses at cell * 0.2."""
    states, ps = [], []
    for k, row in enumerate(cells_nexts):
        st = []
        for i, (c, n) in enumerate(row):
            keys = [("cell", c), ("next", n), ("goal", c), ("priority", (c[0] * 0.2, c[1] * 0.2))]
            keys += list((extra or {}).get((k, i), ()))
            st.append(tuple(keys))
        states.append(tuple(st))
        ps.append([[0.2 * c[0], 0.2 * c[1], 0.0] for c, _ in row])
    return Trace(ids=ids or list(range(1, len(cells_nexts[0]) + 1)),
                 poses=np.array(ps if poses is None else poses, dtype=float), states=states)


GOOD = [[((0, 0), None), ((1, 0), None), ((0, 1), None)],
        [((0, 0), (-1, 0)), ((1, 0), (2, 0)), ((0, 1), None)],
        [((0, 0), (-1, 0)), ((1, 0), (2, 0)), ((0, 1), (0, 0))]]   # 3 follows 1 into (0, 0)


def test_claims_monitor_quiet_on_distinct_claims_and_a_follower():
    r = grid.grid_claims_distinct(_trace(GOOD))
    assert r.status == "held" and r.detail["checked"] == 9


@pytest.mark.parametrize("row, kind, robots", [
    ([((0, 0), (1, 1)), ((1, 0), (1, 1)), ((0, 1), None)], "shared_claim", [1, 2]),
    ([((0, 0), (0, 1)), ((1, 0), None), ((0, 1), None)], "shared_claim", [1, 3]),
    ([((0, 0), None), ((0, 0), None), ((0, 1), None)], "shared_cell", [1, 2]),
    ([((0, 0), (1, 0)), ((1, 0), (0, 0)), ((0, 1), None)], "edge_swap", [1, 2]),
], ids=["two-to-one-waypoint", "onto-a-resting-robot", "one-cell", "swap"])
def test_claims_monitor_fires(row, kind, robots):
    r = grid.grid_claims_distinct(_trace([GOOD[0], row]))
    assert r.status == "violated" and r.witness["kind"] == kind and r.witness["robots"] == robots
    lemma = "wang2020_theorem_iv_a_2" if kind == "edge_swap" else "wang2020_separation_equal_speeds"
    assert r.witness["step"] == 1 and r.witness["lemma"] == lemma


def test_grid_monitors_without_their_keys_are_inconclusive():
    poses = np.zeros((2, 1, 3))
    tr = Trace(ids=[1], poses=poses, states=[((("goal", (0, 0)),),)] * 2)
    for fn in (grid.grid_claims_distinct, grid.grid_waited_window):
        assert fn(tr).status == "inconclusive"
    assert grid.grid_priorities_distinct(tr, 0.6).status == "inconclusive"
    assert grid.grid_heard_neighbours(tr, 0.6).status == "inconclusive"
    assert grid.grid_spacing_of_trace(tr, 0.6).status == "inconclusive"


def test_priorities_monitor():
    assert grid.grid_priorities_distinct(_trace(GOOD), 0.6).status == "held"
    tr = _trace(GOOD)
    states = [tuple(tuple(kv for kv in st if kv[0] != "priority") + (("priority", (9, 9)),) for st in row)
              for row in tr.states]
    tr = Trace(ids=[1, 2, 3], poses=tr.poses, states=states)
    r = grid.grid_priorities_distinct(tr, 0.6)
    assert r.status == "violated" and r.witness["robots"] == [1, 2] and r.witness["step"] == 0
    assert r.witness["premise"] == "distinct_priorities" and r.witness["lemma"] == "wang2020_planner_vertex_one_moment"
    # the same priorities out of range R are no conflict: no pair within R, so nothing was checked
    # (a monitor derived from a lemma calls that vacuous: inconclusive for the run, never violated)
    far = grid.grid_priorities_distinct(tr, 0.1)
    assert far.status == "inconclusive" and not far.applicable and far.detail["vacuous"]


def test_spacing_bound_at_sec_v_values_and_just_outside():
    assert grid.grid_spacing_bound(0.20, 0.05, 0.6).status == "held"
    low = grid.grid_spacing_bound(0.99 * 2 * math.sqrt(2) * 0.05, 0.05, 0.6)
    assert low.status == "violated" and low.witness["bound"] == "l >= 2 sqrt(2) r"
    high = grid.grid_spacing_bound(0.31, 0.05, 0.6)
    assert high.status == "violated" and high.witness["bound"] == "l <= R/2"
    assert grid.grid_spacing_bound(float("nan"), 0.05, 0.6).status == "inconclusive"
    tr = _trace(GOOD)
    tr.meta["params"] = {"range": 0.6, "v": 0.05, "dt": 1.0, "extra": {"grid_spacing": 0.2, "robot_radius": 0.05}}
    assert grid.grid_spacing_of_trace(tr, 0.6).status == "held"


def test_spacing_bound_adds_sec_v_b3_where_the_speeds_differ():
    """Sec. III-A's bounds stay; with speeds in [v_min, v_max], v_min < v_max, Sec. V-B3's
    l >= 2 r sqrt(v_max^2 + v_min^2) / v_min too (r = 0.05, l = 0.2: held for v_min / v_max >=
    1 / sqrt 3); equal speeds check Sec. III-A only (V-B3's bound is then 2 sqrt(2) r)."""
    at_bound = 0.05 / math.sqrt(3)
    ok = grid.grid_spacing_bound(0.20, 0.05, 0.6, v_min=at_bound * 1.001, v_max=0.05)
    assert ok.status == "held" and "Sec. V-B3" in ok.message
    slow = grid.grid_spacing_bound(0.20, 0.05, 0.6, v_min=at_bound * 0.99, v_max=0.05)
    assert slow.status == "violated" and slow.witness["bound"] == grid.SPEED_BOUND == (
        "l >= 2 r sqrt(v_max^2 + v_min^2) / v_min")
    assert slow.witness["lemma"] == "wang2020_separation_speeds" and slow.witness["need"] > 0.20
    same = grid.grid_spacing_bound(0.20, 0.05, 0.6, v_min=0.05, v_max=0.05)
    assert same.status == "held" and "V-B3" not in same.message
    # Sec. III-A's bounds come first and are not relaxed by V-B3
    assert grid.grid_spacing_bound(0.31, 0.05, 0.6, v_min=0.04, v_max=0.05).witness["bound"] == "l <= R/2"
    assert grid.grid_spacing_bound(0.20, 0.05, 0.6, v_min=0.0, v_max=0.05).status == "inconclusive"


@pytest.mark.parametrize("speed_min, status", [(0.01, "violated"), (0.02, "held"), (0.04, "held"), (None, "held")],
                         ids=["below-v-b3", "range-below-drawn-within", "within-v-b3", "one-speed"])
def test_spacing_monitor_reads_the_run_speeds(speed_min, status):
    """On a run's trace: the speeds the engine drew (``meta["speeds"]``), only when they differ. The
    premise is about the run's agents: with speed_min = 0.02 the range [0.02, 0.05] breaks V-B3's
    bound (0.269 m; the ``speed_buffer`` assumption says so), the five speeds drawn (0.024-0.035)
    do not (0.180 m). With 0.01 the drawn 0.0148-0.0305 need 0.228 m > l = 0.2."""
    from swarmproof.models.targets import resolve_target
    from swarmproof.reference_impl.engine import simulate
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020, default_params

    import dataclasses

    alg, p = Wang2020(), default_params()
    if speed_min is not None:
        p = dataclasses.replace(p, extra={**p.extra, "speed_min": speed_min, "speed_max": 0.05})
    goals = resolve_target("shape:letter-l")
    r = simulate(alg, goals, alg.initial(5, 0, p, goals), p, seed=0, max_steps=2, allow_violations=True)
    drawn = (r.trace.meta.get("speeds") or {}).get("speed")
    assert (drawn is None) == (speed_min is None)
    res = grid.grid_spacing_of_trace(r.trace, 0.6)
    assert res.status == status, res.message
    assert ("speed_buffer" in r.broken_assumptions) == (speed_min is not None and speed_min < 0.05 / math.sqrt(3))
    if status == "violated":
        assert res.witness["v_min"] == min(drawn) and res.witness["v_max"] == max(drawn)
        assert res.witness["bound"] == grid.SPEED_BOUND


def _timing_trace(waited, heard_by_1, lead=0):
    """GOOD with ``lead`` more waiting frames first (robots 1 and 2 then set off in step ``lead``)."""
    rows = [GOOD[0]] * lead + GOOD
    extra = {}
    for k in range(len(rows)):
        for i in range(3):
            extra[(k, i)] = [("waited", waited if k == lead + 1 and i == 0 else 5.0), ("window", 2.0),
                             ("heard", heard_by_1 if i == 0 else (1, 2, 3))]
    return _trace(rows, extra=extra)


def test_waited_monitor():
    assert grid.grid_waited_window(_timing_trace(2.5, (2, 3))).status == "held"
    r = grid.grid_waited_window(_timing_trace(2.0, (2, 3)))   # not longer than Delta t
    assert r.status == "violated" and (r.witness["robot"], r.witness["step"]) == (1, 0)
    assert r.witness["lemma"] == "wang2020_lemma_iv_a_1"


def test_waited_monitor_is_exact_at_the_window():
    """grid_waited is derived from wang2020_lemma_iv_a_1's premise i_waited_longer_than_window with
    tol = 0: waited == window (line 30's ">" written ">=") fails; one float step above it holds (the
    normalised -2 waited / window stays below -2).  With the lemma's default tolerance the same
    departure at the window would only be a boundary instance."""
    import dataclasses

    window = 1.9999999999999998                           # a mantissa near 2: the closest quotient to 1
    above = float(np.nextafter(window, np.inf))
    assert -2.0 * above / window < -2.0
    tr = _timing_trace(2.5, (2, 3))
    states = [tuple(tuple((k, window if k == "window" else (above if k == "waited" and v != 5.0 else v))
                          for k, v in st) for st in row) for row in tr.states]
    tr = Trace(ids=[1, 2, 3], poses=tr.poses, states=states)
    r = grid.grid_waited_window(tr)
    assert r.status == "held" and r.detail["checked"] == 3
    at = grid.grid_waited_window(_timing_trace(2.0, (2, 3)))
    assert at.status == "violated" and at.witness["premise"] == "i_waited_longer_than_window"
    loose = dataclasses.replace(grid.GRID_WAITED, tol=None).check(_timing_trace(2.0, (2, 3)), 1.0, 0.0, 1.0)
    assert loose.status == "held" and loose.detail["boundary"] == 1


def test_priority_batch_judges_as_its_instances_one_by_one():
    from swarmproof.invariants.lemma_monitor import StepView, judge_batch, judge_instance

    tr = _trace(GOOD)
    states = [tuple(tuple(kv for kv in st if kv[0] != "priority") + (("priority", (9, 9) if i < 2 else (1, 2)),)
                    for i, st in enumerate(row)) for row in tr.states]
    tr = Trace(ids=[1, 2, 3], poses=tr.poses, states=states)
    b = grid.GRID_PRIORITIES
    (batch, _) = list(b.instances(StepView(tr, 0, 0.6, 0.05, 1.0)))     # step 0: the start's state and the next
    kinds = judge_batch(b.lemma, batch, b.given, b.only)
    for i in range(len(batch)):
        one, _ = judge_instance(b.lemma, batch.instance(i), b.given, b.only)
        assert kinds[one][i]
    assert batch.instance(0).key == {"robots": [1, 2]} and list(kinds["failed"]) == [True, False, False]


def test_heard_monitor():
    # two waiting frames first: robot 1 sets off in step 2, its window of 2 steps reads steps 1..2
    assert grid.grid_heard_neighbours(_timing_trace(3.0, (2, 3), lead=2), 0.6).status == "held"
    r = grid.grid_heard_neighbours(_timing_trace(3.0, (2,), lead=2), 0.6)
    assert r.status == "violated" and r.witness["unheard"] == [3] and r.witness["robot"] == 1
    assert r.witness["step"] == 2 and r.witness["frames"] == [1, 2]
    # robot 3 is 0.2 away: with R = 0.1 it is no neighbour, so nobody is missing
    assert grid.grid_heard_neighbours(_timing_trace(3.0, (2,), lead=2), 0.1).status == "held"
    # setting off in step 0, nothing can have been received yet (nobody broadcast before step 0)
    r0 = grid.grid_heard_neighbours(_timing_trace(3.0, (2,)), 0.6)
    assert r0.status == "held" and r0.detail["checked"] == 3


def test_monitors_registered_with_their_lemmas_and_run_by_check_premises():
    names = ["grid_priorities", "grid_waited"]
    for n in names:
        assert premises.MONITOR_LEMMAS[n] in LEMMAS
    for n in ("grid_claims", "grid_heard", "grid_spacing"):      # properties since issue 32, not monitors
        assert n not in premises.MONITORS
    tr = _timing_trace(3.0, (2, 3))
    out = premises.check_premises(tr, phi=0.6, v=0.05, dt=1.0, monitors=names)
    assert [r.status for r in out] == ["held"] * 2


def _judge(name, tr, streamed=False, phi=0.6):
    """The registered property ``name`` on ``tr``: its check over the whole trace, or its streaming
    monitor fed every step as the engine feeds it."""
    from swarmproof.invariants.registry import PropertyContext, get_property
    from swarmproof.reference_impl.protocol import Params
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020

    prop, params = get_property(name), Params(range=phi, v=0.05)
    if not streamed:
        return prop.check(tr, PropertyContext(Wang2020(), None, params, None))
    mon = prop.stream(Wang2020(), params, {})
    mon.start(tr.ids)
    for t in range(len(tr.poses)):
        mon.observe(t, tr.poses[t], tr.states[t], np.ones(tr.n, dtype=bool))
    return mon.result()


@pytest.mark.parametrize("streamed", [False, True], ids=["trace", "streamed"])
def test_grid_claims_property_fires_on_a_bad_trace_and_is_quiet_on_a_good_one(streamed):
    good = _judge("grid_claims", _trace(GOOD), streamed)
    assert good.name == "grid_claims" and good.status == "held" and good.detail["checked"] == 9
    bad = _judge("grid_claims", _trace([GOOD[0], GOOD[1], [((0, 0), (1, 1)), ((1, 0), (1, 1)), ((0, 1), None)]]),
                 streamed)
    assert bad.status == "violated" and bad.witness["step"] == 2 and bad.witness["kind"] == "shared_claim"
    swap = _judge("grid_claims", _trace([GOOD[0], [((0, 0), (1, 0)), ((1, 0), (0, 0)), ((0, 1), None)]]), streamed)
    assert swap.status == "violated" and swap.witness["kind"] == "edge_swap" and swap.witness["robots"] == [1, 2]


@pytest.mark.parametrize("streamed", [False, True], ids=["trace", "streamed"])
def test_grid_heard_property_fires_on_a_bad_trace_and_is_quiet_on_a_good_one(streamed):
    good = _judge("grid_heard", _timing_trace(3.0, (2, 3), lead=2), streamed)
    assert good.name == "grid_heard" and good.status == "held" and good.detail["checked"] > 0
    bad = _judge("grid_heard", _timing_trace(3.0, (2,), lead=2), streamed)
    assert bad.status == "violated" and bad.witness["unheard"] == [3] and bad.witness["robot"] == 1
    assert bad.witness["step"] == 2 and bad.witness["frames"] == [1, 2]


def test_grid_spacing_property_fires_on_bad_parameters_and_is_quiet_on_the_papers():
    tr = _trace(GOOD)
    tr.meta["params"] = {"range": 0.6, "v": 0.05, "dt": 1.0, "extra": {"grid_spacing": 0.2, "robot_radius": 0.05}}
    good = _judge("grid_spacing", tr)
    assert good.name == "grid_spacing" and good.status == "held"
    tr.meta["params"]["extra"]["grid_spacing"] = 0.12
    bad = _judge("grid_spacing", tr)
    assert bad.status == "violated" and bad.witness["bound"] == "l >= 2 sqrt(2) r"
    assert _judge("grid_spacing", _trace(GOOD)).status == "inconclusive"      # no parameters recorded


def test_swarmproof_prove_runs_the_speed_buffer_lemma_and_lists_both(capsys):
    from swarmproof.cli import main

    code = main(["prove", "wang2020_speed_buffer_v_b3_cases", "--json"])
    doc = json.loads(capsys.readouterr().out)
    (lem,) = doc["lemmas"]
    assert code == 0 and lem["id"] == "wang2020_speed_buffer_v_b3_cases" and lem["status"] == "proved"
    assert lem["premises_satisfiable"] is True and lem["negative_control"]["status"] == "counterexample"
    assert {"wang2020_speed_buffer_v_b3_cases", "wang2020_separation_speeds"} <= {x.id for x in proofs.lookup()}
