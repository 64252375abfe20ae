"""Campaigns on Dask: a matrix of explorations and experiments, resumable, with nothing lost.

A campaign (:mod:`swarmproof.models.campaign_spec`) is split into *tasks*,
each fully determined by the spec (an explorer task: one algorithm, one
property, one Hypothesis seed, ``max_examples`` and no wall clock; an
experiment task: one seeded run of one algorithm on one target with one team
size; a paper-experiment task: one seeded trial ``fn(n, seed, **options)`` of an experiment the
algorithm declares), so the results are the same on 1, 2 or 100 workers.  Tasks run on
``dask.distributed``: an embedded ``LocalCluster`` (processes, one per core)
by default, or an existing cluster by its scheduler address.  The client
alone writes the results store ``DIR/results.sqlite`` (SQLite, one row per
finished task, one transaction each) and the counterexample files
(``DIR/counterexamples/``, written atomically, named by a hash of their
content, so two tasks that shrink to the same scenario share one file).  A
killed client loses only unfinished tasks (``--resume`` skips the finished
ones); a killed worker's tasks are retried by Dask.

Store tables: ``meta(key, value)`` (format, spec, digest), ``results(task,
cell, kind, verdict, figures, counterexample)`` -- the same content whatever
the cluster -- and ``timings(task, seconds, worker)`` (machine-dependent,
kept apart for benchmarks).

References
----------
DESIGN.md section 1 "Past one machine"; docs/campaigns.md.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import sqlite3
import time
from dataclasses import dataclass
from typing import Any, Callable

from swarmproof.models.errors import UsageError
from swarmproof.models.verdict import Verdict

__all__ = ["Task", "plan_tasks", "run_task", "ResultsStore", "run_campaign", "CampaignResult", "STORE_FORMAT",
           "MEASURED", "resolve_experiment", "experiment_options"]

STORE_FORMAT = "swarmproof-campaign-results/1"

#: The verdict of a paper-experiment task that ran: it measured figures and judged nothing (no claim,
#: so never "held"); counted apart, like n/a, but it is what the task was asked to do
#: (docs/decisions.md, "Campaigns: experiment cells").
MEASURED = "measured"

#: How long ``--scheduler ADDRESS`` is tried before it is reported as unreachable (seconds): Dask's
#: client retries a refused connection until then.
SCHEDULER_CONNECT_TIMEOUT = 10.0


@dataclass(frozen=True)
class Task:
    """One unit of work: ``key`` is unique in the campaign and stable across runs."""

    key: str
    cell: str
    kind: str            # "explore" | "simulate" | "experiment" | "exhaustive"
    args: dict

    def as_dict(self) -> dict:
        return {"key": self.key, "cell": self.cell, "kind": self.kind, "args": dict(self.args)}


def resolve_experiment(algorithm: str, name: str) -> tuple:
    """``(ref, function, declaration)`` of experiment ``name`` of ``algorithm`` (a registry name or
    module:qualname): ``ref`` is the ``module:qualname`` the algorithm's class attribute
    ``experiments`` gives, ``declaration`` the function's :class:`~swarmproof.reference_impl.protocol.Experiment`
    (an undeclared function: no options, no bounds of its own).

    Only the class (or factory) that declares ``experiments`` in its own body has them: a
    subclass runs other code, so it inherits none (an experiment function runs the reading its
    author wrote it for).

    Raises
    ------
    UsageError
        An unknown algorithm; an experiment the algorithm does not declare (listing those it
        does); a reference that cannot be imported.
    """
    import importlib

    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.models.errors import did_you_mean
    from swarmproof.reference_impl.protocol import Experiment

    spec = resolve_algorithm(algorithm)
    factory = spec.factory
    own = getattr(factory, "__dict__", {}).get("experiments") or {}
    if name not in own:
        inherited = getattr(factory, "experiments", None) or {}
        if own:
            fix = f"use one of {sorted(own)!r}"
        elif inherited:
            fix = ("its base class declares " + repr(sorted(inherited)) + ", which run the base class's reading, "
                   "not this one (an experiment function builds the algorithm it was written for): use the base class")
        else:
            fix = ("use an algorithm that declares experiments (its class attribute experiments): "
                   "`swarmproof list algorithms` names them")
        raise UsageError(f"experiment={name!r} is not an experiment of algorithm {algorithm!r}"
                         f"{did_you_mean(name, own) if own else ''} (it declares {sorted(own) or 'none'})", fix=fix)
    ref = own[name]
    modname, _, qual = str(ref).partition(":")
    try:
        fn = importlib.import_module(modname)
        for part in qual.split("."):
            fn = getattr(fn, part)
    except Exception as exc:  # noqa: BLE001 - ImportError, AttributeError, or the module's own error
        raise UsageError(f"experiment {name!r} of algorithm {algorithm!r} names {ref!r}, which cannot be imported "
                         f"({type(exc).__name__}: {exc})", fix="fix the algorithm's experiments entry "
                         "(module:qualname of a module-level function)") from None
    if not callable(fn):
        raise UsageError(f"experiment {name!r} of algorithm {algorithm!r} names {ref!r}, which is not a function",
                         fix="point the algorithm's experiments entry at a function (n, seed, **options)")
    decl = getattr(fn, "experiment", None)
    return ref, fn, decl if isinstance(decl, Experiment) else Experiment()


def experiment_options(decl, given: dict) -> tuple[dict, str | None, str | None]:
    """The options of one trial: ``given`` checked against the experiment's declared options and
    completed with their defaults.  Returns ``(options, bad key, error)``: the key and message
    (``name=value`` and what is wrong) of the first problem, or None.  The fix is in the message's
    caller (:func:`_check_run_inputs`)."""
    from swarmproof.models.errors import did_you_mean

    declared = {s.name: s for s in decl.options}
    for k, v in given.items():
        s = declared.get(k)
        if s is None:
            return {}, k, (f"option {k}={v!r} is not an option of this experiment{did_you_mean(k, declared)}; "
                           f"its options: {sorted(declared) or 'none'}")
        why = s.problem(v)
        if why is not None:
            return {}, k, f"option {why}"
    # a whole-number option given as 32.0 is the whole number 32 (ParamSpec accepts it as one)
    given = {k: (int(v) if declared[k].type is int else v) for k, v in given.items()}
    return {**{s.name: s.default for s in decl.options}, **given}, None, None


def _check_names(spec) -> None:
    """Every algorithm, property and target the spec names exists (errors located in the file)."""
    from swarmproof.checkers.explore import FAULT_KINDS, explore_properties, resolve_algorithm
    from swarmproof.models.targets import resolve_target

    for cell in spec.explore:
        try:
            algo = resolve_algorithm(cell.algorithm)
        except UsageError as exc:
            raise spec.error(cell.path + ("algorithm",), exc.message, exc.fix or "use a registry name") from None
        props = set(explore_properties(algo.factory))     # with the algorithm's own properties
        for k, p in enumerate(cell.properties or ()):
            if p not in props and ":" not in p:
                raise spec.error(cell.path + ("properties", k), f"property={p!r} is not registered",
                                 f"use one of {sorted(props)!r}")
        for k, f in enumerate(cell.draw_faults):
            if f not in FAULT_KINDS:
                raise spec.error(cell.path + ("draw_faults", k), f"draw_faults={f!r} is not a fault kind",
                                 f"use one of {list(FAULT_KINDS)!r}")
        for k, name in enumerate(cell.lattices or ()):
            try:
                resolve_target(name, prefer="lattice")
            except UsageError as exc:
                raise spec.error(cell.path + ("lattices", k), f"lattices={name!r}: {exc.message}",
                                 exc.fix or "use a bundled name") from None
    for cell in spec.simulate:
        try:
            resolve_algorithm(cell.algorithm)
        except UsageError as exc:
            raise spec.error(cell.path + ("algorithm",), exc.message, exc.fix or "use a registry name") from None
        for k, name in enumerate(cell.targets):
            try:
                resolve_target(name, prefer="lattice")
            except UsageError as exc:
                raise spec.error(cell.path + ("targets", k), f"targets={name!r}: {exc.message}",
                                 exc.fix or "use a bundled name") from None
    for cell in getattr(spec, "experiment", ()):
        try:
            resolve_algorithm(cell.algorithm)
        except UsageError as exc:
            raise spec.error(cell.path + ("algorithm",), exc.message, exc.fix or "use a registry name") from None
        try:
            resolve_experiment(cell.algorithm, cell.experiment)
        except UsageError as exc:
            raise spec.error(cell.path + ("experiment",), exc.message, exc.fix or "see docs/campaigns.md") from None


def _check_exhaustive_cells(spec) -> None:
    """An exhaustive cell's algorithm, properties, choice kinds and bound, and target, each error at
    its field."""
    from swarmproof.checkers.exhaustive import Bound
    from swarmproof.checkers.explore import explore_properties, resolve_algorithm
    from swarmproof.models.targets import resolve_target

    for cell in getattr(spec, "exhaustive", ()):
        try:
            algo = resolve_algorithm(cell.algorithm)
        except UsageError as exc:
            raise spec.error(cell.path + ("algorithm",), exc.message, exc.fix or "use a registry name") from None
        props = set(explore_properties(algo.factory))
        for k, p in enumerate(cell.properties or ()):
            if p not in props and ":" not in p:
                raise spec.error(cell.path + ("properties", k), f"property={p!r} is not registered",
                                 f"use one of {sorted(props)!r}")
        try:
            bound = Bound(steps=cell.steps, deviations=cell.deviations, kinds=tuple(cell.choices),
                          max_delay=cell.max_delay, max_crashes=cell.max_crashes)
        except UsageError as exc:
            raise spec.error(cell.path + ("choices",), exc.message, exc.fix or "see docs/exhaustive.md") from None
        for k, n in enumerate(cell.robots):
            try:
                bound.check_applies(algo.build(n_robots=n), n)
            except UsageError as exc:
                where = ("robots", k) if "robots=" in exc.message else ("choices",)
                raise spec.error(cell.path + where, exc.message, exc.fix or "see docs/exhaustive.md") from None
        if cell.target is not None:
            try:
                resolve_target(cell.target, prefer="lattice")
            except UsageError as exc:
                raise spec.error(cell.path + ("target",), f"target={cell.target!r}: {exc.message}",
                                 exc.fix or "use a bundled name") from None


def _check_run_inputs(spec) -> None:
    """What every task will run, checked before any task starts, with the same checks and messages as
    ``explore`` and ``simulate`` (issue 29), each error located at its field: team sizes the explorer
    can draw and the algorithm runs, targets of a kind the algorithm forms, ``params`` and ``speeds``
    (declared parameters in their ranges, motion that moves a robot); an experiment cell's
    ``options`` (declared, in range) and ``robots`` (the experiment's sizes and its own check)."""
    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.checkers.explore import _load_targets, check_explore_robots, check_run_params
    from swarmproof.checkers.runs import check_robots
    from swarmproof.models.targets import resolve_target
    from swarmproof.reference_impl.engine.parameters import check_target_kind
    from swarmproof.reference_impl.engine.run import check_team_size

    def located(path, check, *args):
        try:
            return check(*args)
        except UsageError as exc:
            raise spec.error(path, exc.message, exc.fix or "see docs/campaigns.md") from None

    for cell in spec.explore:
        factory = resolve_algorithm(cell.algorithm).factory
        located(cell.path + ("robots",), check_explore_robots, cell.robots, factory)
        algo = located(cell.path + ("algorithm",), resolve_algorithm(cell.algorithm).build, cell.robots[1])
        lats = cell.lattices if cell.lattices is not None else getattr(factory, "explore_targets", None)
        _, loaded, _ = located(cell.path + ("lattices",), _load_targets, lats, False,
                               getattr(factory, "default_range", None))
        for k, target in enumerate(loaded.values()):
            located(cell.path + (("lattices", k) if cell.lattices is not None else ("algorithm",)),
                    check_target_kind, algo, target)
        located(cell.path + ("speeds" if cell.speeds else "params",), check_run_params, algo, loaded,
                dict(cell.params), cell.robots[1], cell.speeds)
    for cell in spec.simulate:
        factory = resolve_algorithm(cell.algorithm).factory
        for k, n in enumerate(cell.robots):
            located(cell.path + ("robots", k), check_robots, n, None)
            algo = located(cell.path + ("algorithm",), resolve_algorithm(cell.algorithm).build, n)
            located(cell.path + ("robots", k), check_team_size, algo, n)
        for k, name in enumerate(cell.targets):
            located(cell.path + ("targets", k), check_target_kind, factory, resolve_target(name, prefer="lattice"))
    for cell in getattr(spec, "experiment", ()):
        _, _, decl = resolve_experiment(cell.algorithm, cell.experiment)
        options, key, why = experiment_options(decl, cell.options)
        if why is not None:
            declared = {s.name: s for s in decl.options}
            fix = (f"give {key} a value in {declared[key].range_text()}" if key in declared
                   else f"use only {sorted(declared)!r}" if declared else "drop options: (this experiment takes none)")
            raise spec.error(cell.path + ("options", key), f"{_label(cell)}: {why}", fix)
        lo, hi = decl.robots
        for k, n in enumerate(cell.robots):
            if n < lo or (hi is not None and n > hi):
                raise spec.error(cell.path + ("robots", k),
                                 f"{_label(cell)}: robots={n} is outside the team sizes it takes, {lo}..{hi or 'any'}",
                                 f"give team sizes in {lo}..{hi or 'any'}")
            if decl.check is not None:
                located(cell.path + ("robots", k), lambda: decl.check(n, **options))


def _label(cell) -> str:
    return f"experiment {cell.experiment!r} of {cell.algorithm!r}"


def plan_tasks(spec) -> list[Task]:
    """Every task of ``spec``, in a fixed order (cells as written, then properties / targets,
    sizes and seeds).  Names are checked first (located errors)."""
    from swarmproof.checkers.explore import explore_properties, resolve_algorithm

    _check_names(spec)
    _check_exhaustive_cells(spec)
    _check_run_inputs(spec)
    tasks: list[Task] = []
    for cell in spec.explore:
        for prop in (cell.properties or explore_properties(resolve_algorithm(cell.algorithm).factory)):
            for seed in cell.seeds:
                args = {"algorithm": cell.algorithm, "property": prop, "seed": seed, "robots": list(cell.robots),
                        "max_examples": cell.max_examples, "lattices": None if cell.lattices is None else list(cell.lattices),
                        "draw_faults": list(cell.draw_faults), "speeds": None if cell.speeds is None else list(cell.speeds),
                        "max_steps": cell.max_steps, "params": dict(cell.params),
                        "allow_violations": cell.allow_violations}
                tasks.append(Task(f"explore[{cell.index}]/{prop}/seed{seed}", cell.label, "explore", args))
    for cell in spec.simulate:
        for target in cell.targets:
            for n in cell.robots:
                for seed in cell.seeds:
                    args = {"algorithm": cell.algorithm, "target": target, "robots": n, "seed": seed,
                            "max_steps": cell.max_steps}
                    if cell.start is not None:      # only when given: older stores' task args stay as they were
                        args["start"] = dict(cell.start)
                    tasks.append(Task(f"simulate[{cell.index}]/{target}/n{n}/seed{seed}", cell.label, "simulate", args))
    for cell in getattr(spec, "experiment", ()):
        ref, _, decl = resolve_experiment(cell.algorithm, cell.experiment)
        options, _, _ = experiment_options(decl, cell.options)
        for n in cell.robots:
            for seed in cell.seeds:
                args = {"algorithm": cell.algorithm, "experiment": cell.experiment, "function": ref, "robots": n,
                        "seed": seed, "options": dict(options)}
                tasks.append(Task(f"experiment[{cell.index}]/{cell.experiment}/n{n}/seed{seed}", cell.label,
                                  "experiment", args))
    for cell in getattr(spec, "exhaustive", ()):
        for prop in (cell.properties or explore_properties(resolve_algorithm(cell.algorithm).factory)):
            for n in cell.robots:
                for seed in cell.seeds:
                    args = {"algorithm": cell.algorithm, "property": prop, "robots": n, "seed": seed,
                            "choices": list(cell.choices), "steps": cell.steps, "deviations": cell.deviations,
                            "max_delay": cell.max_delay, "max_crashes": cell.max_crashes, "target": cell.target}
                    tasks.append(Task(f"exhaustive[{cell.index}]/{prop}/n{n}/seed{seed}", cell.label, "exhaustive",
                                      args))
    return tasks


# ---------------------------------------------------------------------------
# the task function (runs on a worker; everything it needs is in its argument)
# ---------------------------------------------------------------------------

def _explore_task(a: dict) -> dict:
    from swarmproof.checkers.explore import explore

    rep = explore(a["algorithm"], [a["property"]], budget=None, max_examples=a["max_examples"],
                  robots=tuple(a["robots"]), seed=a["seed"], lattices=a["lattices"],
                  draw_faults=tuple(a["draw_faults"]), speeds=a["speeds"], max_steps=a["max_steps"],
                  params=a["params"] or None, allow_violations=a["allow_violations"])
    v = rep.properties[a["property"]]
    cx = v.counterexample
    figures = {"scenarios": v.scenarios, "conclusive": v.conclusive, "steps": v.steps, "capped": v.capped,
               "message": v.message, "claim": rep.claims.get(a["property"]),
               "first_failure_scenarios": v.first_failure_scenarios,
               "counterexample_robots": None if cx is None else len(cx.robots),
               "violation": None if cx is None else dict(cx.violation)}
    return {"verdict": v.status, "figures": figures,
            "counterexample": None if cx is None else cx.as_dict(),
            "first_failure_seconds": v.first_failure_seconds}


def _simulate_task(a: dict) -> dict:
    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.checkers.runs import RUN_PROPERTIES, run_and_check, run_counterexample, run_property_verdicts
    from swarmproof.models.targets import resolve_target

    spec = resolve_algorithm(a["algorithm"])
    initial = None
    if a.get("start"):
        from swarmproof.reference_impl.initial import random_uniform

        initial = random_uniform(a["robots"], a["seed"], side=a["start"]["uniform"],
                                 min_separation=a["start"].get("separation", 0.0))
    checked = run_and_check(a["algorithm"], resolve_target(a["target"], prefer="lattice"), seed=a["seed"],
                            robots=None if initial is not None else a["robots"], initial=initial,
                            max_steps=a["max_steps"])
    doc = checked.doc
    verdicts = run_property_verdicts(checked)
    claimed = [p for p in RUN_PROPERTIES if spec.claims.get(p)]
    verdict = Verdict.combine(verdicts[p][0] for p in (claimed or ["termination"]))
    cx = None
    for p in claimed:
        if verdicts[p][0] is Verdict.VIOLATED:
            cx = run_counterexample(checked, p, verdicts[p][1], ref=spec.ref).as_dict()
            break
    figures = {k: doc.get(k) for k in ("status", "steps", "execution_steps", "satisfied", "fulfillment_ratio",
                                        "connected_throughout", "total_distance", "min_separation")}
    if doc.get("target", {}).get("kind") != "lattice":
        # another kind's figures (e.g. a repeating pattern's epsilon, 002 Def. 9); numbers and texts only
        figures["metrics"] = {k: v for k, v in (doc.get("metrics") or {}).items()
                              if isinstance(v, (int, float, str)) or v is None}
    figures["properties"] = {p: {"verdict": v.value, "message": m, "claim": spec.claims.get(p)}
                             for p, (v, m) in verdicts.items()}
    return {"verdict": verdict.value, "figures": figures, "counterexample": cx, "first_failure_seconds": None}


def check_figures(figures) -> dict:
    """An experiment's figures as the store keeps them: a dict of names to numbers, texts,
    true/false or None (finite numbers only); TypeError/ValueError naming the first that is not."""
    import math

    if not isinstance(figures, dict):
        raise TypeError(f"the experiment returned {type(figures).__name__}, not a dict of figures")
    out = {}
    for k, v in figures.items():
        if not isinstance(k, str):
            raise TypeError(f"figure name {k!r} is not a text")
        if hasattr(v, "item") and not isinstance(v, (str, bytes)):     # numpy scalars
            v = v.item()
        if not (v is None or isinstance(v, (bool, int, float, str))):
            raise TypeError(f"figure {k}={v!r} is not a number, a text, true/false or None")
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"figure {k}={v!r} is not finite")
        out[k] = v
    return out


