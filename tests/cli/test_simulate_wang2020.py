"""`swarmproof simulate wang2020`: the shape scaled to --robots, the arena start, 004's metrics, and
the bad inputs that exit 2 (issue 15; 004 = Wang & Rubenstein 2020)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from swarmproof.cli import main
from swarmproof.models.shapes import shape_for
from swarmproof.models.trace import Trace

METRICS = {"J1", "J2", "optimal_distance", "distance_ratio", "constraint_violations"}


def run(capsys, *argv):
    code = main(["simulate", "wang2020", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_json_trace_and_plot_with_the_shape_scaled_to_the_robots(capsys, tmp_path):
    code, out, _ = run(capsys, "--shape", "letter-l", "--robots", "8", "--seed", "0", "--json",
                       "--trace", str(tmp_path / "t.npz"), "--plot", str(tmp_path / "p.png"))
    doc = json.loads(out)
    assert code == 0, doc
    assert {"satisfied", "min_separation", "total_distance", "metrics", "target"} <= set(doc)
    m = doc["metrics"]
    assert METRICS <= set(m)
    assert doc["satisfied"] is True and doc["robots"] == 8 and m["cells"] == 8     # letter-l (5) scaled to 8
    assert m["J1"] == 0 and m["J2"] == 0 and m["constraint_violations"] == 0
    # every agent walks at least its Manhattan distance to its final goal: the optimum is a lower bound
    assert m["optimal_distance"] > 0 and m["distance_ratio"] >= 1.0
    assert doc["total_distance"] == pytest.approx(m["distance_ratio"] * m["optimal_distance"])
    assert doc["min_separation"] >= 0.2 - 1e-9                      # 004 Theorems IV-A.1/2: l apart at rest
    t = Trace.load(doc["trace"])
    assert t.steps == doc["steps"] and t.n == 8
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the start: distinct waypoints (not the connected start of other grid algorithms), seeded
    cells = {tuple(c) for c in np.rint(t.poses[0][:, :2] / 0.2).astype(int).tolist()}
    assert len(cells) == 8


def test_the_start_is_the_seeded_arena_start():
    from swarmproof.models.shapes import centered_arena
    from swarmproof.models.targets import resolve_target
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020, default_params

    g = Wang2020.scale_target(resolve_target("shape:letter-l"), 30)
    a = Wang2020().initial(30, 4, default_params(), g)
    b = Wang2020().initial(30, 4, default_params(), g)
    c = Wang2020().initial(30, 5, default_params(), g)
    assert np.array_equal(a.poses, b.poses) and not np.array_equal(a.poses, c.poses)
    arena = centered_arena(g.cells, 32)
    cells = [tuple(x) for x in np.rint(a.poses[:, :2] / 0.2).astype(int).tolist()]
    assert len(set(cells)) == 30 and set(cells) <= arena


def test_scaled_target_equals_shape_for(tmp_path):
    from swarmproof.models.targets import resolve_target
    from swarmproof.reference_impl.wang2020.algorithm import Wang2020

    p = tmp_path / "t.txt"
    p.write_text("###\n.#.\n.#.\n")
    for text, name in ((str(p), str(p)), ("shape:letter-n", "letter-n"), ("shape:square-9", "square-9")):
        for n in (9, 40):
            assert Wang2020.scale_target(resolve_target(text), n).cells == shape_for(name, n).cells
    sq = resolve_target("shape:square-9")
    assert Wang2020.scale_target(sq, 9) is sq                    # kept as bundled at its own size


@pytest.mark.parametrize("suffix", ["txt", "png"])
def test_shape_files(capsys, tmp_path, suffix):
    path = tmp_path / f"bar.{suffix}"
    if suffix == "txt":
        path.write_text("##\n##\n##\n")
    else:
        from PIL import Image

        a = np.full((6, 6), 255, np.uint8)
        a[1:5, 2:4] = 0
        Image.fromarray(a).save(path)
    code, out, _ = run(capsys, "--shape", str(path), "--robots", "6", "--seed", "0", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["satisfied"] is True and doc["metrics"]["cells"] == 6
    assert doc["target"] == {"kind": "shape", "name": "bar"}


def test_finding_the_run_ends_with_a_robot_off_the_shape(capsys, tmp_path):
    """A finding (docs/wang2020.md, "False completion"; the explorer's 3-robot counterexample, seed
    0): three agents in a row below letter-l's goals end the run (every agent takes the shape as
    complete, Sec. III-B) with one of them still off the shape.  (Until 0.3.0 the example was a row
    of four, which the default's handshake now forms; an earlier 6-robot example on a 2 x 3 bar
    came from robots exactly R apart not hearing each other -- a rounding error fixed in the
    engine: that bar now forms.)"""
    import json as _json

    init = tmp_path / "row.json"
    init.write_text(_json.dumps({"format": "swarmproof-initial/1", "angle_unit": "rad", "robots": [
        {"id": k, "pose": [x, -0.2, 0.0]} for k, x in ((1, -0.2), (2, 0.0), (0, 0.2))]}))
    code, out, _ = run(capsys, "--shape", "letter-l", "--initial", str(init), "--seed", "0", "--json")
    doc = json.loads(out)
    assert code == 1 and doc["status"] == "finished" and doc["satisfied"] is False
    assert "is on no goal cell" in doc["satisfaction"]["message"]
    # the run ended by Sec. III-B's detection with a goal free: completion_sound names it (claimed)
    assert doc["completion_sound"]["status"] == "violated" and doc["completion_sound"]["witness"]["step"] == 31
    code, out, _ = run(capsys, "--shape", "letter-l", "--initial", str(init), "--seed", "0")
    assert code == 1 and ("  completion detection: violated - completion_sound (Wang & Rubenstein 2020, Sec. III-B) "
                          "broke in step 31: robots 1, 2, 0 declared shape 0 complete in step 31 (hop-count 4 > "
                          "|A| = 3) while 1 of its 3 goals held no agent at rest: (0, 1) (robot 2's goal); robot 1 "
                          "at rest on (0, -1), off the shape") in out.splitlines()


def _disconnected(tmp_path):
    p = tmp_path / "two.txt"
    p.write_text("##..\n##.#\n")
    return [str(p)]


def _blank_png(tmp_path):
    from PIL import Image

    p = tmp_path / "blank.png"
    Image.fromarray(np.full((5, 5), 255, np.uint8)).save(p)
    return [str(p)]


BAD = [
    (lambda tp: ["--shape", *_disconnected(tp), "--robots", "6"],
     r"two\.txt: the shape is not connected: 2 separate parts .*; fix: join the parts"),
    (lambda tp: ["--shape", *_blank_png(tp), "--robots", "6"],
     r"blank\.png: the shape has no dark pixel .*there is no goal cell; fix: draw the shape"),
    (lambda tp: ["--shape", "letter-n", "--robots", "1025"],
     r"n=1025 robots is more than the arena=32x32 holds \(1024 free cells\); fix: give at most 1024 robots "
     r"\(--robots\), or a larger arena \(--param arena="),
    (lambda tp: ["--shape", "letter-l", "--robots", "10", "--param", "arena=3"],
     r"n=10 robots is more than the arena=3x3 holds"),
    (lambda tp: ["--shape", "letter-l", "--robots", "5", "--param", "grid_spacing=0.05"],
     r"assumption 'grid_spacing_bounds' broken: grid_spacing=0.05 is outside .*; fix: "),
    (lambda tp: ["--shape", "letter-l", "--robots", "5", "--param", "delta_t=1"],
     r"assumption 'message_window' broken: delta_t=1.0 < 2/f_comm \* f_max/f_min \* m = 4 \(broadcast_every=2.0, "
     r"loss_repeats=1"),
    (lambda tp: ["--shape", "letter-l", "--robots", "5", "--param", "arena=big"],
     r"arena='big' is not an arena size; fix: give --param arena=SIDE"),
    (lambda tp: ["--shape", "letter-l", "--robots", "5", "--min-separation", "0.5"],
     r"min_separation=0.5 \(--min-separation\) is not used: algorithm 'wang2020' draws its own start \(its "
     r"initial hook: distinct grid waypoints, at least grid_spacing=0.2 apart\); fix: drop --min-separation "
     r"\(a sparser start: a larger arena, --param arena=SIDE\), or give the poses yourself \(--initial FILE\)"),
    (lambda tp: ["--shape", "letter-n", "--then", "letter-v", "--robots", "8"],
     r"then='letter-v': no such file and no bundled shape target of that name; did you mean 'letter-u'\?"
     r".*; fix: give a file path or one of the bundled shape names"),
    (lambda tp: ["--shape", "letter-n", "--then", "lines:wedge", "--robots", "8"],
     r"then='lines:wedge' is a lines target, not a shape; fix: wang2020 forms goal sets"),
    (lambda tp: ["--shape", "letter-n", "--then", *_disconnected(tp), "--robots", "8"],
     r"two\.txt': the shape is not connected"),
]


@pytest.mark.parametrize("argv, match", BAD, ids=["disconnected-txt", "png-no-filled-cell", "more-than-arena",
                                                  "more-than-small-arena", "grid-spacing-too-small",
                                                  "window-below-bound", "bad-arena", "min-separation",
                                                  "then-unknown-shape",
                                                  "then-not-a-shape", "then-disconnected-txt"])
def test_bad_input_exits_2_naming_the_value_and_the_fix(capsys, tmp_path, argv, match):
    code, out, _ = run(capsys, *argv(tmp_path), "--seed", "0", "--json")
    doc = json.loads(out)
    assert code == 2 and doc["exit_code"] == 2
    assert re.search(match, doc["error"]["message"]), doc["error"]["message"]


def test_vectorised_gives_the_same_json_and_trace(capsys, tmp_path):
    """--vectorised (reference_impl/wang2020/fast.py): the same report and the same trace file as the
    per-robot reference; the JSON says it ran vectorised."""
    docs, traces = [], []
    for flag in ((), ("--vectorised",)):
        t = tmp_path / f"t{len(flag)}.json"
        code, out, _ = run(capsys, "--shape", "letter-n", "--robots", "8", "--seed", "3", "--json",
                           "--trace", str(t), *flag)
        assert code == 0, out
        docs.append(json.loads(out))
        traces.append(t.read_bytes())
    ref, fast = docs
    assert fast.pop("vectorised") is True and "vectorised" not in ref
    ref.pop("trace"), fast.pop("trace")
    assert fast == ref and ref["steps"] > 100
    assert traces[0] == traces[1]


@pytest.mark.parametrize("argv,needle", [
    (["simulate", "song2016", "--lattice", "square", "--robots", "4", "--seed", "0", "--vectorised"],
     "algorithm 'song2016' has no vectorised path"),
    (["simulate", "wang2020", "--shape", "letter-l", "--robots", "5", "--seed", "0", "--vectorised",
      "--param", "clock_rate_min=0.5", "--allow-violations"], "clock_rate_min=0.5"),
])
def test_vectorised_refuses_what_it_does_not_cover(capsys, argv, needle):
    code = main(argv)
    _, err = capsys.readouterr()
    assert code == 2 and needle in err and "drop --vectorised" in err and "Traceback" not in err


@pytest.mark.parametrize("flag", [(), ("--vectorised",)])
def test_a_lattice_target_is_a_usage_error_not_a_crash(capsys, flag):
    """wang2020 forms goal sets: a lattice target exits 2 naming it (it crashed with exit 4 when the
    arena start read the target's cells before the controller's check)."""
    code = main(["simulate", "wang2020", "--lattice", "square", "--robots", "8", "--seed", "0", *flag])
    _, err = capsys.readouterr()
    assert code == 2 and "target='square' (lattice)" in err and "shape:letter-l" in err


def test_termination_names_the_last_step_of_a_sparse_trace(capsys):
    """--record-every K keeps every K-th step: termination still says after how many steps the run
    ended (it said the number of recorded frames)."""
    msgs = []
    for k in ("1", "5"):
        code, out, _ = run(capsys, "--shape", "letter-l", "--robots", "6", "--seed", "0", "--json", "--record-every", k)
        doc = json.loads(out)
        msgs.append(doc["termination"]["message"])
        assert f"after {doc['steps']} steps" in doc["termination"]["message"] and doc["steps"] > 100
    assert msgs[0] == msgs[1]


def test_the_trace_of_8_agents_is_about_a_megabyte_not_five(capsys, tmp_path):
    """The review of issue 15 found an 8-agent dense trace of 5 MB: the indented JSON, not what it
    holds (docs/performance.md, "Trace size"). Every state of every step is still there."""
    path = tmp_path / "t.json"
    code, out, _ = run(capsys, "--target", "shape:letter-l", "--robots", "8", "--seed", "0", "--json",
                       "--trace", str(path))
    doc = json.loads(out)
    assert code == 0 and doc["steps"] == 444
    assert path.stat().st_size < 1_300_000                       # 5,054,476 bytes indented, 1,140,219 now
    t = Trace.load(path)
    assert t.frames == 445 and len(t.states) == 445 and dict(t.states[-1][0])["done"]


def test_then_forms_n_then_u_from_the_command_line(capsys, tmp_path):
    """004 Fig. 9's "N" then "U" (issue 15 review): ``--then`` becomes ``params.extra["then"]``, the
    next shape is scaled to the team, and the run is judged on the last shape. The trace shows both
    formed: every goal of N held when the first agent detects it complete, every goal of U at the
    end, every agent's ``completed`` 2."""
    code, out, _ = run(capsys, "--target", "shape:letter-n", "--then", "shape:letter-u", "--robots", "8",
                       "--seed", "0", "--json", "--trace", str(tmp_path / "t.json"))
    doc = json.loads(out)
    assert code == 0 and doc["status"] == "finished" and doc["satisfied"] is True, doc
    assert doc["target"]["name"] == "letter-n" and doc["target"]["judged_as"]["name"] == "letter-u"
    t = Trace.load(doc["trace"])
    assert t.meta["params"]["extra"]["then"] == "shape:letter-u"
    n_cells, u_cells = (set(map(tuple, shape_for(s, 8).cells)) for s in ("letter-n", "letter-u"))
    assert n_cells != u_cells

    def held(i):
        xy = t.poses[i][:, :2] / 0.2
        return {tuple(c) for c in np.rint(xy).astype(int).tolist()} if np.allclose(xy, np.rint(xy)) else set()

    completed = [[dict(s)["completed"] for s in row] for row in t.states]
    first = next(i for i, row in enumerate(completed) if max(row) >= 1)
    assert n_cells <= held(first) and held(t.frames - 1) == u_cells and completed[-1] == [2] * 8
    # the optimum is the two legs': start -> N, then N -> U (metres)
    assert doc["metrics"]["distance_ratio"] >= 1.0


def test_then_runs_on_the_vectorised_path_and_in_the_help(capsys, tmp_path):
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    for path, extra in ((a, ()), (b, ("--vectorised",))):
        code, _, _ = run(capsys, "--shape", "letter-n", "--then", "letter-u", "--robots", "6", "--seed", "1",
                         "--trace", str(path), *extra)
        assert code == 0
    assert a.read_bytes() == b.read_bytes()
    capsys.readouterr()
    assert main(["simulate", "--help"]) == 0
    assert "--target shape:letter-n --then shape:letter-u" in " ".join(capsys.readouterr().out.split())
