"""Random connected starts (001 Sec. VI) and the swarmproof-initial/1 file format."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from swarmproof.models.errors import InputFileError, UsageError
from swarmproof.models.sensing import is_connected
from swarmproof.reference_impl.initial import (InitialConfiguration, dumps, from_file, loads,
                                               random_connected, to_file)


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 40), st.integers(0, 2**32 - 1), st.floats(0.5, 3.0), st.floats(0.0, 0.6))
def test_random_connected_is_connected_separated_and_deterministic(n, seed, phi, frac):
    c = random_connected(n, seed, range=phi, min_separation=frac * phi)
    assert c.n == n and sorted(c.ids.tolist()) == list(range(n))
    assert is_connected(c.poses[:, :2], phi)
    if n > 1:
        d = np.hypot(*(c.poses[:, None, :2] - c.poses[None, :, :2]).transpose(2, 0, 1))
        assert d[~np.eye(n, dtype=bool)].min() >= frac * phi
    assert (-math.pi <= c.poses[:, 2]).all() and (c.poses[:, 2] < math.pi).all()
    assert c == random_connected(n, seed, range=phi, min_separation=frac * phi)


def test_generator_and_seed_agree_and_seeds_differ():
    a = random_connected(10, 3, range=1.2)
    b = random_connected(10, np.random.default_rng(3), range=1.2)
    assert a == b and a != random_connected(10, 4, range=1.2)


def test_spread_box_is_respected():
    c = random_connected(20, 1, range=1.0, min_separation=0.2, spread=3.0)
    assert (c.poses[:, :2] >= 0).all() and (c.poses[:, :2] <= 3.0).all()


BAD_ARGS = [
    ("zero-robots", dict(n=0), "n=0 must be >= 1"),
    ("sep-at-range", dict(min_separation=1.2), r"min_separation=1.2 must be in \[0, range"),
    ("negative-range", dict(range=-1.0), "range=-1.0 must be > 0"),
    ("bad-seed", dict(rng_or_seed="x"), "rng_or_seed='x'"),
    ("impossible", dict(n=30, spread=0.5, min_separation=0.3, max_tries=20), "could not place robot"),
]


@pytest.mark.parametrize("kw,match", [b[1:] for b in BAD_ARGS], ids=[b[0] for b in BAD_ARGS])
def test_bad_arguments(kw, match):
    args = dict(n=5, rng_or_seed=0, range=1.2)
    args.update(kw)
    n, seed = args.pop("n"), args.pop("rng_or_seed")
    with pytest.raises(UsageError, match=match):
        random_connected(n, seed, **args)


@pytest.mark.parametrize("ext,unit", [("yaml", "rad"), ("json", "rad"), ("yaml", "deg")])
def test_file_round_trip(tmp_path, ext, unit):
    c = random_connected(7, 11, range=1.2)
    back = from_file(to_file(c, tmp_path / f"start.{ext}", angle_unit=unit))
    assert back.ids.tolist() == c.ids.tolist()
    if unit == "rad":
        assert back == c                                   # bit for bit
    else:
        assert np.allclose(back.poses, c.poses, atol=1e-12)


def test_dumps_is_readable_yaml():
    text = dumps(InitialConfiguration([2, 0], [[0.5, 0, math.pi / 2], [0, 0, 0]]))
    assert text.splitlines() == ["format: swarmproof-initial/1", "angle_unit: deg", "robots:",
                                 "- {id: 2, pose: [0.5, 0.0, 90.0]}", "- {id: 0, pose: [0.0, 0.0, 0.0]}"]


HEAD = "format: swarmproof-initial/1\nrobots:\n"
BAD_FILES = [
    ("wrong-format", "format: swarmproof-initial/2\nrobots: []\n", r"s\.yaml:1: field 'format'"),
    ("no-robots", "format: swarmproof-initial/1\n", r"field 'robots': robots=None"),
    ("short-pose", HEAD + "  - {id: 1, pose: [0, 0]}\n", r"s\.yaml:3: field 'robots\[0\]\.pose'"),
    ("text-coordinate", HEAD + "  - {id: 1, pose: [0, 0, 0]}\n  - {id: 2, pose: [1, a, 0]}\n",
     r"s\.yaml:4: field 'robots\[1\]\.pose\[1\]': robots\[1\]\.pose\[1\]='a'"),
    ("float-id", HEAD + "  - {id: 1.5, pose: [0, 0, 0]}\n", r"robots\[0\]\.id=1\.5 must be an integer"),
    ("unknown-key", HEAD + "  - {id: 1, pose: [0, 0, 0], role: A}\n", r"unknown key 'role'"),
    ("bad-unit", "format: swarmproof-initial/1\nangle_unit: grad\nrobots: []\n", r"s\.yaml:2: field 'angle_unit'"),
    ("malformed-yaml", HEAD + "  - {id: 1, pose: [0, 0, 0\n", r"s\.yaml:\d+: malformed YAML"),
    ("same-point", HEAD + "  - {id: 1, pose: [0.5, 1, 0]}\n  - {id: 2, pose: [1, 0, 0]}\n"
     "  - {id: 3, pose: [0.5, 1.0, 90]}\n",
     r"s\.yaml:5: field 'robots\[2\]\.pose': robots\[2\] \(id=3\) at \(0\.5, 1\.0\) is on the same point as "
     r"robots\[0\] \(id=1\): two robots cannot stand on one spot; fix: move one of them"),
    # the first pair in file order (the later robot first, then the earlier), within 1e-9
    ("same-point-first-pair", HEAD + "  - {id: 1, pose: [0, 0, 0]}\n  - {id: 2, pose: [0.5, 0, 0]}\n"
     "  - {id: 3, pose: [0.5, 0.0000000001, 0]}\n  - {id: 4, pose: [0, 0, 0]}\n",
     r"s\.yaml:5: field 'robots\[2\]\.pose': robots\[2\] \(id=3\) at \(0\.5, 1e-10\) is on the same point as "
     r"robots\[1\] \(id=2\)"),
    # issue 29: poses up to 1e308 were accepted (squared distances overflow); bounded as lattices are
    ("x-1e308", HEAD + "  - {id: 1, pose: [0, 0, 0]}\n  - {id: 2, pose: [1.0e+308, 0, 0]}\n",
     r"s\.yaml:4: field 'robots\[1\]\.pose\[0\]': robots\[1\]\.pose\[0\]=1e\+308 is beyond the bound "
     r"\|x\| <= 1e6; fix: scale the start"),
    ("theta-1e7", HEAD + "  - {id: 1, pose: [0, 0, 1.0e+7]}\n",
     r"robots\[0\]\.pose\[2\]=10000000 is beyond the bound \|theta\| <= 1e6; fix: reduce the angle"),
]


@pytest.mark.parametrize("text,match", [b[1:] for b in BAD_FILES], ids=[b[0] for b in BAD_FILES])
def test_bad_files_name_file_line_field(text, match):
    with pytest.raises(InputFileError, match=match):
        loads(text, "yaml", "s.yaml")


def test_missing_file_and_bad_json(tmp_path):
    with pytest.raises(InputFileError, match="no such file"):
        from_file(tmp_path / "nope.yaml")
    p = tmp_path / "x.json"
    p.write_text('{"format": "swarmproof-initial/1",\n "robots": [{"id": 1, "pose": [0, 0, true]}]}')
    with pytest.raises(InputFileError, match=r"x\.json:2: field 'robots\[0\]\.pose\[2\]'"):
        from_file(p)
