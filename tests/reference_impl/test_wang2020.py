"""Wang & Rubenstein 2020 (004, registry ``wang2020``): each rule of Algorithms 2-4 on hand-made
observations, the handshake, both selectors, shape-complete detection, the assumptions, the
runtime invariants on mutated planners, determinism, and a 64-agent run."""

from __future__ import annotations


import numpy as np
import pytest

from swarmproof.invariants.algorithm_invariants import InvariantsMonitor, invariants_of
from swarmproof.invariants.properties import CollisionMonitor
from swarmproof.invariants.registry import collision_radius
from swarmproof.models.errors import AssumptionError
from swarmproof.models.targets import GoalSet, resolve_target
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_grid_connected
from swarmproof.reference_impl.protocol import Observation, Params
from swarmproof.reference_impl.registry import get_algorithm
from swarmproof.reference_impl.wang2020.algorithm import (J1, J2, BroadcastHandshakeController, Wang2020,
                                                          Wang2020BroadcastHandshake, Wang2020Controller, WangMsg,
                                                          default_params,
                                                delta_t_of)

L = 0.2
SQUARE9 = tuple((i, j) for i in range(3) for j in range(3))


def _ctl(cell=(0, 0), goal=(2, 0), *, rid=1, shapes=(SQUARE9,), seed=0, cls=Wang2020Controller, **extra):
    """A started controller at ``cell`` with goal ``goal`` (Alg. 2 lines 1-7 ran at clock 0)."""
    p = default_params(0.6, len(shapes[0]))
    p = Params(range=p.range, v=p.v, dt=p.dt, extra={**p.extra, **extra})
    c = cls(rid, p, shapes, np.random.default_rng(seed))
    c.step(_obs(c, 0.0, cell))
    c.T = goal
    return c


def _obs(c, clock, cell=None, msgs=(), pose=None):
    pose = pose if pose is not None else (cell[0] * L, cell[1] * L)
    return Observation(step=int(clock), robot_id=c.id, neighbor_ids=tuple(s for s, _ in msgs),
                       neighbor_poses=np.zeros((len(msgs), 3)), messages=dict(msgs),
                       own_pose=np.array([pose[0], pose[1], 0.0]), clock=float(clock))


def _msg(cell, *, wp=None, nxt=None, T=(9, 9), q_u=(9, 9), hop=None, completed=0, request=None, ack=None):
    return WangMsg((cell[0] * L, cell[1] * L), wp or cell, nxt or cell, T, q_u, hop, completed, request, ack)


def _tick(c, clock, msgs=()):
    return c.step(_obs(c, clock, c.cell, msgs))


# ---------------------------------------------------------------- Algorithm 2 (motion planner)

@pytest.mark.parametrize("goal, nxt", [((2, 1), (1, 0)), ((0, 2), (0, 1)), ((-1, -1), (-1, 0)),
                                       ((0, -3), (0, -1)), ((0, 0), (0, 0))])
def test_lines_9_to_14_pick_the_first_of_w_s_e_n_that_reduces_the_distance_else_stay(goal, nxt):
    c = _ctl(goal=goal)
    c.step(_obs(c, 1.0, (0, 0)))
    assert c.next_step == nxt


def test_line_30_moves_only_after_waiting_more_than_delta_t():
    c = _ctl(goal=(2, 0))
    assert delta_t_of(default_params()) == 4.0
    moves = [_tick(c, t).move for t in (1.0, 2.0, 3.0, 4.0)]      # clock - last_check <= 4: wait
    assert moves == [None] * 4 and not c.moving
    assert _tick(c, 5.0).move == (1, 0) and c.moving and c.wp == (1, 0) and c.cell == (0, 0)
    st = dict(c.state())
    assert st["cell"] == (0, 0) and st["next"] == (1, 0) and st["goal"] == (2, 0) and st["priority"] == (0.0, 0.0)


