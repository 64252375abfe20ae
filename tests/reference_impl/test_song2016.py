"""song2016 (001 Sec. V): each rule on hand-made inputs, then small runs through the engine.

Acceptance runs (20 starts x n x lattice) are in test_song2016_acceptance.py.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmproof.models.errors import AssumptionError, UsageError
from swarmproof.models.library import load
from swarmproof.models.se2 import SE2, relative_many
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Observation, Params
from swarmproof.reference_impl.registry import get_algorithm
from swarmproof.reference_impl.song2016.algorithm import (PARENT_RULES, Song2016, Song2016Controller,
                                                Song2016Message, Song2016SubtreeClock, Vacancy,
                                                compute_message, get_parent_msg,
                                                sequential_fill, vacancies,
                                                vacancy_in_observer_frame)
from swarmproof.reference_impl.song2016.geometry import (closest_point_in_discs, in_discs,
                                                         reachable_point)

SQUARE = load("square")
PHI = SQUARE.range  # 1.2
P = Params(range=PHI, v=0.05, omega=math.pi / 4, dt=1.0)
SQ_EDGES = [(e.transform.x, e.transform.y, e.transform.theta, e.target, e.index)
            for e in SQUARE.out_edges("A")]


def msg(sender, *, highest=None, root=None, relocate=None, parent=None, vacancy=None,
        subtree=False, stable=False, root_path=(), reloc_path=()):
    """A Table I message with readable defaults."""
    return Song2016Message(sender, sender if highest is None else highest, root, relocate, parent,
                           vacancy, subtree, stable, tuple(root_path) or (sender,),
                           tuple(reloc_path) or (sender,))


# ---------------------------------------------------------------------------
# Def. 9: vacancies
# ---------------------------------------------------------------------------

def test_vacancies_in_out_edge_order_and_only_stable_robots_fill():
    # SQUARE out-edges: (1,0), (0,-1), (-1,0), (0,1)
    all_four = vacancies(SQ_EDGES, [], 0.5)
    assert [v.edge for v in all_four] == [0, 1, 2, 3]
    assert all_four[0] == Vacancy(1.0, 0.0, 0.0, "A", 0)
    # a stable robot near (0,-1) fills edge 1; the caller passes stable robots only,
    # so an unstable robot at (1,0) leaves edge 0 a vacancy (Def. 9's parenthesis)
    assert [v.edge for v in vacancies(SQ_EDGES, [(0.0, -1.0 + 1e-7)], 0.5)] == [0, 2, 3]
    # outside the tolerance: still a vacancy
    assert [v.edge for v in vacancies(SQ_EDGES, [(0.0, -0.4)], 0.5)] == [0, 1, 2, 3]
    assert vacancies(SQ_EDGES, [(1, 0), (0, -1), (-1, 0), (0, 1)], 0.5) == ()


def test_controller_vacancy_ignores_unstable_neighbor_at_the_vacancy():
    c = Song2016(n_robots=2).controller(9, P, SQUARE, np.random.default_rng(0))
    c.stable, c.role = True, "A"
    pose_of = {3: (1.0, 0.0, 0.0), 4: (0.0, -1.0, 0.0)}
    msgs = {3: msg(3, stable=False), 4: msg(4, stable=True)}
    assert c._my_vacancy(pose_of, msgs.items()).edge == 0   # robot 3 sits there, unstable
    msgs[3] = msg(3, stable=True)
    assert c._my_vacancy(pose_of, msgs.items()).edge == 2


@settings(max_examples=60)
@given(st.tuples(*[st.floats(-5, 5)] * 2, st.floats(-math.pi, math.pi)),
       st.tuples(*[st.floats(-5, 5)] * 2, st.floats(-math.pi, math.pi)),
       st.sampled_from(load("hexagon").edges))
def test_vacancy_in_observer_frame_is_the_lattice_pose_relative_to_the_owner(gs, gi, edge):
    """Sec. V-A: r_i reaching the transformed vacancy stands at T(e) in r_s's frame."""
    owner, observer = SE2(*gs), SE2(*gi)
    seen = owner.relative_to(observer)                      # p_s^(i)
    t = edge.transform
    vac = Vacancy(t.x, t.y, t.theta, edge.target, edge.index)
    x, y, th = vacancy_in_observer_frame(seen.as_tuple(), vac)
    reached = observer @ SE2(x, y, th)                      # r_i's global pose at the vacancy
    assert reached.relative_to(owner).isclose(t, 1e-9, 1e-9)


def test_printed_matrix_order_of_sec_va_would_misplace_the_vacancy():
    """Why the composition is used (docs/decisions.md): M^(s) M_s^(i) [0,0,1] as printed."""
    seen = SE2(2.0, 0.0, math.pi / 2)                       # r_s seen by r_i, turned 90 deg
    vac = Vacancy(1.0, 0.0, 0.0, "A", 0)
    printed = (SE2(vac.x, vac.y, vac.theta).matrix() @ seen.matrix() @ np.array([0, 0, 1.0]))[:2]
    used = vacancy_in_observer_frame(seen.as_tuple(), vac)[:2]
    assert np.allclose(used, [2.0, 1.0])
    assert np.allclose(printed, [3.0, 0.0])                 # not one unit from r_s along its x-axis
    assert not np.allclose(printed, used)


# ---------------------------------------------------------------------------
# Algorithm 1
# ---------------------------------------------------------------------------