def _experiment_task(a: dict) -> dict:
    """One trial of a paper experiment: ``fn(n, seed, **options)``, its figures, verdict
    :data:`MEASURED` (no claim is judged)."""
    _, fn, _ = resolve_experiment(a["algorithm"], a["experiment"])
    figures = check_figures(fn(a["robots"], a["seed"], **a["options"]))
    return {"verdict": MEASURED, "figures": figures, "counterexample": None, "first_failure_seconds": None}


def _exhaustive_task(a: dict) -> dict:
    """Every choice sequence within the bound from one seeded start, for one property (a start is a
    task of its own: the starts of a cell are independent)."""
    from swarmproof.checkers.exhaustive import Bound, exhaustive

    bound = Bound(steps=a["steps"], deviations=a["deviations"], kinds=tuple(a["choices"]), max_delay=a["max_delay"],
                  max_crashes=a["max_crashes"])
    rep = exhaustive(a["algorithm"], [a["property"]], target=a["target"], robots=a["robots"], seed=a["seed"],
                     bound=bound)
    v = rep.properties[a["property"]]
    cx = v.counterexample
    from swarmproof.checkers.algorithm_spec import resolve_algorithm

    claim = rep.claim(resolve_algorithm(a["algorithm"]).claims, a["property"])
    figures = {"runs": v.runs, "distinct_states": v.distinct_states, "pruned": v.pruned,
               "symmetric_pruned": v.symmetric_pruned, "complete": v.complete, "deviations": v.deviations,
               "message": v.message, "claim": claim, "broken_assumptions": ", ".join(rep.broken_assumptions),
               "counterexample_robots": None if cx is None else len(cx.robots),
               "violation": None if cx is None else dict(cx.violation)}
    status = "n/a" if v.status == "not_applicable" else v.status
    return {"verdict": status, "figures": figures, "counterexample": None if cx is None else cx.as_dict(),
            "first_failure_seconds": None}


