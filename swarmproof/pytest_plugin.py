"""pytest plugin (entry point ``pytest11``): explore algorithms from a user's tests.

Loaded automatically once swarmproof is installed.  It offers

* the fixture ``swarmproof_explore``: call it like
  :func:`swarmproof.checkers.explore.explore` -- with a registry name, a
  ``"module:qualname"`` or your algorithm class -- and chain ``.assert_held()``::

      def test_my_algorithm_keeps_contact(swarmproof_explore):
          swarmproof_explore(MyAlgorithm, properties=["connectivity"], max_examples=20).assert_held()

  The budget comes from the ``swarmproof_budget`` marker (default 60 s) unless
  passed; ``out_dir`` defaults to a per-test temporary folder, or to
  ``DIR/<test>/`` with ``--swarmproof-out DIR`` (ini: ``swarmproof_out``) for
  CI to keep, so a failure message names a counterexample file to ``swarmproof
  replay`` -- and a kept file is a regression test: ``swarmproof.replay_file(path)``
  re-runs it (``.reproduced``).  A failure shows the counterexample's steps and
  the replay command, not swarmproof's source;
* the marker ``@pytest.mark.swarmproof_budget(SECONDS)``;
* the fixture ``swarmproof_verify``: the CI gate of ``swarmproof verify`` from a
  test (:func:`swarmproof.checkers.gate.verify`, same keywords), with
  ``.assert_no_regression()``::

      @pytest.mark.swarmproof_baseline("verify-baseline.json")
      def test_no_regression(swarmproof_verify):
          swarmproof_verify(algorithms=["mypkg.algo:MyAlgorithm"]).assert_no_regression()

  The marker ``@pytest.mark.swarmproof_baseline(FILE)`` names the baseline
  (relative to pytest's rootdir) unless ``baseline=`` is passed; a failure
  prints each regressed row with its counterexample steps and replay command;
  counterexample files go where ``swarmproof_explore`` puts them;
* ``assert_proved(REF)`` (``from swarmproof.pytest_plugin import assert_proved``): proves the
  lemmas an algorithm declares (its class attribute ``lemmas``; ``swarmproof prove --algorithm
  REF``) and fails unless every one is proved, naming each lemma that was not, its status and
  why; returns the proof results::

      def test_my_lemmas_are_proved():
          assert_proved("mypkg.algo:MyAlgorithm")

* at the end of the session, the property table ("proof-of-property run"):
  every algorithm and property explored in the session -- through the fixture
  or by calling :func:`~swarmproof.checkers.explore.explore` directly -- with its verdict
  (held = explored, never proved) and whether it is claimed, then the lemmas
  of the z3 proof suite with their verdicts (proved = for every input of the
  normalised statement, docs/proofs.md) that the explored algorithms' premise
  monitors rest on (none when no explored algorithm declares premises).  The proof suite runs only when the
  fixture was used (about 1 s); ``--swarmproof-no-lemmas`` skips it.  The table
  ends with the held / violated / inconclusive counts and, for every
  ``swarmproof_verify`` run, its comparison with the baseline.

Everything heavy is imported lazily: the plugin costs nothing in test
sessions that do not use it.
"""

from __future__ import annotations

import pytest

_REPORTS_KEY = pytest.StashKey[list]()
_VERIFY_KEY = pytest.StashKey[list]()
_LISTENER_KEY = pytest.StashKey[object]()

TABLE_TITLE = "swarmproof property table (explored, not proved; lemmas proved by z3)"


