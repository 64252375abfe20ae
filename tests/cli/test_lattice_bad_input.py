"""``swarmproof check-lattice`` on bad lattice files: exit 2, file/line/field/fix on
stderr, no traceback, nothing on stdout with ``--json`` (DESIGN.md section 2)."""

from __future__ import annotations

import contextlib
import io
import json
import re

import pytest
import yaml
from hypothesis import given, settings

pytest.importorskip("swarmproof.commands.check_lattice")
pytest.importorskip("swarmproof.checkers.lattice_check")

from swarmproof.cli import main  # noqa: E402
from swarmproof.strategies import mutated_lattice_documents  # noqa: E402

GOOD = """\
format: lattice-graph/1
name: t
range: 1.2
roles: [A]
edges:
  - [A, A, 1, 0, 0]
  - [A, A, -1, 0, 0]
"""

# (id, file name, content (str or bytes), regex for stderr)
CASES = [
    ("malformed-yaml", "m.yaml", GOOD.replace("roles: [A]", "roles: [A"),
     r"m\.yaml:\d+: malformed YAML: .*; fix: "),
    ("malformed-json", "m.json", '{"format": "lattice-graph/1",\n "roles": ["A"]\n "edges": []}',
     r"m\.json:3: malformed JSON: Expecting ',' delimiter .*; fix: check commas"),
    ("unknown-role", "r.yaml", GOOD.replace("[A, A, -1, 0, 0]", "[A, B, -1, 0, 0]"),
     r"r\.yaml:7: field 'edges\[1\]\[1\]': edges\[1\]\[1\]='B' is not a declared role; fix: use one of"),
    ("nan", "n.yaml", GOOD.replace("[A, A, 1, 0, 0]", "[A, A, .nan, 0, 0]"),
     r"n\.yaml:6: field 'edges\[0\]\[2\]': edges\[0\]\[2\]=nan must be a finite number; fix: "),
    ("infinity-json", "i.json",
     '{"format": "lattice-graph/1", "roles": ["A"],\n "edges": [["A", "A", 1, 0, Infinity]]}',
     r"i\.json:2: field 'edges\[0\]\[4\]': edges\[0\]\[4\]=inf must be a finite number; fix: "),
    ("row-length", "l.yaml", GOOD.replace("[A, A, 1, 0, 0]", "[A, A, 1, 0]"),
     r"l\.yaml:6: field 'edges\[0\]': .* has 4 items, expected 5 .*; fix: give exactly five items"),
    ("format-version", "v.yaml", GOOD.replace("lattice-graph/1", "lattice-graph/9"),
     r"v\.yaml:1: field 'format': format='lattice-graph/9' is not supported; "
     r"this swarmproof reads only 'lattice-graph/1'; fix: "),
    ("unknown-key", "k.yaml", GOOD.replace("range: 1.2", "rnage: 1.2"),
     r"k\.yaml:3: field 'rnage': unknown key 'rnage'; fix: use only the keys"),
    ("empty", "e.yaml", "", r"e\.yaml:1: the file is empty; fix: "),
    ("non-utf8", "u.yaml", GOOD.replace("name: t", "name: \xe9").encode("latin-1"),
     r"u\.yaml:2: byte b'\\xe9' .* is not UTF-8 text; fix: save the file as UTF-8"),
    ("missing-file", None, None,
     r"nope\.yaml: no such file and no bundled lattice of that name; fix: give the path"),
    ("directory", "", None, r": is a directory, not a lattice file; fix: "),
]


def _path(tmp_path, name, content):
    if name is None:
        return str(tmp_path / "nope.yaml")
    if name == "":
        return str(tmp_path)
    p = tmp_path / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_text(content)
    return str(p)


@pytest.mark.parametrize("json_flag", [False, True], ids=["human", "json"])
@pytest.mark.parametrize("name, content, pattern", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_file_exits_2_with_location_and_fix(tmp_path, capsys, name, content, pattern, json_flag):
    path = _path(tmp_path, name, content)
    code = main(["check-lattice", path] + (["--json"] if json_flag else []))
    out, err = capsys.readouterr()
    assert code == 2
    if json_flag:  # the error as one JSON document on stdout, nothing else there
        doc = json.loads(out)
        assert doc["exit_code"] == 2 and doc["error"]["kind"] == "usage"
        assert re.search(pattern, doc["error"]["message"])
    else:
        assert out == ""
    assert err.startswith("swarmproof check-lattice: error: ")
    assert "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert re.search(pattern, err), err


def test_no_range_anywhere_is_a_usage_error(tmp_path, capsys):
    p = tmp_path / "norange.yaml"
    p.write_text(GOOD.replace("range: 1.2\n", ""))
    assert main(["check-lattice", str(p), "--json"]) == 2
    out, err = capsys.readouterr()
    assert json.loads(out)["error"]["kind"] == "usage" and "range" in err and "fix:" in err


def test_good_file_still_checks(tmp_path, capsys):
    p = tmp_path / "ok.yaml"
    p.write_text(GOOD.replace(
        "  - [A, A, -1, 0, 0]\n", "  - [A, A, -1, 0, 0]\n  - [A, A, 0, 1, 0]\n  - [A, A, 0, -1, 0]\n"))
    assert main(["check-lattice", str(p), "--json"]) == 0
    assert '"valid": true' in capsys.readouterr().out


@settings(max_examples=40)
@given(mutated_lattice_documents())
def test_mutated_files_always_exit_2(tmp_path_factory, doc):
    p = tmp_path_factory.mktemp("cli") / "fuzz.yaml"
    p.write_text(yaml.safe_dump(doc, allow_unicode=True))
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["check-lattice", str(p), "--json"])
    assert code == 2 and json.loads(out.getvalue())["error"]["kind"] == "usage"
    assert str(p) in err.getvalue() and "fix:" in err.getvalue()