def test_line_26_waits_while_a_message_claims_next_step():
    c = _ctl(goal=(2, 0))
    assert _tick(c, 5.0, [(7, _msg((1, 0)))]).move is None            # robot 7 stands on (1, 0)
    assert dict(c.state())["next"] == (1, 0)
    assert _tick(c, 6.0, [(7, _msg((1, 1), wp=(1, 0)))]).move is None  # robot 7 moving to (1, 0)
    # the messages leave msg_buff after Delta t (received at 6 -> kept while clock - 4 <= 6)
    assert _tick(c, 10.0).move is None and _tick(c, 10.5).move == (1, 0)


@pytest.mark.parametrize("other, waits", [((2, 0), True), ((1, 1), True), ((0, 1), True), ((-1, 0), False),
                                          ((0, -1), False)])
def test_line_28_yields_to_a_lexically_larger_agent_heading_for_the_same_waypoint(other, waits):
    c = _ctl(cell=(0, 0), goal=(2, 0))                   # next_step (1, 0); p = (0, 0)
    mv = _tick(c, 5.0, [(7, _msg(other, nxt=(1, 0)))]).move
    assert (mv is None) == waits and (waits or mv == (1, 0))


def test_a_moving_agent_resets_last_check_on_arrival_line_33():
    c = _ctl(goal=(1, 0))
    assert _tick(c, 5.0).move == (1, 0)
    c.step(_obs(c, 6.0, pose=(0.1, 0.0)))                 # on the edge: blocked in line 32
    assert c.moving and c.cell == (0, 0)
    c.step(_obs(c, 9.0, pose=(0.2, 0.0)))                 # arrived
    assert not c.moving and c.cell == (1, 0) and c.last_check == 9.0


def test_lines_15_to_24_the_gradient_takes_the_lowest_hop_and_anchors_next_to_a_free_goal():
    c = _ctl(cell=(5, 5), goal=(2, 2))
    _tick(c, 1.0, [(7, _msg((5, 6), hop=3, q_u=(0, 0))), (8, _msg((6, 5), hop=None, q_u=(1, 1)))])
    assert (c.hop, c.q_u) == (4, (0, 0))                  # line 19-20: 1 + the lowest hop
    d = _ctl(cell=(3, 1), goal=(0, 0))                    # (2, 1) is in Q, one grid length away (W)
    _tick(d, 1.0, [(7, _msg((4, 1), hop=2, T=(2, 0)))])
    assert (d.hop, d.q_u) == (0, (2, 1))                  # lines 21-24: an anchor
    e = _ctl(cell=(3, 1), goal=(0, 0))
    _tick(e, 1.0, [(7, _msg((4, 1), hop=2, T=(2, 1), q_u=(0, 2)))])
    assert (e.hop, e.q_u) == (3, (0, 2))                  # (2, 1) is held by robot 7: no anchor


# ---------------------------------------------------------------- Algorithm 4 (goal manager)

def test_lines_3_to_10_the_lexically_smaller_agent_leaves_a_shared_goal_gradient_selector():
    c = _ctl(cell=(0, 0), goal=(2, 2), p_random=0.0)
    c.q_u = (1, 2)
    _tick(c, 2.0, [(7, _msg((0, 1), T=(2, 2), hop=None, q_u=(1, 2)))])
    assert c.T == (1, 2) and c.last_check == 2.0          # line 7 (q_u) and the timer reset
    big = _ctl(cell=(3, 3), goal=(2, 2), p_random=0.0)
    _tick(big, 2.0, [(7, _msg((0, 1), T=(2, 2)))])
    assert big.T == (2, 2) and big.last_check == 0.0      # the larger one keeps it


def test_the_random_selector_draws_from_q_and_the_mix_is_ninety_ten():
    picks = []
    for seed in range(200):
        c = _ctl(cell=(0, 0), goal=(2, 2), p_random=1.0, seed=seed)
        c.q_u = (8, 8)
        _tick(c, 2.0, [(7, _msg((0, 1), T=(2, 2)))])
        picks.append(c.T)
    assert set(picks) <= set(SQUARE9) and len(set(picks)) >= 8        # random selector: all of Q
    mixed = []
    for seed in range(400):
        c = _ctl(cell=(0, 0), goal=(2, 2), seed=seed)
        c.q_u = (8, 8)                                                 # not in Q: marks the gradient pick
        _tick(c, 2.0, [(7, _msg((0, 1), T=(2, 2)))])
        mixed.append(c.T == (8, 8))
    assert 0.85 < np.mean(mixed) < 0.95                                # Alg. 4 line 6: rand > 0.1


