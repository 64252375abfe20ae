"""Issue 34, must hold 1: a run of every bundled algorithm, exported as CSV, MCAP and rosbag2
(sqlite3 and mcap storage) and judged by check-run, gets the verdicts that the registry's property
objects give on the simulated trace itself (``get_property(name).check(trace, ctx)``), witness step
equal, for the properties that read poses and parent links: connectivity, tree_links, collision,
formation.  Poses read back exactly, headings within ``HEADING_TOL`` (quaternions are not
bit-exact).  A counterexample exported and re-checked is violated at the same step.

Two rules of a log, stated once here:

* a log records poses, not the run's "finished": check-run's formation needs the swarm at rest
  for ``--static-window``; the comparison uses one period (``dt``): the last step moved nothing.
  (A run that still moved in its last step is inconclusive: test_a_log_that_ends_in_motion...)
* a log is judged as a range graph at phi, whatever the algorithm: for the algorithms whose robots
  all hear each other (jiang, leechong-*: connectivity not applicable in simulate) the trace is
  judged with a range-graph view of the algorithm (``_range_graph_view``).
"""

from __future__ import annotations

import functools
import json
import math

import numpy as np
import pytest

import logkit as lk
from swarmproof.checkers.recorded import check_recorded
from swarmproof.checkers.runs import run_and_check
from swarmproof.commands.export import export_trace
from swarmproof.invariants.registry import PropertyContext, collision_radius, get_property
from swarmproof.models.recorded_io import NS, read_log
from swarmproof.models.targets import resolve_target
from swarmproof.reference_impl.initial import random_grid_connected
from swarmproof.reference_impl.registry import algorithm_names

HEADING_TOL = 1e-9           # rad: quaternion -> yaw is not bit-exact
PROPS = ("connectivity", "tree_links", "collision", "formation")


def _grid_start(n, seed):
    return random_grid_connected(n, seed, range=0.6, spacing=0.2)


#: case id -> (registry name, target, robots or a start, seed): small teams, short runs, seeded.
#: Grid robots (wang2020*, example-grid-goals) start from a connected grid start (their own start
#: is disconnected: connectivity would be vacuous), as many robots as the shape has cells (wang2020
#: scales a shape to its team; check-run does not: test_check_run_scales_the_target...);
#: song2014 (6, seed 1) loses connectivity and a tree link, song2016 (4, seed 0) has a collision.
CASES = {
    "song2016": ("song2016", "lattice:square", 4, 0),
    "song2016-literal": ("song2016-literal", "lattice:square", 4, 0),
    "song2016-subtree-clock": ("song2016-subtree-clock", "lattice:hexagon", 4, 1),
    "song2014": ("song2014", "lattice:square", 6, 1),
    "jiang": ("jiang", "pattern:rhombus-triangles", 4, 0),
    "jiang-literal": ("jiang-literal", "pattern:square-dots", 4, 0),
    "wang2020": ("wang2020", "shape:letter-l", _grid_start(5, 0), 0),
    "wang2020-broadcast-handshake": ("wang2020-broadcast-handshake", "shape:letter-l", _grid_start(5, 2), 2),
    "leechong-leader": ("leechong-leader", "lines:wedge", 4, 0),
    "leechong-leader-fteam": ("leechong-leader-fteam", "lines:circle", 4, 0),
    "leechong-leader-printed": ("leechong-leader-printed", "lines:two-row", 4, 0),
    "leechong-neighbor": ("leechong-neighbor", "lines:wedge", 4, 0),
    "leechong-neighbor-fteam": ("leechong-neighbor-fteam", "lines:diamond", 4, 0),
    "leechong-neighbor-printed": ("leechong-neighbor-printed", "lines:wedge", 5, 1),
    "example-gather": ("example-gather", "lattice:square", 4, 0),
    "example-anonymous-line": ("example-anonymous-line", "lines:line", 4, 0),
    "example-grid-goals": ("example-grid-goals", "shape:square-9", _grid_start(4, 1), 1),
}

REQUIRED = {"song2016", "song2014", "jiang", "wang2020", "leechong-leader", "leechong-neighbor", "example-gather"}


def test_the_table_runs_every_bundled_algorithm():
    names = {alg for alg, *_ in CASES.values()}
    assert names == set(algorithm_names()) and REQUIRED <= names


