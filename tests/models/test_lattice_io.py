"""Reading and writing ``lattice-graph/1`` files (swarmproof.models.lattice_io).

Bad documents sit in one table per syntax; each case checks the rendered
``file:line: field '...': name=value ...; fix: ...`` text with ``match=``.
"""

from __future__ import annotations

import json
import math
import os
import re

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from swarmproof.models import library
from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.models.lattice import LatticeGraph
from swarmproof.models.lattice_io import (ALLOWED_KEYS, FORMAT, dump_lattice, lattice_to_document,
                                          load_lattice_file, loads_lattice, save_lattice)
from swarmproof.models.se2 import SE2
from swarmproof.strategies import (finite_lattices, lattice_graph_documents,
                                   mutated_lattice_documents, periodic_lattices)

# --------------------------------------------------------------------------
# bad YAML documents: (id, text, regex on str(error))
# --------------------------------------------------------------------------

GOOD_YAML = """\
format: lattice-graph/1
name: t
range: 1.2
angle_unit: deg
roles: [A, B]
edges:
  - [A, B, 1, 0, 0]
  - [B, A, -1, 0, 0]
"""


def _y(old: str, new: str) -> str:
    assert old in GOOD_YAML, old
    return GOOD_YAML.replace(old, new, 1)


BAD_YAML = [
    ("malformed-bracket", _y("roles: [A, B]", "roles: [A, B"),
     r"^t\.yaml:\d+: malformed YAML: .*; fix: check indentation"),
    ("malformed-indent", _y("  - [B, A, -1, 0, 0]", " - [B, A, -1, 0, 0]"),
     r"^t\.yaml:8: malformed YAML"),
    ("unknown-role-to", _y("[B, A, -1, 0, 0]", "[B, C, -1, 0, 0]"),
     r"^t\.yaml:8: field 'edges\[1\]\[1\]': edges\[1\]\[1\]='C' is not a declared role; "
     r"fix: use one of roles=\['A', 'B'\] or add 'C' to roles$"),
    ("unknown-role-from", _y("[A, B, 1, 0, 0]", "[Z, B, 1, 0, 0]"),
     r"^t\.yaml:7: field 'edges\[0\]\[0\]': edges\[0\]\[0\]='Z' is not a declared role"),
    ("nan-x", _y("[A, B, 1, 0, 0]", "[A, B, .nan, 0, 0]"),
     r"^t\.yaml:7: field 'edges\[0\]\[2\]': edges\[0\]\[2\]=nan must be a finite number; fix: write x"),
    ("inf-theta", _y("[A, B, 1, 0, 0]", "[A, B, 1, 0, .inf]"),
     r"^t\.yaml:7: field 'edges\[0\]\[4\]': edges\[0\]\[4\]=inf must be a finite number; "
     r"fix: write theta \(in deg\)"),
    ("minus-inf-y", _y("[B, A, -1, 0, 0]", "[B, A, -1, -.inf, 0]"),
     r"^t\.yaml:8: field 'edges\[1\]\[3\]': edges\[1\]\[3\]=-inf must be a finite number"),
    ("row-too-short", _y("[A, B, 1, 0, 0]", "[A, B, 1, 0]"),
     r"^t\.yaml:7: field 'edges\[0\]': edges\[0\]=\['A', 'B', 1, 0\] has 4 items, expected 5 "
     r"\[from, to, x, y, theta\]; fix: give exactly five items"),
    ("row-too-long", _y("[B, A, -1, 0, 0]", "[B, A, -1, 0, 0, 0]"),
     r"^t\.yaml:8: field 'edges\[1\]': .* has 6 items, expected 5"),
    ("row-not-list", _y("  - [B, A, -1, 0, 0]", "  - B A -1 0 0"),
     r"^t\.yaml:8: field 'edges\[1\]': edges\[1\]='B A -1 0 0' must be a list"),
    ("bool-number", _y("[A, B, 1, 0, 0]", "[A, B, true, 0, 0]"),
     r"^t\.yaml:7: field 'edges\[0\]\[2\]': edges\[0\]\[2\]=True must be a number, not a boolean"),
    ("quoted-number", _y("[A, B, 1, 0, 0]", "[A, B, '1', 0, 0]"),
     r"^t\.yaml:7: field 'edges\[0\]\[2\]': edges\[0\]\[2\]='1' must be a number, got str; "
     r"fix: write x as a plain number without quotes$"),
    ("yaml-exponent-without-dot", _y("[A, B, 1, 0, 0]", "[A, B, 1e-3, 0, 0]"),
     r"edges\[0\]\[2\]='1e-3' must be a number, got str; .*write 1\.0e-3"),
    ("row-on-own-lines", _y("  - [A, B, 1, 0, 0]", "  - - A\n    - B\n    - 1\n    - .nan\n    - 0"),
     r"^t\.yaml:10: field 'edges\[0\]\[3\]': edges\[0\]\[3\]=nan"),
    ("format-version-2", _y("format: lattice-graph/1", "format: lattice-graph/2"),
     r"^t\.yaml:1: field 'format': format='lattice-graph/2' is not supported; "
     r"this swarmproof reads only 'lattice-graph/1'; fix: write `format: lattice-graph/1`"),
    ("format-other", _y("format: lattice-graph/1", "format: graphml"),
     r"^t\.yaml:1: field 'format': format='graphml' is not a lattice graph format"),
    ("format-number", _y("format: lattice-graph/1", "format: 1"),
     r"^t\.yaml:1: field 'format': format=1 is not a lattice graph format"),
    ("format-missing", _y("format: lattice-graph/1\n", ""),
     r"^t\.yaml:1: key 'format' is missing; fix: add `format: lattice-graph/1`"),
    ("roles-missing", _y("roles: [A, B]\n", ""),
     r"^t\.yaml:1: key 'roles' is missing; fix: add `roles: \[A, \.\.\.\]`"),
    ("edges-missing", GOOD_YAML.split("edges:")[0],
     r"^t\.yaml:1: key 'edges' is missing"),
    ("unknown-key-typo", _y("range: 1.2", "rnage: 1.2"),
     r"^t\.yaml:3: field 'rnage': unknown key 'rnage'; fix: use only the keys "
     + re.escape(str(list(ALLOWED_KEYS)))),
    ("duplicate-key", _y("angle_unit: deg", "angle_unit: deg\nrange: 2"),
     r"^t\.yaml:5: field 'range': key 'range' appears twice \(lines 3 and 5\); fix: keep one"),
    ("range-zero", _y("range: 1.2", "range: 0"),
     r"^t\.yaml:3: field 'range': range=0 must be > 0"),
    ("range-negative", _y("range: 1.2", "range: -1.5"),
     r"^t\.yaml:3: field 'range': range=-1\.5 must be > 0"),
    ("range-nan", _y("range: 1.2", "range: .nan"),
     r"^t\.yaml:3: field 'range': range=nan must be a finite number"),
    ("range-bool", _y("range: 1.2", "range: yes"),
     r"^t\.yaml:3: field 'range': range=True must be a number, not a boolean"),
    ("range-huge-int", _y("range: 1.2", "range: 1" + "0" * 400),
     r"^t\.yaml:3: field 'range': range=an integer of 401 digits is beyond the bound \|range\| <= 1e6; fix: scale"),
    ("angle-unit", _y("angle_unit: deg", "angle_unit: grad"),
     r"^t\.yaml:4: field 'angle_unit': angle_unit='grad' is not a known unit; fix: use 'deg'"),
    ("roles-empty", _y("roles: [A, B]", "roles: []"),
     r"^t\.yaml:5: field 'roles': roles=\[\] is empty"),
    ("roles-duplicate", _y("roles: [A, B]", "roles: [A, B, A]"),
     r"^t\.yaml:5: field 'roles\[2\]': roles\[2\]='A' is listed twice \(also roles\[0\]\)"),
    ("role-number", _y("roles: [A, B]", "roles: [A, B, 1]"),
     r"^t\.yaml:5: field 'roles\[2\]': roles\[2\]=1 must be a non-empty string; fix: quote"),
    ("role-yes", _y("roles: [A, B]", "roles: [A, B, yes]"),
     r"roles\[2\]=True must be a non-empty string"),
    ("roles-scalar", _y("roles: [A, B]", "roles: A"),
     r"^t\.yaml:5: field 'roles': roles='A' must be a list of role names"),
    ("edges-scalar", GOOD_YAML.split("edges:")[0] + "edges: 5\n",
     r"^t\.yaml:6: field 'edges': edges=5 must be a list of rows"),
    ("edges-empty-value", GOOD_YAML.split("edges:")[0] + "edges:\n",
     r"^t\.yaml:6: field 'edges': edges=None has no rows; fix: .*`edges: \[\]`"),
    ("name-empty", _y("name: t", "name: ''"),
     r"^t\.yaml:2: field 'name': name='' must be a non-empty string"),
    ("not-a-mapping", "- a\n- b\n",
     r"^t\.yaml:1: the document must be a mapping of keys, got list"),
    ("scalar-document", "hello\n",
     r"^t\.yaml:1: the document must be a mapping"),
    ("empty", "", r"^t\.yaml:1: the file is empty"),
    ("blank", "  \n\n", r"^t\.yaml:1: the file is empty"),
    ("comment-only", "# nothing here\n", r"^t\.yaml: the file is empty"),
    ("two-documents", GOOD_YAML + "---\n" + GOOD_YAML,
     r"^t\.yaml:9: malformed YAML: .*single document"),
    ("python-tag", "!!python/object/apply:os.system ['echo hi']\n",
     r"^t\.yaml:1: malformed YAML: .*could not determine a constructor"),
    ("bad-timestamp", _y("name: t", "name: 2020-13-45"),
     r"^t\.yaml: malformed YAML: a value cannot be read"),
    ("control-character", _y("name: t", "name: t\x01"),
     r"^t\.yaml:2: malformed YAML: character '\\x01' is not allowed in YAML text; fix: remove control"),
    ("deep-nesting", "[" * 3000 + "]" * 3000, r"^t\.yaml: malformed YAML: nesting is too deep"),
    ("tab-indent", _y("  - [A, B, 1, 0, 0]", "\t- [A, B, 1, 0, 0]"),
     r"^t\.yaml:7: malformed YAML"),
]


