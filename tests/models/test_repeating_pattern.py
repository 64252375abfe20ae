"""Repeating patterns of 002 (models/repeating_pattern.py): the repeating-pattern/1 file with
located errors, the bundled patterns, the target kind, lattice conversion and check-pattern."""

from __future__ import annotations

import json
import os

import pytest

from swarmproof.cli import main
from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.models.repeating_pattern import (check_pattern, load_pattern, loads_pattern, pattern_names,
                                                 resolve_pattern, schema_path)
from swarmproof.models.targets import resolve_target

GOOD = """\
format: repeating-pattern/1
name: seg
basic: [[0, 0], [0.4, 0]]
assembling: [[0, 0], [1, 0], [0, 1]]
"""

BAD = [
    ("not a mapping", "- 1\n", 1, None, "must be a mapping"),
    ("format", GOOD.replace("repeating-pattern/1", "repeating-pattern/2"), 1, "format", "must be 'repeating-pattern/1'"),
    ("unknown key", GOOD + "colour: red\n", 5, "colour", "key 'colour' is not known"),
    ("missing assembling", "format: repeating-pattern/1\nbasic: [[0, 0]]\n", 1, None, "'assembling' is missing"),
    ("origin first", GOOD.replace("[[0, 0], [0.4, 0]]", "[[0.4, 0], [0, 0]]"), 3, "basic[0]", "must be the origin"),
    ("repeated point", GOOD.replace("[[0, 0], [0.4, 0]]", "[[0, 0], [0.4, 0], [0.4, 0]]"), 3, "basic[2]",
     "repeats basic[1]"),
    ("repeated vector", GOOD.replace("[1, 0], [0, 1]", "[1, 0], [1, 0]"), 4, "assembling[2]", "repeats"),
    ("quoted number", GOOD.replace("[0.4, 0]", "['0.4', 0]"), 3, "basic[1][0]", "without quotes"),
    ("not a pair", GOOD.replace("[0.4, 0]", "[0.4, 0, 1]"), 3, "basic[1]", "must be a pair"),
    ("infinite", GOOD.replace("[0.4, 0]", "[.inf, 0]"), 3, "basic[1][0]", "finite"),
    ("tol", GOOD + "tol: -1\n", 5, "tol", "must be > 0"),
    ("empty basic", GOOD.replace("[[0, 0], [0.4, 0]]", "[]"), 3, "basic", "non-empty list"),
    ("yaml", GOOD + "basic: [\n", None, None, "malformed YAML"),
    ("huge int", GOOD.replace("[1, 0], [0, 1]", "[1" + "0" * 400 + ", 0], [0, 1]"), 4, "assembling[1][0]",
     "of size at most 1e+06"),
    ("huge float", GOOD.replace("[1, 0], [0, 1]", "[1.0e+308, 0], [0, 1]"), 4, "assembling[1][0]", "at most"),
    ("yaml 1.1 exponent", GOOD + "tol: 1e-6\n", 5, "tol", "write 1.0e-6"),
    ("no nonzero vector", GOOD.replace("[[0, 0], [1, 0], [0, 1]]", "[[0, 0]]"), 4, "assembling",
     "no nonzero vector"),
    ("points too close", GOOD.replace("[0.4, 0]", "[1.0e-300, 0]"), 3, "basic[1]", "less than 1e-06"),
]


@pytest.mark.parametrize("name, text, line, fld, match", BAD, ids=[b[0] for b in BAD])
def test_bad_files_are_located(name, text, line, fld, match):
    with pytest.raises(InputFileError) as e:
        loads_pattern(text, "yaml", "p.yaml")
    err = e.value
    assert match in str(err) and err.file == "p.yaml" and "fix: " in str(err)
    if line is not None:
        assert err.line == line, str(err)
    if fld is not None:
        assert err.field == fld, str(err)


def test_json_files_and_schema_agree(tmp_path):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.load(open(schema_path(), encoding="utf-8"))
    for name in pattern_names():
        doc = load_pattern(name).document()
        jsonschema.validate(doc, schema)
        f = tmp_path / f"{name}.json"
        f.write_text(json.dumps(doc))
        assert resolve_target(str(f)).describe() == load_pattern(name).describe()
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"format": "repeating-pattern/1", "basic": [[0, 0]]}, schema)


