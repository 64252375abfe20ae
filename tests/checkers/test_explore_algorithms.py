"""The explorer on algorithm classes (not registry names), the lemma premise property, and the
no-progress rule of oscillation for randomized algorithms (issue 6).

The algorithms below are test-only and defined at module level, so a counterexample file can
name them as ``module:qualname`` and replay can import them again.
"""

from __future__ import annotations

import json
import math

import pytest

from swarmproof.checkers.explore import explore, resolve_algorithm
from swarmproof.checkers.replay import replay_file
from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.reference_impl.examples.algorithms import GatherToLowestId
from swarmproof.reference_impl.protocol import Command
from swarmproof.reference_impl.song2016.algorithm import Song2016


# -- test-only algorithms ---------------------------------------------------------------

class _RootDriftsController:
    """Mutation of song2016: the root drifts forward (001 Sec. V-C: the root never moves)."""

    def __init__(self, inner, robot_id, params):
        self.inner, self.robot_id, self.params = inner, robot_id, params

    def step(self, obs):
        cmd = self.inner.step(obs)
        if dict(self.inner.state()).get("root_id") == self.robot_id:
            return Command(cmd.message, 0.0, 0.5 * self.params.v * self.params.dt)
        return cmd

    def state(self):
        return self.inner.state()


class RootDrifts(Song2016):
    """song2016 with a drifting root; keeps the name, so song2016's premise monitors apply."""

    def controller(self, robot_id, params, lattice, rng):
        return _RootDriftsController(super().controller(robot_id, params, lattice, rng), robot_id, params)


def _arrived(ids, poses, states):
    return float(sum(bool(dict(s)["arrived"]) for s in states))


class _LazyMarchController:
    """Drive straight ahead until ``march`` (params.extra, default 1.0) is covered, resting in
    each step with probability 1/2 (the robot's own generator)."""

    def __init__(self, params, rng):
        self.params, self.rng = params, rng
        self.goal = float(params.extra.get("march", 1.0))
        self.travelled = 0.0

    def step(self, obs):
        left = self.goal - self.travelled
        if left <= 1e-12 or self.rng.random() < 0.5:
            return Command(None, 0.0, 0.0)
        d = min(left, self.params.v * self.params.dt)
        self.travelled += d
        return Command(None, 0.0, d)

    def state(self):
        return (("travelled", round(self.travelled, 9)), ("arrived", self.goal - self.travelled <= 1e-12))


def _travelled(ids, poses, states):
    return float(sum(dict(s)["travelled"] for s in states))


class LazyMarch(GatherToLowestId):
    """A randomized algorithm that makes progress: the distance covered only grows, until every
    robot has covered its march (then it is finished)."""

    name = "lazy-march"
    randomized = True
    claims = {"termination": "test: finishes", "formation": None}

    def controller(self, robot_id, params, lattice, rng):
        return _LazyMarchController(params, rng)

    def finished(self, states):
        return all(dict(s)["arrived"] for s in states)

    progress_measure = staticmethod(_travelled)


class _DitherController:
    def __init__(self, params, rng):
        self.params, self.rng = params, rng

    def step(self, obs):
        return Command(("arrived", False), float(self.rng.uniform(-math.pi, math.pi)), self.params.v * self.params.dt)

    def state(self):
        return (("arrived", False),)


class Dither(GatherToLowestId):
    """A randomized algorithm that never gets anywhere: random headings, no robot ever arrives."""

    name = "dither"
    randomized = True

    def controller(self, robot_id, params, lattice, rng):
        return _DitherController(params, rng)

    def finished(self, states):
        return False

    progress_measure = staticmethod(_arrived)


class DitherNoMeasure(Dither):
    """The same without a progress measure: nothing to judge progress by."""

    name = "dither-unmeasured"
    progress_measure = None


def make_lazy_march():
    """A factory function (not a class) is accepted too."""
    return LazyMarch()


SMALL = dict(robots=(3, 4), lattices=["square"], seed=0)


# -- algorithm classes and factories -----------------------------------------------------

def test_class_and_factory_resolve_with_claims_and_a_module_reference():
    s = resolve_algorithm(LazyMarch)
    assert (s.label, s.ref) == ("lazy-march", f"{__name__}:LazyMarch")
    assert s.claims == {"termination": "test: finishes", "formation": None}
    f = resolve_algorithm(make_lazy_march)
    assert (f.label, f.ref, f.claims) == ("make_lazy_march", f"{__name__}:make_lazy_march", {})
    assert resolve_algorithm(f"{__name__}:Dither").factory is Dither


@pytest.mark.parametrize("algorithm, match", [
    pytest.param(LazyMarch(), r"is an algorithm object.*pass its class \(LazyMarch\)", id="instance"),
    pytest.param(42, "algorithm=42 is not a registry name", id="number"),
    pytest.param("nosuchmodule_xyz:Alg", "cannot be imported", id="missing-module"),
    pytest.param(f"{__name__}:Nope", "has no 'Nope'", id="missing-attribute"),
    pytest.param("song2099", "algorithm='song2099' is not known.*song2016", id="unknown-name"),
])
def test_bad_algorithm_specs(algorithm, match):
    with pytest.raises(UsageError, match=match):
        explore(algorithm, ["connectivity"], budget=5, max_examples=1)


