"""Issue 29 item 9: the budget holds against the algorithm under test.  A controller whose ``step``
never returns is stopped at ``explore --budget`` (inconclusive, naming where it hung) and at
``simulate --timeout`` (exit 3); checkers/watchdog.py is the timer both use.

The commands run in a child process bounded by a generous timeout, so a watchdog that fails
makes the test fail instead of hanging it; no wall-clock figure is asserted."""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from swarmproof.checkers.watchdog import Overstayed, time_limit

HANGMOD = Path(__file__).resolve().parents[1] / "cli" / "data" / "hangmod.py"
RUN = "import sys; from swarmproof.cli import main; sys.exit(main(sys.argv[1:]))"


def _spin_catching_exceptions():
    n = 0
    while True:
        try:
            n += 1
        except Exception:  # noqa: BLE001 - what an algorithm may do; the watchdog is not an Exception
            pass


def test_time_limit_stops_a_loop_that_catches_exceptions_and_names_it():
    with pytest.raises(Overstayed) as info:
        with time_limit(0.2):
            _spin_catching_exceptions()
    assert info.value.seconds == 0.2
    assert "_spin_catching_exceptions" in info.value.where and "test_watchdog.py" in info.value.where
    assert str(info.value).startswith("did not return within 0.2 s (it was in ")
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)          # disarmed afterwards


def test_no_limit_and_an_enclosing_timer_is_put_back():
    with time_limit(None):
        pass
    old = signal.signal(signal.SIGALRM, lambda *a: None)
    try:
        signal.setitimer(signal.ITIMER_REAL, 100.0)
        with time_limit(50.0):
            pass
        left, _ = signal.getitimer(signal.ITIMER_REAL)
        assert 0 < left <= 100.0                   # the enclosing timer runs on
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


@pytest.fixture
def here(tmp_path):
    shutil.copy(HANGMOD, tmp_path / "hangmod.py")
    return tmp_path


def _swarmproof(cwd, *argv):
    out = subprocess.run([sys.executable, "-c", RUN, *argv], cwd=cwd, capture_output=True, text=True,
                         timeout=120)
    return out.returncode, out.stdout, out.stderr


def test_explore_budget_stops_a_step_that_never_returns(here):
    code, out, err = _swarmproof(here, "explore", "hangmod:Hangs", "--property", "connectivity",
                                 "--budget", "3", "--max-examples", "5", "--json")
    assert code == 3, err[-2000:]
    v = json.loads(out)["properties"]["connectivity"]
    assert v["status"] == "inconclusive" and v["budget_hit"] is True
    assert "did not return within" in v["message"] and "hangmod._Controller.step" in v["message"], v["message"]
    assert v["message"].startswith("no scenario gave a judgment (budget spent); the budget stopped a run under "
                                   "way: 3 robots on ")
    assert v["message"].endswith("; no run returned: a step of the algorithm may never return (it is judged, "
                                 "not trusted)")


def test_simulate_timeout_stops_a_step_that_never_returns(here):
    code, out, err = _swarmproof(here, "simulate", "hangmod:Hangs", "--lattice", "square", "--robots", "3",
                                 "--seed", "0", "--timeout", "1", "--json", "--trace", "t.json")
    assert code == 3, err[-2000:]
    doc = json.loads(out)
    assert doc["status"] == "timeout" and doc["exit_code"] == 3 and doc["timeout"] == 1.0
    assert doc["where"].startswith("hangmod._Controller.step (hangmod.py:")
    assert "did not return within 1 s" in doc["message"]
    assert not (here / "t.json").exists()          # no trace of a run that did not end


def test_simulate_timeout_human_report(here):
    code, out, _ = _swarmproof(here, "simulate", "hangmod:Hangs", "--lattice", "square", "--robots", "3",
                               "--seed", "0", "--timeout", "0.5")
    assert code == 3
    assert out.splitlines()[-1] == "result: inconclusive (timeout)"
    assert "did not return within 0.5 s (it was in hangmod._Controller.step" in out


@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf"], ids=["zero", "negative", "nan", "inf"])
def test_simulate_timeout_must_be_positive(cli, value):
    code, _, err = cli("simulate", "song2016", "--lattice", "square", "--robots", "3", "--seed", "0",
                       "--timeout", value)
    assert code == 2
    assert f"--timeout={float(value)!r} must be a number of seconds > 0; fix: e.g. --timeout 60" in err


@pytest.mark.parametrize("argv, name", [
    (["explore", "song2014", "--budget", "1e10", "--max-examples", "2", "--robots", "3..4"], "--budget 1e+10"),
    (["explore", "song2014", "--budget", "1e308", "--max-examples", "2", "--robots", "3..4"], "--budget 1e+308"),
    (["simulate", "song2016", "--target", "square", "--robots", "5", "--seed", "0", "--timeout", "1e10"],
     "--timeout=1e+10"),
], ids=["explore-1e10", "explore-1e308", "simulate-1e10"])
def test_a_limit_past_the_system_timer_is_refused_exit_2(capsys, argv, name):
    """The system timer overflows at 1e10 s (it was exit 4, "timestamp out of range for platform
    time_t"): a limit above MAX_LIMIT_S is a usage error naming the value and the way to no limit."""
    from swarmproof.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"{name} is more than 1e+07 seconds" in err and "fix:" in err and "Traceback" not in err


def test_the_library_refuses_a_budget_past_the_system_timer():
    from swarmproof.checkers.explore import explore
    from swarmproof.models.errors import UsageError

    with pytest.raises(UsageError, match=r"budget=10000000000.0 is more than 1e\+07 s"):
        explore("song2014", ["connectivity"], budget=1e10, max_examples=2, robots=(3, 4))