@pytest.mark.parametrize("text, pattern", [c[1:] for c in BAD_YAML], ids=[c[0] for c in BAD_YAML])
def test_bad_yaml_documents_name_file_line_field_and_fix(text, pattern):
    with pytest.raises(InputFileError, match=pattern) as info:
        loads_lattice(text, "yaml", source="t.yaml")
    assert "fix: " in str(info.value) and "\n" not in str(info.value)
    assert info.value.file == "t.yaml"


# --------------------------------------------------------------------------
# bad JSON documents
# --------------------------------------------------------------------------

GOOD_JSON = """\
{
  "format": "lattice-graph/1",
  "name": "t",
  "range": 1.2,
  "angle_unit": "deg",
  "roles": ["A", "B"],
  "edges": [
    ["A", "B", 1, 0, 0],
    ["B", "A", -1, 0, 0]
  ]
}
"""


def _j(old: str, new: str) -> str:
    assert old in GOOD_JSON, old
    return GOOD_JSON.replace(old, new, 1)


BAD_JSON = [
    ("missing-comma", _j('"name": "t",', '"name": "t"'),
     r"^t\.json:4: malformed JSON: Expecting ',' delimiter \(column 3\); fix: check commas"),
    ("trailing-comma", _j('["B", "A", -1, 0, 0]', '["B", "A", -1, 0, 0],'),
     r"^t\.json:10: malformed JSON"),
    ("single-quotes", _j('"name": "t"', "'name': 't'"),
     r"^t\.json:3: malformed JSON"),
    ("nan", _j('["A", "B", 1, 0, 0]', '["A", "B", NaN, 0, 0]'),
     r"^t\.json:8: field 'edges\[0\]\[2\]': edges\[0\]\[2\]=nan must be a finite number"),
    ("infinity", _j('["B", "A", -1, 0, 0]', '["B", "A", -1, 0, -Infinity]'),
     r"^t\.json:9: field 'edges\[1\]\[4\]': edges\[1\]\[4\]=-inf must be a finite number"),
    ("huge-float", _j('["B", "A", -1, 0, 0]', '["B", "A", 1e400, 0, 0]'),
     r"^t\.json:9: field 'edges\[1\]\[2\]': edges\[1\]\[2\]=inf must be a finite number"),
    ("unknown-role", _j('["B", "A", -1, 0, 0]', '["B", "Q", -1, 0, 0]'),
     r"^t\.json:9: field 'edges\[1\]\[1\]': edges\[1\]\[1\]='Q' is not a declared role"),
    ("row-length", _j('["A", "B", 1, 0, 0]', '["A", "B", 1, 0]'),
     r"^t\.json:8: field 'edges\[0\]': .* has 4 items, expected 5"),
    ("bool", _j('["A", "B", 1, 0, 0]', '["A", "B", 1, false, 0]'),
     r"^t\.json:8: field 'edges\[0\]\[3\]': edges\[0\]\[3\]=False must be a number, not a boolean"),
    ("null-number", _j('["A", "B", 1, 0, 0]', '["A", "B", 1, 0, null]'),
     r"^t\.json:8: field 'edges\[0\]\[4\]': edges\[0\]\[4\]=None must be a number, got NoneType"),
    ("format-version", _j('"lattice-graph/1"', '"lattice-graph/3"'),
     r"^t\.json:2: field 'format': format='lattice-graph/3' is not supported"),
    ("unknown-key", _j('"name": "t",', '"name": "t",\n  "roels": [],'),
     r"^t\.json:4: field 'roels': unknown key 'roels'"),
    ("duplicate-key", _j('"name": "t",', '"name": "t",\n  "name": "u",'),
     r"^t\.json:4: field 'name': key 'name' appears twice \(lines 3 and 4\)"),
    ("role-duplicate", _j('["A", "B"]', '["A", "B", "B"]'),
     r"^t\.json:6: field 'roles\[2\]': roles\[2\]='B' is listed twice"),
    ("rows-on-many-lines", _j('["B", "A", -1, 0, 0]', '[\n      "B",\n      "A",\n      -1,\n      0,\n      "0"\n    ]'),
     r"^t\.json:14: field 'edges\[1\]\[4\]': edges\[1\]\[4\]='0' must be a number"),
    ("array-document", "[1, 2]\n", r"^t\.json:1: the document must be a mapping of keys, got list"),
    ("empty", "", r"^t\.json:1: the file is empty"),
    ("huge-int", _j('"range": 1.2', '"range": 1' + "0" * 5000),
     r"^t\.json: malformed JSON: a value cannot be read"),
    ("deep-nesting", "[" * 3000 + "]" * 3000, r"^t\.json: malformed JSON: nesting is too deep"),
]


