"""Fuzz the command line (issue 13, "one rule for every command"): random argument vectors and
random files -- binary, empty, huge numbers, folders, existing files, missing paths -- for every
subcommand; never a traceback, always a documented exit code, never 4 (swarmproof's own bug).

Every drawn command is bounded (few robots, few steps, few examples, short timeouts) so the
whole test stays within seconds; the slow suite runs more examples."""

from __future__ import annotations

import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

#: the two tests share SEEN, so they run on one xdist worker (``--dist loadgroup``)
pytestmark = pytest.mark.xdist_group("fuzz")

DOCUMENTED = {0, 1, 2, 3}
SEEN: list = []


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("fuzz")
    (d / "binary.json").write_bytes(bytes(range(256)) * 4)
    (d / "empty.yaml").write_text("")
    (d / "huge.yaml").write_text("format: lattice-graph/1\nrange: 1e308\nroles: [A]\n"
                                 "edges:\n  - [A, A, [1e308, 0, 0]]\n  - [A, A, [-1e308, 0, 0]]\n")
    (d / "nan.json").write_text('{"format": "swarmproof-counterexample/1", "version": 1, "params": NaN}')
    (d / "list.json").write_text("[1, 2, 3]")
    (d / "existing.txt").write_text("x")
    (d / "folder").mkdir()
    # issue 29: magnitudes (item 1), a duplicate-heavy file (item 2), repeated keys and deep nesting (item 11)
    (d / "e308.json").write_text('{"format": "lattice-graph/1", "range": 1.2, "roles": ["A"], "edges": '
                                 '[["A", "A", 1e308, 0, 0], ["A", "A", -1e308, 0, 0]]}')
    (d / "e160.yaml").write_text("format: lattice-graph/1\nrange: 1.0e+160\nroles: [A]\nedges:\n"
                                 "  - [A, A, 1.0e+160, 0, 0]\n  - [A, A, -1.0e+160, 0, 0]\n")
    (d / "dups.yaml").write_text("format: lattice-graph/1\nrange: 1.2\nroles: [A]\nedges:\n"
                                 + "  - [A, A, 1, 0, 0]\n" * 300 + "  - [A, A, -1, 0, 0]\n")
    (d / "twice.yaml").write_text("format: swarmproof-campaign/1\nname: x\nname: y\nformat: lattice-graph/1\n"
                                  "roles: [A]\nedges: []\nexplore:\n  - algorithm: song2014\n")
    (d / "deep.yaml").write_text("format: lattice-graph/1\nroles: " + "[" * 50_000 + "]" * 50_000 + "\n")
    return {"binary": str(d / "binary.json"), "empty": str(d / "empty.yaml"), "huge": str(d / "huge.yaml"),
            "e308": str(d / "e308.json"), "e160": str(d / "e160.yaml"), "dups": str(d / "dups.yaml"),
            "twice": str(d / "twice.yaml"), "deep": str(d / "deep.yaml"),
            "nan": str(d / "nan.json"), "list": str(d / "list.json"), "existing": str(d / "existing.txt"),
            "folder": str(d / "folder"), "missing": str(d / "no" / "such.json"), "blank": ""}


WORDS = st.sampled_from(["square", "hexagon", "song2016", "example-gather", "nope", "lines:line", "shape:square-9",
                         "mymod:Nope", "a:b:c", "0", "-1", "1e308", "nan", "inf", "3..2", "2..3", "x=1", "=",
                         "", " ", "\u00e9\u00e8", "--", "-"])
NUMBERS = st.sampled_from(["0", "1", "2", "-1", "1e308", "-1e308", "nan", "inf", "0.5", "3", "abc", "", "none",
                           "1e-300"])
#: issue 29: unknown keys (misspelt ones too), values out of their declared range, every algorithm
PARAMS = st.one_of(WORDS, st.sampled_from(["foo=1", "arnea=5", "comunication_timeout=3", "broadcast_every=0",
                                           "p_random=-1", "d_s=nan", "gap=-1", "arrive_tol=0", "rumor_filter=x"]))


