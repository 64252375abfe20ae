"""Unit tests of the song2014 controller logic on hand-made observations (no engine).

Each test drives :class:`Song2014Controller` or a pure function of
swarmproof.reference_impl.song2014 with an input whose correct output follows
from 000 Sec. IV by hand, and checks that output.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from swarmproof.models.errors import AssumptionError, ProtocolError
from swarmproof.models.lattice import LatticeGraph
from swarmproof.models.se2 import SE2
from swarmproof.reference_impl.protocol import Observation, Params
from swarmproof.reference_impl.song2014.algorithm import (
    ROLE_UNMATCHED, Song2014, Song2014Message, authority_key, descendant_motion, is_higher,
    match_positions, select_parent, solve_matching, unmatched_steps, weight_matrix,
)

SQUARE = LatticeGraph("square", ["A"], [("A", "A", SE2(1, 0, 0)), ("A", "A", SE2(0, 1, 0)),
                                        ("A", "A", SE2(-1, 0, 0)), ("A", "A", SE2(0, -1, 0))])
# Hexagon of 000 Fig. 3 scaled to edge length 1: two roles, three edges each.
_H = [(0, 1), (-math.sqrt(3) / 2, -0.5), (math.sqrt(3) / 2, -0.5)]
HEX = LatticeGraph("hexagon", ["L", "R"],
                   [("L", "R", SE2(x, y, 0)) for x, y in _H] + [("R", "L", SE2(-x, -y, 0)) for x, y in _H])
P = Params(range=1.2, v=0.05, omega=math.pi / 4, dt=1.0)


def obs(step, ids, poses, messages=None, rid=0):
    return Observation(step=step, robot_id=rid, neighbor_ids=tuple(ids),
                       neighbor_poses=np.asarray(poses, dtype=float).reshape(-1, 3),
                       messages=messages or {})


def ctrl(rid, lattice=SQUARE, params=P):
    return Song2014().controller(rid, params, lattice, np.random.default_rng(0))


# -- Sec. IV-A: authorities ---------------------------------------------------

@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(0, 5), min_size=1, max_size=4), st.lists(st.integers(0, 5), min_size=1, max_size=4))
def test_authority_key_orders_exactly_like_def5(a, b):
    a, b = tuple(a), tuple(b)
    if authority_key(a) != authority_key(b):
        assert is_higher(a, b) == (authority_key(a) > authority_key(b))
        assert is_higher(a, b) != is_higher(b, a)
    else:
        assert not is_higher(a, b) and not is_higher(b, a)


def test_select_parent_discards_authorities_holding_own_id():
    msgs = {8: Song2014Message((9, 4, 8), ()), 3: Song2014Message((3,), ())}
    # (9, 4, 8) would win but holds 4: discarded; (3,) loses to <4>: root.
    assert select_parent(4, msgs) == (None, (4,))


def test_select_parent_prefers_shorter_chain_then_higher_sender():
    msgs = {1: Song2014Message((9, 5, 1), ()), 2: Song2014Message((9, 2), ()),
            3: Song2014Message((9, 3), ()), 7: None}
    assert select_parent(0, msgs) == (3, (9, 3, 0))


def test_select_parent_reports_a_def5_tie():
    # Same root, length and sender from two different message keys: impossible
    # with a faithful engine; reported, not hidden.
    msgs = {1: Song2014Message((9, 5), ()), 2: Song2014Message((9, 5), ())}
    with pytest.raises(ProtocolError, match="tie under Def. 5"):
        select_parent(0, msgs)


# -- Def. 6: matching ---------------------------------------------------------

def brute_force(w, n_edges, forced):
    """The paper's optimum by enumeration: minimum sum of edge distances over the
    assignments of rows to distinct columns of the N x max(N, E) matrix that use
    no forced-infinite cell (null columns are free but count-fixed)."""
    n, m = w.shape
    best = math.inf
    for perm in itertools.permutations(range(m), n):
        cost = 0.0
        ok = True
        for r, c in enumerate(perm):
            if forced is not None and (r == forced[0]) != (c == forced[1]):
                ok = False
                break
            if c < n_edges:
                cost += w[r, c] if forced is None or (r, c) != forced else 0.0
        if ok:
            best = min(best, cost)
    return best


@settings(max_examples=150, deadline=None)
@given(st.integers(1, 5), st.integers(1, 4), st.integers(0, 10**6), st.booleans())
def test_solve_matching_is_the_paper_optimum(n, e, seed, with_forced):
    rng = np.random.default_rng(seed)
    nb = rng.uniform(-2, 2, size=(n, 2))
    ex = rng.uniform(-2, 2, size=(e, 2))
    forced = (int(rng.integers(n)), int(rng.integers(e))) if with_forced else None
    w = weight_matrix(nb, ex, forced)
    assert w.shape == (n, max(n, e))
    cols = solve_matching(w, e, forced)
    used = [c for c in cols if c is not None]
    assert len(used) == len(set(used)) == min(n, e)       # nulls only as last resort
    if forced is not None:
        assert cols[forced[0]] == forced[1]
    total = sum(w[r, c] for r, c in enumerate(cols) if c is not None)
    assert total == pytest.approx(brute_force(w, e, forced), abs=1e-9)


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 7), st.integers(0, 6), st.integers(0, 10**6), st.booleans())
def test_fused_matching_equals_paper_matrix_matching(n, e, seed, with_forced):
    rng = np.random.default_rng(seed)
    nb = rng.uniform(-2, 2, size=(n, 2))
    ex = rng.uniform(-2, 2, size=(e, 2)).reshape(e, 2)
    forced = (int(rng.integers(n)), int(rng.integers(e))) if with_forced and n and e else None
    assert match_positions(nb, ex, forced) == solve_matching(weight_matrix(nb, ex, forced), e, forced)


def test_root_matching_sends_the_farthest_extra_robot_to_null():
    # Fig. 5: four neighbors near the square's four slots and a fifth nearby.
    pos = [[1.0, 0.05, 0], [0.0, 0.9, 0], [-1.1, 0, 0], [0, -1, 0], [0.6, 0.6, 0]]
    c = ctrl(10)
    cmd = c.step(obs(0, [1, 2, 3, 4, 5], pos, rid=10))
    assert cmd.message == Song2014Message((10,), ((1, 0), (2, 1), (3, 2), (4, 3), (5, None)))
    assert (cmd.turn, cmd.forward) == (0.0, 0.0)           # Sec. IV-C: roots do not move
    st_ = dict(c.state())
    assert st_["root"] is True and st_["role"] == "A" and st_["parent"] is None


# -- Sec. IV-B-2 and IV-C: descendants ------------------------------------------

def test_descendant_takes_terminal_role_and_forces_parent_to_inverse_edge():
    # Robot 3 is at the origin; parent 9 sits 0.8 to its left, facing +x.
    # The parent (role L) matched robot 3 to edge 2: L -> R at (sqrt3/2, -0.5).
    c = ctrl(3, HEX)
    pmsg = Song2014Message((9,), ((3, 2), (4, 0)))
    cmd = c.step(obs(5, [4, 9], [[0.2, 0.9, 0], [-0.8, 0, 0]], {9: pmsg}, rid=3))
    s = dict(c.state())
    assert s["role"] == "R" and s["parent"] == 9 and s["root"] is False and s["edge"] == 2
    assert cmd.message.authority == (9, 3)
    # The inverse of edge 2 is edge 5 (R -> L at (-sqrt3/2, 0.5)); the parent's row gets it.
    assert dict(cmd.message.matching)[9] == 5
    # Destination = parent pose composed with T(e).
    dest = (-0.8 + math.sqrt(3) / 2, -0.5)
    assert s["target"][:2] == pytest.approx(dest, abs=1e-9)
    # Intermediate destination: within v*dt of itself and phi - v*dt of the parent.
    q = (cmd.forward * math.cos(cmd.turn), cmd.forward * math.sin(cmd.turn))
    assert math.hypot(*q) <= P.v * P.dt + 1e-12
    assert math.hypot(q[0] + 0.8, q[1]) <= P.range - P.v * P.dt + 1e-12


def test_descendant_stays_inside_lemma7_disc_when_destination_is_beyond_it():
    # Parent 1.1 away on +x, destination 1.0 further beyond: the robot is pulled
    # to the disc of radius phi - v dt = 1.15 around the parent.
    turn, fwd, dest = descendant_motion((1.1, 0.0, math.pi), (1.0, 0.0, 0.0), P, 1e-9)
    assert dest[:2] == pytest.approx((0.1, 0.0), abs=1e-12)
    turn2, fwd2, _ = descendant_motion((1.1, 0.0, 0.0), (0.0, 2.0, 0.0), P, 1e-9)
    q = (fwd2 * math.cos(turn2), fwd2 * math.sin(turn2))
    assert math.hypot(q[0] - 1.1, q[1]) == pytest.approx(P.range - P.v * P.dt, abs=1e-12) or \
        math.hypot(*q) == pytest.approx(P.v * P.dt, abs=1e-12)
    assert math.hypot(q[0] - 1.1, q[1]) <= P.range - P.v * P.dt + 1e-12


def test_descendant_at_destination_turns_to_eq8_heading():
    turn, fwd, dest = descendant_motion((-1.0, 0.0, 0.3), (math.cos(0.3), -math.sin(0.3), 0.5), P, 1e-9)
    # T_p @ T(e): position (-1 + 1, 0) = origin; heading 0.3 + 0.5.
    assert dest[:2] == pytest.approx((0.0, 0.0), abs=1e-12)
    assert (turn, fwd) == (pytest.approx(0.8), 0.0)


def test_descendant_absent_from_parent_matching_waits_without_role():
    c = ctrl(3)
    cmd = c.step(obs(2, [9], [[0.5, 0, 0]], {9: Song2014Message((9,), ((7, 0),))}, rid=3))
    assert dict(c.state())["role"] is None and dict(c.state())["parent"] == 9
    assert cmd.message == Song2014Message((9, 3), ()) and (cmd.turn, cmd.forward) == (0.0, 0.0)


# -- Sec. IV-D: unmatched robots -------------------------------------------------

def test_unmatched_robot_moves_away_silent_for_2phi_over_v_then_resumes():
    c = ctrl(3)
    k = unmatched_steps(P)
    assert k == math.ceil(2 * 1.2 / 0.05)
    # Parent 9 straight ahead: "directly away" is a half turn.
    cmd = c.step(obs(10, [9], [[0.5, 0, 0]], {9: Song2014Message((9,), ((3, None),))}, rid=3))
    s = dict(c.state())
    assert cmd.message is None and s["role"] == ROLE_UNMATCHED and s["unmatched_until"] == 10 + k
    assert s["parent"] is None and s["root"] is False and s["authority"] == ()
    turns, fwds = [cmd.turn], [cmd.forward]
    for t in range(11, 10 + k):
        cmd = c.step(obs(t, [9], [[0.5, 0, 0]], {9: Song2014Message((9,), ((3, 0),))}, rid=3))
        assert cmd.message is None                       # ignores messages, stays silent
        turns.append(cmd.turn)
        fwds.append(cmd.forward)
    assert abs(sum(turns)) == pytest.approx(math.pi)       # turned to face away
    assert all(abs(t) <= P.omega * P.dt + 1e-12 for t in turns)
    assert fwds[0] == 0.0 and fwds[-1] == pytest.approx(P.v * P.dt)
    cmd = c.step(obs(10 + k, [], [], {}, rid=3))           # resumes: no one around, root
    assert dict(c.state())["root"] is True and cmd.message == Song2014Message((3,), ())


# -- assumptions and construction -------------------------------------------------

@pytest.mark.parametrize(
    "params, ids, name, match",
    [
        (Params(range=1.0, v=1.0, dt=1.0), [0, 1], "v_dt_below_range", r"v\*dt=1.0 .* not below range=1.0"),
        (Params(range=1.0), [0, 1, 1], "unique_ids", r"duplicated \[1\]"),
        (Params(range=1.0), None, "unique_ids", r"ids=None"),
        (Params(range=1.0, v=0.0), [0, 1], "positive_speed", r"v=0.0 is not > 0"),
    ],
    ids=["v-dt-equals-range", "duplicate-ids", "anonymous", "zero-speed"],
)
def test_assumptions_report_breaks(params, ids, name, match):
    a = {x.name: x for x in Song2014.assumptions}[name]
    msg = a.check(params, 3, ids)
    assert msg is not None
    import re
    assert re.search(match, msg)


def test_assumptions_hold_on_default_parameters():
    assert all(a.check(P, 3, [0, 1, 2]) is None for a in Song2014.assumptions)


def test_lattice_without_inverse_edge_is_refused():
    half = LatticeGraph("half", ["A"], [("A", "A", SE2(1, 0, 0))])
    with pytest.raises(AssumptionError, match="inverse_edges.*has no inverse"):
        ctrl(0, half)


def test_state_is_hashable_and_names_the_documented_keys():
    c = ctrl(1)
    c.step(obs(0, [], [], rid=1))
    s = c.state()
    hash(s)
    assert [k for k, _ in s][:6] == ["role", "parent", "root", "authority", "unmatched_until", "edge"]
    assert "target" in dict(s)


def test_zero_speed_controller_is_built_and_disperses_forever():
    from swarmproof.reference_impl.song2014.algorithm import NEVER
    c = ctrl(3, params=Params(range=1.2, v=0.0))
    c.step(obs(0, [9], [[0.5, 0, 0]], {9: Song2014Message((9,), ((3, None),))}, rid=3))
    assert dict(c.state())["unmatched_until"] == NEVER
