"""Issue 29: the parameter declarations (``ParamSpec``, an algorithm's ``parameters`` and
``target_kinds``) and the engine's checks that read them (reference_impl/engine/parameters.py)."""

from __future__ import annotations

import pytest

from swarmproof.models.errors import UsageError
from swarmproof.models.trace import InitialConfiguration
from swarmproof.reference_impl.engine import simulate
from swarmproof.reference_impl.engine.parameters import check_extra, declared_parameters, engine_parameters
from swarmproof.reference_impl.protocol import Params, ParamSpec, RobotModel
from swarmproof.reference_impl.registry import algorithm_factory, algorithm_names, get_algorithm


@pytest.mark.parametrize("name", algorithm_names())
def test_every_registered_algorithm_declares_its_parameters(name):
    cls = algorithm_factory(name)
    specs = getattr(cls, "parameters", None)
    assert specs is not None and all(isinstance(s, ParamSpec) and s.meaning for s in specs), name
    assert len({s.name for s in specs}) == len(specs)
    if name != "example-gather":     # it forms nothing: any target
        assert getattr(cls, "target_kinds", None), name


@pytest.mark.parametrize("name", [n for n in algorithm_names() if hasattr(algorithm_factory(n), "default_params")])
def test_default_parameters_pass_the_declarations(name):
    alg = get_algorithm(name)
    params = alg.default_params(range=1.2, n=5)
    check_extra(alg, params.extra)     # every default key is declared and in its range
    assert set(params.extra) <= set(declared_parameters(alg))


BAD_VALUES = [
    pytest.param(ParamSpec("k", int, 1, low=1), 0, r"k=0 is outside its range \[1, inf\)", id="int-below"),
    pytest.param(ParamSpec("k", int, 1, low=1), 2.5, r"k=2.5 must be a whole number", id="int-fraction"),
    pytest.param(ParamSpec("k", int, 1, low=1), True, r"k=True must be a number", id="int-bool"),
    pytest.param(ParamSpec("x", float, 0.5, low=0, high=1, high_open=True), 1, r"x=1 is outside its range \[0, 1\)",
                 id="float-open-high"),
    pytest.param(ParamSpec("x", float, 0.5), float("nan"), r"x=nan must be a finite number", id="float-nan"),
    pytest.param(ParamSpec("x", float, 0.5), "fast", r"x='fast' must be a number", id="float-text"),
    pytest.param(ParamSpec("s", str, "a", choices=("a", "b")), "c", r"s='c' is not one of \['a', 'b'\]", id="choice"),
    pytest.param(ParamSpec("s", str, "a"), 3, r"s=3 must be text", id="str-number"),
    pytest.param(ParamSpec("f", bool, False), 1, r"f=1 must be true or false", id="bool-number"),
]


@pytest.mark.parametrize("spec, value, match", BAD_VALUES)
def test_param_spec_names_the_bad_value(spec, value, match):
    import re

    why = spec.problem(value)
    assert why is not None and re.search(match, why), why


class _Declares:
    name = "declares"
    model = RobotModel()
    parameters = (ParamSpec("gap", float, 0.5, low=0, low_open=True, meaning="the gap"),)
    target_kinds = ("lattice",)


class _DeclaresNothing:
    name = "nothing"
    model = RobotModel()


def test_an_algorithm_without_declarations_is_not_checked():
    check_extra(_DeclaresNothing(), {"anything": -1, "grid_spacing": "x"})   # as before issue 29


def test_engine_keys_follow_the_model():
    grid = RobotModel(sensing="global", motion="grid", clocks="async")
    assert {s.name for s in engine_parameters(grid)} >= {"grid_spacing", "speed_min", "clock_rate_min", "broadcast_every"}
    assert {s.name for s in engine_parameters(RobotModel())} == {"robot_radius"}
    with pytest.raises(UsageError, match=r"parameter grid_spacing=1 is not known to algorithm 'declares'"):
        check_extra(_Declares(), {"grid_spacing": 1})


def test_the_engine_preflight_uses_the_declarations():
    """The one code path: the engine refuses before any step, whoever calls it (API, replay, campaigns)."""
    from swarmproof.reference_impl.examples import GatherToLowestId

    init = InitialConfiguration([0, 1], [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]])
    with pytest.raises(UsageError, match=r"parameter gpa=0.2 is not known to algorithm 'example-gather'; "
                                         r"did you mean 'gap'\?"):
        simulate(GatherToLowestId(), None, init, Params(range=1.0, extra={"gpa": 0.2}), seed=0)
    with pytest.raises(UsageError, match=r"v=0.0 must be > 0: robots that cannot move"):
        simulate(GatherToLowestId(), None, init, Params(range=1.0, v=0.0), seed=0)
    with pytest.raises(UsageError, match=r"v\*dt=5e-12 is below 1e-09 \* range=1"):
        simulate(GatherToLowestId(), None, init, Params(range=1.0, dt=1e-10), seed=0)
    r = simulate(GatherToLowestId(), None, init, Params(range=1.0, extra={"gap": 0.2}), seed=0, max_steps=3)
    assert r.steps <= 3


def test_the_engine_preflight_refuses_a_target_of_another_kind():
    from swarmproof.models.targets import resolve_target
    from swarmproof.reference_impl.song2016 import Song2016

    init = InitialConfiguration([0, 1], [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]])
    with pytest.raises(UsageError, match=r"target='letter-l' \(shape\) is not of a kind algorithm 'song2016' forms"):
        simulate(Song2016(n_robots=2), resolve_target("shape:letter-l"), init, Params(range=1.2), seed=0)
