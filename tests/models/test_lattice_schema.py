"""The shipped JSON Schema of ``lattice-graph/1`` agrees with the loader.

The schema cannot express everything the loader checks: that rows name
declared roles, that numbers are finite (JSON Schema sees NaN and infinity
as numbers), and duplicate keys.  Those cases are listed here as the
loader's alone; every other rejected document must be rejected by both.
"""

from __future__ import annotations

import json
import math

import pytest
import yaml
from hypothesis import given, settings

from swarmproof.models import library
from swarmproof.models.errors import InputFileError
from swarmproof.models.lattice_io import loads_lattice, schema_path
from swarmproof.strategies import (SCHEMA_BLIND_KINDS, lattice_graph_documents,
                                   mutated_lattice_documents)

jsonschema = pytest.importorskip("jsonschema")


@pytest.fixture(scope="module")
def validator():
    with open(schema_path(), encoding="utf-8") as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    return jsonschema.Draft202012Validator(schema)


@pytest.mark.parametrize("name", library.names())
def test_bundled_files_validate(validator, name):
    doc = yaml.safe_load(library.text(name))
    assert list(validator.iter_errors(doc)) == []


BASE = {"format": "lattice-graph/1", "name": "t", "range": 1.2, "angle_unit": "deg",
        "roles": ["A", "B"], "edges": [["A", "B", 1, 0, 0], ["B", "A", -1, 0, 0]]}


def _with(**changes):
    doc = json.loads(json.dumps(BASE))
    for k, v in changes.items():
        if v is KeyError:
            del doc[k]
        else:
            doc[k] = v
    return doc


# documents both the loader and the schema reject
BOTH_REJECT = [
    ("format-version", _with(format="lattice-graph/2")),
    ("format-missing", _with(format=KeyError)),
    ("roles-missing", _with(roles=KeyError)),
    ("edges-missing", _with(edges=KeyError)),
    ("edges-null", _with(edges=None)),
    ("unknown-key", _with(rnage=1.2)),
    ("range-zero", _with(range=0)),
    ("range-negative", _with(range=-1)),
    ("range-string", _with(range="1.2")),
    ("range-bool", _with(range=True)),
    ("angle-unit", _with(angle_unit="grad")),
    ("roles-empty", _with(roles=[])),
    ("roles-duplicate", _with(roles=["A", "B", "A"])),
    ("role-number", _with(roles=["A", "B", 1])),
    ("role-empty-string", _with(roles=["A", "B", ""])),
    ("roles-string", _with(roles="A")),
    ("edges-not-list", _with(edges={"A": 1})),
    ("row-not-list", _with(edges=["A B 1 0 0"])),
    ("row-short", _with(edges=[["A", "B", 1, 0]])),
    ("row-long", _with(edges=[["A", "B", 1, 0, 0, 0]])),
    ("row-bool", _with(edges=[["A", "B", True, 0, 0]])),
    ("row-string-number", _with(edges=[["A", "B", "1", 0, 0]])),
    ("row-null", _with(edges=[["A", "B", 1, None, 0]])),
    ("row-role-number", _with(edges=[[1, "B", 1, 0, 0]])),
    ("name-empty", _with(name="")),
    ("name-blank", _with(name="   ")),
    ("name-number", _with(name=5)),
    ("not-a-mapping", [BASE]),
]

# documents only the loader can reject (listed in the schema's description)
LOADER_ONLY = [
    ("unknown-role", _with(edges=[["A", "C", 1, 0, 0]])),
    ("nan", _with(edges=[["A", "B", math.nan, 0, 0]])),
    ("infinity", _with(edges=[["A", "B", 1, 0, math.inf]])),
    ("range-infinite", _with(range=math.inf)),
]


@pytest.mark.parametrize("doc", [c[1] for c in BOTH_REJECT], ids=[c[0] for c in BOTH_REJECT])
def test_schema_rejects_what_the_loader_rejects(validator, doc):
    assert not validator.is_valid(doc)
    with pytest.raises(InputFileError):
        loads_lattice(json.dumps(doc), "json")


@pytest.mark.parametrize("doc", [c[1] for c in LOADER_ONLY], ids=[c[0] for c in LOADER_ONLY])
def test_loader_rejects_what_the_schema_cannot_express(validator, doc):
    assert validator.is_valid(doc)  # documented blind spot of JSON Schema
    with pytest.raises(InputFileError):
        loads_lattice(json.dumps(doc), "json")


def test_base_document_is_valid_for_both(validator):
    assert validator.is_valid(BASE)
    assert loads_lattice(json.dumps(BASE), "json").roles == ("A", "B")


@settings(max_examples=100)
@given(lattice_graph_documents())
def test_schema_accepts_valid_documents(validator, doc):
    assert list(validator.iter_errors(doc)) == []


def _non_finite(x) -> bool:
    if isinstance(x, float):
        return not math.isfinite(x)
    if isinstance(x, list):
        return any(_non_finite(v) for v in x)
    if isinstance(x, dict):
        return any(_non_finite(v) for v in x.values())
    return False


@settings(max_examples=200)
@given(mutated_lattice_documents(with_kind=True))
def test_schema_rejects_mutated_documents_it_can_see(validator, doc_kind):
    doc, kind = doc_kind
    if kind in SCHEMA_BLIND_KINDS or _non_finite(doc):
        return
    assert not validator.is_valid(doc), kind
