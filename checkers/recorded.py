"""Judge a recorded run (a real swarm's log) by the same property objects as the engine's runs.

A log is asynchronous: each robot reports its pose at its own, irregular times.  The properties
judge a run one instant after another, so the samples are first aligned on a common clock
(:class:`Clock`):

* **the clock** ticks every ``period`` (default: the median interval between a robot's
  consecutive samples, over all robots: the log's own rate), from the first instant at which
  every robot has reported (the latest first sample) to the last sample of the log;
* **sample and hold**: at each instant a robot is where its latest sample (at or before the
  instant) put it, and its parent is its latest parent sample (an event stream: a parent holds
  until it changes, however old);
* **staleness**: a pose sample older than ``stale`` (default 2.5 periods: one dropped sample is
  tolerated, two are not) is not evidence at that instant.  An instant at which some robot has no
  fresh sample is *not judged*: it splits the run into windows of judged instants, and the
  every-step properties are judged window by window with fresh monitors (no motion is invented
  across a gap).  A violation in any window is a violation; held needs every instant judged --
  a log with any unjudged instant is at best inconclusive, never held.

The properties are the registry's own objects (:mod:`swarmproof.invariants.registry`), fed the
aligned instants through their streaming monitors (the engine's ``observers``), so a verdict on
a log means what it means on a simulated run; what the log lacks makes a property not
applicable (controller state beyond the parent, messages, exceptions, a target).  A position
tolerance (``pos_tol``: how far a logged pose may be from the true one) widens into margins:
the range by ``2 pos_tol`` (two robots' errors add), the collision radius by ``pos_tol``.  Each
distance property is judged at its nominal value and at the margin that could overturn it; a
verdict that the tolerance could overturn says so (``tolerance_sensitive``).

Examples
--------
>>> import os, tempfile
>>> from swarmproof.models.recorded_io import read_log
>>> d = tempfile.mkdtemp(); p = os.path.join(d, "run.csv")
>>> rows = [f"{k / 10},{i},{i * (0.5 + 0.1 * k)},0,0" for k in range(10) for i in range(3)]
>>> _ = open(p, "w").write("t,id,x,y,theta\\n" + "\\n".join(rows) + "\\n")
>>> rep = check_recorded(read_log(p), phi=1.0, properties=["connectivity"])
>>> r = rep.results["connectivity"]
>>> r.status, r.witness["step"], r.witness["time_s"]
('violated', 5, 0.5)
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, Iterator, Mapping, Sequence

import numpy as np

from swarmproof.invariants.registry import DEFAULT_POS_TOL, PropertyContext, collision_radius, get_property
from swarmproof.invariants.registry import properties as registered_properties
from swarmproof.invariants.result import InvariantResult
from swarmproof.models.errors import UsageError
from swarmproof.models.recorded_io import NS, RecordedLog
from swarmproof.models.trace import Trace

__all__ = ["fmt_s", "shown_at", "Clock", "make_clock", "aligned_frames", "check_recorded", "RecordedReport", "DEFAULT_STALE_PERIODS",
           "DEFAULT_STATIC_WINDOW_S", "MAX_INSTANTS", "TOLERANCE_KNOBS"]

DEFAULT_STALE_PERIODS = 2.5
DEFAULT_STATIC_WINDOW_S = 2.0
#: Instants judged at most (a 100 Hz clock over 27 hours); past it, exit 2.
MAX_INSTANTS = 10_000_000
CHUNK = 1024

#: Property -> (what the margin widens, the direction that makes the property harder to hold).
TOLERANCE_KNOBS = {"connectivity": ("range", -1), "tree_links": ("range", -1), "collision": ("radius", +1)}


def fmt_s(seconds: float) -> str:
    """Seconds as a log shows them: no exponent (epoch stamps stay readable), to the nanosecond below
    1e5 s and to the microsecond above (a double holds no more there).

    >>> fmt_s(14.9998), fmt_s(1767225600.1), fmt_s(0.25), fmt_s(3.0)
    ('14.9998', '1767225600.1', '0.25', '3')
    """
    return f"{seconds:.{9 if abs(seconds) < 1e5 else 6}f}".rstrip("0").rstrip(".")


@dataclass(frozen=True)
class Clock:
    """The common clock of a log: instant ``k`` is at ``start_ns + k * period_ns``."""

    start_ns: int
    period_ns: int
    stale_ns: int
    instants: int
    log_start_ns: int
    log_end_ns: int
    time: str
    #: each robot's staleness bound (ns), in id order: its own sampling interval's multiple, or --stale
    stale_by: tuple = ()

    def seconds(self, k: float) -> float:
        return (self.start_ns + k * self.period_ns) / NS

    def as_dict(self) -> dict:
        lo = min(self.stale_by) if self.stale_by else self.stale_ns
        return {"time": self.time, "start_s": self.start_ns / NS, "end_s": self.seconds(self.instants - 1),
                "period_s": self.period_ns / NS, "stale_s": self.stale_ns / NS, "stale_min_s": lo / NS,
                "instants": self.instants, "log_start_s": self.log_start_ns / NS, "log_end_s": self.log_end_ns / NS}


def _seconds_ns(value: float, name: str) -> int:
    if value is None or not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise UsageError(f"{name}={value!r} must be a finite positive number of seconds",
                         fix=f"e.g. {name}=0.1")
    return max(1, int(round(value * NS)))


def make_clock(log: RecordedLog, *, period: float | None = None, stale: float | None = None) -> Clock:
    """The clock of ``log``: its period (the median sampling interval unless given), staleness bound
    (``DEFAULT_STALE_PERIODS`` periods unless given), first instant (the last robot's first sample
    when they all report within the staleness bound of the first, else the first sample) and
    number of instants."""
    robots = [log.robots[rid] for rid in sorted(log.robots)]
    _one_time_base(log, robots)
    diffs = [np.diff(r.t) for r in robots if len(r.t) > 1]
    if period is None:
        if not diffs:
            raise UsageError(f"log={log.path!r}: every robot has one sample; the sampling period cannot be measured",
                             fix="give the clock's period, e.g. --period 0.1")
        period_ns = int(np.median(np.concatenate(diffs)))
    else:
        period_ns = _seconds_ns(period, "--period")
    if stale is None:
        # each robot by its own rate: a 5 Hz robot among 50 Hz ones is not stale between its samples
        own = [int(np.median(np.diff(r.t))) if len(r.t) > 1 else period_ns for r in robots]
        stale_by = tuple(int(round(DEFAULT_STALE_PERIODS * max(o, period_ns))) for o in own)
    else:
        stale_by = (_seconds_ns(stale, "--stale"),) * len(robots)
    stale_ns = max(stale_by)
    first = [int(r.t[0]) for r in robots]
    last = [int(r.t[-1]) for r in robots]
    # robots that start together (their first samples within the staleness bound): the clock starts
    # when the last of them has reported, so every robot is on it from its first instant; else at the
    # first sample, and a robot is in the swarm from its own first report on (as a robot the engine
    # adds later): nothing before a late robot's first report is dropped
    start, end = (max(first) if max(first) - min(first) <= stale_ns else min(first)), max(last)
    instants = -(-(end - start) // period_ns) + 1      # the last instant at or after the last sample
    if instants > MAX_INSTANTS:
        raise UsageError(f"the clock would have {instants} instants (period {period_ns / NS} s over "
                         f"{(end - start) / NS} s; max_instants={MAX_INSTANTS})",
                         fix="give a longer --period, or judge a part of the log")
    times = sorted({r.time_source for r in robots})
    return Clock(start, period_ns, stale_ns, int(instants), min(first), end, "+".join(times), stale_by)


def _span(ts) -> tuple:
    return min(int(t[0]) for t in ts), max(int(t[-1]) for t in ts)


def _one_time_base(log: RecordedLog, robots) -> None:
    """Header stamps and log times may count from different origins (simulated time from 0, the
    recorder's wall clock from 1970): poses on one and parents or states (log time) or other poses
    on the other never meet.  Refused with the fix, instead of a clock of 10^10 instants or parents
    that silently never apply."""
    groups: dict = {}
    for r in robots:
        groups.setdefault(r.time_source, []).append(r.t)
    extra = [("parents", [p.t for p in (log.parents or {}).values() if len(p.t)]),
             ("states", [s.t for s in (log.states or {}).values() if len(s.t)])]
    spans = [(f"poses ({src} time)", _span(ts)) for src, ts in sorted(groups.items())]
    if "header" in groups:
        spans += [(f"{what} (log time)", _span(ts)) for what, ts in extra if ts]
    for i in range(len(spans)):
        for j in range(i + 1, len(spans)):
            (a, (a0, a1)), (b, (b0, b1)) = spans[i], spans[j]
            if a1 < b0 or b1 < a0:
                raise UsageError(f"the log's times are on two bases: {a} from {fmt_s(a0 / NS)} s to {fmt_s(a1 / NS)} s, "
                                 f"{b} from {fmt_s(b0 / NS)} s to {fmt_s(b1 / NS)} s (they never overlap: header "
                                 "stamps on simulated time, log times on the recorder's clock?)",
                                 fix="judge every message by its log time: --time log")


class _States(tuple):
    """The controller states of one instant as the log gives them: ``(("parent", p),)`` per robot
    (``()`` when the log has no parents), with the fast column read the monitors use."""

    def values_of(self, key: str):
        if key == "parent":
            return self.parents
        return [None] * len(self)


class _Logged(tuple):
    """One robot's state as the log holds it: its parent only.  A lemma binding that reads another
    key finds it missing even where it gives a default (the key was not logged; the controller
    may well have had it): ``logged_only``."""

    logged_only = True


_EMPTY = _Logged()


@lru_cache(maxsize=1 << 16)
def _logged_parent(p) -> _Logged:
    """The (immutable) state of a robot whose logged parent is ``p``: one object per parent, shared by
    every instant that holds it (building them anew was a third of judging a log with parents)."""
    return _Logged((("parent", p),))


def _states(parents: Sequence | None, n: int, log: RecordedLog | None = None, sidx=None) -> _States:
    """The states of one instant: with logged controller states (``log.states``, ``sidx`` each robot's
    index of its latest state sample, -1 none yet) those states, whole; else the parents only."""
    if sidx is not None:
        from swarmproof.invariants.result import state_value

        ids = sorted(log.states)
        got = [log.states[rid].values[i] if i >= 0 else None for rid, i in zip(ids, sidx.tolist())]
        s = _States(got)
        s.parents = [state_value(st, "parent") for st in got]
        return s
    if parents is None:
        s = _States((_EMPTY,) * n)
        s.parents = [None] * n
        return s
    raw = parents.tolist() if isinstance(parents, np.ndarray) else parents
    pl = [None if p < 0 else int(p) for p in raw]
    s = _States(map(_logged_parent, pl))
    s.parents = pl
    return s


def aligned_frames(log: RecordedLog, clock: Clock, chunk: int = CHUNK) -> Iterator:
    """``(k, poses (n x 3), parents (n,) int or None, fresh (n,) bool, present (n,) bool, sidx (n,)
    int or None)`` at every instant, in order (present: the robot has reported by then -- before its
    first sample a robot is not in the swarm yet, as a robot the engine adds later; fresh: present
    and its pose no older than the staleness bound; sidx: with logged states, each robot's latest
    state sample, -1 none yet -- a state, like a parent, holds until it changes),
    ``chunk`` instants computed at a time (memory stays bounded by the chunk)."""
    ids = sorted(log.robots)
    n = len(ids)
    for k0 in range(0, clock.instants, chunk):
        k1 = min(clock.instants, k0 + chunk)
        grid = clock.start_ns + clock.period_ns * np.arange(k0, k1, dtype=np.int64)
        poses = np.empty((k1 - k0, n, 3))
        fresh = np.empty((k1 - k0, n), dtype=bool)
        present = np.empty((k1 - k0, n), dtype=bool)
        pars = np.full((k1 - k0, n), -1, dtype=np.int64) if log.parents is not None else None
        sidx = np.full((k1 - k0, n), -1, dtype=np.int64) if log.states is not None else None
        for j, rid in enumerate(ids):
            r = log.robots[rid]
            idx = np.searchsorted(r.t, grid, side="right") - 1
            ok = idx >= 0
            idx0 = np.where(ok, idx, 0)
            poses[:, j] = r.xyt[idx0]
            fresh[:, j] = ok & (grid - r.t[idx0] <= (clock.stale_by[j] if clock.stale_by else clock.stale_ns))
            present[:, j] = ok
            if pars is not None:
                p = log.parents[rid]
                pi = np.searchsorted(p.t, grid, side="right") - 1
                pars[:, j] = np.where(pi >= 0, p.parent[np.maximum(pi, 0)], -1)
            if sidx is not None:
                sidx[:, j] = np.searchsorted(log.states[rid].t, grid, side="right") - 1
        for i in range(k1 - k0):
            yield (k0 + i, poses[i], (None if pars is None else pars[i]), fresh[i], present[i],
                   (None if sidx is None else sidx[i]))


# ----------------------------------------------------------------------------
# what the log can give: the stand-in algorithm and the run's result
# ----------------------------------------------------------------------------

class _Recorded:
    """What the properties read of "the algorithm" for a log: a range graph, the parent field
    when the log has parents, and -- with ``--algorithm`` -- that algorithm's name, satisfaction
    tolerance and lemma premise monitors (judged on what the log holds)."""

    def __init__(self, algorithm, has_parent: bool, has_states: bool = False) -> None:
        from swarmproof.reference_impl.protocol import RobotModel

        # the algorithm's model: its communication (a complete graph has no range graph to split) and
        # neighbour rule (004's robots hear at distance <= R)
        self.model = getattr(algorithm, "model", None) or RobotModel(communication="neighbors")
        self.state_fields = ("parent",) if has_parent else ()
        self.name = getattr(algorithm, "name", None) or "recorded run"
        self.has_states = has_states
        attrs = ("satisfaction_tol", "premise_monitors", "tree_link_mode")
        if has_states:
            # the log holds the controllers' states: everything the algorithm declares over them
            attrs += ("state_fields", "invariants", "completion_invariants", "properties", "progress_measure",
                      "randomized")
        if algorithm is not None:
            for attr in attrs:
                if getattr(algorithm, attr, None) is not None:
                    setattr(self, attr, getattr(algorithm, attr))


@dataclass
class _Result:
    """The parts of a :class:`~swarmproof.reference_impl.engine.run.SimulationResult` the
    properties read, for one window of a log."""

    status: str
    steps: int
    max_steps: int | None
    static_window: int
    final_ids: np.ndarray
    final_poses: np.ndarray
    crash: Any = None
    observers: tuple = ()
    trace: Any = None


#: Properties a log cannot judge, whatever it holds, and why.
_NEVER = {"no_crash": "a log records no exceptions of the algorithm's code",
          "invariants": "the log records poses and parents; an algorithm's invariants read its controller states",
          "completion_sound": "the log records no completion declarations (controller states)"}
_NEEDS_TARGET = ("formation", "deadlock", "oscillation")


def _not_applicable(prop, stand_in, target, log: RecordedLog, algorithm) -> str | None:
    if prop.name in _NEVER and (log.states is None or prop.name == "no_crash"):
        return _NEVER[prop.name]
    if prop.own and log.states is None:
        return f"{prop.name} is an algorithm's own property: it reads controller states a log does not hold"
    if prop.name in ("invariants", "completion_sound") and algorithm is None:
        what = "runtime invariants" if prop.name == "invariants" else "completion invariants"
        return f"no algorithm given (--algorithm): {prop.name} judges the {what} an algorithm declares"
    if prop.name in _NEEDS_TARGET and target is None:
        return ("no target given (--target): " + ("the final formation is judged against one" if prop.name == "formation"
                else "a swarm at rest cannot be told from a swarm at its goal without one"))
    if prop.name == "premises" and algorithm is None:
        return "no algorithm given (--algorithm): its lemma premise monitors are what premises judges"
    why = prop.not_applicable_to(stand_in, target)
    if why and prop.needs == ("parent", "range_graph") or (why and "parent" in why):
        return "the log has no parent links (a CSV 'parent' column, or parent topics)"
    return why


# ----------------------------------------------------------------------------
# judging
# ----------------------------------------------------------------------------

@dataclass
class RecordedReport:
    """What :func:`check_recorded` found: each property's result, the not-applicable ones, the
    clock, the windows of judged instants and the tolerances."""

    log: RecordedLog
    clock: Clock
    results: dict
    not_applicable: dict
    judged_instants: int
    gaps: list
    tolerance: dict
    sensitive: dict
    phi: float
    radius: float
    static: bool
    frames: list = field(default_factory=list)

    @property
    def ids(self) -> list:
        return sorted(self.log.robots)


def _unseen_samples(log: RecordedLog, clock: Clock) -> int:
    """How many pose samples no instant holds: sample i holds over [t_i, t_i+1) (the last to the
    clock's end), and is seen when an instant falls in it."""
    total = 0
    last_instant = clock.start_ns + (clock.instants - 1) * clock.period_ns
    for r in log.robots.values():
        t = r.t
        k = -((clock.start_ns - t) // clock.period_ns)                # the first instant at or after t_i
        at = clock.start_ns + np.maximum(k, 0) * clock.period_ns
        until = np.append(t[1:], last_instant + 1)
        total += int(np.count_nonzero(at >= until))
    return total


def shown_at(name: str, witness: Mapping) -> float:
    """The step count (fractional) at which a property's violation first shows: a collision inside
    its step, at its fraction; a tree link broken in step t at t + 1 (it held at t); any other at its
    step.  check-run's ``time_s`` and ``instant``, the picture's focus and export's marker use it.

    >>> shown_at("collision", {"step": 39, "fraction": 1.0}), shown_at("tree_links", {"step": 2}), shown_at("connectivity", {"step": 3})
    (40.0, 3.0, 3.0)
    """
    step = float(witness["step"])
    if name == "collision":
        return step + float(witness.get("fraction", 0.0) or 0.0)
    return step + 1.0 if name == "tree_links" else step


def _with_time(res: InvariantResult, clock: Clock) -> InvariantResult:
    """The witness's step as the log's time too: ``time_s`` and ``instant``, where the violation first
    shows (a collision inside its step, at its fraction; a link broken in step t at instant t + 1;
    any other at its step's instant).  ``step`` stays the monitor's own count, as in simulated runs."""
    w = dict(res.witness or {})
    if "step" in w and isinstance(w["step"], (int, np.integer)):
        # the first log time at which the violation shows: a collision inside its step (the fraction), a
        # tree link broken in step t at instant t + 1 (it held at t), any other at its instant
        at = shown_at(res.name, w)
        w["time_s"] = round(clock.seconds(at), 9)
        w["instant"] = int(math.ceil(round(at, 9)))
        return InvariantResult(res.name, res.status, res.cites, w,
                               res.message + f" (seen at {fmt_s(w['time_s'])} s, instant {w['instant']})",
                               res.applicable, dict(res.detail))
    return res


def _params(phi: float, v: float | None, clock: Clock, algorithm, n: int):
    """The run's parameters as a log gives them: the algorithm's defaults (its speed and ``extra``,
    e.g. 004's ``robot_radius``), the range, and one step per instant of the clock."""
    from swarmproof.reference_impl.protocol import Params

    base = None
    f = getattr(algorithm, "default_params", None)
    if callable(f):
        try:
            base = f(range=phi, n=n)
        except Exception:  # noqa: BLE001 - an algorithm whose defaults need more: the log's own
            base = None
    extra = dict(getattr(base, "extra", None) or {})
    return Params(range=phi, v=float(v if v is not None else getattr(base, "v", 0.05)),
                  dt=clock.period_ns / NS, extra=extra)


class _Judge:
    """Every windowed property's monitors for one window, fed the window's instants."""

    def __init__(self, props, stand_in, params_of, options_of, ids) -> None:
        self.props, self.stand_in, self.params_of, self.options_of, self.ids = props, stand_in, params_of, options_of, ids

    def monitors(self):
        out = []
        for key, prop in self.props:
            ob = prop.stream(self.stand_in, self.params_of(key), self.options_of(key))
            ob.start(np.asarray(self.ids))
            out.append((key, prop, ob))
        return out


def check_recorded(log: RecordedLog, *, phi: float, target=None, algorithm=None, properties: Sequence | None = None, radius: float | None = None, pos_tol: float = 0.0,
                   range_margin: float | None = None, collision_margin: float | None = None,
                   period: float | None = None, stale: float | None = None, v: float | None = None,
                   static_window: float = DEFAULT_STATIC_WINDOW_S, keep_frames: int = 0,
                   options: Mapping | None = None, progress=None) -> RecordedReport:
    """Judge ``log`` by ``properties`` (names; default every registered property) at range ``phi``.

    ``algorithm`` (an algorithm object) gives its satisfaction tolerance, speed and lemma premise
    monitors; ``target`` the formation to judge the final instant against; ``pos_tol`` the
    position tolerance (margins: ``range_margin`` default ``2 pos_tol``, ``collision_margin``
    default ``pos_tol``); ``keep_frames`` keeps about that many instants for pictures.
    """
    names = list(properties if properties is not None else [p.name for p in registered_properties() if not p.own])
    if properties is None and algorithm is not None and log.states is not None:
        from swarmproof.invariants.registry import own_properties_of

        names += [n for n in own_properties_of(algorithm) if n not in names]   # its own, over the logged states
    for name, val in (("--range", phi), ("--pos-tol", pos_tol)):
        if not (isinstance(val, (int, float)) and math.isfinite(val) and (val > 0 if name == "--range" else val >= 0)):
            raise UsageError(f"{name}={val!r} must be a finite {'positive' if name == '--range' else 'non-negative'} number")
    clock = make_clock(log, period=period, stale=stale)
    ids = sorted(log.robots)
    n = len(ids)
    params = _params(phi, v, clock, algorithm, n)
    # collision's own rule: the radius given, else the algorithm's robot_radius, else the default
    radius = collision_radius(params, {} if radius is None else {"radius": radius})
    rm = 2.0 * pos_tol if range_margin is None else float(range_margin)
    cm = float(pos_tol) if collision_margin is None else float(collision_margin)
    for name, val in (("--range-margin", rm), ("--collision-margin", cm), ("--radius", radius),
                      ("--static-window", static_window), ("--v", 0.0 if v is None else v)):
        positive = name in ("--radius", "--static-window")
        if isinstance(val, bool) or not (isinstance(val, (int, float)) and math.isfinite(val)
                                         and (val > 0 if positive else val >= 0)):
            raise UsageError(f"{name}={val!r} must be a finite {'positive' if positive else 'non-negative'} number",
                             fix="e.g. --radius 0.1 (a robot's disc), --static-window 2 (seconds)" if positive else
                                 "e.g. 0.02")
    stand_in = _Recorded(algorithm, log.parents is not None or log.states is not None, log.states is not None)
    base_tol = _widen_satisfaction(stand_in, algorithm, target, pos_tol)
    _add_notes(log, clock)
    options = dict(options or {})
    props, na = _select(names, stand_in, target, log, algorithm)
    params = dataclasses.replace(params, extra={**params.extra, "robot_radius": radius})
    static_k = max(1, int(math.ceil(static_window * NS / clock.period_ns)))
    options.setdefault("deadlock_k", static_k)
    options.setdefault("pos_tol", max(pos_tol, DEFAULT_POS_TOL))

    def params_of(key):
        prop, variant = key
        if TOLERANCE_KNOBS.get(prop, ("",))[0] == "range" and variant:
            return Params(range=max(phi + variant * rm, 1e-12), v=params.v, omega=params.omega, dt=params.dt,
                          extra=params.extra)
        return params

    def options_of(key):
        prop, variant = key
        if TOLERANCE_KNOBS.get(prop, ("",))[0] == "radius" and variant:
            return {**options, "radius": radius + variant * cm}
        return {**options, "radius": radius}

    from swarmproof.reference_impl.protocol import Params

    streamed = [p for p in props if p.stream is not None]
    whole = [p for p in props if p.stream is None]
    # nominal, then each tolerance knob's two directions (only the one that could overturn is read)
    keys = [((p.name, 0), p) for p in streamed]
    for p in streamed:
        knob = TOLERANCE_KNOBS.get(p.name, ("",))[0]
        if knob and (rm if knob == "range" else cm) > 0:
            keys += [((p.name, v), p) for v in (-1, +1)
                     if not (knob == "radius" and radius + v * cm <= 0)]   # a disc of radius <= 0: nothing collides
    judge = _Judge(keys, stand_in, params_of, options_of, ids)
    per_key, frames_kept, final, windows, gaps = _stream(log, clock, judge, keep_frames, pos_tol, static_k, ids,
                                                         target, params, options_of, stand_in, progress)
    judged = sum(b - a for a, b in windows)
    results, sensitive = {}, {}
    for p in streamed:
        res = _combine(p, [per_key.get(((p.name, 0), w)) for w in windows], gaps, clock, judged)
        results[p.name] = _with_time(res, clock)
        sensitive[p.name] = _sensitivity(p, res, windows, per_key, gaps, clock, judged)
    last_fresh = final is not None and final[0] == clock.instants - 1
    for p in whole:
        results[p.name] = _judge_whole(p, final, last_fresh, clock, target, params, options, stand_in, ids, static_k)
        if p.name == "formation" and base_tol is not None:
            # judged with the tolerance widened by the log's position tolerance; at the algorithm's own
            # tolerance too, so that a verdict the widening decides says so
            strict = copy.copy(stand_in)
            strict.satisfaction_tol = base_tol
            other = _judge_whole(p, final, last_fresh, clock, target, params, options, strict, ids, static_k)
            sensitive["formation"] = other.status != results[p.name].status
    results = {name: results[name] for name in [p.name for p in props]}
    tol = {"pos_tol": pos_tol, "range_margin": rm, "collision_margin": cm}
    return RecordedReport(log, clock, results, na, judged, gaps, tol, sensitive, phi, radius,
                          bool(final is not None and final[3].status == "static"), frames_kept)


def _widen_satisfaction(stand_in, algorithm, target, pos_tol: float):
    """Def. 2's position tolerance widened by the two robots' errors of a relative position (2D), on
    a lattice target; returns the algorithm's own tolerance (None when nothing was widened)."""
    if not (pos_tol > 0 and target is not None and getattr(target, "kind", "lattice") == "lattice"):
        return None
    from swarmproof.models.satisfaction import DEFAULT_SAT_ANG_TOL, DEFAULT_SAT_POS_TOL

    base = tuple(getattr(algorithm, "satisfaction_tol", None) or (DEFAULT_SAT_POS_TOL, DEFAULT_SAT_ANG_TOL))
    stand_in.satisfaction_tol = (base[0] + 2 * pos_tol, base[1])
    return base


def _select(names, stand_in, target, log, algorithm) -> tuple:
    """``(properties judged, name -> why not applicable)``."""
    props, na = [], {}
    for name in names:
        prop = get_property(name)
        why = _not_applicable(prop, stand_in, target, log, algorithm)
        if why:
            na[prop.name] = why
        else:
            props.append(prop)
    return props, na

def _add_notes(log: RecordedLog, clock: Clock) -> None:
    """What the report's notes say of a log: robots that joined late, samples no instant holds,
    parent ids that name no robot."""
    late = [(rid, r.t[0]) for rid, r in sorted(log.robots.items()) if int(r.t[0]) - clock.start_ns > clock.stale_ns]
    if late:
        note = ("robots that first report later than the staleness bound after the log's start, in the swarm only "
                "from then on (as robots that join): " + ", ".join(f"{rid} at {fmt_s(t / NS)} s" for rid, t in late[:10]))
        if note not in log.notes:
            log.notes.append(note)
    unseen = _unseen_samples(log, clock)
    if unseen:
        note = (f"{unseen} pose samples fall between the clock's instants and are not judged (sample and hold keeps "
                f"the latest at each instant; a robot reported faster than the period {fmt_s(clock.period_ns / NS)} s): "
                "a shorter --period judges them")
        if note not in log.notes:
            log.notes.append(note)
    if log.parents is not None:
        named = set()
        for ps in log.parents.values():
            named.update(int(v) for v in np.unique(ps.parent) if v >= 0)
        strangers = sorted(named - set(log.robots))
        note = f"parent ids that name no robot of the log: {strangers[:10]} (tree_links cannot check those links)"
        if strangers and note not in log.notes:
            log.notes.append(note)


def _stream(log, clock, judge, keep_frames, pos_tol, static_k, ids, target, params, options_of, stand_in,
            progress=None):
    """One pass over the aligned instants: each judged instant (every present robot fresh) is fed to
    the monitors of its window, a window closes at the first unjudged instant after it (or the
    log's end), the unjudged ones make the gaps; frames are kept for pictures.  Returns the
    per-(key, window) results, the kept frames, the last window's end, the windows ``(k0, k1)``
    (k1 exclusive) and the gaps ``{from_step, to_step, from_s, to_s, robots}``."""
    n = len(ids)
    id_arr = np.asarray(ids)
    per_key: dict = {}
    frames_kept: list = []
    windows: list = []
    gaps: list = []
    every = max(1, clock.instants // keep_frames) if keep_frames else 0
    last_move = 0
    prev = None
    mons = cur = gap = None            # the open window's monitors and (k0, last instant, its frame), the open gap
    final = None

    def close(cur):
        k0, k, poses, states, static = cur
        win = (k0, k + 1)
        result = _Result("static" if static else "step_cap", k, None, static_k, id_arr, poses.copy())
        _close_window(mons, per_key, win, not windows, target, params, options_of, stand_in, result)
        windows.append(win)
        return (k, poses.copy(), states, result)

    for k, poses, pars, fresh, present, sidx in aligned_frames(log, clock):
        if progress is not None and not k % 10_000:
            progress(f"judged {k} of {clock.instants} instants")
        if every and (k % every == 0 or k == clock.instants - 1):
            frames_kept.append((k, poses.copy(), None if pars is None else pars.copy(), fresh.copy(), present.copy()))
        # at rest: no robot farther than twice the position tolerance (two samples of a robot standing
        # still differ by up to that) from where it was when the swarm last moved -- measured from
        # that anchor, not step to step, so that a slow drift adds up
        if prev is None or np.max(np.abs(poses[:, :2] - prev), initial=0.0) > max(2 * pos_tol, DEFAULT_POS_TOL):
            if prev is not None:
                last_move = k
            prev = poses[:, :2].copy()
        if not (fresh | ~present).all():
            if cur is not None:
                final, cur = close(cur), None
            stale = id_arr[present & ~fresh].tolist()
            if gap is None:
                gap = {"from_step": k, "to_step": k, "robots": set(stale)}
            else:
                gap["to_step"] = k
                gap["robots"].update(stale)
            continue
        if gap is not None:
            gaps.append(gap)
            gap = None
        if cur is None:
            mons = judge.monitors()
        states = _states(pars, n, log, sidx)
        for _, _, ob in mons:
            ob.observe(k, poses, states, present)
        cur = (k if cur is None else cur[0], k, poses, states, k - last_move >= static_k)
    if cur is not None:
        final = close(cur)
    if gap is not None:
        gaps.append(gap)
    for g in gaps:
        g["from_s"], g["to_s"] = clock.seconds(g["from_step"]), clock.seconds(g["to_step"])
        g["robots"] = sorted(g["robots"])
    return per_key, frames_kept, final, windows, gaps


def _close_window(mons, per_key, win, first: bool, target, params, options_of, stand_in, result):
    """Each monitor's result for the window ``win`` (``first``: the log's first window)."""
    for key, prop, ob in mons:
        ctx = PropertyContext(stand_in, target, params, result, options_of(key))
        judge = getattr(ob, "judge", None)
        res = judge(ctx) if callable(judge) else ob.result()
        if (prop.name == "connectivity" and res.status == "inconclusive" and not first
                and len(getattr(ob, "start_components", None) or []) > 1):
            # a window after a gap opens split: the log's graph was connected at its start, so it
            # split somewhere in the gap -- seen at the window's first instant
            comps = ob.start_components
            res = InvariantResult("connectivity", "violated", res.cites, {"step": int(win[0]), "components": comps},
                                  f"the communication graph is split into {len(comps)} components when every robot "
                                  f"reports again at instant {win[0]} (after a gap): {comps}")
        per_key[(key, win)] = res


def _combine(prop, results, gaps, clock: Clock, judged: int) -> InvariantResult:
    """One verdict from a property's per-window results: the first violation; else held only when
    every instant was judged; else inconclusive, naming the gaps."""
    for r in results:
        if r is not None and r.status == "violated":
            return r
    if not results:
        return InvariantResult(prop.name, "inconclusive", prop.cites, None,
                               f"no instant judged: at every one of the {clock.instants} instants some robot had no "
                               f"sample fresher than {fmt_s(clock.stale_ns / NS)} s", applicable=False)
    if gaps:
        g = gaps[0]
        more = f" (and {len(gaps) - 1} more gaps)" if len(gaps) > 1 else ""
        return InvariantResult(
            prop.name, "inconclusive", prop.cites, None,
            f"not violated in the {judged} judged instants of {clock.instants}, but not judged from {fmt_s(g['from_s'])} s "
            f"to {fmt_s(g['to_s'])} s: robots {g['robots'][:8]} had no sample fresher than {fmt_s(clock.stale_ns / NS)} s"
            f"{more}", detail={"judged_instants": judged, "instants": clock.instants})
    return results[0]       # no gap: one window


def _sensitivity(prop, res, windows, per_key, gaps, clock, judged) -> bool | None:
    """Whether the tolerance could overturn ``res``: held nominally but violated at the strict
    margin, or violated nominally but not at the lenient one; None when no knob applies."""
    knob = TOLERANCE_KNOBS.get(prop.name)
    if knob is None:
        return None
    if not any((((prop.name, v), w) in per_key) for v in (-1, 1) for w in windows):
        return False if res.status != "inconclusive" else None      # no margin: nothing to overturn it
    _, harder = knob
    if res.status == "held":
        other = _combine(prop, [per_key.get(((prop.name, harder), w)) for w in windows], gaps, clock, judged)
        return other.status != "held"
    if res.status == "violated":
        easier = [per_key.get(((prop.name, -harder), w)) for w in windows]
        if all(r is None for r in easier):      # the easier margin leaves nothing to judge (a radius <= 0)
            return True
        other = _combine(prop, easier, gaps, clock, judged)
        return other.status != "violated"
    return None


def _judge_whole(prop, final, last_fresh, clock, target, params, options, stand_in, ids, static_k) -> InvariantResult:
    """A property judged on the whole run (termination, formation): read at the log's last instant."""
    if final is None or not last_fresh:
        return InvariantResult(prop.name, "inconclusive", prop.cites, None,
                               f"the log's last instant ({fmt_s(clock.seconds(clock.instants - 1))} s) is not judged: "
                               "some robot had no fresh sample there")
    k, poses, states, result = final
    frames = 2 if k else 1
    trace = Trace(ids=np.asarray(ids), poses=np.stack([poses] * frames), states=[states] * frames,
                  times=[0, k] if k else None,
                  meta={"status": result.status, "params": {"range": params.range, "v": params.v, "dt": params.dt,
                                                            "extra": dict(params.extra or {})}})
    ctx = PropertyContext(stand_in, target, params, result, options)
    res = prop.check(trace, ctx)
    short = k < static_k
    if short and prop.name in ("termination", "formation") and res.status != "violated":
        return InvariantResult(prop.name, "inconclusive", res.cites, None,
                               f"the log ({k + 1} instants) is shorter than the static window ({static_k} instants): "
                               "it cannot show the swarm at rest")
    if prop.name == "termination":
        if result.status == "static":
            return InvariantResult("termination", "held", res.cites, None,
                                   f"the swarm was at rest (no robot moved more than twice the position tolerance) for the "
                                   f"last {static_k} instants of the log, from {fmt_s(clock.seconds(k - static_k))} s")
        return InvariantResult("termination", "inconclusive", res.cites, None,
                               f"the log ended while robots still moved (in the last {static_k} instants): a finite log "
                               "cannot show a swarm that would never stop")
    if prop.name == "formation" and res.status == "inconclusive" and result.status != "static":
        return InvariantResult("formation", "inconclusive", res.cites, None,
                               f"the log ended while robots still moved (in the last {static_k} instants): the formation "
                               "at its end may not be the final one")
    return res


def _phi_of(range_, target) -> float:
    if range_ is not None:
        return range_
    rng = getattr(target, "range", None)
    if isinstance(rng, (int, float)) and not isinstance(rng, bool) and rng > 0:
        return float(rng)
    raise UsageError("checking a recorded run needs the communication range",
                     fix="give --range PHI (or a lattice --target, whose range is used)")


def judge_log(path, *, range=None, target=None, algorithm=None, properties=None, topics=None,  # noqa: A002
              parent_topics=None, time=None, keep_frames: int = 0, progress=None, state_topics=None, **options):
    """Read and judge one log as ``swarmproof check-run`` does (the command and verify's
    ``recorded`` rows share it): ``target`` and ``algorithm`` by name, the range from ``range`` or
    the lattice target, the radius from ``radius`` or the algorithm's ``robot_radius``; the other
    ``options`` are :func:`check_recorded`'s.  Returns ``(report, claims)``: claims is the
    algorithm's (property -> citation), None without one."""
    from swarmproof.models.recorded_io import read_log

    spec = None
    if algorithm is not None:
        from swarmproof.checkers.algorithm_spec import resolve_algorithm

        spec = resolve_algorithm(algorithm)
    tgt = None
    if target is not None:
        from swarmproof.models.targets import resolve_target

        tgt = resolve_target(target)
    if properties:
        for p in properties:
            get_property(p)
    phi = _phi_of(range, tgt) if range is not None or tgt is not None else None
    if phi is None:
        _phi_of(None, None)            # the range is needed: refused before the log is read
    log = read_log(path, topics=topics, parent_topics=parent_topics, time=time, progress=progress,
                   state_topics=state_topics)
    algo = None
    if spec is not None:
        # as simulate builds it for the team (song2016's timeouts are n), and the target it runs
        # toward with n robots (004: a shape scaled to n goal cells)
        algo = spec.build(n_robots=len(log.robots))
        scale = getattr(algo, "scale_target", None)
        if callable(scale) and tgt is not None:
            tgt = scale(tgt, len(log.robots))
    rep = check_recorded(log, phi=phi, target=tgt, algorithm=algo, properties=properties, keep_frames=keep_frames,
                         progress=progress, **options)
    return rep, (dict(spec.claims) if spec is not None else None)