def test_lines_6_7_own_root_and_relocate_claims():
    v = Vacancy(1.0, 0.0, 0.0, "A", 0)
    m, parent = compute_message(9, True, v, [])
    assert (m.root_id, m.relocate_id, m.vacancy, m.parent_id, parent) == (9, None, v, None, None)
    assert m.path_from_root == (9,) and m.path_from_relocate == (9,)
    m, _ = compute_message(9, True, None, [])                # stable, no vacancy: not a root
    assert (m.root_id, m.relocate_id) == (None, None)
    m, _ = compute_message(4, False, None, [])
    assert (m.root_id, m.relocate_id, m.subtree, m.stable) == (None, 4, True, False)


def test_line_11_highest_id_is_taken_from_every_message_even_rejected_ones():
    looped = msg(3, highest=12, root=8, root_path=(8, 5, 3), stable=True)
    for mode in ("message", "field"):
        m, _ = compute_message(5, False, None, [looped], mode)
        assert m.highest_id == 12
        assert m.root_id is None                              # the root info went through 5


def test_lines_14_16_23_larger_root_and_its_vacancy_win():
    va, vb = Vacancy(1, 0, 0, "A", 0), Vacancy(0, 1, 0, "A", 3)
    a = msg(3, root=7, root_path=(7, 3), vacancy=va, stable=True)
    b = msg(4, root=8, root_path=(8, 4), vacancy=vb, stable=True)
    m, parent = compute_message(5, False, None, [a, b])
    assert (m.root_id, m.vacancy, m.parent_id, parent.sender_id) == (8, vb, 4, 4)
    assert m.path_from_root == (8, 4, 5)
    # the root itself broadcasts its own vacancy (line 23) and no parent (line 26)
    m, parent = compute_message(9, True, va, [b])
    assert (m.root_id, m.vacancy, m.parent_id, m.path_from_root) == (9, va, None, (9,))


def test_lines_21_22_24_25_shortest_paths_with_highest_sender_on_ties():
    a = msg(3, root=9, root_path=(9, 1, 3), relocate=6, reloc_path=(6, 2, 3), stable=True)
    b = msg(4, root=9, root_path=(9, 4), relocate=6, reloc_path=(6, 1, 0, 4))
    c = msg(2, root=9, root_path=(9, 2), relocate=6, reloc_path=(6, 2))
    m, _ = compute_message(5, False, None, [c, a, b])
    assert m.path_from_root == (9, 4, 5)                     # (9,2) and (9,4) tie: highest sender
    assert m.path_from_relocate == (6, 2, 5)
    assert m.relocate_id == 6


def test_lines_27_29_parent_and_subtree_marker():
    reloc = msg(6, root=9, root_path=(9, 6), relocate=6, reloc_path=(6,), subtree=True)
    other = msg(2, root=9, root_path=(9, 1, 2), relocate=6, reloc_path=(6, 2))
    m, parent = compute_message(5, False, None, [reloc, other])
    # 6 is the relocate robot but the only neighbor with the fewest hops: chosen (Sec. V-B)
    assert (m.parent_id, m.subtree) == (6, True)
    m, parent = compute_message(6, False, None, [other])
    assert (m.relocate_id, m.subtree) == (6, True)            # line 29: myID = relocateID


def test_rumor_rule_literal_line_12_starves_the_relocate_robot_of_the_root():
    """docs/decisions.md: the printed line 12 rejects whole messages.

    Relocate robot 2 is not next to root 4; its neighbor 3 is stable, hears the root
    and carries 2's relocate claim back (pathFromRelocate = (2, 3)).  As printed,
    robot 2 rejects 3's message entirely and never learns the root (so it never
    moves: the n=5 run below goes static); read per field (Sec. V-B prose), it does.
    """
    three = msg(3, highest=4, root=4, root_path=(4, 3), relocate=2, reloc_path=(2, 3), stable=True,
                vacancy=Vacancy(1, 0, 0, "A", 0), parent=4)
    literal, _ = compute_message(2, False, None, [three], "message")
    prose, parent = compute_message(2, False, None, [three], "field")
    assert (literal.root_id, literal.parent_id) == (None, None)
    assert (prose.root_id, prose.parent_id, prose.path_from_root) == (4, 3, (4, 3, 2))
    assert prose.path_from_relocate == (2,)                   # relocate info through me: rejected


def test_rumor_rule_stale_root_dies_out():
    """A root that filled its vacancies: its claim echoed back through itself is rejected."""
    echo = msg(3, root=9, root_path=(9, 3), stable=True)
    m, _ = compute_message(9, True, None, [echo])            # 9 has no vacancy any more
    assert m.root_id is None


def test_unknown_rumor_filter_is_refused():
    with pytest.raises(UsageError, match="rumor_filter='both'"):
        compute_message(1, False, None, [], "both")


@pytest.mark.parametrize("cands, relocate, expected", [
    ([msg(5, root=9, root_path=(9, 5)), msg(3, root=9, root_path=(9, 2, 3))], 5, 5),
    ([msg(5, root=9, root_path=(9, 5)), msg(3, root=9, root_path=(9, 3))], 5, 3),
    ([msg(5, root=9, root_path=(9, 5)), msg(3, root=9, root_path=(9, 1, 2, 3))], 7, 5),
    ([msg(4, root=9, root_path=(9, 4)), msg(6, root=9, root_path=(9, 2, 6), stable=True)], 5, 6),
    ([msg(4, root=9, root_path=(9, 4)), msg(6, root=9, root_path=(9, 6))], None, 6),
    ([msg(4, root=8, root_path=(8, 4)), msg(6, root=9, root_path=(9, 1, 6))], None, 6),
], ids=["relocate-only-shortest", "relocate-avoided-on-tie", "shortest",
        "stable-first", "tie-highest-id", "same-root-only"])