_TASKS = {"explore": "_explore_task", "simulate": "_simulate_task", "experiment": "_experiment_task",
          "exhaustive": "_exhaustive_task"}


@contextlib.contextmanager
def worker_warnings():
    """Inside a task on a Dask worker: silence Hypothesis's warning about the `random` module.

    A Dask worker's own threads (heartbeats, comms) use the `random` module; Hypothesis notices the
    global random state moving while a strategy draws and warns that the *strategy* used it.
    Hypothesis's draws come from its own seeded generator, so the results do not depend on it
    (tests/checkers/test_campaign.py compares 1 and 2 workers and a real cluster; test_verify.py
    verify's rows): silence that one warning inside tasks only."""
    import warnings

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Do not use the `random` module inside strategies")
        yield


def run_task(task: dict) -> dict:
    """Run one task (on a worker).  A crash of swarmproof itself becomes an inconclusive result
    naming the error (the campaign goes on; the report lists it), never a lost task."""
    t0 = time.perf_counter()
    try:
        with worker_warnings():
            out = globals()[_TASKS[task["kind"]]](task["args"])
    except Exception as exc:  # noqa: BLE001 - one task's failure must not stop the campaign
        out = {"verdict": "inconclusive", "counterexample": None, "first_failure_seconds": None,
               "figures": {"error": f"{type(exc).__name__}: {exc}"[:500]}}
    out["seconds"] = time.perf_counter() - t0
    out["worker"] = f"{os.uname().nodename}:{os.getpid()}"
    return out