def _swap_pair(cls=Wang2020Controller):
    """Client at (0, 0) (goal (0, 2)), server at (0, 2) (goal (0, 0)): a swap saves 4 edges."""
    return _ctl(cell=(0, 0), goal=(0, 2), rid=1, cls=cls), _ctl(cell=(0, 2), goal=(0, 0), rid=2, cls=cls)


def test_line_11_cost_reducing_swap_runs_the_two_way_handshake_as_one_exchange_within_the_tick():
    """The default (Sec. III-A under II-A c, e): the client sends its request once, point to point
    (``requests``, the first phase of the tick), never in its broadcast; the server answers within
    the tick; both commit there, before either's Algorithm 2 runs (``step``, the second phase), so
    no step sees two agents on one goal."""
    client, server = _swap_pair()
    o_client = _obs(client, 1.0, client.cell, [(2, _msg((0, 2), T=(0, 0)))])
    assert client.requests(o_client) == ((2, (1, (0, 2))),)                           # sent once ...
    assert client.hs.role == "client" and client.T == (0, 2)
    o_server = _obs(server, 1.0, server.cell, [(1, _msg((0, 0), T=(0, 2)))])
    assert server.requests(o_server) == () and server.hs.role == "server" and server.T == (0, 0)
    reply = server.answer(1, (1, (0, 2)), 1.0)                     # the server commits on the request
    assert reply == ("ack", 1, (0, 0)) and server.T == (0, 2) and server.hs is None and server.swaps == 1
    client.on_reply(2, (1, (0, 2)), reply, 1.0)                    # the client commits on the ACK
    assert client.T == (0, 0) and client.hs is None and client.last_check == 1.0 and client.swaps == 1
    assert J2([client.state(), server.state()]) == 0
    # then Algorithm 2 with the new goals: the timer was reset, nobody moves this tick
    cmd_c, cmd_s = client.step(o_client), server.step(o_server)
    assert cmd_c.message.request is None and cmd_c.message.T == (0, 0) and cmd_c.move is None
    assert cmd_s.message.T == (0, 2) and cmd_s.move is None
    o2 = _obs(client, 2.0, client.cell)
    assert client.requests(o2) == ()                                                   # ... only once
    # a tick driven by step() alone (no engine exchange) never sends a request
    lone, _ = _swap_pair()
    _tick(lone, 1.0, [(2, _msg((0, 2), T=(0, 0)))])
    assert lone.hs.role == "client" and lone.requests(_obs(lone, 2.0, lone.cell)) == ()


def test_a_server_nacks_anyone_but_its_intended_peer_and_a_nack_releases_the_client_at_once():
    client, server = _swap_pair()
    client.requests(_obs(client, 1.0, client.cell, [(2, _msg((0, 2), T=(0, 0)))]))
    assert server.answer(1, (1, (0, 2)), 1.0) == ("nack", 1)       # the server never intended this swap
    assert server.T == (0, 0)
    client.on_reply(2, (1, (0, 2)), ("nack", 1), 1.0)
    assert client.hs is None and client.T == (0, 2)                # released, goal kept
    _tick(server, 1.0, [(1, _msg((0, 0), T=(0, 2)))])
    assert server.answer(9, (5, (1, 1)), 2.0) == ("nack", 5) and server.hs.peer == 1 and server.T == (0, 0)
    for t in range(2, 15):
        _tick(server, float(t))
    assert server.hs is None                                        # its wait times out (1 + 3 Delta t = 13)
    assert server.answer(1, (2, (0, 2)), 15.0) == ("nack", 2) and server.T == (0, 0)