@pytest.mark.parametrize("text, pattern", [c[1:] for c in BAD_JSON], ids=[c[0] for c in BAD_JSON])
def test_bad_json_documents_name_file_line_field_and_fix(text, pattern):
    with pytest.raises(InputFileError, match=pattern) as info:
        loads_lattice(text, "json", source="t.json")
    assert "fix: " in str(info.value)


def test_good_documents_load_identically_from_yaml_and_json():
    a = loads_lattice(GOOD_YAML, "yaml", "t.yaml")
    b = loads_lattice(GOOD_JSON, "json", "t.json")
    assert a == b
    assert a.roles == ("A", "B") and a.range == 1.2 and a.name == "t"
    assert [e.as_row() for e in a.edges] == [["A", "B", 1.0, 0.0, 0.0], ["B", "A", -1.0, 0.0, 0.0]]


def test_angle_units_and_defaults():
    rad = loads_lattice(_y("angle_unit: deg", "angle_unit: rad").replace("[A, B, 1, 0, 0]",
                                                                          "[A, B, 1, 0, 1.5]"), "yaml")
    assert rad.edges[0].transform.theta == 1.5
    deg = loads_lattice(_y("angle_unit: deg\n", "").replace("[A, B, 1, 0, 0]", "[A, B, 1, 0, 90]"), "yaml")
    assert deg.edges[0].transform.theta == math.pi / 2  # deg is the default
    wrapped = loads_lattice(_y("[A, B, 1, 0, 0]", "[A, B, 1, 0, 540]"), "yaml")
    assert wrapped.edges[0].transform.theta == -math.pi
    unnamed = loads_lattice(_y("name: t\n", "").replace("range: 1.2\n", ""), "yaml", source="dir/my-grid.yaml")
    assert unnamed.name == "my-grid" and unnamed.range is None


