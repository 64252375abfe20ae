"""The pytest plugin (entry point pytest11): fixture, budget marker, assert_held, session property table
with the proof suite's lemmas."""

import subprocess
import sys
import textwrap

import pytest

from swarmproof.checkers.explore import ExploreReport, PropertyVerdict
from swarmproof.pytest_plugin import TABLE_TITLE, property_table

USER_TESTS = textwrap.dedent('''
    import pytest

    from swarmproof.reference_impl.song2016.algorithm import Song2016


    class MySong2016(Song2016):
        claims = {"connectivity": "my paper, Lemma 3"}


    @pytest.mark.swarmproof_budget(20)
    def test_song2016_keeps_contact(swarmproof_explore):
        swarmproof_explore(MySong2016, ["connectivity", "premises"], max_examples=3, robots=(3, 4)).assert_held()

    @pytest.mark.swarmproof_budget(4)
    def test_song2014_keeps_contact(swarmproof_explore):
        swarmproof_explore("song2014", ["connectivity"], max_examples=15, robots=(4, 6),
                           lattices=["square"]).assert_held()
''')


def _report(algorithm, lemmas, **verdicts):
    rep = ExploreReport(algorithm, 0, 5, (3, 4), ("square",), [], [], claims={"connectivity": "001 Lemma 11"},
                        premise_lemmas=lemmas)
    for name, status in verdicts.items():
        rep.properties[name] = PropertyVerdict(name, status, scenarios=5, steps=700)
    return rep


def test_property_table_lines_with_lemmas():
    class R:
        def __init__(self, id, status):
            self.id, self.status = id, status

    reports = [("t.py::a", _report("song2016", ["bounded_range", "nclb_link_kept"], connectivity="held",
                                   premises="held")),
               ("t.py::b", _report("song2014", ["bounded_range"], premises="violated"))]
    lines = property_table(reports, [R("bounded_range", "proved"), R("scale_invariance", "proved"),
                                     R("nclb_link_kept", "inconclusive")])
    assert lines == [
        "algorithm        property      verdict       claimed  scenarios    steps  test",
        "song2016         connectivity  held          yes              5      700  t.py::a",
        "song2016         premises      held          no               5      700  t.py::a",
        "song2014         premises      violated      no               5      700  t.py::b",
        "explored: 2 held, 1 violated, 0 inconclusive",
        "lemma                              verdict         used by (premise monitors)",
        "bounded_range                      proved          song2016, song2014",
        "nclb_link_kept                     inconclusive    song2016",
    ]                                                  # scale_invariance: no explored algorithm rests on it
    assert property_table(reports[:1], None, "not run (--swarmproof-no-lemmas)")[-1] == \
        "lemmas: not run (--swarmproof-no-lemmas)"
    none = [("t.py::c", _report("mine", [], connectivity="held"))]
    assert property_table(none, [R("bounded_range", "proved")])[-1] == \
        "lemmas: none -- no explored algorithm declares lemma premises (premise_monitors)"


USER_TESTS_SMALL = textwrap.dedent('''
    import swarmproof
    from swarmproof.checkers.explore import explore


    def test_direct_call_is_in_the_table():
        explore("example-gather", ["connectivity"], max_examples=2, robots=(3, 3), budget=None)


    def test_fixture_keeps_counterexamples_for_ci(swarmproof_explore):
        swarmproof_explore("song2014", ["premises"], max_examples=30, robots=(3, 4), lattices=["square"],
                           budget=None).assert_held()


    def test_a_kept_counterexample_is_a_regression_test():
        import glob

        path, = glob.glob("kept/**/*.json", recursive=True)
        assert swarmproof.replay_file(path).reproduced
''')


