"""Properties are objects in a registry (issue 12): the built-ins, and a user's own
property registered, explored, written as a counterexample and replayed."""

from __future__ import annotations

import json
import textwrap

import pytest

from swarmproof.checkers.explore import explore, explore_properties
from swarmproof.cli import main
from swarmproof.invariants.registry import (Property, get_property, properties, property_check,
                                            register_property, unregister_property)
from swarmproof.invariants.result import InvariantResult
from swarmproof.models.errors import UsageError

USER_MODULE = textwrap.dedent('''
    import numpy as np

    from swarmproof.invariants.registry import property_check
    from swarmproof.invariants.result import InvariantResult


    @property_check("tight_swarm", "safety", reads=("poses", "range"),
                    blind_spots="recorded steps only", cites="a user's own property")
    def tight_swarm(trace, ctx):
        """Every two robots stay within half the range of each other."""
        limit = 0.5 * ctx.phi
        for t in range(trace.frames):
            xy = trace.poses[t][:, :2]
            d = np.sqrt(((xy[:, None, :] - xy[None, :, :]) ** 2).sum(-1))
            if d.max() > limit:
                i, j = np.unravel_index(int(d.argmax()), d.shape)
                return InvariantResult("tight_swarm", "violated", "a user's own property",
                                       {"step": t, "pair": [int(trace.ids[i]), int(trace.ids[j])]},
                                       f"robots {int(trace.ids[i])} and {int(trace.ids[j])} are "
                                       f"{d.max():.4g} apart in step {t} (> {limit:.4g})")
        return InvariantResult("tight_swarm", "held", "a user's own property", None, "tight throughout")
''')


@pytest.fixture
def user_property(tmp_path, monkeypatch):
    (tmp_path / "my_props.py").write_text(USER_MODULE)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield "my_props:tight_swarm"
    unregister_property("tight_swarm")
    import sys
    sys.modules.pop("my_props", None)


def test_builtins_are_registered_in_order_with_kind_reads_and_blind_spots():
    names = [p.name for p in properties()]
    assert names[:8] == ["connectivity", "tree_links", "termination", "formation", "collision",
                         "deadlock", "oscillation", "premises"]
    kinds = {p.name: p.kind for p in properties()}
    assert kinds["connectivity"] == kinds["collision"] == kinds["premises"] == "safety"
    assert kinds["termination"] == kinds["formation"] == kinds["deadlock"] == "liveness"
    for p in properties():
        row = p.as_dict()
        assert row["reads"] and row["blind_spots"] and row["cites"], row
    assert get_property("tree_links").closeness is not None
    assert get_property("oscillation").run_monitor is not None


@pytest.mark.parametrize("kwargs, match", [
    (dict(name="", kind="safety"), r"property name=''"),
    (dict(name="a:b", kind="safety"), r"property name='a:b'"),
    (dict(name="x", kind="eventually"), r"kind='eventually' is not one of \['safety', 'liveness'\]"),
    (dict(name="x", kind="safety", check=3), r"check=3 is not callable"),
])
def test_a_bad_property_is_refused_naming_the_field(kwargs, match):
    kwargs.setdefault("check", lambda trace, ctx: None)
    with pytest.raises(UsageError, match=match):
        Property(**kwargs)


def test_a_taken_name_is_refused_and_unknown_names_list_the_registered():
    with pytest.raises(UsageError, match=r"property name='connectivity' is registered already"):
        register_property(Property("connectivity", "safety", lambda trace, ctx: None))
    with pytest.raises(UsageError, match=r"property='nope' is not known; fix: use one of \['connectivity'"):
        get_property("nope")
    with pytest.raises(UsageError, match=r"module 'no_such_module_xyz' cannot be imported"):
        get_property("no_such_module_xyz:p")


def test_a_registered_property_joins_the_default_list_and_leaves_again():
    @property_check("always_held_for_test", "safety", reads=("nothing",), blind_spots="all", cites="test")
    def _check(trace, ctx):
        return InvariantResult("always_held_for_test", "held", "test", None, "held")
    try:
        assert explore_properties()[-1] == "always_held_for_test"
    finally:
        unregister_property("always_held_for_test")
    assert "always_held_for_test" not in explore_properties()


