"""Exhaustive bounded checking (issue 33): the choice tree enumerated, pruned soundly, its
counterexamples replayed exactly; the engine's choice points and state digest."""

from __future__ import annotations

import itertools
import json
from types import SimpleNamespace

import numpy as np
import pytest
from testkit import Toggle, ToggleBuggy, toggle_start

from swarmproof.checkers.exhaustive import Bound, SequenceSearch, deviation_cost, exhaustive, search_start
from swarmproof.checkers.replay import replay_file
from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.reference_impl.engine import FaultModel, simulate
from swarmproof.reference_impl.engine.choices import (Chooser, RecordedChoices, activation_options,
                                                       canonical_bytes, state_digest)
from swarmproof.reference_impl.protocol import Params

PARAMS = Params(range=1.0, v=0.1)


def _search(algo, bound, **kw):
    return search_start(algo, None, toggle_start(), PARAMS, "no_crash", bound, **kw)


# ---------------------------------------------------------------- the choice tree, in closed form

def test_three_robots_two_steps_is_seven_squared_sequences_without_reduction():
    """Non-empty activation subsets of 3 robots: 7 options a step, 7^2 = 49 sequences over 2 steps,
    each enumerated once (the activation sequences seen are exactly the 49)."""
    seen = []
    bound = Bound(steps=2, deviations=4, kinds=("activate",))
    orig = SequenceSearch.choose

    def spy(self, kind, options, default, at=()):
        out = orig(self, kind, options, default, at)
        if len(self.trail) == 2:
            seen.append(tuple(p.options[p.idx] for p in self.trail))
        return out

    SequenceSearch.choose = spy
    try:
        out = _search(Toggle(), bound, prune=False, iterative=False)
    finally:
        SequenceSearch.choose = orig
    assert out.status == "held" and out.complete and out.runs == 49
    subsets = activation_options([1, 2, 3])
    assert len(subsets) == 7 and sorted(seen) == sorted(itertools.product(subsets, repeat=2))


@pytest.mark.parametrize("k", [0, 1, 2, 3, 4])
def test_the_deviation_budget_keeps_exactly_the_sequences_that_cost_at_most_k(k):
    """Leaving j robots out costs j: the runs are the sequences of total cost <= K, counted by
    brute force over the 49."""
    subsets = activation_options([1, 2, 3])
    want = sum(1 for a, b in itertools.product(subsets, repeat=2)
               if deviation_cost("activate", a, subsets[0]) + deviation_cost("activate", b, subsets[0]) <= k)
    out = _search(Toggle(), Bound(steps=2, deviations=k), prune=False, iterative=False)
    assert out.runs == want
    assert [1, 7, 22, 40, 49][k] == want


def test_iterative_deepening_runs_each_level_and_reports_it():
    out = _search(Toggle(), Bound(steps=2, deviations=2), prune=False)
    assert [lv["runs"] for lv in out.levels] == [1, 7, 22] and out.runs == 30
    assert all(lv["complete"] for lv in out.levels)


def test_pruning_ends_runs_at_states_explored_before_and_keeps_the_verdict():
    """Toggle's states merge (a bit flipped twice is as if never flipped, the messages name only
    the step): pruning cuts runs, never the bug."""
    bound = Bound(steps=5, deviations=2)
    plain = _search(Toggle(), bound, prune=False)
    pruned = _search(Toggle(), bound)
    assert plain.status == pruned.status == "held"
    assert pruned.pruned > 0 and pruned.runs < plain.runs
    assert pruned.levels[-1]["distinct_states"] <= plain.levels[-1]["distinct_states"]
    found = _search(ToggleBuggy(), bound)
    assert found.status == "violated"


# ---------------------------------------------------------------- the planted bug

def test_a_planted_bug_is_found_at_its_choice_sequence_with_the_fewest_deviations():
    out = _search(ToggleBuggy(), Bound(steps=4, deviations=3))
    assert out.status == "violated" and out.chooser.used == 2
    assert out.chooser.deviations() == [{"index": 0, "kind": "activate", "at": [0], "option": [2]}]
    assert "planted bug: robot 2 at step 1" in out.message
    # K = 1 cannot reach it: held within that bound
    assert _search(ToggleBuggy(), Bound(steps=4, deviations=1)).status == "held"