@functools.lru_cache(maxsize=None)
def simulated(case: str):
    """``(checked run, radius, {property: (status, witness step) or "n/a"})`` of one case, once per process."""
    alg, target, start, seed = CASES[case]
    kw = {"robots": start} if isinstance(start, int) else {"initial": start}
    c = run_and_check(alg, resolve_target(target), seed=seed, **kw)
    radius = collision_radius(c.params, {})
    out = {}
    for name in PROPS:
        if name in c.not_applicable:
            # no parent links, or no range graph (every robot hears every robot: jiang, leechong-*):
            # simulate says not applicable, and so does check-run --algorithm (the algorithm's model)
            out[name] = "n/a"
            continue
        algo = c.algorithm
        r = get_property(name).check(c.result.trace, PropertyContext(algo, c.lattice, c.params, c.result,
                                                                      {"radius": radius}))
        out[name] = (r.status, (r.witness or {}).get("step"))
    return c, radius, out


def test_the_table_has_violations_to_compare():
    """The round trip compares violations (witness steps), not only held verdicts."""
    found = {(name, v[0]) for case in ("song2014", "song2016", "example-gather")
             for name, v in simulated(case)[2].items() if v != "n/a"}
    assert {("connectivity", "violated"), ("tree_links", "violated"), ("collision", "violated"),
            ("formation", "violated"), ("formation", "held")} <= found


def _export(trace, fmt: str, tmp_path) -> str:
    dest = str(tmp_path / ("run.csv" if fmt == "csv" else "run.mcap" if fmt == "mcap" else "bag"))
    storage = fmt.split("-", 1)[1] if fmt.startswith("rosbag2") else None
    assert export_trace(trace, dest, storage=storage) == dest
    return dest


def _assert_samples_read_back(trace, log, dt: float):
    """Every pose at step s * dt: positions exact, headings within HEADING_TOL (wrapped)."""
    ids = [int(i) for i in trace.ids]
    assert sorted(log.robots) == sorted(ids)
    steps = np.arange(len(trace.poses))
    for j, rid in enumerate(ids):
        r = log.robots[rid]
        assert r.t.tolist() == (steps * int(round(dt * NS))).tolist()
        assert np.array_equal(r.xyt[:, :2], trace.poses[:, j, :2])
        err = np.abs(np.angle(np.exp(1j * (r.xyt[:, 2] - trace.poses[:, j, 2]))))
        assert err.max() <= HEADING_TOL


def _storage_args(fmt: str) -> tuple:
    return ("--storage", fmt.split("-", 1)[1]) if fmt.startswith("rosbag2") else ()


@pytest.fixture(scope="module")
def trace_file(tmp_path_factory):
    """``trace_file(case)``: the case's trace saved once (``simulate --trace``'s format)."""
    d = tmp_path_factory.mktemp("traces")

    @functools.lru_cache(maxsize=None)
    def save(case: str) -> str:
        return simulated(case)[0].result.trace.save(str(d / f"{case}.npz"))
    return save


def _round_trip(case: str, fmt: str, tmp_path, cli, trace_file):
    """simulate (cached) -> trace file -> ``swarmproof export`` -> read_log (poses) and
    ``swarmproof check-run --json --algorithm A --target T`` -> the simulated trace's verdicts."""
    c, radius, sim = simulated(case)
    alg, target, _, _ = CASES[case]
    trace = c.result.trace
    trace_file = trace_file(case)
    dest = str(tmp_path / ("run.csv" if fmt == "csv" else "run.mcap" if fmt == "mcap" else "bag"))
    code, out, err = cli("export", trace_file, "--to", dest, *_storage_args(fmt))
    assert code == 0, err
    log = read_log(dest)
    assert log.format == fmt
    _assert_samples_read_back(trace, log, c.params.dt)
    props = [a for name in PROPS for a in ("--property", name)]
    code, out, err = cli("check-run", dest, "--json", "--algorithm", alg, "--target", target, "--range",
                         repr(c.params.range), "--radius", repr(radius), "--static-window", repr(c.params.dt), *props)
    assert "Traceback" not in err
    doc = json.loads(out)
    clock = doc["clock"]
    assert clock["period_s"] == c.params.dt and doc["gaps"] == [] and doc["radius"] == radius
    assert clock["instants"] == clock["judged_instants"] == len(trace.poses)
    for name in PROPS:
        if sim[name] == "n/a":
            assert name in doc["not_applicable"] and name not in doc["properties"]
            continue
        r = doc["properties"][name]
        assert (r["status"], (r["witness"] or {}).get("step")) == sim[name], (name, r["message"])
        if r["status"] == "violated" and "step" in r["witness"]:     # formation's witness names robots, no step
            w = r["witness"]
            step = w["step"] + (1 if name == "tree_links" else w.get("fraction", 0.0) if name == "collision" else 0)
            assert w["time_s"] == pytest.approx(step * c.params.dt, abs=1e-9)


