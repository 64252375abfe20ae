"""Exploring wang2020 with robots of different speeds (004 Sec. V-B3 relaxes Sec. II-A d; issue 15):
unequal speeds are parameters that break ``same_speed`` on purpose (``--allow-violations``), like
the clock-rate spread; the V-B3 bound on l is the ``speed_buffer`` assumption.  At the bound the
explorer finds nothing; far below it, a collision that replays."""

from __future__ import annotations

import json
import math

from swarmproof.checkers.explore import explore

V = 0.05                                  # 004 Sec. V-A
AT_BOUND = {"speed_min": V / math.sqrt(3), "speed_max": V}   # 2 r sqrt(1 + 3) = 0.2 m = l exactly
BELOW = {"speed_min": 0.01, "speed_max": V}                  # bound 0.1 sqrt(26) = 0.51 m > l = 0.2 m


def test_at_the_v_b3_bound_collision_holds_over_what_it_ran():
    rep = explore("wang2020", ["collision"], budget=None, max_examples=12, robots=(3, 6), seed=0,
                  params={"extra": AT_BOUND}, allow_violations=True)
    assert rep.broken_assumptions == ["same_speed"]           # Sec. II-A d); V-B3 relaxes it
    assert "speed_buffer" in rep.kept_assumptions
    v = rep.properties["collision"]
    assert v.status == "held" and "explored, not proved" in v.message


def test_far_below_the_v_b3_bound_a_slow_leaver_is_caught_and_the_file_replays(tmp_path, capsys):
    rep = explore("wang2020", ["collision"], budget=None, max_examples=20, robots=(3, 8), seed=0,
                  params={"extra": BELOW}, allow_violations=True, out_dir=tmp_path)
    assert set(rep.broken_assumptions) == {"same_speed", "speed_buffer"}
    v = rep.properties["collision"]
    assert v.status == "violated" and "overlap" in v.message
    cx = json.load(open(v.counterexample_path))
    assert cx["params"]["extra"]["speed_min"] == 0.01 and cx["params"]["extra"]["speed_max"] == V
    from swarmproof.cli import main

    code = main(["replay", v.counterexample_path, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 1 and doc["reproduced"] is True and doc["step"] == v.counterexample.violation["step"]


def test_the_explorer_refuses_unequal_speeds_unless_allowed():
    import pytest

    from swarmproof.models.errors import UsageError

    with pytest.raises(UsageError, match=r"break the assumptions \['speed_buffer', 'same_speed'\] of 'wang2020'"):
        explore("wang2020", ["collision"], budget=None, max_examples=2, params={"extra": BELOW})
