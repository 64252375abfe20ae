"""The centralized method 004 compares against ([12], Yu & LaValle 2013) and the Fig. 10-12 trial
runner (reference_impl/wang2020/experiments.py)."""

from __future__ import annotations

import numpy as np
import pytest

from swarmproof.models.assignment import optimal_assignment
from swarmproof.models.errors import UsageError
from swarmproof.models.shapes import centered_arena, random_shape, random_start_cells
from swarmproof.reference_impl.wang2020.experiments import centralized_schedule, shortest_path


def _check_schedule(starts, goals, s):
    """Every step: distinct cells, each agent stays or moves one grid edge, no two agents swap
    across an edge; at the end every goal is occupied."""
    pos = s.positions
    assert pos[0] == [tuple(c) for c in starts]
    moves = 0
    for a, b in zip(pos, pos[1:]):
        assert len(set(b)) == len(b), "two agents on one vertex"
        where = {c: k for k, c in enumerate(a)}
        for k, (u, v) in enumerate(zip(a, b)):
            d = abs(u[0] - v[0]) + abs(u[1] - v[1])
            assert d in (0, 1)
            moves += d
            if d and v in where and where[v] != k:
                j = where[v]
                assert b[j] != u, f"agents {k} and {j} swap across an edge"
    assert set(pos[-1]) == {tuple(g) for g in goals}
    assert moves == s.total_cells
    assert len(pos) == s.steps + 1


@pytest.mark.parametrize("seed", range(6))
def test_random_instances_are_optimal_collision_free_and_within_the_bound(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 60))
    goals = sorted(random_shape(n, rng).cells)
    starts = random_start_cells(n, centered_arena(goals, 12), rng)
    s = centralized_schedule(starts, goals, keep_positions=True)
    _check_schedule(starts, goals, s)
    assert s.total_cells == s.optimal_cells == optimal_assignment(starts, goals).cells
    assert s.steps <= s.bound_steps                     # [12]: |A| + d_max - 1
    assert s.reached[-1] == n and s.travelled[-1] == s.total_cells
    assert all(x <= y for x, y in zip(s.travelled, s.travelled[1:]))


def test_train_and_handoff():
    # a column of agents that must pass through goals already occupied at the start
    starts = [(0, 0), (0, 1), (0, 2)]
    goals = [(0, 2), (0, 3), (0, 4)]
    s = centralized_schedule(starts, goals, keep_positions=True)
    _check_schedule(starts, goals, s)
    assert s.total_cells == 6 and s.steps == 2             # the column moves as a train
    starts = [(0, 0), (1, 0)]
    goals = [(1, 0), (2, 0)]
    s = centralized_schedule(starts, goals, goal_of=[1, 0], keep_positions=True)
    _check_schedule(starts, goals, s)
    assert s.total_cells == 2                              # 0 -> (2, 0) through (1, 0): the rest handed over
    assert s.handoffs == 1


def test_everyone_already_home():
    s = centralized_schedule([(0, 0), (0, 1)], [(0, 1), (0, 0)])
    assert (s.steps, s.bound_steps, s.total_cells, s.reached) == (0, 0, 0, [2])


def test_shortest_path_is_x_then_y():
    assert shortest_path((2, 2), (0, 3)) == [(1, 2), (0, 2), (0, 3)]
    assert len(shortest_path((-3, 5), (4, -1))) == 13


@pytest.mark.parametrize("starts, goals, kw, match", [
    ([(0, 0), (0, 0)], [(1, 0), (2, 0)], {}, "start_cells has a repeated cell"),
    ([(0, 0)], [(1, 0), (2, 0)], {}, "start_cells has 1 cells and goal_cells 2"),
    ([(0, 0), (1, 0)], [(3, 0), (4, 0)], {"goal_of": [0, 0]}, r"goal_of=\[0, 0\] is not a permutation"),
], ids=["repeated-start", "sizes-differ", "goal-of-not-permutation"])
def test_bad_input(starts, goals, kw, match):
    with pytest.raises(UsageError, match=match):
        centralized_schedule(starts, goals, **kw)