def test_an_uncovered_bound_is_inconclusive_with_its_coverage_never_held():
    out = _search(Toggle(), Bound(steps=2, deviations=4), prune=False, max_runs=10)
    assert out.status == "inconclusive" and not out.complete and out.runs == 10
    assert "K <= 1 covered completely" in out.message and "max_runs" in out.message


# ---------------------------------------------------------------- counterexamples replay exactly

def _trace_bytes(result):
    tr = result.trace
    return (tr.poses.tobytes(), json.dumps([list(map(repr, s)) for s in tr.states]),
            json.dumps([e.as_dict() for e in tr.events], sort_keys=True), result.status, result.steps)


def test_an_exhaustive_counterexample_replays_bit_for_bit(tmp_path):
    rep = exhaustive("testkit:ToggleBuggy", ["no_crash"], target="square", initial=toggle_start(),
                     bound=Bound(steps=4, deviations=3), out_dir=tmp_path)
    v = rep.properties["no_crash"]
    assert rep.exit_code == 1 and v.status == "violated" and v.deviations == 2 and v.counterexample_path
    cx = Counterexample.load(v.counterexample_path)
    assert cx.choices["deviations"] == [{"index": 0, "kind": "activate", "at": [0], "option": [2]}]
    assert cx.choices["kinds"] == ["activate"] and cx.choices["steps"] == 4
    text = "\n".join(cx.format_steps())
    assert "step 0: only robot 2 acts (decision 0)" in text
    rr = replay_file(v.counterexample_path)
    assert rr.reproduced and rr.step == cx.violation["step"]
    # the very run the search judged: a second replay and the search's own run give the same bytes
    again = replay_file(v.counterexample_path)
    assert _trace_bytes(rr.result) == _trace_bytes(again.result)
    out = search_start(ToggleBuggy(), None, toggle_start(), PARAMS, "no_crash",
                       Bound(steps=4, deviations=3))
    assert _trace_bytes(out.result)[0] == _trace_bytes(rr.result)[0]
    assert _trace_bytes(out.result)[2] == _trace_bytes(rr.result)[2]


def test_a_clock_phase_deviation_is_told_as_a_robot_s_phase_not_as_a_step(tmp_path):
    """A clock_phase decision's ``at`` is ``(robot,)``, made before step 0: the counterexample's
    steps said "step 1: clock_phase = 0.75" for robot 1's phase (found while measuring wang2020's
    variant, docs/exhaustive.md "Results")."""
    rep = exhaustive("testkit:ToggleBuggy", ["no_crash"], target="square", initial=toggle_start(),
                     bound=Bound(steps=4, deviations=3), out_dir=tmp_path)
    cx = Counterexample.load(rep.properties["no_crash"].counterexample_path)
    cx.choices = {**cx.choices, "kinds": ["activate", "clock_phase"],
                  "deviations": [{"index": 1, "kind": "clock_phase", "at": [1], "option": 0.75},
                                 {"index": 4, "kind": "activate", "at": [2], "option": [1, 3]}]}
    text = "\n".join(cx.format_steps())
    assert "before step 0: robot 1's clock phase is 0.75 (decision 1)" in text
    assert "step 1: clock_phase" not in text
    assert "step 2: only robots 1, 3 act (decision 4)" in text


def test_a_replay_whose_run_makes_other_decisions_is_refused(tmp_path):
    rep = exhaustive("testkit:ToggleBuggy", ["no_crash"], target="square", initial=toggle_start(),
                     bound=Bound(steps=4, deviations=3), out_dir=tmp_path)
    path = rep.properties["no_crash"].counterexample_path
    doc = json.loads(open(path, encoding="utf-8").read())
    doc["choices"]["deviations"][0]["kind"] = "loss"
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(doc, fh)
    with pytest.raises(InputFileError, match="did not make the recorded decisions"):
        replay_file(path)
    doc["choices"]["kinds"] = ["teleport"]
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(doc, fh)
    with pytest.raises(InputFileError, match="teleport"):
        replay_file(path)


def test_recorded_choices_make_the_same_decisions_and_the_rest_default():
    rc = RecordedChoices(["activate"], [{"index": 1, "kind": "activate", "option": [1, 3]}])
    r = simulate(Toggle(), None, toggle_start(), PARAMS, seed=0, max_steps=3, chooser=rc)
    assert rc.n == 3 and rc.diverged is None
    assert r.trace.meta["choices"]["kinds"] == ["activate"]
    assert [s[1][0][1] for s in r.trace.states] == [0, 1, 1, 0]     # robot 2 left out at step 1


