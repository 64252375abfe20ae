"""Not applicable is no verdict (DESIGN.md sections 1 and 5): decided from the property's needs and
the algorithm's declarations before any run, counted apart in verify, never inconclusive."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import pytest

from swarmproof.checkers import report as report_mod
from swarmproof.checkers.baseline import Baseline, compare
from swarmproof.checkers.report import Report, Row, Subject, not_applicable_row
from swarmproof.invariants.capabilities import missing, not_applicable
from swarmproof.invariants.registry import Property, get_property
from swarmproof.models.errors import UsageError
from swarmproof.models.verdict import NOT_APPLICABLE, Verdict
from swarmproof.reference_impl.protocol import RobotModel, VerifyPlan
from swarmproof.reference_impl.registry import algorithm_factory


def _na(name: str, prop: str):
    return get_property(prop).not_applicable_to(algorithm_factory(name))


# -- what the declarations decide ---------------------------------------------------------------

CASES = [
    ("jiang", "connectivity", "no range graph: every robot hears every robot (communication='all')"),
    ("leechong-leader", "connectivity", "no range graph: every robot hears every robot (communication='all')"),
    ("wang2020", "tree_links", "no 'parent' field in its controller states (state_fields=())"),
    ("leechong-neighbor", "tree_links", "no 'parent' field in its controller states (state_fields=('id', "
                                        "'failed')); no range graph: every robot hears every robot "
                                        "(communication='all')"),
    ("example-grid-goals", "premises", "it declares no lemma premise monitors (premise_monitors)"),
    ("song2016", "invariants", "it declares no runtime invariants (invariants)"),
    ("song2016", "connectivity", None),
    ("song2014", "tree_links", None),
    ("wang2020", "connectivity", None),
    ("jiang", "invariants", None),
    ("jiang", "collision", None),
]


@pytest.mark.parametrize("algo,prop,why", CASES, ids=[f"{a}-{p}" for a, p, _ in CASES])
def test_declarations_decide_not_applicable(algo, prop, why):
    assert _na(algo, prop) == why


def test_an_undeclared_capability_is_left_to_the_run():
    # a user's class that does not say whether its states name a parent: tree_links still runs
    User = type("User", (), {"model": RobotModel()})
    assert missing(User, ("parent", "range_graph")) == ()
    assert get_property("tree_links").not_applicable_to(User) is None


def test_a_property_declares_its_needs_and_an_unknown_need_is_refused():
    assert get_property("connectivity").needs == ("range_graph",)
    assert get_property("tree_links").needs == ("parent", "range_graph")
    p = Property("needs_messages", "safety", lambda t, c: None, needs="messages")
    Silent = type("Silent", (), {"model": RobotModel(sensing="anonymous", communication="none")})
    assert p.not_applicable_to(Silent) == "no messages: its robots send none (communication='none')"
    with pytest.raises(UsageError, match="needs='a_graph' is not a need swarmproof knows"):
        Property("bad", "safety", lambda t, c: None, needs=("a_graph",))


def test_lattice_target_need_reads_the_target_or_the_algorithms_targets():
    from swarmproof.models.targets import resolve_target

    lines = algorithm_factory("example-anonymous-line")
    assert not_applicable(lines, ("lattice_target",)) == "no lattice target: it forms lines targets (explore_targets)"
    assert not_applicable(algorithm_factory("song2016"), ("lattice_target",)) is None
    assert not_applicable(algorithm_factory("song2016"), ("lattice_target",), resolve_target("shape:letter-l")) \
        == "no lattice target: the target is a 'shape'"


# -- verify: rows, counts, outputs ----------------------------------------------------------------

def _report():
    rows = [Row("algorithms", "a t n=3", "formation", Verdict.HELD, "3/3 runs held", {"algorithm": "a"}),
            Row("algorithms", "a t n=3", "termination", Verdict.INCONCLUSIVE, "step cap", {"algorithm": "a"},
                claim=None),
            not_applicable_row("algorithms", "a t n=3", "connectivity",
                               "no range graph: every robot hears every robot (communication='all')",
                               {"algorithm": "a"}, "a claim")]
    return Report(rows)


def test_verify_counts_not_applicable_apart_from_inconclusive():
    rep = _report()
    assert rep.counts() == {"proved": 0, "held": 1, "violated": 0, "inconclusive": 1, "n/a": 1}
    # the claimed n/a row decides nothing: the claims held
    assert rep.verdict is Verdict.HELD and rep.exit_code == 0
    table = rep.format_table().splitlines()
    assert table[-1] == "verify: HELD (0 proved, 1 held, 0 violated, 1 inconclusive; 1 n/a (not applicable))"
    assert any(line.split()[3:5] == ["connectivity", "n/a"] for line in table if line.startswith("a t n=3"))
    doc = rep.to_json()
    assert doc["counts"]["n/a"] == 1 and doc["counts"]["inconclusive"] == 1
    na_row = doc["rows"][2]
    assert na_row["verdict"] == "n/a" and na_row["not_applicable"].startswith("no range graph")
    assert na_row["detail"] == "not applicable: no range graph: every robot hears every robot (communication='all')"


def test_only_not_applicable_claims_are_nothing_checked():
    rep = Report([not_applicable_row("exploration", "a n=3..8", "connectivity", "no range graph", {}, "c")])
    assert rep.verdict is Verdict.INCONCLUSIVE and rep.exit_code == 3


def test_junit_markdown_html_show_not_applicable_apart():
    from swarmproof.checkers.ci_outputs import junit_xml, markdown
    from swarmproof.checkers.html_report import render_html

    rep = _report()
    root = ET.fromstring(junit_xml(rep))
    case = next(c for c in root.iter("testcase") if c.get("name") == "connectivity")
    skipped = case.find("skipped")
    assert skipped is not None and skipped.get("type") == "n/a"
    assert skipped.get("message") == "not applicable: no range graph: every robot hears every robot (communication='all')"
    md = markdown(rep)
    assert "| algorithms | a t n=3 | connectivity | n/a | skipped: not applicable: no range graph" in md
    assert "1 n/a (not applicable)" in md
    html = render_html(rep, pictures=False)
    assert 'class="row skipped na" data-verdict="n/a"' in html


def test_unclaimed_legend_says_paper_only_for_an_algorithm_with_one():
    row = Row("algorithms", "u t n=3", "connectivity", Verdict.VIOLATED, "split", {"algorithm": "u"}, claim=None)
    assert Report([row]).legend().startswith("* not claimed by the algorithm:")
    paper_row = Row("algorithms", "s t n=3", "connectivity", Verdict.VIOLATED, "split", {"algorithm": "s"},
                    claim=None, paper="000")
    assert Report([paper_row]).legend().startswith("* not claimed by the paper:")


def test_exploration_section_runs_nothing_for_a_not_applicable_row(monkeypatch):
    def boom(*a, **k):
        raise AssertionError("an n/a row must not be explored")

    monkeypatch.setattr(report_mod, "_explore_one", boom)
    subj = Subject("jiang", "jiang", VerifyPlan(), {"connectivity": None}, algorithm_factory("jiang"))
    rows = report_mod.section_exploration(subjects=[subj], properties=("connectivity", "tree_links", "premises"))
    assert [r.verdict for r in rows] == [NOT_APPLICABLE] * 3
    assert rows[0].data["not_applicable"] == "no range graph: every robot hears every robot (communication='all')"
    assert rows[0].data["explored"] is False and rows[0].subject == "jiang n=3..8"


def test_algorithms_section_runs_nothing_when_every_row_is_not_applicable(monkeypatch):
    import swarmproof.checkers.runs as runs

    def boom(*a, **k):
        raise AssertionError("nothing applicable: nothing to run")

    monkeypatch.setattr(runs, "run_and_check", boom)
    plan = VerifyPlan(("lines:wedge",), robots=4, seeds=(0,))
    subj = Subject("leechong-leader", "leechong-leader", plan, {}, algorithm_factory("leechong-leader"))
    rows = report_mod.section_algorithms(subjects=[subj], properties=("connectivity", "tree_links"))
    assert [(r.property, r.verdict) for r in rows] == [("connectivity", NOT_APPLICABLE),
                                                       ("tree_links", NOT_APPLICABLE)]


# -- baseline -----------------------------------------------------------------------------------

def _baseline(verdict: str, claim=None):
    return Baseline.from_json({"format": "swarmproof-baseline/1", "rows": [
        {"section": "algorithms", "subject": "a t n=3", "property": "connectivity", "verdict": verdict,
         "claim": claim}]})


NA_ROW = not_applicable_row("algorithms", "a t n=3", "connectivity", "no range graph", {"algorithm": "a"}, None)


def test_inconclusive_then_not_applicable_is_no_regression():
    c = compare([NA_ROW], _baseline("inconclusive"))
    assert [ch.outcome for ch in c.changes] == ["n/a"] and c.exit_code == 0
    assert compare([NA_ROW], _baseline("inconclusive"), strict=True).exit_code == 0
    assert "1 n/a (not applicable)" in c.summary_line()


def test_a_verdict_then_not_applicable_fails_only_strict():
    assert compare([NA_ROW], _baseline("held")).exit_code == 0
    assert compare([NA_ROW], _baseline("held"), strict=True).exit_code == 1


def test_not_applicable_in_both_is_same_and_a_new_verdict_is_judged_by_its_claim():
    assert [ch.outcome for ch in compare([NA_ROW], _baseline("n/a")).changes] == ["same"]
    now = Row("algorithms", "a t n=3", "connectivity", Verdict.VIOLATED, "split", {"algorithm": "a"}, claim="c")
    c = compare([now], _baseline("n/a", "c"))
    assert [ch.outcome for ch in c.changes] == ["new"] and c.exit_code == 1


def test_baseline_records_not_applicable_rows_as_such(tmp_path):
    b = Baseline.from_rows([NA_ROW], {"max_examples": 1, "robots": [3, 8], "seed": 0})
    path = b.save(tmp_path / "b.json")
    doc = json.loads(open(path).read())
    assert doc["rows"][0]["verdict"] == "n/a"
    assert Baseline.load(path).rows[("algorithms", "a t n=3", "connectivity")].verdict is NOT_APPLICABLE


# -- explore ------------------------------------------------------------------------------------

def test_explore_says_not_applicable_and_runs_nothing(capsys):
    from swarmproof.cli import main

    code = main(["explore", "jiang", "--property", "connectivity", "--max-examples", "2", "--budget", "none",
                 "--json"])
    doc = json.loads(capsys.readouterr().out)
    entry = doc["properties"]["connectivity"]
    assert entry["status"] == "not_applicable" and entry["scenarios"] == 0
    assert entry["message"] == "not applicable: no range graph: every robot hears every robot (communication='all')"
    assert code == 3            # nothing asked for was applicable: nothing was checked
    code = main(["explore", "jiang", "--property", "connectivity", "--max-examples", "2", "--budget", "none"])
    out = capsys.readouterr().out
    assert "  connectivity  n/a          not applicable: no range graph" in out


def test_a_report_without_claimed_rows_says_why_it_is_inconclusive():
    """Issue 29: `verify --algorithm example-gather --section exploration` said INCONCLUSIVE with no
    reason: no row checks a claim, so nothing was judged (never a pass); the summary and JSON say so."""
    rows = [Row("exploration", "example-gather n=3..8", "termination", Verdict.HELD, "held", {"algorithm": "example-gather"},
                claim=None),
            Row("exploration", "example-gather n=3..8", "collision", Verdict.VIOLATED, "overlap",
                {"algorithm": "example-gather"}, claim=None)]
    rep = Report(rows)
    assert rep.verdict is Verdict.INCONCLUSIVE and rep.exit_code == 3
    last = rep.format_table().splitlines()[-1]
    assert last.startswith("verify: INCONCLUSIVE (0 proved, 1 held, 1 violated, 0 inconclusive): no row checks a "
                           "claim (example-gather claims none of these properties), so nothing was judged")
    assert rep.to_json()["reason"].startswith("no row checks a claim")
    claimed = Report(rows + [Row("exploration", "s n=3..8", "termination", Verdict.HELD, "held", {"algorithm": "s"},
                                 claim="001 Thm. 13")])
    assert "reason" not in claimed.to_json() and "nothing was judged" not in claimed.format_table()