def test_plugin_rows_for_direct_calls_swarmproof_out_and_no_source_in_the_failure(tmp_path):
    (tmp_path / "test_user.py").write_text(USER_TESTS_SMALL)
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--swarmproof-no-lemmas",
                           "--swarmproof-out", "kept", str(tmp_path / "test_user.py")],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300)
    out = proc.stdout
    assert "1 failed, 2 passed" in out, out[-3000:]
    table = out.split(TABLE_TITLE)[1]
    assert "example-gather   connectivity" in table and "test_direct_call_is_in_the_table" in table
    assert "song2014         premises      violated" in table
    kept = list((tmp_path / "kept").rglob("*.json"))
    assert len(kept) == 1 and "test_fixture_keeps_counterexamples_for_ci" in str(kept[0])
    failure = out.split("= FAILURES =")[1].split(TABLE_TITLE)[0]
    assert "counterexample: song2014 violates premises" in failure and "replay: swarmproof replay kept/" in failure
    assert "checkers/explore.py" not in failure          # the user sees the counterexample, not swarmproof's source


@pytest.mark.slow
def test_plugin_gate_fails_with_counterexample_and_prints_table(tmp_path):
    (tmp_path / "test_user.py").write_text(USER_TESTS)
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tmp_path)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=180)
    out = proc.stdout
    assert proc.returncode == 1, out
    assert "1 failed, 1 passed" in out
    assert "connectivity: violated" in out and "counterexample: song2014 violates connectivity" in out
    assert "replay: swarmproof replay" in out
    assert TABLE_TITLE in out
    table = out.split(TABLE_TITLE)[1]
    rows = [line.split() for line in table.splitlines()]
    assert ["song2016", "connectivity", "held", "yes"] in [r[:4] for r in rows]   # the class's own claim
    assert ["song2016", "premises", "held", "no"] in [r[:4] for r in rows]
    assert ["song2014", "connectivity", "violated", "no"] in [r[:4] for r in rows]
    assert ["bounded_range", "proved", "song2016,", "song2014"] in rows
    assert ["relocate_stays_in_range", "proved", "song2016"] in rows


GATE_TESTS = textwrap.dedent('''
    import pytest

    BASELINE = {shipped!r}


    @pytest.mark.swarmproof_baseline(BASELINE)
    def test_lattices_as_the_baseline_says(swarmproof_verify):
        swarmproof_verify(sections=["lattices"]).assert_no_regression()


    @pytest.mark.swarmproof_baseline(BASELINE)
    def test_mutant_regresses(swarmproof_verify):
        swarmproof_verify(algorithms=["{mutant}:Song2016"], sections=["algorithms"],
                          properties=["tree_links"]).assert_no_regression()
''')


def test_swarmproof_verify_fixture_fails_on_regressions_with_the_counterexample(tmp_path):
    """issue 14: a test suite asserts "no regression against the baseline"; a failing row prints its
    counterexample steps and replay command; the session ends with the gate's counts and summary."""
    from testkit import MUTANT, SHIPPED, write_mutant

    write_mutant(tmp_path)
    (tmp_path / "test_gate.py").write_text(GATE_TESTS.format(shipped=SHIPPED, mutant=MUTANT))
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--swarmproof-out", "kept",
                           "-p", "no:randomly", str(tmp_path / "test_gate.py")],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300)
    out = proc.stdout
    assert proc.returncode == 1 and "1 failed, 1 passed" in out, out[-3000:]
    failure = out.split("= FAILURES =")[1].split("swarmproof verify (the CI gate)")[0]
    assert "verify: FAIL: 3 regressions, 1 known finding, 0 improvements, 0 held" in failure
    assert "algorithms: song2016 square n=10 / tree_links: violated -- new claimed" not in failure
    assert "algorithms: song2016 square n=10 / tree_links: violated -- regressed: held in the baseline" in failure
    assert f"run {MUTANT}:Song2016 with seed" in failure and "at step 166: the link child 3 -> parent 6 broke" in failure
    assert "replay: swarmproof replay kept/" in failure
    assert "checkers/gate.py" not in failure                               # not swarmproof's source
    summary = out.split("swarmproof verify (the CI gate)")[1]
    assert "verify (test_gate.py::test_lattices_as_the_baseline_says): 0 proved, 8 held, 0 violated, 0 inconclusive" in summary
    assert "  verify: PASS: 0 regressions, 0 known findings, 0 improvements, 8 held (against " in summary
    assert "  verify: FAIL: 3 regressions" in summary
