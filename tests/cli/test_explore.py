"""`swarmproof explore`: JSON fields (DESIGN.md section 2), exit codes, counterexample files, bad input."""

from __future__ import annotations

import json
import re
import os

import pytest

from swarmproof.cli import main


def run(capsys, *argv):
    code = main(["explore", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_song2014_connectivity_violated_exit_1_and_file_written(capsys, tmp_path):
    code, out, err = run(capsys, "song2014", "--property", "connectivity", "--budget", "none",
                         "--max-examples", "15", "--robots", "4..6", "--seed", "0", "--json",
                         "--out", str(tmp_path))
    doc = json.loads(out)
    assert code == 1 and doc["algorithm"] == "song2014" and doc["seed"] == 0
    p = doc["properties"]["connectivity"]
    assert p["status"] == "violated" and p["scenarios"] >= 1 and p["steps"] > 0
    assert os.path.exists(p["counterexample"])
    assert "counterexample: song2014 violates connectivity" in err  # human lines go to stderr with --json
    code2 = main(["replay", p["counterexample"]])
    out2, _ = capsys.readouterr()
    assert code2 == 1 and "replay: REPRODUCED (violated)" in out2


def test_broken_assumption_and_drawn_faults_named_in_json(capsys, tmp_path):
    code, out, err = run(capsys, "song2016", "--property", "formation", "--budget", "none", "--max-examples", "10",
                         "--robots", "3..5", "--param", "communication_timeout=1", "--allow-violations",
                         "--fault", "crashes", "--json", "--out", str(tmp_path))
    doc = json.loads(out)
    assert code == 1
    assert doc["broken_assumptions"] == ["communication_timeout_sufficient", "no_crashes"]
    assert doc["properties"]["formation"]["status"] == "violated"
    assert "broken assumptions: communication_timeout_sufficient" in err


def test_speeds_drawn_per_scenario_named_in_output_and_json(capsys):
    code, out, err = run(capsys, "song2016", "--property", "connectivity", "--budget", "none",
                         "--max-examples", "3", "--robots", "3..4", "--speeds", "0.05,0.8")
    assert code == 0
    assert out.splitlines()[0] == ("explore song2016: seed 0, robots 3..4, max 3 examples per property, "
                                   "v drawn from [0.05, 0.8]")
    code, out, err = run(capsys, "song2016", "--property", "connectivity", "--budget", "none",
                         "--max-examples", "3", "--robots", "3..4", "--speeds", "0.05,0.8", "--json")
    assert code == 0 and json.loads(out)["speeds"] == [0.05, 0.8]


def test_song2016_held_exit_0_human_output(capsys):
    code, out, err = run(capsys, "song2016", "--property", "connectivity", "--budget", "none",
                         "--max-examples", "3", "--robots", "3..4")
    assert code == 0
    assert "connectivity  held" in out and "explored, not proved" in out


@pytest.mark.parametrize("argv, match", [
    pytest.param(["song2099"], "algorithm='song2099'.*song2016", id="unknown-algorithm"),
    pytest.param(["song2014", "--property", "speed"], "property='speed'.*connectivity", id="unknown-property"),
    pytest.param(["song2014", "--budget", "0"], "--budget 0.0 must be", id="zero-budget"),
    pytest.param(["song2014", "--budget", "-3"], "--budget -3.0 must be", id="negative-budget"),
    pytest.param(["song2014", "--max-examples", "0"], "--max-examples 0 must be", id="zero-examples"),
    pytest.param(["song2014", "--robots", "3-8"], "--robots '3-8' must be MIN..MAX", id="robots-syntax"),
    pytest.param(["song2014", "--robots", "8..3"], "1 <= MIN <= MAX", id="robots-reversed"),
    pytest.param(["song2014", "--fault", "quake"], "kind='quake'.*schedule", id="unknown-fault"),
    pytest.param(["song2016", "--param", "communication_timeout=1"], "communication_timeout_sufficient.*"
                 "--allow-violations", id="broken-assumption-not-allowed"),
    pytest.param(["song2014", "--max-steps", "0"], "--max-steps 0 must be", id="zero-max-steps"),
    pytest.param(["song2016", "--speeds", "0.05,fast"], r"--speeds '0.05,fast': 'fast' is not a number",
                 id="speeds-not-a-number"),
    pytest.param(["song2016", "--speeds", "0.05,-1"], "speeds contains -1.0", id="speeds-negative"),
    pytest.param(["song2016", "--speeds", "0.05,2"], r"speeds=\[0.05, 2.0\] break the assumptions.*"
                 "--allow-violations", id="speeds-break-assumption"),
    pytest.param(["song2016", "--speeds", "0.4", "--v", "0.05"], "speeds=.* and params v=0.05",
                 id="speeds-and-v"),
])
def test_bad_input_exit_2(capsys, argv, match):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert re.search(match, err), err
    assert "Traceback" not in err


@pytest.mark.slow
def test_same_json_in_a_fresh_process_as_in_process(tmp_path):
    """Determinism across processes: the loaded modules must not change Hypothesis's draws."""
    import subprocess
    import sys

    from swarmproof.checkers.explore import explore

    argv = ["song2014", "--property", "connectivity", "--property", "deadlock", "--budget", "120",
            "--max-examples", "8", "--robots", "3..5", "--seed", "2", "--json"]
    proc = subprocess.run([sys.executable, "-m", "swarmproof.cli", "explore", *argv],
                          capture_output=True, text=True, timeout=200)
    assert proc.returncode in (0, 1), proc.stderr
    doc = json.loads(proc.stdout)
    here = explore("song2014", ["connectivity", "deadlock"], budget=120, max_examples=8, robots=(3, 5), seed=2)
    assert not any(v.budget_hit for v in here.properties.values())
    assert doc["properties"] == json.loads(json.dumps(here.as_dict()["properties"]))


def test_module_qualname_algorithm_and_premises_property(capsys, tmp_path):
    code, out, err = run(capsys, "swarmproof.reference_impl.examples:AnonymousLine", "--property", "premises",
                         "--budget", "10", "--max-examples", "2", "--robots", "3..3", "--json")
    doc = json.loads(out)
    assert code == 3 and doc["algorithm"] == "example-anonymous-line"
    assert doc["algorithm_ref"] == "swarmproof.reference_impl.examples:AnonymousLine"
    # it declares no premise monitors: not applicable (no verdict), and nothing else was asked: exit 3
    assert doc["properties"]["premises"]["status"] == "not_applicable" and doc["premise_lemmas"] == []
    assert doc["properties"]["premises"]["message"] == \
        "not applicable: it declares no lemma premise monitors (premise_monitors)"
    code, out, err = run(capsys, "no_such_pkg:Alg", "--property", "premises")
    assert code == 2 and "algorithm='no_such_pkg:Alg' cannot be imported" in err and "Traceback" not in err