CASE_IDS = sorted(CASES)


@pytest.mark.parametrize("case", CASE_IDS)
def test_round_trip_csv(case, tmp_path, cli, trace_file):
    _round_trip(case, "csv", tmp_path, cli, trace_file)


@pytest.mark.parametrize("case", CASE_IDS)
def test_round_trip_mcap(case, tmp_path, cli, trace_file):
    _round_trip(case, "mcap", tmp_path, cli, trace_file)


@pytest.mark.parametrize("case", CASE_IDS)
def test_round_trip_rosbag2_sqlite3(case, tmp_path, cli, trace_file):
    _round_trip(case, "rosbag2-sqlite3", tmp_path, cli, trace_file)


@pytest.mark.parametrize("case", CASE_IDS)
def test_round_trip_rosbag2_mcap(case, tmp_path, cli, trace_file):
    _round_trip(case, "rosbag2-mcap", tmp_path, cli, trace_file)


def test_parent_links_round_trip(tmp_path):
    """The parents a trace's states hold come back as the log's parent samples (-1: none)."""
    c, _, _ = simulated("song2014")
    trace = c.result.trace
    log = read_log(_export(trace, "rosbag2-sqlite3", tmp_path))
    assert log.parents is not None
    for j, rid in enumerate(int(i) for i in trace.ids):
        want = [-1 if dict(trace.states[s][j]).get("parent") is None else dict(trace.states[s][j])["parent"]
                for s in range(len(trace.poses))]
        assert log.parents[rid].parent.tolist() == want


def test_a_log_that_ends_in_motion_has_no_formation_verdict(tmp_path):
    """A run that finished while a robot still moved in its last step: the log cannot tell a
    finished swarm from one that would move on, so formation (and termination) are inconclusive
    whatever the simulated verdict (here held); rest for one period would have sufficed."""
    c, radius, sim = simulated("leechong-leader")
    moved = np.abs(np.diff(c.result.trace.poses[-3:, :, :2], axis=0)).max(axis=(1, 2))
    assert moved[0] > 0 and moved[1] == 0 and sim["formation"] == ("held", None)
    log = read_log(_export(c.result.trace, "csv", tmp_path))
    rep = check_recorded(log, phi=c.params.range, target=c.lattice, algorithm=c.algorithm,
                         properties=["formation", "termination"], radius=radius)      # default window: 2 s
    assert rep.results["formation"].status == "inconclusive"
    assert rep.results["termination"].status == "inconclusive"
    assert "the log ended while robots still moved" in rep.results["termination"].message


def test_the_formation_message_of_a_log_in_motion_names_no_step_cap(tmp_path):
    c, radius, _ = simulated("leechong-leader")
    log = read_log(_export(c.result.trace, "csv", tmp_path))
    rep = check_recorded(log, phi=c.params.range, target=c.lattice, properties=["formation"], radius=radius)
    msg = rep.results["formation"].message
    assert rep.results["formation"].status == "inconclusive"
    assert "step cap" not in msg and "None" not in msg


# ----------------------------------------------------------------------------
# the same through the command line: simulate --trace, export, check-run --json
# ----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def simulated_cli(tmp_path_factory):
    """``simulate song2014 --robots 6 --seed 1 --trace --json``: its JSON and trace file, once per module."""
    import contextlib
    import io

    from swarmproof.cli import main

    d = tmp_path_factory.mktemp("sim")
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["simulate", "song2014", "--lattice", "square", "--robots", "6", "--seed", "1",
                     "--trace", str(d / "t.json"), "--json"])
    assert code == 1          # song2014 claims tree links (000 Lemma 7): violated
    return json.loads(out.getvalue()), str(d / "t.json")


