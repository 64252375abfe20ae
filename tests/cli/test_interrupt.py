"""Issue 29 item 6: Ctrl-C stops every command at once with exit 130 and leaves no report that
looks complete -- sent as a real SIGINT to a real process, while it works.

Each child imports what its command needs, says READY on stderr, and only then runs the command,
so the SIGINT lands in the command's work (not in Python's start-up); the work is long enough
that it cannot finish first.  A timeout bounds a hang (no wall-clock figure is asserted)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

CHILD = ("import sys, z3, hypothesis, swarmproof.checkers.explore, swarmproof.checkers.proofs, "
         "swarmproof.checkers.report, swarmproof.checkers.runs, swarmproof.checkers.gate; "
         "from swarmproof.cli import main, build_parser; build_parser(); "
         "sys.stderr.write('READY\\n'); sys.stderr.flush(); sys.exit(main(sys.argv[1:]))")

#: seconds between READY and the SIGINT: the command is at work by then
SETTLE_S = 2.0


def _interrupt(argv, cwd, settle=SETTLE_S):
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.Popen([sys.executable, "-c", CHILD, *argv], cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stderr.readline().strip() == "READY"
        time.sleep(settle)
        assert proc.poll() is None, "the command finished before the SIGINT: give it more work"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, out, err


def _json_error_only(out: str) -> None:
    """With --json, stdout holds one error document saying it was interrupted, nothing else."""
    doc = json.loads(out)
    assert doc["exit_code"] == 130 and doc["error"]["kind"] == "interrupted", doc


@pytest.mark.parametrize("argv, outputs", [
    pytest.param(["prove", "--json"], [], id="prove"),
    pytest.param(["verify", "--section", "lemmas", "--json", "--junit", "{tmp}/v.xml", "--html", "{tmp}/v.html",
                  "--markdown", "{tmp}/v.md"], ["v.xml", "v.html", "v.md"], id="verify-lemmas"),
    pytest.param(["verify", "--section", "exploration", "--algorithm", "song2016", "--max-examples", "100000",
                  "--json", "--junit", "{tmp}/v.xml", "--html", "{tmp}/v.html", "--markdown", "{tmp}/v.md"],
                 ["v.xml", "v.html", "v.md"], id="verify-exploration", marks=pytest.mark.slow),
    pytest.param(["explore", "song2016", "--property", "connectivity", "--budget", "none", "--max-examples",
                  "100000", "--json", "--out", "{tmp}/cx"], [], id="explore"),
    pytest.param(["simulate", "song2016", "--lattice", "square", "--robots", "80", "--seed", "0", "--max-steps",
                  "1000000", "--json", "--trace", "{tmp}/t.json", "--plot", "{tmp}/p.png"], ["t.json", "p.png"],
                 id="simulate"),
])
def test_one_ctrl_c_stops_the_command_with_130_and_no_report(tmp_path, argv, outputs):
    argv = [a.format(tmp=tmp_path) for a in argv]
    code, out, err = _interrupt(argv, tmp_path)
    assert code == 130, (code, err[-2000:])
    assert "Traceback" not in err and "interrupted (Ctrl-C)" in err, err[-2000:]
    _json_error_only(out)
    for name in outputs:
        assert not (tmp_path / name).exists(), name
    assert not any(p.name.startswith(".tmp-") for p in tmp_path.iterdir())   # no half-written file


CAMPAIGN = """\
format: swarmproof-campaign/1
name: long
explore:
  - algorithm: song2016
    properties: [termination, formation]
    robots: [3, 6]
    seeds: [0, 1, 2, 3, 4, 5, 6, 7]
    max_examples: 200
"""


@pytest.mark.slow   # a local Dask cluster must start and run tasks first (about 25 s here)
def test_ctrl_c_stops_a_campaign_with_130_without_report_md(tmp_path):
    """The campaign's client caught KeyboardInterrupt and exited 3 with a report.md; now 130, no
    report.md, what finished kept for --resume."""
    (tmp_path / "long.yaml").write_text(CAMPAIGN)
    # long enough for the local cluster to start and run tasks (the client then catches the interrupt)
    code, out, err = _interrupt(["campaign", "long.yaml", "--workers", "1", "--out", "c", "--json"], tmp_path,
                                settle=15)
    assert code == 130, (code, err[-2000:])
    assert "Traceback" not in err and "interrupted (Ctrl-C)" in err, err[-2000:]
    assert "tasks finished, kept in c/results.sqlite; --resume continues the campaign" in err, err[-2000:]
    _json_error_only(out)
    assert not (tmp_path / "c" / "report.md").exists()


def test_a_swallowed_ctrl_c_still_exits_130_and_prints_no_report(cli, monkeypatch):
    """A library that catches KeyboardInterrupt and goes on (as Dask's client or an algorithm may)
    cannot turn Ctrl-C into a complete-looking report: the press is remembered."""
    from swarmproof.commands import human, prove
    from swarmproof.models import interrupt

    def swallowing_run(args):
        try:
            interrupt.handler(signal.SIGINT, None)       # what one Ctrl-C does
        except KeyboardInterrupt:
            pass                                         # ...swallowed by someone
        human(args, "lemma  proved")                     # the report it would print
        return 0
    monkeypatch.setattr(prove, "run", swallowing_run)
    code, out, err = cli("prove")
    assert code == 130 and out == "" and "interrupted (Ctrl-C)" in err
    monkeypatch.undo()
    code, _, _ = cli("prove", "translation_invariance")
    assert code == 0


def test_no_file_is_written_after_ctrl_c(tmp_path):
    from swarmproof.models import interrupt
    from swarmproof.models.fileio import atomic_write_text

    interrupt.note()
    try:
        with pytest.raises(KeyboardInterrupt):
            atomic_write_text(tmp_path / "report.md", "# complete-looking\n")
    finally:
        interrupt.reset()
    assert list(tmp_path.iterdir()) == []


def test_a_ctrl_c_while_the_modules_load_is_exit_130_without_a_traceback():
    """The console script's entry (swarmproof.entry) imports only sys before the CLI loads: a Ctrl-C
    while numpy, z3 and the commands load (the first half second) ends the command as one pressed
    later does (a new user's review of issue 34 found the traceback).  The KeyboardInterrupt is
    raised where a real SIGINT lands, inside the import of the CLI -- deterministic, unlike a timer."""
    child = ("import sys, types\n"
             "class Loading(types.ModuleType):\n"
             "    def __getattr__(self, name):\n"
             "        raise KeyboardInterrupt\n"
             "sys.modules['swarmproof.cli'] = Loading('swarmproof.cli')\n"
             "from swarmproof.entry import main\n"
             "main()\n")
    proc = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 130 and "Traceback" not in proc.stderr
    assert proc.stderr.strip() == "swarmproof: interrupted (Ctrl-C); no report was written" and proc.stdout == ""


def test_the_package_loads_nothing_heavy_before_the_entry_runs():
    """``import swarmproof.entry`` (what the console script does first) imports neither numpy nor the CLI."""
    proc = subprocess.run([sys.executable, "-c", "import sys, swarmproof.entry; "
                           "print(sorted(m for m in ('numpy', 'z3', 'swarmproof.cli', 'swarmproof.models') "
                           "if m in sys.modules))"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stderr