def test_a_users_property_is_explored_shrunk_written_and_replayed(user_property, tmp_path, capsys):
    report = explore("example-gather", [user_property], max_examples=20, robots=(2, 5), seed=0,
                     budget=None, out_dir=tmp_path / "cx")
    v = report.properties[user_property]
    assert v.status == "violated" and report.exit_code == 1
    assert len(v.counterexample.robots) == 2          # shrunk to the smallest team that can break it
    assert v.counterexample.violation["message"].startswith("robots ")
    doc = json.loads(open(v.counterexample_path).read())
    assert doc["property"] == "my_props:tight_swarm"
    assert v.counterexample_path.endswith("-my_props_tight_swarm-seed0.json")
    code = main(["replay", v.counterexample_path, "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 1 and out["reproduced"] is True


def test_the_command_line_explores_a_users_property_by_module_name(user_property, tmp_path, capsys):
    code = main(["explore", "example-gather", "--property", user_property, "--max-examples", "10",
                 "--robots", "2..4", "--seed", "1", "--budget", "none", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 1 and doc["properties"][user_property]["status"] == "violated"


def test_completion_sound_runs_the_completion_invariants_an_algorithm_declares():
    """completion_sound is the invariants machinery under another name: whatever invariants an
    algorithm declares as ``completion_invariants``, streamed or on the trace; an invariant that
    counts what it judged (``judged``) and judged nothing leaves the run inconclusive, never held;
    an algorithm that declares none gets no verdict (not applicable)."""
    import numpy as np

    from swarmproof.invariants.algorithm_invariants import Invariant
    from swarmproof.invariants.registry import PropertyContext
    from swarmproof.models.trace import Trace

    class Count:
        """'whenever a robot says done, every robot is at x >= 1'."""

        def __init__(self):
            self.n = 0

        def __call__(self, t, ids, poses, states):
            if not any(dict(s)["done"] for s in states):
                return None
            self.n += 1
            return None if (np.asarray(poses)[:, 0] >= 1).all() else f"done in step {t} short of x = 1"

    def algorithm():
        check = Count()
        return type("Alg", (), {"completion_invariants": (Invariant("done_sound", "done only at x >= 1", "toy",
                                                                     check, judged=lambda: check.n),)})()

    prop = get_property("completion_sound")
    assert prop.kind == "safety" and prop.every_step and prop.needs == ("completion",) and prop.run_monitor is None
    assert prop.not_applicable_to(type("Plain", (), {})) == \
        "its robots do not detect completion (no completion_invariants)"
    xs, done = [0.0, 0.5, 1.0], [False, False, True]
    trace = Trace(ids=[7], poses=np.array([[[x, 0, 0]] for x in xs]), states=[((("done", d),),) for d in done])
    r = prop.check(trace, PropertyContext(algorithm(), None, None, None))
    assert r.status == "held" and r.message == ("done_sound held at every one of 3 observed steps, done_sound "
                                                "judged 1 time")
    early = Trace(ids=[7], poses=trace.poses, states=[((("done", d),),) for d in (False, True, True)])
    r = prop.check(early, PropertyContext(algorithm(), None, None, None))
    assert r.status == "violated" and r.name == "completion_sound" and r.witness["step"] == 1
    assert r.message == "done_sound (toy) broke in step 1: done in step 1 short of x = 1"
    never = Trace(ids=[7], poses=trace.poses, states=[((("done", False),),)] * 3)
    r = prop.check(never, PropertyContext(algorithm(), None, None, None))
    assert r.status == "inconclusive" and r.message == "vacuous: done_sound had nothing to judge in 3 observed steps"
    mon = prop.stream(algorithm(), None, {})              # the streaming form: the same verdict
    mon.start([7])
    for t in range(3):
        mon.observe(t, early.poses[t], early.states[t], np.array([True]))
    assert mon.name == "completion_sound" and mon.result().witness["step"] == 1
