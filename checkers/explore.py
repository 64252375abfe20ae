"""The Hypothesis-driven explorer: hunt counterexamples to a property (issue 6).

For every requested property, Hypothesis draws scenarios -- a connected
initial configuration built constructively, a periodic bundled lattice, the
robot IDs' order, the engine seed -- the engine runs them with a step cap,
and the property is judged on the trace.  A violation fails the Hypothesis
example, so Hypothesis shrinks it to a smaller scenario; the smallest
failing scenario seen becomes the counterexample (a
``swarmproof-counterexample/1`` file, :mod:`swarmproof.models.counterexample`).

Verdicts per property (DESIGN.md section 1 "Verdicts"):

* ``violated`` -- with the shrunk counterexample;
* ``held`` -- over the scenarios and steps explored (never "proved");
* ``inconclusive`` -- no scenario gave a judgment (budget spent before a run
  finished, or every run hit its step cap / was inconclusive).

A property the algorithm cannot give what it needs for (no range graph, no parent field: the
property's ``needs`` against the algorithm's declarations, :mod:`swarmproof.invariants.capabilities`)
is ``not_applicable``: no verdict, not explored, and no part of the exit code (which is 3 when
every property asked for is not applicable: nothing was checked).

Determinism: Hypothesis runs with ``@seed(seed)``, ``database=None``,
``derandomize=False`` and every setting given explicitly (so the "ci"
profile Hypothesis loads when ``CI`` is set changes nothing).  The same
``seed`` and ``max_examples`` give the same verdicts, counterexamples and
JSON as long as the time budget is not hit (the budget is wall-clock time;
the report says ``budget_hit``).  Shrinking is bounded: once the property's
share of the budget is spent the test function raises ``_BudgetSpent``,
Hypothesis ends at once, and the smallest failing scenario seen so far is
kept.

References
----------
000_3ad33c5b62f11d5f.txt (song2014), 001_7a4e517b856331bc.txt Sec. III (the
connected start, the robot model), Lemma 11, Thm. 13 (song2016).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence


from swarmproof.invariants.registry import (DEFAULT_POS_TOL, DEFAULT_PROGRESS_WINDOW, DEFAULT_RADIUS,
                                            progress_values)
from swarmproof.checkers.algorithm_spec import AlgorithmSpec, resolve_algorithm
from swarmproof.checkers.runs import build_params, cx_params
from swarmproof.checkers.watchdog import MAX_LIMIT_S, Overstayed, time_limit
from swarmproof.models.counterexample import Counterexample
from swarmproof.models.errors import UsageError
from swarmproof.models.hypothesis_seed import without_local_constants

__all__ = ["explore_properties", "PERIODIC_LATTICES", "ExploreReport", "PropertyVerdict", "Scenario",
           "explore", "judge", "run_and_judge", "run_scenario", "free_start_box"]

def explore_properties(algorithm=None) -> tuple[str, ...]:
    """The properties the explorer judges by default: every registered one, in
    registration order (:mod:`swarmproof.invariants.registry`; a user's own
    property joins once registered), but an algorithm's own properties (``own=True``, e.g.
    ``tree_link_cases``) only for the ``algorithm`` that declares them (its
    ``properties``), after the others.

    >>> explore_properties()[:2]
    ('connectivity', 'tree_links')
    """
    from swarmproof.invariants.registry import own_properties_of, property_names

    mine = () if algorithm is None else own_properties_of(algorithm)
    return tuple(property_names(own=False)) + tuple(mine)


#: The bundled periodic lattices (models/library.py table).
PERIODIC_LATTICES: tuple[str, ...] = ("square", "hexagon", "octagon-square", "triangle", "kagome",
                                      "honeycomb-rotating")

MIN_SEP_FRACTION = 0.25     # initial robots at least range/4 apart (as initial.random_connected)
#: The longest start link the scenarios draw, as a fraction of the range: just short of phi
#: (neighbors are strictly closer than phi, 001 Sec. III), with room for the 1e-12 rounding of
#: the coordinates.  Links in the last part of the range are the ones the bounded range
#: (001 Lemma 7) and NCLB (Sec. V-C) work hardest to keep (docs/decisions.md).
MAX_LINK_FRACTION = 1.0 - 1e-9


@dataclass(frozen=True)
class Scenario:
    """One drawn scenario (everything a run needs besides the algorithm)."""

    lattice: str
    ids: tuple
    poses: tuple          # ((x, y, theta), ...) radians
    seed: int
    faults: Any = None    # a drawn FaultModel (data-driven hooks only) or None
    v: float | None = None  # a drawn speed (explore(speeds=...)), None: the run's params decide
    #: drawn algorithm parameters (``(key, value)`` pairs for ``Params.extra``) from the algorithm's
    #: ``explore_extra(draw, n)``: 003's failures and positioning errors
    extra: tuple = ()

    @property
    def n(self) -> int:
        return len(self.ids)


@dataclass
class PropertyVerdict:
    """The explorer's verdict on one property."""

    name: str
    status: str
    scenarios: int = 0
    conclusive: int = 0
    steps: int = 0
    capped: int = 0
    seconds: float = 0.0
    budget_hit: bool = False
    counterexample: Counterexample | None = None
    counterexample_path: str | None = None
    message: str = ""
    #: Wall and CPU seconds from the property's start to its first failing scenario (before
    #: shrinking), that scenario's robot count, and how many scenarios ran until then
    #: (None while nothing failed).  Not in :meth:`as_dict`: times differ from run to run.
    first_failure_seconds: float | None = None
    first_failure_cpu: float | None = None
    first_failure_robots: int | None = None
    first_failure_scenarios: int | None = None
    #: ``premises`` only: each lemma premise monitor's outcome over the judged scenarios,
    #: ``{monitor: {"held": n, "violated": n, "vacuous": n, "inconclusive": n}}`` (issue 32: verify
    #: has a row per monitor); None for other properties.
    monitors: dict | None = None

    def as_dict(self) -> dict:
        out = {"status": self.status, "scenarios": self.scenarios, "conclusive": self.conclusive,
               "steps": self.steps, "capped": self.capped, "budget_hit": self.budget_hit,
               "message": self.message,
               "counterexample": self.counterexample_path,
               "violation": None if self.counterexample is None else self.counterexample.violation,
               "robots": None if self.counterexample is None else len(self.counterexample.robots)}
        if self.monitors is not None:
            out["monitors"] = {m: dict(c) for m, c in self.monitors.items()}
        return out


@dataclass
class ExploreReport:
    """What :func:`explore` returns."""

    algorithm: str
    seed: int
    max_examples: int
    robots: tuple
    lattices: tuple
    kept_assumptions: list
    broken_assumptions: list
    properties: dict = field(default_factory=dict)
    #: Property -> where the paper / the class claims it, None when not claimed.
    claims: dict = field(default_factory=dict)
    #: What counterexample files name: the registry name or "module:qualname".
    algorithm_ref: str = ""
    #: Proof-suite lemmas whose premises the algorithm's premise monitors check.
    premise_lemmas: list = field(default_factory=list)
    #: The speeds scenarios drew ``v`` from (``explore(speeds=...)``), None: fixed parameters.
    speeds: tuple | None = None
    #: Warnings (a user's lattice that fails check-lattice at its range), in order.
    warnings: list = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        from swarmproof.models.verdict import EXIT_INCONCLUSIVE, EXIT_OK, EXIT_VIOLATED

        st = [v.status for v in self.properties.values() if v.status != "not_applicable"]
        if "violated" in st:
            return EXIT_VIOLATED
        if "inconclusive" in st or (self.properties and not st):
            return EXIT_INCONCLUSIVE     # every property asked for is not applicable: nothing was checked
        return EXIT_OK

    def assert_held(self) -> "ExploreReport":
        """Raise ``AssertionError`` unless every property held (a test helper).

        The message carries each violated property's counterexample as
        readable steps, or why a property is inconclusive.
        """
        __tracebackhide__ = True   # pytest shows the counterexample, not swarmproof's source
        bad = [(k, v) for k, v in self.properties.items() if v.status not in ("held", "not_applicable")]
        if bad:
            lines = [f"{self.algorithm}: {len(bad)} of {len(self.properties)} properties did not hold "
                     f"(seed {self.seed})"]
            for name, v in bad:
                lines.append(f"{name}: {v.status}: {v.message}")
                if v.counterexample is not None:
                    lines += ["  " + s for s in v.counterexample.format_steps()]
                    if v.counterexample_path:
                        lines.append(f"  replay: swarmproof replay {v.counterexample_path}")
            raise AssertionError("\n".join(lines))
        return self

    def as_dict(self) -> dict:
        return {"algorithm": self.algorithm, "seed": self.seed, "max_examples": self.max_examples,
                "robots": list(self.robots), "lattices": list(self.lattices),
                "kept_assumptions": list(self.kept_assumptions),
                "broken_assumptions": list(self.broken_assumptions),
                "properties": {k: {**v.as_dict(), "claim": self.claims.get(k)}
                               for k, v in self.properties.items()},
                "algorithm_ref": self.algorithm_ref or self.algorithm,
                "premise_lemmas": list(self.premise_lemmas),
                "speeds": None if self.speeds is None else list(self.speeds),
                **({"warnings": list(self.warnings)} if self.warnings else {}),
                "exit_code": self.exit_code}


# ----------------------------------------------------------------------------
# running and judging one scenario (shared with replay)
# ----------------------------------------------------------------------------

