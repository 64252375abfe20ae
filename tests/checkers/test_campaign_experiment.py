"""Campaigns' ``experiment:`` cells (issue 30): a paper experiment's seeded trials on Dask, with the
figures of the experiment function called directly, resumable; the experiment's options and team
sizes checked before anything runs (located errors, exit 2, nothing written); the verdict
``measured`` counted apart; the report's table by team size."""

from __future__ import annotations

import json
import os
import sqlite3

import pytest

from swarmproof.checkers.campaign import CampaignResult, Task, check_figures, plan_tasks
from swarmproof.cli import main
from swarmproof.models.campaign_spec import loads_campaign
from swarmproof.models.errors import UsageError

TINY = """\
format: swarmproof-campaign/1
name: tiny-fig10
experiment:
  - algorithm: wang2020
    experiment: fig10
    robots: [16]
    seeds: [0, 1]
    options: {arena: 32}
"""


def _table(out_dir) -> list[tuple]:
    con = sqlite3.connect(os.path.join(out_dir, "results.sqlite"))
    try:
        return list(con.execute("SELECT task, cell, kind, verdict, figures, counterexample FROM results ORDER BY task"))
    finally:
        con.close()


def test_tasks_are_keyed_by_size_and_seed_with_the_options_completed():
    spec = loads_campaign(TINY.replace("    options: {arena: 32}\n", ""))
    tasks = plan_tasks(spec)
    assert [t.key for t in tasks] == ["experiment[0]/fig10/n16/seed0", "experiment[0]/fig10/n16/seed1"]
    assert tasks[0].args == {"algorithm": "wang2020", "experiment": "fig10", "robots": 16, "seed": 0,
                             "function": "swarmproof.reference_impl.wang2020.experiments:fig10_task",
                             "options": {"arena": 32}}
    assert tasks[0].cell == "experiment[0] wang2020 fig10" and tasks[0].kind == "experiment"


def test_an_experiment_task_as_a_worker_runs_it_is_the_function_called_directly():
    """What a worker runs for a trial (run_task): verdict measured, the function's figures exactly
    (as the store keeps them, through JSON), and the task's seconds apart for the timings table."""
    from swarmproof.checkers.campaign import run_task
    from swarmproof.reference_impl.wang2020.experiments import fig10_task

    task = plan_tasks(loads_campaign(TINY))[1]
    out = run_task(task.as_dict())
    assert out["verdict"] == "measured" and out["counterexample"] is None
    assert json.loads(json.dumps(out["figures"])) == fig10_task(16, 1, arena=32)
    assert out["seconds"] > 0 and "seconds" not in out["figures"]


