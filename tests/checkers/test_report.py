"""The verification report (checkers/report.py): the ``lemmas`` and ``exploration``
sections' rows on tiny budgets, their JSON fields, and the exit-code rule
(proved/held -> 0, a claimed violation -> 1, inconclusive -> 3, unclaimed
violations are findings and not counted), each checked on exact table lines."""

from __future__ import annotations

import json
import os

import pytest
import z3

from swarmproof.checkers import proofs, report
from swarmproof.reference_impl.song2016 import lemmas as song_lemmas
from swarmproof.checkers.proofs import EXTRA_LEMMAS, LEMMAS, Encoding, Lemma, prove
from swarmproof.checkers.report import (Report, Row, exploration_row, lemma_rows, run_report,
                                        section_exploration, section_lemmas)
from swarmproof.models.fileio import dumps_json
from swarmproof.models.verdict import Verdict


def _table_body(rep: Report) -> list[str]:
    """The table without the section header line (it carries wall-clock seconds)."""
    return rep.format_table().splitlines()[1:]


# ---------------------------------------------------------------- lemmas

def test_lemma_rows_each_status_maps_to_its_verdict():
    x = z3.Real("x")
    vacuous = Lemma(id="vacuous_lemma", statement="x > 1 and x < 0 imply x = 42", cites=("test",),
                    normalisations=(), control_note="test",
                    build=lambda: Encoding(premises=[("pos", x > 1), ("neg", x < 0)],
                                           conclusion=x == 42, variables=[x]),
                    control=lambda: song_lemmas.relocate_stays_in_range(4))
    results = [prove(LEMMAS["relocate_stays_in_range"]), prove(EXTRA_LEMMAS["bounded_range_strict_closed"]),
               prove(vacuous)]
    rows = lemma_rows(results)
    assert [(r.section, r.subject, r.property, r.verdict) for r in rows] == [
        ("lemmas", "relocate_stays_in_range", "z3 proof", Verdict.PROVED),
        ("lemmas", "bounded_range_strict_closed", "z3 proof", Verdict.VIOLATED),
        ("lemmas", "vacuous_lemma", "z3 proof", Verdict.INCONCLUSIVE)]
    assert rows[2].claim == "test"
    lines = Report(rows[:2]).format_table().splitlines()
    assert lines[1:] == [
        "subject                      property  verdict       detail",
        "relocate_stays_in_range      z3 proof  proved        auxiliary; premises satisfiable, negative control "
        "refuted (weakened: the segment's end may be 2 phi away), vacuity controls ok (needed: end_within_range, "
        "on_segment, root_still, start_within_range); not proved: that the relocate robot's step ends within phi of the "
        "root: the run-time monitor checks that end directly (a disc is convex; this lemma only extends the "
        "two ends to the path between them)",
        "bounded_range_strict_closed  z3 proof  violated      counterexample s=0.5, p_i_0_x=0, p_i_0_y=0, "
        "p_i_1_x=0, p_i_1_y=-0.5, p_p_1_x=0, p_p_1_y=0.5; auxiliary; premises satisfiable, negative control "
        "refuted (weakened: bounded range of radius phi)",
        "",
        "verify: VIOLATED (1 proved, 0 held, 1 violated, 0 inconclusive)"]
    assert rows[2].detail == ("premises unsatisfiable: the lemma would hold vacuously; auxiliary; premises "
                              "unsatisfiable (vacuous), negative control refuted (weakened: test)")
    assert Report(rows[:1]).exit_code == 0
    assert Report(rows[:2]).exit_code == 1
    assert Report([rows[0], rows[2]]).exit_code == 3


def test_lemma_section_json_fields_and_no_seconds():
    rows = section_lemmas(ids=["relocate_stays_in_range"])
    doc = rows[0].to_json()
    assert set(doc) == {"section", "subject", "property", "verdict", "detail", "claim", "statement",
                        "cites", "status", "premises_satisfiable", "negative_control", "counterexample",
                        "reason", "normalisations", "kind", "vacuity", "not_proved", "rlimit"}
    assert (doc["verdict"], doc["status"], doc["premises_satisfiable"]) == ("proved", "proved", True)
    # z3's work, counted deterministically (issue 32): a verify row's JSON stays bit-identical
    assert doc["rlimit"] == section_lemmas(ids=["relocate_stays_in_range"])[0].to_json()["rlimit"]
    assert doc["rlimit"]["budget"] == 200_000_000 and doc["rlimit"]["used"] > 0
    assert doc["negative_control"]["status"] == "counterexample"
    assert doc["claim"] == "; ".join(LEMMAS["relocate_stays_in_range"].cites)
    assert doc["kind"] == "auxiliary" and doc["vacuity"]["verdict"] == "ok"