def run_scenario(algorithm_name, lattice, ids, poses, params, *, seed: int, max_steps=None,
                 allow_violations: bool = False, faults=None, stop_when=None, chooser=None):
    """Run the engine on one scenario; returns ``(algorithm, SimulationResult)``.

    ``algorithm_name``: anything :func:`resolve_algorithm` accepts, or an :class:`AlgorithmSpec`.
    ``stop_when``: a run-time monitor for ``simulate`` (e.g. a :class:`CycleMonitor`).
    ``chooser``: the engine's decisions (an exhaustive counterexample's recorded choices).
    """
    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.engine import simulate

    spec = algorithm_name if isinstance(algorithm_name, AlgorithmSpec) else resolve_algorithm(algorithm_name)
    initial = InitialConfiguration(list(ids), [list(p) for p in poses])
    algorithm = spec.build(n_robots=initial.n)
    result = simulate(algorithm, lattice, initial, params, seed=seed, max_steps=max_steps,
                      allow_violations=allow_violations, faults=faults, stop_when=stop_when, chooser=chooser)
    return algorithm, result


def run_and_judge(algorithm_name, prop: str, lattice, ids, poses, params, *, seed: int, max_steps=None,
                  allow_violations: bool = False, faults=None, options: Mapping[str, Any] | None = None,
                  early_stop: bool = True):
    """Run one scenario and judge ``prop``; returns ``(algorithm, SimulationResult, InvariantResult)``.

    With ``early_stop`` (the explorer's default) an ``oscillation`` run of a
    deterministic algorithm carries a :class:`~swarmproof.invariants.properties.CycleMonitor`:
    the run ends at the first repeated global state (oscillation's rule 1)
    instead of at the step cap, and the shortened trace is judged.  Rule 1
    then finds the same first cycle, at the same step, as on the whole run,
    so the verdict and its message are the same; when the shortened trace is
    *not* judged violated (the goal held at that step, or another rule would
    have to decide) the scenario is run again to its end without the monitor
    and judged as usual.  An ``invariants`` run carries an
    :class:`~swarmproof.invariants.algorithm_invariants.InvariantsStop` and ends at the first
    step where an invariant breaks (the same judgment as the whole run).  Replay always runs to
    the end.
    """
    spec = algorithm_name if isinstance(algorithm_name, AlgorithmSpec) else resolve_algorithm(algorithm_name)
    from swarmproof.invariants.registry import get_property

    rule = get_property(prop)
    monitor = None
    if early_stop and rule.run_monitor is not None:
        monitor = rule.run_monitor(spec.factory, dict(options or {}))
        if monitor is not None and callable(getattr(monitor, "start", None)):
            monitor.start(list(ids))          # a monitor that needs the robots' IDs (invariants)
    algo, result = run_scenario(spec, lattice, ids, poses, params, seed=seed, max_steps=max_steps,
                                allow_violations=allow_violations, faults=faults, stop_when=monitor)
    r = judge(prop, algo, lattice, params, result, options)
    if result.status == "stopped" and not r.violated:
        algo, result = run_scenario(spec, lattice, ids, poses, params, seed=seed, max_steps=max_steps,
                                    allow_violations=allow_violations, faults=faults)
        r = judge(prop, algo, lattice, params, result, options)
    return algo, result, r


def judge(prop: str, algorithm, lattice, params, result, options: Mapping[str, Any] | None = None):
    """Judge property ``prop`` on a finished run: the registered property's ``check``
    (:mod:`swarmproof.invariants.registry`).

    ``prop`` is a registered name or ``module:name`` of a user's property.
    Returns an :class:`~swarmproof.invariants.result.InvariantResult`;
    ``termination`` and ``formation`` are inconclusive when the run hit its
    step cap (without a bound that decides it).
    """
    from swarmproof.invariants.registry import PropertyContext, get_property

    rule = get_property(prop)
    ctx = PropertyContext(algorithm, lattice, params, result, dict(options or {}))
    return rule.judge(result.trace, ctx)


def closeness(prop: str, result) -> float | None:
    """How near a run that held came to violating ``prop`` (higher is nearer), or None.

    The explorer hands it to Hypothesis's ``target()``, whose optimisation
    passes (after the first 200 valid scenarios, interleaved with
    generation) mutate the scenarios that came nearest.  Only ``tree_links``
    has a score: the longest tree link after its step, as a fraction of phi
    (1 breaks the link; ``detail["longest_link_ratio"]`` of
    :func:`~swarmproof.invariants.connectivity.tree_links_survive`).

    >>> from swarmproof.invariants.result import InvariantResult
    >>> closeness("tree_links", InvariantResult("tree_links", "held", "", detail={"longest_link_ratio": 0.9}))
    0.9
    >>> closeness("formation", InvariantResult("formation", "held", "")) is None
    True
    """
    from swarmproof.invariants.registry import get_property

    fn = get_property(prop).closeness
    return None if fn is None else fn(result)


# ----------------------------------------------------------------------------
# the scenario strategy
# ----------------------------------------------------------------------------

#: Fault kinds the explorer can draw (all replayable: data-driven hooks, or draws from the
#: engine's fault generator, which the run's seed fixes).
FAULT_KINDS: tuple[str, ...] = ("schedule", "crashes", "drops", "additions", "noise", "delays", "latency")
#: Largest drawn message delay (steps) of the ``delays`` fault kind.
MAX_DRAWN_DELAY = 5
#: Largest drawn message delay (steps) of the ``latency`` fault kind: long enough to outlast a
#: protocol's timeouts (004's handshake: 3 Delta t = 12 ticks by default).
MAX_DRAWN_LATENCY = 40

#: Largest drawn sensing-noise standard deviations: (x, y) as a fraction of the range phi, theta in radians.
MAX_NOISE_XY_FRACTION = 0.04
MAX_NOISE_THETA = 0.05


def draw_fault_model(draw, ids: Sequence[int], kinds: Sequence[str], *, poses: Sequence = (),
                     phi: float = 1.0):
    """Draw a replayable FaultModel of the given kinds for robots ``ids`` (inside a composite strategy).

    * ``schedule``: for each of the first 1..20 steps, the IDs that act
      (:class:`TableSchedule`; later steps: everybody acts);
    * ``crashes``: one robot crashes at a step in 0..60;
    * ``drops``: up to 8 lost deliveries ``(step 0..40, sender, receiver)`` (:class:`DropSet`);
    * ``additions``: 1 or 2 robots join, each at a step in 0..60, with the next unused IDs
      (``n``, ``n + 1``: higher than every starting robot), placed at a drawn distance in
      ``[phi/4, 0.95 phi]`` and angle from the *starting* position of a drawn robot (which
      may have moved away by then: a newcomer can join out of range), heading drawn;
    * ``noise``: Gaussian sensing noise, standard deviations drawn in
      ``[0, 0.04 phi]`` for the sensed (x, y) and ``[0, 0.05]`` rad for theta
      (``FaultModel.noise_std``; the draws come from the engine's fault generator,
      seeded by the run's seed, so a replay is exact);
    * ``delays``: every delivery arrives 0..K steps late, K drawn in 1..5
      (``FaultModel.message_delay``), in order or not (``message_reorder`` drawn); the
      delays come from the engine's fault generator (exact replay);
    * ``latency``: every delivery (broadcasts and point-to-point exchanges) arrives 0..K steps
      late, K drawn in 6..40: latencies that outlast timeouts (a link whose latency is not
      negligible, 004 Sec. II-A e); in order unless ``delays`` is drawn too (its reordering),
      and then K is the latency's.

    ``poses`` are the starting poses of the robots ``ids`` (same order), ``phi``
    the range; both are needed for ``additions`` only.
    """
    from hypothesis import strategies as st

    from swarmproof.reference_impl.engine import DropSet, FaultModel, TableSchedule

    kw: dict[str, Any] = {}
    ids = [int(i) for i in ids]
    if "schedule" in kinds:
        k = draw(st.integers(1, 20))
        kw["schedule"] = TableSchedule({t: tuple(sorted(draw(st.lists(st.sampled_from(ids), unique=True))))
                                        for t in range(k)})
    if "crashes" in kinds:
        kw["crashes"] = {draw(st.integers(0, 60)): [draw(st.sampled_from(ids))]}
    if "drops" in kinds and len(ids) >= 2:
        triples = draw(st.lists(st.tuples(st.integers(0, 40), st.sampled_from(ids), st.sampled_from(ids))
                                .filter(lambda x: x[1] != x[2]), min_size=1, max_size=8))
        kw["drop_message"] = DropSet(frozenset(triples))
    if "additions" in kinds:
        adds: dict[int, list] = {}
        next_id = max(ids) + 1
        for k in range(draw(st.integers(1, 2))):
            step = draw(st.integers(0, 60))
            anchor = draw(st.integers(0, len(ids) - 1))
            dist = draw(st.floats(MIN_SEP_FRACTION * phi, 0.95 * phi))
            ang = draw(st.floats(-math.pi, math.pi))
            head = draw(st.floats(-math.pi, math.pi))
            x0, y0 = float(poses[anchor][0]), float(poses[anchor][1])
            adds.setdefault(step, []).append((next_id + k, [x0 + dist * math.cos(ang),
                                                            y0 + dist * math.sin(ang), head]))
        kw["additions"] = adds
    if "noise" in kinds:
        kw["noise_std"] = (draw(st.floats(0.0, MAX_NOISE_XY_FRACTION * phi)),
                           draw(st.floats(0.0, MAX_NOISE_THETA)))
    if "delays" in kinds:
        kw["message_delay"] = draw(st.integers(1, MAX_DRAWN_DELAY))
        kw["message_reorder"] = draw(st.booleans())
    if "latency" in kinds:
        kw["message_delay"] = draw(st.integers(MAX_DRAWN_DELAY + 1, MAX_DRAWN_LATENCY))
    return FaultModel(**kw) if kw else None


