"""Jiang et al. (002) reference implementation (reference_impl/jiang/algorithm.py): each step of
Algorithms 1 and 2 on hand-made states, the two readings of Algorithm 2, runs on every bundled
pattern, determinism (also under delays), the runtime invariants, and the engine's knows_start."""

from __future__ import annotations

import math

import numpy as np
import pytest

from swarmproof.invariants.algorithm_invariants import check_invariants
from swarmproof.models.errors import UsageError
from swarmproof.models.repeating_pattern import load_pattern, pattern_names
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl import initial as im
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.engine.faults import FaultModel
from swarmproof.reference_impl.jiang.algorithm import Group, Jiang, JiangController, JiangLiteral, Layer, assign, nearest
from swarmproof.reference_impl.protocol import Observation, Params

P = Params(range=1.5, v=0.1, omega=math.pi / 2, dt=1.0)
TRI = load_pattern("rhombus-triangles")


def obs(robot_id, pos, inbox=(), step=0):
    return Observation(step, robot_id, (), np.zeros((0, 3)), {}, own_pose=np.array([pos[0], pos[1], 0.0]),
                       delivered=tuple(inbox))


def ctl(robot_id, reading="queue", pattern=TRI):
    return JiangController(robot_id, P, pattern.basic, pattern.assembling, reading, pattern.tol)


POS = {1: (0.0, 0.0), 2: (3.0, 0.0), 3: (0.2, 0.1), 4: (5.0, 5.0), 5: (0.1, 0.4), 6: (3.1, 0.2)}


def test_alg1_the_largest_id_becomes_head_picks_nearest_and_assigns_optimally():
    c = ctl(6)
    c.know_start(tuple(POS), np.array(list(POS.values())))
    cmd = c.step(obs(6, POS[6]))
    g = cmd.message
    assert isinstance(g, Group) and g.head == 6 and g.head_pos == (3.1, 0.2)
    # |B| - 1 = 2 nearest of R \ {6}: robot 2 (0.22 away) and robot 4 (4.9), not 3 (2.9)? -> 2 and 3
    chosen = nearest((3.1, 0.2), [1, 2, 3, 4, 5], POS, 2)
    assert chosen == [2, 3] and [r for r, _ in g.members] == [2, 3]
    targets = [(3.1 + x, 0.2 + y) for x, y in TRI.basic[1:]]
    assert g.members == tuple(assign([2, 3], POS, targets))
    assert g.available == (1, 4, 5)            # R \ N \ {r_i}, sent in the message
    assert dict(c.state())["is_head"] and dict(c.state())["members"] == (2, 3)
    # a robot that is not the largest stays put and silent
    other = ctl(5)
    other.know_start(tuple(POS), np.array(list(POS.values())))
    assert other.step(obs(5, POS[5])).message is None


def test_alg1_a_member_moves_to_its_slot_and_every_receiver_takes_R_from_the_message():
    g = Group((1, 4, 5), 6, (3.1, 0.2), ((2, (3.6, 0.2)), (3, (3.35, 0.633))))
    m = ctl(2)
    m.know_start(tuple(POS), np.array(list(POS.values())))
    cmd = m.step(obs(2, POS[2], [(6, g)]))
    st = dict(m.state())
    assert st["target"] == (3.6, 0.2) and st["head"] == 6 and cmd.forward > 0
    bystander = ctl(5)
    bystander.know_start(tuple(POS), np.array(list(POS.values())))
    sent = bystander.step(obs(5, POS[5], [(6, g)])).message
    # R <- R' = {1, 4, 5} (as printed): 5 is now the largest, becomes the next head in the same
    # step, takes its two nearest (1 and 4) and leaves R empty
    assert dict(bystander.state())["is_head"] and dict(bystander.state())["members"] == (1, 4)
    assert bystander.R == set() and isinstance(sent, Group) and sent.available == () and sent.head == 5


