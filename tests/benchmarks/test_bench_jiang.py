"""benchmarks/jiang: the pieces of the Sec. V-A table that say whether Fig. 7a's alignment can be 1
(docs/jiang.md, "Fig. 7a's quality"): the formation key up to translation, and its doctests."""

from __future__ import annotations

import doctest

import numpy as np

from swarmproof.models.repeating_pattern import load_pattern


def _experiments():
    from testkit import load_benchmark

    return load_benchmark("jiang/experiments")


def test_experiments_doctests():
    mod = _experiments()
    failures, tried = doctest.testmod(mod, optionflags=doctest.ELLIPSIS)
    assert tried > 0 and failures == 0


def test_shape_key_ignores_translation_and_order_and_sees_a_misplaced_copy():
    key = _experiments().shape_key
    p = load_pattern("rhombus-triangles")
    fd = p.formation(27)
    assert key(p, fd) == key(p, fd[::-1] + (2.5, -1.0))
    moved = fd.copy()
    moved[-3:] += (1.0, 0.0)              # the last copy one step right, onto a free slot
    assert key(p, moved) != key(p, fd)
    assert p.alignment(moved) < 1 and p.satisfied(None, moved).status == "held"
    poses = np.column_stack([fd, np.zeros(len(fd))])       # (x, y, theta) rows as a run returns them
    assert key(p, poses) == key(p, fd)
