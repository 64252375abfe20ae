"""Issue 19: the premise monitors and song2016's property ``tree_link_cases`` (a premise monitor
until issue 32) cover every link of the tree Lemma 11 is about.

* a link a child chose in the very step its parent moved (messages take one step, so the
  parent cannot know of it) is in no proved case: song2016 on square, n = 20, seed 1 breaks
  one at step 344 (robot 2 -> 16), and ``tree_link_cases`` names the same step and robots;
* the relocate robot heading for a non-root parent by the nearest safe point (001 Sec. V-C
  case 2 with Fig. 11's intermediate goal, docs/decisions.md) can move away from it: a
  crafted state fed to the real controller is flagged;
* song2014's Lemma 7 premise is checked for children that do not drive (turn in place).
"""

from __future__ import annotations

import numpy as np
import pytest

from swarmproof.invariants.premises import check_premises
from swarmproof.invariants.registry import get_property
from swarmproof.reference_impl.song2014.monitors import descendants_in_parent_bounded_ranges
from swarmproof.reference_impl.song2016.monitors import tree_links_in_proved_cases
from swarmproof.models.library import load
from swarmproof.models.trace import Trace
from swarmproof.reference_impl.protocol import Observation, Params
from swarmproof.reference_impl.song2016.algorithm import Song2016, Song2016Message, Vacancy

PHI, V = 1.2, 0.05


@pytest.fixture(scope="module")
def square_n20_seed1():
    """``run_and_check("song2016", square, seed=1, robots=20)``, once per worker (both tests that
    read it are in the xdist group ``song2016-square-n20-seed1``; the run is deterministic and
    neither test changes it): they each simulated it (3-4 s of CPU)."""
    from swarmproof.checkers.runs import run_and_check

    return run_and_check("song2016", load("square"), seed=1, robots=20)


@pytest.mark.xdist_group("song2016-square-n20-seed1")
def test_the_newly_chosen_link_of_square_n20_seed1_breaks_and_the_monitor_names_it(square_n20_seed1):
    c = square_n20_seed1
    links = c.tree_links
    assert links.violated
    w = links.witness
    assert (w["step"], w["child"], w["parent"], w["newly_chosen"]) == (344, 2, 16, True)
    assert w["distance_before"] < PHI <= w["distance_after"]
    prem = {r.name: r for r in check_premises(c.result.trace)}
    assert "premise:tree_link_cases" not in prem          # a property since issue 32
    cases = tree_links_in_proved_cases(c.result.trace, PHI, V, 1.0)
    assert cases.name == "tree_link_cases" and cases.violated
    assert (cases.witness["step"], cases.witness["child"], cases.witness["parent"]) == (344, 2, 16)
    assert cases.witness["broke"] and cases.witness["newly_chosen"] and cases.witness["parent_moved"]
    assert [344, 2, 16, True, "newly_chosen"] in cases.detail["uncovered_links"]
    # the monitors before issue 19 saw nothing: this is the gap they left
    for old in ("premise:step_bounded", "premise:nclb", "premise:relocate", "premise:child_toward_parent"):
        assert prem[old].held, prem[old]


@pytest.mark.xdist_group("song2016-square-n20-seed1")
def test_the_streamed_property_judges_like_the_whole_trace(square_n20_seed1):
    """The property's streaming monitor, fed every step as the engine feeds it, gives the verdict
    of the check over the whole trace (and simulate, which streams it, says the same)."""
    c = square_n20_seed1
    trace = c.result.trace
    mon = get_property("tree_link_cases").stream(c.algorithm, c.params, {})
    mon.start(trace.ids)
    for t in range(trace.frames):
        mon.observe(t, trace.poses[t], trace.states[t], trace.present_at(t))
    whole = tree_links_in_proved_cases(trace, PHI, V, 1.0)
    assert mon.result().as_dict() == whole.as_dict()
    assert mon.name == "tree_link_cases"


def _msg(sender, parent, stable, path_root, path_reloc, *, subtree=False, relocate=5):
    return Song2016Message(sender, 9, 9, relocate, parent, Vacancy(1.0, 0.0, 0.0, "A", 0), subtree, stable,
                           path_root, path_reloc)