def _fault_probe(kinds: Sequence[str]):
    """A FaultModel with every drawable fault of ``kinds`` switched on (to name the assumptions broken)."""
    from swarmproof.reference_impl.engine import DropSet, FaultModel, TableSchedule

    return FaultModel(schedule=TableSchedule({0: ()}) if "schedule" in kinds else None,
                      crashes={0: [0]} if "crashes" in kinds else {},
                      drop_message=DropSet(frozenset({(0, 0, 1)})) if "drops" in kinds else None,
                      additions={0: [(0, [0.0, 0.0, 0.0])]} if "additions" in kinds else {},
                      noise_std=(0.01, 0.01) if "noise" in kinds else (0.0, 0.0),
                      message_delay=1 if ("delays" in kinds or "latency" in kinds) else 0,
                      message_reorder="delays" in kinds)


#: Angle steps tried, in order, when a drawn placement lands closer than range/4 to a robot
#: already placed (the construction turns the drawn angle by multiples of 2 pi / 12).
PLACEMENT_TURNS = 12


def place_robot(pts: Sequence[tuple], parent: int, dist: float, ang: float, min_sep: float):
    """Where a robot placed ``dist`` from ``pts[parent]`` at angle ``ang`` goes, or None.

    The first of ``ang``, ``ang + 2 pi/12``, ``ang + 4 pi/12``, ... whose point
    is at least ``min_sep`` from every point of ``pts``; None when all twelve
    are too close.  (Turning instead of rejecting keeps almost every draw
    valid, the smallest draw included, which Hypothesis tries first.)

    >>> place_robot([(0.0, 0.0)], 0, 1.0, 0.0, 0.3)
    (1.0, 0.0)
    >>> x, y = place_robot([(0.0, 0.0), (1.0, 0.0)], 0, 1.0, 0.0, 0.3)
    >>> round(x, 6), round(y, 6)
    (0.866025, 0.5)
    """
    px, py = pts[parent]
    for k in range(PLACEMENT_TURNS):
        a = ang + 2.0 * math.pi * k / PLACEMENT_TURNS
        # rounded to 1e-12 so that turned placements print as (0, 1), not (6.12323e-17, 1)
        x, y = round(px + dist * math.cos(a), 12), round(py + dist * math.sin(a), 12)
        if all(math.hypot(x - qx, y - qy) >= min_sep for qx, qy in pts):
            return (x, y)
    return None


#: Free starts (an algorithm with its own ``initial``): robots stand on distinct cells of a square box
#: of about ``FREE_START_CELLS_PER_ROBOT`` cells per robot around the goals (docs/decisions.md).
FREE_START_CELLS_PER_ROBOT = 4


def free_start_box(n: int, goals=None) -> list:
    """The cells a free start of ``n`` grid robots is drawn from: a square of side
    ``ceil(sqrt(4 n))`` cells centred on the goal cells' centre of mass (on (0, 0) without goals),
    in row order from its lower left corner (Hypothesis's smallest draws are its first cells).

    >>> free_start_box(4)[:3], len(free_start_box(4))
    ([(-1, -1), (0, -1), (1, -1)], 16)
    >>> min(free_start_box(2, {(10, 10), (11, 10)})), max(free_start_box(2, {(10, 10), (11, 10)}))
    ((10, 9), (12, 11))
    """
    side = max(2, int(math.ceil(math.sqrt(FREE_START_CELLS_PER_ROBOT * n))))
    if goals:
        cx = sum(c[0] for c in goals) / len(goals)
        cy = sum(c[1] for c in goals) / len(goals)
    else:
        cx = cy = 0.0
    ox = int(math.floor(cx - (side - 1) / 2.0 + 0.5))
    oy = int(math.floor(cy - (side - 1) / 2.0 + 0.5))
    return [(ox + i, oy + j) for j in range(side) for i in range(side)]


def _goal_cells(targets, label: str, n: int, scale_target, grid_spacing: float) -> list | None:
    """The grid cells of the goal set a free start is drawn around: target ``label`` (scaled to
    ``n`` robots when the algorithm scales it) in cells of ``grid_spacing``; None without targets
    or for a target without cells."""
    if targets is None or label not in targets:
        return None
    tgt = targets[label]
    if scale_target is not None:
        tgt = scale_target(tgt, n)
    cells_of = getattr(tgt, "cells", None)
    if cells_of is None:
        return None
    origin = getattr(tgt, "origin", (0.0, 0.0))
    oi, oj = int(round(origin[0] / grid_spacing)), int(round(origin[1] / grid_spacing))
    return [(oi + i, oj + j) for i, j in cells_of]


def _draw_free_cells(draw, n: int, goals) -> list:
    """``n`` distinct cells drawn from :func:`free_start_box` around ``goals`` (not necessarily connected)."""
    from hypothesis import strategies as st

    box = free_start_box(n, goals)
    picks = draw(st.lists(st.integers(0, len(box) - 1), unique=True, min_size=n, max_size=n))
    return [box[k] for k in picks]


def _draw_connected_cells(draw, lo: int, hi: int, phi: float, grid_spacing: float) -> list:
    """``lo..hi`` distinct cells, connected at range ``phi``: cell (0, 0), then each further one a
    drawn offset ``(parent, dx, dy)`` within the range from an earlier cell."""
    from hypothesis import assume
    from hypothesis import strategies as st

    reach = max(1, int(math.floor(MAX_LINK_FRACTION * phi / grid_spacing)))
    offs = st.integers(-reach, reach)
    cells_drawn = draw(st.lists(st.tuples(st.integers(0, max(hi - 2, 0)), offs, offs),
                                min_size=lo - 1, max_size=hi - 1))
    cells = [(0, 0)]
    for k, (parent, dx, dy) in enumerate(cells_drawn, start=1):
        assume((dx, dy) != (0, 0) and math.hypot(dx, dy) * grid_spacing <= MAX_LINK_FRACTION * phi)
        c = (cells[parent % k][0] + dx, cells[parent % k][1] + dy)
        assume(c not in cells)
        cells.append(c)
    return cells


def _draw_connected_points(draw, lo: int, hi: int, phi: float) -> tuple[list, list]:
    """``lo..hi`` points connected at range ``phi`` and their headings (the construction of
    :func:`scenario_strategy`): robot 0 at the origin, then each further one ``(parent,
    distance, angle, heading)`` from an earlier robot, placed by :func:`place_robot`."""
    from hypothesis import assume
    from hypothesis import strategies as st

    angle = st.floats(-math.pi, math.pi)
    min_sep = MIN_SEP_FRACTION * phi
    # the distance is drawn as "longest minus a slack" so that Hypothesis's simplest
    # draws, tried first and shrunk toward, are the most stretched links
    longest = MAX_LINK_FRACTION * phi
    dist = st.floats(0.0, longest - min_sep).map(lambda slack: longest - slack)
    placements = draw(st.lists(st.tuples(st.integers(0, max(hi - 2, 0)), dist, angle, angle),
                               min_size=lo - 1, max_size=hi - 1))
    pts = [(0.0, 0.0)]
    heads = [draw(angle)]
    for k, (parent, d, ang, head) in enumerate(placements, start=1):
        p = place_robot(pts, parent % k, d, ang, min_sep)
        assume(p is not None)
        pts.append(p)
        heads.append(head)
    return pts, heads


def _whole_teams(n: int, k_mult: int) -> int:
    """How many of ``n`` robots placed in order to keep: a whole multiple of ``k_mult`` (a
    team below ``k_mult`` is redrawn); all of them when ``k_mult`` is 1."""
    from hypothesis import assume

    if k_mult <= 1:
        return n
    keep = n - n % k_mult
    assume(keep >= k_mult)
    return keep


def _draw_ids_seed_faults(draw, poses: tuple, fault_kinds: Sequence[str], phi: float):
    """The robots' IDs (a drawn permutation of ``0..n-1``), the engine seed and the faults of
    ``fault_kinds`` (:func:`draw_fault_model`), drawn in that order."""
    from hypothesis import strategies as st

    perm = draw(st.permutations(list(range(len(poses)))))
    seed = draw(st.integers(0, 1000))
    faults = draw_fault_model(draw, perm, fault_kinds, poses=poses, phi=phi) if fault_kinds else None
    return tuple(int(i) for i in perm), seed, faults