# ---------------------------------------------------------------- liveness is never pruned

def test_a_liveness_bug_that_pruning_would_hide_is_found_without_it():
    """A property of the whole run: robot 3's bit is 0 after step 0 and 1 at the end.  With K = 1
    only the sequence leaving robot 3 out at step 0 violates it; at step 4 it reaches the state of
    the sequence leaving robot 3 out at step 1 (explored first, the same budget left): pruned
    there, its end is never seen."""
    from swarmproof.invariants.registry import Property, register_property, unregister_property
    from swarmproof.invariants.result import InvariantResult

    def check(trace, ctx):
        x3 = [dict(s[2])["x"] for s in trace.states]
        if ctx.result.status == "step_cap" and x3[1] == 0 and x3[-1] == 1:
            return InvariantResult("x3_late", "violated", "test", {"step": None}, "robot 3 started late")
        return InvariantResult("x3_late", "held", "test", None, "")

    register_property(Property("x3_late", "liveness", check), replace=True)
    try:
        bound = Bound(steps=6, deviations=1)
        sound = search_start(Toggle(), None, toggle_start(), PARAMS, "x3_late", bound)
        assert sound.status == "violated" and sound.pruned == 0
        assert sound.chooser.deviations() == [{"index": 0, "kind": "activate", "at": [0], "option": [1, 2]}]
        hidden = search_start(Toggle(), None, toggle_start(), PARAMS, "x3_late", bound, prune=True,
                              unsound_liveness_pruning=True)
        # what pruning would hide: no violation found (the runs it kept reach the bound: inconclusive)
        assert hidden.status == "inconclusive" and hidden.pruned > 0 and hidden.chooser is None
        with pytest.raises(UsageError, match="pruned run has no end"):
            search_start(Toggle(), None, toggle_start(), PARAMS, "x3_late", bound, prune=True)
    finally:
        unregister_property("x3_late")


# ---------------------------------------------------------------- the state digest

def _fake_run(**over):
    """A run's state as :func:`state_digest` reads it (two robots), with fields replaced."""
    rng = [np.random.default_rng(np.random.SeedSequence(0, spawn_key=(0, k))) for k in range(2)]
    run = SimpleNamespace(
        n_total=2, present=np.array([True, True]), poses=np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]),
        states=((("x", 0),), (("x", 1),)), robot_rngs=rng, last_msgs=[("t", 0), None], heard_msgs=[None, None],
        outbox=None, last_outbox=None, delivery=SimpleNamespace(pending={}, backlog={}),
        exchanges=SimpleNamespace(queue=[]), clocks=SimpleNamespace(), mover=SimpleNamespace(max_turn=1.0),
        t=3, quiet=0, fault_rng=np.random.default_rng(1), choices=SimpleNamespace(crashes_left=0), status=None,
        idx_l_prev=[0, 1], ids_list=[1, 2], algorithm=Toggle(), seed=0)
    for k, v in over.items():
        setattr(run, k, v)
    return run


def _advanced(seed_key):
    g = np.random.default_rng(np.random.SeedSequence(0, spawn_key=(0, seed_key)))
    g.random()
    return g


@pytest.mark.parametrize("field, value", [
    ("delivery", SimpleNamespace(pending={1: [(4, 0, 0, 1, ("t", 0))]}, backlog={})),    # a message in flight
    ("delivery", SimpleNamespace(pending={}, backlog={1: [(0, ("t", 0))]})),             # a held one
    ("exchanges", SimpleNamespace(queue=[(4, 0, "request", 0, 1, "hi", None)])),
    ("states", ((("x", 0),), (("x", 0),))),                                              # a controller field
    ("states", ((("x", 0),), (("x", 1.0),))),                                            # 1 vs 1.0
    ("poses", np.array([[0.0, 0.0, 0.0], [np.nextafter(0.5, 1), 0.0, 0.0]])),            # one bit of a pose
    ("poses", np.array([[-0.0, 0.0, 0.0], [0.5, 0.0, 0.0]])),                            # -0.0
    ("last_msgs", [("t", 0), ("t", 0)]),
    ("heard_msgs", [("t", 0), None]),
    ("present", np.array([True, False])),
    ("t", 4), ("quiet", 1), ("status", "finished"), ("idx_l_prev", [0]),
    ("choices", SimpleNamespace(crashes_left=1)),
    ("fault_rng", np.random.default_rng(2)),
    ("robot_rngs", [np.random.default_rng(np.random.SeedSequence(0, spawn_key=(0, 0))), _advanced(1)]),
    ("mover", SimpleNamespace(max_turn=1.0, cells=np.array([[0, 0], [1, 0]]))),
])
def test_the_digest_never_merges_two_states_that_differ(field, value):
    assert state_digest(_fake_run()) == state_digest(_fake_run())
    assert state_digest(_fake_run(**{field: value})) != state_digest(_fake_run())


