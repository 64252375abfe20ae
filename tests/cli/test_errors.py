"""One rule for every command (issue 13): a user's mistake exits 2 naming the cause and the
fix; swarmproof's own bug exits 4 with one line naming the traceback file; ``--json`` prints
a JSON error document on stdout in both cases; files are written with the user's umask."""

from __future__ import annotations

import json
import os
import stat

import pytest

from swarmproof import cli
from swarmproof.commands import check_lattice
from swarmproof.models.fileio import atomic_write_text


def run(capsys, *argv):
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _boom(args):
    raise RuntimeError("something inside swarmproof broke\nsecond line")


@pytest.mark.parametrize("as_json", [False, True], ids=["human", "json"])
def test_internal_error_exits_4_with_one_line_and_a_traceback_file(capsys, monkeypatch, as_json):
    monkeypatch.setattr(check_lattice, "run", _boom)
    argv = ["check-lattice", "square"] + (["--json"] if as_json else [])
    code, out, err = run(capsys, *argv)
    assert code == 4
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("swarmproof check-lattice: internal error (a bug in swarmproof, please report it): "
                               "RuntimeError: something inside swarmproof broke; the traceback is in ")
    path = lines[0].rsplit(" ", 1)[1]
    try:
        text = open(path, encoding="utf-8").read()
        assert "Traceback (most recent call last)" in text and "_boom" in text
    finally:
        os.unlink(path)
    assert "Traceback" not in err
    if as_json:
        doc = json.loads(out)
        assert doc["exit_code"] == 4 and doc["command"] == "check-lattice"
        assert doc["error"]["kind"] == "internal" and doc["error"]["traceback"] == path
    else:
        assert out == ""


BAD = [
    (["check-lattice", "square", "--pos-tol", "10"], "pos_tol=10.0 is too large for this graph"),
    (["check-lattice", "square", "--pos-tol", "-1"], "--pos-tol='-1' must be a finite number > 0"),
    (["check-lattice", "square", "--ang-tol", "1"], "ang_tol=1.0 rad is too large"),
    (["check-lattice", "square", "--range", "0"], "--range='0' must be a finite number > 0"),
    (["check-lattice", "square", "--plot", ""], "--plot='' is empty"),
    (["prove", "nclb_link_kept", "--timeout", "1e308"], "--timeout='1e308' must be > 0 and at most 86400"),
    (["prove", "nclb_link_kept", "--timeout", "0"], "--timeout='0' must be > 0"),
]


@pytest.mark.parametrize("argv,message", BAD, ids=["pos-tol-10", "pos-tol-negative", "ang-tol-1", "range-0",
                                                    "plot-empty", "timeout-1e308", "timeout-0"])
@pytest.mark.parametrize("as_json", [False, True], ids=["human", "json"])
def test_bad_input_exits_2_naming_the_value(capsys, argv, message, as_json):
    code, out, err = run(capsys, *(argv + (["--json"] if as_json else [])))
    assert code == 2
    assert message in err and "fix:" in err
    assert "Traceback" not in err
    if as_json:
        doc = json.loads(out)
        assert doc["exit_code"] == 2 and doc["error"]["kind"] == "usage"
        assert message in doc["error"]["message"]
    else:
        assert out == ""


def test_plot_into_a_folder_is_refused_before_any_work(capsys, tmp_path):
    code, out, err = run(capsys, "check-lattice", "square", "--plot", str(tmp_path))
    assert code == 2
    assert f"--plot={str(tmp_path)!r} is a folder" in err
    assert list(tmp_path.iterdir()) == []


def test_an_oserror_on_a_users_file_is_exit_2(capsys, monkeypatch):
    def denied(args):
        raise PermissionError(13, "Permission denied", "/root/secret.yaml")

    monkeypatch.setattr(check_lattice, "run", denied)
    code, out, err = run(capsys, "check-lattice", "x")
    assert code == 2
    assert err.strip() == ("swarmproof check-lattice: error: PermissionError: Permission denied: "
                           "path='/root/secret.yaml'; fix: check the path, its permissions and the free disk space")


@pytest.mark.parametrize("mask,mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)],
                         ids=["umask-022", "umask-077", "umask-002"])
def test_written_files_follow_the_umask(tmp_path, mask, mode):
    old = os.umask(mask)
    try:
        path = atomic_write_text(tmp_path / "out.json", "{}\n")
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(path).st_mode) == mode
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]
