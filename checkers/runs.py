"""One checked run: simulate an algorithm and judge what its paper claims.

Shared by ``swarmproof simulate`` and the algorithm rows of
``swarmproof verify`` so both judge a run the same way: the final formation
against the target (a lattice: 001 Def. 2; any kind of
:mod:`swarmproof.models.targets`), connectivity at every step (001 Lemma 11),
the spanning-tree links, the algorithm's own termination bound when it offers
one (001 Theorem 13), its completion detection at every step when it has one
(``completion_sound``, judged by the property registry), and the metrics of
001 Sec. III-C and 000 Eq. 3.

Every property is judged and reported, but the exit code follows the properties the
algorithm *claims* (its class's ``claims``: property -> citation, None or absent = not
claimed; DESIGN.md section 2): 0 the run ended (finished or static) and every claimed property
held; 1 a claimed property was violated, or the algorithm crashed (``no_crash``: a finding for
any algorithm); 3 the step cap was reached first, or a claimed property is inconclusive.  A
claimed violation outranks the step cap.  An unclaimed property's verdict (a gathering
algorithm's "formation" of a lattice, 004's connectivity) is a finding in the report, not the
exit code.  A property the algorithm cannot give what it needs for (connectivity when every
robot hears every robot, tree links without a parent field) is ``not_applicable``: no verdict.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from swarmproof.models.errors import UsageError
from swarmproof.models.verdict import EXIT_INCONCLUSIVE, EXIT_OK, EXIT_VIOLATED, NOT_APPLICABLE, Verdict

__all__ = ["CheckedRun", "build_params", "check_robots", "MAX_ROBOTS", "run_and_check", "RUN_PROPERTIES", "run_property_verdicts",
           "cx_params", "run_counterexample", "not_applicable_properties"]


@dataclass
class CheckedRun:
    """The outcome of :func:`run_and_check`.

    Attributes
    ----------
    doc : dict
        The ``simulate`` JSON document (DESIGN.md section 2 fields and more).
    exit_code : int
        0 / 1 / 3 as in the module docstring.
    result : SimulationResult
        The engine's result (with its trace).
    lattice, algorithm, params, initial
        What was run (``lattice`` is the target, whatever its kind).
    satisfaction, connectivity, tree_links, termination, completion_sound
        The invariant results (termination is None when the algorithm offers neither a
        ``termination_bound`` nor an ``own_end``; completion_sound is None when the algorithm's
        robots detect no completion: not applicable);
        ``satisfaction`` is a lattice's
        :class:`~swarmproof.models.satisfaction.SatisfactionResult` or another target's
        :class:`~swarmproof.models.targets.TargetCheck`.
    metrics : dict
        The target's figures and the algorithm's (``metrics(result)``, when it has one).
    claims : dict
        Property -> citation (None: not claimed) of :data:`RUN_PROPERTIES`: what decides the exit code.
    not_applicable : dict
        Property -> what the algorithm lacks, for the properties of :data:`RUN_PROPERTIES` that
        are not applicable to it (no verdict).
    """

    doc: dict
    exit_code: int
    result: Any
    lattice: Any
    algorithm: Any
    params: Any
    initial: Any
    satisfaction: Any
    connectivity: Any
    tree_links: Any
    termination: Any
    metrics: dict = dataclasses.field(default_factory=dict)
    claims: dict = dataclasses.field(default_factory=dict)
    not_applicable: dict = dataclasses.field(default_factory=dict)
    completion_sound: Any = None
    #: the lemma premise monitors' verdict, streamed inside the engine on every step (``premises``
    #: of the property registry; None when not asked for or the algorithm declares none)
    premises: Any = None
    #: the exit code is 1 because of a transfer failure in ``premises`` alone (no claimed property
    #: failed, the algorithm did not crash): what simulate's result line says
    exit_by_transfer: bool = False
    #: the algorithm's own properties (its ``properties``, e.g. song2016's ``tree_link_cases``):
    #: name -> result, streamed inside the engine on every step where the property streams
    #: (empty when not asked for or it declares none)
    own: dict = dataclasses.field(default_factory=dict)


#: The largest team a seeded start is drawn for (memory and time bounded on any input; 004's runs
#: are 1,024 robots).
MAX_ROBOTS = 20000


def build_params(algorithm, phi: float, n: int, *, v: float | None = None, omega: float | None = None,
                 dt: float | None = None, extra: Mapping[str, Any] | None = None):
    """Params from the algorithm's defaults (if it offers ``default_params(range, n)``) and overrides,
    checked before any run by the engine's own checks (one code path for simulate, explore, campaigns
    and verify): motion that could move a robot (``v > 0``, a measurable ``v*dt``), and ``extra`` keys
    the algorithm declares, each in its range (:mod:`swarmproof.reference_impl.engine.parameters`)."""
    from swarmproof.reference_impl.engine.parameters import check_extra, check_motion
    from swarmproof.reference_impl.protocol import Params

    f = getattr(algorithm, "default_params", None)
    params = f(range=phi, n=n) if callable(f) else Params(range=phi)
    changes: dict[str, Any] = {}
    for name, val in (("v", v), ("omega", omega), ("dt", dt)):
        if val is not None:
            if not (math.isfinite(val) and (val > 0 or (name == "v" and val >= 0))):
                raise UsageError(f"{name}={val!r} must be a finite positive number")
            changes[name] = val
    if extra:
        check_extra(algorithm, extra)     # the user's keys first: the defaults' keys are the algorithm's own
        changes["extra"] = {**dict(params.extra), **dict(extra)}
    params = dataclasses.replace(params, **changes) if changes else params
    check_motion(params)
    return params


# ---------------------------------------------------------------------------
# the steps of run_and_check
# ---------------------------------------------------------------------------

def _run_range(spec, lattice, kind: str, phi: float | None) -> float:
    """The range of the run: ``phi``, else the target's, else the algorithm's ``default_range``
    (an algorithm whose robots sense everyone, 003, needs one only to draw connected starts)."""
    if phi is None:
        phi = getattr(lattice, "range", None)
    if phi is None:
        # an algorithm whose robots sense everyone (003) needs a range only to draw connected starts
        phi = getattr(spec.factory, "default_range", None)
    if phi is None:
        raise UsageError(f"{kind} {lattice.name!r} has no default range", fix="pass --range PHI")
    if not (math.isfinite(phi) and phi > 0):
        raise UsageError(f"range={phi!r} must be a finite number > 0")
    return phi


def _target_warnings(lattice, phi: float, strict: bool) -> list:
    """The warning about a user's lattice that check-lattice does not pass at ``phi`` (a list of
    at most one); with ``strict`` it is a usage error instead."""
    from swarmproof.checkers.lattice_check import user_lattice_warning

    warnings = []
    w = user_lattice_warning(lattice, phi)
    if w is not None:
        if strict:
            raise UsageError(w, fix="fix the lattice file, or drop --strict to run toward it anyway")
        warnings.append(w)
    return warnings


def check_robots(robots: int | None, initial) -> None:
    """Without an ``initial`` configuration, ``robots`` is required and at most :data:`MAX_ROBOTS`
    (simulate, verify's algorithm rows and campaigns' simulate cells)."""
    if initial is not None:
        return
    if robots is None:
        raise UsageError("robots=None: the number of robots is required without an initial file",
                         fix="e.g. --robots 10")
    if robots < 1:
        raise UsageError(f"robots={robots!r} must be >= 1", fix="give the team size, e.g. --robots 10")
    if robots > MAX_ROBOTS:
        raise UsageError(f"robots={robots!r} is more than swarmproof draws a start for (at most {MAX_ROBOTS})",
                         fix=f"run at most {MAX_ROBOTS} robots, or start from your own poses "
                             f"(swarmproof simulate --initial FILE)")


def _seeded_start(algorithm, n: int, seed: int, params, lattice, phi: float, min_separation):
    """The start drawn for ``n`` robots from ``seed``: the algorithm's own ``initial(n, seed,
    params, target)`` when it has one (004 Sec. V-A: distinct random waypoints of an arena), else a
    random connected start (on grid cells for grid motion).  ``min_separation`` is honoured by the
    random connected start of continuous robots only; given for another start it is a usage error
    (:func:`_unused_min_separation`), never silently dropped."""
    from swarmproof.reference_impl import initial as initial_mod

    start = getattr(algorithm, "initial", None)
    initial = start(n, seed, params, lattice) if callable(start) else None
    grid = getattr(algorithm.model, "motion", None) == "grid"
    if min_separation is not None and (initial is not None or grid):
        raise _unused_min_separation(algorithm, params, min_separation, own_start=initial is not None)
    if initial is None:
        if grid:
            initial = initial_mod.random_grid_connected(n, seed, range=phi,
                                                        spacing=float(params.extra.get("grid_spacing", 1.0)))
        else:
            initial = initial_mod.random_connected(n, seed, range=phi, min_separation=min_separation)
    return initial


def _unused_min_separation(algorithm, params, min_separation, *, own_start: bool = False,
                           initial_file: bool = False) -> UsageError:
    """The usage error of a ``min_separation`` no start would honour (docs/decisions.md, "Wang &
    Rubenstein 2020: the review of issue 15"): an initial file gives the poses; grid robots start
    on distinct waypoints, at least ``grid_spacing`` apart by construction (an algorithm's own
    start, 004 Sec. V-A's arena, is such a start)."""
    what = f"min_separation={min_separation!r} (--min-separation)"
    if initial_file:
        return UsageError(f"{what} is not used with an initial file: the file gives the poses",
                          fix="drop --min-separation, or drop --initial to draw a start that keeps it")
    l = float(dict(params.extra).get("grid_spacing", 1.0))
    if own_start:
        why = (f"algorithm {algorithm.name!r} draws its own start (its initial hook"
               + ("" if getattr(algorithm.model, "motion", None) != "grid" else
                  f": distinct grid waypoints, at least grid_spacing={l!r} apart") + ")")
    else:
        why = (f"algorithm {algorithm.name!r} moves on a grid: its random connected start puts robots on "
               f"distinct waypoints, at least grid_spacing={l!r} apart")
    fix = "drop --min-separation, or give the poses yourself (--initial FILE)"
    if own_start and callable(getattr(algorithm, "arena_size", None)):
        fix = "drop --min-separation (a sparser start: a larger arena, --param arena=SIDE), or give the " \
              "poses yourself (--initial FILE)"
    return UsageError(f"{what} is not used: {why}", fix=fix)


def _engine(algorithm, vectorised: bool) -> Callable:
    """The engine's ``simulate``, or with ``vectorised`` the algorithm's ``vectorised_simulate``
    (same signature, same trace); an algorithm without one is a usage error."""
    from swarmproof.reference_impl.engine import simulate

    if not vectorised:
        return simulate
    simulate = getattr(algorithm, "vectorised_simulate", None)
    if not callable(simulate):
        raise UsageError(f"vectorised=True: algorithm {algorithm.name!r} has no vectorised path",
                         fix="drop --vectorised (docs/engine.md lists the algorithms that have one)")
    return simulate


def _streaming_monitors(algorithm, phi: float, link_mode: str) -> tuple:
    """The monitors a sparse trace needs: connectivity and the tree links are judged on every step
    the engine feeds them (DESIGN.md section 5, "Monitors see every step")."""
    from swarmproof.invariants.connectivity import TreeLinkMonitor, connectivity_monitor

    return (connectivity_monitor(algorithm, phi), TreeLinkMonitor(phi, mode=link_mode))


@dataclass
class _Formation:
    """The final configuration judged against the target: the target judged (an algorithm may
    restate it, 003), its verdict, a lattice's fulfillment ratios and every figure."""

    judged: Any
    sat: Any
    q: float | None
    nq: float | None
    metrics: dict


def _judge_formation(algorithm, result, lattice, kind: str, params, phi: float) -> _Formation:
    """The final formation against the target: a lattice by 001 Def. 2 (and Q, 000 Eq. 3), any
    other kind by its own ``satisfied`` on the robots the algorithm says it judges; then the
    algorithm's own ``metrics(result)``."""
    from swarmproof.invariants.metrics import fulfillment_ratio, non_fulfillment_ratio
    from swarmproof.invariants.satisfaction import DEFAULT_SAT_ANG_TOL, DEFAULT_SAT_POS_TOL, satisfies_lattice

    pos_tol, ang_tol = getattr(algorithm, "satisfaction_tol", (DEFAULT_SAT_POS_TOL, DEFAULT_SAT_ANG_TOL))
    ids, poses = result.final_ids, result.final_poses
    judged = lattice
    if kind == "lattice":
        sat = satisfies_lattice(ids, poses, lattice, phi, pos_tol=pos_tol, ang_tol=ang_tol)
        q = fulfillment_ratio(ids, poses, lattice, phi, sat.roles) if sat.held else None
        nq = non_fulfillment_ratio(ids, poses, lattice, phi, sat.roles) if sat.held else None
        metrics = {"fulfillment_ratio": q, "non_fulfillment_ratio": nq}
    else:
        from swarmproof.invariants.satisfaction import judged_robots

        tol = getattr(algorithm, "satisfaction_tol", None)
        judged, ids, poses = judged_robots(algorithm, result, lattice, params)
        sat = judged.satisfied(ids, poses, phi=phi, tol=tol)
        q = nq = None
        metrics = dict(judged.metrics(ids, poses, phi=phi))
    if result.status == "step_cap" and sat.status == "violated" and dataclasses.is_dataclass(sat):
        # no final configuration to judge: the run was cut, as the explorer's "formation" says
        sat = dataclasses.replace(sat, status="inconclusive", message=(
            f"not judged: the step cap {result.max_steps} was reached before the run ended (the "
            f"configuration at the cap is not a final one; there: {sat.message})"))
    own = getattr(algorithm, "metrics", None)
    if callable(own):
        metrics.update(own(result))
    return _Formation(judged, sat, q, nq, metrics)


def _judge_links(algorithm, result, phi: float, link_mode: str, streamed: bool):
    """Connectivity (001 Lemma 11) and the spanning-tree links over the run: from the streaming
    monitors when ``streamed``, else judged on the trace."""
    from swarmproof.invariants.connectivity import judge_connectivity, tree_links_survive

    if streamed:
        return result.observed("connectivity"), result.observed("tree_links")
    return judge_connectivity(result.trace, phi, algorithm), tree_links_survive(result.trace, phi, mode=link_mode)


#: The properties of :data:`RUN_PROPERTIES` that :func:`run_and_check` judges by the property registry
#: (the property's check on a dense trace, its streaming monitor on a sparse one) rather than by code of
#: its own.
REGISTRY_RUN_PROPERTIES = ("completion_sound",)


def _registry_observers(algorithm, params, na: dict, record_every: int) -> tuple:
    """The streaming monitors of the applicable :data:`REGISTRY_RUN_PROPERTIES` for a sparse trace
    (a dense one is judged step by step afterwards, the same verdict)."""
    from swarmproof.invariants.registry import get_property

    if record_every == 1:
        return ()
    return tuple(get_property(p).stream(algorithm, params, {}) for p in REGISTRY_RUN_PROPERTIES if p not in na)


def _judge_registry(algorithm, lattice, params, result, na: dict) -> dict:
    """Property -> its registry verdict on the run (None where not applicable)."""
    from swarmproof.invariants.registry import PropertyContext, get_property

    ctx = PropertyContext(algorithm, lattice, params, result, {})
    return {p: None if p in na else get_property(p).judge(result.trace, ctx) for p in REGISTRY_RUN_PROPERTIES}


def _own_observers(algorithm, params, lattice) -> dict:
    """Name -> the streaming monitor of each of the algorithm's own properties that streams and
    applies (the engine feeds it every step, whatever the trace keeps)."""
    from swarmproof.invariants.registry import get_property, own_properties_of

    out = {}
    for name in own_properties_of(algorithm):
        prop = get_property(name)
        if prop.stream is not None and prop.not_applicable_to(algorithm, lattice) is None:
            out[name] = prop.stream(algorithm, params, {})
    return out


def _judge_own(algorithm, lattice, params, result, observers: dict) -> dict:
    """Name -> the verdict of each of the algorithm's own properties on the run: its streaming
    monitor's where it streamed (every step), else its check on the trace; None where not applicable."""
    from swarmproof.invariants.registry import PropertyContext, get_property, own_properties_of

    ctx = PropertyContext(algorithm, lattice, params, result, {})
    out = {}
    for name in own_properties_of(algorithm):
        prop = get_property(name)
        ob = observers.get(name)
        if prop.not_applicable_to(algorithm, lattice) is not None:
            out[name] = None
        elif ob is None or result.crash is not None:
            out[name] = prop.judge(result.trace, ctx)
        else:
            judge = getattr(ob, "judge", None)
            out[name] = judge(ctx) if callable(judge) else ob.result()
    return out


def _judge_termination(algorithm, result, params):
    """The algorithm's own termination bound or end (001 Thm. 13) judged on the run; None when it
    offers neither."""
    if callable(getattr(algorithm, "termination_bound", None)) or getattr(algorithm, "own_end", None):
        from swarmproof.invariants.termination import judge_termination

        return judge_termination(result.trace, algorithm, params, result.status, max_steps=result.max_steps)
    return None


def _simulate_document(algorithm, lattice, kind: str, initial, seed: int, phi: float, params, result,
                       formation: _Formation, conn, links, *, record_every: int, warnings: list,
                       vectorised: bool) -> dict:
    """The ``simulate`` JSON document (DESIGN.md section 2 fields and more, in this order),
    without the termination, crash and exit code fields that follow them."""
    from swarmproof.invariants.metrics import execution_steps, min_separation, total_distance

    trace, sat, judged = result.trace, formation.sat, formation.judged
    is_lattice = kind == "lattice"
    satisfied = sat.held if sat.status != "inconclusive" else None
    return {
        "algorithm": algorithm.name,
        "lattice": lattice.name if is_lattice else None,
        "robots": int(initial.n),
        "seed": int(seed),
        "range": float(phi),
        "steps": int(result.steps),
        "status": result.status,
        "static": bool(result.static),
        "execution_steps": int(execution_steps(trace)),
        "satisfies_lattice": satisfied if is_lattice else None,
        "satisfaction": sat.as_dict(),
        "fulfillment_ratio": formation.q,
        "non_fulfillment_ratio": formation.nq,
        "connected_throughout": None if conn.status == "inconclusive" else conn.held,
        "connectivity": conn.as_dict(),
        "tree_links": links.as_dict(),
        "total_distance": total_distance(trace),
        "min_separation": min_separation(trace),
        "broken_assumptions": list(result.broken_assumptions),
        "params": {"v": params.v, "omega": params.omega, "dt": params.dt},
        **({"record_every": int(record_every), "recorded_steps": len(trace.times)} if trace.times else {}),
        **({"warnings": warnings} if warnings else {}),
        **({"vectorised": True} if vectorised else {}),   # the same trace; said so the run is reproducible as run
        "target": {"kind": kind, "name": lattice.name,
                   # the target the final configuration was judged against, when the algorithm restates
                   # it (003: the last pattern of a switching sequence, at the start's span)
                   **({"judged_as": judged.describe()} if not is_lattice and judged is not lattice else {})},
        "satisfied": satisfied,
        "metrics": formation.metrics,
    }


def not_applicable_properties(algorithm, target=None) -> dict[str, str]:
    """Property -> what ``algorithm`` lacks, for each of :data:`RUN_PROPERTIES` that is not
    applicable to it (its declarations against the property's ``needs``).

    >>> from swarmproof.reference_impl.registry import algorithm_factory
    >>> sorted(not_applicable_properties(algorithm_factory("jiang")))
    ['completion_sound', 'connectivity', 'tree_links']
    >>> not_applicable_properties(algorithm_factory("song2016"))
    {'completion_sound': 'its robots do not detect completion (no completion_invariants)'}
    >>> not_applicable_properties(algorithm_factory("wang2020"))
    {'tree_links': "no 'parent' field in its controller states (state_fields=())"}
    """
    from swarmproof.invariants.registry import get_property

    out = {}
    for prop in RUN_PROPERTIES:
        why = get_property(prop).not_applicable_to(algorithm, target)
        if why is not None:
            out[prop] = why
    return out


def _exit_code(result, sat, conn, links, term, claims=None, na=None, more=None) -> int:
    """The run's verdict (module docstring): a crash, or a claimed property violated (a broken
    link, lost connectivity, a violated termination bound, the formation, unsound completion), first;
    then the step cap; then a claimed property inconclusive.  ``claims`` None judges every property
    (as before claims decided); unclaimed and not-applicable properties never decide it.  ``more``:
    property -> result of the :data:`REGISTRY_RUN_PROPERTIES`."""
    na = na or {}

    def judged(prop: str) -> bool:
        return prop not in na and (claims is None or claims.get(prop) is not None)

    if result.crash is not None:
        return EXIT_VIOLATED
    verdicts = {"connectivity": conn, "tree_links": links, "termination": term, "formation": sat, **(more or {})}
    if any(judged(p) and r is not None and r.violated for p, r in verdicts.items()):
        return EXIT_VIOLATED
    if result.status == "step_cap":
        return EXIT_INCONCLUSIVE
    if any(judged(p) and r is not None and r.status == "inconclusive" for p, r in verdicts.items()):
        return EXIT_INCONCLUSIVE     # e.g. claimed connectivity from a disconnected start: vacuous, not a pass
    return EXIT_OK


def _claims_document(claims: dict, na: dict, checked: dict) -> dict:
    """``claims``: property -> citation or None; ``judged``: the claimed, applicable properties the
    exit code follows; ``not_applicable``: property -> what the algorithm lacks."""
    return {"claims": {p: claims.get(p) for p in RUN_PROPERTIES},
            "judged": [p for p in RUN_PROPERTIES if claims.get(p) is not None and p not in na and checked.get(p)],
            "not_applicable": dict(na)}


def _na_document(prop: str, reason: str) -> dict:
    """The JSON of a property that is not applicable to the algorithm: no verdict."""
    from swarmproof.invariants.capabilities import NOT_APPLICABLE_STATUS

    return {"name": prop, "status": NOT_APPLICABLE_STATUS, "cites": None, "witness": None,
            "message": f"not applicable: {reason}", "applicable": False}


def run_and_check(algorithm_name: str, lattice, *, seed: int, robots: int | None = None,
                  initial=None, phi: float | None = None, max_steps: int | None = None,
                  v: float | None = None, omega: float | None = None, dt: float | None = None,
                  extra: Mapping[str, Any] | None = None, min_separation: float | None = None,
                  allow_violations: bool = False,
                  progress: Callable[[int, int], None] | None = None, record_every: int = 1,
                  strict: bool = False, tree_link_mode: str | None = None,
                  vectorised: bool = False, premises: bool = False, own_properties: bool = False) -> CheckedRun:
    """Run ``algorithm_name`` on ``lattice`` (any target) from a seeded connected start (or ``initial``)
    and check it.

    Two optional hooks of the algorithm come first: ``scale_target(target, n)`` gives the target
    it runs toward with ``n`` robots (004: the shape scaled to n goal cells), and
    ``initial(n, seed, params, target)`` its own seeded start instead of the connected one
    (004: distinct random waypoints of an arena).  ``CheckedRun.lattice`` is the target run.
    ``vectorised`` runs the algorithm's optional ``vectorised_simulate`` (``engine.simulate``'s
    signature, the same trace) instead of the engine; an algorithm without one is a usage error.
    ``premises`` streams the algorithm's lemma premise monitors inside the engine on every step
    (``simulate`` asks for them): the JSON's ``premises``; "premises held, conclusion false" (the
    proof does not transfer to the run) makes the exit code 1 whether claimed or not.
    ``own_properties`` judges the algorithm's own properties (its ``properties``: checks of its
    paper that no lemma states), streamed inside the engine on every step where they stream
    (``simulate`` asks for them): the JSON's ``own_properties``; a claimed one decides the exit code
    as any claimed property does.

    The JSON document keeps every field it had for lattices and adds
    ``target{kind, name}``, ``satisfied`` (the target's verdict on the final
    configuration: true, false, or null when inconclusive) and ``metrics{}``
    (the target's and the algorithm's figures); for other kinds ``lattice``,
    ``satisfies_lattice``, ``satisfaction.roles`` and the fulfillment ratios are null.

    Raises
    ------
    UsageError
        Unknown algorithm (lists the valid names), no range, bad numbers,
        or parameters outside the paper's assumptions (``AssumptionError``)
        unless ``allow_violations``.
    """
    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.invariants.connectivity import tree_link_mode_of
    from swarmproof.reference_impl.engine.parameters import check_target_kind
    from swarmproof.reference_impl.engine.run import check_team_size

    spec = resolve_algorithm(algorithm_name)  # unknown names fail first, listing the valid ones
    if seed < 0:
        raise UsageError(f"seed={seed!r} must be >= 0")
    check_target_kind(spec.factory, lattice)  # a target of a kind it does not form: refused before any run
    kind = getattr(lattice, "kind", "lattice")
    phi = _run_range(spec, lattice, kind, phi)
    warnings = _target_warnings(lattice, phi, strict)
    if max_steps is not None and max_steps < 0:
        raise UsageError(f"max_steps={max_steps!r} must be >= 0")
    check_robots(robots, initial)
    n = initial.n if initial is not None else robots
    algorithm = spec.build(n_robots=n)
    check_team_size(algorithm, n)          # before drawing a start: bounded on any input
    scale = getattr(algorithm, "scale_target", None)
    if callable(scale):
        # the algorithm's own target for n robots (004 Sec. V-A: the figure scaled to |A| goals)
        lattice = scale(lattice, n)
    params = build_params(algorithm, phi, n, v=v, omega=omega, dt=dt, extra=extra)
    if initial is None:
        initial = _seeded_start(algorithm, n, seed, params, lattice, phi, min_separation)
    elif min_separation is not None:
        raise _unused_min_separation(algorithm, params, min_separation, initial_file=True)
    link_mode = tree_link_mode_of(algorithm, {"tree_link_mode": tree_link_mode})
    na = not_applicable_properties(algorithm, lattice)
    observers = _streaming_monitors(algorithm, phi, link_mode) if record_every != 1 else ()
    observers += _registry_observers(algorithm, params, na, record_every)
    streamed = bool(observers)         # connectivity and tree links streamed (a sparse trace)
    prem_monitor = _premises_observer(algorithm, params) if premises else None
    if prem_monitor is not None:
        observers += (prem_monitor,)
    own_obs = _own_observers(algorithm, params, lattice) if own_properties else {}
    observers += tuple(own_obs.values())
    result = _engine(algorithm, vectorised)(
        algorithm, lattice, initial, params, seed=seed, max_steps=max_steps, allow_violations=allow_violations,
        progress=progress, record_every=record_every, observers=observers)
    formation = _judge_formation(algorithm, result, lattice, kind, params, phi)
    conn, links = _judge_links(algorithm, result, phi, link_mode, streamed=streamed)
    more = _judge_registry(algorithm, lattice, params, result, na)
    own = _judge_own(algorithm, lattice, params, result, own_obs) if own_properties else {}
    doc = _simulate_document(algorithm, lattice, kind, initial, seed, phi, params, result, formation, conn, links,
                             record_every=record_every, warnings=warnings, vectorised=vectorised)
    term = _judge_termination(algorithm, result, params)
    if term is not None:
        doc["termination"] = term.as_dict()
    if result.crash is not None:
        doc["crash"] = dict(result.crash)
    claims = dict(spec.claims)
    for prop, res in more.items():
        doc[prop] = res.as_dict() if res is not None else None
    for prop in ("connectivity", "tree_links") + REGISTRY_RUN_PROPERTIES:
        if prop in na:
            doc[prop] = _na_document(prop, na[prop])
    if "connectivity" in na:
        doc["connected_throughout"] = None
    doc.update(_claims_document(claims, na, {"termination": term is not None, "formation": True,
                                             "connectivity": True, "tree_links": True,
                                             **{p: True for p in REGISTRY_RUN_PROPERTIES}}))
    if own:
        doc["own_properties"] = {p: (r.as_dict() if r is not None else
                                     _na_document(p, _own_na(algorithm, lattice, p))) for p, r in own.items()}
    code = _exit_code(result, formation.sat, conn, links, term, claims, na,
                      {**more, **{p: r for p, r in own.items() if r is not None}})
    prem = None
    if prem_monitor is not None and result.steps > 0:
        prem = prem_monitor.result()
        doc["premises"] = prem.as_dict()
    by_transfer = prem is not None and prem.violated and bool(prem.witness.get("transfer")) \
        and code != EXIT_VIOLATED
    if by_transfer:
        code = EXIT_VIOLATED         # the proof does not transfer to this run: the worst finding
    doc["exit_code"] = code
    return CheckedRun(doc, code, result, lattice, algorithm, params, initial, formation.sat, conn, links, term,
                      formation.metrics, {p: claims.get(p) for p in RUN_PROPERTIES}, na,
                      completion_sound=more.get("completion_sound"), premises=prem, exit_by_transfer=by_transfer,
                      own=own)


def _own_na(algorithm, target, name: str) -> str:
    """Why the registered property ``name`` is not applicable to ``algorithm`` ("" when it is)."""
    from swarmproof.invariants.registry import get_property

    return get_property(name).not_applicable_to(algorithm, target) or ""


def _premises_observer(algorithm, params):
    """The streaming ``premises`` monitor of the algorithm's declared premise monitors (None when
    it declares none)."""
    from swarmproof.invariants.premises import premise_monitors_of
    from swarmproof.invariants.registry import get_property

    if not premise_monitors_of(algorithm):
        return None
    return get_property("premises").stream(algorithm, params, {})


# ---------------------------------------------------------------------------
# a checked run's verdict per property, and its counterexample file
# (shared by verify's algorithm rows and campaigns' simulate tasks)
# ---------------------------------------------------------------------------

#: The registered properties :func:`run_and_check` judges of every run (verify's ``algorithms``
#: rows and campaigns' simulate tasks, in this order).
RUN_PROPERTIES = ("termination", "formation", "connectivity", "tree_links") + REGISTRY_RUN_PROPERTIES


def run_property_verdicts(checked) -> dict[str, tuple[Verdict, str]]:
    """Verdict and a short detail for each registry property of one checked run."""
    doc = checked.doc
    out: dict[str, tuple[Verdict, str]] = {}
    status = doc["status"]
    if status == "crashed":
        crash = doc["crash"]
        msg = f"the algorithm raised {crash['error']} in step {crash['step']}: {crash['message']}"
        na = getattr(checked, "not_applicable", None) or {}
        return {p: (NOT_APPLICABLE, f"not applicable: {na[p]}") if p in na else
                (Verdict.VIOLATED if p == "termination" else Verdict.INCONCLUSIVE, msg) for p in RUN_PROPERTIES}
    if status == "step_cap":
        out["termination"] = (Verdict.INCONCLUSIVE, f"step cap {doc['steps']} reached")
    elif checked.termination is not None and checked.termination.violated:
        out["termination"] = (Verdict.VIOLATED, checked.termination.message)
    else:
        out["termination"] = (Verdict.HELD, f"{status} at step {doc['execution_steps']}")
    sat = checked.satisfaction
    out["formation"] = (Verdict(sat.status) if status != "step_cap" else Verdict.INCONCLUSIVE,
                        sat.message)
    conn = checked.connectivity
    out["connectivity"] = (Verdict(conn.status), conn.message)
    links = checked.tree_links
    out["tree_links"] = (Verdict(links.status), links.message)
    for prop in REGISTRY_RUN_PROPERTIES:
        res = getattr(checked, prop, None)
        if res is not None:
            out[prop] = (Verdict(res.status), res.message)
    for prop, why in (getattr(checked, "not_applicable", None) or {}).items():
        out[prop] = (NOT_APPLICABLE, f"not applicable: {why}")     # no verdict (never inconclusive)
    return out


def cx_params(p) -> dict:
    """The ``params`` of a counterexample file for the run parameters ``p`` (``Params``)."""
    return {"range": p.range, "v": p.v, "omega": p.omega, "dt": p.dt,
            "extra": {k: v for k, v in dict(p.extra).items()}}


def run_counterexample(checked, prop: str, message: str, ref: str | None = None):
    """A ``swarmproof-counterexample/1`` of one seeded run whose ``prop`` was violated, for
    ``swarmproof replay`` (the same algorithm, start, seed and parameters; the property is
    judged by the registry, as the run was).  ``ref`` is what the file names as the algorithm
    (``module:qualname`` of a user's class; default the algorithm's registry name).  The
    violation's step is the step of the property's witness (None when it has none); a leading
    ``step N:`` of the message is left to the file's ``violation.step``."""
    import re

    from swarmproof.models.counterexample import Counterexample

    res = getattr(checked, prop if prop != "formation" else "satisfaction", None)
    step = (getattr(res, "witness", None) or {}).get("step") if res is not None else None
    init = checked.initial
    target = checked.lattice
    is_lattice = getattr(target, "kind", "lattice") == "lattice"
    if step is not None:
        message = re.sub(rf"^step {int(step)}: ", "", message)
    from swarmproof.reference_impl.protocol import reading_of

    return Counterexample(
        algorithm=ref or checked.algorithm.name, reading=reading_of(checked.algorithm),
        params=cx_params(checked.params),
        lattice=target.name if is_lattice else None,
        robots=[(int(i), tuple(float(x) for x in pose)) for i, pose in zip(init.ids.tolist(), init.poses)],
        seed=int(checked.doc["seed"]), property=prop,
        violation={"step": step, "message": message},
        broken_assumptions=list(checked.doc.get("broken_assumptions", [])),
        target=None if is_lattice else target.describe(),
        clocks=getattr(getattr(checked.result, "trace", None), "meta", {}).get("clocks"))