def test_the_symmetric_digest_merges_relabelled_robots_and_only_them():
    a = _fake_run(states=((("x", 0),), (("x", 1),)), last_msgs=[None, None])
    b = _fake_run(poses=a.poses[::-1].copy(), states=a.states[::-1], last_msgs=[None, None])
    assert state_digest(a) != state_digest(b)                       # slot order differs
    assert state_digest(a, symmetric=True) == state_digest(b, symmetric=True)
    c = _fake_run(states=((("x", 1),), (("x", 1),)), last_msgs=[None, None])
    assert state_digest(a, symmetric=True) != state_digest(c, symmetric=True)
    # a message's sender is named by its key: who sent it to whom survives the relabelling
    a2 = _fake_run(last_msgs=[None, None], delivery=SimpleNamespace(pending={1: [(4, 0, 0, 1, "m")]}, backlog={}))
    b2 = _fake_run(poses=a.poses[::-1].copy(), states=a.states[::-1], last_msgs=[None, None],
                   delivery=SimpleNamespace(pending={0: [(4, 0, 1, 2, "m")]}, backlog={}))
    b3 = _fake_run(poses=a.poses[::-1].copy(), states=a.states[::-1], last_msgs=[None, None],
                   delivery=SimpleNamespace(pending={1: [(4, 0, 0, 1, "m")]}, backlog={}))
    assert state_digest(a2, symmetric=True) == state_digest(b2, symmetric=True)
    assert state_digest(a2, symmetric=True) != state_digest(b3, symmetric=True)


def test_robots_with_the_same_key_fall_back_to_slot_order():
    twin = _fake_run(poses=np.zeros((2, 3)), states=((("x", 0),), (("x", 0),)), last_msgs=[("a",), None])
    swapped = _fake_run(poses=np.zeros((2, 3)), states=((("x", 0),), (("x", 0),)), last_msgs=[None, ("a",)])
    assert state_digest(twin, symmetric=True) != state_digest(swapped, symmetric=True)


def test_canonical_bytes_orders_mappings_and_keeps_float_bits():
    assert canonical_bytes({"a": 1, "b": 2}) == canonical_bytes({"b": 2, "a": 1})
    assert canonical_bytes((1,)) != canonical_bytes((1.0,)) and canonical_bytes(0.0) != canonical_bytes(-0.0)
    assert canonical_bytes([1, 2]) != canonical_bytes((1, 2))


# ---------------------------------------------------------------- the engine's choice points

class _Defaults(Chooser):
    def __init__(self, kinds):
        self.kinds = frozenset(kinds)
        self.max_delay, self.max_crashes = 2, 1
        self.points = []

    def choose(self, kind, options, default, at=()):
        self.points.append((kind, tuple(at)))
        assert options[0] == default
        return default


def test_a_chooser_taking_every_default_gives_the_fault_free_run():
    from swarmproof.reference_impl.registry import get_algorithm

    lat_init = toggle_start()
    plain = simulate(get_algorithm("example-gather"), None, lat_init, Params(range=1.2, v=0.05), seed=3, max_steps=30)
    ch = _Defaults(("activate", "loss", "delay", "duplicate", "reorder", "crash"))
    chosen = simulate(get_algorithm("example-gather"), None, lat_init, Params(range=1.2, v=0.05), seed=3,
                      max_steps=30, chooser=ch)
    assert np.array_equal(plain.trace.poses, chosen.trace.poses) and plain.trace.states == chosen.trace.states
    kinds = {k for k, _ in ch.points}
    assert kinds == {"activate", "loss", "delay", "duplicate", "reorder", "crash"}
    assert set(chosen.broken_assumptions) >= {"synchronous_clocks", "reliable_messages", "no_crashes"}


