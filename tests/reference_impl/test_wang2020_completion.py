"""004 Sec. III-B's shape-complete detection as the ``completion_sound`` property (issue 30):
scripted declarations on hand-made states (violated, held, vacuous, later declarations not
judged), real runs (a formed shape, the 4-agent false completion, two shapes in a row), the
streaming form in simulate's checked run (dense and sparse), the vectorised path's ``completed``
column, and not applicable where robots detect no completion."""

from __future__ import annotations

import numpy as np
import pytest

from swarmproof.checkers.runs import run_and_check
from swarmproof.invariants.registry import PropertyContext, get_property
from swarmproof.models.targets import GoalSet, resolve_target
from swarmproof.models.trace import InitialConfiguration, Trace
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.registry import algorithm_factory
from swarmproof.reference_impl.wang2020.algorithm import Wang2020

L = 0.2
#: the explorer's false completion (seed 0): three agents in a row below letter-l's goals
ROW_OF_THREE = InitialConfiguration([1, 2, 0], [[-0.2, -0.2, 0.0], [0.0, -0.2, 0.0], [0.2, -0.2, 0.0]])
ROW3 = ((0, 0), (1, 0), (2, 0))
PROP = get_property("completion_sound")


def _state(completed, *, hop=None, wp=(0, 0)):
    return (("completed", completed), ("hop", hop), ("wp", wp), ("spacing", L))


def _judge(frames, shapes=(ROW3,)):
    """``frames``: per step, ``[(cell (x, y) in grid units, completed, hop), ...]`` per robot."""
    alg = Wang2020()
    alg._shapes = shapes          # what controller() keeps for a run
    poses = np.array([[[L * x, L * y, 0.0] for (x, y), _, _ in f] for f in frames])
    states = [tuple(_state(c, hop=h) for _, c, h in f) for f in frames]
    trace = Trace(ids=list(range(1, len(frames[0]) + 1)), poses=poses, states=states)
    return PROP.check(trace, PropertyContext(alg, None, None, None))


def test_a_declaration_with_a_goal_unheld_is_violated():
    frames = [[((0, 0), 0, None), ((1, 0), 0, None), ((1, 1), 0, None)],
              [((0, 0), 0, 2), ((1, 0), 1, 4), ((1.5, 1), 0, 3)]]
    r = _judge(frames)
    assert r.status == "violated" and r.witness["step"] == 1 and r.witness["invariant"] == "completion_sound"
    assert r.message == ("completion_sound (004 Sec. III-B) broke in step 1: robot 2 declared shape 0 complete in "
                         "step 1 (hop-count 4 > |A| = 3) while 1 of its 3 goals held no agent at rest: (2, 0) (nobody's goal); "
                         "robot 3 on the edge toward (0, 0)")


def test_an_agent_at_rest_off_the_shape_is_named():
    frames = [[((0, 0), 1, 4), ((1, 0), 0, None), ((5, 5), 0, None)]]
    r = _judge([[((0, 0), 0, None), ((1, 0), 0, None), ((5, 5), 0, None)]] + frames)
    assert r.violated and r.message.endswith("(2, 0) (nobody's goal); robot 3 at rest on (5, 5), off the shape")


def test_long_lists_are_cut_after_six():
    """144 agents declaring at once (beta = 0.01, docs/wang2020.md) must not print 144 IDs."""
    goals = tuple((k, 0) for k in range(8))
    start = [((k, 1), 0, None) for k in range(8)]
    r = _judge([start, [((k, 1), 1, 9) for k in range(8)]], shapes=(goals,))
    assert r.violated and "robots 1, 2, 3, 4, 5, 6 (and 2 more) declared shape 0 complete" in r.message
    assert "(5, 0) (nobody's goal) (and 2 more); robot 1 at rest on (0, 1), off the shape" in r.message
    assert r.message.endswith("robot 6 at rest on (5, 1), off the shape (and 2 more)")


