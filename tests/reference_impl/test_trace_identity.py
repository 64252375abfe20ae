"""Bit-identity of reference traces across core changes (issue 12, "Must hold").

:mod:`benchmarks.trace_hashes` hashes a fixed set of runs (song2016 and song2014 on the
acceptance lattices, several sizes and seeds; the example algorithm and song2016 under
every fault hook; a run with its messages recorded).  The hashes in
``data/trace_hashes.json`` were written on commit f258555, before the core was reshaped
into one module per algorithm; every later commit must reproduce them bit for bit unless
it changes traces on purpose and says so (then ``python benchmarks/trace_hashes.py --write``).
"""

from __future__ import annotations

import importlib.util
import json
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _module():
    spec = importlib.util.spec_from_file_location("trace_hashes", ROOT / "benchmarks" / "trace_hashes.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


EXPECTED = json.loads((ROOT / "tests" / "reference_impl" / "data" / "trace_hashes.json").read_text())
FAST = [k for k in EXPECTED if " n=20 " not in k]


def _check(labels):
    mod = _module()
    got = {label: mod.digest(thunk()) for label, thunk in mod.cases() if label in labels}
    assert set(got) == set(labels)
    changed = sorted(k for k in labels if got[k] != EXPECTED[k])
    assert not changed, f"traces changed: {changed}"


def test_reference_traces_bit_identical_fast_subset():
    _check(FAST)


@pytest.mark.slow
def test_reference_traces_bit_identical_all():
    _check(list(EXPECTED))
