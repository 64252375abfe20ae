"""Grid robots with speeds of their own (004 Sec. V-B3: v_min <= v_m^i <= v_max; issue 15):
the draw, its record in trace.meta, the edge fraction per step, and the usage errors."""

from __future__ import annotations

import numpy as np
import pytest

from swarmproof.models.errors import UsageError
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.engine.motion import SPEED_SPAWN_KEY, grid_speeds
from swarmproof.reference_impl.protocol import Command, Params, RobotModel

GRID = RobotModel(sensing="global", communication="neighbors", motion="grid", clocks="sync")
GRID_ASYNC = RobotModel(sensing="global", communication="neighbors", motion="grid", clocks="async")


def _runner(plan, model=GRID):
    from testkit import Recorder

    def command(rid, k, obs, rng):
        moves = plan.get(rid, [])
        return Command(message=("m", rid, obs.step), move=moves[k] if k < len(moves) else None)
    return Recorder(model, command)


def _run(plan, cells, *, extra=None, v=0.05, spacing=0.2, steps=8, seed=0, model=GRID):
    init = InitialConfiguration(list(range(len(cells))), [[x * spacing, y * spacing, 0.0] for x, y in cells])
    p = Params(range=5.0, v=v, dt=1.0, extra={"grid_spacing": spacing, **(extra or {})})
    return simulate(_runner(plan, model), None, init, p, seed=seed, max_steps=steps, stop_when_static=False)


EAST = {0: [(1, 0)], 1: [(1, 0)], 2: [(1, 0)]}
CELLS = [(0, 0), (0, 2), (0, 4)]
SPREAD = {"speed_min": 0.02, "speed_max": 0.06}


def test_no_keys_or_equal_keys_draw_nothing_and_move_every_robot_at_v():
    plain = _run(EAST, CELLS)
    same = _run(EAST, CELLS, extra={"speed_min": 0.05, "speed_max": 0.05})
    assert "speeds" not in plain.trace.meta and "speeds" not in same.trace.meta
    assert np.array_equal(plain.trace.poses, same.trace.poses)
    # 0.05 m/s * 1 s / 0.2 m = a quarter edge a step, for every robot
    assert plain.trace.poses[:5, :, 0].tolist() == [[0.0] * 3, [0.05] * 3, [0.1] * 3,
                                                    [0.15000000000000002] * 3, [0.2] * 3]
    # equal keys other than v: one speed for all, still no draw
    slow = _run(EAST, CELLS, extra={"speed_min": 0.025, "speed_max": 0.025})
    assert "speeds" not in slow.trace.meta and slow.trace.poses[8, :, 0].tolist() == [0.2] * 3
    assert slow.trace.poses[4, :, 0].tolist() == [0.1] * 3


def test_drawn_speeds_are_recorded_in_range_from_their_own_seed_sequence():
    r = _run(EAST, CELLS, extra=SPREAD, seed=7)
    meta = r.trace.meta["speeds"]
    want = np.random.default_rng(np.random.SeedSequence(7, spawn_key=SPEED_SPAWN_KEY)).uniform(0.02, 0.06, 3)
    assert SPEED_SPAWN_KEY == (3,) and meta["speed"] == want.tolist()
    assert (meta["min"], meta["max"]) == (0.02, 0.06) and all(0.02 <= s <= 0.06 for s in meta["speed"])
    assert len(set(meta["speed"])) == 3
    # the same seed gives the same speeds (replay), another seed others
    assert _run(EAST, CELLS, extra=SPREAD, seed=7).trace.meta["speeds"] == meta
    assert _run(EAST, CELLS, extra=SPREAD, seed=8).trace.meta["speeds"]["speed"] != meta["speed"]


def test_each_robot_crosses_speed_dt_over_spacing_of_its_edge_a_step_and_stops_on_the_cell():
    r = _run(EAST, CELLS, extra=SPREAD, steps=12)
    speeds = r.trace.meta["speeds"]["speed"]
    x = r.trace.poses[:, :, 0]
    for k, s in enumerate(speeds):
        frac = 0.0
        for t in range(1, 13):   # the engine's own accumulation: frac += s dt / l, then clamp on arrival
            frac += s * 1.0 / 0.2
            expect = 0.2 if frac >= 1.0 else frac * 0.2
            if frac >= 1.0:
                frac = 1.0
            assert x[t, k] == pytest.approx(expect, abs=1e-15), (k, t)
    assert x[-1].tolist() == [0.2] * 3 and r.trace.poses[:, :, 1].tolist() == [[0.0, 0.4, 0.8]] * 13


def test_speeds_leave_the_clocks_and_the_robots_draws_untouched():
    a = _run(EAST, CELLS, model=GRID_ASYNC, seed=3)
    b = _run(EAST, CELLS, model=GRID_ASYNC, seed=3, extra=SPREAD)
    assert a.trace.meta["clocks"] == b.trace.meta["clocks"] and "speeds" in b.trace.meta


BAD = [
    ({"speed_min": 0.06, "speed_max": 0.02}, r"speed_min=0.06 > speed_max=0.02; fix: give speed_min <= speed_max"),
    ({"speed_min": 0.06}, r"speed_min=0.06 > speed_max=0.05; fix: .*each defaults to v=0.05"),
    ({"speed_min": 0}, r"params.extra\['speed_min'\]=0 must be a finite speed > 0 \(m/s\); fix: "),
    ({"speed_max": -1.0}, r"params.extra\['speed_max'\]=-1.0 must be a finite speed > 0"),
    ({"speed_max": float("nan")}, r"params.extra\['speed_max'\]=nan must be a finite speed"),
    ({"speed_min": float("inf")}, r"params.extra\['speed_min'\]=inf must be a finite speed"),
    ({"speed_min": "fast"}, r"params.extra\['speed_min'\]='fast' must be a finite speed"),
    ({"speed_max": True}, r"params.extra\['speed_max'\]=True must be a finite speed"),
]


@pytest.mark.parametrize("extra, match", BAD, ids=["min>max", "min>default-v", "zero", "negative", "nan", "inf",
                                                   "string", "bool"])
def test_bad_speeds_are_usage_errors_naming_the_value_and_a_fix(extra, match):
    with pytest.raises(UsageError, match=match):
        _run(EAST, CELLS, extra=extra, steps=1)


@pytest.mark.parametrize("motion", ["holonomic", "differential"])
@pytest.mark.parametrize("key", ["speed_min", "speed_max"])
def test_continuous_motion_refuses_the_grid_speed_keys(motion, key):
    model = RobotModel(sensing="global", communication="all", motion=motion, clocks="sync")
    init = InitialConfiguration([0], [[0.0, 0.0, 0.0]])
    with pytest.raises(UsageError, match=rf"params.extra\['{key}'\]=0.03 .* for motion='grid' only, not "
                                         rf"motion='{motion}'; fix: leave {key} out"):
        simulate(_runner({}, model), None, init, Params(range=1.0, extra={key: 0.03}), seed=0, max_steps=1)


def test_grid_speeds_without_a_seed_is_a_usage_error():
    with pytest.raises(UsageError, match=r"needs the run's seed"):
        grid_speeds(Params(range=1.0, extra=SPREAD), 2, None)
    assert grid_speeds(Params(range=1.0, v=0.05), 2, None) == (0.05, 0.05, None)