def test_bad_fmt_argument_is_a_usage_error():
    with pytest.raises(UsageError, match=r"fmt='xml' is not a lattice file syntax"):
        loads_lattice(GOOD_YAML, "xml")


# --------------------------------------------------------------------------
# files
# --------------------------------------------------------------------------

def test_missing_file(tmp_path):
    p = tmp_path / "nope.yaml"
    with pytest.raises(InputFileError, match=re.escape(str(p)) + r": no such file; fix: check the path"):
        load_lattice_file(p)


def test_directory(tmp_path):
    with pytest.raises(InputFileError, match=r"is a directory, not a lattice file; fix: give the path"):
        load_lattice_file(tmp_path)


def test_empty_file(tmp_path):
    p = tmp_path / "e.json"
    p.write_bytes(b"")
    with pytest.raises(InputFileError, match=r"e\.json:1: the file is empty"):
        load_lattice_file(p)


def test_non_utf8_bytes_name_the_line(tmp_path):
    p = tmp_path / "latin1.yaml"
    p.write_bytes(GOOD_YAML.replace("name: t", "name: caf\xe9").encode("latin-1"))
    with pytest.raises(InputFileError, match=r"latin1\.yaml:2: byte b'\\xe9' at offset \d+ is not UTF-8 text; "
                                             r"fix: save the file as UTF-8"):
        load_lattice_file(p)


