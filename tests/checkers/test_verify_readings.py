"""Issue 19 in ``swarmproof verify``: both readings of song2016's parent rule are judged, the
literal one where its deadlock appears, and Lemma 11's row shows the one-step-lag break; each
violated row can be repeated (the simulate command) and replayed (``--out``).  Issue 31: the
subtree-clock reading of the movement timeout is judged beside the default too."""

from __future__ import annotations

import pytest

import json

from swarmproof.checkers.replay import replay_file
from swarmproof.checkers.report import section_algorithms
from swarmproof.models.verdict import NOT_APPLICABLE, Verdict
from swarmproof.reference_impl import registry


def _only(monkeypatch, name, plan):
    monkeypatch.setattr(registry, "verify_plans", lambda: [(name, plan)])


@pytest.mark.slow   # 7 s CPU (issue 32's time trim); test_song2016.py's test_literal_line_12_deadlocks_short_of_the_lattice keeps the deadlock, make verify its row
def test_the_literal_reading_deadlocks_in_verify_and_the_counterexample_replays(monkeypatch, tmp_path):
    plans = dict(registry.verify_plans())
    _only(monkeypatch, "song2016-literal", plans["song2016-literal"])
    rows = {r.property: r for r in section_algorithms(out_dir=str(tmp_path))}
    term = rows["termination"]
    assert term.subject == "song2016-literal hexagon n=40" and term.claimed
    assert term.verdict is Verdict.VIOLATED and "deadlock" in term.detail
    assert "no unstable robot remains" in term.detail
    assert rows["formation"].verdict is Verdict.VIOLATED
    assert rows["connectivity"].verdict is Verdict.HELD
    data = term.to_json()
    assert data["reproduce"] == "swarmproof simulate song2016-literal --target hexagon --robots 40 --seed 2"
    path = data["counterexample"]
    assert json.loads(open(path, encoding="utf-8").read())["algorithm"] == "song2016-literal"
    rep = replay_file(path)
    assert rep.reproduced and rep.verdict.status == "violated"
    assert rep.verdict.witness["deadlock"] is True


def test_song2016_lemma_11_row_shows_the_one_step_lag(monkeypatch):
    from swarmproof.reference_impl.protocol import VerifyPlan

    base = dict(registry.verify_plans())["song2016"]
    _only(monkeypatch, "song2016", VerifyPlan(targets=(), more=base.more))
    rows = {r.property: r for r in section_algorithms()}
    links = rows["tree_links"]
    assert links.subject == "song2016 square n=20" and links.claimed
    assert links.verdict is Verdict.VIOLATED
    assert "step 344: the link child 2 -> parent 16 broke" in links.detail
    assert "messages take one step" in links.detail and "Lemma 11" in links.detail
    assert links.to_json()["reproduce"] == "swarmproof simulate song2016 --target square --robots 20 --seed 1"
    assert rows["connectivity"].verdict is Verdict.HELD and rows["termination"].verdict is Verdict.HELD


def test_the_subtree_clock_reading_is_judged_beside_the_default(monkeypatch):
    from swarmproof.reference_impl.protocol import VerifyPlan

    plan = dict(registry.verify_plans())["song2016-subtree-clock"]
    assert plan.runs()[0] == ("square", 10, (0, 1, 2))
    _only(monkeypatch, "song2016-subtree-clock", VerifyPlan(targets=("square",), robots=10, seeds=(0,)))
    rows = {r.property: r for r in section_algorithms()}
    assert set(rows) == {"termination", "formation", "connectivity", "tree_links", "completion_sound"}
    # 001's robots detect no completion: no verdict (an n/a row, not claimed)
    assert rows.pop("completion_sound").verdict is NOT_APPLICABLE
    for r in rows.values():
        assert r.subject == "song2016-subtree-clock square n=10" and r.claimed
        assert r.verdict is Verdict.HELD, r.detail
    assert rows["termination"].claim.startswith("001 Thm. 13")
