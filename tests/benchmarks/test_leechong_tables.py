"""benchmarks/leechong/leechong_tables.py: 003's Tables 2-5 as data, the cells that break the paper's claim,
and one cell of the re-run (the full re-run is ``make``-free, by hand; docs/leechong.md)."""

from __future__ import annotations

import os
import re

import pytest

from swarmproof.models.errors import UsageError

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SEED_TEXT = os.path.join(os.path.dirname(ROOT), "shared", "seeds", "003_8f3001202a798af8.txt")


def _load():
    from testkit import load_benchmark

    return load_benchmark("leechong/leechong_tables")


T = _load()


@pytest.mark.skipif(not os.path.exists(SEED_TEXT), reason="the seed paper is not beside the repository")
def test_tables_are_transcribed_exactly_from_the_seed():
    text = open(SEED_TEXT, encoding="utf-8").read()
    for (app, meas), name in T.TABLE_OF.items():
        start = text.index(f"**{name}**")
        rows = {}
        for line in text[start:].splitlines()[1:40]:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if cells and cells[0] in dict(T.PAPER_PATTERNS):
                rows[dict(T.PAPER_PATTERNS)[cells[0]]] = [float(c) for c in cells[1:]]
            if len(rows) == 8:
                break
        assert set(rows) == set(T.PATTERNS), name
        for pat, xs in rows.items():
            assert [x for pair in T.PAPER[app][meas][pat] for x in pair] == xs, (name, pat)


def test_paper_exceptions_are_exactly_the_cells_where_a_is_not_below_f():
    ex = T.paper_exceptions()
    got = [(e["table"], e["pattern"], e["testbed"]) for e in ex]
    assert got == [("Table 3", "three-row", 5), ("Table 3", "wedge", 1), ("Table 3", "wedge", 4),
                   ("Table 3", "wedge", 5), ("Table 3", "arc", 4), ("Table 3", "arc", 5),
                   ("Table 4", "two-column", 3), ("Table 5", "two-column", 3), ("Table 5", "triangle", 5),
                   ("Table 5", "hexagon", 4), ("Table 5", "hexagon", 5)]
    assert all(e["A"] >= e["F"] for e in ex)
    # a brute-force recount over every cell agrees
    count = sum(a >= f for app in T.PAPER.values() for tab in app.values() for cells in tab.values() for a, f in cells)
    assert count == len(ex)
    assert T.paper_mean_exceptions() == []          # on the per-pattern means the claim holds
    assert len(T.paper_repeated_cells()) == 6


def test_a_planted_exception_is_found():
    tab = {p: tuple((1.0, 2.0) for _ in range(5)) for p in T.PATTERNS}
    assert T.paper_exceptions(tab) == []
    tab["arc"] = ((1.0, 2.0), (3.0, 2.0), (1.0, 2.0), (1.0, 2.0), (1.0, 2.0))
    assert [(e["pattern"], e["testbed"]) for e in T.paper_exceptions(tab)] == [("arc", 2)]


def test_one_cell_of_the_rerun_same_start_for_both_teams():
    a = T.run_cell("leader", "A", "triangle", 5)
    f = T.run_cell("leader", "F", "triangle", 5)
    for r in (a, f):
        assert set(r) >= {"distance", "time", "steps", "satisfied", "status", "algorithm"}
        assert r["time"] == pytest.approx(r["steps"] * 0.5)
        assert r["satisfied"] is True and r["status"] == "finished"
    assert a["algorithm"] == "leechong-leader" and f["algorithm"] == "leechong-leader-fteam"
    assert T.testbed(5).poses.tolist() == T.testbed(5).poses.tolist()
    # the documented finding on this cell: the F-team moves less than the A-team
    assert f["distance"] < a["distance"]
    ex = T.our_exceptions([a, f])
    assert {e["measure"] for e in ex} == {"distance", "time"}


def test_the_printed_neighbor_column_is_the_registered_variant():
    """Issue 31: column A is the default (Sec. 2.1's prose IDs), A-printed the ``-printed`` variant."""
    r = T.run_cell("neighbor", "A-printed", "wedge", 1)
    d = T.run_cell("neighbor", "A", "wedge", 1)
    assert r["algorithm"] == "leechong-neighbor-printed" and r["satisfied"] is False   # testbed 1: the formula's IDs
    assert d["algorithm"] == "leechong-neighbor" and d["satisfied"] is True


@pytest.mark.parametrize("args, match", [
    (("sideways", "A", "wedge", 1), "approach='sideways'"),
    (("leader", "B", "wedge", 1), "column='B'"),
    (("leader", "A", "fan-shape", 1), "pattern='fan-shape'"),
], ids=["approach", "column", "pattern"])
def test_bad_cells_are_usage_errors(args, match):
    with pytest.raises(UsageError, match=match):
        T.run_cell(*args)


def test_markdown_of_the_paper_bolds_the_exceptions():
    md = T.markdown_paper()
    assert "| Wedge | **12.15** | 12.11 |" in md
    assert len(re.findall(r"\*\*[0-9.]+\*\*", md)) == len(T.paper_exceptions())


def test_main_rejects_bad_arguments(capsys):
    assert T.main(["--testbeds", "9", "--paper-only"]) == 2
    assert "testbeds=9" in capsys.readouterr().err
    assert T.main(["--patterns", "blob", "--paper-only"]) == 2
    assert T.main(["--paper-only"]) == 0
    assert "Table 3 (leader, time): wedge, testbed-1: A 12.15 vs F 12.11" in capsys.readouterr().out


@pytest.mark.parametrize("name", ["leechong/leechong_tables", "leechong/leechong_figures"])
def test_the_benchmark_modules_doctests(name):
    """tests/test_doctests.py covers the swarmproof packages only; the two scripts' examples here."""
    import doctest

    from testkit import load_benchmark

    mod = load_benchmark(name)
    res = doctest.testmod(mod, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert res.attempted >= 5 and res.failed == 0
