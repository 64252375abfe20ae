"""verify's ``recorded`` section (issue 34): a folder of logs and its manifest as rows of the gate."""

from __future__ import annotations

import json

import pytest

from swarmproof.checkers.gate import verify
from swarmproof.cli import main
from swarmproof.models.errors import InputFileError
from swarmproof.models.recorded_runs import load_recorded_runs, loads_recorded_runs

SPLIT = "t,id,x,y,theta,parent\n" + "".join(
    f"{k / 2},{i},{x},0.0,0.0,{'' if i == 0 else i - 1}\n"
    for k in range(4) for i, x in enumerate((0.0, 1.0, 2.0 + 0.2 * k)))


def _folder(tmp_path, runs: str, files=None):
    (tmp_path / "recorded-runs.yaml").write_text("format: swarmproof-recorded-runs/1\nruns:\n" + runs)
    for name, text in (files or {"lab.csv": SPLIT}).items():
        (tmp_path / name).write_text(text)
    return str(tmp_path)


def test_a_folder_of_logs_is_rows_of_the_gate(tmp_path):
    folder = _folder(tmp_path, "  - {log: lab.csv, range: 1.5, properties: [connectivity, collision, tree_links], "
                               "claims: [connectivity, tree_links]}\n")
    rep = verify(sections=["recorded"], recorded=[folder])
    rows = {r.property: r for r in rep.rows}
    assert set(rows) == {"connectivity", "collision", "tree_links"}
    assert all(r.subject == "recorded lab.csv" and r.section == "recorded" for r in rep.rows)
    assert rows["connectivity"].verdict.value == "violated"
    assert rows["connectivity"].data["violation"]["time_s"] == 1.5
    assert rows["collision"].verdict.value == "held" and rows["collision"].claim is None   # not in claims
    assert rows["connectivity"].claim and rows["tree_links"].claim
    assert "swarmproof check-run" in rows["connectivity"].data["reproduce"]


def test_the_baseline_keeps_a_known_split_green_and_a_change_fails(tmp_path):
    logs = tmp_path / "logs"
    logs.mkdir()
    folder = _folder(logs, "  - {log: lab.csv, range: 1.5, properties: [connectivity]}\n")
    base = str(tmp_path / "base.json")
    assert main(["verify", "--section", "recorded", "--recorded", folder, "--baseline", base,
                 "--update-baseline"]) == 0
    assert main(["verify", "--section", "recorded", "--recorded", folder, "--baseline", base]) == 0   # known
    # robot 2 now stays in range: the row changes, and --strict fails an improvement too
    assert ",2.6," in SPLIT
    (logs / "lab.csv").write_text(SPLIT.replace(",2.6,", ",2.4,"))
    assert main(["verify", "--section", "recorded", "--recorded", folder, "--baseline", base]) == 0
    assert main(["verify", "--section", "recorded", "--recorded", folder, "--baseline", base, "--strict"]) == 1


def test_the_bundled_runs_are_verify_rows():
    rep = verify(sections=["recorded"])
    got = {(r.subject, r.property): r.verdict.value for r in rep.rows}
    assert got[("recorded eight-robots-split", "connectivity")] == "violated"
    assert got[("recorded eight-robots-split", "collision")] == "held"
    assert got[("recorded song2016-square", "formation")] == "held"
    assert got[("recorded song2016-square", "tree_links")] == "held"


@pytest.mark.parametrize("runs, match", [
    ("  - {log: a.csv}\n", r"runs\[0\].*gives no range"),
    ("  - {log: a.csv, range: -1}\n", r"field 'runs\[0\].range': runs\[0\].range=-1 must be a finite positive"),
    ("  - {log: a.csv, range: 1, tme: log}\n", r"key 'tme' is not known here; did you mean 'time'\?"),
    ("  - {log: a.csv, range: 1}\n  - {log: b/a.csv, range: 1}\n", r"name='a.csv' is the name of runs\[0\] too"),
    ("  - {log: a.csv, range: 1, time: gps}\n", r"must be header or log"),
])
def test_a_bad_manifest_names_its_line_and_field(runs, match):
    with pytest.raises(InputFileError, match=match) as e:
        loads_recorded_runs("format: swarmproof-recorded-runs/1\nruns:\n" + runs, "m.yaml")
    assert e.value.line is not None and str(e.value).startswith("m.yaml:")


def test_a_folder_without_a_manifest_is_exit_2_before_any_row(tmp_path, capsys):
    assert main(["verify", "--recorded", str(tmp_path), "--section", "recorded"]) == 2
    err = capsys.readouterr().err
    assert "recorded-runs.yaml" in err and "fix:" in err and "Traceback" not in err
    with pytest.raises(InputFileError, match="has no recorded-runs.yaml"):
        load_recorded_runs(tmp_path)


def test_recorded_rows_in_json(tmp_path, capsys):
    folder = _folder(tmp_path, "  - {log: lab.csv, name: lab, range: 1.5, properties: [connectivity]}\n")
    main(["verify", "--section", "recorded", "--recorded", folder, "--json"])
    doc = json.loads(capsys.readouterr().out)
    row = next(r for r in doc["rows"] if r["section"] == "recorded")
    assert row["subject"] == "recorded lab" and row["verdict"] == "violated"