def test_utf8_bom_is_accepted(tmp_path):
    p = tmp_path / "bom.json"
    p.write_bytes(b"\xef\xbb\xbf" + GOOD_JSON.encode())
    assert load_lattice_file(p).roles == ("A", "B")


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root can read any file")
def test_unreadable_file(tmp_path):  # pragma: no cover - CI runs as root here
    p = tmp_path / "secret.yaml"
    p.write_text(GOOD_YAML)
    p.chmod(0)
    with pytest.raises(InputFileError, match=r"permission denied"):
        load_lattice_file(p)


@pytest.mark.parametrize("ext, text", [(".yml", GOOD_YAML), (".YAML", GOOD_YAML), (".json", GOOD_JSON),
                                       (".lattice", GOOD_JSON), (".lattice", GOOD_YAML), ("", GOOD_YAML)],
                         ids=["yml", "upper-yaml", "json", "other-ext-json", "other-ext-yaml", "no-ext"])
def test_format_by_extension(tmp_path, ext, text):
    p = tmp_path / f"g{ext}"
    p.write_text(text)
    g = load_lattice_file(str(p))
    assert g.roles == ("A", "B") and g.source == str(p)


def test_yaml_text_in_json_file_reports_json_error(tmp_path):
    p = tmp_path / "g.json"
    p.write_text(GOOD_YAML)
    with pytest.raises(InputFileError, match=r"g\.json:1: malformed JSON"):
        load_lattice_file(p)


def test_other_extension_reports_yaml_problem(tmp_path):
    p = tmp_path / "g.txt"
    p.write_text(_y("[A, B, 1, 0, 0]", "[A, X, 1, 0, 0]"))
    with pytest.raises(InputFileError, match=r"g\.txt:7: field 'edges\[0\]\[1\]'"):
        load_lattice_file(p)


# --------------------------------------------------------------------------
# round trips
# --------------------------------------------------------------------------

@pytest.mark.parametrize("name", library.names())
@pytest.mark.parametrize("fmt", ["yaml", "json"])
@pytest.mark.parametrize("unit", ["deg", "rad"])
def test_bundled_round_trip_is_exact(name, fmt, unit):
    g = library.load(name)
    text = dump_lattice(g, fmt, unit)
    back = loads_lattice(text, fmt)
    assert back == g
    assert dump_lattice(back, fmt, unit) == text  # deterministic and idempotent


def test_save_and_load_files(tmp_path):
    g = library.load("octagon-square")
    for fname, unit in (("o.yaml", "deg"), ("o.json", "rad"), ("o.yml", "rad")):
        path = save_lattice(g, tmp_path / fname, angle_unit=unit)
        assert load_lattice_file(path) == g
    assert sorted(os.listdir(tmp_path)) == ["o.json", "o.yaml", "o.yml"]  # no temporary files left
    assert (tmp_path / "o.json").read_text().startswith('{\n  "format": "lattice-graph/1",')


def test_save_into_missing_folder_is_a_usage_error(tmp_path):
    with pytest.raises(UsageError, match=r"does not exist"):
        save_lattice(library.load("square"), tmp_path / "no" / "x.yaml")


