"""Issue 29, "run inputs validated up front" (defects 3, 4, 5, 10 and parts of 15): every run input
is checked before any run, by one code path, with the same message in simulate, explore and campaign;
exit 2 naming what was wrong, never a run on defaults, never "the algorithm crashed", never exit 4."""

from __future__ import annotations

import json

import pytest

SIM = ["--robots", "5", "--seed", "0", "--max-steps", "5"]
EXP = ["--max-examples", "2", "--max-steps", "5", "--budget", "none"]

BAD = [
    # 5: --param keys are checked for every algorithm, with the closest name and the known keys
    pytest.param(["simulate", "wang2020", "--shape", "letter-l", *SIM, "--param", "arnea=5"],
                 r"parameter arnea=5 is not known to algorithm 'wang2020'; did you mean 'arena'\?; "
                 r"fix: use one of its parameters \[.*'arena'", id="5-simulate-wang2020-misspelt"),
    pytest.param(["simulate", "song2014", "--lattice", "square", *SIM, "--param", "foo=1"],
                 r"parameter foo=1 is not known to algorithm 'song2014'; fix: use one of its parameters "
                 r"\['arrive_tol', 'heading_tol', 'robot_radius'\]", id="5-simulate-song2014-unknown"),
    pytest.param(["explore", "song2014", *EXP, "--param", "foo=5"],
                 r"parameter foo=5 is not known to algorithm 'song2014'", id="5-explore-song2014-unknown"),
    pytest.param(["simulate", "jiang", "--pattern", "square-dots", *SIM, "--param", "gap=1"],
                 r"parameter gap=1 is not known to algorithm 'jiang'", id="5-jiang-takes-none"),
    pytest.param(["simulate", "leechong-leader", "--pattern", "wedge", *SIM, "--param", "grid_spacing=1"],
                 r"parameter grid_spacing=1 is not known to algorithm 'leechong-leader'", id="5-engine-key-not-read"),
    pytest.param(["simulate", "wang2020", "--shape", "letter-l", *SIM, "--param", "broadcast_every=0"],
                 r"parameter broadcast_every=0 is outside its range \(0, inf\) .*fix: give broadcast_every a value "
                 r"in \(0, inf\)", id="5-engine-key-out-of-range"),
    pytest.param(["simulate", "wang2020", "--shape", "letter-l", *SIM, "--param", "p_random=-1"],
                 r"parameter p_random=-1 is outside its range \[0, 1\]", id="5-p_random-under-its-own-name"),
    pytest.param(["simulate", "song2016", "--lattice", "square", *SIM, "--param", "communication_timeout=2.5"],
                 r"parameter communication_timeout=2.5 must be a whole number", id="5-type"),
    pytest.param(["simulate", "song2016", "--lattice", "square", *SIM, "--param", "parent_rule=nearest"],
                 r"parameter parent_rule='nearest' is not one of \['relocate_route', 'stable_first', 'fewest_hops'\]",
                 id="5-choices"),
    pytest.param(["simulate", "example-gather", "--lattice", "square", *SIM, "--param", "gpa=0.3"],
                 r"parameter gpa=0.3 is not known to algorithm 'example-gather'; did you mean 'gap'\?",
                 id="5-example-gather"),
    # 10: parameters that make a run meaningless
    pytest.param(["simulate", "song2016", "--lattice", "square", *SIM, "--v", "0"],
                 r"--v 0.0 must be > 0: robots that cannot move make the run meaningless", id="10-simulate-v0"),
    pytest.param(["explore", "song2016", *EXP, "--v", "0"],
                 r"--v 0.0 must be > 0: robots that cannot move", id="10-explore-v0"),
    pytest.param(["simulate", "song2016", "--lattice", "square", *SIM, "--dt", "1e-300"],
                 r"v\*dt=5e-302 is below 1e-09 \* range=1.2: no robot could move measurably", id="10-simulate-tiny-dt"),
    pytest.param(["explore", "song2016", *EXP, "--dt", "1e-300"],
                 r"v\*dt=5e-302 is below 1e-09 \* range", id="10-explore-tiny-dt"),
    pytest.param(["simulate", "song2016", "--lattice", "square", *SIM, "--omega", "0"],
                 r"--omega 0.0 must be > 0: robots that cannot turn", id="10-omega0"),
    # 3: team sizes the explorer cannot draw, refused up front naming the cap
    pytest.param(["explore", "song2016", "--robots", "300..300", "--budget", "20"],
                 r"robots=300 is more than the explorer draws \(at most 64 for connected starts: Hypothesis",
                 id="3-explore-300"),
    pytest.param(["explore", "song2016", "--robots", "1000000"],
                 r"robots=1000000 is more than the explorer draws \(at most 64", id="3-explore-1000000"),
    pytest.param(["explore", "example-grid-goals", "--robots", "3..21"],
                 r"robots=21 is more than the explorer draws \(at most 20 for connected grid starts", id="3-grid-cells"),
    pytest.param(["verify", "--section", "exploration", "--robots", "3000"],
                 r"robots=3000 is more than the explorer draws", id="3-verify"),
    pytest.param(["simulate", "song2016", "--lattice", "square", "--robots", "20001", "--seed", "0"],
                 r"robots=20001 is more than swarmproof draws a start for \(at most 20000\)", id="3-simulate-cap"),
    # 4: a target of the wrong kind is a usage error naming the kinds accepted, not a crash
    pytest.param(["simulate", "song2016", "--target", "shape:letter-l", *SIM],
                 r"target='letter-l' \(shape\) is not of a kind algorithm 'song2016' forms: it takes a lattice target "
                 r"only; fix: give a lattice target, e.g. --target lattice:square", id="4-simulate"),
    pytest.param(["explore", "song2016", "--target", "shape:letter-l", *EXP],
                 r"target='letter-l' \(shape\) is not of a kind algorithm 'song2016' forms", id="4-explore"),
    pytest.param(["simulate", "jiang", "--target", "lines:wedge", *SIM],
                 r"target='wedge' \(lines\) .* it takes a pattern target only", id="4-jiang"),
    # 15 (parts): argparse's messages name the option and what is expected
    pytest.param(["explore", "song2016", "--budget", "soon"],
                 r"argument --budget: 'soon' is not a number of seconds nor 'none'", id="15-budget"),
    pytest.param(["explore", "song2016", "--speeds", "-1,0.05"],
                 r"speeds contains -1.0: every speed must be a finite number > 0", id="15-negative-speeds"),
    pytest.param(["simualte", "song2016"], r"unknown command 'simualte'; did you mean 'simulate'\?", id="15-typo"),
]


