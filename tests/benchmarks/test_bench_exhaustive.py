"""benchmarks/exhaustive: a row of docs/exhaustive.md's jiang table, measured as the script measures
it (the smallest team's break: 4 robots, seed 0, one message 2 steps late), and its table."""

from __future__ import annotations


def test_a_cell_finds_jiang_s_four_robot_break_with_one_deviation_and_it_replays(capsys):
    from testkit import load_benchmark

    bench = load_benchmark("exhaustive/bench_exhaustive")
    row = bench.cell("jiang", "termination", robots=4, seed=0, steps=150, k=1, kinds=("delay",), max_delay=2,
                     target="pattern:rhombus-triangles")
    assert (row["status"], row["deviations"], row["runs"], row["states"], row["replayed"]) == ("violated", 1, 10, 65, True)
    assert row["pruned"] == 0                       # liveness: never pruned
    bench.table([row], "jiang")
    assert "| jiang | termination | 4 | seed 0 | 150 st, K=1, delay, D=2 | off | violated | 1 | 10 | 65 |" in capsys.readouterr().out