def _argv(draw, files):
    cmd = draw(st.sampled_from(["check-lattice", "simulate", "explore", "replay", "prove", "verify",
                                "check-pattern", "campaign", "list"]))
    fileval = st.sampled_from(sorted(files.values()))
    argv = [cmd]
    if cmd == "check-lattice":
        argv.append(draw(st.one_of(fileval, WORDS)))
        opts = {"--range": NUMBERS, "--pos-tol": NUMBERS, "--ang-tol": NUMBERS, "--plot": fileval}
    elif cmd == "simulate":
        argv.append(draw(WORDS))
        opts = {"--target": st.one_of(WORDS, fileval), "--lattice": st.one_of(WORDS, fileval),
                "--robots": st.sampled_from(["1", "3", "0", "-2", "x"]), "--seed": NUMBERS,
                "--range": NUMBERS, "--v": NUMBERS, "--dt": NUMBERS, "--initial": fileval,
                "--trace": fileval, "--plot": fileval, "--param": PARAMS, "--record-every": NUMBERS,
                "--shape": WORDS, "--omega": NUMBERS,
                "--timeout": st.sampled_from(["5", "0", "-1", "nan", "1e10", "1e308", "x"])}
        argv += ["--max-steps", "40"]
    elif cmd == "explore":
        argv.append(draw(st.one_of(WORDS, st.sampled_from(["wang2020", "song2014", "example-grid-goals"]))))
        # issue 29: teams the explorer cannot draw (300, 3000, 1000000) are refused, never exit 4
        opts = {"--property": WORDS, "--robots": st.sampled_from(["2..3", "3", "0..1", "x", "300..300", "3000",
                                                                  "1000000", "65..65"]),
                "--seed": NUMBERS, "--out": fileval, "--lattice": st.one_of(WORDS, fileval),
                "--fault": WORDS, "--v": NUMBERS, "--dt": NUMBERS, "--param": PARAMS,
                "--speeds": st.one_of(WORDS, st.sampled_from(["-1,0.05", "0.05,0", "1e-300"])),
                "--budget": st.sampled_from(["5", "none", "0", "-1", "nan", "inf", "x", "1e10", "1e308"])}
        argv += ["--max-examples", "2", "--max-steps", "40"]
    elif cmd == "check-pattern":
        argv.append(draw(st.one_of(fileval, WORDS)))
        opts = {"--copies": NUMBERS, "--list": st.just("--json")}
    elif cmd == "campaign":
        argv.append(draw(fileval))
        opts = {"--workers": NUMBERS}
        argv += ["--out", os.path.join(os.path.dirname(files["empty"]), "campaign-out")]
    elif cmd == "replay":
        argv.append(draw(st.one_of(fileval, WORDS)))
        opts = {"--plot": fileval, "--gif": fileval}
    elif cmd == "prove":
        # always one name: the whole suite (18 lemmas, ~18 s of z3) is tests/cli/test_prove.py's
        # test_whole_suite_json_exit_0; here it would be most of the fuzz test's time
        argv += [draw(st.sampled_from(["bounded_range", "nclb_link_kept", "nope", ""]))]
        opts = {"--timeout": st.sampled_from(["0.5", "0", "-1", "1e308", "nan", "x"])}
    elif cmd == "list":
        # issue 29: swarmproof list [KIND] [--json]; unknown kinds are exit 2
        argv += draw(st.lists(st.one_of(st.sampled_from(["algorithms", "properties", "lemmas", "targets",
                                                         "patterns", "shapes"]), WORDS), max_size=2))
        opts = {"--json": st.just("--json")}
    else:
        argv += ["--section", draw(st.sampled_from(["lattices", "nope", ""]))]
        opts = {"--out": fileval, "--seed": NUMBERS}
    for opt in draw(st.lists(st.sampled_from(sorted(opts)), max_size=3, unique=True)):
        argv += [opt, draw(opts[opt])]
    if draw(st.booleans()):
        argv.append("--json")
    return argv


@settings(max_examples=150, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_no_traceback_and_a_documented_exit_code(data, files, capsys, monkeypatch, tmp_path_factory):
    from swarmproof.cli import main

    monkeypatch.chdir(tmp_path_factory.getbasetemp())
    argv = _argv(data.draw, files)
    code = main(argv)
    out, err = capsys.readouterr()
    SEEN.append((argv[0], code))
    assert code in DOCUMENTED, (argv, code, err[-500:])
    assert "Traceback" not in err and "Traceback" not in out, (argv, err[-500:])
    if "--json" in argv and "--" not in argv and code == 2:
        import json

        doc = json.loads(out)
        assert doc["exit_code"] == 2 and doc["error"]["kind"] == "usage"


def test_the_fuzzing_reached_every_command_and_more_than_usage_errors():
    """The fuzz test above ran first (same module): it must not have tested only argparse."""
    if not SEEN:
        pytest.skip("run with the fuzz test")
    assert {c for c, _ in SEEN} == {"check-lattice", "simulate", "explore", "replay", "prove", "verify",
                                    "check-pattern", "campaign", "list"}
    assert {code for _, code in SEEN} - {2}, "every drawn command was a usage error"