def test_parent_rules_of_sec_vb(cands, relocate, expected):
    assert get_parent_msg(cands, 9, relocate).sender_id == expected


def test_lemma_12_parent_rule_ignores_stability():
    """PARENT_RULES: the proof of Lemma 12 states the rule without the stable preference."""
    cands = [msg(4, root=9, root_path=(9, 4)), msg(6, root=9, root_path=(9, 2, 6), stable=True)]
    assert get_parent_msg(cands, 9, 5, stable_first=False).sender_id == 4
    m, _ = compute_message(7, False, None, cands, "field", "fewest_hops")
    assert m.parent_id == 4
    assert compute_message(7, False, None, cands, "field", "stable_first")[0].parent_id == 6


def test_relocate_route_rule_sends_only_the_relocate_robot_along_its_shortest_path():
    """PARENT_RULES "relocate_route" (docs/decisions.md, "Relocate robot's parent"): the
    relocate robot takes Lemma 12's parent (its shortest path to the root, here through
    unstable 4) where Sec. V-B would take the stable 6; every other robot keeps Sec. V-B."""
    cands = [msg(4, root=9, root_path=(9, 4)), msg(6, root=9, root_path=(9, 2, 6), stable=True)]
    # robot 7 is the relocate robot (unstable, highest unstable ID it knows)
    assert compute_message(7, False, None, cands, "field", "relocate_route")[0].parent_id == 4
    assert compute_message(7, False, None, cands, "field", "stable_first")[0].parent_id == 6
    # robot 3 is unstable but not the relocate robot (7 is, by a message): Sec. V-B
    reloc = cands + [msg(7, root=9, relocate=7, root_path=(9, 2, 6, 7))]
    m3, _ = compute_message(3, False, None, reloc, "field", "relocate_route")
    assert (m3.relocate_id, m3.parent_id) == (7, 6)
    # a stable robot keeps Sec. V-B too
    assert compute_message(5, True, None, cands, "field", "relocate_route")[0].parent_id == 6


def test_no_parent_without_a_root():
    assert get_parent_msg([msg(3, root=9, root_path=(9, 3))], None, 5) is None
    m, _ = compute_message(5, False, None, [msg(3)])
    assert (m.root_id, m.parent_id) == (None, None)


# ---------------------------------------------------------------------------
# NCLB geometry
# ---------------------------------------------------------------------------

pt = st.tuples(st.floats(-3, 3), st.floats(-3, 3))


@settings(max_examples=150)
@given(goal=pt, centers=st.lists(pt, min_size=1, max_size=4), radius=st.floats(0.2, 2.0),
       samples=st.lists(st.tuples(st.integers(0, 3), st.floats(0, 1), st.floats(-math.pi, math.pi)),
                        min_size=30, max_size=30))
def test_closest_point_in_discs_is_feasible_and_no_sampled_point_is_closer(goal, centers, radius,
                                                                            samples):
    g = closest_point_in_discs(goal, centers, radius)
    pts = []
    for k, u, a in samples:                       # random points of each disc, kept if in all
        cx, cy = centers[k % len(centers)]
        q = (cx + radius * math.sqrt(u) * math.cos(a), cy + radius * math.sqrt(u) * math.sin(a))
        if in_discs(*q, centers, radius, tol=0.0):
            pts.append(q)
    if g is None:
        assert pts == [], "safe region reported empty but a sample lies in it"
        return
    assert in_discs(*g, centers, radius, tol=1e-9)
    dg = math.dist(g, goal)
    for q in pts:
        assert math.dist(q, goal) >= dg - 1e-9


def test_closest_point_examples_of_fig_11():
    # Fig. 11: child behind, vacancy ahead: the intermediate goal is on B_c's rim
    assert closest_point_in_discs((2.0, 0.0), [(-0.5, 0.0)], 1.15) == pytest.approx((0.65, 0.0))
    assert closest_point_in_discs((0.0, 0.0), [(-3.0, 0.0), (3.0, 0.0)], 1.15) is None


@pytest.mark.parametrize("target, expected", [
    ((0.0, 0.02), (math.pi / 2, 0.0)),                        # needs 90 deg > omega*dt: turn only
    ((0.02, 0.0), (0.0, 0.02)),                               # straight, shorter than a step
    ((1.0, 0.0), (0.0, 0.05)),                                # straight, a full step
])
def test_reachable_point_mirrors_the_engine_limits(target, expected):
    turn, fwd, x, y = reachable_point(target, 0.05, math.pi / 4, 1.0)
    assert turn == pytest.approx(min(expected[0], math.pi / 4)) and fwd == pytest.approx(expected[1])


# ---------------------------------------------------------------------------
# The controller on hand-made observations
# ---------------------------------------------------------------------------

def obs(step, me, neighbors=(), messages=None):
    """An observation: neighbors as {id: (x, y, theta)} in my body frame."""
    ids = tuple(sorted(dict(neighbors)))
    poses = np.array([dict(neighbors)[i] for i in ids], dtype=float).reshape(-1, 3)
    poses.setflags(write=False)
    return Observation(step, me, ids, poses, dict(messages or {}))