def assert_proved(algorithm, *, rlimit: int | None = None, timeout_s: float | None = None) -> list:
    """Prove the lemmas ``algorithm`` declares (a registry name or ``module:qualname``; its class
    attribute ``lemmas``) as ``swarmproof prove --algorithm`` does, and fail the test unless every
    one is *proved*: a counterexample, an inconclusive proof (budget spent, z3 unknown, vacuous
    premises, a negative control not refuted) each fail it, named with the reason.  Returns the
    results (:class:`swarmproof.checkers.proofs.LemmaResult`).

    Raises
    ------
    AssertionError
        Some lemma was not proved.
    swarmproof.models.errors.UsageError
        An unknown algorithm, or one that declares no lemmas.
    """
    from swarmproof.checkers.proofs import DEFAULT_TIMEOUT_S, algorithm_lemmas, run_suite

    results = run_suite(algorithm_lemmas(str(algorithm)),
                        timeout_s=DEFAULT_TIMEOUT_S if timeout_s is None else timeout_s, rlimit=rlimit)
    bad = [r for r in results if r.status != "proved"]
    if bad:
        lines = [f"{len(bad)} of {len(results)} lemmas of {algorithm} not proved:"]
        for r in bad:
            lines.append(f"  {r.id}: {r.status}" + (f" ({r.reason})" if r.reason else ""))
            if r.status == "counterexample":
                lines += [f"    {k} = {v!r}" for k, v in (r.counterexample or {}).items()]
        lines.append(f"repeat: swarmproof prove --algorithm {algorithm}")
        raise AssertionError("\n".join(lines))
    return results


def pytest_addoption(parser) -> None:
    group = parser.getgroup("swarmproof")
    group.addoption("--swarmproof-no-lemmas", action="store_true", default=False,
                    help="do not run the z3 proof suite for the end-of-session property table")
    group.addoption("--swarmproof-out", metavar="DIR", default=None,
                    help="write the counterexamples of swarmproof_explore into DIR/<test name>/ "
                         "(for CI to keep as artifacts; default: a per-test temporary folder)")
    parser.addini("swarmproof_out", "folder for swarmproof_explore's counterexamples (as --swarmproof-out)",
                  default=None)


def _current_test() -> str:
    import os

    return os.environ.get("PYTEST_CURRENT_TEST", "").rsplit(" (", 1)[0] or "(outside a test)"


def pytest_configure(config) -> None:
    config.addinivalue_line("markers", "swarmproof_budget(seconds): wall-clock budget of swarmproof_explore")
    config.addinivalue_line("markers", "swarmproof_baseline(file): the baseline swarmproof_verify compares with")
    config.stash[_REPORTS_KEY] = []
    config.stash[_VERIFY_KEY] = []
    reports = config.stash[_REPORTS_KEY]

    def listener(report, reports=reports):
        # every exploration of the session -- the fixture's and direct explore() calls alike
        reports.append((_current_test(), report))
    config.stash[_LISTENER_KEY] = listener
    from swarmproof.listeners import REPORT_LISTENERS   # imports nothing: the plugin stays light

    REPORT_LISTENERS.append(listener)


def pytest_unconfigure(config) -> None:
    listener = config.stash.get(_LISTENER_KEY, None)
    if listener is None:
        return
    from swarmproof.listeners import REPORT_LISTENERS

    if listener in REPORT_LISTENERS:
        REPORT_LISTENERS.remove(listener)


def _out_dir(request, tmp_path):
    import re
    from pathlib import Path

    root = request.config.getoption("swarmproof_out") or request.config.getini("swarmproof_out")
    if not root:
        return tmp_path / "counterexamples"
    return Path(str(root)) / re.sub(r"[^A-Za-z0-9_.-]+", "_", request.node.nodeid)


@pytest.fixture
def swarmproof_explore(request, tmp_path):
    """Run the explorer with the test's budget; every report joins the session's property table."""
    from swarmproof.checkers.explore import explore

    marker = request.node.get_closest_marker("swarmproof_budget")
    default_budget = float(marker.args[0]) if marker is not None and marker.args else 60.0

    def run(algorithm, properties=None, **kwargs):
        __tracebackhide__ = True
        kwargs.setdefault("budget", default_budget)
        kwargs.setdefault("out_dir", _out_dir(request, tmp_path))
        return explore(algorithm, properties, **kwargs)

    return run