def test_the_broadcast_handshake_variant_is_not_atomic_the_server_commits_a_broadcast_earlier():
    """Reading "1" (``wang2020-broadcast-handshake``): request and ACK ride in the broadcasts, so
    between the server's update and the client's both hold the client's goal (J2 = 1), and a
    client whose timeout ends first never takes the server's goal (a half swap)."""
    client, server = _swap_pair(BroadcastHandshakeController)
    cmd = _tick(client, 1.0, [(2, _msg((0, 2), T=(0, 0)))])
    assert client.hs.role == "client" and cmd.message.request == (2, 1, (0, 2)) and client.requests is None
    m_server = _tick(server, 1.0, [(1, _msg((0, 0), T=(0, 2)))]).message
    assert server.hs.role == "server" and m_server.request is None and server.T == (0, 0)
    m_server = _tick(server, 2.0, [(1, cmd.message)]).message       # the request: server updates first
    assert server.T == (0, 2) and server.swaps == 1 and m_server.ack == (1, 1, (0, 0))
    assert J2([client.state(), server.state()]) == 1                # not atomic: both hold (0, 2) now
    _tick(client, 3.0, [(2, m_server)])                             # the ACK
    assert client.T == (0, 0) and client.hs is None and client.last_check == 3.0
    late, server = _swap_pair(BroadcastHandshakeController)         # the half swap: the ACK after the timeout
    cmd = _tick(late, 1.0, [(2, _msg((0, 2), T=(0, 0)))])
    _tick(server, 1.0, [(1, _msg((0, 0), T=(0, 2)))])
    m_server = _tick(server, 2.0, [(1, cmd.message)]).message
    for t in range(2, 15):
        _tick(late, float(t))                                       # timeout 3 Delta t = 12
    assert late.hs is None and late.T == (0, 2) == server.T and J2([late.state(), server.state()]) == 1
    _tick(late, 15.0, [(2, m_server)])                              # the ACK, too late: not taken
    assert late.T != (0, 0) and server.T == (0, 2)                  # (0, 0) is nobody's goal now


def test_the_handshake_times_out_and_the_variant_server_does_not_answer_another_agent():
    client, server = _swap_pair(BroadcastHandshakeController)
    _tick(client, 1.0, [(2, _msg((0, 2), T=(0, 0)))])
    for t in range(2, 13):
        _tick(client, float(t))
    assert client.hs is not None
    _tick(client, 14.0)                                             # timeout 3 Delta t = 12
    assert client.hs is None and client.T == (0, 2)
    _tick(server, 1.0, [(1, _msg((0, 0), T=(0, 2)))])
    stranger = _msg((0, 1), T=(1, 1), request=(2, 5, (1, 1)))
    m = _tick(server, 2.0, [(9, stranger)]).message
    assert server.T == (0, 0) and m.ack is None and server.hs.peer == 1


def test_line_16_equal_cost_swaps_with_probability_beta():
    started = []
    for seed in range(200):
        c = _ctl(cell=(0, 0), goal=(1, 0), seed=seed, beta=0.3)
        _tick(c, 1.0, [(7, _msg((1, 1), T=(0, 1)))])              # 1 + 1 either way
        started.append(c.hs is not None)
    assert 0.2 < np.mean(started) < 0.4


# ---------------------------------------------------------------- shape complete and the next shape

def test_shape_complete_when_the_hop_count_exceeds_the_agents_then_the_next_shape():
    second = tuple((10 + i, j) for i, j in SQUARE9)
    c = _ctl(cell=(5, 5), goal=(1, 1), shapes=(SQUARE9, second))    # no goal cell next to it
    _tick(c, 1.0, [(7, _msg((5, 6), hop=8, T=(1, 2)))])
    assert c.hop == 9 and c.completed == 0                         # 9 is not > |A| = 9
    _tick(c, 6.0, [(7, _msg((5, 6), hop=9, T=(1, 2)))])              # hop 8 has left msg_buff
    assert c.completed == 1 and c.T in second and c.hop == float("inf") and not dict(c.state())["done"]
    d = _ctl(cell=(0, 0), goal=(0, 0), shapes=(SQUARE9, second), rid=3)
    _tick(d, 1.0, [(1, c.message())])                              # the news propagates
    assert d.completed == 1 and d.T in second
    one = _ctl(cell=(5, 5), goal=(1, 1))
    _tick(one, 1.0, [(7, _msg((5, 6), hop=9, T=(1, 2)))])
    assert dict(one.state())["done"] and Wang2020().finished([one.state()])