@pytest.mark.parametrize("fmt", lk.FORMATS)
def test_simulate_export_check_run_agree_with_simulate_json(fmt, simulated_cli, tmp_path, cli, check_run):
    sim, trace_file = simulated_cli
    dest = str(tmp_path / ("run.csv" if fmt == "csv" else "run.mcap" if fmt == "mcap" else "bag"))
    code, out, err = cli("export", trace_file, "--to", dest, "--json", *_storage_args(fmt))
    assert code == 0 and json.loads(out)["format"] == fmt
    code, doc, _ = check_run(dest, "--algorithm", "song2014", "--target", "lattice:square", "--static-window", "1")
    props = doc["properties"]
    for name in ("connectivity", "tree_links"):
        assert props[name]["status"] == sim[name]["status"] == "violated"
        assert props[name]["witness"]["step"] == sim[name]["witness"]["step"]
    assert props["connectivity"]["witness"]["components"] == sim["connectivity"]["witness"]["components"]
    assert (props["tree_links"]["witness"]["child"], props["tree_links"]["witness"]["parent"]) == \
        (sim["tree_links"]["witness"]["child"], sim["tree_links"]["witness"]["parent"])
    assert props["formation"]["status"] == sim["satisfaction"]["status"] == "held"
    assert doc["range"] == sim["range"] == 1.2
    # the algorithm's claims decide, as in simulate: tree links claimed and violated -> exit 1
    assert code == sim["exit_code"] == 1
    assert props["tree_links"]["decides"] is True and props["connectivity"]["decides"] is False


# ----------------------------------------------------------------------------
# a counterexample, exported and re-checked
# ----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def counterexample(tmp_path_factory):
    """tests/cli/test_replay.py's song2014 connectivity counterexample (10 robots, split after step 17)."""
    from swarmproof.models.counterexample import Counterexample
    from swarmproof.reference_impl.initial import random_connected

    start = random_connected(10, 0, range=1.2)
    cx = Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.7853981633974483,
                                                      "dt": 1.0},
                        lattice="square", robots=[(int(i), tuple(p)) for i, p in zip(start.ids, start.poses)],
                        seed=0, property="connectivity", violation={"step": 17, "message": "split"})
    return cx.save(tmp_path_factory.mktemp("cx") / "cx.json")


@pytest.fixture(scope="module")
def replayed(counterexample):
    """``swarmproof replay --json`` of the counterexample, once per module."""
    import contextlib
    import io

    from swarmproof.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["replay", str(counterexample), "--json"])
    doc = json.loads(out.getvalue())
    assert code == 1 and doc["reproduced"] is True and doc["step"] == 17
    return doc


@pytest.mark.parametrize("fmt", lk.FORMATS)
def test_an_exported_counterexample_is_violated_at_its_step(fmt, counterexample, replayed, tmp_path, cli, check_run):
    dest = str(tmp_path / ("cx.csv" if fmt == "csv" else "cx.mcap" if fmt == "mcap" else "cxbag"))
    code, out, err = cli("export", counterexample, "--to", dest, "--json", *_storage_args(fmt))
    exported = json.loads(out)
    assert code == 0 and exported["kind"] == "counterexample" and exported["markers"] == 1
    assert exported["format"] == fmt and exported["robots"] == 10
    assert ("the violation is not marked: a CSV has no topic for markers" if fmt == "csv" else
            "the violation marked on /swarmproof/violation at 17 s") in err
    code, doc, _ = check_run(dest, "--range", "1.2", "--property", "connectivity")
    conn = doc["properties"]["connectivity"]
    assert code == 1 and conn["status"] == "violated"
    assert conn["witness"]["step"] == replayed["step"] == 17 and conn["witness"]["time_s"] == 17.0
    assert conn["witness"]["components"] == [[0], [1, 2, 3, 4, 5, 6, 7, 8, 9]]
    assert f"into 2 components: {conn['witness']['components']}" in replayed["message"]
    assert "splits after step 17" in conn["message"] and "splits after step 17" in replayed["message"]
    assert doc["robots"] == 10 and doc["samples"] == 10 * 189
    if fmt == "csv":                 # poses, parents and states: no marker in a CSV
        assert open(dest).readline() == "t,id,x,y,theta,parent,state\n"
        return
    # the violation on /swarmproof/violation at its step, for RViz and Foxglove
    types, msgs = lk.topics_and_messages(dest, "/swarmproof/violation")
    assert types["/swarmproof/violation"] in ("visualization_msgs/msg/MarkerArray", "visualization_msgs/MarkerArray")
    assert types["/robot_0/pose"] in ("geometry_msgs/msg/PoseStamped", "geometry_msgs/PoseStamped")
    assert types["/robot_0/parent"] in ("std_msgs/msg/Int32", "std_msgs/Int32")
    assert len(msgs) == 1
    t, arr = msgs[0]
    spheres, label = arr.markers
    assert t == 17 * NS and (spheres.header.stamp.sec, spheres.header.stamp.nanosec) == (17, 0)
    assert label.text.startswith("connectivity: the communication graph splits after step 17")
    assert len(spheres.points) == 10          # a split names no robots: every robot at the step


