"""The algorithm protocol: the one small contract between the engine and an algorithm.

DESIGN.md section 1 ("The algorithm protocol").  A robot *controller* sees
only what its paper lets it see (an :class:`Observation`) and returns a
:class:`Command` (a message to broadcast and a motion).  The *engine* owns
global poses, sensing, message delivery, motion limits, the scheduler and
faults; a controller never receives global coordinates unless its model
says so (``sensing="global"``), which is enforced by construction: the
engine builds the observation, the controller only ever sees that.

One protocol fits the five papers:

=====================  ===========  ==============  ===================  ============
paper                  sensing      communication   motion               clocks
=====================  ===========  ==============  ===================  ============
Song & O'Kane 2014/16  ``local``    ``neighbors``   ``differential``     ``sync``
Jiang et al.           ``global``   ``all``         ``differential``     ``sync``
Lee & Chong            ``anonymous````none``        ``holonomic``        ``sync``
Wang & Rubenstein      ``global``   ``neighbors``   ``grid``             ``async``
=====================  ===========  ==============  ===================  ============

``local``: IDs and body-frame poses of neighbors within range phi.
``anonymous``: body-frame positions of all robots, no IDs, no headings
(``neighbor_ids`` is None; messages carry no sender IDs).
``global``: additionally ``own_pose`` in the common frame.

Motion (``differential``, 000 Sec. III-A-3 and 001 Sec. III-A): a command is
"turn in place by ``turn``, then drive straight ``forward``".  The engine
clamps ``|turn|`` to ``omega*dt`` and ``forward`` to
``v * (dt - |turn|/omega)`` (time spent turning is not available for
driving), so no robot ever moves farther than ``v*dt`` in a step.  The
helper :func:`steer_toward` computes such a command toward a body-frame
target point and final heading.

An algorithm declares its :class:`RobotModel` and the :class:`Assumption`
s its paper makes; the engine refuses parameters that break an assumption
(:class:`~swarmproof.models.errors.AssumptionError` naming it) unless the
caller passes ``allow_violations=True``, and the explorer (fault models) can
break them on purpose and says which it broke.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Hashable, Mapping, Protocol, Sequence, runtime_checkable

import numpy as np

__all__ = [
    "Assumption", "RobotModel", "Params", "ParamSpec", "VerifyPlan", "ExhaustiveCell", "Observation", "Command",
    "Controller",
    "Algorithm", "DEFAULT_READING", "reading_of", "steer_toward", "connected_start",
    "Experiment", "ExperimentColumn", "experiment",
]

#: The reading of an algorithm that declares none, and of a counterexample file or baseline that
#: records none (they were written before readings were versioned, when every algorithm was at
#: its first reading): ``"1"`` (defined in :mod:`swarmproof.models.versions`).
from swarmproof.models.versions import DEFAULT_READING  # noqa: E402


@dataclass(frozen=True)
class Assumption:
    """One assumption a paper makes, checkable on parameters and the initial state.

    Attributes
    ----------
    name : str
        Short id, e.g. ``"v_dt_below_range"``; reports and errors use it.
    statement : str
        The assumption in words, e.g. ``"v*dt < phi"``.
    cites : str
        Where the paper makes it, e.g. ``"001 Lemma 7"``.
    check : callable ``(params, n, ids) -> str | None``
        Returns ``None`` when it holds, else a message naming the offending
        values as ``name=value``.  ``ids`` are the robot IDs (may be None for
        anonymous robots).
    check_start : callable ``(params, ids, poses) -> str | None``, optional
        A check that needs the initial poses too (e.g. a connected start);
        the engine calls it with the global initial poses (never a
        controller).  Added by the engine helper; default None.

    See :func:`connected_start` for the ready-made "connected start"
    assumption (001 Sec. III: "starting from an unknown but connected
    distribution of initial poses").
    """

    name: str
    statement: str
    cites: str
    check: Callable[["Params", int, Sequence[int] | None], str | None] = field(compare=False)
    check_start: Callable[["Params", Sequence[int] | None, np.ndarray], str | None] | None = field(
        default=None, compare=False)
    check_target: Callable[["Params", int, Any], str | None] | None = field(default=None, compare=False)


@dataclass(frozen=True)
class RobotModel:
    """What a robot can sense, say, do, and how it is clocked (see module table)."""

    sensing: str = "local"          # "local" | "anonymous" | "global"
    communication: str = "neighbors"  # "neighbors" | "all" | "none"
    motion: str = "differential"    # "differential" | "holonomic" | "grid"
    clocks: str = "sync"            # "sync" | "async"
    #: Who is a neighbor: ``"strict"`` (closer than phi, 000/001 Sec. III) or ``"inclusive"``
    #: (at most phi, e.g. 004's ``<= R``); sensing, messages and the connectivity property use it.
    neighbor_rule: str = "strict"
    #: When messages arrive: ``"timely"`` (the next step, in order: 000/001) or ``"unbounded"``
    #: (any later step, in any order: 002 Sec. III-A, "no fixed upper bound on the time it takes
    #: for a message to be delivered").  Delay and reordering faults break only a timely model.
    message_timing: str = "timely"
    #: ``sensing="anonymous"`` only: the robot knows a fixed label of its own (passed to
    #: ``Algorithm.controller`` as ``robot_id``) though it senses the others anonymously (003
    #: Sec. 3.7's F-team, "robots with initial fixed IDs").  Observations still carry no IDs.
    own_id: bool = False

    CHOICES = {"sensing": ("local", "anonymous", "global"), "communication": ("neighbors", "all", "none"),
               "motion": ("differential", "holonomic", "grid"), "clocks": ("sync", "async"),
               "neighbor_rule": ("strict", "inclusive"), "message_timing": ("timely", "unbounded")}

    def __post_init__(self) -> None:
        from swarmproof.models.errors import UsageError

        for name, allowed in self.CHOICES.items():
            value = getattr(self, name)
            if value not in allowed:
                raise UsageError(f"RobotModel {name}={value!r} is not one of {list(allowed)!r}")


@dataclass(frozen=True)
class Params:
    """Physical parameters of the robots and the step.

    Attributes
    ----------
    range : float
        phi, the sensing/communication range; robots strictly closer than
        phi are neighbors.
    v : float
        Maximum linear speed (distance per unit time).
    omega : float
        Maximum angular speed (radians per unit time).
    dt : float
        Length of one synchronous step.
    extra : mapping
        Algorithm-specific parameters (e.g. ``d_s``, timeouts), read by the
        algorithm; the engine ignores them.
    """

    range: float
    v: float = 0.05
    omega: float = math.pi / 4
    dt: float = 1.0
    extra: Mapping[str, Any] = field(default_factory=dict)

    @property
    def step_length(self) -> float:
        """``v * dt``: the farthest a robot moves in one step."""
        return self.v * self.dt


@dataclass(frozen=True)
class ParamSpec:
    """One key of ``Params.extra`` an algorithm (or the engine) reads: its name, type, range and
    meaning (DESIGN.md section 1, "its parameters (name, type, range, meaning: unknown keys are
    refused)").  An algorithm lists them in its class attribute ``parameters``; the engine's
    preflight checks every run's ``Params.extra`` against them
    (:func:`swarmproof.reference_impl.engine.parameters.check_extra`).

    Attributes
    ----------
    name : str
        The key, as the user types it (``--param NAME=VALUE``, a campaign's ``params:``).
    type : type
        ``float`` (an int is accepted too), ``int`` (a whole number), ``bool``, ``str``, or
        ``object`` (anything: the algorithm checks the value itself, e.g. 003's ``fail`` list).
    default : object
        The value used when the key is absent (None: computed, see ``meaning``).
    low, high : float, optional
        The range of a number; None is unbounded.
    low_open, high_open : bool
        Whether ``low`` / ``high`` themselves are excluded (``(0, inf)``: ``low=0, low_open=True``).
    meaning : str
        What it sets, for errors, ``--help`` texts and the docs' parameter tables.
    choices : tuple, optional
        The values allowed (a ``str`` parameter such as song2016's ``parent_rule``).

    Examples
    --------
    >>> s = ParamSpec("p_random", float, 0.1, low=0, high=1, meaning="probability of a random goal")
    >>> s.range_text()
    '[0, 1]'
    >>> s.problem(0.5) is None, s.problem(-1)
    (True, 'p_random=-1 is outside its range [0, 1] (probability of a random goal)')
    >>> ParamSpec("broadcast_every", float, 1.0, low=0, low_open=True).problem(0)
    'broadcast_every=0 is outside its range (0, inf)'
    >>> ParamSpec("k", int, 3, low=1).problem(2.5)
    'k=2.5 must be a whole number'
    """

    name: str
    type: type = float
    default: Any = None
    low: float | None = None
    high: float | None = None
    meaning: str = ""
    low_open: bool = False
    high_open: bool = False
    choices: tuple | None = None

    def range_text(self) -> str:
        """The allowed values in words: ``[0, 1]``, ``(0, inf)``, ``one of [...]``, ``any str``."""
        if self.choices is not None:
            return f"one of {list(self.choices)!r}"
        if self.type in (int, float) and (self.low is not None or self.high is not None):
            lo = "-inf" if self.low is None else f"{self.low:g}"
            hi = "inf" if self.high is None else f"{self.high:g}"
            return (("(" if self.low_open or self.low is None else "[") + f"{lo}, {hi}" +
                    (")" if self.high_open or self.high is None else "]"))
        return {int: "any whole number", float: "any finite number", bool: "true or false",
                str: "any text"}.get(self.type, "any value")

    def problem(self, value: Any) -> str | None:
        """None when ``value`` is of this parameter's type and within its range, else what is
        wrong, naming it as ``name=value``."""
        what = f"{self.name}={value!r}"
        about = f" ({self.meaning})" if self.meaning else ""
        if self.type is object:
            return None
        if self.type is bool:
            return None if isinstance(value, bool) else f"{what} must be true or false{about}"
        if self.type is str:
            if not isinstance(value, str):
                return f"{what} must be text{about}"
        elif isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            return f"{what} must be a number{about}"
        elif self.type is int and not float(value).is_integer():
            return f"{what} must be a whole number{about}"
        elif not math.isfinite(float(value)):
            return f"{what} must be a finite number{about}"
        if self.choices is not None:
            return None if value in self.choices else f"{what} is not {self.range_text()}{about}"
        if self.type is str:
            return None
        x = float(value)
        low_bad = self.low is not None and (x < self.low or (self.low_open and x == self.low))
        high_bad = self.high is not None and (x > self.high or (self.high_open and x == self.high))
        return f"{what} is outside its range {self.range_text()}{about}" if low_bad or high_bad else None


@dataclass(frozen=True)
class Observation:
    """Everything one robot perceives at the start of one step.

    Attributes
    ----------
    step : int
        The step number (0-based); a local clock, not a global one.
    robot_id : int or None
        The robot's own ID (None for anonymous robots).
    neighbor_ids : tuple of int, or None
        IDs of the sensed robots (None when the model is anonymous), in
        increasing ID order.
    neighbor_poses : numpy.ndarray, shape (k, 3), or (k, 2) when anonymous
        Their poses ``[x, y, theta]`` in this robot's body frame, row i for
        ``neighbor_ids[i]``.  Anonymous robots sense positions only
        (``[x, y]``, no headings: 003 Sec. 2), ordered by ``(x, y)``.  Read-only.
    messages : mapping
        ID -> message that robot broadcast in the previous step, for the
        robots this one can hear now (only those that sent one).  Anonymous
        robots: row of ``neighbor_poses`` -> message of the robot sensed
        there (no sender IDs).
    own_pose : numpy.ndarray or None
        ``[x, y, theta]`` in the common frame, only when ``sensing="global"``.
    inbox : tuple of (sender, message)
        Every delivery of this step in delivery order (a property): with
        delayed, duplicated or reordered messages (fault models) it holds
        what ``messages`` cannot (two messages of one sender, an old one
        after a new one).  ``sender`` is the ID, or None for anonymous robots.
        Without such faults it is ``messages``' items.
    """

    step: int
    robot_id: int | None
    neighbor_ids: tuple[int, ...] | None
    neighbor_poses: np.ndarray
    messages: Mapping[int, Any]
    own_pose: np.ndarray | None = None
    delivered: tuple | None = field(default=None, repr=False)
    #: ``clocks="async"``: this robot's local clock ``phase + rate * t`` when it decides
    #: (its phase and rate are drawn from the seed and recorded); None when synchronous.
    clock: float | None = None

    @property
    def inbox(self) -> tuple:
        if self.delivered is not None:
            return self.delivered
        if self.robot_id is None and self.neighbor_ids is None:
            return tuple((None, m) for m in self.messages.values())
        return tuple(self.messages.items())


@dataclass(frozen=True)
class Command:
    """What a controller returns for one step.

    Attributes
    ----------
    message : object
        Broadcast to the robots that can hear this one (delivered at the
        next step).  ``None`` means silent.  Must be immutable
        (tuples, frozen dataclasses) and compare by value: traces record and
        compare messages.
    turn : float
        Turn in place, radians (counter-clockwise positive), done first.
    forward : float
        Then drive straight this far (>= 0).
    move : (int, int) or None
        ``motion="grid"`` only (``turn`` and ``forward`` stay 0): cross the
        edge to the 4-neighbouring cell ``(dx, dy)`` in the common frame --
        one of ``(1, 0), (-1, 0), (0, 1), (0, -1)`` -- or None to wait.  The
        crossing takes ``grid_spacing / v`` time; a command given while the
        robot is on an edge is ignored until it arrives.
    """

    message: Any = None
    turn: float = 0.0
    forward: float = 0.0
    move: tuple | None = None


@runtime_checkable
class Controller(Protocol):
    """One robot's decision procedure.  Created by :meth:`Algorithm.controller`."""

    def step(self, obs: Observation) -> Command:
        """Decide this step's message and motion from local information only."""
        ...

    def state(self) -> Hashable:
        """A hashable, JSON-friendly snapshot of the controller's internal state
        (e.g. ``(("role", "A"), ("parent", 7), ("stable", True))``).

        Checkers (oscillation, deadlock, premise monitors) read it; it must
        change whenever the controller's future behaviour may change."""
        ...

    # Optional, for point-to-point exchanges answered within the step (negligible latency, e.g.
    # 004 Sec. II-A e; docs/engine.md, "Point-to-point exchanges"):
    #
    # def requests(self, obs: Observation) -> tuple:
    #     """The first part of the step: ``((peer_id, payload), ...)`` to send now.  When any
    #     controller defines it, the engine calls it for every acting robot, then delivers each
    #     request to its addressee if it is a neighbor now and answers it, then calls every
    #     acting robot's ``step`` with the same Observation."""
    # def answer(self, sender_id: int, payload, clock: float):
    #     """A request addressed to this robot arrived: return the reply (None: no answer)."""
    # def on_reply(self, peer_id: int, payload, reply, clock: float) -> None:
    #     """The reply to this robot's request ``payload`` to ``peer_id`` arrived."""
    #
    # ``clock`` is the robot's local clock in the step (``Observation.clock``; the step number
    # when synchronous).  The fault model's loss and delay apply to each direction (a late reply
    # arrives in a later step's exchange).


@runtime_checkable
class Algorithm(Protocol):
    """A formation algorithm, as the engine and the checkers see it."""

    #: Registry name, e.g. ``"song2016"``.
    name: str
    #: What the robots can sense, say and do.
    model: RobotModel
    #: The paper's assumptions (checked before a run).
    assumptions: tuple[Assumption, ...]
    #: The reading version: a short string (``"1"``, ``"2"``, ...), bumped whenever the
    #: algorithm's behaviour changes on purpose (another reading of its paper, a fixed
    #: misreading), never for a refactoring that keeps every trace identical.  Counterexample
    #: files and verify baselines record it; a file made by another reading does not replay
    #: (exit 2, naming the registered reading that does: ``registry.READINGS``).  Optional:
    #: an algorithm without one is at reading :data:`DEFAULT_READING`.
    reading: str

    def controller(self, robot_id: int | None, params: Params, lattice, rng: np.random.Generator) -> Controller:
        """A fresh controller for one robot.  ``rng`` is this robot's own
        generator, spawned by the engine from the run's seed."""
        ...

    def finished(self, states: Sequence[Hashable]) -> bool:
        """The algorithm's own end condition, judged by the omniscient observer
        from every controller's :meth:`Controller.state` (e.g. song2016: no
        unstable robot remains).  Return False if the paper has none; the
        engine then stops on a static state or the step cap."""
        ...

    # Optional class attributes (everything the checkers need to know of an
    # algorithm lives on its class, so a new algorithm is one module):
    #
    # claims : Mapping[str, str | None]
    #     Property name -> the paper's citation for it; a property that is
    #     absent (or None) is not claimed, and its violation is a finding.
    # premise_monitors : tuple of str
    #     The lemma-premise monitors (invariants/premises.py ``MONITORS``) its
    #     proof rests on; the ``premises`` property checks exactly these.
    # lemmas : tuple of str
    #     The ids of ``swarmproof prove``'s lemmas about it (its paper's, or a user's own
    #     registered in the suite): ``swarmproof prove --algorithm NAME`` proves exactly these,
    #     ``swarmproof list lemmas`` names the algorithms of each lemma, and the pytest
    #     plugin's ``assert_proved(NAME)`` fails unless every one is proved.
    # verify : VerifyPlan
    #     What ``swarmproof verify`` runs of it; without one it has no rows.
    # parameters : tuple of ParamSpec
    #     Every ``Params.extra`` key it reads (name, type, range, meaning).  With it, the engine's
    #     preflight refuses a key it does not declare (naming the closest one) and a value out of
    #     its range, before any step; without it (a user's algorithm that declares nothing) no
    #     key is checked.  The engine's own keys (``grid_spacing``, clock rates, ...) are
    #     declared by the engine (``engine/parameters.py``) for the models that read them.
    # target_kinds : tuple of str
    #     The kinds of target it forms (:func:`swarmproof.models.targets.target_kinds`, e.g.
    #     ``("lattice",)``); a target of another kind is a usage error before any run.
    #     Without it, any kind is run.
    # state_fields : tuple of str
    #     The controller-state fields the shared checkers may read, e.g. ``("parent",)`` for a
    #     spanning tree; a property that needs one it lacks is *not applicable* to it
    #     (:mod:`swarmproof.invariants.capabilities`; undeclared: decided by running).
    # paper : str
    #     The seed key of its paper (``"001"``, docs/references.md); a user's class has none,
    #     and its unclaimed properties are then "not claimed by the algorithm".
    # departs_from : tuple of str
    #     Assumptions of its paper this reading does not keep (a registered variant that adds what
    #     the paper assumes away, e.g. wang2020-broadcast-handshake's latency: 004 Sec. II-A e);
    #     ``swarmproof list`` names them.  Empty or absent: it keeps the paper's model.
    # invariant_renames : mapping of str to str
    #     Old names of its runtime invariants -> what they became (``explore --invariant OLD`` says so).
    # knows_start : bool
    #     The paper gives every robot the robot set and all initial positions as input
    #     (002 Sec. III-A, Alg. 1 "Input"); needs ``sensing="global"``.  The engine then
    #     calls ``controller.know_start(ids, positions)`` once before step 0 (``ids`` a
    #     tuple, ``positions`` a read-only ``(n, 2)`` array in the common frame).


@dataclass(frozen=True)
class ExhaustiveCell:
    """Exhaustive rows of ``swarmproof verify`` (issue 33): ``properties`` checked for every choice
    sequence within a bound -- steps, ``deviations`` (K) and choice ``kinds`` only, never wall
    time -- from the seeded start of ``robots`` robots (``seed``), on ``target`` (None: the
    algorithm's default).  One row per property (docs/exhaustive.md).

    >>> ExhaustiveCell(("connectivity",), ("activate",), steps=15, deviations=2).label()
    'n=3 activate S=15 K=2'
    """

    properties: tuple
    kinds: tuple = ("activate",)
    steps: int = 20
    deviations: int = 2
    robots: int = 3
    seed: int = 0
    max_delay: int = 1
    max_crashes: int = 1
    target: str | None = None

    def label(self) -> str:
        """The part of the rows' subject that names the bound."""
        extra = (f" D={self.max_delay}" if "delay" in self.kinds else "") + \
                (f" C={self.max_crashes}" if "crash" in self.kinds else "")
        return f"n={self.robots} {'+'.join(self.kinds)} S={self.steps} K={self.deviations}{extra}"


@dataclass(frozen=True)
class VerifyPlan:
    """What ``swarmproof verify`` runs of one algorithm (its class's ``verify`` attribute).

    Attributes
    ----------
    targets : tuple of str
        Bundled target names for the ``algorithms`` rows (the lattices of
        its paper's figures).
    robots : int
        Robots per run, from the seeded connected starts ``seeds``.
    seeds : tuple of int
    explore : bool
        Whether it gets ``exploration`` rows (every registered property).
    rank : int
        Order of the algorithms in the report (lower first; ties by name).
    more : tuple of (target, robots, seeds)
        Further ``algorithms`` rows at other sizes: a finding that only shows there
        (song2016: the one-step-lag tree-link break of square n = 20, seed 1).
    explore_max_examples : int, optional
        At most this many Hypothesis examples per ``exploration`` row of this algorithm
        (fewer than the gate's when its runs are long: 004's asynchronous agents take
        hundreds of ticks; still a count, never a clock).  None: the gate's number.
    exhaustive : tuple of ExhaustiveCell
        Exhaustive rows (``exhaustive`` section): every choice sequence within each cell's bound.
    explore_properties : tuple of str, optional
        Explore only these properties (None: every registered one).  ``example-gather`` explores
        its lemma premises only (issue 32: its monitor in verify), not the properties an example
        is known to break.
    explore_cost : float, optional
        About how many CPU-seconds this algorithm's ``exploration`` rows take (measured on the
        project machine, docs/performance.md).  It only orders the work when verify explores on
        several processes (``--workers``): costliest first, so that the last task to finish is a
        short one.  It changes no row.  None (unknown): before every algorithm that states one.

    >>> VerifyPlan(("square",)).robots
    10
    >>> VerifyPlan(("square",), more=(("hexagon", 40, (2,)),)).runs()
    (('square', 10, (0, 1, 2)), ('hexagon', 40, (2,)))
    >>> from swarmproof.models.errors import UsageError
    >>> try:
    ...     VerifyPlan(("square",), explore_cost="fast")
    ... except UsageError as exc:
    ...     print(exc.message)
    VerifyPlan explore_cost='fast' must be a number of CPU-seconds >= 0, or None
    """

    targets: tuple = ()
    robots: int = 10
    seeds: tuple = (0, 1, 2)
    explore: bool = True
    rank: int = 100
    more: tuple = ()
    explore_max_examples: int | None = None
    explore_cost: float | None = None
    explore_properties: tuple | None = None
    exhaustive: tuple = ()

    def __post_init__(self) -> None:
        from swarmproof.models.errors import UsageError

        cap = self.explore_max_examples
        if cap is not None and (isinstance(cap, bool) or not isinstance(cap, int) or cap < 1):
            raise UsageError(f"VerifyPlan explore_max_examples={cap!r} must be an integer >= 1, or None",
                             fix="e.g. explore_max_examples=15, or leave it out for the gate's number")
        cost = self.explore_cost
        if cost is not None and (isinstance(cost, bool) or not isinstance(cost, (int, float))
                                 or not math.isfinite(cost) or cost < 0):
            raise UsageError(f"VerifyPlan explore_cost={cost!r} must be a number of CPU-seconds >= 0, or None",
                             fix="e.g. explore_cost=60 (about what its exploration rows take), or leave it out")

    def runs(self) -> tuple:
        """``(target, robots, seeds)`` of every ``algorithms`` row group, in report order."""
        return tuple((t, self.robots, tuple(self.seeds)) for t in self.targets) + tuple(
            (t, int(n), tuple(seeds)) for t, n, seeds in self.more)


@dataclass(frozen=True)
class ExperimentColumn:
    """One column of an experiment's table in a campaign report (by team size).

    Attributes
    ----------
    figure : str
        The figure (a key of the dict the experiment returns).
    header : str
        The column's header.
    stat : str
        ``"count"`` (trials whose figure is a number), ``"median"``, ``"median_range"`` (median
        (min-max)) or ``"mean_sd"`` (mean ± sample standard deviation), over the trials whose
        figure is a number.
    only_if : str, optional
        Only the trials whose figure ``only_if`` is a number count (e.g. a ratio over the
        trials that formed the shape).
    """

    figure: str
    header: str
    stat: str = "median_range"
    only_if: str | None = None

    STATS = ("count", "median", "median_range", "mean_sd")

    def __post_init__(self) -> None:
        from swarmproof.models.errors import UsageError

        if self.stat not in self.STATS:
            raise UsageError(f"ExperimentColumn stat={self.stat!r} is not one of {list(self.STATS)!r}")


@dataclass(frozen=True)
class Experiment:
    """What an experiment function declares (:func:`experiment`): a paper's experiment as seeded
    trials ``fn(n, seed, **options) -> dict of figures`` that a campaign's ``experiment:`` cell
    runs (docs/campaigns.md).

    Attributes
    ----------
    options : tuple of ParamSpec
        Its keyword options, with defaults and ranges: a campaign refuses any other option and a
        value out of range before any task runs.
    robots : (int, int or None)
        The team sizes it takes, ``[MIN, MAX]`` (None: no bound of its own).
    check : callable ``(n, **options) -> None``, optional
        Raises :class:`~swarmproof.models.errors.UsageError` for a team size the options cannot
        hold (e.g. more robots than the arena's cells).
    columns : tuple of ExperimentColumn
        The report's table by team size (empty: every number figure, median (min-max)).
    plot : tuple of str
        Figures the report plots against team size (median and min-max range).
    cites : str
        The paper's experiment it reproduces, e.g. ``"004 Sec. V-A, Fig. 10"``.
    """

    options: tuple = ()
    robots: tuple = (1, None)
    check: Callable | None = field(default=None, compare=False)
    columns: tuple = ()
    plot: tuple = ()
    cites: str = ""


def experiment(*, options=(), robots=(1, None), check=None, columns=(), plot=(), cites: str = ""):
    """Declare ``fn(n, seed, **options) -> dict`` an experiment (its attribute ``experiment``, an
    :class:`Experiment`).  An algorithm lists its experiments in its class attribute
    ``experiments``: name -> ``"module:qualname"`` of such a function.

    The function must be deterministic in its arguments (every random draw seeded from ``n`` and
    ``seed``) and return figures that are numbers, texts, true/false or None: no wall clock and
    no CPU time (a campaign keeps those in its ``timings`` table).  Every declared option must be
    a keyword parameter of the function with the same default.

    Examples
    --------
    >>> @experiment(options=(ParamSpec("side", int, 8, low=1, meaning="arena side"),), robots=(1, 64))
    ... def trial(n, seed, side=8):
    ...     return {"n": n, "side": side}
    >>> trial.experiment.robots, [s.name for s in trial.experiment.options]
    ((1, 64), ['side'])
    >>> experiment(options=(ParamSpec("side", int, 9),))(trial)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: experiment trial declares option side=9 but its parameter's default is 8; fix: give the option the function's default
    """
    import inspect

    from swarmproof.models.errors import UsageError

    def wrap(fn):
        sig = inspect.signature(fn)
        for s in options:
            p = sig.parameters.get(s.name)
            if p is None or p.kind not in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD):
                raise UsageError(f"experiment {fn.__qualname__} declares option {s.name!r} that is not one of "
                                 "its keyword parameters", fix="add the parameter, or drop the option")
            if p.default != s.default:
                raise UsageError(f"experiment {fn.__qualname__} declares option {s.name}={s.default!r} but its "
                                 f"parameter's default is {p.default!r}", fix="give the option the function's default")
        lo, hi = robots
        fn.experiment = Experiment(tuple(options), (int(lo), None if hi is None else int(hi)), check,
                                   tuple(columns), tuple(plot), cites)
        return fn
    return wrap


def reading_of(algorithm) -> str:
    """The reading version of an algorithm class, factory or object (its ``reading`` attribute,
    :data:`DEFAULT_READING` when it declares none).

    >>> class A: reading = "2"
    >>> reading_of(A), reading_of(A()), reading_of(object())
    ('2', '2', '1')
    """
    value = getattr(algorithm, "reading", None)
    return DEFAULT_READING if value is None else str(value)


def steer_toward(target_xy, params: Params, heading: float | None = None,
                 arrive_eps: float = 1e-9, message: Any = None) -> Command:
    """A differential-drive command toward a body-frame point, then a heading.

    Turn toward the target, then drive; once within ``arrive_eps`` of the
    target, turn to ``heading`` (body-frame angle) if one is given.  The
    engine applies the limits; this only chooses the intent.

    Examples
    --------
    >>> p = Params(range=1.0, v=0.1, omega=math.pi, dt=1.0)
    >>> c = steer_toward((0.0, 2.0), p)
    >>> round(c.turn, 6), round(c.forward, 6)
    (1.570796, 2.0)
    >>> steer_toward((0.0, 0.0), p, heading=0.5).turn
    0.5
    """
    x, y = float(target_xy[0]), float(target_xy[1])
    dist = math.hypot(x, y)
    if dist <= arrive_eps:
        return Command(message=message, turn=0.0 if heading is None else float(heading), forward=0.0)
    return Command(message=message, turn=math.atan2(y, x), forward=dist)


def connected_start(cites: str = "001 Sec. III") -> Assumption:
    """The assumption "the communication graph is connected at the start".

    Neighbors are robots strictly closer than ``params.range``
    (:func:`swarmproof.models.sensing.is_connected`, the engine's own rule).

    Examples
    --------
    >>> a = connected_start()
    >>> a.name, a.check(Params(range=1.0), 2, [0, 1]) is None
    ('connected_start', True)
    >>> a.check_start(Params(range=1.0), [0, 1], np.array([[0.0, 0, 0], [2.0, 0, 0]]))
    'the communication graph at range=1.0 is not connected at the start (2 components)'
    """
    from swarmproof.models.sensing import components, is_connected, neighbor_pairs

    def _start(params: Params, ids, poses) -> str | None:
        xy = np.asarray(poses, dtype=float)[:, :2]
        if is_connected(xy, params.range):
            return None
        i, j, _ = neighbor_pairs(xy, params.range)
        k = len(components(len(xy), i, j))
        return (f"the communication graph at range={params.range!r} is not connected at the "
                f"start ({k} components)")

    return Assumption(name="connected_start",
                      statement="the communication graph is connected at the start",
                      cites=cites, check=lambda params, n, ids: None, check_start=_start)
