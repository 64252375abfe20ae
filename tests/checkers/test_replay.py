"""Counterexample files and replay: exact re-runs, readable steps, file errors."""

import json

import pytest

from swarmproof.checkers.replay import replay, replay_file
from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError
from swarmproof.reference_impl.initial import random_connected


@pytest.fixture
def cx():
    # `swarmproof simulate song2014 --lattice square --robots 10 --seed 0` splits at step 17
    start = random_connected(10, 0, range=1.2)
    return Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.7853981633974483,
                                                        "dt": 1.0, "extra": {}},
                          lattice="square", robots=[(int(i), tuple(p)) for i, p in zip(start.ids, start.poses)],
                          seed=0, property="connectivity", violation={"step": 17, "message": "split"})


def test_replay_reproduces_the_known_song2014_split(cx):
    rr = replay(cx)
    assert rr.reproduced and rr.step == 17 and rr.verdict.violated
    assert rr.as_dict()["reproduced"] is True and rr.as_dict()["property"] == "connectivity"


def test_replay_not_reproduced_for_a_property_that_holds(cx, tmp_path):
    cx.property = "collision"
    cx.options = {"radius": 0.01}
    path = cx.save(tmp_path / "c.json")
    rr = replay_file(path)
    assert not rr.reproduced and rr.verdict.status == "held"


def test_file_round_trip_is_bit_exact(cx, tmp_path):
    path = cx.save(tmp_path / "c.json")
    back = Counterexample.load(path)
    assert back == cx and back.to_json() == cx.to_json()
    doc = json.loads(open(path).read())
    for key in ("algorithm", "params", "lattice", "initial", "schedule", "faults", "seed", "property",
                "violation", "version"):
        assert key in doc
    assert doc["format"] == "swarmproof-counterexample/1"
    assert set(doc["initial"]["robots"][0]) == {"id", "pose"}


def test_format_steps_exact_lines():
    c = Counterexample(algorithm="song2016", params={"range": 1.5, "v": 0.05, "omega": 0.5, "dt": 1.0},
                       lattice="hexagon", robots=[(2, (0.0, 0.0, 0.0)), (0, (0.25, -1.0, -1.5707963267948966))],
                       seed=7, property="connectivity", violation={"step": 4, "message": "split after step 4"},
                       faults={"crashes": {"3": [1]}, "message_loss": 0.0, "noise_std": [0.0, 0.0]},
                       broken_assumptions=["no_crashes"])
    assert c.format_steps() == [
        "counterexample: song2016 violates connectivity",
        "lattice hexagon, range 1.5, v=0.05, omega=0.5, dt=1",
        "1. place robot 2 at (0, 0) heading 0 deg",
        "2. place robot 0 at (0.25, -1) heading -90 deg",
        "3. run song2016 with seed 7 (synchronous, faults: robot 1 crashes at step 3) -- broken assumptions: "
        "no_crashes",
        "4. at step 4: split after step 4",
    ]


def test_format_steps_prints_a_link_just_short_of_the_range_as_such():
    # the explorer's stretched-first starts: 1.1999999988 would print as 1.2 at 6 digits,
    # exactly the range, and the start rebuilt from the steps would not be connected
    c = Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.5, "dt": 1.0},
                       lattice="square", robots=[(0, (0.0, 0.0, 0.0)), (1, (1.1999999988, 0.0, 0.0)),
                                                 (2, (0.5, 0.25, 0.0))],
                       seed=0, property="connectivity", violation={"step": 3, "message": "split"})
    lines = c.format_steps()
    assert lines[2:5] == ["1. place robot 0 at (0, 0) heading 0 deg",
                          "2. place robot 1 at (1.199999999, 0) heading 0 deg",
                          "3. place robot 2 at (0.5, 0.25) heading 0 deg"]
    shown = float(lines[3].split("(")[1].split(",")[0])
    assert shown < 1.2


def _doc(cx):
    return json.loads(cx.to_json())


def _set(path, value):
    def edit(d):
        cur = d
        for k in path[:-1]:
            cur = cur[k]
        cur[path[-1]] = value
        return d
    return edit


def _drop(key):
    def edit(d):
        del d[key]
        return d
    return edit


@pytest.mark.parametrize("edit, match", [
    pytest.param(_set(("format",), "swarmproof-trace/1"), "format='swarmproof-trace/1'", id="wrong-format"),
    pytest.param(_set(("version",), 2), "version=2 is not supported", id="wrong-version"),
    pytest.param(_drop("property"), "field 'property' is missing", id="missing-property"),
    pytest.param(_set(("seed",), -1), "seed=-1", id="negative-seed"),
    pytest.param(_set(("params", "v"), "fast"), "params.v='fast'", id="bad-param"),
    pytest.param(_set(("initial", "robots"), []), r"initial.robots=\[\]", id="no-robots"),
    pytest.param(_set(("initial", "robots", 0, "pose"), [0, 0]), r"pose=\[0, 0\]", id="short-pose"),
    pytest.param(_set(("violation", "step"), "17"), "violation.step='17'", id="bad-step"),
])
def test_malformed_files(cx, tmp_path, edit, match):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(edit(_doc(cx))))
    with pytest.raises(InputFileError, match=match) as info:
        Counterexample.load(path)
    assert info.value.file == str(path)


def test_not_json_and_missing_file(tmp_path):
    p = tmp_path / "x.json"
    p.write_text("{\n  oops\n}")
    with pytest.raises(InputFileError, match="not JSON") as info:
        Counterexample.load(p)
    assert info.value.line == 2
    with pytest.raises(InputFileError, match="cannot read"):
        Counterexample.load(tmp_path / "missing.json")


@pytest.mark.parametrize("field, value, match", [
    pytest.param("algorithm", "song2099", "song2099", id="unknown-algorithm"),
    pytest.param("lattice", "sqare", "sqare", id="unknown-lattice"),
    pytest.param("property", "liveness", "liveness", id="unknown-property"),
])
def test_replay_rejects_unknown_names(cx, tmp_path, field, value, match):
    setattr(cx, field, value)
    path = cx.save(tmp_path / "c.json")
    with pytest.raises(InputFileError, match=match):
        replay_file(path)