# ----------------------------------------------------------------------------
# bugs: the algorithm's own range rule and target are not used for a log
# ----------------------------------------------------------------------------

def test_wang2020_round_trip_keeps_its_inclusive_range_rule(tmp_path):
    c = run_and_check("wang2020", resolve_target("shape:square-9"), seed=1, initial=_grid_start(6, 1))
    sim = get_property("connectivity").check(c.result.trace, PropertyContext(c.algorithm, c.lattice, c.params,
                                                                              c.result, {}))
    assert sim.status == "violated" and sim.witness["step"] == 26
    log = read_log(_export(c.result.trace, "csv", tmp_path))
    rep = check_recorded(log, phi=c.params.range, algorithm=c.algorithm, properties=["connectivity"])
    assert rep.results["connectivity"].witness["step"] == 26


def test_check_run_scales_the_target_as_the_algorithm_does(tmp_path, cli, check_run):
    dest = str(tmp_path / "run.csv")
    code, out, _ = cli("simulate", "wang2020", "--shape", "square-9", "--robots", "4", "--seed", "0", "--json",
                       "--export", dest)
    sim = json.loads(out)
    assert code == 0 and sim["satisfaction"]["status"] == "held"
    code, doc, _ = check_run(dest, "--algorithm", "wang2020", "--target", "shape:square-9", "--range", "0.6",
                             "--static-window", "0.5", "--property", "formation")
    assert doc["properties"]["formation"]["status"] == "held", doc["properties"]["formation"]["message"]


def test_a_run_with_a_late_robot_round_trips(tmp_path):
    from swarmproof.models.library import load
    from swarmproof.reference_impl.engine import FaultModel, simulate
    from swarmproof.reference_impl.initial import random_connected
    from swarmproof.reference_impl.protocol import Params
    from swarmproof.reference_impl.registry import get_algorithm

    lattice, params = load("square"), Params(range=1.2, v=0.05)
    algorithm = get_algorithm("song2016", n_robots=6)
    res = simulate(algorithm, lattice, random_connected(6, 4, range=1.2, min_separation=0.3), params, seed=4,
                   faults=FaultModel(additions={3: [(99, [5.0, 5.0, 0.0])]}), allow_violations=True, max_steps=400)
    sim = get_property("connectivity").check(res.trace, PropertyContext(algorithm, lattice, params, res, {}))
    assert sim.status == "violated" and sim.witness["step"] == 4
    rep = check_recorded(read_log(_export(res.trace, "mcap", tmp_path)), phi=1.2, properties=["connectivity"])
    r = rep.results["connectivity"]
    assert (r.status, r.witness and r.witness["step"], r.witness and r.witness["time_s"]) == ("violated", 4, 4.0)


@pytest.mark.parametrize("fmt", lk.FORMATS)
def test_headings_at_the_wrap_read_back_within_tolerance(fmt, tmp_path):
    """Headings at and past +-pi, and tiny ones, through write_log and read_log: equal modulo 2 pi
    within HEADING_TOL (a quaternion gives the yaw in [-pi, pi]; CSV keeps the number written)."""
    from swarmproof.models.recorded_io import write_log

    thetas = [0.0, 1e-12, math.pi, -math.pi, math.pi - 1e-12, -math.pi + 1e-12, 4.0, -7.0, 2.5]
    rows = [(k * 100_000_000, rid, 0.5 * rid, 0.0, th, None) for k, th in enumerate(thetas) for rid in (1, 2)]
    dest = str(tmp_path / ("h.csv" if fmt == "csv" else "h.mcap" if fmt == "mcap" else "hbag"))
    write_log(iter(rows), dest, ids=[1, 2], has_parent=False,
              storage=fmt.split("-", 1)[1] if fmt.startswith("rosbag2") else None)
    got = read_log(dest).robots[2].xyt[:, 2]
    err = np.abs(np.angle(np.exp(1j * (got - np.array(thetas)))))
    assert err.max() <= HEADING_TOL
    if fmt != "csv":
        assert np.all(np.abs(got) <= math.pi)
    else:
        assert got.tolist() == thetas