def ctrl(me, n=3, **extra):
    return Song2016(n_robots=n).controller(me, Params(range=PHI, v=0.05, extra=extra), SQUARE,
                                           np.random.default_rng(0))


def test_highest_robot_becomes_stable_exactly_after_the_communication_timeout():
    c = ctrl(9, n=3)
    lower = {1: msg(1, relocate=1)}
    for t in range(3):
        c.step(obs(t, 9, {1: (1.0, 0, 0)}, lower))
        assert dict(c.state())["stable"] is False
    cmd = c.step(obs(3, 9, {1: (1.0, 0, 0)}, lower))
    s = dict(c.state())
    assert (s["stable"], s["role"], s["parent"]) == (True, "A", None)
    assert cmd.message.stable and cmd.message.root_id == 9 and cmd.message.vacancy.edge == 0
    assert (cmd.turn, cmd.forward) == (0.0, 0.0)


def test_lower_robot_never_becomes_stable_once_it_hears_a_higher_id():
    c = ctrl(1, n=3)
    for t in range(10):
        c.step(obs(t, 1, {9: (1.0, 0, 0)}, {9: msg(9, relocate=9)} if t else {}))
    s = dict(c.state())
    assert (s["stable"], s["highest_id"], s["highest_since"]) == (False, 9, 1)


def test_relocate_robot_waits_both_timeouts_then_heads_for_the_vacancy():
    c = ctrl(5, n=3)                                          # timeouts 3 and 3
    root = msg(9, highest=9, root=9, stable=True, vacancy=Vacancy(1.0, 0.0, 0.0, "A", 0))
    seen = {9: (0.5, 0.5, 0.0)}                               # root ahead-left, same heading
    forwards = []
    for t in range(8):
        cmd = c.step(obs(t, 5, seen, {9: root}))
        forwards.append(cmd.forward)
        s = dict(c.state())
    # relocateID = 5 since step 0 -> relocate at step 3 -> moves from step 3 + 3 = 6
    assert forwards[:6] == [0.0] * 6 and forwards[6] > 0
    assert s["relocate"] and s["mover"] == "relocate" and s["parent"] == 9
    assert s["goal"] == pytest.approx((1.5, 0.5))             # vacancy (1,0) of the root
    turn = math.atan2(0.5, 1.5)
    assert cmd.turn == pytest.approx(turn)
    assert cmd.forward == pytest.approx(0.05 * (1 - turn / (math.pi / 4)))


def test_relocate_robot_at_the_vacancy_turns_then_becomes_stable_with_the_edge_role():
    hexa = load("hexagon")
    alg = Song2016(n_robots=2, communication_timeout=0, movement_timeout=0)
    c = alg.controller(5, Params(range=hexa.range, v=0.05), hexa, np.random.default_rng(0))
    e = hexa.out_edges("A")[0]                                # A -> B at (0, 1)
    vac = Vacancy(e.transform.x, e.transform.y, e.transform.theta, e.target, e.index)
    root = msg(9, highest=9, root=9, stable=True, vacancy=vac)
    # root seen at (0,-1) turned by 0.3 rad: the vacancy is at (-sin .3, cos .3 - 1), heading 0.3
    seen = {9: (0.0, -1.0, 0.3)}
    vx, vy, vth = vacancy_in_observer_frame(seen[9], vac)
    assert math.hypot(vx, vy) > 0.1
    # the robot now stands on the vacancy position with its old heading
    at_pose = SE2(*seen[9]).relative_to(SE2(vx, vy, 0.0))     # root seen from the vacancy point
    cmd = c.step(obs(0, 5, {9: at_pose.as_tuple()}, {9: root}))
    assert dict(c.state())["stable"] is False
    assert cmd.forward == 0.0 and cmd.turn == pytest.approx(0.3)
    turned = SE2(*seen[9]).relative_to(SE2(vx, vy, vth))      # after the turn
    cmd = c.step(obs(1, 5, {9: turned.as_tuple()}, {9: root}))
    s = dict(c.state())
    assert (s["stable"], s["role"]) == (True, "B")
    assert cmd.message.stable and (cmd.turn, cmd.forward) == (0.0, 0.0)


def test_subtree_robot_moves_toward_parent_only_outside_d_s():
    c = ctrl(2, n=2, d_s=0.5, communication_timeout=1, movement_timeout=0)
    parent = msg(6, highest=9, root=9, root_path=(9, 6), relocate=6, reloc_path=(6,), subtree=True)
    cmd = c.step(obs(0, 2, {6: (0.4, 0.0, 0.0)}, {6: parent}))
    assert dict(c.state())["mover"] == "subtree" and cmd.forward == 0.0   # within d_s
    cmd = c.step(obs(1, 2, {6: (0.9, 0.0, 0.0)}, {6: parent}))
    s = dict(c.state())
    assert cmd.forward == pytest.approx(0.05) and cmd.turn == 0.0 and s["moving"]
    assert s["goal"] == (0.9, 0.0) and s["target"] == pytest.approx((0.05, 0.0))