def test_a_chooser_with_an_unknown_kind_is_a_usage_error():
    ch = _Defaults(("teleport",))
    with pytest.raises(UsageError, match="teleport"):
        simulate(Toggle(), None, toggle_start(), PARAMS, seed=0, max_steps=2, chooser=ch)


def test_chosen_crash_delay_and_loss_change_the_run_as_named():
    class Pick(_Defaults):
        def choose(self, kind, options, default, at=()):
            super().choose(kind, options, default, at)
            if kind == "crash" and at == (1,):
                return 3
            if kind == "loss" and at[:1] == (2,) and at[1:] == (1, 2):
                return True
            return default

    ch = Pick(("crash", "loss"))
    r = simulate(Toggle(), None, toggle_start(), PARAMS, seed=0, max_steps=4, chooser=ch)
    kinds = [(e.kind, e.step) for e in r.trace.events if e.kind in ("crash", "drop")]
    assert ("crash", 1) in kinds and ("drop", 2) in kinds
    assert not r.trace.present[-1][2]


def test_bounds_are_checked():
    with pytest.raises(UsageError, match=r"steps=0 \(--max-steps\)"):
        Bound(steps=0, deviations=1)
    with pytest.raises(UsageError, match="teleport"):
        Bound(steps=3, deviations=1, kinds=("teleport",))
    with pytest.raises(UsageError, match="deviations=-1"):
        Bound(steps=3, deviations=-1)
    assert Bound(steps=3, deviations=1, kinds=("loss", "activate")).kinds == ("activate", "loss")


def test_activation_of_too_many_robots_is_refused():
    with pytest.raises(UsageError, match="at most 10 robots"):
        activation_options(list(range(11)))


def test_a_late_delivery_kind_enumerates_delays_up_to_the_bound():
    out = search_start(Toggle(), None, toggle_start(), PARAMS, "no_crash",
                       Bound(steps=3, deviations=1, kinds=("delay",), max_delay=2), prune=False, iterative=False)
    # step 0 broadcasts nothing yet; steps 1 and 2 deliver 4 messages each (1->2, 2->1, 2->3, 3->2),
    # each 0, 1 or 2 steps late: 1 + 8 * 2 sequences with at most one late delivery
    assert out.status == "held" and out.runs == 17


def test_faults_given_beside_the_chooser_keep_their_own_draws():
    fm = FaultModel(message_loss=0.5)
    a = simulate(Toggle(), None, toggle_start(), PARAMS, seed=5, max_steps=6, faults=fm)
    b = simulate(Toggle(), None, toggle_start(), PARAMS, seed=5, max_steps=6, faults=fm,
                 chooser=_Defaults(("activate",)))
    assert [e.as_dict() for e in a.trace.events if e.kind == "drop"] == \
        [e.as_dict() for e in b.trace.events if e.kind == "drop"]


# ---------------------------------------------------------------- the command line

def _initial_file(tmp_path):
    path = tmp_path / "start.json"
    init = toggle_start()
    path.write_text(json.dumps({"format": "swarmproof-initial/1", "robots": [
        {"id": int(i), "pose": [float(x) for x in p]} for i, p in zip(init.ids.tolist(), init.poses.tolist())]}))
    return path


def test_cli_exhaustive_finds_writes_and_replays(cli, tmp_path):
    start = _initial_file(tmp_path)
    code, out, err = cli("explore", "testkit:ToggleBuggy", "--exhaustive", "--initial", start, "--property",
                         "no_crash", "--max-steps", "4", "--deviations", "3", "--target", "square", "--json",
                         "--out", tmp_path)
    assert code == 1, err
    doc = json.loads(out)
    v = doc["properties"]["no_crash"]
    assert doc["mode"] == "exhaustive" and v["status"] == "violated" and v["deviations"] == 2
    ex = v["exhaustive"]
    assert set(ex) >= {"runs", "distinct_states", "pruned", "symmetric_pruned", "complete", "bound"}
    assert ex["bound"] == {"steps": 4, "deviations": 3, "kinds": ["activate"]} and ex["complete"] is False
    code, out, err = cli("replay", v["counterexample_path"])
    assert code == 1 and "reproduced" in (out + err).lower()


def test_cli_exhaustive_held_names_its_bound(cli, tmp_path):
    code, out, err = cli("explore", "testkit:Toggle", "--exhaustive", "--initial", _initial_file(tmp_path),
                         "--property", "no_crash", "--max-steps", "3", "--deviations", "1", "--choices",
                         "activate,loss", "--target", "square")
    assert code == 0, err
    assert "held for every choice sequence within the bound (3 steps, K=1 deviations, choices activate, loss)" in out
    assert "the choices break: synchronous_clocks, reliable_messages" in out


