"""Test-suite configuration.

Hypothesis: the suite is deterministic by default (derandomize, no example
database, no deadline: timings on a shared 2-core machine are noise).  When
``CI`` is set Hypothesis would load its own "ci" profile, which is the same
in spirit; we load ours explicitly so local and CI runs agree.  Set
``HYPOTHESIS_PROFILE=explore`` to search randomly with more examples.
"""

from __future__ import annotations

import os
import sys

import matplotlib

matplotlib.use("Agg")

from hypothesis import HealthCheck, settings  # noqa: E402

settings.register_profile("swarmproof", derandomize=True, database=None, deadline=None,
                          print_blob=True, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("explore", parent=settings.get_profile("swarmproof"),
                          derandomize=False, max_examples=1000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "swarmproof"))


import pytest  # noqa: E402


@pytest.fixture
def cli(capsys):
    """``cli(*argv) -> (exit code, stdout, stderr)`` of ``swarmproof`` run in-process."""
    from swarmproof.cli import main

    def run(*argv):
        code = main([str(a) for a in argv])
        out, err = capsys.readouterr()
        return code, out, err
    return run


# tests/testkit.py: helpers test modules import (``from testkit import Recorder``); importlib
# import mode does not put the tests folder on the path by itself.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture
def recorder():
    """The :class:`testkit.Recorder` test algorithm class."""
    from testkit import Recorder

    return Recorder


# Per-test CPU profile, opt-in: SWARMPROOF_TEST_CPU=FILE appends one line per test phase,
# "cpu_seconds children_cpu_seconds nodeid", where cpu is this process's (every thread, so z3's
# helper threads count) and children the subprocesses it waited for (Dask schedulers, CLI runs).
# CPU, unlike --durations' wall time, does not grow when the machine is loaded, which is how the
# suite's 4-minute budget is apportioned (docs/performance.md, "Test-suite speed").
if os.environ.get("SWARMPROOF_TEST_CPU"):
    import resource
    import time

    def _cpu():
        kids = resource.getrusage(resource.RUSAGE_CHILDREN)
        return time.process_time(), kids.ru_utime + kids.ru_stime

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(item, nextitem):
        own, kids = _cpu()
        yield
        own2, kids2 = _cpu()
        with open(os.environ["SWARMPROOF_TEST_CPU"], "a") as fh:
            fh.write(f"{own2 - own:.3f} {kids2 - kids:.3f} {item.nodeid}\n")


# --dist loadgroup sends the tests of one ``@pytest.mark.xdist_group(NAME)`` to one worker by the
# suffix "@NAME" pytest-xdist adds to their node ids on the workers.  pytest-xdist (3.8) adds it by
# setting ``item._nodeid``, which pytest 9 no longer reads (a node id is ``item._id``, a NodeId):
# the suffix was lost and the groups were spread over the workers like any test, so a per-worker
# cache (testkit.proved) or a module fixture of a group was computed on each worker.  This puts the
# suffix where pytest 9 reads it, after pytest-xdist's own hook and only where that one had no effect.
@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(config, items):
    if not getattr(config.option, "loadgroup", False):
        return                  # not an xdist worker of --dist loadgroup
    for item in items:
        names = sorted({str(m.args[0] if m.args else m.kwargs.get("name", "default"))
                        for m in item.iter_markers("xdist_group")})
        if names and "@" not in item.nodeid and hasattr(item, "_id"):
            from _pytest.nodeid import NodeId   # pytest >= 9, which has item._id

            item._id = NodeId.parse(f"{item.nodeid}@{'_'.join(names)}")