def test_bundled_patterns_assemble_with_quality_one():
    assert pattern_names() == ["rhombus-triangles", "square-dots", "square-segments", "trapezoid-hexagons",
                               "triangle-segments"]
    for name in pattern_names():
        p = resolve_target(name)
        assert p.kind == "pattern"
        r = check_pattern(p, 32)
        assert r.status == "held", r.message
        pts = p.formation(30 * len(p.basic))
        assert p.satisfied(None, pts).status == "held"
        # one robot moved away: quality below 1, violated with the exact epsilon
        moved = pts.copy()
        moved[len(moved) // 2] += (7.77, 3.33)
        v = p.satisfied(None, moved)
        assert v.status == "violated" and v.detail["exact"] and v.detail["epsilon"] < 1


def test_target_describe_round_trip_and_metrics():
    from swarmproof.models.targets import target_from_description

    p = load_pattern("rhombus-triangles")
    assert target_from_description(p.describe()) == p
    m = p.metrics(None, p.formation(12))
    assert (m["epsilon"], m["basic_fulfillment"], m["assembling_fulfillment"], m["method"]) == (1.0, 1.0, 1.0,
                                                                                               "perfect-cover")


def test_an_overlapping_pattern_is_found(tmp_path, capsys):
    f = tmp_path / "overlap.yaml"
    f.write_text(GOOD.replace("[0.4, 0]", "[1, 0]"))        # copies one step apart share a point
    code = main(["check-pattern", str(f), "--json", "--plot", str(tmp_path / "o.png")])
    doc = json.loads(capsys.readouterr().out)
    assert code == 1 and doc["verdict"] == "violated" and doc["overlap"]["pairs"] > 0
    assert os.path.getsize(tmp_path / "o.png") > 1000


def test_check_pattern_command(capsys, tmp_path):
    assert main(["check-pattern", "--list"]) == 0
    assert capsys.readouterr().out.split() == pattern_names()
    assert main(["check-pattern", "rhombus-triangles"]) == 0
    assert "HELD" in capsys.readouterr().out
    assert main(["check-pattern", "lattice:square", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["quality"]["epsilon"] == 1.0
    assert main(["check-pattern", "lattice:hexagon"]) == 2
    assert "2 roles" in capsys.readouterr().err
    assert main(["check-pattern", "no-such"]) == 2
    err = capsys.readouterr().err
    assert "no-such" in err and "rhombus-triangles" in err and "Traceback" not in err
    bad = tmp_path / "bad.yaml"
    bad.write_text(GOOD.replace("[0.4, 0]", "[0.4, x]"))
    assert main(["check-pattern", str(bad)]) == 2
    assert f"{bad}:3" in capsys.readouterr().err
    assert main(["check-pattern", "rhombus-triangles", "--copies", "0"]) == 2
    assert main(["check-pattern"]) == 2


def test_pattern_from_lattice_refuses_what_does_not_convert():
    with pytest.raises(UsageError, match="2 roles"):
        resolve_pattern("lattice:hexagon")
    with pytest.raises(UsageError, match="theta"):
        resolve_pattern("lattice:honeycomb-rotating")
    assert resolve_pattern("lattice:triangle").basic == ((0.0, 0.0),)


def test_simulate_takes_a_converted_lattice_and_does_not_judge_a_range_graph(capsys):
    """Every jiang robot hears every robot: connectivity of the range graph is not applicable
    (no verdict, never a failure), so a run that forms the pattern exits 0."""
    assert main(["simulate", "jiang", "--pattern", "lattice:square", "--robots", "6", "--seed", "0", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["satisfied"] is True and doc["connectivity"]["status"] == "not_applicable"
    assert doc["connected_throughout"] is None
    assert main(["simulate", "jiang", "--lattice", "square", "--robots", "6", "--seed", "0"]) == 2
    err = capsys.readouterr().err    # a lattice target is of a kind jiang does not form (issue 29, item 4)
    assert "is not of a kind algorithm 'jiang' forms: it takes a pattern target only" in err and "fix:" in err


def test_a_spent_search_budget_is_inconclusive_in_check_pattern_and_satisfied(monkeypatch):
    """The third verdict: when the exact-cover search runs out of nodes before it proves quality
    1, check-pattern and the target say inconclusive (exit 3), never held."""
    from swarmproof.models import formation_quality as fq
    from swarmproof.models.repeating_pattern import RepeatingPattern

    def starved(self, poses):
        return fq.formation_quality(poses, self.basic, self.assembling, tol=self.tol, max_cover_nodes=1,
                                    max_milp_nodes=1)

    monkeypatch.setattr(RepeatingPattern, "quality", starved)
    p = load_pattern("rhombus-triangles")
    r = check_pattern(p, 8)
    assert r.status == "inconclusive" and r.to_json()["exit_code"] == 3
    assert p.satisfied(None, p.formation(24)).status == "inconclusive"


def test_the_invariants_property_has_three_verdicts():
    from swarmproof.invariants.algorithm_invariants import Invariant, InvariantsMonitor

    assert InvariantsMonitor(()).result().status == "inconclusive"          # nothing declared: vacuous
    ok = Invariant("ok", "always", "test", lambda t, ids, poses, states: None)
    bad = Invariant("bad", "never at step 2", "test", lambda t, ids, poses, states: "broke" if t == 2 else None)
    for invs, want in (((ok,), "held"), ((ok, bad), "violated")):
        m = InvariantsMonitor(invs)
        m.start([1])
        for t in range(4):
            m.observe(t, [[0.0, 0.0, 0.0]], (("s",),), [True])
        r = m.result()
        assert r.status == want
    assert r.witness == {"invariant": "bad", "step": 2, "statement": "never at step 2"}