def test_R_is_assigned_not_intersected_so_a_stale_group_message_grows_it_back():
    c = ctl(1)
    c.know_start(tuple(POS), np.array(list(POS.values())))
    new = Group((1, 4), 5, POS[5], ((3, (0.6, 0.4)),))
    old = Group((1, 3, 4, 5), 6, POS[6], ((2, (3.6, 0.2)),))
    c.step(obs(1, POS[1], [(5, new), (6, old)]))       # delivered out of order
    assert c.R == {1, 3, 4, 5}


def _phase2(reading):
    """Head 9 is the root (largest head), heads 7 and 8 wait at known positions, R is empty."""
    c = ctl(9, reading, load_pattern("square-dots"))
    c.know_start((7, 8, 9), np.array([[5.0, 0.0], [0.0, 5.0], [0.0, 0.0]]))
    c._set_R(set())
    c.is_head, c.head_of, c.target, c.heads = True, 9, (0.0, 0.0), {7, 8, 9}
    return c


def test_alg2_queue_reading_assigns_free_slots_and_leaves_the_queue():
    c = _phase2("queue")
    lay = c.step(obs(9, (0.0, 0.0))).message
    assert isinstance(lay, Layer) and lay.sender == 9 and lay.queue == (7, 8)
    # A \ {0} = (1,0), (0,1), (1,1) around the root; 7 at (5,0) and 8 at (0,5) nearest to it
    assert dict(lay.assigned) == {7: (1.0, 0.0), 8: (0.0, 1.0)}
    assert lay.heads == ()
    # head 7 is next: (1,0)+(0,1) = (1,1) is free, (1,0)+(1,0) = (2,0) too, but (1,0) itself is taken
    h7 = _phase2("queue")
    h7.id, h7.target, h7.is_head, h7.head_of = 7, (1.0, 0.0), True, 7
    h7._on_layer(lay)
    assert h7._occupied((0.0, 1.0)) and h7._occupied((0.0, 0.0)) and not h7._occupied((2.0, 0.0))


def test_alg2_literal_reading_keeps_the_acting_head_first_and_collects_robots_in_O():
    c = _phase2("literal")
    lay = c.step(obs(9, (0.0, 0.0))).message
    assert lay.queue == (9, 7, 8)             # Q = Q u E u {r_i}: 9 stays first
    assert c.O == (7, 8)                      # O <- O u N: robots, never a vector
    # it acts once ("Upon ... finds"): the next step sends nothing, and nobody else is first
    assert c.step(obs(9, (0.0, 0.0), step=1)).message is None


@pytest.mark.parametrize("name", pattern_names())
def test_every_bundled_pattern_forms_with_quality_one_and_the_invariants_hold(name):
    pat = load_pattern(name)
    alg = Jiang()
    n = 6 * len(pat.basic) if len(pat.basic) > 1 else 8
    init = im.random_connected(n, 3, range=1.5)
    r = simulate(alg, pat, init, alg.default_params(range=1.5, n=n), seed=3)
    assert r.status == "finished"
    assert pat.satisfied(r.final_ids, r.final_poses).status == "held"
    m = pat.metrics(r.final_ids, r.final_poses)
    assert m["epsilon_exact"] == "1" and m["method"] == "perfect-cover"
    assert check_invariants(r.trace, alg).status == "held"


def test_the_literal_reading_stops_after_the_root_layer():
    """10 heads, |A \\ {0}| = 3 slots around the root: 6 heads are never placed."""
    pat, alg = TRI, JiangLiteral()
    init = im.random_connected(30, 0, range=1.5)
    r = simulate(alg, pat, init, alg.default_params(range=1.5, n=30), seed=0)
    assert r.status == "static"              # nobody else is ever first in Q: the own end never comes
    assert pat.satisfied(r.final_ids, r.final_poses).status == "violated"


