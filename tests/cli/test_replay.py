"""`swarmproof replay`: exit 1 while it reproduces, 0 once it does not, 2 on bad files; JSON and plot."""

from __future__ import annotations

import json

import pytest

from swarmproof.cli import main
from swarmproof.models.counterexample import Counterexample
from swarmproof.reference_impl.initial import random_connected


@pytest.fixture
def cx_file(tmp_path):
    start = random_connected(10, 0, range=1.2)
    cx = Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.7853981633974483,
                                                      "dt": 1.0},
                        lattice="square", robots=[(int(i), tuple(p)) for i, p in zip(start.ids, start.poses)],
                        seed=0, property="connectivity", violation={"step": 17, "message": "split"})
    return cx, cx.save(tmp_path / "cx.json")


def test_reproduces_exit_1_json_and_plot(capsys, cx_file, tmp_path):
    _, path = cx_file
    png = tmp_path / "r.png"
    code = main(["replay", path, "--json", "--plot", str(png)])
    out, err = capsys.readouterr()
    doc = json.loads(out)
    assert code == 1
    assert doc["reproduced"] is True and doc["property"] == "connectivity" and doc["step"] == 17
    assert "splits" in doc["message"]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "1. place robot" in err


def test_no_longer_reproduces_exit_0(capsys, cx_file, tmp_path):
    cx, _ = cx_file
    cx.property = "collision"
    cx.options = {"radius": 0.01}
    path = cx.save(tmp_path / "c2.json")
    code = main(["replay", path, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0 and doc["reproduced"] is False and doc["step"] is None


@pytest.mark.parametrize("content, match", [
    pytest.param("not json", "not JSON", id="not-json"),
    pytest.param('{"format": "swarmproof-counterexample/1", "version": 9}', "version=9", id="wrong-version"),
    pytest.param('{"format": "lattice-graph/1"}', "format='lattice-graph/1'", id="wrong-format"),
])
def test_bad_files_exit_2(capsys, tmp_path, content, match):
    p = tmp_path / "bad.json"
    p.write_text(content)
    code = main(["replay", str(p)])
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and match in err and str(p) in err


def test_missing_file_exit_2(capsys, tmp_path):
    code = main(["replay", str(tmp_path / "nope.json")])
    assert code == 2 and "cannot read" in capsys.readouterr().err


def test_gif_is_an_animated_gif_with_the_violation_held(capsys, tmp_path):
    from PIL import Image

    from swarmproof.checkers.plotting import gif_frames
    from swarmproof.checkers.replay import replay
    from swarmproof.commands.replay import gif_replay

    # the explorer's shrunk song2014 "premises" counterexample (tests/checkers/test_explore_algorithms.py)
    cx = Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.7853981633974483,
                                                      "dt": 1.0},
                        lattice="square", robots=[(0, (0.0, 0.0, 0.0)),
                                                  (1, (-0.12811435249807243, 0.7072398993156421, 0.0)),
                                                  (2, (0.03094752572962002, -0.43640405663927384, 0.0))],
                        seed=0, property="premises", violation={"step": 1, "message": "..."}, max_steps=8)
    path = cx.save(tmp_path / "cx.json")
    gif = tmp_path / "out" / "run.gif"
    gif.parent.mkdir()     # a missing folder is refused like every output's, never created (issue 29 item 7)
    code = main(["replay", path, "--json", "--gif", str(gif)])
    doc = json.loads(capsys.readouterr().out)
    assert code == 1 and doc["reproduced"] is True and doc["step"] == 1 and doc["gif"] == str(gif)
    data = gif.read_bytes()
    assert data[:6] == b"GIF89a"
    with Image.open(gif) as im:
        assert im.is_animated and im.n_frames > 1
    assert gif_frames(8, mark=1, max_frames=40) == [0] + [1] * 6 + [2, 3, 4, 5, 6, 7, 8]
    # drawn deterministically: the same run gives the same bytes
    assert open(gif_replay(replay(cx), tmp_path / "again.gif"), "rb").read() == data


def test_an_inconclusive_replay_exits_3(capsys, tmp_path):
    """Issue 29 item 8: a replay that cannot judge its property (a pose of 1e308) is inconclusive,
    exit 3 -- never 0, which says the counterexample no longer reproduces."""
    cx = Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.7853981633974483,
                                                      "dt": 1.0},
                        lattice="square", robots=[(0, (0.0, 0.0, 0.0)), (1, (1e308, 0.0, 0.0))],
                        seed=0, property="connectivity", violation={"step": 3, "message": "split"},
                        allow_violations=True)
    path = cx.save(tmp_path / "huge.json")
    code = main(["replay", path])
    out, err = capsys.readouterr()
    assert "not reproduced (inconclusive)" in out, out + err
    assert code == 3


def test_a_replay_capped_before_the_recorded_step_exits_3(capsys, cx_file, tmp_path):
    """A file whose max_steps stops the run before the step it records the violation at: the
    replay held over fewer steps, which cannot say the violation is gone (exit 3, not 0)."""
    cx, _ = cx_file
    assert cx.violation["step"] == 17
    cx.max_steps = 5
    path = cx.save(tmp_path / "short.json")
    code = main(["replay", path, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 3 and doc["reproduced"] is False and doc["status"] == "inconclusive"
    assert doc["steps_run"] == 5
    assert "before step 17, where the file records the violation" in doc["message"]
    assert "give max_steps of at least 17" in doc["message"]
    cx.max_steps = 17               # the cap reaches the recorded step: reproduced again
    assert main(["replay", cx.save(tmp_path / "enough.json")]) == 1
