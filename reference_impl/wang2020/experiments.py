"""The experiments of Wang & Rubenstein 2020 (004 Sec. V-A, Figs. 9-12) and the centralized method
they compare against ([12], Yu & LaValle 2013), as functions.

* :func:`centralized_schedule` -- 004 Sec. V: "every agent is initially assigned a unique goal
  [...] this assignment minimizes the total traveling distance. It is shown in [12] that with
  such optimal initial assignment, the agents' paths will form a acyclic direct graph, and each
  agent's motion can be then scheduled via vertex ordering."  Our reading (docs/decisions.md,
  "Wang & Rubenstein 2020 experiments (issue 15)"): the distance-optimal assignment
  (:func:`~swarmproof.models.assignment.optimal_assignment`), one shortest grid path per agent
  (x first, then y), the vertex order those paths induce (checked acyclic), and a synchronous
  schedule in unit steps (one grid edge per step, l / v seconds): an agent advances when its next
  vertex is free or is being vacated in the same step by an agent moving on (a "train"); agents
  competing for one vertex go in order of the longest remaining path, then the smaller index;
  an agent that reaches a vertex where an agent rests at its goal hands its remaining path over
  (the agents are indistinguishable, [12]'s unlabeled setting), so the total distance stays the
  optimum.  [12]'s bound on the number of steps, ``|A| + d_max - 1`` (004 Sec. V-A), is reported
  beside the schedule's makespan.
* :func:`wang_trial` -- one run of the reference implementation (``wang2020``) toward a goal set
  from seeded start cells, with the per-step series Figs. 11/12 plot (goals reached, distance
  travelled), measured by a streaming observer at every step.

>>> s = centralized_schedule([(0, 0), (1, 0)], [(3, 0), (4, 0)])
>>> s.total_cells, s.optimal_cells, s.steps, s.bound_steps
(6, 6, 3, 4)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from swarmproof.models.assignment import _check_cells, _check_sizes, optimal_assignment
from swarmproof.models.errors import UsageError

__all__ = ["CentralizedSchedule", "centralized_schedule", "shortest_path", "experiment_params", "start_cells",
           "ProgressObserver", "wang_trial", "EXPERIMENT_DT", "EXPERIMENT_BROADCAST_EVERY", "ARENA"]


def shortest_path(start, goal) -> list:
    """One shortest 4-connected grid path from ``start`` to ``goal`` (x first, then y), without
    the start cell.

    >>> shortest_path((0, 0), (2, -1))
    [(1, 0), (2, 0), (2, -1)]
    >>> shortest_path((1, 1), (1, 1))
    []
    """
    (x, y), (gx, gy) = (int(start[0]), int(start[1])), (int(goal[0]), int(goal[1]))
    out = []
    sx = 1 if gx > x else -1
    while x != gx:
        x += sx
        out.append((x, y))
    sy = 1 if gy > y else -1
    while y != gy:
        y += sy
        out.append((x, y))
    return out


def _topological_rank(paths, starts) -> dict:
    """Rank of every vertex in the order the paths induce (u before v when a path visits u and then
    v: [12]'s vertex ordering); raises if the relation has a cycle (then the path set was not
    distance-optimal)."""
    succ: dict = {}
    indeg: dict = {}
    for s, p in zip(starts, paths):
        prev = s
        indeg.setdefault(prev, 0)
        for v in p:
            indeg.setdefault(v, 0)
            if v not in succ.setdefault(prev, set()):
                succ[prev].add(v)
                indeg[v] += 1
            prev = v
    todo = sorted(v for v, d in indeg.items() if d == 0)
    rank = {}
    while todo:
        nxt = []
        for v in todo:
            rank[v] = len(rank)
            for w in sorted(succ.get(v, ())):
                indeg[w] -= 1
                if indeg[w] == 0:
                    nxt.append(w)
        todo = sorted(nxt)
    if len(rank) != len(indeg):
        raise UsageError("the shortest paths of the assignment induce a cyclic vertex order; the assignment "
                         "is not distance-optimal", fix="pass the optimal assignment (goal_of=None)")
    return rank


@dataclass
class CentralizedSchedule:
    """The centralized method of 004 Sec. V ([12]) on one instance.

    Attributes
    ----------
    steps : int
        Makespan in grid steps (one edge per step): the convergence time is ``steps * l / v``.
    bound_steps : int
        [12]'s worst case ``|A| + d_max - 1`` (004 Sec. V-A), d_max the longest assigned distance
        (0 when every agent starts on its goal).
    total_cells, optimal_cells : int
        Edges travelled by all agents, and the optimal assignment's total (equal by construction;
        both reported so a test can compare them).
    reached : list of int
        Goals occupied after each step (index 0: at the start).
    travelled : list of int
        Edges travelled by all agents up to each step (index 0: 0).
    final : list of (int, int)
        Every agent's cell at the end.
    handoffs : int
        How often a moving agent handed its remaining path to an agent resting at its goal.
    positions : list of lists of (int, int), or None
        Every agent's cell after each step (index 0: the start), with ``keep_positions=True``.
    """

    steps: int
    bound_steps: int
    total_cells: int
    optimal_cells: int
    reached: list = field(repr=False)
    travelled: list = field(repr=False)
    final: list = field(repr=False)
    handoffs: int = 0
    positions: list | None = field(default=None, repr=False)


def centralized_schedule(start_cells, goal_cells, *, goal_of=None, max_steps: int | None = None,
                         keep_positions: bool = False) -> CentralizedSchedule:
    """Schedule the distance-optimal assignment along shortest paths by vertex ordering (004 Sec. V,
    [12]); see the module docstring for what is implemented.

    In [12]'s order: the assignment (:func:`_assignment`), one shortest path per agent
    (:func:`shortest_path`), the vertex order they induce (:func:`_topological_rank`), then the
    synchronous schedule along it (:func:`_schedule`).

    Parameters
    ----------
    start_cells, goal_cells : sequences of (i, j)
        Distinct start cells and distinct goal cells, equally many (004 Sec. II-C).
    goal_of : sequence of int, optional
        Agent k's goal index; default the optimal assignment.
    max_steps : int, optional
        Safety cap (default ``4 * (|A| + d_max) + 10``); reaching it raises (a bug, never a result).
    keep_positions : bool
        Keep every step's cells (``positions``), for checks and pictures.

    Returns
    -------
    CentralizedSchedule

    Raises
    ------
    UsageError
        Unequal sizes, repeated start or goal cells, non-integer cells, or a ``goal_of`` whose paths
        induce a cyclic vertex order.

    Examples
    --------
    Two agents in a row, the front one's goal behind the back one's: the optimal assignment sends
    each to the nearer goal and the schedule moves them as a train.

    >>> s = centralized_schedule([(0, 0), (1, 0)], [(2, 0), (3, 0)])
    >>> s.steps, s.total_cells, s.reached
    (2, 4, [0, 1, 2])
    """
    starts, goals, goal_of, opt = _assignment(start_cells, goal_cells, goal_of)
    n = len(starts)
    paths = [shortest_path(starts[k], goals[goal_of[k]]) for k in range(n)]
    rank = _topological_rank(paths, starts)
    d_max = max((len(p) for p in paths), default=0)
    bound = n + d_max - 1 if d_max > 0 else 0
    cap = int(max_steps) if max_steps is not None else 4 * (n + d_max) + 10
    steps, pos, reached, travelled, handoffs, positions = _schedule(starts, paths, rank, set(goals), cap,
                                                                    keep_positions)
    return CentralizedSchedule(steps=steps, bound_steps=bound, total_cells=travelled[-1], optimal_cells=opt.cells,
                               reached=reached, travelled=travelled, final=pos, handoffs=handoffs,
                               positions=positions)


def _assignment(start_cells, goal_cells, goal_of) -> tuple:
    """The cells as tuples of ints, checked, and agent k's goal index (004 Sec. V: "every agent is
    initially assigned a unique goal [...] this assignment minimizes the total traveling distance";
    default the optimal assignment).  Returns ``(starts, goals, goal_of, optimum)``."""
    s = _check_cells("start_cells", start_cells)
    g = _check_cells("goal_cells", goal_cells)
    n = _check_sizes(s, g)
    starts = [tuple(int(v) for v in c) for c in s.tolist()]
    goals = [tuple(int(v) for v in c) for c in g.tolist()]
    if len(set(starts)) != n:
        raise UsageError("start_cells has a repeated cell", fix="give every agent its own start cell")
    opt = optimal_assignment(starts, goals)
    if goal_of is None:
        goal_of = [j for _, j in opt.pairs]
    goal_of = [int(j) for j in goal_of]
    if sorted(goal_of) != list(range(n)):
        raise UsageError(f"goal_of={goal_of!r} is not a permutation of 0..{n - 1}",
                         fix="give each agent its own goal index")
    return starts, goals, goal_of, opt


def _schedule(starts, paths, rank, goal_set, cap: int, keep_positions: bool) -> tuple:
    """The synchronous schedule of the paths (004 Sec. V: "each agent's motion can be then
    scheduled via vertex ordering", [12]): in each unit step the hand-offs (:func:`_hand_off`),
    then one edge for every agent that may move (:func:`_movers`), until every path is done.

    Returns ``(steps, final cells, reached, travelled, handoffs, positions or None)`` as
    :class:`CentralizedSchedule` names them; raises RuntimeError at ``cap`` steps or when no agent
    can move (bugs, never results)."""
    pos = list(starts)
    todo = [list(reversed(p)) for p in paths]          # remaining path, next vertex last
    at = {c: k for k, c in enumerate(pos)}
    reached = [sum(1 for c in pos if c in goal_set)]
    travelled = [0]
    handoffs = 0
    steps = 0
    positions = [list(pos)] if keep_positions else None
    while any(todo):
        if steps >= cap:
            raise RuntimeError(f"centralized schedule did not finish in {cap} steps (a bug)")
        handoffs += _hand_off(todo, at)
        moved = _movers(todo, pos, at, rank)
        if not moved:
            raise RuntimeError("centralized schedule is stuck (a bug: the vertex order is acyclic)")
        for k in moved:
            del at[pos[k]]
        for k in moved:
            pos[k] = todo[k].pop()
            at[pos[k]] = k
        steps += 1
        reached.append(sum(1 for c in pos if c in goal_set))
        travelled.append(travelled[-1] + len(moved))
        if positions is not None:
            positions.append(list(pos))
    return steps, pos, reached, travelled, handoffs, positions


def _hand_off(todo, at) -> int:
    """The hand-offs of one step (004 Sec. V, [12]'s unlabeled agents): when an agent's next vertex
    holds an agent at rest (at its goal), that one takes the rest of the path beyond the vertex and
    the agent goes no farther than the vertex, so the total distance stays the optimum; the one that
    took over may hand off in turn.  Changes ``todo``; returns how many hand-offs."""
    handoffs = 0
    for k0 in range(len(todo)):
        k = k0
        while todo[k]:
            j = at.get(todo[k][-1])
            if j is None or todo[j]:
                break
            rest = todo[k]
            v = rest.pop()
            todo[j], todo[k] = rest, [v]
            handoffs += 1
            k = j
    return handoffs


def _movers(todo, pos, at, rank) -> list:
    """The agents that cross an edge in this step (004 Sec. V, [12]): an agent moves when its next
    vertex is free or is being vacated by an agent that moves on (a "train"); of the agents that
    want one vertex the one with the longest remaining path goes, then the one whose cell comes
    first in the vertex order, then the smaller index.  Returns their indices."""
    n = len(todo)
    want: dict = {}
    for k in range(n):
        if todo[k]:
            want.setdefault(todo[k][-1], []).append(k)
    winner = {v: min(ks, key=lambda k: (-len(todo[k]), rank[pos[k]], k)) for v, ks in want.items()}
    moves: dict = {}
    for k in range(n):
        if not todo[k] or k in moves:
            continue
        chain, on, cur = [], set(), k
        while True:            # k waits on the agent in its next vertex, that one on the next ...
            if cur in moves:
                ok = moves[cur]
                break
            if cur in on:      # a rotation (impossible with an acyclic order): nobody on it moves
                ok = False
                break
            chain.append(cur)
            on.add(cur)
            v = todo[cur][-1]
            j = at.get(v)
            if winner[v] != cur or (j is not None and not todo[j]):
                ok = False
                break
            if j is None:
                ok = True
                break
            cur = j
        for c in chain:
            moves[c] = ok
    return [k for k, ok in moves.items() if ok]


# -- the decentralized runs (004 Sec. V-A) ---------------------------------------------------------

#: Our time step and f_comm for the experiments (docs/decisions.md, "Wang & Rubenstein 2020
#: experiments (issue 15)"): dt = 0.1 s, a broadcast every tick (f_comm = 10 Hz), so Delta t =
#: 2 / f_comm = 0.2 s (Alg. 2 line 6); an edge (l / v = 4 s) takes 40 ticks.
EXPERIMENT_DT = 0.1
EXPERIMENT_BROADCAST_EVERY = 1.0
#: 004 Sec. V-A's arena is "fixed-size" but not given: 32 x 32 waypoints (1,024, the largest swarm).
ARENA = 32


def experiment_params(n: int, **extra):
    """:func:`~swarmproof.reference_impl.wang2020.default_params` with the experiments' time step and
    f_comm (:data:`EXPERIMENT_DT`, :data:`EXPERIMENT_BROADCAST_EVERY`); ``extra`` overrides
    ``params.extra`` (e.g. ``p_random=1.0`` for the random selector of Fig. 11).

    >>> p = experiment_params(16)
    >>> p.dt, p.extra["broadcast_every"], p.v
    (0.1, 1.0, 0.05)
    """
    import dataclasses

    from .algorithm import default_params

    p = dataclasses.replace(default_params(0.6, n), dt=EXPERIMENT_DT)
    p.extra.update({"broadcast_every": EXPERIMENT_BROADCAST_EVERY, **extra})
    return p


def start_cells(goals, n: int, rng: np.random.Generator, *, arena: int = ARENA) -> list:
    """n start cells drawn uniformly from an ``arena x arena`` square centred on the goals' centre
    of mass (004 Sec. V-A: "a random initialization" in a fixed-size arena; Fig. 11: "a uniform
    random distribution centered at the shape's center of mass")."""
    from swarmproof.models.shapes import centered_arena, random_start_cells

    return random_start_cells(n, centered_arena(goals, arena), rng)


def fig10_instance(n: int, seed: int, arena: int = ARENA) -> tuple:
    """Fig. 10's trial ``(n, seed)``: ``(goal set, start cells)``, a random connected shape of n
    cells (``random_shape``) and n starts uniform in the ``arena``, both from
    ``numpy.random.default_rng([n, seed])`` (the benchmarks' one drawing of it)."""
    from swarmproof.models.shapes import random_shape

    rng = np.random.default_rng([n, seed])
    goals = random_shape(n, rng)
    return goals, start_cells(goals.cells, n, rng, arena=arena)


class ProgressObserver:
    """A streaming monitor (engine ``observers``) of one run toward a goal set, seeing every step:
    goals occupied by an agent resting on them, the distance travelled by all agents (metres, exact:
    grid motion is one straight segment per step), and the first step at which every goal is
    occupied (the shape is formed).  ``every``: keep the series every k steps (and the last)."""

    name = "wang2020_progress"

    def __init__(self, goal_cells, spacing: float, every: int = 10) -> None:
        self.goals = np.array(sorted(tuple(c) for c in goal_cells), dtype=np.int64)
        self.l = float(spacing)
        self.every = int(every)
        # the goals as a boolean grid over their bounding box (occupied() looks cells up in it)
        self._lo = self.goals.min(axis=0) if len(self.goals) else np.zeros(2, dtype=np.int64)
        size = (self.goals.max(axis=0) - self._lo + 1) if len(self.goals) else np.zeros(2, dtype=np.int64)
        self._grid = np.zeros(tuple(int(v) for v in size), dtype=bool)
        self._grid[tuple((self.goals - self._lo).T)] = True

    def start(self, ids) -> None:
        self.prev = None
        self._on = None             # per agent: the goal-grid cell it rests on (flat index), or -1
        self.distance = 0.0
        self.formed_step = None
        self.series = []          # (step, goals occupied, distance)
        self.last = None

    def occupied(self, poses) -> int:
        """How many goals have an agent resting on them (each goal counted once)."""
        xy = poses[:, :2] / self.l
        cells = np.rint(xy)
        rest = np.abs(xy - cells).max(axis=1) <= 1e-9
        c = cells[rest].astype(np.int64) - self._lo
        shape = self._grid.shape
        c = c[(c[:, 0] >= 0) & (c[:, 1] >= 0) & (c[:, 0] < shape[0]) & (c[:, 1] < shape[1])]
        held = np.zeros(shape, dtype=bool)
        held[c[:, 0], c[:, 1]] = True
        return int(np.count_nonzero(held & self._grid))

    def _resting_cells(self, xy) -> np.ndarray:
        """Per agent (rows of ``xy``, metres), the flat index in the goals' bounding box of the cell
        it rests on, or -1 (moving, or outside the box): :meth:`occupied`'s test, row by row."""
        xy = xy / self.l
        cells = np.rint(xy)
        rest = np.abs(xy - cells).max(axis=1) <= 1e-9
        c = cells.astype(np.int64) - self._lo
        shape = self._grid.shape
        ok = rest & (c[:, 0] >= 0) & (c[:, 1] >= 0) & (c[:, 0] < shape[0]) & (c[:, 1] < shape[1])
        return np.where(ok, c[:, 0] * shape[1] + c[:, 1], -1)

    def _occupied_since(self, xy) -> int:
        """:meth:`occupied` of the positions ``xy`` (metres), updated from the last call's for the
        agents whose position changed since (agents per cell of the box, counted)."""
        if self._on is None:
            self._on = self._resting_cells(xy)
            self._count = np.bincount(self._on[self._on >= 0], minlength=self._grid.size)
            self._on_xy = xy
            return int(np.count_nonzero((self._count > 0) & self._grid.ravel()))
        last, self._on_xy = self._on_xy, xy
        moved = np.flatnonzero((xy[:, 0] != last[:, 0]) | (xy[:, 1] != last[:, 1]))
        if len(moved):
            old, new = self._on[moved], self._resting_cells(xy[moved])
            np.subtract.at(self._count, old[old >= 0], 1)
            np.add.at(self._count, new[new >= 0], 1)
            self._on[moved] = new
        return int(np.count_nonzero((self._count > 0) & self._grid.ravel()))

    def observe(self, t, poses, states, present) -> None:
        if self.prev is not None:
            d = poses[:, :2] - self.prev
            self.distance += float(np.sqrt((d * d).sum(axis=1)).sum())
        self.prev = np.array(poses[:, :2])
        occ = None
        if self.formed_step is None or t % self.every == 0:
            occ = self._occupied_since(self.prev)
            if self.formed_step is None and occ == len(self.goals):
                self.formed_step = t
        if t % self.every == 0:
            self.series.append((t, occ, self.distance))
        self.last = (t, occ, self.distance)

    def result(self) -> dict:
        series = list(self.series)
        if self.last is not None and (not series or series[-1][0] != self.last[0]):
            t, occ, d = self.last
            series.append((t, self.occupied(self.prev) if occ is None else occ, d))
        return {"formed_step": self.formed_step, "distance": self.distance, "series": series}


def wang_trial(goals, starts, seed: int, *, params=None, then=(), stop_when_formed: bool = True,
               record_every: int = 1000, every: int = 10, max_steps: int | None = None,
               vectorised: bool = True) -> dict:
    """One run of ``wang2020`` toward ``goals`` (a GoalSet) from ``starts`` (cells), seeded.

    Returns a dict: ``status``, ``steps``, ``formed_step`` (first step with every goal occupied, or
    None), ``formed_s`` (that times dt), ``distance_m`` (all agents), ``series`` ((step, goals
    occupied, distance) every ``every`` steps), ``result`` (the SimulationResult; sparse trace).
    With ``stop_when_formed`` the run stops once the shape is formed (the convergence time of
    Fig. 10); otherwise it runs until every agent detects completion (Sec. III-B) or the cap.
    ``vectorised``: run it on :func:`~swarmproof.reference_impl.wang2020.fast.simulate_fast` (the
    same trace as the per-robot reference, tested bit for bit; ``False``: the reference itself).
    """
    from swarmproof.models.trace import InitialConfiguration
    from swarmproof.reference_impl.engine import simulate
    from .algorithm import Wang2020, goal_cells

    n = len(starts)
    params = params if params is not None else experiment_params(n)
    l = float(params.extra["grid_spacing"])
    alg = Wang2020(then=then)
    init = InitialConfiguration(list(range(n)), [[l * x, l * y, 0.0] for x, y in starts])
    ob = ProgressObserver(goal_cells(goals, l), l, every=every)
    stop = (lambda t, poses, states, present: ob.formed_step is not None) if stop_when_formed else None
    if vectorised:
        from swarmproof.reference_impl.wang2020.fast import simulate_fast as simulate   # noqa: F811
    r = simulate(alg, goals, init, params, seed=seed, record_every=record_every, observers=[ob],
                 stop_when=stop, max_steps=max_steps)
    res = ob.result()
    return {"status": r.status, "steps": r.steps, "formed_step": res["formed_step"],
            "formed_s": None if res["formed_step"] is None else res["formed_step"] * params.dt,
            "distance_m": res["distance"], "series": res["series"], "dt": params.dt, "result": r}


# -- Fig. 10 as a campaign experiment (004 Sec. V-A) --------------------------------------------

def _experiment_constants() -> tuple:
    """``(l, l / v)`` of the experiments: wang2020's grid length (004 Sec. V-B3, 0.2 m) and one
    centralized step, one grid edge at Sec. V-A's v = 0.05 m/s (4 s), read from
    :func:`experiment_params` (never restated)."""
    p = experiment_params(1)
    l = float(p.extra["grid_spacing"])
    return l, l / p.v


#: The grid length l in metres (004 Sec. V-B3) and one centralized step l / v in seconds.
GRID_LENGTH, EDGE_S = _experiment_constants()

__all__ += ["GRID_LENGTH", "EDGE_S", "random_assignment_cells", "fig10_task"]


def random_assignment_cells(starts, goals) -> float:
    """The expected total distance, in grid edges, of a uniformly random assignment of the agents
    to the goals: n times the mean start-goal Manhattan distance (every agent is equally likely
    to get each goal).  The baseline beside the optimum for Fig. 10's ratio (docs/wang2020.md,
    "Why the distance ratio grows with n").

    >>> random_assignment_cells([(0, 0), (2, 0)], [(0, 0), (1, 0)])
    2.0
    """
    S, G = np.asarray(starts, dtype=np.int64), np.asarray(goals, dtype=np.int64)
    return float(np.abs(S[:, None, :] - G[None, :, :]).sum(-1).mean() * len(S))


def _fig10_fits(n: int, arena: int = ARENA) -> None:
    """n distinct start cells need an arena of at least n cells (:func:`start_cells`)."""
    if n > arena * arena:
        raise UsageError(f"robots={n} is more than the arena={arena}x{arena} holds ({arena * arena} start cells)",
                         fix=f"give at most {arena * arena} robots, or a larger arena "
                             f"(options: {{arena: {math.isqrt(n - 1) + 1}}})")


def _fig10_declaration():
    from swarmproof.reference_impl.protocol import ExperimentColumn as C, ParamSpec, experiment

    return experiment(
        options=(ParamSpec("arena", int, ARENA, low=1, high=1024,
                           meaning="the side of the square arena the starts are drawn in, in waypoints, centred "
                                   "on the shape (004 Sec. V-A: fixed-size, not given; 32 here)"),),
        # the paper's swarms are 16..529 (Fig. 10) and 1,024 (Fig. 9); a 4,096-agent trial already
        # takes hours here (docs/performance.md)
        robots=(1, 4096), check=_fig10_fits,
        columns=(C("formed_s", "formed", "count"), C("formed_s", "formed (s)", "median"),
                 C("central_s", "centralized (s)", "median"),
                 C("ratio", "distance ratio", "median_range", only_if="formed_s"),
                 C("random_ratio", "random-assignment ratio", "median")),
        plot=("ratio", "random_ratio"), cites="004 Sec. V-A, Fig. 10")


@_fig10_declaration()
def fig10_task(n: int, seed: int, arena: int = ARENA) -> dict:
    """One trial of 004 Fig. 10 (Sec. V-A): the figures of the decentralized run to formation and of
    the centralized method [12] on the same instance, for a campaign's ``experiment:`` cell
    (``wang2020``'s experiment ``fig10``).

    The instance is :func:`fig10_instance` ``(n, seed, arena)``: a random connected shape of n
    cells and n starts uniform in an ``arena x arena`` square.  Deterministic: no wall clock, no
    CPU time (a campaign keeps those apart).

    Returns
    -------
    dict
        ``status`` and ``steps`` of the run (stopped once formed), ``formed_s`` (simulated seconds
        until every goal is occupied, None if never), ``distance_m`` (all agents), the centralized
        method's ``central_distance_m`` (the optimum), ``central_s`` (its makespan, one edge per
        l / v = 4 s) and ``central_bound_s`` ([12]'s bound), ``ratio`` = distance_m /
        central_distance_m (the paper's "only around 20% more", Sec. V-A; Fig. 10 plots the
        distances per robot and the times), ``random_assignment_m`` (the expected cost of a
        uniformly random assignment, :func:`random_assignment_cells` times l) and
        ``random_ratio`` = random_assignment_m / central_distance_m (ratios None when the optimum
        is 0).

    References
    ----------
    004 Sec. V-A, Fig. 10 ("200 trials" per swarm size, distance compared with the centralized
    method [12]).
    """
    goals, starts = fig10_instance(n, seed, arena)
    w = wang_trial(goals, starts, seed)
    cells = sorted(goals.cells)
    c = centralized_schedule(starts, cells)
    central_m = c.total_cells * GRID_LENGTH
    random_m = random_assignment_cells(starts, cells) * GRID_LENGTH
    return {"status": w["status"], "formed_s": w["formed_s"], "steps": w["steps"], "distance_m": w["distance_m"],
            "central_distance_m": central_m, "central_s": c.steps * EDGE_S, "central_bound_s": c.bound_steps * EDGE_S,
            "ratio": w["distance_m"] / central_m if c.total_cells else None,
            "random_assignment_m": random_m, "random_ratio": random_m / central_m if c.total_cells else None}