def test_runs_are_deterministic_also_under_delay_and_reordering():
    def trace_digest(tr):
        return (tr.poses.tobytes(), repr(tr.states), repr([e.as_dict() for e in tr.events]))

    alg = Jiang()
    init = im.random_connected(12, 1, range=1.5)
    faults = FaultModel(message_delay=3, message_reorder=True)
    a = [simulate(alg, TRI, init, alg.default_params(range=1.5, n=12), seed=1, faults=f) for f in (None, faults)]
    b = [simulate(alg, TRI, init, alg.default_params(range=1.5, n=12), seed=1, faults=f) for f in (None, faults)]
    for x, y in zip(a, b):
        assert trace_digest(x.trace) == trace_digest(y.trace)


def test_delays_break_the_phases_and_the_invariants_see_it():
    """Without a barrier between the phases (002 Sec. IV) a member that hears of its head's
    layer before its group follows nobody: seed 0 with delays up to 3 steps ends with a group
    that is not a copy of B."""
    alg = Jiang()
    init = im.random_connected(12, 0, range=1.5)
    r = simulate(alg, TRI, init, alg.default_params(range=1.5, n=12), seed=0,
                 faults=FaultModel(message_delay=3, message_reorder=True))
    res = check_invariants(r.trace, alg)
    assert res.status == "violated" and res.witness["invariant"] == "group_is_copy"
    assert TRI.satisfied(r.final_ids, r.final_poses).status == "violated"


def test_knows_start_needs_global_sensing_and_hands_over_a_read_only_copy():
    seen = {}

    class Spy(JiangController):
        def know_start(self, ids, positions):
            seen[self.id] = (ids, positions)
            super().know_start(ids, positions)

    class SpyAlg(Jiang):
        def controller(self, robot_id, params, target, rng):
            return Spy(robot_id, params, target.basic, target.assembling, "queue", target.tol)

    init = InitialConfiguration([4, 7], [[0, 0, 0], [0.4, 0, 0]])
    simulate(SpyAlg(), load_pattern("square-segments"), init, P, seed=0, max_steps=3)
    ids, pos = seen[4]
    assert ids == (4, 7) and pos.tolist() == [[0.0, 0.0], [0.4, 0.0]]
    with pytest.raises(ValueError):
        pos[0, 0] = 1.0
    from swarmproof.reference_impl.protocol import RobotModel

    class Local(Jiang):
        model = RobotModel(sensing="local", communication="all")

    with pytest.raises(UsageError, match="knows_start needs sensing='global'"):
        simulate(Local(), load_pattern("square-segments"), init, P, seed=0, max_steps=3)


def test_a_target_that_is_not_a_pattern_is_refused():
    from swarmproof.models import library

    with pytest.raises(UsageError, match="needs a repeating pattern target"):
        Jiang().controller(1, P, library.load("square"), None)


def test_a_stale_R_that_names_a_head_again_makes_it_act_again_as_printed():
    """Alg. 1's "Upon r_i finds that it has the largest ID in R" has no other condition: a head
    whose R grows back (a late Group message, R <- R') and names it the largest forms a second
    group -- of robots already grouped -- and one_group sees it."""
    c = ctl(6)
    c.know_start(tuple(POS), np.array(list(POS.values())))
    first = c.step(obs(6, POS[6])).message                 # head 6 takes 2 and 3
    stale = Group((1, 2, 3, 4, 5, 6), 9, (9.0, 9.0), ())   # an old message from a head 9
    second = c.step(obs(6, POS[6], [(9, stale)], step=1)).message
    assert isinstance(second, Group) and second.head == 6 and second is not first
    assert {r for r, _ in second.members} <= {1, 2, 3, 4, 5}


def test_the_explorer_finds_the_delay_deadlock_and_its_file_replays(tmp_path):
    """Delays within 002's model (no assumption broken) end a run short of its own end; the
    shrunk counterexample file replays exactly."""
    from swarmproof.checkers.explore import explore
    from swarmproof.checkers.replay import replay_file

    rep = explore("jiang", ["termination"], budget=None, max_examples=120, robots=(3, 9), seed=0,
                  lattices=["pattern:rhombus-triangles"], draw_faults=("delays",), out_dir=tmp_path)
    v = rep.properties["termination"]
    assert v.status == "violated" and rep.broken_assumptions == []
    assert "deadlock" in v.message
    rr = replay_file(v.counterexample_path)
    assert rr.reproduced


