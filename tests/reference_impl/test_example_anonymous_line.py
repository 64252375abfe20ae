"""A new algorithm of another kind is one module (issue 12): the anonymous line example
(positions only, no IDs, no messages, holonomic, a ``lines`` target) through simulate,
explore, replay and verify, with no change to the shared packages."""

from __future__ import annotations

import json

import numpy as np

from swarmproof.checkers.explore import explore
from swarmproof.models.targets import resolve_target
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.examples.algorithms import AnonymousLine
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.protocol import Params


def test_simulate_forms_the_line_and_reports_the_lines_target(cli, tmp_path):
    code, out, _ = cli("simulate", "example-anonymous-line", "--target", "lines:line", "--robots", "6",
                       "--seed", "3", "--json", "--plot", str(tmp_path / "line.png"))
    doc = json.loads(out)
    assert code == 0 and doc["status"] == "finished"
    assert doc["target"] == {"kind": "lines", "name": "line"} and doc["satisfied"] is True
    assert doc["lattice"] is None and doc["satisfies_lattice"] is None
    assert doc["metrics"]["max_slot_error"] < 1e-9
    assert (tmp_path / "line.png").stat().st_size > 5000


def test_the_run_does_not_depend_on_the_robots_ids():
    """Anonymous: the same start with other ID labels gives the bit-identical motion."""
    line = resolve_target("lines:line")
    start = random_connected(7, 11, range=1.5)
    p = Params(range=1.5, v=0.05, omega=3.2)
    a = simulate(AnonymousLine(), line, start, p, seed=4)
    relabelled = InitialConfiguration([1000 - int(i) * 7 for i in start.ids], start.poses)
    b = simulate(AnonymousLine(), line, relabelled, p, seed=4)
    assert a.status == b.status == "finished"
    assert a.trace.poses.tobytes() == b.trace.poses.tobytes() and a.trace.states == b.trace.states


def test_explore_on_the_line_and_replay_a_counterexample(cli, tmp_path):
    rep = explore(AnonymousLine, ["formation", "connectivity"], max_examples=15, robots=(2, 5), seed=0,
                  budget=None)
    assert rep.lattices == ("lines:line",)
    assert rep.properties["formation"].status == "held" and rep.properties["formation"].conclusive == 15
    # robots as discs of radius 0.45 collide on the way (the line's interval is 1): a finding
    rep = explore("example-anonymous-line", ["collision"], max_examples=30, robots=(2, 6), seed=0, budget=None,
                  options={"radius": 0.45}, out_dir=tmp_path)
    v = rep.properties["collision"]
    assert v.status == "violated" and v.counterexample.target["kind"] == "lines"
    doc = json.loads(open(v.counterexample_path).read())
    assert doc["lattice"] is None and doc["target"] == {"kind": "lines", "name": "line", "shape": "line",
                                                        "interval": 1.0, "range": 1.5}
    code, out, _ = cli("replay", v.counterexample_path, "--json")
    assert code == 1 and json.loads(out)["reproduced"] is True
    code, out, _ = cli("replay", v.counterexample_path)
    assert "lines line, range 1.5" in out


def test_verify_has_its_rows_beside_the_papers(monkeypatch):
    from swarmproof.checkers.report import section_algorithms
    from swarmproof.reference_impl import registry

    plans = dict(registry.verify_plans())
    assert list(plans)[-2:] == ["example-anonymous-line", "example-grid-goals"]
    monkeypatch.setattr(registry, "verify_plans", lambda: [("example-anonymous-line", plans["example-anonymous-line"])])
    rows = section_algorithms()
    got = {r.property: r.verdict.value for r in rows}
    assert got == {"termination": "held", "formation": "held", "connectivity": "held",
                   "tree_links": "n/a", "completion_sound": "n/a"}
    assert all(r.subject == "example-anonymous-line lines:line n=6" and not r.claimed for r in rows)
