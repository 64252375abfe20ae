"""What a new user's review of check-run found (issue 34), each pinned: the last sample judged,
each robot stale by its own rate, a slow drift is motion and noise is not, two time bases refused,
the instant a violation shows, the manifest checked at its line, names unique across folders."""

from __future__ import annotations

import pytest

import logkit as lk
from swarmproof.checkers.gate import verify
from swarmproof.models.errors import InputFileError, UsageError


def _csv(tmp_path, rows, name="run.csv", header=("t", "id", "x", "y", "theta")):
    return lk.write_csv(tmp_path / name, rows, header)


def test_a_split_in_the_last_sample_is_judged(tmp_path, check_run):
    rows = [(k, i, float(i), 0.0, 0.0) for k in range(11) for i in range(3)] + [(10.6, 2, 5.0, 0.0, 0.0)]
    code, doc, _ = check_run(_csv(tmp_path, rows), "--range", "1.5", "--property", "connectivity")
    w = doc["properties"]["connectivity"]["witness"]
    assert code == 1 and (w["instant"], w["time_s"]) == (11, 11.0)
    assert doc["clock"]["end_s"] == 11.0          # the first instant at or after the last sample


def test_samples_between_instants_are_counted_in_the_notes(tmp_path, check_run):
    rows = [(k, i, float(i), 0.0, 0.0) for k in range(4) for i in range(2)] + [(2.3, 1, 5.0, 0.0, 0.0),
                                                                               (2.6, 1, 1.0, 0.0, 0.0)]
    rows.sort()
    code, doc, _ = check_run(_csv(tmp_path, rows), "--range", "1.5", "--period", "1", "--property", "connectivity")
    assert code == 0 and any("2 pose samples fall between the clock's instants" in n for n in doc["notes"])
    code, doc, _ = check_run(_csv(tmp_path, rows, "b.csv"), "--range", "1.5", "--period", "0.1",
                             "--stale", "2", "--property", "connectivity")
    assert code == 1 and doc["properties"]["connectivity"]["witness"]["time_s"] == pytest.approx(2.3)


def test_a_slow_robot_among_fast_ones_is_judged_by_its_own_rate(tmp_path, check_run):
    rows = [(round(k * 0.02, 4), i, float(i), 0.0, 0.0) for k in range(250) for i in range(3)]
    rows += [(round(k * 0.2, 4), 3, 3.0, 0.0, 0.0) for k in range(26)]
    rows.sort()
    code, doc, _ = check_run(_csv(tmp_path, rows), "--range", "1.5", "--property", "connectivity")
    c = doc["clock"]
    assert code == 0 and c["judged_instants"] == c["instants"] and c["period_s"] == 0.02
    assert (c["stale_min_s"], c["stale_s"]) == (0.05, 0.5)


@pytest.mark.parametrize("step, want", [(0.025, "inconclusive"), (0.0, "held")])
def test_a_slow_drift_is_motion_and_noise_within_the_tolerance_is_not(tmp_path, check_run, step, want):
    """A robot creeping 2.5 cm per 0.1 s under --pos-tol 0.02 moves (each step is under 2D = 4 cm, the
    drift is not); robots that stand still with 1.9 cm of noise are at rest."""
    import numpy as np

    rng = np.random.default_rng(0)
    rows = [(round(k * 0.1, 3), i, i + (k * step if i == 1 else 0.0) + rng.uniform(-0.019, 0.019), 0.0, 0.0)
            for k in range(100) for i in range(2)]
    code, doc, _ = check_run(_csv(tmp_path, rows), "--range", "50", "--pos-tol", "0.02", "--property", "termination")
    assert doc["properties"]["termination"]["status"] == want, doc["properties"]["termination"]["message"]


def test_header_stamps_and_log_times_that_never_meet_are_refused(tmp_path, cli):
    msgs = []
    for k in range(20):
        t = k / 10
        for rid in range(2):
            m = lk.pose(rid, 100 + t, float(rid), 0.0)          # simulated time in the header
            m.log_ns = lk.ns(1.7e9 + t)                          # the recorder's wall clock
            msgs.append(m)
            msgs.append(lk.Msg(f"/robot_{rid}/parent", lk.INT32, lk.ns(1.7e9 + t), {"data": -1 if rid == 0 else 0}))
    path = lk.write("mcap", tmp_path / "simtime", msgs)
    code, out, err = cli("check-run", path, "--range", "1.5")
    assert code == 2 and "two bases" in err and "--time log" in err and "Traceback" not in err
    code, out, err = cli("check-run", path, "--range", "1.5", "--time", "log", "--property", "tree_links")
    assert code == 0, err