# ---------------------------------------------------------------------------
# the results store (client only)
# ---------------------------------------------------------------------------

def _cx_name(cx: dict) -> str:
    body = {k: v for k, v in cx.items() if k != "made_by"}
    digest = hashlib.sha256(json.dumps(body, sort_keys=True).encode("utf-8")).hexdigest()[:16]
    from swarmproof.checkers.explore import _safe

    return f"{_safe(cx['algorithm'] + '-' + cx['property'])}-{digest}.json"


def _no_space(exc: sqlite3.Error) -> bool:
    """Whether SQLite failed for want of disk space (SQLITE_FULL), not for a bad file."""
    return getattr(exc, "sqlite_errorcode", None) == sqlite3.SQLITE_FULL or "disk is full" in str(exc)


class ResultsStore:
    """``DIR/results.sqlite`` and ``DIR/counterexamples/``; written by the campaign's client only."""

    def __init__(self, out_dir: str, spec, *, resume: bool) -> None:
        from swarmproof.models.fileio import check_output_dir

        check_output_dir(out_dir, "--out")
        os.makedirs(out_dir, exist_ok=True)
        self.dir = out_dir
        self.path = os.path.join(out_dir, "results.sqlite")
        existed = os.path.exists(self.path)
        try:
            self.con = sqlite3.connect(self.path)
            self.con.execute("PRAGMA journal_mode=WAL")
            with self.con:
                self.con.execute("CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL)")
                self.con.execute("CREATE TABLE IF NOT EXISTS results(task TEXT PRIMARY KEY, cell TEXT NOT NULL, "
                                 "kind TEXT NOT NULL, verdict TEXT NOT NULL, figures TEXT NOT NULL, "
                                 "counterexample TEXT)")
                self.con.execute("CREATE TABLE IF NOT EXISTS timings(task TEXT PRIMARY KEY, seconds REAL, worker TEXT)")
        except sqlite3.DatabaseError as exc:
            if _no_space(exc):
                raise UsageError(f"--out {out_dir!r}: {self.path} cannot be written ({exc})",
                                 fix="free disk space, or give --out a folder on another disk") from None
            raise UsageError(f"--out {out_dir!r}: {self.path} is not a readable results store ({exc})",
                             fix="give another --out folder, or delete the file") from None
        meta = dict(self.con.execute("SELECT key, value FROM meta"))
        done = self.con.execute("SELECT COUNT(*) FROM results").fetchone()[0]
        if meta and meta.get("format") != STORE_FORMAT:
            raise UsageError(f"--out {out_dir!r} holds a results store of format {meta.get('format')!r}",
                             fix="give another --out folder")
        if meta and meta.get("digest") != spec.digest:
            raise UsageError(f"--out {out_dir!r} holds the results of another campaign "
                             f"(name={json.loads(meta.get('spec', '{}')).get('name')!r}, a different spec)",
                             fix="give another --out folder, or the spec that made it")
        if existed and done and not resume:
            raise UsageError(f"--out {out_dir!r} already holds {done} finished task(s) of this campaign",
                             fix="add --resume to run only the unfinished ones, or give another --out folder")
        with self.con:
            for k, v in (("format", STORE_FORMAT), ("digest", spec.digest),
                         ("spec", json.dumps(spec.document, sort_keys=True))):
                self.con.execute("INSERT OR REPLACE INTO meta VALUES (?, ?)", (k, v))

    def finished(self) -> set[str]:
        return {row[0] for row in self.con.execute("SELECT task FROM results")}

    def write(self, task: Task, out: dict) -> None:
        """Record one finished task (its counterexample file first, then the row, in one transaction)."""
        from swarmproof.models.fileio import atomic_write_json

        cx_path = None
        if out.get("counterexample") is not None:
            folder = os.path.join(self.dir, "counterexamples")
            os.makedirs(folder, exist_ok=True)
            cx_path = os.path.join("counterexamples", _cx_name(out["counterexample"]))
            full = os.path.join(self.dir, cx_path)
            if not os.path.exists(full):
                atomic_write_json(full, out["counterexample"])
        figures = json.dumps(out.get("figures") or {}, sort_keys=True)
        try:
            with self.con:
                self.con.execute("INSERT OR REPLACE INTO results VALUES (?, ?, ?, ?, ?, ?)",
                                 (task.key, task.cell, task.kind, out["verdict"], figures, cx_path))
                self.con.execute("INSERT OR REPLACE INTO timings VALUES (?, ?, ?)",
                                 (task.key, float(out.get("seconds") or 0.0), str(out.get("worker", ""))))
        except sqlite3.OperationalError as exc:     # e.g. the disk is full: what finished before is kept
            raise UsageError(f"--out {self.dir!r}: cannot record task {task.key} ({exc})",
                             fix="free disk space, then run again with --resume") from None

    def rows(self) -> list[tuple]:
        return list(self.con.execute("SELECT task, cell, kind, verdict, figures, counterexample FROM results "
                                     "ORDER BY task"))

    def close(self) -> None:
        self.con.close()


