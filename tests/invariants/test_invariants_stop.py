"""The explorer ends an ``invariants`` run at the first step where one of the algorithm's
invariants breaks (``InvariantsStop``): judging the stopped trace gives the verdict, the step, the
invariant and the message of the whole run."""

from __future__ import annotations

import pytest

from swarmproof.checkers.explore import run_and_judge
from swarmproof.checkers.runs import build_params
from swarmproof.models.targets import resolve_target
from swarmproof.reference_impl.initial import random_connected
from swarmproof.reference_impl.registry import get_algorithm


@pytest.mark.parametrize("algorithm,target", [
    # the printed ID formula breaks ids_unique when both followers stand on one side (n = 3)
    ("leechong-leader-printed", "lines:wedge"),
    ("leechong-neighbor", "lines:two-row"),
])
def test_early_stop_at_a_broken_invariant_gives_the_same_judgment(algorithm, target):
    tgt = resolve_target(target)
    seen_stop = False
    for n, seed in ((3, 0), (3, 1), (3, 2), (4, 3), (5, 4), (6, 5)):
        algo = get_algorithm(algorithm, n_robots=n)
        phi = float(algo.default_range)
        init = random_connected(n, seed, range=phi, min_separation=phi / 4)
        p = build_params(algo, phi, n)
        args = (algorithm, "invariants", tgt, init.ids.tolist(), init.poses.tolist(), p)
        _, full, a = run_and_judge(*args, seed=seed, options={}, early_stop=False)
        _, short, b = run_and_judge(*args, seed=seed, options={}, early_stop=True)
        assert (a.status, a.message, a.witness) == (b.status, b.message, b.witness), (n, seed)
        assert short.steps <= full.steps
        if a.violated and short.steps < full.steps:
            assert short.status == "stopped" and short.steps == a.witness["step"]
            seen_stop = True
    if algorithm == "leechong-leader-printed":
        assert seen_stop, "no start broke an invariant before the run's end: the test shows nothing"


def test_invariants_declared_per_instance_are_not_stopped_early():
    """wang2020 declares its invariants per instance (a property on the class): no early stop, and
    no error (make verify met `'property' object is not iterable`)."""
    from swarmproof.invariants.registry import get_property
    from swarmproof.reference_impl.registry import algorithm_factory

    rule = get_property("invariants")
    assert rule.run_monitor(algorithm_factory("wang2020"), {}) is None
    assert rule.run_monitor(algorithm_factory("leechong-neighbor"), {}) is not None
    assert rule.run_monitor(algorithm_factory("song2016"), {}) is None      # declares none


def test_every_registered_algorithm_gets_a_monitor_or_none():
    from swarmproof.invariants.registry import get_property
    from swarmproof.reference_impl.registry import algorithm_factory, algorithm_names

    rule = get_property("invariants")
    for name in algorithm_names():
        mon = rule.run_monitor(algorithm_factory(name), {})
        assert mon is None or callable(mon), name
