"""Exhaustive bounded checking: every choice sequence within a bound, not a sample (issue 33).

For a fixed start the engine's discrete nondeterminism -- which robots act in a step, each
delivery's fate, which robot crashes when (:mod:`swarmproof.reference_impl.engine.choices`) --
spans a finite tree of choice sequences within a step bound.  This module walks that tree by
*re-execution* (stateless model checking, as CHESS and Hypothesis's choice sequences do): the
engine is deterministic, so a run is fixed by its start, its seed and the choices made; each run
follows a prefix of choices, takes the default everywhere after it and records every choice
point, and the next run changes the deepest choice that still has an untried option.

Bounds (:class:`Bound`): the steps of a run, the choice kinds enumerated, and a **deviation
budget K**: the number of non-default choices a sequence may make (a lost or late message, a
duplicated one, a reordering, a crash; an activation that leaves ``j`` robots out counts ``j``).
The search deepens K from 0 (iterative context bounding, Musuvathi & Qadeer 2007), so the first
counterexample found has the fewest deviations.

Reductions, each sound for what it is used on:

- **State hashing** (safety properties only): after each step of the part of a run past its
  prefix, the run's state digest (:func:`~swarmproof.reference_impl.engine.choices.state_digest`:
  step, poses bit for bit, controller states, generators, messages in flight, clocks, motion,
  choices left) is looked up; a state already explored with at least as much budget left ends
  the run there (status ``"pruned"``): its whole future was explored from the first visit.
  Liveness (termination, formation, deadlock, oscillation) is judged on complete runs, never
  pruned: a pruned run has no end to judge.
- **Symmetry** (anonymous robots, declared by the robot model: ``sensing="anonymous"`` without
  ``own_id``): states equal up to relabelling the robots share a symmetric digest.

Verdicts: *held* means held for every choice sequence within the bound from these starts (the
message and the JSON say the bound); *violated* comes with the counterexample, whose choices
replay exactly (``swarmproof replay``); a bound not covered within the run or time budget is
*inconclusive* with the coverage reached, and so is a liveness property on a run that reached
the step bound.  Exploration by sampling never claims a proof; this does, within its bound only.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

from swarmproof.models.errors import UsageError
from swarmproof.reference_impl.engine.choices import CHOICE_KINDS, Chooser

__all__ = ["Bound", "ExhaustiveVerdict", "ExhaustiveReport", "exhaustive", "search_start", "deviation_cost",
           "SequenceSearch"]

#: Kinds enumerated when none are named: asynchronous activation.
DEFAULT_KINDS = ("activate",)
#: The bound's integer fields, the command-line flag of each and an example value.
_BOUND_FIELDS = (("steps", "--max-steps", "20"), ("deviations", "--deviations", "2"), ("max_delay", "--max-delay", "1"),
                 ("max_crashes", "--max-crashes", "1"))


@dataclass(frozen=True)
class Bound:
    """What an exhaustive search covers.

    Attributes
    ----------
    steps : int
        Each run's step cap.
    deviations : int
        K: the most non-default choices a sequence makes (:func:`deviation_cost`).
    kinds : tuple of str
        The choice kinds enumerated (:data:`~swarmproof.reference_impl.engine.choices.CHOICE_KINDS`);
        every other decision is the fault model's as without a chooser (none: the plain model).
    max_delay : int
        The largest delay of a ``delay`` choice (steps).
    max_crashes : int
        How many robots a ``crash`` choice may crash in one run.
    """

    steps: int
    deviations: int
    kinds: tuple = DEFAULT_KINDS
    max_delay: int = 1
    max_crashes: int = 1

    def __post_init__(self) -> None:
        kinds = tuple(self.kinds)
        for name, flag, example in _BOUND_FIELDS:
            v = getattr(self, name)
            lo = 1 if name == "steps" or (name == "max_delay" and "delay" in kinds) or \
                (name == "max_crashes" and "crash" in kinds) else 0
            if isinstance(v, bool) or not isinstance(v, int) or v < lo:
                why = {("max_delay", 1): " (the delay kind needs a delay to choose)",
                       ("max_crashes", 1): " (the crash kind needs a crash to choose)"}.get((name, lo), "")
                raise UsageError(f"{name}={v!r} ({flag}) must be an integer >= {lo}{why}", fix=f"e.g. {flag} {example}")
        if not kinds:
            raise UsageError("choices=() names no choice kind (--choices)", fix=f"give some of {list(CHOICE_KINDS)}")
        bad = [k for k in kinds if k not in CHOICE_KINDS]
        if bad:
            raise UsageError(f"choice kind={bad[0]!r} is not known (--choices)", fix=f"use some of {list(CHOICE_KINDS)}")
        object.__setattr__(self, "kinds", tuple(sorted(set(kinds), key=CHOICE_KINDS.index)))

    def check_applies(self, algorithm, robots: int) -> None:
        """Refuse, before any run, a kind the algorithm's robot model has no decision of, and
        activation choices over more robots than they enumerate.

        Raises
        ------
        UsageError
            ``clock_phase`` for synchronous clocks, a message kind for robots that send none,
            ``activate`` with more than :data:`MAX_ACTIVATION_ROBOTS` robots.
        """
        from swarmproof.reference_impl.engine.choices import MAX_ACTIVATION_ROBOTS

        model, name = algorithm.model, getattr(algorithm, "name", type(algorithm).__name__)
        if "clock_phase" in self.kinds and getattr(model, "clocks", "sync") != "async":
            raise UsageError(f"choice kind='clock_phase': algorithm {name!r} has synchronous clocks "
                             f"(RobotModel.clocks={model.clocks!r}): there is no phase to choose",
                             fix="drop clock_phase from --choices (activate enumerates schedules)")
        sent = [k for k in ("loss", "delay", "duplicate", "reorder") if k in self.kinds]
        if sent and getattr(model, "communication", "neighbors") == "none":
            raise UsageError(f"choice kind={sent[0]!r}: algorithm {name!r} sends no messages "
                             "(RobotModel.communication='none')", fix=f"drop {', '.join(sent)} from --choices")
        if "activate" in self.kinds and robots > MAX_ACTIVATION_ROBOTS:
            raise UsageError(f"robots={robots} with choice kind='activate': 2^{robots} - 1 schedules a step "
                             f"(at most {MAX_ACTIVATION_ROBOTS} robots)",
                             fix=f"give at most {MAX_ACTIVATION_ROBOTS} robots (--robots), or drop activate")

    def as_dict(self) -> dict:
        out = {"steps": self.steps, "deviations": self.deviations, "kinds": list(self.kinds)}
        if "delay" in self.kinds:
            out["max_delay"] = self.max_delay
        if "crash" in self.kinds:
            out["max_crashes"] = self.max_crashes
        return out

    def text(self) -> str:
        """``"20 steps, K=2 deviations, choices activate, loss"``."""
        extra = (f", delays up to {self.max_delay}" if "delay" in self.kinds else "") + \
                (f", up to {self.max_crashes} crash(es)" if "crash" in self.kinds else "")
        return f"{self.steps} steps, K={self.deviations} deviations, choices {', '.join(self.kinds)}{extra}"


def deviation_cost(kind: str, option, default) -> int:
    """How many deviations choosing ``option`` over ``default`` spends: an activation leaving
    ``j`` robots out costs ``j``; any other non-default option 1; the default 0.

    >>> deviation_cost("activate", (1, 3), (1, 2, 3)), deviation_cost("delay", 2, 0), deviation_cost("loss", False, False)
    (1, 1, 0)
    """
    if option == default:
        return 0
    if kind == "activate":
        return len(default) - len(option)
    return 1


def _jsonable_option(x):
    if isinstance(x, tuple):
        return [_jsonable_option(y) for y in x]
    if hasattr(x, "item"):
        return x.item()
    return x


@dataclass
class _Point:
    kind: str
    options: tuple
    idx: int
    cost: int
    at: tuple


class _Stats:
    """What one level of the search counted."""

    def __init__(self) -> None:
        self.runs = 0
        self.pruned = 0
        self.symmetric_pruned = 0
        self.table: dict = {}          # digest -> most budget left it was explored with
        self.sym_table: dict = {}

    def level(self, k: int, complete: bool) -> dict:
        """What the level of budget ``k`` searched (the JSON's ``levels``)."""
        return {"deviations": k, "runs": self.runs, "distinct_states": len(self.table), "pruned": self.pruned,
                "symmetric_pruned": self.symmetric_pruned, "complete": complete}


class SequenceSearch(Chooser):
    """The chooser of one run of the search: it follows ``prefix`` (option indices), then takes
    every default, and records each choice point (:attr:`trail`).

    With ``stats`` and ``prune``, after each step past the prefix it looks the run's state up in
    the level's tables and ends the run at a state explored before with at least as much budget
    left (``symmetric``: also up to relabelling anonymous robots).
    """

    def __init__(self, bound: Bound, prefix: Sequence[int], budget: int, stats: _Stats | None = None,
                 prune: bool = False, symmetric: bool = False) -> None:
        self.kinds = frozenset(bound.kinds)
        self.max_delay, self.max_crashes = bound.max_delay, bound.max_crashes
        self.prefix, self.budget = list(prefix), int(budget)
        self.stats, self.prune, self.symmetric = stats, prune, symmetric
        self.trail: list[_Point] = []
        self.used = 0

    def choose(self, kind, options, default, at=()):
        options = tuple(options)
        if not options or options[0] != default:
            raise AssertionError(f"choice point {kind} at {at}: the default must be the first option")
        i = len(self.trail)
        idx = self.prefix[i] if i < len(self.prefix) else 0
        if idx >= len(options):       # the run is not the one the prefix was made on: a bug here
            raise AssertionError(f"choice point {i} ({kind} at {at}) has {len(options)} options, prefix says {idx}")
        opt = options[idx]
        cost = deviation_cost(kind, opt, default)
        self.used += cost
        self.trail.append(_Point(kind, options, idx, cost, tuple(at)))
        return opt

    def after_step(self, t, digest) -> bool:
        stats = self.stats
        if stats is None or len(self.trail) < len(self.prefix):
            return False              # still on the prefix: these states were seen by an earlier run
        left = self.budget - self.used
        if self._seen(stats.table, digest(), left):
            stats.pruned += 1
            return True
        if self.symmetric and self._seen(stats.sym_table, digest(symmetric=True), left):
            stats.symmetric_pruned += 1
            return True
        return False

    def _seen(self, table: dict, key: bytes, left: int) -> bool:
        """Whether ``key`` was explored with at least ``left`` budget (then prune, when pruning);
        else note it with ``left``."""
        seen = table.get(key)
        if self.prune and seen is not None and seen >= left:
            return True
        if seen is None or left > seen:
            table[key] = left
        return False

    def describe(self) -> dict:
        from swarmproof.reference_impl.engine.choices import deterministic_from

        return {**super().describe(), "deterministic_from": deterministic_from(self.deviations())}

    def next_prefix(self) -> list[int] | None:
        """The next run's prefix in depth-first order within the budget, or None when the tree is done."""
        trail = self.trail
        used = [0] * (len(trail) + 1)
        for i, p in enumerate(trail):
            used[i + 1] = used[i] + p.cost
        for i in range(len(trail) - 1, -1, -1):
            p = trail[i]
            for j in range(p.idx + 1, len(p.options)):
                if used[i] + deviation_cost(p.kind, p.options[j], p.options[0]) <= self.budget:
                    return [q.idx for q in trail[:i]] + [j]
        return None

    def deviations(self) -> list[dict]:
        """The non-default choices made, as a counterexample records them."""
        return [{"index": i, "kind": p.kind, "at": [int(x) for x in p.at], "option": _jsonable_option(p.options[p.idx])}
                for i, p in enumerate(self.trail) if p.idx != 0]


@dataclass
class ExhaustiveVerdict:
    """One property's verdict over every start searched."""

    property: str
    status: str                      # held | violated | inconclusive | not_applicable
    message: str = ""
    runs: int = 0
    distinct_states: int = 0
    pruned: int = 0
    symmetric_pruned: int = 0
    complete: bool = False
    starts: int = 0
    levels: list = field(default_factory=list)
    deviations: int | None = None    # a counterexample's number of deviations
    counterexample: Any = None
    counterexample_path: str | None = None
    cpu: float = 0.0

    @property
    def violated(self) -> bool:
        return self.status == "violated"

    def add(self, out) -> None:
        """Count one start's search (a :class:`_StartOutcome`)."""
        self.starts += 1
        self.runs += out.runs
        self.distinct_states += out.distinct_states
        self.pruned += out.pruned
        self.symmetric_pruned += out.symmetric_pruned

    def as_dict(self, bound: Bound) -> dict:
        out = {"status": self.status, "message": self.message,
               "exhaustive": {"runs": self.runs, "distinct_states": self.distinct_states, "pruned": self.pruned,
                              "symmetric_pruned": self.symmetric_pruned, "complete": self.complete,
                              "bound": bound.as_dict(), "starts": self.starts, "levels": list(self.levels)}}
        if self.counterexample is not None:
            out["counterexample"] = self.counterexample.as_dict()
            out["deviations"] = self.deviations
        if self.counterexample_path is not None:
            out["counterexample_path"] = self.counterexample_path
        return out


@dataclass
class ExhaustiveReport:
    """What :func:`exhaustive` found, per property."""

    algorithm: str
    seed: int
    bound: Bound
    robots: int
    starts: list
    symmetric: bool
    properties: dict = field(default_factory=dict)
    broken_assumptions: list = field(default_factory=list)

    def claim(self, claims, prop: str):
        """Where the paper claims ``prop`` (``claims``: the algorithm's), None when it does not, or
        when the choices break one of its assumptions: it claims its properties under them, so a
        search outside them gives findings (asynchronous activation of a synchronous model)."""
        return None if self.broken_assumptions else claims.get(prop)

    @property
    def exit_code(self) -> int:
        """1 a property violated, 3 one inconclusive, else 0."""
        st = [v.status for v in self.properties.values()]
        if "violated" in st:
            return 1
        if "inconclusive" in st:
            return 3
        return 0

    def as_dict(self) -> dict:
        return {"algorithm": self.algorithm, "mode": "exhaustive", "seed": self.seed, "robots": self.robots,
                "bound": self.bound.as_dict(), "starts": list(self.starts), "symmetry": self.symmetric,
                "broken_assumptions": list(self.broken_assumptions),
                "properties": {p: v.as_dict(self.bound) for p, v in self.properties.items()},
                "exit_code": self.exit_code}


# ----------------------------------------------------------------------------------------------
# one start
# ----------------------------------------------------------------------------------------------

@dataclass
class _StartOutcome:
    status: str                      # held | violated | inconclusive
    message: str
    runs: int
    distinct_states: int
    pruned: int
    symmetric_pruned: int
    complete: bool
    levels: list
    chooser: SequenceSearch | None = None
    result: Any = None
    verdict: Any = None
    bound_reached: int = 0
    kinds_seen: frozenset = frozenset()


def symmetry_applies(model, symmetry: bool = True, faults=None) -> bool:
    """Whether states are taken up to relabelling the robots: asked for, anonymous robots without
    their own ID (the robot model says so), and nothing drawn in slot order (a fault model's loss,
    delays, noise or schedule draw from one generator, robot by robot)."""
    drawn = faults is not None and (faults.drops_messages or faults.late_messages or faults.noisy
                                    or faults.schedule is not None)
    return bool(symmetry and model.sensing == "anonymous" and not getattr(model, "own_id", False) and not drawn)


class _OutOfBudget(Exception):
    pass


def search_start(algorithm, target, initial, params, prop: str, bound: Bound, *, seed: int = 0,
                 options: Mapping[str, Any] | None = None, faults=None, prune: bool | None = None,
                 symmetry: bool = True, max_runs: int | None = None, deadline: float | None = None,
                 progress: Callable[[dict], None] | None = None, iterative: bool = True,
                 allow_violations: bool = True, factory=None,
                 unsound_liveness_pruning: bool = False) -> _StartOutcome:
    """Search every choice sequence within ``bound`` from one start for a violation of ``prop``.

    ``algorithm`` is a built algorithm object; ``prune`` defaults to True for safety properties and
    must not be True for liveness ones (a pruned run has no end: :class:`UsageError`).  ``iterative``
    deepens K from 0 (the first counterexample has the fewest deviations); without it one search
    with budget K.  ``max_runs`` / ``deadline`` (a ``time.monotonic()`` instant) end the search
    early: inconclusive with the coverage reached.  ``unsound_liveness_pruning`` prunes a liveness
    property too, leaving its pruned runs unjudged (they have no end): only to show what it hides
    (tests/checkers/test_exhaustive.py), never a verdict.
    """
    from swarmproof.checkers.explore import judge
    from swarmproof.invariants.registry import get_property
    from swarmproof.reference_impl.engine import simulate

    rule = get_property(prop)
    safety = rule.kind == "safety"
    if prune is None:
        prune = safety
    if prune and not safety and not unsound_liveness_pruning:
        raise UsageError(f"prune=True for the {rule.kind} property {prop!r}: a pruned run has no end to judge",
                         fix="prune only safety properties (the default)")
    symmetric = symmetry_applies(algorithm.model, symmetry, faults)
    monitor_of = rule.run_monitor if safety else None
    levels: list = []
    total_runs = 0
    bound_reached = 0
    undecided, first_undecided = 0, ""
    kinds_seen: set = set()
    ks = range(bound.deviations + 1) if iterative else (bound.deviations,)
    last = _Stats()

    def run_once(prefix, budget, stats, prune_now):
        ch = SequenceSearch(bound, prefix, budget, stats, prune_now, symmetric)
        monitor = None
        if monitor_of is not None:
            monitor = monitor_of(factory or type(algorithm), dict(options or {}))
            if monitor is not None and callable(getattr(monitor, "start", None)):
                monitor.start(initial.ids.tolist())
        result = simulate(algorithm, target, initial, params, seed=seed, max_steps=bound.steps, faults=faults,
                          allow_violations=allow_violations, stop_when=monitor, chooser=ch)
        return ch, result

    for k in ks:
        stats = _Stats()
        prefix: list[int] | None = []
        while prefix is not None:
            if (max_runs is not None and total_runs >= max_runs) or \
                    (deadline is not None and time.monotonic() > deadline):
                levels.append(stats.level(k, False))
                covered = f"K <= {k - 1} covered completely, " if k > 0 else ""
                why = "max_runs" if max_runs is not None and total_runs >= max_runs else "the time budget"
                return _StartOutcome("inconclusive",
                                     f"{why} spent before the bound was covered ({covered}K = {k}: "
                                     f"{stats.runs} runs, {len(stats.table)} states)", total_runs,
                                     len(stats.table), stats.pruned, stats.symmetric_pruned, False, levels)
            ch, result = run_once(prefix, k, stats, prune)
            stats.runs += 1
            total_runs += 1
            kinds_seen.update(p.kind for p in ch.trail)
            if result.status == "pruned" and not safety:     # (unsound_liveness_pruning) no end to judge
                prefix = ch.next_prefix()
                continue
            verdict = judge(prop, algorithm, target, params, result, options)
            if result.status == "stopped" and not verdict.violated:
                # the early-stop monitor ended a run it did not judge violated: run it to its end,
                # without recording its states (an earlier run of this prefix recorded them)
                ch, result = run_once(prefix, k, None, False)
                verdict = judge(prop, algorithm, target, params, result, options)
            if verdict.violated:
                levels.append(stats.level(k, False))
                return _StartOutcome("violated", verdict.message, total_runs, len(stats.table), stats.pruned,
                                     stats.symmetric_pruned, False, levels, ch, result, verdict)
            if result.status == "step_cap" and not safety:
                # a liveness property on a run cut by the step bound: undecided (oscillation, for
                # one, says held of a run with no cycle yet), never a pass
                bound_reached += 1
            elif verdict.status == "inconclusive" and result.status != "pruned":
                # a run the property could not judge (vacuous: nothing to check): not covered.  A
                # pruned run's prefix may be vacuous; its future was judged on the first visit
                undecided += 1
                first_undecided = first_undecided or verdict.message
            if progress is not None:
                progress({"deviations": k, "runs": total_runs, "states": len(stats.table), "depth": len(ch.trail)})
            prefix = ch.next_prefix()
        levels.append(stats.level(k, True))
        last = stats
    return _covered(prop, bound, bound_reached, undecided, first_undecided, total_runs, last, levels,
                    frozenset(kinds_seen))


def _covered(prop, bound, bound_reached, undecided, first_undecided, total_runs, last, levels, seen) -> _StartOutcome:
    """The outcome of a search that covered its whole bound: held, unless some runs could not be
    judged (a liveness property at the step bound, a vacuous verdict): inconclusive then."""
    stats = (total_runs, len(last.table), last.pruned, last.symmetric_pruned, True, levels)
    if bound_reached:
        return _StartOutcome("inconclusive", f"{bound_reached} of the runs reached the {bound.steps}-step bound before "
                             f"{prop} could be judged (bound reached: never held)", *stats,
                             bound_reached=bound_reached, kinds_seen=seen)
    if undecided:
        return _StartOutcome("inconclusive", f"{undecided} of the runs could not be judged ({first_undecided})", *stats,
                             kinds_seen=seen)
    return _StartOutcome("held", "", *stats, kinds_seen=seen)


# ----------------------------------------------------------------------------------------------
# the command's driver
# ----------------------------------------------------------------------------------------------

def _starts(spec, algorithm, target, params, phi, robots: int, seed: int, starts: int, initial):
    """``[(label, InitialConfiguration)]``: the given start, else ``starts`` seeded starts (seeds
    ``seed, seed + 1, ...``: the start ``swarmproof simulate --robots N --seed S`` runs)."""
    from swarmproof.checkers.runs import _seeded_start

    if initial is not None:
        return [("initial", initial)]
    return [(f"seed {s}", _seeded_start(algorithm, robots, s, params, target, phi, None))
            for s in range(seed, seed + starts)]


class _Violation(Exception):
    """A drawn start whose search found a violation (Hypothesis shrinks it)."""


class _Spent(BaseException):
    """The searches allowed while drawing and shrinking starts are spent."""


#: Exhaustive searches a drawn-starts check may run, shrinking included, per drawn start asked
#: for (a count: the result depends on the seed and the counts only).
SEARCHES_PER_DRAW = 20


def _check_drawn(spec, label, drawing, prop, bound, robots_range, draws: int, *, seed, options, symmetry, max_runs,
                 budget, out_dir, progress, broken) -> ExhaustiveVerdict:
    """Hypothesis-drawn starts (the explorer's strategy), each searched exhaustively; a violating
    start is shrunk by Hypothesis to the smallest that still violates within the bound."""
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as hseed

    from swarmproof.checkers.explore import scenario_strategy
    from swarmproof.models.hypothesis_seed import without_local_constants
    from swarmproof.models.trace import InitialConfiguration

    base, phi, team = drawing
    algo = spec.build(n_robots=robots_range[1])
    grid = None
    if getattr(algo.model, "motion", None) == "grid":
        grid = float((team(robots_range[1])[1].extra or {}).get("grid_spacing", 1.0))
    strategy = scenario_strategy(tuple(robots_range), [label], {label: phi}, grid_spacing=grid,
                                 targets={label: base}, scale_target=getattr(algo, "scale_target", None),
                                 free_starts=grid is not None and callable(getattr(algo, "initial", None)),
                                 algorithm=spec.factory)
    v = ExhaustiveVerdict(prop, "held", complete=True)
    t0 = time.process_time()
    last: dict = {}
    inconclusive: list = []
    seen_kinds: set = set()
    cap = SEARCHES_PER_DRAW * draws

    @hseed(seed)
    # report_multiple_bugs=False: with it, Hypothesis goes on generating for up to 10 s of wall clock
    # after the first failure, and the starts searched would depend on the machine's speed
    @settings(max_examples=draws, database=None, deadline=None, print_blob=False, report_multiple_bugs=False,
              suppress_health_check=list(HealthCheck), phases=[Phase.generate, Phase.shrink])
    @given(strategy)
    def probe(scn) -> None:
        if v.starts >= cap:
            raise _Spent
        init = InitialConfiguration(list(scn.ids), [list(p) for p in scn.poses])
        tgt, params = team(init.n)
        deadline = None if budget is None else time.monotonic() + float(budget)
        out = search_start(spec.build(n_robots=init.n), tgt, init, params, prop, bound, seed=seed, options=options,
                           symmetry=symmetry, max_runs=max_runs, deadline=deadline, factory=spec.factory,
                           progress=None if progress is None else (lambda d: progress(prop, d)))
        v.add(out)
        seen_kinds.update(out.kinds_seen)
        v.levels.append({"start": f"drawn {v.starts} ({init.n} robots)", "levels": out.levels})
        if out.status == "violated":
            last.update(init=init, tgt=tgt, params=params, out=out)   # the shrunk one comes last
            raise _Violation
        if out.status == "inconclusive":
            inconclusive.append(f"a drawn start of {init.n} robots: {out.message}")

    from swarmproof.checkers.explore import _count_bounded_shrinking

    try:
        with without_local_constants(), _count_bounded_shrinking():    # shrinking bounded by counts, not time
            probe()
    except _Violation:
        pass
    except _Spent:
        pass              # the smallest violating start found so far (if any) stands
    v.cpu = time.process_time() - t0
    if last:     # (the search cap can only stop the shrinking: a violating start is known then)
        out = last["out"]
        _mark_violated(v, spec, last["tgt"], label, last["params"], last["init"], seed, prop, out, bound, options,
                       broken, out_dir)
        v.message = (f"{out.message} (a drawn start of {last['init'].n} robots, shrunk; {v.deviations} "
                     f"deviation(s), the fewest from that start; {v.starts} starts searched)")
    elif inconclusive:
        v.status, v.complete = "inconclusive", False
        v.message = "; ".join(inconclusive[:3])
    else:
        v.message = (f"held for every choice sequence within the bound ({bound.text()}) from {v.starts} drawn "
                     f"start(s) of {robots_range[0]}..{robots_range[1]} robots, for the robots' draws of seed "
                     f"{seed}: {v.runs} runs, {v.distinct_states} distinct states" + _unseen_kinds(bound, seen_kinds))
    return v


def _mark_violated(v: ExhaustiveVerdict, spec, tgt, label, params, init, seed, prop, out, bound, options, broken,
                   out_dir) -> None:
    """``v`` violated by ``out``'s run from ``init``: its counterexample, saved into ``out_dir``."""
    v.status, v.complete, v.deviations = "violated", False, out.chooser.used
    v.counterexample = cx = _counterexample(spec, tgt, label, params, init, seed, prop, out, bound, options, broken)
    if out_dir is not None:
        from swarmproof.checkers.explore import _file_label

        os.makedirs(out_dir, exist_ok=True)
        path = os.path.join(os.fspath(out_dir), f"{_file_label(spec)}-{prop}-exhaustive-seed{seed}.json")
        v.counterexample_path = cx.save(path)


def _counterexample(spec, target, label, params, initial, seed: int, prop: str, outcome: _StartOutcome,
                    bound: Bound, options, broken) -> Any:
    from swarmproof.checkers.explore import _cx_lattice, _cx_target
    from swarmproof.checkers.runs import cx_params
    from swarmproof.models.counterexample import Counterexample

    ch = outcome.chooser
    w = outcome.verdict.witness or {}
    return Counterexample(
        algorithm=spec.ref, params=cx_params(params), lattice=_cx_lattice(label, target),
        robots=[(int(i), tuple(float(x) for x in p)) for i, p in zip(initial.ids.tolist(), initial.poses.tolist())],
        seed=int(seed), property=prop, violation={"step": w.get("step"), "message": outcome.message},
        faults=None, max_steps=bound.steps, allow_violations=True, broken_assumptions=list(broken),
        options=dict(options or {}), target=_cx_target(label, target), reading=spec.reading,
        clocks=outcome.result.trace.meta.get("clocks"),
        choices={**bound.as_dict(), "max_delay": bound.max_delay, "max_crashes": bound.max_crashes,
                 "deviations": ch.deviations(), "choice_points": len(ch.trail)})


def _inputs(algorithm, properties, target, robots, seed, initial, starts, bound, params, max_runs, budget,
            draw_robots=None):
    """The checked inputs of :func:`exhaustive`: the algorithm, its target (scaled to the team),
    the parameters, the properties and the starts."""
    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.checkers.explore import _load_targets, explore_properties
    from swarmproof.checkers.runs import _run_range, build_params
    from swarmproof.invariants.registry import get_property

    spec = resolve_algorithm(algorithm)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise UsageError(f"seed={seed!r} must be an integer >= 0")
    if initial is None and (isinstance(robots, bool) or not isinstance(robots, int) or robots < 1):
        raise UsageError(f"robots={robots!r} must be an integer >= 1", fix="e.g. --robots 3")
    if isinstance(starts, bool) or not isinstance(starts, int) or starts < 1:
        raise UsageError(f"starts={starts!r} (--starts) must be an integer >= 1", fix="e.g. --starts 3")
    if max_runs is not None and (isinstance(max_runs, bool) or not isinstance(max_runs, int) or max_runs < 1):
        raise UsageError(f"max_runs={max_runs!r} (--max-runs) must be an integer >= 1", fix="e.g. --max-runs 10000")
    if budget is not None and not (isinstance(budget, (int, float)) and budget > 0):
        raise UsageError(f"budget={budget!r} (--budget) must be a number of seconds > 0, or none",
                         fix="e.g. --budget 60, or --budget none to bound the search by its bound alone")
    n = initial.n if initial is not None else robots
    algo = spec.build(n_robots=n)
    (bound or Bound(steps=20, deviations=2)).check_applies(algo, max(n, (draw_robots or (n, n))[1]))
    if target is None:
        # the algorithm's own default targets (explore's), else its verify plan's, else square
        own = getattr(spec.factory, "explore_targets", None)
        plan = getattr(spec.factory, "verify_plan", None)
        targets = tuple(own or (getattr(plan, "targets", ()) if plan is not None else ()) or ())
        target = targets[0] if targets else "square"
    labels, loaded, _warnings = _load_targets([target], default_range=getattr(spec.factory, "default_range", None))
    label = labels[0]
    tgt = loaded[label]
    scale = getattr(algo, "scale_target", None)
    if callable(scale):
        tgt = scale(tgt, n)
    phi = _run_range(spec, tgt, getattr(tgt, "kind", "lattice"), None)
    p = dict(params or {})
    params_obj = build_params(algo, phi, n, v=p.get("v"), omega=p.get("omega"), dt=p.get("dt"), extra=p.get("extra"))
    props = list(properties) if properties else [q for q in explore_properties(spec.factory)
                                                 if get_property(q).not_applicable_to(algo) is None]
    for q in props:
        get_property(q)            # unknown names: a usage error before any run
    start_list = _starts(spec, algo, tgt, params_obj, phi, n, seed, starts, initial)
    base = loaded[label]

    def team(m: int):
        """The target and parameters of a team of ``m`` robots (a drawn start's size)."""
        a = spec.build(n_robots=m)
        t = scale(base, m) if callable(scale) else base
        return t, build_params(a, phi, m, v=p.get("v"), omega=p.get("omega"), dt=p.get("dt"), extra=p.get("extra"))

    return spec, algo, tgt, label, params_obj, props, start_list, (base, phi, team)


def _check_property(spec, tgt, label, params_obj, prop, bound, start_list, *, seed, options, symmetry, max_runs,
                    budget, out_dir, progress, broken) -> ExhaustiveVerdict:
    """One property searched from every start in turn, up to the first violation."""
    v = ExhaustiveVerdict(prop, "held", complete=True)
    t0 = time.process_time()
    inconclusive = []
    seen_kinds: set = set()
    for start_label, init in start_list:
        deadline = None if budget is None else time.monotonic() + float(budget)
        out = search_start(spec.build(n_robots=init.n), tgt, init, params_obj, prop, bound, seed=seed,
                           options=options, symmetry=symmetry, max_runs=max_runs, deadline=deadline,
                           factory=spec.factory,
                           progress=None if progress is None else (lambda d, prop=prop: progress(prop, d)))
        v.add(out)
        v.complete = v.complete and out.complete
        seen_kinds |= set(out.kinds_seen)
        v.levels.append({"start": start_label, "levels": out.levels})
        if out.status == "violated":
            _mark_violated(v, spec, tgt, label, params_obj, init, seed, prop, out, bound, options, broken, out_dir)
            v.message = (f"{out.message} (start {start_label}, {v.deviations} deviation(s), the fewest from that "
                         f"start; found after {v.runs} runs)")
            break
        if out.status == "inconclusive":
            inconclusive.append(f"start {start_label}: {out.message}")
    v.cpu = time.process_time() - t0
    if v.status != "violated":
        if inconclusive:
            v.status = "inconclusive"
            v.message = "; ".join(inconclusive)
        else:
            v.message = (f"held for every choice sequence within the bound ({bound.text()}) from "
                         f"{v.starts} start(s), for the robots' draws of seed {seed}: {v.runs} runs, "
                         f"{v.distinct_states} distinct states" + _unseen_kinds(bound, seen_kinds))
    return v


def _unseen_kinds(bound: Bound, seen: set) -> str:
    """``"; no decision of kind loss arose"`` for the bound's kinds no run was asked to decide."""
    never = [k for k in bound.kinds if k not in seen]
    if not never:
        return ""
    if len(never) == len(bound.kinds):
        return "; no decision of the kinds asked arose: this was the one run the defaults make"
    return f"; no decision of kind {', '.join(never)} arose"


def exhaustive(algorithm, properties: Sequence[str] | None = None, *, target=None, robots: int = 3, seed: int = 0,
               initial=None, starts: int = 1, bound: Bound | None = None, params: Mapping[str, Any] | None = None,
               options: Mapping[str, Any] | None = None, max_runs: int | None = None, budget: float | None = None,
               symmetry: bool = True, out_dir: str | os.PathLike | None = None,
               progress: Callable[[str, dict], None] | None = None, draw_starts: int | None = None,
               draw_robots: tuple[int, int] | None = None) -> ExhaustiveReport:
    """Check ``properties`` of ``algorithm`` for every choice sequence within ``bound`` from each start.

    Parameters
    ----------
    algorithm : str, class or callable
        As :func:`swarmproof.checkers.explore.explore` takes it.
    properties : sequence of str, optional
        Default: the algorithm's explored properties that apply to it.
    target : str or target, optional
        A bundled lattice, ``KIND:NAME`` or a file; default the algorithm's first explore target
        (``explore_targets``), else its verify plan's first, else ``square``.
    robots, seed, starts : int
        Without ``initial``: ``starts`` seeded starts of ``robots`` robots from seeds ``seed, seed +
        1, ...``.  ``seed`` is also the engine's seed: the robots' own draws are those of that seed
        (the verdict says so).
    initial : InitialConfiguration, optional
        The one start to search from (``--initial FILE``).
    bound : Bound
        Steps, K, choice kinds (default 20 steps, K = 2, activation).
    max_runs, budget : optional
        Runs / wall seconds per start and property; spent before the bound is covered: inconclusive.
    symmetry : bool
        Symmetry reduction where the robot model is anonymous.
    out_dir : path, optional
        Where counterexample files are written.
    progress : callable ``(property, {"deviations", "runs", "states", "depth"})``, optional
    draw_starts : int, optional
        Instead of seeded starts: Hypothesis draws this many connected starts (the explorer's
        scenario strategy, seeded with ``seed``; ``draw_robots`` (MIN, MAX) robots, default
        ``robots``), each searched exhaustively; a start with a violation is shrunk (fewer
        robots, links nearer the range) to the smallest start Hypothesis finds that still
        violates within the bound.
    """
    spec, algo, tgt, label, params_obj, props, start_list, drawing = _inputs(
        algorithm, properties, target, robots, seed, initial, starts, bound, params, max_runs, budget,
        draw_robots if draw_starts else None)
    bound = bound if bound is not None else Bound(steps=20, deviations=2)
    from swarmproof.invariants.registry import get_property
    from swarmproof.reference_impl.engine.choices import Choices
    from swarmproof.reference_impl.engine.faults import FaultModel

    broken = Choices(FaultModel(), None, SequenceSearch(bound, [], bound.deviations)).broken_assumptions(algo.model)
    model = algo.model
    symmetric = symmetry_applies(model, symmetry)
    starts_text = ([f"{draw_starts} drawn"] if draw_starts else [s for s, _ in start_list])
    report = ExhaustiveReport(spec.label, seed, bound, start_list[0][1].n, starts_text, symmetric,
                              broken_assumptions=broken)
    for prop in props:
        why = get_property(prop).not_applicable_to(algo, tgt)
        if why is not None:
            report.properties[prop] = ExhaustiveVerdict(prop, "not_applicable", f"not applicable: {why}")
            continue
        kw = dict(seed=seed, options=options, symmetry=symmetry, max_runs=max_runs, budget=budget, out_dir=out_dir,
                  progress=progress, broken=broken)
        if draw_starts:
            report.properties[prop] = _check_drawn(spec, label, drawing, prop, bound, draw_robots or (robots, robots),
                                                   draw_starts, **kw)
        else:
            report.properties[prop] = _check_property(spec, tgt, label, params_obj, prop, bound, start_list, **kw)
    return report