def scenario_strategy(robots: tuple[int, int], lattices: Sequence[str], phi_of: Mapping[str, float],
                      fault_kinds: Sequence[str] = (), speeds: Sequence[float] | None = None,
                      grid_spacing: float | None = None, team_multiple: Mapping[str, int] | None = None,
                      targets: Mapping[str, Any] | None = None, scale_target: Callable | None = None,
                      free_starts: bool = False, algorithm=None):
    """A Hypothesis strategy of connected :class:`Scenario` objects.

    Robot 0 of the construction sits at the origin with a drawn heading;
    every further robot is one element of a drawn list ``(parent, distance,
    angle, heading)``: it is placed at the distance, drawn in
    ``[range/4, (1 - 1e-9) range]`` (:data:`MAX_LINK_FRACTION`) and shrinking
    toward the long end, from an earlier robot (``parent`` modulo the robots
    placed so far), so the start is connected (001 Sec. III).  A
    placement closer than ``range/4`` to a robot already placed is turned by
    multiples of 30 degrees (:func:`place_robot`) and rejected only when no
    turn fits.  The IDs are a drawn permutation of ``0..n-1``.

    Because each robot after the first is one list element, Hypothesis's
    shrinker drops a robot in one step (deleting the element), and the
    smallest scenario, tried first, is a valid ``robots[0]``-robot start
    with every drawn link just short of the range.
    ``speeds``: when given, each scenario also draws its ``v`` from them
    (``sampled_from``: shrinking goes toward the first).
    ``team_multiple``: target label -> k when the algorithm's paper runs whole multiples of k
    robots (an algorithm's ``team_multiple(target)``; 002 Sec. V-A places ``|F_d|`` robots, a
    whole number of copies of B): the last drawn robots are dropped down to a multiple of k
    (robots are placed in order, so the start stays connected), and a team below k is redrawn.
    ``grid_spacing``: for ``motion="grid"`` algorithms, robots stand on distinct
    cells; each further robot is ``(parent, dx, dy)``, a cell offset within
    the range of an earlier robot (the start is connected), heading 0; ``team_multiple``
    drops the last ones down to a multiple of k here too.
    ``free_starts`` (grid only; an algorithm whose paper starts from any distinct cells, e.g. 004
    Sec. V-A): n is drawn from ``robots`` and the n robots stand on distinct cells drawn from
    :func:`free_start_box` around the goals (not necessarily connected).
    ``scale_target`` (with ``targets``, label -> target): the algorithm's
    ``scale_target(target, n)``; the scenario's robots run toward the target scaled to n (004:
    |Q| = |A|), and the free-start box is centred on that goal set.
    ``algorithm``: its class may draw scenarios of its own kind: ``explore_start(draw, lo, hi,
    phi)`` returns start poses (or None for the construction above: 003's symmetric and
    near-symmetric starts, where leader ties really happen), and ``explore_extra(draw, n)``
    returns a dict of parameters for ``Params.extra`` (003's failures at any step), kept in the
    scenario and in its counterexample file, so a replay runs them again.

    A scenario draws, in this order: the target, the speed, the start (:func:`_draw_free_cells`,
    :func:`_draw_connected_cells`, the algorithm's ``explore_start`` or
    :func:`_draw_connected_points`), the IDs, the engine seed, the faults, then the algorithm's
    ``explore_extra``.  Hypothesis replays and shrinks by that order, so it is kept as it is:
    tests pin the counterexamples it finds.
    """
    from hypothesis import strategies as st

    lo, hi = robots

    @st.composite
    def build(draw):
        lat = draw(st.sampled_from(list(lattices)))
        phi = phi_of[lat]
        v = None if not speeds else float(draw(st.sampled_from(list(speeds))))
        k_mult = (team_multiple or {}).get(lat, 1)
        if grid_spacing is not None:
            if free_starts:
                n = draw(st.integers(lo, hi))
                cells = _draw_free_cells(draw, n, _goal_cells(targets, lat, n, scale_target, grid_spacing))
            else:
                cells = _draw_connected_cells(draw, lo, hi, phi, grid_spacing)
                cells = cells[:_whole_teams(len(cells), k_mult)]
            poses = tuple((cx * grid_spacing, cy * grid_spacing, 0.0) for cx, cy in cells)
            ids, seed, faults = _draw_ids_seed_faults(draw, poses, fault_kinds, phi)
            return Scenario(lat, ids, poses, seed, faults, v)
        own_start = getattr(algorithm, "explore_start", None)
        drawn = own_start(draw, lo, hi, phi) if callable(own_start) else None
        if drawn is not None:
            pts, heads = [(float(x), float(y)) for x, y, _ in drawn], [float(h) for _, _, h in drawn]
        else:
            pts, heads = _draw_connected_points(draw, lo, hi, phi)
        keep = _whole_teams(len(pts), k_mult)
        poses = tuple((float(x), float(y), float(h)) for (x, y), h in zip(pts[:keep], heads[:keep]))
        ids, seed, faults = _draw_ids_seed_faults(draw, poses, fault_kinds, phi)
        own_extra = getattr(algorithm, "explore_extra", None)
        extra = tuple(sorted(own_extra(draw, len(poses)).items())) if callable(own_extra) else ()
        return Scenario(lat, ids, poses, seed, faults, v, extra)

    return build()


# ----------------------------------------------------------------------------
# explore
# ----------------------------------------------------------------------------

#: Scenario runs Hypothesis may spend shrinking a property's first failure before the search
#: stops with the smallest counterexample found so far.  A count, so that the counterexample
#: depends on the seed and the example counts only: Hypothesis's own stop, five minutes of wall
#: clock (``hypothesis.internal.conjecture.engine.MAX_SHRINKING_SECONDS``), gave another
#: counterexample on a loaded machine, so it is lifted while exploring
#: (:func:`_count_bounded_shrinking`).  Hypothesis's count of successful shrinks (500) still holds.
MAX_SHRINK_RUNS = 1000


class _BudgetSpent(BaseException):
    """Raised inside the Hypothesis test once a property's share of the budget is spent.

    A ``BaseException`` (not an ``Exception``), so Hypothesis does not take it
    for a failure to shrink but lets it end the run at once -- generation or
    shrinking -- instead of generating empty examples up to ``max_examples``.
    """


def _check_speeds(speeds, params) -> tuple | None:
    """``speeds`` as a tuple of floats; UsageError naming the bad value."""
    if speeds is None:
        return None
    if isinstance(speeds, (str, bytes)) or not hasattr(speeds, "__iter__"):
        raise UsageError(f"speeds={speeds!r} must be a sequence of speeds", fix="e.g. speeds=[0.05, 0.4, 0.8]")
    out = []
    for s in speeds:
        if isinstance(s, bool) or not isinstance(s, (int, float)) or not math.isfinite(s) or s <= 0:
            raise UsageError(f"speeds contains {s!r}: every speed must be a finite number > 0 (robots that "
                             "cannot move make a run meaningless)",
                             fix="e.g. speeds=[0.05, 0.4, 0.8]")
        out.append(float(s))
    if not out:
        raise UsageError("speeds=[] is empty", fix="give one or more speeds, or leave speeds out")
    if params.get("v") is not None:
        raise UsageError(f"speeds={out!r} and params v={params['v']!r} were both given",
                         fix="give one of them (speeds draws v per scenario)")
    return tuple(out)


@contextlib.contextmanager
def _count_bounded_shrinking():
    """Lift Hypothesis's wall-clock stop of shrinking while exploring: :data:`MAX_SHRINK_RUNS`
    bounds it by a count instead.  Hypothesis documents the constant as monkeypatchable ("for the
    rare users who need to keep on shrinking"); if it moves, exploration still works, only with
    Hypothesis's five-minute stop back."""
    try:
        from hypothesis.internal.conjecture import engine
        original = engine.MAX_SHRINKING_SECONDS
    except (ImportError, AttributeError):  # pragma: no cover - other Hypothesis versions
        yield
        return
    engine.MAX_SHRINKING_SECONDS = 10 ** 9
    try:
        yield
    finally:
        engine.MAX_SHRINKING_SECONDS = original


def _warn_user_lattice(target, strict: bool, warnings: list) -> None:
    from swarmproof.checkers.lattice_check import user_lattice_warning

    msg = user_lattice_warning(target)
    if msg is None:
        return
    if strict:
        raise UsageError(msg, fix="fix the lattice file, or drop --strict to explore it anyway")
    warnings.append(msg)


def _cx_target(label: str, target) -> dict | None:
    """What a counterexample file records of a target beyond its label: nothing for a bundled
    lattice (files as before), else the target's description (a user's lattice with its whole
    document), so the file replays without the original."""
    from swarmproof.models.targets import describe_target

    d = describe_target(target)
    return None if d == {"kind": "lattice", "name": label} else d


def _cx_lattice(label: str, target) -> str | None:
    return label if getattr(target, "kind", "lattice") == "lattice" else None


def _file_label(spec: AlgorithmSpec) -> str:
    """The algorithm's label made safe for a file name."""
    return _safe(spec.label)


def _safe(text: str) -> str:
    """``text`` made safe for a file name (a user's ``module:name`` property has a colon)."""
    import re

    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text)


#: The largest team the scenario strategy draws (:func:`scenario_strategy`), per kind of start:
#: Hypothesis draws each scenario from a bounded buffer of choices and rejects a start whose robots
#: collide (``assume``), so a larger team overruns the buffer or is rejected every time -- it then
#: reports ``Unsatisfiable`` after spending the budget.  Measured with Hypothesis 6.170 (5 examples,
#: seed 0, on a loaded 2-core machine): connected ``points`` 64 robots in 5 s, 80 in 28 s, 150 never;
#: connected grid ``cells`` (range 1.2, spacing 0.2) 20 in 5 s, 25 in 20 s, 50 never; ``free`` grid
#: starts (an algorithm with its own ``initial``, 004) 1000 in 9 s.  Larger teams are for
#: ``simulate`` (at most :data:`~swarmproof.checkers.runs.MAX_ROBOTS`) and campaigns' simulate cells.
EXPLORE_MAX_ROBOTS = {"points": 64, "cells": 20, "free": 1000}


def explore_start_kind(factory) -> str:
    """Which start :func:`scenario_strategy` draws for an algorithm class: ``"free"`` grid cells (grid
    motion and its own ``initial``, 004), connected grid ``"cells"`` (grid motion), else connected
    ``"points"`` (an algorithm's own ``explore_start`` falls back to them)."""
    if getattr(getattr(factory, "model", None), "motion", None) == "grid":
        return "free" if callable(getattr(factory, "initial", None)) else "cells"
    return "points"