def test_two_shapes_in_a_row_through_the_engine():
    line = GoalSet.from_bitmap("line-5", ["#####"], spacing=0.2, origin=(0.0, 1.0))
    shape = resolve_target("shape:letter-l")
    alg = Wang2020(then=line)
    init = InitialConfiguration(list(range(5)), [[0.2 * x, 0.2 * y, 0] for x, y in
                                                 [(-2, 0), (-1, 0), (-2, 1), (-1, 1), (-2, 2)]])
    r = simulate(alg, shape, init, alg.default_params(0.6, 5), seed=1)
    assert r.status == "finished" and line.satisfied(r.final_ids, r.final_poses).status == "held"
    assert {dict(s)["completed"] for s in r.final_states} == {2}


# ---------------------------------------------------------------- assumptions (engine checks)

def _params(**extra):
    p = default_params()
    return Params(range=extra.pop("range", 0.6), v=p.v, dt=p.dt, extra={**p.extra, **extra})


@pytest.mark.parametrize("params, target, n, match", [
    (_params(range=0.25), "shape:letter-l", 5, r"range_vs_radius"),
    (_params(grid_spacing=0.1), "shape:letter-l", 5, r"grid_spacing_bounds"),
    (_params(range=0.35), "shape:letter-l", 5, r"grid_spacing_bounds.*\[0.141421, 0.175\]"),
    (_params(clock_rate_min=0.9, clock_rate_max=1.1), "shape:letter-l", 5, r"same_clock_frequency"),
    (_params(delta_t=3.0), "shape:letter-l", 5, r"message_window.*delta_t=3.0 < 2/f_comm"),
    (_params(beta=1.0), "shape:letter-l", 5, r"beta=1.0 must be in \(0, 1\)"),
    (_params(), "shape:letter-l", 4, r"goal_count.*\|Q\|=5 goal cells of 'letter-l' but \|A\|=n=4"),
    (_params(), GoalSet.from_bitmap("apart", ["#.#"], spacing=0.2), 2, r"goal_connected"),
    (_params(), GoalSet.from_bitmap("off", ["##"], spacing=0.25), 2, r"goals_on_grid"),
], ids=["R<4sqrt2r", "l<2sqrt2r", "l>R/2", "clock-rates", "window", "beta", "|Q|!=|A|", "Q-apart", "Q-off-grid"])
def test_broken_assumptions_are_named(params, target, n, match):
    tgt = resolve_target(target) if isinstance(target, str) else target
    init = InitialConfiguration(list(range(n)), [[0.2 * k, 0.0, 0.0] for k in range(n)])
    with pytest.raises(AssumptionError, match=match):
        simulate(Wang2020(), tgt, init, params, seed=0, max_steps=1)
    r = simulate(Wang2020(), tgt, init, params, seed=0, max_steps=1, allow_violations=True)
    assert r.broken_assumptions


def test_collision_radius_comes_from_params_unless_given():
    assert collision_radius(default_params(), {}) == 0.05
    assert collision_radius(Params(range=1.0), {}) == 0.1 and collision_radius(default_params(), {"radius": 0.3}) == 0.3


def test_registry_and_declarations():
    alg = get_algorithm("wang2020")
    assert alg.name == "wang2020" and alg.model.motion == "grid" and alg.model.neighbor_rule == "inclusive"
    assert [i.name for i in alg.invariants] == ["constraint_vertex", "constraint_edge", "j_bounded", "j2_monotone",
                                               "j1_monotone", "pairwise_swap"]
    assert alg.invariants[0] is not alg.invariants[0]             # fresh J memory per monitor