def test_nclb_keeps_a_moving_robot_in_its_children_bounded_ranges():
    """Fig. 11: the parent may only move where every child can still reach it."""
    c = ctrl(2, n=2, d_s=0.5, communication_timeout=1, movement_timeout=0)
    parent = msg(6, highest=9, root=9, root_path=(9, 6), relocate=6, reloc_path=(6,), subtree=True)
    child = msg(1, highest=9, root=9, root_path=(9, 6, 2, 1), parent=2, subtree=True)
    # parent ahead at 1.0, child behind at 1.14: B_c (radius 1.15) allows 0.01 of progress
    cmd = c.step(obs(0, 2, {6: (1.0, 0, 0), 1: (-1.14, 0, 0)}, {6: parent, 1: child}))
    s = dict(c.state())
    assert s["children"] == (1,)
    assert cmd.forward == pytest.approx(0.01, abs=1e-6)
    assert math.dist(s["target"], (-1.14, 0.0)) <= s["safe_radius"] < PHI - 0.05
    # two children on opposite sides farther apart than 2 (phi - v dt): empty safe region
    other = msg(3, highest=9, root=9, root_path=(9, 6, 2, 3), parent=2, subtree=True)
    cmd = c.step(obs(1, 2, {6: (1.0, 0, 0), 1: (-1.16, 0, 0), 3: (1.16, 0.2, 0)},
                     {6: parent, 1: child, 3: other}))
    s = dict(c.state())
    assert (cmd.turn, cmd.forward, s["moving"], s["target"]) == (0.0, 0.0, False, None)
    assert s["children"] == (1, 3)


def test_robot_outside_its_safe_region_does_not_step_to_a_point_outside_it():
    c = ctrl(2, n=2, d_s=0.5, communication_timeout=1, movement_timeout=0)
    parent = msg(6, highest=9, root=9, root_path=(9, 6), relocate=6, reloc_path=(6,), subtree=True)
    child = msg(1, highest=9, root=9, root_path=(9, 6, 2, 1), parent=2, subtree=True)
    # child at 1.19 (> 1.15): the nearest safe point is 0.04 away behind me, the parent
    # is ahead: the safe waypoint is (-0.04, 0) and it is reachable only after a turn
    cmd = c.step(obs(0, 2, {6: (0.0, 1.0, 0), 1: (-1.19, 0, 0)}, {6: parent, 1: child}))
    s = dict(c.state())
    assert cmd.forward == 0.0 and not s["moving"]


def test_movement_timeout_delays_the_subtree():
    c = ctrl(2, n=2, d_s=0.5, communication_timeout=1, movement_timeout=3)
    parent = msg(6, highest=9, root=9, root_path=(9, 6), relocate=6, reloc_path=(6,), subtree=True)
    fw = [c.step(obs(t, 2, {6: (0.9, 0, 0)}, {6: parent})).forward for t in range(5)]
    assert fw[:3] == [0.0, 0.0, 0.0] and fw[3] > 0


def test_state_has_the_documented_keys_and_is_hashable():
    c = ctrl(2)
    c.step(obs(0, 2))
    s = c.state()
    hash(s)
    assert [k for k, _ in s] == [
        "stable", "role", "parent", "children", "relocate", "subtree", "moving", "goal", "target",
        "safe_radius", "highest_id", "highest_since", "root_id", "relocate_id", "relocate_since",
        "mover", "mover_since", "vacancy"]


def test_finished_when_no_unstable_robot_remains():
    alg = Song2016(n_robots=2)
    a, b = ctrl(1), ctrl(2)
    assert not alg.finished([a.state(), b.state()])
    a.stable = b.stable = True
    a._state = a._snapshot(None, False, (), False, False, None, None, None)
    b._state = b._snapshot(None, False, (), False, False, None, None, None)
    assert alg.finished([a.state(), b.state()])


# ---------------------------------------------------------------------------
# Parameters and assumptions
# ---------------------------------------------------------------------------

LINE = InitialConfiguration([1, 2, 3], [[0, 0, 0], [0.8, 0, 0], [1.6, 0, 0]])


@pytest.mark.parametrize("init, params, alg, name", [
    (LINE, Params(range=1.2, v=1.3), Song2016(n_robots=3), "v_dt_below_range"),
    (LINE, Params(range=1.2, v=0.05, extra={"d_s": 0.0}), Song2016(n_robots=3),
     "safe_distance_in_range"),
    (LINE, Params(range=1.2, v=0.05, extra={"d_s": 1.15}), Song2016(n_robots=3),
     "safe_distance_in_range"),
    (LINE, Params(range=1.2, v=0.05), Song2016(n_robots=3, d_s=-0.1), "safe_distance_in_range"),
    (InitialConfiguration([1, 2], [[0, 0, 0], [3, 0, 0]]), Params(range=1.2, v=0.05),
     Song2016(n_robots=2), "connected_start"),
    (InitialConfiguration([1, 1], [[0, 0, 0], [1, 0, 0]]), Params(range=1.2, v=0.05),
     Song2016(n_robots=2), "unique_ids"),
    (LINE, Params(range=1.2, v=0.05, extra={"communication_timeout": 1}), Song2016(n_robots=3),
     "communication_timeout_sufficient"),
], ids=["v-dt-above-range", "d_s-zero", "d_s-at-bounded-range", "d_s-negative", "disconnected",
        "duplicate-ids", "timeout-too-short"])
def test_broken_assumptions_are_refused_by_name_or_run_when_allowed(init, params, alg, name):
    with pytest.raises(AssumptionError, match=f"assumption '{name}' broken"):
        simulate(alg, SQUARE, init, params, seed=0, max_steps=5)
    r = simulate(alg, SQUARE, init, params, seed=0, max_steps=5, allow_violations=True)
    assert name in r.broken_assumptions


