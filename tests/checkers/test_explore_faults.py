"""Drawn robot additions and sensing noise (issue 6): named as broken assumptions, shrunk,
written to the counterexample file and replayed exactly."""

from __future__ import annotations

import json

import numpy as np
import pytest

from swarmproof.checkers.explore import FAULT_KINDS, explore, run_scenario
from swarmproof.checkers.replay import replay, replay_file
from swarmproof.models import library
from swarmproof.models.counterexample import Counterexample
from swarmproof.reference_impl.engine import FaultModel
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Params


def test_fault_kinds():
    assert FAULT_KINDS == ("schedule", "crashes", "drops", "additions", "noise", "delays", "latency")


@pytest.mark.slow   # 5.5 s CPU (issue 32's time trim); test_drawn_noise_and_additions_are_named keeps drawn additions covered
def test_drawn_additions_break_song2016_formation_named_and_replayed(tmp_path):
    r = explore("song2016", ["formation"], budget=None, max_examples=15, robots=(3, 5), lattices=["square"], seed=0,
                draw_faults=("additions",), out_dir=tmp_path)
    assert r.broken_assumptions == ["fixed_robot_set"] and "fixed_robot_set" not in r.kept_assumptions
    v = r.properties["formation"]
    assert v.status == "violated", v.message
    cx = Counterexample.load(v.counterexample_path)
    n = len(cx.robots)
    assert n == 3 and cx.broken_assumptions == ["fixed_robot_set"]
    joined = [rid for rows in cx.faults["additions"].values() for rid, _ in rows]
    assert joined == [3]  # the next unused ID
    [(step, [[_, (x, y, _th)]])] = cx.faults["additions"].items()
    assert f"(synchronous, faults: robot 3 joins at step {step} at ({x:.6g}, {y:.6g}) heading " \
        in cx.format_steps()[n + 2]
    rr = replay_file(v.counterexample_path)
    assert rr.reproduced and rr.verdict.message == cx.violation["message"]
    assert 3 in rr.result.final_ids.tolist()  # the newcomer is part of the final configuration


def test_drawn_noise_and_additions_are_named():
    r = explore("example-gather", ["connectivity"], budget=None, max_examples=5, robots=(3, 4), lattices=["square"],
                seed=0, draw_faults=("noise", "additions"))
    assert r.broken_assumptions == ["fixed_robot_set", "exact_sensing"]
    assert r.properties["connectivity"].status in ("held", "violated")


def _noisy_cx(noise_std):
    start = random_connected(6, 1, range=1.2)
    return Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.7853981633974483,
                                                        "dt": 1.0, "extra": {}},
                          lattice="square", robots=[(int(i), tuple(p)) for i, p in zip(start.ids, start.poses)],
                          seed=4, property="connectivity", violation={"step": None, "message": ""}, max_steps=300,
                          faults=FaultModel(noise_std=noise_std).describe(), broken_assumptions=["exact_sensing"])


def test_sensing_noise_replays_bit_exactly_from_the_file(tmp_path):
    path = _noisy_cx((0.02, 0.01)).save(tmp_path / "noisy.json")
    a, b = replay_file(path), replay_file(path)
    assert np.array_equal(a.result.trace.poses, b.result.trace.poses)
    assert a.result.trace.meta["faults"]["noise_std"] == [0.02, 0.01]
    quiet = replay(_noisy_cx((0.0, 0.0)))
    steps = min(quiet.result.steps, a.result.steps)
    assert not np.array_equal(quiet.result.trace.poses[:steps], a.result.trace.poses[:steps])  # the noise acts


def test_drawn_faults_replay_through_run_scenario():
    # the exact fault model the explorer draws is rebuilt from its description
    fm = FaultModel(additions={4: [(3, [0.5, 0.5, 0.1])]}, noise_std=(0.01, 0.0))
    again = FaultModel.from_dict(fm.describe())
    lat = library.load("square")
    runs = [run_scenario("song2016", lat, [0, 1, 2], [(0, 0, 0), (1, 0, 0), (0, 1, 0)], Params(range=1.2), seed=2,
                         max_steps=60, faults=f)[1] for f in (fm, again)]
    assert np.array_equal(runs[0].trace.poses, runs[1].trace.poses)
    assert runs[0].broken_assumptions == ("fixed_robot_set", "exact_sensing")


@pytest.mark.parametrize("kind", ["additions", "noise"])
def test_cli_accepts_the_new_fault_kinds(capsys, kind):
    from swarmproof.cli import main

    code = main(["explore", "example-gather", "--property", "connectivity", "--budget", "none", "--max-examples", "2",
                 "--robots", "3..3", "--fault", kind, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code in (0, 1)
    assert doc["broken_assumptions"] == [{"additions": "fixed_robot_set", "noise": "exact_sensing"}[kind]]
