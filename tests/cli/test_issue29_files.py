"""Issue 29, lattice, pattern and campaign files (defects 1, 2, 11, 12 and 15's check-pattern item):
every bad file is exit 2 with file, line, field, the value, the limit and a fix; never exit 4,
never a crash; duplicate positions grouped; one safe YAML reader; messages that show the
difference they state."""

from __future__ import annotations

import io
import json
import math

import pytest

from swarmproof.cli import main


def _lattice_json(rows, extra=""):
    body = ",\n".join("    " + json.dumps(r) for r in rows)
    return ('{\n  "format": "lattice-graph/1",\n  "range": 1.2,\n  "roles": ["A"],' + extra
            + '\n  "edges": [\n' + body + "\n  ]\n}\n")


SQUARE_ROWS = [["A", "A", 1, 0, 0], ["A", "A", -1, 0, 0], ["A", "A", 0, 1, 0], ["A", "A", 0, -1, 0]]
SQUARE_YAML = """format: lattice-graph/1
range: 1.2
roles: [A]
edges:
  - [A, A, 1, 0, 0]
  - [A, A, -1, 0, 0]
  - [A, A, 0, 1, 0]
  - [A, A, 0, -1, 0]
"""

# (id, file name, text, argv after the file, exit code, regex for stderr)
BAD_FILES = [
    ("json-x-1e308", "big.json", _lattice_json([["A", "A", 1e308, 0, 0], ["A", "A", -1e308, 0, 0]]), [], 2,
     r"big\.json:6: field 'edges\[0\]\[2\]': edges\[0\]\[2\]=1e\+308 is beyond the bound \|x\| <= 1e6; "
     r"fix: scale the whole lattice"),
    ("json-x-1e160", "e160.json", _lattice_json([["A", "A", 1e160, 0, 0], ["A", "A", -1e160, 0, 0]]), [], 2,
     r"e160\.json:6: field 'edges\[0\]\[2\]': edges\[0\]\[2\]=1e\+160 is beyond the bound \|x\| <= 1e6"),
    ("yaml-y-1.0e+308", "big.yaml", SQUARE_YAML.replace("[A, A, 0, 1, 0]", "[A, A, 0, 1.0e+308, 0]"), [], 2,
     r"big\.yaml:7: field 'edges\[2\]\[3\]': edges\[2\]\[3\]=1e\+308 is beyond the bound \|y\| <= 1e6"),
    ("yaml-range-1e308", "r.yaml", SQUARE_YAML.replace("range: 1.2", "range: 1.0e+308"), [], 2,
     r"r\.yaml:2: field 'range': range=1e\+308 is beyond the bound \|range\| <= 1e6; fix: scale"),
    ("yaml-range-huge-int", "ri.yaml", SQUARE_YAML.replace("range: 1.2", "range: 1" + "0" * 308), [], 2,
     r"ri\.yaml:2: field 'range': range=1e\+308 is beyond the bound"),
    ("yaml-theta-1e9", "t.yaml", SQUARE_YAML.replace("[A, A, 1, 0, 0]", "[A, A, 1, 0, 1.0e+9]"), [], 2,
     r"t\.yaml:5: field 'edges\[0\]\[4\]': edges\[0\]\[4\]=1000000000 is beyond the bound \|theta\| <= 1e6; "
     r"fix: reduce the angle modulo 360"),
    ("yaml-exponent-as-text", "s.yaml", SQUARE_YAML.replace("[A, A, 1, 0, 0]", "[A, A, 1.0e308, 0, 0]"), [], 2,
     r"s\.yaml:5: field 'edges\[0\]\[2\]': edges\[0\]\[2\]='1\.0e308' must be a number, got str; fix: write x "
     r"as a plain number \(YAML 1\.1 reads 1\.0e308 as text: .*: write 1\.0e\+308\); and note \|x\| <= 1e6"),
    ("duplicate-key-nested", "d.yaml", SQUARE_YAML + "roles: [B]\n", [], 2,
     r"d\.yaml:9: field 'roles': key 'roles' appears twice \(lines 3 and 9\); fix: keep one of them"),
    ("deep-nesting-yaml", "n.yaml", "format: lattice-graph/1\nroles: " + "[" * 200_000 + "]" * 200_000, [], 2,
     r"n\.yaml: malformed YAML: nesting is too deep"),
    ("deep-block-nesting-yaml", "b.yaml", "- " * 100_000 + "x\n", [], 2,
     r"b\.yaml: malformed YAML: nesting is too deep"),
]


