"""Targets (issue 12): the Target protocol, the kinds lattice / lines / shape, resolving
``[KIND:]NAME|FILE``, counterexample files that carry a target, and simulate's JSON."""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest

from swarmproof.models import library
from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.models.satisfaction import fulfillment_ratio, satisfies_lattice
from swarmproof.models.targets import (GoalSet, LinePattern, Target, _KINDS, register_target_kind,
                                       resolve_target, target_from_description, target_kinds)


def _rot(xy, ang, shift):
    c, s = math.cos(ang), math.sin(ang)
    xy = np.asarray(xy, dtype=float)
    return np.column_stack((c * xy[:, 0] - s * xy[:, 1] + shift[0], s * xy[:, 0] + c * xy[:, 1] + shift[1]))


def test_every_kind_is_a_target_and_describes_itself_for_a_round_trip(tmp_path):
    assert target_kinds()[:3] == ["lattice", "lines", "shape"]
    for text in ("square", "lines:line", "shape:square-9", "shape:letter-l"):
        t = resolve_target(text)
        assert isinstance(t, Target)
        d = json.loads(json.dumps(t.describe()))
        back = target_from_description(d)
        assert back.describe() == t.describe() and back.kind == t.kind == d["kind"]
    # a user's lattice file carries its whole document, so it rebuilds without the file
    path = tmp_path / "ring.yaml"
    shutil.copy(library._folder() / "hexagon-ring.yaml", path)
    g = resolve_target(str(path))
    d = json.loads(json.dumps(g.describe()))
    path.unlink()
    assert target_from_description(d) == g


def test_a_lattice_target_judges_as_def_2_and_reports_q():
    sq = library.load("square")
    four = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    check = sq.satisfied([0, 1, 2, 3], four, phi=1.2)
    ref = satisfies_lattice([0, 1, 2, 3], four, sq, 1.2)
    assert (check.status, check.message, check.cites) == (ref.status, ref.message, ref.cites)
    assert sq.metrics([0, 1, 2, 3], four, phi=1.2) == {"fulfillment_ratio": 0.5, "non_fulfillment_ratio": 0.5}
    assert sq.progress([0, 1, 2, 3], four, phi=1.2) == fulfillment_ratio([0, 1, 2, 3], four, sq, 1.2) == 0.5
    bad = sq.satisfied([5, 6], [[0, 0, 0], [0.9, 0, 0]], phi=1.2)
    assert bad.violated and bad.witness["pair"] == [5, 6] and not bad
    with pytest.raises(UsageError, match="has no range and none was given"):
        library.load("square").__class__("x", ["A"], []).satisfied([1], [[0, 0, 0]])


def test_a_line_is_judged_on_positions_up_to_a_rigid_motion_and_a_permutation():
    line = LinePattern("line", interval=0.5)
    pts = line.points(6)
    moved = _rot(pts, 2.1, (3.0, -1.0))[[4, 1, 5, 0, 2, 3]]
    poses = np.column_stack((moved, np.linspace(0, 3, 6)))   # headings are not judged
    assert line.satisfied(range(6), poses).held
    assert line.progress(range(6), poses) == pytest.approx(0.0, abs=1e-9)
    off = poses.copy()
    off[2, 0] += 0.05
    check = line.satisfied(range(6), off)
    assert check.violated and 0.01 < check.witness["max_error"] <= 0.05 + 1e-9
    assert line.progress(range(6), off) < line.progress(range(6), poses)
    # a mirror image of a non-symmetric arrangement is still a line (a line is symmetric)
    assert line.satisfied(range(3), [[0, 0, 0], [0, -0.5, 0], [0, -1.0, 0]]).held
    assert line.satisfied([1, 2], [[0, 0, 0], [0.6, 0, 0]]).violated
    assert line.satisfied([], np.zeros((0, 3))).status == "inconclusive"
    with pytest.raises(UsageError, match=r"interval=0 must be a finite number > 0"):
        LinePattern("x", interval=0)