def test_lemma_section_default_is_the_whole_suite_in_order(monkeypatch):
    seen = []
    monkeypatch.setattr(proofs, "run_suite", lambda ids, timeout_s: seen.append((ids, timeout_s)) or [])
    assert section_lemmas() == []
    assert seen == [([lid], proofs.DEFAULT_TIMEOUT_S) for lid in LEMMAS]


# ----------------------------------------------------------- exploration

def test_exploration_rows_held_claimed_violated_and_finding():
    """song2016 connectivity held (claimed, 001 Lemma 11); song2014 tree_links
    violated (claimed, 000 Lemma 7); song2016 collision violated (not claimed)."""
    rows = (section_exploration(algorithms=["song2016"], properties=["connectivity", "collision"],
                                max_examples=10, robots=(3, 4))
            + section_exploration(algorithms=["song2014"], properties=["tree_links"],
                                  max_examples=20, robots=(4, 6)))
    held, finding, violated = rows
    assert (held.verdict, held.claim) == (Verdict.HELD, "001 Lemma 11 (communication graph stays connected)")
    assert (finding.verdict, finding.claim) == (Verdict.VIOLATED, None)
    assert (violated.verdict, violated.claim) == (
        Verdict.VIOLATED, "000 Lemma 7 (a descendant stays within range of its parent)")
    assert _table_body(Report(rows)) == [
        "subject          property      verdict       detail",
        "song2016 n=3..4  connectivity  held          held over 10 scenarios, 1040 steps "
        "(explored, not proved)",
        "song2016 n=3..4  collision     violated*     4 robots on square: robots 1 and 2 "
        "overlap in step 23: distance 0.1936 < 2r = 0.2 at 1.00 of the step; the file: swarmproof verify "
        "--out DIR",
        "song2014 n=4..6  tree_links    violated      4 robots on square: step 3: the link "
        "child 0 -> parent 2 broke (distance 1.18335 -> 1.21626, range 1.2; decided links); the file: "
        "swarmproof verify --out DIR",
        "",
        "* not claimed by the paper: a finding about the algorithm, not counted in the verdict",
        "verify: VIOLATED (0 proved, 1 held, 2 violated, 0 inconclusive)"]
    # exit codes: held -> 0; an unclaimed violation is not counted -> 0; claimed violation -> 1
    assert Report([held]).exit_code == 0
    assert Report([held, finding]).exit_code == 0
    assert Report([held, finding]).verdict is Verdict.HELD
    assert Report(rows).exit_code == 1
    doc = violated.to_json()
    assert doc["reproduce"] == ("swarmproof explore song2014 --property tree_links --max-examples 20 "
                                "--robots 4..6 --seed 0 --budget none --out DIR")
    assert (doc["status"], doc["counterexample"], doc["counterexample_robots"]) == ("violated", None, 4)
    assert doc["violation"] == {"step": 3, "message": "step 3: the link child 0 -> parent 2 broke (distance "
                                                      "1.18335 -> 1.21626, range 1.2; decided links)"}
    assert {"algorithm", "robots", "seed", "max_examples", "budget", "explored", "scenarios", "conclusive",
            "steps", "capped", "budget_hit", "kept_assumptions", "broken_assumptions"} <= set(doc)
    assert doc["broken_assumptions"] == [] and doc["budget_hit"] is False


def test_exploration_writes_counterexample_only_with_out_dir(tmp_path):
    out = tmp_path / "cx"
    (row,) = section_exploration(algorithms=["song2016"], properties=["collision"], max_examples=10,
                                 robots=(3, 4), out_dir=str(out))
    path = str(out / "song2016-collision-seed0.json")
    assert os.listdir(out) == ["song2016-collision-seed0.json"]
    assert row.detail.endswith(f"; replay: swarmproof replay {path}")
    assert row.to_json()["counterexample"] == path
    assert json.load(open(path))["format"] == "swarmproof-counterexample/1"