def check_explore_robots(robots, algorithm=None) -> tuple[int, int]:
    """``robots`` ``(MIN, MAX)`` as ints, refused (:class:`UsageError` naming the cap and why) when
    the explorer cannot draw such teams: more than :data:`EXPLORE_MAX_ROBOTS` for the algorithm's kind
    of start, or more than the algorithm runs (its ``max_robots``,
    :func:`~swarmproof.reference_impl.engine.run.check_team_size`).  The one check of ``explore``,
    ``verify``'s exploration rows and campaigns' explore cells.

    >>> check_explore_robots((3, 8))
    (3, 8)
    >>> check_explore_robots((300, 300))
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: robots=300 is more than the explorer draws (at most 64 for connected starts: Hypothesis draws each scenario from a bounded buffer, which a larger start overruns); fix: explore at most 64 robots (e.g. --robots 3..64 on the command line, robots: [3, 64] in a campaign); simulate runs teams of up to 20000
    """
    from swarmproof.checkers.runs import MAX_ROBOTS
    from swarmproof.reference_impl.engine.run import check_team_size

    try:
        lo, hi = (int(robots[0]), int(robots[1]))
    except (TypeError, ValueError, IndexError):
        raise UsageError(f"robots={robots!r} must be a pair (MIN, MAX)") from None
    if not 1 <= lo <= hi:
        raise UsageError(f"robots={robots!r} must satisfy 1 <= MIN <= MAX", fix="e.g. robots=(3, 8)")
    start = explore_start_kind(algorithm)
    cap = EXPLORE_MAX_ROBOTS[start]
    if hi > cap:
        what = {"points": "connected starts", "cells": "connected grid starts", "free": "grid starts"}[start]
        raise UsageError(f"robots={hi} is more than the explorer draws (at most {cap} for {what}: Hypothesis "
                         "draws each scenario from a bounded buffer, which a larger start overruns)",
                         fix=f"explore at most {cap} robots (e.g. --robots {lo if lo <= cap else min(3, cap)}..{cap} on the "
                             f"command line, robots: [{lo if lo <= cap else min(3, cap)}, {cap}] in a campaign); simulate "
                             f"runs teams of up to {MAX_ROBOTS}")
    if algorithm is not None:
        check_team_size(algorithm, hi)
    return lo, hi


def _check_inputs(algorithm, properties, budget, max_examples, robots, seed, lattices, out_dir=None, strict=False):
    spec = resolve_algorithm(algorithm)
    from swarmproof.invariants.registry import get_property

    props = list(explore_properties(spec.factory)) if properties is None else list(properties)
    for p in props:
        get_property(p)  # unknown names fail here, listing the registered ones
    if len(set(props)) != len(props):
        raise UsageError(f"properties={props!r} names a property twice", fix="give each property once")
    if not props:
        raise UsageError("properties=[] is empty", fix=f"give one or more of {list(explore_properties(spec.factory))!r}")
    if budget is None:
        budget = math.inf   # no wall-clock limit: max_examples alone bounds the search (machine-independent)
    elif isinstance(budget, bool) or not (isinstance(budget, (int, float)) and math.isfinite(budget) and budget > 0):
        raise UsageError(f"budget={budget!r} must be a finite number of seconds > 0")
    elif budget > MAX_LIMIT_S:
        raise UsageError(f"budget={budget!r} is more than {MAX_LIMIT_S:g} s (about 115 days), the longest "
                         "limit the watchdog can arm", fix="give fewer seconds, or budget=None (--budget none) "
                         "to bound the search by max_examples alone")
    if isinstance(max_examples, bool) or not isinstance(max_examples, int) or max_examples < 1:
        raise UsageError(f"max_examples={max_examples!r} must be an integer >= 1")
    lo, hi = check_explore_robots(robots, spec.factory)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise UsageError(f"seed={seed!r} must be an integer >= 0")
    if lattices is None:
        lattices = getattr(spec.factory, "explore_targets", None)   # an algorithm's own default targets
    if out_dir is not None:
        from swarmproof.models.fileio import check_output_dir

        check_output_dir(out_dir, "out_dir")
    lats, loaded, warnings = _load_targets(lattices, strict, getattr(spec.factory, "default_range", None))
    return spec, props, float(budget), (lo, hi), lats, loaded, warnings


def _load_targets(lattices, strict: bool = False, default_range: float | None = None):
    """Labels and targets the scenarios draw from: bundled periodic lattices by default; else
    each item a bundled name, ``KIND:NAME``, a file (a user's lattice) or a target object."""
    from swarmproof.models import library
    from swarmproof.models.targets import resolve_target, target_kinds

    warnings: list = []
    items = tuple(PERIODIC_LATTICES if lattices is None else lattices)
    if not items:
        raise UsageError("lattices=() is empty", fix=f"give one or more of {list(PERIODIC_LATTICES)!r}")
    loaded: dict = {}
    for item in items:
        if isinstance(item, (str, os.PathLike)):
            label = os.fspath(item)
            if label in library.names():
                target = library.load(label)
            elif os.path.exists(label) or label.partition(":")[0] in target_kinds():
                target = resolve_target(label)
            else:
                raise UsageError(f"lattice={label!r} is not known",
                                 fix=f"use one of {library.names()!r}, or the path of a lattice-graph/1 file")
        elif hasattr(item, "satisfied") and hasattr(item, "name"):
            label, target = str(item.name), item
        else:
            raise UsageError(f"lattices item={item!r} is not a name, a file or a target",
                             fix=f"give bundled names such as {list(PERIODIC_LATTICES)[:3]!r} or lattice files")
        if label in loaded:
            raise UsageError(f"lattices item={label!r} is given twice", fix="give each target once")
        _warn_user_lattice(target, strict, warnings)
        if getattr(target, "range", None) is None and default_range is not None and dataclasses.is_dataclass(target):
            # an algorithm whose robots sense everyone (003) names the range its starts are drawn at
            target = dataclasses.replace(target, range=float(default_range))
        if getattr(target, "range", None) is None:
            raise UsageError(f"{getattr(target, 'kind', 'lattice')} {label!r} has no default range",
                             fix="give a lattice file with a range")
        loaded[label] = target
    return tuple(loaded), loaded, warnings


# ----------------------------------------------------------------------------
# the steps of explore: check the inputs, name the assumptions kept and broken, build the
# scenario strategy, then per property search with Hypothesis and turn what it saw into a verdict
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Exploration:
    """What stays fixed while :func:`explore` searches: the algorithm, its targets and run
    parameters, how runs are judged, and where reports go."""

    spec: AlgorithmSpec
    seed: int
    max_examples: int
    loaded: dict                   # label -> target
    phi_of: dict                   # label -> range
    params: dict                   # overrides of v, omega, dt, extra
    options: dict                  # property options
    fault_model: Any
    max_steps: int | None
    allow_violations: bool
    scale: Callable | None         # the algorithm's scale_target(target, n), or None
    progress: Callable | None
    out_dir: Any
    database_dir: Any


#: The keys of ``explore(params=...)`` (and of a campaign's explore cell ``params:``).
RUN_PARAM_KEYS = ("v", "omega", "dt", "extra")


def check_run_params(algo, loaded: Mapping[str, Any], params: Mapping[str, Any], n_max: int, speeds=None) -> None:
    """Before any scenario: the run parameters as every scenario will build them (each target's range,
    each drawn speed), checked by the engine's own checks (:func:`~swarmproof.checkers.runs.build_params`:
    declared ``extra`` keys in their ranges, motion that moves a robot).  A key of ``params`` other than
    :data:`RUN_PARAM_KEYS` is refused, naming the algorithm parameter it is closest to (a campaign's
    ``params: {communication_timeout: 3}`` belongs under ``extra``)."""
    from swarmproof.reference_impl.engine.parameters import check_extra

    for key, value in params.items():
        if key not in RUN_PARAM_KEYS:
            check_extra(algo, {key: value})      # an unknown name: the closest one and the list
            raise UsageError(f"params {key}={value!r} is not one of {list(RUN_PARAM_KEYS)!r}",
                             fix=f"an algorithm parameter goes under extra: params: {{extra: {{{key}: {value!r}}}}} "
                                 f"(--param {key}={value} on the command line)")
    for name, target in loaded.items():
        for v_try in (speeds or (params.get("v"),)):
            build_params(algo, float(target.range), n_max, v=v_try, omega=params.get("omega"),
                         dt=params.get("dt"), extra=params.get("extra"))


def _check_run_inputs(ex: _Exploration, algo, lats, n_max: int, speeds) -> None:
    """Before any scenario: every target of a kind the algorithm forms
    (:func:`~swarmproof.reference_impl.engine.parameters.check_target_kind`), and
    :func:`check_run_params`."""
    from swarmproof.reference_impl.engine.parameters import check_target_kind

    for name in lats:
        check_target_kind(algo, ex.loaded[name])
    check_run_params(algo, {name: ex.loaded[name] for name in lats}, ex.params, n_max, speeds)