def test_a_goal_set_holds_one_robot_per_cell_and_names_what_is_wrong():
    g = GoalSet.from_bitmap("L", ["#.", "##"], spacing=0.2)
    good = [[0, 0, 0], [0, 0.2, 0], [0.2, 0, 0]]
    assert g.satisfied([1, 2, 3], good).held and g.metrics([1, 2, 3], good) == {
        "cells": 3, "occupied": 3, "off_shape": 0}
    two = g.satisfied([1, 2, 3], [[0, 0, 0], [0, 0, 0], [0.2, 0, 0]])
    assert two.violated and two.witness == {"cell": [0, 0], "robots": [1, 2]}
    off = g.satisfied([1, 2, 3], [[0, 0, 0], [0, 0.2, 0], [0.3, 0, 0]])
    assert off.violated and off.message.startswith("robot 3 at (0.3, 0) is on no goal cell")
    few = g.satisfied([1, 2], [[0, 0, 0], [0, 0.2, 0]])
    assert few.violated and "goal cell (1, 0) is empty" in few.message
    assert g.progress([1, 2], [[0, 0, 0], [0, 0.2, 0]]) == pytest.approx(2 / 3)
    with pytest.raises(UsageError, match=r"bitmap row 0 column 1: 'x'"):
        GoalSet.from_bitmap("bad", ["#x"])
    with pytest.raises(UsageError, match=r"cells=\[\] is empty"):
        GoalSet("empty", frozenset())


def test_resolving_names_kinds_files_and_ambiguity(tmp_path):
    assert resolve_target("square").kind == "lattice"
    assert resolve_target("lattice:square").name == "square"
    assert resolve_target("square-9", kind="shape").kind == "shape"
    with pytest.raises(UsageError, match=r"target kind='patterns' is not known"):
        resolve_target("x", kind="patterns")
    assert resolve_target("pattern:rhombus-triangles").kind == "pattern"
    with pytest.raises(InputFileError, match=r"no-such: no such file and no bundled target of that name"):
        resolve_target("no-such")
    with pytest.raises(InputFileError, match=r"no bundled shape target of that name"):
        resolve_target("square", kind="shape")
    # a description file of any kind
    f = tmp_path / "l.json"
    f.write_text(json.dumps(GoalSet.from_bitmap("mine", ["##"]).describe()))
    assert resolve_target(str(f)).name == "mine"
    assert resolve_target(f"shape:{f}").name == "mine"
    bad = tmp_path / "bad.json"
    bad.write_text('{"kind": "shape", "name": "b", "cells": [[0, 0.5]]}')
    with pytest.raises(InputFileError, match=r"bad.json.*cells=\[\[0, 0.5\]\] must be a list of \[i, j\] integer pairs"):
        resolve_target(str(bad))
    # a name two kinds bundle is ambiguous; the prefix decides
    register_target_kind("testkind", from_description=lambda d: None, bundled=lambda: ["square"],
                         by_name=lambda n: GoalSet.from_bitmap("square", ["#"]))
    try:
        with pytest.raises(UsageError, match=r"target='square' is ambiguous: bundled as lattice, testkind; "
                                             r"fix: say which: lattice:square or testkind:square"):
            resolve_target("square")
        assert resolve_target("testkind:square").kind == "shape"
        assert resolve_target("lattice:square").kind == "lattice"
    finally:
        _KINDS.pop("testkind")


def test_counterexample_files_without_a_target_load_as_before_and_with_one_round_trip(tmp_path):
    base = dict(algorithm="example-gather", params={"range": 1.2, "v": 0.05, "omega": 0.785, "dt": 1.0},
                lattice="square", robots=[(0, (0.0, 0.0, 0.0)), (1, (0.5, 0.0, 0.0))], seed=0,
                property="connectivity", violation={"step": 3, "message": "split"})
    old = Counterexample(**base)
    assert "target" not in old.as_dict()
    assert Counterexample.from_dict(json.loads(old.to_json())).target is None
    shape = GoalSet.from_bitmap("mine", ["##"]).describe()
    new = Counterexample(**dict(base, lattice=None, target=shape))
    back = Counterexample.from_dict(json.loads(new.to_json()))
    assert back.target == shape and back.lattice is None
    assert back.format_steps()[1].startswith("shape mine, range 1.2")
    doc = json.loads(new.to_json())
    doc["target"] = {"kind": 3}
    with pytest.raises(InputFileError, match=r"target=\{'kind': 3\} must be a JSON object with string 'kind' and 'name'"):
        Counterexample.from_dict(doc, file="f.json")


