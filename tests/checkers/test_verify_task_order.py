"""verify --workers hands out its exploration tasks costliest first (``VerifyPlan.explore_cost``):
the order changes when the rows are ready, never the rows."""
import pytest

from swarmproof.checkers.report import _explore_one, _explore_parallel, costliest_first

pytest.importorskip("distributed")


def test_costliest_first_unknown_then_by_cost_ties_in_order():
    assert costliest_first([]) == []
    assert costliest_first([5.0]) == [0]
    assert costliest_first([1, 3, 2]) == [1, 2, 0]
    assert costliest_first([None, 3, None, 3]) == [0, 2, 1, 3]


def test_the_worker_starts_the_costliest_job_first_and_the_results_keep_the_jobs_order():
    from distributed import get_task_stream

    from swarmproof.checkers.campaign import local_client

    jobs = [("song2014", (prop,), 2, (3, 3), 0, None, None) for prop in ("connectivity", "termination", "formation")]
    costs = [1.0, 30.0, 7.0]
    with local_client(1) as client:
        with get_task_stream(client) as stream:
            got = _explore_parallel(jobs, 1, None, client=client, costs=costs)
    start = {}
    for rec in stream.data:
        begin = min(s["start"] for s in rec["startstops"] if s["action"] == "compute")
        start[rec["key"]] = begin
    started = [int(key.split("-")[2]) for key in sorted(start, key=start.get)]
    assert started == [1, 2, 0]
    # the results are one process's, in the jobs' order
    assert got == [_explore_one(*job) for job in jobs]


@pytest.mark.parametrize("cost", ["fast", -1, float("nan"), float("inf"), True], ids=repr)
def test_a_bad_explore_cost_is_a_usage_error_naming_it(cost):
    from swarmproof.models.errors import UsageError
    from swarmproof.reference_impl.protocol import VerifyPlan

    with pytest.raises(UsageError, match=r"explore_cost="):
        VerifyPlan(("square",), explore_cost=cost)


@pytest.mark.parametrize("cost", [None, 0, 12.5, 196])
def test_a_number_of_seconds_or_none_is_an_explore_cost(cost):
    from swarmproof.reference_impl.protocol import VerifyPlan

    assert VerifyPlan(("square",), explore_cost=cost).explore_cost == cost


@pytest.mark.parametrize("cap", ["15", 0, 2.5, True], ids=repr)
def test_a_bad_explore_max_examples_is_a_usage_error_naming_it(cap):
    from swarmproof.models.errors import UsageError
    from swarmproof.reference_impl.protocol import VerifyPlan

    with pytest.raises(UsageError, match=r"explore_max_examples="):
        VerifyPlan(("square",), explore_max_examples=cap)
    assert VerifyPlan(("square",), explore_max_examples=15).explore_max_examples == 15