def test_a_declaration_with_every_goal_held_holds():
    frames = [[((0, 0), 0, None), ((1, 0), 0, None), ((2, 0), 0, None)],
              [((0, 0), 1, 4), ((1, 0), 1, 4), ((2, 0), 0, 3)]]
    r = _judge(frames)
    assert r.status == "held" and r.detail["judged"] == {"completion_sound": 1}
    assert r.message == "completion_sound held at every one of 2 observed steps, completion_sound judged 1 time"


def test_no_declaration_is_vacuous_not_held():
    frames = [[((0, 0), 0, 2), ((1, 0), 0, 1), ((1, 1), 0, 0)]] * 3
    r = _judge(frames)
    assert r.status == "inconclusive" and not r.applicable
    assert r.message == "vacuous: completion_sound had nothing to judge in 3 observed steps"


def test_only_the_first_declaration_of_a_shape_is_judged():
    """Agents that hear the news later (or detect it later) repeat a declaration already judged: in
    a run of two shapes the first agents have left for the next one by then."""
    second = ((0, 3), (1, 3), (2, 3))
    frames = [[((0, 0), 0, None), ((1, 0), 0, None), ((2, 0), 0, None)],
              [((0, 0), 1, None), ((1, 0), 0, 3), ((2, 0), 0, 3)],       # shape 0 declared, formed
              [((0, 0.5), 1, None), ((1, 0), 1, None), ((2, 0), 0, 3)],  # robot 2 hears it; robot 1 leaves
              [((0, 1), 1, None), ((1, 0.5), 1, None), ((2, 0), 1, 5)]]  # robot 3 detects it itself
    r = _judge(frames, shapes=(ROW3, second))
    assert r.status == "held" and r.detail["judged"] == {"completion_sound": 1}
    # the second shape declared while unformed is judged against the second goal set
    frames.append([((0, 1), 2, None), ((1, 1), 1, None), ((2, 1), 1, None)])
    r = _judge(frames, shapes=(ROW3, second))
    assert r.violated and r.witness["step"] == 4
    assert "robot 1 declared shape 1 complete in step 4 (hop-count > |A| = 3) while 3 of its 3 goals" in r.message


def test_the_formed_letter_l_holds_and_the_row_of_three_is_a_false_completion():
    """The module docstring's 5-agent run forms letter-l and declares it once it is formed; the
    3-agent row below it (the explorer's counterexample, docs/wang2020.md, "False completion")
    declares it with a goal free.  (Until 0.3.0 a row of four; the default's handshake forms it now.)"""
    shape = resolve_target("shape:letter-l")
    alg = Wang2020()
    init = InitialConfiguration([1, 2, 3, 4, 5], [[L * x, L * y, 0] for x, y in
                                                  [(-2, 0), (-1, 0), (-2, 1), (-1, 1), (-2, 2)]])
    p = alg.default_params(0.6, 5)
    r = simulate(alg, shape, init, p, seed=0)
    res = PROP.judge(r.trace, PropertyContext(alg, shape, p, r))
    assert r.status == "finished" and res.status == "held" and res.detail["judged"] == {"completion_sound": 1}

    three = Wang2020.scale_target(shape, 3)
    alg = Wang2020()
    init = ROW_OF_THREE
    p = alg.default_params(0.6, 3)
    r = simulate(alg, three, init, p, seed=0)
    res = PROP.judge(r.trace, PropertyContext(alg, three, p, r))
    assert r.status == "finished" and res.violated and res.witness["step"] == 31
    assert res.message.endswith("broke in step 31: robots 1, 2, 0 declared shape 0 complete in step 31 (hop-count "
                                "4 > |A| = 3) while 1 of its 3 goals held no agent at rest: (0, 1) (robot 2's "
                                "goal); robot 1 at rest on (0, -1), off the shape")