@pytest.mark.parametrize("argv, match", BAD)
def test_bad_run_input_exits_2_naming_it(argv, match, capsys):
    import re

    from swarmproof.cli import main

    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, (code, err[-600:])
    assert re.search(match, err), err[-600:]
    assert "Traceback" not in err and "crashed" not in err and "usage:" not in err.split("error:")[-1]


def test_a_subcommand_typo_shows_no_usage_block(capsys):
    from swarmproof.cli import main

    assert main(["simualte"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("swarmproof: error: unknown command 'simualte'") and "usage:" not in err


def test_json_error_document_for_a_bad_parameter(capsys):
    from swarmproof.cli import main

    code = main(["simulate", "song2014", "--lattice", "square", *SIM, "--param", "foo=1", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 2 and doc["error"]["kind"] == "usage" and "foo=1" in doc["error"]["message"]


def test_speeds_written_with_an_equals_sign_reach_the_same_check(capsys):
    from swarmproof.cli import main

    assert main(["explore", "song2016", "--speeds=-1,0.05"]) == 2
    assert "speeds contains -1.0" in capsys.readouterr().err


def test_valid_parameters_still_run(capsys):
    """The declarations accept what the algorithms read: a declared key in range runs (exit 0/1/3)."""
    from swarmproof.cli import main

    code = main(["simulate", "song2016", "--lattice", "square", "--robots", "3", "--seed", "0",
                 "--param", "communication_timeout=3", "--param", "robot_radius=0.1", "--json"])
    assert code in (0, 1, 3) and json.loads(capsys.readouterr().out)["robots"] == 3


CAMPAIGN = """format: swarmproof-campaign/1
name: t
{body}"""

BAD_CAMPAIGNS = [
    pytest.param("explore:\n  - algorithm: song2016\n    robots: [3, 4]\n    params: {comunication_timeout: 3}\n",
                 r"field 'explore\[0\].params': parameter comunication_timeout=3 is not known to algorithm 'song2016'; "
                 r"did you mean 'communication_timeout'\?", id="5-misspelt"),
    pytest.param("explore:\n  - algorithm: song2016\n    robots: [3, 4]\n    params: {communication_timeout: 3}\n",
                 r"params communication_timeout=3 is not one of \['v', 'omega', 'dt', 'extra'\]; fix: an algorithm "
                 r"parameter goes under extra", id="5-not-under-extra"),
    pytest.param("explore:\n  - algorithm: wang2020\n    robots: [3, 4]\n    params: {extra: {p_random: -1}}\n",
                 r"field 'explore\[0\].params': parameter p_random=-1 is outside its range \[0, 1\]", id="5-range"),
    pytest.param("explore:\n  - algorithm: song2016\n    robots: [3, 4]\n    params: {v: 0}\n",
                 r"field 'explore\[0\].params': v=0 must be > 0", id="10-v0"),
    pytest.param("explore:\n  - algorithm: song2016\n    robots: [3, 300]\n",
                 r"field 'explore\[0\].robots': robots=300 is more than the explorer draws .*"
                 r"robots: \[3, 64\] in a campaign", id="3-explore"),
    pytest.param("simulate:\n  - algorithm: song2016\n    targets: [square]\n    robots: [30000]\n    seeds: [0]\n",
                 r"field 'simulate\[0\].robots\[0\]': robots=30000 is more than swarmproof draws a start for .*"
                 r"fix: run at most 20000 robots, or start from your own poses \(swarmproof simulate --initial FILE\)",
                 id="3-simulate"),
    pytest.param("simulate:\n  - algorithm: song2016\n    targets: [shape:letter-l]\n    robots: [5]\n    seeds: [0]\n",
                 r"field 'simulate\[0\].targets\[0\]': target='letter-l' \(shape\) is not of a kind", id="4-simulate"),
    pytest.param("explore:\n  - algorithm: song2016\n    robots: [3, 4]\n    lattices: [shape:letter-l]\n",
                 r"field 'explore\[0\].lattices\[0\]': target='letter-l' \(shape\)", id="4-explore"),
]


@pytest.mark.parametrize("body, match", BAD_CAMPAIGNS)
def test_bad_campaign_cell_exits_2_before_any_task(body, match, tmp_path, capsys):
    import re

    from swarmproof.cli import main

    spec = tmp_path / "c.yaml"
    spec.write_text(CAMPAIGN.format(body=body))
    code = main(["campaign", str(spec), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and re.search(match, err), err[-600:]
    assert not (tmp_path / "out" / "results.sqlite").exists()     # nothing started, nothing half-written
