"""Baselines (checkers/baseline.py): every outcome of a comparison and its exit code, the summary
line, signatures, the file's round trip and its bad-input errors (issue 14, DESIGN.md section 5)."""

from __future__ import annotations

import json
import os

import pytest

from swarmproof.checkers.baseline import BASELINE_FORMAT, Baseline, compare, message_kind, signature
from swarmproof.checkers.report import Report, Row
from swarmproof.models.errors import InputFileError
from swarmproof.models.verdict import Verdict

H, P, V, I = Verdict.HELD, Verdict.PROVED, Verdict.VIOLATED, Verdict.INCONCLUSIVE


def row(prop, verdict, *, claim="001 Lemma 11", message="the link child 1 -> parent 2 broke (distance 1.2)",
        size=4, section="exploration", algorithm="song2016"):
    data = {"algorithm": algorithm}
    if verdict is V:
        data.update(violation={"step": 3, "message": message}, counterexample_robots=size)
    return Row(section, f"{algorithm} n=3..8", prop, verdict, message if verdict is V else "ok", data, claim=claim)


def base_of(*rows, gate=None):
    return Baseline.from_rows(rows, gate or {"max_examples": 300, "robots": [3, 8], "seed": 0})


@pytest.mark.parametrize("then, now, outcome, code", [
    (row("a", H), row("a", H), "same", 0),
    (row("a", P, section="lemmas"), row("a", P, section="lemmas"), "same", 0),
    (row("a", V), row("a", V), "known", 0),
    (row("a", H), row("a", V), "regressed", 1),
    (row("a", P, section="lemmas"), row("a", V, section="lemmas"), "regressed", 1),
    (row("a", I), row("a", V), "regressed", 1),
    (row("a", H, claim=None), row("a", V, claim=None), "regressed", 1),   # in the baseline: compared, claimed or not
    (row("a", V), row("a", V, message="robots 1 and 2 overlap in step 3: distance 0.1"), "changed", 1),
    (row("a", V), row("a", V, size=6), "resized", 0),
    (row("a", H), row("a", I), "inconclusive", 3),
    (row("a", V), row("a", I), "inconclusive", 3),
    (row("a", I), row("a", I), "inconclusive", 3),                       # claimed: never a pass
    (row("a", I, claim=None), row("a", I, claim=None), "same", 0),       # unclaimed: not counted
    (row("a", P), row("a", H), "weakened", 3),
    (row("a", V), row("a", H), "improved", 0),
    (row("a", I), row("a", H), "improved", 0),
], ids=lambda x: x if isinstance(x, (str, int)) else None)
def test_every_outcome_and_its_exit_code(then, now, outcome, code):
    cmp_ = compare([now], base_of(then))
    assert [c.outcome for c in cmp_.changes] == [outcome]
    assert cmp_.exit_code == code


@pytest.mark.parametrize("then, now, code", [
    (row("a", V), row("a", H), 1), (row("a", V), row("a", V, size=6), 1), (row("a", H), row("a", H), 0)],
    ids=["improved", "resized", "same"])
def test_strict_fails_on_improvements_and_resized(then, now, code):
    assert compare([now], base_of(then), strict=True).exit_code == code


def test_rows_absent_from_the_baseline_are_judged_by_their_claims():
    empty = base_of()
    assert compare([row("a", V)], empty).exit_code == 1
    assert compare([row("a", I)], empty).exit_code == 3
    assert compare([row("a", V, claim=None)], empty).exit_code == 0      # a finding
    assert compare([row("a", H)], empty).exit_code == 0
    assert [c.outcome for c in compare([row("a", V)], empty).changes] == ["new"]


def test_gone_rows_are_in_scope_only():
    b = base_of(row("a", H), row("b", H, algorithm="song2014"))
    cmp_ = compare([], b, in_scope=lambda e: e.algorithm == "song2016")
    assert [(c.outcome, c.key[2]) for c in cmp_.changes] == [("gone", "a")]
    assert cmp_.exit_code == 0                                            # a warning (an error with --strict)
    assert "1 baseline row gone" in cmp_.summary_line()