def test_a_collision_shows_at_its_instant_and_the_picture_draws_it(tmp_path, check_run):
    rows = [(k, 0, 0.0, 0.0, 0.0) for k in range(4)] + [(k, 1, 3.0 - k, 0.0, 0.0) for k in range(4)]
    rows.sort()
    code, doc, _ = check_run(_csv(tmp_path, rows), "--range", "5", "--radius", "0.3", "--property", "collision",
                             "--plot", str(tmp_path / "c.png"))
    w = doc["properties"]["collision"]["witness"]
    # 1.0 apart at 2 s, 0.0 at 3 s: the monitor names step 2 and where in it the pair is closest (its
    # end): shown at 3 s, instant 3 -- the instant the picture draws
    assert code == 1 and w["step"] == 2 and w["fraction"] == 1.0 and (w["instant"], w["time_s"]) == (3, 3.0)
    assert (tmp_path / "c.png").stat().st_size > 0


def test_bad_numbers_of_the_command_line_are_usage_errors(tmp_path, check_run):
    path = _csv(tmp_path, [(k, i, float(i), 0.0, 0.0) for k in range(3) for i in range(2)])
    for args in (("--radius", "0"), ("--static-window", "-1"), ("--v", "-1")):
        code, doc, err = check_run(path, "--range", "1.5", *args)
        assert code == 2 and args[0] in err and "exit_code" in doc and "properties" not in doc   # the error document


def _manifest(folder, body):
    folder.mkdir(exist_ok=True)
    (folder / "recorded-runs.yaml").write_text("format: swarmproof-recorded-runs/1\nruns:\n" + body)
    lk.write_csv(folder / "a.csv", [(k, i, float(i), 0.0, 0.0) for k in range(3) for i in range(2)])
    return str(folder)


@pytest.mark.parametrize("body, match", [
    ("  - {log: a.csv, range: 1.5, claims: [connectivty]}\n", r"runs\[0\].claims\[0\].*connectivty"),
    ("  - {log: a.csv, range: 1.5, properties: [connectivity], claims: [collision]}\n",
     r"claims entry 'collision' is not among the run's properties"),
    ("  - {log: a.csv, target: lattice:nosuch}\n", r"runs\[0\].target"),
    ("  - {log: a.csv, range: 1.5, algorithm: nosuch}\n", r"runs\[0\].algorithm"),
])
def test_the_manifest_names_are_checked_at_their_line(tmp_path, body, match):
    folder = _manifest(tmp_path / "logs", body)
    with pytest.raises(InputFileError, match=match) as e:
        verify(sections=["recorded"], recorded=[folder])
    assert e.value.file.endswith("recorded-runs.yaml") and e.value.line == 3


def test_a_run_name_in_two_folders_is_refused(tmp_path):
    a = _manifest(tmp_path / "a", "  - {log: a.csv, range: 1.5, name: night}\n")
    b = _manifest(tmp_path / "b", "  - {log: a.csv, range: 1.5, name: night}\n")
    with pytest.raises(UsageError, match="run name='night' is in"):
        verify(sections=["recorded"], recorded=[a, b])


@pytest.mark.parametrize("make, match", [(lambda p: str(p / "nodir"), "does not exist"),
                                         (lambda p: lk.write_csv(p / "x.csv", [(0, 0, 0.0, 0.0, 0.0)]),
                                          "is a file, not a folder of logs")])
def test_recorded_paths_that_are_not_folders(tmp_path, make, match):
    with pytest.raises(InputFileError, match=match):
        verify(sections=["recorded"], recorded=[make(tmp_path)])


def test_ids_written_as_floats_with_nothing_after_the_point(tmp_path, check_run):
    path = lk.write_csv(tmp_path / "f.csv", [(k, f"{i}.0", float(i), 0.0, 0.0, "" if i == 0 else "0.0")
                                             for k in range(3) for i in range(2)],
                        ("t", "id", "x", "y", "theta", "parent"))
    code, doc, _ = check_run(path, "--range", "1.5", "--property", "tree_links")
    assert code == 0 and doc["ids"] == [0, 1]
    bad = lk.write_csv(tmp_path / "g.csv", [(0, "1.5", 0.0, 0.0, 0.0)])
    code, doc, err = check_run(bad, "--range", "1.5")
    assert code == 2 and "id='1.5' is not an integer" in err


def test_no_topic_match_guesses_the_pattern_from_the_log(tmp_path, cli):
    msgs = [lk.pose(r, k / 10, float(r), 0.0, topic=f"/tb3_{r}/pose_stamped") for k in range(5) for r in range(2)]
    path = lk.write("mcap", tmp_path / "tb3", msgs)
    code, _, err = cli("check-run", path, "--range", "1.5")
    assert code == 2 and "--topics '/tb3_{id}/pose_stamped' fits this log" in err
    code, _, err = cli("check-run", path, "--range", "1.5", "--topics", "/tb3_{id}/pose_stamped",
                       "--property", "connectivity")
    assert code == 0, err
