"""Issue 34, must hold 4: what the commands write.  ``swarmproof export`` of a trace,
``simulate --export``, check-run's ``--plot`` and ``--gif``, and ``--json`` documents that parse
and are the same bytes run after run.  (``export`` of a counterexample, with its violation on
``/swarmproof/violation``: test_round_trip.py, test_an_exported_counterexample_...)"""

from __future__ import annotations

import json
import os

import pytest

import logkit as lk
from swarmproof.models.recorded_io import read_log

PNG = b"\x89PNG\r\n\x1a\n"


def _dest(tmp_path, fmt: str, stem: str = "run") -> tuple[str, tuple]:
    """The ``--to`` of a format and its ``--storage`` arguments."""
    if fmt == "csv":
        return str(tmp_path / f"{stem}.csv"), ()
    if fmt == "mcap":
        return str(tmp_path / f"{stem}.mcap"), ()
    return str(tmp_path / f"{stem}-bag"), ("--storage", fmt.split("-", 1)[1])


@pytest.fixture(scope="module")
def sim_trace(tmp_path_factory):
    """song2014 on square, 4 robots, seed 0: simulate's JSON and its trace (.json, and the same
    trace as .npz)."""
    import contextlib
    import io

    from swarmproof.cli import main
    from swarmproof.models.trace import Trace

    d = tmp_path_factory.mktemp("trace")
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["simulate", "song2014", "--lattice", "square", "--robots", "4", "--seed", "0", "--json",
                     "--trace", str(d / "t.json")])
    assert code == 0
    npz = Trace.load(str(d / "t.json")).save(str(d / "t.npz"))
    return json.loads(out.getvalue()), str(d / "t.json"), npz


@pytest.mark.parametrize("fmt", lk.FORMATS)
def test_export_a_trace(fmt, sim_trace, tmp_path, cli):
    sim, trace_json, _ = sim_trace
    dest, storage = _dest(tmp_path, fmt)
    code, out, err = cli("export", trace_json, "--to", dest, "--json", *storage)
    doc = json.loads(out)
    assert code == 0
    assert doc == {"command": "export", "file": trace_json, "kind": "trace", "to": dest, "format": fmt,
                   "robots": 4, "steps": sim["steps"], "markers": 0}
    assert f"trace {trace_json}: 4 robots, {sim['steps']} steps -> {fmt} {dest}" in err
    log = read_log(dest)
    assert log.format == fmt and sorted(log.robots) == [0, 1, 2, 3] and log.parents is not None
    assert log.samples == 4 * (sim["steps"] + 1)
    if fmt.startswith("rosbag2"):
        assert os.path.isfile(os.path.join(dest, "metadata.yaml"))
        # the bag is renamed into place: no temporary folder is left next to it
        assert sorted(os.listdir(tmp_path)) == [os.path.basename(dest)]


def test_export_an_npz_trace_equals_its_json_trace(sim_trace, tmp_path, cli):
    _, trace_json, trace_npz = sim_trace
    assert cli("export", trace_json, "--to", str(tmp_path / "a.csv"))[0] == 0
    assert cli("export", trace_npz, "--to", str(tmp_path / "b.csv"))[0] == 0
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    header = (tmp_path / "a.csv").read_text().splitlines()[0]
    assert header == "t,id,x,y,theta,parent,state"     # the controller states as JSON, where they change


@pytest.mark.parametrize("args, match", [
    pytest.param(["--to", "{tmp}/x.csv", "--storage", "mcap"], "--storage='mcap' applies to a rosbag2 bag",
                 id="storage-csv"),
    pytest.param(["--to", "{tmp}"], "exists already", id="bag-exists"),
    pytest.param(["--to", "{tmp}/x.txt"], r"the suffix '.txt' is not a log format", id="suffix"),
])
def test_export_refuses_bad_destinations(args, match, sim_trace, tmp_path, cli):
    _, trace_json, _ = sim_trace
    code, out, err = cli("export", trace_json, *[a.replace("{tmp}", str(tmp_path)) for a in args])
    assert code == 2 and out == "" and match in err and "Traceback" not in err
    assert sorted(os.listdir(tmp_path)) == []


def test_export_of_a_bad_trace_file_names_it(tmp_path, cli):
    bad = tmp_path / "t.json"
    bad.write_text('{"format": "lattice-graph/1"}')
    code, out, err = cli("export", str(bad), "--to", str(tmp_path / "x.mcap"))
    assert code == 2 and str(bad) in err and "Traceback" not in err
    assert not (tmp_path / "x.mcap").exists()