def test_summary_line_counts():
    b = base_of(row("a", H), row("b", V), row("c", V), row("d", H))
    now = [row("a", V), row("b", V), row("c", H), row("d", H)]
    b.path = "verify-baseline.json"
    cmp_ = compare(now, b)
    assert cmp_.summary_line() == ("verify: FAIL: 1 regression, 1 known finding, 1 improvement, 2 held "
                                   "(against verify-baseline.json)")
    text = Report(now, comparison=cmp_).format_table()
    assert text.splitlines()[-1] == cmp_.summary_line()
    assert "-- REGRESSED (held or proved in the baseline, violated now)" in text
    assert "[regressed] the link child" in text and "-- known findings (violated, as the baseline says)" in text
    assert "  exploration: song2016 n=3..8 / b: violated [001 Lemma 11] -- violated, as the baseline says" in text


def test_signature_and_message_kind():
    assert signature(row("a", H)) is None
    assert signature(row("a", V)) == {"property": "a", "size": 4, "kind": "the link child # -> parent # broke"}
    assert message_kind("step 12: deadlock: nothing moved") == "deadlock"
    assert message_kind("the algorithm raised ValueError in step 3: boom") == "the algorithm raised ValueError in step #"


def test_round_trip_is_byte_identical(tmp_path):
    b = base_of(row("a", H), row("b", V), row("c", I, claim=None))
    p1, p2 = tmp_path / "one.json", tmp_path / "two.json"
    b.save(p1)
    Baseline.load(p1).save(p2)
    assert p1.read_bytes() == p2.read_bytes()
    doc = json.loads(p1.read_text())
    assert doc["format"] == BASELINE_FORMAT and set(doc["made_by"]) == {"swarmproof", "python", "numpy", "z3"}
    assert [r["property"] for r in doc["rows"]] == ["a", "b", "c"]
    assert doc["rows"][1]["signature"]["kind"] == "the link child # -> parent # broke"


def test_merged_keeps_rows_outside_the_scope():
    old = base_of(row("a", H), row("b", H, algorithm="song2014"))
    new = base_of(row("a", V))
    merged = old.merged(new, lambda e: e.algorithm == "song2016")
    assert {(k[2], e.verdict) for k, e in merged.rows.items()} == {("a", V), ("b", H)}


BAD = [
    ("not-json", "{", "the baseline is not JSON", "not-json.json:1:"),
    ("other-format", json.dumps({"format": "swarmproof-baseline/9", "rows": []}),
     "format='swarmproof-baseline/9' is not 'swarmproof-baseline/1'", "field 'format'"),
    ("a-list", "[]", "is a JSON list, not an object", "field 'format'"),
    ("rows-missing", json.dumps({"format": BASELINE_FORMAT}), "rows=None is not a list", "field 'rows'"),
    ("bad-verdict", json.dumps({"format": BASELINE_FORMAT, "rows": [
        {"section": "s", "subject": "t", "property": "p", "verdict": "passed"}]}),
     "rows[0].verdict='passed' is not one of", "field 'rows[0].verdict'"),
    ("missing-subject", json.dumps({"format": BASELINE_FORMAT, "rows": [
        {"section": "s", "property": "p", "verdict": "held"}]}), "rows[0].subject=None is not a string",
     "field 'rows[0].subject'"),
    ("repeated-row", json.dumps({"format": BASELINE_FORMAT, "rows": [
        {"section": "s", "subject": "t", "property": "p", "verdict": "held"}] * 2}),
     "rows[1] repeats the row", "field 'rows[1]'"),
    ("bad-gate", json.dumps({"format": BASELINE_FORMAT, "gate": {"robots": [3]}, "rows": []}),
     "gate.robots=[3] is not [MIN, MAX]", "field 'gate.robots'"),
]


@pytest.mark.parametrize("name, text, match, where", BAD, ids=[b[0] for b in BAD])
def test_bad_baseline_files_name_what_and_where(tmp_path, name, text, match, where):
    p = tmp_path / f"{name}.json"
    p.write_text(text)
    with pytest.raises(InputFileError, match=r"fix: ") as info:
        Baseline.load(p)
    assert match in str(info.value) and where in str(info.value), str(info.value)


def test_missing_baseline_says_how_to_write_one(tmp_path):
    with pytest.raises(InputFileError, match="does not exist.*--update-baseline"):
        Baseline.load(os.path.join(tmp_path, "none.json"))
