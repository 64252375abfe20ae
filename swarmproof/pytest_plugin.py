"""pytest plugin (entry point ``pytest11``): explore algorithms from a user's tests.

Loaded automatically once swarmproof is installed.  It offers

* the fixture ``swarmproof_explore``: call it like
  :func:`swarmproof.checkers.explore.explore` and chain ``.assert_held()``::

      def test_my_algorithm_keeps_contact(swarmproof_explore):
          swarmproof_explore("song2016", properties=["connectivity"], max_examples=20).assert_held()

  The budget comes from the ``swarmproof_budget`` marker (default 60 s) unless
  passed; ``out_dir`` defaults to a per-test temporary folder, so a failure
  message names a counterexample file to ``swarmproof replay``;
* the marker ``@pytest.mark.swarmproof_budget(SECONDS)``;
* at the end of the session, a property table: every algorithm and property
  explored in the session with its verdict (held = explored, never proved).

Everything heavy is imported lazily: the plugin costs nothing in test
sessions that do not use it.
"""

from __future__ import annotations

import pytest

_REPORTS_KEY = pytest.StashKey[list]()


def pytest_configure(config) -> None:
    config.addinivalue_line("markers", "swarmproof_budget(seconds): wall-clock budget of swarmproof_explore")
    config.stash[_REPORTS_KEY] = []


@pytest.fixture
def swarmproof_explore(request, tmp_path):
    """Run the explorer with the test's budget; every report joins the session's property table."""
    from swarmproof.checkers.explore import explore

    marker = request.node.get_closest_marker("swarmproof_budget")
    default_budget = float(marker.args[0]) if marker is not None and marker.args else 60.0

    def run(algorithm, properties=None, **kwargs):
        kwargs.setdefault("budget", default_budget)
        kwargs.setdefault("out_dir", tmp_path / "counterexamples")
        report = explore(algorithm, properties, **kwargs)
        request.config.stash[_REPORTS_KEY].append((request.node.nodeid, report))
        return report

    return run


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    reports = config.stash.get(_REPORTS_KEY, [])
    if not reports:
        return
    tr = terminalreporter
    tr.section("swarmproof property table (explored, not proved)")
    tr.write_line(f"{'algorithm':<16} {'property':<13} {'verdict':<13} {'scenarios':>9} {'steps':>8}  test")
    for nodeid, rep in reports:
        for name, v in rep.properties.items():
            tr.write_line(f"{rep.algorithm:<16} {name:<13} {v.status:<13} {v.scenarios:>9} {v.steps:>8}  {nodeid}")