def _close(a: LatticeGraph, b: LatticeGraph) -> bool:
    return (a.name == b.name and a.roles == b.roles and a.range == b.range and len(a.edges) == len(b.edges)
            and all(x.source == y.source and x.target == y.target
                    and (x.transform.x, x.transform.y) == (y.transform.x, y.transform.y)
                    and x.transform.isclose(y.transform, 0.0, 1e-12)
                    for x, y in zip(a.edges, b.edges)))


@settings(max_examples=40)
@given(st.one_of(periodic_lattices(), finite_lattices()), st.sampled_from(["yaml", "json"]))
def test_generated_lattices_round_trip(g, fmt):
    assert loads_lattice(dump_lattice(g, fmt, "rad"), fmt) == g  # radians: bit-exact
    assert _close(loads_lattice(dump_lattice(g, fmt, "deg"), fmt), g)  # degrees: within 1 ulp of theta


def test_degree_dump_is_exact_for_decimal_degrees():
    rows = [("A", "A", SE2(0.5, -2.25, math.radians(d))) for d in (60, -60, 1, 0.1, 33.3, 179.9, 12.345)]
    g = LatticeGraph("angles", ["A"], rows)
    text = dump_lattice(g)
    assert "33.3]" in text and "12.345]" in text
    assert loads_lattice(text, "yaml") == g


# --------------------------------------------------------------------------
# fuzzing: no exception other than InputFileError escapes
# --------------------------------------------------------------------------

def _serialize(doc, fmt: str) -> str:
    return json.dumps(doc) if fmt == "json" else yaml.safe_dump(doc, allow_unicode=True)


@settings(max_examples=100)
@given(lattice_graph_documents(), st.sampled_from(["yaml", "json"]))
def test_valid_documents_load_with_their_values(doc, fmt):
    g = loads_lattice(_serialize(doc, fmt), fmt, source="doc")
    assert g.roles == tuple(doc["roles"])
    assert g.range == doc.get("range")
    assert len(g.edges) == len(doc["edges"])
    scale = 1.0 if doc.get("angle_unit") == "rad" else math.pi / 180
    for e, row in zip(g.edges, doc["edges"]):
        assert (e.source, e.target, e.transform.x, e.transform.y) == (row[0], row[1], row[2], row[3])
        assert math.isclose(math.cos(e.transform.theta), math.cos(row[4] * scale), abs_tol=1e-9)
    if "name" in doc:
        assert g.name == doc["name"]
    assert lattice_to_document(g, doc.get("angle_unit", "deg"))["roles"] == doc["roles"]


@settings(max_examples=150)
@given(mutated_lattice_documents(with_kind=True), st.sampled_from(["yaml", "json"]))
def test_mutated_documents_are_rejected_with_input_file_error(doc_kind, fmt):
    doc, kind = doc_kind
    with pytest.raises(InputFileError) as info:
        loads_lattice(_serialize(doc, fmt), fmt, source="fuzz.in")
    msg = str(info.value)
    assert msg.startswith("fuzz.in") and "; fix: " in msg, (kind, msg)


@settings(max_examples=150)
@given(st.data(), st.sampled_from(["yaml", "json"]))
def test_damaged_text_never_raises_anything_else(data, fmt):
    doc = data.draw(st.one_of(lattice_graph_documents(), mutated_lattice_documents()))
    text = _serialize(doc, fmt)
    cut = data.draw(st.integers(0, len(text)))
    junk = data.draw(st.text(alphabet="[]{}:,-'\"#&*!|>% \n\t.0aA\x00\x85\u2028", max_size=4))
    damaged = text[:cut] + junk + text[cut + data.draw(st.integers(0, 3)):]
    try:
        g = loads_lattice(damaged, fmt, source="fuzz.in")
    except InputFileError as exc:
        assert str(exc).startswith("fuzz.in") and "\n" not in str(exc)
    else:
        assert isinstance(g, LatticeGraph)


@settings(max_examples=100)
@given(st.binary(max_size=200), st.sampled_from([".yaml", ".json", ".dat"]))
def test_arbitrary_bytes_never_raise_anything_else(tmp_path_factory, raw, ext):
    p = tmp_path_factory.mktemp("fuzz") / f"f{ext}"
    p.write_bytes(raw)
    try:
        load_lattice_file(p)
    except InputFileError:
        pass


def test_format_constant():
    assert FORMAT == "lattice-graph/1"
