"""Lee & Chong (003) runs through the engine: patterns, the formula's finding, switching, failures,
flocking, the F-team, anonymity and determinism."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from swarmproof.checkers.runs import run_and_check
from swarmproof.models.errors import UsageError
from swarmproof.models.targets import resolve_target
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.leechong.algorithm import LeeChongLeader
from swarmproof.reference_impl.registry import get_algorithm


def run(alg, pattern, seed=0, robots=12, **extra):
    return run_and_check(alg, resolve_target("lines:" + pattern), seed=seed, robots=robots,
                         extra={k: v for k, v in extra.items()})


@pytest.mark.parametrize("pattern", ["circle", "triangle", "diamond", "hexagon", "arc"])
def test_leader_referenced_forms_the_uni_line_patterns(pattern):
    c = run("leechong-leader", pattern)
    assert c.doc["status"] == "finished" and c.doc["satisfied"] is True
    assert c.doc["metrics"]["agreement"] is True and c.doc["termination"]["status"] == "held"


def test_printed_id_formula_breaks_the_wedge_where_the_prose_forms_it():
    """Seed 0 puts 3 followers above u and 8 below: Alg. 1's 2 x rank - 1 hands out IDs 13 and 15
    (``leechong-leader-printed``); the default, Sec. 2.1's prose, forms it."""
    lit = run("leechong-leader-printed", "wedge")
    assert lit.doc["metrics"]["ids_unique"] is False
    assert "outside 0..11" in lit.doc["metrics"]["ids_unique_violation"]
    assert lit.doc["satisfied"] is False
    prose = run("leechong-leader", "wedge")
    assert prose.doc["metrics"]["ids_unique"] is True and prose.doc["satisfied"] is True


def test_neighbor_referenced_deadlocks_when_its_neighbor_id_is_not_allocated():
    """The printed formula's finding for Alg. 4 (``leechong-neighbor-printed``): an N_id nobody holds."""
    c = run("leechong-neighbor-printed", "two-row")
    assert c.doc["termination"]["status"] == "violated"          # a robot waits for a neighbor that is not there
    assert run("leechong-neighbor-printed", "circle").doc["satisfied"] is True
    assert run("leechong-neighbor", "two-row").doc["satisfied"] is True     # the default (prose IDs) forms it


def test_switching_keeps_the_leader_and_the_ids_and_ends_in_the_last_pattern():
    c = run("leechong-leader", "circle", then="two-column,triangle")
    assert c.doc["satisfied"] is True and c.doc["satisfaction"]["message"].find("triangle") >= 0
    first = run("leechong-leader", "circle")
    assert first.doc["metrics"]["ids"] == c.doc["metrics"]["ids"]   # Sec. 3.4: the IDs stay
    assert c.doc["metrics"]["agreements_redone"] == 0


@pytest.mark.parametrize("who", ["leader", "3"])
def test_failure_recovery_reforms_the_pattern_with_the_same_span(who):
    # fail mid-way through a switch, so the team is moving when it happens
    c = run("leechong-leader", "wedge", then="circle", fail=f"{who}@60")
    assert c.doc["metrics"]["failed"] and c.doc["metrics"]["agreements_redone"] == 1
    assert c.doc["satisfied"] is True                              # 11 survivors, the start's span
    assert "interval 1.1" in c.doc["satisfaction"]["message"]       # span 11 over 10 intervals
    assert c.doc["metrics"]["ids_unique"] is True and c.doc["metrics"]["agreement"] is True


def test_flocking_keeps_the_formation_rigid_and_reaches_the_goal():
    c = run("leechong-leader", "arc", flock_to="5,30")
    assert c.doc["satisfied"] is True
    tr = c.result.trace
    # the leader ends 5 intervals from where the pattern first stood, at 30 degrees to u
    lead = [k for k, s in enumerate(tr.states[-1]) if dict(s)["id"] == 0][0]
    moved = tr.poses[-1][lead, :2] - tr.poses[0][lead, :2]
    assert math.hypot(*moved) == pytest.approx(5.0, abs=1e-6)


