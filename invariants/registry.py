"""Properties as objects: the registry the explorer, verify, replay and the pytest plugin iterate.

A :class:`Property` has a name, a kind (``safety``: one bad step violates it;
``liveness``: only the whole run can), what it reads from a run, its blind
spots (what it cannot see), where its statement comes from, and a
``check(trace, context) -> InvariantResult`` that returns one of the three
verdicts (held, violated with a witness, inconclusive).  The built-in
properties are registered here in the order the explorer and ``swarmproof
verify`` list them; a user registers their own with :func:`register_property`
(or the :func:`property_check` decorator) and explores for it by name, or by
``module:name`` on the command line, which also lets ``swarmproof replay``
find it again from a counterexample file.

Examples
--------
>>> [p.name for p in properties()][:4]
['connectivity', 'tree_links', 'termination', 'formation']
>>> get_property("collision").kind
'safety'
>>> get_property("no-such")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
swarmproof.models.errors.UsageError: property='no-such' is not known; fix: use one of ['connectivity', 'tree_links', 'termination', 'formation', 'collision', 'deadlock', 'oscillation', 'premises', 'invariants', 'no_crash', 'completion_sound'], ...or module:name of a property you registered
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

from swarmproof.models.errors import UsageError, did_you_mean

from .connectivity import LEMMA_11
from .properties import CITE_COLLISION, CITE_DEADLOCK, CITE_OSCILLATION, CITE_PREMISES
from .result import InvariantResult
from .termination import THEOREM_13

__all__ = ["Property", "PropertyContext", "register_property", "unregister_property", "property_check",
           "get_property", "properties", "property_names", "own_properties_of", "progress_values",
           "DEFAULT_RADIUS", "DEFAULT_POS_TOL", "DEFAULT_PROGRESS_WINDOW", "collision_radius"]

DEFAULT_RADIUS = 0.1        # robot disc radius for "collision", lattice edges have unit length
DEFAULT_POS_TOL = 1e-6     # oscillation: poses rounded to this when global states are compared
DEFAULT_PROGRESS_WINDOW = 200  # steps without progress that "oscillation" reports for randomized algorithms

KINDS = ("safety", "liveness")


@dataclass(frozen=True)
class PropertyContext:
    """Everything besides the trace that a property may read about one finished run.

    Attributes
    ----------
    algorithm : object
        The algorithm object that ran (its optional attributes --
        ``satisfaction_tol``, ``termination_bound``, ``randomized``,
        ``progress_measure``, ``premise_monitors``, ``tree_link_mode`` --
        refine some properties).
    target : object
        The target the run aimed at (a lattice graph today).
    params : Params
        The run's parameters (``range`` is phi).
    result : SimulationResult
        Status, step count, step cap, static window and final configuration.
    options : mapping
        The explorer's property options (``radius``, ``pos_tol``, ``deadlock_k``, ...).
    """

    algorithm: Any
    target: Any
    params: Any
    result: Any
    options: Mapping[str, Any] = field(default_factory=dict)

    @property
    def phi(self) -> float:
        return float(self.params.range)


@dataclass(frozen=True)
class Property:
    """One property a run is judged by.

    Attributes
    ----------
    name : str
        The name the explorer, verify rows and counterexample files use.
    kind : str
        ``"safety"`` or ``"liveness"``.
    check : callable ``(trace, PropertyContext) -> InvariantResult``
        The judgment: held, violated (with a witness) or inconclusive.
    reads : tuple of str
        What the check reads of a run, e.g. ``("poses", "range")``.
    blind_spots : str
        What it cannot see (so a held verdict is read for what it is).
    cites : str
        Where the statement comes from (a paper's lemma, or "swarmproof").
    closeness : callable ``(InvariantResult) -> float | None``, optional
        How near a run that held came to violating it (higher is nearer);
        the explorer steers Hypothesis toward such runs.
    run_monitor : callable ``(factory, options) -> monitor | None``, optional
        A monitor that may end a run early once the property is decided
        (the explorer re-runs to the end when the early verdict is not a
        violation).
    stream : callable ``(algorithm, params, options) -> observer``, optional
        A streaming monitor the engine feeds every step (``simulate(observers=...)``);
        on a sparse trace the property is judged by it.
    every_step : bool
        The check reads every step of the trace (a safety property over the
        run); on a sparse trace without a streaming monitor it is inconclusive.
    needs : tuple of str
        What it needs of an algorithm that not every algorithm has (names of
        :data:`swarmproof.invariants.capabilities.NEEDS`: ``"range_graph"``, ``"parent"``,
        ``"messages"``, ``"lattice_target"``, ``"premise_monitors"``, ``"invariants"``).  An
        algorithm that declares it cannot give one gets no verdict for the property: *not
        applicable* (:meth:`not_applicable_to`), decided before any run.
    own : bool
        An algorithm's own property (issue 32: a check of its paper that no lemma states, e.g.
        ``tree_link_cases``, which cases of the paper's argument cover each tree link): it applies only to an algorithm that names it in its class
        attribute ``properties`` (:func:`own_properties_of`), and the explorer and ``verify`` judge it
        for those algorithms only (no row for the others).  A paper's package registers its own
        properties when it is imported.
    """

    name: str
    kind: str
    check: Callable[[Any, PropertyContext], InvariantResult]
    reads: tuple = ()
    blind_spots: str = ""
    cites: str = ""
    closeness: Callable[[InvariantResult], float | None] | None = None
    run_monitor: Callable[[Any, Mapping[str, Any]], Any] | None = None
    stream: Callable[[Any, Any, Mapping[str, Any]], Any] | None = None
    every_step: bool = False
    needs: tuple = ()
    own: bool = False

    def not_applicable_to(self, algorithm, target=None) -> str | None:
        """Why this property is not applicable to ``algorithm`` (what it lacks), or None.

        >>> from swarmproof.reference_impl.protocol import RobotModel
        >>> A = type("A", (), {"model": RobotModel(communication="all")})
        >>> get_property("connectivity").not_applicable_to(A)
        "no range graph: every robot hears every robot (communication='all')"
        >>> get_property("collision").not_applicable_to(A) is None
        True
        """
        from .capabilities import not_applicable

        if self.own and self.name not in _declared_properties(algorithm):
            return f"{self.name} is another algorithm's own property (not in its properties)"
        return not_applicable(algorithm, self.needs, target)

    def judge(self, trace, ctx: "PropertyContext") -> InvariantResult:
        """``check`` on a dense trace; on a sparse one (``trace.times``), the result of the
        streaming monitor the run carried, else inconclusive when the check needs every step.
        A run the algorithm crashed is judged by ``no_crash`` only (the others: inconclusive)."""
        crash = getattr(ctx.result, "crash", None)
        if crash is not None and self.name != "no_crash":
            return InvariantResult(self.name, "inconclusive", self.cites, None,
                                   f"the run ended when the algorithm raised {crash['error']} in step "
                                   f"{crash['step']} (a no_crash finding)")
        if getattr(trace, "times", None) is not None and self.every_step:
            for ob in getattr(ctx.result, "observers", ()) or ():
                if getattr(ob, "name", None) == self.name:
                    judge = getattr(ob, "judge", None)
                    return judge(ctx) if callable(judge) else ob.result()
            return InvariantResult(self.name, "inconclusive", self.cites, None,
                                   f"the trace is sparse (record_every={trace.meta.get('record_every')}) and "
                                   f"{self.name} needs every step: run it with its streaming monitor or dense")
        return self.check(trace, ctx)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name or ":" in self.name or self.name != self.name.strip():
            raise UsageError(f"property name={self.name!r} must be a non-empty string without ':' or spaces "
                             "at its ends", fix="e.g. name='no_far_robot'")
        if self.kind not in KINDS:
            raise UsageError(f"property {self.name!r}: kind={self.kind!r} is not one of {list(KINDS)!r}")
        if not callable(self.check):
            raise UsageError(f"property {self.name!r}: check={self.check!r} is not callable",
                             fix="give a function (trace, context) -> InvariantResult")
        from .capabilities import NEEDS

        needs = (self.needs,) if isinstance(self.needs, str) else tuple(self.needs or ())
        bad = [n for n in needs if n not in NEEDS]
        if bad:
            raise UsageError(f"property {self.name!r}: needs={bad[0]!r} is not a need swarmproof knows",
                             fix=f"use some of {sorted(NEEDS)!r}")
        object.__setattr__(self, "needs", needs)

    def as_dict(self) -> dict:
        """The table row of ``swarmproof explore --list`` and docs."""
        return {"name": self.name, "kind": self.kind, "reads": list(self.reads),
                "blind_spots": self.blind_spots, "cites": self.cites, "needs": list(self.needs)}


_REGISTRY: dict[str, Property] = {}


def register_property(prop: Property, *, replace: bool = False) -> Property:
    """Add ``prop`` to the registry (a new name goes last); returns it.

    A name already registered is refused unless ``replace=True`` (a
    re-imported user module registers the same property again: that is
    allowed when it is the same check function's qualified name).
    """
    if not isinstance(prop, Property):
        raise UsageError(f"property={prop!r} is not a Property", fix="build one with Property(name, kind, check)")
    old = _REGISTRY.get(prop.name)
    if old is not None and not replace:
        same = (getattr(old.check, "__module__", None), getattr(old.check, "__qualname__", None)) == \
               (getattr(prop.check, "__module__", None), getattr(prop.check, "__qualname__", None))
        if not same:
            raise UsageError(f"property name={prop.name!r} is registered already",
                             fix="choose another name, or pass replace=True")
    _REGISTRY[prop.name] = prop
    return prop


def unregister_property(name: str) -> None:
    """Remove a user's property (tests; a built-in one can be removed too, at your own risk)."""
    _REGISTRY.pop(name, None)


def property_check(name: str, kind: str, *, reads=(), blind_spots: str = "", cites: str = "", **extra):
    """Decorator: register ``check(trace, context)`` as property ``name``.

    >>> @property_check("few_robots", "safety", reads=("ids",), cites="example")
    ... def _few(trace, ctx):
    ...     bad = trace.n > 100
    ...     return InvariantResult("few_robots", "violated" if bad else "held", "example",
    ...                            {"n": trace.n} if bad else None, f"{trace.n} robots")
    >>> get_property("few_robots").kind
    'safety'
    >>> unregister_property("few_robots")
    """
    def deco(fn):
        register_property(Property(name, kind, fn, tuple(reads), blind_spots, cites, **extra))
        return fn
    return deco


def property_names(*, own: bool = True) -> list[str]:
    """Registered names, in registration order (``own=False``: without the algorithms' own
    properties, which apply only to the algorithms that declare them)."""
    return [n for n, p in _REGISTRY.items() if own or not p.own]


def _declared_properties(algorithm) -> tuple:
    names = getattr(algorithm, "properties", None) or ()
    return (names,) if isinstance(names, str) else tuple(names)


def own_properties_of(algorithm) -> tuple[str, ...]:
    """The names of ``algorithm``'s own properties: its class attribute ``properties`` (each a
    registered property with ``own=True``, e.g. ``tree_link_cases``), else ``()``.
    A name that is not registered, or not an own property, is a usage error naming the algorithm.

    >>> own_properties_of(type("A", (), {"name": "mine"})())
    ()
    >>> own_properties_of(type("B", (), {"name": "mine", "properties": ("collision",)})())
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: properties entry='collision' of algorithm='mine' is not an own property (every algorithm gets it); fix: list in properties only the algorithm's own properties (Property(..., own=True), registered by its package)
    """
    out = []
    for n in _declared_properties(algorithm):
        p = _REGISTRY.get(n) if isinstance(n, str) else None
        if p is None or not p.own:
            who = getattr(algorithm, "name", algorithm)
            why = "is not a registered property" if p is None else "is not an own property (every algorithm gets it)"
            raise UsageError(f"properties entry={n!r} of algorithm={who!r} {why}",
                             fix="list in properties only the algorithm's own properties (Property(..., own=True), "
                                 "registered by its package)")
        out.append(n)
    return tuple(out)


def properties() -> list[Property]:
    """Registered properties, in registration order."""
    return list(_REGISTRY.values())


def get_property(name) -> Property:
    """The property called ``name``, or given as ``module:name`` (the module is imported and must
    register it, or hold a :class:`Property` or a decorated check under that name)."""
    if isinstance(name, Property):
        return name
    if isinstance(name, str) and name in _REGISTRY:
        return _REGISTRY[name]
    if isinstance(name, str) and ":" in name:
        modname, _, attr = name.partition(":")
        import os
        import sys

        if os.getcwd() not in sys.path and "" not in sys.path:   # as pytest's rootdir: modules of the cwd
            sys.path.append(os.getcwd())
        try:
            mod = importlib.import_module(modname)
        except Exception as exc:  # noqa: BLE001 - a user's module: its error is the message
            raise UsageError(f"property={name!r}: module {modname!r} cannot be imported "
                             f"({type(exc).__name__}: {exc})",
                             fix="check the module name and that it is on the Python path") from None
        obj = getattr(mod, attr, None)
        if isinstance(obj, Property):
            return register_property(obj)
        if attr in _REGISTRY:
            return _REGISTRY[attr]
        raise UsageError(f"property={name!r}: {modname} has no Property {attr!r} and registers none of that name",
                         fix="define it with Property(...) or @property_check(name, kind)")
    own = [n for n, p in _REGISTRY.items() if p.own]
    raise UsageError(f"property={name!r} is not known{did_you_mean(name, property_names())}",
                     fix=f"use one of {property_names(own=False)!r}"
                         + (f", an algorithm's own property ({', '.join(own)})" if own else "")
                         + ", or module:name of a property you registered")


# ----------------------------------------------------------------------------
# the built-in properties (moved from the explorer's judge; messages unchanged)
# ----------------------------------------------------------------------------

def progress_values(trace, measure) -> list:
    """``measure(ids, poses, states)`` of the present robots at every recorded step of ``trace``.

    ``measure`` is an algorithm's ``progress_measure`` (the omniscient
    observer's goal measure, higher is closer to the goal); consecutive
    steps with the same poses and states reuse the previous value.
    """
    out: list = []
    prev = None
    for t in range(len(trace.poses)):      # recorded frames
        pres = trace.present_at(t)
        key = (trace.poses[t].tobytes(), pres.tobytes(), trace.states[t])
        if key != prev:
            value = float(measure(trace.ids[pres], trace.poses[t][pres],
                                  tuple(s for s, p in zip(trace.states[t], pres) if p)))
            prev = key
        out.append(value)
    return out


def _satisfaction(ctx: PropertyContext):
    """The target's verdict on the final configuration (a lattice: 001 Def. 2, as before)."""
    from swarmproof.models.satisfaction import DEFAULT_SAT_ANG_TOL, DEFAULT_SAT_POS_TOL, satisfies_lattice

    if getattr(ctx.target, "kind", "lattice") != "lattice":
        from .satisfaction import judged_robots

        target, ids, poses = judged_robots(ctx.algorithm, ctx.result, ctx.target, ctx.params)
        return target.satisfied(ids, poses, phi=ctx.phi,
                                    tol=getattr(ctx.algorithm, "satisfaction_tol", None))
    pos_tol, ang_tol = getattr(ctx.algorithm, "satisfaction_tol", (DEFAULT_SAT_POS_TOL, DEFAULT_SAT_ANG_TOL))
    return satisfies_lattice(ctx.result.final_ids, ctx.result.final_poses, ctx.target, ctx.phi,
                             pos_tol=pos_tol, ang_tol=ang_tol)


def _connectivity(trace, ctx):
    from .connectivity import judge_connectivity

    return judge_connectivity(trace, ctx.phi, ctx.algorithm)


def _tree_links(trace, ctx):
    from .connectivity import tree_link_mode_of, tree_links_survive

    return tree_links_survive(trace, ctx.phi, mode=tree_link_mode_of(ctx.algorithm, ctx.options))


def _connectivity_stream(algorithm, params, options):
    from .connectivity import connectivity_monitor

    return connectivity_monitor(algorithm, params.range)


def _tree_links_stream(algorithm, params, options):
    from .connectivity import TreeLinkMonitor, tree_link_mode_of

    return TreeLinkMonitor(float(params.range), mode=tree_link_mode_of(algorithm, options))


def collision_radius(params, options) -> float:
    """The disc radius the ``collision`` property uses: the ``radius`` option, else the run's
    ``params.extra["robot_radius"]`` (an algorithm's paper value, e.g. 004 Sec. V-A: r = 0.05 m,
    set by its ``default_params``), else :data:`DEFAULT_RADIUS`.

    >>> from swarmproof.reference_impl.protocol import Params
    >>> collision_radius(Params(range=1.0), {}), collision_radius(Params(range=1.0, extra={"robot_radius": 0.05}), {})
    (0.1, 0.05)
    >>> collision_radius(Params(range=1.0, extra={"robot_radius": 0.05}), {"radius": 0.2})
    0.2
    """
    options = dict(options or {})
    if "radius" in options:
        return float(options["radius"])
    extra = getattr(params, "extra", None) or {}
    return float(extra.get("robot_radius", DEFAULT_RADIUS))


def _collision_stream(algorithm, params, options):
    from .properties import CollisionMonitor

    return CollisionMonitor(collision_radius(params, options))


def _premises_stream(algorithm, params, options):
    from .premises import PremisesMonitor, premise_monitors_of

    # the run's params.extra, for monitors with memory across steps (the one-step windows carry none)
    return PremisesMonitor(premise_monitors_of(algorithm), params.range, params.v, params.dt,
                           meta={"params": {"extra": dict(getattr(params, "extra", None) or {})}})


def _deadlock_stream(algorithm, params, options):
    from .properties import DeadlockMonitor

    mon = DeadlockMonitor()
    # judged at the end, as _deadlock: the window and the goal are known only then
    mon.judge = lambda ctx: mon.result(int(ctx.options.get("deadlock_k", ctx.result.static_window)),
                                       _satisfaction(ctx).held)
    return mon


def _tree_links_closeness(r: InvariantResult):
    value = (r.detail or {}).get("longest_link_ratio")
    return None if value is None else float(value)


def _termination(trace, ctx):
    from .termination import judge_termination

    return judge_termination(trace, ctx.algorithm, ctx.params, ctx.result.status, max_steps=ctx.result.max_steps)


def _formation(trace, ctx):
    if ctx.result.status == "step_cap":
        return InvariantResult("formation", "inconclusive", "001 Thm. 13 / Def. 2", None,
                               f"step cap {ctx.result.max_steps} reached before the run ended")
    sat = _satisfaction(ctx)
    return InvariantResult("formation", sat.status, sat.cites, sat.witness, sat.message)


def _collision(trace, ctx):
    from .properties import collision

    return collision(trace, collision_radius(ctx.params, ctx.options))


def _deadlock(trace, ctx):
    from .properties import deadlock

    return deadlock(trace, int(ctx.options.get("deadlock_k", ctx.result.static_window)),
                    goal_reached=_satisfaction(ctx).held)


def _oscillation(trace, ctx):
    from .properties import oscillation

    options, algorithm = ctx.options, ctx.algorithm
    T = ctx.result.steps
    g = _satisfaction(ctx).held
    randomized = bool(getattr(algorithm, "randomized", False))
    window = options.get("progress_window")
    measure = getattr(algorithm, "progress_measure", None)
    progress = None
    if callable(measure) and (randomized or window is not None):
        window = int(DEFAULT_PROGRESS_WINDOW if window is None else window)
        progress = progress_values(trace, measure)
    chosen = (getattr(trace, "meta", None) or {}).get("choices") or {}
    return oscillation(trace, float(options.get("pos_tol", DEFAULT_POS_TOL)), goal_reached=lambda t: g and t == T,
                       randomized=randomized, progress=progress, window=window,
                       progress_eps=float(options.get("progress_eps", 1e-9)),
                       deterministic_from=int(chosen.get("deterministic_from", 0)))


def _oscillation_stream(algorithm, params, options):
    from .properties import OscillationMonitor

    options = dict(options or {})
    randomized = bool(getattr(algorithm, "randomized", False))
    window = options.get("progress_window")
    measure = getattr(algorithm, "progress_measure", None)
    use = callable(measure) and (randomized or window is not None)
    mon = OscillationMonitor(float(options.get("pos_tol", DEFAULT_POS_TOL)), randomized=randomized,
                             measure=measure if use else None,
                             window=int(DEFAULT_PROGRESS_WINDOW if window is None else window) if use else None,
                             progress_eps=float(options.get("progress_eps", 1e-9)))
    mon.judge = lambda ctx: mon.result(_satisfaction(ctx).held)
    return mon


def _oscillation_monitor(factory, options):
    """Deterministic algorithms: end the run at the first repeated global state (rule 1)."""
    if getattr(factory, "randomized", False):
        return None
    from .properties import CycleMonitor

    return CycleMonitor(float(dict(options or {}).get("pos_tol", DEFAULT_POS_TOL)))


def _invariants_monitor(factory, options):
    """End a run at the first step where one of the algorithm's invariants breaks (its class's
    ``invariants`` tuple; declared per instance, or none: no early stop)."""
    from .algorithm_invariants import InvariantsStop, invariants_of

    invs = getattr(factory, "invariants", None)
    if not isinstance(invs, (tuple, list)) or not invs:
        return None          # none, or declared per instance (a property: wang2020's depend on its params)
    return InvariantsStop(invariants_of(factory, (options or {}).get("invariants")))


def _premises(trace, ctx):
    from .premises import premise_monitors_of
    from .properties import premises

    return premises(trace, premise_monitors_of(ctx.algorithm), ctx.phi, ctx.params.v, ctx.params.dt)


def _invariants(trace, ctx):
    from .algorithm_invariants import check_invariants

    return check_invariants(trace, ctx.algorithm, ctx.options.get("invariants"))


def _invariants_stream(algorithm, params, options):
    from .algorithm_invariants import InvariantsMonitor, invariants_of

    return InvariantsMonitor(invariants_of(algorithm, dict(options or {}).get("invariants")))


#: What ``completion_sound`` judges (the statement; each algorithm's invariant cites its paper).
CITE_COMPLETION = ("the algorithm's own completion detection is sound: whenever a robot declares the formation "
                   "complete, it is formed (its completion_invariants)")
_COMPLETION = dict(name="completion_sound", cites=CITE_COMPLETION, declared="completion detection")


def _completion_sound(trace, ctx):
    from .algorithm_invariants import run_invariants

    return run_invariants(trace, tuple(getattr(ctx.algorithm, "completion_invariants", None) or ()), **_COMPLETION)


def _completion_stream(algorithm, params, options):
    from .algorithm_invariants import InvariantsMonitor

    return InvariantsMonitor(tuple(getattr(algorithm, "completion_invariants", None) or ()), **_COMPLETION)


def _no_crash(trace, ctx):
    crash = getattr(ctx.result, "crash", None)
    if crash is None:
        return InvariantResult("no_crash", "held", CITE_NO_CRASH, None,
                               f"the algorithm raised no exception in {ctx.result.steps} steps")
    who = "the algorithm" if crash["robot"] is None else f"robot {crash['robot']}'s controller"
    text = f"{crash['error']}: {crash['message']}" if crash["message"] else crash["error"]
    return InvariantResult("no_crash", "violated", CITE_NO_CRASH,
                           {k: crash[k] for k in ("step", "robot", "error", "message")},
                           f"{who} raised {text} in step {crash['step']}")


CITE_NO_CRASH = "swarmproof: the algorithm under test raises no exception (a crash is a finding)"

for _p in (
    Property("connectivity", "safety", _connectivity, ("poses", "presence", "range"),
             "judged at the end of every step: between two step ends the graph is not sampled",
             LEMMA_11, stream=_connectivity_stream, every_step=True, needs=("range_graph",)),
    Property("tree_links", "safety", _tree_links, ("states' parent", "poses", "range"),
             "only robots whose state names a 'parent'; not applicable to an algorithm that declares no "
             "parent (state_fields) or no range graph; a run where no link was ever checked is inconclusive",
             LEMMA_11, closeness=_tree_links_closeness, stream=_tree_links_stream, every_step=True,
             needs=("parent", "range_graph")),
    Property("termination", "liveness", _termination, ("run status", "poses", "algorithm's termination_bound"),
             "without a termination bound a run cut by the step cap is inconclusive, never held",
             THEOREM_13),
    Property("formation", "liveness", _formation, ("final poses", "ids", "target", "range"),
             "judges the final configuration only; a run cut by the step cap is inconclusive",
             "001 Thm. 13 / Def. 2"),
    Property("collision", "safety", _collision, ("poses between steps", "radius option or params robot_radius"),
             "robots are discs of the radius option; motion within a step is taken as straight",
             CITE_COLLISION, stream=_collision_stream, every_step=True),
    Property("deadlock", "liveness", _deadlock, ("poses", "states", "final poses", "target"),
             "a static window shorter than the run; a goal reached is never a deadlock",
             CITE_DEADLOCK, stream=_deadlock_stream, every_step=True),
    Property("oscillation", "liveness", _oscillation, ("poses", "states", "algorithm's progress_measure"),
             "states compared up to pos_tol; randomized algorithms only by a progress window",
             CITE_OSCILLATION,
             run_monitor=_oscillation_monitor, stream=_oscillation_stream, every_step=True),
    Property("premises", "safety", _premises, ("poses", "states", "range, v, dt"),
             "only the lemma premises the algorithm declares (premise_monitors)",
             CITE_PREMISES, stream=_premises_stream, every_step=True, needs=("premise_monitors",)),
    Property("invariants", "safety", _invariants, ("poses", "states", "the algorithm's invariants"),
             "only the invariants the algorithm declares (its invariants attribute), on its own state keys",
             "the algorithm's own runtime invariants (its invariants attribute)",
             run_monitor=_invariants_monitor, stream=_invariants_stream, every_step=True, needs=("invariants",)),
    Property("no_crash", "safety", _no_crash, ("exceptions the algorithm's code raised",),
             "exceptions only: a controller that loops forever is stopped by the time budget, not found",
             CITE_NO_CRASH),
    # no early-stop monitor: its runs are plain runs, shared with the properties explored before it
    Property("completion_sound", "safety", _completion_sound,
             ("poses", "states", "the algorithm's completion_invariants"),
             "only what the algorithm's completion invariants read of its states (when a robot declares, "
             "what 'formed' means); a run in which no robot declared completion is inconclusive (vacuous)",
             CITE_COMPLETION, stream=_completion_stream, every_step=True, needs=("completion",)),
):
    register_property(_p)
del _p
