"""Readings are versioned (issue 29): every registered algorithm declares its reading version;
counterexample files and baselines record it; replaying a file made with another reading exits 2
and names the registered reading that reproduces it (or where to get it); verify against a
baseline of another reading reports those rows as READING CHANGED (exit 1), never a silent pass."""

from __future__ import annotations

import json

import pytest

from swarmproof.checkers.baseline import Baseline, compare
from swarmproof.cli import main
from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError
from swarmproof.models.verdict import Verdict
from swarmproof.reference_impl import registry
from swarmproof.reference_impl.protocol import reading_of


def _declared_reading(cls):
    """The ``reading`` a class declares itself or inherits from a class that declares it (not the
    protocol's default for classes that declare none)."""
    for klass in getattr(cls, "__mro__", (cls,)):
        if "reading" in vars(klass):
            return vars(klass)["reading"]
    return None


@pytest.mark.parametrize("name", sorted(registry.ALGORITHMS))
def test_every_registered_algorithm_declares_a_reading(name):
    cls = registry.algorithm_factory(name)
    declared = _declared_reading(cls)
    assert isinstance(declared, str) and declared.strip(), f"{name} declares no reading"
    assert registry.reading_of_name(name) == declared == reading_of(cls)
    assert registry.find_reading(name, declared) == (name, None)


def test_jiang_rule_is_not_its_reading():
    jiang, literal = registry.algorithm_factory("jiang"), registry.algorithm_factory("jiang-literal")
    assert (jiang.rule, literal.rule) == ("queue", "literal")
    assert reading_of(jiang) == reading_of(literal) == "1"


# ---------------------------------------------------------------- counterexample files

def _cx(reading="1", algorithm="example-gather"):
    return Counterexample(algorithm=algorithm, reading=reading,
                          params={"range": 1.2, "v": 0.05, "omega": 0.7853981633974483, "dt": 1.0},
                          lattice="square", robots=[(0, (0.0, 0.0, 0.0)), (1, (0.5, 0.0, 0.0)),
                                                    (2, (1.0, 0.0, 0.0))],
                          seed=0, property="connectivity", violation={"step": 3, "message": "split"},
                          max_steps=40)


def test_the_file_records_the_reading_and_old_files_are_reading_1():
    doc = _cx("2").as_dict()
    assert doc["reading"] == "2"
    again = Counterexample.from_dict(doc)
    assert again.reading == "2" and again.recorded_reading == "2" and again == _cx("2")
    del doc["reading"]                                   # a file from before readings were versioned
    old = Counterexample.from_dict(doc)
    assert old.reading is None and old.recorded_reading == "1"
    assert "reading" not in old.as_dict()                # written back as it was read


@pytest.mark.parametrize("value", [3, "", "  ", ["1"]], ids=["int", "empty", "blank", "list"])
def test_a_bad_reading_field_is_refused(value):
    doc = _cx().as_dict()
    doc["reading"] = value
    with pytest.raises(InputFileError, match=r"field 'reading': reading=.* must be a non-empty string"):
        Counterexample.from_dict(doc, file="cx.json")


@pytest.fixture
def old_reading_registered(monkeypatch):
    """``example-gather`` now at reading "2"; its reading "0" kept as ``example-gather-r0``."""
    from swarmproof.reference_impl.examples import GatherToLowestId

    monkeypatch.setattr(GatherToLowestId, "reading", "2")
    monkeypatch.setattr(registry, "ALGORITHMS", {**registry.ALGORITHMS, "example-gather-r0": "testkit:GatherReading0"})
    monkeypatch.setattr(registry, "READINGS", {("example-gather", "0"): "example-gather-r0"})


def test_replay_of_another_reading_exits_2_and_names_the_registered_reading(capsys, tmp_path, old_reading_registered):
    path = _cx("0").save(tmp_path / "cx.json")
    code = main(["replay", path])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert (f"{path}: field 'reading': reading='0': this file was made with reading '0' of "
            "algorithm='example-gather', which runs reading '2' here") in err
    assert "reading '0' of example-gather is registered as 'example-gather-r0'" in err
    assert 'fix: replay it with that reading: set "algorithm": "example-gather-r0" in the file' in err
    assert "no longer reproduces" not in err and "Traceback" not in err
    # the fix works: the registered reading replays the file (and judges it: 0 or 1, not 2)
    doc = json.loads(open(path).read())
    doc["algorithm"] = "example-gather-r0"
    fixed = tmp_path / "fixed.json"
    fixed.write_text(json.dumps(doc))
    code = main(["replay", str(fixed), "--json"])
    assert code in (0, 1) and json.loads(capsys.readouterr().out)["reading"] == "0"


def test_replay_of_an_old_file_without_reading_is_reading_1(capsys, tmp_path, old_reading_registered):
    doc = _cx().as_dict()
    del doc["reading"]
    path = tmp_path / "old.json"
    path.write_text(json.dumps(doc))
    code = main(["replay", str(path), "--json"])
    out, _ = capsys.readouterr()
    doc = json.loads(out)
    assert code == 2 and doc["exit_code"] == 2 and doc["error"]["kind"] == "usage"
    assert ("reading='1' (not recorded: a file from before readings were versioned): this file was made "
            "with reading '1'") in doc["error"]["message"]
    assert "no reading '1' of example-gather is registered in this swarmproof" in doc["error"]["message"]