@pytest.mark.parametrize("alg, extra, match", [
    (Song2016(), {}, "communication_timeout is unknown"),
    (Song2016(n_robots=3), {"timeout": 3}, r"unknown key\(s\) \['timeout'\]"),
    (Song2016(n_robots=3), {"movement_timeout": -1}, "movement_timeout'\\]=-1 must be a whole"),
    (Song2016(n_robots=3), {"communication_timeout": 2.5}, "communication_timeout'\\]=2.5"),
    (Song2016(n_robots=3), {"arrival_epsilon": 0}, "arrival_epsilon'\\]=0 must be a finite"),
    (Song2016(n_robots=3), {"rumor_filter": "path"}, "rumor_filter'\\]='path' is not one of"),
    (Song2016(n_robots=3), {"parent_rule": "nearest"}, "parent_rule'\\]='nearest' is not one of"),
], ids=["no-n", "unknown-key", "negative-timeout", "fractional-timeout", "zero-epsilon",
        "bad-rumor-filter", "bad-parent-rule"])
def test_bad_configuration_is_a_usage_error(alg, extra, match):
    with pytest.raises(UsageError, match=match):
        alg.controller(1, Params(range=1.2, v=0.05, extra=extra), SQUARE, np.random.default_rng(0))


def test_params_extra_overrides_the_constructor():
    cfg = Song2016(n_robots=10, d_s=0.3).config(Params(range=1.2, v=0.05,
                                                       extra={"communication_timeout": 12}), 1.0)
    assert (cfg.communication_timeout, cfg.movement_timeout, cfg.d_s) == (12, 10, 0.3)
    assert cfg.vacancy_tolerance == 0.5 and cfg.rumor_filter == "field"
    assert cfg.parent_rule == "relocate_route"


def test_registry_builds_song2016_with_options():
    alg = get_algorithm("song2016", n_robots=4)
    assert isinstance(alg, Song2016) and alg.name == "song2016"
    assert isinstance(alg.controller(1, P, SQUARE, np.random.default_rng(0)), Song2016Controller)


# ---------------------------------------------------------------------------
# Sec. VI: the sequential fill, and small runs through the engine
# ---------------------------------------------------------------------------

def test_sequential_fill_square_and_hexagon():
    sq = [tuple(round(c, 9) for c in p[:2]) for p, _ in sequential_fill(SQUARE, 7)]
    # library square out-edge order: (1,0), (0,-1), (-1,0), (0,1); then robot 1's (2,0)...
    assert sq == [(0, 0), (1, 0), (0, -1), (-1, 0), (0, 1), (2, 0), (1, -1)]
    hexa = sequential_fill(load("hexagon"), 4)
    assert [r for _, r in hexa] == ["A", "B", "B", "B"]
    with pytest.raises(UsageError, match="no vacancy left after 6 robots"):
        sequential_fill(load("hexagon-ring"), 7)


def run(lattice, n, seed, **kw):
    init = random_connected(n, seed, range=lattice.range, min_separation=0.3)
    return simulate(Song2016(n_robots=n), lattice, init, Params(range=lattice.range, v=0.05),
                    seed=seed, **kw)


def exact_q(poses, roles, lattice, phi):
    """Q of 001 Sec. III-C-2 as an exact fraction (neighbors strictly closer than phi)."""
    xy = np.asarray(poses)[:, :2]
    d = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))
    counts = (d < phi).sum(axis=1) - 1
    return sum(Fraction(int(c), len(lattice.out_edges(r))) for c, r in zip(counts, roles)) / len(roles)


def check_run(r, lattice, n):
    """Terminated, Def. 2 satisfied, connected at every step, the Sec. VI formation."""
    from swarmproof.invariants.connectivity import connected_throughout
    from swarmproof.invariants.satisfaction import satisfies_lattice

    phi = lattice.range
    assert r.status == "finished", (r.status, r.steps)
    ids, poses = r.final_ids, r.final_poses
    sat = satisfies_lattice(ids, poses, lattice, phi)
    assert sat.held, sat
    conn = connected_throughout(r.trace, phi)
    assert conn.held, conn
    # robot of ID rank k (0 = highest) stands at the k-th pose of the sequential fill,
    # in the frame of the highest-ID robot, with the predicted role
    pred = sequential_fill(lattice, n)
    order = np.argsort(-ids)
    rel = relative_many(poses[order[0]], poses[order])
    assert np.abs(rel[:, :2] - np.array([p for p, _ in pred])[:, :2]).max() < 1e-6
    roles = [dict(r.final_states[k])["role"] for k in order]
    assert roles == [role for _, role in pred]
    return exact_q(poses[order], roles, lattice, phi)


@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_small_square_runs_finish_satisfy_stay_connected(n):
    qs = {check_run(run(SQUARE, n, seed), SQUARE, n) for seed in range(2)}
    pred = sequential_fill(SQUARE, n)
    assert qs == {exact_q([p for p, _ in pred], [r for _, r in pred], SQUARE, PHI)}


def test_literal_line_12_deadlocks_short_of_the_lattice():
    """The printed Algorithm 1 (rumor_filter="message") on a start where it deadlocks:
    the relocate robot is not next to the root and never hears of it (never moves)."""
    init = random_connected(5, 2, range=PHI, min_separation=0.3)
    r = simulate(Song2016(n_robots=5, rumor_filter="message"), SQUARE, init, P, seed=2,
                 max_steps=400)
    assert r.status == "step_cap"
    assert np.array_equal(r.trace.poses[-1], r.trace.poses[60])
    unstable = [s for s in r.final_states if not dict(s)["stable"]]
    relocate = [dict(s) for s in unstable if dict(s)["relocate"]]
    assert len(unstable) == 3 and len(relocate) == 1 and relocate[0]["root_id"] is None