# ----------------------------------------------------------------------------
# simulate --export
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("fmt", ["mcap", "rosbag2-sqlite3"])
def test_simulate_export_writes_a_log_check_run_reads(fmt, tmp_path, cli, check_run):
    dest = str(tmp_path / ("run.mcap" if fmt == "mcap" else "bag"))
    code, out, err = cli("simulate", "song2014", "--lattice", "square", "--robots", "6", "--seed", "1", "--json",
                         "--export", dest)
    sim = json.loads(out)
    assert code == 1 and sim["export"] == dest
    code, doc, _ = check_run(dest, "--range", "1.2", "--property", "connectivity", "--property", "tree_links")
    assert doc["format"] == fmt and doc["robots"] == 6
    for name in ("connectivity", "tree_links"):
        assert doc["properties"][name]["status"] == sim[name]["status"] == "violated"
        assert doc["properties"][name]["witness"]["step"] == sim[name]["witness"]["step"]


def test_simulate_export_human_line(tmp_path, cli):
    dest = str(tmp_path / "run.csv")
    code, out, err = cli("simulate", "example-gather", "--lattice", "square", "--robots", "3", "--seed", "2",
                         "--export", dest)
    assert code == 0 and f"  log: {dest} (swarmproof check-run {dest} --range 1.2)" in out.splitlines()
    assert read_log(dest).format == "csv"


def test_simulate_export_to_an_existing_bag_folder_runs_nothing(tmp_path, cli):
    (tmp_path / "bag").mkdir()
    code, out, err = cli("simulate", "example-gather", "--lattice", "square", "--robots", "3", "--seed", "2",
                         "--export", str(tmp_path / "bag"))
    assert code == 2 and "exists already" in err and os.listdir(tmp_path / "bag") == []


# ----------------------------------------------------------------------------
# check-run's pictures and documents
# ----------------------------------------------------------------------------

@pytest.fixture
def split_mcap(tmp_path):
    return lk.write("mcap", str(tmp_path / "split"), lk.split_run(parents=True))


def test_plot_and_gif_are_written(split_mcap, tmp_path, check_run):
    from PIL import Image

    png, gif = tmp_path / "out" / "split.png", tmp_path / "out" / "split.gif"
    png.parent.mkdir()
    code, doc, err = check_run(split_mcap, "--range", "1.2", "--plot", str(png), "--gif", str(gif))
    assert code == 1 and doc["plot"] == str(png) and doc["gif"] == str(gif)
    assert png.read_bytes()[:8] == PNG
    assert gif.read_bytes()[:6] == b"GIF89a"
    with Image.open(gif) as im:
        assert im.n_frames > 1
    assert f"plot: {png}" in err and f"gif: {gif}" in err


def test_the_plot_is_the_same_bytes_twice(split_mcap, tmp_path, check_run):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    assert check_run(split_mcap, "--range", "1.2", "--plot", str(a))[0] == 1
    assert check_run(split_mcap, "--range", "1.2", "--plot", str(b))[0] == 1
    assert a.read_bytes() == b.read_bytes()


def test_plot_to_a_missing_folder_is_refused_before_reading(tmp_path, cli):
    code, out, err = cli("check-run", str(tmp_path / "nope.csv"), "--range", "1.2", "--plot",
                         str(tmp_path / "no" / "x.png"))
    assert code == 2 and "--plot" in err and "does not exist" in err


@pytest.mark.parametrize("fmt", lk.FORMATS)
def test_json_parses_and_is_the_same_bytes_twice(fmt, tmp_path, cli):
    path = lk.write(fmt, str(tmp_path / "split"), lk.split_run(parents=True))
    runs = [cli("check-run", path, "--range", "1.2", "--json") for _ in range(2)]
    assert runs[0] == runs[1]
    code, out, err = runs[0]
    doc = json.loads(out)
    assert code == doc["exit_code"] == 1 and doc["verdict"] == "violated"
    assert doc["command"] == "check-run" and doc["file"] == path and doc["format"] == fmt
    assert set(doc["properties"]) | set(doc["not_applicable"]) >= {"connectivity", "tree_links", "collision",
                                                                  "formation", "termination"}
    assert list(doc) == sorted(doc)               # one canonical key order
    assert out.endswith("\n") and "result: violated (exit 1)" in err


def test_human_output(tmp_path, cli):
    path = lk.write("csv", str(tmp_path / "split"), lk.split_run())
    code, out, err = cli("check-run", path, "--range", "1.2", "--property", "connectivity")
    assert code == 1 and err == ""
    assert out.splitlines() == [
        f"{path}: csv, 3 robots, 93 pose samples, no parent links",
        "clock: csv time, every 0.1 s from 0 s to 3 s (31 instants, 31 judged; a pose older than 0.25 s is stale; "
        "sample and hold)",
        "range 1.2, radius 0.1; tolerance: position 0, range margin 0, collision margin 0",
        "  connectivity: VIOLATED: the communication graph splits after step 15 into 2 components: [[0, 1], [2]] "
        "(seen at 1.5 s, instant 15)",
        "result: violated (exit 1)",
    ]