def test_replay_of_a_retired_or_unknown_reading_says_where_to_get_it(capsys, tmp_path, monkeypatch):
    cx = _cx("7")
    path = cx.save(tmp_path / "cx.json")
    code = main(["replay", path])
    err = capsys.readouterr().err
    assert code == 2
    assert "no reading '7' of example-gather is registered in this swarmproof" in err
    assert "fix: replay it with the swarmproof that wrote it (made_by.swarmproof=" in err
    monkeypatch.setattr(registry, "RETIRED_READINGS",
                        {("example-gather", "7"): "swarmproof 0.0.9 (commit 0123abc)"})
    code = main(["replay", path])
    err = capsys.readouterr().err
    assert code == 2
    assert "reading '7' of example-gather is not registered in this swarmproof" in err
    assert "it is in swarmproof 0.0.9 (commit 0123abc); fix: replay it with swarmproof 0.0.9 (commit 0123abc)" in err


def test_replay_of_a_users_class_with_another_reading(capsys, tmp_path):
    path = _cx("0", algorithm="swarmproof.reference_impl.examples.algorithms:GatherToLowestId").save(tmp_path / "c.json")
    code = main(["replay", path])
    err = capsys.readouterr().err
    assert code == 2
    assert "is not registered, so no other reading of it is known" in err
    assert "fix: replay it with the version of" in err and "that declared reading '0'" in err


def test_replay_of_the_current_reading_judges_it(capsys, tmp_path):
    path = _cx("1", algorithm="song2014").save(tmp_path / "cx.json")
    code = main(["replay", path, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code in (0, 1) and doc["reading"] == "1" and doc["algorithm"] == "song2014"


# ---------------------------------------------------------------- baselines

class _Row:
    def __init__(self, algorithm, verdict, subject=None, prop="connectivity"):
        self.section, self.subject, self.property = "algorithms", subject or f"{algorithm} square n=10", prop
        self.verdict, self.claim, self.claimed, self.detail = verdict, "cite", True, ""
        self.data = {"algorithm": algorithm}


def test_a_baseline_records_the_readings_and_old_baselines_are_reading_1():
    rows = [_Row("song2014", Verdict.HELD), _Row("jiang", Verdict.HELD)]
    base = Baseline.from_rows(rows, {})
    assert base.to_json()["readings"] == {"jiang": "1", "song2014": "1"}
    doc = base.to_json()
    del doc["readings"]
    old = Baseline.from_json(doc)
    assert old.readings == {} and old.reading_of("song2014") == "1"
    assert compare(rows, old).exit_code == 0


def test_rows_of_another_reading_are_not_compared_and_fail_the_gate():
    rows = [_Row("song2014", Verdict.HELD), _Row("jiang", Verdict.HELD)]
    doc = Baseline.from_rows(rows, {}).to_json()
    doc["readings"]["song2014"] = "0"
    cmp_ = compare(rows, Baseline.from_json(doc, file="b.json"))
    assert [c.outcome for c in cmp_.changes] == ["reading", "same"]
    assert cmp_.exit_code == 1
    lines = cmp_.lines()
    assert lines[0].startswith("-- READING CHANGED (the baseline was made with another reading")
    assert lines[1] == ("  algorithms: song2014 square n=10 / connectivity: held [cite] -- the baseline was "
                        "made with reading '0' of song2014, this run uses reading '1' (baseline held, now held): "
                        "not compared; regenerate the baseline on purpose (--update-baseline) and give the reason "
                        "for each changed row")
    assert cmp_.summary_line() == ("verify: FAIL: 0 regressions, 0 known findings, 0 improvements, 2 held; 1 row "
                                   "made with another reading (not compared) (against b.json)")
    assert cmp_.to_json()["readings"] == {"jiang": "1", "song2014": "0"}


def test_merging_keeps_the_readings_of_rows_out_of_scope():
    old = Baseline.from_json({"format": "swarmproof-baseline/1", "readings": {"song2014": "0"},
                              "rows": [{"section": "algorithms", "subject": "song2014 square n=10",
                                        "property": "connectivity", "verdict": "held", "claim": "cite",
                                        "algorithm": "song2014"}]})
    fresh = Baseline.from_rows([_Row("jiang", Verdict.HELD)], {})
    merged = old.merged(fresh, in_scope=lambda e: e.algorithm == "jiang")
    assert merged.readings == {"song2014": "0", "jiang": "1"}


@pytest.mark.parametrize("readings, match", [
    ([], r"field 'readings': readings=\[\] is not an object"),
    ({"song2014": 1}, r"field 'readings.song2014': readings.song2014=1 is not a reading"),
], ids=["list", "number"])
def test_bad_readings_tables_are_refused(readings, match):
    with pytest.raises(InputFileError, match=match):
        Baseline.from_json({"format": "swarmproof-baseline/1", "readings": readings, "rows": []}, file="b.json")


def test_verify_against_a_baseline_of_another_reading_says_so(capsys, tmp_path):
    b = tmp_path / "b.json"
    argv = ["verify", "--algorithm", "example-anonymous-line", "--section", "algorithms", "--baseline", str(b)]
    assert main(argv + ["--update-baseline"]) == 0
    capsys.readouterr()
    doc = json.loads(b.read_text())
    assert doc["readings"] == {"example-anonymous-line": "1"}
    assert main(argv) == 0
    capsys.readouterr()
    doc["readings"]["example-anonymous-line"] = "0"
    b.write_text(json.dumps(doc))
    code = main(argv)
    out = capsys.readouterr().out
    assert code == 1
    assert "-- READING CHANGED" in out and "made with reading '0' of example-anonymous-line" in out
    assert out.splitlines()[-1].startswith("verify: FAIL: 0 regressions")
    assert "made with another reading (not compared)" in out.splitlines()[-1]


def test_the_shipped_baseline_records_every_algorithm_reading():
    from testkit import SHIPPED

    doc = json.load(open(SHIPPED, encoding="utf-8"))
    algos = {r["algorithm"] for r in doc["rows"] if r.get("algorithm")}
    assert set(doc["readings"]) == algos
    assert all(doc["readings"][a] == registry.reading_of_name(a) for a in algos)