# ---------------------------------------------------------------------------
# running
# ---------------------------------------------------------------------------

@dataclass
class CampaignResult:
    spec: Any
    tasks: list[Task]
    results: dict[str, dict]       # task key -> {verdict, figures, counterexample}
    out_dir: str
    cut_short: bool = False
    ran: int = 0                   # tasks run by this invocation (the others were resumed)

    @property
    def exit_code(self) -> int:
        from swarmproof.models.verdict import EXIT_INCONCLUSIVE, EXIT_OK, EXIT_VIOLATED

        verdicts = [r["verdict"] for r in self.results.values()]
        if "violated" in verdicts:
            return EXIT_VIOLATED
        if self.cut_short or "inconclusive" in verdicts or len(self.results) < len(self.tasks):
            return EXIT_INCONCLUSIVE
        if self.tasks and all(v == "not_applicable" for v in verdicts):
            return EXIT_INCONCLUSIVE     # nothing asked for applied: nothing was checked (never a pass)
        # n/a tasks are no verdict: the others decide.  Measured tasks (experiment trials that ran)
        # did what they were asked -- measure, judge nothing -- so a campaign of them exits 0 once
        # every one finished (docs/decisions.md, "Campaigns: experiment cells")
        return EXIT_OK

    def cells(self) -> list[dict]:
        """Per cell: the verdict over its tasks, counts, first-failure figures and the smallest
        counterexample (fewest robots, then its file name)."""
        out: dict[str, dict] = {}
        for t in self.tasks:
            c = out.setdefault(t.cell, {"cell": t.cell, "kind": t.kind, "tasks": 0, "finished": 0,
                                        "counts": {"held": 0, "violated": 0, "inconclusive": 0, "n/a": 0,
                                                   MEASURED: 0},
                                        "smallest_counterexample": None, "first_failure_scenarios": None})
            c["tasks"] += 1
            r = self.results.get(t.key)
            if r is None:
                continue
            c["finished"] += 1
            v = ("n/a" if r["verdict"] == "not_applicable" else
                 r["verdict"] if r["verdict"] in c["counts"] else "inconclusive")
            c["counts"][v] += 1
            fig = r.get("figures") or {}
            if r.get("counterexample_path"):
                size = fig.get("counterexample_robots") or t.args.get("robots")
                cand = {"path": r["counterexample_path"], "robots": size, "task": t.key}
                best = c["smallest_counterexample"]
                if best is None or (cand["robots"], cand["path"]) < (best["robots"], best["path"]):
                    c["smallest_counterexample"] = cand
            ffs = fig.get("first_failure_scenarios")
            if ffs is not None and (c["first_failure_scenarios"] is None or ffs < c["first_failure_scenarios"]):
                c["first_failure_scenarios"] = ffs
        for c in out.values():
            n = c["counts"]
            # n/a (not applicable) is no verdict: a cell of n/a tasks only is "n/a", never held
            # measured (a cell of experiment trials): figures, no verdict on any claim
            c["verdict"] = ("violated" if n["violated"] else
                            "inconclusive" if n["inconclusive"] or c["finished"] < c["tasks"] else
                            "held" if n["held"] else MEASURED if n[MEASURED] else "n/a")
        return list(out.values())

    def to_json(self) -> dict:
        """One document, no wall-clock figure: two runs of one spec compare equal."""
        return {"campaign": self.spec.name, "digest": self.spec.digest, "out": self.out_dir,
                "tasks": len(self.tasks), "finished": len(self.results), "cut_short": self.cut_short,
                "cells": self.cells(),
                "results": [{"task": t.key, "cell": t.cell, "kind": t.kind, **self.results[t.key]}
                            for t in self.tasks if t.key in self.results],
                "exit_code": self.exit_code}