def _kept_and_broken_assumptions(ex: _Exploration, algo, lats, n_max: int, speeds) -> tuple[list, list]:
    """Which of the algorithm's assumptions the chosen parameters keep and which they break.

    Each assumption is probed once per target range (and per drawn speed) with the largest
    team, ``n_max``; the engine itself raises on a break unless ``allow_violations``, so a break
    without it is refused here, before any scenario runs.

    Returns
    -------
    (kept, broken) : (list of str, list of str)
        Assumption names, in the algorithm's order.

    Raises
    ------
    UsageError
        An assumption is broken and ``allow_violations`` is false.
    """
    params = ex.params
    kept, broken = [], []
    for a in getattr(algo, "assumptions", ()):
        msgs = []
        for name in lats:
            for v_try in (speeds or (params.get("v"),)):
                p = build_params(algo, ex.phi_of[name], n_max, v=v_try, omega=params.get("omega"),
                                 dt=params.get("dt"), extra=params.get("extra"))
                msg = a.check(p, n_max, list(range(n_max)))
                if msg:
                    msgs.append(msg)
        (broken if msgs else kept).append(a.name)
    if broken and not ex.allow_violations:
        what = f"speeds={list(speeds)!r}" if speeds else f"params={params!r}"
        raise UsageError(f"{what} break the assumptions {broken!r} of {ex.spec.label!r}",
                         fix="pass allow_violations=True (--allow-violations) to explore outside the paper's assumptions")
    return kept, broken


def _check_draw_faults(draw_faults, fault_model) -> tuple:
    """``draw_faults`` as a tuple of known fault kinds (:data:`FAULT_KINDS`), not with ``fault_model``."""
    draw_faults = tuple(draw_faults or ())
    for kind in draw_faults:
        if kind not in FAULT_KINDS:
            raise UsageError(f"draw_faults kind={kind!r} is not known", fix=f"use some of {list(FAULT_KINDS)!r}")
    if draw_faults and fault_model is not None:
        raise UsageError("fault_model and draw_faults were both given", fix="give one of them")
    return draw_faults


def _with_fault_assumptions(broken: list, algo, fault_model, draw_faults) -> list:
    """``broken`` and, after it, the robot-model assumptions that ``fault_model`` or the drawn
    fault kinds break (each named once)."""
    broken = list(broken)
    if fault_model is not None:
        fb = fault_model.broken_model_assumptions(algo.model)
        broken += [b for b in fb if b not in broken]
    if draw_faults:
        broken += [b for b in _fault_probe(draw_faults).broken_model_assumptions(algo.model) if b not in broken]
    return broken


def _premise_lemmas(algo) -> list:
    """The proof-suite lemmas whose premises the algorithm's premise monitors check, sorted."""
    from swarmproof.invariants.premises import MONITOR_LEMMAS, premise_monitors_of

    return sorted({MONITOR_LEMMAS[m] for m in premise_monitors_of(algo)})


def _scale_target(algo) -> Callable | None:
    """The algorithm's ``scale_target(target, n)`` (004: the goal set scaled to n robots), or None."""
    scale = getattr(algo, "scale_target", None)
    return scale if callable(scale) else None


def _explore_strategy(ex: _Exploration, algo, rng_robots, lats, draw_faults, speeds):
    """The :func:`scenario_strategy` for this algorithm: a grid algorithm's cell spacing, an
    algorithm with its own start drawn as free starts on the grid (004: any distinct
    waypoints), whole multiples of a team size where the algorithm asks for them (unless it
    scales its target), and the algorithm's own scenario draws."""
    factory = ex.spec.factory
    grid_spacing = None
    if getattr(getattr(factory, "model", None), "motion", None) == "grid":
        first = build_params(algo, ex.phi_of[lats[0]], rng_robots[1], extra=ex.params.get("extra"))
        grid_spacing = float((first.extra or {}).get("grid_spacing", 1.0))
    multiple = getattr(factory, "team_multiple", None)
    # an algorithm with its own start (004: any distinct waypoints) gets free starts on the grid
    free = grid_spacing is not None and callable(getattr(algo, "initial", None))
    team_multiple = ({name: int(multiple(g)) for name, g in ex.loaded.items()}
                     if callable(multiple) and ex.scale is None else None)
    return scenario_strategy(rng_robots, lats, ex.phi_of, draw_faults, speeds, grid_spacing, team_multiple,
                             targets=ex.loaded, scale_target=ex.scale, free_starts=free, algorithm=factory)


@dataclass(frozen=True)
class _Ran:
    """What the explorer keeps of one finished run besides its judgments: its counts, its crash
    and what a counterexample file records (the trace itself is not kept)."""

    steps: int
    status: str
    crash: dict | None
    max_steps: int
    broken_assumptions: tuple
    clocks: Any

    @classmethod
    def of(cls, result) -> "_Ran":
        return cls(int(result.steps), result.status, result.crash, int(result.max_steps),
                   tuple(result.broken_assumptions), result.trace.meta.get("clocks"))


#: At most this many scenarios' judgments are kept for the later properties of one explore call
#: (each a few judgments, not a trace: a few kB); past it, later properties run their scenarios.
MAX_SHARED_RUNS = 50_000
#: A later property is judged for sharing only while its judgments cost at most this fraction of
#: a run (CPU, on average over the call so far: :meth:`_SharedRuns.worth_judging`).
SHARE_JUDGE_FRACTION = 0.3


class _SharedRuns:
    """One explore call's runs, judged for every property explored after the one that ran them.

    A run does not depend on the property asked (the engine, the scenario and its seed decide
    it; a property's early-stop monitor, e.g. oscillation's, is the exception, and such
    properties neither give nor take runs here), and Hypothesis draws the same scenarios for each
    property from one seed until a property fails.  So when the second property meets a scenario
    the first one ran, its judgment is read here instead of running the engine again: the same
    verdicts, counts and counterexamples, bit for bit (tested), in a fraction of the time
    (``swarmproof explore song2016``, every property, and each algorithm's rows in verify).
    """

    def __init__(self) -> None:
        self.records: dict[str, tuple[_Ran, dict]] = {}
        self.run_cpu, self.runs = 0.0, 0
        self.judge_cpu: dict[str, float] = {}
        self.judged: dict[str, int] = {}

    def worth_judging(self, prop: str) -> bool:
        """Whether to judge ``prop`` now for later: while its judgments cost less than
        :data:`SHARE_JUDGE_FRACTION` of a run on average (song2016's premises cost about a run
        each, so sharing them would cost more than it saves).  A performance choice only: a
        judgment not kept is made by ``prop``'s own search, with the same outcome."""
        n = self.judged.get(prop, 0)
        if n == 0 or self.runs == 0:
            return True
        return self.judge_cpu[prop] / n <= SHARE_JUDGE_FRACTION * self.run_cpu / self.runs

    def note_run(self, cpu: float) -> None:
        self.run_cpu += cpu
        self.runs += 1

    def note_judgment(self, prop: str, cpu: float) -> None:
        self.judge_cpu[prop] = self.judge_cpu.get(prop, 0.0) + cpu
        self.judged[prop] = self.judged.get(prop, 0) + 1

    @staticmethod
    def key(scn: "Scenario") -> str:
        """The scenario exactly (``repr`` of a float round-trips, so distinct numbers differ)."""
        faults = None if scn.faults is None else scn.faults.describe()
        return repr((scn.lattice, scn.ids, scn.poses, scn.seed, scn.v, scn.extra, faults))

    def get(self, key: str, prop: str):
        rec = self.records.get(key)
        if rec is None or prop not in rec[1] or (rec[0].crash is not None and "no_crash" not in rec[1]):
            return None
        return rec[0], rec[1][prop], rec[1].get("no_crash")

    def put(self, key: str, ran: _Ran, judged: dict) -> None:
        if len(self.records) < MAX_SHARED_RUNS:
            self.records[key] = (ran, judged)


def _shares_runs(prop: str) -> bool:
    """Whether ``prop``'s runs are plain runs (no early-stop monitor): see :class:`_SharedRuns`."""
    from swarmproof.invariants.registry import get_property

    return get_property(prop).run_monitor is None


@dataclass
class _Search:
    """What one property's search has seen so far (updated by every scenario it runs)."""

    prop: str
    t0: float                      # time.monotonic() at the start
    c0: float                      # time.process_time() at the start
    deadline: float                # time.monotonic() after which the search stops
    examples: int = 0              # scenarios Hypothesis handed over
    runs: int = 0                  # scenarios run to a judgment (any status)
    conclusive: int = 0
    steps: int = 0
    capped: int = 0
    hit: bool = False              # the deadline ended the search
    #: a run the deadline stopped before it returned (the watchdog): what it was and where it hung
    overstayed: str | None = None
    why: str | None = None         # the last inconclusive judgment's message
    #: (wall s, cpu s, robots, runs) at the first failing scenario, None while none failed
    first: tuple | None = None
    #: counterexamples in the order found; Hypothesis shrinks, so the last is the smallest
    failures: list = field(default_factory=list)
    #: shrinking was stopped by MAX_SHRINK_RUNS (the counterexample may not be the smallest)
    shrink_capped: bool = False
    #: the runs this explore call shares between its properties (:class:`_SharedRuns`), or None
    shared: "_SharedRuns | None" = None
    #: the properties explored after this one that a run of this search is judged for as well
    later: tuple = ()
    #: ``premises``: each monitor's outcome per judged run (:attr:`PropertyVerdict.monitors`)
    monitors: dict | None = None

    def count(self, result, r) -> None:
        """Add one finished run (a :class:`_Ran`) and its judgment ``r``."""
        per = (getattr(r, "detail", None) or {}).get("monitors") if self.prop == "premises" else None
        if per:
            tally = self.monitors if self.monitors is not None else {}
            self.monitors = tally
            for name, m in per.items():
                kind = "vacuous" if m.get("vacuous") else m.get("status", "inconclusive")
                c = tally.setdefault(name, {"held": 0, "violated": 0, "vacuous": 0, "inconclusive": 0})
                c[kind if kind in c else "inconclusive"] += 1
        self.runs += 1
        self.steps += int(result.steps)
        self.capped += int(result.status == "step_cap")
        if r.status != "inconclusive":
            self.conclusive += 1
        else:
            self.why = r.message

    def note_failure(self, scn: Scenario) -> None:
        """Take the clock and the counts at the first failing scenario (later ones change nothing)."""
        if self.first is None:
            self.first = (time.monotonic() - self.t0, time.process_time() - self.c0, scn.n, self.runs)


