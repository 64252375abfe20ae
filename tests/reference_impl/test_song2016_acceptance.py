"""song2016 acceptance (issue 3 "Must hold"; 001 Sec. VI).

From 20 connected random starts each for n = 10, 20, 30, 40 on square, hexagon and
octagon-square: the run terminates (the algorithm's own end: no unstable robot), the
final configuration satisfies the lattice graph (Def. 2), the communication graph is
connected at every step (Lemma 11), and Q is identical across starts ("the deviation of
the fulfillment ratio is always zero", Sec. VI).

The expected final formation is computed from the lattice graph alone
(:func:`~swarmproof.reference_impl.song2016.sequential_fill`: fill every vacancy of the
highest-ID stable robot in out-edge order, then the next), and each run is compared
robot by robot: the robot of ID rank k (0 = the highest) must stand at the k-th
predicted pose in the frame of the highest-ID robot (1e-6), with the predicted role.
Q is computed exactly (fractions of neighbor counts) and must equal the prediction.

The parent rule is the default ``"relocate_route"`` (docs/decisions.md, "Relocate robot's
parent": Sec. V-B for every robot, the relocate robot on its path to the root as Lemma 11,
Lemma 12 and Theorem 13 describe it); every start gets the full check.

Sec. V-B's stable-first rule applied to the relocate robot too (``parent_rule="stable_first"``)
deadlocks on some starts (docs/song2016.md, "What the implementation found": the relocate robot
sits on a stable parent that is no closer to the root).  Those starts are listed in
:data:`STABLE_FIRST_DEADLOCKS`, and a test checks that under that rule they deadlock exactly
that way and under the default rule they finish (so the list fails if either behaviour
changes).

The full matrix is slow (240 runs; docs/performance.md); one small case runs by default.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from swarmproof.invariants.connectivity import connected_throughout, tree_links_survive
from swarmproof.invariants.premises import params_of
from swarmproof.invariants.satisfaction import satisfies_lattice
from swarmproof.models.library import load
from swarmproof.models.se2 import relative_many
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Params
from swarmproof.reference_impl.song2016.algorithm import Song2016, sequential_fill
from swarmproof.reference_impl.song2016.monitors import tree_links_in_proved_cases

LATTICES = ("square", "hexagon", "octagon-square")
SIZES = (10, 20, 30, 40)
STARTS = 20

#: (lattice, n) -> seeds on which ``parent_rule="stable_first"`` deadlocks (found by this
#: matrix when that rule was the default, 2026-11-22).
STABLE_FIRST_DEADLOCKS: dict[tuple[str, int], frozenset[int]] = {
    ("square", 40): frozenset({15}),
    ("hexagon", 30): frozenset({0, 2, 8, 9, 11, 12, 15}),
    ("hexagon", 40): frozenset({2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 14, 16, 17, 18, 19}),
    ("octagon-square", 30): frozenset({14, 18}),
    ("octagon-square", 40): frozenset({11, 13}),
}


def exact_q(poses, roles, lattice, phi) -> Fraction:
    """Q of 001 Sec. III-C-2 as a fraction: N_i = robots strictly closer than phi."""
    xy = np.asarray(poses, dtype=float)[:, :2]
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    counts = (d < phi).sum(axis=1) - 1
    return sum(Fraction(int(c), len(lattice.out_edges(r))) for c, r in zip(counts, roles)) / len(roles)


def predicted(lattice, n):
    pred = sequential_fill(lattice, n)
    poses = np.array([p for p, _ in pred])
    roles = [r for _, r in pred]
    return poses, roles, exact_q(poses, roles, lattice, lattice.range)


def check_known_deadlock(r, lattice, where) -> None:
    """The deadlock of docs/song2016.md: static, unstable robots left, the one relocate
    robot on the position of its stable, non-root parent, the root out of range."""
    phi = lattice.range
    assert r.status == "static", f"{where}: expected the known deadlock, got {r.status}"
    states = [dict(s) for s in r.final_states]
    ids = r.final_ids.tolist()
    xy = r.final_poses[:, :2]
    assert not all(s["stable"] for s in states)
    movers = [k for k, s in enumerate(states) if s["relocate"]]
    assert len(movers) == 1, f"{where}: relocate robots {movers}"
    k = movers[0]
    parent, root = states[k]["parent"], states[k]["root_id"]
    assert parent is not None and parent != root
    p, q = ids.index(parent), ids.index(root)
    assert states[p]["stable"] and not states[p]["moving"]
    assert float(np.hypot(*(xy[k] - xy[p]))) < 1e-9, f"{where}: relocate robot not on its parent"
    assert float(np.hypot(*(xy[k] - xy[q]))) >= phi


def run(lattice, n, seed, **rule):
    phi = lattice.range
    init = random_connected(n, seed, range=phi, min_separation=0.3)
    return simulate(Song2016(n_robots=n, **rule), lattice, init, Params(range=phi, v=0.05),
                    seed=seed)


def run_and_check(lattice, n, seed, pred_poses, pred_roles) -> Fraction:
    """Full check of one start under the default parent rule; returns its exact Q."""
    phi = lattice.range
    r = run(lattice, n, seed)
    where = f"{lattice.name} n={n} seed={seed}"
    assert r.status == "finished", f"{where}: {r.status} after {r.steps} steps"
    ids, poses = r.final_ids, r.final_poses
    sat = satisfies_lattice(ids, poses, lattice, phi)
    assert sat.held, f"{where}: {sat}"
    conn = connected_throughout(r.trace, phi)
    assert conn.held, f"{where}: {conn}"
    check_tree_link_breaks_are_flagged(r.trace, where)
    order = np.argsort(-ids)
    rel = relative_many(poses[order[0]], poses[order])
    err = float(np.abs(rel[:, :2] - pred_poses[:, :2]).max())
    assert err < 1e-6, f"{where}: final formation is {err:.3g} away from the sequential fill"
    roles = [dict(r.final_states[k])["role"] for k in order]
    assert roles == pred_roles, f"{where}: roles {roles} != predicted {pred_roles}"
    return exact_q(poses[order], roles, lattice, phi)


#: (where, step, child, parent) of every tree-link break the default runs showed, filled by
#: :func:`check_tree_link_breaks_are_flagged` (issue 19: reported, not asserted in number).
TREE_LINK_BREAKS: list = []


def check_tree_link_breaks_are_flagged(trace, where) -> None:
    """Issue 19: a tree link that breaks (every link of the decided tree, newly chosen ones
    included) is always flagged by song2016's property ``tree_link_cases`` (a premise monitor
    until issue 32): it names that very link as in no proved case."""
    links = tree_links_survive(trace, trace.meta["params"]["range"])
    if not links.violated:
        return
    w = links.witness
    TREE_LINK_BREAKS.append((where, w["step"], w["child"], w["parent"]))
    phi, v, dt = params_of(trace)
    cases = tree_links_in_proved_cases(trace, phi, v, dt)     # song2016's property (issue 32)
    assert cases.violated, f"{where}: {links.message}, but tree_link_cases held"
    cw = cases.witness
    assert (cw["step"], cw["child"], cw["parent"], cw["broke"]) == (w["step"], w["child"], w["parent"], True), \
        f"{where}: the break {links.message} is not the uncovered link flagged: {cases.message}"


def check_stable_first_deadlock(lattice, n, seed) -> None:
    """Under Sec. V-B's rule for the relocate robot too, the start deadlocks as documented
    (and stays connected); under the default rule it finishes."""
    r = run(lattice, n, seed, parent_rule="stable_first")
    where = f"{lattice.name} n={n} seed={seed} parent_rule=stable_first"
    check_known_deadlock(r, lattice, where)
    conn = connected_throughout(r.trace, lattice.range)
    assert conn.held, f"{where}: {conn}"


def test_small_representative_case_hexagon_n10():
    """Default suite: three starts of the matrix's smallest hexagon case."""
    lat = load("hexagon")
    poses, roles, q = predicted(lat, 10)
    qs = {run_and_check(lat, 10, seed, poses, roles) for seed in range(3)}
    assert qs == {q}
    assert q == Fraction(3, 5)


def test_stable_first_deadlock_and_the_default_rule_on_one_start():
    """Default suite: hexagon n = 30 seed 0 deadlocks under the stable-first rule for the
    relocate robot and forms the predicted lattice under the default rule."""
    lat = load("hexagon")
    check_stable_first_deadlock(lat, 30, 0)
    poses, roles, q = predicted(lat, 30)
    assert run_and_check(lat, 30, 0, poses, roles) == q


@pytest.mark.slow
@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("name", LATTICES)
def test_acceptance_twenty_starts(name, n):
    lat = load(name)
    poses, roles, q = predicted(lat, n)
    qs = [run_and_check(lat, n, seed, poses, roles) for seed in range(STARTS)]
    assert set(qs) == {q}, f"{name} n={n}: Q differs across starts: {sorted(set(qs))}"


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(STABLE_FIRST_DEADLOCKS), ids=lambda c: f"{c[0]}-{c[1]}")
def test_stable_first_rule_deadlocks_on_the_listed_starts(case):
    name, n = case
    lat = load(name)
    for seed in sorted(STABLE_FIRST_DEADLOCKS[case]):
        check_stable_first_deadlock(lat, n, seed)