def _client(scheduler: str | None, workers: int | None):
    """A dask.distributed Client: to ``scheduler``, or to an embedded LocalCluster of ``workers``
    processes (default: one per core)."""
    import logging

    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise UsageError("campaigns and verify --workers need dask.distributed, which is not installed",
                         fix="pip install 'swarmproof[campaign]' (or: pip install 'dask[distributed]')") from None
    if scheduler is not None:
        try:
            return Client(scheduler, timeout=f"{SCHEDULER_CONNECT_TIMEOUT}s"), None
        except (OSError, TimeoutError) as exc:
            raise UsageError(f"--scheduler {scheduler!r} cannot be reached ({type(exc).__name__}: {exc})",
                             fix="start it with `dask scheduler` (and workers with `dask worker ADDRESS`), or "
                                 "check the address (tcp://HOST:PORT); without --scheduler a local cluster is used") from None
        except ValueError as exc:
            raise UsageError(f"--scheduler {scheduler!r} is not a scheduler address ({exc})",
                             fix="e.g. --scheduler tcp://127.0.0.1:8786") from None
    n = workers or os.cpu_count() or 1
    import dask

    # dashboard_address=":0": any free port (the HTTP server cannot be switched off; 8787 may be taken).
    # The workers' statistical profiler is off: it samples every task's stack every 10 ms, and on
    # the explorer's deep Hypothesis stacks that made a task 55 % slower (jiang's exploration rows:
    # 26 s of CPU in one process, 40 s in a worker; 32 s against 31 s without it;
    # docs/performance.md).  The workers read the setting when they start.
    # worker-saturation 1.0: a worker is sent its next task only when it is free (Dask's default,
    # 1.1, sends a one-thread worker two), so tasks start in priority order wherever a core frees
    # up (verify hands out its exploration tasks costliest first).
    with dask.config.set({"distributed.worker.profile.enabled": False,
                          "distributed.scheduler.worker-saturation": 1.0}):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                               silence_logs=logging.ERROR)
    return Client(cluster), cluster