def _scenario_params(ex: _Exploration, scn: Scenario):
    """The target and run parameters of one scenario: the target scaled to its team when the
    algorithm scales it (004: |Q| = |A|), the drawn speed and parameters over the given ones."""
    lattice = ex.loaded[scn.lattice]
    if ex.scale is not None:
        lattice = ex.scale(lattice, scn.n)     # the algorithm's target for n robots (004: |Q| = |A|)
    algo_n = ex.spec.build(n_robots=scn.n)
    params = ex.params
    extra = {**dict(params.get("extra") or {}), **dict(scn.extra)} if scn.extra else params.get("extra")
    p = build_params(algo_n, ex.phi_of[scn.lattice], scn.n, v=params.get("v") if scn.v is None else scn.v,
                     omega=params.get("omega"), dt=params.get("dt"), extra=extra)
    return lattice, p


def _scenario_counterexample(ex: _Exploration, scn: Scenario, lattice, p, fm, result: _Ran, r,
                             found: str) -> Counterexample:
    """The ``swarmproof-counterexample/1`` of a scenario whose property ``found`` was violated."""
    step = (r.witness or {}).get("step")
    return Counterexample(
        algorithm=ex.spec.ref, reading=ex.spec.reading,
        params=cx_params(p),
        lattice=_cx_lattice(scn.lattice, lattice), target=_cx_target(scn.lattice, lattice),
        robots=[(i, pose) for i, pose in zip(scn.ids, scn.poses)],
        seed=scn.seed, property=found,
        violation={"step": None if step is None else int(step), "message": r.message},
        schedule=None if fm is None else fm.describe().get("schedule"),
        faults=None if fm is None else fm.describe(),
        max_steps=int(result.max_steps), allow_violations=bool(ex.allow_violations),
        broken_assumptions=list(result.broken_assumptions), options=ex.options,
        clocks=result.clocks)


def _scenario_test(ex: _Exploration, search: _Search):
    """The Hypothesis test of one property: run a drawn scenario, judge it, record it in
    ``search``; a violation (or a crash of the algorithm, a ``no_crash`` finding whatever
    property was asked) fails the example so Hypothesis shrinks it."""
    from hypothesis import target

    prop = search.prop

    def test(scn: Scenario) -> None:
        search.examples += 1
        if ex.progress is not None:
            ex.progress(prop, search.examples, ex.max_examples)
        if time.monotonic() > search.deadline:
            search.hit = True
            raise _BudgetSpent()
        if search.first is not None and search.runs - search.first[3] >= MAX_SHRINK_RUNS:
            search.shrink_capped = True    # a count, never the clock: the same seed, the same file
            raise _BudgetSpent()
        lattice, p = _scenario_params(ex, scn)
        fm = scn.faults if scn.faults is not None else ex.fault_model
        key = _SharedRuns.key(scn) if search.shared is not None else None
        had = None if key is None else search.shared.get(key, prop)
        if had is not None:       # an earlier property ran this scenario and judged it for this one
            ran, r, crash_r = had
        else:
            left = None if math.isinf(search.deadline) else max(search.deadline - time.monotonic(), 1e-3)
            c0 = time.process_time()
            try:
                # the budget holds against the algorithm under test: a step that never returns is
                # stopped at the deadline (checkers/watchdog.py), and the search ends there
                with time_limit(left):
                    algo_run, result, r = run_and_judge(
                        ex.spec, prop, lattice, scn.ids, scn.poses, p, seed=scn.seed, max_steps=ex.max_steps,
                        allow_violations=ex.allow_violations, faults=fm, options=ex.options)
            except Overstayed as exc:
                search.hit = True
                if search.overstayed is None:
                    search.overstayed = f"{scn.n} robots on {scn.lattice} (seed {scn.seed}) {exc}"
                raise _BudgetSpent() from None
            ran = _Ran.of(result)
            crash_r = None
            if result.crash is not None and prop != "no_crash":
                crash_r = judge("no_crash", algo_run, lattice, p, result, ex.options)
            if key is not None and search.later:
                shared = search.shared
                shared.note_run(time.process_time() - c0)
                judged = {}
                for q in search.later:
                    if not shared.worth_judging(q):
                        continue
                    c1 = time.process_time()
                    try:
                        judged[q] = judge(q, algo_run, lattice, p, result, ex.options)
                    except Exception:  # noqa: BLE001 - q's own search runs the scenario and meets it
                        pass
                    shared.note_judgment(q, time.process_time() - c1)
                if ran.crash is not None:
                    judged["no_crash"] = crash_r if crash_r is not None else r
                search.shared.put(key, ran, judged)
        score = closeness(prop, r)
        if score is not None:
            target(score, label=prop)
        search.count(ran, r)
        found = prop
        if ran.crash is not None and prop != "no_crash":
            # a crash of the algorithm under test is a finding whatever was asked: no_crash
            found = "no_crash"
            r = crash_r
        if r.violated:
            search.note_failure(scn)
            search.failures.append(_scenario_counterexample(ex, scn, lattice, p, fm, ran, r, found))
            raise AssertionError(r.message)

    return test


def _search_property(ex: _Exploration, strategy, prop: str, share: float,
                     shared: _SharedRuns | None = None, later: tuple = ()) -> _Search:
    """Let Hypothesis search ``strategy`` for a violation of ``prop`` within ``share`` seconds.

    Every setting is explicit (seeded, no deadline, no database unless ``database_dir``), so
    Hypothesis's "ci" profile changes nothing.  The budget ends the search at once
    (:class:`_BudgetSpent`); what was found and shrunk so far is kept.
    """
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as hseed

    t0, c0 = time.monotonic(), time.process_time()
    search = _Search(prop, t0, c0, deadline=t0 + share, shared=shared, later=later)
    db = None
    if ex.database_dir is not None:
        from hypothesis.database import DirectoryBasedExampleDatabase

        db = DirectoryBasedExampleDatabase(os.path.join(os.fspath(ex.database_dir), f"{_file_label(ex.spec)}-{prop}"))
    run = settings(max_examples=ex.max_examples, database=db, derandomize=False, deadline=None,
                   print_blob=False, report_multiple_bugs=False,
                   phases=(Phase.explicit, Phase.reuse, Phase.generate, Phase.shrink),
                   suppress_health_check=list(HealthCheck))(
        hseed(ex.seed)(given(strategy)(_scenario_test(ex, search))))
    try:
        with without_local_constants(), _count_bounded_shrinking():
            run()
    except _BudgetSpent:
        pass  # the share of the budget is spent: keep what was found (and shrunk) so far
    except Exception:  # noqa: BLE001 - the failure is what we recorded in `search.failures`
        if not search.failures:
            raise
    return search


def _mark_violated(ex: _Exploration, verdict: PropertyVerdict, cx: Counterexample) -> None:
    """Make ``verdict`` violated by ``cx``; with ``out_dir``, save ``cx`` as a file."""
    verdict.status = "violated"
    verdict.counterexample = cx
    where = cx.lattice if cx.target is None else (cx.lattice or f"{cx.target['kind']}:{cx.target['name']}")
    verdict.message = f"{len(cx.robots)} robots on {where}: {cx.violation['message']}"
    if ex.out_dir is not None:
        os.makedirs(ex.out_dir, exist_ok=True)
        verdict.counterexample_path = cx.save(os.path.join(
            os.fspath(ex.out_dir), f"{_file_label(ex.spec)}-{_safe(cx.property)}-seed{ex.seed}.json"))


def _search_verdicts(ex: _Exploration, search: _Search) -> tuple[PropertyVerdict, PropertyVerdict | None]:
    """The property's verdict from its search and, when the algorithm crashed, the
    ``no_crash`` verdict (with the crash's counterexample) that comes with it.

    Violated with the smallest counterexample; inconclusive when the algorithm crashed
    (the property was not judged on that run), when no scenario gave a judgment, or when
    the budget, not ``max_examples``, ended the search; else held over what was explored.
    """
    prop, failures = search.prop, search.failures
    v = PropertyVerdict(prop, "held", scenarios=search.runs, conclusive=search.conclusive, steps=search.steps,
                        capped=search.capped, budget_hit=search.hit, seconds=time.monotonic() - search.t0,
                        monitors=search.monitors)
    if search.first is not None:
        (v.first_failure_seconds, v.first_failure_cpu, v.first_failure_robots,
         v.first_failure_scenarios) = search.first
    if failures and failures[-1].property != prop:
        # the algorithm crashed while `prop` was explored: the crash is a no_crash finding
        # (shrunk, with its counterexample); `prop` was not judged on those runs
        crash_v = PropertyVerdict(failures[-1].property, "held", scenarios=search.runs,
                                  conclusive=search.runs, steps=search.steps, capped=search.capped,
                                  budget_hit=search.hit, seconds=time.monotonic() - search.t0)
        _mark_violated(ex, crash_v, failures[-1])
        v.status = "inconclusive"
        v.message = (f"the algorithm crashed ({crash_v.counterexample.violation['message']}): "
                     f"{prop} was not judged on that run; see no_crash")
        return v, crash_v
    if failures:
        _mark_violated(ex, v, failures[-1])  # the last is the smallest
        if search.shrink_capped:
            v.message += f" (shrinking stopped after MAX_SHRINK_RUNS={MAX_SHRINK_RUNS} runs)"
    elif search.conclusive == 0:
        v.status = "inconclusive"
        v.message = ("no scenario gave a judgment" +
                     (" (budget spent)" if search.hit else f" ({search.capped} runs hit the step cap)") +
                     (f"; last: {search.why}" if search.why else "") + _overstayed_note(search) +
                     ("; no run returned: a step of the algorithm may never return (it is judged, not trusted)"
                      if search.overstayed is not None and search.runs == 0 else ""))
    elif search.hit:
        # the clock, not max_examples, ended the search: what was not explored is not a pass
        v.status = "inconclusive"
        v.message = (f"stopped by the budget after {search.runs} of {ex.max_examples} scenarios: held on "
                     f"those ({search.steps} steps){_overstayed_note(search)}, inconclusive for the rest (raise "
                     f"--budget, or bound the search by --max-examples alone with --budget none)")
    else:
        v.message = (f"held over {search.conclusive} judged scenarios and {search.steps} steps "
                     f"(explored, not proved)")
    return v, None