def test_exploration_budget_spent_is_inconclusive_never_held():
    (spent,) = section_exploration(algorithms=["song2016"], properties=["connectivity"], max_examples=5,
                                   robots=(3, 4), budget=1e-9)
    (skipped,) = section_exploration(algorithms=["song2016"], properties=["termination"], max_examples=5,
                                     robots=(3, 4), section_budget=0)
    assert spent.verdict is Verdict.INCONCLUSIVE
    assert spent.detail == "no scenario gave a judgment (budget spent)"
    assert skipped.verdict is Verdict.INCONCLUSIVE
    assert skipped.detail == "not explored: the section's time budget of 0 s was spent before it"
    assert skipped.to_json()["explored"] is False
    held = Row("lemmas", "bounded_range", "z3 proof", Verdict.PROVED, "ok")
    rep = Report([held, spent, skipped])
    assert rep.exit_code == 3
    assert rep.format_table().splitlines()[-1] == "verify: INCONCLUSIVE (1 proved, 0 held, 0 violated, 2 inconclusive)"


_ENTRY = {"status": "held", "scenarios": 200, "conclusive": 200, "steps": 12016, "capped": 0,
          "budget_hit": False, "message": "held over ...", "counterexample": None, "violation": None,
          "robots": None}


@pytest.mark.parametrize("entry, verdict, detail", [
    (_ENTRY, Verdict.HELD, "held over 200 scenarios, 12016 steps (explored, not proved)"),
    (dict(_ENTRY, capped=3), Verdict.HELD,
     "held over 200 scenarios, 12016 steps (explored, not proved); 3 runs hit the step cap"),
    (dict(_ENTRY, budget_hit=True, scenarios=57), Verdict.INCONCLUSIVE,
     "time budget 60 s hit after 57 of 200 scenarios: not a pass (raise the budget or run on a less "
     "loaded machine)"),
    (dict(_ENTRY, status="inconclusive", message="no scenario gave a judgment (4 runs hit the step cap)"),
     Verdict.INCONCLUSIVE, "no scenario gave a judgment (4 runs hit the step cap)"),
    (dict(_ENTRY, status="violated", budget_hit=True, message="4 robots on square: step 3: broke",
          counterexample="cx/a.json"), Verdict.VIOLATED,
     "4 robots on square: step 3: broke (shrinking stopped at the time budget: may not be minimal); "
     "replay: swarmproof replay cx/a.json"),
    (dict(_ENTRY, status="proved"), Verdict.INCONCLUSIVE, "held over ..."),
], ids=["held", "held-capped", "held-but-budget-hit", "inconclusive", "violated-budget-hit",
        "unknown-status-never-proved"])
def test_exploration_row_mapping(entry, verdict, detail):
    row = exploration_row("song2016", "connectivity", entry, "001 Lemma 11", max_examples=200,
                          robots=(3, 8), seed=0, budget=60)
    assert (row.verdict, row.detail, row.subject) == (verdict, detail, "song2016 n=3..8")
    assert row.verdict is not Verdict.PROVED


def test_exploration_reads_the_explorer_properties_at_run_time(monkeypatch):
    from swarmproof.checkers import explore as explore_mod

    monkeypatch.setattr(explore_mod, "explore_properties", lambda algorithm=None: ("connectivity", "termination"))
    calls = []

    class _Rep:
        def __init__(self, algo, props):
            self.algo, self.props = algo, props
            self.properties = {}          # no counterexample objects

        def as_dict(self):
            return {"kept_assumptions": ["a"], "broken_assumptions": [],
                    "properties": {p: dict(_ENTRY) for p in self.props}}

    def fake_explore(algo, props, **kw):
        calls.append((algo, tuple(props), kw["max_examples"], kw["robots"], kw["seed"], kw["out_dir"]))
        return _Rep(algo, props)

    monkeypatch.setattr(explore_mod, "explore", fake_explore)
    rows = section_exploration(max_examples=7)
    # connectivity is not applicable where every robot hears every robot (jiang, leechong-*): those
    # rows are not explored at all (DESIGN.md section 5, "Not applicable")
    # one explorer call per algorithm, its applicable properties together (they share runs)
    assert calls == [(a, tuple(p for p in ("connectivity", "termination")
                               if not (p == "connectivity" and a in ("jiang", "leechong-leader", "leechong-neighbor"))),
                      7, (3, 8), 0, None)
                     for a in ("song2016", "song2014", "jiang", "wang2020", "wang2020-broadcast-handshake",
                               "leechong-leader", "leechong-neighbor", "example-anonymous-line", "example-grid-goals")]
    assert [(r.subject, r.property) for r in rows if not r.applicable] == [
        ("jiang n=3..8", "connectivity"), ("leechong-leader n=3..8", "connectivity"),
        ("leechong-neighbor n=3..8", "connectivity")]
    assert [(r.subject, r.property, r.claimed) for r in rows] == [
        ("song2016 n=3..8", "connectivity", True), ("song2016 n=3..8", "termination", True),
        ("song2014 n=3..8", "connectivity", False), ("song2014 n=3..8", "termination", False),
        ("jiang n=3..8", "connectivity", False), ("jiang n=3..8", "termination", True),
        ("wang2020 n=3..8", "connectivity", False), ("wang2020 n=3..8", "termination", True),
        ("wang2020-broadcast-handshake n=3..8", "connectivity", False),
        ("wang2020-broadcast-handshake n=3..8", "termination", True),
        ("leechong-leader n=3..8", "connectivity", False), ("leechong-leader n=3..8", "termination", True),
        ("leechong-neighbor n=3..8", "connectivity", False), ("leechong-neighbor n=3..8", "termination", True),
        ("example-anonymous-line n=3..8", "connectivity", False),
        ("example-anonymous-line n=3..8", "termination", False),
        ("example-grid-goals n=3..8", "connectivity", False), ("example-grid-goals n=3..8", "termination", False)]