# ---------------------------------------------------------------- invariants on mutated planners

class IgnorePriority(Wang2020Controller):
    """Mutant: Alg. 2 line 28 dropped."""

    def yields_to(self, m):
        return False


class SwapOnEdge(Wang2020Controller):
    """Mutant: line 26 ignores an occupant that wants this agent's waypoint (a head-on swap)."""

    def occupied(self, m):
        return m.wp == self.next_step and m.next_step != self.wp


def _monitored(alg, seed, n=9, target="shape:square-9"):
    mon, col = InvariantsMonitor(invariants_of(alg)), CollisionMonitor(0.05)
    init = random_grid_connected(n, seed, range=0.6, spacing=0.2)
    r = simulate(alg, resolve_target(target), init, alg.default_params(0.6, n), seed=seed, observers=(mon, col))
    return r, mon, col.result()


@pytest.mark.parametrize("mutant, seed, invariant", [(IgnorePriority, 0, "constraint_vertex"),
                                                     (SwapOnEdge, 12, "constraint_edge")])
def test_mutated_planners_break_the_constraints_the_paper_does_not(mutant, seed, invariant):
    r, mon, col = _monitored(Wang2020(), seed)
    assert r.status == "finished" and "constraint_vertex" not in mon.first and "constraint_edge" not in mon.first
    assert col.status == "held"
    alg = type("Mutant", (Wang2020,), {"controller_class": mutant})()
    _, mon, col = _monitored(alg, seed)
    assert invariant in mon.first, mon.first
    assert col.status == "violated"


def test_the_broadcast_handshake_lets_j2_rise_the_default_keeps_lemma_iv_b2_on_the_same_start():
    r, mon, _ = _monitored(Wang2020BroadcastHandshake(), 2, n=5, target="shape:letter-l")
    step, msg = mon.first["j2_monotone"]
    assert "J2 rose" in msg and "handshake ('server'" in msg and "j_bounded" not in mon.first
    r, mon, _ = _monitored(Wang2020(), 2, n=5, target="shape:letter-l")
    assert r.status == "finished" and "j2_monotone" not in mon.first


@pytest.mark.parametrize("seed", range(4))
def test_the_default_keeps_lemma_iv_b2_and_pairwise_swaps_on_nine_agents(seed):
    """Under II-A c, e a swap is atomic and completes before Algorithm 2 acts (the two-phase tick):
    J2 never rises, J1 never rises while J2 = 0, no half swap (Lemma IV-B.2, Sec. III-A), on runs
    that complete handshakes."""
    r, mon, col = _monitored(Wang2020(), seed)
    assert r.status == "finished" and not mon.first and col.status == "held"
    took = {dict(s)["took"] for frame in r.trace.states for s in frame if dict(s)["took"]}
    assert {t[0] for t in took} == {"client", "server"} and len(took) >= 4


