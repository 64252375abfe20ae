"""Property predicates the explorer judges a trace by: collision, deadlock, oscillation.

Each function is pure (it reads a :class:`~swarmproof.models.trace.Trace`
and returns an :class:`~swarmproof.invariants.result.InvariantResult`), says
what it checks, and lists its blind spots.  None of these properties is
claimed by the papers in so many words; they are the generic safety and
liveness failures a formation algorithm can show (issue 6):

* :func:`collision` -- robots as discs of radius ``r`` never overlap, checked
  over the whole straight segment each robot travels in a step (000 and 001
  model a step as a straight move; the papers assume robots never collide,
  001 Sec. III-A "robots ... are ... of negligible size" is NOT assumed here).
* :func:`deadlock` -- K consecutive quiet steps (no pose, broadcast or state
  changes) while the goal is not reached (001 Def. 5: a static configuration
  that does not satisfy the lattice is a failure of Theorem 13).
* :func:`oscillation` -- a revisited global state (a cycle) without the goal,
  and robots moving back and forth again and again; for randomized
  algorithms, no progress of the goal measure over a stated window.
* :func:`premises` -- the lemma premise monitors of the proof suite
  (:mod:`swarmproof.invariants.premises`) that apply to an algorithm, at
  every step, naming the lemma whose premise failed.

Examples
--------
>>> import numpy as np
>>> from swarmproof.models.trace import Trace
>>> poses = np.array([[[0, 0, 0], [2, 0, 0]], [[2, 0, 0], [0, 0, 0]]], float)
>>> t = Trace(ids=[0, 1], poses=poses, states=[(None, None)] * 2)
>>> r = collision(t, 0.1)
>>> r.status, r.witness["step"], r.witness["robots"]
('violated', 0, [0, 1])
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from scipy.spatial import cKDTree

from .premises import CITE_PREMISES, combine_premises, premises  # noqa: F401  (re-exported)
from .result import InvariantResult

__all__ = ["collision", "CollisionMonitor", "combine_premises", "deadlock", "DeadlockMonitor", "OscillationMonitor", "oscillation", "premises", "segment_min_distances"]

CITE_COLLISION = "issue 6: robots as discs never overlap (straight moves per step, 000 Sec. III / 001 Sec. III-A)"
CITE_DEADLOCK = "issue 6 / 001 Def. 5, Thm. 13: no static configuration short of the goal"
CITE_OSCILLATION = "issue 6 / 001 Thm. 13: progress, no revisited global state short of the goal"


def segment_min_distances(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray):
    """Closed-form minimum distance between points moving linearly ``a0->a1`` and ``b0->b1``.

    Both move over the same step, parameter ``s`` in [0, 1].  The relative
    position is ``d(s) = d0 + s*dd``; its norm is smallest at
    ``s* = clip(-d0.dd / |dd|^2, 0, 1)``.

    Parameters
    ----------
    a0, a1, b0, b1 : numpy.ndarray, shape (m, 2)

    Returns
    -------
    dist : numpy.ndarray, shape (m,)
    s : numpy.ndarray, shape (m,)
        The fraction of the step at which the minimum is reached.

    Examples
    --------
    >>> import numpy as np
    >>> d, s = segment_min_distances(np.array([[0., 0]]), np.array([[2., 0]]),
    ...                              np.array([[2., 1]]), np.array([[0., 1]]))
    >>> float(d[0]), float(s[0])
    (1.0, 0.5)
    """
    d0 = np.asarray(a0, float) - np.asarray(b0, float)
    dd = (np.asarray(a1, float) - np.asarray(b1, float)) - d0
    den = np.einsum("ij,ij->i", dd, dd)
    num = -np.einsum("ij,ij->i", d0, dd)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.0)
    s = np.clip(s, 0.0, 1.0)
    d = d0 + s[:, None] * dd
    return np.hypot(d[:, 0], d[:, 1]), s


def collision(trace, radius: float, *, tol: float = 1e-9) -> InvariantResult:
    """Robots as discs of radius ``radius`` never overlap, at any time of any step.

    For every step ``t`` each present robot is taken to move on the straight
    segment from ``poses[t]`` to ``poses[t+1]`` at constant speed; the minimum
    distance of every pair over the step is computed in closed form
    (:func:`segment_min_distances`), not only at the ends.  Candidate pairs
    are pre-filtered with a :class:`scipy.spatial.cKDTree` over the segment
    midpoints (two points moving on segments of lengths ``L_i``, ``L_j`` stay
    within ``(L_i+L_j)/2`` of their midpoints' distance).

    Overlap means a distance strictly below ``2*radius - tol``; touching is allowed.

    Blind spots: a differential-drive robot that turns and drives in one step
    follows an arc, not the chord checked here (the arc stays within
    ``v*dt*(1-cos(dtheta/2))/...`` of the chord: small for small turns);
    robots are discs, the real body shape is ignored; robots absent at either
    end of a step (crashed, not yet added) are skipped in that step.

    Parameters
    ----------
    trace : Trace
    radius : float
        Disc radius, > 0.
    tol : float
        Numerical slack.

    Returns
    -------
    InvariantResult
        ``violated`` with witness ``{step, robots [id, id], distance, fraction}``
        for the first step (and the closest pair in it) with an overlap.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> poses = np.array([[[0, 0, 0], [1, 0, 0]], [[0, 0.5, 0], [1, 0.5, 0]]], float)
    >>> collision(Trace(ids=[0, 1], poses=poses, states=[(None, None)] * 2), 0.4).status
    'held'
    """
    mon = CollisionMonitor(radius, tol)
    mon.start(trace.ids)
    for i in range(len(trace.poses)):      # recorded frames, named by their engine step
        mon.observe(trace.time_of(i), trace.poses[i], trace.states[i], trace.present_at(i))
    return mon.result()


class CollisionMonitor:
    """Streaming form of :func:`collision`: ``observe`` every step, in order (the engine's
    ``observers``), so an overlap inside a step a sparse trace does not keep is found."""

    name = "collision"

    def __init__(self, radius: float, tol: float = 1e-9) -> None:
        if not (math.isfinite(radius) and radius > 0):
            raise ValueError(f"radius={radius!r} must be a finite number > 0")
        self.radius, self.thr = float(radius), 2.0 * float(radius) - tol
        self.ids = None
        self._prev = None
        self.steps = 0
        self.pairs_checked = 0
        self.hit = None

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)

    def observe(self, t, poses, states, present) -> None:
        cur = (int(t), np.array(np.asarray(poses, float)[:, :2], copy=True), np.array(present, copy=True))
        prev, self._prev = self._prev, cur
        if prev is None or self.hit is not None:
            return
        self.steps += 1
        self._check(prev, cur)

    def _check(self, prev, cur) -> None:
        t, a_all, pres0 = prev
        _, b_all, pres1 = cur
        idx = np.flatnonzero(pres0 & pres1)
        if len(idx) < 2:
            return
        a, b = a_all[idx], b_all[idx]
        lengths = np.hypot(*(b - a).T)
        mids = 0.5 * (a + b)
        pairs = cKDTree(mids).query_pairs(self.thr + float(lengths.max()), output_type="ndarray")
        if len(pairs) == 0:
            return
        i, j = pairs[:, 0], pairs[:, 1]
        d, s = segment_min_distances(a[i], b[i], a[j], b[j])
        self.pairs_checked += len(pairs)
        bad = np.flatnonzero(d < self.thr)
        if len(bad):
            k = bad[np.argmin(d[bad])]
            ri, rj = sorted((int(self.ids[idx[i[k]]]), int(self.ids[idx[j[k]]])))
            self.hit = {"step": int(t), "robots": [ri, rj], "distance": float(d[k]), "fraction": float(s[k]),
                        "radius": self.radius}

    def result(self) -> InvariantResult:
        if self.steps == 0 and self._prev is not None and self.hit is None:
            self._check(self._prev, self._prev)          # a run of no steps: the start itself
        radius = self.radius
        if self.hit is not None:
            w = self.hit
            from swarmproof.models.doclines import distinct_texts   # never "0.2 < 2r = 0.2"

            dist, two_r = distinct_texts(w["distance"], 2 * radius)
            return InvariantResult("collision", "violated", CITE_COLLISION, w,
                                   f"robots {w['robots'][0]} and {w['robots'][1]} overlap in step {w['step']}: "
                                   f"distance {dist} < 2r = {two_r} at {w['fraction']:.2f} "
                                   "of the step")
        return InvariantResult("collision", "held", CITE_COLLISION, None,
                               f"no overlap of discs of radius {radius:g} over {self.steps} steps",
                               detail={"pairs_checked": self.pairs_checked})


def _goal_fn(goal_reached) -> Callable[[int], bool]:
    if callable(goal_reached):
        return lambda t: bool(goal_reached(t))
    return lambda t: bool(goal_reached)


def _quiet_steps(trace) -> np.ndarray:
    """quiet[t] (t = 0..T-1): step t changed no pose, no state and no broadcast."""
    P = np.asarray(trace.poses)
    T = len(P) - 1
    if T <= 0:
        return np.zeros(0, dtype=bool)
    quiet = np.all(P[1:] == P[:-1], axis=(1, 2))
    for t in np.flatnonzero(quiet):
        if trace.states[t + 1] != trace.states[t]:
            quiet[t] = False
        elif trace.messages is not None and t >= 1 and trace.messages[t] != trace.messages[t - 1]:
            quiet[t] = False
    return quiet


def deadlock(trace, k: int, goal_reached=False) -> InvariantResult:
    """No ``k`` consecutive quiet steps while the goal is not reached.

    A quiet step moves no robot and changes no controller state and (when the
    trace recorded them) no broadcast.  ``goal_reached`` is a bool (the goal
    was / was not reached, e.g. the final formation satisfies the lattice) or
    a callable ``t -> bool`` asked at the end of the quiet window.

    Blind spots: without recorded messages a change in broadcasts alone is
    not seen (a robot that only talks looks quiet); a quiet stretch shorter
    than ``k`` at the end of the trace is not judged (``inconclusive`` when
    the trace is shorter than ``k`` and the goal is not reached); a robot
    that waits on purpose for longer than ``k`` steps is reported.

    Returns
    -------
    InvariantResult
        ``violated`` with witness ``{step, window}`` (``step``: the first step
        of the quiet window).

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> t = Trace(ids=[0], poses=np.zeros((6, 1, 3)), states=[("wait",)] * 6)
    >>> deadlock(t, 3).status, deadlock(t, 3).witness
    ('violated', {'step': 0, 'window': 3})
    >>> deadlock(t, 3, goal_reached=True).status
    'held'
    """
    if int(k) < 1:
        raise ValueError(f"k={k!r} must be >= 1")
    k = int(k)
    goal = _goal_fn(goal_reached)
    quiet = _quiet_steps(trace)
    run = 0
    for t, q in enumerate(quiet):
        run = run + 1 if q else 0
        if run >= k and not goal(t + 1):
            start = t + 1 - k
            return InvariantResult("deadlock", "violated", CITE_DEADLOCK, {"step": int(start), "window": k},
                                   f"nothing moved or changed for {k} steps from step {start} "
                                   f"and the goal is not reached")
    if len(quiet) < k and not goal(len(quiet)):
        return InvariantResult("deadlock", "inconclusive", CITE_DEADLOCK, None,
                               f"trace of {len(quiet)} steps is shorter than the window k={k}")
    msg = "" if trace.messages is not None else " (broadcasts not recorded)"
    return InvariantResult("deadlock", "held", CITE_DEADLOCK, None,
                           f"no {k} quiet steps short of the goal over {len(quiet)} steps{msg}")


class DeadlockMonitor:
    """Streaming form of :func:`deadlock` (``observe`` every step, in order): it keeps the
    quiet stretches (no pose and no controller state changed; broadcasts are not seen, as on
    a trace without recorded messages), and :meth:`result` judges them with the window ``k``
    and whether the goal was reached, as :func:`deadlock` does."""

    name = "deadlock"

    def __init__(self) -> None:
        self._prev = None
        self.steps = 0
        self.runs: list = []       # (first step, length) of each quiet stretch
        self._run = 0

    def start(self, ids) -> None:
        pass

    def observe(self, t, poses, states, present) -> None:
        cur = (np.array(poses, copy=True), states)
        if self._prev is not None:
            self.steps += 1
            quiet = np.array_equal(cur[0], self._prev[0]) and states == self._prev[1]
            if quiet:
                self._run += 1
                if self._run == 1:
                    self.runs.append([t - 1, 1])
                else:
                    self.runs[-1][1] = self._run
            else:
                self._run = 0
        self._prev = cur

    def result(self, k: int = 1, goal_reached: bool = False) -> InvariantResult:
        k = int(k)
        if not goal_reached:
            for first, length in self.runs:
                if length >= k:
                    return InvariantResult("deadlock", "violated", CITE_DEADLOCK, {"step": int(first), "window": k},
                                           f"nothing moved or changed for {k} steps from step {first} "
                                           f"and the goal is not reached")
            if self.steps < k:
                return InvariantResult("deadlock", "inconclusive", CITE_DEADLOCK, None,
                                       f"trace of {self.steps} steps is shorter than the window k={k}")
        return InvariantResult("deadlock", "held", CITE_DEADLOCK, None,
                               f"no {k} quiet steps short of the goal over {self.steps} steps (broadcasts not recorded)")


def _global_state_key(poses, present, states, pos_tol: float):
    """The global state of oscillation's rule 1: poses rounded to ``pos_tol``, presence, controller states."""
    P = np.asarray(poses, float)
    q = np.round(P[:, :2] / pos_tol).astype(np.int64)
    th = np.round(np.mod(P[:, 2], 2 * np.pi) / pos_tol).astype(np.int64)
    return (q.tobytes(), th.tobytes(), np.asarray(present, bool).tobytes(), states)


def _state_key(trace, t: int, pos_tol: float):
    return _global_state_key(trace.poses[t], trace.present_at(t), trace.states[t], pos_tol)


class CycleMonitor:
    """Run-time form of :func:`oscillation`'s rule 1, for ``simulate(stop_when=...)``.

    Called with each recorded step's poses, states and presence, it returns
    True at the first step whose global state (the same key as rule 1)
    repeats an earlier one other than the step just before: from there a
    deterministic run can only repeat itself, so the explorer stops it
    instead of running to the step cap.  It does not look at the goal:
    judging the stopped trace with :func:`oscillation` decides (the
    explorer runs again without the monitor when that judgment is not a
    violation).  ``step`` is where it fired.

    >>> import numpy as np
    >>> m = CycleMonitor(1e-3)
    >>> [m(t, np.array([[x, 0.0, 0.0]]), ("go",), np.array([True])) for t, x in enumerate([0, 1, 1, 0])]
    [False, False, False, True]
    >>> m.step, m.revisits
    (3, 0)
    """

    def __init__(self, pos_tol: float = 1e-6) -> None:
        self.pos_tol = float(pos_tol)
        self.seen: dict = {}
        self.prev = None
        self.step: int | None = None
        self.revisits: int | None = None

    def __call__(self, t: int, poses, states, present) -> bool:
        key = _global_state_key(poses, present, states, self.pos_tol)
        if key in self.seen and key != self.prev:
            self.step, self.revisits = int(t), int(self.seen[key])
            return True
        self.seen.setdefault(key, int(t))
        self.prev = key
        return False


def oscillation(trace, pos_tol: float = 1e-6, *, goal_reached=False, excursion: float | None = None,
                min_returns: int = 3, randomized: bool = False, progress=None, window: int | None = None,
                progress_eps: float = 1e-9, deterministic_from: int = 0) -> InvariantResult:
    """No cycle of global states and no robot moving back and forth, short of the goal.

    1. *Cycle*: the global state at step ``t2`` -- every pose rounded to
       ``pos_tol`` (x, y and theta in radians) plus every controller's state
       -- equals the one at an earlier step ``t1`` while some step between
       differed, and the goal is not reached at ``t2``.  A deterministic
       algorithm would repeat that cycle for ever (randomized ones may not).
    2. *Back and forth*: a robot comes back within ``pos_tol`` of a position
       it held at an earlier step after leaving it by more than ``excursion``
       (default ``100 * pos_tol``), and does so ``min_returns`` times or more,
       without the goal reached at the last return.

    3. *No progress* (for randomized algorithms, issue 6): with ``progress``
       (the algorithm's goal measure at every recorded step, higher is
       closer to the goal) and ``window`` W, the best value so far must
       rise by more than ``progress_eps`` at least once in every W
       consecutive steps while the goal is not reached; a stall of W steps
       short of the goal is a violation (even if the run reaches the goal
       later: W is the stated patience).

    With ``randomized=True`` rule 1 is not applied: a randomized algorithm
    can revisit a global state without repeating what followed it.  Nor before
    ``deterministic_from``: a run whose decisions were chosen (exhaustive checking's
    choices, issue 33) is deterministic only after its last non-default decision, so rule 1
    compares the states from that step on (a state repeated across a chosen decision is no
    cycle: the next pass need not make it).  A
    randomized algorithm without a ``progress`` measure cannot be judged by
    rule 3, so the result is ``inconclusive`` unless rule 2 fires.

    Blind spots: rounding to a grid can split two states closer than
    ``pos_tol`` that straddle a cell border (a missed cycle) and, with a
    coarse ``pos_tol``, merge states that differ (a false cycle); the
    back-and-forth check is quadratic in the trace length per robot and only
    looks at the last 1000 steps; a cycle longer than the trace is not seen.
    Rule 3 is only as good as the measure: a measure that creeps up by more
    than ``progress_eps`` forever passes (slow or Zeno progress), one that
    ignores part of the goal misses stalls there, and a trace shorter than W
    is not judged by it; a deadlock (nothing moves) is also a stall.

    Returns
    -------
    InvariantResult
        ``violated`` with witness ``{kind: "cycle", step, revisits}``,
        ``{kind: "back_and_forth", robot, step, returns}`` or
        ``{kind: "no_progress", step, since, window, best}``.

    Examples
    --------
    >>> import numpy as np
    >>> from swarmproof.models.trace import Trace
    >>> xs = [0, 1, 0, 1, 0, 1, 0]
    >>> poses = np.array([[[x, 0, 0]] for x in xs], float)
    >>> t = Trace(ids=[5], poses=poses, states=[("go",)] * 7)
    >>> r = oscillation(t, 1e-3)
    >>> r.status, r.witness["kind"], r.witness["step"], r.witness["revisits"]
    ('violated', 'cycle', 2, 0)
    >>> stall = [0, 1, 2, 2, 2, 2, 2]
    >>> r = oscillation(t, 1e-3, randomized=True, progress=stall, window=3, min_returns=9)
    >>> r.status, r.witness
    ('violated', {'kind': 'no_progress', 'step': 5, 'since': 2, 'window': 3, 'best': 2.0})
    >>> oscillation(t, 1e-3, randomized=True, min_returns=9).status
    'inconclusive'
    """
    if not (math.isfinite(pos_tol) and pos_tol > 0):
        raise ValueError(f"pos_tol={pos_tol!r} must be a finite number > 0")
    if min_returns < 1:
        raise ValueError(f"min_returns={min_returns!r} must be >= 1")
    if excursion is None:
        excursion = 100.0 * pos_tol
    goal = _goal_fn(goal_reached)
    T = len(trace.poses) - 1
    if progress is not None:
        if window is None or int(window) < 1:
            raise ValueError(f"window={window!r} must be an int >= 1 when a progress measure is given")
        window = int(window)
        progress = np.asarray(progress, float)
        if progress.shape != (T + 1,):
            raise ValueError(f"progress has shape={progress.shape!r}, expected ({T + 1},): one value per step")
    seen: dict = {}
    prev = None
    for t in range(T + 1 if randomized else max(0, int(deterministic_from)), T + 1):  # rule 1: deterministic only
        key = _state_key(trace, t, pos_tol)
        if key in seen and key != prev and not goal(t):
            t1 = seen[key]
            return InvariantResult("oscillation", "violated", CITE_OSCILLATION,
                                   {"kind": "cycle", "step": int(t), "revisits": int(t1)},
                                   f"the global state at step {t} repeats the one at step {t1} "
                                   f"(poses to {pos_tol:g}, controller states) and the goal is not reached")
        seen.setdefault(key, t)
        prev = key
    W = 1000
    off = max(0, T + 1 - W)
    P = np.asarray(trace.poses, float)[off:, :, :2]
    return _oscillation_tail(P, off, trace.ids, T, goal, pos_tol=pos_tol, excursion=excursion,
                             min_returns=min_returns, randomized=randomized, progress=progress, window=window,
                             progress_eps=progress_eps)


def _oscillation_tail(P, off: int, ids, T: int, goal, *, pos_tol, excursion, min_returns, randomized, progress,
                      window, progress_eps) -> InvariantResult:
    """Rules 2 and 3 of :func:`oscillation` and its final verdict, on the positions ``P`` of
    the last (up to 1,000) steps, the first of them step ``off``; shared with the streaming
    :class:`OscillationMonitor`."""
    # back and forth, per robot: for every anchor step t1, count the separate returns
    # within pos_tol of the anchor position, each after leaving it by more than excursion
    m = len(P)
    cols = np.arange(m)
    later = cols[None, :] >= cols[:, None]
    for r in range(P.shape[1]):
        path = P[:, r]
        D = np.hypot(path[:, None, 0] - path[None, :, 0], path[:, None, 1] - path[None, :, 1])
        C = np.where(later & (D > excursion), 1, np.where(later & (D <= pos_tol), 2, 0)).astype(np.int8)
        last = np.maximum.accumulate(np.where(C > 0, cols[None, :], 0), axis=1)
        prev = np.zeros_like(C)
        prev[:, 1:] = np.take_along_axis(C, last[:, :-1], axis=1)
        ret = (C == 2) & (prev == 1)
        counts = ret.sum(axis=1)
        best = int(np.argmax(counts))
        if counts[best] >= min_returns:
            t2 = int(np.flatnonzero(ret[best])[min_returns - 1]) + off
            if not goal(t2):
                rid = int(ids[r])
                return InvariantResult("oscillation", "violated", CITE_OSCILLATION,
                                       {"kind": "back_and_forth", "robot": rid, "step": t2,
                                        "anchor_step": best + off, "returns": int(counts[best])},
                                       f"robot {rid} came back within {pos_tol:g} of its position at step "
                                       f"{best + off} after leaving it by more than {excursion:g}, "
                                       f"{int(counts[best])} times (the {min_returns}th at step {t2})")
    if progress is not None:
        best, since = progress[0], 0
        for t in range(1, T + 1):
            if progress[t] > best + progress_eps:
                best, since = progress[t], t
            elif t - since >= window and not goal(t):
                return InvariantResult("oscillation", "violated", CITE_OSCILLATION,
                                       {"kind": "no_progress", "step": int(t), "since": int(since),
                                        "window": window, "best": float(best)},
                                       f"no progress for {window} steps: the goal measure stayed at most "
                                       f"{float(best):.6g} (its best, reached at step {since}) through step {t} "
                                       f"and the goal is not reached")
        return InvariantResult("oscillation", "held", CITE_OSCILLATION, None,
                               f"{'' if randomized else 'no revisited global state, '}no robot back and forth "
                               f"{min_returns} times and progress within every {window} steps over {T} steps "
                               f"(tolerance {pos_tol:g})")
    if randomized:
        return InvariantResult("oscillation", "inconclusive", CITE_OSCILLATION, None,
                               "a randomized algorithm without a progress measure: revisited states prove "
                               "no cycle and progress cannot be judged (no robot went back and forth "
                               f"{min_returns} times over {T} steps)")
    return InvariantResult("oscillation", "held", CITE_OSCILLATION, None,
                           f"no revisited global state and no robot back and forth {min_returns} times "
                           f"over {T} steps (tolerance {pos_tol:g})")


class OscillationMonitor:
    """Streaming form of :func:`oscillation` (``observe`` every step, in order).

    Rule 1 (a revisited global state) is decided on the fly, keeping the states seen as
    :func:`oscillation` does; rule 2 needs the last 1,000 steps' positions (a ring buffer);
    rule 3 the goal measure at every step (``measure``, as
    :func:`~swarmproof.invariants.registry.progress_values` computes it).  :meth:`result`
    applies the goal and gives the same verdict and message as on the dense trace."""

    name = "oscillation"
    W = 1000

    def __init__(self, pos_tol: float = 1e-6, *, randomized: bool = False, measure=None, window=None,
                 excursion: float | None = None, min_returns: int = 3, progress_eps: float = 1e-9) -> None:
        from collections import deque

        self.pos_tol, self.randomized, self.measure = float(pos_tol), bool(randomized), measure
        self.window, self.progress_eps, self.min_returns = window, float(progress_eps), int(min_returns)
        self.excursion = 100.0 * self.pos_tol if excursion is None else float(excursion)
        self.seen: dict = {}
        self.prev = None
        self.hit = None
        self.frames = deque(maxlen=self.W)
        self.progress: list = []
        self._pkey = None
        self.T = -1

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)

    def observe(self, t, poses, states, present) -> None:
        self.T = int(t)
        if not self.randomized and self.hit is None:
            key = _global_state_key(poses, present, states, self.pos_tol)
            if key in self.seen and key != self.prev:
                self.hit = (int(t), int(self.seen[key]))
            self.seen.setdefault(key, int(t))
            self.prev = key
        self.frames.append(np.array(np.asarray(poses, float)[:, :2], copy=True))
        if self.measure is not None:
            pkey = (np.asarray(poses).tobytes(), np.asarray(present).tobytes(), states)
            if pkey != self._pkey:
                pres = np.asarray(present, bool)
                self._value = float(self.measure(self.ids[pres], np.asarray(poses)[pres],
                                                 tuple(s_ for s_, p_ in zip(states, pres) if p_)))
                self._pkey = pkey
            self.progress.append(self._value)

    def result(self, goal_reached: bool = False) -> InvariantResult:
        T, g = self.T, bool(goal_reached)

        def goal(t):
            return g and t == T
        if self.hit is not None and not goal(self.hit[0]):
            t, t1 = self.hit
            return InvariantResult("oscillation", "violated", CITE_OSCILLATION,
                                   {"kind": "cycle", "step": int(t), "revisits": int(t1)},
                                   f"the global state at step {t} repeats the one at step {t1} "
                                   f"(poses to {self.pos_tol:g}, controller states) and the goal is not reached")
        P = np.stack(list(self.frames)) if self.frames else np.zeros((0, len(self.ids), 2))
        progress = None
        window = self.window
        if self.measure is not None:
            window = int(window)
            progress = np.asarray(self.progress, float)
        return _oscillation_tail(P, T + 1 - len(P), self.ids, T, goal, pos_tol=self.pos_tol,
                                 excursion=self.excursion, min_returns=self.min_returns, randomized=self.randomized,
                                 progress=progress, window=window, progress_eps=self.progress_eps)


