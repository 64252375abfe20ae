"""wang2020 with robots of different speeds (004 Sec. II-A d relaxed by Sec. V-B3, issue 15): the
``same_speed`` and ``speed_buffer`` assumptions, their consistency with ``grid_spacing_bounds``, and
runs at and below the V-B3 bound."""

from __future__ import annotations

import json
import math

import pytest

from swarmproof.invariants.properties import collision
from swarmproof.models.errors import AssumptionError
from swarmproof.models.targets import resolve_target
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.protocol import Params
from swarmproof.reference_impl.wang2020.algorithm import Wang2020, default_params, speed_buffer_bound, speed_range

SHAPE = resolve_target("shape:letter-l")
#: v_min / v_max at which 004 Sec. V-B3's bound is exactly l = 0.20 m with r = 0.05 m: 1 / sqrt(3)
RHO_AT_02 = 1 / math.sqrt(3)


def _params(**extra):
    p = default_params()
    return Params(range=extra.pop("range", 0.6), v=p.v, dt=p.dt, extra={**p.extra, **extra})


def _names(params, n=5):
    init = InitialConfiguration(list(range(n)), [[0.2 * k, 0.0, 0.0] for k in range(n)])
    return set(simulate(Wang2020(), SHAPE, init, params, seed=0, max_steps=1, allow_violations=True)
               .broken_assumptions)


def test_the_bound_is_sec_iii_a_at_equal_speeds_and_grows_as_v_min_falls():
    assert speed_buffer_bound(default_params()) == 2 * math.sqrt(2) * 0.05
    assert speed_range(default_params()) == (0.05, 0.05)
    at = _params(speed_min=0.05 * RHO_AT_02, speed_max=0.05)
    assert speed_buffer_bound(at) == pytest.approx(0.2, abs=1e-15)
    # Sec. V-B3's two cases: the orthogonal one, 2 r sqrt(v_max^2 + v_min^2) / v_min, dominates the
    # collinear one, 2 r v_max / v_min
    for lo in (0.01, 0.03, 0.049):
        p = _params(speed_min=lo, speed_max=0.05)
        assert speed_buffer_bound(p) == pytest.approx(2 * 0.05 * math.hypot(0.05, lo) / lo)
        assert speed_buffer_bound(p) > 2 * 0.05 * 0.05 / lo


@pytest.mark.parametrize("extra, broken", [
    ({}, set()),
    ({"speed_min": 0.03, "speed_max": 0.05}, {"same_speed"}),                     # 0.6 > 1/sqrt(3): l = 0.2 is enough
    ({"speed_min": 0.05 * RHO_AT_02, "speed_max": 0.05}, {"same_speed"}),          # exactly at the bound
    ({"speed_min": 0.025, "speed_max": 0.05}, {"same_speed", "speed_buffer"}),    # bound 0.2236 > 0.2
    ({"speed_min": 0.04, "speed_max": 0.04}, set()),                              # one speed other than v
    ({"grid_spacing": 0.1}, {"grid_spacing_bounds", "speed_buffer", "goals_on_grid"}),  # equal speeds: 2 sqrt 2 r
], ids=["paper", "spread-within", "at-bound", "below-bound", "equal-not-v", "l<2sqrt2r"])
def test_same_speed_and_speed_buffer_are_broken_exactly_when_their_statements_are_false(extra, broken):
    assert _names(_params(**extra)) == broken


def test_the_engine_refuses_a_grid_below_the_speed_buffer_unless_allowed():
    init = InitialConfiguration(list(range(5)), [[0.2 * k, 0.0, 0.0] for k in range(5)])
    with pytest.raises(AssumptionError, match=r"assumption 'speed_buffer' broken: grid_spacing=0.2 < "
                                              r"2\*robot_radius\*sqrt\(speed_max\^2 \+ speed_min\^2\)/speed_min = "
                                              r"0.223607 \(robot_radius=0.05, speed_min=0.025, speed_max=0.05\) "
                                              r"\(l >= 2 r sqrt\(v_max\^2 \+ v_min\^2\) / v_min .*004 Sec. V-B3\); "
                                              r"fix: change the value, or pass allow_violations=True"):
        simulate(Wang2020(), SHAPE, init, _params(speed_min=0.025, speed_max=0.05), seed=0, max_steps=1)
    with pytest.raises(AssumptionError, match=r"assumption 'same_speed' broken: speed_min=0.03 != speed_max=0.05 "
                                              r"\(every agent has the same speed v_m on a grid edge; 004 Sec. II-A d\)"):
        simulate(Wang2020(), SHAPE, init, _params(speed_min=0.03, speed_max=0.05), seed=0, max_steps=1)


def test_a_run_with_speeds_within_the_bound_ends_without_overlap():
    # (whether the shape is formed at the end is another matter: Sec. III-B's detection can fire
    # early, a finding of docs/wang2020.md, with equal speeds too)
    alg = Wang2020()
    p = _params(speed_min=0.03, speed_max=0.05)
    init = alg.initial(5, 0, p, SHAPE)
    r = simulate(alg, SHAPE, init, p, seed=0, allow_violations=True)
    assert r.status == "finished"
    assert r.broken_assumptions == ("same_speed",) and len(set(r.trace.meta["speeds"]["speed"])) == 5
    assert collision(r.trace, 0.05).status == "held"


def test_cli_exit_2_names_the_speed_buffer(capsys):
    from swarmproof.cli import main

    code = main(["simulate", "wang2020", "--shape", "letter-l", "--robots", "5", "--seed", "0", "--json",
                 "--param", "speed_min=0.025"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 2 and "assumption 'speed_buffer' broken: grid_spacing=0.2 < " in doc["error"]["message"]
    code = main(["simulate", "wang2020", "--shape", "letter-l", "--robots", "5", "--seed", "0", "--json",
                 "--param", "speed_min=-1"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 2 and "parameter speed_min=-1 is outside its range (0, inf)" in doc["error"]["message"] and "fix:" in doc["error"]["message"]
