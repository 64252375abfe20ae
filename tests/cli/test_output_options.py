"""Issue 29 items 7 and 15: every output option of every command goes through one check before any
work (swarmproof.commands.outputs): a missing folder, a folder for a file, a regular file for a
folder, a suffix of another format -- exit 2 naming the option, nothing created, the command not run.

The options are read from the parsers, so an output option added later is tested too (and
``test_every_option_that_writes_is_in_the_table`` fails on one the table does not know)."""

from __future__ import annotations

import argparse
import importlib
import re

import pytest

from swarmproof.cli import COMMAND_MODULES, build_parser, main
from swarmproof.commands.outputs import OUTPUT_OPTIONS


def _subparsers() -> dict:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


#: the least command line each command parses (its inputs need not exist: nothing runs)
BASE = {
    "check-lattice": ["square"],
    "check-pattern": ["rhombus-triangles"],
    "simulate": ["song2016", "--lattice", "square", "--robots", "3", "--seed", "0"],
    "prove": [],
    "verify": [],
    "campaign": ["spec.yaml"],
    "explore": ["song2016"],
    "replay": ["cx.json"],
    "check-run": ["run.csv"],
    "export": ["trace.json"],
    "list": [],
}

#: command name -> its module in swarmproof.commands
MODULE_OF = {importlib.import_module(f"swarmproof.commands.{m}").NAME: m for m in COMMAND_MODULES}

OUTPUTS = sorted((name, action.option_strings[-1], action.dest)
                 for name, p in _subparsers().items() for action in p._actions
                 if action.dest in OUTPUT_OPTIONS and action.option_strings)


def test_the_parsers_have_the_output_options_we_know_of():
    found = {(c, o) for c, o, _ in OUTPUTS}
    assert {("replay", "--gif"), ("replay", "--plot"), ("simulate", "--trace"), ("simulate", "--gif"),
            ("verify", "--junit"), ("verify", "--html"), ("verify", "--markdown"), ("verify", "--out"),
            ("explore", "--out"), ("explore", "--database"), ("campaign", "--out"),
            ("check-lattice", "--plot"), ("check-pattern", "--plot"), ("simulate", "--export"), ("export", "--to"),
            ("check-run", "--plot"), ("check-run", "--gif")} <= found
    assert set(BASE) == set(_subparsers())      # a new command needs its least command line here


def test_every_option_that_writes_is_in_the_table():
    """An option taking a value whose metavar or help says it writes a file or a folder is an output
    option (verify's --baseline FILE, read and with --update-baseline written, is checked by the gate)."""
    writes = []
    for name, p in _subparsers().items():
        for a in p._actions:
            text = (a.help or "").lower()
            if a.option_strings and a.nargs != 0 and (a.metavar in ("PNG", "GIF", "DIR") or text.startswith("write ")
                                     or text.startswith("keep ") and "in dir" in text):
                writes.append((name, a.option_strings[-1], a.dest))
    assert writes and all(dest in OUTPUT_OPTIONS for _, _, dest in writes), writes


@pytest.fixture
def nothing_runs(monkeypatch):
    """Every command's ``run`` fails the test if it is called: the check must come first."""
    for modname in COMMAND_MODULES:
        mod = importlib.import_module(f"swarmproof.commands.{modname}")

        def ran(args, _name=mod.NAME):
            raise AssertionError(f"{_name} ran before its output options were checked")
        monkeypatch.setattr(mod, "run", ran)


def _case(command, option, dest, kind, tmp_path):
    spec = OUTPUT_OPTIONS[dest]
    good = spec.suffixes[0] if spec.suffixes else ""
    if kind == "missing-folder":
        return str(tmp_path / "nonexistent" / f"x{good}"), r"does not exist"
    if kind == "a-folder":
        return str(tmp_path), r"is a folder"
    if kind == "wrong-suffix" and spec.kind == "log":
        return str(tmp_path / "x.txt"), r"the suffix '\.txt' is not a log format; fix: end it with \.csv or \.mcap"
    if kind == "wrong-suffix":
        return str(tmp_path / "x.txt"), r"the suffix '\.txt' is not a format .* writes; fix: end the name with \."
    if kind == "exists":              # a rosbag2 bag is a new folder: an existing one is never written into
        return str(tmp_path), r"exists already"
    if kind == "missing-folder-bag":
        return str(tmp_path / "nonexistent" / "bag"), r"does not exist"
    if kind == "a-file":
        f = tmp_path / "plain-file"
        f.write_text("x")
        return str(f), r"is a file, not a folder"
    if kind == "below-a-file":        # no folder can be made under a regular file (it used to pass the check)
        f = tmp_path / "plain-file"
        f.write_text("x")
        return str(f / "sub"), r"'[^']*plain-file' is a file, so no folder can be made below it"
    raise AssertionError(kind)


BAD = [pytest.param(c, o, d, kind, id=f"{c}-{o}-{kind}")
       for c, o, d in OUTPUTS
       for kind in (("missing-folder", "a-folder", "wrong-suffix") if OUTPUT_OPTIONS[d].kind == "file"
                    else ("missing-folder", "missing-folder-bag", "wrong-suffix", "exists")
                    if OUTPUT_OPTIONS[d].kind == "log" else ("a-file", "below-a-file"))]


@pytest.mark.parametrize("command, option, dest, kind", BAD)
def test_a_bad_output_is_refused_before_any_work(capsys, tmp_path, nothing_runs, command, option, dest, kind):
    value, match = _case(command, option, dest, kind, tmp_path)
    code = main([command, *BASE[command], option, value])
    out, err = capsys.readouterr()
    assert code == 2, err
    assert f"{option}=" in err and "fix:" in err, err
    assert re.search(match, err), err
    assert not (tmp_path / "nonexistent").exists()       # nothing created for a refused option


@pytest.mark.parametrize("command, option, dest",
                         [pytest.param(c, o, d, id=f"{c}-{o}") for c, o, d in OUTPUTS])
def test_a_good_output_passes_the_check(capsys, tmp_path, monkeypatch, command, option, dest):
    mod = importlib.import_module(f"swarmproof.commands.{MODULE_OF[command]}")
    monkeypatch.setattr(mod, "run", lambda args: 0)
    spec = OUTPUT_OPTIONS[dest]
    value = str(tmp_path / ("new-folder" if spec.kind == "folder" else f"x{spec.suffixes[-1]}"))
    assert main([command, *BASE[command], option, value]) == 0, capsys.readouterr().err


def test_replay_gif_into_a_missing_folder_creates_nothing(capsys, tmp_path):
    """The issue's command, run for real: exit 2 and no folder created (it used to create it)."""
    from swarmproof.models.counterexample import Counterexample

    cx = Counterexample(algorithm="song2014", params={"range": 1.2, "v": 0.05, "omega": 0.785, "dt": 1.0},
                        lattice="square", robots=[(0, (0.0, 0.0, 0.0)), (1, (1.0, 0.0, 0.0))], seed=0,
                        property="connectivity", violation={"step": 1, "message": "split"})
    good = cx.save(tmp_path / "good.json")
    code = main(["replay", good, "--gif", str(tmp_path / "nonexistent" / "x.gif")])
    err = capsys.readouterr().err
    assert code == 2 and "--gif=" in err and "does not exist" in err
    assert not (tmp_path / "nonexistent").exists()