# ------------------------------------------------------------ the report

def test_report_json_is_bit_identical_has_no_seconds_and_writes_no_files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    opts = {"exploration": dict(algorithms=["song2016"], properties=["collision"], max_examples=10,
                                robots=(3, 4))}
    a = run_report(["exploration"], options=opts)
    b = run_report(["exploration"], options=opts)
    assert dumps_json(a.to_json()) == dumps_json(b.to_json())
    assert os.listdir(tmp_path) == []  # without out_dir nothing is written (the row says how)
    assert a.rows[0].detail.endswith("; the file: swarmproof verify --out DIR")
    doc = a.to_json()
    assert set(doc) == {"verdict", "rows", "counts", "findings", "exit_code", "reason"}
    # the only row is an unclaimed violation: a finding, and nothing claimed was checked
    assert (doc["verdict"], doc["findings"]) == ("inconclusive", 1)
    assert doc["reason"].startswith("no row checks a claim")
    assert doc["counts"] == {"proved": 0, "held": 0, "violated": 1, "inconclusive": 0, "n/a": 0}


def test_run_report_passes_progress_and_sections_in_order():
    texts = []
    rep = run_report(["lemmas"], progress=texts.append,
                     options={"lemmas": {"ids": ["relocate_stays_in_range", "safe_region_nonempty"]}})
    assert texts == ["lemmas", "lemmas: relocate_stays_in_range", "lemmas: safe_region_nonempty"]
    assert [r.subject for r in rep.rows] == ["relocate_stays_in_range", "safe_region_nonempty"]
    assert list(rep.seconds) == ["lemmas"]
    assert list(report.SECTIONS) == ["lattices", "algorithms", "lemmas", "formulas", "exploration", "exhaustive",
                                    "recorded"]


def test_formulas_section_reports_the_exact_checks_of_003():
    from swarmproof.checkers.report import section_formulas

    rows = section_formulas()
    by = {(r.subject, r.property): r for r in rows}
    assert by[("003 Alg. 1 printed ID formula, leechong-leader-printed and -neighbor-printed (n=2..64)",
               "ids_bijective")].verdict.value == "violated"
    assert by[("003 Alg. 1 ID prose numbering (Sec. 2.1), leechong-leader and -neighbor (n=2..64)",
               "ids_bijective")].verdict.value == "proved"
    assert by[("003 Alg. 4 N_id, two-row, formula IDs (n=2..64)", "neighbor_tree")].verdict.value == "violated"
    assert by[("003 Alg. 4 N_id, two-row, prose IDs (n=2..64)", "neighbor_tree")].verdict.value == "proved"
    assert by[("003 targets of wedge (n=2..64)", "targets_distinct")].verdict.value == "proved"
    assert all(r.section == "formulas" and r.claimed for r in rows)
    assert len({r.subject for r in rows}) == len(rows)          # one check per row, variants not repeated


def test_a_plan_may_explore_fewer_examples(monkeypatch):
    from swarmproof.checkers import explore as explore_mod
    from swarmproof.checkers.report import section_exploration

    monkeypatch.setattr(explore_mod, "explore_properties", lambda algorithm=None: ("collision",))
    seen = []

    class _Rep:
        properties = {}

        def as_dict(self):
            return {"kept_assumptions": [], "broken_assumptions": [], "properties": {"collision": dict(_ENTRY)}}

    monkeypatch.setattr(explore_mod, "explore", lambda algo, props, **kw: seen.append((algo, kw["max_examples"])) or _Rep())
    rows = section_exploration(algorithms=["leechong-leader", "song2014"])
    assert seen == [("leechong-leader", 15), ("song2014", 300)]     # VerifyPlan.explore_max_examples
    assert "--max-examples 15" in rows[0].data["reproduce"]