def test_f_team_uses_fixed_labels_and_forms_the_pattern():
    c = run("leechong-leader-fteam", "diamond")
    assert c.doc["satisfied"] is True
    ids = c.doc["metrics"]["ids"]
    assert ids == {str(k): k for k in range(12)}                   # label k -> ID k


def test_controllers_get_no_identity_and_runs_do_not_depend_on_engine_ids():
    """The engine hands anonymous controllers no ID; relabelling the robots changes nothing."""
    alg = LeeChongLeader()
    seen = []

    class Spy(LeeChongLeader):
        def controller(self, robot_id, params, target, rng):
            seen.append(robot_id)
            return super().controller(robot_id, params, target, rng)

    rng = np.random.default_rng(5)
    xy = rng.uniform(0, 4, (8, 2))
    poses = np.column_stack((xy, rng.uniform(-3, 3, 8)))
    target = resolve_target("lines:circle")
    params = alg.default_params(range=2.0, n=8)
    a = simulate(Spy(), target, InitialConfiguration(list(range(8)), poses), params, seed=3)
    b = simulate(Spy(), target, InitialConfiguration([70, 11, 5, 3, 99, 42, 8, 1], poses), params, seed=3)
    assert set(seen) == {None}
    assert np.array_equal(a.trace.poses, b.trace.poses)
    assert [tuple(x) for x in a.trace.states[-1]] == [tuple(x) for x in b.trace.states[-1]]


def test_symmetric_start_ties_are_broken_by_perturbation_and_deterministic():
    """A regular hexagon around a centre robot: six leader candidates (Sec. 2.1, Fig. 3)."""
    ang = np.arange(6) * math.pi / 3
    xy = np.vstack(([[0.0, 0.0]], np.column_stack((np.cos(ang), np.sin(ang)))))
    init = InitialConfiguration(list(range(7)), np.column_stack((xy, np.zeros(7))))
    alg = get_algorithm("leechong-leader")
    params = alg.default_params(range=2.0, n=7)
    r1 = simulate(alg, resolve_target("lines:wedge"), init, params, seed=1)
    r2 = simulate(alg, resolve_target("lines:wedge"), init, params, seed=1)
    assert np.array_equal(r1.trace.poses, r2.trace.poses)
    assert dict(r1.trace.states[1][1])["phase"] == "agree"          # a tie at step 0
    assert r1.status == "finished"
    assert resolve_target("lines:wedge").satisfied(r1.final_ids, r1.final_poses).held


def test_positioning_errors_distort_the_leader_referenced_pattern():
    c = run("leechong-leader", "wedge", position_errors="3,6,9", error_size=0.3)
    assert c.doc["satisfied"] is False


def test_bad_options_are_usage_errors():
    with pytest.raises(UsageError, match="fail='3'"):
        run("leechong-leader", "wedge", fail="3")
    with pytest.raises(UsageError, match="pattern='blob'"):
        run("leechong-leader", "wedge", then="blob")
    with pytest.raises(UsageError, match="flock_to"):
        run("leechong-leader", "wedge", flock_to="far")
    with pytest.raises(UsageError, match="pattern='line' is not a pattern of 003"):
        run_and_check("leechong-leader", resolve_target("lines:line"), seed=0, robots=4)