def _overstayed_note(search: _Search) -> str:
    """What the budget stopped mid-run, when it did (a step that may never return), else ''."""
    if search.overstayed is None:
        return ""
    return f"; the budget stopped a run under way: {search.overstayed}"


def _explore_property(ex: _Exploration, strategy, prop: str, share: float, report: ExploreReport,
                      shared: _SharedRuns | None = None, later: tuple = ()) -> None:
    """Search ``prop`` for ``share`` seconds at most and enter its verdict in ``report`` (after
    the ``no_crash`` verdict, when the algorithm crashed and no_crash has none yet).  ``shared``
    and ``later``: runs shared with the properties explored after it (:class:`_SharedRuns`)."""
    verdict, crash_verdict = _search_verdicts(ex, _search_property(ex, strategy, prop, share, shared, later))
    if crash_verdict is not None:
        report.properties.setdefault(crash_verdict.name, crash_verdict)
    report.properties[prop] = verdict


def _tell_listeners(report: ExploreReport) -> None:
    """Hand the finished report to every registered listener (e.g. the pytest plugin's table)."""
    from swarmproof.checkers.listeners import REPORT_LISTENERS

    for listener in list(REPORT_LISTENERS):
        listener(report)


def explore(algorithm, properties: Sequence[str] | None = None, *, budget: float = 60.0,
            max_examples: int = 100, robots: tuple[int, int] = (3, 8), seed: int = 0,
            lattices: Sequence[str] | None = None, fault_model=None, out_dir: str | os.PathLike | None = None,
            progress: Callable[[str, int, int], None] | None = None, params: Mapping[str, Any] | None = None,
            allow_violations: bool = False, max_steps: int | None = None,
            options: Mapping[str, Any] | None = None, draw_faults: Sequence[str] = (),
            database_dir: str | os.PathLike | None = None,
            speeds: Sequence[float] | None = None, strict: bool = False) -> ExploreReport:
    """Hunt counterexamples to ``properties`` of ``algorithm``.

    Parameters
    ----------
    algorithm : str, class or callable
        A registered algorithm name, ``"module:qualname"``, or an algorithm class / factory
        following :class:`swarmproof.reference_impl.protocol.Algorithm` (:func:`resolve_algorithm`;
        an unregistered class's claims come from its ``claims`` attribute, else none are claimed).
        Counterexample files record the registry name or ``"module:qualname"``, which
        ``swarmproof replay`` imports.
    properties : sequence of str, optional
        Registered property names (or ``module:name`` of a user's property); default all
        (:func:`explore_properties`).
    budget : float
        Wall-clock seconds for the whole exploration, split evenly between the properties (finding
        and shrinking).
    max_examples : int
        Hypothesis ``max_examples`` per property.
    robots : (int, int)
        Inclusive range of the number of robots.
    seed : int
        Hypothesis seed (``@seed``); with the same ``max_examples`` and the budget not hit, the
        report is the same.
    lattices : sequence, optional
        Targets the scenarios draw from: bundled lattice names, lattice-graph/1 files of your own,
        ``KIND:NAME`` or target objects; default :data:`PERIODIC_LATTICES`.  A counterexample on a
        user's lattice carries its whole document (``target``), so it replays without the file.
    fault_model : FaultModel, optional
        Passed to the engine; the assumptions it breaks are reported.
    out_dir : path, optional
        Where counterexample files are written (``ALGORITHM-PROPERTY-seedS.json``).
    progress : callable ``(property, examples_run, max_examples)``, optional
    params : mapping, optional
        Overrides of ``v``, ``omega``, ``dt`` (and ``extra``) of the algorithm's default parameters;
        with ``allow_violations`` they may break the paper's assumptions (reported).
    allow_violations : bool
        Run scenarios whose parameters break an assumption.
    max_steps : int, optional
        Engine step cap (default: the algorithm's).
    options : mapping, optional
        Property options: ``radius`` (collision), ``deadlock_k``, ``pos_tol`` (oscillation),
        ``invariants`` (names: the ``invariants`` property checks only these of the algorithm's),
        ``progress_window`` (oscillation's no-progress window W, default
        :data:`DEFAULT_PROGRESS_WINDOW` for algorithms with ``randomized = True``; given explicitly
        it applies to any algorithm with a ``progress_measure``), ``progress_eps``.
    draw_faults : sequence of str
        Fault kinds Hypothesis draws per scenario (:data:`FAULT_KINDS`: ``schedule``, ``crashes``,
        ``drops``, ``additions``, ``noise``, ``delays``, ``latency``; see :func:`draw_fault_model`);
        they break robot-model assumptions, which the report names.  Not together with ``fault_model``.
    database_dir : path, optional
        Keep Hypothesis's example database in this folder, so a rerun tries known failures first
        (found at once).  Default None: no database, which the determinism guarantee assumes (a
        database replays stored examples before generating).
    speeds : sequence of float, optional
        Let every scenario draw its speed ``v`` from these values (the first is the one shrinking
        goes toward, e.g. the paper's).  Each must keep the algorithm's assumptions on every lattice
        (else ``allow_violations``); not together with ``params["v"]``.  Longer steps (``v*dt``
        nearer ``phi``) stress the bounded-range and safe-region margins and end runs in fewer
        steps.
    strict : bool
        Refuse a lattice file of yours that check-lattice does not pass at its range (default:
        explore it, with a warning in the report).

    Returns
    -------
    ExploreReport

    Raises
    ------
    UsageError
        Unknown algorithm, property or lattice, non-positive budget or max_examples, bad robots
        range, bad speeds, or parameters that break an assumption without ``allow_violations``.
    """
    spec, props, budget, rng_robots, lats, loaded, warnings = _check_inputs(
        algorithm, properties, budget, max_examples, robots, seed, lattices, out_dir, strict)
    params = dict(params or {})
    speeds = _check_speeds(speeds, params)
    algo = spec.build(n_robots=rng_robots[1])
    ex = _Exploration(spec, seed, max_examples, loaded, {name: float(g.range) for name, g in loaded.items()},
                      params, dict(options or {}), fault_model, max_steps, allow_violations, _scale_target(algo),
                      progress, out_dir, database_dir)
    _check_run_inputs(ex, algo, lats, rng_robots[1], speeds)
    kept, broken = _kept_and_broken_assumptions(ex, algo, lats, rng_robots[1], speeds)
    if options and options.get("invariants") is not None:
        from swarmproof.invariants.algorithm_invariants import invariants_of

        if "invariants" not in props:
            raise UsageError(f"invariant={list(options['invariants'])!r} applies to the invariants property only "
                             f"(properties asked: {list(props)!r})",
                             fix="add --property invariants, or drop --invariant")
        invariants_of(algo, options["invariants"])      # a name it does not declare: exit 2 up front
    draw_faults = _check_draw_faults(draw_faults, fault_model)
    broken = _with_fault_assumptions(broken, algo, fault_model, draw_faults)
    report = ExploreReport(spec.label, seed, max_examples, rng_robots, lats, kept, broken,
                           claims={p: spec.claims.get(p) for p in props}, algorithm_ref=spec.ref,
                           premise_lemmas=_premise_lemmas(algo), speeds=speeds, warnings=list(warnings))
    strategy = _explore_strategy(ex, algo, rng_robots, lats, draw_faults, speeds)
    # not applicable (the algorithm's declarations against the property's needs): not explored
    from swarmproof.invariants.registry import get_property

    na = {p: get_property(p).not_applicable_to(algo) for p in props}
    asked = [p for p in props if na[p] is None]
    sharing = [p for p in asked if _shares_runs(p)]
    shared = _SharedRuns() if len(sharing) > 1 else None
    for prop in props:
        if na[prop] is not None:
            report.properties[prop] = PropertyVerdict(prop, "not_applicable", message=f"not applicable: {na[prop]}")
        elif shared is not None and prop in sharing:
            _explore_property(ex, strategy, prop, budget / len(asked), report, shared,
                              later=tuple(sharing[sharing.index(prop) + 1:]))
        else:
            _explore_property(ex, strategy, prop, budget / len(asked), report)
    _tell_listeners(report)
    return report
