"""`swarmproof prove`: JSON fields (DESIGN.md section 2), exit codes 0/1/2/3, exact human lines."""

from __future__ import annotations

import json
import re

import pytest
import z3
from testkit import FakeTerminal

from swarmproof.checkers import proofs
from swarmproof.reference_impl.song2016 import lemmas as song_lemmas
from swarmproof.cli import main

pytestmark = pytest.mark.proofs

FIELDS = {"id", "statement", "cites", "status", "seconds", "premises_satisfiable",
          "negative_control", "kind", "vacuity", "not_proved"}


def run(capsys, *argv):
    code = main(["prove", *argv])
    out, err = capsys.readouterr()
    return code, out, err


# slow by nature (issue 29): every suite lemma through z3 (11 s of CPU), as
# tests/cli/test_verify.py::test_lemma_section_json_every_lemma_proved_exit_0 does through the
# same run_suite in the default suite; prove's JSON fields and exit 0 stay there in
# test_two_lemmas_json_fields_exit_0 below.
@pytest.mark.slow
def test_whole_suite_json_exit_0(capsys):
    code, out, err = run(capsys, "--json")
    doc = json.loads(out)
    assert code == 0
    assert [d["id"] for d in doc["lemmas"]] == list(proofs.LEMMAS)
    for d in doc["lemmas"]:
        assert FIELDS <= set(d)
        assert d["status"] == "proved" and d["premises_satisfiable"] is True
        assert d["negative_control"]["status"] == "counterexample"
        assert d["negative_control"]["counterexample"]
    assert err == ""


def test_two_lemmas_json_fields_exit_0(capsys):
    code, out, err = run(capsys, "wang2020_lemma_iv_a_1", "wang2020_speed_buffer_v_b3_cases", "--json")
    doc = json.loads(out)
    assert code == 0 and err == ""
    assert [d["id"] for d in doc["lemmas"]] == ["wang2020_lemma_iv_a_1", "wang2020_speed_buffer_v_b3_cases"]
    for d in doc["lemmas"]:
        assert FIELDS <= set(d)
        assert d["status"] == "proved" and d["premises_satisfiable"] is True
        assert d["negative_control"]["status"] == "counterexample"
        assert d["negative_control"]["counterexample"]
    assert doc["lemmas"][0]["kind"] == "paper lemma" and doc["lemmas"][1]["kind"] == "auxiliary"


def test_human_table_exact_lines(capsys):
    code, out, _ = run(capsys, "bounded_range", "relocate_stays_in_range")
    lines = out.splitlines()
    assert code == 0
    assert lines[0] == ("lemma                                status          kind         vacuity         seconds "
                        " rlimit used  cites")
    row = re.sub(r" +\d+\.\d{3} ", "  <s> ", lines[1])
    assert row == ("bounded_range                        proved          paper lemma  ok  <s>           2%  "
                   "Song & O'Kane 2014, Lemma 7, Eqs. 5-7; Song & O'Kane 2016, Lemma 7")   # readable, no seed file
    assert lines[2].startswith("relocate_stays_in_range              proved          auxiliary    ok ")
    assert lines[3] == "2 lemmas: 2 proved, 0 counterexample, 0 inconclusive"
    assert lines[4].startswith("not proved by relocate_stays_in_range: that the relocate robot's step ends")
    assert len(lines) == 5


def test_wrong_lemma_prints_counterexample_as_numbers_exit_1(capsys):
    code, out, _ = run(capsys, "bounded_range_strict_closed")
    assert code == 1
    assert out.splitlines()[2:] == [
        "1 lemmas: 0 proved, 1 counterexample, 0 inconclusive",
        "counterexample to bounded_range_strict_closed "
        "(z3 found premises true and the conclusion false):",
        "  s = 0.5",
        "  p_i_0_x = 0.0",
        "  p_i_0_y = 0.0",
        "  p_i_1_x = 0.0",
        "  p_i_1_y = -0.5",
        "  p_p_1_x = 0.0",
        "  p_p_1_y = 0.5",
    ]