def test_same_seed_gives_the_same_trace():
    a, b = run(SQUARE, 5, 7), run(SQUARE, 5, 7)
    assert a.steps == b.steps
    assert np.array_equal(a.trace.poses, b.trace.poses)
    assert a.trace.states == b.trace.states


def test_one_robot_is_stable_after_the_timeout():
    r = simulate(Song2016(n_robots=1), SQUARE, InitialConfiguration([4], [[0, 0, 0]]), P, seed=0)
    assert (r.status, r.steps, dict(r.final_states[0])["role"]) == ("finished", 2, "A")


@pytest.mark.parametrize("cls, lattice, n, seed", [(Song2016, "square", 6, 3), (Song2016, "octagon-square", 7, 1),
                                                    (Song2016SubtreeClock, "octagon-square", 7, 1)])
def test_memoized_controller_gives_the_identical_trace(cls, lattice, n, seed):
    """docs/performance.md: the optimisation must not change a single bit of the trace (nor in
    song2016-subtree-clock, whose moved movement clock the memoisation reads too)."""
    lat = load(lattice)
    init = random_connected(n, seed, range=lat.range, min_separation=0.3)
    p = Params(range=lat.range, v=0.05)
    fast = simulate(cls(n_robots=n), lat, init, p, seed=seed, record_messages=True)
    plain = simulate(cls(n_robots=n, memoize=False), lat, init, p, seed=seed,
                     record_messages=True)
    assert fast.status == "finished" and fast.steps == plain.steps
    assert np.array_equal(fast.trace.poses, plain.trace.poses)
    assert fast.trace.states == plain.trace.states
    assert fast.trace.messages == plain.trace.messages
    assert fast.trace.to_json() == plain.trace.to_json()


def test_relocate_robot_waits_for_children_beyond_d_s_fig_11():
    """Fig. 11 [left]: dist(r_p, r_c) > d_s, r_p waits; [right]: within d_s it moves."""
    c = ctrl(5, n=2, d_s=0.5, communication_timeout=0, movement_timeout=0)
    root = msg(9, highest=9, root=9, stable=True, vacancy=Vacancy(1.0, 0.0, 0.0, "A", 0))
    child = msg(1, highest=9, root=9, root_path=(9, 5, 1), parent=5, relocate=5, subtree=True)
    far = c.step(obs(0, 5, {9: (0.0, 0.5, 0.0), 1: (-0.7, 0.0, 0.0)}, {9: root, 1: child}))
    s = dict(c.state())
    assert s["relocate"] and s["children"] == (1,) and (far.turn, far.forward) == (0.0, 0.0)
    near = c.step(obs(1, 5, {9: (0.0, 0.5, 0.0), 1: (-0.4, 0.0, 0.0)}, {9: root, 1: child}))
    assert near.forward > 0 and dict(c.state())["moving"]


def test_relocate_robot_does_not_wait_for_a_stable_child():
    """A stable child never moves (Sec. V-C case 1): it bounds the safe region, but the
    relocate robot does not wait for it to come within d_s (docs/decisions.md)."""
    c = ctrl(5, n=2, d_s=0.5, communication_timeout=0, movement_timeout=0)
    root = msg(9, highest=9, root=9, stable=True, vacancy=Vacancy(1.0, 0.0, 0.0, "A", 0))
    child = msg(1, highest=9, root=9, root_path=(9, 5, 1), parent=5, stable=True)
    cmd = c.step(obs(0, 5, {9: (0.0, 0.5, 0.0), 1: (-0.7, 0.0, 0.0)}, {9: root, 1: child}))
    s = dict(c.state())
    assert s["children"] == (1,) and cmd.forward > 0
    assert math.dist(s["target"], (-0.7, 0.0)) <= s["safe_radius"]


class _HorizonChecked(Song2016Controller):
    """Checks every repeat_horizon against _time_matters, step by step (test only)."""

    __slots__ = ()
    log: list = []

    def repeat_horizon(self, t):
        h = super().repeat_horizon(t)
        for s in range(t + 1, min(h, t + 200)):
            assert not self._time_matters(s), (self.robot_id, t, s, h)
        self.log.append((h > t + 1, None if h >= 2 ** 62 else self._time_matters(h)))
        return h


class _HorizonSong2016(Song2016):
    def controller(self, robot_id, params, lattice, rng):
        c = super().controller(robot_id, params, lattice, rng)
        c.__class__ = _HorizonChecked
        return c


def test_repeat_horizon_is_exactly_the_next_expiring_timeout():
    """Engine shortcut (docs/performance.md): the engine asks nothing of a robot whose
    observation is unchanged before its repeat_horizon; no timeout may expire in between,
    and one does expire at a finite horizon. The run is the one without shortcuts."""
    _HorizonChecked.log = []
    init = random_connected(7, 2, range=PHI, min_separation=0.3)
    r = simulate(_HorizonSong2016(n_robots=7), SQUARE, init, P, seed=2, record_messages=True)
    plain = simulate(Song2016(n_robots=7, memoize=False), SQUARE, init, P, seed=2,
                     record_messages=True)
    assert r.status == "finished" and r.trace.to_json() == plain.trace.to_json()
    log = _HorizonChecked.log
    assert sum(long for long, _ in log) > 50            # the shortcut was taken
    finite = [tight for long, tight in log if long and tight is not None]
    assert finite and all(finite)