def test_simulate_json_adds_target_satisfied_and_metrics_keeping_the_lattice_fields(cli):
    code, out, _ = cli("simulate", "example-gather", "--lattice", "square", "--robots", "4",
                       "--seed", "0", "--json")
    doc = json.loads(out)
    assert doc["lattice"] == "square" and doc["target"] == {"kind": "lattice", "name": "square"}
    assert doc["satisfied"] == doc["satisfies_lattice"]
    assert doc["metrics"] == {"fulfillment_ratio": doc["fulfillment_ratio"],
                              "non_fulfillment_ratio": doc["non_fulfillment_ratio"]}
    code2, out2, _ = cli("simulate", "example-gather", "--target", "lattice:square", "--robots", "4",
                         "--seed", "0", "--json")
    assert (code2, out2) == (code, out)


def test_simulate_on_a_shape_has_null_lattice_fields_and_the_shapes_metrics(cli):
    code, out, _ = cli("simulate", "example-gather", "--shape", "square-9", "--range", "1.2",
                       "--robots", "9", "--seed", "1", "--json")
    doc = json.loads(out)
    assert doc["lattice"] is None and doc["satisfies_lattice"] is None and doc["fulfillment_ratio"] is None
    assert doc["target"] == {"kind": "shape", "name": "square-9"}
    # gathering is not the 3x3 shape: reported, but example-gather claims no formation (claims = {}),
    # so it is not judged and decides no exit code (issue 29: simulate judges by claims)
    assert doc["satisfied"] is False and code == 0
    assert doc["claims"]["formation"] is None and "formation" not in doc["judged"]
    assert doc["metrics"]["cells"] == 9 and set(doc["metrics"]) == {"cells", "occupied", "off_shape"}
    code, out, _ = cli("simulate", "example-gather", "--shape", "square-9", "--range", "1.2",
                       "--robots", "9", "--seed", "1")
    assert "  satisfies shape: violated* - " in out and "  cells: 9" in out
    assert out.rstrip().endswith("result: ok (findings, not claimed: formation, connectivity)")


@pytest.mark.parametrize("argv, match", [
    (["--target", "nope"], r"nope: no such file and no bundled target of that name"),
    (["--shape", "square"], r"no bundled shape target of that name"),
    (["--pattern", "x"], r"x: no such file and no bundled pattern target of that name.*rhombus-triangles"),
])
def test_simulate_bad_targets_exit_2_naming_what(cli, argv, match):
    code, out, err = cli("simulate", "example-gather", *argv, "--robots", "3", "--seed", "0")
    assert code == 2 and out == ""
    import re
    assert re.search(match, err), err


def test_explore_on_a_users_lattice_file_writes_a_counterexample_that_replays_without_it(cli, tmp_path):
    path = tmp_path / "my-ring.yaml"
    shutil.copy(library._folder() / "hexagon-ring.yaml", path)
    code, out, _ = cli("explore", "song2014", "--lattice", str(path), "--property", "tree_links",
                       "--max-examples", "30", "--robots", "3..6", "--seed", "0", "--budget", "none",
                       "--out", str(tmp_path / "cx"), "--json")
    doc = json.loads(out)
    assert code == 1 and doc["lattices"] == [str(path)]
    cx_path = doc["properties"]["tree_links"]["counterexample"]
    cx = json.loads(open(cx_path).read())
    assert cx["target"]["kind"] == "lattice" and cx["target"]["document"]["format"] == "lattice-graph/1"
    path.unlink()                                      # the file carries the whole lattice
    code, out, _ = cli("replay", cx_path, "--json")
    assert code == 1 and json.loads(out)["reproduced"] is True


def test_simulate_on_a_target_without_a_range_asks_for_one(cli, tmp_path):
    f = tmp_path / "mine.json"
    f.write_text(json.dumps(GoalSet.from_bitmap("mine", ["##"]).describe()))
    code, out, err = cli("simulate", "example-gather", "--shape", str(f), "--robots", "3", "--seed", "0")
    assert code == 2 and "shape 'mine' has no default range; fix: pass --range PHI" in err
