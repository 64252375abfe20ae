"""A counterexample of a run with asynchronous clocks says so (issue 15: format_steps called every
run "synchronous"); the file keeps the run's recorded clocks (``trace.meta["clocks"]``)."""

from __future__ import annotations

import json

import pytest

from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError

CLOCKS = {"phase": [0.125, 0.75, 0.5], "rate": [0.5, 0.875, 1.0], "broadcast_every": 2.0}


def _cx(**kw):
    base = dict(algorithm="wang2020", params={"range": 0.6, "v": 0.05, "omega": 0.785, "dt": 0.5,
                                               "extra": {"clock_rate_min": 0.5, "clock_rate_max": 1.0}},
                lattice=None, target={"kind": "shape", "name": "letter-l-3", "cells": [[0, 0], [1, 0], [0, 1]],
                                      "spacing": 0.2},
                robots=[(0, (-0.2, -0.2, 0.0)), (1, (0.0, -0.2, 0.0))], seed=0, property="collision",
                violation={"step": 11, "message": "robots 0 and 1 overlap in step 11"}, max_steps=300,
                clocks=CLOCKS)
    base.update(kw)
    return Counterexample(**base)


def test_async_clocks_are_printed_per_robot_and_in_the_run_line():
    c = _cx(faults={"additions": {"4": [[5, [0.2, 0.0, 0.0]]]}})
    assert c.format_steps() == [
        "counterexample: wang2020 violates collision",
        "shape letter-l-3, range 0.6, v=0.05, omega=0.785, dt=0.5",
        "1. place robot 0 at (-0.2, -0.2) heading 0 deg, clock phase 0.125 rate 0.5",
        "2. place robot 1 at (0, -0.2) heading 0 deg, clock phase 0.75 rate 0.875",
        "3. run wang2020 with seed 0 for at most 300 steps with params clock_rate_max=1.0, clock_rate_min=0.5 "
        "(asynchronous clocks: robot clock = phase + rate * step, it decides when its clock passes an integer "
        "and broadcasts its last decision when it passes k * 2 + 1/2; phases drawn in [0, 1), rates drawn in "
        "[0.5, 1]; robots joining later, in order: phase and rate 0.5 and 1, "
        "faults: robot 5 joins at step 4 at (0.2, 0) heading 0 deg)",
        "4. at step 11: robots 0 and 1 overlap in step 11",
    ]


def test_synchronous_runs_read_as_before_and_a_schedule_is_named_beside_the_clocks():
    sync = _cx(clocks=None, params={"range": 0.6, "v": 0.05, "omega": 0.785, "dt": 0.5})
    assert sync.format_steps()[2] == "1. place robot 0 at (-0.2, -0.2) heading 0 deg"
    assert sync.format_steps()[4].endswith("(synchronous, no faults)")
    both = _cx(clocks={"phase": [0.0, 0.5], "rate": [1.0, 1.0], "broadcast_every": 1.0},
               params={"range": 0.6, "v": 0.05, "omega": 0.785, "dt": 0.5}, schedule={"kind": "table"})
    assert both.format_steps()[4].endswith("passes k * 1 + 1/2; phases drawn in [0, 1), rates drawn in [1, 1]; "
                                           "a schedule from the file, no faults)")


def test_clocks_round_trip_and_files_without_them_are_unchanged(tmp_path):
    c = _cx()
    path = c.save(tmp_path / "cx.json")
    doc = json.loads(open(path).read())
    assert doc["clocks"] == CLOCKS
    back = Counterexample.load(path)
    assert back == c and back.format_steps() == c.format_steps()
    plain = _cx(clocks=None)
    assert "clocks" not in plain.as_dict() and Counterexample.from_dict(plain.as_dict()).clocks is None


@pytest.mark.parametrize("clocks, field, match", [
    ([1, 2], "clocks", r"clocks=\[1, 2\] must be a JSON object or null"),
    ({"phase": [0.1], "rate": [0], "broadcast_every": 1}, "clocks.rate",
     r"clocks.rate=\[0\] must be a list of finite numbers > 0"),
    ({"phase": "x", "rate": [1], "broadcast_every": 1}, "clocks.phase", r"clocks.phase='x' must be a list"),
    ({"phase": [0.1, 0.2], "rate": [1], "broadcast_every": 1}, "clocks.rate", r"2 phases and 1 rates"),
    ({"phase": [0.1], "rate": [1], "broadcast_every": None}, "clocks.broadcast_every",
     r"clocks.broadcast_every=None must be a finite number > 0"),
], ids=["not-an-object", "zero-rate", "phase-not-a-list", "lengths-differ", "no-broadcast-every"])
def test_bad_clocks_in_a_file_are_named(clocks, field, match):
    doc = _cx().as_dict()
    doc["clocks"] = clocks
    with pytest.raises(InputFileError, match=match) as info:
        Counterexample.from_dict(doc, file="cx.json")
    assert field in str(info.value) and "drop the field" in str(info.value)


def test_the_explorer_records_the_runs_clocks(tmp_path):
    """An async algorithm's counterexample carries the clocks its trace recorded, and they are the
    ones the replay draws again from the seed."""
    from swarmproof.checkers.explore import explore
    from swarmproof.checkers.replay import replay_file

    rep = explore("example-grid-goals", ["formation"], budget=None, max_examples=20, robots=(3, 5), seed=0,
                  out_dir=tmp_path)
    v = rep.properties["formation"]
    assert v.status == "violated"
    cx = v.counterexample
    assert len(cx.clocks["phase"]) == len(cx.robots) and cx.clocks["broadcast_every"] == 1.0
    assert all(0.9 <= r <= 1.1 for r in cx.clocks["rate"])
    assert "(asynchronous clocks: " in cx.format_steps()[-2]
    rr = replay_file(v.counterexample_path)
    assert rr.reproduced and rr.result.trace.meta["clocks"] == cx.clocks
