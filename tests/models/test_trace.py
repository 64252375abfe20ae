"""swarmproof-trace/1: JSON forms, round trips, and clear errors for bad files."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import pytest

from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.models.trace import Event, InitialConfiguration, Trace, from_jsonable, to_jsonable


@dataclass(frozen=True)
class Msg:
    path: tuple
    d: float


def test_to_jsonable_forms():
    assert to_jsonable(Msg((1, 2), float("-inf"))) == {"__type__": "Msg", "path": [1, 2], "d": "-inf"}
    assert to_jsonable({3: np.int64(4), "a": np.array([1.5])}) == {"3": 4, "a": [1.5]}
    assert to_jsonable(frozenset({(2, 1), (1, 2)})) == [[1, 2], [2, 1]]
    assert from_jsonable({"a": [[1, [2]]]}) == {"a": ((1, (2,)),)}


def _trace():
    return Trace(ids=[5, 2], poses=np.arange(12, dtype=float).reshape(2, 2, 3),
                 states=[(None, (("parent", 5),)), (None, (("parent", 5),))],
                 events=[Event(0, "clamp", (2,), (("why", "turn"),))],
                 messages=[{5: ("hi", (1, 2))}], present=np.ones((2, 2), dtype=bool),
                 meta={"seed": 3})


@pytest.mark.parametrize("name", ["t.json", "t.npz"])
def test_round_trip(tmp_path, name):
    t = _trace()
    back = Trace.load(t.save(tmp_path / name))
    assert back.to_json() == t.to_json()
    assert back.messages == [{5: ("hi", (1, 2))}] and back.events == t.events


def test_npz_header_is_utf8_bytes_and_old_string_headers_still_load(tmp_path):
    """The NPZ header is UTF-8 bytes (a numpy string array stops at 2**31 bytes: a 256-agent 004
    trace crashed there); files written with a string header still load."""
    t = _trace()
    path = t.save(tmp_path / "t.npz")
    with np.load(path) as z:
        assert z["header"].dtype == np.uint8
        old = {k: z[k] for k in z.files}
    old["header"] = np.array(old["header"].tobytes().decode("utf-8"))
    np.savez_compressed(tmp_path / "old.npz", **old)
    assert Trace.load(tmp_path / "old.npz").to_json() == t.to_json()


def test_a_trace_file_is_one_frame_a_line_and_indented_files_still_load(tmp_path):
    """No indentation inside a frame (an 8-robot wang2020 trace was 5 MB, 4.4x its values; issue
    15 review): a top-level key a line, a list element (a frame, an event) a line, no spaces."""
    t = _trace()
    with open(t.save(tmp_path / "t.json"), encoding="utf-8") as f:
        text = f.read()
    lines = text.splitlines()
    assert lines[0] == "{" and lines[-1] == "}" and '"format": "swarmproof-trace/1",' in lines
    states = lines.index('"states": [')
    assert lines[states + 1:states + 3] == ['[null,[["parent",5]]],', '[null,[["parent",5]]]']
    assert lines[lines.index('"poses": [') + 1] == "[[0.0,1.0,2.0],[3.0,4.0,5.0]],"
    assert json.loads(text) == json.loads(json.dumps(t.as_dict()))
    # a file written with the former 2-space indentation reads back as the same trace
    (tmp_path / "old.json").write_text(json.dumps(t.as_dict(), sort_keys=True, indent=2) + "\n")
    assert Trace.load(tmp_path / "old.json").to_json() == t.to_json()


BAD = [
    ("not-json", "{", r"t\.json:1: not valid JSON"),
    ("wrong-format", json.dumps({"format": "swarmproof-trace/9", "ids": [], "poses": [], "states": []}),
     r"field 'format': format='swarmproof-trace/9'"),
    ("missing-states", json.dumps({"format": "swarmproof-trace/1", "ids": [1], "poses": [[[0, 0, 0]]]}),
     r"field 'states': required field 'states' is missing"),
    ("states-length", json.dumps({"format": "swarmproof-trace/1", "ids": [1], "poses": [[[0, 0, 0]]],
                                  "states": []}), r"len\(states\)=0 must equal T\+1=1"),
    ("top-level-list", "[]", "top level is list"),
]


@pytest.mark.parametrize("text,match", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_trace_files(tmp_path, text, match):
    p = tmp_path / "t.json"
    p.write_text(text)
    with pytest.raises(InputFileError, match=match):
        Trace.load(p)


def test_missing_file_and_bad_initial():
    with pytest.raises(InputFileError, match="file does not exist"):
        Trace.load("/nonexistent/t.json")
    with pytest.raises(UsageError, match=r"poses shape=\(1, 2\) must be \(1, 3\)"):
        InitialConfiguration([1], [[0, 0]])
    with pytest.raises(UsageError, match="must be integers"):
        InitialConfiguration([1.5], [[0, 0, 0]])