def test_a_non_optimal_assignment_with_crossing_paths_is_refused():
    # agent 0 at (0, 0) -> (3, 0), agent 1 at (3, 0)... walk through each other's start in
    # opposite directions: the induced vertex order has a cycle
    with pytest.raises(UsageError, match="cyclic vertex order"):
        centralized_schedule([(0, 0), (3, 0)], [(0, 0), (3, 0)], goal_of=[1, 0])


# -- the decentralized trial runner ---------------------------------------------------------------

def test_wang_trial_stops_when_formed_and_measures_the_distance():
    from swarmproof.reference_impl.wang2020.experiments import start_cells, wang_trial

    rng = np.random.default_rng(3)
    goals = random_shape(9, rng)
    starts = start_cells(goals.cells, 9, rng, arena=6)
    w = wang_trial(goals, starts, 3, every=5)
    r = w["result"]
    assert w["status"] == "stopped" and w["formed_step"] == w["steps"]
    assert goals.satisfied(r.final_ids, r.final_poses).status == "held"
    edges = w["distance_m"] / 0.2                 # every agent rests at the end: whole edges
    assert abs(edges - round(edges)) < 1e-6 and round(edges) >= optimal_assignment(starts, sorted(goals.cells)).cells
    steps = [s for s, _, _ in w["series"]]
    assert steps[0] == 0 and steps[-1] == w["steps"] and w["series"][-1][1] == 9
    assert all(b[2] >= a[2] for a, b in zip(w["series"], w["series"][1:]))
    assert w["formed_s"] == pytest.approx(w["steps"] * 0.1)


def test_sparse_grid_trace_keeps_edge_events_but_not_their_frames():
    from swarmproof.reference_impl.wang2020.experiments import start_cells, wang_trial

    rng = np.random.default_rng(4)
    goals = random_shape(9, rng)
    starts = start_cells(goals.cells, 9, rng, arena=6)
    w = wang_trial(goals, starts, 4, record_every=50)
    tr = w["result"].trace
    assert any(e.kind == "edge" for e in tr.events)
    assert all(t % 50 == 0 or t == w["steps"] for t in tr.times)


# -- the per-robot hot path: traces pinned to the implementation before it was optimised.  First
# pinned at 13d8e4b; re-pinned at f6c6410 (main just before the optimisation was merged), whose engine
# lets grid robots exactly R apart hear each other (inclusive rounding) and whose states carry the
# premise monitors' keys: the optimised code gives these same traces bit for bit.  Since 0.3.0
# (issue 30) that reading is ``wang2020-broadcast-handshake``: the variant gives the old default's
# traces bit for bit (a700a8c; then its states gained the key ``took``, the same steps and statuses,
# re-pinned).  ``PINNED_DEFAULT``: the default's (reading "2") at the commit that made it.

PINNED = {
    (12, 0, True, True): ("finished", 544, "b36c6882e8efec7acf9920c11438b34788b1dd3e02d5d55fdd9f55da09424f72"),
    (20, 1, False, False): ("finished", 276, "e7b90e86cabdaecc9ef158b36879f727e4554f65d2352129afa2903f50e7e1ec"),
    (16, 2, True, False): ("finished", 869, "01f2a1acef6502ef8f99ae77cd56cc3f1d4e188f870159a4f9860a3c68a05229"),
}
PINNED_DEFAULT = {
    (12, 0, True, True): ("finished", 505, "7f332908ec13a49dfe998616538dc20fa0110482f1724b6e0bc4b3dcc129413d"),
    (20, 1, False, False): ("finished", 276, "590a11acb4516bdbcb2b21c4644916ef80c59affd83dbb85e389a074bc964dfd"),
    (16, 2, True, False): ("finished", 462, "40ee76257b3c5ca9fd4be84ccad818379d5f32507ce0d5f0306662dffa2348d7"),
}


