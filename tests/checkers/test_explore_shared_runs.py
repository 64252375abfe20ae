"""One explore call over several properties shares its runs between them (checkers/explore.py,
``_SharedRuns``): every property's verdict, counts and counterexample are those of exploring it
alone, bit for bit, and the engine runs fewer times."""

from __future__ import annotations

import pytest

from swarmproof.checkers import explore as explore_mod

_TIMING = ("seconds", "first_failure_seconds", "first_failure_cpu")


def _entries(report) -> dict:
    out = {}
    for name, entry in report.as_dict()["properties"].items():
        out[name] = {k: v for k, v in entry.items() if k not in _TIMING}
    return out


def _cx(report) -> dict:
    return {name: (v.counterexample.as_dict() if v.counterexample is not None else None)
            for name, v in report.properties.items()}


@pytest.mark.parametrize("algorithm,props,robots", [
    # held and violated properties, and oscillation, whose early-stop runs are not shared
    ("song2014", ("connectivity", "collision", "termination", "oscillation"), (3, 6)),
    # several violated properties whose shrinking meets the same scenarios (35 s: slow suite)
    pytest.param("leechong-leader", ("termination", "formation", "deadlock"), (8, 9), marks=pytest.mark.slow),
])
def test_shared_runs_give_the_verdicts_of_one_call_per_property(monkeypatch, algorithm, props, robots):
    runs = []
    real = explore_mod.run_scenario

    def counting(*a, **k):
        runs.append(1)
        return real(*a, **k)

    monkeypatch.setattr(explore_mod, "run_scenario", counting)
    # judge every later property for sharing, whatever it costs (by default one that costs more
    # than SHARE_JUDGE_FRACTION of a run is not: a timing-based choice that changes no outcome)
    monkeypatch.setattr(explore_mod, "SHARE_JUDGE_FRACTION", float("inf"))
    kw = dict(budget=None, max_examples=8, robots=robots, seed=0)
    together = explore_mod.explore(algorithm, list(props), **kw)
    shared_runs = len(runs)
    runs.clear()
    alone = [explore_mod.explore(algorithm, [p], **kw) for p in props]
    separate_runs = len(runs)
    merged_entries, merged_cx = {}, {}
    for rep in alone:
        merged_entries.update(_entries(rep))
        merged_cx.update(_cx(rep))
    assert _entries(together) == merged_entries
    assert _cx(together) == merged_cx
    assert any(e["status"] == "violated" for e in merged_entries.values())
    # the engine ran fewer times: a later property read at least a whole search's worth of runs
    # made for an earlier one (here termination, every scenario of collision's)
    assert shared_runs <= separate_runs - kw["max_examples"], (shared_runs, separate_runs)


@pytest.mark.slow   # 8 s CPU (issue 32's time trim); test_shared_runs_give_the_verdicts_of_one_call_per_property keeps shared runs covered
def test_sharing_only_cheap_judgments_changes_no_outcome():
    """By default a later property is judged for sharing only while its judgments are cheap
    against a run (SHARE_JUDGE_FRACTION); with the default, the verdicts are those of one call
    per property (wang2020: asynchronous agents on a grid, a
    violated property between held ones)."""
    kw = dict(budget=None, max_examples=12, robots=(3, 8), seed=0)
    props = ["formation", "collision", "termination"]
    alone = {}
    for p in props:
        alone.update(_entries(explore_mod.explore("wang2020", [p], **kw)))
    assert _entries(explore_mod.explore("wang2020", props, **kw)) == alone
    assert alone["formation"]["status"] == "violated" and alone["termination"]["status"] == "held"


def test_a_judgment_that_raises_is_not_shared(monkeypatch):
    """A later property whose judgment raises is not stored: its own search runs the scenario and
    meets the error there, as it would alone."""
    shared = explore_mod._SharedRuns()
    ran = explore_mod._Ran(3, "finished", None, 10, (), None)
    shared.put("k", ran, {"termination": "t"})
    assert shared.get("k", "termination") == (ran, "t", None)
    assert shared.get("k", "formation") is None
    crashed = explore_mod._Ran(3, "crashed", {"error": "E"}, 10, (), None)
    shared.put("c", crashed, {"termination": "t"})          # no no_crash judgment: not usable
    assert shared.get("c", "termination") is None