def test_counterexample_beats_inconclusive_for_the_exit_code(capsys):
    # z3's work budget, not seconds: bounded_range_strict_closed's counterexample takes about
    # 4e5 units, nclb_three_children_direct spends 2e6 without an answer, on any machine load
    # (a 0.3 s timeout here could also cut the counterexample short on a loaded machine)
    code, out, _ = run(capsys, "bounded_range_strict_closed", "nclb_three_children_direct",
                       "--rlimit", "2_000_000", "--json")
    doc = json.loads(out)
    assert code == 1 and [d["status"] for d in doc["lemmas"]] == ["counterexample", "inconclusive"]
    assert doc["rlimit"] == 2_000_000 and doc["timeout"] == 300.0
    spent = doc["lemmas"][1]
    assert "z3's budget of rlimit=2000000 was spent" in spent["reason"]
    assert spent["rlimit"]["budget"] == 2_000_000 and spent["rlimit"]["used"] >= 2_000_000


def test_timeout_exit_3(capsys):
    # the outer wall-clock cap still stops a lemma (exit 3), whatever its rlimit budget
    code, out, _ = run(capsys, "nclb_three_children_direct", "--timeout", "0.3", "--json")
    d = json.loads(out)["lemmas"][0]
    assert code == 3 and d["status"] == "inconclusive" and "timeout" in d["reason"]


def test_vacuous_lemma_exit_3(capsys, monkeypatch):
    x = z3.Real("x")
    lem = proofs.Lemma(
        id="vacuous", statement="contradictory premises", cites=("test",), normalisations=(),
        build=lambda: proofs.Encoding(premises=[("a", x > 1), ("b", x < 0)], conclusion=x == 3,
                                      variables=[x]),
        control=lambda: song_lemmas.relocate_stays_in_range(4), control_note="test")
    monkeypatch.setitem(proofs.EXTRA_LEMMAS, "vacuous", lem)
    code, out, _ = run(capsys, "vacuous")
    assert code == 3
    assert out.splitlines()[-1] == ("inconclusive vacuous: premises unsatisfiable: "
                                    "the lemma would hold vacuously")


@pytest.mark.parametrize("argv, message", [
    (["lemma7"], r"lemma='lemma7' is not a known lemma id; fix: use one of: translation_invariance"),
    (["--timeout", "0"], r"--timeout='0' must be > 0"),
    (["--timeout", "-2"], r"--timeout='-2' must be > 0"),
    (["--timeout", "inf"], r"--timeout='inf' must be > 0 and at most 86400"),
    (["--rlimit", "0"], r"--rlimit='0' must be an integer from 1 to 4294967295 \(z3's resource units"),
    (["--rlimit", "1.5e0"], r"--rlimit='1.5e0' must be an integer from 1"),
    (["--rlimit", "4294967296"], r"--rlimit='4294967296' must be an integer from 1 to 4294967295"),
], ids=["unknown-id", "zero-timeout", "negative-timeout", "infinite-timeout", "zero-rlimit",
        "float-rlimit", "huge-rlimit"])
def test_usage_errors_exit_2(capsys, argv, message):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert re.search(message, err)


def test_non_numeric_timeout_exit_2(capsys):
    assert main(["prove", "--timeout", "soon"]) == 2
    assert "--timeout='soon' is not a number of seconds" in capsys.readouterr().err


def test_progress_on_a_terminal_is_erased_before_the_table(monkeypatch):
    """#32: prove shows which lemma it is on when stderr is a terminal, then erases it."""
    term = FakeTerminal()
    monkeypatch.setattr("sys.stdout", term)
    monkeypatch.setattr("sys.stderr", term)
    assert main(["prove", "translation_invariance", "rotation_invariance"]) == 0
    assert "prove: 1/2 translation_invariance" in term.text and "prove: 2/2 rotation_invariance" in term.text
    shown = term.lines()
    assert not any("prove: " in ln for ln in shown), shown
    assert shown[0].startswith("lemma ") and shown[3] == "2 lemmas: 2 proved, 0 counterexample, 0 inconclusive"