@pytest.mark.parametrize("seed, verdict", [(0, "held"), (7, "violated")])
def test_two_shapes_in_a_row_are_each_judged_once(seed, verdict):
    """tests/reference_impl/test_wang2020.py's two shapes: with seed 0 both declarations find their
    shape formed; with seed 7 (which ends with the line formed) letter-l is declared complete with
    every goal assigned (J2 = 0) but two agents still off it, waiting behind the corner: no goal
    lacks an owner, so no agent anchors, and the hop-counts pass |A| = 5.  (Until 0.3.0 the example
    was seed 1, step 127; the default's handshake changed the runs.)"""
    line = GoalSet.from_bitmap("line-5", ["#####"], spacing=0.2, origin=(0.0, 1.0))
    shape = resolve_target("shape:letter-l")
    alg = Wang2020(then=line)
    init = InitialConfiguration(list(range(5)), [[L * x, L * y, 0] for x, y in
                                                 [(-2, 0), (-1, 0), (-2, 1), (-1, 1), (-2, 2)]])
    p = alg.default_params(0.6, 5)
    r = simulate(alg, shape, init, p, seed=seed)
    res = PROP.judge(r.trace, PropertyContext(alg, shape, p, r))
    assert r.status == "finished" and line.satisfied(r.final_ids, r.final_poses).status == "held"
    assert res.status == verdict
    if verdict == "held":
        assert res.detail["judged"] == {"completion_sound": 2}
    else:
        assert res.message.endswith(
            "broke in step 58: robots 0, 1, 2, 3, 4 declared shape 0 complete in step 58 (hop-count > |A| = 5) "
            "while 2 of its 5 goals held no agent at rest: (1, 0) (no known owner), (2, 0) (no known owner); "
            "robot 0 at rest on (-1, 0), off the shape, robot 2 at rest on (-1, 1), off the shape")
        before = [dict(s) for s in r.trace.states[57]]
        assert sorted(d["goal"] for d in before) == sorted(alg._shapes[0])       # J2 = 0 the step before
        assert [d["cell"] for d in before if d["goal"] in ((1, 0), (2, 0))] == [(-1, 0), (-1, 1)]


@pytest.mark.parametrize("record_every", [1, 7], ids=["dense", "sparse"])
def test_run_and_check_judges_it_on_every_step_dense_or_sparse(record_every):
    """simulate's checked run: the registry's check on a dense trace, its streaming monitor on a
    sparse one (the declaration's step need not be recorded); claimed, so it decides the exit code."""
    checked = run_and_check("wang2020", resolve_target("shape:letter-l"), seed=0, initial=ROW_OF_THREE,
                            record_every=record_every)
    res = checked.completion_sound
    assert res.violated and res.witness["step"] == 31 and checked.exit_code == 1
    assert checked.doc["completion_sound"]["status"] == "violated" and "completion_sound" in checked.doc["judged"]
    assert checked.doc["claims"]["completion_sound"].startswith("004 Sec. III-B")


def test_the_vectorised_column_of_completed_is_the_states_and_the_verdict_the_same():
    """fast.py answers ``values_of("completed")`` from its array (the monitor reads it every step
    without building 1,024 states): the same values as the states, the same verdict."""
    from swarmproof.invariants.result import state_value
    from swarmproof.reference_impl.wang2020.fast import simulate_fast

    class Column:
        def __init__(self):
            self.bad, self.read = [], 0

        def start(self, ids):
            pass

        def observe(self, t, poses, states, present):
            col = states.values_of("completed") if hasattr(states, "values_of") else None
            self.read += col is not None
            if col is not None and col != [state_value(s, "completed") for s in states]:
                self.bad.append(t)

    three = Wang2020.scale_target(resolve_target("shape:letter-l"), 3)
    verdicts = []
    for run in (simulate, simulate_fast):
        alg = Wang2020()
        p = alg.default_params(0.6, 3)
        col, mon = Column(), PROP.stream(alg, p, {})
        r = run(alg, three, ROW_OF_THREE, p, seed=0, record_every=5, observers=(col, mon))
        assert col.bad == [] and (col.read > 0) == (run is simulate_fast)
        verdicts.append((r.steps, PROP.judge(r.trace, PropertyContext(alg, three, p, r)).message))
    assert verdicts[0] == verdicts[1] and "broke in step 31" in verdicts[0][1]


@pytest.mark.parametrize("name", ["song2016", "jiang", "example-grid-goals"])
def test_not_applicable_where_robots_detect_no_completion(name):
    assert PROP.not_applicable_to(algorithm_factory(name)) == \
        "its robots do not detect completion (no completion_invariants)"
    assert PROP.not_applicable_to(algorithm_factory("wang2020")) is None
