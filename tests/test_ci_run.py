"""`.ci/run` runs `make test` then `make verify` and fails when either fails; `make test` turns
pytest's exit 5 (no test collected) into a failure that says so.  Both with stand-ins for make and
for the venv's python, so they take a second."""

from __future__ import annotations

import os
import subprocess

import pytest

from testkit import ROOT

STUB = """#!/usr/bin/env bash
echo "make $*" >> "$CI_LOG"
if [ "$1" = "$CI_FAIL" ]; then exit 2; fi
"""


def _ci_run(tmp_path, fail: str = ""):
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    make = bin_ / "make"
    make.write_text(STUB)
    make.chmod(0o755)
    log = tmp_path / "log"
    env = {**os.environ, "PATH": f"{bin_}{os.pathsep}{os.environ['PATH']}", "CI_LOG": str(log), "CI_FAIL": fail,
           "CI": "true"}
    proc = subprocess.run(["bash", os.path.join(ROOT, ".ci", "run")], env=env, capture_output=True, text=True,
                          stdin=subprocess.DEVNULL, timeout=60)
    return proc, log.read_text().splitlines() if log.exists() else []


def test_ci_runs_make_test_then_make_verify(tmp_path):
    proc, calls = _ci_run(tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert calls == ["make test", "make verify"]
    assert proc.stdout.splitlines()[-1] == ".ci/run: make test and make verify passed"


@pytest.mark.parametrize("fail, calls", [("test", ["make test"]), ("verify", ["make test", "make verify"])])
def test_a_failing_step_fails_ci(tmp_path, fail, calls):
    proc, seen = _ci_run(tmp_path, fail)
    assert proc.returncode == 2
    assert seen == calls
    assert f".ci/run: FAILED: make {fail} exited 2" in proc.stdout


def test_make_test_fails_on_pytest_exit_5(tmp_path):
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    python = bin_ / "python"
    python.write_text("#!/usr/bin/env bash\necho \"python $*\"\nexit 5\n")
    python.chmod(0o755)
    stamp = tmp_path / "stamp"
    stamp.write_text("")
    os.utime(stamp, (2**31, 2**31))        # newer than pyproject.toml: no install
    proc = subprocess.run(["make", "--no-print-directory", "-C", ROOT, "test", f"BIN={bin_}", f"STAMP={stamp}"],
                          capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=60)
    assert proc.returncode != 0
    assert "python -m pytest -q -n auto --dist loadgroup" in proc.stdout
    assert "make test: pytest collected no test (exit 5): the suite ran nothing, which is a failure" in proc.stdout