def _cli(capsys, *argv):
    from swarmproof.cli import main

    code = main(["simulate", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_simulate_wedge_with_plot_gif_then_and_fail(capsys, tmp_path):
    png, gif = tmp_path / "out.png", tmp_path / "out.gif"
    base = ["leechong-leader", "--pattern", "wedge", "--robots", "12", "--seed", "0"]
    code, out, _ = _cli(capsys, *base, "--plot", str(png), "--gif", str(gif), "--json")
    doc = json.loads(out)
    assert code == 0 and doc["satisfied"] is True                 # the default's prose IDs (issue 31)
    for key in ("satisfied", "total_distance", "min_separation"):
        assert key in doc
    assert {"agreement", "ids_unique"} <= set(doc["metrics"])
    assert png.read_bytes()[:4] == b"\x89PNG" and gif.read_bytes()[:3] == b"GIF"
    code, out, _ = _cli(capsys, *base, "--then", "circle", "--fail", "leader@30", "--json")
    assert json.loads(out)["metrics"]["failed"]
    code, out, err = _cli(capsys, "leechong-leader", "--pattern", "wedgie", "--robots", "12", "--seed", "0")
    assert code == 2 and "wedgie" in err and "Traceback" not in err
    code, out, err = _cli(capsys, "song2016", "--lattice", "square", "--robots", "4", "--seed", "0", "--then", "circle")
    assert code == 2 and "does not take --then" in err
    code, out, err = _cli(capsys, *base, "--fail", "3@soon")
    assert code == 2 and "STEP='soon'" in err


def test_explorer_draws_symmetric_starts_and_failures(tmp_path):
    """003's own scenarios: symmetric starts make ties happen, and failures are drawn."""
    from hypothesis import given, settings, strategies as st

    from swarmproof.reference_impl.leechong.algorithm import LeeChongLeader

    kinds, fails = set(), set()

    @settings(max_examples=60, derandomize=True, database=None)
    @given(st.data())
    def draws(data):
        start = LeeChongLeader.explore_start(data.draw, 3, 8, 2.0)
        extra = LeeChongLeader.explore_extra(data.draw, 6)
        if start is not None:
            xy = np.array([p[:2] for p in start])
            d = np.hypot(*(xy - xy.mean(axis=0)).T)
            kinds.add("tie" if np.sum(np.isclose(d, d.max(), rtol=1e-9)) > 1 else "no tie")
        fails.add(extra.get("fail", "none").split("@")[0] if extra else "none")

    draws()
    assert kinds == {"tie", "no tie"} and {"leader", "none"} <= fails


# slow by nature (issue 29): 25 explored scenarios of leechong-leader (prose IDs; was leechong-leader-prose) and the shrink of the one that
# breaks its invariants (51 s CPU measured); its scenario hooks stay in the default suite (the test above),
# and make verify runs leechong's exploration rows on every landing.
@pytest.mark.slow
def test_explorer_finds_the_axis_robot_tie_and_the_file_replays(tmp_path):
    """A counterexample of 003's drawn scenarios keeps the drawn failure in its params and replays."""
    from swarmproof.checkers.explore import explore
    from swarmproof.checkers.replay import replay_file

    rep = explore("leechong-leader", ["invariants"], max_examples=25, robots=(3, 6), seed=0,
                  budget=None, out_dir=str(tmp_path))
    v = rep.properties["invariants"]
    # a robot on the axis: two robots put it in different half planes, so two hold ID 1 (and its target)
    assert v.status == "violated" and ("both hold ID 1" in v.message or "(ID 1) and 3 (ID 1)" in v.message)
    assert replay_file(v.counterexample_path).reproduced


def test_flock_rigid_fires_when_followers_do_not_keep_pace():
    """The rigid-formation invariant is not vacuous: followers that ignore the leader's motion break it."""
    from swarmproof.reference_impl.leechong import algorithm as lc

    class Lazy(lc.LeeChongController):
        def _shift(self):
            return np.zeros(2) if self.id != 0 else super()._shift()

    class LazyLeader(lc.LeeChongLeader):
        def controller(self, robot_id, params, target, rng):
            return Lazy(self, params, lc._Patterns(target, params), rng, robot_id)

    rng = np.random.default_rng(2)
    xy = rng.uniform(0, 3, (6, 2))
    init = InitialConfiguration(list(range(6)), np.column_stack((xy, np.zeros(6))))
    alg = LazyLeader()
    params = alg.default_params(range=2.0, n=6)
    params = type(params)(range=params.range, v=params.v, omega=params.omega, dt=params.dt, extra={"flock_to": "3,0"})
    r = simulate(alg, resolve_target("lines:circle"), init, params, seed=0)
    assert LazyLeader.metrics(r)["flock_rigid"] is False
    good = simulate(lc.LeeChongLeader(), resolve_target("lines:circle"), init, params, seed=0)
    assert lc.LeeChongLeader.metrics(good)["flock_rigid"] is True
    assert lc.LeeChongLeader.metrics(good)["same_span"] is True


def test_teams_larger_than_the_algorithm_runs_are_refused_before_any_work():
    with pytest.raises(UsageError, match=r"robots=1000 is more than algorithm 'leechong-leader' runs \(at most 128"):
        run("leechong-leader", "wedge", robots=1000)


@pytest.mark.parametrize("param, message", [
    ("position_errors=x", "position_errors='x'"), ("fail=3", "fail=3 must be ROBOT@STEP"),
    ("flock_to=10", "flock_to=10 must be DISTANCE"), ("error_size=abc", "error_size='abc' must be a number"),
    ("arrive_tol=-1", "arrive_tol=-1 is outside its range (0, inf)"), ("alpha_star=95", "alpha_star=95"),
    ("nosuch=1", "parameter nosuch=1 is not known to algorithm 'leechong-leader'"),
    ("perturbation=-1", "perturbation=-1 is outside its range (0, inf)"),
    ("fail=99@5", "no robot of 12 can hold ID 99"), ("fail=-1@5", "ROBOT=-1 is not an ID"),
])
def test_bad_params_exit_2_naming_the_value(capsys, param, message):
    code, _, err = _cli(capsys, "leechong-leader", "--pattern", "wedge", "--robots", "12", "--seed", "0",
                        "--param", param)
    assert code == 2 and message in err and "Traceback" not in err and "internal" not in err


def test_pattern_params_reach_the_robots_and_the_judge():
    a = run("leechong-leader", "wedge", alpha_star=30)
    b = run("leechong-leader", "wedge", alpha_star=60)
    assert a.doc["satisfied"] and b.doc["satisfied"] and a.doc["total_distance"] != b.doc["total_distance"]
    c = run("leechong-leader", "circle", radius="printed")
    assert c.doc["satisfied"] and c.doc["total_distance"] != run("leechong-leader", "circle").doc["total_distance"]


def test_a_failure_fires_once_at_the_first_step_the_id_is_held():
    c = run("leechong-leader", "wedge", then="circle", fail="3@0")     # IDs exist after step 0
    assert len(c.doc["metrics"]["failed"]) == 1 and c.doc["satisfied"] is True


@pytest.mark.parametrize("alg", ["leechong-leader-fteam", "leechong-neighbor-fteam"])
@pytest.mark.parametrize("who", ["leader@30", "3@40"])
def test_f_team_keeps_its_labels_through_failures(alg, who):
    c = run(alg, "wedge", fail=who)
    m = c.doc["metrics"]
    assert c.doc["status"] == "finished" and c.doc["satisfied"] is True
    assert m["agreement"] is True and m["ids_unique"] is True and len(m["failed"]) == 1


def test_huge_teams_exit_2(capsys):
    code, _, err = _cli(capsys, "song2016", "--lattice", "square", "--robots", "99999999999999999999", "--seed", "0")
    assert code == 2 and "at most 20000" in err


def test_distinct_targets_invariant_on_hand_made_states():
    from swarmproof.reference_impl.leechong.algorithm import _distinct_targets

    def st(i, target, failed=False):
        return (("failed", failed), ("phase", "form"), ("id", i), ("target", target), ("epoch", (0, 0)),
                ("d_u", 1.0))

    ids = np.array([1, 2, 3])
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, math.pi / 2], [5.0, 5.0, 0.0]])
    # robot 1 heads for (2, 1); robot 2 (turned 90 deg) for its body (1, -1) = world (2, 1)
    clash = (st(1, (2.0, 1.0)), st(2, (1.0, -1.0)), st(0, None))
    assert "head for one target" in _distinct_targets(0, ids, poses, clash)
    fine = (st(1, (2.0, 1.0)), st(2, (1.0, -2.0)), st(0, None))
    assert _distinct_targets(0, ids, poses, fine) is None
    to_leader = (st(1, (5.0, 5.0)), st(2, (1.0, -2.0)), st(0, None))
    assert "leader's place" in _distinct_targets(0, ids, poses, to_leader)