def test_the_relocate_robot_moving_away_from_its_non_root_parent_is_flagged():
    """DESIGN.md section 5: a relocate robot with a stable child 1.18 away on one side and its
    (non-root) parent 1.18 away on the opposite side, phi = 1.2, v = 0.05: its move is flagged."""
    lat = load("square")
    params = Params(range=PHI, v=V)
    ctrl = Song2016(n_robots=4).controller(5, params, lat, np.random.default_rng(0))
    # robot 7: stable, not the root (9 is, out of 5's range), on 5's path to the root;
    # robot 3: stable, a child of 5 (its path from the root runs through 5: 5 ignores it)
    msgs = {3: _msg(3, 5, True, (9, 7, 5, 3), (5, 3), subtree=True),
            7: _msg(7, 9, True, (9, 7), (7,), relocate=None)}
    nb = np.array([[1.18, 0.0, 0.0], [-1.18, 0.0, 0.0]])
    before = None
    for t in range(40):
        obs = Observation(step=t, robot_id=5, neighbor_ids=(3, 7), neighbor_poses=nb, messages=msgs)
        prev = ctrl.state()
        cmd = ctrl.step(obs)
        if cmd.forward > 0:
            before = prev
            break
    assert before is not None, "the crafted relocate robot never moved"
    after = dict(ctrl.state())
    assert after["relocate"] and after["parent"] == 7 and after["root_id"] == 9 and after["children"] == (3,)
    ex, ey = after["target"]
    end = np.array([ex, ey])
    assert np.hypot(*(end - nb[1, :2])) > PHI            # it ends out of its parent's range
    # the trace of that step: 5 moves, 7 (stable, parent 9) and 3 (stable, parent 5) stay
    st7 = (("parent", 9), ("children", (5,)), ("relocate", False), ("root_id", 9))
    st3 = (("parent", 5), ("children", ()), ("relocate", False), ("root_id", 9))
    poses = np.array([[[0, 0, 0], [1.18, 0, 0], [-1.18, 0, 0]],
                      [[ex, ey, 0], [1.18, 0, 0], [-1.18, 0, 0]]], dtype=float)
    trace = Trace(ids=[5, 3, 7], poses=poses, states=[(before, st3, st7), (ctrl.state(), st3, st7)],
                  meta={"params": {"range": PHI, "v": V, "dt": 1.0},
                        "premise_monitors": list(Song2016.premise_monitors)})
    r = tree_links_in_proved_cases(trace, PHI, V, 1.0)
    assert r.violated
    assert (r.witness["child"], r.witness["parent"], r.witness["broke"]) == (5, 7, True)
    assert "not the root" in r.message and r.witness["why"] == "relocate_away_from_non_root_parent"
    # and no premise monitor sees it: only the property does
    others = check_premises(trace)
    assert all(not x.violated for x in others), others


def test_song2014_child_that_only_turns_while_its_parent_drives_away_is_flagged():
    """Issue 19, item 3: the child does not move (it turns in place) and stands outside its
    parent's bounded range phi - v dt: Lemma 7's premise fails, and the link can stretch."""
    poses = np.array([[[0, 0, 0], [1.18, 0, 0]], [[-0.05, 0, 0], [1.18, 0, 1.0]]], dtype=float)
    st = ((("parent", None),), (("parent", 1),))
    r = descendants_in_parent_bounded_ranges(Trace(ids=[1, 2], poses=poses, states=[st] * 2), PHI, V, 1.0)
    assert r.violated and (r.witness["child"], r.witness["parent"]) == (2, 1)


def test_tree_link_cases_without_the_state_keys_is_inconclusive_never_held():
    poses = np.zeros((2, 2, 3))
    poses[:, 1, 0] = 1.0
    no_parent = Trace(ids=[1, 2], poses=poses, states=[((("role", None),), (("role", None),))] * 2)
    r = tree_links_in_proved_cases(no_parent, PHI, V, 1.0)
    assert r.status == "inconclusive" and "no 'parent'" in r.message
    moved = poses.copy()
    moved[1, 0, 0] = -0.05                                   # the parent moves: its children are needed
    st = ((("parent", None),), (("parent", 1),))
    r = tree_links_in_proved_cases(Trace(ids=[1, 2], poses=moved, states=[st] * 2), PHI, V, 1.0)
    assert r.status == "inconclusive" and "no 'children'" in r.message
    nothing = Trace(ids=[1, 2], poses=poses, states=[((("parent", None),), (("parent", None),))] * 2)
    r = tree_links_in_proved_cases(nothing, PHI, V, 1.0)
    assert r.held and not r.applicable                      # no link to examine: says so


def test_termination_of_a_run_cut_by_the_step_cap_is_inconclusive():
    from swarmproof.invariants.termination import judge_termination

    t = Trace(ids=[0], poses=np.zeros((4, 1, 3)), states=[(None,)] * 4, meta={"status": "step_cap"})
    own = type("A", (), {"own_end": "all done"})()
    r = judge_termination(t, own, None, "step_cap", max_steps=3)
    assert r.status == "inconclusive" and "step cap 3" in r.message