# -- Fig. 7a's quality: Sec. V-A's alignment measure (docs/jiang.md, "Fig. 7a's quality") -------------

def _shape(pattern, xy):
    """The formation up to translation (Sec. V-A's origin subtracted), as a set of grid points."""
    xy = np.asarray(xy, dtype=float)[:, :2]
    low = xy[xy[:, 1] <= xy[:, 1].min() + pattern.tol]
    rel = xy - low[np.argmin(low[:, 0])]
    return frozenset(map(tuple, np.rint(rel / (10 * pattern.tol)).astype(int).tolist()))


def test_the_desired_formation_comes_from_B_A_n_and_a_planted_misplaced_copy_aligns_below_one():
    p = load_pattern("square-segments")
    fd = p.formation(50)                           # 25 copies: the 5 x 5 square, whole layers
    assert p.fills_whole_layers(50) and np.array_equal(fd, load_pattern("square-segments").formation(50))
    assert p.alignment(fd + (4.0, 7.0)) == 1.0 and p.alignment(fd[::-1]) == 1.0    # translation, order
    # plant one copy misplaced: the copy at the square's top-right corner (4, 4) moved to (5, 0), a
    # free slot one vector of A from the copy at (4, 0): still a perfect pattern (epsilon = 1) ...
    corner = [k for k in range(0, 50, 2) if np.allclose(fd[k], (4.0, 4.0))][0]
    moved = fd.copy()
    moved[corner:corner + 2] += (1.0, -4.0)
    assert p.satisfied(None, moved).status == "held"
    # ... but not the desired formation: 48 of its 50 points align
    assert p.alignment(moved) == pytest.approx(48 / 50)


def test_layer_sizes_are_the_breadth_first_layers_of_A():
    assert load_pattern("square-dots").layer_sizes(10) == (1, 4, 9, 16)
    assert load_pattern("triangle-segments").layer_sizes(6) == (1, 3, 6)
    assert load_pattern("trapezoid-hexagons").layer_sizes(13) == (1, 5, 12, 22)
    p = load_pattern("rhombus-triangles")
    assert [n for n in range(50, 301, 50) if p.fills_whole_layers(n)] == [300]
    # the desired formation of whole layers is the union of those layers, in any growth order
    fd = p.formation(3 * 9)
    assert _shape(p, fd) == _shape(p, np.concatenate([fd[3 * k:3 * k + 3] for k in (0, 3, 2, 1, 8, 4, 6, 7, 5)]))


def test_whole_layers_align_at_one_and_a_partial_layer_depends_on_the_start():
    """002's growth fills a layer's slots in the order of the heads' IDs, and the last heads go to
    the free slots nearest them: with 9 dots (3 x 3, whole layers) every start ends in the desired
    formation, with 6 dots the starts end in different formations, so no desired formation fixed
    before the runs aligns at 1 with all of them."""
    p, alg = load_pattern("square-dots"), Jiang()
    whole, partial = set(), set()
    for seed in range(3):
        r = simulate(alg, p, im.random_uniform(9, seed, side=4.0), alg.default_params(range=1.5, n=9), seed=seed)
        assert r.status == "finished" and p.alignment(r.final_poses) == 1.0
        whole.add(_shape(p, r.final_poses))
    for seed in range(4):
        r = simulate(alg, p, im.random_uniform(6, seed, side=4.0), alg.default_params(range=1.5, n=6), seed=seed)
        assert r.status == "finished" and p.satisfied(None, r.final_poses).status == "held"
        partial.add(_shape(p, r.final_poses))
    assert whole == {_shape(p, p.formation(9))}
    assert len(partial) >= 2
