"""``song2016-subtree-clock``: the relocate robot's movement timeout counted from its own line-29
``subtree`` marker (Song & O'Kane 2016, Alg. 1 line 29), a registered variant of ``song2016``
(docs/decisions.md, "Table III's steps"; docs/song2016.md, "Where Table III's steps go").

It differs from the default in that one clock only: the same final formation (the sequential
fill of Sec. VI, Table II's Q), the relocate robot moving one movement timeout sooner.  Its
memoised trace is the unmemoised one: tests/reference_impl/test_song2016.py.
"""

from __future__ import annotations

import math

import numpy as np

from swarmproof.models.library import load
from swarmproof.models.se2 import relative_many
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Observation, Params
from swarmproof.reference_impl.registry import get_algorithm, reading_of_name, verify_plans
from swarmproof.reference_impl.song2016.algorithm import (Song2016, Song2016Message, Song2016SubtreeClock,
                                                Song2016SubtreeClockController, Vacancy, sequential_fill)

SQUARE = load("square")
PHI = SQUARE.range


def _root_msg():
    return Song2016Message(sender_id=9, stable=True, highest_id=9, root_id=9, path_from_root=(9,),
                           relocate_id=None, path_from_relocate=(9,), parent_id=None, subtree=False,
                           vacancy=Vacancy(1.0, 0.0, 0.0, "A", 0))


def _forwards(alg, steps=8):
    """The relocate robot 5 beside the stable root 9 (timeouts 3): its forward command per step."""
    c = alg.controller(5, Params(range=PHI, v=0.05), SQUARE, np.random.default_rng(0))
    poses = np.array([[0.5, 0.5, 0.0]])
    poses.setflags(write=False)
    out = []
    for t in range(steps):
        out.append(c.step(Observation(t, 5, (9,), poses, {9: _root_msg()})).forward)
    return out, dict(c.state())


def test_the_relocate_robot_moves_one_movement_timeout_sooner():
    # relocateID = 5 since step 0 (its subtree marker, line 29) -> confirmed at step 3 (Def. 10)
    default, _ = _forwards(Song2016(n_robots=3))
    variant, s = _forwards(Song2016SubtreeClock(n_robots=3))
    assert default[:6] == [0.0] * 6 and default[6] > 0          # then the movement timeout: step 6
    assert variant[:3] == [0.0] * 3 and variant[3] > 0          # its clock ran since step 0: step 3
    assert s["mover"] == "relocate" and s["mover_since"] == s["relocate_since"] == 0


def _run(cls, n, seed, v):
    init = random_connected(n, seed, range=PHI, min_separation=0.3)
    return simulate(cls(n_robots=n), SQUARE, init, Params(range=PHI, v=v, omega=math.pi / 4, dt=1.0), seed=seed)


def _formation(r):
    order = np.argsort(-r.final_ids)
    rel = relative_many(r.final_poses[order[0]], r.final_poses[order])
    return rel[:, :2], [dict(r.final_states[k])["role"] for k in order]


def test_same_formation_as_the_default_one_timeout_fewer_per_relocation():
    n = 5
    default, variant = _run(Song2016, n, 0, 0.2), _run(Song2016SubtreeClock, n, 0, 0.2)
    assert default.status == variant.status == "finished"
    # n - 1 relocations, each n steps (the movement timeout) sooner: 95 -> 75 steps
    assert (default.steps, variant.steps) == (95, 95 - (n - 1) * n)
    pred = sequential_fill(SQUARE, n)
    for r in (default, variant):
        xy, roles = _formation(r)
        assert np.abs(xy - np.array([p[:2] for p, _ in pred])).max() < 1e-6   # Sec. VI: the sequential fill
        assert roles == [role for _, role in pred]

    def clocks(r):   # (relocate_since, mover_since) of every confirmed relocate robot
        return sorted({(s["relocate_since"], s["mover_since"]) for row in r.trace.states for s in map(dict, row)
                       if s["mover"] == "relocate"})

    # the one difference: the movement clock starts at the subtree marker, not at the confirmation
    assert all(m == rs + n for rs, m in clocks(default))
    assert clocks(variant) == [(rs, rs) for rs, _ in clocks(variant)] and len(clocks(variant)) == n - 1


def test_registered_with_the_defaults_verify_runs():
    alg = get_algorithm("song2016-subtree-clock", n_robots=4)
    assert isinstance(alg, Song2016SubtreeClock) and alg.name == "song2016-subtree-clock"
    assert isinstance(alg.controller(1, Params(range=PHI, v=0.05), SQUARE, None), Song2016SubtreeClockController)
    assert reading_of_name("song2016-subtree-clock") == "1"
    assert alg.claims == Song2016.claims and alg.parameters == Song2016.parameters
    plans = dict(verify_plans())
    plan = plans["song2016-subtree-clock"]
    assert plan.runs() == plans["song2016"].runs() and plan.explore is False