@pytest.mark.parametrize("reading", ["broadcast-handshake", "default"])
@pytest.mark.parametrize("case", list(PINNED), ids=lambda c: f"n={c[0]}-seed={c[1]}-then={c[2]}-msgs={c[3]}")
def test_wang2020_traces_unchanged_by_the_faster_hot_path(case, reading):
    import importlib.util
    import pathlib

    from swarmproof.models.shapes import shape_for
    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.engine import simulate
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020, Wang2020BroadcastHandshake

    root = pathlib.Path(__file__).resolve().parents[2]
    spec = importlib.util.spec_from_file_location("trace_hashes", root / "benchmarks" / "trace_hashes.py")
    th = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(th)
    n, seed, then, msgs = case
    rng = np.random.default_rng(seed)
    goals = random_shape(n, rng)
    cells = random_start_cells(n, centered_arena(goals.cells, 8), rng)
    init = InitialConfiguration(list(range(n)), [[0.2 * x, 0.2 * y, 0.0] for x, y in cells])
    cls = Wang2020 if reading == "default" else Wang2020BroadcastHandshake
    alg = cls(then=shape_for("letter-u", n) if then else ())
    r = simulate(alg, goals, init, alg.default_params(0.6, n), seed=seed, record_messages=msgs)
    assert (r.status, r.steps, th.digest(r)) == (PINNED_DEFAULT if reading == "default" else PINNED)[case]


def test_bench_script_tables_and_plots_a_tiny_fig10_and_fig12(tmp_path, capsys):
    import json

    from testkit import load_benchmark

    bench = load_benchmark("wang2020/bench_wang2020")
    log = tmp_path / "t.jsonl"
    out = bench.fig10([4, 6], 1, str(tmp_path / "f10.png"), jsonl=str(log))
    assert [r["n"] for r in out["rows"]] == [4, 6] and (tmp_path / "f10.png").stat().st_size > 0
    assert len(log.read_text().splitlines()) == 2
    for r in out["rows"]:
        assert r["central_distance_m"] <= r["distance_m"] + 1e-9        # the optimum is a lower bound
        assert r["central_s"] <= r["central_bound_s"]
    again = bench.fig10([4, 6], 1, None, jsonl=str(log), run=False)     # read back, not re-run
    assert json.dumps(again["rows"], sort_keys=True) == json.dumps(out["rows"], sort_keys=True)
    assert "| 4 | 1 |" in capsys.readouterr().out        # n, trials (this 4-agent trial ends unformed: the early-detection finding)
    res = bench.fig12(5, 1, str(tmp_path / "f12.png"))
    assert len(res["ours_formed_s"]) == 1 and (tmp_path / "f12.png").stat().st_size > 0
    # the centralized schedule's curve never falls; its start is the share of agents starting on goals
    assert res["central_curve"]["monotone"] and res["central_curve"]["largest_drop_pct"] == 0.0
    assert res["ours_curve"]["start_pct"] == res["central_curve"]["start_pct"]
    # a trial recorded before the random-assignment columns gets them from its instance on reading
    old_row = dict(out["rows"][1])
    for k in ("random_assignment_m", "random_ratio", "arena"):
        old_row.pop(k)
    log.write_text(json.dumps(old_row) + "\n")
    back = bench.fig10([6], 1, None, jsonl=str(log), run=False)["rows"][0]
    assert back["random_ratio"] == out["rows"][1]["random_ratio"]
    other = tmp_path / "a64.jsonl"
    other.write_text(json.dumps(dict(out["rows"][1], arena=64)) + "\n")
    with pytest.raises(SystemExit, match="use one file per arena"):
        bench.fig10([6], 1, None, jsonl=str(other), run=False)


