"""Issue 13 item 2 (and DESIGN.md section 5, "Exit codes in practice"): a crash inside the
algorithm under test is a finding -- no_crash, exit 1, a shrunk counterexample that replays to
the same exception -- while a broken protocol (a tuple for a Command, a NaN turn, a dict
state(), a constructor that needs an argument) is the user's contract error: exit 2 naming it.
The user's module sits in the current directory, no PYTHONPATH (as pytest's rootdir)."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data" / "mymod.py"


@pytest.fixture
def here(tmp_path, monkeypatch):
    shutil.copy(DATA, tmp_path / "mymod.py")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", [p for p in sys.path if p not in ("", str(tmp_path))])
    yield tmp_path
    sys.modules.pop("mymod", None)


def test_a_crash_in_the_controller_is_a_shrunk_no_crash_finding_that_replays(cli, here):
    code, out, err = cli("explore", "mymod:Crashy", "--property", "connectivity", "--out", "cx",
                         "--max-examples", "20", "--budget", "none", "--json")
    doc = json.loads(out)
    assert code == 1 and "Traceback" not in err
    crash = doc["properties"]["no_crash"]
    assert crash["status"] == "violated" and crash["robots"] == 3          # shrunk to 3 robots
    assert crash["violation"]["message"].endswith("raised ZeroDivisionError: division by zero in step 3")
    conn = doc["properties"]["connectivity"]
    assert conn["status"] == "inconclusive" and "see no_crash" in conn["message"]
    path = crash["counterexample"]
    assert path.endswith("crashy-no_crash-seed0.json") and json.loads(open(path).read())["property"] == "no_crash"
    code, out, _ = cli("replay", path, "--json")
    rep = json.loads(out)
    assert code == 1 and rep["reproduced"] is True
    assert rep["message"] == rep["recorded_violation"]["message"]                # the same exception
    assert rep["message"].endswith("raised ZeroDivisionError: division by zero in step 3")


def test_explore_by_default_judges_no_crash(cli, here):
    code, out, _ = cli("explore", "mymod:Crashy", "--max-examples", "10", "--budget", "none", "--json")
    doc = json.loads(out)
    assert code == 1 and doc["properties"]["no_crash"]["status"] == "violated"
    assert "no_crash" in doc["properties"]


@pytest.mark.parametrize("cls, match", [
    ("TupleCmd", r"returned \(0.0, 0.1\) at step 0, expected a Command"),
    ("NaNTurn", r"Command turn=nan, forward=0.0 must be finite"),
    ("DictState", r"state\(\) returned an unhashable dict"),
    ("NeedsArg", r"cannot be built without arguments .*missing 1 required positional argument: 'speed'"),
])
def test_a_broken_protocol_is_a_contract_error_exit_2_naming_it(cli, here, cls, match):
    import re

    code, out, err = cli("explore", f"mymod:{cls}", "--property", "connectivity", "--max-examples", "5",
                         "--out", "cx")
    assert code == 2 and "Traceback" not in err and re.search(match, err), err
    assert not (here / "cx").exists()


def test_simulate_takes_module_class_from_the_current_directory_and_reports_a_crash(cli, here):
    code, out, err = cli("simulate", "mymod:Crashy", "--lattice", "square", "--robots", "5", "--seed", "0",
                         "--json")
    doc = json.loads(out)
    assert code == 1 and doc["status"] == "crashed"
    assert doc["crash"]["error"] == "ZeroDivisionError" and doc["crash"]["step"] == 3
    code, out, _ = cli("simulate", "mymod:Crashy", "--lattice", "square", "--robots", "5", "--seed", "0")
    assert "result: the algorithm crashed (a finding)" in out and "raised ZeroDivisionError" in out


def test_an_engine_bug_is_not_blamed_on_the_algorithm(monkeypatch):
    """Only exceptions raised while the algorithm's own code runs are crashes."""
    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.engine import motion, simulate
    from swarmproof.reference_impl.examples.algorithms import GatherToLowestId
    from swarmproof.reference_impl.protocol import Params

    def broken(*a, **k):
        raise RuntimeError("engine bug")
    monkeypatch.setattr(motion.ContinuousMotion, "apply", broken)
    with pytest.raises(RuntimeError, match="engine bug"):
        simulate(GatherToLowestId(), None, InitialConfiguration([0, 1], [[0, 0, 0], [0.5, 0, 0]]),
                 Params(range=1.0), seed=0, max_steps=3)


def test_tree_links_of_an_algorithm_without_a_tree_is_inconclusive_not_held(cli, here):
    """Issue 13 item 7: `explore mymod:CentroidGather --property tree_links` said held, exit 0."""
    # 3-4 robots (issue 29): the verdict is about the algorithm keeping no tree, not the swarm's
    # size; the default 3-8 ran gathers of up to 8 robots (7 s of CPU, now about 3).
    code, out, _ = cli("explore", "mymod:CentroidGather", "--property", "tree_links", "--max-examples", "5",
                       "--robots", "3..4", "--budget", "none", "--json")
    v = json.loads(out)["properties"]["tree_links"]
    assert code == 3 and v["status"] == "inconclusive" and "keeps no spanning tree" in v["message"]
    code, out, _ = cli("simulate", "mymod:CentroidGather", "--lattice", "square", "--robots", "4", "--seed", "0",
                       "--json")
    assert json.loads(out)["tree_links"]["status"] == "inconclusive"


def test_replay_refuses_params_extra_that_simulate_refuses(cli, tmp_path):
    """Issue 13 item 13: the same unknown params.extra key is exit 2 in simulate and in replay."""
    from swarmproof.models.counterexample import Counterexample

    code, _, err = cli("simulate", "song2016", "--lattice", "square", "--robots", "3", "--seed", "0",
                       "--param", "foo=1")
    assert code == 2 and "parameter foo=1 is not known to algorithm 'song2016'" in err
    cx = Counterexample(algorithm="song2016", params={"range": 1.2, "v": 0.05, "omega": 0.785, "dt": 1.0,
                                                      "extra": {"foo": 1}},
                        lattice="square", robots=[(0, (0.0, 0.0, 0.0)), (1, (1.0, 0.0, 0.0))], seed=0,
                        property="connectivity", violation={"step": 1, "message": "x"})
    path = cx.save(tmp_path / "cx.json")
    code, _, err = cli("replay", path)
    assert code == 2 and "parameter foo=1 is not known to algorithm 'song2016'" in err and "field 'params'" in err
