"""benchmarks/recorded/bench_check_run.py: the generated log is deterministic, time-ordered and a
held formation, and a measurement reads and judges it as the script does (a small size)."""

from __future__ import annotations


def test_the_generated_log_is_seeded_ordered_and_a_connected_formation(tmp_path):
    from testkit import load_benchmark

    bench = load_benchmark("recorded/bench_check_run")
    rows = list(bench.samples(9, 0.1, 10.0, seed=0, parents=True))
    assert rows == list(bench.samples(9, 0.1, 10.0, seed=0, parents=True))
    assert len(rows) == 9 * 60
    times = [r[0] for r in rows]
    assert times == sorted(times) and times[0] > bench.EPOCH_NS
    for rid in range(9):
        mine = [r[0] for r in rows if r[1] == rid]
        assert len(mine) == 60 and all(a < b for a, b in zip(mine, mine[1:]))
    assert {r[5] for r in rows if r[1] == 0} == {None} and {r[5] for r in rows if r[1] == 4} == {3}

    paths = bench.write_logs(str(tmp_path), ["csv"], 9, 0.1, 10.0, 0, True)
    out = bench.measure("check", paths["csv"], 0.01, traced=False)
    assert (out["format"], out["samples"], out["messages"], out["robots"]) == ("csv", 540, 540, 9)
    assert out["verdicts"] == {"connectivity": "held", "collision": "held"}
    assert out["sensitive"] == {"connectivity": False, "collision": False}
