"""Mutation benchmark (issue 6): the explorer against plain Monte Carlo on seeded faults.

For every fault of :mod:`mutants` (a copy of a reference implementation with
one mistake) two hunters get the same wall-clock budget B and look for a
violation of the fault's target property:

(a) the explorer, :func:`swarmproof.checkers.explore.explore` with
    ``budget=B``, ``robots=(lo, hi)`` and ``max_examples`` so large
    (:data:`MAX_EXAMPLES`) that the budget ends every search (finding *and*
    shrinking share B), and the fault's ``speeds`` if it has any;
(b) plain seeded Monte Carlo: from ``numpy.random.default_rng(seed)``, again
    and again, a random n in ``[lo, hi]``, a random bundled periodic lattice
    and a random connected start (:func:`reference_impl.initial.random_connected`,
    minimum separation range/4 as the explorer's scenarios) and, for a fault
    with ``speeds``, a v drawn uniformly from them, run by the same
    :func:`~swarmproof.checkers.explore.run_scenario` and judged by the same
    :func:`~swarmproof.checkers.explore.judge`, until a run violates the
    property or B is spent (checked before each run, like the explorer).

Recorded per fault and hunter: found or not, wall and CPU seconds
(``time.process_time``) to the *first* counterexample, the robot count and
violation step of the counterexample (the explorer's after shrinking, and of
its first failing scenario before shrinking).  The explorer's time to its
first failing scenario is taken by wrapping the explorer module's ``judge``
for the run (the explorer itself is unchanged; its own ``seconds`` include
shrinking).  A Monte Carlo hunt that finds nothing within B counts as not
found; for the speed-up its time is taken as B, a lower bound, and the ratio
is then printed as ``>= x``.

Usage (from the repository root)::

    .venv/bin/python benchmarks/bench_mutations.py --budget 60 --seed 0 --json mut.json
    .venv/bin/python benchmarks/bench_mutations.py --faults song2016~nclb-ignored --budget 10
    .venv/bin/python benchmarks/bench_mutations.py --list

Deterministic given the seed, apart from the times (and, when a budget is
hit while shrinking, the explorer's counterexample size, since Hypothesis
stops shrinking at the budget).

References
----------
Issue 6 ("Must hold": the mutation benchmark); 000_3ad33c5b62f11d5f.txt and
001_7a4e517b856331bc.txt for the faults (see mutants.py).
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import os
import platform
import statistics
import sys
import time
from typing import Any, Sequence

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from mutants import FAULTS, FAULT_NAMES, Fault, get_fault, registered  # noqa: E402

from swarmproof.models.errors import UsageError  # noqa: E402
from swarmproof.checkers.explore import judge as _PLAIN_JUDGE  # noqa: E402  (before any wrapping)

DEFAULT_BUDGET = 60.0
DEFAULT_ROBOTS = (3, 8)
#: The team sizes of each paper's own simulations, for ``--mc-robots paper`` (Monte Carlo "what
#: the papers did", issue 6): 001 Sec. VI varied n between 10 and 40; 000 Sec. V between 50 and
#: 250, of which only the smallest, 50, is used: one 50-robot song2014 run to its step cap took
#: 28 s CPU and 841 MB here (2026-11-24), and larger ones would exceed the budget and the memory.
PAPER_ROBOTS = {"song2014": (50, 50), "song2016": (10, 40)}
#: The explorer's ``max_examples`` in the benchmark: so large that the budget, not the example
#: count, ends every search (the explorer stops Hypothesis as soon as its budget is spent).
MAX_EXAMPLES = 10**6


def reference_judgment(fault: Fault, prop: str, lattice, params, result, options=None):
    """The *reference*'s judgment of ``prop`` on the scenario of ``result`` (a mutant's run):
    the same start, parameters, seed and step cap, run with ``fault.reference``."""
    from swarmproof.checkers.explore import run_scenario

    trace = result.trace
    pres = trace.present_at(0)
    ids = [int(i) for i, p in zip(trace.ids.tolist(), pres) if p]
    poses = [list(map(float, q)) for q, p in zip(trace.poses[0], pres) if p]
    algo, ref = run_scenario(fault.reference, lattice, ids, poses, params, seed=int(result.seed),
                             max_steps=int(result.max_steps))
    # the plain judge: inside the explorer's hunt the module's ``judge`` is wrapped by
    # first_violation_clock, which calls this function (it would recurse on the reference)
    return _PLAIN_JUDGE(prop, algo, lattice, params, ref, options)


def reference_fails_too(fault: Fault, prop: str, lattice, params, result, options=None) -> bool:
    """Does the *reference* violate ``prop`` on the scenario of ``result`` (a mutant's run)?

    The benchmark counts a violation as evidence of the fault only when the
    reference passes the same start, parameters and seed (a differential
    check): the reference song2016 itself broke tree links at long steps on
    some starts until its case-3 fix (docs/song2016.md), and such a run tells
    nothing about the fault.
    """
    return reference_judgment(fault, prop, lattice, params, result, options).violated


@contextlib.contextmanager
def first_violation_clock(fault: Fault | None = None):
    """Wrap ``swarmproof.checkers.explore.judge`` to time-stamp the first violated judgment.

    Yields a dict that gets ``wall``, ``cpu`` (absolute ``time.monotonic`` /
    ``time.process_time`` readings), ``robots`` and ``step`` of the first
    violating scenario; the original ``judge`` is restored on exit.  With
    ``fault``, a violation on a scenario where the reference fails too
    (:func:`reference_fails_too`) is turned into ``inconclusive`` for the
    explorer (neither a counterexample nor a pass) and counted in
    ``seen["reference_also"]``.
    """
    from swarmproof.checkers import explore as explore_mod
    from swarmproof.invariants.result import InvariantResult

    original = explore_mod.judge
    seen: dict[str, Any] = {"reference_also": 0}

    def judge(prop, algorithm, lattice, params, result, options=None):
        r = original(prop, algorithm, lattice, params, result, options)
        if r.violated and fault is not None and reference_fails_too(fault, prop, lattice, params, result, options):
            seen["reference_also"] += 1
            return InvariantResult(r.name, "inconclusive", r.cites, None,
                                   f"the reference {fault.reference} fails here too: {r.message}")
        if r.violated and "wall" not in seen:
            seen.update(wall=time.monotonic(), cpu=time.process_time(), robots=int(result.trace.n),
                        step=(r.witness or {}).get("step"))
        return r

    explore_mod.judge = judge
    try:
        yield seen
    finally:
        explore_mod.judge = original


def hunt_explorer(fault: Fault, budget: float, seed: int, robots: tuple[int, int],
                  max_examples: int | None = None) -> dict:
    """Hunt ``fault.target`` on the registered mutant with the explorer (budget ``budget``)."""
    from swarmproof.checkers.explore import explore

    with first_violation_clock(fault) as first:
        w0, c0 = time.monotonic(), time.process_time()
        rep = explore(fault.name, [fault.target], budget=budget,
                      max_examples=MAX_EXAMPLES if max_examples is None else max_examples,
                      robots=robots, seed=seed, options=fault.options, params=fault.params,
                      speeds=fault.speeds or None)
        w1, c1 = time.monotonic(), time.process_time()
    v = rep.properties[fault.target]
    cx = v.counterexample
    replayed = None
    if cx is not None:
        from swarmproof.checkers.replay import replay

        replayed = replay(cx)
    return {
        "hunter": "explorer", "status": v.status, "found": v.status == "violated",
        "seconds_to_first": None if "wall" not in first else first["wall"] - w0,
        "cpu_to_first": None if "cpu" not in first else first["cpu"] - c0,
        "first_robots": first.get("robots"), "first_step": first.get("step"),
        "robots": None if cx is None else len(cx.robots),
        "step": None if cx is None else cx.violation.get("step"),
        "lattice": None if cx is None else cx.lattice,
        "run_steps": None if replayed is None else int(replayed.result.steps),
        "replay_reproduced": None if replayed is None else bool(replayed.reproduced),
        "counterexample": None if cx is None else cx.as_dict(),
        "message": v.message, "scenarios": v.scenarios, "steps": v.steps,
        "seconds_total": w1 - w0, "cpu_total": c1 - c0, "budget_hit": v.budget_hit,
        "first_scenarios": v.first_failure_scenarios,
        "reference_also": first["reference_also"],
        "v": None if cx is None else cx.params.get("v"),
    }


def monte_carlo_start(fault: Fault, algorithm: str, lattice, n: int, run_seed: int, v: float | None):
    """A Monte Carlo run's start and parameters: ``random_connected(n, run_seed)`` (minimum
    separation range/4, as the explorer's scenarios) and ``algorithm``'s parameters with the
    fault's ``params`` and, when given, speed ``v``.  Returns ``(initial, params)``; the hunt
    and :func:`reference_verdict` rebuild the same run from these four numbers."""
    from swarmproof.checkers.explore import MIN_SEP_FRACTION
    from swarmproof.checkers.runs import build_params
    from swarmproof.reference_impl.initial import random_connected
    from swarmproof.reference_impl.registry import get_algorithm

    phi = float(lattice.range)
    init = random_connected(n, run_seed, range=phi, min_separation=MIN_SEP_FRACTION * phi)
    fixed = dict(fault.params)
    if v is not None:
        fixed["v"] = float(v)
    return init, build_params(get_algorithm(algorithm, n_robots=n), phi, n, **fixed)


def hunt_monte_carlo(fault: Fault, budget: float, seed: int, robots: tuple[int, int],
                     lattices: Sequence[str] | None = None, early_stop: bool = False) -> dict:
    """Plain seeded Monte Carlo on the registered mutant until a violation or ``budget`` seconds.

    Each run goes to its end and is judged then, as the papers' simulations
    did; ``early_stop=True`` gives Monte Carlo the explorer's run-time cycle
    monitor as well (:func:`~swarmproof.checkers.explore.run_and_judge`).
    """
    import numpy as np

    from swarmproof.checkers.explore import PERIODIC_LATTICES, run_and_judge
    from swarmproof.models.library import load

    names = list(PERIODIC_LATTICES if lattices is None else lattices)
    loaded = {name: load(name) for name in names}
    rng = np.random.default_rng(seed)
    runs = steps = reference_also = 0
    w0, c0 = time.monotonic(), time.process_time()
    out = {"hunter": "monte_carlo", "status": "held", "found": False, "seconds_to_first": None,
           "cpu_to_first": None, "robots": None, "step": None, "lattice": None, "message": "",
           "run_steps": None,
           "run_seed": None, "reference": None}
    while time.monotonic() - w0 < budget:
        n = int(rng.integers(robots[0], robots[1] + 1))
        name = names[int(rng.integers(len(names)))]
        run_seed = int(rng.integers(0, 2**31 - 1))
        v = float(fault.speeds[int(rng.integers(len(fault.speeds)))]) if fault.speeds else None
        lattice = loaded[name]
        init, params = monte_carlo_start(fault, fault.name, lattice, n, run_seed, v)
        algo, result, r = run_and_judge(fault.name, fault.target, lattice, init.ids.tolist(), init.poses.tolist(),
                                        params, seed=run_seed, options=fault.options, early_stop=early_stop)
        runs += 1
        steps += int(result.steps)
        if r.violated:
            # the reference's judgment of the same run: a violation it shares tells nothing
            ref = reference_judgment(fault, fault.target, lattice, params, result, fault.options)
            if ref.violated:
                reference_also += 1
                continue
            out.update(status="violated", found=True, seconds_to_first=time.monotonic() - w0,
                       cpu_to_first=time.process_time() - c0, robots=n,
                       step=(r.witness or {}).get("step"), lattice=name, message=r.message,
                       run_steps=int(result.steps),
                       run_seed=run_seed, v=params.v, reference=ref.status)
            break
    out.update(runs=runs, steps=steps, reference_also=reference_also, seconds_total=time.monotonic() - w0,
               cpu_total=time.process_time() - c0)
    return out


def reference_verdict(fault: Fault, hunt: dict) -> str | None:
    """The *reference* algorithm's verdict on the scenario of a hunter's counterexample.

    A fault is only told by a counterexample the reference passes, so each one
    is run again with ``fault.reference`` in place of the mutant: the
    explorer's shrunk counterexample through replay, Monte Carlo's failing run
    rebuilt from its ``run_seed``, robot count, lattice and ``v``.  Returns
    ``"held"``, ``"violated"`` (the reference fails there too: not evidence of
    the fault) or ``"inconclusive"``; None when the hunter found nothing.
    """
    if not hunt.get("found"):
        return None
    if hunt["hunter"] == "explorer":
        import dataclasses

        from swarmproof.checkers.replay import replay
        from swarmproof.models.counterexample import Counterexample

        cx = Counterexample.from_dict(hunt["counterexample"])
        return replay(dataclasses.replace(cx, algorithm=fault.reference)).verdict.status
    from swarmproof.checkers.explore import run_and_judge
    from swarmproof.models.library import load

    lattice = load(hunt["lattice"])
    run_seed = int(hunt["run_seed"])
    init, params = monte_carlo_start(fault, fault.reference, lattice, int(hunt["robots"]), run_seed,
                                     hunt.get("v"))
    _, _, r = run_and_judge(fault.reference, fault.target, lattice, init.ids.tolist(), init.poses.tolist(),
                            params, seed=run_seed, options=fault.options, early_stop=False)
    return r.status


def within_budget(hunt: dict, budget: float) -> dict:
    """Count a violation found only if it came within the budget.

    Both hunters check the budget before each run and finish a run under
    way, so a long run can end (and fail) well after ``budget`` seconds
    (measured: one 27-robot song2016 run took 221 s).  Such a hunt is marked
    not found, with ``late_seconds`` (wall seconds to the late violation).
    """
    if hunt["found"] and hunt["seconds_to_first"] is not None and hunt["seconds_to_first"] > budget:
        hunt = dict(hunt, found=False, status="late", late_seconds=hunt["seconds_to_first"])
    return hunt


def speedup(explorer: dict, mc: dict) -> tuple[float | None, bool]:
    """``(ratio, lower_bound)``: Monte Carlo's CPU seconds to first over the explorer's.

    CPU time (``time.process_time``), because the machine is shared.  Monte
    Carlo that found nothing counts with all the CPU time it spent in the
    budget (a lower bound on its time to first); None when the explorer
    found nothing.
    """
    if not explorer["found"] or explorer["cpu_to_first"] is None:
        return None, False
    t_e = max(explorer["cpu_to_first"], 1e-3)   # process_time resolution, no division by ~0
    if mc["found"]:
        return mc["cpu_to_first"] / t_e, False
    return mc["cpu_total"] / t_e, True


def mc_robots_for(fault: Fault, robots: tuple[int, int], mc_robots) -> tuple[int, int]:
    """Monte Carlo's robot range for ``fault``: ``mc_robots``, the paper's sizes for ``"paper"``, else ``robots``.

    >>> f = get_fault("song2014~no-eq8-turn")
    >>> mc_robots_for(f, (3, 8), None), mc_robots_for(f, (3, 8), (10, 30)), mc_robots_for(f, (3, 8), "paper")
    ((3, 8), (10, 30), (50, 50))
    """
    if mc_robots == "paper":
        return PAPER_ROBOTS[fault.reference]
    return tuple(mc_robots or robots)


def run_benchmark(faults: Sequence[Fault], budget: float, seed: int, robots: tuple[int, int],
                  mc_robots: tuple[int, int] | str | None = None, max_examples: int | None = None,
                  log=None, mc_early_stop: bool = False) -> dict:
    """Run both hunters on every fault; returns the JSON document (see :func:`summarize`).

    ``mc_robots``: Monte Carlo's robot range, or ``"paper"`` for each paper's own
    team sizes (:data:`PAPER_ROBOTS`); default the explorer's ``robots``.
    """
    rows = []
    with registered(faults):
        for f in faults:
            e = hunt_explorer(f, budget, seed, robots, max_examples)
            m = hunt_monte_carlo(f, budget, seed, mc_robots_for(f, robots, mc_robots), early_stop=mc_early_stop)
            # Monte Carlo judged its find on the reference already (hunt_monte_carlo)
            e["reference"] = reference_verdict(f, e)
            row = judge_row({"fault": f.name, "reference": f.reference, "description": f.description,
                             "breaks": f.breaks, "property": f.target, "options": dict(f.options),
                             "params": dict(f.params), "speeds": list(f.speeds), "equivalent": f.equivalent,
                             "explorer": e, "monte_carlo": m}, budget)
            rows.append(row)
            if log is not None:
                log(format_row(row))
    doc = summarize(rows, budget, seed, robots, mc_robots or robots)
    doc["mc_early_stop"] = bool(mc_early_stop)
    return doc


def judge_row(row: dict, budget: float) -> dict:
    """Apply :func:`within_budget` to both hunters of a row and set its speed-up."""
    row = dict(row, explorer=within_budget(row["explorer"], budget),
               monte_carlo=within_budget(row["monte_carlo"], budget))
    row["speedup"], row["speedup_lower_bound"] = speedup(row["explorer"], row["monte_carlo"])
    return row


def retable(doc: dict) -> dict:
    """Re-judge a saved document's rows (:func:`judge_row`) and summarize them again."""
    B = doc["budget"]
    out = summarize([judge_row(r, B) for r in doc["rows"]], B, doc["seed"], doc["robots"], doc["mc_robots"])
    for key in ("machine", "mc_early_stop"):
        if key in doc:
            out[key] = doc[key]
    return out


def _median(xs):
    return None if not xs else statistics.median(xs)


def summarize(rows: list[dict], budget: float, seed: int, robots, mc_robots) -> dict:
    """The document: rows plus shares found, medians and the goals of issue 6."""
    k = len(rows)
    ef = [r for r in rows if r["explorer"]["found"]]
    mf = [r for r in rows if r["monte_carlo"]["found"]]
    e_times = [r["explorer"]["seconds_to_first"] for r in ef]
    m_times = [r["monte_carlo"]["seconds_to_first"] for r in mf]
    m_times_bound = [r["monte_carlo"]["seconds_to_first"] if r["monte_carlo"]["found"] else budget
                     for r in rows]
    e_cpu = [r["explorer"]["cpu_to_first"] for r in ef]
    m_cpu_bound = [r["monte_carlo"]["cpu_to_first"] if r["monte_carlo"]["found"] else r["monte_carlo"]["cpu_total"]
                   for r in rows]
    ratios = [r["speedup"] for r in rows if r["speedup"] is not None]
    e_sizes = [r["explorer"]["robots"] for r in ef]
    live = [r for r in rows if not r.get("equivalent")]
    summary = {
        "faults": k,
        "equivalent": k - len(live),
        "explorer_found_live": sum(1 for r in live if r["explorer"]["found"]),
        "explorer_found": len(ef), "monte_carlo_found": len(mf),
        "explorer_share": len(ef) / k if k else None, "monte_carlo_share": len(mf) / k if k else None,
        "explorer_median_seconds_to_first": _median(e_times),
        "monte_carlo_median_seconds_to_first_found": _median(m_times),
        "monte_carlo_median_seconds_to_first_lower_bound": _median(m_times_bound),
        "explorer_median_cpu_to_first": _median(e_cpu),
        "monte_carlo_median_cpu_to_first_lower_bound": _median(m_cpu_bound),
        "median_speedup": _median(ratios),
        "median_cpu_ratio": (None if not e_cpu or not m_cpu_bound
                             else _median(m_cpu_bound) / max(_median(e_cpu), 1e-3)),
        "explorer_max_robots": max(e_sizes) if e_sizes else None,
        "monte_carlo_median_robots": _median([r["monte_carlo"]["robots"] for r in mf]),
        "explorer_also_on_reference": sum(1 for r in ef if r["explorer"].get("reference") == "violated"),
        "explorer_skipped_reference_fails": sum(int(r["explorer"].get("reference_also") or 0) for r in rows),
        "monte_carlo_skipped_reference_fails": sum(int(r["monte_carlo"].get("reference_also") or 0) for r in rows),
        "monte_carlo_also_on_reference": sum(1 for r in mf if r["monte_carlo"].get("reference") == "violated"),
        "goal_every_fault_found": len(ef) == k,
        "goal_every_live_fault_found": all(r["explorer"]["found"] for r in live),
        "goal_5x_every_fault": bool(rows) and all(r["speedup"] is not None and r["speedup"] >= 5 for r in rows),
        # an equivalent mutant has no counterexample to race for, so no speed-up either
        "goal_5x_every_live_fault": bool(live) and all(r["speedup"] is not None and r["speedup"] >= 5
                                                       for r in live),
        "goal_5x_median": bool(ratios) and _median(ratios) >= 5,
        "goal_at_most_8_robots": bool(ef) and all(s <= 8 for s in e_sizes),
    }
    return {"benchmark": "mutations", "budget": budget, "seed": seed, "robots": list(robots),
            "mc_robots": mc_robots if isinstance(mc_robots, str) else list(mc_robots), "rows": rows,
            "summary": summary}


def _fmt_t(h: dict) -> str:
    if h.get("status") == "late":
        return f"after B ({h['late_seconds']:.0f})"
    if not h["found"]:
        return "not found"
    return f"{h['seconds_to_first']:.2f} ({h['cpu_to_first']:.2f})"


def _fmt_ratio(row: dict) -> str:
    if row["speedup"] is None:
        return "-"
    r = row["speedup"]
    return (">= " if row["speedup_lower_bound"] else "") + (f"{r:.1f}x" if r < 10 else f"{r:.0f}x")


HEADER = ("| fault | property | explorer: s to 1st (cpu) | robots 1st -> shrunk, steps | "
          "Monte Carlo: s to 1st (cpu) | MC runs | MC robots, steps | speed-up (cpu) |")
RULE = "|---|---|---|---|---|---|---|---|"


def _steps(h: dict) -> str:
    """The counterexample's length: the violation step, else the run's steps (final-state properties)."""
    if h["step"] is not None:
        return f"step {h['step']}"
    return f"{h['run_steps']} steps"


def format_row(row: dict) -> str:
    """One Markdown table row."""
    e, m = row["explorer"], row["monte_carlo"]
    esize = f"{e['first_robots']} -> {e['robots']}, {_steps(e)}" if e["found"] else "-"
    msize = f"{m['robots']}, {_steps(m)}" if m["found"] else "-"
    return (f"| {row['fault']} | {row['property']} | {_fmt_t(e)} | {esize} | {_fmt_t(m)} | "
            f"{m['runs']} | {msize} | {_fmt_ratio(row)} |")


def format_table(doc: dict) -> list[str]:
    """The Markdown table and the summary lines."""
    s = doc["summary"]
    lines = [HEADER, RULE] + [format_row(r) for r in doc["rows"]]
    B = doc["budget"]

    def t(x):
        return "-" if x is None else f"{x:.2f} s"
    lines += [
        "",
        f"budget B = {B:g} s per hunter and fault, seed {doc['seed']}, robots "
        f"{doc['robots'][0]}..{doc['robots'][1]} (Monte Carlo " +
        ("the papers' team sizes: " + ", ".join(f"{k} {a}..{b}" for k, (a, b) in PAPER_ROBOTS.items())
         if doc["mc_robots"] == "paper" else f"{doc['mc_robots'][0]}..{doc['mc_robots'][1]}") +
        ("; with the explorer's cycle monitor" if doc.get("mc_early_stop") else "; plain runs") + ")",
        f"found: explorer {s['explorer_found']}/{s['faults']}, Monte Carlo {s['monte_carlo_found']}/{s['faults']}"
        + ("" if "explorer_also_on_reference" not in s else
           f"; counterexamples the reference fails too: explorer {s['explorer_also_on_reference']}, "
           f"Monte Carlo {s['monte_carlo_also_on_reference']}")
        + ("" if "monte_carlo_skipped_reference_fails" not in s else
           f"; violations skipped because the reference failed too: explorer "
           f"{s['explorer_skipped_reference_fails']} scenarios, Monte Carlo "
           f"{s['monte_carlo_skipped_reference_fails']} runs"),
        f"median time to first counterexample: explorer {t(s['explorer_median_seconds_to_first'])} "
        f"(found faults), Monte Carlo {t(s['monte_carlo_median_seconds_to_first_found'])} (found faults), "
        f">= {t(s['monte_carlo_median_seconds_to_first_lower_bound'])} counting not found as B (wall); "
        f"CPU: explorer {t(s['explorer_median_cpu_to_first'])}, Monte Carlo >= "
        f"{t(s['monte_carlo_median_cpu_to_first_lower_bound'])}",
        f"median speed-up (CPU) {'-' if s['median_speedup'] is None else format(s['median_speedup'], '.1f') + 'x'}"
        f" (median of the per-fault ratios; ratio of the median CPU times "
        f"{'-' if s.get('median_cpu_ratio') is None else format(s['median_cpu_ratio'], '.1f') + 'x'}); "
        f"explorer counterexamples at most {s['explorer_max_robots']} robots after shrinking; "
        f"Monte Carlo median {s['monte_carlo_median_robots']} robots",
        f"goals: every fault found {'yes' if s['goal_every_fault_found'] else 'NO'}"
        + (f" (every non-equivalent one {'yes' if s.get('goal_every_live_fault_found') else 'NO'}: "
           f"{s['explorer_found_live']}/{s['faults'] - s['equivalent']})" if s.get("equivalent") else "") + "; "
        f">= 5x on every fault {'yes' if s['goal_5x_every_fault'] else 'NO'}"
        + (f" (every non-equivalent one {'yes' if s.get('goal_5x_every_live_fault') else 'NO'})"
           if s.get("equivalent") and "goal_5x_every_live_fault" in s else "") + ", "
        f"median >= 5x {'yes' if s.get('goal_5x_median') else 'NO'}; "
        f"<= 8 robots {'yes' if s['goal_at_most_8_robots'] else 'NO'}",
    ]
    return lines


def _robots_arg(text: str) -> tuple[int, int]:
    try:
        lo, _, hi = text.partition("..")
        pair = (int(lo), int(hi))
    except ValueError:
        raise UsageError(f"robots={text!r} is not MIN..MAX", fix="e.g. --robots 3..8") from None
    if not 1 <= pair[0] <= pair[1]:
        raise UsageError(f"robots={text!r} must satisfy 1 <= MIN <= MAX", fix="e.g. --robots 3..8")
    return pair


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--budget", type=float, default=DEFAULT_BUDGET,
                    help="seconds per hunter and fault (default %(default)s)")
    ap.add_argument("--seed", type=int, default=0, help="explorer and Monte Carlo seed (default 0)")
    ap.add_argument("--faults", default=None,
                    help="comma-separated fault names (default: all; --list shows them)")
    ap.add_argument("--robots", default="3..8", help="robots MIN..MAX for both hunters (default 3..8)")
    ap.add_argument("--mc-robots", default=None,
                    help="robots MIN..MAX for Monte Carlo only, or 'paper' for each paper's own team sizes "
                         "(song2014 50, the smallest of 000 Sec. V's 50..250; song2016 10..40)")
    ap.add_argument("--mc-early-stop", action="store_true",
                    help="give Monte Carlo the explorer's run-time cycle monitor too (default: plain runs)")
    ap.add_argument("--json", dest="json_out", default=None, metavar="OUT", help="write the raw numbers")
    ap.add_argument("--list", action="store_true", help="list the faults and exit")
    ap.add_argument("--from-json", dest="from_json", default=None, metavar="IN",
                    help="print the table of a saved --json document (re-judged) and exit")
    ap.add_argument("--check-reference", action="store_true",
                    help="with --from-json: run every counterexample again on the reference first")
    return ap.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        if args.list:
            for f in FAULTS:
                print(f"{f.name}: {f.description} [{f.breaks}; hunts {f.target}]")
            return 0
        if args.from_json:
            import json

            try:
                with open(args.from_json, encoding="utf-8") as fh:
                    saved = json.load(fh)
                if args.check_reference:
                    with registered([get_fault(r["fault"]) for r in saved["rows"]]):
                        for r in saved["rows"]:
                            f = get_fault(r["fault"])
                            for hunter in ("explorer", "monte_carlo"):
                                r[hunter]["reference"] = reference_verdict(f, r[hunter])
                doc = retable(saved)
            except (OSError, ValueError, KeyError, TypeError) as exc:
                raise UsageError(f"from_json={args.from_json!r} is not a saved benchmark document ({exc})",
                                 fix="pass a file written by --json") from None
            for line in format_table(doc):
                print(line)
            return 0
        import math

        if not (math.isfinite(args.budget) and args.budget > 0):
            raise UsageError(f"budget={args.budget!r} must be a finite number of seconds > 0",
                             fix="e.g. --budget 60")
        if args.seed < 0:
            raise UsageError(f"seed={args.seed!r} must be >= 0", fix="e.g. --seed 0")
        names = FAULT_NAMES if args.faults is None else [s.strip() for s in args.faults.split(",") if s.strip()]
        if not names:
            raise UsageError(f"faults={args.faults!r} names no fault", fix=f"use some of {list(FAULT_NAMES)!r}")
        faults = [get_fault(n) for n in names]
        robots = _robots_arg(args.robots)
        mc_robots = (None if args.mc_robots is None else
                     "paper" if args.mc_robots.strip() == "paper" else _robots_arg(args.mc_robots))
    except UsageError as exc:
        print(f"bench_mutations: error: {exc}", file=sys.stderr)
        return 2
    started = datetime.datetime.now(datetime.timezone.utc)
    load0 = os.getloadavg()[0]
    print(HEADER)
    print(RULE)
    doc = run_benchmark(faults, args.budget, args.seed, robots, mc_robots,
                        log=lambda line: print(line, flush=True), mc_early_stop=args.mc_early_stop)
    doc["machine"] = {"cpus": os.cpu_count(), "machine": platform.machine(),
                      "python": platform.python_version(), "date": started.strftime("%Y-%m-%d %H:%M UTC"),
                      "loadavg_1min_start": load0, "loadavg_1min_end": os.getloadavg()[0]}
    for line in format_table(doc)[len(doc["rows"]) + 2:]:
        print(line)
    print(f"machine: {doc['machine']}")
    if args.json_out:
        from swarmproof.models.fileio import atomic_write_text, dumps_json

        atomic_write_text(args.json_out, dumps_json(doc))
    return 0


if __name__ == "__main__":
    sys.exit(main())