def test_no_progress_when_stderr_is_not_a_terminal(capsys):
    code, out, err = run(capsys, "translation_invariance")
    assert code == 0 and err == ""


# -- lemmas per algorithm (issue 32): prove --algorithm, prove --list, assert_proved ------------

def test_prove_algorithm_proves_exactly_the_lemmas_it_declares(capsys, monkeypatch):
    """song2014's declaration is checked against the suite below; here two cheap lemmas (0.3 s of
    z3) stand in for its three (7 s), to keep make test's time."""
    from swarmproof.reference_impl.song2014 import Song2014

    assert Song2014.lemmas == ("bounded_range", "bounded_range_strict", "intermediate_goal_in_region")
    monkeypatch.setattr(Song2014, "lemmas", ("intermediate_goal_in_region", "relocate_stays_in_range"))
    code, out, err = run(capsys, "--algorithm", "song2014", "--json")
    doc = json.loads(out)
    assert code == 0, err
    assert [d["id"] for d in doc["lemmas"]] == ["intermediate_goal_in_region", "relocate_stays_in_range"]
    assert all(d["status"] == "proved" for d in doc["lemmas"])


@pytest.mark.parametrize("argv, match", [
    (("--algorithm", "example-anonymous-line"),
     r"algorithm='example-anonymous-line' declares no lemmas .*fix: .*example-gather, song2014, song2016"),
    (("--algorithm", "song2014", "bounded_range"), r"give lemma ids or --algorithm=song2014, not both"),
    (("--algorithm", "nosuch"), r"algorithm='nosuch' is not known"),
    (("--list", "bounded_range"), r"--list lists every lemma: it takes no LEMMA and no --algorithm"),
], ids=["no-lemmas", "both", "unknown", "list-with-ids"])
def test_prove_algorithm_and_list_refuse_bad_input_exit_2(capsys, argv, match):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and re.search(match, err), err
    assert "Traceback" not in err


def test_prove_list_is_list_lemmas_with_each_lemma_s_algorithms(capsys):
    code, out, _ = run(capsys, "--list", "--json")
    assert code == 0
    assert main(["list", "lemmas", "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == json.loads(out)
    by_id = {e["name"]: e for e in json.loads(out)["lemmas"]}
    assert by_id["nclb_link_kept"]["algorithms"] == ["song2016", "song2016-literal", "song2016-subtree-clock"]
    assert "song2014" in by_id["bounded_range"]["algorithms"] and "song2016" in by_id["bounded_range"]["algorithms"]
    assert by_id["wang2020_lemma_iv_a_1"]["algorithms"] == ["wang2020", "wang2020-broadcast-handshake"]
    assert by_id["translation_invariance"]["algorithms"] == []
    assert by_id["gather_follower_link_kept"]["algorithms"] == ["example-gather"]
    assert run(capsys, "--list")[1].splitlines()[0] == "lemmas (22):"


def test_every_declared_lemma_of_every_algorithm_is_in_the_suite():
    for name, ids in proofs.lemma_algorithms_by_name().items():
        if ids:
            assert proofs.algorithm_lemmas(name) == ids, name


def test_assert_proved_passes_for_proved_lemmas_and_names_what_was_not(monkeypatch):
    from swarmproof.pytest_plugin import assert_proved
    from swarmproof.reference_impl.song2014 import Song2014

    monkeypatch.setattr(Song2014, "lemmas", ("intermediate_goal_in_region",))     # cheap (0.2 s)
    results = assert_proved("song2014")
    assert [r.id for r in results] == ["intermediate_goal_in_region"] and results[0].status == "proved"
    # an algorithm whose declared lemma is a finding (a real counterexample) fails the test, named
    monkeypatch.setattr(Song2014, "lemmas", ("bounded_range_strict_closed",))
    with pytest.raises(AssertionError, match=r"1 of 1 lemmas of song2014 not proved:\n  "
                                             r"bounded_range_strict_closed: counterexample"):
        assert_proved("song2014")