def test_bench_fig9_draws_a_run_whose_n_never_formed_on_ns_goals(tmp_path):
    """A Fig. 9 run cut before "N" is detected complete (the 1,024-agent run) is drawn on N's goals
    with the number held; the count agrees with the run's own progress observer."""
    from testkit import load_benchmark

    bench = load_benchmark("wang2020/bench_wang2020")
    png = tmp_path / "f9.png"
    out = bench.fig9(30, 0, str(png), 200, arena=8)
    assert out["status"] == "step_cap" and out["N_detected_s"] is None
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    r = bench.fig9_run(30, 0, arena=8, max_steps=200)
    gN, _ = r["_goals"]
    held = bench._goals_held(r["_final"], gN)
    assert 0 < held < len(gN)
    # an agent between two cells holds none; one on a goal holds it
    assert bench._goals_held([[gN[0][0] * 0.2, gN[0][1] * 0.2], [gN[1][0] * 0.2 + 0.1, gN[1][1] * 0.2]], gN) == 1


def test_fig10_task_gives_the_bench_trial_s_figures_and_the_random_assignment_baseline():
    """fig10_task (a campaign's experiment ``fig10``) gives the figures the benchmark recorded for
    the same trial (benchmarks/wang2020/results/fig10-default.jsonl, n = 16, seed 0), plus the
    arena's random-assignment baseline (bench_wang2020_ratio.costs); the benchmark's trial is it
    with the timing fields."""
    import json
    import pathlib

    from testkit import load_benchmark

    from swarmproof.reference_impl.wang2020.experiments import EDGE_S, GRID_LENGTH, fig10_instance, fig10_task

    bench = load_benchmark("wang2020/bench_wang2020")
    assert (GRID_LENGTH, EDGE_S) == (bench.L, bench.EDGE_S)
    got = fig10_task(16, 0)
    jsonl = pathlib.Path(__file__).resolve().parents[2] / "benchmarks/wang2020/results/fig10-default.jsonl"
    want = next(r for r in map(json.loads, jsonl.read_text().splitlines()) if (r["n"], r["seed"]) == (16, 0))
    shared = ("status", "formed_s", "steps", "distance_m", "central_distance_m", "central_s", "central_bound_s",
              "ratio")
    assert {k: got[k] for k in shared} == {k: want[k] for k in shared}
    assert got["formed_s"] is not None and got["ratio"] > 1
    goals, starts = fig10_instance(16, 0)
    opt, rand = load_benchmark("wang2020/bench_wang2020_ratio").costs(starts, sorted(goals.cells))
    assert got["central_distance_m"] == opt * GRID_LENGTH
    assert got["random_assignment_m"] == rand * GRID_LENGTH
    assert got["random_ratio"] == got["random_assignment_m"] / got["central_distance_m"]
    assert set(got) == set(shared) | {"random_assignment_m", "random_ratio"}
    assert all(v is None or isinstance(v, (int, float, str)) for v in got.values())


def test_fig10_task_declares_its_option_and_sizes():
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020, Wang2020BroadcastHandshake
    from swarmproof.reference_impl.wang2020.experiments import fig10_task

    decl = fig10_task.experiment
    assert [(s.name, s.default, s.low, s.high) for s in decl.options] == [("arena", 32, 1, 1024)]
    assert decl.robots == (1, 4096) and decl.plot == ("ratio", "random_ratio")
    decl.check(1024, arena=32)
    with pytest.raises(UsageError, match=r"robots=1025 is more than the arena=32x32 holds \(1024 start cells\); "
                                         r"fix: give at most 1024 robots, or a larger arena \(options: \{arena: 33\}\)"):
        decl.check(1025, arena=32)
    assert Wang2020.experiments == {"fig10": "swarmproof.reference_impl.wang2020.experiments:fig10_task"}
    assert "experiments" not in vars(Wang2020BroadcastHandshake)     # runs the default reading: not its own