# slow by nature: a 1-process embedded cluster twice (the run, then --resume) and two direct trials
# (21 s CPU measured with its children, load 4); the default suite keeps the experiment task as a
# worker runs it (test_an_experiment_task_as_a_worker_runs_it_is_the_function_called_directly), the
# report and exit codes of measured trials (below), and the Dask run with --json, report and --resume
# (tests/checkers/test_campaign.py::test_two_workers_json_report_and_resume).
@pytest.mark.slow
def test_a_tiny_fig10_campaign_on_one_worker_is_the_function_called_directly_and_resumes(tmp_path, capsys):
    """Two 16-agent trials on a 1-process embedded cluster: the stored figures are fig10_task's,
    exit 0 (every trial measured), no wall-clock figure in --json or report.md; a campaign cut
    short (one row gone) resumes only the missing trial and ends with the same table."""
    from swarmproof.reference_impl.wang2020.experiments import fig10_task

    spec = tmp_path / "tiny.yaml"
    spec.write_text(TINY)
    out = str(tmp_path / "out")
    assert main(["campaign", str(spec), "--out", out, "--workers", "1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    rows = _table(out)
    assert [r[0] for r in rows] == ["experiment[0]/fig10/n16/seed0", "experiment[0]/fig10/n16/seed1"]
    for (_, cell, kind, verdict, figures, cx), seed in zip(rows, (0, 1)):
        assert (cell, kind, verdict, cx) == ("experiment[0] wang2020 fig10 arena=32", "experiment", "measured", None)
        assert json.loads(figures) == fig10_task(16, seed, arena=32)
    (cell,) = doc["cells"]
    assert cell["verdict"] == "measured" and cell["counts"] == {"held": 0, "violated": 0, "inconclusive": 0,
                                                                 "n/a": 0, "measured": 2}
    assert doc["exit_code"] == 0 and "seconds" not in json.dumps(doc) and "cpu" not in json.dumps(doc)
    report = open(os.path.join(out, "report.md"), encoding="utf-8").read()
    assert "| experiment[0] wang2020 fig10 arena=32 | measured | 2/2 | 0 | 0 | 0 | 0 | 2 |" in report
    assert "| robots | trials | formed | formed (s) | centralized (s) | distance ratio | random-assignment ratio |" in report
    assert "| 16 | 2 | 2/2 |" in report and "seconds" not in report.split("Seconds of tasks")[0]
    assert os.path.getsize(os.path.join(out, "plots", "experiment-0.png")) > 0
    con = sqlite3.connect(os.path.join(out, "results.sqlite"))
    with con:
        assert [r[0] for r in con.execute("SELECT task FROM timings ORDER BY task")] == [r[0] for r in rows]
        con.execute("DELETE FROM results WHERE task = 'experiment[0]/fig10/n16/seed1'")
    con.close()
    assert main(["campaign", str(spec), "--out", out, "--workers", "1", "--resume"]) == 0
    assert "2/2 tasks finished, 1 run now" in capsys.readouterr().out
    assert _table(out) == rows


def _spec(tmp_path, cell: str) -> str:
    p = tmp_path / "spec.yaml"
    p.write_text("format: swarmproof-campaign/1\nname: bad\nexperiment:\n" + cell)
    return str(p)


BAD = [
    ("unknown-experiment", "  - algorithm: wang2020\n    experiment: fig11\n    robots: [16]\n",
     "experiment='fig11' is not an experiment of algorithm 'wang2020'", 5, "experiment[0].experiment",
     "use one of ['fig10']"),
    ("no-experiments", "  - algorithm: song2014\n    experiment: fig10\n    robots: [16]\n",
     "is not an experiment of algorithm 'song2014' (it declares none)", 5, "experiment[0].experiment",
     "use an algorithm that declares experiments"),
    ("inherited", "  - algorithm: wang2020-broadcast-handshake\n    experiment: fig10\n    robots: [16]\n",
     "is not an experiment of algorithm 'wang2020-broadcast-handshake' (it declares none)", 5,
     "experiment[0].experiment", "its base class declares ['fig10'], which run the base class's reading"),
    ("unknown-option", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [16]\n    options: {arnea: 40}\n",
     "option arnea=40 is not an option of this experiment; did you mean 'arena'?", 7, "experiment[0].options.arnea",
     "use only ['arena']"),
    ("option-range", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [16]\n    options:\n      arena: 0\n",
     "option arena=0 is outside its range [1, 1024]", 8, "experiment[0].options.arena",
     "give arena a value in [1, 1024]"),
    ("option-type", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [16]\n    options: {arena: 2.5}\n",
     "option arena=2.5 must be a whole number", 7, "experiment[0].options.arena", "give arena a value in [1, 1024]"),
    ("robots-range", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [16, 5000]\n    options: {arena: 128}\n",
     "robots=5000 is outside the team sizes it takes, 1..4096", 6, "experiment[0].robots[1]",
     "give team sizes in 1..4096"),
    ("robots-arena", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [16, 2000]\n",
     "robots=2000 is more than the arena=32x32 holds (1024 start cells)", 6, "experiment[0].robots[1]",
     "(options: {arena: 45})"),
    ("robots-form", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [0]\n",
     "experiment[0].robots[0]=0 must be an integer in 1..100000", 6, "experiment[0].robots[0]", "e.g. robots:"),
    ("robots-repeated", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [16, 16]\n",
     "repeats a team size", 6, "experiment[0].robots", "list each size once"),
    ("options-form", "  - algorithm: wang2020\n    experiment: fig10\n    robots: [16]\n    options: [32]\n",
     "experiment[0].options=[32] must be a mapping", 7, "experiment[0].options", "e.g. options: {arena: 32}"),
    ("no-name", "  - algorithm: wang2020\n    robots: [16]\n",
     "experiment[0].experiment=None must be the name of an experiment", 4, "experiment[0].experiment",
     "e.g. experiment: fig10"),
    ("unknown-key", "  - algorithm: wang2020\n    experiment: fig10\n    targets: [square]\n",
     "key 'targets' is not known here", 6, "experiment[0].targets", "use only ['algorithm', 'experiment'"),
]


@pytest.mark.parametrize("name, cell, match, line, fld, fix", BAD, ids=[b[0] for b in BAD])
def test_bad_experiment_cells_exit_2_located_with_nothing_written(tmp_path, capsys, name, cell, match, line, fld, fix):
    spec = _spec(tmp_path, cell)
    out = tmp_path / "out"
    assert main(["campaign", spec, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert match in err and f"spec.yaml:{line}:" in err and f"field '{fld}'" in err, err
    assert "fix: " in err and fix in err.split("fix: ", 1)[1], err
    assert "Traceback" not in err and not out.exists()


def _result(verdicts: dict, planned: int | None = None) -> CampaignResult:
    spec = loads_campaign(TINY)
    tasks = [Task(f"experiment[0]/fig10/n16/seed{k}", "cell", "experiment",
                  {"algorithm": "wang2020", "experiment": "fig10", "robots": 16, "seed": k})
             for k in range(planned or len(verdicts))]
    results = {tasks[k].key: {"verdict": v, "figures": f, "counterexample_path": None}
               for k, (v, f) in verdicts.items()}
    return CampaignResult(spec, tasks, results, out_dir="o")


def test_measured_is_counted_apart_and_exits_0_only_when_every_trial_ran():
    """docs/decisions.md, "Campaigns: experiment cells": a trial that ran is *measured* (no claim
    judged, never held); a campaign of measured trials exits 0 once all finished, 3 with one
    unfinished or failed (inconclusive); measured tasks beside n/a ones decide as held ones do."""
    from swarmproof.checkers.campaign_report import format_summary

    done = _result({0: ("measured", {}), 1: ("measured", {})})
    assert done.exit_code == 0 and done.cells()[0]["verdict"] == "measured"
    assert format_summary(done)[-1].startswith("campaign tiny-fig10: MEASURED: 2/2 tasks finished")
    assert "0 held, 0 violated, 0 inconclusive, 2 measured (experiment trials: no claim judged)" in format_summary(done)[0]
    assert _result({0: ("measured", {})}, planned=2).exit_code == 3
    failed = _result({0: ("measured", {}), 1: ("inconclusive", {"error": "RuntimeError: boom"})})
    assert failed.exit_code == 3 and failed.cells()[0]["verdict"] == "inconclusive"
    assert _result({0: ("measured", {}), 1: ("not_applicable", {})}).exit_code == 0
    assert _result({0: ("not_applicable", {})}).exit_code == 3


def test_the_report_table_is_the_experiment_s_declared_columns():
    from swarmproof.checkers.campaign_report import markdown

    figs = [{"formed_s": 100.0, "central_s": 90.0, "ratio": 1.25, "random_ratio": 1.5},
            {"formed_s": None, "central_s": 100.0, "ratio": 0.5, "random_ratio": 1.7},    # unformed: no ratio
            {"formed_s": 120.0, "central_s": 110.0, "ratio": 1.75, "random_ratio": 1.6}]
    md = markdown(_result({k: ("measured", f) for k, f in enumerate(figs)}))
    assert "| 16 | 3 | 2/3 | 110 | 100 | 1.5 (1.25-1.75) | 1.6 |" in md, md
    assert "*distance ratio* over the trials with `formed_s`" in md
    assert "No trial of this cell has finished yet." in markdown(_result({}, planned=1))


def test_the_report_shows_trials_that_failed_with_their_error():
    """A trial that raised is inconclusive: the table counts it apart (column failed) and the
    report lists it with its error, also when no trial of the cell was measured."""
    from swarmproof.checkers.campaign_report import markdown

    boom = {"error": "UsageError: width=32.0 must be int"}
    md = markdown(_result({0: ("measured", {"formed_s": 100.0, "central_s": 90.0, "ratio": 1.25, "random_ratio": 1.5}),
                           1: ("inconclusive", boom)}))
    assert "| robots | trials | failed |" in md and "| 16 | 1 | 1 |" in md, md
    assert "- `experiment[0]/fig10/n16/seed1`: UsageError: width=32.0 must be int" in md
    only_failed = markdown(_result({0: ("inconclusive", boom)}))
    assert "No trial of this cell has finished yet." not in only_failed
    assert "| 16 | 0 | 1 |" in only_failed and "1 trial(s) did not run to the end" in only_failed


def test_a_whole_number_option_written_as_a_float_is_the_whole_number():
    from swarmproof.checkers.campaign import experiment_options, resolve_experiment

    decl = resolve_experiment("wang2020", "fig10")[2]
    opts, bad, err = experiment_options(decl, {"arena": 32.0})
    assert (bad, err) == (None, None) and opts == {"arena": 32} and type(opts["arena"]) is int
    assert experiment_options(decl, {"arena": 32.5})[0] == {}


def test_a_variant_does_not_inherit_its_base_class_experiments_nor_is_told_to_declare_them():
    from swarmproof.checkers.campaign import resolve_experiment

    with pytest.raises(UsageError) as e:
        resolve_experiment("wang2020-broadcast-handshake", "fig10")
    assert "which run the base class's reading" in e.value.fix and "use the base class" in e.value.fix
    assert "declare experiments on this class" not in e.value.fix


@pytest.mark.parametrize("figures, match", [
    ([1, 2], "returned list, not a dict"),
    ({"x": [1]}, r"figure x=\[1\] is not a number"),
    ({"x": float("nan")}, "figure x=nan is not finite"),
], ids=["list", "nested", "nan"])
def test_figures_must_be_numbers_texts_or_none(figures, match):
    with pytest.raises((TypeError, ValueError), match=match):
        check_figures(figures)


def test_figures_accept_numpy_scalars_as_plain_numbers():
    import numpy as np

    out = check_figures({"a": np.float64(1.5), "b": np.int64(3), "c": None, "d": "stopped", "e": True})
    assert out == {"a": 1.5, "b": 3, "c": None, "d": "stopped", "e": True} and type(out["b"]) is int
