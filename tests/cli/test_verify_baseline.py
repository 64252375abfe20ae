"""`swarmproof verify --baseline` (issue 14): the CI gate through the command line.

Writing and reading a baseline, exit codes 0/1/2/3, the summary line, bad baselines and output
paths (exit 2, nothing written), `--algorithm module:Class`, and the mutation test of the issue's
"Must hold": a copy of song2016 whose robots treat their children as none (NCLB no longer
constrains the parent) regresses the connectivity and tree-link rows of the shipped baseline, with
a counterexample that replays (slow suite since issue 29: about a minute of CPU).  The whole gate (`make verify` on a fresh clone, minutes) is in
the slow suite (tests/cli/test_verify_gate_slow.py).
"""

from __future__ import annotations

import json
import os
import re

import pytest

from swarmproof.cli import main

from testkit import MUTANT, ROOT, SHIPPED, write_mutant


def run(capsys, *argv):
    code = main(["verify", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_update_then_compare_round_trips_byte_identical(capsys, tmp_path):
    b = tmp_path / "b.json"
    code, out, _ = run(capsys, "--section", "lattices", "--baseline", str(b), "--update-baseline")
    assert code == 0 and out.splitlines()[-1] == f"verify: baseline written to {b} (8 rows)"
    first = b.read_bytes()
    code, out, _ = run(capsys, "--section", "lattices", "--baseline", str(b))
    assert code == 0
    assert out.splitlines()[-1] == f"verify: PASS: 0 regressions, 0 known findings, 0 improvements, 8 held (against {b})"
    code, out, _ = run(capsys, "--section", "lattices", "--baseline", str(b), "--update-baseline")
    assert out.splitlines()[-1] == f"verify: baseline written to {b} (8 rows; 0 differed from the previous one)"
    assert b.read_bytes() == first
    code, out, _ = run(capsys, "--section", "lattices", "--baseline", str(b), "--json")
    doc = json.loads(out)
    assert doc["exit_code"] == 0 and doc["baseline"]["counts"]["same"] == 8
    assert {r["baseline"] for r in doc["rows"]} == {"same"}


def test_a_gone_row_warns_and_strict_makes_it_an_error(capsys, tmp_path):
    b = tmp_path / "b.json"
    run(capsys, "--section", "lattices", "--baseline", str(b), "--update-baseline")
    doc = json.loads(b.read_text())
    doc["rows"].append({"section": "lattices", "subject": "retired-lattice", "property": "valid and self-consistent",
                        "verdict": "held", "claim": None})
    b.write_text(json.dumps(doc))
    code, out, _ = run(capsys, "--section", "lattices", "--baseline", str(b))
    assert code == 0
    assert "-- GONE (in the baseline, not produced by this run)" in out
    assert "  lattices: retired-lattice / valid and self-consistent: " in out
    assert out.splitlines()[-1].endswith("8 held; 1 baseline row gone (against %s)" % b)
    code, out, err = run(capsys, "--section", "lattices", "--baseline", str(b), "--strict")
    assert code == 2
    assert "1 row(s) of --baseline" in err and "retired-lattice" in err and "fix: rewrite the baseline" in err
    assert "Traceback" not in err


@pytest.mark.parametrize("content, match", [
    (json.dumps({"format": "swarmproof-baseline/2", "rows": []}),
     "format='swarmproof-baseline/2' is not 'swarmproof-baseline/1'"),
    ('{"format": "swarmproof-baseline/1", "rows": [', "the baseline is not JSON"),
    (json.dumps({"format": "swarmproof-baseline/1", "rows": [{"section": "lattices"}]}),
     "rows[0].subject=None is not a string"),
], ids=["other-version", "corrupted", "bad-row"])
def test_bad_baselines_exit_2_before_running(capsys, tmp_path, content, match):
    b = tmp_path / "b.json"
    b.write_text(content)
    code, out, err = run(capsys, "--section", "lattices", "--baseline", str(b))
    assert code == 2 and out == "" and "Traceback" not in err
    assert match in err and "fix: " in err and str(b) in err


@pytest.mark.parametrize("argv, match", [
    (["--junit", "{tmp}/no/such/dir/j.xml"], "--junit="),
    (["--html", "{tmp}"], "--html="),
    (["--markdown", "{tmp}/missing/m.md"], "--markdown="),
    (["--baseline", "{tmp}/missing/b.json", "--update-baseline"], "--baseline="),
    (["--update-baseline"], "--update-baseline needs --baseline FILE"),
    (["--strict"], "--strict needs --baseline FILE"),
    (["--algorithm", "no_such_module:Algo"], "algorithm='no_such_module:Algo' cannot be imported"),
    (["--algorithm", "song2016", "--algorithm", "song2016"], "another --algorithm already has the name 'song2016'"),
    (["--property", "speed"], "--property 'speed' is not a property of verify's rows"),
], ids=["junit-folder-missing", "html-is-a-folder", "markdown-folder-missing", "baseline-unwritable",
        "update-without-baseline", "strict-without-baseline", "unknown-algorithm", "same-algorithm-twice",
        "unknown-property"])
def test_bad_options_exit_2_and_write_nothing(capsys, tmp_path, argv, match):
    argv = [a.format(tmp=tmp_path) for a in argv]
    before = sorted(os.listdir(tmp_path))
    code, out, err = run(capsys, "--section", "lattices", *argv)
    assert code == 2 and match in err and "fix: " in err and "Traceback" not in err, err
    assert sorted(os.listdir(tmp_path)) == before


def test_gate_parameters_come_from_the_baseline(capsys, tmp_path):
    b = tmp_path / "b.json"
    b.write_text(json.dumps({"format": "swarmproof-baseline/1", "gate": {"max_examples": 300, "robots": [3, 8],
                                                                          "seed": 0}, "rows": []}))
    code, _, err = run(capsys, "--section", "lattices", "--baseline", str(b), "--max-examples", "5")
    assert code == 2
    assert "--max-examples 5 differs from the baseline's gate (max_examples=300" in err


def test_shipped_baseline_is_current_and_records_versions():
    doc = json.load(open(SHIPPED, encoding="utf-8"))
    assert doc["format"] == "swarmproof-baseline/1"
    assert doc["gate"] == {"max_examples": 300, "robots": [3, 8], "seed": 0}
    assert set(doc["made_by"]) == {"swarmproof", "python", "numpy", "z3"}
    rows = {(r["section"], r["subject"], r["property"]): r for r in doc["rows"]}
    # the known findings the gate stays green on, each with its citation and signature
    assert rows[("exploration", "song2014 n=3..8", "tree_links")]["verdict"] == "violated"
    assert rows[("algorithms", "song2016 square n=20", "tree_links")]["signature"]["kind"] == \
        "the link child # -> parent # broke"
    assert rows[("algorithms", "song2016-literal hexagon n=40", "termination")]["verdict"] == "violated"
    # every registered reading of song2016 has the default's algorithms rows, the one-step lag included
    for name in ("song2016", "song2016-subtree-clock"):
        assert rows[("algorithms", f"{name} square n=20", "tree_links")]["verdict"] == "violated"
        assert rows[("algorithms", f"{name} hexagon n=10", "formation")]["verdict"] == "held"
    assert doc["readings"]["song2016-subtree-clock"] == "1"
    assert rows[("exploration", "song2016 n=3..8", "connectivity")]["verdict"] == "held"
    assert all(r["claim"] or r["verdict"] != "violated" or r["section"] in ("algorithms", "exploration", "exhaustive")
               for r in doc["rows"])


# slow by nature (issue 29): the algorithms and exploration rows of a song2016 mutant at the shipped gate's
# example counts (68 s CPU measured, the slowest test of the default suite before); the default suite
# keeps the gate's regression path (tests/checkers/test_baseline.py's outcome table, test_ci_outputs.py's
# regression in JUnit, and this file's --baseline round trips through the command line).
@pytest.mark.slow
def test_mutant_of_song2016_regresses_connectivity_and_tree_links(capsys, tmp_path, monkeypatch):
    """The issue's mutation test, on the rows it names: the shipped baseline, a copy of song2016
    with children treated as none, and replayable counterexamples."""
    write_mutant(tmp_path)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    out_dir = tmp_path / "cx"
    code, out, err = run(capsys, "--algorithm", f"{MUTANT}:Song2016", "--baseline", SHIPPED,
                         "--section", "algorithms", "--section", "exploration",
                         "--property", "connectivity", "--property", "tree_links", "--out", str(out_dir))
    assert code == 1, out + err
    regressed = out.split("-- REGRESSED (held or proved in the baseline, violated now)")[1].split("\n-- ")[0]
    assert "exploration: song2016 n=3..8 / connectivity: violated [Song & O'Kane 2016, Lemma 11" in regressed
    assert "algorithms: song2016 square n=10 / tree_links: violated" in regressed
    last = out.splitlines()[-1]
    assert last.startswith("verify: FAIL: ") and "regression" in last and last.endswith(f"(against {SHIPPED})")
    files = re.findall(r"replay: swarmproof replay (\S+)", regressed)
    conn = [f for f in files if f.endswith("song2016-connectivity-seed0.json")]
    assert conn, regressed
    assert json.load(open(conn[0]))["algorithm"] == f"{MUTANT}:Song2016"
    assert main(["replay", conn[0]]) == 1                  # the counterexample replays on the mutant
    capsys.readouterr()
