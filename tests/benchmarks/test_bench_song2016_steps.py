"""benchmarks/song2016/bench_song2016_steps.py: every step of a song2016 run is attributed to exactly one
term of Song & O'Kane 2016, Thm. 13's accounting (or a row it does not name), observed from outside."""

from __future__ import annotations

import pytest


def _load():
    from testkit import load_benchmark

    return load_benchmark("song2016/bench_song2016_steps")


B = _load()


@pytest.mark.parametrize("reading", ["song2016", "subtree-clock"])
def test_song2016_step_breakdown_sums_to_the_run(reading):
    n = 5
    r = B.run(n, 0, 0.2, reading=reading)
    assert r["status"] == "finished"
    assert sum(r[t] for t in B.TERMS) == r["steps"]     # every step attributed once
    assert r["relocations"] == n - 1                      # Thm. 13: n - 1 robots relocated
    assert r["first"] == n + 1                            # the trailing O(n): timeout n, then the step it turns stable
    assert r["t_comm"] >= (n - 1) * n                     # Def. 10, timeout = n per relocation (Sec. VI)
    assert r["t_move"] == (0 if reading == "subtree-clock" else (n - 1) * n)   # Sec. VI, timeout = n
    assert r["drive"] > 0 and r["end"] == 0


def test_song2016_paper_accounting_adds_up_to_table_iii():
    for n, total in B.TABLE_III_SQUARE.items():
        a = B.paper_accounting(n)
        assert a["first"] + a["t_comm"] + a["t_move"] + a["wait+drive"] == total
