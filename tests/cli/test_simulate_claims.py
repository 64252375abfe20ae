"""`swarmproof simulate` judges by the algorithm's claims (DESIGN.md section 2): the exit code
follows the claimed properties; unclaimed ones are reported (JSON and text, marked *), not
judged; a property the algorithm cannot give what it needs for says "not applicable"."""

from __future__ import annotations

import json
import sys
import textwrap

import pytest

from swarmproof.cli import main


def run(capsys, *argv):
    code = main(["simulate", *argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def split_start(tmp_path):
    """A connected start of 5 agents on the grid (seeded, 004's R = 0.6 m, l = 0.2 m) from which
    wang2020's run toward letter-l splits the communication graph after step 36."""
    from swarmproof.reference_impl.initial import random_grid_connected

    init = random_grid_connected(5, 4, range=0.6, spacing=0.2)
    path = tmp_path / "start.json"
    path.write_text(json.dumps({"format": "swarmproof-initial/1", "angle_unit": "rad", "robots": [
        {"id": int(i), "pose": [float(x) for x in pose]} for i, pose in zip(init.ids, init.poses)]}))
    return str(path)


def test_wang2020_connected_start_that_splits_is_reported_not_judged(capsys, split_start):
    code, out, _ = run(capsys, "wang2020", "--shape", "letter-l", "--initial", split_start, "--seed", "5",
                       "--json")
    doc = json.loads(out)
    # the finding is in the document ...
    assert doc["connectivity"]["status"] == "violated" and doc["connected_throughout"] is False
    assert doc["connectivity"]["message"].startswith("the communication graph splits after step 36 into 2")
    # ... but 004 does not claim connectivity: the exit code follows what it claims, which held
    assert doc["claims"]["connectivity"] is None and doc["claims"]["formation"] is not None
    assert doc["judged"] == ["termination", "formation", "completion_sound"] and doc["satisfied"] is True
    assert doc["completion_sound"]["status"] == "held"
    assert code == 0 and doc["exit_code"] == 0
    # no parent field: tree links are not applicable, not inconclusive
    assert doc["tree_links"]["status"] == "not_applicable"
    assert doc["not_applicable"] == {"tree_links": "no 'parent' field in its controller states (state_fields=())"}
    code, out, _ = run(capsys, "wang2020", "--shape", "letter-l", "--initial", split_start, "--seed", "5")
    lines = out.splitlines()
    assert code == 0
    assert any(line.startswith("  connectivity: violated* - the communication graph splits after step 36")
               for line in lines)
    assert "  tree links: not applicable - no 'parent' field in its controller states (state_fields=())" in lines
    assert "  * not claimed by the paper: reported, not judged for the exit code" in lines
    assert lines[-1] == "result: ok (findings, not claimed: connectivity)"


def test_jiang_connectivity_is_not_applicable(capsys):
    code, out, _ = run(capsys, "jiang", "--pattern", "square-segments", "--robots", "4", "--seed", "0")
    assert ("  connectivity: not applicable - no range graph: every robot hears every robot "
            "(communication='all')") in out.splitlines()
    assert "inconclusive" not in [line.split(": ")[1].split(" ")[0] for line in out.splitlines()
                                  if line.startswith("  connectivity:")]


USER = textwrap.dedent('''
    from swarmproof.reference_impl.examples.algorithms import GatherToLowestId


    class MyGather(GatherToLowestId):
        """A user's gathering algorithm: it claims to end, nothing about lattices."""

        name = "my-gather"
        claims = {"termination": "my notes, Thm. 1"}
''')


@pytest.fixture
def user_module(tmp_path, monkeypatch):
    (tmp_path / "usermod_claims.py").write_text(USER)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield
    sys.modules.pop("usermod_claims", None)


def test_a_users_class_is_judged_by_its_claims_and_its_legend_names_no_paper(capsys, user_module):
    argv = ["usermod_claims:MyGather", "--lattice", "square", "--robots", "6", "--seed", "1"]
    code, out, _ = run(capsys, *argv, "--json")
    doc = json.loads(out)
    # it misses the square lattice (a gathering algorithm): reported, not judged
    assert doc["satisfies_lattice"] is False and doc["claims"]["formation"] is None
    assert doc["judged"] == [] and code == 0          # it has no termination bound or end to judge
    code, out, _ = run(capsys, *argv)
    lines = out.splitlines()
    assert any(line.startswith("  satisfies lattice: violated* - ") for line in lines)
    assert "  * not claimed by the algorithm: reported, not judged for the exit code" in lines
    assert "by the paper" not in out
    assert lines[-1] == "result: ok (findings, not claimed: formation, connectivity)" and code == 0


def test_a_users_claimed_property_that_fails_exits_1(capsys, user_module, monkeypatch):
    import usermod_claims

    monkeypatch.setattr(usermod_claims.MyGather, "claims", {"formation": "my notes, Thm. 2"})
    code, out, _ = run(capsys, "usermod_claims:MyGather", "--lattice", "square", "--robots", "6", "--seed", "1")
    assert code == 1 and out.splitlines()[-1] == "result: a claimed property failed (findings, not claimed: connectivity)"
    assert any(line.startswith("  satisfies lattice: violated - ") for line in out.splitlines())


def test_song2016_still_exits_1_when_its_claimed_tree_links_break(capsys):
    """The issue 19 case (square n = 20 seed 1): 001 claims tree_links (Lemma 11), so the break
    of a link chosen in the step is judged: exit 1."""
    code, out, _ = run(capsys, "song2016", "--lattice", "square", "--robots", "20", "--seed", "1", "--json")
    doc = json.loads(out)
    assert doc["tree_links"]["status"] == "violated" and doc["claims"]["tree_links"].startswith("001 Lemma 11")
    assert "tree_links" in doc["judged"]
    assert doc["not_applicable"] == {"completion_sound": "its robots do not detect completion (no completion_invariants)"}
    assert code == 1 and doc["exit_code"] == 1


def test_a_claimed_property_left_vacuous_is_inconclusive_exit_3(capsys, tmp_path):
    """song2016 claims connectivity (Lemma 11); from a disconnected start the claim is vacuous:
    connectivity inconclusive, and the run exits 3 (never a pass), not 0 (it did: only formation
    and termination could make it 3)."""
    path = tmp_path / "apart.json"
    path.write_text(json.dumps({"format": "swarmproof-initial/1", "angle_unit": "rad", "robots": [
        {"id": 0, "pose": [0.0, 0.0, 0.0]}, {"id": 1, "pose": [0.5, 0.0, 0.0]},
        {"id": 2, "pose": [40.0, 0.0, 0.0]}, {"id": 3, "pose": [40.5, 0.0, 0.0]}]}))
    code, out, _ = run(capsys, "song2016", "--lattice", "square", "--initial", str(path), "--seed", "0",
                       "--max-steps", "200", "--allow-violations", "--json")   # connected_start broken on purpose
    doc = json.loads(out)
    assert doc["claims"]["connectivity"] is not None and "connectivity" in doc["judged"]
    assert doc["connectivity"]["status"] == "inconclusive"
    assert doc["connectivity"]["message"].startswith("vacuous: the start is disconnected")
    assert not any(doc[p]["status"] == "violated" for p in ("connectivity", "tree_links") if doc.get(p))
    assert code == 3 and doc["exit_code"] == 3


def test_a_run_cut_by_the_step_cap_does_not_judge_the_formation(capsys):
    """The formation is a property of the final configuration; a run cut by its step cap has none:
    inconclusive and exit 3, as the explorer's "formation" and verify's rows say -- never
    "violated" (exit 1) for a run that was only stopped early."""
    code, out, _ = run(capsys, "song2016", "--lattice", "square", "--robots", "10", "--seed", "0",
                       "--max-steps", "5", "--json")
    doc = json.loads(out)
    assert code == 3 and doc["exit_code"] == 3 and doc["status"] == "step_cap"
    assert doc["satisfied"] is None and doc["satisfaction"]["status"] == "inconclusive"
    assert "the step cap 5 was reached before the run ended" in doc["satisfaction"]["message"]
    assert "matches no edge" in doc["satisfaction"]["message"]    # what the cut run showed, kept
    code, out, _ = run(capsys, "song2016", "--lattice", "square", "--robots", "10", "--seed", "0",
                       "--max-steps", "5")
    assert code == 3 and "satisfies lattice: inconclusive - not judged" in out
    assert out.rstrip().endswith("result: inconclusive (step cap reached)")