def test_cli_exhaustive_out_of_runs_is_inconclusive_exit_3(cli, tmp_path):
    code, out, err = cli("explore", "testkit:Toggle", "--exhaustive", "--initial", _initial_file(tmp_path),
                         "--property", "no_crash", "--max-steps", "4", "--deviations", "3", "--max-runs", "5",
                         "--target", "square")
    assert code == 3 and "inconclusive" in out and "max_runs spent before the bound was covered" in out


@pytest.mark.parametrize("argv, match", [
    (["--choices", "activate,teleport"], "choice kind='teleport' is not known"),
    (["--deviations", "-1"], "deviations=-1 (--deviations) must be an integer >= 0"),
    (["--max-steps", "0"], "steps=0 (--max-steps) must be an integer >= 1"),
    (["--fault", "delays"], "--fault is for sampling exploration"),
    (["--max-examples", "5"], "--max-examples is for sampling exploration"),
    (["--max-runs", "0"], "max_runs=0 (--max-runs) must be an integer >= 1"),
    (["--robots", "4"], "disagrees with --initial"),
])
def test_cli_exhaustive_bad_input_exit_2(cli, tmp_path, argv, match):
    code, out, err = cli("explore", "testkit:Toggle", "--exhaustive", "--initial", _initial_file(tmp_path),
                         "--target", "square", *argv)
    assert code == 2 and match in err, err
    assert "Traceback" not in err


def test_cli_exhaustive_only_flags_need_exhaustive(cli):
    code, out, err = cli("explore", "song2014", "--deviations", "2")
    assert code == 2 and "--deviations is for exhaustive checking only" in err


# ---------------------------------------------------------------- verify's exhaustive rows

def test_verify_has_exhaustive_rows_bounded_by_steps_k_and_kinds_and_the_baseline_records_coverage(tmp_path):
    from swarmproof.checkers.baseline import Baseline
    from swarmproof.checkers.gate import verify

    path = tmp_path / "base.json"
    rep = verify(algorithms=["testkit:ToggleRows"], sections=["exhaustive"], baseline=path, update_baseline=True,
                 out_dir=tmp_path / "cx")
    rows = {r.subject: r for r in rep.rows}
    assert set(rows) == {"toggle-rows n=3 activate S=4 K=3", "toggle-rows n=3 loss S=3 K=1"}
    bad, good = rows["toggle-rows n=3 activate S=4 K=3"], rows["toggle-rows n=3 loss S=3 K=1"]
    assert bad.verdict.value == "violated" and bad.data["deviations"] == 2 and bad.claim is None
    assert "the choices break synchronous_clocks" in bad.detail and bad.data["counterexample"]
    assert good.verdict.value == "held" and good.data["exhaustive"]["complete"] is True
    assert good.data["reproduce"].startswith("swarmproof explore testkit:ToggleRows --exhaustive --property "
                                             "no_crash --choices loss --max-steps 3 --deviations 1 --robots 3 --seed 0 "
                                             "--starts 1")
    doc = json.loads(path.read_text())
    saved = {r["subject"]: r for r in doc["rows"]}
    assert saved["toggle-rows n=3 loss S=3 K=1"]["exhaustive"] == {
        "complete": True, "bound": {"steps": 3, "deviations": 1, "kinds": ["loss"]}}
    assert saved["toggle-rows n=3 activate S=4 K=3"]["exhaustive"]["complete"] is False
    assert Baseline.load(path).rows[("exhaustive", "toggle-rows n=3 loss S=3 K=1", "no_crash")].exhaustive[
        "complete"] is True
    again = verify(algorithms=["testkit:ToggleRows"], sections=["exhaustive"], baseline=path)
    assert again.comparison.exit_code == 0 and {c.outcome for c in again.comparison.changes} <= {"same", "known"}


# ---------------------------------------------------------------- campaign cells

EXHAUSTIVE_CAMPAIGN = """\
format: swarmproof-campaign/1
name: exhaustive-small
exhaustive:
  - algorithm: song2014
    properties: [connectivity]
    robots: [3]
    seeds: [0, 1]
    choices: [activate]
    steps: 10
    deviations: 1
"""