def test_explore_a_class_then_replay_it_from_the_file(tmp_path):
    r = explore(RootDrifts, ["premises"], budget=None, max_examples=10, out_dir=tmp_path, **SMALL)
    v = r.properties["premises"]
    assert r.algorithm == "song2016" and r.as_dict()["algorithm_ref"] == f"{__name__}:RootDrifts"
    assert v.status == "violated"
    assert v.counterexample.violation["message"].startswith(
        "premise of lemma relocate_stays_in_range failed: step ")
    assert "premise root_still of lemma relocate_stays_in_range failed" in v.counterexample.violation["message"]
    doc = json.loads(open(v.counterexample_path).read())
    assert doc["algorithm"] == f"{__name__}:RootDrifts"
    rr = replay_file(v.counterexample_path)
    assert rr.reproduced and rr.step == v.counterexample.violation["step"]
    assert rr.verdict.witness["lemma"] == "relocate_stays_in_range" and rr.verdict.witness["monitor"] == "relocate"


def test_replay_of_an_unimportable_class_is_a_clear_file_error(tmp_path):
    class Local(GatherToLowestId):
        pass

    r = explore(Local, ["connectivity"], budget=None, max_examples=1, robots=(3, 3), lattices=["square"], seed=0)
    assert r.as_dict()["algorithm_ref"].endswith("<locals>.Local")
    cx = Counterexample(algorithm=r.as_dict()["algorithm_ref"], params={"range": 1.2, "v": 0.05, "omega": 0.5,
                                                                        "dt": 1.0},
                        lattice="square", robots=[(0, (0.0, 0.0, 0.0))], seed=0, property="connectivity",
                        violation={"step": 1, "message": "x"})
    path = cx.save(tmp_path / "local.json")
    with pytest.raises(InputFileError, match="cannot be imported") as info:
        replay_file(path)
    assert info.value.field == "algorithm"


def test_unregistered_class_claims_nothing_by_default():
    r = explore(Dither, ["connectivity"], budget=None, max_examples=1, max_steps=20, **SMALL)
    assert r.claims == {"connectivity": None}
    assert r.as_dict()["properties"]["connectivity"]["claim"] is None


# -- the lemma premise property -----------------------------------------------------------

def test_premises_hold_for_song2016_under_its_assumptions():
    r = explore("song2016", ["premises"], budget=None, max_examples=5, robots=(3, 5), lattices=["square"], seed=0)
    v = r.properties["premises"]
    assert v.status == "held" and v.conclusive == 5 and r.broken_assumptions == []


def test_premises_violated_by_song2014_lemma7_as_implemented(tmp_path):
    # docs/decisions.md "The velocity in Lemma 7": turn-then-drive can stop a descendant outside
    # the parent's disc phi - v dt (000 Lemma 7's premise); kept, not repaired
    r = explore("song2014", ["premises"], budget=None, max_examples=15, robots=(3, 6), lattices=["square"], seed=0,
                out_dir=tmp_path)
    v = r.properties["premises"]
    assert v.status == "violated"
    w = replay_file(v.counterexample_path).verdict.witness
    assert (w["lemma"], w["monitor"]) == ("bounded_range", "parent_bounded_range")
    assert w["distance"] > w["bounded_range"] == pytest.approx(1.15)


def test_premises_not_applicable_when_the_algorithm_declares_none():
    """No premise monitors: the property does not apply (no verdict, never a pass) and no run is spent on it."""
    r = explore("example-anonymous-line", ["premises"], budget=10, max_examples=2, robots=(3, 4), seed=0)
    v = r.properties["premises"]
    assert v.status == "not_applicable" and v.conclusive == 0
    assert v.message == "not applicable: it declares no lemma premise monitors (premise_monitors)"


# -- no progress over a window (randomized algorithms) ------------------------------------

def test_randomized_algorithm_that_progresses_holds():
    r = explore(LazyMarch, ["oscillation"], budget=None, max_examples=5, options={"progress_window": 20},
                **SMALL)
    v = r.properties["oscillation"]
    assert v.status == "held" and v.conclusive == 5, v.message
    assert "progress within every 30 steps" in v.message or v.message.startswith("held over 5")
    assert v.steps > 5 * 20  # the runs are longer than the window: the rule was really applied


def test_randomized_algorithm_without_progress_is_violated_and_replays(tmp_path):
    r = explore(Dither, ["oscillation"], budget=None, max_examples=3, max_steps=150, options={"progress_window": 100},
                out_dir=tmp_path, **SMALL)
    v = r.properties["oscillation"]
    assert v.status == "violated"
    assert v.counterexample.violation == {
        "step": 100, "message": "no progress for 100 steps: the goal measure stayed at most 0 (its best, reached "
                                "at step 0) through step 100 and the goal is not reached"}
    assert len(v.counterexample.robots) == 3
    rr = replay_file(v.counterexample_path)
    assert rr.reproduced and rr.verdict.witness == {"kind": "no_progress", "step": 100, "since": 0, "window": 100,
                                                    "best": 0.0}


def test_randomized_algorithm_without_a_measure_is_inconclusive():
    r = explore(DitherNoMeasure, ["oscillation"], budget=None, max_examples=2, max_steps=150, **SMALL)
    v = r.properties["oscillation"]
    assert v.status == "inconclusive" and "without a progress measure" in v.message
