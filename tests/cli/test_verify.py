"""`swarmproof verify`: the lemma and exploration sections through the command line --
exit codes 0/1/2/3, JSON fields, exact human lines, --out, bad input (tiny budgets)."""

from __future__ import annotations

import json
import os

import pytest

from swarmproof.checkers import explore as explore_mod
from swarmproof.checkers import proofs, report
from swarmproof.cli import main
from swarmproof.reference_impl import registry


def run(capsys, *argv):
    code = main(["verify", *argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def small(monkeypatch):
    """Explore only the named algorithms and properties (read at run time by the section)."""
    def set_(algorithms, properties):
        plans = dict(registry.verify_plans())
        monkeypatch.setattr(registry, "verify_plans", lambda: [(a, plans[a]) for a in algorithms])
        monkeypatch.setattr(explore_mod, "explore_properties", lambda algorithm=None: tuple(properties))
    return set_


@pytest.mark.xdist_group("z3-suite")
def test_lemma_section_json_every_lemma_proved_exit_0(capsys, monkeypatch):
    from testkit import proved

    from swarmproof.checkers import proofs as proofs_mod

    # the lemmas' z3 proofs are those of the per-lemma test (tests/checkers/test_proofs.py),
    # run once per worker: this test judges what verify makes of them
    assert proofs_mod.DEFAULT_TIMEOUT_S == 300.0
    monkeypatch.setattr(proofs_mod, "run_suite", lambda ids=None, timeout_s=300.0, rlimit=None: [
        proved(lem, timeout_s) for lem in proofs_mod.lookup(ids)])
    code, out, err = run(capsys, "--section", "lemmas", "--json")
    doc = json.loads(out)
    assert code == 0 and err == ""
    assert [r["subject"] for r in doc["rows"]] == list(proofs.LEMMAS)
    assert {(r["section"], r["property"], r["verdict"], r["premises_satisfiable"]) for r in doc["rows"]} == {
        ("lemmas", "z3 proof", "proved", True)}
    assert all(r["negative_control"]["status"] == "counterexample" for r in doc["rows"])
    assert "seconds" not in doc and not any("seconds" in r for r in doc["rows"])
    assert doc["counts"] == {"proved": len(proofs.LEMMAS), "held": 0, "violated": 0, "inconclusive": 0, "n/a": 0}


def test_exploration_held_and_finding_exit_0_exact_lines(capsys, small):
    small(["song2016"], ["connectivity", "collision"])
    code, out, _ = run(capsys, "--section", "exploration", "--max-examples", "10", "--robots", "3..4")
    lines = out.splitlines()
    assert code == 0  # the collision violation is not claimed by 001: a finding, not counted
    assert lines[0].startswith("== exploration (") and lines[0].endswith(" s)")
    assert lines[1:] == [
        "subject          property      verdict       detail",
        "song2016 n=3..4  connectivity  held          held over 10 scenarios, 1040 steps (explored, not proved)",
        "song2016 n=3..4  collision     violated*     4 robots on square: robots 1 and 2 overlap in step 23: "
        "distance 0.1936 < 2r = 0.2 at 1.00 of the step; the file: swarmproof verify --out DIR",
        "",
        "* not claimed by the paper: a finding about the algorithm, not counted in the verdict",
        "verify: HELD (0 proved, 1 held, 1 violated, 0 inconclusive)"]


def test_exploration_claimed_violation_exit_1_and_out_dir(capsys, small, tmp_path):
    small(["song2014"], ["tree_links"])
    out_dir = tmp_path / "cx"
    code, out, err = run(capsys, "--section", "exploration", "--max-examples", "20", "--robots", "4..6",
                         "--json", "--out", str(out_dir))
    doc = json.loads(out)
    assert code == 1 and err == ""
    (row,) = doc["rows"]
    path = str(out_dir / "song2014-tree_links-seed0.json")
    assert (row["verdict"], row["claim"], row["counterexample"]) == (
        "violated", "000 Lemma 7 (a descendant stays within range of its parent)", path)
    assert row["detail"].endswith(f"; replay: swarmproof replay {path}")
    assert os.listdir(out_dir) == ["song2014-tree_links-seed0.json"]
    assert main(["replay", path]) == 1  # the written file reproduces the violation
    capsys.readouterr()


def test_exploration_budget_spent_exit_3(capsys, small, monkeypatch):
    small(["song2016"], ["connectivity"])
    monkeypatch.setattr(report, "VERIFY_EXPLORE_SECTION_BUDGET", 0.0)
    code, out, _ = run(capsys, "--section", "exploration")
    assert code == 3
    assert out.splitlines()[2:] == [
        "song2016 n=3..8  connectivity  inconclusive  not explored: the section's time budget of 0 s was "
        "spent before it",
        "",
        "verify: INCONCLUSIVE (0 proved, 0 held, 0 violated, 1 inconclusive)"]


@pytest.mark.parametrize("argv, match", [
    (["--max-examples", "0"], "--max-examples 0 must be >= 1"),
    (["--robots", "5..3"], "must satisfy 1 <= MIN <= MAX"),
    (["--seed", "-1"], "--seed -1 must be >= 0"),
], ids=["max-examples-zero", "robots-reversed", "seed-negative"])
def test_bad_input_exit_2(capsys, argv, match):
    code, out, err = run(capsys, "--section", "exploration", *argv)
    assert code == 2 and out == ""
    assert match in err and "fix:" in err and "Traceback" not in err


def test_unknown_section_exit_2():
    assert main(["verify", "--section", "proofs"]) == 2


def test_tty_progress_overwrites_one_line():
    import io

    from swarmproof.commands import StatusLine

    buf = io.StringIO()
    show = StatusLine(buf, "verify")
    show.width = 30
    show("lemmas: bounded_range")
    show("exploration: song2014 connectivity: example 3 (max 300 + shrinking)")
    show.clear()
    assert buf.getvalue() == ("\r\x1b[Kverify: lemmas: bounded_range"
                              "\r\x1b[Kverify: exploration: song2014 "
                              "\r\x1b[K")


def test_workers_explore_the_rows_on_dask_processes_with_the_same_rows(capsys, tmp_path):
    """--workers 2: the exploration rows on a local Dask cluster of two processes, and the
    algorithms section as a task on the same cluster, give the JSON and the counterexample files of
    the serial run, byte for byte (rows bounded by example counts)."""
    argv = ["--section", "algorithms", "--section", "exploration", "--algorithm", "song2014",
            "--property", "connectivity",
            "--property", "termination", "--max-examples", "12", "--json"]
    docs, files = [], []
    for w in ("1", "2"):
        out_dir = tmp_path / f"cx{w}"
        code, out, _ = run(capsys, *argv, "--workers", w, "--out", str(out_dir))
        doc = json.loads(out)
        docs.append((code, json.dumps(doc, sort_keys=True).replace(str(out_dir), "OUT")))
        verdicts = {r["property"]: r["verdict"] for r in doc["rows"] if r["section"] == "exploration"}
        assert {r["section"] for r in doc["rows"]} == {"algorithms", "exploration"}
        files.append({p.name: p.read_bytes() for p in sorted(out_dir.iterdir())})
    assert docs[0] == docs[1]
    assert files[0] == files[1] and files[0]          # song2014 loses connectivity: a counterexample file
    assert verdicts["connectivity"] == "violated"      # song2014's known finding, found by both


@pytest.mark.parametrize("value", ["0", "-2", "many"])
def test_workers_must_be_a_count_or_auto(capsys, value):
    code, _, err = run(capsys, "--section", "exploration", "--workers", value)
    assert code == 2 and "--workers" in err and "Traceback" not in err