def _literal_lines_10_to_22(my_id, stable, my_vacancy, inbox, per_message):
    """Algorithm 1 lines 3-22 as printed, with the eligible sets kept as lists and the
    shortest paths chosen afterwards (the form before the single-pass optimisation)."""
    def gt(a, b):
        return a is not None and (b is None or a > b)

    def shortest(ms, attr):
        best = None
        for m in ms:
            if best is None or len(getattr(m, attr)) < len(getattr(best, attr)) or (
                    len(getattr(m, attr)) == len(getattr(best, attr)) and m.sender_id > best.sender_id):
                best = m
        return () if best is None else getattr(best, attr)

    highest, root = my_id, (my_id if stable and my_vacancy is not None else None)
    relocate, vac, root_ok, reloc_ok = (None if stable else my_id), None, [], []
    for m in inbox:
        highest = max(highest, m.highest_id)
        in_root, in_reloc = my_id in m.path_from_root, my_id in m.path_from_relocate
        if (not in_root and not per_message) or (per_message and not in_root and not in_reloc):
            root_ok.append(m)
            if gt(m.root_id, root):
                root, vac = m.root_id, m.vacancy
        if (not in_reloc and not per_message) or (per_message and not in_root and not in_reloc):
            reloc_ok.append(m)
            if gt(m.relocate_id, relocate):
                relocate = m.relocate_id
    root_path = shortest([m for m in root_ok if m.root_id == root], "path_from_root") if root is not None else ()
    reloc_path = (shortest([m for m in reloc_ok if m.relocate_id == relocate], "path_from_relocate")
                  if relocate is not None else ())
    return highest, root, relocate, vac, root_path, reloc_path, root_ok


def test_algorithm_1_equals_the_literal_two_pass_form_on_random_inboxes():
    """compute_message folds lines 21-22 into the loop and get_parent_msg is one pass
    (docs/performance.md): same message, same parent as the literal form, 3,000 inboxes."""
    rng = np.random.default_rng(7)
    for _ in range(3000):
        def path():
            return tuple(int(x) for x in rng.choice(12, size=rng.integers(0, 5), replace=False))
        inbox = [Song2016Message(int(rng.integers(12)), int(rng.integers(12)),
                                 [None, 8, 9, 10, 11][rng.integers(5)],
                                 [None, 3, 5, 7, 9, 11][rng.integers(6)], None,
                                 Vacancy(1.0, 0.0, 0.0, "A", int(rng.integers(4))),
                                 bool(rng.random() < 0.3), bool(rng.random() < 0.5), path(), path())
                 for _ in range(rng.integers(0, 8))]
        me, stable = int(rng.integers(12)), bool(rng.random() < 0.5)
        my_vac = Vacancy(0.0, 1.0, 0.0, "A", 1) if rng.random() < 0.5 else None
        for rumor in ("field", "message"):
            for rule in PARENT_RULES:
                got, parent = compute_message(me, stable, my_vac, inbox, rumor, rule)
                hi, root, reloc, vac, rpath, lpath, root_ok = _literal_lines_10_to_22(
                    me, stable, my_vac, inbox, rumor == "message")
                assert (got.highest_id, got.root_id, got.relocate_id) == (hi, root, reloc)
                assert got.vacancy == (my_vac if me == root else vac)
                assert (got.path_from_root, got.path_from_relocate) == (rpath + (me,), lpath + (me,))
                if me != root:
                    stable_first = rule == "stable_first" or (
                        rule == "relocate_route" and (stable or me != reloc))
                    assert parent is _literal_parent(root_ok, root, reloc, stable_first)


def _literal_parent(eligible, root_id, relocate_id, stable_first):
    """Algorithm 1 line 27 / Sec. V-B as a sequence of filters (the unoptimised form)."""
    cands = [m for m in eligible if root_id is not None and m.root_id == root_id and m.path_from_root]
    if stable_first and any(m.stable for m in cands):
        cands = [m for m in cands if m.stable]
    rel = [m for m in cands if m.sender_id == relocate_id]
    if rel and any(len(m.path_from_root) <= len(rel[0].path_from_root)
                   for m in cands if m.sender_id != relocate_id):
        cands = [m for m in cands if m.sender_id != relocate_id]
    best = None
    for m in cands:
        if best is None or len(m.path_from_root) < len(best.path_from_root) or (
                len(m.path_from_root) == len(best.path_from_root) and m.sender_id > best.sender_id):
            best = m
    return best


def test_case3_robot_moves_only_toward_its_parent_regression():
    """Regression case for a defect found 2026-11-24 (docs/song2016.md, "Case 3 ... fixed"): at
    v = 0.8 a case-3 subtree robot outside its safe region drove away from its still parent
    (the waiting relocate robot) and the tree link broke (step 12: 1.0 -> 1.6), because the
    implementation steered to the nearest safe point.  Sec. V-C case 3 says such a robot moves
    directly toward its parent; now it moves along that line only (or waits), and the stored
    counterexample no longer reproduces."""
    import os

    from swarmproof.checkers.replay import replay_file
    from swarmproof.invariants.premises import check_premises

    path = os.path.join(os.path.dirname(__file__), "data", "song2016_case3_moves_away.json")
    r = replay_file(path)
    assert not r.reproduced and r.verdict.status == "held"
    assert r.result.broken_assumptions == ()
    assert not any(x.violated for x in check_premises(r.result.trace))