def test_two_agents_through_the_engine_each_swap_is_one_exchange_event_and_j2_never_rises():
    """The scripted pair through the engine, messages recorded: every handshake is an ``exchange``
    request and its reply in the same step, the two goals swap in that step, and J2 never rises;
    the variant's pair on the same start shows J2 rising (its half of a swap in one step)."""
    pair = GoalSet.from_bitmap("pair", ["##"], spacing=0.2, range=0.6)
    init = InitialConfiguration([1, 2], [[0.0, 0.4, 0.0], [0.2, 0.4, 0.0]])
    seen = 0
    for seed in range(12):
        alg = Wang2020()
        r = simulate(alg, pair, init, alg.default_params(0.6, 2), seed=seed, record_messages=True)
        ex = [e for e in r.trace.events if e.kind == "exchange"]
        for q in [e for e in ex if dict(e.detail)["kind"] == "request"]:
            a = [e for e in ex if dict(e.detail)["kind"] == "reply" and e.step == q.step and e.robots == q.robots[::-1]]
            assert len(a) == 1 and dict(a[0].detail)["reply"][0] in ("ack", "nack")
            reply = dict(a[0].detail)["reply"]
            if reply[0] == "ack":                   # after the step: each holds what the other had
                seen += 1
                client, server = q.robots
                after = {rid: dict(s)["goal"] for rid, s in zip(r.trace.ids.tolist(), r.trace.states[q.step + 1])}
                assert (after[client], after[server]) == (tuple(reply[2]), tuple(dict(q.detail)["request"][1]))
        assert all(m is None or (m.request is None and m.ack is None)
                   for frame in r.trace.messages for m in frame.values())
        j2 = [J2(frame) for frame in r.trace.states[1:]]
        assert all(b <= a for a, b in zip(j2, j2[1:]))
    assert seen > 0
    rises = 0
    for seed in range(12):
        alg = Wang2020BroadcastHandshake()
        r = simulate(alg, pair, init, alg.default_params(0.6, 2), seed=seed)
        j2 = [J2(frame) for frame in r.trace.states[1:]]
        rises += sum(b > a for a, b in zip(j2, j2[1:]))
    assert rises > 0


# ---------------------------------------------------------------- determinism and scale

def test_same_seed_same_trace_other_seed_other_phases():
    shape = resolve_target("shape:square-9")
    alg = Wang2020()

    def go(seed):
        init = random_grid_connected(9, 3, range=0.6, spacing=0.2)
        return simulate(alg, shape, init, alg.default_params(0.6, 9), seed=seed)
    a, b, c = go(4), go(4), go(5)
    assert a.trace.poses.tobytes() == b.trace.poses.tobytes() and a.trace.events == b.trace.events
    assert a.trace.states == b.trace.states
    assert a.trace.meta["clocks"]["phase"] != c.trace.meta["clocks"]["phase"]
    assert a.trace.poses.tobytes() != c.trace.poses.tobytes()


# slow by nature (issue 29): a 64-agent asynchronous run to the end (22 s CPU measured; its 60 s wall
# check failed on the loaded machine at 88 s); the small runs of this file keep the code path.
@pytest.mark.slow
def test_sixty_four_agents_form_an_eight_by_eight_square():
    square = GoalSet.from_bitmap("square-64", ["#" * 8] * 8, spacing=0.2, range=0.6)
    alg = Wang2020()
    init = random_grid_connected(64, 1, range=0.6, spacing=0.2)
    r = simulate(alg, square, init, alg.default_params(0.6, 64), seed=1, record_every=100)
    # no wall-clock bound here (it failed at 203 s on a loaded machine): speed is measured in
    # benchmarks/wang2020/, not in tests
    assert r.status == "finished" and square.satisfied(r.final_ids, r.final_poses).status == "held"


def test_the_z3_lemmas_premises_hold_on_a_run_through_the_premises_property():
    """wang2020 declares the premise monitors of its lemmas; on a 9-robot run each one judges
    departures (not vacuous) and holds -- robots exactly R = 3 l apart hear each other."""
    from swarmproof.checkers.runs import run_and_check
    from swarmproof.invariants.premises import MONITORS
    from swarmproof.models.targets import resolve_target

    c = run_and_check("wang2020", resolve_target("shape:square-9"), seed=0, robots=9)
    p = c.params
    for name in type(c.algorithm).premise_monitors:
        r = MONITORS[name](c.result.trace, p.range, p.v, p.dt)
        assert r.status == "held" and r.applicable, (name, r.message)


def test_inclusive_neighbours_at_exactly_R_on_the_grid():
    import numpy as np

    from swarmproof.models.sensing import neighbor_pairs

    xy = np.array([[2 * 0.2, -0.2], [-1 * 0.2, -0.2]])      # 3 cells apart: 0.6000000000000001 in floats
    assert len(neighbor_pairs(xy, 0.6, inclusive=True)[0]) == 1
    assert len(neighbor_pairs(xy, 0.6, inclusive=False)[0]) == 0