@pytest.fixture
def swarmproof_verify(request, tmp_path):
    """Run the CI gate (:func:`swarmproof.checkers.gate.verify`); the report joins the end-of-session table."""
    from pathlib import Path

    from swarmproof.checkers.gate import verify

    marker = request.node.get_closest_marker("swarmproof_baseline")
    default = marker.args[0] if marker is not None and marker.args else None

    def run(**kwargs):
        __tracebackhide__ = True
        kwargs.setdefault("baseline", default)
        base = kwargs["baseline"]
        if base is not None and not Path(str(base)).is_absolute():
            kwargs["baseline"] = str(Path(str(request.config.rootpath)) / str(base))
        if "out_dir" not in kwargs:
            out = _out_dir(request, tmp_path)
            out.mkdir(parents=True, exist_ok=True)
            kwargs["out_dir"] = str(out)
        rep = verify(**kwargs)
        request.config.stash[_VERIFY_KEY].append((_current_test(), rep))
        return rep

    return run


def verify_lines(runs) -> list[str]:
    """The end-of-session lines of ``swarmproof_verify`` runs: counts and the baseline comparison."""
    from swarmproof.checkers.ci_outputs import summary_line

    lines = []
    for nodeid, rep in runs:
        lines.append(f"verify ({nodeid}): {rep.counts_text()}")
        lines.append(f"  {summary_line(rep)}")
    return lines


def property_table(reports, lemmas=None, lemma_note: str = "") -> list[str]:
    """The lines of the end-of-session table.

    ``reports``: ``(test node id, ExploreReport)`` pairs; ``lemmas``: the proof
    suite's :class:`~swarmproof.checkers.proofs.LemmaResult` s, or None with
    ``lemma_note`` saying why there are none.  A lemma's "used by" names the
    explored algorithms whose premise monitors (the ``premises`` property)
    check its premises.
    """
    lines = [f"{'algorithm':<16} {'property':<13} {'verdict':<13} {'claimed':<8} {'scenarios':>9} {'steps':>8}  test"]
    users: dict = {}
    for nodeid, rep in reports:
        for lemma in rep.premise_lemmas:
            users.setdefault(lemma, [])
            if rep.algorithm not in users[lemma]:
                users[lemma].append(rep.algorithm)
        for name, v in rep.properties.items():
            claimed = "yes" if rep.claims.get(name) else "no"
            lines.append(f"{rep.algorithm:<16} {name:<13} {v.status:<13} {claimed:<8} {v.scenarios:>9} "
                         f"{v.steps:>8}  {nodeid}")
    statuses = [v.status for _, rep in reports for v in rep.properties.values()]
    na = statuses.count("not_applicable")
    lines.append("explored: " + ", ".join(f"{statuses.count(s)} {s}" for s in ("held", "violated", "inconclusive"))
                 + (f"; {na} n/a (not applicable)" if na else ""))
    if lemmas is None:
        lines.append(f"lemmas: {lemma_note}")
        return lines
    used = [r for r in lemmas if users.get(r.id)]
    if not used:
        lines.append("lemmas: none -- no explored algorithm declares lemma premises (premise_monitors)")
        return lines
    lines.append(f"{'lemma':<34} {'verdict':<15} used by (premise monitors)")
    for r in used:
        lines.append(f"{r.id:<34} {r.status:<15} {', '.join(users[r.id])}")
    return lines


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    reports = config.stash.get(_REPORTS_KEY, [])
    runs = config.stash.get(_VERIFY_KEY, [])
    if runs:
        terminalreporter.section("swarmproof verify (the CI gate)")
        for line in verify_lines(runs):
            terminalreporter.write_line(line)
    if not reports:
        return
    lemmas, note = None, ""
    if config.getoption("swarmproof_no_lemmas", False):
        note = "not run (--swarmproof-no-lemmas)"
    else:
        try:
            from swarmproof.checkers.proofs import run_suite

            lemmas = run_suite()
        except Exception as exc:  # noqa: BLE001 - the table must still print
            note = f"not run ({type(exc).__name__}: {exc})"
    tr = terminalreporter
    tr.section(TABLE_TITLE)
    for line in property_table(reports, lemmas, note):
        tr.write_line(line)