def test_a_campaign_s_exhaustive_cell_plans_a_task_per_start_and_a_task_is_the_search():
    from swarmproof.checkers.campaign import plan_tasks, run_task
    from swarmproof.models.campaign_spec import loads_campaign

    tasks = plan_tasks(loads_campaign(EXHAUSTIVE_CAMPAIGN))
    assert [t.key for t in tasks] == ["exhaustive[0]/connectivity/n3/seed0", "exhaustive[0]/connectivity/n3/seed1"]
    assert {t.cell for t in tasks} == {"exhaustive[0] song2014 activate S=10 K=1"}
    out = run_task({"kind": "exhaustive", "args": tasks[1].args})
    direct = exhaustive("song2014", ["connectivity"], robots=3, seed=1,
                        bound=Bound(steps=10, deviations=1)).properties["connectivity"]
    assert out["verdict"] == "held" and out["figures"]["complete"] is True
    assert (out["figures"]["runs"], out["figures"]["distinct_states"]) == (direct.runs, direct.distinct_states)
    assert out["figures"]["claim"] is None and out["figures"]["broken_assumptions"] == "synchronous_clocks"


@pytest.mark.parametrize("cell, match, fld", [
    ("    choices: [teleport]\n", "choice kind='teleport' is not known", "exhaustive[0].choices"),
    ("    properties: [conectivity]\n", "property='conectivity' is not registered", "exhaustive[0].properties[0]"),
    ("    steps: 0\n", "exhaustive[0].steps=0 must be an integer in 1..1000000", "exhaustive[0].steps"),
    ("    bound: 3\n", "key 'bound' is not known here", "exhaustive[0].bound"),
])
def test_bad_exhaustive_cells_are_located(cell, match, fld):
    from swarmproof.checkers.campaign import plan_tasks
    from swarmproof.models.campaign_spec import loads_campaign

    text = "format: swarmproof-campaign/1\nname: bad\nexhaustive:\n  - algorithm: song2014\n" + cell
    with pytest.raises(InputFileError) as info:
        plan_tasks(loads_campaign(text))
    assert match in str(info.value) and info.value.field == fld


# slow by nature: a real `dask scheduler` and `dask worker` subprocesses (as the other campaigns' test)
@pytest.mark.slow
def test_exhaustive_cells_on_a_real_scheduler_give_the_direct_results(tmp_path):
    import importlib.util
    import pathlib

    from swarmproof.checkers.campaign import run_campaign
    from swarmproof.models.campaign_spec import loads_campaign

    path = pathlib.Path(__file__).with_name("test_campaign.py")
    spec_ = importlib.util.spec_from_file_location("campaign_tests", path)
    mod = importlib.util.module_from_spec(spec_)
    spec_.loader.exec_module(mod)
    addr, procs = mod._start_cluster(tmp_path)
    try:
        res = run_campaign(loads_campaign(EXHAUSTIVE_CAMPAIGN), out_dir=str(tmp_path / "remote"), scheduler=addr)
    finally:
        mod._stop(procs)
    assert res.exit_code == 0 and res.ran == 2
    for seed in (0, 1):
        direct = exhaustive("song2014", ["connectivity"], robots=3, seed=seed,
                            bound=Bound(steps=10, deviations=1)).properties["connectivity"]
        got = res.results[f"exhaustive[0]/connectivity/n3/seed{seed}"]
        assert got["figures"]["runs"] == direct.runs and got["verdict"] == "held"
    from swarmproof.checkers.campaign_report import write_report

    report = open(write_report(res), encoding="utf-8").read()
    assert "## exhaustive[0] song2014 activate S=10 K=1" in report and "| connectivity | 3 | seed 1 | held |" in report


# ---------------------------------------------------------------- Hypothesis-drawn starts

def test_drawn_starts_are_searched_and_a_violating_one_shrinks_to_the_smallest_team():
    bound = Bound(steps=3, deviations=2)
    a = exhaustive("testkit:ToggleRows", ["no_crash"], target="square", draw_starts=4, draw_robots=(3, 5),
                   bound=bound).properties["no_crash"]
    b = exhaustive("testkit:ToggleRows", ["no_crash"], target="square", draw_starts=4, draw_robots=(3, 5),
                   bound=bound).properties["no_crash"]
    assert a.status == "violated" and len(a.counterexample.robots) == 3 and a.deviations <= 2
    assert "shrunk" in a.message and a.counterexample == b.counterexample      # the same, seed for seed
    held = exhaustive("testkit:Toggle", ["no_crash"], target="square", draw_starts=3, draw_robots=(3, 4),
                      bound=Bound(steps=2, deviations=1)).properties["no_crash"]
    assert held.status == "held" and held.starts == 3 and "from 3 drawn start(s) of 3..4 robots" in held.message


