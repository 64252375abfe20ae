"""Connectivity (001 Lemma 11), tree links, termination (001 Thm. 13) and trace metrics."""

from __future__ import annotations

import numpy as np
import pytest

from swarmproof.invariants.connectivity import (connected_throughout, first_disconnection,
                                                tree_links_survive)
from swarmproof.invariants.metrics import min_separation, total_distance
from swarmproof.invariants.result import InvariantResult, state_value
from swarmproof.invariants.termination import execution_steps, static_by_bound
from swarmproof.models.trace import Trace


def line_trace(xs_per_step, parents=None, status="static"):
    poses = np.array([[[x, 0.0, 0.0] for x in xs] for xs in xs_per_step])
    n = poses.shape[1]
    st = tuple((("parent", parents[k]),) for k in range(n)) if parents else (None,) * n
    return Trace(ids=list(range(10, 10 + n)), poses=poses, states=[st] * len(poses),
                 meta={"status": status})


def test_connected_throughout_held_and_violated():
    ok = line_trace([[0, 0.5, 1.0], [0, 0.6, 1.1], [0, 0.6, 1.1]])
    assert connected_throughout(ok, 1.0).held and first_disconnection(ok, 1.0) is None
    bad = line_trace([[0, 0.5, 1.0], [0, 0.5, 1.6], [0, 0.5, 1.6]])
    r = connected_throughout(bad, 1.0)
    assert r.violated and r.witness == {"step": 1, "components": [[10, 11], [12]]}


def test_disconnected_start_is_vacuous_inconclusive_neither_a_pass_nor_a_violation():
    r = connected_throughout(line_trace([[0, 5.0]]), 1.0)
    assert r.status == "inconclusive" and not r.applicable and "vacuous" in r.message


def test_exactly_at_range_is_disconnected():
    r = connected_throughout(line_trace([[0, 0.5], [0, 1.0]]), 1.0)
    assert r.violated and r.witness["step"] == 1


def test_tree_links():
    ok = line_trace([[0, 0.5, 1.0], [0, 0.5, 1.4]], parents=[None, 10, 11])
    assert tree_links_survive(ok, 1.0).held
    bad = line_trace([[0, 0.5, 1.0], [0, 0.5, 1.6]], parents=[None, 10, 11])
    r = tree_links_survive(bad, 1.0)
    assert r.violated and r.witness["child"] == 12 and r.witness["parent"] == 11
    assert not tree_links_survive(line_trace([[0, 0.5]]), 1.0).applicable


def test_execution_steps_and_termination_bound():
    t = line_trace([[0, 1], [0, 1.1], [0, 1.2], [0, 1.2], [0, 1.2]])
    assert execution_steps(t) == 2
    assert static_by_bound(t, 2).held
    r = static_by_bound(t, 1)
    assert r.violated and r.witness["robot"] == 11
    capped = line_trace([[0, 1], [0, 1.1], [0, 1.2]], status="step_cap")
    assert static_by_bound(capped, 100).status == "inconclusive"


def test_distance_and_separation():
    t = line_trace([[0, 1], [0, 1.1], [0.3, 1.2]])
    assert total_distance(t) == pytest.approx(0.1 + 0.3 + 0.1)
    assert min_separation(t) == pytest.approx(0.9)
    assert min_separation(line_trace([[0]])) is None


def test_result_and_state_value():
    with pytest.raises(ValueError, match="status='maybe'"):
        InvariantResult("x", "maybe", "")
    from collections import namedtuple
    S = namedtuple("S", "parent role")
    assert state_value(S(3, "A"), "parent") == 3
    assert state_value((("role", "B"),), "parent", "none") == "none"


def test_tree_link_modes_differ_on_a_one_step_parent_switch():
    poses = np.array([[[0, 0, 0], [0.5, 0, 0], [1.4, 0, 0]],
                      [[0, 0, 0], [0.5, 0, 0], [1.6, 0, 0]]], dtype=float)
    before = ((("parent", None),), (("parent", 10),), (("parent", 11),))
    after = ((("parent", None),), (("parent", 10),), (("parent", 10),))  # 12 switches to 10 in step 0
    t = Trace(ids=[10, 11, 12], poses=poses, states=[before, after])
    assert tree_links_survive(t, 1.0, mode="standing").violated        # 12 -> 11 broke
    assert tree_links_survive(t, 1.0, mode="decided").held             # 12 -> 10 was never in range
    assert tree_links_survive(t, 1.0, mode="decided").detail["unsensed_parents"] == 1
    assert tree_links_survive(t, 1.0, mode="persistent").held          # persistent: only 11 -> 10
    with pytest.raises(ValueError, match="mode='sometimes'"):
        tree_links_survive(t, 1.0, mode="sometimes")


def test_a_newly_chosen_link_that_breaks_is_found_by_default_and_hidden_by_persistent():
    """Issue 19: 12 chooses 11 in step 0 and 11 moves away in the same step (it could not
    know of 12 yet).  The default reading (every link of the tree the step decided) reports
    it as newly chosen; the persistent reading does not see it (its stated blind spot)."""
    poses = np.array([[[0, 0, 0], [0.5, 0, 0], [1.4, 0, 0]],
                      [[0, 0, 0], [0.4, 0, 0], [1.45, 0, 0]]], dtype=float)
    before = ((("parent", None),), (("parent", 10),), (("parent", 10),))
    after = ((("parent", None),), (("parent", 10),), (("parent", 11),))
    t = Trace(ids=[10, 11, 12], poses=poses, states=[before, after])
    r = tree_links_survive(t, 1.0)
    assert r.violated and r.witness["newly_chosen"] is True
    assert (r.witness["step"], r.witness["child"], r.witness["parent"], r.witness["mode"]) == (0, 12, 11, "decided")
    assert "messages take one step" in r.message and "Lemma 11" in r.message
    assert tree_links_survive(t, 1.0, mode="persistent").held


def test_tree_links_without_a_tree_or_without_a_checked_link_are_inconclusive():
    from swarmproof.invariants.connectivity import tree_links_survive

    none = tree_links_survive(line_trace([[0, 0.5], [0, 0.6]]), 1.0)
    assert none.status == "inconclusive" and "keeps no spanning tree" in none.message
    far = tree_links_survive(line_trace([[0, 3.0], [0, 3.1]], parents=[None, 10]), 1.0)
    assert far.status == "inconclusive" and "no tree link was between neighbors" in far.message
    kept = tree_links_survive(line_trace([[0, 0.5], [0, 0.6]], parents=[None, 10]), 1.0)
    assert kept.held and kept.detail["links_checked"] == 1