@contextlib.contextmanager
def local_client(workers: int | None):
    """An embedded LocalCluster of ``workers`` processes (:func:`_client`) and its client, both
    closed on leaving (verify's ``--workers``)."""
    client, cluster = _client(None, workers)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _not_yet_there(out_dir: str) -> list[str]:
    """The paths a new results store in ``out_dir`` would create (the store, its SQLite side files,
    the folders up to the first that exists), innermost first; nothing that exists already."""
    made = [os.path.join(out_dir, "results.sqlite" + x) for x in ("", "-wal", "-shm", "-journal")]
    made = [p for p in made if not os.path.exists(p)]
    folder = os.path.abspath(out_dir)
    while folder and not os.path.exists(folder):
        made.append(folder)
        folder = os.path.dirname(folder)
    return made


def _remove_new(paths: list[str]) -> None:
    """Remove what :func:`_not_yet_there` listed (files, then the folders it created, if empty)."""
    for p in paths:
        try:
            (os.rmdir if os.path.isdir(p) else os.unlink)(p)
        except OSError:
            pass


def run_campaign(spec, *, out_dir: str, scheduler: str | None = None, workers: int | None = None,
                 resume: bool = False, progress: Callable[[int, int, int], None] | None = None) -> CampaignResult:
    """Run every unfinished task of ``spec`` on Dask; results stream into ``out_dir``.

    ``progress(done, total, violated)`` is called as tasks finish.  A
    KeyboardInterrupt cuts the campaign short: what finished is kept
    (``cut_short``; exit 3) and ``resume=True`` continues it.

    Raises
    ------
    UsageError
        A bad spec name (located), an unreachable scheduler, an ``out_dir``
        that holds another campaign or finished tasks without ``resume``.
    """
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise UsageError(f"--workers {workers!r} must be >= 1", fix="e.g. --workers 2")
    if scheduler is not None and workers is not None:
        raise UsageError("--workers applies to the embedded cluster only", fix="drop --workers with --scheduler")
    tasks = plan_tasks(spec)
    made = _not_yet_there(out_dir)
    store = ResultsStore(out_dir, spec, resume=resume)
    cut = False
    ran = lost = 0
    try:
        done = store.finished()
        pending = [t for t in tasks if t.key not in done]
        violated = sum(1 for r in store.rows() if r[3] == "violated")
        if progress:
            progress(len(done), len(tasks), violated)
        if pending:
            try:
                client, cluster = _client(scheduler, workers)
            except BaseException:
                store.close()
                _remove_new(made)   # e.g. an unreachable --scheduler: leave nothing behind
                raise
            try:
                from distributed import as_completed

                by_key = {}
                futures = []
                for t in pending:
                    fut = client.submit(run_task, t.as_dict(), key=f"swarmproof-{spec.digest[:12]}-{t.key}",
                                        pure=False, retries=3)
                    by_key[fut.key] = t
                    futures.append(fut)
                finished = len(done)
                for fut in as_completed(futures):
                    try:
                        out = fut.result()
                    except Exception:  # noqa: BLE001 - e.g. KilledWorker after the retries: the task stays unfinished
                        lost += 1
                        continue
                    store.write(by_key[fut.key], out)
                    ran += 1
                    finished += 1
                    violated += out["verdict"] == "violated"
                    if progress:
                        progress(finished, len(tasks), violated)
            except KeyboardInterrupt:
                cut = True
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
        results = {}
        for key, _cell, _kind, verdict, figures, cx in store.rows():
            results[key] = {"verdict": verdict, "figures": json.loads(figures), "counterexample_path": cx}
    finally:
        store.close()
    return CampaignResult(spec, tasks, results, out_dir, cut, ran)