@pytest.mark.parametrize("name,text,extra,code,pattern", [c[1:] for c in BAD_FILES],
                         ids=[c[0] for c in BAD_FILES])
def test_bad_lattice_files_are_usage_errors(tmp_path, capsys, name, text, extra, code, pattern):
    path = tmp_path / name
    path.write_text(text)
    assert main(["check-lattice", str(path), *extra]) == code
    out, err = capsys.readouterr()
    assert out == ""
    assert "Traceback" not in err
    import re
    assert re.search(pattern, err), err


def test_simulate_refuses_a_huge_lattice_before_running(tmp_path, capsys):
    path = tmp_path / "big.json"
    path.write_text(_lattice_json([["A", "A", 1e160, 0, 0], ["A", "A", -1e160, 0, 0]]))
    assert main(["simulate", "song2016", "--lattice", str(path), "--robots", "3", "--seed", "0", "--max-steps", "5"]) == 2
    err = capsys.readouterr().err
    assert "is beyond the bound |x| <= 1e6" in err and "Warning" not in err and "warning" not in err


# ---- item 2: duplicates grouped, sizes limited ---------------------------------------------

def test_identical_rows_are_one_duplicate_group(tmp_path, capsys):
    path = tmp_path / "dup.json"
    path.write_text(_lattice_json([["A", "A", 1, 0, 0]] * 1000 + SQUARE_ROWS[1:]))
    assert main(["check-lattice", str(path), "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    dups = [d for d in doc["defects"] if d["kind"] == "duplicate_position"]
    assert len(dups) == 1
    assert dups[0]["edges"] == list(range(1000))
    assert "role 'A' has 1000 out-edges to one position" in dups[0]["message"]


def test_near_duplicates_across_a_cell_boundary_are_found():
    from swarmproof.checkers.lattice_check import _duplicate_groups

    pt = 1e-7
    # 0.99999999e-7 and 1.00000001e-7 straddle a cell boundary; 5e-7 is far from both
    assert _duplicate_groups([(0.99999999e-7, 0.0), (1.00000001e-7, 0.0), (5e-7, 0.0)], pt) == [[0, 1]]
    assert _duplicate_groups([(0.0, 0.0), (3e-7, 0.0)], pt) == []
    # chains join: a-b within pt and b-c within pt make one group
    assert _duplicate_groups([(0.0, 0.0), (0.9e-7, 0.0), (1.8e-7, 0.0)], pt) == [[0, 1, 2]]


def _inverse_indices_pairwise(graph, pt, at):
    """The definition: for each edge, the first edge (file order) that is its inverse."""
    out = []
    for e in graph.edges:
        t = e.transform.inverse()
        out.append(next((c.index for c in graph.edges if c.source == e.target and c.target == e.source
                         and c.transform.isclose(t, pt, at)), None))
    return out


def test_inverse_lookup_matches_the_pairwise_definition():
    """The hashed inverse lookup (item 2: linear in the rows) finds the same edge as comparing
    every pair: the first in file order, across cell boundaries, with angles on the circle and
    with exact copies answered once."""
    import math
    import random

    from swarmproof.checkers.lattice_check import _inverse_indices
    from swarmproof.models.lattice import LatticeGraph
    from swarmproof.models.se2 import SE2

    rng = random.Random(29)
    pt, at = 1e-7, 1e-6
    base = [(1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 1.0, math.pi / 2), (0.0, -1.0, -math.pi / 2)]
    rows = []
    for _ in range(400):
        x, y, th = rng.choice(base)
        # jitter within and just beyond the tolerances, straddling cell edges; angles near +-pi
        x += rng.choice([0.0, 0.4e-7, -0.9e-7, 1.1e-7, 2.5e-7])
        y += rng.choice([0.0, 0.99e-7, -1.01e-7])
        th = rng.choice([th, th + 0.5e-6, math.pi - 1e-7, -math.pi + 1e-7])
        a, b = rng.choice([("A", "A"), ("A", "B"), ("B", "A")])
        rows.append((a, b, SE2(x, y, th)))
    rows += [rows[5]] * 50                                   # exact copies
    g = LatticeGraph("jitter", ["A", "B"], rows, range=3.0)
    got = _inverse_indices(g, pt, at)
    assert got == _inverse_indices_pairwise(g, pt, at)
    assert sum(i is not None for i in got) > 100 and None in got      # both answers occur


def test_inverse_lookup_of_many_copies_is_linear(monkeypatch):
    """10,000 copies of one row, 10,000 of another and one inverse: the lookup compares a number
    of transforms linear in the rows (30,000 copies took 177 s before, comparing every pair)."""
    from swarmproof.checkers.lattice_check import _inverse_indices
    from swarmproof.models.lattice import LatticeGraph
    from swarmproof.models.se2 import SE2

    n = 10000
    rows = [("A", "A", SE2(1.0, 0.0, 0.5))] * n + [("A", "A", SE2(0.0, 1.0, 0.0))] * n
    rows.append(("A", "A", SE2(1.0, 0.0, 0.5).inverse()))
    g = LatticeGraph("copies", ["A"], rows, range=3.0)
    calls = []
    real = SE2.isclose
    monkeypatch.setattr(SE2, "isclose", lambda self, *a: calls.append(1) or real(self, *a))
    got = _inverse_indices(g, 1e-7, 1e-6)
    assert got[0] == 2 * n and got[n] is None and got[2 * n] == 0
    assert len(calls) <= 10, len(calls)     # pairwise: about n * (2n + 1) comparisons


@pytest.mark.parametrize("what,limit_name,pattern", [
    ("roles", "MAX_ROLES", r"field 'roles': roles has 4 entries, more than the limit of 3; fix: check at most 3 roles"),
    ("edges", "MAX_EDGES", r"field 'edges': edges has 4 rows, more than the limit of 3; fix: check at most 3 edges"),
    ("bytes", "MAX_FILE_BYTES", r"the file is 0\.0 MB, more than the limit of 0 MB .*; fix: check a smaller"),
], ids=["roles", "edges", "file-size"])
def test_size_limits_are_usage_errors(tmp_path, capsys, monkeypatch, what, limit_name, pattern):
    import re

    from swarmproof.models import lattice_io

    monkeypatch.setattr(lattice_io, limit_name, 3 if what != "bytes" else 100)
    path = tmp_path / "big.yaml"
    path.write_text(SQUARE_YAML.replace("roles: [A]", "roles: [A, B, C, D]"))
    assert main(["check-lattice", str(path)]) == 2
    err = capsys.readouterr().err
    assert re.search(pattern, err), err


def test_progress_shows_on_a_terminal_only(capsys, monkeypatch):
    import sys

    class Tty(io.StringIO):
        def isatty(self):
            return True

    tty = Tty()
    monkeypatch.setattr(sys, "stderr", tty)
    assert main(["check-lattice", "square"]) == 0
    assert "check-lattice: 1 roles, 4 edges: Def. 4: self-consistency" in tty.getvalue()
    assert tty.getvalue().endswith("\r\033[K")          # the line is erased at the end
    monkeypatch.undo()
    assert main(["check-lattice", "square"]) == 0
    assert "Def. 4" not in capsys.readouterr().err


def test_the_file_is_parsed_once(tmp_path, capsys, monkeypatch):
    """issue 29 item 2: `_file_angle_unit` parsed the file a second time with PyYAML."""
    import yaml

    from swarmproof.models import doclines

    calls = []
    real = doclines._load_with
    monkeypatch.setattr(doclines, "_load_with", lambda *a, **k: calls.append(1) or real(*a, **k))
    monkeypatch.setattr(yaml, "safe_load", lambda *a, **k: pytest.fail("a second parse"))
    path = tmp_path / "rad.yaml"
    path.write_text(SQUARE_YAML.replace("range: 1.2", "range: 1.5\nangle_unit: rad"))
    assert main(["check-lattice", str(path)]) == 1
    out = capsys.readouterr().out
    assert calls == [1]
    assert "- [A, A, 1, 1, 0]" in out     # fix rows still in the file's unit (rad)


# ---- item 11: one YAML reader, duplicate keys refused everywhere ----------------------------

CAMPAIGN = "format: swarmproof-campaign/1\nname: x\nname: y\nexplore:\n  - algorithm: song2014\n"
PATTERN = "format: repeating-pattern/1\nname: p\nbasic: [[0, 0]]\nassembling: [[1, 0], [0, 1]]\n"
INITIAL = "format: swarmproof-initial/1\nrobots:\n  - {id: 1, pose: [0, 0, 0], id: 2}\n"

DUPLICATE_KEYS = [
    ("campaign", "campaign", "c.yaml", CAMPAIGN,
     r"c\.yaml:3: field 'name': key 'name' appears twice \(lines 2 and 3\); fix: keep one of them"),
    ("campaign-nested", "campaign", "c2.yaml",
     "format: swarmproof-campaign/1\nname: x\nexplore:\n  - algorithm: song2014\n    seeds: [0]\n    seeds: [1]\n",
     r"c2\.yaml:6: field 'explore\[0\]\.seeds': key 'seeds' appears twice \(lines 5 and 6\)"),
    ("pattern", "pattern", "p.yaml", PATTERN + "name: q\n",
     r"p\.yaml:5: field 'name': key 'name' appears twice \(lines 2 and 5\)"),
    ("pattern-json", "pattern", "p.json",
     '{"format": "repeating-pattern/1",\n "basic": [[0, 0]],\n "basic": [[0, 0]], "assembling": [[1, 0]]}',
     r"p\.json:3: field 'basic': key 'basic' appears twice in one object \(lines 2, 3\)"),
    ("initial", "initial", "i.yaml", INITIAL,
     r"i\.yaml:3: field 'robots\[0\]\.id': key 'id' appears twice \(lines 3 and 3\)"),
    ("lattice-json", "lattice", "l.json", '{"format": "lattice-graph/1",\n "format": "lattice-graph/1"}',
     r"l\.json:2: field 'format': key 'format' appears twice \(lines 1 and 2\)"),
]


@pytest.mark.parametrize("kind,name,text,pattern", [c[1:] for c in DUPLICATE_KEYS],
                         ids=[c[0] for c in DUPLICATE_KEYS])
def test_duplicate_keys_are_refused_in_every_format(tmp_path, kind, name, text, pattern):
    from swarmproof.models.errors import InputFileError

    path = tmp_path / name
    path.write_text(text)
    if kind == "campaign":
        from swarmproof.models.campaign_spec import load_campaign_file as load
    elif kind == "pattern":
        from swarmproof.models.repeating_pattern import load_pattern_file as load
    elif kind == "initial":
        from swarmproof.reference_impl.initial import from_file as load
    else:
        from swarmproof.models.lattice_io import load_lattice_file as load
    with pytest.raises(InputFileError, match=pattern):
        load(str(path))


def test_campaign_duplicate_key_on_the_command_line(tmp_path, capsys):
    path = tmp_path / "c.yaml"
    path.write_text(CAMPAIGN)
    assert main(["campaign", str(path), "--out", str(tmp_path / "out")]) == 2
    assert "key 'name' appears twice (lines 2 and 3)" in capsys.readouterr().err


def test_every_yaml_read_goes_through_the_one_loader():
    """No module outside models/doclines.py calls PyYAML's loaders (safe_load, SafeLoader, ...)."""
    import pathlib
    import re

    root = pathlib.Path(__file__).resolve().parents[2]
    offenders = []
    for folder in ("models", "invariants", "reference_impl", "checkers", "swarmproof"):
        for f in (root / folder).rglob("*.py"):
            if f.name == "doclines.py":
                continue
            for n, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1):
                if re.search(r"yaml\.(safe_load|load|full_load|unsafe_load|SafeLoader|CSafeLoader|Loader|compose)\b",
                             line):
                    offenders.append(f"{f.relative_to(root)}:{n}: {line.strip()}")
    assert not offenders, offenders


def test_merge_keys_are_not_duplicates():
    from swarmproof.models.doclines import load_yaml

    data, _ = load_yaml("base: &b {a: 1, c: 3}\nd:\n  <<: *b\n  a: 2\n", "m.yaml")
    assert data["d"] == {"a": 2, "c": 3}


# ---- item 12: messages ----------------------------------------------------------------------

MESSAGES = [
    ("pattern-tol-10", ["check-pattern", "FILE"], "t.yaml", PATTERN + "tol: 10\n", 2,
     r"t\.yaml:5: field 'tol': tol=10 is not small against the pattern: its shortest distance .* is 1; "
     r"fix: tol is an equality tolerance"),
    ("pattern-range-1e308", ["check-pattern", "FILE"], "r.yaml", PATTERN + "range: 1" + "0" * 308 + "\n", 2,
     r"r\.yaml:5: field 'range': range=1e\+308 must be a finite number of size at most 1e\+06"),
    ("pattern-exponent-text", ["check-pattern", "FILE"], "e.yaml", PATTERN + "tol: 1e-6\n", 2,
     r"field 'tol': tol='1e-6' must be a number; fix: write tol as a plain number \(YAML 1\.1 .*: write 1\.0e-6\)"),
    # "range 0" was printed for 1e-300; a lattice that small underflows the checker (numpy warnings,
    # a false "dense pattern"), so it is refused, showing the value it was given
    ("lattice-range-1e-300", ["check-lattice", "FILE", "--json"], "tiny.yaml",
     SQUARE_YAML.replace("range: 1.2", "range: 1.0e-300"), 2,
     r"tiny\.yaml:2: field 'range': range=1e-300 is below the bound range >= 1e-6; fix: scale the whole lattice"),
    ("lattice-edge-1e-300", ["check-lattice", "FILE"], "edge.yaml",
     SQUARE_YAML.replace("[A, A, 1, 0, 0]", "[A, A, 1.0e-300, 0, 0]"), 2,
     r"edge\.yaml:5: field 'edges\[0\]': edges\[0\] has length 1e-300, below the bound length >= 1e-6 "
     r"\(or exactly 0\); fix: scale the whole lattice"),
    ("lattice-option-range-1e308", ["check-lattice", "FILE", "--range", "1e308"], "sq.yaml", SQUARE_YAML, 2,
     r"range=1e\+308 is beyond the bounds 1e-6 <= range <= 1e6 .*; fix: scale the lattice and the range"),
    ("lattice-option-range-1e-300", ["check-lattice", "FILE", "--range", "1e-300"], "sq.yaml", SQUARE_YAML, 2,
     r"range=1e-300 is beyond the bounds 1e-6 <= range <= 1e6"),
    ("campaign-robots-limit", ["campaign", "FILE"], "c.yaml",
     "format: swarmproof-campaign/1\nname: x\nexplore:\n  - algorithm: song2014\n    robots: [1000000, 1000000]\n", 2,
     r"c\.yaml:5: field 'explore\[0\]\.robots': explore\[0\]\.robots=\[1000000, 1000000\] must be \[MIN, MAX\] "
     r"with 1 <= MIN <= MAX <= 100000"),
    ("list-with-name", ["check-pattern", "--list", "rhombus-triangles"], None, None, 2,
     r"--list takes no name \(got FILE='rhombus-triangles'\); fix: run `swarmproof check-pattern --list`"),
]


@pytest.mark.parametrize("argv,name,text,code,pattern", [c[1:] for c in MESSAGES], ids=[c[0] for c in MESSAGES])
def test_messages(tmp_path, capsys, argv, name, text, code, pattern):
    import re

    if name is not None:
        path = tmp_path / name
        path.write_text(text)
        argv = [str(path) if a == "FILE" else a for a in argv]
    if argv[0] == "campaign":
        argv += ["--out", str(tmp_path / "out")]
    assert main(argv) == code
    out, err = capsys.readouterr()
    if pattern is not None:
        assert re.search(pattern, err), err
    if code == 2:
        assert (json.loads(out)["exit_code"] == 2 if "--json" in argv else out == "") and "Traceback" not in err and "Warning" not in err


def test_a_rounded_ring_says_that_pos_tol_decides_it(tmp_path, capsys):
    """A hexagon ring written with 3 decimals: the fix row sits beside an existing row."""
    ring = """format: lattice-graph/1
name: ring6
range: 1.5
roles: [R]
edges:
  - [R, R, 1, 0, 60]
  - [R, R, -0.5, 0.866, -60]
"""
    path = tmp_path / "ring.yaml"
    path.write_text(ring)
    code = main(["check-lattice", str(path)])
    out = capsys.readouterr().out
    assert code == 1
    assert "the tolerance decides it: try --pos-tol" in out, out
    import re

    tol = re.search(r"--pos-tol (\S+) \(now", out).group(1)
    assert main(["check-lattice", str(path), "--pos-tol", tol]) == 0, capsys.readouterr()


def test_comparison_messages_show_the_difference():
    from swarmproof.models.doclines import distinct_texts, num_text

    a, b = distinct_texts(0.19999999999, 0.2)
    assert a != b and float(a) < float(b)
    assert distinct_texts(0.1936, 0.2) == ("0.1936", "0.2")
    assert num_text(1e-300) == "1e-300" and num_text(10 ** 308) == "1e+308"
    assert not math.isnan(float(num_text(2.5)))
