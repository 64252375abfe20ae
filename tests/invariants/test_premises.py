"""Premise monitors (invariants/premises.py, issue 5): hold on song2016 runs, fire on
mutated controllers and traces, each naming its lemma."""

from __future__ import annotations

import numpy as np
import pytest

from swarmproof.invariants.premises import (check_premises, parents_in_bounded_ranges,
                                            relocate_path_in_range, step_bounded)
from swarmproof.models.library import load
from swarmproof.models.trace import Trace
from swarmproof.reference_impl import song2016
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Params


def run16(lattice: str, n: int, seed: int, v: float = 0.05):
    lat = load(lattice)
    init = random_connected(n, seed, range=lat.range, min_separation=0.3)
    return simulate(song2016.Song2016(n_robots=n), lat, init, Params(range=lat.range, v=v),
                    seed=seed).trace


def _copy(trace, poses=None):
    return Trace(ids=trace.ids, poses=trace.poses.copy() if poses is None else poses,
                 states=trace.states, present=getattr(trace, "present", None), meta=trace.meta)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_song2016_meets_every_premise(seed):
    trace = run16("hexagon", 10, seed)
    results = check_premises(trace)
    assert [r.status for r in results] == ["held", "held", "held"], [r.message for r in results]
    assert results[2].detail["checked"] > 0  # the relocate monitor really examined steps


def test_nclb_monitor_fires_on_a_controller_that_ignores_its_childrens_bounded_ranges(monkeypatch):
    # Mutation: the safe region is ignored (the goal itself is taken, any end point "is inside").
    monkeypatch.setattr(song2016, "closest_point_in_discs", lambda goal, centers, radius: goal)
    monkeypatch.setattr(song2016, "in_discs", lambda *a, **k: True)
    trace = run16("square", 20, 2)
    r = parents_in_bounded_ranges(trace, *(1.2, 0.05, 1.0))
    assert r.status == "violated"
    assert r.witness["lemma"] == "nclb_link_kept"
    assert r.witness["distance"] > r.witness["bounded_range"]
    assert r.message.startswith(f"robot {r.witness['parent']} ended step {r.witness['step']}")


def test_step_monitor_fires_on_robots_faster_than_the_proofs_assume():
    trace = run16("hexagon", 10, 0, v=0.1)   # the robots move up to 0.1 per step
    r = step_bounded(trace, v=0.05, dt=1.0)   # the proofs assume 0.05
    assert r.status == "violated" and r.witness["lemma"] == "bounded_range"
    assert 0.05 < r.witness["moved"] <= 0.1 + 1e-9
    assert step_bounded(trace, v=0.1, dt=1.0).status == "held"


def test_relocate_monitor_fires_when_the_root_moves_or_the_robot_leaves_range():
    trace = run16("hexagon", 10, 0)
    ok = relocate_path_in_range(trace, 1.5)
    assert ok.status == "held"
    # Find a step where the relocate robot's parent is the root.
    slot = {int(i): k for k, i in enumerate(trace.ids.tolist())}
    t, k = next((t, k) for t in range(trace.steps) for k in range(trace.n)
                if dict(trace.states[t + 1][k])["relocate"]
                and dict(trace.states[t + 1][k])["parent"] == dict(trace.states[t + 1][k])["root_id"])
    root = slot[dict(trace.states[t + 1][k])["root_id"]]
    moved = trace.poses.copy()
    moved[t + 1:, root, 0] += 0.01             # the root moves in step t
    r = relocate_path_in_range(_copy(trace, moved), 1.5)
    assert r.status == "violated" and r.witness["lemma"] == "relocate_stays_in_range"
    assert r.witness["step"] == t and "root_moved" in r.witness
    far = trace.poses.copy()
    far[t + 1, k, :2] = far[t, root, :2] + np.array([1.52, 0.0])  # beyond phi = 1.5
    r = relocate_path_in_range(_copy(trace, far), 1.5)
    assert r.status == "violated" and r.witness["at"] == "end" and r.witness["step"] == t


def test_missing_state_keys_are_inconclusive_not_held():
    poses = np.zeros((2, 1, 3))
    poses[1, 0, 0] = 0.01
    t = Trace(ids=[1], poses=poses, states=[((("parent", None),),)] * 2)
    assert parents_in_bounded_ranges(t, 1.0, 0.05, 1.0).status == "inconclusive"
    assert relocate_path_in_range(t, 1.0).status == "inconclusive"


LATTICES = ("square", "hexagon", "octagon-square")


@pytest.mark.slow
@pytest.mark.parametrize("lattice", LATTICES)
@pytest.mark.parametrize("n", (10, 20, 30, 40))
def test_premises_hold_on_the_song2016_acceptance_matrix(lattice, n):
    # The starts of tests/reference_impl/test_song2016_acceptance.py (20 per case).
    for seed in range(20):
        results = check_premises(run16(lattice, n, seed))
        bad = [r for r in results if r.status != "held"]
        assert not bad, f"{lattice} n={n} seed={seed}: {[r.message for r in bad]}"