def test_cli_drawn_starts_refuse_a_given_start(cli, tmp_path):
    code, out, err = cli("explore", "testkit:Toggle", "--exhaustive", "--initial", _initial_file(tmp_path),
                         "--draw-starts", "3", "--target", "square")
    assert code == 2 and "--draw-starts draws the starts: not with --initial or --starts" in err


@pytest.mark.parametrize("edit, match", [
    (lambda d: d["choices"]["deviations"][0].update(option=[1, 2, 3]), "lists the default"),
    (lambda d: d["choices"]["deviations"][0].update(index=100000), "a deviation at decision 100000"),
    (lambda d: d["choices"]["deviations"][0].update(at=[3]), r"places it at \[3\]"),
    (lambda d: d["choices"].update(choice_points=7), "choice_points=7"),
])
def test_a_replay_refuses_choices_that_do_not_fit_the_run(tmp_path, edit, match):
    rep = exhaustive("testkit:ToggleBuggy", ["no_crash"], target="square", initial=toggle_start(),
                     bound=Bound(steps=4, deviations=3), out_dir=tmp_path)
    path = rep.properties["no_crash"].counterexample_path
    doc = json.loads(open(path, encoding="utf-8").read())
    edit(doc)
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(doc, fh)
    with pytest.raises(InputFileError, match=match):
        replay_file(path)


def test_kinds_the_model_has_no_decision_of_are_refused_before_any_run():
    with pytest.raises(UsageError, match="synchronous clocks"):
        exhaustive("testkit:Toggle", ["no_crash"], target="square", initial=toggle_start(),
                   bound=Bound(steps=2, deviations=1, kinds=("clock_phase",)))
    with pytest.raises(UsageError, match="at most 10 robots"):
        exhaustive("song2014", ["connectivity"], robots=11, starts=1, bound=Bound(steps=2, deviations=1))
    with pytest.raises(UsageError, match="the delay kind needs a delay"):
        Bound(steps=2, deviations=1, kinds=("delay",), max_delay=0)


def test_a_vacuous_safety_verdict_is_not_held():
    from swarmproof.invariants.registry import Property, register_property, unregister_property
    from swarmproof.invariants.result import InvariantResult

    register_property(Property("nothing_to_check", "safety",
                               lambda trace, ctx: InvariantResult("nothing_to_check", "inconclusive", "test", None,
                                                                  "vacuous: nothing to judge")), replace=True)
    try:
        out = search_start(Toggle(), None, toggle_start(), PARAMS, "nothing_to_check", Bound(steps=2, deviations=1))
        assert out.status == "inconclusive" and "could not be judged (vacuous: nothing to judge)" in out.message
    finally:
        unregister_property("nothing_to_check")


def test_a_kind_that_never_arose_is_named_in_the_held_message():
    v = exhaustive("testkit:Toggle", ["no_crash"], target="square", initial=toggle_start(),
                   bound=Bound(steps=2, deviations=1, kinds=("activate", "crash"), max_crashes=1)).properties["no_crash"]
    assert v.status == "held" and "no decision of kind" not in v.message
    v = exhaustive("testkit:Toggle", ["no_crash"], target="square", initial=toggle_start(),
                   bound=Bound(steps=1, deviations=1, kinds=("delay",))).properties["no_crash"]
    assert v.status == "held" and "no decision of the kinds asked arose" in v.message


def test_the_symmetric_digest_keeps_generators_once_a_robot_drew():
    run = _fake_run(states=((("x", 0),), (("x", 1),)), last_msgs=[None, None])
    swapped = _fake_run(poses=run.poses[::-1].copy(), states=run.states[::-1], last_msgs=[None, None])
    run.seed = swapped.seed = 0
    assert state_digest(run, symmetric=True) == state_digest(swapped, symmetric=True)
    run.robot_rngs[0].random()          # robot 0 drew: its generator is part of it now
    swapped.robot_rngs[0].random()
    assert state_digest(run, symmetric=True) != state_digest(swapped, symmetric=True)
